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


def normalise(text: str) -> str:
    """Lower-case, straight apostrophes, hyphens between letters as spaces, arrows ("->", "=>")
    as colons, ``key=value`` settings as colon statements, dots inside words as spaces; length
    preserved."""
    out = []
    text = _settings(text)
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
    return toks


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
