"""Mission briefs, set 16: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench or the briefs of earlier sets: only the contract (``tests/mission_briefs.py``
and its format test ``tests/test_mission_briefs.py``), the scene index (``../shared/scenes/INDEX.md``
and the scenes' ``classes.json``) and the first 40 lines of set 15 (for the layout of its module
constants and docstring) were read. It is scored once, at first contact, with
``bench/mission_briefs_report.py --set 16``; that figure is the one that counts, and the set is not
edited afterwards to make the interpreter pass.

The voices are GIS analysts (formal, distances in metres, feet, yards, kilometres or words such as
"a stone's throw"), robot operators (terse, symbolic: ``>``, ``:``, ``key: value``, pseudo-code,
lists) and field crews (chatty, typo-ridden, with asides about weather, people, schedules and kit
that are not rules); some briefs are written by non-native speakers of English, some as emails and
some as checklists. Asides that merely mention a layer ("the van's parked by the road") are checked
not to have made a rule. The layers of each brief are the class names of the scene its routes are
checked on, so the route checks run on the real ground truth; briefs over layers no scene holds
(conifers, fords, ruined buildings, dead trees) carry no route checks.
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
    # distance_hard: absolute distance rules make keep-out zones
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Survey requirement for the Baker Lake traverse: the vehicle must at no point come "
            "within 15 metres of the railway embankment."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "railway", 15), ("avoided", "building")),
        routes=(Route("nb2", "keeps", "railway", 15),),
        why="'must at no point come within' is absolute; the building is an unmentioned hazard.",
    ),
    Brief(
        prompt="min_clearance(building) = 4 m  // HARD, abort mission if violated",
        voice="robot",
        construct="distance_hard",
        layers=BUILDINGS,
        expect=(("keep_out", "building", 4),),
        routes=(Route("massachusetts", "keeps", "building", 4),),
    ),
    Brief(
        prompt=(
            "ok so the rule from mrs Haldane (landowner) is u absolutely cannot get closer than "
            "30 ft to the water, she was really clear about that. bring the spare props"
        ),
        voice="field",
        construct="distance_hard",
        layers=SAMPLE,
        expect=(("keep_out", "water", 30 * FT), ("neutral", "grass")),
        routes=(Route("sample", "keeps", "water", 30 * FT),),
        why="30 ft = 9.14 m; 'bring the spare props' is kit, not a rule; grass is unmentioned.",
    ),
    Brief(
        prompt=(
            "Clearance protocol KLA-7: a hard minimum standoff of 3 m from every building footprint "
            "applies throughout the settlement; this is non-negotiable given the density of occupants."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=BUILDINGS,
        expect=(("keep_out", "building", 3),),
        routes=(Route("kampala", "keeps", "building", 3),),
    ),
    Brief(
        prompt=(
            "Please, the robot must never be nearer than twenty meters from the buildings, this is "
            "the law of our village. Thank you very much for the help."
        ),
        voice="field",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "building", 20),),
        routes=(Route("nb1", "keeps", "building", 20),),
        why="A non-native speaker; 'must never be nearer than twenty meters' is absolute.",
    ),
    Brief(
        prompt="RULE 3.2: dist(path, building) >= 25 yd. strict, no tolerance.",
        voice="robot",
        construct="distance_hard",
        layers=SAMPLE,
        expect=(("keep_out", "building", 25 * YD),),
        routes=(Route("sample", "keeps", "building", 25 * YD),),
        why="25 yd = 22.9 m.",
    ),
    Brief(
        prompt=(
            "Under no circumstances may the ground robot pass within two metres of a tree crown; "
            "the understorey instrumentation at plot OSBS-029 is fragile."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=TREES,
        expect=(("keep_out", "tree", 2),),
        routes=(Route("neon", "keeps", "tree", 2),),
    ),
    Brief(
        prompt=(
            "Subject: route constraints for Thursday\n\nHi team,\nHard limit from the rail operator: "
            "nothing within 12 m of the railway track, full stop. Also keep at least 8 m off the "
            "water, that one is a hard limit too.\n\nCheers,\nPriya"
        ),
        voice="analyst",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "railway", 12), ("keep_out", "water", 8)),
        routes=(Route("nb2", "keeps", "railway", 12), Route("nb1", "keeps", "water", 8)),
        why="An email; both limits are called hard.",
    ),
    Brief(
        prompt=(
            "Insurance fella says we must stay fifty feet from any building at all times. No "
            "exceptions. Coffee's in the blue truck if anyone wants it"
        ),
        voice="field",
        construct="distance_hard",
        layers=BUILDINGS,
        expect=(("keep_out", "building", 50 * FT),),
        routes=(Route("massachusetts", "keeps", "building", 50 * FT),),
        why="50 ft = 15.2 m; the coffee is an aside.",
    ),
    Brief(
        prompt="geofence: paved road buffer 6 m = NO ENTRY (hard)",
        voice="robot",
        construct="distance_hard",
        layers=VEGAS,
        expect=(("keep_out", "paved road", 6),),
        routes=(Route("vegas", "keeps", "paved road", 6),),
    ),
    Brief(
        prompt=(
            "The wetland permit stipulates an absolute exclusion buffer of 0.015 km around all open "
            "water, and an equally absolute 10 m setback from the baseball field."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=SAMPLE,
        expect=(("keep_out", "water", 15), ("keep_out", "baseball field", 10)),
        routes=(
            Route("sample", "keeps", "water", 15),
            Route("sample", "keeps", "baseball field", 10),
        ),
        why="0.015 km = 15 m.",
    ),
    Brief(
        prompt="no way we go closer then 10m to the raillway, the foreman will skin us. its raining again btw",
        voice="field",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "railway", 10),),
        routes=(Route("nb2", "keeps", "railway", 10),),
        why="'no way ... closer than' is absolute; typos in 'then' and 'raillway'; the rain is an aside.",
    ),
    Brief(
        prompt=(
            "keep a stone's throw from the building at all times, no exceptions whatsoever, its a "
            "primary school and term started monday"
        ),
        voice="field",
        construct="distance_hard",
        layers=SAMPLE,
        expect=(("keep_out", "building", None),),
        routes=(Route("sample", "farther", "building"),),
        why="A hard rule with no number: a default zone; the route keeps its distance from the building.",
    ),
    Brief(
        prompt="HARD LIMITS\nwater: 5 m\nrailway: 10 m\nbuilding: 3 m",
        voice="robot",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "water", 5), ("keep_out", "railway", 10), ("keep_out", "building", 3)),
        routes=(
            Route("nb1", "keeps", "water", 5),
            Route("nb2", "keeps", "railway", 10),
            Route("nb1", "keeps", "building", 3),
        ),
    ),
    Brief(
        prompt=(
            "The robot is forbidden to come more close than 2 meter to any building, this is a "
            "strict rule of the municipality of Kawempe."
        ),
        voice="field",
        construct="distance_hard",
        layers=BUILDINGS,
        expect=(("keep_out", "building", 2),),
        routes=(Route("kampala", "keeps", "building", 2),),
        why="A non-native speaker; 'forbidden to come more close than' is absolute.",
    ),
    # ------------------------------------------------------------------------------------------
    # distance_soft: softly worded distance rules make soft zones, the number kept
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Where practicable, the route should maintain roughly 25 m of separation from open "
            "water; this is a guideline rather than a constraint."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "water", 25), ("not_lethal", "water")),
        routes=(Route("nb1", "farther", "water"),),
    ),
    Brief(
        prompt="pref: standoff(building) ~5 m (soft, may violate)",
        voice="robot",
        construct="distance_soft",
        layers=BUILDINGS,
        expect=(("soft_zone", "building", 5),),
        routes=(Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        prompt=(
            "If you can, give the trees about fifteen feet of room, they're dropping branches this "
            "time of year. Not a deal breaker if you can't."
        ),
        voice="field",
        construct="distance_soft",
        layers=SAMPLE,
        expect=(("soft_zone", "tree", 15 * FT), ("not_lethal", "tree")),
        routes=(Route("sample", "farther", "tree"),),
        why="15 ft = 4.6 m, explicitly not a deal breaker.",
    ),
    Brief(
        prompt=(
            "It is better if the robot keeps maybe 10 meter from the rail line, but if it is not "
            "possible it is ok, not a big problem."
        ),
        voice="field",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "railway", 10),),
        routes=(Route("nb2", "farther", "railway"),),
        why="A non-native speaker; the rule is explicitly relaxable.",
    ),
    Brief(
        prompt=(
            "Dear Operations,\nPlease aim for a buffer of approximately 20 m around the baseball "
            "field where feasible; a youth league practice is scheduled for 16:30.\nKind regards,\n"
            "M. Okafor, Parks GIS"
        ),
        voice="analyst",
        construct="distance_soft",
        layers=SAMPLE,
        expect=(("soft_zone", "baseball field", 20), ("not_lethal", "baseball field")),
        routes=(Route("sample", "farther", "baseball field"),),
    ),
    Brief(
        prompt="soft_buffer: {paved road: 3m}",
        voice="robot",
        construct="distance_soft",
        layers=VEGAS,
        expect=(("soft_zone", "paved road", 3), ("not_lethal", "paved road")),
        routes=(Route("vegas", "farther", "paved road"),),
    ),
    Brief(
        prompt=(
            "try to keep like two metres off the building walls when u can, kids run out of the "
            "doorways. no biggie if the alley is too tight"
        ),
        voice="field",
        construct="distance_soft",
        layers=BUILDINGS,
        expect=(("soft_zone", "building", 2), ("not_lethal", "building")),
        routes=(Route("kampala", "farther", "building"),),
    ),
    Brief(
        prompt=(
            "A nominal 3 m offset from tree crowns is desirable but may be relaxed in the denser parts of the plot."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=TREES,
        expect=(("soft_zone", "tree", 3),),
        routes=(Route("neon", "farther", "tree"),),
    ),
    Brief(
        prompt=(
            "Checklist for run 4:\n- batteries charged\n- ideally 30 yards clear of buildings\n"
            "- camera lens wiped\n- back at the depot by dusk"
        ),
        voice="field",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "building", 30 * YD), ("neutral", "road")),
        routes=(Route("nb1", "farther", "building"),),
        why="30 yd = 27.4 m, 'ideally'; the other items are kit and schedule; the road is unmentioned.",
    ),
    Brief(
        prompt="road: keep ~8 m if possible\nwater: keep >= 12 m, mandatory",
        voice="robot",
        construct="distance_soft",
        layers=SAMPLE,
        expect=(("soft_zone", "road", 8), ("keep_out", "water", 12)),
        routes=(Route("sample", "keeps", "water", 12), Route("sample", "farther", "road")),
        why="Soft and hard side by side: 'if possible' against 'mandatory'.",
    ),
    Brief(
        prompt=(
            "Two separation rules apply. The railway setback of 20 m is statutory and absolute. "
            "The 10 m margin from vegetation is only advisory."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=NB,
        expect=(("keep_out", "railway", 20), ("soft_zone", "vegetation", 10)),
        routes=(Route("nb2", "keeps", "railway", 20), Route("nb1", "farther", "vegetation")),
    ),
    Brief(
        prompt=("It would be preferable, though by no means essential, to remain a stone's throw from the railway."),
        voice="analyst",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "railway", None), ("not_lethal", "railway")),
        routes=(Route("nb2", "farther", "railway"),),
        why="A soft rule with no number: a soft zone at the default distance.",
    ),
    Brief(
        prompt=("try n stay about 6 yards off the road if its not too much hassle. Gary's got the spare tablet btw"),
        voice="field",
        construct="distance_soft",
        layers=SAMPLE,
        expect=(("soft_zone", "road", 6 * YD), ("not_lethal", "road")),
        routes=(Route("sample", "farther", "road"),),
        why="6 yd = 5.5 m; the tablet is an aside.",
    ),
    # ------------------------------------------------------------------------------------------
    # graded_away: the closer, the dearer
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "stay well clear of the water, honestly the further the better, last summer someone "
            "drowned a rover in there. grass is fine"
        ),
        voice="field",
        construct="graded_away",
        layers=SAMPLE,
        expect=(("graded_away", "water", None), ("neutral", "grass")),
        routes=(Route("sample", "farther", "water"),),
    ),
    Brief(
        prompt=(
            "Proximity to residential structures should be minimised: the cost should rise steadily "
            "as the route approaches a building and fade out entirely beyond 20 m."
        ),
        voice="analyst",
        construct="graded_away",
        layers=BUILDINGS,
        expect=(("graded_away", "building", 20),),
        routes=(Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        prompt="railway: repel, falloff 15m",
        voice="robot",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "railway", 15),),
        routes=(Route("nb2", "farther", "railway"),),
    ),
    Brief(
        prompt="Please do not go near to the trees, more far is more good for us.",
        voice="field",
        construct="graded_away",
        layers=TREES,
        expect=(("graded_away", "tree", None),),
        routes=(Route("neon", "farther", "tree"),),
        why="A non-native speaker: 'more far is more good' is the further the better.",
    ),
    Brief(
        prompt=(
            "hey, quick one: the paved roads are rammed today with the marathon, so keep the bot as "
            "far from them as you reasonably can. thx, J"
        ),
        voice="field",
        construct="graded_away",
        layers=VEGAS,
        expect=(("graded_away", "paved road", None),),
        routes=(Route("vegas", "farther", "paved road"),),
    ),
    Brief(
        prompt=(
            "Keep a generous distance from the water: the greater the separation, the better. "
            "No other constraints apply to this sortie."
        ),
        voice="analyst",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "water", None), ("neutral", "road")),
        routes=(Route("nb1", "farther", "water"),),
    ),
    Brief(
        prompt=(
            "dont go near the buildings, folks are sleeping after the night shift. the closer u get the worse it is"
        ),
        voice="field",
        construct="graded_away",
        layers=BUILDINGS,
        expect=(("graded_away", "building", None),),
        routes=(Route("kampala", "farther", "building"),),
    ),
    Brief(
        prompt="proximity_penalty:\n  building: strong, 0-30 m\n  road: weak",
        voice="robot",
        construct="graded_away",
        layers=SAMPLE,
        expect=(("graded_away", "building", 30), ("graded_away", "road", None)),
        routes=(Route("sample", "farther", "building"),),
    ),
    Brief(
        prompt=(
            "Avoid the water as a matter of course, and the nearer the route comes to it the heavier "
            "the penalty should be; by contrast, the trail is to be favoured."
        ),
        voice="analyst",
        construct="graded_away",
        layers=SAMPLE,
        expect=(("avoided", "water"), ("graded_away", "water", None), ("preferred", "trail")),
        routes=(Route("sample", "farther", "water"), Route("sample", "more_on", "trail")),
    ),
    Brief(
        prompt="keep waaay back from the railway tracks, further = better, theres a freight due at 3",
        voice="field",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "railway", None),),
        routes=(Route("nb2", "farther", "railway"),),
        why="The freight timetable is an aside.",
    ),
    Brief(
        prompt=(
            "Routing criteria (in priority order):\n1. An increasing penalty with proximity to "
            "buildings, negligible past 40 m.\n2. Prefer the road where available."
        ),
        voice="analyst",
        construct="graded_away",
        layers=SAMPLE,
        expect=(("graded_away", "building", 40), ("preferred", "road")),
        routes=(Route("sample", "farther", "building"), Route("sample", "more_on", "road")),
    ),
    Brief(
        prompt="water: keep well away\ntrail: prefer",
        voice="robot",
        construct="graded_away",
        layers=SAMPLE,
        expect=(("graded_away", "water", None), ("preferred", "trail")),
        routes=(Route("sample", "farther", "water"), Route("sample", "more_on", "trail")),
    ),
    Brief(
        prompt=(
            "Please, stay away from the train line, as far as possible is more better, because the "
            "trains there are not stopping."
        ),
        voice="field",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "railway", None), ("not_lethal", "railway")),
        routes=(Route("nb2", "farther", "railway"),),
        why="A non-native speaker; 'train line' is the railway.",
    ),
    # ------------------------------------------------------------------------------------------
    # graded_toward: the closer, the cheaper
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="hug the trail as much as u can, the closer the better. we'll grab lunch after",
        voice="field",
        construct="graded_toward",
        layers=SAMPLE,
        expect=(("graded_toward", "trail", None),),
        routes=(Route("sample", "closer", "trail"),),
    ),
    Brief(
        prompt=(
            "The survey line should remain within sight of the road throughout, with proximity to "
            "the carriageway rewarded."
        ),
        voice="analyst",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "road", None),),
        routes=(Route("nb1", "closer", "road"),),
    ),
    Brief(
        prompt="attract: paved road, radius 20 m",
        voice="robot",
        construct="graded_toward",
        layers=VEGAS,
        expect=(("graded_toward", "paved road", 20),),
        routes=(Route("vegas", "closer", "paved road"),),
    ),
    Brief(
        prompt=(
            "The robot should stay near to the buildings, because the wifi signal is coming from "
            "there. More near is better."
        ),
        voice="field",
        construct="graded_toward",
        layers=BUILDINGS,
        expect=(("graded_toward", "building", None),),
        routes=(Route("massachusetts", "closer", "building"),),
        why="A non-native speaker; the wifi is the reason, not a rule.",
    ),
    Brief(
        prompt=(
            "Hi all,\nFor the water sampling run, please keep the rover close to the shoreline, the "
            "nearer the water the better, we need the dip arm to reach. Don't actually drive into "
            "it obviously.\nRegards,\nLena"
        ),
        voice="analyst",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "water", None), ("beside", "water")),
        routes=(Route("nb1", "closer", "water"),),
        why="Close to the water but not in it: the water itself is avoided or forbidden.",
    ),
    Brief(
        prompt=(
            "stick close to the tree crowns for shade, the sensors overheat in the open. closer's "
            "better but dont bump into them"
        ),
        voice="field",
        construct="graded_toward",
        layers=TREES,
        expect=(("graded_toward", "tree", None), ("beside", "tree")),
        routes=(Route("neon", "closer", "tree"),),
    ),
    Brief(
        prompt=(
            "Preference should be given to ground adjacent to the baseball field, decreasing with "
            "distance up to about 50 m."
        ),
        voice="analyst",
        construct="graded_toward",
        layers=SAMPLE,
        expect=(("graded_toward", "baseball field", 50),),
        routes=(Route("sample", "closer", "baseball field"),),
    ),
    Brief(
        prompt="road: attract (close = cheap)\nbuilding: avoid",
        voice="robot",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "road", None), ("avoided", "building")),
        routes=(Route("nb1", "closer", "road"), Route("nb1", "less_on", "building")),
    ),
    Brief(
        prompt=("stay close to the buildings, the survey markers are all in the alleys between them, nearer is better"),
        voice="field",
        construct="graded_toward",
        layers=BUILDINGS,
        expect=(("graded_toward", "building", None),),
        routes=(Route("kampala", "closer", "building"),),
    ),
    Brief(
        prompt=(
            "The route must remain within easy reach of the road (the closer, the better), yet "
            "observe an absolute 10 m standoff from water."
        ),
        voice="analyst",
        construct="graded_toward",
        layers=SAMPLE,
        expect=(("graded_toward", "road", None), ("keep_out", "water", 10)),
        routes=(Route("sample", "closer", "road"), Route("sample", "keeps", "water", 10)),
    ),
    Brief(
        prompt="I want that the robot goes always near of the paved road, like a dog near his owner.",
        voice="field",
        construct="graded_toward",
        layers=VEGAS,
        expect=(("graded_toward", "paved road", None),),
        routes=(Route("vegas", "closer", "paved road"),),
        why="A non-native speaker; the simile is not a rule.",
    ),
    Brief(
        prompt=(
            "keep the road in sight the whole time, we're tailing the pickup with the base station "
            "on it, the nearer the road the better"
        ),
        voice="field",
        construct="graded_toward",
        layers=SAMPLE,
        expect=(("graded_toward", "road", None), ("avoided", "water")),
        routes=(Route("sample", "closer", "road"),),
        why="The water is an unmentioned hazard at its prior.",
    ),
    # ------------------------------------------------------------------------------------------
    # on_beside: along X but not on X
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="drive along the road but not on it, there's traffic all afternoon",
        voice="field",
        construct="on_beside",
        layers=SAMPLE,
        expect=(("beside", "road"),),
        routes=(Route("sample", "beside", "road", 5),),
    ),
    Brief(
        prompt=(
            "The rover is to follow the road corridor on its shoulder, never on the carriageway "
            "itself, keeping within a few metres of the edge."
        ),
        voice="analyst",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "road"),),
        routes=(Route("nb1", "beside", "road", 5),),
    ),
    Brief(
        prompt="follow(trail, offset=2m); on(trail) = false",
        voice="robot",
        construct="on_beside",
        layers=SAMPLE,
        expect=(("beside", "trail"),),
        routes=(Route("sample", "beside", "trail", 4),),
    ),
    Brief(
        prompt=(
            "stay on the trail the whole way, don't wander onto the grass. theres a picnic at noon "
            "near the baseball field, say hi to Mo"
        ),
        voice="field",
        construct="on_beside",
        layers=SAMPLE,
        expect=(("preferred", "trail"), ("neutral", "baseball field")),
        routes=(Route("sample", "more_on", "trail"), Route("sample", "less_on", "grass")),
        why="On, not beside: the trail is preferred; the picnic by the baseball field is an aside.",
    ),
    Brief(
        prompt="Go along the railway line, next to it, but never on the rails, it is very dangerous.",
        voice="field",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "railway"),),
        routes=(Route("nb2", "beside", "railway", 5),),
        why="A non-native speaker.",
    ),
    Brief(
        prompt=(
            "Traverse alongside the paved roads, using the unsurfaced margin immediately adjacent to "
            "them; the road surface itself is to be avoided."
        ),
        voice="analyst",
        construct="on_beside",
        layers=VEGAS,
        expect=(("beside", "paved road"), ("avoided", "paved road")),
        routes=(Route("vegas", "beside", "paved road", 3),),
    ),
    Brief(
        prompt=(
            "Team, for tomorrow: walk the bank of the creek, right beside the water, but nobody "
            "goes in the water. Forecast says gusts to 40.\nTomás"
        ),
        voice="field",
        construct="on_beside",
        layers=SAMPLE,
        expect=(("beside", "water"),),
        routes=(Route("sample", "beside", "water", 5),),
    ),
    Brief(
        prompt="mode: wall-follow(building)\nbuilding: off limits (no contact)",
        voice="robot",
        construct="on_beside",
        layers=BUILDINGS,
        expect=(("beside", "building"), ("lethal", "building")),
        routes=(
            Route("massachusetts", "beside", "building", 3),
            Route("massachusetts", "zero_on", "building"),
        ),
    ),
    Brief(
        prompt="run the edge of the tree line, not under the canopy, the gps drops out under there",
        voice="field",
        construct="on_beside",
        layers=TREES,
        expect=(("beside", "tree"),),
        routes=(Route("neon", "beside", "tree", 2),),
    ),
    Brief(
        prompt=("Travel on the road is acceptable; travel beside the railway, though not upon it, is preferred."),
        voice="analyst",
        construct="on_beside",
        layers=NB,
        expect=(("neutral", "road"), ("beside", "railway")),
        routes=(Route("nb2", "beside", "railway", 5),),
        why="'Acceptable' merely allows the road.",
    ),
    Brief(
        prompt=(
            "keep to the trail, and where the trail meets the road just go along the side of the "
            "road, not on the road itself"
        ),
        voice="field",
        construct="on_beside",
        layers=SAMPLE,
        expect=(("preferred", "trail"), ("beside", "road")),
        routes=(Route("sample", "more_on", "trail"), Route("sample", "beside", "road", 5)),
    ),
    Brief(
        prompt="road: no driving on surface\nroad: drive parallel, within 3 m",
        voice="robot",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "road"),),
        routes=(Route("nb1", "beside", "road", 4),),
    ),
    # ------------------------------------------------------------------------------------------
    # qualified: paved / unpaved, deciduous / conifer, excepted sub-areas
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="Surfaced (paved) roads are to be preferred; unpaved tracks are to be avoided.",
        voice="analyst",
        construct="qualified",
        layers=VEGAS,
        expect=(
            ("preferred", "paved road"),
            ("avoided", "unpaved road"),
            ("below", "paved road", "unpaved road"),
        ),
        routes=(Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        prompt="paved road: prefer\nunpaved road: no-go",
        voice="robot",
        construct="qualified",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("lethal", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        prompt="use the paved raods not the unpaved ones, the dust clogs the lidar something awful",
        voice="field",
        construct="qualified",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("below", "paved road", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="A typo in 'raods'; the lidar is the reason.",
    ),
    Brief(
        prompt=(
            "Within the stand, deciduous trees may be passed beneath without penalty, whereas "
            "conifers are to be avoided owing to their low branches."
        ),
        voice="analyst",
        construct="qualified",
        layers=("deciduous tree", "conifer", "grass"),
        expect=(("neutral", "deciduous tree"), ("avoided", "conifer"), ("neutral", "grass")),
        why="'Without penalty' lifts the tree prior for the deciduous kind only.",
    ),
    Brief(
        prompt=(
            "the conifer trees are fine to go under, but keep out of the deciduous trees, they've "
            "got wasp nests in them this month"
        ),
        voice="field",
        construct="qualified",
        layers=("conifer tree", "deciduous tree", "road"),
        expect=(("neutral", "conifer tree"), ("lethal", "deciduous tree")),
    ),
    Brief(
        prompt="Avoid every grassed surface except the baseball field, which is open to us today.",
        voice="analyst",
        construct="qualified",
        layers=SAMPLE,
        expect=(("avoided", "grass"), ("neutral", "baseball field")),
        routes=(Route("sample", "less_on", "grass"),),
        why="The exception merely allows the baseball field.",
    ),
    Brief(
        prompt="Stay out of the water except at the marked ford, which we are allowed to cross.",
        voice="analyst",
        construct="qualified",
        layers=("water", "ford", "vegetation", "road"),
        expect=(("lethal", "water"), ("not_lethal", "ford")),
    ),
    Brief(
        prompt="roads: avoid\nEXCEPT paved road: ok",
        voice="robot",
        construct="qualified",
        layers=VEGAS,
        expect=(("avoided", "unpaved road"), ("neutral", "paved road")),
    ),
    Brief(
        prompt=(
            "Keep out of all buildings apart from the ruined building on the north side, which has "
            "been cleared for entry by the structural engineer."
        ),
        voice="analyst",
        construct="qualified",
        layers=("building", "ruined building", "road"),
        expect=(("lethal", "building"), ("not_lethal", "ruined building")),
    ),
    Brief(
        prompt="stay well away from the dead trees, they drop limbs without warning. the live trees are fine",
        voice="field",
        construct="qualified",
        layers=("tree", "dead tree", "grass", "trail"),
        expect=(("graded_away", "dead tree", None), ("neutral", "tree")),
        why="'The live trees are fine' lifts the prior of the tree layer, not of the dead ones.",
    ),
    Brief(
        prompt="Only paved road please. The not-paved road is bad for the wheels of our machine.",
        voice="field",
        construct="qualified",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("avoided", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="A non-native speaker; 'not-paved' is unpaved; 'only' does not use a forbidding word.",
    ),
    Brief(
        prompt="the dirt roads (unpaved) are off limits after last nights rain, paved is grand",
        voice="field",
        construct="qualified",
        layers=VEGAS,
        expect=(("lethal", "unpaved road"), ("not_lethal", "paved road")),
    ),
    # ------------------------------------------------------------------------------------------
    # terse: symbolic orderings, 'X: no-go', 'X fine', typos in multi-word names
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="surface rank (best first): trail > road > grass",
        voice="robot",
        construct="terse",
        layers=SAMPLE,
        expect=(("below", "trail", "road"), ("below", "road", "grass")),
        routes=(Route("sample", "more_on", "trail"),),
    ),
    Brief(
        prompt="building: no-go | railway: no-go | water: avoid",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(("lethal", "building"), ("lethal", "railway"), ("avoided", "water")),
        routes=(
            Route("nb1", "zero_on", "building"),
            Route("nb2", "zero_on", "railway"),
            Route("nb1", "less_on", "water"),
        ),
    ),
    Brief(
        prompt="pavd road: ok ; unpaved raod: avoid",
        voice="robot",
        construct="terse",
        layers=VEGAS,
        expect=(("neutral", "paved road"), ("avoided", "unpaved road")),
        why="Typos in both multi-word names.",
    ),
    Brief(
        prompt="basebal feild: off limits\nwatr: avoid",
        voice="robot",
        construct="terse",
        layers=SAMPLE,
        expect=(("lethal", "baseball field"), ("avoided", "water")),
        routes=(Route("sample", "zero_on", "baseball field"), Route("sample", "less_on", "water")),
    ),
    Brief(
        prompt="building -> keep 5m, HARD",
        voice="robot",
        construct="terse",
        layers=BUILDINGS,
        expect=(("keep_out", "building", 5),),
        routes=(Route("massachusetts", "keeps", "building", 5),),
    ),
    Brief(
        prompt="tree: fine",
        voice="robot",
        construct="terse",
        layers=TREES,
        expect=(("neutral", "tree"),),
        why="'X fine' lifts the tree prior to neutral.",
    ),
    Brief(
        prompt="road >> vegetation > water",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(("below", "road", "vegetation"), ("below", "vegetation", "water")),
        routes=(Route("nb1", "more_on", "road"),),
    ),
    Brief(
        prompt="grass ok. trees no. road pref.",
        voice="robot",
        construct="terse",
        layers=SAMPLE,
        expect=(("neutral", "grass"), ("preferred", "road"), ("below", "road", "grass")),
        routes=(Route("sample", "more_on", "road"), Route("sample", "less_on", "tree")),
        why="'trees no' is at least avoided, so only the route on the trees is checked.",
    ),
    Brief(
        prompt="R-7 surface pref: paved road >>> unpaved road",
        voice="robot",
        construct="terse",
        layers=VEGAS,
        expect=(("below", "paved road", "unpaved road"),),
        routes=(Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        prompt="cross(railway) = never; water: 10m min",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(("no_cross", "railway"), ("keep_out", "water", 10)),
        routes=(Route("nb2", "zero_on", "railway"), Route("nb1", "keeps", "water", 10)),
        why="'10m min' is a minimum: a hard zone.",
    ),
    Brief(
        prompt="biuldings - stay out. tral - yes pls",
        voice="field",
        construct="terse",
        layers=SAMPLE,
        expect=(("lethal", "building"), ("preferred", "trail")),
        routes=(Route("sample", "zero_on", "building"), Route("sample", "more_on", "trail")),
        why="Typos in both names; 'stay out' forbids.",
    ),
    Brief(
        prompt="building: soft 2m",
        voice="robot",
        construct="terse",
        layers=BUILDINGS,
        expect=(("soft_zone", "building", 2), ("not_lethal", "building")),
        routes=(Route("kampala", "farther", "building"),),
    ),
    Brief(
        prompt="water: no crossing. road: crossing ok",
        voice="robot",
        construct="terse",
        layers=SAMPLE,
        expect=(("no_cross", "water"), ("neutral", "road")),
        routes=(Route("sample", "zero_on", "water"),),
    ),
    # ------------------------------------------------------------------------------------------
    # permission: permissions lift priors; stay-out wording forbids; crossings; negations
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "you're allowed to cut across the grass and through the trees today, the groundskeeper "
            "ok'd it. just stay out of the water"
        ),
        voice="field",
        construct="permission",
        layers=SAMPLE,
        expect=(("neutral", "grass"), ("neutral", "tree"), ("lethal", "water")),
        routes=(Route("sample", "zero_on", "water"),),
    ),
    Brief(
        prompt="Entry into vegetated areas is permitted; the railway corridor, however, is off limits.",
        voice="analyst",
        construct="permission",
        layers=NB,
        expect=(("neutral", "vegetation"), ("lethal", "railway")),
        routes=(Route("nb2", "zero_on", "railway"),),
    ),
    Brief(
        prompt="building: passable (sim run, collisions disabled)",
        voice="robot",
        construct="permission",
        layers=BUILDINGS,
        expect=(("neutral", "building"),),
        why="A permission lifts the building prior to neutral.",
    ),
    Brief(
        prompt=("You can go in the water, it is not deep there, no problem. But don't go into the buildings, please."),
        voice="field",
        construct="permission",
        layers=NB,
        expect=(("neutral", "water"), ("lethal", "building")),
        routes=(Route("nb1", "zero_on", "building"),),
        why="A non-native speaker; the water prior is lifted, 'don't go into' forbids.",
    ),
    Brief(
        prompt=(
            "Hello,\nThe baseball field is closed for resurfacing, so keep out of it entirely. The "
            "trail and the road are both open and you may use either.\nBest,\nFacilities Desk"
        ),
        voice="analyst",
        construct="permission",
        layers=SAMPLE,
        expect=(("lethal", "baseball field"), ("neutral", "trail"), ("neutral", "road")),
        routes=(Route("sample", "zero_on", "baseball field"),),
        why="'You may use either' merely allows them.",
    ),
    Brief(
        prompt=(
            "Crossing the railway is prohibited at every point along this section; the route may "
            "otherwise pass over roads freely."
        ),
        voice="analyst",
        construct="permission",
        layers=NB,
        expect=(("no_cross", "railway"), ("neutral", "road")),
        routes=(Route("nb2", "zero_on", "railway"),),
    ),
    Brief(
        prompt="never cross the creek, the bank's collapsing near the culvert. roads fine",
        voice="field",
        construct="permission",
        layers=NB,
        expect=(("no_cross", "water"), ("neutral", "road")),
        routes=(Route("nb1", "zero_on", "water"),),
    ),
    Brief(
        prompt="tree: ALLOWED (crowns are high, rover fits under)",
        voice="robot",
        construct="permission",
        layers=TREES,
        expect=(("neutral", "tree"),),
    ),
    Brief(
        prompt=("There is no need to avoid the trees on this occasion; the water, however, remains a no-go area."),
        voice="analyst",
        construct="permission",
        layers=SAMPLE,
        expect=(("neutral", "tree"), ("lethal", "water")),
        routes=(Route("sample", "zero_on", "water"),),
        why="A negated avoidance is a permission, not an avoidance.",
    ),
    Brief(
        prompt=(
            "ok the buildings are off limits, the community leaders asked us nicely. the open "
            "ground between them u can use however"
        ),
        voice="field",
        construct="permission",
        layers=BUILDINGS,
        expect=(("lethal", "building"),),
        routes=(Route("kampala", "zero_on", "building"),),
    ),
    Brief(
        prompt="Is permitted to walk on the grass. Is not permitted to enter the baseball field.",
        voice="field",
        construct="permission",
        layers=SAMPLE,
        expect=(("neutral", "grass"), ("lethal", "baseball field")),
        routes=(Route("sample", "zero_on", "baseball field"),),
        why="A non-native speaker; 'not permitted to enter' forbids.",
    ),
    Brief(
        prompt="Stay out of the railway corridor, and keep out of the water as well.",
        voice="analyst",
        construct="permission",
        layers=NB,
        expect=(("lethal", "railway"), ("lethal", "water"), ("neutral", "road")),
        routes=(Route("nb1", "zero_on", "water"), Route("nb2", "zero_on", "railway")),
    ),
    Brief(
        prompt=("we're NOT avoiding the vegetation this time, drive straight thru it. do avoid the water tho"),
        voice="field",
        construct="permission",
        layers=NB,
        expect=(("neutral", "vegetation"), ("avoided", "water")),
        routes=(Route("nb1", "less_on", "water"),),
        why="A negation: the vegetation is not avoided.",
    ),
    Brief(
        prompt=(
            "The road and the grass are to be treated alike, with neither preferred over the other. "
            "The water should be avoided."
        ),
        voice="analyst",
        construct="permission",
        layers=SAMPLE,
        expect=(("neutral", "road"), ("neutral", "grass"), ("avoided", "water")),
        routes=(Route("sample", "less_on", "water"),),
    ),
    Brief(
        prompt="you can cross the road but don't drive along it, and never ever cross the water",
        voice="field",
        construct="permission",
        layers=SAMPLE,
        expect=(("avoided", "road"), ("not_lethal", "road"), ("no_cross", "water")),
        routes=(Route("sample", "less_on", "road"), Route("sample", "zero_on", "water")),
        why="Crossing the road is allowed, so it is avoided but passable; the water is never crossed.",
    ),
    # ------------------------------------------------------------------------------------------
    # clauses: every clause accounted for, noise makes no rule
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="avoid the water, and stay clear of the pylons along the east fence",
        voice="field",
        construct="clauses",
        layers=SAMPLE,
        expect=(("avoided", "water"), ("unread", "pylons")),
        routes=(Route("sample", "less_on", "water"),),
        why="There is no pylon layer: that clause is reported, not dropped.",
    ),
    Brief(
        prompt="Prefer the road. Avoid the substation compound. Keep out of the railway.",
        voice="analyst",
        construct="clauses",
        layers=NB,
        expect=(("preferred", "road"), ("lethal", "railway"), ("unread", "substation")),
        routes=(Route("nb1", "more_on", "road"), Route("nb2", "zero_on", "railway")),
    ),
    Brief(
        prompt="road: prefer\nwater: avoid\nbuilding: avoid",
        voice="robot",
        construct="clauses",
        layers=SAMPLE,
        expect=(("preferred", "road"), ("avoided", "water"), ("avoided", "building"), ("all_read",)),
        routes=(Route("sample", "more_on", "road"), Route("sample", "less_on", "building")),
    ),
    Brief(
        prompt=(
            "mornin! weather's grim, bring the waterproofs. the van's parked up by the road. "
            "anyway: stay out of the buildings pls"
        ),
        voice="field",
        construct="clauses",
        layers=NB,
        expect=(("lethal", "building"), ("neutral", "road"), ("not_lethal", "water")),
        routes=(Route("nb1", "zero_on", "building"),),
        why="Where the van is parked is an aside: no rule on the road.",
    ),
    Brief(
        prompt=(
            "Hi Ken,\nThanks for Friday. For the next run: keep the rover off the helipad and avoid "
            "the trees. Sarah sends her regards.\nBest,\nAna"
        ),
        voice="analyst",
        construct="clauses",
        layers=SAMPLE,
        expect=(("avoided", "tree"), ("unread", "helipad")),
        routes=(Route("sample", "less_on", "tree"),),
    ),
    Brief(
        prompt="Please avoid the trees, and also avoid the mud holes near the instrument tower.",
        voice="field",
        construct="clauses",
        layers=TREES,
        expect=(("avoided", "tree"), ("unread", "mud")),
        routes=(Route("neon", "less_on", "tree"),),
    ),
    Brief(
        prompt=("Minimise time spent over buildings. Give way to pedestrians at all crossings. Favour shaded ground."),
        voice="analyst",
        construct="clauses",
        layers=BUILDINGS,
        expect=(("avoided", "building"), ("unread", "pedestrians"), ("unread", "shaded")),
        routes=(Route("massachusetts", "less_on", "building"),),
    ),
    Brief(
        prompt="paved road: prefer\nconstruction zone: avoid\nunpaved road: avoid",
        voice="robot",
        construct="clauses",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("avoided", "unpaved road"), ("unread", "construction")),
        routes=(Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        prompt=(
            "so the kids were playing on the baseball field earlier, nice to see. anyway, the route "
            "should stick to the trail and avoid the road"
        ),
        voice="field",
        construct="clauses",
        layers=SAMPLE,
        expect=(("preferred", "trail"), ("avoided", "road"), ("neutral", "baseball field")),
        routes=(Route("sample", "more_on", "trail"), Route("sample", "less_on", "road")),
        why="The kids on the baseball field are an aside: no rule on it.",
    ),
    Brief(
        prompt=("The vehicle shall avoid buildings and water, and shall prefer the road wherever it is available."),
        voice="analyst",
        construct="clauses",
        layers=NB,
        expect=(
            ("avoided", "building"),
            ("avoided", "water"),
            ("preferred", "road"),
            ("all_read",),
        ),
        routes=(Route("nb1", "more_on", "road"), Route("nb1", "less_on", "water")),
    ),
    Brief(
        prompt=(
            "pre-run checklist:\n[x] tyres\n[x] firmware 2.4.1\n[ ] route: avoid water\n"
            "[ ] route: prefer trail\n[ ] route: dodge the sprinklers"
        ),
        voice="field",
        construct="clauses",
        layers=SAMPLE,
        expect=(("avoided", "water"), ("preferred", "trail"), ("unread", "sprinklers")),
        routes=(Route("sample", "more_on", "trail"), Route("sample", "less_on", "water")),
    ),
    Brief(
        prompt="heads up the drone's at 40% so be quick. route wise just avoid the trees, thats it",
        voice="field",
        construct="clauses",
        layers=TREES,
        expect=(("avoided", "tree"),),
        routes=(Route("neon", "less_on", "tree"),),
    ),
    Brief(
        prompt=(
            "Surface preference, in descending order: trail, road, grass. The baseball field is not to be entered."
        ),
        voice="analyst",
        construct="clauses",
        layers=SAMPLE,
        expect=(
            ("below", "trail", "road"),
            ("below", "road", "grass"),
            ("lethal", "baseball field"),
            ("all_read",),
        ),
        routes=(Route("sample", "more_on", "trail"), Route("sample", "zero_on", "baseball field")),
    ),
    Brief(
        prompt=(
            "road first, vegetation second, water only if there's no other way. Biscuit the dog is coming with us btw"
        ),
        voice="field",
        construct="clauses",
        layers=NB,
        expect=(("below", "road", "vegetation"), ("below", "vegetation", "water")),
        routes=(Route("nb1", "more_on", "road"), Route("nb1", "less_on", "water")),
        why="A ranking in prose; the dog is an aside.",
    ),
]
