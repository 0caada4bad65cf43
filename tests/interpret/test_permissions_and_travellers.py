"""Set 28's other constructs (issue 31), each on phrasings of its own: what the travellers like,
bear and hate; permissions (a safe
state, a need denied, a permission denied by contrast), the traveller between a keeping verb
and its distance, absoluteness said as "the whole way", a word typed on to a name that is a word
of its own ("cabinet" is no "cabin"), a dwelling as a house.
"""

from __future__ import annotations

import pytest

from overseec_core.interpret.offline import interpret_offline


def _read(prompt: str):
    return interpret_offline(prompt)


def _stated(prompt: str) -> dict[str, tuple[float, bool]]:
    return {p.entity: (p.weight, p.lethal) for p in _read(prompt).preferences if not p.prior}


def _cues(prompt: str, kind: str) -> dict[str, tuple[float | None, bool]]:
    return {c.entity: (c.metres, c.hard) for c in _read(prompt).cues if c.kind == kind}


# -- permissions
@pytest.mark.parametrize(
    ("prompt", "entity"),
    [
        ("The barns are empty this week.", "barn"),
        ("no call to go round the fences", "fence"),
        ("There is no restriction on crossing the road.", "road"),
    ],
)
def test_a_safe_state_or_a_denied_need_is_a_permission(prompt, entity):
    stated = _stated(prompt)
    assert stated[entity] == (0.5, False)
    assert not any(c.kind == "no_cross" for c in _read(prompt).cues)


@pytest.mark.parametrize(
    "prompt",
    [
        "You can cross the grass but not through the wetland.",
        "Vehicles are permitted on the trail. But not on the railway.",
    ],
)
def test_a_permission_denied_by_contrast_forbids_the_place(prompt):
    stated = _stated(prompt)
    forbidden = "wetland" if "wetland" in prompt else "railway"
    assert stated[forbidden][1]
    assert not any(c.kind == "unless_near" for c in _read(prompt).cues)


def test_a_contrast_without_a_permission_only_avoids():
    stated = _stated("prefer grass but not on the road")
    assert not stated["road"][1] and stated["road"][0] > 0.5


# -- travellers, absoluteness, words
@pytest.mark.parametrize("traveller", ["rig", "mower", "agv"])
def test_the_traveller_between_keep_and_a_distance_is_no_entity(traveller):
    far = _cues(f"keep the {traveller} 12 m off the railway", "far")
    assert far == {"railway": (12.0, False)}


@pytest.mark.parametrize("wording", ["at every point", "every metre of the route", "all the way"])
def test_a_rule_that_holds_the_whole_way_is_hard(wording):
    assert _cues(f"stay 8 m from the water {wording}", "far") == {"water": (8.0, True)}
    assert not _read(f"stay 8 m from the water {wording}").unparsed


def test_a_word_typed_on_to_a_name_is_a_word_of_its_own():
    assert set(_cues("stay within 20 m of the cabinet", "near")) == {"cabinet"}


def test_a_dwelling_is_a_house():
    assert set(_cues("keep 4 m from every dwelling", "far")) == {"house"}


# -- what the travellers like, bear and hate
def test_likes_and_hates_rank_the_ground():
    prompt = "The ponies adore the bridleway, they can live with grass, but they detest the road."
    stated = _stated(prompt)
    assert stated["trail"][0] < stated["grass"][0] < stated["road"][0]
    assert not _read(prompt).unparsed


def test_a_traveller_that_cannot_stand_a_surface_avoids_it():
    stated = _stated("my mare cannot abide the tarmac")
    assert stated["paved road"][0] > 0.5 and not stated["paved road"][1]


def test_love_of_a_wish_is_no_preference_for_what_it_names():
    preferred = {p.entity for p in _read("I'd love it if you stayed off the road").preferences if p.weight < 0.5}
    assert "road" not in preferred


# -- nearness said plainly
@pytest.mark.parametrize(
    ("prompt", "kind", "entity"),
    [
        ("Closer to the trail means better.", "near", "trail"),
        ("nearer the railway is worse", "far", "railway"),
        ("Further from the water is best.", "far", "water"),
    ],
)
def test_a_plain_comparative_with_its_object_after_it_is_graded(prompt, kind, entity):
    assert set(_cues(prompt, kind)) == {entity}
    assert not _read(prompt).unparsed


@pytest.mark.parametrize("verb", ["stay", "keep", "remain"])
def test_staying_by_a_thing_is_nearness(verb):
    assert set(_cues(f"{verb} by the fence", "near")) == {"fence"}


def test_a_sticking_verb_still_prefers():
    assert _stated("The quad sticks to the trail.")["trail"][0] < 0.5


# -- a ranking's closing qualifier, slips of "off"
def _weights(prompt: str) -> dict[str, float]:
    return {p.entity: p.weight for p in _read(prompt).preferences}


def test_a_long_rankings_closing_qualifier_keeps_the_order():
    w = _weights("trail > road > grass > water only if boxed in")
    assert w["trail"] < w["road"] < w["grass"] < w["water"]
    assert not _read("trail > road > grass > water only if boxed in").unparsed


def test_a_short_rankings_closing_qualifier_is_its_last_items():
    w = _weights("trail > grass as a last resort")
    assert w["trail"] < w["grass"] and w["grass"] > 0.5
    assert w["trail"] <= 0.5


def test_use_only_when_nothing_else_connects_is_a_last_resort():
    assert 0.5 < _weights("only use the trail if nothing else connects")["trail"] < 1.0


def test_keep_of_is_a_slip_for_keep_off():
    assert _stated("pls keep of the grass")["grass"][0] > 0.5


def test_a_word_two_letters_short_of_a_phrase_word_is_no_slip_for_it():
    # "corner" is no slip for "cornered" (a qualifier of use): a corner cut over the grass is no ban
    stated = _stated("keep near the hedge; where you cut a corner over the grass, fine")
    assert not stated.get("grass", (0.5, False))[1] and "cornered" not in str(_read("cut a corner").unparsed)
    assert "corner" in {p.entity for p in _read("you may cut a corner over the grass").preferences}


@pytest.mark.parametrize("wording", ["never lose sight of", "don't lose track of", "without losing touch with"])
def test_contact_a_route_must_not_lose_is_nearness(wording):
    prompt = f"{wording} the fence"
    assert set(_cues(prompt, "near")) == {"fence"}
    assert not any(p.lethal or p.weight > 0.5 for p in _read(prompt).preferences if not p.prior)
