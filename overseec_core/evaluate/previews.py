"""Rasters read for display: a costmap or an image decimated to preview size, never read in full.

Reads use ``out_shape`` (GDAL uses overviews when the file has them), so a 50 000 px image costs
a preview-sized read. The map figures (:mod:`.maps`) draw these.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from rasterio.enums import Resampling

from overseec_core.io.grid import Grid
from overseec_core.io.read import RasterSource, open_raster
from overseec_core.plan.grid import _find_lethal

#: Longest side, in pixels, of rasters read for display.
DEFAULT_DISPLAY_SIZE = 1600


@dataclass(frozen=True, eq=False)
class CostPreview:
    """A decimated costmap for display: mean cost, lethal and nodata cells.

    ``cost`` is masked where a display cell is lethal or has no data. A display cell is lethal
    when at least half of its valid source cells are; it has no data when none is valid.
    ``covers`` is the (columns, rows) of source pixels the preview spans from the grid's origin
    (a little more than the grid when the decimation factor does not divide its size).
    """

    cost: np.ma.MaskedArray
    lethal: np.ndarray
    nodata: np.ndarray
    covers: tuple[float, float]


def display_shape(width: int, height: int, max_size: int) -> tuple[int, int]:
    """(rows, cols) of a decimated read whose longer side is at most ``max_size``."""
    scale = max(width, height) / max_size
    if scale <= 1:
        return height, width
    return max(1, round(height / scale)), max(1, round(width / scale))


def cost_preview_from_array(cost: np.ndarray, max_size: int = DEFAULT_DISPLAY_SIZE) -> CostPreview:
    """Decimate an in-memory costmap (float, ``+inf`` = lethal, NaN = nodata; e.g.
    ``PlanningGrid.cost``) by block means, one strip of blocks at a time (no full-size temporaries)."""
    h, w = cost.shape
    f = max(1, math.ceil(max(h, w) / max_size))
    oh, ow = math.ceil(h / f), math.ceil(w / f)
    mean = np.zeros((oh, ow), dtype=np.float32)
    lethal = np.zeros((oh, ow), dtype=bool)
    nodata = np.zeros((oh, ow), dtype=bool)
    for i in range(oh):
        strip = np.asarray(cost[i * f : (i + 1) * f], dtype=np.float32)
        if strip.shape[1] != ow * f:
            strip = np.concatenate([strip, np.full((strip.shape[0], ow * f - w), np.nan, np.float32)], axis=1)
        blocks = strip.reshape(strip.shape[0], ow, f)
        finite = np.isfinite(blocks)
        n_finite = finite.sum(axis=(0, 2))
        n_lethal = np.isposinf(blocks).sum(axis=(0, 2))
        total = np.where(finite, blocks, 0.0).sum(axis=(0, 2))
        mean[i] = total / np.maximum(n_finite, 1)
        lethal[i] = (n_lethal > 0) & (2 * n_lethal >= n_finite + n_lethal)
        nodata[i] = (n_finite + n_lethal) == 0
    return CostPreview(
        cost=np.ma.masked_array(mean, mask=lethal | nodata),
        lethal=lethal,
        nodata=nodata,
        covers=(float(ow * f), float(oh * f)),
    )


def read_cost_preview(path: str | os.PathLike, max_size: int = DEFAULT_DISPLAY_SIZE) -> CostPreview:
    """Band 1 of a costmap file, decimated (averaged), with its lethal cells.

    Lethal cells are +inf in the file or flagged by its lethal sidecar (found as the planner
    finds it; read decimated with the majority value of each display cell).
    """
    p = Path(path)
    with open_raster(p) as ds:
        shape = display_shape(ds.width, ds.height, max_size)
        tags = dict(ds.tags())
        data = ds.read(1, out_shape=shape, resampling=Resampling.average, masked=True)
        width, height = ds.width, ds.height
    data = data.astype(np.float32)
    values = np.ma.getdata(data)
    nodata = np.ma.getmaskarray(data) | np.isnan(values)
    lethal = np.isposinf(values) & ~nodata
    sidecar = _lethal_sidecar(p, tags)
    if sidecar is not None:
        with open_raster(sidecar) as ds:
            if (ds.width, ds.height) == (width, height):
                flags = ds.read(1, out_shape=shape, resampling=Resampling.mode, masked=True)
                lethal |= np.ma.filled(flags != 0, False) & ~nodata
    cost: np.ma.MaskedArray = np.ma.masked_array(
        np.where(np.isfinite(values), values, 0.0).astype(np.float32), mask=lethal | nodata
    )
    return CostPreview(cost=cost, lethal=lethal, nodata=nodata, covers=(float(width), float(height)))


def _lethal_sidecar(costmap: Path, tags: dict) -> Path | None:
    """The costmap's lethal sidecar as the planner finds it, or None (never an error: it is a plot)."""
    try:
        return _find_lethal(costmap, tags, None)
    except Exception:  # a missing or misnamed sidecar only leaves lethal cells undrawn
        return None


def read_image_preview(path: str | os.PathLike, max_size: int = DEFAULT_DISPLAY_SIZE) -> tuple[np.ndarray, Grid]:
    """RGBA uint8 preview of an image, decimated, read as the pipeline reads it.

    Band choice and intensity stretch come from :class:`RasterSource` (computed once for the
    whole image); pixels without data are transparent.
    """
    with RasterSource(path) as src:
        plan, grid = src.info.plan, src.grid
    with open_raster(path) as ds:
        shape = display_shape(ds.width, ds.height, max_size)
        unique = sorted(set(plan.rgb_bands))
        data = ds.read(unique, out_shape=(len(unique), *shape), resampling=Resampling.average)
        mask = ds.read_masks(unique, out_shape=(len(unique), *shape), resampling=Resampling.nearest)
    index = {b: k for k, b in enumerate(unique)}
    channels = []
    for i, b in enumerate(plan.rgb_bands):
        band = data[index[b]].astype(np.float32)
        if plan.stretch is not None:
            lo, hi = plan.stretch[i]
            band = np.clip(np.nan_to_num((band - lo) * (255.0 / (hi - lo))), 0, 255)
        channels.append(band.astype(np.uint8))
    alpha = np.where(mask.min(axis=0) > 0, 255, 0).astype(np.uint8)
    return np.dstack(channels + [alpha]), grid
