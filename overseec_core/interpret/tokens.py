"""Tokens of a mission prompt: normalising, tokenizing and splitting into sentences.

The first step of the offline interpreter (:mod:`overseec_core.interpret.offline`): lengths are
kept by :func:`normalise`, so every token's character span quotes the original prompt.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from overseec_core.interpret import lexicon as lx


@dataclass
class Tok:
    """One token: the word as read (lower case, contractions expanded) and its character span."""

    word: str
    start: int
    end: int


def is_adverb(word: str) -> bool:
    """Words ending in -ly are adverbs ("carefully", "quietly"), never entity names."""
    return len(word) > 4 and word.endswith("ly") and word not in lx.LY_NOUNS


#: A setting written key=value ("rail=lethal", "veg=ok"): the "=" is a colon.
_SETTING = re.compile(r"(?<=[^\W\d_])=(?=[^\W\d_])")
#: The gap before the next setting on a line ("rail=lethal  veg=ok"): a sentence end.
_NEXT_SETTING = re.compile(r"(?<=\S)[ \t]+(?=[^\W\d_][\w]*=[^\W\d_])")
#: A dot inside a word ("building.standoff", "surface.primary"): a space, not a sentence end.
_INNER_DOT = re.compile(r"(?<=[^\W\d_])\.(?=[^\W\d_])")


def _settings(text: str) -> str:
    """Lines of ``key=value`` settings as colon statements, one per sentence; dotted keys as
    words; length preserved."""
    if len(_SETTING.findall(text)) >= 2:
        text = _NEXT_SETTING.sub(lambda m: ";" + m.group()[1:], text)
    text = _SETTING.sub(":", text)
    return _INNER_DOT.sub(" ", text)


#: A ranking's label and its list: "order of preference (best first): trail, road, grass",
#: "prefs: A; B; C" (up to the end of the sentence or line). A list worst first is left alone:
#: its steps cannot be turned round in place.
_RANKING = re.compile(
    r"(?im)(?:^|(?<=[.!?\n]))[ \t]*((?:(?:order|list) of (?:preference|priority)|preference order|priority order"
    r"|rankings?|ranked|preferences|prefs?|priorities)(?:[ \t]*[,(]?[ \t]*best[ \t]+first[ \t]*\)?)?"
    r"|best[ \t]+first)[ \t]*:([^.!?\n]*)"
)
#: Words that make a list after a ranking label something else than a plain ranking.
_NOT_RANKED = re.compile(r"(?i)\b(then|except|but|not|no|avoid|excluded|never)\b")


def _rankings(text: str) -> str:
    """A ranking's label blanked and its list's separators written as ``>``, so "order of
    preference: trail, road, grass" reads as "trail > road > grass"; length preserved. A list
    with other words in it ("priority: road, then trail") is left as written."""

    def rank(m: re.Match) -> str:
        label, items = m.group(1), m.group(2)
        parts = [p for p in re.split(r"[,;]", items) if p.strip()]
        if len(parts) < 2 or _NOT_RANKED.search(items) or any(len(p.split()) > 3 for p in parts):
            return m.group()
        head = m.group()[: m.start(1) - m.start()]
        return (
            head
            + " " * len(label)
            + m.group()[m.end(1) - m.start() : m.start(2) - m.start()]
            + re.sub(r"[,;]", ">", items)
        )

    return _RANKING.sub(rank, text)


def normalise(text: str) -> str:
    """Lower-case, straight apostrophes, hyphens between letters as spaces, arrows ("->", "=>")
    as colons, ``key=value`` settings as colon statements, dots inside words as spaces, a
    ranking's list as ``>`` steps (:func:`_rankings`); length preserved."""
    out = []
    text = _rankings(_settings(text))
    n = len(text)
    for i, ch in enumerate(text):
        if ch in "\u2019\u2018`\u00b4":
            ch = "'"
        elif ch in "-\u2010\u2011\u2012\u2013" and 0 < i < n - 1 and text[i - 1].isalpha() and text[i + 1].isalpha():
            ch = " "
        elif ch in "-=" and i < n - 1 and text[i + 1] == ">":
            ch = " "  # an arrow "->", "=>" reads as a colon: "bldgs -> keep well away"
        elif ch == ">" and i > 0 and text[i - 1] in "-=":
            ch = ":"
        elif ch == "\u2192":
            ch = ":"
        low = ch.lower()
        out.append(low if len(low) == 1 else ch)
    return "".join(out)


def tokenize(text: str) -> list[Tok]:
    """The prompt's tokens (possessive -s dropped, "&" -> "and", a bare "dont" -> "don't", a
    letter typed three times once, a field abbreviation spelt out: "bldgs" -> "buildings")."""
    toks = []
    for m in lx.TOKEN_RE.finditer(normalise(text)):
        w = m.group()
        if w.endswith("'s") and w not in lx.KEEP_S:
            w = w[:-2]
        w = {"&": "and", "/": "or"}.get(w, w)
        w = _ELONGATED.sub(r"\1", w)  # "waaay" -> "way", "sooo" -> "so"
        w = lx.BARE_CONTRACTIONS.get(w, w)
        for part in w.split(" "):  # "atleast" -> "at least": both words keep the written span
            toks.append(Tok(part, m.start(), m.end()))
    return _hyphen_compounds(toks, text)


def _hyphen_compounds(toks: list[Tok], text: str) -> list[Tok]:
    """ "stand-off", "set-back": two words joined by a hyphen that make one gap noun written
    whole (:data:`lexicon.CLEARANCE_NOUNS`) are that noun; other hyphenated words stay two words
    ("no-go", "tree-line" are read word by word)."""
    out: list[Tok] = []
    for t in toks:
        prev = out[-1] if out else None
        if (
            prev is not None
            and text[prev.end : t.start] in ("-", "\u2010", "\u2011")
            and prev.word + t.word in lx.CLEARANCE_NOUNS
        ):
            out[-1] = Tok(prev.word + t.word, prev.start, t.end)
        else:
            out.append(t)
    return out


#: A letter typed three or more times running (emphasis: "waaay", "sooo far"): read once.
_ELONGATED = re.compile(r"([^\W\d_])\1{2,}")


def sentences(toks: list[Tok]) -> list[list[Tok]]:
    """The tokens split at sentence ends (``. ; ! ?`` and newlines), which are dropped."""
    out: list[list[Tok]] = []
    cur: list[Tok] = []
    for t in toks:
        if t.word in lx.SENTENCE_ENDS:
            if cur:
                out.append(cur)
            cur = []
        else:
            cur.append(t)
    if cur:
        out.append(cur)
    return out
