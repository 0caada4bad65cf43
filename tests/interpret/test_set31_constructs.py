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
