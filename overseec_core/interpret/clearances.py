"""Terse clearance rules and the topics they name: "clearance tree >= 3 m", "railway standoff 15
m", "Buildings: 10 m buffer (hard)", "H2O: 20 m min clearance" -- a far cue of that distance on
the entities after the clearance noun or before it (:func:`clearance_rule`), with the readers of
a topic before a mark (:func:`topic_before`), a distance after one (:func:`distance_after`) and
the entity a rule with no topic is about (:func:`antecedent_topic`), which :mod:`.conditions`'
other cues read too; and the distance lines about a topic ("rail: 5 m min", "bldgs 5 m hard",
:func:`topic_bound`) or keeping away from it ("water: keep well away", :func:`topic_away`).
"""

from __future__ import annotations

import re

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.sentence import Found, Mention, Sentence


def clearance_rule(sent: Sentence, i: int) -> bool:
    """The terse clearance rule: a clearance noun, its entities (after it or before it) and a
    distance -- "clearance tree >= 3 m", "clearance(tree) >= 3 m", "railway standoff 15 m",
    "railway: soft buffer 6 m", "SOFT clearance building 6m". A far cue of that distance; the
    sentence's wording makes it a rule ("strict", "no exceptions") or keeps it soft."""
    w = sent.words
    least_distance = w[i] in ("distance", "spacing") and i > 0 and w[i - 1] in lx.MIN_WORDS  # "min distance: 15 m"
    if not (w[i] in lx.CLEARANCE_NOUNS or least_distance) or not sent.free(i, i + 1):
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
    d = distance_after(sent, k) or _bare_metres(sent, k)
    if d is None:
        return False
    for mm in lst:
        mm.role = "cue"
    sent.claim(Found("cue", start, d[1], "far", tuple(lst), d[0]), "cue")
    return True


#: What may end a clearance rule's bare number ("clearance water 12", "clearance pond 12 soft").
_BARE_ENDS = frozenset({":", ";", ",", "hard", "soft", ")"})


def _bare_metres(sent: Sentence, k: int) -> tuple[float, int] | None:
    """A clearance rule's number written without a unit ("(clearance railway 15 :strict nil)"):
    metres, the tool's unit, where the number ends the rule; None otherwise."""
    w = sent.words
    if k >= sent.n or not sent.free(k, k + 1) or not re.fullmatch(r"\d+(?:\.\d+)?", w[k]):
        return None
    return (float(w[k]), k + 1) if k + 1 == sent.n or w[k + 1] in _BARE_ENDS else None


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


#: Bounds written after a topic's distance ("rail: 5 m min", "road: 50 m max"): far or near.
_TOPIC_BOUNDS = {"min": "far", "minimum": "far", "max": "near", "maximum": "near"}
#: Words between a topic's mark and its distance ("building: keep 5 m", "road: soft 2 m",
#: "water: keep >= 12 m"): the rule's verb, how strict it is, a clearance mark.
_TOPIC_LEADS = frozenset({"keep", "soft", "hard", "within", "<"}) | (lx.CLEARANCE_MARKS - {":", "="})
#: Words after a topic's distance that say how strict it is ("..., HARD", "... if possible").
_TOPIC_TAILS = frozenset({",", "hard", "mandatory", "strict", "soft", "if", "possible", "ideally", "preferably"})
_TOPIC_HARD = frozenset({"hard", "mandatory", "strict", "min", "minimum", "max", "maximum", ">", "≥", "least"})
_TOPIC_SOFT = frozenset({"soft", "possible", "ideally", "preferably"})
#: Signs that stand for the topic's mark ("railway >= 25 m", "dist(path, water) > 10 m").
_TOPIC_SIGNS = frozenset({">", "≥", "<"})
#: A label written before a distance line's topic ("HARD railway >= 25 m", "SOFT water > 10 m").
_TOPIC_LABELS = frozenset({"hard", "soft", "strict", "mandatory"})


def topic_bound(sent: Sentence, i: int) -> bool:
    """A distance line about the topic named before it ("rail: 5 m min", "trail: 50 m max",
    "building -> keep 5m, HARD", "road: keep ~8 m if possible", "water: 5 m"), with only a
    mark, the rule's verb and how strict it is around the distance: a far cue of that distance
    (near with "max"/"within"), hard where a word says so ("HARD", "mandatory", "min", ">="),
    soft otherwise (a heading line, "HARD LIMITS", can harden it: :func:`offline.analyse`)."""
    d = sent.distance(i)
    if d is None:
        return False
    w = sent.words
    j = i
    while j > 0 and w[j - 1] in _TOPIC_LEADS and sent.claimed[j - 1] is None:
        j -= 1
    k = d[1]
    while k < sent.n and (w[k] in _TOPIC_TAILS or w[k] in _TOPIC_BOUNDS) and sent.claimed[k] is None:
        k += 1
    signed = j < i and w[j] in _TOPIC_SIGNS  # "railway >= 25 m": the sign is the mark
    if k < sent.n and w[k] not in lx.SEPARATORS or not sent.free(j, k) or j == 0:
        return False
    tail = set(w[d[1] : k])
    # "bldgs 5 m hard": a terse line with no mark says it by the strictness after the distance
    if w[j - 1] not in (":", "=") and not signed and not tail & (_TOPIC_HARD | _TOPIC_SOFT):
        return False
    topic = topic_before(sent, j)
    if not topic:
        return False
    for mm in topic:
        mm.role = "cue"
    start = min(m.start for m in topic)
    said = set(w[j:i]) | set(w[d[1] : k])
    if start > 0 and w[start - 1] in _TOPIC_LABELS and sent.claimed[start - 1] is None:
        start -= 1  # "HARD railway >= 25 m", "soft water > 10 m": the line's label
        said.add(w[start])
    kind = "near" if said & {"max", "maximum", "within", "<"} else "far"
    hard = bool(said & _TOPIC_HARD) and not said & _TOPIC_SOFT
    sent.claim(Found("cue", start, k, kind, tuple(topic), d[0], hard=hard), "cue")
    return True


#: The way a keeping verb keeps away, after a topic's mark ("water: keep well away").
_AWAY_WORDS = frozenset({"away", "clear", "back"})


def topic_away(sent: Sentence, i: int) -> bool:
    """ "water: keep well away", "railway -> stay clear", "bldgs: keep way back": keeping away
    from the topic named before the mark, with no distance and nothing after it: the graded far
    cue "keep well away from the water" is."""
    w = sent.words
    if w[i] not in lx.OFF_VERBS or i < 2 or w[i - 1] not in (":", "=") or sent.claimed[i] is not None:
        return False
    k = i + 1
    if k < sent.n and w[k] in ("well", "way", "far", "right"):
        k += 1
    if k >= sent.n or w[k] not in _AWAY_WORDS or (k + 1 < sent.n and w[k + 1] not in lx.SEPARATORS):
        return False
    topic = topic_before(sent, i)
    if not topic or not sent.free(i, k + 1):
        return False
    for mm in topic:
        mm.role = "cue"
    sent.claim(Found("cue", min(m.start for m in topic), k + 1, "far", tuple(topic), None), "cue")
    return True
