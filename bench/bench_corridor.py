"""Benchmark: the least-cost corridor against single exact plans on the same costmap.

A corridor is two whole-grid searches (from the start, from the goal) plus combining the two
float64 fields into the ratio and the mask; an exact plan is one A* search that stops at the goal.
The figure that matters: corridor time / (2 x one exact plan) -- how much dearer the corridor is
than planning the route there and back. Same generated costmap as ``bench_plan.py`` (smooth
field, roads, lethal blobs; seeded), corner to corner, 0.5 m pixels, base cost 0.01, one
process, the planner's buffers reused (as ``overseec corridor`` does: one Planner).

    .venv/bin/python bench/bench_corridor.py                 # 4000 x 4000
    .venv/bin/python bench/bench_corridor.py --sizes 1000    # a quick check

Prints wall and CPU seconds (best of --repeat) and the ratio; never asserts timings.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
if str(REPO) not in sys.path:
    sys.path.insert(0, str(REPO))

from bench.bench_plan import BASE, PIXEL, make_costmap  # noqa: E402


def timed(call) -> tuple[float, float, object]:
    """(wall s, CPU s, result) of one call."""
    w0, c0 = time.perf_counter(), time.process_time()
    out = call()
    return time.perf_counter() - w0, time.process_time() - c0, out


def best(call, repeat: int) -> tuple[float, float, object]:
    """The fastest of ``repeat`` runs (wall), with its CPU time and result."""
    runs = [timed(call) for _ in range(repeat)]
    return min(runs, key=lambda r: r[0])


def bench(size: int, repeat: int, seed: int) -> dict:
    """Time an exact plan and a corridor corner to corner on a size x size costmap."""
    from overseec_core.plan import Planner, PlanningGrid
    from overseec_core.plan.corridor import corridor

    cost = make_costmap(size, seed)
    planner = Planner(PlanningGrid(cost=cost, grid=None, pixel_size_m=PIXEL), BASE)
    start, goal = (0, 0), (size - 1, size - 1)
    pw, pc, route = best(lambda: planner.plan([start, goal], mode="exact"), repeat)
    cw, cc, c = best(lambda: corridor(planner, start, goal, 0.1), repeat)
    assert abs(c.optimum - route.cost) <= 1e-9 * route.cost  # the same optimum
    return {
        "size": size,
        "plan_wall": pw,
        "plan_cpu": pc,
        "corridor_wall": cw,
        "corridor_cpu": cc,
        "ratio_wall": cw / (2 * pw),
        "ratio_cpu": cc / (2 * pc),
        "within_10pct": c.cells_within,
        "backend": planner.backend.name,
    }


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print one line per size."""
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="4000", help="comma-separated sides (default 4000)")
    ap.add_argument("--repeat", type=int, default=2, help="runs per measurement, best kept (default 2)")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    print("side   exact plan wall/cpu s   corridor wall/cpu s   corridor / 2 plans (wall, cpu)   cells within 10 %")
    for size in (int(s) for s in args.sizes.split(",")):
        r = bench(size, args.repeat, args.seed)
        print(
            f"{r['size']:>5}  {r['plan_wall']:8.2f} / {r['plan_cpu']:6.2f}      "
            f"{r['corridor_wall']:8.2f} / {r['corridor_cpu']:6.2f}    "
            f"{r['ratio_wall']:6.2f}x, {r['ratio_cpu']:6.2f}x                {r['within_10pct']}   ({r['backend']})"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
