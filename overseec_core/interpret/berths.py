"""Room given to something: "give the houses a wide berth", "give the hedges 5 m", "leave a bit of
room around the buildings", "keep some space between the robot and the fence", "leave about 20
yards between yourself and the houses", "as wide a berth as you can" -- a far cue on what the
room is kept from (:func:`berth_cue`, claimed among :mod:`.conditions`' cues).
"""

from __future__ import annotations

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.distances import between_selves
from overseec_core.interpret.graded import trailing_distance
from overseec_core.interpret.sentence import Found, Sentence


def berth_cue(sent: Sentence, i: int) -> bool:
    """ "give the houses a wide berth (of about 25 m)": a far cue on the entities given it."""
    if sent.words[i] in ("leave", "keep") and sent.free(i, i + 1) and _room_between(sent, i):
        return True
    if sent.words[i] not in lx.GIVE_VERBS or not sent.free(i, i + 1):
        return False
    lst, end = sent.list_forward(i + 1)
    at = sent.skip(end, lx.APPROXIMATORS | {"maybe", "perhaps", "say", "like"})  # "give the houses maybe 10 m"
    if lst and (d := sent.distance(at)) and sent.free(end, d[1]):  # "give the hedges 5 m"
        for mm in lst:
            mm.role = "cue"
        sent.claim(Found("cue", i, d[1], "far", tuple(lst), d[0]), "cue")
        return True
    noun = _berth_noun(sent, end) if lst else None
    if noun is None:
        return False
    metres = trailing_distance(sent, noun + 1)
    for mm in lst:
        mm.role = "cue"
    sent.claim(Found("cue", i, i + 1, "far", tuple(lst), metres), "cue")
    sent.claim(Found("filler", end, _as_you_can(sent, noun + 1), "berth"), "cue")
    return True


#: How much room is given, said after it ("as you (reasonably) can", "you can").
_AS_YOU_CAN = (("as", "you", "reasonably", "can"), ("as", "you", "can"), ("you", "can"), ("as", "we", "can"))


def _as_you_can(sent: Sentence, k: int) -> int:
    """Past "as you (reasonably) can" at ``k`` ("all the room you can"), else ``k``."""
    for p in _AS_YOU_CAN:
        if tuple(sent.words[k : k + len(p)]) == p and sent.free(k, k + len(p)):
            return k + len(p)
    return k


def _room_between(sent: Sentence, i: int) -> bool:
    """ "leave a bit of room between you and the train tracks", "keep some space between the
    robot and the fence": a (soft) far cue on what the room is kept from."""
    noun, metres = _berth_noun(sent, i + 1), None
    at = sent.skip(i + 1, lx.APPROXIMATORS | lx.ARTICLES)  # "leave about 20 yards between yourself and X"
    if noun is None and (d := sent.distance(at)) is not None:  # "leave 5 metres (or so) between us and X"
        noun, metres = d[1] - 1, d[0]
        if tuple(sent.words[d[1] : d[1] + 2]) in lx.APPROX_AFTER:
            noun += 2
        elif d[1] < sent.n and sent.words[d[1]] in lx.GAP_NOUNS | lx.ROOM_NOUNS:
            noun += 1  # "keep a 10 m gap between yourself and the water"
    if noun is not None and _room_around(sent, i, noun, metres):
        return True
    if noun is None or noun + 1 >= sent.n or sent.words[noun + 1] != "between" or not sent.free(i, noun + 2):
        return False
    k = between_selves(sent, noun + 1)
    if k is None:
        return False
    lst, end = sent.list_forward(k)
    if not lst:
        return False
    for mm in lst:
        mm.role = "cue"
    metres = trailing_distance(sent, end) if metres is None else metres
    sent.claim(Found("cue", i, end, "far", tuple(lst), metres), "cue")
    return True


def _room_around(sent: Sentence, i: int, noun: int, metres: float | None) -> bool:
    """ "leave a little room around the buildings, say 5 m": a (soft) far cue on what the room is
    left around, claimed from ``i``; False when no "around X" follows the room noun."""
    if noun + 1 >= sent.n or sent.words[noun + 1] not in ("around", "round") or not sent.free(i, noun + 2):
        return False
    lst, end = sent.list_forward(noun + 2)
    if not lst:
        return False
    for mm in lst:
        mm.role = "cue"
    metres = trailing_distance(sent, end) if metres is None else metres
    sent.claim(Found("cue", i, end, "far", tuple(lst), metres), "cue")
    return True


def _berth_noun(sent: Sentence, k: int) -> int | None:
    """The index of the gap noun of "a (wide) berth", "plenty of room", "a bit of room", "a
    little space" starting at ``k``, else None ("room" taken for a name is no entity here)."""
    w = sent.words
    if k + 2 < sent.n and w[k] == "as" and w[k + 1] in lx.WIDE_WORDS and w[k + 2] in ("a", "an"):
        k += 2  # "as wide a berth as you can" (its "as you can" is a softener: _aim_after)
        j = k + 1
    elif k < sent.n and w[k] in lx.ROOM_NOUNS | {"berth"} and (k + 1 == sent.n or w[k + 1] in lx.SEPARATORS):
        j = k  # "Residential buildings: give them room."
    elif tuple(w[k : k + 2]) in (("all", "the"), ("as", "much")):
        j = k + 2  # "all the room you can", "as much room as you reasonably can"
    elif k >= sent.n or w[k] not in ("a", "an", "plenty", "lots", "some"):
        return None
    else:
        j = k + 1 + (k + 1 < sent.n and w[k + 1] == "of")
    while j < sent.n and w[j] in lx.BERTH_MEASURES | {"of"}:
        j += 1
    if j < sent.n and w[j] in lx.WIDE_WORDS:
        j += 1
    if j >= sent.n or w[j] not in lx.GAP_NOUNS | lx.ROOM_NOUNS:
        return None
    if any(sent.claimed[x] not in (None, "modifier") for x in range(k, j)):  # "a little" is a modifier
        return None
    room = sent.mention_at.get(j)
    if room is not None and w[j] in lx.ROOM_NOUNS and not room.known:
        sent.drop_mention(room)
    return j if sent.free(j, j + 1) else None
