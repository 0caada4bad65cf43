"""The QGIS process never imports torch or transformers (heavy inference is the worker's).

Checked at runtime in a fresh process standing in for QGIS: load the plugin's GUI and Processing
provider, run every non-ML algorithm and a map-tool plan, then look at sys.modules. A fresh process
is needed because other test areas import torch into the pytest process.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from .conftest import REPO, SAMPLE

pytestmark = pytest.mark.qgis

SCRIPT = textwrap.dedent(r"""
    import json, os, sys, tempfile
    from pathlib import Path
    os.environ["QT_QPA_PLATFORM"] = "offscreen"
    from qgis.core import QgsApplication, QgsRasterLayer, QgsProject
    app = QgsApplication([], True)
    app.initQgis()
    sys.path.append(os.path.join(QgsApplication.pkgDataPath(), "python", "plugins"))
    from processing.core.Processing import Processing
    Processing.initialize()
    import processing
    from unittest import mock
    from qgis.gui import QgsMapCanvas
    from qgis.PyQt.QtWidgets import QMainWindow
    window = QMainWindow()
    canvas = QgsMapCanvas(window)
    iface = mock.MagicMock()  # the GUI calls the plugin makes; the real widgets where it matters
    iface.mainWindow.return_value = window
    iface.mapCanvas.return_value = canvas
    from overseec_qgis import classFactory
    plugin = classFactory(iface)
    plugin.initGui()
    sample = Path(sys.argv[1])
    meta = json.loads((sample / "sample.json").read_text())
    out = Path(tempfile.mkdtemp())
    processing.run("overseec:interpret", {"PROMPT": meta["prompt"], "OUTPUT": str(out / "i.json")})
    cm = processing.run("overseec:costmap", {"LABELS": str(sample / "sample_labels.tif"),
                        "CLASSES": str(sample / "classes.json"), "PROMPT": meta["prompt"],
                        "OUTPUT": str(out / "costmap.tif")})["OUTPUT"]
    (sx, sy), (gx, gy) = meta["start"], meta["goal"]
    processing.run("overseec:plan", {"COSTMAP": cm, "START": f"{sx},{sy} [EPSG:32633]",
                   "GOAL": f"{gx},{gy} [EPSG:32633]", "OUTPUT": str(out / "p.geojson")})
    processing.run("overseec:evaluate", {"COSTMAP": cm, "PAIRS": 2, "PLOTS": False,
                   "OUTPUT_DIR": str(out / "eval")})
    layer = QgsRasterLayer(cm, "costmap")
    QgsProject.instance().addMapLayer(layer)
    plugin.map_tool.set_costmap(layer)
    grid = plugin.map_tool.session().grid  # loaded in the planner worker, not here
    assert grid.shape == (1024, 1024)
    plugin.unload()
    print(json.dumps(sorted(m for m in ("torch", "transformers") if m in sys.modules)))
""")


def test_the_qgis_process_never_imports_torch(tmp_path: Path) -> None:
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT, str(SAMPLE)], capture_output=True, text=True, cwd=REPO, timeout=300
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert json.loads(done.stdout.strip().splitlines()[-1]) == []


def test_no_module_of_the_plugin_imports_torch() -> None:
    pattern = re.compile(r"^\s*(from|import)\s+(torch|transformers)\b", re.M)
    offenders = [str(p) for p in (REPO / "overseec_qgis").rglob("*.py") if pattern.search(p.read_text())]
    assert offenders == []
