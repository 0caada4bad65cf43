"""`overseec export`: costmaps and paths in the formats robot and routing stacks read.

    overseec export costmap costmap.tif --to nav2 --out nav2/map.yaml [--nav2-mode scale]
    overseec export costmap costmap.tif --to costmap2d --out costmap2d.tif
    overseec export costmap costmap.tif --to npy --out arrays/cost.npy
    overseec export path path.geojson --to gpx --out path.gpx
    overseec export path path.geojson --to kml --out path.kml
    overseec export path path.geojson --to csv --out path.csv                    (costmap's CRS)
    overseec export path path.geojson --to csv --frame nav2 --nav2-yaml nav2/map.yaml --out p.csv
    overseec export path RUN/ROUTES.gpkg --layer paths_costmap --to gpx --out path.gpx         (the plugin's)

Costmaps: the lethal sidecar is found as `plan` finds it (or --lethal); lethal and keep-out cells
are occupied / 254 / +inf, no data is unknown / 255 / NaN. nav2 writes map.yaml and map.pgm
(trinary: free/occupied/unknown) or map.png (scale: the costs as occupancy 0..99, lethal 100);
the map's local frame has (0, 0) at the costmap's lower-left corner unless --local-origin X Y
(CRS coordinates) says otherwise, and the YAML records it with the CRS. Nav2 needs a projected,
north-up grid with square pixels; anything else is refused with the gdalwarp command to run.
costmap2d writes uint8 costmap_2d values on the same grid (cost c -> round(252 c)); npy writes
X.npy (float32), X.flags.npy and X.json (transform, CRS, pixel size, encodings).

Paths: the GeoJSON `plan` writes (WGS 84), or any line layer GDAL reads in any CRS (the plugin's
route GeoPackage keeps one table per costmap: name it with --layer). CSV rows are path,index,x,y,length_m,cost in the
costmap's CRS (the costmap the path names, or --costmap) or in a Nav2 map's local frame
(--nav2-yaml from `export costmap --to nav2`, or the same origin rule applied to the costmap).
Outputs never replace an input; the output folder's manifest.json records the export. No output
is named manifest.json, and a damaged manifest.json in the output folder (not a UTF-8 JSON
object) is refused before anything is written: move it away or choose another --out.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from overseec_core import formats, runfiles
from overseec_core.commands import output_folders, print_json, recorded_args
from overseec_core.commands.options import finite_number, whole_number
from overseec_core.progress import Progress


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `export` subcommand and its two verbs, `export costmap` and `export path`."""
    from overseec_core.interop import COSTMAP_FORMATS, FRAMES, NAV2_MODES, PATH_FORMATS

    p = sub.add_parser(
        "export",
        help="export a costmap (Nav2, costmap_2d, npy) or a path (GPX, KML, CSV)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    what = p.add_subparsers(dest="what", metavar="WHAT")
    what.required = True

    c = what.add_parser(
        "costmap",
        help="a costmap and its lethal sidecar",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    c.add_argument(
        "costmap", type=Path, metavar="COSTMAP", help="costmap GeoTIFF (float costs in [0, 1], NaN = nodata)"
    )
    c.add_argument("--to", choices=COSTMAP_FORMATS, required=True, help=f"output format: {formats.describe('costmap')}")
    c.add_argument(
        "--out",
        type=Path,
        required=True,
        metavar="FILE",
        help="MAP.yaml (nav2), FILE.tif (costmap2d) or FILE.npy (npy); missing folders are created",
    )
    c.add_argument(
        "--nav2-mode",
        choices=NAV2_MODES,
        default="trinary",
        help="trinary (default: PGM free/occupied/unknown, read alike by every ROS tool) "
        "or scale (PNG keeping the cost levels as occupancy 0..99)",
    )
    c.add_argument(
        "--local-origin",
        nargs=2,
        type=finite_number,
        metavar=("X", "Y"),
        help="CRS coordinates of the Nav2 map frame's (0, 0) (default: the costmap's lower-left corner)",
    )
    c.add_argument(
        "--lethal",
        type=Path,
        metavar="FILE",
        help=f"lethal mask GeoTIFF (default: the sidecar the costmap names, or {runfiles.LETHAL} beside it)",
    )
    c.add_argument("--band", type=whole_number(1), metavar="N", help="the costmap band to export")
    c.add_argument("--json", action="store_true", help="print the result as JSON")
    c.set_defaults(func=run_costmap)

    q = what.add_parser(
        "path",
        help=f"a planned path (GeoJSON from overseec plan, or a line layer, e.g. the plugin's {runfiles.PATHS_LAYER})",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    q.add_argument(
        "path",
        type=Path,
        metavar="PATH",
        help="path GeoJSON (WGS 84) as overseec plan writes it, or any line layer GDAL reads (GeoPackage ...)",
    )
    q.add_argument(
        "--layer",
        metavar="NAME",
        help=f"the layer of a file holding several (a {runfiles.PATHS_LAYER} table, e.g. paths_costmap)",
    )
    q.add_argument("--to", choices=PATH_FORMATS, required=True, help=f"output format: {formats.describe('path')}")
    q.add_argument(
        "--out", type=Path, required=True, metavar="FILE", help="file to write (missing folders are created)"
    )
    q.add_argument(
        "--frame",
        choices=FRAMES,
        default="crs",
        help="CSV coordinates: the costmap's CRS (default) or a Nav2 map's local frame",
    )
    q.add_argument(
        "--nav2-yaml",
        type=Path,
        metavar="FILE",
        help="the Nav2 map YAML (from export costmap --to nav2) whose frame --frame nav2 uses",
    )
    q.add_argument(
        "--costmap", type=Path, metavar="FILE", help="the path's costmap GeoTIFF (default: the one the path names)"
    )
    q.add_argument(
        "--local-origin",
        nargs=2,
        type=finite_number,
        metavar=("X", "Y"),
        help="--frame nav2 without --nav2-yaml: CRS coordinates of the frame's (0, 0)",
    )
    q.add_argument("--band", type=whole_number(1), metavar="N", help="the costmap band to sample")
    q.add_argument("--json", action="store_true", help="print the result as JSON")
    q.set_defaults(func=run_path)


def costmap_options(args: argparse.Namespace):
    """The CostmapExportOptions of the parsed `export costmap` arguments."""
    from overseec_core.interop import CostmapExportOptions

    origin = tuple(args.local_origin) if args.local_origin else None
    return CostmapExportOptions(
        costmap=args.costmap,
        to=args.to,
        out=args.out,
        lethal=args.lethal,
        band=args.band,
        nav2_mode=args.nav2_mode,
        local_origin=origin,
    )


def path_options(args: argparse.Namespace):
    """The PathExportOptions of the parsed `export path` arguments; an InputError when --frame or
    --nav2-yaml is given for a WGS 84 format (GPX, KML)."""
    from overseec_core.errors import InputError
    from overseec_core.interop import PathExportOptions

    if args.to != "csv" and (args.frame != "crs" or args.nav2_yaml is not None):
        raise InputError(f"--frame and --nav2-yaml apply to --to csv; {args.to.upper()} is WGS 84")
    origin = tuple(args.local_origin) if args.local_origin else None
    return PathExportOptions(
        path=args.path,
        layer=args.layer,
        to=args.to,
        out=args.out,
        frame=args.frame,
        nav2_yaml=args.nav2_yaml,
        costmap=args.costmap,
        band=args.band,
        local_origin=origin,
    )


def _check_output(out: Path) -> None:
    """Refuse, before any folder or file is made, a bookkeeping output name and a damaged
    manifest in the output folder (whose manifest records the export)."""
    from overseec_core.io.manifest import check_output_name, check_run_folder

    check_output_name(out)
    check_run_folder(Path(out).parent)


def run_costmap(args: argparse.Namespace, progress: Progress) -> int:
    """Run `export costmap` (interop.export_costmap: Nav2 map, costmap_2d GeoTIFF or npy);
    prints the cell counts and the written files (or the JSON)."""
    from overseec_core.interop import export_costmap

    options = costmap_options(args)
    _check_output(options.out)
    with output_folders(options.out):
        result = export_costmap(options, progress, command_args=recorded_args(args))
    if args.json:
        print_json(args, result.to_json())
        return 0
    n = result.counts
    print(
        f"{result.kind}: {n['passable']} passable, {n['lethal']} lethal "
        f"({n['keep_out']} keep-out), {n['nodata']} no-data cells"
    )
    for role, path in result.outputs.items():
        print(f"{role}: {path}")
    for note in result.notes:
        print(f"note: {note}")
    return 0


def run_path(args: argparse.Namespace, progress: Progress) -> int:
    """Run `export path` (interop.export_path: GPX, KML or CSV); prints the paths, points and
    output file (or the JSON)."""
    from overseec_core.interop import export_path

    options = path_options(args)
    _check_output(options.out)
    with output_folders(options.out):
        result = export_path(options, progress, command_args=recorded_args(args))
    if args.json:
        print_json(args, result.to_json())
        return 0
    frame = f" ({result.frame} frame)" if result.frame else ""
    print(f"{result.kind}{frame}: {result.paths} path(s), {result.points} points -> {result.out}")
    for note in result.notes:
        print(f"note: {note}")
    return 0
