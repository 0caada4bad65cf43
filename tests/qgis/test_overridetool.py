"""The override tool and the overrides layer: presets the core accepts, polygons drawn with mouse
and keys as one undo step each, the style by kind, and Build costmap applying unsaved edits."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from qgis.core import QgsFeature, QgsGeometry, QgsPointXY, QgsProject, QgsRectangle
from qgis.gui import QgsMapMouseEvent
from qgis.PyQt.QtCore import QEvent, QPoint, Qt
from qgis.PyQt.QtGui import QKeyEvent
from qgis.PyQt.QtWidgets import QPushButton

from overseec_core import runfiles
from overseec_core.synthesize.overrides import KINDS, LETHAL_COST, PREFER_COST, classify
from overseec_qgis import overridetool
from overseec_qgis.override_layer import open_overrides
from overseec_qgis.overridetool import (
    COST,
    LETHAL,
    PREFER,
    OverridePreset,
    OverrideTool,
    PresetWidget,
    write_overrides_snapshot,
)

from .conftest import wait_until
from .test_dock import _add_sample_layers, run_and_wait, set_options
from .test_maptool import show_canvas

pytestmark = pytest.mark.qgis

PRESETS = (OverridePreset(LETHAL), OverridePreset(PREFER), OverridePreset(COST, 0.8), OverridePreset(COST, 0.15))


# -- presets ---------------------------------------------------------------------------------


def _cost(preset: OverridePreset) -> float:
    """The cost the core gives cells under a polygon with this preset."""
    return {LETHAL: LETHAL_COST, PREFER: PREFER_COST}.get(preset.kind, preset.cost)


def test_the_tools_kinds_are_the_cores() -> None:
    """The adapter spells the field names once (override_layer.OVERRIDE_FIELDS, light to import in
    QGIS); they are exactly the kinds `--override` reads, in the core's order."""
    assert overridetool.KINDS == KINDS


@pytest.mark.parametrize("preset", PRESETS, ids=lambda p: p.describe())
def test_each_preset_sets_exactly_the_fields_the_core_reads(preset: OverridePreset) -> None:
    """The attributes a preset writes are what `--override` classifies as that kind and cost."""
    attrs = preset.attributes()
    assert set(attrs) == set(KINDS)
    assert classify(attrs) == (preset.kind, _cost(preset))


def test_a_preset_outside_the_scale_is_refused() -> None:
    with pytest.raises(ValueError, match="between 0 and 1"):
        OverridePreset(COST, 1.5)
    with pytest.raises(ValueError, match="one of"):
        OverridePreset("avoid")


def test_the_preset_widget_sets_the_tools_preset(qgis_canvas) -> None:
    """Choosing a kind or moving the cost slider gives the tool that preset."""
    widget = PresetWidget()
    tool = OverrideTool(qgis_canvas)
    widget.changed.connect(tool.set_preset)
    widget.buttons[PREFER].setChecked(True)
    assert tool.preset == OverridePreset(PREFER, widget.spin.value())
    widget.slider.setValue(30)  # moving the cost picks "Cost"
    assert tool.preset == OverridePreset(COST, 0.3) and widget.buttons[COST].isChecked()
    widget.spin.setValue(0.65)
    assert tool.preset == OverridePreset(COST, 0.65) and widget.slider.value() == 65
    widget.buttons[LETHAL].setChecked(True)
    assert tool.preset.kind == LETHAL


# -- drawing -------------------------------------------------------------------------------------


def _mouse(canvas, tool, xy, button=Qt.LeftButton, double=False) -> None:
    """A press and release (and a double click) at map coordinates, as the canvas delivers them."""
    s = canvas.getCoordinateTransform().transform(QgsPointXY(*xy))
    pos = QPoint(round(s.x()), round(s.y()))
    tool.canvasPressEvent(QgsMapMouseEvent(canvas, QEvent.MouseButtonPress, pos, button, button))
    tool.canvasReleaseEvent(QgsMapMouseEvent(canvas, QEvent.MouseButtonRelease, pos, button, Qt.NoButton))
    if double:
        tool.canvasDoubleClickEvent(QgsMapMouseEvent(canvas, QEvent.MouseButtonDblClick, pos, button, button))
        tool.canvasReleaseEvent(QgsMapMouseEvent(canvas, QEvent.MouseButtonRelease, pos, button, Qt.NoButton))


def _value(v):
    """A feature's attribute as Python (NULL -> None)."""
    return None if v is None or (hasattr(v, "isNull") and v.isNull()) else v


def _key(tool, key) -> QKeyEvent:
    e = QKeyEvent(QEvent.KeyPress, key, Qt.NoModifier)
    tool.keyPressEvent(e)
    return e


@pytest.fixture
def drawing(scene, qgis_canvas, qgis_parent, qgis_new_project):
    """The override tool on the scene's overrides layer, the canvas showing the scene."""
    from qgis.core import QgsRasterLayer

    costmap = QgsRasterLayer(str(scene.costmap), "costmap")
    QgsProject.instance().addMapLayer(costmap)
    opened = []

    def open_layer():
        opened.append(open_overrides(scene.folder))
        return opened[-1]

    show_canvas(qgis_canvas, qgis_parent)
    qgis_canvas.setDestinationCrs(costmap.crs())
    qgis_canvas.setExtent(costmap.extent())
    tool = OverrideTool(qgis_canvas, open_layer=open_layer)
    qgis_canvas.setMapTool(tool)
    yield tool, scene, opened
    qgis_canvas.unsetMapTool(tool)
    tool.clear()


def _square(scene, row, col, half=4):
    """Corners of a square of pixels around (row, col), in map coordinates."""
    return [scene.world(row + dr, col + dc) for dr, dc in ((-half, -half), (-half, half), (half, half), (half, -half))]


@pytest.mark.parametrize("preset", PRESETS, ids=lambda p: p.describe())
@pytest.mark.parametrize("finish", ["right click", "double click", "Enter"])
def test_the_tool_adds_each_preset_as_one_undo_step(drawing, preset, finish) -> None:
    tool, scene, opened = drawing
    qgis_canvas = tool.canvas
    tool.set_preset(preset)
    corners = _square(scene, 24, 20)
    for i, xy in enumerate(corners):
        _mouse(qgis_canvas, tool, xy, double=finish == "double click" and i == len(corners) - 1)
    if finish == "right click":
        _mouse(qgis_canvas, tool, corners[-1], button=Qt.RightButton)
    elif finish == "Enter":
        assert _key(tool, Qt.Key_Return).isAccepted()
    (layer,) = opened  # opened once, through open_layer (the dock's Draw overrides in QGIS)
    assert layer.isEditable() and layer.isModified()
    (feature,) = list(layer.getFeatures())
    values = {k: _value(feature[k]) for k in KINDS}
    assert values == preset.attributes()
    assert classify(values) == (preset.kind, _cost(preset))
    geom = feature.geometry()
    assert geom.type() == 2 and len(geom.asPolygon()[0]) == 5  # four corners, closed
    assert abs(geom.area() - (8 * scene.grid.transform.a) ** 2) < 0.5  # the square clicked
    assert not tool.points and tool.band.numberOfVertices() == 0  # ready for the next polygon
    assert layer.undoStack().count() == 1
    layer.undoStack().undo()
    assert layer.featureCount() == 0


def test_backspace_removes_a_vertex_and_esc_drops_the_polygon(drawing) -> None:
    tool, scene, opened = drawing
    corners = _square(scene, 20, 30)
    for xy in corners:
        _mouse(tool.canvas, tool, xy)
    _mouse(tool.canvas, tool, scene.world(40, 60))  # a stray click
    assert len(tool.points) == 5
    e = _key(tool, Qt.Key_Backspace)
    assert e.isAccepted() and len(tool.points) == 4  # not QGIS's "delete selected features"
    assert tool.band.numberOfVertices() >= 4
    _key(tool, Qt.Key_Escape)
    assert tool.points == [] and tool.band.numberOfVertices() == 0
    _key(tool, Qt.Key_Return)
    assert opened == []  # nothing drawn: nothing opened, nothing added


def test_too_few_vertices_or_a_crossing_polygon_say_why(drawing) -> None:
    tool, scene, opened = drawing
    said = []
    tool.failed.connect(said.append)
    for xy in _square(scene, 20, 30)[:2]:
        _mouse(tool.canvas, tool, xy)
    _key(tool, Qt.Key_Return)
    assert "three vertices" in said[-1] and len(tool.points) == 2
    a, b, c, d = _square(scene, 20, 30)
    tool.cancel()
    for xy in (a, c, b, d):  # a bow tie
        _mouse(tool.canvas, tool, xy)
    _key(tool, Qt.Key_Return)
    assert "crosses itself" in said[-1] and opened == []


def test_a_polygon_drawn_on_another_crs_lands_in_the_layers_crs(drawing) -> None:
    from qgis.core import QgsCoordinateReferenceSystem, QgsCoordinateTransform

    tool, scene, opened = drawing
    wgs84 = QgsCoordinateReferenceSystem("EPSG:4326")
    utm = QgsCoordinateReferenceSystem("EPSG:32633")
    to_wgs = QgsCoordinateTransform(utm, wgs84, QgsProject.instance())
    tool.canvas.setDestinationCrs(wgs84)
    tool.canvas.setExtent(to_wgs.transformBoundingBox(QgsRectangle(*scene.world(47, 0), *scene.world(0, 63))))
    corners = _square(scene, 24, 32)
    for xy in corners:
        p = to_wgs.transform(QgsPointXY(*xy))
        _mouse(tool.canvas, tool, (p.x(), p.y()))
    _key(tool, Qt.Key_Return)
    (feature,) = list(opened[0].getFeatures())
    assert opened[0].crs().authid() == "EPSG:32633"
    centre = feature.geometry().centroid().asPoint()
    x, y = scene.world(24, 32)
    assert abs(centre.x() - x) < 1.0 and abs(centre.y() - y) < 1.0  # within a few pixels' clicks


# -- the style --------------------------------------------------------------------------------


def _polygon(corners) -> QgsGeometry:
    ring = [QgsPointXY(*xy) for xy in corners]
    return QgsGeometry.fromPolygonXY([ring + ring[:1]])


def _overrides_with_each_kind(scene):
    """The scene's overrides layer with one feature per preset and one the core rejects, side by side."""
    layer = open_overrides(scene.folder)
    layer.startEditing()
    cases = [(p.attributes(), p) for p in PRESETS] + [
        ({k: None for k in KINDS}, None),
        ({"cost": 0.3, "lethal": 1}, None),
    ]
    centres = []
    for i, (attrs, _preset) in enumerate(cases):
        row, col = 8 + 30 * (i // 3), 10 + 20 * (i % 3)
        f = QgsFeature(layer.fields())
        f.setGeometry(_polygon(_square(scene, row, col, 6)))
        for k, v in attrs.items():
            f[k] = v
        assert layer.addFeature(f)
        centres.append(scene.world(row, col))
    assert layer.commitChanges()
    return layer, cases, centres


def test_the_style_has_a_rule_per_kind_matching_what_the_core_reads(scene, qgis_new_project) -> None:
    """Each feature is drawn by the rule of the kind `--override` gives it; features the core
    rejects (none or two kinds) fall to the grey 'not applied' rule."""
    from qgis.core import QgsExpressionContext, QgsExpressionContextUtils, QgsRenderContext

    layer, cases, _centres = _overrides_with_each_kind(scene)
    renderer = layer.renderer()
    assert renderer.type() == "RuleRenderer"
    ctx = QgsRenderContext()
    ctx.setExpressionContext(QgsExpressionContext(QgsExpressionContextUtils.globalProjectLayerScopes(layer)))
    renderer.startRender(ctx, layer.fields())
    labels = {}
    for f, (_attrs, preset) in zip(sorted(layer.getFeatures(), key=lambda f: f.id()), cases):
        ctx.expressionContext().setFeature(f)
        root = renderer.rootRule()
        (rule,) = [root.findRuleByKey(k) for k in renderer.legendKeysForFeature(f, ctx) if k != root.ruleKey()]
        labels[preset.describe() if preset else str(_attrs)] = rule.label()
    renderer.stopRender(ctx)
    assert labels["lethal (no-go)"] == "lethal (no-go)"
    assert labels["prefer"].startswith("prefer")
    assert labels["cost 0.8"] == "cost 0.8–1.0" and labels["cost 0.15"] == "cost 0.0–0.2"
    rejected = [v for k, v in labels.items() if k.startswith("{")]
    assert rejected and all(v.startswith("not applied") for v in rejected)


def _render(layer, extent, size=(320, 240)):
    from qgis.core import QgsMapRendererParallelJob, QgsMapSettings
    from qgis.PyQt.QtCore import QSize

    settings = QgsMapSettings()
    settings.setLayers([layer])
    settings.setDestinationCrs(layer.crs())
    settings.setExtent(extent)
    settings.setOutputSize(QSize(*size))
    settings.setBackgroundColor(Qt.white)
    job = QgsMapRendererParallelJob(settings)
    job.start()
    job.waitForFinished()
    return job.renderedImage(), settings


def mean_colour(image, centre, half=6) -> tuple[float, float, float]:
    """Mean (r, g, b) of a square of pixels around ``centre``."""
    px = [
        image.pixelColor(x, y)
        for x in range(centre[0] - half, centre[0] + half)
        for y in range(centre[1] - half, centre[1] + half)
    ]
    return tuple(sum(getattr(c, k)() for c in px) / len(px) for k in ("red", "green", "blue"))


def test_rendered_overrides_show_their_kind(scene, qgis_new_project) -> None:
    layer, cases, centres = _overrides_with_each_kind(scene)
    image, settings = _render(layer, layer.extent().buffered(2))
    image.save(str(Path(scene.folder) / "overrides-style.png"))
    colours = {}
    for (attrs, preset), xy in zip(cases, centres):
        p = settings.mapToPixel().transform(QgsPointXY(*xy))
        colours[preset.describe() if preset else str(attrs)] = mean_colour(image, (round(p.x()), round(p.y())))
    r, g, b = colours["lethal (no-go)"]
    assert r > g + 40 and r > b + 40 and r < 200, colours  # dark red
    r, g, b = colours["prefer"]
    assert g > r + 40 and g > b + 40, colours  # green
    hi, lo = colours["cost 0.8"], colours["cost 0.15"]
    assert hi[0] > hi[1] + 30 and lo[1] > lo[0] + 20, colours  # red-ish high cost, green-ish low
    for key in (k for k in colours if k.startswith("{")):
        r, g, b = colours[key]
        assert max(r, g, b) - min(r, g, b) < 50, colours  # grey: not applied


# -- Build costmap with unsaved edits -------------------------------------------------------------


@pytest.fixture
def dock(plugin, tmp_path):
    set_options(plugin, runs_dir=str(tmp_path / "runs"))
    return plugin.dock


def test_build_costmap_applies_an_unsaved_lethal_polygon(plugin, dock, qgis_canvas, qgis_parent) -> None:
    """A lethal polygon drawn with the override tool and never saved is in the next costmap:
    its cells are lethal and cost 1.0; the analyst's file and edit buffer stay as they were."""
    import numpy as np
    import rasterio
    from rasterio.windows import from_bounds

    _add_sample_layers(dock)
    dock.mission.program_edit.setPlainText('cost = where(M["road"], 0.1, 0.5)\n')
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    run_dir = dock.run.run_dir
    with rasterio.open(run_dir / runfiles.COSTMAP) as src:
        left, bottom, right, top = src.bounds
        box = (
            left + (right - left) * 0.4,
            bottom + (top - bottom) * 0.4,
            left + (right - left) * 0.6,
            bottom + (top - bottom) * 0.6,
        )
        window = from_bounds(*box, transform=src.transform).round_offsets().round_lengths()
        before = src.read(1, window=window)
    inner = window.height // 4, window.width // 4  # cells well inside the polygon
    assert np.nanmin(before[inner[0] : -inner[0], inner[1] : -inner[1]]) < 1.0  # not lethal yet

    plugin.preset_widget.buttons[LETHAL].setChecked(True)
    plugin.override_action.trigger()
    tool = plugin.override_tool
    assert qgis_canvas.mapTool() is tool and plugin.override_toolbar.isVisibleTo(plugin.iface.mainWindow())
    show_canvas(qgis_canvas, qgis_parent)
    # the layer opens, then turns editable, on the next turns of the event loop
    wait_until(lambda: tool.layer is not None and tool.layer.isEditable(), 10, "the overrides layer")
    qgis_canvas.setDestinationCrs(tool.layer.crs())
    qgis_canvas.setExtent(QgsRectangle(left, bottom, right, top))
    x0, y0, x1, y1 = box
    for xy in ((x0, y0), (x1, y0), (x1, y1), (x0, y1)):
        _mouse(qgis_canvas, tool, xy)
    _key(tool, Qt.Key_Return)
    layer = tool.layer
    assert layer.isModified() and layer.featureCount() == 1
    assert Path(layer.source().split("|")[0]) == run_dir / runfiles.OVERRIDES_LAYER

    held = []

    def click() -> None:  # the button's own work on the GUI thread, snapshot included
        t, cpu = time.monotonic(), time.thread_time()
        dock.runs.costmap_button.click()
        held.append((round((time.monotonic() - t) * 1000, 1), round((time.thread_time() - cpu) * 1000, 1)))

    assert run_and_wait(dock, click) == ("costmap", True)
    print("Build costmap with unsaved edits held the GUI thread (wall ms, CPU ms):", held[0])
    assert held[0][1] <= 100
    with rasterio.open(run_dir / "costmap-2.tif") as src:
        after = src.read(1, window=window)
        tags = src.tags()
    with rasterio.open(run_dir / "costmap-2.lethal.tif") as src:
        lethal = src.read(1, window=window)
    core = (slice(inner[0], -inner[0]), slice(inner[1], -inner[1]))
    assert (lethal[core] == 1).all() and (after[core] == 1.0).all()
    assert "costmap-2-overrides.gpkg" in tags.get("OVERSEEC_OVERRIDES", "")
    # the analyst's edits are still theirs to save or roll back: file untouched, undo intact
    assert layer.isModified() and layer.isEditable() and layer.undoStack().count() == 1
    saved = QgsProject.instance().mapLayer(layer.id()).dataProvider().featureCount()
    assert saved == 0


def test_a_snapshot_that_cannot_be_written_says_why(scene, qgis_new_project, tmp_path) -> None:
    layer = open_overrides(scene.folder)
    layer.startEditing()
    f = QgsFeature(layer.fields())
    f.setGeometry(_polygon(_square(scene, 20, 20)))
    f["lethal"] = 1
    assert layer.addFeature(f)
    with pytest.raises(OSError, match="cannot write the unsaved override edits"):
        write_overrides_snapshot(layer, tmp_path / "no such folder" / "x.gpkg")
    assert write_overrides_snapshot(layer, tmp_path / "x.gpkg") == tmp_path / "x.gpkg"
    layer.rollBack()
    assert write_overrides_snapshot(layer, tmp_path / "empty.gpkg") is None  # nothing to apply


def test_the_override_action_without_a_costmap_turns_itself_off_and_says_why(plugin, qgis_iface, qgis_canvas) -> None:
    from qgis.core import Qgis

    plugin.override_action.trigger()
    wait_until(lambda: not plugin.override_action.isChecked(), 10, "the action to turn off")
    assert qgis_canvas.mapTool() is not plugin.override_tool
    assert plugin.dock.runs.status_label.text().startswith("overrides: no costmap layer")
    assert any("no costmap layer" in m for m in qgis_iface.messageBar().get_messages(Qgis.Critical))


def test_the_docks_draw_overrides_button_starts_the_override_tool(plugin, scene, qgis_canvas) -> None:
    from qgis.core import QgsRasterLayer

    QgsProject.instance().addMapLayer(QgsRasterLayer(str(scene.costmap), "costmap"))
    plugin.dock.runs.overrides_button.click()
    tool = plugin.override_tool
    assert qgis_canvas.mapTool() is tool and plugin.override_action.isChecked()
    assert tool.layer is plugin.map_tool.overrides_layer and tool.layer.isEditable()
    assert Path(tool.layer.source().split("|")[0]) == scene.folder / runfiles.OVERRIDES_LAYER
    plugin.dock.runs.overrides_button.click()  # again: the same layer, nothing opened twice
    overrides = [
        lyr for lyr in QgsProject.instance().mapLayers().values() if lyr.customProperty("overseec/role") == "overrides"
    ]
    assert overrides == [tool.layer]


def _unsaved_lethal(dock):
    """A costmap built by the dock, then its overrides layer open with an unsaved lethal polygon."""
    _add_sample_layers(dock)
    dock.mission.program_edit.setPlainText('cost = where(M["road"], 0.1, 0.5)\n')
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    layer = dock.runs.edit_overrides()
    e = dock.runs.map_tool.costmap_layer.extent()
    f = QgsFeature(layer.fields())
    f.setGeometry(
        QgsGeometry.fromRect(
            QgsRectangle(e.center().x() - 20, e.center().y() - 20, e.center().x() + 20, e.center().y() + 20)
        )
    )
    f["lethal"] = 1
    assert layer.addFeature(f) and layer.isModified()
    return layer


def test_unsaved_edits_that_cannot_be_written_stop_the_costmap(dock, monkeypatch) -> None:
    """The costmap is never built without the analyst's edits: a snapshot that cannot be
    written raises a one-line OSError instead of falling back to the saved file."""
    import overseec_qgis.overridetool as overridetool

    _unsaved_lethal(dock)

    def refuse(layer, path):
        raise OSError(f"cannot write the unsaved override edits of {layer.name()} to {path}: disk full")

    monkeypatch.setattr(overridetool, "write_overrides_snapshot", refuse)
    with pytest.raises(OSError, match="disk full") as info:
        dock.runs._run_overrides(dock.run.run_dir)
    assert "\n" not in str(info.value)


def test_build_costmap_fails_with_one_line_when_the_edits_cannot_be_written(dock, monkeypatch) -> None:
    import overseec_qgis.overridetool as overridetool

    _unsaved_lethal(dock)
    monkeypatch.setattr(
        overridetool, "write_overrides_snapshot", lambda layer, path: (_ for _ in ()).throw(OSError("disk full"))
    )
    started = []
    dock.slot.busy_changed.connect(started.append)
    dock.runs.build_costmap()  # as the button does (an exception escaping a click aborts PyQt)
    assert started == [] and dock.runs.status_label.text() == "costmap: disk full"


# -- overrides belong to the project; one bad feature never blocks (issue 32 items 1-2) ----------


def _lethal_cells(path: Path, extent: QgsRectangle):
    """Costmap values and lethal flags well inside ``extent`` (the polygon's box)."""
    import rasterio
    from rasterio.windows import from_bounds

    e = extent
    inner = (e.xMinimum() + 5, e.yMinimum() + 5, e.xMaximum() - 5, e.yMaximum() - 5)
    with rasterio.open(path) as src:
        window = from_bounds(*inner, transform=src.transform).round_offsets().round_lengths()
        cost = src.read(1, window=window)
        sidecar = src.tags()["OVERSEEC_LETHAL_FILE"]  # the lethal sidecar the costmap names
    with rasterio.open(path.parent / sidecar) as src:
        lethal = src.read(1, window=window)
    return cost, lethal


def test_a_lethal_polygon_applies_whatever_run_folder_is_current(dock) -> None:
    """Reopening a project or a refused Segment makes a new, empty run folder current; the
    next costmap still applies the lethal polygon drawn on the map (it read 0.0 there before)."""
    layer = _unsaved_lethal(dock)
    assert layer.commitChanges()  # saved in the first run's overrides.gpkg
    box = next(layer.getFeatures()).geometry().boundingBox()
    first = dock.run.run_dir
    dock.run.ensure_run_dir(dock.imagery.layer_combo.currentLayer().source(), new=True)  # what Segment does
    assert dock.run.run_dir != first and not (dock.run.run_dir / runfiles.OVERRIDES_LAYER).exists()
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    built = sorted(dock.run.run_dir.glob("costmap*.tif"))
    cost, lethal = _lethal_cells([p for p in built if "lethal" not in p.name][-1], box)
    assert (lethal == 1).all() and (cost == 1.0).all()


def test_an_attribute_less_polygon_is_skipped_with_one_warning_naming_it(dock, qgis_iface) -> None:
    """QGIS's own Add Polygon with the form left all NULL: the costmap is built from the other
    polygons, and one warning names the feature as the attribute table shows it."""
    from qgis.core import Qgis

    layer = _unsaved_lethal(dock)
    bad = QgsFeature(layer.fields())  # every attribute NULL
    e = dock.runs.map_tool.costmap_layer.extent()
    bad.setGeometry(
        QgsGeometry.fromRect(QgsRectangle(e.xMinimum(), e.yMinimum(), e.xMinimum() + 30, e.yMinimum() + 30))
    )
    assert layer.addFeature(bad) and layer.commitChanges()
    box = next(f for f in layer.getFeatures() if f["lethal"] == 1).geometry().boundingBox()
    applied = dock.runs._run_overrides(dock.run.run_dir)
    assert len(applied) == 1 and applied[0].name == "costmap-2-overrides.gpkg"  # a snapshot without it
    items = [i for i in qgis_iface.messageBar().items() if "skipped" in i.text()]
    assert len(items) == 1 and items[0].level() == Qgis.Warning
    assert "feature 2 has none of cost, lethal, prefer" in items[0].text()
    (button,) = [b for b in items[0].findChildren(QPushButton) if b.text() == "Zoom to feature"]
    button.click()  # selects it (and zooms to it, and opens its row in the attribute table)
    assert layer.selectedFeatureIds() == [2]
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    cost, lethal = _lethal_cells(dock.run.run_dir / "costmap-2.tif", box)
    assert (lethal == 1).all() and (cost == 1.0).all()


def test_the_map_tool_plans_past_an_attribute_less_polygon(scene, qgis_new_project, tmp_path) -> None:
    """The map tool's snapshot holds only the features the core accepts; a layer with none
    applies nothing (and stops nothing)."""
    from overseec_qgis.planfiles import OverridesSnapshot

    layer = open_overrides(scene.folder)
    layer.startEditing()
    for attrs in ({}, {"lethal": 1}, {"cost": 0.3, "lethal": 1}):
        f = QgsFeature(layer.fields())
        f.setGeometry(_polygon(_square(scene, 20, 20)))
        for k, v in attrs.items():
            f[k] = v
        assert layer.addFeature(f)
    snap = OverridesSnapshot(layer, tmp_path / "o.gpkg", QgsProject.instance().transformContext())
    assert len(snap.features) == 1
    assert [s.why.split(";")[0] for s in snap.skipped] == [
        "has none of cost, lethal, prefer",
        "has both cost and lethal",
    ]
    assert all(
        s.describe().startswith("overrides (cost 0-1 / prefer / lethal): a new (unsaved) feature") for s in snap.skipped
    )
    snap.ensure_written()
    from overseec_core.io.read import read_grid
    from overseec_core.synthesize.overrides import read_overrides

    assert len(read_overrides(tmp_path / "o.gpkg", read_grid(scene.costmap))) == 1  # the core takes the file


def test_the_overrides_form_starts_lethal_and_refuses_an_invalid_feature(scene, qgis_new_project) -> None:
    from qgis.core import QgsVectorLayerUtils

    layer = open_overrides(scene.folder)
    layer.startEditing()
    f = QgsVectorLayerUtils.createFeature(layer, _polygon(_square(scene, 20, 20)))  # what Add Polygon makes
    assert f["lethal"] == 1 and classify({k: f[k] for k in KINDS}) == ("lethal", LETHAL_COST)
    ok, _ = QgsVectorLayerUtils.validateAttribute(layer, f, layer.fields().indexOf("lethal"))
    assert ok
    f["cost"] = 0.4  # cost and lethal both: the form says what to fix
    ok, errors = QgsVectorLayerUtils.validateAttribute(layer, f, layer.fields().indexOf("lethal"))
    assert not ok and any("exactly one" in e for e in errors)
