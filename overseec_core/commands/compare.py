"""`overseec compare`: several prompts (or cost programs) on the same layers and points.

    overseec compare --labels gt.tif --classes classes.json \\
        --prompt "prefer roads" --prompt "prefer grass, avoid roads" \\
        --start 534010 5212990 --goal 534500 5212500 --out compare/
    overseec compare --masks RUN_DIR --prompt "stay on the trail" --program mine.program.txt \\
        --crs EPSG:4326 --start 15.0001 36.1 --goal 15.004 36.098 --out compare/ --mode fast

Each prompt or program (in the order given; --prompt and --program mix) gets its costmap,
lethal sidecar, program and route in its own folder, OUT/prompt_1/, OUT/prompt_2/ ..., made
exactly as `overseec costmap` and `overseec plan` make them. Then OUT/ receives:

  difference.tif  float32, band k-1 = cost of prompt k minus cost of prompt 1 (NaN = no data)
  compare.png     one panel per prompt: its costmap and route (other routes faint), scale bar
  compare.csv     per prompt: route length (m), cost, share of route pixels per class (with
  compare.json    --labels/--classes), Hausdorff distance (m) to every other route
  report.md       the same as a readable report, with the figure
  manifest.json   prompts, inputs (hashed), parameters, outputs

Layers are given as for `overseec costmap`; points as for `overseec plan` (--crs for another CRS).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from overseec_core.commands import print_json, recorded_args
from overseec_core.commands.options import (
    add_alias_option,
    add_block_size_option,
    add_entity_layer_options,
    add_mode_option,
    add_point_options,
    add_priors_options,
)
from overseec_core.progress import Progress


class _Candidate(argparse.Action):
    """Collect --prompt and --program into one list, in command-line order."""

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        items = list(getattr(namespace, self.dest, None) or [])
        items.append((self.const, values))
        setattr(namespace, self.dest, items)


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `compare` subcommand: entity layers, prompts, the planning points and outputs."""
    p = sub.add_parser(
        "compare",
        help="compare prompts: costmap and route per prompt, difference raster, side-by-side figure, route table",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_entity_layer_options(p, "entity layers (at least one; as for `overseec costmap`)")
    what = p.add_argument_group("what to compare (two or more, in order)")
    what.add_argument(
        "--prompt",
        dest="candidates",
        action=_Candidate,
        const="prompt",
        metavar="TEXT",
        help="a mission prompt, interpreted offline (repeatable)",
    )
    what.add_argument(
        "--program",
        dest="candidates",
        action=_Candidate,
        const="program",
        metavar="FILE",
        help="a cost program file (repeatable)",
    )
    add_alias_option(p)
    add_priors_options(p)
    pts = p.add_argument_group("points (the same route is planned on every costmap)")
    add_point_options(pts, "the layers'")
    add_mode_option(p)
    p.add_argument("--out", type=Path, required=True, metavar="DIR", help="output folder")
    add_block_size_option(p)
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(func=run, candidates=[])


def options_from_args(args: argparse.Namespace):
    """CompareOptions from the parsed arguments (validated by compare.check_options)."""
    from overseec_core.evaluate.compare import CompareOptions, make_candidates

    points: tuple = ()
    if args.start is not None or args.goal is not None or args.via:
        from overseec_core.errors import InputError

        if args.start is None or args.goal is None:
            raise InputError("give both --start X Y and --goal X Y")
        points = (tuple(args.start), *(tuple(v) for v in args.via), tuple(args.goal))
    return CompareOptions(
        out_dir=args.out,
        candidates=make_candidates(args.candidates),
        points=points,
        crs=args.crs,
        mode=args.mode,
        masks=args.masks,
        labels=args.labels,
        classes=args.classes,
        vectors=tuple(args.vector),
        grid=args.grid,
        line_width_m=args.line_width,
        block_size=args.block_size,
        aliases=tuple(args.alias),
        priors=args.priors,
        no_priors=args.no_priors,
    )


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `compare` (pipeline.run_compare: costmap and route per prompt, difference raster, figure);
    prints one line per route, the Hausdorff distances and the written files (or the JSON)."""
    from overseec_core.evaluate.compare import OTHER_CLASS
    from overseec_core.pipeline import run_compare

    options = options_from_args(args)
    result = run_compare(options, progress, command_args=recorded_args(args))
    if args.json:
        print_json(args, result.to_json())
        return 0
    for r in result.rows:
        share = ""
        if r.class_share:
            top = sorted(((v, k) for k, v in r.class_share.items() if k != OTHER_CLASS), reverse=True)[:3]
            share = "; " + ", ".join(f"{k} {100 * v:.0f}%" for v, k in top if v > 0)
        print(f"{r.name}: {r.length_m:.1f} m, cost {r.cost:.6g}{share}  <- {r.prompt}")
    for pair in result.pairs():
        print(f"hausdorff {pair['a']} - {pair['b']}: {pair['hausdorff_m']:.1f} m")
    for note in result.notes:
        print(f"note: {note}")
    for kind, path in result.files.items():
        print(f"{kind}: {path}")
    return 0
