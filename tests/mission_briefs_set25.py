"""Mission briefs, set 25: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench, the docs or the briefs of earlier sets: only the contract
(``tests/mission_briefs.py`` and its format test ``tests/test_mission_briefs.py``), the scene index
(``../shared/scenes/INDEX.md`` and the scenes' ``classes.json``) and the first 45 lines of set 24
(for the layout, and its docstring's list of voices, which this set avoids) were read. It is
scored once, at first contact, with ``bench/mission_briefs_report.py --set 25``; that figure is the
one that counts, and the set is not edited afterwards to make the interpreter pass.

The voices are a parent giving a teenager the rules, a pipeline right-of-way inspector (both the
written report and the man walking the line), an orienteering coach (handrails, legs, "+" and "-"
marks), a vineyard manager's spray plan and quad rules, a mine-site haul-road standard and its
blasting windows, a wheelchair user and an accessibility request, a military engineer's route
clearance note, a cemetery groundskeeper (yews and oaks, graves), an airport airside vehicle
operating rule, a beach patrol (standing order, radio-caps unit message, the buggy driver), a
ski-resort groomer, a courier's tips to a new colleague (and his SMS shorthand), an elderly speaker
with digressions ("when I was a girl"), a contract with defined terms ("the Exclusion Zone", "the
Route", "Permitted Areas"), Python dicts, pseudo-code (``if dist(p, building) < 6``,
``follow(railway, ...)``, ``cost(p) = base(p) - k / ...``), ALLOW/DENY lines, a German-English and a
Spanish-English mix (English words for the classes, German or Spanish for the rest: "ca. 1,5 m",
"kein Muss", "meiden", "prohibido", "no pasa nada"), a scout leader counting paces, an analyst's
understatement ("I'd rather not explain why the rover went for a swim"), double negatives ("it is
not the case that the rover can't", "don't not use the road") and hedged rankings ("probably trail
over grass, I guess?").

Units come in metres, "mtrs", feet (50 ft = 15.24 m), spelled-out numbers, a decimal comma
("1,5 m") and paces (no metre figure, so none is expected). Orderings come as ">>", "≫" between
cost terms, "+ / - / --" marks, numeric costs and plain ranked speech; permissions as "allowed",
"may traverse", "open to it", "I don't mind", "alles gut", "no pasa nada" and ALLOW; forbidding as
"stay out of", "keep out of", "don't go into", "never go into", "no-go", "NO GO", "forbidden",
"prohibido", "impassable", DENY and the terse "X: no". Qualified classes are paved / unpaved roads
(spelt right, and as "pavd rd" / "unpavd"), conifers against deciduous trees (which no layer
tells apart) and excepted sub-areas, one carried by a layer (the baseball field inside a grass
rule) and one no layer marks (a ford). Rules that hang on what no layer can carry (tide, wind,
rain, rush hour, blasting windows, sunset and daylight, a clock-time window, traffic, pedestrians,
whether anyone is playing) or name things no layer stands for (graves, a fuel bowser, a ford) are
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

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------------------------------
    # distance_hard
    # ------------------------------------------------------------------------------------------
    Brief(
        "Right-of-way inspection, segment 14. The inspection crawler shall maintain a minimum separation "
        "of 15 m from open water at all times, without exception. The crawler may not come within 5 m of "
        "any building on the easement. Travel across vegetation is acceptable.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "water", 15), ("keep_out", "building", 5), ("neutral", "vegetation")),
        (
            Route("nb1", "keeps", "water", 15),
            Route("nb1", "keeps", "building", 5),
            Route("nb2", "keeps", "water", 15),
        ),
        why="'shall maintain a minimum separation ... without exception' and 'may not come within' are "
        "absolute; 'acceptable' is a permission (neutral).",
    ),
    Brief(
        "ok so when you take the robot out to the park it is NOT to go within 10 metres of the pond. "
        "I mean it. not once. grass, trail, whatever, I don't mind",
        "field",
        "distance_hard",
        SAMPLE,
        (("keep_out", "water", 10), ("neutral", "grass"), ("neutral", "trail")),
        (Route("sample", "keeps", "water", 10),),
        why="A parent's 'NOT to go within 10 metres ... not once' is a hard rule; the pond is the water "
        "layer; 'I don't mind' permits grass and trail.",
    ),
    Brief(
        'rules = {"building": {"clearance_m": 8, "hard": True}, "water": {"clearance_m": 20, "hard": True}, '
        '"trail": "prefer"}',
        "robot",
        "distance_hard",
        SAMPLE,
        (("keep_out", "building", 8), ("keep_out", "water", 20), ("preferred", "trail")),
        (
            Route("sample", "keeps", "building", 8),
            Route("sample", "keeps", "water", 20),
            Route("sample", "more_on", "trail"),
        ),
    ),
    Brief(
        "Route clearance, phase two. All call signs stay a minimum of 25 metres from every building, no "
        "deviation, suspected devices. The road is the axis, use it.",
        "field",
        "distance_hard",
        NB,
        (("keep_out", "building", 25), ("preferred", "road")),
        (
            Route("nb1", "keeps", "building", 25),
            Route("nb1", "more_on", "road"),
            Route("nb2", "keeps", "building", 25),
        ),
        why="'a minimum of 25 metres ... no deviation' is absolute; 'the road is the axis, use it' prefers the road.",
    ),
    Brief(
        "Airside Vehicle Operating Rule 7.3: an autonomous baggage tug must not approach within 7.5 m of "
        "any building, whether terminal, hangar or stand office. This clearance is mandatory.",
        "analyst",
        "distance_hard",
        BUILDING,
        (("keep_out", "building", 7.5),),
        (Route("massachusetts", "keeps", "building", 7.5),),
    ),
    Brief(
        "Beach Patrol Standing Order 3. The patrol buggy keeps a strict thirty metres off the water's "
        "edge. Never closer, for any reason. Grass and road are both open to it.",
        "analyst",
        "distance_hard",
        SAMPLE,
        (("keep_out", "water", 30), ("neutral", "grass"), ("neutral", "road")),
        (Route("sample", "keeps", "water", 30),),
        why="'a strict thirty metres ... never closer' is a hard 30 m zone (number spelled out); "
        "'open to it' permits grass and road.",
    ),
    Brief(
        "GROOMER 3 NAV: min dist to trees 3 mtrs, HARD LIMIT, no override.",
        "robot",
        "distance_hard",
        TREE,
        (("keep_out", "tree", 3),),
        (Route("neon", "keeps", "tree", 3),),
        why="'mtrs' is metres.",
    ),
    Brief(
        '1.1 In this Agreement, "the Exclusion Zone" means all land within 50 feet of any Building, and '
        '"the Route" means the path taken by the Vehicle. 4.2 The Route shall not at any point enter the '
        "Exclusion Zone.",
        "analyst",
        "distance_hard",
        BUILDING,
        (("keep_out", "building", 15.24),),
        (Route("massachusetts", "keeps", "building", 15.24),),
        why="The defined Exclusion Zone is 50 ft (15.24 m) around buildings and the Route 'shall not at "
        "any point enter' it: a hard zone in metres.",
    ),
    Brief(
        "Scout leader to the patrol: nobody goes within twenty paces of the railway line. Never. Count "
        "them if you have to.",
        "field",
        "distance_hard",
        NB,
        (("keep_out", "railway", None),),
        (Route("nb2", "farther", "railway"),),
        why="Absolute wording, but paces give no metre figure, so the zone is expected without a number "
        "(kept out 1 m away, not 60 m away); the route check asks only for a wider berth than the flat "
        "route.",
    ),
    # ------------------------------------------------------------------------------------------
    # distance_soft
    # ------------------------------------------------------------------------------------------
    Brief(
        "Right, for the shadow run: try to give the buildings about 12 m if you can, the residents get "
        "twitchy, but don't lose time over it. Trail's your friend.",
        "field",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "building", 12), ("preferred", "trail"), ("avoided", "water")),
        (Route("sample", "farther", "building"), Route("sample", "more_on", "trail")),
        why="'try to ... if you can ... don't lose time over it' is soft; the pond is unmentioned and a "
        "runner takes for granted it is avoided (its prior).",
    ),
    Brief(
        "Hinweis für den Rover: bitte wenn möglich ca. 1,5 m Abstand zur railway halten. Ist aber kein "
        "Muss, nur eine Empfehlung.",
        "analyst",
        "distance_soft",
        NB,
        (("soft_zone", "railway", 1.5),),
        (Route("nb2", "farther", "railway"),),
        why="German-English: 'ca. 1,5 m' is about 1.5 m with a decimal comma; 'wenn möglich' (if possible) "
        "and 'kein Muss, nur eine Empfehlung' (not a must, only a recommendation) make it soft.",
    ),
    Brief(
        "Spray plan, block C: where practicable the sprayer should stay roughly 20 m back from water "
        "(drift buffer). This is guidance, not a hard line.",
        "analyst",
        "distance_soft",
        NB,
        (("soft_zone", "water", 20),),
        (Route("nb1", "farther", "water"), Route("nb2", "farther", "water")),
    ),
    Brief(
        "if dist(p, building) < 6: cost += 0.3   # soft penalty, still passable\n"
        "if dist(p, road) < 4: cost += 0.2   # soft, same idea",
        "robot",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "building", 6), ("soft_zone", "road", 4)),
        (Route("sample", "farther", "building"),),
        why="Pseudo-code adding cost near a class, marked 'soft ... still passable': soft zones of 6 m and 4 m.",
    ),
    Brief(
        "Now when I was a girl we walked everywhere, none of these machines, but never mind that. You'd "
        "want to keep, oh, ten metres or so from the water if you can manage it, my late husband always "
        "said that bank gives way. And the baseball field, the grandchildren play there, so go round it "
        "if it's no bother.",
        "field",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "water", 10), ("avoided", "baseball field")),
        (Route("sample", "farther", "water"), Route("sample", "less_on", "baseball field")),
        why="'ten metres or so ... if you can manage it' is soft; 'go round it if it's no bother' avoids "
        "the baseball field without forbidding it. The digressions are expected to do nothing.",
    ),
    Brief(
        "Mower bot, cemetery rules: keep roughly 2 m off the trees where you can, the roots are "
        "everywhere. And stay off the graves.",
        "field",
        "distance_soft",
        TREE,
        (("soft_zone", "tree", 2), ("unread", "graves")),
        (Route("neon", "farther", "tree"),),
        why="'roughly ... where you can' is soft; graves are no layer, so that clause is reported.",
    ),
    Brief(
        "SOFT_BUFFER water 5m\nSOFT_BUFFER railway 10m\nPREFER road",
        "robot",
        "distance_soft",
        NB,
        (("soft_zone", "water", 5), ("soft_zone", "railway", 10), ("preferred", "road")),
        (
            Route("nb1", "farther", "water"),
            Route("nb2", "farther", "railway"),
            Route("nb1", "more_on", "road"),
        ),
    ),
    Brief(
        "Ideally, I think, the route would probably stay something like 40 m from the buildings, though "
        "honestly that's more a preference than a rule.",
        "analyst",
        "distance_soft",
        BUILDING,
        (("soft_zone", "building", 40),),
        (Route("massachusetts", "farther", "building"),),
        why="Hedged throughout ('ideally', 'probably', 'more a preference than a rule'): soft, the number kept.",
    ),
    # ------------------------------------------------------------------------------------------
    # graded_away
    # ------------------------------------------------------------------------------------------
    Brief(
        "I'm in a powerchair, so the further from the water the better, one slip on a wet bank and I'm "
        "in it. Road's best for me, trail if it has to be, grass is hard going.",
        "field",
        "graded_away",
        SAMPLE,
        (
            ("graded_away", "water", None),
            ("below", "road", "trail"),
            ("below", "trail", "grass"),
            ("avoided", "building"),
        ),
        (Route("sample", "farther", "water"),),
        why="'the further the better' grades by distance; 'best ... if it has to be ... hard going' is a "
        "ranking without levels, so only the order; buildings are unmentioned and stay at their prior.",
    ),
    Brief(
        'avoid_gradient = {"water": 30, "building": 15}  # metres; penalty falls off with distance, '
        "nothing beyond that range",
        "robot",
        "graded_away",
        SAMPLE,
        (("graded_away", "water", 30), ("graded_away", "building", 15)),
        (Route("sample", "farther", "water"), Route("sample", "farther", "building")),
        why="A penalty falling off with distance to nothing at the stated range: graded, reaching neutral "
        "at 30 m and 15 m.",
    ),
    Brief(
        "Don't go near the trees if you can help it, the closer you get the worse the snow is under them.",
        "field",
        "graded_away",
        TREE,
        (("graded_away", "tree", None),),
        (Route("neon", "farther", "tree"),),
        why="A groomer's 'don't go near ... the closer the worse': priced by distance, nothing kept out; "
        "the snow is the reason, not a condition.",
    ),
    Brief(
        "Given that I'd rather not explain to the client why the rover went for a swim, the less time it "
        "spends near the water the happier I'll be.",
        "analyst",
        "graded_away",
        NB,
        (("graded_away", "water", None), ("avoided", "water")),
        (Route("nb1", "farther", "water"), Route("nb2", "farther", "water")),
        why="Understatement: no forbidding word, so the water is avoided (not lethal) and its "
        "surroundings are dearer the nearer they are.",
    ),
    Brief(
        "Haul-road standard HR-2: route cost shall rise with proximity to site buildings, the nearer the "
        "dearer, with no added cost beyond 50 m.",
        "analyst",
        "graded_away",
        BUILDING,
        (("graded_away", "building", 50),),
        (Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        "proximity_penalty: railway (rises as distance falls). vegetation: ok.",
        "robot",
        "graded_away",
        NB,
        (("graded_away", "railway", None), ("neutral", "vegetation")),
        (Route("nb2", "farther", "railway"),),
    ),
    Brief(
        "Tip from me, since you're new on the Kampala run: the closer you ride to the houses the more kids "
        "and chickens jump out, so keep well away from the buildings wherever the lane gives you room.",
        "field",
        "graded_away",
        BUILDING,
        (("graded_away", "building", None),),
        (Route("kampala", "farther", "building"),),
        why="'keep well away' with 'the closer ... the more': graded, nothing kept out.",
    ),
    # ------------------------------------------------------------------------------------------
    # graded_toward
    # ------------------------------------------------------------------------------------------
    Brief(
        "Handrail it: stay close to the trail the whole leg so you never lose contact, even where you cut "
        "a corner over the grass.",
        "field",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "trail", None), ("not_lethal", "grass"), ("avoided", "water")),
        (Route("sample", "closer", "trail"),),
        why="An orienteering handrail: cheaper the nearer the trail; cutting corners over the grass is "
        "allowed; the unmentioned water stays at its prior.",
    ),
    Brief(
        "The ground unit is to keep within sight of the road throughout, the closer the better, as the "
        "support truck will be following on it.",
        "analyst",
        "graded_toward",
        NB,
        (("graded_toward", "road", None),),
        (Route("nb1", "closer", "road"),),
    ),
    Brief(
        "cost(p) = base(p) - k / (1 + dist(p, paved_road))   # pull toward the paved road",
        "robot",
        "graded_toward",
        VEGAS,
        (("graded_toward", "paved road", None),),
        (Route("vegas", "closer", "paved road"),),
        why="A cost falling as the distance to the paved road falls: cheaper the nearer ('paved_road' "
        "is the multi-word class with an underscore).",
    ),
    Brief(
        "Stay near the buildings, love, where people can see you, and try not to go through the trees.",
        "field",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "building", None), ("avoided", "tree")),
        (Route("sample", "closer", "building"), Route("sample", "less_on", "tree")),
        why="'try not to go through' avoids the trees without forbidding them.",
    ),
    Brief(
        "Accessible route requirement: the route should hug the paved road, the nearer the better, since "
        "that is where the kerb ramps are. Unpaved road surfaces are unsuitable and should be avoided.",
        "analyst",
        "graded_toward",
        VEGAS,
        (("graded_toward", "paved road", None), ("avoided", "unpaved road")),
        (Route("vegas", "closer", "paved road"),),
    ),
    Brief(
        "Oye, el robot tiene que ir cerca del road, lo más cerca posible, ¿vale? Y el water está prohibido, eh.",
        "field",
        "graded_toward",
        NB,
        (("graded_toward", "road", None), ("lethal", "water")),
        (Route("nb1", "closer", "road"), Route("nb1", "zero_on", "water")),
        why="Spanish-English: 'cerca del road, lo más cerca posible' (near the road, as near as possible) "
        "is stay-close; 'prohibido' (prohibited) forbids the water.",
    ),
    Brief(
        "MODE=SHADE. Hug the tree crowns (closer = cheaper) to keep the battery cool.",
        "robot",
        "graded_toward",
        TREE,
        (("graded_toward", "tree", None),),
        (Route("neon", "closer", "tree"),),
    ),
    # ------------------------------------------------------------------------------------------
    # on_beside
    # ------------------------------------------------------------------------------------------
    Brief(
        "Walk the line alongside the road, not on it, the marker posts are all on the shoulder.",
        "field",
        "on_beside",
        NB,
        (("beside", "road"),),
        (Route("nb1", "beside", "road", 5),),
    ),
    Brief(
        "follow(railway, offset_m=3, on_track=False)",
        "robot",
        "on_beside",
        NB,
        (("beside", "railway"),),
        (Route("nb2", "beside", "railway", 6),),
        why="Following the railway at an offset, never on the track: beside it.",
    ),
    Brief(
        "Dismounted sections will move parallel to the road, off the road surface, using the verge for cover.",
        "analyst",
        "on_beside",
        NB,
        (("beside", "road"),),
        (Route("nb1", "beside", "road", 5),),
    ),
    Brief(
        "Run the buggy along the water's edge, but stay out of the water itself.",
        "field",
        "on_beside",
        SAMPLE,
        (("beside", "water"), ("lethal", "water")),
        (Route("sample", "beside", "water", 5), Route("sample", "zero_on", "water")),
        why="'stay out of' forbids the water; 'along the water's edge' prefers the band beside it.",
    ),
    Brief(
        "Mow along the avenue of trees, just off the crowns. Don't go under them, the branches are too low "
        "for the mower.",
        "field",
        "on_beside",
        TREE,
        (("beside", "tree"),),
        (Route("neon", "beside", "tree", 3),),
        why="'Don't go under them' is not one of the forbidding phrases, so only 'avoided or lethal' "
        "(what beside asks) is expected of the trees themselves.",
    ),
    Brief(
        'path_rule = {"follow": "trail", "on_trail": False, "side_offset_m": 2}',
        "robot",
        "on_beside",
        SAMPLE,
        (("beside", "trail"),),
        (Route("sample", "beside", "trail", 5),),
    ),
    Brief(
        "Airside tugs shall travel beside the paved road, on the apron edge, and shall not drive on the "
        "paved road itself.",
        "analyst",
        "on_beside",
        VEGAS,
        (("beside", "paved road"),),
        (Route("vegas", "beside", "paved road", 5),),
    ),
    # ------------------------------------------------------------------------------------------
    # qualified
    # ------------------------------------------------------------------------------------------
    Brief(
        "Quads stick to the unpaved roads between the blocks. The paved road is for the trucks, so keep "
        "off it unless you're crossing over.",
        "field",
        "qualified",
        VEGAS,
        (("preferred", "unpaved road"), ("avoided", "paved road"), ("below", "unpaved road", "paved road")),
        (Route("vegas", "less_on", "paved road"),),
        why="A vineyard manager: 'stick to' prefers the unpaved roads; 'keep off it unless you're "
        "crossing' leaves the paved road passable but avoided.",
    ),
    Brief(
        "Light vehicles are permitted on the paved road. Unpaved haul roads are a no-go for light vehicles.",
        "analyst",
        "qualified",
        VEGAS,
        (("neutral", "paved road"), ("lethal", "unpaved road")),
        (Route("vegas", "zero_on", "unpaved road"),),
    ),
    Brief(
        "Auf der paved road ist alles gut. Die unpaved road bitte meiden, da liegt zu viel Schotter.",
        "field",
        "qualified",
        VEGAS,
        (("neutral", "paved road"), ("avoided", "unpaved road")),
        why="German-English: 'alles gut' (all fine) permits the paved road; 'meiden' (avoid) avoids the "
        "unpaved one; the gravel ('Schotter') is the reason.",
    ),
    Brief(
        "Grounds policy: maintenance vehicles are to avoid the grass, with one exception: the baseball "
        "field, which they may cross freely.",
        "analyst",
        "qualified",
        SAMPLE,
        (("avoided", "grass"), ("neutral", "baseball field")),
        (Route("sample", "less_on", "grass"),),
        why="The excepted sub-area is a layer of its own: the grass is avoided, the baseball field "
        "permitted (neutral).",
    ),
    Brief(
        "The yews by the chapel are conifers and the families are touchy about them, so keep the mower "
        "out from under the conifers. The big deciduous ones, the oaks, you can go under, no bother.",
        "field",
        "qualified",
        TREE,
        (("unread", "conifer"), ("not_lethal", "tree")),
        why="The tree layer does not tell conifers from deciduous trees, so the conifer rule cannot be "
        "carried and must be reported; with half the trees expressly allowed, the whole layer must not "
        "be made impassable.",
    ),
    Brief(
        "water: avoid\nEXCEPT: the ford at the road crossing -> ok",
        "robot",
        "qualified",
        NB,
        (("avoided", "water"), ("unread", "ford")),
        (Route("nb1", "less_on", "water"),),
        why="The excepted sub-area (a ford) is marked by no layer: the exception is reported, not applied "
        "to all water.",
    ),
    Brief(
        "surface: unpaved only. trail = prefer. road (paved) = avoid.",
        "robot",
        "qualified",
        SAMPLE,
        (("preferred", "trail"), ("avoided", "road")),
        (Route("sample", "more_on", "trail"), Route("sample", "less_on", "road")),
    ),
    # ------------------------------------------------------------------------------------------
    # terse
    # ------------------------------------------------------------------------------------------
    Brief(
        "pavd road >> unpavd road",
        "robot",
        "terse",
        VEGAS,
        (("below", "paved road", "unpaved road"),),
        why="Typos in both multi-word names; an order without levels.",
    ),
    Brief(
        "bldg: 10m hard. watr: no.",
        "robot",
        "terse",
        SAMPLE,
        (("keep_out", "building", 10), ("lethal", "water")),
        (Route("sample", "keeps", "building", 10), Route("sample", "zero_on", "water")),
        why="'bldg' and 'watr' are building and water; '10m hard' a hard 10 m zone; 'X: no' is the terse "
        "form of 'no X', a prohibition.",
    ),
    Brief(
        "rd fine. trees no. grass meh",
        "field",
        "terse",
        SAMPLE,
        (("neutral", "road"), ("lethal", "tree"), ("below", "road", "grass")),
        (Route("sample", "zero_on", "tree"),),
        why="A courier's SMS: 'rd fine' permits the road; 'trees no' forbids the trees; 'grass meh' is "
        "lukewarm, so grass is only expected to rank behind the road.",
    ),
    Brief(
        "baseball feild: NO GO. trail ok. grass ok.",
        "robot",
        "terse",
        SAMPLE,
        (("lethal", "baseball field"), ("neutral", "trail"), ("neutral", "grass")),
        (Route("sample", "zero_on", "baseball field"),),
        why="'feild' is a typo in the multi-word name; 'NO GO' forbids.",
    ),
    Brief(
        "c(railway) ≫ c(water) > c(vegetation)",
        "analyst",
        "terse",
        NB,
        (("below", "water", "railway"), ("below", "vegetation", "water")),
        why="Cost terms ordered with '≫' and '>': the order only.",
    ),
    Brief(
        "Legs 3 to 5: trail +, grass -, trees --",
        "field",
        "terse",
        SAMPLE,
        (("below", "trail", "grass"), ("below", "grass", "tree")),
        why="An orienteering coach's marks: '+' better than '-' better than '--'; the order only.",
    ),
    Brief(
        "costs: road 0.2, grass 0.6, water 1.0 (impassable)",
        "robot",
        "terse",
        SAMPLE,
        (("preferred", "road"), ("avoided", "grass"), ("lethal", "water")),
        (Route("sample", "more_on", "road"), Route("sample", "zero_on", "water")),
    ),
    Brief(
        "unpavd rd fine. pavd rd fine too. no prefs",
        "robot",
        "terse",
        VEGAS,
        (("neutral", "unpaved road"), ("neutral", "paved road")),
        why="'X fine' with the multi-word names misspelt and abbreviated: both permitted, neither preferred.",
    ),
    # ------------------------------------------------------------------------------------------
    # permission
    # ------------------------------------------------------------------------------------------
    Brief(
        "You're allowed to go under the trees, and yes you can cut through the baseball field if nobody's "
        "playing on it. Stay out of the water, obviously.",
        "field",
        "permission",
        SAMPLE,
        (("neutral", "tree"), ("lethal", "water"), ("unread", "playing")),
        (Route("sample", "zero_on", "water"),),
        why="'allowed' lifts the trees' prior to neutral; the baseball-field permission hangs on whether "
        "anyone is playing, which no layer carries; 'stay out of' forbids the water.",
    ),
    Brief(
        '"Permitted Areas" means the Road and any ground beneath Trees. The Vehicle may traverse any '
        "Permitted Area. The Vehicle shall keep out of the Water.",
        "analyst",
        "permission",
        SAMPLE,
        (("neutral", "road"), ("neutral", "tree"), ("lethal", "water")),
        (Route("sample", "zero_on", "water"),),
        why="Defined terms: the Permitted Areas (road, trees) may be traversed, a permission (neutral); "
        "'keep out of' forbids the water.",
    ),
    Brief(
        "To be clear, it is not the case that the rover can't cross the water; it can, the channel is "
        "ankle deep. And don't not use the road where there is one.",
        "analyst",
        "permission",
        NB,
        (("neutral", "water"), ("preferred", "road")),
        (Route("nb1", "more_on", "road"),),
        why="Double negatives: 'not the case that it can't' permits the water (lifting its prior to "
        "neutral); 'don't not use the road' asks for the road.",
    ),
    Brief(
        'permissions = {"water": "allowed", "tree": "allowed", "building": "forbidden"}',
        "robot",
        "permission",
        SAMPLE,
        (("neutral", "water"), ("neutral", "tree"), ("lethal", "building")),
        (Route("sample", "zero_on", "building"),),
    ),
    Brief(
        "The inspection trolley is permitted on the railway. This permission applies only between 02:00 and 04:00.",
        "analyst",
        "permission",
        NB,
        (("not_lethal", "railway"), ("unread", "02:00")),
        why="The permission is read, but the clock-time window it hangs on is carried by no layer and "
        "must be reported; since the railway's level outside the window is unclear, only 'not lethal' "
        "is expected.",
    ),
    Brief(
        "You go wherever you like, dear, under the trees, over the grass, it's all the same to me, only "
        "mind you don't go into the water, that's all I ask.",
        "field",
        "permission",
        SAMPLE,
        (("neutral", "tree"), ("neutral", "grass"), ("lethal", "water")),
        (Route("sample", "zero_on", "water"),),
    ),
    Brief(
        "Puedes pasar por los buildings, no pasa nada, están abiertos. Pero el railway, ni hablar: es no-go.",
        "field",
        "permission",
        NB,
        (("neutral", "building"), ("lethal", "railway")),
        (Route("nb2", "zero_on", "railway"),),
        why="Spanish-English: 'puedes pasar ... no pasa nada' (you can go through, no problem) permits "
        "the buildings, lifting their prior; 'ni hablar: es no-go' forbids the railway.",
    ),
    Brief(
        "ALLOW building\nDENY water",
        "robot",
        "permission",
        NB,
        (("neutral", "building"), ("lethal", "water")),
        (Route("nb1", "zero_on", "water"),),
        why="ALLOW is a permission (neutral); DENY forbids.",
    ),
    Brief(
        "Hmm, probably trail over grass, I guess? Road's allowed too, I think. Buildings are off limits "
        "though, that one's definite.",
        "analyst",
        "permission",
        SAMPLE,
        (("below", "trail", "grass"), ("neutral", "road"), ("lethal", "building")),
        (Route("sample", "zero_on", "building"),),
        why="A hedged ranking is still an order (trail below grass, no level); the hedged 'allowed' is "
        "a permission; 'off limits' forbids.",
    ),
    # ------------------------------------------------------------------------------------------
    # clauses
    # ------------------------------------------------------------------------------------------
    Brief(
        "UNIT 4: PREFER ROAD. IF TIDE COMING IN, AVOID WATER EVEN MORE.",
        "robot",
        "clauses",
        SAMPLE,
        (("preferred", "road"), ("unread", "tide"), ("avoided", "water")),
        (Route("sample", "more_on", "road"),),
        why="The tide is carried by no layer, so the conditional clause is reported; the water stays "
        "avoided at least at its prior.",
    ),
    Brief(
        "Between sunset and sunrise, vehicles shall keep 10 m from buildings; in daylight, 3 m.",
        "analyst",
        "clauses",
        BUILDING,
        (("unread", "sunset"), ("unread", "daylight")),
        why="Both distances hang on the time of day, which no layer carries: both clauses are reported.",
    ),
    Brief(
        "Stay well clear of the trees, and if the wind gets above 40 km/h just park it.",
        "field",
        "clauses",
        TREE,
        (("graded_away", "tree", None), ("unread", "wind")),
        (Route("neon", "farther", "tree"),),
        why="'Stay well clear' is keep-well-away (graded); the wind clause hangs on weather.",
    ),
    Brief(
        'mission = {"prefer": ["trail"], "avoid": ["water"], "avoid_if_raining": ["grass"], "max_pedestrians": 3}',
        "robot",
        "clauses",
        SAMPLE,
        (("preferred", "trail"), ("avoided", "water"), ("unread", "raining"), ("unread", "pedestrians")),
        (Route("sample", "more_on", "trail"),),
        why="The rain condition and the pedestrian count are carried by no layer.",
    ),
    Brief(
        "During blasting windows all vehicles are to avoid the road. Keep out of the water at all times, "
        "and keep away from the fuel bowser.",
        "analyst",
        "clauses",
        NB,
        (("unread", "blasting"), ("lethal", "water"), ("unread", "bowser")),
        (Route("nb1", "zero_on", "water"),),
        why="The road rule hangs on blasting windows (time); the fuel bowser is no layer; 'keep out of' "
        "forbids the water.",
    ),
    Brief(
        "At rush hour the road's a nightmare, so take the trail then. Never go into the water, mate, obviously.",
        "field",
        "clauses",
        SAMPLE,
        (("unread", "rush hour"), ("lethal", "water")),
        (Route("sample", "zero_on", "water"),),
        why="The road/trail advice hangs on rush hour (traffic, time); 'never go into' forbids.",
    ),
    Brief(
        "Accessibility request: paved road wherever there is a choice; unpaved road only when nothing else "
        "gets through.",
        "analyst",
        "clauses",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road"), ("all_read",)),
        (Route("vegas", "more_on", "paved road"),),
        why="Every clause is about a layer: paved preferred, unpaved a last resort (avoided, passable).",
    ),
    Brief(
        "avoid(road) if traffic > LIGHT else prefer(road)\nkeep_out(water, 5)",
        "robot",
        "clauses",
        NB,
        (("unread", "traffic"), ("keep_out", "water", 5)),
        (Route("nb1", "keeps", "water", 5),),
        why="The road rule hangs on traffic; keep_out(water, 5) is a hard 5 m zone.",
    ),
]

DOUBTFUL: dict[str, str] = {}
