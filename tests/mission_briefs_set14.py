"""Mission briefs, set 14: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora or the bench: only the contract (``tests/mission_briefs.py`` and its format test
``tests/test_mission_briefs.py``) and the scene index (``../shared/scenes/INDEX.md`` and the scenes'
``classes.json``) were read. It is scored once, at first contact, with
``bench/mission_briefs_report.py --set 14``; that figure is the one that counts, and the set is
not edited afterwards to make the interpreter pass.

The voices are GIS analysts (long and formal), robot operators (terse, symbolic) and field teams
(chatty, typo-ridden). The layers of each brief are the class names of the scene its routes are
checked on, so the route checks run on the real ground truth.
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

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------------------------------
    # distance_hard: absolute distance rules make keep-out zones
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "All routes shall maintain a minimum horizontal separation of 15 metres from the railway "
            "corridor; this is a regulatory requirement and is not negotiable."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "railway", 15),),
        routes=(Route("nb1", "keeps", "railway", 15), Route("nb2", "keeps", "railway", 15)),
    ),
    Brief(
        prompt="never within 5m of buildings",
        voice="robot",
        construct="distance_hard",
        layers=BUILDINGS,
        expect=(("keep_out", "building", 5),),
        routes=(Route("massachusetts", "keeps", "building", 5),),
    ),
    Brief(
        prompt="absolutly no closer then twenty metres to the water, thats a hard rule",
        voice="field",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "water", 20),),
        routes=(Route("nb1", "keeps", "water", 20),),
        why="'twenty metres' in words; 'absolutly ... hard rule' makes it absolute despite the typos.",
    ),
    Brief(
        prompt=(
            "Under no circumstances may the vehicle pass immediately adjacent to any building; a clear "
            "buffer must be kept from every structure at all times."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=BUILDINGS,
        expect=(("keep_out", "building", None),),
        routes=(Route("massachusetts", "less_on", "building"),),
        why="Absolute wording with no number: a hard zone of unstated width.",
    ),
    Brief(
        prompt="rail: 10 m buffer, hard. water: 10 m buffer, hard.",
        voice="robot",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "railway", 10), ("keep_out", "water", 10)),
        routes=(Route("nb1", "keeps", "railway", 10), Route("nb1", "keeps", "water", 10)),
        why="'rail' is the railway layer.",
    ),
    Brief(
        prompt=(
            "Whatever you do, never brush up against the trees, the crowns are full of wasp nests. "
            "Keep clear of them, always."
        ),
        voice="field",
        construct="distance_hard",
        layers=TREES,
        expect=(("keep_out", "tree", None),),
        routes=(Route("neon", "less_on", "tree"),),
        why="'never ... always' is absolute; no distance is given.",
    ),
    Brief(
        prompt="Hard constraint: a buffer of twelve metres around the road network is not to be entered.",
        voice="analyst",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "road", 12),),
        routes=(Route("nb1", "keeps", "road", 12),),
    ),
    # ------------------------------------------------------------------------------------------
    # distance_soft: soft zones with the number kept
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Where practicable, routes should maintain approximately 20 m of separation from the "
            "watercourse; minor encroachment is acceptable."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "water", 20),),
        routes=(Route("nb1", "farther", "water"),),
        why="'where practicable' and 'minor encroachment is acceptable' make the 20 m soft.",
    ),
    Brief(
        prompt="try to keep ~8 m off the buildings if you can",
        voice="robot",
        construct="distance_soft",
        layers=BUILDINGS,
        expect=(("soft_zone", "building", 8),),
        routes=(Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        prompt=(
            "id rather we stayed about 10 metres back from the railway line but its not the end of the world if we dont"
        ),
        voice="field",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "railway", 10),),
        routes=(Route("nb1", "farther", "railway"),),
    ),
    Brief(
        prompt="Keep a strict 10 m from the water, and if possible about 5 m from the buildings.",
        voice="field",
        construct="distance_soft",
        layers=NB,
        expect=(("keep_out", "water", 10), ("soft_zone", "building", 5)),
        routes=(Route("nb1", "keeps", "water", 10),),
        why="'strict' makes the water rule hard; 'if possible' makes the building rule soft.",
    ),
    Brief(
        prompt="Give the trees a bit of room, say three metres, where the gaps allow it.",
        voice="field",
        construct="distance_soft",
        layers=TREES,
        expect=(("soft_zone", "tree", 3),),
        routes=(Route("neon", "farther", "tree"),),
    ),
    Brief(
        prompt="bldg margin: 6 m preferred (soft)",
        voice="robot",
        construct="distance_soft",
        layers=BUILDINGS,
        expect=(("soft_zone", "building", 6),),
        routes=(Route("massachusetts", "farther", "building"),),
        why="'bldg' is the usual abbreviation of building.",
    ),
    Brief(
        prompt=(
            "A soft setback of 25 m from the road is desirable for noise reasons, but it may be "
            "relaxed where the terrain forces it."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "road", 25),),
        routes=(Route("nb1", "farther", "road"),),
    ),
    # ------------------------------------------------------------------------------------------
    # graded_away: the closer, the dearer
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="honestly the further from the buildings the better for this one",
        voice="field",
        construct="graded_away",
        layers=BUILDINGS,
        expect=(("graded_away", "building", None),),
        routes=(Route("massachusetts", "farther", "building"), Route("kampala", "farther", "building")),
    ),
    Brief(
        prompt="dont go near the railway tracks pls",
        voice="robot",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "railway", None),),
        routes=(Route("nb1", "farther", "railway"),),
    ),
    Brief(
        prompt=(
            "Proximity to open water should be minimised; the penalty should decrease with distance "
            "and be negligible beyond 30 metres."
        ),
        voice="analyst",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "water", 30),),
        routes=(Route("nb1", "farther", "water"),),
    ),
    Brief(
        prompt="We had a rough time near the water on the last trip. Keep well away from it this time.",
        voice="field",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "water", None),),
        routes=(Route("nb1", "farther", "water"), Route("nb2", "farther", "water")),
        why="'keep well away' with no number is graded nearness, not a hard zone.",
    ),
    Brief(
        prompt="trees: further = better",
        voice="robot",
        construct="graded_away",
        layers=TREES,
        expect=(("graded_away", "tree", None),),
        routes=(Route("neon", "farther", "tree"),),
    ),
    Brief(
        prompt="dont go to near the raod, the trucks come through fast",
        voice="field",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "road", None),),
        routes=(Route("nb1", "farther", "road"),),
        why="'raod' is road; 'to near' is 'too near'.",
    ),
    Brief(
        prompt="Distance from structures is to be maximised, with the penalty tapering off by about 15 m.",
        voice="analyst",
        construct="graded_away",
        layers=BUILDINGS,
        expect=(("graded_away", "building", 15),),
        routes=(Route("massachusetts", "farther", "building"),),
        why="'structures' are the buildings; the fall-off reaches neutral at 15 m.",
    ),
    # ------------------------------------------------------------------------------------------
    # graded_toward: the closer, the cheaper
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="stay close to the road, we want to be able to flag down help if the rover dies",
        voice="field",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "road", None),),
        routes=(Route("nb1", "closer", "road"),),
    ),
    Brief(
        prompt="keep the paved road in sight at all times",
        voice="robot",
        construct="graded_toward",
        layers=VEGAS,
        expect=(("graded_toward", "paved road", None),),
        routes=(Route("vegas", "closer", "paved road"),),
    ),
    Brief(
        prompt="Routes should hug the treeline where possible: the nearer to the trees, the better.",
        voice="analyst",
        construct="graded_toward",
        layers=TREES,
        expect=(("graded_toward", "tree", None),),
        routes=(Route("neon", "closer", "tree"),),
    ),
    Brief(
        prompt="keep neer the water, the dogs need to drink every so often",
        voice="field",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "water", None),),
        routes=(Route("nb1", "closer", "water"),),
    ),
    Brief(
        prompt="vegetation: closer is better",
        voice="robot",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "vegetation", None),),
        routes=(Route("nb1", "closer", "vegetation"),),
    ),
    Brief(
        prompt=(
            "Preference should be given to paths within approximately 15 m of the road network, with "
            "the benefit diminishing with distance."
        ),
        voice="analyst",
        construct="graded_toward",
        layers=NB,
        expect=(("graded_toward", "road", 15),),
        routes=(Route("nb1", "closer", "road"),),
        why="A preference, not a rule: no ground is kept out for being far from the road.",
    ),
    Brief(
        prompt="try to stay within sight of the buildings so the base station keeps its signal",
        voice="field",
        construct="graded_toward",
        layers=BUILDINGS,
        expect=(("graded_toward", "building", None),),
        routes=(Route("massachusetts", "closer", "building"),),
    ),
    # ------------------------------------------------------------------------------------------
    # on_beside: along X but not on X
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="we'll walk the riverbank the whole way but nobody actually goes in the river",
        voice="field",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "water"),),
        routes=(Route("nb1", "beside", "water", 10),),
        why="The river is the water layer.",
    ),
    Brief(
        prompt="follow the railway, never on the tracks",
        voice="robot",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "railway"),),
        routes=(Route("nb1", "beside", "railway", 10),),
    ),
    Brief(
        prompt=(
            "The survey line should run parallel to the road along its verge, without travelling on "
            "the carriageway itself."
        ),
        voice="analyst",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "road"),),
        routes=(Route("nb1", "beside", "road", 8),),
    ),
    Brief(
        prompt="drive the shoulder of the paved road, not the paved road itself",
        voice="robot",
        construct="on_beside",
        layers=VEGAS,
        expect=(("beside", "paved road"),),
        routes=(Route("vegas", "beside", "paved road", 5),),
    ),
    Brief(
        prompt="skirt the edge of the tree crowns but don't go under them",
        voice="field",
        construct="on_beside",
        layers=TREES,
        expect=(("beside", "tree"),),
        routes=(Route("neon", "beside", "tree", 3),),
    ),
    Brief(
        prompt="go allong the edge of the buildngs, not thru them",
        voice="field",
        construct="on_beside",
        layers=BUILDINGS,
        expect=(("beside", "building"),),
        routes=(Route("massachusetts", "beside", "building", 5),),
    ),
    Brief(
        prompt="water edge: yes. water: no.",
        voice="robot",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "water"),),
        routes=(Route("nb2", "beside", "water", 10),),
    ),
    Brief(
        prompt="Keep to the grass right beside the trail rather than walking on the trail itself.",
        voice="field",
        construct="on_beside",
        layers=SAMPLE,
        expect=(("beside", "trail"), ("preferred", "grass")),
        routes=(Route("sample", "beside", "trail", 6),),
    ),
    # ------------------------------------------------------------------------------------------
    # qualified: paved / unpaved, excepted sub-areas
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="If there's a choice, take the unpaved road over the paved road.",
        voice="field",
        construct="qualified",
        layers=VEGAS,
        expect=(("below", "unpaved road", "paved road"),),
    ),
    Brief(
        prompt="Paved road only where you can, please, no dirt tracks.",
        voice="field",
        construct="qualified",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("below", "paved road", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="'dirt tracks' are the unpaved road; 'no' without a forbidding word is a strong avoid.",
    ),
    Brief(
        prompt=(
            "Travel on sealed (paved) roads is preferred; unpaved roads are to be avoided owing to the dust they raise."
        ),
        voice="analyst",
        construct="qualified",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("avoided", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        prompt="Avoid the grass, except the baseball field, which is fine to cross.",
        voice="analyst",
        construct="qualified",
        layers=SAMPLE,
        expect=(("avoided", "grass"), ("neutral", "baseball field")),
        routes=(Route("sample", "less_on", "grass"),),
        why="The baseball field is a grassed sub-area excepted from the grass rule; 'fine' is neutral.",
    ),
    Brief(
        prompt="avoid roads, but the trail is fine",
        voice="robot",
        construct="qualified",
        layers=SAMPLE,
        expect=(("avoided", "road"), ("neutral", "trail")),
        routes=(Route("sample", "less_on", "road"),),
        why="The trail is a minor way excepted from 'roads'; 'fine' is merely allowed.",
    ),
    Brief(
        prompt="unpaved rd is ok, paved rd avoid",
        voice="robot",
        construct="qualified",
        layers=VEGAS,
        expect=(("neutral", "unpaved road"), ("avoided", "paved road")),
        routes=(Route("vegas", "less_on", "paved road"),),
    ),
    Brief(
        prompt="Grass is fine, except the baseball field; there's a game on, so avoid that bit.",
        voice="field",
        construct="qualified",
        layers=SAMPLE,
        expect=(("neutral", "grass"), ("avoided", "baseball field")),
        routes=(Route("sample", "less_on", "baseball field"),),
    ),
    Brief(
        prompt="Stick to the paved road; the unpaved road is passable, just slower.",
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
    # ------------------------------------------------------------------------------------------
    # terse: symbolic rankings and typos
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="road > vegetation > water > railway",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(
            ("below", "road", "vegetation"),
            ("below", "vegetation", "water"),
            ("below", "water", "railway"),
        ),
        routes=(Route("nb1", "less_on", "railway"),),
        why="'A > B' ranks A as better (cheaper) than B; nothing is forbidden.",
    ),
    Brief(
        prompt="paved > unpaved, always",
        voice="robot",
        construct="terse",
        layers=VEGAS,
        expect=(("below", "paved road", "unpaved road"),),
    ),
    Brief(
        prompt="bldg: no. rail: no. road: yes.",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(("avoided", "building"), ("avoided", "railway"), ("preferred", "road")),
        routes=(Route("nb1", "more_on", "road"),),
        why="'no' is not one of the forbidding words, so it is a strong avoid, not impassable.",
    ),
    Brief(
        prompt="trail>grass>road",
        voice="robot",
        construct="terse",
        layers=SAMPLE,
        expect=(("below", "trail", "grass"), ("below", "grass", "road")),
    ),
    Brief(
        prompt="basebal feild ok, watr no-go",
        voice="field",
        construct="terse",
        layers=SAMPLE,
        expect=(("neutral", "baseball field"), ("lethal", "water")),
        routes=(Route("sample", "zero_on", "water"),),
        why="Typos in the multi-word name; 'no-go' forbids.",
    ),
    Brief(
        prompt="trees: fine to pass under",
        voice="robot",
        construct="terse",
        layers=TREES,
        expect=(("neutral", "tree"), ("not_lethal", "tree")),
        why="'fine' lifts the tree prior to merely allowed.",
    ),
    Brief(
        prompt="water: never enter. road: ok.",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(("lethal", "water"), ("neutral", "road")),
        routes=(Route("nb1", "zero_on", "water"),),
    ),
    Brief(
        prompt="unpavd rd > pavd rd",
        voice="field",
        construct="terse",
        layers=VEGAS,
        expect=(("below", "unpaved road", "paved road"),),
        why="Typos and abbreviation in both multi-word names.",
    ),
    # ------------------------------------------------------------------------------------------
    # permission: lifting priors, and stay-out wording that forbids
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="No need to avoid the buildings, they're all ruins now; walk through them if it's shorter.",
        voice="field",
        construct="permission",
        layers=BUILDINGS,
        expect=(("neutral", "building"), ("not_lethal", "building")),
        why="The permission lifts the building prior to neutral; it does not make buildings preferred.",
    ),
    Brief(
        prompt="The creek has been dry since July, so crossing the water is fine.",
        voice="field",
        construct="permission",
        layers=NB,
        expect=(("neutral", "water"), ("not_lethal", "water")),
    ),
    Brief(
        prompt=(
            "The railway was decommissioned in 2019; its tracks may be crossed or walked along without restriction."
        ),
        voice="analyst",
        construct="permission",
        layers=NB,
        expect=(("neutral", "railway"), ("not_lethal", "railway")),
    ),
    Brief(
        prompt="Stay out of the water entirely, the current is far too strong.",
        voice="field",
        construct="permission",
        layers=NB,
        expect=(("lethal", "water"),),
        routes=(Route("nb1", "zero_on", "water"), Route("nb2", "zero_on", "water")),
    ),
    Brief(
        prompt="The buildings are off limits, every single one of them.",
        voice="analyst",
        construct="permission",
        layers=BUILDINGS,
        expect=(("lethal", "building"),),
        routes=(Route("massachusetts", "zero_on", "building"), Route("kampala", "zero_on", "building")),
    ),
    Brief(
        prompt=(
            "Vegetation need not be avoided, as the undergrowth has been cleared. Keep out of the railway corridor."
        ),
        voice="analyst",
        construct="permission",
        layers=NB,
        expect=(("neutral", "vegetation"), ("lethal", "railway")),
        routes=(Route("nb1", "zero_on", "railway"),),
    ),
    Brief(
        prompt="trees are no problem for this rover, it pushes right through them. but don't go into the water",
        voice="robot",
        construct="permission",
        layers=SAMPLE,
        expect=(("neutral", "tree"), ("not_lethal", "tree"), ("lethal", "water")),
        routes=(Route("sample", "zero_on", "water"),),
    ),
    Brief(
        prompt="tree crowns: no-go zone",
        voice="robot",
        construct="permission",
        layers=TREES,
        expect=(("lethal", "tree"),),
        routes=(Route("neon", "zero_on", "tree"),),
    ),
    # ------------------------------------------------------------------------------------------
    # clauses: every clause accounted for
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="Avoid the water and make sure we leave before dawn.",
        voice="field",
        construct="clauses",
        layers=NB,
        expect=(("avoided", "water"), ("unread", "dawn")),
        why="The time of departure is nothing a costmap can hold.",
    ),
    Brief(
        prompt="Payload is 20 kg of sensors. Prefer the road.",
        voice="robot",
        construct="clauses",
        layers=NB,
        expect=(("preferred", "road"), ("unread", "payload")),
        routes=(Route("nb1", "more_on", "road"),),
    ),
    Brief(
        prompt=("Hi all, hope the weekend was good! For tomorrow's run please avoid the railway and prefer the road."),
        voice="analyst",
        construct="clauses",
        layers=NB,
        expect=(("avoided", "railway"), ("preferred", "road"), ("unread", "weekend")),
    ),
    Brief(
        prompt="Prefer the road, avoid the buildings and keep out of the water.",
        voice="analyst",
        construct="clauses",
        layers=NB,
        expect=(("preferred", "road"), ("avoided", "building"), ("lethal", "water"), ("all_read",)),
        routes=(Route("nb1", "zero_on", "water"), Route("nb1", "more_on", "road")),
    ),
    Brief(
        prompt="paved road preferred; unpaved road avoided",
        voice="robot",
        construct="clauses",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("avoided", "unpaved road"), ("all_read",)),
        routes=(Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        prompt="Avoid buildings. The drone battery is down to 40% so don't dawdle.",
        voice="robot",
        construct="clauses",
        layers=BUILDINGS,
        expect=(("avoided", "building"), ("unread", "battery")),
        routes=(Route("massachusetts", "less_on", "building"),),
    ),
    Brief(
        prompt="Scheduled for 0600 hrs. Avoid the trees.",
        voice="robot",
        construct="clauses",
        layers=TREES,
        expect=(("avoided", "tree"), ("unread", "0600")),
        routes=(Route("neon", "less_on", "tree"),),
    ),
    Brief(
        prompt="Use the trail, avoid the grass, and never enter the water.",
        voice="analyst",
        construct="clauses",
        layers=SAMPLE,
        expect=(("preferred", "trail"), ("avoided", "grass"), ("lethal", "water"), ("all_read",)),
        routes=(Route("sample", "zero_on", "water"), Route("sample", "more_on", "trail")),
    ),
    Brief(
        prompt="Keep off the road where you can; the client wants the final report as a PDF.",
        voice="analyst",
        construct="clauses",
        layers=NB,
        expect=(("avoided", "road"), ("unread", "pdf")),
        routes=(Route("nb1", "less_on", "road"),),
        why="'keep off ... where you can' is a soft avoid; the report format is nothing a costmap can hold.",
    ),
]
