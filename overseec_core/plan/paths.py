"""Pixel paths under the planner's step rule: points, step lengths, path lengths and costs.

Step rule (the same as scikit-image's ``MCP_Geometric`` fed ``cost + base``): moving between
8-connected neighbours ``u`` and ``v`` costs ``(0.5 * (cost[u] + cost[v]) + base_cost_per_m) *
step_m``, where ``step_m`` is dx, dy or hypot(dx, dy) in metres. Totals are float64.

With 16 neighbours a path may also take knight moves (+-1, +-2) / (+-2, +-1). Such a step's
segment crosses four cells for a quarter of its length each (the start, two side cells, the
end), so it costs ``(mean of the four cells' costs + base) * hypot`` -- the cell integral of
:func:`overseec_core.plan.smooth.segment_costs`, of which the 8-neighbour rule is the special
case; it is blocked when any of the four is.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from overseec_core.errors import InputError
from overseec_core.plan.grid import STRIP_ROWS, PlanningGrid

#: Default per-metre cost added to every step, so zero-cost areas do not make paths wander.
DEFAULT_BASE_COST_PER_M = 0.01


def octile_m(ny: int, nx: int, dx: float, dy: float) -> float:
    """Shortest 8-connected ground distance over ny rows and nx columns."""
    m = min(ny, nx)
    return m * math.hypot(dx, dy) + (nx - m) * dx + (ny - m) * dy


def finite_range(cost: np.ndarray) -> tuple[float, float]:
    """(min, max) of the finite costs; (0, 0) when there are none."""
    low, high = math.inf, -math.inf
    for r0 in range(0, cost.shape[0], STRIP_ROWS):
        strip = cost[r0 : r0 + STRIP_ROWS]
        fin = strip[np.isfinite(strip)]
        if fin.size:
            low, high = min(low, float(fin.min())), max(high, float(fin.max()))
    return (0.0, 0.0) if low == math.inf else (low, high)


def as_points(points: Sequence[Sequence[int]]) -> list[tuple[int, int]]:
    """``points`` as (row, col) int tuples; InputError unless each is a pair of whole numbers."""
    out = []
    try:
        for p in points:
            r, c = p
            if float(r) != int(r) or float(c) != int(c):
                raise ValueError
            out.append((int(r), int(c)))
    except (TypeError, ValueError):
        raise InputError("points must be (row, col) pixel indices, e.g. [(0, 0), (10, 20)]") from None
    return out


def point_names(n: int) -> list[str]:
    """How errors and outputs name n waypoints: start, via point 1, ..., goal."""
    return ["start"] + [f"via point {i}" for i in range(1, n - 1)] + ["goal"]


def knight_lengths_m(dx: float, dy: float) -> tuple[float, float]:
    """Ground lengths of the knight moves: (two rows and one column, one row and two columns)."""
    return math.hypot(dx, 2 * dy), math.hypot(2 * dx, dy)


def _knights(d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Masks of the knight steps (2 rows 1 column, 1 row 2 columns) among absolute steps ``d``."""
    return (d[:, 0] == 2) & (d[:, 1] == 1), (d[:, 0] == 1) & (d[:, 1] == 2)


def step_lengths_m(pixels: np.ndarray, dx: float, dy: float) -> np.ndarray:
    """Ground length of each step of a pixel path (N-1 values); rejects steps that are neither
    8-connected nor knight moves."""
    px = np.asarray(pixels, dtype=np.int64).reshape(-1, 2)
    d = np.abs(np.diff(px, axis=0))
    knight_r, knight_c = _knights(d)
    if d.size and ((d.max(axis=1) > 1) & ~knight_r & ~knight_c).any():
        raise InputError("path steps must join 8-connected neighbouring pixels (or be knight moves)")
    straight_y, straight_x = (d[:, 0] == 1) & (d[:, 1] == 0), (d[:, 0] == 0) & (d[:, 1] == 1)
    diag = (d[:, 0] == 1) & (d[:, 1] == 1)
    kr, kc = knight_lengths_m(dx, dy)
    return straight_y * dy + straight_x * dx + diag * math.hypot(dx, dy) + knight_r * kr + knight_c * kc


def knight_side_cells(pixels: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For each step of a pixel path: whether it is a knight move and its two side cells.

    Returns (mask (N-1,), side1 (N-1, 2), side2 (N-1, 2)); the side cells of other steps are the
    step's own start cell (so they can be indexed safely). For a step (dr, dc) with |dc| = 2 they
    are (0, sign dc) and (dr, sign dc) from the start; with |dr| = 2, (sign dr, 0) and (sign dr, dc).
    """
    px = np.asarray(pixels, dtype=np.int64).reshape(-1, 2)
    step = np.diff(px, axis=0)
    knight_r, knight_c = _knights(np.abs(step))
    knight = knight_r | knight_c
    sr, sc = np.sign(step[:, 0]), np.sign(step[:, 1])
    a = px[:-1].copy()
    b = px[:-1].copy()
    a[knight_c, 1] += sc[knight_c]
    b[knight_c, 0] += step[knight_c, 0]
    b[knight_c, 1] += sc[knight_c]
    a[knight_r, 0] += sr[knight_r]
    b[knight_r, 0] += sr[knight_r]
    b[knight_r, 1] += step[knight_r, 1]
    return knight, a, b


def path_length_m(pixels: np.ndarray, dx: float, dy: float) -> float:
    """Ground length in metres of an 8-connected pixel path (exact sum of its step lengths)."""
    return float(math.fsum(step_lengths_m(pixels, dx, dy)))


def cumulative_path_cost(
    grid: PlanningGrid,
    pixels: np.ndarray,
    base_cost_per_m: float = DEFAULT_BASE_COST_PER_M,
    *,
    own: bool = False,
) -> np.ndarray:
    """Cost accumulated along a pixel path (float64, first value 0) under the planner's rule.

    Useful to price a path found elsewhere (a reference path, another planner's result) exactly
    as the planner would; impassable cells make the rest of the sum infinite. With ``own``,
    keep-out cells count at the costmap's own value there (:meth:`PlanningGrid.own_cost`), as
    the route of a broken keep-out rule is reported (``RulePlanner``); lethal and nodata cells
    stay infinite.
    """
    px = np.asarray(pixels, dtype=np.int64).reshape(-1, 2)
    if len(px) == 0:
        raise InputError("empty path")
    dx, dy = grid.pixel_size_m
    lens = step_lengths_m(px, dx, dy)
    c = grid.own_cost(px) if own else grid.cost[px[:, 0], px[:, 1]].astype(np.float64)
    c = np.where(np.isfinite(c), c, np.inf)
    steps = (0.5 * (c[:-1] + c[1:]) + base_cost_per_m) * lens
    knight, s1, s2 = knight_side_cells(px)
    if knight.any():  # the cell integral over four cells (see the module docstring)
        c1, c2 = (grid.own_cost(s) if own else grid.cost[s[:, 0], s[:, 1]].astype(np.float64) for s in (s1, s2))
        c1, c2 = np.where(np.isfinite(c1), c1, np.inf), np.where(np.isfinite(c2), c2, np.inf)
        four = (0.25 * (c[:-1] + c1 + c2 + c[1:]) + base_cost_per_m) * lens
        steps = np.where(knight, four, steps)
    return np.concatenate([[0.0], np.cumsum(steps)])
