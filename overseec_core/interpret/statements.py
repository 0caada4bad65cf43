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


def _weight_of(tier: str) -> tuple[float, bool]:
    if tier.startswith("order:"):
        return float(tier.split(":", 1)[1]), False
    return lx.TIERS[tier]


def resolve_weights(st: State) -> None:  # noqa: C901
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
