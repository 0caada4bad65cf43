"""The one orchestration of overseec's stages, shared by the CLI, the QGIS task and Processing.

Each stage function takes plain arguments (paths, option dataclasses, a Progress), writes its
outputs into a run directory with a manifest entry, and returns a frozen result. Stages read and
write files on the image's grid, so any one can be re-run alone: re-prompting re-uses the masks.

    image ─ info ─ interpret ─ segment (+ refine) ─ costmap ─ plan ─ evaluate
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from overseec_core import defaults, runfiles
from overseec_core.costlang.scale import NEUTRAL
from overseec_core.errors import InputError, OutputError
from overseec_core.evaluate import EvaluateOptions
from overseec_core.evaluate.stage import run_evaluate
from overseec_core.extras import require_extra
from overseec_core.interpret.priors import resolve_priors
from overseec_core.interpret.stage import require_all_read, run_interpret
from overseec_core.io.inputs import check_image_data
from overseec_core.io.manifest import RunDir
from overseec_core.io.read import read_grid, read_info
from overseec_core.io.transaction import output_transaction
from overseec_core.locate.stage import run_segment
from overseec_core.pipeline_compare import run_compare as run_compare  # the API's name (docs/api.md)
from overseec_core.pipeline_costmap import interpret_for_costmap as interpret_for_costmap
from overseec_core.pipeline_costmap import run_costmap as run_costmap
from overseec_core.plan.stage import PlanOptions, run_plan
from overseec_core.progress import Progress
from overseec_core.synthesize.fit import fit_program, layer_preferences
from overseec_core.synthesize.layers import load_class_entities, open_layers, parse_vector_spec
from overseec_core.synthesize.options import CostmapOptions
from overseec_core.synthesize.stage import run_synthesize

if TYPE_CHECKING:  # annotations only: the model stages are imported where a model runs (run_segment)
    pass

T = TypeVar("T")


# --- chains of stages (the costmap and compare chains are their own modules; their names stay here) ---
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
    #: A DEM for the costmap's terrain term (slope; ``synthesize.terrain``), passed through.
    dem: Path | None = None
    #: ``--strict``: a prompt clause that was not understood is an error (exit 2).
    strict: bool = False
    segment: Any = None  # overseec_core.locate.segment.SegmentOptions (its segmenter and model); None = defaults
    refine: Any = "default"  # overseec_core.locate.refine.RefineOptions, "default", or None to skip
    plan_mode: str = defaults.PLAN_MODE
    #: The route's steps: 8 neighbours, or 16 with knight moves (``plan --neighbours``).
    plan_neighbours: int = 8
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
        return self.out_dir / runfiles.MANIFEST

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


def run_inputs(o: PipelineOptions) -> list[tuple[str, Path]]:
    """Every file or folder a run reads, with the option that named it."""
    found = [("image", o.image), ("labels", o.labels), ("classes", o.classes), ("reference", o.reference)]
    found += [("vector", parse_vector_spec(spec)[1]) for spec in o.vectors]
    seg = o.segment
    seg_model = seg.resolved_model() if seg is not None else None
    seg_flag = "model" if getattr(seg, "model", None) else "clipseg-model"  # the flag that named it
    for role, model in ((seg_flag, seg_model), ("sam-model", getattr(o.refine, "sam_model", None))):
        if model is not None and Path(str(model)).exists():
            found.append((role, Path(str(model))))
    return [(role, Path(p)) for role, p in found if p is not None]


def check_run_inputs(o: PipelineOptions) -> None:
    """Refuse, before anything is written, a run that would write over one of its inputs (or
    whose DEM is no elevation model)."""
    dem = getattr(o, "dem", None)
    if dem is not None:
        from overseec_core.io.dem import check_dem_file

        check_dem_file(dem)
    out = Path(o.out_dir).resolve()
    outputs = [out / name for name in runfiles.RUN_OUTPUT_NAMES] + [
        out / runfiles.EVALUATION_DIR / name for name in runfiles.RUN_EVALUATION_NAMES
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
    with output_transaction(progress):
        return _run_stages(o, progress, command_args)


def _run_stages(o: PipelineOptions, progress: Progress | None, command_args: dict | None) -> PipelineResult:
    out = Path(o.out_dir)
    run = RunDir(out, command="run", args=command_args)
    info = read_info(o.image, bands=o.bands, assume_crs=o.assume_crs)
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
        terrain=o.dem is not None,
    )
    if o.strict:
        require_all_read(interp)

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
        out=out / runfiles.COSTMAP,
        masks=masks,
        labels=o.labels,
        classes=o.classes,
        vectors=o.vectors,
        program_text="",
        dem=o.dem,
    )
    fitted = fit_program(interp, _layer_names(layers), dict(o.aliases), table, strict=o.strict)
    if progress is not None:
        for note in fitted.notes:
            progress.message(note)
        for warning in fitted.warnings:
            progress.message(f"warning: {warning}")
    cost = run_synthesize(replace(layers, program_text=fitted.text), progress, prompt=o.prompt)

    plan = None
    if len(o.points) >= 2:
        plan = run_plan(
            PlanOptions(
                costmap=cost.costmap,
                points=tuple(o.points),
                out=out / runfiles.PATH,
                crs=o.points_crs,
                mode=o.plan_mode,
                neighbours=o.plan_neighbours,
                native_out=out / runfiles.PATH_NATIVE,
            ),
            progress,
        )

    evaluation = None
    if o.evaluate and (o.labels is not None or o.reference is not None):
        ranks = o.ranks
        unranked: int | str = "max"
        if ranks is None and o.classes is not None:
            ranks, unranked = _ranks_from_fit(interp, fitted, list(load_class_entities(o.classes).values()))
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
