"""Self-corrections: a speaker taking back what they just said, before the sentences are read.

"Avoid the vegetation -- no wait, vegetation is fine": the words before a marker of withdrawal
(:data:`lexicon.WITHDRAWALS`) are withdrawn, never read as rules; their entities stay named (so
"scratch that, just avoid them" finds what "them" stands for), and the interpreter notes what
it dropped. A marker at a sentence's start withdraws the sentence before it ("Stay out of the
buildings. Actually, scratch that: ...").

A replacement puts a name in place of the one the withdrawn words named, the rest of them kept:
"take the grass -- sorry, I mean the trail" reads "take the trail"; "avoid the vegetation -- no
wait, ... it's the water I meant" reads "avoid the water" (a cleft, "it's X I meant", names the
replacement). A replacement marker (:data:`lexicon.REPLACEMENTS`, "I mean", "make that") counts
only after an apology or a comma ("sorry, I mean") and before a bare name; "..., I mean it" is
emphasis, no correction. A revocation ("forget the trail rule", "ignore the water bit") takes back
the rules said before of the entity it names, and only those.
"""

from __future__ import annotations

from dataclasses import dataclass

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.sentence import Sentence
from overseec_core.interpret.tokens import Tok


@dataclass(frozen=True)
class Part:
    """A sentence as it is to be read: its tokens, and what withdrew it (None: read as rules).
    A withdrawn sentence's tokens are its names alone ("the buildings"), read as a mention with
    no preference, so a pronoun after the marker still finds them; ``span`` is what was said."""

    toks: tuple[Tok, ...]
    withdrawn_by: str | None = None
    span: tuple[int, int] | None = None
    #: Entities whose earlier rules this sentence revokes ("forget the trail rule"), and how.
    revokes: tuple[str, ...] = ()
    revoked_by: str = ""


def _withdrawn(toks: list[Tok] | tuple[Tok, ...], marker: str) -> Part:
    """The part a withdrawn sentence leaves: its names, and the span of what it said."""
    sent = Sentence(list(toks))
    names = tuple(t for m in sent.mentions for t in toks[m.start : m.end])
    return Part(names, marker, (toks[0].start, toks[-1].end))


def _marker(toks: list[Tok]) -> tuple[int, int, str] | None:
    """The first marker of withdrawal or replacement: (start, end, kind) with kind
    ``withdraw`` or ``replace``; a replacement only after a lead word ("sorry, I mean")."""
    words = [t.word for t in toks]
    for i in range(len(words)):
        for kind, table in (("withdraw", lx.WITHDRAWALS), ("replace", lx.REPLACEMENTS)):
            for phrase in table:
                if tuple(words[i : i + len(phrase)]) != phrase:
                    continue
                if kind == "replace" and not (i > 0 and words[i - 1] in lx.CORRECTION_LEADS):
                    continue
                return i, i + len(phrase), kind
    return None


def _strip(toks: list[Tok], front: bool) -> list[Tok]:
    """``toks`` without the lead words and commas at their front (or their back)."""
    out = list(toks)
    while out and (out[0] if front else out[-1]).word in lx.CORRECTION_LEADS:
        out.pop(0 if front else -1)
    return out


def _bare_name(toks: list[Tok]) -> bool:
    """Whether ``toks`` only name entities ("the trail", "the gravel track"): every word is
    grammar or inside a mention, and one mention at least is a name, not a pronoun ("I mean it"
    corrects nothing)."""
    if not toks:
        return False
    sent = Sentence(toks)
    inside = {i for m in sent.mentions for i in range(m.start, m.end)}
    named = any(sent.words[m.start] not in lx.PRONOUNS for m in sent.mentions)
    return named and all(i in inside or w in lx.FILLER for i, w in enumerate(sent.words))


def _replace_last(toks: list[Tok], name: list[Tok]) -> list[Tok]:
    """``toks`` with their last mention replaced by the tokens of ``name``."""
    mentions = Sentence(toks).mentions
    if not mentions:
        return list(name)
    last = max(mentions, key=lambda m: m.start)
    return [*toks[: last.start], *name, *toks[last.end :]]


def _cleft(toks: list[Tok]) -> tuple[int, int, list[Tok]] | None:
    """ "it's the water I meant": (start, end, the name's tokens), or None."""
    words = [t.word for t in toks]
    for i, w in enumerate(words):
        opening = 1 if w == "it's" else 2 if words[i : i + 2] in (["it", "is"], ["it", "was"]) else 0
        if not opening:
            continue
        for j in range(i + opening + 1, min(len(words), i + opening + 6)):
            if tuple(words[j : j + 2]) in lx.CLEFT_ENDS:
                name = toks[i + opening : j]
                if _bare_name(name):
                    return i, j + 2, name
    return None


def _split(toks: list[Tok], previous: Part | None) -> tuple[list[Part], bool] | None:
    """How a sentence with a marker reads: (parts, whether ``previous`` is withdrawn too)."""
    found = _marker(toks)
    if found is None:
        return None
    start, end, kind = found
    before, after = _strip(toks[:start], front=False), _strip(toks[end:], front=True)
    if kind == "replace" and not _bare_name(after):
        return None  # "..., I mean it": a replacement names what it puts in place, or is none
    marker = " ".join(t.word for t in toks[start:end])
    takes_previous = not before and previous is not None and previous.withdrawn_by is None
    if takes_previous:
        assert previous is not None
        before = list(previous.toks)
    parts = [_withdrawn(before, marker)] if before and not takes_previous else []
    if before and _bare_name(after):  # "take the grass -- sorry, I mean the trail"
        return [*parts, Part(tuple(_replace_last(before, after)))], takes_previous
    cleft = _cleft(after)
    if before and cleft is not None:  # "... it's the water I meant": the withdrawn words on it
        c0, c1, name = cleft
        rest = _strip(after[:c0], front=False) + _strip(after[c1:], front=True)
        kept = [Part(tuple(rest))] if rest else []
        return [*parts, *kept, Part(tuple(_replace_last(before, name)))], takes_previous
    return [*parts, Part(tuple(after))] if after else parts, takes_previous


def _revocation(toks: list[Tok]) -> Part | None:
    """ "Actually, forget the trail rule, we need the trail after all": the sentence without its
    revocation, naming the entities whose earlier rules it revokes; None without one."""
    words = [t.word for t in toks]
    for i, w in enumerate(words):
        if w not in lx.REVOKE_VERBS:
            continue
        sent = Sentence(toks)
        j = i + 1 + (i + 1 < len(words) and words[i + 1] in ("the", "that", "my", "our", "this"))
        named = [m for m in sent.mentions if m.start == j and m.known]
        if named and named[0].end < len(words) and words[named[0].end] in lx.REVOKED_NOUNS:
            end = named[0].end + 1
            rest = _strip(toks[:i], front=False) + _strip(toks[end:], front=True)
            said = " ".join(words[i:end])
            return Part(tuple(rest), revokes=(named[0].name,), revoked_by=said)
    return None


def corrected(sentences: list[list[Tok]]) -> list[Part]:
    """The sentences as they are to be read, self-corrections applied (see the module doc)."""
    out: list[Part] = []
    for toks in sentences:
        if (revoking := _revocation(toks)) is not None:
            out.append(revoking)
            continue
        split = _split(toks, out[-1] if out else None)
        if split is None:
            out.append(Part(tuple(toks)))
            continue
        parts, takes_previous = split
        if takes_previous:
            out[-1] = _withdrawn(out[-1].toks, "withdrawn by what follows")
        out.extend(parts)
    return out
