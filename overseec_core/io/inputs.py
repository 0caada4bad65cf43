"""What an input must be, checked before a stage works on it.

A raster of the wrong kind usually opens fine and gives plausible-looking output: an RGB photo
given as ``--labels`` would have its red channel read as class ids, a ``classes.json`` from
another dataset would match nothing and give a uniform costmap. These checks turn such
mistakes into one-line errors (or warnings, where the input may still be what the user meant).
"""

from __future__ import annotations

import functools
import os
from collections.abc import Collection
from pathlib import Path

import numpy as np
from rasterio.windows import Window

from overseec_core.errors import InputError, RasterError
from overseec_core.io.read import open_raster
from overseec_core.limits import check_pixels

#: Rows read at a time when listing a class raster's ids (bounded memory on any width).
_STRIP_ROWS = 512
#: Ids class rasters use for background or "ignore" (a classes.json names them as background,
#: and the callers pass its entity ids only): never counted as ids classes.json fails to name.
BACKGROUND_IDS = frozenset({0, 255})


def _ids_text(ids: Collection[int], most: int = 12) -> str:
    listed = sorted(ids)
    more = f" and {len(listed) - most} more" if len(listed) > most else ""
    return (", ".join(str(c) for c in listed[:most]) or "none") + more


def check_class_raster(
    path: str | os.PathLike,
    class_ids: Collection[int],
    what: str = "--labels",
    background_ids: Collection[int] = BACKGROUND_IDS,
) -> list[str]:
    """Refuse a class raster that is not one band of integer ids, or that does not go with
    ``class_ids`` (the entity ids of classes.json, background left out): none of them occurs in
    it, or more than half of them do not while the raster holds ids classes.json does not name
    (other than ``background_ids``): a classes.json of another dataset or version. Return
    warnings naming a class id that is the raster's nodata and the ``class_ids`` absent from it."""
    p = Path(path)
    with open_raster(p) as ds:
        nodata = ds.nodatavals[0] if ds.count else None
        if ds.count != 1:
            raise InputError(
                f"{what} {p} has {ds.count} bands; a class raster has one band of integer class ids (is this an image?)"
            )
        if np.dtype(ds.dtypes[0]).kind not in "iu":
            raise InputError(f"{what} {p}: a class raster holds integer class ids, not {ds.dtypes[0]}")
        check_pixels(ds.width, ds.height, p, "class raster")  # before reading all of it
    present = class_ids_present(str(p.resolve()), p.stat().st_size, p.stat().st_mtime_ns)
    wanted = set(int(c) for c in class_ids)
    if not wanted & present:
        raise InputError(
            f"{what} {p}: none of the class ids in classes.json ({_ids_text(wanted)}) occurs in the raster "
            f"(ids found: {_ids_text(present)}); is this the right classes.json?"
        )
    nodata_id = int(nodata) if nodata is not None and float(nodata).is_integer() else None
    absent = wanted - present - {nodata_id}
    unnamed = present - wanted - set(int(b) for b in background_ids)
    if 2 * len(absent) > len(wanted) and unnamed:
        raise InputError(
            f"{what} {p}: {len(absent)} of the {len(wanted)} class ids in classes.json ({_ids_text(absent)}) "
            f"do not occur in the raster, which holds ids classes.json does not name ({_ids_text(unnamed)}; "
            f"ids found: {_ids_text(present)}); is this the right classes.json?"
        )
    warnings = []
    if nodata_id is not None and nodata_id in wanted:
        # not missing: the raster marks those pixels as no data, so the class never applies
        warnings.append(
            f"{what} {p.name}: class id {nodata_id} of classes.json is the raster's nodata value; "
            "its pixels are read as no data (impassable), not as that class"
        )
    missing = sorted(wanted - present - {nodata_id})
    if missing:
        warnings.append(
            f"{what} {p.name}: class id(s) {', '.join(map(str, missing))} of classes.json do not occur in the raster"
        )
    return warnings


@functools.lru_cache(maxsize=16)
def class_ids_present(path: str, size: int, mtime_ns: int) -> frozenset[int]:
    """The class ids a raster holds (nodata excluded), read in strips.

    Cached on (path, size, mtime): a run opens the same labels more than once.
    """
    ids: set[int] = set()
    with open_raster(path) as ds:
        nodata = ds.nodatavals[0]
        for r0 in range(0, ds.height, _STRIP_ROWS):
            window = Window(0, r0, ds.width, min(_STRIP_ROWS, ds.height - r0))
            try:
                strip = ds.read(1, window=window)
            except Exception as exc:  # rasterio raises RasterioError; GDAL can surface others
                raise RasterError(f"{path}: corrupt or truncated raster ({' '.join(str(exc).split())[:160]})") from None
            ids.update(_unique_ids(strip))
    if nodata is not None and float(nodata).is_integer():
        ids.discard(int(nodata))
    return frozenset(ids)


def check_image_data(path: str | os.PathLike, preview_px: int = 1024) -> None:
    """Refuse an image that cannot be read through or holds no valid pixel at all.

    Reads a decimated preview (from overviews when the file has them, else every block once, as
    the truncation check needs): a truncated file is a RasterError, an all-nodata or all-NaN one
    an InputError, before any stage writes a file.
    """
    p = Path(path)
    with open_raster(p) as ds:
        scale = max(1.0, max(ds.width, ds.height) / preview_px)
        shape = (ds.count, max(1, round(ds.height / scale)), max(1, round(ds.width / scale)))
        try:
            data = ds.read(out_shape=shape, masked=True)
        except Exception as exc:  # rasterio raises RasterioError; GDAL can surface others
            raise RasterError(f"{p}: corrupt or truncated raster ({' '.join(str(exc).split())[:160]})") from None
    valid = ~np.ma.getmaskarray(data)
    if data.dtype.kind == "f":
        valid &= np.isfinite(np.ma.getdata(data))
    if not valid.any():
        raise InputError(f"{p}: the image has no valid pixel (all nodata, masked or NaN)")


def _unique_ids(strip: np.ndarray) -> list[int]:
    """Distinct values of an integer strip; a histogram for 8- and 16-bit ids (far faster)."""
    if strip.dtype in (np.uint8, np.uint16):
        return np.flatnonzero(np.bincount(strip.ravel())).tolist()
    return np.unique(strip).tolist()


__all__ = ["check_class_raster", "check_image_data", "class_ids_present"]
