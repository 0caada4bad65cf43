"""The offline interpreter: deterministic rules that read common mission language.

No model and no network: a tokenizer, the tables in :mod:`.lexicon` and a few passes over each
sentence. Written by hand because no maintained library turns "prefer the roads, grass is fine,
avoid the baseball field" into ranked costs; a general NLP parser (spaCy and the like) would add
hundreds of megabytes and still need these rules on top.

How a prompt is read:

1. Normalise (lower case, curly quotes, "off-limits" -> "off limits"; lengths kept, so fragments
   are quoted from the original text) and tokenize; split sentences at ``. ; ! ?`` and newlines.
2. Claim idioms that contain entity-like words first ("cross-country", "off-road", "off the
   beaten track": a preference for the terrain they name; polite wrappers such as "it would be
   great if": nothing). Then find entity mentions: the longest match in the entity table
   (plurals included), then runs of unknown content words (open vocabulary: "avoid the sandbox"
   names a "sandbox"; grammar words in ``lexicon.FILLER``, words of the phrase tables and -ly adverbs
   never do); an unknown word just before a known entity makes a compound ("dirt roads" ->
   "dirt road", inside road; "muddy tracks" -> "muddy track", since a bare "tracks" is the
   railway).
3. Claim constructs, in this order: conditions ("unless/if/when ... near X / within N m of X";
   "except at/over/via X"; "only at X"), geometric cues ("centre/side of X", "near X",
   "within N m of X", "at least N m from X", "a 20 m buffer around X"; a stated bound is a
   ``hard`` cue), comparisons ("X is better/worse than Y", "prefer X over Y", "X rather than
   Y"), modifiers ("as much as possible", "at all costs", "only if you have to"), preference
   triggers (tiers below; adverbs inside a phrase do not break it: "you can just wade
   through") and ordering markers ("first", "then", "finally").
4. Split into clauses at commas and conjunctions, except "and/or/," between two entities
   ("roads and trails" stays one list). In each clause, each entity takes the tier of the
   nearest trigger group (adjacent triggers combine, the most severe wins: "don't use" = avoid).
   A clause of bare entities joins its neighbour ("avoid water, buildings"); a pronoun ("you may
   cross it") refers to the previous clause's entities.
5. Orderings ("first X, then Y, then Z") and comparisons adjust the weights; a later statement
   about the same entity overrides an earlier one (noted).

Phrasing families (each a table row or rule, never a particular sentence):

=====================  ==================================================================
family                 reading
=====================  ==================================================================
negation + exception   "do not cross the railway except at level crossings", "never enter the
                       water unless near the bridge": X avoid/lethal + ``unless_near`` X, Y.
                       "cross the railway only at level crossings" (nothing else stated, or
                       a permission): X lethal + ``unless_near``; "avoid the river, but only
                       near the village": ``if_near``
last resort            "roads are a last resort", "only if you have to", "only in an
                       emergency": tolerable (worse than neutral ground)
comparatives           "X is better than Y", "prefer X over Y", "X rather than Y", "Y is worse /
                       less preferable than X": X below Y; an unstated side moves off neutral
                       only as far as it must (the worse side is never made preferred)
concealment            "stay under the trees / tree cover", "keep to the canopy", "stay hidden
                       in the forest", "under cover of the trees": prefer
permission             "you can wade through the water", "it's ok to drive through", "feel
                       free to go over": fine = neutral (no objection); "you can go around X":
                       avoid
stay off               "stay off / keep off / get off X": avoid ("the tracks" is the railway)
cross-country          "go cross-country through X", "off-road over X": prefer X
distances              "at least / no closer than N m from X", "never within N m of X": far,
                       hard; "within / no more than N m of X": near, hard; "N m away from X",
                       "a N m buffer around X", "near X", or any of these softened ("try",
                       "ideally", "if possible"): soft
=====================  ==================================================================

Each stated preference carries the phrase it came from (``Preference.phrase``): the trigger
with its entity list, the clause's modifiers and conditions, the neighbouring clause a bare list
or a pronoun took its tier from, the ordering so far, and any comparison naming the entity.

Anything left over -- a clause with no entity or no meaning, words that fit no rule, a
condition it cannot read -- is quoted in ``unparsed``; nothing is dropped silently.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass, field

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.merge import finalize, make_entity
from overseec_core.interpret.priors import PriorTable
from overseec_core.schema import Cue, Interpretation

RULES_VERSION = "offline-rules.v2"


def _comparative_base(word: str) -> str | None:
    """The adjective of a comparative with a valence ("safer" -> "safe", "riskier" -> "risky",
    "wetter" -> "wet", "worse" -> "bad"), else None."""
    if word in lx.COMPARATIVE_FORMS:
        return lx.COMPARATIVE_FORMS[word]
    cands = []
    if word.endswith("ier"):
        cands.append(word[:-3] + "y")
    if word.endswith("er"):
        cands += [word[:-2], word[:-1], word[:-3]]  # faster, safer, wetter
    return next((c for c in cands if c in lx.VALENCE), None)


def _is_adverb(word: str) -> bool:
    """Words ending in -ly are adverbs ("carefully", "quietly"), never entity names."""
    return len(word) > 4 and word.endswith("ly") and word not in lx.LY_NOUNS


# ----------------------------------------------------------------------------- tokens


@dataclass
class Tok:
    word: str
    start: int
    end: int


def normalise(text: str) -> str:
    """Lower-case, straight apostrophes, hyphens between letters as spaces; length preserved."""
    out = []
    n = len(text)
    for i, ch in enumerate(text):
        if ch in "\u2019\u2018`\u00b4":
            ch = "'"
        elif ch in "-\u2010\u2011\u2012\u2013" and 0 < i < n - 1 and text[i - 1].isalpha() and text[i + 1].isalpha():
            ch = " "
        low = ch.lower()
        out.append(low if len(low) == 1 else ch)
    return "".join(out)


def tokenize(text: str) -> list[Tok]:
    toks = []
    for m in lx.TOKEN_RE.finditer(normalise(text)):
        w = m.group()
        if w.endswith("'s") and w not in lx.KEEP_S:
            w = w[:-2]
        w = {"&": "and", "/": "or"}.get(w, w)
        w = lx.BARE_CONTRACTIONS.get(w, w)
        toks.append(Tok(w, m.start(), m.end()))
    return toks


def sentences(toks: list[Tok]) -> list[list[Tok]]:
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


# ----------------------------------------------------------------------------- sentence analysis


@dataclass
class Mention:
    start: int
    end: int  # exclusive token index
    name: str
    known: bool
    role: str = "target"  # target | cond | cue | right
    chain: int = -1  # list id: mentions joined by and/or/commas share it


@dataclass
class Found:
    """A claimed construct: kind, token span and payload."""

    kind: str  # trigger | modifier | comparator | condition | cue | marker
    start: int
    end: int
    value: str  # the phrase table's payload: the trigger's tier, the cue's kind, the marker ...
    mentions: tuple = ()  # mentions it refers to
    metres: float | None = None
    left: tuple = ()  # comparator left side
    hard: bool = False  # a distance stated as a bound ("at least 20 m from", "within 50 m of")


@dataclass(eq=False)
class Clause:
    sent: int
    start: int
    end: int
    toks: list[Tok]
    seps: set[str] = field(default_factory=set)
    found: list[Found] = field(default_factory=list)
    targets: list[Mention] = field(default_factory=list)
    assigned: dict[str, str] = field(default_factory=dict)  # entity -> tier
    markers: set[str] = field(default_factory=set)
    leftover: list[int] = field(default_factory=list)  # token indices not understood
    whole_unparsed: bool = False
    referenced: bool = False  # a later pronoun refers to this clause's entities
    #: entity -> (first, last) clause whose words its tier came from (default: this clause)
    src: dict[str, tuple[Clause, Clause]] = field(default_factory=dict)
    #: entity -> token span (sentence indices) of the words in this clause its tier came from
    tok_src: dict[str, tuple[int, int]] = field(default_factory=dict)

    def took(self, name: str, *spans: tuple[int, int]) -> None:
        """Record that ``name``'s tier came from these token spans (and the clause's modifiers
        and conditions, which qualify the whole clause)."""
        spans = spans + tuple((f.start, f.end) for f in self.found if f.kind in ("modifier", "condition"))
        if name in self.tok_src:
            spans += (self.tok_src[name],)
        if spans:
            self.tok_src[name] = (min(a for a, _ in spans), max(b for _, b in spans))

    def own_span(self, name: str) -> tuple[int, int]:
        if name in self.tok_src:
            a, b = self.tok_src[name]
            return self.toks[a].start, self.toks[b - 1].end
        return self.span()

    def span(self) -> tuple[int, int]:
        """Character span of the clause in the prompt."""
        if self.start >= self.end:
            return 0, 0
        return self.toks[self.start].start, self.toks[self.end - 1].end

    def phrase(self, name: str, prompt: str) -> str:
        """The prompt's words the tier of ``name`` came from: this clause, or the run of clauses
        it was read from ("avoid water, buildings"; "The lake is frozen, so you may cross it")."""
        a, b = self.own_span(name)
        for other in self.src.get(name, ()):
            if other is not self:
                a, b = min(a, other.span()[0]), max(b, other.span()[1])
        return prompt[a:b].strip(" ,;:")

    def text(self, prompt: str) -> str:
        if self.start >= self.end:
            return ""
        return prompt[self.toks[self.start].start : self.toks[self.end - 1].end].strip()


class _Sentence:
    """Mentions and constructs of one sentence (token indices are local to it)."""

    def __init__(self, toks: list[Tok]):
        self.toks = toks
        self.n = len(toks)
        #: (word as written, entity or phrase word, how): words read by spelling or alias
        self.readings: list[tuple[str, str, str]] = []
        self.words = [self._phrase_word(t.word) for t in toks]
        self.claimed: list[str | None] = [None] * self.n
        self.mentions: list[Mention] = []
        self.mention_at: dict[int, Mention] = {}
        self.found: list[Found] = []
        self._claim_idioms()
        self._find_mentions()
        self._claim_all()
        self._joins()

    @property
    def alternatives(self) -> set[int]:
        """Where an alternative marker ("otherwise", "or else") starts a new clause."""
        return {f.start for f in self.found if f.kind == "marker" and f.value == "alt" and f.start > 0}

    def _phrase_word(self, word: str) -> str:
        """A misspelt verb or adjective of the phrase tables, corrected ("folow the road"); an
        entity word is corrected later, where mentions are found."""
        if lx.correct_spelling(word) is not None:
            return word
        fixed = lx.correct_phrase_word(word)
        if fixed is None:
            return word
        self.readings.append((word, fixed, "spelling"))
        return fixed

    # -- idioms
    def _claim_idioms(self) -> None:
        """Idioms that contain words of entity names ("cross-country", "off-road"): grammar."""
        i = 0
        while i < self.n:
            hit = self._match(lx.IDIOMS, i)
            if hit and not (self.words[i] == "off" and i > 0 and self.words[i - 1] in lx.OFF_VERBS):
                # "stay off road X" is staying off it, not going off-road
                kind = "filler" if hit[1] == "polite" else "trigger"
                self._claim(Found(kind, i, i + len(hit[0]), hit[1]), kind)
                i += len(hit[0])
            else:
                i += 1

    # -- mentions
    def _find_mentions(self) -> None:  # noqa: C901
        words, i = self.words, 0
        known: list[Mention] = []
        while i < self.n:
            hit = None
            for k in range(min(lx.MAX_SURFACE_WORDS, self.n - i), 0, -1):
                name = lx.SURFACE.get(tuple(words[i : i + k]))
                if name and self._free(i, i + k):
                    hit = Mention(i, i + k, name, True)
                    break
            if hit:
                known.append(hit)
                surface = tuple(words[hit.start : hit.end])
                if surface not in lx.NAME_FORMS:  # "woods" is the forest: say so
                    self.readings.append((" ".join(surface), hit.name, "alias"))
                i = hit.end
            elif words[i] in lx.SIDE_TOKENS:  # "roadside": a side cue on the road
                known.append(Mention(i, i + 1, lx.SIDE_TOKENS[words[i]], True, role="side"))
                i += 1
            else:
                i += 1
        covered = {j for m in known for j in range(m.start, m.end)}
        content = [j not in covered and self._is_content(j) for j in range(self.n)]
        for j in range(self.n):  # "vegitation", "raod": a near-miss of an entity word
            fixed = lx.correct_spelling(words[j]) if content[j] else None
            if fixed is not None:
                known.append(Mention(j, j + 1, fixed[1], True))
                self.readings.append((words[j], fixed[1], "spelling"))
                content[j] = False
        runs, j = [], 0
        while j < self.n:
            if content[j]:
                k = j
                while k < self.n and content[k]:
                    k += 1
                runs.append((j, k))
                j = k
            else:
                j += 1
        by_start = {m.start: m for m in known}
        mentions = list(known)
        for a, b in runs:
            follower = by_start.get(b)
            if follower is not None and b - a <= 2 and follower.role == "target":
                # "dirt road", "muddy baseball field": open-vocabulary compound of a known entity
                # (counts as known: its head word is in the table)
                mentions.remove(follower)
                head = follower.name
                surface = tuple(self.words[follower.start : follower.end])
                if surface in lx.AMBIGUOUS_SURFACES:  # "muddy tracks": a track, not the railway
                    head = lx.singularise(surface[-1])
                name = " ".join(self.words[a:b]) + " " + head
                mentions.append(Mention(a, follower.end, name, True))
            elif b - a <= 3:
                ws = self.words[a:b]
                name = " ".join(ws[:-1] + [lx.singularise(ws[-1])])
                mentions.append(Mention(a, b, name, False))
            # longer runs are not read as a name; they stay unclaimed and are reported
        mentions.sort(key=lambda m: m.start)
        self.mentions = mentions
        for m in mentions:
            self.mention_at[m.start] = m
            for j in range(m.start, m.end):
                self.claimed[j] = "mention"

    def _is_content(self, j: int) -> bool:
        w = self.words[j]
        return (
            self.claimed[j] is None and w.isalpha() and w not in lx.FILLER and w not in lx.VOCAB and not _is_adverb(w)
        )

    # -- helpers
    def _free(self, a: int, b: int) -> bool:
        return b <= self.n and all(self.claimed[j] is None for j in range(a, b))

    def _match(self, table, i: int):
        cands = table.get(self.words[i]) if i < self.n else None
        for words, payload in cands or ():
            k = len(words)
            if tuple(self.words[i : i + k]) == words and self._free(i, i + k):
                return words, payload
        return None

    def _match_loose(self, table, i: int) -> tuple[str, int] | None:
        """Like _match, but inserted adverbs do not break a phrase ("you can just wade through",
        "stay quietly under"): (payload, end index)."""
        cands = table.get(self.words[i]) if i < self.n and self.claimed[i] is None else None
        for words, payload in cands or ():
            j, ok = i, True
            for w in words:
                while j < self.n and j > i and self.words[j] != w and self.claimed[j] is None and self._inserted(j):
                    j += 1
                if j < self.n and self.words[j] == w and self.claimed[j] is None:
                    j += 1
                else:
                    ok = False
                    break
            if ok:
                return payload, j
        return None

    def _inserted(self, j: int) -> bool:
        w = self.words[j]
        return w in lx.INSERTS or w in lx.AGENT_INSERTS or (_is_adverb(w) and w not in lx.VOCAB)

    def _skip(self, i: int, allowed: set[str] | frozenset[str], limit: int = 4) -> int:
        k = 0
        while i < self.n and k < limit and self.claimed[i] is None and self.words[i] in allowed:
            i += 1
            k += 1
        return i

    def _distance(self, i: int) -> tuple[float, int] | None:
        """'10 m', 'ten metres', '5.5 ft' at i -> (metres, index after)."""
        if i + 1 >= self.n:
            return None
        w = self.words[i]
        value = None
        if re.fullmatch(r"\d+(?:\.\d+)?", w):
            value = float(w)
        elif w in lx.NUMBER_WORDS:
            value = float(lx.NUMBER_WORDS[w])
        if value is None or self.words[i + 1] not in lx.UNITS:
            return None
        return value * lx.UNITS[self.words[i + 1]], i + 2

    def is_subject(self, m: Mention) -> bool:
        """Whether a linking verb follows the mention ("roads are ...", "sand is better"), so it
        is the subject of its own predicate and no list before it runs on into it."""
        j = m.end
        while j < self.n and self.words[j] in lx.INSERTS:
            j += 1
        if j < self.n and self.words[j] in lx.COPULAS:
            return True
        return (
            j + 1 < self.n
            and self.words[j] in ("should", "would", "will", "could", "might")
            and (self.words[j + 1] in lx.COPULAS)
        )

    def in_situation(self, m: Mention) -> bool:
        """Whether the mention is the subject of a state ("the road is blocked")."""
        j = m.end
        while j < self.n and (self.words[j] in lx.COPULAS or self.words[j] in lx.INSERTS):
            j += 1
        return j > m.end and j < self.n and self.words[j] in lx.STATE_WORDS

    def object_of_trigger(self, m: Mention) -> bool:
        """Whether a trigger stands right before the mention (articles aside): its object."""
        j = m.start - 1
        while j >= 0 and self.words[j] in lx.ARTICLES:
            j -= 1
        return j >= 0 and any(f.kind == "trigger" and f.end == j + 1 for f in self.found)

    def _compares_on(self, m: Mention) -> bool:
        """Whether a comparison word follows the mention ("..., and the grass to the bushes"):
        it is the left side of the next comparison, not the end of this list."""
        j = m.end
        return j < self.n and self.claimed[j] is None and self.words[j] in lx.SOFT_COMPARATORS

    def _list_forward(self, i: int) -> tuple[list[Mention], int]:
        """Entity list starting at i (articles skipped): 'the roads, trails and paths'. A
        mention that is the subject of its own predicate ("..., and sand is better") ends it."""
        out: list[Mention] = []
        j = self._skip(i, lx.ARTICLES)
        m = self.mention_at.get(j)
        if m is None or m.role != "target":
            return [], i
        out.append(m)
        end = m.end
        while True:
            k = end
            while k < self.n and self.words[k] in lx.LIST_GLUE and self.claimed[k] is None:
                k += 1
            if k == end:
                break
            k = self._skip(k, lx.ARTICLES)
            nxt = self.mention_at.get(k)
            if nxt is None or nxt.role != "target" or self.is_subject(nxt) or self._compares_on(nxt):
                break
            out.append(nxt)
            end = nxt.end
        return out, end

    def _list_backward(self, i: int) -> list[Mention]:
        """Entity list ending just before i, skipping fillers and triggers: 'roads and trails are'."""
        j, skipped = i - 1, 0
        while (
            j >= 0
            and skipped < 6
            and self.claimed[j] != "mention"
            and (self.words[j] in lx.FILLER or self.words[j] in lx.VOCAB or self.words[j] == ",")
            and self.words[j] not in lx.SEPARATORS - lx.JOINERS  # "B but better than C": not B
        ):
            j -= 1
            skipped += 1
        ends = {m.end - 1: m for m in self.mentions}
        out: list[Mention] = []
        # "A over B over C": B is the right side of one comparison and the left of the next
        while j >= 0 and j in ends and ends[j].role in ("target", "right"):
            m = ends[j]
            out.insert(0, m)
            k = m.start - 1
            while k >= 0 and self.words[k] in lx.ARTICLES:
                k -= 1
            if k >= 0 and self.words[k] in lx.JOINERS and self.claimed[k] is None:
                k -= 1
                while k >= 0 and self.words[k] in lx.ARTICLES | {","} and self.claimed[k] is None:
                    k -= 1
                j = k
            else:
                break
        return out

    def _claim(self, f: Found, role: str) -> None:
        for j in range(f.start, f.end):
            if self.claimed[j] is None:
                self.claimed[j] = role
        self.found.append(f)

    # -- constructs
    def _claim_all(self) -> None:  # noqa: C901
        for i in range(self.n):  # conditions: unless/if ... near X
            hit = self._match(lx.CONDITIONS, i)
            if not hit:
                continue
            j0 = i + len(hit[0])
            j = self._skip(j0, (lx.FILLER | lx.CONDITION_VERBS) - {"near", "by", "along", "around", "within"})
            kind = hit[1]
            if j < self.n and self.words[j] in lx.CONDITION_NEGATORS and kind in ("if_near", "unless_near"):
                # "as long as it's not near the water" = unless near it; "unless it is not near" = if
                kind = "unless_near" if kind == "if_near" else "if_near"
                j = self._skip(j + 1, (lx.FILLER | lx.CONDITION_VERBS) - {"near", "by", "along", "around", "within"})
            metres = None
            prox = self._match(lx.PROXIMITY, j)
            if prox:
                j += len(prox[0])
            elif j < self.n and self.words[j] == "within" and (d := self._distance(j + 1)):
                metres, j = d[0], d[1]
                if j < self.n and self.words[j] in ("of", "from"):
                    j += 1
            elif (
                hit[1] in ("unless_near", "only_at")
                and any(w in lx.EXCEPT_PREPS for w in self.words[j0:j])
                and (hit[1] != "only_at" or any(m.end <= i for m in self.mentions))
            ):
                # ("only on roads" with nothing before it to restrict is a preference for roads)
                pass  # "except at level crossings": the exception is where the other entity is
            else:
                continue
            lst, end = self._list_forward(j)
            if not lst:
                continue
            for m in lst:
                m.role = "cond"
            self._claim(Found("condition", i, end, kind, tuple(lst), metres), "cond")
        for i in range(self.n):
            self._cue_at(i)
        for i in range(self.n):
            self._comparator_at(i)
        for kind, table in (("modifier", lx.MODIFIERS), ("trigger", lx.TRIGGERS), ("marker", lx.MARKERS)):
            i = 0
            while i < self.n:
                hit = self._match_loose(table, i)
                if hit:
                    self._claim(Found(kind, i, hit[1], hit[0]), kind)
                    i = hit[1]
                else:
                    i += 1

    def _cue_at(self, i: int) -> None:  # noqa: C901
        if self.claimed[i] is not None and self.claimed[i] != "mention":
            return
        w = self.words[i]
        m = self.mention_at.get(i)
        if m is not None and m.role == "side":  # "roadside"
            m.role = "target"
            self._claim(Found("cue", i, i + 1, "side", (m,)), "cue")
            return
        if self.claimed[i] == "mention":
            # postfix: "road centre line", "road edge"
            if m is not None and m.end < self.n and self.claimed[m.end] is None:
                nxt = self.words[m.end]
                if nxt in lx.CENTRE | lx.SIDE:
                    end = m.end + 1 + (m.end + 1 < self.n and self.words[m.end + 1] == "line")
                    self._claim(Found("cue", m.end, end, "centre" if nxt in lx.CENTRE else "side", (m,)), "cue")
            return
        if w in lx.CENTRE | lx.SIDE:  # "(the) centre (line) of (the) road"
            j = i + 1
            if j < self.n and self.words[j] == "line":
                j += 1
            if j < self.n and self.words[j] == "of":
                lst, end = self._list_forward(j + 1)
                if lst:
                    self._claim(Found("cue", i, end, "centre" if w in lx.CENTRE else "side", tuple(lst)), "cue")
            return
        metres, hard, need_by = None, False, False
        if far := self._match(lx.FAR_WORDS, i):
            j, kind = i + len(far[0]), "far"
        elif near := self._match(lx.NEAR, i):
            j, kind = i + len(near[0]), "near"
        elif tuple(self.words[i : i + 2]) == ("away", "from") and self._free(i, i + 2):
            j, kind, need_by = i + 2, "far", True  # "keep away from buildings by 20 m"
        elif dist := self._distance_phrase(i):
            kind, metres, hard, j = dist
        else:
            return
        lst, end = self._list_forward(j)
        if not lst:
            return
        if metres is None and end < self.n and self.words[end] == "by" and (d := self._distance(end + 1)):
            metres, end = d[0], d[1]
        elif need_by:
            return  # plain "keep away from X" is the avoid trigger
        for mm in lst:
            mm.role = "cue"
        self._claim(Found("cue", i, end, kind, tuple(lst), metres, hard=hard), "cue")

    def _distance_phrase(self, i: int) -> tuple[str, float | None, bool, int] | None:  # noqa: C901
        """A distance to or from something, up to its "from/of/to": (kind, metres, hard, index).

        "at least 20 m from", "no closer than 15 m to", "a minimum distance of 20 m from" (far,
        hard); "within 50 m of", "no more than 50 m from" (near, hard); "20 m away from", "a
        20 m buffer around", "a safe distance from" (far, soft).
        """
        words, n, k = self.words, self.n, i
        hard = noun = False
        if k < n and words[k] in ("a", "an"):
            k += 1
        if k < n and words[k] in lx.MIN_WORDS:
            hard = words[k] != "safe"
            k += 1
        if k < n and words[k] in lx.GAP_NOUNS:
            noun = True
            k += 1
            if k < n and words[k] == "of":
                k += 1
        elif k > i:
            return None
        kind = "far"
        for size in (3, 2, 1):
            bound = tuple(words[k : k + size])
            if len(bound) == size and (bound in lx.FAR_BOUNDS or bound in lx.NEAR_BOUNDS) and self._free(k, k + size):
                kind, hard = ("far" if bound in lx.FAR_BOUNDS else "near"), True
                k += size
                break
        d = self._distance(k)
        if d is None:
            if noun and k < n and words[k] in ("from", "to", "around") and kind == "far":
                return "far", None, hard, k + 1  # "keep a safe distance from the water"
            return None
        j = d[1]
        if j < n and words[j] in lx.GAP_NOUNS:
            j += 1
        if j < n and words[j] == "away":
            j += 1
        if j < n and words[j] in ("from", "of", "to", "around"):
            return kind, d[0], hard, j + 1
        return None

    def _comparator_at(self, i: int) -> None:
        """Comparisons: a comparator phrase ("better than", "worse than", "rather than") between
        two entity lists; "prefer X over/to Y"; "X over Y" between two entities (chains: "A over
        B over C"); and the split "rather/sooner X than Y"."""
        start = i
        hit = self._match(lx.COMPARATORS, i) or self._adjective_comparison(i)
        if hit:
            words, kind = hit
        elif (
            self.words[i] in lx.SOFT_COMPARATORS
            and self.claimed[i] is None
            and (
                any(w in lx.PREFER_VERBS for w in self.words[:i])  # "prefer A to B, and B to C"
                or (self.words[i] == "over" and self._between_entities(i))
            )
        ):
            words, kind = (self.words[i],), lx.SOFT_COMPARATORS[self.words[i]]
        elif self.words[i] == "than" and self.claimed[i] is None and (opener := self._rather_before(i)) is not None:
            words, kind, start = ("than",), "better", opener
        else:
            return
        # "than go through the forest", "rather than by trail": the verb and preposition of the
        # first side, repeated
        j = self._skip(i + len(words), lx.PASSAGE_VERBS, limit=3)
        right, end = self._list_forward(j)
        left = self._list_backward(i)
        if not left and start == i:
            # "A is worse than B but better than C", "grass is fine but worse than trails": the
            # subject again (of the last comparison, else of the last linking verb)
            earlier = [f for f in self.found if f.kind == "comparator" and f.end <= i]
            subjects = [m for m in self.mentions if m.end <= i and self.is_subject(m)]
            left = list(earlier[-1].left) if earlier else subjects[-1:]
        if not right or not left:
            return
        for m in right:
            m.role = "right"
        self._claim(Found("comparator", start, end, kind, tuple(right), left=tuple(left)), "comparator")

    def _adjective_comparison(self, i: int) -> tuple[tuple[str, ...], str] | None:
        """ "less risky than", "more pleasant than", "safer than", "muddier than": the comparison
        an adjective's valence (lexicon.VALENCE) and its degree make, as (words, better|worse)."""
        w = self.words
        if not self._free(i, min(self.n, i + 3)):
            return None
        if w[i] in ("more", "less") and i + 2 < self.n and w[i + 2] == "than" and w[i + 1] in lx.VALENCE:
            sign = lx.VALENCE[w[i + 1]] * (1 if w[i] == "more" else -1)
            return (w[i], w[i + 1], "than"), "better" if sign > 0 else "worse"
        if i + 1 < self.n and w[i + 1] == "than":
            base = _comparative_base(w[i])
            if base is not None:
                return (w[i], "than"), "better" if lx.VALENCE[base] > 0 else "worse"
        return None

    def _between_entities(self, i: int) -> bool:
        """Whether word i stands right between two entity mentions (articles aside)."""
        before = i - 1
        while before >= 0 and self.words[before] in lx.ARTICLES:
            before -= 1
        after = self._skip(i + 1, lx.ARTICLES)
        return any(m.end - 1 == before for m in self.mentions) and after in self.mention_at

    def _rather_before(self, i: int) -> int | None:
        """Index of an unclaimed "rather"/"sooner" before "than" at i, with an entity between."""
        for k in range(i - 1, max(-1, i - 10), -1):
            if self.words[k] in lx.RATHER_WORDS and self.claimed[k] is None:
                return k if any(k < m.start < i for m in self.mentions) else None
        return None

    def _joins(self) -> None:
        """Mark and/or/commas between two entities as list glue (not clause boundaries)."""
        chain = 0
        ordered = self.mentions
        for idx, m in enumerate(ordered):
            if m.chain < 0:
                m.chain = chain
                chain += 1
            if idx + 1 >= len(ordered):
                break
            nxt = ordered[idx + 1]
            between = range(m.end, nxt.start)
            words = [self.words[j] for j in between]
            if (
                words
                and all(
                    self.claimed[j] is None and (w in lx.LIST_GLUE or w in lx.ARTICLES) for j, w in zip(between, words)
                )
                and any(w in lx.JOINERS for w in words)
                # "prefer vegetation, roads are a last resort", "..., and the lake is off limits":
                # a comma before a subject ends the list; "the parking lot and the lawns are ok"
                # stays one (plural) subject
                and not (self.is_subject(nxt) and "," in words)
            ):
                nxt.chain = m.chain
                for j in between:
                    self.claimed[j] = "join"


# ----------------------------------------------------------------------------- prompt analysis


@dataclass
class _State:
    prompt: str
    mentioned: list[str] = field(default_factory=list)
    statements: dict[str, list[str]] = field(default_factory=dict)  # name -> tiers, in order
    weights: dict[str, tuple[float, bool]] = field(default_factory=dict)
    cues: list[Cue] = field(default_factory=list)
    constraints: list[tuple[str, str, str]] = field(default_factory=list)  # (kind, a, b)
    unparsed: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    #: entity -> the prompt's words of its last statement / of each comparison naming it
    said: dict[str, str] = field(default_factory=dict)
    compared: dict[str, list[str]] = field(default_factory=dict)
    #: entity -> the phrase(s) its stated preference came from (what merge.finalize shows)
    phrases: dict[str, str] = field(default_factory=dict)

    def mention(self, name: str) -> None:
        if name not in self.mentioned:
            self.mentioned.append(name)

    def state(self, name: str, tier: str, phrase: str = "") -> None:
        self.mention(name)
        self.statements.setdefault(name, []).append(tier)
        self.said[name] = phrase

    def compare(self, names: Iterable[str], phrase: str) -> None:
        for name in names:
            if phrase not in self.compared.setdefault(name, []):
                self.compared[name].append(phrase)

    def fragment(self, text: str) -> None:
        text = text.strip(" ,;:.")
        if text and text not in self.unparsed:
            self.unparsed.append(text)


def _split_clauses(sent: _Sentence, s_index: int) -> list[Clause]:
    clauses: list[Clause] = []
    start = 0
    seps: set[str] = set()
    alternatives = sent.alternatives  # "... as a last resort otherwise use the pavement"
    for j in range(sent.n + 1):
        separator = j < sent.n and sent.claimed[j] is None and sent.words[j] in lx.SEPARATORS
        if not (j == sent.n or separator or (j in alternatives and j > start)):
            continue
        if j > start:
            clauses.append(Clause(s_index, start, j, sent.toks, seps))
            seps = set()
        if separator:
            seps.add(sent.words[j])
            start = j + 1
        else:
            start = j  # the marker opens the next clause
    for c in clauses:
        c.found = [f for f in sent.found if c.start <= f.start < c.end]
        c.targets = [m for m in sent.mentions if c.start <= m.start < c.end and m.role == "target"]
        c.markers = {f.value for f in c.found if f.kind == "marker"}
        if c.seps & lx.SEQ_SEPARATORS:
            c.markers.add("next")
    return clauses


def _polarity(members: list[Found], words: list[str]) -> str | None:
    """The tier of adjacent triggers read together.

    Negation scopes over the verb it stands with, so the meaning is composed, not listed:
    a ``leave`` verb ("leave", "stray from", "get off", "wander off") avoids its object, and
    negated ("don't stray from the road", "never leave the trail") keeps to it; a ``cross``
    verb says nothing by itself ("cross the railway only at level crossings" is read by the
    condition), and negated ("do not cross", "never cross", "must not cross") is the nocross
    rule, or a soft avoid when the negation is a wish ("avoid crossing", "try not to cross").
    Otherwise the most severe trigger wins ("don't use" = avoid, "never use" = lethal). None
    when the group says nothing by itself.
    """
    verbs = {f.value for f in members if f.value in lx.VERB_TIERS}
    others = [f for f in members if f.value not in lx.VERB_TIERS]
    negators = [f for f in others if tuple(words[f.start : f.end]) in lx.NEGATORS]
    if "leave" in verbs:
        return "prefer" if negators else "avoid"
    if "cross" in verbs and negators:
        soft = any(tuple(words[f.start : f.end]) in lx.SOFT_NEGATORS for f in negators)
        return "avoid" if soft else "nocross"
    if "enter" in verbs and negators:
        return "avoid"
    if not others:
        return None
    return max(others, key=lambda f: lx.SEVERITY[f.value]).value


def _groups(clause: Clause) -> list[tuple[int, int, str]]:
    """Trigger groups (start, end, tier): adjacent triggers with no entity between combine
    (their tier composed by :func:`_polarity`)."""
    trig = sorted((f for f in clause.found if f.kind == "trigger"), key=lambda f: f.start)
    mods = {f.value for f in clause.found if f.kind == "modifier"}
    mention_pos = sorted(m.start for m in clause.targets)
    members: list[list[Found]] = []
    for f in trig:
        if members and not any(members[-1][-1].end <= p < f.start for p in mention_pos):
            members[-1].append(f)
        else:
            members.append([f])
    words = [t.word for t in clause.toks]
    tiers = [(group, _polarity(group, words)) for group in members]
    groups: list[list] = [[g[0].start, g[-1].end, tier] for g, tier in tiers if tier is not None]
    for tier in ("lethal", "tolerable"):  # "the river, at all costs"; "trees if necessary"
        if not groups and tier in mods:
            f = next(f for f in clause.found if f.kind == "modifier" and f.value == tier)
            groups.append([f.start, f.end, tier])
    for g in groups:
        if "lethal" in mods and lx.SEVERITY[g[2]] >= lx.SEVERITY["avoid"] and g[2] != "nocross":
            g[2] = "lethal"
        elif "strong" in mods and g[2] == "avoid":
            g[2] = "avoid+"
        elif "tolerable" in mods and lx.SEVERITY[g[2]] < lx.SEVERITY["tolerable"]:
            g[2] = "tolerable"
    return [tuple(g) for g in groups]


def _nearest(groups, m: Mention, sent: _Sentence | None = None) -> int:
    """The trigger group an entity takes: the subject of a linking verb takes the predicate
    right after it ("prefer vegetation, roads are a last resort"), the object of a trigger that
    trigger ("prefer the gravel avoid the mud"); otherwise the nearest group (ties to the one
    before the entity)."""
    if sent is not None and sent.is_subject(m):
        after = [gi for gi, (a, _, _) in enumerate(groups) if m.end <= a <= m.end + 5]
        if after:
            return after[0]
    if sent is not None and sent.object_of_trigger(m):  # "prefer the gravel avoid the mud"
        j = m.start
        while j > 0 and sent.words[j - 1] in lx.ARTICLES:
            j -= 1
        before = [gi for gi, (_, b, _) in enumerate(groups) if b == j]
        if before:
            return before[-1]
    best, best_d = 0, None
    for gi, (a, b, _) in enumerate(groups):
        d = (m.start - b + 1) if b <= m.start else (a - m.end + 1) if a >= m.end else 0
        d = d * 2 + (0 if b <= m.start else 1)  # ties go to the trigger before the entity
        if best_d is None or d < best_d:
            best, best_d = gi, d
    return best


def _analyse_clause(st: _State, sent: _Sentence, c: Clause, prev: Clause | None) -> None:  # noqa: C901
    groups = _groups(c)
    used_groups: set[int] = set()
    known_chains = {m.chain for m in c.targets if m.known}
    targets = []
    for m in c.targets:
        if sent.in_situation(m):  # "only if the road is blocked": a situation, not a preference
            continue
        # unknown words beside known entities are not names (reported), unless a trigger takes
        # them as its object ("prefer the gravel avoid the mud")
        if m.known or not known_chains or m.chain in known_chains or sent.object_of_trigger(m):
            targets.append(m)
        else:
            c.leftover.extend(range(m.start, m.end))
    text = c.text(st.prompt)
    cues = [f for f in c.found if f.kind == "cue"]
    softened = any(sent.words[j] in lx.SOFTENERS for j in range(c.start, c.end)) or any(
        f.kind == "modifier" and f.value == "soft" for f in c.found
    )
    near_objs = [m for f in cues if f.value in ("near", "far") for m in f.mentions]
    centre_side = [(f.value, m, f) for f in cues if f.value in ("centre", "side") for m in f.mentions]
    for f in c.found:  # every cue object and comparison side counts as a mention
        for m in f.mentions + f.left:
            st.mention(m.name)
    if not targets and groups and not near_objs and not centre_side:
        referred = (list(prev.assigned) or [m.name for m in prev.targets]) if prev else []
        pronouns = [j for j in range(c.start, c.end) if sent.words[j] in lx.PRONOUNS]
        if prev is not None and referred and pronouns:  # (referred is empty without prev)
            for name in referred:
                c.assigned[name] = groups[0][2]
                c.src[name] = (prev, c)
                c.took(name, groups[0][:2], (pronouns[-1], pronouns[-1] + 1))
            used_groups.add(0)
            prev.referenced = True  # "There is a pond. Avoid it.": the first clause is context
    group_of = {}
    for m in targets:
        if groups:
            gi = _nearest(groups, m, sent)
            used_groups.add(gi)
            c.assigned[m.name] = groups[gi][2]
            group_of[m.name] = gi
    for m in targets:  # "prefer the roads and trails": the trigger and its list
        if m.name in group_of:
            gi = group_of[m.name]
            c.took(m.name, groups[gi][:2], *[(t.start, t.end) for t in targets if group_of.get(t.name) == gi])
    for f in c.found:
        if f.kind == "condition" and f.value == "only_at" and targets:
            _only_at(f, c, [m.name for m in targets], sent.words[c.start : c.end])
    for kind, m, cf in centre_side:
        st.mention(m.name)
        if lx.geometry_of(m.name) != "linear":
            st.notes.append(f"'{kind} of {m.name}' needs a linear entity ({m.name} is areal); ignored")
            st.fragment(text)
            continue
        st.cues.append(Cue(kind, m.name))
        if m.name not in c.assigned:
            if groups:
                gi = _nearest(groups, m)
                used_groups.add(gi)
                c.assigned[m.name] = groups[gi][2]
                c.took(m.name, groups[gi][:2], (cf.start, cf.end), (m.start, m.end))
            else:  # "on the side of the road": travelling on it
                c.assigned[m.name] = "prefer"
                c.took(m.name, (cf.start, cf.end), (m.start, m.end))
    for f in cues:
        if f.value not in ("near", "far"):
            continue
        metres = f.metres if f.metres is not None else lx.DEFAULT_CUE_DISTANCE_M
        others = [m for m in targets if m.name not in {o.name for o in f.mentions}]
        hard = f.hard and not softened
        for obj in f.mentions:
            if f.value == "far":
                st.cues.append(Cue("far", obj.name, metres, hard=hard))
            elif others:  # "avoid grass near roads": grass's preference applies near roads
                for t in others:
                    st.cues.append(Cue("if_near", t.name, metres, obj.name))
            else:
                near_gi = _nearest(groups, obj) if groups else None
                if near_gi is not None and lx.SEVERITY[groups[near_gi][2]] >= lx.SEVERITY["avoid"]:
                    # "avoid going near buildings": keep away, and off them
                    used_groups.add(near_gi)
                    # "never go within 10 m of X" is a rule; "avoid going within ..." a wish
                    a, b, _ = groups[near_gi]
                    wish = any(sent.words[k] in lx.AVOID_WORDS for k in range(a, b))
                    rule = hard and not wish
                    st.cues.append(Cue("far", obj.name, metres, hard=rule))
                    # the rule's keep-out zone covers X itself; lethal would forbid what the
                    # rule allows when no route exists otherwise, so X is strongly avoided
                    tier = groups[near_gi][2]
                    c.assigned[obj.name] = "avoid+" if rule and tier == "lethal" else tier
                    c.took(obj.name, (a, b), (f.start, f.end))
                else:
                    if near_gi is not None:
                        used_groups.add(near_gi)
                    st.cues.append(Cue("near", obj.name, metres, hard=hard))
    for f in c.found:
        if f.kind == "comparator":
            a_char = sent.toks[min([c.start] + [m.start for m in f.left])].start
            st.compare([m.name for m in f.left + f.mentions], st.prompt[a_char : sent.toks[f.end - 1].end].strip())
            for a in f.left:
                for b in f.mentions:
                    if f.value == "better":
                        st.constraints.append(("lt", a.name, b.name))
                    elif f.value == "worse":
                        st.constraints.append(("lt", b.name, a.name))
                    else:
                        st.constraints.append(("eq", a.name, b.name))
    said = set(c.assigned.values())
    for gi, (a, b, tier) in enumerate(groups):
        if gi not in used_groups and tier not in said:  # "go through the grass instead": restated
            c.leftover.extend(range(a, b))
    for j in range(c.start, c.end):
        if (
            sent.claimed[j] is None
            and sent.words[j] not in lx.FILLER
            and sent.words[j] not in lx.SEPARATORS
            and sent.words[j] not in lx.ARTICLES
        ):
            if sent.words[j] in ("if", "unless", "when", "except", "whenever", "where"):
                st.fragment(st.prompt[c.toks[j].start : c.toks[c.end - 1].end])
                continue
            c.leftover.append(j)
    has_meaning = bool(c.assigned) or bool(cues) or any(f.kind == "comparator" for f in c.found)
    if not has_meaning and not targets and not any(f.kind == "condition" for f in c.found):
        if any(
            sent.claimed[j] not in (None,) or sent.words[j] not in lx.FILLER for j in range(c.start, c.end)
        ) and not (c.markers and c.end - c.start <= 2):
            c.whole_unparsed = True


def _only_at(f: Found, owner: Clause, names: list[str], words: list[str]) -> None:
    """ "X only at/near Y". Nothing stated or a permission makes X forbidden except near Y: a
    crossing ("cross the railway only at level crossings", "you may wade through the river only
    near the ford") as the nocross rule, any other passage as impassable; a crossing after a
    stated tier ("avoid water, only cross at the bridge") keeps X's tier except near Y; any
    other stated preference ("avoid the river, but only near the village") holds only near Y.
    ``words``: the words of the clause that says "only"."""
    if all(owner.assigned.get(n, "fine") == "fine" for n in names):
        # a crossing allowed only there is the nocross rule (as "never cross X except at Y");
        # any other passage allowed only there makes X impassable elsewhere
        crossing = any(w in lx.CROSS_VERBS for w in words)
        for n in names:
            owner.assigned[n] = "nocross" if crossing else "lethal"
        f.value = "unless_near"
    elif any(w in lx.CROSS_VERBS for w in words):
        f.value = "unless_near"
    else:
        f.value = "if_near"


def _report_leftovers(st: _State, sent: _Sentence, c: Clause) -> None:
    if c.whole_unparsed:
        if not c.referenced:
            st.fragment(c.text(st.prompt))
        return
    idx = sorted(set(c.leftover))
    run: list[int] = []
    for j in idx:
        if run and any(sent.words[k] not in lx.FILLER and k not in idx for k in range(run[-1] + 1, j)):
            st.fragment(st.prompt[c.toks[run[0]].start : c.toks[run[-1]].end])
            run = []
        run.append(j)
    if run:
        st.fragment(st.prompt[c.toks[run[0]].start : c.toks[run[-1]].end])


def _neighbour_tier(c: Clause, prev: Clause | None, nxt: Clause | None) -> tuple[str | None, Clause]:
    """The tier a clause of bare entities takes, and the clause it came from: the previous
    clause's trailing trigger ("avoid water, buildings"), a predicate standing alone before it
    ("..., as a last resort, roads"; "Off limits: the school"), the next clause's leading trigger
    ("trees: avoid"), else the previous clause's last trigger; None when no neighbour has one."""
    if prev is not None and prev.assigned and _groups(prev):
        if not prev.targets or _groups(prev)[-1][0] < prev.targets[0].start:
            return _groups(prev)[-1][2], prev
    if prev is not None and not prev.targets and not prev.assigned and _groups(prev):
        a, b, tier = _groups(prev)[-1]
        prev.leftover = [j for j in prev.leftover if not a <= j < b]
        prev.whole_unparsed = False
        return tier, prev
    if (
        nxt is not None
        and _groups(nxt)
        and not nxt.markers & {"next", "alt"}
        and (not nxt.targets or _groups(nxt)[0][0] > nxt.targets[0].start)
    ):
        a, b, tier = _groups(nxt)[0]
        nxt.leftover = [j for j in nxt.leftover if not a <= j < b]
        nxt.whole_unparsed = False
        return tier, nxt
    if prev is not None and prev.assigned and _groups(prev):
        return _groups(prev)[-1][2], prev
    return None, c


def _attach_bare(clauses: list[Clause], st: _State) -> None:
    """A clause of bare entities takes its neighbour's tier (:func:`_neighbour_tier`)."""
    for i, c in enumerate(clauses):
        if (
            c.assigned
            or not c.targets
            or c.whole_unparsed
            or c.markers & {"next", "alt", "start"}
            or any(f.kind in ("cue", "comparator") for f in c.found)
        ):
            continue
        prev = clauses[i - 1] if i > 0 and clauses[i - 1].sent == c.sent else None
        if prev is not None and c.seps & lx.CONTRASTIVE:
            prev = None  # "never enter the buildings, but the parking lot ...": no tier carries over
        # "Off limits: the school": a label before a colon names what it applies to, known or not
        labelled = prev is not None and ":" in c.seps and not prev.targets and bool(_groups(prev))
        if not labelled and not any(m.known for m in c.targets):
            c.whole_unparsed = True
            continue
        nxt = clauses[i + 1] if i + 1 < len(clauses) and clauses[i + 1].sent == c.sent else None
        choice, source = _neighbour_tier(c, prev, nxt)
        if choice is None:
            c.whole_unparsed = True
            continue
        for m in c.targets:
            c.assigned[m.name] = choice
            c.src[m.name] = (source, c)


def _conditions(sentence_clauses: list[Clause], st: _State) -> None:
    """Attach 'unless/if near X' to the clause it qualifies (its own, else the next/previous)."""
    for i, c in enumerate(sentence_clauses):
        for f in c.found:
            if f.kind != "condition":
                continue
            owner = c if c.assigned else None
            if owner is None:
                later = [d for d in sentence_clauses[i + 1 :] if d.assigned]
                earlier = [d for d in sentence_clauses[:i] if d.assigned]
                owner = later[0] if later else earlier[-1] if earlier else None
            if owner is None:
                st.fragment(st.prompt[c.toks[f.start].start : c.toks[f.end - 1].end])
                continue
            if f.value == "only_at":
                _only_at(f, owner, list(owner.assigned), [t.word for t in c.toks[c.start : c.end]])
            metres = f.metres if f.metres is not None else lx.DEFAULT_CUE_DISTANCE_M
            for name in owner.assigned:
                if owner is not c:  # "Unless near the road, stay off the grass"
                    first, last = owner.src.get(name, (owner, owner))
                    owner.src[name] = (
                        min(first, c, key=lambda d: d.span()[0]),
                        max(last, c, key=lambda d: d.span()[1]),
                    )
                for other in f.mentions:
                    st.mention(other.name)
                    st.cues.append(Cue(str(f.value), name, metres, other.name))


def _sequences(clauses: list[Clause]) -> list[list[Clause]]:
    seqs: list[list[Clause]] = []
    current: list[Clause] | None = None
    for i, c in enumerate(clauses):
        if "start" in c.markers:
            current = [c]
            seqs.append(current)
        elif c.markers & {"next", "alt"}:
            if current is None:
                # "X. Otherwise Y": X leads only if the prompt said something of it; a bare or
                # unread clause before an alternative is not made preferred by it
                before = clauses[i - 1] if i > 0 else None
                lead = before is not None and (
                    "next" in c.markers
                    or any(t == "prefer" or t.startswith("order:") for t in before.assigned.values())
                )
                current = [before] if lead and before is not None else []
                seqs.append(current)
            current.append(c)
        else:
            current = None
    # "meadows first, ...": a first choice stated alone is still a preference
    return [s for s in seqs if len(s) > 1 or (len(s) == 1 and "start" in s[0].markers)]


def _apply_sequences(clauses: list[Clause], st: _State) -> set[int]:
    """First X, then Y, then Z: positive (or bare) steps get PREFER, PREFER+STEP, ..."""
    in_seq: set[int] = set()
    for seq in _sequences(clauses):
        pos = 0
        for c in seq:
            in_seq.add(id(c))
            if not c.assigned and c.targets:
                for m in c.targets:
                    c.assigned[m.name] = "prefer"
                c.whole_unparsed = False
            # preferred or allowed steps are ordered; a last resort stays one ("then the mud, only as
            # a last resort" is not made preferred by its place in the list)
            positive = [n for n, t in c.assigned.items() if lx.SEVERITY[t] <= lx.SEVERITY["fine"]]
            if not positive:
                continue
            w = min(lx.PREFER + pos * lx.STEP, lx.ORDER_MAX)
            for n in positive:
                c.assigned[n] = f"order:{w:.2f}"
                c.src[n] = (seq[0], c)  # "first roads, then trails": the ordering so far
                c.tok_src.pop(n, None)
            pos += 1
    return in_seq


def _weight_of(tier: str) -> tuple[float, bool]:
    if tier.startswith("order:"):
        return float(tier.split(":", 1)[1]), False
    return lx.TIERS[tier]


def _resolve_weights(st: _State) -> None:  # noqa: C901
    explicit: set[str] = set()
    for name, stmts in st.statements.items():
        tier = stmts[-1]
        st.weights[name] = _weight_of(tier)
        explicit.add(name)
        earlier = {t for t in stmts[:-1] if _weight_of(t) != _weight_of(tier)}
        if earlier:
            st.notes.append(
                f"'{name}': the last statement ({_tier_label(tier)}) overrides an "
                f"earlier one ({', '.join(sorted(_tier_label(t) for t in earlier))})"
            )
    if not st.constraints:
        return
    for _ in range(2 * len(st.constraints) + 1):  # bounded propagation
        changed = False
        for kind, a, b in st.constraints:
            wa = st.weights.get(a)
            wb = st.weights.get(b)
            if kind == "eq":
                if wb is not None and wa != wb and (a not in explicit or wa is None):
                    st.weights[a], changed = wb, True
                elif wa is not None and wb is None:
                    st.weights[b], changed = wa, True
                continue
            if wa is None and wb is None:
                st.weights[a] = (lx.NEUTRAL - lx.STEP, False)
                st.weights[b] = (lx.NEUTRAL, False)
                changed = True
            elif wa is None:  # the unstated side moves off neutral only as far as it must
                assert wb is not None  # both None is the branch above
                st.weights[a] = (max(0.0, min(lx.NEUTRAL, round(wb[0] - lx.STEP, 6))), False)
                changed = True
            elif wb is None:  # "prefer the bridge over the ford": the ford is not made good
                st.weights[b] = (min(0.99, max(lx.NEUTRAL, round(wa[0] + lx.STEP, 6))), False)
                changed = True
            elif wa[1] and not wb[1]:
                continue  # reported below
            elif wb[1] or wa[0] < wb[0]:
                continue
            elif b not in explicit or a in explicit and wa[0] + lx.STEP <= 0.99:
                st.weights[b] = (min(0.99, round(wa[0] + lx.STEP, 6)), False)
                changed = True
            else:
                st.weights[a] = (max(0.0, round(wb[0] - lx.STEP, 6)), False)
                changed = True
        if not changed:
            break
    for kind, a, b in st.constraints:
        wa, wb = st.weights[a], st.weights[b]
        bad = (kind == "lt" and not (wb[1] and not wa[1] or (wa[1] == wb[1] and wa[0] < wb[0]))) or (
            kind == "eq" and wa != wb
        )
        if bad:
            rel = "better than" if kind == "lt" else "as good as"
            st.notes.append(f"could not make '{a}' {rel} '{b}' (conflicting statements)")


def _tier_label(tier: str) -> str:
    return "order" if tier.startswith("order:") else tier


def _note_readings(sent: _Sentence, st: _State) -> None:
    """Say how words were read as entities by spelling or alias ("read 'woods' as 'forest'")."""
    for word, name, how in sent.readings:
        note = f"read '{word}' as '{name}'" + (" (spelling)" if how == "spelling" else "")
        if note not in st.notes:
            st.notes.append(note)


def analyse(prompt: str) -> _State:
    """Read a prompt into statements, cues, orderings and leftovers (no defaults yet)."""
    st = _State(prompt)
    clauses: list[Clause] = []
    sents: list[_Sentence] = []
    for si, toks in enumerate(sentences(tokenize(prompt))):
        sent = _Sentence(toks)
        sents.append(sent)
        own = _split_clauses(sent, si)
        prev = clauses[-1] if clauses else None
        for c in own:
            _analyse_clause(st, sent, c, prev)
            prev = c
        _attach_bare(own, st)
        _conditions(own, st)
        clauses.extend(own)
        _note_readings(sent, st)
    _apply_sequences(clauses, st)
    for c in clauses:
        for name, tier in c.assigned.items():
            st.state(name, tier, c.phrase(name, prompt))
            if tier == "nocross" and Cue("no_cross", name, hard=True) not in st.cues:
                st.cues.append(Cue("no_cross", name, hard=True))
        _report_leftovers(st, sents[c.sent], c)
        for m in c.targets:  # named but given no preference: still segmented (neutral)
            if m.known:
                st.mention(m.name)
    _resolve_weights(st)
    for name in st.weights:
        parts = ([st.said[name]] if st.said.get(name) else []) + st.compared.get(name, [])
        kept = [p for p in parts if not any(p != q and p in q for q in parts)]
        st.phrases[name] = "; ".join(dict.fromkeys(kept))
    return st


def interpret_offline(prompt: str, priors: PriorTable | None = None) -> Interpretation:
    """Interpret a mission prompt with the offline rules (deterministic, no network).

    ``priors``: the costs of hazards the prompt leaves unsaid (None = the built-in table)."""
    st = analyse(prompt)
    mentioned = [make_entity(n) for n in st.mentioned]
    notes = [f"interpreter: {RULES_VERSION}"] + st.notes
    return finalize(
        prompt,
        mentioned=mentioned,
        stated=st.weights,
        cues=st.cues,
        unparsed=st.unparsed,
        notes=notes,
        source="offline",
        phrases=st.phrases,
        priors=priors,
    )
