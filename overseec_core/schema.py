"""What a mission prompt means, as plain frozen data shared by every stage.

The interpreter (LLM or offline) produces an :class:`Interpretation`; segmentation reads its
entities, the cost stage its preferences, hierarchy and cues (or the program text directly).
``to_json`` is the stable document `overseec interpret --json` prints and other tools consume.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal, TypeGuard

Geometry = Literal["linear", "areal"]
GEOMETRIES: tuple[str, ...] = ("linear", "areal")


def is_geometry(value: object) -> TypeGuard[Geometry]:
    """Whether ``value`` is one of :data:`GEOMETRIES` (and so a :data:`Geometry`)."""
    return value in GEOMETRIES


#: Entities every run segments, merged with those the prompt names (the paper's default set).
DEFAULT_ENTITIES: tuple[tuple[str, Geometry], ...] = (
    ("road", "linear"),
    ("trail", "linear"),
    ("grass", "areal"),
    ("tree", "areal"),
    ("building", "areal"),
    ("water", "areal"),
)


#: The neutral level of the cost scale (``costlang.scale.NEUTRAL``; repeated here, where the
#: schema must stay free of numpy, and checked equal by the tests).
NEUTRAL_LEVEL = 0.5


@dataclass(frozen=True)
class Entity:
    """Something to find in the image: a name, its geometry and the text prompts for the segmenter."""

    name: str
    geometry: Geometry = "areal"
    prompts: tuple[str, ...] = ()
    #: Binarisation threshold; None = the geometry's default (linear 0.4, areal 0.8).
    threshold: float | None = None

    @property
    def text_prompts(self) -> tuple[str, ...]:
        return self.prompts or (self.name,)

    def to_json(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "geometry": self.geometry,
            "prompts": list(self.text_prompts),
            "threshold": self.threshold,
        }

    @staticmethod
    def from_json(d: dict[str, Any]) -> Entity:
        return Entity(
            name=str(d["name"]),
            geometry=d.get("geometry", "areal"),
            prompts=tuple(d.get("prompts") or ()),
            threshold=d.get("threshold"),
        )


@dataclass(frozen=True)
class Preference:
    """How much the mission likes an entity: rank 1 = best; weight in [0, 1], lower = preferred."""

    entity: str
    rank: int
    weight: float
    lethal: bool = False
    #: The prompt's words this preference came from ("" = not stated: the neutral default or a prior).
    phrase: str = ""
    #: The level comes from the prior table (``interpret.priors``): a hazard the prompt left unsaid.
    prior: bool = False

    @property
    def band(self) -> str:
        """Where the level sits on the cost scale, in the words ``overseec interpret`` prints:
        ``preferred`` (below neutral), ``neutral``, ``prior`` (an unmentioned hazard's prior),
        ``avoided`` (above neutral, said so) or ``lethal`` (impassable)."""
        if self.lethal:
            return "lethal"
        if self.prior:
            return "prior"
        if self.weight < NEUTRAL_LEVEL - 1e-9:
            return "preferred"
        if self.weight > NEUTRAL_LEVEL + 1e-9:
            return "avoided"
        return "neutral"

    def to_json(self) -> dict[str, Any]:
        return {
            "entity": self.entity,
            "rank": self.rank,
            "weight": self.weight,
            "lethal": self.lethal,
            "phrase": self.phrase,
            "prior": self.prior,
            "band": self.band,
        }

    @staticmethod
    def from_json(d: dict[str, Any]) -> Preference:
        """The preference of a ``to_json`` document (``band`` is derived, so it is not read)."""
        return Preference(
            entity=str(d["entity"]),
            rank=int(d["rank"]),
            weight=float(d["weight"]),
            lethal=bool(d.get("lethal", False)),
            phrase=str(d.get("phrase", "")),
            prior=bool(d.get("prior", False)),
        )


@dataclass(frozen=True)
class Cue:
    """A geometric cue. ``kind`` is one of CUE_KINDS; ``metres`` where the cue has a distance.

    centre: stay on the centre line of a linear entity; side: stay on its edges;
    near: prefer within ``metres`` of ``entity``; far: keep at least ``metres`` from ``entity``;
    unless_near / if_near: ``entity``'s preference applies only away from / near ``other``;
    no_cross: a rule never to cross (or enter) ``entity`` ("do not cross the railway"): the entity
    itself is kept out of, and crossed once, at the cheapest place, only when it separates the points.
    ``hard`` near/far cues are rules ("at least 20 m from", "never within", "stay within"): the
    zone that breaks them is kept out of (impassable wherever a route exists without it).
    """

    kind: str
    entity: str
    metres: float | None = None
    other: str | None = None
    hard: bool = False

    def to_json(self) -> dict[str, Any]:
        return {"kind": self.kind, "entity": self.entity, "metres": self.metres, "other": self.other, "hard": self.hard}


CUE_KINDS: tuple[str, ...] = ("centre", "side", "near", "far", "unless_near", "if_near", "no_cross")


@dataclass(frozen=True)
class Interpretation:
    """Everything Interpret and Synthesize produce from one prompt."""

    prompt: str
    entities: tuple[Entity, ...]
    preferences: tuple[Preference, ...]
    hierarchy: tuple[tuple[str, str], ...] = ()  # (child, parent)
    cues: tuple[Cue, ...] = ()
    program: str = ""
    unparsed: tuple[str, ...] = ()
    source: str = "offline"  # "offline" or "llm:<model>"
    notes: tuple[str, ...] = field(default=())

    def to_json(self) -> dict[str, Any]:
        return {
            "prompt": self.prompt,
            "source": self.source,
            "entities": [e.to_json() for e in self.entities],
            "preferences": [p.to_json() for p in self.preferences],
            "hierarchy": [list(pair) for pair in self.hierarchy],
            "cues": [c.to_json() for c in self.cues],
            "program": self.program,
            "unparsed": list(self.unparsed),
            "notes": list(self.notes),
        }
