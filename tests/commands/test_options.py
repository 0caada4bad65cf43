"""The options several commands take are declared once (``commands/options.py``): a flag two
commands share has the same type, choices, default, arity and action in both, so that what one
command accepts the other accepts too (``costmap --line-width inf`` parsed while ``compare`` refused
it; ``run --start nan 0`` parsed while ``plan`` refused it)."""

from __future__ import annotations

from collections import defaultdict

import pytest

from overseec_core.commands.spec import OptionSpec, check_argv, command_specs

#: Flags that mean different things in different commands, each with why; every other flag two
#: commands share must be declared alike.
DIFFERENT_MEANINGS = {
    "--out": "a file for the commands that write one (costmap, plan ...), a folder for those that write a run",
    "--pairs": "plan: a file of start/goal pairs; run, eval and demo: how many random pairs to draw",
    "--prompt": "compare collects --prompt and --program in command-line order (two or more)",
    "--program": "compare collects --prompt and --program in command-line order (two or more)",
    "--to": "each export sub-command has its own formats",
    "--masks": "eval: a predicted mask raster to score; costmap, compare: a segment run folder",
}


def _declaration(opt: OptionSpec) -> tuple:
    """What must agree between two commands' spellings of a flag (not help, not required)."""
    return (opt.type, opt.choices, repr(opt.default), opt.nargs, opt.metavar, opt.action, opt.takes_value)


def _shared_flags() -> dict[str, dict[str, tuple]]:
    seen: dict[str, dict[str, tuple]] = defaultdict(dict)
    for name, spec in command_specs().items():
        for opt in spec.options:
            for flag in opt.flags:
                seen[flag][name] = _declaration(opt)
    return {flag: by_command for flag, by_command in seen.items() if len(by_command) > 1}


def test_a_flag_two_commands_share_is_declared_alike() -> None:
    drifted = {
        flag: by_command
        for flag, by_command in _shared_flags().items()
        if flag not in DIFFERENT_MEANINGS and len(set(by_command.values())) > 1
    }
    assert not drifted, drifted


def test_the_exceptions_are_still_shared_and_still_differ() -> None:
    """An entry of DIFFERENT_MEANINGS that no longer differs (or is no longer shared) goes."""
    shared = _shared_flags()
    stale = [flag for flag in DIFFERENT_MEANINGS if flag not in shared or len(set(shared[flag].values())) < 2]
    assert not stale, stale


def test_the_shared_options_reach_every_command_that_takes_them() -> None:
    """The builders are used where the issue says the options belong (a command dropping one
    would fall back to a hand-written copy, or lose the option)."""
    specs = command_specs()
    expected = {
        ("costmap", "compare"): (
            "--masks",
            "--labels",
            "--classes",
            "--vector",
            "--grid",
            "--line-width",
            "--block-size",
        ),
        ("plan", "compare", "run", "corridor"): ("--start", "--goal", "--crs"),
        ("plan", "compare", "run"): ("--via",),
        ("plan", "compare", "run", "eval"): ("--mode",),
        ("plan", "run"): ("--neighbours",),
        ("plan", "corridor"): ("--base-cost-per-m", "--lethal-threshold", "--lethal", "--override", "--band"),
        ("interpret", "costmap", "compare", "run"): ("--priors", "--no-priors"),
        ("interpret", "run"): ("--llm-url", "--llm-model", "--llm-timeout"),
        ("segment", "run"): ("--segmenter", "--model", "--gsd", "--refiner", "--sam-model", "--tile-size"),
        ("info", "segment", "run"): ("--bands", "--assume-crs"),
    }
    missing = [
        f"{command} {flag}"
        for commands, flags in expected.items()
        for command in commands
        for flag in flags
        if flag not in specs[command].flags
    ]
    assert not missing, missing


@pytest.mark.parametrize(
    "argv",
    [
        [
            "costmap",
            "--labels",
            "l.tif",
            "--classes",
            "c.json",
            "--program",
            "p",
            "--out",
            "o.tif",
            "--line-width",
            "inf",
        ],
        ["compare", "--labels", "l.tif", "--classes", "c.json", "--out", "d", "--line-width", "inf"],
        ["run", "img.tif", "--prompt", "p", "--out", "d", "--start", "nan", "0", "--goal", "1", "1"],
        ["plan", "c.tif", "--start", "nan", "0", "--goal", "1", "1"],
        [
            "costmap",
            "--labels",
            "l.tif",
            "--classes",
            "c.json",
            "--program",
            "p",
            "--out",
            "o.tif",
            "--block-size",
            "0",
        ],
        ["eval", "--labels", "l.tif", "--classes", "c.json", "--out", "d", "--mode", "quick"],
        ["run", "img.tif", "--prompt", "p", "--out", "d", "--tile-size", "0"],
        ["plan", "c.tif", "--start", "0", "0", "--goal", "1", "1", "--neighbours", "12"],
    ],
    ids=["costmap-line-width", "compare-line-width", "run-nan", "plan-nan", "block-size", "eval-mode", "tile", "steps"],
)
def test_every_command_refuses_what_its_siblings_refuse(argv: list[str]) -> None:
    with pytest.raises(ValueError, match=r"argument --"):
        check_argv(argv)


def test_steps_reach_the_namespace_as_the_planners_ints() -> None:
    """--neighbours is an int on the namespace (the planner's own values), not text to convert."""
    args = check_argv(["plan", "c.tif", "--start", "0", "0", "--goal", "1", "1", "--neighbours", "16"])
    assert args.neighbours == 16 and isinstance(args.neighbours, int)
    assert check_argv(["run", "i.tif", "--prompt", "p", "--out", "d"]).neighbours == 8


def test_the_backend_help_is_read_from_the_registries() -> None:
    """A backend added to a registry reaches every help text (the CLI's, Processing's, the
    dock's tooltip read ``describe_segmenters``/``describe_refiners``), none hand-written."""
    import io
    from contextlib import redirect_stdout

    from overseec_core.cli import build_parser
    from overseec_core.locate.refiners import REFINERS
    from overseec_core.locate.segmenters import SEGMENTERS

    out = io.StringIO()
    with redirect_stdout(out), pytest.raises(SystemExit):
        build_parser().parse_args(["segment", "--help"])
    text = "".join(out.getvalue().split())  # argparse wraps lines, at hyphens too
    for info in (*SEGMENTERS.values(), *REFINERS.values()):
        assert "".join(f"{info.name}: {info.summary}".split()) in text
