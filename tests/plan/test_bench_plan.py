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
