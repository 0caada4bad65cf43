"""The phrase tables claimed over a :class:`~overseec_core.interpret.sentence.Sentence` once its
mentions, conditions, cues and comparisons are: modifiers, triggers and markers (inserted adverbs
and modifiers do not break a phrase), then the readings that change a trigger by its neighbours --
a negated need or avoid permits ("no need to avoid X"), the adjective after "too" says why ("way
too dense"), "only" next to a name prefers it, a shortcut is permitted, "X please" asks for X.
"""

from __future__ import annotations

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.sentence import Found, Sentence


def claim_phrases(sent: Sentence) -> None:
    """Claim the modifiers, triggers and markers of the phrase tables, in that order (inserted
    adverbs do not break a phrase: "you can just wade through")."""
    for kind, table in (("modifier", lx.MODIFIERS), ("trigger", lx.TRIGGERS), ("marker", lx.MARKERS)):
        i = 0
        while i < sent.n:
            hit = sent.match_loose(table, i)
            if hit:
                sent.claim(Found(kind, i, hit[1], hit[0]), kind)
                i = hit[1]
            else:
                i += 1
    for f in sent.found:
        if f.kind == "trigger":
            _lift_negated(sent, f)
    _unfit_adjective(sent)
    _attributive_states(sent)
    _only_trigger(sent)
    _shortcut_permission(sent)
    _route_taken(sent)
    _request(sent)


#: Verbs whose object pronoun may stand for the route itself ("if a route can ..., take it").
_TAKING = frozenset({"take", "use", "choose", "pick"})


def _route_taken(sent: Sentence) -> None:
    """ "If a route can stay 10 m from the buildings, take it": where the sentence's condition is
    about the route itself (a "slack" phrase naming a route noun), "take it" takes that route,
    not the entity named last; the words are read, and nothing is preferred by them."""
    w = sent.words
    routed = any(
        f.kind == "filler" and f.value == "slack" and any(w[k] in lx.ROUTE_NOUNS for k in range(f.start, f.end))
        for f in sent.found
    )
    if not routed:
        return
    for verb in [f for f in sent.found if f.kind == "trigger" and w[f.start] in _TAKING and f.end < sent.n]:
        if w[verb.end] not in lx.OBJECT_PRONOUNS:
            continue
        for m in [m for m in sent.mentions if m.start == verb.end]:
            sent.drop_mention(m)
        verb.kind = "filler"
        for k in range(verb.start, verb.end + 1):
            sent.claimed[k] = "filler"


def _request(sent: Sentence) -> None:
    """ "pvd rd pls", "the trail please": "please" right after a name, ending its clause, asks
    for it (a preference); "please avoid the water" stays politeness."""
    for j in range(1, sent.n):
        ends = j + 1 == sent.n or sent.words[j + 1] in lx.SEPARATORS
        if sent.words[j] != "please" or not ends or sent.claimed[j] is not None or sent.claimed[j - 1] != "mention":
            continue
        k = j - 1
        while k >= 0 and sent.words[k] not in lx.SEPARATORS:
            k -= 1
        if "trigger" not in sent.claimed[k + 1 : j]:  # "avoid the water please": politeness
            sent.claim(Found("trigger", j, j + 1, "prefer"), "trigger")


def _attributive_states(sent: Sentence) -> None:
    """ "Derelict buildings: off limits", "avoid the abandoned sheds": a state word right before
    a name, with another rule in its clause, only says which ones -- it is part of the name (a
    qualified entity, "derelict building"), not a permission ("the railway is disused" stays one)."""
    for f in [f for f in sent.found if f.kind == "trigger" and f.end - f.start == 1]:
        m = sent.mention_at.get(f.end)
        if sent.words[f.start] not in lx.SAFE_STATES or m is None or not m.known:
            continue
        a, b = f.start, m.end
        while a > 0 and sent.words[a - 1] not in lx.SEPARATORS - {":"}:
            a -= 1
        while b < sent.n and sent.words[b] not in lx.SEPARATORS - {":"}:
            b += 1
        if not any(g is not f and g.kind == "trigger" and a <= g.start < b for g in sent.found):
            continue
        sent.found.remove(f)
        sent.claimed[f.start] = "mention"
        sent.mention_at.pop(m.start, None)
        m.name = f"{sent.words[f.start]} {m.name}"
        m.start = f.start
        sent.mention_at[m.start] = m


def _unfit_adjective(sent: Sentence) -> None:
    """ "are way too dense", "gets too hot": the adjective after an avoiding "too" says why,
    it names nothing (an open-vocabulary mention of it is dropped and the word read)."""
    for f in list(sent.found):
        j = f.end
        if f.kind != "trigger" or sent.words[j - 1] != "too" or j >= sent.n:
            continue
        m = sent.mention_at.get(j)
        if sent.words[j] in lx.UNFIT_ADJECTIVES and (m is None or (not m.known and m.end == j + 1)):
            if m is not None:
                sent.drop_mention(m)
            sent.claim(Found("filler", j, j + 1, "unfit"), "trigger")


def _only_trigger(sent: Sentence) -> None:
    """ "roads only", "paved road only where you can", "only the trail": the one entity to
    keep to is preferred. "only" right after a name or right before one (past an article);
    elsewhere ("penalty only", "only if") it is a plain word."""
    w = sent.words
    for j in range(sent.n):
        if w[j] != "only" or sent.claimed[j] is not None:
            continue
        k = j + 1 + (j + 1 < sent.n and w[j + 1] in lx.ARTICLES)
        after = k < sent.n and any(m.start == k and m.role == "target" for m in sent.mentions)
        before = any(m.end == j and m.role == "target" for m in sent.mentions)
        if before or after:
            sent.claim(Found("trigger", j, j + 1, "prefer"), "trigger")


def _shortcut_permission(sent: Sentence) -> None:
    """ "walk through them if it's shorter", "cut across the grass if needed": a way to go
    that is allowed where it helps, not preferred: the preferring trigger before the
    condition permits (tier fine); the condition's words are read with it."""
    for j in range(sent.n):
        p = next((p for p in lx.SHORTCUT_CONDITIONS if tuple(sent.words[j : j + len(p)]) == p), None)
        if p is None or any(sent.claimed[x] not in (None, "mention") for x in range(j, j + len(p))):
            continue
        before = [f for f in sent.found if f.kind == "trigger" and f.end <= j and f.value == "prefer"]
        if not before or any(w in (";", ".", "but") for w in sent.words[before[-1].end : j]):
            continue
        for m in [m for m in sent.mentions if j <= m.start < j + len(p) and not m.known]:
            sent.drop_mention(m)  # "shorter" is no name
        before[-1].value = "fine"
        sent.claim(Found("filler", j, j + len(p), "shortcut"), "trigger")


def _lift_negated(sent: Sentence, f: Found) -> None:
    """ "no need to avoid X", "you don't have to keep off X", "don't avoid X": the trigger's
    entities are permitted (tier fine); the negation's words are claimed with it."""
    for phrases, tiers in ((lx.NEED_NEGATORS, None), (lx.AVOID_NEGATORS, ("avoid", "avoid+", "tolerable", "last"))):
        if tiers is not None and f.value not in tiers:
            continue
        j = f.start  # the negation may stand a few filler words before ("no need for you to avoid")
        while True:
            for p in phrases:
                k = j - len(p)
                if k >= 0 and tuple(sent.words[k:j]) == p and _negation_free(sent, k, j):
                    # the negation's own words may have been read as a trigger ("no", "don't")
                    sent.found = [g for g in sent.found if not (g.kind == "trigger" and k <= g.start < j)]
                    for x in range(k, f.start):
                        sent.claimed[x] = None
                    sent.claim(Found("filler", k, f.start, "lifted"), "trigger")
                    f.value = "fine"
                    return
            if j <= max(0, f.start - 3) or sent.words[j - 1] not in lx.FILLER or sent.claimed[j - 1] is not None:
                break
            j -= 1


def _negation_free(sent: Sentence, k: int, j: int) -> bool:
    """Whether words k..j-1 are unclaimed or wholly the span of triggers inside them."""
    inside = [g for g in sent.found if g.kind == "trigger" and k <= g.start < j]
    if any(g.end > j for g in inside):
        return False
    taken = {x for g in inside for x in range(g.start, g.end)}
    return all(sent.claimed[x] is None or x in taken for x in range(k, j))
