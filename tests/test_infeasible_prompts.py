"""Broken rules from mission prompts, end to end on the real scenes (issue 20).

``tests/plan/test_infeasible_scenes.py`` checks the planner on hand-written programs; here the
rules come from the words a user types, through the offline interpreter (with its priors: the
buildings themselves are obstacles) and the costmap stage, so the whole path is what users get:

- "keep at least 20 m away from the buildings" on both New Brunswick clips and a Kampala window;
- "do not cross the railway, and never enter the water" on the second clip, where the railway
  separates the points (the water is lethal there, so the railway is the only way across).

Each route must spend within 5 % (plus one pixel diagonal) of the least possible metres in the
keep-out zones, and of that the least on buildings (or the railway), against the same independent
scikit-image references; the note must say by how much the rule is broken.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import rasterio

from overseec_core.errors import PlanError
from overseec_core.pipeline import run_costmap
from overseec_core.plan import Planner, load_costmap
from overseec_core.plan.stage import RulePlanner
from overseec_core.synthesize.options import CostmapOptions

from .plan.test_infeasible_scenes import KAMPALA, KAMPALA_WINDOW, NB, Scene, _crop, broken_pairs, check_route

pytestmark = pytest.mark.scenes

KEEP_20M = "Keep at least 20 m away from the buildings."
NO_CROSSING = "Do not cross the railway, and never enter the water."


def _prompt_scene(tmp: Path, labels: Path, classes: Path, prompt: str, entity_id: int) -> Scene:
    if not (labels.exists() and classes.exists()):
        pytest.skip(f"scene not found at {labels.parent}")
    out = tmp / "costmap.tif"
    result = run_costmap(CostmapOptions(out=out, labels=labels, classes=classes, prompt=prompt))
    assert "keep_out" in result.program
    with rasterio.open(labels) as ds:
        entity = ds.read(1) == entity_id
    grid = load_costmap(out)
    assert grid.keep_out is not None
    return Scene(grid, out, entity)


@pytest.mark.parametrize("name", ["nb1", "nb2", "kampala"])
def test_keep_twenty_metres_from_buildings_bends_as_little_as_possible(tmp_path, name: str) -> None:
    if name == "kampala":
        labels = _crop(KAMPALA / "gt_buildings.tif", tmp_path / "labels.tif", KAMPALA_WINDOW)
        scene = _prompt_scene(tmp_path, labels, KAMPALA / "classes.json", KEEP_20M, 1)
    else:
        labels = NB / ("gt_1of2.tif" if name == "nb1" else "gt_2of2.tif")
        scene = _prompt_scene(tmp_path, labels, NB / "classes.json", KEEP_20M, 1)
    rules = RulePlanner(Planner(scene.grid))
    rows = [check_route(scene, a, b, rules) for a, b in broken_pairs(scene, 4, seed=2)]
    assert all(r["entity_m"] <= r["careless_entity_m"] + 1e-9 for r in rows), rows
    print(f"\nINFEASIBLE {name}: " + "; ".join(f"{r['zone_m']:.1f}/{r['entity_m']:.1f} m" for r in rows))


def test_do_not_cross_the_railway_crosses_it_once_at_the_least_width(tmp_path) -> None:
    scene = _prompt_scene(tmp_path, NB / "gt_2of2.tif", NB / "classes.json", NO_CROSSING, 5)
    zone = scene.grid.keep_out
    assert zone is not None
    rules = RulePlanner(Planner(scene.grid))
    for a, b in (((200, 150), (420, 150)), ((150, 20), (420, 300))):
        with pytest.raises(PlanError):
            Planner(scene.grid).plan([a, b])  # the railway separates them
        figures = check_route(scene, a, b, rules)
        result, _ = rules.plan([a, b])
        on_rail = scene.entity[result.pixels[:, 0], result.pixels[:, 1]].astype(np.int8)
        assert np.count_nonzero(np.diff(on_rail) == 1) == 1  # onto the railway once
        assert figures["entity_m"] <= figures["zone_m"] + 1e-9
