"""`overseec segment`: per-entity probabilities and masks (CLIPSeg or another segmenter), refined with SAM.

    overseec segment IMAGE --entity road:linear --entity "baseball field:areal" --out DIR
    overseec segment IMAGE --entities-json interpretation.json --out DIR --no-refine
    overseec segment IMAGE --default-entities --threshold road=0.5 --device cuda --out DIR
    overseec segment IMAGE --entity car --segmenter boxes+sam --model /models/owlv2 --out DIR

With --vectors the masks (refined over coarse) are also written as polygons, masks.gpkg (one
layer per entity, as `overseec vectorize DIR` writes it), in the same all-or-nothing write.

Writes into DIR: probs.tif (float32, one band per entity named after it, NaN nodata) and
masks.tif (uint8: 1 at or above the entity's threshold, 255 nodata); with refinement also
refined_probs.tif, refined_masks.tif and gated.tif (refined probability x refined mask, what the
cost stage reads); and manifest.json (inputs, entities, models and revisions, device, settings,
timings). Thresholds default to 0.4 for linear and 0.8 for areal entities.

--segmenter picks the coarse segmenter (clipseg by default; `--help` lists them all) and --model its
model (default: that segmenter's own, `overseec models list` shows them; --clipseg-model is
--model for clipseg). --gsd M runs the segmenter at M ground metres per pixel (auto: the model's
own resolution) and writes the outputs on the image's grid. Models load from a hub id in the local
Hugging Face cache or a local directory and are never downloaded here: use `overseec models
download NAME` on a machine with network first.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from overseec_core import defaults, runfiles
from overseec_core.commands import print_json, recorded_args
from overseec_core.commands.options import (
    add_read_options,
    add_refiner_options,
    add_segmenter_options,
    add_tile_size_option,
    segmenter_settings,
    whole_number,
)
from overseec_core.errors import InputError
from overseec_core.interpret.entity_input import load_entities_json, parse_entity
from overseec_core.locate.models import DEVICE_CHOICES, PRECISIONS
from overseec_core.locate.segmenters import SEGMENTERS
from overseec_core.progress import Progress
from overseec_core.schema import DEFAULT_ENTITIES, Entity

if TYPE_CHECKING:
    from overseec_core.locate.refine import RefineOptions
    from overseec_core.locate.segment import SegmentOptions


def parse_threshold(text: str) -> tuple[str, float]:
    """'road=0.5' -> ('road', 0.5)."""
    name, sep, value = text.rpartition("=")
    try:
        number = float(value)
    except ValueError:
        number = float("nan")
    if not sep or not name.strip() or not 0.0 < number < 1.0:
        raise InputError(f"--threshold {text!r}: expected NAME=VALUE with 0 < VALUE < 1 (e.g. road=0.5)")
    return name.strip(), number


_positive, _non_negative = whole_number(1), whole_number(0)


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `segment` subcommand: the image, output folder, entities and model options."""
    p = sub.add_parser(
        "segment",
        help="find entities in an image: CLIPSeg (or another segmenter) masks refined by SAM",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("image", metavar="IMAGE", help="GeoTIFF or any GDAL raster")
    p.add_argument("--out", type=Path, required=True, metavar="DIR", help="output folder (created)")
    what = p.add_argument_group("entities")
    what.add_argument(
        "--entity",
        action="append",
        default=[],
        metavar="ENTITY[:linear|areal]",
        help="an entity to find (repeatable); without a geometry, the interpreter's "
        "(road, trail: linear; grass, tree: areal; areal if unknown)",
    )
    what.add_argument(
        "--entities-json",
        type=Path,
        metavar="FILE",
        help="entities as JSON (a list, or `overseec interpret --json` output)",
    )
    what.add_argument(
        "--default-entities",
        action="store_true",
        help="add the default set: " + ", ".join(n for n, _ in DEFAULT_ENTITIES),
    )
    what.add_argument(
        "--threshold",
        action="append",
        default=[],
        metavar="ENTITY=VALUE",
        help="binarisation threshold of an entity, 0 < VALUE < 1 (default linear 0.4, areal 0.8; repeatable)",
    )
    what.add_argument(
        "--prompt-template",
        default="{}",
        metavar="TEXT",
        help='text around each prompt, e.g. "aerial view of {}" (default: the bare name)',
    )
    seg = p.add_argument_group("coarse segmentation")
    add_segmenter_options(seg)
    seg.add_argument(
        "--clipseg-model",
        metavar="ID|DIR",
        help=f"--model for the clipseg segmenter (default {SEGMENTERS['clipseg'].default_model})",
    )
    add_tile_size_option(seg)
    seg.add_argument("--overlap", type=_non_negative, metavar="PX", help="tile overlap (default tile/8)")
    seg.add_argument(
        "--model-size",
        type=_positive,
        metavar="PX",
        help="model input side; tiles are resized to it (default: the model's, 352 for CLIPSeg)",
    )
    seg.add_argument(
        "--batch-size",
        type=_positive,
        metavar="N",
        help="tiles per batch (default 4 on CPU, 16 on GPU; halved on GPU out-of-memory)",
    )
    ref = p.add_argument_group("refinement (SAM, SAM-HQ or SAM 2)")
    ref.add_argument("--no-refine", action="store_true", help="skip SAM refinement")
    add_refiner_options(ref)
    ref.add_argument(
        "--sam-overlap",
        type=_non_negative,
        metavar="PX",
        help="overlap of SAM's native tiles (default 1/16 of its input size: 64 px)",
    )
    ref.add_argument(
        "--sam-iterations",
        type=_positive,
        default=2,
        metavar="N",
        help="SAM passes per component, each prompted by the last (default 2)",
    )
    ref.add_argument(
        "--sam-min-area",
        type=_positive,
        default=256,
        metavar="PX",
        help="components smaller than this keep their coarse mask (default 256)",
    )
    ref.add_argument(
        "--sam-max-components",
        type=_positive,
        default=8,
        metavar="N",
        help="components refined per entity per SAM tile, largest first (default 8)",
    )
    ref.add_argument(
        "--sam-batch-size", type=_positive, metavar="N", help="SAM tiles per encoder call (default 1 on CPU, 4 on GPU)"
    )
    ref.add_argument(
        "--sam-decoder-batch",
        type=_positive,
        metavar="N",
        help="components per SAM mask-decoder call, across an encoder batch (default 4 on CPU, 64 on GPU; "
        "lower it to save GPU memory)",
    )
    run_ = p.add_argument_group("compute")
    run_.add_argument(
        "--device",
        default=defaults.DEVICE,
        metavar="DEVICE",
        help=f"where models run: {', '.join(DEVICE_CHOICES)} (default auto: CUDA, then MPS, then CPU)",
    )
    run_.add_argument(
        "--precision", default="auto", choices=PRECISIONS, help="auto: bf16/fp16 autocast on GPU, fp32 on CPU"
    )
    run_.add_argument(
        "--compile",
        action="store_true",
        help="torch.compile the encoders (the first tiles pay the compilation; pays off on long GPU runs)",
    )
    run_.add_argument(
        "--dask-scheduler", metavar="ADDRESS", help="run tiles on a dask.distributed cluster (e.g. tcp://10.0.0.5:8786)"
    )
    add_read_options(p)
    p.add_argument(
        "--vectors",
        action="store_true",
        help=f"also write the masks as polygons, DIR/{runfiles.MASK_POLYGONS} (one layer per entity)",
    )
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(func=run)


def entities_from_args(args: argparse.Namespace) -> list[Entity]:
    """The entities of --entity, --entities-json and --default-entities (defaults not already
    named), with the --threshold overrides applied."""
    from overseec_core.locate.entities import apply_thresholds

    entities = [parse_entity(t) for t in args.entity]
    if args.entities_json is not None:
        entities += load_entities_json(args.entities_json)
    if args.default_entities:
        have = {e.name.lower() for e in entities}
        entities += [Entity(n, g) for n, g in DEFAULT_ENTITIES if n not in have]
    overrides = dict(parse_threshold(t) for t in args.threshold)
    return list(apply_thresholds(entities, overrides)) if overrides else entities


def stage_options(args: argparse.Namespace) -> tuple[SegmentOptions, RefineOptions | None]:
    """The Locate options the command line asks for: the segmenter's, and SAM's (None with --no-refine)."""
    from overseec_core.locate.entities import PROMPT_TEMPLATES
    from overseec_core.locate.prompts import RefineParams
    from overseec_core.locate.refine import RefineOptions
    from overseec_core.locate.segment import SegmentOptions

    options = SegmentOptions(
        segmenter=args.segmenter,
        model=args.model,
        clipseg_model=args.clipseg_model,
        tile_size=args.tile_size,
        overlap=args.overlap,
        model_size=args.model_size,
        batch_size=args.batch_size,
        device=args.device,
        precision=args.precision,
        compile=args.compile,
        prompt_template=PROMPT_TEMPLATES.get(args.prompt_template, args.prompt_template),
        bands=args.bands,
        assume_crs=args.assume_crs,
        dask_scheduler=args.dask_scheduler,
        **segmenter_settings(args),
    )
    if args.no_refine:
        return options, None
    refine = RefineOptions(
        refiner=args.refiner,
        sam_model=args.sam_model,
        overlap=args.sam_overlap,
        batch_size=args.sam_batch_size,
        device=args.device,
        precision=args.precision,
        compile=args.compile,
        bands=args.bands,
        assume_crs=args.assume_crs,
        dask_scheduler=args.dask_scheduler,
        params=RefineParams(
            iterations=args.sam_iterations,
            min_area=args.sam_min_area,
            max_components=args.sam_max_components,
            decoder_batch=args.sam_decoder_batch,
        ),
    )
    return options, refine


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `segment` (locate.stage.run_segment: probabilities and masks, refined by SAM unless
    --no-refine, and a manifest in --out); prints the outputs and timings (or the JSON)."""
    from overseec_core.io.transaction import output_transaction
    from overseec_core.locate.entities import validate_entities
    from overseec_core.locate.stage import run_segment

    entities = validate_entities(entities_from_args(args))
    options, refine = stage_options(args)
    with output_transaction(progress):  # --vectors: polygons and rasters are kept together or not at all
        result = run_segment(args.image, entities, args.out, options, refine, progress, recorded_args(args))
        polygons = write_vectors(args, progress) if args.vectors else None
    if args.json:
        print_json(args, {**result.to_json(), "vectors": None if polygons is None else polygons.to_json()})
        return 0
    seg = result.segment
    print(
        f"segment  {seg.segmenter} ({seg.model.name}): {len(seg.entities)} entities, {seg.tiles} tiles "
        f"({seg.tiles_skipped} without data) on {seg.device} in {seg.timings['total']:.1f} s"
    )
    print(f"         {seg.probs_path}")
    print(f"         {seg.masks_path}")
    if result.refine is not None:
        r = result.refine
        print(
            f"refine   {r.refiner} on {r.stats.tiles_sam} of {r.tiles} tiles ({r.stats.components_refined} "
            f"components) in {r.timings['total']:.1f} s"
        )
        for path in (r.refined_probs_path, r.refined_masks_path, r.gated_path):
            print(f"         {path}")
    if polygons is not None:
        count = sum(layer.polygons for layer in polygons.layers)
        print(f"vectors  {count} polygons in {len(polygons.layers)} layers in {polygons.seconds:.1f} s")
        print(f"         {polygons.out}")
    print(f"manifest {result.manifest}")
    return 0


def write_vectors(args: argparse.Namespace, progress: Progress):
    """``--vectors``: the folder's masks (refined over coarse) as polygons in ``masks.gpkg``
    (``locate.vectors.vectorize_folder``, the same code as `overseec vectorize`)."""
    from overseec_core.locate.vectors import vectorize_folder

    out = Path(args.out)
    return vectorize_folder(out, out / runfiles.MASK_POLYGONS, progress=progress, command_args=recorded_args(args))
