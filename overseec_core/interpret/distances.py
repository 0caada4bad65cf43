"""A distance to or from something, as the words before an entity list state it: "at least 20 m
from", "no closer than 15 m to", "within 50 m of", "a 30 m exclusion buffer around", "a safe
distance from" (:func:`distance_phrase`), and the negations that turn one round: "nothing within
12 m of" keeps out of the band (:func:`denied_bound`), "don't go far from" is nearness
(:func:`negated_kind`), "nobody gets closer than" is the bound's own negation
(:func:`bound_negation`). Read by :mod:`.conditions`' cues.
"""

from __future__ import annotations

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.sentence import Mention, Sentence

#: Who or what a bound before "within" denies ("nothing within 12 m of", "nobody within ...").
_NOTHING = frozenset({"nothing", "nobody", "noone", "none"})


def denied_bound(sent: Sentence, start: int) -> tuple[str, int]:
    """A hard "within" bound at ``start`` turned round by who it denies: "nothing within 12 m of
    the railway", "no vehicle movement is permitted within 25 m of the water" keep out of that
    band (far, from the denial); ("near", ``start``) otherwise."""
    if start > 0 and sent.words[start - 1] in _NOTHING and sent.claimed[start - 1] is None:
        return "far", start - 1
    denied = _denied_within(sent, start)
    return ("near", start) if denied is None else ("far", denied)


#: Words between a denied subject and its "within" ("no plant is permitted within 30 m of").
_DENIED_VERBS = frozenset({"is", "are", "be", "permitted", "allowed", "shall", "may", "will", "to", "go", "come"})


#: Words that deny who may be within ("no plant", "nothing of ours", "nobody").
_DENIALS = frozenset({"no", "nothing", "nobody", "none"})


def _denied_within(sent: Sentence, i: int) -> int | None:
    """Where "no <who or what> [is permitted] within N m of X" starts, for a "within" at ``i``:
    a "no" (or "nothing", "nobody") before at most five words naming who may not be there ("no
    plant or personnel", "no vehicle movement", "nothing of ours"), none of them a known entity;
    those names are no entities (they are the route's own). None when the bound is not denied."""
    w, j = sent.words, i - 1
    while j >= 0 and w[j] in _DENIED_VERBS and sent.claimed[j] is None and i - j <= 3:
        j -= 1
    named: list[Mention] = []
    for k in range(j, max(-1, j - 6), -1):
        m = next((x for x in sent.mentions if x.start <= k < x.end), None)
        if w[k] in _DENIALS and sent.claimed[k] is None and k < i - 1:
            for x in named:
                sent.drop_mention(x)
            return k
        if m is not None and not m.known:
            if m not in named:
                named.append(m)
        elif sent.claimed[k] is not None or w[k] in lx.SEPARATORS - {",", "and", "or"}:
            return None
    return None


#: What a priced band is said of ("a penalty for tiles within 3 m of", "a bonus for cells within").
_PRICED_PLACES = frozenset({"for", "on", "tiles", "tile", "cells", "cell", "pixels", "ground", "points", "anything"})
#: Words between a pricing verb and its "within" ("is penalised within", "were softly penalised").
_PRICED_BETWEEN = frozenset({"is", "are", "was", "were", "be", "been", "being", "heavily", "lightly", "slightly"})


def priced_within(sent: Sentence, start: int) -> tuple[str, int] | None:
    """A "within N m of X" band priced by the verb before it: "softly penalised within 8 m of tree
    crowns" keeps away from X (far, a soft zone), "rewarded within 10 m of the trail" draws to it
    (near, soft); the kind and where the cue starts (its adverb included), or None."""
    k = start - 1
    while k >= 0 and sent.words[k] in _PRICED_BETWEEN | _PRICED_PLACES and sent.claimed[k] is None:
        k -= 1
    if k < 0 or sent.claimed[k] is not None:
        return None
    w = sent.words[k]
    priced = w in lx.PRICED_WITHIN or w in lx.COST_WORDS  # "a soft penalty for tiles within"
    if not priced and w not in lx.REWARDED_WITHIN and w not in lx.BENEFIT_WORDS:
        return None
    kind = "far" if priced else "near"
    while k > 0 and sent.words[k - 1] in lx.SOFTENERS | {"softly", "gently", "mildly", "a", "an"}:
        if sent.claimed[k - 1] is not None:
            break
        k -= 1  # "softly penalised", "a soft penalty"
    return kind, k


def negated_kind(sent: Sentence, i: int, kind: str) -> tuple[str, int]:
    """A near/far cue at ``i`` with no distance turned round by a negation before it, and where
    the cue then starts: "don't go far from the buildings" is near them, "no walking right up
    next to it" far from it; (``kind``, ``i``) when nothing negates it."""
    if kind == "far" and (neg := _negated_far(sent, i)) is not None:
        return "near", neg
    if kind == "near" and (neg := _negated_near(sent, i)) is not None:
        return "far", neg
    return kind, i


def bound_negation(sent: Sentence, i: int) -> int:
    """Where a hard far cue at ``i`` starts when a negation of its bound stands before it, with
    only a movement verb between ("nobody gets closer than 10 yards to", "don't get any closer
    than 5 m to"): the negation is the rule's own, not an avoid trigger left over."""
    k = i - 1
    while k >= 0 and sent.words[k] in lx.BOUND_VERBS and sent.claimed[k] is None and i - k <= 2:
        k -= 1
    if k >= 0 and k < i - 1 and sent.words[k] in lx.BOUND_NEGATORS and sent.claimed[k] is None:
        return k
    return i


def _negated_near(sent: Sentence, i: int) -> int | None:
    """Where a negated nearness before ``i`` starts ("no walking right up next to it", "nobody
    goes up close to"): the negation with at most three unclaimed words between; None when the
    nearness is not negated ("don't go near X" is an avoid trigger, read before this)."""
    for k in range(i - 1, max(-1, i - 5), -1):
        w = sent.words[k]
        if sent.claimed[k] is not None or w in lx.NEAR_FAR_STOPS:
            return None
        if w in ("no", "nobody", "never"):
            return k
    return None


def _negated_far(sent: Sentence, i: int) -> int | None:
    """Where the negation of a "far from" at ``i`` starts ("don't go far from", "never stray
    far from", "not too far from"): staying near, graded; None when it is not negated."""
    for k in range(i - 1, max(-1, i - 4), -1):
        w = sent.words[k]
        if sent.claimed[k] not in (None,) or w in lx.NEAR_FAR_STOPS:
            return None
        if w in lx.FAR_NEGATORS:
            return k
    return None


def _zone_words(sent: Sentence, j: int, hard: bool) -> tuple[int, bool]:
    """Past the words naming the zone after a distance ("20 m buffer", "30 m exclusion buffer",
    "15 m buffer zone", "10 m safety margin"): the index after them and whether the rule is hard
    (an exclusion keeps the route out unless the distance was an estimate)."""
    words, n = sent.words, sent.n
    k = j
    mods: list[str] = []
    while k < n and len(mods) < 2:
        if tuple(words[k : k + 2]) in lx.EXCLUDING_PAIRS:  # "keep-out", "no-go": an exclusion
            mods.append("exclusion")
            k += 2
        elif words[k] in lx.ZONE_MODIFIERS:
            mods.append(words[k])
            k += 1
        else:
            break
    if k < n and words[k] in lx.GAP_NOUNS:
        k += 1
    elif mods and mods[-1] in lx.GAP_NOUNS:  # "a 30 m buffer around" (the gap noun was a modifier)
        pass
    elif k < n and mods and words[k] in lx.ZONE_NOUNS:  # "a 30 m exclusion zone around"
        pass
    else:
        return j, hard
    if k < n and words[k] in lx.ZONE_NOUNS:
        k += 1
    exclusion = any(lx.ZONE_MODIFIERS[m] for m in mods) and not sent.approximate(j)
    return k, hard or exclusion


#: Words that stress a distance after its article ("a full 10 m", "a good 20 m").
_FULL_WORDS = frozenset({"full", "good", "clear", "solid", "whole"})


def band_phrase(sent: Sentence, i: int) -> tuple[float, float, int] | None:
    """ "between 5 and 10 m from the road", "5-10 m from it": a band of distances from
    something, up to its "from/of": (inner metres, outer metres, index after), else None. The
    inner number takes the outer's unit when it has none of its own."""
    words, n = sent.words, sent.n
    k = i + (i < n and words[i] == "between")
    if k >= n or not sent.free(i, k + 1):
        return None
    first = sent.distance(k)
    if first is not None:
        inner, j = first[0], first[1]
    elif words[k].replace(".", "", 1).isdigit():
        inner, j = None, k + 1
    else:
        return None
    if j >= n or words[j] not in (("and",) if k > i else ("to",)):
        return None
    outer = sent.distance(j + 1)
    if outer is None:
        return None
    if inner is None:
        inner = (
            float(words[k]) * (outer[0] / float(words[j + 1])) if words[j + 1].replace(".", "", 1).isdigit() else None
        )
    e = outer[1] + (outer[1] < n and words[outer[1]] == "away")
    if inner is None or not 0 < inner < outer[0] or e >= n or words[e] not in ("from", "of") or not sent.free(i, e + 1):
        return None
    return inner, outer[0], e + 1


def between_selves(sent: Sentence, k: int) -> int | None:
    """Past "between <the route> and" at ``k`` ("between you and", "between the robot and",
    "between yourself and"): the gap's other side is what follows, as after "from"; the index
    after "and", or None when the words are not there (or already read)."""
    if k >= sent.n or sent.words[k] != "between" or sent.claimed[k] is not None:
        return None
    j = k + 1
    while j < sent.n and sent.words[j] in lx.ROUTE_SELVES and sent.claimed[j] is None:
        j += 1
    if j == k + 1 or j >= sent.n or sent.words[j] != "and" or sent.claimed[j] is not None:
        return None
    return j + 1


def distance_phrase(sent: Sentence, i: int) -> tuple[str, float | None, bool, int] | None:  # noqa: C901
    """A distance to or from something, up to its "from/of/to": (kind, metres, hard, index).

    "at least 20 m from", "no closer than 15 m to", "a minimum distance of 20 m from" (far,
    hard); "within 50 m of", "no more than 50 m from" (near, hard); "20 m away from", "a
    20 m buffer around", "a safe distance from" (far, soft).
    """
    words, n, k = sent.words, sent.n, i
    hard = noun = False
    if k < n and words[k] in ("a", "an"):
        k += 1
        if k < n and words[k] in _FULL_WORDS and sent.distance(k + 1):
            k += 1  # "keep a full 10 m from it", "a good 20 m from the road"
    if k < n and words[k] in lx.MIN_WORDS:
        hard = words[k] != "safe"
        k += 1
    if k < n and words[k] in lx.GAP_NOUNS:
        noun = True
        # "an exclusion radius of 3 m around", "a keep-out buffer of 10 m from": a hard zone
        hard = hard or (k > 0 and lx.ZONE_MODIFIERS.get(words[k - 1], False))
        hard = hard or (k > 1 and tuple(words[k - 2 : k]) in lx.EXCLUDING_PAIRS)
        k += 1
        if k < n and words[k] == "of":
            k += 1
    elif k > i:
        return None
    kind = "far"
    for size in (3, 2, 1):
        bound = tuple(words[k : k + size])
        if len(bound) == size and (bound in lx.FAR_BOUNDS or bound in lx.NEAR_BOUNDS) and sent.free(k, k + size):
            kind, hard = ("far" if bound in lx.FAR_BOUNDS else "near"), True
            k += size
            break
    if sent.approximate(k):
        hard = False  # "within about 50 m of the railway": a preference with a reach, not a rule
    d = sent.distance(k)
    if d is None:
        p = k
        while p < n and words[p] in lx.ZONE_PASSIVE and p - k < 5 and sent.claimed[p] is None:
            if words[p] == "to" and p + 1 < n and words[p + 1] not in lx.ZONE_PASSIVE:
                break  # "a minimum distance to the trees of 3 m": "to" is the distance's own
            p += 1  # "a mandatory exclusion buffer applies around the railway"
        if noun and p < n and words[p] in ("from", "to", "around") and kind == "far":
            return "far", None, hard, p + 1  # "keep a safe distance from the water"
        return None
    j = d[1]
    if tuple(words[j : j + 2]) in lx.APPROX_AFTER or (j < n and words[j] in lx.APPROX_AFTER_WORDS):
        hard = False  # "20 m or so from the river": an estimate
        j += 1 if words[j] in lx.APPROX_AFTER_WORDS else 2
    if j < n and words[j] in ("minimum", "min") and sent.free(j, j + 1):
        kind, hard, j = "far", True, j + 1  # "50 ft minimum from open water"
    for size in (2, 1):  # "25 m or more from the railway" (at least), "50 m or less from" (within)
        after = tuple(words[j : j + size])
        if len(after) == size and (after in lx.FAR_AFTER or after in lx.NEAR_AFTER) and sent.free(j, j + size):
            kind = "far" if after in lx.FAR_AFTER else "near"
            j += size
            break
    j, hard = _zone_words(sent, j, hard)
    if noun or j > d[1]:  # "a 25 m exclusion zone is to be enforced around the railway"
        k = j
        while k < n and words[k] in lx.ZONE_PASSIVE and k - j < 5:
            k += 1
        if k > j and k < n and words[k] in ("from", "around", "round") and sent.free(j, k):
            j = k
    if j < n and words[j] in ("away", "clear", "back", "off"):
        j += 1  # "20 m away from", "30 m clear of", "5 m back from", "5 m off the rail"
        if j < n and words[j] not in ("from", "of", "to", "around") and words[j - 1] == "off":
            return kind, d[0], hard, j
    if j < n and words[j] in ("from", "of", "to", "around", "round"):
        return kind, d[0], hard, j + 1
    if (past := between_selves(sent, j)) is not None:  # "no less than 50 ft between the route and the water"
        return kind, d[0], hard, past
    return None
