"""`overseec info` and `overseec doctor`, and the CLI's error contract (one line, exit 2)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from overseec_core.cli import EXIT_USER, main

from ..conftest import write_tif

OVERSEEC = Path(sys.executable).with_name("overseec")


def test_info_json_has_the_documented_keys(rgb_tif: Path, capsys) -> None:
    assert main(["info", str(rgb_tif), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    for key in ("crs", "width", "height", "count", "dtypes", "pixel_size_m"):
        assert key in info
    assert info["crs"] == "EPSG:32633" and (info["width"], info["height"], info["count"]) == (300, 200, 3)
    assert info["pixel_size_m"] == [0.5, 0.5] and info["dtypes"] == ["uint8"] * 3
    assert info["read_plan"]["rgb_bands"] == [1, 2, 3]


def test_info_table_on_the_bundled_sample(capsys) -> None:
    sample = Path(__file__).resolve().parents[2] / "resources" / "sample" / "sample.tif"
    assert main(["info", str(sample)]) == 0
    out = capsys.readouterr().out
    assert "EPSG:32633" in out and "1024 x 1024" in out and "0.5 m x 0.5 m" in out


def test_info_prints_bounds_at_full_precision(tmp_path: Path, capsys) -> None:
    """The bounds line gives every digit (copyable into --start/--goal or a clip), not 6."""
    from rasterio.transform import from_origin

    left, top = 534012.3456789, 5212999.9876543
    path = write_tif(tmp_path / "i.tif", np.zeros((3, 4, 8), np.uint8), transform=from_origin(left, top, 0.25, 0.25))
    assert main(["info", str(path)]) == 0
    (line,) = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("bounds")]
    assert line.split(None, 1)[1] == f"{left!r}, {top - 1.0!r}, {left + 2.0!r}, {top!r}"
    assert main(["info", str(path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["bounds"] == [left, top - 1.0, left + 2.0, top]


@pytest.mark.parametrize(
    "make,match",
    [
        (lambda d: d / "missing.tif", "no such file"),
        (lambda d: (d / "empty.tif").write_bytes(b"") == 0 and d / "empty.tif", "empty"),
        (lambda d: (d / "text.tif").write_text("not a raster") > 0 and d / "text.tif", "not a readable raster"),
        (lambda d: write_tif(d / "nocrs.tif", np.zeros((3, 4, 4), np.uint8), crs=None), "--assume-crs"),
        (lambda d: write_tif(d / "six.tif", np.zeros((6, 4, 4), np.uint8)), "--bands"),
    ],
)
def test_bad_inputs_give_one_line_and_exit_2(tmp_path: Path, capsys, make, match) -> None:
    path = make(tmp_path)
    assert main(["info", str(path)]) == EXIT_USER
    err = capsys.readouterr().err
    assert err.startswith("overseec: error: ") and match in err
    assert err.count("\n") == 1 and "Traceback" not in err


def test_assume_crs_and_bands_options(tmp_path: Path, capsys) -> None:
    path = write_tif(tmp_path / "ms.tif", np.zeros((5, 4, 4), np.uint16), crs=None)
    assert main(["info", str(path), "--assume-crs", "EPSG:3857", "--bands", "4,3,2", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["crs"] == "EPSG:3857" and info["crs_assumed"] and info["read_plan"]["rgb_bands"] == [4, 3, 2]
    assert main(["info", str(path), "--assume-crs", "EPSG:nope"]) == EXIT_USER
    assert "not a CRS" in capsys.readouterr().err


def test_console_script_runs_in_a_subprocess(rgb_tif: Path) -> None:
    done = subprocess.run([str(OVERSEEC), "info", "--json", str(rgb_tif)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["width"] == 300
    bad = subprocess.run([str(OVERSEEC), "info", str(rgb_tif) + ".nope"], capture_output=True, text=True, timeout=120)
    assert bad.returncode == 2 and bad.stderr.strip() == f"overseec: error: no such file: {rgb_tif}.nope"


def test_doctor_reports_versions_and_an_unreachable_llm(capsys) -> None:
    assert main(["doctor", "--json", "--llm-url", "http://127.0.0.1:9"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["versions"]["gdal"] and report["versions"]["numpy"] == np.__version__
    assert report["device"]["device"] in ("cpu", "cuda", "mps")
    assert report["llm"]["reachable"] is False


def _cache_model(cache: Path, repo_id: str, files: dict[str, str]) -> None:
    """A Hugging Face hub cache entry laid out as huggingface_hub writes it (refs/main -> snapshot)."""
    repo = cache / ("models--" + repo_id.replace("/", "--"))
    commit = "0123456789abcdef0123456789abcdef01234567"
    (repo / "refs").mkdir(parents=True)
    (repo / "refs" / "main").write_text(commit)
    snapshot = repo / "snapshots" / commit
    snapshot.mkdir(parents=True)
    for name, text in files.items():
        (snapshot / name).write_text(text)


def defaults_of(segmenters, name: str) -> str:
    """The registry's default model of segmenter ``name``."""
    return segmenters[name].default_model


def test_doctor_reports_which_default_models_are_in_the_cache(tmp_path: Path, monkeypatch, capsys) -> None:
    """Against a real (temporary) hub cache: CLIPSeg cached, SAM with an entry but no config.json
    (an interrupted download), so present / missing each come from the cache's contents; every
    registered segmenter's default model is listed with what it is for."""
    from overseec_core.locate.refiners import REFINERS
    from overseec_core.locate.segmenters import SEGMENTERS

    constants = pytest.importorskip("huggingface_hub.constants")
    cache = tmp_path / "hub"
    _cache_model(cache, "CIDAS/clipseg-rd64-refined", {"config.json": '{"model_type": "clipseg"}'})
    _cache_model(cache, "facebook/sam-vit-base", {"preprocessor_config.json": "{}"})
    monkeypatch.setattr(constants, "HF_HUB_CACHE", str(cache))
    assert main(["doctor", "--json"]) == 0
    models = json.loads(capsys.readouterr().out)["models"]
    defaults = {info.default_model: info.name for info in SEGMENTERS.values()}
    refiners = {info.default_model: f"refine ({info.name})" for info in REFINERS.values()}
    assert models == {
        "cache": str(cache),
        "present": {m: m == "CIDAS/clipseg-rd64-refined" for m in {**defaults, **refiners}},
        "roles": {**defaults, **refiners},
    }
    assert refiners["facebook/sam-vit-base"] == "refine (sam)" and len(refiners) == 3
    assert defaults["google/owlv2-base-patch16-ensemble"] == "boxes+sam"
    assert main(["doctor"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert f"{'model cache':<13} {cache}" in lines
    assert any(line.split() == ["clipseg", "CIDAS/clipseg-rd64-refined", "present"] for line in lines)
    assert any(
        line.split()
        == [
            "refine",
            "(sam)",
            "facebook/sam-vit-base",
            "missing:",
            "overseec",
            "models",
            "download",
            "facebook/sam-vit-base",
        ]
        for line in lines
    )
    assert any(line.split()[:3] == ["semantic", defaults_of(SEGMENTERS, "semantic"), "missing:"] for line in lines)
    assert any(line.split()[:3] == ["refine", "(sam2)", REFINERS["sam2"].default_model] for line in lines)
    monkeypatch.setattr(constants, "HF_HUB_CACHE", str(tmp_path / "empty"))
    assert main(["doctor", "--json"]) == 0
    assert not any(json.loads(capsys.readouterr().out)["models"]["present"].values())
