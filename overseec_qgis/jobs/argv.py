"""The worker command lines: each stage as an ``overseec --json-progress <command> ...`` argv.

Never a shell string; the LLM's endpoint, model and key go in the environment the CLI reads
(``OVERSEEC_LLM_URL``, ``OVERSEEC_LLM_MODEL``, ``OVERSEEC_LLM_API_KEY``), never the command line
(visible to every user in ``ps``; a URL may hold credentials). ``tests/qgis/test_adapter_contract.py``
checks every argv built here against the CLI's own parser.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

from overseec_core import defaults, runfiles
from overseec_core.locate.refiners import DEFAULT_REFINER
from overseec_core.locate.segmenters import DEFAULT_SEGMENTER

from ..params import BUILT_IN_PRIORS, OFFLINE, LlmSettings, Params, Priors
from ..worker import cli_argv, worker_env

#: Environment variables the worker's interpreter reads the LLM settings from
#: (``overseec_core.interpret.llm``: ENV_KEY, ENV_URL, ENV_MODEL).
API_KEY_ENV = "OVERSEEC_LLM_API_KEY"


LLM_URL_ENV = "OVERSEEC_LLM_URL"


LLM_MODEL_ENV = "OVERSEEC_LLM_MODEL"


def _env(llm: LlmSettings | None = None) -> dict[str, str]:
    return worker_env(llm_cli(llm)[1] if llm is not None else None)


def llm_cli(llm: LlmSettings) -> tuple[list[str], dict[str, str]]:
    """CLI options and extra worker environment for the interpreter's LLM.

    Offline is passed explicitly (``--offline``), so an ``OVERSEEC_LLM_URL`` in QGIS's
    environment does not silently switch the offline choice to an LLM. An LLM's endpoint, model
    and key go in the environment the CLI reads, never on the command line.
    """
    if llm.offline:
        return ["--offline"], {}
    env = {LLM_URL_ENV: llm.endpoint}
    if llm.model:
        env[LLM_MODEL_ENV] = llm.model
    if llm.api_key:
        env[API_KEY_ENV] = llm.api_key
    return [], env


def info_command(worker: Path, path: str, bands: str | None = None) -> tuple[list[str], dict[str, str]]:
    """argv and env for ``overseec info --json`` (how the core will read the image)."""
    args = ["--json"] + (["--bands", bands] if bands else []) + ["--", path]
    return cli_argv(worker, "info", args), _env()


def interpret_command(
    worker: Path, prompt: str, llm: LlmSettings = OFFLINE, priors: Priors = BUILT_IN_PRIORS, terrain: bool = False
) -> tuple[list[str], dict[str, str]]:
    """argv and env for ``overseec interpret --json`` of ``prompt`` (after ``--``: a prompt that
    starts with a dash stays the prompt), with ``priors`` for the hazards it leaves unsaid and
    ``--terrain`` when the costmap will have a DEM (the LLM is offered slope and roughness)."""
    options, extra = llm_cli(llm)
    flags = ["--terrain"] if terrain else []
    return cli_argv(worker, "interpret", ["--json", *options, *priors.cli(), *flags, "--", prompt]), worker_env(extra)


def _model_options(p: Params) -> list[str]:
    """The segmenter, its model, the refiner and its model, as `segment` and `run` take them:
    ``--segmenter`` and ``--refiner`` when not the default; CLIPSeg's model as ``--clipseg-model``,
    another segmenter's as ``--model``; ``--gsd`` when set (InputError when it is not a
    resolution), and boxes+sam's ``--box-threshold`` / ``--max-boxes`` when set and that segmenter
    runs."""
    args = [] if p.segmenter == DEFAULT_SEGMENTER else ["--segmenter", p.segmenter]
    if p.segmenter == "clipseg" and p.clipseg_model:
        args += ["--clipseg-model", p.clipseg_model]
    elif p.segmenter != "clipseg" and p.model:
        args += ["--model", p.model]
    if p.gsd.strip():  # checked here, so a typo fails in one line before any worker starts
        from overseec_core.locate.gsd import parse_gsd  # numpy only: no torch in QGIS

        parse_gsd(p.gsd.strip())
        args += ["--gsd", p.gsd.strip()]
    if p.segmenter == "boxes+sam":  # 0 leaves the detector's defaults
        args += ["--box-threshold", repr(float(p.box_threshold))] if p.box_threshold > 0 else []
        args += ["--max-boxes", str(int(p.max_boxes))] if p.max_boxes > 0 else []
    if not p.refine:  # boxes+sam still turns its boxes into masks with SAM (the sam refiner's checkpoint)
        boxes_sam = p.segmenter == "boxes+sam" and p.refiner == "sam" and p.sam_model
        return args + ["--no-refine"] + (["--sam-model", p.sam_model] if boxes_sam else [])
    if p.refiner != DEFAULT_REFINER:
        args += ["--refiner", p.refiner]
    if p.sam_model:
        args += ["--sam-model", p.sam_model]
    return args


def _segment_options(p: Params) -> list[str]:
    """`overseec segment` options for the model settings (CLI names and defaults)."""
    args = ["--tile-size", str(p.tile_size), "--overlap", str(p.overlap), "--device", p.device or defaults.DEVICE]
    return args + _model_options(p)


def with_thresholds(interp, params: Params):
    """Entities without their own threshold get the form's linear/areal threshold."""
    ents = tuple(
        e
        if e.threshold is not None
        else replace(e, threshold=params.tau_linear if e.geometry == "linear" else params.tau_areal)
        for e in interp.entities
    )
    return replace(interp, entities=ents)


def write_interpretation(interp, path: str | os.PathLike) -> Path:
    """Save an (edited) interpretation as JSON for the worker, atomically."""
    from overseec_core.io.manifest import write_json_atomic

    return write_json_atomic(path, interp.to_json())


def segment_command(
    worker: Path, image: str, run_dir: Path, interp, params: Params, bands: str | None = None
) -> tuple[list[str], dict[str, str]]:
    """argv and env for ``overseec segment`` of the (edited) entities into ``run_dir``.

    The entities (with thresholds filled in) go to the worker as ``entities.json`` in the run
    directory, the format ``overseec interpret --json`` prints.
    """
    entities_file = write_interpretation(with_thresholds(interp, params), Path(run_dir) / runfiles.ENTITIES)
    args = [image, "--entities-json", str(entities_file), "--out", str(run_dir)]
    args += _segment_options(params)
    if bands:
        args += ["--bands", bands]
    return cli_argv(worker, "segment", args), _env()


def run_command(
    worker: Path,
    image: str,
    run_dir: Path,
    prompt: str,
    params: Params,
    llm: LlmSettings = OFFLINE,
    bands: str | None = None,
    points: Sequence[tuple[float, float]] = (),
    crs: str | None = None,
    labels: str | None = None,
    classes: str | None = None,
    reference: str | None = None,
    evaluate: bool = True,
    priors: Priors = BUILT_IN_PRIORS,
    dem: str | os.PathLike | None = None,
) -> tuple[list[str], dict[str, str]]:
    """argv and env for ``overseec run`` (the whole pipeline) into ``run_dir``.

    ``points`` are start, vias..., goal in ``crs``; with a class raster (``labels`` +
    ``classes``) no model runs. The run command takes tile size, device and models; overlap and
    thresholds are the CLI's defaults there. ``priors``: what the hazards the prompt leaves
    unsaid cost. ``dem``: an elevation raster (``--dem``), so the program may read ``slope`` and
    ``roughness``.
    """
    args = [image, f"--prompt={prompt}", "--out", str(run_dir), *priors.cli()]
    if dem:
        args += ["--dem", str(dem)]
    if labels:
        args += ["--labels", labels, "--classes", str(classes)]
    else:
        args += ["--tile-size", str(params.tile_size), "--device", params.device or defaults.DEVICE]
        args += _model_options(params)
    args += llm_cli(llm)[0]
    if bands:
        args += ["--bands", bands]
    if len(points) >= 2:
        flags = ["--start"] + ["--via"] * (len(points) - 2) + ["--goal"]
        for flag, (x, y) in zip(flags, points):
            args += [flag, repr(float(x)), repr(float(y))]
        args += ["--mode", params.plan_mode, "--neighbours", str(params.plan_neighbours)]
        args += ["--crs", crs] if crs else []
    if reference:
        args += ["--reference", reference]
    if not evaluate:
        args += ["--no-eval"]
    return cli_argv(worker, "run", args), _env(llm)


def program_input_path(out: str | os.PathLike) -> Path:
    """Where the dock saves the program it hands to `overseec costmap --program`: beside the
    costmap, named after it (``costmap-2.tif`` -> ``costmap-2.input.cost``)."""
    out = Path(out)
    return out.with_name(f"{out.stem}.input.cost")


def costmap_command(
    worker: Path,
    out: str | os.PathLike,
    program: str,
    masks_dir: str | os.PathLike | None = None,
    labels: str | os.PathLike | None = None,
    classes: str | os.PathLike | None = None,
    overrides: Sequence[str | os.PathLike] = (),
    dem: str | os.PathLike | None = None,
) -> tuple[list[str], dict[str, str]]:
    """argv and env for ``overseec costmap --json``: a cost program over entity layers (a run's
    masks and/or a class raster) -> costmap; ``overrides`` are override polygon files applied
    after the program (``--override``); ``dem`` an elevation raster (``--dem``) the program's
    ``slope`` and ``roughness`` come from. The program text is saved (atomically) as
    :func:`program_input_path` first; the CLI writes the program it used beside the costmap."""
    from overseec_core.io.atomic import write_text_atomic

    program_file = write_text_atomic(program_input_path(out), program)
    args: list[str] = []
    if masks_dir:
        args += ["--masks", str(masks_dir)]
    if labels:
        args += ["--labels", str(labels), "--classes", str(classes)]
    if dem:
        args += ["--dem", str(dem)]
    args += ["--program", str(program_file), "--out", str(out), "--json"]
    for o in overrides:
        args += ["--override", str(o)]
    return cli_argv(worker, "costmap", args), _env()


def corridor_command(
    worker: Path,
    costmap: str | os.PathLike,
    start: tuple[float, float],
    goal: tuple[float, float],
    within_pct: float,
    out: str | os.PathLike,
    crs: str | None = None,
    overrides: Sequence[str | os.PathLike] = (),
) -> tuple[list[str], dict[str, str]]:
    """argv and env for ``overseec corridor --json``: the least-cost corridor between ``start``
    and ``goal`` (in ``crs``, else the costmap's) within ``within_pct`` % of the optimum, into
    ``out`` (the ratio raster) and its mask beside it (``--mask-out``: the CLI's own default name,
    ``OUT`` + :data:`runfiles.CORRIDOR_MASK_SUFFIX`, spelled out so the caller knows the file);
    ``overrides`` are applied in memory (``--override``)."""
    out = Path(out)
    mask = out.with_name(out.stem + runfiles.CORRIDOR_MASK_SUFFIX)
    args = [str(costmap), "--start", repr(float(start[0])), repr(float(start[1]))]
    args += ["--goal", repr(float(goal[0])), repr(float(goal[1])), "--within", repr(float(within_pct))]
    args += ["--out", str(out), "--mask-out", str(mask), "--json"]
    args += ["--crs", crs] if crs else []
    for o in overrides:
        args += ["--override", str(o)]
    return cli_argv(worker, "corridor", args), _env()


def pairs_command(
    worker: Path,
    costmap: str | os.PathLike,
    pairs: str | os.PathLike,
    out: str | os.PathLike,
    mode: str = defaults.PLAN_MODE,
    crs: str | None = None,
    overrides: Sequence[str | os.PathLike] = (),
    neighbours: int = defaults.PLAN_NEIGHBOURS[0],
) -> tuple[list[str], dict[str, str]]:
    """argv and env for ``overseec plan --pairs --json``: one route per start/goal pair of
    ``pairs`` (a CSV ``start_x,start_y,goal_x,goal_y[,id]`` in ``crs``, else the costmap's; or a
    layer of lines) into the GeoPackage ``out`` (layer :data:`runfiles.PAIRS_LAYER`), planned in
    ``mode`` with ``neighbours`` steps, with ``overrides`` applied in memory."""
    args = [str(costmap), "--pairs", str(pairs), "--out", str(out), "--mode", mode, "--json"]
    args += ["--neighbours", str(neighbours)]
    args += ["--crs", crs] if crs else []
    for o in overrides:
        args += ["--override", str(o)]
    return cli_argv(worker, "plan", args), _env()
