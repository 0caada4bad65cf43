"""Sentences that only say how strict a rule is ("No exceptions.", "Not mandatory.", a "HARD
LIMITS" heading over the lines under it), and the one soft cue kept per entity when a brief
grades the same nearness twice.
"""

from __future__ import annotations

from dataclasses import replace

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.sentence import Sentence
from overseec_core.interpret.statements import State
from overseec_core.schema import Cue


def rule_only(sent: Sentence) -> str | None:
    """What a sentence that only qualifies the rule before it says: "hard" ("No exceptions.",
    "Non-negotiable.", "That buffer is an absolute constraint, not a preference."), "soft" ("Not
    mandatory.", "no hard limit", "it is a preference"), or None when it says more than that."""
    read = lx.RULE_WORDS | lx.FILLER | lx.SEPARATORS | lx.ARTICLES
    words = sent.words
    named = [m for m in sent.mentions if words[m.end - 1 : m.end] != ["one"]]  # "on that one": the rule
    if any(m.known or m.name not in read for m in named) or not all(w in read for w in words):
        return None
    in_phrase = {
        k
        for i in range(sent.n)
        for p in lx.ABSOLUTE_PHRASES
        if tuple(words[i : i + len(p)]) == p
        for k in range(i, i + len(p))
    }
    # "not a hard limit" softens; "not a preference" does not, it hardens; "a preference" softens
    said_not = {k for k in range(len(words)) if _negated_wish(words, k)}
    negated = any(
        w in lx.RULE_NEGATORS and k not in in_phrase and not said_not & {k + 1, k + 2} for k, w in enumerate(words)
    )
    wished = any(w in lx.WISH_NOUNS and k not in said_not for k, w in enumerate(words))
    if negated or wished:
        return "soft"
    if sent.absolute() or any(w in lx.RULE_VERDICTS for w in words) or said_not:
        return "hard"
    return None


def _negated_wish(words: list[str], k: int) -> bool:
    """Whether word ``k`` is a wish noun the sentence negates ("not a preference")."""
    return words[k] in lx.WISH_NOUNS and any(v in lx.RULE_NEGATORS for v in words[max(0, k - 2) : k])


def _qualify_rules(st: State, since: int, sent: Sentence, how: str) -> None:
    """Make the distance cues the previous sentence stated hard rules (or soft preferences);
    with none, the sentence has nothing to apply to and is reported as not understood."""
    done = False
    for k in range(since, len(st.cues)):
        if st.cues[k].kind in ("near", "far"):
            st.cues[k] = replace(st.cues[k], hard=how == "hard")
            done = True
    if not done:
        st.fragment(st.prompt[sent.toks[0].start : sent.toks[-1].end])


def _distance_rules(st: State, since: int) -> bool:
    """Whether the cues from ``since`` on hold a distance rule (near or far)."""
    return any(c.kind in ("near", "far") for c in st.cues[since:])


def rule_sentence(
    st: State,
    sent: Sentence,
    how: str,
    heading: tuple[str, Sentence, int] | None,
    cues_before: int,
    last: bool,
) -> tuple[str, Sentence, int] | None:
    """A sentence that only says how strict a rule is: it qualifies the distance rules of the
    sentence before it ("Keep 20 m from the railway. No exceptions."), or, with none there and
    lines after it, heads those lines ("HARD LIMITS"); the heading now in force is returned."""
    if last or _distance_rules(st, cues_before):
        _qualify_rules(st, cues_before, sent, how)
        return heading
    close_heading(st, heading)
    return (how, sent, len(st.cues))


def close_heading(st: State, heading: tuple[str, Sentence, int] | None) -> None:
    """A heading that only says how strict the rules are ("HARD LIMITS" over "water: 5 m",
    "railway: 10 m") makes the distance rules of the lines under it so; one with no rule under
    it is reported as not understood."""
    if heading is not None:
        how, sent, since = heading
        _qualify_rules(st, since, sent, how)


def merge_soft_cues(cues: list[Cue]) -> list[Cue]:
    """One soft cue per (kind, entity, other entity): a brief that says "don't go near the water:
    the further from it the better, up to 30 m" grades the water once, reaching neutral at the
    stated 30 m, not also at the default reach. A stated distance wins over the default; hard
    cues (rules) are kept as they are."""
    out: list[Cue] = []
    at: dict[tuple[str, str, str | None], int] = {}
    for cue in cues:
        key = (cue.kind, cue.entity, cue.other)
        if cue.hard or cue.kind not in ("near", "far"):
            out.append(cue)
            continue
        if key not in at:
            at[key] = len(out)
            out.append(cue)
        elif out[at[key]].metres == lx.DEFAULT_GRADED_DISTANCE_M and cue.metres != lx.DEFAULT_GRADED_DISTANCE_M:
            out[at[key]] = cue
    return out
