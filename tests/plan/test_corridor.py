"""The least-cost corridor and cost-distance fields against a brute-force Dijkstra written here."""

from __future__ import annotations

import math

import numpy as np
import pytest

from overseec_core.errors import InputError, PlanError
from overseec_core.plan.corridor import corridor, cost_distance, cost_distance_many, costs_to
from overseec_core.plan.grid import PlanningGrid
from overseec_core.plan.planner import Planner
from tests.plan.conftest import STEPS8, smooth_costmap, textbook_dijkstra

BACKENDS = ("kernel", "fallback")


def brute_dijkstra(cost: np.ndarray, src: tuple[int, int], base: float, dx: float, dy: float) -> np.ndarray:
    """Plain Dijkstra, 8 neighbours, step = (mean of the two costs + base) x step length."""
    h, w = cost.shape

    def price(r: int, c: int, dr: int, dc: int) -> float | None:
        nr, nc = r + dr, c + dc
        if not (0 <= nr < h and 0 <= nc < w) or not np.isfinite(cost[nr, nc]):
            return None
        step = math.hypot(dx, dy) if dr and dc else (dy if dr else dx)
        return (0.5 * (float(cost[r, c]) + float(cost[nr, nc])) + base) * step

    return textbook_dijkstra((h, w), src, STEPS8, price)


def passable_cells(cost: np.ndarray, rng: np.random.Generator, n: int) -> list[tuple[int, int]]:
    rows, cols = np.nonzero(np.isfinite(cost))
    pick = rng.choice(len(rows), size=n, replace=False)
    return [(int(rows[i]), int(cols[i])) for i in pick]


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_corridor_equals_brute_force(backend: str, seed: int) -> None:
    """Every cell's ratio = (best start->cell + best cell->goal) / optimum, by plain Dijkstra."""
    rng = np.random.default_rng(seed)
    shape = (int(rng.integers(12, 30)), int(rng.integers(12, 30)))
    cost = smooth_costmap(shape, seed=seed, lethal_fraction=0.15, nodata_fraction=0.05)
    dx, dy, base = 0.5, 0.7 if seed % 2 else 0.5, 0.01 * seed
    grid = PlanningGrid.from_array(cost, None, pixel_size_m=(dx, dy))
    planner = Planner(grid, base, planner=backend)
    start, goal = passable_cells(cost, rng, 2)
    ds = brute_dijkstra(cost, start, base, dx, dy)
    if not np.isfinite(ds[goal]):
        with pytest.raises(PlanError, match="no path"):
            corridor(planner, start, goal, 0.1)
        return
    dg = brute_dijkstra(cost, goal, base, dx, dy)
    within = 0.05 * seed
    c = corridor(planner, start, goal, within)
    expect = (ds + dg) / ds[goal]
    reach = np.isfinite(expect)
    assert np.array_equal(np.isfinite(c.ratio), reach)  # NaN exactly where no route passes
    np.testing.assert_allclose(c.ratio[reach], expect[reach], rtol=1e-6)
    assert c.optimum == pytest.approx(ds[goal], rel=1e-12)
    # the mask is the threshold (away from float rounding at the limit)
    clear = reach & (np.abs(expect - (1 + within)) > 1e-9)
    assert np.array_equal(c.mask[clear].astype(bool), expect[clear] <= 1 + within)
    assert not c.mask[~reach].any()


@pytest.mark.parametrize("backend", BACKENDS)
def test_planned_route_is_exactly_one_and_costs_the_optimum(backend: str) -> None:
    cost = smooth_costmap((60, 80), seed=7, lethal_fraction=0.1)
    grid = PlanningGrid.from_array(cost, None, pixel_size_m=(0.5, 0.5))
    planner = Planner(grid, 0.01, planner=backend)
    rng = np.random.default_rng(0)
    for _ in range(3):
        start, goal = passable_cells(cost, rng, 2)
        try:
            route = planner.plan([start, goal], mode="exact")
        except PlanError:
            continue
        field = cost_distance(planner, start)
        assert field[goal] == pytest.approx(route.cost, rel=1e-12)  # distance(goal) = planned cost
        c = corridor(planner, start, goal, 0.02)
        on_route = c.ratio[route.pixels[:, 0], route.pixels[:, 1]]
        assert np.all(on_route == np.float32(1.0))
        assert np.all(c.mask[route.pixels[:, 0], route.pixels[:, 1]] == 1)
        assert np.nanmin(c.ratio) == np.float32(1.0)


def test_kernel_and_fallback_fields_agree() -> None:
    cost = smooth_costmap((40, 50), seed=11, lethal_fraction=0.1, nodata_fraction=0.03)
    grid = PlanningGrid.from_array(cost, None, pixel_size_m=(0.5, 0.8))
    start = passable_cells(cost, np.random.default_rng(1), 1)[0]
    a = cost_distance(Planner(grid, 0.02, planner="kernel"), start)
    b = cost_distance(Planner(grid, 0.02, planner="fallback"), start)
    assert np.array_equal(np.isfinite(a), np.isfinite(b))
    np.testing.assert_allclose(a[np.isfinite(a)], b[np.isfinite(b)], rtol=1e-12)
    targets = [(0, 0), start, (39, 49), (100, 100)]
    expect = [a[t] if t != (100, 100) else np.inf for t in targets]
    np.testing.assert_array_equal(costs_to(Planner(grid, 0.02), start, targets), expect)


def test_bad_input_is_one_line() -> None:
    cost = np.full((10, 10), 0.5, dtype=np.float32)
    cost[5, 5] = np.inf
    planner = Planner(PlanningGrid.from_array(cost, None, pixel_size_m=(1.0, 1.0)), 0.01)
    with pytest.raises(InputError, match="> 0"):
        corridor(planner, (0, 0), (9, 9), 0.0)
    with pytest.raises(PlanError, match="lethal"):
        corridor(planner, (5, 5), (9, 9), 0.1)
    with pytest.raises(PlanError, match="outside"):
        corridor(planner, (0, 0), (10, 9), 0.1)
    with pytest.raises(PlanError, match="same cell"):
        corridor(planner, (1, 1), (1, 1), 0.1)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("seed", [5, 6])
def test_field_from_a_set_of_sources_is_the_min_over_single_sources(backend: str, seed: int) -> None:
    """expand_many: each cell's cost from its cheapest source, = brute force min over sources."""
    rng = np.random.default_rng(seed)
    cost = smooth_costmap((23, 31), seed=seed, lethal_fraction=0.12, nodata_fraction=0.04)
    grid = PlanningGrid.from_array(cost, None, pixel_size_m=(0.5, 0.9))
    sources = passable_cells(cost, rng, 4)
    got = cost_distance_many(Planner(grid, 0.02, planner=backend), sources + sources[:1])  # a duplicate is fine
    expect = np.min([brute_dijkstra(cost, s, 0.02, 0.5, 0.9) for s in sources], axis=0)
    assert np.array_equal(np.isfinite(got), np.isfinite(expect))
    np.testing.assert_allclose(got[np.isfinite(got)], expect[np.isfinite(expect)], rtol=1e-12)
    single = cost_distance_many(Planner(grid, 0.02, planner=backend), sources[:1])
    assert np.array_equal(single, cost_distance(Planner(grid, 0.02, planner=backend), sources[0]))


def test_sources_must_be_passable() -> None:
    cost = np.full((8, 8), 0.5, dtype=np.float32)
    cost[3, 3] = np.nan
    planner = Planner(PlanningGrid.from_array(cost, None, pixel_size_m=(1.0, 1.0)), 0.01)
    with pytest.raises(PlanError, match="source 2 .* nodata"):
        cost_distance_many(planner, [(0, 0), (3, 3)])
    with pytest.raises(PlanError, match="outside"):
        cost_distance_many(planner, [(8, 0)])
    with pytest.raises(InputError):
        cost_distance_many(planner, [])
