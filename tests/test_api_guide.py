"""docs/api.md, the Python API guide, runs as a doctest on the bundled sample scene; the API
reference (``make docs``: docs/build_reference.py, pdoc) builds without torch.

The guide's examples read ``resources/sample/`` and write under ``runs/api/``, relative to the
folder they run in: here a temporary folder holding a copy of the sample, so the checkout's files
are never written (QGIS and GDAL may write ``.aux.xml`` statistics beside inputs).
"""

from __future__ import annotations

import doctest
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
GUIDE = REPO / "docs" / "api.md"
SAMPLE = REPO / "resources" / "sample"


@pytest.mark.parametrize("planner", ["auto", "fallback"])
def test_api_guide_examples_run(planner: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The guide holds with the compiled kernel and on an install without it (the fallback)."""
    shutil.copytree(SAMPLE, tmp_path / "resources" / "sample")
    monkeypatch.chdir(tmp_path)
    for name in ("OVERSEEC_LLM_URL", "OVERSEEC_LLM_MODEL", "OVERSEEC_LLM_FALLBACK"):
        monkeypatch.delenv(name, raising=False)  # the guide's interpretations are the offline ones
    monkeypatch.setenv("OVERSEEC_PLANNER", planner)
    result = doctest.testfile(
        str(GUIDE),
        module_relative=False,
        optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE,
        report=False,
        verbose=False,
    )
    assert result.attempted > 40, f"only {result.attempted} examples found in {GUIDE}"
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples in docs/api.md failed (see above)"


def _build_reference(out: Path, *modules: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    cmd = [sys.executable, str(REPO / "docs" / "build_reference.py"), "--out", str(out), "--modules", *modules]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300, cwd=out.parent, env=env)


def test_api_reference_builds_offline_without_torch(tmp_path: Path) -> None:
    """A few modules of `make docs` (the whole reference takes ~25 s): the stage functions and the
    plan API are documented, a module whose annotations name torch.Tensor (under TYPE_CHECKING)
    renders with torch blocked, and the pages load nothing from the network."""
    pytest.importorskip("pdoc", reason="pdoc is installed by `make docs` (requirements-docs.txt)")
    out = tmp_path / "reference"
    done = _build_reference(
        out, "overseec_core.pipeline", "overseec_core.plan", "overseec_core.plan.stage", "overseec_core.locate.clipseg"
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert "4 modules" in done.stdout
    pipeline = (out / "overseec_core" / "pipeline.html").read_text()
    for name in ("run_costmap", "run_compare", "run_all"):  # the chains; each stage's front door is its stage.py
        assert f'id="{name}"' in pipeline, name
    assert 'id="run_plan"' in (out / "overseec_core" / "plan" / "stage.html").read_text()
    plan = (out / "overseec_core" / "plan.html").read_text()
    assert 'id="Planner"' in plan and 'id="load_costmap"' in plan
    assert (out / "overseec_core" / "locate" / "clipseg.html").is_file()
    for page in out.rglob("*.html"):
        remote = set(re.findall(r'(?:src|href)="(https?://[^/"]*)', page.read_text()))
        assert remote <= {"https://pdoc.dev"}, f"{page.name} refers to {remote}"


def test_api_reference_refuses_a_module_that_needs_torch(tmp_path: Path) -> None:
    """A module importing torch at import time fails the build (torch is blocked): never a page
    quietly missing, nor a reference build that loads the models' packages."""
    pytest.importorskip("pdoc", reason="pdoc is installed by `make docs` (requirements-docs.txt)")
    (tmp_path / "needs_torch_at_import.py").write_text('"""Not documentable without torch."""\nimport torch\n')
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(tmp_path), os.environ.get("PYTHONPATH")])))
    done = _build_reference(tmp_path / "ref", "needs_torch_at_import", env=env)
    assert done.returncode != 0
    assert "needs_torch_at_import" in done.stderr
