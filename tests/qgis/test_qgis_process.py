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
    # PRIORS and NO_PRIORS contradict each other: the command's own one line says so
    table = tmp_path / "priors.json"
    table.write_text('{"building": 0.9}')
    done = qgis_process(
        "run",
        "overseec:costmap",
        "--",
        f"LABELS={SAMPLE / 'sample_labels.tif'}",
        f"CLASSES={SAMPLE / 'classes.json'}",
        "PROMPT=avoid the baseball field",
        f"PRIORS={table}",
        "NO_PRIORS=true",
        f"OUTPUT={tmp_path / 'p.tif'}",
        check=False,
    )
    text = done.stdout + done.stderr
    assert done.returncode != 0 and "--no-priors: not allowed with argument --priors" in text, text[-2000:]
    assert "Traceback" not in text and not (tmp_path / "p.tif").exists()


def _model(tmp_path: Path, name: str, children) -> Path:
    """A Graphical Modeler model file: ``children`` are (child id, algorithm, {param: source}),
    a source being a static value or ("child", output); the last child's OUTPUT is the model's
    output ``saved``. Outputs of the other children are left to the model: temporary outputs."""
    from qgis.core import QgsProcessingModelAlgorithm, QgsProcessingModelChildAlgorithm, QgsProcessingModelOutput
    from qgis.core import QgsProcessingModelChildParameterSource as Source

    model = QgsProcessingModelAlgorithm(name, "tests")
    for i, (child_id, alg_id, params) in enumerate(children):
        child = QgsProcessingModelChildAlgorithm(alg_id)
        child.setChildId(child_id)
        for key, value in params.items():
            src = Source.fromChildOutput(*value) if isinstance(value, tuple) else Source.fromStaticValue(value)
            child.addParameterSources(key, [src])
        if i == len(children) - 1:
            out = QgsProcessingModelOutput("saved", "saved")
            out.setChildId(child_id)
            out.setChildOutputName("OUTPUT")
            child.setModelOutputs({"saved": out})
        model.addChildAlgorithm(child)
    model.updateDestinationParameters()
    path = tmp_path / f"{name}.model3"
    assert model.toFile(str(path))
    return path


def test_qgis_process_costmap_and_plan_with_temporary_outputs(qgis_process, tmp_path: Path) -> None:
    """Costmap and Plan with their default temporary outputs, chained in a model that qgis_process
    runs: the next algorithm opens each temporary output as a layer (a GeoTIFF, then a
    GeoPackage line), and the path saved from the plan's layer keeps its cost."""
    import fiona

    inputs = Path(shutil.copytree(SAMPLE, tmp_path / "in"))
    (sx, sy), (gx, gy) = META["start"], META["goal"]
    model = _model(
        tmp_path,
        "costmap_plan",
        [
            (
                "costmap",
                "overseec:costmap",
                {
                    "LABELS": str(inputs / "sample_labels.tif"),
                    "CLASSES": str(inputs / "classes.json"),
                    "PROMPT": PROMPT,
                },
            ),
            (
                "plan",
                "overseec:plan",
                {
                    "COSTMAP": ("costmap", "OUTPUT"),
                    "START": f"{sx},{sy} [EPSG:32633]",
                    "GOAL": f"{gx},{gy} [EPSG:32633]",
                    "MODE": 1,
                },
            ),
            ("save", "native:savefeatures", {"INPUT": ("plan", "OUTPUT")}),
        ],
    )
    out = tmp_path / "saved.gpkg"
    done = qgis_process("--json", "run", str(model), "--", f"save:saved={out}")
    log = done.stdout + done.stderr
    assert "OUTPUT.gpkg" in log and "OUTPUT.tif" in log  # the temporary outputs the children wrote
    with fiona.open(out) as src:
        (feature,) = list(src)
        assert src.crs.to_epsg() == 32633 and feature["geometry"]["type"] == "LineString"
    assert feature["properties"]["total_cost"] > 0 and feature["properties"]["length_m"] > 300


def test_qgis_process_plan_alone_with_a_temporary_output(qgis_process, tmp_path: Path) -> None:
    (sx, sy), (gx, gy) = META["start"], META["goal"]
    costmap = tmp_path / "c.tif"
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
                str(costmap),
            ]
        )
        == 0
    )
    done = qgis_process(
        "--json",
        "run",
        "overseec:plan",
        "--",
        f"COSTMAP={costmap}",
        f"START={sx},{sy} [EPSG:32633]",
        f"GOAL={gx},{gy} [EPSG:32633]",
        "OUTPUT=TEMPORARY_OUTPUT",
    )
    results = json.loads(done.stdout)["results"]
    assert results["OUTPUT"].endswith(".gpkg") and results["COST"] > 0 and results["LENGTH_M"] > 300


def test_qgis_process_run_into_a_temporary_folder(qgis_process, tmp_path: Path) -> None:
    """`run` into a temporary run folder, in a model: its path opens as a layer for the next
    algorithm (in a project the run's layers arrive as one group; qgis_process has no project)."""
    import fiona

    (sx, sy), (gx, gy) = META["start"], META["goal"]
    model = _model(
        tmp_path,
        "run_save",
        [
            (
                "run",
                "overseec:run",
                {
                    "INPUT": str(SAMPLE / "sample.tif"),
                    "PROMPT": PROMPT,
                    "LABELS": str(SAMPLE / "sample_labels.tif"),
                    "CLASSES": str(SAMPLE / "classes.json"),
                    "START": f"{sx},{sy} [EPSG:32633]",
                    "GOAL": f"{gx},{gy} [EPSG:32633]",
                    "EVALUATE": False,
                },
            ),
            # (the path's list-valued 'waypoints' property has no GeoPackage field type)
            ("keep", "native:retainfields", {"INPUT": ("run", "PATH"), "FIELDS": ["total_cost", "mode"]}),
            ("save", "native:savefeatures", {"INPUT": ("keep", "OUTPUT")}),
        ],
    )
    out = tmp_path / "run_path.gpkg"
    qgis_process("--json", "run", str(model), "--", f"save:saved={out}")
    with fiona.open(out) as src:
        (feature,) = list(src)
    assert feature["properties"]["mode"] == "exact" and feature["properties"]["total_cost"] > 0


def test_qgis_process_help_says_what_is_needed(qgis_process) -> None:
    text = qgis_process("help", "overseec:costmap").stdout
    assert "Needs: entity layers (MASKS, or LABELS + CLASSES, or both)" in text
    assert "LABELS: Entity layers: class raster (integer ids)\n\ta classified raster" in text  # parameter help
    assert "PRIORS: Priors of unsaid hazards (JSON file)\n\ta JSON object of entity -> prior level" in text
    assert "NO_PRIORS: No priors (unsaid hazards are neutral)" in text
