"""One sentence of a prompt as the offline interpreter reads it: entity mentions and constructs.

A :class:`Sentence` finds its idioms and entity mentions when it is made (steps 1-2 of the grammar
in :mod:`overseec_core.interpret.offline`); the constructs are then claimed over it by
:mod:`.conditions` (conditions, geometric cues), :mod:`.comparisons` and :func:`.phrases.claim_phrases`
(modifiers, triggers, markers), and :meth:`Sentence.joins` marks the list glue between entities.
Token indices are local to the sentence.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.tokens import Tok, is_adverb


@dataclass
class Mention:
    """An entity named at a token span of a sentence, with its role (target, condition, cue ...)
    and the list of mentions it belongs to."""

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


#: Quantifiers a partitive "of" follows before a list ("any of the houses", "each of the ponds").
_PARTITIVES = frozenset({"any", "all", "each", "either", "some", "most", "none"})


#: Words after which an object pronoun stands for the entity named last.
_PRONOUN_GOVERNORS = lx.PRONOUN_PREPOSITIONS | lx.HUG_VERBS | lx.GIVE_VERBS | lx.APPROACH_VERBS | {"keep"}


class Sentence:
    """Mentions and constructs of one sentence (token indices are local to it)."""

    def __init__(self, toks: list[Tok], antecedent: str | None = None):
        self.toks = toks
        #: The entity named last before this sentence, which "it"/"them" may stand for.
        self.antecedent = antecedent
        self.n = len(toks)
        #: On-versus-beside readings (``interpret.beside``), set when the sentence is read.
        self.beside: list = []
        #: (word as written, entity or phrase word, how): words read by spelling or alias
        self.readings: list[tuple[str, str, str]] = []
        self.words = [self._phrase_word(t.word) for t in toks]
        self.claimed: list[str | None] = [None] * self.n
        self.mentions: list[Mention] = []
        self.mention_at: dict[int, Mention] = {}
        self.found: list[Found] = []
        #: (start, end) of words that name a gap's kind ("minimum horizontal separation"),
        #: claimed with the cue they qualify
        self.gap_modifiers: list[tuple[int, int]] = []
        self._claim_idioms()
        self._find_mentions()

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
            hit = self.match(lx.IDIOMS, i)
            after = self.words[i + len(hit[0])] if hit and i + len(hit[0]) < self.n else ""
            if hit and hit[1] == "available" and after in ("no", "none", "not", "nothing"):
                hit = None  # "only when there is no other way": a last resort, not availability
            if hit and hit[1] == "slack" and i > 0 and self.words[i - 1] in lx.COPULAS:
                hit = None  # "the bush and the grass are no worries": said of them, a permission
            if hit and not (self.words[i] == "off" and i > 0 and self.words[i - 1] in lx.OFF_VERBS):
                # "stay off road X" is staying off it, not going off-road
                fillers = ("polite", "traveller", "slack", "emphasis", "available")
                kind = "filler" if hit[1] in fillers else "marker" if hit[1] == "alt" else "trigger"
                self.claim(Found(kind, i, i + len(hit[0]), hit[1]), kind)
                if hit[1] == "available":  # "if the trail goes where we're headed": the "if" too
                    self._claim_condition_word(i)
                i += len(hit[0])
            else:
                i += 1

    def _claim_condition_word(self, i: int) -> None:
        """The free condition word a few words before an availability verb ("if the trail
        goes our way"): read with it, as grammar."""
        for j in range(i - 1, max(-1, i - 6), -1):
            if self.words[j] in lx.AVAILABILITY_CONDITIONS and self.claimed[j] is None:
                self.claim(Found("filler", j, j + 1, "available"), "filler")
                return

    # -- mentions
    def _find_mentions(self) -> None:
        """Find the entity mentions and claim their words: names of the entity table (longest
        first), misspelt entity words, then runs of unknown content words (open vocabulary)."""
        known = self._table_mentions()
        covered = {j for m in known for j in range(m.start, m.end)}
        content = [j not in covered and self._is_content(j) for j in range(self.n)]
        known += self._misspelt_mentions(content)
        mentions = self._open_mentions(known, _runs(content))
        mentions += self._pronoun_mentions(mentions)
        mentions.sort(key=lambda m: m.start)
        self._itself(mentions)
        self.mentions = mentions
        for m in mentions:
            self.mention_at[m.start] = m
            for j in range(m.start, m.end):
                self.claimed[j] = "mention"

    def _itself(self, mentions: list[Mention]) -> None:
        """ "the carriageway itself", "the road surface itself": a generic name that stresses
        "itself" after a kind of it was named ("the shoulder of the paved road") is that kind,
        noted as a reading (the surface beside which the route runs)."""
        for k, m in enumerate(mentions):
            after = m.end + (m.end < self.n and self.words[m.end] in ("surface", "surfaces"))
            if after >= self.n or self.words[after] not in ("itself", "themselves"):
                continue
            before = [b.name for b in mentions[:k] if b.known] + ([self.antecedent] if self.antecedent else [])
            kind = next((b for b in reversed(before) if lx.parent_of(b) == m.name), None)
            if kind is not None:
                self.readings.append((" ".join(self.words[m.start : m.end]), kind, "pronoun"))
                m.name = kind

    def _table_mentions(self) -> list[Mention]:
        """The entity table's names (the longest match at each word; an alias is noted) and side
        tokens ("roadside": a side cue on the road)."""
        words, i = self.words, 0
        known: list[Mention] = []
        while i < self.n:
            hit = self._surface_at(i) or self._misspelt_name(i)
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
        return known

    def _surface_at(self, i: int) -> Mention | None:
        """The entity-table name starting at word ``i``: a qualifier with a head noun of its
        parent ("coniferous stands": the qualified kind), else the longest surface."""
        words = self.words
        if i + 1 < self.n and self.free(i, i + 2) and (qualified := lx.qualified_head(words[i], words[i + 1])):
            return Mention(i, i + 2, qualified, True)
        if (after := self._material_after(i)) is not None:  # "the roads of earth", "roads with asphalt"
            return after
        for k in range(min(lx.MAX_SURFACE_WORDS, self.n - i), 0, -1):
            name = lx.SURFACE.get(tuple(words[i : i + k]))
            if name and self.free(i, i + k) and not (k == 1 and self._qualifies_next(i)):
                return Mention(i, i + k, name, True)
        return None

    def _material_after(self, i: int) -> Mention | None:
        """A head noun with its material after it ("the roads of earth", "roads with asphalt",
        "paths made of gravel"): the qualified kind, as "earth roads" names it; None otherwise."""
        w = self.words
        j = i + 1 + (i + 2 < self.n and w[i + 1] == "made")
        if j + 1 >= self.n or w[j] not in ("of", "with", "in") or not self.free(i, j + 2):
            return None
        qualified = lx.qualified_head(w[j + 1], w[i])
        return Mention(i, j + 2, qualified, True) if qualified else None

    def _qualifies_next(self, i: int) -> bool:
        """Whether word ``i`` is a qualified kind's one-word name ("deciduous") standing before
        another noun ("deciduous woodland"): then it is part of that name, read as a compound."""
        w = self.words
        if i + 1 >= self.n or not {w[i], lx.singularise(w[i])} & lx.QUALIFIER_WORDS:
            return False
        nxt = w[i + 1]
        return nxt.isalpha() and nxt not in lx.FILLER and nxt not in lx.VOCAB and not is_adverb(nxt)

    def _misspelt_name(self, i: int) -> Mention | None:
        """A name of two or more words typed with slips at word ``i`` ("basebal feild"), noted
        as a spelling reading; the longest wins."""
        for k in range(min(lx.MAX_SURFACE_WORDS, self.n - i), 1, -1):
            name = lx.correct_surface(tuple(self.words[i : i + k])) if self.free(i, i + k) else None
            if name:
                self.readings.append((" ".join(self.words[i : i + k]), name, "spelling"))
                return Mention(i, i + k, name, True)
        return None

    def _misspelt_mentions(self, content: list[bool]) -> list[Mention]:
        """Content words that are a near-miss of an entity word ("vegitation", "raod"); they are
        no longer content (``content`` is updated)."""
        found = []
        for j in range(self.n):
            fixed = lx.correct_spelling(self.words[j]) if content[j] else None
            if fixed is not None:
                found.append(Mention(j, j + 1, fixed[1], True))
                self.readings.append((self.words[j], fixed[1], "spelling"))
                content[j] = False
        return found

    def _open_mentions(self, known: list[Mention], runs: list[tuple[int, int]]) -> list[Mention]:
        """``known`` with the runs of unknown content words added: a run of one or two words
        before a known entity makes a compound of it ("dirt road"), a run of up to three words
        names an entity of its own; longer runs are not read as a name (they are reported)."""
        by_start = {m.start: m for m in known}
        mentions = list(known)
        for a, b in runs:
            follower = by_start.get(b)
            if follower is not None and b - a <= 2 and follower.role == "target":
                mentions.remove(follower)
                mentions.append(self._compound(a, b, follower))
            elif self._gap_modifier(a, b):  # "a minimum horizontal separation of 15 m from ..."
                self.gap_modifiers.append((a, b))
            elif (kind := self._bare_qualifier(a, b)) is not None:  # "paved > unpaved"
                mentions.append(Mention(a, b, kind, True))
            elif b - a <= 3 and lx.singularise(self.words[b - 1]) not in lx.NON_TERRAIN:
                ws = self.words[a:b]
                name = " ".join(ws[:-1] + [lx.singularise(ws[-1])])
                mentions.append(Mention(a, b, name, False))
        return mentions

    def _gap_modifier(self, a: int, b: int) -> bool:
        """Whether the unknown words a..b qualify a gap noun after a minimum ("a minimum
        horizontal separation", "a safe lateral clearance"): the gap's kind, not an entity."""
        w = self.words
        return a > 0 and w[a - 1] in lx.MIN_WORDS and b < self.n and w[b] in lx.GAP_NOUNS

    def _bare_qualifier(self, a: int, b: int) -> str | None:
        """The qualified kind one qualifier word names where no noun follows it ("paved >
        unpaved", "sealed: good"): a terse brief drops the parent noun ("paved road")."""
        if b - a != 1 or (b < self.n and self.words[b].isalpha() and self.words[b] not in lx.FILLER):
            return None
        word = self.words[a]
        for parent in lx.QUALIFIED_HEADS:
            kind = lx.SURFACE.get((word, parent))
            if kind in lx.QUALIFIED_KINDS:
                return kind
        return None

    def _pronoun_mentions(self, mentions: list[Mention]) -> list[Mention]:
        """ "within 50 m of it", "the firm ground next to it", "hug it": an object pronoun after a
        preposition (or a hugging verb) stands for the entity named last (in this sentence, else before it);
        noted as a reading so the user sees what it was taken for."""
        found = []
        for j in range(self.n - 1):  # "so avoid that bit", "that part is fine": the entity named last
            if self.words[j] not in lx.DEMONSTRATIVES or self.words[j + 1] not in lx.PART_NOUNS:
                continue
            if any(self.claimed[x] is not None for x in (j, j + 1)) or any(m.start == j + 1 for m in mentions):
                continue
            name, known = self._antecedent(mentions, j)
            if name is not None:
                found.append(Mention(j, j + 2, name, known))
                self.readings.append((f"{self.words[j]} {self.words[j + 1]}", name, "pronoun"))
        for j in range(1, self.n):
            if self.words[j] not in lx.OBJECT_PRONOUNS or self.claimed[j] is not None:
                continue
            # "hug it", "keep it close", "give it 15 m"
            # "costs rise as you approach it"
            if self.words[j - 1] not in lx.PRONOUN_PREPOSITIONS | lx.HUG_VERBS | lx.GIVE_VERBS | lx.APPROACH_VERBS | {
                "keep"
            }:
                continue
            name, known = self._antecedent(mentions, j)
            if name is not None:
                found.append(Mention(j, j + 1, name, known))
                self.readings.append((self.words[j], name, "pronoun"))
        return found

    def _antecedent(self, mentions: list[Mention], j: int) -> tuple[str | None, bool]:
        """What the pronoun at j stands for: the known entity named last before it in the
        sentence, else the one before the sentence, else an open-vocabulary name before it, else
        the known entity named next ("next to it rather than in the marsh")."""
        targets = [m for m in mentions if m.role == "target"]
        known_before = [m for m in targets if m.known and m.end <= j]
        if known_before:
            return known_before[-1].name, True
        if self.antecedent is not None:
            return self.antecedent, True
        before = [m for m in targets if m.end <= j]
        if before:
            return before[-1].name, False
        after = [m for m in targets if m.known and m.start > j]
        return (after[0].name, True) if after else (None, True)

    def _compound(self, a: int, b: int, follower: Mention) -> Mention:
        """ "dirt road", "muddy baseball field": an open-vocabulary compound of a known entity
        (counts as known: its head word is in the table)."""
        head = follower.name
        surface = tuple(self.words[follower.start : follower.end])
        if surface in lx.AMBIGUOUS_SURFACES:  # "muddy tracks": a track, not the railway
            head = lx.singularise(surface[-1])
        name = " ".join(self.words[a:b]) + " " + head
        return Mention(a, follower.end, name, True)

    def _is_content(self, j: int) -> bool:
        w = self.words[j]
        return self.claimed[j] is None and w.isalpha() and w not in lx.FILLER and w not in lx.VOCAB and not is_adverb(w)

    # -- helpers
    def drop_mention(self, m: Mention) -> None:
        """Forget an open-vocabulary mention a construct reads otherwise ("a bit of room")."""
        self.mentions.remove(m)
        for j in range(m.start, m.end):
            self.mention_at.pop(j, None)
            self.claimed[j] = None

    def free(self, a: int, b: int) -> bool:
        return b <= self.n and all(self.claimed[j] is None for j in range(a, b))

    def match(self, table, i: int):
        cands = table.get(self.words[i]) if i < self.n else None
        for words, payload in cands or ():
            k = len(words)
            if tuple(self.words[i : i + k]) == words and self.free(i, i + k):
                return words, payload
        return None

    def match_loose(self, table, i: int) -> tuple[str, int] | None:
        """Like _match, but inserted adverbs do not break a phrase ("you can just wade through",
        "stay quietly under"): (payload, end index)."""
        cands = table.get(self.words[i]) if i < self.n and self.claimed[i] is None else None
        for words, payload in cands or ():
            j, ok = i, True
            for w in words:
                # an inserted adverb, or a modifier claimed already ("keep mostly on the road")
                while j < self.n and j > i and self.words[j] != w and self._skippable(j):
                    j += 1
                if j < self.n and self.words[j] == w and self.claimed[j] is None:
                    j += 1
                else:
                    ok = False
                    break
            if ok:
                return payload, j
        return None

    def _skippable(self, j: int) -> bool:
        return (self.claimed[j] is None and self._inserted(j)) or self.claimed[j] == "modifier"

    def _inserted(self, j: int) -> bool:
        w = self.words[j]
        return w in lx.INSERTS or w in lx.AGENT_INSERTS or (is_adverb(w) and w not in lx.VOCAB)

    def skip(self, i: int, allowed: set[str] | frozenset[str], limit: int = 4) -> int:
        k = 0
        while i < self.n and k < limit and self.claimed[i] is None and self.words[i] in allowed:
            i += 1
            k += 1
        return i

    def absolute(self) -> bool:
        """Whether the sentence words a rule as absolute ("at all times", "never", "must"):
        :data:`~overseec_core.interpret.lexicon.ABSOLUTE_WORDS` or one of the phrases."""
        if any(w in lx.ABSOLUTE_WORDS for w in self.words):
            return True
        return any(
            tuple(self.words[i : i + len(p)]) == p
            and not (p[-1] == "to" and i > 0 and self.words[i - 1] in lx.OBLIGATION_NEGATORS)
            for p in lx.ABSOLUTE_PHRASES
            for i in range(self.n)
        )

    def rule_wording(self) -> bool:
        """Whether the sentence states a distance cue in absolute words (those words are read
        as making it a rule, not left over)."""
        return self.absolute() and any(f.kind == "cue" and f.value in ("near", "far") for f in self.found)

    def distance(self, i: int) -> tuple[float, int] | None:
        """'10 m', 'ten metres', '5.5 ft', 'about 50 m', '6 ft 6 in' at i -> (metres, index
        after); an estimate's word (:data:`~overseec_core.interpret.lexicon.APPROXIMATORS`) is
        part of it (:meth:`approximate` tells)."""
        if self.approximate(i):
            i += 1
        if i + 1 >= self.n:
            return None
        number = self.number(i)
        if number is None or number[1] >= self.n or self.words[number[1]] not in lx.UNITS:
            return None
        value, u = number
        metres, end = value * lx.UNITS[self.words[u]], u + 1
        if end + 1 < self.n and re.fullmatch(r"\d+(?:\.\d+)?", self.words[end]):
            sub = lx.SUB_UNITS.get(self.words[end + 1])
            if sub is not None and sub < lx.UNITS[self.words[u]]:  # "6 ft 6 in": feet and inches
                metres, end = metres + float(self.words[end]) * sub, end + 2
        return metres, end

    def number(self, i: int) -> tuple[float, int] | None:
        """The number at word i, in figures or words ("10", "ten", "twenty five", the radio's
        "two-zero"), and the index after it; None when there is none."""
        w = self.words[i]
        if re.fullmatch(r"\d+(?:\.\d+)?", w):
            return float(w), i + 1
        if w not in lx.NUMBER_WORDS:
            return None
        value = float(lx.NUMBER_WORDS[w])
        nxt = self.words[i + 1] if i + 1 < self.n else ""
        # "twenty five metres", "thirty-five m": tens and units spoken as two words
        if value >= 20 and value % 10 == 0 and nxt in lx.NUMBER_WORDS and 0 < lx.NUMBER_WORDS[nxt] < 10:
            return value + lx.NUMBER_WORDS[nxt], i + 2
        # "two-zero metres", "one five metres": a radio operator's digits, one word each
        while value < 1000 and i + 1 < self.n and w in lx.RADIO_DIGITS and self.words[i + 1] in lx.RADIO_DIGITS:
            value = value * 10 + lx.RADIO_DIGITS[self.words[i + 1]]
            i += 1
            w = self.words[i]
        return value, i + 1

    def approximate(self, i: int) -> bool:
        """Whether the distance at word i is worded as an estimate ("about 50 m")."""
        return i < self.n and self.words[i] in lx.APPROXIMATORS and self.claimed[i] is None

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
        """Whether the mention is the subject of a state ("the road is blocked"); a state a rule
        says ("the gravel road is closed to traffic": a trigger) is no situation."""
        j = m.end
        while j < self.n and (self.words[j] in lx.COPULAS or self.words[j] in lx.INSERTS):
            j += 1
        return j > m.end and j < self.n and self.words[j] in lx.STATE_WORDS and self.claimed[j] != "trigger"

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

    def list_forward(self, i: int) -> tuple[list[Mention], int]:
        """Entity list starting at i (articles skipped): 'the roads, trails and paths'. A
        mention that is the subject of its own predicate ("..., and sand is better") ends it."""
        out: list[Mention] = []
        j = self.skip(i, lx.ARTICLES | lx.LEAD_MODIFIERS)
        if 0 < j < self.n and self.words[j] == "of" and self.words[j - 1] in _PARTITIVES and self.free(j, j + 1):
            j = self.skip(j + 1, lx.ARTICLES | lx.LEAD_MODIFIERS)  # "any of the houses", "all of the ponds"
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
            k = self.skip(k, lx.ARTICLES)
            nxt = self.mention_at.get(k)
            if nxt is None or nxt.role != "target" or self.is_subject(nxt) or self._compares_on(nxt):
                break
            out.append(nxt)
            end = nxt.end
        return out, end

    def list_backward(self, i: int) -> list[Mention]:
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

    def claim(self, f: Found, role: str) -> None:
        for j in range(f.start, f.end):
            if self.claimed[j] is None:
                self.claimed[j] = role
        self.found.append(f)

    def joins(self) -> None:
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


def _runs(content: list[bool]) -> list[tuple[int, int]]:
    """The (start, end) of each run of consecutive content words."""
    runs, j = [], 0
    while j < len(content):
        if content[j]:
            k = j
            while k < len(content) and content[k]:
                k += 1
            runs.append((j, k))
            j = k
        else:
            j += 1
    return runs
