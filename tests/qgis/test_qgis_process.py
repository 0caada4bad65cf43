"""End to end: the built plugin zip, enabled in a throw-away profile, run by ``qgis_process.bin``.

These are the README's commands. Debian's ``/usr/bin/qgis_process`` wrapper fails on bookworm,
so the binary is called directly. The profile lives in tmp_path (QGIS_CUSTOM_CONFIG_PATH and
HOME), never in the user's.
"""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
import rasterio

from overseec_core.cli import main as cli_main

from .conftest import REPO, SAMPLE

pytestmark = [
    pytest.mark.qgis,
    pytest.mark.skipif(shutil.which("qgis_process.bin") is None, reason="needs qgis_process.bin"),
]

PROMPT = json.loads((SAMPLE / "sample.json").read_text())["prompt"]
META = json.loads((SAMPLE / "sample.json").read_text())


@pytest.fixture(scope="module")
def qgis_process(tmp_path_factory):
    """A function running `qgis_process.bin ARGS` with the plugin unpacked and enabled."""
    root = tmp_path_factory.mktemp("qgis_process")
    spec = importlib.util.spec_from_file_location("build_plugin", REPO / "scripts" / "build_plugin.py")
    builder = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(builder)
    builder.extract(builder.build(root / "overseec.zip"), root / "plugins")
    env = {k: v for k, v in os.environ.items() if not k.startswith("QGIS_")}
    env.update(
        QT_QPA_PLATFORM="offscreen",
        HOME=str(root / "home"),
        QGIS_PLUGINPATH=str(root / "plugins"),
        QGIS_CUSTOM_CONFIG_PATH=str(root / "profile"),
        OVERSEEC_VENV=str(REPO / ".venv"),
    )

    def run(*args: str, check: bool = True) -> subprocess.CompletedProcess:
        done = subprocess.run(
            ["qgis_process.bin", *args], capture_output=True, text=True, env=env, cwd=root, timeout=300
        )
        if check:
            assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
        return done

    enabled = run("plugins", "enable", "overseec")
    assert "overseec" in enabled.stdout
    ini = root / "profile" / "profiles" / "default" / "QGIS" / "QGIS3.ini"
    assert "overseec=true" in ini.read_text(), "the plugin was not enabled in the throw-away profile"
    run.root = root
    return run


def test_qgis_process_lists_every_algorithm(qgis_process) -> None:
    out = qgis_process("list").stdout
    for alg in ("interpret", "segment", "costmap", "plan", "run", "evaluate", "exportcostmap", "exportpath", "compare"):
        assert f"overseec:{alg}" in out


def test_qgis_process_costmap_and_plan_match_the_cli(qgis_process, tmp_path: Path) -> None:
    out = tmp_path / "q"
    inputs = Path(shutil.copytree(SAMPLE, tmp_path / "in"))  # QGIS writes .aux.xml statistics beside inputs
    done = qgis_process(
        "--json",
        "run",
        "overseec:costmap",
        "--",
        f"LABELS={inputs / 'sample_labels.tif'}",
        f"CLASSES={inputs / 'classes.json'}",
        f"PROMPT={PROMPT}",
        f"OUTPUT={out / 'costmap.tif'}",
    )
    results = json.loads(done.stdout)["results"]
    assert results["OUTPUT"] == str(out / "costmap.tif")
    assert (
        cli_main(
            [
                "costmap",
                "--labels",
                str(SAMPLE / "sample_labels.tif"),
                "--classes",
                str(SAMPLE / "classes.json"),
                "--prompt",
                PROMPT,
                "--out",
                str(tmp_path / "cli.tif"),
            ]
        )
        == 0
    )
    with rasterio.open(results["OUTPUT"]) as a, rasterio.open(tmp_path / "cli.tif") as b:
        np.testing.assert_array_equal(a.read(), b.read())

    (sx, sy), (gx, gy) = META["start"], META["goal"]
    done = qgis_process(
        "--json",
        "run",
        "overseec:plan",
        "--",
        f"COSTMAP={out / 'costmap.tif'}",
        f"START={sx},{sy} [EPSG:32633]",
        f"GOAL={gx},{gy} [EPSG:32633]",
        "MODE=1",
        f"OUTPUT={out / 'path.geojson'}",
    )
    results = json.loads(done.stdout)["results"]
    assert (
        cli_main(
            [
                "plan",
                str(out / "costmap.tif"),
                "--start",
                str(sx),
                str(sy),
                "--goal",
                str(gx),
                str(gy),
                "--mode",
                "exact",
                "--out",
                str(tmp_path / "cli.geojson"),
            ]
        )
        == 0
    )
    cli = json.loads((tmp_path / "cli.geojson").read_text())["features"][0]
    assert results["COST"] == pytest.approx(cli["properties"]["total_cost"])
    assert json.loads(Path(results["OUTPUT"]).read_text())["features"][0]["geometry"] == cli["geometry"]


def test_qgis_process_reports_a_user_error_in_one_line(qgis_process, tmp_path: Path) -> None:
    done = qgis_process(
        "run",
        "overseec:costmap",
        "--",
        f"LABELS={SAMPLE / 'sample_labels.tif'}",
        f"CLASSES={SAMPLE / 'classes.json'}",
        "PROGRAM_TEXT=cost = where(M['lava'], 1, 0)",
        f"OUTPUT={tmp_path / 'c.tif'}",
        check=False,
    )
    assert done.returncode != 0
    text = done.stdout + done.stderr
    assert "lava" in text and "Traceback" not in text
    assert not (tmp_path / "c.tif").exists()
