"""The segmenter registry: which backends Locate can run, by name, without importing any of them.

Every coarse segmenter is one module of this package exposing
``load(model, entities, options) -> LoadedSegmenter`` (:mod:`.base` says what that returns: the
batch predictor the tiling engine drives; a backend's helpers, such as ``semantic_meta`` and ``detectors``, sit
beside it). This table names them; adding a backend is its module plus one :class:`SegmenterInfo`
line below. The table is standard library only, so ``overseec
--help``, the QGIS plugin and the Processing algorithms list the names and default models without
torch; :func:`get_backend` imports a backend when a run needs it.

* ``clipseg`` (default): CLIPSeg, text-prompted, one encoder pass per tile for all entities (the paper's);
* ``boxes+sam``: text-prompted boxes (OWLv2) refined into masks by SAM, for object-like entities;
* ``semantic``: a fixed-ontology semantic-segmentation model (a ``transformers`` checkpoint such
  as SegFormer, or an ONNX model with a class metadata file), its classes mapped to entity names.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from types import ModuleType

from overseec_core.errors import InputError


@dataclass(frozen=True)
class SegmenterInfo:
    """One registry entry: the name users pick, the module under this package, its default model."""

    name: str  # what --segmenter, Processing and the dock offer
    module: str  # module name under overseec_core.locate.segmenters
    default_model: str  # hub id (or path) used when no --model is given
    summary: str  # one line for --help, `models list`, the plugin


#: The backends, in the order menus list them (the default first: Processing enums hold indices).
SEGMENTERS: dict[str, SegmenterInfo] = {
    info.name: info
    for info in (
        SegmenterInfo(
            "clipseg",
            "clipseg",
            "CIDAS/clipseg-rd64-refined",
            "CLIPSeg: text-prompted probabilities, one encoder pass per tile (the paper's)",
        ),
        SegmenterInfo(
            "boxes+sam",
            "boxes_sam",
            "google/owlv2-base-patch16-ensemble",
            "text-prompted OWLv2 boxes refined by SAM (object-like entities)",
        ),
        SegmenterInfo(
            "semantic",
            "semantic",
            "nvidia/segformer-b0-finetuned-ade-512-512",
            "a fixed-ontology semantic segmenter (SegFormer checkpoint or ONNX), classes mapped to entities",
        ),
    )
}
#: The segmenter a run uses unless told otherwise.
DEFAULT_SEGMENTER = "clipseg"


def describe_segmenters() -> str:
    """Every backend as "name: summary", in menu order: what help texts and tooltips say, so a
    new backend reaches them without a hand-written list going stale."""
    return "; ".join(f"{i.name}: {i.summary}" for i in SEGMENTERS.values())


def segmenter_names() -> tuple[str, ...]:
    """The registered names, default first (the CLI's ``--segmenter`` choices)."""
    return tuple(SEGMENTERS)


def segmenter_info(name: str) -> SegmenterInfo:
    """The entry of ``name``, or a one-line InputError listing the names."""
    try:
        return SEGMENTERS[name]
    except KeyError:
        raise InputError(f"unknown segmenter {name!r}; use one of {', '.join(SEGMENTERS)}") from None


def default_model(name: str) -> str:
    """The model ``name`` loads when none is given."""
    return segmenter_info(name).default_model


def get_backend(name: str) -> ModuleType:
    """Import and return the backend module of ``name`` (its ``load`` makes a LoadedSegmenter).

    An unknown name, or a registered backend whose module this installation lacks, is a one-line
    InputError; an ImportError inside the module (a missing dependency) propagates as it is.
    """
    info = segmenter_info(name)
    qualified = f"{__name__}.{info.module}"
    try:
        module = importlib.import_module(qualified)
    except ModuleNotFoundError as exc:
        if exc.name != qualified:
            raise
        raise InputError(f"segmenter {name!r} is not installed in this version") from None
    if not callable(getattr(module, "load", None)):
        raise InputError(f"segmenter {name!r}: {qualified} has no load(model, entities, options)")
    return module


__all__ = [
    "DEFAULT_SEGMENTER",
    "SEGMENTERS",
    "SegmenterInfo",
    "default_model",
    "get_backend",
    "segmenter_info",
    "segmenter_names",
]
