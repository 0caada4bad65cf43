"""The evaluate stage's options and result, and the stage itself (:func:`evaluate_paths`):
sample and plan pairs, measure every path, write metrics.json, report.md, pairs.csv,
paths.geojson and the plots.

``overseec eval``, the QGIS task and Processing all go through
:func:`run_evaluate` below, which uses these.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from overseec_core import defaults
from overseec_core.errors import EvaluateError, InputError, OutputError, PlanError
from overseec_core.evaluate.classes import RankTable, load_classes, parse_ranks
from overseec_core.evaluate.geometry import (
    ReferenceSet,
    VectorLine,
    check_same_grid,
    endpoint_tolerance_m,
    hausdorff,
    map_diagonal_m,
    matching_references,
    point_json,
    rasterise_line,
    read_lines,
)
from overseec_core.evaluate.iou import compute_iou, parse_matches
from overseec_core.evaluate.metrics import (
    NEAR_OPTIMAL_RATIO,
    EvaluatedPath,
    RankOptimalPlanner,
    kde_centre_of_mass,
    linear_fit,
    rank_scale,
    rrpi,
    summarise_ratios,
)
from overseec_core.evaluate.previews import cost_preview_from_array
from overseec_core.evaluate.report import DEFINITIONS, render_report, write_pairs_csv, write_paths_geojson, write_plots
from overseec_core.evaluate.sampling import DEFAULT_MIN_SEPARATION_FRACTION, sample_pairs, sample_pairs_uniform
from overseec_core.io.atomic import write_text_atomic
from overseec_core.io.grid import Grid, crs_label
from overseec_core.io.inputs import check_class_raster
from overseec_core.io.manifest import RunDir, write_json_atomic
from overseec_core.io.read import open_raster, read_grid
from overseec_core.io.transaction import transactional
from overseec_core.io.write import check_output_path
from overseec_core.limits import check_pixels
from overseec_core.plan import MODES, Planner, load_costmap, path_length_m
from overseec_core.plan.stage import RulePlanner
from overseec_core.progress import NullProgress, Progress, check_cancelled
from overseec_core.runfiles import EVALUATION_FILES


@dataclass(frozen=True)
class EvaluateOptions:
    """What `overseec eval` was asked to do. Every input is optional; each metric runs when its
    inputs are there (IoU: masks + labels + classes; RRPI: labels + classes + ranks; sampling:
    costmap; Hausdorff: reference paths)."""

    out_dir: Path
    labels: Path | None = None
    classes: Path | None = None
    ranks: str | Mapping[str, int] | None = None
    unranked_rank: int | str = "max"
    costmap: Path | None = None
    pairs: int = 50
    seed: int = 0
    min_separation_m: float | None = None
    #: one of ``defaults.PAIR_DRAWS``: over passable cells a separation apart, or uniform over the
    #: image as the paper draws its pairs (a pair on an impassable cell is then unreachable)
    pair_draw: str = defaults.PAIR_DRAWS[0]
    plan_mode: str = "exact"
    reference: Path | None = None
    paths: Path | None = None
    symmetric: bool = False
    masks: Path | None = None
    matches: tuple[str, ...] = ()
    mask_threshold: float | None = None
    image: Path | None = None
    plots: bool = True
    plot_size: int = 1600

    def inputs(self) -> dict[str, Path]:
        """Input files by role (for the manifest and the never-overwrite check)."""
        roles = ("labels", "classes", "costmap", "reference", "paths", "masks", "image")
        return {r: Path(getattr(self, r)) for r in roles if getattr(self, r) is not None}


@dataclass(frozen=True)
class EvaluateResult:
    """The figures (as written to metrics.json) and the files written."""

    metrics: Mapping[str, Any]
    files: Mapping[str, Path]


def check_options(o: EvaluateOptions) -> None:  # noqa: C901
    """One-line InputErrors for options that cannot work together or files that do not exist."""
    if o.ranks is not None and (o.labels is None or o.classes is None):
        raise InputError("--ranks needs --labels (class raster) and --classes (classes.json)")
    if o.masks is not None and (o.labels is None or o.classes is None):
        raise InputError("--masks needs --labels (ground-truth class raster) and --classes")
    if o.labels is not None and o.classes is None:
        raise InputError("--labels needs --classes (classes.json: class id -> name)")
    if o.pairs < 0:
        raise InputError(f"--pairs must be >= 0, not {o.pairs}")
    if o.min_separation_m is not None and o.min_separation_m < 0:
        raise InputError(f"--min-separation must be >= 0 metres, not {o.min_separation_m:g}")
    if o.pair_draw not in defaults.PAIR_DRAWS:
        raise InputError(f"--pair-draw must be one of {', '.join(defaults.PAIR_DRAWS)}, not {o.pair_draw!r}")
    if o.pair_draw == "image" and o.min_separation_m is not None:
        raise InputError("--min-separation applies to --pair-draw passable; the paper's image draw keeps no separation")
    if o.matches and o.masks is None:
        raise InputError("--match needs --masks")
    if o.image is not None and o.costmap is None:
        raise InputError("--image is drawn under the costmap; give --costmap too")
    nothing = o.masks is None and o.costmap is None and o.paths is None
    if nothing:
        raise InputError(
            "nothing to evaluate: give --costmap (paths, RRPI, Hausdorff), --paths (given paths) or --masks (IoU)"
        )
    if o.paths is not None and o.costmap is None and o.labels is None:
        raise InputError("--paths needs --costmap or --labels to place the paths on a grid")
    for role, path in o.inputs().items():
        if not Path(path).exists():
            raise InputError(f"no such file for --{role}: {path}")
    for role in ("labels", "costmap"):
        path = getattr(o, role)
        if path is not None:
            grid = read_grid(path)
            check_pixels(grid.width, grid.height, path, role)
    # cheap content checks, so that a mistake fails before any output is made
    classes = load_classes(o.classes) if o.classes is not None else None
    if classes is not None and o.labels is not None:
        check_class_raster(o.labels, classes.names)  # warnings: IoU reports absent classes itself
    if o.ranks is not None:
        assert classes is not None  # --ranks needs --classes (checked above)
        parse_ranks(o.ranks, classes, o.unranked_rank)
    parse_matches(o.matches)
    if o.costmap is not None:
        if o.plan_mode not in MODES:
            raise InputError(f"unknown planning mode {o.plan_mode!r}; use {' or '.join(MODES)}")
        if o.labels is not None:
            check_same_grid(read_grid(o.costmap), read_grid(o.labels), f"costmap {o.costmap}", f"labels {o.labels}")
    if o.masks is not None:
        assert o.labels is not None  # --masks needs --labels (checked above)
        check_same_grid(read_grid(o.labels), read_grid(o.masks), f"labels {o.labels}", f"masks {o.masks}")


def _output_paths(o: EvaluateOptions) -> dict[str, Path]:
    out = Path(o.out_dir)
    if out.exists() and not out.is_dir():
        raise OutputError(f"--out {out} exists and is not a folder")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"cannot create output folder {out} ({exc.strerror})") from None
    files = {k: out / v for k, v in EVALUATION_FILES.items()}
    inputs = list(o.inputs().values())
    for f in files.values():
        check_output_path(f, inputs)
    return files


def _read_labels(path: Path, grid: Grid) -> tuple[np.ndarray, float | None]:
    check_same_grid(grid, read_grid(path), "the costmap", f"labels {path}")
    with open_raster(path) as ds:
        if ds.dtypes[0][0] not in "ui":
            raise EvaluateError(f"labels {path} must hold integer class ids, not {ds.dtypes[0]}")
        return ds.read(1), ds.nodata


def _planned(name: str, group: str, res: Any) -> EvaluatedPath:
    return EvaluatedPath(
        name=name,
        group=group,
        pixels=np.asarray(res.pixels, dtype=np.int64),
        length_m=float(res.length_m),
        cost=float(res.cost),
        mode=str(res.mode),
    )


class _CancelOnly(NullProgress):
    """Forwards only cancellation to the planner, so its per-query bars do not replace ours."""

    def __init__(self, outer: Progress) -> None:
        super().__init__()
        self._outer = outer

    def cancelled(self) -> bool:
        return self._outer.cancelled()


def _sample_and_plan(
    rules: Any, o: EvaluateOptions, grid: Grid, progress: Progress
) -> tuple[list[EvaluatedPath], dict[str, Any]]:
    """Draw ``o.pairs`` seeded pairs (over passable cells, or uniform over the image as the paper
    does) and plan each; unreachable ones are listed."""
    rng = np.random.default_rng(o.seed)
    sep: float | None = None
    if o.pair_draw == "image":
        pairs = sample_pairs_uniform(rules.grid.passable.shape, o.pairs, rng)
    else:
        sep = o.min_separation_m
        if sep is None:
            sep = DEFAULT_MIN_SEPARATION_FRACTION * map_diagonal_m(grid)
        pairs = sample_pairs(rules.grid.passable, o.pairs, rng, sep, grid.pixel_size_m())
    paths: list[EvaluatedPath] = []
    unreachable: list[dict[str, Any]] = []
    broken_before = rules.rules_broken
    inner = _CancelOnly(progress)
    progress.begin("evaluate: planning", len(pairs), unit="pair")
    for k, (start, goal) in enumerate(pairs):
        check_cancelled(progress)
        try:
            res, _ = rules.plan([start, goal], mode=o.plan_mode, progress=inner)
            paths.append(_planned(f"pair {k + 1}", "sampled", res))
        except PlanError as exc:
            unreachable.append(
                {
                    "name": f"pair {k + 1}",
                    "start": point_json(grid, start),
                    "goal": point_json(grid, goal),
                    "error": str(exc),
                }
            )
        progress.advance()
    progress.end()
    sampling = {
        "seed": o.seed,
        "draw": o.pair_draw,
        "requested": o.pairs,
        "drawn": len(pairs),
        "planned": len(paths),
        "min_separation_m": sep,
        "mode": o.plan_mode,
        "unreachable": unreachable,
        "rules_not_met": rules.rules_broken - broken_before,
    }
    return paths, sampling


def _drawn_paths(
    lines: Sequence[VectorLine], group: str, grid: Grid, planner: Any | None, source: Path | None, notes: list[str]
) -> list[EvaluatedPath]:
    """Lines rasterised to pixel chains, priced on the costmap when there is one.

    Given paths (``group == "given"``) must lie inside the grid; reference paths that leave it
    are only noted (they still count for the Hausdorff distance).
    """
    dx, dy = grid.pixel_size_m()
    out = []
    for line in lines:
        chain = rasterise_line(line.rows_cols)
        inside = ((chain >= 0) & (chain < (grid.height, grid.width))).all()
        if not inside:
            if group == "given":
                raise EvaluateError(f"path {line.name!r} in {source} leaves the costmap's extent")
            notes.append(f"reference {line.name!r} leaves the grid; it has no RRPI or cost")
            continue
        cost = planner.path_cost(chain) if planner is not None else None
        if cost is not None and not math.isfinite(cost):
            notes.append(f"{group} path {line.name!r} crosses impassable cells of the costmap")
            cost = None
        out.append(
            EvaluatedPath(name=line.name, group=group, pixels=chain, length_m=path_length_m(chain, dx, dy), cost=cost)
        )
    return out


def _reference_plans(rules: Any, references: Sequence[VectorLine], mode: str, notes: list[str]) -> list[EvaluatedPath]:
    """Plan between the first and last vertex of each reference path (keep-out zones entered
    only when they must be, as for sampled pairs)."""
    out = []
    for line in references:
        ends = np.floor(line.rows_cols[[0, -1]] + 0.5).astype(np.int64)
        try:
            res, _ = rules.plan([tuple(map(int, ends[0])), tuple(map(int, ends[1]))], mode=mode)
        except PlanError as exc:
            notes.append(f"no plan between the ends of reference {line.name!r}: {exc}")
            continue
        out.append(_planned(f"plan along {line.name}", "reference-ends", res))
    return out


def evaluate_paths(options: EvaluateOptions, progress: Progress | None = None) -> EvaluateResult:  # noqa: C901
    """Run every metric the inputs allow and write metrics.json, report.md, pairs.csv,
    paths.geojson and the PNG plots into ``options.out_dir`` (created if missing)."""
    o = options
    progress = progress or NullProgress()
    check_options(o)
    files = _output_paths(o)
    metrics: dict[str, Any] = {
        "inputs": {k: str(v) for k, v in o.inputs().items()},
        "definitions": DEFINITIONS,
        "notes": [],
    }
    notes: list[str] = metrics["notes"]
    classes = load_classes(o.classes) if o.classes is not None else None
    ranks: RankTable | None = None
    if o.ranks is not None:
        assert classes is not None  # --ranks needs --classes (check_options)
        ranks = parse_ranks(o.ranks, classes, o.unranked_rank)
        metrics["ranks"] = ranks.to_json(classes)

    iou = None
    if o.masks is not None:
        assert o.labels is not None and classes is not None  # --masks needs both (check_options)
        iou = compute_iou(o.masks, o.labels, classes, parse_matches(o.matches), o.mask_threshold, progress)
        metrics["iou"] = iou.to_json()

    paths: list[EvaluatedPath] = []
    references: list[VectorLine] = []
    kde = fit = None
    grid = None
    cost_preview = None
    if o.costmap is not None or o.paths is not None:
        grid_source = o.costmap if o.costmap is not None else o.labels
        assert grid_source is not None  # --paths needs --costmap or --labels (check_options)
        grid = read_grid(grid_source)
        metrics["grid"] = {
            "crs": crs_label(grid.crs),
            "width": grid.width,
            "height": grid.height,
            "pixel_size_m": list(grid.pixel_size_m()),
            "diagonal_m": map_diagonal_m(grid),
        }
        if o.reference is not None:
            references = read_lines(o.reference, grid, what="reference path")
        planner = None
        base_cost_per_m = None
        if o.costmap is not None:
            planner = Planner(load_costmap(o.costmap))
            rules = RulePlanner(planner)  # one relaxed copy at most, shared by all queries
            base_cost_per_m = planner.base_cost_per_m
            if o.pairs > 0:
                sampled, metrics["sampling"] = _sample_and_plan(rules, o, grid, progress)
                paths += sampled
                if metrics["sampling"]["drawn"] < o.pairs:
                    notes.append(
                        f"only {metrics['sampling']['drawn']} of {o.pairs} pairs could be drawn "
                        f"{metrics['sampling']['min_separation_m']:.1f} m apart; "
                        "lower --min-separation for more"
                    )
            if references and o.paths is None:
                paths += _reference_plans(rules, references, o.plan_mode, notes)
        if o.paths is not None:
            paths += _drawn_paths(read_lines(o.paths, grid, what="path"), "given", grid, planner, o.paths, notes)
        paths += _drawn_paths(references, "reference", grid, planner, o.reference, notes)
        if planner is not None and o.plots:
            cost_preview = cost_preview_from_array(planner.grid.cost, o.plot_size)
        # the costmap and its planner are done with: free them before the rank planner is built
        planner = None
        labels: np.ndarray | None = None
        nodata: float | None = None
        if ranks is not None:
            assert o.labels is not None  # --ranks needs --labels (check_options)
            labels, nodata = _read_labels(o.labels, grid)
        paths = _measure_all(paths, o, grid, ranks, labels, nodata, references)
        if labels is not None and ranks is not None and paths:
            paths, metrics["rank_optimal"] = _rank_optimal(
                paths, labels, ranks, nodata, grid, base_cost_per_m, progress, notes
            )
        labels = None
        metrics["paths"] = [p.to_json(grid) for p in paths]
        metrics["summary"] = _summaries(paths)
        if references:
            metrics["hausdorff"] = _hausdorff_summary(paths, references, o.symmetric, grid)
        points = [(p.length_m, p.rrpi) for p in paths if p.group == "sampled" and p.rrpi is not None]
        if points:
            kde = kde_centre_of_mass([x for x, _ in points], [y for _, y in points])
            fit = linear_fit([x for x, _ in points], [y for _, y in points])
            metrics["kde"] = kde.to_json()
            metrics["fit"] = None if fit is None else {**asdict(fit), "unit": "RRPI per metre"}

    written: dict[str, Path] = {}
    if o.plots:
        written.update(
            write_plots(
                files,
                grid,
                paths,
                references,
                kde,
                fit,
                iou,
                cost_preview,
                costmap=o.costmap,
                image=o.image,
                plot_size=o.plot_size,
            )
        )
    if paths:
        assert grid is not None  # paths are only made on a grid (above)
        written["pairs_csv"] = write_pairs_csv(files["pairs_csv"], paths)
        written["paths_geojson"] = write_paths_geojson(files["paths_geojson"], paths, grid)
    metrics["files"] = {k: v.name for k, v in written.items()}
    written["metrics"] = write_json_atomic(files["metrics"], metrics)
    written["report"] = write_text_atomic(files["report"], render_report(metrics))
    return EvaluateResult(metrics=metrics, files=written)


def _measure_all(
    paths: Sequence[EvaluatedPath],
    o: EvaluateOptions,
    grid: Grid,
    ranks: RankTable | None,
    labels: np.ndarray | None,
    nodata: float | None,
    references: Sequence[VectorLine],
) -> list[EvaluatedPath]:
    """RRPI of every path (with ranks) and, for every system path whose start and goal match a
    reference path's ends, its Hausdorff distance to the reference paths of that pair."""
    pixel_size = grid.pixel_size_m()
    diagonal = map_diagonal_m(grid)
    tolerance = endpoint_tolerance_m(grid)
    refsets: dict[tuple[int, ...], ReferenceSet] = {}
    out = []
    for p in paths:
        value = rrpi(labels, p.pixels, ranks, nodata) if labels is not None and ranks is not None else None
        hd = None
        matched = None
        if references and p.group != "reference":
            idx = tuple(matching_references(p.pixels[0], p.pixels[-1], references, pixel_size, tolerance))
            matched = tuple(references[i].name for i in idx)
            if idx:
                if idx not in refsets:
                    refsets[idx] = ReferenceSet.build([references[i] for i in idx], pixel_size)
                hd = hausdorff(p.pixels, refsets[idx], pixel_size, diagonal, o.symmetric)
        out.append(replace(p, rrpi=value, hausdorff=hd, references=matched))
    return out


def _rank_optimal(
    paths: Sequence[EvaluatedPath],
    labels: np.ndarray,
    ranks: RankTable,
    nodata: float | None,
    grid: Grid,
    base_cost_per_m: float | None,
    progress: Progress,
    notes: list[str],
) -> tuple[list[EvaluatedPath], dict[str, Any]]:
    """The rank-optimal RRPI between the ends of every path with an RRPI, and its summary."""
    try:
        ropt = RankOptimalPlanner(labels, ranks, nodata, grid, base_cost_per_m=base_cost_per_m)
    except ImportError as exc:  # the planner's native kernel is not built
        notes.append(f"no rank-optimal reference: the planner is not available ({exc})")
        return list(paths), {"groups": {}, "headline": None, "error": str(exc)}
    inner = _CancelOnly(progress)
    out: list[EvaluatedPath] = []
    failed: list[str] = []
    progress.begin("evaluate: rank-optimal routes", sum(p.rrpi is not None for p in paths), unit="path")
    for p in paths:
        if p.rrpi is None:
            out.append(p)
            continue
        check_cancelled(progress)
        try:
            best = ropt.optimum(p.pixels[0], p.pixels[-1], progress=inner).rrpi
        except PlanError:
            best = None
            failed.append(p.name)
        out.append(replace(p, rrpi_optimal=best, rank_optimal_ran=True))
        progress.advance()
    progress.end()
    if failed:
        shown = ", ".join(repr(n) for n in failed[:5]) + (" ..." if len(failed) > 5 else "")
        notes.append(
            f"no rank-optimal route for {len(failed)} path(s) (an end on label nodata, or nodata "
            f"between the ends): {shown}"
        )
    groups = {}
    for group in dict.fromkeys(p.group for p in out):
        members = [(p.rrpi, p.rrpi_optimal) for p in out if p.group == group and p.rrpi is not None]
        if members:
            groups[group] = summarise_ratios([v for v, _ in members], [b for _, b in members])
    headline = next(
        (g for g in ("sampled", "reference-ends", "given", "reference") if groups.get(g, {}).get("n")), None
    )
    k = rank_scale(ranks)
    summary = {
        "rank_scale": k,
        "cost": f"(rank - 1) / {k - 1}" if k > 1 else "0",
        "base_cost_per_m": ropt.base_cost_per_m,
        "mode": "exact",
        "near_optimal_ratio": NEAR_OPTIMAL_RATIO,
        "headline": headline,
        "groups": groups,
    }
    return out, summary


def _summaries(paths: Sequence[EvaluatedPath]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for group in dict.fromkeys(p.group for p in paths):
        members = [p for p in paths if p.group == group]
        s: dict[str, Any] = {"n": len(members), "mean_length_m": float(np.mean([p.length_m for p in members]))}
        if members[0].rrpi is not None:  # RRPI is measured for every path or for none
            rrpis = [(p.rrpi, len(p.pixels)) for p in members if p.rrpi is not None]
            s["mean_rrpi"] = float(np.mean([v for v, _ in rrpis]))
            s["mean_rrpi_per_pixel"] = float(np.mean([v / n for v, n in rrpis]))
        measured = [p.hausdorff for p in members if p.hausdorff is not None]
        if any(p.references is not None for p in members):
            s["n_hausdorff"] = len(measured)
        if measured:
            s["mean_hausdorff_paper"] = float(np.mean([h.paper for h in measured]))
            s["mean_hausdorff_normalised"] = float(np.mean([h.normalised for h in measured]))
            s["mean_hausdorff_m"] = float(np.mean([h.hausdorff_m for h in measured]))
        out[group] = s
    return out


def _hausdorff_summary(
    paths: Sequence[EvaluatedPath], references: Sequence[VectorLine], symmetric: bool, grid: Grid
) -> dict[str, Any]:
    """How many paths matched a reference pair, per group, and the headline figure: the mean
    normalised Hausdorff over the matched given paths, else reference-end plans, else sampled
    pairs (the first group with a match)."""
    matched = {}
    for group in dict.fromkeys(p.group for p in paths if p.group != "reference"):
        members = [p for p in paths if p.group == group]
        matched[group] = {"matched": sum(p.hausdorff is not None for p in members), "paths": len(members)}
    out: dict[str, Any] = {
        "references": [line.name for line in references],
        "kind": "symmetric" if symmetric else "directed",
        "sample_step_m": min(grid.pixel_size_m()) / 4.0,
        "endpoint_tolerance_m": endpoint_tolerance_m(grid),
        "matched": matched,
    }
    for group in ("given", "reference-ends", "sampled"):
        members = [p for p in paths if p.group == group and p.hausdorff is not None]
        if members:
            break
    else:
        out.update({"paths": None, "n": 0, "headline": None, "mean_paper_normalised": None, "mean_normalised": None})
        return out
    measured = [p.hausdorff for p in members if p.hausdorff is not None]  # all of them (above)
    out.update(
        {
            "paths": group,
            "n": len(members),
            "n_paths": matched[group]["paths"],
            "headline": "mean_paper_normalised",
            "mean_paper_normalised": float(np.mean([h.paper for h in measured])),
            "mean_normalised": float(np.mean([h.normalised for h in measured])),
            "mean_m": float(np.mean([h.hausdorff_m for h in measured])),
            "mean_point_distance_m": float(np.mean([h.mean_m for h in measured])),
        }
    )
    return out


# --- the stage: paths and masks -> metrics, plots, report ---
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
