"""Issue 31's constructs in the offline interpreter, each on phrasings of its own (the held-out
brief sets in tests/mission_briefs_set*.py measure them; these pin the rules).

- distance rules worded as absolute anywhere in the sentence are hard; a number survives
  ("..., say 20 m"); soft wording stays soft;
- on versus beside: the object avoided (forbidden with "never") and a near cue beside it;
- "stay out of / keep out of / don't go into X" forbid X; "avoid X" stays an avoid;
- symbolic chains ("A > B > C", "A >> B", "A before B") and colon verdicts ("X: no go, Y: yes");
- qualified roads: "tarmac" is the paved road, "gravel" the unpaved one, a bare "road" both;
- a common English word is never read as a misspelt entity ("weather permitting").
"""

from __future__ import annotations

import pytest

from overseec_core.interpret import lexicon as lx
from overseec_core.interpret.matching import match_entity
from overseec_core.interpret.normalise import normalise
from overseec_core.interpret.offline import interpret_offline

#: Where a graded cue with no number reaches neutral.
G = lx.DEFAULT_GRADED_DISTANCE_M


def _cues(prompt: str) -> list[tuple]:
    return [(c.kind, c.entity, c.metres, c.hard) for c in interpret_offline(prompt).cues]


def _bands(prompt: str) -> dict[str, str]:
    return {p.entity: p.band for p in interpret_offline(prompt).preferences if p.phrase}


def _weights(prompt: str) -> dict[str, float]:
    return {p.entity: p.weight for p in interpret_offline(prompt).preferences}


@pytest.mark.parametrize(
    "prompt, entity, metres",
    [
        ("the survey team must remain 12 m from the houses", "house", 12.0),
        ("at all times keep 6 m from the ditch", "ditch", 6.0),
        ("never get nearer than 30 m to the lake", "lake", 30.0),
        ("under no circumstances come within 4 m of the pylons", "electric tower", 4.0),
    ],
)
def test_absolute_wording_makes_a_distance_rule_hard(prompt: str, entity: str, metres: float) -> None:
    assert ("far", entity, metres, True) in _cues(prompt)
    assert not interpret_offline(prompt).unparsed  # the absolute words are read, not left over


@pytest.mark.parametrize(
    "prompt, entity, metres",
    [
        ("if you can, keep some distance from the barn, about 15 m", "barn", 15.0),
        ("ideally stay 8 m off the hedge", "hedge", 8.0),
    ],
)
def test_soft_wording_stays_soft_and_keeps_its_number(prompt: str, entity: str, metres: float) -> None:
    assert ("far", entity, metres, False) in _cues(prompt)


@pytest.mark.parametrize(
    "prompt, entity, band",
    [
        ("walk the lake shore but not in the lake", "lake", "avoided"),
        ("go alongside the canal, never in it", "canal", "lethal"),
        ("skirt the orchard edge without entering", "orchard", "avoided"),
    ],
)
def test_on_versus_beside(prompt: str, entity: str, band: str) -> None:
    it = interpret_offline(prompt)
    assert _bands(prompt)[entity] == band
    assert any(c.kind == "near" and c.entity == entity and not c.hard for c in it.cues)
    assert not it.unparsed


@pytest.mark.parametrize("prompt", ["stay out of the swamp", "keep out of the swamp", "don't go into the swamp"])
def test_staying_out_forbids(prompt: str) -> None:
    assert _bands(prompt)["wetland"] == "lethal"


def test_avoid_stays_an_obstacle_not_a_rule() -> None:
    assert _bands("avoid the swamp")["wetland"] == "avoided"


@pytest.mark.parametrize(
    "prompt, order",
    [
        ("footpath > lawn > mud", ("footpath", "lawn", "mud")),
        ("sand >> rock", ("sand", "rock")),
        ("meadow before scrub", ("meadow", "bush")),
    ],
)
def test_symbolic_and_terse_orderings(prompt: str, order: tuple[str, ...]) -> None:
    w = _weights(prompt)
    assert all(w[a] < w[b] for a, b in zip(order, order[1:])), w


def test_a_verdict_after_a_colon_belongs_to_the_names_before_it() -> None:
    bands = _bands("bridge: yes, railway: no go")
    assert bands["bridge"] == "preferred" and bands["railway"] == "lethal"


@pytest.mark.parametrize("prompt", ["roads good", "the tracks are nice"])
def test_terse_praise_prefers(prompt: str) -> None:
    assert "preferred" in _bands(prompt).values()


def test_qualified_roads_map_to_their_own_layers() -> None:
    layers = ["paved road", "unpaved road", "grass"]
    assert match_entity("paved road", layers).layers == ("paved road",)
    assert match_entity("unpaved road", layers).layers == ("unpaved road",)
    assert set(match_entity("road", layers).layers) == {"paved road", "unpaved road"}
    assert match_entity("trail", layers).layers == ("unpaved road",)  # drawn as the unpaved road
    w = _weights("blacktop before gravel")
    assert w["paved road"] < w["unpaved road"]


def test_a_common_word_is_not_a_misspelt_entity() -> None:
    it = interpret_offline("prefer the roads, weather permitting")
    assert "water" not in {p.entity for p in it.preferences if p.phrase}
    assert not any("'weather' as" in n for n in it.notes)


@pytest.mark.parametrize(
    "prompt, cue",
    [
        # graded nearness worded as an aim, a noun or a verb (no distance: the default reach)
        ("keep as far as you reasonably can from the pylons", ("far", "electric tower", G, False)),
        ("get as close as possible to the hedge", ("near", "hedge", G, False)),
        ("reduce exposure to the highway", ("far", "highway", G, False)),
        ("maximise the separation from the barns", ("far", "barn", G, False)),
        ("stay within earshot of the road", ("near", "road", G, False)),
        ("hug the fence", ("near", "fence", G, False)),
        # a gap given to an entity, and how it falls off
        ("leave the sheds a generous margin", ("far", "shed", G, False)),
        (
            "keep off the lawn and give the barn a good berth, the further the better up to 40 m",
            ("far", "barn", 40.0, False),
        ),
        ("the nearer to the trail the better", ("near", "trail", G, False)),
        # an estimate is a preference with a reach, never the opposite rule
        ("stay within about 50 m of the railway", ("near", "railway", 50.0, False)),
        ("keep roughly 20 m back from the ditch", ("far", "ditch", 20.0, False)),
    ],
)
def test_graded_nearness_in_other_words(prompt: str, cue: tuple) -> None:
    assert cue in _cues(prompt)
    assert not interpret_offline(prompt).unparsed


@pytest.mark.parametrize(
    "prompt, cue",
    [
        ("follow the canal and keep within 30 m of it", ("near", "canal", 30.0, True)),
        ("There is a quarry to the east. Stay 25 m away from it.", ("far", "quarry", 25.0, False)),
    ],
)
def test_a_pronoun_after_a_preposition_stands_for_the_entity_named_last(prompt: str, cue: tuple) -> None:
    interp = interpret_offline(prompt)
    assert cue in _cues(prompt)
    assert any("read 'it' as" in n for n in interp.notes)  # the user sees what 'it' was taken for


def test_a_graded_afterthought_with_nothing_to_shape_is_reported() -> None:
    assert interpret_offline("prefer the road. the further the better").unparsed == ("the further the better",)


@pytest.mark.parametrize(
    "prompt, entity, band",
    [
        ("keep to the dry ground next to the bog rather than in it", "wetland", "avoided"),
        ("go along the canal but stay out of the canal itself", "canal", "lethal"),
        ("trace the wall on its outer side", "wall", "avoided"),
    ],
)
def test_beside_with_other_negations(prompt: str, entity: str, band: str) -> None:
    interp = interpret_offline(prompt)
    assert _bands(prompt)[entity] == band
    assert ("near", entity) in [(c.kind, c.entity) for c in interp.cues]


@pytest.mark.parametrize(
    "prompt, entity",
    [
        ("drive parallel to the canal without using the towpath itself", "towpath"),
        ("follow the hedge corridor without occupying the hedge", "hedge"),
        ("keep along the shoulder of the highway, never traversing it", "highway"),
    ],
)
def test_beside_without_using_the_object(prompt: str, entity: str) -> None:
    interp = interpret_offline(prompt)
    assert _bands(prompt)[entity] in ("avoided", "lethal")
    assert ("near", entity) in [(c.kind, c.entity) for c in interp.cues]


@pytest.mark.parametrize(
    "prompt, entity",
    [
        ("follow the hedge. the hedge itself is off limits", "hedge"),
        ("skirt the orchard. avoid the orchard", "orchard"),
    ],
)
def test_beside_holds_when_the_object_is_avoided_in_another_clause(prompt: str, entity: str) -> None:
    interp = interpret_offline(prompt)
    assert _bands(prompt)[entity] in ("avoided", "lethal")
    assert ("near", entity) in [(c.kind, c.entity) for c in interp.cues]


def test_following_an_object_the_prompt_does_not_avoid_adds_no_band() -> None:
    interp = interpret_offline("follow the hedge")
    assert not interp.cues and _bands("follow the hedge")["hedge"] == "preferred"


def test_walking_an_edge_prefers_the_band_and_keeps_the_objects_tier() -> None:
    interp = interpret_offline("walk the edge of the orchard")
    assert ("near", "orchard") in [(c.kind, c.entity) for c in interp.cues]
    assert _bands("walk the edge of the orchard").get("orchard", "neutral") == "neutral"  # not made avoided
    assert not interp.unparsed


@pytest.mark.parametrize(
    "prompt, hard",
    [
        ("Keep 15 m from the pylons. No exceptions.", True),
        ("Keep 15 m from the pylons. Non-negotiable.", True),
        ("Keep 15 m from the pylons. Not mandatory.", False),
        ("Stay 15 m from the pylons; it is not a hard limit.", False),
        ("Keep 15 m from the pylons. no hard limit.", False),
        ("Keep 15 m from the pylons. That buffer is an absolute constraint, not a preference.", True),
        ("Keep 15 m from the pylons. Not a suggestion.", True),
        ("Keep 15 m from the pylons. It is a preference, not a hard limit.", False),
        ("Keep 15 m from the pylons. This distance is only a guideline.", False),
    ],
)
def test_a_sentence_that_only_qualifies_the_rule_before_it(prompt: str, hard: bool) -> None:
    interp = interpret_offline(prompt)
    assert [(c.kind, c.entity, c.metres, c.hard) for c in interp.cues] == [("far", "electric tower", 15.0, hard)]
    assert not interp.unparsed
    assert "exception" not in {e.name for e in interp.entities}  # wording, never an entity


@pytest.mark.parametrize(
    "prompt, metres, hard",
    [
        ("observe a 30 m exclusion buffer around the depot", 30.0, True),
        ("a 30 m exclusion zone around the depot", 30.0, True),
        ("keep a 20 m buffer zone around the depot", 20.0, False),
        ("maintain a 12 m safety margin from the depot", 12.0, False),
        ("a 25 m keep-out zone round the depot", 25.0, True),
    ],
)
def test_a_zone_keeps_its_number_and_an_exclusion_is_hard(prompt: str, metres: float, hard: bool) -> None:
    interp = interpret_offline(prompt)
    assert [(c.kind, c.metres, c.hard) for c in interp.cues] == [("far", metres, hard)]
    assert not interp.unparsed


def test_a_rule_qualifier_with_no_rule_before_it_is_reported() -> None:
    assert "No exceptions" in interpret_offline("Prefer the road. No exceptions.").unparsed


@pytest.mark.parametrize(
    "prompt, metres",
    [
        ("the minimum separation from the barn is 12 m", 12.0),
        ("buffer around the barn: 12 m", 12.0),
        ("keep roughly 12 metres off the barn's edge", 12.0),
    ],
)
def test_a_distance_stated_after_its_entity(prompt: str, metres: float) -> None:
    assert [(c.kind, c.entity, c.metres) for c in interpret_offline(prompt).cues] == [("far", "barn", metres)]
    assert not interpret_offline(prompt).unparsed


@pytest.mark.parametrize(
    "prompt, cue",
    [
        ("keep 12m from the barn", ("far", "barn", 12.0, False)),  # a number and its unit written together
        ("stay 12 m or so from the barn", ("far", "barn", 12.0, False)),  # an estimate after the number
        ("if poss give the barn 12 m", ("far", "barn", 12.0, False)),
        ("must stay at least 12 m off the perimeter fence", ("far", "fence", 12.0, True)),
        ("Hard constraint: never within 12 m of the barn.", ("far", "barn", 12.0, True)),
        ("Soft constraint: a clearance of 12 m from the barn.", ("far", "barn", 12.0, False)),
        ("Setback from the barn: 12 m minimum, mandatory.", ("far", "barn", 12.0, True)),
        ("keep 12 m from the power line corridor at all times", ("far", "power line", 12.0, True)),
    ],
)
def test_distance_rules_in_field_and_spec_wording(prompt: str, cue: tuple) -> None:
    assert _cues(prompt) == [cue]
    assert not interpret_offline(prompt).unparsed


def test_absolute_wording_without_a_number_is_graded_not_an_invented_limit() -> None:
    # "at all times" with no distance: no boundary is stated, so none is drawn at the default
    assert _cues("stay close to the trail at all times") == [("near", "trail", G, False)]
    assert _cues("stay within 30 m of the trail at all times") == [("near", "trail", 30.0, True)]


@pytest.mark.parametrize(
    "prompt, entity",
    [
        ("no need to avoid the barns", "barn"),
        ("you don't have to avoid the barns", "barn"),
        ("don't avoid the barns, they are empty", "barn"),
        ("the barns are derelict", "barn"),
        ("the railway is disused", "railway"),
    ],
)
def test_a_negated_avoid_or_a_harmless_state_permits(prompt: str, entity: str) -> None:
    assert _bands(prompt)[entity] == "neutral"


def test_a_plain_negated_use_still_avoids() -> None:
    assert _bands("don't use the road")["road"] == "avoided"


@pytest.mark.parametrize(
    "prompt, parent, parent_band, child, child_band",
    [
        ("the meadows are fine except the orchard", "meadow", "neutral", "orchard", "avoided"),
        (
            "all meadows are fine apart from the orchard, which must not be entered",
            "meadow",
            "neutral",
            "orchard",
            "lethal",
        ),
        ("avoid the woods other than the clearing", "forest", "avoided", "clearing", "neutral"),
    ],
)
def test_an_excepted_sub_area_takes_the_other_side(
    prompt: str, parent: str, parent_band: str, child: str, child_band: str
) -> None:
    bands = _bands(prompt)
    assert (bands[parent], bands[child]) == (parent_band, child_band)


@pytest.mark.parametrize(
    "prompt, cue",
    [
        # the traveller named as the subject, and a noun after the object, are no entities
        ("the crew should stay near the canal for the whole patrol", ("near", "canal", G, False)),
        ("cells close to the hedge are best", ("near", "hedge", G, False)),
        ("the planned path should remain in close proximity to the towpath", ("near", "towpath", G, False)),
        ("keep within line of sight of the barn", ("near", "barn", G, False)),
        ("stay near of the orchard", ("near", "orchard", G, False)),
        ("keep way away from the pond", ("far", "pond", G, False)),
        # lessening or growing a gap noun or a proximity noun, wherever the verb stands
        ("minimise the distance to the footpath", ("near", "footpath", G, False)),
        ("maximise closeness to the footpath", ("near", "footpath", G, False)),
        ("exposure to the highway should be minimised", ("far", "highway", G, False)),
        ("the penalty grows with proximity to the silo", ("far", "silo", G, False)),
        ("cost falls as distance from the silo decreases", ("near", "silo", G, False)),
        ("cost rises with distance from the towpath", ("near", "towpath", G, False)),
        # correlatives that end in a price, and where the fall-off ends
        ("the nearer the route gets to the canal, the cheaper", ("near", "canal", G, False)),
        ("keep off the pond, the closer the worse", ("far", "pond", G, False)),
        ("avoid the barn; the further the better", ("far", "barn", G, False)),
        ("stay clear of the silo, tapering off by 25 m", ("far", "silo", 25.0, False)),
        ("keep well away from the shed, no effect beyond about 18 metres", ("far", "shed", 18.0, False)),
        # a correlative about its topic, and the terse symbolic correlative
        ("pond the further the better", ("far", "pond", G, False)),
        ("hedges fine. silo: the further the better", ("far", "silo", G, False)),
        ("towpath, the closer the better", ("near", "towpath", G, False)),
        ("silo: closer = worse", ("far", "silo", G, False)),
        ("avoid the barn. closer = worse", ("far", "barn", G, False)),
        ("use the towpath, nearer is better", ("near", "towpath", G, False)),
    ],
)
def test_graded_nearness_said_by_subjects_verbs_and_correlatives(prompt: str, cue: tuple) -> None:
    assert _cues(prompt) == [cue]
    assert not interpret_offline(prompt).unparsed


@pytest.mark.parametrize(
    "prompt, entity, band",
    [
        ("footpath: fine | hedgerow: avoid", "hedge", "avoided"),  # a bar separates rules like a full stop
        ("footpath -> prefer", "footpath", "preferred"),  # an arrow reads as a colon
        ("bldgs: avoid", "building", "avoided"),  # a field abbreviation
        ("stay on the rds", "road", "preferred"),
        ("the barn is sooo bad", "barn", "avoided"),  # a letter typed three times
        ("tenis cort: avoid", "tennis court", "avoided"),  # a multi-word name typed with slips
        ("prefer the swiming pol", "swimming pool", "preferred"),
    ],
)
def test_field_notes_abbreviations_symbols_and_slips(prompt: str, entity: str, band: str) -> None:
    assert _bands(prompt).get(entity) == band, _bands(prompt)


def test_a_word_one_slip_from_a_name_word_needs_the_rest_of_the_name() -> None:
    """ "cort" alone is no court and "pol" alone no pool: a slip is read only inside a whole name."""
    assert "tennis court" not in _bands("avoid the cort")
    assert "swimming pool" not in _bands("prefer the pol")


def test_an_abbreviation_that_spells_two_words_keeps_the_rule() -> None:
    assert _cues("stay atleast 9 m frm the barn at all times") == [("far", "barn", 9.0, True)]


@pytest.mark.parametrize(
    "prompt, entity",
    [
        ("the crew is cleared to walk across the meadow", "meadow"),
        ("the hedges pose no problem for the tracked rover", "hedge"),
        ("no concern with the sheds", "shed"),
        ("allow: ditch, hedge", "ditch"),
        ("ditch: neutral", "ditch"),
    ],
)
def test_permissions_in_spec_and_radio_wording_are_neutral(prompt: str, entity: str) -> None:
    assert _bands(prompt).get(entity) == "neutral", _bands(prompt)


def test_a_forbid_label_forbids_and_cheap_prefers() -> None:
    assert _bands("forbid: pond | footpath: cheap") == {"pond": "lethal", "footpath": "preferred"}


def test_qualified_trees_map_to_their_own_layers_and_a_bare_tree_to_both() -> None:
    layers = ["conifer tree", "deciduous tree", "grass"]
    assert match_entity("evergreen", layers).layers == ("conifer tree",)
    assert match_entity("broadleaf", layers).layers == ("deciduous tree",)
    assert sorted(match_entity("tree", layers).layers) == ["conifer tree", "deciduous tree"]
    bands = _bands("the pines are fine to drive under; keep away from the broadleaf trees")
    assert bands.get("conifer tree") == "neutral" and bands.get("deciduous tree") == "avoided", bands


def test_a_qualifier_word_before_another_noun_is_part_of_its_name() -> None:
    names = {p.entity for p in interpret_offline("avoid the deciduous woodland and the pine orchard").preferences}
    assert {"deciduous tree", "pine orchard"} <= names, names  # woodland is a tree head, orchard is not


@pytest.mark.parametrize(
    "prompt, kind, layer",
    [
        ("avoid the coniferous stands", "conifer tree", "conifer tree"),
        ("prefer the deciduous woodland", "deciduous tree", "deciduous forest"),
        ("the paved surface is to be avoided", "paved road", "paved road"),
    ],
)
def test_a_qualifier_before_a_head_of_its_parent_names_the_qualified_kind(prompt: str, kind: str, layer: str) -> None:
    assert kind in {p.entity for p in interpret_offline(prompt).preferences if p.phrase}
    assert match_entity(kind, (layer, "grass", "unpaved road")).layers == (layer,)


@pytest.mark.parametrize(
    "prompt, unread",
    [
        ("follow the towpath, and send photos of the lock gates at noon", "photos"),
        ("prefer the track; get back to base before nightfall", "nightfall"),
        ("keep off the hedges, fuel is low", "fuel"),
    ],
)
def test_a_clause_about_logistics_is_reported_not_read_as_terrain(prompt: str, unread: str) -> None:
    interp = interpret_offline(prompt)
    assert any(unread in u for u in interp.unparsed), interp.unparsed
    assert not any(unread.rstrip("s") in p.entity for p in interp.preferences)


def test_a_logistics_clause_is_reported_whole_and_its_nouns_are_no_entities() -> None:
    interp = interpret_offline("prefer the track, and the battery will be swapped at the gate")
    assert "the battery will be swapped at the gate" in interp.unparsed, interp.unparsed
    assert {p.entity for p in interp.preferences if p.phrase} == {"track"}


def test_a_cue_clause_whose_subject_is_unknown_is_still_read() -> None:
    assert not interpret_offline("the survey party must remain 12 m from the silo").unparsed


@pytest.mark.parametrize(
    "prompt, entity",
    [
        ("building: keep out\nroad: prefer", "building"),
        ("the pond - stay out", "pond"),
        ("stay outta the sheds", "shed"),
    ],
)
def test_keeping_out_without_of_forbids(prompt: str, entity: str) -> None:
    assert _bands(prompt)[entity] == "lethal"
    assert not interpret_offline(prompt).unparsed


def test_settings_written_key_equals_value_read_one_by_one() -> None:
    interp = interpret_offline("rail=lethal  veg=ok  bldg=avoid")
    bands = _bands("rail=lethal  veg=ok  bldg=avoid")
    assert bands == {"railway": "lethal", "vegetation": "neutral", "building": "avoided"}
    assert not interp.unparsed
    # an "=" with spaces, or before a number, is no setting; a dot inside a key is a space
    assert normalise("trail = grass; x=1") == "trail = grass; x=1"
    assert normalise("building.standoff") == "building standoff"


def test_a_cost_label_reads_order_symbols_by_cost() -> None:
    by_cost = _weights("cost: grass < road < building")
    assert by_cost["grass"] < by_cost["road"] < by_cost["building"]
    by_pref = _weights("pref: road > trail > grass")
    assert by_pref["road"] < by_pref["trail"] < by_pref["grass"]
    assert not interpret_offline("cost: grass < road < building").unparsed
    assert not interpret_offline("pref: road > trail > grass").unparsed
    plain = _weights("grass < road")  # unlabelled, "<" is the worse side
    assert plain["road"] < plain["grass"]


@pytest.mark.parametrize(
    "prompt, entity",
    [
        ("dont go far from the barn", "barn"),
        ("never stray far from the towpath", "towpath"),
        ("stay not too far from the hedge", "hedge"),
    ],
)
def test_a_negated_far_is_nearness(prompt: str, entity: str) -> None:
    assert _cues(prompt) == [("near", entity, G, False)]
    assert not interpret_offline(prompt).unparsed


def test_a_far_from_after_a_comma_is_not_negated_by_the_clause_before() -> None:
    assert _cues("not the barn, keep far from the hedge")[-1][:2] == ("far", "hedge")


@pytest.mark.parametrize(
    "prompt, cue",
    [
        ("attract: towpath. falloff 50 m.", ("near", "towpath", 50.0, False)),
        ("barn: repel", ("far", "barn", G, False)),
        ("repulsor: barn, linear falloff, radius 30 m. no hard limits.", ("far", "barn", 30.0, False)),
        ("hedge: ATTRACT, radius 25 m", ("near", "hedge", 25.0, False)),
        (
            "cost should rise with proximity to the silo and fall to the background level beyond 40 m",
            ("far", "silo", 40.0, False),
        ),
        ("an absolute exclusion radius of three metres around the silo", ("far", "silo", 3.0, True)),
        ("keep about twenty five metres from the silo if you can", ("far", "silo", 25.0, False)),
    ],
)
def test_planner_field_words_reaches_and_spoken_numbers(prompt: str, cue: tuple) -> None:
    assert _cues(prompt) == [cue]
    assert not interpret_offline(prompt).unparsed


@pytest.mark.parametrize(
    "prompt, cue",
    [
        ("stay as close to the towpath as you can", ("near", "towpath", G, False)),
        ("keep as far from the silo as the terrain permits", ("far", "silo", G, False)),
    ],
)
def test_an_aim_with_its_preposition_first(prompt: str, cue: tuple) -> None:
    assert _cues(prompt) == [cue]


@pytest.mark.parametrize(
    "prompt, cue",
    [
        # a proximity noun as the subject, priced or rewarded, its reach said after
        ("proximity to the silo is discouraged", ("far", "silo", G, False)),
        (
            "proximity to the kennels is to be penalised more heavily the closer the rover gets",
            ("far", "kennel", G, False),
        ),
        ("silo proximity cost: ramps down to 0 at 14 m", ("far", "silo", 14.0, False)),
        ("kennel proximity penalised", ("far", "kennel", G, False)),
        ("towpath proximity: reward", ("near", "towpath", G, False)),
        ("proximity to the towpath: bonus. within 6 m is best.", ("near", "towpath", 6.0, False)),
        ("minimise proximity(silo). falloff 9 m.", ("far", "silo", 9.0, False)),
        ("pond proximity: the further the better, falloff to neutral at 11 m", ("far", "pond", 11.0, False)),
        (
            "the cost should rise as the rover approaches the kennels, tapering to nothing at 22 m",
            ("far", "kennel", 22.0, False),
        ),
        # kept in sight, close, pulled toward
        ("keep the towpath in view the whole time", ("near", "towpath", G, False)),
        ("keep the canal close", ("near", "canal", G, False)),
        ("bias the rover towards the towpath", ("near", "towpath", G, False)),
        ("the nearer the canal, the cheaper", ("near", "canal", G, False)),
        # terse clearance rules, hard where the sentence says so, soft otherwise
        ("clearance rule: silo >= 4 m, strict", ("far", "silo", 4.0, True)),
        ("HARD clearance(kennels) >= 6 m", ("far", "kennel", 6.0, True)),
        ("kennels: 12 m buffer (hard)", ("far", "kennel", 12.0, True)),
        ("silo standoff 8 m (penalty only, passable)", ("far", "silo", 8.0, False)),
        ("SOFT margin pond 5m (weight low)", ("far", "pond", 5.0, False)),
        # distances bounded after the number, zones in the passive
        ("ideally stay 12 metres or more from the silo", ("far", "silo", 12.0, False)),
        ("a 30 m exclusion zone is to be enforced around the kennels", ("far", "kennel", 30.0, True)),
        ("under no circumstances come within eleven mtrs of the silo", ("far", "silo", 11.0, True)),
    ],
)
def test_graded_and_clearance_constructs_of_sets_10_to_13(prompt: str, cue: tuple) -> None:
    assert _cues(prompt) == [cue]
    assert not interpret_offline(prompt).unparsed, interpret_offline(prompt).unparsed


@pytest.mark.parametrize(
    "prompt, cue",
    [
        # the subject of a keeping verb is the route, not a thing whose preference holds near X
        ("the convoy should remain in the vicinity of the towpath", ("near", "towpath", G, False)),
        ("the rover is required to keep within sight of the canal", ("near", "canal", G, False)),
        ("at no point may the path come within 15 m of the pond", ("far", "pond", 15.0, True)),
    ],
)
def test_a_subject_before_its_keeping_verb_is_the_route(prompt: str, cue: tuple) -> None:
    assert _cues(prompt) == [cue]


def test_a_graded_afterthought_with_its_reach_grades_the_cue_once() -> None:
    prompt = "don't go near the pond: the further from it the better, up to 25 m, beyond which it no longer matters"
    assert _cues(prompt) == [("far", "pond", 25.0, False)]
    assert not interpret_offline(prompt).unparsed


def test_the_shoreline_is_ground_near_the_water() -> None:
    assert _cues("walk the shoreline") == [("near", "water", G, False)]
    assert _cues("shadow the waterline") == [("near", "water", G, False)]


@pytest.mark.parametrize(
    "prompt",
    [
        "order of preference (best first): towpath, meadow, allotment",
        "prefs: towpath; meadow; allotment",
        "Ranking, best first: towpath, meadow, allotment.",
    ],
)
def test_a_ranking_label_orders_its_list_best_first(prompt: str) -> None:
    w = _weights(prompt)
    assert w["towpath"] < w["meadow"] < w["allotment"], w
    assert not interpret_offline(prompt).unparsed
    assert "pref" not in w and "ranking" not in w  # the label is no entity


def test_a_list_after_a_label_with_other_words_is_not_a_ranking() -> None:
    assert normalise("priority: road, then trail; water excluded") == "priority: road, then trail; water excluded"


@pytest.mark.parametrize(
    "prompt, expect",
    [
        (
            "allotment: 0.9\ntowpath: 0.1\nmeadow: 0.5",
            {"allotment": "avoided", "towpath": "preferred", "meadow": "neutral"},
        ),
        ("towpath = 0.2, allotment: 0.8", {"towpath": "preferred", "allotment": "avoided"}),
        ("meadow cost 0.5", {"meadow": "neutral"}),
    ],
)
def test_a_configured_cost_on_the_0_1_scale_is_read_as_that_cost(prompt: str, expect: dict) -> None:
    bands = _bands(prompt)
    assert {k: bands.get(k) for k in expect} == expect, bands
    assert not interpret_offline(prompt).unparsed


def test_a_number_with_a_unit_is_no_cost_and_a_setting_is_reported() -> None:
    assert "towpath" not in _bands("towpath 0.5 km")
    read = interpret_offline("costmap resolution 0.05; meadow: 0.5")
    assert read.unparsed == ("costmap resolution 0.05",)
    assert _bands("costmap resolution 0.05; meadow: 0.5") == {"meadow": "neutral"}


@pytest.mark.parametrize(
    "prompt, cue",
    [
        ("ideally the track would stay 12 metres or more from the kennels", ("far", "kennel", 12.0, False)),
        ("at no point may the path come within 9 m of the pond", ("far", "pond", 9.0, True)),
        ("the route must keep at least 6 m from the silo", ("far", "silo", 6.0, True)),
    ],
)
def test_the_route_named_as_the_subject_is_no_terrain_to_prefer(prompt: str, cue: tuple) -> None:
    """ "the track would stay ..." is the route keeping away, not a track to prefer or avoid."""
    assert _cues(prompt) == [cue]
    bands = _bands(prompt)
    assert bands.get("track") is None and bands.get("path") is None, bands


def test_a_track_that_is_the_object_of_a_preference_is_still_terrain() -> None:
    assert _bands("the track should be preferred").get("track") == "preferred"


# -- set 14's constructs (first contact 2026-12-02), each on phrasings of its own ----------------


@pytest.mark.parametrize(
    "prompt, cue",
    [
        ("keep a minimum lateral clearance of 6 m from the buildings", ("far", "building", 6.0)),
        ("a safe vertical separation of 4 m from the railway", ("far", "railway", 4.0)),
    ],
)
def test_a_word_between_a_minimum_and_its_gap_names_the_gaps_kind_not_an_entity(prompt: str, cue: tuple) -> None:
    got = interpret_offline(prompt)
    assert [(c.kind, c.entity, c.metres) for c in got.cues] == [cue]
    assert not got.unparsed, got.unparsed
    assert {e.name for e in got.entities} & {"lateral", "vertical"} == set()


@pytest.mark.parametrize(
    "prompt, entity, metres",
    [
        ("leave the hedges a bit of room, about 2 m", "hedge", 2.0),
        ("give the water a little space", "water", G),
    ],
)
def test_room_given_to_an_entity_is_a_soft_far_cue(prompt: str, entity: str, metres: float) -> None:
    got = interpret_offline(prompt)
    assert [(c.kind, c.entity, c.metres, c.hard) for c in got.cues] == [("far", entity, metres, False)]
    assert not got.unparsed and "room" not in {e.name for e in got.entities}


def test_a_restatement_of_the_fall_off_is_read_with_its_cue_and_a_contradiction_is_not() -> None:
    assert not interpret_offline("don't go near the pond, the cost decreasing with distance").unparsed
    assert not interpret_offline("stay close to the trail with the bonus fading with distance").unparsed
    # a near cue whose "penalty" falls with distance says the opposite of itself: reported
    assert interpret_offline("stay near the trail, the penalty decreasing with distance").unparsed
    # in a sentence of its own with the reach, after the cue's sentence
    got = interpret_offline("Stay well away from the lake. The cost should fall with distance, negligible past 25 m.")
    assert [(c.kind, c.entity, c.metres) for c in got.cues] == [("far", "lake", 25.0)] and not got.unparsed


def test_a_route_noun_bounded_by_within_is_the_route_not_a_trail() -> None:
    got = interpret_offline("give priority to paths within 20 m of the river")
    assert [(c.kind, c.entity, c.metres) for c in got.cues] == [("near", "river", 20.0)]
    assert "path" not in {e.name for e in got.entities} and not got.unparsed
    assert _weights("give priority to the footpath")["footpath"] < 0.5
    assert _cues("prefer paths near the river")[0][:2] == ("if_near", "path")  # a path near it: a trail


@pytest.mark.parametrize(
    "prompt, words",
    [
        ("Morning team! Please avoid the pond.", "Morning team"),
        ("stay on the trail; the customer needs the files by friday", "customer"),
        ("keep off the grass, there's a match on", "match"),
    ],
)
def test_chatter_about_people_time_files_and_events_is_reported_not_read_as_terrain(prompt: str, words: str) -> None:
    got = interpret_offline(prompt)
    assert any(words.lower() in u.lower() for u in got.unparsed), got.unparsed
    named = {e.name for e in got.entities}
    assert not named & {"team", "customer", "file", "match", "morning"}, named


@pytest.mark.parametrize(
    "prompt, expect",
    [
        ("stay neer the trail", ("near", "trail")),
        ("don't go neer the pond", ("far", "pond")),
    ],
)
def test_one_vowel_typed_for_another_in_a_short_keeping_word_is_corrected(prompt: str, expect: tuple) -> None:
    assert [c[:2] for c in _cues(prompt)] == [expect]
    assert _weights("stey off the grass")["grass"] > 0.5


def test_a_vowel_slip_never_turns_a_real_word_into_another() -> None:
    assert lx.correct_phrase_word("fuel") is None and lx.correct_phrase_word("lake") is None
    assert lx.correct_phrase_word("neer") == "near"


@pytest.mark.parametrize("prompt", ["walk the riverside, but nobody goes into the river", "follow the creekside"])
def test_a_water_side_word_is_ground_beside_the_water(prompt: str) -> None:
    assert ("near", "water") in [c[:2] for c in _cues(prompt)]


def test_nobody_going_in_avoids_and_nobody_needing_to_avoid_permits() -> None:
    assert _weights("nobody walks on the grass")["grass"] > 0.5
    assert _weights("nobody has to avoid the sheds")["shed"] == 0.5


@pytest.mark.parametrize(
    "prompt, entity",
    [
        ("the hedges need not be avoided", "hedge"),
        ("the sheds needn't be avoided", "shed"),
    ],
)
def test_a_passive_permission_lifts_the_prior(prompt: str, entity: str) -> None:
    assert _weights(prompt)[entity] == 0.5


@pytest.mark.parametrize("prompt", ["trail only", "only the trail, please", "trail only where possible"])
def test_only_next_to_a_name_prefers_it(prompt: str) -> None:
    assert _weights(prompt)["trail"] < 0.5 and not interpret_offline(prompt).unparsed


def test_only_away_from_a_name_is_a_plain_word() -> None:
    assert not interpret_offline("hedge standoff 4 m (penalty only, passable)").unparsed


@pytest.mark.parametrize(
    "prompt, entity",
    [("cut across the lawn if it's quicker", "lawn"), ("cut through the hedge if it's shorter", "hedge")],
)
def test_a_way_allowed_where_it_helps_is_permitted_not_preferred(prompt: str, entity: str) -> None:
    assert _weights(prompt)[entity] == 0.5 and not interpret_offline(prompt).unparsed


def test_that_bit_stands_for_the_entity_named_last_even_an_excepted_one() -> None:
    w = _weights("The lawn is fine, except the cricket pitch. Avoid that part.")
    assert w["cricket pitch"] > 0.5 and w["lawn"] == 0.5


@pytest.mark.parametrize("prompt", ["sealed > unsealed", "tarmac: good. unsealed: bad"])
def test_a_bare_qualifier_names_its_qualified_kind(prompt: str) -> None:
    w = _weights(prompt)
    assert w["paved road"] < w["unpaved road"], w


def test_keeping_out_of_a_railway_corridor_forbids_the_railway_and_prefers_no_band_beside_it() -> None:
    got = interpret_offline("The grass is fine. Keep out of the railway corridor.")
    assert not got.cues and next(p for p in got.preferences if p.entity == "railway").lethal


def test_a_watercourse_is_water() -> None:
    assert lx.KNOWN_BY_NAME["river"].parent == "water" and ("watercourse",) in lx.SURFACE


def test_a_clause_that_only_states_a_situation_takes_no_neighbours_tier() -> None:
    """ "roads blocked for repairs" says what state the road is in; it is not a bare list
    waiting for the next clause's "off limits"."""
    w = _weights("crossing the road is fine today, roads blocked for repairs, but the pond is off limits")
    assert w["road"] == 0.5 and w["pond"] == 1.0


def test_a_gap_noun_written_with_a_hyphen_is_that_noun() -> None:
    from overseec_core.interpret.tokens import tokenize

    assert [t.word for t in tokenize("a stand-off of 12 m; a set-back; a no-go zone")][:8] == [
        "a",
        "standoff",
        "of",
        "12",
        "m",
        ";",
        "a",
        "setback",
    ]
    assert _cues("keep a stand-off of 12 m from the railway")[0][:3] == ("far", "railway", 12.0)


def test_a_buffer_worded_as_absolute_without_a_number_keeps_out_the_default_distance() -> None:
    """A buffer is a zone by name; "never go near" names none and stays graded."""
    assert _cues("a setback from the hedges is mandatory") == [("far", "hedge", lx.DEFAULT_CUE_DISTANCE_M, True)]
    assert _cues("never go near the pond") == [("far", "pond", G, False)]


# ----------------------------------------------------------------------------- set 15's constructs


@pytest.mark.parametrize(
    "prompt, first, last",
    [
        ("1. trail  2. meadow  3. marsh", "trail", "wetland"),
        ("Ranking\n1) meadow\n2) sand\n3) trail", "meadow", "trail"),
    ],
)
def test_a_numbered_list_of_names_is_a_ranking_best_first(prompt: str, first: str, last: str) -> None:
    w = _weights(prompt)
    assert w[first] < 0.5 and w[first] < w[last]
    assert normalise(prompt).count(">") == 2  # the markers became steps; length kept
    assert len(normalise(prompt)) == len(prompt)


def test_a_numbered_list_of_instructions_stays_as_written() -> None:
    assert normalise("1. stay on the trail 2. avoid the marsh") == "1. stay on the trail 2. avoid the marsh"


@pytest.mark.parametrize(
    "prompt, entity, metres",
    [
        ("nobody goes closer than 8 m to the barn", "barn", 8.0),
        ("do not get any nearer then 12 m to the pylons", "electric tower", 12.0),
        ("stay at least 6 m from all of the sheds", "shed", 6.0),
    ],
)
def test_a_negated_bound_is_the_rules_own_negation(prompt: str, entity: str, metres: float) -> None:
    assert ("far", entity, metres, True) in _cues(prompt)
    assert not interpret_offline(prompt).unparsed


@pytest.mark.parametrize(
    "prompt, kind, entity, metres, hard",
    [
        ("pond: >= 4 m clearance", "far", "pond", 4.0, None),
        ("fence: 3 m min", "far", "fence", 3.0, True),
        ("trail: 30 m max", "near", "trail", 30.0, True),
        ("keep ≥ 7 m from the hedge", "far", "hedge", 7.0, True),
        ("pond: aim for 9 m clearance, not strict", "far", "pond", 9.0, False),
        ("hedge buffer ~4 m preferred, can violate it", "far", "hedge", 4.0, False),
    ],
)
def test_a_topics_distance_with_its_bound_or_mark(prompt: str, kind: str, entity: str, metres: float, hard) -> None:
    cue = next(c for c in _cues(prompt) if c[1] == entity)
    assert cue[:3] == (kind, entity, metres)
    assert hard is None or cue[3] is hard
    assert not interpret_offline(prompt).unparsed


def test_a_compound_ending_in_a_qualified_kind_finds_that_kind() -> None:
    layers = ["paved road", "unpaved road"]
    assert match_entity("smooth asphalt road", layers).layers == ("paved road",)
    assert match_entity("rutted unpaved road", layers).layers == ("unpaved road",)
    assert match_entity("surfaced road", layers).layers == ("paved road",)
    assert match_entity("non paved road", layers).layers != ("paved road",)
    assert match_entity("oak", ["deciduous tree", "conifer tree"]).layers == ("deciduous tree",)
    assert match_entity("fir", ["deciduous tree", "conifer tree"]).layers == ("conifer tree",)


def test_too_something_for_the_mission_avoids_the_subject_and_names_nothing() -> None:
    w = _weights("walk under the birches, the larch plantation is far too thick")
    assert w["deciduous tree"] < 0.5 < w["conifer tree"]
    assert "thick" not in w
    assert "muddy canal" in {e.name for e in interpret_offline("avoid the muddy canal").entities}


def test_a_negation_after_a_comma_about_another_entity_is_that_entitys() -> None:
    bands = _bands("follow the canal where you can, and never cross the railway")
    assert bands["canal"] == "preferred"
    assert ("no_cross", "railway", None, True) in _cues("follow the canal where you can, and never cross the railway")
    assert _bands("walk along the canal bank, but never in the canal")["canal"] == "lethal"  # the canal's own


def test_a_negated_beside_word_prefers_no_band() -> None:
    assert not any(c[0] == "near" for c in _cues("never drive along the edge of the lake"))


def test_dont_go_in_forbids_as_dont_go_into_does() -> None:
    assert _bands("don't go in the pond")["pond"] == "lethal"
    assert _bands("skirt the marsh, dont go in it")["wetland"] == "lethal"


def test_crossing_x_never_is_the_nocross_rule() -> None:
    assert ("no_cross", "railway", None, True) in _cues("x-ing tracks: never")
    assert ("no_cross", "road", None, True) in _cues("crossing the road: never")
    assert _bands("road: never")["road"] == "lethal"


def test_negated_nearness_keeps_away() -> None:
    assert ("far", "hedge", G, False) in _cues("no driving right up next to the hedge")


def test_keeping_clear_worded_as_absolute_is_a_zone_of_the_default_distance() -> None:
    assert ("far", "pond", lx.DEFAULT_CUE_DISTANCE_M, True) in _cues("keep clear of the pond at all times")
    assert _cues("keep clear of the pond") == [("far", "pond", G, False)]


@pytest.mark.parametrize(
    "prompt, kind",
    [("keep well away from the riverbank", "far"), ("stay near the shoreline", "near")],
)
def test_a_water_side_word_after_a_distance_word_is_the_water(prompt: str, kind: str) -> None:
    assert _cues(prompt) == [(kind, "water", G, False)]
    assert "water" not in _bands(prompt)  # the shore is ground by the water, no tier on the water


def test_terse_away_and_more_distance() -> None:
    assert _cues("away from the pond, more distance = better") == [("far", "pond", G, False)]


def test_a_graded_reach_said_as_out_to_a_distance() -> None:
    assert _cues("closeness to the pond should be penalised progressively out to a distance of 25 m") == [
        ("far", "pond", 25.0, False)
    ]
    assert _cues("hedge: avoid, closer = worse, 12m") == [("far", "hedge", 12.0, False)]


def test_room_between_you_and_it_and_slack_said_as_chat() -> None:
    assert _cues("leave some room between you and the hedge") == [("far", "hedge", G, False)]
    prompt = "give the barn perhaps 15 m, but it's not the end of the world if you cut a bit closer"
    assert _cues(prompt) == [("far", "barn", 15.0, False)]
    assert not interpret_offline(prompt).unparsed


def test_go_round_avoids_and_go_under_the_trees_prefers() -> None:
    assert _bands("prefer the trail, go round the pond")["pond"] == "avoided"
    assert _bands("go under the trees")["tree"] == "preferred"


def test_an_aside_between_a_negation_and_its_on_keeps_the_beside_reading() -> None:
    prompt = "head along the canal, parallel to it, without at any point driving in the canal itself"
    assert _bands(prompt)["canal"] in ("avoided", "lethal")
    assert any(c[0] == "near" and c[1] == "canal" for c in _cues(prompt))


def test_imposing_no_constraint_lifts_the_prior() -> None:
    assert _weights("the hedges impose no constraint on the drone")["hedge"] == 0.5


def test_a_verdict_after_a_name_is_that_names_own_not_a_chain_label() -> None:
    w = _weights("gravel preferred > sand avoided")
    assert w["unpaved road"] < 0.5 < w["sand"]


# ----------------------------------------------------------------------------- set 16's constructs
@pytest.mark.parametrize(
    ("prompt", "cues"),
    [
        ("building -> keep 5m, HARD", [("far", "building", 5.0, True)]),
        ("building: soft 2m", [("far", "building", 2.0, False)]),
        ("road: keep ~8 m if possible", [("far", "road", 8.0, False)]),
        ("water: keep >= 12 m, mandatory", [("far", "water", 12.0, True)]),
        ("trail: within 20 m", [("near", "trail", 20.0, False)]),
    ],
)
def test_a_topic_line_with_a_distance_is_a_clearance_rule(prompt: str, cues: list) -> None:
    assert _cues(prompt) == cues
    assert not interpret_offline(prompt).unparsed


def test_a_heading_says_how_strict_the_lines_under_it_are() -> None:
    prompt = "HARD LIMITS\nwater: 5 m\nrailway: 10 m"
    assert _cues(prompt) == [("far", "water", 5.0, True), ("far", "railway", 10.0, True)]
    assert not interpret_offline(prompt).unparsed
    # after a rule it qualifies that rule, as before
    assert _cues("Keep 20 m from the railway. No exceptions.") == [("far", "railway", 20.0, True)]


def test_a_ranking_label_with_its_order_said() -> None:
    w = _weights("Surface preference, in descending order: trail, road, grass.")
    assert w["trail"] < w["road"] < w["grass"]
    w = _weights("route preference (most preferred first): trail; road; grass")
    assert w["trail"] < w["road"] < w["grass"]


def test_a_crossing_the_verdict_forbids_is_the_never_cross_rule() -> None:
    for prompt in ("Crossing the railway is prohibited.", "cross(railway) = never"):
        assert ("no_cross", "railway", None, True) in _cues(prompt), prompt
    assert _bands("crossing the road is fine")["road"] == "neutral"


def test_permissions_said_as_not_avoiding_alike_or_grand() -> None:
    assert _weights("we're NOT avoiding the vegetation this time")["vegetation"] == 0.5
    w = _weights("The road and the grass are to be treated alike.")
    assert w["road"] == w["grass"] == 0.5
    assert _weights("paved is grand, gravel is off limits")["paved road"] == 0.5
    assert _bands("the baseball field is not to be entered")["baseball field"] == "lethal"


def test_a_bracketed_aside_is_read_on_its_own() -> None:
    interp = interpret_offline("tree: ALLOWED (crowns are high, rover fits under)")
    assert {p.entity: p.weight for p in interp.preferences if p.phrase} == {"tree": 0.5}
    assert "crowns are high" in interp.unparsed
    # a bracketed qualifier stays with its rule
    assert _weights("the dirt roads (unpaved) are off limits")["unpaved road"] == 1.0


def test_keeping_back_from_is_keeping_away() -> None:
    assert _cues("keep waaay back from the railway tracks")[0][:2] == ("far", "railway")
    assert _cues("stay well back from the water")[0][:2] == ("far", "water")


def test_nothing_within_a_distance_keeps_out_and_full_stop_is_emphasis() -> None:
    prompt = "nothing within 12 m of the railway track, full stop"
    assert _cues(prompt) == [("far", "railway", 12.0, True)]
    assert not interpret_offline(prompt).unparsed
    assert _cues("stay within 12 m of the road") == [("near", "road", 12.0, True)]


def test_a_distance_named_without_its_number_is_a_zone_when_absolute() -> None:
    hard = _cues("keep a stone's throw from the building at all times")
    assert len(hard) == 1 and hard[0][:2] == ("far", "building") and hard[0][3] is True
    assert _cues("keep a safe distance from the building")[0][3] is False
    assert _cues("remain a stone's throw from the railway")[0][:2] == ("far", "railway")


def test_keeping_away_from_a_topic_is_its_graded_far_cue() -> None:
    for prompt in ("water: keep well away\ntrail: prefer", "railway -> stay clear"):
        interp = interpret_offline(prompt)
        assert [(c.kind, c.entity, c.hard) for c in interp.cues][0][0] == "far", prompt
        assert not interp.unparsed, prompt
    assert _cues("water: keep well away")[0][1] == "water"


@pytest.mark.parametrize(
    "prompt, entity, metres",
    [
        ("HARD water >= 12m", "water", 12.0),
        ("strict: dist(route, lake) >= 30 m", "lake", 30.0),
        ("house: min_clearance=8m (hard)", "house", 8.0),
    ],
)
def test_symbolic_bounds_are_hard_rules_with_their_number(prompt: str, entity: str, metres: float) -> None:
    assert ("far", entity, metres, True) in _cues(prompt)
    assert not interpret_offline(prompt).unparsed


def test_a_comparison_of_costs_ranks_the_cheaper_first() -> None:
    w = _weights("cost(road) < cost(grass) < cost(scrub)")
    assert w["road"] < w["grass"] < w["bush"]
    w = _weights("cost(scrub) > cost(grass)")  # the same order written the other way
    assert w["grass"] < w["bush"]


def test_signs_after_a_mark_are_verdicts_and_a_plus_between_names_joins() -> None:
    bands = _bands("trail: ++\nmarsh: --")
    assert bands["trail"] == "preferred" and bands["wetland"] == "avoided"
    assert _bands("grass + trail: ok") == {"grass": "neutral", "trail": "neutral"}
    assert _cues("prefer 15 m+ from the barn when possible")[0][:3] == ("far", "barn", 15.0)  # a bound, not "and"


@pytest.mark.parametrize(
    "prompt, metres",
    [
        ("keep away from the pond, the penalty dying away to nothing by 25 m", 25.0),
        ("cost should rise steadily as the rover nears the pond and fade out completely beyond 18 m", 18.0),
        ("the pond: the closer the harsher the penalty, tapering off past 35 m", 35.0),
    ],
)
def test_a_fall_off_ends_where_its_words_say(prompt: str, metres: float) -> None:
    cues = _cues(prompt)
    assert [c[:3] for c in cues] == [("far", "pond", metres)], cues
    assert not interpret_offline(prompt).unparsed


def test_a_correlative_reads_the_quantity_it_grows() -> None:
    assert _cues("the nearer the rover gets to the fence the heavier the cost")[0][:2] == ("far", "fence")
    assert _cues("the closer to the hedge the bigger the reward")[0][:2] == ("near", "hedge")
    assert _cues("the further from the ditch the smaller the cost")[0][:2] == ("far", "ditch")


def test_an_aim_with_no_object_grades_what_the_clause_keeps_away_from() -> None:
    interp = interpret_offline("keep away from the quarry, as far as you can")
    assert [(c.kind, c.entity, c.hard) for c in interp.cues] == [("far", "quarry", False)]
    assert not interp.unparsed
    assert _cues("hug the hedge as tightly as possible")[0][:2] == ("near", "hedge")


def test_a_last_resort_is_dearer_than_what_is_used_if_needed() -> None:
    w = _weights("grass first, then scrub if necessary, the marsh only as a last resort")
    assert w["grass"] < 0.5 < w["bush"] < w["wetland"] < lx.AVOID
    w = _weights("prefs: trail > road > grass; marsh = last resort")
    assert max(w["trail"], w["road"], w["grass"]) < w["wetland"]


def test_no_concern_is_a_permission_and_freely_is_allowed_not_sought() -> None:
    for prompt in ("don't worry about the buildings", "the barns are nothing to worry about"):
        interp = interpret_offline(prompt)
        assert {p.band for p in interp.preferences if p.phrase} == {"neutral"}, prompt
        assert not any("worry" in p.entity for p in interp.preferences), prompt
    assert _bands("never cross the railway; you may drive over the grass freely")["grass"] == "neutral"


def test_preferred_over_prefers_its_left_side() -> None:
    bands = _bands("gravel roads are to be preferred over tarmac, which should be avoided")
    assert bands["unpaved road"] == "preferred" and bands["paved road"] == "avoided"


def test_unlabelled_ground_anchors_an_ordering_at_neutral() -> None:
    w = _weights("tarmac > gravel > off-road")
    assert w["paved road"] < w["unpaved road"] < 0.5
    w = _weights("trail > open ground > scrub > marsh")
    assert w["trail"] < 0.5 < w["bush"] < w["wetland"]


def test_a_word_that_is_never_terrain_is_no_misspelt_entity() -> None:
    interp = interpret_offline("avoid the railway, the trains run hourly")
    assert "trail" not in {p.entity for p in interp.preferences if p.phrase}
    assert _bands("the non-paved road is bad for the wheels")["unpaved road"] == "avoided"


def test_a_key_that_carries_its_unit_and_a_comment_that_hardens_it() -> None:
    assert _cues("standoff.pond.min_ft = 30  # do not relax") == [("far", "pond", 30 * 0.3048, True)]
    assert _cues("hedge.soft_gap_m: 4")[0][:3] == ("far", "hedge", 4.0)
    assert not interpret_offline("standoff.pond.min_ft = 30  # do not relax").unparsed


def test_a_topic_with_an_aim_or_a_labelled_nearness_is_graded() -> None:
    assert _cues("pylons: as far away as you can")[0][:2] == ("far", "electric tower")
    assert _cues("keep_near: the hedge")[0][:2] == ("near", "hedge")


def test_closed_to_us_forbids_and_the_rest_anchors_an_ordering() -> None:
    assert _bands("the farm track is closed to vehicles")["trail"] == "lethal"
    w = _weights("trail > scrub > anything else")
    assert w["trail"] < w["bush"] < 0.5


def test_room_left_between_us_and_a_thing_is_a_soft_zone_and_slack_is_read() -> None:
    prompt = "leave 3 m or so between the rover and the hedge, no big deal if you can't"
    assert _cues(prompt) == [("far", "hedge", 3.0, False)]
    assert not interpret_offline(prompt).unparsed


def test_going_straight_over_is_allowed_not_sought() -> None:
    assert _bands("the pond is frozen, just drive straight across it")["pond"] == "neutral"
    assert _bands("go through the meadow")["meadow"] == "preferred"  # a route sought out stays preferred


def test_a_chat_n_after_a_comma_is_and_and_a_best_bet_is_preferred() -> None:
    bands = _bands("meadow before scrub, n keep out of the pond")
    assert bands["pond"] == "lethal" and bands.get("meadow") != "lethal"
    assert _bands("gravel roads are our best bet")["unpaved road"] == "preferred"


def test_a_denied_presence_within_a_distance_is_a_hard_zone() -> None:
    for prompt in (
        "Condition 2.1: no machinery or staff within 15 m of the pond at any time.",
        "no vehicle traffic is allowed within 40 ft of the hedge under any circumstances",
    ):
        interp = interpret_offline(prompt)
        assert [(c.kind, c.hard) for c in interp.cues] == [("far", True)], prompt
        assert not interp.unparsed, prompt
        assert not [p for p in interp.preferences if p.phrase], prompt  # the staff are no terrain
    assert _cues("stay within 10 m of the hedge") == [("near", "hedge", 10.0, True)]


def test_a_minimum_after_the_number_and_a_buffer_that_applies_are_hard() -> None:
    assert _cues("Setback: 20 ft minimum from the pond. No waivers will be granted.") == [
        ("far", "pond", 20 * 0.3048, True)
    ]
    assert _cues("an exclusion buffer extends around the silo")[0][:2] == ("far", "silo")


def test_a_clearance_with_no_topic_is_about_the_topic_before() -> None:
    assert _cues("Silo: keep out. Min sep 8 m, hard.") == [("far", "silo", 8.0, True)]
    assert interpret_offline("Buffer 10 m.").cues == ()  # with nothing before, it is not read


def test_the_side_of_a_thing_not_on_it_is_beside_it() -> None:
    interp = interpret_offline("walk along the side of the hedge, not on top of it")
    assert ("near", "hedge") in [(c.kind, c.entity) for c in interp.cues]
    assert _bands("walk along the side of the hedge, not on top of it")["hedge"] == "avoided"
    assert ("side", "road") in [(c.kind, c.entity) for c in interpret_offline("stay on the side of the road").cues]


def test_the_generic_name_itself_is_the_kind_named_before() -> None:
    interp = interpret_offline("drive along the verge of the paved road; the road itself is off limits")
    assert _bands("drive along the verge of the paved road; the road itself is off limits")["paved road"] == "lethal"
    assert "road" not in {p.entity for p in interp.preferences if p.phrase}


def test_numbered_items_in_brackets_rank_and_rule_labels_are_names() -> None:
    w = _weights("Preference order: (1) meadow, (2) scrub, (3) marsh")
    assert w["meadow"] < w["bush"] < w["wetland"]
    assert not interpret_offline("Rule 4.1: avoid the marsh").unparsed


def test_an_infinitive_after_to_is_no_comparison() -> None:
    w = _weights("prefer the meadow and try not to use the pond")
    assert w["meadow"] < 0.5 < w["pond"]
    assert _weights("prefer the meadow to the marsh")["meadow"] < _weights("prefer the meadow to the marsh")["wetland"]


def test_a_comparison_does_not_reach_back_into_the_one_before() -> None:
    w = _weights("the meadow is better than scrub, and the trail is better than the meadow")
    assert w["trail"] < w["meadow"] < w["bush"]
    notes = interpret_offline("the meadow is better than scrub, and the trail is better than the meadow").notes
    assert not any("conflicting statements" in n for n in notes)


def test_regional_road_names_and_uses_allowed_only_as_a_last_resort() -> None:
    bands = _bands("Kindly use the pakka road. Kachcha road is to be used only if no other option is there.")
    assert bands["paved road"] == "preferred" and _weights("kachcha road only as a last resort")["unpaved road"] > 0.6
    w = _weights("ply the tarred road; untarred road only when there is no other way")
    assert w["unpaved road"] == lx.LAST_RESORT


def test_permission_by_likeness_or_by_being_passable_enough() -> None:
    assert _bands("the spur line closed long ago, treat it like any other ground")["railway"] == "neutral"
    bands = _bands("the hedge is thin enough to drive through; the meadow is better than the hedge")
    assert bands["hedge"] == "neutral" and bands["meadow"] == "preferred"


def test_room_around_a_thing_a_full_distance_and_a_reach_where_it_stops_mattering() -> None:
    assert _cues("leave some room around the silo, say 6 m") == [("far", "silo", 6.0, False)]
    assert ("far", "pond", 12.0, True) in _cues("keep a full 12 m from the pond at all times")
    assert not interpret_offline("keep a full 12 m from the pond at all times").unparsed
    cues = _cues("The closer to the silo, the worse; beyond 25 m it no longer matters.")
    assert cues == [("far", "silo", 25.0, False)]


def test_a_lone_edge_before_a_negated_thing_is_beside_it() -> None:
    interp = interpret_offline("Ride the verge, not the lane.")
    assert ("near", "road") in [(c.kind, c.entity) for c in interp.cues] and not interp.unparsed
    assert _bands("Ride the verge, not the lane.")["road"] == "avoided"
    beside = interpret_offline("go alongside the hedge on the meadow edge, never on the hedge itself")
    assert _bands("go alongside the hedge on the meadow edge, never on the hedge itself")["hedge"] == "lethal"
    assert ("near", "hedge") in [(c.kind, c.entity) for c in beside.cues]
