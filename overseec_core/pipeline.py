"""The one orchestration of overseec's stages, shared by the CLI, the QGIS task and Processing.

Each stage function takes plain arguments (paths, option dataclasses, a Progress), writes its
outputs into a run directory with a manifest entry, and returns a frozen result. Stages read and
write files on the image's grid, so any one can be re-run alone: re-prompting re-uses the masks.

    image ─ info ─ interpret ─ segment (+ refine) ─ costmap ─ plan ─ evaluate
"""

from __future__ import annotations

import os
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np

from overseec_core import defaults, runfiles
from overseec_core.costlang.scale import NEUTRAL
from overseec_core.errors import InputError, OutputError, OverseecError
from overseec_core.evaluate import EvaluateOptions, load_classes
from overseec_core.evaluate.compare import (
    CSV_NAME,
    DIFFERENCE_NAME,
    FIGURE_NAME,
    JSON_NAME,
    REPORT_NAME,
    Candidate,
    CompareOptions,
    check_options,
    class_shares,
    hausdorff_matrix,
    sample_pixels,
    write_difference,
)
from overseec_core.evaluate.compare_report import CompareResult, RouteRow, render_csv, render_report
from overseec_core.evaluate.maps import PlotPath, side_by_side_figure
from overseec_core.evaluate.previews import read_cost_preview
from overseec_core.evaluate.stage import run_evaluate
from overseec_core.extras import require_extra
from overseec_core.interpret import interpret
from overseec_core.interpret.priors import resolve_priors
from overseec_core.interpret.stage import require_all_read, run_interpret
from overseec_core.io.atomic import atomic_path, write_text_atomic
from overseec_core.io.inputs import check_image_data
from overseec_core.io.manifest import RunDir, write_json_atomic
from overseec_core.io.read import read_grid, read_info
from overseec_core.io.transaction import output_transaction
from overseec_core.locate.stage import run_segment
from overseec_core.plan.stage import PlanOptions, run_plan
from overseec_core.progress import NullProgress, Progress, check_cancelled
from overseec_core.schema import Interpretation
from overseec_core.synthesize.fit import check_program_choice, fit_program, layer_preferences
from overseec_core.synthesize.layers import load_class_entities, open_layers, parse_vector_spec
from overseec_core.synthesize.options import CostmapOptions, CostmapResult
from overseec_core.synthesize.stage import run_synthesize

if TYPE_CHECKING:  # annotations only: the model stages are imported where a model runs (run_segment)
    pass

T = TypeVar("T")


# --- chains of stages ---
def interpret_for_costmap(options: CostmapOptions) -> Interpretation | None:
    """The offline interpretation of a costmap's prompt, or None when a program is given."""
    check_program_choice(options)
    if options.prompt is None:
        return None
    if not options.prompt.strip():
        raise InputError("--prompt is empty; say what to prefer and avoid")
    interp = interpret(options.prompt, offline=True, priors=options.prior_table())
    if options.strict:
        require_all_read(interp)
    return interp


def run_costmap(
    options: CostmapOptions,
    progress: Progress | None = None,
    command_args: dict | None = None,
    *,
    prompt: str | None = None,
) -> CostmapResult:
    """`overseec costmap`: Interpret (offline, when the options carry a prompt), then Synthesize
    (:func:`overseec_core.synthesize.stage.run_synthesize`)."""
    if options.dem is not None:
        from overseec_core.io.dem import check_dem_file

        check_dem_file(options.dem)  # a photo given as the DEM fails first, not after the reading
    interpretation = interpret_for_costmap(options)
    return run_synthesize(options, progress, command_args, prompt=prompt, interpretation=interpretation)


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


# --- compare: several prompts or programs, each through costmap and plan ---

# --------------------------------------------------------------------------------------------
# The command
# --------------------------------------------------------------------------------------------


def _titled(candidate: Candidate, exc: OverseecError) -> OverseecError:
    """The same error, its message prefixed with the candidate it concerns."""
    short = candidate.title if len(candidate.title) <= 60 else candidate.title[:57] + "..."
    if exc.args and isinstance(exc.args[0], str):
        exc.args = (f"{candidate.name} ({short!r}): {exc.args[0]}",) + tuple(exc.args[1:])
    return exc


def _rel(path: Path, root: Path) -> str:
    try:
        return Path(path).resolve().relative_to(root.resolve()).as_posix()
    except ValueError:
        return str(path)


def _same_program_notes(candidates: Sequence[Candidate], programs: Sequence[str]) -> list[str]:
    """Notes for candidates whose programs came out the same (their costmaps are equal)."""
    notes: list[str] = []
    first: dict[str, Candidate] = {}
    for c, text in zip(candidates, programs):
        body = "\n".join(ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#"))
        if body in first:
            notes.append(
                f"{c.name} and {first[body].name} give the same cost program: their costmaps and routes are the same"
            )
        else:
            first[body] = c
    return notes


def _input_files(o: CompareOptions) -> list[tuple[str, Path]]:
    """The files to hash into the manifest: every input file, and for a --masks folder the mask
    and probability rasters the costmap stage reads from it (runfiles.MASK_FILES)."""

    files = []
    for role, path in o.inputs():
        if path.is_dir() and role == "masks":
            pair = next((pair for pair in runfiles.MASK_FILES if (path / pair[0]).is_file()), ())
            files += [(role, path / name) for name in pair if (path / name).is_file()]
        elif path.is_file():
            files.append((role, path))
    return files


def run_compare(
    options: CompareOptions, progress: Progress | None = None, command_args: dict | None = None
) -> CompareResult:
    """Every candidate's costmap and route, then the difference raster, figure and tables.

    All outputs are one transaction: a failure or a cancel (in any candidate) leaves the output
    folder as it was, and removes the folders it created.
    """

    check_options(options)
    out = Path(options.out_dir)
    created = [d for d in (out, *(out / c.name for c in options.candidates)) if not d.exists()]
    try:
        with output_transaction(progress):
            return _run(options, progress or NullProgress(), command_args)
    except BaseException:
        for folder in reversed(created):  # only if empty: nothing of anyone else's goes
            try:
                folder.rmdir()
            except OSError:
                pass
        raise


def _run(o: CompareOptions, progress: Progress, command_args: dict | None) -> CompareResult:

    t0 = time.perf_counter()
    out = Path(o.out_dir)
    run = RunDir(out, command="compare", args=command_args)
    for role, path in _input_files(o):
        run.record_input(f"compare_{role}_{path.name}", path)
    run.update_parameters(
        compare={
            "prompts": [{"name": c.name, "kind": c.kind, "value": c.value} for c in o.candidates],
            "points": [list(p) for p in o.points],
            "crs": o.crs,
            "mode": o.mode,
            "vectors": list(o.vectors),
            "aliases": [list(a) for a in o.aliases],
            "line_width_m": o.line_width_m,
            "block_size": o.block_size,
        }
    )
    with run.stage("compare"):
        costmaps, plans = _run_candidates(o, progress)
        t_runs = time.perf_counter()
        difference = write_difference(
            [cm.costmap for cm in costmaps],
            [c.name for c in o.candidates],
            out / DIFFERENCE_NAME,
            o.block_size,
            progress,
        )
        routes = [np.asarray(p.result.pixels, dtype=np.int64) for p in plans]
        classes, shares = _route_shares(o, routes)
        rows = tuple(_route_row(c, cm, p, s, out) for c, cm, p, s in zip(o.candidates, costmaps, plans, shares))
        notes = _same_program_notes(o.candidates, [cm.program for cm in costmaps])
        for note in notes:
            progress.message(f"note: {note}")
        grid = read_grid(costmaps[0].costmap)
        _write_figure(out / FIGURE_NAME, grid, o.candidates, [cm.costmap for cm in costmaps], routes)
        result = CompareResult(
            out_dir=out,
            rows=rows,
            hausdorff_m=hausdorff_matrix(routes, grid.pixel_size_m()),
            difference=difference,
            files=_output_files(out),
            points=tuple(o.points),
            crs=o.crs,
            mode=o.mode,
            classes=tuple(classes.values()),
            notes=tuple(notes),
            timings={"candidates_s": round(t_runs - t0, 4), "compare_s": round(time.perf_counter() - t_runs, 4)},
        )
        _write_tables(result)
    run.set(
        "compare",
        {
            "prompts": [r.to_json() for r in rows],
            "pairs": result.pairs(),
            "difference": [b.to_json() for b in difference],
            "notes": list(notes),
            "outputs": {k: v.name for k, v in result.files.items()},
            "folders": [c.name for c in o.candidates],
            "timings": dict(result.timings),
        },
    )
    run.save()
    return result


def _run_candidates(o: CompareOptions, progress: Progress) -> tuple[list, list]:
    """Each candidate through the costmap stage and the planner, into its subfolder; an error
    names the candidate it came from."""

    costmaps, plans = [], []
    for c in o.candidates:
        check_cancelled(progress)
        progress.message(f"{c.name}: {c.title}")
        folder = Path(o.out_dir) / c.name
        folder.mkdir(parents=True, exist_ok=True)
        try:
            cost = run_costmap(
                o.costmap_options(c), progress, command_args={"compare": c.name, "kind": c.kind, "value": c.value}
            )
            plan = run_plan(
                PlanOptions(
                    costmap=cost.costmap, points=tuple(o.points), out=folder / runfiles.PATH, crs=o.crs, mode=o.mode
                ),
                progress,
                command_args={"compare": c.name},
            )
        except OverseecError as exc:
            _titled(c, exc)  # the same error, its message now naming the candidate
            raise
        costmaps.append(cost)
        plans.append(plan)
    return costmaps, plans


def _route_shares(
    o: CompareOptions, routes: Sequence[np.ndarray]
) -> tuple[dict[int, str], list[Mapping[str, float] | None]]:
    """Classes (id -> name, in id order) and each route's class shares; none without labels."""

    if o.labels is None or o.classes is None:
        return {}, [None] * len(routes)
    classes = dict(sorted(load_classes(o.classes).names.items()))
    return classes, [class_shares(*sample_pixels(o.labels, r), classes) for r in routes]


def _route_row(c: Candidate, cm: Any, p: Any, share: Mapping[str, float] | None, out: Path) -> RouteRow:
    """The table row of one candidate from its costmap (CostmapResult) and plan (PlanRunResult)."""
    r = p.result
    return RouteRow(
        name=c.name,
        kind=c.kind,
        prompt=c.title,
        length_m=float(r.length_m),
        cost=float(r.cost),
        n_pixels=int(len(r.pixels)),
        mode=str(r.mode),
        bound=float(r.bound),
        class_share=share,
        costmap=_rel(cm.costmap, out),
        route=_rel(p.outputs["geojson"], out),
        program_file=_rel(cm.program_file, out),
        program_source=cm.program_source,
        mean_cost=cm.mean_cost,
        notes=tuple(r.notes),
    )


def _write_figure(
    path: Path, grid: Any, candidates: Sequence[Candidate], costmaps: Sequence[Path], routes: Sequence[np.ndarray]
) -> Path:
    """compare.png: :func:`maps.side_by_side_figure`, written atomically."""

    fig, _ = side_by_side_figure(
        grid,
        [read_cost_preview(p, max_size=900) for p in costmaps],
        [PlotPath(rows_cols=r, label=c.name) for c, r in zip(candidates, routes)],
        [f"{c.index}. {c.title}" for c in candidates],
    )
    with atomic_path(path, suffix=".partial.png") as tmp:
        fig.savefig(tmp, format="png")
    return path


def _output_files(out: Path) -> dict[str, Path]:
    return {
        "difference": out / DIFFERENCE_NAME,
        "figure": out / FIGURE_NAME,
        "csv": out / CSV_NAME,
        "json": out / JSON_NAME,
        "report": out / REPORT_NAME,
    }


def _write_tables(result: CompareResult) -> None:
    """compare.csv, compare.json and report.md, each atomically."""

    write_text_atomic(result.files["csv"], render_csv(result))
    write_json_atomic(result.files["json"], result.to_json())
    write_text_atomic(result.files["report"], render_report(result))
