"""Normalising a mission prompt's text before it is tokenized: notations written out as the
words they stand for, with every character kept where it was, so each token's span quotes the
original prompt.

The first step of :func:`overseec_core.interpret.tokens.tokenize`: settings written
``key=value`` and snake_case keys, a ranking's label and list as ``>`` steps, numbered lists and
ordinals, tables and checklist leaders, bracketed asides and glosses, functions of a layer, rule
labels, telegram STOPs, clock times, decimal commas (XML, JSON and tick-box notations are
:mod:`overseec_core.interpret.markup`'s). Every rewrite preserves length.
"""

from __future__ import annotations

import re

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.markup import markup

#: A setting written key=value ("rail=lethal", "veg=ok"): the "=" is a colon.
_SETTING = re.compile(r"(?<=[^\W\d_])=(?=[^\W\d_])")
#: The gap before the next setting on a line ("rail=lethal  veg=ok"): a sentence end.
_NEXT_SETTING = re.compile(r"(?<=\S)[ \t]+(?=[^\W\d_][\w]*=[^\W\d_])")
#: A dot inside a word ("building.standoff", "surface.primary"): a space, not a sentence end.
_INNER_DOT = re.compile(r"(?<=[^\W\d_])\.(?=[^\W\d_])")


#: A setting whose key carries the unit ("min_m = 6", "soft_buffer_ft: 20"): the unit moves
#: after the number.
_UNIT_KEY = re.compile(r"(?i)_(m|ft|yd|km|metres|meters|feet|yards)([ \t]*[:=][ \t]*)(\d+(?:\.\d+)?)")


def _unit_keys(text: str) -> str:
    """ "clearance.building.min_m = 6" reads as "... min = 6 m": the unit a key carries stands
    after the number; length preserved."""
    return _UNIT_KEY.sub(lambda m: m.group(2) + m.group(3) + " " + m.group(1), text)


#: A numbered label before a rule ("Condition 4.2:", "RULE 3.2:", "Permit condition 7:", "R1:"):
#: the rule's name, never terrain.
_RULE_LABEL = re.compile(
    r"(?im)(?:^|(?<=[.;!?\n]))([ \t]*(?:permit[ \t]+)?(?:condition|rule|clause|item|requirement|constraint|"
    r"note|section|article|paragraph|para|§|r|c)[ \t]*\d+(?:\.\d+)*[ \t]*[:)\-.])"
)


#: A sub-clause's label at the start of its line ("1.a The rover shall ...", "3.b)", "2.c:").
_SUB_LABEL = re.compile(r"(?im)^([ \t]*\d{1,2}(?:\.\d{1,2})*\.[a-z]\b[.):]?)(?=[ \t])")


#: A rule's label in words at the start of a sentence ("Rule one, stay on the trail. Rule two,
#: ..."), its number spelt out, or a letter and a number ("Course rule C-4:").
_WORD_RULE_LABEL = re.compile(
    r"(?im)(?:^|(?<=[.;!?\n]))([ \t]*(?:\w+[ \t]+)?(?:rule|step|item|point|condition)[ \t]+"
    r"(?:one|two|three|four|five|six|seven|eight|nine|ten|[a-z]-?\d+)[ \t]*[,:.)\-])"
)
#: Dot leaders of a checklist ("WATER ........ NO-GO", "Roads ..... preferred ..... check"):
#: the run of dots is the colon between item and value; a closing "check" ticks the line.
_LEADERS = re.compile(r"(?<=\S)([ \t]*\.{3,}[ \t]*)(?=\S)")
_TICK = re.compile(r"(?i):([ \t]*(?:check|checked|done|ok)\b)")


def _leaders(text: str) -> str:
    """A checklist's dot leaders as colons and its closing ticks blank; length preserved."""
    if not _LEADERS.search(text):
        return text
    text = _LEADERS.sub(lambda m: ":" + " " * (len(m.group(1)) - 1), text)
    return _TICK.sub(lambda m: " " + " " * len(m.group(1)), text)


def _rule_labels(text: str) -> str:
    """A rule's numbered label blanked ("Condition 4.2: no plant within 30 m of the water", "1.a
    The rover shall avoid water"); length preserved."""
    text = _SUB_LABEL.sub(lambda m: " " * len(m.group(1)), text)
    text = _WORD_RULE_LABEL.sub(lambda m: " " * len(m.group(1)), text)
    return _RULE_LABEL.sub(lambda m: " " * len(m.group(1)), text)


#: A configuration line that only says how strict the setting before it is ("railway_strict =
#: yes", "road.hard: false"): read as a line "hard" or "soft" (:func:`overseec_core.interpret.
#: rules.rule_only` applies it to the distance line before).
_STRICT_KEY = re.compile(
    r"(?im)^([ \t]*[a-z][\w.]*?[_.](?:strict|hard|mandatory)[ \t]*[:=][ \t]*(yes|no|true|false|on|off))[ \t]*$"
)
#: A configuration's section header alone on its line ("[standoff]"): a label, no rule.
_SECTION = re.compile(r"(?m)^([ \t]*\[[^\W\d][\w .-]*\])[ \t]*$")
#: A configuration file's name alone on its line ("# agv.toml", "costs.yaml:"): a label, no rule.
_FILE_NAME = re.compile(r"(?im)^([ \t]*(?:#|//)?[ \t]*[\w-]+\.(?:toml|ya?ml|ini|json|cfg|conf)[ \t]*:?)[ \t]*$")
#: "road_m = 4" once its unit is after the number ("road = 4 m"): the spaced "=" of a setting.
_SPACED_SETTING = re.compile(r"(?m)^([ \t]*[^\W\d][\w.]*[ \t]+)=(?=[ \t]*\d)")


#: The underscore of a snake_case key between two letters ("proximity_penalty", "side_offset").
_SNAKE = re.compile(r"(?<=[^\W\d_])_(?=[^\W\d_])")


#: A key saying the route is not on something ("on_track=False", "on_trail: no"): off it.
_OFF_KEY = re.compile(r"(?i)\bon_([^\W\d_]+)([\"']?[ \t]*[:=][ \t]*(?:false|no|0))\b")


def _off_key(m: re.Match) -> str:
    """ "on_track=False" as "off track" (length kept: the key's "on_" and value make room)."""
    return "off " + m.group(1) + " " * (len(m.group(2)) - 1)


def _strictness(m: re.Match) -> str:
    word = "hard" if m.group(2).lower() in ("yes", "true", "on") else "soft"
    return word + " " * (len(m.group(1)) - len(word))


def _settings(text: str) -> str:
    """Lines of ``key=value`` settings as colon statements, one per sentence ("road = 4 m" too);
    dotted keys as words; a strictness key ("railway_strict = yes") as "hard" or "soft", a
    section header ("[standoff]") and a file name ("# agv.toml") blank; length preserved."""
    text = _STRICT_KEY.sub(_strictness, text)
    text = _SECTION.sub(lambda m: " " * len(m.group(1)), text)
    text = _FILE_NAME.sub(lambda m: " " * len(m.group(1)), text)
    text = _SPACED_SETTING.sub(lambda m: m.group(1) + ":", text)
    text = _OFF_KEY.sub(_off_key, text)  # "on_track=False": "off track"
    text = _SNAKE.sub(" ", text)  # "proximity_penalty: railway", "side_offset": words
    if len(_SETTING.findall(text)) >= 2:
        text = _NEXT_SETTING.sub(lambda m: ";" + m.group()[1:], text)
    text = _SETTING.sub(":", text)
    return _INNER_DOT.sub(" ", text)


#: A ranking's label and its list: "order of preference (best first): trail, road, grass",
#: "prefs: A; B; C" (up to the end of the sentence or line). A list worst first is left alone:
#: its steps cannot be turned round in place.
_RANKING = re.compile(
    r"(?im)(?:^|(?<=[.!?\n]))[ \t]*((?:(?:order|list) of (?:preference|priority)|(?:\w+[ \t]+)?preference order"
    r"|priority order|rankings?|ranked|(?:\w+[ \t]+)?preferences?|prefs?|priorities)"
    r"(?:[ \t]*[,(]?[ \t]*(?:best[ \t]+first|most[ \t]+preferred[ \t]+first|in[ \t]+(?:descending[ \t]+)?order"
    r"|descending)[ \t]*\)?)?"
    r"|best[ \t]+first|in[ \t]+descending[ \t]+order)[ \t]*:([^.!?\n]*)"
)
#: Words that make a list after a ranking label something else than a plain ranking.
_NOT_RANKED = re.compile(r"(?i)\b(then|except|but|not|no|avoid|excluded|never)\b")


#: A ranking's label alone on its line, its list on the lines below ("Priorities:\n1. road").
_LABEL_LINE = re.compile(
    r"(?im)^([ \t]*(?:priorities|preferences|prefs|rankings?|order of (?:preference|priority)|priority order)"
    r"[ \t]*:)[ \t]*$(?=\n[ \t]*(?:[-*\u2022][ \t]*)?\d{1,2}[.)])"
)


def _rankings(text: str) -> str:
    """A ranking's label blanked and its list's separators written as ``>``, so "order of
    preference: trail, road, grass" reads as "trail > road > grass"; length preserved. A list
    with other words in it ("priority: road, then trail") is left as written."""

    def rank(m: re.Match) -> str:
        label, items = m.group(1), m.group(2)
        parts = [p for p in re.split(r"[,;>]", items) if p.strip()]  # ">": a numbered list read already
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


#: A numbered list's marker ("1.", "2)", "3 -") at the start of the text, of a line, or after a space.
_NUMBERED = re.compile(r"(?m)(?:^|(?<=\s))[ \t]*\(?(\d{1,2})[.)][ \t]+")


#: An ordinal rank before its item ("1st choice: trail", "2nd: grass", "third option - road",
#: "last choice: road"): the choice noun optional, a colon, "=" or dash after it.
_ORDINAL = re.compile(
    r"(?im)(?:^|(?<=[\s.;,]))[ \t]*(?:(\d{1,2})(?:st|nd|rd|th)|(first|second|third|fourth|fifth|last))"
    r"(?:[ \t]+(?:choice|option|pick|preference|priority))?[ \t]*[:=\-][ \t]*"
)
_ORDINAL_WORDS = {"first": 1, "second": 2, "third": 3, "fourth": 4, "fifth": 5}


def _ordinal_marks(text: str) -> list[re.Match]:
    """The ordinal ranks of a ranking written "1st: trail. 2nd: grass. last choice: road",
    ranked 1, 2, 3 ... in order, a "last" only at the end; [] when the text has no such run."""
    marks = list(_ORDINAL.finditer(text))
    ranks = [int(m.group(1)) if m.group(1) else _ORDINAL_WORDS.get(m.group(2).lower(), 0) for m in marks]
    if (
        len(marks) < 2
        or any(r == 0 for r in ranks[:-1])
        or ranks[: len(ranks) - (ranks[-1] == 0)] != list(range(1, len(ranks) + 1 - (ranks[-1] == 0)))
    ):
        return []
    return marks


def _numbered_rankings(text: str) -> str:
    """A numbered list of short names ("1. road  2. open ground  3. vegetation", one per line or
    on one line; or ranked by ordinals, "1st choice: trail. 2nd: grass. last choice: road") read
    as a ranking, best first: its markers become ``>`` steps ("road > open ground > vegetation");
    length preserved. A list of instructions ("1. stay on the road 2.
    avoid the water") or one not numbered 1, 2, 3 ... is left as written. A ranking's label
    alone on its line above the list ("Priorities:") is blanked."""
    text = _LABEL_LINE.sub(lambda m: " " * len(m.group(1)), text)
    marks = list(_NUMBERED.finditer(text))
    if len(marks) < 2 or [int(m.group(1)) for m in marks] != list(range(1, len(marks) + 1)):
        marks = _ordinal_marks(text)
        if not marks:
            return text
    items = [text[m.end() : nxt.start() if nxt else len(text)] for m, nxt in zip(marks, [*marks[1:], None])]
    last = re.match(r"[^.!?;\n]*", items[-1])
    items[-1] = last.group() if last else items[-1]
    if any(not it.strip() or len(it.split()) > 3 or _NOT_RANKED.search(it) for it in items):
        return text
    out = list(text)
    for k, m in enumerate(marks):
        span = range(m.start(), m.end())
        for i in span:
            out[i] = " "
        if k:  # the step between two items; a line break between them too
            out[m.start()] = ">"
            j = m.start() - 1
            while j >= 0 and text[j] in " \t\r\n.,;-*\u2022":  # a bullet's mark too ("- 2. grass")
                out[j] = " "
                j -= 1
    return "".join(out)


#: A bracketed aside that is a sentence of its own: three words or more, no number, a verb of
#: state in it ("(crowns are high, rover fits under)", "(sim run, collisions disabled)"); a
#: bracketed qualifier ("(unpaved)", "(best first)", "(at least 10 m)", "(penalty only,
#: passable)") is not one: it is read with the rule it stands by.
_ASIDE = re.compile(r"\(([^()\d]*)\)")
_ASIDE_VERBS = re.compile(r"(?i)\b(?:is|are|was|were|fits?|has|have|had|disabled|enabled)\b")


_UNIT_ALT = "|".join(sorted((re.escape(u) for u in lx.UNITS), key=len, reverse=True))
_FIGURE = r"\d+(?:[.,]\d+)?[ \t]*(?:" + _UNIT_ALT + r")\b\.?"
#: A distance glossed in another unit in brackets ("4 m (roughly 13 ft)", "15 ft (4.5 m)"):
#: the gloss echoes the figure before it.
_GLOSS = re.compile(
    r"(?i)(?<="
    + r"[a-z.])([ \t]*\([ \t]*(?:(?:"
    + "|".join(re.escape(a) for a in sorted(lx.APPROXIMATORS))
    + r"|ca\.?|"
    r"i\.e\.|or|that's|that is|=|≈)[ \t]*)?" + _FIGURE + r"[ \t]*\))"
)


#: A decimal comma in a distance ("2,5 m", "1,5 metres"): one or two digits after it, then a unit.
_DECIMAL_COMMA = re.compile(r"(?i)(?<=\d),(?=\d{1,2}[ \t]*(?:" + _UNIT_ALT + r")\b)")


def _glosses(text: str) -> str:
    """A distance's bracketed gloss in another unit blanked ("hold 4 m (roughly 13 ft) off"):
    the figure stated first is the one meant, and the echo would be read as a second figure;
    length preserved."""
    return _GLOSS.sub(lambda m: " " * len(m.group(1)) if _FIGURE_BEFORE.search(text, 0, m.start()) else m.group(), text)


#: A distance ending right where a gloss starts.
_FIGURE_BEFORE = re.compile(r"(?i)" + _FIGURE.replace(r"\b\.?", r"\.?") + r"$")


def _asides(text: str) -> str:
    """A bracketed aside's brackets written as sentence ends, so the explanation ("tree:
    ALLOWED (crowns are high, rover fits under)") is read on its own and never runs into the
    rule beside it; length preserved."""

    def aside(m: re.Match) -> str:
        inner = m.group(1)
        if len(inner.split()) < 3 or not _ASIDE_VERBS.search(inner):
            return m.group()
        return "." + inner + "."

    return _ASIDE.sub(aside, text)


#: A function of one layer written as a programmer writes it ("cost(trail)", "dist(path,
#: building)", "distance(route, water)"): its argument is the layer.
_FUNCTION = re.compile(
    r"(?i)\b(?:dist|distance|d|cost|price|penalty|c)[ \t]*\([ \t]*"
    r"(?:(?:path|route|robot|rover|vehicle|p|x)[ \t]*,[ \t]*)?([^(),\n]+?)[ \t]*\)"
)


def _functions(text: str) -> str:
    """ "cost(trail) < cost(grass)" reads as "trail < grass", "dist(path, building) >= 25 yd" as
    "building >= 25 yd": the function's name and brackets blanked, its layer kept; length
    preserved."""

    def blank(m: re.Match) -> str:
        inner = m.start(1) - m.start()
        return " " * inner + m.group(1) + " " * (m.end() - m.end(1))

    def line(text: str) -> str:
        costs = [m for m in _FUNCTION.finditer(text) if not m.group().lower().startswith("d")]
        text = _FUNCTION.sub(blank, text)
        if len(costs) >= 2:  # "cost(A) < cost(B)": A is the cheaper, "A > B" as a ranking writes it
            text = text.translate(_TURNED)
        return text

    return "".join(line(part) for part in text.splitlines(keepends=True))


#: The signs of a comparison of costs turned round into a ranking's.
_TURNED = str.maketrans({"<": ">", ">": "<", "≤": "≥", "≥": "≤", "≫": "<", "≪": ">"})


#: A table's rule line ("|---|:---:|", "----+----"): no cells.
_TABLE_RULE = re.compile(r"^[\s|+:\-]*-[\s|+:\-]*$")
#: Header cells of a table of verdicts ("surface | cost", "terrain | rule", "class | rule | distance").
_TABLE_HEADS = frozenset(
    "cost costs weight weights penalty price value rule rules verdict status preference rating score class "
    "terrain surface layer entity type kind distance distances buffer clearance range note notes action name "
    "feature".split()
)
#: A cell that says nothing ("-", "n/a"): blank in the row read.
_EMPTY_CELLS = frozenset({"-", "--", "\u2013", "\u2014", "n/a", "na", "none", ""})


def _tables(text: str) -> str:
    """A table of verdicts ("surface | cost", "asphalt | 1", "ice | do not enter"; a third
    column of distances, "| water | keep out | 10 m |"; markdown's outer pipes and rule lines
    too) read row by row as "name: verdict ...": the first inner pipe is a colon, the others
    and the empty cells ("-") blanks, the outer pipes, rule lines and a header row of column
    names blanks; length preserved. Text with fewer than two such rows is left as written."""
    lines = text.splitlines(keepends=True)
    cells = [[c for c in ln.strip().strip("|").split("|")] for ln in lines]
    rows = [
        i
        for i, c in enumerate(cells)
        if len(c) >= 2 and c[0].strip() and c[1].strip() and "|" in lines[i] and not _TABLE_RULE.match(lines[i])
    ]
    if len(rows) < 2:
        return text
    out = []
    for i, ln in enumerate(lines):
        if _TABLE_RULE.match(ln) and "-" in ln and "|" in ln:
            out.append("".join(ch if ch in "\r\n" else " " for ch in ln))
        elif i in rows and all(x.strip().lower() in _TABLE_HEADS for x in cells[i]):
            out.append("".join(ch if ch in "\r\n" else " " for ch in ln))
        elif i in rows:
            out.append(_table_row(ln))
        else:
            out.append(ln)
    return "".join(out)


def _table_row(ln: str) -> str:
    """One row of a table as "name: verdict ..." (see :func:`_tables`); length preserved."""
    body = ln.rstrip("\r\n")
    lead, trail = len(body) - len(body.lstrip()), len(body.rstrip())
    inner = list(body[lead:trail])
    if inner and inner[0] == "|":
        inner[0] = " "
    if len(inner) > 1 and inner[-1] == "|":
        inner[-1] = " "
    pipes = [k for k, ch in enumerate(inner) if ch == "|"]
    bounds = [-1, *pipes, len(inner)]
    for a, b in zip(bounds, bounds[1:]):
        if "".join(inner[a + 1 : b]).strip().lower() in _EMPTY_CELLS:
            inner[a + 1 : b] = [" "] * (b - a - 1)
    for n, k in enumerate(pipes):
        inner[k] = ":" if n == 0 else " "
    return body[:lead] + "".join(inner) + body[trail:] + ln[len(body) :]


#: A telegram's sentence end ("AVOID TREES STOP NO CONCERN BEYOND FIFTEEN METRES STOP").
_TELEGRAM_STOP = re.compile(r"\bSTOP\b")


def _telegram(text: str) -> str:
    """A telegram's "STOP"s as full stops, where the text is written in capitals and says STOP
    twice or more (a plain "stop at the gate" keeps its verb); length preserved."""
    letters = [c for c in text if c.isalpha()]
    if len(_TELEGRAM_STOP.findall(text)) < 2 or sum(c.isupper() for c in letters) < 0.8 * len(letters):
        return text
    return _TELEGRAM_STOP.sub(".   ", text)


#: A label at a line's start before a colon ("Lee: dirt's ok", "@sam: no"): a chat's speaker
#: where it names no terrain and no wording, and the chat names two speakers, one of them twice.
_SPEAKER = re.compile(r"(?m)^([ \t]*)(@?[A-Za-z][\w.-]{0,20})([ \t]*):")


def _speakers(text: str) -> str:
    """A chat's speaker labels blanked ("Lee: dirt roads ok?\nKim: ...\nLee: thanks"); a label
    that names terrain or is wording ("Water: avoid", "Note: ...") is no speaker; length preserved."""
    found = [m for m in _SPEAKER.finditer(text) if _speaker_name(m.group(2))]
    names = [m.group(2).lower() for m in found]
    at = any(n.startswith("@") for n in names)
    if not found or not at and (len(set(names)) < 2 or len(set(names)) == len(names)):
        return text
    out = list(text)
    for m in found:
        out[m.start(2) : m.end()] = " " * (m.end() - m.start(2))
    return "".join(out)


def _speaker_name(label: str) -> bool:
    """Whether a line's label can be a person's name: "@" before it, or a capitalised word that
    is no entity, no wording and no misspelling of either."""
    if label.startswith("@"):
        return True
    word = label.lower()
    if not label[0].isupper() or not word.isalpha():
        return False
    known = (word,) in lx.SURFACE or word in lx.VOCAB or word in lx.FILLER or word in lx.NON_TERRAIN
    return not known and lx.correct_spelling(word) is None


#: An arrow between two items ("road → trail", "road -> trail", "road => trail").
_ARROW = re.compile(r"[ \t]*(?:\u2192|->|=>)[ \t]*")


def _arrow_chains(text: str) -> str:
    """A line of three or more short items joined by arrows ("road → trail → grass → trees")
    is a ranking, best first: its arrows are ``>`` steps (one arrow stays a colon: "bldgs ->
    keep well away"); the last item may carry a bracketed qualifier; length preserved."""
    out = []
    for line in text.splitlines(keepends=True):
        parts = _ARROW.split(line.rstrip("\r\n"))
        items = [re.sub(r"\([^()]*\)\s*$", "", p) for p in parts]  # "trees (only if stuck)"
        if len(parts) >= 3 and all(0 < len(p.split()) <= 3 for p in items):
            line = _ARROW.sub(lambda m: m.group().replace("\u2192", ">").replace("->", " >").replace("=>", " >"), line)
        out.append(line)
    return "".join(out)


#: The colon of a clock time ("between 02:00 and 04:00"): no mark between a topic and its rule.
_TIME_COLON = re.compile(r"(?:(?<=\b\d)|(?<=\b\d\d)):(?=\d\d\b)")


def normalise(text: str) -> str:
    """Lower-case, straight apostrophes, hyphens between letters as spaces, arrows ("->", "=>")
    as colons, ``key=value`` settings as colon statements, dots inside words as spaces, a
    ranking's list as ``>`` steps (:func:`_rankings`, :func:`_numbered_rankings`); length preserved."""
    out = []
    text = _speakers(_telegram(_TIME_COLON.sub("h", text)))  # "02:00" is one time, "02h00"
    text = _DECIMAL_COMMA.sub(".", text)  # "2,5 m" is 2.5 m
    text = _settings(_unit_keys(_functions(_rule_labels(_tables(_leaders(markup(text)))))))
    text = _asides(_glosses(_rankings(_numbered_rankings(_arrow_chains(text)))))
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
