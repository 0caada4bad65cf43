"""`overseec vectorize`: masks as polygons, a GeoPackage with one layer per entity.

    overseec vectorize RUN_DIR --out RUN_DIR/masks.gpkg
    overseec vectorize --labels gt.tif --classes classes.json --out classes.gpkg --simplify 0.5

From a segment folder: the bands of refined_masks.tif (else masks.tif), named by their entity,
with each polygon's mean probability from the probabilities beside them. From a class raster:
one layer per class name of classes.json (background classes left out), probability 1. Each
polygon carries area_m2 (ground square metres, in any CRS), mean_prob and pixels; geometries
are in the raster's CRS, on the exact pixel edges unless --simplify gives a tolerance in ground
metres (topology preserved, geometries valid). The raster is read in strips of --block-rows
rows; polygons crossing strips are joined, so memory stays bounded on any image height. The
GeoPackage is written atomically and never over an input; manifest.json in its folder records it.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from overseec_core import runfiles
from overseec_core.commands import output_folders, print_json, recorded_args
from overseec_core.commands.options import non_negative_number, whole_number
from overseec_core.progress import Progress

#: Rows per strip (the core's default, spelled here so that `overseec vectorize --help` stays light).
DEFAULT_BLOCK_ROWS = 512


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `vectorize` subcommand: a segment folder or a class raster, the GeoPackage, options."""
    p = sub.add_parser(
        "vectorize",
        help="masks or a class raster as polygons (GeoPackage, one layer per entity)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "folder",
        type=Path,
        nargs="?",
        metavar="DIR",
        help=f"segment output folder holding {runfiles.REFINED_MASKS} or {runfiles.MASKS} (or give --labels)",
    )
    p.add_argument("--labels", type=Path, metavar="FILE", help="class raster (GeoTIFF of integer class ids)")
    p.add_argument("--classes", type=Path, metavar="FILE", help="classes.json of --labels: class id -> name")
    p.add_argument("--out", type=Path, required=True, metavar="FILE", help="the GeoPackage to write (.gpkg)")
    p.add_argument(
        "--simplify",
        type=non_negative_number,
        default=0.0,
        metavar="METRES",
        help="simplification tolerance in ground metres (default 0: exact pixel edges)",
    )
    p.add_argument(
        "--block-rows",
        type=whole_number(1),
        default=DEFAULT_BLOCK_ROWS,
        metavar="N",
        help=f"raster rows read at a time (default {DEFAULT_BLOCK_ROWS}); the polygons do not depend on it",
    )
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(func=run)


def _check_sources(args: argparse.Namespace) -> None:
    """Exactly one source: a folder, or --labels with --classes."""
    from overseec_core.errors import InputError

    if args.folder is not None and (args.labels is not None or args.classes is not None):
        raise InputError("give a segment folder or --labels/--classes, not both")
    if args.folder is None and args.labels is None:
        raise InputError("give a segment folder (DIR) or --labels FILE --classes FILE")
    if args.labels is not None and args.classes is None:
        raise InputError("--labels needs --classes (the classes.json naming its class ids)")
    if args.classes is not None and args.labels is None:
        raise InputError("--classes goes with --labels (the class raster it names)")


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `vectorize` (locate.vectors): prints one line per layer (or the JSON)."""
    from overseec_core.io.manifest import check_output_name, check_run_folder
    from overseec_core.locate import vectors

    _check_sources(args)
    check_output_name(args.out)
    check_run_folder(Path(args.out).parent)
    options = {"simplify_m": args.simplify, "block_rows": args.block_rows, "progress": progress}
    with output_folders(args.out):
        if args.folder is not None:
            source: vectors.Source = vectors.MaskFolderSource(args.folder)
        else:
            from overseec_core.synthesize.layers import load_class_entities  # the one classes.json reading

            source = vectors.ClassRasterSource(args.labels, load_class_entities(args.classes), args.classes)
        result = vectors.vectorize(source, args.out, command_args=recorded_args(args), **options)
    if args.json:
        print_json(args, result.to_json())
        return 0
    for layer in result.layers:
        print(f"{layer.name}: {layer.polygons} polygon(s), {layer.area_m2:.6g} m²")
    for warning in result.warnings:
        print(f"note: {warning}")
    print(f"wrote {result.out}")
    return 0
