"""The first-use environment check: what it finds (packages, model weights), what it advises."""

from __future__ import annotations

import json
import subprocess
import textwrap
from pathlib import Path

import pytest

import overseec_core
from overseec_qgis import venvs
from overseec_qgis.envcheck import (
    SETUP_ACTION,
    check_worker,
    ensure_core_importable,
    project_dir_of,
    segment_problem,
)
from overseec_qgis.worker import candidate_workers, find_worker, worker_python

from .conftest import REPO

pytestmark = pytest.mark.qgis

SYSTEM_PYTHON = Path("/usr/bin/python3")


def test_no_worker_offers_the_set_up_action() -> None:
    report = check_worker(None)
    assert not report.ok and not report.models_ok and report.setup_helps
    assert "not found" in report.problems[0]
    assert report.advice[0].startswith(SETUP_ACTION)
    assert "environment OK" not in report.text()


@pytest.mark.skipif(not SYSTEM_PYTHON.exists(), reason="needs Debian's /usr/bin/python3")
def test_an_environment_without_torch_or_the_core_gets_exact_commands(tmp_path: Path) -> None:
    """A 'venv' whose python is Debian's bare interpreter: no overseec_core, no torch."""
    bin_dir = tmp_path / "venv" / "bin"
    bin_dir.mkdir(parents=True)
    (bin_dir / "python3").symlink_to(SYSTEM_PYTHON)
    worker = bin_dir / "overseec"
    worker.write_text("#!/bin/sh\nexit 0\n")
    worker.chmod(0o755)
    report = check_worker(worker)
    assert not report.ok and not report.models_ok and report.setup_helps
    assert report.modules["overseec_core"] is None and report.modules["torch"] is None
    assert report.advice[0].startswith(SETUP_ACTION)
    assert f"{tmp_path / 'venv' / 'bin' / 'pip'} install overseec[models]" in "\n".join(report.advice)
    assert any("segmentation needs torch and transformers" in p for p in report.problems)
    assert report.weights == {}  # no core, so nothing could say where the models are


def test_a_windows_conda_environment_keeps_its_interpreter_at_the_root(tmp_path: Path) -> None:
    """conda on Windows: ``<env>/python.exe`` with the entry points in ``Scripts/``; the worker's
    interpreter is that one, never QGIS's own."""
    env = tmp_path / "condaenv"
    (env / "Scripts").mkdir(parents=True)
    (env / "python.exe").write_text("")
    exe = env / "Scripts" / "overseec.exe"
    exe.write_text("")
    assert venvs.python(env) == env / "python.exe"
    assert worker_python(exe) == env / "python.exe"


@pytest.mark.skipif(not SYSTEM_PYTHON.exists(), reason="needs Debian's /usr/bin/python3")
def test_a_windows_layout_venv_is_found_and_checked(tmp_path: Path, monkeypatch) -> None:
    """Scripts/python.exe, Scripts/overseec.exe and Lib/site-packages: the layout comes from
    the folder, not from the platform the plugin runs on."""
    venv = tmp_path / "winvenv"
    scripts = venv / "Scripts"
    scripts.mkdir(parents=True)
    (venv / "Lib" / "site-packages").mkdir(parents=True)
    (scripts / "python.exe").symlink_to(SYSTEM_PYTHON)
    exe = scripts / "overseec.exe"
    exe.write_text("#!/bin/sh\nexit 0\n")
    exe.chmod(0o755)
    assert venvs.layout(venv) == venvs.WINDOWS and venvs.python(venv) == scripts / "python.exe"
    assert venvs.site_packages(venv) == [venv / "Lib" / "site-packages"]
    monkeypatch.delenv("OVERSEEC_WORKER", raising=False)
    assert ("environment", exe) in candidate_workers(venv=str(venv))
    assert find_worker(venv=str(venv)) == exe
    assert worker_python(exe) == scripts / "python.exe"
    report = check_worker(exe)
    assert report.python and report.modules["numpy"]  # the probe really ran python.exe
    assert f"{scripts / 'pip.exe'} install overseec[models]" in "\n".join(report.advice)
    # a POSIX venv next to it keeps bin/
    (tmp_path / "posix" / "bin").mkdir(parents=True)
    assert venvs.executable(tmp_path / "posix", "pip") == tmp_path / "posix" / "bin" / "pip"


def _fake_model(folder: Path, model_type: str) -> Path:
    """A model folder as resolve_model checks it: config.json with the type, a weights file."""
    folder.mkdir(parents=True)
    (folder / "config.json").write_text(json.dumps({"model_type": model_type}))
    (folder / "model.safetensors").write_bytes(b"")
    return folder


def test_missing_weights_are_named_with_how_to_provide_a_copied_folder(tmp_path: Path, monkeypatch) -> None:
    worker = REPO / ".venv" / "bin" / "overseec"
    if not worker.exists():
        pytest.skip("no project venv")
    monkeypatch.setenv("HF_HOME", str(tmp_path / "empty-hf-home"))  # no cached hub models
    clipseg = _fake_model(tmp_path / "copied-clipseg", "clipseg")
    report = check_worker(worker, clipseg_model=str(clipseg), sam_model="")
    assert report.weights["clipseg"]["ok"] and report.weights["clipseg"]["path"] == str(clipseg)
    assert report.missing_weights == ("SAM",) and not report.all_ok
    assert "environment OK" not in report.text()
    assert any("SAM (facebook/sam-vit-base)" in p for p in report.problems)
    assert any("SAM model to that folder" in a and "--sam-model" in a for a in report.advice)
    assert any("HF_HOME" in a for a in report.advice)
    assert not report.setup_helps  # installing packages does not bring weights
    # both missing: both named (the CLI alone stops at the first one)
    both = segment_problem(worker, clipseg_model="", sam_model="")
    assert "CLIPSeg (CIDAS/clipseg-rd64-refined) and SAM (facebook/sam-vit-base)" in both
    assert "CLIPSeg model / SAM model" in both
    # without refinement SAM is not needed; a copied folder for each model makes it whole
    assert segment_problem(worker, clipseg_model=str(clipseg), refine=False) == ""
    sam = _fake_model(tmp_path / "copied-sam", "sam")
    whole = check_worker(worker, clipseg_model=str(clipseg), sam_model=str(sam))
    if whole.models_ok:
        assert whole.all_ok and "environment OK" in whole.text(), whole.text()


@pytest.mark.parametrize(
    "refiner, default, model_type, label",
    [
        ("sam", "facebook/sam-vit-base", "sam", "SAM"),
        ("sam-hq", "syscv-community/sam-hq-vit-base", "sam_hq", "SAM-HQ"),
        ("sam2", "facebook/sam2.1-hiera-tiny", "sam2", "SAM 2"),
    ],
)
def test_the_chosen_refiners_default_model_is_checked(tmp_path: Path, monkeypatch, refiner, default, model_type, label):
    """Each refiner has its own default checkpoint; a copied folder must be of the refiner's kind."""
    from overseec_core.locate.refiners import REFINERS

    assert REFINERS[refiner].default_model == default
    worker = REPO / ".venv" / "bin" / "overseec"
    if not worker.exists():
        pytest.skip("no project venv")
    monkeypatch.setenv("HF_HOME", str(tmp_path / "empty-hf-home"))
    clipseg = str(_fake_model(tmp_path / "clipseg", "clipseg"))
    report = check_worker(worker, clipseg_model=clipseg, refiner=refiner, weights_only=True)
    assert report.weights[refiner] == {"name": default, "ok": False, "error": report.weights[refiner]["error"]}
    assert report.missing_weights == (label,)
    problem = segment_problem(worker, clipseg_model=clipseg, refiner=refiner)
    assert f"{label} ({default})" in problem and "SAM model" in problem
    own = str(_fake_model(tmp_path / refiner, model_type))
    assert check_worker(worker, clipseg_model=clipseg, sam_model=own, refiner=refiner, weights_only=True).weights[
        refiner
    ]["ok"]
    other = "sam2" if refiner != "sam2" else "sam"
    wrong = str(_fake_model(tmp_path / "wrong", "sam2" if other == "sam2" else "sam"))
    mismatch = check_worker(worker, clipseg_model=clipseg, sam_model=wrong, refiner=refiner, weights_only=True)
    assert not mismatch.weights[refiner]["ok"]  # a SAM 2 folder is no SAM checkpoint, and back
    assert segment_problem(worker, clipseg_model=clipseg, refiner=refiner, refine=False) == ""


@pytest.mark.models
def test_the_project_venv_passes_and_reports_its_device(tmp_path: Path) -> None:
    worker = REPO / ".venv" / "bin" / "overseec"
    if not worker.exists():
        pytest.skip("no project venv")
    clipseg = _fake_model(tmp_path / "clipseg", "clipseg")
    sam = _fake_model(tmp_path / "sam", "sam")
    report = check_worker(worker, clipseg_model=str(clipseg), sam_model=str(sam))
    assert report.ok and report.models_ok and report.all_ok, report.text()
    assert report.modules["overseec_core"] == overseec_core.__version__
    assert report.modules["torch"] and report.modules["transformers"]
    assert report.device in ("cpu", "cuda", "mps")
    assert "environment OK" in report.text()
    assert project_dir_of(worker) == REPO


def test_core_packages_are_borrowed_from_the_venv_when_qgis_python_lacks_them(tmp_path: Path) -> None:
    """Debian's Python (QGIS's) has no shapely/scikit-image; the project's venv supplies them,
    appended to sys.path so QGIS's own numpy and GDAL bindings keep precedence."""
    if not SYSTEM_PYTHON.exists() or not (REPO / ".venv").is_dir():
        pytest.skip("needs Debian's /usr/bin/python3 and the project venv")
    probe = subprocess.run([str(SYSTEM_PYTHON), "-c", "import shapely"], capture_output=True)
    if probe.returncode == 0:
        pytest.skip("this Python already has shapely")
    script = textwrap.dedent(f"""
        import sys
        sys.path.insert(0, {str(REPO)!r})
        import numpy
        from overseec_qgis.envcheck import ensure_core_importable
        bare = ensure_core_importable(None)
        print(bare.ok, "; ".join(bare.advice))
        ok = ensure_core_importable({str(REPO / ".venv")!r})
        import shapely, skimage
        print(ok.ok, shapely.__file__.startswith({str(REPO / ".venv")!r}), numpy.__file__.startswith("/usr/lib"))
    """)
    done = subprocess.run(
        [str(SYSTEM_PYTHON), "-I", "-c", script], capture_output=True, text=True, timeout=120, cwd=tmp_path
    )
    assert done.returncode == 0, done.stderr
    bare, borrowed = done.stdout.strip().splitlines()
    assert bare.startswith("False") and SETUP_ACTION in bare and "scikit-image" in bare
    assert borrowed == "True True True"
    assert ensure_core_importable(None).ok  # this (venv) interpreter has everything
