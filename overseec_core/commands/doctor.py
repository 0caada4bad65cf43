"""`overseec doctor`: what this installation has, and what it would use.

Versions (Python, GDAL, rasterio, numpy, torch, transformers, QGIS), how overseec was installed,
which planner it plans with (the compiled kernel, or the scikit-image fallback and why), the
compute device, the model cache and which default models are in it (each segmenter's and SAM's),
and whether the configured LLM endpoint answers. Each check is independent: a missing piece is
reported, never a crash, and the advice fits the install (`make setup` in a checkout, pip for a wheel or sdist).

`overseec doctor --kernel` checks the planner itself, from any install: it plans small grids
(a wall with one gap; a seeded costmap with non-square pixels and lethal cells) with the compiled
kernel, exact and fast, and compares the costs with scikit-image's MCP_Geometric (the same step
rule). Exit 1 when the kernel plans wrong; with no kernel it says that the fallback planner is in
use, checks the fallback the same way, and exits 0.
"""

from __future__ import annotations

import argparse
import importlib
import os
import platform
import shutil
import subprocess
import urllib.error
import urllib.request
from typing import Any

from overseec_core import install
from overseec_core.commands import print_json
from overseec_core.locate.refiners import REFINERS
from overseec_core.locate.segmenters import SEGMENTERS
from overseec_core.progress import Progress

#: What each default model is for: the segmenters' (the registry's) and the refiners' (their table's).
MODEL_ROLES = {
    **{info.default_model: info.name for info in SEGMENTERS.values()},
    **{info.default_model: f"refine ({info.name})" for info in REFINERS.values()},
}
DEFAULT_MODELS = tuple(MODEL_ROLES)


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `doctor` subcommand: --json, --kernel and the LLM endpoint to probe."""
    p = sub.add_parser("doctor", help="check the installation: versions, device, models, LLM", description=__doc__)
    p.add_argument("--json", action="store_true", help="print a JSON document")
    p.add_argument(
        "--kernel",
        action="store_true",
        help="check the planner: plan small grids with the compiled kernel against scikit-image "
        "(exit 1 when it plans wrong; with no kernel, say that the fallback is in use)",
    )
    p.add_argument(
        "--llm-url",
        default=os.environ.get("OVERSEEC_LLM_URL"),
        metavar="URL",
        help="OpenAI-compatible endpoint to probe (default: $OVERSEEC_LLM_URL)",
    )
    p.set_defaults(func=run)


def _version(module: str) -> str | None:
    try:
        return getattr(importlib.import_module(module), "__version__", "installed")
    except Exception:
        return None


def _qgis_version() -> str | None:
    """Ask QGIS's own tool rather than importing qgis (the core never imports it)."""
    exe = shutil.which("qgis_process.bin") or shutil.which("qgis_process")
    if exe is None:
        return None
    env = dict(os.environ, QT_QPA_PLATFORM=os.environ.get("QT_QPA_PLATFORM", "offscreen"))
    try:
        out = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=60, env=env)
    except (OSError, subprocess.TimeoutExpired):
        return "present (version unknown)"
    for line in out.stdout.splitlines():
        if line.startswith("QGIS"):
            return line.split(maxsplit=1)[1].strip()
    return "present (version unknown)"


def _device() -> dict[str, Any]:
    try:
        import torch
    except Exception:
        advice = install.detect().extra_advice("models")
        return {"device": None, "note": f"torch not installed (segmentation needs it): {advice}"}
    info: dict[str, Any] = {
        "cuda": torch.cuda.is_available(),
        "mps": bool(getattr(torch.backends, "mps", None) and torch.backends.mps.is_available()),
        "threads": torch.get_num_threads(),
    }
    if info["cuda"]:
        info["device"] = "cuda"
        info["cuda_name"] = torch.cuda.get_device_name(0)
    else:
        info["device"] = "mps" if info["mps"] else "cpu"
    return info


def _models() -> dict[str, Any]:
    try:
        from huggingface_hub import constants, try_to_load_from_cache
    except Exception:
        advice = install.detect().extra_advice("models")
        return {"cache": None, "present": {}, "note": f"huggingface_hub not installed: {advice}"}
    present = {}
    for model in DEFAULT_MODELS:
        hit = try_to_load_from_cache(model, "config.json")
        present[model] = isinstance(hit, str)
    return {"cache": constants.HF_HUB_CACHE, "present": present, "roles": dict(MODEL_ROLES)}


def _llm(url: str | None) -> dict[str, Any]:
    """Whether ``url`` answers ``GET /models``. No credentials are sent (any HTTP answer, 401
    included, means reachable); the URL is shown with its user:password as ``***@`` and the error
    text is redacted, since the report is printed and may be pasted into an issue."""
    from overseec_core.interpret.llm import redact, redact_url, split_userinfo, url_secrets

    if not url:
        return {"url": None, "reachable": None, "note": "no LLM configured: the offline interpreter is used"}
    shown = redact(redact_url(url), url_secrets(url))
    probe = split_userinfo(url)[0].rstrip("/") + "/models"
    try:
        with urllib.request.urlopen(probe, timeout=3) as resp:
            return {"url": shown, "reachable": True, "status": resp.status}
    except urllib.error.HTTPError as exc:
        return {"url": shown, "reachable": True, "status": exc.code}
    except (urllib.error.URLError, OSError, ValueError) as exc:
        reason = getattr(exc, "reason", exc)
        return {"url": shown, "reachable": False, "error": redact(str(reason), url_secrets(url))}


def collect(llm_url: str | None = None) -> dict[str, Any]:
    """The installation report: package versions, install kind, planner backend, torch device,
    model cache and whether the LLM endpoint answers."""
    import rasterio

    versions = {
        "overseec": _version("overseec_core"),
        "python": platform.python_version(),
        "gdal": rasterio.__gdal_version__,
        "rasterio": rasterio.__version__,
        "numpy": _version("numpy"),
        "scipy": _version("scipy"),
        "shapely": _version("shapely"),
        "pyproj": _version("pyproj"),
        "torch": _version("torch"),
        "transformers": _version("transformers"),
        "dask": _version("dask"),
        "qgis": _qgis_version(),
    }
    return {
        "versions": versions,
        "install": _install(),
        "planner": _planner(),
        "device": _device(),
        "models": _models(),
        "llm": _llm(llm_url),
    }


def _install() -> dict[str, Any]:
    how = install.detect()
    return {
        "kind": how.kind,
        "checkout": None if how.checkout is None else str(how.checkout),
        "source": None if how.source is None else str(how.source),
        "python": how.python,
    }


def _planner() -> dict[str, Any]:
    """Which planner a Planner made now uses (the compiled kernel or the fallback, and why)."""
    from overseec_core.errors import OverseecError
    from overseec_core.plan import planner_backend

    try:
        backend = planner_backend()
    except OverseecError as exc:  # OVERSEEC_PLANNER wrong, or =kernel without one
        return {"planner": None, "error": str(exc), "summary": f"cannot plan: {exc}"}
    return {**backend.to_json(), "summary": backend.describe()}


# ------------------------------------------------------------------------------------------------
# --kernel: the planner's smoke check (also scripts/kernel_smoke.py, cibuildwheel's wheel test)
# ------------------------------------------------------------------------------------------------


def _check_grids() -> list[tuple[str, Any, tuple[float, float], list[tuple[int, int]]]]:
    """(name, cost, (dx, dy) metres, points) of the grids the check plans on."""
    import numpy as np

    # 9 x 9 unit costs, 2 m x 1 m pixels, a wall on column 4 with a gap in the bottom row
    wall = np.ones((9, 9), np.float32)
    wall[:8, 4] = np.inf
    # seeded costs in [0, 1], 0.7 m x 1.3 m pixels, 15 % lethal cells, a via point
    rng = np.random.default_rng(21)
    seeded = rng.random((48, 64)).astype(np.float32)
    seeded[rng.random(seeded.shape) < 0.15] = np.inf
    points = [(0, 0), (24, 40), (47, 63)]
    for r, c in points:
        seeded[r, c] = 0.5
    return [
        ("9 x 9 wall, 2 x 1 m px", wall, (2.0, 1.0), [(0, 0), (0, 8)]),
        ("64 x 48 seeded, 0.7 x 1.3 m px, lethal cells, a via", seeded, (0.7, 1.3), points),
    ]


def _mcp_cost(cost: Any, pixel: tuple[float, float], base: float, points: list[tuple[int, int]]) -> float:
    """The reference: MCP_Geometric's cheapest cost through ``points``, leg by leg."""
    import numpy as np
    from skimage.graph import MCP_Geometric

    mcp = MCP_Geometric(cost.astype(np.float64) + base, sampling=(pixel[1], pixel[0]))
    total = 0.0
    for a, b in zip(points[:-1], points[1:]):
        cum, _ = mcp.find_costs([a], [b])
        total += float(cum[b])
    return total


def kernel_check() -> dict[str, Any]:
    """Plan the check grids with the compiled kernel (exact and fast; the fallback when there is
    no kernel) and compare each cost with MCP_Geometric. ``ok`` is False only when a planner plans
    wrong; ``kernel`` says whether the compiled kernel was checked; ``line`` is a one-line summary
    beginning with "kernel FILE:" or "no compiled kernel:"."""
    import math

    from overseec_core.plan import Planner, PlanningGrid, planner_backend

    installed = planner_backend("auto")
    use = "kernel" if installed.name == "kernel" else "fallback"
    base = 0.01
    results, ok = [], True
    for name, cost, pixel, points in _check_grids():
        planner = Planner(PlanningGrid.from_array(cost, pixel_size_m=pixel), base, planner=use)
        exact = planner.plan(points, mode="exact")
        fast = planner.plan(points, mode="fast")
        want = _mcp_cost(cost, pixel, base, points)
        good = (
            math.isclose(exact.cost, want, rel_tol=1e-9)
            and fast.cost >= want * (1 - 1e-9)
            and fast.bound <= want * (1 + 1e-9)
            and math.isclose(exact.cost, planner.path_cost(exact.pixels), rel_tol=1e-9)
            and tuple(exact.pixels[0]) == points[0]
            and tuple(exact.pixels[-1]) == points[-1]
            and bool(math.isfinite(cost[exact.pixels[:, 0], exact.pixels[:, 1]].max()))
        )
        ok = ok and good
        results.append({"grid": name, "exact": exact.cost, "fast": fast.cost, "mcp": want, "ok": good})
    first = results[0]
    figures = f"exact {first['exact']:.6f} fast {first['fast']:.6f} mcp {first['mcp']:.6f}"
    if use == "kernel":
        line = f"kernel {installed.kernel_file}: {figures}" + ("" if ok else " -- WRONG COSTS")
    else:
        line = (
            f"no compiled kernel: the fallback planner is in use ({installed.reason}); "
            f"the fallback plans {'correctly' if ok else 'WRONG COSTS'}: {figures}"
        )
    return {"ok": ok, "kernel": use == "kernel", "planner": installed.to_json(), "grids": results, "line": line}


def run_kernel_check(args: argparse.Namespace) -> int:
    """`doctor --kernel`: print the planner check (kernel_check) per grid; 1 when a planner plans wrong.
    An ``OVERSEEC_PLANNER`` that `plan` would refuse (unknown, or the kernel where none loads) is
    refused here too, in the same one line, before anything is checked."""
    from overseec_core.plan import planner_backend

    planner_backend()  # InputError / PlanError: what `plan` says about this environment
    report = kernel_check()
    if args.json:
        print_json(args, report)
    else:
        print(report["line"])
        for g in report["grids"]:
            state = "ok" if g["ok"] else "WRONG"
            print(f"  {g['grid']:<52} exact {g['exact']:.6f}  fast {g['fast']:.6f}  mcp {g['mcp']:.6f}  {state}")
        forced = os.environ.get("OVERSEEC_PLANNER", "").strip().lower()
        if report["kernel"] and forced and forced != "auto":
            print(f"  (OVERSEEC_PLANNER={forced} is set: routes are planned with {forced})")
    return 0 if report["ok"] else 1


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `doctor`: print the installation report (collect) as aligned lines or JSON, or the
    planner check with --kernel. Writes nothing."""
    if args.kernel:
        return run_kernel_check(args)
    report = collect(args.llm_url)
    if args.json:
        print_json(args, report)
        return 0
    for name, version in report["versions"].items():
        print(f"{name:<13} {version or 'not installed'}")
    how = report["install"]
    where = how["checkout"] or how["source"] or ""
    print(f"{'install':<13} {how['kind']}{' (' + where + ')' if where else ''}, python {how['python']}")
    print(f"{'planner':<13} {report['planner']['summary']}")
    dev = report["device"]
    print(
        f"{'device':<13} {dev.get('device') or dev.get('note')}"
        + (f" ({dev['cuda_name']})" if dev.get("cuda_name") else "")
    )
    models = report["models"]
    print(f"{'model cache':<13} {models['cache'] or models.get('note')}")
    for model, ok in models["present"].items():
        role = models.get("roles", {}).get(model, "")
        print(f"  {role:<13} {model:<42} {'present' if ok else 'missing: overseec models download ' + model}")
    llm = report["llm"]
    state = llm.get("note") or ("reachable" if llm["reachable"] else f"NOT reachable ({llm.get('error')})")
    print(f"{'llm':<13} {llm['url'] or ''} {state}".rstrip())
    return 0
