"""Set 21's constructs (issue 31), each on phrasings of its own: self-corrections, indifference,
availability conditionals, texting, indifferent reaches, amounts and gaps "between", topic
labels and headings of the way to go.
"""

from __future__ import annotations

import pytest

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.corrections import corrected
from overseec_core.interpret.normalise import normalise
from overseec_core.interpret.offline import interpret_offline
from overseec_core.interpret.tokens import sentences, tokenize


def _read(prompt: str):
    return interpret_offline(prompt)


def _weights(prompt: str) -> dict[str, float]:
    return {p.entity: p.weight for p in _read(prompt).preferences}


def _lethal(prompt: str) -> set[str]:
    return {p.entity for p in _read(prompt).preferences if p.lethal}


def _far(prompt: str) -> dict[str, float | None]:
    return {c.entity: c.metres for c in _read(prompt).cues if c.kind == "far"}


# -- self-corrections
def test_a_withdrawal_drops_the_words_before_it_and_notes_them() -> None:
    r = _read("Keep off the grass -- no wait, the grass is fine; avoid the sand.")
    w = {p.entity: p.weight for p in r.preferences}
    assert w["grass"] == lx.FINE and w["sand"] > lx.FINE
    assert any("'Keep off the grass' read as withdrawn ('no wait')" in n for n in r.notes)
    assert not r.unparsed


def test_a_withdrawal_opening_a_sentence_withdraws_the_one_before_and_keeps_its_names() -> None:
    # "them" after the marker is the forest the withdrawn sentence named
    assert "forest" not in _lethal("Never enter the forest. On second thought: just stay away from them.")
    assert _weights("Never enter the forest. On second thought: just stay away from them.")["forest"] > lx.FINE


def test_a_replacement_puts_its_name_in_place_of_the_withdrawn_one() -> None:
    w = _weights("Use the sand -- sorry, I mean the trail.")
    assert w["trail"] < lx.FINE and w.get("sand", lx.FINE) == lx.FINE
    # a cleft names the replacement: the withdrawn verb goes to it
    w = _weights("Prefer the grass -- wait no, the grass is fine, it's the road I meant.")
    assert w["road"] < lx.FINE and w["grass"] == lx.FINE


def test_emphasis_is_no_correction() -> None:
    assert "quarry" in _lethal("Stay out of the quarry, I mean it.")
    assert [(len(p.toks), p.withdrawn_by) for p in corrected(sentences(tokenize("Avoid the pond, I mean it.")))] == [
        (7, None)
    ]


# -- indifference and caution
@pytest.mark.parametrize(
    "prompt, entity",
    [
        ("I don't mind the railway.", "railway"),
        ("We're not too fussed about the trees.", "tree"),
        ("The buildings don't matter today, we fly above them.", "building"),
        ("Honestly the hedges won't hurt you.", "hedge"),
        ("Not that we care much about the water.", "water"),
        ("The fences are irrelevant.", "fence"),
    ],
)
def test_indifference_is_no_preference(prompt: str, entity: str) -> None:
    assert _weights(prompt)[entity] == lx.FINE


def test_caution_avoids_and_never_mind_permits() -> None:
    assert _weights("Prefer the trail and mind the ditch.")["ditch"] > lx.FINE
    assert _weights("Be careful around the sand.")["sand"] > lx.FINE
    assert _weights("Never mind the sand, take the road.")["sand"] == lx.FINE


# -- availability conditionals and their alternatives
def test_if_there_is_x_take_it_prefers_x_and_if_not_is_the_fallback() -> None:
    w = _weights("If there's a trail, use it. If there isn't, take the grass rather than the sand.")
    assert w["trail"] < w["grass"] < lx.FINE
    assert not _read("If there's a trail, use it. If there isn't, take the grass.").unparsed


def test_if_x_goes_our_way_and_if_neither_works_rank_the_fallbacks() -> None:
    w = _weights("If the road heads our way, follow it; otherwise the trail; only if neither works, the grass.")
    assert w["road"] < w["trail"] < w["grass"]
    assert "only when there is no other way" not in lx.IDIOMS  # a last resort, never availability
    assert _weights("gravel road only when there is no other way")["unpaved road"] == lx.LAST_RESORT


# -- texting
def test_texted_words_are_read() -> None:
    assert lx.read_texting("nvr") == "never" and lx.read_texting("pvd") == "paved"
    assert lx.read_texting("unpavd") == "unpaved" and lx.read_texting("wtr") == "water"
    assert lx.read_texting("grass") is None and lx.read_texting("xyz") is None
    assert "water" in _lethal("nvr go in2 the wtr")
    w = _weights("stick to the pvd rd, avoid the unpavd one")
    assert w["paved road"] < lx.FINE < w["unpaved road"]


# -- distances
@pytest.mark.parametrize(
    "prompt, metres",
    [
        ("Stay away from the pond, the nearer the worse, but past about 25 metres I don't care.", 25.0),
        ("Keep clear of the pond, the closer the worse; after 8 m it is all the same.", 8.0),
        ("Do not go too near the pond -- the closer, the worse -- from 12 metres on it is all the same.", 12.0),
    ],
)
def test_an_indifferent_reach_ends_the_fall_off(prompt: str, metres: float) -> None:
    assert _far(prompt) == {"pond": metres}


def test_amounts_in_words_and_a_gap_between_are_distances() -> None:
    assert _far("keep half a dozen metres from the hedge") == {"hedge": 6.0}
    assert _far("keep a couple of metres from the hedge") == {"hedge": 2.0}
    assert _far("leave 10 m between the rover and the hedge") == {"hedge": 10.0}


# -- labels and headings
def test_an_unknown_topic_before_a_colon_takes_its_verdict() -> None:
    assert "minefield" in _lethal("Minefield: never enter.")
    assert _weights("Axis of advance: the ridge. Quarry: no go.")["ridge"] < lx.FINE
    assert "quarry" in _lethal("Axis of advance: the ridge. Quarry: no go.")


def test_the_material_after_the_road_qualifies_it() -> None:
    w = _weights("The road of dirt is forbidden; it goes only by the road of asphalt.")
    assert w["paved road"] < lx.FINE and "unpaved road" in _lethal("The road of dirt is forbidden.")


# -- tables, relative costs, requests and firsts
def test_a_two_column_table_reads_row_by_row_and_relative_costs_rank() -> None:
    table = "terrain | cost\n--- | ---\nroad | 1\nsand | 3\ngrass | 2\nquarry | never"
    assert len(normalise(table)) == len(table)
    w = _weights(table)
    assert w["road"] < w["grass"] < w["sand"] < lx.FINE
    assert "quarry" in _lethal(table)
    assert _weights("road: 3").get("road", lx.FINE) == lx.FINE  # a lone relative cost says nothing
    assert _weights("tree: 0.9, road: 0.2")["tree"] == 0.9  # the 0-1 scale is unchanged


def test_please_after_a_name_asks_for_it_and_stays_politeness_elsewhere() -> None:
    assert _weights("the trail please, and avoid the sand")["trail"] < lx.FINE
    assert _weights("avoid the sand please")["sand"] > lx.FINE


def test_a_first_named_after_its_list_ranks_it_first() -> None:
    w = _weights("keep to the trail and the road, road first")
    assert w["road"] < w["trail"] < lx.FINE
    w = _weights("road first, then the trail")
    assert w["road"] < w["trail"]


def test_emphasis_fronting_and_liking() -> None:
    assert "pond" in _lethal("But the pond, absolutely cannot go in -- this is the red line.")
    assert not _read("Never enter the pond, that's my bottom line.").unparsed
    assert _weights("Over the trail it likes to drive.")["trail"] < lx.FINE


def test_a_pronoun_after_a_near_cue_stands_for_its_object() -> None:
    r = _read("Hug the hedges for cover, right up against the sheds, but never go inside one.")
    assert "shed" in {p.entity for p in r.preferences if p.lethal}
    assert ("near", "shed") in {(c.kind, c.entity) for c in r.cues} and not r.unparsed


# -- set 22's constructs
def test_marks_are_verdicts_and_a_lone_tilde_is_so_so() -> None:
    w = _weights("rly ✗ | rd ✓ | veg ~")
    assert w["road"] < lx.FINE == w["vegetation"] < w["railway"]
    assert _far("keep ~10 m from the sand") == {"sand": 10.0}


def test_field_shorthand_for_a_minimum_clearance() -> None:
    r = _read("H2O: 20m min clr, hard.")
    assert [(c.kind, c.entity, c.metres, c.hard) for c in r.cues] == [("far", "water", 20.0, True)]


def test_a_reach_said_as_nothing_extra_past() -> None:
    assert _far("Cost should fall off with distance from the sand: heavy next to it, nothing extra past 12 m.") == {
        "sand": 12.0
    }


@pytest.mark.parametrize(
    "prompt, entity, band",
    [
        ("Skip the sand, the trail is fine.", "sand", "avoided"),
        ("The grass is fair game.", "grass", "neutral"),
        ("The drone may overfly the hedges.", "hedge", "neutral"),
        ("Nobody goes into the pond.", "pond", "lethal"),
        ("Just keep it out of the orchard.", "orchard", "lethal"),
        ("Keep the rover mostly on the trail.", "trail", "preferred"),
    ],
)
def test_verbs_of_skipping_permission_and_keeping(prompt: str, entity: str, band: str) -> None:
    p = next(p for p in _read(prompt).preferences if p.entity == entity)
    got = (
        "lethal" if p.lethal else "preferred" if p.weight < lx.FINE else "neutral" if p.weight == lx.FINE else "avoided"
    )
    assert got == band


def test_a_time_said_with_last_is_no_sequence() -> None:
    w = _weights("Crossing the railway is allowed, the line was decommissioned last year.")
    assert w["railway"] == lx.FINE and "year" not in w


def test_as_wide_a_berth_as_you_can_and_a_gap_between_with_an_estimate() -> None:
    r = _read("Please give the hedges as wide a berth as you can.")
    assert [(c.kind, c.entity) for c in r.cues] == [("far", "hedge")] and not r.unparsed
    assert _far("leave about 10 m between yourself and the hedge") == {"hedge": 10.0}


def test_multiples_are_relative_costs() -> None:
    w = _weights("grass costs 2x road. sand 5x.")
    assert w["road"] < w["grass"] < w["sand"] < lx.FINE


def test_a_revocation_takes_back_only_the_rules_on_its_entity() -> None:
    r = _read(
        "Keep 5 m off the trail and stay out of the pond. Actually, forget the trail rule, we need the trail after all."
    )
    assert not [c for c in r.cues if c.entity == "trail"] and not r.unparsed
    assert "pond" in {p.entity for p in r.preferences if p.lethal}
    assert any("rules on trail" in n for n in r.notes)


def test_a_topic_with_a_pronoun_cue_after_its_colon_and_a_bare_topic_at_the_end() -> None:
    r = _read("🚜 route notes:\n• 🌊 pond: give it ~15 m if it's easy\n• 🛣️ road: fine")
    assert _far("pond: give it ~15 m if it's easy") == {"pond": 15.0}
    assert not r.unparsed or r.unparsed == ("route notes",)
    assert _weights("road: fine. grass:")["road"] == lx.FINE  # a mark at a sentence's end reads nothing
