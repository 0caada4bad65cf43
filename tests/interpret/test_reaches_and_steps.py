"""Set 29's graded constructs (issue 31), each on phrasings of its own: where a fall-off ends said
as indifference ("no concern beyond", "no issue at all", "not bothered once it's past", "fading to
no bother at all by"), a graded cue said per step of distance ("every metre closer counts against
it"), "the more risk" as a correlative's end, and a telegram's STOPs.
"""

from __future__ import annotations

import pytest

from overseec_core.interpret.offline import interpret_offline


def _read(prompt: str):
    return interpret_offline(prompt)


def _cues(prompt: str, kind: str) -> dict[str, float | None]:
    return {c.entity: c.metres for c in _read(prompt).cues if c.kind == kind}


@pytest.mark.parametrize(
    "reach",
    [
        "No worry past 18 metres.",
        "There is no problem at all beyond 18 m.",
        "Past 18 m there is no issue.",
        "It fades to no concern at all by 18 metres.",
        "We're not bothered once it's past 18 m.",
    ],
)
def test_indifference_past_a_distance_is_where_the_fall_off_ends(reach):
    prompt = f"The closer to the pylon the worse. {reach}"
    assert _cues(prompt, "far") == {"electric tower": 18.0}
    assert not _read(prompt).unparsed


@pytest.mark.parametrize(
    ("prompt", "kind", "entity"),
    [
        ("every yard nearer the river counts against it", "far", "river"),
        ("each step closer to the trail is better", "near", "trail"),
        ("Avoid the pond. Every metre closer is worse.", "far", "pond"),
    ],
)
def test_a_graded_cue_said_per_step_of_distance(prompt, kind, entity):
    assert set(_cues(prompt, kind)) == {entity}
    assert not _read(prompt).unparsed


def test_more_risk_ends_a_correlative():
    assert set(_cues("the nearer the cliff, the more danger", "far")) == {"cliff"}


def test_a_telegrams_stops_end_its_sentences():
    prompt = "PREFER TRAIL STOP AVOID WATER STOP"
    weights = {p.entity: p.weight for p in _read(prompt).preferences}
    assert weights["trail"] < 0.5 < weights["water"]
    assert not _read(prompt).unparsed


# -- set 29's other constructs
def _stated(prompt: str) -> dict[str, tuple[float, bool]]:
    return {p.entity: (p.weight, p.lethal) for p in _read(prompt).preferences if not p.prior}


def test_what_a_rankings_line_names_last_is_its_last_step():
    w = {e: v[0] for e, v in _stated("road > trail; grass & building last").items()}
    assert w["road"] < w["trail"] < w["grass"] and w["trail"] < w["building"]


def test_a_json_record_about_one_subject_reads_as_one_rule():
    prompt = '[{"name": "building", "buffer_m": 7, "mandatory": true}, {"name": "trail", "rating": "preferred"}]'
    assert _cues(prompt, "far") == {"building": 7.0}
    assert _stated(prompt)["trail"][0] < 0.5
    assert not _read(prompt).unparsed


def test_a_sections_use_and_crossing_keys_speak_of_its_thing():
    prompt = "[road]\naccess = forbidden\n\n[railway]\ncrossing = allowed\n"
    stated = _stated(prompt)
    assert stated["road"][1] and stated["railway"] == (0.5, False)
    assert not _read(prompt).unparsed
    assert "level crossing" not in stated


def test_the_least_distance_of_a_topic_is_a_clearance():
    assert _cues("hedge min distance: 4 m", "far") == {"hedge": 4.0}


def test_preference_and_use_qualifiers():
    assert _stated("Drive on the trail by preference.")["trail"][0] < 0.5
    assert 0.5 < _stated("Take the gravel track only if nothing else gets you through.")["unpaved road"][0] < 1.0
    for prompt in ("Drive on the trail by preference.", "Take the gravel track only if nothing else gets you through."):
        assert not _read(prompt).unparsed


def test_passing_under_a_thing_as_often_as_you_like_allows_it():
    stated = _stated("Cycle under the oaks as often as you like.")
    assert stated["deciduous tree"][0] <= 0.5 and not _read("Cycle under the oaks as often as you like.").unparsed


def test_a_bare_traveller_part_and_a_keeping_particle_is_an_order():
    assert _stated("Follow the hedge. Tyres off the lawn.")["lawn"][0] > 0.5
    assert _stated("keep its wheels out of the pond")["pond"][0] > 0.5
    assert _stated("keep tyres off the lawn")["lawn"][0] > 0.5 and not _read("keep tyres off the lawn").unparsed


def test_altogether_strengthens_an_avoid():
    assert _stated("avoid the grass altogether")["grass"][0] > _stated("avoid the grass")["grass"][0]


# -- rules worded as absolute
def _far(prompt: str) -> dict[str, tuple[float | None, bool]]:
    return {c.entity: (c.metres, c.hard) for c in _read(prompt).cues if c.kind == "far"}


@pytest.mark.parametrize(
    "prompt",
    [
        "Hold 9 m off the railway and regard that distance as a fence.",
        "Treat a 9 m cordon round the railway as a wall.",
        "Stay 9 m from the railway. Do not violate this.",
        "Stay 9 m from the railway, not ever.",
        "Stay 9 m from the railway, not for anything.",
    ],
)
def test_a_rule_worded_as_a_wall_or_unbreakable_is_hard(prompt):
    assert _far(prompt) == {"railway": (9.0, True)}
    assert not _read(prompt).unparsed


def test_a_ring_road_is_still_a_road():
    assert _stated("avoid the ring road")["road"][0] > 0.5
    assert not _read("avoid the ring road").unparsed


def test_treating_a_thing_as_a_wall_keeps_the_thing():
    # the object names what the rule is about: it is kept, only "as a wall" reads "strictly"
    assert _far("treat a 4 m buffer around the hedge as a fence") == {"hedge": (4.0, True)}
