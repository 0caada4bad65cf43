"""Georeferenced raster input.

:class:`RasterSource` opens any GDAL raster and serves RGB uint8 chips for windows, whatever the
source is (RGB, RGBA, panchromatic, uint16/float, multispectral with a band choice), plus a validity
mask from alpha/nodata/internal masks. Intensity stretching is computed once for the whole image from
a decimated read (GDAL uses overviews when present), never per tile, so tiles agree with each other.

Everything uses the rasterio 1.3 API (Debian's python3-rasterio), one GDAL in the process.
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import rasterio
from rasterio._err import CPLE_BaseError
from rasterio.crs import CRS
from rasterio.enums import ColorInterp, MaskFlags, Resampling
from rasterio.errors import NotGeoreferencedWarning, RasterioError, RasterioIOError
from rasterio.transform import Affine
from rasterio.windows import Window

from overseec_core.errors import InputError, RasterError
from overseec_core.io.grid import Grid, crs_label, parse_crs, pixel_size_m
from overseec_core.limits import MAX_JSON_BYTES, read_json_limited

#: Longest side of the decimated read used to compute the stretch percentiles.
STRETCH_SAMPLE_SIZE = 2048
DEFAULT_PERCENTILES = (2.0, 98.0)
#: What GDAL failures surface as through rasterio 1.3 (RasterioIOError is not a RasterioError there).
GDAL_ERRORS = (RasterioError, RasterioIOError, CPLE_BaseError)


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


def open_raster(path: str | os.PathLike, *, threads: bool = False) -> rasterio.DatasetReader:
    """Open a raster for reading, turning GDAL's failures into one-line RasterErrors.

    ``threads``: decode a compressed GeoTIFF's blocks on every core (GDAL's ``NUM_THREADS``
    open option): for a file read whole, e.g. a costmap loaded for planning, where it halves
    the wall time on two cores. Other drivers ignore the option."""
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
            ds = rasterio.open(p, **({"NUM_THREADS": "ALL_CPUS"} if threads else {}))
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


def read_classes_json(path: str | os.PathLike, error: type[Exception] = InputError) -> dict[int, str]:
    """A class raster's ``classes.json``: {class id: name} as written (names stripped).

    Accepts ``{"1": "road", ...}`` or ``{"classes": {...}}``. A missing file is an InputError;
    a malformed one raises ``error`` (stages pick their own error class), in one line.
    """
    p = Path(path)
    if not p.exists():
        raise InputError(f"--classes {p}: no such file")
    try:
        data = read_json_limited(p, MAX_JSON_BYTES, "--classes")
    except InputError as exc:  # a stage may file a malformed table under its own error class
        raise error(str(exc)) from None
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
