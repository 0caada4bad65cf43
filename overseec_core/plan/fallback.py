"""The planner without its compiled kernel: scikit-image's ``MCP_Geometric``.

The C kernel (``_kernel.c``) is optional: an install where it could not be compiled (no
compiler when pip built the sdist) or does not load (built against another NumPy ABI) still
plans, with this search. It prices steps exactly as the kernel does: ``MCP_Geometric`` moves
between 8-connected neighbours for the mean of the two cells' costs times the step length,
with ``sampling=(dy, dx)`` for non-square pixels, so fed ``cost + base_cost_per_m`` it charges
``(mean of the two costs + base) x step length`` -- the kernel's rule -- and finds paths of the
same cost (equal to about 1e-12; among equally cheap paths it may pick another one).

What differs is speed and memory: Dijkstra without A* over a binary heap, and no fast mode (fast
mode runs the exact search here; the result says so). Measured with ``bench/bench_plan.py
--sizes 2000,4000`` corner to corner (exact, 8 % lethal, 0.5 m pixels, 2 CPUs), the compiled
kernel first and then the fallback (``OVERSEEC_PLANNER=fallback``, the same command):

====  =====================  ==============================  =================================
side  kernel, exact (repeat)  fallback, exact (repeat): ratio  kernel fast vs fallback fast (= exact)
====  =====================  ==============================  =================================
2000  0.36 s (0.35 s)        2.83 s (2.66 s): 7.6-7.9x        0.09 s vs 2.55 s: 28x
4000  1.84 s (1.95 s)        17.5 s (13.4 s): 6.9-9.5x        0.11 s vs 15.3 s: 140x
====  =====================  ==============================  =================================

(the fallback's first query includes building its search: 0.4 s at 2000², 2.2 s at 4000²) --
hence :data:`SLOWDOWN` and :data:`FAST_SLOWDOWN`. Memory: about 22 bytes per pixel once built and
74 at the peak of building (1.2 GB over the costmap at 4000²), against the kernel's 13.

Lethal cells (+inf) and nodata (NaN, made +inf here: ``MCP_Geometric`` crashes on NaN) are never
entered. ``find_costs`` holds the GIL for the whole search, so a query is cancelled from inside
it: ``MCP.goal_reached``, which the search calls for every cell it settles, is overridden to
return the stop flag :meth:`McpSearch.stop` sets (a Python call per cell: about 15 % of the
search, the price of stopping within a second instead of at the end of the query). Building the
search cannot be stopped, so it runs in a thread the caller waits on, looking at the cancel flag
(:func:`_build_cancellable`): a cancel while it builds is answered at once too.
"""

from __future__ import annotations

import threading
from typing import Any

import numpy as np

#: The fallback's speed against the compiled kernel's exact search, and its fast mode (the table above).
SLOWDOWN = "7-10x"
FAST_SLOWDOWN = "30-140x"
#: The note every result planned by the fallback carries (``{reason}``: why, and how to get the kernel).
NOTE = "planned with the fallback planner (scikit-image), {slowdown} slower than the compiled kernel; {reason}"
#: Added to the note for a fast-mode request.
FAST_NOTE = "; fast mode runs its exact search ({slowdown} slower than the kernel's fast mode)"
#: Why the fallback refuses 16-neighbour steps: ``MCP_Geometric`` prices a step by its two end
#: cells only, so a knight move's cell integral (four cells, see ``_kernel.c``) cannot be given
#: to it, and a knight move may not cut a lethal corner, which it cannot check either.
NO_KNIGHTS = (
    "16-neighbour steps need the compiled planner kernel (overseec_core/plan/_kernel.c); this install "
    "plans with the scikit-image fallback, which has 8 only: use --neighbours 8 or install a C compiler "
    "and reinstall (`overseec doctor` says which planner an install has)"
)
#: Why the fallback refuses the anisotropic mode (a DEM with a slope model): ``MCP_Geometric``
#: prices a step by its two cells' costs, the same in both directions (``MCP``'s Python hooks
#: would see the step but cost a Python call per edge), so uphill and downhill cannot differ.
NO_TERRAIN = (
    "slope-dependent costs (--dem with --slope-model) need the compiled planner kernel "
    "(overseec_core/plan/_kernel.c); the scikit-image fallback prices a step the same both ways: "
    "install a C compiler and reinstall (`overseec doctor` says which planner an install has)"
)
#: Statuses of a search, as the kernel's: found, no path, cancelled.
FOUND, NO_PATH, CANCELLED = 0, 1, 2


def _mcp_class() -> type:
    """``MCP_Geometric`` with a cancel check (skimage is imported on first use only)."""
    from skimage.graph import MCP_Geometric

    class CancellableMCP(MCP_Geometric):
        #: 0 goes on, 2 stops the whole search (MCP's protocol); a plain int, the cheapest check
        stop_flag = 0

        def goal_reached(self, index: int, cumcost: float) -> int:
            return self.stop_flag

    return CancellableMCP


class BuildCancelled(Exception):
    """The cancel flag was set while the search was being built (the planner says Cancelled)."""


#: How often the wait for the search's construction looks at the cancel flag (s).
BUILD_POLL_S = 0.05


def _build_cancellable(costs: np.ndarray, sampling: tuple[float, float], cancel: np.ndarray) -> Any:
    """``MCP_Geometric`` over ``costs``, built in a thread while this one waits in
    :data:`BUILD_POLL_S` steps: the construction (4-7 s at 6000², no Python code in it) cannot be
    stopped, but it releases the GIL, so the waiting thread sees the cancel flag -- and the main
    thread's signal handlers run -- within a tenth of a second. Raises :class:`BuildCancelled`
    when the flag is set first; the abandoned build finishes in the background and is dropped."""
    box: list[Any] = []
    failed: list[BaseException] = []

    def build() -> None:
        try:
            box.append(_mcp_class()(costs, sampling=sampling))
        except BaseException as exc:
            failed.append(exc)

    thread = threading.Thread(target=build, name="overseec-fallback-build", daemon=True)
    thread.start()
    while thread.is_alive():
        thread.join(BUILD_POLL_S)
        if cancel[0]:
            raise BuildCancelled
    if failed:
        raise failed[0]
    return box[0]


class McpSearch:
    """Shortest paths on one costmap with ``MCP_Geometric``, built once, reused per query.

    ``cost`` is the planner's (H, W) float32 array (+inf lethal, NaN nodata); ``cancel`` the
    planner's one-byte cancel flag, read when a query starts (a cancel that came first stops it);
    :meth:`stop` stops a running one.
    """

    def __init__(self, cost: np.ndarray, base_cost_per_m: float, dx: float, dy: float, cancel: np.ndarray) -> None:
        costs = cost.astype(np.float64)
        costs += base_cost_per_m
        costs[~np.isfinite(costs)] = np.inf  # NaN (nodata) would crash MCP; +inf is never entered
        self.shape = cost.shape
        self._mcp: Any = _build_cancellable(costs, (dy, dx), cancel)
        del costs  # MCP keeps its own (padded, flat) copy
        self._cancel = cancel
        self._cum: np.ndarray | None = None

    def stop(self) -> None:
        """Stop the running query (from any thread); it returns CANCELLED."""
        self._mcp.stop_flag = 2

    def _find(self, a: tuple[int, int], ends: list[tuple[int, int]] | None) -> np.ndarray | None:
        """MCP's cumulative costs from ``a`` (None when cancelled)."""
        self._cum = None
        self._mcp.stop_flag = 2 if self._cancel[0] else 0
        cum, _traceback = self._mcp.find_costs([a], ends) if ends else self._mcp.find_costs([a])
        if self._mcp.stop_flag or self._cancel[0]:
            return None
        return cum

    def nbytes(self) -> int:
        """About what the built search holds: padded costs, cumulative costs, traceback, flags."""
        h, w = self.shape
        return int((h + 2) * (w + 2) * 22)

    def leg(self, a: tuple[int, int], b: tuple[int, int]) -> tuple[int, np.ndarray | None, float, int]:
        """(status, pixels (N, 2) int64 from a to b, cost, cells reached) of the cheapest path."""
        cum = self._find(a, [b])
        if cum is None:
            return CANCELLED, None, 0.0, 0
        reached = int(np.count_nonzero(np.isfinite(cum)))
        cost = float(cum[b])
        if not np.isfinite(cost):
            return NO_PATH, None, 0.0, reached
        pixels = np.asarray(self._mcp.traceback(b), dtype=np.int64).reshape(-1, 2)
        return FOUND, pixels, cost, reached

    def expand(self, a: tuple[int, int]) -> tuple[int, int]:
        """(status, cells reached) of the cost-distance from ``a`` to every cell."""
        cum = self._find(a, None)
        if cum is None:
            return CANCELLED, 0
        self._cum = cum
        return FOUND, int(np.count_nonzero(np.isfinite(cum)))

    def cumulative(self) -> np.ndarray | None:
        """The last :meth:`expand`'s float64 cost-distances (+inf unreachable; a view, not a copy),
        exact where :meth:`cumulative_rows` rounds to float32; None without one."""
        return self._cum

    def cumulative_rows(self, r0: int, r1: int) -> np.ndarray | None:
        """Rows r0:r1 of the last :meth:`expand` (float32, NaN unreachable); None without one."""
        if self._cum is None:
            return None
        rows = self._cum[r0:r1]
        return np.where(np.isfinite(rows), rows, np.nan).astype(np.float32)


__all__ = [
    "CANCELLED",
    "FAST_NOTE",
    "FAST_SLOWDOWN",
    "FOUND",
    "NOTE",
    "NO_PATH",
    "NO_TERRAIN",
    "SLOWDOWN",
    "BuildCancelled",
    "McpSearch",
]
