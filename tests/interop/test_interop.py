"""Exports for robot and routing stacks, each read back by a reader of its format: Nav2 YAML +
PGM/PNG through a re-implementation of Nav2's map_io loader, costmap_2d GeoTIFF through rasterio,
npy + JSON through numpy, GPX and KML through OGR (fiona), CSV numerically."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import fiona
import numpy as np
import pytest
import rasterio
import yaml
from affine import Affine
from PIL import Image
from rasterio.crs import CRS
from rasterio.transform import from_origin

from overseec_core.cli import main
from overseec_core.errors import InputError
from overseec_core.interop import CostmapExportOptions, PathExportOptions, export_costmap, export_path
from overseec_core.interop.costmap import (
    KEEP_OUT_MEANING,
    costmap2d_values,
    scale_occupancy,
    scale_pixels,
)
from overseec_core.interop.frames import nav2_geometry
from overseec_core.interop.paths import gpx_text, parse_paths
from overseec_core.io.grid import Grid
from overseec_core.plan import load_costmap
from tests.plan.conftest import UTM_ORIGIN, smooth_costmap, write_costmap, write_lethal

H, W = 40, 50


@pytest.fixture
def scene(tmp_path: Path) -> dict:
    """A 40 x 50 UTM costmap at 0.5 m: costs across [0, 1] (0.5 included), a no-data block, a
    lethal wall and a keep-out zone in overseec's own tagged sidecar."""
    cost = smooth_costmap((H, W), seed=7, lethal_fraction=0.0)
    cost[0, :5] = [0.0, 0.25, 0.5, 0.75, 1.0]
    cost[30:35, 2:8] = np.nan
    lethal = np.zeros((H, W), np.uint8)
    lethal[5:25, 20] = 1
    lethal[10:14, 30:36] = 2
    lethal[31, 3] = 1  # a lethal flag on a no-data cell stays no data
    costmap = write_costmap(
        tmp_path / "costmap.tif",
        cost,
        tags={"OVERSEEC_LETHAL_FILE": "lethal.tif", "OVERSEEC_PROMPT": "prefer the road"},
    )
    write_lethal(tmp_path / "lethal.tif", lethal, tags={"OVERSEEC_COSTMAP_FILE": "costmap.tif"})
    out = tmp_path / "out"
    out.mkdir()
    return {"costmap": costmap, "cost": cost, "lethal": lethal, "dir": tmp_path, "out": out}


def classes(scene: dict) -> dict[str, np.ndarray]:
    nodata = np.isnan(scene["cost"])
    lethal = (scene["lethal"] == 1) & ~nodata
    keep = (scene["lethal"] == 2) & ~nodata
    return {"nodata": nodata, "lethal": lethal, "keep_out": keep, "passable": ~(nodata | lethal | keep)}


# ------------------------------------------------------------------------------------------------
# Nav2: a reader written from nav2_map_server/src/map_io.cpp (loadMapYaml + loadMapFromFile)
# ------------------------------------------------------------------------------------------------


def read_pgm(path: Path) -> np.ndarray:
    """Parse a binary PGM (P5, maxval 255, comments allowed) with numpy alone."""
    data = path.read_bytes()
    tokens, pos = [], 0
    while len(tokens) < 4:
        while data[pos : pos + 1].isspace():
            pos += 1
        if data[pos : pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end : end + 1].isspace():
            end += 1
        tokens.append(data[pos:end])
        pos = end
    assert tokens[0] == b"P5" and int(tokens[3]) == 255
    w, h = int(tokens[1]), int(tokens[2])
    pixels = np.frombuffer(data[pos + 1 :], dtype=np.uint8)
    assert pixels.size == w * h
    return pixels.reshape(h, w)


def nav2_load(yaml_path: Path) -> tuple[dict, np.ndarray]:
    """(YAML, OccupancyGrid data as (height, width) int8 with row 0 = the map's bottom row)."""
    doc = yaml.safe_load(yaml_path.read_text())
    for key in ("image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh"):
        assert key in doc, key
    assert len(doc["origin"]) == 3
    image = yaml_path.parent / doc["image"]
    mode = doc.get("mode", "trinary")
    if image.suffix == ".pgm":
        grey, alpha = read_pgm(image).astype(float), None
    else:
        img = Image.open(image)
        assert img.mode == "LA"
        arr = np.asarray(img)
        grey, alpha = arr[..., 0].astype(float), arr[..., 1]
    shade = grey / 255.0
    occ = shade if doc["negate"] else 1.0 - shade
    o, f = doc["occupied_thresh"], doc["free_thresh"]
    if mode == "trinary":
        cell = np.where(o < occ, 100, np.where(occ < f, 0, -1))
    else:
        assert mode == "scale"
        cell = np.where(o < occ, 100, np.where(occ < f, 0, np.rint((occ - f) / (o - f) * 100.0)))
        if alpha is not None:
            cell = np.where(alpha != 255, -1, cell)
    # msg.data[width * (height - y - 1) + x] = cell(x, y): image row y is map row height - y - 1
    return doc, cell.astype(np.int8)[::-1]


def test_nav2_trinary_round_trip(scene: dict) -> None:
    out = scene["out"] / "map.yaml"
    origin = (UTM_ORIGIN[0] - 100.0, UTM_ORIGIN[1] - 1000.0)
    export_costmap(CostmapExportOptions(scene["costmap"], "nav2", out, local_origin=origin))
    doc, cells = nav2_load(out)
    assert doc["mode"] == "trinary" and doc["image"] == "map.pgm"
    bottom_up = {k: v[::-1] for k, v in classes(scene).items()}
    assert cells.shape == (H, W)
    assert (cells[bottom_up["lethal"]] == 100).all() and bottom_up["lethal"].any()
    assert (cells[bottom_up["keep_out"]] == 100).all() and bottom_up["keep_out"].any()
    assert (cells[bottom_up["nodata"]] == -1).all() and bottom_up["nodata"].any()
    assert (cells[bottom_up["passable"]] == 0).all()
    # geometry: map cell (x, y) centre = origin + (x + 0.5, y + 0.5) * resolution equals the
    # GeoTIFF's centre of pixel (row H - 1 - y, col x) minus the recorded local origin
    assert doc["resolution"] == 0.5 and doc["origin"][2] == 0.0
    assert doc["overseec_local_origin"] == list(origin)
    assert CRS.from_wkt(doc["overseec_crs_wkt"]) == CRS.from_epsg(32633)
    with rasterio.open(scene["costmap"]) as ds:
        t = ds.transform
    for x, y in [(0, 0), (W - 1, 0), (0, H - 1), (17, 23)]:
        mx = doc["origin"][0] + (x + 0.5) * doc["resolution"]
        my = doc["origin"][1] + (y + 0.5) * doc["resolution"]
        gx, gy = t * (x + 0.5, (H - 1 - y) + 0.5)
        assert mx == pytest.approx(gx - origin[0], abs=1e-9)
        assert my == pytest.approx(gy - origin[1], abs=1e-9)
    assert doc["origin"][:2] == [100.0, 1000.0 - H * 0.5]


def test_nav2_default_origin_is_the_lower_left_corner(scene: dict) -> None:
    out = scene["out"] / "map.yaml"
    export_costmap(CostmapExportOptions(scene["costmap"], "nav2", out))
    doc = yaml.safe_load(out.read_text())
    assert doc["origin"] == [0.0, 0.0, 0.0]
    assert doc["overseec_local_origin"] == [UTM_ORIGIN[0], UTM_ORIGIN[1] - H * 0.5]


def test_nav2_scale_keeps_the_costs(scene: dict) -> None:
    out = scene["out"] / "scale.yaml"
    export_costmap(CostmapExportOptions(scene["costmap"], "nav2", out, nav2_mode="scale"))
    doc, cells = nav2_load(out)
    assert doc["mode"] == "scale" and doc["image"] == "scale.png"
    c = classes(scene)
    top_down = cells[::-1]
    expect = np.floor(np.nan_to_num(scene["cost"]) * 99 + 0.5)
    assert (top_down[c["passable"]] == expect[c["passable"]]).all()
    assert list(top_down[0, :5]) == [0, 25, 50, 74, 99]  # 0.5 neutral -> 50, 1.0 still passable
    assert (top_down[c["lethal"] | c["keep_out"]] == 100).all()
    assert (top_down[c["nodata"]] == -1).all()


def test_scale_pixels_invert_exactly_under_nav2_rules() -> None:
    v = np.arange(-1, 101, dtype=np.int16)
    grey, alpha = scale_pixels(v)
    back = np.rint((1.0 - grey / 255.0) * 100.0)
    assert (back[1:] == v[1:]).all() and alpha[0] == 0 and (alpha[1:] == 255).all()
    cost = np.array([0.0, 0.004, 0.5, 1.0, np.inf, np.nan], np.float32)
    assert scale_occupancy(cost).tolist() == [0, 0, 50, 99, 100, -1]


def test_nav2_refuses_geographic_and_non_square_grids() -> None:
    geo = Grid(CRS.from_epsg(4326), from_origin(15.0, 47.0, 1e-5, 1e-5), 10, 10)
    with pytest.raises(InputError, match="geographic.*gdalwarp -t_srs EPSG:32633"):
        nav2_geometry(geo, "c.tif")
    oblong = Grid(CRS.from_epsg(32633), Affine(0.5, 0, 5e5, 0, -0.25, 4e6), 10, 10)
    with pytest.raises(InputError, match="not square"):
        nav2_geometry(oblong, "c.tif")
    rotated = Grid(CRS.from_epsg(32633), Affine(0.5, 0.1, 5e5, 0.1, -0.5, 4e6), 10, 10)
    with pytest.raises(InputError, match="rotated"):
        nav2_geometry(rotated, "c.tif")


# ------------------------------------------------------------------------------------------------
# costmap_2d GeoTIFF and npy
# ------------------------------------------------------------------------------------------------


def test_costmap2d_geotiff_values_per_class(scene: dict) -> None:
    out = scene["out"] / "c2d.tif"
    export_costmap(CostmapExportOptions(scene["costmap"], "costmap2d", out))
    with rasterio.open(scene["costmap"]) as src, rasterio.open(out) as ds:
        assert ds.crs == src.crs and ds.transform == src.transform and ds.shape == src.shape
        assert ds.dtypes[0] == "uint8" and ds.nodata == 255
        values = ds.read(1)
    c = classes(scene)
    expect = np.floor(np.nan_to_num(scene["cost"]) * 252 + 0.5)
    assert (values[c["passable"]] == expect[c["passable"]]).all()
    assert list(values[0, :5]) == [0, 63, 126, 189, 252]
    assert (values[c["lethal"]] == 254).all() and (values[c["keep_out"]] == 254).all()
    assert (values[c["nodata"]] == 255).all()
    assert not np.isin(values, [253]).any()


def test_costmap2d_mapping_bounds() -> None:
    cost = np.array([0.0, 0.001, 0.999, 1.0, np.inf, np.nan], np.float32)
    assert costmap2d_values(cost).tolist() == [0, 0, 252, 252, 254, 255]


def test_npy_round_trip(scene: dict) -> None:
    out = scene["out"] / "cost.npy"
    export_costmap(CostmapExportOptions(scene["costmap"], "npy", out))
    arr = np.load(out, allow_pickle=False)
    flags = np.load(scene["out"] / "cost.flags.npy", allow_pickle=False)
    meta = json.loads((scene["out"] / "cost.json").read_text())
    c = classes(scene)
    assert arr.dtype == np.float32 and arr.shape == (H, W) == tuple(meta["shape"])
    assert (np.isnan(arr) == c["nodata"]).all()
    assert (np.isposinf(arr) == (c["lethal"] | c["keep_out"])).all()
    assert (arr[c["passable"]] == scene["cost"][c["passable"]]).all()
    assert (flags[c["passable"]] == 0).all() and (flags[c["lethal"]] == 1).all()
    assert (flags[c["keep_out"]] == 2).all() and (flags[c["nodata"]] == 255).all()
    with rasterio.open(scene["costmap"]) as ds:
        assert Affine.from_gdal(*meta["transform_gdal"]) == ds.transform
        assert Affine(*meta["transform_affine"]) == ds.transform
        assert CRS.from_wkt(meta["crs_wkt"]) == ds.crs and meta["crs_epsg"] == 32633
    assert meta["pixel_size_m"] == [0.5, 0.5]
    assert meta["cost_scale"]["0.5"].startswith("neutral")
    assert meta["counts"]["keep_out"] == int(c["keep_out"].sum())


@pytest.mark.parametrize(("to", "name"), [("nav2", "map.yaml"), ("costmap2d", "c2d.tif"), ("npy", "cost.npy")])
def test_every_export_says_keep_out_cells_are_lethal_and_what_they_are(scene: dict, to: str, name: str) -> None:
    """Buildings and water are keep-out by default (obstacles), so most maps have keep-out cells:
    each format says they are exported as lethal, what makes them, and that overseec's planner
    (unlike a robot's) enters them as a last resort; the export's notes say it with the count."""
    out = scene["out"] / name
    result = export_costmap(CostmapExportOptions(scene["costmap"], to, out))
    n = int(classes(scene)["keep_out"].sum())
    (note,) = [x for x in result.notes if "keep-out" in x]
    assert note.startswith(f"{n} keep-out cells") and "exported as lethal" in note
    for words in ("distance rules", "never-cross", "buildings and water", "last resort"):
        assert words in note
    if to == "nav2":
        comments = " ".join(line[1:].strip() for line in out.read_text().splitlines() if line.startswith("#"))
        assert KEEP_OUT_MEANING in comments
        assert "#   keep-out cells), 205 unknown" in out.read_text()  # the trinary encoding line
    elif to == "costmap2d":
        with rasterio.open(out) as ds:
            assert ds.tags()["OVERSEEC_KEEP_OUT"] == KEEP_OUT_MEANING
    else:
        meta = json.loads(out.with_suffix(".json").read_text())
        assert meta["keep_out"] == KEEP_OUT_MEANING
        assert "building or water" in meta["flags_encoding"]["2"]
    # a costmap without keep-out cells gets no such note
    flags = scene["lethal"].copy()
    flags[flags == 2] = 0
    write_lethal(scene["dir"] / "lethal.tif", flags, tags={"OVERSEEC_COSTMAP_FILE": "costmap.tif"})
    (scene["out"] / "again").mkdir()
    plain = export_costmap(CostmapExportOptions(scene["costmap"], to, scene["out"] / "again" / name))
    assert not [x for x in plain.notes if "keep-out" in x]


def test_no_sidecar_exports_with_a_note(tmp_path: Path) -> None:
    cost = smooth_costmap((20, 20), seed=1, lethal_fraction=0.0)
    costmap = write_costmap(tmp_path / "bare.tif", cost)
    result = export_costmap(CostmapExportOptions(costmap, "costmap2d", tmp_path / "c2d.tif"))
    assert any("no lethal sidecar" in n for n in result.notes)
    assert result.counts["lethal"] == 0


# ------------------------------------------------------------------------------------------------
# Paths: GPX, KML (read by OGR), CSV
# ------------------------------------------------------------------------------------------------


@pytest.fixture
def planned(scene: dict) -> dict:
    """A path planned on the scene's costmap by `overseec plan` (with its pixel CSV)."""
    with rasterio.open(scene["costmap"]) as ds:
        t = ds.transform
    start, goal = t * (1.5, 1.5), t * (W - 2.5, H - 2.5)
    path = scene["dir"] / "path.geojson"
    assert (
        main(
            [
                "--quiet",
                "plan",
                str(scene["costmap"]),
                "--start",
                *map(str, start),
                "--goal",
                *map(str, goal),
                "--out",
                str(path),
                "--pixels",
            ]
        )
        == 0
    )
    feature = json.loads(path.read_text())["features"][0]
    with open(scene["dir"] / "path.pixels.csv") as f:
        pixels = [(int(r["row"]), int(r["col"])) for r in csv.DictReader(f)]
    return {**scene, "path": path, "feature": feature, "pixels": pixels, "transform": t}


def _coords(feature: dict) -> np.ndarray:
    return np.array(feature["geometry"]["coordinates"], dtype=float)


def test_gpx_read_back_by_ogr(planned: dict) -> None:
    out = planned["out"] / "path.gpx"
    export_path(PathExportOptions(planned["path"], "gpx", out))
    with fiona.open(out, layer="track_points") as src:
        pts = np.array([f["geometry"]["coordinates"][:2] for f in src])
    assert np.abs(pts - _coords(planned["feature"])).max() < 1e-7
    with fiona.open(out, layer="tracks") as src:
        (trk,) = list(src)
        assert trk["properties"]["name"] == "prefer the road"
        assert "cost" in trk["properties"]["desc"]
    with fiona.open(out, layer="waypoints") as src:
        wps = {f["properties"]["name"]: f["geometry"]["coordinates"] for f in src}
    assert set(wps) == {"start", "goal"}
    assert np.allclose(wps["start"], _coords(planned["feature"])[0], atol=1e-7)


def test_kml_read_back_by_ogr(planned: dict) -> None:
    out = planned["out"] / "path.kml"
    export_path(PathExportOptions(planned["path"], "kml", out))
    fiona.supported_drivers.setdefault("KML", "r")
    with fiona.open(out, layer="path", driver="KML") as src:
        (line,) = list(src)
        assert line["properties"]["Name"] == "prefer the road"
        coords = np.array(line["geometry"]["coordinates"])[:, :2]
    assert np.abs(coords - _coords(planned["feature"])).max() < 1e-7
    with fiona.open(out, layer="waypoints", driver="KML") as src:
        names = [f["properties"]["Name"] for f in src]
        ends = np.array([f["geometry"]["coordinates"][:2] for f in src])
    assert names == ["start", "goal"]
    assert np.abs(ends - _coords(planned["feature"])[[0, -1]]).max() < 1e-7


def read_csv(path: Path) -> list[dict]:
    with open(path) as f:
        return list(csv.DictReader(f))


def test_csv_in_the_costmaps_crs(planned: dict) -> None:
    out = planned["out"] / "path.csv"
    export_path(PathExportOptions(planned["path"], "csv", out))
    rows = read_csv(out)
    t = planned["transform"]
    assert len(rows) == len(planned["pixels"])
    for rec, (r, c) in zip(rows, planned["pixels"]):
        x, y = t * (c + 0.5, r + 0.5)
        assert float(rec["x"]) == pytest.approx(x, abs=1e-6)
        assert float(rec["y"]) == pytest.approx(y, abs=1e-6)
        assert float(rec["cost"]) == pytest.approx(float(planned["cost"][r, c]), rel=1e-6)
    assert float(rows[0]["length_m"]) == 0.0
    assert float(rows[-1]["length_m"]) == pytest.approx(planned["feature"]["properties"]["length_m"], abs=1e-5)


def test_csv_in_the_nav2_frame_matches_the_map(planned: dict) -> None:
    origin = (UTM_ORIGIN[0] - 7.0, UTM_ORIGIN[1] - 33.0)
    nav2 = planned["out"] / "map.yaml"
    export_costmap(CostmapExportOptions(planned["costmap"], "nav2", nav2, local_origin=origin))
    out = planned["out"] / "path_nav2.csv"
    export_path(PathExportOptions(planned["path"], "csv", out, frame="nav2", nav2_yaml=nav2))
    doc, cells = nav2_load(nav2)
    res, (ox, oy) = doc["resolution"], doc["origin"][:2]
    for rec, (r, c) in zip(read_csv(out), planned["pixels"]):
        x, y = float(rec["x"]), float(rec["y"])
        # the cell of the Nav2 map this point falls in is the path's pixel, and it is free
        mx, my = int(math.floor((x - ox) / res)), int(math.floor((y - oy) / res))
        assert (mx, H - 1 - my) == (c, r)
        assert cells[my, mx] == 0
        assert x == pytest.approx(ox + (mx + 0.5) * res, abs=1e-6)
        assert y == pytest.approx(oy + (my + 0.5) * res, abs=1e-6)
    # the same origin rule without the YAML gives the same numbers
    again = planned["out"] / "again.csv"
    export_path(PathExportOptions(planned["path"], "csv", again, frame="nav2", local_origin=origin))
    assert again.read_text() == out.read_text()


def test_parse_paths_rejects_projected_coordinates() -> None:
    doc = {"type": "LineString", "coordinates": [[534010.0, 5212990.0], [534011.0, 5212991.0]]}
    with pytest.raises(InputError, match="WGS 84"):
        parse_paths(doc)


def test_gpx_escapes_prompt_text() -> None:
    (path,) = parse_paths(
        {
            "type": "Feature",
            "properties": {"prompt": "avoid <water> & \x01mud"},
            "geometry": {"type": "LineString", "coordinates": [[15, 47], [15.1, 47.1]]},
        }
    )
    text = gpx_text([path])
    assert "avoid &lt;water&gt; &amp; mud" in text


def test_loaded_grid_agrees_with_the_export_classes(scene: dict) -> None:
    """The exports classify cells as the planner does (guards the fixture's expectations)."""
    grid = load_costmap(scene["costmap"])
    c = classes(scene)
    assert (np.isposinf(grid.cost) == (c["lethal"] | c["keep_out"])).all()
    assert (grid.keep_out == c["keep_out"]).all()


def _as_plugin_table(planned: dict, gpkg: Path) -> list[tuple[float, float]]:
    """The planned route written as the plugin's map tool keeps it: a table of ``paths.gpkg``
    in the costmap's CRS (UTM, through the pixel centres), its start and goal as a WKT
    MULTIPOINT, beside another costmap's table; returns the route's vertices in that CRS."""
    with rasterio.open(planned["costmap"]) as ds:
        utm = ds.crs
    t = planned["transform"]
    xy = [t * (c + 0.5, r + 0.5) for r, c in planned["pixels"]]
    fields = {"total_cost": "float", "length_m": "float", "mode": "str", "vias": "int", "waypoints": "str"}
    schema = {"geometry": "LineString", "properties": fields}
    props = planned["feature"]["properties"]
    (x0, y0), (x1, y1) = xy[0], xy[-1]
    record = {
        "geometry": {"type": "LineString", "coordinates": xy},
        "properties": {
            "total_cost": props["total_cost"],
            "length_m": props["length_m"],
            "mode": "exact",
            "vias": 0,
            "waypoints": f"MultiPoint (({x0} {y0}),({x1} {y1}))",
        },
    }
    for table, records in (("paths_other", [record, record]), ("paths_costmap", [record])):
        with fiona.open(gpkg, "w", driver="GPKG", layer=table, schema=schema, crs_wkt=utm.to_wkt()) as dst:
            dst.writerecords(records)
    return xy


def test_a_route_table_of_the_plugins_paths_gpkg_exports_like_the_geojson(planned: dict) -> None:
    gpkg = planned["dir"] / "paths.gpkg"
    xy = _as_plugin_table(planned, gpkg)
    out = planned["out"] / "table.csv"
    export_path(PathExportOptions(gpkg, "csv", out, costmap=planned["costmap"], layer="paths_costmap"))
    reference = planned["out"] / "geojson.csv"
    export_path(PathExportOptions(planned["path"], "csv", reference))
    rows, ref = read_csv(out), read_csv(reference)
    assert [r["index"] for r in rows] == [r["index"] for r in ref]
    for a, b, (x, y) in zip(rows, ref, xy):
        for key in ("x", "y", "length_m", "cost"):
            assert float(a[key]) == pytest.approx(float(b[key]), abs=1e-6), key
        assert (float(a["x"]), float(a["y"])) == pytest.approx((x, y), abs=1e-6)
    gpx = planned["out"] / "table.gpx"
    export_path(PathExportOptions(gpkg, "gpx", gpx, layer="paths_costmap"))
    with fiona.open(gpx, layer="waypoints") as src:
        wps = {f["properties"]["name"]: f["geometry"]["coordinates"] for f in src}
    assert set(wps) == {"start", "goal"}  # from the table's waypoints, reprojected
    assert np.allclose(wps["goal"], _coords(planned["feature"])[-1], atol=1e-7)
    with fiona.open(gpx, layer="tracks") as src:
        (track,) = list(src)
    assert "mode exact" in track["properties"]["desc"]


def test_a_paths_gpkg_with_several_tables_needs_the_layer_named(planned: dict, capsys) -> None:
    gpkg = planned["dir"] / "paths.gpkg"
    _as_plugin_table(planned, gpkg)
    out = planned["out"] / "p.gpx"
    argv = ["export", "path", str(gpkg), "--to", "gpx", "--out", str(out)]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"overseec: error: path {gpkg}: 2 layers (paths_other, paths_costmap); name one with --layer"]
    assert main([*argv, "--layer", "paths_gone"]) == 2
    assert "no layer 'paths_gone' (it has: paths_other, paths_costmap)" in capsys.readouterr().err
    assert not out.exists()
    assert main([*argv, "--layer", "paths_other"]) == 0  # two routes: two tracks
    with fiona.open(out, layer="tracks") as src:
        assert len(list(src)) == 2
