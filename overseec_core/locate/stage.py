"""Locate's front door: an image and entities -> probability and mask rasters (a registered
segmenter, CLIPSeg by default, then SAM), with the run folder's manifest. torch/transformers are
imported only when a model runs.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import asdict
from typing import TYPE_CHECKING, TypeVar

from overseec_core.extras import require_extra
from overseec_core.io.manifest import RunDir
from overseec_core.io.transaction import transactional
from overseec_core.progress import Progress
from overseec_core.schema import Entity

if TYPE_CHECKING:  # annotations only: the model stages are imported where a model runs
    from overseec_core.locate.refine import RefineOptions
    from overseec_core.locate.segment import LocateResult, SegmentOptions

T = TypeVar("T")


# --- stage: segment ---
@transactional
def run_segment(
    image: str | os.PathLike,
    entities: Sequence[Entity],
    out_dir: str | os.PathLike,
    options: SegmentOptions | None = None,
    refine: RefineOptions | None = None,
    progress: Progress | None = None,
    command_args: dict | None = None,
) -> LocateResult:
    """Locate: the segmenter's probabilities and masks (``options.segmenter``, CLIPSeg by default),
    then (unless ``refine`` is None) SAM refinement, into ``out_dir`` with its manifest (image
    hash, entities, the segmenter and the models with revisions, device, tile settings, per-stage
    timings). torch/transformers are imported only when this runs."""
    require_extra("models", "segmentation (CLIPSeg and SAM)")
    if (options is not None and options.dask_scheduler) or (refine is not None and refine.dask_scheduler):
        require_extra("dask", "--dask-scheduler")
    # segment/refine/models: only when segmenting (re-prompting never loads them, nor torch)
    from overseec_core.locate.entities import validate_entities
    from overseec_core.locate.gsd import parse_gsd
    from overseec_core.locate.refine import check_refine_options, refine_image
    from overseec_core.locate.segment import LocateResult, SegmentOptions, segment_image
    from overseec_core.locate.segmenters import get_backend

    options = options or SegmentOptions()
    ents = validate_entities(entities)
    get_backend(options.segmenter)  # an unknown or absent segmenter fails before the run folder is made
    parse_gsd(options.gsd)  # so does a bad --gsd
    if refine is not None:
        check_refine_options(refine)  # a missing SAM fails now, not after the CLIPSeg pass
    run = RunDir(out_dir, command="segment", args=command_args)
    run.record_input("image", image)
    params = {"segment": {k: v for k, v in asdict(options).items() if k != "dask_scheduler"}}
    if refine is not None:
        params["refine"] = {k: v for k, v in asdict(refine).items() if k != "dask_scheduler"}
    run.update_parameters(**params)
    run.set("entities", [e.to_json() for e in ents])
    with run.stage("segment"):
        seg = segment_image(image, ents, run.path, options, progress)
    run.set("segment", seg.to_json())
    run.set("segmenter", seg.segmenter)
    models = {seg.segmenter: seg.model.to_json()}
    run.set("models", models)
    ref = None
    if refine is not None:
        from overseec_core.locate.models import release_models

        release_models()  # one model in memory at a time: the segmenter's go before SAM loads
        with run.stage("refine"):
            ref = refine_image(image, seg.probs_path, ents, run.path, refine, progress)
        run.set("refine", ref.to_json())
        run.set("models", {**models, "sam": ref.model.to_json()})
    run.save()
    return LocateResult(segment=seg, refine=ref, manifest=run.manifest_path)
