"""Set 23's constructs (issue 31), each on phrasings of its own: a regulation's "shall not",
bounds worded "no less than" and gaps "between the route and X", bands of distance, priced
bands, reaches said as all the room wanted, wider-room correlatives, three-column tables,
ordinal rankings, spoken hesitations, beside-but-not-on sharing one object, ground covers an
edge is made of, qualifying states, compound feet-and-inches, and exceptions after a comma.
"""

from __future__ import annotations

import pytest

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.offline import interpret_offline
from overseec_core.interpret.tokens import tokenize
from overseec_core.synthesize.fit import fit_program


def _read(prompt: str):
    return interpret_offline(prompt)


def _weights(prompt: str) -> dict[str, float]:
    return {p.entity: p.weight for p in _read(prompt).preferences}


def _lethal(prompt: str) -> set[str]:
    return {p.entity for p in _read(prompt).preferences if p.lethal}


def _cues(prompt: str, kind: str) -> dict[str, tuple[float | None, bool]]:
    return {c.entity: (c.metres, c.hard) for c in _read(prompt).cues if c.kind == kind}


# -- a regulation's prohibitions
@pytest.mark.parametrize(
    "prompt",
    ["Trucks shall not enter the marsh.", "The marsh shall not be used.", "The marsh is not to be used."],
)
def test_shall_not_forbids_as_must_not_does(prompt: str) -> None:
    assert "wetland" in _lethal(prompt)
    assert not _read(prompt).unparsed


def test_should_not_stays_an_avoid() -> None:
    assert "wetland" not in _lethal("You should not enter the marsh.")


# -- bounds and gaps
def test_no_less_than_is_at_least_and_less_than_is_within() -> None:
    assert _cues("Stay no less than 20 m from the railway.", "far") == {"railway": (20.0, True)}
    assert _cues("Stay less than 20 m from the railway.", "near") == {"railway": (20.0, True)}


def test_a_gap_between_the_route_and_a_thing_is_kept_from_the_thing() -> None:
    assert _cues("Keep at least 8 m between the robot and the hedge.", "far") == {"hedge": (8.0, True)}
    assert _cues("Keep a 10 m gap between yourself and the fence.", "far") == {"fence": (10.0, False)}


@pytest.mark.parametrize(
    ("prompt", "hard"),
    [("Stay between 3 and 6 m from the hedge.", False), ("You must stay 3 to 6 metres from the hedge.", True)],
)
def test_a_band_is_its_two_edges(prompt: str, hard: bool) -> None:
    assert _cues(prompt, "far") == {"hedge": (3.0, hard)}
    assert _cues(prompt, "near") == {"hedge": (6.0, hard)}


def test_an_obligation_hardens_a_rule_and_a_negated_one_does_not() -> None:
    assert _cues("The trench has to stay 4 m from the hedge.", "far") == {"hedge": (4.0, True)}
    assert _cues("You don't have to stay 4 m from the hedge.", "far") == {"hedge": (4.0, False)}


def test_feet_and_inches_add_up() -> None:
    ((metres, _),) = _cues("Keep at least 5 feet 3 inches from the fence.", "far").values()
    assert metres == pytest.approx(5 * 0.3048 + 3 * 0.0254)


# -- priced bands and reaches
def test_a_penalty_within_a_band_is_a_soft_zone_kept_away_from() -> None:
    r = _read("Routes are heavily penalised within 12 m of the pylons.")
    assert {(c.kind, c.entity, c.metres, c.hard) for c in r.cues} == {("far", "electric tower", 12.0, False)}


def test_a_reward_within_a_band_draws_the_route_and_its_subject_is_the_route() -> None:
    r = _read("Paths are rewarded within 10 m of the road.")
    assert {(c.kind, c.entity, c.metres, c.hard) for c in r.cues} == {("near", "road", 10.0, False)}


def test_a_cost_that_fell_with_proximity_draws_the_route() -> None:
    assert "trail" in _cues("The cost fell steadily with proximity to the trail.", "near")


def test_where_an_effect_reaches_is_the_graded_cues_reach() -> None:
    assert _cues("Penalise proximity to the sheds, the influence extending no further than 15 m.", "far") == {
        "shed": (15.0, False)
    }


def test_a_distance_said_to_be_enough_is_the_reach_of_the_cue_before() -> None:
    r = _read("The further from the hedge the better. Twenty metres should be enough.")
    assert {(c.entity, c.metres) for c in r.cues if c.kind == "far"} == {("hedge", 20.0)}
    assert not r.unparsed


def test_more_room_given_is_further_away() -> None:
    assert "shed" in _cues("The bigger the buffer you leave around the sheds, the better.", "far")
    assert not _read("The bigger the buffer you leave around the sheds, the better.").unparsed


# -- terse forms
def test_a_three_column_table_reads_row_by_row() -> None:
    w = _weights("| feature | rule | distance |\n|---|---|---|\n| marsh | avoid | - |\n| road | prefer | - |")
    assert w["wetland"] > lx.FINE > w["road"]


def test_ordinals_rank_best_first() -> None:
    w = _weights("1st choice: road. 2nd choice: trail. last: grass.")
    assert w["road"] < w["trail"] < w["grass"]


def test_a_ranking_must_run_in_order() -> None:
    w = _weights("2nd: road. 1st: trail.")
    assert not w.get("road", lx.FINE) < w.get("trail", lx.FINE)


def test_a_terse_distance_with_its_strictness_after_it_is_a_rule() -> None:
    assert _cues("rail 15 m hard", "far") == {"railway": (15.0, True)}


def test_meh_is_a_little_worse_than_fine() -> None:
    w = _weights("trail ok / grass meh")
    assert w["trail"] == lx.FINE < w["grass"] < lx.AVOID


# -- spoken briefs
def test_hesitations_and_the_word_said_again_are_dropped() -> None:
    words = [t.word for t in tokenize("keep off the, uh, the marsh")]
    assert words == ["keep", "off", "the", "marsh"]
    assert _weights("so, like, keep off the, erm, the marsh")["wetland"] > lx.FINE
    assert "like" in [t.word for t in tokenize("I like the road")]


def test_permission_as_a_noun_permits() -> None:
    assert _weights("The rover has permission to wade the stream.")["stream"] == lx.FINE


# -- on versus beside
def test_beside_but_not_on_shares_the_object_named_after_both() -> None:
    r = _read("Travel alongside, but not on, the railway.")
    assert _weights("Travel alongside, but not on, the railway.")["railway"] > lx.FINE
    assert "railway" not in _lethal("Travel alongside, but not on, the railway.")
    assert "railway" in {c.entity for c in r.cues if c.kind == "near"}
    assert "railway" in _lethal("Travel alongside, but never on, the railway.")


def test_an_edge_made_of_a_ground_cover_is_that_cover() -> None:
    prompt = "Walk beside the railway on the grass verge, never on the railway itself."
    w = _weights(prompt)
    assert w["grass"] < lx.FINE and "railway" in _lethal(prompt)
    assert not _read(prompt).unparsed


# -- qualifiers and exceptions
def test_a_state_before_a_name_with_a_rule_qualifies_it() -> None:
    assert _weights("Vacant buildings: avoid.")["vacant building"] > lx.FINE
    assert _weights("The shed is vacant.")["shed"] == lx.FINE


def test_bare_room_given_keeps_away() -> None:
    assert "shed" in _cues("Give the sheds room.", "far")


def test_an_exception_after_a_comma_excepts_from_the_clause_before() -> None:
    w = _weights("Avoid the grass, except the lawn.")
    assert w["grass"] > lx.FINE and w["lawn"] == lx.FINE


def test_an_exception_its_parent_layer_overrules_is_reported_as_without_effect() -> None:
    interp = interpret_offline("Avoid the buildings, except the old barn.")
    shared = fit_program(interp, ["building"])
    assert any("barn" in u for u in shared.no_effect)
    assert any("shares its layer" in w and "barn" in w for w in shared.warnings)
    own = fit_program(interp, ["building", "old barn"])
    assert not own.no_effect
