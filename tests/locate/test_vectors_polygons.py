"""Masks as polygons (`overseec_core.locate.vectors`, `overseec vectorize`): areas, strips, CRSs,
simplification, probabilities, atomic output, the CLI, and the real scenes' class rasters."""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import fiona
import numpy as np
import pytest
import shapely
import shapely.geometry
from pyproj import Geod
from rasterio.crs import CRS
from rasterio.transform import from_origin
from scipy import ndimage

from overseec_core import runfiles
from overseec_core.cli import EXIT_CANCELLED, EXIT_USER, main
from overseec_core.commands import vectorize as vectorize_command
from overseec_core.errors import Cancelled, InputError, OutputError
from overseec_core.io.grid import Grid
from overseec_core.io.read import open_raster
from overseec_core.io.write import write_array
from overseec_core.locate import polygonize, vectors
from overseec_core.progress import NullProgress
from overseec_core.synthesize.layers import load_class_entities

SCENES = Path(__file__).resolve().parents[2].parent / "shared" / "scenes"
UTM = CRS.from_epsg(32633)


def blobs(height: int, width: int, seed: int, fill: float = 0.45) -> np.ndarray:
    """A random mask with regions of many shapes and sizes: rings, U shapes, holes, islands."""
    rng = np.random.default_rng(seed)
    noise = ndimage.gaussian_filter(rng.normal(size=(height, width)), 2.0)
    return noise > np.quantile(noise, 1 - fill)


def class_raster(tmp_path: Path, labels: np.ndarray, grid: Grid, names: dict[int, str]) -> tuple[Path, Path]:
    tif = write_array(tmp_path / "labels.tif", labels.astype(np.uint8), grid)
    classes = tmp_path / "classes.json"
    classes.write_text(json.dumps({str(k): v for k, v in names.items()}))
    return tif, classes


def read_layers(path: Path) -> dict[str, list[dict]]:
    """Every layer of a GeoPackage: features as (geometry, properties) dicts."""
    out = {}
    for name in fiona.listlayers(path):
        with fiona.open(path, layer=name) as src:
            out[name] = [{"geometry": shapely.geometry.shape(f["geometry"]), **dict(f["properties"])} for f in src]
    return out


def same_polygons(a: list, b: list) -> bool:
    """The same polygons, one for one (topological equality, whatever the vertex order)."""
    if len(a) != len(b):
        return False
    tree = shapely.STRtree(b)
    used: set[int] = set()
    for geom in a:
        match = [i for i in tree.query(geom, predicate="covers") if i not in used and b[i].equals(geom)]
        if not match:
            return False
        used.add(int(match[0]))
    return True


# --------------------------------------------------------------------------------------------
# Areas, strips, CRSs
# --------------------------------------------------------------------------------------------


def test_areas_are_the_pixel_counts_times_the_pixel_area_exactly(tmp_path: Path) -> None:
    grid = Grid(UTM, from_origin(534_000.0, 5_213_000.0, 0.5, 0.5), 97, 83)
    labels = blobs(83, 97, seed=1).astype(np.uint8) + 2 * blobs(83, 97, seed=2, fill=0.2)
    labels[labels > 2] = 2
    tif, classes = class_raster(tmp_path, labels, grid, {0: "unlabeled", 1: "grass", 2: "water"})
    out = tmp_path / "v.gpkg"
    result = vectors.vectorize_labels(tif, load_class_entities(classes), out, classes_file=classes, block_rows=16)
    layers = read_layers(out)
    assert sorted(layers) == ["grass", "water"]  # background skipped as load_class_entities does
    for cid, name in ((1, "grass"), (2, "water")):
        feats = layers[name]
        assert sum(f["pixels"] for f in feats) == int((labels == cid).sum())
        assert all(f["area_m2"] == f["pixels"] * 0.25 for f in feats)  # exact: 0.5 m pixels
        assert all(f["geometry"].area == pytest.approx(f["area_m2"], rel=1e-12) for f in feats)  # metric CRS
        assert all(f["mean_prob"] == 1.0 and f["geometry"].is_valid for f in feats)
        n_regions = ndimage.label(labels == cid)[1]
        assert len(feats) == n_regions  # one polygon per 4-connected region
        summary = next(s for s in result.layers if s.name == name)
        assert summary.polygons == len(feats) and summary.area_m2 == pytest.approx((labels == cid).sum() * 0.25)


@pytest.mark.parametrize("block_rows", [1, 3, 7, 16, 50])
def test_polygons_crossing_strips_come_out_whole_whatever_the_strip_height(tmp_path: Path, block_rows: int) -> None:
    """Strips of any height (one row included) give the very polygons of a one-strip run."""
    grid = Grid(UTM, from_origin(534_000.0, 5_213_000.0, 1.0, 1.0), 70, 61)
    labels = blobs(61, 70, seed=3, fill=0.55).astype(np.uint8)
    labels[5:40, 10:14] = 1  # a tall bar through many seams
    labels[20:30, 30:60] = 1
    labels[23:27, 35:55] = 0  # a ring whose hole closes only across the seams
    tif, classes = class_raster(tmp_path, labels, grid, {1: "thing"})
    names = load_class_entities(classes)
    whole = vectors.vectorize_labels(tif, names, tmp_path / "whole.gpkg", block_rows=10_000)
    split = vectors.vectorize_labels(tif, names, tmp_path / f"b{block_rows}.gpkg", block_rows=block_rows)
    a = read_layers(tmp_path / "whole.gpkg")["thing"]
    b = read_layers(tmp_path / f"b{block_rows}.gpkg")["thing"]
    assert same_polygons([f["geometry"] for f in a], [f["geometry"] for f in b])
    assert sorted(f["pixels"] for f in a) == sorted(f["pixels"] for f in b)
    assert whole.layers == split.layers and len(a) == ndimage.label(labels == 1)[1]
    assert any(len(f["geometry"].interiors) for f in b)  # the ring kept its hole


def test_a_region_split_by_a_seam_joins_into_one_polygon() -> None:
    """The polygonizer alone: a U shape whose arms meet only in the lower strip, and a ring
    over three strips, each come out once, whole."""
    mask = np.zeros((9, 8), bool)
    mask[0:6, 1] = mask[0:6, 5] = True  # the arms: two regions in the upper strip
    mask[5, 1:6] = True  # the base joins them below the seam
    mask[6:9, 2:7] = True
    mask[7, 4] = False  # a hole in the lowest strip
    poly = polygonize.StripPolygonizer(9)
    found = []
    for row0 in (0, 3, 6):
        found += list(poly.feed(mask[row0 : row0 + 3], None, row0))
    found += list(poly.finish())
    assert len(found) == 1 and found[0].pixels == int(mask.sum()) and found[0].polygon.area == mask.sum()
    assert found[0].polygon.geom_type == "Polygon" and len(found[0].polygon.interiors) == 1


def test_open_regions_are_only_those_reaching_the_newest_seam() -> None:
    """Memory does not grow with the image: on a tall strip of small blobs, the regions kept
    open at any time are at most those reaching the newest strip's last row, and the finished
    ones leave at once."""
    mask = blobs(3000, 80, seed=11, fill=0.3)
    rows = 50
    poly = polygonize.StripPolygonizer(len(mask))
    most_open, out = 0, 0
    for row0 in range(0, len(mask), rows):
        out += len(list(poly.feed(mask[row0 : row0 + rows], None, row0)))
        seam = row0 + rows
        if seam < len(mask):
            runs = ndimage.label(mask[seam - 1])[1]  # stretches of mask along the strip's last row
            assert len(poly._open) <= runs
        most_open = max(most_open, len(poly._open))
    out += len(list(poly.finish()))
    assert out == ndimage.label(mask)[1] and 0 < most_open < 20


def test_a_geographic_raster_gives_areas_in_square_metres(tmp_path: Path) -> None:
    """EPSG:4326 at 36 N (Las Vegas, the real scenes' grid): area_m2 is the geodesic area of
    the polygon on the ellipsoid, not square degrees."""
    step = 2.7e-6
    grid = Grid(CRS.from_epsg(4326), from_origin(-115.30, 36.20, step, step), 120, 90)
    labels = blobs(90, 120, seed=4, fill=0.3).astype(np.uint8)
    tif, classes = class_raster(tmp_path, labels, grid, {1: "road"})
    out = tmp_path / "geo.gpkg"
    result = vectors.vectorize_labels(tif, load_class_entities(classes), out, block_rows=32)
    px, py = grid.pixel_size_m()
    assert 0.2 < px < 0.3 and 0.29 < py < 0.31  # not square on the ground
    geod = Geod(ellps="WGS84")
    feats = read_layers(out)["road"]
    for f in feats:
        assert f["area_m2"] == pytest.approx(f["pixels"] * px * py, rel=1e-12)
        true = abs(geod.geometry_area_perimeter(f["geometry"])[0])
        assert f["area_m2"] == pytest.approx(true, rel=2e-3)
        assert f["geometry"].bounds[0] > -115.31  # in the raster's CRS: degrees
    assert result.layers[0].area_m2 == pytest.approx(float(labels.sum()) * px * py)


def test_web_mercator_areas_are_ground_metres_not_map_metres(tmp_path: Path) -> None:
    """At 47 N a Web Mercator metre is 0.68 ground metres: areas shrink by its square."""
    from pyproj import Transformer

    x0, y0 = Transformer.from_crs(4326, 3857, always_xy=True).transform(8.0, 47.0)
    grid = Grid(CRS.from_epsg(3857), from_origin(x0, y0, 0.1, 0.1), 80, 60)
    labels = blobs(60, 80, seed=5).astype(np.uint8)
    tif, classes = class_raster(tmp_path, labels, grid, {1: "building"})
    out = tmp_path / "wm.gpkg"
    vectors.vectorize_labels(tif, load_class_entities(classes), out)
    to_ll = Transformer.from_crs(3857, 4326, always_xy=True)
    geod = Geod(ellps="WGS84")
    for f in read_layers(out)["building"]:
        lonlat = shapely.transform(f["geometry"], lambda xy: np.column_stack(to_ll.transform(xy[:, 0], xy[:, 1])))
        assert f["area_m2"] == pytest.approx(abs(geod.geometry_area_perimeter(lonlat)[0]), rel=1e-3)
        assert f["area_m2"] == pytest.approx(f["geometry"].area * math.cos(math.radians(47.0)) ** 2, rel=2e-3)


def test_simplified_polygons_stay_valid_with_fewer_vertices_and_close_areas(tmp_path: Path) -> None:
    grid = Grid(UTM, from_origin(534_000.0, 5_213_000.0, 0.5, 0.5), 150, 130)
    labels = blobs(130, 150, seed=6, fill=0.5).astype(np.uint8)
    tif, classes = class_raster(tmp_path, labels, grid, {1: "grass"})
    names = load_class_entities(classes)
    vectors.vectorize_labels(tif, names, tmp_path / "exact.gpkg", block_rows=40)
    result = vectors.vectorize_labels(tif, names, tmp_path / "simple.gpkg", simplify_m=1.0, block_rows=40)
    exact, simple = read_layers(tmp_path / "exact.gpkg")["grass"], read_layers(tmp_path / "simple.gpkg")["grass"]
    assert all(f["geometry"].is_valid and not f["geometry"].is_empty for f in simple)
    assert all(f["geometry"].geom_type == "Polygon" for f in simple)
    count = lambda fs: sum(len(shapely.get_coordinates(f["geometry"])) for f in fs)  # noqa: E731
    assert count(simple) < 0.6 * count(exact)
    assert all(f["area_m2"] == pytest.approx(f["geometry"].area, rel=1e-9) for f in simple)  # metric, square px
    total = float(labels.sum()) * 0.25
    assert result.layers[0].area_m2 == pytest.approx(total, rel=0.02)
    assert result.to_json()["simplify_m"] == 1.0


# --------------------------------------------------------------------------------------------
# Segment folders: bands, probabilities
# --------------------------------------------------------------------------------------------


def segment_folder(folder: Path, refined: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """masks.tif (uint8, 255 nodata) + probs.tif (float32, NaN nodata) as `overseec segment` writes
    them; with ``refined`` the refined pair too (different masks, so which was read shows)."""
    folder.mkdir(parents=True, exist_ok=True)
    grid = Grid(UTM, from_origin(534_000.0, 5_213_000.0, 0.5, 0.5), 64, 48)
    rng = np.random.default_rng(9)
    probs = np.stack([ndimage.gaussian_filter(rng.random((48, 64)), 3) for _ in range(2)]).astype(np.float32)
    probs = (probs - probs.min()) / (probs.max() - probs.min())
    masks = (probs >= 0.5).astype(np.uint8)
    masks[:, :4, :6] = 255  # nodata corner
    probs[:, :4, :6] = np.nan
    names = ("road", "tree crown")
    write_array(folder / runfiles.MASKS, masks, grid, nodata=255, descriptions=names)
    write_array(folder / runfiles.PROBS, probs, grid, nodata=float("nan"), descriptions=names)
    if refined:
        masks = (probs >= 0.6).astype(np.uint8)
        write_array(folder / runfiles.REFINED_MASKS, masks, grid, nodata=255, descriptions=names)
        write_array(folder / runfiles.REFINED_PROBS, probs, grid, nodata=float("nan"), descriptions=names)
    return masks, probs


def test_a_segment_folder_gives_one_layer_per_band_with_mean_probabilities(tmp_path: Path) -> None:
    masks, probs = segment_folder(tmp_path / "run", refined=True)
    out = tmp_path / "run" / "masks.gpkg"
    result = vectors.vectorize_folder(tmp_path / "run", out, block_rows=7)
    layers = read_layers(out)
    assert list(layers) == ["road", "tree crown"] and result.source == "segment folder"
    assert result.inputs[0].name == runfiles.REFINED_MASKS  # refined preferred
    for k, name in enumerate(layers):
        lab, n = ndimage.label(masks[k] == 1)
        expected = sorted((int((lab == i).sum()), float(probs[k][lab == i].mean())) for i in range(1, n + 1))
        got = sorted((f["pixels"], f["mean_prob"]) for f in layers[name])
        assert [g[0] for g in got] == [e[0] for e in expected]
        assert np.allclose([g[1] for g in got], [e[1] for e in expected], rtol=1e-6)
        assert all(f["mean_prob"] >= 0.6 for f in layers[name])  # refined masks: probs >= 0.6
    with fiona.open(out, layer="road") as src:
        assert CRS.from_wkt(src.crs_wkt) == UTM
    entry = json.loads((tmp_path / "run" / runfiles.MANIFEST).read_text())["vectors"]["masks.gpkg"]
    assert entry["polygons"] == sum(len(v) for v in layers.values())


def test_a_folder_without_probabilities_leaves_mean_prob_empty(tmp_path: Path) -> None:
    segment_folder(tmp_path / "run")
    (tmp_path / "run" / runfiles.PROBS).unlink()
    vectors.vectorize_folder(tmp_path / "run", tmp_path / "v.gpkg")
    assert {f["mean_prob"] for f in read_layers(tmp_path / "v.gpkg")["road"]} == {None}


def test_errors_are_one_line_and_nothing_is_written(tmp_path: Path) -> None:
    segment_folder(tmp_path / "run")
    with pytest.raises(InputError, match="no such folder"):
        vectors.vectorize_folder(tmp_path / "nothing", tmp_path / "v.gpkg")
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match=f"no {runfiles.MASKS}"):
        vectors.vectorize_folder(tmp_path / "empty", tmp_path / "v.gpkg")
    with pytest.raises(OutputError, match=r"\*\.gpkg"):
        vectors.vectorize_folder(tmp_path / "run", tmp_path / "v.shp")
    with pytest.raises(OutputError, match="is the input"):
        vectors.vectorize_folder(tmp_path / "run", tmp_path / "run" / runfiles.MASKS)
    assert not (tmp_path / "v.gpkg").exists() and not (tmp_path / "v.shp").exists()


class CancelAfter(NullProgress):
    """Asks to stop after ``n`` strips."""

    def __init__(self, n: int) -> None:
        super().__init__()
        self.n = n

    def cancelled(self) -> bool:
        return self.done >= self.n

    def advance(self, n: int = 1) -> None:
        self.done = getattr(self, "done", 0) + n


def test_a_cancel_leaves_the_earlier_file_and_no_partial_one(tmp_path: Path) -> None:
    segment_folder(tmp_path / "run")
    out = tmp_path / "v.gpkg"
    vectors.vectorize_folder(tmp_path / "run", out)
    before = out.read_bytes()
    with pytest.raises(Cancelled):
        vectors.vectorize_folder(tmp_path / "run", out, block_rows=4, progress=CancelAfter(5))
    assert out.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["manifest.json", "run", "v.gpkg"]


# --------------------------------------------------------------------------------------------
# The command
# --------------------------------------------------------------------------------------------


def test_the_cli_end_to_end_prints_a_json_summary(tmp_path: Path, capsys) -> None:
    segment_folder(tmp_path / "run")
    out = tmp_path / "new" / "masks.gpkg"  # a missing folder is created
    assert main(["-q", "vectorize", str(tmp_path / "run"), "--out", str(out), "--simplify", "0.5", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [layer["name"] for layer in doc["layers"]] == ["road", "tree crown"]
    layers = read_layers(out)
    assert [layer["polygons"] for layer in doc["layers"]] == [len(v) for v in layers.values()]
    assert doc["layers"][0]["area_m2"] == pytest.approx(sum(f["area_m2"] for f in layers["road"]))
    manifest = json.loads((out.parent / runfiles.MANIFEST).read_text())
    assert manifest["commands"][-1]["command"] == "vectorize"
    assert manifest["vectors"]["masks.gpkg"]["simplify_m"] == 0.5
    assert any(k.endswith(runfiles.MASKS) for k in manifest["inputs"])


def test_the_cli_reads_a_class_raster_and_prints_its_layers(tmp_path: Path, capsys) -> None:
    grid = Grid(UTM, from_origin(534_000.0, 5_213_000.0, 0.5, 0.5), 40, 30)
    labels = blobs(30, 40, seed=8).astype(np.uint8)
    tif, classes = class_raster(tmp_path, labels, grid, {0: "background", 1: "water (Hydro)"})
    code = main(["-q", "vectorize", "--labels", str(tif), "--classes", str(classes), "--out", str(tmp_path / "c.gpkg")])
    printed = capsys.readouterr().out
    assert code == 0 and printed.startswith("water: ") and f"{labels.sum() * 0.25:.6g} m²" in printed


@pytest.mark.parametrize(
    "argv, says",
    [
        (["{tmp}/nothing"], "no such folder"),
        (["--labels", "{tmp}/labels.tif", "--classes", "{tmp}/other.json"], "is this the right classes.json"),
        (["--labels", "{tmp}/labels.tif", "--classes", "{tmp}/broken.json"], "not JSON ("),
        (["--labels", "{tmp}/labels.tif"], "--labels needs --classes"),
        (["{tmp}/run", "--labels", "{tmp}/labels.tif"], "not both"),
        ([], "give a segment folder"),
    ],
)
def test_cli_errors_are_one_line_with_exit_2(tmp_path: Path, capsys, argv: list[str], says: str) -> None:
    segment_folder(tmp_path / "run")
    grid = Grid(UTM, from_origin(534_000.0, 5_213_000.0, 0.5, 0.5), 20, 20)
    class_raster(tmp_path, blobs(20, 20, seed=1).astype(np.uint8), grid, {1: "grass"})
    (tmp_path / "other.json").write_text(json.dumps({"7": "road", "8": "water"}))
    (tmp_path / "broken.json").write_text("{not json")
    out = tmp_path / "out" / "v.gpkg"
    code = main(["-q", "vectorize", *(a.format(tmp=tmp_path) for a in argv), "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == EXIT_USER and len(err.splitlines()) == 1 and says in err, err
    assert not (tmp_path / "out").exists()  # no folder left behind


def test_the_cli_cancelled_is_exit_130(tmp_path: Path, monkeypatch, capsys) -> None:
    segment_folder(tmp_path / "run")
    monkeypatch.setattr("overseec_core.cli.make_progress", lambda args, token: CancelAfter(1))
    assert main(["vectorize", str(tmp_path / "run"), "--out", str(tmp_path / "v.gpkg")]) == EXIT_CANCELLED
    assert not (tmp_path / "v.gpkg").exists()


def test_the_command_default_strip_height_is_the_cores() -> None:
    assert vectorize_command.DEFAULT_BLOCK_ROWS == vectors.DEFAULT_BLOCK_ROWS


# --------------------------------------------------------------------------------------------
# The issue's bar: the real scenes' class rasters
# --------------------------------------------------------------------------------------------


def real_class_rasters() -> list[tuple[str, Path, Path]]:
    found = []
    for classes in sorted(SCENES.glob("*/classes.json")):
        for gt in sorted(classes.parent.glob("gt*.tif")):
            found.append((f"{classes.parent.name}/{gt.name}", gt, classes))
    return found


REAL = real_class_rasters()


@pytest.mark.skipif(not REAL, reason=f"the real scenes are not in {SCENES}")
@pytest.mark.parametrize("name, gt, classes", REAL, ids=[r[0] for r in REAL])
def test_real_scene_polygons_reproduce_the_class_areas(tmp_path: Path, name: str, gt: Path, classes: Path) -> None:
    """The issue's bar: total polygon area per class within 0.5 % of the class's pixel area (here
    exact to rounding at the default, no simplification), strips of 256 rows."""
    entities = load_class_entities(classes)
    t0 = time.perf_counter()
    result = vectors.vectorize_labels(gt, entities, tmp_path / "v.gpkg", classes_file=classes, block_rows=256)
    seconds = time.perf_counter() - t0
    with open_raster(gt) as ds:
        counts = np.bincount(ds.read(1).ravel(), minlength=256)
        if ds.nodata is not None:  # nodata pixels belong to no class (the Quebec tiles' 0)
            counts[int(ds.nodata)] = 0
        grid = Grid(ds.crs, ds.transform, ds.width, ds.height)
    px, py = grid.pixel_size_m()
    layers = read_layers(tmp_path / "v.gpkg")
    worst = 0.0
    for summary in result.layers:
        ids = [cid for cid, n in entities.items() if n == summary.name]
        pixel_area = float(counts[ids].sum()) * px * py
        polygon_area = sum(f["area_m2"] for f in layers[summary.name])
        assert sum(f["pixels"] for f in layers[summary.name]) == int(counts[ids].sum())
        if pixel_area:
            worst = max(worst, abs(polygon_area - pixel_area) / pixel_area)
    assert worst <= 0.005
    assert worst <= 1e-9  # exact pixel edges: the areas are the counts
    assert all(f["geometry"].is_valid for fs in layers.values() for f in fs)
    print(f"{name}: worst relative area error {worst:.2e}, {seconds:.2f} s")


class _Said(NullProgress):
    """A progress that keeps what it was told."""

    def __init__(self) -> None:
        super().__init__()
        self.said: list[str] = []

    def message(self, text: str) -> None:
        self.said.append(text)


def test_a_speckled_mask_says_its_count_its_rate_and_how_to_make_it_smaller(tmp_path: Path, monkeypatch) -> None:
    """A checkerboard of one-pixel polygons (issue 33 rule 7): the count and the rate are said as
    they grow, and once past the very-many mark one line says how to make it smaller."""
    monkeypatch.setattr(vectors, "COUNT_EVERY", 500)
    monkeypatch.setattr(vectors, "VERY_MANY_POLYGONS", 1200)
    side = 60
    labels = ((np.add.outer(np.arange(side), np.arange(side)) % 2) == 0).astype(np.uint8)  # 1800 one-pixel squares
    grid = Grid(UTM, from_origin(534_000.0, 5_213_000.0, 0.5, 0.5), side, side)
    tif, classes = class_raster(tmp_path, labels, grid, {0: "unlabeled", 1: "speckle"})
    said = _Said()
    result = vectors.vectorize_labels(
        tif, load_class_entities(classes), tmp_path / "v.gpkg", classes_file=classes, progress=said
    )
    assert result.layers[0].polygons == side * side // 2
    counts = [t for t in said.said if "polygons so far" in t]
    assert [t.split(": ")[2].split(" ")[0] for t in counts] == ["500", "1,000", "1,500"]
    assert all(t.endswith("/s)") for t in counts)
    (warning,) = [t for t in said.said if "over 1,200 polygons" in t]
    assert "--simplify" in warning and "gdal_sieve.py" in warning
