"""`overseec segment`: outputs and manifest, one-line errors, JSON progress in a subprocess."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import rasterio

pytest.importorskip("torch")

from overseec_core.cli import main

from .conftest import write_geotiff

REPO = Path(__file__).resolve().parents[2]
OVERSEEC = Path(sys.executable).parent / "overseec"


def models(tiny_clipseg: Path, tiny_sam: Path) -> list[str]:
    return ["--clipseg-model", str(tiny_clipseg), "--sam-model", str(tiny_sam), "--device", "cpu", "--tile-size", "96"]


def test_segment_and_refine_with_manifest(tiny_clipseg, tiny_sam, tmp_path, capsys) -> None:
    from overseec_core.sample import generate

    scene = generate(tmp_path / "scene", size=256)
    out = tmp_path / "run"
    code = main(
        [
            "-q",
            "segment",
            str(scene.image),
            "--entity",
            "road:linear",
            "--entity",
            "baseball field:areal",
            "--entity",
            "tree",
            "--threshold",
            "tree=0.6",
            "--out",
            str(out),
            "--json",
            *models(tiny_clipseg, tiny_sam),
        ]
    )
    assert code == 0, capsys.readouterr().err
    doc = json.loads(capsys.readouterr().out)
    assert doc["segment"]["thresholds"] == [0.4, 0.8, 0.6]
    names = {"probs.tif", "masks.tif", "refined_probs.tif", "refined_masks.tif", "gated.tif", "manifest.json"}
    assert names <= {p.name for p in out.iterdir()}
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["stages"]["segment"]["status"] == manifest["stages"]["refine"]["status"] == "ok"
    assert manifest["models"]["clipseg"]["path"] == str(tiny_clipseg.resolve())
    assert manifest["models"]["sam"]["model_type"] == "sam"
    assert manifest["segment"]["device"].startswith("cpu") and manifest["segment"]["tile_size"] == 96
    assert manifest["segment"]["overlap"] == 12  # 1/8 of the tile by default
    assert [e["name"] for e in manifest["entities"]] == ["road", "baseball field", "tree"]
    assert len(manifest["inputs"]["image"]["sha256"]) == 64
    with rasterio.open(scene.image) as src, rasterio.open(out / "gated.tif") as g:
        assert (g.crs, g.transform, g.width, g.height) == (src.crs, src.transform, src.width, src.height)
        assert g.descriptions == ("road", "baseball field", "tree")


def test_no_refine_and_entities_json(tiny_clipseg, tiny_sam, tmp_path, capsys) -> None:
    image = write_geotiff(tmp_path / "img.tif", 120, 100)
    doc = {
        "prompt": "prefer roads",
        "entities": [
            {"name": "road", "geometry": "linear", "prompts": ["road", "street"]},
            {"name": "water", "geometry": "areal", "threshold": 0.7},
        ],
    }
    spec = tmp_path / "interpretation.json"
    spec.write_text(json.dumps(doc))
    out = tmp_path / "run"
    assert (
        main(
            [
                "-q",
                "segment",
                str(image),
                "--entities-json",
                str(spec),
                "--no-refine",
                "--out",
                str(out),
                *models(tiny_clipseg, tiny_sam),
            ]
        )
        == 0
    )
    printed = capsys.readouterr().out
    assert "probs.tif" in printed and "refined_probs" not in printed
    assert sorted(p.name for p in out.iterdir()) == ["manifest.json", "masks.tif", "probs.tif"]
    with rasterio.open(out / "masks.tif") as m, rasterio.open(out / "probs.tif") as p:
        probs, masks = p.read(), m.read()
    np.testing.assert_array_equal(masks[1], probs[1] >= 0.7)
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["entities"][0]["prompts"] == ["road", "street"]
    assert "refine" not in manifest["stages"]


@pytest.mark.parametrize(
    "args, message",
    [
        ([], "no entities to segment"),
        (["--entity", "road:lineal"], "geometry must be linear or areal"),
        (["--entity", "road", "--entity", "Road:linear"], "duplicate entity name 'Road'"),
        (["--entity", "road", "--threshold", "river=0.3"], "--threshold for unknown entity 'river'"),
        (["--entity", "road", "--threshold", "road=2"], "expected NAME=VALUE with 0 < VALUE < 1"),
        (["--entity", "road", "--device", "tpu"], "unknown device 'tpu'"),
        (["--entity", "road", "--clipseg-model", "{bare}"], "has no weights"),
        (["--entity", "road", "--clipseg-model", "{sam}"], "unsupported model type 'sam'"),
        (["--entity", "road", "--entities-json", "{missing}"], "no such file"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(args, message, tiny_clipseg, tiny_sam, tmp_path, capsys) -> None:
    image = write_geotiff(tmp_path / "img.tif", 64, 64)
    bare = tmp_path / "bare"
    bare.mkdir()
    (bare / "config.json").write_text((tiny_clipseg / "config.json").read_text())
    fill = {"bare": str(bare), "sam": str(tiny_sam), "missing": str(tmp_path / "nope.json")}
    argv = [
        "segment",
        str(image),
        "--out",
        str(tmp_path / "out"),
        "--clipseg-model",
        str(tiny_clipseg),
        "--sam-model",
        str(tiny_sam),
    ] + [a.format(**fill) for a in args]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("overseec: error:") and message in err
    assert len(err.splitlines()) == 1


def test_subprocess_json_progress(tiny_clipseg, tiny_sam, tmp_path) -> None:
    """The way the QGIS plugin drives it: its own process, JSON lines on stdout."""
    image = write_geotiff(tmp_path / "img.tif", 200, 150)
    out = tmp_path / "run"
    env = dict(os.environ, OMP_NUM_THREADS="1")
    done = subprocess.run(
        [
            str(OVERSEEC),
            "--json-progress",
            "segment",
            str(image),
            "--entity",
            "road:linear",
            "--entity",
            "tree",
            "--out",
            str(out),
            *models(tiny_clipseg, tiny_sam),
        ],
        capture_output=True,
        text=True,
        cwd=REPO,
        env=env,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    # JSON events, then the human summary (the plugin keeps non-JSON lines as log text)
    events = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
    stages = [(e["event"], e.get("stage")) for e in events if e["event"] in ("begin", "end")]
    assert stages == [("begin", "segment"), ("end", "segment"), ("begin", "refine"), ("end", "refine")]
    progress = [e for e in events if e["event"] == "progress" and e["stage"] == "segment"]
    assert progress[-1]["done"] == progress[-1]["total"] == 6 and "eta_s" in progress[-1]
    assert any(e["event"] == "message" and "CLIPSeg" in e["text"] for e in events)
    assert (out / "gated.tif").exists()


def test_missing_sam_fails_before_any_work(tiny_clipseg, tmp_path, capsys) -> None:
    image = write_geotiff(tmp_path / "img.tif", 64, 64)
    out = tmp_path / "out"
    assert (
        main(
            [
                "segment",
                str(image),
                "--entity",
                "road",
                "--out",
                str(out),
                "--clipseg-model",
                str(tiny_clipseg),
                "--sam-model",
                str(tmp_path / "no-sam"),
            ]
        )
        == 2
    )
    assert "sam model" in capsys.readouterr().err
    assert not (out / "probs.tif").exists()


def test_compute_switches_reach_both_stages() -> None:
    """--device, --precision and --compile set CLIPSeg's and SAM's options alike; --no-refine
    leaves SAM out."""
    from overseec_core.cli import build_parser
    from overseec_core.commands.segment import stage_options

    parser = build_parser()
    args = parser.parse_args(["segment", "x.tif", "--out", "o", "--device", "cpu", "--precision", "fp32", "--compile"])
    clipseg, sam = stage_options(args)
    assert sam is not None
    assert (clipseg.device, clipseg.precision, clipseg.compile) == ("cpu", "fp32", True)
    assert (sam.device, sam.precision, sam.compile) == ("cpu", "fp32", True)
    plain, no_sam = stage_options(parser.parse_args(["segment", "x.tif", "--out", "o", "--no-refine"]))
    assert no_sam is None and plain.compile is False and plain.device == "auto"


def test_sam_decoder_batch_reaches_the_refine_options() -> None:
    """--sam-decoder-batch sets the components per decoder call (GPU memory); unset it is auto."""
    from overseec_core.cli import build_parser
    from overseec_core.commands.segment import stage_options

    parser = build_parser()
    _, sam = stage_options(parser.parse_args(["segment", "x.tif", "--out", "o", "--sam-decoder-batch", "16"]))
    assert sam is not None and sam.params.decoder_batch == 16
    assert sam.params.components_per_call(on_gpu=True) == 16
    _, auto = stage_options(parser.parse_args(["segment", "x.tif", "--out", "o"]))
    assert auto is not None and auto.params.decoder_batch is None
    assert (auto.params.components_per_call(on_gpu=True), auto.params.components_per_call(on_gpu=False)) == (64, 4)


def test_refiner_choice_reaches_segment_and_run() -> None:
    """--refiner (the refiners' table) and --sam-model (None: the refiner's default) reach the
    RefineOptions of `segment`, `run` and `demo`; an unknown refiner is an argparse error."""
    from overseec_core.cli import build_parser
    from overseec_core.commands.run import options_from_args
    from overseec_core.commands.segment import stage_options
    from overseec_core.locate.refiners import REFINERS

    parser = build_parser()
    _, default = stage_options(parser.parse_args(["segment", "x.tif", "--out", "o"]))
    assert default is not None and (default.refiner, default.sam_model) == ("sam", None)
    assert default.model_name == REFINERS["sam"].default_model
    _, hq = stage_options(parser.parse_args(["segment", "x.tif", "--out", "o", "--refiner", "sam-hq"]))
    assert hq is not None and (hq.refiner, hq.model_name) == ("sam-hq", REFINERS["sam-hq"].default_model)
    run_args = ["run", "x.tif", "--prompt", "p", "--out", "o", "--refiner", "sam2", "--sam-model", "/m"]
    refine = options_from_args(parser.parse_args(run_args)).refine
    assert refine is not None and (refine.refiner, refine.sam_model) == ("sam2", "/m")
    assert parser.parse_args(["demo", "--segment", "--refiner", "sam2"]).refiner == "sam2"
    with pytest.raises(SystemExit):
        parser.parse_args(["segment", "x.tif", "--out", "o", "--refiner", "sam3"])


def test_segment_with_the_sam2_refiner(tiny_clipseg, tmp_path, capsys) -> None:
    """`segment --refiner sam2` refines with a SAM 2 checkpoint end to end; the manifest says so."""
    from . import builders_refiners

    sam2 = builders_refiners.save_sam2(tmp_path / "tiny-sam2")
    image = write_geotiff(tmp_path / "img.tif", 160, 128)
    out = tmp_path / "run"
    args = ["-q", "segment", str(image), "--entity", "road:linear", "--out", str(out), "--json"]
    args += ["--clipseg-model", str(tiny_clipseg), "--refiner", "sam2", "--sam-model", str(sam2)]
    assert main([*args, "--device", "cpu", "--tile-size", "96"]) == 0, capsys.readouterr().err
    doc = json.loads(capsys.readouterr().out)
    assert doc["refine"]["refiner"] == "sam2" and doc["refine"]["model"]["model_type"] == "sam2"
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["stages"]["refine"]["status"] == "ok"


def _polygons(path: Path) -> dict[str, list[tuple[int, float]]]:
    """Each layer of a GeoPackage: its polygons' (pixels, mean_prob), sorted."""
    import fiona

    return {
        name: sorted(
            (f["properties"]["pixels"], round(f["properties"]["mean_prob"], 6)) for f in fiona.open(path, layer=name)
        )
        for name in fiona.listlayers(path)
    }


def test_segment_vectors_writes_the_masks_as_polygons(tiny_clipseg, tiny_sam, tmp_path, capsys) -> None:
    """--vectors writes masks.gpkg (one layer per entity) from the refined masks, the polygons
    `overseec vectorize` makes of the same folder; the manifest records it beside the stages."""
    from overseec_core import runfiles

    image = write_geotiff(tmp_path / "img.tif", 160, 128)
    out = tmp_path / "run"
    args = ["-q", "segment", str(image), "--entity", "road:linear", "--entity", "grass:areal", "--out", str(out)]
    assert main([*args, "--vectors", "--json", *models(tiny_clipseg, tiny_sam)]) == 0, capsys.readouterr().err
    doc = json.loads(capsys.readouterr().out)
    gpkg = out / runfiles.MASK_POLYGONS
    assert doc["vectors"]["out"] == str(gpkg) and doc["refine"] is not None
    assert doc["vectors"]["inputs"][0].endswith(runfiles.REFINED_MASKS)  # refined over coarse
    layers = _polygons(gpkg)
    assert list(layers) == ["road", "grass"]
    again = tmp_path / "again.gpkg"
    assert main(["-q", "vectorize", str(out), "--out", str(again)]) == 0
    assert _polygons(again) == layers
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["stages"]["refine"]["status"] == "ok"
    assert manifest["vectors"][runfiles.MASK_POLYGONS]["polygons"] == sum(len(v) for v in layers.values())
    capsys.readouterr()
    assert main([*args, "--no-refine", *models(tiny_clipseg, tiny_sam)[:2], "--device", "cpu", "--vectors"]) == 0
    assert f"         {gpkg}" in capsys.readouterr().out.splitlines()


def test_segment_vectors_failing_leaves_no_rasters(tiny_clipseg, tiny_sam, tmp_path, capsys) -> None:
    """Vectors and rasters are one write: when masks.gpkg cannot be written (a folder is in the
    way), the run folder is left as it was, without probs.tif or masks.tif."""
    from overseec_core import runfiles

    image = write_geotiff(tmp_path / "img.tif", 160, 128)
    out = tmp_path / "run"
    (out / runfiles.MASK_POLYGONS).mkdir(parents=True)
    args = ["-q", "segment", str(image), "--entity", "road:linear", "--out", str(out), "--no-refine", "--vectors"]
    assert main([*args, "--clipseg-model", str(tiny_clipseg), "--device", "cpu"]) != 0
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    assert sorted(p.name for p in out.iterdir()) == [runfiles.MASK_POLYGONS]


def test_gsd_and_box_flags_reach_run_as_they_reach_segment() -> None:
    """`run --gsd --box-threshold --max-boxes` give the pipeline's SegmentOptions the same fields
    `segment` gets (the flags are parsed by both; run used to drop them)."""
    from overseec_core.cli import build_parser
    from overseec_core.commands.options import segmenter_settings
    from overseec_core.commands.run import options_from_args

    flags = ["--segmenter", "boxes+sam", "--gsd", "0.3", "--box-threshold", "0.2", "--max-boxes", "7"]
    parser = build_parser()
    seg_args = parser.parse_args(["segment", "x.tif", "--out", "o", *flags])
    segment = options_from_args(parser.parse_args(["run", "x.tif", "--prompt", "p", "--out", "o", *flags])).segment
    assert segment is not None
    for name, value in segmenter_settings(seg_args).items():
        assert getattr(segment, name) == value, name
    assert (segment.box_threshold, segment.max_boxes) == (0.2, 7)
