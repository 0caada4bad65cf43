"""The dock works in a QGIS Python that has neither rasterio, scipy nor the planner kernel.

Windows and macOS QGIS ship a Python without rasterio, and the plugin zip carries no compiled
kernel: the dock's reading check, Interpret and Build costmap must all run in the overseec
environment's worker. A fresh QGIS Python process loads the plugin from a pure-Python copy of
the tree with ``rasterio``, ``scipy``, ``skimage`` and ``overseec_core.plan._kernel`` made
unimportable (a meta-path finder that refuses them, installed before the plugin is imported),
interprets offline, builds a costmap on the sample scene's class raster, and reports what it got
and what it imported.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from .conftest import REPO, SAMPLE
from .desktop import pure_python_plugin

pytestmark = [pytest.mark.qgis, pytest.mark.slow]

SCRIPT = r"""
import importlib.abc, json, os, sys, tempfile
from pathlib import Path

FORBIDDEN = ("rasterio", "scipy", "skimage", "overseec_core.plan._kernel")


class Refuse(importlib.abc.MetaPathFinder):
    # What a Windows/macOS QGIS Python lacks: importing it fails as it would there.
    def find_spec(self, name, path=None, target=None):
        if any(name == f or name.startswith(f + ".") for f in FORBIDDEN):
            raise ImportError(f"No module named {name!r} (refused by the test)")
        return None


sys.meta_path.insert(0, Refuse())
plugin_dir, sample, worker = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3]
sys.path.insert(0, str(plugin_dir))
os.environ["QT_QPA_PLATFORM"] = "offscreen"
from qgis.core import QgsApplication, QgsProject, QgsRasterLayer, QgsSettings
app = QgsApplication([], False)
app.initQgis()
from qgis.PyQt.QtCore import QCoreApplication
QCoreApplication.setOrganizationName(f"overseec-dock-portable-{os.getpid()}")  # settings of its own
import overseec_qgis
assert Path(overseec_qgis.__file__).parent == plugin_dir / "overseec_qgis", overseec_qgis.__file__
from overseec_qgis.dock.panel import OverseecDock
from overseec_qgis.settings import PluginSettings

PluginSettings.save_fields(worker_path=worker, runs_dir=tempfile.mkdtemp(), offline=True)
dock = OverseecDock(None)
result = {}


def wait(start):
    outcome = []
    dock.task_done.connect(lambda stage, ok: outcome.append((stage, ok)))
    start()
    for _ in range(6000):
        if outcome:
            break
        app.processEvents()
        import time; time.sleep(0.02)
    return outcome[0] if outcome else ("timeout", False)


dock.imagery.file_widget.setFilePath(str(sample / "sample.tif"))
for _ in range(3000):  # the reading check is a background task
    if dock.imagery.info_task is None:
        break
    app.processEvents()
    import time; time.sleep(0.02)
result["info"] = dock.imagery.info_view.toPlainText()
labels = QgsRasterLayer(str(sample / "sample_labels.tif"), "labels", "gdal")
QgsProject.instance().addMapLayer(labels)
dock.mission.labels_combo.setLayer(labels)
dock.mission.classes_widget.setFilePath(str(sample / "classes.json"))
dock.mission.offline_check.setChecked(True)
dock.mission.prompt_edit.setPlainText("prefer the road, avoid the water and the buildings")
result["interpret"] = wait(dock.mission.interpret_button.click)
result["entities"] = [r["name"] for r in dock.mission.entity_rows()]
result["program_valid"] = dock.mission.validate_program()
result["costmap"] = wait(dock.runs.costmap_button.click)
result["status"] = dock.runs.status_label.text()
layers = [l for l in QgsProject.instance().mapLayers().values() if l.customProperty("overseec/role") == "costmap"]
result["costmap_layers"] = [(Path(l.source()).name, l.isValid(), l.width(), l.crs().authid()) for l in layers]
result["lethal"] = [l.name() for l in QgsProject.instance().mapLayers().values()
                    if l.customProperty("overseec/role") == "lethal"]
dock.shutdown()
Path(QgsSettings().fileName()).unlink(missing_ok=True)
heavy = (
    "rasterio",
    "overseec_core.plan",
    "overseec_core.pipeline",
    "overseec_core.synthesize.layers",
    "overseec_core.synthesize.engine",
    "torch",
    "scipy",
)
result["heavy"] = sorted(m for m in sys.modules if m.startswith(heavy))
print(json.dumps(result))
"""


def test_the_dock_interprets_and_builds_a_costmap_without_rasterio_or_the_kernel(tmp_path: Path) -> None:
    plugin_dir = pure_python_plugin(tmp_path / "plugin")
    worker = REPO / ".venv" / "bin" / "overseec"
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT, str(plugin_dir), str(SAMPLE), str(worker)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    r = json.loads(done.stdout.strip().splitlines()[-1])
    assert "1024 x 1024 px" in r["info"] and "EPSG:32633" in r["info"], r["info"]
    assert r["interpret"] == ["interpret", True], r["status"]
    assert {"road", "water", "building"} <= set(r["entities"])
    assert r["program_valid"] is True
    assert r["costmap"] == ["costmap", True], r["status"]
    assert r["costmap_layers"] == [["costmap.tif", True, 1024, "EPSG:32633"]]
    assert r["lethal"] == ["costmap lethal / keep-out"]
    assert r["heavy"] == []
