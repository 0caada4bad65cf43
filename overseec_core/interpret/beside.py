"""On versus beside: "along the river bank but not in the river", "follow the fence line, never
on it", "skirt the forest edge without entering".

Such a sentence names an object X twice over: the band beside X is where to go, X itself is
where not to. Read per sentence, before its clauses: a *beside* word before X ("along",
"alongside", "beside", "next to", "parallel to", "skirt", "follow") or an *edge* noun of X ("the
river bank", "the edge of the forest", "the verge of the road"), together with a negated
"on / in / into / entering" ("but not in the river", "never on it", "without entering",
"keeping off the carriageway", "rather than in the marsh", "stay out of the water") or a side
of X ("trace the hedge on its field side"). Then X is avoided (forbidden when the negation is a "never" or
"must not") and a soft ``near`` cue on X prefers the ground beside it, the nearer the better
(``costlang.synth``: the cue lowers only ground that is not avoided, so X itself keeps its
level). The words are claimed, so nothing of the construct is reported as not understood.

A beside word whose sentence has no negation ("follow the hedge. The hedge itself is off
limits") is *pending*: it holds when the prompt avoids or forbids X anywhere, and adds nothing
otherwise ("follow the hedge" keeps preferring the hedge).
"""

from __future__ import annotations

from dataclasses import dataclass

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.sentence import Found, Mention, Sentence

#: Ground beside the object that the route should keep to, when the sentence states no width.
BESIDE_BAND_M = 5.0

BESIDE_WORDS = frozenset(
    "along alongside beside parallel skirt skirts skirting follow follows following trace traces tracing "
    "track tracks tracking flank flanking hug hugs hugging thread threading weave weaving".split()
)
BESIDE_PAIRS = frozenset({("next", "to"), ("parallel", "to"), ("parallel", "with"), ("close", "to")})
EDGE_NOUNS = frozenset(
    "bank banks edge edges verge verges shore shores shoreline shorelines margin margins perimeter fringe "
    "fringes embankment embankments line lines boundary rim brink towpath shoulder shoulders side sides".split()
)  # not "corridor": the railway corridor is the railway's land ("keep out of the railway corridor")
#: Negations of being on / in X ("not in", "never on", "without entering", "rather than in",
#: "off the ...", "out of the ...").
NEGATIONS = frozenset("not never without don't no off out avoid avoiding rather instead".split())
FORBIDDING = frozenset({"never"})
ON_WORDS = frozenset(
    "on in into onto inside entering enter enters touching touch itself crossing cross over upon within "
    "using use uses occupying occupy occupies traversing traverse under beneath".split()
)
#: Being inside X, which "don't" forbids ("don't go in it", "don't enter the river").
ENTERING = frozenset("in into inside enter entering".split())
_GAP = 3  # words allowed between a beside word and the object ("along the old river")


#: Verbs of travelling an edge ("walk the edge of the marsh"): with an edge noun and no
#: negation, the band beside the object is preferred and the object keeps its own tier.
EDGE_VERBS = frozenset(
    "walk walks walking drive drives driving run runs running ride riding hug hugs hugging use take".split()
)


@dataclass(frozen=True)
class Beside:
    """One on-versus-beside reading: the object, its tier (avoid or lethal; None: the object
    keeps the tier the prompt or its prior gives it) and the band width."""

    name: str
    tier: str | None
    metres: float = BESIDE_BAND_M
    #: "track alongside the paved road; on-road travel prohibited": a beside word with no
    #: negation in its sentence, which holds when the prompt avoids or forbids the object
    #: elsewhere (its words are not claimed: the sentence reads them as it would without it).
    pending: bool = False


def _beside_word_before(sent: Sentence, m: Mention) -> list[int]:
    """Indices of the beside word (and its partner) governing ``m``, or []."""
    for k in range(max(0, m.start - _GAP - 1), m.start):
        w = sent.words[k]
        if any(o.known and o.start <= k < o.end for o in sent.mentions):
            continue  # "the gravel track, ...": part of an entity's name, not a verb
        if w in BESIDE_WORDS:
            return [] if _peaks_before(sent, k) else [k]
        if k + 1 < sent.n and (w, sent.words[k + 1]) in BESIDE_PAIRS:
            return [] if _peaks_before(sent, k) else [k, k + 1]
    return []


def _peaks_before(sent: Sentence, k: int) -> bool:
    """Whether a cost's peak or trough is what stands beside ("highest right next to it"): a
    graded cue's shape (:func:`overseec_core.interpret.conditions.claim_cues`), no band to drive in."""
    j = k - 1
    j -= j >= 0 and sent.words[j] in lx.PEAK_ADVERBS
    j -= j >= 0 and sent.words[j] in lx.COST_WORDS
    return j >= 0 and sent.words[j] in lx.PEAK_WORDS | lx.TROUGH_WORDS


#: Ground covers that an edge noun after them is made of, not the edge of ("ride on the grass
#: verge", "the gravel shoulder"): the route is on them.
EDGE_MATERIALS = frozenset({"grass", "gravel", "dirt", "sand", "turf", "earth", "soil", "lawn", "mud"})


def _edge_of(sent: Sentence, m: Mention) -> list[int]:
    """Indices of an edge noun of ``m``: "the river bank", "the edge of the forest" (never of
    a ground cover it is made of: "the grass verge" is grass, :func:`material_edges`)."""
    if m.end < sent.n and sent.words[m.end] in EDGE_NOUNS and not _material(sent, m):
        return [m.end]
    for k in range(max(0, m.start - 4), m.start - 1):
        if sent.words[k] in EDGE_NOUNS and sent.words[k + 1] == "of":
            return [k, k + 1]
    return []


def _negated_on(sent: Sentence, after: int, name: str | None = None) -> tuple[list[int], bool] | None:
    """The negated "on/in X" after word ``after``: its indices and whether it forbids. Another
    entity named first ("go along the road, the lake is off limits") takes what follows: the
    negation is about it, not the road."""
    blocked = False  # another entity named first: the negation must name ours again ("not on the trail itself")
    for k in range(after, sent.n):
        other = sent.mention_at.get(k)
        if (
            other is not None
            and other.role == "target"
            and other.name != name
            and sent.words[k - 1] in (",", "the", "and", "a")
        ):
            blocked = True
        if sent.words[k] not in NEGATIONS or tuple(sent.words[k : k + 2]) == ("off", "limits"):
            continue
        for j in range(k + 1, min(sent.n, k + 4 + _gap_words(sent, k + 1))):
            if sent.words[j] in ON_WORDS:
                obj = _negated_object(sent, j + 1)
                if blocked and (obj is None or obj.name != name):
                    return None
                if obj is not None and obj.name != name and _led(sent, obj.name):
                    return None  # "alongside the trail on the grass margin, not on the trail": the trail's negation
                forbids = (
                    sent.words[k] in FORBIDDING
                    or (k > 0 and sent.words[k - 1 : k + 1] == ["must", "not"])
                    # "don't go in it", "don't enter the water": as "don't go into X", forbidding
                    or (sent.words[k] == "don't" and sent.words[j] in ENTERING)
                )
                return list(range(k, j + 1)), forbids
        if sent.words[k] == "off":  # "keeping off the carriageway"
            return [k], False
        if sent.words[k] == "out" and k + 1 < sent.n and sent.words[k + 1] == "of":
            return [k, k + 1], True  # "stay out of the water": forbidden, as "keep out of X" is
    return None


def _led(sent: Sentence, name: str) -> bool:
    """Whether a mention of ``name`` in the sentence has a beside word or edge noun of its own."""
    return any(o.name == name and (_beside_word_before(sent, o) or _edge_of(sent, o)) for o in sent.mentions)


def _side_of(sent: Sentence, m: Mention) -> list[int]:
    """Indices of "on its (field) side" / "on the far side" right after ``m``: beside it, not on it."""
    k = m.end
    if k + 2 < sent.n and sent.words[k] == "on" and sent.words[k + 1] in ("its", "their", "the"):
        for j in range(k + 2, min(sent.n, k + 5)):
            if sent.words[j] in ("side", "sides"):
                return list(range(k, j + 1))
    return []


def _material(sent: Sentence, m: Mention) -> bool:
    """Whether the mention is named by a ground cover word ("grass", "gravel": an unpaved road)."""
    end = m.end - (m.end - m.start > 1 and sent.words[m.end - 1] in EDGE_NOUNS)  # "grass verge" once joined
    return lx.singularise(sent.words[end - 1]) in EDGE_MATERIALS


def material_edges(sent: Sentence) -> None:
    """ "on the grass verge", "along the gravel shoulder": the edge noun after a ground cover
    is part of its name (the verge is grass), so the route on it is on the cover."""
    for m in sent.mentions:
        if _material(sent, m) and m.end < sent.n and sent.words[m.end] in EDGE_NOUNS:
            if sent.claimed[m.end] is None:
                sent.claimed[m.end] = "mention"
                m.end += 1


def _shared_object(sent: Sentence, out: list[Beside]) -> None:
    """ "adjacent to, but never upon, building footprints", "beside but not on the rails": a
    beside word and a negated "on" that share the object named after both -- the band beside
    it preferred, the object itself avoided (forbidden with "never")."""
    w = sent.words
    for k in range(sent.n - 3):
        if sent.claimed[k] is not None:
            continue
        lead = 2 if (w[k], w[k + 1]) in BESIDE_PAIRS | {("adjacent", "to")} else int(w[k] in BESIDE_WORDS)
        if not lead:
            continue
        j = k + lead
        j += j < sent.n and w[j] == ","
        j += j < sent.n and w[j] in ("but", "yet", "and")
        if j + 1 >= sent.n or w[j] not in NEGATIONS or w[j + 1] not in ON_WORDS:
            continue
        neg = j
        j += 2
        j += j < sent.n and w[j] == ","
        obj = _negated_object(sent, j)
        if obj is None or not sent.free(k, j) or not all(sent.claimed[x] is None for x in range(j, obj.start)):
            continue
        _claim(sent, obj, list(range(k, obj.start)))
        obj.role = "cue"
        if all(b.name != obj.name for b in out):
            out.append(Beside(obj.name, "lethal" if w[neg] in FORBIDDING else "avoid"))


def claim_beside(sent: Sentence) -> list[Beside]:
    """The sentence's on-versus-beside readings; their words are claimed as a cue."""
    out: list[Beside] = []
    material_edges(sent)
    _shared_object(sent, out)
    for m in sent.mentions:
        lead = _beside_word_before(sent, m) + _edge_of(sent, m)
        if not lead and (lone := _lone_edge(sent, m)) is not None:  # "walk the verge, not the road"
            _claim(sent, m, lone)
            if all(b.name != m.name for b in out):
                out.append(Beside(m.name, "avoid"))
            m.role = "cue"
            continue
        if not lead or _negated_lead(sent, lead[0]):
            continue  # "never run along the water's edge": no band beside it is wanted
        neg = _own_negation(sent, m)
        if sent.words[lead[0]] in ("side", "sides") and (neg is None or not _negates_itself(sent, m, neg[0])):
            continue  # "drive on the side of the road" (on it), "... of the road, don't go over water"
        side = _side_of(sent, m)
        if neg is None and not side:
            _unnegated(sent, m, lead, out)
            continue
        words, forbids = neg if neg is not None else (side, False)
        _claim(sent, m, _travelling(sent, lead[0]), lead, words)
        tier = "lethal" if forbids else "avoid"
        for obj in (m, _negated_object(sent, words[-1] + 1)):
            if obj is None:
                continue
            obj.role = "cue"  # not the object of a trigger ("keep to the ground ... rather than in the marsh")
            if all(b.name != obj.name for b in out):
                out.append(Beside(obj.name, tier))
    _on_material(sent, out)
    return out


def _on_material(sent: Sentence, out: list[Beside]) -> None:
    """ "ride alongside the trail on the grass verge, never on the trail": beside a thing (a
    reading of ``out`` holds), the ground cover the route is said to be on is where to go
    (preferred); a negated "on" ("don't drive on the grass verge") is left to the phrase tables."""
    if all(b.pending for b in out):
        return
    for m in sent.mentions:
        if not _material(sent, m) or m.end - m.start < 2:
            continue
        k = m.start - 1 - (m.start > 0 and sent.words[m.start - 1] in ("the", "a", "an"))
        if k < 0 or sent.words[k] != "on" or sent.claimed[k] is not None:
            continue
        if any(x in NEGATIONS or x in ("don't", "avoid") for x in sent.words[max(0, k - 4) : k]):
            continue
        sent.claim(Found("trigger", k, k + 1, "prefer"), "trigger")


def _lone_edge(sent: Sentence, m: Mention) -> list[int] | None:
    """ "walk the verge, not the road", "keep to the shoulder, never the carriageway": an edge
    noun of nothing named, then a negation right before ``m`` (articles aside): the edge is
    ``m``'s, the route beside it. The indices from the edge noun's verb to ``m``, or None."""
    k = m.start - 1
    while k >= 0 and sent.words[k] in ("the", "a", "an", "its", "their"):
        k -= 1
    if k < 1 or sent.words[k] not in ("not", "never") or sent.words[k - 1] != ",":
        return None
    for e in range(k - 2, max(-1, k - 5), -1):
        w = sent.words[e]
        if w in EDGE_NOUNS and sent.claimed[e] is None and not any(o.start <= e < o.end for o in sent.mentions):
            start = next((j for j in range(max(0, e - 3), e) if sent.words[j] in EDGE_VERBS | _GOING), e)
            return list(range(start, k + 1))
    return None


def _unnegated(sent: Sentence, m: Mention, lead: list[int], out: list[Beside]) -> None:
    """A beside word or edge noun with no negation: "walk the edge of the marsh" prefers the
    band beside it (the object keeps its tier); otherwise the reading is pending."""
    if _edge_of(sent, m) and _edge_travelled(sent, lead[0]):
        _claim(sent, m, lead)
        if all(b.name != m.name for b in out):
            out.append(Beside(m.name, None))
    elif m.known and all(b.name != m.name for b in out):
        out.append(Beside(m.name, None, pending=True))


def _own_negation(sent: Sentence, m: Mention) -> tuple[list[int], bool] | None:
    """The negated "on/in X" of ``m``'s beside reading (:func:`_negated_on`), unless it is
    another rule's ("follow the road ..., and never cross the water": the water's)."""
    neg = _negated_on(sent, m.end, m.name)
    return None if neg is not None and _about_another(sent, m, neg[0]) else neg


def _negated_lead(sent: Sentence, k: int) -> bool:
    """Whether a negation stands within four words before the beside word at ``k`` ("never run
    along", "don't walk beside", "never drive along the edge of"), with nothing claimed between."""
    for j in range(k - 1, max(-1, k - 5), -1):
        if sent.claimed[j] is not None and sent.claimed[j] != "mention":
            return False
        if sent.words[j] in ("never", "don't", "not", "no"):
            return True
    return False


def _about_another(sent: Sentence, m: Mention, words: list[int]) -> bool:
    """Whether a negation found after ``m`` is another rule's: coordinated ("..., and never cross
    the water") or past a semicolon, with another entity as its own object. A contrast ("but
    never inside the water", "not in the water", "off the track bed") stays the beside rule's."""
    obj = _negated_object(sent, words[-1] + 1)
    between = sent.words[m.end : words[0]]
    coordinated = ";" in between or (len(between) >= 2 and between[-2:] == [",", "and"]) or between[-1:] == ["and"]
    return obj is not None and obj.name != m.name and coordinated


#: Words that may stand between a negation and its "on" beyond the usual three ("without at
#: any point travelling on the rails", "never at any time on the road").
_ASIDES = frozenset("at any point time stage ever actually".split())


def _gap_words(sent: Sentence, k: int) -> int:
    """How many aside words (:data:`_ASIDES`) follow index ``k``."""
    j = k
    while j < sent.n and sent.words[j] in _ASIDES:
        j += 1
    return j - k


def _negated_object(sent: Sentence, k: int) -> Mention | None:
    """The mention the negation names right after it ("rather than in the marsh", "stay out of
    the water itself"), or None."""
    while k < sent.n and sent.words[k] in ("the", "a", "an", "its", "their", "this", "that"):
        k += 1
    return sent.mention_at.get(k)


#: Verbs of going that lead to an edge noun ("go along the side of the trail").
_GOING = frozenset("go goes going move moves moving travel travels proceed proceeds keep stay".split())


def _negates_itself(sent: Sentence, m: Mention, words: list[int]) -> bool:
    """Whether the negation ``words`` after "the side of X" is about X itself ("not on top of
    it", "never on the trail"), not about something else ("don't go over water")."""
    obj = _negated_object(sent, words[-1] + 1)
    return obj is not None and obj.name == m.name


def _travelling(sent: Sentence, first: int) -> list[int]:
    """The words that travel to an edge noun at ``first`` ("go along the side of", "walk the
    edge of"): from the first verb or beside word within three words before it; [] when none."""
    lead = [k for k in range(max(0, first - 3), first) if sent.words[k] in BESIDE_WORDS | EDGE_VERBS | _GOING]
    return list(range(lead[0], first)) if lead else []


def _edge_travelled(sent: Sentence, first: int) -> bool:
    """Whether a beside word or an edge verb comes within three words before index ``first``."""
    return any(w in BESIDE_WORDS or w in EDGE_VERBS for w in sent.words[max(0, first - 3) : first + 1])


def _claim(sent: Sentence, m: Mention, *spans: list[int]) -> None:
    """Claim each span's free words as the beside cue on ``m``."""
    for span in spans:
        free = [k for k in span if sent.claimed[k] is None]
        if free:
            sent.claim(Found("cue", free[0], free[-1] + 1, "beside", (m,)), "cue")
