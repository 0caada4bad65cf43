"""Fitting a program to the layers that exist: an interpretation's preferences, cues and priors
carried over to the matched layers (:mod:`overseec_core.interpret.matching`).

Synthesize receives an interpretation; it never interprets a prompt itself (the pipeline does,
then hands the interpretation here).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import replace

from overseec_core.costlang import check_program, program_from_interpretation
from overseec_core.costlang.scale import NEUTRAL, off_neutral
from overseec_core.errors import CostProgramError, InputError
from overseec_core.interpret.matching import RULES, match_entities, match_entity
from overseec_core.interpret.merge import dense_ranks
from overseec_core.interpret.priors import BUILT_IN as BUILT_IN_PRIORS
from overseec_core.interpret.priors import PriorTable
from overseec_core.limits import MAX_PROGRAM_BYTES, read_text_limited
from overseec_core.schema import Interpretation, Preference
from overseec_core.synthesize.options import CostmapOptions, ResolvedProgram


class NoLayerMatched(InputError):
    """None of the entities the prompt speaks about matches a layer, so its words would have no
    effect. Carries the facts (``entities``: the unmatched entities the prompt speaks about;
    ``layers``: the layer names) so that an adapter can phrase advice for its own fields (the
    dock's Entity aliases); the message is the CLI's, with its ``--alias`` option."""

    def __init__(self, entities: Sequence[str], layers: Sequence[str]) -> None:
        self.entities = tuple(entities)
        self.layers = tuple(layers)
        super().__init__(
            f"none of the entities the prompt speaks about "
            f"({', '.join(self.entities)}) matches a layer "
            f"({', '.join(self.layers) or 'none'}); name a layer or add "
            "--alias ENTITY=LAYER"
        )


def unmatched_entities(interp, matches) -> tuple[str, ...]:
    """The entities the prompt speaks about (stated preferences and cues, not priors) that match
    no layer: its words about them have no effect (``matches``: :func:`match_entities`'s, as
    ``ResolvedProgram.mapping`` keeps them)."""
    layer_of = {m.entity: m.layers for m in matches}
    return tuple(p.entity for p in interp.preferences if _said(p, interp.cues) and not layer_of.get(p.entity))


def _written_as(notes: Sequence[str], entity: str) -> str:
    """The words a prompt wrote for ``entity`` when the interpreter noted reading them as it
    ("read 'pylons' as 'electric tower'"), else ""."""
    pattern = re.compile(r"read '([^']+)' as '" + re.escape(entity) + "'")
    return next((hit.group(1) for n in notes if (hit := pattern.match(n))), "")


def _named(entity: str, phrase: str) -> str:
    """The words about an entity as reported, with its name where they do not hold it ("old
    barn: that one is derelict")."""
    return phrase if phrase and entity.split()[-1] in phrase.lower() else f"{entity}: {phrase}" if phrase else entity


def require_all_matched(no_effect: Sequence[str]) -> None:
    """``--strict``: an :class:`InputError` (exit 2) naming the prompt's words about entities no
    layer stands for (``no_effect``), so a batch run never plans as if a rule it cannot draw
    were kept."""
    if no_effect:
        quoted = "; ".join(repr(u) for u in no_effect)
        raise InputError(
            f"--strict: {len(no_effect)} clause(s) of the prompt name nothing the layers show: {quoted}; "
            "add --alias ENTITY=LAYER, or drop --strict to run without them"
        )


def check_program_choice(options: CostmapOptions) -> None:
    """Refuse options that give no program source or more than one (prompt, file, text)."""
    given = [x for x in (options.prompt, options.program, options.program_text) if x is not None]
    if len(given) != 1:
        raise InputError("give exactly one of --prompt TEXT or --program FILE")


def resolve_program(
    options: CostmapOptions, layer_names: Sequence[str], interpretation: Interpretation | None = None
) -> ResolvedProgram:
    """The program text from a file, inline text or the prompt's ``interpretation``.

    For a prompt, the interpreter's own program is used when every entity it reads has a layer;
    otherwise the program is synthesised again from its preferences restricted to the entities
    that have layers, and the notes say which entities were left out. The prompt is interpreted
    before this stage (:func:`overseec_core.pipeline.run_costmap`): Synthesize never interprets.
    """
    check_program_choice(options)
    if options.program is not None:
        text = read_text_limited(options.program, MAX_PROGRAM_BYTES, "--program")
        return ResolvedProgram(text, "file")
    if options.program_text is not None:
        return ResolvedProgram(options.program_text, "text")
    if interpretation is None:
        raise ValueError("a costmap from a prompt needs the prompt's interpretation (pipeline.run_costmap)")
    return fit_program(interpretation, layer_names, dict(options.aliases), options.prior_table(), strict=options.strict)


def _said(pref, cues) -> bool:
    """Whether the prompt said something about this entity: a preference it stated (a level off
    neutral, or a permission, which carries the words it came from) or a cue naming it. A level
    taken from the prior table is not something the prompt said."""
    if any(pref.entity in (c.entity, c.other) for c in cues):
        return True
    return not getattr(pref, "prior", False) and (off_neutral(pref) or bool(getattr(pref, "phrase", "")))


def layer_preferences(interp, matches, priors: PriorTable | None = None) -> tuple[dict, list[str]]:
    """The preference each matched layer takes, and notes on conflicts.

    When several entities land on one layer, what the prompt said wins over what it did not
    (priors and unstated defaults), then the closer match (alias, name, synonym/modifier,
    broader, and among broader matches the nearer kind: grass before the baseball field on a
    ``vegetation`` layer; "follow the road, avoid the highway" keeps the road's preference on a
    ``road`` layer), then a prior over plain neutral, then the preference farthest from neutral
    (lethal first, ties to the worse). A prior carries over only to a layer that has a prior of
    its own (trees' prior never makes a whole ``vegetation`` layer avoided).
    """
    return _preferences(_layer_choices(interp, matches, priors))


def _preferences(choices: dict[str, tuple]) -> tuple[dict, list[str]]:
    """:func:`layer_preferences` of choices made already (:func:`_layer_choices`)."""
    chosen, notes = {}, []
    for layer, (best, cands, overruled, allowed) in choices.items():
        chosen[layer] = replace(best, entity=layer)
        if allowed:
            notes.append(
                f"layer '{layer}' stands for {', '.join(p.entity for p in cands)}; '{best.entity}' is forbidden "
                f"but {', '.join(allowed)} allowed on it: the layer is avoided, not impassable"
            )
        elif overruled:
            notes.append(
                f"layer '{layer}' stands for {', '.join(p.entity for p in cands)}; "
                f"kept the preference of '{best.entity}' (over {', '.join(overruled)})"
            )
    return chosen, notes


def overruled_entities(interp, matches, priors: PriorTable | None = None) -> dict[str, str]:
    """The stated entities whose preference no layer keeps: every layer they match keeps another
    entity's different preference ("keep off the buildings, apart from the old barn" on one
    ``building`` layer: the barn's exception draws nothing). Entity -> the entity kept instead."""
    return _overruled(_layer_choices(interp, matches, priors))


def _overruled(choices: dict[str, tuple]) -> dict[str, str]:
    """:func:`overruled_entities` of choices made already (:func:`_layer_choices`)."""
    kept: set[str] = set()
    lost: dict[str, str] = {}
    for best, _, overruled, _ in choices.values():
        kept.add(best.entity)
        for entity in overruled:
            lost.setdefault(entity, best.entity)
    return {e: by for e, by in lost.items() if e not in kept}


def _layer_choices(interp, matches, priors: PriorTable | None) -> dict[str, tuple]:
    """Per matched layer: the preference it keeps (:func:`layer_preferences`' order), every
    candidate, and the stated entities whose different preference it overrules."""
    table = BUILT_IN_PRIORS if priors is None else priors
    prefs = {p.entity: p for p in interp.preferences}
    by_layer: dict[str, list] = {}
    for m in matches:
        if m.entity in prefs:
            pref = prefs[m.entity]
            for layer in m.layers:
                if getattr(pref, "prior", False) and table.for_name(layer) is None:
                    continue
                by_layer.setdefault(layer, []).append((pref, (RULES.index(m.rule), m.depth)))
    out = {}
    for layer, cands in by_layer.items():
        best, _ = max(
            cands,
            key=lambda pr: (
                _said(pr[0], interp.cues),
                -pr[1][0],
                -pr[1][1],
                off_neutral(pr[0]),
                pr[0].lethal,
                round(abs(pr[0].weight - NEUTRAL), 6),  # levels are 6-decimal: 0.7 - 0.5 ties 0.5 - 0.3
                pr[0].weight,
            ),
        )
        overruled = [
            p.entity
            for p, _ in cands
            if p is not best
            and _said(p, interp.cues)
            and (abs(p.weight - best.weight) > 1e-9 or p.lethal != best.lethal)
        ]
        allowed = _allowed_beside(best, cands, interp.cues)
        if allowed:  # a rule that cannot be kept bends as little as possible
            best = replace(best, lethal=False)
            overruled = [e for e in overruled if e not in allowed]
        out[layer] = (best, [p for p, _ in cands], overruled, allowed)
    return out


def _allowed_beside(best, cands: list, cues) -> tuple[str, ...]:
    """The stated entities allowed (neutral or preferred) on the layer whose kept preference
    ``best`` forbids another entity that the layer stands for as well as for it (``cands``:
    (preference, match key) pairs): "keep out from under the conifers; the oaks you can go
    under" over one ``tree`` layer, not "shallow water is fine" on a ``deep water`` layer that
    matches the deep water by name. The layer cannot forbid the one and allow the other, and an
    impassable layer would take away what the prompt allows, so it is avoided (1.0, passable)
    and the forbidding rule is reported as not kept (:func:`bent_rules`)."""
    key = next((k for p, k in cands if p is best), None)
    if not best.lethal:
        return ()
    return tuple(
        p.entity
        for p, k in cands
        if k == key and p.entity != best.entity and _said(p, cues) and not p.lethal and p.weight <= NEUTRAL + 1e-9
    )


def bent_rules(choices: dict[str, tuple]) -> dict[str, tuple[str, tuple[str, ...]]]:
    """The forbidden entities whose layer is only avoided (:func:`_allowed_beside`): entity ->
    (layer, the entities allowed on it)."""
    return {best.entity: (layer, allowed) for layer, (best, _, _, allowed) in choices.items() if allowed}


def layer_priors(layer_names: Sequence[str], taken: Iterable[str], priors: PriorTable) -> dict:
    """Preferences from the prior table for layers no prompt entity stands for ("railway (Train)"
    in a class raster when the prompt never speaks of railways)."""
    out = {}
    for layer in layer_names:
        prior = priors.for_name(layer)
        if layer not in taken and prior is not None:
            out[layer] = Preference(layer, 0, prior.level, prior.lethal, prior=True)
    return out


def _layer_cues(interp, layer_of: Mapping[str, tuple[str, ...]]) -> tuple[list, list[str]]:
    """Cues carried over to layers; a condition whose other entity lands on the entity's own
    layer ("except at level crossings" on a ``railway`` layer) cannot be told apart: dropped."""
    cues, notes = [], []
    for c in interp.cues:
        for a in layer_of.get(c.entity, ()):
            others = layer_of.get(c.other, ()) if c.other else (None,)
            for b in others:
                if c.other and b == a:
                    notes.append(
                        f"'{c.kind}' of {c.entity} near {c.other}: both are the layer "
                        f"'{a}', so the condition cannot be drawn; dropped"
                    )
                    continue
                cues.append(replace(c, entity=a, other=b))
    return cues, notes


def fit_program(
    interp,
    layer_names: Sequence[str],
    aliases: Mapping[str, str] | None = None,
    priors: PriorTable | None = None,
    strict: bool = False,
) -> ResolvedProgram:
    """An interpretation's program, fitted to the layers that exist.

    Prompt entities are matched to layer names (:mod:`interpret.matching`: normalised names,
    synonyms, modifiers, broader classes, user ``aliases``). The interpretation's own program
    (LLM-written or synthesised) is kept when every entity matches a layer of its own name and
    no other layer takes a prior; otherwise a program is synthesised from the preferences
    carried over to the matched layers plus the priors (``priors``; None = the built-in table)
    of the layers no entity stands for. Raises :class:`InputError` when the prompt says nothing
    this tool understood, or nothing it says matches a layer (its words would have no effect);
    with ``strict`` also when anything it says matches no layer (:func:`require_all_matched`).
    A prompt that only gives permissions ("buildings are fine") is kept, with a note: without
    priors to fall back on, its costmap is the shortest-route one.
    """
    table = BUILT_IN_PRIORS if priors is None else priors
    notes = list(getattr(interp, "notes", ()))
    unparsed = list(getattr(interp, "unparsed", ()))
    source = f"prompt:{getattr(interp, 'source', 'offline')}"
    data = interp.to_json() if hasattr(interp, "to_json") else None
    matches = match_entities([e.name for e in interp.entities], layer_names, aliases)
    mapping_note = "entities -> layers: " + "; ".join(m.describe() for m in matches)
    stated = [p for p in interp.preferences if _said(p, interp.cues)]
    layer_of = {m.entity: m.layers for m in matches}
    unmatched = unmatched_entities(interp, matches)
    # every clause of the brief is accounted for: one warning per clause that was not understood
    warnings = [f"not understood, so it has no effect: {u!r}" for u in unparsed]
    said = {p.entity: p.phrase for p in interp.preferences if getattr(p, "phrase", "")}
    for entity in unmatched:  # a cue's entity has no phrase: the words the prompt wrote for it
        said.setdefault(entity, _written_as(notes, entity))
    warnings += [
        f"'{entity}' matches no layer, so the prompt's words about it have no effect"
        + (f" ({said[entity]!r})" if said.get(entity) else "")
        + f" (layers: {', '.join(layer_names)}); add --alias '{entity}=LAYER'"
        for entity in unmatched
    ]
    choices = _layer_choices(interp, matches, table)  # made once: the overruled and the layers' preferences
    overruled = _overruled(choices)
    warnings += [
        f"'{entity}' shares its layer with '{by}', whose rule the layer keeps, so the prompt's words about it "
        f"have no effect" + (f" ({said[entity]!r})" if said.get(entity) else "")
        for entity, by in overruled.items()
    ]
    bent = bent_rules(choices)
    warnings += [
        f"'{entity}' is forbidden, but its layer '{layer}' also stands for {', '.join(allowed)}, which the prompt "
        f"allows: the layer is avoided, not impassable, so the rule is not kept as stated"
        + (f" ({said[entity]!r})" if said.get(entity) else "")
        for entity, (layer, allowed) in bent.items()
    ]
    no_effect = (
        tuple(said.get(entity) or entity for entity in unmatched)
        + tuple(_named(entity, said.get(entity, "")) for entity in overruled)
        + tuple(_named(entity, said.get(entity, "")) for entity in bent)
    )
    if strict:
        require_all_matched(no_effect)
    warnings += [
        f"alias {key}={target}: no layer is called '{target}' (layers: {', '.join(layer_names)}); ignored"
        for key, target in (aliases or {}).items()
        if match_entity(target, layer_names).rule != "name"
    ]
    if stated and not any(layer_of.get(p.entity) for p in stated):
        raise NoLayerMatched([p.entity for p in stated], layer_names)
    if not stated:
        raise InputError(
            "the prompt states no preference this tool understood, so the costmap "
            "would be uniform; say what to prefer or avoid"
            + (f" (not understood: {'; '.join(repr(u) for u in unparsed)})" if unparsed else "")
        )
    notes.append(mapping_note)
    prefs, conflict_notes = _preferences(choices)
    extra = layer_priors(layer_names, prefs, table)
    if extra:
        notes.append(
            "layers no prompt entity stands for, at their priors: "
            + ", ".join(f"{n} {'lethal' if p.lethal else f'{p.weight:g}'}" for n, p in extra.items())
        )
    permission_only = all(not off_neutral(p) for p in stated) and not interp.cues
    if permission_only:
        moved = [n for n, p in {**prefs, **extra}.items() if off_neutral(p)]
        notes.append(
            "the prompt only gives permission ("
            + ", ".join(p.entity for p in stated)
            + " at neutral); "
            + (
                f"the unsaid hazards keep their priors ({', '.join(moved)})"
                if moved
                else "nothing else is priced, so this is the shortest-route costmap"
            )
        )
    identity = all(m.layers == (m.entity,) for m in matches if m.layers)
    if identity and not extra:
        try:
            check_program(interp.program, layer_names)
            return ResolvedProgram(interp.program, source, tuple(notes), data, matches, tuple(warnings), no_effect)
        except CostProgramError:
            pass
    cues, cue_notes = _layer_cues(interp, layer_of)
    notes += conflict_notes + cue_notes
    prefs.update(extra)
    ranks = dense_ranks({n: (p.weight, p.lethal) for n, p in prefs.items()})
    prefs = {n: replace(p, rank=ranks[n]) for n, p in prefs.items()}
    entities = list(prefs)
    hierarchy = {
        (a, b) for c, p in interp.hierarchy for a in layer_of.get(c, ()) for b in layer_of.get(p, ()) if a != b
    }
    text = program_from_interpretation(entities, list(prefs.values()), sorted(hierarchy), cues)
    return ResolvedProgram(text, source + "+refit", tuple(notes), data, matches, tuple(warnings), no_effect)
