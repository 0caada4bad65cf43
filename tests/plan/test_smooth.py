"""Line-of-sight smoothing (overseec_core.plan.smooth, ``overseec plan --smooth``).

The checks are independent of the implementation: segment costs against a dense numerical
integral, "touches no impassable cell" against an exact segment/cell-rectangle intersection test
and dense sampling, lengths against the Euclidean distance.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from overseec_core.cli import main
from overseec_core.errors import InputError
from overseec_core.plan import Planner, PlanningGrid
from overseec_core.plan.smooth import parse_tolerance, polyline_length_m, segment_costs, smooth_route, waypoint_indices
from overseec_core.plan.stage import plan_keeping_rules
from tests.plan.conftest import UTM_ORIGIN, smooth_costmap, write_costmap

BASE = 0.01
#: Non-square pixels everywhere: ground metres must not assume dx == dy.
PIXEL = (0.5, 0.8)
#: Float slack on "cost <= bound" (sums of a few thousand float64 terms).
REL = 1e-12


# ------------------------------------------------------------------------------------------------
# Independent references
# ------------------------------------------------------------------------------------------------


def dense_integral(cost: np.ndarray, p0, p1, pixel=PIXEL, base=BASE, n: int = 20000) -> float:
    """Midpoint-rule integral of (cell cost + base) along the segment between two centres."""
    t = (np.arange(n) + 0.5) / n
    y = p0[0] + 0.5 + t * (p1[0] - p0[0])
    x = p0[1] + 0.5 + t * (p1[1] - p0[1])
    c = cost[np.floor(y).astype(int), np.floor(x).astype(int)].astype(np.float64)
    length = math.hypot((p1[0] - p0[0]) * pixel[1], (p1[1] - p0[1]) * pixel[0])
    return float(((c + base) * (length / n)).sum())


def touches(p0, p1, r: int, c: int, eps: float = 1e-9) -> bool:
    """Does the closed segment between the centres of p0 and p1 meet the closed cell (r, c)?

    Liang-Barsky clipping against the cell grown by ``eps`` (so corner contact counts).
    """
    y0, x0 = p0[0] + 0.5, p0[1] + 0.5
    dy, dx = p1[0] - p0[0], p1[1] - p0[1]
    lo, hi = 0.0, 1.0
    for d, q0, a, b in ((dy, y0, r - eps, r + 1 + eps), (dx, x0, c - eps, c + 1 + eps)):
        if d == 0:
            if not a <= q0 <= b:
                return False
            continue
        t1, t2 = (a - q0) / d, (b - q0) / d
        lo, hi = max(lo, min(t1, t2)), min(hi, max(t1, t2))
    return lo <= hi


def segment_is_clear(cost: np.ndarray, p0, p1) -> bool:
    """Brute force: every cell of the bounding box the segment touches is passable, checked by
    the exact intersection test and by dense sampling (each sample +-eps in both axes)."""
    r_lo, r_hi = min(p0[0], p1[0]) - 1, max(p0[0], p1[0]) + 1
    c_lo, c_hi = min(p0[1], p1[1]) - 1, max(p0[1], p1[1]) + 1
    h, w = cost.shape
    for r in range(max(0, r_lo), min(h, r_hi + 1)):
        for c in range(max(0, c_lo), min(w, c_hi + 1)):
            if touches(p0, p1, r, c) and not np.isfinite(cost[r, c]):
                return False
    t = np.linspace(0.0, 1.0, 4001)
    y = p0[0] + 0.5 + t * (p1[0] - p0[0])
    x = p0[1] + 0.5 + t * (p1[1] - p0[1])
    for oy in (-1e-7, 1e-7):
        for ox in (-1e-7, 1e-7):
            rr = np.clip(np.floor(y + oy).astype(int), 0, h - 1)
            cc = np.clip(np.floor(x + ox).astype(int), 0, w - 1)
            if not np.isfinite(cost[rr, cc]).all():
                return False
    return True


def random_case(seed: int, shape=(70, 90)) -> tuple[PlanningGrid, object]:
    """A seeded costmap with lethal blobs and nodata, and an exact route across it with a via."""
    cost = smooth_costmap(shape, seed, lethal_fraction=0.15, nodata_fraction=0.03)
    for r, c in ((1, 1), (shape[0] // 2, shape[1] // 2), (shape[0] - 2, shape[1] - 2)):
        cost[r - 1 : r + 2, c - 1 : c + 2] = 0.4
    grid = PlanningGrid.from_array(cost, pixel_size_m=PIXEL)
    points = [(1, 1), (shape[0] // 2, shape[1] // 2), (shape[0] - 2, shape[1] - 2)]
    return grid, Planner(grid, BASE).plan(points)


def routable_cases(n: int):
    for seed in range(n * 3):
        try:
            yield random_case(seed)
        except Exception:
            continue


# ------------------------------------------------------------------------------------------------
# The segment integral
# ------------------------------------------------------------------------------------------------


def test_segment_cost_is_the_exact_cell_integral() -> None:
    """A row of three cells: half of the first, all of the second, half of the third; and
    random segments against a dense numerical integral (which converges to the same value)."""
    cost = np.array([[0.1, 0.5, 0.9]], dtype=np.float32)
    got, ok = segment_costs(cost, PIXEL, BASE, np.array([[0, 0]]), np.array([[0, 2]]))
    dx = PIXEL[0]
    want = 0.5 * dx * (0.1 + BASE) + dx * (0.5 + BASE) + 0.5 * dx * (0.9 + BASE)
    assert ok[0] and got[0] == pytest.approx(want, rel=1e-6)
    rng = np.random.default_rng(7)
    field = rng.random((40, 50)).astype(np.float32)
    ends = rng.integers(0, [40, 50], size=(30, 2))
    start = np.array([[17, 23]])
    got, ok = segment_costs(field, PIXEL, BASE, start, ends)
    assert ok.all()
    for k, e in enumerate(ends):
        assert got[k] == pytest.approx(dense_integral(field, start[0], e), rel=2e-3, abs=1e-9)


def test_grid_steps_cost_the_same_under_both_rules() -> None:
    """The cell integral of a step between neighbouring centres is the planner's mean rule, so
    the grid route's integral cost equals its planner cost."""
    for grid, res in routable_cases(3):
        sm = smooth_route(res, grid, BASE, 0.01)
        assert sm.grid_cost_integral == pytest.approx(res.cost, rel=1e-9)
        assert sm.grid_cost == res.cost


def test_corner_touch_is_refused() -> None:
    """Segments through a lattice corner need all four cells there passable, even those the
    segment crosses for a zero length."""
    cost = np.full((4, 5), 0.2, dtype=np.float32)
    # (0,0)->(2,2) passes the corner (1,1): cells (0,1) and (1,0) only touch it
    # (0,0)->(1,3) passes the corner (1,2): cells (1,1) and (0,2) only touch it
    # (3,0)->(1,2) and (1,2)->(3,0) (up-right, down-left) pass the corner (3,1): (2,0) and (3,1)
    for start, end, touched in (
        ((0, 0), (2, 2), (0, 1)),
        ((0, 0), (2, 2), (1, 0)),
        ((0, 0), (1, 3), (1, 1)),
        ((0, 0), (1, 3), (0, 2)),
        ((3, 0), (1, 2), (2, 0)),
        ((3, 0), (1, 2), (3, 1)),
        ((1, 2), (3, 0), (2, 0)),
        ((1, 2), (3, 0), (3, 1)),
    ):
        blocked = cost.copy()
        blocked[touched] = np.inf
        free = segment_costs(cost, PIXEL, BASE, np.array([start]), np.array([end]))[1][0]
        hit = segment_costs(blocked, PIXEL, BASE, np.array([start]), np.array([end]))[1][0]
        assert free and not hit, (start, end, touched)
        assert not segment_is_clear(blocked, start, end)  # the brute force agrees
    # a near miss is not a touch: (0,0)->(1,3) never meets (1,0) or (0,3)
    for cell in ((1, 0), (0, 3)):
        blocked = cost.copy()
        blocked[cell] = np.nan
        assert segment_costs(blocked, PIXEL, BASE, np.array([[0, 0]]), np.array([[1, 3]]))[1][0]


def test_smoothing_does_not_shortcut_through_a_corner_touch() -> None:
    """Open map, a single lethal cell that the straight start-goal line only touches at a corner:
    the smoothed route bends around it instead of grazing it."""
    cost = np.full((12, 12), 0.3, dtype=np.float32)
    cost[5, 6] = np.inf  # the diagonal (0,0)->(11,11) passes the corner (6,6) of this cell
    grid = PlanningGrid.from_array(cost, pixel_size_m=(1.0, 1.0))
    res = Planner(grid, BASE).plan([(0, 0), (11, 11)])
    sm = smooth_route(res, grid, BASE, 0.05)
    assert not segment_is_clear(cost, (0, 0), (11, 11))
    for a, b in zip(sm.vertices[:-1], sm.vertices[1:]):
        if np.abs(b - a).max() > 1:
            assert segment_is_clear(cost, tuple(a), tuple(b))


# ------------------------------------------------------------------------------------------------
# Smoothing guarantees
# ------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("tol", [0.0, 0.01, 0.05])
def test_smoothed_cost_within_tolerance(tol: float) -> None:
    n = 0
    for grid, res in routable_cases(6):
        sm = smooth_route(res, grid, BASE, tol)
        assert sm.cost <= sm.grid_cost_integral * (1 + tol) * (1 + REL)
        # the reported cost is the integral of the drawn line (independent reference)
        ref = sum(dense_integral(grid.cost, a, b) for a, b in zip(sm.vertices[:-1], sm.vertices[1:]))
        assert sm.cost == pytest.approx(ref, rel=2e-3)
        assert sm.length_m == pytest.approx(polyline_length_m(sm.vertices, PIXEL))
        assert len(sm.vertices) < len(res.pixels)
        n += 1
    assert n >= 4


def test_tolerance_zero_never_increases_cost() -> None:
    n = 0
    for grid, res in routable_cases(8):
        sm = smooth_route(res, grid, BASE, 0.0)
        assert sm.cost <= sm.grid_cost_integral * (1 + REL)
        marks = waypoint_indices(res.pixels, res.waypoints)
        for leg, (a, b) in enumerate(zip(marks[:-1], marks[1:])):  # and leg by leg
            grid_leg = smooth_route(_sub(res, a, b), grid, BASE, 0.0).grid_cost_integral
            assert sm.leg_costs[leg] <= grid_leg * (1 + REL)
        n += 1
    assert n >= 5


def _sub(res, a: int, b: int):
    """The part of a route between pixel indices a and b, as a one-leg PathResult."""
    from dataclasses import replace

    px = res.pixels[a : b + 1]
    return replace(res, pixels=px, waypoints=(tuple(px[0]), tuple(px[-1])))


def test_no_segment_touches_an_impassable_cell() -> None:
    n = 0
    for grid, res in routable_cases(6):
        sm = smooth_route(res, grid, BASE, 0.05)
        steps = set(map(tuple, np.concatenate([res.pixels[:-1], res.pixels[1:]], axis=1).tolist()))
        for a, b in zip(sm.vertices[:-1], sm.vertices[1:]):
            if (*a, *b) in steps:
                continue  # the planner's own step, kept as it is
            assert segment_is_clear(grid.cost, tuple(a), tuple(b)), (a, b)
        n += 1
    assert n >= 4


def test_open_staircase_becomes_one_straight_segment() -> None:
    cost = np.full((100, 200), 0.3, dtype=np.float32)
    grid = PlanningGrid.from_array(cost, pixel_size_m=PIXEL)
    res = Planner(grid, BASE).plan([(5, 5), (90, 190)])
    assert len(res.pixels) > 100
    sm = smooth_route(res, grid, BASE)
    euclid = math.hypot(85 * PIXEL[1], 185 * PIXEL[0])
    assert len(sm.vertices) == 2
    assert abs(sm.length_m - euclid) <= 1e-3 * euclid
    assert sm.cost == pytest.approx((0.3 + BASE) * euclid, rel=1e-6)
    assert sm.cost < res.cost and sm.grid_length_m > sm.length_m


def test_via_points_stay_vertices() -> None:
    cost = np.full((80, 120), 0.3, dtype=np.float32)
    grid = PlanningGrid.from_array(cost, pixel_size_m=PIXEL)
    points = [(3, 3), (70, 20), (10, 100), (3, 3)]  # back to the start: a revisited pixel
    res = Planner(grid, BASE).plan(points)
    sm = smooth_route(res, grid, BASE)
    verts = [tuple(v) for v in sm.vertices.tolist()]
    assert verts == points  # open map: one segment per leg, every via a vertex
    for grid, res in routable_cases(4):
        sm = smooth_route(res, grid, BASE, 0.05)
        marks = waypoint_indices(res.pixels, res.waypoints)
        assert set(marks) <= set(sm.indices.tolist())
        assert [tuple(v) for v in sm.vertices[np.searchsorted(sm.indices, marks)].tolist()] == [
            tuple(w) for w in res.waypoints
        ]


def test_route_through_a_keep_out_zone_keeps_its_grid_steps_there() -> None:
    """A start inside a keep-out zone (a broken distance rule): shortcuts never enter the zone,
    the steps inside it stay, priced at the top of the scale like the planner reports them."""
    cost = np.full((40, 60), 0.2, dtype=np.float32)
    keep = np.zeros(cost.shape, bool)
    keep[0:10, 0:10] = True
    cost[keep] = np.inf
    grid = PlanningGrid(cost=cost, grid=None, pixel_size_m=PIXEL, keep_out=keep)
    res, _planner = plan_keeping_rules(grid, [(2, 2), (35, 55)], base_cost_per_m=BASE)
    sm = smooth_route(res, grid, BASE, 0.01)
    assert sm.grid_cost_integral == pytest.approx(res.cost, rel=1e-9)
    assert sm.cost <= sm.grid_cost_integral * 1.01 * (1 + REL)
    assert len(sm.vertices) < len(res.pixels)
    for a, b in zip(sm.vertices[:-1], sm.vertices[1:]):
        if np.abs(b - a).max() > 1:
            assert segment_is_clear(cost, tuple(a), tuple(b))


def test_a_broken_rule_route_is_integrated_at_the_zone_cells_own_costs(tmp_path: Path) -> None:
    """A loaded costmap whose keep-out zone cuts the map (a broken rule) and keeps cheap own costs
    under the zone (0.05..0.3, not the top of the scale): the grid route's cell integral equals
    the cost the planner reports for it (zone cells at their own cost), leg by leg, and the
    smoothed route stays within the tolerance of that."""
    from rasterio.transform import from_origin

    from overseec_core.plan import load_costmap
    from tests.plan.test_keep_out import write_lethal

    rng = np.random.default_rng(5)
    cost = rng.uniform(0.1, 0.6, (50, 70)).astype(np.float32)
    flags = np.zeros(cost.shape, np.uint8)
    flags[:, 30:36] = 2
    cost[:, 30:36] = rng.uniform(0.05, 0.3, (50, 6)).astype(np.float32)
    costmap = write_costmap(tmp_path / "costmap.tif", cost, transform=from_origin(*UTM_ORIGIN, *PIXEL))
    write_lethal(tmp_path / "lethal.tif", flags, costmap)
    grid = load_costmap(costmap)
    assert grid.pixel_size_m == pytest.approx(PIXEL) and grid.zone_costs is not None
    # leg 1 must cross the zone, leg 2 stays on its side
    res, _planner = plan_keeping_rules(grid, [(5, 3), (45, 66), (5, 60)], base_cost_per_m=BASE)
    assert len(res.notes) == 1 and "cannot be met between start and via point 1" in res.notes[0]
    assert grid.keep_out[res.pixels[:, 0], res.pixels[:, 1]].any()
    sm = smooth_route(res, grid, BASE, 0.01)
    assert sm.grid_cost == res.cost
    assert sm.grid_cost_integral == pytest.approx(res.cost, rel=1e-9)
    assert sm.cost <= sm.grid_cost_integral * 1.01 * (1 + REL)
    assert sm.cost == pytest.approx(math.fsum(sm.leg_costs), rel=1e-12)
    for got, planned in zip(sm.leg_costs, res.leg_costs):
        assert got <= planned * 1.01 * (1 + 1e-9)
    for a, b in zip(sm.vertices[:-1], sm.vertices[1:]):
        if np.abs(b - a).max() > 1:  # shortcuts never touch the zone
            assert segment_is_clear(grid.cost, tuple(a), tuple(b))


def test_parse_tolerance() -> None:
    assert parse_tolerance("0.02") == 0.02
    assert parse_tolerance("2%") == pytest.approx(0.02)
    assert parse_tolerance("0") == 0.0
    for bad in ("5", "-0.1", "nan", "abc", "150%"):
        with pytest.raises(InputError):
            parse_tolerance(bad)


# ------------------------------------------------------------------------------------------------
# CLI
# ------------------------------------------------------------------------------------------------


def test_cli_smooth_writes_both_routes(tmp_path: Path, capsys) -> None:
    cost = smooth_costmap((60, 80), seed=3, lethal_fraction=0.05)
    cost[0:3, 0:3] = cost[-3:, -3:] = 0.5
    costmap = write_costmap(tmp_path / "costmap.tif", cost)

    def pt(row: int, col: int) -> list[str]:
        return [str(UTM_ORIGIN[0] + (col + 0.5) * 0.5), str(UTM_ORIGIN[1] - (row + 0.5) * 0.5)]

    for sub in ("out", "plain", "pct"):
        (tmp_path / sub).mkdir()
    out = tmp_path / "out" / "route.geojson"
    rc = main(
        [
            "--quiet",
            "plan",
            str(costmap),
            "--start",
            *pt(1, 1),
            "--goal",
            *pt(58, 78),
            "--out",
            str(out),
            "--smooth",
            "--native-crs",
            "--pixels",
        ]
    )
    assert rc == 0
    printed = capsys.readouterr().out
    assert "path: cost" in printed and "smoothed: cost" in printed and "vs grid" in printed
    (feature,) = json.loads(out.read_text())["features"]
    props = feature["properties"]
    assert props["route"] == "smoothed" and props["smoothing"]["tolerance"] == 0.01
    coords = feature["geometry"]["coordinates"]
    assert len(coords) == props["n_vertices"] < props["grid_route"]["n_vertices"] == props["n_pixels"]
    assert props["length_m"] < props["grid_route"]["length_m"]
    assert props["total_cost"] <= props["grid_route"]["cost_integral"] * 1.01 * (1 + REL)
    assert props["grid_route"]["cost"] == pytest.approx(props["grid_route"]["cost_integral"], rel=1e-9)
    manifest = json.loads((out.parent / "manifest.json").read_text())
    assert manifest["plan"]["smoothing"]["smoothed"]["n_vertices"] == props["n_vertices"]
    assert manifest["parameters"]["plan"]["smooth"] == 0.01
    # the pixel CSV keeps the grid route; the GeoPackage draws the smoothed line
    assert len(out.with_name("route.pixels.csv").read_text().splitlines()) == props["n_pixels"] + 1
    import fiona

    with fiona.open(out.with_name("route.native.gpkg"), layer="path") as src:
        (rec,) = list(src)
        assert len(rec["geometry"]["coordinates"]) == props["n_vertices"]
        assert json.loads(rec["properties"]["grid_route"])["n_vertices"] == props["n_pixels"]
    # a percentage, and without --smooth nothing changes
    plain = tmp_path / "plain" / "route.geojson"
    assert (
        main(["--quiet", "plan", str(costmap), "--start", *pt(1, 1), "--goal", *pt(58, 78), "--out", str(plain)]) == 0
    )
    (f2,) = json.loads(plain.read_text())["features"]
    assert "grid_route" not in f2["properties"]
    assert len(f2["geometry"]["coordinates"]) == props["n_pixels"]
    assert "smoothed" not in capsys.readouterr().out
    pct = tmp_path / "pct" / "route.geojson"
    assert (
        main(
            [
                "--quiet",
                "plan",
                str(costmap),
                "--start",
                *pt(1, 1),
                "--goal",
                *pt(58, 78),
                "--out",
                str(pct),
                "--smooth",
                "5%",
            ]
        )
        == 0
    )
    (f3,) = json.loads(pct.read_text())["features"]
    assert f3["properties"]["smoothing"]["tolerance"] == pytest.approx(0.05)


def test_cli_smooth_refuses_a_bare_large_number(tmp_path: Path, capsys) -> None:
    with pytest.raises(SystemExit) as exc:
        main(
            [
                "--quiet",
                "plan",
                "x.tif",
                "--start",
                "0",
                "0",
                "--goal",
                "1",
                "1",
                "--out",
                str(tmp_path / "r.geojson"),
                "--smooth",
                "5",
            ]
        )
    assert exc.value.code == 2
    assert "0.01 = 1 %" in capsys.readouterr().err


@pytest.mark.slow
def test_bench_runs_at_a_small_size() -> None:
    """bench/bench_smooth.py runs and prints both routes (figures are not checked)."""
    import subprocess
    import sys

    repo = Path(__file__).resolve().parents[2]
    done = subprocess.run(
        [sys.executable, str(repo / "bench" / "bench_smooth.py"), "--sizes", "300", "--vias", "1"],
        capture_output=True,
        text=True,
        cwd=repo,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    rows = [line.split() for line in done.stdout.splitlines() if line.strip().startswith(("0.01", "0 "))]
    assert len(rows) == 2 and all(len(r) == 11 for r in rows)
