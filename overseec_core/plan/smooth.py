"""Line-of-sight smoothing of a planned grid route (``overseec plan --smooth``).

The planner's route is an 8-connected chain of pixel centres: a staircase wherever the best
direction is not a multiple of 45 degrees. Smoothing replaces runs of it by straight segments
between its own vertices (string pulling), as long as each segment

- touches only passable cells: every cell the closed segment meets, corners included (a
  segment through a lattice corner must find all four cells around it passable; whether it
  passes through one is decided in integer arithmetic, so rounding can never hide a touch),
  so it never grazes a lethal, nodata or keep-out cell;
- costs at most ``(1 + tolerance)`` times the part of the grid route it replaces.

**Cost of a segment: the cell integral.** The costmap is taken as piecewise constant on its
cells; a segment costs the sum over the cells it crosses of ``(cell cost + base cost per metre)
x the ground length of the segment inside that cell`` (an exact grid traversal in the manner of
Amanatides & Woo, in metres with non-square pixels). The planner prices a step between
neighbouring centres with the mean of the two cells' costs; **for such a step both rules give
the same number** (the step spends exactly half its length in each end cell; a diagonal step's
two other corner cells get a zero length), so the grid route's integral cost equals its planner
cost up to rounding. The comparison is therefore made honestly under one rule: each shortcut's
integral cost against the integral cost of the grid steps it replaces, so the smoothed route's
integral cost is at most ``(1 + tolerance)`` times the grid route's integral cost. Both are
reported, with the grid route's planner-rule cost beside them.

**Algorithm.** Greedy farthest-feasible shortcutting, one leg at a time (the start, via points
and goal stay vertices). First, for every vertex at once, the jumps of 2..:data:`SHORT` steps
and of :data:`PROBE_JUMPS` steps are tested in a few vectorised batches, so rough or cluttered
ground, where most shortcuts fail, never turns into a Python loop of small array operations per
vertex. The greedy walk then jumps to the farthest allowed of those; where the longest short
jump or a probe passes, every vertex up to :data:`WINDOW` steps ahead is tested (allowed jumps
come in sparse runs, e.g. along a road, so the farthest one is looked for, not the first
refusal), then the look-ahead doubles while its farthest candidate passes, with at most
:data:`WINDOW` sampled candidates per round (one vectorised traversal each): a long straight
stretch becomes one segment at a cost that grows with its length, not its square. A single grid
step is always allowed (it is the planner's own move, even where it cuts between two diagonal
lethal cells, which the stricter shortcut rule refuses). The work is ``O(route pixels x
(SHORT^2 + sum(PROBE_JUMPS)))`` cells plus, per kept vertex, ``O(WINDOW x jump x log jump)``;
on the 10000^2 bench costmap it is a few % of the exact plan (bench/bench_smooth.py).
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from overseec_core.errors import Cancelled, InputError
from overseec_core.plan.grid import PlanningGrid
from overseec_core.plan.paths import path_length_m
from overseec_core.plan.result import PathResult
from overseec_core.progress import Progress

#: Default cost tolerance of --smooth: 1 % above the grid route's (integral) cost.
DEFAULT_TOLERANCE = 0.01
#: Jumps of up to this many grid steps are tested for every vertex at once (one batch).
SHORT = 8
#: Longer jumps also tested for every vertex at once: where one passes, the greedy walk looks
#: at every vertex up to WINDOW steps ahead. (16, 32, 64) kept about as few vertices as six
#: probes (12..64) in half the time; without probes, 3-40x more vertices stayed at tolerance 0.
PROBE_JUMPS = (16, 32, 64)
#: Segments per batch of those tests (bounds their temporary memory to some tens of MB).
BATCH_SEGMENTS = 1 << 14
#: Most candidate end vertices tested per round of the doubling look-ahead beyond SHORT.
WINDOW = 64
#: Price of an impassable cell in :func:`segment_costs`, so a segment's cost stays finite (its
#: caller refuses the segment anyway). The grid steps of a route that had to enter a keep-out zone
#: are priced at the zone cells' own costs instead (:func:`grid_step_costs` with ``own``), like
#: :class:`~overseec_core.plan.stage.RulePlanner` reports them.
IMPASSABLE_STEP_PRICE = 1.0
COST_RULE = "cell integral: sum over crossed cells of (cell cost + base) x length inside the cell"


@dataclass(frozen=True)
class SmoothedRoute:
    """A grid route after line-of-sight smoothing, with both routes' figures.

    ``vertices`` (M, 2) int64 (row, col): pixel centres, a subsequence of the grid route's
    pixels (``indices`` into them), the start, via points and goal included. ``cost`` is the
    cell-integral cost of the straight segments, ``grid_cost_integral`` the grid route's under
    the same rule, ``grid_cost`` its planner (mean-of-two-cells) cost.
    """

    vertices: np.ndarray
    indices: np.ndarray
    tolerance: float
    cost: float
    length_m: float
    leg_costs: tuple[float, ...]
    grid_cost: float
    grid_cost_integral: float
    grid_length_m: float
    grid_vertices: int
    seconds: float

    @property
    def cost_change(self) -> float:
        """(smoothed - grid) / grid, both under the cell-integral rule (0 for a free route)."""
        g = self.grid_cost_integral
        return 0.0 if g <= 0 else (self.cost - g) / g

    def to_json(self) -> dict[str, Any]:
        """Both routes' vertices, length and cost, as plain JSON types (manifest, --json)."""
        return {
            "tolerance": self.tolerance,
            "cost_rule": COST_RULE,
            "smoothed": {
                "n_vertices": int(len(self.vertices)),
                "length_m": self.length_m,
                "cost": self.cost,
                "leg_costs": list(self.leg_costs),
            },
            "grid": {
                "n_vertices": self.grid_vertices,
                "length_m": self.grid_length_m,
                "cost": self.grid_cost,
                "cost_integral": self.grid_cost_integral,
            },
            "cost_change": self.cost_change,
            "seconds": round(self.seconds, 6),
        }

    def properties(self) -> dict[str, Any]:
        """Path-output properties when the geometry is the smoothed line: the top-level
        figures describe that line, ``grid_route`` summarises the planner's pixel route."""
        return {
            "route": "smoothed",
            "total_cost": self.cost,
            "length_m": self.length_m,
            "n_vertices": int(len(self.vertices)),
            "leg_costs": list(self.leg_costs),
            "cost_rule": COST_RULE,
            "grid_route": {
                "n_vertices": self.grid_vertices,
                "length_m": self.grid_length_m,
                "cost": self.grid_cost,
                "cost_integral": self.grid_cost_integral,
                "cost_rule": "planner: (mean of the two cells' costs + base) x step",
            },
            "smoothing": {
                "tolerance": self.tolerance,
                "cost_change": self.cost_change,
                "seconds": round(self.seconds, 6),
            },
        }


# ------------------------------------------------------------------------------------------------
# Tolerance parsing
# ------------------------------------------------------------------------------------------------


def parse_tolerance(text: str) -> float:
    """A cost tolerance from '0.02' (a fraction) or '2%'; refuses values above 100 %.

    Why refuse ``--smooth 5``: it almost certainly means 5 %, and silently allowing a route five
    times costlier would be worse than a one-line error.
    """
    s = str(text).strip()
    percent = s.endswith("%")
    try:
        value = float(s[:-1] if percent else s)
    except ValueError:
        raise InputError(
            f"smoothing tolerance {text!r} is not a number; give a fraction (0.01) or a percentage (1%)"
        ) from None
    if percent:
        value /= 100.0
    if not (math.isfinite(value) and 0.0 <= value <= 1.0):
        raise InputError(f"smoothing tolerance {text!r} must be between 0 and 1 (a fraction: 0.01 = 1 %) or 0%..100%")
    return value


def tolerance_arg(text: str) -> float:
    """argparse type for ``--smooth [TOL]``: :func:`parse_tolerance` with argparse's error."""
    try:
        return parse_tolerance(text)
    except InputError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


# ------------------------------------------------------------------------------------------------
# Exact cell traversal of many segments at once
# ------------------------------------------------------------------------------------------------


def _ragged(counts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For counts n_k: (segment id, 1-based rank m in 1..n_k) of every item, flattened."""
    total = int(counts.sum())
    seg = np.repeat(np.arange(len(counts)), counts)
    starts = np.cumsum(counts) - counts
    m = np.arange(total) - np.repeat(starts, counts) + 1
    return seg, m


def segment_costs(
    cost: np.ndarray, pixel_size_m: tuple[float, float], base_cost_per_m: float, starts: np.ndarray, ends: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Cell-integral cost and passability of straight segments between pixel centres.

    ``starts``/``ends`` (K, 2) int (row, col), or one start for all; returns (cost (K,) float64,
    passable (K,) bool). A segment from centre (r0 + .5, c0 + .5) to (r1 + .5, c1 + .5), with
    nr = |r1 - r0| and nc = |c1 - c0|, crosses the m-th vertical grid line at t = (2m - 1) /
    (2 nc) and the k-th horizontal one at (2k - 1) / (2 nr). Whether one comes before the other
    is an integer comparison, (2k - 1) nc vs (2m - 1) nr, so each crossing's rank in the merged
    order, and the cell the segment enters there, are computed exactly, without a sort and
    without rounding; the gaps between consecutive crossings are the cells' shares of the
    segment (Amanatides & Woo's traversal, for all segments at once). Equal products mean the
    segment passes through a lattice corner: the vertical crossing is ranked first (the
    zero-length piece between them lies in one corner cell) and the fourth cell around the
    corner is checked as well, so ``passable`` covers every cell the closed segment meets.
    Impassable cells are priced at :data:`IMPASSABLE_STEP_PRICE` so the cost stays finite
    (callers ignore the cost of an impassable segment, except for the grid route's own steps).
    """
    p1 = np.asarray(ends, dtype=np.int64).reshape(-1, 2)
    p0 = np.broadcast_to(np.asarray(starts, dtype=np.int64).reshape(-1, 2), p1.shape)
    k = len(p1)
    dx, dy = pixel_size_m
    r0, c0 = p0[:, 0], p0[:, 1]
    dr, dc = p1[:, 0] - r0, p1[:, 1] - c0
    sr, sc = np.sign(dr), np.sign(dc)
    nr, nc = np.abs(dr), np.abs(dc)
    length = np.hypot(dr * dy, dc * dx)
    n = nr + nc
    slots = n + 2  # t = 0, the crossings in order, t = 1
    off = np.cumsum(slots) - slots
    size = int(slots.sum())
    seg = np.repeat(np.arange(k), slots)
    t = np.empty(size)
    rows = np.empty(size, dtype=np.int64)
    cols = np.empty(size, dtype=np.int64)
    t[off], rows[off], cols[off] = 0.0, r0, c0
    last = off + n + 1
    t[last], rows[last], cols[last] = 1.0, p1[:, 0], p1[:, 1]

    sv, mv = _ragged(nc)  # vertical crossings: m-th column line of segment sv
    nrv, ncv = nr[sv], nc[sv]
    before = ((2 * mv - 1) * nrv + ncv - 1) // (2 * ncv)  # horizontal crossings strictly earlier
    at = off[sv] + mv + before
    t[at] = (mv - 0.5) / ncv
    rows[at], cols[at] = r0[sv] + sr[sv] * before, c0[sv] + sc[sv] * mv

    sh, kh = _ragged(nr)  # horizontal crossings: k-th row line of segment sh
    nrh, nch = nr[sh], nc[sh]
    upto = ((2 * kh - 1) * nch + nrh) // (2 * nrh)  # vertical crossings earlier or at the same t
    at = off[sh] + kh + upto
    t[at] = (kh - 0.5) / nrh
    rows[at], cols[at] = r0[sh] + sr[sh] * kh, c0[sh] + sc[sh] * upto
    corner = (upto > 0) & ((2 * upto - 1) * nrh == (2 * kh - 1) * nch)

    c = cost[rows, cols].astype(np.float64)
    blocked = ~np.isfinite(c)
    bad = np.bincount(seg, weights=blocked, minlength=k)
    if corner.any():  # the corner cell the pieces skip: row after the crossing, column before
        sk = sh[corner]
        fourth = cost[r0[sk] + sr[sk] * kh[corner], c0[sk] + sc[sk] * (upto[corner] - 1)]
        bad += np.bincount(sk, weights=~np.isfinite(fourth), minlength=k)
    c[blocked] = IMPASSABLE_STEP_PRICE
    piece = np.maximum(t[1:] - t[:-1], 0.0)  # the piece after each slot (ties: ~0)
    piece[last[:-1]] = 0.0  # from one segment's t = 1 to the next one's t = 0
    total = np.bincount(seg[:-1], weights=(c[:-1] + base_cost_per_m) * piece, minlength=k) * length
    return total, bad == 0


def grid_step_costs(
    cost: np.ndarray,
    pixel_size_m: tuple[float, float],
    base_cost_per_m: float,
    pixels: np.ndarray,
    own: np.ndarray | None = None,
) -> np.ndarray:
    """Cell-integral cost of each step of a pixel route (N - 1 values; equals the planner's
    mean-of-two-cells step cost up to rounding, see the module docstring).

    ``own`` (N,) is the costmap's own value at each pixel
    (:meth:`~overseec_core.plan.grid.PlanningGrid.own_cost`): a step with an end cell that
    ``cost`` makes impassable (a keep-out cell on a route that had to enter one) is priced with
    those values, ``(mean of the two own costs + base) x step length``, the cell integral of a
    grid step. Without ``own`` such a step gets :data:`IMPASSABLE_STEP_PRICE`."""
    px = np.asarray(pixels, dtype=np.int64).reshape(-1, 2)
    if len(px) < 2:
        return np.zeros(0)
    steps = segment_costs(cost, pixel_size_m, base_cost_per_m, px[:-1], px[1:])[0]
    if own is not None:
        ends = ~np.isfinite(cost[px[:, 0], px[:, 1]])
        hit = ends[:-1] | ends[1:]
        if hit.any():
            o = np.asarray(own, dtype=np.float64).reshape(-1)
            a, b = px[:-1][hit], px[1:][hit]
            d = (b - a).astype(np.float64)
            length = np.hypot(d[:, 0] * pixel_size_m[1], d[:, 1] * pixel_size_m[0])
            steps[hit] = (0.5 * (o[:-1][hit] + o[1:][hit]) + base_cost_per_m) * length
    return steps


# ------------------------------------------------------------------------------------------------
# Greedy shortcutting
# ------------------------------------------------------------------------------------------------


def _feasible(
    cost: np.ndarray,
    pixel_size_m: tuple[float, float],
    base: float,
    leg: np.ndarray,
    prefix: np.ndarray,
    i: int,
    cand: np.ndarray,
    tolerance: float,
) -> np.ndarray:
    """Which candidate end indices ``cand`` the segment from vertex ``i`` may jump to."""
    seg_cost, ok = segment_costs(cost, pixel_size_m, base, leg[i : i + 1], leg[cand])
    allowed = (1.0 + tolerance) * (prefix[cand] - prefix[i])
    return ok & (seg_cost <= allowed)


def _reach(
    cost: np.ndarray,
    pixel_size_m: tuple[float, float],
    base: float,
    leg: np.ndarray,
    prefix: np.ndarray,
    tolerance: float,
    jumps: Sequence[int],
) -> np.ndarray:
    """For every vertex i, the largest d of ``jumps`` such that i -> i + d is allowed (1 when
    none is: the grid step). All vertices at once, in chunks, so a route where shortcuts rarely
    pass (rough or cluttered ground) costs a few vectorised passes, not a Python loop of small
    array operations per vertex."""
    n = len(leg)
    reach = np.ones(n, dtype=np.int64)
    d = np.asarray(jumps, dtype=np.int64)
    chunk = max(1, BATCH_SEGMENTS // max(1, len(d)))
    for a in range(0, max(0, n - 2), chunk):
        i = np.arange(a, min(n - 2, a + chunk))
        ii, jj = np.repeat(i, len(d)), (i[:, None] + d[None, :]).ravel()
        keep = jj < n
        ii, jj = ii[keep], jj[keep]
        if not len(ii):
            break
        seg_cost, ok = segment_costs(cost, pixel_size_m, base, leg[ii], leg[jj])
        ok &= seg_cost <= (1.0 + tolerance) * (prefix[jj] - prefix[ii])
        np.maximum.at(reach, ii[ok], jj[ok] - ii[ok])
    return reach


def _next_vertex(
    cost: np.ndarray,
    pixel_size_m: tuple[float, float],
    base: float,
    leg: np.ndarray,
    prefix: np.ndarray,
    i: int,
    tolerance: float,
    window: int,
    reach: int,
    probe: int,
    short: int,
) -> int:
    """The farthest vertex the greedy rule jumps to from ``i`` (at least ``i + 1``).

    ``reach`` is the farthest allowed jump of at most ``short`` steps, ``probe`` the farthest
    allowed one of :data:`PROBE_JUMPS`. When either says longer jumps may pass, every vertex up
    to ``window`` steps ahead is tested, then the look-ahead doubles while its farthest
    candidate passes (at most ``window`` sampled candidates per round)."""
    last = len(leg) - 1
    best = i + max(reach, probe)
    if best >= last or (reach < short and probe <= reach):
        return min(best, last)
    cand = np.arange(i + reach + 1, min(last, i + max(window, 2 * (best - i))) + 1)
    while len(cand):
        ok = _feasible(cost, pixel_size_m, base, leg, prefix, i, cand, tolerance)
        if not ok.any():
            break
        best = max(best, int(cand[ok][-1]))
        if best != cand[-1] or best == last:
            break
        # the farthest candidate passed: look twice as far, sampling at most `window` ends
        hi = min(last, i + 2 * (best - i))
        cand = np.unique(np.linspace(best + 1, hi, num=min(window, hi - best)).round().astype(np.int64))
    return best


def smooth_leg(
    cost: np.ndarray,
    pixel_size_m: tuple[float, float],
    base_cost_per_m: float,
    leg: np.ndarray,
    tolerance: float = DEFAULT_TOLERANCE,
    window: int = WINDOW,
    short: int = SHORT,
    own: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Smooth one leg (pixel route between two consecutive waypoints).

    Returns (indices of the kept vertices into ``leg``, their segments' integral costs, the
    leg's grid step integral costs). Each kept segment costs at most ``(1 + tolerance)`` times
    the grid steps it replaces, so the leg's total does too. ``own``: the costmap's own value at
    each pixel of ``leg``, for grid steps in keep-out zones (see :func:`grid_step_costs`).
    """
    leg = np.asarray(leg, dtype=np.int64).reshape(-1, 2)
    steps = grid_step_costs(cost, pixel_size_m, base_cost_per_m, leg, own)
    if len(leg) < 3:
        return np.arange(len(leg)), steps, steps
    prefix = np.concatenate([[0.0], np.cumsum(steps)])
    reach = _reach(cost, pixel_size_m, base_cost_per_m, leg, prefix, tolerance, range(2, short + 1))
    probe = _reach(cost, pixel_size_m, base_cost_per_m, leg, prefix, tolerance, [d for d in PROBE_JUMPS if d > short])
    kept = [0]
    i = 0
    while i < len(leg) - 1:
        i = _next_vertex(
            cost, pixel_size_m, base_cost_per_m, leg, prefix, i, tolerance, window, int(reach[i]), int(probe[i]), short
        )
        kept.append(i)
    idx = np.asarray(kept, dtype=np.int64)
    seg = segment_costs(cost, pixel_size_m, base_cost_per_m, leg[idx[:-1]], leg[idx[1:]])[0]
    single = np.diff(idx) == 1  # kept grid steps: their own step cost, bit for bit
    seg[single] = steps[idx[:-1][single]]
    return idx, seg, steps


def waypoint_indices(pixels: np.ndarray, waypoints: Sequence[Sequence[int]]) -> list[int]:
    """Index of each waypoint in the route's pixels, in order (legs are joined end to start, so
    waypoint k+1 is the first occurrence of its pixel at or after waypoint k's index)."""
    px = np.asarray(pixels, dtype=np.int64).reshape(-1, 2)
    out: list[int] = []
    at = 0
    for r, c in waypoints:
        hits = np.flatnonzero((px[at:, 0] == r) & (px[at:, 1] == c))
        if not len(hits):
            raise InputError(f"waypoint (row {r}, col {c}) is not on the route")
        at += int(hits[0])
        out.append(at)
    if out[0] != 0 or out[-1] != len(px) - 1:
        raise InputError("the route does not start at its first waypoint and end at its last")
    return out


def smooth_route(
    result: PathResult,
    grid: PlanningGrid,
    base_cost_per_m: float,
    tolerance: float = DEFAULT_TOLERANCE,
    *,
    window: int = WINDOW,
    progress: Progress | None = None,
) -> SmoothedRoute:
    """Smooth ``result`` (planned on ``grid`` with ``base_cost_per_m``), each leg on its own.

    ``grid`` must be the strict grid (keep-out zones impassable): shortcuts never enter them,
    and a route that had to (a broken keep-out rule) keeps its grid steps there, priced at the
    zone cells' own costs (:meth:`~overseec_core.plan.grid.PlanningGrid.own_cost`) as the
    planner's result reports them, so ``grid_cost_integral`` matches ``result.cost``.
    """
    tol = float(tolerance)
    if not (math.isfinite(tol) and 0.0 <= tol <= 1.0):
        raise InputError(f"smoothing tolerance must be between 0 and 1, not {tolerance}")
    if int(window) < 1:
        raise InputError(f"smoothing window must be >= 1, not {window}")
    t0 = time.perf_counter()
    px = np.asarray(result.pixels, dtype=np.int64).reshape(-1, 2)
    marks = waypoint_indices(px, result.waypoints)
    cost, size = grid.cost, grid.pixel_size_m
    # the costmap's own values along the route: only a route through a keep-out zone needs them
    own = None
    if grid.keep_out is not None and grid.keep_out[px[:, 0], px[:, 1]].any():
        own = grid.own_cost(px)
    indices: list[np.ndarray] = [np.zeros(1, dtype=np.int64)]
    leg_costs: list[float] = []
    seg_costs: list[np.ndarray] = []
    step_costs: list[np.ndarray] = []
    if progress is not None:
        progress.begin("smooth", total=len(marks) - 1, unit="leg")
    try:
        for a, b in zip(marks[:-1], marks[1:]):
            if progress is not None and progress.cancelled():
                raise Cancelled("smoothing cancelled by the user")
            leg_own = None if own is None else own[a : b + 1]
            idx, seg, steps = smooth_leg(cost, size, base_cost_per_m, px[a : b + 1], tol, int(window), own=leg_own)
            indices.append(idx[1:] + a)
            seg_costs.append(seg)
            step_costs.append(steps)
            leg_costs.append(math.fsum(seg))
            if progress is not None:
                progress.advance(1)
    finally:
        if progress is not None:
            progress.end()
    index = np.concatenate(indices)
    vertices = px[index]
    return SmoothedRoute(
        vertices=vertices,
        indices=index,
        tolerance=tol,
        cost=math.fsum(np.concatenate(seg_costs)) if seg_costs else 0.0,
        length_m=polyline_length_m(vertices, size),
        leg_costs=tuple(leg_costs),
        grid_cost=float(result.cost),
        grid_cost_integral=math.fsum(np.concatenate(step_costs)) if step_costs else 0.0,
        grid_length_m=path_length_m(px, *size),
        grid_vertices=int(len(px)),
        seconds=time.perf_counter() - t0,
    )


def smooth_if_asked(
    result: PathResult,
    grid: PlanningGrid,
    base_cost_per_m: float,
    tolerance: float | None,
    progress: Progress | None = None,
) -> SmoothedRoute | None:
    """:func:`smooth_route` when a tolerance is given (``--smooth``), else None."""
    if tolerance is None:
        return None
    return smooth_route(result, grid, base_cost_per_m, tolerance, progress=progress)


def polyline_length_m(vertices: np.ndarray, pixel_size_m: tuple[float, float]) -> float:
    """Ground length of straight segments between pixel centres (metres, non-square pixels)."""
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 2)
    if len(v) < 2:
        return 0.0
    d = np.diff(v, axis=0)
    return math.fsum(np.hypot(d[:, 0] * pixel_size_m[1], d[:, 1] * pixel_size_m[0]))
