"""Mission briefs, set 29: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench, the docs or the briefs of earlier sets: only the contract
(``tests/mission_briefs.py`` and its format test ``tests/test_mission_briefs.py``), the scene index
(``../shared/scenes/INDEX.md`` and the scenes' ``classes.json``), the first 60 lines of set 28
(for the layout, and its docstring's list of voices) and the first 25 lines of sets 25, 26 and 27
(their docstrings' lists of voices, which this set avoids) were read. It is scored once, at first
contact, with ``bench/mission_briefs_report.py --set 29``; that figure is the one that counts, and
the set is not edited afterwards to make the interpreter pass.

The voices are a search-and-rescue radio log ("SAR Two to Base, copy all", "How copy, over"), a
golf course superintendent (the clubhouse, the ponds on 7 and 12 drained for relining, the cart
path, the water hazard's bank), a university campus facilities email ("Dear colleagues", "Kind
regards, Facilities Management", the loading dock, the scaffolding on the library), a Scottish
speaker ("ye'll no come within", "o' the railway", "awa' frae", "dinnae go in it"), an Indian
English speaker ("Kindly ensure", "minimum 5 metres distance", "no exceptions will be
entertained", "near to the road only", "do the needful"), a South African speaker ("Try keep",
"hey", "the tar road", "not the end of the world"), a Dutch cyclist writing English ("It is
absolutely not allowed", "4 meter", "I become nervous of cars", "Over the road you may cross",
"the rails itself"), a shepherd whose flock spooks at traffic, a metal detectorist (15 feet from
any tree, beeping over anything metallic), a water-main leak crew (the open trench, the verge and
the carriageway), a lawn-mower robot's support chat ("Customer: ... ~12 m"), an insurance
adjuster ("for liability reasons", "risk rating", the shallow ford by the gate), a bird-watcher
(herons that lift at 20 yards), a mountain-bike trail builder (deciduous trees and conifers whose
needles hide the roots), a cricket groundsman (the mown grass of the square, the long grass of the
outfield), a tow-truck dispatcher ("Dispatch to Unit 9"), telegrams ("AVOID TREES STOP"), JSON
objects (``"min_distance_m": 15, "strict": true``, ``"falloff_m"``, ``"follow"``/``"offset_m"``,
``"max_speed_kmh"``), an INI file (``[water]`` / ``buffer_m = 8`` / ``enforcement = soft``,
``crossing = allowed``, ``access = forbidden``), Jira tickets with acceptance criteria ("RBT-412",
"AC1:", "AC2:"), a legal easement ("the Grantee", "the Servient Land", "expressly permitted to
cross the railway at grade"), a quantified formula (``dist(p, water) >= 12 m`` over every point of
the route), a texting teenager ("lowkey", "fr", "its a hard no", "closer = better", "not ON it
lol"), a dictated voice memo whose spoken punctuation was transcribed ("Note to self comma",
"full stop"), a stream-of-consciousness memo with no punctuation at all, and terse lines with typos
and abbreviations ("watr: no-go", "bldgs: 5m hard", "baseball feild ok", "pavd road >> unpavd rd",
"rail: NO / water: no / veg: fine", "trees --").

Units come in metres and meters ("4 meter"), feet (a 20-foot ring = 6.096 m, 15 feet = 4.572 m),
yards (10 yards = 9.144 m, 20 yards = 18.288 m), numbers as words ("eight metres", "ten metres",
"FIFTEEN METRES", "forty metres"), ranges ("three to four metres": the lower figure is probed, and
the upper is inside the probe's margin, so either reading passes), "~12 m", "5m" and JSON/INI
numbers. Hard distance rules are worded "at all times; that is a hard limit, not a guideline",
"under no circumstances ... this restriction is absolute", ``"strict": true``, "not negotiable and
no exceptions will be entertained", "treat a 20-foot ring ... as a wall. Nothing on wheels goes
inside it", "NEVER ... its a hard no", "No ever, no for anything", "Mandatory - do not breach it",
"a hard constraint, never relaxed" and "absolutely not allowed ... also not a little bit"; soft
ones "where feasible ... guidance rather than a rule", ``enforcement = soft``, "Nice to have ...
Don't fuss", "not the end of the world", "allowed, only penalised", "a preference and not a rule",
"lowkey ... not a big deal if u cant" and "where it reasonably can ... not a hard rule". Graded
nearness away comes as "every metre nearer the water counts against it", "the closer the worse",
"the nearer the road the worse, fading to no bother at all by about 30 metres out", ``"mode":
"graded", "falloff_m": 20``, "as far ... as possible; nearer it goes, more is the risk. Beyond 25
metres there is no issue", "the closer ye get tae them, the worse it is", "the further from the
road the better", "more cautious the closer it gets", "EACH METRE CLOSER WORSE" and "a wide berth;
the nearer it passes, the higher the risk rating"; toward as "hug the cart path", "as near as
practical to the tree line", "keep close ... ideally within about 10 metres ... the closer the
better", "near to the road only; nearer is better", "stay tight by the water", ``"prefer_near"``,
"keep close to the tar road", "nearer's better, every metre closer helps", "closer = better" and
"keep within sight of the railway ... nearer the better". On versus beside comes as "along the
edge of the water hazard, never in it", "Work the verge, not the carriageway", "next to the
railway ... but never on the rails itself", "alongside the vegetation ... never enters", "alongside
the trees only, not under them", ``"on_road": false``, "along its bank ... dinnae go in it", "only
along the strip immediately adjoining the buildings ... shall not traverse", "next to the trail
not ON it" and "FOLLOW EDGE OF GRASS STOP WHEELS OFF GRASS ITSELF". Qualified kinds are paved versus
unpaved road, deciduous trees versus conifers, mown versus long grass, and excepted sub-areas (the
loading dock of the buildings, the shallow ford of the water). Permissions come as "has the
go-ahead to roll straight across the water areas today; no need to skirt them", "no problem, you
can go under them freely", ``crossing = allowed``, "u can totally go thru", "expressly permitted
... without restriction", next to forbidding in "strictly do not go into", ``access = forbidden``,
"stay out of", "shall keep out of", "off limits" and "a no-go area". Clauses no layer carries (a
radio schedule, scaffolding, beeping, a speed limit) are expected unread. Where a brief is
ambiguous ("keep off the grass": banned or only avoided? how dear is "meh", "--" or "rail: NO"?)
less is checked.
"""

from __future__ import annotations

from .mission_briefs import Brief, Route

#: Briefs retired after first contact, with the reason (none yet).
DOUBTFUL: dict[str, str] = {}

#: The New Brunswick clips' classes (nb1 shows no railway).
_NB = ("building", "road", "water", "vegetation", "railway")
#: The bundled sample's classes, less the baseball field.
_GOLF = ("grass", "trail", "tree", "water", "building", "road")

BRIEFS: tuple[Brief, ...] = (
    # ==========================================================================================
    # distance_hard: absolute distance rules, a keep-out zone of the stated metres
    # ==========================================================================================
    Brief(
        "SAR Two to Base, copy all. Rover holds no less than 10 metres from the water at all times; that is a hard limit, not a guideline. Over.",
        "field",
        "distance_hard",
        ("grass", "road", "trail", "tree", "water", "building"),
        (("keep_out", "water", 10),),
        (Route("sample", "keeps", "water", 10),),
    ),
    Brief(
        "Clause 4.2 (Restriction). The Grantee's vehicle shall under no circumstances pass within 6 metres of any building on the Servient Land, and this restriction is absolute.",
        "analyst",
        "distance_hard",
        _NB,
        (("keep_out", "building", 6),),
        (Route("nb1", "keeps", "building", 6),),
    ),
    Brief(
        '{"rules": [{"class": "railway", "min_distance_m": 15, "strict": true}]}',
        "robot",
        "distance_hard",
        _NB,
        (("keep_out", "railway", 15),),
        (Route("nb2", "keeps", "railway", 15),),
    ),
    Brief(
        "Kindly ensure the rover is maintaining minimum 5 metres distance from buildings at all times. This is not negotiable and no exceptions will be entertained.",
        "field",
        "distance_hard",
        ("building", "road", "grass", "tree"),
        (("keep_out", "building", 5),),
        (Route("massachusetts", "keeps", "building", 5),),
    ),
    Brief(
        "Superintendent's standing rule: treat a 20-foot ring around the clubhouse and every other building as a wall. Nothing on wheels goes inside it.",
        "field",
        "distance_hard",
        _GOLF,
        (("keep_out", "building", 6.096),),
        (Route("sample", "keeps", "building", 6.096),),
        why="20 ft = 6.096 m; the clubhouse is one of the buildings the rule names",
    ),
    Brief(
        "ok so dad says NEVER within like 10 yards of the road, hes dead serious, its a hard no",
        "field",
        "distance_hard",
        ("road", "grass", "tree", "building"),
        (("keep_out", "road", 9.144),),
        why="10 yd = 9.144 m; 'like' hedges the figure, not the rule, which 'NEVER ... hard no' makes absolute",
    ),
    Brief(
        "Right, listen: ye'll no come within eight metres o' the railway. No ever, no for anything, that's the law on this job.",
        "field",
        "distance_hard",
        _NB,
        (("keep_out", "railway", 8),),
    ),
    Brief(
        "Leak crew, site rule: an exclusion of three to four metres round every building while the trench is open. Mandatory - do not breach it under any circumstances.",
        "field",
        "distance_hard",
        ("building", "road", "grass"),
        (("keep_out", "building", 3),),
        (Route("kampala", "keeps", "building", 3),),
        why="a range: ground 1 m and 2 m is inside either reading, ground 6 m outside both",
    ),
    Brief(
        "for every point p of the route: dist(p, water) >= 12 m. A hard constraint, never relaxed.",
        "robot",
        "distance_hard",
        ("water", "grass", "trail", "road", "tree"),
        (("keep_out", "water", 12),),
    ),
    Brief(
        "It is absolutely not allowed to come closer than 4 meter to the trees, also not a little bit. That distance you keep always.",
        "field",
        "distance_hard",
        ("tree", "grass"),
        (("keep_out", "tree", 4),),
    ),
    # ==========================================================================================
    # distance_soft: distance rules worded softly, a soft zone with the number kept
    # ==========================================================================================
    Brief(
        "Dear colleagues, where feasible the delivery robot should keep around 5 metres clear of the buildings. Please read this as guidance rather than a rule; passing closer is acceptable when needed. Kind regards, Facilities Management",
        "analyst",
        "distance_soft",
        ("building", "road", "grass", "tree", "trail"),
        (("soft_zone", "building", 5), ("not_lethal", "building")),
        (Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        "[water]\nbuffer_m = 8\nenforcement = soft\n",
        "robot",
        "distance_soft",
        ("water", "grass", "tree", "road"),
        (("soft_zone", "water", 8), ("not_lethal", "water")),
        (Route("sample", "farther", "water"),),
    ),
    Brief(
        "Nice to have: about 15 feet between the detector rig and any tree. Don't fuss if the ground won't allow it.",
        "field",
        "distance_soft",
        ("tree", "grass", "trail"),
        (("soft_zone", "tree", 4.572), ("not_lethal", "tree")),
        why="15 ft = 4.572 m",
    ),
    Brief(
        "Try keep about ten metres from the railway, hey, but it's not the end of the world if you go nearer.",
        "field",
        "distance_soft",
        _NB,
        (("soft_zone", "railway", 10), ("not_lethal", "railway")),
        (Route("nb2", "farther", "railway"),),
    ),
    Brief(
        "RBT-412 Soft road buffer\n* AC1: the planner prefers paths at least 3 m from the road\n* AC2: paths closer than 3 m are allowed, only penalised\n* AC3: road is not a blocked class",
        "analyst",
        "distance_soft",
        ("road", "grass", "trail", "building", "tree"),
        (("soft_zone", "road", 3), ("not_lethal", "road")),
    ),
    Brief(
        "Ideally stay 20 yards off the water so the herons don't lift, though it is a preference and not a rule.",
        "field",
        "distance_soft",
        _NB,
        (("soft_zone", "water", 18.288), ("not_lethal", "water")),
        (Route("nb1", "farther", "water"),),
        why="20 yd = 18.288 m",
    ),
    Brief(
        "lowkey try to stay like 2 m from the buildings?? not a big deal if u cant tho",
        "field",
        "distance_soft",
        ("building", "road"),
        (("soft_zone", "building", 2), ("not_lethal", "building")),
    ),
    Brief(
        "Note to self comma the rover should keep roughly six metres back from the road where it reasonably can full stop not a hard rule full stop",
        "analyst",
        "distance_soft",
        _NB,
        (("soft_zone", "road", 6), ("not_lethal", "road")),
        why="dictation transcribed the spoken punctuation; the rule itself is plain",
    ),
    # ==========================================================================================
    # graded_away: the closer, the dearer
    # ==========================================================================================
    Brief(
        "The further the line stays from the ponds, the happier I am; every metre nearer the water counts against it.",
        "field",
        "graded_away",
        _GOLF,
        (("graded_away", "water", None),),
        (Route("sample", "farther", "water"),),
    ),
    Brief(
        "Base to SAR Four: stay well clear of the water, the closer the worse. How copy, over.",
        "field",
        "graded_away",
        _NB,
        (("graded_away", "water", None),),
    ),
    Brief(
        "The flock spooks at traffic, so the nearer the road the worse, fading to no bother at all by about 30 metres out.",
        "field",
        "graded_away",
        ("road", "grass", "tree", "building"),
        (("graded_away", "road", 30),),
        (Route("sample", "farther", "road"),),
    ),
    Brief(
        '{"avoid": {"building": {"mode": "graded", "falloff_m": 20}}}',
        "robot",
        "graded_away",
        ("building", "road", "grass"),
        (("graded_away", "building", 20),),
        (Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        "Please keep the rover as far from the railway line as possible; nearer it goes, more is the risk. Beyond 25 metres there is no issue at all.",
        "analyst",
        "graded_away",
        _NB,
        (("graded_away", "railway", 25),),
        (Route("nb2", "farther", "railway"),),
    ),
    Brief(
        "Keep awa' frae the buildings, mind; the closer ye get tae them, the worse it is.",
        "field",
        "graded_away",
        _NB,
        (("graded_away", "building", None),),
    ),
    Brief(
        "The further from the road the better, I become nervous of cars. Over the road you may cross, that is fine.",
        "field",
        "graded_away",
        ("road", "grass", "trail", "tree"),
        (("graded_away", "road", None), ("not_lethal", "road")),
        why="crossing the road is allowed, so the road is not forbidden; nearness to it is what costs",
    ),
    Brief(
        "Customer: can the mower shy away from the water? Like, more cautious the closer it gets, and not bothered once it's past ~12 m.",
        "analyst",
        "graded_away",
        ("water", "grass", "tree"),
        (("graded_away", "water", 12),),
    ),
    Brief(
        "AVOID TREES STOP EACH METRE CLOSER WORSE STOP NO CONCERN BEYOND FIFTEEN METRES STOP",
        "robot",
        "graded_away",
        ("tree", "grass"),
        (("graded_away", "tree", 15),),
        (Route("neon", "farther", "tree"),),
    ),
    Brief(
        "For liability reasons we would like the route to give the vegetation a wide berth; the nearer it passes, the higher the risk rating we assign.",
        "analyst",
        "graded_away",
        _NB,
        (("graded_away", "vegetation", None),),
    ),
    # ==========================================================================================
    # graded_toward: the closer, the cheaper
    # ==========================================================================================
    Brief(
        "Have it hug the cart path: the closer it sticks to the trail, the better.",
        "field",
        "graded_toward",
        _GOLF,
        (("graded_toward", "trail", None),),
        (Route("sample", "closer", "trail"),),
    ),
    Brief(
        "SAR Three, search leg two: stay as near as practical to the tree line.",
        "field",
        "graded_toward",
        ("tree", "grass", "road", "water"),
        (("graded_toward", "tree", None),),
    ),
    Brief(
        "For wayfinding the robot should keep close to the buildings, ideally within about 10 metres of them, and the closer the better.",
        "analyst",
        "graded_toward",
        ("building", "road", "grass", "tree", "trail"),
        (("graded_toward", "building", 10),),
        (Route("massachusetts", "closer", "building"),),
    ),
    Brief(
        "Rover should remain near to the road only; nearer is better, so we can do the needful if it breaks down.",
        "field",
        "graded_toward",
        _NB,
        (("graded_toward", "road", None),),
        (Route("nb1", "closer", "road"),),
    ),
    Brief(
        "Stay tight by the water please, the view is beautiful. Closer is nicer.",
        "field",
        "graded_toward",
        ("water", "grass", "trail", "tree"),
        (("graded_toward", "water", None),),
    ),
    Brief(
        '{"prefer_near": "vegetation", "falloff_m": 15, "closer_is_cheaper": true}',
        "robot",
        "graded_toward",
        _NB,
        (("graded_toward", "vegetation", 15),),
    ),
    Brief(
        "Keep close to the tar road, hey; the nearer you stay to the paved road, the better.",
        "field",
        "graded_toward",
        ("paved road", "unpaved road"),
        (("graded_toward", "paved road", None),),
        (Route("vegas", "closer", "paved road"),),
    ),
    Brief(
        "Work along near the trees where the ewes shelter; nearer's better, every metre closer helps.",
        "field",
        "graded_toward",
        ("tree", "grass"),
        (("graded_toward", "tree", None),),
        (Route("neon", "closer", "tree"),),
    ),
    Brief(
        "stay close to the buildings pls its creepy out there, closer = better",
        "field",
        "graded_toward",
        ("building",),
        (("graded_toward", "building", None),),
    ),
    Brief(
        "okay so for this one I want it to keep within sight of the railway you know never wandering far off nearer the better really I'd say forty metres is about the limit",
        "analyst",
        "graded_toward",
        _NB,
        (("graded_toward", "railway", 40),),
    ),
    # ==========================================================================================
    # on_beside: along X but not on X
    # ==========================================================================================
    Brief(
        "Run along the edge of the water hazard, never in it; the bank beside the water is ideal.",
        "field",
        "on_beside",
        _GOLF,
        (("beside", "water"),),
        (Route("sample", "beside", "water", 5),),
    ),
    Brief(
        "Work the verge, not the carriageway: keep right beside the road but off the road surface itself.",
        "field",
        "on_beside",
        _NB,
        (("beside", "road"),),
        (Route("nb1", "beside", "road", 5),),
    ),
    Brief(
        "Ride next to the railway, on the small path beside it, but never on the rails itself.",
        "field",
        "on_beside",
        _NB,
        (("beside", "railway"),),
        (Route("nb2", "beside", "railway", 6),),
    ),
    Brief(
        "RBT-509 Hedge-follow mode\n* AC1: the route runs alongside the vegetation, within about 3 m of it\n* AC2: the route never enters the vegetation",
        "analyst",
        "on_beside",
        _NB,
        (("beside", "vegetation"),),
    ),
    Brief(
        "Kindly go alongside the trees only, not under them.",
        "field",
        "on_beside",
        ("tree", "grass"),
        (("beside", "tree"),),
    ),
    Brief(
        '{"follow": "road", "offset_m": 2, "on_road": false}',
        "robot",
        "on_beside",
        ("road", "grass", "trail", "tree", "building"),
        (("beside", "road"),),
        (Route("sample", "beside", "road", 4),),
    ),
    Brief(
        "Follow the water along its bank, aye, but dinnae go in it.",
        "field",
        "on_beside",
        _NB,
        (("beside", "water"),),
    ),
    Brief(
        "The Grantee may pass only along the strip immediately adjoining the buildings, and shall not traverse any building.",
        "analyst",
        "on_beside",
        ("building", "road", "grass"),
        (("beside", "building"),),
        (Route("massachusetts", "beside", "building", 4),),
    ),
    Brief(
        "walk next to the trail not ON it lol, the trail's for the runners",
        "field",
        "on_beside",
        ("trail", "grass", "tree", "road"),
        (("beside", "trail"),),
    ),
    Brief(
        "FOLLOW EDGE OF GRASS STOP WHEELS OFF GRASS ITSELF STOP",
        "robot",
        "on_beside",
        ("grass", "road", "trail"),
        (("beside", "grass"),),
    ),
    # ==========================================================================================
    # qualified: paved / unpaved, deciduous / conifer, mown / long grass, excepted sub-areas
    # ==========================================================================================
    Brief(
        "Dispatch to Unit 9: stick to paved road wherever you can, unpaved road only if nothing else gets you there.",
        "field",
        "qualified",
        ("paved road", "unpaved road"),
        (("preferred", "paved road"), ("below", "paved road", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        '{"paved road": "prefer", "unpaved road": "avoid"}',
        "robot",
        "qualified",
        ("paved road", "unpaved road"),
        (("preferred", "paved road"), ("avoided", "unpaved road")),
    ),
    Brief(
        "Ride under the deciduous trees all you like, but steer round the conifers: the needles hide the roots.",
        "field",
        "qualified",
        ("deciduous tree", "conifer", "grass", "trail"),
        (("below", "deciduous tree", "conifer"), ("avoided", "conifer")),
        why="'all you like' may read as allowed or as preferred, so only the order and the conifers' level are checked",
    ),
    Brief(
        "All buildings are off limits to the robot, with one exception: the loading dock, where it may go.",
        "analyst",
        "qualified",
        ("building", "loading dock", "road", "grass"),
        (("lethal", "building"), ("not_lethal", "loading dock")),
        (Route("massachusetts", "zero_on", "building"),),
    ),
    Brief(
        "The mown grass of the square is a no-go area; the long grass of the outfield is fine to run across.",
        "field",
        "qualified",
        ("mown grass", "long grass", "building"),
        (("lethal", "mown grass"), ("neutral", "long grass")),
    ),
    Brief(
        "Our assessor notes the water should be avoided, apart from the shallow ford by the gate, which is fine to drive through.",
        "analyst",
        "qualified",
        ("water", "ford", "grass", "road"),
        (("avoided", "water"), ("neutral", "ford")),
    ),
    # ==========================================================================================
    # terse: symbolic rankings, 'X: no', 'X ok', typos and abbreviations
    # ==========================================================================================
    Brief(
        "trail > road > grass; tree & water last",
        "analyst",
        "terse",
        ("grass", "road", "trail", "tree", "water"),
        (
            ("below", "trail", "road"),
            ("below", "road", "grass"),
            ("below", "grass", "tree"),
            ("below", "grass", "water"),
        ),
        (Route("sample", "more_on", "trail"),),
    ),
    Brief(
        "watr: no-go. bldgs: 5m hard",
        "field",
        "terse",
        ("water", "building", "grass", "road"),
        (("lethal", "water"), ("keep_out", "building", 5)),
        (Route("sample", "zero_on", "water"),),
    ),
    Brief(
        "baseball feild ok, tree meh",
        "field",
        "terse",
        ("baseball field", "tree", "grass"),
        (("neutral", "baseball field"),),
        why="'meh' is not priced; 'ok' merely allows the field",
    ),
    Brief(
        "pavd road >> unpavd rd",
        "field",
        "terse",
        ("paved road", "unpaved road"),
        (("below", "paved road", "unpaved road"),),
        (Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        "rail: NO / water: no / veg: fine",
        "robot",
        "terse",
        _NB,
        (("neutral", "vegetation"),),
        (Route("nb2", "less_on", "railway"),),
        why="'NO' may ban the railway or only avoid it, so its level is not checked; a route uses it less either way",
    ),
    Brief(
        "grass ok | trees -- | water never",
        "analyst",
        "terse",
        ("grass", "tree", "water", "trail"),
        (("neutral", "grass"), ("below", "grass", "tree")),
        why="'--' and a bare 'never' are not priced; the trees stay at least at their prior, above allowed grass",
    ),
    # ==========================================================================================
    # permission: permissions that lift priors, and stay-out wording that forbids
    # ==========================================================================================
    Brief(
        "The ponds on 7 and 12 are drained for relining, so the rover has the go-ahead to roll straight across the water areas today; no need to skirt them.",
        "field",
        "permission",
        _GOLF,
        (("neutral", "water"), ("not_lethal", "water")),
    ),
    Brief(
        "Trees are no problem, you can go under them freely. But buildings, strictly do not go into them.",
        "field",
        "permission",
        ("tree", "building", "grass", "road"),
        (("neutral", "tree"), ("lethal", "building")),
        (Route("massachusetts", "zero_on", "building"),),
    ),
    Brief(
        "[railway]\ncrossing = allowed\n\n[water]\naccess = forbidden\n",
        "robot",
        "permission",
        _NB,
        (("neutral", "railway"), ("lethal", "water")),
    ),
    Brief(
        "ok u can totally go thru the trees its fine, just stay out of the water fr",
        "field",
        "permission",
        ("tree", "water", "grass"),
        (("neutral", "tree"), ("lethal", "water")),
        (Route("sample", "zero_on", "water"),),
    ),
    Brief(
        "The Grantee is expressly permitted to cross the railway at grade and may enter vegetation without restriction, but shall keep out of all water.",
        "analyst",
        "permission",
        _NB,
        (("neutral", "railway"), ("neutral", "vegetation"), ("lethal", "water")),
        (Route("nb2", "zero_on", "water"),),
    ),
    # ==========================================================================================
    # clauses: clauses no layer carries are reported, never silently dropped
    # ==========================================================================================
    Brief(
        "SAR One: stay on the road where you can, and radio Base with your position every 15 minutes. Over.",
        "field",
        "clauses",
        _NB,
        (("preferred", "road"), ("unread", "radio")),
    ),
    Brief(
        "Please keep the robot off the grass, and do not let it near the scaffolding on the library.",
        "analyst",
        "clauses",
        ("grass", "building", "road", "trail"),
        (("unread", "scaffolding"),),
        why="no layer stands for scaffolding; 'keep off the grass' may ban or only avoid it, so it is not checked",
    ),
    Brief(
        "Stick to the trail, and beep twice whenever you pass over anything metallic.",
        "field",
        "clauses",
        ("trail", "grass", "tree"),
        (("preferred", "trail"), ("unread", "beep")),
        (Route("sample", "more_on", "trail"),),
    ),
    Brief(
        '{"avoid": ["water"], "max_speed_kmh": 6}',
        "robot",
        "clauses",
        ("water", "grass", "road"),
        (("avoided", "water"), ("unread", "speed")),
    ),
    Brief(
        "Use the road by preference, avoid buildings, and keep out of the water altogether.",
        "analyst",
        "clauses",
        _NB,
        (("preferred", "road"), ("avoided", "building"), ("lethal", "water"), ("all_read",)),
        (Route("nb1", "zero_on", "water"),),
    ),
)
