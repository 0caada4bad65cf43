"""Path outputs: the prompt behind a costmap, GeoJSON for one-pixel paths, pixel CSV without a CRS,
and one clean error with nothing left behind when an output does not fit."""

from __future__ import annotations

import json
import os

import numpy as np
import pytest

from overseec_core.errors import OutputError
from overseec_core.plan import Planner, PlanningGrid, load_costmap
from overseec_core.plan.export import (
    find_prompt,
    path_geojson,
    path_properties,
    waypoint_records,
    write_cumulative,
    write_geojson,
    write_native_gpkg,
    write_pixels,
)

from ..io.test_full_disk import EFBIG_REASON, digest, fsize_limit
from .conftest import write_costmap


def test_prompt_from_tags_else_from_the_costmap_stage_manifest(tmp_path) -> None:
    cost = np.full((5, 5), 0.2, np.float32)
    tagged = load_costmap(write_costmap(tmp_path / "t.tif", cost, tags={"OVERSEEC_PROMPT": "stay on trails"}))
    assert find_prompt(tagged) == "stay on trails"
    plain = load_costmap(write_costmap(tmp_path / "costmap.tif", cost))
    assert find_prompt(plain) is None
    manifest = {"parameters": {"costmap": {"prompt": "avoid the field"}}, "costmap": {"file": "costmap.tif"}}
    (tmp_path / "manifest.json").write_text(json.dumps(manifest))
    assert find_prompt(plain) == "avoid the field"
    manifest["costmap"]["file"] = "other.tif"  # the manifest speaks of another costmap
    (tmp_path / "manifest.json").write_text(json.dumps(manifest))
    assert find_prompt(plain) is None


def test_one_pixel_path_is_a_valid_linestring(tmp_path) -> None:
    grid = load_costmap(write_costmap(tmp_path / "c.tif", np.full((4, 4), 0.3, np.float32)))
    res = Planner(grid).plan([(2, 2), (2, 2)])
    props = path_properties(res, grid, 0.01, waypoint_records(grid, res), None)
    doc = path_geojson(res, grid, props)
    coords = doc["features"][0]["geometry"]["coordinates"]
    assert len(coords) == 2 and coords[0] == coords[1]
    out = write_geojson(tmp_path / "one.geojson", doc, inputs=[tmp_path / "c.tif"])
    assert json.loads(out.read_text())["features"][0]["properties"]["total_cost"] == 0.0
    with pytest.raises(OutputError, match="is the input"):
        write_geojson(tmp_path / "c.tif", doc, inputs=[tmp_path / "c.tif"])


def test_pixels_csv_for_a_bare_array(tmp_path) -> None:
    grid = PlanningGrid.from_array(np.array([[0.0, 1.0, 0.0]]), pixel_size_m=(2.0, 2.0))
    res = Planner(grid, 0.5).plan([(0, 0), (0, 2)])
    text = write_pixels(tmp_path / "p.csv", res, grid, 0.5).read_text().splitlines()
    assert text[0] == "index,row,col,x,y,cum_cost"
    assert text[1:] == ["0,0,0,,,0", "1,0,1,,,2", "2,0,2,,,4"]  # (0.5 + 0.5) x 2 m per step


def test_pixels_of_a_broken_rule_route_count_the_zone_at_its_own_cost(tmp_path) -> None:
    """A route that must cross a keep-out wall (own cost 0.2 under it, not the top of the scale):
    cum_cost stays finite through the zone, climbs at the zone cells' own costs and ends at the
    route's reported cost, in the CSV and in the JSON (which cannot hold an infinity)."""
    from overseec_core.plan.stage import plan_keeping_rules

    from .test_keep_out import write_lethal

    cost = np.full((12, 12), 0.5, np.float32)
    cost[:, 6] = 0.2
    flags = np.zeros(cost.shape, np.uint8)
    flags[:, 6] = 2  # the wall cuts the map: no route keeps the rule
    costmap = write_costmap(tmp_path / "c.tif", cost)
    write_lethal(tmp_path / "lethal.tif", flags, costmap)
    grid = load_costmap(costmap)
    res, _ = plan_keeping_rules(grid, [(5, 1), (5, 10)], base_cost_per_m=0.01)
    assert "cannot be met" in res.notes[0] and res.pixels.tolist() == [[5, c] for c in range(1, 11)]
    # 0.5 m steps along row 5: (mean of the two cells + 0.01) x 0.5, the wall at 0.2
    row = cost[5].astype(np.float64)
    expected = np.concatenate([[0.0], np.cumsum((0.5 * (row[1:10] + row[2:11]) + 0.01) * 0.5)])
    lines = write_pixels(tmp_path / "p.csv", res, grid, 0.01).read_text().splitlines()
    cum = np.array([float(line.split(",")[-1]) for line in lines[1:]])
    assert np.allclose(cum, expected, rtol=1e-8, atol=0) and cum[-1] == pytest.approx(res.cost, rel=1e-8)
    doc = json.loads(write_pixels(tmp_path / "p.json", res, grid, 0.01).read_text())
    assert doc["cum_cost"] == pytest.approx(expected.tolist(), rel=1e-12)
    assert doc["cum_cost"][-1] == pytest.approx(res.cost, rel=1e-12) == doc["total_cost"]


# --------------------------------------------------------------------------------------------
# A full disk (a file size limit here; tests/io/test_full_disk.py has the real tmpfs)
# --------------------------------------------------------------------------------------------


def _planned(tmp_path):
    """A 300 x 300 costmap, its planner and a corner-to-corner path."""
    from .conftest import smooth_costmap

    cost = smooth_costmap((300, 300), seed=7, lethal_fraction=0.0)
    grid = load_costmap(write_costmap(tmp_path / "c.tif", cost))
    planner = Planner(grid)
    res = planner.plan([(5, 5), (290, 290)])
    props = path_properties(res, grid, 0.01, waypoint_records(grid, res), None)
    return grid, planner, res, props


def _writers(grid, planner, res, props):
    return {
        "path.geojson": lambda p: write_geojson(p, path_geojson(res, grid, props)),
        "path.native.gpkg": lambda p: write_native_gpkg(p, res, grid, props),
        "path.pixels.csv": lambda p: write_pixels(p, res, grid, 0.01),
        "path.pixels.json": lambda p: write_pixels(p, res, grid, 0.01),
        "cum.tif": lambda p: write_cumulative(p, planner, (5, 5)),
    }


@pytest.mark.parametrize("name", ["path.geojson", "path.native.gpkg", "path.pixels.csv", "path.pixels.json", "cum.tif"])
def test_every_path_output_past_the_size_limit_is_one_error(tmp_path, capfd, name) -> None:
    """Each writer fails with one OutputError naming its file, prints nothing, keeps the old
    file byte-for-byte and leaves no temporary file or sidecar."""
    grid, planner, res, props = _planned(tmp_path)
    write = _writers(grid, planner, res, props)[name]
    out = tmp_path / "out"
    out.mkdir()
    probe = write(out / f"probe{os.path.splitext(name)[1]}")  # same kind, to learn its size
    size = probe.stat().st_size
    probe.unlink()
    target = out / name
    target.write_bytes(b"previous result")
    before = digest(target)
    capfd.readouterr()
    with fsize_limit(size // 2):
        with pytest.raises(OutputError) as err:
            write(target)
    assert str(err.value) == f"cannot write {target}: {EFBIG_REASON}"
    assert digest(target) == before
    assert [p.name for p in out.iterdir()] == [name]
    assert capfd.readouterr().err == ""


def test_geojson_positions_are_lon_lat_and_the_bbox_is_west_south_east_north(tmp_path) -> None:
    """RFC 7946: each position is [longitude, latitude]; bbox is [west, south, east, north]. A path
    from the north-west corner to the south-east one, on a UTM grid, checked against pyproj."""
    from pyproj import Transformer
    from rasterio.transform import from_origin

    from .conftest import UTM_ORIGIN

    cost = np.full((20, 20), 0.3, np.float32)
    grid = load_costmap(write_costmap(tmp_path / "c.tif", cost, transform=from_origin(*UTM_ORIGIN, 100.0, 100.0)))
    res = Planner(grid).plan([(0, 0), (19, 19)])
    doc = path_geojson(res, grid, {})
    to_wgs84 = Transformer.from_crs("EPSG:32633", "EPSG:4326", always_xy=True)
    west, north = to_wgs84.transform(UTM_ORIGIN[0] + 50.0, UTM_ORIGIN[1] - 50.0)
    east, south = to_wgs84.transform(UTM_ORIGIN[0] + 1950.0, UTM_ORIGIN[1] - 1950.0)
    coords = doc["features"][0]["geometry"]["coordinates"]
    np.testing.assert_allclose(coords[0], [west, north], atol=1e-8)
    np.testing.assert_allclose(coords[-1], [east, south], atol=1e-8)
    assert 14.9 < west < 15.1 and 36.0 < north < 36.2  # longitude first, about 15 E 36.1 N
    np.testing.assert_allclose(doc["bbox"], [west, south, east, north], atol=1e-8)
    assert doc["features"][0]["bbox"] == doc["bbox"]
