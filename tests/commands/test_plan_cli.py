"""`overseec plan` end to end: projected and geographic costmaps, points in another CRS, the
GeoJSON / GeoPackage / pixel / cost-distance outputs, and one-line errors."""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
from pathlib import Path

import fiona
import numpy as np
import pytest
import rasterio
from pyproj import Geod, Transformer
from rasterio.transform import from_origin

from overseec_core.cli import main
from overseec_core.plan import Planner, load_costmap
from tests.plan.conftest import UTM_ORIGIN, smooth_costmap, write_costmap, write_lethal

REPO = Path(__file__).resolve().parents[2]
TO_LONLAT = Transformer.from_crs("EPSG:32633", "EPSG:4326", always_xy=True)


def utm_point(row: float, col: float) -> tuple[float, float]:
    """Map coordinates (UTM 33N) inside pixel (row, col) of the 0.5 m test grid."""
    return UTM_ORIGIN[0] + (col + 0.3) * 0.5, UTM_ORIGIN[1] - (row + 0.6) * 0.5


@pytest.fixture
def scene(tmp_path: Path) -> dict:
    """A 60 x 80 UTM costmap with a lethal sidecar (compose naming) and a prompt tag."""
    cost = smooth_costmap((60, 80), seed=3, lethal_fraction=0.0)
    lethal = np.zeros(cost.shape, np.uint8)
    lethal[20:40, 30:33] = 1
    cost[0:3, 0:3] = cost[-3:, -3:] = 0.5
    costmap = write_costmap(
        tmp_path / "costmap.tif",
        cost,
        tags={"OVERSEEC_LETHAL_FILE": "lethal.tif", "OVERSEEC_PROMPT": "prefer the road"},
    )
    write_lethal(tmp_path / "lethal.tif", lethal, tags={"OVERSEEC_COSTMAP_FILE": "costmap.tif"})
    return {"costmap": costmap, "cost": cost, "lethal": lethal, "dir": tmp_path}


def run_cli(*argv: str) -> int:
    return main(["--quiet", "plan", *argv])


def read_geojson(path: Path) -> dict:
    doc = json.loads(path.read_text())
    assert doc["type"] == "FeatureCollection" and "crs" not in doc  # RFC 7946: WGS 84 only
    (feature,) = doc["features"]
    assert feature["geometry"]["type"] == "LineString"
    return feature


def test_projected_costmap_end_to_end(scene: dict, tmp_path: Path) -> None:
    start, goal = utm_point(1, 1), utm_point(57, 76)
    out = tmp_path / "out" / "route.geojson"
    out.parent.mkdir()
    rc = run_cli(
        str(scene["costmap"]),
        "--start",
        *map(str, start),
        "--goal",
        *map(str, goal),
        "--out",
        str(out),
        "--native-crs",
        "--pixels",
        "--cumulative",
        str(tmp_path / "out" / "cum.tif"),
    )
    assert rc == 0
    feature = read_geojson(out)
    props, coords = feature["properties"], np.array(feature["geometry"]["coordinates"])
    # same answer as the library on the same costmap
    planner = Planner(load_costmap(scene["costmap"]), 0.01)
    ref = planner.plan([(1, 1), (57, 76)])
    assert props["total_cost"] == pytest.approx(ref.cost, rel=1e-12)
    assert props["length_m"] == pytest.approx(ref.length_m)
    assert props["mode"] == "exact" and props["optimal"] and props["bound"] == pytest.approx(ref.cost)
    assert props["prompt"] == "prefer the road"
    assert props["lethal_mask"].endswith("lethal.tif")
    assert len(coords) == len(ref.pixels)
    # lon/lat order, and the ends are the requested points (within one pixel)
    assert (14.9 < coords[:, 0]).all() and (coords[:, 0] < 15.1).all() and (36.0 < coords[:, 1]).all()
    geod = Geod(ellps="WGS84")
    for got, want in ((coords[0], start), (coords[-1], goal)):
        lon, lat = TO_LONLAT.transform(*want)
        assert geod.inv(got[0], got[1], lon, lat)[2] < 0.5
    assert [w["name"] for w in props["waypoints"]] == ["start", "goal"]
    assert props["waypoints"][0]["requested"] == pytest.approx(list(start))
    # the path never touches a lethal cell of the sidecar
    assert not scene["lethal"][ref.pixels[:, 0], ref.pixels[:, 1]].any()

    gpkg = tmp_path / "out" / "route.native.gpkg"
    assert set(fiona.listlayers(gpkg)) == {"path", "waypoints"}
    with fiona.open(gpkg, layer="path") as src:
        assert src.crs_wkt and rasterio.crs.CRS.from_wkt(src.crs_wkt).to_epsg() == 32633
        line = next(iter(src))
        first = line["geometry"]["coordinates"][0]
        assert first == pytest.approx((UTM_ORIGIN[0] + 0.75, UTM_ORIGIN[1] - 0.75))
        assert line["properties"]["total_cost"] == pytest.approx(ref.cost)
    with fiona.open(gpkg, layer="waypoints") as src:
        assert [f["properties"]["name"] for f in src] == ["start", "goal"]

    with open(tmp_path / "out" / "route.pixels.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert [[int(r["row"]), int(r["col"])] for r in rows] == ref.pixels.tolist()
    assert float(rows[-1]["cum_cost"]) == pytest.approx(ref.cost, rel=1e-8)

    with rasterio.open(tmp_path / "out" / "cum.tif") as ds:
        cum = ds.read(1)
        assert ds.dtypes[0] == "float32" and ds.crs.to_epsg() == 32633
    assert cum[1, 1] == 0.0 and cum[57, 76] == pytest.approx(ref.cost, rel=1e-6)
    assert np.isnan(cum[scene["lethal"] == 1]).all()
    manifest = json.loads((tmp_path / "out" / "manifest.json").read_text())
    assert manifest["plan"]["cost"] == pytest.approx(ref.cost) and manifest["plan"]["mode"] == "exact"
    assert manifest["inputs"]["plan_costmap_costmap.tif"]["sha256"]
    assert manifest["parameters"]["plan"]["base_cost_per_m"] == 0.01
    assert not list((tmp_path / "out").glob(".*partial*"))


def test_points_in_wgs84_on_a_projected_costmap_and_via_points(scene: dict, tmp_path: Path) -> None:
    pts = [TO_LONLAT.transform(*utm_point(r, c)) for r, c in ((1, 1), (50, 10), (57, 76))]
    out = tmp_path / "p.geojson"
    rc = run_cli(
        str(scene["costmap"]),
        "--crs",
        "EPSG:4326",
        "--start",
        *map(str, pts[0]),
        "--via",
        *map(str, pts[1]),
        "--goal",
        *map(str, pts[2]),
        "--out",
        str(out),
        "--mode",
        "fast",
        "--pixels-out",
        str(tmp_path / "p.json"),
    )
    assert rc == 0
    props = read_geojson(out)["properties"]
    assert [(w["row"], w["col"]) for w in props["waypoints"]] == [(1, 1), (50, 10), (57, 76)]
    assert props["requested_mode"] == "fast" and props["mode"] in ("fast", "exact")
    exact = Planner(load_costmap(scene["costmap"])).plan([(1, 1), (50, 10), (57, 76)])
    assert exact.cost * (1 - 1e-12) <= props["total_cost"] and props["bound"] <= exact.cost * (1 + 1e-12)
    doc = json.loads((tmp_path / "p.json").read_text())
    assert [doc["rows"][0], doc["cols"][0]] == [1, 1] and doc["crs"] == "EPSG:32633"
    assert len(doc["x"]) == len(doc["rows"]) == props["n_pixels"]


def test_geographic_costmap(tmp_path: Path) -> None:
    cost = smooth_costmap((50, 40), seed=8, lethal_fraction=0.05)
    cost[:2, :2] = cost[-2:, -2:] = 0.4
    step = 2.7e-6 * 10  # about 2.4 m east-west, 3.0 m north-south at 36 N
    costmap = write_costmap(tmp_path / "geo.tif", cost, crs="EPSG:4326", transform=from_origin(15.0, 36.1, step, step))
    start = (15.0 + 0.5 * step, 36.1 - 0.5 * step)
    goal = (15.0 + 39.5 * step, 36.1 - 49.5 * step)
    out = tmp_path / "geo.geojson"
    assert run_cli(str(costmap), "--start", *map(str, start), "--goal", *map(str, goal), "--out", str(out)) == 0
    feature = read_geojson(out)
    coords = np.array(feature["geometry"]["coordinates"])
    assert coords[0] == pytest.approx(start, abs=1e-9) and coords[-1] == pytest.approx(goal, abs=1e-9)
    grid = load_costmap(costmap)
    dx, dy = grid.pixel_size_m
    assert dx == pytest.approx(2.43, abs=0.05) and dy == pytest.approx(3.0, abs=0.05)  # not square
    ref = Planner(grid).plan([(0, 0), (49, 39)])
    assert feature["properties"]["total_cost"] == pytest.approx(ref.cost, rel=1e-12)
    assert feature["properties"]["length_m"] == pytest.approx(ref.length_m)
    assert ref.length_m > 49 * dy  # metres, not degrees


@pytest.mark.parametrize(
    "args, message",
    [
        (["--start", "499990", "3999990"], r"^overseec: error: start \(499990, 3999990\) is outside the costmap"),
        (["--start", *map(str, utm_point(30, 31))], r"^overseec: error: start \(.*\) is on a lethal cell"),
        (["--crs", "EPSG:99999"], r"^overseec: error: not a CRS"),
        (["--lethal-threshold", "0"], r"^overseec: error: start .* is on a lethal cell"),
    ],
)
def test_one_line_errors(scene: dict, tmp_path: Path, capsys, args: list[str], message: str) -> None:
    base = {"--start": list(map(str, utm_point(1, 1))), "--goal": list(map(str, utm_point(57, 76)))}
    argv = [str(scene["costmap"]), "--out", str(tmp_path / "e.geojson")]
    for key, value in base.items():
        if key not in args:
            argv += [key, *value]
    capsys.readouterr()
    assert run_cli(*argv, *args) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and __import__("re").search(message, err), err
    assert not (tmp_path / "e.geojson").exists()


def test_unreachable_goal_and_overwriting_the_costmap_are_refused(scene: dict, tmp_path: Path, capsys) -> None:
    cost = np.full((20, 20), 0.3, np.float32)
    cost[:, 10] = np.inf
    walled = write_costmap(tmp_path / "walled.tif", cost)
    rc = run_cli(
        str(walled),
        "--start",
        *map(str, utm_point(5, 2)),
        "--goal",
        *map(str, utm_point(5, 15)),
        "--out",
        str(tmp_path / "w.geojson"),
    )
    assert rc == 2 and "no path from start" in capsys.readouterr().err
    rc = run_cli(
        str(walled), "--start", *map(str, utm_point(5, 2)), "--goal", *map(str, utm_point(5, 5)), "--out", str(walled)
    )
    assert rc == 2 and "is the input" in capsys.readouterr().err


def test_subprocess_cli_json(scene: dict, tmp_path: Path) -> None:
    out = tmp_path / "s.geojson"
    exe = Path(sys.executable).parent / "overseec"
    cmd = [
        str(exe) if exe.exists() else sys.executable,
        *([] if exe.exists() else ["-m", "overseec_core.cli"]),
        "--quiet",
        "plan",
        str(scene["costmap"]),
        "--start",
        *map(str, utm_point(1, 1)),
        "--goal",
        *map(str, utm_point(57, 76)),
        "--out",
        str(out),
        "--json",
        "--mode",
        "fast",
    ]
    done = subprocess.run(cmd, capture_output=True, text=True, cwd=REPO, timeout=300)
    assert done.returncode == 0, done.stderr
    result = json.loads(done.stdout)
    assert result["outputs"]["geojson"] == str(out) and math.isfinite(result["total_cost"])
    assert result["requested_mode"] == "fast" and result["bound"] <= result["total_cost"]
    assert read_geojson(out)["properties"]["total_cost"] == pytest.approx(result["total_cost"])


def test_lon_lat_without_crs_gets_a_hint(scene: dict, tmp_path: Path, capsys) -> None:
    """Degrees given as metres land next to the CRS's origin: say so, and what to add."""
    lon, lat = TO_LONLAT.transform(*utm_point(1, 1))
    goal = TO_LONLAT.transform(*utm_point(57, 76))
    argv = [str(scene["costmap"]), "--start", str(lon), str(lat), "--goal", *map(str, goal)]
    assert run_cli(*argv, "--out", str(tmp_path / "p.geojson")) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "is outside the costmap costmap.tif" in err
    assert err.rstrip().endswith("; these look like longitude/latitude; add --crs EPSG:4326"), err
    # the hint is the fix: the same numbers with --crs EPSG:4326 plan
    assert run_cli(*argv, "--crs", "EPSG:4326", "--out", str(tmp_path / "p.geojson")) == 0
    # numbers that are no degrees, or a CRS given: no hint
    far = [str(scene["costmap"]), "--start", "499990", "3999990", "--goal", *map(str, utm_point(57, 76))]
    assert run_cli(*far, "--out", str(tmp_path / "q.geojson")) == 2
    assert "look like" not in capsys.readouterr().err
    assert run_cli(*argv[:2], "10", "10", *argv[4:], "--crs", "EPSG:4326", "--out", str(tmp_path / "q.geojson")) == 2
    assert "look like" not in capsys.readouterr().err


def test_smoothed_json_uses_the_files_names_and_figures(scene: dict, tmp_path: Path, capsys) -> None:
    """`plan --smooth --json` reports the route the file holds, under the file's keys: total_cost,
    length_m, n_vertices, leg_costs of the smoothed line; the grid route under grid_route."""
    out = tmp_path / "s" / "route.geojson"
    argv = [str(scene["costmap"]), "--start", *map(str, utm_point(1, 1)), "--goal", *map(str, utm_point(57, 76))]
    capsys.readouterr()
    assert main(["--quiet", "plan", *argv, "--out", str(out), "--smooth", "--native-crs", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    props = read_geojson(out)["properties"]
    assert props["route"] == doc["route"] == "smoothed"
    for key in ("total_cost", "length_m", "n_vertices", "leg_costs", "grid_route", "smoothing", "n_pixels", "prompt"):
        assert doc[key] == props[key], key
    assert "cost" not in doc  # one name per figure: the file's
    assert doc["total_cost"] != doc["grid_route"]["cost"] and doc["length_m"] < doc["grid_route"]["length_m"]
    with fiona.open(out.with_name("route.native.gpkg"), layer="path") as layer:
        (rec,) = list(layer)
    assert rec["properties"]["total_cost"] == pytest.approx(doc["total_cost"])
    assert doc["outputs"]["geojson"] == str(out) and set(doc["timings"]) >= {"total_s", "smooth_s"}
    # without --smooth the same names describe the grid route, which the file then holds
    assert main(["--quiet", "plan", *argv, "--out", str(tmp_path / "g.geojson"), "--json"]) == 0
    plain = json.loads(capsys.readouterr().out)
    grid_props = read_geojson(tmp_path / "g.geojson")["properties"]
    assert plain["total_cost"] == grid_props["total_cost"] == pytest.approx(doc["grid_route"]["cost"])
    assert plain["length_m"] == grid_props["length_m"] and "grid_route" not in plain
