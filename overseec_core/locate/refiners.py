"""The refiners the refine stage can run, with their default checkpoints (light: no torch).

One table owns the choice: the CLI's ``--refiner`` choices, the plugin's menus and
:class:`overseec_core.locate.refine.RefineOptions` read it, and :mod:`overseec_core.locate.sam`
loads whichever entry is named. Every refiner is a promptable segmenter of the SAM family that
``transformers`` ships (an image encoder run once per tile, a mask decoder run per component on
point, box and mask prompts), so the refine stage drives all of them with the same code:

* ``sam``: Segment Anything (``SamModel``), the OVerSeeC paper's refiner;
* ``sam-hq``: SAM-HQ (``SamHQModel``): SAM's encoder and decoder plus a high-quality output token
  fused with the encoder's early features, for finer boundaries (thin roads, building edges);
* ``sam2``: SAM 2.1 (``Sam2Model``): a hierarchical (Hiera) encoder whose finer feature levels feed
  the decoder; the tiny checkpoint is several times faster than SAM ViT-B on CPU.

Imports only the standard library and light project modules, so ``overseec --help`` and the QGIS
plugin can list the names without torch.
"""

from __future__ import annotations

from dataclasses import dataclass

from overseec_core.errors import InputError
from overseec_core.locate.models import DEFAULT_SAM, DEFAULT_SAM2, DEFAULT_SAM_HQ


@dataclass(frozen=True)
class RefinerInfo:
    """One refiner: its name, the ``model_type`` its checkpoints declare, its default model."""

    name: str  # the --refiner value, also the model kind a resolved checkpoint records
    model_type: str  # config.json's model_type of its checkpoints
    model_class: str  # the transformers class that loads it
    default_model: str  # hub id used when no model is given
    summary: str  # one line for help texts and `overseec models list`


#: The refiners, in the order menus show them; the first is the default.
REFINERS: dict[str, RefinerInfo] = {
    info.name: info
    for info in (
        RefinerInfo("sam", "sam", "SamModel", DEFAULT_SAM, "Segment Anything ViT-B (the paper's refiner)"),
        RefinerInfo(
            "sam-hq",
            "sam_hq",
            "SamHQModel",
            DEFAULT_SAM_HQ,
            "SAM-HQ ViT-B: SAM with a high-quality output token, finer boundaries",
        ),
        RefinerInfo(
            "sam2",
            "sam2",
            "Sam2Model",
            DEFAULT_SAM2,
            "SAM 2.1 Hiera-T: hierarchical encoder, fast on CPU",
        ),
    )
}
DEFAULT_REFINER = "sam"


def describe_refiners() -> str:
    """Every refiner as "name: summary", in menu order (help texts and tooltips read this)."""
    return "; ".join(f"{i.name}: {i.summary}" for i in REFINERS.values())


def refiner_names() -> tuple[str, ...]:
    """The refiner names, default first (the CLI's ``choices``)."""
    return tuple(REFINERS)


def get_refiner(name: str) -> RefinerInfo:
    """The table entry of ``name``, or a one-line InputError listing the names."""
    info = REFINERS.get(str(name).strip().lower())
    if info is None:
        raise InputError(f"unknown refiner {name!r}; use one of {', '.join(REFINERS)}")
    return info


def default_model(refiner: str) -> str:
    """The checkpoint ``refiner`` runs when no model is given."""
    return get_refiner(refiner).default_model


__all__ = ["DEFAULT_REFINER", "REFINERS", "RefinerInfo", "default_model", "get_refiner", "refiner_names"]
