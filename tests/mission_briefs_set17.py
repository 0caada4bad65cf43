"""Mission briefs, set 17: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench or the briefs of earlier sets: only the contract (``tests/mission_briefs.py``
and its format test ``tests/test_mission_briefs.py``), the scene index (``../shared/scenes/INDEX.md``
and the scenes' ``classes.json``) and the first 40 lines of set 16 (for the layout of its module
constants and docstring) were read. It is scored once, at first contact, with
``bench/mission_briefs_report.py --set 17``; that figure is the one that counts, and the set is not
edited afterwards to make the interpreter pass.

The voices are GIS analysts (formal, distances in metres, feet, yards or kilometres), robot
operators (terse, symbolic: ``>``, ``>>``, ``:``, ``key=value``, pseudo-code, lists) and field
crews (chatty, typo-ridden, with asides about weather, people, vehicles and kit that are not
rules). Asides that merely mention a layer ("my truck's parked on the road", "we had lunch by the
water") are checked not to have made a rule. The constructs are ranked preferences ("A before B,
B before C", "A > B > C"), forbidden areas versus plain avoidance, permissions that lift priors,
hard and soft distance rules with numbers, graded nearness, on versus beside, qualified classes
on the Las Vegas scene (tarmac, asphalt, blacktop against dirt tracks and gravel), and clauses
that are noise or name things no layer stands for. The layers of each brief are the class names
of the scene its routes are checked on, so the route checks run on the real ground truth; briefs
over layers no scene holds (conifers, ruined buildings, shallow ponds) carry no route checks.
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

FT = 0.3048
YD = 0.9144

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------------------------------
    # distance_hard: distance rules worded as absolute
    # ------------------------------------------------------------------------------------------
    Brief(
        "Plan the survey traverse so that it never comes closer than 15 m to any building. "
        "Water crossings should be avoided.",
        "analyst",
        "distance_hard",
        NB,
        (
            ("keep_out", "building", 15),
            ("avoided", "water"),
            ("not_lethal", "water"),
        ),
        (
            Route("nb1", "keeps", "building", 15),
            Route("nb1", "less_on", "water"),
        ),
    ),
    Brief(
        "ok so we gotta be at least 30 feet from the water at all times, insurance thing. roads are "
        "fine to walk on. its sunny out so bring sunscreen lol",
        "field",
        "distance_hard",
        NB,
        (
            ("keep_out", "water", 30 * FT),
            ("neutral", "road"),
        ),
        (Route("nb2", "keeps", "water", 30 * FT),),
        why="'at all times' makes the 30 ft absolute; 'roads are fine' allows them (neutral); "
        "the sunscreen is an aside.",
    ),
    Brief(
        "building: min_clearance=5m (hard)",
        "robot",
        "distance_hard",
        BUILDINGS,
        (("keep_out", "building", 5),),
        (Route("massachusetts", "keeps", "building", 5),),
    ),
    Brief(
        "The route must not pass within 20 yards of the baseball field at any point.",
        "analyst",
        "distance_hard",
        SAMPLE,
        (("keep_out", "baseball field", 20 * YD),),
        (Route("sample", "keeps", "baseball field", 20 * YD),),
    ),
    Brief(
        "HARD railway >= 25m\nHARD building >= 10m\nelse shortest",
        "robot",
        "distance_hard",
        NB,
        (
            ("keep_out", "railway", 25),
            ("keep_out", "building", 10),
        ),
        (
            Route("nb2", "keeps", "railway", 25),
            Route("nb2", "keeps", "building", 10),
        ),
    ),
    Brief(
        "stay a good 3 metres off every tree, no exceptions. the canopy drops branches when its windy like today",
        "field",
        "distance_hard",
        TREES,
        (("keep_out", "tree", 3),),
        (Route("neon", "keeps", "tree", 3),),
        why="'no exceptions' makes the 3 m absolute; the wind is the reason, not a rule.",
    ),
    Brief(
        "Maintain a clearance of no less than 50 ft from every structure; the clearance is mandatory.",
        "analyst",
        "distance_hard",
        BUILDINGS,
        (("keep_out", "building", 50 * FT),),
        (
            Route("massachusetts", "keeps", "building", 50 * FT),
            Route("kampala", "keeps", "building", 50 * FT),
        ),
        why="'structure' is the building layer; in Kampala no route can keep 15 m, so the check "
        "is the fewest metres inside the zone.",
    ),
    Brief(
        "keep a safe distance from the railway at all times, no ifs no buts. we lost a rover to a "
        "freight train last spring",
        "field",
        "distance_hard",
        NB,
        (("keep_out", "railway", None),),
        (Route("nb2", "keeps", "railway", 1),),
        why="absolute wording with no number: a hard zone of the default width.",
    ),
    # ------------------------------------------------------------------------------------------
    # distance_soft: distance rules worded softly
    # ------------------------------------------------------------------------------------------
    Brief(
        "Where practicable, keep roughly 20 m from the railway; this is a preference rather than a constraint.",
        "analyst",
        "distance_soft",
        NB,
        (
            ("soft_zone", "railway", 20),
            ("not_lethal", "railway"),
        ),
        (Route("nb2", "farther", "railway"),),
    ),
    Brief(
        "try to keep some distance from the houses if u can, folks get nervous about the drone. "
        "not a big deal if you have to pass close tho",
        "field",
        "distance_soft",
        BUILDINGS,
        (
            ("soft_zone", "building", None),
            ("not_lethal", "building"),
        ),
        (Route("massachusetts", "farther", "building"),),
        why="'houses' are the building layer; 'not a big deal if you pass close' makes it soft.",
    ),
    Brief(
        "water: soft clearance 10m\nroad: ok",
        "robot",
        "distance_soft",
        SAMPLE,
        (
            ("soft_zone", "water", 10),
            ("neutral", "road"),
        ),
        (Route("sample", "farther", "water"),),
    ),
    Brief(
        "if possible keep like 2m from the tree crowns, ideally, but squeezing past is ok when theres no room",
        "field",
        "distance_soft",
        TREES,
        (("soft_zone", "tree", 2),),
        (Route("neon", "farther", "tree"),),
    ),
    Brief(
        "It would be preferable for the path to remain about 15 feet clear of the paved roads, though "
        "brief approaches are acceptable.",
        "analyst",
        "distance_soft",
        VEGAS,
        (("soft_zone", "paved road", 15 * FT),),
        (Route("vegas", "farther", "paved road"),),
    ),
    # ------------------------------------------------------------------------------------------
    # graded_away: the further the better
    # ------------------------------------------------------------------------------------------
    Brief(
        "the further from the railway the better honestly, trains come thru here with no warning",
        "field",
        "graded_away",
        NB,
        (("graded_away", "railway", None),),
        (Route("nb2", "farther", "railway"),),
    ),
    Brief(
        "buildings: keep well away",
        "robot",
        "graded_away",
        BUILDINGS,
        (("graded_away", "building", None),),
        (
            Route("massachusetts", "farther", "building"),
            Route("kampala", "farther", "building"),
        ),
    ),
    Brief(
        "Proximity to water should be penalised progressively, the penalty falling to nothing at 30 metres.",
        "analyst",
        "graded_away",
        SAMPLE,
        (("graded_away", "water", 30),),
        (Route("sample", "farther", "water"),),
    ),
    Brief(
        "dont go near the water, my boots leak. roads r fine",
        "field",
        "graded_away",
        NB,
        (
            ("graded_away", "water", None),
            ("neutral", "road"),
        ),
        (Route("nb1", "farther", "water"),),
    ),
    Brief(
        "tree -> the farther the better (falloff 5 m)",
        "robot",
        "graded_away",
        TREES,
        (("graded_away", "tree", 5),),
        (Route("neon", "farther", "tree"),),
    ),
    Brief(
        "Prefer alignments that stay well away from paved roads; the greater the separation, the better.",
        "analyst",
        "graded_away",
        VEGAS,
        (("graded_away", "paved road", None),),
        (Route("vegas", "farther", "paved road"),),
    ),
    # ------------------------------------------------------------------------------------------
    # graded_toward: the nearer the better
    # ------------------------------------------------------------------------------------------
    Brief(
        "stay close to the road teh whole way, we're radioing from the truck and signal is awful out here",
        "field",
        "graded_toward",
        NB,
        (("graded_toward", "road", None),),
        (Route("nb1", "closer", "road"),),
    ),
    Brief(
        "The route should hug the trail as closely as possible and remain within sight of it throughout.",
        "analyst",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "trail", None),),
        (Route("sample", "closer", "trail"),),
    ),
    Brief(
        "near(paved road): better\nunpaved road: avoid",
        "robot",
        "graded_toward",
        VEGAS,
        (
            ("graded_toward", "paved road", None),
            ("avoided", "unpaved road"),
        ),
        (Route("vegas", "closer", "paved road"),),
    ),
    Brief(
        "keep near the water if u can, we're sampling along the shore and the cooler is heavy",
        "field",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "water", None),),
        (Route("sample", "closer", "water"),),
    ),
    Brief(
        "Keep within sight of the buildings; the closer to them the better.",
        "analyst",
        "graded_toward",
        BUILDINGS,
        (("graded_toward", "building", None),),
        (Route("massachusetts", "closer", "building"),),
    ),
    # ------------------------------------------------------------------------------------------
    # on_beside: along X but not on X
    # ------------------------------------------------------------------------------------------
    Brief(
        "walk along the river bank but not in the water pls, we've got waders but still",
        "field",
        "on_beside",
        NB,
        (("beside", "water"),),
        (Route("nb1", "beside", "water", 5),),
        why="'river' is the water layer; the waders are an aside, not a permission.",
    ),
    Brief(
        "follow: road edge\non road: no",
        "robot",
        "on_beside",
        NB,
        (("beside", "road"),),
        (Route("nb1", "beside", "road", 5),),
    ),
    Brief(
        "Proceed along the shoulder of the paved road, never on the carriageway itself.",
        "analyst",
        "on_beside",
        VEGAS,
        (("beside", "paved road"),),
        (Route("vegas", "beside", "paved road", 5),),
    ),
    Brief(
        "follow the trails edge, not on it - theres a fun run on the trail today, runners everywhere",
        "field",
        "on_beside",
        SAMPLE,
        (("beside", "trail"),),
        (Route("sample", "beside", "trail", 5),),
    ),
    Brief(
        "Track alongside the railway at a short distance; the rails themselves must never be entered.",
        "analyst",
        "on_beside",
        NB,
        (
            ("beside", "railway"),
            ("lethal", "railway"),
        ),
        (
            Route("nb2", "beside", "railway", 5),
            Route("nb2", "zero_on", "railway"),
        ),
    ),
    Brief(
        "skirt round the edge of the tree crowns, dont go under them, the sensor needs open sky",
        "field",
        "on_beside",
        TREES,
        (("beside", "tree"),),
        (Route("neon", "beside", "tree", 2),),
    ),
    # ------------------------------------------------------------------------------------------
    # qualified: paved / unpaved, conifer / deciduous, excepted sub-areas
    # ------------------------------------------------------------------------------------------
    Brief(
        "stick to the tarmac, the dirt tracks are off limits after the rain, total mud",
        "field",
        "qualified",
        VEGAS,
        (
            ("preferred", "paved road"),
            ("lethal", "unpaved road"),
        ),
        (
            Route("vegas", "more_on", "paved road"),
            Route("vegas", "zero_on", "unpaved road"),
        ),
    ),
    Brief(
        "paved road > unpaved road > off-road",
        "robot",
        "qualified",
        VEGAS,
        (
            ("below", "paved road", "unpaved road"),
            ("preferred", "paved road"),
            ("preferred", "unpaved road"),
        ),
        (Route("vegas", "more_on", "paved road"),),
        why="'off-road' is unlabelled ground (0.5): both road classes rank above it, so both are preferred.",
    ),
    Brief(
        "Gravel roads are to be preferred over asphalt; asphalt carries traffic and should be avoided.",
        "analyst",
        "qualified",
        VEGAS,
        (
            ("preferred", "unpaved road"),
            ("avoided", "paved road"),
            ("below", "unpaved road", "paved road"),
        ),
        (Route("vegas", "less_on", "paved road"),),
    ),
    Brief(
        "we're on dirt bikes so the gravel tracks are perfect. blacktop's fine too but no need to go looking for it",
        "field",
        "qualified",
        VEGAS,
        (
            ("preferred", "unpaved road"),
            ("neutral", "paved road"),
            ("below", "unpaved road", "paved road"),
        ),
        (Route("vegas", "more_on", "unpaved road"),),
    ),
    Brief(
        "Route through the deciduous stands where possible; the conifer plantation is off limits "
        "during the spraying programme.",
        "analyst",
        "qualified",
        ("conifer", "deciduous tree", "road"),
        (
            ("preferred", "deciduous tree"),
            ("lethal", "conifer"),
        ),
    ),
    Brief(
        "building: avoid | ruined building: ok",
        "robot",
        "qualified",
        ("building", "ruined building", "road"),
        (
            ("avoided", "building"),
            ("neutral", "ruined building"),
        ),
    ),
    Brief(
        "stay out of the water except the shallow pond by the car park, thats fine to wade thru",
        "field",
        "qualified",
        ("water", "shallow pond", "grass"),
        (
            ("lethal", "water"),
            ("not_lethal", "shallow pond"),
        ),
    ),
    # ------------------------------------------------------------------------------------------
    # terse: symbolic briefs, rankings, typos in multi-word names
    # ------------------------------------------------------------------------------------------
    Brief(
        "pref: trail > road > grass; water = last resort",
        "robot",
        "terse",
        SAMPLE,
        (
            ("below", "trail", "road"),
            ("below", "road", "grass"),
            ("below", "grass", "water"),
            ("preferred", "trail"),
        ),
        (Route("sample", "more_on", "trail"),),
    ),
    Brief(
        "water: no-go\nrailway: no-go\nroad: ++",
        "robot",
        "terse",
        NB,
        (
            ("lethal", "water"),
            ("lethal", "railway"),
            ("preferred", "road"),
        ),
        (
            Route("nb1", "zero_on", "water"),
            Route("nb2", "zero_on", "railway"),
            Route("nb1", "more_on", "road"),
        ),
    ),
    Brief(
        "basebal feild: avoid\nbuildngs: avoid\ntrial: pref",
        "robot",
        "terse",
        SAMPLE,
        (
            ("avoided", "baseball field"),
            ("avoided", "building"),
            ("preferred", "trail"),
        ),
        (
            Route("sample", "less_on", "baseball field"),
            Route("sample", "more_on", "trail"),
        ),
        why="typos: 'basebal feild', 'buildngs', 'trial' for trail (the only layer it can mean).",
    ),
    Brief(
        "pavedroad: ok\nunpaved rd: no-go",
        "robot",
        "terse",
        VEGAS,
        (
            ("neutral", "paved road"),
            ("lethal", "unpaved road"),
        ),
        (Route("vegas", "zero_on", "unpaved road"),),
    ),
    Brief(
        "bldg >> open ground",
        "robot",
        "terse",
        BUILDINGS,
        (
            ("avoided", "building"),
            ("not_lethal", "building"),
        ),
        (Route("massachusetts", "less_on", "building"),),
        why="'>>' ranks buildings far dearer than open ground: strongly avoided, not forbidden.",
    ),
    Brief(
        "tree: fine (rover clears the canopy)",
        "robot",
        "terse",
        TREES,
        (("neutral", "tree"),),
        why="'fine' allows the trees, lifting their prior to neutral; no route differs from flat.",
    ),
    # ------------------------------------------------------------------------------------------
    # permission: permissions that lift priors, and stay-out wording that forbids
    # ------------------------------------------------------------------------------------------
    Brief(
        "the sheds out there are all empty ruins, no need to avoid them. we'll be done by 4 anyway",
        "field",
        "permission",
        BUILDINGS,
        (
            ("neutral", "building"),
            ("not_lethal", "building"),
        ),
        why="'sheds' are the building layer; 'no need to avoid' lifts the prior to neutral.",
    ),
    Brief(
        "creek's dry this time of year so dont worry about the water, just go straight across. still "
        "stay out of the railway tho",
        "field",
        "permission",
        NB,
        (
            ("neutral", "water"),
            ("lethal", "railway"),
        ),
        (Route("nb2", "zero_on", "railway"),),
    ),
    Brief(
        "The railway line is decommissioned and may be crossed and walked freely; buildings are still to be avoided.",
        "analyst",
        "permission",
        NB,
        (
            ("neutral", "railway"),
            ("not_lethal", "railway"),
            ("avoided", "building"),
        ),
        (Route("nb2", "less_on", "building"),),
    ),
    Brief(
        "water: ok (frozen)\nbuilding: keep out",
        "robot",
        "permission",
        SAMPLE,
        (
            ("neutral", "water"),
            ("lethal", "building"),
        ),
        (Route("sample", "zero_on", "building"),),
    ),
    Brief(
        "All structures in the survey area are to be treated as no-go zones; entry into any building is prohibited.",
        "analyst",
        "permission",
        BUILDINGS,
        (("lethal", "building"),),
        (
            Route("kampala", "zero_on", "building"),
            Route("massachusetts", "zero_on", "building"),
        ),
    ),
    Brief(
        "trees r no problem for the rover, it drives right under the canopy, dont bother avoiding em",
        "field",
        "permission",
        TREES,
        (
            ("neutral", "tree"),
            ("not_lethal", "tree"),
        ),
    ),
    Brief(
        "the ball field's closed for the season so crossing it is totally fine, but never enter the "
        "water, that pond is deep",
        "field",
        "permission",
        SAMPLE,
        (
            ("neutral", "baseball field"),
            ("lethal", "water"),
        ),
        (Route("sample", "zero_on", "water"),),
    ),
    # ------------------------------------------------------------------------------------------
    # clauses: every clause accounted for (noise, things no layer stands for, rankings in words)
    # ------------------------------------------------------------------------------------------
    Brief(
        "avoid the power lines and the buildings, also grab coffee on the way lol",
        "field",
        "clauses",
        NB,
        (
            ("unread", "power lines"),
            ("avoided", "building"),
        ),
        (Route("nb1", "less_on", "building"),),
    ),
    Brief(
        "Avoid the pylons and the water. Otherwise take the shortest path.",
        "analyst",
        "clauses",
        SAMPLE,
        (
            ("unread", "pylons"),
            ("avoided", "water"),
        ),
        (Route("sample", "less_on", "water"),),
    ),
    Brief(
        "railway=avoid; road=prefer; water=avoid",
        "robot",
        "clauses",
        NB,
        (
            ("avoided", "railway"),
            ("preferred", "road"),
            ("avoided", "water"),
            ("all_read",),
        ),
        (
            Route("nb1", "more_on", "road"),
            Route("nb1", "less_on", "water"),
            Route("nb2", "less_on", "railway"),
        ),
    ),
    Brief(
        "avoid the paved roads, and watch out for the coyotes, saw two yesterday by the wash",
        "field",
        "clauses",
        VEGAS,
        (
            ("avoided", "paved road"),
            ("unread", "coyotes"),
        ),
        (Route("vegas", "less_on", "paved road"),),
    ),
    Brief(
        "Remain clear of the helipad and avoid overflying the buildings.",
        "analyst",
        "clauses",
        BUILDINGS,
        (
            ("unread", "helipad"),
            ("avoided", "building"),
        ),
        (Route("massachusetts", "less_on", "building"),),
    ),
    Brief(
        "grass: prefer\ntrail: prefer\nfountain: avoid",
        "robot",
        "clauses",
        SAMPLE,
        (
            ("preferred", "grass"),
            ("preferred", "trail"),
            ("unread", "fountain"),
        ),
        (Route("sample", "more_on", "grass"),),
    ),
    Brief(
        "Prefer the roads, avoid the vegetation, and keep out of the water.",
        "analyst",
        "clauses",
        NB,
        (
            ("preferred", "road"),
            ("avoided", "vegetation"),
            ("lethal", "water"),
            ("all_read",),
        ),
        (
            Route("nb1", "more_on", "road"),
            Route("nb1", "less_on", "vegetation"),
            Route("nb1", "zero_on", "water"),
        ),
    ),
    Brief(
        "Use the trail before the road, and the road before the grass.",
        "analyst",
        "clauses",
        SAMPLE,
        (
            ("below", "trail", "road"),
            ("below", "road", "grass"),
            ("all_read",),
        ),
        (Route("sample", "more_on", "trail"),),
    ),
    Brief(
        "roads first, then vegetation if u have to, water only as a last resort. its gonna rain so be quick",
        "field",
        "clauses",
        NB,
        (
            ("below", "road", "vegetation"),
            ("below", "vegetation", "water"),
            ("preferred", "road"),
            ("not_lethal", "water"),
        ),
        (Route("nb1", "more_on", "road"),),
        why="a last resort is dearest but still allowed; the rain is an aside.",
    ),
    Brief(
        "cost(trail) < cost(grass) < cost(tree)\nbuilding: forbidden",
        "robot",
        "clauses",
        SAMPLE,
        (
            ("below", "trail", "grass"),
            ("below", "grass", "tree"),
            ("lethal", "building"),
        ),
        (Route("sample", "zero_on", "building"),),
    ),
    Brief(
        "mission: survey-17\nweather: windy\nbuilding: avoid\nroad: prefer",
        "robot",
        "clauses",
        NB,
        (
            ("avoided", "building"),
            ("preferred", "road"),
            ("unread", "windy"),
        ),
        (Route("nb1", "more_on", "road"),),
        why="the weather line is metadata, not a rule: it must be reported, not silently dropped.",
    ),
    Brief(
        "avoid the railway pls. my truck's parked on the road by the big building, come find me after",
        "field",
        "clauses",
        NB,
        (
            ("avoided", "railway"),
            ("neutral", "road"),
            ("not_lethal", "building"),
        ),
        (Route("nb2", "less_on", "railway"),),
        why="the truck on the road by the building is an aside: the road stays neutral and the "
        "building keeps its prior.",
    ),
    Brief(
        "avoid the baseball field, kids have practice. we had lunch by the water earlier, lovely spot",
        "field",
        "clauses",
        SAMPLE,
        (
            ("avoided", "baseball field"),
            ("avoided", "water"),
            ("not_lethal", "water"),
        ),
        (Route("sample", "less_on", "baseball field"),),
        why="lunch by the water is an aside: the water keeps its prior (avoided), not preferred.",
    ),
]
