"""`pip install` of the sdist and the wheel into a fresh, plain venv: the demo runs, and without a
compiler the install plans with the fallback planner and says so.

For each Python (``/usr/bin/python3``; more with ``OVERSEEC_INSTALL_PYTHONS=python3.12,python3.13``,
names on PATH or paths):

1. a plain venv (``-m venv``, no system site packages: nothing from Debian);
2. the wheel, built from the sdist by that venv's pip with build isolation (setuptools and NumPy 2
   from PyPI, as cibuildwheel and a user's pip build it: a kernel built against Debian's NumPy 1.24
   would not load under the NumPy 2 that pip installs), installed with its dependencies from PyPI
   (pip's cache reused; ``numpy<2.3``); never ``[models]``: the demo needs no model;
3. ``overseec doctor --kernel`` and ``overseec demo --out DIR`` from a folder outside the checkout;
4. the sdist installed again with no compiler (``CC=/bin/false``, PATH without gcc): the optional
   kernel build fails, pip installs the rest, ``overseec plan`` on the demo's costmap plans with the
   fallback (same cost as the kernel's route, the fallback note) and the advice is pip's.

Prints the install time and the venv's size per Python (``pytest -s``). Skipped when PyPI is
unreachable.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.slow

#: The interpreters to install into: the system Python, plus OVERSEEC_INSTALL_PYTHONS.
EXTRA_PYTHONS = os.environ.get("OVERSEEC_INSTALL_PYTHONS", "")
PYTHONS = ["/usr/bin/python3"] + [p.strip() for p in EXTRA_PYTHONS.split(",") if p.strip()]
#: Keeps the resolver on releases with wheels for every Python tested (and quick to install).
RUNTIME_CONSTRAINTS = "numpy<2.3\n"
NOTE_START = "planned with the fallback planner (scikit-image), "


def _index_url() -> str:
    return os.environ.get("PIP_INDEX_URL", "https://pypi.org/simple").rstrip("/") + "/"


def _pypi_problem() -> str | None:
    """Why PyPI cannot be used here (None when it answers)."""
    url = _index_url() + "pip/"
    try:
        with urllib.request.urlopen(url, timeout=15) as resp:
            resp.read(1)
        return None
    except (urllib.error.URLError, OSError, ValueError) as exc:
        return f"PyPI is unreachable ({url}: {getattr(exc, 'reason', exc)}); the install test needs it"


def _clean_env(**extra: str) -> dict[str, str]:
    """This environment without what would leak the checkout or its venv into the new one."""
    drop = ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV", "OVERSEEC_PLANNER", "PYTHONSTARTUP")
    env = {k: v for k, v in os.environ.items() if k not in drop}
    env.setdefault("QT_QPA_PLATFORM", "offscreen")
    env.update(extra)
    return env


def _run(argv: list, cwd: Path, timeout: float = 900, **env: str) -> subprocess.CompletedProcess:
    done = subprocess.run(
        [str(a) for a in argv], capture_output=True, text=True, timeout=timeout, cwd=cwd, env=_clean_env(**env)
    )
    return done


def _ok(done: subprocess.CompletedProcess) -> str:
    assert done.returncode == 0, f"{done.args}\nstdout:\n{done.stdout[-4000:]}\nstderr:\n{done.stderr[-4000:]}"
    return done.stdout


def _du_mb(path: Path) -> float:
    total = sum(f.stat().st_size for f in path.rglob("*") if f.is_file() and not f.is_symlink())
    return total / 2**20


def _the_plugin_says_which_planner(venv: Path) -> None:
    """The QGIS plugin's environment check and Set up environment name the worker's planner."""
    try:
        from overseec_qgis.envcheck import check_worker
        from overseec_qgis.setup_env import planner_of
    except ImportError:  # no PyQGIS here
        return
    report = check_worker(venv / "bin" / "overseec")
    assert report.planner.startswith("fallback (scikit-image MCP_Geometric"), report.text()
    assert f"planner: {report.planner}" in report.text()
    assert planner_of(venv) == report.planner


@pytest.fixture(scope="module")
def sdist(tmp_path_factory) -> Path:
    problem = _pypi_problem()
    if problem:
        pytest.skip(problem)
    # from a copy of the work tree's files (tracked, and new ones git does not ignore), as a fresh
    # clone has them: setuptools also packs whatever a stale overseec.egg-info/SOURCES.txt lists
    tree, out = tmp_path_factory.mktemp("tree"), tmp_path_factory.mktemp("sdist")
    listed = _ok(_run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"], cwd=REPO))
    for name in filter(None, listed.split("\0")):
        src = REPO / name
        if src.is_file():
            (tree / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, tree / name)
    _ok(_run([sys.executable, "setup.py", "-q", "sdist", "-d", out], cwd=tree, timeout=300))
    (path,) = out.glob("overseec-*.tar.gz")
    return path


@pytest.mark.parametrize("python", PYTHONS)
def test_pip_install_runs_the_demo_and_plans_without_a_compiler(python: str, sdist: Path, tmp_path: Path) -> None:
    exe = shutil.which(python)
    if exe is None:
        pytest.skip(f"{python} not found")
    version = _ok(_run([exe, "-c", "import sys; print('%d.%d' % sys.version_info[:2])"], cwd=tmp_path)).strip()
    venv = tmp_path / "venv"
    vpy, overseec = venv / "bin" / "python", venv / "bin" / "overseec"
    started = time.perf_counter()
    _ok(_run([exe, "-m", "venv", venv], cwd=tmp_path, timeout=300))
    _ok(_run([vpy, "-m", "pip", "install", "-q", "--upgrade", "pip"], cwd=tmp_path))

    # the wheel, as pip builds it from the sdist (build isolation: setuptools, NumPy 2 headers);
    # --no-cache-dir: never a wheel cached from another build of the same file
    t0 = time.perf_counter()
    wheels = tmp_path / "wheels"
    _ok(_run([vpy, "-m", "pip", "wheel", "-q", "--no-deps", "--no-cache-dir", "-w", wheels, sdist], cwd=tmp_path))
    (wheel,) = wheels.glob("overseec-*.whl")
    build_s = time.perf_counter() - t0
    import zipfile

    with zipfile.ZipFile(wheel) as zf:
        names = zf.namelist()
    assert any(n.startswith("overseec_core/plan/_kernel.") and n.endswith(".so") for n in names)
    assert "overseec_core/data/sample/sample.tif" in names and "overseec_core/data/sample/sample.json" in names
    assert any(n.endswith(".dist-info/licenses/LICENSE") for n in names)

    t0 = time.perf_counter()
    constraints = tmp_path / "constraints.txt"
    constraints.write_text(RUNTIME_CONSTRAINTS)
    _ok(_run([vpy, "-m", "pip", "install", "-q", "-c", constraints, wheel], cwd=tmp_path))
    install_s = time.perf_counter() - t0
    size_mb = _du_mb(venv)
    pip_freeze = _ok(_run([vpy, "-m", "pip", "list", "--format=freeze"], cwd=tmp_path))
    assert "torch" not in pip_freeze.lower() and "transformers" not in pip_freeze.lower()

    # the compiled kernel plans right; the demo runs from anywhere on the shipped sample
    kernel = _ok(_run([overseec, "doctor", "--kernel"], cwd=tmp_path))
    assert kernel.startswith("kernel ") and str(venv) in kernel, kernel
    t0 = time.perf_counter()
    demo_out = tmp_path / "runs" / "demo"
    demo = _ok(_run([overseec, "-q", "demo", "--out", demo_out], cwd=tmp_path, timeout=900))
    demo_s = time.perf_counter() - t0
    assert "planner    compiled kernel (" in demo and f"{venv}" in demo
    sample_dir = next((venv / "lib").glob("python*/site-packages/overseec_core/data/sample"))
    assert f"sample     {sample_dir / 'sample.tif'}" in demo
    for name in ("costmap.tif", "lethal.tif", "path.geojson", "manifest.json", "evaluation/report.md"):
        assert (demo_out / name).is_file(), name
    kernel_cost = json.loads((demo_out / "path.geojson").read_text())["features"][0]["properties"]["total_cost"]
    doctor = _ok(_run([overseec, "doctor"], cwd=tmp_path))
    assert "install       package (" in doctor and "planner       compiled kernel" in doctor
    device = next(line for line in doctor.splitlines() if line.startswith("device"))
    assert f'{vpy} -m pip install "{wheel}[models]"' in device and "make setup" not in doctor

    # no compiler: the optional kernel fails to build, the rest installs, the fallback plans
    nogcc = tmp_path / "bin"
    nogcc.mkdir()
    t0 = time.perf_counter()
    hidden = dict(CC="/bin/false", CXX="/bin/false", LDSHARED="/bin/false", PATH=f"{venv / 'bin'}:{nogcc}")
    argv = [vpy, "-m", "pip", "install", "-v", "--force-reinstall", "--no-deps", "--no-cache-dir", sdist]
    built = _run(argv, cwd=tmp_path, **hidden)
    _ok(built)
    sdist_s = time.perf_counter() - t0
    assert "the planner kernel (overseec_core/plan/_kernel.c) could not be compiled" in built.stdout + built.stderr
    plan_dir = next((venv / "lib").glob("python*/site-packages/overseec_core/plan"))
    assert not list(plan_dir.glob("_kernel*.so"))
    check = _ok(_run([overseec, "doctor", "--kernel"], cwd=tmp_path))
    assert check.startswith("no compiled kernel: the fallback planner is in use (the compiled kernel is not installed")
    assert "the fallback plans correctly" in check
    assert f'{vpy} -m pip install --force-reinstall --no-deps "{sdist}"' in check and "make setup" not in check

    meta = json.loads((sample_dir / "sample.json").read_text())
    (sx, sy), (gx, gy) = meta["start"], meta["goal"]
    out = tmp_path / "fallback" / "path.geojson"
    t0 = time.perf_counter()
    argv = [overseec, "plan", demo_out / "costmap.tif", "--start", sx, sy, "--goal", gx, gy, "--out", out]
    plan = _ok(_run(argv, cwd=tmp_path))
    plan_s = time.perf_counter() - t0
    assert f"note: {NOTE_START}" in plan, plan
    props = json.loads(out.read_text())["features"][0]["properties"]
    assert props["total_cost"] == pytest.approx(kernel_cost, rel=1e-9)
    assert [n for n in props["notes"] if n.startswith(NOTE_START)]
    _the_plugin_says_which_planner(venv)
    total_s = time.perf_counter() - started
    print(
        f"\nPython {version}: pip install of the wheel and its dependencies {install_s:.0f} s "
        f"(wheel built from the sdist in {build_s:.0f} s), venv {size_mb:.0f} MB; demo {demo_s:.1f} s; "
        f"sdist without a compiler {sdist_s:.0f} s, fallback plan {plan_s:.1f} s; {total_s:.0f} s in all"
    )
