"""``overseec:costmap`` with its DEM parameter: the same costmap as ``overseec costmap --dem``."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import rasterio
from qgis.core import QgsProcessingException
from rasterio.transform import Affine

from overseec_core.cli import main as cli_main

from ..synthesize.test_compose import utm_grid
from ..synthesize.test_terrain import write_dem
from .processing_fixtures import *  # noqa: F403 (the fixtures: private settings, provider, project)
from .test_processing import read, run

pytestmark = pytest.mark.qgis


PROGRAM = 'cost = where(M["road"], 0.1, 0.5)\ncost = max(cost, normalize(slope, 15, 30))'


@pytest.fixture
def scene(tmp_path: Path) -> dict[str, Path]:
    """Labels (a road band on grass) and a 0.5 m DEM: flat west of 30 m, a 45 degree ramp east."""
    from overseec_core.io.write import write_array

    grid = utm_grid(60, 40, 1.0, 1.0)
    labels = np.full(grid.shape, 2, np.uint8)
    labels[18:22] = 1
    write_array(tmp_path / "gt.tif", labels, grid)
    (tmp_path / "classes.json").write_text(json.dumps({"1": "road", "2": "grass"}))
    t = grid.transform * Affine.translation(-4.25, -4.25) * Affine.scale(0.5)
    rows, cols = np.mgrid[0:176, 0:256]
    x, _ = t * (cols + 0.5, rows + 0.5)
    z = np.maximum(x - grid.transform.c - 30.0, 0.0) + 120.0
    return {"dir": tmp_path, "dem": write_dem(tmp_path / "dem.tif", z, grid.crs, t)}


def test_costmap_takes_a_dem_as_the_cli_does(provider, scene) -> None:
    d = scene["dir"]
    params = {"LABELS": str(d / "gt.tif"), "CLASSES": str(d / "classes.json"), "PROGRAM_TEXT": PROGRAM}
    res = run("costmap", {**params, "DEM": str(scene["dem"]), "OUTPUT": str(d / "q" / "c.tif")})
    cost = read(res["OUTPUT"])[0]
    assert cost[20, 5] == pytest.approx(0.1) and cost[5, 50] == pytest.approx(1.0)
    (d / "p.txt").write_text(PROGRAM + "\n")
    cli = ["costmap", "--labels", str(d / "gt.tif"), "--classes", str(d / "classes.json"), "--program"]
    assert cli_main([*cli, str(d / "p.txt"), "--dem", str(scene["dem"]), "--out", str(d / "c.tif")]) == 0
    np.testing.assert_array_equal(cost, read(d / "c.tif")[0])
    with rasterio.open(res["OUTPUT"]) as ds:
        assert ds.tags()["OVERSEEC_DEM_FILE"] == str(scene["dem"])


def test_costmap_without_the_dem_names_the_parameter(provider, scene) -> None:
    d = scene["dir"]
    params = {"LABELS": str(d / "gt.tif"), "CLASSES": str(d / "classes.json"), "PROGRAM_TEXT": PROGRAM}
    with pytest.raises(QgsProcessingException, match="--dem"):
        run("costmap", {**params, "OUTPUT": str(d / "q" / "c.tif")})
