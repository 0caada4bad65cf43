"""Set 29's graded constructs (issue 31), each on phrasings of its own: where a fall-off ends said
as indifference ("no concern beyond", "no issue at all", "not bothered once it's past", "fading to
no bother at all by"), a graded cue said per step of distance ("every metre closer counts against
it"), "the more risk" as a correlative's end, and a telegram's STOPs.
"""

from __future__ import annotations

import pytest

from overseec_core.interpret.offline import interpret_offline


def _read(prompt: str):
    return interpret_offline(prompt)


def _cues(prompt: str, kind: str) -> dict[str, float | None]:
    return {c.entity: c.metres for c in _read(prompt).cues if c.kind == kind}


@pytest.mark.parametrize(
    "reach",
    [
        "No worry past 18 metres.",
        "There is no problem at all beyond 18 m.",
        "Past 18 m there is no issue.",
        "It fades to no concern at all by 18 metres.",
        "We're not bothered once it's past 18 m.",
    ],
)
def test_indifference_past_a_distance_is_where_the_fall_off_ends(reach):
    prompt = f"The closer to the pylon the worse. {reach}"
    assert _cues(prompt, "far") == {"electric tower": 18.0}
    assert not _read(prompt).unparsed


@pytest.mark.parametrize(
    ("prompt", "kind", "entity"),
    [
        ("every yard nearer the river counts against it", "far", "river"),
        ("each step closer to the trail is better", "near", "trail"),
        ("Avoid the pond. Every metre closer is worse.", "far", "pond"),
    ],
)
def test_a_graded_cue_said_per_step_of_distance(prompt, kind, entity):
    assert set(_cues(prompt, kind)) == {entity}
    assert not _read(prompt).unparsed


def test_more_risk_ends_a_correlative():
    assert set(_cues("the nearer the cliff, the more danger", "far")) == {"cliff"}


def test_a_telegrams_stops_end_its_sentences():
    prompt = "PREFER TRAIL STOP AVOID WATER STOP"
    weights = {p.entity: p.weight for p in _read(prompt).preferences}
    assert weights["trail"] < 0.5 < weights["water"]
    assert not _read(prompt).unparsed
