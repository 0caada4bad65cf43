"""What ``fit_program`` hands an adapter when prompt entities match no layer: the facts (which
entities, which layers) beside the CLI's one-line message, so that the QGIS dock can point at its
own Entity aliases field without rewriting the CLI's text."""

from __future__ import annotations

import pytest

from overseec_core.errors import InputError
from overseec_core.interpret.matching import match_entities
from overseec_core.schema import Entity, Interpretation, Preference
from overseec_core.synthesize.fit import NoLayerMatched, fit_program, unmatched_entities

LAYERS = ("grass", "road", "water", "building")


def _interp(*prefs: Preference) -> Interpretation:
    return Interpretation(
        prompt="", entities=tuple(Entity(p.entity) for p in prefs), preferences=prefs, program="cost = 0.5\n"
    )


def test_nothing_matched_carries_the_entities_and_layers_with_the_clis_message() -> None:
    interp = _interp(Preference("compound", 1, 0.9, False, phrase="avoid the compound"))
    with pytest.raises(NoLayerMatched) as info:
        fit_program(interp, LAYERS)
    exc = info.value
    assert isinstance(exc, InputError)
    assert exc.entities == ("compound",) and exc.layers == LAYERS
    assert str(exc) == (
        "none of the entities the prompt speaks about (compound) matches a layer "
        "(grass, road, water, building); name a layer or add --alias ENTITY=LAYER"
    )


def test_the_unmatched_entities_of_a_partly_matched_prompt() -> None:
    interp = _interp(
        Preference("compound", 1, 0.9, False, phrase="avoid the compound"),
        Preference("road", 0, 0.1, False, phrase="prefer the roads"),
    )
    fitted = fit_program(interp, LAYERS)
    assert unmatched_entities(interp, fitted.mapping) == ("compound",)
    assert unmatched_entities(interp, match_entities(["compound", "road"], LAYERS, {"compound": "building"})) == ()
    (warning,) = fitted.warnings
    assert warning.startswith("'compound' matches no layer") and "--alias 'compound=LAYER'" in warning
    assert "'avoid the compound'" in warning and fitted.no_effect == ("avoid the compound",)


def test_a_cue_on_an_unmatched_entity_quotes_the_words_the_prompt_wrote_for_it() -> None:
    """ "stay clear of the pylons": the cue's entity has no phrase of its own, so the warning and
    ``--strict`` quote the word read as it, where the user can find it in the brief."""
    from overseec_core.interpret.offline import interpret_offline

    fitted = fit_program(interpret_offline("avoid the water and stay clear of the pylons"), LAYERS)
    assert fitted.no_effect == ("pylons",)
    (warning,) = fitted.warnings
    assert warning.startswith("'electric tower' matches no layer") and "('pylons')" in warning
