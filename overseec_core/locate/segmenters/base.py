"""What a segmenter backend returns, and the small helpers backends share.

A backend module (``overseec_core/locate/segmenters/<module>.py``, named in the registry of
:mod:`overseec_core.locate.segmenters`) exposes::

    load(model: str | None, entities: Sequence[Entity], options: SegmentOptions) -> LoadedSegmenter

``model`` None means the backend's default (its registry entry); ``options`` carries device,
precision, batch_size, model_size, prompt_template and compile. The :class:`LoadedSegmenter` it
returns is a batch predictor for the tiling engine
(:data:`overseec_core.locate.tiling.BatchPredictor`): tiles ``(B, H, W, 3) uint8`` and their
validity ``(B, H, W) bool`` in, per-entity probabilities ``(B, E, H, W) float32`` in [0, 1] out,
entities in the order given. So tiling, blending, devices, the Dask path, CUDA out-of-memory
back-off and the output rasters are the same for every backend: a backend only maps pixels to
probabilities.

torch is imported inside the helpers, never at import time.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

import numpy as np

from overseec_core.locate.entities import entity_prompts
from overseec_core.locate.models import BatchState, ModelRef, run_with_backoff
from overseec_core.locate.segmenters import default_model
from overseec_core.schema import Entity

if TYPE_CHECKING:
    import torch


@runtime_checkable
class LoadedSegmenter(Protocol):
    """A loaded backend, ready to predict batches of tiles (see the module docstring)."""

    ref: ModelRef  # the resolved model: what the manifest records
    device: Any  # torch.device
    precision: str  # "fp32", "bf16" or "fp16"
    state: BatchState  # the micro-batch size, halved for the run on CUDA out-of-memory
    model_size: int  # px per tile side the model sees
    encoder_calls: int  # tiles through the model's image encoder (tests, the manifest)

    def describe(self) -> str:
        """One line for the progress log, e.g. 'CLIPSeg tiny-clipseg on cpu (1 threads), fp32'."""
        ...

    def __call__(self, rgb: np.ndarray, valid: np.ndarray) -> np.ndarray:
        """(B, H, W, 3) uint8 tiles and (B, H, W) validity -> (B, E, H, W) float32 in [0, 1]."""
        ...


def model_or_default(model: str | None, segmenter: str) -> str:
    """``model`` as given, or the registry's default model of ``segmenter`` when it is None or ''."""
    return str(model) if model else default_model(segmenter)


def entity_texts(entities: Sequence[Entity], template: str = "{}") -> list[tuple[str, ...]]:
    """Each entity's text prompts put into ``template`` (the texts a text-prompted model sees)."""
    return [entity_prompts(e, template) for e in entities]


def predict_in_chunks(chunk: Callable[[int, int], np.ndarray], n: int, state: BatchState) -> np.ndarray:
    """``chunk(start, stop)`` over ``range(n)`` in micro-batches of ``state.size`` (halved on CUDA
    out-of-memory), concatenated as float32: the body of a backend's ``__call__``."""
    return np.concatenate(run_with_backoff(chunk, n, state)).astype(np.float32, copy=False)


def resize_maps(maps: torch.Tensor, size: tuple[int, int]) -> torch.Tensor:
    """(B, E, s, t) maps -> (B, E, h, w), bilinear (half-pixel centres, no antialiasing): how a
    model's output grid is brought back onto its tile."""
    import torch.nn.functional as F  # noqa: N812 (PyTorch's own convention)

    b, e, s, t = maps.shape
    if (s, t) == tuple(size):
        return maps
    up = F.interpolate(maps.reshape(b * e, 1, s, t), size=size, mode="bilinear", align_corners=False)
    return up.reshape(b, e, *size)


__all__ = [
    "LoadedSegmenter",
    "entity_texts",
    "model_or_default",
    "predict_in_chunks",
    "resize_maps",
]
