"""A screenshot of the dock beside the map (sample image, costmap, planned path), kept as a PNG.

Rendered offscreen: the dock with QWidget.grab(), the map with QgsMapRendererParallelJob. The
test fails if either half is blank (too little pixel variance or too few colours). The PNG goes
to $OVERSEEC_ARTIFACTS (default tests/artifacts/overseec_qgis.png); docs/img/ keeps a copy.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
from qgis.core import QgsMapRendererParallelJob, QgsMapSettings, QgsProject, QgsRasterLayer
from qgis.PyQt.QtCore import QCoreApplication, QSize, Qt
from qgis.PyQt.QtGui import QColor, QImage, QPainter

from overseec_core.pipeline import run_costmap
from overseec_core.plan.stage import PlanOptions, run_plan
from overseec_core.synthesize.options import CostmapOptions
from overseec_qgis import jobs
from overseec_qgis.layers import Provenance, add_costmap, add_path, run_group

from .conftest import SAMPLE, artifacts_dir, wait_until

pytestmark = pytest.mark.qgis

META = json.loads((SAMPLE / "sample.json").read_text())


def as_array(image: QImage) -> np.ndarray:
    """(H, W, 3) RGB uint8 copy of a QImage."""
    image = image.convertToFormat(QImage.Format_RGB888)
    ptr = image.constBits()
    ptr.setsize(image.sizeInBytes())
    rows = np.frombuffer(ptr, np.uint8).reshape(image.height(), image.bytesPerLine())
    return rows[:, : image.width() * 3].reshape(image.height(), image.width(), 3).copy()


def assert_not_blank(arr: np.ndarray, what: str) -> None:
    colours = len(np.unique(arr.reshape(-1, 3), axis=0))
    assert arr.std() > 20 and colours > 50, f"{what} looks blank (std {arr.std():.1f}, {colours} colours)"


def test_screenshot_of_the_dock_and_the_map(plugin, tmp_path: Path) -> None:
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    cm = run_costmap(
        CostmapOptions(
            out=run_dir / "costmap.tif",
            labels=SAMPLE / "sample_labels.tif",
            classes=SAMPLE / "classes.json",
            prompt=META["prompt"],
        )
    )
    plan = run_plan(
        PlanOptions(
            costmap=cm.costmap,
            points=(tuple(META["start"]), tuple(META["goal"])),
            out=run_dir / "path.geojson",
            native_out=run_dir / "path.gpkg",
            mode="exact",
        )
    )
    project = QgsProject.instance()
    image = QgsRasterLayer(str(SAMPLE / "sample.tif"), "sample")
    project.addMapLayer(image)
    prov = Provenance(run_dir=str(run_dir), prompt=META["prompt"], program=cm.program, stage="costmap")
    group = run_group("overseec: sample")
    # the route in the costmap's CRS, as the map tool's paths.gpkg holds it: late in a full suite run,
    # reprojecting the WGS 84 GeoJSON inside the render thread has come out unprojected (under study)
    path_layer = add_path(f"{plan.outputs['native']}|layername=path", group, prov, name="path")
    costmap = add_costmap(cm.costmap, group, prov)

    settings = QgsMapSettings()
    settings.setLayers([path_layer, costmap, image])
    settings.setDestinationCrs(costmap.crs())
    settings.setExtent(costmap.extent())
    settings.setOutputSize(QSize(1000, 1000))
    settings.setBackgroundColor(QColor("white"))
    job = QgsMapRendererParallelJob(settings)
    job.start()
    job.waitForFinished()
    map_image = job.renderedImage()
    assert_not_blank(as_array(map_image), "the map")

    dock = plugin.dock
    dock.environment.checked_once = True  # the first-use environment check has its own test
    dock.imagery.layer_combo.setLayer(image)
    dock.mission.prompt_edit.setPlainText(META["prompt"])
    dock.mission.show_interpretation(jobs.interpret(META["prompt"]))
    dock.mission.validate_program()
    wait_until(lambda: dock.imagery.info_task is None, 60, "the image reading check")
    dock.setFloating(True)
    dock.resize(460, 1000)
    dock.show()
    QCoreApplication.processEvents()
    dock_image = dock.grab().toImage()
    dock.hide()
    assert_not_blank(as_array(dock_image), "the dock")

    shot = QImage(
        dock_image.width() + map_image.width(), max(dock_image.height(), map_image.height()), QImage.Format_RGB32
    )
    shot.fill(Qt.white)
    painter = QPainter(shot)
    painter.drawImage(0, 0, dock_image)
    painter.drawImage(dock_image.width(), 0, map_image)
    painter.end()
    out = artifacts_dir() / "overseec_qgis.png"
    assert shot.save(str(out), "PNG")
    assert out.stat().st_size > 20_000
    # the path is drawn: its colour (the path style's #0050ff) appears on the map
    arr = as_array(map_image).astype(int)
    blue = (abs(arr[..., 2] - 0xFF) < 40) & (abs(arr[..., 1] - 0x50) < 40) & (arr[..., 0] < 60)
    why = (
        f"path layer valid={path_layer.isValid()} features={path_layer.featureCount()} "
        f"renderer={path_layer.renderer().dump() if path_layer.renderer() else None} "
        f"crs={path_layer.crs().authid()} extent={path_layer.extent().toString()} map={costmap.extent().toString()} "
        f"map crs={costmap.crs().authid()!r} valid={costmap.crs().isValid()} "
        f"open fds={len(os.listdir('/proc/self/fd'))}"
    )
    assert blue.sum() > 200, why
