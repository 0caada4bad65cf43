"""Terse clearance rules and the topics they name: "clearance tree >= 3 m", "railway standoff 15
m", "Buildings: 10 m buffer (hard)", "H2O: 20 m min clearance" -- a far cue of that distance on
the entities after the clearance noun or before it (:func:`clearance_rule`), with the readers of
a topic before a mark (:func:`topic_before`), a distance after one (:func:`distance_after`) and
the entity a rule with no topic is about (:func:`antecedent_topic`), which :mod:`.conditions`'
other cues read too.
"""

from __future__ import annotations

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.sentence import Found, Mention, Sentence


def clearance_rule(sent: Sentence, i: int) -> bool:
    """The terse clearance rule: a clearance noun, its entities (after it or before it) and a
    distance -- "clearance tree >= 3 m", "clearance(tree) >= 3 m", "railway standoff 15 m",
    "railway: soft buffer 6 m", "SOFT clearance building 6m". A far cue of that distance; the
    sentence's wording makes it a rule ("strict", "no exceptions") or keeps it soft."""
    w = sent.words
    if w[i] not in lx.CLEARANCE_NOUNS or not sent.free(i, i + 1):
        return False
    after = i + 1  # "clearance rule: tree >= 3 m"
    while after < sent.n and w[after] in ("rule", "rules", "constraint", ":", "-") and sent.claimed[after] is None:
        after += 1
    lst, k = sent.list_forward(after)
    start = i
    if not lst and (done := _clearance_after_distance(sent, i)) is not None:  # "Buildings: 10 m buffer (hard)"
        return done
    if not lst:  # the entities before: "railway standoff 15 m", "building: min clearance 5 m"
        lst = topic_before(sent, i, lx.SOFTENERS | LEAD_MARKS) or antecedent_topic(sent, i)
        if not lst:
            return False
        start, k = min(m.start for m in lst), i + 1
    d = distance_after(sent, k)
    if d is None:
        return False
    for mm in lst:
        mm.role = "cue"
    sent.claim(Found("cue", start, d[1], "far", tuple(lst), d[0]), "cue")
    return True


def _clearance_after_distance(sent: Sentence, i: int) -> bool | None:
    """ "Buildings: 10 m buffer", "water: try for 15 m clearance", "H2O: 20 m min clearance": the
    clearance noun at ``i`` after its distance and the topic before that; whether it was claimed,
    or None when no distance ends before the noun."""
    gap = i  # the minimum word between the distance and the noun
    while gap > 0 and sent.words[gap - 1] in lx.MIN_WORDS and sent.claimed[gap - 1] is None:
        gap -= 1
    if (before := _distance_before(sent, gap)) is None:
        return None
    metres, at = before
    topic = topic_before(sent, at, lx.SOFTENERS | LEAD_MARKS)
    if not topic or not sent.free(at, i + 1):
        return False
    for mm in topic:
        mm.role = "cue"
    sent.claim(Found("cue", min(m.start for m in topic), i + 1, "far", tuple(topic), metres), "cue")
    return True


def antecedent_topic(sent: Sentence, i: int) -> list[Mention]:
    """ "Bldgs: keep out of. Min separation 5 m, hard.": a clearance sentence that names nothing
    is about the entity the sentence before named last (noted as a reading); [] otherwise."""
    if sent.antecedent is None or sent.mentions or distance_after(sent, i + 1) is None:
        return []
    sent.readings.append((sent.words[i], sent.antecedent, "pronoun"))
    return [Mention(i, i + 1, sent.antecedent, True, role="cue")]


#: Words between a topic and the distance of its clearance ("buildings: >= 3 m standoff",
#: "water: aim for 15 m clearance", "rail: at least 5 m buffer").
LEAD_MARKS = frozenset({">", "<", "at", "least", "min", "minimum", "for", "aim", "go", "give", "keep", "a", "an"})


def _distance_before(sent: Sentence, i: int) -> tuple[float, int] | None:
    """The distance that ends right before word ``i`` ("10 m buffer"): (metres, its first
    index), else None."""
    for k in range(max(0, i - 4), i):
        d = sent.distance(k)
        if d is not None and d[1] == i:
            return d[0], k
    return None


def topic_before(sent: Sentence, k: int, also: frozenset[str] | set[str] = frozenset()) -> list[Mention]:
    """The entities named just before word ``k`` as its topic ("Buildings: 10 m buffer"), a
    mark (or words of ``also``: "railway: soft buffer") or nothing between; empty when none."""
    j = k
    while j > 0 and (sent.words[j - 1] in (":", "-", "=") or sent.words[j - 1] in also) and sent.claimed[j - 1] is None:
        j -= 1
    lst = sent.list_backward(j)
    if not lst or max(m.end for m in lst) != j or any(m.role != "target" for m in lst):
        return []
    return lst


def distance_after(sent: Sentence, k: int) -> tuple[float, int] | None:
    """A free distance at ``k`` after at most three clearance marks (">= 3 m", "of at least 3
    m"): (metres, index after), else None."""
    k0 = k
    while k < sent.n and sent.words[k] in lx.CLEARANCE_MARKS and sent.claimed[k] is None and k - k0 < 3:
        k += 1
    d = sent.distance(k)
    return d if d is not None and sent.free(k, d[1]) else None
