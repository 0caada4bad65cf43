"""Advice that fits how overseec was installed: `make setup` only in the checkout's own venv, pip
with this environment's interpreter (and the wheel or sdist it came from) everywhere else."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

from overseec_core import install
from overseec_core.cli import EXIT_USER, main
from overseec_core.install import Install

REPO = Path(__file__).resolve().parents[2]
PIP = f"{sys.executable} -m pip"


def test_this_checkout_venv_is_the_checkout_kind() -> None:
    how = install.detect()
    if Path(sys.prefix).resolve() != (REPO / ".venv").resolve():
        pytest.skip("not running in the checkout's .venv")
    assert how.kind == "checkout" and how.checkout == REPO
    assert how.extra_advice() == f"run `make setup` in {REPO}"
    assert "make setup" in how.kernel_advice()


@pytest.mark.parametrize(
    "how,extra,reinstall,kernel",
    [
        (
            Install("package"),
            f'{PIP} install "overseec[models]"',  # finds overseec installed: adds the extra's packages
            f"{PIP} install --force-reinstall --no-deps <the overseec wheel or sdist>",
            "install a C compiler",
        ),
        (
            Install("package", source=Path("/w/overseec-0.1.0-cp311-cp311-linux_x86_64.whl")),
            f'{PIP} install "/w/overseec-0.1.0-cp311-cp311-linux_x86_64.whl[models]"',
            f'{PIP} install --force-reinstall --no-deps "/w/overseec-0.1.0-cp311-cp311-linux_x86_64.whl"',
            "and reinstall: ",
        ),
        (
            Install("editable", checkout=Path("/src/overseec")),
            f'{PIP} install -e "/src/overseec[models]"',
            f'{PIP} install -e "/src/overseec"',
            "Visual Studio Build Tools on Windows",
        ),
    ],
)
def test_pip_installs_get_pip_commands_never_make(how: Install, extra: str, reinstall: str, kernel: str) -> None:
    assert how.extra_advice("models") == extra
    assert how.reinstall_advice() == reinstall
    assert kernel in how.kernel_advice() and how.kernel_advice().endswith(reinstall)
    assert "make" not in extra + reinstall + how.kernel_advice()


def test_a_package_install_names_the_wheel_it_came_from(tmp_path: Path, monkeypatch) -> None:
    """pip's direct_url.json (PEP 610): a local wheel that still exists is the one to reinstall."""
    wheel = tmp_path / "overseec-0.1.0-py3-none-any.whl"
    wheel.write_bytes(b"")
    monkeypatch.setattr(install, "is_checkout", lambda folder: False)
    monkeypatch.setattr(install, "_direct_url", lambda: {"url": wheel.as_uri(), "archive_info": {}})
    install.detect.cache_clear()
    try:
        how = install.detect()
        assert how.kind == "package" and how.source == wheel
        wheel.unlink()  # gone: the package name instead
        install.detect.cache_clear()
        assert install.detect() == Install("package")
    finally:
        install.detect.cache_clear()


@pytest.fixture
def pip_installed(monkeypatch) -> Install:
    """Pretend this is a pip install of the package (the advice code asks install.detect())."""
    how = Install("package")
    monkeypatch.setattr(install, "detect", lambda: how)
    return how


def test_demo_without_its_sample_tells_a_pip_user_how_to_get_it_back(tmp_path, monkeypatch, capsys, pip_installed):
    from overseec_core import sample

    monkeypatch.setattr(sample, "PACKAGE_SAMPLE", tmp_path / "package")
    monkeypatch.setattr(sample, "CHECKOUT_SAMPLE", tmp_path / "checkout")
    assert main(["demo", "--out", str(tmp_path / "run")]) == EXIT_USER
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "make setup" not in err
    assert f"{PIP} install --force-reinstall --no-deps <the overseec wheel or sdist>" in err
    assert "`overseec sample --out DIR`" in err and "--sample DIR" in err
    assert main(["demo", "--sample", str(tmp_path), "--out", str(tmp_path / "run")]) == EXIT_USER
    assert f"write one with `overseec sample --out {tmp_path}`" in capsys.readouterr().err


def test_demo_runs_on_a_generated_sample(tmp_path, capsys) -> None:
    folder = tmp_path / "small"
    assert main(["sample", "--out", str(folder), "--size", "256"]) == 0
    assert main(["-q", "demo", "--sample", str(folder), "--out", str(tmp_path / "run"), "--pairs", "3"]) == 0
    out = capsys.readouterr().out
    assert f"sample     {folder / 'sample.tif'} (256 x 256 px, 0.5 m, EPSG:32633)" in out
    assert "planner    compiled kernel (" in out
    assert (tmp_path / "run" / "path.geojson").is_file()


def test_models_download_without_huggingface_hub_names_the_extra(monkeypatch, capsys, pip_installed) -> None:
    monkeypatch.setitem(sys.modules, "huggingface_hub", None)  # import fails
    assert main(["models", "download", "CIDAS/clipseg-rd64-refined"]) == EXIT_USER
    err = capsys.readouterr().err
    assert "huggingface_hub, part of overseec's models extra" in err
    assert f'{PIP} install "overseec[models]"' in err and "make setup" not in err
    assert main(["doctor", "--json"]) == 0
    models = json.loads(capsys.readouterr().out)["models"]
    assert models["cache"] is None and f'{PIP} install "overseec[models]"' in models["note"]


def test_doctor_says_how_overseec_was_installed_and_which_planner_it_has(capsys) -> None:
    assert main(["doctor", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["install"]["kind"] in install.KINDS and report["install"]["python"] == sys.executable
    assert report["planner"]["planner"] in ("kernel", "fallback") and report["planner"]["summary"]
    assert main(["doctor"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert any(line.startswith("install ") for line in lines)
    assert any(line.startswith("planner ") and report["planner"]["summary"] in line for line in lines)


@pytest.mark.qgis
def test_the_plugin_names_the_worker_environments_planner() -> None:
    """The environment check (dock, "Check environment") and Set up environment's last line."""
    pytest.importorskip("qgis")
    from overseec_qgis.envcheck import check_worker
    from overseec_qgis.setup_env import planner_of

    worker = Path(sys.executable).with_name("overseec")
    report = check_worker(worker)
    assert report.planner.startswith("compiled kernel (") and f"planner: {report.planner}" in report.text()
    assert planner_of(Path(sys.prefix)) == report.planner
