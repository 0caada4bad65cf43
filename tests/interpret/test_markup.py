"""Rules written as data (``interpret.markup``, ``interpret.config_lines``), set 28's (issue 31),
on phrasings of their own: XML elements and their attributes, JSON's quoted keys, CSV rows under a
header, tick-box tables, YAML mappings.
"""

from __future__ import annotations

import pytest

from overseec_core.interpret.markup import markup
from overseec_core.interpret.offline import interpret_offline


def _read(prompt: str):
    return interpret_offline(prompt)


def _stated(prompt: str) -> dict[str, tuple[float, bool]]:
    return {p.entity: (p.weight, p.lethal) for p in _read(prompt).preferences if not p.prior}


def _far(prompt: str) -> dict[str, tuple[float | None, bool]]:
    return {c.entity: (c.metres, c.hard) for c in _read(prompt).cues if c.kind == "far"}


# -- XML
def test_an_xml_element_reads_as_its_words_with_strictness():
    prompt = (
        "<mission>\n"
        "  <standoff target='building' distance_m='9' mandatory='yes'/>\n"
        "  <standoff target='water' distance_m='4' mandatory='no'/>\n"
        "</mission>"
    )
    assert _far(prompt) == {"building": (9.0, True), "water": (4.0, False)}
    assert not _read(prompt).unparsed


def test_xml_text_content_and_subject_attributes_read_as_verdicts():
    assert _stated('<prefer layer="trail"/><avoid layer="grass"/>')["trail"][0] < 0.5
    stated = _stated("<forbid>railway</forbid>\n<prefer>road</prefer>")
    assert stated["railway"][1] and stated["road"][0] < 0.5


def test_markup_keeps_every_word_where_it_was_written():
    text = '<keepout class="water" min_m="6"/>'
    out = markup(text)
    assert len(out) == len(text)
    assert out.index("water") == text.index("water") and out.index("keepout") == text.index("keepout")
    assert "<" not in out and ">" not in out and '"' not in out


def test_prose_with_angle_brackets_is_left_alone():
    assert markup("road > trail > grass") == "road > trail > grass"
    assert markup("keep < 5 m from the fence") == "keep < 5 m from the fence"


# -- JSON
def test_json_quoted_keys_and_a_strict_flag_read():
    prompt = '{"water": {"buffer_m": 11, "strict": false}, "trail": {"cost": "preferred"}}'
    assert _far(prompt) == {"water": (11.0, False)}
    assert _stated(prompt)["trail"][0] < 0.5
    assert not _read(prompt).unparsed


def test_a_strict_key_alone_on_its_line_stays_the_sections():
    prompt = "[buffer.building]\nmin_m = 3\nstrict = false\n"
    assert _far(prompt) == {"building": (3.0, False)}


# -- CSV
def test_csv_rows_read_under_their_header():
    prompt = "layer;buffer_ft;mode\nrailway;30;hard\ngrass;10;soft"
    far = _far(prompt)
    assert far["railway"][0] == pytest.approx(9.144) and far["railway"][1]
    assert far["grass"][0] == pytest.approx(3.048) and not far["grass"][1]
    assert not _read(prompt).unparsed


def test_a_csv_verdict_column_reads_as_the_verdict():
    stated = _stated("terrain,rule\ntrail,preferred\nwater,forbidden\ntree,avoid")
    assert stated["trail"][0] < 0.5 < stated["tree"][0] and stated["water"][1]


def test_a_comma_list_is_not_a_table():
    stated = _stated("prefer road, trail\navoid water, tree")
    assert stated["road"][0] < 0.5 < stated["water"][0]


# -- tick-box tables
def test_a_tick_box_table_reads_the_ticked_column():
    prompt = (
        "| terrain | preferred | fine | forbidden |\n"
        "|-----|-----|-----|-----|\n"
        "| trail | ✓ |  |  |\n"
        "| grass |  | ✓ |  |\n"
        "| building |  |  | ✓ |"
    )
    stated = _stated(prompt)
    assert stated["trail"][0] < stated["grass"][0] and stated["building"][1]
    assert not stated["grass"][1]


# -- YAML mappings
def test_a_yaml_mapping_names_the_entity_of_its_keys():
    prompt = "railway:\n  buffer_m: 8\n  strict: yes\ntrail:\n  rating: preferred\n"
    assert _far(prompt) == {"railway": (8.0, True)}
    assert _stated(prompt)["trail"][0] < 0.5
    assert not _read(prompt).unparsed


def test_a_yaml_key_that_names_a_rule_is_no_section():
    # "shore_follow" names the rule: read as a section, "follow ... stay on = false" would avoid the water
    prompt = "shore_follow:\n  reference_layer: water\n  stay_on_reference: false\n"
    assert _stated(prompt).get("water", (0.5, False))[0] <= 0.5
