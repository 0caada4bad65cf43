"""Graded nearness: how a near/far cue falls off with distance, and where it reaches neutral.

Claimed over a :class:`~overseec_core.interpret.sentence.Sentence` by
:func:`overseec_core.interpret.conditions.claim_cues`: correlatives ("the further from X the
better", "the closer to X, the worse", "the heavier the penalty"; :func:`graded_clause`,
:func:`symbolic_graded`), a fall-off's end ("tapering off by 30 m", "falling to nothing at 30 m",
"past 15 m it stops mattering"; :mod:`overseec_core.interpret.reach`), aims with no
object of their own ("..., as far as possible"; :func:`trailing_aim`), restatements of the
fall-off (:func:`graded_explanation`) and a distance stated after a cue's entities
(:func:`trailing_distance`). Without entities of their own these shape the cue stated before them
(``graded_far`` / ``graded_near`` / ``graded_reach``: ``cues._shape_graded``).
"""

from __future__ import annotations

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.sentence import Found, Mention, Sentence


def _explained_kind(sent: Sentence, cue: Found | None) -> str | None:
    """Whether the cue a graded restatement explains keeps far or near (None: no such cue). In
    its own sentence after the cue's ("...; the penalty should decrease with distance and be
    negligible beyond 30 m") it is the graded cue's reach; "don't go near the pond" (whose
    trigger is claimed later) keeps far."""
    kind = {"far": "far", "near": "near", "graded_reach": "far"}.get(cue.value) if cue is not None else None
    if cue is None or kind is None:
        return None
    before = sent.words[max(0, cue.start - 3) : cue.start]
    if kind == "near" and any(w in lx.FAR_NEGATORS or w in lx.AVOID_WORDS for w in before):
        return "far"
    return kind


def graded_explanation(sent: Sentence, i: int) -> bool:
    """ "... ; the penalty should decrease with distance", "..., with the benefit diminishing
    with distance": a clause restating how the cue before it falls off (the penalty of a far
    cue, the benefit of a near one, falling with distance), read with that cue. A restatement
    that contradicts the cue, or one with no cue before it, is not read."""
    w = sent.words
    noun = sent.mention_at.get(i)  # "benefit" may have been taken for an open-vocabulary name
    if w[i] not in lx.COST_WORDS | lx.BENEFIT_WORDS or (noun is not None and noun.known):
        return False
    if noun is None and not sent.free(i, i + 1):
        return False
    cue = next((f for f in reversed(sent.found) if f.kind == "cue"), None)
    kind = _explained_kind(sent, cue)
    if cue is None or kind is None:
        return False
    for k in range(i + 1, min(sent.n - 2, i + 5)):
        if w[k] in lx.FALL_VERBS and w[k + 1] == "with" and w[k + 2] in ("distance", "range"):
            if cue.value == "graded_reach" and w[i] not in lx.COST_WORDS:
                return False
            if (kind == "far") != (w[i] in lx.COST_WORDS) or not sent.free(i + 1, k + 3):
                return False
            if noun is not None:
                sent.drop_mention(noun)
            start = i
            while start > 0 and sent.claimed[start - 1] is None and w[start - 1] in lx.ARTICLES | {"with"}:
                start -= 1
            sent.claim(Found("filler", start, k + 3, "graded"), "cue")
            return True
    return False


#: The room a cost is said to change with ("rises as the gap shrinks", "falls as the distance grows").
_GAP_NOUNS = frozenset({"gap", "gaps", "distance", "separation", "clearance", "range", "spacing"})
_CLOSING = frozenset({"closes", "narrows", "shrinks", "shortens", "falls", "drops", "decreases", "tightens"})
_OPENING = frozenset({"opens", "widens", "grows", "lengthens", "rises", "increases"})


def rising_as_gap_closes(sent: Sentence, i: int) -> bool:
    """ "(the cost) rises as the gap shrinks", "(the penalty) falls as the distance grows": a
    restatement that the cost before it is graded, read with the cue it restates (``graded_far``;
    a benefit rising as the gap closes, ``graded_near``)."""
    w = sent.words
    k = i + (w[i] in lx.COST_WORDS | lx.BENEFIT_WORDS)
    if k + 3 >= sent.n or w[k] not in lx.RISE_VERBS | lx.FALL_VERBS or w[k + 1] != "as":
        return False
    j = k + 2 + (w[k + 2] == "the")
    if j + 1 >= sent.n or w[j] not in _GAP_NOUNS or w[j + 1] not in _CLOSING | _OPENING:
        return False
    if not sent.free(i, j + 2):
        return False
    dearer_nearer = (w[k] in lx.RISE_VERBS) == (w[j + 1] in _CLOSING)
    benefit = w[i] in lx.BENEFIT_WORDS
    sent.claim(Found("cue", i, j + 2, "graded_far" if dearer_nearer != benefit else "graded_near", ()), "cue")
    return True


def _correlative_end(w: list[str], k: int) -> bool | None:
    """ "the better" / "the cheaper" (True), "the worse" / "the more expensive" (False) at word
    ``k``, else None."""
    if k + 1 >= len(w) or w[k] != "the":
        return None
    word = w[k + 2] if w[k + 1] == "more" and k + 2 < len(w) else w[k + 1]
    if word in lx.CORRELATIVE_GOOD or word in lx.FEELING_BETTER:
        return True
    if word in lx.CORRELATIVE_BAD or word in lx.FEELING_WORSE or _bothers(w, k):
        return False
    more, less = w[k + 1] in lx.CORRELATIVE_MORE, w[k + 1] in lx.CORRELATIVE_LESS
    if more or less:  # "the heavier the penalty" is worse, "the bigger the reward" better
        j = k + 2 + (k + 2 < len(w) and w[k + 2] == "the")
        noun = w[j] if j < len(w) else ""
        if noun in lx.BENEFIT_WORDS:
            return less is False
        if noun in lx.COST_WORDS or (more and not noun.isalpha()):
            return more is False
        if noun in ("i", "we", "they") and j + 1 < len(w) and w[j + 1] in _WORRIES:  # "the less I worry"
            return less
    return None


def _bothers(w: list[str], k: int) -> bool:
    """ "the more it bugs people", "the more it worries me": a correlative's end that bothers."""
    return tuple(w[k + 1 : k + 3]) == ("more", "it") and k + 3 < len(w) and w[k + 3] in lx.BOTHER_VERBS


#: Who feels a correlative's end, and how ("the twitchier I get", "the more it bugs people").
_FEELERS = frozenset({"i", "we", "they", "you", "people", "everyone", "folk", "folks", "me", "us", "them"})
_FEEL_VERBS = frozenset({"get", "gets", "feel", "feels", "am", "are", "is", "become", "grow"})


def _correlative_stop(w: list[str], k: int) -> int:
    """Where a correlative's second half that ends at ``k`` (after "the heavier") really ends:
    past the quantity it grows ("the penalty", "the cost should be", "the reward gets")."""
    j = k + (k < len(w) and w[k] == "the")
    if j < len(w) and w[j] in lx.COST_WORDS | lx.BENEFIT_WORDS:
        k = j + 1
        while k < len(w) and w[k] in lx.CORRELATIVE_VERBS:
            k += 1
    return k


def _correlative_gap(sent: Sentence, k: int) -> tuple[int, list[Mention]] | None:
    """ "the nearer <a few words> to X, the cheaper": the index of the second "the" and X."""
    w = sent.words
    for j in range(k, min(sent.n, k + 8)):
        if w[j] in ("to", "from", "off") and j + 1 < sent.n:  # "the farther it wanders off the trail, the worse"
            lst, e = sent.list_forward(j + 1)
            e += e < sent.n and w[e] == ","  # "the nearer ... to it, the cheaper"
            if lst and _correlative_end(w, e) is not None:
                return e, lst
    return None


def graded_clause(sent: Sentence, i: int) -> bool:
    """ "the further the better (up to 25 m)", "the closer to the river the better": how a
    graded cue falls off. With an entity it is a cue of its own; without, it shapes the cue
    stated before it (``value`` "graded_far"/"graded_near"; ``cues._shape_graded`` attaches it)."""
    w = sent.words
    if (other := _other_graded(sent, i)) is not None:
        return other
    if i + 1 >= sent.n or w[i] != "the" or w[i + 1] not in lx.GRADED_FAR | lx.GRADED_NEAR:
        return False
    kind = "far" if w[i + 1] in lx.GRADED_FAR else "near"
    k, lst = i + 2, list[Mention]()
    if k < sent.n and w[k] in ("from", "to", "away"):
        k += 1 + (w[k] == "away" and k + 1 < sent.n and w[k + 1] == "from")
        lst, k = sent.list_forward(k)
        if not lst:
            return False
        k += k < sent.n and w[k] == "," and _correlative_end(w, k + 1) is not None  # "the closer to X, the worse"
    k = _traveller_gap(w, k) if _correlative_end(w, k) is None else k  # "the closer it gets, the worse"
    verdict = _correlative_end(w, k)
    if verdict is None and lst == []:
        k, lst = _correlative_subject(sent, k)
        verdict = _correlative_end(w, k)
    if verdict is None or not sent.free(i, i + 2):
        return False
    start = i
    if not lst and (lst := _graded_topic(sent, i)):  # "water: the further the better"
        start = min(m.start for m in lst)
    if not verdict:  # "the closer, the worse": it is the other way round
        kind = "near" if kind == "far" else "far"
    end = _second_half_end(w, k)
    metres = None
    up = end + (end < sent.n and w[end] == ",")  # "the better, up to 30 metres"
    if tuple(w[up : up + 2]) == ("up", "to") and (d := sent.distance(up + 2)) and sent.free(end, d[1]):
        metres, end = d[0], d[1]
        end = _beyond_which(sent, end)
    else:
        metres = trailing_distance(sent, end)
    _claim_graded(sent, start, end, kind, lst, metres)
    return True


#: What a distance step is counted in ("every metre closer", "each step nearer").
_STEPS = frozenset(set(lx.UNITS) | {"step", "steps", "pace", "paces", "inch", "inches", "bit"})
#: How a step is said to count ("is worse", "counts against it", "costs more").
_STEP_VERDICTS = {"against": False, "worse": False, "better": True, "more": False, "less": True}


def _per_step(sent: Sentence, i: int) -> bool | None:
    """ "each metre closer worse", "every metre nearer the water counts against it", "every
    step further from the road is better": a graded cue said per step of distance, on the
    object after the comparative or the topic before; None when the words are not there."""
    w = sent.words
    if i + 3 >= sent.n or w[i] not in ("each", "every") or w[i + 1] not in _STEPS:
        return None
    if w[i + 2] not in lx.GRADED_FAR | lx.GRADED_NEAR:
        return None
    j = _traveller_gap(w, i + 3)  # "every metre further the rig runs from the water"
    j += j < sent.n and w[j] in ("to", "from", "away", "off")
    lst, k = sent.list_forward(j)
    k = k if lst else j
    after = k
    while k < sent.n and w[k] in ("is", "are", "counts", "count", "costs", "means", "makes", "=") and k - i < 12:
        k += 1
    if k + 1 < sent.n and w[k] in ("a", "one") and w[k + 1] in _STEPS:  # "is a metre better", "a bit worse"
        k += 2
    good = _STEP_VERDICTS.get(w[k]) if k < sent.n else None
    step = sent.mention_at.get(i + 1)  # "step" may have been read as a name
    if (
        good is None
        or not sent.free(after, k + 1)
        or not all(sent.claimed[x] in (None, "mention") for x in (i, i + 1, i + 2))
    ):
        return None
    if step is not None and not step.known:
        sent.drop_mention(step)
    end = k + 1
    end += w[k] == "against" and end < sent.n and w[end] in lx.PRONOUNS and sent.free(end, end + 1)  # "against it"
    kind = "far" if (w[i + 2] in lx.GRADED_FAR) == good else "near"
    lst = lst or _graded_topic(sent, i)
    _claim_graded(sent, min([i] + [m.start for m in lst if m.start < i]), end, kind, lst, trailing_distance(sent, end))
    return True


def _second_half_end(w: list[str], k: int) -> int:
    """Where a correlative's second half, starting at the "the" at ``k``, ends ("the worse", "the
    more expensive", "the less I worry")."""
    if k + 3 < len(w) and w[k + 2] in ("i", "we", "they") and w[k + 3] in _WORRIES:
        return k + 4
    j = k + 2 + (w[k + 1] == "more")
    if _bothers(w, k):  # "the more it bugs people"
        j = k + 4
    elif w[j - 1] not in lx.FEELING_WORSE | lx.FEELING_BETTER:
        return _correlative_stop(w, j)
    while j < len(w) and w[j] in _FEELERS | _FEEL_VERBS:  # "the twitchier I get"
        j += 1
    return j


def _other_graded(sent: Sentence, i: int) -> bool | None:
    """A graded clause said other than as "the X-er ..., the Y-er" (more room, a plain
    comparative, a step of distance): whether it read one, None when none is there."""
    for reader in (_wider_room, _plain_comparative, _per_step, _verdict_first):
        if (other := reader(sent, i)) is not None:
            return other
    return None


def _plain_comparative(sent: Sentence, i: int) -> bool | None:
    """ "water: farther is better", "trail - closer is best": the correlative said plainly, of
    the topic named before it; None when the words are not there, False when no topic is."""
    w = sent.words
    if i + 2 >= sent.n or w[i] not in lx.GRADED_FAR | lx.GRADED_NEAR:
        return None
    if w[i + 1] not in _SAYS:
        return _comparative_of(sent, i)
    good = _comparative_verdict(w, i + 2)
    if good is None:
        return None
    lst = _graded_topic(sent, i)
    if not lst or not sent.free(i, i + 3):
        return False
    kind = "far" if (w[i] in lx.GRADED_FAR) == good else "near"
    _claim_graded(sent, min(m.start for m in lst), i + 3, kind, lst, trailing_distance(sent, i + 3))
    return True


#: The verb between a plain comparative and its verdict ("farther is better", "nearer the water
#: means worse").
_SAYS = frozenset({"is", "=", "'s", "means", "mean"})


def _comparative_verdict(w: list[str], k: int) -> bool | None:
    """Whether the verdict at ``k`` is good (True) or bad (False); None when there is none."""
    if k >= len(w):
        return None
    if w[k] in lx.CORRELATIVE_GOOD | {"best", "good"}:
        return True
    return False if w[k] in lx.CORRELATIVE_BAD | {"worst", "bad"} else None


def _comparative_of(sent: Sentence, i: int) -> bool | None:
    """ "nearer the water means worse", "closer to the road is better", "further from the
    buildings is best": a plain comparative with its object after it, a graded cue on the
    object; None when the words are not there."""
    w = sent.words
    j = i + 1 + (w[i + 1] in ("to", "from"))
    lst, k = sent.list_forward(j)
    if not lst or k + 1 >= sent.n or w[k] not in _SAYS or not sent.free(i, j):
        return None
    good = _comparative_verdict(w, k + 1)
    if good is None or not sent.free(k, k + 2):
        return None
    kind = "far" if (w[i] in lx.GRADED_FAR) == good else "near"
    _claim_graded(sent, i, k + 2, kind, lst, trailing_distance(sent, k + 2))
    return True


#: Words between the room of "the wider the margin" and whom it is given ("you give (to)",
#: "we leave around", "from").
_ROOM_GIVING = frozenset({"you", "we", "i", "give", "leave", "allow", "keep", "to", "around", "round", "from", "of"})


def _wider_room(sent: Sentence, i: int) -> bool | None:
    """ "the wider the margin you give the buildings, the happier everyone is", "the more room
    around the hedges the better": more room is further away, a graded far cue on whom it is
    given (claimed with its second half); less room nearer ("the smaller the gap between unit and
    road the better"); None when the words at ``i`` are not such a clause."""
    w = sent.words
    if i + 2 >= sent.n or w[i] != "the" or w[i + 1] not in lx.WIDER_WORDS | lx.NARROWER_WORDS:
        return None
    wider = w[i + 1] in lx.WIDER_WORDS
    r = i + 2 + (w[i + 2] == "the" and i + 3 < sent.n)  # "the wider the margin", "the more room"
    room = sent.mention_at.get(r)  # "margin" may have been taken for an edge, "room" for a name
    if w[r] not in lx.GAP_NOUNS | lx.ROOM_NOUNS | {"berth"} or not sent.free(i, r):
        return None
    if sent.claimed[r] is not None and (room is None or room.known and room.role != "side"):
        return None
    k = r + 1
    while k < sent.n and w[k] in _ROOM_GIVING | _GAP_SIDES and sent.claimed[k] is None and k - i < 8:
        k += 1  # "the smaller the gap between unit and road"
    lst, e = sent.list_forward(k)
    e += e < sent.n and w[e] == ","
    good = _correlative_end(w, e) if lst else None
    if good is None:
        return None
    if room is not None:
        sent.drop_mention(room)
    end = e + 2
    while end < sent.n and w[end] in _CORRELATIVE_PEOPLE | lx.CORRELATIVE_VERBS | {"am"}:
        if (who := sent.mention_at.get(end)) is not None and not who.known:
            sent.drop_mention(who)  # "everyone" is no place
        end += 1  # "the happier everyone is"
    _claim_graded(sent, i, end, "far" if good == wider else "near", lst, trailing_distance(sent, end))
    return True


#: Care said as a verdict ("more cautious the closer it gets"): more of it is worse.
_CARE_WORDS = frozenset({"cautious", "careful", "wary", "nervous", "worried", "alert"})


def _first_verdict(w: list[str], i: int) -> tuple[bool, int] | None:
    """A verdict standing before the correlative it judges ("worse", "more cautious", "it's
    cheaper"): whether it is good, and where the correlative's "the" starts; None when none."""
    k = i + (2 if tuple(w[i : i + 2]) in (("it", "is"), ("it", "gets")) else w[i] in ("it's", "its"))
    if k < len(w) and w[k] in lx.CORRELATIVE_GOOD | lx.CORRELATIVE_BAD:
        return w[k] in lx.CORRELATIVE_GOOD, k + 1
    if k + 1 < len(w) and w[k] in ("more", "less") and w[k + 1] in _CARE_WORDS:
        return w[k] == "less", k + 2
    return None


def _verdict_first(sent: Sentence, i: int) -> bool | None:
    """ "worse the closer it gets", "more cautious the closer you get to the pond", "it's better
    the nearer it stays to the trail": a correlative whose verdict comes first, of the object
    after its comparative or, with none, shaping the cue before it; None when not there."""
    w = sent.words
    if (first := _first_verdict(w, i)) is None:
        return None
    good, k = first
    if k + 1 >= sent.n or w[k] != "the" or w[k + 1] not in lx.GRADED_FAR | lx.GRADED_NEAR:
        return None
    j = _traveller_gap(w, k + 2)
    lst, end = list[Mention](), j
    if j < sent.n and w[j] in ("to", "from", "off"):
        lst, end = sent.list_forward(j + 1)
        end = end if lst else j
    if not sent.free(i, k + 2) or any(sent.claimed[x] not in (None, "mention") for x in range(k + 2, end)):
        return None
    for m in [m for m in sent.mentions if k + 2 <= m.start < j and sent.words[m.start] in lx.PRONOUNS]:
        sent.drop_mention(m)  # "it gets": the traveller, no mention of the entity
    kind = "far" if (w[k + 1] in lx.GRADED_FAR) == good else "near"
    lst = lst or _graded_topic(sent, i)
    _claim_graded(sent, min([i] + [m.start for m in lst]), end, kind, lst, trailing_distance(sent, end))
    return True


#: The route's own side of a gap, between the room and what it is kept from ("between unit and").
_GAP_SIDES = frozenset({"between", "and"} | lx.ROUTE_SELVES)


#: Who a correlative's second half is said of ("the happier everyone is", "the better we like it").
_CORRELATIVE_PEOPLE = frozenset({"everyone", "everybody", "we", "i", "you", "they", "all"})


#: Who moves between a correlative's halves ("the closer it gets", "the nearer the rover comes").
_MOVERS = frozenset({"it", "you", "we", "they", "one", "route", "path"} | lx.TRAVELLER_WORDS)
_MOVING = frozenset(
    "get gets come comes go goes is are drives moves stay stays runs wanders strays drifts ventures creeps edges"
    " sneaks".split()
)
#: What a speaker does less of the better it is ("the closer in it stays, the less I worry").
_WORRIES = frozenset({"worry", "worries", "fret", "frets", "fuss", "panic", "stress"})


def _traveller_gap(w: list[str], k: int) -> int:
    """Past "it gets", "the rover comes" (and a comma) between a correlative's halves; ``k``
    when no traveller's clause stands there."""
    k += k < len(w) and w[k] in ("in", "out", "away")  # "the closer in it stays"
    j = k + (k < len(w) and w[k] in ("the", "a", "our"))
    if j + 1 >= len(w) or w[j] not in _MOVERS or w[j + 1] not in _MOVING:
        return k
    return j + 2 + (j + 2 < len(w) and w[j + 2] == ",")


def _correlative_subject(sent: Sentence, k: int) -> tuple[int, list[Mention]]:
    """The entities of a correlative named between its halves, and where its second half
    starts: "the nearer a cell is to it, the cheaper", "the nearer the shoreline, the cheaper";
    (``k``, []) when there are none."""
    if (j := _correlative_gap(sent, k)) is not None:
        return j
    side = sent.mention_at.get(sent.skip(k, lx.ARTICLES))
    if side is not None and side.role == "side":  # "shoreline": the water's side is the water here
        side.role = "target"
    named, e = sent.list_forward(k)
    e += e < sent.n and sent.words[e] == ","
    if named and _correlative_end(sent.words, e) is not None:
        return e, named
    return k, []


def _beyond_which(sent: Sentence, end: int) -> int:
    """Past ", beyond which (distance) no longer matters" after a graded reach (it restates the
    reach); ``end`` when it is not there."""
    w = sent.words
    k = end + (end < sent.n and w[end] == ",")
    if tuple(w[k : k + 2]) not in (("beyond", "which"), ("after", "which"), ("past", "which")):
        return end
    for e in range(k + 2, min(sent.n, k + 8)):
        if w[e] in ("matters", "matter", "counts", "count", "applies"):
            return e + 1 if sent.free(end, e + 1) else end
    return end


def symbolic_graded(sent: Sentence, i: int) -> bool:
    """ "closer = worse", "nearer -> cheaper", "further is better": the terse correlative, about
    its topic ("water: closer = worse") or, with none, shaping the cue before it."""
    w = sent.words
    gap = i + 1 < sent.n and w[i] == "more" and w[i + 1] in ("distance", "space", "room", "clearance")
    if i + 1 >= sent.n or not (gap or w[i] in lx.GRADED_FAR | lx.GRADED_NEAR):
        return False
    k = i + 1 + gap  # "more distance = better" says what "further = better" says
    k += k < sent.n and w[k] in (":", "=", "->", "→", "is", "means")  # the tokens read "=" and "->" as ":"
    if k >= sent.n or not sent.free(i, k + 1):
        return False
    good = w[k] in lx.CORRELATIVE_GOOD
    if not (good or w[k] in lx.CORRELATIVE_BAD):
        return False
    kind = "far" if gap or w[i] in lx.GRADED_FAR else "near"
    if not good:
        kind = "near" if kind == "far" else "far"
    lst = _graded_topic(sent, i)
    start = min((m.start for m in lst), default=i)
    end, metres = k + 1, trailing_distance(sent, k + 1)
    if metres is None and end + 1 < sent.n and w[end] == "," and (d := sent.distance(end + 1)) and d[1] == sent.n:
        metres, end = d[0], d[1]  # "road: avoid, closer = worse, 20m": the reach ends the sentence
    _claim_graded(sent, start, end, kind, lst, metres)
    return True


#: Closeness restated as a pleasure ("nice and close", "good and tight").
_NICE = frozenset({"nice", "good", "lovely"})
_NICE_CLOSE = {"close": "near", "near": "near", "tight": "near", "snug": "near", "far": "far", "clear": "far"}


def nice_and_close(sent: Sentence, i: int) -> bool:
    """ "near the house, nice and close", "keep off the rails, nice and clear": the cue before
    restated (``graded_near`` / ``graded_far``, shaping it as "the closer the better" does)."""
    w = sent.words
    if i + 2 >= sent.n or w[i] not in _NICE or w[i + 1] != "and" or w[i + 2] not in _NICE_CLOSE:
        return False
    if not sent.free(i, i + 3):
        return False
    sent.claim(Found("cue", i, i + 3, f"graded_{_NICE_CLOSE[w[i + 2]]}", ()), "cue")
    return True


def trailing_aim(sent: Sentence, i: int) -> bool:
    """ "stay away from the railway, as far as possible", "hug the trail as closely as you can":
    an aim with no object of its own grades the cue or the keeping-away stated before it
    (``graded_far`` / ``graded_near``, as "the further the better" does)."""
    w = sent.words
    if i + 3 >= sent.n or w[i] != "as" or w[i + 1] not in lx.AIM_WORDS:
        return False
    kind = lx.AIM_WORDS[w[i + 1]]
    k = i + 2 + (w[i + 2] == "away")
    if k >= sent.n or w[k] != "as":
        return False
    end = next((k + 1 + len(p) for p in lx.AIM_ENDS if tuple(w[k + 1 : k + 1 + len(p)]) == p), None)
    if end is None or not sent.free(i, end):
        return False
    if any(x in ("from", "of", "to") for x in w[end : end + 2]):
        return False  # "as far as possible from the railway": the aim's own object (_aim_opening)
    end += end < sent.n and w[end] in ("is", "=")
    end += end < sent.n and w[end] in ("more", "much", "even", "the")
    end += end < sent.n and w[end] in lx.CORRELATIVE_GOOD | {"best"}
    if lst := _graded_topic(sent, i):  # "building: as far as possible"
        _claim_graded(sent, min(m.start for m in lst), end, kind, lst, None)
        return True
    sent.claim(Found("cue", i, end, f"graded_{kind}", ()), "cue")
    return True


def _claim_graded(sent: Sentence, start: int, end: int, kind: str, lst: list[Mention], metres: float | None) -> None:
    """Claim a graded clause: a near/far cue on ``lst``, or with no entities a ``graded_<kind>``
    that shapes the cue stated before it (``cues._shape_graded``)."""
    for mm in lst:
        mm.role = "cue"
    sent.claim(Found("cue", start, end, kind if lst else f"graded_{kind}", tuple(lst), metres), "cue")


#: What may stand between a topic and its graded clause: "water: the further the better",
#: "railway - the further the better", "pylons = the closer the worse".
TOPIC_MARKS = frozenset({":", "-", "=", ",", "->", "→"})


def _graded_topic(sent: Sentence, i: int) -> list[Mention]:
    """The entities a graded clause at ``i`` is about when they are its topic, named just before
    it with nothing but a mark between and nothing else governing them: "water: the further the
    better", "trail, the closer the better". The list opens the sentence or follows a mark of
    its own ("roads fine; water the further the better"); empty when there is none."""
    j = i
    while j > 0 and sent.words[j - 1] in TOPIC_MARKS and sent.claimed[j - 1] is None:
        j -= 1
    lst = sent.list_backward(j)
    if not lst or any(m.role != "target" for m in lst):
        return []
    first = min(m.start for m in lst)
    k = first - 1
    while k >= 0 and sent.words[k] in lx.ARTICLES and sent.claimed[k] is None:
        k -= 1
    if k >= 0 and sent.words[k] not in TOPIC_MARKS | {";", "."}:
        return []
    if any(sent.claimed[t] not in (None, "mention") for t in range(first, i)):
        return []
    return lst


#: Words that introduce a distance given after the cue ("keep some distance from the river,
#: say 20 m", "a wide berth to the houses (about 25 m)").
#: A copula or sign states it ("the minimum separation from the railway is 20 m", "buffer
#: around the pylons: 15 m").
_AFTERTHOUGHT = {
    "say",
    "about",
    "around",
    "roughly",
    "approximately",
    "maybe",
    "like",
    "approx",
    "circa",
    "of",
    "is",
    "are",
    "be",
    "=",
    ":",
    "equals",
    "remains",
    "stays",
}


def trailing_distance(sent: Sentence, end: int) -> float | None:
    """A distance stated just after a cue's entity list ("..., say 20 m"): its metres (the words
    are claimed as the cue's), or None. A number in a rule always survives."""
    for k in range(end, min(sent.n, end + 4)):
        if sent.claimed[k] is not None:
            return None
        if k == end and (d := sent.distance(k)):  # "min dist to trees 3 mtrs": the number right after
            for j in range(end, d[1]):
                sent.claimed[j] = "cue"
            return d[0]
        if sent.words[k] in _AFTERTHOUGHT and (d := sent.distance(k + 1)):
            stop = d[1] + (d[1] < sent.n and sent.words[d[1]] in lx.MIN_WORDS and sent.claimed[d[1]] is None)
            for j in range(end, stop):  # "standoff from the depot: 25 m minimum"
                sent.claimed[j] = "cue"
            return d[0]
        if sent.words[k] not in lx.SEPARATORS and sent.words[k] not in lx.FILLER:
            return None
    return None
