"""Rules stated as their consequence: "if it touches the water, the rover is lost", "if the rover
gets within 6 m of a tree the survey is scrubbed".

A careful reader takes the consequence for the verdict: going there is forbidden, and coming
within N m is a hard clearance of N m. Claimed over a
:class:`~overseec_core.interpret.sentence.Sentence` before the conditions, so the "if" is not read
as a condition that no layer can carry: the "if" clause becomes a forbidding trigger (or a hard
far cue) on the entities it names, and the consequence is grammar.
"""

from __future__ import annotations

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.sentence import Found, Sentence

#: Words that open a consequence's "if" clause.
_OPENERS = frozenset({"if", "should", "once", "whenever"})
#: How far (words) the consequence's verdict may stand after the entity list of its "if" clause
#: (its subject between: "the survey", "our rover").
_REACH = 4


def claim_consequences(sent: Sentence) -> None:
    """Claim every "if <the traveller> <reaches> X, <the mission is lost>" of the sentence."""
    for i in range(sent.n):
        if sent.words[i] in _OPENERS and sent.free(i, i + 1):
            _consequence_at(sent, i)


def _consequence_at(sent: Sentence, i: int) -> None:
    """The consequence whose "if" is at ``i``: a reaching (:func:`_reaching`), the entities,
    then the verdict on the mission (:func:`_doom_after`)."""
    reach = _reaching(sent, i)
    if reach is None:
        return
    k, metres = reach
    lst, end = sent.list_forward(k)
    if not lst:
        return
    doom = _doom_after(sent, end)
    if doom is None:
        return
    if metres is None:
        sent.claim(Found("trigger", i, k, "lethal"), "trigger")
    else:
        for m in lst:
            m.role = "cue"
        sent.claim(Found("cue", i, end, "far", tuple(lst), metres, hard=True), "cue")
    for m in [m for m in sent.mentions if end <= m.start < doom]:  # "the survey is scrubbed": no names
        sent.drop_mention(m)
        for j in range(m.start, m.end):
            sent.claimed[j] = None
    sent.claim(Found("filler", end, doom, "consequence"), "filler")


def _reaching(sent: Sentence, i: int) -> tuple[int, float | None] | None:
    """After the "if" at ``i``: its subject (the traveller) and a verb of reaching ("touches",
    "ends up in", "gets within 6 m of"); where the entities start and the distance of a
    "within" (None for contact), or None when the clause is no such reaching."""
    j = i + 1
    while j < sent.n and sent.words[j] in lx.CONSEQUENCE_SUBJECTS and j - i <= 3:
        j += 1
    verb = sent.match(lx.CONTACT_VERBS, j)
    if j == i + 1 or verb is None:
        return None
    k = j + len(verb[0])
    if verb[0][-1] != "within":
        return k, None
    d = sent.distance(k)
    if d is None:
        return None
    return d[1] + (d[1] < sent.n and sent.words[d[1]] in ("of", "from")), d[0]


def _doom_after(sent: Sentence, end: int) -> int | None:
    """Where the consequence after an "if" clause ends ("..., the rover is lost", "... the survey
    is scrubbed", "... it's game over"): separators, up to three words of its subject, then its
    verdict (:data:`~overseec_core.interpret.lexicon.DOOM`); None when none follows."""
    a = end
    while a < sent.n and sent.words[a] in lx.SEPARATORS:
        a += 1
    w = sent.words
    for k in range(a, min(sent.n, a + _REACH)):
        for words, _ in lx.DOOM.get(w[k], ()):  # as words: "scrubbed" may stand as a name
            if tuple(w[k : k + len(words)]) == words:
                return k + len(words)
        if w[k] in lx.SEPARATORS:
            return None
    return None
