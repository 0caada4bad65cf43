"""The whole pipeline, as `overseec run` and `overseec demo` drive it."""

from __future__ import annotations

import json
from pathlib import Path

import fiona
import numpy as np
import pytest
import rasterio

from overseec_core import sample
from overseec_core.cli import EXIT_USER, main
from overseec_core.io.read import read_grid


@pytest.fixture(scope="module")
def small_scene(tmp_path_factory) -> sample.SampleScene:
    return sample.generate(tmp_path_factory.mktemp("scene"), size=256, seed=0)


def _run_on_labels(scene: sample.SampleScene, out: Path, prompt: str) -> dict:
    meta = json.loads(scene.meta.read_text())
    argv = [
        "--quiet",
        "run",
        str(scene.image),
        "--prompt",
        prompt,
        "--offline",
        "--labels",
        str(scene.labels),
        "--classes",
        str(scene.classes),
        "--start",
        *map(str, meta["start"]),
        "--goal",
        *map(str, meta["goal"]),
        "--reference",
        str(scene.reference),
        "--pairs",
        "3",
        "--out",
        str(out),
    ]
    assert main(argv) == 0
    return json.loads((out / "evaluation" / "metrics.json").read_text())


def test_run_on_known_labels_writes_every_stage(small_scene, tmp_path: Path) -> None:
    out = tmp_path / "run"
    metrics = _run_on_labels(small_scene, out, sample.PROMPT)
    for name in (
        "interpretation.json",
        "costmap.tif",
        "lethal.tif",
        "costmap.program.txt",
        "path.geojson",
        "path_native.gpkg",
        "manifest.json",
        "evaluation/report.md",
    ):
        assert (out / name).exists(), name
    manifest = json.loads((out / "manifest.json").read_text())
    assert {"interpret", "costmap"} <= set(manifest["stages"])
    assert all(s["status"] == "ok" for s in manifest["stages"].values())
    assert manifest["inputs"]["image"]["sha256"]
    assert read_grid(out / "costmap.tif").same_as(read_grid(small_scene.image))
    with rasterio.open(out / "costmap.tif") as ds:
        cost = ds.read(1)
    assert np.nanmin(cost) >= 0 and np.nanmax(cost) <= 1
    path = json.loads((out / "path.geojson").read_text())["features"][0]
    assert path["geometry"]["type"] == "LineString" and path["properties"]["mode"] == "exact"
    # the labels are the masks here: nothing to score them against, so no IoU (`overseec eval
    # --masks` scores segmented masks); RRPI and Hausdorff are measured
    assert "iou" not in metrics and {"summary", "kde", "hausdorff"} <= set(metrics)
    evaluation = json.loads((out / "evaluation" / "manifest.json").read_text())
    assert {"eval_labels", "eval_classes", "eval_costmap", "eval_reference"} <= set(evaluation["inputs"])
    assert "eval_masks" not in evaluation["inputs"] and not (out / "evaluation" / "iou.png").exists()


def test_the_prompt_steers_the_route(small_scene, tmp_path: Path) -> None:
    """'Prefer the roads' follows the reference route along the roads; 'avoid the roads' leaves it."""
    along = _run_on_labels(small_scene, tmp_path / "along", sample.PROMPT)
    away = _run_on_labels(small_scene, tmp_path / "away", "avoid the roads as much as possible, grass is fine")
    near = along["hausdorff"]["mean_normalised"]
    far = away["hausdorff"]["mean_normalised"]
    assert near < 0.05 < far


def test_run_plans_with_the_steps_asked_for(small_scene, tmp_path: Path, capsys) -> None:
    """`run --neighbours 16` plans its route as `plan --neighbours 16` does on the run's costmap."""
    meta = json.loads(small_scene.meta.read_text())
    ends = ["--start", *map(str, meta["start"]), "--goal", *map(str, meta["goal"])]
    out = tmp_path / "run"
    argv = ["--quiet", "run", str(small_scene.image), "--prompt", sample.PROMPT, "--offline"]
    argv += ["--labels", str(small_scene.labels), "--classes", str(small_scene.classes), *ends]
    assert main([*argv, "--neighbours", "16", "--no-eval", "--out", str(out)]) == 0
    route = json.loads((out / "path.geojson").read_text())["features"][0]["properties"]
    costs = {}
    for steps in ("8", "16"):
        single = tmp_path / steps / "path.geojson"
        plan = ["--quiet", "plan", str(out / "costmap.tif"), *ends, "--neighbours", steps]
        assert main([*plan, "--out", str(single)]) == 0
        costs[steps] = json.loads(single.read_text())["features"][0]["properties"]["total_cost"]
    capsys.readouterr()
    assert route["total_cost"] == costs["16"] < costs["8"]
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["parameters"]["plan"]["neighbours"] == 16


def test_run_needs_classes_with_labels(small_scene, tmp_path: Path, capsys) -> None:
    assert (
        main(
            [
                "run",
                str(small_scene.image),
                "--prompt",
                "prefer roads",
                "--labels",
                str(small_scene.labels),
                "--out",
                str(tmp_path / "x"),
            ]
        )
        == EXIT_USER
    )
    err = capsys.readouterr().err
    assert "--labels and --classes go together" in err and err.count("\n") == 1


def test_demo_runs_on_the_bundled_sample(tmp_path: Path, capsys) -> None:
    assert main(["--quiet", "demo", "--out", str(tmp_path / "demo"), "--pairs", "2"]) == 0
    out = capsys.readouterr().out
    assert "road 1, trail 1, grass 2" in out and "path.geojson" in out
    assert (tmp_path / "demo" / "evaluation" / "paths_overlay.png").stat().st_size > 10_000


@pytest.mark.models
def test_run_segments_with_models(tmp_path: Path) -> None:
    """Image + prompt all the way through CLIPSeg, SAM, costmap and plan (tiny random models)."""
    pytest.importorskip("transformers")
    from tests.locate.builders import save_clipseg, save_sam

    scene = sample.generate(tmp_path / "scene", size=96, seed=1)
    clipseg = save_clipseg(tmp_path / "clipseg")
    sam = save_sam(tmp_path / "sam")
    meta = json.loads(scene.meta.read_text())
    out = tmp_path / "run"
    argv = [
        "--quiet",
        "run",
        str(scene.image),
        "--prompt",
        "prefer the roads, avoid the water",
        "--offline",
        "--clipseg-model",
        str(clipseg),
        "--sam-model",
        str(sam),
        "--tile-size",
        "64",
        "--device",
        "cpu",
        "--start",
        *map(str, meta["start"]),
        "--goal",
        *map(str, meta["goal"]),
        "--out",
        str(out),
    ]
    assert main(argv) == 0
    with rasterio.open(out / "probs.tif") as ds:
        names = set(ds.descriptions)
    assert {"road", "water", "grass"} <= names
    for name in ("masks.tif", "refined_masks.tif", "gated.tif", "costmap.tif", "path.geojson"):
        assert read_grid(out / name).same_as(read_grid(scene.image)) if name.endswith(".tif") else (out / name).exists()
    manifest = json.loads((out / "manifest.json").read_text())
    assert {"segment", "refine", "costmap"} <= set(manifest["stages"])
    assert "clipseg" in manifest["models"] and "sam" in manifest["models"]


def test_run_json_and_the_prompt_in_every_path(small_scene, tmp_path: Path, capsys) -> None:
    """`run --json` prints the pipeline's result; the prompt that made the costmap is in its tags,
    so the path files carry it (GPX/KML tracks are named after it) and re-plans find it."""
    meta = json.loads(small_scene.meta.read_text())
    points = ["--start", *map(str, meta["start"]), "--goal", *map(str, meta["goal"])]
    labels = ["--labels", str(small_scene.labels), "--classes", str(small_scene.classes)]
    out = tmp_path / "run"
    prompt = "prefer the roads, avoid the water"
    capsys.readouterr()
    assert (
        main(
            ["-q", "run", str(small_scene.image), "--prompt", prompt, *labels, *points, "--pairs", "2"]
            + ["--out", str(out), "--json"]
        )
        == 0
    )
    doc = json.loads(capsys.readouterr().out)
    assert doc["prompt"] == doc["interpretation"]["prompt"] == prompt
    assert doc["out_dir"] == str(out) and doc["manifest"] == str(out / "manifest.json") and doc["masks"] is None
    assert doc["costmap"]["costmap"] == str(out / "costmap.tif")
    assert doc["plan"]["prompt"] == prompt and doc["plan"]["outputs"]["geojson"] == str(out / "path.geojson")
    assert "rrpi" in json.dumps(doc["evaluation"]["metrics"]) and doc["evaluation"]["files"]["report"]
    with rasterio.open(out / "costmap.tif") as ds:
        assert ds.tags()["OVERSEEC_PROMPT"] == prompt
    assert json.loads((out / "manifest.json").read_text())["parameters"]["costmap"]["prompt"] == prompt
    props = json.loads((out / "path.geojson").read_text())["features"][0]["properties"]
    assert props["prompt"] == prompt
    with fiona.open(out / "path_native.gpkg", layer="path") as layer:
        assert next(iter(layer))["properties"]["prompt"] == prompt
    gpx = tmp_path / "gpx" / "path.gpx"
    assert main(["-q", "export", "path", str(out / "path.geojson"), "--to", "gpx", "--out", str(gpx)]) == 0
    assert f"<name>{prompt}</name>" in gpx.read_text()
    # a re-plan elsewhere, away from the run's manifest, still knows the prompt from the costmap
    alone = tmp_path / "alone"
    alone.mkdir()
    for name in ("costmap.tif", "lethal.tif"):
        (alone / name).write_bytes((out / name).read_bytes())
    replanned = tmp_path / "replan" / "p.geojson"
    assert main(["-q", "plan", str(alone / "costmap.tif"), *points, "--out", str(replanned)]) == 0
    assert json.loads(replanned.read_text())["features"][0]["properties"]["prompt"] == prompt
