"""Evaluation metrics on hand-checkable inputs: RRPI, Hausdorff (any CRS), IoU, KDE, sampling, plots."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from affine import Affine
from pyproj import Transformer
from rasterio.crs import CRS
from rasterio.transform import from_origin

from overseec_core.errors import EvaluateError, InputError
from overseec_core.evaluate import (
    ClassTable,
    EvaluateOptions,
    ReferenceSet,
    compute_iou,
    densify,
    evaluate_paths,
    hausdorff,
    kde_centre_of_mass,
    linear_fit,
    load_classes,
    map_diagonal_m,
    parse_ranks,
    rasterise_line,
    read_lines,
    render_report,
    rrpi,
    sample_pairs,
    sample_pairs_uniform,
)
from overseec_core.io.grid import Grid

from ..conftest import write_tif

CLASSES = {0: "unlabeled", 1: "road", 2: "grass", 3: "water (Hydro)"}
ORIGIN = (500000.0, 4000000.0)


def utm_grid(width: int, height: int, px: float = 1.0, py: float = 1.0) -> Grid:
    return Grid(
        crs=CRS.from_epsg(32633), transform=Affine(px, 0, ORIGIN[0], 0, -py, ORIGIN[1]), width=width, height=height
    )


def write_classes(path: Path, classes: dict[int, str] = CLASSES) -> Path:
    path.write_text(json.dumps({str(k): v for k, v in classes.items()}))
    return path


def write_lines(
    path: Path, grid: Grid, lines_rc: list[list[tuple[float, float]]], epsg: int = 4326, names: list[str] | None = None
) -> Path:
    """GeoJSON LineStrings through pixel centres (row, col) of ``grid``, stored in ``epsg``."""
    to = Transformer.from_crs(grid.crs.to_wkt(), f"EPSG:{epsg}", always_xy=True)
    features = []
    for k, line in enumerate(lines_rc):
        rc = np.asarray(line, dtype=float)
        xs, ys = grid.transform * (rc[:, 1] + 0.5, rc[:, 0] + 0.5)
        lon, lat = to.transform(np.asarray(xs), np.asarray(ys))
        features.append(
            {
                "type": "Feature",
                "properties": {"name": names[k] if names else f"line {k}"},
                "geometry": {"type": "LineString", "coordinates": list(map(list, zip(lon, lat)))},
            }
        )
    doc = {"type": "FeatureCollection", "features": features}
    if epsg != 4326:
        doc["crs"] = {"type": "name", "properties": {"name": f"urn:ogc:def:crs:EPSG::{epsg}"}}
    path.write_text(json.dumps(doc))
    return path


# ---------------------------------------------------------------------------------- classes / ranks


def test_classes_and_ranks_parse_names_aliases_and_ids(tmp_path: Path) -> None:
    classes = load_classes(write_classes(tmp_path / "classes.json"))
    ranks = parse_ranks("road=1, Grass=2,hydro=3", classes)
    assert dict(ranks.ranks) == {1: 1, 2: 2, 3: 3} and ranks.unranked_rank == 3
    assert dict(parse_ranks("1=1,water=2", classes, unranked=7).ranks) == {1: 1, 3: 2}
    assert parse_ranks({"road": 1}, classes, unranked="max").unranked_rank == 1


@pytest.mark.parametrize(
    "spec, message",
    [
        ("road=1,gravel=2", "unknown class 'gravel'"),
        ("road=0", "must be >= 1"),
        ("road=first", "must be an integer"),
        ("road=1,1=2", "ranked twice"),
        ("road", "CLASS=RANK"),
        ("", "empty"),
    ],
)
def test_bad_ranks_are_one_line_errors(spec: str, message: str) -> None:
    with pytest.raises(EvaluateError, match=message) as err:
        parse_ranks(spec, ClassTable(CLASSES))
    assert "\n" not in str(err.value)


def test_bad_classes_file(tmp_path: Path) -> None:
    (tmp_path / "a.json").write_text("{not json")
    (tmp_path / "b.json").write_text('{"road": "x"}')
    with pytest.raises(EvaluateError, match="not JSON"):
        load_classes(tmp_path / "a.json")
    with pytest.raises(EvaluateError, match="not an integer"):
        load_classes(tmp_path / "b.json")
    with pytest.raises(InputError, match="no such"):
        load_classes(tmp_path / "missing.json")


def test_rrpi_exact_on_a_hand_made_raster() -> None:
    labels = np.array([[1, 1, 2, 2, 0], [1, 3, 2, 9, 0], [1, 1, 1, 1, 1]], dtype=np.uint8)
    ranks = parse_ranks("road=1,grass=2,water=4", ClassTable(CLASSES))  # unranked: max = 4
    path = np.array([(0, 0), (0, 1), (0, 2), (0, 3), (1, 3), (2, 4), (1, 4), (0, 4)])
    # road 0 + road 0 + grass 1 + grass 1 + class 9 (not in classes) 3 + road 0 + unlabeled 3 + 3
    assert rrpi(labels, path, ranks) == 11
    assert rrpi(labels, [(1, 1)], ranks) == 3  # water rank 4
    ranks2 = parse_ranks("road=1,grass=2,water=4", ClassTable(CLASSES), unranked=2)
    assert rrpi(labels, path, ranks2) == 0 + 0 + 1 + 1 + 1 + 0 + 1 + 1
    # label nodata counts as unranked even if a class shares its value
    assert rrpi(labels, [(0, 0)], ranks2, nodata=1) == 1
    assert rrpi(labels, np.empty((0, 2), dtype=int), ranks) == 0


def test_rasterise_line_is_8_connected_through_vertices() -> None:
    chain = rasterise_line(np.array([(0.0, 0.0), (2.0, 5.0), (2.2, 5.0), (4.0, 5.0)]))
    assert tuple(chain[0]) == (0, 0) and tuple(chain[-1]) == (4, 5)
    steps = np.abs(np.diff(chain, axis=0))
    assert steps.max() == 1 and (steps.sum(axis=1) > 0).all()
    assert (2, 5) in map(tuple, chain)


def test_densify_keeps_vertices_and_step() -> None:
    pts, seg = densify(np.array([(0.0, 0.0), (10.0, 0.0), (10.0, 3.0)]), 0.25)
    assert len(pts) == 40 + 12 + 1
    assert np.hypot(*np.diff(pts, axis=0).T).max() <= 0.25 + 1e-12
    np.testing.assert_allclose(pts[[0, 40, -1]], [(0, 0), (10, 0), (10, 3)])
    assert (seg[:40] == 0).all() and (seg[40:] == 1).all()
    # 49.000000001 m is 196 steps of 0.25 m, not 197 (float noise from reprojection)
    assert len(densify(np.array([(0.0, 0.0), (49.000000001, 0.0)]), 0.25)[0]) == 197


def test_reference_distance_is_exact_between_samples() -> None:
    from overseec_core.evaluate import VectorLine

    # one diagonal segment, sampled every 2 m; the point (0, 10) is 10/sqrt(2) from the line y = x
    ref = ReferenceSet.build([VectorLine("d", np.array([(0.0, 0.0), (30.0, 30.0)]))], (1.0, 1.0), step_m=2.0)
    d = ref.distance(np.array([(0.0, 10.0), (40.0, 30.0), (-3.0, -4.0)]))
    np.testing.assert_allclose(d, [10 / math.sqrt(2), 10.0, 5.0], rtol=1e-12)


# ---------------------------------------------------------------------------------- Hausdorff


def test_hausdorff_reference_in_wgs84_against_a_utm_grid(tmp_path: Path) -> None:
    grid = utm_grid(100, 100)
    ref = write_lines(tmp_path / "ref.geojson", grid, [[(10, 0), (10, 99)]])
    lines = read_lines(ref, grid)
    np.testing.assert_allclose(lines[0].rows_cols, [(10, 0), (10, 99)], atol=1e-6)
    refset = ReferenceSet.build(lines, grid.pixel_size_m())
    path = np.array([(13, c) for c in range(100)])
    diag = map_diagonal_m(grid)
    assert diag == pytest.approx(math.hypot(100, 100))
    hd = hausdorff(path, refset, grid.pixel_size_m(), diag)
    assert hd.directed_m == pytest.approx(3.0, abs=1e-4)
    assert hd.mean_m == pytest.approx(3.0, abs=1e-4)
    assert hd.normalised == pytest.approx(3.0 / diag, rel=1e-4)
    # a path that also visits row 20 strays 10 m from the reference at worst
    bent = np.array([(10, 0), (15, 5), (20, 10), (15, 15)])
    bent_hd = hausdorff(bent, refset, grid.pixel_size_m(), diag)
    assert bent_hd.directed_m == pytest.approx(10.0, abs=1e-4)
    # the paper's figure is the mean point distance (0, 5, 10, 5 m) per diagonal, not the maximum
    assert bent_hd.paper == pytest.approx(5.0 / diag, rel=1e-4) and bent_hd.normalised == pytest.approx(10.0 / diag)


def test_symmetric_hausdorff_charges_unvisited_reference() -> None:
    grid = utm_grid(100, 100)
    from overseec_core.evaluate import VectorLine

    refset = ReferenceSet.build([VectorLine("r", np.array([(10.0, 0.0), (10.0, 99.0)]))], (1.0, 1.0))
    half = np.array([(13, c) for c in range(50)])
    hd = hausdorff(half, refset, (1.0, 1.0), map_diagonal_m(grid), symmetric=True)
    assert hd.directed_m == pytest.approx(3.0)
    assert hd.reverse_m == pytest.approx(math.hypot(3, 99 - 49))
    assert hd.hausdorff_m == hd.reverse_m


def test_hausdorff_in_metres_on_non_square_pixels(tmp_path: Path) -> None:
    grid = utm_grid(80, 50, px=2.0, py=0.5)  # 160 m x 25 m
    ref = write_lines(tmp_path / "ref.geojson", grid, [[(10, 0), (10, 79)], [(0, 5), (49, 5)]], epsg=32633)
    refset = ReferenceSet.build(read_lines(ref, grid), grid.pixel_size_m())
    diag = map_diagonal_m(grid)
    assert diag == pytest.approx(math.hypot(160, 25))
    rows_off = np.array([(14, c) for c in range(20, 60)])  # 4 rows x 0.5 m = 2 m
    cols_off = np.array([(r, 8) for r in range(30, 50)])  # 3 cols x 2 m = 6 m from the vertical line
    assert hausdorff(rows_off, refset, grid.pixel_size_m(), diag).directed_m == pytest.approx(2.0)
    assert hausdorff(cols_off, refset, grid.pixel_size_m(), diag).directed_m == pytest.approx(6.0)


def test_reference_file_errors(tmp_path: Path) -> None:
    grid = utm_grid(10, 10)
    (tmp_path / "points.geojson").write_text(
        json.dumps(
            {
                "type": "FeatureCollection",
                "features": [
                    {"type": "Feature", "properties": {}, "geometry": {"type": "Point", "coordinates": [15.0, 36.0]}}
                ],
            }
        )
    )
    (tmp_path / "junk.geojson").write_text("this is not geojson")
    with pytest.raises(EvaluateError, match="no LineString"):
        read_lines(tmp_path / "points.geojson", grid)
    with pytest.raises(InputError, match="not a readable vector file"):
        read_lines(tmp_path / "junk.geojson", grid)


# ---------------------------------------------------------------------------------- KDE and fit


def test_kde_com_of_a_tight_cluster_is_its_mean(rng: np.random.Generator) -> None:
    lengths = rng.normal(1500.0, 2.0, 200)
    values = rng.normal(40.0, 0.5, 200)
    kde = kde_centre_of_mass(lengths, values)
    assert kde.com[0] == pytest.approx(lengths.mean(), abs=0.05)
    assert kde.com[1] == pytest.approx(values.mean(), abs=0.05)
    assert kde.mode[0] == pytest.approx(1500.0, abs=1.5) and kde.mode[1] == pytest.approx(40.0, abs=0.5)
    assert kde.density.shape == (len(kde.ys), len(kde.xs))


def test_kde_mode_sits_in_the_dense_cluster(rng: np.random.Generator) -> None:
    lengths = np.concatenate([rng.normal(200, 5, 90), rng.normal(900, 5, 10)])
    values = np.concatenate([rng.normal(10, 1, 90), rng.normal(80, 1, 10)])
    kde = kde_centre_of_mass(lengths, values)
    assert abs(kde.mode[0] - 200) < 10 and abs(kde.mode[1] - 10) < 3
    assert 200 < kde.com[0] < 900  # the centre of mass is pulled by both clusters


def test_kde_degenerate_axes() -> None:
    kde = kde_centre_of_mass([100.0, 200.0, 300.0, 250.0], [0, 0, 0, 0])  # every path on rank 1
    assert kde.com[1] == 0.0 and kde.com[0] == pytest.approx(212.5, rel=0.05)
    assert "1-D" in kde.note and kde.density is None
    two = kde_centre_of_mass([10.0, 20.0], [1.0, 3.0])
    assert two.com == (15.0, 2.0) and "fewer than 3" in two.note
    with pytest.raises(EvaluateError):
        kde_centre_of_mass([], [])


def test_linear_fit_slope() -> None:
    x = np.array([100.0, 200.0, 300.0, 400.0])
    fit = linear_fit(x, 0.05 * x + 2.0)
    assert fit.slope == pytest.approx(0.05) and fit.intercept == pytest.approx(2.0) and fit.r == pytest.approx(1.0)
    assert linear_fit([5.0, 5.0], [1.0, 2.0]) is None


# ---------------------------------------------------------------------------------- sampling


def test_sampling_is_seeded_uniform_passable_and_separated() -> None:
    passable = np.ones((60, 80), dtype=bool)
    passable[:, 30:35] = False
    a = sample_pairs(passable, 40, np.random.default_rng(7), 20.0, (1.0, 1.0))
    b = sample_pairs(passable, 40, np.random.default_rng(7), 20.0, (1.0, 1.0))
    c = sample_pairs(passable, 40, np.random.default_rng(8), 20.0, (1.0, 1.0))
    assert a == b and a != c and len(a) == 40
    for (sr, sc), (gr, gc) in a:
        assert passable[sr, sc] and passable[gr, gc]
        assert math.hypot(sr - gr, sc - gc) >= 20.0
    # separation is measured in metres: 2 m wide pixels make columns count double
    wide = sample_pairs(passable, 30, np.random.default_rng(1), 100.0, (2.0, 1.0))
    assert all(math.hypot(sr - gr, 2 * (sc - gc)) >= 100.0 for (sr, sc), (gr, gc) in wide)


def test_the_papers_draw_is_seeded_and_uniform_over_every_cell() -> None:
    a = sample_pairs_uniform((40, 50), 400, np.random.default_rng(3))
    assert a == sample_pairs_uniform((40, 50), 400, np.random.default_rng(3)) and len(a) == 400
    assert a != sample_pairs_uniform((40, 50), 400, np.random.default_rng(4))
    cells = np.array([c for pair in a for c in pair])
    assert all(s != g for s, g in a) and cells.min() >= 0 and (cells.max(axis=0) < (40, 50)).all()
    # uniform: each quarter of the image gets about a quarter of the 800 ends
    quarter = np.bincount((cells[:, 0] >= 20) * 2 + (cells[:, 1] >= 25), minlength=4)
    assert quarter.min() > 150
    with pytest.raises(EvaluateError, match="fewer than 2 cells"):
        sample_pairs_uniform((1, 1), 3, np.random.default_rng(0))


def test_sampling_sparse_valid_cells_and_errors() -> None:
    passable = np.zeros((200, 200), dtype=bool)
    passable[5, 5] = passable[190, 190] = passable[5, 190] = True  # 3 of 40 000 cells
    pairs = sample_pairs(passable, 5, np.random.default_rng(0), 50.0, (1.0, 1.0))
    cells = {(5, 5), (190, 190), (5, 190)}
    assert len(pairs) == 5 and all(s in cells and g in cells and s != g for s, g in pairs)
    with pytest.raises(EvaluateError, match="longer than the map diagonal"):
        sample_pairs(passable, 5, np.random.default_rng(0), 1e6, (1.0, 1.0))
    with pytest.raises(EvaluateError, match="fewer than 2 passable"):
        sample_pairs(np.zeros((5, 5), dtype=bool), 5, np.random.default_rng(0), 1.0, (1.0, 1.0))


# ---------------------------------------------------------------------------------- IoU


GT = np.array([[1, 1, 0, 2, 2, 2], [1, 1, 0, 2, 2, 2], [0, 0, 0, 2, 2, 2], [1, 1, 1, 0, 0, 0]], dtype=np.uint8)


def _masks(tmp_path: Path, names: list[str], transform=None) -> Path:
    road = np.zeros_like(GT)
    road[0:2, 0:3] = 255  # 4 true positives, 2 false positives; misses the bottom row's 3 road pixels
    grass = np.zeros_like(GT)
    grass[0:3, 4:6] = 255
    grass[3, 5] = 255  # 6 TP, 1 FP, 3 FN
    tree = np.full_like(GT, 255)
    path = write_tif(tmp_path / "masks.tif", np.stack([road, grass, tree]), transform=transform)
    import rasterio

    with rasterio.open(path, "r+") as ds:
        for i, name in enumerate(names, start=1):
            ds.set_band_description(i, name)
    return path


def test_iou_exact_counts(tmp_path: Path) -> None:
    labels = write_tif(tmp_path / "gt.tif", GT)
    masks = _masks(tmp_path, ["road", "Grass", "tree"])
    res = compute_iou(masks, labels, ClassTable(CLASSES))
    by = {c.name: c for c in res.classes}
    assert (by["road"].tp, by["road"].fp, by["road"].fn) == (4, 2, 3) and by["road"].iou == pytest.approx(4 / 9)
    assert (by["grass"].tp, by["grass"].fp, by["grass"].fn) == (6, 1, 3) and by["grass"].iou == pytest.approx(0.6)
    assert res.mean_iou == pytest.approx((4 / 9 + 0.6) / 2)
    assert res.unmatched_bands == ("tree",) and set(res.missing_classes) == {"unlabeled", "water (Hydro)"}
    assert res.valid_pixels == GT.size and res.mode == "masks"


def test_iou_match_option_and_nodata(tmp_path: Path) -> None:
    gt = GT.copy()
    gt[0, 0] = 255  # a road TP becomes nodata: excluded
    labels = write_tif(tmp_path / "gt.tif", gt, nodata=255)
    masks = _masks(tmp_path, ["paved road", "lawn", "tree"])
    res = compute_iou(
        masks, labels, ClassTable(CLASSES), [("road", "paved road"), ("grass", "lawn"), ("grass", "tree")]
    )
    by = {c.name: c for c in res.classes}
    assert (by["road"].tp, by["road"].fp, by["road"].fn) == (3, 2, 3)
    # grass predicted by lawn OR tree (tree covers everything): 9 TP, every other valid pixel FP
    assert by["grass"].bands == ("lawn", "tree") and (by["grass"].tp, by["grass"].fp) == (9, GT.size - 1 - 9)
    with pytest.raises(EvaluateError, match="no band 'gravel'"):
        compute_iou(masks, labels, ClassTable(CLASSES), [("road", "gravel")])
    with pytest.raises(EvaluateError, match="unknown class 'path'"):
        compute_iou(masks, labels, ClassTable(CLASSES), [("path", "lawn")])


def test_iou_of_a_segmentation_masks_file_ignores_its_nodata(tmp_path: Path) -> None:
    """masks.tif as the segment stage writes it: uint8 0/1 per named band, 255 = nodata."""
    labels = write_tif(tmp_path / "gt.tif", GT)
    road = (GT == 1).astype(np.uint8)
    road[3, :] = 255  # the bottom row was never segmented: its 3 road pixels are not misses
    grass = np.zeros_like(GT)
    grass[3, :] = 255
    masks = write_tif(tmp_path / "masks.tif", np.stack([road, grass]), nodata=255)
    import rasterio

    with rasterio.open(masks, "r+") as ds:
        ds.descriptions = ("road", "grass")
    res = compute_iou(masks, labels, ClassTable(CLASSES))
    by = {c.name: c for c in res.classes}
    assert res.valid_pixels == 18
    assert (by["road"].tp, by["road"].fp, by["road"].fn) == (4, 0, 0) and by["road"].iou == 1.0
    assert (by["grass"].tp, by["grass"].fp, by["grass"].fn) == (0, 0, 9) and by["grass"].iou == 0.0


def test_iou_class_raster_against_itself_and_grid_mismatch(tmp_path: Path) -> None:
    labels = write_tif(tmp_path / "gt.tif", GT)
    res = compute_iou(labels, labels, ClassTable(CLASSES))
    assert res.mode == "classes"
    assert {c.name: c.iou for c in res.classes} == {"unlabeled": 1.0, "road": 1.0, "grass": 1.0, "water (Hydro)": None}
    assert res.mean_iou == 1.0
    shifted = _masks(tmp_path, ["road", "grass", "tree"], transform=from_origin(500001.0, 4000000.0, 0.5, 0.5))
    with pytest.raises(EvaluateError, match="different grids"):
        compute_iou(shifted, labels, ClassTable(CLASSES))


# ---------------------------------------------------------------------------------- plots


def _assert_png_not_blank(path: Path) -> None:
    from matplotlib.image import imread

    img = imread(path)
    assert img.ndim == 3 and img.shape[0] > 100 and img.shape[1] > 100
    assert float(img[..., :3].std()) > 0.05, f"{path} looks blank"


def test_plots_are_written_and_not_blank(tmp_path: Path, rng: np.random.Generator) -> None:
    from overseec_core.evaluate import maps, plots

    lengths = rng.uniform(100, 1000, 40)
    values = 0.05 * lengths + rng.normal(0, 5, 40)
    kde = kde_centre_of_mass(lengths, values)
    p1 = plots.plot_rrpi_vs_length(tmp_path / "rrpi.png", lengths, values, kde, linear_fit(lengths, values))
    grid = utm_grid(300, 200, 0.5, 0.5)
    cost = rng.random((200, 300)).astype(np.float32)
    cost[:20, :20] = np.nan
    costmap = write_tif(tmp_path / "cost.tif", cost, nodata=float("nan"))
    image = write_tif(tmp_path / "img.tif", rng.integers(0, 255, (3, 200, 300), dtype=np.uint8))
    path = [
        maps.PlotPath(np.array([(10, 10), (100, 150), (190, 290)])),
        maps.PlotPath(np.array([(50, 0), (50, 299)]), kind="reference", label="reference"),
    ]
    p2 = maps.plot_paths_overlay(tmp_path / "overlay.png", grid, path, costmap=costmap, image=image, max_size=64)
    p3 = plots.plot_iou(tmp_path / "iou.png", ["road", "grass", "water"], [0.5, 0.9, None], 0.7)
    for p in (p1, p2, p3):
        _assert_png_not_blank(p)
    assert not list(tmp_path.glob(".*partial*"))


def test_image_preview_is_decimated(tmp_path: Path, rng: np.random.Generator) -> None:
    from overseec_core.evaluate.previews import read_image_preview

    image = write_tif(tmp_path / "img.tif", rng.integers(0, 4000, (3, 200, 300), dtype=np.uint16))
    rgba, grid = read_image_preview(image, max_size=60)
    assert rgba.shape == (40, 60, 4) and rgba.dtype == np.uint8 and grid.width == 300
    assert rgba[..., :3].std() > 10 and (rgba[..., 3] == 255).all()


# ---------------------------------------------------------------------------------- the stage without a planner


def test_evaluate_given_paths_with_labels_reference_and_masks(tmp_path: Path) -> None:
    grid = utm_grid(40, 30)
    labels = np.full((30, 40), 2, dtype=np.uint8)  # grass
    labels[10, :] = 1  # an east-west road on row 10
    labels_tif = write_tif(tmp_path / "gt.tif", labels, transform=grid.transform)
    classes = write_classes(tmp_path / "classes.json")
    on_road = [(10, 0), (10, 39)]
    detour = [(10, 0), (15, 5), (15, 34), (10, 39)]  # same ends as the reference, strays 5 m from it
    elsewhere = [(20, 0), (20, 39)]  # other ends: no reference of its own, so no Hausdorff distance
    paths = write_lines(
        tmp_path / "paths.geojson", grid, [on_road, detour, elsewhere], names=["on", "off", "elsewhere"]
    )
    ref = write_lines(tmp_path / "ref.geojson", grid, [on_road], epsg=3857)
    out = tmp_path / "out"
    res = evaluate_paths(
        EvaluateOptions(
            out_dir=out,
            labels=labels_tif,
            classes=classes,
            ranks="road=1,grass=2",
            paths=paths,
            reference=ref,
            masks=labels_tif,
        )
    )
    m = json.loads((out / "metrics.json").read_text())
    by = {p["name"]: p for p in m["paths"]}
    # the detour: 6 + 29 + 5 = 40 pixels, of which only its two ends are road
    assert by["on"]["rrpi"] == 0 and by["off"]["rrpi"] == 38 and by["elsewhere"]["rrpi"] == 40
    assert by["on"]["length_m"] == pytest.approx(39.0) and by["on"]["pixels"] == 40
    assert by["on"]["hausdorff"]["directed_m"] == pytest.approx(0.0, abs=1e-3)
    assert by["off"]["hausdorff"]["directed_m"] == pytest.approx(5.0, abs=1e-3)
    assert by["off"]["hausdorff_references"] == ["line 0"]
    assert by["elsewhere"]["hausdorff"] is None and by["elsewhere"]["hausdorff_references"] == []
    diag = math.hypot(40, 30)
    h = m["hausdorff"]
    assert h["mean_normalised"] == pytest.approx((0 + 5.0 / diag) / 2, abs=1e-4)
    # the headline is the paper's: mean point distance per diagonal (the detour is 5 m off only
    # along its far side, so its mean is well under its maximum)
    off_mean = by["off"]["hausdorff"]["mean_m"]
    assert 0 < off_mean < 5.0 and h["headline"] == "mean_paper_normalised"
    assert h["mean_paper_normalised"] == pytest.approx((0 + off_mean / diag) / 2, abs=1e-4)
    assert m["summary"]["given"]["mean_hausdorff_paper"] == pytest.approx(h["mean_paper_normalised"])
    assert h["paths"] == "given" and h["n"] == 2 and h["n_paths"] == 3
    assert h["matched"] == {"given": {"matched": 2, "paths": 3}} and h["endpoint_tolerance_m"] == 3.0
    assert m["summary"]["given"]["n_hausdorff"] == 2
    # rank-optimal: on the road RRPI 0 is optimal; the detour has the road between its ends (inf);
    # from (20, 0) to (20, 39) the best route climbs 10 grass pixels to the road and back: RRPI 20
    assert (by["on"]["rrpi_optimal"], by["on"]["rrpi_ratio"]) == (0, 1.0)
    assert by["off"]["rrpi_optimal"] == 0 and by["off"]["rrpi_ratio"] is None and by["off"]["rrpi_ratio_infinite"]
    assert by["elsewhere"]["rrpi_optimal"] == 20 and by["elsewhere"]["rrpi_ratio"] == 2.0
    g = m["rank_optimal"]["groups"]["given"]
    assert m["rank_optimal"]["headline"] == "given"
    assert g["n"] == 3 and g["median_ratio"] == 2.0 and g["worst_ratio"] is None and g["n_infinite"] == 1
    assert g["share_within_5pct"] == pytest.approx(1 / 3) and g["mean_excess_rrpi"] == pytest.approx((0 + 38 + 20) / 3)
    assert m["iou"]["mean_iou"] == 1.0
    assert res.files["metrics"] == out / "metrics.json" and res.metrics["iou"] == m["iou"]
    report = (out / "report.md").read_text()
    for key in ("overlay_plot", "iou_plot"):
        assert f"]({m['files'][key]})" in report and (out / m["files"][key]).is_file()
        _assert_png_not_blank(out / m["files"][key])
    assert "## Rank-optimal reference" in report and "| given | 3 | 2.000 | 33 % | inf | 19.3 |" in report
    assert "matched: 2 of 3 given" in report
    gj = json.loads((out / "paths.geojson").read_text())
    lon, lat = gj["features"][0]["geometry"]["coordinates"][0]
    assert 14 < lon < 16 and 35 < lat < 37  # UTM 33N at 4000 km northing, written in WGS 84
    csv_rows = {r.split(",")[0]: r.split(",") for r in (out / "pairs.csv").read_text().splitlines()}
    header = csv_rows["name"]
    assert header[-4:] == ["rrpi_optimal", "rrpi_ratio", "hausdorff_references", "hausdorff_paper"]
    assert csv_rows["elsewhere"][-4:] == ["20", "2.0000", "", ""] and csv_rows["off"][-4:-1] == ["0", "inf", "line 0"]
    assert float(csv_rows["off"][-1]) == pytest.approx(off_mean / diag, abs=1e-6)
    assert "Hausdorff distance as the paper defines it" in report and f"**{h['mean_paper_normalised']:.4f}**" in report


def test_evaluate_refuses_paths_outside_and_overwriting_inputs(tmp_path: Path) -> None:
    grid = utm_grid(20, 20)
    labels_tif = write_tif(tmp_path / "gt.tif", np.ones((20, 20), dtype=np.uint8), transform=grid.transform)
    classes = write_classes(tmp_path / "classes.json")
    outside = write_lines(tmp_path / "p.geojson", grid, [[(5, 5), (5, 40)]], names=["long"])
    with pytest.raises(EvaluateError, match="'long'.*leaves the costmap"):
        evaluate_paths(EvaluateOptions(out_dir=tmp_path / "o", labels=labels_tif, classes=classes, paths=outside))
    with pytest.raises(InputError, match="nothing to evaluate"):
        evaluate_paths(EvaluateOptions(out_dir=tmp_path / "o", labels=labels_tif, classes=classes))
    write_classes(tmp_path / "metrics.json")  # an input named like an output
    from overseec_core.errors import OutputError

    with pytest.raises(OutputError, match="is the input"):
        evaluate_paths(
            EvaluateOptions(out_dir=tmp_path, labels=labels_tif, classes=tmp_path / "metrics.json", masks=labels_tif)
        )


def test_report_renders_without_optional_sections() -> None:
    text = render_report({"inputs": {}, "notes": ["something odd"], "files": {}})
    assert text.startswith("# overseec evaluation") and "> something odd" in text
