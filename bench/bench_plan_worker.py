"""Benchmark: re-plan latency through the planner worker, as the QGIS map tool sees it.

A seeded 4000 x 4000 costmap GeoTIFF (bench_plan.make_costmap: smooth field, cheap roads, lethal
blobs; UTM 33N, 0.5 m) is written to a temporary folder; one `overseec plan-server` is started
through the plugin's own client (overseec_qgis.planclient, which is what QGIS uses), the costmap
is loaded, and a user's drag is replayed: a via point (or the goal) moves in small steps and each
position is planned again (start, via, goal; fast mode). Prints the round trip (request written
to answer parsed) and the worker's own planning time per re-plan, median and p95, and the same
queries planned in this process by the core Planner for comparison (with and without fast mode's
tight lower bound, which the worker skips).

    .venv/bin/python bench/bench_plan_worker.py                  # 4000², 40 steps per drag
    .venv/bin/python bench/bench_plan_worker.py --size 1000      # a quick check
    .venv/bin/python bench/bench_plan_worker.py --neighbours 16  # the dock's Steps: knight moves

Never asserts timings.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
if str(REPO) not in sys.path:
    sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "bench"))

from bench_plan import make_costmap  # noqa: E402

ORIGIN = (500000.0, 4000000.0)
PIXEL = 0.5


def write_costmap(path: Path, cost: np.ndarray) -> Path:
    """Write ``cost`` as a tiled float32 GeoTIFF (UTM 33N, NaN nodata) for the worker to load;
    returns ``path``."""
    import rasterio
    from rasterio.transform import from_origin

    profile = dict(
        driver="GTiff",
        width=cost.shape[1],
        height=cost.shape[0],
        count=1,
        dtype="float32",
        crs="EPSG:32633",
        transform=from_origin(*ORIGIN, PIXEL, PIXEL),
        nodata=float("nan"),
        tiled=True,
        blockxsize=512,
        blockysize=512,
    )
    with rasterio.open(path, "w", **profile) as ds:
        ds.write(cost, 1)
    return path


def world(row: int, col: int) -> tuple[float, float]:
    """Map coordinates (x, y) of the centre of pixel (row, col) of the bench costmap."""
    return ORIGIN[0] + (col + 0.5) * PIXEL, ORIGIN[1] - (row + 0.5) * PIXEL


def passable_near(cost: np.ndarray, row: int, col: int) -> tuple[int, int]:
    """The passable cell nearest (row, col) within a growing window (a user drops points on ground)."""
    h, w = cost.shape
    for r in range(0, max(h, w)):
        r0, r1, c0, c1 = max(0, row - r), min(h, row + r + 1), max(0, col - r), min(w, col + r + 1)
        ok = np.argwhere(np.isfinite(cost[r0:r1, c0:c1]))
        if len(ok):
            dr, dc = ok[np.argmin(np.abs(ok[:, 0] + r0 - row) + np.abs(ok[:, 1] + c0 - col))]
            return int(dr + r0), int(dc + c0)
    raise SystemExit("no passable cell")


def drag_path(cost: np.ndarray, a: tuple[int, int], b: tuple[int, int], steps: int) -> list[tuple[int, int]]:
    """Positions of a point dragged from a to b in equal steps (each snapped onto passable ground)."""
    out = []
    for t in np.linspace(0.0, 1.0, steps):
        out.append(passable_near(cost, round(a[0] + t * (b[0] - a[0])), round(a[1] + t * (b[1] - a[1]))))
    return out


def summary(ms: list[float]) -> str:
    """Median, 95th percentile and maximum of latencies in ms, as one aligned line."""
    q = np.percentile(ms, [50, 95])
    return f"median {q[0]:7.1f} ms   p95 {q[1]:7.1f} ms   max {max(ms):7.1f} ms"


def main() -> int:
    """Time the re-plans of two drags (a via, the goal) through an `overseec plan-server` worker
    and in process with the core Planner, and print the latencies."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=4000)
    ap.add_argument("--steps", type=int, default=40, help="re-plans per drag")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--neighbours", type=int, choices=(8, 16), default=8, help="the planner's steps")
    args = ap.parse_args()
    steps = args.neighbours

    from overseec_core.plan import Planner, load_costmap
    from overseec_qgis.planclient import PlanClient

    n = args.size
    cost = make_costmap(n, args.seed)
    with tempfile.TemporaryDirectory(prefix="overseec-bench-worker-") as tmp:
        path = write_costmap(Path(tmp) / "costmap.tif", cost)
        start = passable_near(cost, n // 20, n // 13)
        goal = passable_near(cost, n - n // 12, n - n // 10)
        drags = {
            "drag a via (2 legs)": [
                [start, via, goal]
                for via in drag_path(cost, (n // 3, 2 * n // 3), (n // 3 + n // 10, 2 * n // 3 - n // 8), args.steps)
            ],
            "drag the goal (1 leg)": [
                [start, g] for g in drag_path(cost, goal, (goal[0] - n // 8, goal[1] - n // 10), args.steps)
            ],
        }
        client = PlanClient([sys.executable, "-m", "overseec_core.cli", "plan-server"])
        try:
            t0 = time.perf_counter()
            client.ping()
            t_start = time.perf_counter() - t0
            t0 = time.perf_counter()
            client.load(path)
            t_load = time.perf_counter() - t0
            print(
                f"costmap {n} x {n} (seed {args.seed}, {steps} neighbours); "
                f"worker start {t_start:.2f} s, load {t_load:.2f} s"
            )
            print(f"{'':24}{'through the worker (round trip, wall)':50}{'worker planning: wall / CPU'}")
            results = {}
            for name, queries in drags.items():
                # warm: the first plan after the load (and the planner's rebuild for 16 steps)
                client.plan(path, [world(*p) for p in queries[0]], "fast", neighbours=steps)
                trip, inside, cpu, costs = [], [], [], []
                for pts in queries:
                    reply = client.plan(path, [world(*p) for p in pts], "fast", neighbours=steps)
                    trip.append(reply.round_trip_ms)
                    inside.append(reply.worker_ms)
                    cpu.append(reply.worker_cpu_ms)
                    costs.append(reply.cost)
                results[name] = costs
                print(
                    f"{name:24}{summary(trip):50}  median {statistics.median(inside):.1f} / "
                    f"{statistics.median(cpu):.1f} ms, p95 {np.percentile(inside, 95):.1f} / "
                    f"{np.percentile(cpu, 95):.1f} ms"
                )
        finally:
            client.close()

        grid = load_costmap(path)
        print("in process (core Planner, fast mode), wall / CPU:")
        variants = (
            ("as the worker plans", dict(tight_bound=False, coarse_trees=4)),
            ("no coarse trees", dict(tight_bound=False)),
            ("default (overseec plan)", {}),
        )
        for label, kwargs in variants:
            planner = Planner(grid, neighbours=steps, **kwargs)
            planner.prepare_fast()
            for name, queries in drags.items():
                planner.plan(queries[0], mode="fast")
                ms, cpu, costs = [], [], []
                for pts in queries:
                    t0, c0 = time.perf_counter(), time.thread_time()
                    res = planner.plan(pts, mode="fast")
                    ms.append(1000 * (time.perf_counter() - t0))
                    cpu.append(1000 * (time.thread_time() - c0))
                    costs.append(res.cost)
                rel = max(abs(a / b - 1) for a, b in zip(costs, results[name]))
                print(
                    f"  {label + ': ' + name:48}{summary(ms)}  CPU median {statistics.median(cpu):.1f} ms"
                    f"  (costs within {rel:.1e} of the worker's)"
                )
    return 0


if __name__ == "__main__":
    sys.exit(main())
