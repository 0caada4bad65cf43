"""Check that a cost program keeps the cost scale its interpretation asks for.

The scale (``LANGUAGE.md``, "The cost scale"): ground covered by no entity is neutral (0.5);
an entity the mission prefers costs less than that, one it avoids more, a lethal one is lethal.
An LLM may write any valid program, so before its program is used it is *probed*: evaluated on
small synthetic layers where one entity (with its hierarchy parents, since a child lies inside
its parent) covers a square and nothing else is present, and on layers where nothing is
present at all. A program that puts an avoided entity at or below neutral, a preferred one at
or above it, leaves a lethal entity passable, or moves empty ground off neutral is refused with
an error located at the entity's first use, and goes back to the LLM like a syntax error; so is a
program that never reads an entity the mission speaks about, or has no ``keep_out`` while the
mission states a distance rule, or leaves an obstacle (an entity at ``OBSTACLE_LEVEL``) out of
``keep_out``.

The probes are evaluated with our own interpreter, like any block of a real image; they only
say how the program treats each entity on its own (entities with an ``if_near`` condition are
not probed, since their preference depends on another entity's presence).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from typing import Protocol

import numpy as np

from overseec_core.costlang.evaluator import evaluate_program
from overseec_core.costlang.lang import normalise_entity_name
from overseec_core.costlang.tree import Program
from overseec_core.errors import CostProgramError

#: Cost of ground covered by no entity: the neutral level of the scale (the interpreters' ordinal
#: key for "no preference", ``interpret.lexicon.NEUTRAL``, has the same value on purpose).
NEUTRAL = 0.5
#: Levels closer than this to NEUTRAL are neutral (levels are rounded to 6 decimals).
LEVEL_EPS = 1e-9
#: The top of the avoided band: a passable entity at this level is an *obstacle* (buildings and
#: water nobody mentioned, ``interpret.priors``): gone around wherever a route exists, and
#: crossed as little as possible where one does not (a keep-out zone of the entity itself).
OBSTACLE_LEVEL = 1.0
#: The interpreters' tiers (``interpret.lexicon`` names them): preferred ground, and the avoided
#: tiers below the priors of the hazards nobody needs to mention (trees 0.85, railways 0.9,
#: buildings and water OBSTACLE_LEVEL: ``interpret.priors``), so a field the prompt avoids is
#: still better ground than a house; LETHAL is the top of the scale, impassable.
PREFER_LEVEL = 0.10
TOLERABLE_LEVEL = 0.60
#: "X only as a last resort": the worst ground still used, dearer than what is used "if needed".
LAST_RESORT_LEVEL = 0.65
AVOID_LEVEL = 0.70
STRONG_AVOID_LEVEL = 0.80
LETHAL_LEVEL = 1.0
#: An ordering's step between neighbours ("first X, then Y") and the highest level it may give
#: (orderings stay on the preferred side of neutral).
ORDER_STEP = 0.10
ORDER_MAX_LEVEL = 0.45
#: The built-in priors of the hazards a prompt leaves unsaid (``interpret.priors.BUILT_IN``).
PRIOR_LEVELS = {"tree": 0.85, "railway": 0.9, "building": OBSTACLE_LEVEL, "water": OBSTACLE_LEVEL}
#: The geometric cues' levels (``costlang.synth``): the most non-avoided ground costs right beside
#: a soft ``near`` cue's entity and at its distance; the least anything costs right beside a soft
#: ``far`` cue's entity and at its distance (above neutral: a soft zone, not only a slope); the
#: least a preferred or allowed entity costs where an ``unless_near`` exception holds.
NEAR_LEVEL, NEAR_EDGE_LEVEL = 0.25, 0.45
FAR_LEVEL, FAR_EDGE_LEVEL = 1.0, 0.6
CONDITION_AVOID_LEVEL = 0.75
#: How far empty ground may sit from NEUTRAL in a checked program.
NEUTRAL_TOLERANCE = 0.05
#: Probe geometry: a square entity of PROBE_SIDE pixels inside a PROBE_GRID grid, 1 m pixels
#: (the square is wider than the default linear width, so centre/side cues see a whole feature).
PROBE_GRID, PROBE_SIDE = 64, 21


class Level(Protocol):
    """What the scale reads of a preference (:class:`overseec_core.schema.Preference`, or any
    object with these attributes): its entity, its cost level and whether it is lethal."""

    @property
    def entity(self) -> str: ...
    @property
    def weight(self) -> float: ...
    @property
    def lethal(self) -> bool: ...


class ScaleCue(Protocol):
    """What the scale reads of a cue (:class:`overseec_core.schema.Cue`, or any object with these
    attributes; a ``hard`` attribute, where present, makes a near/far cue a rule)."""

    @property
    def kind(self) -> str: ...
    @property
    def entity(self) -> str: ...
    @property
    def metres(self) -> float | None: ...


def is_obstacle(pref: Level) -> bool:
    """Whether a preference makes its entity an obstacle: passable, at the top of the scale."""
    return not pref.lethal and pref.weight >= OBSTACLE_LEVEL - LEVEL_EPS


def off_neutral(pref: Level) -> bool:
    """Whether a preference (``weight`` level, ``lethal``) moves its entity off neutral ground."""
    return bool(pref.lethal) or abs(pref.weight - NEUTRAL) > LEVEL_EPS


def _locate(program: Program, entity: str) -> tuple[int | None, int | None]:
    """Line and column of the entity's first use in the program text (else of ``cost``)."""
    want = normalise_entity_name(entity)
    for lineno, line in enumerate(program.text.splitlines(), start=1):
        for m in re.finditer(r'[MP]\[\s*(["\'])(.*?)\1\s*\]', line):
            if normalise_entity_name(m.group(2)) == want:
                return lineno, m.start()
    cost = next((s for s in program.statements if s.target == "cost"), None)
    return (cost.line, cost.col) if cost else (None, None)


def _probe(program: Program, present: Iterable[str]) -> tuple[float, bool, bool]:
    """(cost, lethal, keep_out) at the centre of a square covered by ``present`` and nothing else."""
    shape = (PROBE_GRID, PROBE_GRID)
    lo = (PROBE_GRID - PROBE_SIDE) // 2
    square = np.zeros(shape, dtype=bool)
    square[lo : lo + PROBE_SIDE, lo : lo + PROBE_SIDE] = True
    on = {normalise_entity_name(n) for n in present}
    masks = {e: square if normalise_entity_name(e) in on else np.zeros(shape, dtype=bool) for e in program.entities}
    flat = {t: np.zeros(shape, dtype=np.float32) for t in program.terrain}  # terrain adds cost only: probe it flat
    result = evaluate_program(program, masks, {}, sampling=(1.0, 1.0), shape=shape, terrain=flat)
    c = PROBE_GRID // 2
    return float(result.cost[c, c]), bool(result.lethal[c, c]), bool(result.keep_out[c, c])


def _ancestors(entity: str, hierarchy: Sequence[tuple[str, str]]) -> list[str]:
    parent_of = dict(hierarchy)
    out, node = [], parent_of.get(entity)
    while node is not None and node not in out and node != entity:
        out.append(node)
        node = parent_of.get(node)
    return out


def check_scale(
    program: Program,
    preferences: Sequence[Level],
    hierarchy: Sequence[tuple[str, str]] = (),
    cues: Sequence[ScaleCue] = (),
) -> None:
    """Refuse a program that contradicts its interpretation's cost scale (see the module doc).

    ``preferences`` are objects with ``entity``, ``weight`` (cost level) and ``lethal``;
    ``cues`` objects with ``kind`` and ``entity``. Raises :class:`CostProgramError` located at
    the offending entity's first use in the program.
    """
    empty, _, _ = _probe(program, ())
    if abs(empty - NEUTRAL) > NEUTRAL_TOLERANCE:
        cost_stmt = next((s for s in program.statements if s.target == "cost"), None)
        raise CostProgramError(
            f"ground covered by no entity costs {empty:.2f}; it must be neutral, {NEUTRAL:g} "
            f"(write e.g. cost = clip({NEUTRAL:g} + acc, 0, 1))",
            cost_stmt.line if cost_stmt else None,
            cost_stmt.col if cost_stmt else None,
        )
    cost_line = next((s for s in program.statements if s.target == "cost"), None)
    rules = [c for c in cues if (getattr(c, "hard", False) and c.kind in ("near", "far")) or c.kind == "no_cross"]
    if rules and not program.has_keep_out:
        c = rules[0]
        raise CostProgramError(
            f"the mission has a distance rule ({c.kind} {c.entity}"
            f"{f', {c.metres:g} m' if c.metres else ''}) but the program assigns no keep_out",
            cost_line.line if cost_line else None,
            cost_line.col if cost_line else None,
        )
    conditional = {c.entity for c in cues if c.kind == "if_near"}
    readable = {normalise_entity_name(e) for e in program.entities}
    for p in preferences:
        if p.entity in conditional or not off_neutral(p):
            continue
        if normalise_entity_name(p.entity) not in readable:
            raise CostProgramError(
                f"the program never reads '{p.entity}', which the mission "
                f"{'forbids' if p.lethal else 'prefers' if p.weight < NEUTRAL else 'avoids'}",
                cost_line.line if cost_line else None,
                cost_line.col if cost_line else None,
            )
        problem = _level_problem(p, *_probe(program, [p.entity, *_ancestors(p.entity, hierarchy)]))
        if problem:
            line, col = _locate(program, p.entity)
            raise CostProgramError(f"the program {problem}", line, col)


def _level_problem(p: Level, cost: float, lethal: bool, kept_out: bool) -> str | None:
    """What is wrong with how a probed program treats preference ``p`` on its own, if anything."""
    if p.lethal and not lethal:
        return f"leaves '{p.entity}' passable, but the mission forbids it (put it in lethal)"
    if is_obstacle(p) and not (kept_out or lethal):
        return (
            f"leaves '{p.entity}' out of keep_out, but at level {OBSTACLE_LEVEL:g} it is an obstacle "
            "(gone around wherever a route exists: add it to keep_out)"
        )
    if not p.lethal and p.weight > NEUTRAL + LEVEL_EPS and cost <= NEUTRAL:
        return (
            f"gives '{p.entity}' a cost of {cost:.2f}, at or below neutral ({NEUTRAL:g}), "
            f"but the mission avoids it (level {p.weight:g})"
        )
    if not p.lethal and p.weight < NEUTRAL - LEVEL_EPS and (cost >= NEUTRAL or lethal):
        return (
            f"gives '{p.entity}' a cost of {cost:.2f}, at or above neutral ({NEUTRAL:g}), "
            f"but the mission prefers it (level {p.weight:g})"
        )
    return None
