"""Evaluation charts as PNG files (matplotlib, Agg backend, no pyplot global state): RRPI vs length, IoU.

Figures are built with :class:`matplotlib.figure.Figure` and rendered by the Agg canvas, so
plotting works headless, in threads and inside QGIS without touching pyplot's figure registry.
Every file is written under a temporary name and renamed when complete. The map figures (a
costmap with paths) are in :mod:`.maps`, which builds and saves its figures with the two helpers
here.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from overseec_core.io.atomic import atomic_path

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def new_figure(width_in: float, height_in: float) -> Figure:
    """A blank figure on an Agg canvas (no pyplot), at the evaluation plots' resolution."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg  # lazy: only drawing loads matplotlib
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width_in, height_in), dpi=110)
    FigureCanvasAgg(fig)
    return fig


def save_png(fig: Figure, path: str | os.PathLike) -> Path:
    """Write ``fig`` as a PNG at ``path`` (under a temporary name, renamed when complete)."""
    with atomic_path(path, suffix=".partial.png") as tmp:
        fig.savefig(tmp, format="png")
    return Path(path)


# --------------------------------------------------------------------------------------------
# RRPI vs length
# --------------------------------------------------------------------------------------------


def plot_rrpi_vs_length(
    path: str | os.PathLike,
    lengths: Sequence[float],
    values: Sequence[float],
    kde=None,
    fit=None,
    title: str = "RRPI vs path length",
) -> Path:
    """Scatter of (length, RRPI) per path, KDE contours, centre of mass and mode, fitted line.

    ``kde`` is an :class:`overseec_core.evaluate.KdeSummary`, ``fit`` a ``LinearFit`` (both optional).
    """
    fig = new_figure(6.4, 4.8)
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
        ax.plot(
            xx,
            fit.slope * xx + fit.intercept,
            color="darkorange",
            lw=1.5,
            zorder=4,
            label=f"fit: {fit.slope * 1000:.3g} RRPI/km, r={fit.r:.2f}",
        )
    if kde is not None:
        ax.scatter(
            [kde.com[0]],
            [kde.com[1]],
            marker="*",
            s=260,
            c="crimson",
            edgecolors="white",
            zorder=5,
            label=f"KDE centre of mass ({kde.com[0]:.0f} m, {kde.com[1]:.1f})",
        )
        if kde.density is not None:
            ax.scatter(
                [kde.mode[0]],
                [kde.mode[1]],
                marker="X",
                s=90,
                c="purple",
                edgecolors="white",
                zorder=5,
                label="KDE mode",
            )
    ax.set_xlabel("path length (m)")
    ax.set_ylabel("RRPI (sum of rank - 1 over path pixels)")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", fontsize=8, framealpha=0.85)
    fig.tight_layout()
    return save_png(fig, path)


# --------------------------------------------------------------------------------------------
# IoU
# --------------------------------------------------------------------------------------------


def plot_iou(
    path: str | os.PathLike, names: Sequence[str], values: Sequence[float | None], mean_iou: float | None = None
) -> Path:
    """Bar chart of IoU per class (classes without pixels in either raster shown empty)."""
    fig = new_figure(max(4.0, 0.8 * len(names) + 2.0), 4.0)
    ax = fig.add_subplot(1, 1, 1)
    heights = [v if v is not None else 0.0 for v in values]
    bars = ax.bar(range(len(names)), heights, color="seagreen")
    for bar, v in zip(bars, values):
        ax.text(
            bar.get_x() + bar.get_width() / 2,
            bar.get_height() + 0.02,
            "n/a" if v is None else f"{v:.2f}",
            ha="center",
            fontsize=8,
        )
    if mean_iou is not None:
        ax.axhline(mean_iou, color="darkorange", ls="--", lw=1.2, label=f"mean IoU {mean_iou:.3f}")
        ax.legend(loc="upper right", fontsize=8)
    ax.set_xticks(range(len(names)))
    ax.set_xticklabels(names, rotation=30, ha="right", fontsize=8)
    ax.set_ylim(0, 1.1)
    ax.set_ylabel("IoU")
    ax.set_title("IoU per class")
    fig.tight_layout()
    return save_png(fig, path)
