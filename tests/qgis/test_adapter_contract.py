"""The QGIS adapters say what the CLI says: every flag, choice and default they use is the CLI's.

The CLI's parser is the one declaration of each command's options
(``overseec_core.commands.spec``). Here every argv the plugin's worker client builds
(``overseec_qgis.jobs``, ``planclient``) is parsed by that parser and must mean what the
parameters say, and every Processing algorithm's enum options and defaults are compared with the
CLI's choices and defaults of the flag each parameter feeds. A flag renamed, a choice added or
dropped, or a default changed on one side only fails here.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest
from qgis.core import (
    QgsProcessingParameterBoolean,
    QgsProcessingParameterEnum,
    QgsProcessingParameterNumber,
)

from overseec_core import defaults
from overseec_core.commands.spec import check_argv, command_spec
from overseec_core.locate.refiners import DEFAULT_REFINER, refiner_names
from overseec_core.locate.segmenters import DEFAULT_SEGMENTER, segmenter_names
from overseec_qgis import jobs, planclient
from overseec_qgis.params import PLAN_MODE, LlmSettings, Params, Priors

pytestmark = pytest.mark.qgis

WORKER = Path("/opt/overseec/bin/overseec")
LLM = LlmSettings(endpoint="http://localhost:11434/v1", model="m", api_key="k")
PRIORS = (Priors(), Priors(path="/data/priors.json"), Priors(off=True))


def parse(argv: list[str]):
    """The CLI's reading of a worker argv (``cli_argv``: the worker, then what follows ``overseec``)."""
    assert argv[0] == str(WORKER)
    return check_argv(argv[1:])


def param_variants() -> list[Params]:
    """Default Params and each choice the dock and the options page offer, one change at a time."""
    base = Params()
    return [
        base,
        *(replace(base, device=d) for d in defaults.DEVICES),
        *(replace(base, plan_mode=m) for m in defaults.PLAN_MODES),
        *(replace(base, plan_neighbours=n) for n in defaults.PLAN_NEIGHBOURS),
        replace(base, refine=False),
        replace(base, refine=False, sam_model="sam-folder"),
        replace(base, clipseg_model="clipseg-folder", sam_model="sam-folder"),
        replace(base, tile_size=256, overlap=0),
        *(replace(base, segmenter=s) for s in segmenter_names()),
        *(replace(base, segmenter=s, model="model-folder", clipseg_model="clipseg-folder") for s in segmenter_names()),
        *(replace(base, refiner=r) for r in refiner_names()),
        *(replace(base, refiner=r, sam_model="refiner-folder") for r in refiner_names()),
        replace(base, refine=False, refiner="sam2"),
        replace(base, gsd="0.3"),
        replace(base, segmenter="semantic", gsd="auto"),
        replace(base, segmenter="boxes+sam", box_threshold=0.25, max_boxes=4, gsd="1.5"),
        replace(base, segmenter="clipseg", box_threshold=0.25, max_boxes=4),  # boxes+sam's only
    ]


def check_models(args, params: Params) -> None:
    """The segmenter and its model as the CLI reads them: CLIPSeg's model from --clipseg-model,
    another segmenter's from --model; nothing given means the segmenter's own default."""
    assert args.segmenter == params.segmenter
    if params.segmenter == "clipseg":
        assert (args.clipseg_model or "", args.model) == (params.clipseg_model, None)
    else:
        assert (args.model or "", args.clipseg_model) == (params.model, None)
    assert args.gsd == (None if not params.gsd else "auto" if params.gsd == "auto" else float(params.gsd))
    boxes = params.segmenter == "boxes+sam"
    assert args.box_threshold == (params.box_threshold if boxes and params.box_threshold else None)
    assert args.max_boxes == (params.max_boxes if boxes and params.max_boxes else None)
    if params.refine:  # the refiner and its checkpoint (None: the refiner's own)
        assert (args.refiner, args.sam_model or "") == (params.refiner, params.sam_model)


# ------------------------------------------------------------------------------------------------
# The worker client's argv
# ------------------------------------------------------------------------------------------------


def test_the_plugins_parameter_defaults_are_the_clis() -> None:
    p = Params()
    for command in ("segment", "run"):
        spec = command_spec(command)
        assert p.tile_size == spec.option("--tile-size").default
        assert p.device == spec.option("--device").default
        assert p.refine is not spec.option("--no-refine").default  # --no-refine: off by default
        assert p.segmenter == spec.option("--segmenter").default == DEFAULT_SEGMENTER
        assert spec.option("--segmenter").choices == segmenter_names()
        assert p.model == "" and spec.option("--model").default is None  # the segmenter's own
        assert p.refiner == spec.option("--refiner").default == DEFAULT_REFINER
        assert spec.option("--refiner").choices == refiner_names()
        assert p.sam_model == "" and spec.option("--sam-model").default is None  # the refiner's own
    assert command_spec("segment").option("--overlap").default is None  # None: an eighth of a tile
    assert p.overlap == defaults.overlap_for(command_spec("segment").option("--tile-size").default)
    # the one deliberate difference (params.Params): interactive planning starts fast
    assert p.plan_mode == PLAN_MODE == defaults.INTERACTIVE_PLAN_MODE
    assert PLAN_MODE in command_spec("run").option("--mode").choices
    assert command_spec("run").option("--mode").default == defaults.PLAN_MODE


def test_the_llm_reaches_the_worker_through_the_variables_the_core_reads() -> None:
    from overseec_core.interpret import llm

    assert (jobs.LLM_URL_ENV, jobs.LLM_MODEL_ENV, jobs.API_KEY_ENV) == (llm.ENV_URL, llm.ENV_MODEL, llm.ENV_KEY)


def test_info_and_interpret_argv_parse_as_the_cli_reads_them() -> None:
    for bands in (None, "3,2,1"):
        args = parse(jobs.info_command(WORKER, "-odd name.tif", bands)[0])
        assert (args.command, args.image, args.bands) == ("info", "-odd name.tif", bands)
    for llm in (LlmSettings(), LLM):
        for priors in PRIORS:
            argv, env = jobs.interpret_command(WORKER, "-avoid the water", llm, priors)
            args = parse(argv)
            assert args.terrain is False
            assert parse(jobs.interpret_command(WORKER, "p", llm, priors, terrain=True)[0]).terrain is True
            assert args.command == "interpret" and args.offline is llm.offline
            assert (str(args.priors) if args.priors else "", args.no_priors) == (priors.path, priors.off)
            assert args.json and args.json_progress
            assert args.prompt == "-avoid the water"
            assert (env.get(jobs.LLM_URL_ENV, ""), env.get(jobs.API_KEY_ENV, "")) == (llm.endpoint, llm.api_key)


def test_segment_argv_parses_with_every_parameter_choice(tmp_path) -> None:
    interp = jobs.edited_interpretation(None, "", jobs.parse_entities("road:linear, grass"), "")
    for params in param_variants():
        for bands in (None, "4,3,2"):
            args = parse(jobs.segment_command(WORKER, "image.tif", tmp_path, interp, params, bands)[0])
            assert args.command == "segment" and args.bands == bands
            assert (args.tile_size, args.overlap, args.device) == (params.tile_size, params.overlap, params.device)
            assert args.no_refine is not params.refine
            check_models(args, params)


def test_a_bad_resolution_fails_in_one_line_before_the_worker(tmp_path) -> None:
    """The dock's Resolution field goes through the core's --gsd parser when the argv is built, so a
    typo is the core's one-line InputError there (the dock shows it), not a worker's usage error."""

    interp = jobs.edited_interpretation(None, "", jobs.parse_entities("road:linear"), "")
    good = parse(jobs.segment_command(WORKER, "image.tif", tmp_path, interp, replace(Params(), gsd=" 0.5 "), None)[0])
    assert good.gsd == 0.5
    for bad in ("fine", "-1", "0", "nan"):
        with pytest.raises(jobs.InputError, match="gsd") as info:
            jobs.segment_command(WORKER, "image.tif", tmp_path, interp, replace(Params(), gsd=bad), None)
        assert "\n" not in str(info.value)


def test_run_argv_parses_with_every_parameter_choice(tmp_path) -> None:
    points = [(1.0, 2.0), (3.0, 4.0), (5.0, 6.0)]
    for params in param_variants():
        for llm in (LlmSettings(), LLM):
            for priors in PRIORS:
                argv, _env = jobs.run_command(
                    WORKER, "image.tif", tmp_path, "-prefer roads", params, llm, "3,2,1", points, "EPSG:32633",
                    reference="ref.geojson", evaluate=False, priors=priors,
                )  # fmt: skip
                args = parse(argv)
                assert (args.command, args.prompt, args.mode) == ("run", "-prefer roads", params.plan_mode)
                assert int(args.neighbours) == params.plan_neighbours
                assert (args.tile_size, args.device, args.no_refine) == (
                    params.tile_size,
                    params.device,
                    not params.refine,
                )
                check_models(args, params)
                assert args.start == [1.0, 2.0] and args.via == [[3.0, 4.0]] and args.goal == [5.0, 6.0]
                assert args.no_eval and args.offline is llm.offline and args.no_priors is priors.off
    labelled = parse(jobs.run_command(WORKER, "i.tif", tmp_path, "p", Params(), labels="gt.tif", classes="c.json")[0])
    assert (str(labelled.labels), str(labelled.classes), labelled.start) == ("gt.tif", "c.json", None)
    assert labelled.dem is None
    with_dem = parse(jobs.run_command(WORKER, "i.tif", tmp_path, "p", Params(), dem="/data/dem 1.tif")[0])
    assert str(with_dem.dem) == "/data/dem 1.tif"


def test_costmap_and_plan_server_argv_parse_as_the_cli_reads_them(tmp_path) -> None:
    sources = ({"masks_dir": tmp_path}, {"labels": "gt.tif", "classes": "c.json"})
    for src in sources:
        for overrides in ((), ("a.gpkg", "b.geojson")):
            out = tmp_path / "costmap-2.tif"
            args = parse(jobs.costmap_command(WORKER, out, "cost = 0.5", overrides=overrides, **src)[0])
            assert args.command == "costmap" and args.out == out and args.json
            assert [str(o) for o in args.override] == list(overrides)
            assert args.dem is None
            dem = parse(jobs.costmap_command(WORKER, out, "cost = slope / 90", dem="/data/dem.tif", **src)[0])
            assert str(dem.dem) == "/data/dem.tif" and dem.program == jobs.program_input_path(out)
    assert check_argv(planclient.worker_argv(WORKER)[1:]).command == "plan-server"


def test_corridor_and_pairs_argv_parse_as_the_cli_reads_them(tmp_path) -> None:
    from overseec_core import runfiles

    for crs, overrides in ((None, ()), ("EPSG:32633", ("overrides.gpkg",))):
        out = tmp_path / "corridor-2.tif"
        argv = jobs.corridor_command(WORKER, "cm.tif", (500010.5, 3999990.0), (1, 2), 12.5, out, crs, overrides)[0]
        args = parse(argv)
        assert args.command == "corridor" and args.costmap == Path("cm.tif") and args.json
        assert (args.start, args.goal, args.within) == ([500010.5, 3999990.0], [1.0, 2.0], 12.5)
        assert args.out == out and args.mask_out == out.with_name("corridor-2" + runfiles.CORRIDOR_MASK_SUFFIX)
        assert args.crs == crs and [str(o) for o in args.override] == list(overrides)
        for mode, steps in zip(defaults.PLAN_MODES, reversed(defaults.PLAN_NEIGHBOURS)):
            pairs, routes = tmp_path / "p.csv", tmp_path / "r.gpkg"
            argv = jobs.pairs_command(WORKER, "cm.tif", pairs, routes, mode, crs, overrides, int(steps))[0]
            args = parse(argv)
            assert args.command == "plan" and args.pairs == tmp_path / "p.csv" and args.out == tmp_path / "r.gpkg"
            assert args.mode == mode and args.crs == crs and args.json and args.start is None
            assert args.neighbours == steps
            assert [str(o) for o in args.override] == list(overrides)


# ------------------------------------------------------------------------------------------------
# The Processing algorithms' parameters
# ------------------------------------------------------------------------------------------------

#: Flags whose values the command checks after parsing (no argparse choices): what it accepts.
#: ``--device`` also takes ``cuda:N``, which is typed rather than picked from a menu.
CHECKED_AFTER_PARSING = {
    ("segment", "--device"): defaults.DEVICES,
    ("run", "--device"): defaults.DEVICES,
}
#: The algorithms this test must find (each names its own command and flags: COMMAND, FLAGS).
ALGORITHMS = {
    "interpret",
    "segment",
    "costmap",
    "plan",
    "costmatrix",
    "corridor",
    "run",
    "evaluate",
    "compare",
    "exportcostmap",
    "exportpath",
    "vectorize",
}
#: Defaults that differ from the CLI's on purpose: Plan path starts fast, as the dock and the
#: map tool do (params.Params); "exact" is one choice away.
DELIBERATE = {("plan", "MODE"): defaults.INTERACTIVE_PLAN_MODE, ("costmatrix", "MODE"): defaults.INTERACTIVE_PLAN_MODE}


@pytest.fixture(scope="module")
def provider(qgis_processing):
    """The plugin's Processing provider with its algorithms loaded (whichever files they live in)."""
    from overseec_qgis.processing.provider import OverseecProvider

    provider = OverseecProvider()
    provider.refreshAlgorithms()
    return provider


def _cli_choices(command: str, flag: str) -> tuple[str, ...]:
    choices = command_spec(command).option(flag).choices
    return choices if choices is not None else CHECKED_AFTER_PARSING[(command, flag)]


def _algorithms(provider) -> dict[str, Any]:
    """The algorithms that run a CLI command (the extract tool runs none), by id."""
    algs = {a.name(): a for a in provider.algorithms() if getattr(a, "COMMAND", "")}
    assert ALGORITHMS <= set(algs), "an algorithm this test knows is gone: update ALGORITHMS"
    return algs


def test_processing_enum_options_and_defaults_are_the_clis(provider) -> None:
    algs = _algorithms(provider)
    seen = set()
    for alg_id, alg in algs.items():
        for p in alg.parameterDefinitions():
            if not isinstance(p, QgsProcessingParameterEnum):
                continue
            key = (alg_id, p.name())
            assert p.name() in alg.FLAGS, f"overseec:{alg_id} {p.name()}: say which CLI flag it feeds (its FLAGS)"
            seen.add(key)
            command, flag = alg.COMMAND, alg.FLAGS[p.name()]
            options = tuple(p.options())
            # the same set; the menu's order is the algorithm's (saved models store indices)
            assert sorted(options) == sorted(_cli_choices(command, flag)), f"overseec:{alg_id} {p.name()} vs {flag}"
            chosen = options[int(p.defaultValue())]
            cli_default = command_spec(command).option(flag).default
            if key in DELIBERATE:
                assert chosen == DELIBERATE[key]
            elif cli_default is not None:  # a menu holds text; the CLI's value may be a number (steps)
                assert chosen == str(cli_default), (
                    f"overseec:{alg_id} {p.name()} defaults to {chosen}, the CLI to {cli_default}"
                )
    assert {k for k in DELIBERATE} <= seen, f"deliberate defaults of parameters no longer there: {DELIBERATE}"
    assert len(seen) >= 20  # the menus of segment, run, plan, evaluate, compare, export ...


def test_processing_number_and_switch_defaults_are_the_clis(provider) -> None:
    """Every number and switch parameter that feeds a flag (its algorithm's FLAGS) defaults to the
    CLI's default (a switch of the opposite sense, INVERTED: REFINE feeds --no-refine, to the
    opposite); a number whose flag has no default (None: the command decides) is optional."""
    checked = 0
    for alg_id, alg in _algorithms(provider).items():
        for p in alg.parameterDefinitions():
            if not isinstance(p, QgsProcessingParameterNumber | QgsProcessingParameterBoolean):
                continue
            if p.name() not in alg.FLAGS:
                continue
            flag = alg.FLAGS[p.name()]
            cli_default = command_spec(alg.COMMAND).option(flag).default
            if cli_default is None:
                continue
            expected = (not cli_default) if p.name() in alg.INVERTED else cli_default
            assert p.defaultValue() == expected, (
                f"overseec:{alg_id} {p.name()} defaults to {p.defaultValue()}, {flag}: {cli_default}"
            )
            checked += 1
    assert checked >= 12


def test_processing_backend_help_names_every_registered_backend() -> None:
    from overseec_core.locate.refiners import refiner_names
    from overseec_core.locate.segmenters import segmenter_names
    from overseec_qgis.processing import parameters

    assert all(f"{n}:" in parameters.SEGMENTER_HELP for n in segmenter_names())
    assert all(f"{n}:" in parameters.REFINER_HELP for n in refiner_names())


def test_the_processing_spec_file_is_the_clis_own() -> None:
    """``cli_spec.json`` (what Processing generates parameters from) is the spec read from the
    CLI's parser, for every command an algorithm runs; regenerate it with the command named."""
    import json

    from overseec_core.commands.spec import snapshot_text
    from overseec_qgis.processing import cli_options

    held = cli_options.SPEC_FILE.read_text(encoding="utf-8")
    commands = list(json.loads(held))
    fix = f"python -m overseec_core.commands.spec {' '.join(map(repr, commands))} > {cli_options.SPEC_FILE}"
    assert held == snapshot_text(commands), f"the CLI changed: regenerate the spec ({fix})"


def test_every_algorithm_runs_a_command_the_spec_file_holds(provider) -> None:
    import json

    from overseec_qgis.processing import cli_options

    held = set(json.loads(cli_options.SPEC_FILE.read_text(encoding="utf-8")))
    missing = {alg.COMMAND for alg in _algorithms(provider).values()} - held
    assert not missing, f"add {sorted(missing)} to {cli_options.SPEC_FILE.name} (see its module's docstring)"


def test_generated_parameters_take_the_clis_kind_default_and_bounds(provider) -> None:
    """The parameters Plan path generates from `overseec plan`'s declarations: a menu of the
    CLI's choices, a number with its default and least value, an optional number where the
    CLI has no default, a raster layer for a FILE taken as a layer."""
    from qgis.core import QgsProcessingParameterRasterLayer

    alg = _algorithms(provider)["plan"]
    steps = alg.parameterDefinition("NEIGHBOURS")
    assert isinstance(steps, QgsProcessingParameterEnum) and steps.options() == ["8", "16"]
    base = alg.parameterDefinition("BASE_COST_PER_M")
    assert isinstance(base, QgsProcessingParameterNumber)
    assert base.dataType() == QgsProcessingParameterNumber.Double
    assert (base.defaultValue(), base.minimum()) == (command_spec("plan").option("--base-cost-per-m").default, 0.0)
    assert base.help() == command_spec("plan").option("--base-cost-per-m").help
    lethal = alg.parameterDefinition("LETHAL_THRESHOLD")
    assert lethal.defaultValue() is None and lethal.flags() & lethal.FlagOptional
    assert isinstance(alg.parameterDefinition("DEM"), QgsProcessingParameterRasterLayer)
    assert alg.parameterDefinition("SLOPE_MODEL").options() == list(defaults.SLOPE_MODELS)
