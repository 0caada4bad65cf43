"""First-use check of the Python environments the plugin depends on.

Two environments matter:

* The worker environment (the venv's ``overseec`` command) runs every stage: the image reading
  check, interpret, segment, costmap, plan (``overseec plan-server``), evaluate. It needs
  the core's packages, torch, transformers and the model weights. :func:`check_worker` asks that
  interpreter, in a subprocess (QGIS itself never imports torch), what it has, which device it
  would use, and whether the CLIPSeg and SAM models resolve offline exactly as ``overseec
  segment`` resolves them (``overseec_core.locate.models.resolve_model``: a folder, or a hub id in the
  Hugging Face cache).
  It also says which planner the worker plans with: the compiled kernel, or the slower
  scikit-image fallback where the kernel could not be compiled (and why).
* QGIS's own Python only checks and edits text with the core (the cost language, entity tables,
  interpretations: numpy only). Where the project's venv was made from the same interpreter with
  ``--system-site-packages``, :func:`ensure_core_importable` borrows its packages (appended to
  ``sys.path``, so QGIS's own numpy/GDAL bindings keep precedence) so the dock can also match
  program names to the entity rasters as you type; without them (Windows and macOS QGIS) the
  worker's costmap checks the names instead.

Both return plain reports whose ``advice`` lines say what to do: the dock's "Set up environment"
action for a missing or incomplete environment (``setup_helps``), and how to provide a copied
model folder for missing weights. A missing package is a message in the dock, not a traceback.
Paths work for both venv layouts (``bin/`` and ``Scripts/…exe``, :mod:`venvs`).
"""

from __future__ import annotations

import importlib
import json
import os
import site
import subprocess
import sys
from dataclasses import dataclass, field, replace
from pathlib import Path

from . import venvs
from .worker import worker_env, worker_python

#: The core's packages QGIS's Python may borrow from the venv (for reading entity rasters).
CORE_MODULES = ("numpy", "scipy", "rasterio", "shapely", "skimage", "pyproj")
#: Modules the worker needs for segmentation and refinement.
MODEL_MODULES = ("torch", "transformers")

#: The action in the dock that creates the worker environment (setup_env.py).
SETUP_ACTION = "press 'Set up environment' in the overseec panel"
#: Where the model settings are (options.py).
OPTIONS_PAGE = "Settings › Options › overseec"
#: Display names of the model kinds (the refiners' are the weights' keys of their checkpoints).
MODEL_NAMES = {"clipseg": "CLIPSeg", "sam": "SAM", "sam-hq": "SAM-HQ", "sam2": "SAM 2"}
#: The refiners' kinds: their checkpoint is the CLI's --sam-model and the options page's SAM model.
REFINER_KINDS = ("sam", "sam-hq", "sam2")

# Run by the worker's interpreter with `-c`: a fixed program, no user text in it; the model
# names arrive as sys.argv[1:] (the segmenter's model or "" for its default, the refiner's model
# or "" to skip it, "weights" to check only the weights: no torch import, so the check before
# Segment takes a fraction of a second, or "all", then the segmenter's name and the refiner's),
# never as code. CLIPSeg and the refiner (SAM, SAM-HQ or SAM 2: its checkpoint must be of its
# kind) are resolved as the CLI resolves them; another segmenter's model is only looked for (its backend
# checks the kind when it loads).
_PROBE = r"""
import importlib, json, sys
r = {"python": "%d.%d.%d" % sys.version_info[:3], "executable": sys.executable, "modules": {}, "errors": {}}
names = ("overseec_core", "numpy", "scipy", "rasterio", "shapely", "skimage", "torch", "transformers")
weights_only = sys.argv[3:4] == ["weights"]
segmenter = sys.argv[4] if len(sys.argv) > 4 else "clipseg"
refiner = sys.argv[5] if len(sys.argv) > 5 else "sam"
for m in names[:1] if weights_only else names:
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
r["weights"] = {}
if r["modules"].get("overseec_core"):
    try:
        from overseec_core.locate import models
        if segmenter == "clipseg":
            wanted = [("clipseg", sys.argv[1] or models.DEFAULT_CLIPSEG)]
        else:
            from overseec_core.locate.segmenters import default_model
            wanted = [(segmenter, sys.argv[1] or default_model(segmenter))]
        for kind, name in wanted + [(refiner, sys.argv[2])]:
            if not name:
                continue
            try:
                if kind in models.MODEL_TYPES:
                    path = models.resolve_model(name, kind).path
                else:
                    path = models.local_copy(name)
                    if path is None:
                        raise ValueError("%s model %s is not available offline" % (kind, name))
                r["weights"][kind] = {"name": name, "ok": True, "path": str(path)}
            except Exception as exc:
                r["weights"][kind] = {"name": name, "ok": False, "error": str(exc).splitlines()[0]}
        try:
            from huggingface_hub import constants
            r["hub_cache"] = constants.HF_HUB_CACHE
        except Exception:
            r["hub_cache"] = ""
    except Exception as exc:
        r["errors"]["weights"] = "%s: %s" % (type(exc).__name__, exc)
if r["modules"].get("overseec_core") and not weights_only:
    try:
        from overseec_core.plan import planner_backend
        backend = planner_backend()
        r["planner"] = {"name": backend.name, "text": backend.describe()}
    except Exception as exc:
        r["planner"] = {"name": "", "text": "unknown (%s: %s)" % (type(exc).__name__, exc)}
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
    #: kind -> {"name", "ok", "path" or "error"} for the CLIPSeg (and, when refining, SAM) model.
    weights: dict = field(default_factory=dict)
    #: Which planner the worker plans with: "compiled kernel (...)" or "fallback (...): why" ("" unknown).
    planner: str = ""
    problems: tuple[str, ...] = ()
    advice: tuple[str, ...] = ()
    #: True when the dock's "Set up environment" action fixes (some of) the problems.
    setup_helps: bool = False

    @property
    def missing_weights(self) -> tuple[str, ...]:
        """Display names of the models whose weights were not found ("CLIPSeg", "SAM")."""
        return tuple(MODEL_NAMES.get(k, k) for k, w in self.weights.items() if not w.get("ok"))

    @property
    def all_ok(self) -> bool:
        """Everything a full run needs: the core, the models' packages and their weights."""
        return self.ok and self.models_ok and not self.problems

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
        if self.planner:
            lines.append(f"planner: {self.planner}")
        for kind, w in self.weights.items():
            state = f"found in {w['path']}" if w.get("ok") else "MISSING"
            lines.append(f"{MODEL_NAMES.get(kind, kind)} weights ({w.get('name')}): {state}")
        lines += [f"problem: {p}" for p in self.problems]
        lines += [f"to fix: {a}" for a in self.advice]
        if self.all_ok:
            lines.append("environment OK")
        return "\n".join(lines)


def project_dir_of(worker: str | os.PathLike) -> Path | None:
    """The checkout a ``<project>/.venv/bin/overseec`` worker belongs to, when it looks like one."""
    venv = venvs.venv_of(Path(worker).resolve() if Path(worker).exists() else worker)
    project = venv.parent
    if (project / "Makefile").is_file() and (project / "overseec_core").is_dir():
        return project
    return None


_venv_of = venvs.venv_of
#: The venv's site-packages for this interpreter's version (both layouts; may be empty).
site_packages = venvs.site_packages


def missing_core_modules() -> list[str]:
    """The core packages (:data:`CORE_MODULES`) this interpreter cannot import."""
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
    """Make the core's raster reading importable here, borrowing the venv's packages if needed.

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
    root = Path(venv) if venv else (_venv_of(worker) if worker else None)
    pip = venvs.executable(root, "pip") if root else "<venv>/bin/pip"
    advice = [
        f"{SETUP_ACTION} (it makes a venv from QGIS's Python {py} with --system-site-packages "
        "and installs overseec[models] into it; QGIS borrows its packages)",
        f"or, by hand: {pip} install {' '.join(_pip_name(m) for m in missing)}",
    ]
    return EnvReport(
        ok=False,
        python=sys.version.split()[0],
        problems=(f"QGIS's Python {py} cannot import {', '.join(missing)}",),
        advice=tuple(advice),
        setup_helps=True,
    )


def _pip_name(module: str) -> str:
    return {"skimage": "scikit-image"}.get(module, module)


def _setting(kind: str) -> str:
    """The Options page field that names a model of ``kind`` (a refiner's: 'SAM model'; a
    segmenter other than CLIPSeg: 'Segmenter model')."""
    if kind in REFINER_KINDS:
        return "SAM model"
    return f"{MODEL_NAMES[kind]} model" if kind in MODEL_NAMES else "Segmenter model"


def _flag(kind: str) -> str:
    """The CLI flag that names a model of ``kind``."""
    return "--sam-model" if kind in REFINER_KINDS else "--clipseg-model" if kind == "clipseg" else "--model"


def weights_advice(report: EnvReport) -> tuple[str, ...]:
    """How to provide the missing model weights on a machine without network (one line each)."""
    lines = []
    for kind, w in report.weights.items():
        if w.get("ok"):
            continue
        label = MODEL_NAMES.get(kind, kind)
        flag = _flag(kind)
        lines.append(
            f"copy a {label} model folder (saved with save_pretrained; `overseec models path {w.get('name')}` "
            f"prints it on a machine that has the model) and set {OPTIONS_PAGE} › {_setting(kind)} to that "
            f"folder (the CLI's {flag})"
        )
    if lines:
        lines.append(
            "or copy a whole Hugging Face cache and start QGIS with HF_HOME set to it; "
            "with network: overseec models download NAME"
        )
    return tuple(lines)


def check_worker(
    worker: str | os.PathLike | None,
    timeout_s: float = 120.0,
    clipseg_model: str = "",
    sam_model: str = "",
    refine: bool = True,
    weights_only: bool = False,
    segmenter: str = "clipseg",
    model: str = "",
    refiner: str = "sam",
) -> EnvReport:
    """Ask the worker's interpreter what it has (in a subprocess: torch stays out of QGIS).

    ``clipseg_model`` / ``sam_model`` are the plugin's model settings ("" = the core's defaults);
    ``segmenter`` the coarse segmenter and ``model`` the model of a segmenter other than CLIPSeg
    ("" = its default); ``refiner`` the refiner (sam, sam-hq, sam2) whose checkpoint
    ``sam_model`` names ("" = that refiner's default: each has its own), checked as that kind and
    reported under the refiner's name. Its weights are checked only when ``refine`` is on
    (segmentation without refinement never loads a refiner). ``weights_only`` skips the packages
    (only ``weights`` is meaningful then).
    """
    from overseec_core import __version__ as plugin_version

    if worker is None or not Path(worker).is_file():
        return EnvReport(
            ok=False,
            problems=("the overseec worker (the `overseec` command of a Python environment) was not found",),
            advice=(
                f"{SETUP_ACTION}: it creates the environment and installs overseec[models] into it",
                f"or point {OPTIONS_PAGE} › 'overseec command' at an existing <venv>/bin/overseec "
                "(<venv>\\Scripts\\overseec.exe on Windows), or start QGIS with OVERSEEC_VENV=<venv>",
            ),
            setup_helps=True,
        )
    python = worker_python(worker)
    sam = "" if not refine else (sam_model or _default_refiner_model(refiner))
    seg_model = clipseg_model if segmenter == "clipseg" else model
    try:
        # -I: isolated, so neither the current folder nor PYTHONPATH can lend it packages
        proc = subprocess.run(
            [str(python), "-I", "-c", _PROBE, seg_model, sam, "weights" if weights_only else "all", segmenter, refiner],
            capture_output=True,
            text=True,
            timeout=timeout_s,
            env=worker_env(),
        )
        data = json.loads(proc.stdout.strip().splitlines()[-1])
    except (OSError, subprocess.SubprocessError, ValueError, IndexError) as exc:
        return EnvReport(
            ok=False,
            worker=str(worker),
            problems=(f"{python} could not be run to check the environment ({exc})",),
            advice=(f"{SETUP_ACTION} (it makes a new environment)",),
            setup_helps=True,
        )
    modules = data.get("modules", {})
    errors = data.get("errors", {})
    problems, advice = [], []
    setup_helps = False
    venv = _venv_of(worker)
    project = project_dir_of(worker)
    pip = venvs.executable(venv, "pip")
    if not modules.get("overseec_core"):
        problems.append(f"overseec_core is not installed in {venv} ({errors.get('overseec_core', '')})")
        setup_helps = True
    core_missing = [m for m in ("numpy", "scipy", "rasterio", "shapely", "skimage") if not modules.get(m)]
    if core_missing:
        problems.append(f"missing in the worker environment: {', '.join(core_missing)}")
        setup_helps = True
    models_missing = [m for m in MODEL_MODULES if not modules.get(m)]
    if models_missing:
        detail = "; ".join(errors.get(m, "") for m in models_missing if errors.get(m))
        problems.append(
            f"segmentation needs {' and '.join(models_missing)}, which the worker "
            f"environment lacks{' (' + detail + ')' if detail else ''}"
        )
        setup_helps = True
    core_version = modules.get("overseec_core")
    if core_version and core_version != plugin_version:
        problems.append(f"the worker runs overseec {core_version} but the plugin is {plugin_version}")
        setup_helps = True
    if setup_helps:
        target = f"-e {project}[models]" if project else "overseec[models]"
        advice.append(f"{SETUP_ACTION} (installs overseec[models] into {venv})")
        advice.append(f"or, by hand: {pip} install {target}")
    weights = data.get("weights", {})
    missing = [MODEL_NAMES.get(k, k) for k, w in weights.items() if not w.get("ok")]
    if missing:
        names = " and ".join(
            f"{MODEL_NAMES.get(k, k)} ({w.get('name')})" for k, w in weights.items() if not w.get("ok")
        )
        cache = data.get("hub_cache") or "the Hugging Face cache"
        problems.append(
            f"model weights missing: {names}: not a model folder and not in {cache}; segmentation cannot run"
        )
    ok = bool(core_version) and not core_missing and core_version == plugin_version
    report = EnvReport(
        ok=ok,
        models_ok=not models_missing and not core_missing,
        worker=str(worker),
        python=data.get("python", ""),
        device=data.get("device", ""),
        device_name=data.get("device_name", ""),
        modules=modules,
        weights=weights,
        planner=str(data.get("planner", {}).get("text", "")),
        problems=tuple(problems),
        advice=tuple(advice),
        setup_helps=setup_helps,
    )
    return replace(report, advice=report.advice + weights_advice(report))


def _default_refiner_model(refiner: str) -> str:
    """The default checkpoint of ``refiner`` (the core's refiners' table; light, no torch)."""
    from overseec_core.locate.refiners import REFINERS

    info = REFINERS.get(refiner)
    if info is None:
        raise ValueError(f"unknown refiner {refiner!r}; use one of {', '.join(REFINERS)}")
    return info.default_model


def segment_problem(
    worker: str | os.PathLike,
    clipseg_model: str = "",
    sam_model: str = "",
    refine: bool = True,
    segmenter: str = "clipseg",
    model: str = "",
    refiner: str = "sam",
) -> str:
    """ "" when the worker has every model segmentation will load (the ``refiner``'s checkpoint
    among them), else one line naming each
    missing one and where to set a copied folder (run before Segment: the CLI itself stops at
    the first missing model)."""
    report = check_worker(
        worker,
        clipseg_model=clipseg_model,
        sam_model=sam_model,
        refine=refine,
        weights_only=True,
        segmenter=segmenter,
        model=model,
        refiner=refiner,
    )
    missing = [(k, w) for k, w in report.weights.items() if not w.get("ok")]
    if not missing:
        return ""
    names = " and ".join(f"{MODEL_NAMES.get(k, k)} ({w.get('name')})" for k, w in missing)
    settings = " / ".join(_setting(k) for k, _ in missing)
    return (
        f"model weights missing: {names}; set {OPTIONS_PAGE} › {settings} to a copied model folder "
        "(Check environment says how to get one)"
    )


def fix_tool_problem(worker: str | os.PathLike | None, sam_model: str = "") -> str:
    """ "" when the worker can run the fix-mask tool's SAM (``sam_model``, "" = the default
    checkpoint), else one line saying what is missing and where to set it: checked when the tool
    is chosen, so the analyst learns it before the first click, in the options page's terms."""
    report = check_worker(worker, sam_model=sam_model, refine=True, weights_only=True, refiner="sam")
    if worker is None or not Path(worker).is_file():
        return f"the fix-mask tool runs SAM in the overseec environment: {report.problems[0]}"
    sam = report.weights.get("sam")
    if sam is None:
        return f"the fix-mask tool cannot check SAM: {report.problems[0]}" if report.problems else ""
    return "" if sam.get("ok") else fix_tool_missing_sam(str(sam.get("name")))


def fix_tool_missing_sam(name: str) -> str:
    """The one line saying the fix-mask tool lacks SAM checkpoint ``name``, and the remedy."""
    return (
        f"the fix-mask tool needs SAM weights ({name}), which are missing: set "
        f"{OPTIONS_PAGE} › {_setting('sam')} to a copied model folder (Check environment says how to get one)"
    )
