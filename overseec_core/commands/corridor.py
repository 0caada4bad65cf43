"""`overseec corridor`: the least-cost corridor between two points, as rasters on the costmap's grid.

    overseec corridor costmap.tif --start 500010 3999990 --goal 500480 3999600 --within 10 \\
                      --out corridor.tif
    overseec corridor costmap.tif --crs EPSG:4326 --start 15.0001 36.1 --goal 15.004 36.098 \\
                      --within 5% --out out/corridor.tif --mask-out out/near-optimal.tif

Every cell gets the cost of the best route from the start to the goal through it, divided by the
optimal route's cost: 1.0 on the optimal route (and any route as cheap), 1.1 where the best
route through the cell costs 10 % more, nodata where no route passes (lethal, nodata, cut off).
Written as a float32 GeoTIFF (--out) and, beside it, a uint8 mask of the cells within --within
percent of the optimum (1 = inside; OUT-within.tif unless --mask-out names it). Exact: two
whole-grid searches with the planner's own step rule (see `overseec plan`), so the optimum is
the exact route's cost.

Points are X Y in the costmap's CRS unless --crs names another. Lethal cells (the sidecar,
cost >= --lethal-threshold, nodata) are impassable, and so are keep-out zones: the corridor never
enters one. --override applies operator corrections in memory, as `overseec plan` does. The
output folder's manifest records the costmap, parameters and figures; --json prints them.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from overseec_core import runfiles
from overseec_core.commands import output_folders, print_json, recorded_args
from overseec_core.commands.options import add_costmap_read_options, add_point_options, finite_number
from overseec_core.progress import Progress


def percentage(text: str) -> float:
    """argparse type: a percentage > 0 ("10" or "10%")."""
    value = finite_number(text.strip().removesuffix("%"))
    if value <= 0:
        raise argparse.ArgumentTypeError(f"expected a percentage > 0, not {text!r}")
    return value


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `corridor` subcommand: costmap, start, goal, within, outputs and the planner's costs."""
    p = sub.add_parser(
        "corridor",
        help="least-cost corridor between two points (ratio + mask GeoTIFFs)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("costmap", type=Path, metavar="COSTMAP", help="costmap GeoTIFF (float costs, NaN = nodata)")
    add_point_options(p, "the costmap's", required=True, vias=False)
    p.add_argument(
        "--within",
        type=percentage,
        required=True,
        metavar="PCT",
        help="percentage over the optimum (10 or 10%%): the mask holds cells on routes at most PCT %% dearer",
    )
    p.add_argument(
        "--out",
        type=Path,
        required=True,
        metavar="FILE",
        help=f"ratio GeoTIFF to write, e.g. {runfiles.CORRIDOR} (missing folders are created)",
    )
    p.add_argument(
        "--mask-out",
        type=Path,
        metavar="FILE",
        help=f"mask GeoTIFF (uint8, 1 = within --within); default OUT{runfiles.CORRIDOR_MASK_SUFFIX} beside --out",
    )
    add_costmap_read_options(p)
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(func=run)


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `corridor` (plan.corridor.run_corridor); prints the optimum, the corridor's size and files."""
    from overseec_core.io.manifest import check_output_name, check_run_folder
    from overseec_core.plan.corridor import CorridorOptions, run_corridor

    options = CorridorOptions(
        costmap=args.costmap,
        start=tuple(args.start),
        goal=tuple(args.goal),
        within_pct=args.within,
        out=args.out,
        mask_out=args.mask_out,
        crs=args.crs,
        base_cost_per_m=args.base_cost_per_m,
        lethal=args.lethal,
        lethal_threshold=args.lethal_threshold,
        band=args.band,
        overrides=tuple(args.override),
    )
    for file in (options.out, options.mask_file):
        check_output_name(file)
    check_run_folder(Path(options.out).parent)
    with output_folders(options.out, options.mask_file):
        done = run_corridor(options, progress, command_args=recorded_args(args))
    if args.json:
        print_json(args, done.to_json())
        return 0
    c = done.corridor
    print(
        f"corridor: optimum {c.optimum:.6g}, {c.cells_within} cells within {args.within:g} % of it, {c.seconds:.2f} s"
    )
    for kind, path in done.outputs.items():
        print(f"{kind}: {path}")
    return 0
