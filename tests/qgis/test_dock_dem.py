"""The dock's DEM (issue 26): a raster layer or a file in the Entity layers box, handed to
Build costmap as ``--dem``; the program checker lets a program read ``slope``/``roughness`` only
when a DEM is chosen (else the error names the dock's DEM field, at the line); the project keeps
the choice."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import rasterio
from qgis.core import QgsProject, QgsRasterLayer
from rasterio.transform import Affine

from overseec_qgis.dock.fitting import DEM_FIELD

from ..synthesize.test_terrain import write_dem
from .conftest import SAMPLE, wait_until
from .heartbeat import MAX_BLOCK_MS, Heartbeat, pump
from .test_dock import _add_sample_layers, run_and_wait
from .test_dock import dock as dock

pytestmark = pytest.mark.qgis

#: Roads cheap, the rest neutral, and steep ground (over 30 degrees) as dear as it gets.
SLOPE_PROGRAM = 'cost = where(M["road"], 0.1, 0.5)\ncost = max(cost, normalize(slope, 15, 30))\n'
#: Where the ramp begins, metres east of the sample's west edge (the sample is 512 m wide).
RAMP_X_M = 256.0


def sample_dem(folder: Path) -> Path:
    """A 2 m DEM over the sample (and 10 m beyond it): flat west of RAMP_X_M, a 45 degree ramp east."""
    with rasterio.open(SAMPLE / "sample_labels.tif") as ds:
        crs, (west, north) = ds.crs, (ds.transform.c, ds.transform.f)
    transform = Affine(2.0, 0.0, west - 10.0, 0.0, -2.0, north + 10.0)
    rows, cols = np.mgrid[0:270, 0:270]
    x, _ = transform * (cols + 0.5, rows + 0.5)
    z = 200.0 + np.maximum(np.asarray(x) - west - RAMP_X_M, 0.0)
    return write_dem(folder / "dem.tif", z, crs, transform)


def _status(dock) -> str:
    return dock.mission.program_status.text()


def _marked_line(dock) -> int | None:
    sel = dock.mission.program_edit.extraSelections()
    return sel[0].cursor.blockNumber() + 1 if sel else None


def test_slope_needs_the_dock_dem_then_build_costmap_passes_it(plugin, dock, tmp_path) -> None:
    """Without a DEM the program reading slope is an error at its line naming the DEM field;
    choosing a DEM file re-checks it (no GUI block over the rule); Build costmap then gives
    steep ground the program's cost, so the DEM reached the worker as --dem."""
    _add_sample_layers(dock)
    m = dock.mission
    m.program_edit.setPlainText(SLOPE_PROGRAM)
    assert not m.validate_program()
    assert "'slope' (degrees)" in _status(dock) and DEM_FIELD in _status(dock) and "--dem" not in _status(dock)
    assert _marked_line(dock) == 2
    assert m.layer_sources()["dem"] is None

    dem = sample_dem(tmp_path)
    with Heartbeat() as beat:
        m.dem_file_widget.setFilePath(str(dem))
        wait_until(lambda: _status(dock).startswith("✓"), 10, "the program checked again")
        pump(0.05)
    assert beat.blocked_ms <= MAX_BLOCK_MS, f"choosing the DEM blocked the GUI {beat.blocked_ms:.0f} ms"
    print(f"DEM chosen -> program re-checked: longest GUI block {beat.blocked_ms:.1f} ms")
    assert _marked_line(dock) is None and m.layer_sources()["dem"] == str(dem)

    assert run_and_wait(dock, dock.runs.costmap_button.click) == ("costmap", True)
    with rasterio.open(plugin.map_tool.costmap_layer.source()) as ds:
        cost = ds.read(1)
    half = int(RAMP_X_M / 0.5)
    assert cost[:, half + 20 :].min() == pytest.approx(1.0)  # the ramp: 45 degrees, dearest
    assert np.median(cost[:, : half - 20]) <= 0.5  # flat ground keeps the semantic cost


def test_a_dem_layer_is_used_and_a_non_file_layer_is_named(dock, tmp_path) -> None:
    _add_sample_layers(dock)
    m = dock.mission
    layer = QgsRasterLayer(str(sample_dem(tmp_path)), "my dem")
    assert layer.isValid()
    QgsProject.instance().addMapLayer(layer)
    m.dem_file_widget.setFilePath(str(tmp_path / "other.tif"))
    m.dem_combo.setLayer(layer)
    assert m.dem_path() == layer.source() and m.dem_problem() == ""
    m.program_edit.setPlainText(SLOPE_PROGRAM)
    assert m.validate_program()
    m.dem_combo.setLayer(None)  # "none": the file field's DEM
    assert m.dem_path() == str(tmp_path / "other.tif")
    m.dem_file_widget.setFilePath("")
    assert not m.validate_program() and DEM_FIELD in _status(dock)
    m.program_edit.setPlainText('cost = where(M["road"], 0.1, 0.5)\n')
    assert m.validate_program()  # a program without terrain needs no DEM
    tiles = QgsRasterLayer("type=xyz&url=http://127.0.0.1:9/{z}/{x}/{y}.png", "tiles", "wms")
    assert tiles.isValid()
    QgsProject.instance().addMapLayer(tiles)
    m.dem_combo.setLayer(tiles)
    m.program_edit.setPlainText(SLOPE_PROGRAM)
    assert not m.validate_program() and m.layer_sources()["dem"] is None
    assert "the layer 'tiles' in DEM (elevation) is not a raster file" in _status(dock)


def _save_clear_read(m, path: Path) -> None:
    """Save the project, clear it (the DEM fields empty), open it again, unchanged."""
    project = QgsProject.instance()
    assert project.isDirty()
    assert project.write(str(path))
    project.clear()
    assert m.dem_combo.currentLayer() is None and m.dem_file_widget.filePath() == ""
    assert project.read(str(path))
    assert not project.isDirty()


def test_the_project_keeps_the_dem(dock, tmp_path) -> None:
    _add_sample_layers(dock)
    m = dock.mission
    dem = sample_dem(tmp_path)
    QgsProject.instance().addMapLayer(QgsRasterLayer(str(dem), "my dem"))
    m.prompt_edit.setPlainText("prefer roads")
    m.dem_combo.setLayer(QgsProject.instance().mapLayersByName("my dem")[0])
    _save_clear_read(m, tmp_path / "layer.qgz")
    assert m.dem_combo.currentLayer().name() == "my dem" and m.dem_path() == str(dem)

    m.dem_combo.setLayer(None)
    m.dem_file_widget.setFilePath(str(dem))
    _save_clear_read(m, tmp_path / "file.qgz")
    assert m.dem_combo.currentLayer() is None and m.dem_file_widget.filePath() == str(dem)
