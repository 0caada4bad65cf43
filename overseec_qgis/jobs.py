"""The one mapping from the plugin's forms to the core: worker command lines and light helpers.

The dock and the Processing algorithms both go through these functions, so the same parameters
mean the same thing everywhere, and QGIS computes nothing itself:

* every stage (reading check, interpret, segment, costmap, run) is an ``overseec
  --json-progress <command> ...`` argv for the worker process (the CLI of the overseec
  environment), never a shell string; results come back as the CLI's ``--json`` document. QGIS's
  own Python (no rasterio, no planner kernel on Windows and macOS) only checks and edits text:
  the cost program (``costlang``), entity tables, interpretations;
* the LLM endpoint, model and API key reach the worker through the environment the CLI reads
  (``OVERSEEC_LLM_URL``, ``OVERSEEC_LLM_MODEL``, ``OVERSEEC_LLM_API_KEY``), never its command
  line (visible to every user in ``ps``; a URL may hold credentials).

Core modules are imported inside functions: loading the plugin stays cheap and never pulls in
anything heavy (and never torch). :func:`layer_names` and :func:`fit_to_layers` use the core's
layer reader when QGIS's Python has rasterio, and fall back to the entities table otherwise
(the worker's costmap then checks the names).
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from overseec_core import defaults, runfiles
from overseec_core.errors import CostProgramError, InputError, OverseecError  # noqa: F401 -- re-exported
from overseec_core.locate.refiners import DEFAULT_REFINER
from overseec_core.locate.segmenters import DEFAULT_SEGMENTER

from . import envcheck
from .params import BUILT_IN_PRIORS, OFFLINE, LlmSettings, Params, Priors
from .worker import cli_argv, configured_worker, find_worker, run_worker, worker_env

#: Environment variables the worker's interpreter reads the LLM settings from
#: (``overseec_core.interpret.llm``: ENV_KEY, ENV_URL, ENV_MODEL).
API_KEY_ENV = "OVERSEEC_LLM_API_KEY"
LLM_URL_ENV = "OVERSEEC_LLM_URL"
LLM_MODEL_ENV = "OVERSEEC_LLM_MODEL"


def core_version() -> str:
    """The core's version: the dock re-runs its environment check once per new version."""
    from overseec_core import __version__

    return __version__


# --------------------------------------------------------------------------------------------
# Input
# --------------------------------------------------------------------------------------------


def layer_file(layer) -> str:
    """The file behind a GDAL raster layer ('' for non-file sources such as WMS)."""
    if layer.providerType() != "gdal":
        return ""
    path = layer.source().split("|")[0]
    return path if Path(path).is_file() else ""


def info_command(worker: Path, path: str, bands: str | None = None) -> tuple[list[str], dict[str, str]]:
    """argv and env for ``overseec info --json`` (how the core will read the image)."""
    args = ["--json"] + (["--bands", bands] if bands else []) + ["--", path]
    return cli_argv(worker, "info", args), _env()


def no_worker_message() -> str:
    """Why there is no worker, in one line (the environment check's first problem)."""
    report = envcheck.check_worker(None)
    return report.problems[0] if report.problems else "no overseec environment"


def run_json(argv: Sequence[str], env: Mapping[str, str], timeout_s: float) -> dict[str, Any]:
    """Run a short worker command here (not in a task) and return its ``--json`` document;
    InputError with the CLI's one-line reason when it fails or takes over ``timeout_s``."""
    printed: list[str] = []
    deadline = time.monotonic() + timeout_s
    res = run_worker(
        argv,
        on_event=lambda e: printed.append(e.text) if e.kind == "text" else None,
        is_cancelled=lambda: time.monotonic() > deadline,
        env=env,
    )
    if not res.ok:
        raise InputError(f"`overseec {argv[2]}` took over {timeout_s:g} s" if res.cancelled else res.summary())
    doc = result_document(printed)
    if not doc:
        raise InputError(f"`overseec {argv[2]} --json` printed no document ({argv[0]})")
    return doc


def result_document(lines: Sequence[str]) -> dict[str, Any]:
    """The ``--json`` document a CLI command prints after its progress events: one line (as the
    CLI prints it under --json-progress), or indented, ``{`` on a line of its own (older CLIs);
    {} when there is none."""
    for i, line in enumerate(lines):
        text = line.strip()
        if not text.startswith("{"):
            continue
        try:
            doc = json.loads("\n".join(lines[i:]) if text == "{" else text)
        except ValueError:
            return {}
        return doc if isinstance(doc, dict) else {}
    return {}


def describe_info(info: Mapping[str, Any]) -> str:
    """The core's info as a few lines for the dock (the same facts `overseec info` prints)."""
    px, py = info["pixel_size_m"]
    return "\n".join(
        [
            f"{info['width']} x {info['height']} px, {info['count']} band(s) {', '.join(info['dtypes'])}",
            f"CRS {info['crs']}{' (assumed)' if info.get('crs_assumed') else ''}, pixel {px:.3g} x {py:.3g} m",
            f"read as: {info['read_plan']['description']}",
            f"nodata: {'NaN' if info.get('nodata_is_nan') else info.get('nodata')}, "
            f"alpha band: {info.get('alpha_band') or 'none'}",
        ]
    )


# --------------------------------------------------------------------------------------------
# Interpret and the cost program
# --------------------------------------------------------------------------------------------


def check_program(text: str, entity_names: Sequence[str]):
    """Check a cost program against the entity names with the core's checker (runs in QGIS's own
    Python: costlang needs no rasterio)."""
    from overseec_core.costlang import check_program as check

    return check(text, entity_names)


def edited_interpretation(base, prompt: str, rows: Sequence[Mapping[str, Any]], program: str):
    """The interpretation with the dock's edits: entity table rows and program text."""
    from overseec_core.schema import Entity, Interpretation

    entities = tuple(
        Entity(
            name=r["name"], geometry=r["geometry"], prompts=tuple(r.get("prompts") or ()), threshold=r.get("threshold")
        )
        for r in rows
    )
    if base is None:
        return Interpretation(prompt=prompt, entities=entities, preferences=(), program=program, source="edited")
    return replace(base, prompt=prompt or base.prompt, entities=entities, program=program)


def entities_from_file(path: str | os.PathLike):
    """An Interpretation holding the entities of a JSON file (a list of entities, or any document
    with "entities", e.g. `overseec interpret --json`), read by the core's entity parser (the
    one `overseec segment --entities-json` uses)."""
    from overseec_core.interpret.entity_input import load_entities_json
    from overseec_core.schema import Interpretation

    return Interpretation(
        prompt="", entities=tuple(load_entities_json(Path(path))), preferences=(), source=f"file:{Path(path).name}"
    )


def write_interpretation(interp, path: str | os.PathLike) -> Path:
    """Save an (edited) interpretation as JSON for the worker, atomically."""
    from overseec_core.io.manifest import write_json_atomic

    return write_json_atomic(path, interp.to_json())


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


def interpret_command(
    worker: Path, prompt: str, llm: LlmSettings = OFFLINE, priors: Priors = BUILT_IN_PRIORS, terrain: bool = False
) -> tuple[list[str], dict[str, str]]:
    """argv and env for ``overseec interpret --json`` of ``prompt`` (after ``--``: a prompt that
    starts with a dash stays the prompt), with ``priors`` for the hazards it leaves unsaid and
    ``--terrain`` when the costmap will have a DEM (the LLM is offered slope and roughness)."""
    options, extra = llm_cli(llm)
    flags = ["--terrain"] if terrain else []
    return cli_argv(worker, "interpret", ["--json", *options, *priors.cli(), *flags, "--", prompt]), worker_env(extra)


def interpret(
    prompt: str,
    llm: LlmSettings = OFFLINE,
    worker: Path | None = None,
    timeout_s: float = 300.0,
    priors: Priors = BUILT_IN_PRIORS,
):
    """Prompt -> Interpretation, by ``overseec interpret --json`` in the worker (the settings'
    worker unless given: :func:`.worker.configured_worker`), waiting for it here: for scripts
    and tests; the dock runs the same command in a task."""
    if worker is None:
        worker = configured_worker()
    if worker is None:
        raise InputError(no_worker_message())
    return interpretation_from_json(run_json(*interpret_command(worker, prompt, llm, priors), timeout_s=timeout_s))


def interpretation_from_json(doc: Mapping[str, Any]):
    """The Interpretation of an ``overseec interpret --json`` document (the schema's fields)."""
    from overseec_core.schema import Cue, Entity, Interpretation, Preference

    if not isinstance(doc.get("entities"), list):
        raise InputError("the interpreter returned no entities")
    return Interpretation(
        prompt=str(doc.get("prompt", "")),
        entities=tuple(Entity.from_json(e) for e in doc["entities"]),
        preferences=tuple(Preference.from_json(p) for p in doc.get("preferences") or ()),
        hierarchy=tuple((str(c), str(p)) for c, p in doc.get("hierarchy") or ()),
        cues=tuple(Cue(**c) for c in doc.get("cues") or ()),
        program=str(doc.get("program", "")),
        unparsed=tuple(doc.get("unparsed") or ()),
        source=str(doc.get("source", "offline")),
        notes=tuple(doc.get("notes") or ()),
    )


# --------------------------------------------------------------------------------------------
# Worker commands
# --------------------------------------------------------------------------------------------


def find_worker_for(settings) -> Path | None:
    """The worker (`overseec` command) the settings lead to: their command path, else their venv,
    else one found from the plugin's folder; None when there is none."""
    return find_worker(settings.worker_path, settings.venv, Path(__file__).parent)


def _env(llm: LlmSettings | None = None) -> dict[str, str]:
    return worker_env(llm_cli(llm)[1] if llm is not None else None)


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


#: Share of a run's time per stage, for one overall progress bar (segmentation dominates).
RUN_WEIGHTS = {"interpret": 1.0, "segment": 70.0, "refine": 20.0, "costmap": 3.0, "plan": 2.0, "evaluate": 1.0}


def stage_weights(command: str, params: Params, segments: bool = True) -> dict[str, float]:
    """The stages a worker command reports and their weights: refine only when it runs, no
    segmentation at all when a class raster stands in for the masks."""
    stages = {"segment": ("segment", "refine"), "run": tuple(RUN_WEIGHTS)}.get(command, (command,))
    skip = ({"refine"} if not params.refine else set()) | ({"segment", "refine"} if not segments else set())
    return {s: RUN_WEIGHTS.get(s, 1.0) for s in stages if s not in skip}


def with_thresholds(interp, params: Params):
    """Entities without their own threshold get the form's linear/areal threshold."""
    ents = tuple(
        e
        if e.threshold is not None
        else replace(e, threshold=params.tau_linear if e.geometry == "linear" else params.tau_areal)
        for e in interp.entities
    )
    return replace(interp, entities=ents)


def parse_entities(text: str) -> list[dict]:
    """'road:linear, grass, baseball field:areal' -> entity rows, through the core's one entity
    parser (``overseec_core.interpret.entity_input``: without a geometry, the lexicon's, as the CLI does)."""
    from overseec_core.interpret.entity_input import parse_entity_list

    return [{"name": e.name, "geometry": e.geometry, "threshold": None, "prompts": []} for e in parse_entity_list(text)]


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


def run_command(  # noqa: C901
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


# --------------------------------------------------------------------------------------------
# Entity layers and the costmap
# --------------------------------------------------------------------------------------------


def layer_names(
    masks_dir: str | os.PathLike | None = None,
    labels: str | os.PathLike | None = None,
    classes: str | os.PathLike | None = None,
) -> tuple[str, ...]:
    """Entity names the costmap stage will see for these layer sources (the core decides).

    Raises ImportError where QGIS's Python cannot read rasters with the core (no rasterio):
    callers then check against the entities table and leave the layers to the worker."""
    from overseec_core.synthesize.layers import open_layers
    from overseec_core.synthesize.options import CostmapOptions

    options = CostmapOptions(
        out=Path(runfiles.COSTMAP), masks=_path(masks_dir), labels=_path(labels), classes=_path(classes)
    )
    source = open_layers(options)
    try:
        return tuple(source.names)
    finally:
        source.close()


def fit_to_layers(interp, names: Sequence[str], aliases_text: str = "", priors: Priors = BUILT_IN_PRIORS):
    """The interpretation's program fitted to the layers' names (matching, aliases, and the
    ``priors`` it was interpreted with for layers no entity stands for), as `overseec costmap
    --prompt` fits it; InputError for bad aliases, a bad priors file or nothing matched."""
    from overseec_core.interpret.matching import parse_aliases
    from overseec_core.synthesize.fit import fit_program

    try:
        aliases = parse_aliases(aliases_text)
    except ValueError as exc:
        raise InputError(str(exc)) from None
    return fit_program(interp, list(names), dict(aliases), priors.table())


def _path(p: str | os.PathLike | None) -> Path | None:
    return Path(p) if p else None


def next_costmap_path(folder: str | os.PathLike) -> Path:
    """``costmap.tif``, then ``costmap-2.tif``, ...: each re-prompt keeps its own costmap, program
    and layer, so earlier layers (and their provenance) stay as they were."""
    folder = Path(folder)
    first = Path(runfiles.COSTMAP)
    if not (folder / first).exists():
        return folder / first
    n = 2
    while (folder / f"{first.stem}-{n}{first.suffix}").exists():
        n += 1
    return folder / f"{first.stem}-{n}{first.suffix}"


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


@dataclass(frozen=True)
class CostmapSummary:
    """What the dock shows of an ``overseec costmap --json`` document."""

    costmap: Path
    lethal: Path
    program_file: Path
    program: str
    entities: tuple[str, ...]
    notes: tuple[str, ...]
    warnings: tuple[str, ...]
    mean_cost: float | None

    @staticmethod
    def from_json(doc: Mapping[str, Any]) -> CostmapSummary:
        try:
            return CostmapSummary(
                costmap=Path(doc["costmap"]),
                lethal=Path(doc["lethal"]),
                program_file=Path(doc["program_file"]),
                program=str(doc["program"]),
                entities=tuple(doc.get("entities") or ()),
                notes=tuple(doc.get("notes") or ()),
                warnings=tuple(doc.get("warnings") or ()),
                mean_cost=doc.get("mean_cost"),
            )
        except (KeyError, TypeError) as exc:
            raise InputError(f"`overseec costmap --json` printed no usable document (missing {exc})") from None


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


def replace_params(params: Params, **changes) -> Params:
    """A copy of ``params`` with ``changes`` applied (Params is frozen)."""
    return replace(params, **changes)


def crs_text(crs) -> str:
    """A QgsCoordinateReferenceSystem as text the core parses (EPSG:XXXX, else WKT)."""
    return crs.authid() if crs.authid().upper().startswith("EPSG:") else crs.toWkt()


# --------------------------------------------------------------------------------------------
# Environment
# --------------------------------------------------------------------------------------------


def check_worker_env(worker: Path | None) -> envcheck.EnvReport:
    """Check the worker's environment (packages, versions, model weights) in a subprocess; with no
    worker, a report saying it was not found and how to set one up."""
    return envcheck.check_worker(worker)


def environment_report(settings, progress=None) -> envcheck.EnvReport:
    """The worker check (packages, and the weights of the models the settings name): every
    stage runs there. QGIS's Python only borrows the environment's packages where it can (for
    matching program names to the entity layers as you type); lacking them is no problem."""
    worker = find_worker_for(settings)
    envcheck.ensure_core_importable(settings.venv or None, worker)
    p = settings.params
    return envcheck.check_worker(
        worker,
        clipseg_model=p.clipseg_model,
        sam_model=p.sam_model,
        refine=p.refine,
        refiner=p.refiner,
        segmenter=p.segmenter,
        model=p.model,
    )
