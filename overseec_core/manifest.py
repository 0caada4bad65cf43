"""Run directories and their provenance manifest.

Every job writes into one directory: its outputs plus ``manifest.json``, which records what went
in (paths, sizes, SHA-256), how it was asked for (command, arguments, parameters), with what
(versions, model ids) and how long each stage took. Stages re-run alone (re-prompting re-uses
masks) update the same manifest, so it always describes the files beside it.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
import os
import platform
import sys
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator

from . import __version__
from .atomic import write_text_atomic
from .errors import Cancelled, OutputError

MANIFEST_NAME = "manifest.json"
_HASH_CHUNK = 4 << 20


def sha256_file(path: str | os.PathLike) -> str:
    """Hex SHA-256 of a file, read in chunks (inputs can be gigabytes)."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        while chunk := f.read(_HASH_CHUNK):
            h.update(chunk)
    return h.hexdigest()


def _now() -> str:
    return _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")


def software_versions() -> dict[str, str]:
    """Versions of what shaped the outputs; torch/transformers only if this process loaded them."""
    import numpy
    import rasterio

    versions = {
        "overseec": __version__,
        "python": platform.python_version(),
        "platform": platform.platform(),
        "numpy": numpy.__version__,
        "rasterio": rasterio.__version__,
        "gdal": rasterio.__gdal_version__,
    }
    for name in ("scipy", "torch", "transformers", "shapely", "pyproj"):
        module = sys.modules.get(name)
        if module is not None:
            versions[name] = getattr(module, "__version__", "?")
    return versions


def write_json_atomic(path: str | os.PathLike, data: Any) -> Path:
    """Write JSON to a temporary file beside ``path`` and rename it into place."""
    return write_text_atomic(path, json.dumps(data, indent=2, default=str) + "\n")


class RunDir:
    """A job's output directory and its manifest (created or continued)."""

    def __init__(self, path: str | os.PathLike, command: str | None = None,
                 args: dict[str, Any] | None = None) -> None:
        self.path = Path(path)
        if self.path.exists() and not self.path.is_dir():
            raise OutputError(f"run directory {self.path} exists and is not a directory")
        try:
            self.path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise OutputError(f"cannot create run directory {self.path} ({exc.strerror})") from None
        if not os.access(self.path, os.W_OK):
            raise OutputError(f"run directory {self.path} is not writable")
        self.data = self._load()
        self.data["updated"] = _now()
        self.data["versions"] = software_versions()
        if command is not None:
            self.data.setdefault("commands", []).append({"command": command, "args": args or {},
                                                         "at": _now()})

    def _load(self) -> dict[str, Any]:
        file = self.path / MANIFEST_NAME
        if file.exists():
            try:
                return json.loads(file.read_text(encoding="utf-8"))
            except (OSError, json.JSONDecodeError):
                pass  # a damaged manifest is replaced, outputs are still described anew
        return {"overseec_version": __version__, "created": _now(), "inputs": {}, "parameters": {},
                "stages": {}}

    @property
    def manifest_path(self) -> Path:
        return self.path / MANIFEST_NAME

    def file(self, name: str) -> Path:
        """Path of an output inside the run directory."""
        return self.path / name

    def record_input(self, role: str, path: str | os.PathLike, hash_file: bool = True) -> None:
        """Record an input file: absolute path, size and SHA-256."""
        p = Path(path)
        entry: dict[str, Any] = {"path": str(p.resolve()), "size": p.stat().st_size}
        if hash_file:
            entry["sha256"] = sha256_file(p)
        self.data.setdefault("inputs", {})[role] = entry

    def set(self, key: str, value: Any) -> None:
        """Set a top-level manifest entry (entities, program, models, parameters ...)."""
        self.data[key] = value

    def update_parameters(self, **params: Any) -> None:
        self.data.setdefault("parameters", {}).update(params)

    @contextmanager
    def stage(self, name: str) -> Iterator[dict[str, Any]]:
        """Time a stage and record its outcome; the manifest is saved either way."""
        record: dict[str, Any] = {"started": _now(), "status": "running"}
        self.data.setdefault("stages", {})[name] = record
        t0 = time.perf_counter()
        try:
            yield record
            record["status"] = "ok"
        except Cancelled:
            record["status"] = "cancelled"
            raise
        except BaseException as exc:
            record["status"] = "failed"
            record["error"] = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise
        finally:
            record["seconds"] = round(time.perf_counter() - t0, 3)
            record["finished"] = _now()
            self.save()

    def save(self) -> Path:
        return write_json_atomic(self.manifest_path, self.data)
