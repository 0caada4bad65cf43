"""Mission briefs, set 22: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench, the docs or the briefs of earlier sets: only the contract
(``tests/mission_briefs.py`` and its format test ``tests/test_mission_briefs.py``), the scene index
(``../shared/scenes/INDEX.md`` and the scenes' ``classes.json``) and the first 40 lines of set 21
(its docstring, for the layout) were read. It is scored once, at first contact, with
``bench/mission_briefs_report.py --set 22``; that figure is the one that counts, and the set is
not edited afterwards to make the interpreter pass.

The voices are a search-and-rescue base on the radio (call signs, "over", "all units"), a
surveyor's field-book shorthand ("TRAV.", "H2O", "min clr", "pvd rd"), contract clauses ("the
Contractor shall ...", "the Operator is prohibited ..."), a wildlife biologist worried about
nesting ospreys and herons, a film location scout, an insurance assessor, Jira tickets ("AC:",
"Given / When / Then"), YAML- and JSON-ish notes, emoji bullet lists, polite questions ("could
you maybe ...?"), hedges ("probably best to ..."), a double negative ("not unwilling to cross"),
numeric ratios ("grass costs 2x road") and shares ("mostly on paved road, say 90 %"), passive
voice, non-native speakers (German word order, Spanish calques, Hindi-English order and fillers
such as "only", "small small", "please"), a teenager's chat ("lol", "tbh", "r", "u", "bc"), a
rambling team email with one real rule and one unmappable rule buried in it, a brief that
withdraws one of its rules at the end, conditional weather and time-of-day asides that no layer
can carry (expected unread) and things the layers do not have (power lines, a substation,
beehives, a barn, a ford kept apart from the water only by its own layer).

Each construct has seven or eight briefs; route checks are given wherever the scene holds the
class. Unmentioned hazards are expected at their priors (avoided) only where a careful reader
would take that for granted; everything else a brief leaves open is left unexpected.
"""

from __future__ import annotations

from tests.mission_briefs import Brief, Route

SAMPLE = ("grass", "road", "trail", "tree", "water", "building", "baseball field")
NB = ("building", "road", "water", "vegetation", "railway")
VEGAS = ("paved road", "unpaved road")
BUILDING = ("building",)
TREE = ("tree",)

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------------------------------
    # distance_hard: absolute distance rules with a number
    # ------------------------------------------------------------------------------------------
    Brief(
        "Rescue Two, this is Base. Route to the casualty. You will not come within ten metres of "
        "the railway, repeat, ten metres, no closer. Over.",
        "field",
        "distance_hard",
        NB,
        (("keep_out", "railway", 10), ("avoided", "building")),
        (Route("nb2", "keeps", "railway", 10),),
        why="buildings are unmentioned hazards and keep their prior",
    ),
    Brief(
        "The Contractor shall maintain a clearance of not less than 12 m from every building for "
        "the duration of the works.",
        "analyst",
        "distance_hard",
        BUILDING,
        (("keep_out", "building", 12),),
        (Route("massachusetts", "keeps", "building", 12),),
    ),
    Brief(
        "TRAV. STN 4 to STN 7. H2O: 20m min clr, hard. Rd OK.",
        "field",
        "distance_hard",
        SAMPLE,
        (("keep_out", "water", 20), ("not_lethal", "road")),
        (Route("sample", "keeps", "water", 20),),
        why="'hard' marks the clearance absolute; 'Rd OK' only allows the road",
    ),
    Brief(
        "The robot must hold always 25 feet distance to the water, this is not negotiable.",
        "robot",
        "distance_hard",
        NB,
        (("keep_out", "water", 7.62),),
        (Route("nb1", "keeps", "water", 7.62),),
        why="25 ft = 7.62 m",
    ),
    Brief(
        "OPS-212. Given the rover is crossing the plot, When it plans a path, Then it never "
        "passes within 3 m of a tree crown. AC: zero tolerance.",
        "robot",
        "distance_hard",
        TREE,
        (("keep_out", "tree", 3),),
        (Route("neon", "keeps", "tree", 3),),
    ),
    Brief(
        "Please, the drone must to stay minimum 3 metres away of the buildings, always, is obligatory.",
        "robot",
        "distance_hard",
        BUILDING,
        (("keep_out", "building", 3),),
        (Route("kampala", "keeps", "building", 3),),
    ),
    Brief(
        "A buffer of 30 m around the water is to be respected absolutely: herons are nesting all along the banks.",
        "field",
        "distance_hard",
        SAMPLE,
        (("keep_out", "water", 30), ("neutral", "grass")),
        (Route("sample", "keeps", "water", 30),),
        why="the herons are the reason for the buffer, not a rule of their own; grass is unmentioned and no hazard",
    ),
    # ------------------------------------------------------------------------------------------
    # distance_soft: distance rules worded softly, the number kept
    # ------------------------------------------------------------------------------------------
    Brief(
        "Could you maybe keep something like 10 metres off the buildings? Not the end of the world if you can't.",
        "analyst",
        "distance_soft",
        BUILDING,
        (("soft_zone", "building", 10), ("not_lethal", "building")),
        (Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        "Probably best to leave a 6 m gap from the trees, but squeeze through if that's the only way.",
        "robot",
        "distance_soft",
        TREE,
        (("soft_zone", "tree", 6), ("not_lethal", "tree")),
        (Route("neon", "farther", "tree"),),
    ),
    Brief(
        "For liability reasons we would prefer the crew stays roughly 20 m back from the railway "
        "line; it is a recommendation, not a condition of cover.",
        "analyst",
        "distance_soft",
        NB,
        (("soft_zone", "railway", 20), ("not_lethal", "railway")),
        (Route("nb2", "farther", "railway"),),
    ),
    Brief(
        "🚜 route notes:\n• 🌊 water: give it ~15 m if it's easy\n• 🛣️ road: fine\n• 🏠 buildings: avoid",
        "field",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "water", 15), ("not_lethal", "road"), ("avoided", "building")),
        (Route("sample", "farther", "water"),),
    ),
    Brief(
        "Sir, from the river 12 metres distance you please keep if possible only, small small "
        "going near it is also okay.",
        "field",
        "distance_soft",
        NB,
        (("soft_zone", "water", 12), ("not_lethal", "water")),
        (Route("nb1", "farther", "water"),),
        why="'river' names the water layer; 'small small going near it is okay' makes it soft",
    ),
    Brief(
        "clearance:\n  railway: 8m   # soft, preference only\n  road: 4m      # soft as well",
        "analyst",
        "distance_soft",
        NB,
        (("soft_zone", "railway", 8), ("soft_zone", "road", 4)),
        (Route("nb2", "farther", "railway"),),
    ),
    Brief(
        "We'd like the camera dolly to stay about thirty metres from the baseball field so the "
        "bleachers don't end up in shot. Nice-to-have; the director can live with it.",
        "field",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "baseball field", 30), ("not_lethal", "baseball field")),
        (Route("sample", "farther", "baseball field"),),
    ),
    # ------------------------------------------------------------------------------------------
    # graded_away: the closer, the dearer
    # ------------------------------------------------------------------------------------------
    Brief(
        "Ospreys nest in the big trees. Please give the trees as wide a berth as you can; the "
        "closer you pass, the more the birds are disturbed.",
        "field",
        "graded_away",
        TREE,
        (("graded_away", "tree", None), ("avoided", "tree")),
        (Route("neon", "farther", "tree"),),
    ),
    Brief(
        "Cost should fall off with distance from the road: heavy right next to it, nothing extra past 25 m.",
        "robot",
        "graded_away",
        NB,
        (("graded_away", "road", 25),),
        (Route("nb1", "farther", "road"),),
    ),
    Brief(
        "ok so like dont go near the water lol, the further the better tbh",
        "field",
        "graded_away",
        SAMPLE,
        (("graded_away", "water", None), ("avoided", "water")),
        (Route("sample", "farther", "water"),),
    ),
    Brief(
        "All units, Base. Hazmat spill reported on the railway. Keep as far from the tracks as "
        "you practically can, distance is your friend. Over.",
        "field",
        "graded_away",
        NB,
        (("graded_away", "railway", None), ("not_lethal", "railway")),
        (Route("nb2", "farther", "railway"),),
        why="'as far as you practically can' grades by distance; nothing forbids the tracks outright",
    ),
    Brief(
        "BLDG proximity penalty, linear, zero beyond 15 m.",
        "analyst",
        "graded_away",
        BUILDING,
        (("graded_away", "building", 15),),
        (Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        "Given a planned route through the neighbourhood, When a segment passes near a building, "
        "Then its cost rises the nearer it gets. No hard limit.",
        "robot",
        "graded_away",
        BUILDING,
        (("graded_away", "building", None),),
        (Route("kampala", "farther", "building"),),
    ),
    Brief(
        "Mira, the water: cuanto más lejos, mejor. After some 40 metres from it I don't care anymore.",
        "field",
        "graded_away",
        NB,
        (("graded_away", "water", 40),),
        (Route("nb1", "farther", "water"),),
    ),
    # ------------------------------------------------------------------------------------------
    # graded_toward: the closer, the cheaper
    # ------------------------------------------------------------------------------------------
    Brief(
        "Base to Team Echo: work your way in close to the road, the tighter to it the better, "
        "you'll want the vehicle for extraction. Over.",
        "field",
        "graded_toward",
        NB,
        (("graded_toward", "road", None),),
        (Route("nb1", "closer", "road"),),
    ),
    Brief(
        "Keep the crew within easy reach of the trail: the nearer the trail, the easier it is to haul the gear.",
        "field",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "trail", None), ("avoided", "water")),
        (Route("sample", "closer", "trail"),),
        why="water is an unmentioned hazard and keeps its prior",
    ),
    Brief(
        "Survey transects should stay near the water's edge; the closer to the shoreline, the better the samples.",
        "field",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "water", None), ("avoided", "water")),
        (Route("sample", "closer", "water"),),
        why="near the edge is not in the water: the water itself keeps its prior",
    ),
    Brief(
        "The rover's radio needs line of sight to the building, so stay close to it, the nearer "
        "the better; the signal dies past 30 m.",
        "robot",
        "graded_toward",
        BUILDING,
        (("graded_toward", "building", 30), ("avoided", "building")),
        (Route("massachusetts", "closer", "building"),),
        why="a rover cannot drive into a building: close to it, not on it",
    ),
    Brief(
        "I want the path mostly within a few metres of the paved road, eight metres tops would be "
        "great, and nearer is better.",
        "analyst",
        "graded_toward",
        VEGAS,
        (("graded_toward", "paved road", 8),),
        (Route("vegas", "closer", "paved road"),),
    ),
    Brief(
        "Is it possible to keep the walk close to the trees? Shade matters, and the closer to them the better.",
        "field",
        "graded_toward",
        TREE,
        (("graded_toward", "tree", None),),
        (Route("neon", "closer", "tree"),),
    ),
    Brief(
        '{"mission": "rail inspection", "attract_to": "railway", "falloff_m": 50}',
        "analyst",
        "graded_toward",
        NB,
        (("graded_toward", "railway", 50),),
        (Route("nb2", "closer", "railway"),),
    ),
    # ------------------------------------------------------------------------------------------
    # on_beside: along X but not on X
    # ------------------------------------------------------------------------------------------
    Brief(
        "Ground team, follow the railway out to the bridge. Walk beside the tracks and stay off the rails themselves. Over.",
        "field",
        "on_beside",
        NB,
        (("beside", "railway"),),
        (Route("nb2", "beside", "railway", 10),),
    ),
    Brief(
        "The Contractor shall route the survey vehicle adjacent to, but not upon, the paved road.",
        "analyst",
        "on_beside",
        VEGAS,
        (("beside", "paved road"),),
        (Route("vegas", "beside", "paved road", 8),),
    ),
    Brief(
        "Mow the strip next to the trail and keep the wheels off the trail surface itself.",
        "robot",
        "on_beside",
        SAMPLE,
        (("beside", "trail"),),
        (Route("sample", "beside", "trail", 5),),
    ),
    Brief(
        "The robot goes next to the water, on the bank, but into the water it may not go.",
        "robot",
        "on_beside",
        NB,
        (("beside", "water"), ("lethal", "water")),
        (Route("nb1", "beside", "water", 10), Route("nb1", "zero_on", "water")),
        why="'may not go into' forbids",
    ),
    Brief(
        "just follow the road but like on the side of it not actually on it bc cars",
        "field",
        "on_beside",
        NB,
        (("beside", "road"),),
        (Route("nb1", "beside", "road", 6),),
    ),
    Brief(
        "Follow the edge of the tree line without entering the canopy.",
        "field",
        "on_beside",
        TREE,
        (("beside", "tree"),),
        (Route("neon", "beside", "tree", 4),),
    ),
    Brief(
        "🚶 along the baseball field ✅\n🚶 across the baseball field ❌",
        "analyst",
        "on_beside",
        SAMPLE,
        (("beside", "baseball field"),),
        (Route("sample", "beside", "baseball field", 6),),
    ),
    # ------------------------------------------------------------------------------------------
    # qualified: paved / unpaved, deciduous / conifer, excepted sub-areas
    # ------------------------------------------------------------------------------------------
    Brief(
        "Keep the sedan mostly on paved road, say 90 % of the way, and the unpaved stuff is off limits.",
        "robot",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("lethal", "unpaved road")),
        (Route("vegas", "more_on", "paved road"), Route("vegas", "zero_on", "unpaved road")),
    ),
    Brief(
        "unpvd rd: avoid. pvd rd: pref.",
        "analyst",
        "qualified",
        VEGAS,
        (("avoided", "unpaved road"), ("preferred", "paved road"), ("below", "paved road", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        "Dirt road you avoid please, tar road is best only.",
        "field",
        "qualified",
        VEGAS,
        (("avoided", "unpaved road"), ("preferred", "paved road")),
        (Route("vegas", "more_on", "paved road"),),
        why="dirt road = unpaved, tar road = paved",
    ),
    Brief(
        "Cut through the deciduous stand if you need to, but keep out of the conifers, the new seedlings are in there.",
        "field",
        "qualified",
        ("deciduous tree", "conifer tree", "grass"),
        (("lethal", "conifer tree"), ("not_lethal", "deciduous tree"), ("neutral", "grass")),
    ),
    Brief(
        "Avoid water everywhere except the ford, which is perfectly fine to drive through.",
        "robot",
        "qualified",
        ("water", "ford", "road"),
        (("avoided", "water"), ("not_lethal", "ford"), ("below", "ford", "water")),
    ),
    Brief(
        "Keep off the buildings, apart from the old barn: that one is derelict and we can drive through its gap.",
        "field",
        "qualified",
        BUILDING,
        (("unread", "barn"),),
        (Route("massachusetts", "less_on", "building"),),
        why="no layer holds the barn, so the exception cannot be mapped and must be reported",
    ),
    Brief(
        "Gravel tracks are fine but skip the asphalt, the robot's tyres overheat on it.",
        "robot",
        "qualified",
        VEGAS,
        (("avoided", "paved road"), ("below", "unpaved road", "paved road")),
        (Route("vegas", "less_on", "paved road"),),
        why="gravel track = unpaved road, asphalt = paved road",
    ),
    Brief(
        "Wet ground: the marsh is fine to slog through, the open lake is a no-go.",
        "field",
        "qualified",
        ("marsh", "lake", "grass"),
        (("lethal", "lake"), ("not_lethal", "marsh"), ("below", "marsh", "lake")),
    ),
    # ------------------------------------------------------------------------------------------
    # terse: symbolic, tabular, typos
    # ------------------------------------------------------------------------------------------
    Brief(
        "road > trail > grass >> tree",
        "analyst",
        "terse",
        SAMPLE,
        (("below", "road", "trail"), ("below", "trail", "grass"), ("below", "grass", "tree")),
        (Route("sample", "more_on", "road"),),
    ),
    Brief(
        "water: no\nbuilding: no\nroad: yes",
        "robot",
        "terse",
        SAMPLE,
        (("lethal", "water"), ("lethal", "building"), ("preferred", "road")),
        (Route("sample", "zero_on", "water"), Route("sample", "zero_on", "building")),
        why="a bare 'no' against a class in a list of yes/no is read as forbidding it",
    ),
    Brief(
        "basebal feild = avoid, grass = fine",
        "field",
        "terse",
        SAMPLE,
        (("avoided", "baseball field"), ("not_lethal", "grass")),
        (Route("sample", "less_on", "baseball field"),),
    ),
    Brief(
        '{"prefer": ["trail"], "avoid": ["water", "tree"], "forbid": ["building"]}',
        "analyst",
        "terse",
        SAMPLE,
        (("preferred", "trail"), ("avoided", "water"), ("avoided", "tree"), ("lethal", "building"), ("all_read",)),
        (Route("sample", "zero_on", "building"), Route("sample", "more_on", "trail")),
    ),
    Brief(
        "rly ✗ | rd ✓ | veg ~",
        "field",
        "terse",
        NB,
        (("preferred", "road"), ("below", "road", "vegetation"), ("below", "vegetation", "railway")),
        (Route("nb2", "less_on", "railway"),),
        why="rly = railway, rd = road, veg = vegetation; '~' sits between the tick and the cross",
    ),
    Brief(
        "grass costs 2x road. trees 5x.",
        "analyst",
        "terse",
        SAMPLE,
        (("below", "road", "grass"), ("below", "grass", "tree")),
        (Route("sample", "less_on", "tree"),),
    ),
    Brief(
        "paved rd pls, NOT unpaved",
        "robot",
        "terse",
        VEGAS,
        (("preferred", "paved road"), ("below", "paved road", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
    ),
    # ------------------------------------------------------------------------------------------
    # permission: lifting priors, and stay-out wording that forbids
    # ------------------------------------------------------------------------------------------
    Brief(
        "We're not unwilling to cross the water: the amphibious rover handles it.",
        "robot",
        "permission",
        NB,
        (("neutral", "water"), ("avoided", "building")),
        why="the double negative allows the water (neutral); buildings keep their prior",
    ),
    Brief(
        "The Operator is prohibited from entering any water. The Operator may overfly buildings without restriction.",
        "analyst",
        "permission",
        NB,
        (("lethal", "water"), ("neutral", "building"), ("all_read",)),
        (Route("nb1", "zero_on", "water"),),
    ),
    Brief(
        "Buildings are no problem for the drone, it flies right over them. Just keep it out of the trees.",
        "robot",
        "permission",
        SAMPLE,
        (("neutral", "building"), ("lethal", "tree")),
        (Route("sample", "zero_on", "tree"),),
    ),
    Brief(
        "The grass is fair game, the trail is fair game, but nobody goes into the water; the insurer won't cover it.",
        "field",
        "permission",
        SAMPLE,
        (("lethal", "water"), ("neutral", "grass"), ("not_lethal", "trail")),
        (Route("sample", "zero_on", "water"),),
    ),
    Brief(
        "What's labelled building on this map is mostly tin-roof sheds the robot rolls straight "
        "under, so treat buildings as passable, no penalty.",
        "robot",
        "permission",
        BUILDING,
        (("neutral", "building"), ("not_lethal", "building")),
    ),
    Brief(
        "trees r fine u can go thru them, just not the water ok",
        "field",
        "permission",
        SAMPLE,
        (("neutral", "tree"), ("below", "tree", "water")),
        why="'just not the water' is left between avoided and forbidden: only the order is settled",
    ),
    Brief(
        "Crossing the railway is allowed, the line was decommissioned last year, but keep out of the buildings.",
        "analyst",
        "permission",
        NB,
        (("neutral", "railway"), ("lethal", "building")),
        (Route("nb2", "zero_on", "building"),),
    ),
    # ------------------------------------------------------------------------------------------
    # clauses: every clause accounted for
    # ------------------------------------------------------------------------------------------
    Brief(
        "Hi all, hope the week's going OK. Quick recap from Tuesday: Sam is still chasing the "
        "permits, the van is back, and the debrief moves to Thursday because half of us are out. "
        "For the route itself, the one thing that matters is that the rover stays off the railway "
        "entirely, and please don't let it near the beehives either. Coffee's on me next time. "
        "Cheers, Priya",
        "field",
        "clauses",
        NB,
        (("lethal", "railway"), ("unread", "beehive")),
        (Route("nb2", "zero_on", "railway"),),
        why="'stays off ... entirely' forbids; no layer holds the beehives, so that rule must be reported",
    ),
    Brief(
        "Take the road. If it rains, stay off the grass as well.",
        "robot",
        "clauses",
        SAMPLE,
        (("preferred", "road"), ("unread", "rain")),
        (Route("sample", "more_on", "road"),),
        why="the planner has no weather: the conditional clause cannot be applied and must be reported",
    ),
    Brief(
        "Avoid the buildings. Between 6 and 8 am the trail belongs to the joggers, so skip it then.",
        "field",
        "clauses",
        SAMPLE,
        (("avoided", "building"), ("not_lethal", "building"), ("unread", "joggers")),
        (Route("sample", "less_on", "building"),),
        why="a time window cannot be mapped",
    ),
    Brief(
        "Avoid the power lines and the substation; the road is fine.",
        "field",
        "clauses",
        NB,
        (("unread", "power"), ("unread", "substation"), ("not_lethal", "road")),
    ),
    Brief(
        "Keep 5 m off the trail and stay out of the water. Actually, forget the trail rule, we need the trail after all.",
        "analyst",
        "clauses",
        SAMPLE,
        (("lethal", "water"), ("not_lethal", "trail"), ("all_read",)),
        (Route("sample", "zero_on", "water"),),
        why="the last sentence withdraws the trail rule; understood, it is read, not unread",
    ),
    Brief(
        "Roads are to be preferred, trees are to be avoided, and water is never to be entered.",
        "analyst",
        "clauses",
        SAMPLE,
        (("preferred", "road"), ("avoided", "tree"), ("lethal", "water"), ("all_read",)),
        (Route("sample", "zero_on", "water"), Route("sample", "more_on", "road")),
    ),
    Brief(
        "Kilo One, Base. Casualty is past the far side of the field. Avoid the water, use the road "
        "where you can, and check in on channel three every ten minutes. Over.",
        "field",
        "clauses",
        NB,
        (("avoided", "water"), ("preferred", "road"), ("unread", "channel")),
        (Route("nb1", "less_on", "water"), Route("nb1", "more_on", "road")),
        why="the radio check-in is no route rule and no layer: it must be reported, not silently dropped",
    ),
]

#: Briefs retired after scoring because their expectation contradicts the cost-scale contract
#: (id or prompt -> reason). Empty at first contact.
DOUBTFUL: dict[str, str] = {}
