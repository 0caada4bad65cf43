"""`overseec eval`: the paper's metrics, plots and a report for a costmap, paths and masks.

    overseec eval --labels GT.tif --classes classes.json --ranks road=1,grass=2 \\
                  --costmap C.tif --pairs 50 --seed 0 --out DIR

samples N start-goal pairs uniformly over passable cells (seeded), plans each, and reports per-pair
length, cost and RRPI, the KDE centre of mass of (length, RRPI) and a linear fit. With --ranks each
path is also compared with the rank-optimal route between its ends (RRPI ratio). --reference adds
the Hausdorff distance to human-drawn paths, for paths (of --paths, else planned between each
reference's ends) whose start and goal match a reference's ends; --masks adds IoU per class.
Writes metrics.json, report.md, pairs.csv, paths.geojson and PNG plots (paths in map coordinates)
into DIR.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from overseec_core import defaults, runfiles
from overseec_core.commands import print_json, recorded_args
from overseec_core.commands.options import add_mode_option
from overseec_core.errors import InputError
from overseec_core.progress import Progress


def _separation(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected metres, not {text!r}") from None


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `eval` subcommand: ground truth, the costmap and paths to evaluate, and the outputs."""
    p = sub.add_parser(
        "eval",
        help="evaluate: RRPI, KDE centre of mass, Hausdorff, IoU, plots, report",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--out", required=True, type=Path, metavar="DIR", help="output folder (created if missing)")
    g = p.add_argument_group("ground truth")
    g.add_argument(
        "--labels", type=Path, metavar="FILE", help="ground-truth class raster (integer ids) on the costmap grid"
    )
    g.add_argument("--classes", type=Path, metavar="FILE", help="classes.json: class id -> name")
    g.add_argument(
        "--ranks",
        metavar="CLASS=RANK,...",
        help="rank per class, 1 = most preferred: road=1,grass=2,... (names or ids)",
    )
    g.add_argument(
        "--unranked-rank",
        default="max",
        metavar="max|N",
        help="rank of classes left out of --ranks, background and nodata (default: the largest rank)",
    )
    s = p.add_argument_group("paths")
    s.add_argument("--costmap", type=Path, metavar="FILE", help="costmap GeoTIFF to plan on")
    s.add_argument(
        "--pairs", type=int, default=50, metavar="N", help="start-goal pairs to sample and plan (default 50; 0: none)"
    )
    s.add_argument("--seed", type=int, default=0, metavar="N", help="seed of the pair sampler (default 0)")
    s.add_argument(
        "--min-separation",
        type=_separation,
        metavar="METRES",
        help="least straight-line distance between start and goal (default: 20%% of the map diagonal)",
    )
    s.add_argument(
        "--pair-draw",
        choices=defaults.PAIR_DRAWS,
        default=defaults.PAIR_DRAWS[0],
        help="where pairs are drawn: over passable cells, --min-separation apart (default), or uniformly "
        "over the whole image as the paper draws its 50 pairs (pairs on impassable cells are unreachable)",
    )
    add_mode_option(s)
    s.add_argument(
        "--paths", type=Path, metavar="FILE", help="evaluate these paths (LineStrings, any vector format and CRS)"
    )
    s.add_argument(
        "--reference", type=Path, metavar="FILE", help="human-drawn reference paths for the Hausdorff distance"
    )
    s.add_argument(
        "--symmetric",
        action="store_true",
        help="symmetric Hausdorff distance (default: directed, from each path to the references)",
    )
    m = p.add_argument_group("segmentation")
    m.add_argument(
        "--masks",
        type=Path,
        metavar="FILE",
        help="masks raster (one band per entity, named) or a class raster, for IoU",
    )
    m.add_argument(
        "--match",
        action="append",
        default=[],
        metavar="CLASS=BAND",
        help="pair a ground-truth class with a mask band of another name, e.g. 'road=paved road' "
        "(repeatable; several bands for one class are merged)",
    )
    m.add_argument(
        "--mask-threshold",
        type=float,
        metavar="VALUE",
        help="mask value counted as positive (default: > 0 for integer masks, >= 0.5 for float)",
    )
    o = p.add_argument_group("plots")
    o.add_argument("--image", type=Path, metavar="FILE", help="image to draw under the costmap and paths")
    o.add_argument("--no-plots", action="store_true", help="write no PNG plots")
    o.add_argument(
        "--plot-size",
        type=int,
        default=1600,
        metavar="PX",
        help="longest side of rasters read for plots (default 1600)",
    )
    p.add_argument("--json", action="store_true", help=f"print {runfiles.EVALUATION_FILES['metrics']} on stdout")
    p.set_defaults(func=run)


def options_from_args(args: argparse.Namespace):
    """EvaluateOptions from parsed arguments."""
    from overseec_core.evaluate import EvaluateOptions

    if args.plot_size < 64:
        raise InputError(f"--plot-size must be at least 64 px, not {args.plot_size}")
    return EvaluateOptions(
        out_dir=args.out,
        labels=args.labels,
        classes=args.classes,
        ranks=args.ranks,
        unranked_rank=args.unranked_rank,
        costmap=args.costmap,
        pairs=args.pairs,
        seed=args.seed,
        min_separation_m=args.min_separation,
        pair_draw=args.pair_draw,
        plan_mode=args.mode,
        reference=args.reference,
        paths=args.paths,
        symmetric=args.symmetric,
        masks=args.masks,
        matches=tuple(args.match),
        mask_threshold=args.mask_threshold,
        image=args.image,
        plots=not args.no_plots,
        plot_size=args.plot_size,
    )


def summary_lines(metrics: dict) -> list[str]:
    """The headline figures, one per line."""
    lines = []
    s = metrics.get("sampling")
    if s:
        lines.append(
            f"pairs: {s['planned']} planned of {s['drawn']} drawn, {len(s['unreachable'])} unreachable"
            + (f", {s['rules_not_met']} could not keep a keep-out rule" if s.get("rules_not_met") else "")
        )
    kde = metrics.get("kde")
    if kde:
        lines.append(f"KDE centre of mass: length {kde['com']['length_m']:.1f} m, RRPI {kde['com']['rrpi']:.2f}")
    fit = metrics.get("fit")
    if fit:
        sign = "-" if fit["intercept"] < 0 else "+"
        lines.append(
            f"fit: RRPI = {fit['slope']:.4g} x length_m {sign} {abs(fit['intercept']):.4g} (r = {fit['r']:.3f})"
        )
    for group, g in metrics.get("summary", {}).items():
        extra = f", mean RRPI {g['mean_rrpi']:.2f}" if "mean_rrpi" in g else ""
        lines.append(f"{group} paths: {g['n']}, mean length {g['mean_length_m']:.1f} m{extra}")
    ro = metrics.get("rank_optimal")
    if ro and ro.get("headline"):
        g = ro["groups"][ro["headline"]]
        median = "inf" if g["median_ratio"] is None else f"{g['median_ratio']:.3f}"
        worst = "inf" if g["worst_ratio"] is None else f"{g['worst_ratio']:.3f}"
        lines.append(
            f"RRPI / rank-optimal ({ro['headline']} paths, n={g['n']}): median {median}, "
            f"{100 * g['share_within_5pct']:.0f}% within 5%, worst {worst}"
        )
    h = metrics.get("hausdorff")
    if h and h.get("mean_normalised") is not None:
        lines.append(
            f"mean Hausdorff ({h['kind']}, {h['n']} of {h.get('n_paths', h['n'])} {h['paths']} paths "
            f"matched a reference): {h['mean_normalised']:.4f} of the diagonal ({h['mean_m']:.1f} m)"
        )
    elif h:
        lines.append("Hausdorff: no path shares its start and goal with a reference path")
    iou = metrics.get("iou")
    if iou:
        per = ", ".join(f"{c['name']} {c['iou']:.3f}" for c in iou["classes"] if c["iou"] is not None)
        mean = "n/a" if iou["mean_iou"] is None else f"{iou['mean_iou']:.4f}"
        lines.append(f"mean IoU: {mean} ({per})")
    return lines


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `eval` (evaluate.stage.run_evaluate: metrics.json, report.md, pairs.csv, paths, plots in
    --out); prints the metric summary and the report's path (or the metrics as JSON)."""
    from overseec_core.evaluate.stage import run_evaluate

    options = options_from_args(args)
    command_args = recorded_args(args)
    result = run_evaluate(options, progress, command_args=command_args)
    if args.json:
        print_json(args, result.metrics, default=str)
        return 0
    for line in summary_lines(dict(result.metrics)):
        print(line)
    print(f"report: {result.files['report']}")
    return 0
