"""Mission briefs, set 21: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench, the docs or the briefs of earlier sets: only the contract
(``tests/mission_briefs.py`` and its format test ``tests/test_mission_briefs.py``), the scene index
(``../shared/scenes/INDEX.md`` and the scenes' ``classes.json``) and the first 40 lines of set 20
(for the layout of its module constants and docstring) were read. It is scored once, at first
contact, with ``bench/mission_briefs_report.py --set 21``; that figure is the one that counts, and
the set is not edited afterwards to make the interpreter pass.

The voices are a vineyard manager, a utility-line inspector on a pole-line patrol, an
archaeologist protecting a dig, a farmer talking casually ("ya", "outta", "y'all", "blacktop"), a
military-style terse order ("Axis of advance: road. Railway: no-go.") and someone who rambles with
asides about colleagues and landmarks (field crews); a wheelchair-accessibility auditor, a writer
of spreadsheet-like "class: cost" and "surface | cost" tables and an over-polite email with
greetings and apologies (analysts); a drone-delivery dispatcher writing dispatch tickets, a text
message with abbreviations ("pls", "rd", "bldgs", "n", "thx", "nvr go in2", "pvd rd", "u"),
someone who corrects themself mid-sentence ("avoid the vegetation -- no wait, vegetation is
fine"), conditional phrasing ("if there's a road, take it; if there isn't ...") and negated
preferences ("I don't mind the trees", "not that I care much about the grass", "I'm not fussed
about the buildings") (robot operators and field crews). Non-native English speakers bring
translated idioms: Spanish ("more far, more better", "the road of earth", "it is prohibited to
enter"), German ("hold 15 metres distance", "over the road it likes to drive", "in the nearness
of", "from 4 metres on it is all the same"), Chinese ("this is the red line", "the nearer, the more
danger") and Arabic ("God willing", "like its shadow", "like the eye that never leaves its
beloved").

The constructs are ranked preferences (chains "A beats B, B beats C", conditional fall-backs "if A
..., otherwise B, only if neither, C", "A rather than B", "A first", symbolic "then" and cost
tables with words or numbers), forbidden areas ("stay out of", "no-go", "never enter", "off
limits", "cannot go in", "under no circumstances enter", "impassable", "forbidden", "do not
enter", "stay outta", "nvr go in2") against plain avoidance ("avoid", "bypass", "mind the water",
"avoid them where it's easy"), permissions that lift priors (buildings a drone flies over, company
buildings, market stalls labelled building, empty holiday lets, waterproof drones over water,
trees the writer does not mind, a railway that is "ok if needed" or not a bother), hard distance rules
with numbers in metres, feet and yards (some spelled out: "eight metres", "two metres") and
absolute wording ("no exceptions", "I mean never", "under no circumstances", "without fail",
"at all times", "insists ... never"), soft distance rules ("if possible ... it is no must",
"a guideline rather than a rule", "where practical", "if you can ... not a rule", "ideally",
"if you can manage"), graded nearness both ways ("more far, more better", "the closer the worse,
though past about 30 metres I don't care", "after 5 metres it is all the same", "the nearer it
keeps, the better", "as close ... as it reasonably can", "as near as possible"), on versus beside
(a couple of metres off the road, a stream bank, a pole line beside the road, the paved road's
edge, hugging the walls of houses, the open ground beside tree crowns, a power line not flown
over), qualified classes on the Las Vegas scene (paved road as asphalted road and blacktop
against unpaved road as the road of earth and a gravel road) and an excepted sub-area (grass
avoided but the baseball field allowed), typos ("trial", "raod", "feild", "pavd", "unpavd"), and
clauses naming things no layer stands for (guy wires, an old mill, trenches by an old cellar,
stairs and kerbs to note, transformer boxes, picnic tables and a playground, survey pegs, a ford),
which must be reported unread. The layers of each brief are the class names of the scene its
routes are checked on; briefs over layers no scene holds (vineyard, pole line, dig site,
accessibility, drone airspace, farm, battlefield, road surfaces) carry no route checks.
"""

from __future__ import annotations

from .mission_briefs import Brief, Route

#: New Brunswick clips (nb1, nb2).
NB = ("building", "road", "water", "vegetation", "railway")
#: Las Vegas roads.
VEGAS = ("paved road", "unpaved road")
#: Kampala informal settlement, and the Massachusetts suburb.
KAMPALA = ("building",)
MASSACHUSETTS = ("building",)
#: Florida forest plot (tree crowns).
NEON = ("tree",)
#: The bundled sample.
SAMPLE = ("grass", "road", "trail", "tree", "water", "building", "baseball field")
#: Layers no scene holds (no route checks).
VINEYARD = ("vine row", "headland", "irrigation pond")
POLE_LINE = ("power line", "substation", "access track")
DIG = ("trench", "spoil heap", "footpath")
ACCESS = ("sidewalk", "curb ramp", "stairs", "gravel", "grass")
AIRSPACE = ("street", "no-fly zone", "rooftop")
FARM = ("farm track", "hay field", "cattle pen")
BATTLEFIELD = ("ridge", "minefield", "river")
SURFACES = ("asphalt", "gravel", "mud", "ice")


NB_BRIEFS = [
    Brief(
        "Dispatch to courier drone 12: you fly above the rooftops today, so the buildings don't matter. "
        "Stay out of the rail corridor, though, and follow the road whenever it heads our way.",
        "robot",
        "permission",
        NB,
        (("neutral", "building"), ("not_lethal", "building"), ("lethal", "railway"), ("preferred", "road")),
        (Route("nb2", "zero_on", "railway"), Route("nb1", "more_on", "road")),
        why="'the buildings don't matter' lifts the building prior to neutral; 'stay out of' forbids the rail corridor.",
    ),
    Brief(
        "Ah, just go on through the bush, the vegetation won't hurt ya. Mind the water though, "
        "I don't want the thing wading about in it.",
        "field",
        "permission",
        NB,
        (("neutral", "vegetation"), ("avoided", "water"), ("not_lethal", "water")),
        (Route("nb1", "less_on", "water"),),
        why="'won't hurt ya' merely allows the vegetation; 'mind the water' is avoidance, not a prohibition.",
    ),
    Brief(
        "Axis of advance: road. Railway: no-go. Water: 20 m standoff, no exceptions. Buildings: bypass.",
        "field",
        "distance_hard",
        NB,
        (
            ("preferred", "road"),
            ("lethal", "railway"),
            ("keep_out", "water", 20),
            ("avoided", "building"),
            ("not_lethal", "building"),
        ),
        (
            Route("nb2", "zero_on", "railway"),
            Route("nb1", "keeps", "water", 20),
            Route("nb1", "more_on", "road"),
        ),
        why="A military order: 'no-go' forbids, a standoff 'no exceptions' is a hard zone, 'bypass' avoids.",
    ),
    Brief(
        "Line patrol, spans 14 to 22: take the road wherever you can, avoid the buildings, and watch out "
        "for the guy wires anchored by each pole.",
        "field",
        "clauses",
        NB,
        (("preferred", "road"), ("avoided", "building"), ("unread", "guy wire")),
        (Route("nb1", "more_on", "road"), Route("nb1", "less_on", "building")),
        why="No layer stands for guy wires or poles: that clause must be reported unread.",
    ),
    Brief(
        "Please, the robot must go far from the railway -- more far, more better. The road is good for him.",
        "robot",
        "graded_away",
        NB,
        (("graded_away", "railway", None), ("preferred", "road")),
        (Route("nb2", "farther", "railway"),),
        why="Spanish 'cuanto más lejos, mejor': the further from the railway the better.",
    ),
    Brief(
        "The route should if possible hold 15 metres distance to the water; it is no must, but it would "
        "be nice. Over the road it likes to drive.",
        "robot",
        "distance_soft",
        NB,
        (("soft_zone", "water", 15), ("preferred", "road")),
        (Route("nb1", "more_on", "road"),),
        why="German 'Abstand halten ... kein Muss': a soft 15 m zone; 'fährt gern über die Straße': road preferred.",
    ),
    Brief(
        "The buildings all belong to our company, the robot can pass through them, no problem. But the "
        "water, absolutely cannot go in -- this is the red line.",
        "field",
        "permission",
        NB,
        (("neutral", "building"), ("not_lethal", "building"), ("lethal", "water")),
        (Route("nb1", "zero_on", "water"),),
        why="Chinese 红线 ('red line') marks an absolute limit; 'cannot go in' forbids the water.",
    ),
    Brief(
        "God willing, the vehicle stays near the road, following it like its shadow; the nearer it keeps, the better.",
        "robot",
        "graded_toward",
        NB,
        (("graded_toward", "road", None),),
        (Route("nb1", "closer", "road"),),
    ),
    Brief(
        "pls stay on rd, avoid bldgs n water, rail ok if needed thx",
        "robot",
        "terse",
        NB,
        (
            ("preferred", "road"),
            ("avoided", "building"),
            ("avoided", "water"),
            ("not_lethal", "railway"),
            ("below", "road", "railway"),
        ),
        (Route("nb1", "more_on", "road"), Route("nb1", "less_on", "building")),
        why="A text message: rd = road, bldgs = buildings, rail = railway; 'ok if needed' allows the railway.",
    ),
    Brief(
        "Avoid the vegetation -- no wait, vegetation is fine, it's the water I meant. Avoid the water.",
        "robot",
        "clauses",
        NB,
        (("neutral", "vegetation"), ("avoided", "water"), ("not_lethal", "water"), ("all_read",)),
        (Route("nb1", "less_on", "water"),),
        why="The writer takes back 'avoid the vegetation': only the correction stands.",
    ),
    Brief(
        "If there's a road, take it. If there isn't, cut across the vegetation rather than through a building.",
        "field",
        "clauses",
        NB,
        (("preferred", "road"), ("below", "road", "vegetation"), ("below", "vegetation", "building"), ("all_read",)),
        (Route("nb1", "more_on", "road"),),
        why="A conditional fall-back is a ranking: road, then vegetation, then buildings.",
    ),
    Brief(
        "I don't mind the vegetation, and I'm not bothered about the railway either, but I really don't "
        "want it going near the water.",
        "field",
        "permission",
        NB,
        (("neutral", "vegetation"), ("neutral", "railway"), ("not_lethal", "railway"), ("graded_away", "water", None)),
        (Route("nb1", "farther", "water"),),
        why="Negated preferences allow (the railway prior lifted to neutral); 'near the water' is graded.",
    ),
    Brief(
        "class: cost\nroad: 0.1\nvegetation: 0.5\nbuilding: 0.9\nwater: forbidden",
        "analyst",
        "terse",
        NB,
        (
            ("preferred", "road"),
            ("neutral", "vegetation"),
            ("avoided", "building"),
            ("not_lethal", "building"),
            ("lethal", "water"),
        ),
        (
            Route("nb1", "zero_on", "water"),
            Route("nb1", "more_on", "road"),
            Route("nb1", "less_on", "building"),
        ),
        why="A spreadsheet table on the cost scale: 0.1 preferred, 0.5 neutral, 0.9 avoided, 'forbidden' lethal.",
    ),
    Brief(
        "So we're taking the survey rover out past the old mill this afternoon -- Dave's meeting it at the "
        "far end, assuming he's on time for once -- and what I'd like is for it to keep its distance from "
        "the railway, the closer the worse, though past about 30 metres I honestly don't care, and apart "
        "from that it can wander wherever it likes.",
        "field",
        "graded_away",
        NB,
        (("graded_away", "railway", 30), ("unread", "mill")),
        (Route("nb2", "farther", "railway"),),
        why="A graded fall-off reaching neutral at 30 m; the old mill is named and no layer stands for it.",
    ),
    Brief(
        "Run parallel to the road, a couple of metres off it, but never on the road itself.",
        "robot",
        "on_beside",
        NB,
        (("beside", "road"),),
        (Route("nb1", "beside", "road", 5),),
    ),
    Brief(
        "Field season rule: the rover must never come within 40 feet of any building, no exceptions, and "
        "the trenches beside the old cellar are not to be touched.",
        "field",
        "distance_hard",
        NB,
        (("keep_out", "building", 12.192), ("unread", "trench")),
        (Route("nb1", "keeps", "building", 12.192),),
        why="40 ft = 12.192 m, absolute; the dig's trenches have no layer and must be reported unread.",
    ),
]


SAMPLE_BRIEFS = [
    Brief(
        "Trail beats road, road beats grass, and anything beats pushing through the trees.",
        "robot",
        "terse",
        SAMPLE,
        (("below", "trail", "road"), ("below", "road", "grass"), ("below", "grass", "tree"), ("avoided", "tree")),
        (Route("sample", "more_on", "trail"), Route("sample", "less_on", "tree")),
    ),
    Brief(
        "We prefer the trail, and the grass also is fine. In the water no -- it is prohibited to enter.",
        "field",
        "permission",
        SAMPLE,
        (("preferred", "trail"), ("neutral", "grass"), ("below", "trail", "grass"), ("lethal", "water")),
        (Route("sample", "more_on", "trail"), Route("sample", "zero_on", "water")),
        why="Spanish 'está prohibido entrar': forbidden; 'también está bien': the grass merely allowed.",
    ),
    Brief(
        "Accessibility audit route: grass and the baseball field are heavy going for a wheelchair, so avoid "
        "both; stick to the road and the trail, road first. Also note any stairs or kerbs you come across.",
        "analyst",
        "clauses",
        SAMPLE,
        (
            ("avoided", "grass"),
            ("avoided", "baseball field"),
            ("preferred", "road"),
            ("preferred", "trail"),
            ("below", "road", "trail"),
            ("unread", "stairs"),
        ),
        (Route("sample", "more_on", "road"), Route("sample", "less_on", "grass")),
        why="No layer stands for stairs or kerbs: the note-taking clause must be reported unread.",
    ),
    Brief(
        "Dear team, I hope this message finds you well. If it is not too much trouble, might I kindly ask "
        "that the rover keep as close to the trail as it reasonably can? Many thanks in advance for your "
        "consideration. Warm regards, Priya",
        "analyst",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "trail", None),),
        (Route("sample", "closer", "trail"),),
    ),
    Brief(
        "Never get within 15 yards of the water. I mean never.",
        "field",
        "distance_hard",
        SAMPLE,
        (("keep_out", "water", 13.716),),
        (Route("sample", "keeps", "water", 13.716),),
        why="15 yd = 13.716 m, worded absolutely.",
    ),
    Brief(
        "Follow the stream along its bank -- don't get the wheels wet, but stay right alongside the water the whole way.",
        "field",
        "on_beside",
        SAMPLE,
        (("beside", "water"),),
        (Route("sample", "beside", "water", 5),),
    ),
    Brief(
        "Avoid the grass, except the baseball field -- that one's fine to cross.",
        "field",
        "qualified",
        SAMPLE,
        (
            ("avoided", "grass"),
            ("not_lethal", "grass"),
            ("neutral", "baseball field"),
            ("not_lethal", "baseball field"),
        ),
        (Route("sample", "less_on", "grass"),),
        why="An excepted sub-area: the baseball field is grass-like but allowed, so it is held neutral.",
    ),
    Brief(
        "Prefer the trial and the raod; stay out of the baseball feild.",
        "robot",
        "terse",
        SAMPLE,
        (("preferred", "trail"), ("preferred", "road"), ("lethal", "baseball field")),
        (Route("sample", "more_on", "trail"), Route("sample", "zero_on", "baseball field")),
        why="Typos: trial = trail, raod = road, feild = field; 'stay out of' forbids.",
    ),
    Brief(
        "If the trail goes where we're headed, use it; otherwise use the road; only if neither works, go over the grass.",
        "robot",
        "clauses",
        SAMPLE,
        (("preferred", "trail"), ("below", "trail", "road"), ("below", "road", "grass"), ("all_read",)),
        (Route("sample", "more_on", "trail"),),
        why="A chain of conditional fall-backs is a ranking: trail, road, grass.",
    ),
    Brief(
        "Not that I care much about the grass, and I don't mind the trees either, but stay out of the "
        "baseball field -- there's a game on.",
        "field",
        "permission",
        SAMPLE,
        (("neutral", "grass"), ("neutral", "tree"), ("not_lethal", "tree"), ("lethal", "baseball field")),
        (Route("sample", "zero_on", "baseball field"),),
        why="Negated preferences merely allow: the grass neutral, the tree prior lifted to neutral.",
    ),
    Brief(
        "Thunderstorms forecast: the closer to the trees, the worse, but out past 20 m it no longer matters.",
        "field",
        "graded_away",
        SAMPLE,
        (("graded_away", "tree", 20),),
        (Route("sample", "farther", "tree"),),
    ),
    Brief(
        "Route: trail, then road. Water: do not cross. Treeline: avoid.",
        "field",
        "terse",
        SAMPLE,
        (("preferred", "trail"), ("below", "trail", "road"), ("no_cross", "water"), ("avoided", "tree")),
        (
            Route("sample", "more_on", "trail"),
            Route("sample", "zero_on", "water"),
            Route("sample", "less_on", "tree"),
        ),
        why="A terse order: 'do not cross' is a never-cross rule; the treeline is the trees.",
    ),
    Brief(
        "Drop-off run 88: the drone flies low, so treat the trees as a no-fly zone -- never enter the canopy. "
        "Flying over water is fine, the unit is waterproof.",
        "robot",
        "permission",
        SAMPLE,
        (("lethal", "tree"), ("neutral", "water"), ("not_lethal", "water")),
        (Route("sample", "zero_on", "tree"),),
        why="'never enter' forbids the trees; 'fine' lifts the water prior to neutral.",
    ),
    Brief(
        "Pole-line inspection along the road: keep beside the road, never on it, and stay 5 m clear of the "
        "transformer boxes.",
        "field",
        "on_beside",
        SAMPLE,
        (("beside", "road"), ("unread", "transformer")),
        (Route("sample", "beside", "road", 5),),
        why="No layer stands for transformer boxes: that clause must be reported unread.",
    ),
    Brief(
        "Under no circumstances may the route pass closer than eight metres to the water's edge.",
        "analyst",
        "distance_hard",
        SAMPLE,
        (("keep_out", "water", 8),),
        (Route("sample", "keeps", "water", 8),),
    ),
    Brief(
        "Take the grass -- sorry, I mean the trail; the grass is muddy today, so avoid it.",
        "robot",
        "clauses",
        SAMPLE,
        (("preferred", "trail"), ("avoided", "grass"), ("not_lethal", "grass"), ("all_read",)),
        (Route("sample", "more_on", "trail"), Route("sample", "less_on", "grass")),
        why="The first clause is corrected: the trail is wanted, the grass avoided.",
    ),
    Brief(
        "Keep to the trail, and steer clear of the picnic tables and the playground.",
        "field",
        "clauses",
        SAMPLE,
        (("preferred", "trail"), ("unread", "picnic"), ("unread", "playground")),
        (Route("sample", "more_on", "trail"),),
        why="No layer stands for picnic tables or a playground.",
    ),
    Brief(
        "If you can manage, keep half a dozen metres from the trees; closer is allowed when there's no other way through.",
        "robot",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "tree", 6),),
        (Route("sample", "less_on", "tree"),),
        why="Half a dozen metres = 6 m, worded softly.",
    ),
]


VEGAS_BRIEFS = [
    Brief(
        "Delivery bot 3: keep to the paved road as much as you can; the unpaved road rattles the parcels, so avoid it.",
        "robot",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road"), ("not_lethal", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        "The road of earth is forbidden for the truck; it goes only by the asphalted road.",
        "field",
        "qualified",
        VEGAS,
        (("lethal", "unpaved road"), ("preferred", "paved road")),
        (Route("vegas", "zero_on", "unpaved road"), Route("vegas", "more_on", "paved road")),
        why="Spanish 'camino de tierra' is the unpaved road, 'carretera asfaltada' the paved one.",
    ),
    Brief(
        "stay on the pavd raod, avoid the unpavd one",
        "robot",
        "terse",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road"), ("below", "paved road", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
        why="Typos in both multi-word names; 'the unpavd one' is the unpaved road.",
    ),
    Brief(
        "Survey walk: never closer than 10 feet to the paved road, the traffic is heavy.",
        "field",
        "distance_hard",
        VEGAS,
        (("keep_out", "paved road", 3.048),),
        (Route("vegas", "keeps", "paved road", 3.048),),
        why="10 ft = 3.048 m, worded absolutely.",
    ),
    Brief(
        "Stay alongside the paved road, just off the edge of the asphalt, never on it.",
        "robot",
        "on_beside",
        VEGAS,
        (("beside", "paved road"),),
        (Route("vegas", "beside", "paved road", 4),),
    ),
    Brief(
        "Let the rover not go far from the paved road -- like the eye that never leaves its beloved. The closer, the better.",
        "robot",
        "graded_toward",
        VEGAS,
        (("graded_toward", "paved road", None),),
        (Route("vegas", "closer", "paved road"),),
    ),
    Brief(
        "The unpaved road is fine for the truck, no need to avoid it, but prefer the paved road when there's a choice.",
        "analyst",
        "qualified",
        VEGAS,
        (("neutral", "unpaved road"), ("preferred", "paved road"), ("below", "paved road", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        "robot: pvd rd pls, dirt rd ok if u must",
        "robot",
        "terse",
        VEGAS,
        (("preferred", "paved road"), ("below", "paved road", "unpaved road"), ("not_lethal", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
        why="pvd rd = paved road, dirt rd = unpaved road, allowed but ranked below.",
    ),
    Brief(
        "Y'all stick to the blacktop now, that gravel road'll chew the tires right up.",
        "field",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
        why="Blacktop is the paved road; a gravel road is unpaved.",
    ),
]


KAMPALA_BRIEFS = [
    Brief(
        "Medical drone drop in the settlement: never fly closer than 3 m to any building -- people gather on the rooftops.",
        "robot",
        "distance_hard",
        KAMPALA,
        (("keep_out", "building", 3),),
        (Route("kampala", "keeps", "building", 3),),
    ),
    Brief(
        "Where practical keep about 6 feet between the robot and the house walls; squeezing closer is "
        "allowed if there's no other way.",
        "field",
        "distance_soft",
        KAMPALA,
        (("soft_zone", "building", 1.8288),),
        (Route("kampala", "less_on", "building"),),
        why="6 ft = 1.8288 m, worded softly; the house walls are the buildings.",
    ),
    Brief(
        "Everything marked as building here is market stalls and tarpaulin sheds, so the robot can roll right through it.",
        "field",
        "permission",
        KAMPALA,
        (("neutral", "building"), ("not_lethal", "building")),
        why="The stalls and sheds are what the building layer holds: a permission, not a new thing.",
    ),
    Brief(
        "Keep a respectful distance from the houses: the nearer, the more danger, but after 5 metres it is all the same.",
        "robot",
        "graded_away",
        KAMPALA,
        (("graded_away", "building", 5),),
        (Route("kampala", "farther", "building"),),
        why="Chinese 越近越危险 ('the nearer, the more danger'): graded, reaching neutral at 5 m.",
    ),
    Brief(
        "Stay out of the buildings -- actually, scratch that, just avoid them where it's easy; a few shortcuts through are OK.",
        "robot",
        "permission",
        KAMPALA,
        (("avoided", "building"), ("not_lethal", "building")),
        (Route("kampala", "less_on", "building"),),
        why="The stay-out wording is taken back: plain avoidance, shortcuts allowed.",
    ),
    Brief(
        "Hug the walls for cover, right up against the buildings, but never go inside one.",
        "field",
        "on_beside",
        KAMPALA,
        (("beside", "building"), ("lethal", "building")),
        (Route("kampala", "beside", "building", 2), Route("kampala", "zero_on", "building")),
        why="'never go inside' forbids the buildings; the ground right beside them is wanted.",
    ),
]


MASSACHUSETTS_BRIEFS = [
    Brief(
        "Good afternoon, and apologies for the bother -- our insurer insists that the robot must never be "
        "within 10 metres of any house. Thank you ever so much, and sorry again.",
        "analyst",
        "distance_hard",
        MASSACHUSETTS,
        (("keep_out", "building", 10),),
        (Route("massachusetts", "keeps", "building", 10),),
    ),
    Brief(
        "Leaflet robot, door to door: stay right next to the houses, the closer the better, but don't go into any of them.",
        "robot",
        "on_beside",
        MASSACHUSETTS,
        (("beside", "building"), ("lethal", "building"), ("graded_toward", "building", None)),
        (Route("massachusetts", "beside", "building", 5), Route("massachusetts", "zero_on", "building")),
        why="'don't go into' forbids the houses; the ground beside them is cheaper the nearer.",
    ),
    Brief(
        "nvr go in2 any bldg. k thx",
        "robot",
        "permission",
        MASSACHUSETTS,
        (("lethal", "building"),),
        (Route("massachusetts", "zero_on", "building"),),
        why="A text message: 'never go into any building' forbids.",
    ),
    Brief(
        "If you can, leave about 20 yards between yourself and the houses -- not a rule, just good manners.",
        "field",
        "distance_soft",
        MASSACHUSETTS,
        (("soft_zone", "building", 18.288),),
        (Route("massachusetts", "farther", "building"),),
        why="20 yd = 18.288 m, worded softly.",
    ),
    Brief(
        "I'm not fussed about the buildings, they're all empty holiday lets this time of year -- go through if it's shorter.",
        "field",
        "permission",
        MASSACHUSETTS,
        (("neutral", "building"), ("not_lethal", "building")),
    ),
]


NEON_BRIEFS = [
    Brief(
        "Forestry drone at canopy height: under no circumstances enter a tree crown.",
        "robot",
        "permission",
        NEON,
        (("lethal", "tree"),),
        (Route("neon", "zero_on", "tree"),),
    ),
    Brief(
        "Keep 1.5 m from every tree at all times, the sensor mast snags on low branches.",
        "field",
        "distance_hard",
        NEON,
        (("keep_out", "tree", 1.5),),
        (Route("neon", "keeps", "tree", 1.5),),
    ),
    Brief(
        "Stay in the shade: the nearer the trees, the better.",
        "field",
        "graded_toward",
        NEON,
        (("graded_toward", "tree", None),),
        (Route("neon", "closer", "tree"),),
    ),
    Brief(
        "We have here a small forest plot, and the robot shall please drive so that it comes not too near "
        "to the trees -- the closer, the worse -- from 4 metres on it is all the same.",
        "analyst",
        "graded_away",
        NEON,
        (("graded_away", "tree", 4),),
        (Route("neon", "farther", "tree"),),
        why="German 'ab 4 Metern ist es egal': the fall-off reaches neutral at 4 m.",
    ),
    Brief(
        "Ideally 2 m off the crowns, but it's fine to squeeze closer where the stand is thick.",
        "robot",
        "distance_soft",
        NEON,
        (("soft_zone", "tree", 2),),
        (Route("neon", "less_on", "tree"),),
        why="The crowns are the trees; 'ideally' makes the 2 m zone soft.",
    ),
    Brief(
        "Weave along the edges of the tree crowns -- keep to the open ground right beside them, not under them.",
        "field",
        "on_beside",
        NEON,
        (("beside", "tree"),),
        (Route("neon", "beside", "tree", 2),),
    ),
]


#: Briefs over layers no scene holds: no route checks.
OTHER_BRIEFS = [
    Brief(
        "Drive the headlands only; the vine rows are off limits until after harvest, and keep well back "
        "from the irrigation pond.",
        "field",
        "graded_away",
        VINEYARD,
        (("preferred", "headland"), ("lethal", "vine row"), ("graded_away", "irrigation pond", None)),
        why="A vineyard manager: 'off limits' forbids, 'keep well back' is graded nearness.",
    ),
    Brief(
        "Inspection drone: follow the power line, beside it but never directly over it; the substation is "
        "off limits; the access track is fine.",
        "robot",
        "on_beside",
        POLE_LINE,
        (("beside", "power line"), ("lethal", "substation"), ("neutral", "access track")),
    ),
    Brief(
        "Site rules for the survey rover: the excavation trenches are no-go, keep two metres off the spoil "
        "heaps without fail, and use the footpath between them.",
        "field",
        "distance_hard",
        DIG,
        (("lethal", "trench"), ("keep_out", "spoil heap", 2), ("preferred", "footpath")),
        why="An archaeologist: 'no-go' forbids, 'two metres ... without fail' is a hard zone.",
    ),
    Brief(
        "Stay on the footpath, keep out of the trenches, and mind the string lines and survey pegs marking the grid.",
        "field",
        "clauses",
        DIG,
        (("preferred", "footpath"), ("lethal", "trench"), ("unread", "survey peg")),
        why="No layer stands for string lines or survey pegs.",
    ),
    Brief(
        "Accessibility check: the route must use the sidewalk and the curb ramps, stairs are impassable "
        "for a wheelchair, and gravel is to be avoided; grass is acceptable.",
        "analyst",
        "permission",
        ACCESS,
        (
            ("preferred", "sidewalk"),
            ("preferred", "curb ramp"),
            ("lethal", "stairs"),
            ("avoided", "gravel"),
            ("neutral", "grass"),
        ),
        why="'impassable' forbids the stairs; 'acceptable' merely allows the grass.",
    ),
    Brief(
        "Dispatch: route the drone over the streets, never into the no-fly zone; rooftops are fine to overfly.",
        "robot",
        "permission",
        AIRSPACE,
        (("preferred", "street"), ("lethal", "no-fly zone"), ("neutral", "rooftop")),
    ),
    Brief(
        "Just keep to the farm track, eh -- the hay field's about ready to cut so don't be flattening it, "
        "and stay outta the cattle pen, the bull's in there.",
        "field",
        "permission",
        FARM,
        (("preferred", "farm track"), ("below", "farm track", "hay field"), ("lethal", "cattle pen")),
        why="'stay outta' is 'stay out of': forbidden; the hay field is at least dearer than the track.",
    ),
    Brief(
        "Axis of advance: along the ridge. Minefield: never enter. River: cross only at the ford.",
        "field",
        "clauses",
        BATTLEFIELD,
        (("preferred", "ridge"), ("lethal", "minefield"), ("unread", "ford")),
        why="No layer stands for the ford, so the river-crossing clause cannot be honoured and is reported.",
    ),
    Brief(
        "surface | cost\nasphalt | 1\ngravel | 2\nmud | 5\nice | do not enter",
        "analyst",
        "terse",
        SURFACES,
        (("below", "asphalt", "gravel"), ("below", "gravel", "mud"), ("lethal", "ice")),
        why="A relative cost table: the numbers rank the surfaces; 'do not enter' forbids the ice.",
    ),
]


BRIEFS = NB_BRIEFS + SAMPLE_BRIEFS + VEGAS_BRIEFS + KAMPALA_BRIEFS + MASSACHUSETTS_BRIEFS + NEON_BRIEFS + OTHER_BRIEFS

#: Briefs retired after writing (id or prompt -> why); none.
DOUBTFUL: dict[str, str] = {}
