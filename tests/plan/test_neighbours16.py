"""16-neighbour steps (``Planner(neighbours=16)``): knight moves priced by the cell integral.

Checked against a brute-force Dijkstra written here over the same edge set (8 neighbours at the
mean of the two cells, knight moves at the mean of the four cells they cross, every cell of a
step passable), on both of the kernel's queues; in open ground the route is shorter than the
8-neighbour one; a knight move never crosses a lethal cell; the fallback refuses 16 in one line.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from overseec_core.cli import main
from overseec_core.errors import InputError, PlanError
from overseec_core.plan import Planner, PlanningGrid, _kernel
from overseec_core.plan.paths import knight_side_cells, step_lengths_m
from overseec_core.plan.smooth import segment_costs

from .conftest import KNIGHTS, STEPS8, UTM_ORIGIN, smooth_costmap, textbook_dijkstra, write_costmap

pytestmark = pytest.mark.skipif(_kernel is None, reason="16 neighbours need the compiled kernel")


def _step(cost: np.ndarray, dx: float, dy: float, base: float, r: int, c: int, dr: int, dc: int) -> float | None:
    """The brute force's price of one step (None: off the grid or through a blocked cell)."""
    h, w = cost.shape
    nr, nc = r + dr, c + dc
    if not (0 <= nr < h and 0 <= nc < w):
        return None
    length = math.hypot(dr * dy, dc * dx)
    if abs(dr) <= 1 and abs(dc) <= 1:
        cells = [(r, c), (nr, nc)]
    elif abs(dc) == 2:  # the two cells the segment crosses between the end cells
        sc = dc // 2
        cells = [(r, c), (r, c + sc), (nr, c + sc), (nr, nc)]
    else:
        sr = dr // 2
        cells = [(r, c), (r + sr, c), (r + sr, nc), (nr, nc)]
    vals = [float(cost[p]) for p in cells]
    if not all(math.isfinite(v) for v in vals):
        return None
    return (sum(vals) / len(vals) + base) * length


def brute_force(cost: np.ndarray, dx: float, dy: float, base: float, start: tuple[int, int]) -> np.ndarray:
    """Textbook Dijkstra with a binary heap over 8 neighbours plus the knight moves."""
    return textbook_dijkstra(
        cost.shape, start, STEPS8 + KNIGHTS, lambda r, c, dr, dc: _step(cost, dx, dy, base, r, c, dr, dc)
    )


def _planner(cost: np.ndarray, dx: float, dy: float, base: float, neighbours: int = 16) -> Planner:
    return Planner(PlanningGrid.from_array(cost, None, pixel_size_m=(dx, dy)), base, neighbours=neighbours)


@pytest.mark.parametrize(("seed", "base", "queue"), [(0, 0.01, "ring"), (1, 0.05, "ring"), (2, 0.0, "heap")])
def test_costs_equal_a_brute_force_dijkstra_over_the_same_edges(seed: int, base: float, queue: str) -> None:
    cost = smooth_costmap((17, 23), seed, lethal_fraction=0.15)
    if queue == "heap":  # a zero-cost cell and no base: no bucket width, the radix heap with A*
        cost[np.isfinite(cost)] -= float(np.nanmin(cost[np.isfinite(cost)]))
    dx, dy = 0.5, 0.7
    planner = _planner(cost, dx, dy, base)
    assert (planner._ring[1] > 0) == (queue == "ring")
    free = np.argwhere(np.isfinite(cost))
    rng = np.random.default_rng(seed)
    for i in rng.choice(len(free), size=4, replace=False):
        start = tuple(int(v) for v in free[i])
        want = brute_force(cost, dx, dy, base, start)
        got = planner.cumulative(start).astype(np.float64)
        # the raster is float32: compare at its precision, then the exact goal costs below
        reach = np.isfinite(want)
        assert np.array_equal(reach, np.isfinite(got))
        np.testing.assert_allclose(got[reach], want[reach], rtol=1e-6, atol=1e-6)
        for j in rng.choice(len(free), size=5, replace=False):
            goal = tuple(int(v) for v in free[j])
            if not reach[goal]:
                with pytest.raises(PlanError, match="no path"):
                    planner.plan([start, goal])
                continue
            res = planner.plan([start, goal])
            assert res.cost == pytest.approx(want[goal], rel=1e-9, abs=1e-12)
            # the route's own price under the step rule (knight steps: four cells) is its cost
            assert planner.path_cost(res.pixels) == pytest.approx(res.cost, rel=1e-9, abs=1e-12)


def test_knight_steps_cost_the_cell_integral_of_smooth() -> None:
    """The kernel's knight price is smooth.segment_costs' exact segment integral."""
    cost = smooth_costmap((9, 9), 3, lethal_fraction=0.0)
    dx, dy, base = 0.5, 0.8, 0.02
    planner = _planner(cost, dx, dy, base)
    for dr, dc in KNIGHTS:
        start, goal = (4, 4), (4 + dr, 4 + dc)
        res = planner.plan([start, goal])
        integral, ok = segment_costs(cost, (dx, dy), base, np.array([start]), np.array([goal]))
        assert ok[0]
        if len(res.pixels) == 2:  # the knight move itself was cheapest
            assert res.cost == pytest.approx(float(integral[0]), rel=1e-12)
        else:
            assert res.cost <= float(integral[0]) * (1 + 1e-12)


def test_open_ground_route_is_shorter_than_eight_neighbours_and_near_the_straight_line() -> None:
    cost = np.full((60, 90), 0.5, dtype=np.float32)
    start, goal = (5, 3), (50, 80)
    dx = dy = 0.5
    r8 = _planner(cost, dx, dy, 0.01, neighbours=8).plan([start, goal])
    r16 = _planner(cost, dx, dy, 0.01).plan([start, goal])
    euclid = math.hypot((goal[0] - start[0]) * dy, (goal[1] - start[1]) * dx)
    assert r16.length_m < r8.length_m
    assert r16.cost < r8.cost
    assert r16.length_m - euclid < 0.5 * (r8.length_m - euclid)
    assert r16.length_m >= euclid - 1e-9
    d = np.abs(np.diff(r16.pixels, axis=0))
    assert ((d.max(axis=1) == 2) & (d.min(axis=1) == 1)).any()  # knight moves were used


@pytest.mark.parametrize("side", [(0, 1), (1, 1)])
def test_a_knight_move_never_crosses_a_lethal_cell(side: tuple[int, int]) -> None:
    """(0, 0) -> (1, 2) crosses (0, 1) and (1, 1): with either lethal the knight move is not
    allowed, and the route goes around (dearer than the move would have been)."""
    cost = np.full((4, 5), 0.1, dtype=np.float32)
    free = _planner(cost, 1.0, 1.0, 0.0).plan([(0, 0), (1, 2)])
    assert len(free.pixels) == 2  # in the open the knight move is the route
    cost[side] = np.inf
    res = _planner(cost, 1.0, 1.0, 0.0).plan([(0, 0), (1, 2)])
    knight, s1, s2 = knight_side_cells(res.pixels)
    for k, a, b in zip(knight, s1, s2):
        if k:
            assert np.isfinite(cost[tuple(a)]) and np.isfinite(cost[tuple(b)])
    assert res.cost > free.cost
    assert np.isfinite(res.cost)


@pytest.mark.parametrize("axis", [0, 1])
def test_no_knight_move_jumps_a_one_cell_lethal_wall(axis: int) -> None:
    """A wall one cell thick: a knight move (two cells along) would land beyond it, but it
    crosses a wall cell on the way, so there is no path with 16 neighbours either."""
    cost = np.full((8, 8), 0.2, dtype=np.float32)
    if axis:
        cost[:, 4] = np.inf
    else:
        cost[4, :] = np.inf
    for nb in (8, 16):
        with pytest.raises(PlanError, match="no path"):
            _planner(cost, 1.0, 1.0, 0.01, neighbours=nb).plan([(0, 0), (7, 7)])


def test_path_lengths_accept_knight_steps_and_reject_longer_jumps() -> None:
    px = np.array([[0, 0], [1, 2], [3, 3], [3, 4]])
    assert step_lengths_m(px, 0.5, 1.0) == pytest.approx([math.hypot(1.0, 1.0), math.hypot(2.0, 0.5), 0.5])
    with pytest.raises(InputError, match="knight"):
        step_lengths_m(np.array([[0, 0], [2, 2]]), 1.0, 1.0)


def test_fast_mode_with_16_neighbours_keeps_a_valid_bound() -> None:
    cost = smooth_costmap((120, 140), 5, lethal_fraction=0.1)
    planner = Planner(
        PlanningGrid.from_array(cost, None, pixel_size_m=(0.5, 0.5)), 0.01, coarse_factor=8, neighbours=16
    )
    free = np.argwhere(np.isfinite(cost))
    start, goal = tuple(int(v) for v in free[0]), tuple(int(v) for v in free[-1])
    exact = planner.plan([start, goal])
    fast = planner.plan([start, goal], mode="fast")
    assert fast.cost >= exact.cost * (1 - 1e-12)
    assert fast.bound <= exact.cost * (1 + 1e-12)
    assert planner.path_cost(fast.pixels) == pytest.approx(fast.cost, rel=1e-9)


def test_neighbours_must_be_8_or_16() -> None:
    cost = np.ones((4, 4), dtype=np.float32)
    with pytest.raises(InputError, match="8 or 16"):
        _planner(cost, 1.0, 1.0, 0.01, neighbours=4)


def test_the_fallback_refuses_16_neighbours_naming_the_kernel() -> None:
    grid = PlanningGrid.from_array(np.ones((4, 4), dtype=np.float32), None, pixel_size_m=(1.0, 1.0))
    with pytest.raises(PlanError, match=r"_kernel\.c") as err:
        Planner(grid, 0.01, planner="fallback", neighbours=16)
    assert "\n" not in str(err.value)
    Planner(grid, 0.01, planner="fallback", neighbours=8)  # 8 still works there


def test_overseec_plan_neighbours_16_writes_a_shorter_route_and_records_it(tmp_path: Path, capsys) -> None:
    """The CLI: --neighbours 16 plans with knight moves (a shorter route in open ground than the
    default 8), the grid route's cost equals its cell integral (grid_route.cost_integral), and
    the manifest records the choice."""
    cost = np.full((40, 60), 0.4, dtype=np.float32)
    costmap = write_costmap(tmp_path / "cost.tif", cost)

    def pt(r: int, c: int) -> list[str]:
        return [str(UTM_ORIGIN[0] + (c + 0.5) * 0.5), str(UTM_ORIGIN[1] - (r + 0.5) * 0.5)]

    lengths = {}
    for nb in (8, 16):
        out = tmp_path / f"n{nb}" / "route.geojson"
        out.parent.mkdir()
        args = ["--quiet", "plan", str(costmap), "--start", *pt(2, 2), "--goal", *pt(35, 50), "--out", str(out)]
        assert main([*args, "--neighbours", str(nb), "--smooth", "0"]) == 0
        props = json.loads(out.read_text())["features"][0]["properties"]
        grid_route = props["grid_route"]
        assert grid_route["cost"] == pytest.approx(grid_route["cost_integral"], rel=1e-9)
        lengths[nb] = grid_route["length_m"]
        manifest = json.loads((out.parent / "manifest.json").read_text())
        assert manifest["parameters"]["plan"]["neighbours"] == nb
    assert lengths[16] < lengths[8]
    capsys.readouterr()
    with pytest.raises(SystemExit):
        main(
            ["plan", str(costmap), "--start", *pt(2, 2), "--goal", *pt(3, 3), "--out", "x.geojson", "--neighbours", "4"]
        )


def test_the_choices_are_the_planners() -> None:
    """`defaults.PLAN_NEIGHBOURS` (the CLI's choices and Processing's menu) is the planner's own
    list, and so are the slope models. (--pairs/--matrix with 16: tests/commands/test_plan_pairs_cli.py.)"""
    from overseec_core import defaults
    from overseec_core.plan.paths import SLOPE_MODELS
    from overseec_core.plan.planner import NEIGHBOURS

    assert defaults.PLAN_NEIGHBOURS == NEIGHBOURS == (8, 16)
    assert defaults.SLOPE_MODELS == tuple(SLOPE_MODELS)  # Processing's menu is the planner's models
    from overseec_core.plan.backend import _kernel

    if _kernel is not None:  # the kernel's ids are the table's (a stale kernel is not loaded at all)
        assert _kernel.SLOPE_MODEL_IDS == SLOPE_MODELS == defaults.SLOPE_MODEL_IDS
