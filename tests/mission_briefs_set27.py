"""Mission briefs, set 27: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench, the docs or the briefs of earlier sets: only the contract
(``tests/mission_briefs.py`` and its format test ``tests/test_mission_briefs.py``), the scene index
(``../shared/scenes/INDEX.md`` and the scenes' ``classes.json``), the first 45 lines of set 26
(for the layout, and its docstring's list of voices) and the first 25 lines of sets 23, 24 and 25
(their docstrings' lists of voices, which this set avoids) were read. It is scored once, at first
contact, with ``bench/mission_briefs_report.py --set 27``; that figure is the one that counts, and
the set is not edited afterwards to make the interpreter pass.

The voices are a park-and-ride shuttle dispatcher, a beekeeper (the hives along the tree line,
the mower), an archaeologist (trenches, spoil heaps, the old walls), a marathon course designer
("Course rule C-4"), a surveyor's CAD layer notes (``C-ROAD``, ``A-BLDG``, ``W-HYDRO``), a drone
racing league rulebook ("Rule 7.3 (Ground Support Vehicles)"), a hospital porter robot's
facilities manager (corridors, the loading dock), a tree surgeon (the chipper, conifers and
deciduous trees), a film-crew grip (the dolly, the camera buggy, the DP), a cyclist commuter
("ride the shoulder, not the carriageway"), a Nav2 ``costmap_2d`` YAML block
(``inflation_radius``, ``cost_scaling_factor``), a pilot's checklist read aloud (dotted leaders,
"check"), a kindergarten teacher on a nature walk ("robot buddy"), a wildfire crew boss on the
radio ("Engine 7"), a hotel concierge giving directions, a real-estate agent, a snowshoe guide,
a skateboarder's slang ("sketchier", "shred those"), an Irish-English speaker ("sure look",
"grand", "bar the baseball field"), a Nigerian-English speaker ("it is not by force", "tarred
road", "at all at all"), an Australian mine's induction cards ("LVs", "no dramas"), a lawyer's
"notwithstanding" clause, Reddit comments with edits ("EDIT: actually ..."), and self-corrections
("avoid grass, sorry, I mean avoid the trees"; "5 m, no, scratch that, 8 m").

Units come in metres, feet (30 feet = 9.144 m), numbers as words in other forms ("a dozen
metres" = 12, "half a dozen metres" = 6, "a metre and a half" = 1.5, "fifteen (15) metres"),
vague measures that give no number ("a stone's throw", "twenty steps": no metre figure is
expected), ranges ("8-10 m": the lower figure is the one a soft zone is probed at, so either
reading passes) and bounds ("6 m or more", "5 m or so", "ten metres or thereabouts", "forty
metres or so"). Orderings come chained ("road beats trail beats grass"), as "A > B", as "X is
where we want to be" and as fallbacks ("only if the paved one is blocked"); where a brief gives an
order but no level only the order is expected. Permissions come as "green light", "free to",
"allowed", "you may", "hereby permitted", "you can go through", "fine", "all yours" and grudging
"if you really must" (not lethal, still avoided); forbidding as "stay out of", "keep out of",
"off limits", "a no-go", "shall not enter", "don't go into", "not allowed ... ever", NO-GO in a
checklist and the terse "X: no". Distance rules come hard ("must never, ever", "absolute", "No
exceptions", "you do not, and I mean do not", "shall at no time", "always", "Non-negotiable"),
soft ("where practical, not mandatory", "desirable", "not a hard rule", "if you can", "not a
deal-breaker", "it's grand if you can't", "desired, not required", "it is not by force"), graded
away ("the further the better, out to 25 m", "closer = worse", ``inflation_radius``), graded
toward ("hug the road", "keep within sight of", "within a stone's throw ... nearer is better")
and graded both ways in one brief, and on versus beside ("ride the shoulder, not the
carriageway", "parallel to the railway, never on it", "alongside the water but never in it").
Qualified classes come as sealed / gravel / tarred / untarred / paved / unpaved roads and conifer
/ deciduous trees; excepted sub-areas as "except the strip by the hives", "bar the baseball
field" and "except the east wing loading dock". Clauses that hang on what no layer carries
(rain, rush hour, lunchtime, the season, a crowd, the lobby and the fountain, spoil heaps and
trenches, hives, a loading dock, a blocked road) are expected unread; briefs whose every clause
is readable are expected all read.

Each construct has seven to nine briefs; route checks are given wherever the scene holds the
class (nb2 for the railway, vegas for paved / unpaved roads, massachusetts and kampala for
buildings, neon for tree crowns, the bundled sample for grass, trail and the baseball field).
"""

from __future__ import annotations

from tests.mission_briefs import Brief, Route

BRIEFS: list[Brief] = [
    # ==========================================================================================
    # distance_hard: distance rules worded as absolute
    # ==========================================================================================
    Brief(
        prompt=(
            "The hives sit along the tree line, so that's my worry. The mower must never, ever come "
            "within 12 metres of the trees; the bees go mad at the noise. Grass is what it should "
            "be driving on."
        ),
        voice="field",
        construct="distance_hard",
        layers=("tree", "grass", "road"),
        expect=(("keep_out", "tree", 12), ("preferred", "grass")),
        routes=(Route("sample", "keeps", "tree", 12), Route("sample", "more_on", "grass")),
        why="'must never, ever come within 12 metres' is absolute; 'what it should be driving on' prefers grass.",
    ),
    Brief(
        prompt=(
            "Trench edges collapse without warning. The rover stays at least 4 m from every "
            "building on site, the old walls are being dug out and that is absolute. It may use the "
            "road as it pleases."
        ),
        voice="field",
        construct="distance_hard",
        layers=("building", "road", "vegetation"),
        expect=(("keep_out", "building", 4), ("not_lethal", "road")),
        routes=(Route("nb1", "keeps", "building", 4), Route("massachusetts", "keeps", "building", 4)),
        why="'as it pleases' is a permission, so only not-lethal is expected of the road, not a preference.",
    ),
    Brief(
        prompt=(
            "SITE INDUCTION CARD 3 - LIGHT VEHICLES. Minimum 30 m standoff from the water at all "
            "times (tailings dam). No exceptions. Stick to the roads."
        ),
        voice="field",
        construct="distance_hard",
        layers=("road", "water", "building"),
        expect=(("keep_out", "water", 30), ("preferred", "road")),
        routes=(Route("nb1", "keeps", "water", 30), Route("nb1", "more_on", "road")),
    ),
    Brief(
        prompt=(
            "Crew boss to dozer: you do not, and I mean do not, push line within 30 feet of the "
            "railway. That's an order. Vegetation is what we're cutting through, so vegetation is fine."
        ),
        voice="field",
        construct="distance_hard",
        layers=("railway", "vegetation", "road"),
        expect=(("keep_out", "railway", 9.144), ("not_lethal", "vegetation"), ("neutral", "vegetation")),
        routes=(Route("nb2", "keeps", "railway", 9.144),),
        why="30 feet = 9.144 m; vegetation is no hazard and 'fine' merely allows it: neutral.",
    ),
    Brief(
        prompt=(
            "Notwithstanding any other provision of this brief, the Vehicle shall at no time approach "
            "within fifteen (15) metres of any building, and this clause shall prevail over any "
            "preference expressed herein. Subject to the foregoing, the Vehicle should favour the road."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=("building", "road"),
        expect=(("keep_out", "building", 15), ("preferred", "road")),
        routes=(Route("massachusetts", "keeps", "building", 15), Route("nb1", "keeps", "building", 15)),
    ),
    Brief(
        prompt=(
            "Porter bot policy for the grounds run to the east wing: the bot keeps half a dozen "
            "metres or more from the buildings at all times. Non-negotiable."
        ),
        voice="robot",
        construct="distance_hard",
        layers=("building", "road", "grass"),
        expect=(("keep_out", "building", 6),),
        routes=(Route("kampala", "keeps", "building", 6), Route("massachusetts", "keeps", "building", 6)),
        why="'half a dozen metres or more' is a lower bound of 6 m; 'at all times' and 'Non-negotiable' make it hard.",
    ),
    Brief(
        prompt=(
            "Course rule C-4: the course may never pass closer than a dozen metres to open water. "
            "Runners need the road."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=("water", "road", "grass"),
        expect=(("keep_out", "water", 12), ("preferred", "road")),
        routes=(Route("sample", "keeps", "water", 12), Route("nb1", "keeps", "water", 12)),
        why="'a dozen metres' = 12 m.",
    ),
    Brief(
        prompt=(
            "Grip dept note for the camera buggy: it never touches or rubs up against a building, "
            "always leave a gap. Absolute."
        ),
        voice="field",
        construct="distance_hard",
        layers=("building", "road"),
        expect=(("keep_out", "building", None),),
        routes=(Route("massachusetts", "zero_on", "building"),),
        why="A hard rule with no number: ground 1 m from a building is kept out, ground 60 m away is not.",
    ),
    Brief(
        prompt=(
            "Crew must stay 5 m, no, scratch that, 8 m from the railway at all times, no exceptions. Roads are fine."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=("railway", "road", "vegetation"),
        expect=(("keep_out", "railway", 8), ("not_lethal", "road")),
        routes=(Route("nb2", "keeps", "railway", 8),),
        why="The self-correction replaces 5 m with 8 m: ground 7 m from the rails is kept out.",
    ),
    # ==========================================================================================
    # distance_soft: distance rules worded softly
    # ==========================================================================================
    Brief(
        prompt=(
            "LAYER NOTES. C-ROAD (roads): preferred travel. A-BLDG (buildings): offset 3 m where "
            "practical, not mandatory. W-HYDRO (water): offset 5 m desirable."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=("road", "building", "water"),
        expect=(("preferred", "road"), ("soft_zone", "building", 3), ("soft_zone", "water", 5)),
        routes=(Route("nb1", "more_on", "road"),),
    ),
    Brief(
        prompt=(
            "On the snowshoe loop I like folks to keep 8-10 m back from the water's edge, because of "
            "the ice shelves. Not a hard rule, just good sense. The trails are where we want to be."
        ),
        voice="field",
        construct="distance_soft",
        layers=("water", "trail", "tree"),
        expect=(("soft_zone", "water", 8), ("preferred", "trail")),
        routes=(Route("sample", "more_on", "trail"),),
        why="A range: the soft zone is probed at 1 m and 7 m, inside either reading (8 or 10 m).",
    ),
    Brief(
        prompt=(
            "Commute settings: roads good. Give the buildings a metre and a half if you can, car doors "
            "open without warning. Not fussed otherwise."
        ),
        voice="field",
        construct="distance_soft",
        layers=("road", "building", "grass"),
        expect=(("preferred", "road"), ("soft_zone", "building", 1.5)),
        routes=(Route("nb1", "more_on", "road"),),
        why="'a metre and a half' = 1.5 m; 'if you can' makes it soft.",
    ),
    Brief(
        prompt=(
            "This one's got everything! Ideally the viewing route keeps 5 m or so off the neighbours' "
            "buildings, privacy you know, but honestly it's not a deal-breaker. Lovely grass, use it."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=("building", "grass", "road"),
        expect=(("soft_zone", "building", 5), ("preferred", "grass")),
        routes=(Route("sample", "more_on", "grass"),),
    ),
    Brief(
        prompt=(
            "Ah sure look, try and keep ten metres or thereabouts from the railway if you can at all, "
            "but it's grand if you can't. The road's the best way."
        ),
        voice="field",
        construct="distance_soft",
        layers=("railway", "road", "vegetation"),
        expect=(("soft_zone", "railway", 10), ("preferred", "road")),
        routes=(Route("nb1", "more_on", "road"),),
        why="'it's grand if you can't' makes the 10 m soft; 'the best way' prefers the road.",
    ),
    Brief(
        prompt=(
            "Pre-taxi checklist. Water clearance ..... twenty metres, desired, not required ..... "
            "check. Roads ..... preferred ..... check. Buildings ..... avoid ..... check."
        ),
        voice="robot",
        construct="distance_soft",
        layers=("water", "road", "building"),
        expect=(("soft_zone", "water", 20), ("preferred", "road"), ("avoided", "building")),
        routes=(Route("nb1", "more_on", "road"), Route("nb1", "less_on", "building")),
    ),
    Brief(
        prompt=(
            "Please, try to keep at least 4 metres from the buildings, but it is not by force. We will "
            "use the road, and the grass is also okay, no wahala."
        ),
        voice="field",
        construct="distance_soft",
        layers=("building", "road", "grass"),
        expect=(("soft_zone", "building", 4), ("below", "road", "grass"), ("not_lethal", "grass")),
        routes=(Route("sample", "more_on", "road"),),
        why=(
            "'not by force' (not compulsory) makes the 4 m soft; the road is what will be used and the "
            "grass 'also okay', so the road is expected below the grass and the grass not forbidden."
        ),
    ),
    # ==========================================================================================
    # graded_away: priced by distance, the closer the dearer
    # ==========================================================================================
    Brief(
        prompt=(
            "global_costmap:\n"
            "  plugins: [static_layer, inflation_layer]\n"
            "  static_layer:\n"
            "    lethal_classes: [building]\n"
            "  inflation_layer:\n"
            "    inflated_classes: [building]\n"
            "    inflation_radius: 6.0\n"
            "    cost_scaling_factor: 2.5\n"
        ),
        voice="robot",
        construct="graded_away",
        layers=("building", "road"),
        expect=(("lethal", "building"), ("graded_away", "building", 6.0)),
        routes=(Route("massachusetts", "zero_on", "building"), Route("massachusetts", "farther", "building")),
        why=(
            "Nav2 inflation: cost decays with distance from the obstacle and reaches free space at "
            "inflation_radius, so graded away out to 6 m; lethal_classes makes the building impassable."
        ),
    ),
    Brief(
        prompt=(
            "Okay friends, on our nature walk robot buddy stays far from the water. The closer to the "
            "pond, the more careful we get, and once we're about twenty steps away it doesn't matter "
            "anymore."
        ),
        voice="field",
        construct="graded_away",
        layers=("water", "grass", "tree"),
        expect=(("graded_away", "water", None),),
        routes=(Route("sample", "farther", "water"),),
        why="'twenty steps' is no metre figure, so only the fall-off is expected, not where it ends.",
    ),
    Brief(
        prompt=(
            "Felling today. Keep the chipper as far from the trees as you can, the further the better, "
            "out to 25 m; past that I don't care."
        ),
        voice="field",
        construct="graded_away",
        layers=("tree", "road", "grass"),
        expect=(("graded_away", "tree", 25),),
        routes=(Route("neon", "farther", "tree"), Route("sample", "farther", "tree")),
    ),
    Brief(
        prompt=(
            "Rule 7.3 (Ground Support Vehicles). GSVs shall keep well away from the railway; cost "
            "increases with proximity. Rule 7.4. GSVs shall prefer roads."
        ),
        voice="analyst",
        construct="graded_away",
        layers=("railway", "road", "vegetation"),
        expect=(("graded_away", "railway", None), ("preferred", "road")),
        routes=(Route("nb2", "farther", "railway"),),
    ),
    Brief(
        prompt=(
            "If I may, sir: the further from the road, the more pleasant the stroll, though it really "
            "only matters within forty metres or so. The trail through the grounds is lovely."
        ),
        voice="field",
        construct="graded_away",
        layers=("road", "trail", "grass"),
        expect=(("graded_away", "road", 40), ("preferred", "trail")),
        routes=(Route("sample", "more_on", "trail"),),
        why="'lovely' recommends the trail: preferred. The fall-off reaches neutral at about 40 m.",
    ),
    Brief(
        prompt=(
            "yo the rover should NOT be vibin near the water, like the closer it gets the sketchier, "
            "ya know? roads are sick tho, shred those"
        ),
        voice="field",
        construct="graded_away",
        layers=("water", "road", "grass"),
        expect=(("graded_away", "water", None), ("preferred", "road")),
        routes=(Route("nb1", "more_on", "road"), Route("nb1", "farther", "water")),
    ),
    Brief(
        prompt=(
            "Honestly just make it avoid buildings, closer = worse. EDIT: to be clear, it only needs "
            "to care within about 10 m, after that whatever. EDIT 2: and yes it can drive on grass, "
            "people keep asking."
        ),
        voice="analyst",
        construct="graded_away",
        layers=("building", "grass", "road"),
        expect=(("graded_away", "building", 10), ("neutral", "grass")),
        routes=(Route("massachusetts", "farther", "building"),),
        why="The first edit bounds the fall-off at 10 m; 'yes it can drive on grass' merely allows it.",
    ),
    # ==========================================================================================
    # graded_toward: cheaper the nearer
    # ==========================================================================================
    Brief(
        prompt=(
            "Dispatch to shuttle bot: hug the road, the nearer the road the better, you want to be "
            "right by it the whole way. Avoid the water."
        ),
        voice="field",
        construct="graded_toward",
        layers=("road", "water", "building"),
        expect=(("graded_toward", "road", None), ("avoided", "water")),
        routes=(Route("nb1", "closer", "road"), Route("nb1", "less_on", "water")),
    ),
    Brief(
        prompt=(
            "Engine 7, keep within sight of the water at all times, that's our escape route and our "
            "safety zone. The closer to the water the better."
        ),
        voice="field",
        construct="graded_toward",
        layers=("water", "vegetation", "road"),
        expect=(("graded_toward", "water", None),),
        routes=(Route("nb1", "closer", "water"),),
        why="Nearness to the water is asked for; nothing is said about driving in it, so no level of water.",
    ),
    Brief(
        prompt=(
            "Survey transect: stay close to the trail, ideally within 5 m of it, the nearer the "
            "better, the finds are along the old path. The spoil heaps are wherever, ignore them."
        ),
        voice="analyst",
        construct="graded_toward",
        layers=("trail", "grass", "tree"),
        expect=(("graded_toward", "trail", 5), ("unread", "spoil")),
        routes=(Route("sample", "closer", "trail"),),
        why="No layer stands for the spoil heaps: the words about them must be reported, not dropped.",
    ),
    Brief(
        prompt=(
            "Grounds mode: the porter should stay near the buildings, closer is cheaper, so it's in "
            "the shade. Use the road only to cross it."
        ),
        voice="robot",
        construct="graded_toward",
        layers=("building", "road", "grass"),
        expect=(("graded_toward", "building", None), ("avoided", "road")),
        routes=(Route("massachusetts", "closer", "building"),),
        why="'the road only to cross it' means as little road as possible: avoided, not forbidden.",
    ),
    Brief(
        prompt=(
            "Course brief: the nearer the water, the nicer the views, so pull the line toward it; the "
            "nearer the buildings, the worse. Trail beats grass."
        ),
        voice="analyst",
        construct="graded_toward",
        layers=("water", "building", "trail", "grass"),
        expect=(
            ("graded_toward", "water", None),
            ("graded_away", "building", None),
            ("below", "trail", "grass"),
        ),
        routes=(Route("sample", "closer", "water"),),
        why="Graded nearness both ways in one brief; 'Trail beats grass' gives an order only.",
    ),
    Brief(
        prompt=(
            "The robot should always be close to the road, the closer the better, within ten metres "
            "is best, I beg. As for the water, don't enter it at all at all."
        ),
        voice="field",
        construct="graded_toward",
        layers=("road", "water", "vegetation"),
        expect=(("graded_toward", "road", 10), ("lethal", "water")),
        routes=(Route("nb1", "closer", "road"), Route("nb1", "zero_on", "water")),
        why="'within ten metres is best' prices nearness, not a hard band; 'don't enter it' forbids the water.",
    ),
    Brief(
        prompt=(
            "For the tracking shot keep the rig within a stone's throw of the trees, nearer is "
            "better, the DP wants leaves in frame."
        ),
        voice="field",
        construct="graded_toward",
        layers=("tree", "grass", "road"),
        expect=(("graded_toward", "tree", None),),
        routes=(Route("neon", "closer", "tree"), Route("sample", "closer", "tree")),
        why="'a stone's throw' gives no metre figure.",
    ),
    # ==========================================================================================
    # on_beside: along X but not on X
    # ==========================================================================================
    Brief(
        prompt="Ride the shoulder, not the carriageway: keep just beside the road, never on it.",
        voice="field",
        construct="on_beside",
        layers=("road", "grass", "building"),
        expect=(("beside", "road"),),
        routes=(Route("nb1", "beside", "road", 5),),
    ),
    Brief(
        prompt=(
            "Rule 9.1. Ground crews travel parallel to the railway, never on it; the strip within a "
            "few metres of the rails is the designated crew lane."
        ),
        voice="analyst",
        construct="on_beside",
        layers=("railway", "vegetation", "road"),
        expect=(("beside", "railway"),),
        routes=(Route("nb2", "beside", "railway", 5),),
    ),
    Brief(
        prompt=("Runners go along the verge next to the road, not on the road itself, which stays open to traffic."),
        voice="analyst",
        construct="on_beside",
        layers=("road", "building", "vegetation"),
        expect=(("beside", "road"),),
        routes=(Route("nb1", "beside", "road", 4),),
    ),
    Brief(
        prompt=(
            "We walk the shore, alongside the water but never in it; a couple of metres back from "
            "the edge is the sweet spot."
        ),
        voice="field",
        construct="on_beside",
        layers=("water", "trail", "tree"),
        expect=(("beside", "water"),),
        routes=(Route("sample", "beside", "water", 5), Route("nb1", "beside", "water", 5)),
    ),
    Brief(
        prompt="cruise next to the trail not on it, the trail's for the hikers bro",
        voice="field",
        construct="on_beside",
        layers=("trail", "grass", "tree"),
        expect=(("beside", "trail"),),
        routes=(Route("sample", "beside", "trail", 4),),
    ),
    Brief(
        prompt=(
            "Card 7, haul roads: light vehicles travel on the LV track beside the haul road, not on "
            "the haul road itself."
        ),
        voice="field",
        construct="on_beside",
        layers=("road", "building", "water"),
        expect=(("beside", "road"),),
        routes=(Route("nb1", "beside", "road", 5),),
        why="The haul road is the road layer; the LV track is the band beside it, which no layer holds.",
    ),
    Brief(
        prompt=("Drive along the line of trees, beside them but not under the canopy, there are roots and low limbs."),
        voice="field",
        construct="on_beside",
        layers=("tree", "grass", "road"),
        expect=(("beside", "tree"),),
        routes=(Route("neon", "beside", "tree", 3),),
    ),
    # ==========================================================================================
    # qualified: paved / unpaved, conifer / deciduous, excepted sub-areas
    # ==========================================================================================
    Brief(
        prompt=("Shuttles run on the paved road, please; the unpaved road only if the paved one is blocked."),
        voice="field",
        construct="qualified",
        layers=("paved road", "unpaved road"),
        expect=(("preferred", "paved road"), ("avoided", "unpaved road"), ("unread", "blocked")),
        routes=(Route("vegas", "more_on", "paved road"),),
        why=(
            "The unpaved road is a fallback, so avoided but not forbidden; whether the paved road is "
            "blocked is nothing a layer carries, so that condition is reported."
        ),
    ),
    Brief(
        prompt=(
            "The drive in is lovely: sealed road the whole way, and the gravel road is there if you "
            "need it, though it's a bit rough."
        ),
        voice="analyst",
        construct="qualified",
        layers=("paved road", "unpaved road"),
        expect=(
            ("preferred", "paved road"),
            ("below", "paved road", "unpaved road"),
            ("not_lethal", "unpaved road"),
        ),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="Sealed = paved, gravel = unpaved; the gravel road is usable but second, so only the order is expected.",
    ),
    Brief(
        prompt=(
            "Keep away from the conifers, they're brittle this time of year. The deciduous trees are "
            "fine to pass under."
        ),
        voice="field",
        construct="qualified",
        layers=("conifer", "deciduous tree", "grass"),
        expect=(
            ("avoided", "conifer"),
            ("neutral", "deciduous tree"),
            ("below", "deciduous tree", "conifer"),
        ),
        why="'fine to pass under' merely allows the deciduous trees (lifting any tree prior): neutral.",
    ),
    Brief(
        prompt="Avoid the grass, except the strip by the hives, that bit needs cutting.",
        voice="field",
        construct="qualified",
        layers=("grass", "tree", "road"),
        expect=(("avoided", "grass"), ("unread", "hives")),
        routes=(Route("sample", "less_on", "grass"),),
        why="No layer holds the strip by the hives: the exception cannot be applied and must be reported.",
    ),
    Brief(
        prompt="Keep away from the grass and the trees, bar the baseball field, that's grand to cross.",
        voice="field",
        construct="qualified",
        layers=("grass", "tree", "baseball field", "road"),
        expect=(("avoided", "grass"), ("avoided", "tree"), ("neutral", "baseball field")),
        routes=(Route("sample", "less_on", "grass"), Route("sample", "less_on", "tree")),
        why="'bar' = except; the baseball field is excepted and 'grand to cross' merely allows it.",
    ),
    Brief(
        prompt="Use only the tarred road; the untarred ones are off limits during this job.",
        voice="field",
        construct="qualified",
        layers=("paved road", "unpaved road", "building"),
        expect=(("preferred", "paved road"), ("lethal", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"), Route("vegas", "zero_on", "unpaved road")),
        why="Tarred = paved, untarred = unpaved (Nigerian English); 'during this job' is the whole mission.",
    ),
    Brief(
        prompt=("Buildings are a no-go for the bot, except the east wing loading dock, where it docks to charge."),
        voice="robot",
        construct="qualified",
        layers=("building", "road", "grass"),
        expect=(("lethal", "building"), ("unread", "dock")),
        routes=(Route("massachusetts", "zero_on", "building"),),
        why="The excepted sub-area has no layer: the rule holds for the buildings and the exception is reported.",
    ),
    # ==========================================================================================
    # terse: terse and symbolic briefs, typos in multi-word names
    # ==========================================================================================
    Brief(
        prompt="road beats trail beats grass. water: off limits.",
        voice="field",
        construct="terse",
        layers=("road", "trail", "grass", "water"),
        expect=(("below", "road", "trail"), ("below", "trail", "grass"), ("lethal", "water")),
        routes=(Route("sample", "zero_on", "water"),),
        why="A chained comparison gives the order, not the levels.",
    ),
    Brief(
        prompt="tree: no-go / grass: fine / trail > grass",
        voice="field",
        construct="terse",
        layers=("tree", "grass", "trail"),
        expect=(("lethal", "tree"), ("not_lethal", "grass"), ("below", "trail", "grass")),
        routes=(Route("sample", "zero_on", "tree"),),
    ),
    Brief(
        prompt="baseball feild - keep out. gras fine. road best.",
        voice="field",
        construct="terse",
        layers=("baseball field", "grass", "road"),
        expect=(("lethal", "baseball field"), ("not_lethal", "grass"), ("preferred", "road")),
        routes=(Route("sample", "zero_on", "baseball field"), Route("sample", "more_on", "road")),
        why="Typos in the names ('feild', 'gras'); 'keep out' forbids.",
    ),
    Brief(
        prompt="paved raod > unpavd road; both ok",
        voice="analyst",
        construct="terse",
        layers=("paved road", "unpaved road"),
        expect=(
            ("below", "paved road", "unpaved road"),
            ("not_lethal", "paved road"),
            ("not_lethal", "unpaved road"),
        ),
        why="An order with no level; 'both ok' rules out forbidding either.",
    ),
    Brief(
        prompt=("WATER ........ NO-GO\nRAILWAY ...... NO-GO\nROAD ......... PREFERRED\nVEGETATION ... AS REQUIRED"),
        voice="robot",
        construct="terse",
        layers=("water", "railway", "road", "vegetation"),
        expect=(
            ("lethal", "water"),
            ("lethal", "railway"),
            ("preferred", "road"),
            ("not_lethal", "vegetation"),
        ),
        routes=(
            Route("nb1", "zero_on", "water"),
            Route("nb2", "zero_on", "railway"),
            Route("nb1", "more_on", "road"),
        ),
    ),
    Brief(
        prompt="buildings >= 5 m (hard). roads good. water bad.",
        voice="analyst",
        construct="terse",
        layers=("building", "road", "water"),
        expect=(("keep_out", "building", 5), ("preferred", "road"), ("avoided", "water")),
        routes=(Route("nb1", "keeps", "building", 5), Route("nb1", "less_on", "water")),
    ),
    Brief(
        prompt="water: no. trees: if u must. trail pls",
        voice="field",
        construct="terse",
        layers=("water", "tree", "trail"),
        expect=(("lethal", "water"), ("avoided", "tree"), ("not_lethal", "tree"), ("preferred", "trail")),
        routes=(
            Route("sample", "zero_on", "water"),
            Route("sample", "less_on", "tree"),
            Route("sample", "more_on", "trail"),
        ),
        why="'X: no' forbids; 'if u must' allows the trees grudgingly, so they stay avoided but passable.",
    ),
    # ==========================================================================================
    # permission: permissions that lift priors, and stay-out wording that forbids
    # ==========================================================================================
    Brief(
        prompt=("Engine 7, you can go straight through the water here, it's shallow. The railway, keep out of it."),
        voice="field",
        construct="permission",
        layers=("vegetation", "water", "railway"),
        expect=(("not_lethal", "water"), ("neutral", "water"), ("lethal", "railway")),
        routes=(Route("nb2", "zero_on", "railway"),),
        why="'you can go straight through' merely allows the water, lifting its prior to neutral.",
    ),
    Brief(
        prompt=(
            "Robot buddy, you may walk under the trees with us today! But you must stay out of the water, no splashing!"
        ),
        voice="field",
        construct="permission",
        layers=("tree", "water", "grass"),
        expect=(("neutral", "tree"), ("lethal", "water")),
        routes=(Route("sample", "zero_on", "water"),),
    ),
    Brief(
        prompt=(
            "The Operator is hereby permitted to traverse the railway at any point. Notwithstanding "
            "the foregoing, the Operator shall not enter any building."
        ),
        voice="analyst",
        construct="permission",
        layers=("railway", "building", "road"),
        expect=(("neutral", "railway"), ("lethal", "building")),
        routes=(Route("nb2", "zero_on", "building"),),
    ),
    Brief(
        prompt=(
            "The porter bot is allowed through the buildings, it uses the corridors. It must not go "
            "into the water, though."
        ),
        voice="robot",
        construct="permission",
        layers=("building", "water", "road"),
        expect=(("neutral", "building"), ("lethal", "water")),
        routes=(Route("nb1", "zero_on", "water"),),
    ),
    Brief(
        prompt=(
            "Card 5. LVs are free to cross the railway anywhere, no dramas. The dam water is off limits, full stop."
        ),
        voice="field",
        construct="permission",
        layers=("railway", "water", "road"),
        expect=(("neutral", "railway"), ("not_lethal", "railway"), ("lethal", "water")),
        routes=(Route("nb2", "zero_on", "water"),),
    ),
    Brief(
        prompt=(
            "Set it to avoid the water. EDIT: actually it's fine through the water, the creek is "
            "ankle deep. EDIT 2: buildings are still off limits obviously."
        ),
        voice="analyst",
        construct="permission",
        layers=("water", "building", "road"),
        expect=(("neutral", "water"), ("lethal", "building")),
        routes=(Route("nb1", "zero_on", "building"),),
        why="The first edit withdraws 'avoid the water' and allows it: the later word stands.",
    ),
    Brief(
        prompt=(
            "The trees, you can go through them if you really must, but I'd rather you didn't. The "
            "water is a no-go, the ice won't hold."
        ),
        voice="field",
        construct="permission",
        layers=("tree", "water", "trail"),
        expect=(("not_lethal", "tree"), ("avoided", "tree"), ("lethal", "water")),
        routes=(Route("sample", "zero_on", "water"), Route("sample", "less_on", "tree")),
        why="A grudging permission: the trees are passable but still avoided.",
    ),
    Brief(
        prompt="The mower is allowed on the grass, of course, but it is not allowed on the road, ever.",
        voice="field",
        construct="permission",
        layers=("grass", "road", "tree"),
        expect=(("not_lethal", "grass"), ("lethal", "road")),
        routes=(Route("sample", "zero_on", "road"),),
        why="'not allowed ... ever' forbids the road outright.",
    ),
    # ==========================================================================================
    # clauses: every clause accounted for
    # ==========================================================================================
    Brief(
        prompt="Avoid grass, sorry, I mean avoid the trees. Stick to the trail.",
        voice="field",
        construct="clauses",
        layers=("grass", "tree", "trail"),
        expect=(("avoided", "tree"), ("neutral", "grass"), ("preferred", "trail")),
        routes=(Route("sample", "less_on", "tree"), Route("sample", "more_on", "trail")),
        why="The self-correction withdraws 'avoid grass': grass is left an unmentioned non-hazard.",
    ),
    Brief(
        prompt=("If it's raining, stay off the grass; otherwise the grass is fine. Always keep out of the water."),
        voice="field",
        construct="clauses",
        layers=("grass", "water", "road"),
        expect=(("unread", "raining"), ("lethal", "water")),
        routes=(Route("sample", "zero_on", "water"),),
        why="The rain is nothing a layer carries; no level of grass is expected since it hangs on the rain.",
    ),
    Brief(
        prompt=(
            "Mine's set up so it avoids the road during rush hour and prefers it otherwise. EDIT: "
            "forgot to say, it has to stay out of the railway."
        ),
        voice="analyst",
        construct="clauses",
        layers=("road", "railway", "vegetation"),
        expect=(("unread", "rush"), ("not_lethal", "road"), ("lethal", "railway")),
        routes=(Route("nb2", "zero_on", "railway"),),
    ),
    Brief(
        prompt=(
            "Keep clear of the crowd by the catering trucks, and the road is ours until lunchtime. "
            "Keep out of the water, the camera's not waterproof."
        ),
        voice="field",
        construct="clauses",
        layers=("road", "water", "building"),
        expect=(("unread", "crowd"), ("unread", "lunchtime"), ("lethal", "water")),
        routes=(Route("nb1", "zero_on", "water"),),
        why="People and the time of day hang on nothing a layer carries.",
    ),
    Brief(
        prompt=(
            "In spring the trail floods, so use the road then; in the other seasons take the trail. "
            "Never enter the water."
        ),
        voice="field",
        construct="clauses",
        layers=("trail", "road", "water"),
        expect=(("unread", "spring"), ("lethal", "water")),
        routes=(Route("sample", "zero_on", "water"),),
        why="The season decides between the trail and the road, so neither order is expected.",
    ),
    Brief(
        prompt=(
            "Keep the wheelbarrow robot off the spoil heaps and well away from the open trenches. The road is best."
        ),
        voice="field",
        construct="clauses",
        layers=("road", "building", "grass"),
        expect=(("unread", "spoil"), ("unread", "trench"), ("preferred", "road")),
        routes=(Route("nb1", "more_on", "road"),),
    ),
    Brief(
        prompt=(
            "Rule one, stay on the trail. Rule two, don't go into the water. Rule three, stay away from the trees."
        ),
        voice="field",
        construct="clauses",
        layers=("trail", "water", "tree"),
        expect=(("preferred", "trail"), ("lethal", "water"), ("avoided", "tree"), ("all_read",)),
        routes=(Route("sample", "zero_on", "water"), Route("sample", "more_on", "trail")),
    ),
    Brief(
        prompt=(
            "Turn left out of the lobby, follow the road past the fountain, and do avoid the grass, "
            "the gardener is very particular."
        ),
        voice="field",
        construct="clauses",
        layers=("road", "grass", "building"),
        expect=(("preferred", "road"), ("avoided", "grass"), ("unread", "lobby"), ("unread", "fountain")),
        routes=(Route("sample", "less_on", "grass"),),
        why="The lobby and the fountain are landmarks no layer holds; 'follow the road' prefers the road.",
    ),
    Brief(
        prompt="Ground crew: use the road, avoid the grass, keep out of the water.",
        voice="analyst",
        construct="clauses",
        layers=("road", "grass", "water"),
        expect=(("preferred", "road"), ("avoided", "grass"), ("lethal", "water"), ("all_read",)),
        routes=(Route("sample", "zero_on", "water"), Route("sample", "more_on", "road")),
    ),
]

#: Briefs retired after scoring because their expectation contradicts the cost-scale contract
#: (id or prompt -> the reason). None at first contact.
DOUBTFUL: dict[str, str] = {}
