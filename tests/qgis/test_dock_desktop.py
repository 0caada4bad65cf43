"""The dock's mission in the real QGIS desktop (the `qgis` binary under Xvfb): typed, saved with
Project › Save, closed with Project › New and opened again, while a 10 ms heartbeat on QGIS's GUI
thread times every step.

A ``--code`` script loads the plugin from a pure-Python copy, types the prompt and the aliases
with QTest, clicks Interpret (the real worker), edits the program, saves the project through
QGIS's own Save action, starts a new project and opens the saved one through ``iface.addProject``.
It writes the dock's fields at each point, the Runs line before and after saving, the longest GUI
block per step (the longest heartbeat gap less the time the thread waited for a CPU in it), and
grabs of the Mission section before saving and after reopening (compared by pixels: the reopened
dock shows what was saved).
"""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import pytest

from .conftest import SAMPLE, artifacts_dir
from .desktop import META, as_rgb, desktop_config, needs_desktop, run_desktop

pytestmark = [pytest.mark.qgis, pytest.mark.slow]

#: The GUI rule of the issue (ms).
LIMIT_MS = 100.0

SCRIPT = textwrap.dedent(
    r"""
    from qgis.core import QgsProject, QgsRasterLayer
    from qgis.PyQt.QtCore import Qt
    from qgis.PyQt.QtTest import QTest

    result["blocks"] = []

    def wait(predicate, what, timeout=90):
        if not wait_for(predicate, timeout):
            raise RuntimeError("timed out waiting for " + what)

    def step(name, action, done=lambda: True):
        # the longest heartbeat gap from the action until it is done (ms), less the time the
        # thread waited for a CPU in it, and the gap itself
        beat = Heartbeat().start()
        pump(0.05)
        action()
        wait(done, name)
        pump(0.05)
        beat.stop()
        result["blocks"].append([name, round(beat.blocked_ms, 1), round(beat.longest_ms, 1)])

    def fields(dock):
        m, im = dock.mission, dock.imagery
        layer = im.layer_combo.currentLayer()
        labels = m.labels_combo.currentLayer()
        return {
            "image": layer.name() if layer else "",
            "prompt": m.prompt_edit.toPlainText(),
            "rows": [list(r) for r in m.entities_table.cells()],
            "program": m.program_edit.toPlainText(),
            "aliases": m.aliases_edit.text(),
            "class raster": labels.name() if labels else "",
            "classes": m.classes_widget.filePath(),
            "interpretation": m.interpretation.prompt if m.interpretation else None,
        }

    def grab(widget, name):
        # the same view both times: every text box at its start, nothing focused
        for w in widget.findChildren(QWidget):
            w.clearFocus()
        for edit in (widget.prompt_edit, widget.program_edit):
            edit.moveCursor(QTextCursor.Start)
            edit.ensureCursorVisible()
        widget.entities_table.scrollToTop()
        pump(0.3)
        path = os.path.join(CFG["out_dir"], name)
        widget.grab().toImage().save(path)
        return path

    from qgis.PyQt.QtGui import QTextCursor
    from qgis.PyQt.QtWidgets import QWidget

    def timed(cls, name):
        # how long the dock's own project slots take inside QGIS's save and open (ms)
        slot = getattr(cls, name)

        def wrapper(self, *args):
            t, w = time.perf_counter(), cpu_wait_s()
            try:
                return slot(self, *args)
            finally:
                ms = 1000 * (time.perf_counter() - t - (cpu_wait_s() - w))
                result.setdefault("slots", {}).setdefault(name, []).append(round(ms, 1))

        setattr(cls, name, wrapper)

    def main():
        def wrap_slots():
            from overseec_qgis.dock.panel import OverseecDock
            for name in ("_project_read", "_project_writing", "_project_cleared"):
                timed(OverseecDock, name)  # before the dock connects them

        win, plugin = open_plugin((1400, 950), wrap_slots)
        dock = plugin.dock
        done = []
        dock.task_done.connect(lambda stage, ok: done.append((stage, ok)))
        step("first show (environment check)", lambda: (dock.show(), dock.raise_()),
             lambda: dock.environment.task is None)
        project = QgsProject.instance()
        image = QgsRasterLayer(CFG["image"], "sample image")
        labels = QgsRasterLayer(CFG["labels"], "sample labels")
        project.addMapLayers([image, labels])
        m = dock.mission
        step("input image", lambda: dock.imagery.layer_combo.setLayer(image), lambda: dock.imagery.info_task is None)

        def class_raster():
            m.labels_combo.setLayer(labels)
            m.classes_widget.setFilePath(CFG["classes"])

        step("class raster", class_raster, m.names_known)
        m.offline_check.setChecked(True)
        m.prompt_edit.setFocus()
        QTest.keyClicks(m.prompt_edit, CFG["prompt"])
        step("Interpret", lambda: QTest.mouseClick(m.interpret_button, Qt.LeftButton), lambda: bool(done))
        result["interpreted"] = done[-1]
        m.program_edit.setFocus()
        m.program_edit.moveCursor(m.program_edit.textCursor().End)

        def edit_program():
            QTest.keyClicks(m.program_edit, "# keep to the road")

        step("program edit", edit_program,
             lambda: not m.program_timer.isActive() and m.program_status.text().startswith("✓"))
        m.aliases_edit.setFocus()
        QTest.keyClicks(m.aliases_edit, "compound=building")
        result["runs_before_save"] = dock.parameters.models_label.text()
        result["saved"] = fields(dock)
        project.setFileName(CFG["project"])
        step("Project › Save", lambda: iface.actionSaveProject().trigger())
        result["runs_after_save"] = dock.parameters.models_label.text()
        result["dirty_after_save"] = project.isDirty()
        result["shot_saved"] = grab(m, "mission-saved.png")
        iface.newProject(False)
        pump(0.3)
        result["cleared"] = fields(dock)
        step("project open (iface.addProject)", lambda: iface.addProject(CFG["project"]),
             lambda: dock.imagery.info_task is None and m.names_known() and not m.program_timer.isActive())
        pump(0.3)
        result["reopened"] = fields(dock)
        result["runs_after_open"] = dock.parameters.models_label.text()
        result["needs_interpreting"] = m.needs_interpreting()
        result["shot_reopened"] = grab(m, "mission-reopened.png")
        iface.messageBar().clearWidgets()
        win.resizeDocks([dock], [520], Qt.Horizontal)
        pump(0.5)
        win.grab().toImage().save(os.path.join(CFG["out_dir"], "dock-reopened.png"))
        plugin.unload()

    start(main, 150000)
    """
)


@pytest.fixture(scope="module")
def desktop_mission(tmp_path_factory) -> dict:
    """One QGIS desktop session typing, saving and reopening a mission; its JSON report."""
    tmp = tmp_path_factory.mktemp("dock-desktop")
    (tmp / "mission").mkdir()
    config = desktop_config(
        tmp,
        image=str(SAMPLE / "sample.tif"),
        labels=str(SAMPLE / "sample_labels.tif"),
        classes=str(SAMPLE / "classes.json"),
        prompt=META["prompt"],
        project=str(tmp / "mission" / "mission.qgz"),
    )
    keep = {"dock-reopened.png": "dock-reopened.png"}
    result = run_desktop(tmp, "drive_dock.py", SCRIPT, config, timeout=300, check_exit=False, keep=keep)
    out = Path(config["out_dir"])
    rows = [(name, ms, f"{wall:>8} ms") for name, ms, wall in result["blocks"]]
    rows += [(f"  of which the dock's {slot}", max(ms), "") for slot, ms in result.get("slots", {}).items()]
    head = f"{'step':<40} {'block':>11} {'(gap)':>11}\n"
    table = head + "\n".join(f"{name:<40} {ms:>8} ms {wall}".rstrip() for name, ms, wall in rows)
    print("\nlongest GUI block per step (QGIS desktop):\n" + table)
    (artifacts_dir() / "dock-desktop-responsiveness.txt").write_text(table + "\n")
    return {"result": result, "out": out, "config": config}


@needs_desktop
def test_the_reopened_project_shows_the_mission_it_was_saved_with(desktop_mission) -> None:
    r, config = desktop_mission["result"], desktop_mission["config"]
    assert r["interpreted"] == ["interpret", True]
    saved = r["saved"]
    assert saved["prompt"] == config["prompt"] and saved["aliases"] == "compound=building"
    assert saved["program"].endswith("# keep to the road") and len(saved["rows"]) >= 4
    assert saved["image"] == "sample image" and saved["class raster"] == "sample labels"
    assert r["cleared"]["prompt"] == "" and r["cleared"]["rows"] == [] and r["cleared"]["program"] == ""
    assert r["reopened"] == saved
    assert r["needs_interpreting"] is False  # Run all keeps the edited program
    # the Mission section looks the same after reopening (pixels)
    before, after = as_rgb(Path(r["shot_saved"])), as_rgb(Path(r["shot_reopened"]))
    assert before.shape == after.shape and before.std() > 20
    differ = np.any(np.abs(before - after) > 40, axis=-1).mean()
    assert differ < 0.01, f"{differ:.1%} of the Mission section's pixels differ after reopening"


@needs_desktop
def test_the_runs_line_names_the_folder_beside_the_saved_project(desktop_mission) -> None:
    r, config = desktop_mission["result"], desktop_mission["config"]
    beside = str(Path(config["project"]).parent / "overseec-runs")
    assert "asked on the first run (project not saved)" in r["runs_before_save"]
    assert f"Runs: {beside}" in r["runs_after_save"] and f"Runs: {beside}" in r["runs_after_open"]
    assert r["dirty_after_save"] is False


@needs_desktop
def test_no_step_blocks_qgis_longer_than_100_ms(desktop_mission) -> None:
    r = desktop_mission["result"]
    # Project › Save and opening a project block QGIS while it writes and reads the project and
    # its layers (QGIS's own work, not the dock's): for those, the dock's slots inside them count
    blocks = {name: ms for name, ms, _gap in r["blocks"] if not name.startswith("project open") and "Save" not in name}
    blocks.update({f"dock {slot}": max(ms) for slot, ms in r["slots"].items()})
    assert {"dock _project_read", "dock _project_writing"} <= set(blocks)
    slow = {name: ms for name, ms in blocks.items() if ms is None or ms > LIMIT_MS}
    assert not slow, f"the GUI thread was blocked longer than {LIMIT_MS:g} ms: {slow}"
