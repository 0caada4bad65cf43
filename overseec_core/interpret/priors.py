"""Common-sense priors: what the hazards a prompt leaves unsaid cost.

A mission prompt names what it cares about ("prefer the roads, avoid the baseball field") and
leaves the rest to common sense: nobody who writes that wants the route through a house or a
river. The paper merges the prompt's entities with a default set for this reason; this module
gives that default set its costs. It is the one owner of the table: the README, ``LANGUAGE.md``,
``overseec interpret`` and the manifest show what is here.

The built-in table (levels on the cost scale: neutral 0.5, the avoided band (0.5, 1]):

=========  =====  ===========================================================================
entity     level  why
=========  =====  ===========================================================================
tree       0.85   trees block a ground vehicle and hide what is under them, but a path through
                  a gap is often fine: the paper ranks trees 4th of 5 (below buildings)
railway    0.90   crossing tracks is a real hazard, yet railways are crossed every day
building   1.0    never drive through a building: the top of the avoided band (paper: 5th of 5)
water      1.0    open water stops a ground vehicle: the top of the band
=========  =====  ===========================================================================

The top of the band (1.0) is an *obstacle* (``costlang.scale.OBSTACLE_LEVEL``): the route goes
around buildings and water wherever a way around exists, and where none does (a river between
the points, a start inside a courtyard) it crosses them as little as possible, at the cheapest
place, and says so. None is lethal: a prior says "avoid", never "impassable", so a route still
exists when the only way passes a tree line or a ford. Priors sit above what a prompt's own "avoid" (0.7) and
"avoid as much as possible" (0.8) cost, as in the paper, which ranks the unmentioned trees and
buildings below the baseball field its prompt avoids: a field is a preference, a house an
obstacle. The merge rules (:func:`apply_prior`):

- an entity the prompt does not mention, or mentions without a preference (only in a distance
  cue, say), takes its prior level, or its nearest ancestor's in the entity table ("house" is a
  building, "lake" is water, "forest" is trees);
- "prefer X" puts X below neutral, and permission ("X is fine", "you can wade through the
  water") at neutral, whatever its prior;
- "avoid X" never puts X below its prior: it takes the higher of its ranked level and the
  prior (so "avoid the buildings" keeps buildings at the top of the band);
- "X is a last resort" (tolerable) is a statement of use, so it stands even below the prior;
- lethal is lethal; unmentioned entities without a prior and unlabelled ground stay neutral.

Users replace the table with a JSON file (``--priors FILE``: an object of entity name -> level
in (0.5, 1], ``"obstacle"`` (= 1.0) or ``"lethal"``) or switch it off (``--no-priors``).
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from overseec_core.costlang.scale import PRIOR_LEVELS
from overseec_core.errors import InputError
from overseec_core.interpret import lexicon
from overseec_core.interpret.matching import meanings, normalise
from overseec_core.limits import read_json_limited

#: Levels a prior may take: strictly inside the avoided band (a prior at neutral says nothing).
PRIOR_MIN_EXCLUSIVE, PRIOR_MAX = lexicon.NEUTRAL, 1.0
#: Stated keys at or above this are "avoid" statements, which never go below the prior.
AVOID_KEY = lexicon.AVOID
#: Largest priors file read (a table of names, not a document).
MAX_PRIORS_BYTES = 64 * 1024


@dataclass(frozen=True)
class Prior:
    """One hazard's cost when the prompt leaves it unsaid."""

    entity: str
    level: float
    lethal: bool = False
    why: str = ""

    def to_json(self) -> dict:
        return {"entity": self.entity, "level": self.level, "lethal": self.lethal, "why": self.why}


@dataclass(frozen=True)
class PriorTable:
    """The priors in force, and where they came from (``built-in``, a file path, ``none``)."""

    priors: tuple[Prior, ...]
    source: str = "built-in"

    def for_name(self, name: str) -> Prior | None:
        """The prior of ``name``: its own (by normalised name or synonym), else its nearest
        ancestor's in the entity table ("lake" -> water), else None."""
        by_name = {normalise(p.entity): p for p in self.priors}
        node: str | None = normalise(name)
        seen: set[str] = set()
        while node and node not in seen:
            seen.add(node)
            for meaning in sorted(meanings(node)):
                if meaning in by_name:
                    return by_name[meaning]
            parent = lexicon.parent_of(node)
            node = normalise(parent) if parent else None
        return None

    def describe(self) -> str:
        """One line: 'tree 0.85, railway 0.9, building 1, water 1 (built-in)'."""
        if not self.priors:
            return f"no priors ({self.source})"
        items = ", ".join(f"{p.entity} {'lethal' if p.lethal else f'{p.level:g}'}" for p in self.priors)
        return f"{items} ({self.source})"

    def to_json(self) -> dict:
        return {"source": self.source, "priors": [p.to_json() for p in self.priors]}


BUILT_IN = PriorTable(
    (
        Prior("tree", PRIOR_LEVELS["tree"], why="blocks a ground vehicle; paper rank 4 of 5, below buildings"),
        Prior("railway", PRIOR_LEVELS["railway"], why="crossing tracks is a hazard, but a routine one"),
        Prior("building", PRIOR_LEVELS["building"], why="never drive through a building; paper rank 5 of 5"),
        Prior("water", PRIOR_LEVELS["water"], why="open water stops a ground vehicle"),
    ),
    "built-in",
)
NONE = PriorTable((), "none (--no-priors)")


def parse_priors(data: object, source: str) -> PriorTable:
    """A table from a decoded JSON document: ``{"building": 1.0, "water": "lethal", ...}``."""
    if not isinstance(data, Mapping):
        raise InputError(f'{source}: priors must be a JSON object of entity name -> level, e.g. {{"building": 1.0}}')
    priors = []
    for key, value in data.items():
        name = " ".join(str(key).split()).lower()
        if not name:
            raise InputError(f"{source}: an entity name is empty")
        if value == "lethal":
            priors.append(Prior(name, 1.0, lethal=True, why=f"from {source}"))
            continue
        if value == "obstacle":
            value = PRIOR_MAX
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise InputError(
                f'{source}: the prior of {name!r} must be a level in (0.5, 1], "obstacle" or "lethal", not {value!r}'
            )
        if not PRIOR_MIN_EXCLUSIVE < float(value) <= PRIOR_MAX:
            raise InputError(
                f"{source}: the prior of {name!r} is {value}; priors lie in the avoided band (0.5, 1] "
                "(to leave an entity neutral, leave it out of the table)"
            )
        priors.append(Prior(name, float(value), why=f"from {source}"))
    return PriorTable(tuple(priors), source)


def load_priors(path: str | os.PathLike) -> PriorTable:
    """The table in a JSON file (see :func:`parse_priors`); InputError with one line otherwise."""
    data = read_json_limited(Path(path), MAX_PRIORS_BYTES, "--priors")
    return parse_priors(data, str(path))


def resolve_priors(path: str | os.PathLike | None = None, *, enabled: bool = True) -> PriorTable:
    """The table a command runs with: ``NONE`` when switched off, a file's, else the built-in."""
    if not enabled:
        if path is not None:
            raise InputError("--priors and --no-priors contradict each other; give one")
        return NONE
    return BUILT_IN if path is None else load_priors(path)


def apply_prior(level: float, lethal: bool, key: float, prior: Prior | None) -> tuple[float, bool, bool]:
    """A stated preference merged with its entity's prior: ``(level, lethal, raised)``.

    ``level``/``lethal`` are what the ranking gave the stated ordinal ``key``; an "avoid"
    statement (``key >= AVOID_KEY``) never goes below the prior (``raised`` says it was lifted).
    """
    if prior is None or lethal:
        return level, lethal, False
    if key >= AVOID_KEY - 1e-9:
        if prior.lethal:
            return 1.0, True, True
        if level < prior.level - 1e-9:
            return prior.level, False, True
    return level, lethal, False
