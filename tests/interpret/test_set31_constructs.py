"""Constructs of issue 31 met in set 31, each on phrasings of its own: travelling an area's edge,
a price or a reward put near a thing, a cost said to rise as the gap closes, things listed under
a verdict's section, the side of a thing kept off, a chat's speakers, a clitic "'s" before a
verdict, "don't fuss about", "confined to", "it's not to go", "don't you dare" and a section's
number.
"""

from __future__ import annotations

import pytest

from overseec_core.interpret.offline import interpret_offline


def _levels(prompt: str) -> dict[str, tuple[float, bool]]:
    return {p.entity: (p.weight, p.lethal) for p in interpret_offline(prompt).preferences if p.phrase}


def _cues(prompt: str) -> set[tuple[str, str]]:
    return {(c.kind, c.entity) for c in interpret_offline(prompt).cues}


@pytest.mark.parametrize(
    "prompt",
    [
        "Drive along the edge of the pond.",
        "Ride round the margin of the marsh.",
        "We like to drive along the edge of the pond.",
        "Ideally it should run along the margins of the pond.",
        "I'd like it to skirt along the edges of the pond.",
    ],
)
def test_travelling_an_areas_edge_prefers_the_band_not_the_area(prompt):
    read = interpret_offline(prompt)
    assert {c.kind for c in read.cues} == {"near"}
    assert all(p.weight >= 0.5 for p in read.preferences)
    assert not read.unparsed


@pytest.mark.parametrize(
    ("prompt", "kind"),
    [
        ("Proximity penalty near the pond.", "far"),
        ("A cost close to the houses, please.", "far"),
        ("A bonus next to the trail.", "near"),
    ],
)
def test_a_price_or_reward_put_near_a_thing(prompt, kind):
    assert {k for k, _ in _cues(prompt)} == {kind}
    assert not interpret_offline(prompt).unparsed


@pytest.mark.parametrize(
    ("prompt", "read"),
    [
        ("Keep away from the pond; the cost rises as the gap shrinks.", True),
        ("Keep away from the pond; the penalty falls as the distance grows.", True),
        ("Keep away from the pond; the cost rises as the distance grows.", False),
    ],
)
def test_a_cost_rising_as_the_gap_closes_restates_the_cue(prompt, read):
    assert (_cues(prompt) == {("far", "pond")}) is read  # the contradiction grades nothing
    assert (not interpret_offline(prompt).unparsed) is read


def test_things_listed_under_a_verdicts_section_take_its_verdict():
    levels = _levels("[prefer]\ntrail = yes\n\n[never]\npond = true\n\n[avoid]\ngrass: yes")
    assert levels["trail"][0] < 0.5
    assert levels["pond"][1]
    assert 0.5 < levels["grass"][0] and not levels["grass"][1]
    assert _levels("[avoid]\ngrass = no\npond = yes")["grass"] == (0.5, False)


def test_a_named_sections_yes_is_no_verdict():
    read = interpret_offline("[pond]\nswans = yes")
    assert not _levels("[pond]\nswans = yes") and read.unparsed


@pytest.mark.parametrize(
    "prompt",
    [
        "[trail]\nsurface = forbidden\nverge = preferred",
        "[trail]\nverge = preferred\nsurface = forbidden",
        "Never drive on the trail. Use the side of the trail.",
    ],
)
def test_the_side_of_a_thing_kept_off_is_the_band_beside_it(prompt):
    assert _levels(prompt)["trail"][1]
    assert _cues(prompt) == {("near", "trail")}


def test_the_side_of_a_thing_travelled_stays_on_it():
    assert _cues("Drive on the side of the trail.") == {("side", "trail")}
    assert _levels("Drive on the side of the trail.")["trail"][0] < 0.5


def test_a_chats_speakers_are_no_terrain():
    prompt = "Ana: can it take the grass?\nBo: grass is fine, the pond isn't\nAna: thanks"
    read = interpret_offline(prompt)
    assert set(_levels(prompt)) == {"grass", "pond"}
    assert not read.unparsed


def test_a_label_that_names_terrain_is_no_speaker():
    levels = _levels("Water: avoid\nTrail: yes\nWater: never")
    assert levels["water"][1] and levels["trail"][0] < 0.5
    assert set(_levels("Scaffolding: keep off\nCranes: never")) == {"scaffolding", "crane"}


@pytest.mark.parametrize(
    ("prompt", "better", "worse"),
    [
        ("The grass's fine but the trail's better", "trail", "grass"),
        ("The trail's worse than the road.", "road", "trail"),
    ],
)
def test_a_clitic_is_before_a_verdict(prompt, better, worse):
    levels = {k.split()[-1]: v for k, v in _levels(prompt).items()}
    assert levels[better][0] < levels[worse][0]


def test_a_possessive_before_a_noun_says_no_is():
    assert _cues("Follow the road's edge.") == {("near", "road")}


@pytest.mark.parametrize(
    "prompt",
    ["Don't fuss about the grass.", "The grass? Don't you go worrying about it.", "No need to stress over the grass."],
)
def test_not_fussing_about_a_thing_permits_it(prompt):
    assert _levels(prompt)["grass"] == (0.5, False)
    assert not interpret_offline(prompt).unparsed


@pytest.mark.parametrize("prompt", ["Driving is confined to the trail.", "Operation shall be restricted to the trail."])
def test_confined_to_a_thing_prefers_it(prompt):
    assert _levels(prompt)["trail"][0] < 0.5
    assert not interpret_offline(prompt).unparsed


@pytest.mark.parametrize(
    "prompt",
    ["It's not to go into the pond.", "The rover is not to enter the pond.", "Don't you dare put it in the pond."],
)
def test_an_order_not_to_go_forbids(prompt):
    assert _levels(prompt)["pond"][1]
    assert not interpret_offline(prompt).unparsed


def test_reserved_for_others_keeps_off_and_a_texted_good_prefers():
    assert 0.5 < _levels("The grass is reserved for pedestrians.")["grass"][0]
    assert _levels("grass: gd")["grass"][0] < 0.5


def test_a_sections_number_is_no_rule():
    read = interpret_offline("Section 4.1. Avoid the pond.")
    assert set(_levels("Section 4.1. Avoid the pond.")) == {"pond"}
    assert not read.unparsed


def _far(prompt: str) -> dict[str, float]:
    return {c.entity: c.metres for c in interpret_offline(prompt).cues if c.kind == "far"}


def test_multiword_names_under_a_verdicts_section():
    levels = _levels("[prefer]\nunpaved road = yes\n\n[avoid]\npaved road = yes")
    assert levels["unpaved road"][0] < 0.5 < levels["paved road"][0]


def test_a_protobuf_record_reads_as_one_rule():
    prompt = 'entry { class: "trail" effect: PREFER }\nrule { class: "pond" effect: FORBID }'
    levels = _levels(prompt)
    assert levels["trail"][0] < 0.5 and levels["pond"][1]
    assert not interpret_offline(prompt).unparsed


def test_a_protobuf_field_with_its_shape_and_range():
    prompt = 'rule {\n  class: "pond"\n  effect: REPEL\n  shape: INVERSE_DISTANCE\n  range_m: 18\n}'
    assert _far(prompt) == {"pond": 18.0}
    assert not interpret_offline(prompt).unparsed


@pytest.mark.parametrize(("strict", "hard"), [("t", True), ("nil", False)])
def test_a_lisp_clearance_with_a_bare_number(strict, hard):
    read = interpret_offline(f"(rules\n  (prefer trail)\n  (clearance pond 9 :strict {strict}))")
    assert [(c.entity, c.metres, c.hard) for c in read.cues if c.kind == "far"] == [("pond", 9.0, hard)]
    assert not read.unparsed


def test_a_bare_number_with_more_words_after_it_is_no_clearance():
    assert _far("clearance pond 9 sheep") == {}


@pytest.mark.parametrize(
    "reach",
    ["Once it's 16 m clear it makes no odds to me.", "Beyond 16 m it makes no difference.", "(fades out ~16 m)"],
)
def test_where_a_fall_off_ends_said_loosely(reach):
    prompt = f"Keep off the pond, the closer the worse. {reach}"
    assert _far(prompt) == {"pond": 16.0}
    assert not interpret_offline(prompt).unparsed


@pytest.mark.parametrize(
    ("prompt", "kind"),
    [
        ("The nearer it sneaks to the pond, the jumpier I get.", "far"),
        ("The nearer it gets to the sheds, the more it annoys people.", "far"),
        ("The closer to the trail, the calmer we feel.", "near"),
        ("The closer the rover comes to the pond, the more anxious they are.", "far"),
    ],
)
def test_a_correlatives_end_said_as_feelings(prompt, kind):
    read = interpret_offline(prompt)
    assert {c.kind for c in read.cues} == {kind}
    assert not read.unparsed


def test_the_running_lines_are_the_railway_and_a_persons_possessive_points():
    assert _far("Nobody takes it within 7 metres of the running lines.") == {"railway": 7.0}
    assert _far("It does not go within 4 meters of anyone's house.") == {"house": 4.0}


def test_pottering_near_things_nice_and_close():
    prompt = "I like it to trundle about near the shed, nice and close."
    assert _cues(prompt) == {("near", "shed")}
    assert not interpret_offline(prompt).unparsed


@pytest.mark.parametrize(
    "prompt", ["I'd rather it stayed off the grass.", "The grass though, I'd rather it kept mostly off there."]
)
def test_a_wish_in_the_past_tense_keeps_off(prompt):
    assert 0.5 < _levels(prompt)["grass"][0] < 1.0


def test_there_after_a_preposition_only_at_a_clause_end():
    assert "trail" not in _levels("Is there a trail over there?")
    assert not _levels("Avoid the pond. From there the trail is best.")["pond"][0] < 0.5


def test_a_two_word_key_outside_a_section_is_a_terse_rule():
    assert _levels("marsh areas: no")["wetland"][1]


@pytest.mark.parametrize("machine", ["forwarder", "skidder", "snowcat"])
def test_a_working_machine_is_the_traveller(machine):
    prompt = f"I'd rather the {machine} kept 6 m clear of the pond."
    assert _far(prompt) == {"pond": 6.0}
    assert not interpret_offline(prompt).unparsed


def test_a_working_machine_as_a_subject_is_no_entity():
    assert set(_levels("The snowcat must avoid the pond.")) == {"pond"}
    assert not interpret_offline("The snowcat must avoid the pond.").unparsed


def test_a_preference_not_a_rule_softens_the_rule():
    read = interpret_offline("Never within 6 m of the pond, but that's a preference, not a rule.")
    assert [(c.entity, c.hard) for c in read.cues if c.kind == "far"] == [("pond", False)]
    assert not read.unparsed


@pytest.mark.parametrize(
    ("prompt", "metres"),
    [
        ("Nothing goes within 7 m either side of the creek.", 7.0),
        ("A buffer of two chains on both sides of the creek; never enter it.", 40.2336),
        ("Keep a 9 m buffer either side of the creek and never go inside it.", 9.0),
    ],
)
def test_a_band_either_side_of_a_thing_is_around_it(prompt, metres):
    cues = [(c.entity, c.metres, c.hard) for c in interpret_offline(prompt).cues if c.kind == "far"]
    assert cues == [("creek", metres, True)]


def test_either_side_without_a_band_is_the_things_side():
    assert _cues("Walk on either side of the road.") == {("side", "road")}


@pytest.mark.parametrize(
    "prompt",
    [
        "Use the trail; the grass only if the trail is blocked.",
        "Use the trail; the grass only when the trail is flooded.",
    ],
)
def test_a_way_used_only_when_another_is_unusable_is_a_fallback(prompt):
    levels = _levels(prompt)
    assert levels["trail"][0] < 0.5 < levels["grass"][0] < 0.7
    assert not interpret_offline(prompt).unparsed


def test_only_if_a_state_that_is_no_blockage_stays_a_condition():
    assert _levels("Cross the road only if it is clear.").get("road", (0.0, False))[0] != 0.6


def test_a_penalties_section_with_a_shape_and_a_soft_key():
    prompt = 'penalties = {"pond": {"shape": "decay_with_distance", "reach_m": 14, "hard": false}}'
    read = interpret_offline(prompt)
    assert _far(prompt) == {"pond": 14.0}
    assert 0.5 < _levels(prompt)["pond"][0]
    assert not read.unparsed


def test_chat_fillers_and_a_shuttle_say_nothing_of_the_ground():
    prompt = "yo the shuttle should not be vibin near the pond, ya know?"
    read = interpret_offline(prompt)
    assert set(_levels(prompt)) == {"pond"}
    assert not read.unparsed


def test_singlish_anyhow_is_no_name_and_the_ban_holds():
    levels = _levels("Take the road. Don't anyhow go into the pond.")
    assert set(levels) == {"road", "pond"} and levels["pond"][0] > 0.5


def test_an_exception_of_an_open_thing_and_a_cart_traveller():
    prompt = "The cart never enters the buildings, apart from the open shed."
    levels = _levels(prompt)
    assert levels["building"][1] and not levels["shed"][1]
    assert not interpret_offline(prompt).unparsed


@pytest.mark.parametrize(("prompt", "name"), [("Give houses a miss.", "house"), ("give the pond a miss", "pond")])
def test_giving_a_thing_a_miss_avoids_it(prompt, name):
    assert 0.5 < _levels(prompt)[name][0]
    assert not interpret_offline(prompt).unparsed


def test_permitted_with_a_penalty_is_an_avoid():
    levels = _levels("Grass permitted with a penalty; the trail preferred.")
    assert levels["trail"][0] < 0.5 < levels["grass"][0] and not levels["grass"][1]


@pytest.mark.parametrize(
    "prompt", ["You're cleared to drive through the pond.", "The pond is shallow; drive through it freely."]
)
def test_being_cleared_or_going_freely_permits(prompt):
    assert _levels(prompt)["pond"] == (0.5, False)
    assert not interpret_offline(prompt).unparsed


def test_planted_is_no_slip_for_planned():
    assert "planted bed" in _levels("Keep out of every planted bed.")
