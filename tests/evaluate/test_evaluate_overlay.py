"""The path overlay of `overseec eval`: map coordinates, scale bar, lethal cells, paired ends."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from affine import Affine
from matplotlib.colors import to_hex
from rasterio.crs import CRS

from overseec_core.evaluate import EvaluateOptions, evaluate_paths, maps, previews
from overseec_core.io.grid import Grid
from overseec_core.io.write import write_array

from .test_evaluate import ORIGIN, _assert_png_not_blank, utm_grid, write_classes


def _paths() -> list[maps.PlotPath]:
    return [
        maps.PlotPath(np.array([(10, 10), (30, 50), (55, 75)]), tag="1"),
        maps.PlotPath(np.array([(50, 5), (5, 70)]), tag="2"),
        maps.PlotPath(np.array([(30.0, 0.0), (30.0, 79.0)]), kind="reference"),
    ]


def _cost(h: int = 60, w: int = 80) -> np.ndarray:
    cost = np.tile(np.linspace(0, 1, w, dtype=np.float32), (h, 1))
    cost[40:50, 20:30] = np.inf  # lethal
    cost[:5, :5] = np.nan  # nodata
    return cost


def test_axes_are_map_coordinates_with_crs_labels_and_a_scale_bar() -> None:
    grid = utm_grid(80, 60, px=0.5, py=0.5)  # 40 m x 30 m
    of = maps.overlay_figure(grid, _paths(), cost=_cost(), max_size=200)
    ax = of.ax
    assert ax.get_xlim() == pytest.approx((ORIGIN[0], ORIGIN[0] + 40.0))
    assert ax.get_ylim() == pytest.approx((ORIGIN[1] - 30.0, ORIGIN[1]))
    assert ax.get_xlabel() == "EPSG:32633 easting (m)" and ax.get_ylabel() == "EPSG:32633 northing (m)"
    assert of.frame.map_coordinates and ax.get_aspect() == pytest.approx(1.0)
    assert of.scale_bar_m == 10.0  # the nice length under a quarter of 40 m
    texts = [t.get_text() for t in ax.findobj(lambda a: hasattr(a, "get_text"))]
    assert "10 m" in texts
    # path 1's pixels are drawn at their pixel centres in map coordinates
    line = next(ln for ln in ax.lines if len(ln.get_xdata()) == 3)
    np.testing.assert_allclose(line.get_xdata(), ORIGIN[0] + 0.5 * (np.array([10, 50, 75]) + 0.5))
    np.testing.assert_allclose(line.get_ydata(), ORIGIN[1] - 0.5 * (np.array([10, 30, 55]) + 0.5))


def test_lethal_cells_are_drawn_apart_from_the_cost_ramp() -> None:
    grid = utm_grid(80, 60)
    of = maps.overlay_figure(grid, _paths(), cost=_cost(), max_size=200)
    assert of.lethal_cells == 100
    images = of.ax.get_images()
    lethal = [im for im in images if im.get_cmap().N == 1]
    assert len(lethal) == 1 and to_hex(lethal[0].get_cmap()(0.5)) == maps.LETHAL_COLOUR
    ramp = next(im for im in images if im.get_cmap().name == maps.COST_CMAP)
    assert ramp.get_array().mask[45, 25] and ramp.get_array().mask[0, 0]  # lethal and nodata not on the ramp
    labels = [t.get_text() for t in of.figure.legends[0].get_texts()]
    assert "lethal" in labels and "no data" in labels and "reference path" in labels


def test_each_start_is_paired_with_its_goal() -> None:
    grid = utm_grid(80, 60)
    of = maps.overlay_figure(grid, _paths(), cost=_cost(), max_size=200)
    ax = of.ax
    tags = [t.get_text() for t in ax.texts]
    assert sorted(tags) == ["1", "1", "2", "2"]  # each tag at both ends
    # start (o) and goal (X) of a path share the path's colour; the two paths differ
    colours = [to_hex(c.get_facecolor()[0]) for c in ax.collections if len(c.get_offsets()) == 1]
    assert colours[0] == colours[1] and colours[2] == colours[3] and colours[0] != colours[2]
    system = [ln for ln in ax.lines if ln.get_linestyle() == "-" and to_hex(ln.get_color()) in colours]
    assert {to_hex(ln.get_color()) for ln in system} == {colours[0], colours[2]}
    # the tags sit at the ends: the first annotation points at path 1's start
    x0, y0 = of.frame.xy(np.array([(10, 10)]))
    assert ax.texts[0].xy == pytest.approx((x0[0], y0[0]))


def test_geographic_grid_axes_and_ground_aspect() -> None:
    lat0 = 36.0
    grid = Grid(crs=CRS.from_epsg(4326), transform=Affine(2.7e-6, 0, -115.0, 0, -2.7e-6, lat0), width=80, height=60)
    of = maps.overlay_figure(grid, _paths(), cost=_cost(), max_size=200)
    assert of.ax.get_xlabel() == "EPSG:4326 longitude (°)" and of.ax.get_ylabel() == "EPSG:4326 latitude (°)"
    assert of.ax.get_xlim() == pytest.approx((-115.0, -115.0 + 80 * 2.7e-6))
    # one degree of latitude is longer on the ground than one of longitude: aspect ~ 1 / cos(lat)
    assert of.ax.get_aspect() == pytest.approx(1 / math.cos(math.radians(lat0)), rel=0.01)
    px_m = grid.pixel_size_m()[0]
    assert of.scale_bar_m == maps.nice_length_m(0.25 * 80 * px_m) == 2.0  # 80 px x 0.243 m = 19.5 m


def test_nice_lengths() -> None:
    assert [maps.nice_length_m(v) for v in (37.0, 0.3, 1200.0, 10.0, 9.99)] == [20.0, 0.2, 1000.0, 10.0, 5.0]


def test_cost_preview_of_an_array_keeps_lethal_and_nodata() -> None:
    cost = np.full((10, 10), 0.5, np.float32)
    cost[0:2, 0:2] = np.inf  # a whole display cell lethal
    cost[2, 2] = np.inf  # one lethal cell of four: the display cell is the mean of the other three
    cost[8:10, 8:10] = np.nan
    cost[4:6, 4:6] = [[0.0, 1.0], [0.25, 0.75]]
    pv = previews.cost_preview_from_array(cost, max_size=5)
    assert pv.cost.shape == (5, 5) and pv.covers == (10.0, 10.0)
    assert pv.lethal[0, 0] and not pv.lethal[1, 1] and pv.lethal.sum() == 1
    assert pv.nodata[4, 4] and pv.nodata.sum() == 1
    assert pv.cost[2, 2] == pytest.approx(0.5) and pv.cost[1, 1] == pytest.approx(0.5)
    assert pv.cost.mask[0, 0] and pv.cost.mask[4, 4] and not pv.cost.mask[1, 1]
    odd = previews.cost_preview_from_array(np.zeros((7, 5), np.float32), max_size=3)
    assert odd.cost.shape == (3, 2) and odd.covers == (6.0, 9.0) and odd.nodata.sum() == 0


def test_cost_preview_of_a_file_reads_the_lethal_sidecar(tmp_path: Path) -> None:
    grid = utm_grid(80, 60)
    cost = np.full((60, 80), 0.3, np.float32)
    cost[:10, :10] = np.nan
    costmap = write_array(tmp_path / "costmap.tif", cost, grid, nodata=float("nan"))
    lethal = np.zeros((60, 80), np.uint8)
    lethal[20:40, 40:60] = 1
    lethal[:10, :10] = 1  # compose flags nodata as lethal too: it stays nodata
    write_array(tmp_path / "lethal.tif", lethal, grid)
    pv = previews.read_cost_preview(costmap, max_size=40)
    assert pv.cost.shape == (30, 40) and pv.covers == (80.0, 60.0)
    assert pv.lethal[10:20, 20:30].all() and pv.lethal.sum() == 100
    assert pv.nodata[:5, :5].all() and not pv.lethal[:5, :5].any()
    out = maps.plot_paths_overlay(tmp_path / "o.png", grid, _paths(), costmap=costmap, max_size=40)
    _assert_png_not_blank(out)


def test_eval_writes_the_overlay_from_the_loaded_costmap(tmp_path: Path) -> None:
    grid = utm_grid(80, 60)
    labels = np.full((60, 80), 2, dtype=np.uint8)
    labels[30, :] = 1
    cost = np.where(labels == 1, 0.05, 0.5).astype(np.float32)
    cost[10:20, 50:70] = np.inf  # lethal in the costmap itself
    s = {
        "labels": write_array(tmp_path / "labels.tif", labels, grid),
        "costmap": write_array(tmp_path / "cost.tif", cost, grid),
        "classes": write_classes(tmp_path / "classes.json"),
    }
    out = tmp_path / "out"
    evaluate_paths(
        EvaluateOptions(
            out_dir=out,
            labels=s["labels"],
            classes=s["classes"],
            ranks="road=1,grass=2",
            costmap=s["costmap"],
            pairs=4,
            seed=1,
        )
    )
    m = json.loads((out / "metrics.json").read_text())
    assert m["files"]["overlay_plot"] == "paths_overlay.png"
    _assert_png_not_blank(out / "paths_overlay.png")
