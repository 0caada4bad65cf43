"""Tiles as tasks on a dask.distributed cluster (``--dask-scheduler ADDRESS``).

The client keeps the whole streaming side: a reader thread reads tiles in windows ahead and groups
them exactly as a local run batches them, the client sends each group's pixels as one task
(``Cluster.depth`` groups in flight, :func:`overseec_core.locate.stages.lookahead`) and takes the answers
in tile order, and a worker thread blends and writes them. Workers only run models
on what they are sent (a SAM worker also prepares its tiles' prompts). So the outputs are the local
run's (same batches through the same code, to float rounding of arrays that crossed processes),
workers need no access to the image or the output folder, and the client's memory stays bounded
by the groups in flight.

Workers load each model once: the task functions below go through the process-wide cache of
:func:`overseec_core.locate.models.cached_model`. A segmentation worker loads the segmenter by its
registry name (:func:`overseec_core.locate.segmenters.get_backend`, then the backend's ``load``
with the entities and options the client sent: a :class:`SegmenterSpec`), once per spec, so a
text-prompted backend embeds its texts once per worker; a worker resolves the model name itself
(its own Hugging Face cache or the same local path) on its own device (``auto`` picks its GPU).

No home-made process pools or RPC: dask.distributed does the scheduling and the transport.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from overseec_core.errors import InputError
from overseec_core.locate.gsd import Resampling, resampled
from overseec_core.locate.models import cached_model, describe_device, resolve_device
from overseec_core.locate.prompts import RefineParams
from overseec_core.locate.refiners import DEFAULT_REFINER
from overseec_core.locate.sam import SamRefiner, TileStats
from overseec_core.locate.sam_model import load_sam
from overseec_core.locate.segmenters import get_backend
from overseec_core.locate.stages import StageClock, lookahead, pipeline
from overseec_core.locate.tiling import (
    READ_AHEAD,
    StreamingBlender,
    StreamStats,
    blend_weights,
    drive_in_order,
)
from overseec_core.progress import Progress
from overseec_core.schema import Entity


@dataclass(frozen=True)
class ModelSpec:
    """What a worker needs to load and run a model: name/path, device, precision, batch."""

    model: str
    device: str = "auto"
    precision: str = "auto"
    batch_size: int | None = None
    model_size: int | None = None
    compile: bool = False
    refiner: str = DEFAULT_REFINER  # the refiners' table name: which family ``model`` loads as


@dataclass(frozen=True)
class SegmenterSpec:
    """What a worker needs to load a segmenter as the client did: its registry name, the model
    (None: the backend's default), the entities, the stage's options (a ``SegmentOptions``
    with the client's batch and input sizes and no scheduler) and the processing resolution
    (:class:`overseec_core.locate.gsd.Resampling`; None: native)."""

    segmenter: str
    model: str | None
    entities: tuple[Entity, ...]
    options: Any
    resampling: Resampling | None = None


def connect(address: str, timeout_s: float = 10.0):
    """A dask.distributed Client for ``address``, or a one-line InputError within the timeout."""
    try:
        from distributed import Client
    except ImportError:  # pragma: no cover - a declared optional dependency
        raise InputError("--dask-scheduler needs dask.distributed: pip install distributed") from None
    try:
        client = Client(address, timeout=timeout_s, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as exc:
        reason = " ".join(str(exc).split())[:160] or type(exc).__name__
        raise InputError(f"cannot reach the Dask scheduler at {address} ({reason})") from None
    if not client.scheduler_info().get("workers"):
        client.close()
        raise InputError(f"the Dask scheduler at {address} has no workers")
    return client


def worker_device(device: str) -> str:
    """Runs on a worker: the device that worker resolves ``device`` to."""
    return describe_device(resolve_device(device))


class Cluster:
    """A connection to the cluster for one stage: submits tasks, knows how deep to pipeline."""

    def __init__(self, address: str, device: str) -> None:
        self.client = connect(address)
        self.address = address
        labels = self.client.run(worker_device, device)
        self.workers = len(labels)
        self.depth = 2 * self.workers  # groups in flight: every worker busy, one queued
        self.device_label = f"dask {self.workers} worker(s): {', '.join(sorted(set(labels.values())))}"

    def submit(self, fn: Callable[..., Any], *args: Any):
        return self.client.submit(fn, *args, pure=False)

    def scatter(self, data: Any):
        return self.client.scatter(data, broadcast=True)

    def __enter__(self) -> Cluster:
        return self

    def __exit__(self, *exc: object) -> None:
        self.client.close()


# --------------------------------------------------------------------------------------------
# Task functions (run on workers)
# --------------------------------------------------------------------------------------------


def segmenter_task(spec: SegmenterSpec, rgb: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """(B, h, w, 3) uint8 + (B, h, w) validity -> (B, E, h, w) probabilities, with the worker's
    segmenter (loaded once per spec in this process)."""
    segmenter = cached_model(
        ("segmenter", repr(spec)),
        lambda: resampled(get_backend(spec.segmenter).load(spec.model, spec.entities, spec.options), spec.resampling),
    )
    return segmenter(rgb, valid)


def refine_task(
    spec: ModelSpec, params: RefineParams, thresholds: Sequence[float], rgb: np.ndarray, coarse: Sequence[np.ndarray]
) -> tuple[list[np.ndarray], TileStats]:
    """Refiner tiles: (B, h, w, 3) uint8 and B (E, h, w) coarse maps -> (B (E, h, w) maps, stats),
    with the refiner family ``spec.refiner`` (SAM, SAM-HQ or SAM 2) loaded once per worker.

    The worker prepares the prompts itself (CPU work next to its model, not on the client)."""
    bundle = load_sam(spec.model, spec.device, spec.precision, spec.compile, spec.refiner)
    refiner = SamRefiner(bundle, params, spec.batch_size)
    return refiner(rgb, coarse, thresholds), refiner.stats


# --------------------------------------------------------------------------------------------
# Client side: a segmenter over the tile grid
# --------------------------------------------------------------------------------------------


def segment_on_dask(
    source,
    cluster: Cluster,
    spec: SegmenterSpec,
    sink,
    grid,
    channels: int,
    blend: str,
    batch_size: int,
    flush_rows: int,
    progress: Progress | None,
    stage: str = "segment",
):
    """:func:`overseec_core.locate.tiling.stream_predict` with each batch run as a task on the cluster.

    Batches are formed as stream_predict forms them (``batch_size`` windows, tiles without data
    dropped), so each task sees what the local predictor would see.
    """
    windows = grid.windows()
    weight = blend_weights(grid.tile_shape, blend)
    next_rows = [int(w.row_off) for w in windows[1:]] + [grid.height]
    groups = [windows[i : i + batch_size] for i in range(0, len(windows), batch_size)]
    shared = cluster.scatter(spec)
    clock = StageClock()
    t0 = time.perf_counter()
    skipped = 0

    def read(group):
        return [source.read_chip(w) for w in group]

    def submit(chips):
        keep = [c for c in chips if c.any_valid]
        if not keep:
            return chips, None
        rgb, valid = np.stack([c.rgb for c in keep]), np.stack([c.valid for c in keep])
        future = cluster.submit(segmenter_task, shared, rgb, valid)
        return chips, future

    def gather(item):
        nonlocal skipped
        chips, future = item
        preds = iter(future.result() if future is not None else ())
        skipped += sum(not c.any_valid for c in chips)
        return chips, [next(preds) if chip.any_valid else None for chip in chips]

    blender = StreamingBlender(
        grid.width, grid.height, channels, sink, blend, flush_rows, capacity_rows=grid.tile_shape[0] + flush_rows
    )
    with contextlib.closing(pipeline(groups, [("read", read, READ_AHEAD)], clock)) as chips:
        in_flight = lookahead(chips, submit, int(cluster.depth))
        drive_in_order(in_flight, gather, blender, weight, next_rows, progress, stage, clock)
    seconds = time.perf_counter() - t0
    return StreamStats(
        tiles=len(windows),
        tiles_skipped=skipped,
        batches=len(groups),
        seconds=seconds,
        seconds_reading=clock.busy.get("read", 0.0),
        seconds_predicting=clock.busy.get("model", 0.0),
        peak_buffer_rows=blender.peak_buffer_rows,
        seconds_blending=clock.busy.get("blend+write", 0.0),
    )


__all__ = [
    "Cluster",
    "ModelSpec",
    "SegmenterSpec",
    "connect",
    "refine_task",
    "segment_on_dask",
    "segmenter_task",
    "worker_device",
]
