"""Rules written as data: XML elements, JSON's quoted keys, CSV rows under a header and
tick-box tables read as the sentences they stand for.

    <clearance class="water" min_m="12" strict="true"/>   ->  clearance water min_m=12 hard .
    {"building": {"clearance_m": 8, "hard": true}}         ->  {building: {clearance_m: 8, hard}}
    class,min_clearance_m,enforcement                      ->  (the header: no rule)
    building,7,advisory                                    ->  building : min clearance 7 m advisory
    | class | ok | avoid | never |                          ->  (the header: no rule)
    | water |    |       |   x   |                          ->  water : never

:func:`markup` rewrites the text (length preserved, so every token still quotes the prompt);
:func:`tabulated` rewrites a row's tokens, putting the header's words where the row's values
are, since a row alone says nothing; each carries the span of the cell it reads, so a rule
quotes its row. Written by hand because a parser of
XML, JSON or CSV wants a whole well-formed document, and a brief is a fragment among prose.
"""

from __future__ import annotations

import re
from bisect import bisect_right
from collections.abc import Callable

from overseec_core.interpret import lexicon as lx

#: An XML tag with its attributes ("<clearance class=\"water\" min_m=\"12\"/>", "</rules>").
_TAG = re.compile(r"<(/?)([^\W\d][\w:.-]*)((?:[ \t]+[\w:.-]+[ \t]*=[ \t]*(?:\"[^\"<>]*\"|'[^'<>]*'))*)[ \t]*(/?)>")
#: One attribute of a tag: its name, its quoted value.
_ATTRIBUTE = re.compile(r"([\w:.-]+)[ \t]*=[ \t]*([\"'])([^\"'<>]*)\2")
#: Attributes that name the thing a rule is about: their value is the subject ("class=\"water\"").
_SUBJECT_KEYS = frozenset({"class", "name", "layer", "entity", "type", "id", "target", "feature", "of", "terrain"})
#: Tag names that only group rules, never state one ("<rules>", "<layer name=...>").
_GROUPING_TAGS = frozenset({"rules", "rule", "costmap", "config", "layers", "layer", "classes", "class", "item"})
#: Keys whose boolean value says how strict the rule is ("strict=\"true\"", "\"hard\": false").
_STRICT_VALUE = re.compile(
    r"(?i)(?<![\w.])(strict|hard|mandatory)[\"']?[ \t]*[:=][ \t]*[\"']?(true|false|yes|no)\b[\"']?"
)
#: A keyword argument saying how strict a rule is, as Lisp writes it ("(clearance water 12
#: :strict nil)"; ``t`` is true, ``nil`` false).
_KEYWORD_STRICT = re.compile(r"(?i)(?<![\w:]):(strict|hard|mandatory)[ \t]+(t|nil|true|false|yes|no)\b")
#: A short quoted name as JSON writes keys and values ("\"building\":", ": \"lethal\"").
_QUOTED_KEY = re.compile(r"\"([^\W\d][\w .-]{0,40})\"(?=[ \t]*:)|(?<=:)([ \t]*)\"([^\W\d][\w .-]{0,40})\"")


#: A quoted key that names what a rule is about, with its colon ("\"class\": \"railway\"",
#: "'layer': 'water'"): the value alone is the subject.
_SUBJECT_PAIR = re.compile(r"(?i)([\"'])(?:" + "|".join(sorted(_SUBJECT_KEYS)) + r")\1[ \t]*:[ \t]*(?=[\"'][^\W\d])")


#: A word that only names the record after it ("rule { class: \"trail\" ... }", "layer {").
_RECORD_NAME = re.compile(r"(?i)(?<![\w\"'])(?:rules?|items?|entry|entries|layers?|config|message|block)[ \t]*(?=\{)")
#: A subject key written bare before a quoted value, as protobuf's text format writes it
#: ("class: \"water\""): the value alone is the subject.
_BARE_SUBJECT = re.compile(r"(?i)(?<![\w\"'])(?:" + "|".join(sorted(_SUBJECT_KEYS)) + r")[ \t]*:[ \t]*(?=[\"'][^\W\d])")


def markup(text: str) -> str:
    """XML tags read as their words and JSON's quotes blanked (see the module's examples), a
    quoted subject key blank before its value; length preserved. Text with no tag and no quoted
    key is returned as written."""
    text = _RECORD_NAME.sub(lambda m: " " * len(m.group()), text)
    text = _RECORD.sub(_one_record, _TAG.sub(_tag, text))
    text = _SUBJECT_PAIR.sub(lambda m: " " * len(m.group()), text)
    text = _STRICT_VALUE.sub(lambda m: _strictness(m) if _inline(text, m.start()) else m.group(), text)
    text = _KEYWORD_STRICT.sub(_strictness, text)
    return _QUOTED_KEY.sub(_unquoted, text)


#: An object with no object inside it ("{\"class\": \"railway\", \"min_m\": 15}").
_RECORD = re.compile(r"\{[^{}]*\}")


def _one_record(m: re.Match) -> str:
    """An object about one subject (a subject key in it: "{\"class\": \"railway\", \"min_m\":
    15, \"strict\": true}", protobuf's "{ class: \"tree\" effect: ATTRACT }") read as one
    clause: its commas and line breaks blank, a bare subject key too. An object of several
    names ("{\"trail\": \"good\", \"water\": \"no\"}") keeps them."""
    record = m.group()
    if _BARE_SUBJECT.search(record):
        record = _BARE_SUBJECT.sub(lambda k: " " * len(k.group()), record)
    elif not _SUBJECT_PAIR.search(record):
        return record
    return record.replace(",", " ").replace("\n", " ")


def _inline(text: str, k: int) -> bool:
    """Whether something stands before ``k`` on its line: a key line of its own ("hard = true"
    under "[standoff.water]") is the section's, read by :mod:`config_lines`."""
    return bool(text[text.rfind("\n", 0, k) + 1 : k].strip())


def _strictness(m: re.Match) -> str:
    word = "hard" if m.group(2).lower() in ("true", "yes", "t") else "soft"
    return word + " " * (len(m.group()) - len(word))


def _unquoted(m: re.Match) -> str:
    """ "\"building\":" as " building :", ": \"lethal\"" as ":  lethal "."""
    if m.group(1) is not None:
        return " " + m.group(1) + " "
    return m.group(2) + " " + m.group(3) + " "


def _tag(m: re.Match) -> str:
    """One tag as words in place: its brackets blank, a grouping tag's name ("<rules>",
    "</costmap>") blank, a subject's value alone ("class=\"water\"": "water"), a strictness
    its word ("strict=\"true\"": "hard"), any other attribute ``key=value`` unquoted; an
    element's end a sentence end. Every word stays where it was written."""
    closing, name, empty = m.group(1), m.group(2), m.group(4)
    out = [" "] * len(m.group())
    if not closing and name.lower() not in _GROUPING_TAGS:
        at = m.start(2) - m.start()
        out[at : at + len(name)] = name
    base = m.start(3) - m.start()
    for a in _ATTRIBUTE.finditer(m.group(3)):
        key, value = a.group(1).lower(), a.group(3)
        if key in ("strict", "hard", "mandatory") and value.lower() in ("true", "false", "yes", "no"):
            word = "hard" if value.lower() in ("true", "yes") else "soft"
            out[base + a.start() : base + a.start() + len(word)] = word
            continue
        if key not in _SUBJECT_KEYS:
            out[base + a.start(1) : base + a.end(1)] = a.group(1)
            out[base + a.end(1) : base + a.start(2)] = "=" + " " * (a.start(2) - a.end(1) - 1)
        out[base + a.start(3) : base + a.end(3)] = value
    if m.group(3) or empty or (closing and name.lower() not in _GROUPING_TAGS):
        out[-1] = "."
    return "".join(out)


#: The first column's name of a table of rules: the thing each row is about.
_KEY_COLUMNS = frozenset(
    "class classes layer entity terrain surface feature name type zone label category landcover item object "
    "hazard area".split()
)
#: A ticked cell of a tick-box table.
_TICKS = frozenset({"x", "✓", "✔", "✅", "yes", "y", "*", "•", "●"})
#: A CSV field separator.
_SEPARATORS = (",", ";", "\t")


def tabulated(toks: list, text: str, make: Callable[[str, int, int], object]) -> list:
    """``toks`` with each CSV row under a header and each tick-box row read with its header's
    words (see the module's examples); the header lines' tokens dropped. ``make(word, start,
    end)`` builds a token; ``toks`` carry ``word``, ``start`` and ``end`` into ``text``."""
    rows = {**_csv_rows(text), **_tick_rows(text)}
    if not rows:
        return toks
    starts = [0] + [m.end() for m in re.finditer("\n", text)]
    out: list = []
    done: set[int] = set()
    for t in toks:
        line = bisect_right(starts, t.start) - 1
        if t.word == "\n" or line not in rows:
            out.append(t)
        elif line not in done:
            done.add(line)
            out.extend(rows[line](toks, make))
    return out


#: Words that are no name a record's verdict key could follow.
_GRAMMAR = frozenset(lx.VERDICT_COLUMNS | lx.VOCAB)


def nested_verdicts(toks: list) -> list:
    """ "{trail: {cost: preferred}}", "trail: cost: preferred" and a record's "trail rating:
    preferred" read "trail : preferred": a verdict key between a name and its value
    (:data:`lexicon.VERDICT_COLUMNS`) is dropped."""
    out: list = []
    dropped = False
    for i, t in enumerate(toks):
        key = t.word in lx.VERDICT_COLUMNS and i + 1 < len(toks) and toks[i + 1].word == ":"
        if key and len(out) >= 2 and out[-1].word == ":" and out[-2].word[0].isalpha():
            dropped = True  # "trail : cost : preferred": the key and its colon
            continue
        if key and out and out[-1].word[0].isalpha() and out[-1].word not in _GRAMMAR:
            continue  # "{name: trail, rating: preferred}" read "trail rating : preferred": the key
        if not (dropped and t.word == ":"):  # the dropped key's own colon
            out.append(t)
        dropped = False
    return out


Span = tuple[int, int]


def _lines(text: str) -> list[tuple[int, str]]:
    """Each line with its start offset."""
    out, at = [], 0
    for ln in text.split("\n"):
        out.append((at, ln))
        at += len(ln) + 1
    return out


def _cells(at: int, line: str, sep: str) -> list[Span]:
    """The spans of a line's cells split at ``sep`` (a table's outer pipes dropped)."""
    spans, start = [], at
    for k, ch in enumerate(line + sep):
        if ch == sep:
            spans.append((start, at + k))
            start = at + k + 1
    return spans


def _words_in(toks: list, span: Span) -> list:
    """The tokens inside a span that are words or numbers, no marks."""
    return [t for t in toks if span[0] <= t.start and t.end <= span[1] and (t.word[0].isalnum() or t.word in _TICKS)]


def _is_name(cell: str) -> bool:
    return re.fullmatch(r"[ \t]*[^\W\d][\w .-]*[ \t]*", cell) is not None


def _csv_rows(text: str) -> dict[int, Callable]:
    """Line index -> a reader of that line's tokens, for each CSV block: a header of column
    names whose first is a key column ("class,min_clearance_m,enforcement"), then rows with as
    many cells; the header line reads as nothing."""
    lines = _lines(text)
    found: dict[int, Callable] = {}
    for i, (at, ln) in enumerate(lines):
        sep = next((s for s in _SEPARATORS if ln.count(s) >= 1), None)
        if sep is None or i in found or "|" in ln:
            continue
        heads = _cells(at, ln, sep)
        names = [text[a:b] for a, b in heads]
        if not all(_is_name(n) for n in names) or names[0].strip().lower() not in _KEY_COLUMNS:
            continue
        body = []
        for j in range(i + 1, len(lines)):
            if lines[j][1].count(sep) != len(heads) - 1 or not lines[j][1].strip():
                break
            body.append(j)
        if not body:
            continue
        found[i] = lambda toks, make: []
        for j in body:
            found[j] = _row_reader(heads, _cells(lines[j][0], lines[j][1], sep), text)
    return found


def _row_reader(heads: list[Span], cells: list[Span], text: str) -> Callable:
    """A reader of one CSV row: "building : min clearance 7 m advisory" for "building,7,advisory"
    under "class,min_clearance_m,enforcement"."""

    def read(toks: list, make: Callable) -> list:
        subject = _words_in(toks, cells[0])
        if not subject:
            return []
        out = [*subject, make(":", cells[0][1], cells[0][1] + 1)]
        for head, cell in zip(heads[1:], cells[1:]):
            values, names = _words_in(toks, cell), _words_in(toks, head)
            if not values:
                continue
            names = [make(n.word, cell[0], cell[1]) for n in names]  # quoting the row, not the header
            if text[head[0] : head[1]].strip().lower() in lx.VERDICT_COLUMNS:
                out.extend(values)
            elif names and names[-1].word in lx.UNITS and values[0].word[0].isdigit():  # "min_clearance_m": 7 m
                out.extend([*names[:-1], *values, names[-1]])
            else:
                out.extend([*names, *values])
        return out

    return read


def _tick_rows(text: str) -> dict[int, Callable]:
    """Line index -> a reader of that line's tokens, for a tick-box table: a header row of a key
    column and verdict columns ("| class | ok | avoid | never |"), then rows whose other cells
    are ticks or blank ("| water | | | x |"), read "water : never"; the header and rule lines
    read as nothing. Needs two ticked rows."""
    lines = _lines(text)
    tables = [(i, at, ln) for i, (at, ln) in enumerate(lines) if ln.count("|") >= 2]
    for k, (i, at, ln) in enumerate(tables):
        heads = _pipe_cells(at, ln)
        if len(heads) < 3 or not all(_is_name(text[a:b]) for a, b in heads):
            continue
        if text[heads[0][0] : heads[0][1]].strip().lower() not in _KEY_COLUMNS:
            continue
        found: dict[int, Callable] = {i: lambda toks, make: []}
        ticks = 0
        for j, jat, jln in tables[k + 1 :]:
            cells = _pipe_cells(jat, jln)
            marks = [text[a:b].strip().lower() for a, b in cells[1:]]
            if re.fullmatch(r"[\s|:\-+]*", jln):
                found[j] = lambda toks, make: []
            elif len(cells) == len(heads) and all(c in _TICKS or not c for c in marks) and any(marks):
                ticked = [(h, cell) for h, cell, c in zip(heads[1:], cells[1:], marks) if c]
                found[j] = _tick_reader(cells[0], ticked)
                ticks += 1
            else:
                break
        if ticks >= 2:
            return found
    return {}


def _pipe_cells(at: int, line: str) -> list[Span]:
    """A pipe table row's cells, the outer pipes dropped."""
    spans = _cells(at, line, "|")
    if spans and not line[: spans[0][1] - at].strip():
        spans = spans[1:]
    if spans and not line[spans[-1][0] - at :].strip():
        spans = spans[:-1]
    return spans


def _tick_reader(subject: Span, ticked: list[tuple[Span, Span]]) -> Callable:
    """A reader of one tick-box row: its subject, ":", the ticked columns' names."""

    def read(toks: list, make: Callable) -> list:
        words = _words_in(toks, subject)
        if not words:
            return []
        out = [*words, make(":", subject[1], subject[1] + 1)]
        for head, tick in ticked:
            out.extend(make(t.word, tick[0], tick[1]) for t in _words_in(toks, head))
        return out

    return read
