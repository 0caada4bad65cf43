"""The offline interpreter: the paper's prompts, the phrase tiers, cues, orderings, leftovers."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from overseec_core.costlang import check_program
from overseec_core.errors import InterpretError
from overseec_core.interpret import interpret
from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.offline import interpret_offline
from overseec_core.interpret.schema import DEFAULT_ENTITIES, Cue

PAPER = ("Prefer the roads and trails, grass should be fine, try to avoid the baseball field as "
         "much as possible.")


def prefs(prompt: str) -> dict[str, tuple[int, float, bool]]:
    return {p.entity: (p.rank, p.weight, p.lethal) for p in interpret_offline(prompt).preferences}


def ranks(prompt: str) -> dict[str, int]:
    return {k: v[0] for k, v in prefs(prompt).items()}


def weight(prompt: str, entity: str) -> float:
    return prefs(prompt)[entity][1]


def lethal(prompt: str, entity: str) -> bool:
    return prefs(prompt)[entity][2]


# ----------------------------------------------------------------------------- the paper's prompts


def test_paper_prompt_ranking_exact():
    it = interpret_offline(PAPER)
    r = {p.entity: p.rank for p in it.preferences}
    assert (r["road"], r["trail"], r["grass"], r["baseball field"]) == (1, 1, 2, 3)
    assert it.hierarchy == (("baseball field", "grass"),)
    assert [e.name for e in it.entities] == [n for n, _ in DEFAULT_ENTITIES] + ["baseball field"]
    assert {e.name: e.geometry for e in it.entities}["baseball field"] == "areal"
    assert it.unparsed == () and it.cues == ()
    assert it.source == "offline"
    check_program(it.program, [e.name for e in it.entities])


def test_avoid_electric_tower_vs_can_go_under():
    avoid = prefs("avoid electric tower")["electric tower"]
    under = prefs("you can go under the electric towers")["electric tower"]
    assert avoid[1] >= lx.AVOID and under[1] <= lx.FINE
    assert not under[2]  # passable
    assert avoid[0] > ranks("avoid electric tower")["grass"]  # worse than what is fine
    assert lethal("electric towers are impassable", "electric tower")
    assert prefs("avoid pylons") == prefs("avoid electric tower")  # synonym


def test_avoid_river_vs_river_is_dry():
    avoid = prefs("avoid river")["river"]
    dry = prefs("the river is dry")["river"]
    assert avoid == (avoid[0], lx.AVOID, False)
    assert dry[1] == lx.FINE and not dry[2]
    assert dry[1] < avoid[1]
    it = interpret_offline("the river is dry")
    assert ("river", "water") in it.hierarchy


def test_centre_vs_side_of_the_road():
    centre = interpret_offline("stay on the center of the road")
    side = interpret_offline("drive on the side of the road")
    assert centre.cues == (Cue("centre", "road"),) and side.cues == (Cue("side", "road"),)
    for it in (centre, side):
        assert {p.entity: p.rank for p in it.preferences}["road"] == 1
        assert it.unparsed == ()
        check_program(it.program, [e.name for e in it.entities])
    assert interpret_offline("keep to the edges of the road").cues == (Cue("side", "road"),)
    assert interpret_offline("follow the road centre line").cues == (Cue("centre", "road"),)
    assert interpret_offline("stay on the roadside").cues == (Cue("side", "road"),)


def test_paper_example_with_dry_pond_and_sides():
    it = interpret_offline("avoid the baseball field. the pond is dry, so you can go over it. "
                           "stay on the sides of the road, dont go over water.")
    p = {x.entity: (x.weight, x.lethal) for x in it.preferences}
    assert p["baseball field"] == (lx.AVOID, False)
    assert p["pond"] == (lx.FINE, False)
    assert p["water"] == (lx.AVOID, False)
    assert p["road"] == (lx.PREFER, False)
    assert Cue("side", "road") in it.cues
    assert set(it.hierarchy) == {("baseball field", "grass"), ("pond", "water")}
    assert it.unparsed == ()


# ----------------------------------------------------------------------------- tiers


@pytest.mark.parametrize("phrase, tier", [
    ("prefer the trees", lx.PREFER), ("trees are best", lx.PREFER), ("trees are ideal", lx.PREFER),
    ("stay on the trees", lx.PREFER), ("trees are fine", lx.FINE), ("trees are okay", lx.FINE),
    ("trees are acceptable", lx.FINE), ("trees are tolerable", lx.TOLERABLE),
    ("use trees only if necessary", lx.TOLERABLE), ("avoid trees", lx.AVOID),
    ("don't go through trees", lx.AVOID), ("stay off the trees", lx.AVOID),
    ("try to avoid trees as much as possible", lx.STRONG_AVOID),
    ("you may cross the trees", lx.FINE),
])
def test_phrase_tiers(phrase, tier):
    p = prefs(phrase)["tree"]
    assert p[1] == tier and not p[2]
    assert interpret_offline(phrase).unparsed == ()


@pytest.mark.parametrize("phrase", [
    "never enter the water", "water is forbidden", "water is impassable", "water is off-limits",
    "avoid water at all costs", "you must not cross the water", "water is a no-go zone",
    "under no circumstances go into the water",
])
def test_lethal_phrases(phrase):
    assert prefs(phrase)["water"] == (max(ranks(phrase).values()), 1.0, True)
    assert interpret_offline(phrase).unparsed == ()


def test_negation_combines_with_the_trigger_beside_it():
    assert weight("don't use the grass", "grass") == lx.AVOID
    assert weight("grass is not fine", "grass") == lx.AVOID
    assert weight("grass isn't okay", "grass") == lx.AVOID
    assert lethal("never use the grass", "grass")


def test_each_entity_takes_the_nearest_trigger():
    p = prefs("avoid water and roads are fine")
    assert p["water"][1] == lx.AVOID and p["road"][1] == lx.FINE
    p = prefs("The robot should avoid trees and buildings, prefer the road")
    assert p["tree"][1] == p["building"][1] == lx.AVOID and p["road"][1] == lx.PREFER


def test_lists_and_bare_clauses_share_the_trigger():
    p = prefs("avoid water, buildings and trees; you may cross the river")
    assert p["water"][1] == p["building"][1] == p["tree"][1] == lx.AVOID
    assert p["river"][1] == lx.FINE
    assert weight("trees: avoid", "tree") == lx.AVOID
    p = prefs("roads, trails and paths are fine")
    assert p["road"][1] == p["trail"][1] == p["path"][1] == lx.FINE


def test_pronoun_refers_to_the_previous_clause():
    assert weight("The lake is frozen, so you may cross it", "lake") == lx.FINE
    assert weight("There is a pond. Avoid it.", "pond") == lx.AVOID


# ----------------------------------------------------------------------------- orderings


def test_first_then_ordering():
    r = ranks("First use the roads, then trails, then grass.")
    assert r["road"] < r["trail"] < r["grass"] < r["tree"]
    p = prefs("Use trails first, then roads, finally grass. Never cross the river.")
    assert p["trail"][0] < p["road"][0] < p["grass"][0]
    assert p["river"][2]


def test_better_worse_than():
    r = ranks("Roads are better than trails. Grass is worse than trails.")
    assert r["road"] < r["trail"] < r["grass"]
    r = ranks("trails are better than roads")
    assert r["trail"] < r["road"]
    r = ranks("prefer the bridge over the ford")
    assert r["bridge"] < r["ford"]
    r = ranks("use the trails rather than the grass")
    assert r["trail"] < r["grass"]
    r = ranks("grass is fine but worse than trails")
    assert r["trail"] < r["grass"]
    p = prefs("the pond is as good as the lake, the lake is okay")
    assert p["pond"][1] == p["lake"][1] == lx.FINE


def test_later_statement_wins_and_is_noted():
    it = interpret_offline("Avoid grass. Grass is fine.")
    assert {p.entity: p.weight for p in it.preferences}["grass"] == lx.FINE
    assert any("'grass': the last statement (fine) overrides an earlier one (avoid)" in n for n in it.notes)


# ----------------------------------------------------------------------------- conditions and cues


def test_unless_near_condition():
    it = interpret_offline("avoid grass unless near a road")
    assert {p.entity: p.weight for p in it.preferences}["grass"] == lx.AVOID
    assert it.cues == (Cue("unless_near", "grass", lx.DEFAULT_CUE_DISTANCE_M, "road"),)
    check_program(it.program, [e.name for e in it.entities])
    assert interpret_offline("Unless near the road, stay off the grass").cues == it.cues
    assert interpret_offline("avoid grass, unless it is near a road").cues == it.cues


def test_if_near_and_distances():
    it = interpret_offline("grass is okay if within 5 m of a trail")
    assert it.cues == (Cue("if_near", "grass", 5.0, "trail"),)
    assert interpret_offline("avoid grass unless within 20 ft of the road or trail").cues == (
        Cue("unless_near", "grass", pytest.approx(6.096), "road"),
        Cue("unless_near", "grass", pytest.approx(6.096), "trail"))
    assert interpret_offline("avoid grass near roads").cues == (
        Cue("if_near", "grass", lx.DEFAULT_CUE_DISTANCE_M, "road"),)


def test_near_and_far_cues():
    it = interpret_offline("Keep at least 10 m from buildings and stay within 5 metres of the road")
    assert it.cues == (Cue("far", "building", 10.0), Cue("near", "road", 5.0))
    assert interpret_offline("stay 2 km away from the water").cues == (Cue("far", "water", 2000.0),)
    assert interpret_offline("stay near the river").cues == (
        Cue("near", "river", lx.DEFAULT_CUE_DISTANCE_M),)
    it = interpret_offline("avoid going near buildings")
    assert it.cues == (Cue("far", "building", lx.DEFAULT_CUE_DISTANCE_M),)
    assert {p.entity: p.weight for p in it.preferences}["building"] == lx.AVOID
    for text in ("stay ten metres away from the power lines", "keep more than 15 m from the lake"):
        it = interpret_offline(text)
        assert it.cues[0].kind == "far" and it.unparsed == ()
        check_program(it.program, [e.name for e in it.entities])


# ----------------------------------------------------------------------------- entities


def test_geometry_table_and_fallback():
    geo = {e.name: e.geometry for e in interpret_offline(
        "avoid the railway, power lines, fences, rivers, the lake, the forest, buildings, "
        "the parking lot and the muddy canal").entities}
    assert geo["railway"] == geo["power line"] == geo["fence"] == geo["river"] == "linear"
    assert geo["lake"] == geo["forest"] == geo["building"] == geo["parking lot"] == "areal"
    assert geo["muddy canal"] == "linear"  # compound: geometry of its known tail
    assert lx.geometry_of("goat track") == "linear" and lx.geometry_of("sandbox") == "areal"


def test_hierarchy_table():
    it = interpret_offline("avoid the football field, the lawn, the highway, the footpath, "
                           "the orchard, the shed, the stream and the electric tower")
    assert set(it.hierarchy) == {("football field", "grass"), ("lawn", "grass"), ("highway", "road"),
                                 ("footpath", "trail"), ("orchard", "tree"), ("shed", "building"),
                                 ("stream", "water")}
    assert lx.parent_of("electric tower") is None and lx.parent_of("dirt road") == "road"
    assert lx.parent_of("muddy baseball field") == "grass" and lx.parent_of("concrete bridge") is None


def test_open_vocabulary_entities_and_compounds():
    it = interpret_offline("prefer dirt roads, avoid the sandbox")
    p = {x.entity: x.weight for x in it.preferences}
    assert p["dirt road"] == lx.PREFER and p["sandbox"] == lx.AVOID
    assert ("dirt road", "road") in it.hierarchy
    assert it.unparsed == ()


def test_defaults_get_their_prior_and_a_note():
    it = interpret_offline("avoid the sandbox")
    p = {x.entity: (x.weight, x.lethal) for x in it.preferences}
    assert {n: p[n][0] for n, _ in DEFAULT_ENTITIES} == lx.DEFAULT_PRIORS
    assert not any(p[n][1] for n, _ in DEFAULT_ENTITIES)
    assert any(n.startswith("no preference stated, default weights: road 0.1") for n in it.notes)


def test_entities_named_only_in_cues_get_neutral_weight():
    p = {x.entity: x.weight for x in interpret_offline("keep 10 m from the pylons").preferences}
    assert p["electric tower"] == lx.NEUTRAL


# ----------------------------------------------------------------------------- leftovers


@pytest.mark.parametrize("prompt, fragment", [
    ("Avoid the baseball field on weekends", "weekends"),
    ("Please be careful", "Please be careful"),
    ("Prefer roads. Éviter l'eau", "Éviter l'eau"),
    ("If the river is dry, you may cross it", "If the river is dry"),
    ("cross the bridge", "cross the bridge"),
    ("stay in the middle of the field", "stay in the middle of the field"),
])
def test_what_is_not_understood_is_reported(prompt, fragment):
    assert fragment in interpret_offline(prompt).unparsed


def test_nothing_dropped_from_a_mixed_prompt():
    it = interpret_offline("Prefer roads, do a barrel roll, avoid water")
    assert {p.entity: p.weight for p in it.preferences}["water"] == lx.AVOID
    assert any("barrel roll" in u for u in it.unparsed)


def test_deterministic():
    prompt = "first roads then trails, avoid grass unless near a road, keep 5 m from buildings"
    a, b = interpret_offline(prompt), interpret_offline(prompt)
    assert a == b and a.to_json() == b.to_json()


@pytest.mark.parametrize("prompt", ["", "   ", "...", "12 34"])
def test_empty_or_wordless_prompts_are_errors(prompt):
    with pytest.raises(InterpretError):
        interpret(prompt, offline=True)


def test_long_prompt_is_refused():
    with pytest.raises(InterpretError, match="at most"):
        interpret("avoid water " * 1000, offline=True)


# ----------------------------------------------------------------------------- property


_WORDS = sorted({w for phrase in lx.SURFACE for w in phrase} | set(
    "prefer avoid never fine okay tolerable best ideal forbidden impassable off limits at all costs "
    "can go under you may cross worse better than first then unless if near within at least 10 m "
    "from of the side centre center edge it them , . ; and or but not don't dry 5 km ft".split()))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.one_of(st.sampled_from(_WORDS), st.text(max_size=6)), min_size=1, max_size=25))
def test_any_prompt_gives_an_error_or_a_valid_interpretation(words):
    prompt = " ".join(words)
    try:
        it = interpret(prompt, offline=True)
    except InterpretError:
        return
    names = [e.name for e in it.entities]
    assert len(set(names)) == len(names)
    assert {p.entity for p in it.preferences} == set(names)
    assert all(0.0 <= p.weight <= 1.0 and p.rank >= 1 for p in it.preferences)
    assert all(c in names and p in names for c, p in it.hierarchy)
    assert all(u in prompt for u in it.unparsed)  # quoted from the prompt itself
    check_program(it.program, names)
