"""Evaluation plots as PNG files (matplotlib, Agg backend, no pyplot global state).

Figures are built with :class:`matplotlib.figure.Figure` and rendered by the Agg canvas, so
plotting works headless, in threads and inside QGIS without touching pyplot's figure registry.
Rasters are read decimated (``out_shape``; GDAL uses overviews when the file has them), never in
full, so a 50 000 px image costs a preview-sized read. Every file is written under a temporary
name and renamed when complete.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from rasterio.enums import Resampling

from overseec_core.errors import EvaluateError
from overseec_core.io.atomic import atomic_path
from overseec_core.io.grid import Grid, crs_label
from overseec_core.io.read import RasterSource, open_raster

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

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
    return _save(fig, path)


# --------------------------------------------------------------------------------------------
# Costmap / image with paths, in map coordinates
# --------------------------------------------------------------------------------------------

#: Colour of lethal cells on the overlay: outside the cost ramp (RdYlGn_r, the QGIS style's).
LETHAL_COLOUR = "#000000"
COST_CMAP = "RdYlGn_r"
#: Colours of system paths, one per pair (cycled); start, goal and path share it.
PAIR_COLOURS = (
    "#1f77b4",
    "#9467bd",
    "#17becf",
    "#e377c2",
    "#8c564b",
    "#0044aa",
    "#7f7f7f",
    "#008080",
    "#ff7f0e",
    "#00bfff",
)
#: Above this many system paths the pair numbers are left off (colour still pairs the ends).
MAX_TAGGED_PATHS = 40


@dataclass(frozen=True)
class PlotPath:
    """A path to draw, in the costmap's (row, col) pixel coordinates (integers at pixel centres)."""

    rows_cols: np.ndarray  # (N, 2)
    kind: str = "system"  # "system" (planned or given) or "reference"
    label: str | None = None
    #: short text drawn beside both the start and the goal (e.g. the pair number)
    tag: str | None = None


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
        from overseec_core.plan.grid import _find_lethal

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


@dataclass(frozen=True)
class MapFrame:
    """How the costmap grid's pixels map onto the plot's axes.

    For a north-up grid (no rotation terms) the axes are the CRS's coordinates: ``x = x0 + sx *
    col`` and ``y = y0 + sy * row`` at pixel corners. A rotated grid falls back to pixel
    coordinates (``map_coordinates`` False). ``metres_per_x`` / ``metres_per_y`` are ground
    metres per axis unit (from :meth:`Grid.pixel_size_m`, so geographic CRSs are right too).
    """

    x0: float
    sx: float
    y0: float
    sy: float
    map_coordinates: bool
    metres_per_x: float
    metres_per_y: float
    xlabel: str
    ylabel: str

    @classmethod
    def of(cls, grid: Grid) -> MapFrame:
        t = grid.transform
        px_m, py_m = grid.pixel_size_m()
        if abs(t.b) > 1e-12 * abs(t.a) or abs(t.d) > 1e-12 * abs(t.e):
            return cls(
                x0=-0.5,
                sx=1.0,
                y0=-0.5,
                sy=1.0,
                map_coordinates=False,
                metres_per_x=px_m,
                metres_per_y=py_m,
                xlabel="column (px; rotated grid)",
                ylabel="row (px)",
            )
        name = _crs_short(grid.crs)
        if grid.crs.is_geographic:
            xlabel, ylabel = f"{name} longitude (°)", f"{name} latitude (°)"
        else:
            unit = _unit_abbrev(grid.crs)
            xlabel, ylabel = f"{name} easting ({unit})", f"{name} northing ({unit})"
        return cls(
            x0=t.c,
            sx=t.a,
            y0=t.f,
            sy=t.e,
            map_coordinates=True,
            metres_per_x=px_m / abs(t.a),
            metres_per_y=py_m / abs(t.e),
            xlabel=xlabel,
            ylabel=ylabel,
        )

    def xy(self, rows_cols: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Axis coordinates of (row, col) pixel positions (integers at pixel centres)."""
        rc = np.asarray(rows_cols, dtype=np.float64).reshape(-1, 2)
        return self.x0 + self.sx * (rc[:, 1] + 0.5), self.y0 + self.sy * (rc[:, 0] + 0.5)

    def extent(self, cols: float, rows: float) -> tuple[float, float, float, float]:
        """imshow extent (left, right, bottom, top) of ``cols`` x ``rows`` pixels from the origin."""
        return (self.x0, self.x0 + self.sx * cols, self.y0 + self.sy * rows, self.y0)

    @property
    def aspect(self) -> float:
        """Axes aspect that draws one ground metre equally long in x and y."""
        return self.metres_per_y / self.metres_per_x


def _crs_short(crs) -> str:
    label = crs_label(crs) or "unknown CRS"
    if label.startswith("EPSG:"):
        return label
    try:
        import pyproj

        name = pyproj.CRS.from_wkt(crs.to_wkt()).name
    except Exception:  # an odd WKT still gets an axis label
        name = "CRS"
    return name if len(name) <= 40 else name[:37] + "..."


def _unit_abbrev(crs) -> str:
    try:
        unit = crs.linear_units_factor[0]
    except Exception:  # no linear unit
        return "m"
    return {"metre": "m", "meter": "m", "foot": "ft", "US survey foot": "US ft"}.get(unit, unit)


def nice_length_m(target_m: float) -> float:
    """The largest 1, 2 or 5 x 10^k metres not above ``target_m`` (a scale bar's length)."""
    if not target_m > 0:
        return 1.0
    k = math.floor(math.log10(target_m))
    for m in (5, 2, 1):
        if m * 10.0**k <= target_m * (1 + 1e-9):
            return float(m * 10.0**k)
    return float(10.0**k)


def _length_label(metres: float) -> str:
    return f"{metres / 1000:g} km" if metres >= 1000 else f"{metres:g} m"


@dataclass(frozen=True, eq=False)
class OverlayFigure:
    """The overlay figure and what it shows (for tests and callers that save it themselves)."""

    figure: object  # matplotlib.figure.Figure
    ax: object  # its map Axes
    frame: MapFrame
    scale_bar_m: float
    lethal_cells: int  # display cells drawn as lethal
    n_system: int


def overlay_figure(  # noqa: C901
    grid: Grid,
    paths: Sequence[PlotPath],
    costmap: str | os.PathLike | None = None,
    image: str | os.PathLike | None = None,
    max_size: int = DEFAULT_DISPLAY_SIZE,
    title: str = "paths",
    cost: np.ndarray | CostPreview | None = None,
) -> OverlayFigure:
    """The costmap (translucent over the image when one is given) with paths, in map coordinates.

    ``grid`` is the costmap's grid; paths are in its (row, col) pixels. The cost comes from
    ``cost`` (an in-memory costmap array, +inf = lethal, NaN = nodata, or a :class:`CostPreview`)
    or else the ``costmap`` file. Axes are the CRS's coordinates with a scale bar in ground
    metres; lethal cells are solid black (outside the cost ramp) and nodata hatched; each system
    path, its start (o) and goal (X) share a colour and, up to :data:`MAX_TAGGED_PATHS` paths,
    carry the path's tag at both ends.
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch, Rectangle
    from matplotlib.patheffects import withStroke
    from mpl_toolkits.axes_grid1.anchored_artists import AnchoredSizeBar

    frame = MapFrame.of(grid)
    aspect_px = (grid.height * grid.pixel_size_m()[1]) / max(grid.width * grid.pixel_size_m()[0], 1e-12)
    fig = _figure(7.5, max(3.5, min(6.0 * aspect_px, 12.0)) + 1.6)
    ax = fig.add_subplot(1, 1, 1)
    full = frame.extent(grid.width, grid.height)
    legend: list = []
    if image is not None:
        rgba, img_grid = read_image_preview(image, max_size)
        ax.imshow(rgba, extent=_image_extent(img_grid, grid, frame), interpolation="bilinear", zorder=0, aspect="auto")
    preview = (
        cost
        if isinstance(cost, CostPreview)
        else (
            cost_preview_from_array(cost, max_size)
            if cost is not None
            else (read_cost_preview(costmap, max_size) if costmap is not None else None)
        )
    )
    lethal_cells = 0
    if preview is not None:
        ext = frame.extent(*preview.covers)
        if preview.nodata.any():
            ax.add_patch(
                Rectangle(
                    (min(full[0], full[1]), min(full[2], full[3])),
                    abs(full[1] - full[0]),
                    abs(full[3] - full[2]),
                    facecolor="white",
                    edgecolor="#999999",
                    hatch="////",
                    lw=0,
                    zorder=0.5 if image is None else -1,
                )
            )
            if image is None:
                legend.append(Patch(facecolor="white", edgecolor="#999999", hatch="////", label="no data"))
        im = ax.imshow(
            preview.cost,
            extent=ext,
            cmap=COST_CMAP,
            vmin=0.0,
            vmax=1.0,
            alpha=0.55 if image is not None else 1.0,
            interpolation="nearest",
            zorder=1,
            aspect="auto",
        )
        from mpl_toolkits.axes_grid1 import make_axes_locatable

        cax = make_axes_locatable(ax).append_axes("right", size="3.5%", pad=0.08)
        cbar = fig.colorbar(im, cax=cax)
        cbar.set_label("cost (0 = preferred, 1 = avoid)")
        lethal_cells = int(preview.lethal.sum())
        if lethal_cells:
            ax.imshow(
                np.ma.masked_array(np.ones(preview.lethal.shape, np.float32), mask=~preview.lethal),
                extent=ext,
                cmap=ListedColormap([LETHAL_COLOUR]),
                vmin=0,
                vmax=1,
                interpolation="nearest",
                zorder=1.5,
                aspect="auto",
            )
            legend.append(Patch(facecolor=LETHAL_COLOUR, label="lethal"))
    halo = [withStroke(linewidth=3.2, foreground="white", alpha=0.8)]
    refs = [p for p in paths if p.kind == "reference"]
    system = [p for p in paths if p.kind != "reference" and len(np.asarray(p.rows_cols))]
    for p in refs:
        x, y = frame.xy(p.rows_cols)
        ax.plot(x, y, color="white", lw=3.4, alpha=0.9, zorder=2)
        ax.plot(x, y, color="black", lw=1.4, ls="--", zorder=2.1)
    if refs:
        legend.append(Line2D([], [], color="black", lw=1.4, ls="--", label="reference path"))
    width = 1.8 if len(system) <= 10 else 1.0
    tagged = len(system) <= MAX_TAGGED_PATHS
    for k, p in enumerate(system):
        colour = PAIR_COLOURS[k % len(PAIR_COLOURS)]
        x, y = frame.xy(p.rows_cols)
        ax.plot(x, y, color=colour, lw=width, alpha=0.9, zorder=3, path_effects=halo)
        ax.scatter(x[:1], y[:1], marker="o", s=34, c=colour, edgecolors="black", linewidths=0.7, zorder=4)
        ax.scatter(x[-1:], y[-1:], marker="X", s=48, c=colour, edgecolors="black", linewidths=0.7, zorder=4)
        if tagged and p.tag:
            for xe, ye in ((x[0], y[0]), (x[-1], y[-1])):
                ax.annotate(
                    p.tag,
                    (xe, ye),
                    xytext=(4, 4),
                    textcoords="offset points",
                    fontsize=7,
                    color=colour,
                    weight="bold",
                    zorder=5,
                    path_effects=[withStroke(linewidth=2.2, foreground="white")],
                )
        if p.label:
            legend.append(Line2D([], [], color=colour, lw=width, label=p.label))
    if system:
        legend.append(
            Line2D(
                [],
                [],
                ls="",
                marker="o",
                markersize=6,
                markerfacecolor="#bbbbbb",
                markeredgecolor="black",
                label="start" + (" (number = pair)" if tagged and any(p.tag for p in system) else ""),
            )
        )
        legend.append(
            Line2D(
                [],
                [],
                ls="",
                marker="X",
                markersize=7,
                markerfacecolor="#bbbbbb",
                markeredgecolor="black",
                label="goal (same colour as its start)",
            )
        )
    ax.set_xlim(full[0], full[1])
    ax.set_ylim(full[2], full[3])
    ax.set_aspect(frame.aspect)
    ax.set_xlabel(frame.xlabel)
    ax.set_ylabel(frame.ylabel)
    ax.ticklabel_format(useOffset=False, style="plain")
    ax.tick_params(labelsize=7)
    for tick in ax.get_xticklabels():
        tick.set_rotation(20)
    ax.set_title(title)
    map_width_m = grid.width * grid.pixel_size_m()[0]
    bar_m = nice_length_m(0.25 * map_width_m)
    ax.add_artist(
        AnchoredSizeBar(
            ax.transData,
            bar_m / frame.metres_per_x,
            _length_label(bar_m),
            "lower left",
            pad=0.4,
            borderpad=0.6,
            sep=3,
            color="black",
            frameon=True,
            size_vertical=0,
            fontproperties={"size": 8},
        )
    )
    rows = 0
    if legend:
        ncol = min(4, len(legend))
        rows = math.ceil(len(legend) / ncol)
        fig.legend(handles=legend, loc="lower center", ncol=ncol, fontsize=7, framealpha=0.9)
    fig.tight_layout(rect=(0, 0.045 * rows * 7.5 / fig.get_figheight(), 1, 1))
    return OverlayFigure(
        figure=fig, ax=ax, frame=frame, scale_bar_m=bar_m, lethal_cells=lethal_cells, n_system=len(system)
    )


def _image_extent(img_grid: Grid, grid: Grid, frame: MapFrame) -> tuple[float, float, float, float]:
    """imshow extent of the image in the overlay's axes (the costmap's CRS, or its pixels)."""
    if img_grid.crs != grid.crs:
        raise EvaluateError(
            f"--image is in {crs_label(img_grid.crs)} but the costmap is in "
            f"{crs_label(grid.crs)}; use an image on the costmap's CRS"
        )
    if frame.map_coordinates:
        t = img_grid.transform
        if abs(t.b) < 1e-12 * abs(t.a) and abs(t.d) < 1e-12 * abs(t.e):
            return (t.c, t.c + t.a * img_grid.width, t.f + t.e * img_grid.height, t.f)
        raise EvaluateError("--image has a rotated geotransform; warp it north-up to draw it")
    inv = ~grid.transform
    c0, r0 = inv * (img_grid.transform * (0, 0))
    c1, r1 = inv * (img_grid.transform * (img_grid.width, img_grid.height))
    return (c0 - 0.5, c1 - 0.5, r1 - 0.5, r0 - 0.5)


def plot_paths_overlay(
    path: str | os.PathLike,
    grid: Grid,
    paths: Sequence[PlotPath],
    costmap: str | os.PathLike | None = None,
    image: str | os.PathLike | None = None,
    max_size: int = DEFAULT_DISPLAY_SIZE,
    title: str = "paths",
    cost: np.ndarray | CostPreview | None = None,
) -> Path:
    """Write :func:`overlay_figure` as a PNG."""
    return _save(overlay_figure(grid, paths, costmap, image, max_size, title, cost).figure, path)


# --------------------------------------------------------------------------------------------
# IoU
# --------------------------------------------------------------------------------------------


def plot_iou(
    path: str | os.PathLike, names: Sequence[str], values: Sequence[float | None], mean_iou: float | None = None
) -> Path:
    """Bar chart of IoU per class (classes without pixels in either raster shown empty)."""
    fig = _figure(max(4.0, 0.8 * len(names) + 2.0), 4.0)
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
    return _save(fig, path)


# --------------------------------------------------------------------------------------------
# Side by side: one costmap and route per prompt (overseec compare)
# --------------------------------------------------------------------------------------------


def side_by_side_figure(  # noqa: C901
    grid: Grid,
    costs: Sequence[CostPreview | str | os.PathLike],
    routes: Sequence[PlotPath],
    titles: Sequence[str],
    max_size: int = 900,
    ncols: int | None = None,
) -> tuple[Figure, tuple[Axes, ...]]:
    """One panel per costmap on the same grid, for comparing prompts on one map.

    Panel k shows costmap k (a :class:`CostPreview` or a costmap file; lethal cells black, nodata
    hatched) with route k in bold and every other route faint, each route in the same colour in
    every panel, in the CRS's coordinates with a scale bar in ground metres, under ``titles[k]``
    (wrapped). One cost colour bar serves all panels (they share the 0..1 scale); a legend names
    the routes. Returns the Figure (Agg canvas, no pyplot) and its panel Axes, in order.
    """
    import textwrap

    from matplotlib.colors import ListedColormap
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch, Rectangle
    from matplotlib.patheffects import withStroke
    from mpl_toolkits.axes_grid1.anchored_artists import AnchoredSizeBar

    n = len(costs)
    if n == 0 or len(routes) != n or len(titles) != n:
        raise ValueError("side_by_side_figure needs one route and one title per costmap")
    ncols = ncols or (n if n <= 3 else math.ceil(math.sqrt(n)))
    nrows = math.ceil(n / ncols)
    frame = MapFrame.of(grid)
    px_m, py_m = grid.pixel_size_m()
    aspect = (grid.height * py_m) / max(grid.width * px_m, 1e-12)
    panel_w = 4.2
    panel_h = min(max((panel_w - 0.9) * aspect, 2.0), 8.0) + 1.2  # + title and axis labels
    legend_rows = math.ceil((n + 3) / 3)  # routes, "the others", lethal, no data; 3 columns
    legend_h = 0.18 * legend_rows + 0.15
    fig = _figure(panel_w * ncols + 1.0, panel_h * nrows + legend_h)
    gs = fig.add_gridspec(nrows, ncols + 1, width_ratios=[1.0] * ncols + [0.05])
    full = frame.extent(grid.width, grid.height)
    bar_m = nice_length_m(0.25 * grid.width * px_m)
    colours = [PAIR_COLOURS[k % len(PAIR_COLOURS)] for k in range(n)]
    halo = [withStroke(linewidth=3.4, foreground="white", alpha=0.85)]
    axes, image, any_lethal, any_nodata = [], None, False, False
    for k in range(n):
        ax = fig.add_subplot(gs[k // ncols, k % ncols], label=f"panel {k + 1}")
        given = costs[k]
        preview = given if isinstance(given, CostPreview) else read_cost_preview(given, max_size)
        ext = frame.extent(*preview.covers)
        if preview.nodata.any():
            any_nodata = True
            ax.add_patch(
                Rectangle(
                    (min(full[0], full[1]), min(full[2], full[3])),
                    abs(full[1] - full[0]),
                    abs(full[3] - full[2]),
                    facecolor="white",
                    edgecolor="#999999",
                    hatch="////",
                    lw=0,
                    zorder=0.5,
                )
            )
        image = ax.imshow(
            preview.cost,
            extent=ext,
            cmap=COST_CMAP,
            vmin=0.0,
            vmax=1.0,
            interpolation="nearest",
            zorder=1,
            aspect="auto",
        )
        if preview.lethal.any():
            any_lethal = True
            ax.imshow(
                np.ma.masked_array(np.ones(preview.lethal.shape, np.float32), mask=~preview.lethal),
                extent=ext,
                cmap=ListedColormap([LETHAL_COLOUR]),
                vmin=0,
                vmax=1,
                interpolation="nearest",
                zorder=1.5,
                aspect="auto",
            )
        for j, route in enumerate(routes):  # the others first, faint, under this panel's own
            rc = np.asarray(route.rows_cols)
            if j == k or not len(rc):
                continue
            x, y = frame.xy(rc)
            ax.plot(x, y, color=colours[j], lw=1.2, alpha=0.75, ls=(0, (4, 2)), zorder=2)
        own = np.asarray(routes[k].rows_cols)
        if len(own):
            x, y = frame.xy(own)
            ax.plot(x, y, color=colours[k], lw=2.0, zorder=3, path_effects=halo)
            ax.scatter(x[:1], y[:1], marker="o", s=34, c=colours[k], edgecolors="black", linewidths=0.7, zorder=4)
            ax.scatter(x[-1:], y[-1:], marker="X", s=48, c=colours[k], edgecolors="black", linewidths=0.7, zorder=4)
        ax.set_xlim(full[0], full[1])
        ax.set_ylim(full[2], full[3])
        ax.set_aspect(frame.aspect)
        ax.set_xlabel(frame.xlabel, fontsize=7)
        ax.set_ylabel(frame.ylabel, fontsize=7)
        ax.ticklabel_format(useOffset=False, style="plain")
        ax.tick_params(labelsize=6)
        for tick in ax.get_xticklabels():
            tick.set_rotation(20)
        lines = textwrap.wrap(str(titles[k]), 40) or [""]
        if len(lines) > 3:
            lines = lines[:2] + [textwrap.shorten(" ".join(lines[2:]), 40, placeholder=" ...")]
        ax.set_title("\n".join(lines), fontsize=9, color=colours[k])
        ax.add_artist(
            AnchoredSizeBar(
                ax.transData,
                bar_m / frame.metres_per_x,
                _length_label(bar_m),
                "lower left",
                pad=0.4,
                borderpad=0.6,
                sep=3,
                color="black",
                frameon=True,
                size_vertical=0,
                fontproperties={"size": 7},
            )
        )
        axes.append(ax)
    cax = fig.add_subplot(gs[:, -1], label="colour bar")
    cbar = fig.colorbar(image, cax=cax)
    cbar.set_label("cost (0 = preferred, 1 = avoid)", fontsize=8)
    cbar.ax.tick_params(labelsize=7)
    legend = [
        Line2D([], [], color=colours[k], lw=2.0, label=textwrap.shorten(f"{titles[k]}", 48, placeholder=" ..."))
        for k in range(n)
    ]
    legend.append(
        Line2D([], [], color="#777777", lw=1.2, alpha=0.75, ls=(0, (4, 2)), label="the other prompts' routes")
    )
    if any_lethal:
        legend.append(Patch(facecolor=LETHAL_COLOUR, label="lethal"))
    if any_nodata:
        legend.append(Patch(facecolor="white", edgecolor="#999999", hatch="////", label="no data"))
    fig.legend(handles=legend, loc="lower center", ncol=min(3, len(legend)), fontsize=7, framealpha=0.9)
    fig.tight_layout(rect=(0, (legend_h + 0.05) / fig.get_figheight(), 1, 1))
    boxes = [a.get_position() for a in axes]  # the colour bar as tall as the panels, not the grid
    bottom, top = min(b.y0 for b in boxes), max(b.y1 for b in boxes)
    where = cax.get_position()
    cax.set_position([where.x0, bottom, where.width, top - bottom])
    return fig, tuple(axes)
