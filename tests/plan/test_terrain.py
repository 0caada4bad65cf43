"""Anisotropic planning on a DEM (``Planner(elevation=..., slope_model=...)``).

Checked on generated elevations: on a plane of known slope every step costs its analytic price
(cost x 3D length x f(slope)); on a random terrain A -> B and B -> A differ and each equals a
brute-force Dijkstra written here over the same directed edges (8 and 16 neighbours); a route
goes around a steep hill instead of over it; the 3D length is >= the ground length and equal to
it on flat ground; cells without elevation are never entered; the fallback refuses in one line.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import ndimage

from overseec_core.errors import InputError, PlanError
from overseec_core.plan import Planner, PlanningGrid, _kernel
from overseec_core.plan.paths import SLOPE_MIN, slope_factor

from .conftest import KNIGHTS, STEPS8, smooth_costmap, textbook_dijkstra

pytestmark = pytest.mark.skipif(_kernel is None, reason="the slope models need the compiled kernel")


def tobler(s: float) -> float:
    """Tobler's hiking function as a multiplier, written out from its definition (km/h)."""
    speed = 6.0 * math.exp(-3.5 * abs(s + 0.05))
    return (6.0 * math.exp(-3.5 * 0.05)) / speed


def vehicle(s: float) -> float:
    """The vehicle model, written out from its documented numbers."""
    if abs(s) > 0.5:
        return math.inf
    if s > 0:
        return 1.0 + 10.0 * s
    return 1.0 + 5.0 * max(0.0, -s - 0.15)


FUNCS = {"tobler": tobler, "vehicle": vehicle}


def _cells(r: int, c: int, dr: int, dc: int) -> list[tuple[int, int]]:
    nr, nc = r + dr, c + dc
    if abs(dr) <= 1 and abs(dc) <= 1:
        return [(r, c), (nr, nc)]
    if abs(dc) == 2:
        return [(r, c), (r, c + dc // 2), (nr, c + dc // 2), (nr, nc)]
    return [(r, c), (r + dr // 2, c), (r + dr // 2, nc), (nr, nc)]


def step_price(cost, z, dx, dy, base, model, r, c, dr, dc) -> float | None:
    """The brute force's price of the directed step (r, c) -> (r + dr, c + dc)."""
    h, w = cost.shape
    nr, nc = r + dr, c + dc
    if not (0 <= nr < h and 0 <= nc < w):
        return None
    vals = [float(cost[p]) for p in _cells(r, c, dr, dc)]
    if not all(math.isfinite(v) for v in vals) or not math.isfinite(z[nr, nc]):
        return None
    ground = math.hypot(dr * dy, dc * dx)
    dz = float(z[nr, nc]) - float(z[r, c])
    f = FUNCS[model](dz / ground)
    if not math.isfinite(f):
        return None
    return (sum(vals) / len(vals) + base) * math.hypot(ground, dz) * f


def brute_force(cost, z, dx, dy, base, model, start, neighbours) -> np.ndarray:
    """Textbook Dijkstra over the directed edges."""
    steps = STEPS8 + (KNIGHTS if neighbours == 16 else [])
    return textbook_dijkstra(
        cost.shape, start, steps, lambda r, c, dr, dc: step_price(cost, z, dx, dy, base, model, r, c, dr, dc)
    )


def _planner(cost, z, dx, dy, base, model, neighbours=8, **kw) -> Planner:
    grid = PlanningGrid.from_array(cost, None, pixel_size_m=(dx, dy))
    return Planner(grid, base, elevation=z, slope_model=model, neighbours=neighbours, **kw)


def test_the_models_are_the_documented_functions() -> None:
    s = np.linspace(-0.7, 0.7, 281)
    for name, func in FUNCS.items():
        assert slope_factor(name, s) == pytest.approx([func(float(v)) for v in s], rel=1e-12)
        assert float(slope_factor(name, 0.0)) == pytest.approx(1.0)
        finite = slope_factor(name, s)[np.isfinite(slope_factor(name, s))]
        assert finite.min() >= SLOPE_MIN[name] * (1 - 1e-12)  # the heuristic's scale is a true minimum
    assert SLOPE_MIN["tobler"] == pytest.approx(tobler(-0.05))


@pytest.mark.parametrize("model", ["tobler", "vehicle"])
@pytest.mark.parametrize("uphill", [True, False])
def test_plane_of_known_slope_prices_each_step_analytically(model: str, uphill: bool) -> None:
    h, w, dx, dy, base, grade = 3, 30, 2.0, 1.5, 0.05, 0.125  # exact in float32
    cost = np.full((h, w), np.inf, np.float32)
    cost[1] = 0.375  # one passable row: the route is the straight line
    z = (np.arange(w, dtype=np.float64)[None, :] * dx * grade * np.ones((h, 1))).astype(np.float32)
    p = _planner(cost, z, dx, dy, base, model)
    a, b = ((1, 0), (1, w - 1)) if uphill else ((1, w - 1), (1, 0))
    res = p.plan([a, b])
    s = grade if uphill else -grade
    dz = float(z[1, 1]) - float(z[1, 0])
    one = (0.375 + base) * math.hypot(dx, dz) * FUNCS[model](s)
    assert res.cost == pytest.approx((w - 1) * one, rel=1e-9)
    assert res.cost == pytest.approx(p.path_cost(res.pixels), rel=1e-12)
    assert res.length_m == pytest.approx((w - 1) * math.hypot(dx, dz), rel=1e-9)
    assert p.path_length_2d_m(res.pixels) == pytest.approx((w - 1) * dx)


@pytest.mark.parametrize("model", ["tobler", "vehicle"])
@pytest.mark.parametrize("neighbours", [8, 16])
def test_both_directions_equal_a_brute_force_and_differ(model: str, neighbours: int) -> None:
    h, w, dx, dy, base = 16, 21, 1.0, 1.3, 0.02
    cost = smooth_costmap((h, w), 4, lethal_fraction=0.1)
    rng = np.random.default_rng(7)
    z = ndimage.gaussian_filter(rng.random((h, w)), 2.0)
    z = ((z - z.min()) / (z.max() - z.min()) * 6.0 + np.arange(w)[None, :] * 0.35).astype(np.float32)
    z[3, 4] = np.nan  # no elevation: never entered
    fin = np.flatnonzero(np.isfinite(cost.ravel()) & np.isfinite(z.ravel()))
    a = tuple(int(v) for v in np.unravel_index(fin[0], cost.shape))
    b = tuple(int(v) for v in np.unravel_index(fin[-1], cost.shape))
    p = _planner(cost, z, dx, dy, base, model, neighbours)
    fwd_bf = brute_force(cost, z, dx, dy, base, model, a, neighbours)
    back_bf = brute_force(cost, z, dx, dy, base, model, b, neighbours)
    assert math.isfinite(fwd_bf[b]) and math.isfinite(back_bf[a])
    fwd, back = p.plan([a, b]), p.plan([b, a])
    assert fwd.cost == pytest.approx(fwd_bf[b], rel=1e-9)
    assert back.cost == pytest.approx(back_bf[a], rel=1e-9)
    assert abs(fwd.cost - back.cost) > 1e-3 * fwd.cost
    for res in (fwd, back):
        assert p.path_cost(res.pixels) == pytest.approx(res.cost, rel=1e-9)
        assert (3, 4) not in {tuple(px) for px in res.pixels.tolist()}
    # the whole cost-distance field from a (no heuristic, every cell) agrees too
    p.expand(a)
    field = p.cumulative_rows(0, h).astype(np.float64)
    reach = np.isfinite(fwd_bf)
    assert np.isnan(field[~reach]).all()
    assert field[reach] == pytest.approx(fwd_bf[reach], rel=1e-6)


def test_tobler_uphill_dearer_and_a_mild_descent_cheaper_than_flat() -> None:
    h, w, dx = 3, 25, 1.0
    cost = np.full((h, w), np.inf, np.float32)
    cost[1] = 0.3
    ramp = np.arange(w, dtype=np.float32)[None, :] * np.ones((h, 1), np.float32)
    flat = _planner(cost, np.zeros((h, w), np.float32), dx, dx, 0.0, "tobler").plan([(1, 0), (1, w - 1)]).cost
    steep = _planner(cost, ramp * 0.2, dx, dx, 0.0, "tobler")
    up, down = steep.plan([(1, 0), (1, w - 1)]).cost, steep.plan([(1, w - 1), (1, 0)]).cost
    assert up > down > flat
    mild = _planner(cost, ramp * 0.05, dx, dx, 0.0, "tobler")
    assert mild.plan([(1, w - 1), (1, 0)]).cost < flat < mild.plan([(1, 0), (1, w - 1)]).cost


@pytest.mark.parametrize("model", ["tobler", "vehicle"])
def test_the_route_goes_around_a_steep_hill(model: str) -> None:
    h, w, dx = 61, 61, 1.0
    cost = np.full((h, w), 0.5, np.float32)
    yy, xx = np.mgrid[0:h, 0:w]
    z = (25.0 * np.exp(-((yy - 30) ** 2 + (xx - 30) ** 2) / (2 * 7.0**2))).astype(np.float32)
    grid = PlanningGrid.from_array(cost, None, pixel_size_m=(dx, dx))
    flat = Planner(grid, 0.05).plan([(30, 0), (30, 60)])
    assert flat.pixels[:, 0].tolist() == [30] * 61  # without a DEM: straight over the top
    res = _planner(cost, z, dx, dx, 0.05, model).plan([(30, 0), (30, 60)])
    assert float(z[res.pixels[:, 0], res.pixels[:, 1]].max()) < 0.5 * float(z.max())
    assert np.abs(res.pixels[:, 0] - 30).max() >= 10


def test_3d_length_counts_the_climb_and_equals_ground_length_on_flat_ground() -> None:
    cost = smooth_costmap((20, 20), 3, lethal_fraction=0.0)
    flat = _planner(cost, np.full((20, 20), 100.0, np.float32), 1.0, 1.0, 0.01, "tobler")
    res = flat.plan([(0, 0), (19, 19)])
    assert res.length_m == flat.path_length_2d_m(res.pixels)
    iso = Planner(PlanningGrid.from_array(cost, None, pixel_size_m=(1.0, 1.0)), 0.01).plan([(0, 0), (19, 19)])
    assert res.cost == pytest.approx(iso.cost, rel=0.2)  # flat: f in [0.84, 1] of the plain rule
    hilly = _planner(
        cost, np.add.outer(np.arange(20.0), np.arange(20.0)).astype(np.float32) * 0.1, 1.0, 1.0, 0.01, "tobler"
    )
    res = hilly.plan([(0, 0), (19, 19)])
    assert res.length_m > hilly.path_length_2d_m(res.pixels)


def test_cells_without_elevation_are_impassable() -> None:
    cost = np.full((15, 15), 0.2, np.float32)
    z = np.zeros((15, 15), np.float32)
    z[:, 7] = np.nan  # a wall without elevation ...
    z[12, 7] = 0.0  # ... with one gap
    p = _planner(cost, z, 1.0, 1.0, 0.01, "vehicle")
    res = p.plan([(2, 0), (2, 14)])
    assert [7 != c or r == 12 for r, c in res.pixels.tolist()] == [True] * len(res.pixels)
    assert (12, 7) in {tuple(px) for px in res.pixels.tolist()}
    with pytest.raises(PlanError, match="no elevation"):
        p.plan([(2, 7), (2, 14)])
    z[12, 7] = np.nan
    with pytest.raises(PlanError, match="no path.*lethal or nodata cells separate them"):
        _planner(cost, z, 1.0, 1.0, 0.01, "vehicle").plan([(2, 0), (2, 14)])


def test_vehicle_never_takes_a_step_steeper_than_its_limit() -> None:
    cost = np.full((3, 10), np.inf, np.float32)
    cost[1] = 0.2
    z = np.zeros((3, 10), np.float32)
    z[:, 5:] = 0.6  # one 60 % step up
    # the slope limit separates them, and the message says so (issue 33 rule 6), not "lethal cells"
    with pytest.raises(PlanError, match=r"no path.*slopes steeper than the vehicle model drives \(50% either way"):
        _planner(cost, z, 1.0, 1.0, 0.01, "vehicle").plan([(1, 0), (1, 9)])
    assert math.isfinite(_planner(cost, z, 1.0, 1.0, 0.01, "tobler").plan([(1, 0), (1, 9)]).cost)


def test_fast_mode_runs_the_exact_search_with_a_note() -> None:
    cost = smooth_costmap((40, 40), 5, lethal_fraction=0.05)
    z = np.add.outer(np.arange(40.0), np.zeros(40)).astype(np.float32)
    fin = np.argwhere(np.isfinite(cost))
    a, b = tuple(fin[0]), tuple(fin[-1])
    p = _planner(cost, z, 1.0, 1.0, 0.01, "tobler")
    fast, exact = p.plan([a, b], mode="fast"), p.plan([a, b])
    assert fast.cost == exact.cost and fast.mode == "exact"
    assert any("fast mode has no slope model" in n for n in fast.notes)


def test_bad_terrain_arguments_are_one_line_errors(monkeypatch: pytest.MonkeyPatch) -> None:
    cost = np.full((5, 6), 0.2, np.float32)
    grid = PlanningGrid.from_array(cost, None, pixel_size_m=(1.0, 1.0))
    z = np.zeros((5, 6), np.float32)
    with pytest.raises(InputError, match="slope model"):
        Planner(grid, elevation=z)
    with pytest.raises(InputError, match="unknown slope model"):
        Planner(grid, elevation=z, slope_model="mule")
    with pytest.raises(InputError, match="resample"):
        Planner(grid, elevation=np.zeros((4, 6), np.float32), slope_model="tobler")
    with pytest.raises(PlanError, match="compiled planner kernel") as err:
        Planner(grid, elevation=z, slope_model="tobler", planner="fallback")
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("seed", [2, 4])
def test_a_star_stays_exact_where_steps_are_cheaper_than_flat_ground(seed: int) -> None:
    """A gentle 5 % descent towards the goal, where Tobler's multiplier is at its minimum (0.84):
    a heuristic not scaled by that minimum overestimates and A* returns a dearer route (these
    seeds catch it); scaled, the cost is the brute force's."""
    h, w = 14, 24
    cost = smooth_costmap((h, w), seed, lethal_fraction=0.1)
    cost[np.isfinite(cost)] = 0.05 + 0.1 * cost[np.isfinite(cost)]
    rng = np.random.default_rng(seed)
    noise = 0.02 * ndimage.gaussian_filter(rng.random((h, w)), 1.0)
    z = (-0.05 * np.arange(w)[None, :] * np.ones((h, 1)) + noise).astype(np.float32)
    fin = np.flatnonzero(np.isfinite(cost.ravel()))
    a = tuple(int(v) for v in np.unravel_index(fin[0], cost.shape))
    b = tuple(int(v) for v in np.unravel_index(fin[-1], cost.shape))
    bf = brute_force(cost, z, 1.0, 1.0, 0.0, "tobler", a, 8)
    assert _planner(cost, z, 1.0, 1.0, 0.0, "tobler").plan([a, b]).cost == pytest.approx(bf[b], rel=1e-12)
