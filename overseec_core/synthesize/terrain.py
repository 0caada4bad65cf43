"""Terrain fields for the cost language from a DEM: ``slope`` (degrees) and ``roughness`` (metres).

Both look at a cell's 3x3 neighbourhood of elevations on the costmap grid (the DEM resampled by
:class:`overseec_core.io.dem.DemReader`), read with a one-pixel margin around every window, so a
cell's value never depends on the block that computes it, and cells on the grid's edge use the
DEM beyond it where the DEM reaches.

- **slope**: Horn's (1981) method, the one GDAL's ``gdaldem slope`` and most GIS use:
  ``dz/dx = ((c + 2f + i) - (a + 2d + g)) / (8 dx)``, ``dz/dy = ((g + 2h + i) - (a + 2b + c)) / (8 dy)``
  over the window ``a b c / d e f / g h i``, with ``dx``, ``dy`` the ground metres of one pixel
  along x and y (:meth:`Grid.pixel_size_m`: they differ for non-square and geographic pixels),
  and ``slope = degrees(atan(hypot(dz/dx, dz/dy)))``: 0 flat, 45 a rise of 1 per 1, 90 vertical.
- **roughness**: the root mean square of the nine elevations' residuals from their least-squares
  plane, in metres. It is 0 on any plane, however steep (slope is its own field), and grows with
  bumps, ditches, boulders and noise at the scale of the grid's pixels.

Edges of the data (the DEM's border, its nodata holes): a missing side neighbour is extrapolated
linearly through the centre from the opposite one (``2 e - opposite``), or takes the centre's
value when that is missing too (as ``gdaldem -compute_edges`` does); a missing corner neighbour
lies on the plane through the centre and its two side neighbours. Both are exact on a plane, so
a plane has its slope and zero roughness up to the data's edge; elsewhere the edge cells'
values are estimates from fewer elevations. A cell without elevation has no terrain: it is
nodata in the costmap (NaN, and 1 in the lethal sidecar), like a cell without masks.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from rasterio.windows import Window

from overseec_core.costlang import Program
from overseec_core.costlang.evaluator import missing_dem_message
from overseec_core.costlang.ops import MAX_ROUGHNESS_M, TERRAIN
from overseec_core.errors import CostProgramError
from overseec_core.io.dem import DemReader
from overseec_core.io.grid import Grid

#: Slopes (degrees) of the terrain term a prompt's program gets when a DEM is given: cost rises
#: from the program's own value at PROMPT_SLOPE_FROM to 1.0 (the obstacle level) at PROMPT_SLOPE_TO.
PROMPT_SLOPE_FROM, PROMPT_SLOPE_TO = 15.0, 30.0
#: The lines appended to a prompt's program when a DEM is given (terrain only ever adds cost:
#: a preferred road on a 20 degree slope costs at least 0.33, any ground at 30 degrees 1.0).
PROMPT_TERRAIN_TERM = (
    f"# terrain (--dem): slopes above {PROMPT_SLOPE_FROM:g} degrees cost more, "
    f"{PROMPT_SLOPE_TO:g} and steeper the most\n"
    f"cost = max(cost, normalize(slope, {PROMPT_SLOPE_FROM:g}, {PROMPT_SLOPE_TO:g}))\n"
)

#: The 3x3 offsets (row, col) around a cell, centre excluded.
_NEIGHBOURS = tuple((dr, dc) for dr in (-1, 0, 1) for dc in (-1, 0, 1) if (dr, dc) != (0, 0))


def _shifted(z: np.ndarray, dr: int, dc: int) -> np.ndarray:
    """The neighbour at (dr, dc) of every interior cell of ``z`` (shape (h - 2, w - 2))."""
    h, w = z.shape
    return z[1 + dr : h - 1 + dr, 1 + dc : w - 1 + dc]


def neighbourhood(z: np.ndarray) -> dict[tuple[int, int], np.ndarray]:
    """The 3x3 elevations around every interior cell of ``z`` (a window with a one-pixel margin),
    missing neighbours filled so that a plane stays a plane: a side neighbour (N, S, E, W) is
    ``2 e - opposite`` (``e`` when the opposite is missing too), a corner neighbour the plane
    through the centre and its two (filled) side neighbours, ``side_row + side_col - e``."""
    centre = _shifted(z, 0, 0)
    raw = {(dr, dc): _shifted(z, dr, dc) for dr, dc in _NEIGHBOURS}
    if not np.isnan(z).any():  # the usual case: nothing to fill
        return {(0, 0): centre, **raw}
    out = {(0, 0): centre}
    for (dr, dc), v in raw.items():
        if dr == 0 or dc == 0:
            opposite = raw[(-dr, -dc)]
            fill = np.where(np.isnan(opposite), centre, 2.0 * centre - opposite)
            out[(dr, dc)] = np.where(np.isnan(v), fill, v)
    for (dr, dc), v in raw.items():
        if dr != 0 and dc != 0:
            out[(dr, dc)] = np.where(np.isnan(v), out[(dr, 0)] + out[(0, dc)] - centre, v)
    return out


Neighbourhood = dict[tuple[int, int], np.ndarray]


def slope_degrees(z: np.ndarray, pixel_size_m: tuple[float, float], n: Neighbourhood | None = None) -> np.ndarray:
    """Horn's slope in degrees of the interior cells of ``z`` (elevations in metres with a
    one-pixel margin; NaN where the centre has no elevation). ``pixel_size_m`` is (x, y);
    ``n``: :func:`neighbourhood` of ``z`` when the caller has it already."""
    n = neighbourhood(z) if n is None else n
    dx, dy = pixel_size_m
    east = n[(-1, 1)] + 2.0 * n[(0, 1)] + n[(1, 1)]
    west = n[(-1, -1)] + 2.0 * n[(0, -1)] + n[(1, -1)]
    south = n[(1, -1)] + 2.0 * n[(1, 0)] + n[(1, 1)]
    north = n[(-1, -1)] + 2.0 * n[(-1, 0)] + n[(-1, 1)]
    gx = (east - west) / (8.0 * dx)
    gy = (south - north) / (8.0 * dy)
    return np.where(np.isnan(n[(0, 0)]), np.nan, np.degrees(np.arctan(np.hypot(gx, gy))))


def roughness_m(z: np.ndarray, n: Neighbourhood | None = None) -> np.ndarray:
    """RMS residual (metres) of each interior cell's 3x3 elevations about their least-squares
    plane (NaN where the centre has no elevation), clipped to the language's static bound.
    ``n``: :func:`neighbourhood` of ``z`` when the caller has it already."""
    n = neighbourhood(z) if n is None else n
    centre = n[(0, 0)]
    d = {k: v - centre for k, v in n.items() if k != (0, 0)}  # relative to the centre (d = 0 there)
    mean = _total(d.values()) / 9.0
    p = (_total(d[(r, 1)] for r in (-1, 0, 1)) - _total(d[(r, -1)] for r in (-1, 0, 1))) / 6.0
    q = (_total(d[(1, c)] for c in (-1, 0, 1)) - _total(d[(-1, c)] for c in (-1, 0, 1))) / 6.0
    squares = mean * mean  # the centre's residual: 0 - mean
    for (dr, dc), v in d.items():
        r = v - mean
        r -= p * dc if dc else 0.0
        r -= q * dr if dr else 0.0
        squares = squares + r * r
    return np.minimum(np.sqrt(squares / 9.0), MAX_ROUGHNESS_M)


def _total(arrays) -> np.ndarray:
    """The sum of arrays, in one buffer."""
    it = iter(arrays)
    out = np.array(next(it), dtype=np.float64)
    for a in it:
        out += a
    return out


@dataclass
class TerrainBlock:
    """Terrain fields for one window (finite; 0 where there is no elevation) and where they hold."""

    fields: dict[str, np.ndarray]
    valid: np.ndarray


class TerrainSource:
    """The terrain fields a program reads, window by window, from a DEM on the costmap grid."""

    def __init__(self, dem: str | os.PathLike, grid: Grid) -> None:
        self.path = Path(dem)
        self.grid = grid
        self.dem = DemReader(self.path, grid)
        self.pixel_size_m = grid.pixel_size_m()
        #: Cells of the core windows evaluated so far that had no elevation (the engine counts them).
        self.missing_pixels = 0

    def read(self, names: Sequence[str], window: Window) -> TerrainBlock:
        """``names`` (terrain fields) over ``window``; ``valid`` is False where the DEM gives no
        elevation (those cells become nodata in the costmap)."""
        unknown = [n for n in names if n not in TERRAIN]
        if unknown:
            raise ValueError(f"not terrain fields: {unknown}")
        z = self.dem.read(window, margin=1)
        valid = ~np.isnan(z[1:-1, 1:-1])
        fields = {}
        with np.errstate(invalid="ignore"):
            n = neighbourhood(z)
            for name in names:
                value = slope_degrees(z, self.pixel_size_m, n) if name == "slope" else roughness_m(z, n)
                fields[name] = np.where(valid, value, 0.0)
        return TerrainBlock(fields, valid)

    def describe(self) -> str:
        """One line for the log: the DEM and the ground pixel size slopes are measured with."""
        px, py = self.pixel_size_m
        return f"{self.dem.describe()}; slope on {px:.4g} x {py:.4g} m pixels"

    def close(self) -> None:
        """Close the DEM."""
        self.dem.close()


def require_dem(program: Program, dem: Path | None) -> None:
    """A one-line error (at the first terrain field's line) when the program reads terrain and no
    DEM was given."""
    if program.terrain_uses and dem is None:
        name, line, col = program.terrain_uses[0]
        raise CostProgramError(missing_dem_message(name), line, col)


def with_prompt_terrain(text: str) -> str:
    """A prompt's program with the terrain term (:data:`PROMPT_TERRAIN_TERM`) appended."""
    return text.rstrip("\n") + "\n" + PROMPT_TERRAIN_TERM
