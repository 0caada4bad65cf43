"""Set 30's constructs (issue 31), each on phrasings of its own: sight a route must not leave, a
correlative whose traveller wanders off a thing or whose end is the speaker's worry, nearness said
as "snug to", room given "as much as you can", steps of distance with the traveller's own clause,
where a distance stops mattering said with "by", rules made hard by "zero tolerance", German and
texted verdicts.
"""

from __future__ import annotations

import pytest

from overseec_core.interpret.offline import interpret_offline


def _read(prompt: str):
    return interpret_offline(prompt)


def _cues(prompt: str, kind: str) -> dict[str, tuple[float | None, bool]]:
    return {c.entity: (c.metres, c.hard) for c in _read(prompt).cues if c.kind == kind}


def _stated(prompt: str) -> dict[str, tuple[float, bool]]:
    return {p.entity: (p.weight, p.lethal) for p in _read(prompt).preferences if not p.prior}


def test_sight_a_route_must_not_leave_is_nearness_not_a_ban():
    prompt = "Don't let the mower out of view of the barn."
    assert set(_cues(prompt, "near")) == {"barn"}
    assert not _stated(prompt).get("barn", (0.5, False))[1]


@pytest.mark.parametrize(
    "prompt",
    [
        "the further the buggy strays off the towpath, the worse",
        "keep by the towpath; the closer in it stays, the less we fret",
    ],
)
def test_a_correlative_with_the_travellers_own_clause(prompt):
    assert set(_cues(prompt, "near")) == {"towpath"}
    assert not _read(prompt).unparsed


def test_snug_and_tight_to_a_thing_are_nearness():
    assert set(_cues("keep the cart snug against the hedge", "near")) == {"hedge"}
    assert set(_cues("run tight to the fence", "near")) == {"fence"}


@pytest.mark.parametrize("room", ["all the room you can", "as much room as you reasonably can"])
def test_room_given_as_much_as_you_can_is_a_graded_far_cue(room):
    prompt = f"give the sheds {room}"
    assert set(_cues(prompt, "far")) == {"shed"}
    assert not _read(prompt).unparsed


def test_a_step_of_distance_with_the_travellers_clause():
    prompt = "Every yard nearer the quad gets to the pond is a yard worse."
    assert set(_cues(prompt, "far")) == {"pond"}
    assert not _read(prompt).unparsed


def test_where_distance_stops_mattering_said_with_by():
    prompt = "Keep the trolley away from the road; by about 14 m out it no longer matters."
    assert _cues(prompt, "far") == {"road": (14.0, False)}


@pytest.mark.parametrize("wording", ["Zero tolerance on that one.", "No tolerance.", "No exceptions on this one."])
def test_zero_tolerance_makes_the_rule_before_it_hard(wording):
    prompt = f"Keep 7 m off the railway. {wording}"
    assert _cues(prompt, "far") == {"railway": (7.0, True)}
    assert not _read(prompt).unparsed


def test_a_pronoun_rule_sentence_still_forbids_its_thing():
    assert _stated("Stay within sight of the lake. Do not go into it.")["lake"][1]


def test_german_and_texted_verdicts():
    assert _stated("buildings verboten")["building"][1]
    stated = _stated("gras gud, di road bad")
    assert stated["grass"][0] < 0.5 < stated["road"][0]


def test_not_going_crazy_over_a_rule_softens_it():
    assert _cues("give the houses 10 m, but dont go crazy over it", "far") == {"house": (10.0, False)}
    assert not _read("give the houses 10 m, but dont go crazy over it").unparsed


def test_less_room_between_the_route_and_a_thing_is_nearness():
    prompt = "the narrower the gap between the robot and the hedge, the better"
    assert set(_cues(prompt, "near")) == {"hedge"}
    assert set(_cues("the wider the margin you give the hedge, the better", "far")) == {"hedge"}


def test_a_distance_whose_verdict_says_less_or_more():
    assert set(_cues("distance to the trail: shorter is better", "near")) == {"trail"}
    assert set(_cues("DIST FROM WATER: MORE IS BETTER", "far")) == {"water"}


def test_clinging_to_a_thing_and_carrying_no_penalty():
    assert set(_cues("cling to the towpath", "near")) == {"towpath"}
    assert _stated("Walking on the trail carries no penalty.")["trail"] == (0.5, False)


def test_a_nominal_standoff_is_a_soft_one():
    assert _cues("keep a nominal standoff of 3 m from the road", "far") == {"road": (3.0, False)}


def test_texted_nearness_and_comparatives():
    assert set(_cues("stay nr the trail, closr = cheapr", "near")) == {"trail"}
    assert not _read("stay nr the trail, closr = cheapr").unparsed
