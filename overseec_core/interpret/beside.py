"""On versus beside: "along the river bank but not in the river", "follow the fence line, never
on it", "skirt the forest edge without entering".

Such a sentence names an object X twice over: the band beside X is where to go, X itself is
where not to. Read per sentence, before its clauses: a *beside* word before X ("along",
"alongside", "beside", "next to", "parallel to", "skirt", "follow") or an *edge* noun of X ("the
river bank", "the edge of the forest", "the verge of the road"), together with a negated
"on / in / into / entering" ("but not in the river", "never on it", "without entering",
"keeping off the carriageway"). Then X is avoided (forbidden when the negation is a "never" or
"must not") and a soft ``near`` cue on X prefers the ground beside it, the nearer the better
(``costlang.synth``: the cue lowers only ground that is not avoided, so X itself keeps its
level). The words are claimed, so nothing of the construct is reported as not understood.
"""

from __future__ import annotations

from dataclasses import dataclass

from overseec_core.interpret.sentence import Found, Mention, Sentence

#: Ground beside the object that the route should keep to, when the sentence states no width.
BESIDE_BAND_M = 5.0

BESIDE_WORDS = frozenset(
    "along alongside beside parallel skirt skirts skirting follow follows following trace traces tracing "
    "track tracks tracking flank flanking".split()
)
BESIDE_PAIRS = frozenset({("next", "to"), ("parallel", "to"), ("parallel", "with"), ("close", "to")})
EDGE_NOUNS = frozenset(
    "bank banks edge edges verge verges shore shores shoreline shorelines margin margins perimeter fringe "
    "fringes embankment embankments line lines boundary rim brink towpath".split()
)
#: Negations of being on / in X ("not in", "never on", "without entering", "off the ...").
NEGATIONS = frozenset("not never without don't no off avoid avoiding".split())
FORBIDDING = frozenset({"never"})
ON_WORDS = frozenset(
    "on in into onto inside entering enter enters touching touch itself crossing cross over upon within".split()
)
_GAP = 3  # words allowed between a beside word and the object ("along the old river")


@dataclass(frozen=True)
class Beside:
    """One on-versus-beside reading: the object, its tier (avoid or lethal) and the band width."""

    name: str
    tier: str
    metres: float = BESIDE_BAND_M


def _beside_word_before(sent: Sentence, m: Mention) -> list[int]:
    """Indices of the beside word (and its partner) governing ``m``, or []."""
    for k in range(max(0, m.start - _GAP - 1), m.start):
        w = sent.words[k]
        if w in BESIDE_WORDS:
            return [k]
        if k + 1 < sent.n and (w, sent.words[k + 1]) in BESIDE_PAIRS:
            return [k, k + 1]
    return []


def _edge_of(sent: Sentence, m: Mention) -> list[int]:
    """Indices of an edge noun of ``m``: "the river bank", "the edge of the forest"."""
    if m.end < sent.n and sent.words[m.end] in EDGE_NOUNS:
        return [m.end]
    for k in range(max(0, m.start - 4), m.start - 1):
        if sent.words[k] in EDGE_NOUNS and sent.words[k + 1] == "of":
            return [k, k + 1]
    return []


def _negated_on(sent: Sentence, after: int) -> tuple[list[int], bool] | None:
    """The negated "on/in X" after word ``after``: its indices and whether it forbids."""
    for k in range(after, sent.n):
        if sent.words[k] not in NEGATIONS:
            continue
        for j in range(k + 1, min(sent.n, k + 4)):
            if sent.words[j] in ON_WORDS:
                forbids = sent.words[k] in FORBIDDING or (k > 0 and sent.words[k - 1 : k + 1] == ["must", "not"])
                return list(range(k, j + 1)), forbids
        if sent.words[k] == "off":  # "keeping off the carriageway"
            return [k], False
    return None


def claim_beside(sent: Sentence) -> list[Beside]:
    """The sentence's on-versus-beside readings; their words are claimed as a cue."""
    out: list[Beside] = []
    for m in sent.mentions:
        lead = _beside_word_before(sent, m) + _edge_of(sent, m)
        if not lead:
            continue
        neg = _negated_on(sent, m.end)
        if neg is None:
            continue
        words, forbids = neg
        for span in (lead, words):
            free = [k for k in span if sent.claimed[k] is None]
            if free:
                sent.claim(Found("cue", free[0], free[-1] + 1, "beside", (m,)), "cue")
        if all(b.name != m.name for b in out):
            out.append(Beside(m.name, "lethal" if forbids else "avoid"))
    return out
