"""Where things live inside a Python virtual environment, for both layouts.

A venv made on Linux or macOS keeps its programs in ``bin/`` (``bin/python3``, ``bin/pip``,
``bin/overseec``) and its packages in ``lib/pythonX.Y/site-packages``; one made on Windows keeps
them in ``Scripts/`` (``Scripts/python.exe``, ``Scripts/overseec.exe``) and ``Lib/site-packages``.
The layout is read from the folder itself (whichever of ``bin/`` and ``Scripts/`` exists) and
only falls back to this platform's convention for a venv that does not exist yet, so a path
copied from another machine or written by another tool is still understood.

Plain Python (no Qt): the worker finder, the environment check and the set-up task share it.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

#: The two layouts: (programs folder, executable suffix).
POSIX = ("bin", "")
WINDOWS = ("Scripts", ".exe")


def layout(venv: str | os.PathLike) -> tuple[str, str]:
    """``("bin", "")`` or ``("Scripts", ".exe")`` for ``venv`` (see the module docstring)."""
    root = Path(venv)
    if (root / "Scripts").is_dir() and not (root / "bin").is_dir():
        return WINDOWS
    if (root / "bin").is_dir():
        return POSIX
    return WINDOWS if sys.platform == "win32" else POSIX


def scripts_dir(venv: str | os.PathLike) -> Path:
    """The venv's programs folder (``bin/`` or ``Scripts/``)."""
    return Path(venv) / layout(venv)[0]


def executable(venv: str | os.PathLike, name: str) -> Path:
    """``<venv>/bin/<name>`` or ``<venv>\\Scripts\\<name>.exe``."""
    folder, suffix = layout(venv)
    return Path(venv) / folder / f"{name}{suffix}"


def python(venv: str | os.PathLike) -> Path:
    """The venv's interpreter: ``bin/python3`` (else ``bin/python``) or ``Scripts/python.exe``;
    a conda environment on Windows keeps it at its root (``<env>/python.exe``) instead."""
    for name in ("python3", "python"):
        candidate = executable(venv, name)
        if candidate.is_file():
            return candidate
    if layout(venv) == WINDOWS and (Path(venv) / "python.exe").is_file():
        return Path(venv) / "python.exe"
    return executable(venv, "python3" if layout(venv) == POSIX else "python")


def venv_of(program: str | os.PathLike) -> Path:
    """The venv a program inside it belongs to (``<venv>/bin/x`` or ``<venv>/Scripts/x.exe``)."""
    return Path(program).parent.parent


def sibling(program: str | os.PathLike, name: str) -> Path | None:
    """The program ``name`` in the same folder as ``program`` (with ``.exe`` when that folder
    holds Windows programs), or None when there is none."""
    folder = Path(program).parent
    for candidate in (folder / name, folder / f"{name}.exe"):
        if candidate.is_file():
            return candidate
    return None


def site_packages(venv: str | os.PathLike, version: tuple[int, int] | None = None) -> list[Path]:
    """The venv's site-packages folders for Python ``version`` (default: this one) that exist."""
    major, minor = version or sys.version_info[:2]
    root = Path(venv)
    candidates = [root / "lib" / f"python{major}.{minor}" / "site-packages", root / "Lib" / "site-packages"]
    return [c for c in candidates if c.is_dir()]
