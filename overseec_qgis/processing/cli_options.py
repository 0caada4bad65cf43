"""Processing parameters generated from the CLI's own declaration of an option.

An algorithm names the CLI options it shows (a tuple of :class:`CliOption`, one line each); the
parameter's kind, choices, default, bounds and help come from the command's spec, and the argv is
built back from the same entries (:func:`cli_args`), so showing an existing `overseec` option in
Processing is one line in the algorithm, and a new one is its CLI declaration plus that line.

The spec is ``cli_spec.json`` beside this module: the output of ``python -m
overseec_core.commands.spec COMMAND ...``, read here because QGIS's process does not build the CLI's
parser (that imports every command module and their dependencies). ``tests/qgis/test_adapter_contract.py``
fails, naming the command that regenerates it, when the file and the CLI differ.
"""

from __future__ import annotations

import functools
import json
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from qgis.core import (
    QgsProcessingParameterBoolean,
    QgsProcessingParameterDefinition,
    QgsProcessingParameterEnum,
    QgsProcessingParameterFile,
    QgsProcessingParameterNumber,
    QgsProcessingParameterRasterLayer,
    QgsProcessingParameterString,
)

from .base import OverseecAlgorithm, enum_parameter

#: The commands' specs as the CLI declares them (generated; see the module's docstring).
SPEC_FILE = Path(__file__).with_name("cli_spec.json")

#: The CLI's number types (their names in the spec) -> (Processing's number kind, least value).
_NUMBER_TYPES: Mapping[str, tuple[int, float | None]] = {
    "finite_number": (QgsProcessingParameterNumber.Double, None),
    "non_negative_number": (QgsProcessingParameterNumber.Double, 0.0),
    "float": (QgsProcessingParameterNumber.Double, None),
    "int": (QgsProcessingParameterNumber.Integer, None),
}
_WHOLE_NUMBER = re.compile(r"whole number >= (-?\d+)")


@dataclass(frozen=True)
class CliOption:
    """A CLI option an algorithm shows as a parameter; only what the CLI cannot say is given here."""

    #: The option's flag (``--base-cost-per-m``); the parameter is named after it (BASE_COST_PER_M).
    flag: str
    #: The parameter's label; default: the CLI's help up to its first aside.
    label: str = ""
    #: The parameter's help; default: the CLI's help.
    help: str = ""
    #: A FILE option taken as a raster layer (any raster QGIS reads) rather than a file name.
    raster: bool = False
    #: Another parameter this one goes with: passed only when that one is given (SLOPE_MODEL: DEM).
    needs: str = ""
    advanced: bool = True

    @property
    def name(self) -> str:
        """The parameter's name: the flag in capitals, dashes as underscores."""
        return self.flag.lstrip("-").upper().replace("-", "_")


@functools.cache
def _specs() -> dict[str, Any]:
    return json.loads(SPEC_FILE.read_text(encoding="utf-8"))


def cli_option(command: str, flag: str) -> dict[str, Any]:
    """The spec of ``command``'s option ``flag`` (a KeyError naming both when the CLI has none)."""
    for option in _specs().get(command, {}).get("options", ()):
        if flag in option["flags"]:
            return option
    raise KeyError(f"`overseec {command}` has no option {flag} in {SPEC_FILE.name}")


def _label(spec: Mapping[str, Any]) -> str:
    """The CLI's help up to its first aside (`` (``, ``;``, ``:``), capitalised."""
    text = re.split(r" \(|;|:", spec["help"], maxsplit=1)[0].strip()
    return text[:1].upper() + text[1:]


def parameter(command: str, option: CliOption) -> QgsProcessingParameterDefinition:
    """The Processing parameter of ``option``: an enum for choices (the CLI's default, else its
    first choice), a switch, a number with the
    CLI's default and least value, a raster layer or file, else text; optional unless required."""
    spec = cli_option(command, option.flag)
    name, label, default = option.name, option.label or _label(spec), spec["default"]
    optional = not spec["required"]
    if spec["choices"]:  # no default: the command takes its first choice (--slope-model)
        return enum_parameter(name, label, spec["choices"], spec["choices"][0] if default is None else str(default))
    if spec["action"] == "store_true":
        return QgsProcessingParameterBoolean(name, label, bool(default))
    kind = spec["type"]
    whole = _WHOLE_NUMBER.fullmatch(kind or "")
    if kind in _NUMBER_TYPES or whole:
        number, least = (QgsProcessingParameterNumber.Integer, float(whole.group(1))) if whole else _NUMBER_TYPES[kind]
        p = QgsProcessingParameterNumber(name, label, number, default, optional=optional and default is None)
        if least is not None:
            p.setMinimum(least)
        return p
    if kind == "Path":
        if option.raster:
            return QgsProcessingParameterRasterLayer(name, label, optional=optional)
        return QgsProcessingParameterFile(name, label, optional=optional)
    if kind is None and spec["takes_value"]:
        return QgsProcessingParameterString(name, label, default, optional=optional)
    raise TypeError(f"{command} {option.flag}: no Processing parameter for a {kind or spec['action']} option")


def add_cli_options(alg: OverseecAlgorithm, options: Sequence[CliOption]) -> None:
    """Add the parameters of ``options`` to ``alg`` (help: the entry's, else the CLI's)."""
    for option in options:
        help = option.help or cli_option(alg.COMMAND, option.flag)["help"]
        alg.param(parameter(alg.COMMAND, option), help, advanced=option.advanced)


def cli_flags(options: Sequence[CliOption]) -> dict[str, str]:
    """Parameter -> flag of ``options``, for an algorithm's ``FLAGS``."""
    return {option.name: option.flag for option in options}


def _given(parameters: Mapping[str, Any], name: str) -> bool:
    return parameters.get(name) not in (None, "")


def cli_args(alg: OverseecAlgorithm, parameters, context, options: Sequence[CliOption]) -> list[str]:
    """The argv ``options`` add: an enum's choice, a switch when on, a number, file or text when
    given (an option whose ``needs`` is not given adds nothing)."""
    args: list[str] = []
    for option in options:
        if option.needs and not _given(parameters, option.needs):
            continue
        definition = alg.parameterDefinition(option.name)
        name = option.name
        if isinstance(definition, QgsProcessingParameterEnum):
            args += alg.arg(name, alg.enum_value(parameters, name, context))
        elif isinstance(definition, QgsProcessingParameterBoolean):
            args += alg.arg(name, alg.parameterAsBool(parameters, name, context))
        elif isinstance(definition, QgsProcessingParameterNumber):
            if _given(parameters, name) or definition.defaultValue() is not None:
                if definition.dataType() == QgsProcessingParameterNumber.Integer:
                    args += alg.arg(name, alg.parameterAsInt(parameters, name, context))
                else:
                    args += alg.arg(name, repr(alg.parameterAsDouble(parameters, name, context)))
        elif isinstance(definition, QgsProcessingParameterRasterLayer):
            args += alg.arg(name, alg.optional_raster_file(parameters, name, context))
        elif isinstance(definition, QgsProcessingParameterFile):
            args += alg.arg(name, alg.optional_file(parameters, name, context))
        else:
            args += alg.arg(name, alg.optional_str(parameters, name, context), joined=True)
    return args
