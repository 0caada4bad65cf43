"""Mission briefs, set 18: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench or the briefs of earlier sets: only the contract (``tests/mission_briefs.py``
and its format test ``tests/test_mission_briefs.py``), the scene index (``../shared/scenes/INDEX.md``
and the scenes' ``classes.json``) and the first 40 lines of set 17 (for the layout of its module
constants and docstring) were read. It is scored once, at first contact, with
``bench/mission_briefs_report.py --set 18``; that figure is the one that counts, and the set is not
edited afterwards to make the interpreter pass.

The voices are GIS analysts (formal, report and permit language, distances in metres, feet, yards
or kilometres), robot operators (terse and symbolic: ``>``, ``>>``, ``key: value``, YAML-ish lists,
config lines, pseudo-code) and field crews (chatty, texting style, typos, asides about heat, rain,
geese, batteries and vans that are not rules), some of them writing in non-native English. The
constructs are ranked preferences in words and symbols ("A over B", "rather A than B", "A before
B", "A is better than B", "A >> B >> C"), forbidden areas against plain avoidance, permissions that
lift priors (unoccupied outbuildings, frozen lakes, sparse trees, a decommissioned line), hard and
soft distance rules with numbers, graded nearness in both directions, on versus beside, qualified
classes on the Las Vegas scene (tarmac, asphalt, sealed roads against dirt, sand and gravel), and
clauses naming things no layer stands for (power lines, culverts, cattle grids, solar panels),
which must be reported unread. Asides that merely mention a layer are checked not to have made a
rule (the layer keeps its prior). The layers of each brief are the class names of the scene its
routes are checked on; briefs over layers no scene holds carry no route checks.
"""

from __future__ import annotations

from .mission_briefs import Brief, Route

#: New Brunswick clips (nb1, nb2).
NB = ("building", "road", "water", "vegetation", "railway")
#: Las Vegas roads.
VEGAS = ("paved road", "unpaved road")
#: Kampala and Massachusetts building footprints.
BUILDINGS = ("building",)
#: NEON forest plot tree crowns.
TREES = ("tree",)
#: The bundled sample scene.
SAMPLE = ("grass", "road", "trail", "tree", "water", "building", "baseball field")

#: Briefs whose expectation was later found to contradict the cost-scale contract (none yet).
DOUBTFUL: dict[str, str] = {}

#: Metres in a foot and in a yard (briefs written in imperial units).
FT = 0.3048
YD = 0.9144


BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------------------------------
    # distance_hard: absolute wording, a keep-out zone of the stated metres
    # ------------------------------------------------------------------------------------------
    Brief(
        "The survey line shall remain a minimum of 15 m from every building at all times; the road "
        "network is the preferred corridor.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "building", 15), ("preferred", "road")),
        (Route("nb1", "keeps", "building", 15), Route("nb1", "more_on", "road")),
    ),
    Brief(
        "Permit condition 4(b): no part of the traverse may come within 50 feet of the rail corridor.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "railway", 50 * FT),),
        (Route("nb2", "keeps", "railway", 50 * FT),),
        why="'no part may come within' is absolute wording; 50 ft is 15.24 m",
    ),
    Brief(
        "clearance.building.min_m = 6   # hard limit, do not relax",
        "robot",
        "distance_hard",
        BUILDINGS,
        (("keep_out", "building", 6),),
        (Route("massachusetts", "keeps", "building", 6),),
    ),
    Brief(
        "ok so the landowner was v clear, we NEVER get closer than 20 yards to the houses, dont care "
        "how long it takes. rain coming after 3 so lets move",
        "field",
        "distance_hard",
        BUILDINGS,
        (("keep_out", "building", 20 * YD),),
        (Route("massachusetts", "keeps", "building", 20 * YD),),
        why="'never closer than' is absolute; houses are the building layer; the rain is an aside",
    ),
    Brief(
        "A standoff of no less than 0.03 km from open water is to be maintained throughout the operation.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "water", 30),),
        (Route("nb1", "keeps", "water", 30),),
    ),
    Brief(
        "Under no circumstances may the path pass within 2 m of a building footprint.",
        "analyst",
        "distance_hard",
        BUILDINGS,
        (("keep_out", "building", 2),),
        (Route("kampala", "keeps", "building", 2),),
    ),
    Brief(
        "NEVER within 10 ft of the pond!! the geese there will go for the robot, trust me",
        "field",
        "distance_hard",
        SAMPLE,
        (("keep_out", "water", 10 * FT),),
        (Route("sample", "keeps", "water", 10 * FT),),
    ),
    Brief(
        "HARD dist(tree) >= 3 m",
        "robot",
        "distance_hard",
        TREES,
        (("keep_out", "tree", 3),),
        (Route("neon", "keeps", "tree", 3),),
    ),
    # ------------------------------------------------------------------------------------------
    # distance_soft: soft wording, a soft zone with the number kept
    # ------------------------------------------------------------------------------------------
    Brief(
        "Where practicable the path should hold roughly 10 m off buildings; this is a recommendation, "
        "not a constraint.",
        "analyst",
        "distance_soft",
        NB,
        (("soft_zone", "building", 10), ("not_lethal", "building")),
        (Route("nb1", "farther", "building"),),
    ),
    Brief(
        "try to leave 5 metres or so between us and the trees if u can, no biggie if u cant. "
        "someone grab the spare batteries pls",
        "field",
        "distance_soft",
        TREES,
        (("soft_zone", "tree", 5), ("not_lethal", "tree")),
        (Route("neon", "farther", "tree"),),
    ),
    Brief(
        "water.soft_buffer_m: 7",
        "robot",
        "distance_soft",
        NB,
        (("soft_zone", "water", 7),),
        (Route("nb1", "farther", "water"),),
    ),
    Brief(
        "Ideally the alignment sits about 30 ft off the tarmac, although crossing it is acceptable.",
        "analyst",
        "distance_soft",
        VEGAS,
        (("soft_zone", "paved road", 30 * FT), ("not_lethal", "paved road")),
        (Route("vegas", "farther", "paved road"),),
        why="tarmac is the paved road; 'ideally' and 'crossing is acceptable' make the zone soft",
    ),
    Brief(
        "If possible please keep a distance of 12 meter from the rail, it is preferable but not obligatory.",
        "field",
        "distance_soft",
        NB,
        (("soft_zone", "railway", 12), ("not_lethal", "railway")),
        (Route("nb2", "farther", "railway"),),
    ),
    Brief(
        "would be nice to stay 8 m-ish back from the road, cars fly past here",
        "field",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "road", 8), ("not_lethal", "road")),
        (Route("sample", "farther", "road"),),
    ),
    # ------------------------------------------------------------------------------------------
    # graded_away: priced by distance, the closer the dearer
    # ------------------------------------------------------------------------------------------
    Brief(
        "The further the alignment lies from the watercourse, the better.",
        "analyst",
        "graded_away",
        NB,
        (("graded_away", "water", None),),
        (Route("nb1", "farther", "water"),),
    ),
    Brief(
        "dont go near the houses, the folks there get twitchy about robots lol",
        "field",
        "graded_away",
        BUILDINGS,
        (("graded_away", "building", None),),
        (Route("kampala", "farther", "building"),),
    ),
    Brief(
        "building: as far as possible",
        "robot",
        "graded_away",
        BUILDINGS,
        (("graded_away", "building", None),),
        (Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        "Proximity to tree crowns is to be penalised, the penalty fading to nothing beyond 15 m.",
        "analyst",
        "graded_away",
        TREES,
        (("graded_away", "tree", 15),),
        (Route("neon", "farther", "tree"),),
    ),
    Brief(
        "give the tracks a wide berth, the more room the better. train horn nearly gave me a heart attack yesterday",
        "field",
        "graded_away",
        NB,
        (("graded_away", "railway", None),),
        (Route("nb2", "farther", "railway"),),
    ),
    Brief(
        "Is better when we are more far from the water.",
        "field",
        "graded_away",
        SAMPLE,
        (("graded_away", "water", None),),
        (Route("sample", "farther", "water"),),
    ),
    # ------------------------------------------------------------------------------------------
    # graded_toward: cheaper the nearer
    # ------------------------------------------------------------------------------------------
    Brief(
        "The route should remain in close proximity to the road network wherever feasible.",
        "analyst",
        "graded_toward",
        NB,
        (("graded_toward", "road", None),),
        (Route("nb1", "closer", "road"),),
    ),
    Brief(
        "stick close to the treeline so we get some shade, its like 35 degrees out here",
        "field",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "tree", None),),
        (Route("sample", "closer", "tree"),),
    ),
    Brief(
        "stay_near: paved road",
        "robot",
        "graded_toward",
        VEGAS,
        (("graded_toward", "paved road", None),),
        (Route("vegas", "closer", "paved road"),),
    ),
    Brief(
        "The operator is to keep the vehicle within sight of the baseball field for the duration.",
        "analyst",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "baseball field", None),),
        (Route("sample", "closer", "baseball field"),),
    ),
    Brief(
        "keep near the buildings if ya can, the wifi relay is up on one of the roofs",
        "field",
        "graded_toward",
        BUILDINGS,
        (("graded_toward", "building", None),),
        (Route("massachusetts", "closer", "building"),),
    ),
    # ------------------------------------------------------------------------------------------
    # on_beside: along X, not on X
    # ------------------------------------------------------------------------------------------
    Brief(
        "Walk the river bank, but at no point enter the water itself.",
        "analyst",
        "on_beside",
        NB,
        (("beside", "water"),),
        (Route("nb1", "beside", "water", 5),),
    ),
    Brief(
        "follow the edge of the road, NOT on it, trucks come thru here fast",
        "field",
        "on_beside",
        NB,
        (("beside", "road"),),
        (Route("nb1", "beside", "road", 5),),
    ),
    Brief(
        "along: paved road  # shoulder only, wheels never on the asphalt",
        "robot",
        "on_beside",
        VEGAS,
        (("beside", "paved road"),),
        (Route("vegas", "beside", "paved road", 4),),
    ),
    Brief(
        "Route along the margins of the trail rather than on the trail surface proper.",
        "analyst",
        "on_beside",
        SAMPLE,
        (("beside", "trail"),),
        (Route("sample", "beside", "trail", 4),),
    ),
    Brief(
        "We go next to the railway line, but never on the rails itself.",
        "field",
        "on_beside",
        NB,
        (("beside", "railway"),),
        (Route("nb2", "beside", "railway", 5),),
    ),
    Brief(
        "skirt round the pond, dont get the wheels wet tho",
        "field",
        "on_beside",
        SAMPLE,
        (("beside", "water"),),
        (Route("sample", "beside", "water", 5),),
    ),
    # ------------------------------------------------------------------------------------------
    # qualified: paved against unpaved on the Las Vegas scene, and qualified layers no scene holds
    # ------------------------------------------------------------------------------------------
    Brief(
        "Tarmac is preferred; dirt tracks are to be avoided.",
        "analyst",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road"), ("below", "paved road", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        "Gravel is preferred over tarmac for the tracked platform.",
        "analyst",
        "qualified",
        VEGAS,
        (("below", "unpaved road", "paved road"), ("preferred", "unpaved road")),
    ),
    Brief(
        "Unsealed roads are closed to the survey vehicle; sealed roads may be used without restriction.",
        "analyst",
        "qualified",
        VEGAS,
        (("lethal", "unpaved road"), ("not_lethal", "paved road")),
        (Route("vegas", "zero_on", "unpaved road"),),
        why="'closed to' forbids the unsealed (unpaved) roads; 'used without restriction' is a plain allowance",
    ),
    Brief(
        "paved road: 0.2\nunpaved road: 0.8",
        "robot",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
        why="explicit costs on the 0..1 scale: 0.2 below neutral, 0.8 above",
    ),
    Brief(
        "The asphalt road is more good than the sand road, please use it.",
        "field",
        "qualified",
        VEGAS,
        (("below", "paved road", "unpaved road"), ("preferred", "paved road")),
        (Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        "dirt roads are our best bet, blacktop only if we really have to",
        "field",
        "qualified",
        VEGAS,
        (("below", "unpaved road", "paved road"), ("preferred", "unpaved road"), ("not_lethal", "paved road")),
    ),
    Brief(
        "Conifer stands are too dense for the rover and should be avoided; deciduous woodland is fine.",
        "analyst",
        "qualified",
        ("conifer", "deciduous tree"),
        (("avoided", "conifer"), ("not_lethal", "deciduous tree"), ("below", "deciduous tree", "conifer")),
        why="layers no scene holds: no route checks",
    ),
    # ------------------------------------------------------------------------------------------
    # terse: symbolic, lists, config lines, typos in multi-word names
    # ------------------------------------------------------------------------------------------
    Brief(
        "road >> grass >> tree",
        "robot",
        "terse",
        SAMPLE,
        (("below", "road", "grass"), ("below", "grass", "tree")),
        (Route("sample", "more_on", "road"), Route("sample", "less_on", "tree")),
    ),
    Brief(
        "- avoid: water\n- avoid: railway\n- prefer: road",
        "robot",
        "terse",
        NB,
        (("avoided", "water"), ("avoided", "railway"), ("preferred", "road")),
        (Route("nb1", "more_on", "road"), Route("nb1", "less_on", "water")),
    ),
    Brief(
        "nogo=building; pref=trail",
        "robot",
        "terse",
        SAMPLE,
        (("lethal", "building"), ("preferred", "trail")),
        (Route("sample", "zero_on", "building"), Route("sample", "more_on", "trail")),
    ),
    Brief(
        "baseball feild > grass > evrything else",
        "field",
        "terse",
        SAMPLE,
        (("preferred", "baseball field"), ("below", "baseball field", "grass"), ("below", "grass", "road")),
        (Route("sample", "more_on", "baseball field"),),
        why="the typo names the baseball field; the chain ranks grass above the unnamed rest (road)",
    ),
    Brief(
        "if cls in (tree, water): cost = high",
        "robot",
        "terse",
        SAMPLE,
        (("avoided", "tree"), ("avoided", "water")),
        (Route("sample", "less_on", "water"),),
        why="'high' is dear, not impassable",
    ),
    Brief(
        "pavd road ok, unpavd road avoid",
        "robot",
        "terse",
        VEGAS,
        (("not_lethal", "paved road"), ("avoided", "unpaved road"), ("below", "paved road", "unpaved road")),
    ),
    # ------------------------------------------------------------------------------------------
    # permission: lifting priors, and stay-out wording that forbids (against plain avoidance)
    # ------------------------------------------------------------------------------------------
    Brief(
        "The outbuildings on this site are unoccupied and need not be avoided.",
        "analyst",
        "permission",
        NB,
        (("neutral", "building"),),
        why="a permission lifts the building prior to merely allowed (neutral)",
    ),
    Brief(
        "lake's frozen solid this time of yr, just go straight over it if its shorter. cold as heck tho",
        "field",
        "permission",
        NB,
        (("neutral", "water"),),
    ),
    Brief(
        "The trees here are very sparse, is no problem to drive under them.",
        "field",
        "permission",
        TREES,
        (("neutral", "tree"),),
    ),
    Brief(
        "railway: permitted   # line decommissioned 2019",
        "robot",
        "permission",
        NB,
        (("neutral", "railway"),),
    ),
    Brief(
        "All structures are strictly off limits to the UGV.",
        "analyst",
        "permission",
        BUILDINGS,
        (("lethal", "building"),),
        (Route("massachusetts", "zero_on", "building"),),
    ),
    Brief(
        "keep out of the water no matter what, the robot aint waterproof",
        "field",
        "permission",
        NB,
        (("lethal", "water"),),
        (Route("nb1", "zero_on", "water"),),
    ),
    Brief(
        "try not to go thru the trees but its not the end of the world if u do",
        "field",
        "permission",
        TREES,
        (("avoided", "tree"), ("not_lethal", "tree")),
        (Route("neon", "less_on", "tree"),),
        why="plain avoidance, explicitly not forbidding",
    ),
    Brief(
        "Vegetation may be crossed freely; the railway, however, is a no-go area.",
        "analyst",
        "permission",
        NB,
        (("neutral", "vegetation"), ("lethal", "railway")),
        (Route("nb2", "zero_on", "railway"),),
    ),
    Brief(
        "Never enter the baseball field, a game is on this afternoon.",
        "field",
        "permission",
        SAMPLE,
        (("lethal", "baseball field"),),
        (Route("sample", "zero_on", "baseball field"),),
    ),
    # ------------------------------------------------------------------------------------------
    # clauses: ranked chains in words read in full, unread clauses reported, asides make no rule
    # ------------------------------------------------------------------------------------------
    Brief(
        "Avoid the buildings and keep clear of the overhead power lines.",
        "analyst",
        "clauses",
        NB,
        (("avoided", "building"), ("unread", "power line")),
        (Route("nb1", "less_on", "building"),),
    ),
    Brief(
        "avoid the road pls, and mind the cattle grid by the gate",
        "field",
        "clauses",
        NB,
        (("avoided", "road"), ("unread", "cattle grid")),
        (Route("nb1", "less_on", "road"),),
    ),
    Brief(
        "avoid: [water, culvert]",
        "robot",
        "clauses",
        NB,
        (("avoided", "water"), ("unread", "culvert")),
        (Route("nb1", "less_on", "water"),),
    ),
    Brief(
        "Please avoid the mud zones and use the paved road.",
        "field",
        "clauses",
        VEGAS,
        (("preferred", "paved road"), ("unread", "mud")),
        (Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        "go round the solar panels, and dont cross the railway whatever u do",
        "field",
        "clauses",
        NB,
        (("unread", "solar panel"), ("no_cross", "railway")),
        (Route("nb2", "zero_on", "railway"),),
    ),
    Brief(
        "Trails over roads, and roads over grass.",
        "analyst",
        "clauses",
        SAMPLE,
        (("below", "trail", "road"), ("below", "road", "grass"), ("all_read",)),
        (Route("sample", "more_on", "trail"),),
    ),
    Brief(
        "id rather walk the grass than the road, and the road rather than the trees",
        "field",
        "clauses",
        SAMPLE,
        (("below", "grass", "road"), ("below", "road", "tree")),
        (Route("sample", "less_on", "tree"),),
    ),
    Brief(
        "For this traverse roads are better than vegetation, and water is to be avoided.",
        "analyst",
        "clauses",
        NB,
        (("below", "road", "vegetation"), ("avoided", "water"), ("all_read",)),
        (Route("nb1", "more_on", "road"), Route("nb1", "less_on", "water")),
    ),
    Brief(
        "First choice the road, after it the vegetation, the water never.",
        "field",
        "clauses",
        NB,
        (("below", "road", "vegetation"), ("lethal", "water")),
        (Route("nb1", "zero_on", "water"), Route("nb1", "more_on", "road")),
        why="'the water never' forbids the water",
    ),
    Brief(
        "road before grass, grass before trees, n keep out the water",
        "field",
        "clauses",
        SAMPLE,
        (("below", "road", "grass"), ("below", "grass", "tree"), ("lethal", "water")),
        (Route("sample", "zero_on", "water"), Route("sample", "more_on", "road")),
        why="'keep out the water' is 'keep out of' with the 'of' dropped",
    ),
    Brief(
        "had a brew down by the river earlier, nice spot. anyway just use the road where u can",
        "field",
        "clauses",
        NB,
        (("preferred", "road"), ("avoided", "water"), ("not_lethal", "water")),
        (Route("nb1", "more_on", "road"),),
        why="the river is only mentioned in an aside: the water keeps its (avoided) prior",
    ),
    Brief(
        "Prefer the trail; steer clear of the compost heaps.",
        "analyst",
        "clauses",
        SAMPLE,
        (("preferred", "trail"), ("unread", "compost")),
        (Route("sample", "more_on", "trail"),),
    ),
]
