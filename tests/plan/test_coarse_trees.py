"""Fast mode's kept coarse trees (Planner(coarse_trees=N)), which interactive re-plans use."""

from __future__ import annotations

import numpy as np
import pytest

from overseec_core.plan import Planner, PlanningGrid

from .conftest import smooth_costmap


@pytest.fixture(scope="module")
def grid() -> PlanningGrid:
    cost = smooth_costmap((240, 300), seed=11, lethal_fraction=0.06)
    cost[:4, :4] = cost[-4:, -4:] = 0.5
    return PlanningGrid.from_array(cost, pixel_size_m=(0.5, 0.5))


def passable(grid: PlanningGrid, r: int, c: int) -> tuple[int, int]:
    ok = np.argwhere(np.isfinite(grid.cost))
    return tuple(int(v) for v in ok[np.argmin(np.abs(ok - (r, c)).sum(axis=1))])


def test_a_drag_reads_coarse_routes_off_trees_at_the_ends_that_stay(grid) -> None:
    planner = Planner(grid, coarse_factor=6, coarse_trees=4)
    exact = Planner(grid)
    start, goal = passable(grid, 2, 2), passable(grid, 236, 296)
    vias = [passable(grid, 80 + 5 * i, 200 - 7 * i) for i in range(8)]
    fl = None
    for i, via in enumerate(vias):
        res = planner.plan([start, via, goal], mode="fast")
        fl = planner._fast_level()
        # the first query keeps no tree; later ones grow them at start and goal, and reuse them
        k = fl.k
        roots = {(start[0] // k, start[1] // k), (goal[0] // k, goal[1] // k)}
        assert (set(fl.trees) >= roots) == (i > 0)
        best = exact.plan([start, via, goal], mode="exact")
        assert res.cost >= best.cost - 1e-9 and res.bound <= best.cost + 1e-9
        assert planner.path_cost(res.pixels) == pytest.approx(res.cost, rel=1e-12)
        assert tuple(res.pixels[0]) == start and tuple(res.pixels[-1]) == goal
        assert any((res.pixels == via).all(axis=1))
    # a route read off a tree is a cheapest coarse route, as a search finds
    ca, cb = (start[0] // k, start[1] // k), (vias[-1][0] // k, vias[-1][1] // k)
    from_tree = planner._coarse_route(fl, start, vias[-1], None)
    searched = fl.coarse._leg_exact(ca, cb, None)
    assert fl.coarse.path_cost(from_tree) == pytest.approx(searched.cost, rel=1e-12)
    assert len(fl.trees) <= 4


def test_without_coarse_trees_nothing_is_kept(grid) -> None:
    planner = Planner(grid, coarse_factor=6)
    start, goal = passable(grid, 2, 2), passable(grid, 236, 296)
    for via in (passable(grid, 80, 200), passable(grid, 90, 190)):
        planner.plan([start, via, goal], mode="fast")
    assert not planner._fast_level().trees
