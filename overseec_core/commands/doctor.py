"""`overseec doctor`: what this installation has, and what it would use.

Versions (Python, GDAL, rasterio, numpy, torch, transformers, QGIS), the compute device, the
model cache and which default models are in it, and whether the configured LLM endpoint answers.
Each check is independent: a missing piece is reported, never a crash.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import platform
import shutil
import subprocess
import urllib.error
import urllib.request
from typing import Any

from ..progress import Progress

DEFAULT_MODELS = ("CIDAS/clipseg-rd64-refined", "facebook/sam-vit-base")


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("doctor", help="check the installation: versions, device, models, LLM", description=__doc__)
    p.add_argument("--json", action="store_true", help="print a JSON document")
    p.add_argument(
        "--llm-url",
        default=os.environ.get("OVERSEEC_LLM_URL"),
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
        return {"device": None, "note": "torch not installed: run `make setup`"}
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
        return {"cache": None, "present": {}}
    present = {}
    for model in DEFAULT_MODELS:
        hit = try_to_load_from_cache(model, "config.json")
        present[model] = isinstance(hit, str)
    return {"cache": constants.HF_HUB_CACHE, "present": present}


def _llm(url: str | None) -> dict[str, Any]:
    """Whether ``url`` answers ``GET /models``. No credentials are sent (any HTTP answer, 401
    included, means reachable); the URL is shown with its user:password as ``***@`` and the error
    text is redacted, since the report is printed and may be pasted into an issue."""
    from ..interpret.llm import redact, redact_url, split_userinfo, url_secrets

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
    return {"versions": versions, "device": _device(), "models": _models(), "llm": _llm(llm_url)}


def run(args: argparse.Namespace, progress: Progress) -> int:
    report = collect(args.llm_url)
    if args.json:
        print(json.dumps(report, indent=2))
        return 0
    for name, version in report["versions"].items():
        print(f"{name:<13} {version or 'not installed'}")
    dev = report["device"]
    print(
        f"{'device':<13} {dev.get('device') or dev.get('note')}"
        + (f" ({dev['cuda_name']})" if dev.get("cuda_name") else "")
    )
    models = report["models"]
    print(f"{'model cache':<13} {models['cache']}")
    for model, ok in models["present"].items():
        print(f"  {model:<30} {'present' if ok else 'missing: overseec models download ' + model}")
    llm = report["llm"]
    state = llm.get("note") or ("reachable" if llm["reachable"] else f"NOT reachable ({llm.get('error')})")
    print(f"{'llm':<13} {llm['url'] or ''} {state}".rstrip())
    return 0
