"""What the offline interpreter has read of a prompt so far, and the weights it comes to.

:class:`State` collects the statements (entity -> tiers, in order), cues, comparison constraints,
notes and unparsed fragments of a whole prompt; :func:`resolve_weights` turns them into weights:
the last statement about an entity wins (noted), then the comparisons adjust them.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

from overseec_core.interpret import lexicon as lx
from overseec_core.schema import Cue


@dataclass
class State:
    """The offline interpreter's record of one prompt: mentions, statements, cues, comparison
    constraints, notes and unparsed fragments, from which the weights are resolved."""

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
    #: graded afterthoughts with no cue before them ("avoid buildings, the further the better"):
    #: (kind, metres or None, the prompt's words), resolved once every statement is known
    graded: list[tuple[str, float | None, str]] = field(default_factory=list)

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


#: A weight and whether it is lethal.
Weight = tuple[float, bool]


def _weight_of(tier: str) -> Weight:
    """The weight of a tier, or of a step of an ordering ("order:0.20")."""
    if tier.startswith(("order:", "level:")):
        return float(tier.split(":", 1)[1]), False
    return lx.TIERS[tier]


def resolve_weights(st: State) -> None:
    """Turn the statements into ``st.weights``: the last statement of each entity wins, then the
    comparisons move weights as little as they must; a comparison they cannot meet is noted."""
    explicit = _stated_weights(st)
    if not st.constraints:
        return
    _anchor_ground(st.weights, st.constraints, explicit)
    _propagate(st.weights, st.constraints, explicit)
    st.notes.extend(_unmet(st.weights, st.constraints))


def _stated_weights(st: State) -> set[str]:
    """Each stated entity's weight from its last statement (an earlier, different one is noted);
    the names stated."""
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
    return explicit


def _anchor_ground(weights: dict[str, Weight], constraints: list[tuple[str, str, str]], explicit: set[str]) -> None:
    """ "paved road > unpaved road > off-road": ground no layer labels stands at neutral in an
    ordering, and the unstated names ranked above it (below it) start a step apart above
    (below) neutral, as many steps as the longest chain between them, so the order holds."""
    names = {x for _, a, b in constraints for x in (a, b)}
    anchors = names & lx.UNLABELLED_GROUND - explicit
    if not anchors:
        return
    steps = {g: 0 for g in anchors}
    for _ in range(len(constraints)):  # longest chains, by relaxation (orders are short)
        for kind, a, b in constraints:
            if kind != "lt":
                continue
            if b in steps and steps[b] <= 0 and a not in explicit and steps.get(a, 1) > steps[b] - 1:
                steps[a] = steps[b] - 1  # a ranks above ground: below neutral
            if a in steps and steps[a] >= 0 and b not in explicit and steps.get(b, -1) < steps[a] + 1:
                steps[b] = steps[a] + 1
    for name, k in steps.items():
        weights[name] = (min(0.99, max(0.0, round(lx.NEUTRAL + k * lx.STEP, 6))), False)
        if name in anchors:
            explicit.add(name)


def _propagate(weights: dict[str, Weight], constraints: list[tuple[str, str, str]], explicit: set[str]) -> None:
    """Apply the comparisons until nothing changes (bounded: twice as many rounds as there are
    comparisons, and one more)."""
    for _ in range(2 * len(constraints) + 1):
        changed = False
        for kind, a, b in constraints:
            step = _apply_eq if kind == "eq" else _apply_lt
            changed = step(weights, a, b, explicit) or changed
        if not changed:
            break


def _apply_eq(weights: dict[str, Weight], a: str, b: str, explicit: set[str]) -> bool:
    """One step of "a is as good as b": an unstated side takes the other's weight. Whether a
    weight changed."""
    wa, wb = weights.get(a), weights.get(b)
    if wb is not None and wa != wb and (a not in explicit or wa is None):
        weights[a] = wb
        return True
    if wa is not None and wb is None:
        weights[b] = wa
        return True
    return False


def _apply_lt(weights: dict[str, Weight], a: str, b: str, explicit: set[str]) -> bool:
    """One step of "a is better than b" (lower): an unstated side moves off neutral only as far
    as it must, never to the other side of it; between two stated sides the one not stated
    outright moves (else b, if there is room, else a). Whether a weight changed."""
    wa, wb = weights.get(a), weights.get(b)
    if wa is None and wb is None:
        weights[a] = (lx.NEUTRAL - lx.STEP, False)
        weights[b] = (lx.NEUTRAL, False)
    elif wa is None:  # the unstated side moves off neutral only as far as it must
        assert wb is not None  # both None is the branch above
        weights[a] = (max(0.0, min(lx.NEUTRAL, round(wb[0] - lx.STEP, 6))), False)
    elif wb is None:  # "prefer the bridge over the ford": the ford is not made good
        weights[b] = (min(0.99, max(lx.NEUTRAL, round(wa[0] + lx.STEP, 6))), False)
    elif (wa[1] and not wb[1]) or wb[1] or wa[0] < wb[0]:
        return False  # met already, or cannot be met (a lethal a: reported by _unmet)
    elif b not in explicit or a in explicit and wa[0] + lx.STEP <= 0.99:
        weights[b] = (min(0.99, round(wa[0] + lx.STEP, 6)), False)
    else:
        weights[a] = (max(0.0, round(wb[0] - lx.STEP, 6)), False)
    return True


def _unmet(weights: dict[str, Weight], constraints: list[tuple[str, str, str]]) -> list[str]:
    """A note for each comparison the weights do not meet (conflicting statements)."""
    notes = []
    for kind, a, b in constraints:
        wa, wb = weights.get(a), weights.get(b)
        if wa is None or wb is None:  # "x as good as y", neither stated: nothing to meet
            continue
        bad = (kind == "lt" and not (wb[1] and not wa[1] or (wa[1] == wb[1] and wa[0] < wb[0]))) or (
            kind == "eq" and wa != wb
        )
        if bad:
            rel = "better than" if kind == "lt" else "as good as"
            notes.append(f"could not make '{a}' {rel} '{b}' (conflicting statements)")
    return notes


def _tier_label(tier: str) -> str:
    """A tier as a note names it (an ordering's step is "order")."""
    if tier.startswith("level:"):
        return f"cost {tier.split(':', 1)[1]}"
    return "order" if tier.startswith("order:") else tier
