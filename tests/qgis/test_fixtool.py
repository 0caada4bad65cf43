"""The fix-mask tool driven by QTest mouse and key events on a canvas showing the sample image.

The canvas is in Web Mercator while the image is in UTM 33N, so every click and box goes through
the CRS transformation. SAM runs in a real `overseec sam-server` worker (a tiny random-weight
checkpoint built in a subprocess: this process stands in for QGIS and never imports torch).
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import rasterio
from qgis.core import (
    Qgis,
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsPointXY,
    QgsProject,
    QgsRasterLayer,
    QgsRectangle,
)
from qgis.PyQt.QtCore import QPoint, Qt
from qgis.PyQt.QtTest import QTest
from qgis.PyQt.QtWidgets import QPushButton

from overseec_core.io.grid import Grid
from overseec_core.io.manifest import RunDir
from overseec_core.io.read import read_classes_json
from overseec_core.io.write import write_array
from overseec_qgis.fixtool import EXCLUDE_COLOUR, INCLUDE_COLOUR, FixMaskTool, target_from_layer
from overseec_qgis.layers import Provenance, add_masks
from overseec_qgis.samclient import SamClient

from .conftest import REPO, SAMPLE, wait_until
from .test_maptool import click, drag, show_canvas

pytestmark = pytest.mark.qgis

ENTITY = "building"
#: The canvas shows image rows 600..856, columns 400..656 (a few buildings); SAM's view is that extent.
ROWS, COLS = (600, 856), (400, 656)


@pytest.fixture(scope="module")
def tiny_sam(tmp_path_factory) -> Path:
    """A tiny random SAM (tests/locate/builders.py), built in a subprocess."""
    pytest.importorskip("numpy")
    folder = tmp_path_factory.mktemp("models") / "tiny-sam"
    code = (
        "import sys; from pathlib import Path; from tests.locate.builders import save_sam; save_sam(Path(sys.argv[1]))"
    )
    done = subprocess.run(
        [sys.executable, "-c", code, str(folder)], cwd=REPO, capture_output=True, text=True, timeout=600
    )
    if done.returncode != 0 and "No module named 'torch'" in done.stderr:
        pytest.skip("needs torch and transformers in the worker environment")
    assert done.returncode == 0, done.stderr
    return folder


@pytest.fixture(scope="module")
def client():
    """One SAM worker for the module, as QGIS keeps one per session."""
    c = SamClient([sys.executable, "-m", "overseec_core.cli", "sam-server", "--device", "cpu"])
    yield c
    c.close()


def make_run(folder: Path, tiny_sam: Path | None) -> tuple[Path, Path]:
    """The sample image and a segment folder from its class raster (masks.tif, probs.tif, one band
    per class), whose manifest names the image and the SAM it was refined with (none: no SAM)."""
    folder.mkdir(parents=True)
    image = Path(shutil.copy(SAMPLE / "sample.tif", folder / "sample.tif"))
    seg = folder / "seg"
    seg.mkdir()
    classes = read_classes_json(SAMPLE / "classes.json")
    with rasterio.open(SAMPLE / "sample_labels.tif") as ds:
        labels = ds.read(1)
        grid = Grid(ds.crs, ds.transform, ds.width, ds.height)
    names = list(classes.values())
    masks = np.stack([labels == k for k in classes]).astype(np.uint8)
    write_array(seg / "masks.tif", masks, grid, nodata=255, descriptions=names)
    write_array(seg / "probs.tif", np.where(masks > 0, 0.9, 0.1).astype(np.float32), grid, descriptions=names)
    run = RunDir(seg)
    run.record_input("image", image, hash_file=False)
    if tiny_sam is not None:
        run.set("models", {"sam": {"name": "tiny", "path": str(tiny_sam)}})
    run.save()
    return image, seg


@pytest.fixture
def on_canvas(tmp_path, tiny_sam, client, qgis_canvas, qgis_iface, qgis_parent, qgis_new_project):
    image, seg = make_run(tmp_path / "run", tiny_sam)
    QgsProject.instance().addMapLayer(QgsRasterLayer(str(image), "image"))
    layers = add_masks(seg / "masks.tif", prov=Provenance.from_run_dir(seg, "mask"))
    mask_layer = next(la for la in layers if la.customProperty("overseec/entity") == ENTITY)
    canvas = qgis_canvas
    show_canvas(canvas, qgis_parent)
    canvas.setDestinationCrs(QgsCoordinateReferenceSystem("EPSG:3857"))
    with rasterio.open(image) as ds:
        t = ds.transform
    (x0, y1), (x1, y0) = t * (COLS[0], ROWS[0]), t * (COLS[1], ROWS[1])
    to_canvas = QgsCoordinateTransform(mask_layer.crs(), canvas.mapSettings().destinationCrs(), QgsProject.instance())
    canvas.setExtent(to_canvas.transformBoundingBox(QgsRectangle(x0, y0, x1, y1)))
    canvas.refresh()
    tool = FixMaskTool(canvas, qgis_iface, client=client)
    tool.set_target(target_from_layer(mask_layer))
    canvas.setMapTool(tool)
    replies, applied = [], []
    tool.changed.connect(replies.append)
    tool.applied.connect(applied.append)
    yield tool, canvas, to_canvas, t, seg, mask_layer, replies, applied
    canvas.unsetMapTool(tool)
    tool.clear()


def screen(canvas, to_canvas, transform, row: float, col: float) -> QPoint:
    """Screen position of an image pixel's centre."""
    p = to_canvas.transform(QgsPointXY(*(transform * (col + 0.5, row + 0.5))))
    s = canvas.getCoordinateTransform().transform(p)
    return QPoint(round(s.x()), round(s.y()))


def band_area_in_image_crs(tool) -> float:
    geom = tool.mask_band.asGeometry()
    geom.transform(tool._to_image())
    return geom.area()


def building_pixel(seg: Path) -> tuple[int, int]:
    """A pixel inside a building within the canvas span."""
    with rasterio.open(seg / "masks.tif") as ds:
        names = list(ds.descriptions)
        mask = ds.read(names.index(ENTITY) + 1)
    rows, cols = np.nonzero(mask[ROWS[0] + 40 : ROWS[1] - 40, COLS[0] + 40 : COLS[1] - 40] == 1)
    assert len(rows), "no building in the canvas span of the sample"
    k = len(rows) // 2
    return ROWS[0] + 40 + int(rows[k]), COLS[0] + 40 + int(cols[k])


def test_clicks_and_a_box_update_the_overlay_and_enter_writes_the_mask(on_canvas, client) -> None:
    tool, canvas, to_canvas, t, seg, mask_layer, replies, applied = on_canvas
    row, col = building_pixel(seg)
    assert target_from_layer(mask_layer).image.endswith("sample.tif")

    click(canvas, screen(canvas, to_canvas, t, row, col))  # include: opens the view, then prompts
    wait_until(lambda: replies, 300, "the first mask")
    assert tool.view is not None and tool.view.entities[0] == "grass"
    c0, r0, w, h = tool.view.window  # the canvas extent on the image (a little more, reprojected)
    assert c0 <= COLS[0] < COLS[1] <= c0 + w < COLS[1] + 10 and r0 <= ROWS[0] < ROWS[1] <= r0 + h < ROWS[1] + 10
    assert not tool.view_band.asGeometry().isEmpty()
    assert [m.fillColor() for m in tool.markers] == [INCLUDE_COLOUR]
    first = replies[-1]
    assert tool.mask_band.numberOfVertices() > 0 and first.outline_scale == 1
    assert band_area_in_image_crs(tool) == pytest.approx(first.area_px * 0.25, rel=1e-6)  # 0.5 m pixels

    click(canvas, screen(canvas, to_canvas, t, row + 30, col - 30), Qt.RightButton)  # exclude
    assert len(replies) == 2 and [label for _p, label in tool.points] == [1, 0]
    assert [m.fillColor() for m in tool.markers] == [INCLUDE_COLOUR, EXCLUDE_COLOUR]
    click(canvas, screen(canvas, to_canvas, t, row - 20, col + 20), modifiers=Qt.ShiftModifier)  # exclude too
    assert len(replies) == 3 and [label for _p, label in tool.points] == [1, 0, 0]

    drag(canvas, screen(canvas, to_canvas, t, row - 25, col - 25), screen(canvas, to_canvas, t, row + 25, col + 25))
    assert len(replies) == 4 and tool.box is not None and not tool.box_band.asGeometry().isEmpty()
    last = replies[-1]
    assert last.outline_scale == 1
    assert band_area_in_image_crs(tool) == pytest.approx(last.area_px * 0.25, rel=1e-6)
    assert client.ping()["embeddings"] == 1  # every prompt used the one embedding

    with rasterio.open(seg / "masks.tif") as ds:
        band = list(ds.descriptions).index(ENTITY) + 1
        before = ds.read(band)
    QTest.keyClick(canvas, Qt.Key_Return)
    assert len(applied) == 1 and applied[0].pixels_added == last.added_px
    with rasterio.open(seg / "masks.tif") as ds:
        after = ds.read(band)
    changed = np.argwhere(after != before)
    assert len(changed) == last.added_px + last.removed_px > 0
    assert changed[:, 0].min() >= r0 and changed[:, 0].max() < r0 + h  # inside the view only
    assert changed[:, 1].min() >= c0 and changed[:, 1].max() < c0 + w
    edits = json.loads((seg / "manifest.json").read_text())["mask_edits"]
    assert list(edits) == [applied[0].edit] and edits[applied[0].edit]["entity"] == ENTITY
    assert tool.points == [] and tool.box is None and tool.mask_band.numberOfVertices() == 0
    # the mask layer shows the new file
    r, c = changed[0]
    value, ok = mask_layer.dataProvider().sample(QgsPointXY(*(t * (c + 0.5, r + 0.5))), band)
    assert ok and value == after[r, c]


def test_keys_undo_reset_and_mode_and_a_click_beyond_the_view_opens_a_new_one(on_canvas, client) -> None:
    tool, canvas, to_canvas, t, seg, _layer, replies, _applied = on_canvas
    row, col = building_pixel(seg)
    embeddings = client.ping()["embeddings"]
    click(canvas, screen(canvas, to_canvas, t, row, col))
    wait_until(lambda: replies, 300, "the first mask")
    click(canvas, screen(canvas, to_canvas, t, row + 10, col + 10))
    assert len(tool.points) == 2
    QTest.keyClick(canvas, Qt.Key_Backspace)
    assert len(tool.points) == 1 and len(replies) == 3
    QTest.keyClick(canvas, Qt.Key_D)
    assert tool.mode == "remove" and replies[-1].added_px == 0
    QTest.keyClick(canvas, Qt.Key_Escape)
    assert tool.points == [] and tool.mask_band.numberOfVertices() == 0 and tool.view is not None

    first_view = tool.view
    canvas.setExtent(canvas.extent().buffered(canvas.extent().width()))  # zoom out: the view is no longer all
    canvas.refresh()
    click(canvas, screen(canvas, to_canvas, t, ROWS[1] + 60, COLS[1] + 60))
    wait_until(lambda: tool.view is not None and tool.view is not first_view and len(replies) >= 5, 300, "a new view")
    assert client.ping()["embeddings"] == embeddings + 2 and len(tool.points) == 1


def test_the_plugin_action_needs_a_mask_layer(plugin, qgis_iface, tmp_path, tiny_sam) -> None:
    _image, seg = make_run(tmp_path / "run", tiny_sam)
    qgis_iface.messageBar().clear_messages()
    plugin.fix_action.trigger()
    assert not plugin.fix_action.isChecked()
    assert "mask layer" in " ".join(qgis_iface.messageBar().get_messages(Qgis.Warning))
    layers = add_masks(seg / "masks.tif", prov=Provenance.from_run_dir(seg, "mask"))
    qgis_iface.setActiveLayer(layers[0])
    plugin.fix_action.trigger()
    canvas = qgis_iface.mapCanvas()
    assert plugin.fix_action.isChecked() and canvas.mapTool() is plugin.fix_tool
    assert plugin.fix_tool.target.entity == "grass" and plugin.fix_tool.target.segment_dir == str(seg)
    plugin.fix_action.trigger()
    assert canvas.mapTool() is not plugin.fix_tool


def test_the_client_opens_the_view_again_in_a_restarted_worker(tmp_path, tiny_sam) -> None:
    import os
    import signal
    import time

    from overseec_qgis.samclient import SamRejected, SamWorkerError

    image, seg = make_run(tmp_path / "run", tiny_sam)
    with rasterio.open(image) as ds:
        t = ds.transform
    (x0, y1), (x1, y0) = t * (COLS[0], ROWS[0]), t * (COLS[1], ROWS[1])
    c = SamClient([sys.executable, "-m", "overseec_core.cli", "sam-server", "--device", "cpu"])
    try:
        with pytest.raises(SamRejected, match="no view is open"):
            c.prompt(ENTITY, [t * (500, 700)], [1])
        assert c.open(image, seg, (x0, y0, x1, y1)).reused is False
        first = c.prompt(ENTITY, [t * (500, 700)], [1])
        os.kill(c.pid, signal.SIGKILL)
        time.sleep(0.2)
        again = c.prompt(ENTITY, [t * (500, 700)], [1])  # a new worker, the view opened there first
        assert c.starts == 2 and again.area_px == first.area_px and c.info is not None
        with pytest.raises(SamRejected, match="outside the view"):
            c.prompt(ENTITY, [t * (10, 10)], [1])
    finally:
        c.close()
    broken = SamClient(["/nonexistent/overseec", "sam-server"])
    with pytest.raises(SamWorkerError, match="cannot start the SAM worker"):
        broken.open(image, seg, (x0, y0, x1, y1))


def _armed_on_a_mask(plugin, qgis_iface, seg) -> None:
    layers = add_masks(seg / "masks.tif", prov=Provenance.from_run_dir(seg, "mask"))
    qgis_iface.setActiveLayer(layers[0])
    qgis_iface.messageBar().clearWidgets()
    plugin.fix_action.trigger()


def _bar_texts(qgis_iface) -> list[str]:
    return [item.text() for item in qgis_iface.messageBar().items()]


def test_missing_sam_weights_disarm_the_tool_when_it_is_chosen_not_at_the_first_click(
    plugin, qgis_iface, tmp_path, tiny_sam
) -> None:
    from overseec_qgis.settings import PluginSettings

    _image, seg = make_run(tmp_path / "run", tiny_sam)
    plugin.dock.settings.current = PluginSettings.save_fields(sam_model=str(tmp_path / "no-such-sam"))
    _armed_on_a_mask(plugin, qgis_iface, seg)
    canvas = qgis_iface.mapCanvas()
    wait_until(lambda: canvas.mapTool() is not plugin.fix_tool, 120, "the SAM check to disarm the tool")
    assert not plugin.fix_action.isChecked() and plugin.fix_tool.view is None  # no click was needed
    texts = _bar_texts(qgis_iface)
    assert len(texts) == 1 and "Settings › Options › overseec › SAM model" in texts[0], texts
    assert "overseec models download" not in texts[0] and "no-such-sam" in texts[0]
    options = qgis_iface.messageBar().items()[0].findChild(QPushButton, "overseecFixToolOptions")
    assert options is not None and options.text() == "Options…"


def test_a_known_sam_problem_refuses_at_once_and_found_weights_keep_the_tool_armed(
    plugin, qgis_iface, tmp_path, tiny_sam
) -> None:
    from overseec_qgis import jobs
    from overseec_qgis.envcheck import EnvReport
    from overseec_qgis.settings import PluginSettings

    _image, seg = make_run(tmp_path / "run", tiny_sam)
    settings = PluginSettings.save_fields(sam_model=str(tiny_sam))
    plugin.dock.settings.current = settings
    worker = str(jobs.find_worker_for(settings))
    plugin.dock.environment.report = EnvReport(ok=True, worker=worker, weights={"sam": {"ok": False, "name": "sam-x"}})
    _armed_on_a_mask(plugin, qgis_iface, seg)
    assert not plugin.fix_action.isChecked()  # refused before any check ran
    assert "SAM weights (sam-x)" in _bar_texts(qgis_iface)[0]
    plugin.dock.environment.report = None
    _armed_on_a_mask(plugin, qgis_iface, seg)
    wait_until(lambda: plugin._sam_task is None, 120, "the SAM check")
    assert plugin.fix_action.isChecked() and qgis_iface.mapCanvas().mapTool() is plugin.fix_tool
    assert (worker, str(tiny_sam)) in plugin._sam_ok and not _bar_texts(qgis_iface)
