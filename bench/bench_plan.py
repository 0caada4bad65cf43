"""Benchmark: overseec's planner vs dijkstra3d and scikit-image MCP_Geometric.

Corner-to-corner queries on generated costmaps (smooth field + cheap roads + lethal blobs,
seeded). Every tool runs in a fresh subprocess so its peak RSS is its own; each subprocess loads
the same costmap from a .npy file, and reports wall and CPU time of the query (CPU time is the
fairer figure on a shared machine), of a repeated query and of its setup, peak
RSS (and its growth over the RSS right after loading the costmap and importing), and the cost of the
path it found priced with overseec's step rule (mean of the two cells' costs + base, times the step
length) -- so the costs are comparable even though dijkstra3d optimises a slightly different rule
(destination cell x step length).

    .venv/bin/python bench/bench_plan.py                 # 4000 and 10000 (the full run)
    .venv/bin/python bench/bench_plan.py --sizes 300     # a quick check

Prints a table; never asserts timings. Needs requirements-bench.txt (dijkstra3d, psutil).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
if str(REPO) not in sys.path:
    sys.path.insert(0, str(REPO))

BASE = 0.01
PIXEL = (0.5, 0.5)  # dx, dy metres
TOOLS = ("overseec-exact", "overseec-fast", "dijkstra3d", "mcp")


def make_costmap(size: int, seed: int = 0) -> np.ndarray:
    """A size x size float32 costmap in [0, 1]: smooth field, cheap roads, lethal blobs (inf)."""
    from scipy import ndimage
    from skimage.draw import line

    rng = np.random.default_rng(seed)
    coarse = max(8, size // 64)
    zoom = size / coarse

    def smooth() -> np.ndarray:
        f = ndimage.zoom(
            rng.random((coarse, coarse)).astype(np.float32), zoom, order=1, grid_mode=True, mode="nearest"
        )[:size, :size]
        return f

    field = smooth()
    lo, hi = float(field.min()), float(field.max())
    cost = (0.3 + 0.7 * (field - lo) / max(hi - lo, 1e-6)).astype(np.float32)
    blobs = smooth()
    lethal = blobs > np.quantile(blobs[::7, ::7], 0.92)
    del blobs, field
    roads = np.zeros((size, size), dtype=bool)
    n_roads = max(4, size // 250)
    for _ in range(n_roads):
        pts = rng.integers(0, size, (4, 2))
        for (r0, c0), (r1, c1) in zip(pts[:-1], pts[1:]):
            rr, cc = line(int(r0), int(c0), int(r1), int(c1))
            roads[rr, cc] = True
    roads = ndimage.binary_dilation(roads, iterations=1)
    cost[lethal] = np.inf
    cost[roads] = 0.02  # roads cross lethal blobs (bridges)
    del roads, lethal
    corner = max(3, size // 100)
    for r, c in ((0, 0), (size - 1, size - 1)):
        cost[max(0, r - corner) : r + corner + 1, max(0, c - corner) : c + corner + 1] = 0.5
    labels, _n = ndimage.label(np.isfinite(cost), structure=np.ones((3, 3)))
    if labels[0, 0] != labels[-1, -1]:  # corners cut off: a track through a random midpoint
        mid = rng.integers(size // 4, 3 * size // 4, 2)
        for (r0, c0), (r1, c1) in (((0, 0), mid), (mid, (size - 1, size - 1))):
            rr, cc = line(int(r0), int(c0), int(r1), int(c1))
            cost[rr, cc] = np.where(np.isfinite(cost[rr, cc]), cost[rr, cc], np.float32(0.6))
    return cost


def price(cost: np.ndarray, pixels: np.ndarray) -> float:
    from overseec_core.plan import PlanningGrid, cumulative_path_cost

    g = PlanningGrid(cost=cost, grid=None, pixel_size_m=PIXEL)
    return float(cumulative_path_cost(g, pixels, BASE)[-1])


def peak_rss_mb() -> float:
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def worker(tool: str, npy: str) -> dict:
    """Runs in a fresh process: load, run one tool, report."""
    import psutil

    if tool.startswith("overseec"):  # import first: the RSS baseline includes each tool's imports
        import overseec_core.plan  # noqa: F401
    elif tool == "dijkstra3d":
        import dijkstra3d  # noqa: F401
    elif tool == "mcp":
        import skimage.graph  # noqa: F401
    cost = np.load(npy)
    h, w = cost.shape
    start, goal = (0, 0), (h - 1, w - 1)
    rss_loaded = psutil.Process().memory_info().rss / 2**20
    out: dict = {"tool": tool, "rss_after_load_mb": rss_loaded}
    if tool.startswith("overseec"):
        from overseec_core.plan import Planner, PlanningGrid

        mode = tool.split("-")[1]
        t0 = time.perf_counter()
        grid = PlanningGrid(cost=cost, grid=None, pixel_size_m=PIXEL)
        planner = Planner(grid, BASE)
        if mode == "fast":
            planner.prepare_fast()
        out["setup_s"] = time.perf_counter() - t0
        t0, c0 = time.perf_counter(), time.process_time()
        res = planner.plan([start, goal], mode=mode)
        out["query_s"], out["query_cpu_s"] = time.perf_counter() - t0, time.process_time() - c0
        out["cost"] = res.cost
        out["bound"] = res.bound
        out["mode_used"] = res.mode
        out["expanded"] = res.expanded
        if mode == "fast":  # the interactive figure: a repeated query on the loaded costmap
            t0 = time.perf_counter()
            planner.plan([goal, start], mode=mode)
            out["repeat_query_s"] = time.perf_counter() - t0
        else:
            t0 = time.perf_counter()
            planner.plan([start, goal], mode=mode)
            out["repeat_query_s"] = time.perf_counter() - t0
        mem = planner.memory_bytes()
        out["planner_bytes_per_pixel"] = mem["per_pixel"]
    elif tool == "dijkstra3d":
        import dijkstra3d

        field = cost + np.float32(BASE)  # inf stays inf: impassable
        t0, c0 = time.perf_counter(), time.process_time()
        path = dijkstra3d.dijkstra(field, start, goal, connectivity=8, anisotropy=(PIXEL[1], PIXEL[0]))
        out["query_s"], out["query_cpu_s"] = time.perf_counter() - t0, time.process_time() - c0
        out["cost"] = price(cost, np.asarray(path)[:, :2])
    elif tool == "mcp":
        from skimage.graph import MCP_Geometric

        t0 = time.perf_counter()
        costs = cost.astype(np.float64) + BASE
        mcp = MCP_Geometric(costs, sampling=(PIXEL[1], PIXEL[0]))
        out["setup_s"] = time.perf_counter() - t0
        t0, c0 = time.perf_counter(), time.process_time()
        cum, _tb = mcp.find_costs([start], [goal])
        out["query_s"], out["query_cpu_s"] = time.perf_counter() - t0, time.process_time() - c0
        out["cost"] = float(cum[goal])
    else:
        raise SystemExit(f"unknown tool {tool}")
    out["peak_rss_mb"] = peak_rss_mb()
    return out


def run_tool(tool: str, npy: str, timeout: float) -> dict:
    cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", tool, "--npy", npy]
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"tool": tool, "error": f"timed out after {timeout:.0f} s"}
    if proc.returncode != 0:
        return {"tool": tool, "error": (proc.stderr.strip().splitlines() or ["failed"])[-1]}
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    res["process_s"] = time.perf_counter() - t0
    return res


def fmt(v, spec: str) -> str:
    """Format a figure, or right-align a dash in the same width when there is none."""
    return format(v, spec) if v is not None else "-".rjust(int(spec.split(".")[0] or 0))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="4000,10000", help="comma-separated sides (default 4000,10000)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--tools", default=",".join(TOOLS), help=f"subset of {','.join(TOOLS)}")
    ap.add_argument("--timeout", type=float, default=1800.0, help="per-tool seconds")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--npy", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        print(json.dumps(worker(args.worker, args.npy)))
        return 0
    tools = [t.strip() for t in args.tools.split(",") if t.strip()]
    print(
        f"bench_plan: corner-to-corner, base {BASE}/m, pixel {PIXEL[0]} x {PIXEL[1]} m, seed {args.seed}, "
        f"{os.cpu_count()} CPUs, python {sys.version.split()[0]}"
    )
    for size in (int(s) for s in args.sizes.split(",")):
        with tempfile.TemporaryDirectory(prefix="bench_plan_") as tmp:
            t0 = time.perf_counter()
            cost = make_costmap(size, args.seed)
            npy = os.path.join(tmp, "cost.npy")
            np.save(npy, cost)
            lethal = float(np.isinf(cost).mean())
            del cost
            print(
                f"\n== {size} x {size} ({size * size / 1e6:.0f} Mpx, {lethal:.1%} lethal; "
                f"generated in {time.perf_counter() - t0:.1f} s)"
            )
            print(
                f"{'tool':<16}{'query s':>10}{'cpu s':>8}{'repeat s':>10}{'setup s':>9}{'peak RSS MB':>13}"
                f"{'+ over load':>12}{'cost':>16}{'bound':>14}  notes"
            )
            rows = [run_tool(t, npy, args.timeout) for t in tools]
            ref = next((r.get("cost") for r in rows if r["tool"] == "mcp" and "cost" in r), None)
            for r in rows:
                if "error" in r:
                    print(f"{r['tool']:<16}  error: {r['error']}")
                    continue
                notes = []
                if "planner_bytes_per_pixel" in r:
                    notes.append(f"{r['planner_bytes_per_pixel']:.1f} B/px")
                if r.get("mode_used") and r["tool"] == "overseec-fast":
                    notes.append(f"mode={r['mode_used']}")
                if ref is not None and r.get("cost") is not None and ref > 0:
                    rel = (r["cost"] - ref) / ref
                    notes.append("= MCP cost" if abs(rel) <= 1e-9 else f"{rel:+.3%} vs MCP")
                print(
                    f"{r['tool']:<16}{fmt(r.get('query_s'), '10.2f')}{fmt(r.get('query_cpu_s'), '8.2f')}"
                    f"{fmt(r.get('repeat_query_s'), '10.2f')}"
                    f"{fmt(r.get('setup_s'), '9.2f')}{fmt(r.get('peak_rss_mb'), '13.0f')}"
                    f"{fmt(r['peak_rss_mb'] - r['rss_after_load_mb'], '12.0f')}"
                    f"{fmt(r.get('cost'), '16.6f')}{fmt(r.get('bound'), '14.4f')}  {', '.join(notes)}"
                )
            for key, what in (("query_s", "wall"), ("query_cpu_s", "CPU")):
                times = {r["tool"]: r.get(key) for r in rows if "error" not in r}
                if times.get("dijkstra3d") and times.get("overseec-exact"):
                    print(
                        f"overseec exact vs dijkstra3d ({what} time): "
                        f"{times['dijkstra3d'] / times['overseec-exact']:.1f}x faster"
                    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
