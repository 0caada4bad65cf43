"""Issue 31's constructs in the offline interpreter, each on phrasings of its own (the held-out
brief sets in tests/mission_briefs_set*.py measure them; these pin the rules).

- distance rules worded as absolute anywhere in the sentence are hard; a number survives
  ("..., say 20 m"); soft wording stays soft;
- on versus beside: the object avoided (forbidden with "never") and a near cue beside it;
- "stay out of / keep out of / don't go into X" forbid X; "avoid X" stays an avoid;
- symbolic chains ("A > B > C", "A >> B", "A before B") and colon verdicts ("X: no go, Y: yes");
- qualified roads: "tarmac" is the paved road, "gravel" the unpaved one, a bare "road" both;
- a common English word is never read as a misspelt entity ("weather permitting").
"""

from __future__ import annotations

import pytest

from overseec_core.interpret.matching import match_entity
from overseec_core.interpret.offline import interpret_offline


def _cues(prompt: str) -> list[tuple]:
    return [(c.kind, c.entity, c.metres, c.hard) for c in interpret_offline(prompt).cues]


def _bands(prompt: str) -> dict[str, str]:
    return {p.entity: p.band for p in interpret_offline(prompt).preferences if p.phrase}


def _weights(prompt: str) -> dict[str, float]:
    return {p.entity: p.weight for p in interpret_offline(prompt).preferences}


@pytest.mark.parametrize(
    "prompt, entity, metres",
    [
        ("the survey team must remain 12 m from the houses", "house", 12.0),
        ("at all times keep 6 m from the ditch", "ditch", 6.0),
        ("never get nearer than 30 m to the lake", "lake", 30.0),
        ("under no circumstances come within 4 m of the pylons", "electric tower", 4.0),
    ],
)
def test_absolute_wording_makes_a_distance_rule_hard(prompt: str, entity: str, metres: float) -> None:
    assert ("far", entity, metres, True) in _cues(prompt)
    assert not interpret_offline(prompt).unparsed  # the absolute words are read, not left over


@pytest.mark.parametrize(
    "prompt, entity, metres",
    [
        ("if you can, keep some distance from the barn, about 15 m", "barn", 15.0),
        ("ideally stay 8 m off the hedge", "hedge", 8.0),
    ],
)
def test_soft_wording_stays_soft_and_keeps_its_number(prompt: str, entity: str, metres: float) -> None:
    assert ("far", entity, metres, False) in _cues(prompt)


@pytest.mark.parametrize(
    "prompt, entity, band",
    [
        ("walk the lake shore but not in the lake", "lake", "avoided"),
        ("go alongside the canal, never in it", "canal", "lethal"),
        ("skirt the orchard edge without entering", "orchard", "avoided"),
    ],
)
def test_on_versus_beside(prompt: str, entity: str, band: str) -> None:
    it = interpret_offline(prompt)
    assert _bands(prompt)[entity] == band
    assert any(c.kind == "near" and c.entity == entity and not c.hard for c in it.cues)
    assert not it.unparsed


@pytest.mark.parametrize("prompt", ["stay out of the swamp", "keep out of the swamp", "don't go into the swamp"])
def test_staying_out_forbids(prompt: str) -> None:
    assert _bands(prompt)["wetland"] == "lethal"


def test_avoid_stays_an_obstacle_not_a_rule() -> None:
    assert _bands("avoid the swamp")["wetland"] == "avoided"


@pytest.mark.parametrize(
    "prompt, order",
    [
        ("footpath > lawn > mud", ("footpath", "lawn", "mud")),
        ("sand >> rock", ("sand", "rock")),
        ("meadow before scrub", ("meadow", "bush")),
    ],
)
def test_symbolic_and_terse_orderings(prompt: str, order: tuple[str, ...]) -> None:
    w = _weights(prompt)
    assert all(w[a] < w[b] for a, b in zip(order, order[1:])), w


def test_a_verdict_after_a_colon_belongs_to_the_names_before_it() -> None:
    bands = _bands("bridge: yes, railway: no go")
    assert bands["bridge"] == "preferred" and bands["railway"] == "lethal"


@pytest.mark.parametrize("prompt", ["roads good", "the tracks are nice"])
def test_terse_praise_prefers(prompt: str) -> None:
    assert "preferred" in _bands(prompt).values()


def test_qualified_roads_map_to_their_own_layers() -> None:
    layers = ["paved road", "unpaved road", "grass"]
    assert match_entity("paved road", layers).layers == ("paved road",)
    assert match_entity("unpaved road", layers).layers == ("unpaved road",)
    assert set(match_entity("road", layers).layers) == {"paved road", "unpaved road"}
    assert match_entity("trail", layers).layers == ("unpaved road",)  # drawn as the unpaved road
    w = _weights("blacktop before gravel")
    assert w["paved road"] < w["unpaved road"]


def test_a_common_word_is_not_a_misspelt_entity() -> None:
    it = interpret_offline("prefer the roads, weather permitting")
    assert "water" not in {p.entity for p in it.preferences if p.phrase}
    assert not any("'weather' as" in n for n in it.notes)
