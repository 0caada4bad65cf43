"""Fixtures for the QGIS plugin tests (pytest-qgis, offscreen).

Tiny georeferenced scenes are written into tmp_path with the core's own writer; the plugin is
loaded through its ``classFactory`` against pytest-qgis's stub iface and unloaded afterwards.
Screenshots and other artefacts go to $OVERSEEC_ARTIFACTS (default tests/artifacts/).
"""

from __future__ import annotations

import atexit
import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from rasterio.crs import CRS
from rasterio.transform import from_origin

from overseec_core.io.grid import Grid
from overseec_core.io.write import write_array

REPO = Path(__file__).resolve().parents[2]


def _private_sample() -> Path:
    """A copy of resources/sample for this test session, removed at exit.

    QGIS writes GDAL statistics (``*.aux.xml``) beside the rasters it opens; tests must never
    write into the repository, so they open this copy instead.
    """
    folder = Path(tempfile.mkdtemp(prefix="overseec-sample-"))
    atexit.register(shutil.rmtree, folder, True)
    return Path(shutil.copytree(REPO / "resources" / "sample", folder / "sample"))


SAMPLE = _private_sample()
ORIGIN = (534_000.0, 5_213_000.0)  # UTM 33N, like the bundled sample
PIXEL = 0.5
ENTITIES = ("road", "grass", "water")


def artifacts_dir() -> Path:
    path = Path(os.environ.get("OVERSEEC_ARTIFACTS", REPO / "tests" / "artifacts"))
    path.mkdir(parents=True, exist_ok=True)
    return path


@dataclass(frozen=True)
class Scene:
    """A small synthetic run directory: image, masks, probabilities and a costmap."""

    folder: Path
    image: Path
    masks: Path
    probs: Path
    costmap: Path
    grid: Grid

    def world(self, row: float, col: float) -> tuple[float, float]:
        """Map coordinates (EPSG:32633) of a pixel centre."""
        x, y = self.grid.transform * (col + 0.5, row + 0.5)
        return float(x), float(y)


def make_scene(folder: Path, height: int = 48, width: int = 64) -> Scene:
    """Grass everywhere, a road along row 10 and column 50, a water block in the middle.

    The water is lethal (``lethal.tif`` beside the costmap, as the costmap stage writes it) and
    sits on the straight line from the lower left to the upper right.
    """
    folder.mkdir(parents=True, exist_ok=True)
    grid = Grid(CRS.from_epsg(32633), from_origin(*ORIGIN, PIXEL, PIXEL), width, height)
    road = np.zeros((height, width), bool)
    road[10, 5:] = True
    road[10:, 50] = True
    water = np.zeros((height, width), bool)
    water[18:34, 20:40] = True
    grass = ~(road | water)
    masks = np.stack([road, grass, water]).astype(np.uint8)
    probs = np.where(masks > 0, 0.9, 0.1).astype(np.float32)
    cost = np.where(road, 0.05, 0.5).astype(np.float32)
    cost[water] = 1.0
    rng = np.random.default_rng(7)
    rgb = np.stack(
        [
            masks[0] * 90 + masks[1] * 96 + masks[2] * 46,
            masks[0] * 90 + masks[1] * 140 + masks[2] * 84,
            masks[0] * 96 + masks[1] * 62 + masks[2] * 118,
        ]
    ).astype(np.int16)
    rgb = np.clip(rgb + rng.integers(-8, 9, rgb.shape), 0, 255).astype(np.uint8)
    image = write_array(folder / "image.tif", rgb, grid)
    write_array(folder / "lethal.tif", water.astype(np.uint8), grid)  # the planner's sidecar
    return Scene(
        folder=folder,
        image=image,
        masks=write_array(folder / "masks.tif", masks, grid, nodata=255, descriptions=ENTITIES),
        probs=write_array(folder / "probs.tif", probs, grid, descriptions=ENTITIES),
        costmap=write_array(folder / "costmap.tif", cost, grid),
        grid=grid,
    )


@pytest.fixture
def scene(tmp_path: Path) -> Scene:
    return make_scene(tmp_path / "run")


def wait_until(predicate, timeout_s: float = 60.0, what: str = "condition") -> None:
    """Process Qt events until ``predicate()`` is true (tasks report back through the loop)."""
    from qgis.PyQt.QtCore import QCoreApplication

    deadline = time.monotonic() + timeout_s
    while not predicate():
        if time.monotonic() > deadline:
            raise AssertionError(f"timed out after {timeout_s:g} s waiting for {what}")
        QCoreApplication.processEvents()
        time.sleep(0.01)


@pytest.fixture(scope="session")
def tiny_clipseg(tmp_path_factory) -> Path:
    """A tiny random CLIPSeg (the segment tests' builder, tests/locate/builders.py), built in a
    subprocess so that this process -- standing in for QGIS -- never imports torch."""
    if any(importlib.util.find_spec(m) is None for m in ("torch", "transformers")):
        pytest.skip("needs torch and transformers in the worker environment")
    folder = tmp_path_factory.mktemp("models") / "tiny-clipseg"
    code = (
        "import sys; from pathlib import Path; from tests.locate.builders import save_clipseg; "
        "save_clipseg(Path(sys.argv[1]))"
    )
    done = subprocess.run(
        [sys.executable, "-c", code, str(folder)], cwd=REPO, capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr
    return folder


@pytest.fixture(scope="session", autouse=True)
def private_qgis_settings(qgis_app):
    """QgsSettings of this test process's own (a private organisation name, file removed at the
    end): tests never read or change the user's QGIS settings, and concurrent test processes on
    one machine never see each other's worker, venv or model settings."""
    from qgis.core import QgsSettings
    from qgis.PyQt.QtCore import QCoreApplication

    before = QCoreApplication.organizationName()
    QCoreApplication.setOrganizationName(f"overseec-tests-{os.getpid()}")
    yield
    Path(QgsSettings().fileName()).unlink(missing_ok=True)
    QCoreApplication.setOrganizationName(before)


@pytest.fixture(autouse=True)
def canvas_idle_after_test(qgis_iface):
    """After each test, stop the test canvas's render job and wait until it has ended: the next
    test's fresh project deletes the layers, and a render thread still iterating a deleted vector
    layer's features crashes the process (QGIS's own canvas cancels its jobs when layers go; the
    pytest-qgis canvas is not wired to the project that way). The canvas also lets go of the
    layers, so a refresh scheduled meanwhile renders nothing."""
    from qgis.PyQt.QtCore import QCoreApplication

    yield
    canvas = qgis_iface.mapCanvas()
    canvas.stopRendering()
    canvas.setLayers([])  # a render the clearing itself schedules has nothing to read
    deadline = time.monotonic() + 30
    while canvas.isDrawing() and time.monotonic() < deadline:
        QCoreApplication.processEvents()
        time.sleep(0.01)


@pytest.fixture(autouse=True)
def tasks_drained_after_test(qgis_app):
    """After each test (and after the plugin's unload, which cancels the dock's jobs), wait until
    QGIS's task manager holds no task: a task left running holds one of the thread pool's threads
    (two on a two-core machine), and the next test's tasks would queue behind it. A task still
    there after a minute is cancelled, and named on stdout (the test left it hanging)."""
    from qgis.core import QgsApplication
    from qgis.PyQt.QtCore import QCoreApplication

    yield
    manager = QgsApplication.taskManager()

    def drained(timeout_s: float) -> bool:
        deadline = time.monotonic() + timeout_s
        while manager.countActiveTasks() and time.monotonic() < deadline:
            QCoreApplication.processEvents()
            time.sleep(0.01)
        return not manager.countActiveTasks()

    if not drained(60.0):
        print("tasks left running after the test:", "; ".join(t.description() for t in manager.activeTasks()))
        manager.cancelAll()
        drained(15.0)


@pytest.fixture
def plugin(qgis_iface, qgis_new_project):
    """The plugin, loaded like QGIS loads it (classFactory, initGui) and unloaded after."""
    from qgis.core import QgsSettings

    from overseec_qgis import classFactory

    QgsSettings().remove("overseec")  # start from the defaults, whatever an earlier session saved
    p = classFactory(qgis_iface)
    p.initGui()
    yield p
    p.unload()
