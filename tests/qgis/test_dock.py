"""The dock drives real runs: interpret, edit, costmap on the sample scene, plan, segment, fail.

The sample scene's class raster stands in for masks (no model needed) for the costmap; the
worker-process path runs the real `overseec` CLI with a tiny random CLIPSeg.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from qgis.core import Qgis, QgsApplication, QgsFeature, QgsGeometry, QgsProject, QgsRasterLayer, QgsRectangle, QgsTask

from .conftest import SAMPLE, wait_until

pytestmark = pytest.mark.qgis

META = json.loads((SAMPLE / "sample.json").read_text())


def run_and_wait(dock, start, timeout_s: float = 300.0) -> tuple[str, bool]:
    """Press a dock button and wait for its task to report back (failures print the status).

    The wait ends on the dock's ``task_done`` signal, success or failure; the timeout only guards
    against a hang, so it is generous: a worker subprocess on a loaded two-core CI machine has
    taken over 120 s to start and finish a stage."""
    outcome = []
    logged = []
    QgsApplication.messageLog().messageReceived.connect(lambda msg, tag, level: logged.append(msg))
    dock.task_done.connect(lambda stage, ok: outcome.append((stage, ok)))
    start()
    try:
        wait_until(lambda: outcome, timeout_s, "the dock's task")
    except AssertionError:
        print(_stuck(dock), "\n".join(logged))
        raise
    assert dock.slot.task is None and dock.runs.cancel_button.isEnabled() is False
    if not outcome[0][1]:
        print("dock status:", dock.runs.status_label.text(), "\n".join(logged))
    return outcome[0]


def _stuck(dock) -> str:
    """What a wait that timed out was stuck behind: the dock's status, its job and names task,
    and every task the task manager holds (a queued task waits for a free thread)."""
    manager = QgsApplication.taskManager()
    held = [f"{t.description()!r} status={QgsTask.status(t)} progress={t.progress():.0f}" for t in manager.tasks()]
    return (
        f"dock status: {dock.runs.status_label.text()!r}; slot task: {dock.slot.task!r}; "
        f"names task: {dock.mission.names_task!r}; manager tasks ({manager.countActiveTasks()} active): "
        + ("; ".join(held) or "none")
    )


@pytest.fixture
def dock(plugin, tmp_path):
    """The plugin's dock with its runs folder set on the options page, as a user sets it."""
    set_options(plugin, runs_dir=str(tmp_path / "runs"))
    return plugin.dock


def set_options(plugin, **values):
    """Fill the real Settings › Options page the plugin registered, and press OK (apply)."""
    page = plugin.options_factory.createWidget(None)
    widgets = {
        "runs_dir": page.runs_widget.setFilePath,
        "venv": page.venv_widget.setFilePath,
        "worker_path": page.worker_widget.setFilePath,
        "install_source": page.source_widget.setFilePath,
        "clipseg_model": page.clipseg_edit.setText,
        "sam_model": page.sam_edit.setText,
        "device": page.device_combo.setCurrentText,
        "llm_endpoint": page.endpoint_edit.setText,
        "llm_model": page.model_edit.setText,
        "llm_authcfg": page.auth_select.setConfigId,
    }
    for key, value in values.items():
        widgets[key](value)
    page.apply()
    page.deleteLater()


def _messages(iface, level):
    return list(iface.messageBar().get_messages(level))


def test_interpret_fills_the_table_and_program_errors_point_at_their_line(dock) -> None:
    dock.mission.offline_check.setChecked(True)
    dock.mission.prompt_edit.setPlainText(META["prompt"])
    assert run_and_wait(dock, dock.mission.interpret_button.click) == ("interpret", True)
    names = [r["name"] for r in dock.mission.entity_rows()]
    assert {"road", "trail", "grass", "baseball field"} <= set(names)
    geometry = {r["name"]: r["geometry"] for r in dock.mission.entity_rows()}
    assert geometry["road"] == "linear" and geometry["grass"] == "areal"
    assert dock.mission.validate_program() and dock.mission.program_status.text().startswith("✓")
    # an error on line 3 is reported with its line and marked there
    dock.mission.program_edit.setPlainText('a = M["road"]\nb = a\ncost = where(a, 0.1, nope)\n')
    assert not dock.mission.validate_program()
    assert "line 3" in dock.mission.program_status.text() and "nope" in dock.mission.program_status.text()
    (sel,) = dock.mission.program_edit.extraSelections()
    assert sel.cursor.blockNumber() == 2
    # an entity the layers do not have is an error too
    dock.mission.program_edit.setPlainText('cost = where(M["lava"], 1.0, 0.1)\n')
    assert not dock.mission.validate_program() and "lava" in dock.mission.program_status.text()


def _costmap_of(group):
    """The costmap layer of a dock costmap group (the lethal layer lies above it)."""
    (layer,) = [n.layer() for n in group.findLayers() if n.layer().customProperty("overseec/role") == "costmap"]
    return layer


def _add_sample_layers(dock):
    project = QgsProject.instance()
    image = QgsRasterLayer(str(SAMPLE / "sample.tif"), "sample")
    labels = QgsRasterLayer(str(SAMPLE / "sample_labels.tif"), "sample labels")
    assert image.isValid() and labels.isValid()
    project.addMapLayers([image, labels])
    dock.imagery.layer_combo.setLayer(image)
    dock.mission.labels_combo.setLayer(labels)
    dock.mission.classes_widget.setFilePath(str(SAMPLE / "classes.json"))
    wait_for_info(dock)
    wait_until(dock.mission.names_known, 60, "the entity layers' names (read in a task)")
    return image, labels


def wait_for_info(dock) -> str:
    """The image description, once the worker's reading check (a background task) is back."""
    wait_until(lambda: dock.imagery.info_task is None, 60, "the image reading check")
    return dock.imagery.info_view.toPlainText()


def test_costmap_from_the_sample_scene_then_plan_on_it(plugin, dock, qgis_iface, qgis_canvas, qgis_parent) -> None:
    from qgis.core import QgsPointXY
    from qgis.gui import QgsMapMouseEvent
    from qgis.PyQt.QtCore import QEvent, QPoint, Qt

    from overseec_core.plan.stage import PlanOptions, run_plan

    from .test_maptool import show_canvas

    image, _labels = _add_sample_layers(dock)
    assert (
        "1024 x 1024 px" in dock.imagery.info_view.toPlainText()
        and "EPSG:32633" in dock.imagery.info_view.toPlainText()
    )
    dock.mission.prompt_edit.setPlainText(META["prompt"])
    assert run_and_wait(dock, dock.mission.interpret_button.click) == ("interpret", True)
    assert dock.mission.validate_program()
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    root = QgsProject.instance().layerTreeRoot()
    group = root.children()[0]
    assert group.name().startswith("overseec costmap:")
    lethal_node, node = group.findLayers()
    costmap = node.layer()
    assert Path(costmap.source()).name == "costmap.tif" and costmap.crs() == image.crs()
    assert costmap.renderer().type() == "singlebandpseudocolor"
    # lethal cells are 1.0 in the costmap, like the most avoided ground: the sidecar above it
    # draws them (1) and keep-out zones (2) in colours far from anything the ramp shows
    lethal = lethal_node.layer()
    assert Path(lethal.source()) == Path(costmap.source()).with_name("lethal.tif")
    assert lethal.customProperty("overseec/role") == "lethal"
    palette = {int(c.value): c.color for c in lethal.renderer().classes()}
    assert palette[0].alpha() == 0 and palette[1].alpha() == 255 and palette[2].alpha() == 255
    ok, r, g, b, _a = costmap.renderer().shader().shade(0.95)
    assert ok
    for value in (1, 2):
        c = palette[value]
        assert abs(c.red() - r) + abs(c.green() - g) + abs(c.blue() - b) > 150, (value, c.name(), (r, g, b))
    assert META["prompt"] in costmap.metadata().abstract()
    assert "cost =" in costmap.metadata().abstract()
    assert plugin.map_tool.costmap_layer is costmap

    # plan with the map tool, exact mode, clicking the sample's start and goal
    dock.parameters.mode_combo.setCurrentText("exact")
    plugin.plan_action.trigger()
    assert qgis_canvas.mapTool() is plugin.map_tool and dock.runs.plan_button.isChecked()
    show_canvas(qgis_canvas, qgis_parent)
    qgis_canvas.setDestinationCrs(costmap.crs())
    qgis_canvas.setExtent(costmap.extent())
    tool = plugin.map_tool
    for x, y in (META["start"], META["goal"]):
        s = qgis_canvas.getCoordinateTransform().transform(QgsPointXY(x, y))
        pos = QPoint(round(s.x()), round(s.y()))
        for kind in (QEvent.MouseButtonPress, QEvent.MouseButtonRelease):
            e = QgsMapMouseEvent(
                qgis_canvas, kind, pos, Qt.LeftButton, Qt.LeftButton if kind == QEvent.MouseButtonPress else Qt.NoButton
            )
            (tool.canvasPressEvent if kind == QEvent.MouseButtonPress else tool.canvasReleaseEvent)(e)
    assert tool.wait()  # the worker plans in the background
    (feature,) = list(tool.paths_layer.getFeatures())
    clicked = [
        tool.session().grid.world_to_pixel(p.x(), p.y())
        for p in (feature.geometry().asPolyline()[0], feature.geometry().asPolyline()[-1])
    ]
    # the CLI's plan stage between the same pixels' centres gives the same path
    centres = [tool.session().grid.pixel_to_world(r, c) for r, c in clicked]
    cli = run_plan(
        PlanOptions(
            costmap=Path(costmap.source()),
            points=tuple(centres),
            out=Path(costmap.source()).with_name("cli_path.geojson"),
            mode="exact",
        )
    )
    assert feature["total_cost"] == pytest.approx(cli.result.cost)
    assert feature["length_m"] == pytest.approx(cli.result.length_m)
    assert feature["mode"] == "exact"
    # saved, the paths become a file layer the project keeps
    saved = dock.runs.save_paths()
    assert saved == Path(costmap.source()).with_name("paths-1.geojson")
    wait_until(lambda: dock.runs.save_task is None, 30, "the save task")  # written and opened in a task
    (saved_layer,) = [
        lyr for lyr in QgsProject.instance().mapLayers().values() if lyr.source().split("|")[0] == str(saved)
    ]
    assert saved_layer.name().startswith("saved paths — ") and saved_layer.featureCount() == 1
    assert next(saved_layer.getFeatures())["total_cost"] == pytest.approx(cli.result.cost)

    # draw overrides: overrides.gpkg beside the costmap, editable; a lethal polygon over the
    # route's middle re-plans it around the polygon at once
    first_paths = tool.paths_layer
    overrides = dock.runs.edit_overrides()
    assert overrides.isEditable() and overrides.source().split("|")[0] == str(
        Path(costmap.source()).with_name("overrides.gpkg")
    )
    line = feature.geometry().asPolyline()
    mid = line[len(line) // 2]
    f = QgsFeature(overrides.fields())
    f.setGeometry(QgsGeometry.fromRect(QgsRectangle(mid.x() - 6, mid.y() - 6, mid.x() + 6, mid.y() + 6)))
    f["lethal"] = 1
    assert overrides.addFeature(f)
    assert tool.wait()  # one re-plan once the edits settle
    (rerouted,) = list(first_paths.getFeatures())
    assert rerouted["total_cost"] > feature["total_cost"]
    assert all(abs(p.x() - mid.x()) > 5 or abs(p.y() - mid.y()) > 5 for p in rerouted.geometry().asPolyline())
    assert overrides.commitChanges() and overrides.featureCount() == 1
    overrides.startEditing()
    assert overrides.deleteFeature(next(overrides.getFeatures()).id())
    assert tool.wait()
    (restored,) = list(first_paths.getFeatures())
    assert restored["total_cost"] == pytest.approx(feature["total_cost"])
    overrides.rollBack()
    tool.set_overrides_layer(None)

    # re-prompt: a new program re-uses the layers and adds costmap-2 beside the first one; the
    # route is planned again on it, into its own layer beside the first route
    first_source = costmap.source()
    dock.mission.program_edit.setPlainText('cost = where(M["road"], 0.05, where(M["grass"], 0.9, 1.0))\n')
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    (second,) = [
        layer for layer in QgsProject.instance().mapLayers().values() if Path(layer.source()).name == "costmap-2.tif"
    ]
    assert costmap.isValid() and costmap.source() == first_source  # the earlier layer is intact
    assert plugin.map_tool.costmap_layer is second
    assert tool.wait()
    assert tool.paths_layer is not first_paths and tool.paths_layer.featureCount() == 1
    (again,) = list(tool.paths_layer.getFeatures())
    assert again["total_cost"] != pytest.approx(feature["total_cost"])
    assert first_paths.featureCount() == 1


def test_a_failed_costmap_keeps_earlier_layers_and_says_why(dock, qgis_iface, tmp_path) -> None:
    _add_sample_layers(dock)
    dock.mission.program_edit.setPlainText('cost = where(M["road"], 0.1, 0.5)\n')
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    layers_before = set(QgsProject.instance().mapLayers())
    qgis_iface.messageBar().clear_messages()
    logged = []
    QgsApplication.messageLog().messageReceived.connect(lambda msg, tag, level: logged.append((tag, msg)))
    # make the run fail inside the task: a folder sits where the lethal sidecar must go
    (dock.run.run_dir / "costmap-2.lethal.tif").mkdir()
    outcome = run_and_wait(dock, dock.runs.costmap_button.click)
    assert outcome == ("costmap", False)
    (critical,) = _messages(qgis_iface, Qgis.Critical)
    assert "costmap-2.lethal.tif" in critical and len(critical.splitlines()) == 1
    assert any(tag == "overseec" for tag, _ in logged)
    assert set(QgsProject.instance().mapLayers()) == layers_before


def test_invalid_program_never_starts_a_task(dock, qgis_iface) -> None:
    _add_sample_layers(dock)
    qgis_iface.messageBar().clear_messages()
    dock.mission.program_edit.setPlainText("cost = 1 +\n")
    dock.runs.build_costmap()
    assert dock.slot.task is None
    (critical,) = _messages(qgis_iface, Qgis.Critical)
    assert "line 1" in critical


@pytest.mark.models
def test_segment_in_the_worker_adds_entity_layers_then_costmap_from_masks(
    plugin, dock, scene, tiny_clipseg, qgis_iface
) -> None:
    image = QgsRasterLayer(str(scene.image), "small image")
    QgsProject.instance().addMapLayer(image)
    dock.imagery.layer_combo.setLayer(image)
    dock.mission.entities_table.setRowCount(0)
    for name, geometry in (("road", "linear"), ("grass", "areal")):
        dock.mission.add_entity_row(name, geometry, None, ())
    set_options(plugin, clipseg_model=str(tiny_clipseg), device="cpu")
    dock.parameters.refine_check.setChecked(False)
    dock.parameters.tile_spin.setValue(64)
    dock.parameters.overlap_spin.setValue(8)
    progress = []
    dock.runs.progress_bar.valueChanged.connect(progress.append)
    assert run_and_wait(dock, dock.runs.segment_button.click) == ("segment", True)
    assert progress and max(progress) == 100
    group = QgsProject.instance().layerTreeRoot().children()[0]
    names = [n.layer().name() for n in group.findLayers()]
    assert names == ["road mask", "grass mask", "road probability", "grass probability"]
    assert all(n.layer().crs().authid() == "EPSG:32633" for n in group.findLayers())
    assert "masks.tif" in dock.mission.masks_label.text()
    # the costmap now reads the run's masks
    dock.mission.labels_combo.setLayer(None)
    dock.mission.program_edit.setPlainText('cost = where(M["road"], 0.1, 0.6)\n')
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    costmap = _costmap_of(QgsProject.instance().layerTreeRoot().children()[0])
    assert Path(costmap.source()).parent == dock.run.run_dir


@pytest.mark.models
def test_cancel_stops_the_worker_and_adds_nothing(plugin, dock, tiny_clipseg, qgis_iface) -> None:
    image = QgsRasterLayer(str(SAMPLE / "sample.tif"), "sample")
    QgsProject.instance().addMapLayer(image)
    dock.imagery.layer_combo.setLayer(image)
    dock.mission.entities_table.setRowCount(0)
    dock.mission.add_entity_row("road", "linear", None, ())
    set_options(plugin, clipseg_model=str(tiny_clipseg))
    dock.parameters.refine_check.setChecked(False)
    dock.parameters.tile_spin.setValue(64)
    dock.parameters.overlap_spin.setValue(0)
    dock.runs.progress_bar.valueChanged.connect(lambda v: v > 0 and dock.slot.cancel())
    layers_before = set(QgsProject.instance().mapLayers())
    qgis_iface.messageBar().clear_messages()
    assert run_and_wait(dock, dock.runs.segment_button.click) == ("segment", False)
    # the user's own cancel is information that goes away, not a sticky red error
    assert not _messages(qgis_iface, Qgis.Critical)
    assert "cancelled" in _messages(qgis_iface, Qgis.Info)[-1]
    assert set(QgsProject.instance().mapLayers()) == layers_before
    assert not (dock.run.run_dir / "masks.tif").exists()


def test_run_to_costmap_with_a_class_raster_keeps_the_users_program(dock) -> None:
    """Run all = the stage buttons in order; with a class raster no model runs, and an edited
    program (for the same prompt) is what the costmap uses."""
    _add_sample_layers(dock)
    dock.mission.prompt_edit.setPlainText(META["prompt"])
    assert run_and_wait(dock, dock.mission.interpret_button.click) == ("interpret", True)
    edited = 'cost = where(M["road"], 0.05, 0.7)\nlethal = M["water"]\n'
    dock.mission.program_edit.setPlainText(edited)
    done = []
    dock.run_done.connect(done.append)
    first_run = dock.run.run_dir
    dock.runs.run_button.click()
    wait_until(lambda: done, 120, "Run all")
    run_dir = Path(done[0])
    assert run_dir != first_run and run_dir == dock.run.run_dir
    assert (run_dir / "costmap.program.txt").read_text() == edited
    costmap = _costmap_of(QgsProject.instance().layerTreeRoot().children()[0])
    assert Path(costmap.source()) == run_dir / "costmap.tif"
    assert edited.strip() in costmap.metadata().abstract()
    # a new prompt is interpreted again before the costmap
    dock.mission.prompt_edit.setPlainText("prefer the trails, avoid the buildings")
    done.clear()
    dock.runs.run_button.click()
    wait_until(lambda: done, 120, "Run all")
    assert dock.mission.interpretation.prompt == "prefer the trails, avoid the buildings"
    assert "trail" in (Path(done[0]) / "costmap.program.txt").read_text()


def test_interpreting_with_a_class_raster_matches_names_and_applies_aliases(dock) -> None:
    """The program in the editor reads the class raster's layers: "lakes" and "houses" are found
    by the matching rules, "compound" only through the dock's alias."""
    _add_sample_layers(dock)
    dock.mission.offline_check.setChecked(True)
    dock.mission.prompt_edit.setPlainText("avoid the lakes and the houses, prefer the paths")
    assert run_and_wait(dock, dock.mission.interpret_button.click) == ("interpret", True)
    program = dock.mission.program_edit.toPlainText()
    assert 'M["water"]' in program or 'P["water"]' in program
    assert 'P["building"]' in program and 'P["trail"]' in program and "lake" not in program
    assert dock.mission.validate_program()
    dock.mission.prompt_edit.setPlainText("avoid the compound")
    dock.mission.aliases_edit.setText("compound=building")
    assert run_and_wait(dock, dock.mission.interpret_button.click) == ("interpret", True)
    assert 'P["building"]' in dock.mission.program_edit.toPlainText() and dock.mission.validate_program()


def _building_cells_of_the_newest_costmap() -> tuple[set, set]:
    """Costs and lethal-sidecar flags of the sample's building cells in the newest costmap group."""
    import numpy as np
    import rasterio

    group = QgsProject.instance().layerTreeRoot().children()[0]
    files = {n.layer().customProperty("overseec/role"): n.layer().source() for n in group.findLayers()}
    with (
        rasterio.open(SAMPLE / "sample_labels.tif") as labels,
        rasterio.open(files["costmap"]) as cost,
        rasterio.open(files["lethal"]) as lethal,
    ):
        building = labels.read(1) == 6
        costs = {round(float(c), 6) for c in np.unique(cost.read(1)[building])}
        return costs, set(np.unique(lethal.read(1)[building]).tolist())


def test_the_missions_priors_reach_the_costmap_and_stay_with_the_project(dock, tmp_path) -> None:
    """ "avoid the baseball field" leaves buildings unsaid: the built-in prior makes them an
    obstacle (1.0, keep-out 2); "No priors" leaves them neutral (Run all interprets again when the
    priors changed); a priors file replaces the table. The project keeps the mission's priors."""
    _add_sample_layers(dock)
    dock.mission.offline_check.setChecked(True)
    dock.mission.prompt_edit.setPlainText("avoid the baseball field")
    assert run_and_wait(dock, dock.mission.interpret_button.click) == ("interpret", True)
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    assert _building_cells_of_the_newest_costmap() == ({1.0}, {2})

    dock.mission.no_priors_check.setChecked(True)
    assert not dock.mission.priors_widget.isEnabled()
    done = []
    dock.run_done.connect(done.append)
    dock.runs.run_button.click()
    wait_until(lambda: done, 120, "Run all")
    assert dock.mission.interpretation_priors == dock.mission.priors() and dock.mission.priors().off
    assert _building_cells_of_the_newest_costmap() == ({0.5}, {0})

    table = tmp_path / "priors.json"
    table.write_text('{"building": 0.9}')
    dock.mission.no_priors_check.setChecked(False)
    dock.mission.priors_widget.setFilePath(str(table))
    assert dock.mission.priors_widget.isEnabled() and dock.mission.priors().cli() == [f"--priors={table}"]
    assert run_and_wait(dock, dock.mission.interpret_button.click) == ("interpret", True)
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    assert _building_cells_of_the_newest_costmap() == ({0.9}, {0})

    # saved with the project, cleared with it, back when it is opened again
    dock.mission.aliases_edit.setText("compound=building")
    project = QgsProject.instance()
    assert project.write(str(tmp_path / "mission.qgz"))
    project.clear()
    assert dock.mission.priors_widget.filePath() == "" and dock.mission.aliases_edit.text() == ""
    assert project.read(str(tmp_path / "mission.qgz"))
    assert dock.mission.priors_widget.filePath() == str(table) and not dock.mission.no_priors_check.isChecked()
    assert dock.mission.aliases_edit.text() == "compound=building"
    dock.mission.no_priors_check.setChecked(True)
    assert project.write()
    project.clear()
    assert project.read(str(tmp_path / "mission.qgz"))
    assert dock.mission.no_priors_check.isChecked() and dock.mission.priors().off


# ------------------------------------------------------------------------------------------------
# Runs that persist, overrides, messages, the environment
# ------------------------------------------------------------------------------------------------


def _layer_state(project) -> dict[str, tuple[str, str, str]]:
    """name -> (source, renderer type, role) of every layer of a project."""
    return {
        layer.name(): (layer.source(), layer.renderer().type(), layer.customProperty("overseec/role"))
        for layer in project.mapLayers().values()
    }


@pytest.mark.models
def test_a_saved_project_reopens_with_the_same_masks_costmap_and_run(
    plugin, scene, tiny_clipseg, qgis_iface, tmp_path
) -> None:
    """No runs folder set: runs go beside the saved project, every layer points into the run
    folder, and reopening the project shows the same layers and resumes the run."""
    dock = plugin.dock
    set_options(plugin, runs_dir="", clipseg_model=str(tiny_clipseg), device="cpu")
    project = QgsProject.instance()
    project_file = tmp_path / "mission" / "mission.qgz"
    project_file.parent.mkdir()
    assert project.write(str(project_file))
    image = QgsRasterLayer(str(scene.image), "small image")
    project.addMapLayer(image)
    dock.imagery.layer_combo.setLayer(image)
    dock.mission.entities_table.setRowCount(0)
    for name, geometry in (("road", "linear"), ("grass", "areal")):
        dock.mission.add_entity_row(name, geometry, None, ())
    dock.parameters.refine_check.setChecked(False)
    dock.parameters.tile_spin.setValue(64)
    dock.parameters.overlap_spin.setValue(8)
    assert run_and_wait(dock, dock.runs.segment_button.click) == ("segment", True)
    run_dir = dock.run.run_dir
    assert run_dir.parent == project_file.parent / "overseec-runs"
    dock.mission.program_edit.setPlainText('cost = where(M["road"], 0.1, 0.6)\n')
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    before = _layer_state(project)
    roles = {role for _source, _renderer, role in before.values()}
    assert {"mask", "probability", "costmap", "lethal"} <= roles
    for source, _renderer, role in before.values():
        if role:
            assert Path(source.split("|")[0]).parent == run_dir, source
    assert project.write()

    project.clear()
    assert dock.run.run_dir is None and not project.mapLayers()
    assert project.read(str(project_file))
    after = _layer_state(project)
    assert after == before
    assert all(layer.isValid() for layer in project.mapLayers().values())
    assert dock.run.run_dir == run_dir and "masks.tif" in dock.mission.masks_label.text()
    assert dock.imagery.image_path() == str(scene.image)
    # the dock carries on with the reopened run: a new costmap lands beside the first
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    assert (run_dir / "costmap-2.tif").is_file()


def test_an_unsaved_project_asks_for_the_runs_folder_once(plugin, qgis_iface, tmp_path) -> None:
    dock = plugin.dock
    set_options(plugin, runs_dir="")
    asked = []
    dock.run.ask_runs_folder = lambda: asked.append(1) or str(tmp_path / "chosen")
    first = dock.run.ensure_run_dir(str(SAMPLE / "sample.tif"), new=True)
    second = dock.run.ensure_run_dir(str(SAMPLE / "sample.tif"), new=True)
    assert asked == [1] and first.parent == second.parent == tmp_path / "chosen"
    # declined: a temporary folder, said so once as information (not an error)
    dock.run.session_runs = None
    dock.run.ask_runs_folder = lambda: ""
    qgis_iface.messageBar().clear_messages()
    temp = dock.run.ensure_run_dir(str(SAMPLE / "sample.tif"), new=True)
    assert temp.parent.name == "overseec-runs" and "temporary" in _messages(qgis_iface, Qgis.Info)[0]
    assert not _messages(qgis_iface, Qgis.Critical)


def test_build_costmap_applies_the_run_folders_overrides(dock) -> None:
    """Like Processing and `overseec costmap --override`: a lethal polygon drawn with Draw
    overrides is in the next costmap the dock builds."""
    import rasterio

    _add_sample_layers(dock)
    dock.mission.program_edit.setPlainText('cost = where(M["road"], 0.1, 0.5)\n')
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    overrides = dock.runs.edit_overrides()
    with rasterio.open(dock.run.run_dir / "costmap.tif") as src:
        left, bottom, right, top = src.bounds
        first_lethal = int((rasterio.open(dock.run.run_dir / "lethal.tif").read(1) == 1).sum())
    cx, cy = (left + right) / 2, (bottom + top) / 2
    f = QgsFeature(overrides.fields())
    f.setGeometry(QgsGeometry.fromRect(QgsRectangle(cx - 20, cy - 20, cx + 20, cy + 20)))
    f["lethal"] = 1
    assert overrides.addFeature(f) and overrides.commitChanges()
    dock.runs.map_tool.set_overrides_layer(None)
    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    with rasterio.open(dock.run.run_dir / "costmap-2.lethal.tif") as src:
        lethal = src.read(1)
    with rasterio.open(dock.run.run_dir / "costmap-2.tif") as src:
        tags = src.tags()
    assert int((lethal == 1).sum()) > first_lethal
    assert "overrides.gpkg" in tags.get("OVERSEEC_OVERRIDES", "")


def _fake_model(folder: Path, model_type: str) -> Path:
    folder.mkdir(parents=True)
    (folder / "config.json").write_text(json.dumps({"model_type": model_type}))
    (folder / "model.safetensors").write_bytes(b"")
    return folder


def _check_env(dock):
    reports = []
    dock.env_checked.connect(reports.append)
    dock.environment.check_environment()
    wait_until(lambda: reports, 120, "the environment check")
    return reports[0]


def _worker_without_weights(plugin, qgis_iface, tmp_path, monkeypatch):
    """The dock with the project venv as its worker and no model weights anywhere (an empty
    Hugging Face cache): (dock, message bar); skipped without the venv."""
    from .conftest import REPO

    worker = REPO / ".venv" / "bin" / "overseec"
    if not worker.exists():
        pytest.skip("no project venv")
    monkeypatch.setenv("HF_HOME", str(tmp_path / "empty-hf"))  # nothing cached
    set_options(plugin, worker_path=str(worker), clipseg_model="", sam_model="")
    return plugin.dock, qgis_iface.messageBar()


def test_environment_warning_names_the_weights_and_goes_away_once_fixed(
    plugin, qgis_iface, tmp_path, monkeypatch
) -> None:
    dock, bar = _worker_without_weights(plugin, qgis_iface, tmp_path, monkeypatch)
    report = _check_env(dock)
    assert report.missing_weights == ("CLIPSeg", "SAM") and "environment OK" not in dock.environment.env_label.text()
    assert "CLIPSeg weights (CIDAS/clipseg-rd64-refined): MISSING" in dock.environment.env_label.text()
    (item,) = [i for i in bar.items() if i.title() == "overseec environment"]
    assert "CLIPSeg" in item.text() and "SAM" in item.text() and item.level() == Qgis.Warning
    # Segment names both missing models before any model loads (the CLI alone names only one)
    image = QgsRasterLayer(str(SAMPLE / "sample.tif"), "sample")
    QgsProject.instance().addMapLayer(image)
    dock.imagery.layer_combo.setLayer(image)
    dock.mission.add_entity_row("road", "linear", None, ())
    dock.parameters.refine_check.setChecked(True)
    set_options(plugin, runs_dir=str(tmp_path / "runs"))
    bar.clear_messages()
    assert run_and_wait(dock, dock.runs.segment_button.click) == ("segment", False)
    (critical,) = _messages(qgis_iface, Qgis.Critical)
    assert "CLIPSeg (CIDAS/clipseg-rd64-refined) and SAM (facebook/sam-vit-base)" in critical
    # copied model folders set on the options page fix it: the warning goes, "environment OK"
    clipseg, sam = _fake_model(tmp_path / "clipseg", "clipseg"), _fake_model(tmp_path / "sam", "sam")
    rechecked = []
    dock.env_checked.connect(rechecked.append)
    set_options(plugin, clipseg_model=str(clipseg), sam_model=str(sam))
    wait_until(lambda: rechecked or dock.environment.task is None, 120, "the re-check the options started")
    assert rechecked, dock.environment.env_label.text()
    report = rechecked[0]
    if not report.models_ok:
        pytest.skip("the project venv has no torch: the environment cannot pass")
    assert report.all_ok and "environment OK" in dock.environment.env_label.text(), report.text()
    assert not [i for i in bar.items() if i.title() == "overseec environment"]


def test_the_dock_s_own_check_does_not_nag_about_what_only_segmentation_needs(
    plugin, qgis_iface, tmp_path, monkeypatch
) -> None:
    """The check the dock runs by itself when first shown: with the core working but no model
    weights, the panel says what is missing but the message bar stays quiet and the check is
    remembered as done for this version (next session: no check, no bar), so class-raster work
    is never nagged; Check environment, asked for, still warns (issue 32 item 7)."""
    from overseec_qgis import jobs
    from overseec_qgis.settings import PluginSettings

    dock, bar = _worker_without_weights(plugin, qgis_iface, tmp_path, monkeypatch)
    wait_until(lambda: dock.environment.task is None, 120, "a re-check the options started")
    dock.settings.current = PluginSettings.save_fields(env_checked="")
    bar.clearWidgets()
    reports = []
    dock.env_checked.connect(reports.append)
    dock.environment.check_environment(automatic=True)
    wait_until(lambda: reports, 120, "the environment check")
    assert reports[0].ok and not reports[0].all_ok and reports[0].missing_weights
    assert "MISSING" in dock.environment.env_label.text()
    assert not [i for i in bar.items() if i.title() == "overseec environment"]
    assert PluginSettings.load().env_checked == jobs.core_version()  # not again next session
    _check_env(dock)  # asked for: the warning comes
    (item,) = [i for i in bar.items() if i.title() == "overseec environment"]
    assert "CLIPSeg" in item.text()


def test_set_up_environment_from_the_dock(plugin, tmp_path, monkeypatch) -> None:
    """The dock's action makes the venv (installing the wheel named on the options page, its
    models extra from a local wheelhouse; see test_setup_env), points the settings at it and
    checks the new environment."""
    from overseec_qgis.settings import PluginSettings

    from .test_setup_env import make_wheelhouse

    house = make_wheelhouse(tmp_path / "wheels", monkeypatch)
    set_options(plugin, install_source=str(house / "overseec-0.0.1-py3-none-any.whl"))
    dock = plugin.dock
    reports = []
    dock.env_checked.connect(reports.append)
    venv = tmp_path / "analyst-env"
    assert run_and_wait(dock, lambda: dock.environment.set_up_environment(venv), 240) == ("set up", True)
    settings = PluginSettings.load()
    assert settings.venv == str(venv.resolve()) and settings.worker_path == ""
    assert (venv / "bin" / "overseec").is_file()
    wait_until(lambda: reports, 120, "the check after set-up")
    # the stand-in has no overseec_core: the check says so (and offers set-up again)
    assert reports[0].worker == str(venv.resolve() / "bin" / "overseec") and reports[0].setup_helps


def test_imagery_from_a_layer_is_extracted_into_the_run_folder_and_used(
    plugin, dock, qgis_iface, qgis_canvas, qgis_parent
) -> None:
    """Imagery box: source layer, Canvas extent / Draw area, GSD -> size; Extract writes
    image.tif into a new run folder in a task and makes it the input image."""
    from qgis.gui import QgsMapMouseEvent
    from qgis.PyQt.QtCore import QEvent, QPoint, Qt

    from .test_maptool import show_canvas

    source = QgsRasterLayer(str(SAMPLE / "sample.tif"), "basemap")
    QgsProject.instance().addMapLayer(source)
    show_canvas(qgis_canvas, qgis_parent)
    qgis_canvas.setDestinationCrs(source.crs())
    full = source.extent()
    part = QgsRectangle(full.xMinimum(), full.yMinimum(), full.center().x(), full.center().y())
    qgis_canvas.setExtent(part)
    dock.imagery.source_combo.setLayer(source)
    assert "area" in dock.imagery.extract_label.text()
    dock.imagery.canvas_extent_button.click()
    dock.imagery.gsd_spin.setValue(1.0)
    plan = dock.imagery.extract_plan
    assert plan is not None and plan.gsd_m == 1.0 and "px" in dock.imagery.extract_label.text()
    assert plan.extent.contains(qgis_canvas.extent()) or plan.extent.intersects(part)
    # far too fine for the area: one line, and no task starts
    dock.imagery.gsd_spin.setValue(0.01)
    if dock.imagery.extract_plan is None:
        assert dock.imagery.extract_label.text().startswith("✗")
    dock.imagery.gsd_spin.setValue(1.0)

    # Draw area: drag a rectangle with the tool
    dock.imagery.draw_area_button.click()
    tool = dock.imagery.extent_tool
    assert qgis_canvas.mapTool() is tool
    to_screen = qgis_canvas.getCoordinateTransform().transform
    a = to_screen(full.xMinimum() + 20, full.yMaximum() - 20)
    b = to_screen(full.xMinimum() + 120, full.yMaximum() - 80)
    pa, pb = QPoint(round(a.x()), round(a.y())), QPoint(round(b.x()), round(b.y()))
    tool.canvasPressEvent(QgsMapMouseEvent(qgis_canvas, QEvent.MouseButtonPress, pa, Qt.LeftButton, Qt.LeftButton))
    tool.canvasMoveEvent(QgsMapMouseEvent(qgis_canvas, QEvent.MouseMove, pb, Qt.NoButton, Qt.LeftButton))
    tool.canvasReleaseEvent(QgsMapMouseEvent(qgis_canvas, QEvent.MouseButtonRelease, pb, Qt.LeftButton, Qt.NoButton))
    assert not dock.imagery.draw_area_button.isChecked() and qgis_canvas.mapTool() is not tool
    plan = dock.imagery.extract_plan
    assert plan is not None and 90 <= plan.width <= 110 and 50 <= plan.height <= 70, dock.imagery.extract_label.text()

    qgis_canvas.refreshAllLayers()  # the canvas draws the same layer while the task renders it
    assert run_and_wait(dock, dock.imagery.extract_button.click) == ("extract", True)
    image = dock.run.run_dir / "image.tif"
    assert image.is_file() and dock.imagery.file_widget.filePath() == str(image)
    assert dock.imagery.image_path() == str(image) and f"{plan.width} x {plan.height} px" in wait_for_info(dock)
    extracted = [lyr for lyr in QgsProject.instance().mapLayers().values() if lyr.source() == str(image)]
    assert len(extracted) == 1 and extracted[0].customProperty("overseec/role") == "image"
    # the next stage works in that run folder
    assert dock.run.ensure_run_dir(dock.imagery.image_path()) == image.parent


def test_screenshots_of_the_dock_and_the_options_page(plugin, qgis_canvas) -> None:
    """docs/img/dock.png and docs/img/options.png come from here (copied from the artifacts):
    the whole dock after Interpret with an imagery area chosen and a real environment check,
    and the options page, rendered offscreen with QWidget.grab()."""
    from overseec_qgis import jobs

    from .conftest import artifacts_dir
    from .test_screenshot import as_array, assert_not_blank

    dock = plugin.dock
    set_options(plugin, runs_dir="/data/overseec-runs")
    image = QgsRasterLayer(str(SAMPLE / "sample.tif"), "sample")
    QgsProject.instance().addMapLayer(image)
    dock.imagery.source_combo.setLayer(image)
    dock.imagery.set_extract_area(image.extent(), image.crs())
    dock.imagery.layer_combo.setLayer(image)
    dock.mission.prompt_edit.setPlainText(META["prompt"])
    dock.mission.show_interpretation(jobs.interpret(META["prompt"]))
    dock.mission.validate_program()
    _check_env(dock)
    body = dock.widget().widget()
    body.resize(480, body.sizeHint().height())
    body.show()
    shot = body.grab().toImage()
    assert_not_blank(as_array(shot), "the dock")
    assert shot.save(str(artifacts_dir() / "dock.png"), "PNG")
    page = plugin.options_factory.createWidget(None)
    page.resize(640, page.sizeHint().height())
    page.show()
    options = page.grab().toImage()
    page.deleteLater()
    assert options.height() > 300 and options.save(str(artifacts_dir() / "options.png"), "PNG")


def test_a_running_job_disables_every_sections_start_buttons(dock) -> None:
    """One job at a time: while the job slot is busy, the start buttons of every section are
    off and Cancel is on; when it ends, the reverse (and the progress bar is reset)."""
    starts = (
        dock.imagery.extract_button,
        dock.mission.interpret_button,
        dock.runs.segment_button,
        dock.runs.costmap_button,
        dock.runs.run_button,
        dock.environment.setup_button,
        dock.routes.corridor_button,
        dock.routes.pairs_button,
    )
    assert all(b.isEnabled() for b in starts) and not dock.runs.cancel_button.isEnabled()
    dock.slot.set_busy(True)
    dock.runs.progress_bar.setValue(40)
    assert not any(b.isEnabled() for b in starts) and dock.runs.cancel_button.isEnabled()
    dock.slot.set_busy(False)
    assert all(b.isEnabled() for b in starts) and not dock.runs.cancel_button.isEnabled()
    assert dock.runs.progress_bar.value() == 0


def test_a_segment_folder_with_polygons_adds_them_above_the_masks(dock, scene) -> None:
    """A run folder holding masks.gpkg (`segment --vectors`) gets one styled polygon layer per
    entity, in the entity's mask colour, above the masks, when the dock adds the segment's layers."""
    from overseec_core import runfiles
    from overseec_core.locate.vectors import vectorize_folder
    from overseec_qgis.layers import ENTITY_COLOURS

    result = vectorize_folder(scene.folder, scene.folder / runfiles.MASK_POLYGONS)
    dock.runs._add_outputs(scene.folder, "segment", ("mask", "probability"))
    group = QgsProject.instance().layerTreeRoot().children()[0]
    found = [n.layer() for n in group.findLayers()]
    entities = [layer.name for layer in result.layers]
    assert sum(layer.polygons for layer in result.layers) > 0
    assert [layer.name() for layer in found[: len(entities)]] == [f"{e} polygons" for e in entities]
    assert [layer.name() for layer in found[len(entities) :]][:1] == [f"{entities[0]} mask"]
    for i, layer in enumerate(found[: len(entities)]):
        assert layer.featureCount() == result.layers[i].polygons
        assert layer.customProperty("overseec/entity") == entities[i]
        assert layer.renderer().symbol().symbolLayer(0).strokeColor().name() == ENTITY_COLOURS[i]
    (scene.folder / runfiles.MASK_POLYGONS).unlink()  # without the file: the masks only, as before
    dock.runs._add_outputs(scene.folder, "segment", ("mask", "probability"))
    group = QgsProject.instance().layerTreeRoot().children()[0]
    assert not any(n.layer().name().endswith(" polygons") for n in group.findLayers())
