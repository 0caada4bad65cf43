"""Entities of the Locate stage: validation, thresholds, prompt texts, output tags, and the checks
both stages make on their settings and output folder (no model)."""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from overseec_core import defaults
from overseec_core.errors import InputError, OutputError
from overseec_core.schema import GEOMETRIES, Entity

#: The paper's binarisation thresholds by geometry.
DEFAULT_THRESHOLDS: dict[str, float] = defaults.THRESHOLDS
#: Nodata of the uint8 mask outputs (0 and 1 are the mask values).
MASK_NODATA = 255
#: Prompt templates selectable with --prompt-template (off by default until measured better).
PROMPT_TEMPLATES: dict[str, str] = {
    "none": "{}",
    "aerial": "aerial view of {}",
    "satellite": "satellite image of {}",
}


def threshold_of(entity: Entity) -> float:
    """The entity's binarisation threshold: its own, else its geometry's default."""
    if entity.threshold is not None:
        return float(entity.threshold)
    return DEFAULT_THRESHOLDS[entity.geometry]


def validate_entities(entities: Sequence[Entity]) -> tuple[Entity, ...]:
    """Non-empty, unique (case-insensitive) names, known geometries, thresholds in (0, 1)."""
    ents = tuple(entities)
    if not ents:
        raise InputError(
            "no entities to segment; pass --entity NAME:linear|areal "
            "(e.g. --entity road:linear) or --entities-json FILE"
        )
    seen: dict[str, str] = {}
    for e in ents:
        name = e.name.strip()
        if not name:
            raise InputError("an entity has an empty name")
        if name.lower() in seen:
            raise InputError(f"duplicate entity name {name!r}; each entity is one output band")
        seen[name.lower()] = name
        if e.geometry not in GEOMETRIES:
            raise InputError(f"entity {name!r}: geometry {e.geometry!r} is not one of {', '.join(GEOMETRIES)}")
        t = e.threshold
        if t is not None and not (isinstance(t, (int, float)) and 0.0 < float(t) < 1.0):
            raise InputError(f"entity {name!r}: threshold {t!r} must be between 0 and 1 (exclusive)")
        if any(not p.strip() for p in e.text_prompts):
            raise InputError(f"entity {name!r}: empty text prompt")
    return ents


def apply_thresholds(entities: Sequence[Entity], overrides: dict[str, float]) -> tuple[Entity, ...]:
    """Set per-entity thresholds from ``{name: value}``; unknown names are an InputError."""
    by_name = {e.name.lower(): e for e in entities}
    unknown = [n for n in overrides if n.lower() not in by_name]
    if unknown:
        raise InputError(
            f"--threshold for unknown entit{'y' if len(unknown) == 1 else 'ies'} "
            f"{', '.join(map(repr, unknown))}; entities are "
            f"{', '.join(e.name for e in entities)}"
        )
    lowered = {k.lower(): v for k, v in overrides.items()}
    return tuple(replace(e, threshold=lowered[e.name.lower()]) if e.name.lower() in lowered else e for e in entities)


def entity_prompts(entity: Entity, template: str = "{}") -> tuple[str, ...]:
    """The texts CLIPSeg sees for an entity: each prompt put into the template."""
    return tuple(template.replace("{}", p) if "{}" in template else f"{template} {p}" for p in entity.text_prompts)


def entities_tag(entities: Sequence[Entity]) -> str:
    """JSON stored in the output GeoTIFFs so later stages know names, geometries, thresholds."""
    return json.dumps(
        [
            {"name": e.name, "geometry": e.geometry, "threshold": threshold_of(e), "prompts": list(e.text_prompts)}
            for e in entities
        ]
    )


def threshold_masks(rows: np.ndarray, tau: np.ndarray | float) -> np.ndarray:
    """uint8 masks of blended rows: 1 where ``rows >= tau``, 0 below, MASK_NODATA where NaN.

    Built in place on one boolean array (two bytes of temporaries per value): the rows of a SAM
    block over a 10000 px width are hundreds of MB, and ``np.where`` would go through int64."""
    with np.errstate(invalid="ignore"):
        masks = np.greater_equal(rows, tau).view(np.uint8)
    masks[np.isnan(rows)] = MASK_NODATA
    return masks


def check_tile_options(tile_size: int, overlap: int, what: str = "tile") -> None:
    """Tiles of at least 32 px, overlapping by at most half a tile (the reference's 50%)."""
    if tile_size < 32:
        raise InputError(f"--tile-size {tile_size} is too small; use at least 32 px")
    if not 0 <= overlap <= tile_size // 2:
        raise InputError(f"overlap {overlap} must be between 0 and half the {what} ({tile_size // 2} px)")


def prepare_out_dir(out_dir: str | os.PathLike, image: str | os.PathLike) -> Path:
    """Create the output folder (and parents); refuse the input's own path."""
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out} exists and is not a folder")
    if out.resolve() == Path(image).resolve():
        raise InputError(f"--out {out} is the input image")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"cannot create output folder {out} ({exc.strerror or exc})") from None
    return out


__all__ = [
    "DEFAULT_THRESHOLDS",
    "MASK_NODATA",
    "PROMPT_TEMPLATES",
    "apply_thresholds",
    "check_tile_options",
    "entities_tag",
    "entity_prompts",
    "prepare_out_dir",
    "threshold_masks",
    "threshold_of",
    "validate_entities",
]
