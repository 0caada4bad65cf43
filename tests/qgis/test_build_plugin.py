"""scripts/build_plugin.py: the zip QGIS's "Install from ZIP" accepts."""

from __future__ import annotations

import configparser
import importlib.util
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import overseec_core

pytestmark = pytest.mark.qgis

REPO = Path(__file__).resolve().parents[2]


def _builder():
    spec = importlib.util.spec_from_file_location("build_plugin", REPO / "scripts" / "build_plugin.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("dist") / "overseec.zip"
    done = subprocess.run(
        [sys.executable, str(REPO / "scripts" / "build_plugin.py"), "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert "built" in done.stdout
    return out


def test_zip_holds_one_plugin_folder_with_everything(built: Path) -> None:
    with zipfile.ZipFile(built) as zf:
        names = zf.namelist()
        assert zf.testzip() is None
        assert {n.split("/")[0] for n in names} == {"overseec"}
        for required in (
            "overseec/metadata.txt",
            "overseec/__init__.py",
            "overseec/overseec_qgis/__init__.py",
            "overseec/overseec_qgis/plugin.py",
            "overseec/overseec_qgis/processing/provider.py",
            "overseec/overseec_core/__init__.py",
            "overseec/overseec_core/pipeline.py",
            "overseec/resources/icons/overseec.svg",
            "overseec/resources/styles/costmap.qml",
            "overseec/resources/styles/path.qml",
            "overseec/resources/styles/mask.qml",
            "overseec/resources/styles/probability.qml",
        ):
            assert required in names, required
        assert not any("__pycache__" in n or n.endswith(".pyc") for n in names)
        # the planner's compiled kernel travels with the core
        assert any(n.startswith("overseec/overseec_core/plan/_kernel.") and n.endswith((".so", ".pyd")) for n in names)
        assert "def classFactory" in zf.read("overseec/__init__.py").decode()
        cp = configparser.ConfigParser(interpolation=None)
        cp.read_string(zf.read("overseec/metadata.txt").decode())
    g = cp["general"]
    assert g["version"] == overseec_core.__version__
    assert g["qgisMinimumVersion"] == "3.22"
    assert g["hasProcessingProvider"] == "yes"
    assert g["name"] == "overseec"
    for key in ("homepage", "tracker", "repository", "icon", "about", "description", "author", "email"):
        assert g[key].strip(), key
    assert f"overseec/{g['icon']}" in names


def test_zip_is_reproducible(built: Path, tmp_path: Path) -> None:
    again = _builder().build(tmp_path / "again.zip")
    assert again.read_bytes() == built.read_bytes()


def test_unpacked_plugin_imports_its_bundled_core(built: Path, tmp_path: Path) -> None:
    """QGIS imports the folder as package `overseec`; it must use the core shipped inside it."""
    plugins = tmp_path / "plugins"
    target = _builder().extract(built, plugins)
    script = (
        f"import sys; sys.path.insert(0, {str(plugins)!r}); import overseec, overseec_core, overseec_qgis; "
        "print(callable(overseec.classFactory)); print(overseec_core.__file__); "
        "print(overseec_qgis.__file__)"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    ok, core_file, qgis_file = done.stdout.split()
    assert ok == "True"
    assert Path(core_file).is_relative_to(target) and Path(qgis_file).is_relative_to(target)


def test_metadata_version_must_match_the_core(tmp_path: Path) -> None:
    b = _builder()
    bad = tmp_path / "metadata.txt"
    bad.write_text((REPO / "metadata.txt").read_text().replace(f"version={overseec_core.__version__}", "version=9.9.9"))
    with pytest.raises(b.BuildError, match="differs from overseec_core"):
        b.check_metadata(bad)
    missing = tmp_path / "m2.txt"
    missing.write_text("[general]\nname=overseec\n")
    with pytest.raises(b.BuildError, match="missing"):
        b.check_metadata(missing)
