"""Shares of the route: "spend at most 10 % of the route on grass", "at least 80 % on the road",
"the rest belongs on the road or the trail".

A cost map cannot hold a share (the route's length on a class is the planner's outcome, not a
cell's cost), so a careful reader takes what the share says of the class: a cap avoids it, a
floor prefers it, and "the rest" goes where the rest is said to belong. Claimed over a
:class:`~overseec_core.interpret.sentence.Sentence` before the phrase tables, as triggers on the
entities named after the share.
"""

from __future__ import annotations

from overseec_core.interpret.sentence import Found, Sentence

#: A share's bound, by its words: a cap (avoid) or a floor (prefer).
_BOUNDS: dict[tuple[str, ...], str] = {
    ("at", "most"): "avoid",
    ("no", "more", "than"): "avoid",
    ("not", "more", "than"): "avoid",
    ("less", "than"): "avoid",
    ("under",): "avoid",
    ("max",): "avoid",
    ("maximum",): "avoid",
    ("at", "least"): "prefer",
    ("no", "less", "than"): "prefer",
    ("more", "than"): "prefer",
    ("over",): "prefer",
    ("min",): "prefer",
    ("minimum",): "prefer",
}
#: Verbs before a share that are read with it ("spend at most 10 % on grass").
_SPEND = frozenset({"spend", "spends", "spending", "put", "keep", "have"})
#: What the share is of ("10 % of the route", "of it", "of the distance").
_WHOLE = frozenset({"route", "path", "distance", "trip", "journey", "drive", "run", "length", "it", "way"})
#: Prepositions between a share and its class.
_ON = frozenset({"on", "in", "over", "through", "across", "along", "via"})
#: Words between "the rest" and its class ("the rest belongs on the road", "the rest should go on").
_REST_VERBS = frozenset({"belongs", "belong", "goes", "go", "should", "must", "can", "stays", "stay", "is", "be", "of"})


def claim_shares(sent: Sentence) -> None:
    """Claim every share of the route in the sentence, left to right."""
    for i in range(sent.n):
        if sent.free(i, i + 1):
            _bounded_share(sent, i) or _the_rest(sent, i)


def _bounded_share(sent: Sentence, i: int) -> bool:
    """ "at most 10 % of the route on grass": a cap avoids the class, a floor prefers it."""
    w = sent.words
    bound = next((b for b in _BOUNDS if tuple(w[i : i + len(b)]) == b), None)
    if bound is None:
        return False
    k = i + len(bound)
    if k + 1 >= sent.n or not w[k].replace(".", "", 1).isdigit() or w[k + 1] not in ("%", "percent"):
        return False
    k += 2
    if k + 1 < sent.n and w[k] == "of":  # "of the route"
        j = k + 1 + (w[k + 1] in ("the", "its", "our", "your", "a"))
        if j < sent.n and w[j] in _WHOLE:
            k = j + 1
    if k >= sent.n or w[k] not in _ON or not sent.free(i, k + 1):
        return False
    lst, _ = sent.list_forward(k + 1)
    if not lst:
        return False
    start = i - (i > 0 and w[i - 1] in _SPEND and sent.free(i - 1, i))
    sent.claim(Found("trigger", start, k + 1, _BOUNDS[bound]), "trigger")
    return True


def _the_rest(sent: Sentence, i: int) -> bool:
    """ "the rest belongs on the road or the trail": where the rest of the route goes, preferred."""
    w = sent.words
    if w[i] != "rest" or i == 0 or w[i - 1] != "the":
        return False
    k = i + 1
    while k < sent.n and (w[k] in _REST_VERBS or w[k] in _WHOLE or w[k] == "the") and k - i <= 4:
        k += 1
    if k >= sent.n or w[k] not in _ON or not sent.free(i - 1, k + 1):
        return False
    lst, _ = sent.list_forward(k + 1)
    if not lst:
        return False
    sent.claim(Found("trigger", i - 1, k + 1, "prefer"), "trigger")
    return True
