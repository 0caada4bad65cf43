"""How this copy of overseec was installed, and advice that fits it.

Three kinds, told apart by pip's install record (``direct_url.json``, PEP 610) and by where the
package lies:

* ``checkout``: the Debian flow, ``make setup`` -- an editable install from a source checkout
  whose ``.venv`` is the running environment. Advice: ``make setup`` in that checkout.
* ``editable``: an editable install from a checkout into another environment (``pip install -e``
  on macOS, Windows, conda ...). Advice: ``pip install -e "<checkout>[models]"``.
* ``package``: a wheel or sdist installed by pip (from PyPI or a local file). Advice: ``pip
  install "overseec[models]"``, or the local wheel, sdist or source folder it was installed from
  when that is still there.

Every pip command is spelt with this interpreter's full path (``<python> -m pip``), so it targets
the environment overseec runs in whatever is on PATH. Nothing here imports more than the standard
library.
"""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass
from functools import lru_cache
from importlib import metadata
from pathlib import Path
from typing import Any
from urllib.parse import unquote, urlparse

#: The distribution name on PyPI.
DIST_NAME = "overseec"
KINDS = ("checkout", "editable", "package")


@dataclass(frozen=True)
class Install:
    """Where overseec runs from: its kind, the checkout (if any) and the local file pip used."""

    kind: str
    #: The source checkout of an editable install (``checkout`` / ``editable``).
    checkout: Path | None = None
    #: The local wheel, sdist or source folder pip installed from, when it still exists (``package``).
    source: Path | None = None
    python: str = sys.executable

    @property
    def pip(self) -> str:
        """pip of the running environment, as a command line."""
        return f"{_quote(self.python)} -m pip"

    def requirement(self, extra: str | None = None) -> str:
        """What to hand pip to (re)install this overseec, with ``extra`` (quoted for a shell)."""
        suffix = f"[{extra}]" if extra else ""
        if self.kind in ("checkout", "editable") and self.checkout is not None:
            return f'-e "{self.checkout}{suffix}"'
        if self.source is not None:
            return f'"{self.source}{suffix}"'
        return f'"{DIST_NAME}{suffix}"'

    def extra_advice(self, extra: str = "models") -> str:
        """How to add an optional extra (``models``: torch, transformers, huggingface_hub)."""
        if self.kind == "checkout" and self.checkout is not None:
            return f"run `make setup` in {self.checkout}"
        return f"{self.pip} install {self.requirement(extra)}"

    def reinstall_advice(self) -> str:
        """How to put back a damaged install (package data or the compiled kernel missing)."""
        if self.kind == "checkout" and self.checkout is not None:
            return f"run `make setup` in {self.checkout}"
        if self.kind == "editable" and self.checkout is not None:
            return f"{self.pip} install {self.requirement()}"
        if self.source is None:  # the file it came from is unknown or gone (overseec is on no index yet)
            return f"{self.pip} install --force-reinstall --no-deps <the overseec wheel or sdist>"
        return f"{self.pip} install --force-reinstall --no-deps {self.requirement()}"

    def kernel_advice(self) -> str:
        """How to get the compiled planner kernel where the fallback is in use."""
        if self.kind == "checkout" and self.checkout is not None:
            return f"run `make setup` in {self.checkout} (it builds the kernel)"
        compiler = (
            "a C compiler (gcc or clang; Xcode's command-line tools on macOS; Visual Studio Build Tools on Windows)"
        )
        return f"install {compiler} and reinstall: {self.reinstall_advice()}"


def _quote(text: str) -> str:
    return f'"{text}"' if any(c.isspace() for c in text) else text


def _direct_url() -> dict[str, Any]:
    """pip's record of where overseec was installed from ({} when absent or unreadable)."""
    try:
        text = metadata.distribution(DIST_NAME).read_text("direct_url.json")
        return json.loads(text) if text else {}
    except (metadata.PackageNotFoundError, ValueError, OSError):
        return {}


def _file_of(url: str) -> Path | None:
    parsed = urlparse(url)
    if parsed.scheme != "file":
        return None
    path = unquote(parsed.path)
    if sys.platform == "win32" and path.startswith("/") and len(path) > 2 and path[2] == ":":
        path = path[1:]  # file:///C:/... -> C:/...
    return Path(path)


def is_checkout(folder: Path) -> bool:
    """A source checkout of overseec: the build files beside the package."""
    return (
        (folder / "pyproject.toml").is_file()
        and (folder / "setup.py").is_file()
        and (folder / "overseec_core").is_dir()
    )


@lru_cache(maxsize=1)
def detect() -> Install:
    """This installation's :class:`Install` (cached: it cannot change while running)."""
    package_root = Path(__file__).resolve().parent.parent
    direct = _direct_url()
    editable = bool(direct.get("dir_info", {}).get("editable"))
    if is_checkout(package_root):
        checkout = package_root
    elif editable and (source := _file_of(direct.get("url", ""))) is not None and is_checkout(source):
        checkout = source
    else:
        checkout = None
    if checkout is not None:
        in_own_venv = Path(sys.prefix).resolve() == (checkout / ".venv").resolve()
        has_make = (checkout / "Makefile").is_file()
        return Install("checkout" if in_own_venv and has_make else "editable", checkout=checkout)
    source = _file_of(direct.get("url", ""))
    if source is not None and not (source.is_file() if "archive_info" in direct else is_checkout(source)):
        source = None
    return Install("package", source=source)


__all__ = ["DIST_NAME", "KINDS", "Install", "detect", "is_checkout"]
