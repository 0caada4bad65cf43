"""Held-out mission-language set (issue 20): prompts nobody tunes the interpreter against.

The main corpus (tests/mission_prompts.py) is what the offline interpreter has been tuned on, so
its pass rate overstates how well the interpreter reads missions it has never seen. These prompts
were written without looking at the interpreter's phrase tables (``interpret/offline.py``,
``interpret/lexicon.py``), the way GIS analysts and robotics operators phrase missions: varied
word order, punctuation and politeness, long multi-clause missions, British and American spelling,
entity names beyond the corpus (footpaths, meadows, sheds, brooks, verges, sand, mud, ...) and
realistic typos. They use the same nine phrasing families, the same :class:`Case` type and the
same expectation kinds and checks (``mission_prompts.check_case``); see that module's docstring
for what each expectation means.

This is a MEASUREMENT, not a gate: ``bench/mission_language_report.py --heldout`` prints the pass
rate per family; the tests only check the set's format (size, families, novelty). Do not edit a
held-out prompt or its expectation to make the interpreter pass, and do not tune the interpreter
against these prompts: that would turn it into a second training set. Add new held-out prompts
instead, and retire a case only where its expectation contradicts the cost-scale contract
(README "What the costs mean"), saying so in :data:`DOUBTFUL`.
"""

from __future__ import annotations

from pathlib import Path

from .mission_prompts import HEADLINE, NB_LAYERS, SAMPLE_LAYERS, C, Case, literal_prompts

MIN_CASES = 60
MIN_PER_FAMILY = 6

#: Files whose prompts (every string literal in them) the held-out set must not repeat.
NOT_FROM = ("tests/mission_prompts.py", "tests/invariants_data.py", "tests/interpret/*.py")

HELDOUT: list[Case] = [
    # ------------------------------------------------------------------ 1. negation over motion verbs
    C(
        "The UGV must not leave the paved road at any time.",
        "negation_motion",
        ("road", "grass", "building", "water"),
        (("preferred", "road"), ("not_lethal", "grass")),
        why="'must not leave' = stay on; 'at any time' strengthens it but makes nothing lethal",
    ),
    C(
        "Under no circumstances should the robot stray off the footpath.",
        "negation_motion",
        ("footpath", "grass", "building", "water"),
        (("preferred", "footpath"), ("not_lethal", "footpath")),
        why="'under no circumstances' negates straying: the footpath is preferred, nothing else is named",
    ),
    C(
        "Stay off the farmland, it's been freshly seeded.",
        "negation_motion",
        ("farmland", "road", "building", "water"),
        (("avoided", "farmland"),),
    ),
    C(
        "Please don't get off the gravel path - the ground either side is boggy.",
        "negation_motion",
        ("path", "grass", "water", "building"),
        (("preferred", "path"),),
    ),
    C(
        "Keep the vehicle off the grass and don't wander from the road.",
        "negation_motion",
        ("grass", "road", "building", "water"),
        (("avoided", "grass"), ("preferred", "road"), ("below", "road", "grass")),
    ),
    C(
        "No leaving the trail; stay clear of the stream as well.",
        "negation_motion",
        ("trail", "stream", "vegetation", "building"),
        (("preferred", "trail"), ("avoided", "stream")),
    ),
    C(
        "For this leg the robot must not stray from the towpath, it isn't rated for the rough ground either side.",
        "negation_motion",
        ("towpath", "grass", "canal", "building"),
        (("preferred", "towpath"), ("not_lethal", "canal")),
    ),
    # ------------------------------------------------------------------ 2. last resort inside lists
    C(
        "Favour the footpaths; the main road is our last resort.",
        "last_resort",
        ("footpath", "road", "grass", "building"),
        (("preferred", "footpath"), ("avoided", "road")),
    ),
    C(
        "Crossing the meadow is fine, the woods are a last resort.",
        "last_resort",
        ("meadow", "woods", "road", "building"),
        (("neutral", "meadow"), ("avoided", "woods")),
    ),
    C(
        "Last resort only: the sand. Otherwise stick to the road.",
        "last_resort",
        ("sand", "road", "grass", "building"),
        (("avoided", "sand"), ("preferred", "road")),
    ),
    C(
        "Take the trail, then the grass, and the mud only as an absolute last resort.",
        "last_resort",
        ("trail", "grass", "mud", "building"),
        (("preferred", "trail"), ("avoided", "mud"), ("below", "grass", "mud")),
        why="'then the grass' ranks grass after the trail; the mud is tolerable, not lethal",
    ),
    C(
        "Wading the river is a last resort if there is genuinely no other way.",
        "last_resort",
        ("river", "road", "grass", "building"),
        (("avoided", "river"),),
    ),
    C(
        "roads first, then paths, with the open fields as a last resort",
        "last_resort",
        ("road", "path", "field", "building"),
        (("preferred", "road"), ("preferred", "path"), ("avoided", "field"), ("below", "road", "field")),
    ),
    C(
        "The forest should only be entered as a last resort; use the fire roads.",
        "last_resort",
        ("forest", "road", "building", "water"),
        (("avoided", "forest"), ("preferred", "road")),
    ),
    # ------------------------------------------------------------------ 3. comparatives and chains
    C(
        "The gravel path is better than the lawn.",
        "comparative",
        ("path", "lawn", "building", "water"),
        (("below", "path", "lawn"),),
    ),
    C(
        "Sand over mud, every time.",
        "comparative",
        ("sand", "mud", "road", "water"),
        (("below", "sand", "mud"),),
    ),
    C(
        "I'd much rather the robot drove on the road than on the verge.",
        "comparative",
        ("road", "verge", "building", "water"),
        (("below", "road", "verge"),),
    ),
    C(
        "Meadow is preferable to woodland.",
        "comparative",
        ("meadow", "woodland", "road", "building"),
        (("below", "meadow", "woodland"),),
    ),
    C(
        "Fields are less risky than the forest, and the forest is less risky than the marsh.",
        "comparative",
        ("field", "forest", "marsh", "road"),
        (("below", "field", "forest"), ("below", "forest", "marsh")),
    ),
    C(
        "Tarmac rather than gravel, please.",
        "comparative",
        ("tarmac", "gravel", "grass", "building"),
        (("below", "tarmac", "gravel"),),
    ),
    C(
        "Between the beach and the dunes, the beach is the better option.",
        "comparative",
        ("beach", "dune", "road", "water"),
        (("below", "beach", "dune"),),
    ),
    # ------------------------------------------------------------------ 4. conditions
    C(
        "Driving across the fields is OK unless you're close to the houses.",
        "condition",
        ("field", "building", "road", "water"),
        (("far_band", "field", "building", "neutral"), ("near_above_far", "field", "building")),
        why="houses are buildings (broader match)",
    ),
    C(
        "Grass is acceptable, except where it is near the river.",
        "condition",
        ("grass", "river", "road", "building"),
        (("far_band", "grass", "river", "neutral"), ("near_above_far", "grass", "river")),
    ),
    C(
        "Avoid the road except near the bridge.",
        "condition",
        ("road", "bridge", "grass", "water"),
        (("far_band", "road", "bridge", "avoided"), ("near_below_far", "road", "bridge")),
    ),
    C(
        "Stay out of the forest unless you're within 10 m of the trail.",
        "condition",
        ("forest", "trail", "road", "building"),
        (("far_band", "forest", "trail", "avoided"), ("near_below_far", "forest", "trail")),
        why="'stay out of X unless near Y' is 'avoid X except near Y'",
    ),
    C(
        "Mud is fine as long as it's not next to the water.",
        "condition",
        ("mud", "water", "road", "building"),
        (("far_band", "mud", "water", "neutral"), ("near_above_far", "mud", "water")),
        why="'fine as long as not next to Y' is 'fine unless near Y'",
    ),
    C(
        "Keep off the sand, except where it's close to the road.",
        "condition",
        ("sand", "road", "water", "building"),
        (("far_band", "sand", "road", "avoided"), ("near_below_far", "sand", "road")),
    ),
    C(
        "The farmland can be used, unless it is right beside the railway.",
        "condition",
        ("farmland", "railway", "road", "water"),
        (("far_band", "farmland", "railway", "neutral"), ("near_above_far", "farmland", "railway")),
    ),
    # ------------------------------------------------------------------ 5. scope of off limits / no-go / never
    C(
        "Prefer the footpaths and avoid the car park; the pond is strictly off limits.",
        "scope",
        ("footpath", "car park", "pond", "grass"),
        (("lethal", "pond"), ("preferred", "footpath"), ("avoided", "car park")),
    ),
    C(
        "The railway corridor is a no-go, but crossing the field is fine.",
        "scope",
        ("railway", "field", "road", "building"),
        (("lethal", "railway"), ("neutral", "field")),
    ),
    C(
        "Never enter the sheds; the lawn is fine and the road is preferred.",
        "scope",
        ("shed", "lawn", "road", "water"),
        (("lethal", "shed"), ("neutral", "lawn"), ("preferred", "road")),
    ),
    C(
        "Avoid the marsh where possible, the quarry is a no-go area, and otherwise keep to the road.",
        "scope",
        ("marsh", "quarry", "road", "building"),
        (("avoided", "marsh"), ("lethal", "quarry"), ("preferred", "road")),
    ),
    C(
        "Off limits: the school. Otherwise prefer the paths over the grass.",
        "scope",
        ("school", "path", "grass", "road"),
        (("lethal", "school"), ("below", "path", "grass")),
    ),
    C(
        "For today's survey run the UGV should keep to the access road wherever possible, avoid the orchard, "
        "and under no circumstances enter the reservoir, which is off limits.",
        "scope",
        ("road", "orchard", "reservoir", "grass"),
        (("preferred", "road"), ("avoided", "orchard"), ("lethal", "reservoir")),
    ),
    C(
        "farmland's a no go zone for the rover but the dirt road is ok",
        "scope",
        ("farmland", "road", "grass", "building"),
        (("lethal", "farmland"), ("neutral", "road")),
    ),
    # ------------------------------------------------------------------ 6. do not cross vs never cross
    C(
        "Under no circumstances cross the river.",
        "no_cross",
        ("river", "road", "vegetation", "building"),
        (("no_cross", "river"), ("avoided", "river")),
        why="the same hard rule as 'never cross': a no_cross cue, not a lethal river",
    ),
    C(
        "The UGV must not cross the main road.",
        "no_cross",
        ("road", "grass", "building", "water"),
        (("no_cross", "road"), ("avoided", "road")),
    ),
    C(
        "Do NOT cross the stream at any point.",
        "no_cross",
        ("stream", "road", "grass", "building"),
        (("no_cross", "stream"), ("avoided", "stream")),
    ),
    C(
        "Avoid crossing the railway line if you can.",
        "no_cross",
        ("railway", "road", "vegetation", "building"),
        (("no_no_cross", "railway"), ("avoided", "railway")),
    ),
    C(
        "Crossing the road should be kept to a minimum.",
        "no_cross",
        ("road", "grass", "trail", "building"),
        (("no_no_cross", "road"), ("avoided", "road")),
        why="a soft wish (minimise crossings), not a 'do not cross' rule",
    ),
    C(
        "Prefer the path, and don't cross the brook.",
        "no_cross",
        ("path", "brook", "grass", "building"),
        (("preferred", "path"), ("no_cross", "brook"), ("avoided", "brook")),
    ),
    C(
        "Try to avoid crossing the river, but never cross the railway.",
        "no_cross",
        ("river", "railway", "road", "vegetation"),
        (("no_no_cross", "river"), ("avoided", "river"), ("no_cross", "railway"), ("avoided", "railway")),
    ),
    # ------------------------------------------------------------------ 7. misspellings and colloquial words
    C(
        "Prefer the grsas and avoid the water.",
        "spelling",
        ("grass", "water", "road", "building"),
        (("preferred", "grass"), ("avoided", "water"), ("note_quotes", "grsas"), ("not_unparsed", "grsas")),
    ),
    C(
        "Keep away from the railwey.",
        "spelling",
        ("railway", "road", "vegetation", "building"),
        (("avoided", "railway"), ("note_quotes", "railwey"), ("not_unparsed", "railwey")),
    ),
    C(
        "Stick to the trial and stay off the feilds.",
        "spelling",
        ("trail", "field", "road", "building"),
        (
            ("preferred", "trail"),
            ("avoided", "field"),
            ("note_quotes", "trial"),
            ("note_quotes", "feilds"),
            ("not_unparsed", "feilds"),
        ),
        why="'trial' is a real English word typed for 'trail': only the context says so",
    ),
    C(
        "Stay away from the houses.",
        "spelling",
        ("building", "road", "grass", "water"),
        (("avoided", "building"), ("note_quotes", "houses")),
        why="a synonym: the entity->layer mapping 'house -> building' names it",
    ),
    C(
        "Follow the tarmac.",
        "spelling",
        ("road", "grass", "building", "water"),
        (("preferred", "road"), ("note_quotes", "tarmac")),
        why="British colloquial for a paved road",
    ),
    C(
        "avoid the watter and the vegatation",
        "spelling",
        ("water", "vegetation", "road", "building"),
        (
            ("avoided", "water"),
            ("avoided", "vegetation"),
            ("note_quotes", "watter"),
            ("note_quotes", "vegatation"),
            ("not_unparsed", "watter"),
            ("not_unparsed", "vegatation"),
        ),
    ),
    C(
        "Go through the meadows where you can.",
        "spelling",
        ("grass", "road", "building", "water"),
        (("preferred", "grass"), ("note_quotes", "meadows")),
        why="a meadow is grass: the mapping 'meadow -> grass' names it",
    ),
    # ------------------------------------------------------------------ 8. priors of unmentioned hazards
    C(
        "Stick to the roads where you can.",
        "prior",
        SAMPLE_LAYERS,
        (
            ("preferred", "road"),
            ("band", "tree", "prior"),
            ("band", "building", "prior"),
            ("band", "water", "prior"),
            ("avoided", "tree"),
            ("avoided", "building"),
            ("avoided", "water"),
            ("not_below", "building", "tree"),
            ("neutral", "grass"),
        ),
    ),
    C(
        "Keep well clear of the houses.",
        "prior",
        SAMPLE_LAYERS,
        (
            ("band", "building", "avoided"),
            ("avoided", "building"),
            ("ge_prompt", "building", HEADLINE),
            ("band", "tree", "prior"),
            ("band", "water", "prior"),
        ),
    ),
    C(
        "You can wade across the river.",
        "prior",
        SAMPLE_LAYERS,
        (("band", "water", "neutral"), ("neutral", "water"), ("band", "tree", "prior"), ("band", "building", "prior")),
    ),
    C(
        "Drive on the grass; sheds and houses are off limits.",
        "prior",
        SAMPLE_LAYERS,
        (
            ("preferred", "grass"),
            ("lethal", "building"),
            ("band", "building", "lethal"),
            ("band", "tree", "prior"),
            ("band", "water", "prior"),
        ),
    ),
    C(
        "Head along the trail.",
        "prior",
        ("trail", *NB_LAYERS),
        (
            ("preferred", "trail"),
            ("avoided", "railway"),
            ("avoided", "water"),
            ("avoided", "building"),
            ("band", "water", "prior"),
            ("band", "building", "prior"),
            ("neutral", "road"),
            ("neutral", "vegetation"),
        ),
        why="road and vegetation are no hazards: unmentioned, they stay neutral",
    ),
    C(
        "Going under the trees is fine, but try to keep out of the water.",
        "prior",
        SAMPLE_LAYERS,
        (
            ("band", "tree", "neutral"),
            ("neutral", "tree"),
            ("band", "water", "avoided"),
            ("avoided", "water"),
            ("ge_prompt", "water", HEADLINE),
            ("band", "building", "prior"),
        ),
    ),
    C(
        "Minimise time on the baseball field and follow the road.",
        "prior",
        SAMPLE_LAYERS,
        (
            ("avoided", "baseball field"),
            ("preferred", "road"),
            ("band", "tree", "prior"),
            ("band", "building", "prior"),
            ("band", "water", "prior"),
            ("not_below", "building", "tree"),
        ),
    ),
    C(
        "Try to avoid the woods.",
        "prior",
        SAMPLE_LAYERS,
        (
            ("band", "tree", "avoided"),
            ("avoided", "tree"),
            ("ge_prompt", "tree", HEADLINE),
            ("band", "building", "prior"),
            ("band", "water", "prior"),
        ),
    ),
    # ------------------------------------------------------------------ 9. outcomes
    C("Walking on the grass is permitted.", "outcome", SAMPLE_LAYERS, (("costmap_ok",), ("permission_note",))),
    C(
        "The trail and the baseball field are both okay to use.",
        "outcome",
        SAMPLE_LAYERS,
        (("costmap_ok",), ("permission_note",)),
    ),
    C(
        "It's fine to go through the trees and over the grass.",
        "outcome",
        SAMPLE_LAYERS,
        (("costmap_ok",), ("permission_note",)),
    ),
    C("Hi, can you plan me a route please?", "outcome", SAMPLE_LAYERS, (("error",), ("cli_exit", 2))),
    C("Be careful out there.", "outcome", SAMPLE_LAYERS, (("error",), ("cli_exit", 2))),
    C("Fastest route possible, cheers.", "outcome", SAMPLE_LAYERS, (("error",),)),
    C(
        "Stay on the road and keep off the grass.",
        "outcome",
        SAMPLE_LAYERS,
        (
            ("cli_band", "road", "preferred"),
            ("cli_band", "grass", "avoided"),
            ("cli_band", "tree", "prior"),
            ("cli_band", "building", "prior"),
            ("cli_band", "water", "prior"),
        ),
    ),
    C(
        "Water is a no-go; the trees are fine.",
        "outcome",
        SAMPLE_LAYERS,
        (("cli_band", "water", "lethal"), ("cli_band", "tree", "neutral"), ("costmap_ok",)),
    ),
]

#: Held-out prompts whose expected reading is a judgement call (reported with '?').
DOUBTFUL: dict[str, str] = {
    "Stick to the trial and stay off the feilds.": "'trial' is a real word: reading it as 'trail' needs the "
    "context (the layers have a trail, no trial)",
    "Between the beach and the dunes, the beach is the better option.": "the comparison is spread over two "
    "clauses ('between A and B, A is better')",
    "Crossing the road should be kept to a minimum.": "a soft wish with no 'avoid' / 'try not to': avoided, "
    "no hard cue",
    "Fastest route possible, cheers.": "'fastest' states no preference over any entity: an error, not a "
    "uniform costmap",
    "Under no circumstances cross the river.": "'under no circumstances' could be read as making the river "
    "lethal; the contract says a crossing rule is a no_cross cue",
    "Follow the tarmac.": "'tarmac' is a surface: should it map to the road layer at all?",
    "Keep well clear of the houses.": "(noted after the first run) 'keep clear of' may be read as a distance "
    "rule (a keep-out zone round the houses) rather than a stated 'avoid'; the band check wants the stated one",
}


def old_prompts(repo: Path) -> set[str]:
    """What this set must not repeat: the string literals of :data:`NOT_FROM`'s files."""
    return literal_prompts(repo, NOT_FROM)
