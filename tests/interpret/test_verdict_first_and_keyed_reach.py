"""Graded constructs of issue 31, each on phrasings of its own: a correlative whose verdict comes
first ("worse the nearer it gets"), a configuration's fall-off keys ("falloff_m", "mode":
"graded"), "shy away from" and "steer clear of", and speed, which is no terrain.
"""

from __future__ import annotations

import pytest

from overseec_core.interpret.offline import interpret_offline


def _cues(prompt: str, kind: str) -> dict[str, float | None]:
    return {c.entity: c.metres for c in interpret_offline(prompt).cues if c.kind == kind}


@pytest.mark.parametrize(
    ("prompt", "kind", "entity"),
    [
        ("Avoid the pylon: worse the nearer it comes.", "far", "electric tower"),
        ("Keep off the pond, more careful the closer you get.", "far", "pond"),
        ("Cheaper the nearer to the trail.", "near", "trail"),
        ("It's better the further from the houses.", "far", "house"),
        ("Hug the road; less wary the closer it stays.", "near", "road"),
    ],
)
def test_a_correlative_whose_verdict_comes_first(prompt, kind, entity):
    read = interpret_offline(prompt)
    assert entity in _cues(prompt, kind)
    assert not read.unparsed


def test_a_verdict_first_correlative_keeps_the_reach_after_it():
    assert _cues("Avoid the pond, worse the nearer it goes; past 22 m it stops mattering.", "far") == {"pond": 22.0}


@pytest.mark.parametrize(
    ("prompt", "kind", "entity", "metres"),
    [
        ('{"avoid": {"pond": {"mode": "graded", "decay_m": 18}}}', "far", "pond", 18.0),
        ('{"prefer": {"trail": {"profile": "graded"}}}', "near", "trail", 40.0),
        ("avoid: railway\nshape = gradual\nfalloff_m = 12", "far", "railway", 12.0),
    ],
)
def test_a_configurations_fall_off_keys_grade_what_it_avoids_or_prefers(prompt, kind, entity, metres):
    read = interpret_offline(prompt)
    assert _cues(prompt, kind) == {entity: metres}
    assert not read.unparsed


def test_a_reach_alone_grades_a_preferred_thing_toward_it():
    assert _cues("Prefer the trail, dying away by 14 m.", "near") == {"trail": 14.0}


@pytest.mark.parametrize("verb", ["shy away from", "steer clear of", "steer well clear of"])
def test_shying_and_steering_away_keep_far(verb):
    prompt = f"The rover should {verb} the pond."
    assert "pond" in _cues(prompt, "far")
    assert not interpret_offline(prompt).unparsed


@pytest.mark.parametrize("prompt", ['{"prefer": ["trail"], "speed_limit": 9}', "Prefer the trail. Speed: 9 km/h max."])
def test_speed_is_no_terrain_and_its_rule_is_reported(prompt):
    read = interpret_offline(prompt)
    assert [p.entity for p in read.preferences if p.weight < 0.5] == ["trail"]
    assert all("speed" not in p.entity for p in read.preferences)
    assert any("speed" in u.lower() for u in read.unparsed)
