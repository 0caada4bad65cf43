"""Costs a prompt states as numbers: "tree: 0.9", "road = 0.2" (levels on the 0-1 scale, read
as that cost) and relative costs above 1 ("asphalt | 1", "gravel | 2", "mud | 5": ranked,
cheapest first). Claimed over a sentence by :func:`claim_levels`, given to a clause's entities
by :func:`stated_levels`, and turned into an ordering by :func:`relative_levels` once the whole
prompt is read (a relative cost means something only beside the others).
"""

from __future__ import annotations

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.clauses import Clause
from overseec_core.interpret.sentence import Found, Sentence

#: Words between an entity and the cost a configuration gives it ("tree: 0.9", "road cost 0.2").
_LEVEL_MARKS = frozenset({":", "=", "cost", "costs", "weight", "level", "is", "are", "at"})


def claim_levels(sent: Sentence) -> None:
    """ "tree: 0.9", "road = 0.2", "grass cost 0.5": a cost on the 0-1 scale given to the
    known entity before it, as a robot's configuration states it (``level`` found; read as that
    cost, 0.5 neutral). A number with a unit is a distance, not a cost; a name the lexicon does
    not know takes a cost only as a key ("helipad: 0.9"), so "costmap resolution 0.05" stays a
    setting."""
    w = sent.words
    for m in list(sent.mentions):
        if m.role != "target":
            continue
        k = m.end
        keyed = k < sent.n and w[k] in (":", "=")
        multiple = k + 1 < sent.n and w[k + 1] in _TIMES  # "mud 4 times more expensive than the trail"
        if not m.known and not keyed and not multiple:
            continue  # "costmap resolution 0.05" is a setting, no layer's cost
        while k < sent.n and w[k] in _LEVEL_MARKS and sent.claimed[k] is None and k - m.end < 2:
            k += 1
        if k >= sent.n:
            continue
        marked = k > m.end  # "mud: 5", "gravel cost 2": a relative cost needs its mark
        times = k + 1 < sent.n and w[k + 1] in _TIMES  # "grass costs 2x road", "trees 5x"
        relative = (marked or times) and _is_relative(w[k])
        if not sent.free(k, k + 1) or not (_is_level(w[k]) or relative):
            continue
        if times and relative:
            base = _past_comparison(sent, k + 2)  # "rail 3x worse than road": the multiple of road's cost
            sent.claim(Found("level", m.end, base, w[k], (m,)), "level")
            _claim_base(sent, base)
            continue
        if k + 1 < sent.n and w[k + 1] not in (",", "and", "/", "|"):
            continue  # "road 0.2 km", "tree 0.9 of the time": not a cost
        sent.claim(Found("level", m.end, k + 1, w[k], (m,)), "level")


#: The words of a multiple ("2x road", "3 times the road").
_TIMES = frozenset({"x", "times"})


#: Words between a multiple and its base that say it is dearer ("3x worse than road", "2 times
#: more expensive than the trail", "5x the cost of road").
_DEARER = frozenset({"worse", "dearer", "costlier", "pricier", "more", "expensive", "than", "as", "cost", "of"})


def _past_comparison(sent: Sentence, k: int) -> int:
    """Past the words of a dearer comparison after a multiple, up to its base (``k`` when none)."""
    j, past = k, k
    while j < sent.n and sent.words[j] in _DEARER and sent.claimed[j] is None and j - k < 4:
        j += 1
        if sent.words[j - 1] in ("than", "of"):
            past = j
    return past


def _claim_base(sent: Sentence, k: int) -> None:
    """The entity a multiple is of ("grass costs 2x road"): relative cost 1."""
    k += k < sent.n and sent.words[k] in ("the", "a", "an")
    base = sent.mention_at.get(k)
    if base is not None and base.role == "target":
        sent.claim(Found("level", base.start, base.end, "1", (base,)), "level")


def _is_relative(word: str) -> bool:
    """Whether a token may be a relative cost ("asphalt: 1, gravel: 2, mud: 5"): a number above
    the 0-1 scale, read as one only beside others (:func:`relative_levels`)."""
    try:
        return 1.0 < float(word) <= 1000.0
    except ValueError:
        return False


def relative_levels(clauses: list[Clause]) -> None:
    """Costs above 1 are relative ("asphalt | 1", "gravel | 2", "mud | 5"): when a prompt states
    two or more, every stated cost is a step of an ordering, cheapest first (``order:``, the
    steps of "first X, then Y"); a lone one ("road: 3") says no cost and is dropped."""
    stated = [(c, n, t) for c in clauses for n, t in c.assigned.items() if t.startswith("level:")]
    levels = [(c, n, float(t.split(":", 1)[1])) for c, n, t in stated]
    if not any(v > 1.0 for _, _, v in levels):
        return
    steps = sorted({v for _, _, v in levels})
    for c, name, v in levels:
        if len(steps) < 2:
            del c.assigned[name]
        else:
            c.assigned[name] = f"order:{min(lx.PREFER + lx.STEP * steps.index(v), lx.ORDER_MAX):.2f}"


def _is_level(word: str) -> bool:
    """Whether a token is a cost on the 0-1 scale ("0.9", "0", "1", ".5" is tokenised "5")."""
    try:
        value = float(word)
    except ValueError:
        return False
    return 0.0 <= value <= 1.0 and (word in ("0", "1") or "." in word)


def stated_levels(c: Clause) -> None:
    """ "tree: 0.9": each stated cost is its entity's tier (``level:0.90``)."""
    for f in c.found:
        if f.kind == "level":
            for m in f.mentions:
                c.assigned[m.name] = f"level:{float(f.value):.2f}"
                c.took(m.name, (f.start, f.end), (f.start, f.end))
