"""The planner: exact paths on hand-checked grids, optimal costs against scikit-image's
MCP_Geometric, impassable cells and waypoint errors, buffer reuse, fast mode and its bound."""

from __future__ import annotations

import math

import numpy as np
import pytest
from skimage.graph import MCP_Geometric

from overseec_core.errors import Cancelled, InputError, PlanError
from overseec_core.plan import Planner, PlanningGrid, _kernel, cumulative_path_cost
from overseec_core.plan import planner as planner_module
from overseec_core.plan.coarse import hop_offsets
from overseec_core.plan.planner import UNVISITED
from overseec_core.progress import NullProgress

from .conftest import smooth_costmap

SQRT2 = math.sqrt(2.0)


def planner_for(cost, dx=1.0, dy=1.0, base=0.0, **kw) -> Planner:
    return Planner(PlanningGrid.from_array(np.asarray(cost, dtype=np.float32), pixel_size_m=(dx, dy)), base, **kw)


def mcp_costs(cost: np.ndarray, start, dx: float, dy: float, base: float) -> np.ndarray:
    """scikit-image's cumulative costs under the same rule (impassable cells: inf)."""
    c = np.where(np.isfinite(cost), cost.astype(np.float64) + base, np.inf)
    cum, _ = MCP_Geometric(c, sampling=(dy, dx)).find_costs([start])
    return cum


def assert_8_connected(pixels: np.ndarray) -> None:
    steps = np.abs(np.diff(pixels, axis=0))
    assert steps.max() <= 1 and (steps.sum(axis=1) > 0).all()


# --------------------------------------------------------------------------------------------
# Hand-checked grids
# --------------------------------------------------------------------------------------------


def test_row_of_costs_is_the_sum_of_step_means() -> None:
    res = planner_for([[1, 2, 3, 4, 5]]).plan([(0, 0), (0, 4)])
    assert res.cost == pytest.approx(1.5 + 2.5 + 3.5 + 4.5, rel=1e-15)
    assert res.pixels.tolist() == [[0, 0], [0, 1], [0, 2], [0, 3], [0, 4]]
    assert res.length_m == pytest.approx(4.0)
    assert res.mode == "exact" and res.bound == res.cost


def test_detour_around_an_expensive_wall_uses_diagonals() -> None:
    cost = [[1, 9, 1], [1, 9, 1], [1, 1, 1]]
    res = planner_for(cost).plan([(0, 0), (0, 2)])
    assert res.pixels.tolist() == [[0, 0], [1, 0], [2, 1], [1, 2], [0, 2]]
    assert res.cost == pytest.approx(2 + 2 * SQRT2, rel=1e-15)
    assert res.length_m == pytest.approx(2 + 2 * SQRT2)


def test_lethal_wall_forces_the_same_detour_and_a_closed_wall_has_no_path() -> None:
    cost = np.array([[1, np.inf, 1], [1, np.inf, 1], [1, 1, 1]], dtype=np.float32)
    assert planner_for(cost).plan([(0, 0), (0, 2)]).pixels.tolist() == [[0, 0], [1, 0], [2, 1], [1, 2], [0, 2]]
    cost[2, 1] = np.nan  # nodata closes the gap
    with pytest.raises(PlanError, match=r"no path from start \(row 0, col 0\) to goal \(row 0, col 2\)"):
        planner_for(cost).plan([(0, 0), (0, 2)])


def test_base_cost_makes_zero_cost_paths_straight() -> None:
    res = planner_for(np.zeros((5, 5)), base=0.01).plan([(0, 0), (4, 4)])
    assert res.pixels.tolist() == [[i, i] for i in range(5)]
    assert res.cost == pytest.approx(4 * SQRT2 * 0.01, rel=1e-14)


def test_zero_cost_without_base_uses_the_radix_heap_and_returns_zero() -> None:
    planner = planner_for(np.zeros((6, 7)), base=0.0)
    assert planner._ring == (0.0, 0)  # no positive least step: the bucket ring cannot be used
    res = planner.plan([(0, 0), (5, 6)])
    assert res.cost == 0.0
    assert res.pixels[0].tolist() == [0, 0] and res.pixels[-1].tolist() == [5, 6]
    assert_8_connected(res.pixels)


@pytest.mark.parametrize("over", [False, True])
def test_the_kernels_max_ring_decides_between_the_ring_and_the_radix_heap(over: bool) -> None:
    """The planner takes its ring limit from the kernel (one constant): a cost range needing just
    under MAX_RING buckets uses the ring, just over uses the radix heap; both are exact."""
    assert planner_module.MAX_RING == _kernel.MAX_RING == 1 << 16
    high = (1.01 if over else 0.99) * (_kernel.MAX_RING - 2) / SQRT2
    cost = np.ones((12, 14), dtype=np.float32)
    cost[3:9, 4:10] = high
    cost[5, 2:12] = 2.0
    planner = planner_for(cost)
    ring = planner._ring[1]
    assert (ring == 0) == over and (over or 0.98 * _kernel.MAX_RING < ring <= _kernel.MAX_RING)
    cum = mcp_costs(cost, (0, 0), 1.0, 1.0, 0.0)
    for goal in [(11, 13), (5, 11), (7, 6)]:
        assert planner.plan([(0, 0), goal]).cost == pytest.approx(cum[goal], rel=1e-9)


def test_the_kernel_search_takes_named_arguments_only() -> None:
    cost = np.ones((3, 3), dtype=np.float32)
    state = np.zeros(9, dtype=np.uint8)
    dist = np.full(9, UNVISITED)
    args = dict(
        cost=cost,
        dist=dist,
        state=state,
        workspace=_kernel.workspace(),
        dx=1.0,
        dy=1.0,
        base=0.0,
        start=0,
        goal=8,
        cancel=np.zeros(1, dtype=np.uint8),
        bbox=np.array([3, -1, 3, -1], dtype=np.int64),
    )
    with pytest.raises(TypeError, match="no positional arguments"):
        _kernel.search(*args.values())
    with pytest.raises(TypeError, match="needs the keyword arguments .* start"):
        _kernel.search(**{k: v for k, v in args.items() if k != "start"})
    with pytest.raises(ValueError, match="too many ring buckets"):
        _kernel.search(**args, width=0.5, ring=_kernel.MAX_RING + 1)
    status, goal_dist, settled, _pushed = _kernel.search(**args)
    assert (status, goal_dist) == (0, pytest.approx(2 * SQRT2)) and settled > 0
    assert _kernel.trace(state, 3, 3, 8).tolist() == [[0, 0], [1, 1], [2, 2]]


def test_non_square_pixels_price_rows_with_dy_and_diagonals_with_the_hypotenuse() -> None:
    column = planner_for(np.ones((3, 1)), dx=1.0, dy=3.0).plan([(0, 0), (2, 0)])
    assert column.cost == pytest.approx(6.0) and column.length_m == pytest.approx(6.0)
    row = planner_for(np.ones((1, 3)), dx=1.0, dy=3.0).plan([(0, 0), (0, 2)])
    assert row.cost == pytest.approx(2.0)
    diag = planner_for(np.ones((2, 2)), dx=1.0, dy=3.0).plan([(0, 0), (1, 1)])
    assert diag.pixels.tolist() == [[0, 0], [1, 1]]
    assert diag.cost == pytest.approx(math.hypot(1.0, 3.0))


def test_same_start_and_goal_is_a_one_pixel_path() -> None:
    res = planner_for(np.ones((3, 3))).plan([(1, 1), (1, 1)], mode="fast")
    assert res.pixels.tolist() == [[1, 1]] and res.cost == 0.0 and res.length_m == 0.0


# --------------------------------------------------------------------------------------------
# Optimal cost against scikit-image MCP_Geometric
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("seed", range(8))
def test_exact_cost_equals_mcp_geometric(seed: int) -> None:
    rng = np.random.default_rng(seed)
    shape = (int(rng.integers(8, 70)), int(rng.integers(8, 70)))
    cost = rng.random(shape).astype(np.float32) ** int(rng.integers(1, 4))
    cost[rng.random(shape) < 0.15] = np.inf
    cost[rng.random(shape) < 0.05] = np.nan
    dx, dy = rng.uniform(0.1, 3.0, 2)
    base = [0.0, 0.01, 0.3][seed % 3]
    start = (int(rng.integers(0, shape[0])), int(rng.integers(0, shape[1])))
    cost[start] = 0.5
    planner = planner_for(cost, dx, dy, base)
    cum = mcp_costs(cost, start, dx, dy, base)
    reachable = np.argwhere(np.isfinite(cum))
    goals = reachable[rng.choice(len(reachable), size=min(5, len(reachable)), replace=False)]
    for goal in map(tuple, goals):
        res = planner.plan([start, goal])
        assert res.cost == pytest.approx(cum[goal], rel=1e-9, abs=1e-12)
        assert res.pixels[0].tolist() == list(start) and res.pixels[-1].tolist() == list(goal)
        assert_8_connected(res.pixels)
        assert np.isfinite(cost[res.pixels[:, 0], res.pixels[:, 1]]).all()
        # the reported cost is the cost of the reported path
        assert planner.path_cost(res.pixels) == pytest.approx(res.cost, rel=1e-12, abs=1e-12)
    unreachable = np.argwhere(~np.isfinite(cum) & np.isfinite(cost))
    if len(unreachable):
        with pytest.raises(PlanError, match="no path"):
            planner.plan([start, tuple(unreachable[0])])


@pytest.mark.parametrize("low", [0.0, 0.001])
def test_radix_heap_and_astar_path_equals_mcp_geometric(low: float) -> None:
    """Costs spanning 1e5 (or touching 0 with no base) leave the bucket ring for the radix heap,
    with A* whenever the least cost per metre is positive."""
    rng = np.random.default_rng(21)
    cost = (low + 100.0 * rng.random((50, 60)) ** 3).astype(np.float32)
    cost[rng.random(cost.shape) < 0.1] = np.inf
    cost[0, 0] = cost[49, 59] = low
    planner = planner_for(cost, dx=0.9, dy=0.4, base=0.0)
    assert planner._ring == (0.0, 0) and (planner._hscale > 0) == (low > 0)
    cum = mcp_costs(cost, (0, 0), 0.9, 0.4, 0.0)
    for goal in [(49, 59), (10, 50), (45, 3)]:
        if np.isfinite(cum[goal]):
            assert planner.plan([(0, 0), goal]).cost == pytest.approx(cum[goal], rel=1e-9)


def test_cost_distance_raster_equals_mcp_everywhere() -> None:
    cost = smooth_costmap((45, 38), seed=11, lethal_fraction=0.12, nodata_fraction=0.03)
    cost[20, 20] = 0.3
    planner = planner_for(cost, dx=0.7, dy=1.9, base=0.01)
    cum = planner.cumulative((20, 20))
    ref = mcp_costs(cost, (20, 20), 0.7, 1.9, 0.01)
    assert cum.dtype == np.float32
    assert np.array_equal(np.isnan(cum), ~np.isfinite(ref))
    fin = np.isfinite(ref)
    np.testing.assert_allclose(cum[fin], ref[fin], rtol=1e-6)  # float32 output


def test_waypoints_are_visited_in_order_and_legs_add_up() -> None:
    cost = smooth_costmap((40, 50), seed=5, lethal_fraction=0.05)
    pts = [(1, 1), (35, 5), (5, 45), (38, 48)]
    for p in pts:
        cost[p] = 0.4
    planner = planner_for(cost, dx=0.5, dy=0.5, base=0.01)
    res = planner.plan(pts)
    legs = [mcp_costs(cost, a, 0.5, 0.5, 0.01)[b] for a, b in zip(pts[:-1], pts[1:])]
    assert res.leg_costs == pytest.approx(legs, rel=1e-9)
    assert res.cost == pytest.approx(sum(legs), rel=1e-9)
    visited = [tuple(p) for p in res.pixels.tolist()]
    idx = [visited.index(p) for p in pts]
    assert idx == sorted(idx) and idx[0] == 0 and idx[-1] == len(visited) - 1
    assert_8_connected(res.pixels)
    assert cumulative_path_cost(planner.grid, res.pixels, 0.01)[-1] == pytest.approx(res.cost, rel=1e-12)


# --------------------------------------------------------------------------------------------
# Impassable points and malformed input
# --------------------------------------------------------------------------------------------


@pytest.fixture
def blocked() -> Planner:
    cost = np.ones((10, 10), dtype=np.float32)
    cost[5, 5] = np.inf
    cost[6, 6] = np.nan
    return planner_for(cost)


@pytest.mark.parametrize(
    "points, message",
    [
        ([(5, 5), (0, 0)], r"start \(row 5, col 5\) is on a lethal cell"),
        ([(0, 0), (6, 6)], r"goal \(row 6, col 6\) is on a nodata cell"),
        ([(0, 0), (10, 0)], r"goal \(row 10, col 0\) is outside the costmap \(10 x 10 pixels\)"),
        ([(-1, 0), (1, 1)], r"start \(row -1, col 0\) is outside"),
        ([(0, 0), (5, 5), (9, 9)], r"via point 1 \(row 5, col 5\) is on a lethal cell"),
    ],
)
def test_points_that_cannot_be_on_a_path_are_named(blocked: Planner, points, message) -> None:
    with pytest.raises(PlanError, match=message):
        blocked.plan(points)


def test_labels_replace_pixel_indices_in_messages(blocked: Planner) -> None:
    with pytest.raises(PlanError, match=r"^goal \(500010, 3999990\) is on a lethal cell"):
        blocked.plan([(0, 0), (5, 5)], labels=["(500000, 4000000)", "(500010, 3999990)"])


@pytest.mark.parametrize("points", [[(0, 0)], [(0, 0), (1.5, 2)], [(0, 0), "ab"], [1, 2]])
def test_malformed_points_are_input_errors(blocked: Planner, points) -> None:
    with pytest.raises(InputError):
        blocked.plan(points)


def test_bad_mode_and_base_are_input_errors(blocked: Planner) -> None:
    with pytest.raises(InputError, match="unknown planning mode"):
        blocked.plan([(0, 0), (1, 1)], mode="quick")
    with pytest.raises(InputError, match="base cost"):
        Planner(blocked.grid, -1.0)
    with pytest.raises(InputError, match="costs must be >= 0"):
        PlanningGrid.from_array(np.array([[1.0, -0.5]]))


# --------------------------------------------------------------------------------------------
# Reuse, memory, cancellation
# --------------------------------------------------------------------------------------------


def test_repeated_queries_reuse_buffers_and_match_a_fresh_planner() -> None:
    cost = smooth_costmap((64, 90), seed=7, lethal_fraction=0.1)
    grid = PlanningGrid.from_array(cost, pixel_size_m=(0.5, 0.8))
    rng = np.random.default_rng(1)
    passable = np.argwhere(np.isfinite(cost))
    queries = [[tuple(passable[i]) for i in rng.choice(len(passable), 2)] for _ in range(8)]
    planner = Planner(grid, 0.01, coarse_factor=4)
    ids = {k: (id(v), v.__array_interface__["data"][0]) for k, v in planner.buffers.items()}
    for i, q in enumerate(queries):
        mode = "fast" if i in (1, 2, 3, 6) else "exact"  # consecutive fast queries, then exact
        try:
            got = planner.plan(q, mode=mode)
        except PlanError:
            with pytest.raises(PlanError):
                Planner(grid, 0.01, coarse_factor=4).plan(q, mode=mode)
            continue
        fresh = Planner(grid, 0.01, coarse_factor=4).plan(q, mode=mode)
        assert got.cost == fresh.cost and np.array_equal(got.pixels, fresh.pixels)
        if i == 4:
            planner.cumulative(q[0])  # a full expansion in between changes nothing either
    assert {k: (id(v), v.__array_interface__["data"][0]) for k, v in planner.buffers.items()} == ids
    # resetting what the last query wrote leaves every cell unvisited, even after consecutive
    # corridor searches (each reset must cover the previous corridor, not the next one)
    far = [tuple(passable[0]), tuple(passable[-1])]
    near = [tuple(passable[len(passable) // 3]), tuple(passable[2 * len(passable) // 3])]
    for q in (far, near, far):
        planner.plan(q, mode="fast")
        planner.plan(q[::-1], mode="fast")
    planner._reset_dirty()
    assert (planner.buffers["dist"] == UNVISITED).all() and not planner.buffers["state"].any()


def test_planner_memory_is_under_20_bytes_per_pixel() -> None:
    cost = smooth_costmap((400, 500), seed=2, lethal_fraction=0.08)
    cost[:3, :3] = cost[-3:, -3:] = 0.3
    planner = Planner(PlanningGrid.from_array(cost, pixel_size_m=(0.5, 0.5)), 0.01)
    planner.plan([(0, 0), (399, 499)])
    planner.plan([(0, 0), (399, 499)], mode="fast")
    mem = planner.memory_bytes()
    assert mem["dist"] == 8 * cost.size and mem["state"] == cost.size and mem["cost"] == 4 * cost.size
    assert mem["fast"] > 0 and mem["heap"] > 0
    assert mem["per_pixel"] <= 20.0, mem


class _CancelNow(NullProgress):
    def cancelled(self) -> bool:
        return True


def test_cancelling_stops_the_search_and_the_planner_stays_usable() -> None:
    cost = smooth_costmap((300, 300), seed=4, lethal_fraction=0.0)
    planner = planner_for(cost, base=0.01)
    with pytest.raises(Cancelled):
        planner.plan([(0, 0), (299, 299)], progress=_CancelNow())
    again = planner.plan([(0, 0), (299, 299)])
    assert again.cost == planner_for(cost, base=0.01).plan([(0, 0), (299, 299)]).cost


# --------------------------------------------------------------------------------------------
# Fast mode
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("seed", range(5))
def test_fast_mode_cost_is_at_least_exact_and_its_bound_at_most(seed: int) -> None:
    cost = smooth_costmap((120, 150), seed=seed, lethal_fraction=0.1)
    rng = np.random.default_rng(seed)
    passable = np.argwhere(np.isfinite(cost))
    planner = Planner(PlanningGrid.from_array(cost, pixel_size_m=(0.6, 0.4)), 0.01, coarse_factor=4)
    for _ in range(4):
        a, b = (tuple(p) for p in passable[rng.choice(len(passable), 2)])
        try:
            exact = planner.plan([a, b])
        except PlanError:
            with pytest.raises(PlanError, match="no path"):
                planner.plan([a, b], mode="fast")
            continue
        fast = planner.plan([a, b], mode="fast")
        assert fast.requested_mode == "fast" and fast.mode in ("fast", "exact")
        assert fast.cost >= exact.cost * (1 - 1e-12)
        assert 0.0 <= fast.bound <= exact.cost * (1 + 1e-12)
        assert fast.bound <= fast.cost
        assert planner.path_cost(fast.pixels) == pytest.approx(fast.cost, rel=1e-12)
        assert_8_connected(fast.pixels)


def test_fast_mode_bound_is_informative_on_a_smooth_map() -> None:
    cost = smooth_costmap((200, 200), seed=9, lethal_fraction=0.0)
    planner = Planner(PlanningGrid.from_array(cost, pixel_size_m=(0.5, 0.5)), 0.01, coarse_factor=4)
    exact = planner.plan([(0, 0), (199, 199)])
    fast = planner.plan([(0, 0), (199, 199)], mode="fast")
    octile_only = planner._hscale * 199 * math.sqrt(0.5)
    assert octile_only < fast.bound <= exact.cost
    assert fast.mode == "fast" and fast.gap < 1.0


def _wall_map(height: int) -> np.ndarray:
    cost = np.full((height, 200), 0.5, dtype=np.float32)
    cost[:, 100] = np.inf
    cost[height - 1, 100] = 0.5  # the only gap, at the bottom
    return cost


def test_fast_mode_widens_its_corridor_to_reach_a_gap() -> None:
    planner = planner_for(_wall_map(40), base=0.01, coarse_factor=4, corridor_blocks=1)
    fast = planner.plan([(20, 0), (20, 199)], mode="fast")
    assert fast.mode == "fast" and any("widened" in n for n in fast.notes)
    assert fast.cost >= planner.plan([(20, 0), (20, 199)]).cost


def test_fast_mode_falls_back_to_exact_when_the_corridor_holds_no_path() -> None:
    planner = planner_for(_wall_map(80), base=0.01, coarse_factor=4, corridor_blocks=1)
    fast = planner.plan([(40, 0), (40, 199)], mode="fast")
    exact = planner.plan([(40, 0), (40, 199)])
    assert fast.mode == "exact" and any("exact search used" in n for n in fast.notes)
    assert fast.cost == exact.cost and fast.bound == fast.cost


def test_hop_lengths_are_the_least_ground_distance_between_blocks() -> None:
    offs, lens = hop_offsets(2, 4, 1.0, 2.0)
    table = {tuple(o): v for o, v in zip(offs.tolist(), lens.tolist())}
    assert len(table) == 16
    assert table[(0, 2)] == pytest.approx(5 * 1.0)  # 5 columns apart at dx = 1
    assert table[(2, 0)] == pytest.approx(5 * 2.0)  # 5 rows apart at dy = 2
    assert table[(2, 1)] == pytest.approx(math.hypot(1, 2) + 4 * 2.0)  # 5 rows, 1 column
    assert table[(-2, -2)] == pytest.approx(5 * math.hypot(1, 2))
