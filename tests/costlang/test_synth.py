"""Programs synthesised from preferences: the paper's accumulation, hierarchy, lethal, cues."""

from __future__ import annotations

import re

import numpy as np
import pytest

from overseec_core.costlang import (
    LANGUAGE_FILE,
    OPERATORS,
    check_program,
    evaluate_program,
    operator_reference,
    program_from_interpretation,
)
from overseec_core.costlang.scale import check_scale
from overseec_core.costlang.synth import FAR_EDGE_LEVEL, FAR_LEVEL, NEAR_EDGE_LEVEL, NEAR_LEVEL
from overseec_core.errors import InterpretError
from overseec_core.schema import Cue, Entity, Preference

ENTITIES = [
    Entity("road", "linear"),
    Entity("trail", "linear"),
    Entity("grass"),
    Entity("baseball field"),
    Entity("building"),
    Entity("water"),
    Entity("electric tower"),
]
NAMES = [e.name for e in ENTITIES]


def costs(text: str, masks: dict, probs: dict | None = None, sampling=(1.0, 1.0)):
    program = check_program(text, NAMES)
    assert program.warnings == ()
    return evaluate_program(program, masks, probs, sampling=sampling)


def layers(shape, **regions) -> dict:
    out = {n: np.zeros(shape, bool) for n in NAMES}
    for name, sl in regions.items():
        out[name.replace("_", " ")][sl] = True
    return out


def test_paper_prompt_road_trail_grass_baseball_field():
    """'Prefer the roads and trails, grass should be fine, try to avoid the baseball field'."""
    prefs = [
        Preference("road", 1, 0.0),
        Preference("trail", 1, 0.0),
        Preference("grass", 2, 0.5),
        Preference("baseball field", 3, 1.0),
    ]
    text = program_from_interpretation(ENTITIES, prefs, [("baseball field", "grass")])
    shape = (4, 10)
    masks = layers(shape, road=np.s_[0, :], trail=np.s_[1, :5], grass=np.s_[2:, :], baseball_field=np.s_[3, 5:])
    probs = {n: np.full(shape, 0.9) for n in NAMES}
    r = costs(text, masks, probs)
    assert r.cost[0, 0] == pytest.approx(0.05)  # road: 0.5 + (0 - 0.5) * P
    assert r.cost[1, 0] == pytest.approx(0.05)  # trail
    assert r.cost[1, 7] == 0.5  # nothing: neutral ground
    assert r.cost[2, 0] == 0.5  # grass is fine: neutral too
    assert r.cost[3, 7] == pytest.approx(0.95)  # the field: 0.5 + (1 - 0.5) * P
    assert not r.lethal.any()


def test_hierarchy_removes_the_child_from_a_parent_with_a_preference():
    prefs = [Preference("grass", 1, 0.25), Preference("baseball field", 3, 1.0)]
    text = program_from_interpretation(ENTITIES, prefs, [("baseball field", "grass")])
    assert 'REMOVE(M["grass"], M["baseball field"])' in text
    masks = layers((2, 4), grass=np.s_[:, :], baseball_field=np.s_[1, 2:])
    r = costs(text, masks)
    assert r.cost[0, 0] == 0.25 and r.cost[1, 3] == 1.0  # the field's own level only


def test_weak_detections_stay_on_their_side_of_neutral():
    """An avoided entity found with low confidence is never cheaper than open ground."""
    prefs = [Preference("road", 1, 0.0), Preference("building", 3, 1.0)]
    text = program_from_interpretation(ENTITIES, prefs)
    masks = layers((1, 2), road=np.s_[0, 0], building=np.s_[0, 1])
    r = costs(text, masks, {"road": np.full((1, 2), 0.3), "building": np.full((1, 2), 0.3)})
    assert r.cost[0, 0] < 0.5 < r.cost[0, 1]


def test_lethal_entities_cost_one_and_are_flagged():
    """'avoid the electric tower' (lethal) vs 'you can go under the electric tower'."""
    shape = (3, 3)
    masks = layers(shape, grass=np.s_[:, :], electric_tower=np.s_[1, 1])
    avoid = program_from_interpretation(
        ENTITIES, [Preference("grass", 1, 0.25), Preference("electric tower", 3, 1.0, lethal=True)]
    )
    under = program_from_interpretation(ENTITIES, [Preference("grass", 1, 0.25), Preference("electric tower", 2, 0.5)])
    a, u = costs(avoid, masks), costs(under, masks)
    assert a.lethal[1, 1] and a.lethal.sum() == 1 and a.cost[1, 1] == 1.0
    assert not u.lethal.any()
    # under a neutral tower the grass' preference still holds
    assert u.cost[1, 1] == pytest.approx(0.25) and u.cost[0, 0] == pytest.approx(0.25)


def test_centre_and_side_of_the_road_order_the_road_pixels_oppositely():
    shape = (11, 12)
    masks = layers(shape, road=np.s_[3:8, :], grass=np.s_[:3, :])
    masks["grass"][8:] = True
    prefs = [Preference("road", 1, 0.0), Preference("grass", 2, 0.5)]
    centre = costs(program_from_interpretation(ENTITIES, prefs, cues=[Cue("centre", "road", 10.0)]), masks).cost[:, 6]
    side = costs(program_from_interpretation(ENTITIES, prefs, cues=[Cue("side", "road")]), masks).cost[:, 6]
    assert centre[5] < centre[4] < centre[3]  # centre line cheapest
    assert side[3] < side[4] < side[5]  # borders cheapest
    # the whole road still beats the grass
    assert centre[3:8].max() < 0.5 and side[3:8].max() < 0.5
    assert centre[0] == side[0] == 0.5


def test_keep_ten_metres_from_buildings_is_a_zone_above_neutral():
    shape = (5, 40)
    masks = layers(shape, grass=np.s_[:, :], building=np.s_[:, :2])
    text = program_from_interpretation(
        ENTITIES, [Preference("grass", 1, 0.0), Preference("building", 3, 0.95)], cues=[Cue("far", "building", 10.0)]
    )
    r = costs(text, masks, sampling=(1.0, 1.0))
    # graded (issue 31): FAR_LEVEL beside the buildings, falling linearly to FAR_EDGE_LEVEL at 10 m
    d = np.arange(2, 12) - 1.0  # metres from column 1
    want = FAR_LEVEL - (FAR_LEVEL - FAR_EDGE_LEVEL) * d / 10.0
    assert np.allclose(r.cost[0, 2:12], want)
    assert np.all(np.diff(r.cost[0, 2:12]) < 0)  # the closer, the dearer
    assert np.all(r.cost[:, 2:12] > 0.5)  # all of the zone is above neutral
    assert np.allclose(r.cost[:, 12:], 0.0)
    assert not r.lethal.any() and not r.keep_out.any()  # a zone to avoid, not a rule


def test_an_entity_at_the_top_of_the_scale_is_an_obstacle():
    """Level 1.0 (passable) is an obstacle: its mask, less its sub-entities with levels of their
    own, joins keep_out; 0.95 is merely avoided."""
    shape, names = (4, 30), ["water", "river", "building"]
    masks = {n: np.zeros(shape, bool) for n in names}
    masks["water"][:, :10], masks["river"][:, 4:6], masks["building"][:, 20:] = True, True, True
    prefs = [
        Preference("water", 3, 1.0, prior=True),
        Preference("river", 2, 0.5, phrase="you can wade the river"),
        Preference("building", 2, 0.95),
    ]
    hierarchy = [("river", "water")]
    text = program_from_interpretation(names, prefs, hierarchy)
    program = check_program(text, names)
    r = evaluate_program(program, masks, None, sampling=(1.0, 1.0))
    assert r.keep_out[:, :4].all() and r.keep_out[:, 6:10].all()  # the water, not the river
    assert not r.keep_out[:, 4:6].any() and not r.keep_out[:, 10:].any()
    assert np.allclose(r.cost[:, :4], 1.0) and np.allclose(r.cost[:, 20:], 0.95) and not r.lethal.any()
    check_scale(program, prefs, hierarchy)


def test_at_least_ten_metres_is_a_keep_out_rule():
    shape = (5, 40)
    masks = layers(shape, grass=np.s_[:, :], building=np.s_[:, :2])
    text = program_from_interpretation(
        ENTITIES, [Preference("grass", 1, 0.0)], cues=[Cue("far", "building", 10.0, hard=True)]
    )
    r = costs(text, masks)
    assert r.keep_out[:, :12].all() and not r.keep_out[:, 12:].any()
    assert not r.lethal.any()


def test_far_from_a_lethal_entity_is_a_keep_out_zone():
    shape = (3, 20)
    masks = layers(shape, grass=np.s_[:, :], water=np.s_[:, :1])
    text = program_from_interpretation(
        ENTITIES,
        [Preference("grass", 1, 0.2), Preference("water", 2, 1.0, lethal=True)],
        cues=[Cue("far", "water", 3.0)],
    )
    r = costs(text, masks)
    assert r.lethal[:, 0].all() and not r.lethal[:, 1:].any()
    assert r.keep_out[:, 1:4].all() and not r.keep_out[:, 4:].any()


def test_near_cue_lowers_ground_near_the_entity_below_neutral():
    shape = (3, 20)
    masks = layers(shape, water=np.s_[:, :1], building=np.s_[:, 3])
    text = program_from_interpretation(
        ENTITIES, [Preference("water", 2, 0.5), Preference("building", 3, 1.0)], cues=[Cue("near", "water", 5.0)]
    )
    r = costs(text, masks)
    # graded (issue 31): NEAR_LEVEL beside the water, rising linearly to NEAR_EDGE_LEVEL at 5 m
    assert r.cost[0, 1] == pytest.approx(NEAR_LEVEL + (NEAR_EDGE_LEVEL - NEAR_LEVEL) * 1 / 5)
    assert r.cost[0, 5] == pytest.approx(NEAR_EDGE_LEVEL)  # neutral ground 5 m away
    assert r.cost[0, 1] < r.cost[0, 2] < r.cost[0, 4] < 0.5  # the nearer, the cheaper
    assert r.cost[0, 3] == 1.0  # an avoided building stays avoided
    assert r.cost[0, 6] == 0.5  # farther: neutral


def test_stay_within_is_a_keep_out_rule_beyond_the_distance():
    shape = (3, 20)
    masks = layers(shape, road=np.s_[:, :1])
    text = program_from_interpretation(ENTITIES, [], cues=[Cue("near", "road", 5.0, hard=True)])
    r = costs(text, masks)
    assert not r.keep_out[:, :6].any() and r.keep_out[:, 6:].all()


def test_unless_near_and_if_near_condition_a_preference():
    shape = (3, 30)
    masks = layers(shape, grass=np.s_[:, :], road=np.s_[:, :1])
    prefs = [Preference("road", 1, 0.0), Preference("grass", 3, 1.0, lethal=True)]
    unless = program_from_interpretation(ENTITIES, prefs, cues=[Cue("unless_near", "grass", 5.0, "road")])
    r = costs(unless, masks)
    # near the road (within 5 m) the objection is lifted: plain ground, not lethal
    assert not r.lethal[:, 1:6].any() and r.lethal[:, 6:].all()
    assert r.cost[0, 3] == pytest.approx(0.5)
    if_near = program_from_interpretation(
        ENTITIES, [Preference("road", 1, 0.0), Preference("grass", 3, 1.0)], cues=[Cue("if_near", "grass", 5.0, "road")]
    )
    r = costs(if_near, masks)
    # avoided only near the road; elsewhere plain ground (never the road's preferred level)
    assert r.cost[0, 3] == pytest.approx(1.0) and r.cost[0, 20] == pytest.approx(0.5)


def test_levels_outside_the_scale_are_refused_and_no_preference_is_neutral():
    masks = layers((2, 2), road=np.s_[0, :], grass=np.s_[1, :])
    with pytest.raises(InterpretError, match="cost levels in"):
        program_from_interpretation(ENTITIES, [Preference("grass", 2, 4.0)])
    assert np.all(costs(program_from_interpretation(ENTITIES, []), masks).cost == 0.5)


def test_transitive_hierarchy_removes_all_descendants_and_ignores_cycles():
    ents = ["water", "river", "ford"]
    prefs = [Preference("water", 2, 0.8), Preference("river", 3, 1.0), Preference("ford", 1, 0.1)]
    text = program_from_interpretation(ents, prefs, [("river", "water"), ("ford", "river"), ("water", "ford")])
    check_program(text, ents)
    assert re.search(r'REMOVE\(M\["water"\], OR\(M\["ford"\], M\["river"\]\)\)', text)


def test_synthesis_is_deterministic_and_checks():
    prefs = [Preference("road", 1, 0.0), Preference("grass", 2, 0.5)]
    cues = [Cue("centre", "road", 8.0), Cue("far", "building", 10.0)]
    a = program_from_interpretation(ENTITIES, prefs, [], cues)
    b = program_from_interpretation(list(ENTITIES), list(prefs), (), tuple(cues))
    assert a == b
    assert check_program(a, NAMES).reach_m == 10.0


def test_names_with_quotes_and_symbols_are_quoted_safely():
    ents = ['dirt "road"', "café/terrace"]
    text = program_from_interpretation(
        ents, [Preference(ents[0], 1, 0.1), Preference(ents[1], 2, 0.6)], [(ents[1], ents[0])]
    )
    assert set(check_program(text, ents).entities) == set(ents)


@pytest.mark.parametrize(
    "kwargs, fragment",
    [
        (dict(preferences=[Preference("lava", 1, 0.1)]), "'lava'"),
        (dict(preferences=[Preference("road", 1, -0.1)]), "weight"),
        (dict(preferences=[], cues=[Cue("beside", "road")]), "unknown cue kind"),
        (dict(preferences=[], cues=[Cue("near", "lava", 3.0)]), "'lava'"),
        (
            dict(preferences=[Preference("road", 1, 0.1)], cues=[Cue("unless_near", "road", 3.0)]),
            "needs the other entity",
        ),
    ],
)
def test_inconsistent_interpretations_are_refused(kwargs, fragment):
    with pytest.raises(InterpretError, match=re.escape(fragment)):
        program_from_interpretation(ENTITIES, **kwargs)


def test_operator_reference_describes_every_operator_and_its_example_checks():
    ref = operator_reference()
    for name in OPERATORS:
        assert f"`{name}(" in ref
    example = re.search(r"```python\n(.*?)```", ref, re.S).group(1)
    check_program(example, NAMES)


def test_language_md_examples_all_check():
    blocks = re.findall(r"```python\n(.*?)```", LANGUAGE_FILE.read_text(), re.S)
    assert len(blocks) >= 7
    for block in blocks:
        check_program(block, NAMES + ["tree"])


def test_if_near_any_of_several_others_and_unless_near_all():
    """An entity's preference that holds 'near the road' holds near either road layer."""
    shape = (3, 30)
    masks = layers(shape, grass=np.s_[:, :], road=np.s_[:, :1], trail=np.s_[:, 29:])
    prefs = [Preference("grass", 3, 1.0)]
    text = program_from_interpretation(
        ENTITIES, prefs, cues=[Cue("if_near", "grass", 3.0, "road"), Cue("if_near", "grass", 3.0, "trail")]
    )
    r = costs(text, masks)
    assert r.cost[0, 2] == 1.0 and r.cost[0, 27] == 1.0 and r.cost[0, 15] == 0.5
    text = program_from_interpretation(
        ENTITIES, prefs, cues=[Cue("unless_near", "grass", 3.0, "road"), Cue("unless_near", "grass", 3.0, "trail")]
    )
    r = costs(text, masks)
    assert r.cost[0, 2] == 0.5 and r.cost[0, 27] == 0.5 and r.cost[0, 15] == 1.0
