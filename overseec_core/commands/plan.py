"""`overseec plan`: a least-cost path on a costmap between points given in any CRS.

    overseec plan costmap.tif --start 500010 3999990 --goal 500480 3999600 --out path.geojson
    overseec plan costmap.tif --crs EPSG:4326 --start 15.0001 36.1 --via 15.002 36.099 \\
                  --goal 15.004 36.098 --out path.geojson --mode fast --native-crs --pixels

Points are X Y in the costmap's CRS unless --crs names another (x = longitude for EPSG:4326).
Step cost = (mean of the two cells' costs + --base-cost-per-m) x step length in metres; lethal
cells (the lethal sidecar, cost >= --lethal-threshold, nodata) are impassable. --mode exact
(default) finds the optimal path; --mode fast plans coarse-to-fine in a corridor and reports a
guaranteed lower bound on the optimal cost next to its own.

Writes RFC 7946 GeoJSON (WGS 84 lon/lat, pixel centres) with the cost, length, mode, bound,
costmap, prompt and waypoints; --native-crs adds PATH.native.gpkg in the costmap's CRS (opens
in QGIS with the full CRS); --pixels adds PATH.pixels.csv (row, col, x, y, cumulative cost) for
other planners; --cumulative OUT.tif the cost-distance raster from the start.

--dem FILE [--slope-model tobler|vehicle] plans on terrain (anisotropic): the DEM is
resampled onto the costmap grid and each step costs (mean of its cells' costs + base) x its 3D
length x f(slope), slope = climb / ground length, signed, so A -> B and B -> A differ. tobler
(default): Tobler's hiking function as a multiplier of flat ground, exp(3.5 (|s + 0.05| - 0.05));
vehicle (a design choice): 1 + 10 s uphill, 1 + 5 (|s| - 0.15) below -15 %, no step steeper than
50 %. length_m counts the climb (length_2d_m: on the map); cells without elevation are
impassable; fast mode runs the exact search; not with --smooth, --pairs or --matrix.

--smooth [TOL] replaces the staircase by straight line-of-sight segments between the route's
own pixel centres (start, vias and goal stay vertices) that touch no impassable cell and cost at
most TOL more than the grid route (default 0.01 = 1 %; "2%" works too), costs taken as the exact
integral over the cells each segment crosses. The GeoJSON/GeoPackage line is then the smoothed
one, with the grid route's figures in its `grid_route` property; --pixels keeps the grid route.

Many routes, one costmap load: --pairs FILE (a CSV with start_x,start_y,goal_x,goal_y and an
optional id, in --crs or the costmap's CRS; or a vector layer of lines from start to goal) plans
one route per pair into --out ROUTES.gpkg (layer "routes", costmap CRS: id, total_cost,
length_m, mode, error for a pair that could not be planned). --matrix OUT.csv --points FILE
(x,y[,id] or a point layer) writes the cost of the best route between every two points;
--sources FILE prices from its points to --points instead (one-to-many). One search per source.

    overseec plan costmap.tif --pairs pairs.csv --out routes.gpkg
    overseec plan costmap.tif --points depots.csv --matrix costs.csv

--json prints the path's properties under the names the GeoJSON uses (total_cost, length_m,
n_pixels, ... of the route written; with --smooth the smoothed one, plus grid_route and
smoothing), with outputs, timings and the planner's expanded count. Output folders are created.
No output may be named manifest.json (the folder's record), and a damaged manifest.json in the
--out folder (not a UTF-8 JSON object) is refused before anything is written: move it away.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from overseec_core import defaults
from overseec_core.commands import output_folders, print_json, recorded_args
from overseec_core.commands.options import (
    add_costmap_read_options,
    add_mode_option,
    add_neighbours_option,
    add_point_options,
)
from overseec_core.progress import Progress


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `plan` subcommand: the costmap, start, vias and goal, mode, costs and outputs."""
    from overseec_core.plan.smooth import DEFAULT_TOLERANCE, tolerance_arg

    p = sub.add_parser(
        "plan",
        help="plan a least-cost path on a costmap (GeoJSON out)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "costmap", type=Path, metavar="COSTMAP", help="costmap GeoTIFF (float costs in [0, 1], NaN = nodata)"
    )
    add_point_options(p, "the costmap's", note="needed without --pairs")
    p.add_argument(
        "--out",
        type=Path,
        metavar="FILE",
        help="GeoJSON file to write (WGS 84; missing folders are created); with --pairs the routes GeoPackage",
    )
    p.add_argument(
        "--pairs",
        type=Path,
        metavar="FILE",
        help="plan one route per start/goal pair: CSV start_x,start_y,goal_x,goal_y[,id] or a layer of lines",
    )
    p.add_argument(
        "--matrix",
        type=Path,
        metavar="FILE",
        help="write the route cost between the --points (or from --sources to --points) as CSV",
    )
    p.add_argument("--points", type=Path, metavar="FILE", help="points of the --matrix: CSV x,y[,id] or a point layer")
    p.add_argument(
        "--sources", type=Path, metavar="FILE", help="the --matrix's rows (default: the --points): one-to-many"
    )
    add_mode_option(p)
    p.add_argument(
        "--native-crs", action="store_true", help="also write the path in the costmap's CRS (OUT.native.gpkg)"
    )
    p.add_argument(
        "--native-out",
        type=Path,
        metavar="FILE",
        help="where to write the native-CRS GeoPackage, FILE.gpkg (implies --native-crs)",
    )
    p.add_argument("--pixels", action="store_true", help="also write the path's pixel indices (OUT.pixels.csv)")
    p.add_argument(
        "--pixels-out",
        type=Path,
        metavar="FILE",
        help="where to write the pixel indices, CSV or JSON by suffix (implies --pixels)",
    )
    p.add_argument(
        "--cumulative",
        type=Path,
        metavar="FILE",
        help="write the cost-distance raster from the start to FILE.tif (float32, NaN unreachable)",
    )
    add_costmap_read_options(p)
    p.add_argument(
        "--smooth",
        nargs="?",
        const=DEFAULT_TOLERANCE,
        type=tolerance_arg,
        metavar="TOL",
        help="straighten the route by line-of-sight shortcuts costing at most TOL more "
        f"(fraction or percentage; default {DEFAULT_TOLERANCE:g} = 1 %%)",
    )
    add_neighbours_option(p)
    p.add_argument(
        "--dem",
        type=Path,
        metavar="FILE",
        help="plan on terrain: a DEM (any CRS and resolution, resampled onto the costmap grid); steps "
        "cost their 3D length times a slope multiplier (--slope-model), uphill and downhill differ, "
        "length_m counts the climb; cells without elevation are impassable (needs the compiled kernel)",
    )
    p.add_argument(
        "--slope-model",
        choices=defaults.SLOPE_MODELS,
        help="with --dem: tobler (Tobler's hiking function, default) or vehicle (1 + 10 x grade uphill, "
        "braking below -15 %%, no steps steeper than 50 %%)",
    )
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(func=run)


def options_from_args(args: argparse.Namespace):
    """The PlanOptions of the parsed arguments: points in order (start, vias, goal), and the
    optional native-CRS and pixel outputs at their default names when asked for without a file."""
    from overseec_core.plan.stage import PlanOptions, default_outputs

    extra = default_outputs(args.out)
    native = args.native_out or (extra["native"] if args.native_crs else None)
    pixels = args.pixels_out or (extra["pixels"] if args.pixels else None)
    points = (tuple(args.start), *(tuple(v) for v in args.via), tuple(args.goal))
    return PlanOptions(
        costmap=args.costmap,
        points=points,
        out=args.out,
        crs=args.crs,
        mode=args.mode,
        base_cost_per_m=args.base_cost_per_m,
        lethal=args.lethal,
        lethal_threshold=args.lethal_threshold,
        native_out=native,
        pixels_out=pixels,
        cumulative_out=args.cumulative,
        band=args.band,
        overrides=tuple(args.override),
        smooth=args.smooth,
        neighbours=args.neighbours,
        dem=args.dem,
        slope_model=args.slope_model,
    )


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `plan` (plan.stage.run_plan: the route GeoJSON and the optional extra outputs, recorded
    in the folder's manifest); prints cost, mode, length and the written files (or the JSON)."""
    from overseec_core.errors import InputError
    from overseec_core.io.manifest import check_output_name, check_run_folder
    from overseec_core.plan.stage import run_plan

    if args.pairs is not None or args.matrix is not None:
        refuse_terrain_for_pairs(args)
        return run_pairs_command(args, progress)
    if args.start is None or args.goal is None or args.out is None:
        raise InputError("plan needs --start X Y, --goal X Y and --out FILE (or --pairs FILE / --matrix FILE)")
    if args.points is not None or args.sources is not None:
        raise InputError("--points/--sources go with --matrix OUT.csv")
    options = options_from_args(args)
    command_args = recorded_args(args)
    for file in (options.out, options.native_out, options.pixels_out, options.cumulative_out):
        if file is not None:
            check_output_name(file)
    check_run_folder(Path(options.out).parent)  # its manifest records the plan
    with output_folders(options.out, options.native_out, options.pixels_out, options.cumulative_out):
        done = run_plan(options, progress, command_args=command_args)
    if args.json:
        print_json(args, done.to_json())
        return 0
    r = done.result
    quality = "optimal" if r.mode == "exact" else f"the optimal cost is >= {r.bound:.6g}"
    climb = "" if options.dem is None else f" ({done.properties['length_2d_m']:.1f} m on the map)"
    print(
        f"path: cost {r.cost:.6g} ({r.mode} mode; {quality}), {r.length_m:.1f} m{climb}, "
        f"{len(r.pixels)} pixels, {r.seconds:.2f} s"
    )
    if done.smoothed is not None:
        print(smoothed_line(done.smoothed))
    for note in r.notes:
        print(f"note: {note}")
    for kind, path in done.outputs.items():
        print(f"{kind}: {path}")
    return 0


def refuse_terrain_for_pairs(args: argparse.Namespace) -> None:
    """One-line InputError for --dem/--slope-model with --pairs/--matrix (their planner, in
    plan.pairs, has no slope model: refused rather than silently planned flat)."""
    from overseec_core.errors import InputError

    if args.dem is not None or args.slope_model is not None:
        raise InputError("--dem/--slope-model plan one route (--start/--goal); --pairs and --matrix do not take them")


def smoothed_line(s) -> str:
    """One line comparing the smoothed route with the grid route (both cell-integral costs)."""
    return (
        f"smoothed: cost {s.cost:.6g} vs grid {s.grid_cost_integral:.6g} ({s.cost_change:+.2%}, "
        f"tolerance {s.tolerance:.3g}; cell-integral rule, grid planner cost {s.grid_cost:.6g}), "
        f"{s.length_m:.1f} m vs {s.grid_length_m:.1f} m, {len(s.vertices)} vertices vs "
        f"{s.grid_vertices}, {s.seconds:.2f} s"
    )


#: Options of a single route that --pairs / --matrix do not take.
SINGLE_ROUTE_ONLY = ("start", "goal", "via", "native_crs", "native_out", "pixels", "pixels_out", "cumulative", "smooth")


def run_pairs_command(args: argparse.Namespace, progress: Progress) -> int:
    """`plan --pairs` / `--matrix` (plan.pairs.run_pairs): the routes GeoPackage and/or the cost
    matrix CSV from one costmap load; prints one line per route (or the JSON)."""
    from overseec_core.errors import InputError
    from overseec_core.io.manifest import check_output_name, check_run_folder
    from overseec_core.plan.pairs import PairsOptions, run_pairs

    given = [name for name in SINGLE_ROUTE_ONLY if getattr(args, name) not in (None, False, [])]
    if given:
        flags = ", ".join("--" + name.replace("_", "-") for name in given)
        raise InputError(f"{flags}: single-route options; --pairs/--matrix plan many routes without them")
    options = PairsOptions(
        costmap=args.costmap,
        pairs=args.pairs,
        out=args.out,
        points=args.points,
        sources=args.sources,
        matrix_out=args.matrix,
        crs=args.crs,
        mode=args.mode,
        base_cost_per_m=args.base_cost_per_m,
        neighbours=args.neighbours,
        lethal=args.lethal,
        lethal_threshold=args.lethal_threshold,
        band=args.band,
        overrides=tuple(args.override),
    )
    targets = options.targets()
    for file in targets.values():
        check_output_name(file)
        check_run_folder(Path(file).parent)
    with output_folders(*targets.values()):
        done = run_pairs(options, progress, command_args=recorded_args(args))
    if args.json:
        print_json(args, done.to_json())
        return 0
    for route in done.routes:
        r = route.result
        print(route.error if r is None else f"pair {route.pair.id}: cost {r.cost:.6g}, {r.length_m:.1f} m ({r.mode})")
    if done.routes:
        print(f"routes: {len(done.routes) - done.failed} planned, {done.failed} without a route")
    if done.matrix is not None:
        print(f"matrix: {done.matrix.shape[0]} x {done.matrix.shape[1]} costs")
    for note in done.notes:
        print(f"note: {note}")
    for kind, path in done.outputs.items():
        print(f"{kind}: {path}")
    return 0
