"""Programs held to the cost scale: probes catch what breaks it, with a located error."""

from __future__ import annotations

import pytest

from overseec_core.costlang import check_program
from overseec_core.costlang.scale import check_scale
from overseec_core.errors import CostProgramError
from overseec_core.interpret import interpret
from overseec_core.schema import Cue, Preference

NAMES = ["road", "grass", "baseball field", "water"]
PREFS = [
    Preference("road", 1, 0.0),
    Preference("grass", 2, 0.5),
    Preference("baseball field", 3, 0.95),
    Preference("water", 4, 1.0, lethal=True),
]
HIERARCHY = [("baseball field", "grass")]


def check(text: str, prefs=PREFS, hierarchy=HIERARCHY, cues=()) -> None:
    check_scale(check_program(text, NAMES), prefs, hierarchy, cues)


def test_a_program_on_the_scale_passes():
    check('acc = sum(-0.5 * P["road"], 0.5 * P["baseball field"])\ncost = clip(0.5 + acc, 0, 1)\nlethal = M["water"]\n')


@pytest.mark.parametrize(
    "text, message, line",
    [
        ('cost = where(M["road"], 0.1, 1.0)\nlethal = M["water"]\n', "no entity costs 1.00", 1),
        ('cost = 0.5 - 0.5 * M["road"] + 0.4 * M["baseball field"]\nlethal = M["water"]\n', None, None),
        (
            'x = 1\ncost = 0.5 + 0.4 * M["road"] + 0.4 * M["baseball field"]\nlethal = M["water"]\n',
            "gives 'road' a cost of 0.90, at or above neutral",
            2,
        ),
        (
            'cost = 0.5 - 0.5 * M["road"] - 0.2 * M["baseball field"]\nlethal = M["water"]\n',
            "gives 'baseball field' a cost of 0.30, at or below neutral",
            1,
        ),
        ('cost = 0.5 - 0.5 * M["road"] + 0.5 * M["baseball field"] + 0.5 * M["water"]\n', "leaves 'water' passable", 1),
    ],
)
def test_off_scale_programs_are_refused_where_the_entity_is_used(text, message, line):
    if message is None:
        check(text)
        return
    with pytest.raises(CostProgramError, match=message) as info:
        check(text)
    assert info.value.line == line


def test_an_obstacle_left_out_of_keep_out_is_refused_where_it_is_used():
    prefs = [Preference("road", 1, 0.0), Preference("water", 3, 1.0, prior=True)]
    text = 'cost = clip(0.5 - 0.5 * P["road"] + 0.5 * P["water"], 0, 1)\n'
    with pytest.raises(CostProgramError, match="leaves 'water' out of keep_out.*obstacle") as info:
        check(text, prefs, [])
    assert (info.value.line, info.value.col) == (1, text.index('P["water"]'))
    check(text + 'keep_out = M["water"]\n', prefs, [])


def test_a_child_is_probed_inside_its_parent():
    """The field lies inside the grass: a program that lets a preferred grass win there fails."""
    prefs = [Preference("grass", 1, 0.0), Preference("baseball field", 3, 0.95)]
    with pytest.raises(CostProgramError, match="baseball field"):
        check('cost = clip(0.5 - 0.5 * M["grass"] + 0.4 * M["baseball field"], 0, 1)\n', prefs)
    check(
        'g = REMOVE(M["grass"], M["baseball field"])\n'
        'cost = clip(0.5 - 0.5 * M["grass"] * g + 0.5 * M["baseball field"], 0, 1)\n',
        prefs,
    )


def test_conditional_preferences_are_not_probed():
    prefs = [Preference("road", 1, 0.0), Preference("grass", 3, 0.95)]
    # grass is avoided only near roads: alone on empty ground it is neutral, and that is fine
    text = 'cost = clip(where(near(M["road"], 5), 0.5 + 0.5 * M["grass"], 0.5) - 0.5 * M["road"], 0, 1)\n'
    check(text, prefs, (), [Cue("if_near", "grass", 5.0, "road")])


@pytest.mark.parametrize(
    "prompt",
    [
        "Prefer the roads and trails, grass should be fine, try to avoid the baseball field as much as possible",
        "stay on the centre of the road, never cross the railway, avoid the water unless near the bridge",
        "first the trails, then the roads, then the grass; the river is a last resort",
        "keep at least 20 m from buildings, stay within 50 m of the road, stay near the river",
    ],
)
def test_synthesised_programs_keep_the_scale(prompt):
    it = interpret(prompt, offline=True)
    check_scale(check_program(it.program, [e.name for e in it.entities]), it.preferences, it.hierarchy, it.cues)


def test_a_program_that_drops_a_stated_entity_or_a_rule_is_refused():
    with pytest.raises(CostProgramError, match="never reads 'water', which the mission forbids"):
        check('cost = clip(0.5 - 0.5 * M["road"] + 0.5 * M["baseball field"], 0, 1)\n')
    rule = [Cue("far", "road", 20.0, hard=True)]
    text = 'cost = clip(0.5 - 0.5 * M["road"] + 0.5 * M["baseball field"], 0, 1)\nlethal = M["water"]\n'
    with pytest.raises(CostProgramError, match="distance rule .* no keep_out"):
        check(text, cues=rule)
    check(text + 'keep_out = near(M["road"], 20)\n', cues=rule)
