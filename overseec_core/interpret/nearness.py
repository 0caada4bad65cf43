"""Cues of nearness read from their own constructions: a bias toward or away from a thing ("a
slight bias away from the railway"), a cost that rises with nearness, where a cost peaks, a
proximity compound ("proximity penalty: railway"), keeping a thing in sight or in touch ("keep the
road in view", "never lose sight of the trail"), a band between two distances ("stay 5 to 10 m
from the hedge"). Readers :func:`overseec_core.interpret.conditions.claim_cues` tries at each
word; each claims its words and returns whether it read one.
"""

from __future__ import annotations

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.distances import band_phrase
from overseec_core.interpret.sentence import Found, Mention, Sentence
from overseec_core.interpret.tokens import is_adverb


def bias_cue(sent: Sentence, i: int) -> bool:
    """ "bias the planner toward the water's edge", "pull the route towards the road": a
    graded near cue on what the route is pulled toward."""
    w = sent.words
    if w[i] not in lx.BIAS_VERBS or not sent.free(i, i + 1):
        return False
    for k in range(i + 1, min(sent.n, i + 5)):
        if w[k] in ("toward", "towards") and sent.free(i, k + 1):
            lst, end = sent.list_forward(k + 1)
            if not lst:
                return False
            _claim_cue(sent, i, end, "near", lst)
            return True
    return False


def rising_cost(sent: Sentence, i: int) -> bool:
    """ "cost should rise as the route approaches the railway", "the penalty grows as you get
    closer to X": a graded far cue (a falling cost, a near cue) on what is approached."""
    w = sent.words
    if w[i] not in lx.COST_WORDS or not sent.free(i, i + 1):
        return False
    change = next((k for k in range(i + 1, min(sent.n, i + 4)) if w[k] in lx.RISE_VERBS | lx.FALL_VERBS), None)
    if change is None:
        return False
    a = change + 1 + (change + 1 < sent.n and is_adverb(w[change + 1]))  # "rise steadily as": no matter how
    if a >= sent.n or w[a] not in ("as", "when", "while"):
        return False
    for k in range(a + 1, min(sent.n, a + 7)):
        # "as you near the water": "near" is the verb after its subject
        if w[k] in lx.APPROACH_VERBS or (w[k] == "near" and w[k - 1] in ("you", "we", "it", "they", "one")):
            j = k + 1 + (k + 1 < sent.n and w[k + 1] in ("to", "the") and w[k] in ("closer", "nearer"))
            lst, end = sent.list_forward(j)
            if not lst or not sent.free(i, j):
                return False
            # "proximity to houses minimised: the cost should rise as ..." restates the cue
            _claim_unless_restated(sent, i, end, "far" if w[change] in lx.RISE_VERBS else "near", lst)
            return True
    return False


def peak_cue(sent: Sentence, i: int) -> bool:
    """ "costs climb as you approach it, highest right next to it": where the cost peaks, said of
    the ground next to something, is a graded far cue (its lowest there, a near one); one that
    restates a cue the sentence states already is read with it."""
    w = sent.words
    if w[i] not in lx.PEAK_WORDS | lx.TROUGH_WORDS or not sent.free(i, i + 1):
        return False
    j = i + 1
    j += j < sent.n and w[j] in lx.COST_WORDS and sent.free(j, j + 1)  # "highest cost right by it"
    j += j < sent.n and w[j] in lx.PEAK_ADVERBS and sent.free(j, j + 1)
    near = sent.match(lx.NEAR, j)
    if near is None:
        return False
    lst, end = sent.list_forward(j + len(near[0]))
    if not lst:
        return False
    _claim_unless_restated(sent, i, end, "far" if w[i] in lx.PEAK_WORDS else "near", lst)
    return True


def _claim_cue(
    sent: Sentence, start: int, end: int, kind: str, lst: list[Mention], metres: float | None = None
) -> None:
    """Claim words ``start``..``end`` as a ``kind`` cue on ``lst`` (its mentions the cue's, no
    trigger's objects)."""
    for mm in lst:
        mm.role = "cue"
    sent.claim(Found("cue", start, end, kind, tuple(lst), metres), "cue")


def _claim_unless_restated(sent: Sentence, start: int, end: int, kind: str, lst: list[Mention]) -> None:
    """Claim a ``kind`` cue on ``lst``, or, where it restates a cue the sentence already states
    (:func:`_restates`), its words as read with that cue (its mentions dropped)."""
    if not _restates(sent, kind, lst):
        _claim_cue(sent, start, end, kind, lst)
        return
    for mm in lst:
        sent.drop_mention(mm)
    sent.claim(Found("filler", start, end, "graded"), "cue")


def _restates(sent: Sentence, kind: str, lst: list[Mention]) -> bool:
    """Whether a cue of ``kind`` on ``lst`` restates one the sentence already states: the same
    kind on entities of the same head ("residential structures" ... "a building")."""
    heads = {m.name.split()[-1] for m in lst}
    return any(
        f.kind == "cue" and f.value == kind and heads <= {m.name.split()[-1] for m in f.mentions} for f in sent.found
    )


def proximity_compound(sent: Sentence, i: int) -> bool:
    """ "bldg proximity cost: ramps down to 0 at 12 m", "water proximity penalised", "trail
    proximity: reward": a proximity noun right after the entities it is about, priced (a far
    cue) or rewarded (a near cue) by the words after it; with neither it is no cue here (a
    correlative after it, "building proximity: the further the better", reads it as its topic)."""
    w = sent.words
    if w[i] not in lx.PROXIMITY_NOUNS - {"time", "contact"} or not sent.free(i, i + 1):
        return False
    lst = sent.list_backward(i)
    if not lst or max(m.end for m in lst) != i or any(m.role != "target" for m in lst):
        return False
    k = sent.skip(i + 1, {":", "-", "=", "is", "are", "gets", "get", "should", "be", "must", "will"})
    if k >= sent.n or w[k] not in lx.PROXIMITY_PRICED | lx.PROXIMITY_REWARDED | lx.LESSENED | lx.GROWN:
        return False
    lessen = w[k] in lx.PROXIMITY_PRICED | lx.LESSENED
    _claim_cue(sent, min(m.start for m in lst), k + 1, "far" if lessen else "near", lst)
    return True


#: The words that put a price or a reward near a thing ("a penalty near the trees").
_PRICED_NEAR = (("near",), ("close", "to"), ("next", "to"), ("around",), ("beside",), ("by",))


def priced_near(sent: Sentence, i: int) -> bool:
    """ "proximity penalty near trees", "a cost close to the water", "a bonus next to the trail":
    a price put near a thing keeps away from it (a far cue), a reward draws to it (near)."""
    w = sent.words
    k = i + (w[i] in lx.PROXIMITY_NOUNS and i + 1 < sent.n)
    if k + 1 >= sent.n or w[k] not in lx.COST_WORDS | lx.BENEFIT_WORDS or not sent.free(i, k + 1):
        return False
    prep = next((p for p in _PRICED_NEAR if tuple(w[k + 1 : k + 1 + len(p)]) == p), None)
    if prep is None or not sent.free(k + 1, k + 1 + len(prep)):
        return False
    lst, end = sent.list_forward(k + 1 + len(prep))
    if not lst or any(m.role != "target" for m in lst):
        return False
    _claim_cue(sent, i, end, "far" if w[k] in lx.COST_WORDS else "near", lst)
    return True


def in_sight_cue(sent: Sentence, i: int) -> bool:
    """ "keep the trail in sight", "keep the road in view (the whole way)", "keep it close": a
    graded near cue on the entities kept in sight or close (no distance stated, as "within
    sight of X")."""
    if sent.words[i] not in lx.OFF_VERBS | {"have", "having"} or not sent.free(i, i + 1):
        return False
    lst, end = sent.list_forward(i + 1)
    if not lst or end >= sent.n:
        return False
    if sent.words[end] in ("close", "near", "nearby", "handy") and sent.free(end, end + 1):
        stop = end + 1  # "keep it close", "keep the road near"
    elif end + 1 < sent.n and sent.words[end] == "in" and sent.words[end + 1] in lx.WITHIN_NOUNS:
        stop = end + 2
    else:
        return False
    if not sent.free(end, stop):
        return False
    _claim_cue(sent, i, stop, "near", lst)
    return True


#: The contact a route keeps with a thing ("never lose sight of the road", "don't lose track of
#: the river", "without losing touch with the hedge").
_TOUCH_NOUNS = frozenset(lx.WITHIN_NOUNS | {"track", "contact", "touch"})
#: The words right before "lose" that deny the losing.
_LOSS_NEGATORS = frozenset("never not don't dont without shouldn't mustn't won't cannot can't".split())


def kept_in_touch(sent: Sentence, i: int) -> bool:
    """ "never lose sight of the road", "don't lose contact with the trail": the contact a
    route must not lose is a graded near cue on the thing, as "keep the road in sight" is (not
    a ban on the road: the negation is of the losing)."""
    w = sent.words
    if w[i] not in ("lose", "losing") or i == 0 or w[i - 1] not in _LOSS_NEGATORS:
        return False
    if i + 2 >= sent.n or w[i + 1] not in _TOUCH_NOUNS or w[i + 2] not in ("of", "with"):
        return False
    named = [m for j in (i, i + 1) if (m := sent.mention_at.get(j)) is not None and not m.known]
    if any(m.start < i or m.end > i + 2 for m in named):
        return False
    for m in named:  # "lose" or "track" read as a name of their own
        sent.drop_mention(m)
    return _near_what_follows(sent, i - 1, i + 3)


def kept_in_sight(sent: Sentence, i: int) -> bool:
    """ "never let the robot out of eyeshot of the school buildings", "don't let it out of sight
    of the road": what the route must not leave the sight of is a graded near cue on it, not a
    ban (the negation is of the letting out)."""
    w = sent.words
    if w[i] != "let" or i == 0 or w[i - 1] not in _LOSS_NEGATORS:
        return False
    k = i + 1
    while k < sent.n and k - i < 4 and w[k] != "out":  # "let the robot", "let it"
        k += 1
    if k + 3 >= sent.n or w[k] != "out" or w[k + 1] != "of" or w[k + 2] not in _TOUCH_NOUNS or w[k + 3] != "of":
        return False
    for j in range(i + 1, k + 3):  # the traveller, "eyeshot" read as names of their own
        if (m := sent.mention_at.get(j)) is not None and not m.known and m.end <= k + 3:
            sent.drop_mention(m)
    return _near_what_follows(sent, i - 1, k + 4)


def _near_what_follows(sent: Sentence, start: int, end: int) -> bool:
    """Claim words ``start``..``end`` as a graded near cue on the entities listed right after
    them ("never lose sight of | the road and the trail"); False when none are listed there or
    the words are taken."""
    lst, _ = sent.list_forward(end)
    if not lst or not sent.free(start, end):
        return False
    _claim_cue(sent, start, end, "near", lst)
    return True


def band_cue(sent: Sentence, i: int) -> bool:
    """ "has to run between 5 and 10 m from the road", "stay 5 to 10 m from the hedge": a band
    beside something, read as its two edges -- a far cue at the inner distance and a near cue
    at the outer one (rules where the sentence words them as absolute, as any distance is)."""
    band = band_phrase(sent, i)
    if band is None:
        return False
    inner, outer, j = band
    lst, end = sent.list_forward(j)
    if not lst:
        return False
    _claim_cue(sent, i, end, "far", lst, inner)
    _claim_cue(sent, i, end, "near", lst, outer)
    return True
