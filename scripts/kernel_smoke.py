#!/usr/bin/env python3
"""Smoke test of an installed overseec: the compiled planner kernel loads and plans small grids.

Run against a wheel or sdist install (cibuildwheel's test-command, tests/plan/test_kernel_portable.py)
from a folder outside the checkout, so ``overseec_core`` comes from the installation. The check is
``overseec doctor --kernel`` (``overseec_core.commands.doctor.kernel_check``: exact and fast plans
against scikit-image's MCP_Geometric), which every install has; this script differs only in that a
missing kernel fails it: a wheel must carry its kernel. Prints one line ("kernel FILE: exact ...
fast ... mcp ...") and exits non-zero when anything is off.
"""

from __future__ import annotations

import sys


def main() -> int:
    """Plan the check grids with the installed kernel; 0 only when it loads and plans right."""
    from overseec_core.commands.doctor import kernel_check

    report = kernel_check()
    print(report["line"])
    return 0 if report["ok"] and report["kernel"] else 1


if __name__ == "__main__":
    sys.exit(main())
