"""Clauses of a sentence: where a sentence splits, and which tier each entity of a clause takes.

A sentence is split at commas and conjunctions (not at the list glue between two entities); in
each clause adjacent triggers form a group whose tier is composed with the negation in scope
(:func:`trigger_groups`, :func:`_polarity`), and each entity takes the nearest group's tier
(:func:`nearest_group`). A clause of bare entities takes a neighbour's tier (:func:`attach_bare`),
and orderings ("first X, then Y") turn into ordered weights (:func:`apply_sequences`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.sentence import Found, Mention, Sentence
from overseec_core.interpret.tokens import Tok


@dataclass(eq=False)
class Clause:
    """A stretch of a sentence between separators: the constructs and targets in it, and the tier
    each of its entities takes (and which words it came from)."""

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


def split_clauses(sent: Sentence, s_index: int) -> list[Clause]:
    """Split a sentence at its separators (not list glue) and alternative markers, and give each
    clause its constructs, targets and markers."""
    clauses: list[Clause] = []
    start = 0
    seps: set[str] = set()
    alternatives = sent.alternatives  # "... as a last resort otherwise use the pavement"
    # "if there isn't, cut across ...": the comma after an alternative is no clause of its own
    alt_ends = {f.end for f in sent.found if f.kind == "marker" and f.value == "alt"}
    for j in range(sent.n + 1):
        separator = j < sent.n and sent.claimed[j] is None and sent.words[j] in lx.SEPARATORS and j not in alt_ends
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


#: A clause's trigger groups: (start, end, tier) of adjacent triggers read together.
Groups = list[tuple[int, int, str]]


def trigger_groups(clause: Clause) -> Groups:
    """Trigger groups (start, end, tier): adjacent triggers with no entity between combine
    (their tier composed by :func:`_polarity`)."""
    trig = sorted((f for f in clause.found if f.kind == "trigger"), key=lambda f: f.start)
    mods = {f.value for f in clause.found if f.kind == "modifier"}
    # a compared entity separates triggers too ("asphalt preferred > dirt roads avoided")
    compared = [m for f in clause.found if f.kind == "comparator" for m in (*f.left, *f.mentions)]
    mention_pos = sorted(m.start for m in (*clause.targets, *compared))
    members: list[list[Found]] = []
    for f in trig:
        if members and not any(members[-1][-1].end <= p < f.start for p in mention_pos):
            members[-1].append(f)
        else:
            members.append([f])
    words = [t.word for t in clause.toks]
    tiers = [(group, _polarity(group, words)) for group in members]
    groups: list[list] = [[g[0].start, g[-1].end, tier] for g, tier in tiers if tier is not None]
    for tier in ("lethal", "last", "tolerable"):  # "the river, at all costs"; "trees if necessary"
        if not groups and tier in mods:
            f = next(f for f in clause.found if f.kind == "modifier" and f.value == tier)
            groups.append([f.start, f.end, tier])
    if not groups and "strong" in mods and not any(f.kind == "cue" for f in clause.found):
        # "paved road wherever possible", "the trail as much as you can": use it, as often as it goes
        f = next(f for f in clause.found if f.kind == "modifier" and f.value == "strong")
        groups.append([f.start, f.end, "prefer"])
    for g in groups:
        g[2] = _modified(g[2], mods)
        if g[2] == "prefer" and g[1] < len(words) and words[g[1]] in lx.OBJECT_PRONOUNS and words[g[0]] in _MOTION:
            g[2] = "fine"  # "canopy ok, go thru it": passing what was just named is allowed, not sought
    _forbidden_crossings(tiers, groups)
    _terse_refusals(groups, words, mention_pos)
    return [tuple(g) for g in groups]


#: What may stand between a name and its terse verdict ("water: no", "rail = no", "trees - no").
_VERDICT_MARKS = frozenset({":", "=", "-", "->", "→"})


def _terse_refusals(groups: list[list], words: list[str], mention_pos: list[int]) -> None:
    """ "water: no.", "rail no", "unpaved road: no": a bare "no" that is a name's whole verdict,
    ending its clause, refuses that ground outright (lethal), as a checklist's "no" does; "no"
    before a name ("no water") stays the avoid it always was (in place)."""
    for g in groups:
        start, end = g[0], g[1]
        if g[2] != "avoid" or end - start != 1 or words[start] != "no":
            continue
        if any(w not in lx.SEPARATORS and w not in ("!", ".") for w in words[end:]):
            continue
        k = start - 1
        while k >= 0 and words[k] in _VERDICT_MARKS:
            k -= 1
        # "rail: no": the mark ends the name's clause, and the verdict clause is the bare "no"
        if k < start - 1 or any(p <= k for p in mention_pos):
            g[2] = "lethal"


#: Verbs of passing that, with a pronoun for their object, restate an allowance ("go thru it").
_MOTION = frozenset("go drive walk ride cross wade travel head pass move cut fly roll".split())


def _modified(tier: str, mods: set[str]) -> str:
    """A trigger group's tier as the clause's modifiers change it ("at all costs" makes an
    avoid lethal, "as much as possible" stronger, "freely" an allowance, "as a last resort" and
    "if needed" the worst ground still used)."""
    if "lethal" in mods and lx.SEVERITY[tier] >= lx.SEVERITY["avoid"] and tier != "nocross":
        return "lethal"
    if "strong" in mods and tier == "avoid":
        return "avoid+"
    if "freely" in mods and tier == "prefer":
        return "fine"  # "the route may pass over roads freely": allowed, not sought
    for weaker in ("last", "tolerable"):  # "water only as a last resort", "trees if needed"
        if weaker in mods and lx.SEVERITY[tier] < lx.SEVERITY[weaker]:
            return weaker
    return tier


def _forbidden_crossings(tiers: list[tuple[list[Found], str | None]], groups: list[list]) -> None:
    """ "Crossing the railway is prohibited": what a forbidding verdict after a bare crossing
    verb forbids is the crossing, so the group's tier is the nocross rule (in place)."""
    crossing_at = [g[0].start for g, tier in tiers if tier is None and any(f.value == "cross" for f in g)]
    for g in groups:
        if g[2] == "lethal" and any(s < g[0] for s in crossing_at):
            g[2] = "nocross"


def nearest_group(groups, m: Mention, sent: Sentence | None = None) -> int:
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


def _neighbour_tier(c: Clause, prev: Clause | None, nxt: Clause | None) -> tuple[str | None, Clause]:
    """The tier a clause of bare entities takes, and the clause it came from: the previous
    clause's trailing trigger ("avoid water, buildings"), a predicate standing alone before it
    ("..., as a last resort, roads"; "Off limits: the school"), the next clause's leading trigger
    ("trees: avoid"), else the previous clause's last trigger; None when no neighbour has one.
    A verdict after a colon belongs to the names before it first ("water: no go, trail: yes")."""
    if nxt is not None and ":" in nxt.seps and not nxt.targets and trigger_groups(nxt):
        a, b, tier = trigger_groups(nxt)[0]
        if tuple(t.word for t in nxt.toks[a:b]) in lx.NEGATORS and _crosses(c):
            tier = "nocross"  # "crossing the railway: never" is "never cross the railway"
        nxt.leftover = [j for j in nxt.leftover if not a <= j < b]
        nxt.whole_unparsed = False
        return tier, nxt
    if prev is not None and prev.assigned and trigger_groups(prev):
        if not prev.targets or trigger_groups(prev)[-1][0] < prev.targets[0].start:
            return trigger_groups(prev)[-1][2], prev
    if prev is not None and not prev.targets and not prev.assigned and trigger_groups(prev):
        a, b, tier = trigger_groups(prev)[-1]
        prev.leftover = [j for j in prev.leftover if not a <= j < b]
        prev.whole_unparsed = False
        return tier, prev
    if (
        nxt is not None
        and trigger_groups(nxt)
        and not nxt.markers & {"next", "alt"}
        and (not nxt.targets or trigger_groups(nxt)[0][0] > nxt.targets[0].start)
    ):
        a, b, tier = trigger_groups(nxt)[0]
        nxt.leftover = [j for j in nxt.leftover if not a <= j < b]
        nxt.whole_unparsed = False
        return tier, nxt
    if prev is not None and prev.assigned and trigger_groups(prev):
        return trigger_groups(prev)[-1][2], prev
    return None, c


def _crosses(c: Clause) -> bool:
    """Whether the clause names a crossing of its entities ("crossing the railway", "x-ing rail")."""
    return any(f.kind == "trigger" and f.value == "cross" for f in c.found)


def _states_a_situation(c: Clause) -> bool:
    """Whether a clause only says what state its entities are in ("tracks closed for works",
    "road flooded"): a state word right after an entity is no list waiting for a neighbour's
    tier (it would take the next clause's "off limits")."""
    return any(m.end < c.end and c.toks[m.end].word.lower() in lx.STATE_WORDS for m in c.targets)


def _cue_names(c: Clause) -> set[str]:
    """The entities the clause's cues are on."""
    return {m.name for f in c.found if f.kind == "cue" for m in f.mentions}


def attach_bare(clauses: list[Clause]) -> None:
    """A clause of bare entities takes its neighbour's tier (:func:`_neighbour_tier`)."""
    for i, c in enumerate(clauses):
        if (
            c.assigned
            or not c.targets
            or c.whole_unparsed
            or c.markers & {"next", "alt", "start"}
            or any(f.kind in ("cue", "comparator") for f in c.found)
            or _states_a_situation(c)
        ):
            continue
        prev = clauses[i - 1] if i > 0 and clauses[i - 1].sent == c.sent else None
        if prev is not None and c.seps & lx.CONTRASTIVE:
            prev = None  # "never enter the buildings, but the parking lot ...": no tier carries over
        # "Off limits: the school": a label before a colon names what it applies to, known or not
        labelled = prev is not None and ":" in c.seps and not prev.targets and bool(trigger_groups(prev))
        nxt = clauses[i + 1] if i + 1 < len(clauses) and clauses[i + 1].sent == c.sent else None
        # "water: give it ~15 m": the clause after the colon names the topic in a cue (by pronoun)
        if nxt is not None and ":" in nxt.seps and {m.name for m in c.targets} <= _cue_names(nxt):
            c.referenced = True
            continue
        # "Minefield: never enter": a topic before a colon that opens the sentence, known or not
        topic = c.start == 0 and nxt is not None and ":" in nxt.seps and not nxt.targets
        if not (labelled or topic) and not any(m.known for m in c.targets):
            c.whole_unparsed = True
            continue
        choice, source = _neighbour_tier(c, prev, nxt)
        if choice is None:
            c.whole_unparsed = True
            continue
        for m in c.targets:
            c.assigned[m.name] = choice
            c.src[m.name] = (source, c)


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


def first_of_list(clauses: list[Clause]) -> None:
    """ "stick to the road and the trail, road first": a first choice named again after the list
    it is one of ranks it one step above the rest of that list (all stay preferred); a first
    that opens a sequence ("road first, then the trail") is left to :func:`apply_sequences`."""
    for i, c in enumerate(clauses):
        nxt = clauses[i + 1] if i + 1 < len(clauses) and clauses[i + 1].sent == c.sent else None
        if "start" not in c.markers or (nxt and nxt.markers & {"next", "alt"}):
            continue
        firsts = [f for f in c.found if f.kind == "marker" and f.value == "start"]
        named = {m.name for m in c.targets if any(m.end == f.start for f in firsts)}
        listed = c if c.assigned else clauses[i - 1] if i > 0 and clauses[i - 1].sent == c.sent else None
        if listed is None or not named:
            continue
        positive = [n for n, t in listed.assigned.items() if lx.SEVERITY.get(t, 9) <= lx.SEVERITY["fine"]]
        if not named < set(positive):
            continue
        for n in positive:
            listed.assigned[n] = f"order:{lx.PREFER + (0 if n in named else lx.STEP):.2f}"
        c.markers.discard("start")
        c.whole_unparsed = False


def apply_sequences(clauses: list[Clause]) -> set[int]:
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
            positive = [n for n, t in c.assigned.items() if lx.SEVERITY.get(t, 9) <= lx.SEVERITY["fine"]]
            if not positive:
                continue
            w = min(lx.PREFER + pos * lx.STEP, lx.ORDER_MAX)
            for n in positive:
                c.assigned[n] = f"order:{w:.2f}"
                c.src[n] = (seq[0], c)  # "first roads, then trails": the ordering so far
                c.tok_src.pop(n, None)
            pos += 1
    return in_seq
