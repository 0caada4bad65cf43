"""Prompt entities matched to layer names: each rule, its order, and what is never matched."""

from __future__ import annotations

import pytest

from overseec_core.interpret.matching import layer_names, match_entity, parse_alias

BAKER_LAKE = ["building", "road", "water (Hydro)", "vegetation", "railway (Train)"]
VEGAS = ["paved road (buffered centerline)", "unpaved road (buffered centerline)"]


@pytest.mark.parametrize(
    "entity, layers, expected, rule",
    [
        ("Roads", BAKER_LAKE, ("road",), "name"),
        ("hydro", BAKER_LAKE, ("water (Hydro)",), "name"),
        ("buildings", BAKER_LAKE, ("building",), "name"),
        ("tracks", BAKER_LAKE, ("railway (Train)",), "synonym"),
        ("railroad", BAKER_LAKE, ("railway (Train)",), "synonym"),
        ("paved road", BAKER_LAKE, ("road",), "modifier"),  # an entity of its own inside road (issue 31)
        ("dirt road", BAKER_LAKE, ("road",), "modifier"),
        ("road", VEGAS, tuple(VEGAS), "synonym"),
        ("paved road", VEGAS, (VEGAS[0],), "name"),
        ("tree", ["tree crown (bounding box)"], ("tree crown (bounding box)",), "synonym"),
        ("woods", ["tree crown (bounding box)"], ("tree crown (bounding box)",), "synonym"),
        ("house", ["building"], ("building",), "synonym"),
        ("lake", BAKER_LAKE, ("water (Hydro)",), "broader"),
        ("river", BAKER_LAKE, ("water (Hydro)",), "broader"),
        ("grass", BAKER_LAKE, ("vegetation",), "broader"),
        ("tree crown", BAKER_LAKE, ("vegetation",), "broader"),
        ("baseball field", ["grass", "road"], ("grass",), "broader"),
    ],
)
def test_rules(entity, layers, expected, rule):
    m = match_entity(entity, layers)
    assert (m.layers, m.rule) == (expected, rule)


@pytest.mark.parametrize(
    "entity, layers",
    [
        ("building", VEGAS),
        ("road", ["building"]),
        ("electric tower", BAKER_LAKE),
        ("country", BAKER_LAKE),
        ("trail", BAKER_LAKE),
        ("road", ["non-road"]),
        ("water", ["land (non-water)", "forest"]),
    ],
)
def test_unmatched(entity, layers):
    """Nothing is forced onto an unrelated layer (and synonym loops terminate)."""
    m = match_entity(entity, layers)
    assert m.layers == () and m.rule == "unmatched" and "unmatched" in m.describe()


def test_an_exact_name_beats_a_broader_class_and_aliases_beat_everything():
    assert match_entity("grass", ["grass", "vegetation"]).layers == ("grass",)
    assert match_entity("lake", BAKER_LAKE, {"lake": "building"}).layers == ("building",)
    # an alias to a layer that is not there falls through to the rules
    assert match_entity("lake", BAKER_LAKE, {"lake": "pond"}).rule == "broader"


def test_layer_names_split_labels():
    assert layer_names("water (Hydro)") == {"water", "hydro"}
    assert layer_names("background/unlabeled") == {"background", "unlabeled"}


def test_parse_alias():
    assert parse_alias(" Lake = Water ") == ("lake", "water")
    with pytest.raises(ValueError, match="ENTITY=LAYER"):
        parse_alias("lake")
