"""The click-to-plan map tool driven by synthetic mouse and key events on the canvas.

The canvas is in Web Mercator while the costmap is in UTM 33N, so every click goes through the
CRS transformation; the expected path comes from the core Planner on the same pixels.
"""

from __future__ import annotations

import numpy as np
import pytest
from qgis.core import QgsCoordinateReferenceSystem, QgsCoordinateTransform, QgsPointXY, QgsProject
from qgis.gui import QgsMapMouseEvent
from qgis.PyQt.QtCore import QEvent, QPoint, Qt
from qgis.PyQt.QtGui import QKeyEvent

import overseec_core.plan as core_plan
from overseec_qgis.layers import add_costmap
from overseec_qgis.maptool import PlanMapTool

pytestmark = pytest.mark.qgis


def show_canvas(canvas, parent, size=(600, 600)) -> None:
    """Offscreen, the canvas takes its size only once shown (its map settings follow)."""
    from qgis.PyQt.QtCore import QCoreApplication

    parent.resize(*size)
    parent.show()
    canvas.resize(*size)
    QCoreApplication.processEvents()


@pytest.fixture
def on_canvas(scene, qgis_canvas, qgis_iface, qgis_parent, qgis_new_project):
    layer = add_costmap(scene.costmap)
    canvas = qgis_canvas
    show_canvas(canvas, qgis_parent)
    canvas.setDestinationCrs(QgsCoordinateReferenceSystem("EPSG:3857"))
    to_canvas = QgsCoordinateTransform(layer.crs(), canvas.mapSettings().destinationCrs(), QgsProject.instance())
    canvas.setExtent(to_canvas.transformBoundingBox(layer.extent()))
    tool = PlanMapTool(canvas, qgis_iface)
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


def click(tool, canvas, pos: QPoint, button=Qt.LeftButton, modifiers=Qt.NoModifier) -> None:
    for kind in (QEvent.MouseButtonPress, QEvent.MouseButtonRelease):
        e = QgsMapMouseEvent(
            canvas, kind, pos, button, button if kind == QEvent.MouseButtonPress else Qt.NoButton, modifiers
        )
        (tool.canvasPressEvent if kind == QEvent.MouseButtonPress else tool.canvasReleaseEvent)(e)


def features(tool):
    return list(tool.paths_layer.getFeatures()) if tool.paths_layer is not None else []


def test_clicks_plan_a_path_like_the_core_planner(on_canvas) -> None:
    scene, canvas, tool, to_canvas = on_canvas
    planned = []
    tool.planned.connect(planned.append)
    click(tool, canvas, screen(canvas, to_canvas, scene, 44, 2))  # start
    assert not features(tool)
    click(tool, canvas, screen(canvas, to_canvas, scene, 3, 60))  # goal -> plan
    assert len(planned) == 1
    feats = features(tool)
    assert len(feats) == 1
    layer = tool.paths_layer
    assert layer.crs().authid() == "EPSG:32633"
    assert layer.customProperty("overseec/role") == "path"
    f = feats[0]
    # the same pixels planned by the core directly give the same cost and length
    grid = core_plan.load_costmap(scene.costmap)
    res = core_plan.Planner(grid).plan([(44, 2), (3, 60)], mode="fast")
    assert f["total_cost"] == pytest.approx(res.cost) and f["length_m"] == pytest.approx(res.length_m)
    assert f["mode"] in ("fast", "exact") and f["vias"] == 0
    line = f.geometry().asPolyline()
    assert len(line) == len(res.pixels)
    # vertices are pixel centres in the costmap CRS, never on the (lethal) water
    rows_cols = [grid.world_to_pixel(p.x(), p.y()) for p in line]
    assert rows_cols[0] == (44, 2) and rows_cols[-1] == (3, 60)
    water = np.zeros(grid.shape, bool)
    water[18:34, 20:40] = True
    assert not any(water[r, c] for r, c in rows_cols)


def test_shift_click_adds_a_via_and_dragging_replans(on_canvas) -> None:
    scene, canvas, tool, to_canvas = on_canvas
    click(tool, canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(tool, canvas, screen(canvas, to_canvas, scene, 10, 10), modifiers=Qt.ShiftModifier)
    click(tool, canvas, screen(canvas, to_canvas, scene, 44, 60))
    (f,) = features(tool)
    assert f["vias"] == 1
    rows_cols = [tool.session().grid.world_to_pixel(p.x(), p.y()) for p in f.geometry().asPolyline()]
    assert (10, 10) in rows_cols
    first_id, first_cost = f.id(), f["total_cost"]
    # drag the goal to another pixel: the same feature is re-planned
    goal = screen(canvas, to_canvas, scene, 44, 60)
    new_goal = screen(canvas, to_canvas, scene, 40, 45)
    tool.canvasPressEvent(QgsMapMouseEvent(canvas, QEvent.MouseButtonPress, goal, Qt.LeftButton, Qt.LeftButton))
    tool.canvasMoveEvent(QgsMapMouseEvent(canvas, QEvent.MouseMove, new_goal, Qt.NoButton, Qt.LeftButton))
    tool.canvasReleaseEvent(QgsMapMouseEvent(canvas, QEvent.MouseButtonRelease, new_goal, Qt.LeftButton))
    (g,) = features(tool)
    assert g.id() == first_id and g["total_cost"] != pytest.approx(first_cost)
    end = g.geometry().asPolyline()[-1]
    assert tool.session().grid.world_to_pixel(end.x(), end.y()) == (40, 45)


def test_one_planner_per_costmap_for_repeated_plans(on_canvas, monkeypatch) -> None:
    scene, canvas, tool, to_canvas = on_canvas
    loads = []
    real = core_plan.load_costmap
    monkeypatch.setattr(core_plan, "load_costmap", lambda *a, **k: loads.append(a) or real(*a, **k))
    for k, goal_col in enumerate((30, 40, 50, 60)):
        # a click away from the markers starts a new path (one on a marker would move it)
        click(tool, canvas, screen(canvas, to_canvas, scene, 44 - 2 * k, 2))
        click(tool, canvas, screen(canvas, to_canvas, scene, 5, goal_col))
    assert len(features(tool)) == 4  # each finished path stays; the next click starts a new one
    assert len(loads) == 1, "the costmap was reloaded for a click"


def test_right_click_and_escape_cancel(on_canvas) -> None:
    scene, canvas, tool, to_canvas = on_canvas
    click(tool, canvas, screen(canvas, to_canvas, scene, 44, 2))
    assert len(tool.points) == 1
    click(tool, canvas, screen(canvas, to_canvas, scene, 5, 5), button=Qt.RightButton)
    assert tool.points == [] and not features(tool)
    click(tool, canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(tool, canvas, screen(canvas, to_canvas, scene, 20, 5), modifiers=Qt.ShiftModifier)
    tool.keyPressEvent(QKeyEvent(QEvent.KeyPress, Qt.Key_Escape, Qt.NoModifier))
    assert tool.points == [] and not features(tool)
    # a click after cancelling starts afresh
    click(tool, canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(tool, canvas, screen(canvas, to_canvas, scene, 3, 60))
    assert len(features(tool)) == 1


def test_a_goal_on_lethal_water_is_reported_not_raised(on_canvas, qgis_iface) -> None:
    from qgis.core import Qgis

    scene, canvas, tool, to_canvas = on_canvas
    errors = []
    tool.failed.connect(errors.append)
    qgis_iface.messageBar().clear_messages()
    click(tool, canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(tool, canvas, screen(canvas, to_canvas, scene, 25, 30))  # inside the water block
    assert len(errors) == 1 and "lethal" in errors[0]
    assert not features(tool)
    warnings = qgis_iface.messageBar().get_messages(Qgis.Warning)
    assert warnings and "lethal" in warnings[-1]


def test_save_paths_writes_rfc7946_geojson(on_canvas, tmp_path) -> None:
    import json

    scene, canvas, tool, to_canvas = on_canvas
    click(tool, canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(tool, canvas, screen(canvas, to_canvas, scene, 3, 60))
    out = tool.save_paths(tmp_path / "paths.geojson")
    doc = json.loads(out.read_text())
    (feat,) = doc["features"]
    assert feat["geometry"]["type"] == "LineString"
    lon, lat = feat["geometry"]["coordinates"][0]
    assert 15.0 < lon < 16.0 and 47.0 < lat < 47.2  # UTM 33N near 534 km E, 5213 km N
    assert feat["properties"]["total_cost"] > 0 and feat["properties"]["length_m"] > 0
    assert not list(tmp_path.glob(".*partial*"))


def test_switching_costmaps_keeps_the_tool_working(on_canvas, scene, tmp_path) -> None:
    """A new costmap gets its own paths layer; markers still draw; new routes go there."""
    import shutil

    _, canvas, tool, to_canvas = on_canvas
    click(tool, canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(tool, canvas, screen(canvas, to_canvas, scene, 3, 60))
    first_layer = tool.paths_layer
    copy = tmp_path / "other"
    shutil.copytree(scene.folder, copy)
    other = add_costmap(copy / "costmap.tif", name="costmap 2")
    tool.set_costmap(other)
    tool.cancel()
    click(tool, canvas, screen(canvas, to_canvas, scene, 40, 4))
    assert tool.markers is not None and tool.markers.numberOfVertices() == 1
    click(tool, canvas, screen(canvas, to_canvas, scene, 5, 58))
    assert tool.paths_layer is not first_layer
    assert "costmap 2" in tool.paths_layer.name()
    assert len(list(first_layer.getFeatures())) == 1


def _costmap_variant(scene, folder, prompt: str, road_cost: float):
    """The scene's costmap with another road cost, as a re-prompted costmap layer."""
    import shutil

    import rasterio

    shutil.copytree(scene.folder, folder)
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
    click(tool, canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(tool, canvas, screen(canvas, to_canvas, scene, 3, 60))
    first_layer = tool.paths_layer
    (first,) = features(tool)
    avoid_roads = _costmap_variant(scene, tmp_path / "avoid", "avoid the roads", 0.9)
    tool.set_costmap(avoid_roads)
    second_layer = tool.paths_layer
    assert second_layer is not None and second_layer is not first_layer
    assert second_layer.name() == "path — avoid the roads"
    (second,) = list(second_layer.getFeatures())
    assert second["total_cost"] > first["total_cost"]  # the roads it used cost more now
    ends = [
        tool.session().grid.world_to_pixel(p.x(), p.y())
        for p in (second.geometry().asPolyline()[0], second.geometry().asPolyline()[-1])
    ]
    assert ends == [(44, 2), (3, 60)]
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
    click(tool, canvas, screen(canvas, to_canvas, scene, 44, 2))
    click(tool, canvas, screen(canvas, to_canvas, scene, 3, 60))
    (before,) = features(tool)
    crossed = {tool.session().grid.world_to_pixel(p.x(), p.y()) for p in before.geometry().asPolyline()}
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
    route = {tool.session().grid.world_to_pixel(p.x(), p.y()) for p in after.geometry().asPolyline()}
    assert not route & walled
    assert scene.costmap.exists() and tool.session().base.cost[row, col] != np.inf  # file untouched
    layer.rollBack()  # the edit is undone: the original route comes back
    (restored,) = features(tool)
    assert restored["total_cost"] == pytest.approx(before["total_cost"])


def test_a_distance_rule_that_cannot_be_met_is_planned_and_said(tmp_path) -> None:
    """The map tool plans as `overseec plan` does: into a keep-out zone only when it must."""
    import rasterio
    from rasterio.transform import from_origin

    from overseec_qgis.maptool import CostmapSession

    profile = dict(
        driver="GTiff",
        width=20,
        height=20,
        count=1,
        crs="EPSG:32633",
        transform=from_origin(500000.0, 4000000.0, 1.0, 1.0),
    )
    with rasterio.open(tmp_path / "costmap.tif", "w", dtype="float32", **profile) as ds:
        ds.write(np.full((1, 20, 20), 0.5, np.float32))
    flags = np.zeros((1, 20, 20), np.uint8)
    flags[0, :, 10] = 2  # a keep-out wall across the whole map
    with rasterio.open(tmp_path / "lethal.tif", "w", dtype="uint8", **profile) as ds:
        ds.write(flags)
        ds.update_tags(OVERSEEC_COSTMAP_FILE="costmap.tif")
    session = CostmapSession(str(tmp_path / "costmap.tif"), QgsCoordinateReferenceSystem("EPSG:32633"))
    result = session.plan([(500002.5, 3999989.5), (500017.5, 3999989.5)], "exact")
    assert result.length_m == pytest.approx(15.0) and "cannot be met" in result.notes[0]
