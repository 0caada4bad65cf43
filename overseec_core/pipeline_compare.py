"""The compare chain: several prompts or programs, each through the costmap chain and the planner,
then the difference raster, the figure and the tables -- what ``overseec compare`` runs
(``pipeline.run_compare`` is this module's; the comparisons themselves are
:mod:`overseec_core.evaluate.compare`'s).
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from overseec_core import runfiles
from overseec_core.errors import OverseecError
from overseec_core.evaluate import load_classes
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
from overseec_core.io.atomic import atomic_path, write_text_atomic
from overseec_core.io.manifest import RunDir, write_json_atomic
from overseec_core.io.read import read_grid
from overseec_core.io.transaction import output_transaction
from overseec_core.pipeline_costmap import run_costmap
from overseec_core.plan.stage import PlanOptions, run_plan
from overseec_core.progress import NullProgress, Progress, check_cancelled

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
