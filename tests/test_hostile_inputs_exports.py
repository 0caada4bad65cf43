"""Hostile inputs to exports and to the inputs every command opens (issue 23).

Each case runs the real console script (tests/test_hostile.py's helpers) and asserts the exit
status (2, or 130 when cancelled), exactly one ``overseec: error: ...`` line on stderr, no
traceback, and that no file was changed or added (SHA-256 before and after).
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import rasterio
from rasterio.transform import from_origin
from rasterio.warp import Resampling, calculate_default_transform, reproject

from tests import test_hostile
from tests.test_hostile import GIB, POINTS, _huge_vrt, assert_one_line_error, overseec, partial_files, snapshot

#: test_hostile's fixtures: the sample scene with its costmap, copied per test
scene_template = test_hostile.scene_template
scene = test_hostile.scene


def _refused(scene: Path, *argv: str, says: str, status: int = 2, **kw) -> subprocess.CompletedProcess:
    before = snapshot(scene)
    done = overseec(*argv, cwd=scene, timeout=kw.pop("timeout", 60), **kw)
    assert_one_line_error(done, status, says)
    assert "Traceback" not in done.stdout + done.stderr
    assert not partial_files(scene)
    assert snapshot(scene) == before, "a refused command changed or added a file"
    return done


# --------------------------------------------------------------------------------------------
# 1. Inputs are opened only when they are regular files
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "argv",
    [
        ("plan", "c/costmap.tif", *POINTS, "--override", "edits.gpkg", "--out", "p/p.geojson"),
        (
            "costmap",
            "--labels",
            "sample_labels.tif",
            "--classes",
            "classes.json",
            "--prompt",
            "prefer roads",
            "--override",
            "edits.gpkg",
            "--out",
            "e/c.tif",
        ),
        (
            "costmap",
            "--labels",
            "sample_labels.tif",
            "--classes",
            "classes.json",
            "--program",
            "edits.gpkg",
            "--out",
            "e/c.tif",
        ),
        (
            "costmap",
            "--labels",
            "sample_labels.tif",
            "--classes",
            "classes.json",
            "--vector",
            "road=edits.gpkg",
            "--prompt",
            "prefer roads",
            "--out",
            "e/c.tif",
        ),
    ],
    ids=["plan-override", "costmap-override", "costmap-program", "costmap-vector"],
)
def test_a_fifo_input_is_refused_not_waited_on(scene: Path, argv) -> None:
    os.mkfifo(scene / "edits.gpkg")
    t0 = time.monotonic()
    _refused(scene, *argv, says="named pipe", timeout=30)
    assert time.monotonic() - t0 < 30


def test_a_device_override_is_refused(scene: Path) -> None:
    _refused(scene, "plan", "c/costmap.tif", *POINTS, "--override", "/dev/zero", "--out", "p/p.geojson", says="device")


# --------------------------------------------------------------------------------------------
# 3. --lethal must be a one-band mask of integer (or 0/1 float) flags
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "argv, says",
    [
        (
            ("export", "costmap", "c/costmap.tif", "--to", "nav2", "--lethal", "sample.tif", "--out", "x/m.yaml"),
            "3 bands",
        ),
        (("plan", "c/costmap.tif", *POINTS, "--lethal", "sample.tif", "--out", "p/p.geojson"), "3 bands"),
        (
            ("export", "costmap", "c/costmap.tif", "--to", "npy", "--lethal", "c/costmap.tif", "--out", "x/a.npy"),
            "float values",
        ),
    ],
    ids=["export-rgb-photo", "plan-rgb-photo", "export-costmap-as-lethal"],
)
def test_lethal_must_be_a_one_band_mask(scene: Path, argv, says: str) -> None:
    _refused(scene, *argv, says=says)


def test_a_0_1_float_lethal_mask_is_still_accepted(scene: Path) -> None:
    with rasterio.open(scene / "c" / "lethal.tif") as ds:
        profile = dict(ds.profile, dtype="float32", nodata=None)
        flags = (ds.read(1) != 0).astype("float32")
    with rasterio.open(scene / "mask01.tif", "w", **profile) as ds:
        ds.write(flags, 1)
    done = overseec(
        "export", "costmap", "c/costmap.tif", "--to", "npy", "--lethal", "mask01.tif", "--out", "x/a.npy", cwd=scene
    )
    assert done.returncode == 0, done.stderr


# --------------------------------------------------------------------------------------------
# 4. Budgets apply to export path; a deeply nested path file is one line
# --------------------------------------------------------------------------------------------


def test_export_path_applies_the_pixel_budget(scene: Path) -> None:
    _huge_vrt(scene / "c" / "huge.vrt", scene / "c" / "costmap.tif", 2_000_000, "Float32")
    argv = ("export", "path", "reference_route.geojson", "--to", "csv", "--costmap", "c/huge.vrt", "--out", "x/p.csv")
    _refused(scene, *argv, says="pixel budget", memory_cap=4 * GIB)
    _refused(
        scene, "--max-pixels", "1000", *argv[:-2], "--costmap", "c/costmap.tif", "--out", "x/p.csv", says="pixel budget"
    )


def test_a_deeply_nested_path_file_is_one_line(scene: Path) -> None:
    (scene / "nested.geojson").write_text("[" * 200_000 + "]" * 200_000)
    _refused(scene, "export", "path", "nested.geojson", "--to", "gpx", "--out", "x/p.gpx", says="nested too deeply")


# --------------------------------------------------------------------------------------------
# 2. A Nav2 export of a large costmap stops soon after Ctrl-C
# --------------------------------------------------------------------------------------------


def test_ctrl_c_stops_a_large_nav2_scale_export_within_a_second(tmp_path: Path) -> None:
    n = 6000
    cost = np.random.default_rng(23).random((n, n), dtype=np.float32)
    profile = dict(driver="GTiff", width=n, height=n, count=1, dtype="float32", crs="EPSG:32633", tiled=True)
    with rasterio.open(tmp_path / "big.tif", "w", transform=from_origin(500000, 5200000, 0.5, 0.5), **profile) as ds:
        ds.write(cost, 1)
    del cost
    before = snapshot(tmp_path)
    proc = subprocess.Popen(
        [sys.executable, "-m", "overseec_core.console", "-q", "export", "costmap", "big.tif", "--to", "nav2"]
        + ["--nav2-mode", "scale", "--out", "nav2/map.yaml"],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    time.sleep(4.0)  # imports and loading (~2 s): encoding the map takes ~10 s more
    assert proc.poll() is None, "the export finished before the signal"
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    stopped = time.monotonic() - sent
    assert proc.returncode == 130, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("overseec: error: ") and "cancelled" in lines[0], err
    assert "Traceback" not in out + err
    assert stopped < 1.5, f"stopped {stopped:.1f} s after Ctrl-C"
    assert snapshot(tmp_path) == before and not partial_files(tmp_path)


# --------------------------------------------------------------------------------------------
# 5. The reprojection advice for Nav2 works when followed
# --------------------------------------------------------------------------------------------


def test_nav2_advice_for_web_mercator_is_a_utm_zone_that_exports(scene: Path) -> None:
    with rasterio.open(scene / "c" / "costmap.tif") as ds:
        t, w, h = calculate_default_transform(ds.crs, "EPSG:3857", ds.width, ds.height, *ds.bounds)
        merc = np.full((h, w), np.nan, dtype="float32")
        reproject(ds.read(1), merc, src_transform=ds.transform, src_crs=ds.crs, dst_transform=t, dst_crs="EPSG:3857",
                  resampling=Resampling.nearest)  # fmt: skip
        profile = dict(ds.profile, crs="EPSG:3857", transform=t, width=w, height=h, nodata=None)
    (scene / "m").mkdir()
    with rasterio.open(scene / "m" / "merc.tif", "w", **profile) as ds:
        ds.write(merc, 1)
    done = _refused(scene, "export", "costmap", "m/merc.tif", "--to", "nav2", "--out", "x/map.yaml", says="gdalwarp")
    advice = re.search(r"gdalwarp -t_srs (EPSG:\d+) -tr (\S+) (\S+) ", done.stderr)
    assert advice, done.stderr
    target, size = advice.group(1), float(advice.group(2))
    assert re.fullmatch(r"EPSG:32[67]\d\d", target), target  # the UTM zone of the map's centre
    # follow the advice (rasterio's reproject: gdalwarp -t_srs TARGET -tr SIZE SIZE -r near)
    with rasterio.open(scene / "m" / "merc.tif") as ds:
        t2, w2, h2 = calculate_default_transform(ds.crs, target, ds.width, ds.height, *ds.bounds, resolution=size)
        utm = np.full((h2, w2), np.nan, dtype="float32")
        reproject(ds.read(1), utm, src_transform=ds.transform, src_crs=ds.crs, dst_transform=t2, dst_crs=target,
                  src_nodata=np.nan, dst_nodata=np.nan, resampling=Resampling.nearest)  # fmt: skip
        profile = dict(ds.profile, crs=target, transform=t2, width=w2, height=h2, nodata=np.nan)
    (scene / "metric").mkdir()
    with rasterio.open(scene / "metric" / "merc.tif", "w", **profile) as ds:
        ds.write(utm, 1)
    done = overseec("export", "costmap", "metric/merc.tif", "--to", "nav2", "--out", "x/map.yaml", cwd=scene)
    assert done.returncode == 0, done.stderr
    assert (scene / "x" / "map.yaml").exists() and (scene / "x" / "map.pgm").exists()
