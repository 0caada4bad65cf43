"""docs/api.md, the Python API guide, runs as a doctest on the bundled sample scene.

The guide's examples read ``resources/sample/`` and write under ``runs/api/``, relative to the
folder they run in: here a temporary folder holding a copy of the sample, so the checkout's files
are never written (QGIS and GDAL may write ``.aux.xml`` statistics beside inputs).
"""

from __future__ import annotations

import doctest
import shutil
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
GUIDE = REPO / "docs" / "api.md"
SAMPLE = REPO / "resources" / "sample"


def test_api_guide_examples_run(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    shutil.copytree(SAMPLE, tmp_path / "resources" / "sample")
    monkeypatch.chdir(tmp_path)
    for name in ("OVERSEEC_LLM_URL", "OVERSEEC_LLM_MODEL", "OVERSEEC_LLM_FALLBACK"):
        monkeypatch.delenv(name, raising=False)  # the guide's interpretations are the offline ones
    result = doctest.testfile(
        str(GUIDE),
        module_relative=False,
        optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE,
        report=False,
        verbose=False,
    )
    assert result.attempted > 40, f"only {result.attempted} examples found in {GUIDE}"
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples in docs/api.md failed (see above)"
