"""bench/bench_plan.py runs at a tiny size and agrees with MCP_Geometric (figures are not checked)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


@pytest.mark.slow
def test_bench_runs_at_a_small_size() -> None:
    pytest.importorskip("psutil")
    done = subprocess.run([sys.executable, str(REPO / "bench" / "bench_plan.py"), "--sizes", "96",
                           "--tools", "overseec-exact,overseec-fast,mcp"],
                          capture_output=True, text=True, cwd=REPO, timeout=600)
    assert done.returncode == 0, done.stderr
    lines = {line.split()[0]: line for line in done.stdout.splitlines() if line.strip()}
    assert "= MCP cost" in lines["overseec-exact"]
    assert "error" not in lines["overseec-fast"] and "B/px" in lines["overseec-fast"]
