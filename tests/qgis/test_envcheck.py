"""The first-use environment check: what it finds, and the exact commands it suggests."""

from __future__ import annotations

import subprocess
import textwrap
from pathlib import Path

import pytest

import overseec_core
from overseec_qgis.envcheck import check_worker, ensure_core_importable, project_dir_of

from .conftest import REPO

pytestmark = pytest.mark.qgis

SYSTEM_PYTHON = Path("/usr/bin/python3")


def test_no_worker_says_to_run_make_setup() -> None:
    report = check_worker(None)
    assert not report.ok and not report.models_ok
    assert "not found" in report.problems[0]
    assert any("make setup" in a for a in report.advice)
    assert "to fix, run: make setup" in report.text()


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
    assert not report.ok and not report.models_ok
    assert report.modules["overseec_core"] is None and report.modules["torch"] is None
    text = "\n".join(report.advice)
    assert f"{tmp_path / 'venv' / 'bin' / 'pip'} install -e" in text
    assert "torch transformers safetensors" in text
    assert any("segmentation needs torch and transformers" in p for p in report.problems)


@pytest.mark.models
def test_the_project_venv_passes_and_reports_its_device() -> None:
    worker = REPO / ".venv" / "bin" / "overseec"
    if not worker.exists():
        pytest.skip("no project venv")
    report = check_worker(worker)
    assert report.ok and report.models_ok, report.text()
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
    assert bare.startswith("False") and "make setup" in bare and "scikit-image" in bare
    assert borrowed == "True True True"
    assert ensure_core_importable(None).ok  # this (venv) interpreter has everything
