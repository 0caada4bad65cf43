"""Mission briefs, set 19: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench or the briefs of earlier sets: only the contract (``tests/mission_briefs.py``
and its format test ``tests/test_mission_briefs.py``), the scene index (``../shared/scenes/INDEX.md``
and the scenes' ``classes.json``) and the first 40 lines of set 18 (for the layout of its module
constants and docstring) were read. It is scored once, at first contact, with
``bench/mission_briefs_report.py --set 19``; that figure is the one that counts, and the set is not
edited afterwards to make the interpreter pass.

The voices are a utility company's GIS analyst planning inspection traverses, an environmental
consultant quoting permit conditions, a search-and-rescue coordinator and a university field
course (analysts and field crews), a farm robot operator, a drone-delivery ops engineer writing
config and a terse military-style order (robot operators), and tired field techs texting from a
phone (typos, no punctuation, abbreviations), some of them writing in non-native English. The
constructs are ranked preferences (chains, "A before B", "A over B", "rather A than B", "A is
better than B", numbered lists), forbidden areas ("stay out of X entirely", "never enter",
"off limits", "no-go", "keep out of") against plain avoidance ("avoid X", "try not to use X"),
permissions that lift priors (vacant buildings, a frozen pond, a dry riverbed, thinned canopy, a
disused railway), hard distance rules with numbers in metres, feet and yards and absolute wording,
soft distance rules ("ideally", "where practicable"), graded nearness in both directions, on
versus beside (bank not water, shoulder not carriageway, canopy edge not crowns), qualified classes
on the Las Vegas scene (paved road against unpaved road under many names), and clauses naming things
no layer stands for (a gas pipeline, transformer boxes, beehives, irrigation canals, wind turbines,
a survey mast, a sinkhole), which must be reported unread. The layers of each brief are the class
names of the scene its routes are checked on; briefs over layers no scene holds carry no route
checks.
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
#: A farm's own layers (no scene holds them: no route checks).
FARM = ("crop", "headland", "track", "pond")

#: Briefs retired after scoring, with the reason (none yet).
DOUBTFUL: dict[str, str] = {}

#: Metres in a foot and in a yard.
FT = 0.3048
YD = 0.9144

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------------------------------
    # Hard distance rules: absolute wording, numbers in metres, feet and yards
    # ------------------------------------------------------------------------------------------
    Brief(
        "Feeder inspection traverse. At no point may the crew come within 12 m of a building.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "building", 12),),
        (
            Route("nb1", "keeps", "building", 12),
            Route("massachusetts", "keeps", "building", 12),
        ),
    ),
    Brief(
        "Standoff requirement: 50 ft minimum from open water. This is absolute; no waivers will be granted.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "water", 50 * FT),),
        (Route("nb1", "keeps", "water", 50 * FT),),
    ),
    Brief(
        "rail safety says nobody gets closer than 20 yards to the tracks. period. no exceptions",
        "field",
        "distance_hard",
        NB,
        (("keep_out", "railway", 20 * YD),),
        (Route("nb2", "keeps", "railway", 20 * YD),),
    ),
    Brief(
        "tree_clearance_min_m: 3   # hard limit, rotor safety, never violate",
        "robot",
        "distance_hard",
        TREES,
        (("keep_out", "tree", 3),),
        (Route("neon", "keeps", "tree", 3),),
    ),
    Brief(
        "Permit condition 7: no vehicle movement is permitted within 25 metres of the water under any circumstances.",
        "analyst",
        "distance_hard",
        SAMPLE,
        (("keep_out", "water", 25), ("avoided", "building")),
        (Route("sample", "keeps", "water", 25),),
        why="the building is not mentioned: it keeps its hazard prior",
    ),
    Brief(
        "The drone it must always stay minimum 8 metre away from the houses, this is a strict rule.",
        "field",
        "distance_hard",
        BUILDINGS,
        (("keep_out", "building", 8),),
        (Route("massachusetts", "keeps", "building", 8),),
        why="non-native wording of an absolute standoff; houses are the building layer",
    ),
    Brief(
        "Condition 4.2: no plant or personnel within 30 m of the watercourse at any time. "
        "Condition 4.3: travel through vegetation is to be minimised.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "water", 30), ("avoided", "vegetation"), ("not_lethal", "vegetation")),
        (Route("nb1", "keeps", "water", 30), Route("nb1", "less_on", "vegetation")),
    ),
    Brief(
        "A mandatory exclusion buffer applies around the railway; the rover may not encroach on it under any circumstances.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "railway", None),),
        why="absolute wording with no number: a hard zone of the default width",
    ),
    # ------------------------------------------------------------------------------------------
    # Soft distance rules: the number kept, nothing kept out
    # ------------------------------------------------------------------------------------------
    Brief(
        "Where practicable, hold the inspection vehicle roughly 10 m back from buildings.",
        "analyst",
        "distance_soft",
        NB,
        (("soft_zone", "building", 10), ("not_lethal", "building")),
        (Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        "try to give the water like 15 m if u can, not a big deal if u cant",
        "field",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "water", 15), ("not_lethal", "water")),
    ),
    Brief(
        "water_buffer_m: 6   # soft, preference only, ok to break if needed",
        "robot",
        "distance_soft",
        NB,
        (("soft_zone", "water", 6), ("not_lethal", "water")),
    ),
    Brief(
        "Ideally the sensor platform passes no nearer than 2 m to a tree crown, though brushing closer is tolerable.",
        "analyst",
        "distance_soft",
        TREES,
        (("soft_zone", "tree", 2), ("not_lethal", "tree")),
    ),
    Brief(
        "If possible please keep some 30 feet from the buildings, but it is not obligatory.",
        "field",
        "distance_soft",
        BUILDINGS,
        (("soft_zone", "building", 30 * FT), ("not_lethal", "building")),
    ),
    Brief(
        "No entry within 10 m of the water, and that one is absolute; where it can be managed, "
        "also keep about 5 m from buildings.",
        "analyst",
        "distance_soft",
        NB,
        (("keep_out", "water", 10), ("soft_zone", "building", 5)),
        (Route("nb1", "keeps", "water", 10),),
        why="one hard rule and one soft one in the same brief: only the first is kept out",
    ),
    # ------------------------------------------------------------------------------------------
    # Graded nearness, away: the closer the dearer
    # ------------------------------------------------------------------------------------------
    Brief(
        "honestly the further from the tracks the better, trains come thru fast here",
        "field",
        "graded_away",
        NB,
        (("graded_away", "railway", None),),
        (Route("nb2", "farther", "railway"),),
    ),
    Brief(
        "Keep well clear of the water; extra distance from it is worth a longer route.",
        "analyst",
        "graded_away",
        NB,
        (("graded_away", "water", None), ("not_lethal", "water")),
        (Route("nb1", "farther", "water"),),
    ),
    Brief(
        "All search teams: don't go near the buildings, several have been flagged as structurally unsound.",
        "analyst",
        "graded_away",
        NB,
        (("graded_away", "building", None),),
        (Route("nb1", "farther", "building"),),
        why="'don't go near' prices nearness; it does not forbid the building",
    ),
    Brief(
        "Distance from tree crowns is good: the more the better up to 10 m, beyond that it makes no difference.",
        "analyst",
        "graded_away",
        TREES,
        (("graded_away", "tree", 10),),
        (Route("neon", "farther", "tree"),),
    ),
    Brief(
        "Please the robot should not go near of the baseball field, there are children playing.",
        "field",
        "graded_away",
        SAMPLE,
        (("graded_away", "baseball field", None),),
        (Route("sample", "farther", "baseball field"),),
    ),
    Brief(
        "Maximise separation from buildings; the benefit tapers off at 20 m.",
        "analyst",
        "graded_away",
        BUILDINGS,
        (("graded_away", "building", 20),),
        (Route("massachusetts", "farther", "building"),),
    ),
    # ------------------------------------------------------------------------------------------
    # Graded nearness, toward: the closer the cheaper
    # ------------------------------------------------------------------------------------------
    Brief(
        "Search parties should stay close to the road so the trucks can reach them quickly.",
        "analyst",
        "graded_toward",
        NB,
        (("graded_toward", "road", None),),
        (Route("nb1", "closer", "road"),),
    ),
    Brief(
        "keep within sight of the trail the whole way, we only have one radio between us",
        "field",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "trail", None),),
        (Route("sample", "closer", "trail"),),
    ),
    Brief(
        "nav_mode: hug the water, nearer is better",
        "robot",
        "graded_toward",
        NB,
        (("graded_toward", "water", None),),
        (Route("nb1", "closer", "water"),),
    ),
    Brief(
        "Move tight along the treeline throughout. Do not stray from it.",
        "robot",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "tree", None),),
        (Route("sample", "closer", "tree"),),
        why="a military-style order to hug the tree edge",
    ),
    Brief(
        "For the mapping exercise students should remain near the buildings; the nearer, the better.",
        "field",
        "graded_toward",
        BUILDINGS,
        (("graded_toward", "building", None),),
        (Route("massachusetts", "closer", "building"),),
    ),
    Brief(
        "The rover should keep close to the paved road so it stays in range of the support vehicle.",
        "analyst",
        "graded_toward",
        VEGAS,
        (("graded_toward", "paved road", None),),
        (Route("vegas", "closer", "paved road"),),
    ),
    # ------------------------------------------------------------------------------------------
    # On versus beside
    # ------------------------------------------------------------------------------------------
    Brief(
        "walk the river bank, not the river itself. feet dry pls",
        "field",
        "on_beside",
        NB,
        (("beside", "water"),),
        (Route("nb1", "beside", "water", 5),),
    ),
    Brief(
        "Survey along the shoulder of the paved road; the carriageway itself is not to be driven on.",
        "analyst",
        "on_beside",
        VEGAS,
        (("beside", "paved road"),),
        (Route("vegas", "beside", "paved road", 5),),
    ),
    Brief(
        "follow: road edge\non road: avoid",
        "robot",
        "on_beside",
        NB,
        (("beside", "road"),),
        (Route("nb1", "beside", "road", 5),),
    ),
    Brief(
        "Go along the side of the trail, not on top of it, because the trail surface is fragile.",
        "field",
        "on_beside",
        SAMPLE,
        (("beside", "trail"),),
        (Route("sample", "beside", "trail", 5),),
    ),
    Brief(
        "Fly the edge of the canopy and never over the crowns themselves.",
        "analyst",
        "on_beside",
        TREES,
        (("beside", "tree"),),
        (Route("neon", "beside", "tree", 3),),
    ),
    Brief(
        "go along next to the buildings, like right along the walls, but obviously not thru them",
        "field",
        "on_beside",
        BUILDINGS,
        (("beside", "building"),),
        (Route("massachusetts", "beside", "building", 5),),
    ),
    # ------------------------------------------------------------------------------------------
    # Qualified classes on the Las Vegas scene
    # ------------------------------------------------------------------------------------------
    Brief(
        "Use sealed, paved roads wherever possible; unpaved tracks should be avoided.",
        "analyst",
        "qualified",
        VEGAS,
        (
            ("preferred", "paved road"),
            ("avoided", "unpaved road"),
            ("not_lethal", "unpaved road"),
            ("below", "paved road", "unpaved road"),
        ),
        (Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        "dirt roads r better than the blacktop for the tracked bot, it chews up asphalt",
        "field",
        "qualified",
        VEGAS,
        (("below", "unpaved road", "paved road"),),
        why="dirt roads are the unpaved class, blacktop and asphalt the paved one",
    ),
    Brief(
        "paved road: prefer\nunpaved road: forbidden",
        "robot",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("lethal", "unpaved road")),
        (Route("vegas", "more_on", "paved road"), Route("vegas", "zero_on", "unpaved road")),
    ),
    Brief(
        "The truck can drive on the asphalt road, but the gravel road it is not allowed to enter.",
        "field",
        "qualified",
        VEGAS,
        (("lethal", "unpaved road"), ("not_lethal", "paved road")),
        (Route("vegas", "zero_on", "unpaved road"),),
    ),
    Brief(
        "Keep off the tarmac as far as practicable; the sand tracks are acceptable.",
        "analyst",
        "qualified",
        VEGAS,
        (("avoided", "paved road"), ("not_lethal", "paved road"), ("below", "unpaved road", "paved road")),
        (Route("vegas", "less_on", "paved road"),),
    ),
    Brief(
        "Delivery legs should favour the bitumen-sealed streets over any dirt lane.",
        "analyst",
        "qualified",
        VEGAS,
        (("below", "paved road", "unpaved road"), ("preferred", "paved road")),
        (Route("vegas", "more_on", "paved road"),),
    ),
    # ------------------------------------------------------------------------------------------
    # Terse and symbolic
    # ------------------------------------------------------------------------------------------
    Brief(
        "trail > road > grass ; water = no-go",
        "robot",
        "terse",
        SAMPLE,
        (("below", "trail", "road"), ("below", "road", "grass"), ("lethal", "water")),
        (Route("sample", "zero_on", "water"), Route("sample", "more_on", "trail")),
    ),
    Brief(
        "road >> vegetation. bldgs off limits.",
        "robot",
        "terse",
        NB,
        (("below", "road", "vegetation"), ("lethal", "building")),
        (Route("nb1", "zero_on", "building"), Route("nb1", "more_on", "road")),
    ),
    Brief(
        "stay on the paved raod, stay out of the unpavd road entirely",
        "field",
        "terse",
        VEGAS,
        (("preferred", "paved road"), ("lethal", "unpaved road")),
        (Route("vegas", "more_on", "paved road"), Route("vegas", "zero_on", "unpaved road")),
        why="typos in both multi-word names",
    ),
    Brief(
        "canopy ok, go thru it",
        "robot",
        "terse",
        TREES,
        (("neutral", "tree"), ("not_lethal", "tree")),
        why="a terse permission: the canopy is merely allowed, so neutral",
    ),
    Brief(
        "prio: 1) road 2) vegetation 3) building. water: never enter",
        "robot",
        "terse",
        NB,
        (("below", "road", "vegetation"), ("below", "vegetation", "building"), ("lethal", "water")),
        (Route("nb1", "zero_on", "water"),),
    ),
    Brief(
        "Bldgs: keep out of. Min sep 5 m, hard.",
        "robot",
        "terse",
        BUILDINGS,
        (("lethal", "building"), ("keep_out", "building", 5)),
        (Route("massachusetts", "zero_on", "building"), Route("massachusetts", "keeps", "building", 5)),
    ),
    Brief(
        "# delivery corridor v3\nprefer: road\navoid: [vegetation]\nno_go: [water]\nmin_clearance_building_m: 10  # hard",
        "robot",
        "terse",
        NB,
        (
            ("preferred", "road"),
            ("avoided", "vegetation"),
            ("lethal", "water"),
            ("keep_out", "building", 10),
        ),
        (Route("nb1", "zero_on", "water"), Route("nb1", "keeps", "building", 10)),
    ),
    Brief(
        "Route: avoid open road. Hug treeline. Buildings: no-go.",
        "robot",
        "terse",
        SAMPLE,
        (
            ("avoided", "road"),
            ("not_lethal", "road"),
            ("graded_toward", "tree", None),
            ("lethal", "building"),
        ),
        (
            Route("sample", "less_on", "road"),
            Route("sample", "zero_on", "building"),
            Route("sample", "closer", "tree"),
        ),
    ),
    # ------------------------------------------------------------------------------------------
    # Permissions that lift priors, and stay-out wording that forbids
    # ------------------------------------------------------------------------------------------
    Brief(
        "All buildings on this parcel are vacant and scheduled for demolition, so the robot may pass "
        "through them. Stay out of the water entirely.",
        "analyst",
        "permission",
        NB,
        (("neutral", "building"), ("not_lethal", "building"), ("lethal", "water")),
        (Route("nb1", "zero_on", "water"),),
    ),
    Brief(
        "ponds frozen solid, ok to drive across the ice. avoid the buildings tho",
        "field",
        "permission",
        NB,
        (("neutral", "water"), ("not_lethal", "water"), ("avoided", "building"), ("not_lethal", "building")),
        (Route("nb1", "less_on", "building"),),
    ),
    Brief(
        "railway: disused since 2009, treat as open ground",
        "robot",
        "permission",
        NB,
        (("neutral", "railway"), ("not_lethal", "railway")),
    ),
    Brief(
        "The stand has been thinned and the crowns are sparse; flying through the canopy is permitted.",
        "analyst",
        "permission",
        TREES,
        (("neutral", "tree"), ("not_lethal", "tree")),
    ),
    Brief(
        "The river is dry in this season, so crossing the water area is allowed. But never enter the buildings.",
        "field",
        "permission",
        SAMPLE,
        (("neutral", "water"), ("not_lethal", "water"), ("lethal", "building")),
        (Route("sample", "zero_on", "building"),),
    ),
    Brief(
        "Mower bot: stay on the grass, the trail is ok too, keep out of the baseball field and the water.",
        "robot",
        "permission",
        SAMPLE,
        (
            ("preferred", "grass"),
            ("not_lethal", "trail"),
            ("lethal", "baseball field"),
            ("lethal", "water"),
        ),
        (
            Route("sample", "zero_on", "baseball field"),
            Route("sample", "zero_on", "water"),
            Route("sample", "more_on", "grass"),
        ),
    ),
    Brief(
        "Avoid the vegetation where you can, and keep out of the buildings altogether.",
        "analyst",
        "permission",
        NB,
        (("avoided", "vegetation"), ("not_lethal", "vegetation"), ("lethal", "building")),
        (Route("nb1", "less_on", "vegetation"), Route("nb1", "zero_on", "building")),
        why="plain avoidance against stay-out wording in one sentence",
    ),
    Brief(
        "Try not to use the road, it is busy today, but don't go into the water.",
        "field",
        "permission",
        NB,
        (("avoided", "road"), ("not_lethal", "road"), ("lethal", "water")),
        (Route("nb1", "less_on", "road"), Route("nb1", "zero_on", "water")),
    ),
    # ------------------------------------------------------------------------------------------
    # Clauses: what no layer holds is reported unread; plain rankings are read whole
    # ------------------------------------------------------------------------------------------
    Brief(
        "Avoid the buildings and stay clear of the gas pipeline easement.",
        "analyst",
        "clauses",
        NB,
        (("avoided", "building"), ("unread", "pipeline")),
        (Route("nb1", "less_on", "building"),),
    ),
    Brief(
        "stick to the trail n watch out for the beehives by the gate",
        "field",
        "clauses",
        SAMPLE,
        (("preferred", "trail"), ("unread", "beehives")),
        (Route("sample", "more_on", "trail"),),
    ),
    Brief(
        "avoid: [road, transformer_boxes]",
        "robot",
        "clauses",
        NB,
        (("avoided", "road"), ("unread", "transformer")),
        (Route("nb1", "less_on", "road"),),
    ),
    Brief(
        "Prefer the paved road. Also please avoid the irrigation canals.",
        "field",
        "clauses",
        VEGAS,
        (("preferred", "paved road"), ("unread", "canal")),
        (Route("vegas", "more_on", "paved road"),),
        why="no layer of the Vegas scene holds water: the canals clause has no effect",
    ),
    Brief(
        "Keep 10 m from buildings where practicable and do not overfly the wind turbines.",
        "analyst",
        "clauses",
        BUILDINGS,
        (("soft_zone", "building", 10), ("unread", "turbine")),
    ),
    Brief(
        "Avoid tree crowns. The survey mast is off limits.",
        "analyst",
        "clauses",
        TREES,
        (("avoided", "tree"), ("not_lethal", "tree"), ("unread", "mast")),
        (Route("neon", "less_on", "tree"),),
        why="a forbidding word on something no layer holds must be reported, not dropped",
    ),
    Brief(
        "stay off the road and dont go near the sinkhole by the barn",
        "field",
        "clauses",
        NB,
        (("avoided", "road"), ("unread", "sinkhole")),
        (Route("nb1", "less_on", "road"),),
    ),
    Brief(
        "Headland before track, track before crop; never enter the pond; watch the drainage tiles.",
        "robot",
        "clauses",
        FARM,
        (
            ("below", "headland", "track"),
            ("below", "track", "crop"),
            ("lethal", "pond"),
            ("unread", "drainage"),
        ),
        why="a farm's own layers: no scene holds them, so no route checks",
    ),
    Brief(
        "Prefer the trail, then the road; avoid the trees and the water.",
        "analyst",
        "clauses",
        SAMPLE,
        (
            ("preferred", "trail"),
            ("below", "trail", "road"),
            ("avoided", "tree"),
            ("avoided", "water"),
            ("all_read",),
        ),
        (Route("sample", "more_on", "trail"), Route("sample", "less_on", "water")),
    ),
    Brief(
        "Trail before road, and road before grass.",
        "analyst",
        "clauses",
        SAMPLE,
        (("below", "trail", "road"), ("below", "road", "grass"), ("preferred", "trail"), ("all_read",)),
        (Route("sample", "more_on", "trail"),),
    ),
    Brief(
        "id rather take the road than cut over the grass",
        "field",
        "clauses",
        SAMPLE,
        (("below", "road", "grass"),),
    ),
    Brief(
        "For the carts the road is better than the vegetation, and the vegetation is better than the water.",
        "field",
        "clauses",
        NB,
        (("below", "road", "vegetation"), ("below", "vegetation", "water"), ("all_read",)),
    ),
    Brief(
        "Ranked preference: (1) trail, (2) grass, (3) road.",
        "analyst",
        "clauses",
        SAMPLE,
        (("below", "trail", "grass"), ("below", "grass", "road"), ("all_read",)),
    ),
    Brief(
        "Grass over road, every time.",
        "field",
        "clauses",
        SAMPLE,
        (("below", "grass", "road"), ("avoided", "water"), ("all_read",)),
        why="the water is not mentioned: it keeps its hazard prior",
    ),
]
