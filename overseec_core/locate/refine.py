"""Locate, fine: SAM refinement of the coarse CLIPSeg masks, prompted as SAMRefiner does.

The refiner is a choice (``RefineOptions.refiner``, :mod:`overseec_core.locate.refiners`): SAM
(the paper's), SAM-HQ or SAM 2, each with its default checkpoint unless ``sam_model`` names one;
all run through the same code below (the differences live in :mod:`overseec_core.locate.sam`).

SAM is run on its own tile grid of native imagery: tiles of the model's input size (1024 px for
SAM ViT-B), never an upscaled smaller tile (the reference upscales 512 px tiles to 1024: four
times the encoder work per area). An image smaller than that is padded, as SAM's processor pads.
Tiles where no entity has a coarse mask worth refining skip SAM entirely; otherwise the image
embedding is computed once per tile and shared by every entity and component.

Per tile and entity, each connected component of the coarse mask is refined separately, largest
first, with points, a box and the coarse logits as prompts (:mod:`overseec_core.locate.prompts`),
fed back for a small number of iterations, stopping early for a component whose mask no longer
changes. Components under ``min_area`` pixels, and those beyond the ``max_components`` largest of
an entity in a tile, keep their coarse mask (SAM's 4 px mask cells cannot improve tiny ones).

Per entity the tile's refined probability is SAM's (max over components) inside the components'
context boxes and, elsewhere, the coarse probability recalibrated so that the entity's threshold
maps to 0.5; the refined mask is then ``refined probability >= 0.5`` everywhere. Overlapping SAM
tiles are blended by the tiling engine's :class:`~overseec_core.locate.tiling.StreamingBlender` (one band
per entity), rows stream into ``refined_probs.tif``, ``refined_masks.tif`` and ``gated.tif``
(P^tau = P * M, what the cost stage reads).

The tile loop overlaps three stages: a reader thread (:func:`overseec_core.locate.stages.pipeline`)
reads each group of tiles with its window of ``probs.tif`` and prepares the components and prompts
(CPU); the caller's thread runs SAM (or submits the group to Dask, several groups in flight); a
worker thread blends in tile order, thresholds and writes the rows
(:func:`overseec_core.locate.tiling.drive_in_order`).
"""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from overseec_core import defaults, runfiles
from overseec_core.errors import InputError, RasterError
from overseec_core.io.read import RasterSource, open_raster
from overseec_core.io.write import RasterWriter
from overseec_core.locate.dask import Cluster, ModelSpec, refine_task
from overseec_core.locate.entities import (
    MASK_NODATA,
    check_tile_options,
    entities_tag,
    prepare_out_dir,
    threshold_masks,
    threshold_of,
    validate_entities,
)
from overseec_core.locate.models import (
    ModelRef,
    describe_device,
    resolve_device,
    resolve_precision,
)
from overseec_core.locate.prompts import RefineParams, calibrate, needs_sam
from overseec_core.locate.refiners import DEFAULT_REFINER, get_refiner
from overseec_core.locate.sam import SamRefiner, TileStats, cancel_between_layers
from overseec_core.locate.sam_model import load_sam, resolve_refiner_model
from overseec_core.locate.stages import StageClock, lookahead, pipeline
from overseec_core.locate.tiling import (
    StreamingBlender,
    TileGrid,
    blend_weights,
    drive_in_order,
)
from overseec_core.progress import Progress
from overseec_core.schema import Entity

if TYPE_CHECKING:
    from rasterio.windows import Window


@dataclass(frozen=True)
class RefineOptions:
    """Settings of the SAM refinement."""

    sam_model: str | None = None  # the refiner's checkpoint (hub id or folder); None: the refiner's default
    overlap: int | None = None  # default: SAM input size // 16 (64 px of 1024: tiles are large)
    batch_size: int | None = None  # tiles per encoder call: 1 on CPU, 4 on GPU
    device: str = defaults.DEVICE
    precision: str = "auto"
    blend: str = "hann"
    params: RefineParams = RefineParams()
    bands: str | Sequence[int] | None = None
    assume_crs: str | None = None
    dask_scheduler: str | None = None
    compile: bool = False  # torch.compile SAM's image encoder (pays off on long GPU runs)
    refiner: str = DEFAULT_REFINER  # "sam", "sam-hq" or "sam2" (overseec_core.locate.refiners)

    @property
    def model_name(self) -> str:
        """The checkpoint this refinement runs: ``sam_model``, else the refiner's default."""
        return self.sam_model or get_refiner(self.refiner).default_model


@dataclass(frozen=True)
class RefineResult:
    """What refinement wrote and how: the manifest records :meth:`to_json`."""

    refined_probs_path: Path
    refined_masks_path: Path
    gated_path: Path
    model: ModelRef
    device: str
    precision: str
    tile_size: int
    overlap: int
    tiles: int
    tiles_nodata: int
    stats: TileStats
    params: RefineParams
    timings: dict[str, float] = field(default_factory=dict)
    batch_size: int = 1  # tiles per encoder call
    refiner: str = DEFAULT_REFINER

    def to_json(self) -> dict:
        return {
            "refiner": self.refiner,
            "refined_probs": str(self.refined_probs_path),
            "refined_masks": str(self.refined_masks_path),
            "gated": str(self.gated_path),
            "model": self.model.to_json(),
            "device": self.device,
            "precision": self.precision,
            "tile_size": self.tile_size,
            "overlap": self.overlap,
            "tiles": self.tiles,
            "tiles_nodata": self.tiles_nodata,
            "batch_size": self.batch_size,
            **asdict(self.stats),
            "params": asdict(self.params),
            "timings_s": {k: round(v, 3) for k, v in self.timings.items()},
        }


def check_refine_options(options: RefineOptions) -> ModelRef:
    """Validate settings and find the model before any work starts (fail fast, offline)."""
    info = get_refiner(options.refiner)
    options.params.check()
    resolve_precision(options.precision, resolve_device(options.device))
    if options.overlap is not None and options.overlap < 0:
        raise InputError(f"--sam-overlap must be >= 0, got {options.overlap}")
    return resolve_refiner_model(options.sam_model, info.name)


def refine_sink(probs_w: RasterWriter, masks_w: RasterWriter, gated_w: RasterWriter):
    """Blended (E, n, W) refined probabilities -> probabilities, masks (>= 0.5) and P * M.

    Works in place on ``rows`` (the sink's own copy, or the blender's view, which it may modify),
    with one byte of temporaries per value: NaN stays NaN in P * M (NaN * 0 is NaN)."""

    def sink(rows: np.ndarray, row_off: int) -> None:
        probs_w.write(rows, row_off)
        masks = threshold_masks(rows, 0.5)
        masks_w.write(masks, row_off)
        np.multiply(rows, masks == 1, out=rows)
        gated_w.write(rows, row_off)

    return sink


def _check_probs(pds, grid, entities: Sequence[Entity], probs_path) -> None:
    same = (
        (pds.width, pds.height) == (grid.width, grid.height)
        and pds.crs == grid.crs
        and pds.transform.almost_equals(grid.transform)
    )
    if not same:
        raise RasterError(f"{probs_path} is not on the image's grid; run segmentation on this image first")
    if pds.count != len(entities):
        raise RasterError(f"{probs_path} has {pds.count} bands for {len(entities)} entities")
    names = [d or "" for d in pds.descriptions]
    if any(names) and [n.lower() for n in names] != [e.name.lower() for e in entities]:
        raise RasterError(f"{probs_path} holds entities {', '.join(names)}, not {', '.join(e.name for e in entities)}")


def refine_image(
    image: str | os.PathLike,
    probs_path: str | os.PathLike,
    entities: Sequence[Entity],
    out_dir: str | os.PathLike,
    options: RefineOptions = RefineOptions(),
    progress: Progress | None = None,
) -> RefineResult:
    """Refine ``probs.tif`` of ``image`` with SAM into ``out_dir`` (three GeoTIFFs, atomically)."""
    t_start = time.perf_counter()
    ents = validate_entities(entities)
    thresholds = tuple(threshold_of(e) for e in ents)
    check_refine_options(options)
    out = prepare_out_dir(out_dir, image)
    with RasterSource(image, bands=options.bands, assume_crs=options.assume_crs) as src, open_raster(probs_path) as pds:
        grid = src.grid
        _check_probs(pds, grid, ents, probs_path)
        t0 = time.perf_counter()
        bundle = load_sam(options.sam_model, options.device, options.precision, options.compile, options.refiner)
        t_load = time.perf_counter() - t0
        size = bundle.image_size
        overlap = size // 16 if options.overlap is None else int(options.overlap)
        check_tile_options(size, overlap, "SAM tile")
        tiles = TileGrid(grid.width, grid.height, size, overlap)
        refiner = SamRefiner(bundle, options.params, options.batch_size)
        device_label = describe_device(bundle.device)
        if progress is not None:
            progress.message(
                f"refine: {bundle.refiner} {bundle.ref.name} on {device_label} ({bundle.precision}), "
                f"{len(tiles)} tiles of {size} px (tiles without coarse masks are skipped)"
            )
        names = [e.name for e in ents]
        tags = {"OVERSEEC_STAGE": "refine", "OVERSEEC_ENTITIES": entities_tag(ents), "OVERSEEC_MODEL": bundle.ref.name}
        common: dict[str, Any] = dict(descriptions=names, tags=tags, inputs=[image, probs_path])
        t0 = time.perf_counter()
        with (
            RasterWriter(out / runfiles.REFINED_PROBS, grid, len(ents), "float32", nodata=float("nan"), **common) as pw,
            RasterWriter(out / runfiles.REFINED_MASKS, grid, len(ents), "uint8", nodata=MASK_NODATA, **common) as mw,
            RasterWriter(out / runfiles.GATED, grid, len(ents), "float32", nodata=float("nan"), **common) as gw,
            contextlib.ExitStack() as stack,
        ):
            clock = StageClock()
            blender = StreamingBlender(
                grid.width,
                grid.height,
                len(ents),
                refine_sink(pw, mw, gw),
                options.blend,
                flush_rows=pw.block_rows,
                capacity_rows=tiles.tile_shape[0] + pw.block_rows,
            )
            cluster = None
            if options.dask_scheduler:
                cluster = stack.enter_context(Cluster(options.dask_scheduler, options.device))
                device_label = cluster.device_label
            else:
                stack.enter_context(cancel_between_layers(bundle, progress))
            nodata = _drive(src, pds, tiles, refiner, cluster, thresholds, blender, options, progress, clock)
        t_tiles = time.perf_counter() - t0
    return RefineResult(
        refined_probs_path=out / runfiles.REFINED_PROBS,
        refined_masks_path=out / runfiles.REFINED_MASKS,
        gated_path=out / runfiles.GATED,
        model=bundle.ref,
        device=device_label,
        precision=bundle.precision,
        tile_size=size,
        overlap=overlap,
        tiles=len(tiles),
        tiles_nodata=nodata,
        stats=refiner.stats,
        params=options.params,
        batch_size=refiner.state.size,
        refiner=bundle.refiner,
        timings={
            "load_model": t_load,
            "tiles": t_tiles,
            **{f"stage_{k}": v for k, v in sorted(clock.busy.items())},
            "total": time.perf_counter() - t_start,
        },
    )


def _read_group(
    src, pds, group: list[Window], refiner: SamRefiner, thresholds, prepare: bool, counts: dict[str, int]
) -> tuple[list, list[np.ndarray | None], list[int], list]:
    """Chips and coarse maps of a group of tiles: tiles without data or coarse masks answered at
    once, the others listed (``todo``) with their prompts prepared when ``prepare`` (a local run;
    a Dask worker prepares its own, so it gets the coarse maps)."""
    chips = [src.read_chip(w) for w in group]
    coarse = [pds.read(window=w).astype(np.float32) for w in group]
    outputs: list[np.ndarray | None] = [None] * len(group)
    todo, work = [], []
    for i, (chip, probs) in enumerate(zip(chips, coarse)):
        if not chip.any_valid:
            counts["nodata"] += 1
        elif needs_sam(probs, thresholds, refiner.params):
            todo.append(i)
            work.append(refiner.prepare(probs, thresholds) if prepare else probs)
        else:
            outputs[i] = calibrate(probs, thresholds)
            refiner.stats.tiles_no_mask += 1
    return chips, outputs, todo, work


def _filled(outputs: list, todo: Sequence[int], refined: Sequence[np.ndarray]) -> list:
    """``outputs`` with the refined maps put at the ``todo`` positions."""
    for i, out in zip(todo, refined):
        outputs[i] = out
    return outputs


def _drive(
    src, pds, tiles: TileGrid, refiner: SamRefiner, cluster, thresholds, blender, options, progress, clock: StageClock
) -> int:
    """Tiles in row-major groups of the encoder batch: read and prepared in a reader thread, refined
    in this thread (or submitted as one Dask task per group, ``cluster.depth`` groups in flight,
    results taken in order), blended in order and written by a worker thread."""
    windows = tiles.windows()
    weight = blend_weights(tiles.tile_shape, options.blend)
    batch = refiner.state.size
    groups = [windows[k : k + batch] for k in range(0, len(windows), batch)]
    next_rows = [int(w.row_off) for w in windows[1:]] + [tiles.height]
    spec = ModelSpec(
        options.model_name, options.device, options.precision, batch, compile=options.compile, refiner=options.refiner
    )
    counts = {"nodata": 0}

    def read(group: list[Window]) -> tuple[list, list[np.ndarray | None], list[int], list]:
        return _read_group(src, pds, group, refiner, thresholds, cluster is None, counts)

    def refine_here(item: tuple) -> tuple[list, list]:
        chips, outputs, todo, plans = item
        refined = refiner.refine_prepared(np.stack([chips[i].rgb for i in todo]), plans) if todo else []
        return chips, _filled(outputs, todo, refined)

    def submit(item: tuple) -> tuple:
        chips, outputs, todo, coarse = item
        future = None
        if todo:
            rgb = np.stack([chips[i].rgb for i in todo])
            future = cluster.submit(refine_task, spec, refiner.params, thresholds, rgb, coarse)
        return chips, outputs, todo, future

    def gather(item: tuple) -> tuple[list, list]:
        chips, outputs, todo, future = item
        refined: list[np.ndarray] = []
        if future is not None:
            refined, stats = future.result()
            refiner.stats.add(stats)
        return chips, _filled(outputs, todo, refined)

    # a prepared SAM group is ~50 MB per tile: one ready, one in the reader's hands
    with contextlib.closing(pipeline(groups, [("read", read, 1)], clock)) as read_groups:
        if cluster is None:
            drive_in_order(read_groups, refine_here, blender, weight, next_rows, progress, "refine", clock)
        else:
            in_flight = lookahead(read_groups, submit, int(cluster.depth))
            drive_in_order(in_flight, gather, blender, weight, next_rows, progress, "refine", clock)
    return counts["nodata"]


__all__ = [
    "RefineOptions",
    "RefineResult",
    "check_refine_options",
    "refine_image",
    "refine_sink",
]
