"""Benchmark: time ``plan --smooth`` adds to an exact plan, and what it changes in the route.

Corner-to-corner exact queries on bench_plan.py's generated costmaps (smooth field + cheap roads
+ lethal blobs, seeded, 0.5 m pixels), optionally with via points; then line-of-sight smoothing
(overseec_core.plan.smooth) of the route. Prints the plan time, the smoothing time, their ratio
(the target is <= 10 %), and vertices / length / cost of the grid and the smoothed route (both
costs under the cell-integral rule, and the grid route's planner cost).

    .venv/bin/python bench/bench_smooth.py                    # 10000 x 10000 (the full run)
    .venv/bin/python bench/bench_smooth.py --sizes 2000,4000  # quicker

Never asserts timings.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
for p in (REPO, REPO / "bench"):
    if str(p) not in sys.path:
        sys.path.insert(0, str(p))

from bench_plan import BASE, PIXEL, make_costmap  # noqa: E402


def nearest_passable(cost: np.ndarray, r: int, c: int) -> tuple[int, int]:
    """The passable cell nearest (r, c) within a growing square (a via point on open ground)."""
    for rad in range(0, max(cost.shape)):
        win = cost[max(0, r - rad) : r + rad + 1, max(0, c - rad) : c + rad + 1]
        hit = np.argwhere(np.isfinite(win))
        if len(hit):
            rr, cc = hit[0]
            return int(max(0, r - rad) + rr), int(max(0, c - rad) + cc)
    raise SystemExit("no passable cell")


def run_size(size: int, seed: int, tolerances: list[float], vias: int, window: int) -> None:
    """Generate, plan exact, smooth at each tolerance, print one row per tolerance."""
    from overseec_core.plan import Planner, PlanningGrid
    from overseec_core.plan.smooth import smooth_route

    t0 = time.perf_counter()
    cost = make_costmap(size, seed)
    gen_s = time.perf_counter() - t0
    grid = PlanningGrid(cost=cost, grid=None, pixel_size_m=PIXEL)
    points = [(0, 0)]
    for k in range(1, vias + 1):  # via points along the anti-diagonal: forces sharp turns
        f = k / (vias + 1)
        points.append(nearest_passable(cost, int(f * (size - 1)), int((1 - f) * (size - 1))))
    points.append((size - 1, size - 1))
    planner = Planner(grid, BASE)
    t0 = time.perf_counter()
    try:
        res = planner.plan(points, mode="exact")
    except Exception as exc:
        print(f"\n== {size} x {size}: no plan ({exc})")
        return
    plan_s = time.perf_counter() - t0
    print(
        f"\n== {size} x {size} ({size * size / 1e6:.0f} Mpx, {np.isinf(cost).mean():.1%} lethal, "
        f"generated in {gen_s:.1f} s); {len(points) - 2} via point(s); exact plan {plan_s:.2f} s, "
        f"{len(res.pixels)} pixels, {res.length_m:.1f} m, planner cost {res.cost:.6f}"
    )
    print(
        f"{'tol':>6}{'plan s':>9}{'smooth s':>10}{'ratio':>8}{'grid vtx':>10}{'smooth vtx':>11}"
        f"{'grid m':>11}{'smooth m':>11}{'grid cost':>13}{'smooth cost':>13}{'change':>9}"
    )
    for tol in tolerances:
        t0 = time.perf_counter()
        sm = smooth_route(res, grid, BASE, tol, window=window)
        smooth_s = time.perf_counter() - t0
        print(
            f"{tol:>6.3g}{plan_s:>9.2f}{smooth_s:>10.3f}{smooth_s / plan_s:>8.1%}"
            f"{sm.grid_vertices:>10d}{len(sm.vertices):>11d}{sm.grid_length_m:>11.1f}"
            f"{sm.length_m:>11.1f}{sm.grid_cost_integral:>13.4f}{sm.cost:>13.4f}"
            f"{sm.cost_change:>+9.3%}"
        )


def main(argv: list[str] | None = None) -> int:
    """Command line: for each size, plan corner to corner exactly, smooth at each tolerance and
    print the time smoothing adds and how the route changes."""
    from overseec_core.plan.smooth import DEFAULT_TOLERANCE, WINDOW

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="10000", help="comma-separated sides (default 10000)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument(
        "--tolerances",
        default=f"{DEFAULT_TOLERANCE},0",
        help=f"comma-separated cost tolerances (default {DEFAULT_TOLERANCE},0)",
    )
    ap.add_argument("--vias", type=int, default=0, help="via points along the anti-diagonal")
    ap.add_argument("--window", type=int, default=WINDOW, help=f"look-ahead window (default {WINDOW})")
    args = ap.parse_args(argv)
    tols = [float(t) for t in args.tolerances.split(",") if t.strip()]
    print(
        f"bench_smooth: corner-to-corner exact plan + smoothing, base {BASE}/m, pixel "
        f"{PIXEL[0]} x {PIXEL[1]} m, seed {args.seed}, window {args.window}, {os.cpu_count()} CPUs, "
        f"python {sys.version.split()[0]}"
    )
    for size in (int(s) for s in args.sizes.split(",")):
        run_size(size, args.seed, tols, args.vias, args.window)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
