"""First-use check of the Python environments the plugin depends on.

Two environments matter:

* QGIS's own Python runs the non-ML stages in-process (interpret offline, costmap, plan,
  evaluate) through ``overseec_core.pipeline``; they need numpy, scipy, shapely, scikit-image and
  rasterio. When QGIS's Python lacks some (Debian's QGIS has no shapely 2 or scikit-image), the
  project's venv -- made with ``--system-site-packages`` from the same interpreter -- supplies them:
  :func:`ensure_core_importable` appends its site-packages to ``sys.path`` (appended, so QGIS's
  own numpy/GDAL bindings keep precedence).
* The worker environment (the venv's ``overseec`` command) runs segmentation; it needs torch and
  transformers. :func:`check_worker` asks that interpreter, in a subprocess (QGIS itself never
  imports torch), what it has and which device it would use.

Both return plain reports whose ``advice`` lines say exactly what to run, so a missing package is
a message in the dock, not a traceback.
"""

from __future__ import annotations

import importlib
import json
import os
import site
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

from .worker import worker_env, worker_python

#: Modules the in-process (non-ML) stages import.
CORE_MODULES = ("numpy", "scipy", "rasterio", "shapely", "skimage", "pyproj")
#: Modules the worker needs for segmentation and refinement.
MODEL_MODULES = ("torch", "transformers")

# Run by the worker's interpreter with `-c`: a fixed program, no user text in it.
_PROBE = r"""
import importlib, json, sys
r = {"python": "%d.%d.%d" % sys.version_info[:3], "executable": sys.executable, "modules": {}, "errors": {}}
for m in ("overseec_core", "numpy", "scipy", "rasterio", "shapely", "skimage", "torch", "transformers"):
    try:
        r["modules"][m] = getattr(importlib.import_module(m), "__version__", "?")
    except Exception as exc:
        r["modules"][m] = None
        r["errors"][m] = "%s: %s" % (type(exc).__name__, str(exc).splitlines()[0] if str(exc) else "")
r["device"] = "cpu"
r["device_name"] = ""
if r["modules"].get("torch"):
    torch = sys.modules["torch"]
    if torch.cuda.is_available():
        r["device"] = "cuda"
        r["device_name"] = torch.cuda.get_device_name(0)
    elif getattr(torch.backends, "mps", None) is not None and torch.backends.mps.is_available():
        r["device"] = "mps"
print(json.dumps(r))
"""


@dataclass(frozen=True)
class EnvReport:
    """What an environment has, what is wrong, and what to run about it."""

    ok: bool
    #: True when segmentation (torch + transformers) can run.
    models_ok: bool = False
    worker: str = ""
    python: str = ""
    device: str = ""
    device_name: str = ""
    modules: dict = field(default_factory=dict)
    problems: tuple[str, ...] = ()
    advice: tuple[str, ...] = ()

    def text(self) -> str:
        """A multi-line summary for the dock and the log."""
        lines = []
        if self.worker:
            lines.append(f"worker: {self.worker} (Python {self.python})")
        if self.modules:
            have = ", ".join(f"{k} {v}" for k, v in self.modules.items() if v)
            lines.append(f"installed: {have}")
        if self.device:
            lines.append(f"device: {self.device}{' (' + self.device_name + ')' if self.device_name else ''}")
        lines += [f"problem: {p}" for p in self.problems]
        lines += [f"to fix, run: {a}" for a in self.advice]
        if self.ok and not self.problems:
            lines.append("environment OK")
        return "\n".join(lines)


def project_dir_of(worker: str | os.PathLike) -> Path | None:
    """The checkout a ``<project>/.venv/bin/overseec`` worker belongs to, when it looks like one."""
    venv = Path(worker).resolve().parent.parent if Path(worker).exists() else Path(worker).parent.parent
    project = venv.parent
    if (project / "Makefile").is_file() and (project / "overseec_core").is_dir():
        return project
    return None


def _venv_of(worker: str | os.PathLike) -> Path:
    return Path(worker).parent.parent


def site_packages(venv: str | os.PathLike) -> list[Path]:
    """The venv's site-packages directories for this interpreter's version (may be empty)."""
    v = f"python{sys.version_info[0]}.{sys.version_info[1]}"
    venv = Path(venv)
    cands = [venv / "lib" / v / "site-packages", venv / "Lib" / "site-packages"]
    return [c for c in cands if c.is_dir()]


def missing_core_modules() -> list[str]:
    """The in-process stages' modules this interpreter cannot import."""
    missing = []
    for name in CORE_MODULES:
        if name in sys.modules:
            continue
        try:
            importlib.import_module(name)
        except Exception:  # ImportError, or a binary mismatch surfacing as another error
            missing.append(name)
    return missing


def ensure_core_importable(venv: str | os.PathLike | None = None, worker: str | os.PathLike | None = None) -> EnvReport:
    """Make the in-process stages importable, borrowing the venv's packages if needed.

    ``venv`` (or the environment of ``worker``) must be built from this same Python version;
    its site-packages are appended to ``sys.path``. Importing the core pulls in no torch.
    """
    missing = missing_core_modules()
    if missing:
        root = Path(venv) if venv else (_venv_of(worker) if worker else None)
        dirs = site_packages(root) if root else []
        for d in dirs:
            if str(d) not in sys.path:
                site.addsitedir(str(d))  # appends, so QGIS's own packages keep precedence
        importlib.invalidate_caches()
        missing = missing_core_modules()
    if not missing:
        return EnvReport(ok=True, python=sys.version.split()[0])
    py = f"{sys.version_info[0]}.{sys.version_info[1]}"
    project = project_dir_of(worker) if worker else None
    advice = []
    if project is not None:
        advice.append(f"cd {project} && make setup")
    else:
        advice.append(
            "make setup   (in the overseec project directory), then set the plugin's "
            "'Python environment' to the project's .venv"
        )
    advice.append(
        f"or: <venv>/bin/pip install {' '.join(_pip_name(m) for m in missing)}  "
        f"(a venv made from QGIS's Python {py} with --system-site-packages)"
    )
    return EnvReport(
        ok=False,
        python=sys.version.split()[0],
        problems=(f"QGIS's Python {py} cannot import {', '.join(missing)}",),
        advice=tuple(advice),
    )


def _pip_name(module: str) -> str:
    return {"skimage": "scikit-image"}.get(module, module)


def check_worker(worker: str | os.PathLike | None, timeout_s: float = 120.0) -> EnvReport:
    """Ask the worker's interpreter what it has (in a subprocess: torch stays out of QGIS)."""
    from overseec_core import __version__ as plugin_version

    if worker is None or not Path(worker).is_file():
        return EnvReport(
            ok=False,
            problems=("the overseec worker (the `overseec` command of the project's venv) was not found",),
            advice=(
                "make setup   (in the overseec project directory; it creates .venv with torch and transformers)",
                "then set the plugin's 'overseec command' to <project>/.venv/bin/overseec, "
                "or start QGIS with OVERSEEC_VENV=<project>/.venv",
            ),
        )
    python = worker_python(worker)
    try:
        # -I: isolated, so neither the current folder nor PYTHONPATH can lend it packages
        proc = subprocess.run(
            [str(python), "-I", "-c", _PROBE],
            capture_output=True,
            text=True,  # noqa: S603
            timeout=timeout_s,
            env=worker_env(),
        )
        data = json.loads(proc.stdout.strip().splitlines()[-1])
    except (OSError, subprocess.SubprocessError, ValueError, IndexError) as exc:
        return EnvReport(
            ok=False,
            worker=str(worker),
            problems=(f"{python} could not be run to check the environment ({exc})",),
            advice=("make setup   (in the overseec project directory)",),
        )
    modules = data.get("modules", {})
    errors = data.get("errors", {})
    problems, advice = [], []
    venv = _venv_of(worker)
    project = project_dir_of(worker)
    pip = venv / "bin" / "pip"
    if not modules.get("overseec_core"):
        problems.append(f"overseec_core is not installed in {venv} ({errors.get('overseec_core', '')})")
        advice.append(f"{pip} install -e {project or '<overseec project directory>'}")
    core_missing = [m for m in ("numpy", "scipy", "rasterio", "shapely", "skimage") if not modules.get(m)]
    if core_missing:
        problems.append(f"missing in the worker environment: {', '.join(core_missing)}")
        advice.append(
            f"cd {project} && make setup"
            if project
            else f"{pip} install {' '.join(_pip_name(m) for m in core_missing)}"
        )
    models_missing = [m for m in MODEL_MODULES if not modules.get(m)]
    if models_missing:
        detail = "; ".join(errors.get(m, "") for m in models_missing if errors.get(m))
        problems.append(
            f"segmentation needs {' and '.join(models_missing)}, which the worker "
            f"environment lacks{' (' + detail + ')' if detail else ''}"
        )
        constraints = f" -c {project / 'constraints.txt'}" if project else ""
        advice.append(
            f"{pip} install{constraints} torch transformers safetensors"
            + (f"   (or: cd {project} && make setup)" if project else "")
        )
    core_version = modules.get("overseec_core")
    if core_version and core_version != plugin_version:
        problems.append(f"the worker runs overseec {core_version} but the plugin is {plugin_version}")
        advice.append(
            f"{pip} install -e {project or '<overseec project directory>'}   "
            "(or install the plugin zip built from the same checkout)"
        )
    ok = bool(core_version) and not core_missing and core_version == plugin_version
    return EnvReport(
        ok=ok,
        models_ok=not models_missing and not core_missing,
        worker=str(worker),
        python=data.get("python", ""),
        device=data.get("device", ""),
        device_name=data.get("device_name", ""),
        modules=modules,
        problems=tuple(problems),
        advice=tuple(advice),
    )
