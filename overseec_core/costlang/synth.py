"""Synthesise a cost program from structured preferences (the offline path and the LLM fallback).

The program implements the OVerSeeC accumulation (paper, Synthesize):

    cost = sum_c  w_c * M_c^G * P^tau_c

- ``P^tau_c`` = ``P["c"]`` (probability gated by the entity's mask),
- ``M_c^G`` = the mask with the hierarchy applied: a parent minus all its descendants
  ("baseball field" is removed from "grass", so the field's weight is not added to grass'),
- the sum is divided by the largest weight when that exceeds 1 (weights are normally in [0, 1]),
  then limited to 1: the costmap is in [0, 1] by construction, with constants from the program
  only (no data-dependent rescaling), so blocks evaluate exactly like the whole image,
- pixels covered by no preferred/avoided entity get the maximum, 1.0,
- lethal entities get 1.0 and are flagged in ``lethal`` (impassable for the planner).

Cues refine entity terms:

- ``centre`` / ``side`` (linear entities): inside the entity, add ``delta * centre(M, width)``
  (or ``edge``), where ``delta`` is half the gap to the next worse weight, so the whole road still
  beats the next entity and its centre line (or its sides) beats the rest of it;
- ``near`` (prefer within m of e): away from ``near(M[e], m)`` cost becomes ``0.5 + 0.5 * cost``
  (half way to the maximum);
- ``far`` (keep at least m from e): ``cost = 1`` within ``near(M[e], m)``; lethal too when e is;
- ``unless_near`` / ``if_near`` (e's preference holds only away from / only near ``other``):
  elsewhere e's pixels take ``other``'s weight (or 0.5 when ``other`` has no preference), and a
  lethal e is lethal only where its preference holds.
"""

from __future__ import annotations

import json
import re
from typing import Iterable, Sequence

from ..errors import InterpretError
from ..interpret.schema import CUE_KINDS, Cue, Entity, Preference

#: Nominal width of a linear feature for centre/side cues when the cue gives none (metres).
DEFAULT_LINEAR_WIDTH_M = 10.0
#: Weight an entity takes where a conditional preference does not hold and ``other`` has none.
NEUTRAL_WEIGHT = 0.5
#: How strongly a ``near`` cue pushes cost towards the maximum away from the entity.
NEAR_PENALTY = 0.5


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


def program_from_interpretation(entities: Sequence[Entity | str], preferences: Sequence[Preference],
                                hierarchy: Sequence[tuple[str, str]] = (),
                                cues: Sequence[Cue] = ()) -> str:
    """A deterministic cost program (text) from entities, preferences, hierarchy and cues.

    Raises :class:`InterpretError` when the data refer to entities that are not in ``entities``,
    use an unknown cue kind, or carry a negative weight.
    """
    ents = _names(entities)
    known = set(ents)
    prefs: dict[str, Preference] = {}
    for p in preferences:
        if p.entity not in known:
            raise InterpretError(f"preference for '{p.entity}', which is not among the entities "
                                 f"({', '.join(ents) or 'none'})")
        if not p.weight >= 0:
            raise InterpretError(f"preference for '{p.entity}' has weight {p.weight}; weights are >= 0")
        prefs.setdefault(p.entity, p)
    for c in cues:
        if c.kind not in CUE_KINDS:
            raise InterpretError(f"unknown cue kind '{c.kind}' (known: {', '.join(CUE_KINDS)})")
        for name in (c.entity, c.other):
            if name is not None and name not in known:
                raise InterpretError(f"cue '{c.kind}' refers to '{name}', which is not among the entities")
        if c.kind in ("unless_near", "if_near") and c.other is None:
            raise InterpretError(f"cue '{c.kind}' on '{c.entity}' needs the other entity")

    taken: set[str] = {"cost", "lethal", "acc", "covered", "M", "P"}
    lines = ["# overseec cost program, synthesised from the interpreted preferences",
             "# cost = sum_c w_c * M_c^G * P_c (hierarchy applied); uncovered pixels cost 1.0;",
             "# lethal entities cost 1.0 and are impassable. Lower cost = preferred."]
    for name, p in sorted(prefs.items(), key=lambda kv: (kv[1].rank, kv[0])):
        flag = ", lethal" if p.lethal else ""
        lines.append(f"#   {name}: rank {p.rank}, weight {_num(p.weight)}{flag}")

    if not prefs:
        lines.append("# no preferences: every pixel costs the same")
        lines.append("cost = 1.0")
        return "\n".join(lines) + "\n"

    desc = _descendants(hierarchy, known)
    gmask: dict[str, str] = {}
    for name in prefs:
        children = [c for c in desc.get(name, [])]
        if children:
            ident = _ident(name, taken, "g")
            removed = children[0] if len(children) == 1 else None
            what = f'M[{_quote(removed)}]' if removed else \
                "OR(" + ", ".join(f"M[{_quote(c)}]" for c in children) + ")"
            lines.append(f"# hierarchy: {', '.join(children)} inside {name}")
            lines.append(f"{ident} = REMOVE(M[{_quote(name)}], {what})")
            gmask[name] = ident

    weights = sorted({p.weight for p in prefs.values()})
    scale = max(1.0, weights[-1])

    def weight_of(name: str | None) -> float:
        if name is not None and name in prefs:
            return prefs[name].weight
        return NEUTRAL_WEIGHT * scale

    def next_gap(w: float) -> float:
        higher = [x for x in weights if x > w]
        return (higher[0] if higher else scale) - w

    conditions: dict[str, list[str]] = {}
    alt_weight: dict[str, float] = {}
    for c in cues:
        if c.kind in ("unless_near", "if_near") and c.entity in prefs:
            metres = c.metres if c.metres is not None else DEFAULT_LINEAR_WIDTH_M
            zone = f"near(M[{_quote(c.other)}], {_num(metres)})"
            conditions.setdefault(c.entity, []).append(zone if c.kind == "if_near" else f"NOT({zone})")
            alt_weight[c.entity] = weight_of(c.other)

    cond_ident: dict[str, str] = {}
    for name, conds in conditions.items():
        ident = _ident(name, taken, "applies")
        expr = conds[0] if len(conds) == 1 else "AND(" + ", ".join(conds) + ")"
        lines.append(f"# {name}'s preference holds only here; elsewhere it weighs "
                     f"{_num(alt_weight[name])}")
        lines.append(f"{ident} = {expr}")
        cond_ident[name] = ident

    shape_terms: dict[str, list[str]] = {}
    for c in cues:
        if c.kind in ("centre", "side") and c.entity in prefs:
            width = c.metres if c.metres is not None else DEFAULT_LINEAR_WIDTH_M
            fn = "centre" if c.kind == "centre" else "edge"
            delta = next_gap(prefs[c.entity].weight) / 2.0
            if delta > 0:
                shape_terms.setdefault(c.entity, []).append(
                    f"{_num(delta)} * {fn}(M[{_quote(c.entity)}], {_num(width)})")

    terms = []
    for name in sorted(prefs, key=lambda n: (prefs[n].rank, n)):
        w = prefs[name].weight
        weight = _num(w)
        if name in cond_ident:
            weight = f"where({cond_ident[name]}, {_num(w)}, {_num(alt_weight[name])})"
        term = f"{weight} * P[{_quote(name)}]"
        if name in shape_terms:
            term = f"({weight} * P[{_quote(name)}] + {' + '.join(shape_terms[name])})" \
                   f" * M[{_quote(name)}]"
        if name in gmask:
            term = f"{term} * {gmask[name]}"
        terms.append(term)
    acc = terms[0] if len(terms) == 1 else "sum(" + ", ".join(terms) + ")"
    lines.append(f"acc = {acc}")
    if scale > 1.0:
        lines.append(f"acc = acc / {_num(scale)}")
    covered = [f"M[{_quote(n)}]" for n in sorted(prefs)]
    lines.append("covered = " + (covered[0] if len(covered) == 1 else "OR(" + ", ".join(covered) + ")"))
    lines.append("cost = where(covered, min(acc, 1.0), 1.0)")

    for c in cues:
        metres = c.metres if c.metres is not None else DEFAULT_LINEAR_WIDTH_M
        if c.kind == "near":
            lines.append(f"# prefer within {_num(metres)} m of {c.entity}")
            lines.append(f"cost = where(near(M[{_quote(c.entity)}], {_num(metres)}), cost, "
                         f"{_num(NEAR_PENALTY)} + {_num(1.0 - NEAR_PENALTY)} * cost)")
        elif c.kind == "far":
            lines.append(f"# keep at least {_num(metres)} m from {c.entity}")
            lines.append(f"cost = where(near(M[{_quote(c.entity)}], {_num(metres)}), 1.0, cost)")

    lethal_parts = []
    for name in sorted(prefs):
        if not prefs[name].lethal:
            continue
        part = gmask.get(name, f"M[{_quote(name)}]")
        if name in cond_ident:
            part = f"AND({part}, {cond_ident[name]})"
        lethal_parts.append(part)
    for c in cues:
        if c.kind == "far" and c.entity in prefs and prefs[c.entity].lethal:
            metres = c.metres if c.metres is not None else DEFAULT_LINEAR_WIDTH_M
            lethal_parts.append(f"near(M[{_quote(c.entity)}], {_num(metres)})")
    if lethal_parts:
        lines.append("lethal = " + (lethal_parts[0] if len(lethal_parts) == 1
                                    else "OR(" + ", ".join(lethal_parts) + ")"))
        lines.append("cost = where(lethal, 1.0, cost)")
    return "\n".join(lines) + "\n"
