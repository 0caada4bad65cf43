"""Set 26's constructs (issue 31), each on phrasings of its own: rules stated as their
consequence, shares of the route, multiples of "as good as", a terse "X: no", configuration
sections and booleans, distance glosses and decimal commas, a trailing minimum, peaks of a
graded cost, topic leads, comparatives with no "than", materials after their head noun.
"""

from __future__ import annotations

import pytest

from overseec_core.interpret.normalise import normalise
from overseec_core.interpret.offline import interpret_offline
from overseec_core.interpret.sentence import Sentence
from overseec_core.interpret.statements import State, resolve_weights
from overseec_core.interpret.tokens import tokenize


def _read(prompt: str):
    return interpret_offline(prompt)


def _weights(prompt: str) -> dict[str, float]:
    return {p.entity: p.weight for p in _read(prompt).preferences}


def _lethal(prompt: str) -> set[str]:
    return {p.entity for p in _read(prompt).preferences if p.lethal}


def _cues(prompt: str, kind: str) -> dict[str, tuple[float | None, bool]]:
    return {c.entity: (c.metres, c.hard) for c in _read(prompt).cues if c.kind == kind}


# -- consequences
@pytest.mark.parametrize(
    ("prompt", "entity"),
    [
        ("Should the robot drive into the pond, the job is ruined.", "pond"),
        ("If we end up in the marsh we're done for.", "wetland"),
        ("if it ever gets onto the railway it's game over", "railway"),
    ],
)
def test_a_consequence_forbids_where_it_follows_from(prompt: str, entity: str) -> None:
    r = _read(prompt)
    assert entity in {p.entity for p in r.preferences if p.lethal}
    assert not r.unparsed


def test_a_consequence_of_coming_within_a_distance_is_a_hard_clearance() -> None:
    assert _cues("If the drone comes within 12 m of the building, the mission is scrubbed.", "far") == {
        "building": (12.0, True)
    }


def test_an_if_clause_with_no_consequence_stays_unread() -> None:
    r = _read("If it touches the water, send a photo.")
    assert "water" not in _lethal("If it touches the water, send a photo.")
    assert r.unparsed


# -- shares of the route
def test_a_cap_on_a_share_avoids_the_class_and_a_floor_prefers_it() -> None:
    w = _weights("Keep no more than 5 percent of the trip on the trail; at least 70 % on the road.")
    assert w["trail"] > 0.5 > w["road"]


def test_the_rest_goes_where_it_is_said_to_belong() -> None:
    w = _weights("Under 20% on grass, the rest should go on the trail.")
    assert w["grass"] > 0.5 > w["trail"]


# -- multiples of an equality
@pytest.mark.parametrize(
    ("prompt", "better", "worse"),
    [
        ("Trails are twice as good as grass.", "trail", "grass"),
        ("Grass is half as good as the road.", "road", "grass"),
        ("Water is three times as bad as the trees.", "tree", "water"),
    ],
)
def test_a_multiple_of_as_good_as_is_a_comparison(prompt: str, better: str, worse: str) -> None:
    w = _weights(prompt)
    assert w[better] < w[worse]


def test_as_good_as_without_a_multiple_is_still_an_equality_and_never_fails() -> None:
    w = _weights("Grass is as good as trail; mud is as good as sand.")
    assert w["grass"] == w["trail"]


def test_an_equality_between_two_names_nothing_states_is_no_conflict() -> None:
    """The weights of two names only compared with each other stay unset: no comparison to
    meet, no note, no crash (set 26's "twice as good as" once named "twice" so)."""
    st = State("x")
    st.constraints.append(("eq", "bog", "fen"))
    resolve_weights(st)
    assert st.notes == [] and "bog" not in st.weights


# -- a terse "no"
@pytest.mark.parametrize("prompt", ["trail fine. grass no.", "grass: no", "grass = no; road: ok"])
def test_a_bare_no_as_a_names_verdict_forbids_it(prompt: str) -> None:
    assert "grass" in _lethal(prompt)


def test_no_before_a_name_stays_an_avoid() -> None:
    assert "grass" not in _lethal("no grass please")


# -- configuration sections and booleans
def test_a_section_names_the_entity_of_its_keys() -> None:
    prompt = "[standoff.water]\nmin_m = 7\nhard = true\n"
    assert _cues(prompt, "far") == {"water": (7.0, True)}
    assert not _read(prompt).unparsed


def test_boolean_keys_read_as_their_verdicts() -> None:
    prompt = "[layers.water]\npassable = false\n\n[layers.grass]\npassable = true\n"
    assert _lethal(prompt) == {"water"}
    assert _weights(prompt)["grass"] == 0.5


def test_a_place_key_reads_as_where_the_route_is() -> None:
    toks = [t.word for t in tokenize("[trail]\non = false\nalong = true\n")]
    assert toks == ["\n", "not", "on", "trail", "\n", "along", "trail", "\n"]


def test_a_section_whose_keys_name_things_is_only_a_group() -> None:
    toks = [t.word for t in tokenize("[buffers]\nhedge_m = 6\n")]
    assert "buffers" not in toks


def test_a_config_file_name_names_nothing() -> None:
    r = _read("# rover.yaml\nwater: forbidden\n")
    assert "water" in {p.entity for p in r.preferences if p.lethal} and not r.unparsed


# -- distances: glosses, decimal commas, trailing minima
@pytest.mark.parametrize(
    ("prompt", "metres"),
    [
        ("Keep 6 m (about 20 ft) off the water.", 6.0),
        ("Keep 30 ft (9 m) off the water.", 9.144),
        ("Keep 1,5 m from the water.", 1.5),
    ],
)
def test_the_figure_stated_first_is_the_one_meant(prompt: str, metres: float) -> None:
    assert _cues(prompt, "far")["water"][0] == pytest.approx(metres)
    assert not _read(prompt).unparsed
    assert len(normalise(prompt)) == len(prompt)


def test_a_thousands_comma_is_no_decimal() -> None:
    assert normalise("1,000 m") == "1,000 m"


@pytest.mark.parametrize("prompt", ["Stay 8 m at the minimum from the water.", "8 m at least from the water, please."])
def test_a_minimum_after_its_distance_is_a_hard_bound(prompt: str) -> None:
    assert _cues(prompt, "far") == {"water": (8.0, True)}


# -- graded costs: peaks, easing off, topic leads
def test_a_peak_next_to_a_thing_restates_the_graded_far_cue() -> None:
    prompt = "The penalty grows as you near the water, strongest right beside it, easing off by 20 m."
    r = _read(prompt)
    assert {(c.kind, c.entity, c.metres) for c in r.cues} == {("far", "water", 20.0)}
    assert not r.unparsed


def test_a_peak_alone_is_a_graded_far_cue() -> None:
    assert "water" in _cues("Cost is highest right next to the water.", "far")


@pytest.mark.parametrize("lead", ["As for", "Regarding", "Looking at", "With respect to"])
def test_a_topic_lead_names_no_entity(lead: str) -> None:
    r = _read(f"{lead} the trees: avoid them.")
    assert {p.entity for p in r.preferences if p.phrase} == {"tree"}
    assert not r.unparsed


# -- comparatives with no "than", materials after their noun
def test_a_comparative_with_no_than_compares_with_what_was_named_before() -> None:
    w = _weights("Gravel roads are allowed. The paved ones are nicer.")
    assert w["paved road"] < w["unpaved road"]
    w = _weights("Grass is fine, but the trail is better.")
    assert w["trail"] < w["grass"]


def test_a_comparative_with_nothing_before_says_nothing() -> None:
    assert _read("The trail is better.").unparsed


def test_a_material_after_its_head_noun_qualifies_it() -> None:
    r = _read("Use the roads made of asphalt; avoid the roads of gravel.")
    w = {p.entity: p.weight for p in r.preferences}
    assert w["paved road"] < 0.5 < w["unpaved road"]
    assert {p.entity for p in r.preferences if p.phrase} == {"paved road", "unpaved road"}  # no plain "road"


# -- nearness said plainly, verse, a route's own conditions
def test_lingering_by_a_thing_is_nearness() -> None:
    assert "water" in _cues("Let it dwell near the water.", "near")


def test_a_plain_comparative_of_a_topic_is_graded() -> None:
    assert "building" in _cues("buildings: farther is better", "far")
    assert "trail" in _cues("trail -- nearer is best", "near")
    assert "water" in _cues("water: closer is worse", "far")


def test_a_spaced_slash_breaks_a_line_and_a_tight_one_is_or() -> None:
    assert [t.word for t in tokenize("trees / the nearer the sweeter")][1] == ","
    assert [t.word for t in tokenize("road/trail")] == ["road", "or", "trail"]


def test_taking_a_route_prefers_nothing_it_passes() -> None:
    prompt = "If the route can keep 12 m from the water, use it; if it cannot, closer is fine."
    r = _read(prompt)
    assert {(c.kind, c.entity, c.metres, c.hard) for c in r.cues} == {("far", "water", 12.0, False)}
    assert "water" not in {p.entity for p in r.preferences if p.phrase}
    assert not r.unparsed


# -- prices said as nouns
def test_a_heavy_price_avoids_more_than_a_small_one() -> None:
    w = _weights("a stiff penalty for the trail; a slight penalty on grass")
    assert w["trail"] > w["grass"] > 0.5
    assert _weights("road: heavy penalty")["road"] > 0.5


def test_a_peak_word_after_a_graded_fall_off_restates_it() -> None:
    r = _read("Cost falls off with distance from the trail: heavy right beside it, nothing extra past 15 m.")
    assert {(c.kind, c.entity, c.metres) for c in r.cues} == {("far", "trail", 15.0)}
    assert not r.unparsed


def test_an_adverb_is_no_slip_of_its_adjective() -> None:
    assert [t.word for t in tokenize("more heavily")] == ["more", "heavily"]
    assert Sentence(tokenize("penalised more heavily the closer it gets")).words[2] == "heavily"


# -- checklists and layer notes (set 27)
def test_dot_leaders_read_as_a_checklists_colons() -> None:
    prompt = "TRAIL ....... PREFERRED\nGRASS ....... AS REQUIRED\nWATER ....... NO GO ..... check"
    r = _read(prompt)
    w = {p.entity: p.weight for p in r.preferences}
    assert w["trail"] < 0.5 == w["grass"] and "water" in _lethal(prompt)
    assert not r.unparsed and len(normalise(prompt)) == len(prompt)


def test_a_rule_numbered_in_words_is_a_label() -> None:
    r = _read("Rule one, keep off the grass. Step two: use the road.")
    assert {p.entity for p in r.preferences if p.phrase} == {"grass", "road"} and not r.unparsed


def test_an_offset_is_a_clearance_and_not_required_softens_it() -> None:
    assert _cues("TREES: offset 4 m", "far") == {"tree": (4.0, False)}
    assert _cues("water clearance 20 m, not required", "far") == {"water": (20.0, False)}


def test_the_course_is_the_route() -> None:
    r = _read("The course must never come within 8 m of the water.")
    assert {p.entity for p in r.preferences if p.phrase} <= {"water"}
    assert _cues("The course must never come within 8 m of the water.", "far") == {"water": (8.0, True)}


def test_slang_correlatives_grade_away() -> None:
    assert "water" in _cues("water: the closer it gets the sketchier", "far")


# -- "too far" / "too close": a warning, the other way round
@pytest.mark.parametrize(
    ("prompt", "entity", "kind"),
    [
        ("Go too far from the footpath.", "footpath", "near"),
        ("Never go too close to the water.", "water", "far"),  # negated as well
        ("Get too close to the pond and the wheels sink.", "pond", "far"),
        ("don't stray too far from the trail", "trail", "near"),  # negated: negated_kind's, not flipped twice
        ("Stay far from the river.", "river", "far"),  # no "too": as said
        ("Go too far from the trail, later we cannot find you.", "trail", "near"),  # "later" is time
    ],
)
def test_too_far_and_too_close_are_warnings(prompt: str, entity: str, kind: str) -> None:
    got = {c.entity: c.kind for c in _read(prompt).cues}
    assert got.get(entity) == kind and "later" not in got, got
