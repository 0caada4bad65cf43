"""scripts/build_plugin.py: the zip QGIS's "Install from ZIP" accepts, pure Python on every platform."""

from __future__ import annotations

import configparser
import importlib.util
import shutil
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
        # pure Python: no compiled code and no C source (the kernel lives in the overseec environment)
        assert [n for n in names if n.endswith((".so", ".pyd", ".dylib", ".dll", ".c", ".h", ".o"))] == []
        for n in names:
            if not n.endswith("/"):
                assert not zf.read(n)[:4].startswith((b"\x7fELF", b"MZ", b"\xcf\xfa\xed\xfe")), n
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


def _checkout_copy(tmp_path: Path) -> Path:
    """What the build reads, copied (the planner kernel's in-place build included when present)."""
    root = tmp_path / "checkout"
    skip = shutil.ignore_patterns("__pycache__", ".*")
    for package in ("overseec_core", "overseec_qgis"):
        shutil.copytree(REPO / package, root / package, ignore=skip)
    for d in ("resources/icons", "resources/styles"):
        shutil.copytree(REPO / d, root / d, ignore=skip)
    for name in ("metadata.txt", "README.md"):
        shutil.copy2(REPO / name, root / name)
    return root


def test_build_refuses_compiled_code(tmp_path: Path) -> None:
    """A binary anywhere in the package tree, or one under a shipped name, stops the build."""
    b = _builder()
    root = _checkout_copy(tmp_path)
    kernel = root / "overseec_core" / "plan" / "_kernel.cpython-311-x86_64-linux-gnu.so"
    kernel.write_bytes(b"\x7fELF in-place build of _kernel.c")  # what `make venv` leaves: tolerated, left out
    clean = b.build(tmp_path / "clean.zip", root=root)
    with zipfile.ZipFile(clean) as zf:
        assert not [n for n in zf.namelist() if "_kernel" in n and not n.endswith("/")]
        assert "overseec/overseec_core/plan/planner.py" in zf.namelist()

    for stray in (
        "overseec_qgis/_fast.cpython-311-x86_64-linux-gnu.so",
        "overseec_core/plan/helper.pyd",
        "overseec_core/libx.dylib",
    ):
        (root / stray).write_bytes(b"\x7fELF")
        out = tmp_path / "refused.zip"
        with pytest.raises(b.BuildError, match="compiled code"):
            b.build(out, root=root)
        assert not out.exists() and not list(tmp_path.glob(".refused.zip*"))
        (root / stray).unlink()

    disguised = root / "overseec_core" / "blob.json"
    disguised.write_bytes(b"MZ\x90\x00 a Windows DLL renamed")
    with pytest.raises(b.BuildError, match="overseec_core/blob.json is an executable binary"):
        b.build(tmp_path / "refused.zip", root=root)


def test_cli_reports_a_stray_binary_in_one_line(tmp_path: Path) -> None:
    root = _checkout_copy(tmp_path)
    (root / "overseec_qgis" / "_fast.so").write_bytes(b"\x7fELF")
    script = root / "scripts" / "build_plugin.py"
    script.parent.mkdir()
    shutil.copy2(REPO / "scripts" / "build_plugin.py", script)
    done = subprocess.run(
        [sys.executable, str(script), "--out", str(tmp_path / "p.zip")], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        "build_plugin: error: overseec_qgis/_fast.so is compiled code; the plugin is pure Python (native code "
        "belongs in the overseec environment: an extension in setup.py, built by pip)"
    ]
    assert not (tmp_path / "p.zip").exists()
