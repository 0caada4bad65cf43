"""Turn what an interpreter understood into an :class:`Interpretation`: defaults, ranks, hierarchy.

Both interpreters (offline and LLM) end here, so the rules are the same whichever ran:

* entities: the default set (road, trail, grass, tree, building, water) first, in that order,
  then the prompt's own entities in order of first mention;
* preferences: one per entity. What the prompt stated is an ordinal key (lower = better); an
  entity the prompt gives no preference is neutral (``lexicon.NEUTRAL``): no invented preference.
  Ranks are the dense rank of ``(lethal, key)`` over the entities *and the neutral level*
  (unlabelled ground always exists), so rank 1 is the best, equal keys share a rank and lethal
  entities rank last. Weights are the cost levels of those ranks (:func:`cost_levels`): the
  best preferred rank costs 0, neutral 0.5, the worst avoided 1.0, evenly spaced on each side,
  so costs are affine in rank whenever as many ranks lie below neutral as above it;
* hierarchy: (child, parent) pairs whose entities both exist, without self-pairs, duplicates or
  cycles;
* cues: only those naming existing entities and a known kind.

Whatever is dropped on the way is said in ``notes``.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import replace

from overseec_core.costlang import MAX_RADIUS_M, program_from_interpretation
from overseec_core.interpret import lexicon
from overseec_core.interpret.priors import BUILT_IN, PriorTable, apply_prior
from overseec_core.schema import CUE_KINDS, DEFAULT_ENTITIES, Cue, Entity, Interpretation, Preference, is_geometry

#: The cost of neutral ground: unmentioned entities, unlabelled pixels, "X is fine".
NEUTRAL = lexicon.NEUTRAL


def cost_levels(keys: Mapping[str, tuple[float, bool]]) -> tuple[dict[str, float], dict[str, int]]:
    """Cost level and rank of each entity from its ordinal key ``(key, lethal)``.

    Preferred keys (below ``NEUTRAL``) spread evenly over [0, 0.5): the best costs 0, so a
    ranking of preferred ground ("first roads, then trails, then grass") keeps the paper's
    evenly spaced rank weights. Avoided keys keep their own value as their level, on the one
    absolute scale the prior table uses too (``interpret.priors``): "a last resort" 0.6,
    "avoid" 0.7, "avoid as much as possible" 0.8, trees' prior 0.85, railways' 0.9, buildings'
    and water's 1.0 -- so an avoided field never ties with a house nobody mentioned.
    ``NEUTRAL`` costs 0.5; lethal entities cost 1 (and are impassable). Ranks are dense over
    the resulting levels with the neutral level always counted (:func:`dense_ranks`).
    """
    plain = {round(k, 6) for k, lethal in keys.values() if not lethal}
    below = sorted(k for k in plain if k < NEUTRAL)
    level = {k: NEUTRAL * i / len(below) for i, k in enumerate(below)}
    level.update({k: min(1.0, k) for k in plain if k > NEUTRAL})
    level[round(NEUTRAL, 6)] = NEUTRAL
    levels: dict[str, float] = {}
    for name, (k, lethal) in keys.items():
        levels[name] = 1.0 if lethal else round(level[round(k, 6)], 6)
    return levels, dense_ranks({n: (levels[n], keys[n][1]) for n in keys})


def make_entity(name: str, geometry: str | None = None, prompts: Sequence[str] = ()) -> Entity:
    """An entity with its geometry (given, else from the table / head word) and text prompts."""
    geom = geometry if is_geometry(geometry) else lexicon.geometry_of(name)
    return Entity(name=name, geometry=geom, prompts=tuple(prompts) or lexicon.prompts_of(name))


def merge_entities(mentioned: Iterable[Entity]) -> tuple[tuple[Entity, ...], list[str]]:
    """Defaults first (a mention of a default name refines its prompts), then the others.

    A default entity keeps its geometry even if a mention says otherwise (the segmentation
    thresholds depend on it); that is noted.
    """
    notes: list[str] = []
    by_name: dict[str, Entity] = {}
    order: list[str] = []
    for name, geom in DEFAULT_ENTITIES:
        by_name[name] = make_entity(name, geom)
        order.append(name)
    defaults = dict(DEFAULT_ENTITIES)
    for ent in mentioned:
        if ent.name in defaults:
            if ent.geometry != defaults[ent.name]:
                notes.append(
                    f"'{ent.name}' is a default {defaults[ent.name]} entity; "
                    f"kept {defaults[ent.name]} (the reply said {ent.geometry})"
                )
            if ent.prompts:
                by_name[ent.name] = Entity(ent.name, defaults[ent.name], ent.prompts, ent.threshold)
            continue
        if ent.name not in by_name:
            order.append(ent.name)
        by_name[ent.name] = ent
    return tuple(by_name[n] for n in order), notes


def clean_hierarchy(  # noqa: C901
    pairs: Iterable[tuple[str, str]],
    names: set[str],
    *,
    quiet: Iterable[tuple[str, str]] = (),
) -> tuple[tuple[tuple[str, str], ...], list[str]]:
    """Keep (child, parent) pairs over known names; drop self-pairs, duplicates, second parents
    and cycles (each said in the notes). ``quiet`` pairs (from the table) come after and are
    skipped without a note where they conflict: they are suggestions, not what the prompt said.
    """
    notes: list[str] = []
    kept: list[tuple[str, str]] = []
    parent_of: dict[str, str] = {}

    def closes_cycle(child: str, parent: str) -> bool:
        node: str | None = parent
        while node is not None:
            if node == child:
                return True
            node = parent_of.get(node)
        return False

    def problem(child: str, parent: str) -> str | None:
        if child not in names or parent not in names:
            return f"hierarchy pair ({child!r} inside {parent!r}) names an unknown entity; dropped"
        if child in parent_of:
            if parent_of[child] == parent:
                return ""
            return f"'{child}' already lies inside '{parent_of[child]}'; dropped the second parent '{parent}'"
        if closes_cycle(child, parent):
            return f"hierarchy pair ({child!r} inside {parent!r}) would make a cycle; dropped"
        return None

    for pairs_, noisy in ((pairs, True), (quiet, False)):
        for child, parent in pairs_:
            why = problem(child, parent)
            if why is None:
                parent_of[child] = parent
                kept.append((child, parent))
            elif why and noisy:
                notes.append(why)
    return tuple(kept), notes


def table_hierarchy(entities: Sequence[Entity]) -> list[tuple[str, str]]:
    """Part-of pairs from the table (lexicon.py) among the given entities."""
    names = {e.name for e in entities}
    pairs = []
    for ent in entities:
        parent = lexicon.parent_of(ent.name)
        if parent and parent in names and parent != ent.name:
            pairs.append((ent.name, parent))
    return pairs


def clean_cues(cues: Iterable[Cue], names: set[str]) -> tuple[tuple[Cue, ...], list[str]]:
    """Keep cues of a known kind over known entities (deduplicated, in order)."""
    notes: list[str] = []
    kept: list[Cue] = []
    for cue in cues:
        if cue.metres is not None and not 0 < cue.metres <= MAX_RADIUS_M:
            metres = min(float(MAX_RADIUS_M), max(0.5, cue.metres)) if cue.metres == cue.metres else float(MAX_RADIUS_M)
            notes.append(
                f"{cue.kind} cue on {cue.entity!r}: {cue.metres:g} m is outside (0, "
                f"{MAX_RADIUS_M:g}] m; used {metres:g} m"
            )
            cue = replace(cue, metres=metres)
        if cue.kind not in CUE_KINDS:
            notes.append(f"cue kind {cue.kind!r} is unknown (known: {', '.join(CUE_KINDS)}); dropped")
        elif cue.entity not in names or (cue.other is not None and cue.other not in names):
            notes.append(f"{cue.kind} cue on {cue.entity!r} names an unknown entity; dropped")
        elif cue not in kept:
            kept.append(cue)
    return tuple(kept), notes


def synthesize_program(entities, preferences, hierarchy, cues) -> str:
    """The deterministic cost program for these preferences (the cost language's generator)."""
    return program_from_interpretation(entities, preferences, hierarchy, cues)


def dense_ranks(levels: Mapping[str, tuple[float, bool]]) -> dict[str, int]:
    """Rank of each entity by its final ``(level, lethal)``, with the neutral level always
    counted (unlabelled ground exists): rank 1 is the cheapest, equal levels share a rank and
    lethal entities rank last."""
    plain = sorted({round(w, 6) for w, lethal in levels.values() if not lethal} | {round(NEUTRAL, 6)})
    rank_of = {w: i + 1 for i, w in enumerate(plain)}
    return {n: len(plain) + 1 if lethal else rank_of[round(w, 6)] for n, (w, lethal) in levels.items()}


def merge_priors(
    entities: Sequence[Entity],
    stated: Mapping[str, tuple[float, bool]],
    priors: PriorTable,
) -> tuple[dict[str, tuple[float, bool, bool]], list[str]]:
    """Each entity's ``(level, lethal, from_prior)``: stated preferences ranked on the cost
    scale (:func:`cost_levels`) and merged with the prior table (``interpret.priors``); an
    unstated entity takes its prior, else neutral. Notes say where a prior lifted an "avoid"."""
    keys: dict[str, tuple[float, bool]] = {}
    for ent in entities:
        if ent.name in stated:
            w, lethal = stated[ent.name]
            keys[ent.name] = (1.0 if lethal else min(1.0, max(0.0, float(w))), bool(lethal))
    levels, _ = cost_levels(keys) if keys else ({}, {})
    out: dict[str, tuple[float, bool, bool]] = {}
    notes: list[str] = []
    for ent in entities:
        prior = priors.for_name(ent.name)
        if ent.name in keys:
            key, lethal = keys[ent.name]
            level, lethal, raised = apply_prior(levels[ent.name], lethal, key, prior)
            if raised and prior is not None:
                notes.append(
                    f"'{ent.name}': avoided, and kept at its prior ({'lethal' if lethal else f'{level:g}'}, "
                    f"as {prior.entity}): an 'avoid' never makes a hazard cheaper than when left unsaid"
                )
            out[ent.name] = (round(level, 6), lethal, False)
        elif prior is not None:
            out[ent.name] = (prior.level, prior.lethal, True)
        else:
            out[ent.name] = (NEUTRAL, False, False)
    return out, notes


def finalize(
    prompt: str,
    *,
    mentioned: Sequence[Entity],
    stated: Mapping[str, tuple[float, bool]],
    hierarchy: Iterable[tuple[str, str]] = (),
    cues: Iterable[Cue] = (),
    unparsed: Sequence[str] = (),
    notes: Sequence[str] = (),
    source: str = "offline",
    program: str | None = None,
    phrases: Mapping[str, str] | None = None,
    priors: PriorTable | None = None,
) -> Interpretation:
    """Merge with the defaults and the priors, derive ranks and cost levels, clean hierarchy
    and cues, synthesize the program.

    ``stated`` maps entity name -> (ordinal key, lethal) for what the prompt said; ``phrases``
    entity name -> the prompt's words it came from. ``priors`` None means the built-in table
    (``interpret.priors.BUILT_IN``). ``program`` None means: derive it from the preferences
    with the cost language's generator.
    """
    phrases = phrases or {}
    table = BUILT_IN if priors is None else priors
    entities, out_notes = merge_entities(mentioned)
    names = {e.name for e in entities}
    for name in stated:
        if name not in names:  # cannot happen from finalize's callers; guard the invariant
            out_notes.append(f"preference for unknown entity {name!r} dropped")
    merged, prior_notes = merge_priors(entities, stated, table)
    ranks = dense_ranks({n: (w, lethal) for n, (w, lethal, _) in merged.items()})
    preferences = tuple(
        Preference(
            e.name,
            ranks[e.name],
            merged[e.name][0],
            merged[e.name][1],
            phrases.get(e.name, ""),
            prior=merged[e.name][2],
        )
        for e in entities
    )
    pairs, h_notes = clean_hierarchy(hierarchy, names, quiet=table_hierarchy(entities))
    kept_cues, c_notes = clean_cues(cues, names)
    all_notes = list(notes) + out_notes + prior_notes + h_notes + c_notes
    from_prior = [p for p in preferences if p.prior]
    if from_prior:
        all_notes.append(
            "hazards with no stated preference, at their priors ("
            + table.source
            + "; --no-priors or --priors FILE to change): "
            + ", ".join(f"{p.entity} {'lethal' if p.lethal else f'{p.weight:g}'}" for p in from_prior)
        )
    unstated = [p.entity for p in preferences if not p.prior and p.entity not in stated]
    if unstated:
        all_notes.append(f"no preference stated (neutral, {NEUTRAL:g}): " + ", ".join(unstated))
    if program is None:
        program = synthesize_program(entities, preferences, pairs, kept_cues)
    return Interpretation(
        prompt=prompt,
        entities=entities,
        preferences=preferences,
        hierarchy=pairs,
        cues=kept_cues,
        program=program,
        unparsed=tuple(unparsed),
        source=source,
        notes=tuple(all_notes),
    )
