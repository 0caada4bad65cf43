"""Route planning on costmaps: load, plan (exact or fast), export.

Contract (stable; ``overseec eval`` and the QGIS map tool code against it)::

    from overseec_core.plan import load_costmap, Planner, PathResult, PlanningGrid

    grid = load_costmap(path, lethal_path=None, lethal_threshold=None)
    planner = Planner(grid, base_cost_per_m=0.01)   # working memory allocated once
    res = planner.plan([(row, col), ...], mode="exact")  # or "fast"; start, vias..., goal

:func:`load_costmap` reads band 1 of a costmap GeoTIFF as float32 (nodata -> NaN) and marks
lethal cells +inf: from the uint8 sidecar (nonzero = impassable) named by the costmap tag
``OVERSEEC_LETHAL_FILE`` or found beside it as ``lethal.tif`` (or ``lethal_path``), and where
``cost >= lethal_threshold``. NaN and +inf cells are impassable.

:class:`PlanningGrid` fields: ``cost`` (H, W) float32 (+inf lethal, NaN nodata), ``grid``
(:class:`overseec_core.io.grid.Grid`: crs, transform, width, height; None for bare arrays),
``pixel_size_m`` (x, y) metres, ``source`` path, ``lethal_source``, ``tags``; properties
``passable`` / ``lethal`` / ``nodata`` (bool masks computed on demand), ``prompt`` (from the tags);
``world_to_pixel(x, y, crs=None) -> (row, col)`` (floor; crs = the points' CRS, default the
costmap's), ``pixel_to_world(rows, cols, crs=None) -> (xs, ys)`` (pixel centres),
``blocked_reason(row, col) -> 'outside' | 'lethal' | 'nodata' | None``.
``PlanningGrid.from_array(cost, grid=None, lethal=None, lethal_threshold=None,
pixel_size_m=None)`` wraps an in-memory array.

:class:`Planner` ``(grid, base_cost_per_m=0.01, *, coarse_factor=None, corridor_blocks=2,
bound_hops=3, tight_bound=True)`` (``tight_bound=False``: fast mode reports only the octile
bound, which saves about half of a long fast query): step cost between 8-connected neighbours = (mean of the two costs +
base_cost_per_m) x step length in metres (dx, dy or hypot(dx, dy)), float64 totals -- the rule of
scikit-image's ``MCP_Geometric`` fed ``cost + base`` with ``sampling=(dy, dx)``.
``plan(points, mode="exact" | "fast", *, labels=None, progress=None) -> PathResult`` (points are
(row, col) pixel indices; ``labels`` name them in errors); ``expand(point)`` +
``cumulative_rows(r0, r1)`` / ``cumulative(point)`` give the cost-distance raster (float32, NaN
unreachable); ``path_cost(pixels)`` prices any pixel path; ``memory_bytes()``; ``cancel()``.
Errors: :class:`overseec_core.errors.PlanError` naming the point ("goal (x, y) is on a lethal
cell", "... is outside the costmap", "no path from start ... to goal ..."), ``InputError`` for
malformed arguments, ``Cancelled`` when cancelled.

:class:`PathResult`: ``pixels`` (N, 2) int64 (row, col) start..goal, 8-connected; ``cost`` (float);
``length_m``; ``mode`` ('exact' or 'fast': the mode that produced the path -- fast falls back to
exact when its corridor holds no path); ``bound`` (a guaranteed lower bound on the optimal cost;
== cost in exact mode); ``gap`` = (cost - bound) / cost; ``seconds``; ``waypoints``;
``leg_costs``; ``expanded`` (cells settled); ``notes``; ``to_json()``.

Without the compiled kernel (not built: no compiler when pip compiled the sdist; or not loading)
:class:`Planner` plans with scikit-image's ``MCP_Geometric`` (:mod:`.fallback`): the same step rule
and path costs, several times slower, fast mode = the exact search, and a note on every result.
:func:`planner_backend` -> :class:`PlannerBackend` (``name`` 'kernel' or 'fallback', ``reason``,
``describe()``) says which one a Planner made now uses; ``OVERSEEC_PLANNER`` = ``auto`` (default),
``kernel`` (refuse to plan without it) or ``fallback`` (always) chooses, read when a Planner is made.
"""

from overseec_core.plan.backend import PLANNER_ENV, PlannerBackend, planner_backend
from overseec_core.plan.grid import PlanningGrid, load_costmap
from overseec_core.plan.paths import DEFAULT_BASE_COST_PER_M, cumulative_path_cost, path_length_m, point_names
from overseec_core.plan.planner import MODES, Planner
from overseec_core.plan.result import PathResult

__all__ = [
    "DEFAULT_BASE_COST_PER_M",
    "MODES",
    "PLANNER_ENV",
    "PathResult",
    "Planner",
    "PlannerBackend",
    "PlanningGrid",
    "cumulative_path_cost",
    "load_costmap",
    "path_length_m",
    "planner_backend",
    "point_names",
]
