"""Configuration fragments read as sentences: a TOML/INI section's name stands for the entity
its keys are about, and a boolean key reads as the verdict it names.

    [clearance.building]        ->  clearance building min 5 m
    min_m = 5                       hard
    hard = true

    [road]                      ->  not on road
    on = false                      beside road
    beside = true

    [layers.tree]               ->  tree traversable
    traversable = true

A token rewrite (:func:`overseec_core.interpret.tokens.tokenize` runs it): it inserts the
section's words, with the header's span, before each of its key lines whose key is a word of
the grammar (a key that names something, "[buffers] hedge_m = 6", is its own subject), and rewrites a key whose
value is a boolean; the text itself is never changed, so every token still quotes the prompt.
Written by hand because no configuration parser reads a fragment that is half prose, and the
grammar wants words, not a parsed document.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from overseec_core.interpret import lexicon as lx

#: A section header alone on its line: "[road]", "[clearance.building]", "[layers.tree]".
_HEADER = re.compile(r"(?m)^[ \t]*\[([^\W\d][\w .-]*)\][ \t]*$")
#: A YAML mapping's key alone on its line ("trail:", "  water:"): a section whose body is the
#: more indented lines under it.
_YAML_HEADER = re.compile(r"(?m)^([ \t]*)([^\W\d][\w .-]*):[ \t]*$")
#: A key line: "min_m = 5", "on: false"; inside a section also a name of up to three words
#: ("[avoid]\nunpaved road = yes"; outside one, "water bodies: no" is a terse rule, no setting).
_KEY_LINE = re.compile(r"(?m)^[ \t]*[^\W\d][\w.]*[ \t]*[:=]")
_SECTION_KEY_LINE = re.compile(r"(?m)^[ \t]*[^\W\d][\w.]*(?:[ \t]+[^\W\d][\w.]*){0,2}[ \t]*[:=]")
#: A key path's words that only group the keys, never name terrain ("layers.tree").
_GROUPING = frozenset({"layers", "layer", "classes", "class", "entities", "entity", "terrain", "zones", "rules"})
#: Boolean values (true and false).
_TRUE = frozenset({"true", "yes", "on"})
_FALSE = frozenset({"false", "no", "off"})
#: Keys that are prepositions of where the route is ("on = false", "beside = true"): the
#: verdict reads "beside road", "not on road".
#: Keys that name the use of the section's thing ("[water] access = forbidden"): the verdict
#: is the thing's own.
_USE_KEYS = frozenset({"access", "entry", "use", "usage", "travel", "driving", "passage", "transit", "traversal"})
#: Keys that name crossing the section's thing ("[railway] crossing = allowed"): read before
#: it, so "railway crossing" is no level crossing.
_CROSSING_KEYS = frozenset({"crossing", "crossings", "cross"})
#: Keys that are words of the grammar or a verdict's column ("min", "cost"): the section's words
#: go before them (a key that names something, "hedge_m", is its own subject).
#: Keys that stand for the section's thing itself ("[road]\nsurface = forbidden": the road).
_SELF_KEYS = frozenset({"surface", "itself", "body", "interior", "inside", "footprint", "area"})
_GRAMMAR_KEYS = frozenset(lx.VOCAB | lx.VERDICT_COLUMNS | _USE_KEYS | _CROSSING_KEYS | _SELF_KEYS)
_PLACE_KEYS = frozenset({"on", "beside", "along", "near", "inside", "in", "under", "over", "through"})


def sectioned(toks: list, text: str, make: Callable[[str, int, int], object]) -> list:
    """``toks`` with each section's words before its key lines and boolean keys read as
    verdicts; ``make(word, start, end)`` builds a token (a line ends at its "\\n" token)."""
    spans = _section_spans(text)
    out: list = []
    line: list = []
    for t in toks:
        if t.word != "\n":
            line.append(t)
            continue
        out.extend(_read_line(line, spans, text, make))
        out.append(t)
        line = []
    return out + _read_line(line, spans, text, make)


def _section_spans(text: str) -> list[tuple[int, int, int, int, list[str]]]:
    """Each section with key lines under it: (body start, body end, header start, header end,
    the header's words without grouping words); a body ends at a blank line or the next header."""
    spans = []
    for m in _HEADER.finditer(text):
        body = m.end() + 1
        blank = re.search(r"\n[ \t]*\n|\n[ \t]*\[", text[m.end() :])
        end = m.end() + blank.start() if blank else len(text)
        words = [w for w in re.split(r"[\s._-]+", m.group(1).lower()) if w and w not in _GROUPING]
        if words and _SECTION_KEY_LINE.match(text, body):
            spans.append((body, end, m.start(1), m.end(1), words))
    return spans + _yaml_spans(text)


def _yaml_spans(text: str) -> list[tuple[int, int, int, int, list[str]]]:
    """Each YAML mapping key that names something, with key lines indented under it ("trail:\n
    cost: preferred"; not "riverbank_follow:", a rule's name), as :func:`_section_spans` gives
    them; its body ends at the first line indented no deeper."""
    spans = []
    for m in _YAML_HEADER.finditer(text):
        body, depth = m.end() + 1, len(m.group(1).expandtabs())
        end = body
        for line in text[body:].split("\n"):
            if not line.strip() or len(line) - len(line.lstrip()) <= depth:
                break
            end += len(line) + 1
        words = [w for w in re.split(r"[\s._-]+", m.group(2).lower()) if w and w not in _GROUPING]
        named = words and not any(w in lx.VOCAB for w in words)  # "water:", not "riverbank_follow:"
        if named and end > body and _KEY_LINE.match(text, body):
            spans.append((body, min(end, len(text)), m.start(2), m.end(2), words))
    return spans


def _read_line(line: list, spans: list, text: str, make: Callable[[str, int, int], object]) -> list:
    """One line's tokens: a boolean setting as its verdict, the section's words put where the
    verdict reads them; any other key line of a section with the section's words first."""
    if not line:
        return line
    if any(h[2] == line[0].start for h in spans):  # the header's own line ("trail:"): its body reads it
        return []
    header = max((h for h in spans if h[0] <= line[0].start < h[1]), default=None)  # the innermost
    # "[buffers] hedge_m = 6": a key that names something is its own subject, the section a group
    section = [make(w, header[2], header[3]) for w in header[4]] if header and line[0].word in _GRAMMAR_KEYS else []
    keyed = (_SECTION_KEY_LINE if header else _KEY_LINE).match(text, text.rfind("\n", 0, line[0].start) + 1) is not None
    if not keyed:
        return line
    if len(line) < 2:
        return section + line
    if section and line[0].word in _USE_KEYS | lx.VERDICT_COLUMNS and _keyed_by(text, line):
        return section + line[1:]  # "trail:\n  cost: preferred", "[water]\naccess = forbidden"
    if section and line[0].word in _CROSSING_KEYS:  # "[railway]\ncrossing = allowed": "crossing railway"
        return [line[0], *section, *line[1:]]
    if header and not section and (listed := _listed_under_verdict(header, line, text, make)):
        return listed
    return _boolean_line(section, line, text, make)


def _listed_under_verdict(header: tuple, line: list, text: str, make: Callable[[str, int, int], object]) -> list:
    """ "[avoid]\ngrass = yes": a thing ticked under a section reads as the section's words
    before it ("avoid grass", with the header's span): a verdict's section gives it that verdict;
    under a section that names a thing ("[pond]\nswans = yes") it reads as no rule. [] when the
    line is no such thing (its value no boolean). False says the section's verdict does not
    hold: "[avoid]\ngrass = no" reads "grass fine"."""
    value = line[-1]
    if value.word not in _TRUE | _FALSE:
        return []
    name = line[:-2] if line[-2].word == ":" else line[:-1]
    between = ":" if line[-2].word == ":" else text[line[-2].end : value.start]
    if not name or not re.fullmatch(r"[ \t]*[:=][ \t]*", between):
        return []
    if value.word in _FALSE:
        return [*name, make("fine", value.start, value.end)]
    return [*[make(w, header[2], header[3]) for w in header[4]], *name]


def _keyed_by(text: str, line: list) -> bool:
    """Whether the line's first word is its key: a colon token or an "=" (no token) after it."""
    return line[1].word == ":" or re.fullmatch(r"[ \t]*=[ \t]*", text[line[0].end : line[1].start]) is not None


def _boolean_line(section: list, line: list, text: str, make: Callable[[str, int, int], object]) -> list:
    """A key line of a section (its words in ``section``): a boolean setting as its verdict,
    any other with the section's words first."""
    if len(line) >= 3 and line[-2].word == ":" and line[-1].word in _TRUE | _FALSE:  # "hard: true" ("=" is no token)
        line = [*line[:-2], line[-1]]
    key, value = line[-2], line[-1]
    if value.word not in _TRUE | _FALSE or not re.fullmatch(r"[ \t]*[:=][ \t]*", text[key.end : value.start]):
        return section + line
    path = [t for t in (*section, *line[:-2]) if t.word not in _GROUPING]
    if key.word in ("hard", "strict", "mandatory"):  # the line before is a rule, or a wish
        return [make("hard" if value.word in _TRUE else "soft", key.start, value.end)]
    if not path:
        return line
    negated = [make("not", value.start, value.end)] if value.word in _FALSE else []
    if key.word in _PLACE_KEYS:  # "[road] on = false": "not on road"
        return [*negated, key, *path]
    return [*path, *negated, key]  # "[layers.building] traversable = false": "building not traversable"
