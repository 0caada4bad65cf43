"""`overseec run`: the whole pipeline, image + prompt -> masks, costmap, path and evaluation.

    overseec run IMAGE --prompt "prefer roads, avoid water" --start X Y --goal X Y --out DIR
    overseec run IMAGE --prompt "..." --labels GT.tif --classes classes.json --start X Y --goal X Y --out DIR

Stages run in order into one run directory (interpretation.json, probs/masks from CLIPSeg + SAM,
costmap.tif + lethal.tif + the cost program, path.geojson, evaluation/) whose manifest.json
records every input, parameter, model and timing. With --labels/--classes the masks come from
the class raster instead of segmentation (no model needed). Points are in the image's CRS unless
--crs names another.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from overseec_core import defaults
from overseec_core.commands import print_json, recorded_args
from overseec_core.commands.options import (
    add_alias_option,
    add_llm_options,
    add_mode_option,
    add_neighbours_option,
    add_point_options,
    add_priors_options,
    add_read_options,
    add_refiner_options,
    add_segmenter_options,
    add_strict_option,
    add_tile_size_option,
    add_vector_option,
    segmenter_settings,
)
from overseec_core.progress import Progress


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `run` subcommand: image, prompt, run folder, masks, segmentation, planning and
    evaluation options."""
    p = sub.add_parser(
        "run",
        help="run the whole pipeline on an image and a prompt",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("image", metavar="IMAGE", help="GeoTIFF or any GDAL raster")
    p.add_argument("--prompt", required=True, metavar="TEXT", help="the mission, in plain language")
    p.add_argument("--out", type=Path, required=True, metavar="DIR", help="run directory (created)")
    p.add_argument("--offline", action="store_true", help="use the offline interpreter (no LLM)")
    add_llm_options(p)
    masks = p.add_argument_group("masks (default: CLIPSeg + SAM segmentation; --segmenter picks another)")
    masks.add_argument("--labels", type=Path, metavar="FILE", help="class raster to use as masks instead of segmenting")
    masks.add_argument("--classes", type=Path, metavar="FILE", help="classes.json of --labels (id -> name)")
    add_alias_option(masks)
    add_priors_options(p)
    add_strict_option(p)
    p.add_argument(
        "--dem",
        type=Path,
        metavar="FILE",
        help="elevation raster (any CRS and resolution; metres unless the file says feet): slopes above "
        "15 degrees cost more, 30 degrees and steeper cost 1.0",
    )
    add_vector_option(masks, "an extra entity layer from vector data, e.g. road=roads.gpkg (repeatable)")
    add_segmenter_options(masks)
    masks.add_argument("--clipseg-model", metavar="ID|DIR", help="--model for the clipseg segmenter")
    add_refiner_options(masks)
    masks.add_argument("--no-refine", action="store_true", help="skip SAM refinement")
    add_tile_size_option(masks)
    masks.add_argument(
        "--device",
        default=defaults.DEVICE,
        metavar="DEVICE",
        help="where models run: auto, cpu, cuda, cuda:N or mps (default auto: CUDA, then MPS, then CPU)",
    )
    route = p.add_argument_group("route")
    add_point_options(route, "the image's")
    add_mode_option(route)
    add_neighbours_option(route)
    ev = p.add_argument_group("evaluation (with --labels or --reference)")
    ev.add_argument(
        "--ranks", metavar="CLASS=RANK,...", help="RRPI ranks, e.g. road=1,grass=2 (default: from the prompt)"
    )
    ev.add_argument("--reference", type=Path, metavar="FILE", help="reference paths (GeoJSON) for Hausdorff")
    ev.add_argument("--pairs", type=int, default=20, metavar="N", help="random start-goal pairs (default 20)")
    ev.add_argument("--seed", type=int, default=0, metavar="N", help="seed of the pair sampler (default 0)")
    ev.add_argument("--no-eval", action="store_true", help="skip evaluation")
    add_read_options(p)
    p.add_argument(
        "--json",
        action="store_true",
        help="print the result as JSON: the out folder, manifest, and each stage's --json document",
    )
    p.set_defaults(func=run)


def options_from_args(args: argparse.Namespace):
    """The PipelineOptions of the parsed arguments (segment and refine unless --labels); an
    InputError when only one of --start and --goal is given."""
    from overseec_core.pipeline import PipelineOptions

    points = []
    if args.start is not None and args.goal is not None:
        points = [tuple(args.start), *[tuple(v) for v in args.via], tuple(args.goal)]
    elif args.start is not None or args.goal is not None or args.via:
        from overseec_core.errors import InputError

        raise InputError("planning needs both --start and --goal")
    segment = refine = None
    if args.labels is None:
        from overseec_core.locate.refine import RefineOptions
        from overseec_core.locate.segment import SegmentOptions

        segment = SegmentOptions(
            segmenter=args.segmenter,
            model=args.model,
            clipseg_model=args.clipseg_model,
            tile_size=args.tile_size,
            device=args.device,
            **segmenter_settings(args),
        )
        if not args.no_refine:
            refine = RefineOptions(device=args.device, refiner=args.refiner, sam_model=args.sam_model)
    return PipelineOptions(
        image=Path(args.image),
        prompt=args.prompt,
        out_dir=args.out,
        points=tuple(points),
        points_crs=args.crs,
        bands=args.bands,
        assume_crs=args.assume_crs,
        offline=True if args.offline else None,
        llm_url=args.llm_url,
        llm_model=args.llm_model,
        llm_key_env=args.llm_key_env,
        llm_fallback_offline=args.llm_fallback_offline,
        labels=args.labels,
        classes=args.classes,
        vectors=tuple(args.vector),
        segment=segment,
        refine=refine,
        plan_mode=args.mode,
        plan_neighbours=args.neighbours,
        evaluate=not args.no_eval,
        ranks=args.ranks,
        reference=args.reference,
        pairs=args.pairs,
        seed=args.seed,
        aliases=tuple(args.alias),
        priors=args.priors,
        no_priors=args.no_priors,
        dem=args.dem,
        strict=args.strict,
    )


def print_summary(result) -> None:
    """What was made, where: one line per stage."""
    interp = result.interpretation
    ranked = ", ".join(
        f"{p.entity} {p.rank}" + (" (lethal)" if p.lethal else "")
        for p in sorted(interp.preferences, key=lambda p: p.rank)
    )
    print(f"interpret  {interp.source}: {ranked}")
    if interp.unparsed:  # (the costmap stage has warned once per clause on stderr)
        print(f"           not understood: {'; '.join(interp.unparsed)}")
    if result.masks is not None:
        print(f"segment    {result.masks}")
    c = result.costmap
    print(f"costmap    {c.costmap} (mean cost {c.mean_cost:.3f}, {c.lethal_pixels} lethal px)")
    print(f"program    {c.program_file}")
    if result.plan is not None:
        r = result.plan.result
        print(f"plan       {result.plan.outputs['geojson']} ({r.length_m:.1f} m, cost {r.cost:.3f}, {r.mode})")
    if result.evaluation is not None:
        files = result.evaluation.files
        print(f"evaluate   {files.get('report', files.get('metrics'))}")
    print(f"manifest   {result.manifest}")


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `run` (pipeline.run_all: interpret, segment, costmap, plan and evaluate into --out);
    prints the run's summary (or the JSON)."""
    from overseec_core.pipeline import run_all

    command_args = recorded_args(args)
    result = run_all(options_from_args(args), progress, command_args)
    if args.json:
        print_json(args, result.to_json(), default=str)
    else:
        print_summary(result)
    return 0
