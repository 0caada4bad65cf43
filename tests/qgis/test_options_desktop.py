"""The overseec page in the real Settings › Options dialog (the `qgis` binary under Xvfb).

A script given to QGIS with ``--code`` (in a throw-away profile) loads the plugin, presses the
dock's *Settings…*: QGIS's own Options dialog must open on the overseec page. The script types a
runs folder and a SAM model folder into the page, grabs the dialog ($OVERSEEC_ARTIFACTS/
options_dialog.png; docs/img/options.png is such a grab) and presses OK, so QGIS itself calls the page's
``apply()``; the settings the plugin then reads are written to a JSON file the test checks.
Unloading must unregister the page: the dialog opened again has no overseec entry.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import textwrap
from pathlib import Path

import pytest

from .conftest import REPO, artifacts_dir

pytestmark = [pytest.mark.qgis, pytest.mark.slow]

QGIS = shutil.which("qgis")
XVFB = shutil.which("xvfb-run")

SCRIPT = textwrap.dedent(
    r"""
    import json, os, sys, time, traceback
    CFG = json.load(open(os.environ["OVERSEEC_OPTIONS_CONFIG"]))
    sys.path.insert(0, CFG["repo"])
    from qgis.utils import iface
    from qgis.PyQt.QtCore import QCoreApplication, QTimer
    from qgis.PyQt.QtWidgets import QApplication, QListView, QTreeView, QWidget

    result = {}

    def finish():
        with open(CFG["result"], "w") as f:
            json.dump(result, f, indent=1)
        os._exit(0)

    def pump(seconds):
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            QCoreApplication.processEvents()
            time.sleep(0.02)

    def entries(dlg):
        names = []
        for view in dlg.findChildren(QTreeView) + dlg.findChildren(QListView):
            model = view.model()
            stack = [model.index(r, 0) for r in range(model.rowCount())]
            while stack:
                index = stack.pop()
                names.append(str(index.data()))
                stack += [model.index(r, 0, index) for r in range(model.rowCount(index))]
        return names

    def fill_and_accept():
        try:
            dlg = QApplication.activeModalWidget()
            result["dialog"] = type(dlg).__name__ if dlg is not None else None
            dlg.resize(1100, 760)
            pump(0.5)
            page = dlg.findChild(QWidget, "overseecOptions")
            result["page_visible"] = bool(page is not None and page.isVisible())
            result["entries"] = entries(dlg)
            page.runs_widget.setFilePath(CFG["runs"])
            page.sam_edit.setText(CFG["sam"])
            pump(0.3)
            result["saved_png"] = dlg.grab().save(CFG["png"])
            dlg.accept()
        except Exception:
            result["error"] = traceback.format_exc()
            finish()

    def after_unload():
        try:
            dlg = QApplication.activeModalWidget()
            result["entries_after_unload"] = entries(dlg) if dlg is not None else None
            if dlg is not None:
                dlg.reject()
        except Exception:
            result["error"] = traceback.format_exc()

    def main():
        try:
            iface.mainWindow().resize(1280, 860)
            iface.mainWindow().show()
            pump(0.5)
            from overseec_qgis import classFactory
            from overseec_qgis.settings import PluginSettings

            plugin = classFactory(iface)
            plugin.initGui()
            QTimer.singleShot(3000, fill_and_accept)
            plugin.dock.environment.options_button.click()  # modal: returns when the dialog closes
            s = PluginSettings.load()
            result["runs_dir"] = s.runs_dir
            result["sam_model"] = s.params.sam_model
            result["dock_shows"] = plugin.dock.parameters.models_label.text()
            plugin.unload()
            QTimer.singleShot(3000, after_unload)
            iface.showOptionsDialog(iface.mainWindow())
        except Exception:
            result["error"] = traceback.format_exc()
        finish()

    QTimer.singleShot(1500, main)
    """
)


@pytest.mark.skipif(QGIS is None or XVFB is None, reason="needs the qgis binary and xvfb-run")
def test_the_page_in_the_real_options_dialog(tmp_path: Path) -> None:
    script = tmp_path / "options.py"
    script.write_text(SCRIPT)
    png = artifacts_dir() / "options_dialog.png"
    cfg = {
        "repo": str(REPO),
        "result": str(tmp_path / "result.json"),
        "png": str(png),
        "runs": str(tmp_path / "my runs"),
        "sam": str(tmp_path / "copied-sam"),
    }
    (tmp_path / "cfg.json").write_text(json.dumps(cfg))
    env = dict(os.environ, OVERSEEC_OPTIONS_CONFIG=str(tmp_path / "cfg.json"))
    env.pop("QT_QPA_PLATFORM", None)  # a real X display (Xvfb), not offscreen
    done = subprocess.run(
        [XVFB, "-a", "-s", "-screen 0 1400x1000x24", QGIS, "--nologo", "--noversioncheck", "--noplugins"]
        + ["--profiles-path", str(tmp_path / "profiles"), "--code", str(script)],
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
    )
    result_file = tmp_path / "result.json"
    assert result_file.exists(), done.stdout[-2000:] + done.stderr[-2000:]
    result = json.loads(result_file.read_text())
    assert "error" not in result, result["error"]
    assert result["dialog"] and result["page_visible"] and "overseec" in result["entries"]
    assert result["runs_dir"] == cfg["runs"] and result["sam_model"] == cfg["sam"]
    assert cfg["runs"] in result["dock_shows"] and cfg["sam"] in result["dock_shows"]
    assert result["entries_after_unload"] and "overseec" not in result["entries_after_unload"]
    assert result["saved_png"] and png.stat().st_size > 20_000
