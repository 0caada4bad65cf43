"""One module per `overseec` subcommand: ``register(subparsers)`` and ``run(args, progress)``.

The helpers below are shared by the command modules (they are not commands themselves).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any


def recorded_args(args: argparse.Namespace) -> dict[str, Any]:
    """The parsed arguments as the manifest records them (paths as text, no handler, no
    password from a URL's user:password part)."""
    from ..interpret.llm import redact

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
    from ..interpret.matching import parse_alias

    try:
        return parse_alias(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def add_priors_options(parser: argparse.ArgumentParser) -> None:
    """The shared --priors / --no-priors options of the commands that read prompts: what the
    hazards a prompt leaves unsaid cost (``interpret.priors``)."""
    from ..interpret.priors import BUILT_IN

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
