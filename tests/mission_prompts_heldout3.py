"""Third held-out mission-language set (issue 20): prompts nobody has tuned the interpreter against.

The offline interpreter has by now been fixed against the main corpus and both earlier held-out
sets (tests/mission_prompts_heldout.py, tests/mission_prompts_heldout2.py), so their pass rates
overstate how well a mission the interpreter has never seen is read. These 50+ prompts are new
and untouched: written without reading the interpreter (``overseec_core/interpret/``) and without
reading the earlier sets' prompts (only the corpus module's docstring and format), in the voices of
the people who type missions: a QGIS analyst (terse "layer: level" lists), a robotics engineer
writing a multi-sentence brief, a field operator on a phone (lower case, no punctuation, typos), a
non-native English speaker, and someone dictating to a voice assistant (split compounds, filler
words). Terrain words vary widely (lanes, footpaths, pavement, lawns, meadows, crops, woods,
hedges, barns, creeks, canals, ponds, tracks, car parks, playgrounds, sand, mud, gravel ...).

Same nine phrasing families, same :class:`Case` type, same expectation kinds and checks
(``mission_prompts.check_case``; its docstring says what each expectation means) and the same
cost-scale contract: neutral 0.5 for unlabelled ground and anything merely allowed, preferred
below, avoided above, lethal only for off limits / no-go / never enter and only in its own clause;
"do not cross" / "never cross" is the hard never-cross rule (not lethal), "try not to cross" /
"avoid crossing" a plain avoid; unmentioned trees, buildings and water take their priors.

This is a MEASUREMENT, not a gate: ``bench/mission_language_report.py --heldout3`` prints the pass
rate per family; the tests only check the set's format (size, families, novelty, well-formed
expectations). Do not edit a prompt or its expectation to make the interpreter pass, and do not
tune the interpreter against these prompts. Write a fourth set instead, and retire a case only
where its expectation contradicts the cost-scale contract, saying so in :data:`DOUBTFUL`.
"""

from __future__ import annotations

from pathlib import Path

from .mission_prompts import C, Case, literal_prompts

MIN_CASES = 50
MIN_PER_FAMILY = 5

#: Files whose prompts (every string literal in them) this set must not repeat.
NOT_FROM = (
    "tests/mission_prompts.py",
    "tests/mission_prompts_heldout.py",
    "tests/mission_prompts_heldout2.py",
    "tests/invariants_data.py",
    "tests/interpret/*.py",
)

#: Reference prompts for ``ge_prompt`` (the entity unmentioned there: it sits at its prior).
REF_ROAD = "Prefer the road."
REF_GRASS = "Stay on the grass."

HELDOUT3: list[Case] = [
    # ------------------------------------------------------------------ 1. negation over motion verbs
    C(
        "the rover shouldnt ever get off the gravel, its the only firm ground out there",
        "negation_motion",
        ("gravel", "mud", "grass", "water"),
        (("preferred", "gravel"), ("not_lethal", "mud"), ("not_lethal", "grass")),
        why="phone voice, no apostrophes: 'shouldnt ever get off' = stay on the gravel",
    ),
    C(
        "Under no circumstances should the vehicle leave the paved lane.",
        "negation_motion",
        ("road", "grass", "tree", "building"),
        (("preferred", "road"), ("not_lethal", "grass")),
        why="'under no circumstances ... leave' negates leaving: stay on the lane (road); nothing becomes lethal",
    ),
    C(
        "keep off the lawns, the groundskeeper will go mad",
        "negation_motion",
        ("grass", "path", "building", "tree"),
        (("avoided", "grass"), ("not_lethal", "grass")),
    ),
    C(
        "The platform shall remain on the service road for the whole transect. "
        "It should not stray onto the farmland on either side.",
        "negation_motion",
        ("road", "farmland", "tree", "water"),
        (("preferred", "road"), ("avoided", "farmland"), ("below", "road", "farmland")),
        why="'stray onto X' is motion into X: negated it is avoid X (unlike 'stray from X')",
    ),
    C(
        "Please the robot must not go out from the footpath, it is very important.",
        "negation_motion",
        ("path", "grass", "building", "water"),
        (("preferred", "path"), ("not_lethal", "grass")),
        why="non-native 'go out from' = leave: negated, stay on the footpath",
    ),
    C(
        "okay so don't come off the sidewalk at all and stay off the grass too",
        "negation_motion",
        ("sidewalk", "grass", "road", "building"),
        (("preferred", "sidewalk"), ("avoided", "grass"), ("below", "sidewalk", "grass")),
        why="dictated: 'don't come off' = stay on; 'stay off' = avoid, in one sentence",
    ),
    # ------------------------------------------------------------------ 2. last resort
    C(
        "Stick to the main road. The forest trails are a last resort, only if the road is blocked.",
        "last_resort",
        ("road", "trail", "forest", "building"),
        (("preferred", "road"), ("avoided", "trail"), ("below", "road", "trail")),
    ),
    C(
        "grass ok mud last resort never the pond",
        "last_resort",
        ("grass", "mud", "water", "road"),
        (("neutral", "grass"), ("avoided", "mud"), ("lethal", "water")),
        why="phone shorthand, three clauses without punctuation; 'never the pond' = never enter it",
    ),
    C(
        "The sand we can use only as last option, better is the paved road.",
        "last_resort",
        ("sand", "road", "grass", "water"),
        (("avoided", "sand"), ("preferred", "road"), ("below", "road", "sand")),
        why="non-native: 'last option' = last resort; 'better is the road' prefers the road",
    ),
    C(
        "Go round the meadow if you can, it's a last resort. Avoid the hedges.",
        "last_resort",
        ("grass", "shrub", "road", "building"),
        (("avoided", "grass"), ("avoided", "shrub"), ("not_lethal", "grass"), ("not_lethal", "shrub")),
        why="meadow -> grass, hedges -> shrub; both above neutral, neither lethal",
    ),
    C(
        "only go through the car park as a last resort otherwise use the pavement",
        "last_resort",
        ("parking lot", "sidewalk", "road", "building"),
        (("avoided", "parking lot"), ("preferred", "sidewalk")),
        why="British: car park = parking lot, pavement = sidewalk",
    ),
    C(
        "Use the bridge over the creek; wading through the creek is a last resort.",
        "last_resort",
        ("bridge", "water", "road", "grass"),
        (("preferred", "bridge"), ("avoided", "water"), ("not_lethal", "water"), ("below", "bridge", "water")),
        why="a stated last resort stands (0.6) even on water, whose prior is an obstacle",
    ),
    # ------------------------------------------------------------------ 3. comparatives
    C(
        "Farm roads are better than the fields, and the fields are better than the woods.",
        "comparative",
        ("road", "field", "forest", "building"),
        (("below", "road", "field"), ("below", "field", "forest"), ("not_lethal", "forest")),
    ),
    C(
        "id rather take the long way round on the road than cut across the lawn",
        "comparative",
        ("road", "grass", "building", "tree"),
        (("below", "road", "grass"),),
    ),
    C(
        "Gravel over sand, sand over mud.",
        "comparative",
        ("gravel", "sand", "mud", "water"),
        (("below", "gravel", "sand"), ("below", "sand", "mud"), ("not_lethal", "mud")),
    ),
    C(
        "Bushes are less risky than the stream. Best of all is the footpath.",
        "comparative",
        ("shrub", "water", "path", "building"),
        (("below", "shrub", "water"), ("below", "path", "shrub"), ("preferred", "path")),
        why="bushes -> shrub, stream -> water; 'best of all' puts the footpath first",
    ),
    C(
        "Prefer more the sidewalk to the road, there are cars there.",
        "comparative",
        ("sidewalk", "road", "grass", "building"),
        (("below", "sidewalk", "road"), ("not_lethal", "road")),
        why="non-native 'prefer more A to B' = prefer A to B",
    ),
    C(
        "Preference order for the traverse: paved road first, then gravel, then grass. Avoid the parking lot.",
        "comparative",
        ("road", "gravel", "grass", "parking lot"),
        (
            ("below", "road", "gravel"),
            ("below", "gravel", "grass"),
            ("below", "grass", "parking lot"),
            ("avoided", "parking lot"),
        ),
    ),
    # ------------------------------------------------------------------ 4. conditions
    C(
        "Grass is fine unless it's close to the houses.",
        "condition",
        ("grass", "building", "road", "tree"),
        (("near_above_far", "grass", "building"), ("far_band", "grass", "building", "neutral")),
    ),
    C(
        "avoid the road except near the farm buildings",
        "condition",
        ("road", "building", "field", "water"),
        (("near_below_far", "road", "building"), ("far_band", "road", "building", "avoided")),
    ),
    C(
        "Crossing the meadow is ok as long as it's not right next to the lake.",
        "condition",
        ("grass", "water", "road", "tree"),
        (("near_above_far", "grass", "water"), ("far_band", "grass", "water", "neutral")),
        why="meadow -> grass, lake -> water; 'ok as long as not next to Y' = fine unless near Y",
    ),
    C(
        "Sand is okay but not when near the water, there it is soft.",
        "condition",
        ("sand", "water", "road", "grass"),
        (("near_above_far", "sand", "water"), ("far_band", "sand", "water", "neutral")),
    ),
    C(
        "Stay out of the woods except close to the road.",
        "condition",
        ("forest", "road", "grass", "building"),
        (("near_below_far", "forest", "road"), ("far_band", "forest", "road", "avoided")),
        why="'stay out of X except near Y' = avoid X except near Y",
    ),
    C(
        "paths are ok unless they run next to the canal",
        "condition",
        ("path", "water", "grass", "building"),
        (("near_above_far", "path", "water"), ("far_band", "path", "water", "neutral")),
    ),
    # ------------------------------------------------------------------ 5. scope of off limits / no-go / never
    C(
        "The orchard is off limits but the grass between the rows is fine.",
        "scope",
        ("tree", "grass", "road", "building"),
        (("lethal", "tree"), ("neutral", "grass")),
        why="orchard -> tree; 'off limits' holds only in its clause, the grass is merely allowed",
    ),
    C(
        "The playground is a no-go. The lawn and the footpath are fine.",
        "scope",
        ("playground", "grass", "path", "building"),
        (("lethal", "playground"), ("neutral", "grass"), ("neutral", "path")),
    ),
    C(
        "never enter the barn, use the farm lane and avoid the crops",
        "scope",
        ("building", "road", "farmland", "tree"),
        (("lethal", "building"), ("preferred", "road"), ("avoided", "farmland"), ("not_lethal", "farmland")),
        why="barn -> building, lane -> road, crops -> farmland; 'never enter' scopes over the barn only",
    ),
    C(
        "Railway corridor: off limits. Roads: preferred. Water: avoid where possible.",
        "scope",
        ("railway", "road", "water", "grass"),
        (("lethal", "railway"), ("preferred", "road"), ("avoided", "water"), ("not_lethal", "water")),
        why="QGIS analyst's 'layer: level' list; each item its own clause",
    ),
    C(
        "stay out of the river its off limits but the bridge and the road are fine to use",
        "scope",
        ("water", "bridge", "road", "grass"),
        (("lethal", "water"), ("neutral", "bridge"), ("neutral", "road")),
        why="'fine to use' is permission (neutral); off limits does not reach past 'but'",
    ),
    # ------------------------------------------------------------------ 6. never cross (hard) vs try not to (soft)
    C(
        "Do not cross the railway line under any circumstances.",
        "no_cross",
        ("railway", "road", "grass", "building"),
        (("no_cross", "railway"), ("avoided", "railway"), ("not_lethal", "railway")),
        why="'under any circumstances' strengthens the never-cross rule; it stays a rule (keep-out), not lethal",
    ),
    C(
        "try not to cross the stream its deep in places",
        "no_cross",
        ("water", "grass", "path", "tree"),
        (("no_no_cross", "water"), ("avoided", "water"), ("not_lethal", "water")),
    ),
    C(
        "The robot must never cross the main road; keep it on the sidewalk on this side.",
        "no_cross",
        ("road", "sidewalk", "grass", "building"),
        (("no_cross", "road"), ("avoided", "road"), ("not_lethal", "road"), ("preferred", "sidewalk")),
    ),
    C(
        "It is not allowed for the robot to cross the river.",
        "no_cross",
        ("water", "road", "grass", "bridge"),
        (("no_cross", "water"), ("not_lethal", "water")),
        why="non-native phrasing of 'must not cross the river' (hard rule)",
    ),
    C(
        "avoid crossing the tracks if you can, and stay on the gravel",
        "no_cross",
        ("railway", "gravel", "grass", "building"),
        (("no_no_cross", "railway"), ("avoided", "railway"), ("not_lethal", "railway"), ("preferred", "gravel")),
        why="tracks -> railway; 'avoid crossing ... if you can' is soft",
    ),
    C(
        "dont cross the creek",
        "no_cross",
        ("water", "grass", "road", "tree"),
        (("no_cross", "water"), ("avoided", "water"), ("not_lethal", "water")),
    ),
    # ------------------------------------------------------------------ 7. misspellings and synonyms
    C(
        "stick to the sidwalk and avoid the parkign lot",
        "spelling",
        ("sidewalk", "parking lot", "road", "building"),
        (
            ("preferred", "sidewalk"),
            ("avoided", "parking lot"),
            ("note_quotes", "sidwalk"),
            ("note_quotes", "parkign"),
        ),
    ),
    C(
        "Prefer the pathways, stay clear of the shurbs.",
        "spelling",
        ("path", "shrub", "grass", "building"),
        (("preferred", "path"), ("avoided", "shrub"), ("note_quotes", "shurbs")),
    ),
    C(
        "go arround the resevoir and use the raod",
        "spelling",
        ("water", "road", "grass", "tree"),
        (("preferred", "road"), ("avoided", "water"), ("note_quotes", "resevoir"), ("note_quotes", "raod")),
        why="'go around X' = avoid X; reservoir -> water",
    ),
    C(
        "Avoid the hedgerows and the woodland, prefer the pasture.",
        "spelling",
        ("shrub", "tree", "grass", "road"),
        (
            ("avoided", "shrub"),
            ("avoided", "tree"),
            ("preferred", "grass"),
            ("note_quotes", "hedgerows"),
            ("note_quotes", "pasture"),
        ),
        why="synonyms: hedgerow -> shrub, woodland -> tree, pasture -> grass",
    ),
    C(
        "Keep to the tarmac and out of the bog.",
        "spelling",
        ("road", "wetland", "grass", "water"),
        (("preferred", "road"), ("avoided", "wetland"), ("note_quotes", "tarmac"), ("not_unparsed", "bog")),
        why="British colloquial: tarmac = paved road, bog = wetland",
    ),
    C(
        "avoid the rail road and keep to the foot path",
        "spelling",
        ("railway", "path", "grass", "building"),
        (("avoided", "railway"), ("preferred", "path"), ("not_unparsed", "rail")),
        why="voice transcription splits compounds: 'rail road' = railroad, 'foot path' = footpath",
    ),
    # ------------------------------------------------------------------ 8. priors of unmentioned hazards
    C(
        "Prefer the cycle path, avoid the crops.",
        "prior",
        ("path", "farmland", "tree", "building", "water"),
        (
            ("preferred", "path"),
            ("avoided", "farmland"),
            ("band", "tree", "prior"),
            ("band", "building", "prior"),
            ("band", "water", "prior"),
            ("not_below", "building", "tree"),
        ),
    ),
    C(
        "avoid all the houses pls",
        "prior",
        ("building", "road", "grass", "tree"),
        (
            ("avoided", "building"),
            ("not_lethal", "building"),
            ("ge_prompt", "building", REF_ROAD),
            ("band", "tree", "prior"),
        ),
        why="'avoid' never makes buildings cheaper than their prior; not lethal either",
    ),
    C(
        "you can wade through the pond if needed, prefer the grass",
        "prior",
        ("water", "grass", "building", "tree"),
        (("neutral", "water"), ("preferred", "grass"), ("band", "building", "prior"), ("not_lethal", "building")),
        why="permission to wade makes the water neutral whatever its prior",
    ),
    C(
        "Walking under the trees is fine. Stick to the trail otherwise.",
        "prior",
        ("tree", "trail", "building", "water"),
        (("neutral", "tree"), ("preferred", "trail"), ("band", "building", "prior"), ("band", "water", "prior")),
    ),
    C(
        "Only use the farm lane. The barns are off limits.",
        "prior",
        ("road", "building", "tree", "water"),
        (
            ("preferred", "road"),
            ("lethal", "building"),
            ("band", "tree", "prior"),
            ("band", "water", "prior"),
            ("not_lethal", "tree"),
            ("not_lethal", "water"),
        ),
        why="off limits on the barns makes buildings lethal, the unmentioned trees and water stay at their priors",
    ),
    C(
        "Mission: survey along the hedge line. Stay on the grass margin and avoid the woods.",
        "prior",
        ("grass", "tree", "building", "water"),
        (
            ("preferred", "grass"),
            ("avoided", "tree"),
            ("ge_prompt", "tree", REF_GRASS),
            ("band", "building", "prior"),
            ("band", "water", "prior"),
        ),
        why="woods -> tree; 'avoid the woods' never puts trees below their prior",
    ),
    # ------------------------------------------------------------------ 9. outcomes
    C(
        "the lawn's fine to drive on",
        "outcome",
        ("grass", "road", "building"),
        (("permission_note",),),
    ),
    C(
        "Bridges and sidewalks are both okay to use.",
        "outcome",
        ("bridge", "sidewalk", "road", "water"),
        (("permission_note",), ("costmap_ok",)),
    ),
    C(
        "asdf test 123",
        "outcome",
        ("road", "grass", "building"),
        (("error",), ("cli_exit", 2)),
    ),
    C(
        "Please make the route look good for the demo tomorrow.",
        "outcome",
        ("road", "grass", "building"),
        (("error",),),
        why="no terrain and no preference: nothing understood",
    ),
    C(
        "prefer the gravel avoid the mud",
        "outcome",
        ("gravel", "mud", "grass"),
        (("costmap_ok",), ("cli_band", "gravel", "preferred"), ("cli_band", "mud", "avoided")),
    ),
    C(
        "steer clear of the helipad",
        "outcome",
        ("road", "grass", "building"),
        (("error",), ("cli_exit", 2)),
        why="its only entity matches no layer: an error, never a uniform costmap",
    ),
]

#: Prompts whose expected reading is a judgement call (reported with '?').
DOUBTFUL: dict[str, str] = {
    "only go through the car park as a last resort otherwise use the pavement": "'pavement' is the sidewalk "
    "in British English but the road surface in American English; the expectation takes the British reading",
    "grass ok mud last resort never the pond": "'never the pond' has no verb; read as 'never enter' (lethal), "
    "but it could be taken as a strong avoid",
    "Keep to the tarmac and out of the bog.": "'bog' -> wetland is a synonym a layer-matching rule may not "
    "know; it could also be read as mud or water",
    "It is not allowed for the robot to cross the river.": "'not allowed to cross' is taken as the hard "
    "never-cross rule; the contract names only 'do not cross' / 'never cross'",
    "Do not cross the railway line under any circumstances.": "'under any circumstances' reads like 'at all "
    "costs' (lethal), but the contract keeps 'do not cross' a rule whatever the wording",
    "Stay out of the woods except close to the road.": "'stay out of' is read as avoid; some would read "
    "'stay out' as never enter",
    "you can wade through the pond if needed, prefer the grass": "(added after the first run) 'if needed' "
    "hedges the permission like 'only if you have to' (a last resort, 0.6); the expectation takes the "
    "contract's 'you can wade' = neutral",
    "avoid the rail road and keep to the foot path": "split compounds from voice input: 'rail road' and "
    "'foot path' each need to be joined (or read by their head noun) to match railway and path",
}


def old_prompts(repo: Path) -> set[str]:
    """What this set must not repeat: the string literals of :data:`NOT_FROM`'s files."""
    return literal_prompts(repo, NOT_FROM)
