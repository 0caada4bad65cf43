"""Pixel paths under the planner's step rule: points, step lengths, path lengths and costs.

Step rule (the same as scikit-image's ``MCP_Geometric`` fed ``cost + base``): moving between
8-connected neighbours ``u`` and ``v`` costs ``(0.5 * (cost[u] + cost[v]) + base_cost_per_m) *
step_m``, where ``step_m`` is dx, dy or hypot(dx, dy) in metres. Totals are float64.

With 16 neighbours a path may also take knight moves (+-1, +-2) / (+-2, +-1). Such a step's
segment crosses four cells for a quarter of its length each (the start, two side cells, the
end), so it costs ``(mean of the four cells' costs + base) * hypot`` -- the cell integral of
:func:`overseec_core.plan.smooth.segment_costs`, of which the 8-neighbour rule is the special
case; it is blocked when any of the four is.

Anisotropic mode (a DEM on the grid and a slope model, ``--dem`` / ``--slope-model``): a step of
ground length ``L`` that climbs ``dz = z[v] - z[u]`` metres costs ``(mean of its cells' costs +
base) * hypot(L, dz) * f(dz / L)`` -- the 3D length, times a multiplier ``f`` of the signed slope
(uphill positive), so A -> B and B -> A differ. ``f`` is relative to flat ground (``f(0) = 1``):

- ``tobler``: Tobler's hiking function (W. Tobler, "Three presentations on geographical analysis
  and modeling", NCGIA 93-1, 1993): walking speed ``6 exp(-3.5 |s + 0.05|)`` km/h, so
  ``f(s) = speed(0) / speed(s) = exp(3.5 (|s + 0.05| - 0.05))``: fastest on a 5 % descent
  (f = 0.84), 1.42x on a 10 % climb, 5.6x on a 50 % one.
- ``vehicle`` (a design choice, not from a source; meant for a ground vehicle): ``1 + 10 s``
  uphill (a 10 % grade doubles the cost), 1 downhill to a 15 % grade and ``1 + 5 (|s| - 0.15)``
  beyond (braking), and a step steeper than 50 % (26.6 degrees) either way is never taken.

The kernel (``_kernel.c``, ``slope_factor``) computes the same functions; :data:`SLOPE_MIN`
(f's minimum, > 0) scales the A* heuristic so it stays admissible.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from overseec_core import defaults
from overseec_core.errors import InputError
from overseec_core.plan.grid import STRIP_ROWS, PlanningGrid

#: Default per-metre cost added to every step, so zero-cost areas do not make paths wander.
DEFAULT_BASE_COST_PER_M = 0.01


#: Slope models of the anisotropic mode, by name: the kernel's model id (``defaults``' table).
SLOPE_MODELS = defaults.SLOPE_MODEL_IDS
#: The smallest value each slope model's multiplier takes (the heuristic is scaled by it).
SLOPE_MIN = {"tobler": math.exp(-0.175), "vehicle": 1.0}
#: The vehicle model's numbers (a design choice): cost per unit uphill grade, downhill grade that
#: brakes for free, cost per unit grade beyond it, steepest grade driven either way.
VEHICLE_UP, VEHICLE_FREE_DOWN, VEHICLE_BRAKE, VEHICLE_MAX = 10.0, 0.15, 5.0, 0.5


def check_slope_model(model: object) -> str:
    """``model`` when it is a slope model (:data:`SLOPE_MODELS`), else a one-line InputError: the
    one check the options, the planner, the path costs and the worker's requests share."""
    if not isinstance(model, str) or model not in SLOPE_MODELS:
        raise InputError(f"unknown slope model {model!r}; use one of {', '.join(SLOPE_MODELS)}")
    return model


def slope_factor(model: str, s: np.ndarray | float) -> np.ndarray:
    """The slope model's cost multiplier for signed slopes ``s`` (dz / ground length, uphill
    positive); +inf where the vehicle model never drives (see the module docstring)."""
    s = np.asarray(s, dtype=np.float64)
    if model == "tobler":
        return np.exp(3.5 * (np.abs(s + 0.05) - 0.05))
    check_slope_model(model)
    down = np.where(-s > VEHICLE_FREE_DOWN, 1.0 + VEHICLE_BRAKE * (-s - VEHICLE_FREE_DOWN), 1.0)
    f = np.where(s > 0, 1.0 + VEHICLE_UP * s, down)
    return np.where(np.abs(s) > VEHICLE_MAX, np.inf, f)


def step_dz(pixels: np.ndarray, elevation: np.ndarray) -> np.ndarray:
    """Elevation change of each step of a pixel path (N-1 values, metres; NaN without elevation)."""
    px = np.asarray(pixels, dtype=np.int64).reshape(-1, 2)
    z = elevation[px[:, 0], px[:, 1]].astype(np.float64)
    return np.diff(z)


def path_length_3d_m(pixels: np.ndarray, dx: float, dy: float, elevation: np.ndarray) -> float:
    """Length in metres of a pixel path counting its elevation change (sum of each step's
    hypot(ground length, dz)); >= :func:`path_length_m`, equal on flat ground."""
    lens = step_lengths_m(pixels, dx, dy)
    return float(math.fsum(np.sqrt(lens * lens + step_dz(pixels, elevation) ** 2)))


def octile_m(ny: int, nx: int, dx: float, dy: float) -> float:
    """Shortest 8-connected ground distance over ny rows and nx columns."""
    m = min(ny, nx)
    return m * math.hypot(dx, dy) + (nx - m) * dx + (ny - m) * dy


def finite_range(cost: np.ndarray) -> tuple[float, float]:
    """(min, max) of the finite costs; (0, 0) when there are none."""
    low, high = math.inf, -math.inf
    for r0 in range(0, cost.shape[0], STRIP_ROWS):
        strip = cost[r0 : r0 + STRIP_ROWS]
        fin = np.isfinite(strip)  # reductions over a mask: no copy of the finite cells
        low = min(low, float(np.min(strip, where=fin, initial=np.inf)))
        high = max(high, float(np.max(strip, where=fin, initial=-np.inf)))
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
    elevation: np.ndarray | None = None,
    slope_model: str | None = None,
) -> np.ndarray:
    """Cost accumulated along a pixel path (float64, first value 0) under the planner's rule.

    Useful to price a path found elsewhere (a reference path, another planner's result) exactly
    as the planner would; impassable cells make the rest of the sum infinite. With ``own``,
    keep-out cells count at the costmap's own value there (:meth:`PlanningGrid.own_cost`), as
    the route of a broken keep-out rule is reported (``RulePlanner``); lethal and nodata cells
    stay infinite. With ``elevation`` ((H, W) metres on the grid) and ``slope_model``, steps are
    priced by the anisotropic rule (3D length times the slope multiplier; see the module docstring).
    """
    px = np.asarray(pixels, dtype=np.int64).reshape(-1, 2)
    if len(px) == 0:
        raise InputError("empty path")
    dx, dy = grid.pixel_size_m
    lens = step_lengths_m(px, dx, dy)
    if elevation is not None:
        model = check_slope_model(slope_model)
        dz = step_dz(px, elevation)
        with np.errstate(invalid="ignore"):
            factor = np.sqrt(lens * lens + dz * dz) * slope_factor(model, dz / np.where(lens > 0, lens, 1.0))
        lens = np.where(np.isfinite(factor), factor, np.inf)
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
