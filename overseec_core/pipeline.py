"""The one orchestration of overseec's stages, shared by the CLI, the QGIS task and Processing.

Each stage function takes plain arguments (paths, option dataclasses, a Progress), writes its
outputs into a run directory with a manifest entry, and returns a frozen result. Stages read and
write files on the image's grid, so any one can be re-run alone: re-prompting re-uses the masks.

    image ─ info ─ interpret ─ segment (+ refine) ─ costmap ─ plan ─ evaluate
"""

from __future__ import annotations

import functools
import importlib.util
import json
import os
import time as _time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from overseec_core import defaults, runfiles
from overseec_core.costlang import check_program
from overseec_core.costlang.scale import NEUTRAL
from overseec_core.errors import InputError, ModelError, OutputError, OverseecError
from overseec_core.evaluate import EvaluateOptions, EvaluateResult, check_options, evaluate_paths
from overseec_core.interpret import interpret
from overseec_core.interpret.llm import LLMConfig, resolve_config
from overseec_core.interpret.priors import BUILT_IN as BUILT_IN_PRIORS
from overseec_core.interpret.priors import PriorTable, resolve_priors
from overseec_core.interpret.templates import template_ids
from overseec_core.io.atomic import write_text_atomic
from overseec_core.io.inputs import check_image_data
from overseec_core.io.manifest import RunDir, write_json_atomic
from overseec_core.io.read import RasterInfo, read_grid, read_info
from overseec_core.io.transaction import output_transaction
from overseec_core.io.write import check_output_path
from overseec_core.limits import check_pixels
from overseec_core.plan import load_costmap
from overseec_core.plan.export import (
    find_prompt,
    path_geojson,
    path_properties,
    waypoint_records,
    write_cumulative,
    write_geojson,
    write_native_gpkg,
    write_pixels,
)
from overseec_core.plan.grid import PROMPT_TAGS
from overseec_core.plan.overrides import apply_to_planning_grid, path_override_properties
from overseec_core.plan.stage import PlanOptions, PlanRunResult, plan_keeping_rules, points_to_pixels
from overseec_core.progress import Progress
from overseec_core.schema import Entity, Interpretation
from overseec_core.synthesize.engine import TAG_PROGRAM, check_outputs, compose_costmap, output_paths
from overseec_core.synthesize.fit import fit_program, layer_preferences, resolve_program
from overseec_core.synthesize.layers import load_classes, open_layers, parse_vector_spec
from overseec_core.synthesize.options import CostmapOptions, CostmapResult
from overseec_core.synthesize.overrides import TAG_OVERRIDES, load_overrides, record_overrides, tag_value

if TYPE_CHECKING:  # annotations only: the model stages are imported where a model runs (run_segment)
    from overseec_core.locate.refine import RefineOptions
    from overseec_core.locate.segment import LocateResult, SegmentOptions

T = TypeVar("T")


def run_info(
    image: str | os.PathLike, bands: Sequence[int] | str | None = None, assume_crs: str | None = None
) -> RasterInfo:
    """Describe an image: georeferencing, layout and how the pipeline will read it."""
    return read_info(image, bands=bands, assume_crs=assume_crs)


#: The optional extras (``pip install "overseec[EXTRA]"``) and the modules each one brings.
EXTRAS: dict[str, tuple[str, ...]] = {
    "models": ("torch", "transformers", "safetensors", "huggingface_hub"),
    "dask": ("dask", "distributed"),
}


def extra_for(module: str | None) -> str | None:
    """The extra that installs ``module`` (or a submodule of it), or None."""
    root = (module or "").split(".")[0]
    return next((extra for extra, modules in EXTRAS.items() if root in modules), None)


def missing_extra(extra: str, what: str, module: str, hint: str = "") -> OverseecError:
    """The one-line error for a stage whose extra is not installed."""
    kind = ModelError if extra == "models" else InputError
    return kind(f'{what} needs {module}, which is not installed: pip install "overseec[{extra}]"{hint}')


def require_extra(extra: str, what: str, hint: str = "") -> None:
    """Refuse, before anything is read or written, a stage whose optional extra is missing:
    one line naming the pip extra, not an ImportError half-way."""
    for module in EXTRAS[extra]:
        try:
            found = importlib.util.find_spec(module) is not None
        except (ImportError, ValueError):  # a broken install, or an import hook refusing it
            found = False
        if not found:
            raise missing_extra(extra, what, module, hint)


def transactional(stage: Callable[..., T]) -> Callable[..., T]:
    """Run a stage's writes as one transaction (:mod:`overseec_core.io.transaction`): cancelled or
    failed, it leaves its folder as it was, not with a new lethal.tif beside an old costmap."""

    @functools.wraps(stage)
    def run(*args: Any, **kwargs: Any) -> T:
        with output_transaction():
            return stage(*args, **kwargs)

    return run


# --- stage: interpret ---
def run_interpret(
    prompt: str,
    *,
    offline: bool | None = None,
    llm: LLMConfig | None = None,
    llm_url: str | None = None,
    llm_model: str | None = None,
    api_key: str | None = None,
    llm_key_env: str | None = None,
    llm_timeout: float | None = None,
    llm_retries: int | None = None,
    llm_fallback_offline: bool | None = None,
    out: str | os.PathLike | None = None,
    run_dir: str | os.PathLike | None = None,
    progress: Progress | None = None,
    command_args: dict | None = None,
    priors: PriorTable | None = None,
) -> Interpretation:
    """Interpret: prompt -> entities, preferences, hierarchy, cues and a cost program.

    ``priors``: what hazards the prompt leaves unsaid cost (None = the built-in table); the
    table used is recorded in the run's manifest.

    The LLM runs when ``llm`` or ``llm_url`` is given, or ``OVERSEEC_LLM_URL`` is set and
    ``offline`` is not True; otherwise the offline interpreter. ``out`` gets the JSON document
    (atomically); ``run_dir`` gets it as ``interpretation.json`` plus a manifest entry
    (``interpretation``, the LLM settings without the key, templates, timing).
    """
    if offline and (llm is not None or llm_url):
        raise InputError("--offline and an LLM (--llm-url) were both given; choose one")
    config = llm
    if config is None and not offline:
        config = resolve_config(
            url=llm_url,
            model=llm_model,
            key_env=llm_key_env,
            api_key=api_key,
            timeout_s=llm_timeout,
            retries=llm_retries,
            fallback_offline=llm_fallback_offline,
        )
    if out is not None:
        check_output_path(out, [])  # before the (possibly slow) LLM calls
    run = RunDir(run_dir, command="interpret", args=command_args) if run_dir is not None else None
    table = BUILT_IN_PRIORS if priors is None else priors
    if run is None:
        result = interpret(prompt, offline=config is None, llm=config, progress=progress, priors=table)
    else:
        run.update_parameters(
            interpret={
                "interpreter": "llm" if config else "offline",
                "llm": config.describe() if config else None,
                "templates": list(template_ids()) if config else [],
                "priors": table.to_json(),
            }
        )
        with run.stage("interpret"):
            result = interpret(prompt, offline=config is None, llm=config, progress=progress, priors=table)
        run.set("interpretation", result.to_json())
        write_json_atomic(run.file(runfiles.INTERPRETATION), result.to_json())
        run.save()
    if out is not None:
        write_json_atomic(out, result.to_json())
    return result


# --- stage: segment ---
@transactional
def run_segment(
    image: str | os.PathLike,
    entities: Sequence[Entity],
    out_dir: str | os.PathLike,
    options: SegmentOptions | None = None,
    refine: RefineOptions | None = None,
    progress: Progress | None = None,
    command_args: dict | None = None,
) -> LocateResult:
    """Locate: CLIPSeg probabilities and masks, then (unless ``refine`` is None) SAM refinement,
    into ``out_dir`` with its manifest (image hash, entities, models with revisions, device, tile
    settings, per-stage timings). torch/transformers are imported only when this runs."""
    require_extra("models", "segmentation (CLIPSeg and SAM)")
    if (options is not None and options.dask_scheduler) or (refine is not None and refine.dask_scheduler):
        require_extra("dask", "--dask-scheduler")
    # segment/refine/models: only when segmenting (re-prompting never loads them, nor torch)
    from overseec_core.locate.entities import validate_entities
    from overseec_core.locate.refine import check_refine_options, refine_image
    from overseec_core.locate.segment import LocateResult, SegmentOptions, segment_image

    options = options or SegmentOptions()
    ents = validate_entities(entities)
    if refine is not None:
        check_refine_options(refine)  # a missing SAM fails now, not after the CLIPSeg pass
    run = RunDir(out_dir, command="segment", args=command_args)
    run.record_input("image", image)
    params = {"segment": {k: v for k, v in asdict(options).items() if k != "dask_scheduler"}}
    if refine is not None:
        params["refine"] = {k: v for k, v in asdict(refine).items() if k != "dask_scheduler"}
    run.update_parameters(**params)
    run.set("entities", [e.to_json() for e in ents])
    with run.stage("segment"):
        seg = segment_image(image, ents, run.path, options, progress)
    run.set("segment", seg.to_json())
    run.set("models", {"clipseg": seg.model.to_json()})
    ref = None
    if refine is not None:
        from overseec_core.locate.models import release_models

        release_models("clipseg")  # one model in memory at a time
        with run.stage("refine"):
            ref = refine_image(image, seg.probs_path, ents, run.path, refine, progress)
        run.set("refine", ref.to_json())
        run.set("models", {"clipseg": seg.model.to_json(), "sam": ref.model.to_json()})
    run.save()
    return LocateResult(segment=seg, refine=ref, manifest=run.manifest_path)


# --- stage: costmap ---
@transactional
def run_costmap(
    options: CostmapOptions,
    progress: Progress | None = None,
    command_args: dict | None = None,
    *,
    prompt: str | None = None,
) -> CostmapResult:
    """Program + entity layers -> costmap.tif, its lethal sidecar and the program text, beside
    each other in ``options.out``'s folder (whose manifest records inputs, program and timings).
    Only reads mask/label/vector files: re-prompting never re-runs segmentation.

    The prompt behind the program (``options.prompt``, or ``prompt`` when the program text was
    made from one elsewhere, as `run` does) goes into the costmap's tags (``OVERSEEC_PROMPT``)
    and the manifest, so that every path planned on it carries the prompt (GPX/KML names)."""
    t0 = _time.perf_counter()
    prompt = options.prompt if prompt is None else prompt
    out, lethal_out, program_out = output_paths(options.out)
    source = open_layers(options)
    try:
        check_pixels(source.grid.width, source.grid.height, source.inputs[0] if source.inputs else out, "entity layer")
        overrides = load_overrides(options.overrides, source.grid) if options.overrides else None
        extra_inputs = [p for p in (options.program, *options.overrides) if p is not None]
        check_outputs([out, lethal_out], list(source.inputs) + extra_inputs)
        same_program = options.program is not None and Path(options.program).resolve() == program_out.resolve()
        if not same_program:
            check_outputs([program_out], list(source.inputs) + extra_inputs)
        resolved = resolve_program(options, source.names)
        program = check_program(resolved.text, source.names)
        t_program = _time.perf_counter() - t0
        warnings = source.warnings + resolved.warnings + program.warnings
        if progress is not None:
            for note in resolved.notes:
                progress.message(note)
            for warning in warnings:
                progress.message(f"warning: {warning}")
        run = RunDir(out.parent, command="costmap", args=command_args)
        for i, path in enumerate(source.inputs):
            run.record_input(f"costmap_layer_{i + 1}_{Path(path).name}", path)
        if options.program is not None:
            run.record_input("cost_program", options.program)
        run.update_parameters(
            costmap={
                "block_size": options.block_size,
                "line_width_m": options.line_width_m,
                "prompt": prompt,
                "priors": options.prior_table().to_json() if options.prompt is not None else None,
            }
        )
        tags = {
            TAG_PROGRAM: program_out.name,
            "OVERSEEC_PROGRAM_SOURCE": resolved.source,
            "OVERSEEC_PROGRAM_ENTITIES": json.dumps(list(program.entities)),
        }
        if prompt:
            tags[PROMPT_TAGS[0]] = prompt
        if overrides is not None:
            tags[TAG_OVERRIDES] = tag_value(overrides)
        with run.stage("costmap"):
            stats = compose_costmap(
                program,
                source,
                out,
                lethal_out,
                block_size=options.block_size,
                tags=tags,
                progress=progress,
                overrides=overrides,
            )
            if not same_program:
                write_text_atomic(program_out, program.text)
        run.set(
            "cost_program",
            {
                "file": program_out.name,
                "text": program.text,
                "source": resolved.source,
                "entities": list(program.entities),
                "notes": list(resolved.notes),
                "warnings": list(warnings),
                "entity_layers": [m.to_json() for m in resolved.mapping],
                "aliases": dict(options.aliases),
                "interpretation": resolved.interpretation,
            },
        )
        run.set(
            "costmap",
            {
                "file": out.name,
                "lethal_file": lethal_out.name,
                "halo_px": list(stats.halo),
                "valid_pixels": stats.valid_pixels,
                "lethal_pixels": stats.lethal_pixels,
                "keep_out_pixels": stats.keep_out_pixels,
                "mean_cost": stats.mean_cost,
            },
        )
        override_summary = record_overrides(run, overrides, stats.overrides, "costmap", progress)
        run.save()
    finally:
        source.close()
    timings = {
        "program_s": round(t_program, 4),
        "compose_s": round(stats.seconds, 4),
        "total_s": round(_time.perf_counter() - t0, 4),
    }
    return CostmapResult(
        costmap=out,
        lethal=lethal_out,
        program_file=program_out,
        manifest=run.manifest_path,
        program=program.text,
        program_source=resolved.source,
        entities=program.entities,
        layers=source.names,
        notes=resolved.notes,
        warnings=warnings,
        halo=stats.halo,
        blocks=stats.blocks,
        valid_pixels=stats.valid_pixels,
        lethal_pixels=stats.lethal_pixels,
        mean_cost=stats.mean_cost,
        timings=timings,
        keep_out_pixels=stats.keep_out_pixels,
        overrides=override_summary,
    )


# --- stage: plan ---
@transactional
def run_plan(options: PlanOptions, progress: Progress | None = None, command_args: dict | None = None) -> PlanRunResult:
    """Costmap + map points (any CRS) -> a path: RFC 7946 GeoJSON (WGS 84) with cost, length,
    mode, bound and prompt; on request the path in the costmap's CRS (GeoPackage), its pixel
    indices and the cost-distance raster from the start. The output folder's manifest records
    the costmap (hashed), parameters, the result and timings."""
    o = options
    requested = {"geojson": o.out, "native": o.native_out, "pixels": o.pixels_out, "cumulative": o.cumulative_out}
    targets = {k: Path(v) for k, v in requested.items() if v is not None}
    if len({p.resolve() for p in targets.values()}) != len(targets):
        raise InputError("two outputs have the same path; give each output its own file")
    for path in targets.values():
        check_output_path(path, o.inputs())
    t0 = _time.perf_counter()
    grid = load_costmap(o.costmap, lethal_path=o.lethal, lethal_threshold=o.lethal_threshold, band=o.band)
    # the lethal sidecar found beside the costmap is an input too: never write over it
    inputs = o.inputs() + ([Path(grid.lethal_source)] if grid.lethal_source else [])
    for path in targets.values():
        check_output_path(path, inputs)
    overrides = override_counts = None
    if o.overrides:  # in memory: the costmap file stays as it is
        # a costmap without georeferencing has no grid: load_overrides refuses None (InputError)
        overrides = load_overrides(o.overrides, grid.grid)  # type: ignore[arg-type]
        grid, override_counts = apply_to_planning_grid(grid, overrides)
    pixels, labels = points_to_pixels(grid, o.points, o.crs)
    t1 = _time.perf_counter()
    result, planner = plan_keeping_rules(
        grid, pixels, mode=o.mode, base_cost_per_m=o.base_cost_per_m, labels=labels, progress=progress
    )
    t2 = _time.perf_counter()
    from overseec_core.plan.smooth import smooth_if_asked  # --smooth: shortcuts on the strict grid

    smoothed = smooth_if_asked(result, grid, o.base_cost_per_m, o.smooth, progress)
    line = None if smoothed is None else smoothed.vertices  # the geometry written
    prompt = find_prompt(grid)
    waypoints = waypoint_records(grid, result, o.points, o.crs)
    props = path_properties(result, grid, o.base_cost_per_m, waypoints, prompt, smoothed)
    plan_overrides = None
    if overrides is not None and override_counts is not None:  # both set above, or neither
        plan_overrides = overrides.summary(override_counts, "plan")
    props.update(path_override_properties(grid.tags, plan_overrides))
    write_geojson(targets["geojson"], path_geojson(result, grid, props, line), inputs)
    if "native" in targets:
        write_native_gpkg(targets["native"], result, grid, props, inputs, pixels=line)
    if "pixels" in targets:
        write_pixels(targets["pixels"], result, grid, o.base_cost_per_m, inputs)
    if "cumulative" in targets:
        write_cumulative(targets["cumulative"], planner, pixels[0], label=labels[0], inputs=inputs, progress=progress)
    timings = {
        "load_s": round(t1 - t0, 4),
        "plan_s": round(t2 - t1, 4),
        "write_s": round(_time.perf_counter() - t2, 4),
        "total_s": round(_time.perf_counter() - t0, 4),
    }
    timings.update({} if smoothed is None else {"smooth_s": round(smoothed.seconds, 4)})  # in write_s
    run = RunDir(targets["geojson"].parent, command="plan", args=command_args)
    run.record_input(f"plan_costmap_{Path(o.costmap).name}", o.costmap)
    if grid.lethal_source:
        run.record_input(f"plan_lethal_{Path(grid.lethal_source).name}", grid.lethal_source)
    record_overrides(run, overrides, override_counts, "plan", progress)
    run.update_parameters(
        plan={
            "mode": o.mode,
            "base_cost_per_m": o.base_cost_per_m,
            "lethal_threshold": o.lethal_threshold,
            "crs": o.crs,
            "points": [list(p) for p in o.points],
            "smooth": o.smooth,
        }
    )
    run.set(
        "plan",
        {
            **result.to_json(),
            "outputs": {k: p.name for k, p in targets.items()},
            "waypoints": waypoints,
            "prompt": prompt,
            "timings": timings,
            **({} if smoothed is None else {"smoothing": smoothed.to_json()}),
        },
    )
    run.save()
    return PlanRunResult(
        result=result,
        outputs=targets,
        waypoints=waypoints,
        prompt=prompt,
        timings=timings,
        smoothed=smoothed,
        properties=props,
    )


# --- stage: evaluate ---
@transactional
def run_evaluate(
    options: EvaluateOptions, progress: Progress | None = None, command_args: dict | None = None
) -> EvaluateResult:
    """Evaluate paths and masks into ``options.out_dir``: RRPI over sampled start-goal pairs with
    its KDE centre of mass and fit, Hausdorff distance to reference paths, IoU per class, plots,
    metrics.json and report.md; inputs (hashed), parameters and timing go to the manifest."""
    check_options(options)
    run = RunDir(options.out_dir, command="eval", args=command_args)
    for role, path in options.inputs().items():
        run.record_input(f"eval_{role}", path)
    params = {
        k: v
        for k, v in asdict(options).items()
        if not isinstance(v, Path) and k not in ("masks", "labels", "classes", "costmap", "reference", "paths", "image")
    }
    run.update_parameters(evaluate=params)
    with run.stage("evaluate"):
        result = evaluate_paths(options, progress)
    run.set("evaluation", {k: Path(v).name for k, v in result.files.items()})
    run.save()
    return result


# --- full pipeline ---


@dataclass(frozen=True)
class PipelineOptions:
    """One whole job: image + prompt -> interpretation, masks, costmap, path, evaluation.

    Masks come from segmentation (``segment``, refined unless ``refine`` is None) or, when
    ``labels`` + ``classes`` are given, from a class raster the user already has (and then no
    model is needed). ``points`` are map coordinates (start, vias..., goal) in ``points_crs``
    (None = the image's CRS); with fewer than two points nothing is planned. Evaluation runs when
    there is something to measure against: labels (RRPI) or ``reference`` paths (Hausdorff). A
    run takes its masks either from segmentation or from the labels, so it has no ground truth
    to score segmented masks against: their IoU is ``overseec eval --masks RUN/masks.tif --labels
    GT.tif --classes classes.json --out DIR`` (:func:`run_evaluate` with ``masks``).
    """

    image: Path
    prompt: str
    out_dir: Path
    points: tuple[tuple[float, float], ...] = ()
    points_crs: str | None = None
    bands: str | None = None
    assume_crs: str | None = None
    offline: bool | None = None
    llm_url: str | None = None
    llm_model: str | None = None
    llm_key_env: str | None = None
    llm_fallback_offline: bool | None = None
    labels: Path | None = None
    classes: Path | None = None
    vectors: tuple[str, ...] = ()
    #: Prompt entity -> layer name pairs the matching rules do not find ("lake" -> "water").
    aliases: tuple[tuple[str, str], ...] = ()
    #: A prior table file replacing the built-in one (``interpret.priors``); ``no_priors``
    #: switches priors off.
    priors: Path | None = None
    no_priors: bool = False
    segment: Any = None  # overseec_core.locate.segment.SegmentOptions; None = defaults
    refine: Any = "default"  # overseec_core.locate.refine.RefineOptions, "default", or None to skip
    plan_mode: str = defaults.PLAN_MODE
    evaluate: bool = True
    ranks: str | None = None
    reference: Path | None = None
    pairs: int = 20
    seed: int = 0


@dataclass(frozen=True)
class PipelineResult:
    """Where everything went."""

    out_dir: Path
    interpretation: Any
    masks: Path | None
    costmap: Any
    plan: Any = None
    evaluation: Any = None

    @property
    def manifest(self) -> Path:
        return self.out_dir / "manifest.json"

    def to_json(self) -> dict[str, Any]:
        """What `overseec run --json` prints: each stage's own --json document (None for a stage
        that did not run) and where the run's files are."""
        ev = self.evaluation
        return {
            "out_dir": str(self.out_dir),
            "manifest": str(self.manifest),
            "prompt": self.interpretation.prompt,
            "interpretation": self.interpretation.to_json(),
            "masks": None if self.masks is None else str(self.masks),
            "costmap": self.costmap.to_json(),
            "plan": None if self.plan is None else self.plan.to_json(),
            "evaluation": None
            if ev is None
            else {"files": {k: str(v) for k, v in ev.files.items()}, "metrics": dict(ev.metrics)},
        }


def _ranks_from_fit(interp: Any, fitted: Any, class_names: Sequence[str]) -> tuple[str | None, int]:
    """RRPI ranks for the label classes, from the preferences the costmap gave their layers
    (compose.layer_preferences, the same choice), and the rank of neutral ground."""
    neutral_rank = 1 + len(
        {round(p.weight, 6) for p in interp.preferences if not p.lethal and p.weight < NEUTRAL - 1e-9}
    )
    chosen, _ = layer_preferences(interp, fitted.mapping)
    pairs = [f"{name}={chosen[name].rank if name in chosen else neutral_rank}" for name in class_names]
    return ",".join(pairs) or None, neutral_rank


#: What `run` writes into its folder ...
RUN_OUTPUT_NAMES = runfiles.RUN_OUTPUT_NAMES
#: ... and into its evaluation/ subfolder.
RUN_EVALUATION_NAMES = runfiles.RUN_EVALUATION_NAMES


def run_inputs(o: PipelineOptions) -> list[tuple[str, Path]]:
    """Every file or folder a run reads, with the option that named it."""
    found = [("image", o.image), ("labels", o.labels), ("classes", o.classes), ("reference", o.reference)]
    found += [("vector", parse_vector_spec(spec)[1]) for spec in o.vectors]
    for stage, attr in ((o.segment, "clipseg_model"), (o.refine, "sam_model")):
        model = getattr(stage, attr, None)
        if model is not None and Path(str(model)).exists():
            found.append((attr.replace("_", "-"), Path(str(model))))
    return [(role, Path(p)) for role, p in found if p is not None]


def check_run_inputs(o: PipelineOptions) -> None:
    """Refuse, before anything is written, a run that would write over one of its inputs."""
    out = Path(o.out_dir).resolve()
    outputs = [out / name for name in RUN_OUTPUT_NAMES] + [
        out / runfiles.EVALUATION_DIR / name for name in RUN_EVALUATION_NAMES
    ]
    for role, path in run_inputs(o):
        p = path.resolve()
        if p in outputs or p == out or any(_same_file(p, q) for q in outputs):
            which = "the image" if role == "image" else f"--{role}"
            raise OutputError(
                f"{which} {path} is where the run writes its outputs "
                f"({'the --out folder' if p == out else p.name}); move it or choose "
                "another --out"
            )


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.exists() and b.exists() and os.path.samefile(a, b)
    except OSError:
        return False


def check_run_grids(o: PipelineOptions) -> None:
    """A run's class raster must lie on its image's grid: the costmap, the path and the
    evaluation are all made on the labels' grid and drawn over the image."""
    check_image_data(o.image)
    if o.labels is None:
        return
    image, labels = read_grid(o.image), read_grid(o.labels)
    if not image.same_as(labels, tol=1e-6):
        why = (
            f"{image.width}x{image.height} vs {labels.width}x{labels.height} px"
            if image.shape != labels.shape
            else "their CRS or geotransforms differ"
        )
        raise InputError(
            f"--labels {o.labels} is not on the grid of the image {o.image} ({why}); "
            "resample one onto the other's grid first"
        )


def run_all(
    options: PipelineOptions, progress: Progress | None = None, command_args: dict | None = None
) -> PipelineResult:
    """Run every stage into ``options.out_dir``; each stage records itself in its manifest.

    The run's outputs are one transaction: a run cancelled or failing half-way leaves the folder
    (an earlier run's files, its manifest) exactly as it was."""
    o = options
    if (o.labels is None) != (o.classes is None):
        raise InputError("--labels and --classes go together")
    if o.labels is None:
        require_extra(
            "models",
            "a run without --labels segments the image (CLIPSeg and SAM) and",
            "; or give a class raster with --labels and --classes",
        )
        if getattr(o.segment, "dask_scheduler", None):
            require_extra("dask", "--dask-scheduler")
    check_run_inputs(o)
    check_run_grids(o)
    resolve_priors(o.priors, enabled=not o.no_priors)  # a bad --priors file: one line, nothing written
    with output_transaction():
        return _run_stages(o, progress, command_args)


def _run_stages(o: PipelineOptions, progress: Progress | None, command_args: dict | None) -> PipelineResult:
    out = Path(o.out_dir)
    run = RunDir(out, command="run", args=command_args)
    info = run_info(o.image, bands=o.bands, assume_crs=o.assume_crs)
    run.record_input("image", o.image)
    run.set("image", info.to_json())
    run.save()

    table = resolve_priors(o.priors, enabled=not o.no_priors)
    interp = run_interpret(
        o.prompt,
        priors=table,
        offline=o.offline,
        llm_url=o.llm_url,
        llm_model=o.llm_model,
        llm_key_env=o.llm_key_env,
        llm_fallback_offline=o.llm_fallback_offline,
        run_dir=out,
        progress=progress,
    )

    masks = None
    if o.labels is None:
        from overseec_core.locate.refine import RefineOptions  # model stages: only when segmenting
        from overseec_core.locate.segment import SegmentOptions

        seg = replace(o.segment or SegmentOptions(), bands=o.bands, assume_crs=o.assume_crs)
        ref = RefineOptions() if o.refine == "default" else o.refine
        if ref is not None:
            ref = replace(ref, bands=o.bands, assume_crs=o.assume_crs)
        run_segment(o.image, interp.entities, out, seg, ref, progress)
        masks = out

    layers = CostmapOptions(
        out=out / runfiles.COSTMAP, masks=masks, labels=o.labels, classes=o.classes, vectors=o.vectors, program_text=""
    )
    fitted = fit_program(interp, _layer_names(layers), dict(o.aliases), table)
    if progress is not None:
        for note in fitted.notes:
            progress.message(note)
        for warning in fitted.warnings:
            progress.message(f"warning: {warning}")
    cost = run_costmap(replace(layers, program_text=fitted.text), progress, prompt=o.prompt)

    plan = None
    if len(o.points) >= 2:
        plan = run_plan(
            PlanOptions(
                costmap=cost.costmap,
                points=tuple(o.points),
                out=out / runfiles.PATH,
                crs=o.points_crs,
                mode=o.plan_mode,
                native_out=out / runfiles.PATH_NATIVE,
            ),
            progress,
        )

    evaluation = None
    if o.evaluate and (o.labels is not None or o.reference is not None):
        ranks = o.ranks
        unranked: int | str = "max"
        if ranks is None and o.classes is not None:
            ranks, unranked = _ranks_from_fit(interp, fitted, list(load_classes(o.classes).values()))
        evaluation = run_evaluate(
            EvaluateOptions(
                out_dir=out / runfiles.EVALUATION_DIR,
                labels=o.labels,
                classes=o.classes,
                ranks=ranks,
                unranked_rank=unranked,
                costmap=cost.costmap,
                pairs=o.pairs,
                seed=o.seed,
                reference=o.reference,
                paths=plan.outputs["geojson"] if plan is not None else None,
                image=Path(o.image),
            ),
            progress,
        )
    return PipelineResult(
        out_dir=out, interpretation=interp, masks=masks, costmap=cost, plan=plan, evaluation=evaluation
    )


def _layer_names(layers: Any) -> list[str]:
    """Entity names the costmap stage will have layers for (the same opener it uses)."""
    source = open_layers(layers)
    try:
        return list(source.names)
    finally:
        source.close()
