"""`overseec plan --dem DEM.tif --slope-model ...`: anisotropic routes through the command line.

A DEM in another resolution is resampled onto the costmap grid; the route's cost differs by
direction, ``length_m`` counts the climb next to ``length_2d_m``, the manifest records the DEM
and the model; cells the DEM does not cover are impassable; misuse is a one-line error.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from rasterio.crs import CRS
from rasterio.transform import from_origin

from overseec_core.cli import main
from overseec_core.plan import _kernel

from ..plan.conftest import UTM_ORIGIN, write_costmap
from ..synthesize.test_terrain import write_dem as write_terrain_dem

pytestmark = pytest.mark.skipif(_kernel is None, reason="the slope models need the compiled kernel")
PX = 0.5


def write_dem(path: Path, z: np.ndarray, pixel: float, origin=UTM_ORIGIN) -> Path:
    """A float32 DEM GeoTIFF in UTM 33N metres."""
    return write_terrain_dem(path, z, CRS.from_epsg(32633), from_origin(*origin, pixel, pixel), nodata=-9999.0)


def pt(r: int, c: int) -> list[str]:
    """Map coordinates of pixel (r, c)'s centre on the costmap grid."""
    return [str(UTM_ORIGIN[0] + (c + 0.5) * PX), str(UTM_ORIGIN[1] - (r + 0.5) * PX)]


@pytest.fixture
def scene(tmp_path: Path) -> dict[str, Path]:
    """A 30 x 60 costmap (0.5 m pixels) and a 1 m DEM rising 0.2 m per metre eastwards, reaching
    beyond the grid on every side (so every cell has an elevation)."""
    costmap = write_costmap(tmp_path / "cost.tif", np.full((30, 60), 0.4, dtype=np.float32))
    cols = np.arange(34)[None, :] * np.ones((19, 1))
    dem = write_dem(tmp_path / "dem.tif", 100.0 + 0.2 * (cols - 2) * 1.0, 1.0, (UTM_ORIGIN[0] - 2, UTM_ORIGIN[1] + 2))
    return {"costmap": costmap, "dem": dem}


def _plan(tmp_path: Path, name: str, costmap: Path, a, b, *extra: str) -> tuple[int, dict, dict]:
    out = tmp_path / name / "route.geojson"
    args = ["--quiet", "plan", str(costmap), "--start", *pt(*a), "--goal", *pt(*b), "--out", str(out), *extra]
    rc = main(args)
    if rc != 0:
        return rc, {}, {}
    props = json.loads(out.read_text())["features"][0]["properties"]
    return rc, props, json.loads((out.parent / "manifest.json").read_text())


@pytest.mark.parametrize("model", ["tobler", "vehicle"])
def test_plan_on_a_dem_prices_direction_counts_the_climb_and_records_the_model(
    tmp_path: Path, scene: dict[str, Path], model: str
) -> None:
    dem = str(scene["dem"])
    rc, up, manifest = _plan(tmp_path, "up", scene["costmap"], (15, 2), (15, 57), "--dem", dem, "--slope-model", model)
    assert rc == 0
    rc, down, _ = _plan(tmp_path, "down", scene["costmap"], (15, 57), (15, 2), "--dem", dem, "--slope-model", model)
    assert rc == 0
    assert up["total_cost"] > down["total_cost"]  # a 20 % climb: dearer than the descent either way
    assert up["length_2d_m"] == pytest.approx(55 * PX)
    assert up["length_m"] == pytest.approx(55 * PX * np.hypot(1.0, 0.2), rel=1e-3)
    assert up["slope_model"] == model
    assert manifest["parameters"]["plan"]["slope_model"] == model
    assert manifest["parameters"]["plan"]["dem"] == dem
    assert any(k.startswith("plan_dem_") for k in manifest["inputs"])
    assert manifest["plan"]["length_2d_m"] == pytest.approx(55 * PX)
    rc, flat, manifest = _plan(tmp_path, "flat", scene["costmap"], (15, 2), (15, 57))
    assert rc == 0 and "slope_model" not in flat and manifest["parameters"]["plan"]["slope_model"] is None
    assert flat["length_m"] == pytest.approx(55 * PX)


def test_default_model_is_tobler_and_cells_without_elevation_are_impassable(tmp_path: Path, scene, capsys) -> None:
    # a DEM covering only the western half of the grid (30 m x 15 m from the origin: columns < 30)
    half = write_dem(tmp_path / "half.tif", np.full((15, 15), 50.0), 1.0)
    rc, props, _ = _plan(tmp_path, "ok", scene["costmap"], (5, 2), (25, 20), "--dem", str(half))
    assert rc == 0 and props["slope_model"] == "tobler"
    assert props["length_m"] == pytest.approx(props["length_2d_m"])  # flat DEM: 3D = 2D
    capsys.readouterr()
    rc, _, _ = _plan(tmp_path, "off", scene["costmap"], (5, 2), (5, 50), "--dem", str(half))
    err = capsys.readouterr().err.strip()
    assert rc != 0 and "no elevation" in err and "\n" not in err


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--slope-model", "tobler"], "--slope-model needs --dem"),
        (["--dem", "DEM", "--smooth"], "--smooth"),
        (["--dem", "FAR"], "does not overlap"),
    ],
)
def test_misuse_is_a_one_line_error(tmp_path: Path, scene, capsys, extra: list[str], message: str) -> None:
    far = write_dem(tmp_path / "far.tif", np.zeros((5, 5)), 1.0, (UTM_ORIGIN[0] + 5000, UTM_ORIGIN[1]))
    extra = [{"DEM": str(scene["dem"]), "FAR": str(far)}.get(e, e) for e in extra]
    capsys.readouterr()
    rc, _, _ = _plan(tmp_path, "bad", scene["costmap"], (15, 2), (15, 57), *extra)
    err = capsys.readouterr().err.strip()
    assert rc != 0 and message in err and "\n" not in err
