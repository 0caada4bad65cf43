"""Keep-out zones (distance rules): avoided where possible, entered and reported otherwise."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import rasterio

from overseec_core.cli import main
from overseec_core.plan import load_costmap
from overseec_core.plan.stage import plan_keeping_rules

from .conftest import UTM_ORIGIN, write_costmap


def write_lethal(path: Path, flags: np.ndarray, like: Path, tagged: bool = True) -> Path:
    with rasterio.open(like) as ds:
        profile = dict(
            driver="GTiff", width=ds.width, height=ds.height, count=1, dtype="uint8", crs=ds.crs, transform=ds.transform
        )
    with rasterio.open(path, "w", **profile) as ds:
        ds.write(flags.astype(np.uint8), 1)
        if tagged:  # overseec's own sidecar (compose tags it); only there is 2 a keep-out flag
            ds.update_tags(OVERSEEC_COSTMAP_FILE=like.name)
    return path


@pytest.fixture()
def wall(tmp_path: Path) -> tuple[Path, np.ndarray]:
    """20 x 20 neutral costmap; a keep-out wall across column 10 with a gap at rows 0-2."""
    cost = np.full((20, 20), 0.5, np.float32)
    costmap = write_costmap(tmp_path / "costmap.tif", cost)
    flags = np.zeros((20, 20), np.uint8)
    flags[3:, 10] = 2
    flags[15, 2] = 1  # one lethal cell, never entered
    write_lethal(tmp_path / "lethal.tif", flags, costmap)
    return costmap, flags


def test_keep_out_cells_are_remembered_and_impassable(wall) -> None:
    costmap, flags = wall
    grid = load_costmap(costmap)
    assert grid.keep_out is not None and np.array_equal(grid.keep_out, flags == 2)
    assert np.isposinf(grid.cost[flags > 0]).all()
    result, _ = plan_keeping_rules(grid, [(10, 2), (10, 18)])
    assert not grid.keep_out[result.pixels[:, 0], result.pixels[:, 1]].any()
    assert result.pixels[:, 0].min() <= 2  # around through the gap
    assert result.notes == ()


def test_a_rule_that_cannot_be_met_is_entered_as_little_as_possible_and_reported(wall, tmp_path) -> None:
    costmap, flags = wall
    flags = flags.copy()
    flags[:3, 10] = 2  # close the gap: no route keeps the rule
    write_lethal(tmp_path / "lethal.tif", flags, costmap)
    grid = load_costmap(costmap)
    result, _ = plan_keeping_rules(grid, [(10, 2), (10, 18)])
    inside = flags[result.pixels[:, 0], result.pixels[:, 1]]
    assert (inside == 2).sum() == 1 and not (inside == 1).any()  # crosses the wall once
    assert len(result.notes) == 1 and "cannot be met" in result.notes[0]
    assert "1.0 m inside it" in result.notes[0]  # 0.5 m pixels: two half steps


def test_a_point_inside_a_keep_out_zone_is_reported_not_refused(wall) -> None:
    grid = load_costmap(wall[0])
    result, _ = plan_keeping_rules(grid, [(10, 10), (10, 18)])
    assert "cannot be met" in result.notes[0]


def test_lethal_cells_stay_impassable_even_then(wall, tmp_path) -> None:
    costmap, flags = wall
    flags = flags.copy()
    flags[:, 12] = 1
    write_lethal(tmp_path / "lethal.tif", flags, costmap)
    with pytest.raises(Exception, match="no path"):
        plan_keeping_rules(load_costmap(costmap), [(10, 2), (10, 18)])


def test_plan_cli_reports_the_broken_rule(wall, tmp_path, capsys) -> None:
    costmap, flags = wall
    flags = flags.copy()
    flags[:3, 10] = 2
    write_lethal(tmp_path / "lethal.tif", flags, costmap)
    x0, y0 = UTM_ORIGIN
    out = tmp_path / "path.geojson"
    assert (
        main(
            [
                "plan",
                str(costmap),
                "--start",
                str(x0 + 1.25),
                str(y0 - 5.25),
                "--goal",
                str(x0 + 9.25),
                str(y0 - 5.25),
                "--out",
                str(out),
            ]
        )
        == 0
    )
    assert "cannot be met" in capsys.readouterr().out
    props = json.loads(out.read_text())["features"][0]["properties"]
    assert any("cannot be met" in n for n in props["notes"])


def test_eval_counts_the_pairs_that_cannot_keep_a_rule(wall, tmp_path) -> None:
    from overseec_core.evaluate import EvaluateOptions, evaluate_paths

    costmap, flags = wall
    flags = flags.copy()
    flags[:3, 10] = 2  # the wall now cuts the map: pairs across it break the rule
    write_lethal(tmp_path / "lethal.tif", flags, costmap)
    evaluate_paths(EvaluateOptions(out_dir=tmp_path / "eval", costmap=costmap, pairs=12, seed=1, plots=False))
    metrics = json.loads((tmp_path / "eval" / "metrics.json").read_text())
    sampling = metrics["sampling"]
    assert sampling["unreachable"] == [] and sampling["planned"] == 12
    assert 0 < sampling["rules_not_met"] < 12
    assert "could not keep a distance rule" in (tmp_path / "eval" / "report.md").read_text()


def test_a_users_own_lethal_mask_is_impassable_wherever_nonzero(wall, tmp_path) -> None:
    costmap, flags = wall
    flags = flags.copy()
    flags[:3, 10] = 2
    mask = write_lethal(tmp_path / "mine.tif", flags, costmap, tagged=False)
    grid = load_costmap(costmap, lethal_path=mask)
    assert grid.keep_out is None and np.isposinf(grid.cost[flags == 2]).all()
    with pytest.raises(Exception, match="no path"):
        plan_keeping_rules(grid, [(10, 2), (10, 18)])


def test_only_the_leg_that_cannot_keep_the_rule_enters_and_its_cost_counts_the_zone_at_one(wall, tmp_path) -> None:
    from overseec_core.plan.planner import cumulative_path_cost

    costmap, flags = wall
    flags = flags.copy()
    flags[:3, 10] = 2
    write_lethal(tmp_path / "lethal.tif", flags, costmap)
    grid = load_costmap(costmap)
    result, _ = plan_keeping_rules(grid, [(17, 2), (2, 3), (10, 18)])
    first_leg = result.pixels[: int(np.flatnonzero((result.pixels == (2, 3)).all(axis=1))[0]) + 1]
    assert not grid.keep_out[first_leg[:, 0], first_leg[:, 1]].any()  # leg 1 keeps the rule
    assert (flags[result.pixels[:, 0], result.pixels[:, 1]] == 2).sum() == 1
    assert len(result.notes) == 1 and "between via point 1 and goal" in result.notes[0]
    shown = grid.cost.copy()
    shown[grid.keep_out] = 1.0  # what the costmap shows there
    from overseec_core.plan import PlanningGrid

    assert result.cost == pytest.approx(
        float(cumulative_path_cost(PlanningGrid.from_array(shown, pixel_size_m=grid.pixel_size_m), result.pixels)[-1])
    )
