"""bench/bench_plan_worker.py runs at a small size: it talks to a real worker, replays both drags,
and the in-process planner configured as the worker plans finds the same costs (timings are not
checked)."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("steps", ["8", "16"])
def test_the_worker_bench_runs_and_agrees_with_the_core(steps: str) -> None:
    bench = [str(REPO / "bench" / "bench_plan_worker.py"), "--size", "300", "--steps", "4", "--neighbours", steps]
    done = subprocess.run(
        [sys.executable, *bench],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    out = done.stdout
    assert f"costmap 300 x 300 (seed 0, {steps} neighbours)" in out
    for drag in ("drag a via (2 legs)", "drag the goal (1 leg)"):
        (row,) = [line for line in out.splitlines() if line.startswith(drag)]
        assert re.search(r"median +[\d.]+ ms +p95 +[\d.]+ ms", row), row
        (same,) = [line for line in out.splitlines() if f"as the worker plans: {drag}" in line]
        assert "costs within 0.0e+00 of the worker's" in same, same
