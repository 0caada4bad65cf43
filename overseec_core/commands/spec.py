"""The command specification the adapters derive from: every `overseec` command's options as data.

The CLI's argparse parser is the one place where flags, choices and defaults are declared (each
command module registers its own, shared options come from :mod:`overseec_core.commands`). This
module reads them back as frozen values, so that the QGIS worker's argv and the Processing
parameters are checked against the same facts (``tests/qgis/test_adapter_contract.py``), and
:func:`check_argv` refuses an argv that the CLI would refuse, without running anything.

Building the parser imports every command module (rasterio and numpy, never torch), so the QGIS
plugin itself does not import this module at run time; its tests do.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import io
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

#: Global options every command accepts (before or after its name); not part of a command's spec.
_GLOBAL_DESTS = frozenset({"quiet", "json_progress", "verbose", "cog", "max_pixels", "help"})


@dataclass(frozen=True)
class OptionSpec:
    """One option of a command as the CLI declares it."""

    flags: tuple[str, ...]
    dest: str
    choices: tuple[str, ...] | None
    default: Any
    #: Whether the option takes a value (``--mode exact``) or is a switch (``--no-refine``).
    takes_value: bool
    nargs: int | str | None
    required: bool
    #: The name of the value type (``"finite_number"``, ``"whole number >= 1"``, ``"Path"``; None: text).
    type: str | None = None
    #: What the help shows for the value (``"FILE"``, ``("X", "Y")``).
    metavar: str | tuple[str, ...] | None = None
    #: How argparse stores it (``"store"``, ``"append"``, ``"store_true"`` ...).
    action: str = "store"
    #: The option's help as ``overseec CMD --help`` shows it (``%(default)s`` filled in).
    help: str = ""

    def to_json(self) -> dict[str, Any]:
        """The option as a JSON object (the snapshot the QGIS plugin reads, :func:`snapshot`)."""
        default = self.default
        if not (default is None or isinstance(default, (str, int, float, bool, list))):
            default = str(default)  # a Path
        return {
            "flags": list(self.flags),
            "dest": self.dest,
            "choices": list(self.choices) if self.choices is not None else None,
            "default": default,
            "takes_value": self.takes_value,
            "nargs": self.nargs,
            "required": self.required,
            "type": self.type,
            "metavar": list(self.metavar) if isinstance(self.metavar, tuple) else self.metavar,
            "action": self.action,
            "help": self.help,
        }


@dataclass(frozen=True)
class CommandSpec:
    """A command (``plan``, or a sub-command such as ``export costmap``) and its options."""

    name: str
    options: tuple[OptionSpec, ...]
    positionals: tuple[str, ...]

    def option(self, flag: str) -> OptionSpec:
        """The option spelled ``flag``; KeyError naming the command when it has none."""
        for opt in self.options:
            if flag in opt.flags:
                return opt
        raise KeyError(f"`overseec {self.name}` has no option {flag}")

    @property
    def flags(self) -> frozenset[str]:
        """Every spelling of every option of the command."""
        return frozenset(f for opt in self.options for f in opt.flags)


#: argparse's own action classes by the names ``add_argument(action=...)`` takes.
_ACTION_NAMES = {
    argparse._StoreAction: "store",
    argparse._AppendAction: "append",
    argparse._StoreTrueAction: "store_true",
    argparse._StoreFalseAction: "store_false",
    argparse._StoreConstAction: "store_const",
    argparse._CountAction: "count",
}


def _help(action: argparse.Action) -> str:
    """The help text with argparse's ``%(default)s`` ... filled in, as ``--help`` prints it."""
    if not action.help or action.help is argparse.SUPPRESS:
        return ""
    return argparse.HelpFormatter("overseec")._expand_help(action)


def _option(action: argparse.Action) -> OptionSpec:
    choices = tuple(str(c) for c in action.choices) if action.choices is not None else None
    return OptionSpec(
        flags=tuple(action.option_strings),
        dest=action.dest,
        choices=choices,
        default=action.default,
        takes_value=action.nargs != 0,
        nargs=action.nargs,
        required=action.required,
        type=getattr(action.type, "__name__", None) if action.type is not None else None,
        metavar=action.metavar,
        action=_ACTION_NAMES.get(type(action), type(action).__name__),
        help=_help(action),
    )


def _walk(parser: argparse.ArgumentParser, prefix: str) -> dict[str, CommandSpec]:
    found: dict[str, CommandSpec] = {}
    for action in parser._actions:
        if not isinstance(action, argparse._SubParsersAction):
            continue
        for name, child in action.choices.items():
            full = f"{prefix} {name}".strip()
            options = tuple(
                _option(a)
                for a in child._actions
                if a.option_strings and a.dest not in _GLOBAL_DESTS and a.default is not argparse.SUPPRESS
            )
            positionals = tuple(
                a.dest for a in child._actions if not a.option_strings and not isinstance(a, argparse._SubParsersAction)
            )
            found[full] = CommandSpec(full, options, positionals)
            found.update(_walk(child, full))
    return found


@functools.cache
def command_specs() -> dict[str, CommandSpec]:
    """Every command's spec, by name (``"plan"``, ``"export costmap"``), read from the CLI parser."""
    from overseec_core.cli import build_parser  # the CLI imports the command modules; this reads them

    return _walk(build_parser(), "")


def command_spec(name: str) -> CommandSpec:
    """One command's spec; KeyError listing the commands for an unknown name."""
    specs = command_specs()
    if name not in specs:
        raise KeyError(f"no command {name!r}; commands: {', '.join(sorted(specs))}")
    return specs[name]


def check_argv(argv: Sequence[str]) -> argparse.Namespace:
    """Parse ``argv`` (what follows ``overseec``) as the CLI would, without running the command.

    Raises ValueError carrying argparse's own message for an argv the CLI would refuse (an unknown
    flag, a choice it does not offer, a missing value)."""
    from overseec_core.cli import build_parser

    err = io.StringIO()
    try:
        with contextlib.redirect_stderr(err):
            return build_parser().parse_args(list(argv))
    except SystemExit:
        raise ValueError(err.getvalue().strip().splitlines()[-1] if err.getvalue().strip() else "refused") from None


def snapshot(commands: Sequence[str] | None = None) -> dict[str, Any]:
    """The specs of ``commands`` (default: all) as one JSON document, by command name.

    The QGIS plugin generates its Processing parameters from this document
    (``overseec_qgis/processing/cli_spec.json``), because its process does not build the CLI's
    parser (that would import every command module and their dependencies into QGIS);
    ``tests/qgis/test_adapter_contract.py`` fails when the file is not this function's output."""
    specs = command_specs()
    names = sorted(specs) if commands is None else list(commands)
    return {
        name: {
            "positionals": list(specs[name].positionals),
            "options": [o.to_json() for o in specs[name].options],
        }
        for name in names
    }


def snapshot_text(commands: Sequence[str] | None = None) -> str:
    """:func:`snapshot` as the file holds it (indented, sorted, one trailing newline)."""
    import json

    return json.dumps(snapshot(commands), indent=1, sort_keys=True) + "\n"


if __name__ == "__main__":  # python -m overseec_core.commands.spec [COMMAND ...] > FILE.json
    import sys

    sys.stdout.write(snapshot_text(sys.argv[1:] or None))
