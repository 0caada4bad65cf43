"""Where a graded cue's fall-off ends: the distance past which nearness no longer matters.

Claimed over a :class:`~overseec_core.interpret.sentence.Sentence` by
:func:`overseec_core.interpret.conditions.claim_cues`, each as a ``graded_reach`` cue without
entities of its own that ``cues._shape_graded`` attaches to the graded cue stated before it: a
fall-off's end ("tapering off by 30 m", "falling to nothing at 30 m"; :func:`graded_reach`, whose
verbs of falling are read by the small grammar of :func:`fall_off_opening`), the point past which
distance stops mattering ("past 15 m it stops mattering"; :func:`mattering_reach`) and a distance
said to be all the room wanted ("20 m should be enough"; :func:`enough_reach`). Split from
:mod:`overseec_core.interpret.graded`, which reads how the cue falls off.
"""

from __future__ import annotations

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.sentence import Found, Sentence


def graded_reach(sent: Sentence, i: int) -> bool:
    """ "tapering off by 30 m", "no effect beyond about 12 metres", "up to ~40 m, after that
    whatever": where the graded cue stated before reaches neutral (``value`` "graded_reach";
    ``cues._shape_graded`` attaches it to that cue)."""
    w = sent.words
    openings = [len(p) for p in lx.REACH_BY_FIRST.get(w[i], ()) if tuple(w[i : i + len(p)]) == p]
    if (fall := fall_off_opening(w, i)) is not None:
        openings.append(fall - i)
    for size in openings:
        k = i + size
        opening = tuple(w[i:k])
        if sent.free(i, k):
            d = sent.distance(sent.skip(k, lx.APPROXIMATORS))
            if d is not None and not (d[1] < sent.n and sent.words[d[1]] in ("around", "round", "from", "of")):
                end = d[1]
                if end + 1 < sent.n and w[end] in ("is", "are") and w[end + 1] in lx.REACH_VERDICTS:
                    end += 2  # "within 10 m is pref"
                elif end < sent.n and w[end] == "out" and sent.free(end, end + 1):
                    end += 1  # "reaching at most 25 m out"
                if opening == ("within",) and end == d[1]:
                    continue  # a bare "within 10 m" says no reach
                sent.claim(Found("cue", _reach_subject(sent, i), end, "graded_reach", (), d[0]), "cue")
                return True
    return False


#: Who is said to be at the distance ("once it's 20 m clear", "once we're past 15 m").
_BEING = frozenset({"it's", "its", "it", "is", "we're", "you're", "they're", "we", "you", "are"})


def mattering_reach(sent: Sentence, i: int) -> bool:
    """ "past 15 m it stops mattering", "beyond 30 m it no longer matters", "after 20 m it doesn't
    count", "past about 30 metres I don't care", "from 4 metres on it is all the same": where the
    graded cue before reaches neutral (``graded_reach``), said as the point past
    which distance does not matter."""
    w = sent.words
    at = sent.skip(i + 1, lx.APPROXIMATORS | _BEING)  # "once it's 20 m clear"
    if w[i] not in lx.MATTERING_OPENINGS or (d := sent.distance(sent.skip(at, lx.APPROXIMATORS))) is None:
        return False
    if w[i] == "from" and (d[1] >= sent.n or w[d[1]] not in ("on", "onward", "onwards", "out")):
        return False  # "from 4 metres on it is all the same"; never "20 m from the road"
    for e in range(d[1], min(sent.n, d[1] + 7)):
        no_concern = w[e] in lx.NO_CONCERN_NOUNS and w[e - 1] == "no"  # "beyond 25 m there is no issue"
        if w[e] in lx.MATTERING_WORDS or w[e] in lx.INDIFFERENT_ENDS or no_concern:
            pronouns = [m for m in sent.mentions if i <= m.start <= e and w[m.start] in lx.PRONOUNS]
            taken = {j for m in pronouns for j in range(m.start, m.end)}  # "... on it is all the same"
            if not all(sent.claimed[j] is None or j in taken for j in range(i, e + 1)):
                return False
            for m in pronouns:  # the pronoun is the distance's "it", no mention of the entity
                sent.mentions.remove(m)
                sent.mention_at.pop(m.start, None)
                sent.claimed[m.start] = None
            sent.claim(Found("cue", i, e + 1, "graded_reach", (), d[0]), "cue")
            return True
    return False


def _reach_subject(sent: Sentence, i: int) -> int:
    """Where a reach at ``i`` starts with the quantity that falls off named before it ("the
    penalty dying away by 25 m", "the cost should fade out beyond 20 m"); ``i`` without one."""
    w, k = sent.words, i
    while k > 0 and w[k - 1] in lx.CORRELATIVE_VERBS and sent.claimed[k - 1] is None:
        k -= 1
    if (
        k == 0
        or w[k - 1] not in lx.COST_WORDS | lx.BENEFIT_WORDS | lx.REACH_SUBJECTS
        or sent.claimed[k - 1] is not None
    ):
        return i
    k -= 1
    k -= k > 0 and w[k - 1] in lx.ARTICLES and sent.claimed[k - 1] is None
    return k - (k > 0 and w[k - 1] == "with" and sent.claimed[k - 1] is None)  # "with the effect reaching"


def enough_reach(sent: Sentence, i: int) -> bool:
    """ "About 30 m is plenty", "20 m should be enough": a distance said to be all the room wanted,
    standing alone, is where the graded cue before it reaches neutral (``graded_reach``)."""
    w = sent.words
    d = sent.distance(i)
    if d is None or i > 0 and w[i - 1] not in lx.SEPARATORS:
        return False
    k = d[1]
    while k < sent.n and w[k] in ("is", "are", "should", "will", "would", "be", "probably", "more", "than"):
        k += 1
    if k >= sent.n or w[k] not in lx.ENOUGH_WORDS or not sent.free(i, k):
        return False
    if k + 1 < sent.n and w[k + 1] not in lx.SEPARATORS:
        return False
    if (word := sent.mention_at.get(k)) is not None:
        if word.known:
            return False
        sent.drop_mention(word)  # "plenty" is no place
    sent.claim(Found("cue", i, k + 1, "graded_reach", (), d[0]), "cue")
    return True


def fall_off_opening(words: list[str], i: int) -> int | None:
    """Where the distance of a fall-off's end starts when its words open at ``i`` ("falling to
    nothing at", "fade out entirely beyond", "drops to the background level past", "dying away
    by"): a verb of falling, then optionally a particle, "to" and a level (with "the" and
    "level"/"cost"), a word of how wholly, then a preposition; None when they do not."""
    n = len(words)
    if i >= n or words[i] not in lx.FALL_OFF_VERBS:
        return None
    k = i + 1
    k += k < n and words[k] in lx.FALL_OFF_PARTICLES
    if k < n and words[k] == "to":
        j = k + 1 + (k + 1 < n and words[k + 1] == "the")
        if j + 1 < n and words[j] == "no" and words[j + 1] in lx.NO_CONCERN_NOUNS:  # "to no bother at all"
            k = j + 2 + 2 * (tuple(words[j + 2 : j + 4]) == ("at", "all"))
        elif j >= n or words[j] not in lx.FALL_OFF_LEVELS:
            return None
        else:
            k = j + 1 + (j + 1 < n and words[j + 1] in ("level", "cost", "levels"))
    k += k < n and words[k] in lx.FALL_OFF_WHOLLY
    if k == i + 2 and words[i + 1] in lx.FALL_OFF_PARTICLES and k < n and _number_at(words[k]):
        return k  # "fades out ~20 m", "tapering off 30 m": the particle ends the verb
    if k >= n or words[k] not in lx.FALL_OFF_PREPS or k == i + 1 and words[i] in ("return", "returns", "reach"):
        return None
    return k + 1


def _number_at(word: str) -> bool:
    """Whether a distance may start with ``word`` ("20", "~", "about", "twenty")."""
    return word[:1].isdigit() or word in lx.APPROXIMATORS or word in lx.NUMBER_WORDS


#: The noun a shape's value may end in ("linear decay", "inverse distance", "exponential falloff").
_SHAPE_NOUNS = frozenset({"distance", "decay", "falloff", "fade", "square", "squared", "ramp"})


def keyed_reach(sent: Sentence, i: int) -> bool:
    """ "falloff_m": 20 (read "falloff : 20 m"), "decay = 15 m": a configuration's key for where
    a fall-off ends (``graded_reach``); "mode": "graded" (a key's value) says the cost falls
    off, with no reach of its own. Without a cue before them they grade what the prompt avoids or prefers."""
    w = sent.words
    if w[i] in lx.GRADED_VALUES and i > 0 and sent.free(i, i + 1):
        mark = w[i - 1] in (":", "=")  # "shape = gradual" tokenises without its "="
        start = i - 1 - mark if i - mark > 0 and w[i - 1 - mark] in lx.SHAPE_KEYS else i
        if (mark or start < i) and sent.free(start, i):  # "mode: graded", ": graded"
            end = i + 1 + (i + 1 < sent.n and w[i + 1] in _SHAPE_NOUNS and sent.free(i + 1, i + 2))
            if tuple(w[end : end + 2]) == ("with", "distance") and sent.free(end, end + 2):
                end += 2  # "shape: decay_with_distance"
            sent.claim(Found("cue", start, end, "graded_reach", ()), "cue")  # "shape: inverse distance"
            return True
    if i + 2 >= sent.n or w[i + 1] not in (":", "="):
        return False
    if w[i] not in lx.REACH_KEYS or (d := sent.distance(sent.skip(i + 2, lx.APPROXIMATORS))) is None:
        return False
    if not sent.free(i, d[1]):
        return False
    sent.claim(Found("cue", i, d[1], "graded_reach", (), d[0]), "cue")
    return True
