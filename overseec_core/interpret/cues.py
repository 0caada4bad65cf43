"""A clause's geometric cues: centre and side of a line, near and far (with their distances,
bounds and softeners), the object a near-far rule keeps away from, exceptions, and how graded
cues are shaped by the reaches and restatements around them (:mod:`.graded` claims those).

Read by :func:`offline._analyse_clause` for each clause; :func:`resolve_graded` runs once the
whole prompt is read (a restatement may name its cue's entity only by reference).
"""

from __future__ import annotations

from dataclasses import replace

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.clauses import Clause, Groups, nearest_group
from overseec_core.interpret.sentence import Found, Mention, Sentence
from overseec_core.interpret.statements import State
from overseec_core.schema import Cue


def centre_side_cue(
    st: State, c: Clause, kind: str, m: Mention, cf: Found, groups: Groups, used_groups: set[int]
) -> None:
    """A centre or side cue on a linear entity (on an areal one: noted and ignored); the entity
    takes the nearest tier, or is preferred ("on the side of the road": travelling on it)."""
    st.mention(m.name)
    if lx.geometry_of(m.name) != "linear":
        if kind == "side" and any(f.value in ("near", "far") and m in f.mentions for f in c.found):
            return  # "6 m off the water's edge": a distance from an area is from its edge
        st.notes.append(f"'{kind} of {m.name}' needs a linear entity ({m.name} is areal); ignored")
        st.fragment(c.text(st.prompt))
        return
    st.cues.append(Cue(kind, m.name))
    if m.name in c.assigned:
        return
    if groups:
        gi = nearest_group(groups, m)
        used_groups.add(gi)
        c.assigned[m.name] = groups[gi][2]
        c.took(m.name, groups[gi][:2], (cf.start, cf.end), (m.start, m.end))
    else:
        c.assigned[m.name] = "prefer"
        c.took(m.name, (cf.start, cf.end), (m.start, m.end))


def _near_far_cue(
    st: State,
    sent: Sentence,
    c: Clause,
    f: Found,
    targets: list[Mention],
    groups: Groups,
    used_groups: set[int],
    softened: bool,
) -> None:
    """A near/far cue: keep far from each object; near an object, the clause's other targets'
    preference applies ("avoid grass near roads"), else stay near it, or keep away from it when
    an avoiding trigger governs it ("avoid going near buildings")."""
    # "avoid grass near roads": the thing that is near comes before the cue word; a noun after
    # its object ("stay near the river throughout the transit") is no such thing
    # ... nor the subject of the keeping verb the cue completes ("the survey track should remain
    # in the vicinity of the road", "the unit is required to keep within sight of the trail")
    others = [
        m
        for m in targets
        if m.name not in {o.name for o in f.mentions}
        and m.start < f.start
        and not any(w in lx.PREDICATE_WORDS for w in sent.words[m.end : f.start])
        # ... nor what the cue's own verb acts on ("paths were biased toward the paved road",
        # "trajectories were softly penalised within 8 m of the crowns"): the route itself
        and not any(w in lx.ROUTE_PREDICATES for w in sent.words[m.end : f.start + 2])
    ]
    # absolute wording makes a rule of a stated distance; with none ("stay close to the road at
    # all times") there is no boundary to keep, so the cue is graded (no invented limit)
    # ... but a buffer is a zone by name ("a mandatory stand-off from the railway"): worded as
    # absolute with no number, it keeps out the default distance
    # (or a clearance: "stay clear of the railway at all times")
    # ... or a distance named without its number ("keep a safe distance from the school at all
    # times", "a stone's throw from the building at all times")
    zone = f.value == "far" and any(
        w in lx.CLEARANCE_NOUNS or w in ("clear", "distance", "throw") for w in sent.words[f.start : f.end]
    )
    hard = (f.hard or (sent.absolute() and (f.metres is not None or zone))) and not softened
    # a graded cue with no number prices distance over a reach a route feels; a rule or a
    # condition ("avoid grass near roads") with none keeps the plain default
    plain = f.metres if f.metres is not None else lx.DEFAULT_CUE_DISTANCE_M
    metres = plain if hard or f.metres is not None else lx.DEFAULT_GRADED_DISTANCE_M
    for obj in f.mentions:
        if f.value == "far":
            st.cues.append(Cue("far", obj.name, metres, hard=hard))
        elif others:  # "avoid grass near roads": grass's preference applies near roads
            for t in others:
                st.cues.append(Cue("if_near", t.name, plain, obj.name))
        else:
            _near_object(st, sent, c, f, obj, metres, hard, groups, used_groups)


def distance_cues(
    st: State,
    sent: Sentence,
    c: Clause,
    cues: list[Found],
    targets: list[Mention],
    groups: Groups,
    used_groups: set[int],
) -> None:
    """The clause's near/far cues (softened by its wording or the sentence's label) and the
    graded afterthoughts that shape the cue before them."""
    softened = (
        any(sent.words[j] in lx.SOFTENERS for j in range(c.start, c.end))
        or any(f.kind == "modifier" and f.value == "soft" for f in c.found)
        or "soft" in rule_labels(sent)
        or any(w in lx.ADVISORY_WORDS for w in sent.words)  # "Mitigation measure M4 (advisory): ..."
        or any(f.kind == "filler" and f.value == "slack" for f in sent.found)  # "not the end of the world"
    )
    for f in cues:
        if f.value in ("near", "far"):
            _near_far_cue(st, sent, c, f, targets, groups, used_groups, softened)
        elif f.value in ("graded_far", "graded_near", "graded_reach"):
            _shape_graded(st, sent, c, f)


def excepted(st: State, c: Clause, f: Found, prev: Clause | None = None) -> None:
    """An entity excepted from its clause ("lawns are fine except the cricket pitch") takes the
    other side of the clause's tier (avoided where the others are fine, fine where they are
    avoided); a later statement about it ("which must not be driven on") is stated after and
    counts too. A clause of its own after a comma ("Avoid the grass, except the mown strip")
    excepts from the clause before it in the sentence. With nothing to except it from, the
    words are not understood."""
    names = {m.name for m in f.mentions}
    tiers = [t for n, t in c.assigned.items() if n not in names]
    if not tiers and prev is not None and prev.sent == c.sent and f.start == c.start:
        tiers = [t for n, t in prev.assigned.items() if n not in names]
    if not tiers:
        st.fragment(st.prompt[c.toks[f.start].start : c.toks[f.end - 1].end])
        return
    for m in f.mentions:
        st.mention(m.name)
        c.assigned[m.name] = lx.EXCEPTED_TIER.get(tiers[0], "avoid")
        c.took(m.name, (f.start, f.end))


def rule_labels(sent: Sentence) -> set[str]:
    """How strict the sentence's labels say its rule is ("Hard constraint: ..."): {"hard"},
    {"soft"}, or empty."""
    return {v for i in range(sent.n - 1) if (v := lx.RULE_LABELS.get((sent.words[i], sent.words[i + 1])))}


#: The cues a strictness qualifier may speak of (a graded one's reach or shape included).
_DISTANCE_CUES = frozenset({"near", "far", "graded_reach", "graded_far", "graded_near"})


def qualifier_clause(sent: Sentence, c: Clause) -> bool:
    """Whether the clause only says how strict the sentence's distance rule is ("Hard
    constraint", "mandatory", "25 m minimum"): read with the rule, not left over."""
    if not any(f.kind == "cue" and f.value in _DISTANCE_CUES for f in sent.found):
        return False
    read = lx.RULE_WORDS | lx.SOFTENERS | lx.FILLER | lx.SEPARATORS | lx.ARTICLES | {"soft", "constraint"}
    if rule_labels(sent):  # "..., ok to violate", "..., can be violated": the label's own words
        read = read | {w for pair in lx.RULE_LABELS for w in pair} | {"ok", "okay", "fine"}
    return all(sent.words[j] in read or sent.claimed[j] == "cue" for j in range(c.start, c.end))


def _shape_graded(st: State, sent: Sentence, c: Clause, f: Found) -> None:
    """ "..., the further the better (up to 25 m)": the last near/far cue stated so far is graded
    (soft), reaching neutral at the distance given; "tapering off by 30 m" (``graded_reach``) sets
    where the last soft near/far cue reaches neutral, or with none grades what the prompt avoids
    (:func:`resolve_graded`). With nothing to grade the words are not understood."""
    kind = f.value.removeprefix("graded_")
    for k in range(len(st.cues) - 1, -1, -1):
        cue = st.cues[k]
        if cue.kind == kind or (kind == "reach" and cue.kind in ("near", "far") and not cue.hard):
            st.cues[k] = replace(cue, metres=cue.metres if f.metres is None else f.metres, hard=False)
            return
    text = st.prompt[c.toks[f.start].start : c.toks[f.end - 1].end]
    if kind in ("near", "far"):  # no cue before it: grade what the prompt avoids or prefers
        st.graded.append((kind, f.metres, text))
    elif kind == "reach" and st.graded and st.graded[-1][0] == "reach":  # "mode: graded, falloff: 25 m"
        if f.metres is not None:
            st.graded[-1] = ("reach", f.metres, st.graded[-1][2])
    elif kind == "reach" and (f.metres is not None or not f.mentions and _said_graded(sent, f)):
        st.graded.append(("reach", f.metres, text))  # "avoid the pond, tapering off by 25 m": graded
    else:
        st.fragment(text)


def resolve_graded(st: State) -> None:
    """ "keep away from the water, the closer the worse": an afterthought with no cue before it
    grades the entity mentioned last whose tier keeps away from it (far: avoided or worse) or
    draws to it (near: preferred); with none, its words are not understood."""
    for said, metres, text in st.graded:
        kinds = ("far", "near") if said == "reach" else (said,)  # a reach alone: whichever way the tier says
        graded = next(((n, k) for n in reversed(st.mentioned) for k in kinds if graded_by(st, n, k)), None)
        if graded is None:
            st.fragment(text)
        else:
            metres = lx.DEFAULT_GRADED_DISTANCE_M if metres is None else metres
            st.cues.append(Cue(graded[1], graded[0], metres, hard=False))


def _said_graded(sent: Sentence, f: Found) -> bool:
    """Whether a reach with no distance says the cost is graded ("mode: graded")."""
    return any(w in lx.GRADED_VALUES for w in sent.words[f.start : f.end])


def graded_by(st: State, name: str, kind: str) -> bool:
    """Whether ``name``'s latest tier is what a graded ``kind`` grades: avoided or worse (far),
    preferred (near)."""
    tiers = st.statements.get(name) or [""]
    sev = lx.SEVERITY.get(tiers[-1])
    if sev is None:
        return False
    return sev >= lx.SEVERITY["avoid"] if kind == "far" else sev == lx.SEVERITY["prefer"]


def _near_object(
    st: State,
    sent: Sentence,
    c: Clause,
    f: Found,
    obj: Mention,
    metres: float,
    hard: bool,
    groups: Groups,
    used_groups: set[int],
) -> None:
    """ "near X" with no other target: keep away from X (and off it) when the nearest trigger
    avoids, else stay near it."""
    near_gi = nearest_group(groups, obj) if groups else None
    if near_gi is None or lx.SEVERITY[groups[near_gi][2]] < lx.SEVERITY["avoid"]:
        if near_gi is not None:
            used_groups.add(near_gi)
        st.cues.append(Cue("near", obj.name, metres, hard=hard))
        return
    # "avoid going near buildings": keep away, and off them
    used_groups.add(near_gi)
    # "never go within 10 m of X" is a rule; "avoid going within ..." a wish
    a, b, tier = groups[near_gi]
    wish = any(sent.words[k] in lx.AVOID_WORDS for k in range(a, b))
    rule = hard and not wish
    st.cues.append(Cue("far", obj.name, metres, hard=rule))
    # the rule's keep-out zone covers X itself; lethal would forbid what the rule allows when no
    # route exists otherwise, so X is strongly avoided
    c.assigned[obj.name] = "avoid+" if rule and tier == "lethal" else tier
    c.took(obj.name, (a, b), (f.start, f.end))
