"""One module per `overseec` subcommand: ``register(subparsers)`` and ``run(args, progress)``.

The helpers below are shared by the command modules (they are not commands themselves); the
options several commands take, and their value types, are declared once in :mod:`.options`.
"""

from __future__ import annotations

import argparse
import json
import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any


def recorded_args(args: argparse.Namespace) -> dict[str, Any]:
    """The parsed arguments as the manifest records them (paths as text, no handler, no
    password from a URL's user:password part)."""
    from overseec_core.interpret.llm import redact

    def text(value: Any) -> Any:
        if isinstance(value, Path):
            return str(value)
        return redact(value) if isinstance(value, str) and "@" in value else value

    return {k: text(v) for k, v in vars(args).items() if k != "func"}


def print_json(args: argparse.Namespace, document: Any, **dumps: Any) -> None:
    """Print a command's ``--json`` document on stdout: indented for a reader, or, with the global
    ``--json-progress``, compact on ONE line, so that a driving process reading JSON lines gets
    the document as one line after the progress events."""
    if getattr(args, "json_progress", False):
        print(json.dumps(document, separators=(",", ":"), **dumps), flush=True)
    else:
        print(json.dumps(document, indent=2, **dumps))


def _make_folders(out: Path) -> list[Path]:
    """Create the missing folders above ``out``, top down; return those made here."""
    from overseec_core.errors import OutputError

    missing: list[Path] = []
    folder = out.parent if str(out.parent) else Path(".")
    while not folder.exists() and folder.parent != folder:
        if folder.is_symlink():  # a dangling link: mkdir cannot make its target
            raise OutputError(f"cannot write {out}: folder {folder} is a broken link")
        missing.append(folder)
        folder = folder.parent
    if folder.exists() and not folder.is_dir():
        raise OutputError(f"cannot write {out}: {folder} is a file, not a folder")
    made = []
    for new in reversed(missing):
        try:
            new.mkdir()
        except FileExistsError:  # made meanwhile (by another output, another process)
            continue
        except OSError as exc:
            raise OutputError(f"cannot write {out}: cannot create folder {new} ({exc.strerror or exc})") from None
        made.append(new)
    return made


@contextmanager
def output_folders(*files: str | os.PathLike | None) -> Iterator[None]:
    """Create the missing folders above each output file (as folder outputs create themselves),
    and remove the ones made here again, when still empty, if the command fails.

    Use it around the stage call, outside the stage's output transaction, so that the files are
    taken back first and the folders can go. A folder above an output that exists as a file is a
    one-line :class:`~overseec_core.errors.OutputError`; nothing is created for it.
    """
    created: list[Path] = []
    try:
        for file in files:
            if file is not None:
                created += _make_folders(Path(file))
        yield
    except BaseException:
        for folder in reversed(created):
            try:
                folder.rmdir()
            except OSError:  # not empty (or gone): leave it
                pass
        raise
