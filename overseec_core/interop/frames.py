"""The local metric frame of a Nav2 map: a projected, north-up grid of square ground-metre cells,
its origin and scale (:class:`LocalFrame`), and where a map lies in it (:func:`nav2_geometry`,
which refuses any other grid with the gdalwarp command that makes one). Read by the costmap
writers (:mod:`.costmap`) and the path exports' local frame (:mod:`.paths`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from rasterio.crs import CRS

from overseec_core import runfiles
from overseec_core.errors import InputError
from overseec_core.io.grid import Grid, crs_label

#: Relative tolerance for "square" ground pixels.
SQUARE_TOLERANCE = 1e-6


@dataclass(frozen=True)
class LocalFrame:
    """A metric frame on a projected CRS: local = (crs - origin) x ground metres per CRS unit.

    ``origin`` is the CRS coordinates of local (0, 0); ``scale`` the ground metres of one CRS unit
    (1 for UTM in metres, 0.3048 for a foot-based grid, the measured factor where
    :meth:`Grid.pixel_size_m` scales map units).
    """

    crs: CRS
    origin: tuple[float, float]
    scale: float = 1.0

    def to_local(self, xs, ys) -> tuple[np.ndarray, np.ndarray]:
        return (
            (np.asarray(xs, dtype=float) - self.origin[0]) * self.scale,
            (np.asarray(ys, dtype=float) - self.origin[1]) * self.scale,
        )

    def to_crs(self, lx, ly) -> tuple[np.ndarray, np.ndarray]:
        return (
            np.asarray(lx, dtype=float) / self.scale + self.origin[0],
            np.asarray(ly, dtype=float) / self.scale + self.origin[1],
        )


@dataclass(frozen=True)
class Nav2Geometry:
    """Where a Nav2 map lies: its local frame, cell size (m) and lower-left corner (local m)."""

    frame: LocalFrame
    resolution: float
    origin: tuple[float, float]


def _utm_hint(grid: Grid) -> str:
    """'EPSG:326ZZ' (or 327ZZ) of the UTM zone at the grid's centre, for the gdalwarp hint."""
    from pyproj import Transformer

    cx, cy = grid.transform * (grid.width / 2.0, grid.height / 2.0)
    try:
        lon, lat = Transformer.from_crs(grid.crs.to_wkt(), "EPSG:4326", always_xy=True).transform(cx, cy)
    except Exception:  # pyproj raises several kinds; the hint is only a hint
        return "EPSG:<UTM zone>"
    if not (math.isfinite(lon) and math.isfinite(lat)):
        return "EPSG:<UTM zone>"
    zone = min(60, max(1, int(math.floor((lon + 180.0) / 6.0)) + 1))
    return f"EPSG:{(32600 if lat >= 0 else 32700) + zone}"


def _warp_hint(grid: Grid, source: str | None, size: float) -> str:
    name = Path(source).name if source else runfiles.COSTMAP
    # the UTM zone of the map's centre, whatever the CRS: warping into the map's own CRS (Web
    # Mercator, a grid whose units are not square on the ground) would give a map refused again
    target = _utm_hint(grid)
    return (
        f"reproject it first, e.g. gdalwarp -t_srs {target} -tr {size:.6g} {size:.6g} -r near "
        f"{name} metric/{name} (and the lethal sidecar the same way into metric/)"
    )


def nav2_geometry(
    grid: Grid, source: str | None = None, local_origin: tuple[float, float] | None = None
) -> Nav2Geometry:
    """The Nav2 map frame of a grid, or a one-line InputError when Nav2 cannot hold it.

    Nav2 cells are square metres in a flat frame: the CRS must be projected, the grid north-up
    (no rotation, rows going south) and the pixels square in ground metres. Refused grids get
    the gdalwarp command that makes a suitable one (nearest neighbour keeps lethal cells whole).
    """
    t = grid.transform
    name = source or "the costmap"
    px, py = grid.pixel_size_m()
    size = min(px, py)
    if grid.crs is None or not grid.crs.is_projected:
        kind = "geographic" if grid.crs is not None and grid.crs.is_geographic else "not projected"
        raise InputError(
            f"{name}: its CRS {crs_label(grid.crs)} is {kind}; a Nav2 map needs square "
            f"metric cells: {_warp_hint(grid, source, size)}"
        )
    if t.b != 0 or t.d != 0 or t.a <= 0 or t.e >= 0:
        raise InputError(
            f"{name}: the grid is rotated or flipped; a Nav2 map needs a north-up grid: "
            f"{_warp_hint(grid, source, size)}"
        )
    if abs(px - py) > SQUARE_TOLERANCE * max(px, py):
        raise InputError(
            f"{name}: pixels are {px:.6g} x {py:.6g} m on the ground, not square; a Nav2 "
            f"map needs square metric cells: {_warp_hint(grid, source, size)}"
        )
    scale = px / t.a
    left, bottom = t.c, t.f + t.e * grid.height
    if local_origin is None:
        local_origin = (left, bottom)
    ox, oy = (float(v) for v in local_origin)
    if not (math.isfinite(ox) and math.isfinite(oy)):
        raise InputError(f"--local-origin must be finite CRS coordinates, not {local_origin}")
    frame = LocalFrame(crs=grid.crs, origin=(ox, oy), scale=scale)
    lx, ly = frame.to_local(left, bottom)
    return Nav2Geometry(frame=frame, resolution=px, origin=(float(lx), float(ly)))
