"""Tiles as tasks on a dask.distributed cluster (``--dask-scheduler ADDRESS``).

The client keeps the whole streaming side: it reads tiles in windows, blends predictions in the
same order as a local run and writes the outputs; workers only run models on the pixels they are
sent and return the tile's maps. So the outputs are the same as a local run's, workers need no
access to the image or the output folder, and memory on the client stays bounded by tiles.

Workers load each model once: the task functions below go through the process-wide cache of
:func:`overseec_core.models.cached_model`, keyed by model path, device and precision. A worker
resolves the model name itself (its own Hugging Face cache or the same local path), on its own
best device (``auto``). Text embeddings are computed once on the client and scattered to every
worker once.

No home-made process pools or RPC: dask.distributed does the scheduling and transport.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from .errors import InputError


@dataclass(frozen=True)
class ModelSpec:
    """What a worker needs to load a model: name/path, device, precision, batch."""

    model: str
    device: str = "auto"
    precision: str = "auto"
    batch_size: int | None = None
    model_size: int | None = None


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
    workers = client.scheduler_info().get("workers", {})
    if not workers:
        client.close()
        raise InputError(f"the Dask scheduler at {address} has no workers")
    return client


def worker_device(device: str) -> str:
    """Runs on a worker: the device that worker resolves ``device`` to."""
    from .models import describe_device, resolve_device

    return describe_device(resolve_device(device))


def _device_label(client, device: str) -> str:
    labels = client.run(worker_device, device)
    distinct = sorted(set(labels.values()))
    return f"dask {len(labels)} worker(s): {', '.join(distinct)}"


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


def refine_task(spec: ModelSpec, params: Any, thresholds: Sequence[float], rgb: np.ndarray,
                coarse: np.ndarray) -> tuple[np.ndarray, Any]:
    """One SAM tile: (h, w, 3) uint8 and (E, h, w) coarse probabilities -> ((2E, h, w), stats)."""
    from .refine import SamRefiner, load_sam

    refiner = SamRefiner(load_sam(spec.model, spec.device, spec.precision), params, 1)
    out = refiner(rgb[None], [coarse], thresholds)[0]
    return out, refiner.stats


# --------------------------------------------------------------------------------------------
# Client-side adapters
# --------------------------------------------------------------------------------------------


class DaskClipSegPredictor:
    """A stream_predict predictor that fans each batch out to workers, chunk by chunk, in order."""

    def __init__(self, client, spec: ModelSpec, cond: np.ndarray, chunk: int) -> None:
        self.client, self.spec, self.chunk = client, spec, max(1, chunk)
        self.workers = len(client.scheduler_info()["workers"])
        self.batch_size = self.chunk * self.workers * 2  # keep every worker busy
        self.cond = client.scatter(cond, broadcast=True)
        self.device_label = _device_label(client, spec.device)
        self.tiles_sent = 0

    def __call__(self, rgb: np.ndarray, valid: np.ndarray) -> np.ndarray:
        futures = [self.client.submit(clipseg_task, self.spec, self.cond, rgb[i:i + self.chunk], pure=False)
                   for i in range(0, len(rgb), self.chunk)]
        self.tiles_sent += len(rgb)
        return np.concatenate(self.client.gather(futures))

    def __enter__(self) -> "DaskClipSegPredictor":
        return self

    def __exit__(self, *exc: object) -> None:
        self.client.close()


class DaskRefineRunner:
    """Sends the SAM tiles that need refinement to workers, one task per tile, results in order."""

    def __init__(self, client, spec: ModelSpec, params: Any, thresholds: Sequence[float]) -> None:
        from .refine import TileStats

        self.client, self.spec, self.params = client, spec, params
        self.thresholds = tuple(thresholds)
        self.in_flight = 2 * len(client.scheduler_info()["workers"])
        self.device_label = _device_label(client, spec.device)
        self.stats = TileStats()

    def run(self, rgbs: Sequence[np.ndarray], coarses: Sequence[np.ndarray]) -> list[np.ndarray]:
        futures = [self.client.submit(refine_task, self.spec, self.params, self.thresholds, rgb, coarse,
                                      pure=False) for rgb, coarse in zip(rgbs, coarses)]
        outs = []
        for out, stats in self.client.gather(futures):
            self.stats.add(stats)
            outs.append(out)
        return outs

    def __enter__(self) -> "DaskRefineRunner":
        return self

    def __exit__(self, *exc: object) -> None:
        self.client.close()


def dask_clipseg_predictor(address: str, options: Any, cond: "torch.Tensor", chunk: int) -> DaskClipSegPredictor:
    """Connect and build the CLIPSeg fan-out for :func:`overseec_core.segment.segment_image`."""
    spec = ModelSpec(options.clipseg_model, options.device, options.precision, chunk, options.model_size)
    return DaskClipSegPredictor(connect(address), spec, cond.detach().cpu().numpy(), chunk)


def dask_refine_runner(address: str, options: Any, thresholds: Sequence[float]) -> DaskRefineRunner:
    """Connect and build the SAM fan-out for :func:`overseec_core.refine.refine_image`."""
    spec = ModelSpec(options.sam_model, options.device, options.precision, 1)
    return DaskRefineRunner(connect(address), spec, options.params, thresholds)


__all__ = ["DaskClipSegPredictor", "DaskRefineRunner", "ModelSpec", "clipseg_task", "connect",
           "dask_clipseg_predictor", "dask_refine_runner", "refine_task", "worker_device"]
