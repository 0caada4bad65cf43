"""The offline interpreter: deterministic rules that read common mission language.

No model and no network: a tokenizer, the tables in :mod:`.lexicon` and a few passes over each
sentence. Written by hand because no maintained library turns "prefer the roads, grass is fine,
avoid the baseball field" into ranked costs; a general NLP parser (spaCy and the like) would add
hundreds of megabytes and still need these rules on top.

How a prompt is read:

1. Normalise (lower case, curly quotes, "off-limits" -> "off limits"; lengths kept, so fragments
   are quoted from the original text) and tokenize; split sentences at ``. ; ! ?`` and newlines.
2. Claim idioms that contain entity-like words first ("cross-country", "off-road", "off the
   beaten track": a preference for the terrain they name; polite wrappers such as "it would be
   great if": nothing). Then find entity mentions: the longest match in the entity table
   (plurals included), then runs of unknown content words (open vocabulary: "avoid the sandbox"
   names a "sandbox"; grammar words in ``lexicon.FILLER``, words of the phrase tables and -ly adverbs
   never do); an unknown word just before a known entity makes a compound ("dirt roads" ->
   "dirt road", inside road; "muddy tracks" -> "muddy track", since a bare "tracks" is the
   railway).
3. Claim constructs, in this order: conditions ("unless/if/when ... near X / within N m of X";
   "except at/over/via X"; "only at X"), geometric cues ("centre/side of X", "near X",
   "within N m of X", "at least N m from X", "a 20 m buffer around X"; a stated bound is a
   ``hard`` cue), comparisons ("X is better/worse than Y", "prefer X over Y", "X rather than
   Y"), modifiers ("as much as possible", "at all costs", "only if you have to"), preference
   triggers (tiers below; adverbs inside a phrase do not break it: "you can just wade
   through") and ordering markers ("first", "then", "finally").
4. Split into clauses at commas and conjunctions, except "and/or/," between two entities
   ("roads and trails" stays one list). In each clause, each entity takes the tier of the
   nearest trigger group (adjacent triggers combine, the most severe wins: "don't use" = avoid).
   A clause of bare entities joins its neighbour ("avoid water, buildings"); a pronoun ("you may
   cross it") refers to the previous clause's entities.
5. Orderings ("first X, then Y, then Z") and comparisons adjust the weights; a later statement
   about the same entity overrides an earlier one (noted).

Phrasing families (each a table row or rule, never a particular sentence):

=====================  ==================================================================
family                 reading
=====================  ==================================================================
negation + exception   "do not cross the railway except at level crossings", "never enter the
                       water unless near the bridge": X avoid/lethal + ``unless_near`` X, Y.
                       "cross the railway only at level crossings" (nothing else stated, or
                       a permission): X lethal + ``unless_near``; "avoid the river, but only
                       near the village": ``if_near``
last resort            "roads are a last resort", "only if you have to", "only in an
                       emergency": tolerable (worse than neutral ground)
comparatives           "X is better than Y", "prefer X over Y", "X rather than Y", "Y is worse /
                       less preferable than X": X below Y; an unstated side moves off neutral
                       only as far as it must (the worse side is never made preferred)
concealment            "stay under the trees / tree cover", "keep to the canopy", "stay hidden
                       in the forest", "under cover of the trees": prefer
permission             "you can wade through the water", "it's ok to drive through", "feel
                       free to go over": fine = neutral (no objection); "you can go around X":
                       avoid
stay off               "stay off / keep off / get off X": avoid ("the tracks" is the railway)
cross-country          "go cross-country through X", "off-road over X": prefer X
distances              "at least / no closer than N m from X", "never within N m of X": far,
                       hard; "within / no more than N m of X": near, hard; "N m away from X",
                       "a N m buffer around X", "near X", or any of these softened ("try",
                       "ideally", "if possible"): soft
=====================  ==================================================================

Each stated preference carries the phrase it came from (``Preference.phrase``): the trigger
with its entity list, the clause's modifiers and conditions, the neighbouring clause a bare list
or a pronoun took its tier from, the ordering so far, and any comparison naming the entity.

Anything left over -- a clause with no entity or no meaning, words that fit no rule, a
condition it cannot read -- is quoted in ``unparsed``; nothing is dropped silently.
"""

from __future__ import annotations

from dataclasses import replace

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.beside import claim_beside
from overseec_core.interpret.clauses import (
    Clause,
    apply_sequences,
    attach_bare,
    first_of_list,
    nearest_group,
    split_clauses,
    trigger_groups,
)
from overseec_core.interpret.comparisons import claim_comparisons
from overseec_core.interpret.conditions import (
    attach_conditions,
    claim_conditions,
    claim_cues,
    claim_exceptions,
    only_at,
)
from overseec_core.interpret.corrections import Part, corrected
from overseec_core.interpret.merge import finalize, make_entity
from overseec_core.interpret.priors import PriorTable
from overseec_core.interpret.sentence import Found, Mention, Sentence
from overseec_core.interpret.statements import State, resolve_weights
from overseec_core.interpret.tokens import Tok, is_adverb, sentences, tokenize
from overseec_core.schema import Cue, Interpretation

RULES_VERSION = "offline-rules.v2"


def read_sentence(toks: list[Tok], antecedent: str | None = None) -> Sentence:
    """A sentence with its mentions and every construct claimed, in the grammar's order:
    on-versus-beside, conditions, cues, comparisons, then modifiers, triggers and markers; last
    the list glue. ``antecedent``: the entity named last before it ("keep within 50 m of it")."""
    sent = Sentence(toks, antecedent)
    sent.beside = claim_beside(sent)  # before conditions: "but not in the river" is no exception
    claim_conditions(sent)
    claim_exceptions(sent)
    claim_cues(sent)
    for a, b in sent.gap_modifiers:  # "minimum horizontal separation": read with its cue
        if sent.free(a, b) and any(f.kind == "cue" and f.start <= b <= f.end for f in sent.found):
            sent.claim(Found("filler", a - sent.free(a - 1, a), b, "gap kind"), "cue")  # "safe" too
    _routes_within(sent)
    claim_comparisons(sent)
    _claim_levels(sent)
    sent.claim_phrases()
    sent.joins()
    return sent


Groups = list[tuple[int, int, str]]

#: Words between an entity and the cost a configuration gives it ("tree: 0.9", "road cost 0.2").
_LEVEL_MARKS = frozenset({":", "=", "cost", "costs", "weight", "level", "is", "at"})


def _claim_levels(sent: Sentence) -> None:
    """ "tree: 0.9", "road = 0.2", "grass cost 0.5": a cost on the 0-1 scale given to the
    known entity before it, as a robot's configuration states it (``level`` found; read as that
    cost, 0.5 neutral). A number with a unit is a distance, not a cost; a name the lexicon does
    not know takes a cost only as a key ("helipad: 0.9"), so "costmap resolution 0.05" stays a
    setting."""
    w = sent.words
    for m in list(sent.mentions):
        if m.role != "target":
            continue
        k = m.end
        if not m.known and not (k < sent.n and w[k] in (":", "=")):
            continue  # "costmap resolution 0.05" is a setting, no layer's cost
        while k < sent.n and w[k] in _LEVEL_MARKS and sent.claimed[k] is None and k - m.end < 2:
            k += 1
        marked = k > m.end  # "mud: 5", "gravel cost 2": a relative cost needs its mark
        if k >= sent.n or not sent.free(k, k + 1) or not (_is_level(w[k]) or (marked and _is_relative(w[k]))):
            continue
        if k + 1 < sent.n and w[k + 1] not in (",", "and", "/", "|"):
            continue  # "road 0.2 km", "tree 0.9 of the time": not a cost
        sent.claim(Found("level", m.end, k + 1, w[k], (m,)), "level")


def _is_relative(word: str) -> bool:
    """Whether a token may be a relative cost ("asphalt: 1, gravel: 2, mud: 5"): a number above
    the 0-1 scale, read as one only beside others (:func:`_relative_levels`)."""
    try:
        return 1.0 < float(word) <= 1000.0
    except ValueError:
        return False


def _relative_levels(clauses: list[Clause]) -> None:
    """Costs above 1 are relative ("asphalt | 1", "gravel | 2", "mud | 5"): when a prompt states
    two or more, every stated cost is a step of an ordering, cheapest first (``order:``, the
    steps of "first X, then Y"); a lone one ("road: 3") says no cost and is dropped."""
    stated = [(c, n, t) for c in clauses for n, t in c.assigned.items() if t.startswith("level:")]
    levels = [(c, n, float(t.split(":", 1)[1])) for c, n, t in stated]
    if not any(v > 1.0 for _, _, v in levels):
        return
    steps = sorted({v for _, _, v in levels})
    for c, name, v in levels:
        if len(steps) < 2:
            del c.assigned[name]
        else:
            c.assigned[name] = f"order:{min(lx.PREFER + lx.STEP * steps.index(v), lx.ORDER_MAX):.2f}"


def _is_level(word: str) -> bool:
    """Whether a token is a cost on the 0-1 scale ("0.9", "0", "1", ".5" is tokenised "5")."""
    try:
        value = float(word)
    except ValueError:
        return False
    return 0.0 <= value <= 1.0 and (word in ("0", "1") or "." in word)


def _analyse_clause(st: State, sent: Sentence, c: Clause, prev: Clause | None) -> None:
    """Read one clause: its entities' tiers (from the nearest trigger group, or through a pronoun
    from the previous clause), its cues, conditions and comparisons, and what is left over."""
    groups = trigger_groups(c)
    used_groups: set[int] = set()
    targets = _clause_targets(sent, c)
    cues = [f for f in c.found if f.kind == "cue"]
    near_objs = [m for f in cues if f.value in ("near", "far") for m in f.mentions]
    centre_side = [(f.value, m, f) for f in cues if f.value in ("centre", "side") for m in f.mentions]
    for f in c.found:  # every cue object and comparison side counts as a mention
        for m in f.mentions + f.left:
            st.mention(m.name)
    if not targets and groups and not near_objs and not centre_side:
        _refer_back(sent, c, prev, groups, used_groups)
    _assign_targets(sent, c, targets, groups, used_groups)
    _compared_verdicts(c, groups, used_groups)
    for f in c.found:
        if f.kind == "condition" and f.value == "only_at" and targets:
            only_at(f, c, [m.name for m in targets], sent.words[c.start : c.end])
    for f in c.found:
        if f.kind == "exception":
            _excepted(st, c, f)
    _levels(c)
    for kind, m, cf in centre_side:
        _centre_side_cue(st, c, kind, m, cf, groups, used_groups)
    _distance_cues(st, sent, c, cues, targets, groups, used_groups)
    _comparisons(st, sent, c)
    _clause_leftovers(st, sent, c, groups, used_groups)
    _mark_unparsed(sent, c, targets, cues)


def _route_subject(sent: Sentence, m: Mention) -> bool:
    """Whether ``m`` is the route itself as its sentence's subject: a route noun ("the track",
    "the path") opening the sentence, then a modal and a keeping or moving verb ("the track
    would stay 25 m or more from the railway"). Its words are read (claimed as filler)."""
    w = sent.words
    words = w[m.start : m.end]
    if len(words) != 1 or words[0] not in lx.ROUTE_NOUNS or m.end >= sent.n:
        return False
    j = m.start - 1 - (m.start > 0 and w[m.start - 1] in lx.ARTICLES)
    if j >= 0 and w[j] in lx.MODALS and w[m.end] in lx.ROUTE_VERBS:  # "at no point may the path come"
        ok = True
    else:  # "(ideally) the track would stay ..."
        opening = w[: m.start]
        ok = all(t in lx.ARTICLES or t in lx.SOFTENERS or is_adverb(t) for t in opening)
        ok = ok and m.end + 1 < sent.n and w[m.end] in lx.MODALS and w[m.end + 1] in lx.ROUTE_VERBS
    if ok:
        sent.claimed[m.start] = "filler"
    return ok


def _routes_within(sent: Sentence) -> None:
    """ "preference to paths within 15 m of the road", "routes within 10 m of the river are
    best": a route noun right before a "within" cue is the route itself, not a trail near the
    road; it is no entity, and its word is read (claimed as filler)."""
    for f in list(sent.found):
        if f.kind != "cue" or sent.words[f.start] != "within" or f.start == 0:
            continue
        m = next((m for m in sent.mentions if m.end == f.start and m.end - m.start == 1), None)
        if m is not None and lx.singularise(sent.words[m.start]) in lx.ROUTE_NOUNS:
            sent.drop_mention(m)
            sent.claimed[m.start] = "filler"


def _levels(c: Clause) -> None:
    """ "tree: 0.9": each stated cost is its entity's tier (``level:0.90``)."""
    for f in c.found:
        if f.kind == "level":
            for m in f.mentions:
                c.assigned[m.name] = f"level:{float(f.value):.2f}"
                c.took(m.name, (f.start, f.end), (f.start, f.end))


def _clause_targets(sent: Sentence, c: Clause) -> list[Mention]:
    """The clause's entities that take a tier: not the subject of a situation ("only if the road
    is blocked"), and unknown words only where no known entity stands beside them or a trigger
    takes them as its object ("prefer the gravel avoid the mud"); the others are left over."""
    known_chains = {m.chain for m in c.targets if m.known}
    targets = []
    for m in c.targets:
        if sent.in_situation(m) or _route_subject(sent, m):
            continue
        if m.known or not known_chains or m.chain in known_chains or sent.object_of_trigger(m):
            targets.append(m)
        else:
            c.leftover.extend(range(m.start, m.end))
    return targets


def _refer_back(sent: Sentence, c: Clause, prev: Clause | None, groups: Groups, used_groups: set[int]) -> None:
    """A pronoun in a clause of triggers alone ("you may cross it") gives the previous clause's
    entities this clause's first tier; the previous clause becomes context."""
    referred = (list(prev.assigned) or [m.name for m in prev.targets]) if prev else []
    if prev is not None and not referred and prev.sent == c.sent:  # "right up against the houses, but never enter one"
        referred = [m.name for m in sent.mentions if prev.start <= m.start < prev.end and m.role == "cue"]
    pronouns = [j for j in range(c.start, c.end) if sent.words[j] in lx.PRONOUNS]
    relative = [j for j in range(c.start, min(c.end, c.start + 2)) if sent.words[j] in lx.RELATIVE_PRONOUNS]
    before = [m for m in sent.mentions if m.end <= c.start]
    if relative and before:  # "except the cricket pitch, which must not be driven on": the pitch
        referred, pronouns = [before[-1].name], relative
    if prev is not None and referred and pronouns:  # (referred is empty without prev)
        for name in referred:
            c.assigned[name] = groups[0][2]
            c.src[name] = (prev, c)
            c.took(name, groups[0][:2], (pronouns[-1], pronouns[-1] + 1))
        used_groups.add(0)
        prev.referenced = True  # "There is a pond. Avoid it.": the first clause is context


def _assign_targets(sent: Sentence, c: Clause, targets: list[Mention], groups: Groups, used_groups: set[int]) -> None:
    """Each target takes its nearest group's tier; its phrase is the trigger and its list."""
    group_of = {}
    for m in targets:
        if groups:
            gi = nearest_group(groups, m, sent)
            used_groups.add(gi)
            c.assigned[m.name] = groups[gi][2]
            group_of[m.name] = gi
    for m in targets:  # "prefer the roads and trails": the trigger and its list
        if m.name in group_of:
            gi = group_of[m.name]
            c.took(m.name, groups[gi][:2], *[(t.start, t.end) for t in targets if group_of.get(t.name) == gi])


def _compared_verdicts(c: Clause, groups: Groups, used_groups: set[int]) -> None:
    """A compared entity with its own verdict right after it ("asphalt preferred > dirt roads
    avoided") takes that verdict; the comparison then orders the two as well."""
    for f in c.found:
        if f.kind != "comparator":
            continue
        for m in (*f.left, *f.mentions):
            gi = next((g for g, (a, _, _) in enumerate(groups) if a == m.end), None)
            if gi is not None and m.name not in c.assigned:
                used_groups.add(gi)
                c.assigned[m.name] = groups[gi][2]
                c.took(m.name, groups[gi][:2], (m.start, m.end))


def _centre_side_cue(
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


def _distance_cues(
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
        or "soft" in _rule_labels(sent)
        or any(f.kind == "filler" and f.value == "slack" for f in sent.found)  # "not the end of the world"
    )
    for f in cues:
        if f.value in ("near", "far"):
            _near_far_cue(st, sent, c, f, targets, groups, used_groups, softened)
        elif f.value in ("graded_far", "graded_near", "graded_reach"):
            _shape_graded(st, sent, c, f)


def _excepted(st: State, c: Clause, f: Found) -> None:
    """An entity excepted from its clause ("lawns are fine except the cricket pitch") takes the
    other side of the clause's tier (avoided where the others are fine, fine where they are
    avoided); a later statement about it ("which must not be driven on") is stated after and
    counts too. With nothing in the clause to except it from, the words are not understood."""
    tiers = [t for n, t in c.assigned.items() if n not in {m.name for m in f.mentions}]
    if not tiers:
        st.fragment(st.prompt[c.toks[f.start].start : c.toks[f.end - 1].end])
        return
    for m in f.mentions:
        st.mention(m.name)
        c.assigned[m.name] = lx.EXCEPTED_TIER.get(tiers[0], "avoid")
        c.took(m.name, (f.start, f.end))


def _rule_labels(sent: Sentence) -> set[str]:
    """How strict the sentence's labels say its rule is ("Hard constraint: ..."): {"hard"},
    {"soft"}, or empty."""
    return {v for i in range(sent.n - 1) if (v := lx.RULE_LABELS.get((sent.words[i], sent.words[i + 1])))}


def _qualifier_clause(sent: Sentence, c: Clause) -> bool:
    """Whether the clause only says how strict the sentence's distance rule is ("Hard
    constraint", "mandatory", "25 m minimum"): read with the rule, not left over."""
    if not any(f.kind == "cue" and f.value in ("near", "far") for f in sent.found):
        return False
    read = lx.RULE_WORDS | lx.SOFTENERS | lx.FILLER | lx.SEPARATORS | lx.ARTICLES | {"soft", "constraint"}
    if _rule_labels(sent):  # "..., ok to violate", "..., can be violated": the label's own words
        read = read | {w for pair in lx.RULE_LABELS for w in pair} | {"ok", "okay", "fine"}
    return all(sent.words[j] in read or sent.claimed[j] == "cue" for j in range(c.start, c.end))


def _shape_graded(st: State, sent: Sentence, c: Clause, f: Found) -> None:
    """ "..., the further the better (up to 25 m)": the last near/far cue stated so far is graded
    (soft), reaching neutral at the distance given; "tapering off by 30 m" (``graded_reach``) sets
    where the last soft near/far cue reaches neutral, or with none grades what the prompt avoids
    (:func:`_resolve_graded`). With nothing to grade the words are not understood."""
    kind = f.value.removeprefix("graded_")
    for k in range(len(st.cues) - 1, -1, -1):
        cue = st.cues[k]
        if cue.kind == kind or (kind == "reach" and cue.kind in ("near", "far") and not cue.hard):
            st.cues[k] = replace(cue, metres=cue.metres if f.metres is None else f.metres, hard=False)
            return
    text = st.prompt[c.toks[f.start].start : c.toks[f.end - 1].end]
    if kind in ("near", "far"):  # no cue before it: grade what the prompt avoids or prefers
        st.graded.append((kind, f.metres, text))
    elif kind == "reach" and f.metres is not None:  # "avoid the pond, tapering off by 25 m": far, graded
        st.graded.append(("far", f.metres, text))
    else:
        st.fragment(text)


def _resolve_graded(st: State) -> None:
    """ "keep away from the water, the closer the worse": an afterthought with no cue before it
    grades the entity mentioned last whose tier keeps away from it (far: avoided or worse) or
    draws to it (near: preferred); with none, its words are not understood."""
    for kind, metres, text in st.graded:
        target = next((n for n in reversed(st.mentioned) if _graded_by(st, n, kind)), None)
        if target is None:
            st.fragment(text)
        else:
            st.cues.append(Cue(kind, target, lx.DEFAULT_GRADED_DISTANCE_M if metres is None else metres, hard=False))


def _graded_by(st: State, name: str, kind: str) -> bool:
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


def _comparisons(st: State, sent: Sentence, c: Clause) -> None:
    """Each comparison of the clause: its phrase for both sides, and a constraint per pair."""
    for f in c.found:
        if f.kind != "comparator":
            continue
        a_char = sent.toks[min([c.start] + [m.start for m in f.left])].start
        st.compare([m.name for m in f.left + f.mentions], st.prompt[a_char : sent.toks[f.end - 1].end].strip())
        said = sent.words[f.start : min(m.start for m in f.mentions)]
        if f.value == "better" and any(w in lx.PREFER_VERBS for w in said):
            for a in f.left:  # "gravel is to be preferred over asphalt": preferred, not merely better
                c.assigned.setdefault(a.name, "prefer")
        for a in f.left:
            for b in f.mentions:
                if f.value == "better":
                    st.constraints.append(("lt", a.name, b.name))
                elif f.value == "worse":
                    st.constraints.append(("lt", b.name, a.name))
                else:
                    st.constraints.append(("eq", a.name, b.name))


def _clause_leftovers(st: State, sent: Sentence, c: Clause, groups: Groups, used_groups: set[int]) -> None:
    """Trigger groups that gave no tier and restate none, and words no rule claimed, are left
    over; an unread condition ("if ...", "unless ...") is reported to the clause's end."""
    said = set(c.assigned.values())
    # the absolute wording of a distance rule ("never", "no matter what", "at all times") is read
    rule_words = lx.RULE_WORDS if sent.rule_wording() else frozenset()
    # "ideally", "if possible" soften a distance cue of the clause (read, not left over)
    if any(f.kind == "cue" and f.value in ("near", "far") for f in c.found) or _qualifier_clause(sent, c):
        rule_words = rule_words | lx.SOFTENERS | {"soft"}
        if _rule_labels(sent) and _qualifier_clause(sent, c):  # "..., ok to violate"
            rule_words = rule_words | {"ok", "okay", "fine"}
    for gi, (a, b, tier) in enumerate(groups):
        if gi not in used_groups and tier not in said:  # "go through the grass instead": restated
            if not all(sent.words[k] in rule_words for k in range(a, b)):
                c.leftover.extend(range(a, b))
    for j in range(c.start, c.end):
        if (
            sent.claimed[j] is None
            and sent.words[j] not in rule_words
            and sent.words[j] not in lx.FILLER
            and sent.words[j] not in lx.SEPARATORS
            and sent.words[j] not in lx.ARTICLES
        ):
            if sent.words[j] in ("if", "unless", "when", "except", "whenever", "where"):
                st.fragment(st.prompt[c.toks[j].start : c.toks[c.end - 1].end])
                continue
            c.leftover.append(j)


def _mark_unparsed(sent: Sentence, c: Clause, targets: list[Mention], cues: list[Found]) -> None:
    """A clause with no meaning, no target and no condition, but words other than grammar (a
    short marker clause aside), is unparsed as a whole."""
    has_meaning = bool(c.assigned) or bool(cues) or any(f.kind == "comparator" for f in c.found)
    if has_meaning or targets or any(f.kind == "condition" for f in c.found):
        return
    if _qualifier_clause(sent, c):  # "Hard constraint: never within 5 m of the pylons"
        return
    read = lx.FILLER | lx.SEPARATORS | lx.ARTICLES
    if all(sent.claimed[j] in ("cue", "filler") or sent.words[j] in read for j in range(c.start, c.end)):
        return  # "cost: grass < road": a label read with the sentence's ordering; an idiom read
    if any(sent.claimed[j] not in (None,) or sent.words[j] not in lx.FILLER for j in range(c.start, c.end)) and not (
        c.markers and c.end - c.start <= 2
    ):
        c.whole_unparsed = True


def _report_leftovers(st: State, sent: Sentence, c: Clause) -> None:
    if c.whole_unparsed:
        if not c.referenced:
            st.fragment(c.text(st.prompt))
        return
    idx = sorted(set(c.leftover))
    run: list[int] = []
    for j in idx:
        if run and any(sent.words[k] not in lx.FILLER and k not in idx for k in range(run[-1] + 1, j)):
            st.fragment(st.prompt[c.toks[run[0]].start : c.toks[run[-1]].end])
            run = []
        run.append(j)
    if run:
        st.fragment(st.prompt[c.toks[run[0]].start : c.toks[run[-1]].end])


def _rule_only(sent: Sentence) -> str | None:
    """What a sentence that only qualifies the rule before it says: "hard" ("No exceptions.",
    "Non-negotiable.", "That buffer is an absolute constraint, not a preference."), "soft" ("Not
    mandatory.", "no hard limit", "it is a preference"), or None when it says more than that."""
    read = lx.RULE_WORDS | lx.FILLER | lx.SEPARATORS | lx.ARTICLES
    words = sent.words
    if any(m.known or m.name not in read for m in sent.mentions) or not all(w in read for w in words):
        return None
    in_phrase = {
        k
        for i in range(sent.n)
        for p in lx.ABSOLUTE_PHRASES
        if tuple(words[i : i + len(p)]) == p
        for k in range(i, i + len(p))
    }
    # "not a hard limit" softens; "not a preference" does not, it hardens; "a preference" softens
    said_not = {k for k in range(len(words)) if _negated_wish(words, k)}
    negated = any(
        w in lx.RULE_NEGATORS and k not in in_phrase and not said_not & {k + 1, k + 2} for k, w in enumerate(words)
    )
    wished = any(w in lx.WISH_NOUNS and k not in said_not for k, w in enumerate(words))
    if negated or wished:
        return "soft"
    if sent.absolute() or any(w in lx.RULE_VERDICTS for w in words) or said_not:
        return "hard"
    return None


def _negated_wish(words: list[str], k: int) -> bool:
    """Whether word ``k`` is a wish noun the sentence negates ("not a preference")."""
    return words[k] in lx.WISH_NOUNS and any(v in lx.RULE_NEGATORS for v in words[max(0, k - 2) : k])


def _qualify_rules(st: State, since: int, sent: Sentence, how: str) -> None:
    """Make the distance cues the previous sentence stated hard rules (or soft preferences);
    with none, the sentence has nothing to apply to and is reported as not understood."""
    done = False
    for k in range(since, len(st.cues)):
        if st.cues[k].kind in ("near", "far"):
            st.cues[k] = replace(st.cues[k], hard=how == "hard")
            done = True
    if not done:
        st.fragment(st.prompt[sent.toks[0].start : sent.toks[-1].end])


def _distance_rules(st: State, since: int) -> bool:
    """Whether the cues from ``since`` on hold a distance rule (near or far)."""
    return any(c.kind in ("near", "far") for c in st.cues[since:])


def _rule_sentence(
    st: State,
    sent: Sentence,
    how: str,
    heading: tuple[str, Sentence, int] | None,
    cues_before: int,
    last: bool,
) -> tuple[str, Sentence, int] | None:
    """A sentence that only says how strict a rule is: it qualifies the distance rules of the
    sentence before it ("Keep 20 m from the railway. No exceptions."), or, with none there and
    lines after it, heads those lines ("HARD LIMITS"); the heading now in force is returned."""
    if last or _distance_rules(st, cues_before):
        _qualify_rules(st, cues_before, sent, how)
        return heading
    _close_heading(st, heading)
    return (how, sent, len(st.cues))


def _close_heading(st: State, heading: tuple[str, Sentence, int] | None) -> None:
    """A heading that only says how strict the rules are ("HARD LIMITS" over "water: 5 m",
    "railway: 10 m") makes the distance rules of the lines under it so; one with no rule under
    it is reported as not understood."""
    if heading is not None:
        how, sent, since = heading
        _qualify_rules(st, since, sent, how)


def _note_readings(sent: Sentence, st: State) -> None:
    """Say how words were read as entities by spelling or alias ("read 'woods' as 'forest'")."""
    for word, name, how in sent.readings:
        note = f"read '{word}' as '{name}'" + {"spelling": " (spelling)", "pronoun": " (the entity named last)"}.get(
            how, ""
        )
        if note not in st.notes:
            st.notes.append(note)


def _apply_beside(st: State, sents: list[Sentence]) -> None:
    """On versus beside (``interpret.beside``), stated last: the object itself is not the way
    (avoided, or forbidden), the band beside it is (a soft near cue)."""
    for sent in sents:
        for b in sent.beside:
            if b.pending:  # beside X, and X avoided or forbidden somewhere in the prompt
                if _graded_by(st, b.name, "far") and Cue("near", b.name, b.metres) not in st.cues:
                    st.cues.append(Cue("near", b.name, b.metres))
                continue
            if b.tier is not None:
                st.state(b.name, b.tier, st.prompt[sent.toks[0].start : sent.toks[-1].end])
            else:
                st.mention(b.name)
            st.cues.append(Cue("near", b.name, b.metres))


def _merge_soft_cues(cues: list[Cue]) -> list[Cue]:
    """One soft cue per (kind, entity, other entity): a brief that says "don't go near the water:
    the further from it the better, up to 30 m" grades the water once, reaching neutral at the
    stated 30 m, not also at the default reach. A stated distance wins over the default; hard
    cues (rules) are kept as they are."""
    out: list[Cue] = []
    at: dict[tuple, int] = {}
    for cue in cues:
        key = (cue.kind, cue.entity, cue.other)
        if cue.hard or cue.kind not in ("near", "far"):
            out.append(cue)
            continue
        if key not in at:
            at[key] = len(out)
            out.append(cue)
        elif out[at[key]].metres == lx.DEFAULT_GRADED_DISTANCE_M and cue.metres != lx.DEFAULT_GRADED_DISTANCE_M:
            out[at[key]] = cue
    return out


def _last_named(sent: Sentence, before: str | None) -> str | None:
    """What a pronoun of the next sentence stands for: the known entity this one named last,
    or the excepted one it ends on ("..., except the cricket pitch. Avoid that part."), else
    its last open-vocabulary name, else ``before``."""
    named = sorted((m for m in sent.mentions if m.role in ("target", "cue", "except")), key=lambda m: m.start)
    if named and named[-1].role == "except":
        return named[-1].name
    return next((m.name for m in reversed(named) if m.known), named[-1].name if named else before)


def _note_withdrawn(st: State, part: Part, prompt: str) -> None:
    """A note of what a self-correction withdrew ("avoid the vegetation -- no wait, ...")."""
    if part.withdrawn_by and part.span:
        said = prompt[part.span[0] : part.span[1]]
        st.notes.append(f"'{said}' read as withdrawn ('{part.withdrawn_by}')")


def _state_clauses(st: State, clauses: list[Clause], sents: list[Sentence], parts: list[Part]) -> None:
    """Each clause's tiers as statements (and the nocross rule's cue), its leftovers reported
    (never a withdrawn sentence's names), and every known entity it names mentioned."""
    for c in clauses:
        for name, tier in c.assigned.items():
            st.state(name, tier, c.phrase(name, st.prompt))
            if tier == "nocross" and Cue("no_cross", name, hard=True) not in st.cues:
                st.cues.append(Cue("no_cross", name, hard=True))
        if not parts[c.sent].withdrawn_by:
            _report_leftovers(st, sents[c.sent], c)
        for m in c.targets:  # named but given no preference: still segmented (neutral)
            if m.known:
                st.mention(m.name)


def analyse(prompt: str) -> State:
    """Read a prompt into statements, cues, orderings and leftovers (no defaults yet)."""
    st = State(prompt)
    clauses: list[Clause] = []
    sents: list[Sentence] = []
    antecedent: str | None = None
    cues_before = 0  # how many cues the sentences before the last one stated
    heading: tuple[str, Sentence, int] | None = None  # "HARD LIMITS" over the lines after it
    parts = corrected(sentences(tokenize(prompt)))
    all_toks = [list(p.toks) for p in parts]
    for si, toks in enumerate(all_toks):
        sent = read_sentence(toks, antecedent)
        sents.append(sent)
        _note_withdrawn(st, parts[si], prompt)
        if how := _rule_only(sent):  # "Keep 20 m from the railway. No exceptions." / "Not mandatory."
            heading = _rule_sentence(st, sent, how, heading, cues_before, last=si + 1 == len(all_toks))
            continue
        cues_before = len(st.cues)
        antecedent = _last_named(sent, antecedent)
        own = split_clauses(sent, si)
        prev = clauses[-1] if clauses else None
        for c in own:
            _analyse_clause(st, sent, c, prev)
            prev = c
        attach_bare(own)
        attach_conditions(own, st)
        clauses.extend(own)
        _note_readings(sent, st)
    _close_heading(st, heading)
    _relative_levels(clauses)
    first_of_list(clauses)
    apply_sequences(clauses)
    _state_clauses(st, clauses, sents, parts)
    _resolve_graded(st)
    _apply_beside(st, sents)
    st.cues = _merge_soft_cues(st.cues)
    resolve_weights(st)
    for name in st.weights:
        said = ([st.said[name]] if st.said.get(name) else []) + st.compared.get(name, [])
        kept = [p for p in said if not any(p != q and p in q for q in said)]
        st.phrases[name] = "; ".join(dict.fromkeys(kept))
    return st


def interpret_offline(prompt: str, priors: PriorTable | None = None) -> Interpretation:
    """Interpret a mission prompt with the offline rules (deterministic, no network).

    ``priors``: the costs of hazards the prompt leaves unsaid (None = the built-in table)."""
    st = analyse(prompt)
    mentioned = [make_entity(n) for n in st.mentioned]
    notes = [f"interpreter: {RULES_VERSION}"] + st.notes
    return finalize(
        prompt,
        mentioned=mentioned,
        stated=st.weights,
        cues=st.cues,
        unparsed=st.unparsed,
        notes=notes,
        source="offline",
        phrases=st.phrases,
        priors=priors,
    )
