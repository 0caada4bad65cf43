"""Cost-distance fields and least-cost corridors, under exactly the planner's step rule.

A *cost-distance field* from a cell is the cost of the cheapest route from it to every cell:
the planner's full Dijkstra without an early exit (``Planner.expand``: the compiled kernel's
``search`` with ``goal=-1``, or scikit-image's ``MCP_Geometric`` in the fallback), the same step
costs as a planned route -- (mean of the two cells' costs + base cost per metre) x step length,
8-neighbour, lethal and nodata cells never entered -- read back in float64.

The *least-cost corridor* between a start and a goal gives every cell the cost of the best route
from the start to the goal *through that cell*, divided by the optimum::

    ratio(v) = (d_start(v) + d_goal(v)) / d_start(goal)

Steps cost the same both ways (the mean of the two cells is symmetric), so d_goal(v), the cost
from v to the goal, is the field grown from the goal. The ratio is 1.0 on the optimal route (and
on every other route as cheap), grows away from it, and is NaN where no route passes (lethal,
nodata, or cut off from the start). The cells with ratio <= 1 + PCT / 100 are the ones some route
within PCT % of the optimum passes through: the alternatives a mission planner can choose
among, where a single route is brittle. Two whole-grid searches (two ``expand`` calls); memory
beyond the planner's: one float64 field (8 B/px), the float32 ratio (4) and the mask (1).

:func:`run_corridor` is the `overseec corridor` stage: costmap + two map points -> the ratio
GeoTIFF and the within-PCT mask GeoTIFF on the costmap's grid, written atomically, recorded in
the output folder's manifest.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from overseec_core import runfiles
from overseec_core.errors import InputError, OutputError, PlanError
from overseec_core.io.grid import parse_crs
from overseec_core.io.manifest import RunDir
from overseec_core.io.transaction import transactional
from overseec_core.io.write import RasterWriter, check_output_path
from overseec_core.plan.grid import PlanningGrid, load_costmap
from overseec_core.plan.paths import DEFAULT_BASE_COST_PER_M
from overseec_core.plan.planner import UNVISITED, Planner, run_cancellable
from overseec_core.progress import Progress

#: Rows handled at a time when the two fields are combined (bounds the float64 temporaries).
CHUNK_ROWS = 512


def _raw_field(planner: Planner) -> np.ndarray:
    """The (H, W) float64 distances of the planner's last ``expand`` (a view, not a copy):
    unreached cells hold :data:`UNVISITED` (kernel) or +inf (fallback)."""
    h, w = planner.shape
    if planner.backend.name == "kernel":
        return planner.buffers["dist"].reshape(h, w)
    # the fallback keeps MCP_Geometric's float64 cumulative costs of its last expand()
    # (overseec_core.plan.fallback.McpSearch.cumulative; cumulative_rows() rounds to float32)
    mcp = getattr(planner, "_mcp", None)
    cum = mcp.cumulative() if mcp is not None else None
    if cum is None:
        raise PlanError("no cost-distance available: the fallback planner kept no field")
    return cum


def cost_distance(
    planner: Planner, point: Sequence[int], *, label: str | None = None, progress: Progress | None = None
) -> np.ndarray:
    """The cost-distance field from ``point`` (row, col): float64 (H, W), +inf where no route
    reaches. Raises PlanError for a point outside the grid or on a lethal/nodata cell."""
    planner.expand(point, label=label, progress=progress)
    raw = _raw_field(planner)
    out = raw.copy()
    out[out >= UNVISITED] = np.inf
    return out


def cost_distance_many(
    planner: Planner, points: Sequence[Sequence[int]], *, progress: Progress | None = None
) -> np.ndarray:
    """The cost-distance field from a *set* of source cells (each at cost 0): float64 (H, W),
    each cell's cost from its cheapest source, +inf where none reaches (GRASS ``r.cost`` with
    several start points). One search: the kernel's ``expand_many`` (its own buffers, 9 B/px,
    freed on return), or ``MCP_Geometric`` with every source as a start in the fallback. Raises
    PlanError for a source outside the grid or on a blocked cell, InputError for no source."""
    from overseec_core.errors import Cancelled
    from overseec_core.plan.backend import _kernel
    from overseec_core.plan.paths import as_points

    pts = as_points(points)
    if not pts:
        raise InputError("a cost-distance field needs at least one source cell")
    for i, (r, c) in enumerate(pts):
        why = planner.grid.blocked_reason(r, c)
        if why is not None:
            where = "outside the costmap" if why == "outside" else f"on a {why} cell"
            raise PlanError(f"source {i + 1} (row {r}, col {c}) is {where}")
    h, w = planner.shape
    dx, dy = planner.grid.pixel_size_m
    if planner.backend.name != "kernel":
        from skimage.graph import MCP_Geometric

        costs = planner.grid.cost.astype(np.float64) + planner.base_cost_per_m
        costs[~np.isfinite(costs)] = np.inf
        cum, _ = MCP_Geometric(costs, sampling=(dy, dx)).find_costs(pts)
        return np.asarray(cum, dtype=np.float64)
    dist = np.empty(h * w, dtype=np.float64)
    dist.view(np.uint8).fill(0x7F)
    state = np.zeros(h * w, dtype=np.uint8)
    cancel = np.zeros(1, dtype=np.uint8)
    bbox = np.array([h, -1, w, -1], dtype=np.int64)
    sources = np.array([r * w + c for r, c in pts], dtype=np.int64)
    status, _settled = run_cancellable(
        lambda: _kernel.expand_many(
            planner.grid.cost, dist, state, _kernel.workspace(), dx, dy, planner.base_cost_per_m, sources, cancel, bbox
        ),
        cancel,
        progress,
    )
    if status == 2:
        raise Cancelled("planning cancelled by the user")
    out = dist.reshape(h, w)
    out[out >= UNVISITED] = np.inf
    return out


def costs_to(
    planner: Planner,
    point: Sequence[int],
    targets: Sequence[Sequence[int]],
    *,
    label: str | None = None,
    progress: Progress | None = None,
) -> np.ndarray:
    """Route costs from ``point`` to each of ``targets`` (row, col) from one whole-grid search:
    float64 (len(targets),), +inf for a target no route reaches (or one outside the grid)."""
    planner.expand(point, label=label, progress=progress)
    raw = _raw_field(planner)
    h, w = planner.shape
    out = np.full(len(targets), np.inf)
    for i, (r, c) in enumerate(targets):
        if 0 <= r < h and 0 <= c < w and raw[r, c] < UNVISITED:
            out[i] = float(raw[r, c])
    return out


@dataclass(frozen=True)
class Corridor:
    """The least-cost corridor between two cells (see the module docstring).

    ``ratio`` (H, W) float32: best-through-cell cost / optimum (1.0 on the optimal route, NaN
    where no route passes); ``mask`` (H, W) uint8: 1 where the float64 ratio <= 1 + within;
    ``optimum`` the optimal route's cost (= the planner's exact route cost).
    """

    ratio: np.ndarray
    mask: np.ndarray
    optimum: float
    within: float
    start: tuple[int, int]
    goal: tuple[int, int]
    seconds: float

    @property
    def cells_within(self) -> int:
        """How many cells lie in the corridor (mask set)."""
        return int(np.count_nonzero(self.mask))

    def to_json(self) -> dict[str, Any]:
        """The corridor's figures as plain JSON types (the CLI's --json, the manifest)."""
        return {
            "optimum": self.optimum,
            "within_pct": 100.0 * self.within,
            "cells_within": self.cells_within,
            "cells_reachable": int(np.count_nonzero(np.isfinite(self.ratio))),
            "start_pixel": list(self.start),
            "goal_pixel": list(self.goal),
            "seconds": round(self.seconds, 4),
        }


def corridor(
    planner: Planner,
    start: Sequence[int],
    goal: Sequence[int],
    within: float,
    *,
    labels: Sequence[str] | None = None,
    progress: Progress | None = None,
) -> Corridor:
    """The least-cost corridor from ``start`` to ``goal`` (row, col) with the cells within
    ``within`` (a fraction: 0.1 = 10 %) of the optimum. Two whole-grid searches.

    PlanError for a point outside the grid or on a blocked cell, for start == goal (no optimum
    to divide by) and when no route joins them; InputError for ``within`` <= 0."""
    s = (int(start[0]), int(start[1]))
    g = (int(goal[0]), int(goal[1]))
    ls, lg = labels if labels is not None else (f"(row {s[0]}, col {s[1]})", f"(row {g[0]}, col {g[1]})")
    _check_ends(planner, s, g, ls, lg, within)
    t0 = time.perf_counter()
    if progress is not None:
        progress.begin("corridor", total=2, unit="search")
    try:
        from_start = cost_distance(planner, s, label=ls, progress=progress)
        optimum = float(from_start[g])
        if not math.isfinite(optimum):
            raise PlanError(f"no path from start {ls} to goal {lg}: lethal or nodata cells separate them")
        if optimum <= 0:
            raise PlanError("the optimal route costs 0 (zero costs and --base-cost-per-m 0): no ratio to take")
        if progress is not None:
            progress.advance(1)
        planner.expand(g, label=lg, progress=progress)
        from_goal = _raw_field(planner)
        ratio, mask = _combine(from_start, from_goal, optimum, within)
        if progress is not None:
            progress.advance(1)
    finally:
        if progress is not None:
            progress.end()
    return Corridor(ratio, mask, optimum, within, s, g, time.perf_counter() - t0)


def _check_ends(planner: Planner, s: tuple[int, int], g: tuple[int, int], ls: str, lg: str, within: float) -> None:
    """One-line errors, before any search, for a bad ``within`` or end point."""
    if not (math.isfinite(within) and within > 0):
        raise InputError(f"--within must be a percentage > 0, not {100.0 * within:g}")
    for name, label, (r, c) in (("start", ls, s), ("goal", lg, g)):
        why = planner.grid.blocked_reason(r, c)
        if why == "outside":
            raise PlanError(f"{name} {label} is outside the costmap ({planner.shape[1]} x {planner.shape[0]} pixels)")
        if why is not None:
            raise PlanError(f"{name} {label} is on a {why} cell; move it onto passable ground")
    if s == g:
        raise PlanError(f"start {ls} and goal {lg} are the same cell: a corridor needs two places")


def _combine(
    from_start: np.ndarray, from_goal: np.ndarray, optimum: float, within: float
) -> tuple[np.ndarray, np.ndarray]:
    """(ratio float32, mask uint8) from the two float64 fields, a band of rows at a time."""
    h, w = from_start.shape
    ratio = np.empty((h, w), dtype=np.float32)
    mask = np.empty((h, w), dtype=np.uint8)
    limit = 1.0 + within
    for r0 in range(0, h, CHUNK_ROWS):
        r1 = min(h, r0 + CHUNK_ROWS)
        total = from_start[r0:r1] + from_goal[r0:r1]  # inf / ~1.4e306 + x where unreached
        reach = (total < UNVISITED) & np.isfinite(total)
        rel = np.where(reach, total / optimum, np.nan)
        ratio[r0:r1] = rel
        mask[r0:r1] = reach & (rel <= limit)
    return ratio, mask


# ------------------------------------------------------------------------------------------------
# The stage: `overseec corridor`
# ------------------------------------------------------------------------------------------------


def mask_path(out: str | Path) -> Path:
    """The within-PCT mask written beside the ratio raster: ``C.tif`` -> ``C-within.tif``."""
    out = Path(out)
    stem = out.name[: -len(out.suffix)] if out.suffix else out.name
    return out.with_name(f"{stem}{runfiles.CORRIDOR_MASK_SUFFIX}")


@dataclass(frozen=True)
class CorridorOptions:
    """What `overseec corridor` computes and where it writes it.

    ``start``/``goal`` are (x, y) in ``crs`` (None = the costmap's CRS); ``within_pct`` the
    percentage over the optimum (10 = routes up to 10 % dearer); ``mask_out`` None =
    :func:`mask_path` of ``out``.
    """

    costmap: Path
    start: tuple[float, float]
    goal: tuple[float, float]
    within_pct: float
    out: Path
    mask_out: Path | None = None
    crs: str | None = None
    base_cost_per_m: float = DEFAULT_BASE_COST_PER_M
    lethal: Path | None = None
    lethal_threshold: float | None = None
    band: int | None = None
    overrides: tuple[Path, ...] = ()

    def __post_init__(self) -> None:
        if not (math.isfinite(self.within_pct) and self.within_pct > 0):
            raise InputError(f"--within must be a percentage > 0, not {self.within_pct:g}")
        if self.crs is not None:
            parse_crs(self.crs)

    @property
    def mask_file(self) -> Path:
        """Where the mask goes."""
        return Path(self.mask_out) if self.mask_out is not None else mask_path(self.out)

    def inputs(self) -> list[Path]:
        """The files read (never written over)."""
        return [p for p in (self.costmap, self.lethal, *self.overrides) if p is not None]


@dataclass(frozen=True)
class CorridorRunResult:
    """A computed corridor and the files written for it."""

    corridor: Corridor
    outputs: dict[str, Path]
    timings: dict[str, float]

    def to_json(self) -> dict[str, Any]:
        """`overseec corridor --json`."""
        return {
            **self.corridor.to_json(),
            "outputs": {k: str(v) for k, v in self.outputs.items()},
            "timings": self.timings,
        }


def _load(o: CorridorOptions, inputs: list[Path]) -> tuple[PlanningGrid, Any, Any]:
    """The costmap with its overrides applied in memory, the overrides and their counts."""
    from overseec_core.plan.overrides import with_overrides

    grid = load_costmap(o.costmap, lethal_path=o.lethal, lethal_threshold=o.lethal_threshold, band=o.band)
    if grid.grid is None:
        raise OutputError("a corridor raster needs a georeferenced costmap")
    return with_overrides(grid, o.overrides)


def write_corridor(
    ratio_out: Path, mask_out: Path, grid: PlanningGrid, c: Corridor, base_cost_per_m: float, inputs: list[Path]
) -> None:
    """The ratio GeoTIFF (float32, NaN nodata) and the mask GeoTIFF (uint8 0/1) on the costmap's grid."""
    g = grid.need_grid()
    tags = {
        "OVERSEEC_CORRIDOR_OPTIMUM": repr(c.optimum),
        "OVERSEEC_CORRIDOR_WITHIN_PCT": repr(100.0 * c.within),
        "OVERSEEC_START_ROW": str(c.start[0]),
        "OVERSEEC_START_COL": str(c.start[1]),
        "OVERSEEC_GOAL_ROW": str(c.goal[0]),
        "OVERSEEC_GOAL_COL": str(c.goal[1]),
        "OVERSEEC_BASE_COST_PER_M": repr(base_cost_per_m),
    }
    if grid.source:
        tags["OVERSEEC_COSTMAP_FILE"] = Path(grid.source).name
    for path, array, dtype, nodata, name in (
        (ratio_out, c.ratio, "float32", math.nan, "corridor_ratio"),
        (mask_out, c.mask, "uint8", None, f"within_{100.0 * c.within:g}_pct"),
    ):
        with RasterWriter(path, g, 1, dtype, nodata=nodata, descriptions=[name], tags=tags, inputs=inputs) as w:
            step = max(1, w.block_rows)
            for r0 in range(0, grid.height, step):
                w.write(array[r0 : r0 + step], r0)


@transactional
def run_corridor(
    options: CorridorOptions, progress: Progress | None = None, command_args: dict | None = None
) -> CorridorRunResult:
    """Costmap + start and goal (any CRS) -> the corridor ratio and mask GeoTIFFs, recorded in
    the output folder's manifest (costmap hashed, parameters, figures, timings)."""
    from overseec_core.plan.stage import points_to_pixels, record_costmap_inputs

    o = options
    targets = {"corridor": Path(o.out), "mask": o.mask_file}
    if targets["corridor"].resolve() == targets["mask"].resolve():
        raise InputError("the corridor and its mask have the same path; give each output its own file")
    for path in targets.values():
        check_output_path(path, o.inputs())
    t0 = time.perf_counter()
    grid, overrides, counts = _load(o, o.inputs())
    inputs = o.inputs() + ([Path(grid.lethal_source)] if grid.lethal_source else [])
    for path in targets.values():
        check_output_path(path, inputs)
    pixels, labels = points_to_pixels(grid, (o.start, o.goal), o.crs)
    t1 = time.perf_counter()
    planner = Planner(grid, o.base_cost_per_m)
    c = corridor(planner, pixels[0], pixels[1], o.within_pct / 100.0, labels=labels, progress=progress)
    t2 = time.perf_counter()
    write_corridor(targets["corridor"], targets["mask"], grid, c, o.base_cost_per_m, inputs)
    timings = {
        "load_s": round(t1 - t0, 4),
        "corridor_s": round(t2 - t1, 4),
        "write_s": round(time.perf_counter() - t2, 4),
        "total_s": round(time.perf_counter() - t0, 4),
    }
    run = RunDir(targets["corridor"].parent, command="corridor", args=command_args)
    record_costmap_inputs(run, "corridor", o.costmap, grid, (overrides, counts), progress)
    run.update_parameters(
        corridor={
            "within_pct": o.within_pct,
            "base_cost_per_m": o.base_cost_per_m,
            "lethal_threshold": o.lethal_threshold,
            "crs": o.crs,
            "start": list(o.start),
            "goal": list(o.goal),
        }
    )
    run.set(
        "corridor",
        {**c.to_json(), "outputs": {k: p.name for k, p in targets.items()}, "timings": timings},
    )
    run.save()
    return CorridorRunResult(c, targets, timings)


__all__ = [
    "Corridor",
    "CorridorOptions",
    "CorridorRunResult",
    "corridor",
    "cost_distance",
    "cost_distance_many",
    "costs_to",
    "mask_path",
    "run_corridor",
    "write_corridor",
]
