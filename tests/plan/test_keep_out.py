"""Keep-out zones (distance rules): avoided where possible, entered and reported otherwise."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import rasterio

from overseec_core.cli import main
from overseec_core.plan import load_costmap
from overseec_core.plan.grid import KEEP_OUT_ENTRY_COST
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
    # the wall is one 0.5 m pixel thick: the steps in and out are each half inside it. One
    # sentence, true whatever made the zone (the sidecar's flag 2 does not say which rule did)
    assert result.notes[0] == (
        "a keep-out rule cannot be met between start and goal (a distance rule, a never-cross rule "
        "or an obstacle such as a building or water): no route avoids it, so this one runs 0.5 m "
        "inside (0.0 m of that on avoided ground)"
    )


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
    assert "could not keep a keep-out rule" in (tmp_path / "eval" / "report.md").read_text()


def test_a_users_own_lethal_mask_is_impassable_wherever_nonzero(wall, tmp_path) -> None:
    costmap, flags = wall
    flags = flags.copy()
    flags[:3, 10] = 2
    mask = write_lethal(tmp_path / "mine.tif", flags, costmap, tagged=False)
    grid = load_costmap(costmap, lethal_path=mask)
    assert grid.keep_out is None and np.isposinf(grid.cost[flags == 2]).all()
    with pytest.raises(Exception, match="no path"):
        plan_keeping_rules(grid, [(10, 2), (10, 18)])


def test_only_the_leg_that_cannot_keep_the_rule_enters_and_its_cost_counts_the_zone_at_its_own_cost(
    wall, tmp_path
) -> None:
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
    assert result.cost == pytest.approx(own_cost_of(costmap, result.pixels), rel=1e-12)


def own_cost_of(costmap: Path, pixels: np.ndarray) -> float:
    """A route's cost under the planner's step rule with the costmap file's own values (the
    sidecar ignored): what a broken rule's route reports."""
    from overseec_core.plan import PlanningGrid
    from overseec_core.plan.paths import cumulative_path_cost

    with rasterio.open(costmap) as ds:
        own = PlanningGrid.from_array(ds.read(1), pixel_size_m=ds.res)
    return float(cumulative_path_cost(own, pixels)[-1])


def test_the_grid_keeps_the_costmaps_own_values_under_keep_out_cells(tmp_path, monkeypatch) -> None:
    from overseec_core.plan import grid as grid_module

    # small strips and lookup chunks, and a width that is no multiple of 8, so every seam is met
    monkeypatch.setattr(grid_module, "STRIP_ROWS", 5)
    monkeypatch.setattr(grid_module, "ZONE_ROWS", 3)
    rng = np.random.default_rng(7)
    cost = rng.uniform(0.0, 1.0, (23, 13)).astype(np.float32)
    costmap = write_costmap(tmp_path / "costmap.tif", cost)
    flags = (rng.random(cost.shape) < 0.4).astype(np.uint8) * 2
    flags[0, :3] = 1
    flags[7:12] = 0  # a strip with no zone at all
    write_lethal(tmp_path / "lethal.tif", flags, costmap)
    grid = load_costmap(costmap)
    every = np.argwhere(np.ones(cost.shape, bool))
    own = grid.own_cost(every).reshape(cost.shape)
    shuffled = rng.permutation(len(every))
    assert np.array_equal(grid.own_cost(every[shuffled]), own.reshape(-1)[shuffled])  # any order
    assert np.array_equal(own[flags != 1], cost[flags != 1].astype(np.float64))
    assert np.isposinf(own[flags == 1]).all() and np.isposinf(grid.cost[flags > 0]).all()
    assert grid.zone_costs is not None and len(grid.zone_costs.values) == (flags == 2).sum()
    relaxed = grid.entering_keep_out().cost
    assert np.allclose(relaxed[flags == 2], KEEP_OUT_ENTRY_COST + cost[flags == 2], rtol=0, atol=1e-4)
    assert np.isposinf(relaxed[flags == 1]).all() and np.array_equal(relaxed[flags == 0], cost[flags == 0])
    # a keep-out cell at or above --lethal-threshold is lethal, never entered
    strict = load_costmap(costmap, lethal_threshold=0.8)
    over = (flags == 2) & (cost >= 0.8)
    assert over.any() and not strict.keep_out[over].any()
    assert np.isposinf(strict.entering_keep_out().cost[over]).all()
    assert np.array_equal(strict.own_cost(every).reshape(cost.shape)[(flags == 2) & ~over], cost[(flags == 2) & ~over])


def test_overrides_that_clear_keep_out_cells_win_in_the_relaxed_grid(tmp_path) -> None:
    """Overrides take cells out of the zone (their cost is then the override's, or lethal); the
    own values kept for the zone must not come back there."""
    import fiona
    import shapely

    from overseec_core.plan.overrides import apply_to_planning_grid
    from overseec_core.synthesize.overrides import load_overrides

    cost = np.full((6, 6), 0.5, np.float32)
    costmap = write_costmap(tmp_path / "costmap.tif", cost)
    flags = np.zeros(cost.shape, np.uint8)
    flags[:, 3] = 2
    write_lethal(tmp_path / "lethal.tif", flags, costmap)
    x0, y0 = UTM_ORIGIN

    def cell(row: int, col: int):  # polygon covering the centre of (row, col), 0.5 m pixels
        return shapely.box(x0 + col * 0.5 + 0.1, y0 - row * 0.5 - 0.4, x0 + col * 0.5 + 0.4, y0 - row * 0.5 - 0.1)

    edits = tmp_path / "edits.gpkg"
    schema = {"geometry": "Polygon", "properties": {"cost": "float", "lethal": "int"}}
    with fiona.open(edits, "w", driver="GPKG", crs="EPSG:32633", schema=schema) as dst:
        dst.write({"geometry": shapely.geometry.mapping(cell(2, 3)), "properties": {"cost": 0.1, "lethal": None}})
        dst.write({"geometry": shapely.geometry.mapping(cell(4, 3)), "properties": {"cost": None, "lethal": 1}})
    loaded = load_costmap(costmap)
    grid, _ = apply_to_planning_grid(loaded, load_overrides([edits], loaded.need_grid()))
    assert grid.keep_out is not None and not grid.keep_out[2, 3] and not grid.keep_out[4, 3]
    relaxed = grid.entering_keep_out().cost
    assert relaxed[2, 3] == np.float32(0.1) and np.isposinf(relaxed[4, 3])
    assert np.allclose(relaxed[[0, 1, 3, 5], 3], KEEP_OUT_ENTRY_COST + 0.5, rtol=0, atol=1e-4)
    assert grid.own_cost(np.array([[2, 3], [3, 3], [4, 3]])).tolist() == [pytest.approx(0.1), 0.5, np.inf]


@pytest.fixture()
def two_passages(tmp_path: Path) -> tuple[Path, np.ndarray, np.ndarray]:
    """21 x 21 neutral costmap, 0.5 m; a keep-out band over columns 6-14 that cuts the map, lethal
    except two passages of the same length inside the zone: row 6 over buildings (cost 1.0),
    row 13 over neutral ground (0.5). The costly one is nearer the straight line from (7, 2) to
    (7, 18); the neutral one saves 9 x 0.5 m x 0.5 = 2.25 against a detour that costs about 1.1."""
    cost = np.full((21, 21), 0.5, np.float32)
    flags = np.zeros(cost.shape, np.uint8)
    flags[:, 6:15] = 1
    flags[6, 6:15] = flags[13, 6:15] = 2
    cost[6, 6:15] = 1.0
    costmap = write_costmap(tmp_path / "costmap.tif", cost)
    write_lethal(tmp_path / "lethal.tif", flags, costmap)
    return costmap, cost, flags


def test_inside_the_zone_the_route_takes_the_cheaper_of_two_equally_long_passages(two_passages) -> None:
    costmap, cost, flags = two_passages
    grid = load_costmap(costmap)
    result, _ = plan_keeping_rules(grid, [(7, 2), (7, 18)])
    rows = result.pixels[flags[result.pixels[:, 0], result.pixels[:, 1]] == 2, 0]
    assert set(rows.tolist()) == {13}  # the neutral passage, not the buildings
    assert not (flags[result.pixels[:, 0], result.pixels[:, 1]] == 1).any()  # lethal never entered
    # 9 zone pixels in a row: 0.25 m in, 8 x 0.5 m, 0.25 m out
    assert len(result.notes) == 1
    assert "runs 4.5 m inside (0.0 m of that on avoided ground)" in result.notes[0]
    assert result.cost == pytest.approx(own_cost_of(costmap, result.pixels), rel=1e-12)


def test_the_note_counts_the_metres_on_avoided_ground(two_passages, tmp_path) -> None:
    costmap, cost, flags = two_passages
    flags = flags.copy()
    flags[13, 6:15] = 1  # only the passage over buildings is left
    write_lethal(tmp_path / "lethal.tif", flags, costmap)
    grid = load_costmap(costmap)
    result, _ = plan_keeping_rules(grid, [(7, 2), (7, 18)])
    assert "runs 4.5 m inside (4.5 m of that on avoided ground)" in result.notes[0]
    assert result.cost == pytest.approx(own_cost_of(costmap, result.pixels), rel=1e-12)


def test_a_never_cross_strip_is_crossed_once_at_its_narrowest(tmp_path) -> None:
    """keep_out = M["X"] (never cross X): X cuts the map, 2 pixels wide over rows 0-9 and 6 wide
    over rows 10-20. Even though the narrow part costs more (1.0 against 0.5) and lies off the
    straight line from (15, 2) to (15, 18), the route crosses there: 1.0 m inside X, not 3.0 m."""
    cost = np.full((21, 21), 0.5, np.float32)
    flags = np.zeros(cost.shape, np.uint8)
    flags[:10, 9:11] = 2
    flags[10:, 7:13] = 2
    cost[:10, 9:11] = 1.0
    costmap = write_costmap(tmp_path / "costmap.tif", cost)
    write_lethal(tmp_path / "lethal.tif", flags, costmap)
    grid = load_costmap(costmap)
    result, _ = plan_keeping_rules(grid, [(15, 2), (15, 18)])
    inside = result.pixels[flags[result.pixels[:, 0], result.pixels[:, 1]] == 2]
    assert len(inside) == 2 and (inside[:, 0] < 10).all()
    assert "runs 1.0 m inside (1.0 m of that on avoided ground)" in result.notes[0]
    assert result.cost == pytest.approx(own_cost_of(costmap, result.pixels), rel=1e-12)
