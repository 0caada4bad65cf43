"""Tokens of a mission prompt: tokenizing, the token rewrites and splitting into sentences.

The first step of the offline interpreter (:mod:`overseec_core.interpret.offline`): the text is
normalised first (:mod:`overseec_core.interpret.normalise`, lengths kept), so every token's
character span quotes the original prompt.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.config_lines import sectioned
from overseec_core.interpret.markup import nested_verdicts, tabulated
from overseec_core.interpret.normalise import normalise


@dataclass
class Tok:
    """One token: the word as read (lower case, contractions expanded) and its character span."""

    word: str
    start: int
    end: int


def is_adverb(word: str) -> bool:
    """Words ending in -ly are adverbs ("carefully", "quietly"), never entity names."""
    return len(word) > 4 and word.endswith("ly") and word not in lx.LY_NOUNS


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
        w = _clitics(m.group()) + _clitic_is(norm, m)
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


#: Verdicts a clitic "'s" says "is" before ("tarmac's better", "the pond's off limits").
_IS_BEFORE = frozenset(
    "better worse best worst fine ok okay good bad great alright preferred forbidden banned off not never".split()
)
_NEXT_WORD = re.compile(r"[ \t]*([a-z]+)")


def _clitic_is(norm: str, m: re.Match) -> str:
    """ " is" when the word at ``m`` ends in a clitic "'s" and a verdict follows it ("dirt's ok
    but tarmac's better": "tarmac is better"); the possessive ("the road's edge") says nothing."""
    nxt = _NEXT_WORD.match(norm, m.end())
    clitic = m.group().endswith("'s") and m.group() not in lx.KEEP_S  # "it's" is read as itself
    return " is" if clitic and nxt is not None and nxt.group(1) in _IS_BEFORE else ""


def _clitics(w: str) -> str:
    """A word with its clitic read: possessive -s dropped ("road's"), a person's possessive as
    "the" ("anybody's house"), "'ll" as " will" ("that road'll chew the tires up"), "'n" after a
    comparative as " than" ("better'n gravel")."""
    if w.endswith("'s") and w[:-2] in lx.POSSESSORS:
        return "the"
    if w.endswith("'s") and w not in lx.KEEP_S:
        w = w[:-2]
    if w.endswith("'ll") and w not in lx.FILLER:
        w = w[:-3] + " will"
    if w.endswith("'n") and (w[:-2].endswith("er") or w[:-2] in ("more", "less")):
        w = w[:-2] + " than"
    return w


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
                if not size and i + 3 < len(toks) and toks[i + 3].word in lx.TRAVELLER_WORDS:
                    size = 3  # "keep the picker robot snug to the trail"
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


def _given_a_miss(toks: list[Tok]) -> list[Tok]:
    """ "give houses a miss", "give the old quarry a miss": the thing between "give" and "a miss"
    avoided, read "avoid houses" ("give it a miss" is a phrase of its own)."""
    out: list[Tok] = []
    i = 0
    while i < len(toks):
        if toks[i].word in ("give", "gives") and i + 2 < len(toks):
            k = next((k for k in range(i + 2, min(len(toks) - 1, i + 6)) if toks[k].word == "a"), None)
            names = toks[i + 1 : k] if k is not None else []
            if k is not None and toks[k + 1].word == "miss" and not any(t.word in ("it", "them") for t in names):
                out += [Tok("avoid", toks[i].start, toks[i].end), *names]
                i = k + 2
                continue
        out.append(toks[i])
        i += 1
    return out


#: What makes the usual way unusable ("only if the paved one is blocked", "when the trail is flooded").
_UNUSABLE = frozenset(
    "blocked closed impassable unavailable flooded shut jammed congested busy full washed out".split()
)


def _fallback_condition(toks: list[Tok]) -> list[Tok]:
    """ "the unpaved road only if the paved one is blocked", "grass only when the trail is
    closed": a way used only when another cannot be is a fallback, read "if needed" (tolerable):
    the condition says when it is needed, and its words keep their span."""
    out: list[Tok] = []
    i = 0
    while i < len(toks):
        j = i + 1
        end = None
        if toks[i].word == "only" and j < len(toks) and toks[j].word in ("if", "when"):
            for k in range(j + 1, min(len(toks) - 1, j + 7)):
                if toks[k].word in ("is", "are", "'s", "gets", "get", "becomes") and toks[k + 1].word in _UNUSABLE:
                    end = k + 1
                    break
                if toks[k].word in (",", ";", ".", "\n"):
                    break
        if end is None:
            out.append(toks[i])
            i += 1
            continue
        out += [Tok("if", toks[i].start, toks[j].end), Tok("needed", toks[j + 1].start, toks[end].end)]
        i = end + 1
    return out


def _either_side(toks: list[Tok]) -> list[Tok]:
    """ "20 m either side of the creek", "a buffer each side of the road", "5 m on both sides of
    the trail": a band around the thing, read "around" (its three or four words keep their span)."""
    out: list[Tok] = []
    i = 0
    while i < len(toks):
        k = i + (toks[i].word == "on")
        words = tuple(t.word for t in toks[k : k + 3])
        before = out[-1].word if out else ""
        band = before in lx.UNITS or before in lx.ZONE_NOUNS | lx.CLEARANCE_NOUNS
        if band and words in (("either", "side", "of"), ("each", "side", "of"), ("both", "sides", "of")):
            out.append(Tok("around", toks[i].start, toks[k + 2].end))
            i = k + 3
            continue
        out.append(toks[i])
        i += 1
    return out


#: The prepositions after which "there" is the place just named ("kept mostly off there").
_THERE_PLACES = frozenset({"off", "on", "in", "into", "near", "from", "across", "through", "under"})


def _place_there(toks: list[Tok]) -> list[Tok]:
    """ "the paved road though, I'd rather it kept off there": "there" after a preposition is the
    place named before, read as "it" (its pronoun); "there is" and "over there" stay."""
    out: list[Tok] = []
    for i, t in enumerate(toks):
        end = i + 1 == len(toks) or toks[i + 1].word in (".", ",", ";", ":", "!", "?", "\n", "and", "but", "so")
        if t.word == "there" and out and out[-1].word in _THERE_PLACES and end:
            out.append(Tok("it", t.start, t.end))
            continue
        out.append(t)
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


#: Verbs of treating a rule as something ("treat it as a wall").
_TREAT_VERBS = frozenset({"treat", "treats", "treated", "treating", "regard", "regarded", "consider", "considered"})
#: What a rule treated as a wall is: never crossed.
_WALL_WORDS = frozenset({"wall", "walls", "fence", "fences", "barrier", "barriers", "boundary", "cliff", "cliffs"})


def _treated_as_wall(toks: list[Tok]) -> list[Tok]:
    """ "treat it as a wall", "treat a 20-foot ring around the clubhouse as a wall", "regard that
    line as a fence": the rule is absolute, so "as a wall" reads "strictly" and the verb goes (its
    object stays: what the rule is about, or the rule itself)."""
    out: list[Tok] = []
    i = 0
    while i < len(toks):
        j = _wall_at(toks, i) if toks[i].word in _TREAT_VERBS else None
        if j is None:
            out.append(toks[i])
            i += 1
            continue
        out.extend(toks[i + 1 : j])  # what the rule is about, or the rule itself ("it", "that line")
        end = j + 1 + (toks[j + 1].word in ("a", "an", "the")) + 1
        out.append(Tok("strictly", toks[j].start, toks[end - 1].end))
        i = end
    return out


def _wall_at(toks: list[Tok], i: int) -> int | None:
    """Where "as (a) wall" stands after a treating verb at ``i`` (within 14 words, none of them
    a sentence end), else None."""
    for j in range(i + 1, min(len(toks) - 1, i + 15)):
        w = toks[j].word
        if w in (".", ";", "!", "?", "\n"):
            return None
        if w == "as":
            k = j + 1 + (toks[j + 1].word in ("a", "an", "the"))
            return j if k < len(toks) and toks[k].word in _WALL_WORDS and j > i + 1 else None
    return None


#: How much distance a verdict says is better ("distance to the road: less is better").
_LESS_MORE = {"less": "closer", "lower": "closer", "smaller": "closer", "shorter": "closer", "more": "farther"}
_LESS_MORE |= {"greater": "farther", "larger": "farther", "bigger": "farther", "higher": "farther"}


def _distance_verdict(toks: list[Tok]) -> list[Tok]:
    """ "distance to the road: less is better", "DIST TO PAVED ROAD: LESS IS BETTER", "distance
    from the water: more is better": read as "closer to the road is better", "farther from the
    water is better" (a plain comparative with its object after it)."""
    for i in range(len(toks) - 5):
        if toks[i].word not in ("distance", "dist") or toks[i + 1].word not in ("to", "from"):
            continue
        colon = next((j for j in range(i + 2, min(len(toks), i + 8)) if toks[j].word in (":", "=", "-")), None)
        if colon is None or colon + 3 >= len(toks):
            continue
        amount, verb = toks[colon + 1].word, toks[colon + 2].word
        if amount not in _LESS_MORE or verb not in ("is", "="):
            continue
        said = Tok(_LESS_MORE[amount], toks[i].start, toks[i].end)
        return [*toks[:i], said, *toks[i + 1 : colon], toks[colon + 2], *toks[colon + 3 :]]
    return toks


#: The token rewrites after the hyphen compounds, in the order :func:`tokenize` applies them.
_REWRITES = (
    _distance_verdict,
    _treated_as_wall,
    _ranked_last,
    _disfluencies,
    _contrasted_permission,
    _trailing_minimum,
    _on_top_of,
    _fallback_condition,
    _given_a_miss,
    _either_side,
    _place_there,
    _than_slips,
    _chat_and,
    _amounts,
    _tilde_verdicts,
    _kept_object,
)
