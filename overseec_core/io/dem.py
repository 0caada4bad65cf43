"""A digital elevation model (DEM) resampled onto a costmap grid, served window by window.

``overseec costmap --dem DEM.tif``: any GDAL raster in any CRS and resolution. Its first band is
resampled onto the costmap's grid with ``rasterio.warp.reproject`` (bilinear; the DEM's nodata
is never interpolated into, cells it leaves empty are NaN) and converted to metres.

Why tiles: the costmap is composed block by block with a halo, and a pixel's elevation must not
depend on which block asked for it (block-wise evaluation equals whole-image evaluation exactly).
GDAL's warper approximates the coordinate transform per request and scales its kernel by the
request's size, so warping each block's own window would give slightly different values at the
same pixel (by 0.14 m on a rough DEM in EPSG:4326 under a UTM grid). The DEM is therefore
warped in fixed tiles of the grid (:data:`TILE` pixels a side, aligned at the grid's origin,
plus the one row and column beyond each edge that slope needs for the edge cells' neighbours),
and a window is cut from the tiles it touches: each pixel's value comes from one
tile, whoever asks. A small LRU cache keeps recent tiles (:data:`CACHE_BYTES`), so the halos of
neighbouring blocks are not warped twice; memory is bounded by the cache and one window.

Units: elevations are metres unless the file says otherwise: the band's unit type (``ft``,
``US survey foot``, ...) or the vertical axis of a compound CRS. A unit overseec does not know is
refused rather than guessed.
"""

from __future__ import annotations

import math
import os
from collections import OrderedDict
from pathlib import Path
from typing import Any

import numpy as np
import rasterio
from rasterio.enums import Resampling
from rasterio.transform import Affine
from rasterio.warp import reproject, transform_bounds
from rasterio.windows import Window

from overseec_core.errors import InputError, RasterError
from overseec_core.io.grid import Grid, crs_label
from overseec_core.io.read import GDAL_ERRORS, open_raster
from overseec_core.limits import check_pixels

#: Pixels per side of the fixed tiles the DEM is warped in.
TILE = 512
#: Most bytes of warped tiles kept between windows (float64 tiles: 2 MiB each at 512 pixels).
CACHE_BYTES = 128 * 2**20
#: Elevation units (lower case, as GDAL band unit types and CRS axis units spell them) -> metres.
UNITS_M: dict[str, float] = {
    "": 1.0,
    "m": 1.0,
    "metre": 1.0,
    "metres": 1.0,
    "meter": 1.0,
    "meters": 1.0,
    "ft": 0.3048,
    "foot": 0.3048,
    "feet": 0.3048,
    "international foot": 0.3048,
    "us-ft": 1200.0 / 3937.0,
    "ftus": 1200.0 / 3937.0,
    "us survey foot": 1200.0 / 3937.0,
    "us survey feet": 1200.0 / 3937.0,
    "foot_us": 1200.0 / 3937.0,
}


def elevation_unit(ds: rasterio.io.DatasetReader, path: Path) -> tuple[str, float]:
    """(unit as the file says it, metres per unit) of the DEM's first band.

    The band's unit type wins; without one, the vertical axis of a compound CRS; without either,
    metres. An unknown unit is a one-line InputError (a guess would scale every slope).
    """
    unit = (ds.units[0] if ds.units else "") or _vertical_unit(ds) or ""
    key = " ".join(unit.split()).lower()
    if key not in UNITS_M:
        raise InputError(
            f"--dem {path}: elevation unit {unit!r} is not one overseec knows (metres or feet); "
            "set it, e.g. gdal_edit.py -units m DEM.tif"
        )
    return unit or "m", UNITS_M[key]


def _vertical_unit(ds: rasterio.io.DatasetReader) -> str | None:
    """The unit of the vertical axis of the DEM's compound CRS, if it has one."""
    if ds.crs is None:
        return None
    try:
        import pyproj

        crs = pyproj.CRS.from_wkt(ds.crs.to_wkt())
        for sub in crs.sub_crs_list:
            for axis in sub.axis_info:
                if axis.direction in ("up", "down"):
                    return str(axis.unit_name)
    except Exception:  # pyproj raises CRSError for odd WKT: no vertical unit known
        return None
    return None


def check_dem_raster(ds: Any, path: Path) -> None:
    """What a raster must be to serve as elevation, checked before any pixel is read (issue 33
    rule 1: the checks the costmap and images get): one band (a photo's brightness is no
    elevation) of numbers, and within the pixel budget (:func:`~overseec_core.limits.check_pixels`)."""
    if ds.count != 1:
        raise InputError(
            f"--dem {path}: {ds.count} bands; a DEM has one band of elevations (is this an image? "
            "extract the elevation band with gdal_translate -b N)"
        )
    interp = getattr(ds, "colorinterp", ())
    if interp and getattr(interp[0], "name", "") == "palette":
        raise InputError(f"--dem {path}: a paletted (colour-mapped) raster is no elevation model")
    check_pixels(ds.width, ds.height, path, "--dem")


def check_dem_file(path: str | os.PathLike) -> None:
    """Open a DEM and check it (:func:`check_dem_raster`, a CRS) before any other work: where the
    ``--dem`` input enters a command, so a photo given as a DEM fails in its first second."""
    p = Path(path)
    try:
        ds = open_raster(p)
    except (InputError, RasterError) as exc:
        raise type(exc)(f"--dem: {exc}") from None
    with ds:
        check_dem_raster(ds, p)
        if ds.crs is None:
            raise RasterError(f"--dem {p}: the DEM has no CRS; it must be georeferenced")


class DemReader:
    """A DEM on a costmap grid: :meth:`read` gives the elevation (metres, NaN = none) of any window
    of the grid, also beyond its edges (the margin slope needs), warped in fixed tiles."""

    def __init__(self, path: str | os.PathLike, grid: Grid, tile: int = TILE, cache_bytes: int = CACHE_BYTES) -> None:
        self.path = Path(path)
        self.grid = grid
        self.tile = int(tile)
        self._cache: OrderedDict[tuple[int, int], np.ndarray] = OrderedDict()
        self._cache_tiles = max(4, cache_bytes // (8 * self.tile * self.tile))
        try:
            self._ds = open_raster(self.path)
        except (InputError, RasterError) as exc:
            raise type(exc)(f"--dem: {exc}") from None
        try:
            check_dem_raster(self._ds, self.path)
            if self._ds.crs is None:
                raise RasterError(f"--dem {self.path}: the DEM has no CRS; it must be georeferenced")
            self.unit, self.metres_per_unit = elevation_unit(self._ds, self.path)
            self.nodata = self._ds.nodata
            self._check_overlap()
        except BaseException:
            self._ds.close()
            raise

    def _check_overlap(self) -> None:
        """Refuse a DEM that covers none of the grid (before any work is done)."""
        g = self.grid
        left, bottom, right, top = rasterio.transform.array_bounds(g.height, g.width, g.transform)
        try:
            dl, db, dr, dt = transform_bounds(self._ds.crs, g.crs, *self._ds.bounds, densify_pts=21)
        except GDAL_ERRORS as exc:
            raise InputError(
                f"--dem {self.path}: cannot relate its CRS {crs_label(self._ds.crs)} to the costmap's "
                f"{crs_label(g.crs)} ({' '.join(str(exc).split())[:120]})"
            ) from None
        finite = all(math.isfinite(v) for v in (dl, db, dr, dt))
        if not finite or dl >= right or dr <= left or db >= top or dt <= bottom:
            raise InputError(
                f"--dem {self.path}: the DEM does not overlap the costmap grid (DEM bounds "
                f"{dl:.6g}, {db:.6g}, {dr:.6g}, {dt:.6g} vs grid {left:.6g}, {bottom:.6g}, {right:.6g}, {top:.6g} "
                f"in {crs_label(g.crs)})"
            )

    def _tile_box(self, ti: int, tj: int) -> tuple[int, int, int, int]:
        """(row0, col0, rows, cols) of tile (ti, tj): its square clipped to the grid grown by one
        pixel, the farthest any read reaches (a window of the grid plus a one-pixel margin)."""
        t, g = self.tile, self.grid
        r0, r1 = max(ti * t, -1), min((ti + 1) * t, g.height + 1)
        c0, c1 = max(tj * t, -1), min((tj + 1) * t, g.width + 1)
        return r0, c0, max(r1 - r0, 0), max(c1 - c0, 0)

    def _warp_tile(self, ti: int, tj: int) -> np.ndarray:
        """Tile (row ti, column tj) of the grid's tiling (:meth:`_tile_box`), in metres (NaN where
        the DEM has no data)."""
        r0, c0, h, w = self._tile_box(ti, tj)
        out = np.full((h, w), np.nan, dtype=np.float64)
        if out.size == 0:
            return out
        dst_transform = self.grid.transform * Affine.translation(c0, r0)
        try:
            reproject(
                source=rasterio.band(self._ds, 1),
                destination=out,
                src_nodata=self.nodata,
                dst_transform=dst_transform,
                dst_crs=self.grid.crs,
                dst_nodata=np.nan,
                resampling=Resampling.bilinear,
            )
        except GDAL_ERRORS as exc:
            detail = " ".join(str(exc).split())[:160]
            raise RasterError(f"--dem {self.path}: cannot read or resample it ({detail})") from None
        if self.metres_per_unit != 1.0:
            out *= self.metres_per_unit
        return out

    def _tile(self, ti: int, tj: int) -> np.ndarray:
        key = (ti, tj)
        hit = self._cache.get(key)
        if hit is not None:
            self._cache.move_to_end(key)
            return hit
        tile = self._warp_tile(ti, tj)
        self._cache[key] = tile
        while len(self._cache) > self._cache_tiles:
            self._cache.popitem(last=False)
        return tile

    def read(self, window: Window, margin: int = 0) -> np.ndarray:
        """Elevation (float64 metres, NaN where the DEM has no data) of ``window`` of the grid grown
        by ``margin`` pixels on each side (at most 1 beyond the grid's edge); the row and column
        outside the grid are read from the DEM too (NaN where it does not reach)."""
        r0, c0 = int(window.row_off) - margin, int(window.col_off) - margin
        h, w = int(window.height) + 2 * margin, int(window.width) + 2 * margin
        g = self.grid
        if r0 < -1 or c0 < -1 or r0 + h > g.height + 1 or c0 + w > g.width + 1:
            raise ValueError(f"window {window} with margin {margin} reaches more than one pixel beyond the grid")
        out = np.empty((h, w), dtype=np.float64)
        t = self.tile
        for ti in range(r0 // t, (r0 + h - 1) // t + 1):
            for tj in range(c0 // t, (c0 + w - 1) // t + 1):
                tile = self._tile(ti, tj)
                tr0, tc0, th, tw = self._tile_box(ti, tj)
                a0, a1 = max(r0, tr0), min(r0 + h, tr0 + th)
                b0, b1 = max(c0, tc0), min(c0 + w, tc0 + tw)
                out[a0 - r0 : a1 - r0, b0 - c0 : b1 - c0] = tile[a0 - tr0 : a1 - tr0, b0 - tc0 : b1 - tc0]
        return out

    def describe(self) -> str:
        """One line for the log: the file, its CRS, resolution and unit."""
        ds = self._ds
        return (
            f"DEM {self.path.name}: {ds.width} x {ds.height} px in {crs_label(ds.crs)}, "
            f"resampled bilinearly onto the costmap grid; elevations in {self.unit}"
            + (f" (x {self.metres_per_unit:g} to metres)" if self.metres_per_unit != 1.0 else "")
        )

    def close(self) -> None:
        """Close the DEM file and drop the tile cache."""
        self._cache.clear()
        self._ds.close()

    def __enter__(self) -> DemReader:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
