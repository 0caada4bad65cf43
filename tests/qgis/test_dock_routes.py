"""The dock's Routes box with the real worker: the corridor of the planned route, and many pairs.

A costmap is built on the sample scene (its class raster stands in for masks) and a route is
planned with the map tool, as tests/qgis/test_dock.py does; then Corridor loads two styled rasters
whose ratio is 1.0 along the route, and Plan pairs from a generated line layer and from two point
layers (in another CRS) loads one route per pair, costed as the single plans of the same points.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import rasterio
from qgis.core import (
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsFeature,
    QgsGeometry,
    QgsPointXY,
    QgsProject,
    QgsVectorLayer,
)

from overseec_core import runfiles
from overseec_qgis.legend import find_routes_group

from .heartbeat import MAX_BLOCK_MS, Heartbeat
from .test_dock import META, _add_sample_layers, run_and_wait, set_options

pytestmark = pytest.mark.qgis


@pytest.fixture
def dock(plugin, tmp_path):
    """The plugin's dock with its runs folder set on the options page, as a user sets it."""
    set_options(plugin, runs_dir=str(tmp_path / "runs"))
    return plugin.dock


def _costmap(dock) -> Path:
    """Build the sample's costmap in the dock (exact planning); returns its file."""
    _add_sample_layers(dock)
    dock.mission.prompt_edit.setPlainText(META["prompt"])
    assert run_and_wait(dock, dock.mission.interpret_button.click) == ("interpret", True)
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    dock.parameters.mode_combo.setCurrentText("exact")
    return Path(dock.runs.map_tool.costmap_path())


def _plan_route(plugin, canvas, parent, costmap_layer) -> list[QgsPointXY]:
    """Click the sample's start and goal with the map tool; the planned route's vertices."""
    from qgis.gui import QgsMapMouseEvent
    from qgis.PyQt.QtCore import QEvent, QPoint, Qt

    from .test_maptool import show_canvas

    plugin.plan_action.trigger()
    show_canvas(canvas, parent)
    canvas.setDestinationCrs(costmap_layer.crs())
    canvas.setExtent(costmap_layer.extent())
    tool = plugin.map_tool
    for x, y in (META["start"], META["goal"]):
        s = canvas.getCoordinateTransform().transform(QgsPointXY(x, y))
        pos = QPoint(round(s.x()), round(s.y()))
        for kind in (QEvent.MouseButtonPress, QEvent.MouseButtonRelease):
            pressed = kind == QEvent.MouseButtonPress
            e = QgsMapMouseEvent(canvas, kind, pos, Qt.LeftButton, Qt.LeftButton if pressed else Qt.NoButton)
            (tool.canvasPressEvent if pressed else tool.canvasReleaseEvent)(e)
    assert tool.wait() and tool.complete
    (feature,) = list(tool.paths_layer.getFeatures())
    return feature.geometry().asPolyline()


def _values_at(path: Path, points: list[QgsPointXY]) -> np.ndarray:
    with rasterio.open(path) as src:
        return np.array([v[0] for v in src.sample([(p.x(), p.y()) for p in points])], dtype=float)


def test_corridor_of_the_planned_route_loads_two_styled_rasters(plugin, dock, qgis_canvas, qgis_parent) -> None:
    costmap = _costmap(dock)
    route = _plan_route(plugin, qgis_canvas, qgis_parent, dock.runs.map_tool.costmap_layer)
    dock.routes.within_spin.setValue(5.0)
    with Heartbeat() as beat:
        assert run_and_wait(dock, dock.routes.corridor_button.click) == ("corridor", True)
    assert beat.blocked_ms <= MAX_BLOCK_MS, f"the GUI thread was blocked {beat.blocked_ms:.0f} ms"
    print(f"corridor: longest GUI block {beat.blocked_ms:.1f} ms (gap {beat.longest_ms:.1f} ms)")
    ratio_file = costmap.with_name(runfiles.CORRIDOR)
    mask_file = ratio_file.with_name(ratio_file.stem + runfiles.CORRIDOR_MASK_SUFFIX)
    assert ratio_file.is_file() and mask_file.is_file()
    # the optimal route's cells: ratio 1.0, inside the mask
    ratios = _values_at(ratio_file, route)
    assert np.allclose(ratios, 1.0, atol=1e-4), ratios.max()
    assert (_values_at(mask_file, route) == 1).all()
    # both loaded, styled, in one group right below the routes group
    root = QgsProject.instance().layerTreeRoot()
    assert root.children()[0] is find_routes_group()
    group = root.children()[1]
    assert group.name().startswith("overseec corridor:")
    layers = {Path(n.layer().source()).name: n.layer() for n in group.findLayers()}
    assert set(layers) == {ratio_file.name, mask_file.name}
    ratio = layers[ratio_file.name]
    assert ratio.renderer().type() == "singlebandpseudocolor"
    assert ratio.renderer().classificationMax() == pytest.approx(1.05)
    assert ratio.name().startswith("corridor — within 5 % of cost")
    assert all(lyr.customProperty("overseec/role") == "corridor" for lyr in layers.values())
    # a second corridor goes beside the first, never over it
    assert run_and_wait(dock, dock.routes.corridor_button.click) == ("corridor", True)
    assert costmap.with_name("corridor-2.tif").is_file() and ratio.isValid()


def test_corridor_without_a_route_says_so_in_one_line(plugin, dock, qgis_iface) -> None:
    from qgis.core import Qgis

    _costmap(dock)
    dock.routes.corridor_button.click()
    assert dock.slot.task is None
    (message,) = [m for m in qgis_iface.messageBar().get_messages(Qgis.Critical) if "corridor" in m]
    assert "plan a route" in message and "\n" not in message


def _pixel_centres(costmap: Path, cells) -> list[tuple[float, float]]:
    with rasterio.open(costmap) as src:
        return [src.xy(r, c) for r, c in cells]


def _single_cost(costmap: Path, start, goal, tmp_path: Path, neighbours: int = 8) -> float:
    from overseec_core.plan.stage import PlanOptions, run_plan

    out = tmp_path / f"single{neighbours}" / f"{start[0]:.0f}-{goal[0]:.0f}.geojson"
    out.parent.mkdir(exist_ok=True)
    options = PlanOptions(costmap=costmap, points=(start, goal), out=out, mode="exact", neighbours=neighbours)
    return run_plan(options).result.cost


def _routes_layer(out_name: str) -> QgsVectorLayer:
    group = find_routes_group()
    (layer,) = [n.layer() for n in group.findLayers() if Path(n.layer().source().split("|")[0]).name == out_name]
    return layer


def test_plan_pairs_from_lines_and_from_point_layers(dock, tmp_path) -> None:
    costmap = _costmap(dock)
    ends = _pixel_centres(costmap, [(100, 100), (900, 850), (50, 900), (980, 20), (500, 500), (600, 80)])
    pairs = [(ends[0], ends[1], "a"), (ends[2], ends[3], "b"), (ends[4], ends[5], "c")]
    crs = dock.runs.map_tool.costmap_layer.crs()
    lines = QgsVectorLayer(f"LineString?crs={crs.authid()}&field=id:string", "pairs", "memory")
    for s, g, ident in pairs:
        f = QgsFeature(lines.fields())
        f.setGeometry(QgsGeometry.fromPolylineXY([QgsPointXY(*s), QgsPointXY(*g)]))
        f["id"] = ident
        lines.dataProvider().addFeature(f)
    QgsProject.instance().addMapLayer(lines)
    dock.routes.pairs_combo.setLayer(lines)
    assert not dock.routes.goals_combo.isEnabled()
    with Heartbeat() as beat:
        assert run_and_wait(dock, dock.routes.pairs_button.click) == ("pairs", True)
    assert beat.blocked_ms <= MAX_BLOCK_MS, f"the GUI thread was blocked {beat.blocked_ms:.0f} ms"
    print(f"plan pairs: longest GUI block {beat.blocked_ms:.1f} ms (gap {beat.longest_ms:.1f} ms)")
    single = {ident: _single_cost(costmap, s, g, tmp_path) for s, g, ident in pairs}
    routes = _routes_layer("routes.gpkg")
    assert routes.name().startswith("routes — ") and routes.customProperty("overseec/role") == "path"
    got = {f["id"]: f["total_cost"] for f in routes.getFeatures()}
    assert got.keys() == single.keys()
    for ident, cost in single.items():
        assert got[ident] == pytest.approx(cost, rel=1e-9), ident

    # the same pairs as two point layers in WGS 84, paired by feature order (no id field)
    wgs84 = QgsCoordinateReferenceSystem("EPSG:4326")
    to_wgs = QgsCoordinateTransform(crs, wgs84, QgsProject.instance())
    starts = QgsVectorLayer("Point?crs=EPSG:4326", "starts", "memory")
    goals = QgsVectorLayer("Point?crs=EPSG:4326", "goals", "memory")
    for s, g, _ident in pairs:
        for layer, p in ((starts, s), (goals, g)):
            f = QgsFeature(layer.fields())
            f.setGeometry(QgsGeometry.fromPointXY(to_wgs.transform(QgsPointXY(*p))))
            layer.dataProvider().addFeature(f)
    QgsProject.instance().addMapLayers([starts, goals])
    dock.routes.pairs_combo.setLayer(starts)
    assert dock.routes.goals_combo.isEnabled()
    dock.routes.goals_combo.setLayer(goals)
    assert run_and_wait(dock, dock.routes.pairs_button.click) == ("pairs", True)
    second = _routes_layer("routes-2.gpkg")
    costs = [f["total_cost"] for f in sorted(second.getFeatures(), key=lambda f: int(f["id"]))]
    assert costs == pytest.approx([single[i] for _s, _g, i in pairs], rel=1e-9)
    written = (costmap.parent / "routes-2.pairs.csv").read_text().splitlines()
    assert written[0] == "start_x,start_y,goal_x,goal_y,id" and len(written) == 4

    # unequal point layers fail in one line, before any worker starts
    goals.dataProvider().deleteFeatures([next(goals.getFeatures()).id()])
    assert run_and_wait(dock, dock.routes.pairs_button.click) == ("pairs", False)
    assert "3 start points but 2 goal points" in dock.runs.status_label.text()


def test_steps_16_reach_the_map_tool_plan_pairs_and_the_saved_settings(
    plugin, dock, qgis_canvas, qgis_parent, tmp_path
) -> None:
    """The dock's Steps: with 16 the map tool's route and Plan pairs cost what the core's
    16-neighbour plan costs (less than with 8), Corridor says it steps to 8, and the choice is kept
    in the settings."""
    from overseec_qgis.settings import PluginSettings

    costmap = _costmap(dock)
    steps = dock.parameters.steps_combo
    steps.setCurrentIndex(steps.findData(16))
    tool = dock.runs.map_tool
    assert tool.neighbours == 16
    route = _plan_route(plugin, qgis_canvas, qgis_parent, tool.costmap_layer)
    (feature,) = list(tool.paths_layer.getFeatures())
    grid = tool.session().grid
    ends = [grid.pixel_to_world(*grid.world_to_pixel(p.x(), p.y())) for p in (route[0], route[-1])]
    sixteen = _single_cost(costmap, ends[0], ends[1], tmp_path, 16)
    assert feature["total_cost"] == pytest.approx(sixteen, rel=1e-9)
    assert sixteen < _single_cost(costmap, ends[0], ends[1], tmp_path, 8)
    csv_file = tmp_path / "one pair.csv"
    (s, g) = ends
    csv_file.write_text(f"start_x,start_y,goal_x,goal_y,id\n{s[0]!r},{s[1]!r},{g[0]!r},{g[1]!r},only\n")
    dock.routes.pairs_file.setFilePath(str(csv_file))
    assert run_and_wait(dock, dock.routes.pairs_button.click) == ("pairs", True)
    (paired,) = list(_routes_layer("routes.gpkg").getFeatures())
    assert paired["total_cost"] == pytest.approx(sixteen, rel=1e-9)
    assert run_and_wait(dock, dock.routes.corridor_button.click) == ("corridor", True)
    assert "the corridor steps to 8 neighbours, the route on the map to 16" in dock.runs.status_label.text()
    dock.settings.save()
    assert PluginSettings.load().params.plan_neighbours == 16


def test_a_csv_file_of_pairs_is_planned_as_given(dock, tmp_path) -> None:
    costmap = _costmap(dock)
    (s, g) = _pixel_centres(costmap, [(120, 80), (870, 900)])
    csv_file = tmp_path / "my pairs.csv"
    csv_file.write_text(f"start_x,start_y,goal_x,goal_y,id\n{s[0]!r},{s[1]!r},{g[0]!r},{g[1]!r},only\n")
    dock.routes.pairs_file.setFilePath(str(csv_file))
    assert run_and_wait(dock, dock.routes.pairs_button.click) == ("pairs", True)
    (route,) = list(_routes_layer("routes.gpkg").getFeatures())
    assert route["id"] == "only" and route["total_cost"] == pytest.approx(_single_cost(costmap, s, g, tmp_path))
    dock.routes.pairs_file.setFilePath(str(tmp_path / "missing.csv"))
    dock.routes.pairs_button.click()  # refused before any task starts
    assert dock.slot.task is None
    assert "no such pairs file" in dock.runs.status_label.text()


def test_a_running_job_disables_the_routes_buttons(dock) -> None:
    buttons = (dock.routes.corridor_button, dock.routes.pairs_button)
    assert all(b.isEnabled() for b in buttons)
    dock.slot.set_busy(True)
    assert not any(b.isEnabled() for b in buttons)
    dock.slot.set_busy(False)
    assert all(b.isEnabled() for b in buttons)
