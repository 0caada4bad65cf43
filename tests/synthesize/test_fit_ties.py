"""Which preference a layer keeps when several prompt entities land on it (``fit.layer_preferences``).

Each test builds two entities that share one layer and differ in exactly one component of the
tie-break key -- said by the prompt, closer match rule, nearer broader depth, a prior over plain
neutral, lethal, farther from neutral, the worse level -- with every earlier component equal, so
that component alone decides. Where a later component would pick the other entity, dropping the
component under test flips the winner; where the entities tie on everything after it, both
entity orders are tried, since ``max`` would otherwise keep whichever came first.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import pytest

from overseec_core.interpret.matching import match_entities
from overseec_core.schema import Entity, Interpretation, Preference
from overseec_core.synthesize.fit import layer_preferences


def said(entity: str, weight: float, phrase: str, lethal: bool = False) -> Preference:
    """A preference the prompt stated, with the words it came from."""
    return Preference(entity, 1, weight, lethal, phrase=phrase)


def fit(prefs: Sequence[Preference], layers: Sequence[str], rules: Sequence[tuple[str, int]]):
    """``layer_preferences`` for an interpretation of just these preferences, after checking that
    the entities match ``layers`` by the expected (rule, depth) each, so the test exercises the
    key component it names and not an earlier one."""
    interp = Interpretation(prompt="", entities=tuple(Entity(p.entity) for p in prefs), preferences=tuple(prefs))
    matches = match_entities([p.entity for p in prefs], layers)
    assert [(m.rule, m.depth) for m in matches] == list(rules)
    return layer_preferences(interp, matches)


def overruled_note(layer: str, cands: Sequence[Preference], kept: str, over: str) -> str:
    names = ", ".join(p.entity for p in cands)
    return f"layer '{layer}' stands for {names}; kept the preference of '{kept}' (over {over})"


def test_what_the_prompt_said_beats_a_closer_match_at_its_prior() -> None:
    # "building" names the layer but only carries its prior; "shed" is a broader match the
    # prompt spoke about: the prompt's words win (by name alone the prior would)
    prior = Preference("building", 1, 1.0, prior=True)
    shed = said("shed", 0.3, "sheds are good cover")
    chosen, notes = fit([prior, shed], ["building"], [("name", 0), ("broader", 1)])
    assert chosen == {"building": replace(shed, entity="building")}
    assert notes == []  # a prior is not something the prompt said: nothing was overruled


def test_the_closer_match_rule_wins() -> None:
    # both said, both depth 0: "forest" is the layer's name, "woods" only a synonym; the synonym's
    # level is farther from neutral, so without the rule it would win
    forest = said("forest", 0.3, "prefer the forest")
    woods = said("woods", 0.8, "avoid the woods")
    chosen, notes = fit([forest, woods], ["forest"], [("name", 0), ("synonym", 0)])
    assert chosen == {"forest": replace(forest, entity="forest")}
    assert notes == [overruled_note("forest", [forest, woods], "forest", "woods")]


def test_the_nearer_broader_kind_wins() -> None:
    # grass is one step below vegetation, the baseball field two (field -> grass -> vegetation);
    # the field's level is farther from neutral, so without the depth it would win
    grass = said("grass", 0.3, "grass is good")
    field = said("baseball field", 0.8, "avoid the baseball field")
    chosen, notes = fit([field, grass], ["vegetation"], [("broader", 2), ("broader", 1)])
    assert chosen == {"vegetation": replace(grass, entity="vegetation")}
    assert notes == [overruled_note("vegetation", [field, grass], "grass", "baseball field")]


@pytest.mark.parametrize("order", [1, -1])
def test_a_prior_beats_plain_neutral(order: int) -> None:
    # neither said, both synonyms of the layer: the unsaid hazard keeps its prior over the
    # unsaid neutral default
    house = Preference("house", 1, 1.0, prior=True)
    structure = Preference("structure", 1, 0.5)
    prefs = [house, structure][::order]
    chosen, notes = fit(prefs, ["building"], [("synonym", 0)] * 2)
    assert chosen == {"building": replace(house, entity="building")}
    assert notes == []


@pytest.mark.parametrize("order", [1, -1])
def test_lethal_wins_a_tie_in_level(order: int) -> None:
    # both name the layer ("water (Hydro)" answers to both), both at 1.0: only one is lethal
    water = said("water", 1.0, "never enter the water", lethal=True)
    hydro = said("hydro", 1.0, "avoid hydro")
    prefs = [water, hydro][::order]
    chosen, notes = fit(prefs, ["water (Hydro)"], [("name", 0)] * 2)
    assert chosen == {"water (Hydro)": replace(water, entity="water (Hydro)")}
    assert notes == [overruled_note("water (Hydro)", prefs, "water", "hydro")]


@pytest.mark.parametrize("order", [1, -1])
def test_the_level_farther_from_neutral_wins(order: int) -> None:
    # 0.1 is 0.4 from neutral, 0.8 only 0.3: the stronger wish wins though 0.8 is the worse level
    water = said("water", 0.1, "prefer the water")
    hydro = said("hydro", 0.8, "avoid hydro")
    prefs = [water, hydro][::order]
    chosen, notes = fit(prefs, ["water (Hydro)"], [("name", 0)] * 2)
    assert chosen == {"water (Hydro)": replace(water, entity="water (Hydro)")}
    assert notes == [overruled_note("water (Hydro)", prefs, "water", "hydro")]


@pytest.mark.parametrize("order", [1, -1])
@pytest.mark.parametrize(("good", "bad"), [(0.25, 0.75), (0.3, 0.7), (0.4, 0.6)])
def test_equally_strong_levels_go_to_the_worse(order: int, good: float, bad: float) -> None:
    # equally far from neutral, exact in binary (0.25/0.75) or not (0.5 - 0.3 != 0.7 - 0.5 in
    # floating point, and 0.7 is the avoid level): the worse is kept
    water = said("water", good, "water is good")
    hydro = said("hydro", bad, "avoid hydro")
    prefs = [water, hydro][::order]
    chosen, notes = fit(prefs, ["water (Hydro)"], [("name", 0)] * 2)
    assert chosen == {"water (Hydro)": replace(hydro, entity="water (Hydro)")}
    assert notes == [overruled_note("water (Hydro)", prefs, "hydro", "water")]


def _interp(prefs: Sequence[Preference]) -> Interpretation:
    return Interpretation(prompt="", entities=tuple(Entity(p.entity) for p in prefs), preferences=tuple(prefs))


def test_a_layer_forbidden_for_one_kind_and_allowed_for_another_is_avoided_not_impassable() -> None:
    from overseec_core.synthesize.fit import fit_program

    conifer = said("conifer tree", 1.0, "keep out from under the conifers", lethal=True)
    oak = said("deciduous tree", 0.5, "the oaks you can go under")
    prefs, notes = fit([conifer, oak], ["tree", "grass"], [("modifier", 0), ("modifier", 0)])
    assert prefs["tree"].weight == 1.0 and not prefs["tree"].lethal
    assert any("avoided, not impassable" in n for n in notes)
    fitted = fit_program(_interp([conifer, oak]), ["tree", "grass"])
    assert any("conifer" in u for u in fitted.no_effect)  # the forbidding rule is not kept as stated
    assert not any("deciduous" in u for u in fitted.no_effect)  # the permission had its effect
    assert any("not kept as stated" in w for w in fitted.warnings)


def test_a_kind_matched_by_name_keeps_its_lethal_layer() -> None:
    # "shallow water is fine" lands on the "deep water" layer only as a broader match: no bend
    deep = said("deep water", 1.0, "deep water is a no-go", lethal=True)
    shallow = said("shallow water", 0.5, "shallow water is fine")
    prefs, _ = layer_preferences(
        _interp([deep, shallow]), match_entities(["deep water", "shallow water"], ["deep water"])
    )
    assert prefs["deep water"].lethal


def test_a_lethal_kind_beside_an_avoided_one_stays_lethal() -> None:
    conifer = said("conifer tree", 1.0, "never under the conifers", lethal=True)
    oak = said("deciduous tree", 0.7, "avoid the oaks")
    prefs, _ = fit([conifer, oak], ["tree"], [("modifier", 0), ("modifier", 0)])
    assert prefs["tree"].lethal
