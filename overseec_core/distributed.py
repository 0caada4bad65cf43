"""Tiles as tasks on a dask.distributed cluster (``--dask-scheduler ADDRESS``).

The client keeps the whole streaming side: it reads tiles in windows, groups them exactly as a
local run batches them, sends each group's pixels as one task, blends the answers in tile order
and writes the outputs. Workers only run models on what they are sent. So the outputs are the
local run's bit for bit (same batches through the same code), workers need no access to the image
or the output folder, and the client's memory stays bounded by the tiles in flight.

Workers load each model once: the task functions below go through the process-wide cache of
:func:`overseec_core.models.cached_model`, keyed by model path, device and precision. A worker
resolves the model name itself (its own Hugging Face cache or the same local path) on its own
device (``auto`` picks its GPU). Text embeddings are computed once on the client and scattered to
the workers once.

No home-made process pools or RPC: dask.distributed does the scheduling and the transport.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np

from .errors import InputError
from .progress import Progress, check_cancelled

T = TypeVar("T")
R = TypeVar("R")


@dataclass(frozen=True)
class ModelSpec:
    """What a worker needs to load and run a model: name/path, device, precision, batch."""

    model: str
    device: str = "auto"
    precision: str = "auto"
    batch_size: int | None = None
    model_size: int | None = None


def lookahead(items: Iterable[T], start: Callable[[T], R], depth: int) -> Iterator[R]:
    """``start(item)`` for up to ``depth`` items ahead, yielding what it returned in order.

    With Dask, ``start`` submits a task and returns its future, so ``depth`` groups of tiles are
    computed at once while the consumer blends the oldest; with ``depth=1`` it is a plain loop.
    """
    pending: deque[R] = deque()
    for item in items:
        pending.append(start(item))
        if len(pending) >= depth:
            yield pending.popleft()
    while pending:
        yield pending.popleft()


def blend_in_order(
    results: Iterable[tuple[list, list]],
    blender,
    weight: np.ndarray,
    next_rows: Sequence[int],
    progress: Progress | None,
    stage: str,
) -> None:
    """Blend (chips, maps) groups in tile order, a map of None meaning "no prediction here";
    rows above the next tile are flushed after each tile, cancellation is checked per group."""
    if progress is not None:
        progress.begin(stage, len(next_rows), "tile")
    index = 0
    try:
        for chips, maps in results:
            check_cancelled(progress)
            for chip, pred in zip(chips, maps):
                if pred is not None:
                    blender.add(chip.window, pred, weight, chip.valid)
                blender.flush_before(next_rows[index])  # rows above the next tile are final
                index += 1
            if progress is not None:
                progress.advance(len(chips))
        blender.close()
    finally:
        if progress is not None:
            progress.end()


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
    from .models import describe_device, resolve_device

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


def clipseg_task(spec: ModelSpec, cond: np.ndarray, rgb: np.ndarray) -> np.ndarray:
    """(B, h, w, 3) uint8 -> (B, E, h, w) CLIPSeg probabilities, with the worker's cached model."""
    import torch

    from .segment import ClipSegPredictor, load_clipseg

    bundle = load_clipseg(spec.model, spec.device, spec.precision)
    predictor = ClipSegPredictor(bundle, torch.from_numpy(cond), spec.model_size, spec.batch_size)
    return predictor(rgb, np.ones(rgb.shape[:3], bool))


def refine_task(
    spec: ModelSpec, params: Any, thresholds: Sequence[float], rgb: np.ndarray, coarse: Sequence[np.ndarray]
) -> tuple[list[np.ndarray], Any]:
    """SAM tiles: (B, h, w, 3) uint8 and B (E, h, w) coarse maps -> (B (E, h, w) maps, stats)."""
    from .refine import SamRefiner, load_sam

    refiner = SamRefiner(load_sam(spec.model, spec.device, spec.precision), params, spec.batch_size)
    return refiner(rgb, coarse, thresholds), refiner.stats


# --------------------------------------------------------------------------------------------
# Client side: CLIPSeg over the tile grid
# --------------------------------------------------------------------------------------------


def segment_on_dask(
    source,
    cluster: Cluster,
    spec: ModelSpec,
    cond: np.ndarray,
    sink,
    grid,
    channels: int,
    blend: str,
    batch_size: int,
    flush_rows: int,
    progress: Progress | None,
    stage: str = "segment",
):
    """:func:`overseec_core.tiling.stream_predict` with each batch run as a task on the cluster.

    Batches are formed as stream_predict forms them (``batch_size`` windows, tiles without data
    dropped), so each task sees what the local predictor would see.
    """
    from .tiling import StreamingBlender, StreamStats, blend_weights

    windows = grid.windows()
    weight = blend_weights(grid.tile_shape, blend)
    blender = StreamingBlender(
        grid.width, grid.height, channels, sink, blend, flush_rows, capacity_rows=grid.tile_shape[0] + flush_rows
    )
    next_rows = [int(w.row_off) for w in windows[1:]] + [grid.height]
    groups = [windows[i : i + batch_size] for i in range(0, len(windows), batch_size)]
    shared = cluster.scatter(cond)
    t0 = time.perf_counter()
    stats = {"skipped": 0, "read": 0.0}

    def start(group):
        t = time.perf_counter()
        chips = [source.read_chip(w) for w in group]
        stats["read"] += time.perf_counter() - t
        keep = [c for c in chips if c.any_valid]
        stats["skipped"] += len(chips) - len(keep)
        future = cluster.submit(clipseg_task, spec, shared, np.stack([c.rgb for c in keep])) if keep else None
        return chips, future

    def results():
        for chips, future in lookahead(groups, start, cluster.depth):
            preds = iter(future.result() if future is not None else ())
            yield chips, [next(preds) if chip.any_valid else None for chip in chips]

    blend_in_order(results(), blender, weight, next_rows, progress, stage)
    seconds = time.perf_counter() - t0
    return StreamStats(
        tiles=len(windows),
        tiles_skipped=int(stats["skipped"]),
        batches=len(groups),
        seconds=seconds,
        seconds_reading=stats["read"],
        seconds_predicting=seconds - stats["read"],
        peak_buffer_rows=blender.peak_buffer_rows,
    )


__all__ = [
    "Cluster",
    "ModelSpec",
    "blend_in_order",
    "clipseg_task",
    "connect",
    "lookahead",
    "refine_task",
    "segment_on_dask",
    "worker_device",
]
