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

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.beside import BESIDE_BAND_M, claim_beside
from overseec_core.interpret.clauses import (
    Clause,
    Groups,
    apply_sequences,
    attach_bare,
    first_of_list,
    nearest_group,
    split_clauses,
    trigger_groups,
)
from overseec_core.interpret.comparisons import claim_comparisons
from overseec_core.interpret.conditions import (
    attach_conditions,
    claim_conditions,
    claim_cues,
    claim_exceptions,
    only_at,
)
from overseec_core.interpret.consequences import claim_consequences
from overseec_core.interpret.corrections import Part, corrected
from overseec_core.interpret.cues import (
    centre_side_cue,
    distance_cues,
    excepted,
    graded_by,
    qualifier_clause,
    resolve_graded,
    rule_labels,
)
from overseec_core.interpret.levels import claim_levels, relative_levels, stated_levels
from overseec_core.interpret.merge import finalize, make_entity
from overseec_core.interpret.phrases import claim_phrases
from overseec_core.interpret.priors import PriorTable
from overseec_core.interpret.rules import close_heading, merge_soft_cues, rule_only, rule_sentence
from overseec_core.interpret.sentence import Found, Mention, Sentence
from overseec_core.interpret.shares import claim_shares
from overseec_core.interpret.statements import State, resolve_weights
from overseec_core.interpret.tokens import Tok, is_adverb, sentences, tokenize
from overseec_core.schema import Cue, Interpretation

RULES_VERSION = "offline-rules.v2"


def read_sentence(toks: list[Tok], antecedent: str | None = None) -> Sentence:
    """A sentence with its mentions and every construct claimed, in the grammar's order:
    on-versus-beside, conditions, cues, comparisons, then modifiers, triggers and markers; last
    the list glue. ``antecedent``: the entity named last before it ("keep within 50 m of it")."""
    sent = Sentence(toks, antecedent)
    sent.beside = claim_beside(sent)  # before conditions: "but not in the river" is no exception
    claim_consequences(sent)  # before conditions: "if it touches the water, the rover is lost"
    claim_shares(sent)  # "spend at most 10 % of the route on grass"
    claim_conditions(sent)
    claim_exceptions(sent)
    claim_cues(sent)
    for a, b in sent.gap_modifiers:  # "minimum horizontal separation": read with its cue
        if sent.free(a, b) and any(f.kind == "cue" and f.start <= b <= f.end for f in sent.found):
            sent.claim(Found("filler", a - sent.free(a - 1, a), b, "gap kind"), "cue")  # "safe" too
    _routes_within(sent)
    claim_comparisons(sent)
    claim_levels(sent)
    claim_phrases(sent)
    sent.joins()
    return sent


def _analyse_clause(st: State, sent: Sentence, c: Clause, prev: Clause | None) -> None:
    """Read one clause: its entities' tiers (from the nearest trigger group, or through a pronoun
    from the previous clause), its cues, conditions and comparisons, and what is left over."""
    groups = trigger_groups(c)
    if _closing_qualifier(c, groups) >= 2:
        # "road > trail > grass > trees only if stuck": the ranking's own last level (avoided)
        # says it already; a fixed level for the last item would squeeze the middle ones onto one
        groups = []
    used_groups: set[int] = set()
    targets = _clause_targets(sent, c)
    cues = [f for f in c.found if f.kind == "cue"]
    near_objs = [m for f in cues if f.value in ("near", "far") for m in f.mentions]
    centre_side = [(f.value, m, f) for f in cues if f.value in ("centre", "side") for m in f.mentions]
    for f in c.found:  # every cue object and comparison side counts as a mention
        for m in f.mentions + f.left:
            st.mention(m.name)
    if not targets and groups and not near_objs and not centre_side:
        _refer_back(sent, c, prev, groups, used_groups)
    _assign_targets(sent, c, targets, groups, used_groups)
    _compared_verdicts(c, groups, used_groups)
    for f in c.found:
        if f.kind == "condition" and f.value == "only_at" and targets:
            only_at(f, c, [m.name for m in targets], sent.words[c.start : c.end])
    for f in c.found:
        if f.kind == "exception":
            excepted(st, c, f, prev)
    stated_levels(c)
    for kind, m, cf in centre_side:
        centre_side_cue(st, c, kind, m, cf, groups, used_groups)
    distance_cues(st, sent, c, cues, targets, groups, used_groups)
    _comparisons(st, sent, c)
    _clause_leftovers(st, sent, c, groups, used_groups)
    _mark_unparsed(sent, c, targets, cues)


def _route_subject(sent: Sentence, m: Mention) -> bool:
    """Whether ``m`` is the route itself as its sentence's subject: a route noun ("the track",
    "the path") opening the sentence, then a modal and a keeping or moving verb ("the track
    would stay 25 m or more from the railway"). Its words are read (claimed as filler)."""
    w = sent.words
    words = w[m.start : m.end]
    if len(words) != 1 or words[0] not in lx.ROUTE_NOUNS or m.end >= sent.n:
        return False
    j = m.start - 1 - (m.start > 0 and w[m.start - 1] in lx.ARTICLES)
    if j >= 0 and w[j] in lx.MODALS and w[m.end] in lx.ROUTE_VERBS:  # "at no point may the path come"
        ok = True
    else:  # "(ideally) the track would stay ..."
        opening = w[: m.start]
        ok = all(t in lx.ARTICLES or t in lx.SOFTENERS or is_adverb(t) for t in opening)
        ok = ok and m.end + 1 < sent.n and w[m.end] in lx.MODALS and w[m.end + 1] in lx.ROUTE_VERBS
    if ok:
        sent.claimed[m.start] = "filler"
    return ok


def _routes_within(sent: Sentence) -> None:
    """ "preference to paths within 15 m of the road", "routes within 10 m of the river are
    best": a route noun right before a "within" cue is the route itself, not a trail near the
    road; it is no entity, and its word is read (claimed as filler)."""
    for f in list(sent.found):
        if f.kind != "cue" or sent.words[f.start] != "within" or f.start == 0:
            continue
        m = next((m for m in sent.mentions if m.end == f.start and m.end - m.start == 1), None)
        if m is not None and lx.singularise(sent.words[m.start]) in lx.ROUTE_NOUNS:
            sent.drop_mention(m)
            sent.claimed[m.start] = "filler"


def _clause_targets(sent: Sentence, c: Clause) -> list[Mention]:
    """The clause's entities that take a tier: not the subject of a situation ("only if the road
    is blocked"), and unknown words only where no known entity stands beside them or a trigger
    takes them as its object ("prefer the gravel avoid the mud"); the others are left over."""
    known_chains = {m.chain for m in c.targets if m.known}
    targets = []
    for m in c.targets:
        if sent.in_situation(m) or _route_subject(sent, m):
            continue
        if m.known or not known_chains or m.chain in known_chains or sent.object_of_trigger(m):
            targets.append(m)
        else:
            c.leftover.extend(range(m.start, m.end))
    return targets


def _refer_back(sent: Sentence, c: Clause, prev: Clause | None, groups: Groups, used_groups: set[int]) -> None:
    """A pronoun in a clause of triggers alone ("you may cross it") gives the previous clause's
    entities this clause's first tier; the previous clause becomes context."""
    referred = (list(prev.assigned) or [m.name for m in prev.targets]) if prev else []
    if prev is not None and not referred and prev.sent == c.sent:  # "right up against the houses, but never enter one"
        referred = [m.name for m in sent.mentions if prev.start <= m.start < prev.end and m.role == "cue"]
    pronouns = [j for j in range(c.start, c.end) if sent.words[j] in lx.PRONOUNS]
    relative = [j for j in range(c.start, min(c.end, c.start + 2)) if sent.words[j] in lx.RELATIVE_PRONOUNS]
    before = [m for m in sent.mentions if m.end <= c.start]
    if relative and before:  # "except the cricket pitch, which must not be driven on": the pitch
        referred, pronouns = [before[-1].name], relative
    if prev is not None and referred and pronouns:  # (referred is empty without prev)
        for name in referred:
            c.assigned[name] = groups[0][2]
            c.src[name] = (prev, c)
            c.took(name, groups[0][:2], (pronouns[-1], pronouns[-1] + 1))
        used_groups.add(0)
        prev.referenced = True  # "There is a pond. Avoid it.": the first clause is context


def _assign_targets(sent: Sentence, c: Clause, targets: list[Mention], groups: Groups, used_groups: set[int]) -> None:
    """Each target takes its nearest group's tier; its phrase is the trigger and its list. A
    ranking's closing qualifier ("road > trail > trees if needed") is its last item's only."""
    group_of = {}
    for m in _qualified_items(c, targets, groups):
        if groups:
            gi = nearest_group(groups, m, sent)
            used_groups.add(gi)
            c.assigned[m.name] = groups[gi][2]
            group_of[m.name] = gi
    for m in targets:  # "prefer the roads and trails": the trigger and its list
        if m.name in group_of:
            gi = group_of[m.name]
            c.took(m.name, groups[gi][:2], *[(t.start, t.end) for t in targets if group_of.get(t.name) == gi])


def _closing_qualifier(c: Clause, groups: Groups) -> int:
    """How many ranking steps stand before the clause's groups when they are only qualifiers
    of use ("if needed", "only if stuck", "as a last resort") after a ranking's last step; 0
    otherwise."""
    steps = [f.start for f in c.found if f.kind == "comparator"]
    if not steps or not groups or any(g[2] not in ("tolerable", "last") or g[0] < max(steps) for g in groups):
        return 0
    return len(steps)


def _qualified_items(c: Clause, targets: list[Mention], groups: Groups) -> list[Mention]:
    """The targets the clause's groups speak of: all of them, unless the groups close a
    ranking ("road > trees if needed": the trees are used if needed, the road is still the
    best), when only the items after its last step."""
    if not _closing_qualifier(c, groups):
        return targets
    last = max(f.start for f in c.found if f.kind == "comparator")
    return [m for m in targets if m.start > last]


def _compared_verdicts(c: Clause, groups: Groups, used_groups: set[int]) -> None:
    """A compared entity with its own verdict right after it ("asphalt preferred > dirt roads
    avoided") takes that verdict; the comparison then orders the two as well."""
    for f in c.found:
        if f.kind != "comparator":
            continue
        for m in (*f.left, *f.mentions):
            gi = next((g for g, (a, _, _) in enumerate(groups) if a == m.end), None)
            if gi is not None and m.name not in c.assigned:
                used_groups.add(gi)
                c.assigned[m.name] = groups[gi][2]
                c.took(m.name, groups[gi][:2], (m.start, m.end))


def _comparisons(st: State, sent: Sentence, c: Clause) -> None:
    """Each comparison of the clause: its phrase for both sides, and a constraint per pair."""
    for f in c.found:
        if f.kind != "comparator":
            continue
        a_char = sent.toks[min([c.start] + [m.start for m in f.left])].start
        st.compare([m.name for m in f.left + f.mentions], st.prompt[a_char : sent.toks[f.end - 1].end].strip())
        said = sent.words[f.start : min(m.start for m in f.mentions)]
        if f.value == "better" and any(w in lx.PREFER_VERBS for w in said):
            for a in f.left:  # "gravel is to be preferred over asphalt": preferred, not merely better
                c.assigned.setdefault(a.name, "prefer")
        for a in f.left:
            for b in f.mentions:
                if f.value == "better":
                    st.constraints.append(("lt", a.name, b.name))
                elif f.value == "worse":
                    st.constraints.append(("lt", b.name, a.name))
                else:
                    st.constraints.append(("eq", a.name, b.name))


def _clause_leftovers(st: State, sent: Sentence, c: Clause, groups: Groups, used_groups: set[int]) -> None:
    """Trigger groups that gave no tier and restate none, and words no rule claimed, are left
    over; an unread condition ("if ...", "unless ...") is reported to the clause's end."""
    said = set(c.assigned.values())
    # the absolute wording of a distance rule ("never", "no matter what", "at all times") is read
    rule_words = lx.RULE_WORDS if sent.rule_wording() else frozenset()
    # "ideally", "if possible" soften a distance cue of the clause (read, not left over)
    if any(f.kind == "cue" and f.value in ("near", "far") for f in c.found) or qualifier_clause(sent, c):
        rule_words = rule_words | lx.SOFTENERS | {"soft"}
        if rule_labels(sent) and qualifier_clause(sent, c):  # "..., ok to violate"
            rule_words = rule_words | {"ok", "okay", "fine"} | {w for pair in lx.RULE_LABELS for w in pair}
    for gi, (a, b, tier) in enumerate(groups):
        if gi not in used_groups and tier not in said:  # "go through the grass instead": restated
            if not all(sent.words[k] in rule_words for k in range(a, b)):
                c.leftover.extend(range(a, b))
    for j in range(c.start, c.end):
        if (
            sent.claimed[j] is None
            and sent.words[j] not in rule_words
            and sent.words[j] not in lx.FILLER
            and sent.words[j] not in lx.SEPARATORS
            and sent.words[j] not in lx.ARTICLES
        ):
            if sent.words[j] in ("if", "unless", "when", "except", "whenever", "where"):
                st.fragment(st.prompt[c.toks[j].start : c.toks[c.end - 1].end])
                continue
            c.leftover.append(j)


def _mark_unparsed(sent: Sentence, c: Clause, targets: list[Mention], cues: list[Found]) -> None:
    """A clause with no meaning, no target and no condition, but words other than grammar (a
    short marker clause aside), is unparsed as a whole."""
    has_meaning = bool(c.assigned) or bool(cues) or any(f.kind == "comparator" for f in c.found)
    if has_meaning or targets or any(f.kind == "condition" for f in c.found):
        return
    if qualifier_clause(sent, c):  # "Hard constraint: never within 5 m of the pylons"
        return
    read = lx.FILLER | lx.SEPARATORS | lx.ARTICLES
    if all(sent.claimed[j] in ("cue", "filler") or sent.words[j] in read for j in range(c.start, c.end)):
        return  # "cost: grass < road": a label read with the sentence's ordering; an idiom read
    if any(sent.claimed[j] not in (None,) or sent.words[j] not in lx.FILLER for j in range(c.start, c.end)) and not (
        c.markers and c.end - c.start <= 2
    ):
        c.whole_unparsed = True


def _report_leftovers(st: State, sent: Sentence, c: Clause) -> None:
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


def _note_readings(sent: Sentence, st: State) -> None:
    """Say how words were read as entities by spelling or alias ("read 'woods' as 'forest'")."""
    for word, name, how in sent.readings:
        note = f"read '{word}' as '{name}'" + {"spelling": " (spelling)", "pronoun": " (the entity named last)"}.get(
            how, ""
        )
        if note not in st.notes:
            st.notes.append(note)


def _kept_off_sides(st: State) -> None:
    """The side of a linear thing the prompt also keeps off or forbids ("[road]\nsurface =
    forbidden\nverge = preferred", "never drive on the road; use its side") is the band beside
    it: the side cue becomes a soft near cue, and what preferred the thing with its side is
    the side's, not the thing's."""
    avoid = lx.SEVERITY["avoid"]
    for k, cue in enumerate(st.cues):
        tiers = st.statements.get(cue.entity, [])
        if cue.kind != "side" or not any(lx.SEVERITY.get(t, 0) >= avoid for t in tiers):
            continue
        st.cues[k] = Cue("near", cue.entity, BESIDE_BAND_M)
        _drop_prefer(st, cue.entity)


def _drop_prefer(st: State, name: str) -> None:
    """Take back what preferred ``name`` itself when it was its edge or side that was preferred."""
    kept = [t for t in st.statements.get(name, []) if t != "prefer"]
    if kept:
        st.statements[name] = kept
    else:
        st.statements.pop(name, None)


def _apply_beside(st: State, sents: list[Sentence]) -> None:
    """On versus beside (``interpret.beside``), stated last: the object itself is not the way
    (avoided, or forbidden), the band beside it is (a soft near cue); so is the side of a linear
    thing the prompt keeps off ("verge = preferred" under "[road]", "surface = forbidden" after)."""
    _kept_off_sides(st)
    for sent in sents:
        for b in sent.beside:
            if b.pending:  # beside X, and X avoided or forbidden somewhere in the prompt
                if graded_by(st, b.name, "far") and Cue("near", b.name, b.metres) not in st.cues:
                    st.cues.append(Cue("near", b.name, b.metres))
                continue
            if b.tier is not None:
                st.state(b.name, b.tier, st.prompt[sent.toks[0].start : sent.toks[-1].end])
            else:  # "(I'd like it to) drive along the edge of the pond": the edge is preferred, not the pond
                st.mention(b.name)
                _drop_prefer(st, b.name)
            st.cues.append(Cue("near", b.name, b.metres))


def _last_named(sent: Sentence, before: str | None) -> str | None:
    """What a pronoun of the next sentence stands for: the known entity this one named last,
    or the excepted one it ends on ("..., except the cricket pitch. Avoid that part."), else
    its last open-vocabulary name, else ``before``."""
    named = sorted((m for m in sent.mentions if m.role in ("target", "cue", "except")), key=lambda m: m.start)
    if named and named[-1].role == "except":
        return named[-1].name
    return next((m.name for m in reversed(named) if m.known), named[-1].name if named else before)


def _note_withdrawn(st: State, part: Part, prompt: str) -> None:
    """A note of what a self-correction withdrew ("avoid the vegetation -- no wait, ...")."""
    if part.withdrawn_by and part.span:
        said = prompt[part.span[0] : part.span[1]]
        st.notes.append(f"'{said}' read as withdrawn ('{part.withdrawn_by}')")


def _revoke(st: State, clauses: list[Clause], part: Part) -> None:
    """ "forget the trail rule": the tiers and cues stated before on the entities it names are
    taken back (the entities stay named), and a note says so."""
    if not part.revokes:
        return
    for c in clauses:
        for name in part.revokes:
            c.assigned.pop(name, None)
    st.cues = [cue for cue in st.cues if cue.entity not in part.revokes and cue.other not in part.revokes]
    st.notes.append(f"rules on {', '.join(part.revokes)} said before '{part.revoked_by}' were withdrawn")


def _state_clauses(st: State, clauses: list[Clause], sents: list[Sentence], parts: list[Part]) -> None:
    """Each clause's tiers as statements (and the nocross rule's cue), its leftovers reported
    (never a withdrawn sentence's names), and every known entity it names mentioned."""
    for c in clauses:
        for name, tier in c.assigned.items():
            st.state(name, tier, c.phrase(name, st.prompt))
            if tier == "nocross" and Cue("no_cross", name, hard=True) not in st.cues:
                st.cues.append(Cue("no_cross", name, hard=True))
        if not parts[c.sent].withdrawn_by:
            _report_leftovers(st, sents[c.sent], c)
        for m in c.targets:  # named but given no preference: still segmented (neutral)
            if m.known:
                st.mention(m.name)


def analyse(prompt: str) -> State:
    """Read a prompt into statements, cues, orderings and leftovers (no defaults yet)."""
    st = State(prompt)
    clauses: list[Clause] = []
    sents: list[Sentence] = []
    antecedent: str | None = None
    cues_before = 0  # how many cues the sentences before the last one stated
    heading: tuple[str, Sentence, int] | None = None  # "HARD LIMITS" over the lines after it
    parts = corrected(sentences(tokenize(prompt)))
    all_toks = [list(p.toks) for p in parts]
    for si, toks in enumerate(all_toks):
        sent = read_sentence(toks, antecedent)
        sents.append(sent)
        _note_withdrawn(st, parts[si], prompt)
        _revoke(st, clauses, parts[si])
        if how := rule_only(sent):  # "Keep 20 m from the railway. No exceptions." / "Not mandatory."
            heading = rule_sentence(st, sent, how, heading, cues_before, last=si + 1 == len(all_toks))
            continue
        cues_before = len(st.cues)
        antecedent = _last_named(sent, antecedent)
        own = split_clauses(sent, si)
        prev = clauses[-1] if clauses else None
        for c in own:
            _analyse_clause(st, sent, c, prev)
            prev = c
        attach_bare(own)
        attach_conditions(own, st)
        clauses.extend(own)
        _note_readings(sent, st)
    close_heading(st, heading)
    relative_levels(clauses)
    first_of_list(clauses)
    apply_sequences(clauses)
    _state_clauses(st, clauses, sents, parts)
    resolve_graded(st)
    _apply_beside(st, sents)
    st.cues = merge_soft_cues(st.cues)
    resolve_weights(st)
    for name in st.weights:
        said = ([st.said[name]] if st.said.get(name) else []) + st.compared.get(name, [])
        kept = [p for p in said if not any(p != q and p in q for q in said)]
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
