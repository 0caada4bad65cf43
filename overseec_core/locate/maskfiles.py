"""The segment folder's rasters as a mask edit sees them: which files an edit writes, and
replacing one band's window of a GeoTIFF atomically.

:class:`MaskFiles` finds the mask raster (refined masks over coarse ones), its probability and,
beside refined masks, the gated raster, with the entity each band holds. :func:`write_window`
updates one band's window of a copy beside the file (overviews rebuilt), checks it, and renames
it over the original, so a failure never leaves a half-written file under the original's name;
the click-to-fix session (:mod:`overseec_core.locate.interactive`) runs its writes through it
inside one output transaction.
"""

from __future__ import annotations

import os
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import rasterio
from rasterio.enums import Resampling
from rasterio.windows import Window

from overseec_core import runfiles
from overseec_core.errors import InputError, OutputError, RasterError
from overseec_core.io.atomic import atomic_path
from overseec_core.io.grid import Grid
from overseec_core.io.read import GDAL_ERRORS, open_raster
from overseec_core.io.write import gdal_errors, verify_geotiff


@dataclass(frozen=True)
class MaskFiles:
    """The rasters an edit of a segment folder writes: mask, probability, and gated beside refined
    masks; entity names from the mask's band descriptions."""

    folder: Path
    mask: Path
    probability: Path | None
    gated: Path | None
    entities: tuple[str, ...]
    grid: Grid

    @staticmethod
    def find(folder: str | os.PathLike) -> MaskFiles:
        """The files of ``folder`` (a one-line InputError when it holds no masks)."""
        d = Path(folder)
        mask = runfiles.first_existing(d, "mask") if d.is_dir() else None
        if mask is None:
            raise InputError(f"{d}: no {runfiles.MASKS} or {runfiles.REFINED_MASKS}; run `overseec segment` first")
        pair = dict(runfiles.MASK_FILES)[mask.name]
        prob = d / pair if (d / pair).is_file() else None
        gated = d / runfiles.GATED if mask.name == runfiles.REFINED_MASKS and (d / runfiles.GATED).is_file() else None
        with open_raster(mask) as ds:
            if ds.crs is None:
                raise RasterError(f"{mask} has no CRS")
            grid = Grid(ds.crs, ds.transform, ds.width, ds.height)
            names = tuple((n or "").strip() for n in ds.descriptions)
        if not all(names) or len(set(names)) != len(names):
            raise InputError(f"{mask}: each band must be named after its entity (band descriptions)")
        return MaskFiles(d, mask, prob, gated, names, grid)

    def band(self, entity: str) -> int:
        """The 1-based band of an entity (a one-line InputError naming the ones there are)."""
        try:
            return self.entities.index(entity) + 1
        except ValueError:
            raise InputError(f"no entity {entity!r} in {self.mask.name}; it has {', '.join(self.entities)}") from None

    def stamp(self) -> tuple[int, int]:
        """What changes when the mask file is replaced (mtime in ns, size)."""
        st = os.stat(self.mask)
        return st.st_mtime_ns, st.st_size


def read_window(path: Path, band: int, window: Window) -> np.ndarray:
    """One band's window of a raster (a one-line RasterError for a corrupt file)."""
    with open_raster(path) as ds:
        try:
            return ds.read(band, window=window)
        except GDAL_ERRORS as exc:
            raise RasterError(f"{path}: corrupt or truncated raster ({' '.join(str(exc).split())[:160]})") from None


def write_window(path: Path, band: int, window: Window, values: np.ndarray) -> None:
    """Replace one band's window of a GeoTIFF atomically: a copy beside it is updated in place
    (rasterio ``r+``; overviews rebuilt when it has any), checked, and renamed over ``path``."""
    with atomic_path(path, ".partial.tif", (".aux.xml",)) as tmp:
        shutil.copyfile(path, tmp)
        with gdal_errors() as messages:
            try:
                with rasterio.open(tmp, "r+") as ds:
                    ds.write(values.astype(ds.dtypes[band - 1], copy=False), band, window=window)
                    factors = ds.overviews(1)
                    if factors:
                        method = ds.tags(ns="rio_overview").get("resampling", "nearest")
                        ds.build_overviews(factors, Resampling[method])
                    grid = Grid(ds.crs, ds.transform, ds.width, ds.height)
                    count, dtype = ds.count, ds.dtypes[0]
            except GDAL_ERRORS as exc:
                raise OutputError(f"cannot update {path}: {' '.join(str(exc).split())[:160]}") from None
            if messages:
                raise OutputError(f"cannot update {path}: {messages[-1]}")
        problem = verify_geotiff(tmp, grid, count, dtype)
        if problem:
            raise OutputError(f"cannot update {path}: {problem}")


def scaled(prob: np.ndarray, dtype: np.dtype) -> np.ndarray:
    """Probabilities in a band's type (integer bands hold 0..max)."""
    if np.dtype(dtype).kind in "ui":
        return np.round(prob * float(np.iinfo(dtype).max))
    return prob


__all__ = ["MaskFiles", "read_window", "scaled", "write_window"]
