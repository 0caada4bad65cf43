"""Mission briefs, set 23: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench, the docs or the briefs of earlier sets: only the contract
(``tests/mission_briefs.py`` and its format test ``tests/test_mission_briefs.py``), the scene index
(``../shared/scenes/INDEX.md`` and the scenes' ``classes.json``) and the first 40 lines of set 22
(for the layout) were read. It is scored once, at first contact, with
``bench/mission_briefs_report.py --set 23``; that figure is the one that counts, and the set is
not edited afterwards to make the interpreter pass.

The voices are a park ranger's incident report, a utility company's work order, an agronomist's
scouting notes, a mountain-bike race marshal, a delivery-robot fleet's Slack thread (several
short messages, timestamps and quote marks), a surveyor dictating to speech-to-text (homophones,
no punctuation, "period" spoken aloud), a five-paragraph military order (SMEAC), a hiking club's
newsletter, planning-permission conditions, a child talking to a robot, a voice-assistant
transcript with fillers ("um", "like"), an academic methods section in the passive voice, a
checklist with [x] / [ ] boxes and a Markdown table with columns "class | rule | distance".
Units come in feet, feet and inches and kilometres; orderings come as ratios ("three times
worse"), ordinal ranks ("1st choice", "last choice"), "prefer X to Y" and "X over Y"; bounds as
"no more than", "at most", "at minimum" and a "between 5 and 10 m" band; exceptions as "unless"
and "except"; permissions negated ("you may not", "not allowed unless"). Rules that hang on what
no layer can carry (rain, dusk, traffic, whether the ground is dry, level-crossing gates) are
expected unread.

Each construct has seven to nine briefs; route checks are given wherever the scene holds the
class. Unmentioned hazards are expected at their priors (avoided, not lethal) only where a
careful reader would take that for granted; where a brief gives an order but no level, only the
order is expected.
"""

from __future__ import annotations

from tests.mission_briefs import Brief, Route

SAMPLE = ("grass", "road", "trail", "tree", "water", "building", "baseball field")
NB = ("building", "road", "water", "vegetation", "railway")
VEGAS = ("paved road", "unpaved road")
BUILDING = ("building",)
TREE = ("tree",)

FT = 0.3048

#: Briefs retired after scoring because their expectation contradicts the contract (none yet).
DOUBTFUL: dict[str, str] = {}

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------------------------------
    # distance_hard
    # ------------------------------------------------------------------------------------------
    Brief(
        "WORK ORDER 4471-B\n"
        "Scope: walk-down survey, pole 12 to pole 19.\n"
        "Restriction: crew to remain a minimum of 15 m from any building at all times.\n"
        "Roads may be crossed.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "building", 15), ("not_lethal", "road"), ("avoided", "water")),
        (Route("nb1", "keeps", "building", 15),),
        why="'a minimum of ... at all times' is absolute; water is unmentioned and keeps its prior",
    ),
    Brief(
        "Regulatory setback: no less than 50 ft between the route and the water, anywhere along "
        "it. This is not a suggestion.",
        "analyst",
        "distance_hard",
        SAMPLE,
        (("keep_out", "water", 50 * FT), ("avoided", "building")),
        (Route("sample", "keeps", "water", 50 * FT),),
        why="50 ft is 15.24 m; 'not a suggestion' makes it hard",
    ),
    Brief(
        "1. SITUATION: dense informal settlement, narrow gaps between structures.\n"
        "2. MISSION: UGV moves from RP1 to RP2.\n"
        "3. EXECUTION: hold a 3 m standoff from every building, no exceptions.\n"
        "4. SERVICE SUPPORT: none.\n"
        "5. COMMAND AND SIGNAL: net on channel 4.",
        "analyst",
        "distance_hard",
        BUILDING,
        (("keep_out", "building", 3), ("unread", "channel")),
        (Route("kampala", "keeps", "building", 3),),
        why="the signal paragraph has no bearing on the map and must be reported, not dropped",
    ),
    Brief(
        "Spec sheet: railway clearance 0.02 km, hard limit. Leave everything else at default.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "railway", 20), ("avoided", "building"), ("not_lethal", "water")),
        (Route("nb2", "keeps", "railway", 20),),
        why="0.02 km is 20 m; 'at default' keeps the priors for the rest",
    ),
    Brief(
        "Condition 7: No part of the approved inspection route shall pass within 10 metres of "
        "the baseball field. Condition 8: The route shall not enter the water.",
        "analyst",
        "distance_hard",
        SAMPLE,
        (("keep_out", "baseball field", 10), ("lethal", "water")),
        (Route("sample", "keeps", "baseball field", 10), Route("sample", "zero_on", "water")),
        why="'shall not enter' forbids as plainly as 'never enter'",
    ),
    Brief(
        "Incident 23-118: bear sighted in the woods east of the lot. Until further notice the "
        "patrol unit must keep at least 12 m clear of every tree. The trail stays open.",
        "field",
        "distance_hard",
        SAMPLE,
        (("keep_out", "tree", 12), ("not_lethal", "trail"), ("avoided", "water")),
        (Route("sample", "keeps", "tree", 12),),
    ),
    Brief(
        "Clearance requirement for the sidewalk robot: at minimum 6 ft 6 in from buildings, "
        "measured from the wall. Non-negotiable.",
        "analyst",
        "distance_hard",
        BUILDING,
        (("keep_out", "building", 6.5 * FT),),
        (Route("massachusetts", "keeps", "building", 6.5 * FT),),
        why="6 ft 6 in is 1.98 m",
    ),
    Brief(
        "The cable trench has to run between 5 and 10 m from the road. Never nearer than 5 m; try to keep it under 10.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "road", 5),),
        (Route("nb1", "keeps", "road", 5),),
        why="the lower edge of the band is worded absolutely; the upper edge has no expectation kind",
    ),
    # ------------------------------------------------------------------------------------------
    # distance_soft
    # ------------------------------------------------------------------------------------------
    Brief(
        "From the newsletter: members walking the Mere loop this month are asked, where they "
        "can, to give the water a berth of roughly 10 metres, as the banks are eroding. It is a "
        "request, not a rule.",
        "field",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "water", 10), ("not_lethal", "water")),
        (Route("sample", "farther", "water"),),
    ),
    Brief(
        "Scouting notes, plot 4. Rover should ideally stay ~3 m off the vegetation to avoid "
        "trampling the edges; fine to cut closer if it has to. Road OK.",
        "field",
        "distance_soft",
        NB,
        (("soft_zone", "vegetation", 3), ("avoided", "vegetation"), ("not_lethal", "road")),
        (Route("nb1", "farther", "vegetation"),),
        why="trampling is the worry, so the vegetation itself is avoided too, but nothing forbids it",
    ),
    Brief(
        "um okay so like, try to keep, uh, about 5 metres from the buildings? if you can? it's "
        "not a big deal if you don't",
        "robot",
        "distance_soft",
        BUILDING,
        (("soft_zone", "building", 5), ("not_lethal", "building")),
        (Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        "Preferably stay 30 feet or more from the railway; a shorter approach is acceptable "
        "where the terrain forces it.",
        "analyst",
        "distance_soft",
        NB,
        (("soft_zone", "railway", 30 * FT), ("not_lethal", "railway")),
        (Route("nb2", "farther", "railway"),),
        why="30 ft is 9.14 m",
    ),
    Brief(
        "Trajectories were softly penalised within 8 m of tree crowns; the penalty entered as a "
        "cost term rather than a constraint, so crowns could still be approached when no "
        "alternative existed.",
        "analyst",
        "distance_soft",
        TREE,
        (("soft_zone", "tree", 8), ("not_lethal", "tree")),
        (Route("neon", "farther", "tree"),),
    ),
    Brief(
        "[10:14] priya: bots keep hugging the pond again\n"
        "[10:15] priya: can we nudge them ~6m back from the water\n"
        "[10:15] marco: soft though pls, dont want them boxed in\n"
        "[10:16] priya: 👍 soft",
        "robot",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "water", 6), ("not_lethal", "water")),
        (Route("sample", "farther", "water"),),
    ),
    Brief(
        "Try to stay 4 m or so off the paved road where you can; crossing it is allowed.",
        "robot",
        "distance_soft",
        VEGAS,
        (("soft_zone", "paved road", 4), ("not_lethal", "paved road")),
        (Route("vegas", "farther", "paved road"),),
    ),
    # ------------------------------------------------------------------------------------------
    # graded_away
    # ------------------------------------------------------------------------------------------
    Brief(
        "Marshal brief, stage 3. The sweep bike sticks to the road. Spectators gather by the "
        "buildings, so the further you ride from them the better. Don't go anywhere near the "
        "water either.",
        "field",
        "graded_away",
        SAMPLE,
        (("preferred", "road"), ("graded_away", "building", None), ("graded_away", "water", None)),
        (
            Route("sample", "more_on", "road"),
            Route("sample", "farther", "building"),
            Route("sample", "farther", "water"),
        ),
    ),
    Brief(
        "robot you have to go to the other side but the trees are scary so stay really really "
        "far from the trees ok? more far is more better",
        "robot",
        "graded_away",
        SAMPLE,
        (("graded_away", "tree", None), ("avoided", "tree")),
        (Route("sample", "farther", "tree"),),
    ),
    Brief(
        "Penalise proximity to buildings, with the effect reaching at most 25 m out.",
        "analyst",
        "graded_away",
        BUILDING,
        (("graded_away", "building", 25),),
        (Route("kampala", "farther", "building"),),
        why="'at most 25 m' is the reach of the fall-off, not a hard zone",
    ),
    Brief(
        "okay next traverse keep well away from the rail way the closer you get the worse it is "
        "out to about fifteen meters after that dont care period roads are fine period",
        "field",
        "graded_away",
        NB,
        (("graded_away", "railway", 15), ("not_lethal", "road")),
        (Route("nb2", "farther", "railway"),),
        why="speech-to-text splits 'railway' and spells the number out",
    ),
    Brief(
        "Keep clear of the water by as much as you can; its influence should die out by 0.04 km.",
        "analyst",
        "graded_away",
        SAMPLE,
        (("graded_away", "water", 40),),
        (Route("sample", "farther", "water"),),
        why="0.04 km is 40 m, the reach of the fall-off",
    ),
    Brief(
        "A word from the committee: the herd grazes round the buildings at Low Farm, so the "
        "wider the margin you give the buildings the happier everyone is. About 30 m is plenty.",
        "field",
        "graded_away",
        NB,
        (("graded_away", "building", 30), ("not_lethal", "building")),
        (Route("nb1", "farther", "building"),),
    ),
    Brief(
        "Near a tree is bad, nearer is worse, touching one is worst. Past 12 m they stop mattering.",
        "field",
        "graded_away",
        TREE,
        (("graded_away", "tree", 12), ("avoided", "tree")),
        (Route("neon", "farther", "tree"),),
    ),
    # ------------------------------------------------------------------------------------------
    # graded_toward
    # ------------------------------------------------------------------------------------------
    Brief(
        "Search pattern: keep the trail in sight the whole way. The missing walker was last seen "
        "on it, so the closer to the trail, the better.",
        "field",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "trail", None),),
        (Route("sample", "closer", "trail"),),
    ),
    Brief(
        "Be no more than 20 m from the road if you can help it, and the nearer the better.",
        "robot",
        "graded_toward",
        NB,
        (("graded_toward", "road", 20), ("avoided", "building")),
        (Route("nb1", "closer", "road"),),
        why="'no more than 20 m ... if you can help it' is a soft pull toward the road",
    ),
    Brief(
        "Paths were biased toward the paved road network: cost decreased monotonically with "
        "proximity to paved road, with no effect beyond 50 m.",
        "analyst",
        "graded_toward",
        VEGAS,
        (("graded_toward", "paved road", 50),),
        (Route("vegas", "closer", "paved road"),),
    ),
    Brief(
        "Walk the margins today. Stay near the vegetation so the camera catches the crop rows; "
        "the nearer the rows the better the images.",
        "field",
        "graded_toward",
        NB,
        (("graded_toward", "vegetation", None),),
        (Route("nb1", "closer", "vegetation"),),
    ),
    Brief(
        "hey so, like, can you just stick close to the, um, the railroad tracks? like the closer the better honestly",
        "robot",
        "graded_toward",
        NB,
        (("graded_toward", "railway", None),),
        (Route("nb2", "closer", "railway"),),
    ),
    Brief(
        "Pre-run checklist\n"
        "[x] Battery above 80 %\n"
        "[x] Route: stay close to the trees for shade (closer = better)\n"
        "[ ] Headlights\n"
        "[x] Buildings: avoid",
        "robot",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "tree", None), ("avoided", "building"), ("unread", "battery")),
        (Route("sample", "closer", "tree"), Route("sample", "less_on", "building")),
        why="the battery line is a check, not a rule about the map; the unticked box sets nothing",
    ),
    Brief(
        "MISSION: recon team moves under cover to OP2.\n"
        "EXECUTION: make maximum use of the tree line for concealment. The closer to the trees, "
        "the better.",
        "analyst",
        "graded_toward",
        TREE,
        (("graded_toward", "tree", None),),
        (Route("neon", "closer", "tree"),),
    ),
    # ------------------------------------------------------------------------------------------
    # on_beside
    # ------------------------------------------------------------------------------------------
    Brief(
        "[09:02] dana: bots getting lost in the car park again\n"
        "[09:03] dana: make them hug the buildings\n"
        "[09:03] sam: but not ON them obviously\n"
        "[09:04] dana: yes obviously lol",
        "robot",
        "on_beside",
        BUILDING,
        (("beside", "building"),),
        (Route("massachusetts", "beside", "building", 3),),
    ),
    Brief(
        "robot stay close to the water like a duck does! but dont go IN the water thats not allowed",
        "robot",
        "on_beside",
        SAMPLE,
        (("beside", "water"), ("lethal", "water")),
        (Route("sample", "beside", "water", 5), Route("sample", "zero_on", "water")),
        why="'dont go IN' is the child's 'don't go into': forbidding",
    ),
    Brief(
        "Course marshals: ride alongside the trail on the grass verge, never on the trail "
        "itself. Racers own the trail today.",
        "field",
        "on_beside",
        SAMPLE,
        (("beside", "trail"), ("preferred", "grass")),
        (Route("sample", "beside", "trail", 5),),
    ),
    Brief(
        "WO-2291. Crew to follow the railway corridor on foot, walking beside the track, never "
        "on the ballast or the rails.",
        "analyst",
        "on_beside",
        NB,
        (("beside", "railway"),),
        (Route("nb2", "beside", "railway", 5),),
    ),
    Brief(
        "follow the road but on the shoulder not the road its self stay just off it a couple of "
        "meters their is a verge the whole way",
        "field",
        "on_beside",
        NB,
        (("beside", "road"),),
        (Route("nb1", "beside", "road", 3),),
    ),
    Brief(
        "Track the paved road from the verge: parallel to it, a few metres off, not on the asphalt.",
        "robot",
        "on_beside",
        VEGAS,
        (("beside", "paved road"),),
        (Route("vegas", "beside", "paved road", 4),),
    ),
    Brief(
        "The platform travelled adjacent to, but never upon, building footprints, holding a band "
        "within roughly 2 m of the facade.",
        "analyst",
        "on_beside",
        BUILDING,
        (("beside", "building"),),
        (Route("kampala", "beside", "building", 3),),
    ),
    # ------------------------------------------------------------------------------------------
    # qualified
    # ------------------------------------------------------------------------------------------
    Brief(
        "| class | rule | distance |\n|---|---|---|\n| paved road | prefer | - |\n| unpaved road | avoid | - |",
        "analyst",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road"), ("below", "paved road", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        "Scouting, block C: the conifers are fine to pass under. Stay out of the deciduous trees, "
        "they were sprayed this morning.",
        "field",
        "qualified",
        ("deciduous tree", "conifer tree", "grass"),
        (("lethal", "deciduous tree"), ("neutral", "conifer tree")),
        why="'fine to pass under' merely allows (neutral); 'stay out of' forbids",
    ),
    Brief(
        "All buildings are off limits to the patrol robot except the visitor centre, which it may enter to dock.",
        "field",
        "qualified",
        ("building", "visitor centre"),
        (("lethal", "building"), ("neutral", "visitor centre")),
        (Route("massachusetts", "zero_on", "building"),),
        why="the visitor centre is excepted and merely allowed",
    ),
    Brief(
        "Prefer the unpaved roads to the paved ones. Paved road is allowed, just second best.",
        "robot",
        "qualified",
        VEGAS,
        (("below", "unpaved road", "paved road"), ("not_lethal", "paved road")),
        (Route("vegas", "more_on", "unpaved road"),),
    ),
    Brief(
        "Shallow water is OK to ford. Deep water is a no-go.",
        "field",
        "qualified",
        ("shallow water", "deep water", "grass"),
        (("lethal", "deep water"), ("neutral", "shallow water")),
    ),
    Brief(
        "Condition 3: Construction traffic shall use the paved road only. Condition 4: The "
        "unpaved road shall not be used at any time.",
        "analyst",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("lethal", "unpaved road")),
        (Route("vegas", "more_on", "paved road"), Route("vegas", "zero_on", "unpaved road")),
        why="'shall not be used at any time' forbids the unpaved road",
    ),
    Brief(
        "Avoid the grass, except the mown strip by the trail, which is the line I want you on.",
        "field",
        "qualified",
        ("grass", "mown strip", "trail"),
        (("avoided", "grass"), ("preferred", "mown strip"), ("below", "mown strip", "grass")),
    ),
    Brief(
        "Residential buildings: give them room. Derelict buildings: off limits entirely.",
        "analyst",
        "qualified",
        ("residential building", "derelict building"),
        (("lethal", "derelict building"), ("avoided", "residential building"), ("not_lethal", "residential building")),
    ),
    # ------------------------------------------------------------------------------------------
    # terse
    # ------------------------------------------------------------------------------------------
    Brief(
        "1st choice: trail. 2nd: grass. last choice: road.",
        "robot",
        "terse",
        SAMPLE,
        (("below", "trail", "grass"), ("below", "grass", "road")),
        (Route("sample", "more_on", "trail"),),
        why="ranks give an order, not levels",
    ),
    Brief(
        "basebal feild = no-go",
        "robot",
        "terse",
        SAMPLE,
        (("lethal", "baseball field"),),
        (Route("sample", "zero_on", "baseball field"),),
    ),
    Brief(
        "pavd rd preferd, unpavd rd fine",
        "robot",
        "terse",
        VEGAS,
        (("preferred", "paved road"), ("neutral", "unpaved road"), ("below", "paved road", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        "grass ok / road meh",
        "robot",
        "terse",
        SAMPLE,
        (("below", "grass", "road"), ("not_lethal", "road")),
    ),
    Brief(
        "road = 3x trail (cost)",
        "analyst",
        "terse",
        SAMPLE,
        (("below", "trail", "road"),),
        why="a ratio gives the order only",
    ),
    Brief(
        "avod the railwya, stay on teh road",
        "robot",
        "terse",
        NB,
        (("avoided", "railway"), ("preferred", "road")),
        (Route("nb2", "less_on", "railway"), Route("nb1", "more_on", "road")),
    ),
    Brief(
        "bldgs 5 m hard; wtr avoid",
        "field",
        "terse",
        SAMPLE,
        (("keep_out", "building", 5), ("avoided", "water")),
        (Route("sample", "keeps", "building", 5), Route("sample", "less_on", "water")),
    ),
    # ------------------------------------------------------------------------------------------
    # permission
    # ------------------------------------------------------------------------------------------
    Brief(
        "The footbridge is out, so the patrol robot has my authorisation to wade the water where "
        "needed. Buildings remain off limits.",
        "field",
        "permission",
        SAMPLE,
        (("neutral", "water"), ("lethal", "building")),
        (Route("sample", "zero_on", "building"),),
        why="authorised to wade: the water's prior is lifted to merely allowed",
    ),
    Brief(
        "Note to the groundskeeping bot: you may not enter the baseball field. Everywhere else is yours.",
        "robot",
        "permission",
        SAMPLE,
        (("lethal", "baseball field"), ("not_lethal", "grass")),
        (Route("sample", "zero_on", "baseball field"),),
        why="'you may not enter' forbids like 'never enter'",
    ),
    Brief(
        "you're allowed to walk on the grass, mummy said so. but you're not allowed in the water",
        "robot",
        "permission",
        SAMPLE,
        (("neutral", "grass"), ("lethal", "water")),
        (Route("sample", "zero_on", "water"),),
        why="'not allowed in' forbids",
    ),
    Brief(
        "Permit granted: the crew may traverse vegetation along the right-of-way. Buildings: no entry.",
        "analyst",
        "permission",
        NB,
        (("neutral", "vegetation"), ("lethal", "building")),
        (Route("nb1", "zero_on", "building"),),
    ),
    Brief(
        "[14:40] lee: ok trees are fine now, the canopy sensor upgrade shipped\n"
        "[14:41] ana: so they can go under canopy?\n"
        "[14:41] lee: yep, no penalty",
        "robot",
        "permission",
        TREE,
        (("neutral", "tree"), ("not_lethal", "tree")),
    ),
    Brief(
        "um so you don't have to avoid the buildings anymore? like, it's fine, you can go right up to them",
        "robot",
        "permission",
        BUILDING,
        (("neutral", "building"), ("not_lethal", "building")),
    ),
    Brief(
        "Water is allowed, but count it three times worse than grass.",
        "analyst",
        "permission",
        SAMPLE,
        (("not_lethal", "water"), ("below", "grass", "water")),
    ),
    Brief(
        "Condition 12: The applicant shall keep out of the railway land. The public roads may be used freely.",
        "analyst",
        "permission",
        NB,
        (("lethal", "railway"), ("not_lethal", "road")),
        (Route("nb2", "zero_on", "railway"),),
    ),
    Brief(
        "You may not cross the railway under any circumstances.",
        "robot",
        "permission",
        NB,
        (("no_cross", "railway"),),
        (Route("nb2", "zero_on", "railway"),),
    ),
    # ------------------------------------------------------------------------------------------
    # clauses
    # ------------------------------------------------------------------------------------------
    Brief(
        "Use the trail. If it's raining, stay off the grass as well.",
        "field",
        "clauses",
        SAMPLE,
        (("preferred", "trail"), ("unread", "raining")),
        (Route("sample", "more_on", "trail"),),
        why="the map cannot know the weather",
    ),
    Brief(
        "After dusk, keep 20 m from the buildings; in daylight there's no restriction.",
        "robot",
        "clauses",
        BUILDING,
        (("unread", "dusk"),),
        why="the rule hangs on the time of day",
    ),
    Brief(
        "Use the road, except when traffic is heavy; then go round by the verge.",
        "robot",
        "clauses",
        NB,
        (("unread", "traffic"),),
    ),
    Brief(
        "Drive on the road. Keep out of the water. Avoid buildings.",
        "robot",
        "clauses",
        NB,
        (("preferred", "road"), ("lethal", "water"), ("avoided", "building"), ("all_read",)),
        (
            Route("nb1", "more_on", "road"),
            Route("nb1", "zero_on", "water"),
            Route("nb1", "less_on", "building"),
        ),
    ),
    Brief(
        "First choice the trail, then the grass. The water is off limits.",
        "field",
        "clauses",
        SAMPLE,
        (("below", "trail", "grass"), ("lethal", "water"), ("all_read",)),
        (Route("sample", "zero_on", "water"),),
    ),
    Brief(
        "Keep 10 m from the power lines and avoid the water.",
        "field",
        "clauses",
        SAMPLE,
        (("avoided", "water"), ("unread", "power")),
        (Route("sample", "less_on", "water"),),
        why="no layer stands for power lines",
    ),
    Brief(
        "Avoid the grass unless it's dry.",
        "field",
        "clauses",
        SAMPLE,
        (("unread", "dry"),),
    ),
    Brief(
        "Crossing the railway is not allowed unless the level-crossing gates are up.",
        "analyst",
        "clauses",
        NB,
        (("unread", "gates"),),
        why="whether the gates are up is not on the map",
    ),
    Brief(
        "Take grass over road every time, and keep out of the water.",
        "robot",
        "clauses",
        SAMPLE,
        (("below", "grass", "road"), ("lethal", "water"), ("all_read",)),
        (Route("sample", "zero_on", "water"),),
    ),
]
