"""Map figures as PNG files: a costmap (over its image) with paths, and costmaps side by side.

Figures are drawn in the costmap's CRS coordinates (:class:`MapFrame`) with a scale bar in ground
metres, lethal cells black and nodata hatched, from rasters read at preview size (:mod:`.previews`).
They are built as in :mod:`.plots` (Agg canvas, no pyplot, written atomically); matplotlib is
imported inside the drawing functions, so that importing the evaluate stage does not load it.
"""

from __future__ import annotations

import math
import os
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from overseec_core.errors import EvaluateError
from overseec_core.evaluate.plots import new_figure, save_png
from overseec_core.evaluate.previews import (
    DEFAULT_DISPLAY_SIZE,
    CostPreview,
    cost_preview_from_array,
    read_cost_preview,
    read_image_preview,
)
from overseec_core.io.grid import Grid, crs_label

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

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
#: How nodata is drawn (hatched white), on the map and in its legend.
NODATA_STYLE = {"facecolor": "white", "edgecolor": "#999999", "hatch": "////"}


@dataclass(frozen=True)
class PlotPath:
    """A path to draw, in the costmap's (row, col) pixel coordinates (integers at pixel centres)."""

    rows_cols: np.ndarray  # (N, 2)
    kind: str = "system"  # "system" (planned or given) or "reference"
    label: str | None = None
    #: short text drawn beside both the start and the goal (e.g. the pair number)
    tag: str | None = None


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


def _draw_nodata(ax: Axes, full: tuple[float, float, float, float], zorder: float) -> None:
    """Hatch the whole map extent at ``zorder``: nodata cells (masked in the cost image) show it."""
    from matplotlib.patches import Rectangle

    origin = (min(full[0], full[1]), min(full[2], full[3]))
    ax.add_patch(Rectangle(origin, abs(full[1] - full[0]), abs(full[3] - full[2]), **NODATA_STYLE, lw=0, zorder=zorder))


def _draw_lethal(ax: Axes, lethal: np.ndarray, ext: tuple[float, float, float, float]) -> None:
    """Lethal display cells in solid :data:`LETHAL_COLOUR`, above the cost ramp."""
    from matplotlib.colors import ListedColormap

    ax.imshow(
        np.ma.masked_array(np.ones(lethal.shape, np.float32), mask=~lethal),
        extent=ext,
        cmap=ListedColormap([LETHAL_COLOUR]),
        vmin=0,
        vmax=1,
        interpolation="nearest",
        zorder=1.5,
        aspect="auto",
    )


def _draw_ends(ax: Axes, x: np.ndarray, y: np.ndarray, colour: str) -> None:
    """A path's start (o) and goal (X) in its colour."""
    ax.scatter(x[:1], y[:1], marker="o", s=34, c=colour, edgecolors="black", linewidths=0.7, zorder=4)
    ax.scatter(x[-1:], y[-1:], marker="X", s=48, c=colour, edgecolors="black", linewidths=0.7, zorder=4)


def _frame_axes(
    ax: Axes, frame: MapFrame, full: tuple[float, float, float, float], label_size: float | None, tick_size: float
) -> None:
    """A map panel's limits, ground-true aspect, axis labels and plain (unshifted) tick labels."""
    ax.set_xlim(full[0], full[1])
    ax.set_ylim(full[2], full[3])
    ax.set_aspect(frame.aspect)
    size = {} if label_size is None else {"fontsize": label_size}
    ax.set_xlabel(frame.xlabel, **size)
    ax.set_ylabel(frame.ylabel, **size)
    ax.ticklabel_format(useOffset=False, style="plain")
    ax.tick_params(labelsize=tick_size)
    for tick in ax.get_xticklabels():
        tick.set_rotation(20)


def _add_scale_bar(ax: Axes, frame: MapFrame, bar_m: float, font_size: float) -> None:
    """A ``bar_m`` ground-metre scale bar in the lower left corner."""
    from mpl_toolkits.axes_grid1.anchored_artists import AnchoredSizeBar

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
            fontproperties={"size": font_size},
        )
    )


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
    from matplotlib.lines import Line2D  # matplotlib stays lazy (module docstring)
    from matplotlib.patches import Patch
    from matplotlib.patheffects import withStroke
    from mpl_toolkits.axes_grid1 import make_axes_locatable

    frame = MapFrame.of(grid)
    aspect_px = (grid.height * grid.pixel_size_m()[1]) / max(grid.width * grid.pixel_size_m()[0], 1e-12)
    fig = new_figure(7.5, max(3.5, min(6.0 * aspect_px, 12.0)) + 1.6)
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
            _draw_nodata(ax, full, zorder=0.5 if image is None else -1)
            if image is None:
                legend.append(Patch(**NODATA_STYLE, label="no data"))
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
        cax = make_axes_locatable(ax).append_axes("right", size="3.5%", pad=0.08)
        cbar = fig.colorbar(im, cax=cax)
        cbar.set_label("cost (0 = preferred, 1 = avoid)")
        lethal_cells = int(preview.lethal.sum())
        if lethal_cells:
            _draw_lethal(ax, preview.lethal, ext)
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
        _draw_ends(ax, x, y, colour)
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
    _frame_axes(ax, frame, full, label_size=None, tick_size=7)
    ax.set_title(title)
    map_width_m = grid.width * grid.pixel_size_m()[0]
    bar_m = nice_length_m(0.25 * map_width_m)
    _add_scale_bar(ax, frame, bar_m, font_size=8)
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
    return save_png(overlay_figure(grid, paths, costmap, image, max_size, title, cost).figure, path)


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
    from matplotlib.lines import Line2D  # matplotlib stays lazy (module docstring)
    from matplotlib.patches import Patch
    from matplotlib.patheffects import withStroke

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
    fig = new_figure(panel_w * ncols + 1.0, panel_h * nrows + legend_h)
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
            _draw_nodata(ax, full, zorder=0.5)
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
            _draw_lethal(ax, preview.lethal, ext)
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
            _draw_ends(ax, x, y, colours[k])
        _frame_axes(ax, frame, full, label_size=7, tick_size=6)
        lines = textwrap.wrap(str(titles[k]), 40) or [""]
        if len(lines) > 3:
            lines = lines[:2] + [textwrap.shorten(" ".join(lines[2:]), 40, placeholder=" ...")]
        ax.set_title("\n".join(lines), fontsize=9, color=colours[k])
        _add_scale_bar(ax, frame, bar_m, font_size=7)
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
        legend.append(Patch(**NODATA_STYLE, label="no data"))
    fig.legend(handles=legend, loc="lower center", ncol=min(3, len(legend)), fontsize=7, framealpha=0.9)
    fig.tight_layout(rect=(0, (legend_h + 0.05) / fig.get_figheight(), 1, 1))
    boxes = [a.get_position() for a in axes]  # the colour bar as tall as the panels, not the grid
    bottom, top = min(b.y0 for b in boxes), max(b.y1 for b in boxes)
    where = cax.get_position()
    cax.set_position([where.x0, bottom, where.width, top - bottom])
    return fig, tuple(axes)
