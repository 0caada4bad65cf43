"""`overseec demo`: the whole pipeline on the bundled sample scene.

Interprets the sample's mission prompt, builds the costmap, plans from the sample's start to its
goal and evaluates (RRPI over random pairs, Hausdorff to the reference route). Masks come from the
sample's known class raster unless --segment is given: segmentation needs CLIPSeg and SAM weights,
which no step here downloads (`overseec models download` on a machine with network, then
--segment, or --clipseg-model/--sam-model DIR).

The sample ships with every install (inside the package; resources/sample in a checkout), so the
demo needs no models, no network and no checkout; --sample DIR runs it on a scene written by
`overseec sample --out DIR` instead.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from overseec_core.errors import InputError
from overseec_core.locate.refiners import DEFAULT_REFINER, refiner_names
from overseec_core.progress import Progress


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `demo` subcommand: output folder, prompt, and whether to segment with the models."""
    p = sub.add_parser(
        "demo",
        help="run the pipeline on the bundled sample scene",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "--out", type=Path, default=Path("runs/demo"), metavar="DIR", help="run directory (default runs/demo)"
    )
    p.add_argument("--prompt", metavar="TEXT", help="another mission for the sample (default: the sample's own)")
    p.add_argument(
        "--segment",
        action="store_true",
        help="segment with CLIPSeg + SAM instead of using the known labels (needs weights)",
    )
    p.add_argument(
        "--clipseg-model", metavar="ID|DIR", help="with --segment: the CLIPSeg model (hub id in the cache, or a folder)"
    )
    p.add_argument(
        "--sam-model", metavar="ID|DIR", help="with --segment: the refiner's model (hub id in the cache, or a folder)"
    )
    p.add_argument(
        "--refiner",
        choices=refiner_names(),
        default=DEFAULT_REFINER,
        help="with --segment: the refiner of the masks (default %(default)s)",
    )
    p.add_argument(
        "--pairs", type=int, default=20, metavar="N", help="random start/goal pairs the evaluation plans (default 20)"
    )
    p.add_argument(
        "--sample",
        type=Path,
        metavar="DIR",
        help="a sample scene written by `overseec sample --out DIR` (default: the one shipped with overseec)",
    )
    p.set_defaults(func=run)


def find_scene(folder: Path | None):
    """The scene to run on: ``folder`` (--sample) or the shipped one; InputError saying what to do."""
    from overseec_core.install import detect
    from overseec_core.sample import PACKAGE_SAMPLE, bundled_sample, scene_in

    if folder is not None:
        scene = scene_in(folder)
        if scene is None:
            raise InputError(
                f"{folder} holds no complete sample scene (sample.tif, sample_labels.tif, classes.json, "
                f"reference_route.geojson, sample.json); write one with `overseec sample --out {folder}`"
            )
        return scene
    scene = bundled_sample()
    if scene is None:
        raise InputError(
            f"the sample scene shipped with overseec is missing ({PACKAGE_SAMPLE}); put it back with "
            f"{detect().reinstall_advice()}, or write one with `overseec sample --out DIR` and run "
            "`overseec demo --sample DIR`"
        )
    return scene


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `demo`: the whole pipeline (pipeline.run_all) on the bundled sample scene into --out,
    with the sample's labels as masks unless --segment; prints the setup and the run's summary."""
    from dataclasses import replace

    from overseec_core.commands.run import print_summary
    from overseec_core.pipeline import PipelineOptions, run_all
    from overseec_core.plan import planner_backend

    scene = find_scene(args.sample)
    meta = json.loads(scene.meta.read_text(encoding="utf-8"))
    options = PipelineOptions(
        image=scene.image,
        prompt=args.prompt or meta["prompt"],
        out_dir=args.out,
        offline=True,
        points=(tuple(meta["start"]), tuple(meta["goal"])),
        reference=scene.reference,
        labels=None if args.segment else scene.labels,
        classes=scene.classes,
        pairs=args.pairs,
    )
    if args.segment:
        from overseec_core.locate.refine import RefineOptions
        from overseec_core.locate.segment import SegmentOptions

        seg, ref = SegmentOptions(), RefineOptions(refiner=args.refiner)
        if args.clipseg_model:
            seg = replace(seg, clipseg_model=args.clipseg_model)
        if args.sam_model:
            ref = replace(ref, sam_model=args.sam_model)
        options = replace(options, segment=seg, refine=ref, classes=None)
    size, pixel, crs = meta.get("size", 1024), meta.get("pixel_size_m", 0.5), meta.get("crs", "EPSG:32633")
    print(f"sample     {scene.image} ({size} x {size} px, {pixel:g} m, {crs})")
    print(f"prompt     {options.prompt}")
    print(
        "masks      "
        + (
            "CLIPSeg + SAM"
            if args.segment
            else f"the sample's known classes ({scene.labels.name}); --segment to use the models"
        )
    )
    print(f"planner    {planner_backend().describe()}")
    result = run_all(options, progress, {"command": "demo", "out": str(args.out)})
    print_summary(result)
    return 0
