"""The offline interpreter: the paper's prompts, the phrase tiers, cues, orderings, leftovers.

What the interpreter states are ordinal keys (lower = better; ``lexicon.NEUTRAL`` is no
preference): tests read them from :func:`analyse` (``st.weights``). What the whole
interpretation carries after merging (ranks, cost levels, phrases) is read from
:func:`interpret_offline`.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from overseec_core.costlang import check_program
from overseec_core.errors import InterpretError
from overseec_core.interpret import interpret
from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.lexicon import FILLER
from overseec_core.interpret.offline import analyse, interpret_offline
from overseec_core.interpret.priors import BUILT_IN
from overseec_core.schema import DEFAULT_ENTITIES, Cue

PAPER = "Prefer the roads and trails, grass should be fine, try to avoid the baseball field as much as possible."


def prefs(prompt: str) -> dict[str, tuple[int, float, bool]]:
    """Entity -> (rank, cost level, lethal) of the merged interpretation."""
    return {p.entity: (p.rank, p.weight, p.lethal) for p in interpret_offline(prompt).preferences}


def ranks(prompt: str) -> dict[str, int]:
    return {k: v[0] for k, v in prefs(prompt).items()}


def keys(prompt: str) -> dict[str, tuple[float, bool]]:
    """What the prompt stated: entity -> (ordinal key, lethal); unstated entities are absent."""
    return analyse(prompt).weights


def weight(prompt: str, entity: str) -> float:
    """The stated ordinal key of an entity (lower = better)."""
    return keys(prompt)[entity][0]


def lethal(prompt: str, entity: str) -> bool:
    return prefs(prompt)[entity][2]


_TIER_OF = {v: k for k, v in lx.TIERS.items()}


def tier(prompt: str, entity: str) -> str | None:
    """The tier name of what the prompt stated about an entity (None: nothing stated)."""
    k = keys(prompt).get(entity)
    return None if k is None else _TIER_OF.get(k, f"order:{k[0]:.2f}")


# ----------------------------------------------------------------------------- the paper's prompts


def test_paper_prompt_ranking_exact():
    it = interpret_offline(PAPER)
    r = {p.entity: p.rank for p in it.preferences}
    # the paper's ranking of its headline prompt: the unsaid trees (4), buildings and water (5) at
    # their priors, worse than the field the prompt avoids (3)
    assert (r["road"], r["trail"], r["grass"], r["baseball field"]) == (1, 1, 2, 3)
    assert (r["tree"], r["building"], r["water"]) == (4, 5, 5)
    assert {p.entity: p.band for p in it.preferences if p.prior} == {
        "tree": "prior",
        "building": "prior",
        "water": "prior",
    }
    assert it.hierarchy == (("baseball field", "grass"),)
    assert [e.name for e in it.entities] == [n for n, _ in DEFAULT_ENTITIES] + ["baseball field"]
    assert {e.name: e.geometry for e in it.entities}["baseball field"] == "areal"
    assert it.unparsed == () and it.cues == ()
    assert it.source == "offline"
    check_program(it.program, [e.name for e in it.entities])


def test_avoid_electric_tower_vs_can_go_under():
    assert tier("avoid electric tower", "electric tower") == "avoid"
    assert tier("you can go under the electric towers", "electric tower") == "fine"  # = neutral
    assert not lethal("you can go under the electric towers", "electric tower")  # passable
    r = ranks("avoid electric tower")
    assert r["electric tower"] > r["grass"]  # worse than what is unmentioned (neutral)
    assert lethal("electric towers are impassable", "electric tower")
    assert prefs("avoid pylons") == prefs("avoid electric tower")  # synonym


def test_avoid_river_vs_river_is_dry():
    assert keys("avoid river")["river"] == (lx.AVOID, False)
    assert keys("the river is dry")["river"] == (lx.FINE, False)
    assert prefs("the river is dry")["river"][1] < prefs("avoid river")["river"][1]
    it = interpret_offline("the river is dry")
    assert ("river", "water") in it.hierarchy


def test_centre_vs_side_of_the_road():
    centre = interpret_offline("stay on the center of the road")
    side = interpret_offline("drive on the side of the road")
    assert centre.cues == (Cue("centre", "road"),) and side.cues == (Cue("side", "road"),)
    for it in (centre, side):
        assert {p.entity: p.rank for p in it.preferences}["road"] == 1
        assert it.unparsed == ()
        check_program(it.program, [e.name for e in it.entities])
    assert interpret_offline("keep to the edges of the road").cues == (Cue("side", "road"),)
    assert interpret_offline("follow the road centre line").cues == (Cue("centre", "road"),)
    assert interpret_offline("stay on the roadside").cues == (Cue("side", "road"),)


def test_paper_example_with_dry_pond_and_sides():
    it = interpret_offline(
        "avoid the baseball field. the pond is dry, so you can go over it. "
        "stay on the sides of the road, dont go over water."
    )
    p = analyse(it.prompt).weights
    assert p["baseball field"] == (lx.AVOID, False)
    assert p["pond"] == (lx.FINE, False)
    assert p["water"] == (lx.AVOID, False)
    assert p["road"] == (lx.PREFER, False)
    assert Cue("side", "road") in it.cues
    assert set(it.hierarchy) == {("baseball field", "grass"), ("pond", "water")}
    assert it.unparsed == ()


# ----------------------------------------------------------------------------- tiers


@pytest.mark.parametrize(
    "phrase, tier",
    [
        ("prefer the trees", lx.PREFER),
        ("trees are best", lx.PREFER),
        ("trees are ideal", lx.PREFER),
        ("stay on the trees", lx.PREFER),
        ("trees are fine", lx.FINE),
        ("trees are okay", lx.FINE),
        ("trees are acceptable", lx.FINE),
        ("trees are tolerable", lx.TOLERABLE),
        ("use trees only if necessary", lx.TOLERABLE),
        ("avoid trees", lx.AVOID),
        ("don't go through trees", lx.AVOID),
        ("stay off the trees", lx.AVOID),
        ("try to avoid trees as much as possible", lx.STRONG_AVOID),
        ("you may cross the trees", lx.FINE),
    ],
)
def test_phrase_tiers(phrase, tier):
    assert keys(phrase)["tree"] == (tier, False)
    assert interpret_offline(phrase).unparsed == ()


@pytest.mark.parametrize(
    "phrase",
    [
        "never enter the water",
        "water is forbidden",
        "water is impassable",
        "water is off-limits",
        "avoid water at all costs",
        "water is a no-go zone",
        "under no circumstances go into the water",
    ],
)
def test_lethal_phrases(phrase):
    assert prefs(phrase)["water"] == (max(ranks(phrase).values()), 1.0, True)
    assert interpret_offline(phrase).unparsed == ()


@pytest.mark.parametrize(
    "phrase",
    [
        "you must not cross the water",
        "never cross the water",
        "do not cross the water",
        "don't cross the water",
        "you cannot cross the water",
        "under no circumstances cross the water",
    ],
)
def test_crossing_prohibitions_are_one_rule_whatever_the_wording(phrase):
    """ "do not cross" and "never cross" mean the same: the nocross rule (kept unless the water
    separates the points, then crossed once at the cheapest place), never lethal."""
    it = interpret_offline(phrase)
    p = {x.entity: x for x in it.preferences}["water"]
    assert tier(phrase, "water") == "nocross" and not p.lethal and p.weight >= lx.STRONG_AVOID
    assert Cue("no_cross", "water", hard=True) in it.cues and "keep_out" in it.program
    assert it.unparsed == ()


@pytest.mark.parametrize("phrase", ["try not to cross the water", "avoid crossing the water"])
def test_a_wish_not_to_cross_is_a_soft_avoid(phrase):
    it = interpret_offline(phrase)
    assert tier(phrase, "water") == "avoid" and not any(c.kind == "no_cross" for c in it.cues)


def test_negation_combines_with_the_trigger_beside_it():
    assert weight("don't use the grass", "grass") == lx.AVOID
    assert weight("grass is not fine", "grass") == lx.AVOID
    assert weight("grass isn't okay", "grass") == lx.AVOID
    assert lethal("never use the grass", "grass")


def test_each_entity_takes_the_nearest_trigger():
    p = keys("avoid water and roads are fine")
    assert p["water"][0] == lx.AVOID and p["road"][0] == lx.FINE
    p = keys("The robot should avoid trees and buildings, prefer the road")
    assert p["tree"][0] == p["building"][0] == lx.AVOID and p["road"][0] == lx.PREFER


def test_lists_and_bare_clauses_share_the_trigger():
    p = keys("avoid water, buildings and trees; you may cross the river")
    assert p["water"][0] == p["building"][0] == p["tree"][0] == lx.AVOID
    assert p["river"][0] == lx.FINE
    assert weight("trees: avoid", "tree") == lx.AVOID
    p = keys("roads, trails and paths are fine")
    assert p["road"][0] == p["trail"][0] == p["path"][0] == lx.FINE


def test_pronoun_refers_to_the_previous_clause():
    assert weight("The lake is frozen, so you may cross it", "lake") == lx.FINE
    assert weight("There is a pond. Avoid it.", "pond") == lx.AVOID


# ----------------------------------------------------------------------------- orderings


def test_first_then_ordering():
    r = ranks("First use the roads, then trails, then grass.")
    assert r["road"] < r["trail"] < r["grass"] < r["tree"]
    it = interpret_offline("Use trails first, then roads, finally grass. Never cross the river.")
    p = {x.entity: (x.rank, x.weight, x.lethal) for x in it.preferences}
    assert p["trail"][0] < p["road"][0] < p["grass"][0]
    assert not p["river"][2] and Cue("no_cross", "river", hard=True) in it.cues  # a rule, not lethal


def test_better_worse_than():
    r = ranks("Roads are better than trails. Grass is worse than trails.")
    assert r["road"] < r["trail"] < r["grass"]
    r = ranks("trails are better than roads")
    assert r["trail"] < r["road"]
    r = ranks("prefer the bridge over the ford")
    assert r["bridge"] < r["ford"]
    r = ranks("use the trails rather than the grass")
    assert r["trail"] < r["grass"]
    r = ranks("grass is fine but worse than trails")
    assert r["trail"] < r["grass"]
    p = keys("the pond is as good as the lake, the lake is okay")
    assert p["pond"][0] == p["lake"][0] == lx.FINE


def test_later_statement_wins_and_is_noted():
    it = interpret_offline("Avoid grass. Grass is fine.")
    assert keys(it.prompt)["grass"] == (lx.FINE, False)
    assert {p.entity: p.phrase for p in it.preferences}["grass"] == "Grass is fine"
    assert any("'grass': the last statement (fine) overrides an earlier one (avoid)" in n for n in it.notes)


# ----------------------------------------------------------------------------- conditions and cues


def test_unless_near_condition():
    it = interpret_offline("avoid grass unless near a road")
    assert keys(it.prompt)["grass"] == (lx.AVOID, False)
    assert it.cues == (Cue("unless_near", "grass", lx.DEFAULT_CUE_DISTANCE_M, "road"),)
    check_program(it.program, [e.name for e in it.entities])
    assert interpret_offline("Unless near the road, stay off the grass").cues == it.cues
    assert interpret_offline("avoid grass, unless it is near a road").cues == it.cues


def test_if_near_and_distances():
    it = interpret_offline("grass is okay if within 5 m of a trail")
    assert it.cues == (Cue("if_near", "grass", 5.0, "trail"),)
    assert interpret_offline("avoid grass unless within 20 ft of the road or trail").cues == (
        Cue("unless_near", "grass", pytest.approx(6.096), "road"),
        Cue("unless_near", "grass", pytest.approx(6.096), "trail"),
    )
    assert interpret_offline("avoid grass near roads").cues == (
        Cue("if_near", "grass", lx.DEFAULT_CUE_DISTANCE_M, "road"),
    )


def test_near_and_far_cues():
    it = interpret_offline("Keep at least 10 m from buildings and stay within 5 metres of the road")
    assert it.cues == (Cue("far", "building", 10.0, hard=True), Cue("near", "road", 5.0, hard=True))
    far = interpret_offline("stay 2 km away from the water")  # units read; the language's limit applies
    assert far.cues == (Cue("far", "water", 500.0),)
    assert any("2000 m is outside (0, 500] m; used 500 m" in n for n in far.notes)
    assert interpret_offline("stay near the river").cues == (Cue("near", "river", lx.DEFAULT_GRADED_DISTANCE_M),)
    it = interpret_offline("avoid going near buildings")
    assert it.cues == (Cue("far", "building", lx.DEFAULT_GRADED_DISTANCE_M),)
    assert keys(it.prompt)["building"] == (lx.AVOID, False)
    for text in ("stay ten metres away from the power lines", "keep more than 15 m from the lake"):
        it = interpret_offline(text)
        assert it.cues[0].kind == "far" and it.unparsed == ()
        check_program(it.program, [e.name for e in it.entities])


# ----------------------------------------------------------------------------- entities


def test_geometry_table_and_fallback():
    geo = {
        e.name: e.geometry
        for e in interpret_offline(
            "avoid the railway, power lines, fences, rivers, the lake, the forest, buildings, "
            "the parking lot and the muddy canal"
        ).entities
    }
    assert geo["railway"] == geo["power line"] == geo["fence"] == geo["river"] == "linear"
    assert geo["lake"] == geo["forest"] == geo["building"] == geo["parking lot"] == "areal"
    assert geo["muddy canal"] == "linear"  # compound: geometry of its known tail
    assert lx.geometry_of("goat track") == "linear" and lx.geometry_of("sandbox") == "areal"


def test_hierarchy_table():
    it = interpret_offline(
        "avoid the football field, the lawn, the highway, the footpath, "
        "the orchard, the shed, the stream and the electric tower"
    )
    assert set(it.hierarchy) == {
        ("football field", "grass"),
        ("lawn", "grass"),
        ("highway", "road"),
        ("footpath", "trail"),
        ("orchard", "tree"),
        ("shed", "building"),
        ("stream", "water"),
    }
    assert lx.parent_of("electric tower") is None and lx.parent_of("dirt road") == "road"
    assert lx.parent_of("muddy baseball field") == "grass" and lx.parent_of("concrete bridge") is None


def test_open_vocabulary_entities_and_compounds():
    # ("dirt roads" is the table's "unpaved road" since issue 31; "cobbled" is unknown)
    it = interpret_offline("prefer cobbled roads, avoid the sandbox")
    p = keys(it.prompt)
    assert p["cobbled road"][0] == lx.PREFER and p["sandbox"][0] == lx.AVOID
    assert ("cobbled road", "road") in it.hierarchy
    assert it.unparsed == ()


@pytest.mark.parametrize(
    "prompt",
    [
        "avoid the sandbox",
        "roads are a last resort",
        "stay under the trees",
        "keep at least 20 m away from buildings",
        "grass is better than water",
        "go cross-country through the vegetation",
    ],
)
def test_unmentioned_entities_get_no_stated_preference(prompt):
    """Only what the prompt names gets a stated preference; the default set the segmenter looks
    for stays neutral (no invented 'trail' or 'road' preference)."""
    st = analyse(prompt)
    for name in st.weights:  # every stated entity is named in the prompt ("buildings", "trees")
        assert name.split()[-1][:4] in prompt.lower()
    it = interpret_offline(prompt)
    for p in it.preferences:
        if p.entity not in st.weights:
            prior = BUILT_IN.for_name(p.entity)
            assert p.phrase == "" and not p.lethal
            # unsaid: neutral, or the prior of a hazard (never an invented preference)
            assert (p.weight, p.prior) == ((prior.level, True) if prior else (lx.NEUTRAL, False))
    assert "trail" not in st.weights


def test_entities_named_only_in_cues_get_neutral_weight():
    p = {x.entity: x.weight for x in interpret_offline("keep 10 m from the pylons").preferences}
    assert p["electric tower"] == lx.NEUTRAL


# ----------------------------------------------------------------------------- mission language
# Phrasing families (issue 9): each is a rule or table row, tested on several wordings.


def _neutral_rank(prompt: str) -> int:
    """Rank of the neutral level: one more than the number of distinct levels below it."""
    return 1 + len({w for _, w, lethal in prefs(prompt).values() if not lethal and w < lx.NEUTRAL})


@pytest.mark.parametrize(
    "prompt, entity, expected, other, metres",
    [
        ("do not cross the railway except at level crossings", "railway", "nocross", "level crossing", None),
        ("do not cross the railway, except at the level crossings", "railway", "nocross", "level crossing", None),
        ("the railway is off limits except at the level crossing", "railway", "lethal", "level crossing", None),
        ("never enter the water unless near the bridge", "water", "lethal", "bridge", None),
        ("never enter the water unless over the bridge", "water", "lethal", "bridge", None),
        ("avoid roads except near the village", "road", "avoid", "village", None),
        ("stay off the grass except near the trails", "grass", "avoid", "trail", None),
        # "don't go into X" forbids X (issue 31), here except at the ford
        ("don't go into the river except at the ford", "river", "lethal", "ford", None),
        ("avoid the highway unless within 20 m of the bridge", "highway", "avoid", "bridge", 20.0),
        # "only at Y" after crossing or a permission: impassable except near Y
        ("cross the railway only at level crossings", "railway", "nocross", "level crossing", None),
        ("you may wade through the river only near the ford", "river", "nocross", "ford", None),
        ("avoid water, only cross at the bridge", "water", "avoid", "bridge", None),
    ],
)
def test_negation_with_an_exception(prompt, entity, expected, other, metres):
    it = interpret_offline(prompt)
    assert tier(prompt, entity) == expected
    cue = Cue("unless_near", entity, metres or lx.DEFAULT_CUE_DISTANCE_M, other)
    assert cue in it.cues
    assert it.unparsed == ()
    assert other in {e.name for e in it.entities}
    check_program(it.program, [e.name for e in it.entities])


def test_only_near_after_a_stated_preference_restricts_it():
    it = interpret_offline("avoid the river, but only near the village")
    assert tier(it.prompt, "river") == "avoid"
    assert it.cues == (Cue("if_near", "river", lx.DEFAULT_CUE_DISTANCE_M, "village"),)
    it = interpret_offline("use the trails only near the village")
    assert it.cues == (Cue("if_near", "trail", lx.DEFAULT_CUE_DISTANCE_M, "village"),)


@pytest.mark.parametrize(
    "prompt, entity",
    [
        ("drive only on roads", "road"),
        ("stay only on the trails", "trail"),
        ("only drive on the grass", "grass"),
    ],
)
def test_only_with_nothing_to_restrict_is_a_preference(prompt, entity):
    it = interpret_offline(prompt)
    assert keys(prompt) == {entity: (lx.PREFER, False)}
    assert it.cues == () and it.unparsed == ()


def test_level_crossing_is_an_entity():
    assert lx.SURFACE[("level", "crossings")] == "level crossing"
    assert lx.SURFACE[("railway", "crossing")] == "level crossing"
    assert lx.geometry_of("level crossing") == "areal" and lx.parent_of("level crossing") is None


@pytest.mark.parametrize(
    "prompt, entity, expected",
    [
        ("roads are a last resort", "road", "last"),
        ("use the roads only as a last resort", "road", "last"),
        ("only cross water if you have to", "water", "tolerable"),
        ("take the highway only if absolutely necessary", "highway", "tolerable"),
        ("the forest is our last option", "forest", "last"),
        ("use the bridge only in an emergency", "bridge", "last"),
        ("grass, if necessary", "grass", "tolerable"),
    ],
)
def test_last_resort_is_tolerable(prompt, entity, expected):
    """Worse than neutral ground: used only where nothing unmentioned gets through; a last
    resort is the worst ground still used, dearer than what is used "if needed"."""
    assert tier(prompt, entity) == expected
    assert interpret_offline(prompt).unparsed == ()
    assert ranks(prompt)[entity] > _neutral_rank(prompt)


@pytest.mark.parametrize(
    "prompt, better, worse",
    [
        ("grass is better than water", "grass", "water"),
        ("prefer trails over roads", "trail", "road"),
        ("use the grass rather than the sand", "grass", "sand"),
        ("sand is worse than grass", "grass", "sand"),
        ("the road is less preferable than the trail", "trail", "road"),
        ("choose the bridge over the ford", "bridge", "ford"),
        ("trails are preferable to roads", "trail", "road"),
        ("take the trails instead of the roads", "trail", "road"),
        ("roads are not as good as trails", "trail", "road"),
    ],
)
def test_comparatives_order_both_sides(prompt, better, worse):
    st = analyse(prompt)
    assert better in st.weights and worse in st.weights
    assert st.weights[better][0] < st.weights[worse][0]
    assert st.weights[worse][0] >= lx.NEUTRAL  # the worse side is not made preferred
    r = ranks(prompt)
    assert r[better] < r[worse]
    assert st.phrases[better] == st.phrases[worse] != ""
    assert interpret_offline(prompt).unparsed == ()


@pytest.mark.parametrize(
    "prompt, entity",
    [
        ("stay under the trees", "tree"),
        ("stay under the tree cover", "tree"),
        ("keep to the tree canopy", "tree"),
        ("keep under the canopy", "tree"),
        ("stay hidden in the forest", "forest"),
        ("move under cover of the trees", "tree"),
        ("remain concealed among the trees", "tree"),
        ("stay in the shade of the trees", "tree"),
    ],
)
def test_concealment_prefers_the_cover(prompt, entity):
    assert tier(prompt, entity) == "prefer"
    it = interpret_offline(prompt)
    assert it.unparsed == ()
    assert [e.name for e in it.entities if e.name not in dict(DEFAULT_ENTITIES)] == (
        [] if entity == "tree" else [entity]
    )


def test_concealment_negated():
    assert tier("don't stay under the power lines", "power line") == "avoid"


@pytest.mark.parametrize(
    "prompt, entity",
    [
        ("you can wade through the water", "water"),
        ("it's ok to drive through the grass", "grass"),
        ("you may cross the stream", "stream"),
        ("feel free to go over the bridge", "bridge"),
        ("you are allowed to drive on the grass", "grass"),
        ("it is fine to walk across the field", "field"),
        ("you could swim across the pond", "pond"),
        ("you can just wade through the water", "water"),
        ("go ahead and drive through the grass", "grass"),
    ],
)
def test_permission_is_neutral(prompt, entity):
    """Permission is no objection: neutral, neither sought nor avoided."""
    assert tier(prompt, entity) == "fine" and lx.FINE == lx.NEUTRAL
    p = prefs(prompt)[entity]
    assert p[1] == lx.NEUTRAL and not p[2] and p[0] == _neutral_rank(prompt)
    assert interpret_offline(prompt).unparsed == ()


@pytest.mark.parametrize(
    "prompt, expected",
    [
        ("you can't wade through the water", "lethal"),
        ("you may not cross the water", "nocross"),
        ("you can go around the water", "avoid"),
        ("go around the water", "avoid"),
    ],
)
def test_negated_permission_and_going_around(prompt, expected):
    assert tier(prompt, "water") == expected


@pytest.mark.parametrize(
    "prompt, entity",
    [
        ("stay off the tracks", "railway"),
        ("stay off the train tracks", "railway"),
        ("keep off the railroad tracks", "railway"),
        ("stay off the rail tracks", "railway"),
        ("keep off the grass", "grass"),
        ("get off the road", "road"),
        ("stay off roads", "road"),
    ],
)
def test_stay_off_is_avoid(prompt, entity):
    assert tier(prompt, entity) == "avoid"
    assert interpret_offline(prompt).unparsed == ()


def test_tracks():
    """A bare "tracks" is the railway; qualified tracks ("dirt tracks") are not."""
    assert tier("drive along the dirt tracks", "trail") == "prefer"
    st = analyse("avoid the muddy tracks")
    assert st.weights == {"muddy track": (lx.AVOID, False)}
    assert lx.geometry_of("muddy track") == "linear"


@pytest.mark.parametrize(
    "prompt, entity",
    [
        ("go cross-country through the vegetation", "vegetation"),
        ("head cross country over the fields", "field"),
        ("off-road through the grass", "grass"),
        ("drive off road across the sand", "sand"),
        ("go overland through the bushes", "bush"),
        ("go off the beaten track through the forest", "forest"),
        ("The rover should head across country over the grass", "grass"),
    ],
)
def test_cross_country_prefers_the_terrain_named(prompt, entity):
    st = analyse(prompt)
    assert st.weights == {entity: (lx.PREFER, False)}
    assert st.mentioned == [entity]  # never 'country', 'off', the 'road' of off-road, 'track'
    assert interpret_offline(prompt).unparsed == ()


def test_cross_country_without_terrain_is_reported():
    it = interpret_offline("travel cross-country")
    assert analyse(it.prompt).weights == {} and "travel cross-country" in it.unparsed


@pytest.mark.parametrize(
    "prompt, names",
    [
        ("Please go cross-country through the vegetation, carefully and quietly.", {"vegetation"}),
        ("Head off-road over the fields as quickly as possible", {"field"}),
        ("I'd like you to stay under the tree cover whenever you can", {"tree"}),
        ("Make sure to keep well away from the water, ok?", {"water"}),
        ("Honestly, just get there safely and avoid the roads", {"road"}),
        ("You can basically wade through the water if you really need to", {"water"}),
        ("Let's move quietly and stay hidden in the forest", {"forest"}),
        ("It would be great if you could stay off the tracks and avoid the houses", {"railway", "house"}),
        ("Please try your best to avoid water and go through the grass instead", {"water", "grass"}),
        ("We need you to get to the target fast, roads are a last resort", {"road"}),
        ("Feel free to take the trails if you want, but stay away from the river", {"trail", "river"}),
        ("The drone must keep at least 20 m away from buildings at all times", {"building"}),
        ("Proceed off-road through the fields and keep a low profile", {"field"}),
    ],
)
def test_filler_words_never_become_entities(prompt, names):
    st = analyse(prompt)
    assert set(st.mentioned) == names
    for name in st.mentioned:  # open-vocabulary names are content words only
        if name not in lx.KNOWN_BY_NAME:
            assert not set(name.split()) & FILLER


def test_filler_heavy_prompts_keep_their_meaning():
    p = keys("Please try your best to avoid water and go through the grass instead")
    assert p == {"water": (lx.AVOID, False), "grass": (lx.PREFER, False)}
    p = keys("Feel free to take the trails if you want, but stay away from the river")
    assert p == {"trail": (lx.FINE, False), "river": (lx.AVOID, False)}
    assert keys("It would be great if you could stay off the tracks")["railway"] == (lx.AVOID, False)
    assert interpret_offline("It would be great if you could stay off the tracks").unparsed == ()


@pytest.mark.parametrize(
    "prompt, cue",
    [
        # a bound ("at least", "no closer than", "within", "no more than", "never within") is a rule
        ("keep at least 20 m away from buildings", Cue("far", "building", 20.0, hard=True)),
        ("stay at least 30 m from the water", Cue("far", "water", 30.0, hard=True)),
        ("never go within 10 m of the railway", Cue("far", "railway", 10.0, hard=True)),
        ("no closer than 15 m to houses", Cue("far", "house", 15.0, hard=True)),
        ("keep a minimum distance of 20 m from the water", Cue("far", "water", 20.0, hard=True)),
        ("stay within 50 m of the road", Cue("near", "road", 50.0, hard=True)),
        ("stay no more than 30 m from the trail", Cue("near", "trail", 30.0, hard=True)),
        # a plain distance, or a softened one, is a preference
        ("stay 20 m away from buildings", Cue("far", "building", 20.0)),
        ("keep away from buildings by 20 m", Cue("far", "building", 20.0)),
        ("keep a 20 m buffer around the water", Cue("far", "water", 20.0)),
        ("try to stay within 50 m of the road", Cue("near", "road", 50.0)),
        ("stay near the river", Cue("near", "river", lx.DEFAULT_GRADED_DISTANCE_M)),
        ("avoid going within 5 m of the water", Cue("far", "water", 5.0)),
        ("keep a safe distance from the pylons", Cue("far", "electric tower", lx.DEFAULT_GRADED_DISTANCE_M)),
    ],
)
def test_distance_rules(prompt, cue):
    it = interpret_offline(prompt)
    assert it.cues == (cue,)
    assert it.unparsed == ()
    check_program(it.program, [e.name for e in it.entities])


def test_never_within_is_a_rule_and_strongly_avoids_the_entity():
    # the rule's keep-out zone covers the railway; lethal would forbid the fallback the rule allows
    assert keys("never go within 10 m of the railway") == {"railway": (lx.STRONG_AVOID, False)}
    assert keys("keep at least 20 m away from buildings") == {}  # a distance, not a preference


# ----------------------------------------------------------------------------- explainability


@pytest.mark.parametrize(
    "prompt, expected",
    [
        (
            PAPER,
            {
                "road": "Prefer the roads and trails",
                "trail": "Prefer the roads and trails",
                "grass": "grass should be fine",
                "baseball field": "avoid the baseball field as much as possible",
            },
        ),
        (
            "avoid water, buildings and trees; you may cross the river",
            {
                "water": "avoid water, buildings and trees",
                "building": "avoid water, buildings and trees",
                "tree": "avoid water, buildings and trees",
                "river": "you may cross the river",
            },
        ),
        ("avoid water, buildings", {"water": "avoid water, buildings", "building": "avoid water, buildings"}),
        ("avoid water. Buildings are fine", {"water": "avoid water", "building": "Buildings are fine"}),
        ("The lake is frozen, so you may cross it", {"lake": "The lake is frozen, so you may cross it"}),
        ("Unless near the road, stay off the grass", {"grass": "Unless near the road, stay off the grass"}),
        (
            "First use the roads, then trails, then grass.",
            {
                "road": "First use the roads",
                "trail": "First use the roads, then trails",
                "grass": "First use the roads, then trails, then grass",
            },
        ),
        (
            "Roads are better than trails. Grass is worse than trails.",
            {
                "road": "Roads are better than trails",
                "trail": "Roads are better than trails; Grass is worse than trails",
                "grass": "Grass is worse than trails",
            },
        ),
        ("stay on the center of the road", {"road": "stay on the center of the road"}),
        ("never go within 10 m of the railway", {"railway": "never go within 10 m of the railway"}),
    ],
)
def test_each_stated_preference_carries_its_phrase(prompt, expected):
    it = interpret_offline(prompt)
    got = {p.entity: p.phrase for p in it.preferences if p.phrase}
    assert got == expected
    for p in it.preferences:
        for part in p.phrase.split("; "):
            assert part in prompt  # quoted from the prompt itself
    assert all(d["phrase"] == got.get(d["entity"], "") for d in it.to_json()["preferences"])


# ----------------------------------------------------------------------------- leftovers


@pytest.mark.parametrize(
    "prompt, fragment",
    [
        ("Avoid the baseball field on weekends", "weekends"),
        ("Please be careful", "Please be careful"),
        ("Prefer roads. Éviter l'eau", "Éviter l'eau"),
        ("If the river is dry, you may cross it", "If the river is dry"),
        ("cross the bridge", "cross the bridge"),
        ("stay in the middle of the field", "stay in the middle of the field"),
    ],
)
def test_what_is_not_understood_is_reported(prompt, fragment):
    assert fragment in interpret_offline(prompt).unparsed


def test_nothing_dropped_from_a_mixed_prompt():
    it = interpret_offline("Prefer roads, do a barrel roll, avoid water")
    assert keys(it.prompt)["water"] == (lx.AVOID, False)
    assert any("barrel roll" in u for u in it.unparsed)


def test_deterministic():
    prompt = "first roads then trails, avoid grass unless near a road, keep 5 m from buildings"
    a, b = interpret_offline(prompt), interpret_offline(prompt)
    assert a == b and a.to_json() == b.to_json()


@pytest.mark.parametrize("prompt", ["", "   ", "...", "12 34"])
def test_empty_or_wordless_prompts_are_errors(prompt):
    with pytest.raises(InterpretError):
        interpret(prompt, offline=True)


def test_long_prompt_is_refused():
    with pytest.raises(InterpretError, match="at most"):
        interpret("avoid water " * 1000, offline=True)


# ----------------------------------------------------------------------------- property


_WORDS = sorted(
    {w for phrase in lx.SURFACE for w in phrase}
    | set(
        "prefer avoid never fine okay tolerable best ideal forbidden impassable off limits at all costs "
        "can go under you may cross worse better than first then unless if near within at least 10 m "
        "from of the side centre center edge it them , . ; and or but not don't dry 5 km ft".split()
    )
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.one_of(st.sampled_from(_WORDS), st.text(max_size=6)), min_size=1, max_size=25))
def test_any_prompt_gives_an_error_or_a_valid_interpretation(words):
    prompt = " ".join(words)
    try:
        it = interpret(prompt, offline=True)
    except InterpretError:
        return
    names = [e.name for e in it.entities]
    assert len(set(names)) == len(names)
    assert {p.entity for p in it.preferences} == set(names)
    assert all(0.0 <= p.weight <= 1.0 and p.rank >= 1 for p in it.preferences)
    assert all(c in names and p in names for c, p in it.hierarchy)
    assert all(u in prompt for u in it.unparsed)  # quoted from the prompt itself
    check_program(it.program, names)
