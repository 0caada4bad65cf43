"""The "Set up environment" action for real: a venv made from this Python, pip installing
``overseec[models]`` from a local wheelhouse (``PIP_NO_INDEX``, no network), pip's lines in the
log, progress, and a cancel that removes the half-made environment.

The wheels are built here by hand (a wheel is a zip with METADATA, WHEEL and RECORD): a stand-in
``overseec`` whose ``models`` extra requires a second wheel, so pip really resolves the extra
and really writes the ``overseec`` console script.
"""

from __future__ import annotations

import base64
import hashlib
import zipfile
from pathlib import Path

import pytest
from qgis.core import QgsApplication

from overseec_qgis import venvs
from overseec_qgis.setup_env import (
    InstallTarget,
    PipProgress,
    SetupEnvTask,
    SetupError,
    base_python,
    checkout_of,
    default_venv,
    install_target,
    set_up,
)

from .conftest import REPO, wait_until

pytestmark = pytest.mark.qgis


def _wheel(folder: Path, name: str, files: dict[str, str], metadata: list[str], entry_points: str = "") -> Path:
    dist = f"{name}-0.0.1.dist-info"
    files = dict(files)
    files[f"{dist}/METADATA"] = (
        "\n".join(["Metadata-Version: 2.1", f"Name: {name}", "Version: 0.0.1", *metadata]) + "\n"
    )
    files[f"{dist}/WHEEL"] = "Wheel-Version: 1.0\nGenerator: overseec-test\nRoot-Is-Purelib: true\nTag: py3-none-any\n"
    if entry_points:
        files[f"{dist}/entry_points.txt"] = entry_points
    record = []
    for path, text in files.items():
        digest = base64.urlsafe_b64encode(hashlib.sha256(text.encode()).digest()).rstrip(b"=").decode()
        record.append(f"{path},sha256={digest},{len(text.encode())}")
    files[f"{dist}/RECORD"] = "\n".join(record + [f"{dist}/RECORD,,"]) + "\n"
    out = folder / f"{name}-0.0.1-py3-none-any.whl"
    with zipfile.ZipFile(out, "w") as zf:
        for path, text in files.items():
            zf.writestr(path, text)
    return out


def make_wheelhouse(house: Path, monkeypatch) -> Path:
    """A stand-in overseec[models] (its extra needs ``overseec-tiny-models``) in ``house``, and
    pip told to install from there only (no index, no network)."""
    house.mkdir()
    _wheel(
        house,
        "overseec",
        {"overseec_standin/__init__.py": "def main():\n    print('stand-in overseec')\n"},
        ["Provides-Extra: models", 'Requires-Dist: overseec-tiny-models; extra == "models"'],
        "[console_scripts]\noverseec = overseec_standin:main\n",
    )
    _wheel(house, "overseec_tiny_models", {"overseec_tiny_models.py": "VALUE = 7\n"}, [])
    monkeypatch.setenv("PIP_NO_INDEX", "1")
    monkeypatch.setenv("PIP_FIND_LINKS", str(house))
    return house


@pytest.fixture
def wheelhouse(tmp_path: Path, monkeypatch) -> Path:
    return make_wheelhouse(tmp_path / "wheels", monkeypatch)


def test_install_targets_and_where_the_venv_goes(tmp_path: Path) -> None:
    plain = install_target("", tmp_path / "plugins" / "overseec")
    assert plain == InstallTarget("overseec[models]") and plain.pip_args() == ["overseec[models]"]
    # the plugin running from this checkout installs the checkout, editable, with its constraints
    here = install_target("", REPO / "overseec_qgis")
    assert here.pip_args() == ["-c", str(REPO / "constraints.txt"), "-e", f"{REPO}[models]"]
    assert checkout_of(REPO / "overseec_qgis") == REPO and checkout_of(tmp_path / "a" / "b") is None
    sdist = tmp_path / "overseec-0.1.0.tar.gz"
    sdist.write_bytes(b"")
    assert install_target(str(sdist)).pip_args() == [f"{sdist}[models]"]
    with pytest.raises(SetupError, match="does not exist"):
        install_target(str(tmp_path / "nowhere.whl"))
    assert default_venv(REPO / "overseec_qgis", tmp_path) == REPO / ".venv"
    assert (
        default_venv(tmp_path / "plugins" / "overseec", tmp_path / "profile")
        == tmp_path / "profile" / "overseec" / "venv"
    )
    assert venvs.python(REPO / ".venv").is_file() and base_python().is_file()


def test_pip_progress_follows_pip_phases() -> None:
    p = PipProgress(0.15)
    fractions = [
        p.update(line)
        for line in (
            "Looking in links: /w",
            "Processing /w/overseec-0.0.1-py3-none-any.whl",
            "Collecting overseec-tiny-models",
            "Installing collected packages: overseec-tiny-models, overseec",
            "Successfully installed overseec-0.0.1 overseec-tiny-models-0.0.1",
        )
    ]
    assert fractions[0] == 0.15 and fractions[1] < fractions[2] < fractions[3] < fractions[4] == 1.0


def test_the_task_makes_the_venv_and_installs_overseec_models(qgis_app, wheelhouse, tmp_path) -> None:
    venv = tmp_path / "env"
    task = SetupEnvTask(venv, install_target(""))
    progress: list[float] = []
    task.progressChanged.connect(progress.append)
    outcome: list = []
    task.succeeded.connect(lambda r: outcome.append(("ok", r)))
    task.failed.connect(lambda m, d: outcome.append(("failed", m, d)))
    QgsApplication.taskManager().addTask(task)
    wait_until(lambda: outcome, 240, "the set-up task")
    assert outcome[0][0] == "ok", outcome
    result = outcome[0][1]
    assert result.created and result.venv == venv.resolve()
    assert result.worker == venvs.executable(venv, "overseec") and result.worker.is_file()
    # pip's own lines were streamed, in order, and progress rose to 100
    assert any(line.startswith("Successfully installed") for line in task.lines)
    assert any("overseec-tiny-models" in line for line in task.lines)
    assert progress and progress[-1] == 100.0 and progress == sorted(progress)
    # the extra's requirement is importable in the new environment, and the script runs
    import subprocess

    done = subprocess.run([str(result.worker)], capture_output=True, text=True, timeout=60)
    assert done.stdout.strip() == "stand-in overseec"
    # a second run re-uses the venv (nothing to create) and pip finds everything installed
    again = set_up(venv, install_target(""))
    assert not again.created and again.worker == result.worker


def test_cancel_removes_the_new_environment(qgis_app, wheelhouse, tmp_path) -> None:
    venv = tmp_path / "cancelled-env"
    task = SetupEnvTask(venv, install_target(""))
    outcome: list = []
    task.failed.connect(lambda m, d: outcome.append(m))
    task.succeeded.connect(lambda r: outcome.append(r))
    task.progressChanged.connect(lambda p: task.cancel() if p > 0 else None)  # cancel once it started
    QgsApplication.taskManager().addTask(task)
    wait_until(lambda: outcome, 120, "the cancelled task")
    assert task.was_cancelled and "cancelled" in outcome[0]
    assert not venv.exists()


def test_a_failing_install_says_why_and_leaves_no_venv(qgis_app, wheelhouse, tmp_path) -> None:
    venv = tmp_path / "failed-env"
    (venv).mkdir()  # an empty folder the user chose stays, empty
    with pytest.raises(SetupError, match="pip could not install no-such-package"):
        set_up(venv, InstallTarget("no-such-package[models]"))
    assert venv.is_dir() and not any(venv.iterdir())
    full = tmp_path / "full"
    full.mkdir()
    (full / "data.txt").write_text("mine")
    with pytest.raises(SetupError, match="not a Python environment"):
        set_up(full, InstallTarget("overseec[models]"))
    assert (full / "data.txt").read_text() == "mine"
