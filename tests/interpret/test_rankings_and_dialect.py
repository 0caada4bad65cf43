"""Set 28's last constructs (issue 31), on phrasings of their own: a ranking written with arrows,
a bare name "wherever possible", a comparative contracted with "than" ("better'n"), "X will do".
"""

from __future__ import annotations

import pytest

from overseec_core.interpret.offline import interpret_offline


def _weights(prompt: str) -> dict[str, float]:
    return {p.entity: p.weight for p in interpret_offline(prompt).preferences if not p.prior}


@pytest.mark.parametrize("arrow", ["\u2192", "->", "=>"])
def test_three_items_joined_by_arrows_are_a_ranking(arrow):
    prompt = f"trail {arrow} grass {arrow} road (only as a last resort)"
    w = _weights(prompt)
    assert w["trail"] < w["grass"] < w["road"]
    assert not interpret_offline(prompt).unparsed


def test_one_arrow_stays_a_colon():
    assert _weights("water -> avoid")["water"] > 0.5


@pytest.mark.parametrize("wording", ["wherever possible", "as much as you can", "whenever you can"])
def test_a_bare_name_used_wherever_possible_is_preferred(wording):
    assert _weights(f"The towpath {wording}.")["towpath"] < 0.5


def test_a_strong_modifier_on_an_avoid_stays_an_avoid():
    assert _weights("avoid the grass wherever possible")["grass"] > 0.5


def test_a_comparative_contracted_with_than():
    w = _weights("Tarmac's better'n dirt.")
    assert w["paved road"] < w["bare soil"]
    assert not interpret_offline("Tarmac's better'n dirt.").unparsed


def test_a_name_that_will_do_is_used_grudgingly():
    w = _weights("The trail's best; the grass will do.")
    assert w["trail"] < 0.5 < w["grass"] < 0.7
