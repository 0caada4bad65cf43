"""Mission briefs, set 30: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench, the docs or the briefs of earlier sets: only the contract
(``tests/mission_briefs.py`` and its format test ``tests/test_mission_briefs.py``), the scene index
(``../shared/scenes/INDEX.md`` and the scenes' ``classes.json``), the first 80 lines of set 29
(for the layout, and its docstring's list of voices and wordings), the first 25 lines of sets 26,
27 and 28 (their docstrings' lists of voices, which this set avoids) and the ruff settings of
``pyproject.toml`` were read. It is scored once, at first contact, with
``bench/mission_briefs_report.py --set 30``; that figure is the one that counts, and the set is not
edited afterwards to make the interpreter pass.

The voices are a harbour master's notices ("NOTICE TO ALL HARBOUR USERS", the quay, the slipway
and the pontoon, the flats at low tide), a ground-penetrating-radar survey crew (the cart, "the
rails wreck our radar returns", a railway possession, the open barn whose floor is scanned), a
flood-recovery volunteer coordinator (silt, mud and debris, flood cracks in the walls), a farm
contractor spraying a drift-prone mix (the label's buffer, the hedge bank, the fish), a
delivery-robot fleet operator's incident retrospective ("INC-2291, action 3", "Root cause:",
"Corrective action:", "Retro finding 2"), a vineyard manager (the picker robot between the rows,
the quad, the freight trains that shake the posts loose, vines pruned high), a cemetery
groundskeeper (the mower bot, the chapel, the graves and headstones, the yews, the mourners'
trail), a school caretaker ("while the kids are in", "the little ones are out at break", the long
grass by the fence), an airside NOTAM ("NOTAM R0412/25 GND ROVER OPS", "WI 20 M", "NO
DEVIATION"), a New Zealand speaker ("Yeah nah", "sweet as", "chur", "metal road", "tarseal"), a
Canadian French speaker writing English ("please to stay 8 metres of the trees", "it is not
grave", "More the robot is far of the road, more it is good", "near of the grass"), a Jamaican
English speaker ("Mi a tell yuh straight", "cyaan go nearer than ten yards", "side-a di railway,
close close", "nuh fi climb pon di track dem"), a German engineer's terse requirements ("Req.
4.3", "7,5 m", "Zero tolerance", "lateral offset of 2-4 m", "Water: verboten"), Python dict
literals (``"min_gap_m": 15, "absolute": True``, ``"shape": "decay_with_distance", "reach_m"``,
``attract = {... "pull": "strong", "falloff_m": 25}``), a CSV rules table (``class,
min_distance_m,enforcement`` with ``advisory`` rows), command-line flags (``--forbid water
--avoid building --prefer trail``), numbered SOPs ("SOP-22 Rover Transit. 4.1 ... 4.2"), Slack
threads in which people correct each other ("@priya: ... soft I think? / @tom: no, ops said it's
a hard 10"), a voice-assistant transcription with no punctuation ("hey rover new rule ..."),
rhymed verse in couplets (lines split by " / "), an exam question ("Q4 (6 marks) ... Show your
working."), and terse lines with typos ("bulidings", "railwy, closr = cheapr", "basball field",
"treez bad, gras gud", "paved raod", "unpavd road"). The commission also proposed a solar farm
O&M technician, an archaeologist, a wildfire crew boss, a TOML file, a drone pilot's checklist,
an Australian speaker and a haiku-ish brief; sets 26 and 27 had used those (or a near copy), so
this set has the GPR crew, the flood coordinator, the vineyard manager, the CSV table, the NOTAM,
the New Zealander and rhymed couplets instead.

Units come in metres and meters ("eight meters"), feet (30 feet = 9.144 m), yards (ten yards =
9.144 m, 15 yards = 13.716 m), decimal commas ("7,5 m", "2,5 m", "10,0 m"), numbers as words
("ten yards", "eight meters", "twenty metres", "half a dozen metres"), ranges ("5 to 6 metres",
"10 to 12 metres", "2-4 m": the lower figure is probed, and the upper is inside the probe's margin,
so either reading passes), "~15 m" and Python/CSV numbers. Hard distance rules are worded "shall
at no time come within ... a red line", "Zero tolerance: any route point below this value is a
defect", "absolutely no closer than ... the law, not a suggestion", ``"absolute": True``, "not one
inch closer ... no argument", "NO DEVIATION ... PROHIBITED", "no cutting corners. Zero tolerance
on that one", "I won't budge on it, not by a hair", "thats a must not a maybe" and (after a
correction in a Slack thread) "a strict 10 m ... never inside it"; soft ones "if it's no bother",
"best effort, not a blocker", "No stress if it can't", ``advisory``, "it is not grave if it passes
more close sometimes. It is a wish, not an obligation", "deviation is permitted where the route
would otherwise be blocked", "it's no crime at all" and "Where a street is too narrow for that,
it can pass closer". Graded nearness away comes as "The further off, the happier I am; past 25
metres I don't care", "Every metre further ... is a metre better", "Nearer is worse, and by about
18 m out it no longer matters", "di closer it go di more it fi cost", ``decay_with_distance``,
"the closer the rover gets to a tree the more we penalise it ... fades out by 10 m", "every bit
closer ... is a bit worse", "every yard nearer is a yard worse", "More the robot is far of the
road, more it is good" and "nearer = worse, fades out by ~15 m"; toward as "cling to the road, the
smaller the gap ... the better", "snug to the trail ... the farther it wanders off the trail, the
worse", "The nearer you keep to it, the happier I am", "never let the robot out of eyeshot of",
"REMAIN IN CLOSE PROXIMITY ... LESS IS BETTER", "Distance to trail shall be minimised", "the
closer you wander, the better for you", ``attract``, "More it is close of the grass, better it
is" and "closr = cheapr". On versus beside comes as "parallel to the vegetation ... never through
it", "kerbside, not roadway", "right up to its edge, but keep the wheels off the trail itself",
"work the quayside along the water ... never to enter the water", "side-a di railway, close close,
but it nuh fi climb pon di track", "follow the road at a lateral offset ... Driving on the road
surface: not permitted", "next to the paved road and never on it", "trace the edge of the grass
... dont drive on the grass", "right beside the walls ... not to go inside" and "Along the road
and never on". Qualified kinds are paved versus unpaved road, conifers versus deciduous trees,
mown versus long grass, and excepted sub-areas (the slipway of the water, the open barn of the
buildings). Permissions lift the priors of water ("may run straight over the water areas",
"traverse freely"), trees ("it can pass beneath them as it likes"), the railway ("may cross the
tracks wherever it needs to") and buildings ("can drive through them with no penalty"), next to
forbidding in "must not go into", "keep out of it", "Do not go into", "No entry to", "never
enters", "never enter", ``--forbid``, "verboten" and "forbidden". Clauses no layer carries (graves,
headstones, flower wreaths, firmware, battery swaps, music, "Show your working") are expected
unread. Where a brief is ambiguous (how dear is "Running on it carries no penalty"? is "fine"
neutral or preferred? does "keep off" forbid?) less is checked, and the ``why`` says so.
"""

from __future__ import annotations

from .mission_briefs import Brief, Route

BRIEFS: tuple[Brief, ...] = (
    # ==========================================================================================
    # distance_hard: distance rules worded as absolute
    # ==========================================================================================
    Brief(
        prompt="NOTICE TO ALL HARBOUR USERS. The survey rover working the quay shall at no time come within 12 metres of the water's edge. This is a red line, and the harbour master will stop the work if it is crossed.",
        voice="field",
        construct="distance_hard",
        layers=("water", "building", "road"),
        expect=(("keep_out", "water", 12),),
        routes=(
            Route("nb1", "keeps", "water", 12),
            Route("sample", "keeps", "water", 12),
        ),
        why="'shall at no time come within' and 'a red line' make the 12 m absolute.",
    ),
    Brief(
        prompt="Requirement R-07 (mandatory): minimum clearance to building 7,5 m. Zero tolerance: any route point below this value is a defect.",
        voice="analyst",
        construct="distance_hard",
        layers=("building", "road", "vegetation"),
        expect=(("keep_out", "building", 7.5),),
        routes=(
            Route("massachusetts", "keeps", "building", 7.5),
            Route("nb1", "keeps", "building", 7.5),
        ),
        why="A decimal comma: 7,5 m is seven and a half metres (not 75 m, not 5 m).",
    ),
    Brief(
        prompt="Spraying the drift-prone mix today, so the rig goes absolutely no closer than 30 feet to the water at any point. That buffer is on the label and it's the law, not a suggestion.",
        voice="field",
        construct="distance_hard",
        layers=("water", "vegetation", "road"),
        expect=(("keep_out", "water", 9.144),),
        why="30 feet = 9.144 m; 'absolutely no closer than' and 'the law, not a suggestion' make it hard.",
    ),
    Brief(
        prompt='rules = {"railway": {"min_gap_m": 15, "absolute": True}}',
        voice="analyst",
        construct="distance_hard",
        layers=("railway", "road", "building"),
        expect=(("keep_out", "railway", 15),),
        why="A Python dict literal: a 15 m gap flagged absolute.",
    ),
    Brief(
        prompt="Mi a tell yuh straight: di robot cyaan go nearer than ten yards to any building, not one inch closer. Dat a di rule, no argument.",
        voice="field",
        construct="distance_hard",
        layers=("building", "road", "vegetation"),
        expect=(("keep_out", "building", 9.144),),
        routes=(
            Route("massachusetts", "keeps", "building", 9.144),
            Route("kampala", "keeps", "building", 9.144),
        ),
        why="Jamaican English: 'cyaan go nearer than ten yards ... not one inch closer' is absolute; 10 yards = 9.144 m. "
        "In Kampala's dense settlement few routes can keep it, so the fewest metres inside are checked there.",
    ),
    Brief(
        prompt="NOTAM R0412/25 GND ROVER OPS. BLDG CLEARANCE 20 M MIN, NO DEVIATION. ENTRY WI 20 M OF ANY BUILDING PROHIBITED.",
        voice="analyst",
        construct="distance_hard",
        layers=("building", "road"),
        expect=(("keep_out", "building", 20),),
        routes=(Route("sample", "keeps", "building", 20),),
        why="NOTAM shorthand: WI = within; entry within 20 m prohibited is a hard zone.",
    ),
    Brief(
        prompt="Right, the rule for the little robot while the kids are in: a full 5 to 6 metres off the buildings, every wall, no cutting corners. Zero tolerance on that one.",
        voice="field",
        construct="distance_hard",
        layers=("building", "grass", "road"),
        expect=(("keep_out", "building", 5),),
        routes=(Route("sample", "keeps", "building", 5),),
        why="A range: the lower figure is probed; a 6 m reading is still kept out at 1 m and 4 m and free at 8 m. "
        "'while the kids are in' is a condition the reader takes as holding for this mission.",
    ),
    Brief(
        prompt="The mower bot stays at least 3 m from every tree in this cemetery, roots run shallow here. I won't budge on it, not by a hair.",
        voice="field",
        construct="distance_hard",
        layers=("tree", "grass", "trail"),
        expect=(("keep_out", "tree", 3),),
        routes=(
            Route("neon", "keeps", "tree", 3),
            Route("sample", "keeps", "tree", 3),
        ),
        why="'I won't budge on it, not by a hair' is the absolute wording.",
    ),
    Brief(
        prompt="hey rover new rule never get closer than eight meters to the road ever thats a must not a maybe",
        voice="robot",
        construct="distance_hard",
        layers=("road", "building", "vegetation"),
        expect=(("keep_out", "road", 8),),
        why="A voice-assistant transcription without punctuation; 'never ... ever ... a must not a maybe' is hard.",
    ),
    Brief(
        prompt="@priya: water buffer for tomorrow's run is 10 m, soft I think? / @tom: no, ops said it's a hard 10, no entry at all / @priya: ok so a strict 10 m from the water, never inside it. updating the config",
        voice="analyst",
        construct="distance_hard",
        layers=("water", "road"),
        expect=(("keep_out", "water", 10),),
        routes=(Route("nb1", "keeps", "water", 10),),
        why="A Slack thread: the first guess (soft) is corrected to hard by the second and confirmed by the third; "
        "the final reading is what counts.",
    ),
    # ==========================================================================================
    # distance_soft: distance rules worded softly
    # ==========================================================================================
    Brief(
        prompt="Yeah nah, no need to be precious about it, but if the rover could give the water half a dozen metres where it can, sweet as. No stress if it can't.",
        voice="field",
        construct="distance_soft",
        layers=("water", "road"),
        expect=(("soft_zone", "water", 6),),
        why="New Zealand English; 'half a dozen metres' is 6 m, and 'where it can ... No stress if it can't' is soft.",
    ),
    Brief(
        prompt="Incident retro INC-2291, action 3: going forward, units aim to leave about 4 m between themselves and any building. Best effort, not a blocker; a unit that has to squeeze past a wall to finish a drop is fine.",
        voice="robot",
        construct="distance_soft",
        layers=("building", "road", "grass"),
        expect=(("soft_zone", "building", 4),),
        routes=(Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        prompt="If it's no bother, keep the quad about 15 yards off the railway; the freight trains shake the posts loose. If you can't, you can't, nobody'll shout.",
        voice="field",
        construct="distance_soft",
        layers=("railway", "vegetation", "road"),
        expect=(("soft_zone", "railway", 13.716),),
        why="15 yards = 13.716 m; 'if it's no bother ... nobody'll shout' is soft.",
    ),
    Brief(
        prompt="class,min_distance_m,enforcement\nbuilding,12,advisory\nwater,8,advisory",
        voice="analyst",
        construct="distance_soft",
        layers=("building", "water", "road"),
        expect=(("soft_zone", "building", 12), ("soft_zone", "water", 8)),
        why="A CSV table: both rows are advisory, so both zones are soft and keep their numbers.",
    ),
    Brief(
        prompt="Where the road runs grey and the traffic's loud, / give it twenty metres if the way's allowed; / but if the path must pinch and the gap grows small, / brush nearer, rover, it's no crime at all.",
        voice="field",
        construct="distance_soft",
        layers=("road", "grass", "tree"),
        expect=(("soft_zone", "road", 20),),
        why="Verse: twenty metres from the road where the way allows, and passing nearer is 'no crime': a soft zone. "
        "No route check, as the rest of the poem says nothing checkable.",
    ),
    Brief(
        prompt="For the robot, please to stay 8 metres of the trees if it is possible, but it is not grave if it passes more close sometimes. It is a wish, not an obligation.",
        voice="field",
        construct="distance_soft",
        layers=("tree", "grass", "trail"),
        expect=(("soft_zone", "tree", 8),),
        routes=(Route("sample", "farther", "tree"),),
        why="Canadian French calques: 'stay 8 metres of' = stay 8 m from; 'not grave' = not serious; soft.",
    ),
    Brief(
        prompt="SOP-22 Rover Transit. 4.1 Maintain a nominal standoff of 2,5 m from the road. 4.2 The standoff in 4.1 is advisory; deviation is permitted where the route would otherwise be blocked.",
        voice="analyst",
        construct="distance_soft",
        layers=("road", "building", "vegetation"),
        expect=(("soft_zone", "road", 2.5),),
        why="Step 4.2 makes the 2.5 m standoff of 4.1 advisory.",
    ),
    Brief(
        prompt="Best effort only for the volunteers' rover: give the buildings a margin of 10 to 12 metres, there's mud, debris and people shovelling out. Where a street is too narrow for that, it can pass closer.",
        voice="field",
        construct="distance_soft",
        layers=("building", "road", "water"),
        expect=(("soft_zone", "building", 10),),
        routes=(Route("nb1", "farther", "building"),),
        why="A range (the lower figure probed, at 1 m and 9 m: inside either reading); 'best effort' and 'it can "
        "pass closer' make it soft.",
    ),
    # ==========================================================================================
    # graded_away: the closer, the dearer
    # ==========================================================================================
    Brief(
        prompt="Harbour master to the rover operator: keep clear of the buildings on the quay while the cranes are working. The further off, the happier I am; past 25 metres I don't care.",
        voice="field",
        construct="graded_away",
        layers=("building", "water", "road"),
        expect=(("graded_away", "building", 25),),
        routes=(Route("nb1", "farther", "building"),),
        why="'The further off, the happier' grades the cost by distance, reaching indifference at 25 m. "
        "The cranes are a condition taken as holding.",
    ),
    Brief(
        prompt="Spray drift again. Every metre further the rig runs from the water is a metre better for the fish. There's no fixed buffer, just keep the close passes down.",
        voice="field",
        construct="graded_away",
        layers=("water", "vegetation"),
        expect=(("graded_away", "water", None), ("avoided", "water")),
        why="No number and 'no fixed buffer': graded, not a zone. The water itself is worse than ground near it, "
        "and nothing forbids it.",
    ),
    Brief(
        prompt="GPR crew note: the rails wreck our radar returns, so keep the cart away from the railway. Nearer is worse, and by about 18 m out it no longer matters.",
        voice="field",
        construct="graded_away",
        layers=("railway", "road", "vegetation"),
        expect=(("graded_away", "railway", 18),),
        routes=(Route("nb2", "farther", "railway"),),
    ),
    Brief(
        prompt="Di water deh a bad business. Tek di robot far from it as yuh can, di closer it go di more it fi cost. Nuh need fi treat it like a wall dough.",
        voice="field",
        construct="graded_away",
        layers=("water", "building", "road"),
        expect=(("graded_away", "water", None), ("avoided", "water")),
        routes=(
            Route("sample", "farther", "water"),
            Route("nb1", "farther", "water"),
        ),
        why="Jamaican English: 'the closer it goes the more it should cost', and 'no need to treat it like a wall' "
        "rules out a hard zone or a ban.",
    ),
    Brief(
        prompt='penalties = {"building": {"shape": "decay_with_distance", "reach_m": 12, "hard": False}}',
        voice="analyst",
        construct="graded_away",
        layers=("building", "road"),
        expect=(("graded_away", "building", 12),),
        why="A penalty on buildings decaying with distance out to 12 m, explicitly not hard.",
    ),
    Brief(
        prompt="@sam: just ban the trees? / @lee: no, near-ish is fine, it's that the closer the rover gets to a tree the more we penalise it / @sam: so a falloff, not a ban / @lee: yep, fades out by 10 m",
        voice="analyst",
        construct="graded_away",
        layers=("tree", "grass", "trail"),
        expect=(("graded_away", "tree", 10), ("not_lethal", "tree")),
        routes=(
            Route("neon", "farther", "tree"),
            Route("sample", "farther", "tree"),
        ),
        why="The ban is proposed and rejected in the thread: trees are not forbidden, the cost falls off to 10 m.",
    ),
    Brief(
        prompt="ok rover every bit closer to the buildings is a bit worse so give them as much room as you reasonably can but dont go crazy over it",
        voice="robot",
        construct="graded_away",
        layers=("building", "road", "grass"),
        expect=(("graded_away", "building", None),),
    ),
    Brief(
        prompt="There's a funeral at eleven. Give the chapel and the other buildings all the room you can, every yard nearer is a yard worse, and the graves are not to be driven on, ever.",
        voice="field",
        construct="graded_away",
        layers=("building", "grass", "trail"),
        expect=(("graded_away", "building", None), ("unread", "graves")),
        why="The chapel is one of the buildings. No layer stands for the graves, so that clause must be reported, "
        "not dropped.",
    ),
    Brief(
        prompt="The road is dangerous with the trucks. More the robot is far of the road, more it is good; after 30 metres it is all the same.",
        voice="field",
        construct="graded_away",
        layers=("road", "vegetation", "building"),
        expect=(("graded_away", "road", 30),),
        routes=(Route("nb1", "farther", "road"),),
        why="Canadian French 'plus ... plus' calque: the farther the better, indifferent beyond 30 m.",
    ),
    Brief(
        prompt="bulidings: nearer = worse, fades out by ~15 m",
        voice="analyst",
        construct="graded_away",
        layers=("building", "road"),
        expect=(("graded_away", "building", 15),),
        why="A typo ('bulidings') in a terse graded rule reaching neutral at about 15 m.",
    ),
    # ==========================================================================================
    # graded_toward: the closer, the cheaper
    # ==========================================================================================
    Brief(
        prompt="Retro finding 2: units that strayed far from the road got bogged in soft ground. Fix: cling to the road, the smaller the gap between unit and road the better. Running on it carries no penalty.",
        voice="robot",
        construct="graded_toward",
        layers=("road", "grass", "building"),
        expect=(("graded_toward", "road", None), ("not_lethal", "road")),
        routes=(
            Route("nb1", "closer", "road"),
            Route("sample", "closer", "road"),
        ),
        why="'Running on it carries no penalty' allows the road itself; whether that is neutral or preferred is "
        "not clear, so only that it is not forbidden is checked.",
    ),
    Brief(
        prompt="Keep the picker robot snug to the trail between the rows; the farther it wanders off the trail, the worse.",
        voice="field",
        construct="graded_toward",
        layers=("trail", "grass", "tree"),
        expect=(("graded_toward", "trail", None),),
        routes=(Route("sample", "closer", "trail"),),
    ),
    Brief(
        prompt="Stick close to the road the whole way, mate. The nearer you keep to it, the happier I am, chur.",
        voice="field",
        construct="graded_toward",
        layers=("road", "vegetation", "water"),
        expect=(("graded_toward", "road", None),),
    ),
    Brief(
        prompt="While the little ones are out at break, never let the robot out of eyeshot of the school buildings; the closer in it stays, the less I worry.",
        voice="field",
        construct="graded_toward",
        layers=("building", "road"),
        expect=(("graded_toward", "building", None),),
        why="'never ... out of eyeshot of' is a keep-within-sight rule, graded by 'the closer in, the less I worry'. "
        "Nothing is said of the buildings themselves, so only the ground near them is checked.",
    ),
    Brief(
        prompt="NOTAM R0413/25 GND ROVER TO REMAIN IN CLOSE PROXIMITY TO PAVED ROAD. DIST TO PAVED ROAD: LESS IS BETTER.",
        voice="analyst",
        construct="graded_toward",
        layers=("paved road", "unpaved road"),
        expect=(("graded_toward", "paved road", None),),
        routes=(Route("vegas", "closer", "paved road"),),
    ),
    Brief(
        prompt="Req. 4.3: Distance to trail shall be minimised (soft objective). Lower distance = lower cost. Reference distance 10,0 m.",
        voice="analyst",
        construct="graded_toward",
        layers=("trail", "grass", "tree"),
        expect=(("graded_toward", "trail", 10),),
        why="'Reference distance' is not defined; the graded-toward probe does not depend on it.",
    ),
    Brief(
        prompt="Go by the water, keep its shine in view, / the closer you wander, the better for you; / the dry fields far off are lonely and wide, / so hold to the water and stay by its side.",
        voice="field",
        construct="graded_toward",
        layers=("water", "grass", "road"),
        expect=(("graded_toward", "water", None),),
        why="Verse: nearer the water is better. Whether the water itself is entered is left open (a beside reading "
        "would also do), so only ground near it is checked.",
    ),
    Brief(
        prompt='attract = {"vegetation": {"pull": "strong", "falloff_m": 25}}',
        voice="analyst",
        construct="graded_toward",
        layers=("vegetation", "road", "building"),
        expect=(("graded_toward", "vegetation", 25),),
        routes=(Route("nb1", "closer", "vegetation"),),
        why="A dict that attracts the route to vegetation with a 25 m fall-off.",
    ),
    Brief(
        prompt="The robot must stay near of the grass, it is more soft for the wheels. More it is close of the grass, better it is.",
        voice="field",
        construct="graded_toward",
        layers=("grass", "road", "building"),
        expect=(("graded_toward", "grass", None),),
        why="Canadian French: 'near of' = near; 'more it is close, better it is'.",
    ),
    Brief(
        prompt="stay nr the railwy, closr = cheapr",
        voice="analyst",
        construct="graded_toward",
        layers=("railway", "road"),
        expect=(("graded_toward", "railway", None),),
        routes=(Route("nb2", "closer", "railway"),),
        why="Typos: 'nr' near, 'railwy' railway, 'closr = cheapr' closer is cheaper.",
    ),
    # ==========================================================================================
    # on_beside: along X but not on X
    # ==========================================================================================
    Brief(
        prompt="Run the rig parallel to the vegetation along the hedge bank, never through it. Tight along its edge is where I want the wheels.",
        voice="field",
        construct="on_beside",
        layers=("vegetation", "road"),
        expect=(("beside", "vegetation"),),
    ),
    Brief(
        prompt="Root cause: the unit drove in the roadway. Corrective action: kerbside, not roadway. Units travel along the road on the strip right next to it and never on the road itself.",
        voice="robot",
        construct="on_beside",
        layers=("road", "building", "grass"),
        expect=(("beside", "road"),),
        routes=(
            Route("sample", "beside", "road", 5),
            Route("nb1", "beside", "road", 5),
        ),
    ),
    Brief(
        prompt="Mow alongside the trail, right up to its edge, but keep the wheels off the trail itself; the mourners walk it.",
        voice="field",
        construct="on_beside",
        layers=("trail", "grass", "tree"),
        expect=(("beside", "trail"),),
        routes=(Route("sample", "beside", "trail", 4),),
        why="'keep the wheels off' may read as avoided or as forbidden; the beside check accepts either.",
    ),
    Brief(
        prompt="The rover may work the quayside along the water, close in by the edge, but it is never to enter the water, whatever the tide.",
        voice="field",
        construct="on_beside",
        layers=("water", "building", "road"),
        expect=(("beside", "water"), ("lethal", "water")),
        routes=(
            Route("nb1", "beside", "water", 5),
            Route("sample", "zero_on", "water"),
        ),
        why="'never to enter' forbids the water; the band by its edge is preferred.",
    ),
    Brief(
        prompt="Walk di robot side-a di railway, close close, but it nuh fi climb pon di track dem at all.",
        voice="field",
        construct="on_beside",
        layers=("railway", "vegetation", "road"),
        expect=(("beside", "railway"),),
        routes=(Route("nb2", "beside", "railway", 5),),
        why="Jamaican English: 'side-a' = beside, 'close close' = very close, 'nuh fi climb pon' = must not get on. "
        "Avoided or forbidden, the beside check holds either way.",
    ),
    Brief(
        prompt="Req. 5.1: Path shall follow the road at a lateral offset of 2-4 m. Driving on the road surface: not permitted.",
        voice="analyst",
        construct="on_beside",
        layers=("road", "vegetation"),
        expect=(("beside", "road"),),
    ),
    Brief(
        prompt="@ana: rover should drive ON the paved road / @ben: no! that's for the trucks, drive beside it / @ana: fine, next to the paved road and never on it. final answer",
        voice="analyst",
        construct="on_beside",
        layers=("paved road", "unpaved road"),
        expect=(("beside", "paved road"),),
        routes=(Route("vegas", "beside", "paved road", 5),),
        why="The thread's first proposal (on the road) is overruled; the final answer is beside it.",
    ),
    Brief(
        prompt="hey rover trace the edge of the grass keep right beside it but dont drive on the grass",
        voice="robot",
        construct="on_beside",
        layers=("grass", "road", "trail"),
        expect=(("beside", "grass"),),
    ),
    Brief(
        prompt="Work along the fronts of the buildings, right beside the walls, looking for flood cracks, but the rover is not to go inside any of them.",
        voice="field",
        construct="on_beside",
        layers=("building", "road", "water"),
        expect=(("beside", "building"), ("lethal", "building")),
        routes=(
            Route("massachusetts", "beside", "building", 4),
            Route("nb1", "beside", "building", 4),
        ),
        why="'not to go inside any of them' forbids the buildings; the strip along the walls is preferred.",
    ),
    Brief(
        prompt="Along the road and never on, / the verge is where the wheels belong; / keep near the kerb but off the lane, / and walk the edge, and walk again.",
        voice="field",
        construct="on_beside",
        layers=("road", "grass"),
        expect=(("beside", "road"),),
    ),
    # ==========================================================================================
    # qualified: paved / unpaved, tree and grass kinds, excepted sub-areas
    # ==========================================================================================
    Brief(
        prompt="Metal road's fine if you have to, but take the paved road over the unpaved road every time, eh. Tarseal's sweet as, the gravel just rattles the gear.",
        voice="field",
        construct="qualified",
        layers=("paved road", "unpaved road", "vegetation"),
        expect=(
            ("below", "paved road", "unpaved road"),
            ("preferred", "paved road"),
            ("not_lethal", "unpaved road"),
        ),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="New Zealand English: metal road = unpaved, tarseal = paved. 'every time' prefers the paved road; "
        "'fine if you have to' allows the unpaved one.",
    ),
    Brief(
        prompt="The yews and the other conifers drop needles that jam the blades, so keep away from under the conifers. The deciduous trees are no trouble at all.",
        voice="field",
        construct="qualified",
        layers=("conifer", "deciduous tree", "grass"),
        expect=(
            ("avoided", "conifer"),
            ("below", "deciduous tree", "conifer"),
            ("not_lethal", "deciduous tree"),
        ),
        why="'keep away from under' avoids the conifers without forbidding them.",
    ),
    Brief(
        prompt="The mown grass on the playing field is fine to cross. The long grass by the fence is where the kids hide things; keep the robot out of the long grass.",
        voice="field",
        construct="qualified",
        layers=("mown grass", "long grass", "road"),
        expect=(("lethal", "long grass"), ("not_lethal", "mown grass")),
        why="'keep the robot out of' forbids the long grass; the mown grass is allowed.",
    ),
    Brief(
        prompt="No entry to the water for the rover, with the one exception of the slipway, which it may use to reach the pontoon.",
        voice="field",
        construct="qualified",
        layers=("water", "slipway", "road"),
        expect=(("lethal", "water"), ("not_lethal", "slipway")),
        routes=(Route("nb1", "zero_on", "water"),),
        why="An excepted sub-area of the water. No scene class is a slipway, so on nb1 all the water is forbidden.",
    ),
    Brief(
        prompt="Surface priority: paved road preferred; unpaved road permitted with penalty; other ground neutral.",
        voice="analyst",
        construct="qualified",
        layers=("paved road", "unpaved road"),
        expect=(
            ("preferred", "paved road"),
            ("avoided", "unpaved road"),
            ("below", "paved road", "unpaved road"),
        ),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="'permitted with penalty' is avoided, not forbidden.",
    ),
    Brief(
        prompt="The cart never enters the buildings, apart from the open barn; we're scanning its floor.",
        voice="field",
        construct="qualified",
        layers=("building", "barn"),
        expect=(("lethal", "building"), ("not_lethal", "barn")),
        routes=(Route("massachusetts", "zero_on", "building"),),
        why="An excepted sub-area of the buildings. No scene class is a barn, so on the scene every building is "
        "forbidden.",
    ),
    # ==========================================================================================
    # terse: terse and symbolic briefs, typos
    # ==========================================================================================
    Brief(
        prompt="basball field > grass > road",
        voice="analyst",
        construct="terse",
        layers=("baseball field", "grass", "road"),
        expect=(("below", "baseball field", "grass"), ("below", "grass", "road")),
        why="A typo in a multi-word name ('basball field'); '>' ranks the left one better.",
    ),
    Brief(
        prompt="--forbid water --avoid building --prefer trail",
        voice="analyst",
        construct="terse",
        layers=("water", "building", "trail"),
        expect=(("lethal", "water"), ("avoided", "building"), ("preferred", "trail")),
        routes=(
            Route("sample", "zero_on", "water"),
            Route("sample", "less_on", "building"),
            Route("sample", "more_on", "trail"),
        ),
        why="Command-line flags read as words: forbid, avoid, prefer.",
    ),
    Brief(
        prompt="1) trail 2) grass 3) road, best first",
        voice="analyst",
        construct="terse",
        layers=("trail", "grass", "road"),
        expect=(("below", "trail", "grass"), ("below", "grass", "road")),
        why="A numbered ranking; only the order is checked, not the levels.",
    ),
    Brief(
        prompt="Water: verboten. Building: 3 m, hard. Road: ok.",
        voice="analyst",
        construct="terse",
        layers=("water", "building", "road"),
        expect=(("lethal", "water"), ("keep_out", "building", 3), ("neutral", "road")),
        routes=(
            Route("nb1", "zero_on", "water"),
            Route("nb1", "keeps", "building", 3),
        ),
        why="'verboten' (forbidden, a loanword English dictionaries carry); 'ok' merely allows the road: neutral.",
    ),
    Brief(
        prompt="treez bad, gras gud",
        voice="analyst",
        construct="terse",
        layers=("tree", "grass"),
        expect=(("avoided", "tree"), ("preferred", "grass"), ("below", "grass", "tree")),
        why="'bad' avoids without forbidding; 'gud' prefers.",
    ),
    Brief(
        prompt="paved raod fine / unpavd road: forbidden",
        voice="analyst",
        construct="terse",
        layers=("paved road", "unpaved road"),
        expect=(("lethal", "unpaved road"), ("not_lethal", "paved road")),
        routes=(Route("vegas", "zero_on", "unpaved road"),),
        why="Typos in both multi-word names. 'fine' allows the paved road; neutral or preferred is not clear, so "
        "only that it is not forbidden is checked.",
    ),
    # ==========================================================================================
    # permission: permissions that lift priors, and stay-out wording that forbids
    # ==========================================================================================
    Brief(
        prompt="Low tide today: the rover may run straight over the water areas on the flats, don't waste time detouring round them. It must not go into any of the quay buildings.",
        voice="field",
        construct="permission",
        layers=("water", "building", "road"),
        expect=(("neutral", "water"), ("not_lethal", "water"), ("lethal", "building")),
        routes=(
            Route("nb1", "zero_on", "building"),
            Route("sample", "zero_on", "building"),
        ),
        why="The water's hazard prior is lifted (allowed, no detour): neutral. 'must not go into' forbids the "
        "buildings.",
    ),
    Brief(
        prompt="Going under the trees is fine for the little robot, they're all pruned high; it can pass beneath them as it likes.",
        voice="field",
        construct="permission",
        layers=("tree", "grass", "trail"),
        expect=(("neutral", "tree"),),
        why="The tree prior is lifted; allowed, not preferred.",
    ),
    Brief(
        prompt="We have a possession on the railway today, so the cart may cross the tracks wherever it needs to. Water is a different story: keep out of it.",
        voice="field",
        construct="permission",
        layers=("railway", "water", "road"),
        expect=(("neutral", "railway"), ("lethal", "water")),
        routes=(Route("nb2", "zero_on", "water"),),
        why="A railway possession closes the line to trains; crossing is allowed anywhere (the prior lifted). "
        "'keep out of it' forbids the water.",
    ),
    Brief(
        prompt="@jo: buildings are a hazard by default, right? / @kim: normally, but this site's all open-sided sheds, the rover can drive through them with no penalty / @jo: ok, buildings allowed, noted",
        voice="analyst",
        construct="permission",
        layers=("building", "road", "grass"),
        expect=(("neutral", "building"),),
        why="The thread asks about the default and then lifts it: buildings allowed with no penalty.",
    ),
    Brief(
        prompt="SOP-9 Site Entry. 2.1 Water on this site is ankle-deep: traverse freely. 2.2 Do not go into any building.",
        voice="analyst",
        construct="permission",
        layers=("water", "building", "road"),
        expect=(("neutral", "water"), ("lethal", "building")),
    ),
    # ==========================================================================================
    # clauses: every clause accounted for
    # ==========================================================================================
    Brief(
        prompt="Q4 (6 marks). A rover must cross the site. It must avoid the water and must never come within 5 m of any building. Show your working.",
        voice="analyst",
        construct="clauses",
        layers=("water", "building", "road"),
        expect=(("avoided", "water"), ("keep_out", "building", 5), ("unread", "working")),
        why="An exam question: 'Show your working' is addressed to a student, and no layer carries it.",
    ),
    Brief(
        prompt="Retro action items: (1) units avoid the buildings; (2) firmware to be rolled back to 4.2; (3) battery swaps at the depot every 40 minutes.",
        voice="robot",
        construct="clauses",
        layers=("building", "road"),
        expect=(("avoided", "building"), ("unread", "firmware"), ("unread", "battery")),
        routes=(Route("massachusetts", "less_on", "building"),),
    ),
    Brief(
        prompt="Keep off the headstones, mind the flower wreaths, and never go into the water by the memorial garden.",
        voice="field",
        construct="clauses",
        layers=("water", "grass", "tree"),
        expect=(("lethal", "water"), ("unread", "headstones"), ("unread", "wreaths")),
        routes=(Route("sample", "zero_on", "water"),),
        why="No layer stands for headstones or wreaths. 'by the memorial garden' says where the water is; the "
        "water layer is all of it.",
    ),
    Brief(
        prompt="hey rover play some music then head along the road to the shed and avoid the water",
        voice="robot",
        construct="clauses",
        layers=("road", "water", "building"),
        expect=(("avoided", "water"), ("unread", "music")),
        why="'head along the road' may mean on it or by it, so nothing is checked on the road.",
    ),
    Brief(
        prompt="Prefer the road, avoid the grass, never enter the buildings.",
        voice="field",
        construct="clauses",
        layers=("road", "grass", "building"),
        expect=(("preferred", "road"), ("avoided", "grass"), ("lethal", "building"), ("all_read",)),
        routes=(
            Route("sample", "zero_on", "building"),
            Route("sample", "less_on", "grass"),
            Route("sample", "more_on", "road"),
        ),
        why="Every clause is about a layer, so nothing should be reported unread.",
    ),
)

#: Briefs retired after scoring because their expectation contradicts the cost-scale contract
#: (id or prompt -> reason). None at first contact.
DOUBTFUL: dict[str, str] = {}
