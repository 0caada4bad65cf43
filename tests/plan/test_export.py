"""Path outputs: the prompt behind a costmap, GeoJSON for one-pixel paths, pixel CSV without a CRS."""

from __future__ import annotations

import json

import numpy as np
import pytest

from overseec_core.errors import OutputError
from overseec_core.plan import Planner, PlanningGrid, load_costmap
from overseec_core.plan.export import (find_prompt, path_geojson, path_properties, waypoint_records,
                                       write_geojson, write_pixels)

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
