"""The project keeps the dock's mission: image, prompt, entities, program, aliases, priors, class
raster and runs folder come back when the project is opened again, without interpreting again
over the user's edits; the Runs line follows the project's file."""

from __future__ import annotations

from pathlib import Path

import pytest
from qgis.core import QgsProject

from .conftest import SAMPLE, wait_until
from .test_dock import META, _add_sample_layers, run_and_wait, set_options
from .test_dock import dock as dock

pytestmark = pytest.mark.qgis


def _fields(dock) -> dict:
    """Every mission field the dock shows, as plain values."""
    m = dock.mission
    return {
        "image": (dock.imagery.layer_combo.currentLayer().name() if dock.imagery.layer_combo.currentLayer() else ""),
        "image file": dock.imagery.file_widget.filePath(),
        "bands": dock.imagery.bands_edit.text(),
        "prompt": m.prompt_edit.toPlainText(),
        "rows": m.entities_table.cells(),
        "program": m.program_edit.toPlainText(),
        "aliases": m.aliases_edit.text(),
        "priors": m.priors_widget.filePath(),
        "no priors": m.no_priors_check.isChecked(),
        "class raster": m.labels_combo.currentLayer().name() if m.labels_combo.currentLayer() else "",
        "classes": m.classes_widget.filePath(),
    }


def test_a_reopened_project_shows_the_mission_it_was_saved_with(dock, tmp_path) -> None:
    """Interpret, then edit the table and the program; save, clear, open: every field is back,
    the edits included, and Run all does not interpret again (the edits reach the costmap)."""
    _add_sample_layers(dock)
    dock.mission.offline_check.setChecked(True)
    dock.mission.prompt_edit.setPlainText(META["prompt"])
    priors = tmp_path / "priors.json"
    priors.write_text('{"building": 0.9}')
    dock.mission.priors_widget.setFilePath(str(priors))
    assert run_and_wait(dock, dock.mission.interpret_button.click) == ("interpret", True)
    dock.mission.add_entity_row("pond", "areal", 0.4, ("pond", "small lake"))
    dock.mission.entities_table.item(0, 2).setText("0.35")
    edited = 'cost = where(M["road"], 0.05, 0.7)\nlethal = M["water"]\n'
    dock.mission.program_edit.setPlainText(edited)
    dock.mission.aliases_edit.setText("pond=water")
    dock.imagery.bands_edit.setText("1,2,3")
    saved = _fields(dock)
    assert saved["image"] == "sample" and saved["class raster"] == "sample labels" and len(saved["rows"]) >= 5
    interpretation = dock.mission.interpretation
    project = QgsProject.instance()
    project_file = tmp_path / "mission.qgz"
    assert project.write(str(project_file))

    project.clear()
    cleared = _fields(dock)
    assert cleared["prompt"] == "" and cleared["rows"] == () and cleared["program"] == "" and not cleared["image"]
    assert project.read(str(project_file))
    assert _fields(dock) == saved
    assert dock.mission.interpretation == interpretation and not dock.mission.needs_interpreting()
    assert not project.isDirty()

    # Run all keeps the edited program: the prompt is not interpreted again
    done = []
    dock.run_done.connect(done.append)
    assert run_and_wait(dock, dock.runs.run_button.click)[1]
    assert done, "Run all reported success but no run folder"
    assert (Path(done[0]) / "costmap.program.txt").read_text() == edited
    assert dock.mission.program_edit.toPlainText() == edited


def test_an_image_file_and_the_runs_folder_chosen_for_an_unsaved_project_come_back(plugin, tmp_path) -> None:
    """A project stored without a folder beside it keeps the runs folder chosen while it was
    unsaved; the input image given as a file comes back as that file."""
    dock = plugin.dock
    set_options(plugin, runs_dir="")
    dock.run.ask_runs_folder = lambda: str(tmp_path / "chosen")
    dock.imagery.show_image(str(SAMPLE / "sample.tif"))
    assert dock.run.runs_folder() == tmp_path / "chosen"
    project = QgsProject.instance()
    assert project.write(str(tmp_path / "p.qgz"))
    project.clear()
    assert dock.run.root() is None and dock.imagery.image_path() == ""
    assert project.read(str(tmp_path / "p.qgz"))
    assert dock.run.session_runs == tmp_path / "chosen"
    assert dock.imagery.image_path() == str(SAMPLE / "sample.tif")


def test_a_project_from_an_older_plugin_keeps_the_earlier_behaviour(dock, tmp_path) -> None:
    """No mission entries (a project an older plugin saved: aliases, priors and the run only):
    the aliases come back, the other fields stay blank, the run's image is the input."""
    project = QgsProject.instance()
    run_dir = tmp_path / "runs" / "sample-1"
    run_dir.mkdir(parents=True)
    dock.mission.aliases_edit.setText("lake=water")
    dock.run.set_run_dir(run_dir, str(SAMPLE / "sample.tif"))
    project.writeEntry("overseec", "aliases", "lake=water")
    project.writeProject.disconnect(dock._project_writing)  # as an older plugin saved it
    try:
        assert project.write(str(tmp_path / "old.qgz"))
    finally:
        project.writeProject.connect(dock._project_writing)
    project.clear()
    assert project.read(str(tmp_path / "old.qgz"))
    assert project.readEntry("overseec", "prompt", "")[1] is False
    assert dock.mission.aliases_edit.text() == "lake=water"
    assert dock.mission.prompt() == "" and dock.mission.entity_rows() == [] and dock.mission.interpretation is None
    assert dock.run.run_dir == run_dir and dock.imagery.image_path() == str(SAMPLE / "sample.tif")


def test_the_runs_line_follows_the_project_file(plugin, tmp_path) -> None:
    """ "asked on the first run (project not saved)" until the project is saved; then the runs
    folder beside it, whether it was saved with write(path) or Save As (a new file name)."""
    dock = plugin.dock
    set_options(plugin, runs_dir="")
    project = QgsProject.instance()
    assert "asked on the first run" in _runs_text(dock)
    for folder in ("a", "b"):
        (tmp_path / folder).mkdir()
    assert project.write(str(tmp_path / "a" / "m.qgz"))
    assert f"Runs: {tmp_path / 'a' / 'overseec-runs'}" in _runs_text(dock)
    project.setFileName(str(tmp_path / "b" / "m.qgz"))  # Save As
    assert project.write()
    assert f"Runs: {tmp_path / 'b' / 'overseec-runs'}" in _runs_text(dock)


@pytest.mark.parametrize("answer", ["chosen", ""])
def test_the_runs_line_says_where_runs_went_once_the_first_run_asked(plugin, tmp_path, answer: str) -> None:
    """An unsaved project: the first run asks where runs go; the line then names the folder
    chosen, or the temporary folder used when the question was declined (said temporary), never
    "asked on the first run" any more (issue 32 item 7)."""
    dock = plugin.dock
    set_options(plugin, runs_dir="")
    QgsProject.instance().clear()
    chosen = tmp_path / "chosen"
    dock.run.ask_runs_folder = lambda: str(chosen) if answer else ""
    assert "asked on the first run" in _runs_text(dock)
    where = dock.run.runs_folder()
    text = _runs_text(dock)
    assert "asked on the first run" not in text
    if answer:
        assert where == chosen and f"Runs: {chosen}" in text
    else:
        assert f"Runs: {where} (temporary" in text
    QgsProject.instance().clear()  # a new project asks again
    assert "asked on the first run" in _runs_text(dock)


def _runs_text(dock) -> str:
    """The parameters box's line that names the runs folder."""
    return dock.parameters.models_label.text()


def test_a_prompt_entity_without_a_layer_is_explained_in_the_dock_with_its_alias_field(dock, qgis_iface) -> None:
    """ "compound" matches none of the class raster's layers: the program box, the status line
    and the message bar say so and name the dock's Entity aliases field (not the CLI's --alias);
    with the alias the program reads the building layer and the explanation goes away."""
    from qgis.core import Qgis

    _add_sample_layers(dock)
    dock.mission.offline_check.setChecked(True)
    bar = qgis_iface.messageBar()
    for prompt, none_matched in (("avoid the compound", True), ("avoid the compound, prefer the roads", False)):
        bar.clear_messages()
        dock.mission.prompt_edit.setPlainText(prompt)
        assert run_and_wait(dock, dock.mission.interpret_button.click) == ("interpret", True)
        advice = dock.mission.fit_label.text()
        assert "'compound'" in advice and "in Entity aliases" in advice and "compound=" in advice, advice
        assert ("none of the entities" in advice) is none_matched
        assert "--alias" not in advice and "--alias" not in dock.runs.status_label.text()
        assert "Entity aliases" in dock.runs.status_label.text()
        (warning,) = bar.get_messages(Qgis.Warning)
        assert "Entity aliases" in warning and "--alias" not in warning
    QgsProject.instance().clear()  # another mission: the explanation goes with the old one
    assert dock.mission.fit_label.text() == "" and dock.mission.fit_label.isHidden()
    _add_sample_layers(dock)
    dock.mission.prompt_edit.setPlainText("avoid the compound, prefer the roads")
    dock.mission.aliases_edit.setText("compound=building")
    assert run_and_wait(dock, dock.mission.interpret_button.click) == ("interpret", True)
    assert dock.mission.fit_label.text() == "" and 'P["building"]' in dock.mission.program_edit.toPlainText()


def test_an_unread_clause_is_highlighted_in_the_prompt_and_warned_about(dock, qgis_iface) -> None:
    """Part of the brief not understood: never a bare "Interpreted"; the words are marked in
    the prompt box (text untouched), a warning is in the message bar, and the marks go when the
    prompt is edited (issue 31 item 7, issue 32 item 7)."""
    from qgis.core import Qgis

    _add_sample_layers(dock)
    dock.mission.offline_check.setChecked(True)
    prompt = "avoid the buildings, and make sure the operator logs the start time"
    dock.mission.prompt_edit.setPlainText(prompt)
    assert run_and_wait(dock, dock.mission.interpret_button.click) == ("interpret", True)
    status = dock.runs.status_label.text()
    assert "not understood" in status and "logs the start time" in status, status
    marks = dock.mission.prompt_edit.extraSelections()
    assert [m.cursor.selectedText() for m in marks] == list(dock.mission.unread) and marks
    assert [m.cursor.selectedText() for m in marks] == ["make sure the operator logs the start time"]
    assert dock.mission.prompt_edit.toPlainText() == prompt
    assert any("not understood" in w for w in qgis_iface.messageBar().get_messages(Qgis.Warning))
    dock.mission.prompt_edit.setPlainText("avoid the buildings")
    assert dock.mission.prompt_edit.extraSelections() == []
    assert run_and_wait(dock, dock.mission.interpret_button.click) == ("interpret", True)
    assert "not understood" not in dock.runs.status_label.text()


def test_a_names_task_that_ended_without_reporting_is_replaced(dock) -> None:
    """The entity layers' names are read in a task; one that ended without its report reaching
    the dock (here: its signals cut, as a lost report would leave it) must not keep later
    callers (Build costmap, Run all) waiting for ever: the next request reads them again."""
    from qgis.core import QgsTask

    from overseec_qgis.dock.common import detach

    _add_sample_layers(dock)
    mission = dock.mission
    mission.masks_updated()
    stale = mission.names_task
    assert stale is not None
    for signal in (stale.succeeded, stale.failed):
        signal.disconnect()
    wait_until(lambda: QgsTask.status(stale) in (QgsTask.Complete, QgsTask.Terminated), 60.0, "the names task to end")
    assert mission.names_task is stale and not mission.names_known()
    called = []
    mission.load_names(lambda: called.append(True))
    wait_until(lambda: called, 60.0, "the names to be read again")
    assert mission.names_known() and mission.names_task is None
    detach(stale)
