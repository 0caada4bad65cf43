"""`overseec costmap`: entity layers + a prompt or a cost program -> costmap.tif.

    overseec costmap --masks RUN_DIR --prompt "prefer roads, avoid the water" --out costmap.tif
    overseec costmap --labels gt.tif --classes classes.json --program my.program.txt --out c.tif
    overseec costmap --masks RUN_DIR --vector road=osm_roads.gpkg --program p.txt --out c.tif

Layers come from the segment stage's folder (masks.tif/probs.tif, refined_* preferred), a class
raster with its classes.json, and/or vector layers rasterised onto the same grid; they can be
combined. Writes the costmap (float32 'cost' in [0, 1], lower = better, NaN = no data), a lethal
sidecar (uint8, 1 = impassable) and the program text (edit it and re-run with --program), and
updates manifest.json in the costmap's folder. Only mask files are read: re-prompting is seconds.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from overseec_core import runfiles
from overseec_core.commands import output_folders, print_json, recorded_args
from overseec_core.commands.options import (
    add_alias_option,
    add_block_size_option,
    add_entity_layer_options,
    add_priors_options,
    add_strict_option,
)
from overseec_core.errors import InputError
from overseec_core.progress import Progress


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `costmap` subcommand: entity layers, the prompt or cost program, and its options."""
    p = sub.add_parser(
        "costmap",
        help="compose a costmap from masks and a prompt or cost program",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_entity_layer_options(p, "entity layers (at least one)")
    p.add_argument(
        "--dem",
        type=Path,
        metavar="FILE",
        help="elevation raster (any CRS and resolution; metres unless the file says feet), resampled "
        "onto the grid: programs read slope (degrees) and roughness (metres); a prompt's costmap gets "
        "slopes above 15 degrees costlier, 30 and steeper 1.0",
    )
    prog = p.add_mutually_exclusive_group(required=True)
    prog.add_argument("--prompt", metavar="TEXT", help="mission prompt, interpreted offline")
    prog.add_argument("--program", type=Path, metavar="FILE", help="cost program file")
    add_alias_option(p)
    add_priors_options(p)
    add_strict_option(p)
    p.add_argument(
        "--override",
        type=Path,
        action="append",
        default=[],
        metavar="FILE",
        help="operator corrections applied after the program: polygons (any OGR "
        "format and CRS) with cost (0..1), lethal=1 or prefer=1 (repeatable)",
    )
    p.add_argument(
        "--out",
        type=Path,
        required=True,
        metavar="FILE",
        help=f"costmap GeoTIFF to write ({runfiles.LETHAL} and the program go beside it; missing folders are created)",
    )
    add_block_size_option(p)
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(func=run)


def options_from_args(args: argparse.Namespace):
    """The CostmapOptions of the parsed arguments; an InputError when no entity layer is given."""
    from overseec_core.synthesize.options import CostmapOptions

    if args.masks is None and args.labels is None and args.classes is None and not args.vector:
        raise InputError("no entity layers: give --masks DIR, --labels L --classes C, or --vector")
    return CostmapOptions(
        out=args.out,
        masks=args.masks,
        labels=args.labels,
        classes=args.classes,
        vectors=tuple(args.vector),
        grid=args.grid,
        prompt=args.prompt,
        program=args.program,
        line_width_m=args.line_width,
        block_size=args.block_size,
        aliases=tuple(args.alias),
        priors=args.priors,
        no_priors=args.no_priors,
        overrides=tuple(args.override),
        dem=args.dem,
        strict=args.strict,
    )


def _terrain_line(terrain: dict) -> str:
    """The DEM's line of the summary: which fields the program read, and the cells left without elevation."""
    if not terrain["used"]:
        return f"dem      {terrain['dem']}  (not used: the program reads neither slope nor roughness)"
    missing = terrain["missing_pixels"]
    gap = (
        f", {missing} cells ({100.0 * terrain['missing_fraction']:.3g} %) without elevation: nodata" if missing else ""
    )
    return f"dem      {terrain['dem']}  ({', '.join(terrain['fields'])}; elevations in {terrain['unit']}{gap})"


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `costmap` (pipeline.run_costmap: writes the costmap, lethal sidecar and program in --out);
    prints its paths, mean cost and lethal share (or the JSON)."""
    from overseec_core.pipeline import run_costmap

    options = options_from_args(args)
    command_args = recorded_args(args)
    with output_folders(options.out):
        result = run_costmap(options, progress, command_args=command_args)
    if args.json:
        print_json(args, result.to_json())
        return 0
    lethal = 100.0 * result.lethal_pixels / result.valid_pixels if result.valid_pixels else 0.0
    mean = "n/a" if result.mean_cost is None else f"{result.mean_cost:.3f}"
    keep_out = 100.0 * result.keep_out_pixels / result.valid_pixels if result.valid_pixels else 0.0
    rules = f", keep-out {keep_out:.1f}%" if result.keep_out_pixels else ""
    print(f"costmap  {result.costmap}  (mean cost {mean}, lethal {lethal:.1f}%{rules} of valid pixels)")
    print(f"lethal   {result.lethal}")
    if result.terrain:
        print(_terrain_line(result.terrain))
    if result.overrides:
        cells = result.overrides["cells"]
        print(
            f"override {', '.join(result.overrides['files'])}  ({cells['lethal']} cells made "
            f"lethal, {cells['cost']} given a cost, {cells['unblocked']} unblocked)"
        )
    print(
        f"program  {result.program_file}  ({result.program_source}; entities: {', '.join(result.entities) or 'none'})"
    )
    return 0
