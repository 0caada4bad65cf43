"""Second held-out mission-language set (issue 20): prompts nobody has tuned the interpreter against.

The first held-out set (tests/mission_prompts_heldout.py) has since been used to fix the offline
interpreter, so it is now a second training set and its pass rate overstates how well missions
the interpreter has never seen are read. These prompts are new and untouched: written without
reading the interpreter's phrase tables (``interpret/offline.py``, ``interpret/lexicon.py``) and
without reading the earlier corpora beyond their format, in the voices of the people who type
missions: a GIS analyst in QGIS, a robotics engineer writing a brief, a field operator on a phone
(short, lower case, typos), a non-native English speaker. They use the same nine phrasing
families, the same :class:`Case` type and the same expectation kinds and checks
(``mission_prompts.check_case``); see that module's docstring for what each expectation means and
the README "What the costs mean" for the cost scale the expectations follow.

This is a MEASUREMENT, not a gate: ``bench/mission_language_report.py --heldout2`` prints the pass
rate per family; the tests only check the set's format (size, families, novelty, well-formed
expectations). Do not edit a prompt or its expectation to make the interpreter pass, and do not
tune the interpreter against these prompts. Add a third set instead, and retire a case only where
its expectation contradicts the cost-scale contract, saying so in :data:`DOUBTFUL`.
"""

from __future__ import annotations

from pathlib import Path

from .mission_prompts import NB_LAYERS, SAMPLE_LAYERS, C, Case, literal_prompts

MIN_CASES = 50
MIN_PER_FAMILY = 5

#: Files whose prompts (every string literal in them) this set must not repeat.
NOT_FROM = (
    "tests/mission_prompts.py",
    "tests/mission_prompts_heldout.py",
    "tests/invariants_data.py",
    "tests/interpret/*.py",
)

HELDOUT2: list[Case] = [
    # ------------------------------------------------------------------ 1. negation over motion verbs
    C(
        "The rover must not get off the footpath until it reaches the gate.",
        "negation_motion",
        ("path", "grass", "tree", "building", "water"),
        (("preferred", "path"), ("not_lethal", "grass")),
        why="'must not get off' = stay on; the footpath is the path layer",
    ),
    C(
        "dont stray off the lane pls",
        "negation_motion",
        ("road", "grass", "tree", "building"),
        (("preferred", "road"),),
    ),
    C(
        "At no point may the robot leave the sidewalk.",
        "negation_motion",
        ("sidewalk", "road", "grass", "building"),
        (("preferred", "sidewalk"), ("not_lethal", "road"), ("not_lethal", "grass")),
        why="'at no point may ... leave' = stay on the sidewalk; nothing else becomes lethal",
    ),
    C(
        "Keep the vehicle off the lawns.",
        "negation_motion",
        ("grass", "road", "building", "tree"),
        (("avoided", "grass"), ("not_lethal", "grass")),
    ),
    C(
        "Stay away from the crops and do not leave the dirt road.",
        "negation_motion",
        ("farmland", "road", "grass", "building"),
        (("avoided", "farmland"), ("preferred", "road"), ("below", "road", "farmland")),
    ),
    C(
        "no leaving the trail, and keep out of the mud",
        "negation_motion",
        ("trail", "mud", "grass", "tree"),
        (("preferred", "trail"), ("avoided", "mud"), ("not_lethal", "mud")),
    ),
    C(
        "Mission brief: the UGV is not to depart from the gravel track between waypoints 3 and 7.",
        "negation_motion",
        ("trail", "grass", "tree", "building"),
        (("preferred", "trail"),),
        why="'is not to depart from' = stay on; a gravel track is an unpaved trail (no railway in the layers)",
    ),
    # ------------------------------------------------------------------ 2. last resort
    C(
        "Use the sidewalks; crossing the lawn is a last resort.",
        "last_resort",
        ("sidewalk", "grass", "road", "building"),
        (("preferred", "sidewalk"), ("avoided", "grass"), ("below", "sidewalk", "grass")),
    ),
    C(
        "Meadows first, the gravel road only if there is no other option.",
        "last_resort",
        ("grass", "road", "tree", "water"),
        (("preferred", "grass"), ("avoided", "road"), ("not_lethal", "road")),
        why="'only if there is no other option' is a last resort in other words",
    ),
    C(
        "Take the paths. Bushes if you have to, but that's the last resort.",
        "last_resort",
        ("path", "shrub", "grass", "building"),
        (("preferred", "path"), ("avoided", "shrub"), ("below", "path", "shrub")),
    ),
    C(
        "Last resort: the creek bed. Otherwise stick to the trail.",
        "last_resort",
        ("trail", "water", "grass", "tree"),
        (("preferred", "trail"), ("avoided", "water"), ("not_lethal", "water")),
    ),
    C(
        "prefer the farm tracks, fields are a last resort and the barns are a no-go",
        "last_resort",
        ("trail", "farmland", "building", "road"),
        (("preferred", "trail"), ("avoided", "farmland"), ("not_lethal", "farmland"), ("lethal", "building")),
    ),
    C(
        "In the worst case you may cut through the woods, otherwise keep to the roads.",
        "last_resort",
        ("road", "forest", "grass", "building"),
        (("preferred", "road"), ("avoided", "forest"), ("not_lethal", "forest")),
        why="'in the worst case you may' is a last resort, not a plain permission",
    ),
    C(
        "the parking lot is our last resort, go around it if at all possible",
        "last_resort",
        ("parking lot", "road", "grass", "building"),
        (("avoided", "parking lot"), ("not_lethal", "parking lot")),
    ),
    # ------------------------------------------------------------------ 3. comparatives
    C("Gravel is better than mud.", "comparative", ("gravel", "mud", "grass", "road"), (("below", "gravel", "mud"),)),
    C(
        "i'd rather go through the meadow than the forest",
        "comparative",
        ("grass", "forest", "road", "building"),
        (("below", "grass", "forest"),),
    ),
    C("Sand over mud, always.", "comparative", ("sand", "mud", "road", "water"), (("below", "sand", "mud"),)),
    C(
        "Driving through the field is less risky than going through the woods.",
        "comparative",
        ("field", "forest", "road", "building"),
        (("below", "field", "forest"),),
    ),
    C(
        "Prefer the path to the grass, and the grass to the bushes.",
        "comparative",
        ("path", "grass", "shrub", "building"),
        (("below", "path", "grass"), ("below", "grass", "shrub")),
        why="'prefer A to B' twice: a chain path < grass < shrub",
    ),
    C(
        "Dirt tracks are worse than paved roads but better than the crops.",
        "comparative",
        ("trail", "road", "farmland", "building"),
        (("below", "road", "trail"), ("below", "trail", "farmland")),
    ),
    C(
        "the sidewalk is safer than the road for the robot",
        "comparative",
        ("sidewalk", "road", "grass", "building"),
        (("below", "sidewalk", "road"),),
    ),
    C(
        "Better to take the lane than to drive across the field.",
        "comparative",
        ("road", "field", "tree", "building"),
        (("below", "road", "field"),),
    ),
    # ------------------------------------------------------------------ 4. conditions
    C(
        "Driving on grass is acceptable unless it's right beside the river.",
        "condition",
        ("grass", "water", "road", "building"),
        (("near_above_far", "grass", "water"), ("far_band", "grass", "water", "neutral")),
    ),
    C(
        "The road you should avoid, except when near to the bridge.",
        "condition",
        ("road", "bridge", "grass", "water"),
        (("far_band", "road", "bridge", "avoided"), ("near_below_far", "road", "bridge")),
    ),
    C(
        "you can drive on the fields as long as you're not next to the houses",
        "condition",
        ("field", "building", "road", "tree"),
        (("near_above_far", "field", "building"), ("far_band", "field", "building", "neutral")),
    ),
    C(
        "Stay off the sand, unless you're close to the parking lot.",
        "condition",
        ("sand", "parking lot", "road", "grass"),
        (("far_band", "sand", "parking lot", "avoided"), ("near_below_far", "sand", "parking lot")),
    ),
    C(
        "Paths are OK except where they run next to the railway.",
        "condition",
        ("path", "railway", "grass", "building"),
        (("near_above_far", "path", "railway"), ("far_band", "path", "railway", "neutral")),
    ),
    C(
        "meadow ok but not near the pond",
        "condition",
        ("grass", "water", "trail", "tree"),
        (("near_above_far", "grass", "water"), ("far_band", "grass", "water", "neutral")),
    ),
    C(
        "Avoid driving on the lawn except close to the sheds.",
        "condition",
        ("grass", "building", "path", "tree"),
        (("far_band", "grass", "building", "avoided"), ("near_below_far", "grass", "building")),
    ),
    # ------------------------------------------------------------------ 5. scope of off limits / no-go / never
    C(
        "The lake is off limits; the meadow and the trail are both fine.",
        "scope",
        ("water", "grass", "trail", "tree"),
        (("lethal", "water"), ("neutral", "grass"), ("neutral", "trail")),
    ),
    C(
        "Prefer the road. Railway tracks are a no-go.",
        "scope",
        ("road", "railway", "grass", "building"),
        (("preferred", "road"), ("lethal", "railway"), ("not_lethal", "grass"), ("not_lethal", "building")),
    ),
    C(
        "never enter the buildings, but the parking lot and the lawns are ok",
        "scope",
        ("building", "parking lot", "grass", "road"),
        (("lethal", "building"), ("neutral", "parking lot"), ("neutral", "grass")),
    ),
    C(
        "the canal is off-limits and try to stay on the towpath",
        "scope",
        ("water", "path", "grass", "tree"),
        (("lethal", "water"), ("preferred", "path"), ("not_lethal", "grass"), ("not_lethal", "tree")),
        why="a towpath is the path along a canal; 'off-limits' reaches only the canal",
    ),
    C(
        "Do not ever enter the forest. Crossing the stream is fine though.",
        "scope",
        ("forest", "water", "grass", "road"),
        (("lethal", "forest"), ("neutral", "water"), ("not_lethal", "grass")),
    ),
    C(
        "Avoid the crops; the greenhouse is off limits.",
        "scope",
        ("farmland", "building", "road", "grass"),
        (("avoided", "farmland"), ("not_lethal", "farmland"), ("lethal", "building")),
        why="a greenhouse is a building; off limits reaches it only, the crops are merely avoided",
    ),
    C(
        "Sand is a no-go area but mud and gravel are ok.",
        "scope",
        ("sand", "mud", "gravel", "road"),
        (("lethal", "sand"), ("neutral", "mud"), ("neutral", "gravel")),
    ),
    # ------------------------------------------------------------------ 6. no_cross
    C(
        "Do not cross the creek, find another way around.",
        "no_cross",
        ("water", "grass", "trail", "tree"),
        (("no_cross", "water"), ("avoided", "water"), ("not_lethal", "water")),
    ),
    C(
        "The rover shall never cross the rail line.",
        "no_cross",
        ("railway", "road", "grass", "building"),
        (("no_cross", "railway"), ("avoided", "railway"), ("not_lethal", "railway")),
    ),
    C(
        "try not to cross the canal if you can help it",
        "no_cross",
        ("water", "path", "grass", "building"),
        (("no_no_cross", "water"), ("avoided", "water"), ("not_lethal", "water")),
    ),
    C(
        "Avoid crossing the main road.",
        "no_cross",
        ("road", "sidewalk", "grass", "building"),
        (("no_no_cross", "road"), ("avoided", "road")),
    ),
    C(
        "The robot must not cross the stream; follow the footpath on this side.",
        "no_cross",
        ("water", "path", "grass", "tree"),
        (("no_cross", "water"), ("preferred", "path"), ("not_lethal", "water")),
    ),
    C(
        "do NOT cross the tracks!!",
        "no_cross",
        ("railway", "road", "grass", "building"),
        (("no_cross", "railway"), ("not_lethal", "railway")),
        why="'the tracks' in a crossing rule, with a railway layer: the railway",
    ),
    C(
        "Crossing the river is something we'd rather avoid.",
        "no_cross",
        ("water", "road", "grass", "tree"),
        (("no_no_cross", "water"), ("avoided", "water")),
    ),
    # ------------------------------------------------------------------ 7. spelling and colloquial words
    C(
        "folow the raods",
        "spelling",
        ("road", "grass", "tree", "building"),
        (("preferred", "road"), ("note_quotes", "raods")),
    ),
    C(
        "avoid the bulidings and the wtaer",
        "spelling",
        ("building", "water", "road", "grass"),
        (("avoided", "building"), ("avoided", "water"), ("note_quotes", "bulidings"), ("note_quotes", "wtaer")),
    ),
    C(
        "prefer the gras and the feild",
        "spelling",
        ("grass", "field", "road", "building"),
        (("preferred", "grass"), ("preferred", "field"), ("note_quotes", "gras"), ("note_quotes", "feild")),
    ),
    C(
        "use the footpathes, the medow is fine",
        "spelling",
        ("path", "grass", "tree", "building"),
        (("preferred", "path"), ("neutral", "grass"), ("note_quotes", "medow")),
    ),
    C(
        "avoid the brigde, prefer the streat",
        "spelling",
        ("bridge", "road", "water", "grass"),
        (("avoided", "bridge"), ("preferred", "road"), ("note_quotes", "brigde"), ("note_quotes", "streat")),
    ),
    C(
        "Stick to the blacktop.",
        "spelling",
        ("road", "grass", "tree", "building"),
        (("preferred", "road"), ("note_quotes", "blacktop")),
        why="American colloquial word for an asphalt road",
    ),
    C(
        "stay off the scrubland",
        "spelling",
        ("shrub", "grass", "road", "tree"),
        (("avoided", "shrub"), ("note_quotes", "scrubland")),
    ),
    # ------------------------------------------------------------------ 8. priors of unmentioned hazards
    C(
        "Main thing: prefer the asphalt roads.",
        "prior",
        ("road", "grass", "tree", "building", "water", "railway"),
        (
            ("preferred", "road"),
            ("neutral", "grass"),
            ("band", "tree", "prior"),
            ("band", "building", "prior"),
            ("band", "water", "prior"),
            ("band", "railway", "prior"),
            ("not_below", "building", "tree"),
            ("not_lethal", "water"),
            ("not_lethal", "railway"),
        ),
    ),
    C(
        "please steer clear of the houses and use the lanes",
        "prior",
        ("building", "road", "grass", "tree"),
        (
            ("avoided", "building"),
            ("not_lethal", "building"),
            ("ge_prompt", "building", "use the lanes"),
            ("band", "tree", "prior"),
            ("preferred", "road"),
        ),
        why="'steer clear of' = avoid: never below the building prior, never lethal",
    ),
    C(
        "driving between the trees is allowed, prefer grass",
        "prior",
        ("tree", "grass", "building", "water"),
        (("neutral", "tree"), ("preferred", "grass"), ("band", "building", "prior"), ("avoided", "water")),
    ),
    C(
        "Wading the stream is OK, follow the trail otherwise.",
        "prior",
        ("water", "trail", "grass", "tree"),
        (("neutral", "water"), ("preferred", "trail"), ("band", "tree", "prior")),
    ),
    C(
        "Prefer the footpaths; sheds are off limits.",
        "prior",
        ("path", "building", "tree", "water", "grass"),
        (
            ("preferred", "path"),
            ("lethal", "building"),
            ("band", "tree", "prior"),
            ("band", "water", "prior"),
            ("not_lethal", "water"),
        ),
    ),
    C(
        "Follow the farm lanes across the farmland.",
        "prior",
        ("road", "farmland", "building", "water", "railway", "tree"),
        (
            ("band", "railway", "prior"),
            ("band", "building", "prior"),
            ("band", "water", "prior"),
            ("avoided", "railway"),
            ("not_lethal", "railway"),
            ("not_below", "building", "tree"),
        ),
    ),
    C(
        "Stay out of the pond please, the robot isn't waterproof.",
        "prior",
        ("water", "grass", "road", "tree"),
        (("avoided", "water"), ("not_lethal", "water"), ("ge_prompt", "water", "drive on the grass")),
        why="'stay out of' = avoid: the water keeps at least its prior, and nothing says lethal",
    ),
    # ------------------------------------------------------------------ 9. outcomes
    C(
        "The lawns are fine to drive on.",
        "outcome",
        ("grass", "road", "building", "tree"),
        (("permission_note",), ("neutral", "grass")),
    ),
    C(
        "Barns and sheds are ok to pass through.",
        "outcome",
        ("building", "road", "grass", "tree"),
        (("permission_note",), ("neutral", "building")),
    ),
    C("you can drive on gravel", "outcome", ("gravel", "road", "grass", "building"), (("permission_note",),)),
    C("Let's go, quick as you can!", "outcome", SAMPLE_LAYERS, (("error",),)),
    C("Hi, thanks for the help yesterday.", "outcome", SAMPLE_LAYERS, (("error",), ("cli_exit", 2))),
    C(
        "Never drive into the water; the trees are alright, prefer the road.",
        "outcome",
        SAMPLE_LAYERS,
        (
            ("cli_band", "water", "lethal"),
            ("cli_band", "tree", "neutral"),
            ("cli_band", "road", "preferred"),
            ("costmap_ok",),
        ),
    ),
    C(
        "Just follow the road please.",
        "outcome",
        NB_LAYERS,
        (
            ("cli_band", "road", "preferred"),
            ("cli_band", "building", "prior"),
            ("cli_band", "water", "prior"),
            ("costmap_ok",),
        ),
    ),
]

#: Prompts whose expected reading is a judgement call (reported with '?').
DOUBTFUL: dict[str, str] = {
    "Mission brief: the UGV is not to depart from the gravel track between waypoints 3 and 7.": "'track' "
    "could mean a railway; with no railway layer the trail is the only reading, but the waypoint numbers "
    "are noise the interpreter may trip over",
    "Meadows first, the gravel road only if there is no other option.": "a last resort without the words "
    "'last resort' ('only if there is no other option')",
    "In the worst case you may cut through the woods, otherwise keep to the roads.": "'you may' (permission, "
    "neutral) vs 'in the worst case' (last resort, avoided): the expectation takes the last resort",
    "prefer the farm tracks, fields are a last resort and the barns are a no-go": "'farm tracks' could be "
    "read as a railway; there is no railway layer",
    "Driving through the field is less risky than going through the woods.": "'field' may be mapped to "
    "farmland or grass before the layer 'field' is considered",
    "the canal is off-limits and try to stay on the towpath": "'towpath' is a specialised word: mapping it "
    "to the path layer needs a synonym or a compound split (tow + path)",
    "do NOT cross the tracks!!": "'tracks' could be a trail; in a crossing rule with a railway layer the "
    "railway is meant",
    "Stick to the blacktop.": "synonym, not a typo: does the note quoting the word as written apply?",
    "stay off the scrubland": "'scrubland' -> shrub is a synonym, not a typo",
    "Stay out of the pond please, the robot isn't waterproof.": "'stay out of' could be read as a keep-out "
    "(lethal); the contract says only off limits / no-go / never enter is lethal",
    "Let's go, quick as you can!": "'quick' states no preference over any entity: an error, not a uniform costmap",
}


def old_prompts(repo: Path) -> set[str]:
    """What this set must not repeat: the string literals of :data:`NOT_FROM`'s files."""
    return literal_prompts(repo, NOT_FROM)
