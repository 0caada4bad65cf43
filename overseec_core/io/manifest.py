"""Run directories and their provenance manifest.

Every job writes into one directory: its outputs plus ``manifest.json``, which records what went
in (paths, sizes, SHA-256), how it was asked for (command, arguments, parameters), with what
(versions, model ids) and how long each stage took. Stages re-run alone (re-prompting re-uses
masks) update the same manifest, so it always describes the files beside it.

Two commands may write into one folder at once (a QGIS re-plan while a batch `costmap` runs).
Each :class:`RunDir` therefore remembers what *it* changed and, on every save, re-reads the
manifest under an exclusive lock, applies its changes on top and writes it back: no entry of
the other writer is lost.

A damaged manifest is refused, never replaced: a ``manifest.json`` that is not a UTF-8 JSON
object (binary, truncated, a JSON list, a folder) is one :class:`~overseec_core.errors.OutputError`
naming it (``DIR/manifest.json is not a manifest (not UTF-8 JSON object); move it away or choose
another --out``), raised by :func:`read_manifest` before a command writes anything, so the folder
stays as it was. The bookkeeping names themselves (``manifest.json``, ``.manifest.lock``) are never
an output's name (:func:`check_output_name`).
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
import os
import platform
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

try:
    import fcntl
except ImportError:  # Windows
    fcntl = None  # type: ignore[assignment]
    import msvcrt

from overseec_core import __version__, runfiles
from overseec_core.errors import Cancelled, OutputError
from overseec_core.io.atomic import write_text_atomic

MANIFEST_NAME = runfiles.MANIFEST
#: Windows only (POSIX locks the folder itself): a hidden lock file beside the manifest; it
#: stays, since removing it would race with other writers.
LOCK_NAME = runfiles.MANIFEST_LOCK
_HASH_CHUNK = 4 << 20


def sha256_file(path: str | os.PathLike) -> str:
    """Hex SHA-256 of a file, read in chunks (inputs can be gigabytes)."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        while chunk := f.read(_HASH_CHUNK):
            h.update(chunk)
    return h.hexdigest()


def _now() -> str:
    return _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds")


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


def read_manifest(folder: str | os.PathLike) -> dict[str, Any] | None:
    """The manifest of a run folder, or None when it has none.

    Refuses (OutputError, one line) a ``manifest.json`` that is not a regular file holding a UTF-8
    JSON object, and one that cannot be read: the command stops before writing anything, and the
    damaged file (the user's to look at) is neither merged into nor replaced.
    """
    file = Path(folder) / MANIFEST_NAME
    if not os.path.lexists(file):
        return None
    data: Any = None
    if file.is_file():  # not a folder, a FIFO or a device (nothing to block on or read forever)
        try:
            data = json.loads(file.read_bytes().decode("utf-8"))
        except OSError as exc:
            raise OutputError(
                f"cannot read {file} ({exc.strerror or exc}); move it away or choose another --out"
            ) from None
        except (UnicodeDecodeError, ValueError, RecursionError):
            data = None
    if not isinstance(data, dict):
        raise OutputError(f"{file} is not a manifest (not UTF-8 JSON object); move it away or choose another --out")
    return data


def check_run_folder(folder: str | os.PathLike) -> None:
    """Refuse, before any output is written, a run folder whose manifest is damaged
    (:func:`read_manifest`); a folder that does not exist yet is fine."""
    if Path(folder).is_dir():
        read_manifest(folder)


def check_output_name(path: str | os.PathLike) -> None:
    """Refuse an output named like the run folder's bookkeeping (manifest.json, .manifest.lock):
    writing it would merge into, or be lost under, the manifest."""
    if runfiles.is_bookkeeping_name(path):
        raise OutputError(
            f"{path} is the run folder's bookkeeping file ({Path(path).name}), never an output; choose another name"
        )


def write_json_atomic(path: str | os.PathLike, data: Any) -> Path:
    """Write JSON to a temporary file beside ``path`` and rename it into place."""
    return write_text_atomic(path, json.dumps(data, indent=2, default=str) + "\n")


def _acquire(folder: Path) -> Callable[[], None]:
    """Take the folder's exclusive lock and return the function that releases it.

    POSIX: a flock on the folder itself, so no file is left behind. Windows, where a folder
    cannot be locked: a byte lock on a hidden lock file beside the manifest.
    """
    if fcntl is not None:
        fd = os.open(folder, os.O_RDONLY)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
        except BaseException:
            os.close(fd)
            raise

        def release_folder() -> None:
            fcntl.flock(fd, fcntl.LOCK_UN)
            os.close(fd)

        return release_folder
    f = open(folder / LOCK_NAME, "a+b")
    for _ in range(6):  # msvcrt.LK_LOCK itself retries for 10 s; a minute in all
        try:
            msvcrt.locking(f.fileno(), msvcrt.LK_LOCK, 1)
            break
        except OSError:
            continue
    else:
        f.close()
        raise OutputError(f"{folder}: another overseec process holds the manifest lock")

    def release_file() -> None:
        f.seek(0)
        msvcrt.locking(f.fileno(), msvcrt.LK_UNLCK, 1)
        f.close()

    return release_file


@contextmanager
def folder_lock(folder: str | os.PathLike) -> Iterator[None]:
    """Hold the run folder's exclusive advisory lock (against other overseec processes)."""
    try:
        release = _acquire(Path(folder))
    except OSError as exc:
        raise OutputError(f"cannot lock {folder} ({exc.strerror or exc})") from None
    try:
        yield
    finally:
        release()


class RunDir:
    """A job's output directory and its manifest (created or continued).

    Changes go through :meth:`set`, :meth:`record_input`, :meth:`update_parameters` and
    :meth:`stage`, which also note them, so :meth:`save` can merge them into whatever another
    process saved in the meantime. A damaged ``manifest.json`` in the folder is refused, on
    opening and on every save (:func:`read_manifest`), never replaced.
    """

    def __init__(self, path: str | os.PathLike, command: str | None = None, args: dict[str, Any] | None = None) -> None:
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
        #: (section, key) or (key,) -> value this RunDir set; re-applied on every save.
        self._changes: dict[tuple[str, ...], Any] = {}
        self._commands: list[dict[str, Any]] = []
        self.set("updated", _now())
        self.set("versions", software_versions())
        if command is not None:
            entry = {"command": command, "args": args or {}, "at": _now(), "pid": os.getpid()}
            self._commands.append(entry)
            self.data.setdefault("commands", []).append(entry)

    def _load(self) -> dict[str, Any]:
        data = read_manifest(self.path)  # a damaged manifest is refused, never replaced
        if data is not None:
            return data
        return {"overseec_version": __version__, "created": _now(), "inputs": {}, "parameters": {}, "stages": {}}

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
        self._put(("inputs", role), entry)

    def set(self, key: str, value: Any) -> None:
        """Set a top-level manifest entry (entities, program, models, parameters ...)."""
        self._put((key,), value)

    def set_entry(self, section: str, key: str, value: Any) -> None:
        """Set one entry of a section ({"exports": {name: ...}}); merged per entry on save, so
        two writers adding entries to one section keep both."""
        self._put((section, key), value)

    def update_parameters(self, **params: Any) -> None:
        for key, value in params.items():
            self._put(("parameters", key), value)

    def _put(self, keys: tuple[str, ...], value: Any) -> None:
        self._changes[keys] = value
        _assign(self.data, keys, value)

    @contextmanager
    def stage(self, name: str) -> Iterator[dict[str, Any]]:
        """Time a stage and record its outcome; the manifest is saved either way."""
        record: dict[str, Any] = {"started": _now(), "status": "running"}
        self._put(("stages", name), record)
        t0 = time.perf_counter()
        failed = True
        try:
            yield record
            record["status"] = "ok"
            failed = False
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
            try:
                self.save()
            except OutputError:
                if not failed:
                    raise
                # the stage's own error (often the same full disk) is the one to report

    def save(self) -> Path:
        """Merge this RunDir's changes into the manifest on disk, under the folder's lock."""
        with folder_lock(self.path):
            current = self._load()
            for keys, value in self._changes.items():
                _assign(current, keys, value)
            commands = current.setdefault("commands", [])
            commands += [c for c in self._commands if c not in commands]
            self.data = current
            return write_json_atomic(self.manifest_path, current)


def _assign(data: dict[str, Any], keys: tuple[str, ...], value: Any) -> None:
    """data[k1][k2]... = value, creating sections (a non-dict section is replaced)."""
    for key in keys[:-1]:
        section = data.get(key)
        if not isinstance(section, dict):
            section = data[key] = {}
        data = section
    data[keys[-1]] = value
