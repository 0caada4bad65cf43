"""Conditions and geometric cues: where a preference holds, and how near or far to keep.

Claimed over a :class:`~overseec_core.interpret.sentence.Sentence` before comparisons and
triggers: conditions ("unless/if/when ... near X", "within N m of X", "except at X", "only at X";
:func:`claim_conditions`) and cues ("centre/side of X", "near X", "at least N m from X", "a 20 m
buffer around X"; a stated bound is a ``hard`` cue; :func:`claim_cues`). Once the clauses have
their tiers, a condition attaches to the clause it qualifies (:func:`attach_conditions`), and
"X only at Y" is read by what else the prompt says of X (:func:`only_at`). How a graded cue falls
off, and where it reaches neutral, is read by :mod:`overseec_core.interpret.graded`.
"""

from __future__ import annotations

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.berths import berth_cue
from overseec_core.interpret.clauses import Clause
from overseec_core.interpret.clearances import (
    clearance_rule,
    distance_after,
    topic_away,
    topic_bound,
)
from overseec_core.interpret.distances import (
    bound_negation,
    denied_bound,
    distance_phrase,
    negated_kind,
    priced_within,
)
from overseec_core.interpret.graded import (
    TOPIC_MARKS,
    graded_clause,
    graded_explanation,
    nice_and_close,
    rising_as_gap_closes,
    symbolic_graded,
    trailing_aim,
    trailing_distance,
)
from overseec_core.interpret.nearness import (
    band_cue,
    bias_cue,
    in_sight_cue,
    kept_in_sight,
    kept_in_touch,
    peak_cue,
    priced_near,
    proximity_compound,
    rising_cost,
)
from overseec_core.interpret.reach import enough_reach, graded_reach, keyed_reach, mattering_reach
from overseec_core.interpret.sentence import Found, Mention, Sentence
from overseec_core.interpret.statements import State
from overseec_core.schema import Cue


def claim_conditions(sent: Sentence) -> None:
    """Claim the conditions: "unless/if ... near X", "within N m of X", "except at/over/via X",
    "only at X" (the entities named become the condition's, not targets)."""
    for i in range(sent.n):  # conditions: unless/if ... near X
        hit = sent.match(lx.CONDITIONS, i)
        if not hit:
            continue
        j0 = i + len(hit[0])
        j = sent.skip(j0, (lx.FILLER | lx.CONDITION_VERBS) - {"near", "by", "along", "around", "within"})
        kind = hit[1]
        if j < sent.n and sent.words[j] in lx.CONDITION_NEGATORS and kind in ("if_near", "unless_near"):
            # "as long as it's not near the water" = unless near it; "unless it is not near" = if
            kind = "unless_near" if kind == "if_near" else "if_near"
            j = sent.skip(j + 1, (lx.FILLER | lx.CONDITION_VERBS) - {"near", "by", "along", "around", "within"})
        metres = None
        prox = sent.match(lx.PROXIMITY, j)
        if prox:
            j += len(prox[0])
        elif j < sent.n and sent.words[j] == "within" and (d := sent.distance(j + 1)):
            metres, j = d[0], d[1]
            if j < sent.n and sent.words[j] in ("of", "from"):
                j += 1
        elif (
            hit[1] in ("unless_near", "only_at")
            and hit[0] != ("but", "not")  # "on grass but not on the road": a contrast, the road itself
            and any(w in lx.EXCEPT_PREPS for w in sent.words[j0:j])
            and (hit[1] != "only_at" or any(m.end <= i for m in sent.mentions))
        ):
            # ("only on roads" with nothing before it to restrict is a preference for roads)
            pass  # "except at level crossings": the exception is where the other entity is
        else:
            continue
        lst, end = sent.list_forward(j)
        if not lst:
            continue
        for m in lst:
            m.role = "cond"
        sent.claim(Found("condition", i, end, kind, tuple(lst), metres), "cond")


def claim_exceptions(sent: Sentence) -> None:
    """ "lawns are fine except the cricket pitch", "all fields apart from the paddock": an entity
    excepted from what its clause says of the others (after the conditions, so "except at the
    level crossing" stays a condition)."""
    for i in range(sent.n):
        size = next((len(p) for p in lx.EXCEPTING if tuple(sent.words[i : i + len(p)]) == p), 0)
        if not size or not sent.free(i, i + size):
            continue
        lst, end = sent.list_forward(i + size)
        if not lst:
            continue
        for m in lst:
            m.role = "except"
        sent.claim(Found("exception", i, end, "except", tuple(lst)), "cond")


def claim_cues(sent: Sentence) -> None:
    """Claim the geometric cues: "centre/side of X", "near X", "N m from X", "a buffer around X"."""
    for i in range(sent.n):  # first: "lose" and "track" in "never lose track of X" are no names
        kept_in_touch(sent, i) or kept_in_sight(sent, i)
    for i in range(sent.n):
        _cue_at(sent, i)
    for i in range(sent.n):  # after every cue: a restatement may come before the reach it shapes
        graded_explanation(sent, i)


def _cue_at(sent: Sentence, i: int) -> None:
    """Claim the cue that starts at word i, if any: a side token ("roadside"), a postfix after a
    mention ("road centre line"), a prefix ("centre of the road"), or a distance."""
    if sent.claimed[i] is not None and sent.claimed[i] != "mention":
        return
    m = sent.mention_at.get(i)
    if m is not None and m.role == "side":  # "roadside"; "the shoreline" is ground near the water
        near = sent.words[i] in lx.NEAR_SIDE_TOKENS
        # the shoreline is ground near the water, not the water: no trigger's tier lands on it
        m.role = "cue" if near else "target"
        sent.claim(Found("cue", i, i + 1, "near" if near else "side", (m,)), "cue")
    elif sent.claimed[i] == "mention":
        _postfix_cue(sent, m)
    elif sent.words[i] in lx.CENTRE | lx.SIDE:
        if not clearance_rule(sent, i):  # "bldg margin 7 m" is a clearance rule
            _prefix_cue(sent, i)
    elif not (
        berth_cue(sent, i)
        or in_sight_cue(sent, i)
        or proximity_compound(sent, i)
        or priced_near(sent, i)
        or clearance_rule(sent, i)
        or bias_cue(sent, i)
        or rising_cost(sent, i)
        or peak_cue(sent, i)
        or graded_clause(sent, i)
        or symbolic_graded(sent, i)
        or rising_as_gap_closes(sent, i)
        or graded_reach(sent, i)
        or mattering_reach(sent, i)
        or enough_reach(sent, i)
        or keyed_reach(sent, i)
        or trailing_aim(sent, i)
        or nice_and_close(sent, i)
        or _field_cue(sent, i)
        or topic_bound(sent, i)
        or topic_away(sent, i)
        or band_cue(sent, i)
    ):
        _distance_cue(sent, i)


def _field_cue(sent: Sentence, i: int) -> bool:
    """ "attract: road", "repel the water", "water: repel", "repulsor: building": a graded near
    (attract) or far (repel) cue on the entities after the field word, else on those right
    before it."""
    w = sent.words[i]
    if w not in lx.ATTRACT_WORDS | lx.REPEL_WORDS or not sent.free(i, i + 1):
        return False
    kind = "near" if w in lx.ATTRACT_WORDS else "far"
    # "attract: road", "should be attracted to the trail", "repelled by the water"
    lst, end = sent.list_forward(sent.skip(i + 1, lx.ARTICLES | {":", "-", "to", "toward", "towards", "by"}))
    start = i
    if not lst:
        k = i - 1
        while k >= 0 and sent.words[k] in (":", "-", ","):
            k -= 1
        m = next((m for m in sent.mentions if m.end - 1 == k), None)
        if m is None:
            return False
        lst, start, end = [m], m.start, i + 1
    for mm in lst:
        mm.role = "cue"
    sent.claim(Found("cue", start, end, kind, tuple(lst), None), "cue")
    return True


def _postfix_cue(sent: Sentence, m: Mention | None) -> None:
    """ "road centre line", "road edge": a centre or side word right after the mention."""
    if m is not None and m.end < sent.n and sent.claimed[m.end] is None:
        nxt = sent.words[m.end]
        if nxt in lx.CLEARANCE_NOUNS and distance_after(sent, m.end + 1) is not None:
            return  # "bldg margin 7 m": a clearance rule (clearance_rule), not the building's side
        if nxt in lx.CENTRE | lx.SIDE:
            end = m.end + 1 + (m.end + 1 < sent.n and sent.words[m.end + 1] == "line")
            sent.claim(Found("cue", m.end, end, "centre" if nxt in lx.CENTRE else "side", (m,)), "cue")


def _prefix_cue(sent: Sentence, i: int) -> None:
    """ "(the) centre (line) of (the) road", "the side of the trail"."""
    w = sent.words[i]
    j = i + 1
    if j < sent.n and sent.words[j] == "line":
        j += 1
    if j < sent.n and sent.words[j] == "of":
        lst, end = sent.list_forward(j + 1)
        if lst:
            sent.claim(Found("cue", i, end, "centre" if w in lx.CENTRE else "side", tuple(lst)), "cue")


def _distance_opening(sent: Sentence, i: int) -> tuple[str, float | None, bool, bool, int] | None:
    """The words before the entity list of a near/far cue: (kind, metres, hard, whether a "by N m"
    must follow, index of the list)."""
    if far := sent.match(lx.FAR_WORDS, i):
        return "far", None, False, False, i + len(far[0])
    if near := sent.match(lx.NEAR, i):
        return "near", None, False, False, i + len(near[0])
    if tuple(sent.words[i : i + 2]) == ("away", "from") and sent.free(i, i + 2):
        # "keep away from buildings by 20 m"; "away from water, ...": a terse far cue of its own
        alone = i == 0 or sent.words[i - 1] in TOPIC_MARKS | {";"}
        return "far", None, False, not alone, i + 2
    if aim := _aim_opening(sent, i):
        return aim
    if graded := _graded_noun_opening(sent, i):
        return graded
    if sent.words[i] in lx.HUG_VERBS and sent.free(i, i + 1):
        return "near", None, False, False, i + 1  # "hug the tree line"
    if i + 1 < sent.n and sent.words[i] in lx.TIGHT_WORDS and sent.words[i + 1] in lx.TIGHT_PREPOSITIONS:
        if sent.free(i, i + 2):
            return "near", None, False, False, i + 2  # "move tight along the treeline"
    if dist := distance_phrase(sent, i):
        kind, metres, hard, j = dist
        return kind, metres, hard, False, j
    return None


def _aim_opening(sent: Sentence, i: int) -> tuple[str, float | None, bool, bool, int] | None:
    """ "as far as practicable from X", "as close as you can to X": a graded (soft) cue."""
    kind = lx.AIM_OPENINGS.get(tuple(sent.words[i : i + 3]))
    if kind is None and tuple(sent.words[i : i + 3]) in lx.AIM_WITH_PREP and sent.free(i, i + 3):
        return lx.AIM_WITH_PREP[tuple(sent.words[i : i + 3])], None, False, False, i + 3  # "as close to X as ..."
    room = sent.mention_at.get(i + 2)  # "as much room as you can from X": "room" is no place
    room = room if room is not None and not room.known and room.end == i + 3 else None
    if kind is None or not (sent.free(i, i + 3) or (room is not None and sent.free(i, i + 2))):
        return None
    preps = ("from", "of") if kind == "far" else ("to", "by")
    for k in range(i + 3, min(sent.n, i + 3 + lx.AIM_GAP + 1)):
        if sent.claimed[k] not in (None,):
            return None
        if sent.words[k] in preps:
            if room is not None:
                sent.drop_mention(room)
            return kind, None, False, False, k + 1
    return None


def _graded_noun_opening(sent: Sentence, i: int) -> tuple[str, float | None, bool, bool, int] | None:
    """ "within sight of X" (near); "minimise proximity to X", "maximise the distance from X"
    (far): graded cues with no distance stated."""
    w = sent.words
    if w[i] == "within" and i + 2 < sent.n and w[i + 1] in lx.WITHIN_NOUNS and sent.free(i, i + 2):
        k = i + 2 + (w[i + 2] == "link")  # "within radio link range of"
        k += k < sent.n and w[k] in ("range", "distance")
        if k < sent.n and w[k] == "of":
            return "near", None, False, False, k + 1
    if (verb := _lessen_verb_opening(sent, i)) is not None:
        return verb
    if w[i] in lx.PROXIMITY_NOUNS | lx.GAP_NOUNS and i + 1 < sent.n and w[i + 1] in ("to", "from", "with"):
        # the verb elsewhere in the sentence: "proximity to the canopy should be minimised",
        # "cost rises with proximity to buildings"
        lessen, said = _lessened(w, i)
        kind = _graded_kind(w[i], lessen) if lessen is not None and sent.free(i, i + 2) else None
        if kind is not None:
            for j in said:  # the verbs that said it are read with the cue
                if sent.free(j, j + 1):
                    sent.claim(Found("filler", j, j + 1, "graded"), "cue")
                    _claim_intensifier(sent, j + 1)
            return kind, None, False, False, i + 2
    return None


def _lessen_verb_opening(sent: Sentence, i: int) -> tuple[str, float | None, bool, bool, int] | None:
    """ "minimise proximity to X", "maximise the distance from X", "minimise proximity(X)": the
    verb before its noun (a graded cue with no distance stated)."""
    w = sent.words
    if w[i] not in lx.LESSEN_VERBS | lx.GROW_VERBS or not sent.free(i, i + 1):
        return None
    k = sent.skip(i + 1, lx.ARTICLES | {"our", "your", "its"})
    if k + 1 >= sent.n:
        return None
    kind = _graded_kind(w[k], w[i] in lx.LESSEN_VERBS)
    if kind is not None and w[k + 1] in ("to", "from", "with", "near"):
        return kind, None, False, False, k + 2
    if kind is not None and w[k] in lx.PROXIMITY_NOUNS and k + 1 in sent.mention_at:  # "proximity(building)"
        return kind, None, False, False, k + 1
    return None


def _claim_intensifier(sent: Sentence, k: int) -> None:
    """ "(penalised) more heavily the closer the robot gets": how a graded cue's verb grows
    with nearness, read with the cue (it says what the cue already says)."""
    w = sent.words
    j = k + (k < sent.n and w[k] == "more")
    j += j < sent.n and w[j] in ("heavily", "strongly", "steeply", "sharply", "severely")
    if j + 1 >= sent.n or j == k or w[j] != "the" or w[j + 1] not in lx.GRADED_NEAR:
        return
    for e in range(j + 2, min(sent.n, j + 7)):
        if w[e] in ("gets", "comes", "goes", "is", "moves", "drives"):
            if sent.free(k, e + 1):
                sent.claim(Found("filler", k, e + 1, "graded"), "cue")
            return


def _graded_kind(noun: str, lessen: bool) -> str | None:
    """The graded cue of lessening or growing a proximity noun or a gap noun: less proximity
    or more distance keeps away (far); less distance or more proximity stays near."""
    if noun in lx.PROXIMITY_NOUNS:
        return "far" if lessen else "near"
    if noun in lx.GAP_NOUNS:
        return "near" if lessen else "far"
    return None


def _lessened(words: list[str], i: int) -> tuple[bool | None, list[int]]:
    """Whether the sentence lessens (True) or grows (False) the proximity or gap noun at ``i``
    with a verb away from it -- a participle after it ("should be minimised"), or a cost that
    rises (the noun is lessened) or falls with it before it -- and where those words are; None
    when neither."""
    after = range(i + 2, len(words))
    for j in after:
        if words[j] in lx.LESSENED or words[j] in lx.GROWN:
            return words[j] in lx.LESSENED, [j]
        if words[j] in lx.PROXIMITY_PRICED | lx.PROXIMITY_REWARDED and words[i] in lx.PROXIMITY_NOUNS:
            return words[j] in lx.PROXIMITY_PRICED, [j]  # "proximity to building: reward"
    before = range(max(0, i - 6), i)
    cost = [j for j in before if words[j] in lx.COST_WORDS]
    change = [j for j in before if words[j] in lx.RISE_VERBS | lx.FALL_VERBS]
    if not cost or not change:
        return None, []
    rises = words[change[0]] in lx.RISE_VERBS
    # "cost rises as the distance falls": the noun's own change after it turns the sense round;
    # "cost should rise with proximity to X and fall ... beyond 40 m" coordinates the cost's
    own = []
    for j in after:
        if words[j] in ("and", ",", ";", "then", "but"):
            break
        if words[j] in lx.FALL_VERBS:
            own.append(j)
    return rises != bool(own), cost + change + own[:1]


def _near_bound(sent: Sentence, start: int) -> tuple[str, int, bool]:
    """A hard "within N m of X" at ``start`` as its words before it turn it: priced ("softly
    penalised within 8 m of X": a soft far zone), denied ("nothing within 12 m of X": far, a
    rule) or as stated (near, a rule); the kind, where the cue starts and whether it is hard."""
    if (priced := priced_within(sent, start)) is not None:
        return priced[0], priced[1], False
    kind, start = denied_bound(sent, start)
    return kind, start, True


def _excess(sent: Sentence, i: int, kind: str) -> tuple[str, int]:
    """A near/far cue after "too" is a warning, the other way round: "go too far from the road
    and we lose you" is near the road, "too close to the water" far from it; (``kind``, ``i``)
    without "too". A negation before it ("don't stray too far") is :func:`negated_kind`'s."""
    if i > 0 and sent.words[i - 1] == "too" and sent.claimed[i - 1] is None:
        return ("near" if kind == "far" else "far"), i - 1
    return kind, i


def _turned(sent: Sentence, i: int, kind: str, metres: float | None) -> tuple[str, int]:
    """A near/far cue with no distance turned round by a negation (:func:`negated_kind`) or,
    failing that, by "too" (:func:`_excess`), and where it then starts; a measured one as said."""
    if metres is not None:
        return kind, i
    kind, start = negated_kind(sent, i, kind)
    return _excess(sent, i, kind) if start == i else (kind, start)


def _distance_cue(sent: Sentence, i: int) -> None:
    """ "near X", "far from X", "at least 20 m from X", "keep away from X by 20 m"."""
    opening = _distance_opening(sent, i)
    if opening is None:
        return
    kind, metres, hard, need_by, j = opening
    j += j < sent.n and sent.words[j] == ":" and sent.claimed[j] is None  # "stay near: the road"
    side = sent.mention_at.get(sent.skip(j, lx.ARTICLES))
    if side is not None and side.role == "side" and sent.words[side.start] in lx.NEAR_SIDE_TOKENS:
        side.role = "target"  # "well away from the shoreline", "near the riverbank": the water it lines
    lst, end = sent.list_forward(j)
    if not lst:
        return
    kind, start = _turned(sent, i, kind, metres)
    if metres is None and end < sent.n and sent.words[end] == "by" and (d := sent.distance(end + 1)):
        metres, end = d[0], d[1]
    elif need_by:
        return  # plain "keep away from X" is the avoid trigger
    if metres is None:
        metres = trailing_distance(sent, end)
    if hard and kind == "near":
        kind, start, hard = _near_bound(sent, start)
    if hard and kind == "far":
        start = bound_negation(sent, start)
    for mm in lst:
        mm.role = "cue"
    sent.claim(Found("cue", start, end, kind, tuple(lst), metres, hard=hard), "cue")


def only_at(f: Found, owner: Clause, names: list[str], words: list[str]) -> None:
    """ "X only at/near Y". Nothing stated or a permission makes X forbidden except near Y: a
    crossing ("cross the railway only at level crossings", "you may wade through the river only
    near the ford") as the nocross rule, any other passage as impassable; a crossing after a
    stated tier ("avoid water, only cross at the bridge") keeps X's tier except near Y; any
    other stated preference ("avoid the river, but only near the village") holds only near Y.
    ``words``: the words of the clause that says "only"."""
    if all(owner.assigned.get(n, "fine") == "fine" for n in names):
        # a crossing allowed only there is the nocross rule (as "never cross X except at Y");
        # any other passage allowed only there makes X impassable elsewhere
        crossing = any(w in lx.CROSS_VERBS for w in words)
        for n in names:
            owner.assigned[n] = "nocross" if crossing else "lethal"
        f.value = "unless_near"
    elif any(w in lx.CROSS_VERBS for w in words):
        f.value = "unless_near"
    else:
        f.value = "if_near"


def attach_conditions(sentence_clauses: list[Clause], st: State) -> None:
    """Attach 'unless/if near X' to the clause it qualifies (its own, else the next/previous)."""
    for i, c in enumerate(sentence_clauses):
        for f in c.found:
            if f.kind != "condition":
                continue
            owner = c if c.assigned else None
            if owner is None:
                later = [d for d in sentence_clauses[i + 1 :] if d.assigned]
                earlier = [d for d in sentence_clauses[:i] if d.assigned]
                owner = later[0] if later else earlier[-1] if earlier else None
            if owner is None:
                st.fragment(st.prompt[c.toks[f.start].start : c.toks[f.end - 1].end])
                continue
            if f.value == "only_at":
                only_at(f, owner, list(owner.assigned), [t.word for t in c.toks[c.start : c.end]])
            metres = f.metres if f.metres is not None else lx.DEFAULT_CUE_DISTANCE_M
            for name in owner.assigned:
                if owner is not c:  # "Unless near the road, stay off the grass"
                    first, last = owner.src.get(name, (owner, owner))
                    owner.src[name] = (
                        min(first, c, key=lambda d: d.span()[0]),
                        max(last, c, key=lambda d: d.span()[1]),
                    )
                for other in f.mentions:
                    st.mention(other.name)
                    st.cues.append(Cue(str(f.value), name, metres, other.name))
