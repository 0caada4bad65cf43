"""Merging an interpreter's reading with the defaults: order, ranks, hierarchy and cue cleaning."""

from __future__ import annotations

import pytest

from overseec_core.costlang import check_program
from overseec_core.interpret.merge import NEUTRAL, clean_cues, clean_hierarchy, cost_levels, finalize, make_entity
from overseec_core.schema import DEFAULT_ENTITIES, Cue, Entity


def test_cost_levels_ranks_include_neutral_and_lethal_last():
    levels, ranks = cost_levels(
        {"a": (0.1, False), "b": (0.1, False), "c": (0.5, False), "d": (1.0, True), "e": (1.0, False)}
    )
    assert ranks == {"a": 1, "b": 1, "c": 2, "e": 3, "d": 4}
    assert levels == {"a": 0.0, "b": 0.0, "c": 0.5, "e": 1.0, "d": 1.0}


def test_cost_levels_spread_preferred_evenly_and_keep_avoided_on_the_absolute_scale():
    levels, ranks = cost_levels(
        {"p1": (0.1, False), "p2": (0.2, False), "p3": (0.3, False), "t": (0.6, False), "a": (0.85, False)}
    )
    assert levels == {
        "p1": 0.0,
        "p2": pytest.approx(1 / 6, abs=1e-6),
        "p3": pytest.approx(1 / 3, abs=1e-6),
        "t": 0.6,  # a last resort
        "a": 0.85,  # avoid: between trees' prior (0.75) and buildings' (1.0)
    }
    assert ranks == {"p1": 1, "p2": 2, "p3": 3, "t": 5, "a": 6}  # rank 4 is neutral ground


def test_cost_levels_neutral_rank_exists_without_neutral_entities():
    levels, ranks = cost_levels({"road": (0.1, False), "water": (0.85, False)})
    assert (levels, ranks) == ({"road": 0.0, "water": 0.85}, {"road": 1, "water": 3})
    only_avoid, r = cost_levels({"water": (0.95, False)})
    assert only_avoid == {"water": 0.95} and r == {"water": 2}
    assert min(only_avoid.values()) > NEUTRAL


def test_clean_hierarchy():
    names = {"a", "b", "c", "d"}
    pairs, notes = clean_hierarchy(
        [("a", "b"), ("b", "c"), ("c", "a"), ("a", "d"), ("a", "b"), ("x", "b"), ("d", "d")],
        names,
        quiet=[("d", "a"), ("c", "d")],
    )
    assert pairs == (("a", "b"), ("b", "c"), ("d", "a"))
    text = " | ".join(notes)
    assert "('c' inside 'a') would make a cycle" in text
    assert "'a' already lies inside 'b'; dropped the second parent 'd'" in text
    assert "names an unknown entity" in text and "('d' inside 'd')" in text
    assert len(notes) == 4  # the quiet (table) pair that conflicts says nothing


def test_clean_cues():
    cues, notes = clean_cues(
        [
            Cue("centre", "a"),
            Cue("centre", "a"),
            Cue("zigzag", "a"),
            Cue("near", "zz", 5.0),
            Cue("if_near", "a", 5.0, "b"),
        ],
        {"a", "b"},
    )
    assert cues == (Cue("centre", "a"), Cue("if_near", "a", 5.0, "b"))
    assert len(notes) == 2


def test_finalize_defaults_first_priors_and_program():
    it = finalize(
        "p",
        mentioned=[make_entity("lava"), Entity("road", "areal", ("asphalt",))],
        stated={"lava": (0.3, True), "grass": (1.7, False)},
        cues=[Cue("far", "lava", 5.0)],
    )
    assert [e.name for e in it.entities] == [n for n, _ in DEFAULT_ENTITIES] + ["lava"]
    road = it.entities[0]
    assert road.geometry == "linear" and road.prompts == ("asphalt",)  # default geometry kept
    assert any("kept linear" in n for n in it.notes)
    w = {p.entity: (p.weight, p.lethal) for p in it.preferences}
    assert w["lava"] == (1.0, True) and w["grass"] == (1.0, False)  # lethal -> 1.0; clipped
    assert w["road"] == (NEUTRAL, False)  # unmentioned: no invented preference
    assert all(p.phrase == "" for p in it.preferences)
    assert it.cues == (Cue("far", "lava", 5.0),)
    check_program(it.program, [e.name for e in it.entities])


def test_table_hierarchy_is_added():
    it = finalize("p", mentioned=[make_entity("pond"), make_entity("parking lot")], stated={})
    assert set(it.hierarchy) == {("pond", "water"), ("parking lot", "road")}
