"""`overseec demo`: the whole pipeline on the bundled sample scene.

Interprets the sample's mission prompt, builds the costmap, plans from the sample's start to its
goal and evaluates (RRPI over random pairs, Hausdorff to the reference route). Masks come from the
sample's known class raster unless --segment is given: segmentation needs CLIPSeg and SAM weights,
which no step here downloads (`overseec models download` on a machine with network, then
--segment, or --clipseg-model/--sam-model DIR).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from ..errors import InputError
from ..progress import Progress


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "demo",
        help="run the pipeline on the bundled sample scene",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "--out", type=Path, default=Path("runs/demo"), metavar="DIR", help="run directory (default runs/demo)"
    )
    p.add_argument("--prompt", help="another mission for the sample (default: the sample's own)")
    p.add_argument(
        "--segment",
        action="store_true",
        help="segment with CLIPSeg + SAM instead of using the known labels (needs weights)",
    )
    p.add_argument("--clipseg-model", metavar="ID|DIR")
    p.add_argument("--sam-model", metavar="ID|DIR")
    p.add_argument("--pairs", type=int, default=20)
    p.set_defaults(func=run)


def run(args: argparse.Namespace, progress: Progress) -> int:
    from dataclasses import replace

    from ..pipeline import PipelineOptions, run_all
    from ..sample import bundled_sample
    from .run import print_summary

    scene = bundled_sample()
    if scene is None:
        raise InputError(
            "the bundled sample is missing (resources/sample); make it with `overseec sample --out resources/sample`"
        )
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
        from ..locate.refine import RefineOptions
        from ..locate.segment import SegmentOptions

        seg, ref = SegmentOptions(), RefineOptions()
        if args.clipseg_model:
            seg = replace(seg, clipseg_model=args.clipseg_model)
        if args.sam_model:
            ref = replace(ref, sam_model=args.sam_model)
        options = replace(options, segment=seg, refine=ref, classes=None)
    print(f"sample     {scene.image} (1024 x 1024 px, 0.5 m, EPSG:32633)")
    print(f"prompt     {options.prompt}")
    print(
        "masks      "
        + (
            "CLIPSeg + SAM"
            if args.segment
            else f"the sample's known classes ({scene.labels.name}); --segment to use the models"
        )
    )
    result = run_all(options, progress, {"command": "demo", "out": str(args.out)})
    print_summary(result)
    return 0
