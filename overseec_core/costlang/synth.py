"""Synthesise a cost program from structured preferences (the offline path and the LLM fallback).

The program puts the OVerSeeC accumulation on overseec's cost scale (``LANGUAGE.md``, "The cost
scale"): neutral ground costs ``NEUTRAL`` = 0.5, and each entity moves its pixels from neutral
towards its own level by its confidence:

    cost = 0.5 + sum_c  (w_c - 0.5) * M_c^G * P^tau_c        (clipped to [0, 1])

- ``w_c`` is the entity's level (merge.cost_levels: preferred below 0.5, avoided above it);
  entities at the neutral level add nothing, so they cost what unlabelled ground costs,
- ``P^tau_c`` = ``P["c"]`` (probability gated by the entity's mask; 1 inside class rasters),
  so a weak detection of an avoided entity never drops below neutral (the paper's plain
  ``w * P`` would make a 40 %-sure building cheaper than open ground),
- ``M_c^G`` = the mask with the hierarchy applied: a parent minus all its descendants
  ("baseball field" is removed from "grass", so the field's weight is not added to grass'),
- lethal entities get 1.0 and are flagged in ``lethal`` (impassable for the planner).

Cues refine entity terms:

- ``centre`` / ``side`` (linear entities): inside the entity, add ``delta * centre(M, width)``
  (or ``edge``), where ``delta`` is half the gap to the next worse level, so the whole road still
  beats the next level and its centre line (or its sides) beats the rest of it;
- ``near`` (stay near e): graded nearness, the nearer the cheaper: ground that is not avoided
  within ``m`` of e costs at most ``NEAR_LEVEL`` (below neutral) beside e, rising linearly with
  the ground distance to ``NEAR_EDGE_LEVEL`` at ``m`` (beyond it, nothing changes); a hard
  ``near`` ("stay within 50 m of the road") makes everything farther than ``m`` from e a
  keep-out zone. Hard ``near`` cues with the same distance share one zone around all their
  entities (an entity matched to several layers, "road" -> "paved road" and "unpaved road", is
  within reach of either);
- ``far`` (keep m from e): graded, the closer the dearer: within ``m`` of e cost is at least
  ``FAR_LEVEL`` beside e, falling linearly with the ground distance to ``FAR_EDGE_LEVEL`` (still
  above neutral) at ``m``, and unchanged beyond (so a route that must pass keeps as far off as
  it can, instead of grazing e inside a flat band); a hard ``far`` ("at least 20 m from", "never
  within") makes the zone keep-out, as does any ``far`` cue on a lethal entity;
- ``unless_near`` / ``if_near`` (e's preference holds only away from / only near ``other``):
  elsewhere e's pixels are plain ground (neutral: "avoid the lawn except close to the sheds"
  lifts the objection near the sheds, whatever the sheds themselves cost), and a lethal e is
  lethal only where its preference holds. An exception to a preference or a permission ("the
  vegetation is fine unless near buildings") is the opposite: there the mission objects, so e
  costs what ``other`` costs, and at least ``CONDITION_AVOID_LEVEL``;
- ``no_cross`` (a rule never to cross e: "do not cross the railway"): e itself is a keep-out
  zone, so the planner crosses it only when it separates the points, once, at the cheapest place.

An entity at ``OBSTACLE_LEVEL`` (1.0, passable: the buildings and water nobody mentioned) is an
obstacle: its mask (less its sub-entities, which carry their own levels) joins ``keep_out`` the
same way, so routes go around it wherever they can, and cross it as little as possible where
they must.

Keep-out zones go into ``keep_out``: the planner treats them as impassable wherever a route
exists without them, and says so when it has to enter one.
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from overseec_core.costlang import scale
from overseec_core.costlang.scale import LEVEL_EPS, NEUTRAL, OBSTACLE_LEVEL, is_obstacle, off_neutral
from overseec_core.errors import InterpretError
from overseec_core.schema import CUE_KINDS, Cue, Entity, Preference

#: Nominal width of a linear feature for centre/side cues when the cue gives none (metres).
DEFAULT_LINEAR_WIDTH_M = 10.0
#: The cues' levels (``costlang.scale``, the one home of every level): near ground falls off from
#: NEAR_LEVEL to NEAR_EDGE_LEVEL, far ground from FAR_LEVEL to FAR_EDGE_LEVEL, linear in ground
#: metres; CONDITION_AVOID_LEVEL where an ``unless_near`` exception holds.
NEAR_LEVEL, NEAR_EDGE_LEVEL = scale.NEAR_LEVEL, scale.NEAR_EDGE_LEVEL
FAR_LEVEL, FAR_EDGE_LEVEL = scale.FAR_LEVEL, scale.FAR_EDGE_LEVEL
CONDITION_AVOID_LEVEL = scale.CONDITION_AVOID_LEVEL


def _quote(name: str) -> str:
    return json.dumps(name, ensure_ascii=False)


def _ident(name: str, taken: set[str], prefix: str) -> str:
    base = re.sub(r"[^0-9a-zA-Z]+", "_", name).strip("_").lower() or "entity"
    ident, k = f"{prefix}_{base}", 2
    while ident in taken:
        ident, k = f"{prefix}_{base}_{k}", k + 1
    taken.add(ident)
    return ident


def _num(x: float) -> str:
    text = f"{float(x):.6g}"
    return text if any(c in text for c in ".e") else text + ".0"


def _names(entities: Iterable[Entity | str]) -> dict[str, Entity]:
    out: dict[str, Entity] = {}
    for e in entities:
        ent = e if isinstance(e, Entity) else Entity(str(e))
        out.setdefault(ent.name, ent)
    return out


def _descendants(hierarchy: Sequence[tuple[str, str]], known: set[str]) -> dict[str, list[str]]:
    children: dict[str, list[str]] = {}
    for child, parent in hierarchy:
        if child in known and parent in known and child != parent:
            children.setdefault(parent, []).append(child)
    result: dict[str, list[str]] = {}
    for parent in children:
        seen: list[str] = []
        stack = list(children[parent])
        while stack:
            c = stack.pop()
            if c == parent or c in seen:
                continue
            seen.append(c)
            stack.extend(children.get(c, []))
        result[parent] = sorted(seen)
    return result


def _any_of(parts: Sequence[str]) -> str:
    """One part as it is, several joined with ``OR``."""
    return parts[0] if len(parts) == 1 else "OR(" + ", ".join(parts) + ")"


def _masks(names: Iterable[str]) -> list[str]:
    """``M[name]`` of each name."""
    return [f"M[{_quote(n)}]" for n in names]


def _without_children(name: str, children: Sequence[str]) -> str:
    """``M[name]`` less the masks of its sub-entities (which carry levels of their own)."""
    if not children:
        return f"M[{_quote(name)}]"
    return f"REMOVE(M[{_quote(name)}], {_any_of(_masks(children))})"


def _checked_preferences(ents: dict[str, Entity], preferences: Sequence[Preference]) -> dict[str, Preference]:
    """The first preference of each entity; an InterpretError for an unknown entity or a weight
    outside [0, 1]."""
    prefs: dict[str, Preference] = {}
    for p in preferences:
        if p.entity not in ents:
            raise InterpretError(
                f"preference for '{p.entity}', which is not among the entities ({', '.join(ents) or 'none'})"
            )
        if not 0 <= p.weight <= 1:
            raise InterpretError(
                f"preference for '{p.entity}' has weight {p.weight}; weights are cost levels in [0, 1]"
            )
        prefs.setdefault(p.entity, p)
    return prefs


def _check_cues(known: set[str], cues: Sequence[Cue]) -> None:
    """An InterpretError for an unknown cue kind, an unknown entity, or a condition without its
    other entity."""
    for c in cues:
        if c.kind not in CUE_KINDS:
            raise InterpretError(f"unknown cue kind '{c.kind}' (known: {', '.join(CUE_KINDS)})")
        for name in (c.entity, c.other):
            if name is not None and name not in known:
                raise InterpretError(f"cue '{c.kind}' refers to '{name}', which is not among the entities")
        if c.kind in ("unless_near", "if_near") and c.other is None:
            raise InterpretError(f"cue '{c.kind}' on '{c.entity}' needs the other entity")


def _header(prefs: dict[str, Preference]) -> list[str]:
    """The program's opening comments: the formula, then each preference by rank."""
    lines = [
        "# overseec cost program, synthesised from the interpreted preferences",
        f"# cost = {_num(NEUTRAL)} + sum_c (w_c - {_num(NEUTRAL)}) * M_c^G * P_c (hierarchy applied):",
        f"# neutral ground costs {_num(NEUTRAL)}, preferred entities less, avoided ones more;",
        "# lethal entities are impassable. Lower cost = preferred.",
    ]
    for name, p in sorted(prefs.items(), key=lambda kv: (kv[1].rank, kv[0])):
        flag = ", lethal" if p.lethal else ""
        lines.append(f"#   {name}: rank {p.rank}, level {_num(p.weight)}{flag}")
    return lines


def _level_of(prefs: dict[str, Preference], name: str | None) -> float:
    """The level of ``name``'s ground: its preference's, neutral when it has none or is lethal."""
    if name is not None and name in prefs and not prefs[name].lethal:
        return prefs[name].weight
    return NEUTRAL


def _alt_levels(prefs: dict[str, Preference], cues: Sequence[Cue]) -> dict[str, float]:
    """The level of each conditional entity where its preference fails: plain ground, or for a
    preference or permission with an exception ("fine unless near Y"), at least what Y costs."""
    alt_level: dict[str, float] = {}
    for c in cues:
        if c.kind in ("unless_near", "if_near") and c.entity in prefs and c.other is not None:
            own = prefs[c.entity]
            alt = NEUTRAL  # where an objection or a preference does not hold, the entity is plain ground
            if c.kind == "unless_near" and not own.lethal and own.weight <= NEUTRAL + LEVEL_EPS:
                # "fine unless near Y": near Y it is objected to, at least as much as Y itself
                alt = max(_level_of(prefs, c.other), CONDITION_AVOID_LEVEL)
            alt_level[c.entity] = alt
    return alt_level


def _hierarchy_masks(
    active: Iterable[str], desc: dict[str, list[str]], taken: set[str]
) -> tuple[list[str], dict[str, str]]:
    """Lines naming each active parent's mask less its sub-entities, and parent -> that name."""
    lines: list[str] = []
    gmask: dict[str, str] = {}
    for name in active:
        children = list(desc.get(name, []))
        if children:
            ident = _ident(name, taken, "g")
            lines.append(f"# hierarchy: {', '.join(children)} inside {name}")
            lines.append(f"{ident} = {_without_children(name, children)}")
            gmask[name] = ident
    return lines, gmask


def _condition_zones(
    active: dict[str, Preference], cues: Sequence[Cue]
) -> tuple[dict[str, list[str]], dict[str, list[str]]]:
    """For each conditional entity, the zones near which its preference holds (``if_near``: any
    of them) and those it holds away from (``unless_near``: all of them)."""
    near_any: dict[str, list[str]] = {}
    away_all: dict[str, list[str]] = {}
    for c in cues:
        # c.other is set for these kinds (checked before); the test narrows it for the type checker
        if c.kind in ("unless_near", "if_near") and c.entity in active and c.other is not None:
            metres = c.metres if c.metres is not None else DEFAULT_LINEAR_WIDTH_M
            zone = f"near(M[{_quote(c.other)}], {_num(metres)})"
            (near_any if c.kind == "if_near" else away_all).setdefault(c.entity, []).append(zone)
    return near_any, away_all


def _condition_masks(
    active: dict[str, Preference], cues: Sequence[Cue], alt_level: dict[str, float], taken: set[str]
) -> tuple[list[str], dict[str, str]]:
    """Lines naming where each conditional entity's preference holds, and entity -> that name."""
    near_any, away_all = _condition_zones(active, cues)
    lines: list[str] = []
    cond_ident: dict[str, str] = {}
    for name in sorted(set(near_any) | set(away_all)):
        ins, outs = near_any.get(name, []), away_all.get(name, [])
        conds = ([_any_of(ins)] if ins else []) + [f"NOT({z})" for z in outs]
        ident = _ident(name, taken, "applies")
        expr = conds[0] if len(conds) == 1 else "AND(" + ", ".join(conds) + ")"
        lines.append(f"# {name}'s preference holds only here; elsewhere it costs {_num(alt_level[name])}")
        lines.append(f"{ident} = {expr}")
        cond_ident[name] = ident
    return lines, cond_ident


def _shape_terms(prefs: dict[str, Preference], cues: Sequence[Cue]) -> dict[str, list[str]]:
    """The centre/side terms of each entity: half the gap to the next worse level, so the whole
    entity still beats that level and its centre line (or sides) beats the rest of it."""
    levels = sorted({p.weight for p in prefs.values() if not p.lethal} | {NEUTRAL, 1.0})

    def next_gap(w: float) -> float:
        higher = [x for x in levels if x > w + LEVEL_EPS]
        return (higher[0] if higher else 1.0) - w

    shape_terms: dict[str, list[str]] = {}
    for c in cues:
        if c.kind in ("centre", "side") and c.entity in prefs and not prefs[c.entity].lethal:
            width = c.metres if c.metres is not None else DEFAULT_LINEAR_WIDTH_M
            fn = "centre" if c.kind == "centre" else "edge"
            delta = next_gap(prefs[c.entity].weight) / 2.0
            if delta > 0:
                shape_terms.setdefault(c.entity, []).append(
                    f"{_num(delta)} * {fn}(M[{_quote(c.entity)}], {_num(width)})"
                )
    return shape_terms


@dataclass(frozen=True)
class _Masks:
    """The names a program gives masks: parents less their sub-entities (``gmask``), where each
    conditional preference holds (``cond_ident``) and what it costs elsewhere (``alt_level``)."""

    gmask: dict[str, str]
    cond_ident: dict[str, str]
    alt_level: dict[str, float]


def _term(name: str, p: Preference, shape: list[str] | None, masks: _Masks) -> str:
    """One entity's term of the accumulation."""
    w = 1.0 if p.lethal else p.weight
    offset = _num(w - NEUTRAL)
    if name in masks.cond_ident:
        offset = f"where({masks.cond_ident[name]}, {_num(w - NEUTRAL)}, {_num(masks.alt_level[name] - NEUTRAL)})"
    term = f"{offset} * P[{_quote(name)}]"
    if shape:
        term = f"({term} + {' + '.join(shape)}) * M[{_quote(name)}]"
    if name in masks.gmask:
        term = f"{term} * {masks.gmask[name]}"
    return term


def _accumulation(
    prefs: dict[str, Preference], active: Iterable[str], shape_terms: dict[str, list[str]], masks: _Masks
) -> list[str]:
    """The lines that set ``cost``: neutral plus every entity's term, clipped to [0, 1]."""
    names = sorted(set(active) | set(shape_terms), key=lambda n: (prefs[n].rank, n))
    terms = [_term(n, prefs[n], shape_terms.get(n), masks) for n in names]
    if not terms:
        return [f"cost = {_num(NEUTRAL)}"]
    acc = terms[0] if len(terms) == 1 else "sum(" + ", ".join(terms) + ")"
    return [f"acc = {acc}", f"cost = clip({_num(NEUTRAL)} + acc, 0.0, 1.0)"]


def _metres(c: Cue) -> float:
    """The cue's distance, or the default width of a linear feature when it gives none."""
    return c.metres if c.metres is not None else DEFAULT_LINEAR_WIDTH_M


def _hard_near_rules(cues: Sequence[Cue]) -> tuple[list[str], list[str]]:
    """Hard ``near`` cues: one keep-out zone per distance, outside reach of any of its entities
    (comment lines, keep-out parts)."""
    within: dict[float, list[str]] = {}
    for c in cues:
        if c.kind == "near" and c.hard:
            names = within.setdefault(_metres(c), [])
            if c.entity not in names:
                names.append(c.entity)
    lines, parts = [], []
    for metres, names in within.items():
        lines.append(f"# rule: stay within {_num(metres)} m of {' or '.join(names)}")
        parts.append(f"NOT(near({_any_of(_masks(names))}, {_num(metres)}))")
    return lines, parts


def _cue_rule(c: Cue, prefs: dict[str, Preference], cond_ident: dict[str, str]) -> tuple[list[str], list[str]]:
    """The lines and keep-out parts of one soft ``near``, ``far`` or ``no_cross`` cue."""
    metres = _metres(c)
    zone = f"near(M[{_quote(c.entity)}], {_num(metres)})"
    lethal_entity = c.entity in prefs and prefs[c.entity].lethal
    falloff = f"distance(M[{_quote(c.entity)}], {_num(metres)}) / {_num(metres)}"
    if c.kind == "near" and not c.hard:
        return [
            f"# prefer within {_num(metres)} m of {c.entity}, the nearer the better: ground there that is "
            f"not avoided costs at most {_num(NEAR_LEVEL)} beside it, {_num(NEAR_EDGE_LEVEL)} at {_num(metres)} m",
            f"cost = where(AND({zone}, cost <= {_num(NEUTRAL)}), min(cost, {_num(NEAR_LEVEL)} + "
            f"{_num(NEAR_EDGE_LEVEL - NEAR_LEVEL)} * {falloff}), cost)",
        ], []
    if c.kind == "far" and (c.hard or lethal_entity):
        return [f"# rule: keep at least {_num(metres)} m from {c.entity}"], [zone]
    if c.kind == "far":
        return [
            f"# keep {_num(metres)} m from {c.entity}, the closer the dearer: that zone costs at least "
            f"{_num(FAR_LEVEL)} beside it, {_num(FAR_EDGE_LEVEL)} at {_num(metres)} m",
            f"cost = where({zone}, max(cost, {_num(FAR_LEVEL)} - "
            f"{_num(FAR_LEVEL - FAR_EDGE_LEVEL)} * {falloff}), cost)",
        ], []
    if c.kind == "no_cross":
        part = f"M[{_quote(c.entity)}]"
        return [f"# rule: never cross {c.entity} (crossed once, at the cheapest place, only if it must be)"], [
            f"AND({part}, {cond_ident[c.entity]})" if c.entity in cond_ident else part
        ]
    return [], []


def _obstacles(
    prefs: dict[str, Preference], cues: Sequence[Cue], desc: dict[str, list[str]], masks: _Masks
) -> tuple[list[str], list[str]]:
    """Obstacles (entities at ``OBSTACLE_LEVEL`` with no ``no_cross`` rule): gone around wherever
    a route exists (comment lines, keep-out parts)."""
    lines, parts = [], []
    for name in sorted(prefs):
        if is_obstacle(prefs[name]) and not any(c.kind == "no_cross" and c.entity == name for c in cues):
            part = masks.gmask.get(name) or _without_children(name, desc.get(name, []))
            lines.append(f"# obstacle: {name} (level {_num(OBSTACLE_LEVEL)}) is gone around wherever a route exists")
            parts.append(f"AND({part}, {masks.cond_ident[name]})" if name in masks.cond_ident else part)
    return lines, parts


def _lethal(prefs: dict[str, Preference], masks: _Masks) -> list[str]:
    """The lines that mark lethal entities (where their preference holds) impassable."""
    parts = []
    for name in sorted(prefs):
        if not prefs[name].lethal:
            continue
        part = masks.gmask.get(name, f"M[{_quote(name)}]")
        if name in masks.cond_ident:
            part = f"AND({part}, {masks.cond_ident[name]})"
        parts.append(part)
    if not parts:
        return []
    return ["lethal = " + _any_of(parts), "cost = where(lethal, 1.0, cost)"]


def _keep_out(
    prefs: dict[str, Preference], cues: Sequence[Cue], desc: dict[str, list[str]], masks: _Masks
) -> tuple[list[str], list[str]]:
    """Every rule's lines in program order (hard near, then each cue, then obstacles), and the
    keep-out parts they add."""
    lines, parts = _hard_near_rules(cues)
    for c in cues:
        more_lines, more_parts = _cue_rule(c, prefs, masks.cond_ident)
        lines += more_lines
        parts += more_parts
    more_lines, more_parts = _obstacles(prefs, cues, desc, masks)
    return lines + more_lines, parts + more_parts


def program_from_interpretation(
    entities: Sequence[Entity | str],
    preferences: Sequence[Preference],
    hierarchy: Sequence[tuple[str, str]] = (),
    cues: Sequence[Cue] = (),
) -> str:
    """A deterministic cost program (text) from entities, preferences, hierarchy and cues.

    Raises :class:`InterpretError` when the data refer to entities that are not in ``entities``,
    use an unknown cue kind, or carry a negative weight.
    """
    ents = _names(entities)
    prefs = _checked_preferences(ents, preferences)
    _check_cues(set(ents), cues)
    taken: set[str] = {"cost", "lethal", "keep_out", "acc", "M", "P"}
    lines = _header(prefs)
    alt_level = _alt_levels(prefs, cues)
    active = {
        n: p
        for n, p in prefs.items()
        if off_neutral(p) or (n in alt_level and abs(alt_level[n] - p.weight) > LEVEL_EPS)
    }
    if not active and not cues:
        lines += ["# no preferences: every pixel is neutral ground", f"cost = {_num(NEUTRAL)}"]
        return "\n".join(lines) + "\n"
    desc = _descendants(hierarchy, set(ents))
    hierarchy_lines, gmask = _hierarchy_masks(active, desc, taken)
    condition_lines, cond_ident = _condition_masks(active, cues, alt_level, taken)
    masks = _Masks(gmask, cond_ident, alt_level)
    lines += hierarchy_lines + condition_lines
    lines += _accumulation(prefs, active, _shape_terms(prefs, cues), masks)
    rule_lines, keep_out_parts = _keep_out(prefs, cues, desc, masks)
    lines += rule_lines + _lethal(prefs, masks)
    if keep_out_parts:
        lines.append("keep_out = " + _any_of(keep_out_parts))
    return "\n".join(lines) + "\n"
