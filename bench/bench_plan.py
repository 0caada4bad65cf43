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
    .venv/bin/python bench/bench_plan.py --sizes 40000 --tools overseec-exact   # 1.6 Gpx, ~21 GB
    .venv/bin/python bench/bench_plan.py --sizes 10000 --tools overseec-exact,dijkstra3d,overseec-exact16
                                                          # the issue-26 figure (+ 16 neighbours)

``--keep-out-fraction F`` measures overseec's planner alone on the common case of keep-out
cells: the same seeded costmap gets blobs of keep-out cells over a fraction F of it (small
blobs like buildings, large ones like water; own cost 1.0, as the priors give buildings and
water), written as a GeoTIFF with overseec's tagged lethal sidecar and planned as ``overseec
plan`` does (``load_costmap`` + ``RulePlanner``). Four queries, each in exact and fast mode:

- ``open``: corner to corner on the costmap without its sidecar (no keep-out);
- ``around``: corner to corner with the keep-out blobs, which a route avoids (a track is
  cleared through them if they cut the corners apart);
- ``open-goal``: from the top-left corner to the goal of ``inside``, without keep-out;
- ``inside``: the same, with the goal deep inside a building blob near the bottom-right corner,
  so the strict plan fails and the relaxed one (``entering_keep_out``) runs.

    .venv/bin/python bench/bench_plan.py --sizes 4000 --keep-out-fraction 0.1

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
#: Further tools, run only when named in --tools: the exact planner with 16-neighbour steps.
EXTRA_TOOLS = ("overseec-exact16",)


#: Largest side generated in one piece; larger costmaps are tiled from pieces this size (their
#: temporaries -- zoomed fields, a label image -- would not fit beside a 40,000² costmap).
TILE_MAX = 10000


def make_costmap(size: int, seed: int = 0) -> np.ndarray:
    """A size x size float32 costmap in [0, 1]: smooth field, cheap roads, lethal blobs (inf).

    Sides above :data:`TILE_MAX` are built by blocks: the costmap of a TILE_MAX-sized piece
    (``size`` a multiple of it) repeated, so generating needs little beyond the result; corner
    to corner stays routable (each piece connects its corners, and neighbouring pieces meet at
    their cleared corner squares)."""
    if size > TILE_MAX:
        return _tiled_costmap(size, seed)
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


def _tiled_costmap(size: int, seed: int, out: np.ndarray | None = None) -> np.ndarray:
    """make_costmap's TILE_MAX piece repeated over a size x size costmap (by blocks), into
    ``out`` when given (a memory-mapped .npy: the costmap is then never whole in memory)."""
    if size % TILE_MAX:
        raise SystemExit(f"sizes above {TILE_MAX} must be multiples of it (tiled), not {size}")
    piece, n = make_costmap(TILE_MAX, seed), size // TILE_MAX
    out = np.empty((size, size), dtype=np.float32) if out is None else out
    for i in range(n):
        for j in range(n):
            out[i * TILE_MAX : (i + 1) * TILE_MAX, j * TILE_MAX : (j + 1) * TILE_MAX] = piece
    return out


#: Own cost of keep-out cells in the --keep-out-fraction costmaps: buildings and water (level 1.0).
KEEP_OUT_OWN_COST = 1.0
#: Share of the keep-out fraction given to building-like blobs (the rest is water-like).
BUILDING_SHARE = 0.6
#: --keep-out-fraction queries: (name, with the keep-out sidecar, goal: the far corner or inside).
KEEP_OUT_SCENARIOS = (
    ("open", False, "corner"),
    ("around", True, "corner"),
    ("open-goal", False, "inside"),
    ("inside", True, "inside"),
)
#: Where the --keep-out-fraction GeoTIFFs lie (UTM, 0.5 m pixels: bench PIXEL).
BENCH_CRS, BENCH_ORIGIN = "EPSG:32633", (500000.0, 4000000.0)


def _blobs(rng: np.random.Generator, size: int, coarse: int) -> np.ndarray:
    """A size x size float32 field of smooth random blobs about size / coarse pixels across."""
    from scipy import ndimage

    # at least 8 x 8: the field is flat only in its corner squares, (size / 2 coarse)^2 each, and
    # a quantile threshold falling on such a tie would select nothing
    coarse = max(8, coarse)
    field = rng.random((coarse, coarse)).astype(np.float32)
    return ndimage.zoom(field, size / coarse, order=1, grid_mode=True, mode="nearest")[:size, :size]


def _top(field: np.ndarray, allowed: np.ndarray, fraction: float) -> np.ndarray:
    """The ``fraction`` of the ``allowed`` cells where ``field`` is highest (the threshold is a
    quantile estimated on a subsample)."""
    sample = field[::7, ::7][allowed[::7, ::7]]
    if fraction <= 0 or not len(sample):
        return np.zeros(field.shape, dtype=bool)
    return (field > np.quantile(sample, 1.0 - min(1.0, fraction))) & allowed


def make_keep_out(cost: np.ndarray, fraction: float, seed: int = 0) -> tuple[np.ndarray, tuple[int, int]]:
    """Keep-out blobs over about ``fraction`` of ``cost`` (changed in place: own cost 1.0 under
    them, tracks cleared where they cut the corners apart) and the ``inside`` goal.

    Building-like blobs are ~24 px (12 m) across, water-like ones ~200 px (100 m); neither
    covers lethal cells, roads (bridges) or the corner squares. Returns (keep-out mask, goal):
    the goal is the deepest building cell in the bottom-right eighth of the map (a quarter, a
    half, the whole map where that has none).
    """
    from scipy import ndimage
    from skimage.draw import line

    size = cost.shape[0]
    rng = np.random.default_rng(seed + 1)
    allowed = np.isfinite(cost) & (cost >= 0.1)  # no lethal cell, no road (roads cost 0.02)
    corner = max(3, size // 100)
    allowed[: corner + 1, : corner + 1] = allowed[-corner - 1 :, -corner - 1 :] = False
    share = float(allowed.mean())
    buildings = _top(_blobs(rng, size, size // 24), allowed, BUILDING_SHARE * fraction / share)
    rest = allowed & ~buildings
    need = fraction * cost.size - int(buildings.sum())  # water makes up the rest of the fraction
    keep = buildings | _top(_blobs(rng, size, size // 200), rest, need / max(1, int(rest.sum())))
    del rest, allowed
    for _ in range(8):  # the route must exist around the blobs: clear a track where they cut
        labels, _n = ndimage.label(np.isfinite(cost) & ~keep, structure=np.ones((3, 3)))
        if labels[0, 0] == labels[-1, -1]:
            break
        mid = rng.integers(size // 4, 3 * size // 4, 2)
        for (r0, c0), (r1, c1) in (((0, 0), mid), (mid, (size - 1, size - 1))):
            rr, cc = line(int(r0), int(c0), int(r1), int(c1))
            keep[rr, cc] = False
            cost[rr, cc] = np.where(np.isfinite(cost[rr, cc]), cost[rr, cc], np.float32(0.6))
    del labels
    cost[keep] = np.float32(KEEP_OUT_OWN_COST)
    for win in (size // 8, size // 4, size // 2, size):  # the nearest corner window with a building
        win = max(16, win)
        depth = ndimage.distance_transform_edt(buildings[-win:, -win:] & keep[-win:, -win:])
        r, c = np.unravel_index(int(np.argmax(depth)), depth.shape)
        if depth[r, c] > 0:
            return keep, (size - win + int(r), size - win + int(c))
    raise SystemExit("no building blob left: raise --keep-out-fraction")


def write_keep_out_files(tmp: str, cost: np.ndarray, keep: np.ndarray) -> tuple[str, str]:
    """The costmap GeoTIFF and overseec's tagged lethal sidecar (2 on keep-out cells)."""
    import rasterio
    from rasterio.transform import from_origin

    h, w = cost.shape
    profile = dict(
        driver="GTiff",
        width=w,
        height=h,
        count=1,
        crs=BENCH_CRS,
        transform=from_origin(*BENCH_ORIGIN, *PIXEL),
        tiled=True,
        blockxsize=512,
        blockysize=512,
    )
    # not lethal.tif nor cost.lethal.tif: load_costmap finds the sidecar only when asked to
    tif, lethal = os.path.join(tmp, "cost.tif"), os.path.join(tmp, "keep_out_sidecar.tif")
    with rasterio.open(tif, "w", dtype="float32", **profile) as ds:
        ds.write(cost, 1)
    with rasterio.open(lethal, "w", dtype="uint8", **profile) as ds:
        ds.write(np.where(keep, np.uint8(2), np.uint8(0)), 1)
        ds.update_tags(OVERSEEC_COSTMAP_FILE="cost.tif")
    return tif, lethal


def keep_out_worker(mode: str, tif: str, lethal: str | None, goal: tuple[int, int]) -> dict:
    """Runs in a fresh process: load the GeoTIFF (+ sidecar) as ``overseec plan`` does, plan
    from the top-left corner to ``goal`` with a RulePlanner, twice, and report."""
    import psutil

    from overseec_core.plan import Planner, load_costmap
    from overseec_core.plan.stage import RulePlanner

    rss0 = psutil.Process().memory_info().rss / 2**20
    t0 = time.perf_counter()
    grid = load_costmap(tif, lethal_path=lethal)
    out: dict = {"load_s": time.perf_counter() - t0, "rss_after_load_mb": psutil.Process().memory_info().rss / 2**20}
    out["rss_before_load_mb"] = rss0
    out["keep_out_cells"] = 0 if grid.keep_out is None else int(grid.keep_out.sum())
    t0 = time.perf_counter()
    rules = RulePlanner(Planner(grid, BASE))
    if mode == "fast":
        rules.strict.prepare_fast()
    out["setup_s"] = time.perf_counter() - t0
    points = [(0, 0), goal]
    t0, c0 = time.perf_counter(), time.process_time()
    res, used = rules.plan(points, mode=mode)
    out["query_s"], out["query_cpu_s"] = time.perf_counter() - t0, time.process_time() - c0
    t0 = time.perf_counter()
    rules.plan(points, mode=mode)  # the same query again: a relaxed planner is kept by then
    out["repeat_query_s"] = time.perf_counter() - t0
    inside, avoided = rules.metres_inside(res.pixels)
    out.update(
        cost=res.cost,
        bound=res.bound,
        mode_used=res.mode,
        expanded=res.expanded,
        relaxed=used is not rules.strict,
        m_inside=inside,
        m_avoided=avoided,
        notes=list(res.notes),
        # both planners when the relaxed one ran (the strict one stays loaded beside it)
        bytes_per_pixel=sum(
            p.memory_bytes()["per_pixel"] for p in {id(rules.strict): rules.strict, id(used): used}.values()
        ),
    )
    out["peak_rss_mb"] = peak_rss_mb()
    return out


def run_keep_out(sizes: list[int], fraction: float, seed: int, timeout: float) -> None:
    """The --keep-out-fraction benchmark: one table per size (see the module docstring)."""
    for size in sizes:
        with tempfile.TemporaryDirectory(prefix="bench_plan_keep_out_") as tmp:
            t0 = time.perf_counter()
            cost = make_costmap(size, seed)
            keep, goal = make_keep_out(cost, fraction, seed)
            tif, lethal = write_keep_out_files(tmp, cost, keep)
            lethal_share, keep_share = float(np.isinf(cost).mean()), float(keep.mean())
            del cost, keep
            print(
                f"\n== {size} x {size} ({size * size / 1e6:.0f} Mpx, {lethal_share:.1%} lethal, "
                f"{keep_share:.1%} keep-out; inside goal at row {goal[0]}, col {goal[1]}; "
                f"generated in {time.perf_counter() - t0:.1f} s)"
            )
            print(
                f"{'query':<11}{'mode':<7}{'load s':>8}{'setup s':>9}{'query s':>9}{'cpu s':>8}{'repeat s':>10}"
                f"{'peak RSS MB':>13}{'cost':>14}{'m inside':>10}  notes"
            )
            for name, with_keep_out, where in KEEP_OUT_SCENARIOS:
                end = (size - 1, size - 1) if where == "corner" else goal
                for mode in ("exact", "fast"):
                    cmd = [sys.executable, str(Path(__file__).resolve()), "--keep-out-worker", mode, "--tif", tif]
                    cmd += ["--goal", f"{end[0]},{end[1]}"] + (["--lethal", lethal] if with_keep_out else [])
                    try:
                        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
                    except subprocess.TimeoutExpired:
                        print(f"{name:<11}{mode:<7}  error: timed out after {timeout:.0f} s")
                        continue
                    if proc.returncode != 0:
                        print(f"{name:<11}{mode:<7}  error: {(proc.stderr.strip().splitlines() or ['failed'])[-1]}")
                        continue
                    r = json.loads(proc.stdout.strip().splitlines()[-1])
                    notes = [f"{r['bytes_per_pixel']:.1f} B/px", f"mode={r['mode_used']}"]
                    notes.append("relaxed (rule broken)" if r["relaxed"] else "strict")
                    print(
                        f"{name:<11}{mode:<7}{r['load_s']:8.2f}{r['setup_s']:9.2f}{r['query_s']:9.2f}"
                        f"{r['query_cpu_s']:8.2f}{r['repeat_query_s']:10.2f}{r['peak_rss_mb']:13.0f}"
                        f"{r['cost']:14.6f}{r['m_inside']:10.1f}  {', '.join(notes)}"
                    )


def price(cost: np.ndarray, pixels: np.ndarray) -> float:
    """Cost of the route ``pixels`` over ``cost`` as overseec prices it (base cost per metre
    included), so every tool's route is scored on one scale."""
    from overseec_core.plan import PlanningGrid, cumulative_path_cost

    g = PlanningGrid(cost=cost, grid=None, pixel_size_m=PIXEL)
    return float(cumulative_path_cost(g, pixels, BASE)[-1])


def peak_rss_mb() -> float:
    """Peak resident memory of this process in MiB (``ru_maxrss`` is in KiB on Linux)."""
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def worker(tool: str, npy: str) -> dict:
    """Runs in a fresh process: load, run one tool, report."""
    import psutil

    if tool.startswith("overseec"):  # import first: the RSS baseline includes each tool's imports
        import overseec_core.plan  # noqa: F401
    elif tool == "dijkstra3d":
        import dijkstra3d
    elif tool == "mcp":
        import skimage.graph  # noqa: F401
    # above TILE_MAX the costmap is memory-mapped: its pages are the file's, which the kernel may
    # drop and re-read, so the planner's own memory (dist + state) is what must fit
    cost = np.load(npy, mmap_mode="r" if os.path.getsize(npy) > 4 * TILE_MAX**2 + 4096 else None)
    h, w = cost.shape
    start, goal = (0, 0), (h - 1, w - 1)
    rss_loaded = psutil.Process().memory_info().rss / 2**20
    out: dict = {"tool": tool, "rss_after_load_mb": rss_loaded}
    if tool.startswith("overseec"):
        from overseec_core.plan import Planner, PlanningGrid

        mode = tool.split("-")[1]
        neighbours = 16 if mode.endswith("16") else 8
        mode = mode.removesuffix("16")
        t0 = time.perf_counter()
        grid = PlanningGrid(cost=cost, grid=None, pixel_size_m=PIXEL)
        planner = Planner(grid, BASE, neighbours=neighbours)
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
        out["length_m"] = res.length_m
        if mode == "fast":  # the interactive figure: a repeated query on the loaded costmap
            t0 = time.perf_counter()
            planner.plan([goal, start], mode=mode)
            out["repeat_query_s"] = time.perf_counter() - t0
        elif h <= TILE_MAX:  # above it one query is the figure (minutes each)
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
    """Run ``tool`` in a fresh worker subprocess on the saved costmap (its peak RSS is its own) and
    return its JSON result with ``process_s``, or an ``error`` entry when it fails or times out."""
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


def save_costmap(npy: str, size: int, seed: int) -> float:
    """Write make_costmap(size, seed) to ``npy``; returns its lethal share. Above TILE_MAX it is
    written by blocks into the file (never whole in memory)."""
    if size > TILE_MAX:
        cost = np.lib.format.open_memmap(npy, mode="w+", dtype=np.float32, shape=(size, size))
        _tiled_costmap(size, seed, cost)
        cost.flush()
        return float(np.isinf(cost[:TILE_MAX, :TILE_MAX]).mean())  # the same in every tile
    cost = make_costmap(size, seed)
    np.save(npy, cost)
    return float(np.isinf(cost).mean())


def run_tools(sizes: list[int], tools: list[str], seed: int, timeout: float) -> None:
    """The comparison of planners: one table per size (see the module docstring)."""
    print(
        f"bench_plan: corner-to-corner, base {BASE}/m, pixel {PIXEL[0]} x {PIXEL[1]} m, seed {seed}, "
        f"{os.cpu_count()} CPUs, python {sys.version.split()[0]}"
    )
    for size in sizes:
        with tempfile.TemporaryDirectory(prefix="bench_plan_") as tmp:
            t0 = time.perf_counter()
            npy = os.path.join(tmp, "cost.npy")
            lethal = save_costmap(npy, size, seed)
            print(
                f"\n== {size} x {size} ({size * size / 1e6:.0f} Mpx, {lethal:.1%} lethal; "
                f"generated in {time.perf_counter() - t0:.1f} s)"
            )
            print(
                f"{'tool':<16}{'query s':>10}{'cpu s':>8}{'repeat s':>10}{'setup s':>9}{'peak RSS MB':>13}"
                f"{'+ over load':>12}{'cost':>16}{'bound':>14}  notes"
            )
            rows = [run_tool(t, npy, timeout) for t in tools]
            ref = next((r.get("cost") for r in rows if r["tool"] == "mcp" and "cost" in r), None)
            for r in rows:
                if "error" in r:
                    print(f"{r['tool']:<16}  error: {r['error']}")
                    continue
                notes = []
                if "planner_bytes_per_pixel" in r:
                    notes.append(f"{r['planner_bytes_per_pixel']:.1f} B/px")
                if "length_m" in r:
                    notes.append(f"{r['length_m']:.0f} m")
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


def main(argv: list[str] | None = None) -> int:
    """Command line: compare the planners on each size (or, with --keep-out-fraction, overseec with
    and without keep-out blobs) and print the table; the hidden --worker options run one tool."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="4000,10000", help="comma-separated sides (default 4000,10000)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--tools", default=",".join(TOOLS), help=f"subset of {','.join(TOOLS + EXTRA_TOOLS)}")
    ap.add_argument("--timeout", type=float, default=1800.0, help="per-tool seconds")
    ap.add_argument(
        "--keep-out-fraction",
        type=float,
        default=None,
        metavar="F",
        help="plan with keep-out blobs (buildings, water) over a fraction F of the costmap, against "
        "the same costmap without them (overseec only; --tools is ignored)",
    )
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--npy", help=argparse.SUPPRESS)
    ap.add_argument("--keep-out-worker", help=argparse.SUPPRESS)
    ap.add_argument("--tif", help=argparse.SUPPRESS)
    ap.add_argument("--lethal", help=argparse.SUPPRESS)
    ap.add_argument("--goal", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        print(json.dumps(worker(args.worker, args.npy)))
        return 0
    if args.keep_out_worker:
        r, c = (int(v) for v in args.goal.split(","))
        print(json.dumps(keep_out_worker(args.keep_out_worker, args.tif, args.lethal, (r, c))))
        return 0
    sizes = [int(s) for s in args.sizes.split(",")]
    if args.keep_out_fraction is not None:
        if not 0.0 < args.keep_out_fraction < 1.0:
            ap.error("--keep-out-fraction must be between 0 and 1")
        print(
            f"bench_plan --keep-out-fraction {args.keep_out_fraction}: overseec plan's RulePlanner, base "
            f"{BASE}/m, pixel {PIXEL[0]} x {PIXEL[1]} m, seed {args.seed}, {os.cpu_count()} CPUs, "
            f"load average {os.getloadavg()[0]:.1f}, python {sys.version.split()[0]}"
        )
        run_keep_out(sizes, args.keep_out_fraction, args.seed, args.timeout)
        return 0
    run_tools(sizes, [t.strip() for t in args.tools.split(",") if t.strip()], args.seed, args.timeout)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
