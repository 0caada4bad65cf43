"""Mission briefs, set 20: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench, the docs or the briefs of earlier sets: only the contract
(``tests/mission_briefs.py`` and its format test ``tests/test_mission_briefs.py``), the scene index
(``../shared/scenes/INDEX.md`` and the scenes' ``classes.json``) and the first 40 lines of set 19
(for the layout of its module constants and docstring) were read. It is scored once, at first
contact, with ``bench/mission_briefs_report.py --set 20``; that figure is the one that counts, and
the set is not edited afterwards to make the interpreter pass.

The voices are a wildfire crew lead on the radio, a mining surveyor, a park ranger writing a
trail-maintenance work order, a search-and-rescue lead and a groundskeeper (field crews), a
logistics planner writing bullet points, a planetary-rover researcher borrowing Earth imagery and an
environmental analyst (analysts), and a student writing a first robot mission, someone shouting in
capitals and someone pasting a YAML or JSON fragment (robot operators); British, Australian, Indian
and Nigerian English speakers bring their own idioms (metalled roads, towpaths, bitumen, bone-dry
creeks, pucca and kutcha roads, "kindly", "ply the tarred road"). The constructs are ranked
preferences (chains, "A before B", "A over B", "rather A than B", "A is better than B", numbered and
bulleted lists), forbidden areas ("keep out of them", "never enter", "off limits", "no-go", "must
not be entered", "never go in") against plain avoidance ("avoid X", "try not to use X"), permissions
that lift priors (vacant buildings, a frozen pond, a dry creek, trees spaced out enough to drive
through, a closed branch line), hard distance rules with numbers in metres, feet and yards (one
spelled out) and absolute wording, soft distance rules ("ideally", "where practicable", "if you can
manage it", "wherever feasible", "not a hard limit"), graded nearness both ways ("the further from X
the better", "a wide berth", "don't go near", "tapering to nothing by 20 m", "stay close to", "keep
within sight of"), on versus beside (verge not road, towpath not canal, shoulder not asphalt,
between crowns not under them), qualified classes on the Las Vegas scene (paved against unpaved road
as metalled, bitumen, sealed, tarred, pucca and asphalt against unmetalled, dirt, kutcha, untarred
and washboard), typos in multi-word names, and clauses naming things no layer stands for (a helipad,
a blast zone and explosives magazine, pallet stacks, forklifts, a cell tower, dunes and sand
ripples, pylons, scrub and a gutter), which must be reported unread. The layers of each brief are
the class names of the scene its routes are checked on; briefs over layers no scene holds carry no
route checks.
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
#: The bundled sample.
SAMPLE = ("grass", "road", "trail", "tree", "water", "building", "baseball field")

#: Briefs retired after scoring because their expectation contradicts the contract (none yet).
DOUBTFUL: dict[str, str] = {}

FT = 0.3048
YD = 0.9144

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------------------------------
    # Hard distance rules: absolute wording, numbers in metres, feet, yards, spelled out
    # ------------------------------------------------------------------------------------------
    Brief(
        "Traverse for the pit survey. The settling pond is unstable at the margins, so the rover must "
        "never come closer than 25 m to the water. Haul roads carry live trucks and are a no-go.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "water", 25), ("lethal", "road")),
        (Route("nb1", "keeps", "water", 25), Route("nb1", "zero_on", "road")),
        why="A mining surveyor: 'never closer than 25 m' is absolute; haul roads are the road layer, "
        "and 'no-go' forbids them.",
    ),
    Brief(
        "MAINTAIN 12 METRES MINIMUM FROM ALL STRUCTURES AT ALL TIMES. NO EXCEPTIONS.",
        "robot",
        "distance_hard",
        BUILDINGS,
        (("keep_out", "building", 12),),
        (Route("massachusetts", "keeps", "building", 12),),
        why="All capitals; structures are the building footprints; 'at all times, no exceptions' is absolute.",
    ),
    Brief(
        "Crew, listen up: nobody gets within 100 feet of the rail line, period.",
        "field",
        "distance_hard",
        NB,
        (("keep_out", "railway", 100 * FT),),
        (Route("nb2", "keeps", "railway", 100 * FT),),
        why="A crew lead; 'period' makes the 100 ft (30.48 m) rule absolute.",
    ),
    Brief(
        "Under no circumstances is the mower to come within 15 yards of the pavilion or any other building.",
        "field",
        "distance_hard",
        NB,
        (("keep_out", "building", 15 * YD),),
        (Route("nb1", "keeps", "building", 15 * YD),),
        why="A groundskeeper; the pavilion is one of the buildings, and 'under no circumstances' is absolute.",
    ),
    Brief(
        "Division Alpha, copy. Hard line: stay thirty metres off the road, fire's spotting across it. "
        "Break. The trees are fuel, keep out of them. Over.",
        "field",
        "distance_hard",
        SAMPLE,
        (("keep_out", "road", 30), ("lethal", "tree")),
        (Route("sample", "keeps", "road", 30), Route("sample", "zero_on", "tree")),
        why="Wildfire radio traffic: 'hard line' makes the spelled-out thirty metres absolute; 'keep out "
        "of' forbids the trees.",
    ),
    Brief(
        "Mars analogue run on Earth imagery. Treat open water as a crater-rim hazard: the rover may not pass "
        "within 8 m of it. Buildings stand in for boulder fields and must not be entered.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "water", 8), ("lethal", "building")),
        (Route("nb1", "keeps", "water", 8), Route("nb1", "zero_on", "building")),
        why="A planetary-rover researcher: 'may not pass within 8 m' is absolute; 'must not be entered' forbids.",
    ),
    Brief(
        "We're running a biodiversity transect through the park next Tuesday and volunteers will be walking "
        "behind the robot, so bear that in mind. The trail is the obvious choice and it's what I'd like it "
        "to use most; grass is an acceptable fallback. Nobody should be anywhere near the water, the banks "
        "are collapsing, so keep a full 10 m from it with no exceptions. The baseball field is being "
        "reseeded and is off limits. And if you can, leave a little room around the buildings, say 5 m, "
        "though that one isn't critical.",
        "analyst",
        "distance_hard",
        SAMPLE,
        (
            ("preferred", "trail"),
            ("below", "trail", "grass"),
            ("keep_out", "water", 10),
            ("lethal", "baseball field"),
            ("soft_zone", "building", 5),
        ),
        (
            Route("sample", "more_on", "trail"),
            Route("sample", "keeps", "water", 10),
            Route("sample", "zero_on", "baseball field"),
        ),
        why="A long paragraph with context mixed in: the water rule is absolute ('a full 10 m, no "
        "exceptions'), the building one explicitly soft.",
    ),
    # ------------------------------------------------------------------------------------------
    # Soft distance rules: the number kept, no keep-out
    # ------------------------------------------------------------------------------------------
    Brief(
        "Where practicable, hold a 10 m standoff from buildings; it's a preference, not a rule.",
        "analyst",
        "distance_soft",
        NB,
        (("soft_zone", "building", 10),),
        why="Explicitly soft: a dearer band of 10 m, nothing kept out.",
    ),
    Brief(
        "If you can manage it, stop about 5 m back from the creek. No worries if you can't.",
        "field",
        "distance_soft",
        NB,
        (("soft_zone", "water", 5),),
        why="Australian English; the creek is the water layer and the rule is plainly soft.",
    ),
    Brief(
        "Kindly maintain approximately 15 metre gap from railway line wherever feasible.",
        "analyst",
        "distance_soft",
        NB,
        (("soft_zone", "railway", 15),),
        (Route("nb2", "farther", "railway"),),
        why="Indian English; 'wherever feasible' makes the 15 m soft.",
    ),
    Brief(
        "Route notes:\n- paved road preferred\n- try for ~10 m clearance from unpaved road (not a hard limit)",
        "analyst",
        "distance_soft",
        VEGAS,
        (("preferred", "paved road"), ("soft_zone", "unpaved road", 10)),
        (Route("vegas", "more_on", "paved road"),),
        why="A logistics planner's bullets; the clearance is declared not hard.",
    ),
    Brief(
        "Ideally give the ball field about 30 feet of room; the grounds crew would appreciate it.",
        "field",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "baseball field", 30 * FT),),
        why="'Ideally' keeps the 30 ft (9.14 m) band soft.",
    ),
    # ------------------------------------------------------------------------------------------
    # Graded nearness, away
    # ------------------------------------------------------------------------------------------
    Brief(
        "The further from the water the better, those banks are eroding.",
        "field",
        "graded_away",
        NB,
        (("graded_away", "water", None),),
        (Route("nb1", "farther", "water"),),
    ),
    Brief(
        "Give the railway a wide berth, if you'd be so kind.",
        "field",
        "graded_away",
        NB,
        (("graded_away", "railway", None),),
        (Route("nb2", "farther", "railway"),),
        why="British politeness; a wide berth is keeping well away, priced by distance, not a fixed zone.",
    ),
    Brief(
        "Don't go near the houses, people are sleeping.",
        "field",
        "graded_away",
        BUILDINGS,
        (("graded_away", "building", None),),
        (Route("kampala", "farther", "building"),),
    ),
    Brief(
        "Proximity to roads is penalised: heavily right at the edge, tapering to nothing by 20 m.",
        "analyst",
        "graded_away",
        NB,
        (("graded_away", "road", 20),),
        (Route("nb1", "farther", "road"),),
        why="The fall-off is stated: it reaches neutral at 20 m.",
    ),
    Brief(
        "Please, the robot should not go anywhere near the rail track o.",
        "field",
        "graded_away",
        NB,
        (("graded_away", "railway", None),),
        (Route("nb2", "farther", "railway"),),
        why="Nigerian English (the closing 'o' is emphasis); 'not anywhere near' is graded nearness.",
    ),
    Brief(
        "The closer to a building, the worse; past 15 m it stops mattering.",
        "analyst",
        "graded_away",
        BUILDINGS,
        (("graded_away", "building", 15),),
        (Route("massachusetts", "farther", "building"),),
    ),
    # ------------------------------------------------------------------------------------------
    # Graded nearness, toward
    # ------------------------------------------------------------------------------------------
    Brief(
        "Stay close to the road so the support truck can reach you.",
        "field",
        "graded_toward",
        NB,
        (("graded_toward", "road", None),),
        (Route("nb1", "closer", "road"),),
        why="A search-and-rescue lead.",
    ),
    Brief(
        "WORK ORDER 2207 - brushing crew. Keep within sight of the trail while moving between work sites.",
        "field",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "trail", None),),
        (Route("sample", "closer", "trail"),),
        why="A park ranger's work order; within sight of the trail is the nearer the cheaper.",
    ),
    Brief(
        "Facade survey: the nearer the buildings the better, so hang close to them.",
        "analyst",
        "graded_toward",
        BUILDINGS,
        (("graded_toward", "building", None),),
        (Route("massachusetts", "closer", "building"),),
    ),
    Brief(
        "Shade helps the batteries, so keep near the tree crowns.",
        "robot",
        "graded_toward",
        TREES,
        (("graded_toward", "tree", None),),
        (Route("neon", "closer", "tree"),),
    ),
    Brief(
        "For the thermal-inertia study, stay near the lake; it is our stand-in for a paleolake basin.",
        "analyst",
        "graded_toward",
        NB,
        (("graded_toward", "water", None),),
        (Route("nb1", "closer", "water"),),
        why="A planetary researcher using the lake as an analogue; near it, not in it.",
    ),
    # ------------------------------------------------------------------------------------------
    # On versus beside
    # ------------------------------------------------------------------------------------------
    Brief(
        "Walk the verge, not the road.",
        "field",
        "on_beside",
        NB,
        (("beside", "road"),),
        (Route("nb1", "beside", "road", 5),),
    ),
    Brief(
        "Follow the towpath along the canal and keep off the water itself.",
        "field",
        "on_beside",
        NB,
        (("beside", "water"),),
        (Route("nb1", "beside", "water", 5),),
        why="British: the towpath is the bank beside the canal (water).",
    ),
    Brief(
        "Drive on the shoulder of the paved road, never on the asphalt itself.",
        "robot",
        "on_beside",
        VEGAS,
        (("beside", "paved road"),),
        (Route("vegas", "beside", "paved road", 5),),
    ),
    Brief(
        "Thread between the crowns; don't go under them.",
        "field",
        "on_beside",
        TREES,
        (("beside", "tree"),),
        (Route("neon", "beside", "tree", 3),),
    ),
    Brief(
        "Walk alongside the trail on the grass margin, not on the trail itself, we are re-gravelling it.",
        "field",
        "on_beside",
        SAMPLE,
        (("beside", "trail"),),
        (Route("sample", "beside", "trail", 5),),
    ),
    Brief(
        "Robot should move along the bank of the lake only, not inside the water.",
        "analyst",
        "on_beside",
        NB,
        (("beside", "water"),),
        (Route("nb1", "beside", "water", 5),),
        why="Indian English: the bank, not the water.",
    ),
    # ------------------------------------------------------------------------------------------
    # Qualified classes: paved against unpaved road on the Las Vegas scene
    # ------------------------------------------------------------------------------------------
    Brief(
        "Keep to the metalled roads; unmetalled tracks are a last resort.",
        "field",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road"), ("below", "paved road", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
        why="British: metalled is paved; a last resort is avoided, not forbidden.",
    ),
    Brief(
        "Stick to the bitumen, mate, and avoid the dirt roads. Steer well clear of the scrub too.",
        "field",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road"), ("unread", "scrub")),
        (Route("vegas", "more_on", "paved road"),),
        why="Australian: bitumen is paved; no layer holds scrub here.",
    ),
    Brief(
        "Kindly prefer the pucca road. Kutcha road is to be used only if no other option is there.",
        "analyst",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road"), ("below", "paved road", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
        why="Indian English: pucca is paved, kutcha unpaved; 'only if no other option' is avoidance.",
    ),
    Brief(
        "The robot should ply the tarred road. Untarred road should only be used when there is no other "
        "way. It should not go near the gutter.",
        "field",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road"), ("unread", "gutter")),
        (Route("vegas", "more_on", "paved road"),),
        why="Nigerian English: to ply a road is to travel it; no layer holds the gutter.",
    ),
    Brief(
        "Asphalt is fine to drive on. The washboard dirt tracks are off limits, they shake the lidar loose.",
        "robot",
        "qualified",
        VEGAS,
        (("not_lethal", "paved road"), ("lethal", "unpaved road")),
        (Route("vegas", "zero_on", "unpaved road"),),
    ),
    Brief(
        '{"prefer": "sealed road", "avoid": "dirt track"}',
        "robot",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
        why="A pasted JSON fragment; sealed is paved, a dirt track unpaved.",
    ),
    Brief(
        "Route priorities:\n1. paved road\n2. unpaved road\n3. open ground",
        "analyst",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("below", "paved road", "unpaved road"), ("preferred", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
        why="A numbered list: both roads rank above open ground (neutral), so both are preferred, paved first.",
    ),
    Brief(
        "I'd rather it took the dirt road than the bitumen, the sealed road's full of road trains.",
        "field",
        "qualified",
        VEGAS,
        (("below", "unpaved road", "paved road"),),
        why="Australian 'rather A than B' with the unusual order: unpaved is the cheaper of the two.",
    ),
    # ------------------------------------------------------------------------------------------
    # Terse and symbolic briefs, and ranked chains
    # ------------------------------------------------------------------------------------------
    Brief(
        "bldg: avoid. water: NO-GO. rd: prefer",
        "robot",
        "terse",
        NB,
        (("avoided", "building"), ("lethal", "water"), ("preferred", "road")),
        (Route("nb1", "less_on", "building"), Route("nb1", "zero_on", "water"), Route("nb1", "more_on", "road")),
    ),
    Brief(
        "paved raod preferred, unpaved raod avoid",
        "robot",
        "terse",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
        why="The same typo in both multi-word names.",
    ),
    Brief(
        "ball field: off limits / trail: yes please / trees: avoid",
        "field",
        "terse",
        SAMPLE,
        (("lethal", "baseball field"), ("preferred", "trail"), ("avoided", "tree")),
        (
            Route("sample", "zero_on", "baseball field"),
            Route("sample", "more_on", "trail"),
            Route("sample", "less_on", "tree"),
        ),
    ),
    Brief(
        "prefer: [trail]\navoid: [road, building]\nno_go: [water]",
        "robot",
        "terse",
        SAMPLE,
        (
            ("preferred", "trail"),
            ("avoided", "road"),
            ("avoided", "building"),
            ("lethal", "water"),
            ("all_read",),
        ),
        (Route("sample", "more_on", "trail"), Route("sample", "zero_on", "water")),
        why="A pasted YAML fragment, every key a rule over a layer.",
    ),
    Brief(
        "Use the trail before the grass, and the grass before the road.",
        "field",
        "terse",
        SAMPLE,
        (("below", "trail", "grass"), ("below", "grass", "road")),
        (Route("sample", "more_on", "trail"),),
    ),
    Brief(
        "Pick grass over trail, and trail over road.",
        "robot",
        "terse",
        SAMPLE,
        (("below", "grass", "trail"), ("below", "trail", "road")),
    ),
    # ------------------------------------------------------------------------------------------
    # Permissions that lift priors, and stay-out wording that forbids
    # ------------------------------------------------------------------------------------------
    Brief(
        "The pond's frozen solid this week, so crossing on the ice is fine.",
        "field",
        "permission",
        NB,
        (("neutral", "water"), ("not_lethal", "water"), ("below", "water", "building")),
        why="Allowed, so neutral: below the unmentioned buildings, which keep their prior.",
    ),
    Brief(
        "The buildings on site are vacant shells slated for demolition; the robot may pass through them.",
        "analyst",
        "permission",
        NB,
        (("neutral", "building"), ("not_lethal", "building"), ("below", "building", "water")),
        why="Passing through is allowed: neutral, below the unmentioned water's prior.",
    ),
    Brief(
        "Creek's bone dry this time of year, drive straight through it. Try not to cross the railway though.",
        "field",
        "permission",
        NB,
        (("neutral", "water"), ("avoided", "railway"), ("not_lethal", "railway")),
        (Route("nb2", "less_on", "railway"),),
        why="Australian: the dry creek (water) is allowed; 'try not to' is avoidance, not a ban.",
    ),
    Brief(
        "The branch line closed years ago and the rails have been lifted, so treat it like any other ground.",
        "field",
        "permission",
        NB,
        (("neutral", "railway"), ("below", "railway", "building")),
        why="A disused railway: like any other ground is neutral, below the buildings' prior.",
    ),
    Brief(
        "Never enter the ball field while a game is on. Try not to use the road either, though it's "
        "allowed if there's no other way.",
        "field",
        "permission",
        SAMPLE,
        (("lethal", "baseball field"), ("avoided", "road"), ("not_lethal", "road")),
        (Route("sample", "zero_on", "baseball field"), Route("sample", "less_on", "road")),
        why="Forbidden against plain avoidance in one brief.",
    ),
    Brief(
        "my teacher said the trees are spaced out so the robot can drive thru them, but it must never go in the pond",
        "robot",
        "permission",
        SAMPLE,
        (("neutral", "tree"), ("not_lethal", "tree"), ("lethal", "water")),
        (Route("sample", "zero_on", "water"),),
        why="A student: sparse trees allowed (neutral); never going in the pond forbids the water.",
    ),
    Brief(
        "The trees are sparse enough to drive through; still, grass is better than trees, and the trail "
        "is better than grass.",
        "analyst",
        "permission",
        SAMPLE,
        (("not_lethal", "tree"), ("below", "grass", "tree"), ("below", "trail", "grass")),
        (Route("sample", "more_on", "trail"),),
        why="'A is better than B' chained on top of a permission.",
    ),
    # ------------------------------------------------------------------------------------------
    # Clauses: things no layer holds are reported unread, never silently dropped
    # ------------------------------------------------------------------------------------------
    Brief(
        "Avoid the road. Stay well clear of the helipad, rotors are turning.",
        "field",
        "clauses",
        NB,
        (("avoided", "road"), ("unread", "helipad")),
        (Route("nb1", "less_on", "road"),),
    ),
    Brief(
        "Prefer the road, and keep 30 m from the blast zone and the explosives magazine.",
        "analyst",
        "clauses",
        NB,
        (("preferred", "road"), ("unread", "blast"), ("unread", "magazine")),
        (Route("nb1", "more_on", "road"),),
        why="A mining surveyor: no layer holds the blast zone or the magazine.",
    ),
    Brief(
        "Yard move checklist:\n- use roads where possible\n- avoid buildings\n- keep clear of the pallet "
        "stacks\n- watch out for forklifts",
        "analyst",
        "clauses",
        NB,
        (("preferred", "road"), ("avoided", "building"), ("unread", "pallet"), ("unread", "forklifts")),
        (Route("nb1", "more_on", "road"), Route("nb1", "less_on", "building")),
        why="A logistics planner's bullets, two of them over things no layer holds.",
    ),
    Brief(
        "Avoid the buildings. Keep at least 10 m from the cell tower.",
        "analyst",
        "clauses",
        BUILDINGS,
        (("avoided", "building"), ("unread", "cell tower")),
        (Route("massachusetts", "less_on", "building"),),
    ),
    Brief(
        "Stay on the paved road, it approximates the lava-tube roof. Avoid the dune field and any sand ripples.",
        "analyst",
        "clauses",
        VEGAS,
        (("preferred", "paved road"), ("unread", "dune"), ("unread", "ripples")),
        (Route("vegas", "more_on", "paved road"),),
        why="A planetary-rover researcher: the dunes and ripples have no layer here.",
    ),
    Brief(
        "Avoid the trees, prefer the grass, and try not to use the water.",
        "robot",
        "clauses",
        SAMPLE,
        (("avoided", "tree"), ("preferred", "grass"), ("avoided", "water"), ("not_lethal", "water"), ("all_read",)),
        (Route("sample", "less_on", "tree"), Route("sample", "less_on", "water")),
        why="Every clause is over a layer: nothing to report.",
    ),
    Brief(
        "AVOID THE RAILWAY. KEEP AWAY FROM THE PYLONS.",
        "robot",
        "clauses",
        NB,
        (("avoided", "railway"), ("unread", "pylons")),
        (Route("nb2", "less_on", "railway"),),
    ),
]
