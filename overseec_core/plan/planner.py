"""Shortest paths on a :class:`PlanningGrid`: exact A* and a fast coarse-to-fine corridor mode.

Paths follow the step rule of :mod:`.paths`: 8 neighbours by default, or 16 (``neighbours=16``:
knight moves too, each priced by the exact cell integral of the four cells it crosses, never
through a lethal cell; routes run closer to straight lines). The hot loop is the C kernel in
``_kernel.c``; the fallback plans 8 neighbours only and refuses 16 in one line. With 16, fast
mode's lower bound is the straight-line one (the octile and block-hop bounds assume 8). A
:class:`Planner` allocates its working memory (float64 distance + one state byte per pixel, and
the kernel's heap) once; each query resets only the cells the previous query touched, so
interactive use (the QGIS map tool, ``overseec eval`` planning many pairs) never re-reads the
costmap or re-allocates per query. Without the kernel a Planner plans with the fallback
(:mod:`.backend` says which one and why).

Fast mode plans on a block-averaged copy of the costmap (k x k blocks, :mod:`.coarse`; the level it
builds once is :mod:`.fast`'s), then runs
the exact search restricted to a corridor of blocks around that coarse path, widening the corridor
twice and falling back to the exact search when the corridor holds no path. Its cost comes with a
guaranteed lower bound on the optimum (``PathResult.bound``; see :func:`.coarse.hop_offsets`).

Anisotropic mode (``elevation`` + ``slope_model``, :mod:`.paths` documents the rule and the
models): each step is priced by its 3D length times a multiplier of its signed slope, so uphill and
downhill differ; ``length_m`` then counts the elevation change. The kernel plans it with A* whose
heuristic is scaled by the model's smallest multiplier (admissible: 3D length >= ground length),
on the radix heap (the bucket ring needs a largest step cost, which steep slopes do not have);
fast mode runs the exact search there (its coarse level and bounds know no slopes), and the
scikit-image fallback refuses it in one line (``MCP_Geometric`` prices a step by its two costs
only, the same both ways).
"""

from __future__ import annotations

import functools
import math
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TypeVar

import numpy as np

from overseec_core import defaults
from overseec_core.errors import Cancelled, InputError, PlanError
from overseec_core.plan import fallback
from overseec_core.plan.backend import NEIGHBOURS as NEIGHBOURS  # re-exported: callers check with the planner's rule
from overseec_core.plan.backend import (  # _kernel: None where it does not load
    UNVISITED,
    _kernel,
    checked_neighbours,
    checked_terrain,
    planner_backend,
    run_cancellable,
)
from overseec_core.plan.backend import check_neighbours as check_neighbours  # re-exported, as NEIGHBOURS
from overseec_core.plan.fast import FastLevel, build_fast_level, corridor_region, hop_bound, trace_tree
from overseec_core.plan.grid import PlanningGrid
from overseec_core.plan.paths import (
    DEFAULT_BASE_COST_PER_M,
    SLOPE_MIN,
    SLOPE_MODELS,
    as_points,
    cumulative_path_cost,
    finite_range,
    knight_lengths_m,
    octile_m,
    path_length_3d_m,
    path_length_m,
    point_names,
)
from overseec_core.plan.result import PathResult
from overseec_core.progress import Progress

_T = TypeVar("_T")
#: The note of a fast-mode request planned with a slope model (its exact search ran instead).
TERRAIN_FAST_NOTE = "fast mode has no slope model: the exact search was run"
MODES = defaults.PLAN_MODES
#: Most buckets in the kernel's bucket ring; a costmap that would need more uses the radix heap.
#: Defined (and its choice measured) in _kernel.c; 0 while the kernel is not built.
MAX_RING: int = _kernel.MAX_RING if _kernel is not None else 0


@dataclass
class _Leg:
    """One leg of a query (between two consecutive points): its path, cost, bound and notes."""

    pixels: np.ndarray
    cost: float
    bound: float
    mode: str
    expanded: int
    notes: list[str] = field(default_factory=list)


class Planner:
    """Plans paths on one loaded costmap, reusing its buffers across queries.

    Not thread-safe for concurrent queries (a lock serialises them); :meth:`cancel` may be
    called from any thread to stop a running query (it raises :class:`Cancelled`).
    """

    def __init__(
        self,
        grid: PlanningGrid,
        base_cost_per_m: float = DEFAULT_BASE_COST_PER_M,
        *,
        coarse_factor: int | None = None,
        corridor_blocks: int = 2,
        bound_hops: int = 3,
        tight_bound: bool = True,
        coarse_trees: int = 0,
        planner: str | None = None,
        neighbours: int = 8,
        elevation: np.ndarray | None = None,
        slope_model: str | None = None,
    ) -> None:
        #: What this one plans with (:func:`planner_backend` of ``planner``: 'auto', 'kernel' or
        #: 'fallback'; None = OVERSEEC_PLANNER); ``backend.name`` is 'kernel' or 'fallback'.
        self.backend = planner_backend(planner)
        if not isinstance(grid, PlanningGrid):
            raise InputError("Planner needs a PlanningGrid (see load_costmap / PlanningGrid.from_array)")
        base = float(base_cost_per_m)
        if not (math.isfinite(base) and base >= 0):
            raise InputError(f"base cost per metre must be a finite number >= 0, not {base_cost_per_m}")
        if coarse_factor is not None and int(coarse_factor) < 2:
            raise InputError(f"coarse factor must be >= 2, not {coarse_factor}")
        if int(corridor_blocks) < 1 or int(bound_hops) < 2:
            raise InputError("corridor_blocks must be >= 1 and bound_hops >= 2")
        #: 8 (straight and diagonal steps) or 16 (plus knight moves priced by the cell integral).
        self.neighbours = checked_neighbours(neighbours, self.backend.name)
        self.grid = grid
        self.base_cost_per_m = base
        self.coarse_factor = None if coarse_factor is None else int(coarse_factor)
        self.corridor_blocks = int(corridor_blocks)
        self.bound_hops = int(bound_hops)
        #: Fast mode's lower bound: the block-hop search (tight, about half a 4000² fast query)
        #: or only the octile bound (weaker, free) for interactive re-plans that never show it.
        self.tight_bound = bool(tight_bound)
        #: Fast mode keeps up to this many whole coarse shortest-path trees, rooted at points the
        #: previous query also had (the ends that stay put while a user drags a via or the goal),
        #: so a re-plan reads the coarse route off a tree instead of searching (0 = never).
        self.coarse_trees = max(0, int(coarse_trees))
        self._last_points: frozenset[tuple[int, int]] = frozenset()
        self._cost = grid.cost
        if not (self._cost.dtype == np.float32 and self._cost.flags.c_contiguous):
            raise InputError("PlanningGrid.cost must be C-contiguous float32")
        h, w = self._cost.shape
        if h * w >= 2**32 - 1:
            raise PlanError(
                f"the costmap has {h * w} cells; the planner handles fewer than 2^32 (crop or downsample it)"
            )
        self._shape = (h, w)
        #: Anisotropic mode: (H*W) float32 elevations (NaN: no elevation, never entered) and the
        #: slope model's name; None without a DEM.
        self.elevation, self.slope_model = checked_terrain(elevation, slope_model, (h, w), self.backend.name)
        self._dx, self._dy = grid.pixel_size_m
        self._diag = math.hypot(self._dx, self._dy)
        self._cancel = np.zeros(1, dtype=np.uint8)
        #: The fallback's search (built on its first query); None with the kernel.
        self._mcp: fallback.McpSearch | None = None
        if self.backend.name == "kernel":
            try:
                self._dist = np.empty(h * w, dtype=np.float64)
                self._state = np.zeros(h * w, dtype=np.uint8)
            except MemoryError:
                raise PlanError(
                    f"not enough memory to plan on a {w} x {h} costmap ({9 * h * w / 2**30:.1f} GiB of working memory)"
                ) from None
            # Marking every cell unvisited touches H x W x 8 bytes for the first time: on a
            # 7000² costmap 0.7 s of page faults. It runs in a thread (numpy's fill releases the
            # GIL) while the rest of the set-up and the fast level are built; searches wait for it.
            self._filling: threading.Thread | None = threading.Thread(
                target=self._dist.view(np.uint8).fill, args=(0x7F,), name="overseec-planner-buffers", daemon=True
            )
            self._filling.start()
            self._ws = _kernel.workspace()
        else:  # the fallback holds its own buffers (fallback.McpSearch)
            self._dist = np.empty(0, dtype=np.float64)
            self._state = np.empty(0, dtype=np.uint8)
            self._filling = None
            self._ws = None
        #: cells the last search wrote to, [r0, r1, c0, c1] inclusive (empty: r0 > r1)
        self._bbox = np.array([h, -1, w, -1], dtype=np.int64)
        self._dirty_region: np.ndarray | None = None
        self._dirty_k = 1
        self._expanded_from: int | None = None
        self._lock = threading.Lock()
        self._fast: FastLevel[Planner] | None = None
        low, high = finite_range(self._cost)
        #: A* heuristic: the cheapest possible cost per metre times the octile distance.
        self._hscale = low + base
        if self.slope_model is not None:  # every step costs at least its ground length x f's minimum
            self._hscale *= SLOPE_MIN[self.slope_model]
        # Bucket ring (exact Dijkstra with O(1) queue operations) when every step costs at least
        # `width` and the ring stays small; otherwise the radix heap with A*.
        width = (low + base) * min(self._dx, self._dy) * (1.0 - 1e-6)
        longest = max(self._diag, *knight_lengths_m(self._dx, self._dy)) if self.neighbours == 16 else self._diag
        ring = math.ceil((high + base) * longest / width) + 2 if width > 0 else 0
        self._ring = (width, ring) if width > 0 and ring <= MAX_RING and self.slope_model is None else (0.0, 0)

    # ---------------------------------------------------------------- introspection

    @property
    def shape(self) -> tuple[int, int]:
        return self._shape

    @property
    def buffers(self) -> dict[str, np.ndarray]:
        """The per-pixel working arrays (the same objects for the planner's whole life; empty
        with the fallback, which holds its own)."""
        self._buffers_ready()
        return {"dist": self._dist, "state": self._state}

    def _buffers_ready(self) -> None:
        """Wait until the per-pixel buffers are marked unvisited (see ``__init__``)."""
        if self._filling is not None:
            self._filling.join()
            self._filling = None

    def memory_bytes(self) -> dict[str, float]:
        """Bytes held: the costmap, the per-pixel buffers, the heap, the fast-mode level (with
        the fallback: the costmap and, once built, its search as 'fallback')."""
        if self.backend.name == "fallback":
            parts = {"cost": self._cost.nbytes, "fallback": 0 if self._mcp is None else self._mcp.nbytes()}
        else:
            parts = {
                "cost": self._cost.nbytes,
                "dist": self._dist.nbytes,
                "state": self._state.nbytes,
                "heap": _kernel.workspace_bytes(self._ws),
                "fast": 0 if self._fast is None else self._fast.nbytes(),
            }
        total = sum(parts.values())
        return {**parts, "total": total, "per_pixel": total / max(1, self._cost.size)}

    def cancel(self) -> None:
        """Ask a running query to stop (it raises Cancelled); safe from any thread."""
        self._cancel[0] = 1
        if self._mcp is not None:
            self._mcp.stop()

    # ---------------------------------------------------------------- queries

    def plan(  # noqa: C901
        self,
        points: Sequence[Sequence[int]],
        mode: str = "exact",
        *,
        labels: Sequence[str] | None = None,
        progress: Progress | None = None,
    ) -> PathResult:
        """Plan through ``points`` [(row, col), ...]: start, via points..., goal.

        ``labels`` name the points in error messages (e.g. their map coordinates); by default
        they are shown as pixel indices. Raises :class:`PlanError` for a point outside the grid,
        on a lethal or nodata cell, or when no path exists.
        """
        if mode not in MODES:
            raise InputError(f"unknown planning mode {mode!r}; use 'exact' or 'fast'")
        pts = as_points(points)
        if len(pts) < 2:
            raise InputError("planning needs at least a start and a goal")
        names = point_names(len(pts))
        if labels is None:
            labels = [f"(row {r}, col {c})" for r, c in pts]
        elif len(labels) != len(pts):
            raise InputError(f"{len(labels)} labels for {len(pts)} points")
        for name, label, (r, c) in zip(names, labels, pts):
            self._check_point(name, label, r, c)
        t0 = time.perf_counter()
        legs: list[_Leg] = []
        with self._lock:
            if progress is not None:
                progress.begin("plan", total=len(pts) - 1, unit="leg")
            try:
                for i in range(len(pts) - 1):
                    a, b = pts[i], pts[i + 1]
                    corridor = mode == "fast" and self.slope_model is None
                    leg = self._leg_fast(a, b, progress) if corridor else self._leg_exact(a, b, progress)
                    if leg is None:
                        raise PlanError(
                            f"no path from {names[i]} {labels[i]} to {names[i + 1]} "
                            f"{labels[i + 1]}: {self._what_separates(a, b)} separate them"
                        )
                    legs.append(leg)
                    if progress is not None:
                        progress.advance(1)
            finally:
                if progress is not None:
                    progress.end()
            self._last_points = frozenset(pts)
        pixels = np.concatenate([legs[0].pixels] + [leg.pixels[1:] for leg in legs[1:]])
        notes: list[str] = []
        for leg in legs:
            notes.extend(n for n in leg.notes if n not in notes)
        if self.backend.name == "fallback":
            fast = fallback.FAST_NOTE.format(slowdown=fallback.FAST_SLOWDOWN) if mode == "fast" else ""
            notes.append(self.backend.note + fast)
        cost = float(math.fsum(leg.cost for leg in legs))
        bound = min(cost, float(math.fsum(leg.bound for leg in legs)))
        if self.slope_model is not None and mode == "fast":
            notes.append(TERRAIN_FAST_NOTE)
        return PathResult(
            pixels=pixels,
            cost=cost,
            length_m=self.path_length_m(pixels),
            mode="fast" if any(leg.mode == "fast" for leg in legs) else "exact",
            bound=bound,
            seconds=time.perf_counter() - t0,
            waypoints=tuple(pts),
            leg_costs=tuple(leg.cost for leg in legs),
            requested_mode=mode,
            expanded=sum(leg.expanded for leg in legs),
            notes=tuple(notes),
        )

    def expand(self, point: Sequence[int], *, label: str | None = None, progress: Progress | None = None) -> int:
        """Cost-distance from ``point`` to every reachable cell; returns how many were reached.

        The distances stay in the planner until the next query; read them with
        :meth:`cumulative_rows`.
        """
        ((r, c),) = as_points([point])
        self._check_point("start", label or f"(row {r}, col {c})", r, c)
        with self._lock:
            if self.backend.name == "fallback":
                self._expanded_from = None
                # built inside the cancellable call: a cancel while the search is built is seen too
                status, reached = self._run(lambda: self._fallback().expand((r, c)), progress)
                if status == fallback.CANCELLED:
                    raise Cancelled("planning cancelled by the user")
                self._expanded_from = r * self._shape[1] + c
                return reached
            status, _d, settled = self._search(r * self._shape[1] + c, -1, None, 1, 0.0, progress)
            self._expanded_from = r * self._shape[1] + c
        return settled + 1

    def cumulative_rows(self, r0: int, r1: int) -> np.ndarray:
        """Rows r0:r1 of the cost-distance raster from :meth:`expand` (float32, NaN unreachable)."""
        if self._expanded_from is None:
            raise PlanError("no cost-distance available: call expand(point) first")
        if self._mcp is not None:
            rows = self._mcp.cumulative_rows(r0, r1)
            if rows is None:
                raise PlanError("no cost-distance available: call expand(point) first")
            return rows
        h, w = self._shape
        self._buffers_ready()
        rows = self._dist.reshape(h, w)[r0:r1]
        return np.where(rows >= UNVISITED, np.nan, rows).astype(np.float32)

    def cumulative(self, point: Sequence[int]) -> np.ndarray:
        """The whole cost-distance raster from ``point`` (float32 (H, W), NaN unreachable)."""
        self.expand(point)
        return self.cumulative_rows(0, self._shape[0])

    def prepare_fast(self) -> None:
        """Build the coarse level fast mode uses (done on the first fast query otherwise); with
        the fallback, its search (fast mode runs the exact search there)."""
        with self._lock:
            if self.backend.name == "fallback":
                self._run(self._fallback, None)  # the cancel flag of an earlier query cleared first
            else:
                self._fast_level()

    # ---------------------------------------------------------------- path helpers

    def path_length_m(self, pixels: np.ndarray) -> float:
        """Length in metres of a pixel path (8-neighbour and knight steps): on the ground, or in
        3D (counting the elevation change) in anisotropic mode."""
        if self.elevation is not None:
            return path_length_3d_m(pixels, self._dx, self._dy, self.elevation.reshape(self._shape))
        return path_length_m(pixels, self._dx, self._dy)

    def path_length_2d_m(self, pixels: np.ndarray) -> float:
        """Ground (map) length in metres of a pixel path, whatever the mode."""
        return path_length_m(pixels, self._dx, self._dy)

    def path_cost(self, pixels: np.ndarray) -> float:
        """Cost of any pixel path of 8-neighbour and knight steps under this planner's step rule
        (inf if blocked)."""
        elevation = None if self.elevation is None else self.elevation.reshape(self._shape)
        return float(
            cumulative_path_cost(
                self.grid, pixels, self.base_cost_per_m, elevation=elevation, slope_model=self.slope_model
            )[-1]
        )

    # ---------------------------------------------------------------- internals

    def _what_separates(self, a: tuple[int, int], b: tuple[int, int]) -> str:
        """Why no route joins ``a`` and ``b`` (a failed leg): the vehicle slope model's steepest
        grade when a route exists on the flat grid (one more search, on the failure path only),
        else lethal or no-data cells."""
        if self.slope_model == "vehicle" and self.elevation is not None:
            from overseec_core.plan.paths import VEHICLE_MAX

            # the same ground on the flat, cells without elevation still closed
            open_z = np.isfinite(self.elevation.reshape(self._shape))
            cost = np.where(open_z, self.grid.cost, np.inf).astype(np.float32)
            level = PlanningGrid.from_array(cost, pixel_size_m=self.grid.pixel_size_m)
            flat = Planner(level, self.base_cost_per_m, neighbours=self.neighbours, planner=self.backend.name)
            try:
                flat.plan([a, b], mode="exact")
            except PlanError:
                return "lethal or nodata cells"
            return (
                f"slopes steeper than the vehicle model drives ({VEHICLE_MAX:.0%} either way; "
                "--slope-model tobler has no limit)"
            )
        return "lethal or nodata cells"

    def _check_point(self, name: str, label: str, r: int, c: int) -> None:
        why = self.grid.blocked_reason(r, c)
        if why == "outside":
            h, w = self._shape
            raise PlanError(f"{name} {label} is outside the costmap ({w} x {h} pixels)")
        if why is not None:
            raise PlanError(f"{name} {label} is on a {why} cell; move it onto passable ground")
        if self.elevation is not None and not math.isfinite(float(self.elevation[r * self._shape[1] + c])):
            raise PlanError(f"{name} {label} has no elevation in the DEM (outside it or nodata); move it onto the DEM")

    def _run(self, call: Callable[[], _T], progress: Progress | None) -> _T:
        """Run a kernel call; with a Progress, a watcher thread forwards its cancel request."""
        return run_cancellable(call, self._cancel, progress, on_cancel=self.cancel)

    def _reset_dirty(self) -> None:
        """Mark unvisited again the cells the last search wrote (its bbox, within its corridor).

        Must run before the corridor buffer is refilled: the reset reads the last corridor.
        """
        h, w = self._shape
        self._buffers_ready()
        _kernel.reset(self._dist, self._state, h, w, self._bbox, self._dirty_region, self._dirty_k)
        self._bbox[:] = (h, -1, w, -1)
        self._dirty_region, self._dirty_k = None, 1
        self._expanded_from = None

    def _search(
        self, start: int, goal: int, region: np.ndarray | None, k: int, hscale: float, progress: Progress | None
    ) -> tuple[int, float, int]:
        self._reset_dirty()
        self._dirty_region, self._dirty_k = region, k
        width, ring = self._ring
        try:
            status, dist, settled, _pushed = self._run(
                functools.partial(
                    _kernel.search,
                    cost=self._cost,
                    dist=self._dist,
                    state=self._state,
                    workspace=self._ws,
                    dx=self._dx,
                    dy=self._dy,
                    base=self.base_cost_per_m,
                    start=start,
                    cancel=self._cancel,
                    bbox=self._bbox,
                    hscale=hscale,
                    width=width,
                    ring=ring,
                    goal=goal,
                    region=region,
                    region_k=k,
                    neighbours=self.neighbours,
                    elevation=self.elevation,
                    slope_model=0 if self.slope_model is None else SLOPE_MODELS[self.slope_model],
                ),
                progress,
            )
        except MemoryError:
            raise PlanError(
                "ran out of memory for the search queue; close other programs or plan on a smaller costmap"
            ) from None
        if status == 2:
            raise Cancelled("planning cancelled by the user")
        return status, dist, settled

    def _fallback(self) -> fallback.McpSearch:
        """The fallback's search on this costmap, built on first use."""
        if self._mcp is None:
            try:
                self._mcp = fallback.McpSearch(self._cost, self.base_cost_per_m, self._dx, self._dy, self._cancel)
            except fallback.BuildCancelled:
                raise Cancelled("planning cancelled by the user") from None
            except MemoryError:
                h, w = self._shape
                raise PlanError(
                    f"not enough memory for the fallback planner on a {w} x {h} costmap "
                    f"(about {70 * h * w / 2**30:.1f} GiB while it is built)"
                ) from None
        return self._mcp

    def _leg_fallback(self, a: tuple[int, int], b: tuple[int, int], progress: Progress | None) -> _Leg | None:
        self._expanded_from = None
        status, pixels, cost, reached = self._run(lambda: self._fallback().leg(a, b), progress)
        if status == fallback.CANCELLED:
            raise Cancelled("planning cancelled by the user")
        if status != fallback.FOUND or pixels is None:
            return None
        return _Leg(pixels, cost, cost, "exact", reached)

    def _leg_exact(
        self, a: tuple[int, int], b: tuple[int, int], progress: Progress | None, notes: Sequence[str] = ()
    ) -> _Leg | None:
        if self.backend.name == "fallback":
            return self._leg_fallback(a, b, progress)
        w = self._shape[1]
        ia, ib = a[0] * w + a[1], b[0] * w + b[1]
        status, dist, settled = self._search(ia, ib, None, 1, self._hscale, progress)
        if status != 0:
            return None
        pixels = _kernel.trace(self._state, self._shape[0], w, ib)
        return _Leg(pixels, dist, dist, "exact", settled, list(notes))

    def _leg_fast(self, a: tuple[int, int], b: tuple[int, int], progress: Progress | None) -> _Leg | None:
        if self.backend.name == "fallback":  # no corridor search without the kernel: exact
            return self._leg_fallback(a, b, progress)
        fl = self._fast_level()
        k, w = fl.k, self._shape[1]
        if a == b:
            return self._leg_exact(a, b, progress)
        coarse = self._coarse_route(fl, a, b, progress)
        if coarse is None:
            # every block a fine path crosses holds a passable cell, so no coarse path = no path
            return None
        ia, ib = a[0] * w + a[1], b[0] * w + b[1]
        radius = self.corridor_blocks
        for attempt in range(3):
            self._reset_dirty()
            region = corridor_region(fl, coarse, radius)
            status, dist, settled = self._search(ia, ib, region, k, self._hscale, progress)
            if status == 0:
                pixels = _kernel.trace(self._state, self._shape[0], w, ib)
                bound = min(dist, self._lower_bound(fl, a, b))
                notes = [] if attempt == 0 else [f"fast: corridor widened to {radius} blocks"]
                return _Leg(pixels, dist, bound, "fast", settled, notes)
            radius *= 2
        return self._leg_exact(a, b, progress, notes=["fast: no path inside the corridor; exact search used"])

    def _coarse_route(
        self, fl: FastLevel[Planner], a: tuple[int, int], b: tuple[int, int], progress: Progress | None
    ) -> np.ndarray | None:
        """Blocks of the cheapest coarse route between a's and b's blocks (None: no route).

        Read off a kept coarse tree rooted at either end when there is one (or grown there when
        that end was a point of the previous query too); searched otherwise."""
        k = fl.k
        ends = ((a[0] // k, a[1] // k), a), ((b[0] // k, b[1] // k), b)
        if self.coarse_trees:
            for (root, _), (other, _) in (ends, ends[::-1]):
                if root in fl.trees:
                    fl.trees.move_to_end(root)
                    return trace_tree(fl.trees[root], other)
            for (root, point), (other, _) in (ends, ends[::-1]):
                if point in self._last_points:
                    return trace_tree(self._grow_tree(fl, root, progress), other)
        leg = fl.coarse._leg_exact(ends[0][0], ends[1][0], progress)
        return None if leg is None else leg.pixels

    def _grow_tree(self, fl: FastLevel[Planner], root: tuple[int, int], progress: Progress | None) -> Planner:
        """A whole coarse shortest-path tree from ``root`` (the oldest tree's buffers reused)."""
        if len(fl.trees) >= self.coarse_trees:
            _old, tree = fl.trees.popitem(last=False)
        else:
            tree = Planner(fl.coarse.grid, self.base_cost_per_m, planner="kernel")
        tree.expand(root, progress=progress)
        fl.trees[root] = tree
        return tree

    def _lower_bound(self, fl: FastLevel[Planner], a: tuple[int, int], b: tuple[int, int]) -> float:
        """max(octile bound, block-hop bound) on the optimal cost from a to b (the octile bound
        alone when the planner was made with ``tight_bound=False``)."""
        if self.neighbours == 16:  # knight steps beat octile lengths; the hop bound assumes 8
            return self._hscale * math.hypot((a[0] - b[0]) * self._dy, (a[1] - b[1]) * self._dx)
        octile = self._hscale * octile_m(abs(a[0] - b[0]), abs(a[1] - b[1]), self._dx, self._dy)
        if not self.tight_bound:
            return octile
        return max(octile, hop_bound(fl, a, b, self.bound_hops, self._ws))

    def _fast_level(self) -> FastLevel[Planner]:
        if self._fast is None:
            self._fast = build_fast_level(
                self._cost,
                (self._dx, self._dy),
                self.base_cost_per_m,
                self.bound_hops,
                self.coarse_factor,
                lambda grid: Planner(grid, self.base_cost_per_m, planner="kernel"),  # fast mode is the kernel's
            )
        return self._fast
