"""Locate, coarse: text-prompted segmentation over overlapping tiles, by a registered segmenter.

For each entity (name, linear|areal, text prompts) the segmenter predicts a probability map;
tiles are read in windows, predicted in batches and blended seam-free by the tiling engine
(:func:`overseec_core.locate.tiling.stream_predict`: reader, model and blend-and-write stages overlap)
straight into ``probs.tif`` (one float32 band per entity, NaN nodata) and ``masks.tif`` (uint8, 1
where the probability reaches the entity's threshold, 255 nodata), both on the input's grid.

The segmenter is picked by name from the registry (:mod:`overseec_core.locate.segmenters`:
``clipseg``, the default and the paper's; ``boxes+sam``; ``semantic``); whichever it is, its
loaded form is the batch predictor the engine drives, so tiling, blending, devices, the Dask path
and the writers here are the same for all. With ``gsd`` the segmenter runs at another ground
resolution and its outputs land on the image's grid (:mod:`overseec_core.locate.gsd`, a wrapper
around the same batch predictor). With ``dask_scheduler`` the batches run on a cluster
(:mod:`overseec_core.locate.dask`), each worker loading the segmenter by name.
"""

from __future__ import annotations

import os
import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from overseec_core import defaults, runfiles
from overseec_core.errors import InputError
from overseec_core.io.read import RasterSource
from overseec_core.io.write import RasterWriter
from overseec_core.limits import check_pixels
from overseec_core.locate.dask import Cluster, SegmenterSpec, segment_on_dask
from overseec_core.locate.entities import (
    MASK_NODATA,
    check_tile_options,
    entities_tag,
    prepare_out_dir,
    threshold_masks,
    threshold_of,
    validate_entities,
)
from overseec_core.locate.gsd import Resampling, check_resampling, parse_gsd, plan_resampling, resampled
from overseec_core.locate.models import ModelRef, describe_device
from overseec_core.locate.segmenters import DEFAULT_SEGMENTER, get_backend
from overseec_core.locate.segmenters.base import LoadedSegmenter
from overseec_core.locate.tiling import StreamStats, TileGrid, stream_predict, writer_sink
from overseec_core.progress import Progress
from overseec_core.schema import Entity

if TYPE_CHECKING:
    from overseec_core.locate.refine import RefineResult

#: Smallest image side the segmenter accepts (CLIPSeg patches are 16 px).
MIN_IMAGE_SIDE = 16


@dataclass(frozen=True)
class SegmentOptions:
    """Settings of the coarse segmentation; None means 'the sensible default for this input'.

    ``segmenter`` names the backend (the registry's); ``model`` its model (hub id, folder or, for
    backends that take one, a file), None for the backend's own default. ``clipseg_model`` is the
    CLIPSeg model as the older callers name it (``--clipseg-model``, the plugin's setting): used
    by the ``clipseg`` segmenter when ``model`` is None, ignored by the others. ``sam_model``,
    ``box_threshold`` and ``max_boxes`` are the ``boxes+sam`` backend's (None: its defaults).
    ``gsd`` is the processing resolution in ground metres per pixel, ``"auto"`` for the
    segmenter's trained one (native when it names none), None for the image's own; with it the tile
    side follows from the model's input size and ``tile_size`` is not used.
    """

    segmenter: str = DEFAULT_SEGMENTER
    model: str | None = None
    clipseg_model: str | None = None
    tile_size: int = defaults.TILE_SIZE
    overlap: int | None = None  # default: defaults.overlap_for(tile_size), an eighth of a tile
    model_size: int | None = None  # default: the checkpoint's input size (352)
    batch_size: int | None = None  # default: 4 on CPU, 16 on GPU
    device: str = defaults.DEVICE
    precision: str = "auto"
    blend: str = "hann"
    prompt_template: str = "{}"
    bands: str | Sequence[int] | None = None
    assume_crs: str | None = None
    dask_scheduler: str | None = None
    compile: bool = False  # torch.compile the encoder and decoder layers (pays off on long GPU runs)
    gsd: float | str | None = None  # processing resolution (m/px), "auto", or None: native
    # boxes+sam only (None: the backend's defaults; the other segmenters ignore them)
    sam_model: str | None = None  # the SAM that turns boxes into masks (default facebook/sam-vit-base)
    box_threshold: float | None = None  # detector score a box needs (default: the detector family's)
    max_boxes: int | None = None  # boxes kept per entity and tile, best first

    def resolved_overlap(self, tile_size: int | None = None) -> int:
        """The tile overlap: ``overlap``, else an eighth of ``tile_size`` (default: ``self.tile_size``)."""
        tile = self.tile_size if tile_size is None else tile_size
        return defaults.overlap_for(tile) if self.overlap is None else int(self.overlap)

    def resolved_model(self) -> str | None:
        """The model the segmenter is asked for: ``model``, else ``clipseg_model`` for CLIPSeg,
        else None (the backend's default)."""
        if self.model:
            return str(self.model)
        if self.segmenter == "clipseg" and self.clipseg_model:
            return str(self.clipseg_model)
        return None


@dataclass(frozen=True)
class SegmentResult:
    """What the stage wrote and how: the manifest records :meth:`to_json`."""

    probs_path: Path
    masks_path: Path
    entities: tuple[Entity, ...]
    thresholds: tuple[float, ...]
    model: ModelRef
    device: str
    precision: str
    tile_size: int
    overlap: int
    model_size: int
    batch_size: int
    tiles: int
    tiles_skipped: int
    encoder_calls: int
    timings: dict[str, float] = field(default_factory=dict)
    dask_scheduler: str | None = None
    segmenter: str = DEFAULT_SEGMENTER
    gsd: dict | None = None  # the processing resolution (Resampling.to_json), None: native

    def to_json(self) -> dict:
        return {
            "segmenter": self.segmenter,
            "gsd": self.gsd,
            "probs": str(self.probs_path),
            "masks": str(self.masks_path),
            "entities": [e.to_json() for e in self.entities],
            "thresholds": list(self.thresholds),
            "model": self.model.to_json(),
            "device": self.device,
            "precision": self.precision,
            "tile_size": self.tile_size,
            "overlap": self.overlap,
            "model_size": self.model_size,
            "batch_size": self.batch_size,
            "tiles": self.tiles,
            "tiles_skipped": self.tiles_skipped,
            "encoder_calls": self.encoder_calls,
            "dask_scheduler": self.dask_scheduler,
            "timings_s": {k: round(v, 3) for k, v in self.timings.items()},
        }


def mask_sink(probs_writer: RasterWriter, masks_writer: RasterWriter, thresholds: Sequence[float]):
    """A row sink writing blended probabilities and their thresholded masks in one pass."""
    probs_sink = writer_sink(probs_writer)
    tau = np.asarray(thresholds, np.float32)[:, None, None]

    def sink(rows: np.ndarray, row_off: int) -> None:
        masks_writer.write(threshold_masks(rows, tau), row_off)
        probs_sink(rows, row_off)  # last: it may modify the rows in place

    return sink


def _predict_on_dask(
    src, segmenter: LoadedSegmenter, spec: SegmenterSpec, sink, tiles, channels, options, flush_rows, progress
):
    """The tiles as tasks on the cluster: each worker loads the segmenter ``spec`` names."""
    assert options.dask_scheduler is not None
    with Cluster(options.dask_scheduler, options.device) as cluster:
        stats = segment_on_dask(
            src, cluster, spec, sink, tiles, channels, options.blend, segmenter.state.size, flush_rows, progress
        )
        return stats, cluster.device_label, stats.tiles - stats.tiles_skipped


def _predict_here(src, segmenter: LoadedSegmenter, sink, tiles, channels, options, flush_rows, progress):
    """The tiles through the tiling engine in this process."""
    stats = stream_predict(
        src,
        segmenter,
        sink,
        tiles,
        channels,
        blend=options.blend,
        batch_size=segmenter.state.size,
        flush_rows=flush_rows,
        progress=progress,
        stage="segment",
    )
    return stats, describe_device(segmenter.device), int(segmenter.encoder_calls)


def segment_image(
    image: str | os.PathLike,
    entities: Sequence[Entity],
    out_dir: str | os.PathLike,
    options: SegmentOptions = SegmentOptions(),
    progress: Progress | None = None,
) -> SegmentResult:
    """Coarse per-entity probabilities and masks of ``image`` into ``out_dir``.

    The segmenter ``options.segmenter`` names (the registry's; an unknown or absent one fails
    before anything is read) predicts; writes ``probs.tif`` and ``masks.tif`` atomically (nothing
    under the final names on error or cancellation). With ``options.dask_scheduler`` the tiles run
    on a dask.distributed cluster.
    """
    t_start = time.perf_counter()
    ents = validate_entities(entities)
    backend = get_backend(options.segmenter)
    parse_gsd(options.gsd)  # a bad --gsd fails before anything is read
    if options.gsd is None:
        check_tile_options(options.tile_size, options.resolved_overlap())
    thresholds = tuple(threshold_of(e) for e in ents)
    out = prepare_out_dir(out_dir, image)
    with RasterSource(image, bands=options.bands, assume_crs=options.assume_crs) as src:
        grid = src.grid
        if min(grid.width, grid.height) < MIN_IMAGE_SIDE:
            raise InputError(
                f"{image} is {grid.width}x{grid.height} px; segmentation needs at "
                f"least {MIN_IMAGE_SIDE} px on each side"
            )
        check_pixels(grid.width, grid.height, image, "image")
        t0 = time.perf_counter()
        segmenter: LoadedSegmenter = backend.load(options.resolved_model(), ents, options)
        t_load = time.perf_counter() - t0
        resampling, tile_size = _processing_resolution(options, segmenter, grid)
        segmenter = resampled(segmenter, resampling)
        overlap = options.resolved_overlap(tile_size)
        check_tile_options(tile_size, overlap)
        tiles = TileGrid(grid.width, grid.height, tile_size, overlap)
        if progress is not None:
            progress.message(
                f"segment: {segmenter.describe()}, {len(tiles)} tiles of {tile_size} px, {len(ents)} entities"
            )
        tags = {
            "OVERSEEC_STAGE": "segment",
            "OVERSEEC_ENTITIES": entities_tag(ents),
            "OVERSEEC_SEGMENTER": options.segmenter,
            "OVERSEEC_MODEL": segmenter.ref.name,
        }
        t0 = time.perf_counter()
        names = [e.name for e in ents]
        with (
            RasterWriter(
                out / runfiles.PROBS,
                grid,
                len(ents),
                "float32",
                nodata=float("nan"),
                descriptions=names,
                tags=tags,
                inputs=[image],
            ) as pw,
            RasterWriter(
                out / runfiles.MASKS,
                grid,
                len(ents),
                "uint8",
                nodata=MASK_NODATA,
                descriptions=names,
                tags=tags,
                inputs=[image],
            ) as mw,
        ):
            sink = mask_sink(pw, mw, thresholds)
            if options.dask_scheduler:
                # workers load what the client loaded: the same model, batch and input size
                spec = SegmenterSpec(
                    options.segmenter,
                    options.resolved_model(),
                    ents,
                    replace(
                        options,
                        batch_size=segmenter.state.size,
                        model_size=segmenter.model_size,
                        dask_scheduler=None,
                        gsd=None,
                    ),
                    resampling,
                )
                run = _predict_on_dask(src, segmenter, spec, sink, tiles, len(ents), options, pw.block_rows, progress)
            else:
                run = _predict_here(src, segmenter, sink, tiles, len(ents), options, pw.block_rows, progress)
        stats, device_label, encoder_calls = run
        t_tiles = time.perf_counter() - t0
    return SegmentResult(
        probs_path=out / runfiles.PROBS,
        masks_path=out / runfiles.MASKS,
        entities=ents,
        thresholds=thresholds,
        model=segmenter.ref,
        device=device_label,
        precision=segmenter.precision,
        tile_size=tile_size,
        overlap=overlap,
        model_size=segmenter.model_size,
        batch_size=segmenter.state.size,
        tiles=stats.tiles,
        tiles_skipped=stats.tiles_skipped,
        encoder_calls=encoder_calls,
        timings=_timings(t_start, t_load, t_tiles, stats, getattr(segmenter, "timings", None) or {}),
        dask_scheduler=options.dask_scheduler,
        segmenter=options.segmenter,
        gsd=None if resampling is None else resampling.to_json(),
    )


def _processing_resolution(options: SegmentOptions, segmenter: LoadedSegmenter, grid) -> tuple[Resampling | None, int]:
    """The resampling ``options.gsd`` asks for (None: native) and the native tile side that goes
    with it (``options.tile_size`` when native). The image's ground resolution comes from its grid
    (ground metres, also for geographic CRSs); the segmenter's trained one from its ``gsd_m``."""
    if options.gsd is None:
        return None, options.tile_size
    resampling = plan_resampling(options.gsd, getattr(segmenter, "gsd_m", None), grid.pixel_size_m())
    if resampling is None:  # auto, and the segmenter names no resolution: native
        return None, options.tile_size
    return resampling, check_resampling(resampling, segmenter.model_size, grid.width, grid.height)


def _timings(t_start: float, t_load: float, t_tiles: float, stats: StreamStats, extra: dict[str, float]) -> dict:
    """The stage's timings: loading (with the backend's own phases, e.g. text embeddings), tiles
    and each tile stage's busy time."""
    return {
        "load_model": t_load,
        **extra,
        "tiles": t_tiles,
        "predict": stats.seconds_predicting,
        "read": stats.seconds_reading,
        "blend_write": stats.seconds_blending,
        "total": time.perf_counter() - t_start,
    }


@dataclass(frozen=True)
class LocateResult:
    """The Locate stage as the pipeline runs it: coarse, refined (or None) and the manifest."""

    segment: SegmentResult
    refine: RefineResult | None
    manifest: Path | None = None

    def to_json(self) -> dict:
        return {
            "segment": self.segment.to_json(),
            "refine": None if self.refine is None else self.refine.to_json(),
            "manifest": None if self.manifest is None else str(self.manifest),
        }


__all__ = [
    "LocateResult",
    "MIN_IMAGE_SIDE",
    "SegmentOptions",
    "SegmentResult",
    "mask_sink",
    "segment_image",
]
