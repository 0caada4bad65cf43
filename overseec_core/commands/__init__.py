"""One module per `overseec` subcommand: ``register(subparsers)`` and ``run(args, progress)``.

The helpers below are shared by the command modules (they are not commands themselves).
"""

from __future__ import annotations

import argparse
import json
import math
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


def finite_number(text: str) -> float:
    """argparse type: a finite number."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, not {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, not {text!r}")
    return value


def non_negative_number(text: str) -> float:
    """argparse type: a finite number >= 0."""
    value = finite_number(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"expected a number >= 0, not {text!r}")
    return value


def whole_number(minimum: int):
    """argparse type factory: a whole number >= ``minimum``."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number, not {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"expected a number >= {minimum}, not {value}")
        return value

    parse.__name__ = f"whole number >= {minimum}"
    return parse


def entity_alias(text: str) -> tuple[str, str]:
    """argparse type: ENTITY=LAYER, a prompt entity name and the layer it stands for."""
    from overseec_core.interpret.matching import parse_alias

    try:
        return parse_alias(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def add_priors_options(parser: argparse.ArgumentParser) -> None:
    """The shared --priors / --no-priors options of the commands that read prompts: what the
    hazards a prompt leaves unsaid cost (``interpret.priors``)."""
    from overseec_core.interpret.priors import BUILT_IN

    g = parser.add_mutually_exclusive_group()
    g.add_argument(
        "--priors",
        type=Path,
        metavar="FILE",
        help='JSON object of entity -> prior level in (0.5, 1], "obstacle" (= 1) or "lethal", replacing the built-in '
        f"priors of unsaid hazards ({BUILT_IN.describe()})",
    )
    g.add_argument(
        "--no-priors",
        action="store_true",
        help="no priors: what the prompt does not mention is neutral ground",
    )


def add_strict_option(parser: argparse.ArgumentParser) -> None:
    """The shared --strict option of the commands that read prompts into a costmap: a clause of
    the prompt that was not understood is an error (exit 2) instead of a warning, for batch runs."""
    parser.add_argument(
        "--strict",
        action="store_true",
        help="fail (exit 2) when any clause of the prompt was not understood, instead of warning and "
        "building the costmap without it",
    )


def add_alias_option(parser: argparse.ArgumentParser) -> None:
    """The shared --alias option of the commands that match prompt entities to layers."""
    parser.add_argument(
        "--alias",
        action="append",
        default=[],
        type=entity_alias,
        metavar="ENTITY=LAYER",
        help="the layer a prompt entity stands for when the names differ and the "
        "built-in matching misses it, e.g. lake=water (repeatable)",
    )


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
