"""The ``clipseg`` segmenter (the paper's, the default): CLIPSeg, text-prompted, per entity.

:func:`load` resolves and loads the checkpoint (:func:`overseec_core.locate.clipseg.load_clipseg`,
cached per process), computes the entities' text embeddings once (several prompts of an entity
are averaged) and returns the shared-encoder batch predictor
(:class:`overseec_core.locate.clipseg.ClipSegPredictor`: one vision-encoder pass per tile for all
entities), which is a :class:`~overseec_core.locate.segmenters.base.LoadedSegmenter`.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import TYPE_CHECKING

from overseec_core.locate.clipseg import ClipSegPredictor, load_clipseg, text_embeddings
from overseec_core.locate.segmenters.base import entity_texts, model_or_default
from overseec_core.schema import Entity

if TYPE_CHECKING:
    from overseec_core.locate.segment import SegmentOptions

NAME = "clipseg"


def load(model: str | None, entities: Sequence[Entity], options: SegmentOptions) -> ClipSegPredictor:
    """CLIPSeg ``model`` (None: the registry's default) ready to predict ``entities``' probabilities.

    ``options``: device, precision, compile (the bundle), prompt_template (the texts),
    model_size and batch_size (the predictor). The text-embedding time is in ``timings``.
    """
    bundle = load_clipseg(model_or_default(model, NAME), options.device, options.precision, options.compile)
    t0 = time.perf_counter()
    cond = text_embeddings(bundle, entity_texts(entities, options.prompt_template))
    predictor = ClipSegPredictor(bundle, cond, options.model_size, options.batch_size)
    predictor.timings["text_embeddings"] = time.perf_counter() - t0
    return predictor


__all__ = ["NAME", "load"]
