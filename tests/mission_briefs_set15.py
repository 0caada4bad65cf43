"""Mission briefs, set 15: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench or the briefs of earlier sets: only the contract (``tests/mission_briefs.py``
and its format test ``tests/test_mission_briefs.py``), the scene index (``../shared/scenes/INDEX.md``
and the scenes' ``classes.json``) and the header of set 14 (for the layout of its constants) were
read. It is scored once, at first contact, with ``bench/mission_briefs_report.py --set 15``; that
figure is the one that counts, and the set is not edited afterwards to make the interpreter pass.

The voices are GIS analysts (long and formal, distances in metres, feet, yards or words), robot
operators (terse, symbolic: ``>``, ``->``, ``:``, lists) and field teams (chatty, typo-ridden,
with asides about times, people and kit that are not rules). The layers of each brief are the
class names of the scene its routes are checked on, so the route checks run on the real ground
truth.
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
            "Every planned path is required to remain at least twenty-five metres clear of the rail "
            "line at every point along its length; treat that clearance as a hard constraint."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "railway", 25), ("all_read",)),
        routes=(Route("nb1", "keeps", "railway", 25), Route("nb2", "keeps", "railway", 25)),
    ),
    Brief(
        prompt="Under no circumstances may the vehicle come within 40 ft of any open water body.",
        voice="analyst",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "water", 40 * FT),),
        routes=(Route("nb2", "keeps", "water", 40 * FT),),
        why="40 ft is 12.2 m.",
    ),
    Brief(
        prompt="min clearance bldg 8m. hard.",
        voice="robot",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "building", 8),),
        routes=(Route("nb1", "keeps", "building", 8),),
    ),
    Brief(
        prompt="buildings: >= 3 m standoff, always",
        voice="robot",
        construct="distance_hard",
        layers=BUILDINGS,
        expect=(("keep_out", "building", 3),),
        routes=(Route("kampala", "keeps", "building", 3),),
    ),
    Brief(
        prompt=(
            "ok so the rule from the landowners is nobody gets closer than 10 yards to any of the "
            "houses, no exceptions, they were super clear about it"
        ),
        voice="field",
        construct="distance_hard",
        layers=BUILDINGS,
        expect=(("keep_out", "building", 10 * YD),),
        routes=(Route("massachusetts", "keeps", "building", 10 * YD),),
        why="10 yards is 9.1 m; 'no exceptions' makes it absolute.",
    ),
    Brief(
        prompt="dont get any closer then 5 metres to the rail lines. thats a hard rule from the safety officer",
        voice="field",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "railway", 5),),
        routes=(Route("nb2", "keeps", "railway", 5),),
    ),
    Brief(
        prompt=(
            "The route must never run directly along the water's edge; a mandatory buffer from the "
            "shoreline applies to all legs of the mission."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "water", None),),
        routes=(Route("nb1", "keeps", "water", 1),),
        why="A mandatory buffer with no number: the default zone (ground 1 m from the water kept out).",
    ),
    Brief(
        prompt="keep-out radius 15 m around all structures",
        voice="robot",
        construct="distance_hard",
        layers=BUILDINGS,
        expect=(("keep_out", "building", 15),),
        routes=(Route("massachusetts", "keeps", "building", 15),),
    ),
    Brief(
        prompt="u must stay clear of the railway at all times, absolutly no walking right up next to it",
        voice="field",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "railway", None),),
        routes=(Route("nb1", "keeps", "railway", 1),),
        why="'must ... at all times, absolutely no' is absolute wording with no number.",
    ),
    Brief(
        prompt=(
            "A minimum clearance of two metres from every building footprint is required throughout; "
            "any route that breaches it is invalid."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=BUILDINGS,
        expect=(("keep_out", "building", 2),),
        routes=(Route("kampala", "keeps", "building", 2),),
    ),
    Brief(
        prompt="road standoff 12 m mandatory; rail standoff 6 m mandatory",
        voice="robot",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "road", 12), ("keep_out", "railway", 6), ("all_read",)),
        routes=(Route("nb2", "keeps", "road", 12), Route("nb1", "keeps", "railway", 6)),
    ),
    # ------------------------------------------------------------------------------------------
    # distance_soft: softly worded distance rules make soft zones, the number kept
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Where practicable the route should maintain roughly 20 metres of separation from the "
            "railway, although brief encroachments are acceptable if they save significant distance."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "railway", 20), ("not_lethal", "railway")),
        routes=(Route("nb1", "farther", "railway"),),
    ),
    Brief(
        prompt="bldg buffer 6m (soft, can violate)",
        voice="robot",
        construct="distance_soft",
        layers=BUILDINGS,
        expect=(("soft_zone", "building", 6),),
        routes=(Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        prompt=("if u can, give the houses maybe 10 m or so, but its not the end of the world if you cut a bit closer"),
        voice="field",
        construct="distance_soft",
        layers=BUILDINGS,
        expect=(("soft_zone", "building", 10),),
        routes=(Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        prompt="It is preferable, though not mandatory, to keep approximately 30 ft back from the river bank.",
        voice="analyst",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "water", 30 * FT), ("not_lethal", "water")),
        routes=(Route("nb2", "farther", "water"),),
        why="30 ft is 9.1 m.",
    ),
    Brief(
        prompt="water: try for 15m clearance, not strict",
        voice="robot",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "water", 15),),
        routes=(Route("nb1", "farther", "water"),),
    ),
    Brief(
        prompt=(
            "ideally stay like fifteen metres off the road, the cars go fast there, but if its the "
            "only way thru thats ok"
        ),
        voice="field",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "road", 15), ("not_lethal", "road")),
        routes=(Route("nb1", "farther", "road"),),
    ),
    Brief(
        prompt="Some separation from the structures is desirable but should not be enforced rigidly.",
        voice="analyst",
        construct="distance_soft",
        layers=BUILDINGS,
        expect=(("soft_zone", "building", None),),
        routes=(Route("kampala", "farther", "building"),),
    ),
    Brief(
        prompt="try and leave a bit of room between you and the train tracks if its easy to",
        voice="field",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "railway", None),),
        routes=(Route("nb2", "farther", "railway"),),
    ),
    Brief(
        prompt="rail standoff ~10 m preferred, ok to violate",
        voice="robot",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "railway", 10), ("not_lethal", "railway")),
        routes=(Route("nb1", "farther", "railway"),),
    ),
    # ------------------------------------------------------------------------------------------
    # graded_away: the closer, the dearer
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Exposure to the roadway should be minimised: the cost of a path ought to rise the "
            "nearer it comes to the road, with no effect beyond about 25 metres."
        ),
        voice="analyst",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "road", 25),),
        routes=(Route("nb1", "farther", "road"),),
    ),
    Brief(
        prompt="the further from the buildings the better honestly, people get nervous seeing the robot",
        voice="field",
        construct="graded_away",
        layers=BUILDINGS,
        expect=(("graded_away", "building", None),),
        routes=(Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        prompt="away from water, more distance = better",
        voice="robot",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "water", None),),
        routes=(Route("nb2", "farther", "water"),),
    ),
    Brief(
        prompt=(
            "Proximity to the railway carries increasing risk; nearness to it should be penalised "
            "progressively out to a distance of fifteen metres."
        ),
        voice="analyst",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "railway", 15),),
        routes=(Route("nb1", "farther", "railway"),),
    ),
    Brief(
        prompt="dont go near the houses if u can help it, theres kids everywhere round there",
        voice="field",
        construct="graded_away",
        layers=BUILDINGS,
        expect=(("graded_away", "building", None), ("not_lethal", "building")),
        routes=(Route("kampala", "farther", "building"),),
    ),
    Brief(
        prompt="bldg proximity penalty, falloff 10 m",
        voice="robot",
        construct="graded_away",
        layers=BUILDINGS,
        expect=(("graded_away", "building", 10),),
        routes=(Route("kampala", "farther", "building"),),
    ),
    Brief(
        prompt=(
            "Keep the approach well away from the shoreline, with nearness weighted more heavily "
            "within 60 feet of the water."
        ),
        voice="analyst",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "water", 60 * FT),),
        routes=(Route("nb1", "farther", "water"),),
        why="60 ft is 18.3 m.",
    ),
    Brief(
        prompt="keep well away from the road, theres a film crew set up along it all day (Jen's lot)",
        voice="field",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "road", None),),
        routes=(Route("nb2", "farther", "road"),),
    ),
    Brief(
        prompt="road: avoid, closer = worse, 20m",
        voice="robot",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "road", 20), ("avoided", "road")),
        routes=(Route("nb1", "farther", "road"), Route("nb1", "less_on", "road")),
    ),
    # ------------------------------------------------------------------------------------------
    # graded_toward: the closer, the cheaper
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "The route should remain as close as reasonably possible to the road, so that the "
            "support vehicle can reach the team at short notice."
        ),
        voice="analyst",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "road", None),),
        routes=(Route("nb1", "closer", "road"),),
    ),
    Brief(
        prompt="stay near the river if u can, were taking water samples on the way",
        voice="field",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "water", None),),
        routes=(Route("nb2", "closer", "water"),),
    ),
    Brief(
        prompt="near buildings = good, the nearer the better",
        voice="robot",
        construct="graded_toward",
        layers=BUILDINGS,
        expect=(("graded_toward", "building", None),),
        routes=(Route("kampala", "closer", "building"),),
    ),
    Brief(
        prompt=(
            "Proximity to buildings is beneficial for radio coverage; nearness should be rewarded "
            "within approximately 30 metres of a structure."
        ),
        voice="analyst",
        construct="graded_toward",
        layers=BUILDINGS,
        expect=(("graded_toward", "building", 30),),
        routes=(Route("massachusetts", "closer", "building"),),
    ),
    Brief(
        prompt="keep within sight of the railway line, its our landmark, we'll get lost otherwise lol",
        voice="field",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "railway", None),),
        routes=(Route("nb1", "closer", "railway"),),
    ),
    Brief(
        prompt="veg edge: prefer proximity, 10 m",
        voice="robot",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "vegetation", 10),),
        routes=(Route("nb2", "closer", "vegetation"),),
    ),
    Brief(
        prompt=("Favour paths that remain within about fifty feet of the water; the closer to the bank, the better."),
        voice="analyst",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "water", 50 * FT),),
        routes=(Route("nb1", "closer", "water"),),
        why="50 ft is 15.2 m.",
    ),
    Brief(
        prompt="try and stay close to the houses, the wifi relay only reaches like 20 m",
        voice="field",
        construct="graded_toward",
        layers=BUILDINGS,
        expect=(("graded_toward", "building", 20),),
        routes=(Route("massachusetts", "closer", "building"),),
    ),
    Brief(
        prompt="road proximity: prefer. nearer -> cheaper",
        voice="robot",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "road", None),),
        routes=(Route("nb2", "closer", "road"),),
    ),
    # ------------------------------------------------------------------------------------------
    # on_beside: along X but not on X
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Proceed along the railway corridor, parallel to the tracks, without at any point "
            "travelling on the rails themselves."
        ),
        voice="analyst",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "railway"),),
        routes=(Route("nb1", "beside", "railway", 6),),
    ),
    Brief(
        prompt="walk along the road but on the verge, never on the actual tarmac, too many trucks",
        voice="field",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "road"),),
        routes=(Route("nb2", "beside", "road", 5),),
    ),
    Brief(
        prompt="follow road edge, not on road",
        voice="robot",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "road"),),
        routes=(Route("nb1", "beside", "road", 5),),
    ),
    Brief(
        prompt=(
            "The path should follow the edge of the woodland closely but remain on open ground "
            "rather than entering the vegetation."
        ),
        voice="analyst",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "vegetation"),),
        routes=(Route("nb2", "beside", "vegetation", 5),),
    ),
    Brief(
        prompt="hug the rivers edge, dont go in it obviously lol",
        voice="field",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "water"), ("lethal", "water")),
        routes=(Route("nb1", "beside", "water", 5), Route("nb1", "zero_on", "water")),
        why="'don't go in it' is the forbidding 'don't go into'.",
    ),
    Brief(
        prompt="parallel to rail, offset 3-5 m, never on rail",
        voice="robot",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "railway"),),
        routes=(Route("nb2", "beside", "railway", 5),),
    ),
    Brief(
        prompt=(
            "Routes ought to skirt the building perimeters closely, for shade and cover, but must "
            "not pass through any structure."
        ),
        voice="analyst",
        construct="on_beside",
        layers=BUILDINGS,
        expect=(("beside", "building"),),
        routes=(Route("massachusetts", "beside", "building", 5),),
    ),
    Brief(
        prompt="stick right by the walls of the houses, along them not thru them",
        voice="field",
        construct="on_beside",
        layers=BUILDINGS,
        expect=(("beside", "building"),),
        routes=(Route("kampala", "beside", "building", 3),),
    ),
    Brief(
        prompt="along paved road shoulder -> ok. on paved road -> no",
        voice="robot",
        construct="on_beside",
        layers=VEGAS,
        expect=(("beside", "paved road"),),
        routes=(Route("vegas", "beside", "paved road", 5),),
    ),
    Brief(
        prompt=(
            "go alongside the tracks the whole way, its the easiest way to navigate out there, "
            "but dont walk on the tracks themselves"
        ),
        voice="field",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "railway"),),
        routes=(Route("nb1", "beside", "railway", 5),),
    ),
    # ------------------------------------------------------------------------------------------
    # qualified: paved / unpaved, deciduous / conifer
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Prefer sealed asphalt carriageways throughout; unsurfaced dirt roads should be avoided "
            "owing to dust and soft ground."
        ),
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
        prompt=(
            "stick to the gravel roads if you can, the robots tyres get way too hot on the tarmac in the afternoon"
        ),
        voice="field",
        construct="qualified",
        layers=VEGAS,
        expect=(
            ("preferred", "unpaved road"),
            ("below", "unpaved road", "paved road"),
            ("not_lethal", "paved road"),
        ),
        why="No route check: the unpaved class is nearly empty on the Vegas scene.",
    ),
    Brief(
        prompt=(
            "Use surfaced roads for transit wherever available; unpaved tracks are not to be used "
            "under any circumstances."
        ),
        voice="analyst",
        construct="qualified",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("lethal", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"), Route("vegas", "zero_on", "unpaved road")),
        why="'not to be used under any circumstances' forbids.",
    ),
    Brief(
        prompt="pls no driving on the dirt tracks, theyre totally washed out after the storm. blacktop is fine",
        voice="field",
        construct="qualified",
        layers=VEGAS,
        expect=(("lethal", "unpaved road"), ("not_lethal", "paved road")),
        routes=(Route("vegas", "zero_on", "unpaved road"),),
        why="'no driving on' forbids; the blacktop is merely allowed.",
    ),
    Brief(
        prompt="paved rd: prefer. unpaved rd: avoid",
        voice="robot",
        construct="qualified",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("avoided", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        prompt=(
            "The rover should keep to the asphalt wherever it can, and otherwise cross open desert "
            "rather than use the graded dirt roads."
        ),
        voice="analyst",
        construct="qualified",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("avoided", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="Open desert is unlabelled ground; dirt roads are dearer than it.",
    ),
    Brief(
        prompt="go under the oaks n maples if poss, the pine stands are way too dense for the quad",
        voice="field",
        construct="qualified",
        layers=("deciduous tree", "conifer tree"),
        expect=(
            ("preferred", "deciduous tree"),
            ("avoided", "conifer tree"),
            ("below", "deciduous tree", "conifer tree"),
        ),
        why="No scene has these classes: reading only.",
    ),
    Brief(
        prompt="tarmac good, gravel bad, simple as",
        voice="field",
        construct="qualified",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("avoided", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        prompt="Unsealed roads may be used where necessary, but sealed roads are strongly preferred.",
        voice="analyst",
        construct="qualified",
        layers=VEGAS,
        expect=(
            ("preferred", "paved road"),
            ("below", "paved road", "unpaved road"),
            ("not_lethal", "unpaved road"),
        ),
        routes=(Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        prompt="asphalt only; dirt = no-go",
        voice="robot",
        construct="qualified",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("lethal", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"), Route("vegas", "zero_on", "unpaved road")),
    ),
    # ------------------------------------------------------------------------------------------
    # terse: symbolic orderings and short rules
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="road > veg > bldg",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(("below", "road", "vegetation"), ("below", "vegetation", "building")),
        why="An ordering only: levels not asserted.",
    ),
    Brief(
        prompt="water bodies: no",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(("lethal", "water"),),
        routes=(Route("nb1", "zero_on", "water"),),
        why="'X: no' forbids X.",
    ),
    Brief(
        prompt="rail ok, roads preferred, bldg avoid",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(
            ("neutral", "railway"),
            ("preferred", "road"),
            ("avoided", "building"),
            ("below", "road", "railway"),
        ),
        routes=(Route("nb2", "more_on", "road"), Route("nb2", "less_on", "building")),
    ),
    Brief(
        prompt="veg -> avoid; road -> prefer",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(("avoided", "vegetation"), ("preferred", "road")),
        routes=(Route("nb1", "more_on", "road"), Route("nb1", "less_on", "vegetation")),
    ),
    Brief(
        prompt="pavd raod: yes / unpaved rd: no",
        voice="robot",
        construct="terse",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("lethal", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"), Route("vegas", "zero_on", "unpaved road")),
        why="Typos in a multi-word class name.",
    ),
    Brief(
        prompt="bldg: no-go",
        voice="robot",
        construct="terse",
        layers=BUILDINGS,
        expect=(("lethal", "building"),),
        routes=(Route("massachusetts", "zero_on", "building"),),
    ),
    Brief(
        prompt="1. road  2. open ground  3. vegetation",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(("preferred", "road"), ("avoided", "vegetation"), ("below", "road", "vegetation")),
        routes=(Route("nb1", "more_on", "road"), Route("nb1", "less_on", "vegetation")),
        why="A ranked list around open (unlabelled, neutral) ground.",
    ),
    Brief(
        prompt="avoid: water, railway, buildings",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(
            ("avoided", "water"),
            ("avoided", "railway"),
            ("avoided", "building"),
            ("not_lethal", "railway"),
        ),
        routes=(Route("nb2", "less_on", "railway"), Route("nb2", "less_on", "building")),
    ),
    Brief(
        prompt="prefer: road | avoid: vegitation",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(("preferred", "road"), ("avoided", "vegetation")),
        routes=(Route("nb2", "more_on", "road"),),
    ),
    Brief(
        prompt="raod good, railwya bad",
        voice="field",
        construct="terse",
        layers=NB,
        expect=(("preferred", "road"), ("avoided", "railway")),
        routes=(Route("nb1", "more_on", "road"), Route("nb1", "less_on", "railway")),
    ),
    Brief(
        prompt="x-ing rail: never",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(("no_cross", "railway"),),
        routes=(Route("nb2", "less_on", "railway"),),
    ),
    # ------------------------------------------------------------------------------------------
    # permission: permissions lift priors; stay-out wording forbids
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="fine to cut across the railway tracks, theyre disused, no trains since like 2015",
        voice="field",
        construct="permission",
        layers=NB,
        expect=(("neutral", "railway"), ("not_lethal", "railway")),
        why="Merely allowed: neutral. No route check (the flat route is the same costmap there).",
    ),
    Brief(
        prompt="the ponds frozen solid this week so walking straight over the water is ok",
        voice="field",
        construct="permission",
        layers=NB,
        expect=(("neutral", "water"), ("not_lethal", "water")),
    ),
    Brief(
        prompt=(
            "The platform operates at altitude above roof level, so building footprints impose no "
            "constraint on the route."
        ),
        voice="analyst",
        construct="permission",
        layers=BUILDINGS,
        expect=(("neutral", "building"),),
    ),
    Brief(
        prompt="rail: allowed. water: no-go.",
        voice="robot",
        construct="permission",
        layers=NB,
        expect=(("neutral", "railway"), ("lethal", "water")),
        routes=(Route("nb1", "zero_on", "water"),),
    ),
    Brief(
        prompt=("Crossing the railway is permitted at any point, but the team must stay out of the water entirely."),
        voice="analyst",
        construct="permission",
        layers=NB,
        expect=(("neutral", "railway"), ("not_lethal", "railway"), ("lethal", "water")),
        routes=(Route("nb2", "zero_on", "water"),),
    ),
    Brief(
        prompt=(
            "going right through the buildings is fine, theyre all derelict and wide open, we "
            "checked with Sam yesterday"
        ),
        voice="field",
        construct="permission",
        layers=BUILDINGS,
        expect=(("neutral", "building"), ("not_lethal", "building")),
    ),
    Brief(
        prompt="Entry into any building is prohibited; the structures are off limits to the survey team.",
        voice="analyst",
        construct="permission",
        layers=NB,
        expect=(("lethal", "building"),),
        routes=(Route("nb1", "zero_on", "building"),),
    ),
    Brief(
        prompt="keep out of the veg pls, the ticks are terrible this year",
        voice="field",
        construct="permission",
        layers=NB,
        expect=(("lethal", "vegetation"),),
        routes=(Route("nb2", "zero_on", "vegetation"),),
    ),
    Brief(
        prompt="trees ok",
        voice="robot",
        construct="permission",
        layers=TREES,
        expect=(("neutral", "tree"), ("not_lethal", "tree")),
    ),
    Brief(
        prompt="ok to go over the tracks and thru the veg, just dont go into the water",
        voice="field",
        construct="permission",
        layers=NB,
        expect=(("neutral", "railway"), ("not_lethal", "vegetation"), ("lethal", "water")),
        routes=(Route("nb1", "zero_on", "water"),),
    ),
    Brief(
        prompt=(
            "Water features may be traversed, the vehicle being amphibious; avoidance of the railway, "
            "however, remains advisable."
        ),
        voice="analyst",
        construct="permission",
        layers=NB,
        expect=(("neutral", "water"), ("avoided", "railway"), ("not_lethal", "railway")),
        routes=(Route("nb2", "less_on", "railway"),),
    ),
    Brief(
        prompt="The route must not cross the railway line at any point.",
        voice="analyst",
        construct="permission",
        layers=NB,
        expect=(("no_cross", "railway"),),
        routes=(Route("nb1", "less_on", "railway"),),
    ),
    Brief(
        prompt="whatever u do dont cross the road, the site manager will go mental",
        voice="field",
        construct="permission",
        layers=NB,
        expect=(("no_cross", "road"),),
        routes=(Route("nb2", "less_on", "road"),),
    ),
    Brief(
        prompt="no crossing: water",
        voice="robot",
        construct="permission",
        layers=NB,
        expect=(("no_cross", "water"),),
        routes=(Route("nb1", "less_on", "water"),),
    ),
    # ------------------------------------------------------------------------------------------
    # clauses: unread clauses reported, every clause of a plain brief read
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="avoid the road, and make sure to radio base every half hour",
        voice="field",
        construct="clauses",
        layers=NB,
        expect=(("avoided", "road"), ("unread", "radio")),
        routes=(Route("nb1", "less_on", "road"),),
    ),
    Brief(
        prompt="road: prefer; battery swap @ 40%",
        voice="robot",
        construct="clauses",
        layers=NB,
        expect=(("preferred", "road"), ("unread", "battery")),
        routes=(Route("nb2", "more_on", "road"),),
    ),
    Brief(
        prompt=(
            "Prefer the road network; avoid the railway; and route around the temporary exclusion "
            "area declared by the county last Thursday."
        ),
        voice="analyst",
        construct="clauses",
        layers=NB,
        expect=(("preferred", "road"), ("avoided", "railway"), ("unread", "exclusion")),
        routes=(Route("nb1", "more_on", "road"), Route("nb1", "less_on", "railway")),
        why="The exclusion area is no layer of the brief: its clause cannot be read.",
    ),
    Brief(
        prompt="stay away from the houses, and watch out for the dogs at the blue gate",
        voice="field",
        construct="clauses",
        layers=BUILDINGS,
        expect=(("avoided", "building"), ("unread", "dogs")),
        routes=(Route("massachusetts", "less_on", "building"),),
    ),
    Brief(
        prompt="Prefer the road, avoid the vegetation, and keep at least ten metres from the railway.",
        voice="analyst",
        construct="clauses",
        layers=NB,
        expect=(
            ("preferred", "road"),
            ("avoided", "vegetation"),
            ("keep_out", "railway", 10),
            ("all_read",),
        ),
        routes=(Route("nb1", "keeps", "railway", 10), Route("nb1", "more_on", "road")),
    ),
    Brief(
        prompt="road: prefer. water: avoid. rail: 5 m min.",
        voice="robot",
        construct="clauses",
        layers=NB,
        expect=(("preferred", "road"), ("avoided", "water"), ("keep_out", "railway", 5), ("all_read",)),
        routes=(Route("nb2", "keeps", "railway", 5), Route("nb2", "more_on", "road")),
    ),
    Brief(
        prompt="stay on the roads where u can, try not to use the rail line, and go round the water",
        voice="field",
        construct="clauses",
        layers=NB,
        expect=(("preferred", "road"), ("avoided", "railway"), ("avoided", "water"), ("all_read",)),
        routes=(Route("nb1", "more_on", "road"), Route("nb1", "less_on", "railway")),
    ),
    Brief(
        prompt="use the paved roads, and avoid the area where the drone lost GPS yesterday",
        voice="field",
        construct="clauses",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("unread", "GPS")),
        routes=(Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        prompt=(
            "Maintain a minimum clearance of 4 m from all buildings, prefer the roads, and do not "
            "enter the water under any circumstances."
        ),
        voice="analyst",
        construct="clauses",
        layers=NB,
        expect=(("keep_out", "building", 4), ("preferred", "road"), ("lethal", "water"), ("all_read",)),
        routes=(Route("nb2", "keeps", "building", 4), Route("nb2", "zero_on", "water")),
    ),
    Brief(
        prompt=(
            "go along the road, the lake is off limits, and Toms bringing the thermal camera so "
            "we'll film the whole way"
        ),
        voice="field",
        construct="clauses",
        layers=NB,
        expect=(("preferred", "road"), ("lethal", "water"), ("unread", "camera")),
        routes=(Route("nb1", "zero_on", "water"), Route("nb1", "more_on", "road")),
    ),
    Brief(
        prompt="avoid bldg; no-fly zone sector 7",
        voice="robot",
        construct="clauses",
        layers=BUILDINGS,
        expect=(("avoided", "building"), ("unread", "sector")),
        routes=(Route("kampala", "less_on", "building"),),
    ),
    Brief(
        prompt="asphalt preferred > dirt roads avoided; ETA 14:30",
        voice="robot",
        construct="clauses",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("avoided", "unpaved road"), ("unread", "ETA")),
        routes=(Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        prompt=(
            "The survey line should keep well away from the railway, follow the road where it can, "
            "and never cross the water."
        ),
        voice="analyst",
        construct="clauses",
        layers=NB,
        expect=(
            ("graded_away", "railway", None),
            ("preferred", "road"),
            ("no_cross", "water"),
            ("all_read",),
        ),
        routes=(Route("nb2", "farther", "railway"), Route("nb2", "more_on", "road")),
    ),
]
