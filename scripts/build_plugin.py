#!/usr/bin/env python3
"""Build the installable QGIS plugin: ``dist/overseec.zip`` with one folder, ``overseec/``.

QGIS's "Install from ZIP" wants a zip holding exactly one folder with ``metadata.txt`` and an
``__init__.py`` that defines ``classFactory``. The folder gets:

    overseec/metadata.txt          version checked against overseec_core.__version__
    overseec/__init__.py           classFactory; puts the folder on sys.path for the two packages
    overseec/overseec_qgis/        the QGIS adapter
    overseec/overseec_core/        the headless core (same code the CLI runs)
    overseec/resources/icons/, overseec/resources/styles/
    overseec/LICENSE, README.md    when the checkout has them

The zip is pure Python and the same on every platform: no compiled file (``.so``, ``.pyd``,
``.dylib``, ``.dll``) and no C source. QGIS's Python on Windows or macOS could not load a binary
built here, so whatever needs one (the planner's C kernel, torch) runs in the overseec
environment instead: the venv or conda env where ``make setup`` or ``pip install overseec[models]``
built it, whose path the plugin's settings hold. The build refuses (BuildError) a compiled file in
the package tree other than the in-place build of a C source beside it (``make venv`` builds the
kernel there; it stays out of the zip), and any shipped file that is an executable binary.

The zip is reproducible (sorted entries, fixed timestamps). Usage:

    python scripts/build_plugin.py                 # -> dist/overseec.zip
    python scripts/build_plugin.py --dir /tmp/p     # also unpack to /tmp/p/overseec (QGIS_PLUGINPATH=/tmp/p)
"""

from __future__ import annotations

import argparse
import configparser
import os
import re
import shutil
import sys
import tempfile
import zipfile
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
PLUGIN_NAME = "overseec"
PACKAGES = ("overseec_qgis", "overseec_core")
PACKAGE_SUFFIXES = {".py", ".ui", ".json", ".txt", ".md", ".qml", ".svg", ".png"}
#: Compiled code: never in the zip.
BINARY_SUFFIXES = (".so", ".pyd", ".dylib", ".dll")
#: The first bytes of ELF, PE (Windows) and Mach-O (thin and fat) files.
BINARY_MAGIC = (
    b"\x7fELF",
    b"MZ",
    b"\xfe\xed\xfa\xce",
    b"\xfe\xed\xfa\xcf",
    b"\xce\xfa\xed\xfe",
    b"\xcf\xfa\xed\xfe",
    b"\xca\xfe\xba\xbe",
)
RESOURCE_DIRS = ("resources/icons", "resources/styles")
EXTRA_FILES = ("LICENSE", "README.md")
SKIP_DIRS = {"__pycache__", ".pytest_cache", ".mypy_cache"}
ZIP_DATE = (2020, 1, 1, 0, 0, 0)

ROOT_INIT = '''"""overseec QGIS plugin (assembled by scripts/build_plugin.py; edit the sources, not this)."""

import os
import sys

_HERE = os.path.dirname(os.path.abspath(__file__))
if _HERE not in sys.path:
    # overseec_core and overseec_qgis ship inside this folder as top-level packages.
    sys.path.insert(0, _HERE)


def classFactory(iface):  # noqa: N802 -- the name QGIS looks for
    from overseec_qgis import classFactory as factory

    return factory(iface)
'''


class BuildError(Exception):
    """The plugin cannot be built as it stands (metadata.txt wrong, a version mismatch, a binary
    file); main prints it and exits 2."""

    pass


def core_version(root: Path = REPO) -> str:
    """The ``__version__`` in ``overseec_core/__init__.py``, read as text (the build does not import
    the package); a BuildError when there is none."""
    text = (root / "overseec_core" / "__init__.py").read_text(encoding="utf-8")
    m = re.search(r'^__version__\s*=\s*["\']([^"\']+)["\']', text, re.M)
    if not m:
        raise BuildError("overseec_core/__init__.py defines no __version__")
    return m.group(1)


def check_metadata(path: Path, root: Path = REPO) -> configparser.ConfigParser:
    """The checks QGIS's plugin installer makes, plus version == overseec_core.__version__."""
    cp = configparser.ConfigParser(interpolation=None)
    cp.read(path, encoding="utf-8")
    if "general" not in cp:
        raise BuildError(f"{path}: no [general] section")
    g = cp["general"]
    for key in ("name", "description", "about", "version", "qgisMinimumVersion", "author", "email", "repository"):
        if not g.get(key, "").strip():
            raise BuildError(f"{path}: {key} is missing or empty")
    if not re.fullmatch(r"\d+\.\d+(\.\d+)?", g["qgisMinimumVersion"].strip()):
        raise BuildError(f"{path}: qgisMinimumVersion must look like 3.22")
    if g["version"].strip() != core_version(root):
        raise BuildError(f"{path}: version {g['version']} differs from overseec_core.__version__ {core_version(root)}")
    if g.get("hasProcessingProvider", "").strip().lower() not in ("yes", "true"):
        raise BuildError(f"{path}: hasProcessingProvider must be yes")
    icon = g.get("icon", "").strip()
    if icon and not (root / icon).is_file():
        raise BuildError(f"{path}: icon {icon} not found")
    return cp


def is_inplace_build(path: Path) -> bool:
    """``X.<tag>.so`` / ``X.<tag>.pyd`` beside ``X.c``: an extension ``make venv`` built in place.

    It serves the overseec environment (this checkout's venv); the plugin reaches it there.
    """
    stem = path.name.split(".", 1)[0]
    return path.suffix in (".so", ".pyd") and (path.parent / f"{stem}.c").is_file()


def check_pure_python(files: list[tuple[Path, str]], root: Path = REPO) -> None:
    """Refuse compiled code: a stray binary in the package tree, or a shipped file that is one."""
    for package in PACKAGES:
        for p in sorted((root / package).rglob("*")):
            if p.suffix in BINARY_SUFFIXES and not is_inplace_build(p):
                raise BuildError(
                    f"{p.relative_to(root)} is compiled code; the plugin is pure Python (native code "
                    "belongs in the overseec environment: an extension in setup.py, built by pip)"
                )
    for src, arc in files:
        with src.open("rb") as fh:
            head = fh.read(4)
        if arc.endswith(BINARY_SUFFIXES) or head.startswith(BINARY_MAGIC):
            raise BuildError(f"{arc} is an executable binary; the plugin zip must be pure Python")


def plugin_files(root: Path = REPO) -> list[tuple[Path, str]]:  # noqa: C901
    """(source, archive name inside overseec/) for every file the plugin ships."""
    files: list[tuple[Path, str]] = [(root / "metadata.txt", "metadata.txt")]
    for package in PACKAGES:
        top = root / package
        if not (top / "__init__.py").is_file():
            raise BuildError(f"{top} is not a package")
        for dirpath, dirnames, filenames in os.walk(top):
            dirnames[:] = sorted(d for d in dirnames if d not in SKIP_DIRS and not d.startswith("."))
            for name in sorted(filenames):
                p = Path(dirpath) / name
                if p.suffix in PACKAGE_SUFFIXES and not name.startswith("."):
                    files.append((p, p.relative_to(root).as_posix()))
    for d in RESOURCE_DIRS:
        for p in sorted((root / d).glob("*")):
            if p.is_file():
                files.append((p, p.relative_to(root).as_posix()))
    for name in EXTRA_FILES:
        if (root / name).is_file():
            files.append((root / name, name))
    return files


def build(out: Path, root: Path = REPO) -> Path:
    """Write the zip of the checkout at ``root`` atomically (temporary file beside ``out``, then rename)."""
    check_metadata(root / "metadata.txt", root)
    files = plugin_files(root)
    check_pure_python(files, root)
    out.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{out.name}.", suffix=".partial", dir=out.parent)
    os.close(fd)
    try:
        with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as zf:
            entries: list[tuple[Path | None, str]] = [(None, "__init__.py"), *files]
            dirs = sorted(
                {
                    parent.as_posix() + "/"
                    for _, arc in entries
                    for parent in Path(PLUGIN_NAME, arc).parents
                    if parent != Path(".")
                }
            )
            for d in dirs:
                info = zipfile.ZipInfo(d, ZIP_DATE)
                info.external_attr = (0o40755 << 16) | 0x10
                zf.writestr(info, "")
            for src, arc in sorted(entries, key=lambda e: e[1]):
                info = zipfile.ZipInfo(f"{PLUGIN_NAME}/{arc}", ZIP_DATE)
                info.compress_type = zipfile.ZIP_DEFLATED
                info.external_attr = 0o100644 << 16
                data = ROOT_INIT.encode() if src is None else src.read_bytes()
                zf.writestr(info, data)
        os.replace(tmp, out)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return out


def extract(zip_path: Path, dest: Path) -> Path:
    """Unpack the plugin into ``dest/overseec`` (replacing an older copy) for QGIS_PLUGINPATH."""
    target = dest / PLUGIN_NAME
    if target.exists():
        shutil.rmtree(target)
    dest.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(zip_path) as zf:
        zf.extractall(dest)
    return target


def main(argv: list[str] | None = None) -> int:
    """Command line: build the plugin zip (optionally unpack it for QGIS_PLUGINPATH) and print its
    size, file count and version; 2 on a build error."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument(
        "--out", type=Path, default=REPO / "dist" / "overseec.zip", help="zip to write (default: dist/overseec.zip)"
    )
    parser.add_argument("--dir", type=Path, help="also unpack the plugin to DIR/overseec (use DIR as QGIS_PLUGINPATH)")
    args = parser.parse_args(argv)
    try:
        out = build(args.out)
        with zipfile.ZipFile(out) as zf:
            count = sum(1 for n in zf.namelist() if not n.endswith("/"))
        print(f"built {out} ({out.stat().st_size // 1024} KiB, {count} files, version {core_version()}, pure Python)")
        if args.dir:
            print(f"unpacked to {extract(out, args.dir)}")
    except (BuildError, OSError) as exc:
        print(f"build_plugin: error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
