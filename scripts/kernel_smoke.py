#!/usr/bin/env python3
"""Smoke test of an installed overseec: the compiled planner kernel loads and plans a tiny grid.

Run against a wheel or sdist install (cibuildwheel's test-command, tests/plan/test_kernel_portable.py)
from a folder outside the checkout, so ``overseec_core`` comes from the installation. Prints one
line with the kernel's file and exits non-zero when anything is off.
"""

from __future__ import annotations

import math
import sys

import numpy as np


def main() -> int:
    from overseec_core.plan import Planner, PlanningGrid, _kernel

    # 9 x 9 unit-cost grid, 2 m x 1 m pixels, a wall on column 4 with a gap in the bottom row.
    cost = np.ones((9, 9), np.float32)
    cost[:8, 4] = np.inf
    grid = PlanningGrid.from_array(cost, pixel_size_m=(2.0, 1.0))
    planner = Planner(grid, base_cost_per_m=0.0)
    exact = planner.plan([(0, 0), (0, 8)], mode="exact")
    fast = planner.plan([(0, 0), (0, 8)], mode="fast")
    # The reference: scikit-image's MCP_Geometric, whose step rule (mean of the two cells' costs
    # x step length) the kernel implements; the path must detour through the gap.
    from skimage.graph import MCP_Geometric

    mcp = MCP_Geometric(cost.astype(np.float64), sampling=(1.0, 2.0))
    costs, _ = mcp.find_costs([(0, 0)], [(0, 8)])
    want = float(costs[0, 8])
    ok = (
        math.isclose(exact.cost, want, rel_tol=1e-9)
        and math.isclose(fast.cost, want, rel_tol=1e-9)
        and tuple(exact.pixels[0]) == (0, 0)
        and tuple(exact.pixels[-1]) == (0, 8)
        and all(cost[r, c] == 1 for r, c in exact.pixels)
    )
    print(f"kernel {_kernel.__file__}: exact {exact.cost:.6f} fast {fast.cost:.6f} mcp {want:.6f}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
