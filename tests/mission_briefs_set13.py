"""Mission briefs, set 13: mixed voices (GIS analyst, robot operator, field team) and mixed styles.

Long formal briefs, terse and symbolic ones, phone-typed ones with typos, briefs that carry
irrelevant chatter, numbers written as words, ranges, conditionals and passive voice.

Written without reading the interpreter (``overseec_core/interpret/``), its tests, its corpora or
the bench; only the contract (``tests/mission_briefs.py``) and the scene index
(``shared/scenes/INDEX.md`` and the scenes' ``classes.json``) were read. Scored once, at first
contact, with ``bench/mission_briefs_report.py --set 13``. A case found to contradict the
cost-scale contract is retired in ``DOUBTFUL`` with the reason; no brief is edited to pass.
"""

from __future__ import annotations

from .mission_briefs import Brief, Route

# Layer tuples, one per real scene (class names as in the scene index / classes.json).
NB = ("building", "road", "water", "vegetation", "railway")  # nb1, nb2 (New Brunswick, 5 classes)
VEGAS = ("paved road", "unpaved road")  # SpaceNet Las Vegas roads
KAMPALA = ("building",)  # OSM footprints, dense informal settlement
MASSACHUSETTS = ("building",)  # suburb, 1 m
NEON = ("tree",)  # Florida forest plot, tree crowns
SAMPLE = ("grass", "road", "trail", "tree", "water", "building", "baseball field")  # bundled sample

# Layer tuples with no real scene (no route checks possible on them).
FOREST = ("deciduous tree", "conifer tree", "trail")
NB_BARN = (*NB, "barn")  # New Brunswick classes plus an excepted sub-area (the barn is unlabelled there)

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------------------------------
    # distance_hard: distance rules worded as absolute
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "All survey routes shall maintain a minimum separation of 12 m from the railway "
            "corridor. This is a safety requirement and is not subject to trade-off."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "railway", 12),),
        routes=(Route("nb1", "keeps", "railway", 12), Route("nb2", "keeps", "railway", 12)),
        why="'shall maintain a minimum separation' and 'not subject to trade-off' are absolute",
    ),
    Brief(
        prompt="Hard constraint for the UGV: it may never get closer than five metres to a building.",
        voice="robot",
        construct="distance_hard",
        layers=MASSACHUSETTS,
        expect=(("keep_out", "building", 5),),
        routes=(Route("massachusetts", "keeps", "building", 5),),
        why="'hard constraint', 'never closer than'; the number is written as a word",
    ),
    Brief(
        prompt="walking thru the settlement. absolutly no closer than 2m to any building, people live in them",
        voice="field",
        construct="distance_hard",
        layers=KAMPALA,
        expect=(("keep_out", "building", 2),),
        routes=(Route("kampala", "keeps", "building", 2),),
        why="'absolutely no closer than' is absolute despite the typo; where the dense settlement "
        "leaves no 2 m gap the route runs the fewest metres inside",
    ),
    Brief(
        prompt=(
            "At no point may the path come within 20 metres of open water (the reservoir banks "
            "are unstable and undercut)."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=SAMPLE,
        expect=(("keep_out", "water", 20),),
        routes=(Route("sample", "keeps", "water", 20),),
        why="'at no point may ... come within' is absolute; the parenthesis is only the reason",
    ),
    Brief(
        prompt=(
            "Configure a strict 8 m exclusion buffer around every building, and favour roads for the rest of the run."
        ),
        voice="robot",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "building", 8), ("preferred", "road")),
        routes=(Route("nb1", "keeps", "building", 8), Route("nb2", "more_on", "road")),
        why="a 'strict exclusion buffer' is a hard zone; 'favour roads' prefers them",
    ),
    Brief(
        prompt="landowners rule: no nearer than ten metres to the baseball field. full stop.",
        voice="field",
        construct="distance_hard",
        layers=SAMPLE,
        expect=(("keep_out", "baseball field", 10),),
        routes=(Route("sample", "keeps", "baseball field", 10),),
        why="'no nearer than ... full stop' is absolute; ten written as a word",
    ),
    Brief(
        prompt=(
            "A mandatory stand-off from the railway applies. No figure has been specified, but "
            "the requirement is absolute."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "railway", None),),
        routes=(Route("nb2", "keeps", "railway", 1),),
        why="an absolute stand-off without a number: a hard zone of the default size (at least 1 m)",
    ),
    # ------------------------------------------------------------------------------------------
    # distance_soft: distance rules worded softly, the number kept
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Where practicable, routes should keep roughly 15 m back from the water's edge; brief "
            "approaches are acceptable if they shorten the route considerably."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "water", 15),),
        routes=(Route("nb1", "farther", "water"),),
        why="'where practicable' and 'brief approaches are acceptable' make it soft",
    ),
    Brief(
        prompt="If you can, hold about 6 m off the buildings. It's a preference, not a hard limit.",
        voice="robot",
        construct="distance_soft",
        layers=MASSACHUSETTS,
        expect=(("soft_zone", "building", 6),),
        routes=(Route("massachusetts", "farther", "building"),),
        why="conditional and explicitly 'not a hard limit'",
    ),
    Brief(
        prompt="try to keep something like 10 to 15 m away from the trees where possible, the dogs get spooked under them",
        voice="field",
        construct="distance_soft",
        layers=SAMPLE,
        expect=(("soft_zone", "tree", 10),),
        routes=(Route("sample", "farther", "tree"),),
        why="a soft range; the lower end is used so the probes (1 m, 9 m) are inside either reading",
    ),
    Brief(
        prompt=(
            "Ideally the track would stay twenty-five metres or more from the railway line, "
            "though this is a preference rather than a rule."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "railway", 25),),
        routes=(Route("nb2", "farther", "railway"),),
        why="'ideally', 'a preference rather than a rule'; the number is in words",
    ),
    Brief(
        prompt=(
            "Soft 3 m buffer around tree crowns please; entering the buffer is allowed when there is no cheaper option."
        ),
        voice="robot",
        construct="distance_soft",
        layers=NEON,
        expect=(("soft_zone", "tree", 3),),
        routes=(Route("neon", "farther", "tree"),),
        why="explicitly soft: the buffer may be entered",
    ),
    Brief(
        prompt="stay 10m off teh road unles that makes the walk way longer, cars come round fast",
        voice="field",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "road", 10),),
        routes=(Route("nb2", "farther", "road"),),
        why="'unless that makes the walk way longer' trades the distance against length: soft",
    ),
    # ------------------------------------------------------------------------------------------
    # graded_away: priced by distance, the closer the dearer
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Route desirability should increase with distance from buildings; proximity to any "
            "structure is to be penalised progressively."
        ),
        voice="analyst",
        construct="graded_away",
        layers=SAMPLE,
        expect=(("graded_away", "building", None),),
        routes=(Route("sample", "farther", "building"),),
        why="'penalised progressively' with proximity: a graded fall-off, no keep-out",
    ),
    Brief(
        prompt="Give the water a wide berth on this run; the chassis isn't sealed.",
        voice="robot",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "water", None),),
        routes=(Route("nb1", "farther", "water"),),
        why="'a wide berth' is keep-well-away wording with no number",
    ),
    Brief(
        prompt="try not to get near the buildings if u can help it, closer = worse",
        voice="field",
        construct="graded_away",
        layers=KAMPALA,
        expect=(("graded_away", "building", None),),
        routes=(Route("kampala", "farther", "building"),),
        why="'closer = worse' states the gradient outright",
    ),
    Brief(
        prompt="Cost should rise as the route approaches the railway, tapering to nothing at 30 m.",
        voice="analyst",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "railway", 30),),
        routes=(Route("nb2", "farther", "railway"),),
        why="a graded fall-off that reaches neutral at 30 m",
    ),
    Brief(
        prompt="Maximise clearance from tree crowns: the nearer a crown, the higher the cost.",
        voice="robot",
        construct="graded_away",
        layers=NEON,
        expect=(("graded_away", "tree", None),),
        routes=(Route("neon", "farther", "tree"),),
        why="the nearer, the dearer; no number, no absolute wording",
    ),
    Brief(
        prompt="stay as far from the water as u reasonably can. past forty metres it doesnt matter anymore",
        voice="field",
        construct="graded_away",
        layers=SAMPLE,
        expect=(("graded_away", "water", 40),),
        routes=(Route("sample", "farther", "water"),),
        why="'as far as you reasonably can' is graded; the fall-off ends at forty metres (in words)",
    ),
    # ------------------------------------------------------------------------------------------
    # graded_toward: the nearer, the cheaper
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "The route should remain as near to the road network as practicable, since the "
            "support vehicle must be able to reach the team quickly."
        ),
        voice="analyst",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "road", None),),
        routes=(Route("nb1", "closer", "road"), Route("nb2", "closer", "road")),
        why="nearness to the road is wanted, not travel on it",
    ),
    Brief(
        prompt="Keep the trail in view the whole way; our comms relay sits on it. Closer is better.",
        voice="robot",
        construct="graded_toward",
        layers=SAMPLE,
        expect=(("graded_toward", "trail", None),),
        routes=(Route("sample", "closer", "trail"),),
        why="within sight of the trail, 'closer is better'",
    ),
    Brief(
        prompt="keep near the trees, we need the shade, its 35 degrees out here",
        voice="field",
        construct="graded_toward",
        layers=NEON,
        expect=(("graded_toward", "tree", None),),
        routes=(Route("neon", "closer", "tree"),),
        why="near the trees for shade; the temperature is chatter, not a distance",
    ),
    Brief(
        prompt="For wayfinding purposes, the nearer the path keeps to buildings, the better.",
        voice="analyst",
        construct="graded_toward",
        layers=MASSACHUSETTS,
        expect=(("graded_toward", "building", None),),
        routes=(Route("massachusetts", "closer", "building"),),
        why="'the nearer, the better' toward buildings",
    ),
    Brief(
        prompt="Sampling run: bias the planner toward the water's edge. The nearer the shoreline, the cheaper.",
        voice="robot",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "water", None),),
        routes=(Route("nb1", "closer", "water"),),
        why="toward the water's edge, cheaper the nearer",
    ),
    Brief(
        prompt="stick close to teh road pls, no signal anywhere else",
        voice="field",
        construct="graded_toward",
        layers=SAMPLE,
        expect=(("graded_toward", "road", None),),
        routes=(Route("sample", "closer", "road"),),
        why="'stick close to' is nearness (typo in 'the')",
    ),
    # ------------------------------------------------------------------------------------------
    # on_beside: along X but not on X
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Follow the railway corridor, travelling parallel to it on the adjacent ground rather "
            "than on the track bed itself."
        ),
        voice="analyst",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "railway"),),
        routes=(Route("nb1", "beside", "railway", 10),),
        why="adjacent ground preferred, the track bed itself not",
    ),
    Brief(
        prompt="Run along the paved road on its shoulder; the wheels are not to touch the asphalt itself.",
        voice="robot",
        construct="on_beside",
        layers=VEGAS,
        expect=(("beside", "paved road"),),
        routes=(Route("vegas", "beside", "paved road", 5),),
        why="the shoulder beside the paved road, not the road surface",
    ),
    Brief(
        prompt="walk next to the trail but off it, they just reseeded it",
        voice="field",
        construct="on_beside",
        layers=SAMPLE,
        expect=(("beside", "trail"),),
        routes=(Route("sample", "beside", "trail", 5),),
        why="next to the trail, not on it",
    ),
    Brief(
        prompt="The route is to run alongside the shoreline: adjacent to the water, never in it.",
        voice="analyst",
        construct="on_beside",
        layers=SAMPLE,
        expect=(("beside", "water"),),
        routes=(Route("sample", "beside", "water", 10),),
        why="beside the water; the water itself avoided or forbidden",
    ),
    Brief(
        prompt="Track the road edge. Stay beside the road, off the carriageway.",
        voice="robot",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "road"),),
        routes=(Route("nb2", "beside", "road", 5),),
        why="beside the road, off its surface",
    ),
    Brief(
        prompt="keep right alongside the buildings but not in them obviously, were checking the gutters",
        voice="field",
        construct="on_beside",
        layers=MASSACHUSETTS,
        expect=(("beside", "building"),),
        routes=(Route("massachusetts", "beside", "building", 5),),
        why="along the walls, not through the buildings",
    ),
    # ------------------------------------------------------------------------------------------
    # qualified: paved / unpaved, deciduous / conifer, excepted sub-areas
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="Travel is to be restricted to paved road wherever possible; unpaved road surfaces are to be avoided.",
        voice="analyst",
        construct="qualified",
        layers=VEGAS,
        expect=(
            ("preferred", "paved road"),
            ("avoided", "unpaved road"),
            ("below", "paved road", "unpaved road"),
        ),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="'wherever possible' makes paved road preferred, not mandatory; unpaved avoided",
    ),
    Brief(
        prompt="Prefer unpaved road to paved road; the rover's tyres grip gravel better than hot asphalt.",
        voice="robot",
        construct="qualified",
        layers=VEGAS,
        expect=(("below", "unpaved road", "paved road"),),
        why="only an order is given; no route check (the unpaved class is nearly empty on vegas)",
    ),
    Brief(
        prompt="conifers r fine to walk under but avoid the deciduous ones, branches keep dropping",
        voice="field",
        construct="qualified",
        layers=FOREST,
        expect=(
            ("neutral", "conifer tree"),
            ("avoided", "deciduous tree"),
            ("below", "conifer tree", "deciduous tree"),
        ),
        why="'fine' merely allows conifers (lifts the tree prior to neutral); deciduous avoided",
    ),
    Brief(
        prompt="Coniferous stands are preferred for overhead cover; deciduous trees should be costed as neutral.",
        voice="analyst",
        construct="qualified",
        layers=FOREST,
        expect=(("preferred", "conifer tree"), ("neutral", "deciduous tree")),
        why="the two tree kinds get different levels",
    ),
    Brief(
        prompt="Avoid grass, except the baseball field, which is open for transit.",
        voice="robot",
        construct="qualified",
        layers=SAMPLE,
        expect=(("avoided", "grass"), ("neutral", "baseball field"), ("not_lethal", "baseball field")),
        routes=(Route("sample", "less_on", "grass"),),
        why="the baseball field is excepted from the grass rule and merely allowed",
    ),
    Brief(
        prompt="stay off all the buildings apart from the old barn, the barn is fine to cut thru",
        voice="field",
        construct="qualified",
        layers=NB_BARN,
        expect=(("avoided", "building"), ("neutral", "barn"), ("not_lethal", "barn")),
        routes=(Route("nb1", "less_on", "building"),),
        why="'stay off' avoids (not a forbidding phrase); the barn is an excepted sub-area, merely allowed",
    ),
    # ------------------------------------------------------------------------------------------
    # terse: symbolic, clipped, typo-ridden
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="trail > road > grass",
        voice="field",
        construct="terse",
        layers=SAMPLE,
        expect=(("below", "trail", "road"), ("below", "road", "grass")),
        why="a ranking, best first; only the order is given",
    ),
    Brief(
        prompt="roads: prefer. water: no-go. rail: avoid.",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(("preferred", "road"), ("lethal", "water"), ("avoided", "railway")),
        routes=(
            Route("nb1", "zero_on", "water"),
            Route("nb1", "more_on", "road"),
            Route("nb2", "less_on", "railway"),
        ),
        why="'no-go' forbids; 'rail' is the railway",
    ),
    Brief(
        prompt="Buildings: 10 m buffer (hard). Vegetation: neutral.",
        voice="analyst",
        construct="terse",
        layers=NB,
        expect=(("keep_out", "building", 10), ("neutral", "vegetation")),
        routes=(Route("nb2", "keeps", "building", 10),),
        why="'(hard)' makes the buffer absolute",
    ),
    Brief(
        prompt="basebal feild avoid, gras fine",
        voice="field",
        construct="terse",
        layers=SAMPLE,
        expect=(("avoided", "baseball field"), ("neutral", "grass")),
        routes=(Route("sample", "less_on", "baseball field"),),
        why="typos in the multi-word name; 'fine' merely allows grass",
    ),
    Brief(
        prompt="pavd road good / unpavd road bad",
        voice="robot",
        construct="terse",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("avoided", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="typos in both qualified names",
    ),
    Brief(
        prompt="road good. water no.",
        voice="field",
        construct="terse",
        layers=SAMPLE,
        expect=(("preferred", "road"), ("avoided", "water")),
        routes=(Route("sample", "more_on", "road"), Route("sample", "less_on", "water")),
        why="a bare 'no' is not one of the contract's forbidding phrases, so water is avoided",
    ),
    Brief(
        prompt="Order of preference, best first: trail; road; grass; building.",
        voice="analyst",
        construct="terse",
        layers=SAMPLE,
        expect=(("below", "trail", "road"), ("below", "road", "grass"), ("below", "grass", "building")),
        why="a ranked list; only the order is stated",
    ),
    # ------------------------------------------------------------------------------------------
    # permission: lifting priors, and stay-out wording that forbids
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="Crossing the railway at grade is permitted for this survey, so the corridor need not be avoided.",
        voice="analyst",
        construct="permission",
        layers=NB,
        expect=(("neutral", "railway"), ("not_lethal", "railway")),
        why="permission lifts the railway prior to neutral; no route effect against a flat map",
    ),
    Brief(
        prompt="You're cleared to drive under tree canopy, it's sparse. Keep out of the water, though.",
        voice="robot",
        construct="permission",
        layers=SAMPLE,
        expect=(("neutral", "tree"), ("lethal", "water")),
        routes=(Route("sample", "zero_on", "water"),),
        why="trees merely allowed (prior lifted); 'keep out of' forbids water",
    ),
    Brief(
        prompt="were allowed to walk thru the buildings today, the doors are all open",
        voice="field",
        construct="permission",
        layers=KAMPALA,
        expect=(("neutral", "building"), ("not_lethal", "building")),
        why="permission lifts the building prior; no route effect against a flat map",
    ),
    Brief(
        prompt="The baseball field is off limits during the tournament; grass may be crossed freely.",
        voice="analyst",
        construct="permission",
        layers=SAMPLE,
        expect=(("lethal", "baseball field"), ("neutral", "grass")),
        routes=(Route("sample", "zero_on", "baseball field"),),
        why="'off limits' forbids; grass merely allowed",
    ),
    Brief(
        prompt=(
            "Do not go into the water under any circumstances. Buildings are okay to pass "
            "through; they're derelict shells."
        ),
        voice="robot",
        construct="permission",
        layers=NB,
        expect=(("lethal", "water"), ("neutral", "building")),
        routes=(Route("nb1", "zero_on", "water"), Route("nb2", "zero_on", "water")),
        why="'do not go into' forbids; buildings merely allowed",
    ),
    Brief(
        prompt="stay out of the buildings!! wading thru the water is fine tho, its ankle deep",
        voice="field",
        construct="permission",
        layers=SAMPLE,
        expect=(("lethal", "building"), ("neutral", "water")),
        routes=(Route("sample", "zero_on", "building"),),
        why="'stay out of' forbids; water merely allowed (prior lifted)",
    ),
    Brief(
        prompt="Tree canopy is no obstacle for this platform; it may drive beneath crowns freely.",
        voice="robot",
        construct="permission",
        layers=NEON,
        expect=(("neutral", "tree"), ("not_lethal", "tree")),
        why="'no obstacle' is a permission, not a prohibition; trees lifted to neutral",
    ),
    # ------------------------------------------------------------------------------------------
    # clauses: every clause accounted for
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="Prefer the trail network. Deliverables are due at the county office on Thursday.",
        voice="analyst",
        construct="clauses",
        layers=SAMPLE,
        expect=(("preferred", "trail"), ("unread", "Thursday")),
        routes=(Route("sample", "more_on", "trail"),),
        why="the deadline has no route meaning and must be reported, not dropped",
    ),
    Brief(
        prompt="Avoid the vegetation. Beep twice on arrival.",
        voice="robot",
        construct="clauses",
        layers=NB,
        expect=(("avoided", "vegetation"), ("unread", "beep")),
        routes=(Route("nb1", "less_on", "vegetation"),),
        why="an actuator instruction the costmap cannot express",
    ),
    Brief(
        prompt="hey its sam, running late sorry. avoid the grass, its muddy. bring the blue tablet",
        voice="field",
        construct="clauses",
        layers=SAMPLE,
        expect=(("avoided", "grass"), ("unread", "tablet")),
        routes=(Route("sample", "less_on", "grass"),),
        why="chatter around one real rule; the packing request is reported as unread",
    ),
    Brief(
        prompt="Prefer roads, avoid water, and treat the railway as neutral.",
        voice="analyst",
        construct="clauses",
        layers=NB,
        expect=(("preferred", "road"), ("avoided", "water"), ("neutral", "railway"), ("all_read",)),
        routes=(Route("nb1", "more_on", "road"), Route("nb2", "less_on", "water")),
        why="three plain clauses, all of them costmap rules",
    ),
    Brief(
        prompt="Stay out of the buildings and keep at least 4 m from them.",
        voice="robot",
        construct="clauses",
        layers=MASSACHUSETTS,
        expect=(("lethal", "building"), ("keep_out", "building", 4), ("all_read",)),
        routes=(Route("massachusetts", "keeps", "building", 4),),
        why="both clauses are rules: 'stay out of' forbids, 'at least 4 m' is an unhedged minimum",
    ),
    Brief(
        prompt="stay near the trees, take a pic every 50 steps, and dont forget sunscreen",
        voice="field",
        construct="clauses",
        layers=NEON,
        expect=(("graded_toward", "tree", None), ("unread", "pic"), ("unread", "sunscreen")),
        routes=(Route("neon", "closer", "tree"),),
        why="one rule, two clauses with no route meaning that must be reported",
    ),
    Brief(
        prompt="Avoid the water, then return to the launch point once the goal is reached.",
        voice="robot",
        construct="clauses",
        layers=SAMPLE,
        expect=(("avoided", "water"), ("unread", "launch")),
        routes=(Route("sample", "less_on", "water"),),
        why="a return leg is a mission step, not a cost; it must be reported",
    ),
]

#: Cases retired because their expectation contradicts the cost-scale contract (id -> reason).
DOUBTFUL: dict[str, str] = {}
