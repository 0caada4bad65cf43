"""Tokens of a mission prompt: normalising, tokenizing and splitting into sentences.

The first step of the offline interpreter (:mod:`overseec_core.interpret.offline`): lengths are
kept by :func:`normalise`, so every token's character span quotes the original prompt.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.config_lines import sectioned
from overseec_core.interpret.markup import markup, nested_verdicts, tabulated


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
    r"note|r|c)[ \t]*\d+(?:\.\d+)*[ \t]*[:)\-])"
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


#: The colon of a clock time ("between 02:00 and 04:00"): no mark between a topic and its rule.
_TIME_COLON = re.compile(r"(?:(?<=\b\d)|(?<=\b\d\d)):(?=\d\d\b)")


def normalise(text: str) -> str:
    """Lower-case, straight apostrophes, hyphens between letters as spaces, arrows ("->", "=>")
    as colons, ``key=value`` settings as colon statements, dots inside words as spaces, a
    ranking's list as ``>`` steps (:func:`_rankings`, :func:`_numbered_rankings`); length preserved."""
    out = []
    text = _telegram(_TIME_COLON.sub("h", text))  # "02:00" is one time, "02h00"
    text = _DECIMAL_COMMA.sub(".", text)  # "2,5 m" is 2.5 m
    text = _settings(_unit_keys(_functions(_rule_labels(_tables(_leaders(markup(text)))))))
    text = _asides(_glosses(_rankings(_numbered_rankings(text))))
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


def _ends_item(text: str, k: int) -> bool:
    """Whether only blanks stand between ``k`` and the end of a list item (a comma, a semicolon,
    a full stop, a line end, the end of the text)."""
    rest = text[k:].lstrip(" \t")
    return not rest or rest[0] in ",;.\n|"


def _slash(norm: str, m: re.Match) -> str:
    """A slash as read: "or" between two words ("road/trail"); spaced, it breaks a line of verse
    or a list (",": "water's edge / farther is better")."""
    spaced = norm[m.start() - 1 : m.start()] == " " and norm[m.end() : m.end() + 1] in (" ", "\n")
    return "," if spaced else "or"


def tokenize(text: str) -> list[Tok]:
    """The prompt's tokens (possessive -s dropped, "&" -> "and", a bare "dont" -> "don't", a
    letter typed three times once, a field abbreviation spelt out: "bldgs" -> "buildings", a
    texted word read: "nvr" -> "never", "in2" -> "into")."""
    toks: list[Tok] = []
    norm = normalise(text)
    for m in lx.TOKEN_RE.finditer(norm):
        w = m.group()
        if w.endswith("'s") and w not in lx.KEEP_S:
            w = w[:-2]
        if w.endswith("'ll") and w not in lx.FILLER:  # "that road'll chew the tires up": "road will"
            w = w[:-3] + " will"
        w = _slash(norm, m) if w == "/" else {"&": "and"}.get(w, w)
        w = lx.MARK_VERDICTS.get(w, w)  # "rd ✓ | rly ✗"
        if w[0] in "+-":  # "road: ++", "water: --" after a mark; "grass + road" joins; "20 m+" is a bound
            prev = toks[-1].word if toks else ""
            if prev in (":", "=") and w in lx.SIGN_VERDICTS:
                w = lx.SIGN_VERDICTS[w]
            elif prev.isalpha() and prev not in lx.UNITS and w in lx.ITEM_SIGNS and _ends_item(norm, m.end()):
                # "trail +, grass -, trees --": a sign ending its item is its verdict, and the item's end
                w = lx.ITEM_SIGNS[w] + " ;"
            elif w.startswith("+") and prev.isalpha() and prev not in lx.UNITS:
                w = "and"
            else:
                continue
        w = _ELONGATED.sub(r"\1", w)  # "waaay" -> "way", "sooo" -> "so"
        w = lx.BARE_CONTRACTIONS.get(w, w)
        w = lx.read_texting(w) or w  # "nvr go in2 any bldg", "pvd rd"
        for part in w.split(" "):  # "atleast" -> "at least": both words keep the written span
            toks.append(Tok(part, m.start(), m.end()))
    toks = _hyphen_compounds(toks, text)
    toks = nested_verdicts(tabulated(toks, text, Tok))  # "class,min_m\nwater,12": "water : min 12 m"
    toks = sectioned(toks, text, Tok)  # "[road]\non = false": "not on road"
    for rewrite in _REWRITES:  # in order: each reads the tokens the one before left
        toks = rewrite(toks)
    return toks


def _kept_object(toks: list[Tok]) -> list[Tok]:
    """ "keep it out of the trees", "keep the sedan mostly on paved road": the traveller between a
    keeping verb and its preposition is dropped, so the rule reads as "keep out of the trees",
    "keep mostly on paved road" (:data:`lexicon.TRAVELLER_WORDS`)."""
    out: list[Tok] = []
    i = 0
    while i < len(toks):
        if _bare_traveller(toks, i):  # "WHEELS OFF GRASS": "keep off grass"
            out.append(Tok("keep", toks[i].start, toks[i].end))
            i += 1
            continue
        out.append(toks[i])
        if toks[i].word in lx.KEEP_OBJECT_VERBS and i + 1 < len(toks):
            nxt = toks[i + 1].word
            size = 1 if nxt in ("it", "them") or nxt in lx.TRAVELLER_WORDS else 0
            if nxt in ("the", "your", "our", "that", "this", "its", "their") and i + 2 < len(toks):
                size = 2 if toks[i + 2].word in lx.TRAVELLER_WORDS else 0
            k = i + 1 + size
            while size and k < len(toks) and is_adverb(toks[k].word):
                k += 1  # "keep the sedan mostly on ..."
            if size and k < len(toks) and toks[k].word in lx.KEEP_OBJECT_PREPS:
                i += 1 + size
                continue
        i += 1
    return out


def _bare_traveller(toks: list[Tok], i: int) -> bool:
    """Whether token ``i`` opens a sentence with the traveller and a keeping particle and no verb
    ("wheels off the grass itself", "tyres clear of the verge"): an order to keep it there."""
    opens = i == 0 or toks[i - 1].word in (".", ";", "!", "\n", ":")
    nxt = toks[i + 1].word if i + 1 < len(toks) else ""
    return opens and toks[i].word in lx.TRAVELLER_WORDS and nxt in ("off", "clear", "away", "out")


def _tilde_verdicts(toks: list[Tok]) -> list[Tok]:
    """ "veg ~" in a list of marks ("rd ✓ | veg ~"): a tilde after a word and before no number
    is "so-so", read as fine; "~15 m" stays an estimate."""
    for i, t in enumerate(toks):
        nxt = toks[i + 1].word if i + 1 < len(toks) else ""
        if t.word == "~" and i > 0 and toks[i - 1].word.isalpha() and not nxt[:1].isdigit():
            t.word = "fine"
    return toks


def _amounts(toks: list[Tok]) -> list[Tok]:
    """ "half a dozen metres" is "6 metres", "a couple of metres" "2 metres": an amount in words
    (:data:`lexicon.AMOUNTS`) right before a unit is its number."""
    out: list[Tok] = []
    i = 0
    while i < len(toks):
        for words, number in lx.AMOUNTS.items():
            k = i + len(words)
            if tuple(t.word for t in toks[i:k]) == words and k < len(toks) and toks[k].word in lx.UNITS:
                out.append(Tok(number, toks[i].start, toks[k - 1].end))
                i = k
                break
        else:
            out.append(toks[i])
            i += 1
    return out


#: A minimum said after its distance ("2.5 m at the minimum from", "3 m at least from", "5 m
#: minimum from"), before the preposition of the bound.
_TRAILING_MINIMA = (("at", "the", "minimum"), ("at", "a", "minimum"), ("at", "minimum"), ("at", "least"), ("minimum",))


def _trailing_minimum(toks: list[Tok]) -> list[Tok]:
    """ "keep 2.5 m at the minimum from the buildings" reads as "keep at least 2.5 m from the
    buildings": the minimum moves before the number it bounds (a hard bound, as stated)."""
    out: list[Tok] = []
    i = 0
    while i < len(toks):
        t = toks[i]
        hit = next(
            (
                words
                for words in _TRAILING_MINIMA
                if i + 1 + len(words) < len(toks)
                and tuple(x.word for x in toks[i + 1 : i + 1 + len(words)]) == words
                and toks[i + 1 + len(words)].word in ("from", "of", "off", "away", "clear", "between")
            ),
            None,
        )
        if t.word in lx.UNITS and hit is not None and out and re.fullmatch(r"\d+(?:\.\d+)?", out[-1].word):
            number = out.pop()
            span = toks[i + 1].start, toks[i + len(hit)].end
            out += [Tok("at", *span), Tok("least", *span), number, t]
            i += 1 + len(hit)
            continue
        out.append(t)
        i += 1
    return out


def _on_top_of(toks: list[Tok]) -> list[Tok]:
    """ "on top of it" is "on it" ("go along the side of the trail, not on top of it")."""
    out: list[Tok] = []
    for t in toks:
        if t.word == "of" and len(out) >= 2 and out[-1].word == "top" and out[-2].word == "on":
            out.pop()
            continue
        out.append(t)
    return out


#: What follows a chat "n" that starts a new thought rather than a list ("potholes n my back
#: cant take it"): the "n" is not read as "and" there.
_NEW_THOUGHT = frozenset("my i i'm im we our me it its they he she you u".split())


def _chat_and(toks: list[Tok]) -> list[Tok]:
    """ "oaks n maples", "stick to the road n avoid the mud": a lone "n" between two words is
    "and", unless what follows starts a thought of its own (a pronoun)."""
    for prev, t, nxt in zip(toks, toks[1:], toks[2:]):
        joins = prev.word.isalpha() or prev.word == ","  # "road n trail", "..., n keep out the water"
        if t.word == "n" and joins and nxt.word.isalpha() and nxt.word not in _NEW_THOUGHT:
            t.word = "and"
    return toks


#: Comparatives after which "then" is a slip for "than" ("no closer then 5 m").
_COMPARATIVES = frozenset("closer nearer further farther more less fewer".split())


def _than_slips(toks: list[Tok]) -> list[Tok]:
    """ "closer then 5 m" is "closer than 5 m": a "then" right after a comparative is "than" (a
    sequence's "then" follows a name or a comma, never a comparative)."""
    for prev, t in zip(toks, toks[1:]):
        if t.word == "then" and prev.word in _COMPARATIVES:
            t.word = "than"
    return toks


def _hyphen_compounds(toks: list[Tok], text: str) -> list[Tok]:
    """ "stand-off", "set-back", "off-road": two words joined by a hyphen that make one word
    written whole (:data:`lexicon.HYPHEN_COMPOUNDS`: the gap nouns, and the ground off the roads,
    never "stay off the road") are that word; other hyphenated words stay two words
    ("no-go", "tree-line" are read word by word); "x-ing" is "crossing", as road signs write it."""
    out: list[Tok] = []
    for t in toks:
        prev = out[-1] if out else None
        joined = prev is not None and text[prev.end : t.start] in ("-", "\u2010", "\u2011")
        if joined and prev is not None and prev.word + t.word in lx.HYPHEN_COMPOUNDS:
            out[-1] = Tok(prev.word + t.word, prev.start, t.end)
        elif joined and prev is not None and (prev.word, t.word) == ("x", "ing"):
            out[-1] = Tok("crossing", prev.start, t.end)  # "x-ing rail: never": the signs' crossing
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


#: Sounds a speaker makes while thinking ("stick close to the, um, the railroad tracks").
_HESITATIONS = frozenset({"um", "umm", "uh", "uhh", "uhm", "er", "erm", "ehm", "hmm", "mm"})


def _disfluencies(toks: list[Tok]) -> list[Tok]:
    """A spoken brief's hesitations dropped with the commas around them ("the, um, the railroad
    tracks"), a word then said again once ("the the railroad"), and "like" set off by commas
    ("hey so, like, can you ..."): what is left reads as the sentence meant. A correction's own
    words ("no wait, I mean") are kept."""
    out: list[Tok] = []
    k, n = 0, len(toks)
    while k < n:
        w = toks[k].word
        filler = w in _HESITATIONS or (w == "like" and 0 < k < n - 1 and toks[k - 1].word == toks[k + 1].word == ",")
        if filler:
            if out and out[-1].word == ",":
                out.pop()
            k += 1 + (k + 1 < n and toks[k + 1].word == ",")
            continue
        if out and w == out[-1].word and w in lx.ARTICLES | {"to", "of", "on", "in"}:
            k += 1  # "the the railroad" after the hesitation is gone
            continue
        out.append(toks[k])
        k += 1
    return out


#: Words that grant a way ("you are allowed under the trees", "you may drive on grass").
_PERMISSIONS = frozenset({"allowed", "permitted", "authorised", "authorized", "cleared", "may", "can"})
#: Words that end the search for a permission before a contrast.
_NEGATING = frozenset({"not", "never", "no", "don't", "can't", "cannot", "mustn't", "nor"})
#: Where a contrast's object is ("but not in the pond").
_CONTRAST_PREPS = frozenset({"in", "into", "on", "onto", "under", "through", "across", "over", "inside"})


def _contrasted_permission(toks: list[Tok]) -> list[Tok]:
    """ "you ARE allowed under the trees. but NOT in the pond", "you may drive on grass but not
    on the road": a "but not" before a place, after a permission in its sentence or the one
    before, denies that permission there, so it reads "but not allowed in the pond" (forbidden,
    as "not allowed in the pond" is), not a bare "not in" (avoided)."""
    out: list[Tok] = []
    stops = 0
    granted = False
    for i, t in enumerate(toks):
        out.append(t)
        if t.word in (".", "!", "?", ";", "\n"):
            stops += 1
            granted = granted and stops < 2
        elif t.word in _PERMISSIONS:
            granted, stops = True, 0
        elif t.word in _NEGATING and not (i > 0 and toks[i - 1].word == "but"):
            granted = False
        nxt = toks[i + 1].word if i + 1 < len(toks) else ""
        if granted and t.word == "not" and i > 0 and toks[i - 1].word == "but" and nxt in _CONTRAST_PREPS:
            out.append(Tok("allowed", t.start, t.end))
            granted = False
    return out


def _ranked_last(toks: list[Tok]) -> list[Tok]:
    """ "trail > road > grass; tree & water last": what a ranking's line names last after it is
    the ranking's last step ("... > grass > tree & water"), not a new sequence of its own."""
    out: list[Tok] = []
    i = 0
    while i < len(toks):
        t = toks[i]
        end = _last_item_end(toks, i + 1) if t.word in (";", ",") and _ranks_before(out) else None
        if end is None:
            out.append(t)
            i += 1
            continue
        out.append(Tok(">", t.start, t.end))
        out.extend(toks[i + 1 : end])  # the items, without their "last"
        i = end + 1
    return out


def _ranks_before(out: list[Tok]) -> bool:
    """Whether the line so far is a ranking (a ">" step since the last line break)."""
    for t in reversed(out):
        if t.word == "\n":
            return False
        if t.word == ">":
            return True
    return False


def _last_item_end(toks: list[Tok], k: int) -> int | None:
    """Where "last" stands after a short list of names from ``k`` ("tree & water last"), with
    nothing after it on its line; None otherwise."""
    j = k
    while j < len(toks) and j - k < 6 and toks[j].word not in ("last", ";", ".", "\n", ">"):
        j += 1
    if j == k or j >= len(toks) or toks[j].word != "last":
        return None
    if j + 1 < len(toks) and toks[j + 1].word not in (".", ";", "\n", "!"):
        return None
    return j


#: The token rewrites after the hyphen compounds, in the order :func:`tokenize` applies them.
_REWRITES = (
    _ranked_last,
    _disfluencies,
    _contrasted_permission,
    _trailing_minimum,
    _on_top_of,
    _than_slips,
    _chat_and,
    _amounts,
    _tilde_verdicts,
    _kept_object,
)
