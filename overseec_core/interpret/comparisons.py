"""Comparisons: "X is better/worse than Y", "prefer X over Y", "X rather than Y", chains.

Claimed over a :class:`~overseec_core.interpret.sentence.Sentence` after conditions and cues: a
comparator phrase between two entity lists, an adjective with a valence and a degree ("safer
than", "less risky than"; ``lexicon.VALENCE``), "prefer X over/to Y", "X over Y" between two
entities (chains: "A over B over C", where B is the right side of one comparison and the left of
the next) and the split "rather/sooner X than Y". Each becomes a constraint between weights, which
:func:`overseec_core.interpret.statements.resolve_weights` applies.
"""

from __future__ import annotations

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.sentence import Found, Mention, Sentence


def _comparative_base(word: str) -> str | None:
    """The adjective of a comparative with a valence ("safer" -> "safe", "riskier" -> "risky",
    "wetter" -> "wet", "worse" -> "bad"), else None."""
    if word in lx.COMPARATIVE_FORMS:
        return lx.COMPARATIVE_FORMS[word]
    cands = []
    if word.endswith("ier"):
        cands.append(word[:-3] + "y")
    if word.endswith("er"):
        cands += [word[:-2], word[:-1], word[:-3]]  # faster, safer, wetter
    return next((c for c in cands if c in lx.VALENCE), None)


def claim_comparisons(sent: Sentence) -> None:
    """Claim every comparison of the sentence, left to right."""
    for i in range(sent.n):
        _comparator_at(sent, i)


def _comparator_at(sent: Sentence, i: int) -> None:
    """Comparisons: a comparator phrase ("better than", "worse than", "rather than") between
    two entity lists; "prefer X over/to Y"; "X over Y" between two entities (chains: "A over
    B over C"); and the split "rather/sooner X than Y"."""
    start = i
    hit = sent.match(lx.COMPARATORS, i) or _adjective_comparison(sent, i)
    if hit:
        words, kind = hit
        if kind == "equal" and (multiplied := _multiplied(sent, i, words)) is not None:
            start, kind = multiplied  # "twice as good as": no equality, a comparison
    elif (
        sent.words[i] in lx.SOFT_COMPARATORS
        and sent.claimed[i] is None
        and not _infinitive(sent, i)
        and (
            any(w in lx.PREFER_VERBS for w in sent.words[:i])  # "prefer A to B, and B to C"
            or (sent.words[i] in lx.BETWEEN_COMPARATORS and _between_entities(sent, i))
        )
    ):
        words, kind = (sent.words[i],), lx.SOFT_COMPARATORS[sent.words[i]]
        kind = _by_cost(sent, i, kind)
    elif sent.words[i] == "than" and sent.claimed[i] is None and (opener := _rather_before(sent, i)) is not None:
        words, kind, start = ("than",), "better", opener
    else:
        _bare_comparative(sent, i)
        return
    # "than go through the forest", "rather than by trail": the verb and preposition of the
    # first side, repeated
    j = sent.skip(i + len(words), lx.PASSAGE_VERBS, limit=3)
    right, end = sent.list_forward(j)
    left = sent.list_backward(start if words != ("than",) else i)
    # "grass is better than trees, and the trail is better than grass": the list before a
    # comparison does not reach back into the one before it (a chain's middle, alone, does)
    left = [m for m in left if m.role != "right"] or left
    if not left and start == i:
        # "A is worse than B but better than C", "grass is fine but worse than trails": the
        # subject again (of the last comparison, else of the last linking verb)
        earlier = [f for f in sent.found if f.kind == "comparator" and f.end <= i]
        subjects = [m for m in sent.mentions if m.end <= i and sent.is_subject(m)]
        left = list(earlier[-1].left) if earlier else subjects[-1:]
    if not right or not left:
        return
    for m in right:
        m.role = "right"
    sent.claim(Found("comparator", start, end, kind, tuple(right), left=tuple(left)), "comparator")


#: The valence of the equality phrases a multiple turns into a comparison ("twice as good as").
_EQUAL_VALENCE: dict[tuple[str, ...], int] = {("as", "good", "as"): 1, ("as", "fine", "as"): 1, ("as", "bad", "as"): -1}


def _multiplied(sent: Sentence, i: int, words: tuple[str, ...]) -> tuple[int, str] | None:
    """ "roads are twice as good as trails", "three times as bad as", "2x as good as", "half as
    good as": a multiple before an equality phrase with a valence makes it a comparison, as
    (the multiple's first index, better|worse); None when there is no multiple."""
    sign = _EQUAL_VALENCE.get(words)
    if sign is None or i == 0 or not sent.free(i - 1, i):
        return None
    w = sent.words
    factor, first = lx.MULTIPLE_WORDS.get(w[i - 1]), i - 1
    if factor is None and w[i - 1] in ("times", "x") and i >= 2 and sent.free(i - 2, i - 1):
        number = sent.number(i - 2)
        factor, first = (number[0], i - 2) if number is not None and number[1] == i - 1 else (None, i)
    if factor is None or factor == 1.0:
        return None
    return first, "better" if (factor > 1.0) == (sign > 0) else "worse"


#: Comparatives that, said with no "than", compare with what the sentence named before.
_BARE_COMPARATIVES = {"better": "better", "nicer": "better", "preferable": "better", "worse": "worse"}


def _bare_comparative(sent: Sentence, i: int) -> None:
    """ "Dirt roads are allowed; the paved ones are better": a comparative predicate with no
    "than", ending its clause, compares its subject with the entity named before it (in an
    earlier clause, else the sentence before); nothing when there is none."""
    w = sent.words
    kind = _BARE_COMPARATIVES.get(w[i])
    if kind is None or not sent.free(i, i + 1) or i == 0 or w[i - 1] not in lx.COPULAS:
        return
    if i + 1 < sent.n and w[i + 1] not in lx.SEPARATORS | {"."}:
        return
    subject = next(  # "the paved ones are better": the qualifier's "ones" between
        (
            m
            for m in sent.mentions
            if m.role == "target" and m.end <= i - 1 and set(w[m.end : i - 1]) <= {"ones", "one"}
        ),
        None,
    )
    if subject is None:
        return
    before = [m for m in sent.mentions if m.end <= subject.start and m.role == "target" and m.name != subject.name]
    if before and any(w[k] in lx.SEPARATORS for k in range(before[-1].end, subject.start)):
        other = before[-1]
    elif not before and sent.antecedent is not None and sent.antecedent != subject.name:
        other = Mention(i, i + 1, sent.antecedent, True, role="right")  # named in the sentence before
    else:
        return
    sent.claim(Found("comparator", i, i + 1, kind, (other,), left=(subject,)), "comparator")


#: Order symbols, which a cost label reads the other way round ("cost: grass < road").
_SYMBOLS = frozenset({">", ">>", ">>>", "<", "<<"})


def _by_cost(sent: Sentence, i: int, kind: str) -> str:
    """An order symbol's sense, and its label read with it: labelled a cost ("cost: grass <
    road < building", "penalty: water > mud") less cost is better, so the symbol reads the other
    way round; labelled a preference ("pref: road > trail") or unlabelled, "A > B" prefers A."""
    if sent.words[i] not in _SYMBOLS:
        return kind
    # a label opens the chain ("pref: road > trail"); a verdict after a name is that name's own
    # ("asphalt preferred > dirt roads avoided")
    first = min((m.start for m in sent.mentions if m.start < i), default=i)
    label = next((k for k in range(first) if sent.words[k] in lx.COST_WORDS | lx.PREFER_VERBS), None)
    if label is None:
        return kind
    if sent.free(label, label + 1):
        sent.claim(Found("filler", label, label + 1, "order label"), "cue")
    if sent.words[label] in lx.PREFER_VERBS:
        return kind
    return "worse" if kind == "better" else "better"


#: Verbs whose infinitive after "to" is no comparison ("prefer the grass and try not to use the water").
_INFINITIVES = frozenset(
    "use go drive walk take cross stay keep avoid be get move travel ride pass enter run head wade follow".split()
)


def _infinitive(sent: Sentence, i: int) -> bool:
    """Whether "to" at ``i`` opens an infinitive ("to use the water"), not "prefer A to B"."""
    return sent.words[i] == "to" and i + 1 < sent.n and sent.words[i + 1] in _INFINITIVES


def _adjective_comparison(sent: Sentence, i: int) -> tuple[tuple[str, ...], str] | None:
    """ "less risky than", "more pleasant than", "safer than", "muddier than": the comparison
    an adjective's valence (lexicon.VALENCE) and its degree make, as (words, better|worse)."""
    w = sent.words
    if not sent.free(i, min(sent.n, i + 3)):
        return None
    if w[i] in ("more", "less") and i + 2 < sent.n and w[i + 2] == "than" and w[i + 1] in lx.VALENCE:
        sign = lx.VALENCE[w[i + 1]] * (1 if w[i] == "more" else -1)
        return (w[i], w[i + 1], "than"), "better" if sign > 0 else "worse"
    if i + 1 < sent.n and w[i + 1] == "than":
        base = _comparative_base(w[i])
        if base is not None:
            return (w[i], "than"), "better" if lx.VALENCE[base] > 0 else "worse"
    return None


def _between_entities(sent: Sentence, i: int) -> bool:
    """Whether word i stands right between two entity mentions (articles aside)."""
    before = i - 1
    while before >= 0 and sent.words[before] in lx.ARTICLES:
        before -= 1
    after = sent.skip(i + 1, lx.ARTICLES)
    return any(m.end - 1 == before for m in sent.mentions) and after in sent.mention_at


def _rather_before(sent: Sentence, i: int) -> int | None:
    """Index of an unclaimed "rather"/"sooner" before "than" at i, with an entity between."""
    for k in range(i - 1, max(-1, i - 10), -1):
        if sent.words[k] in lx.RATHER_WORDS and sent.claimed[k] is None:
            return k if any(k < m.start < i for m in sent.mentions) else None
    return None
