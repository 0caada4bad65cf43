"""The click-to-plan map tool driven by QTest mouse and key events on the canvas viewport.

Events go through the canvas as a user's would (so the canvas's own handling -- Shift+drag zoom
for tools that allow it -- is in the loop). The canvas is in Web Mercator while the costmap is in
UTM 33N, so every click goes through the CRS transformation; plans run in a real planner worker
(`overseec plan-server`), and the expected path comes from the core Planner on the same pixels.

The tool answers on the GUI thread once the worker has (``tool.wait()`` processes events until
then). The responsiveness tests give the worker slow loads and plans (:class:`SlowClient`) and
hold a 10 ms heartbeat (:mod:`tests.qgis.heartbeat`) to the issue's rule: no action blocks the
GUI thread longer than 100 ms.
"""

from __future__ import annotations

import hashlib
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from qgis.core import (
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsLayerTreeRegistryBridge,
    QgsPointXY,
    QgsProject,
)
from qgis.gui import QgsMapTool
from qgis.PyQt.QtCore import QPoint, Qt
from qgis.PyQt.QtTest import QTest

import overseec_core.plan as core_plan
from overseec_qgis.layers import add_costmap
from overseec_qgis.maptool import GOAL_COLOUR, LOADING_MESSAGE, START_COLOUR, VIA_COLOUR, PlanMapTool
from overseec_qgis.planclient import PlanClient

from ..plan.test_server import densify
from .conftest import REPO
from .heartbeat import MAX_BLOCK_MS, Heartbeat, pump, wait_for

pytestmark = pytest.mark.qgis


def show_canvas(canvas, parent, size=(600, 600)) -> None:
    """Offscreen, the canvas takes its size only once shown (its map settings follow)."""
    from qgis.PyQt.QtCore import QCoreApplication

    parent.resize(*size)
    parent.show()
    canvas.resize(*size)
    QCoreApplication.processEvents()


@pytest.fixture(scope="module")
def client():
    """One planner worker for the module, as QGIS keeps one per session."""
    c = PlanClient([sys.executable, "-m", "overseec_core.cli", "plan-server"])
    yield c
    c.close()


@pytest.fixture
def on_canvas(scene, qgis_canvas, qgis_iface, qgis_parent, qgis_new_project, client):
    layer = add_costmap(scene.costmap)
    canvas = qgis_canvas
    show_canvas(canvas, qgis_parent)
    canvas.setDestinationCrs(QgsCoordinateReferenceSystem("EPSG:3857"))
    to_canvas = QgsCoordinateTransform(layer.crs(), canvas.mapSettings().destinationCrs(), QgsProject.instance())
    canvas.setExtent(to_canvas.transformBoundingBox(layer.extent()))
    canvas.refresh()
    tool = PlanMapTool(canvas, qgis_iface, client=client)
    tool.set_costmap(layer)
    canvas.setMapTool(tool)
    yield scene, canvas, tool, to_canvas
    canvas.unsetMapTool(tool)
    tool.clear()


def screen(canvas, to_canvas, scene, row, col) -> QPoint:
    """Screen position of a costmap pixel centre."""
    p = to_canvas.transform(QgsPointXY(*scene.world(row, col)))
    s = canvas.getCoordinateTransform().transform(p)
    return QPoint(round(s.x()), round(s.y()))


def click(canvas, pos: QPoint, button=Qt.LeftButton, modifiers=Qt.NoModifier) -> None:
    QTest.mouseClick(canvas.viewport(), button, modifiers, pos)


def drag(canvas, a: QPoint, b: QPoint, release: bool = True) -> None:
    """Press at a, move to b in steps with the button held, release at b.

    Through the top-level window (QTest's QWindow events): QTest's QWidget mouseMove only moves
    the cursor, which an offscreen platform never turns into an event."""
    window, top = canvas.window().windowHandle(), canvas.window()

    def at(p: QPoint) -> QPoint:
        return canvas.viewport().mapTo(top, p)

    QTest.mousePress(window, Qt.LeftButton, Qt.NoModifier, at(a))
    for t in (0.25, 0.5, 0.75, 1.0):
        QTest.mouseMove(window, at(QPoint(round(a.x() + t * (b.x() - a.x())), round(a.y() + t * (b.y() - a.y())))))
    if release:
        QTest.mouseRelease(window, Qt.LeftButton, Qt.NoModifier, at(b))


def release_at(canvas, p: QPoint) -> None:
    top = canvas.window()
    QTest.mouseRelease(top.windowHandle(), Qt.LeftButton, Qt.NoModifier, canvas.viewport().mapTo(top, p))


def features(tool):
    """The paths layer's features once every request of the tool was answered."""
    assert tool.wait(), "the tool's requests were not answered"
    return list(tool.paths_layer.getFeatures()) if tool.paths_layer is not None else []


def pixels_of(tool, feature) -> list[tuple[int, int]]:
    """Every pixel of a planned route (its vertices are where it turns)."""
    vertices = np.array([tool.session().grid.world_to_pixel(p.x(), p.y()) for p in feature.geometry().asPolyline()])
    return [tuple(p) for p in densify(vertices).tolist()]


def test_clicks_plan_a_path_like_the_core_planner(on_canvas) -> None:
    scene, canvas, tool, to_canvas = on_canvas
    planned = []
    tool.planned.connect(planned.append)
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))  # start
    assert not features(tool)
    click(canvas, screen(canvas, to_canvas, scene, 3, 60))  # goal -> plan
    assert tool.wait() and len(planned) == 1 and planned[0].ms > 0
    (f,) = features(tool)
    layer = tool.paths_layer
    assert layer.crs().authid() == "EPSG:32633"
    assert layer.customProperty("overseec/role") == "path"
    # the same pixels planned by the core directly give the same cost and length
    grid = core_plan.load_costmap(scene.costmap)
    res = core_plan.Planner(grid).plan([(44, 2), (3, 60)], mode="fast")
    assert f["total_cost"] == pytest.approx(res.cost) and f["length_m"] == pytest.approx(res.length_m)
    assert f["mode"] in ("fast", "exact") and f["vias"] == 0
    # vertices are the route's pixel centres where it turns (the same line), in the costmap CRS
    vertices = np.array([grid.world_to_pixel(p.x(), p.y()) for p in f.geometry().asPolyline()])
    assert np.array_equal(densify(vertices), res.pixels) and len(vertices) < len(res.pixels)
    water = np.zeros(grid.shape, bool)
    water[18:34, 20:40] = True
    assert not water[res.pixels[:, 0], res.pixels[:, 1]].any()


def test_the_tool_has_no_zoom_rectangle_so_shift_click_adds_a_via(on_canvas) -> None:
    scene, canvas, tool, to_canvas = on_canvas
    assert not tool.flags() & QgsMapTool.AllowZoomRect
    extent = canvas.extent()
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 10, 10), modifiers=Qt.ShiftModifier)
    click(canvas, screen(canvas, to_canvas, scene, 44, 60))
    assert canvas.extent() == extent  # the canvas did not zoom
    (f,) = features(tool)
    assert f["vias"] == 1 and (10, 10) in pixels_of(tool, f)
    assert pixels_of(tool, f)[0] == (44, 2) and pixels_of(tool, f)[-1] == (44, 60)


def test_markers_are_drawn_start_green_vias_orange_goal_red(on_canvas) -> None:
    scene, canvas, tool, to_canvas = on_canvas
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 10, 10), modifiers=Qt.ShiftModifier)
    assert [m.fillColor() for m in tool.markers] == [START_COLOUR, VIA_COLOUR]
    click(canvas, screen(canvas, to_canvas, scene, 30, 45), modifiers=Qt.ShiftModifier)
    click(canvas, screen(canvas, to_canvas, scene, 44, 60))
    markers = tool.markers
    assert [m.fillColor() for m in markers] == [START_COLOUR, VIA_COLOUR, VIA_COLOUR, GOAL_COLOUR]
    for marker, (row, col) in zip(markers, [(44, 2), (10, 10), (30, 45), (44, 60)]):
        assert marker.isVisible() and marker.scene() is canvas.scene()
        centre = canvas.getCoordinateTransform().transform(marker.center())
        expected = screen(canvas, to_canvas, scene, row, col)
        assert abs(centre.x() - expected.x()) <= 1 and abs(centre.y() - expected.y()) <= 1


def test_dragging_any_point_replans_the_same_feature(on_canvas) -> None:
    scene, canvas, tool, to_canvas = on_canvas
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 10, 10), modifiers=Qt.ShiftModifier)
    click(canvas, screen(canvas, to_canvas, scene, 44, 60))
    (f,) = features(tool)
    # drag the goal, then the via: each drag re-plans the same feature
    drag(canvas, screen(canvas, to_canvas, scene, 44, 60), screen(canvas, to_canvas, scene, 40, 45))
    (g,) = features(tool)
    assert g.id() == f.id() and g["total_cost"] != pytest.approx(f["total_cost"])
    assert pixels_of(tool, g)[-1] == (40, 45)
    drag(canvas, screen(canvas, to_canvas, scene, 10, 10), screen(canvas, to_canvas, scene, 5, 30))
    (h,) = features(tool)
    assert h.id() == f.id() and (5, 30) in pixels_of(tool, h) and h["total_cost"] != pytest.approx(g["total_cost"])
    assert h["vias"] == 1
    # Esc during a drag puts the point back and plans nothing
    drag(canvas, screen(canvas, to_canvas, scene, 44, 2), screen(canvas, to_canvas, scene, 40, 10), release=False)
    QTest.keyClick(canvas, Qt.Key_Escape)
    release_at(canvas, screen(canvas, to_canvas, scene, 40, 10))
    (same,) = features(tool)
    assert same.geometry().equals(h.geometry()) and len(tool.points) == 3


def test_a_drag_previews_the_route_live_and_stores_it_on_release(on_canvas) -> None:
    scene, canvas, tool, to_canvas = on_canvas
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 3, 60))
    (before,) = features(tool)
    drag(canvas, screen(canvas, to_canvas, scene, 3, 60), screen(canvas, to_canvas, scene, 40, 45), release=False)
    assert tool.wait()
    assert tool.preview.numberOfVertices() > 1  # the route to where the goal is now
    end = tool.preview.asGeometry().asPolyline()[-1]
    back = to_canvas.transform(end, QgsCoordinateTransform.ReverseTransform)
    assert tool.session().grid.world_to_pixel(back.x(), back.y()) == (40, 45)
    (during,) = features(tool)
    assert during.geometry().equals(before.geometry())  # nothing stored while dragging
    release_at(canvas, screen(canvas, to_canvas, scene, 40, 45))
    assert tool.wait() and tool.preview.numberOfVertices() == 0
    (after,) = features(tool)
    assert pixels_of(tool, after)[-1] == (40, 45)
    assert tool.paths_layer.undoStack().count() == 2
    # exact mode (one plan can take seconds on a large costmap) plans only on release
    tool.mode = "exact"
    drag(canvas, screen(canvas, to_canvas, scene, 40, 45), screen(canvas, to_canvas, scene, 30, 50), release=False)
    assert tool.wait() and tool.preview.numberOfVertices() == 0
    release_at(canvas, screen(canvas, to_canvas, scene, 30, 50))
    (exact,) = features(tool)
    assert exact["mode"] == "exact" and pixels_of(tool, exact)[-1] == (30, 50)


def test_a_click_near_a_finished_paths_start_starts_a_new_path(on_canvas) -> None:
    scene, canvas, tool, to_canvas = on_canvas
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 3, 60))
    (first,) = features(tool)
    near_start = screen(canvas, to_canvas, scene, 44, 2) + QPoint(2, 1)
    click(canvas, near_start)  # a click, not a drag: a new start
    assert len(tool.points) == 1 and not tool.complete
    (unchanged,) = features(tool)
    assert unchanged.geometry().equals(first.geometry())
    click(canvas, screen(canvas, to_canvas, scene, 5, 30))
    assert len(features(tool)) == 2


def test_arming_the_tool_loads_the_topmost_costmap_before_the_first_click(scene, qgis_new_project, qgis_canvas, client):
    """A costmap the tool was never given (added by the analyst, say): arming the tool starts its
    load, so the goal click waits for no load of its own."""
    client.request("unload")
    add_costmap(scene.costmap)
    tool = PlanMapTool(qgis_canvas, None, client=client)
    try:
        qgis_canvas.setMapTool(tool)
        deadline = time.monotonic() + 60
        while str(scene.costmap) not in client.ping()["loaded"]:
            assert time.monotonic() < deadline, "arming the tool did not load the costmap"
            time.sleep(0.05)
    finally:
        qgis_canvas.unsetMapTool(tool)
        tool.clear()


def test_a_costmap_given_to_the_tool_is_loaded_before_the_first_click(scene, qgis_new_project, qgis_canvas, client):
    client.request("unload")
    tool = PlanMapTool(qgis_canvas, None, client=client)
    try:
        tool.set_costmap(add_costmap(scene.costmap))
        deadline = time.monotonic() + 60
        while str(scene.costmap) not in client.ping()["loaded"]:
            assert time.monotonic() < deadline, "the costmap was not preloaded"
            time.sleep(0.05)
    finally:
        tool.clear()


def test_one_worker_load_for_repeated_plans(on_canvas, client) -> None:
    scene, canvas, tool, to_canvas = on_canvas
    client.request("unload")
    before = client.ping()["loads"]
    for k, goal_col in enumerate((30, 40, 50, 60)):
        click(canvas, screen(canvas, to_canvas, scene, 44 - 2 * k, 2))
        click(canvas, screen(canvas, to_canvas, scene, 5, goal_col))
    assert len(features(tool)) == 4  # each finished path stays; the next click starts a new one
    assert client.ping()["loads"] - before <= 1, "the worker reloaded the costmap for a click"


def test_right_click_and_escape_cancel(on_canvas) -> None:
    scene, canvas, tool, to_canvas = on_canvas
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    assert len(tool.points) == 1 and len(tool.markers) == 1
    click(canvas, screen(canvas, to_canvas, scene, 5, 5), button=Qt.RightButton)
    assert tool.points == [] and tool.markers == [] and not features(tool)
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 20, 5), modifiers=Qt.ShiftModifier)
    QTest.keyClick(canvas, Qt.Key_Escape)
    assert tool.points == [] and not features(tool)
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 3, 60))
    assert len(features(tool)) == 1


def test_a_goal_on_lethal_water_is_reported_not_raised(on_canvas, qgis_iface) -> None:
    from qgis.core import Qgis

    scene, canvas, tool, to_canvas = on_canvas
    errors = []
    tool.failed.connect(errors.append)
    qgis_iface.messageBar().clear_messages()
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 25, 30))  # inside the water block
    assert tool.wait() and len(errors) == 1 and "lethal" in errors[0] and "\n" not in errors[0]
    assert not features(tool)
    warnings = qgis_iface.messageBar().get_messages(Qgis.Warning)
    assert warnings and "lethal" in warnings[-1]


def test_paths_live_in_a_geopackage_on_top_with_undo_and_survive_a_reopened_project(on_canvas, tmp_path) -> None:
    scene, canvas, tool, to_canvas = on_canvas
    project = QgsProject.instance()
    root = project.layerTreeRoot()
    # the legend selection is inside a group below the costmap: new layers would land there
    group = root.addGroup("basemaps")
    project.layerTreeRegistryBridge().setLayerInsertionPoint(QgsLayerTreeRegistryBridge.InsertionPoint(group, 0))
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 3, 60))
    assert tool.wait()
    # (a dangling insertion point would crash the next addMapLayer once the project is cleared)
    project.layerTreeRegistryBridge().setLayerInsertionPoint(QgsLayerTreeRegistryBridge.InsertionPoint(root, 0))
    layer = tool.paths_layer
    assert layer.providerType() == "ogr"
    assert layer.source().split("|")[0] == str(scene.folder / "paths.gpkg")
    assert root.children()[0].findLayer(layer.id()) is not None  # in the routes group, first in the legend
    assert root.layerOrder()[0] is layer
    (planned,) = features(tool)
    drag(canvas, screen(canvas, to_canvas, scene, 3, 60), screen(canvas, to_canvas, scene, 5, 45))
    (moved,) = features(tool)
    assert not moved.geometry().equals(planned.geometry())
    assert layer.isEditable() and layer.undoStack().count() == 2
    layer.undoStack().undo()  # the drag's re-plan is taken back
    (undone,) = features(tool)
    assert undone.geometry().equals(planned.geometry())
    layer.undoStack().redo()
    # saving the project commits the paths into the GeoPackage; the reopened project has them
    project_file = tmp_path / "project.qgz"
    assert project.write(str(project_file))
    assert not layer.isModified()
    saved = [(f["total_cost"], f.geometry().asWkt(3)) for f in layer.getFeatures()]
    assert saved and saved[0][0] == pytest.approx(moved["total_cost"])
    project.clear()
    assert project.read(str(project_file))
    (reopened,) = [
        lyr for lyr in project.mapLayers().values() if lyr.source().startswith(str(scene.folder / "paths.gpkg"))
    ]
    assert [(f["total_cost"], f.geometry().asWkt(3)) for f in reopened.getFeatures()] == saved


def test_save_paths_writes_rfc7946_geojson(on_canvas, tmp_path) -> None:
    import json

    scene, canvas, tool, to_canvas = on_canvas
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 3, 60))
    assert tool.wait()
    out = tool.save_paths(tmp_path / "paths.geojson")
    doc = json.loads(out.read_text())
    (feat,) = doc["features"]
    assert feat["geometry"]["type"] == "LineString"
    lon, lat = feat["geometry"]["coordinates"][0]
    assert 15.0 < lon < 16.0 and 47.0 < lat < 47.2  # UTM 33N near 534 km E, 5213 km N
    assert feat["properties"]["total_cost"] > 0 and feat["properties"]["length_m"] > 0
    assert set(feat["properties"]) == {"total_cost", "length_m", "mode", "vias"}
    assert not list(tmp_path.glob(".*partial*"))


def test_switching_costmaps_keeps_the_tool_working(on_canvas, scene, tmp_path) -> None:
    """A new costmap gets its own paths layer; markers still draw; new routes go there."""
    import shutil

    _, canvas, tool, to_canvas = on_canvas
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 3, 60))
    assert tool.wait()
    first_layer = tool.paths_layer
    copy = tmp_path / "other"
    shutil.copytree(scene.folder, copy, ignore=shutil.ignore_patterns("paths.gpkg*"))
    other = add_costmap(copy / "costmap.tif", name="costmap 2")
    tool.set_costmap(other)
    tool.cancel()
    click(canvas, screen(canvas, to_canvas, scene, 40, 4))
    assert tool.markers is not None and len(tool.markers) == 1
    click(canvas, screen(canvas, to_canvas, scene, 5, 58))
    assert tool.wait() and tool.paths_layer is not first_layer
    assert "costmap 2" in tool.paths_layer.name()
    assert tool.paths_layer.source().split("|")[0] == str(copy / "paths.gpkg")
    assert len(list(first_layer.getFeatures())) == 1


def _costmap_variant(scene, folder, prompt: str, road_cost: float):
    """The scene's costmap with another road cost, as a re-prompted costmap layer."""
    import shutil

    import rasterio

    shutil.copytree(scene.folder, folder, ignore=shutil.ignore_patterns("paths.gpkg*"))
    with rasterio.open(folder / "costmap.tif", "r+") as ds:
        cost = ds.read(1)
        cost[cost < 0.1] = road_cost
        ds.write(cost, 1)
    layer = add_costmap(folder / "costmap.tif", name=folder.name)
    layer.setCustomProperty("overseec/prompt", prompt)
    return layer


def test_reprompting_plans_the_same_route_beside_the_earlier_one(on_canvas, scene, tmp_path) -> None:
    """A costmap from a new prompt gets the same start and goal planned on it, in a layer named
    after its prompt; the earlier route stays in its own layer (one legend entry per prompt)."""
    _, canvas, tool, to_canvas = on_canvas
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 3, 60))
    assert tool.wait()
    first_layer = tool.paths_layer
    (first,) = features(tool)
    avoid_roads = _costmap_variant(scene, tmp_path / "avoid", "avoid the roads", 0.9)
    tool.set_costmap(avoid_roads)
    assert tool.wait()
    second_layer = tool.paths_layer
    assert second_layer is not None and second_layer is not first_layer
    assert second_layer.name() == "path — avoid the roads"
    (second,) = list(second_layer.getFeatures())
    assert second["total_cost"] > first["total_cost"]  # the roads it used cost more now
    ends = pixels_of(tool, second)
    assert [ends[0], ends[-1]] == [(44, 2), (3, 60)]
    assert len(list(first_layer.getFeatures())) == 1
    names = {layer.name() for layer in QgsProject.instance().mapLayers().values()}
    assert {first_layer.name(), "path — avoid the roads"} <= names


def _polygon_layer(scene, rows: range, cols: range, **fields):
    from qgis.core import QgsField, QgsVectorLayer
    from qgis.PyQt.QtCore import QVariant

    layer = QgsVectorLayer("Polygon?crs=EPSG:32633", "overrides", "memory")
    layer.dataProvider().addAttributes(
        [QgsField("cost", QVariant.Double), QgsField("lethal", QVariant.Int), QgsField("prefer", QVariant.Int)]
    )
    layer.updateFields()
    QgsProject.instance().addMapLayer(layer)
    return layer, _polygon(layer, scene, rows, cols, **fields)


def _polygon(layer, scene, rows: range, cols: range, **fields):
    from qgis.core import QgsFeature, QgsGeometry

    (x0, y0), (x1, y1) = scene.world(rows.start, cols.start), scene.world(rows.stop, cols.stop)
    f = QgsFeature(layer.fields())
    f.setGeometry(
        QgsGeometry.fromPolygonXY([[QgsPointXY(x0, y0), QgsPointXY(x1, y0), QgsPointXY(x1, y1), QgsPointXY(x0, y1)]])
    )
    for name, value in fields.items():
        f[name] = value
    return f


def test_drawing_an_override_polygon_replans_the_route(on_canvas, scene) -> None:
    """An analyst draws a lethal polygon over the route in an editable overrides layer: the route
    is planned again around it at once (unsaved edits count), and again when it is deleted."""
    _, canvas, tool, to_canvas = on_canvas
    digest = hashlib.sha256(scene.costmap.read_bytes()).hexdigest()
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 3, 60))
    (before,) = features(tool)
    crossed = set(pixels_of(tool, before))
    row, col = sorted(crossed)[len(crossed) // 2]
    layer, _ = _polygon_layer(scene, range(0, 0), range(0, 0))
    tool.set_overrides_layer(layer)
    layer.startEditing()
    wall = _polygon(layer, scene, range(max(row - 3, 0), row + 4), range(max(col - 3, 0), col + 4), lethal=1)
    assert layer.addFeature(wall)
    (after,) = features(tool)
    assert after.id() == before.id() and after["total_cost"] > before["total_cost"]
    # the polygon's corners are pixel centres: the cells whose centres lie inside are walled
    walled = {(r, c) for r in range(max(row - 2, 0), row + 4) for c in range(max(col - 2, 0), col + 4)}
    assert not set(pixels_of(tool, after)) & walled
    assert hashlib.sha256(scene.costmap.read_bytes()).hexdigest() == digest  # file untouched
    layer.rollBack()  # the edit is undone: the original route comes back
    (restored,) = features(tool)
    assert restored["total_cost"] == pytest.approx(before["total_cost"])


def test_the_map_tool_module_never_loads_the_kernel() -> None:
    """QGIS's Python plans through the worker: the tool's modules import no planner code."""
    import re

    pattern = re.compile(r"^\s*(from|import)\s+(overseec_core\.plan|\.\.?plan\b)", re.M)
    for name in (
        "maptool.py",
        "planrequests.py",
        "planpaths.py",
        "planoverrides.py",
        "planmarkers.py",
        "planmixin.py",
        "planclient.py",
        "lineclient.py",
        "planjobs.py",
        "planfiles.py",
        "layers.py",
    ):
        assert not pattern.search((REPO / "overseec_qgis" / name).read_text()), name


NO_KERNEL_SCRIPT = """
import importlib.util, json, sys
sys.path.insert(0, sys.argv[1])
from qgis.core import QgsApplication, QgsProject, QgsRasterLayer, QgsPointXY
from qgis.gui import QgsMapCanvas
from qgis.PyQt.QtCore import QPoint, Qt
from qgis.PyQt.QtTest import QTest
app = QgsApplication([], True)
app.initQgis()
import overseec_core
from overseec_qgis.maptool import PlanMapTool
from overseec_qgis.planclient import close_shared_client
layer = QgsRasterLayer(sys.argv[2], "costmap")
QgsProject.instance().addMapLayer(layer)
canvas = QgsMapCanvas()
canvas.resize(600, 600)
canvas.show()
canvas.setDestinationCrs(layer.crs())
canvas.setExtent(layer.extent())
app.processEvents()
tool = PlanMapTool(canvas)
tool.set_costmap(layer)
canvas.setMapTool(tool)
planned = []
tool.planned.connect(planned.append)
tool.failed.connect(print)
for (x, y), mods in zip(json.loads(sys.argv[3]), (Qt.NoModifier, Qt.ShiftModifier, Qt.NoModifier)):
    p = canvas.getCoordinateTransform().transform(QgsPointXY(x, y))
    QTest.mouseClick(canvas.viewport(), Qt.LeftButton, mods, QPoint(round(p.x()), round(p.y())))
tool.wait()
vias = [f["vias"] for f in tool.paths_layer.getFeatures()] if tool.paths_layer else []
tool.clear()
close_shared_client()
print(json.dumps({
    "core": overseec_core.__file__,
    "kernel_findable": importlib.util.find_spec("overseec_core.plan._kernel") is not None,
    "kernel_loaded": "overseec_core.plan._kernel" in sys.modules,
    "planned": len(planned),
    "vias": vias,
}))
"""


def test_the_tool_plans_where_no_kernel_can_be_imported(scene, tmp_path) -> None:
    """A pure-Python copy of the plugin (as the zip ships it) plans through the worker."""
    import json
    import os
    import shutil
    import subprocess

    copy = tmp_path / "plugin"
    for name in ("overseec_qgis", "overseec_core", "resources"):
        shutil.copytree(REPO / name, copy / name, ignore=shutil.ignore_patterns("*.so", "*.pyd", "__pycache__"))
    points = [scene.world(44, 2), scene.world(10, 10), scene.world(3, 60)]
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env.update(OVERSEEC_WORKER=str(Path(sys.prefix) / "bin" / "overseec"), QT_QPA_PLATFORM="offscreen")
    done = subprocess.run(
        [sys.executable, "-c", NO_KERNEL_SCRIPT, str(copy), str(scene.costmap), json.dumps(points)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env=env,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["core"].startswith(str(copy))
    assert not report["kernel_findable"] and not report["kernel_loaded"]
    assert report["planned"] == 1 and report["vias"] == [1]


# -- responsiveness, overrides from any tool, undo/redo -------------------------------------------


class SlowClient(PlanClient):
    """A real planner worker whose loads and plans take longer (a large costmap's read, an exact
    search on it), and that counts the plans it sent."""

    load_delay_s = 0.0
    plan_delay_s = 0.0

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.plans_sent = 0

    def load(self, costmap, band=None, overrides=()):
        time.sleep(self.load_delay_s)
        return super().load(costmap, band, overrides)

    def request(self, op, timeout_s=None, **fields):
        if op == "plan":  # sent (under the client's lock): the worker is busy for the delay
            self.plans_sent += 1
            time.sleep(self.plan_delay_s)
        return super().request(op, timeout_s, **fields)


@pytest.fixture(scope="module")
def slow_client():
    c = SlowClient([sys.executable, "-m", "overseec_core.cli", "plan-server"])
    c.ping()  # the worker is up: the tests time the tool, not a Python start
    yield c
    c.close()


@pytest.fixture
def slow_canvas(scene, qgis_canvas, qgis_iface, qgis_parent, qgis_new_project, slow_client):
    """The tool on the canvas with a slow worker, not yet given the costmap (the test does): the
    tool is armed before the costmap is added, so arming preloads nothing."""
    slow_client.load_delay_s = slow_client.plan_delay_s = 0.0
    slow_client.request("unload")
    canvas = qgis_canvas
    tool = PlanMapTool(canvas, qgis_iface, client=slow_client)
    canvas.setMapTool(tool)
    layer = add_costmap(scene.costmap)
    show_canvas(canvas, qgis_parent)
    canvas.setDestinationCrs(QgsCoordinateReferenceSystem("EPSG:3857"))
    to_canvas = QgsCoordinateTransform(layer.crs(), canvas.mapSettings().destinationCrs(), QgsProject.instance())
    canvas.setExtent(to_canvas.transformBoundingBox(layer.extent()))
    canvas.refresh()
    qgis_iface.messageBar().clearWidgets()
    yield scene, canvas, tool, to_canvas, layer, slow_client
    canvas.unsetMapTool(tool)
    tool.wait()
    tool.clear()


def loading_shown(iface) -> bool:
    return any(LOADING_MESSAGE in item.text() for item in iface.messageBar().items())


def test_a_click_before_the_load_finished_waits_for_it_without_blocking(slow_canvas, qgis_iface) -> None:
    """The first click after the tool is given a costmap that is still loading (1.5 s here):
    the GUI thread is never blocked, a message says the costmap is loading, and the route is
    planned as soon as the load is done."""
    scene, canvas, tool, to_canvas, layer, client = slow_canvas
    client.load_delay_s = 1.5
    planned = []
    tool.planned.connect(planned.append)
    with Heartbeat() as beat:
        t0 = time.monotonic()
        tool.set_costmap(layer)  # the load starts now, in the background
        pump(0.05)
        click(canvas, screen(canvas, to_canvas, scene, 44, 2))
        pump(0.05)
        click(canvas, screen(canvas, to_canvas, scene, 3, 60))
        pump(0.05)
        waiting = (tool.loading, len(planned), loading_shown(qgis_iface))
        assert wait_for(lambda: planned, 60)
        took = time.monotonic() - t0
    assert beat.blocked_ms <= MAX_BLOCK_MS, f"the GUI thread was blocked {beat.blocked_ms:.0f} ms"
    assert waiting == (True, 0, True)  # queued behind the load, with a message
    assert took >= 1.5 and beat.ticks > 50
    assert not tool.loading and not loading_shown(qgis_iface)
    (f,) = features(tool)
    assert pixels_of(tool, f)[0] == (44, 2) and pixels_of(tool, f)[-1] == (3, 60)
    assert client.plans_sent == 1


def test_an_exact_plan_runs_as_a_task_without_blocking_and_cancel_drops_it(slow_canvas) -> None:
    """Exact plans run as tasks in QGIS's task manager; the GUI thread is never blocked, and
    cancelling the task drops its answer."""
    from qgis.core import QgsApplication

    scene, canvas, tool, to_canvas, layer, client = slow_canvas
    tool.set_costmap(layer)
    assert tool.wait()
    tool.mode = "exact"
    client.plan_delay_s = 1.0
    planned = []
    tool.planned.connect(planned.append)
    manager = QgsApplication.taskManager()

    def our_tasks():
        return [t for t in manager.activeTasks() if t.description().startswith("overseec: planning")]

    with Heartbeat() as beat:
        pump(0.05)
        click(canvas, screen(canvas, to_canvas, scene, 44, 2))
        click(canvas, screen(canvas, to_canvas, scene, 3, 60))
        assert wait_for(lambda: our_tasks(), 10), "no task in the task manager"
        assert wait_for(lambda: planned, 60)
    assert beat.blocked_ms <= MAX_BLOCK_MS, f"the GUI thread was blocked {beat.blocked_ms:.0f} ms"
    (f,) = features(tool)
    assert f["mode"] == "exact" and wait_for(lambda: not our_tasks(), 10)
    # the next one is cancelled from the task manager: nothing is stored
    drag(canvas, screen(canvas, to_canvas, scene, 3, 60), screen(canvas, to_canvas, scene, 30, 50))
    assert wait_for(lambda: our_tasks(), 10)
    manager.cancelAll()
    assert tool.wait()
    (same,) = features(tool)
    assert len(planned) == 1 and same.geometry().equals(f.geometry())


def test_a_drag_preview_never_blocks_and_never_piles_up(slow_canvas) -> None:
    """Moving a marker re-plans a preview in the background (0.2 s a plan here): the GUI thread
    is never blocked, and while a preview is in flight only the latest position waits."""
    scene, canvas, tool, to_canvas, layer, client = slow_canvas
    tool.set_costmap(layer)
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 3, 60))
    assert tool.wait()
    client.plan_delay_s = 0.2
    sent = client.plans_sent
    window, top = canvas.window().windowHandle(), canvas.window()
    a, b = screen(canvas, to_canvas, scene, 3, 60), screen(canvas, to_canvas, scene, 40, 45)
    steps = 20
    with Heartbeat() as beat:
        t0 = time.monotonic()
        QTest.mousePress(window, Qt.LeftButton, Qt.NoModifier, canvas.viewport().mapTo(top, a))
        for i in range(1, steps + 1):
            t = i / steps
            p = QPoint(round(a.x() + t * (b.x() - a.x())), round(a.y() + t * (b.y() - a.y())))
            QTest.mouseMove(window, canvas.viewport().mapTo(top, p))
            pump(0.02)
        assert tool.wait()
        took = time.monotonic() - t0
    assert beat.blocked_ms <= MAX_BLOCK_MS, f"the GUI thread was blocked {beat.blocked_ms:.0f} ms"
    previews = client.plans_sent - sent
    # one preview in flight at a time (0.2 s each), the latest position next: not one per move
    assert 2 <= previews <= took / client.plan_delay_s + 1 and previews <= steps // 2, (previews, took)
    end = tool.preview.asGeometry().asPolyline()[-1]
    back = to_canvas.transform(end, QgsCoordinateTransform.ReverseTransform)
    assert tool.session().grid.world_to_pixel(back.x(), back.y()) == (40, 45)  # the latest position
    release_at(canvas, b)
    (f,) = features(tool)
    assert pixels_of(tool, f)[-1] == (40, 45)


def marker_pixels(tool, canvas, to_canvas) -> list[tuple[int, int]]:
    """The costmap pixels under the current markers (start, vias, goal)."""
    grid = tool.session().grid
    out = []
    for marker in tool.markers:
        p = to_canvas.transform(marker.center(), QgsCoordinateTransform.ReverseTransform)
        out.append(grid.world_to_pixel(p.x(), p.y()))
    return out


def test_undo_and_redo_move_the_markers_with_the_path(on_canvas) -> None:
    """Undo of a drag's re-plan puts the marker back where the path now ends, and the next drag
    starts from there; redo moves it again; undo of the plan itself takes the markers away."""
    scene, canvas, tool, to_canvas = on_canvas
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 3, 60))
    (planned,) = features(tool)
    drag(canvas, screen(canvas, to_canvas, scene, 3, 60), screen(canvas, to_canvas, scene, 40, 45))
    (dragged,) = features(tool)
    assert marker_pixels(tool, canvas, to_canvas) == [(44, 2), (40, 45)]
    stack = tool.paths_layer.undoStack()
    stack.undo()
    assert marker_pixels(tool, canvas, to_canvas) == [(44, 2), (3, 60)]
    (undone,) = features(tool)
    assert undone.geometry().equals(planned.geometry())
    stack.redo()
    assert marker_pixels(tool, canvas, to_canvas) == [(44, 2), (40, 45)]
    stack.undo()
    # the next drag grabs the goal where the undo put it
    drag(canvas, screen(canvas, to_canvas, scene, 3, 60), screen(canvas, to_canvas, scene, 30, 50))
    (again,) = features(tool)
    assert again.id() == planned.id() and pixels_of(tool, again)[-1] == (30, 50)
    assert marker_pixels(tool, canvas, to_canvas) == [(44, 2), (30, 50)]
    # undo down to the plan's creation: the path is gone, so are its markers; redo brings both
    stack.undo()
    stack.undo()
    assert not features(tool) and tool.markers == []
    stack.redo()
    assert len(features(tool)) == 1 and marker_pixels(tool, canvas, to_canvas) == [(44, 2), (3, 60)]


def test_old_paths_tables_get_the_waypoints_field(on_canvas, scene) -> None:
    """A paths.gpkg made before waypoints were stored gains the field with the next plan."""
    from qgis.core import QgsField, QgsFields, QgsVectorFileWriter, QgsWkbTypes
    from qgis.PyQt.QtCore import QVariant

    from overseec_qgis.layers import PATH_FIELDS, paths_table

    _, canvas, tool, to_canvas = on_canvas
    assert ("waypoints", "string") in PATH_FIELDS
    fields = QgsFields()
    for name, kind in (("total_cost", QVariant.Double), ("length_m", QVariant.Double), ("mode", QVariant.String)):
        fields.append(QgsField(name, kind))
    fields.append(QgsField("vias", QVariant.Int))
    fields.append(QgsField("path_id", QVariant.String))
    options = QgsVectorFileWriter.SaveVectorOptions()
    options.driverName, options.layerName = "GPKG", paths_table(scene.costmap)
    writer = QgsVectorFileWriter.create(
        str(scene.folder / "paths.gpkg"),
        fields,
        QgsWkbTypes.LineString,
        QgsCoordinateReferenceSystem("EPSG:32633"),
        QgsProject.instance().transformContext(),
        options,
    )
    del writer
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 3, 60))
    (f,) = features(tool)
    assert f["waypoints"].startswith("MultiPoint")
    drag(canvas, screen(canvas, to_canvas, scene, 3, 60), screen(canvas, to_canvas, scene, 40, 45))
    features(tool)
    tool.paths_layer.undoStack().undo()
    assert marker_pixels(tool, canvas, to_canvas) == [(44, 2), (3, 60)]


def test_override_edits_made_with_another_tool_replan_once(slow_canvas) -> None:
    """The analyst switches to another map tool (the route and its markers stay) and edits the
    overrides layer: a lethal polygon across the route and two more edits in quick succession
    re-plan the route once, around the polygon."""
    from qgis.gui import QgsMapToolPan

    scene, canvas, tool, to_canvas, layer, client = slow_canvas
    tool.set_costmap(layer)
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 3, 60))
    (before,) = features(tool)
    overrides, _ = _polygon_layer(scene, range(0, 0), range(0, 0))
    tool.set_overrides_layer(overrides)
    assert tool.wait()
    pan = QgsMapToolPan(canvas)
    canvas.setMapTool(pan)  # another tool: the map tool is deactivated
    assert canvas.mapTool() is pan and len(tool.markers) == 2 and tool.complete
    planned = []
    tool.planned.connect(planned.append)
    sent = client.plans_sent
    crossed = set(pixels_of(tool, before))
    row, col = sorted(crossed)[len(crossed) // 2]
    overrides.startEditing()
    wall = _polygon(overrides, scene, range(max(row - 3, 0), row + 4), range(max(col - 3, 0), col + 4), lethal=1)
    assert overrides.addFeature(wall)  # edit 1
    assert overrides.addFeature(_polygon(overrides, scene, range(40, 44), range(20, 24), cost=0.9))  # edit 2
    fid = [f.id() for f in overrides.getFeatures()][-1]
    assert overrides.changeAttributeValue(fid, overrides.fields().indexOf("cost"), 0.8)  # edit 3
    assert not planned  # settling: nothing planned yet
    assert tool.wait()
    assert client.plans_sent - sent == 1 and len(planned) == 1
    (after,) = features(tool)
    walled = {(r, c) for r in range(max(row - 2, 0), row + 4) for c in range(max(col - 2, 0), col + 4)}
    assert after.id() == before.id() and after["total_cost"] > before["total_cost"]
    assert not set(pixels_of(tool, after)) & walled
    # undo in the overrides layer re-plans too: the wall's edits are taken back
    stack = overrides.undoStack()
    while stack.canUndo():
        stack.undo()
    assert tool.wait() and len(planned) == 2
    (restored,) = features(tool)
    assert restored["total_cost"] == pytest.approx(before["total_cost"])
    canvas.unsetMapTool(pan)


def test_a_reopened_project_loads_its_costmap_at_once_and_the_first_click_does_not_block(slow_canvas, tmp_path) -> None:
    """Opening a project has the worker load its costmap in the background (before any click);
    the first plan after reopening never blocks the GUI thread."""
    scene, canvas, tool, to_canvas, layer, client = slow_canvas
    tool.set_costmap(layer)
    click(canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(canvas, screen(canvas, to_canvas, scene, 3, 60))
    features(tool)
    project = QgsProject.instance()
    assert project.write(str(tmp_path / "project.qgz"))
    project.clear()
    assert tool.markers == [] and tool.costmap_layer is None and tool.paths_layer is None
    client.request("unload")
    client.load_delay_s = 1.0
    planned = []
    tool.planned.connect(planned.append)
    with Heartbeat() as beat:
        assert project.read(str(tmp_path / "project.qgz"))
        assert tool.costmap_path() == str(scene.costmap) and tool.busy()  # loading already
        pump(0.05)
        click(canvas, screen(canvas, to_canvas, scene, 40, 2))
        click(canvas, screen(canvas, to_canvas, scene, 5, 58))
        assert wait_for(lambda: planned, 60)
    assert beat.blocked_ms <= MAX_BLOCK_MS, f"the GUI thread was blocked {beat.blocked_ms:.0f} ms"
    assert len(features(tool)) == 2  # the reopened path and the new one, in the reopened layer
