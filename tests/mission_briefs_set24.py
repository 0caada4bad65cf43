"""Mission briefs, set 24: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench, the docs or the briefs of earlier sets: only the contract
(``tests/mission_briefs.py`` and its format test ``tests/test_mission_briefs.py``), the scene index
(``../shared/scenes/INDEX.md`` and the scenes' ``classes.json``) and the first 45 lines of set 23
(for the layout) were read. It is scored once, at first contact, with
``bench/mission_briefs_report.py --set 24``; that figure is the one that counts, and the set is
not edited afterwards to make the interpreter pass.

The voices are a drone pilot's NOTAM-style brief (capitals, lettered items), a construction site
safety officer, a lawyer's easement clause ("the Grantee shall not"), a wildlife biologist's field
protocol, a search-and-rescue incident commander on the radio (callsigns, "over", digits spoken
one at a time: "two-zero"), a non-native speaker (dropped articles, odd word order), a golf course
superintendent, YAML, INI and JSON configuration fragments, a ROS-style parameter block, an
insurance loss adjuster, a farm manager's WhatsApp voice note transcribed, a heritage officer's
advice, a Scottish speaker ("the burn", "dinnae fash"), a game designer writing pathfinding rules,
a snow-plough dispatcher, an environmental-impact mitigation measure, a film location scout, an
Australian speaker ("a wide berth", "no worries"), an Indian-English speaker ("kindly", "pucca"
and "kaccha" roads), a tweet-length note with emoji, a numbered SOP with sub-clauses (1.a, 1.b),
an accessibility review and a tour guide. Units come in metres, feet, yards and radio digits, and
once as "a couple of car lengths" (no number, so no metre figure is expected). Orderings come as
"prefer a > b > c", ``cost(a) > cost(b)`` and ratios ("3x worse"); permissions as "may pass and
repass", "no worries", "authorised" and their negations ("NOT authorised", "not permitted");
exceptions as "with the exception of"; classes under regional or trade words (tarmac, metalled,
gravel track, cart path, burn, scrub, bush) and one sub-class no layer carries (coniferous trees).
Rules that hang on what no layer can carry (visibility, snow, wind, the afternoon, night, how many
cars are about) or name things no layer stands for (pylons, a substation, the greens) are expected
unread.

Each construct has seven or eight briefs; route checks are given wherever the scene holds the
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
YD = 0.9144

#: Briefs retired after scoring because their expectation contradicts the contract (none yet).
DOUBTFUL: dict[str, str] = {}

BRIEFS: list[Brief] = [
    # ==========================================================================================
    # distance_hard: absolute distance rules, a hard zone of the stated metres
    # ==========================================================================================
    Brief(
        prompt=(
            "UAS OPS BRIEF // LOW-LEVEL TRANSIT\n"
            "A) LATERAL SEPARATION FROM ALL BUILDINGS: 50 FT MINIMUM, NO EXCEPTIONS.\n"
            "B) OVERFLIGHT OF WATER PERMITTED.\n"
            "C) RMK: LAUNCH FROM ROAD, RECOVER AT BASEBALL FIELD."
        ),
        voice="robot",
        construct="distance_hard",
        layers=SAMPLE,
        expect=(
            ("keep_out", "building", 50 * FT),
            ("neutral", "water"),
            ("not_lethal", "water"),
        ),
        routes=(Route("sample", "keeps", "building", 50 * FT),),
        why="'minimum, no exceptions' is absolute; 50 ft = 15.24 m; 'permitted' lifts water's prior to neutral",
    ),
    Brief(
        prompt=(
            "Site safety rule 4 for the survey rover: it must never come within 8 metres of the "
            "building under construction, full stop. The exclusion zone is marked with Heras "
            "fencing. Everywhere else on site it can go where it likes."
        ),
        voice="field",
        construct="distance_hard",
        layers=BUILDING,
        expect=(("keep_out", "building", 8),),
        routes=(
            Route("massachusetts", "keeps", "building", 8),
            Route("kampala", "keeps", "building", 8),
        ),
    ),
    Brief(
        prompt=(
            "2.3 The Grantee's vehicles shall at no time be operated within thirty (30) feet of any "
            "dwelling or other building on the Servient Land, and shall not enter any watercourse "
            "thereon."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=SAMPLE,
        expect=(
            ("keep_out", "building", 30 * FT),
            ("lethal", "water"),
        ),
        routes=(
            Route("sample", "keeps", "building", 30 * FT),
            Route("sample", "zero_on", "water"),
        ),
        why=(
            "'shall at no time ... within' is absolute (30 ft = 9.144 m); 'shall not enter any "
            "watercourse' is the lawyer's 'must not enter', and a watercourse is the water layer"
        ),
    ),
    Brief(
        prompt=(
            "Protocol 7.2 (nesting season). The UGV shall maintain a minimum buffer of 25 m from all "
            "open water; this buffer is mandatory under the licence. No other restrictions apply to "
            "vegetation."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=NB,
        expect=(
            ("keep_out", "water", 25),
            ("neutral", "vegetation"),
        ),
        routes=(
            Route("nb1", "keeps", "water", 25),
            Route("nb2", "keeps", "water", 25),
        ),
        why="'no other restrictions apply to vegetation' states vegetation is merely allowed: neutral",
    ),
    Brief(
        prompt=(
            "Ground Team Two, this is Incident Command. Be advised the railway line is live. You "
            "are to hold a minimum of two-zero metres off the tracks, I say again, two-zero metres. "
            "Stay out of the water. How copy, over."
        ),
        voice="field",
        construct="distance_hard",
        layers=NB,
        expect=(
            ("keep_out", "railway", 20),
            ("lethal", "water"),
        ),
        routes=(
            Route("nb2", "keeps", "railway", 20),
            Route("nb1", "zero_on", "water"),
            Route("nb2", "zero_on", "water"),
        ),
        why="radio digits 'two-zero' are 20; 'you are to hold a minimum' is an order, so hard",
    ),
    Brief(
        prompt=("Robot must not go more near than 12 meter to the trees, this is strict rule. Grass and road is ok."),
        voice="robot",
        construct="distance_hard",
        layers=SAMPLE,
        expect=(
            ("keep_out", "tree", 12),
            ("neutral", "grass"),
            ("neutral", "road"),
        ),
        routes=(Route("sample", "keeps", "tree", 12),),
    ),
    Brief(
        prompt=(
            "Mower bot, overnight run: never closer than 15 yards to the clubhouse or any other "
            "building. Stay off the greens (we don't have those mapped, I know). Fairway grass is all "
            "fine."
        ),
        voice="field",
        construct="distance_hard",
        layers=SAMPLE,
        expect=(
            ("keep_out", "building", 15 * YD),
            ("neutral", "grass"),
            ("unread", "green"),
        ),
        routes=(Route("sample", "keeps", "building", 15 * YD),),
        why=(
            "15 yd = 13.716 m; the greens are a part of the grass no layer marks, so that rule "
            "cannot be carried and must be reported rather than applied to all grass"
        ),
    ),
    Brief(
        prompt=(
            "constraints:\n"
            "  water:\n"
            "    min_clearance_ft: 40   # hard limit, do not violate\n"
            "  road:\n"
            "    allowed: true\n"
        ),
        voice="robot",
        construct="distance_hard",
        layers=SAMPLE,
        expect=(
            ("keep_out", "water", 40 * FT),
            ("neutral", "road"),
        ),
        routes=(Route("sample", "keeps", "water", 40 * FT),),
        why="the unit is in the key (ft): 40 ft = 12.192 m; the comment makes it hard",
    ),
    # ==========================================================================================
    # distance_soft: softly worded distance rules, a soft zone with the number kept
    # ==========================================================================================
    Brief(
        prompt=(
            "For the subsidence survey the rover should, where reasonably practicable, keep about "
            "6 m clear of the insured buildings. This is guidance rather than a condition, and "
            "brief approaches are acceptable if the site layout demands it."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=BUILDING,
        expect=(("soft_zone", "building", 6),),
        routes=(Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        prompt=(
            "hiya it's Dave so for the sprayer robot tomorrow try and give the water a bit of room "
            "yeah like ideally ten metres or so off the pond edge doesn't have to be exact if it has "
            "to cut a bit closer that's fine cheers"
        ),
        voice="field",
        construct="distance_soft",
        layers=SAMPLE,
        expect=(("soft_zone", "water", 10),),
        routes=(Route("sample", "farther", "water"),),
    ),
    Brief(
        prompt=(
            "Heritage advice: to protect the root zones of the veteran trees, the survey robot ought "
            "to keep roughly 5 m back from the tree crowns where it can. Closer passes are tolerable "
            "when unavoidable."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=TREE,
        expect=(("soft_zone", "tree", 5),),
        routes=(Route("neon", "farther", "tree"),),
    ),
    Brief(
        prompt=("[standoff]\nroad_m = 4\nroad_strict = no\nrailway_m = 15\nrailway_strict = yes\n"),
        voice="robot",
        construct="distance_soft",
        layers=NB,
        expect=(
            ("soft_zone", "road", 4),
            ("keep_out", "railway", 15),
        ),
        routes=(
            Route("nb1", "farther", "road"),
            Route("nb2", "keeps", "railway", 15),
        ),
        why=(
            "the config marks the road standoff not strict (soft) and the railway one strict "
            "(hard); 'road_strict = no' qualifies the standoff and does not forbid the road"
        ),
    ),
    Brief(
        prompt=(
            "Och, just keep the wee machine a fair bit back fae the burn, maybe fifteen metres if ye "
            "can manage it, but dinnae fash if the path takes ye closer."
        ),
        voice="field",
        construct="distance_soft",
        layers=SAMPLE,
        expect=(("soft_zone", "water", 15),),
        routes=(Route("sample", "farther", "water"),),
        why="a burn is Scots for a stream (the water layer); 'if ye can manage it' and 'dinnae fash' make it soft",
    ),
    Brief(
        prompt=(
            "NPC pathing: add a soft penalty for tiles within 3 m of a building (NPCs should prefer "
            "not to hug walls, but they can if it's the only way through). Roads and grass cost the "
            "same as open ground."
        ),
        voice="robot",
        construct="distance_soft",
        layers=SAMPLE,
        expect=(
            ("soft_zone", "building", 3),
            ("neutral", "road"),
            ("neutral", "grass"),
        ),
        routes=(Route("sample", "farther", "building"),),
    ),
    Brief(
        prompt=(
            "Dispatch to unit 14: when you clear the lot, preferably stay a couple of car lengths off "
            "the buildings, give 'em some room for the drifts. If the wind's up, forget it and do "
            "what you can."
        ),
        voice="field",
        construct="distance_soft",
        layers=BUILDING,
        expect=(
            ("soft_zone", "building", None),
            ("unread", "wind"),
        ),
        routes=(Route("massachusetts", "farther", "building"),),
        why=(
            "'a couple of car lengths' gives no number, so no metre figure is expected; the wind "
            "clause hangs on weather no layer carries"
        ),
    ),
    Brief(
        prompt=(
            "Mitigation measure M4 (advisory): survey vehicles should, as far as possible, remain at "
            "least 30 m from the railway corridor. Where this cannot be achieved, reduced separation "
            "is acceptable."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "railway", 30),),
        routes=(Route("nb2", "farther", "railway"),),
        why="'at least 30 m' is softened by 'advisory', 'as far as possible' and the acceptance of less",
    ),
    # ==========================================================================================
    # graded_away: the nearer, the dearer
    # ==========================================================================================
    Brief(
        prompt=(
            "Scout notes for the camera dolly bot: the further it stays from the water, the better. "
            "Don't want reflections of the rig in the lake shots."
        ),
        voice="field",
        construct="graded_away",
        layers=SAMPLE,
        expect=(("graded_away", "water", None),),
        routes=(Route("sample", "farther", "water"),),
    ),
    Brief(
        prompt=(
            "Mate, keep the ute-bot well clear of the buildings, yeah? Give 'em a wide berth, the "
            "further the better. The bush and the grass are no worries."
        ),
        voice="field",
        construct="graded_away",
        layers=SAMPLE,
        expect=(
            ("graded_away", "building", None),
            ("neutral", "grass"),
            ("neutral", "tree"),
        ),
        routes=(Route("sample", "farther", "building"),),
        why="'the bush' is Australian for wooded country (the tree layer); 'no worries' is a permission: neutral",
    ),
    Brief(
        prompt=(
            "Kindly ensure the robot is not going near the railway line. As much distance as possible "
            "from the railway is preferred. Road crossing is allowed."
        ),
        voice="robot",
        construct="graded_away",
        layers=NB,
        expect=(
            ("graded_away", "railway", None),
            ("neutral", "road"),
        ),
        routes=(Route("nb2", "farther", "railway"),),
    ),
    Brief(
        prompt=(
            "Disturbance to roosting bats rises with proximity to tree cover. Cost should therefore "
            "decrease with distance from trees, reaching background levels at 20 m; beyond 20 m, "
            "proximity is irrelevant."
        ),
        voice="analyst",
        construct="graded_away",
        layers=TREE,
        expect=(("graded_away", "tree", 20),),
        routes=(Route("neon", "farther", "tree"),),
    ),
    Brief(
        prompt="🚫🏠 stay far from houses, further = better 🙏",
        voice="robot",
        construct="graded_away",
        layers=BUILDING,
        expect=(("graded_away", "building", None),),
        routes=(
            Route("massachusetts", "farther", "building"),
            Route("kampala", "farther", "building"),
        ),
        why="houses are buildings; 'stay far from' with 'further = better' prices by distance, it forbids nothing",
    ),
    Brief(
        prompt=(
            "Given the claimant's allegation of vibration damage, the inspection vehicle's exposure "
            "to the buildings should be minimised: the closer it passes, the worse, with the concern "
            "fading out entirely by 50 feet."
        ),
        voice="analyst",
        construct="graded_away",
        layers=BUILDING,
        expect=(("graded_away", "building", 50 * FT),),
        routes=(Route("massachusetts", "farther", "building"),),
        why="the concern fades out by 50 ft = 15.24 m: the fall-off reaches neutral there",
    ),
    Brief(
        prompt=(
            "SOP-12 Water proximity\n"
            "1. General\n"
            "  1.a The rover shall avoid approaching water.\n"
            "  1.b Proximity cost is graded: nearer is worse.\n"
            "  1.c No fixed standoff applies.\n"
            "2. Other classes\n"
            "  2.a Road use is unrestricted."
        ),
        voice="analyst",
        construct="graded_away",
        layers=NB,
        expect=(
            ("graded_away", "water", None),
            ("neutral", "road"),
        ),
        routes=(
            Route("nb1", "farther", "water"),
            Route("nb2", "farther", "water"),
        ),
    ),
    Brief(
        prompt=(
            "Don't let the robot anywhere near the pond on seven, and the more distance between it "
            "and the water the happier I'll be. Stick to the cart paths where you can."
        ),
        voice="field",
        construct="graded_away",
        layers=SAMPLE,
        expect=(
            ("graded_away", "water", None),
            ("preferred", "trail"),
        ),
        routes=(
            Route("sample", "farther", "water"),
            Route("sample", "more_on", "trail"),
        ),
        why=(
            "'anywhere near' with 'the more distance the happier' is graded nearness, not a hard "
            "zone; a golf course's cart paths are the trail layer, and 'stick to' prefers them"
        ),
    ),
    # ==========================================================================================
    # graded_toward: the nearer, the cheaper
    # ==========================================================================================
    Brief(
        prompt=(
            "Rover One, Base. Keep within sight of the road at all times, the closer the better, we "
            "may need to extract you. Over."
        ),
        voice="field",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "road", None),),
        routes=(Route("nb1", "closer", "road"),),
    ),
    Brief(
        prompt=(
            "Accessibility review, recommendation 3: the guided-tour robot's route ought to keep close "
            "to the lake shore, as visitors value the water views; the nearer the shore, the better."
        ),
        voice="analyst",
        construct="graded_toward",
        layers=SAMPLE,
        expect=(("graded_toward", "water", None),),
        routes=(Route("sample", "closer", "water"),),
    ),
    Brief(
        prompt=(
            "Companion AI: pathfinding should be attracted to tree cover. Tiles adjacent to trees are "
            "cheapest and the bonus fades with distance. Never path through buildings."
        ),
        voice="robot",
        construct="graded_toward",
        layers=SAMPLE,
        expect=(
            ("graded_toward", "tree", None),
            ("lethal", "building"),
        ),
        routes=(
            Route("sample", "closer", "tree"),
            Route("sample", "zero_on", "building"),
        ),
        why="'never path through' is the game designer's 'never enter': lethal",
    ),
    Brief(
        prompt="Please the robot go always near of the trail, not far of it. More near is more good.",
        voice="robot",
        construct="graded_toward",
        layers=SAMPLE,
        expect=(("graded_toward", "trail", None),),
        routes=(Route("sample", "closer", "trail"),),
    ),
    Brief(
        prompt=(
            "VLOS ops, visual referencing: stay close to the buildings and hug the built-up area, "
            "the nearer the better."
        ),
        voice="robot",
        construct="graded_toward",
        layers=BUILDING,
        expect=(("graded_toward", "building", None),),
        routes=(Route("massachusetts", "closer", "building"),),
    ),
    Brief(
        prompt=(
            "yeah so the fencing bot keep it tight to the tree line all the way round within about 5 "
            "metres ideally don't let it wander out into the middle"
        ),
        voice="field",
        construct="graded_toward",
        layers=SAMPLE,
        expect=(("graded_toward", "tree", 5),),
        routes=(Route("sample", "closer", "tree"),),
        why="'tight to the tree line ... within about 5 metres ideally' is a soft pull toward the trees, not a keep-in zone",
    ),
    Brief(
        prompt=(
            "Transect design: the vehicle should remain near vegetation cover to minimise flushing of "
            "ground-nesting birds in the open. Proximity to vegetation is to be rewarded, increasingly "
            "so as distance decreases."
        ),
        voice="analyst",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "vegetation", None),),
        routes=(
            Route("nb1", "closer", "vegetation"),
            Route("nb2", "closer", "vegetation"),
        ),
    ),
    Brief(
        prompt=(
            "The Licensee shall, so far as reasonably practicable, keep the survey vehicle close to the "
            "public road, and shall not enter any building."
        ),
        voice="analyst",
        construct="graded_toward",
        layers=NB,
        expect=(
            ("graded_toward", "road", None),
            ("lethal", "building"),
        ),
        routes=(
            Route("nb1", "closer", "road"),
            Route("nb1", "zero_on", "building"),
            Route("nb2", "zero_on", "building"),
        ),
    ),
    # ==========================================================================================
    # on_beside: along X but not on it
    # ==========================================================================================
    Brief(
        prompt=(
            "Unit 9, sidewalk bot: run along the road but NOT on it, stay on the verge right next to "
            "the kerb. The roadway is for the big ploughs."
        ),
        voice="field",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "road"),),
        routes=(Route("nb1", "beside", "road", 5),),
    ),
    Brief(
        prompt=(
            "3. Railway inspection\n"
            "  3.a The vehicle travels parallel to the railway.\n"
            "  3.b It must not enter the track bed itself.\n"
            "  3.c Preferred lateral offset: 2-5 m."
        ),
        voice="analyst",
        construct="on_beside",
        layers=NB,
        expect=(
            ("beside", "railway"),
            ("lethal", "railway"),
        ),
        routes=(
            Route("nb2", "beside", "railway", 5),
            Route("nb2", "zero_on", "railway"),
        ),
        why="the track bed is the railway layer itself, and 'must not enter' forbids it",
    ),
    Brief(
        prompt=(
            "riverbank_follow:\n"
            "  reference_layer: water\n"
            "  stay_on_reference: false\n"
            "  lateral_offset_m: 3\n"
            "  note: hug the bank, don't drive into the river\n"
        ),
        voice="robot",
        construct="on_beside",
        layers=SAMPLE,
        expect=(("beside", "water"),),
        routes=(Route("sample", "beside", "water", 5),),
    ),
    Brief(
        prompt=(
            "Patrol AI follows the road's edge: the shoulder tiles next to the road are cheap, the "
            "road tiles themselves carry a heavy penalty."
        ),
        voice="robot",
        construct="on_beside",
        layers=SAMPLE,
        expect=(
            ("beside", "road"),
            ("avoided", "road"),
        ),
        routes=(Route("sample", "beside", "road", 5),),
    ),
    Brief(
        prompt=("Run the mower bot along the edge of the trees, out on the grass beside them, not under the canopy."),
        voice="field",
        construct="on_beside",
        layers=SAMPLE,
        expect=(("beside", "tree"),),
        routes=(Route("sample", "beside", "tree", 5),),
        why="'under the canopy' is on the tree layer; 'on the grass beside them' places the band, it adds no grass rule",
    ),
    Brief(
        prompt="follow trail but stay OFF it - drive the shoulder, 2-3 m out. thx",
        voice="robot",
        construct="on_beside",
        layers=SAMPLE,
        expect=(("beside", "trail"),),
        routes=(Route("sample", "beside", "trail", 5),),
    ),
    Brief(
        prompt=(
            "The drainage claim requires photographs of the watercourse bank along its full length; the "
            "vehicle should proceed beside the water, on the adjacent ground, and should not enter the "
            "water."
        ),
        voice="analyst",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "water"),),
        routes=(Route("nb1", "beside", "water", 5),),
        why=(
            "'should not enter' is softer than 'must not enter', so only 'avoided or forbidden' "
            "(the beside cue) is expected of the water itself"
        ),
    ),
    # ==========================================================================================
    # qualified: paved / unpaved, regional names for a class, excepted sub-areas, sub-classes
    # ==========================================================================================
    Brief(
        prompt=(
            "Plough bot 3: only clear the paved roads tonight. The dirt roads are off limits, they're not our contract."
        ),
        voice="field",
        construct="qualified",
        layers=VEGAS,
        expect=(
            ("preferred", "paved road"),
            ("lethal", "unpaved road"),
        ),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="dirt roads are the unpaved road class; 'tonight' dates the job, it is no condition",
    ),
    Brief(
        prompt=(
            "Tracking vehicle should stick to the tarmac for the smooth shots. Gravel tracks shake the "
            "rig, avoid those."
        ),
        voice="field",
        construct="qualified",
        layers=VEGAS,
        expect=(
            ("preferred", "paved road"),
            ("avoided", "unpaved road"),
        ),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="tarmac is paved road, gravel tracks are unpaved road",
    ),
    Brief(
        prompt=(
            "All grassed areas are to be avoided, with the exception of the baseball field, which may "
            "be crossed freely."
        ),
        voice="analyst",
        construct="qualified",
        layers=SAMPLE,
        expect=(
            ("avoided", "grass"),
            ("neutral", "baseball field"),
            ("below", "baseball field", "grass"),
        ),
        routes=(Route("sample", "less_on", "grass"),),
        why="the baseball field is the excepted grassed area; 'may be crossed freely' is a permission: neutral",
    ),
    Brief(
        prompt="Robot should prefer the pucca road. Kaccha road it should avoid as far as possible.",
        voice="robot",
        construct="qualified",
        layers=VEGAS,
        expect=(
            ("preferred", "paved road"),
            ("avoided", "unpaved road"),
        ),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="Indian English: a pucca road is metalled (paved), a kaccha (kutcha) road is unsurfaced (unpaved)",
    ),
    Brief(
        prompt=(
            "Water tiles are impassable for ground units. The bridges where the trail or the road "
            "crosses the water are fine."
        ),
        voice="robot",
        construct="qualified",
        layers=SAMPLE,
        expect=(
            ("lethal", "water"),
            ("not_lethal", "trail"),
            ("not_lethal", "road"),
        ),
        routes=(Route("sample", "zero_on", "water"),),
        why=(
            "the excepted sub-area (bridges) lies on the trail and road layers, not the water, so "
            "water stays impassable while the crossings stay open"
        ),
    ),
    Brief(
        prompt=(
            "Tracked loader: asphalt roads are off limits, we'll chew up the surface. Keep out of the "
            "railway as well. Unmade ground and scrub is all fine."
        ),
        voice="field",
        construct="qualified",
        layers=NB,
        expect=(
            ("lethal", "road"),
            ("lethal", "railway"),
            ("neutral", "vegetation"),
        ),
        routes=(
            Route("nb1", "zero_on", "road"),
            Route("nb2", "zero_on", "railway"),
        ),
        why=(
            "the road layer carries no surface split, so 'asphalt roads' is read as the road layer; "
            "scrub is vegetation and 'all fine' a permission: neutral"
        ),
    ),
    Brief(
        prompt=(
            "Survey design: the rover should avoid coniferous trees (a goshawk is nesting in one); "
            "deciduous trees pose no concern."
        ),
        voice="analyst",
        construct="qualified",
        layers=TREE,
        expect=(("unread", "conifer"),),
        why=(
            "the tree layer has no conifer / deciduous split; a careful reader reports the rule on "
            "the sub-class instead of applying it (or its opposite) to every tree"
        ),
    ),
    Brief(
        prompt=(
            "The right of way extends over the metalled carriageway only; the unmetalled track is "
            "excluded and must not be entered."
        ),
        voice="analyst",
        construct="qualified",
        layers=VEGAS,
        expect=(
            ("lethal", "unpaved road"),
            ("neutral", "paved road"),
        ),
        routes=(Route("vegas", "zero_on", "unpaved road"),),
        why="metalled = paved, unmetalled track = unpaved road; a right of way is a permission: neutral",
    ),
    # ==========================================================================================
    # terse: symbols, 'X: no', 'X fine', typos in multi-word names
    # ==========================================================================================
    Brief(
        prompt="prefer trail > grass > road",
        voice="robot",
        construct="terse",
        layers=SAMPLE,
        expect=(
            ("below", "trail", "grass"),
            ("below", "grass", "road"),
        ),
        why="'prefer a > b' ranks a above b, so a is cheaper; no level is given, only the order",
    ),
    Brief(
        prompt="water: NO. trees: fine 🌲✅ 💧❌",
        voice="robot",
        construct="terse",
        layers=SAMPLE,
        expect=(
            ("lethal", "water"),
            ("neutral", "tree"),
            ("not_lethal", "tree"),
        ),
        routes=(Route("sample", "zero_on", "water"),),
        why="a bare capital 'NO' against a class (and the cross mark) is the terse 'not allowed': forbidding",
    ),
    Brief(
        prompt="cost(bldg) > cost(veg) > cost(road)",
        voice="analyst",
        construct="terse",
        layers=NB,
        expect=(
            ("below", "vegetation", "building"),
            ("below", "road", "vegetation"),
        ),
        why="bldg and veg abbreviate building and vegetation; only the order is given",
    ),
    Brief(
        prompt="basball feild: keep out. grass ok.",
        voice="field",
        construct="terse",
        layers=SAMPLE,
        expect=(
            ("lethal", "baseball field"),
            ("neutral", "grass"),
            ("avoided", "water"),
            ("not_lethal", "water"),
        ),
        routes=(Route("sample", "zero_on", "baseball field"),),
        why="both words of 'baseball field' are misspelt; water is unmentioned and a careful reader keeps its prior",
    ),
    Brief(
        prompt="unpavd rd: avoid / pavd rd: ok",
        voice="robot",
        construct="terse",
        layers=VEGAS,
        expect=(
            ("avoided", "unpaved road"),
            ("neutral", "paved road"),
            ("below", "paved road", "unpaved road"),
        ),
    ),
    Brief(
        prompt="tree=avoid\nwater=nogo\nroad=prefer",
        voice="analyst",
        construct="terse",
        layers=SAMPLE,
        expect=(
            ("avoided", "tree"),
            ("lethal", "water"),
            ("preferred", "road"),
        ),
        routes=(
            Route("sample", "less_on", "tree"),
            Route("sample", "zero_on", "water"),
            Route("sample", "more_on", "road"),
        ),
        why="'nogo' is 'no-go' without its hyphen: forbidding",
    ),
    Brief(
        prompt="rail 3x worse than road. veg 2x worse than road.",
        voice="field",
        construct="terse",
        layers=NB,
        expect=(
            ("below", "road", "vegetation"),
            ("below", "vegetation", "railway"),
        ),
        why="the two ratios on one base order all three: road, then vegetation (2x), then railway (3x)",
    ),
    # ==========================================================================================
    # permission: permissions lift priors; stay-out wording forbids
    # ==========================================================================================
    Brief(
        prompt=(
            "right so the bot's allowed through the trees this time it's fine they've been thinned "
            "and it can go in the water too it's only ankle deep"
        ),
        voice="field",
        construct="permission",
        layers=SAMPLE,
        expect=(
            ("neutral", "tree"),
            ("neutral", "water"),
            ("not_lethal", "water"),
        ),
    ),
    Brief(
        prompt=(
            "The Grantee may pass and repass over the roads and the grass, but shall not enter any "
            "building on the land."
        ),
        voice="analyst",
        construct="permission",
        layers=SAMPLE,
        expect=(
            ("neutral", "road"),
            ("neutral", "grass"),
            ("lethal", "building"),
        ),
        routes=(Route("sample", "zero_on", "building"),),
    ),
    Brief(
        prompt="Is permitted cross the water. Not permitted enter in the buildings.",
        voice="robot",
        construct="permission",
        layers=SAMPLE,
        expect=(
            ("neutral", "water"),
            ("not_lethal", "water"),
            ("lethal", "building"),
        ),
        routes=(Route("sample", "zero_on", "building"),),
        why="the negated permission to enter forbids, as 'must not enter' does",
    ),
    Brief(
        prompt=(
            "Water's not a problem for this rig, it's amphibious. Keep out of the railway corridor "
            "though, no exceptions."
        ),
        voice="field",
        construct="permission",
        layers=NB,
        expect=(
            ("neutral", "water"),
            ("not_lethal", "water"),
            ("lethal", "railway"),
        ),
        routes=(Route("nb2", "zero_on", "railway"),),
        why="'not a problem' lifts water's prior to neutral; the railway corridor is the railway layer",
    ),
    Brief(
        prompt='{"tree": "allow", "building": "deny"}',
        voice="robot",
        construct="permission",
        layers=SAMPLE,
        expect=(
            ("neutral", "tree"),
            ("lethal", "building"),
        ),
        routes=(Route("sample", "zero_on", "building"),),
        why="an allow / deny table: allow is a permission (neutral), deny forbids",
    ),
    Brief(
        prompt="OVERFLIGHT OF BUILDINGS IS NOT AUTHORISED. OVERFLIGHT OF TREES AND WATER: AUTHORISED.",
        voice="robot",
        construct="permission",
        layers=SAMPLE,
        expect=(
            ("lethal", "building"),
            ("neutral", "tree"),
            ("neutral", "water"),
        ),
        routes=(Route("sample", "zero_on", "building"),),
        why="'not authorised' is a negated permission, which forbids; 'authorised' merely allows: neutral",
    ),
    Brief(
        prompt=("You don't need to avoid the trees, the mower can go right under them. Stay out of the water hazards."),
        voice="field",
        construct="permission",
        layers=SAMPLE,
        expect=(
            ("neutral", "tree"),
            ("lethal", "water"),
        ),
        routes=(Route("sample", "zero_on", "water"),),
        why="on a golf course the water hazards are the water layer",
    ),
    Brief(
        prompt=(
            "Buildings are no longer a constraint following the demolition; the inspection vehicle may "
            "cross the former building footprints. Water remains off limits."
        ),
        voice="analyst",
        construct="permission",
        layers=SAMPLE,
        expect=(
            ("neutral", "building"),
            ("lethal", "water"),
        ),
        routes=(Route("sample", "zero_on", "water"),),
    ),
    # ==========================================================================================
    # clauses: every clause accounted for
    # ==========================================================================================
    Brief(
        prompt=(
            "All units, Control. Stay out of the water. If visibility drops below fifty metres, hold "
            "position. Control out."
        ),
        voice="field",
        construct="clauses",
        layers=NB,
        expect=(
            ("lethal", "water"),
            ("unread", "visibility"),
        ),
        routes=(Route("nb1", "zero_on", "water"),),
        why="'fifty metres' measures visibility, not a distance from a layer",
    ),
    Brief(
        prompt=("Unit 22: use the roads, they're cleared. If it starts snowing again, stay off the roads and wait."),
        voice="field",
        construct="clauses",
        layers=NB,
        expect=(
            ("preferred", "road"),
            ("not_lethal", "road"),
            ("unread", "snow"),
        ),
        routes=(Route("nb1", "more_on", "road"),),
        why="the stay-off rule hangs on snowfall no layer carries, so it must not fire on the road",
    ),
    Brief(
        prompt=(
            "Keep the robot off the grass during the afternoon picnic hour; the rest of the day it's "
            "fine. Always avoid the water."
        ),
        voice="field",
        construct="clauses",
        layers=SAMPLE,
        expect=(
            ("not_lethal", "grass"),
            ("avoided", "water"),
            ("unread", "afternoon"),
        ),
        routes=(Route("sample", "less_on", "water"),),
        why="the grass rule hangs on the time of day, so it is reported and must not forbid the grass",
    ),
    Brief(
        prompt="The route shall avoid buildings and prefer roads. Water is to be avoided as well.",
        voice="analyst",
        construct="clauses",
        layers=SAMPLE,
        expect=(
            ("avoided", "building"),
            ("preferred", "road"),
            ("avoided", "water"),
            ("all_read",),
        ),
        routes=(
            Route("sample", "less_on", "building"),
            Route("sample", "more_on", "road"),
        ),
    ),
    Brief(
        prompt=(
            "Pathing rules: prefer trails; avoid water; at night, NPCs should stick to the roads "
            "under the streetlights."
        ),
        voice="robot",
        construct="clauses",
        layers=SAMPLE,
        expect=(
            ("preferred", "trail"),
            ("avoided", "water"),
            ("unread", "night"),
        ),
        routes=(Route("sample", "more_on", "trail"),),
    ),
    Brief(
        prompt="Robot go on grass, this is preferred. Road use only when is not much cars on it.",
        voice="robot",
        construct="clauses",
        layers=SAMPLE,
        expect=(
            ("preferred", "grass"),
            ("unread", "cars"),
        ),
        routes=(Route("sample", "more_on", "grass"),),
        why="the road rule hangs on traffic no layer carries; the grass preference stands on its own",
    ),
    Brief(
        prompt=("Avoid the pylons and the overhead lines; avoid water; keep out of the substation compound."),
        voice="analyst",
        construct="clauses",
        layers=NB,
        expect=(
            ("avoided", "water"),
            ("unread", "pylon"),
            ("unread", "substation"),
        ),
        routes=(Route("nb1", "less_on", "water"),),
        why="no layer stands for pylons or a substation; those rules are reported, not dropped",
    ),
]
