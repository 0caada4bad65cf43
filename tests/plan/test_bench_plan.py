"""bench/bench_plan.py runs at a tiny size and its printed figures are the planner's own: the costs,
bounds and bytes per pixel it prints match a direct planner run on the same seeded costmap
(timings are not checked)."""

from __future__ import annotations

import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from skimage.graph import MCP_Geometric

from overseec_core.plan import Planner, PlanningGrid

REPO = Path(__file__).resolve().parents[2]
SIZE = 96


def _bench_module():
    spec = importlib.util.spec_from_file_location("bench_plan", REPO / "bench" / "bench_plan.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _rows(stdout: str) -> dict[str, list[str]]:
    """The table's rows by tool: tool, query s, cpu s, repeat s, setup s, peak RSS, + over load,
    cost, bound, then the notes."""
    tools = ("overseec-exact", "overseec-fast", "mcp")
    return {
        line.split()[0]: line.split() for line in stdout.splitlines() if line.split()[:1] and line.split()[0] in tools
    }


@pytest.mark.slow
def test_bench_runs_at_a_small_size() -> None:
    pytest.importorskip("psutil")
    done = subprocess.run(
        [
            sys.executable,
            str(REPO / "bench" / "bench_plan.py"),
            "--sizes",
            str(SIZE),
            "--tools",
            "overseec-exact,overseec-fast,mcp",
        ],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    rows = _rows(done.stdout)
    assert set(rows) == {"overseec-exact", "overseec-fast", "mcp"}, done.stdout

    bench = _bench_module()
    cost = bench.make_costmap(SIZE, 0)
    lethal = re.search(rf"== {SIZE} x {SIZE} \(\d+ Mpx, ([\d.]+)% lethal", done.stdout)
    assert lethal is not None and float(lethal.group(1)) == pytest.approx(100 * np.isinf(cost).mean(), abs=0.05)
    grid = PlanningGrid(cost=cost, grid=None, pixel_size_m=bench.PIXEL)
    corners = [(0, 0), (SIZE - 1, SIZE - 1)]
    # the same queries as the bench's workers: one, then its repeat (fast mode: reversed)
    exact_planner, fast_planner = Planner(grid, bench.BASE), Planner(grid, bench.BASE)
    exact = exact_planner.plan(corners, mode="exact")
    exact_planner.plan(corners, mode="exact")
    fast_planner.prepare_fast()
    fast = fast_planner.plan(corners, mode="fast")
    fast_planner.plan(corners[::-1], mode="fast")
    mcp_cum, _ = MCP_Geometric(
        cost.astype(np.float64) + bench.BASE, sampling=(bench.PIXEL[1], bench.PIXEL[0])
    ).find_costs([corners[0]])

    # printed with 6 decimals (costs) and 4 (bounds): the figures of a direct run
    ex, fa, mcp = rows["overseec-exact"], rows["overseec-fast"], rows["mcp"]
    assert float(ex[7]) == pytest.approx(exact.cost, abs=1e-6)
    assert float(ex[8]) == pytest.approx(exact.bound, abs=1e-4) == pytest.approx(exact.cost, abs=1e-4)
    assert float(fa[7]) == pytest.approx(fast.cost, abs=1e-6)
    assert float(fa[8]) == pytest.approx(fast.bound, abs=1e-4)
    assert float(fa[8]) <= float(ex[7]) <= float(fa[7])  # the bound holds, fast never beats exact
    assert float(mcp[7]) == pytest.approx(mcp_cum[corners[1]], abs=1e-6)
    assert mcp[8] == "-" and "= MCP cost" in " ".join(ex[9:])
    # the bytes per pixel each planner holds after its queries (fast: with its coarse level)
    assert f"{exact_planner.memory_bytes()['per_pixel']:.1f} B/px" in " ".join(ex[9:])
    assert f"{fast_planner.memory_bytes()['per_pixel']:.1f} B/px" in " ".join(fa[9:])
    assert f"mode={fast.mode}" in " ".join(fa[9:])
    # timings: numbers, never checked against any figure
    for row in (ex, fa):
        assert all(float(v) >= 0 for v in row[1:5])


@pytest.mark.slow
def test_bench_keep_out_fraction_plans_as_overseec_plan_does(tmp_path) -> None:
    """--keep-out-fraction: the keep-out share it prints is the blobs' share, the route around
    them keeps the rule, the goal inside a building breaks it, and every printed cost and metres
    inside are those of overseec plan's RulePlanner on the same files (timings not checked)."""
    pytest.importorskip("psutil")
    from overseec_core.plan import load_costmap
    from overseec_core.plan.stage import RulePlanner

    size, fraction = 160, 0.1
    done = subprocess.run(
        [
            sys.executable,
            str(REPO / "bench" / "bench_plan.py"),
            "--sizes",
            str(size),
            "--keep-out-fraction",
            str(fraction),
        ],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    rows = {
        (p[0], p[1]): p
        for p in (line.split() for line in done.stdout.splitlines())
        if p[:1] and p[0] in ("open", "around", "open-goal", "inside")
    }
    assert len(rows) == 8, done.stdout

    bench = _bench_module()
    cost = bench.make_costmap(size, 0)
    keep, goal = bench.make_keep_out(cost, fraction, 0)
    head = re.search(r"([\d.]+)% keep-out; inside goal at row (\d+), col (\d+)", done.stdout)
    assert head is not None and (int(head.group(2)), int(head.group(3))) == goal
    assert float(head.group(1)) == pytest.approx(100 * keep.mean(), abs=0.05)
    assert keep.mean() == pytest.approx(fraction, abs=0.02) and keep[goal]
    tif, lethal = bench.write_keep_out_files(str(tmp_path), cost, keep)
    for name, with_keep_out, where in bench.KEEP_OUT_SCENARIOS:
        end = (size - 1, size - 1) if where == "corner" else goal
        rules = RulePlanner(Planner(load_costmap(tif, lethal_path=lethal if with_keep_out else None), bench.BASE))
        for mode in ("exact", "fast"):
            row = rows[(name, mode)]
            res, used = rules.plan([(0, 0), end], mode=mode)
            # query, mode, load, setup, query, cpu, repeat, peak RSS, cost, m inside, notes
            assert float(row[8]) == pytest.approx(res.cost, abs=1e-6)
            assert float(row[9]) == pytest.approx(rules.metres_inside(res.pixels)[0], abs=0.05)
            broken = name == "inside"
            assert (used is not rules.strict) == broken
            assert ("relaxed (rule broken)" in " ".join(row[10:])) == broken
            assert (float(row[9]) > 0) == broken
            assert all(float(v) >= 0 for v in row[2:8])
