"""Georeferenced raster input and output.

Reading: :class:`RasterSource` opens any GDAL raster and serves RGB uint8 chips for windows,
whatever the source is (RGB, RGBA, panchromatic, uint16/float, multispectral with a band choice),
plus a validity mask from alpha/nodata/internal masks. Intensity stretching is computed once for
the whole image from a decimated read (GDAL uses overviews when present), never per tile, so tiles
agree with each other.

Writing: :class:`RasterWriter` writes tiled, compressed GeoTIFFs on an exact copy of an input grid,
into a temporary file beside the target that is renamed only when complete, with overviews and band
descriptions. It refuses to overwrite any input.

Everything uses the rasterio 1.3 API (Debian's python3-rasterio), one GDAL in the process.
"""

from __future__ import annotations

import functools
import json
import math
import os
import threading
import warnings
from collections.abc import Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NoReturn

import numpy as np
import rasterio
from rasterio._err import CPLE_BaseError
from rasterio.crs import CRS
from rasterio.enums import ColorInterp, Interleaving, MaskFlags, Resampling
from rasterio.errors import NotGeoreferencedWarning, RasterioError, RasterioIOError
from rasterio.transform import Affine
from rasterio.windows import Window

from overseec_core.atomic import discard, output_error, publish, space_reason, temp_beside
from overseec_core.errors import InputError, OutputError, RasterError
from overseec_core.limits import MAX_JSON_BYTES, read_text_limited

#: Longest side of the decimated read used to compute the stretch percentiles.
STRETCH_SAMPLE_SIZE = 2048
DEFAULT_PERCENTILES = (2.0, 98.0)
#: What GDAL failures surface as through rasterio 1.3 (RasterioIOError is not a RasterioError there).
GDAL_ERRORS = (RasterioError, RasterioIOError, CPLE_BaseError)


# --------------------------------------------------------------------------------------------
# Grid and georeferencing
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Grid:
    """The pixel grid outputs share with their input: CRS, transform and size."""

    crs: CRS
    transform: Affine
    width: int
    height: int

    @property
    def shape(self) -> tuple[int, int]:
        return (self.height, self.width)

    def same_as(self, other: Grid, tol: float = 1e-9) -> bool:
        """True when both grids are the same pixels in the same CRS."""
        return (
            self.shape == other.shape
            and self.crs == other.crs
            and self.transform.almost_equals(other.transform, precision=tol)
        )

    def pixel_size_m(self) -> tuple[float, float]:
        """Ground size (x, y) of one pixel in metres; see :func:`pixel_size_m`."""
        return pixel_size_m(self.crs, self.transform, self.width, self.height)

    def ground_scale(self) -> GroundScale:
        """How this grid's map units became ground metres; see :func:`ground_scale`."""
        return ground_scale(self.crs, self.transform, self.width, self.height)


#: A projected CRS keeps its nominal pixel size (transform step x linear unit) while the ground scale
#: measured at the image centre is within this relative tolerance of 1 on both axes (UTM's 0.9996 at
#: its central meridian, State Plane zones); beyond it the measured ground size is used.
NOMINAL_SCALE_TOLERANCE = 1e-3
#: Points per side of the lattice on which :func:`ground_scale` samples the scale across the image.
_SPAN_SAMPLES = 5
_MEASURE_LOCK = threading.Lock()


@dataclass(frozen=True)
class GroundScale:
    """How one grid's map units become ground metres: what :func:`pixel_size_m` returns, and why.

    ``pixel_size_m`` is the (x, y) size used everywhere; ``measured_m`` the geodesic ground size of
    one pixel step at the image centre (None where the CRS has no ellipsoid to measure on);
    ``nominal_m`` the transform step times the CRS's linear unit (None for geographic CRSs);
    ``factor`` = measured / nominal, the map's local scale at the centre (ground metres per map
    metre; 1 / k for a projection with point scale k). ``method`` says which was used: "nominal"
    (projected, scale within :data:`NOMINAL_SCALE_TOLERANCE` of 1), "scaled" (projected, measured
    size used), "geodesic" (geographic CRS) or "unmeasured" (no ellipsoid or outside the
    projection's domain: nominal size, scale unknown). ``span`` is (min, max) over the image of the
    true ground length of a one-pixel step (along x or y) divided by the length that
    ``pixel_size_m`` gives it: the relative error of lengths measured with one pixel size for the
    whole image (None where unmeasured).
    """

    pixel_size_m: tuple[float, float]
    method: str
    measured_m: tuple[float, float] | None = None
    nominal_m: tuple[float, float] | None = None
    factor: tuple[float, float] | None = None
    span: tuple[float, float] | None = None

    @property
    def max_error(self) -> float | None:
        """Largest relative length error anywhere in the image (0.0017 = 0.17 %), or None."""
        return None if self.span is None else max(abs(self.span[0] - 1.0), abs(self.span[1] - 1.0))

    def to_dict(self) -> dict:
        return {
            "pixel_size_m": list(self.pixel_size_m),
            "method": self.method,
            "measured_m": None if self.measured_m is None else list(self.measured_m),
            "nominal_m": None if self.nominal_m is None else list(self.nominal_m),
            "factor": None if self.factor is None else list(self.factor),
            "span": None if self.span is None else list(self.span),
            "max_error": self.max_error,
        }

    def describe(self) -> str:
        px, py = self.pixel_size_m
        tol = f"{100 * NOMINAL_SCALE_TOLERANCE:g} %"
        text = {
            "nominal": f"nominal (map units are ground metres within {tol})",
            "scaled": "scaled to ground metres at the image centre",
            "geodesic": "measured on the ellipsoid at the image centre",
            "unmeasured": "nominal (scale not measurable)",
        }[self.method]
        out = f"pixel {px:.6g} x {py:.6g} m, {text}"
        if self.factor is not None:
            out += f"; local scale {self.factor[0]:.6f} x {self.factor[1]:.6f} ground m per map m"
        if self.max_error is not None:
            out += f"; lengths within {100.0 * self.max_error:.2g} % across the image"
        return out


def pixel_size_m(crs: CRS, transform: Affine, width: int, height: int) -> tuple[float, float]:
    """Ground size of one pixel (x, y) in metres, for projected and geographic CRSs.

    Ground metres are geodesic distances on the CRS's ellipsoid (terrain height is ignored: 1000 m
    of elevation adds 0.016 %). One pixel step along x and along y is measured at the image centre
    (central differences, pixel ±0.5) after converting to the CRS's own geographic CRS:

    * geographic CRSs always use the measured size (pixels are not square on the ground: at 36 N a
      2.7e-6 degree pixel is about 0.24 m east-west and 0.30 m north-south);
    * projected CRSs keep their nominal size (transform step x linear unit) while the local scale
      is within :data:`NOMINAL_SCALE_TOLERANCE` (0.1 %) of 1 on both axes -- all of a UTM zone,
      State Plane and national survey grids, whose grid distances are the convention and whose
      stated resolution (0.5 m) users see in QGIS -- and use the measured size beyond it, e.g.
      Web Mercator, whose map metres are sec(latitude) ground metres (0.682 ground m per map m at
      47 N, 1.000 at the equator), or a UTM grid used far outside its zone;
    * CRSs without an ellipsoid (engineering/local) or a centre outside the projection's domain
      use the nominal size.

    One size serves the whole image: where the scale varies across it (Web Mercator: sec(lat)
    changes by about tan(lat) x the latitude span in radians: 0.17 % over 10 km of ground
    north-south at 47 N, so +-0.08 % at the edges), lengths away from the centre carry that error;
    :func:`ground_scale` reports it (``span``, ``max_error``) with the factor and the decision. Cached per
    (CRS, transform, size).
    """
    return ground_scale(crs, transform, width, height).pixel_size_m


def ground_scale(crs: CRS, transform: Affine, width: int, height: int) -> GroundScale:
    """The ground-metre decision behind :func:`pixel_size_m` with its factor and error (cached)."""
    if crs is None:
        raise RasterError("the raster has no CRS; pass --assume-crs EPSG:XXXX to say which it is")
    return _ground_scale(
        crs.to_wkt(),
        tuple(transform)[:6],
        int(width),
        int(height),
        bool(crs.is_geographic),
        bool(crs.is_projected),
        float(crs.linear_units_factor[1]) if crs.is_projected else 1.0,
    )


@functools.lru_cache(maxsize=32)
def _lonlat_measurer(wkt: str):
    """(transformer to the CRS's geographic CRS, degrees per its angle unit, Geod), or None."""
    import pyproj
    from pyproj import Geod, Transformer

    try:
        src = pyproj.CRS.from_wkt(wkt)
        geo = src.geodetic_crs
        if geo is None:
            return None
        if len(geo.axis_info) > 2:
            # CRS.to_2d is pyproj >= 3.6; on an older one this raises and the CRS keeps nominal sizes
            geo = geo.to_2d()  # type: ignore[attr-defined, unused-ignore]
        deg_per_unit = math.degrees(geo.axis_info[0].unit_conversion_factor)
        geod = geo.get_geod() or Geod(ellps="WGS84")
        return Transformer.from_crs(src, geo, always_xy=True), deg_per_unit, geod
    except Exception:  # pyproj raises CRSError/ProjError; an unmeasurable CRS keeps nominal sizes
        return None


def _ground_steps(measurer, transform: Affine, cols: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Geodesic length (m) of one pixel step along x and y centred on each (col, row); NaN where
    the points fall outside the projection's domain."""
    tr, deg, geod = measurer
    n = len(cols)
    c = np.concatenate([cols - 0.5, cols + 0.5, cols, cols])
    r = np.concatenate([rows, rows, rows - 0.5, rows + 0.5])
    x, y = transform * (c, r)
    with np.errstate(all="ignore"):
        lon, lat = (np.asarray(v, dtype=np.float64) * deg for v in tr.transform(x, y, errcheck=False))
    ok = np.isfinite(lon) & np.isfinite(lat) & (np.abs(lat) <= 90.0)
    lon, lat = np.where(ok, lon, 0.0), np.where(ok, lat, 0.0)
    dx = np.abs(geod.inv(lon[:n], lat[:n], lon[n : 2 * n], lat[n : 2 * n])[2])
    dy = np.abs(geod.inv(lon[2 * n : 3 * n], lat[2 * n : 3 * n], lon[3 * n :], lat[3 * n :])[2])
    dx = np.where(ok[:n] & ok[n : 2 * n], dx, np.nan)
    dy = np.where(ok[2 * n : 3 * n] & ok[3 * n :], dy, np.nan)
    return dx, dy


@functools.lru_cache(maxsize=256)
def _ground_scale(
    wkt: str, t: tuple, width: int, height: int, geographic: bool, projected: bool, unit_m: float
) -> GroundScale:
    transform = Affine(*t)
    nominal = (math.hypot(transform.a, transform.d) * unit_m, math.hypot(transform.b, transform.e) * unit_m)
    measurer = _lonlat_measurer(wkt) if (geographic or projected) else None
    if measurer is None:
        if geographic:
            raise RasterError("cannot measure pixel sizes in this geographic CRS (no ellipsoid)")
        return GroundScale(pixel_size_m=nominal, method="unmeasured", nominal_m=nominal if projected else None)
    k = _SPAN_SAMPLES
    cols, rows = np.meshgrid(np.linspace(0.0, width, k), np.linspace(0.0, height, k))
    with _MEASURE_LOCK:  # one pyproj transformer per CRS is shared; measure one grid at a time
        dx, dy = _ground_steps(measurer, transform, cols.ravel(), rows.ravel())
    centre = (k * k) // 2
    measured = (float(dx[centre]), float(dy[centre]))
    if not all(math.isfinite(v) and v > 0 for v in measured):
        if geographic:
            raise RasterError(
                f"cannot measure pixel sizes: the image centre is not a valid longitude/latitude (transform {tuple(t)})"
            )
        return GroundScale(pixel_size_m=nominal, method="unmeasured", nominal_m=nominal)
    if geographic:
        size, method, nom, factor = measured, "geodesic", None, None
    else:
        factor = (measured[0] / nominal[0], measured[1] / nominal[1])
        if all(abs(f - 1.0) <= NOMINAL_SCALE_TOLERANCE for f in factor):
            size, method = nominal, "nominal"
        else:
            size, method = measured, "scaled"
        nom = nominal
    ratios = np.concatenate([dx / size[0], dy / size[1]])
    ratios = ratios[np.isfinite(ratios)]
    span = (float(ratios.min()), float(ratios.max()))
    return GroundScale(
        pixel_size_m=(float(size[0]), float(size[1])),
        method=method,
        measured_m=measured,
        nominal_m=nom,
        factor=factor,
        span=span,
    )


def parse_crs(text: str) -> CRS:
    """A CRS from user text (EPSG:XXXX, WKT, PROJ string), or a one-line InputError."""
    try:
        return CRS.from_user_input(text)
    except Exception:  # rasterio raises CRSError, but GDAL can surface others
        raise InputError(f"not a CRS: {text!r} (use e.g. EPSG:32633)") from None


def crs_label(crs: CRS | None) -> str | None:
    """Short name for a CRS: 'EPSG:XXXX' when it has one, else its WKT."""
    if crs is None:
        return None
    epsg = crs.to_epsg()
    return f"EPSG:{epsg}" if epsg else crs.to_wkt()


# --------------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ReadPlan:
    """How a source becomes RGB uint8: which bands, which alpha, which stretch."""

    rgb_bands: tuple[int, int, int]
    alpha_band: int | None
    #: (low, high) per RGB channel, mapped to 0..255; None when the source is already uint8.
    stretch: tuple[tuple[float, float], ...] | None
    note: str = ""

    def describe(self) -> str:
        bands = ",".join(str(b) for b in self.rgb_bands)
        alpha = f", alpha from band {self.alpha_band}" if self.alpha_band else ""
        if self.stretch is None:
            stretch = "no stretch (uint8)"
        else:
            stretch = "linear stretch " + "; ".join(f"{lo:g}..{hi:g}" for lo, hi in self.stretch)
        return f"RGB from bands {bands}{alpha}; {stretch}{'; ' + self.note if self.note else ''}"


@dataclass(frozen=True)
class RasterInfo:
    """What `overseec info` reports: georeferencing, layout and how the image will be read."""

    path: str
    driver: str
    grid: Grid
    count: int
    dtypes: tuple[str, ...]
    nodata: float | None
    colorinterp: tuple[str, ...]
    block_shapes: tuple[tuple[int, int], ...]
    overviews: tuple[int, ...]
    pixel_size_m: tuple[float, float]
    plan: ReadPlan
    crs_assumed: bool = False

    def to_json(self) -> dict:
        g = self.grid
        return {
            "path": self.path,
            "driver": self.driver,
            "crs": crs_label(g.crs),
            "epsg": g.crs.to_epsg(),
            "crs_wkt": g.crs.to_wkt(),
            "crs_assumed": self.crs_assumed,
            "width": g.width,
            "height": g.height,
            "count": self.count,
            "dtypes": list(self.dtypes),
            "transform": list(g.transform)[:6],
            "bounds": _bounds(g),
            "pixel_size_m": list(self.pixel_size_m),
            "nodata": None if self.nodata is None or math.isnan(self.nodata) else self.nodata,
            "nodata_is_nan": self.nodata is not None and math.isnan(self.nodata),
            "alpha_band": self.plan.alpha_band,
            "colorinterp": list(self.colorinterp),
            "block_shapes": [list(b) for b in self.block_shapes],
            "overviews": list(self.overviews),
            "read_plan": {
                "rgb_bands": list(self.plan.rgb_bands),
                "alpha_band": self.plan.alpha_band,
                "stretch": None if self.plan.stretch is None else [list(s) for s in self.plan.stretch],
                "description": self.plan.describe(),
            },
        }


def _bounds(grid: Grid) -> list[float]:
    left, bottom, right, top = rasterio.transform.array_bounds(grid.height, grid.width, grid.transform)
    return [left, bottom, right, top]


def open_raster(path: str | os.PathLike) -> rasterio.DatasetReader:
    """Open a raster for reading, turning GDAL's failures into one-line RasterErrors."""
    p = Path(path)
    if not p.exists():
        raise InputError(f"no such file: {p}")
    if p.is_dir():
        raise InputError(f"{p} is a directory, not a raster file")
    if p.stat().st_size == 0:
        raise RasterError(f"{p} is empty (0 bytes)")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NotGeoreferencedWarning)
            ds = rasterio.open(p)
    except GDAL_ERRORS as exc:
        raise RasterError(f"{p} is not a readable raster ({_gdal_reason(exc)})") from None
    if ds.width == 0 or ds.height == 0 or ds.count == 0:
        ds.close()
        raise RasterError(f"{p} has no pixels ({ds.width}x{ds.height}, {ds.count} bands)")
    return ds


def _gdal_reason(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return text[:200] if text else type(exc).__name__


def parse_bands(text: str | Sequence[int] | None) -> tuple[int, ...] | None:
    """'4,3,2' -> (4, 3, 2); validates shape only (the image checks the range)."""
    if text is None or text == "":
        return None
    if isinstance(text, str):
        try:
            bands = tuple(int(t) for t in text.replace(" ", "").split(","))
        except ValueError:
            raise InputError(f"--bands takes band numbers like 4,3,2, not {text!r}") from None
    else:
        bands = tuple(int(b) for b in text)
    if len(bands) not in (1, 3):
        raise InputError(f"--bands takes 1 (panchromatic) or 3 (R,G,B) band numbers, not {len(bands)}")
    return bands


def _choose_bands(
    ds: rasterio.DatasetReader, bands: tuple[int, ...] | None
) -> tuple[tuple[int, int, int], int | None, str]:
    interp = list(ds.colorinterp)
    alpha = next((i + 1 for i, c in enumerate(interp) if c == ColorInterp.alpha), None)
    if alpha is None and ds.count in (2, 4) and any(MaskFlags.alpha in f for f in ds.mask_flag_enums):
        alpha = ds.count
    if bands is not None:
        bad = [b for b in bands if not 1 <= b <= ds.count]
        if bad:
            raise InputError(f"--bands {','.join(map(str, bands))}: the image has bands 1..{ds.count}")
        rgb = bands * 3 if len(bands) == 1 else bands
        return (rgb[0], rgb[1], rgb[2]), alpha, "bands chosen with --bands"
    colour = [i + 1 for i, c in enumerate(interp) if c != ColorInterp.alpha]
    named = {c: i + 1 for i, c in enumerate(interp)}
    if len(colour) == 1:
        return (colour[0],) * 3, alpha, "single band replicated to RGB"
    if len(colour) == 3:
        return (colour[0], colour[1], colour[2]), alpha, ""
    if all(c in named for c in (ColorInterp.red, ColorInterp.green, ColorInterp.blue)):
        return (
            (named[ColorInterp.red], named[ColorInterp.green], named[ColorInterp.blue]),
            alpha,
            "RGB bands found by colour interpretation",
        )
    if len(colour) == 4:
        return (1, 2, 3), alpha, "4 bands without alpha: read as R,G,B,(NIR); use --bands to choose"
    raise RasterError(
        f"{ds.name} has {ds.count} bands ({', '.join(c.name for c in interp)}); "
        "choose three with --bands R,G,B (for example --bands 4,3,2)"
    )


def _compute_stretch(
    ds: rasterio.DatasetReader, bands: Sequence[int], percentiles: tuple[float, float]
) -> tuple[tuple[float, float], ...]:
    """Per-band percentile limits from one decimated read of the whole image."""
    scale = max(ds.width, ds.height) / STRETCH_SAMPLE_SIZE
    shape = (max(1, round(ds.height / scale)), max(1, round(ds.width / scale))) if scale > 1 else (ds.height, ds.width)
    unique = sorted(set(bands))
    try:
        data = ds.read(unique, out_shape=(len(unique), *shape), resampling=Resampling.nearest, masked=True)
    except GDAL_ERRORS as exc:
        raise RasterError(f"{ds.name}: corrupt or truncated raster ({_gdal_reason(exc)})") from None
    limits = {}
    for k, b in enumerate(unique):
        band = data[k]
        values = band.compressed() if np.ma.is_masked(band) else np.asarray(band).ravel()
        values = values[np.isfinite(values)]
        if values.size == 0:
            limits[b] = (0.0, 1.0)
            continue
        lo, hi = np.percentile(values, percentiles)
        if hi <= lo:
            hi = lo + 1.0
        limits[b] = (float(lo), float(hi))
    return tuple(limits[b] for b in bands)


@dataclass(frozen=True)
class Chip:
    """RGB uint8 pixels for one window and which of them hold data."""

    window: Window
    rgb: np.ndarray  # (H, W, 3) uint8
    valid: np.ndarray  # (H, W) bool

    @property
    def any_valid(self) -> bool:
        return bool(self.valid.any())


class RasterSource:
    """A raster opened for windowed RGB reads; never loads the whole image.

    Use as a context manager. ``bands`` picks bands (1 = panchromatic, 3 = R,G,B);
    ``assume_crs`` supplies a CRS for images without one.
    """

    def __init__(
        self,
        path: str | os.PathLike,
        bands: Sequence[int] | str | None = None,
        assume_crs: str | CRS | None = None,
        percentiles: tuple[float, float] = DEFAULT_PERCENTILES,
    ) -> None:
        self.path = Path(path)
        self._ds = open_raster(self.path)
        try:
            self.info = self._describe(parse_bands(bands), assume_crs, percentiles)
        except BaseException:
            self._ds.close()
            raise

    def _describe(
        self, bands: tuple[int, ...] | None, assume_crs: str | CRS | None, percentiles: tuple[float, float]
    ) -> RasterInfo:
        ds = self._ds
        crs, assumed = ds.crs, False
        if crs is None or not crs.to_wkt():
            if assume_crs is None:
                raise RasterError(f"{self.path} has no CRS; pass --assume-crs EPSG:XXXX to say which it is")
            crs = assume_crs if isinstance(assume_crs, CRS) else parse_crs(assume_crs)
            assumed = True
        if ds.transform == Affine.identity() and not assumed and not ds.gcps[0]:
            raise RasterError(f"{self.path} has no geotransform (pixel grid only); it cannot be placed on a map")
        rgb, alpha, note = _choose_bands(ds, bands)
        needs_stretch = any(ds.dtypes[b - 1] != "uint8" for b in rgb)
        stretch = _compute_stretch(ds, rgb, percentiles) if needs_stretch else None
        grid = Grid(crs=crs, transform=ds.transform, width=ds.width, height=ds.height)
        return RasterInfo(
            path=str(self.path),
            driver=ds.driver,
            grid=grid,
            count=ds.count,
            dtypes=tuple(ds.dtypes),
            nodata=ds.nodata,
            colorinterp=tuple(c.name for c in ds.colorinterp),
            block_shapes=tuple(tuple(s) for s in ds.block_shapes),
            overviews=tuple(ds.overviews(1)),
            pixel_size_m=pixel_size_m(crs, ds.transform, ds.width, ds.height),
            plan=ReadPlan(rgb_bands=rgb, alpha_band=alpha, stretch=stretch, note=note),
            crs_assumed=assumed,
        )

    @property
    def grid(self) -> Grid:
        return self.info.grid

    def read_chip(self, window: Window) -> Chip:
        """RGB uint8 and validity for one window (inside the image)."""
        plan = self.info.plan
        unique = sorted(set(plan.rgb_bands))
        try:
            data = self._ds.read(unique, window=window)
            masks = self._ds.read_masks(unique, window=window)
        except GDAL_ERRORS as exc:
            raise RasterError(
                f"{self.path}: corrupt or truncated raster; reading window "
                f"{window.col_off},{window.row_off} failed ({_gdal_reason(exc)})"
            ) from None
        index = {b: k for k, b in enumerate(unique)}
        valid = masks.min(axis=0) > 0
        if data.dtype.kind == "f":
            valid &= np.isfinite(data).all(axis=0)
        channels = [data[index[b]] for b in plan.rgb_bands]
        if plan.stretch is not None:
            channels = [_stretch_to_uint8(c, lo, hi) for c, (lo, hi) in zip(channels, plan.stretch)]
        rgb = np.stack(channels, axis=-1).astype(np.uint8, copy=False)
        rgb[~valid] = 0
        return Chip(window=window, rgb=rgb, valid=valid)

    def close(self) -> None:
        self._ds.close()

    def __enter__(self) -> RasterSource:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _stretch_to_uint8(band: np.ndarray, lo: float, hi: float) -> np.ndarray:
    scaled = (band.astype(np.float32) - np.float32(lo)) * np.float32(255.0 / (hi - lo))
    return np.clip(np.nan_to_num(scaled, nan=0.0), 0, 255).astype(np.uint8)


def read_info(
    path: str | os.PathLike, bands: Sequence[int] | str | None = None, assume_crs: str | None = None
) -> RasterInfo:
    """Open, describe and close."""
    with RasterSource(path, bands=bands, assume_crs=assume_crs) as src:
        return src.info


def read_grid(path: str | os.PathLike) -> Grid:
    """The grid of any raster (for checking that stage outputs line up)."""
    with open_raster(path) as ds:
        if ds.crs is None:
            raise RasterError(f"{path} has no CRS")
        return Grid(crs=ds.crs, transform=ds.transform, width=ds.width, height=ds.height)


# --------------------------------------------------------------------------------------------
# Writing
# --------------------------------------------------------------------------------------------


def _env_flag(name: str) -> bool:
    return os.environ.get(name, "").strip().lower() in ("1", "true", "yes")


@dataclass(frozen=True)
class WriteOptions:
    """GeoTIFF layout of outputs: tiled, compressed, with internal overviews.

    GDAL cannot stream a Cloud-Optimized GeoTIFF: the COG layout (overviews before the data) needs
    a full rewrite through the COG driver after the data is written, measured at 5-7x the cost of
    building internal overviews on large outputs. It is therefore opt-in: ``cog=True``, or the
    environment variable OVERSEEC_COG=1 (the CLI's ``--cog``). Compression defaults to ZSTD
    (fast, read by every GDAL >= 2.3 and so by QGIS); OVERSEEC_COMPRESS=deflate for older readers.
    """

    blocksize: int = 512
    compress: str = field(default_factory=lambda: os.environ.get("OVERSEEC_COMPRESS", "zstd"))
    zlevel: int = 6
    zstd_level: int = 1
    overviews: bool = True
    overview_resampling: Resampling = Resampling.average
    cog: bool = field(default_factory=lambda: _env_flag("OVERSEEC_COG"))
    #: Compression of the streamed temporary file when a COG rewrite follows (read once, deleted).
    intermediate_compress: str = "zstd"
    #: GDAL compression threads (GTiff/COG NUM_THREADS).
    threads: str = "ALL_CPUS"
    #: Before the rename every output is checked (:func:`verify_geotiff`): its block index and
    #: its last blocks, a few milliseconds. True also decodes every block (slower, see there).
    verify_every_block: bool = False


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def check_output_path(path: str | os.PathLike, inputs: Iterable[str | os.PathLike] = ()) -> Path:
    """Refuse outputs that would overwrite an input, take a run folder's bookkeeping name
    (manifest.json, .manifest.lock) or cannot be written; return the path."""
    from overseec_core.manifest import check_output_name

    out = Path(path)
    check_output_name(out)
    for src in inputs:
        if src is None:
            continue
        src = Path(src)
        if out.resolve() == src.resolve() or _same_file(out, src):
            raise OutputError(f"output {out} is the input {src}; choose another output path")
    parent = out.parent if str(out.parent) else Path(".")
    if not parent.is_dir():
        raise OutputError(f"cannot write {out}: folder {parent} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise OutputError(f"cannot write {out}: folder {parent} is not writable")
    if out.is_dir():
        raise OutputError(f"cannot write {out}: it is a directory")
    return out


#: Most GDAL failure messages kept per call (a full disk can repeat one per block).
_MAX_GDAL_MESSAGES = 20
#: GDAL's CE_Failure: the class of the messages :func:`gdal_errors` collects (CE_Fatal is 4).
_CE_FAILURE = 3


@functools.lru_cache(maxsize=1)
def _osgeo_gdal() -> Any:
    """osgeo.gdal when it drives the very GDAL rasterio uses (Debian's python3-gdal), else None.

    GDAL reports some write failures only to its error handler, never to the caller: blocks its
    cache flushes at close, a directory it cannot rewrite. rasterio 1.3 has no public way to
    push a handler; osgeo's ``PushErrorHandler`` does, and a self-test (an error raised through
    rasterio must reach it) makes sure it is the same library, not a second GDAL.
    """
    try:
        from osgeo import gdal
    except Exception:  # not installed or broken: the written file's verification still guards
        return None
    seen: list[str] = []
    with rasterio.Env():
        gdal.PushErrorHandler(lambda cls, no, msg: seen.append(str(msg)))
        try:
            rasterio.open("/vsimem/overseec-selftest-missing.tif").close()
        except Exception:  # expected: the file does not exist
            pass
        finally:
            gdal.PopErrorHandler()
    return gdal if seen else None


@contextmanager
def gdal_errors() -> Iterator[list[str]]:
    """Run GDAL calls with their failure messages collected instead of printed.

    Inside, GDAL's default handler (``ERROR 1: ...`` lines on stderr, one per failed block) is
    replaced: rasterio's Env routes messages to logging, and where :func:`_osgeo_gdal` is
    available a handler on top of it collects every CE_Failure message, including those of
    calls that do not fail (a close whose flush hit a full disk). GDAL's handler stack is
    per thread: enter it in the thread that makes the calls.
    """
    messages: list[str] = []
    gdal = _osgeo_gdal()
    with rasterio.Env():
        if gdal is None:
            yield messages
            return

        def collect(cls: int, _no: int, msg: str) -> None:
            if cls >= _CE_FAILURE and len(messages) < _MAX_GDAL_MESSAGES:
                messages.append(" ".join(str(msg).split()))

        gdal.PushErrorHandler(collect)
        try:
            yield messages
        finally:
            gdal.PopErrorHandler()


def _write_failed(messages: Sequence[str]) -> bool:
    """True when GDAL's messages say data did not reach the file (I/O, not e.g. PROJ notes)."""
    if space_reason(None, messages) is not None:
        return True
    words = ("write", "seek", "i/o", "io error", "flush")
    return any(w in m.lower() for m in messages for w in words)


def _block_counts(ds) -> tuple[int, int]:
    """Blocks across and down one band of ``ds``."""
    bh, bw = ds.block_shapes[0]
    return -(-ds.width // bw), -(-ds.height // bh)


def _check_block_index(ds, size: int, level: str) -> str | None:
    """None when every block of every band has bytes inside a file of ``size`` bytes.

    libtiff records a block's offset before writing it and its byte count after: a block whose
    write failed (a full disk) has a count of 0, which GDAL would read back silently as nodata.
    """
    nbx, nby = _block_counts(ds)
    bands = [1] if ds.interleaving == Interleaving.pixel else ds.indexes
    for b in bands:
        for y in range(nby):
            for x in range(nbx):
                off = ds.get_tag_item(f"BLOCK_OFFSET_{x}_{y}", "TIFF", bidx=b)
                n = ds.get_tag_item(f"BLOCK_SIZE_{x}_{y}", "TIFF", bidx=b)
                if not off or not n or int(off) <= 0 or int(n) <= 0 or int(off) + int(n) > size:
                    return f"block {x},{y} of band {b}{level} was not written"
    return None


def _read_blocks(ds, every: bool) -> None:
    """Decode the last block row (the last data written), or every block row with ``every``."""
    bh = ds.block_shapes[0][0]
    last = ((ds.height - 1) // bh) * bh
    for row in range(0, ds.height, bh) if every else [last]:
        ds.read(window=Window(0, row, ds.width, min(bh, ds.height - row)))


def verify_geotiff(
    path: str | os.PathLike, grid: Grid, count: int, dtype: str, every_block: bool = False
) -> str | None:
    """Reopen a just-written GeoTIFF; None when it is whole, else what is wrong (one phrase).

    Checks the grid, band count and type; that every block of every band and overview has
    bytes in the file (the block index: milliseconds); decodes the last block row of the full
    resolution and the whole smallest overview (catching a truncated tail). ``every_block``
    decodes everything (about +40 % of the write time for a 4000 x 4000 float32 output, against
    about +6 % for the default).
    """
    try:
        return _verify_geotiff(Path(path), grid, count, dtype, every_block)
    except (*GDAL_ERRORS, OSError) as exc:
        return f"it does not read back ({_gdal_reason(exc)})"


def _verify_geotiff(path: Path, grid: Grid, count: int, dtype: str, every_block: bool) -> str | None:
    size = os.path.getsize(path)
    with rasterio.open(path) as ds:
        if (ds.width, ds.height, ds.count) != (grid.width, grid.height, count):
            return f"it reads back as {ds.count} x {ds.height} x {ds.width}"
        if set(ds.dtypes) != {dtype}:
            return f"it reads back as {ds.dtypes[0]}, not {dtype}"
        if ds.crs != grid.crs or not ds.transform.almost_equals(grid.transform):
            return "its georeferencing did not survive"
        levels = len(ds.overviews(1))
        problem = _check_block_index(ds, size, "")
        if problem:
            return problem
        _read_blocks(ds, every_block)
    for k in range(levels):
        with rasterio.open(path, overview_level=k) as ov:
            problem = _check_block_index(ov, size, f" of overview {k + 1}")
            if problem:
                return problem
            if k == levels - 1 or every_block:
                _read_blocks(ov, True)
    return None


class RasterWriter:
    """Writes a GeoTIFF on a given grid, atomically.

    Data goes to a hidden temporary file beside the target; on success the file gets overviews
    (and a COG layout), is closed, checked (:func:`verify_geotiff`), flushed to the disk and
    renamed over the target. Every GDAL call runs inside :func:`gdal_errors`, so a failure GDAL
    only reports to its handler (a full disk found while flushing its cache) is noticed and
    nothing is printed. On any exception or failed check the temporary file is deleted and the
    target is untouched; a full disk is ``cannot write PATH: no space left on device``.
    """

    def __init__(
        self,
        path: str | os.PathLike,
        grid: Grid,
        count: int,
        dtype: str,
        nodata: float | None = None,
        descriptions: Sequence[str] | None = None,
        tags: dict[str, str] | None = None,
        inputs: Iterable[str | os.PathLike] = (),
        options: WriteOptions | None = None,
        photometric: str = "minisblack",
    ) -> None:
        self.path = check_output_path(path, inputs)
        options = options or WriteOptions()
        #: "minisblack" (default): every band is data, so a 3- or 4-band uint8 output (masks of
        #: three or four entities) is never taken for RGB(A); "rgb" for imagery.
        self.photometric = photometric
        self.grid, self.count, self.dtype = grid, count, np.dtype(dtype).name
        self.nodata, self.options = nodata, options
        self.descriptions = list(descriptions or [])
        self.tags = dict(tags or {})
        if self.descriptions and len(self.descriptions) != count:
            raise OutputError(f"{len(self.descriptions)} band names for {count} bands")
        self._tmp = temp_beside(self.path, ".partial.tif")
        self._ds = None
        with gdal_errors() as messages:
            try:
                self._ds = rasterio.open(self._tmp, "w", **self._profile())
            except (*GDAL_ERRORS, OSError) as exc:
                self._fail(exc, messages)

    def _profile(self) -> dict:
        g, o = self.grid, self.options
        block = o.blocksize
        tiled = g.width >= block and g.height >= block
        compress = o.intermediate_compress if (o.cog and tiled) else o.compress
        profile = dict(
            driver="GTiff",
            width=g.width,
            height=g.height,
            count=self.count,
            dtype=self.dtype,
            crs=g.crs,
            transform=g.transform,
            nodata=self.nodata,
            compress=compress,
            BIGTIFF="IF_SAFER",
            num_threads=o.threads,
            photometric=self.photometric,
        )
        if compress.lower() in ("deflate", "zstd", "lzw"):
            profile["predictor"] = 3 if np.dtype(self.dtype).kind == "f" else 2
        if compress.lower() == "deflate":
            profile["zlevel"] = o.zlevel
        if compress.lower() == "zstd":
            profile["zstd_level"] = o.zstd_level
        if tiled:
            profile.update(tiled=True, blockxsize=block, blockysize=block)
        return profile

    @property
    def block_rows(self) -> int:
        """Rows per output block: flushing whole block rows keeps GDAL's cache small."""
        return self.options.blocksize if self._profile().get("tiled") else 1

    def _fail(self, exc: BaseException | None, messages: Sequence[str] = ()) -> NoReturn:
        """Delete the temporary file and raise the one-line OutputError for this failure.

        The reason is worked out first, while the temporary file still shows how far it got
        (a size limit) and the disk how full it is.
        """
        err = output_error(self.path, exc, messages, self._tmp)
        self._discard()
        raise err from None

    def write(self, data: np.ndarray, row_off: int, col_off: int = 0) -> None:
        """Write (count, h, w) or (h, w) data at an offset."""
        if data.ndim == 2:
            data = data[None]
        window = Window(col_off, row_off, data.shape[2], data.shape[1])
        assert self._ds is not None  # opened by __init__ (or it raised)
        with gdal_errors() as messages:
            try:
                self._ds.write(data.astype(self.dtype, copy=False), window=window)
            except (*GDAL_ERRORS, OSError) as exc:
                self._fail(exc, messages)
            if _write_failed(messages):
                self._fail(None, messages)

    def _finish(self) -> None:  # noqa: C901
        """Descriptions, tags, close; overviews; COG rewrite; verify; flush and rename.

        The data is closed (GDAL's block cache flushed, where a full disk usually shows) and
        checked *before* overviews are built on the reopened file: GDAL 3.6 building overviews
        on a dataset whose flush has just failed dereferences a dead TIFF handle and crashes
        the process (seen with the disk full a few KB into the file).
        """
        ds = self._ds
        assert ds is not None  # opened by __init__ (or it raised)
        o = self.options
        factors = overview_factors(self.grid.width, self.grid.height, o.blocksize)
        with gdal_errors() as messages:
            try:
                for i, name in enumerate(self.descriptions, start=1):
                    ds.set_band_description(i, name)
                if self.tags:
                    ds.update_tags(**self.tags)
                ds.close()
            except (*GDAL_ERRORS, OSError) as exc:
                self._fail(exc, messages)
            if _write_failed(messages):
                self._fail(None, messages)
            try:
                if o.overviews and factors and not o.cog:
                    self._add_overviews(factors)
                if o.cog and self._profile().get("tiled"):
                    self._to_cog(bool(factors) and o.overviews)
            except (*GDAL_ERRORS, OSError) as exc:
                self._fail(exc, messages)
            if _write_failed(messages):
                self._fail(None, messages)
            problem = verify_geotiff(self._tmp, self.grid, self.count, self.dtype, every_block=o.verify_every_block)
            if problem:
                self._fail(None, [f"incomplete file: {problem}", *messages])
        try:
            publish(self._tmp, self.path)
        except OSError as exc:
            self._fail(exc)

    def _add_overviews(self, factors: list[int]) -> None:
        """Build internal overviews in the closed temporary file (reopened for update)."""
        o = self.options
        with rasterio.open(self._tmp, "r+", num_threads=o.threads) as ds:
            ds.build_overviews(factors, o.overview_resampling)
            ds.update_tags(ns="rio_overview", resampling=o.overview_resampling.name)

    def _to_cog(self, overviews: bool) -> None:
        """Rewrite the finished temporary file in COG layout (streams through GDAL)."""
        from rasterio.shutil import copy as rio_copy

        o = self.options
        cog_tmp = temp_beside(self.path, ".cog.tif")
        try:
            opts = dict(
                driver="COG",
                blocksize=o.blocksize,
                compress=o.compress.upper(),
                overviews="AUTO" if overviews else "NONE",
                bigtiff="IF_SAFER",
                overview_resampling=o.overview_resampling.name.upper(),
                num_threads=o.threads,
            )
            if o.compress.lower() in ("deflate", "zstd", "lzw"):
                opts["predictor"] = "YES"
            if o.compress.lower() == "deflate":
                opts["level"] = o.zlevel
            if o.compress.lower() == "zstd":
                opts["level"] = o.zstd_level
            rio_copy(self._tmp, cog_tmp, **opts)
            os.replace(cog_tmp, self._tmp)
        except BaseException:
            discard(cog_tmp, (".aux.xml",))
            raise

    def _discard(self) -> None:
        """Close (GDAL's flush errors silenced) and delete the temporary file and its sidecars."""
        if self._ds is not None and not self._ds.closed:
            with gdal_errors():
                try:
                    self._ds.close()
                except (*GDAL_ERRORS, OSError):
                    pass  # already failing; the file is deleted below
        discard(self._tmp, (".aux.xml",))

    def __enter__(self) -> RasterWriter:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is not None:
            self._discard()
            return
        try:
            self._finish()
        except BaseException:
            self._discard()
            raise


def overview_factors(width: int, height: int, blocksize: int = 512) -> list[int]:
    """2, 4, 8 ... until the smallest overview fits in one block."""
    factors, f = [], 2
    while max(width, height) / f >= blocksize / 2 and max(width, height) > blocksize:
        factors.append(f)
        f *= 2
    return factors


def write_array(
    path: str | os.PathLike,
    data: np.ndarray,
    grid: Grid,
    nodata: float | None = None,
    descriptions: Sequence[str] | None = None,
    tags: dict[str, str] | None = None,
    inputs: Iterable[str | os.PathLike] = (),
    options: WriteOptions | None = None,
    photometric: str = "minisblack",
) -> Path:
    """Write a whole in-memory array (count, H, W) or (H, W); for small results and tests."""
    arr = data[None] if data.ndim == 2 else data
    with RasterWriter(
        path,
        grid,
        arr.shape[0],
        arr.dtype.name,
        nodata=nodata,
        descriptions=descriptions,
        tags=tags,
        inputs=inputs,
        options=options,
        photometric=photometric,
    ) as w:
        w.write(arr, 0)
    return Path(path)


def read_classes_json(path: str | os.PathLike, error: type[Exception] = InputError) -> dict[int, str]:
    """A class raster's ``classes.json``: {class id: name} as written (names stripped).

    Accepts ``{"1": "road", ...}`` or ``{"classes": {...}}``. A missing file is an InputError;
    a malformed one raises ``error`` (stages pick their own error class), in one line.
    """
    p = Path(path)
    if not p.exists():
        raise InputError(f"--classes {p}: no such file")
    text = read_text_limited(p, MAX_JSON_BYTES, "--classes")
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise error(f"--classes {p}: not a JSON file ({str(exc)[:120]})") from None
    if isinstance(data, dict) and isinstance(data.get("classes"), dict):
        data = data["classes"]
    if not isinstance(data, dict) or not data:
        raise error(
            f'--classes {p}: expected an object mapping class ids to names, e.g. {{"1": "building", "2": "road"}}'
        )
    names: dict[int, str] = {}
    for key, name in data.items():
        try:
            cid = int(key)
        except (TypeError, ValueError):
            raise error(f"--classes {p}: class id {key!r} is not an integer") from None
        if not isinstance(name, str) or not name.strip():
            raise error(f"--classes {p}: class {cid} has no name")
        names[cid] = name.strip()
    return names


def read_band_window(path: str | os.PathLike, band: int | Sequence[int], window: Window | None = None) -> np.ndarray:
    """Read one or more bands of a raster window, with the same one-line errors as the reader."""
    with open_raster(path) as ds:
        try:
            return ds.read(band, window=window)
        except GDAL_ERRORS as exc:
            raise RasterError(f"{path}: corrupt or truncated raster ({_gdal_reason(exc)})") from None


__all__ = [
    "Chip",
    "Grid",
    "GroundScale",
    "RasterInfo",
    "RasterSource",
    "RasterWriter",
    "ReadPlan",
    "WriteOptions",
    "check_output_path",
    "crs_label",
    "gdal_errors",
    "open_raster",
    "overview_factors",
    "parse_bands",
    "parse_crs",
    "ground_scale",
    "pixel_size_m",
    "read_band_window",
    "read_classes_json",
    "read_grid",
    "read_info",
    "verify_geotiff",
    "write_array",
]
