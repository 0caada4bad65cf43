"""Evaluation plots as PNG files (matplotlib, Agg backend, no pyplot global state).

Figures are built with :class:`matplotlib.figure.Figure` and rendered by the Agg canvas, so
plotting works headless, in threads and inside QGIS without touching pyplot's figure registry.
Rasters are read decimated (``out_shape``; GDAL uses overviews when the file has them), never in
full, so a 50 000 px image costs a preview-sized read. Every file is written under a temporary
name and renamed when complete.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import numpy as np
from rasterio.enums import Resampling

from .atomic import atomic_path
from .errors import EvaluateError
from .raster import Grid, RasterSource, crs_label, open_raster

#: Longest side, in pixels, of rasters read for display.
DEFAULT_DISPLAY_SIZE = 1600


def _figure(width_in: float, height_in: float):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width_in, height_in), dpi=110)
    FigureCanvasAgg(fig)
    return fig


def _save(fig, path: str | os.PathLike) -> Path:
    with atomic_path(path, suffix=".partial.png") as tmp:
        fig.savefig(tmp, format="png")
    return Path(path)


# --------------------------------------------------------------------------------------------
# RRPI vs length
# --------------------------------------------------------------------------------------------


def plot_rrpi_vs_length(path: str | os.PathLike, lengths: Sequence[float], values: Sequence[float],
                        kde=None, fit=None, title: str = "RRPI vs path length") -> Path:
    """Scatter of (length, RRPI) per path, KDE contours, centre of mass and mode, fitted line.

    ``kde`` is an :class:`overseec_core.evaluate.KdeSummary`, ``fit`` a ``LinearFit`` (both optional).
    """
    fig = _figure(6.4, 4.8)
    ax = fig.add_subplot(1, 1, 1)
    x = np.asarray(lengths, dtype=float)
    y = np.asarray(values, dtype=float)
    if kde is not None and kde.density is not None:
        top = float(kde.density.max())
        levels = np.linspace(0.05 * top, top, 8)  # below 5 % of the peak stays white
        ax.contourf(kde.xs, kde.ys, kde.density, levels=levels, cmap="Blues", alpha=0.55)
        ax.contour(kde.xs, kde.ys, kde.density, levels=levels, colors="steelblue", linewidths=0.6)
    ax.scatter(x, y, s=18, c="black", alpha=0.75, label=f"paths (n={len(x)})", zorder=3)
    if fit is not None and len(x):
        xx = np.array([x.min(), x.max()])
        ax.plot(xx, fit.slope * xx + fit.intercept, color="darkorange", lw=1.5, zorder=4,
                label=f"fit: {fit.slope * 1000:.3g} RRPI/km, r={fit.r:.2f}")
    if kde is not None:
        ax.scatter([kde.com[0]], [kde.com[1]], marker="*", s=260, c="crimson", edgecolors="white",
                   zorder=5, label=f"KDE centre of mass ({kde.com[0]:.0f} m, {kde.com[1]:.1f})")
        if kde.density is not None:
            ax.scatter([kde.mode[0]], [kde.mode[1]], marker="X", s=90, c="purple", edgecolors="white",
                       zorder=5, label="KDE mode")
    ax.set_xlabel("path length (m)")
    ax.set_ylabel("RRPI (sum of rank - 1 over path pixels)")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", fontsize=8, framealpha=0.85)
    fig.tight_layout()
    return _save(fig, path)


# --------------------------------------------------------------------------------------------
# Costmap / image with paths
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class PlotPath:
    """A path to draw, in the costmap's (row, col) pixel coordinates."""

    rows_cols: np.ndarray  # (N, 2)
    kind: str = "system"  # "system" (planned or given) or "reference"
    label: str | None = None


def display_shape(width: int, height: int, max_size: int) -> tuple[int, int]:
    """(rows, cols) of a decimated read whose longer side is at most ``max_size``."""
    scale = max(width, height) / max_size
    if scale <= 1:
        return height, width
    return max(1, round(height / scale)), max(1, round(width / scale))


def read_costmap_preview(path: str | os.PathLike, max_size: int = DEFAULT_DISPLAY_SIZE) -> np.ma.MaskedArray:
    """Band 1 of a costmap, decimated (averaged), nodata masked."""
    with open_raster(path) as ds:
        shape = display_shape(ds.width, ds.height, max_size)
        data = ds.read(1, out_shape=shape, resampling=Resampling.average, masked=True)
    data = np.ma.masked_invalid(data.astype(np.float32))
    return data


def read_image_preview(path: str | os.PathLike, max_size: int = DEFAULT_DISPLAY_SIZE
                       ) -> tuple[np.ndarray, Grid]:
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


def _extent_in(grid: Grid, target: Grid) -> tuple[float, float, float, float]:
    """imshow extent (left, right, bottom, top) of ``grid`` in ``target``'s pixel coordinates.

    Pixel (row, col) of ``target`` is centred on integer coordinates, so paths given as pixel
    indices line up with the raster without rescaling.
    """
    if grid.crs != target.crs:
        raise EvaluateError(f"--image is in {crs_label(grid.crs)} but the costmap is in "
                            f"{crs_label(target.crs)}; use an image on the costmap's CRS")
    inv = ~target.transform
    c0, r0 = inv * (grid.transform * (0, 0))
    c1, r1 = inv * (grid.transform * (grid.width, grid.height))
    return (c0 - 0.5, c1 - 0.5, r1 - 0.5, r0 - 0.5)


def plot_paths_overlay(path: str | os.PathLike, grid: Grid, paths: Sequence[PlotPath],
                       costmap: str | os.PathLike | None = None, image: str | os.PathLike | None = None,
                       max_size: int = DEFAULT_DISPLAY_SIZE, title: str = "paths") -> Path:
    """The costmap (translucent over the image when one is given) with paths, starts and goals.

    ``grid`` is the costmap's grid: paths are drawn in its pixel coordinates.
    """
    aspect = grid.height / max(grid.width, 1)
    fig = _figure(7.5, max(3.0, min(6.0 * aspect, 12.0)) + 1.0)  # ~6 in of map beside the colour bar
    ax = fig.add_subplot(1, 1, 1)
    full = (-0.5, grid.width - 0.5, grid.height - 0.5, -0.5)
    if image is not None:
        rgba, img_grid = read_image_preview(image, max_size)
        ax.imshow(rgba, extent=_extent_in(img_grid, grid), interpolation="bilinear", zorder=0)
    if costmap is not None:
        cost = read_costmap_preview(costmap, max_size)
        im = ax.imshow(cost, extent=full, cmap="magma_r", vmin=0.0, vmax=1.0,
                       alpha=0.5 if image is not None else 1.0, interpolation="nearest", zorder=1)
        cbar = fig.colorbar(im, ax=ax, fraction=0.04, pad=0.02)
        cbar.set_label("cost (lower = better)")
    system = [p for p in paths if p.kind != "reference"]
    width = 1.6 if len(system) <= 10 else 0.9
    for k, p in enumerate(paths):
        rc = np.asarray(p.rows_cols, dtype=float).reshape(-1, 2)
        if len(rc) == 0:
            continue
        if p.kind == "reference":
            ax.plot(rc[:, 1], rc[:, 0], color="white", lw=3.2, alpha=0.9, zorder=2)
            ax.plot(rc[:, 1], rc[:, 0], color="black", lw=1.4, ls="--", zorder=2,
                    label=p.label if p.label else None)
        else:
            ax.plot(rc[:, 1], rc[:, 0], color="deepskyblue", lw=width, alpha=0.85, zorder=3,
                    label=p.label if p.label else None)
    if system:
        starts = np.array([np.asarray(p.rows_cols)[0] for p in system if len(p.rows_cols)])
        goals = np.array([np.asarray(p.rows_cols)[-1] for p in system if len(p.rows_cols)])
        ax.scatter(starts[:, 1], starts[:, 0], marker="o", s=30, c="lime", edgecolors="black",
                   linewidths=0.6, zorder=4, label="start")
        ax.scatter(goals[:, 1], goals[:, 0], marker="X", s=40, c="red", edgecolors="black",
                   linewidths=0.6, zorder=4, label="goal")
    ax.set_xlim(full[0], full[1])
    ax.set_ylim(full[2], full[3])
    ax.set_xlabel("column (px)")
    ax.set_ylabel("row (px)")
    ax.set_title(title)
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        ax.legend(loc="upper right", fontsize=7, framealpha=0.85)
    fig.tight_layout()
    return _save(fig, path)


# --------------------------------------------------------------------------------------------
# IoU
# --------------------------------------------------------------------------------------------


def plot_iou(path: str | os.PathLike, names: Sequence[str], values: Sequence[float | None],
             mean_iou: float | None = None) -> Path:
    """Bar chart of IoU per class (classes without pixels in either raster shown empty)."""
    fig = _figure(max(4.0, 0.8 * len(names) + 2.0), 4.0)
    ax = fig.add_subplot(1, 1, 1)
    heights = [v if v is not None else 0.0 for v in values]
    bars = ax.bar(range(len(names)), heights, color="seagreen")
    for bar, v in zip(bars, values):
        ax.text(bar.get_x() + bar.get_width() / 2, bar.get_height() + 0.02,
                "n/a" if v is None else f"{v:.2f}", ha="center", fontsize=8)
    if mean_iou is not None:
        ax.axhline(mean_iou, color="darkorange", ls="--", lw=1.2, label=f"mean IoU {mean_iou:.3f}")
        ax.legend(loc="upper right", fontsize=8)
    ax.set_xticks(range(len(names)))
    ax.set_xticklabels(names, rotation=30, ha="right", fontsize=8)
    ax.set_ylim(0, 1.1)
    ax.set_ylabel("IoU")
    ax.set_title("IoU per class")
    fig.tight_layout()
    return _save(fig, path)
