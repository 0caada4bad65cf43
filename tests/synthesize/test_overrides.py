"""Override polygons (issue 12): operator corrections applied after the cost program, by
`costmap --override` (block-wise, written) and by `plan --override` (in memory)."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import fiona
import numpy as np
import pytest
import rasterio
import shapely
from pyproj import Transformer
from rasterio.transform import from_origin
from rasterio.windows import Window

from overseec_core.cli import main
from overseec_core.io.grid import Grid
from overseec_core.plan import load_costmap
from overseec_core.plan.overrides import apply_to_planning_grid
from overseec_core.synthesize.overrides import (
    LETHAL_BURN,
    Override,
    OverrideSet,
    apply_to_block,
    classify,
    load_overrides,
)

ORIGIN = (500000.0, 4000000.0)  # UTM 33N
PX = 0.5
SHAPE = (80, 100)
TO_LONLAT = Transformer.from_crs("EPSG:32633", "EPSG:4326", always_xy=True)
PROMPT = "prefer the road, never enter the water, keep at least 2 m from buildings"


# ------------------------------------------------------------------------------------ helpers


def cells_box(r0: int, r1: int, c0: int, c1: int) -> shapely.Polygon:
    """Polygon (UTM) along cell edges covering the centres of rows r0..r1, cols c0..c1."""
    return shapely.box(ORIGIN[0] + c0 * PX, ORIGIN[1] - (r1 + 1) * PX, ORIGIN[0] + (c1 + 1) * PX, ORIGIN[1] - r0 * PX)


def utm(row: float, col: float) -> tuple[float, float]:
    """Map point inside cell (row, col)."""
    return ORIGIN[0] + (col + 0.5) * PX, ORIGIN[1] - (row + 0.5) * PX


def write_gpkg(path: Path, features: list[tuple[shapely.Geometry, dict]], crs: str = "EPSG:32633") -> Path:
    """A GeoPackage of polygons with cost (float), lethal and prefer (int) fields."""
    schema = {"geometry": "Polygon", "properties": {"cost": "float", "lethal": "int", "prefer": "int"}}
    with fiona.open(path, "w", driver="GPKG", crs=crs, schema=schema) as dst:
        for geom, props in features:
            dst.write(
                {
                    "geometry": shapely.geometry.mapping(geom),
                    "properties": {k: props.get(k) for k in ("cost", "lethal", "prefer")},
                }
            )
    return path


def write_lonlat_geojson(path: Path, features: list[tuple[dict | shapely.Geometry, dict]]) -> Path:
    """RFC 7946 GeoJSON (WGS 84) from UTM geometries (or raw GeoJSON geometry dicts)."""
    feats = []
    for geom, props in features:
        if isinstance(geom, dict):
            g = geom
        else:
            g = shapely.geometry.mapping(
                shapely.transform(geom, lambda xy: np.column_stack(TO_LONLAT.transform(xy[:, 0], xy[:, 1])))
            )
        feats.append({"type": "Feature", "geometry": g, "properties": props})
    path.write_text(json.dumps({"type": "FeatureCollection", "features": feats}))
    return path


def write_uniform_costmap(path: Path, value: float = 0.5) -> Path:
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        width=SHAPE[1],
        height=SHAPE[0],
        count=1,
        dtype="float32",
        crs="EPSG:32633",
        transform=from_origin(*ORIGIN, PX, PX),
        nodata=float("nan"),
    ) as ds:
        ds.write(np.full(SHAPE, value, np.float32), 1)
    return path


def read(path: Path) -> np.ndarray:
    with rasterio.open(path) as ds:
        return ds.read(1)


def sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def plan(costmap: Path, out: Path, start=(20, 5), goal=(20, 95), *extra: str) -> dict:
    """`overseec plan` between two cells; the GeoJSON feature."""
    argv = [
        "-q",
        "plan",
        str(costmap),
        "--start",
        *map(str, utm(*start)),
        "--goal",
        *map(str, utm(*goal)),
        "--out",
        str(out),
        *extra,
    ]
    assert main(argv) == 0
    return json.loads(out.read_text())["features"][0]


def route_cells(costmap: Path, feature: dict) -> np.ndarray:
    """(row, col) of each vertex of a GeoJSON route on the costmap's grid."""
    grid = load_costmap(costmap)
    lon, lat = np.array(feature["geometry"]["coordinates"]).T
    rows, cols = grid.world_to_pixel(lon, lat, crs="EPSG:4326")
    return np.column_stack([rows, cols])


@pytest.fixture
def labels_scene(tmp_path: Path) -> dict:
    """Class raster (grass, a road along rows 8-10, a water block, a building) on UTM 33N."""
    lab = np.ones(SHAPE, np.uint8)
    lab[8:11, :] = 2
    lab[25:60, 45:56] = 3
    lab[70:75, 20:30] = 4
    path = tmp_path / "labels.tif"
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        width=SHAPE[1],
        height=SHAPE[0],
        count=1,
        dtype="uint8",
        crs="EPSG:32633",
        transform=from_origin(*ORIGIN, PX, PX),
    ) as ds:
        ds.write(lab, 1)
    classes = tmp_path / "classes.json"
    classes.write_text(json.dumps({"1": "grass", "2": "road", "3": "water", "4": "building"}))
    return {"labels": path, "classes": classes, "dir": tmp_path}


def costmap_cli(scene: dict, out: Path, *extra: str) -> int:
    out.parent.mkdir(parents=True, exist_ok=True)
    return main(
        [
            "-q",
            "costmap",
            "--labels",
            str(scene["labels"]),
            "--classes",
            str(scene["classes"]),
            "--prompt",
            PROMPT,
            "--out",
            str(out),
            *extra,
        ]
    )


# ------------------------------------------------------------------------ feature properties


@pytest.mark.parametrize(
    "props, expected",
    [
        ({"cost": 0.25}, ("cost", 0.25)),
        ({"Cost": "0.8", "lethal": 0, "prefer": None}, ("cost", 0.8)),
        ({"cost": 0}, ("cost", 0.0)),
        ({"prefer": True}, ("prefer", 0.0)),
        ({"prefer": 1, "cost": None}, ("prefer", 0.0)),
        ({"lethal": "yes"}, ("lethal", 1.0)),
        ({"lethal": 1, "prefer": 0}, ("lethal", 1.0)),
    ],
)
def test_feature_kinds(props: dict, expected: tuple) -> None:
    assert classify(props) == expected


@pytest.mark.parametrize(
    "props, fragment",
    [
        ({}, "none of cost, lethal, prefer"),
        ({"lethal": 0, "prefer": False}, "none of cost, lethal, prefer"),
        ({"cost": 1.5}, "outside [0, 1]"),
        ({"cost": float("nan")}, "outside [0, 1]"),
        ({"cost": "cheap"}, "not a number"),
        ({"cost": 0.3, "lethal": True}, "both cost and lethal"),
        ({"prefer": 1, "lethal": 1}, "both lethal and prefer"),
        ({"lethal": "maybe"}, "lethal 'maybe' is not true/false"),
    ],
)
def test_bad_feature_properties(props: dict, fragment: str) -> None:
    with pytest.raises(ValueError, match=None) as err:
        classify(props)
    assert fragment in str(err.value)


# ------------------------------------------------------------------ overlap and cell rules


GRID = Grid(
    crs=rasterio.crs.CRS.from_epsg(32633), transform=from_origin(*ORIGIN, PX, PX), width=SHAPE[1], height=SHAPE[0]
)


def _set(*specs: tuple[str, float, shapely.Geometry]) -> OverrideSet:
    return OverrideSet(
        [Path("x.gpkg")],
        [Override(Path("x.gpkg"), str(i), kind, cost, geom) for i, (kind, cost, geom) in enumerate(specs)],
        GRID,
    )


def test_overlaps_lethal_wins_then_the_highest_cost_whatever_the_order() -> None:
    a = ("cost", 0.2, cells_box(0, 9, 0, 9))
    b = ("cost", 0.8, cells_box(5, 14, 5, 14))
    c = ("prefer", 0.0, cells_box(0, 30, 12, 20))
    d = ("lethal", 1.0, cells_box(10, 20, 15, 25))
    window = Window(0, 0, SHAPE[1], SHAPE[0])
    burns = [_set(*order).burn(window) for order in ((a, b, c, d), (d, c, b, a), (c, a, d, b))]
    for burn in burns[1:]:
        np.testing.assert_array_equal(burn, burns[0])
    burn = burns[0]
    assert burn[2, 2] == np.float32(0.2) and burn[7, 7] == np.float32(0.8)  # 0.2 under 0.8
    assert burn[12, 13] == np.float32(0.8)  # prefer (0.0) under cost 0.8
    assert burn[25, 13] == 0.0  # prefer alone
    assert burn[15, 17] == LETHAL_BURN  # prefer under lethal
    assert np.isnan(burn[40, 40])


def test_cells_are_covered_by_their_centre() -> None:
    # a polygon covering a bit less than half of cells 0..2 beyond col 9: only centres count
    poly = shapely.box(ORIGIN[0], ORIGIN[1] - 1.5, ORIGIN[0] + 10 * PX + 0.24, ORIGIN[1])
    burn = _set(("cost", 0.3, poly)).burn(Window(0, 0, 20, 5))
    assert np.isfinite(burn[0:3, 0:10]).all() and np.isnan(burn[0:3, 10:]).all()
    assert np.isnan(burn[3:]).all()


def test_block_rules_unblock_keep_out_and_lethal_but_not_nodata() -> None:
    cost = np.array([[0.5, 1.0, 0.7, np.nan]], np.float32)
    lethal = np.array([[0, 1, 2, 1]], np.uint8)
    new_cost, new_lethal, counts = apply_to_block(cost, lethal, np.full((1, 4), 0.1, np.float32))
    np.testing.assert_array_equal(new_lethal, [[0, 0, 0, 1]])
    np.testing.assert_allclose(new_cost[0, :3], 0.1) and np.isnan(new_cost[0, 3])
    assert (counts.covered, counts.cost, counts.unblocked, counts.lethal) == (3, 3, 2, 0)
    new_cost, new_lethal, counts = apply_to_block(cost, lethal, np.full((1, 4), LETHAL_BURN, np.float32))
    np.testing.assert_array_equal(new_lethal, [[1, 1, 1, 1]])
    assert new_cost[0, 2] == 1.0 and np.isnan(new_cost[0, 3])
    assert (counts.covered, counts.lethal) == (3, 2)
    assert cost[0, 0] == 0.5 and lethal[0, 2] == 2  # inputs untouched


# --------------------------------------------------------------------------- planning effects


def test_lethal_override_across_the_route_is_avoided(tmp_path: Path) -> None:
    costmap = write_uniform_costmap(tmp_path / "costmap.tif")
    wall = cells_box(0, 69, 48, 51)  # rows 70..79 stay open
    edits = write_gpkg(tmp_path / "edits.gpkg", [(wall, {"lethal": 1})])
    before = plan(costmap, tmp_path / "before.geojson")
    after = plan(costmap, tmp_path / "after.geojson", (20, 5), (20, 95), "--override", str(edits))
    cells_before, cells_after = route_cells(costmap, before), route_cells(costmap, after)
    assert any(48 <= c <= 51 and r <= 69 for r, c in cells_before)  # it crossed the wall's place
    assert not np.array_equal(cells_before, cells_after)
    xs, ys = np.array([utm(r, c) for r, c in cells_after]).T
    assert shapely.distance(wall, shapely.points(xs, ys)).min() > 0
    assert after["properties"]["overrides_applied"] is True
    assert after["properties"]["overrides"][0]["stage"] == "plan"
    assert before["properties"]["overrides_applied"] is False


def test_prefer_corridor_attracts_the_route(tmp_path: Path) -> None:
    costmap = write_uniform_costmap(tmp_path / "costmap.tif")
    corridor = cells_box(40, 42, 0, 99)
    edits = write_gpkg(tmp_path / "edits.gpkg", [(corridor, {"prefer": 1})])

    def share_inside(feature: dict) -> float:
        cells = route_cells(costmap, feature)
        return float(np.mean((cells[:, 0] >= 40) & (cells[:, 0] <= 42)))

    before = share_inside(plan(costmap, tmp_path / "before.geojson"))
    after = share_inside(plan(costmap, tmp_path / "after.geojson", (20, 5), (20, 95), "--override", str(edits)))
    assert before == 0.0 and after > 0.5


def _equivalence_edits(tmp_path: Path) -> Path:
    return write_gpkg(
        tmp_path / "edits.gpkg",
        [
            (cells_box(38, 42, 40, 60), {"prefer": 1}),  # a ford through the lethal water
            (cells_box(0, 30, 70, 73), {"lethal": 1}),  # a wall across the road
            (cells_box(60, 79, 10, 40), {"cost": 0.9}),  # over the building's keep-out zone
        ],
    )


def test_plan_override_equals_costmap_override_and_leaves_the_costmap_alone(labels_scene: dict, tmp_path: Path) -> None:
    edits = _equivalence_edits(tmp_path)
    plain, baked = tmp_path / "plain" / "costmap.tif", tmp_path / "baked" / "costmap.tif"
    assert costmap_cli(labels_scene, plain) == 0
    assert costmap_cli(labels_scene, baked, "--override", str(edits)) == 0
    hashes = {p: sha(p) for p in (plain, plain.with_name("lethal.tif"))}
    for start, goal in (((40, 2), (40, 97)), ((5, 2), (5, 97)), ((78, 0), (20, 99))):
        in_memory = plan(plain, tmp_path / "plain" / "p.geojson", start, goal, "--override", str(edits))
        from_file = plan(baked, tmp_path / "baked" / "p.geojson", start, goal)
        assert in_memory["geometry"] == from_file["geometry"]
        assert in_memory["properties"]["total_cost"] == pytest.approx(from_file["properties"]["total_cost"], rel=1e-12)
        assert from_file["properties"]["overrides"][0]["stage"] == "costmap"
    # cell by cell, with and without a lethal threshold (it applies to override costs too)
    for threshold in (None, 0.85):
        in_memory, _ = apply_to_planning_grid(
            load_costmap(plain, lethal_threshold=threshold), load_overrides([edits], GRID)
        )
        from_file = load_costmap(baked, lethal_threshold=threshold)
        np.testing.assert_array_equal(in_memory.cost, from_file.cost)
        np.testing.assert_array_equal(in_memory.keep_out, from_file.keep_out)
    assert np.isposinf(in_memory.cost[60:80, 10:41]).all()
    assert {p: sha(p) for p in hashes} == hashes
    # the ford is used: the route between the west and east edges crosses the water there
    lethal = read(baked.with_name("lethal.tif"))
    assert (lethal[38:43, 45:56] == 0).all() and (lethal[25:38, 45:56] == 1).all()
    assert (lethal[0:31, 70:74] == 1).all() and (lethal[60:80, 10:41] != 2).all()
    assert np.allclose(read(baked)[60:80, 10:41], 0.9)


def test_manifests_record_the_hashed_file_and_what_changed(labels_scene: dict, tmp_path: Path) -> None:
    edits = _equivalence_edits(tmp_path)
    plain, out = tmp_path / "plain" / "costmap.tif", tmp_path / "run" / "costmap.tif"
    assert costmap_cli(labels_scene, plain) == 0
    assert costmap_cli(labels_scene, out, "--override", str(edits)) == 0
    manifest = json.loads(out.with_name("manifest.json").read_text())
    entry = manifest["inputs"]["costmap_override_1_edits.gpkg"]
    assert entry["sha256"] == sha(edits)
    summary = manifest["costmap_overrides"]
    assert summary["features"] == {"cost": 1, "prefer": 1, "lethal": 1}
    # expected counts from the plain costmap and the polygons' cells
    cost0, flags0 = read(plain), read(plain.with_name("lethal.tif"))
    target = np.full(SHAPE, np.nan, np.float32)
    target[60:80, 10:41] = 0.9
    target[38:43, 40:61] = 0.0
    walled = np.zeros(SHAPE, bool)
    walled[0:31, 70:74] = True
    soft = np.isfinite(target) & ~walled
    assert summary["cells"] == {
        "covered": int((soft | walled).sum()),
        "lethal": int((walled & (flags0 != 1)).sum()),
        "cost": int((soft & ((flags0 != 0) | (cost0 != target))).sum()),
        "unblocked": int((soft & (flags0 != 0)).sum()),
    }
    assert summary["cells"]["unblocked"] > 0 and summary["cells"]["lethal"] == 124
    with rasterio.open(out) as ds:
        assert json.loads(ds.tags()["OVERSEEC_OVERRIDES"])["files"] == ["edits.gpkg"]
    plan(plain, tmp_path / "plain" / "p.geojson", (40, 2), (40, 97), "--override", str(edits))
    manifest = json.loads(plain.with_name("manifest.json").read_text())
    assert manifest["inputs"]["plan_override_1_edits.gpkg"]["sha256"] == sha(edits)
    assert manifest["plan_overrides"]["cells"] == summary["cells"]
    assert "costmap_overrides" not in manifest


def test_costmap_override_is_block_wise_exact(labels_scene: dict, tmp_path: Path) -> None:
    edits = _equivalence_edits(tmp_path)
    whole, blocks = tmp_path / "whole" / "costmap.tif", tmp_path / "blocks" / "costmap.tif"
    assert costmap_cli(labels_scene, whole, "--override", str(edits)) == 0
    assert costmap_cli(labels_scene, blocks, "--override", str(edits), "--block-size", "16") == 0
    for name in ("costmap.tif", "lethal.tif"):
        np.testing.assert_array_equal(read(whole.with_name(name)), read(blocks.with_name(name)))


# ---------------------------------------------------------------------------------- CRS


def test_lonlat_override_on_a_utm_costmap_lands_on_the_right_cells(labels_scene: dict, tmp_path: Path) -> None:
    box = cells_box(12, 19, 30, 44)
    edits = write_lonlat_geojson(tmp_path / "edits.geojson", [(box, {"cost": 0.75})])
    expected = np.zeros(SHAPE, bool)
    expected[12:20, 30:45] = True
    out = tmp_path / "c" / "costmap.tif"
    assert costmap_cli(labels_scene, out, "--override", str(edits)) == 0
    np.testing.assert_array_equal(read(out) == np.float32(0.75), expected)
    costmap = write_uniform_costmap(tmp_path / "uniform.tif")
    grid, counts = apply_to_planning_grid(load_costmap(costmap), load_overrides([edits], GRID))
    np.testing.assert_array_equal(grid.cost == np.float32(0.75), expected)
    assert counts.covered == counts.cost == expected.sum()


# ---------------------------------------------------------------------------------- errors


POINT = {"type": "Point", "coordinates": [15.0, 36.1]}


@pytest.mark.parametrize(
    "bad, fragment",
    [
        ({}, "feature fid 1 has none of cost, lethal, prefer"),
        ({"cost": 1.5}, "feature fid 1: cost 1.5 is outside [0, 1]"),
        ({"cost": 0.3, "lethal": True}, "feature fid 1 has both cost and lethal"),
        ("point", "feature fid 1 is a Point; overrides are polygons"),
    ],
)
@pytest.mark.parametrize("command", ["plan", "costmap"])
def test_bad_features_are_one_line_and_exit_2(
    labels_scene: dict, tmp_path: Path, capsys, bad, fragment: str, command: str
) -> None:
    good = (cells_box(0, 3, 0, 3), {"cost": 0.2})
    second = (POINT, {"cost": 0.2}) if bad == "point" else (cells_box(5, 8, 5, 8), bad)
    edits = write_lonlat_geojson(tmp_path / "edits.geojson", [good, second])
    out = tmp_path / "c" / "costmap.tif"
    if command == "plan":
        costmap = write_uniform_costmap(tmp_path / "costmap.tif")
        argv = [
            "-q",
            "plan",
            str(costmap),
            "--start",
            *map(str, utm(1, 1)),
            "--goal",
            *map(str, utm(9, 9)),
            "--out",
            str(tmp_path / "p.geojson"),
            "--override",
            str(edits),
        ]
        rc = main(argv)
    else:
        capsys.readouterr()
        rc = costmap_cli(labels_scene, out, "--override", str(edits))
    err = capsys.readouterr().err.strip()
    assert rc == 2
    assert len(err.splitlines()) == 1 and fragment in err and "edits.geojson" in err
    assert not out.exists() and not (tmp_path / "p.geojson").exists()


def test_missing_file_and_file_without_crs_are_one_line(tmp_path: Path, capsys) -> None:
    costmap = write_uniform_costmap(tmp_path / "costmap.tif")
    base = [
        "-q",
        "plan",
        str(costmap),
        "--start",
        *map(str, utm(1, 1)),
        "--goal",
        *map(str, utm(9, 9)),
        "--out",
        str(tmp_path / "p.geojson"),
    ]
    assert main(base + ["--override", str(tmp_path / "nope.gpkg")]) == 2
    assert "no such file" in capsys.readouterr().err
    shp = tmp_path / "nocrs.shp"
    with fiona.open(
        shp, "w", driver="ESRI Shapefile", schema={"geometry": "Polygon", "properties": {"cost": "float"}}
    ) as dst:
        dst.write({"geometry": shapely.geometry.mapping(cells_box(0, 3, 0, 3)), "properties": {"cost": 0.1}})
    assert main(base + ["--override", str(shp)]) == 2
    assert "has no CRS" in capsys.readouterr().err
