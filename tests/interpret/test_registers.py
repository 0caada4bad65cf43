"""Set 24's constructs (issue 31), each on phrasings of its own: the registers a brief comes in --
radio digits, numbered sub-clauses, configuration lines with strictness keys and section
headers, multiples worded as "worse than", permissions and denials of regulations and config
values, a game's "tiles", advice labels, priced bands said with a noun, speech written as said.
"""

from __future__ import annotations

import pytest

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.normalise import normalise
from overseec_core.interpret.offline import interpret_offline
from overseec_core.interpret.tokens import tokenize


def _read(prompt: str):
    return interpret_offline(prompt)


def _weights(prompt: str) -> dict[str, float]:
    return {p.entity: p.weight for p in _read(prompt).preferences}


def _lethal(prompt: str) -> set[str]:
    return {p.entity for p in _read(prompt).preferences if p.lethal}


def _cues(prompt: str, kind: str) -> dict[str, tuple[float | None, bool]]:
    return {c.entity: (c.metres, c.hard) for c in _read(prompt).cues if c.kind == kind}


# -- registers
def test_radio_digits_are_one_number() -> None:
    assert _cues("Hold a minimum of one five metres off the hedge.", "far") == {"hedge": (15.0, True)}
    assert _cues("Stay twenty five metres from the hedge.", "far") == {"hedge": (25.0, False)}


def test_numbered_sub_clause_labels_name_nothing() -> None:
    r = _read("3.c The robot shall avoid the marsh.\n3.d Trails are fine.")
    assert {p.entity for p in r.preferences if not p.prior} >= {"wetland", "trail"}
    assert not {"c", "d", "d trail"} & {p.entity for p in r.preferences}
    assert not r.unparsed


def test_configuration_strictness_keys_and_section_headers() -> None:
    text = "[buffers]\nhedge_m = 6\nhedge_strict = yes\npond_m = 9\npond_strict = no\n"
    assert len(normalise(text)) == len(text)
    r = _read(text)
    assert {(c.entity, c.metres, c.hard) for c in r.cues} == {("hedge", 6.0, True), ("pond", 9.0, False)}
    assert not r.unparsed


def test_a_line_that_only_says_soft_softens_the_rule_before() -> None:
    assert _cues("Keep 20 m from the hedge.\nSoft.", "far") == {"hedge": (20.0, False)}
    assert _cues("Keep 20 m from the hedge. Not a soft rule.", "far") == {"hedge": (20.0, True)}


def test_an_advice_label_softens_every_distance_of_its_sentence() -> None:
    assert _cues("Advisory: keep at least 30 m from the railway.", "far") == {"railway": (30.0, False)}
    assert _cues("Keep at least 30 m from the railway.", "far") == {"railway": (30.0, True)}


# -- orders and levels
def test_a_multiple_worse_than_a_base_is_dearer_than_the_base() -> None:
    w = _weights("grass 2x worse than trail; mud 4 times more expensive than the trail")
    assert w["trail"] < w["grass"] < w["mud"]
    assert not _read("grass 2x worse than trail").unparsed


@pytest.mark.parametrize(
    "prompt",
    [
        '{"marsh": "deny"}',
        "OVERFLIGHT OF THE MARSH IS NOT AUTHORISED.",
        "Marsh tiles are impassable.",
    ],
)
def test_denials_forbid(prompt: str) -> None:
    assert "wetland" in _lethal(prompt)
    assert not {"tile", "marsh tile"} & {p.entity for p in _read(prompt).preferences}


@pytest.mark.parametrize(
    "prompt",
    [
        "Overflight of the buildings: authorised.",
        "The buildings are no worries.",
        "Buildings are no longer a constraint.",
        "No further restrictions apply to buildings.",
        "Use of the buildings is unrestricted.",
    ],
)
def test_permissions_lift_the_prior(prompt: str) -> None:
    w = _weights(prompt)
    assert w["building"] == lx.FINE
    assert "building" not in _lethal(prompt)


def test_a_penalty_carried_avoids_and_a_games_tiles_are_their_terrain() -> None:
    assert _weights("Road cells carry a penalty.")["road"] > lx.FINE
    assert not _read("The road tiles themselves carry a penalty.").unparsed


# -- nearness
def test_avoiding_approach_keeps_away_graded() -> None:
    assert "hedge" in _cues("Avoid approaching the hedge.", "far")


def test_as_much_room_as_possible_from_a_thing_keeps_away_from_it() -> None:
    assert "hedge" in _cues("Leave as much room as you can from the hedge.", "far")


def test_attracted_and_tight_draw_near() -> None:
    assert "trail" in _cues("The route should be attracted to the trail.", "near")
    assert "hedge" in _cues("Stay tight to the hedge.", "near")


def test_a_penalty_for_cells_within_a_band_is_a_soft_zone() -> None:
    assert _cues("Add a penalty for cells within 6 m of the pylons.", "far") == {"electric tower": (6.0, False)}


def test_the_track_bed_is_the_railway() -> None:
    assert "railway" in _lethal("The robot must not enter the track bed.")


# -- speech as written
def test_speech_as_said_reads_as_meant() -> None:
    assert [t.word for t in tokenize("give 'em room")] == ["give", "them", "room"]
    assert [t.word for t in tokenize("dinnae go in fae here")][:3] == ["don't", "go", "in"]
    assert "wetland" in _lethal("Dinnae go into the marsh.")


# -- code-like notation
def test_a_minimum_distance_to_a_thing_with_its_number_after_it() -> None:
    assert _cues("min dist to trees 3 mtrs, HARD LIMIT", "far") == {"tree": (3.0, True)}
    assert _cues("Keep a minimum distance to the hedge of 4 m.", "far") == {"hedge": (4.0, True)}


def test_costs_as_c_of_a_layer_and_much_greater_than() -> None:
    w = _weights("c(trail) ≫ c(grass) > c(road)")
    assert w["road"] < w["grass"] < w["trail"]


def test_paces_are_a_walkers_distance() -> None:
    assert _cues("Nobody goes within ten paces of the hedge.", "far") == {"hedge": (7.5, True)}


def test_an_only_when_nothing_else_works_is_a_last_resort() -> None:
    w = _weights("Grass wherever you like; gravel only when nothing else works.")
    assert w["unpaved road"] > lx.FINE and "unpaved road" not in _lethal("gravel only when nothing else works")


def test_idioms_of_liking_and_of_hard_ground() -> None:
    w = _weights("The trail's your friend. Gravel if it has to be. Grass is hard going.")
    assert w["trail"] < lx.FINE < w["unpaved road"] < lx.AVOID and w["grass"] > lx.FINE
    assert not _read("Gravel if it has to be.").unparsed


def test_snake_case_keys_read_as_words_and_an_on_key_set_false_keeps_off() -> None:
    text = 'rule = {"follow": "hedge", "on_hedge": False}'
    assert len(normalise(text)) == len(text)
    assert "off hedge" in normalise(text)
    assert normalise("side_offset") == "side offset"
    r = _read(text)
    assert "hedge" in {c.entity for c in r.cues if c.kind == "near"}


def test_a_sign_ending_a_list_item_is_its_verdict() -> None:
    w = _weights("Leg 2: road +, gravel -, grass --")
    assert w["road"] < w["unpaved road"] < w["grass"]
    assert [t.word for t in tokenize("grass + road")] == ["grass", "and", "road"]


def test_a_clock_time_is_no_mark_and_its_clause_is_reported_whole() -> None:
    r = _read("The trail is fine. This applies only between 02:00 and 04:00.")
    assert any("02:00" in u for u in r.unparsed)
    assert "02h00" in normalise("between 02:00 and")
