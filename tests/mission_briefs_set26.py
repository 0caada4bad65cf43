"""Mission briefs, set 26: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench, the docs or the briefs of earlier sets: only the contract
(``tests/mission_briefs.py`` and its format test ``tests/test_mission_briefs.py``), the scene index
(``../shared/scenes/INDEX.md`` and the scenes' ``classes.json``), the first 45 lines of set 25
(for the layout, and its docstring's list of voices) and the first 25 lines of sets 22, 23 and 24
(their docstrings' lists of voices, which this set avoids) were read. It is scored once, at first
contact, with ``bench/mission_briefs_report.py --set 26``; that figure is the one that counts, and
the set is not edited afterwards to make the interpreter pass.

The voices are a lake warden on a lake with no lifeguard, a railway track inspector's notebook
("km 14.2", "not negotiable"), a dog walker talking about her dog ("he bolts at cars"), a solar
farm O&M technician (inverter stations, the access road that belongs to the trucks), a
fire-lookout dispatcher ("Lookout to Engine 7"), a sommelier-style flowery writer ("the nearer
their cool shade, the sweeter"), a robotics student's GitHub issue ("**Expected:** /
**Actual:**", "Feature request"), a haiku-ish terse poet (lines split by " / "), a legal-aid
plain-English notice ("You are allowed to ... You must ..."), a warehouse AGV engineer's TOML
config (``[clearance.building]``, ``min_m``, ``traversable = false``), a TV weather presenter
("a gentle buffer ... would be welcome", "costs climb steeply as you approach", "easing off to
nothing by about 30 metres out"), a priority-ordered bullet list with sub-bullets, British
understatement ("one would rather not get terribly close", "one shan't lose sleep over it",
"quite out of bounds"), a nervous first-time operator asking questions ("Is it allowed ...? I
think yes?"), a geocacher (the cache under a tree, "fair game"), a surveyor mixing metric and
imperial ("4 m (roughly 13 ft)"), a translator's stiff French-English ("it is obligatory to
conserve a distance", "more far, more good", "the roads of earth", "circulate along"),
if/then/otherwise rules in plain language, a share cap ("at most 10 % of the route on grass"),
comparisons ("roads are twice as good as trails"), rules stated as consequences ("if it touches
the water, the rover is lost", "the survey is scrubbed") and exceptions ("except the lone tree by
the gate", "save the baseball field", "except the stretch over the bridge").

Units come in metres, feet (15 ft = 4.572 m), yards (ten yards = 9.144 m, five yards = 4.572 m),
spelled-out numbers ("twelve", "twenty"), decimal commas ("2,5 m", "1,5 m") and a metric figure
with its imperial gloss (the metre figure is the one expected). Orderings come as "then ... then
... never", numbered priority bullets, "twice as good as", "a last resort", "better", "where you
want to be" and if/otherwise chains; permissions as "allowed", "fair game", "cleared to", "clear
to drive through", "no problem", "may ... if it really must", ``traversable = true`` and a
question answered by the asker; forbidding as "stay out of", "keep out of", "a no-go", "do not
enter", "quite out of bounds", ``traversable = false``, the terse "X: no" and consequences.
Distance rules come hard ("under no circumstances within", "not negotiable", "hard limit",
``hard = true``), soft ("if you can", "not a strict thing", "though nothing strict", "not an
obligation", "if it can't, closer is acceptable"), graded away ("the closer the worse, up to
20 m", "farther is better"), graded toward ("keep within sight of", "stay within 3 m of ...
wherever possible", "the nearer the better") and as on-versus-beside ("beside the railway, never
on the rails", "on the verge next to the road, not on the road itself", ``on = false`` /
``beside = true``). Qualified classes are paved / unpaved roads (spelt right, as "asphalt" and
"earth", as "dirt roads", and as the typo "paved roud"), dead against healthy trees (which no
layer tells apart) and excepted sub-areas, one carried by a layer (the baseball field inside a
grass rule) and two no layer marks (the lone tree by the gate, the closed bridge stretch). Rules
that hang on what no layer can carry (showers, swimmers being about, dark, crews on site) or name
things no layer stands for (a dog park, the gate, the bridge, dead trees) are expected unread;
where such a conditional rule would forbid a class, that class is expected not to be forbidden
outright.

Each construct has seven to nine briefs; route checks are given wherever the scene holds the
class. Unmentioned hazards are not given expectations here; where a brief gives an order but no
level, only the order is expected.
"""

from __future__ import annotations

from tests.mission_briefs import Brief, Route

#: The bundled sample's classes.
SAMPLE = ("grass", "road", "trail", "tree", "water", "building", "baseball field")
#: The New Brunswick clips' classes.
NB = ("building", "road", "water", "vegetation", "railway")
#: The Las Vegas roads' classes.
VEGAS = ("paved road", "unpaved road")
#: Building-only scenes (Kampala, Massachusetts).
BUILDINGS = ("building",)
#: The NEON tree-crown plot.
TREES = ("tree",)

FT = 0.3048
YD = 0.9144

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------------------------------
    # distance_hard: absolute distance rules, a keep-out zone of the stated metres
    # ------------------------------------------------------------------------------------------
    Brief(
        "Lake warden's standing rule, as there is no lifeguard on this lake: under no circumstances "
        "is the rover to come within 10 m of the water.",
        "field",
        "distance_hard",
        SAMPLE,
        (("keep_out", "water", 10),),
        (Route("sample", "keeps", "water", 10), Route("nb1", "keeps", "water", 10)),
        why="'under no circumstances ... within 10 m' is absolute; the lifeguard aside is no rule",
    ),
    Brief(
        "Notebook, km 14.2: nothing of ours within 15 ft of the railway. Not negotiable.",
        "field",
        "distance_hard",
        NB,
        (("keep_out", "railway", 15 * FT),),
        (Route("nb2", "keeps", "railway", 15 * FT),),
        why="15 ft = 4.572 m; 'not negotiable' makes it hard",
    ),
    Brief(
        "Hold 4 m (roughly 13 ft) off every building, no matter what.",
        "analyst",
        "distance_hard",
        BUILDINGS,
        (("keep_out", "building", 4),),
        (Route("massachusetts", "keeps", "building", 4), Route("kampala", "keeps", "building", 4)),
        why="the metre figure is the stated one, the feet a gloss of it; 'no matter what' is absolute",
    ),
    Brief(
        "Never get closer than twelve metres to the railway line.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "railway", 12),),
        (Route("nb2", "keeps", "railway", 12),),
    ),
    Brief(
        "It is obligatory to conserve a distance of 2,5 m at the minimum from the buildings, without any exception.",
        "analyst",
        "distance_hard",
        BUILDINGS,
        (("keep_out", "building", 2.5),),
        (Route("kampala", "keeps", "building", 2.5),),
        why="decimal comma: 2,5 m is 2.5 m; 'obligatory ... without any exception' is absolute",
    ),
    Brief(
        "Hard limit, folks: stay at least ten yards from the water at all times.",
        "field",
        "distance_hard",
        SAMPLE,
        (("keep_out", "water", 10 * YD),),
        (Route("sample", "keeps", "water", 10 * YD),),
        why="ten yards = 9.144 m",
    ),
    Brief(
        "If the rover gets within 6 m of a tree the survey is scrubbed, so it simply must not.",
        "field",
        "distance_hard",
        TREES,
        (("keep_out", "tree", 6),),
        (Route("neon", "keeps", "tree", 6),),
        why="a rule stated as its consequence, then 'it simply must not': absolute",
    ),
    Brief(
        "# agv.toml\n[clearance.building]\nmin_m = 5\nhard = true",
        "robot",
        "distance_hard",
        BUILDINGS,
        (("keep_out", "building", 5),),
        (Route("massachusetts", "keeps", "building", 5),),
    ),
    # ------------------------------------------------------------------------------------------
    # distance_soft: softly worded distance rules, a soft zone with the number kept
    # ------------------------------------------------------------------------------------------
    Brief(
        "If you can, keep roughly 8 m off the trees; it's not the end of the world if you can't.",
        "field",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "tree", 8), ("not_lethal", "tree")),
        (Route("sample", "farther", "tree"),),
    ),
    Brief(
        "Try to give the road a bit of room, say 15 feet, but it's not a strict thing.",
        "field",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "road", 15 * FT), ("not_lethal", "road")),
        (Route("sample", "farther", "road"),),
        why="15 feet = 4.572 m",
    ),
    Brief(
        "And for the rover today: a gentle buffer of about twenty metres around the water would be "
        "welcome, though nothing strict.",
        "analyst",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "water", 20), ("not_lethal", "water")),
        (Route("sample", "farther", "water"),),
    ),
    Brief(
        "Ideally we'd like five yards or so between the rover and the railway, but one shan't lose sleep over it.",
        "analyst",
        "distance_soft",
        NB,
        (("soft_zone", "railway", 5 * YD), ("not_lethal", "railway")),
        (Route("nb2", "farther", "railway"),),
        why="five yards = 4.572 m; 'ideally' and 'shan't lose sleep over it' make it soft",
    ),
    Brief(
        "Preferably stay 3 m clear of the buildings (inverter stations); cutting closer is fine if the path needs it.",
        "field",
        "distance_soft",
        NB,
        (("soft_zone", "building", 3), ("not_lethal", "building")),
        (Route("nb1", "farther", "building"),),
    ),
    Brief(
        "If it is possible, the robot holds itself at 1,5 m from the trees, but this is not an obligation.",
        "analyst",
        "distance_soft",
        TREES,
        (("soft_zone", "tree", 1.5),),
        (Route("neon", "farther", "tree"),),
        why="decimal comma: 1,5 m is 1.5 m; 'not an obligation' makes it soft",
    ),
    Brief(
        "**Expected:** the planner should *prefer* to stay 6 m or more from the water (soft, not a "
        "hard constraint). **Actual:** it hugs the shoreline.",
        "robot",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "water", 6), ("not_lethal", "water")),
        (Route("sample", "farther", "water"),),
        why="the issue states the wanted behaviour as soft; the 'Actual' line is a report, no rule",
    ),
    Brief(
        "If a route can stay 10 m from the buildings, take it; if it can't, getting closer is acceptable.",
        "analyst",
        "distance_soft",
        BUILDINGS,
        (("soft_zone", "building", 10),),
        (Route("massachusetts", "farther", "building"),),
        why="an if/otherwise that allows the zone to be entered when needed: a soft zone",
    ),
    # ------------------------------------------------------------------------------------------
    # graded_away: priced by distance, the closer the dearer
    # ------------------------------------------------------------------------------------------
    Brief(
        "The closer to the water the worse, up to 20 m; past that it doesn't matter.",
        "analyst",
        "graded_away",
        SAMPLE,
        (("graded_away", "water", 20),),
        (Route("sample", "farther", "water"),),
    ),
    Brief(
        "Looking at the railway: costs climb steeply as you approach it, highest right next to it, "
        "easing off to nothing by about 30 metres out.",
        "analyst",
        "graded_away",
        NB,
        (("graded_away", "railway", 30),),
        (Route("nb2", "farther", "railway"),),
        why="a weather presenter's fall-off: dearest close by, neutral from 30 m",
    ),
    Brief(
        "One would rather not get terribly close to the buildings, if it's all the same to you.",
        "analyst",
        "graded_away",
        BUILDINGS,
        (("graded_away", "building", None),),
        (Route("massachusetts", "farther", "building"),),
        why="understatement for 'don't go near': graded, no number, nothing forbidden",
    ),
    Brief(
        "water's edge / farther is better, / always farther",
        "field",
        "graded_away",
        SAMPLE,
        (("graded_away", "water", None),),
        (Route("sample", "farther", "water"),),
    ),
    Brief(
        "It is preferable that the robot holds itself far from the trees: more far, more good, until 15 metres.",
        "analyst",
        "graded_away",
        TREES,
        (("graded_away", "tree", 15),),
        (Route("neon", "farther", "tree"),),
        why="'more far, more good, until 15 metres': the fall-off reaches neutral at 15 m",
    ),
    Brief(
        "The vehicle should keep well away from houses and other buildings. The nearer it gets, the worse.",
        "analyst",
        "graded_away",
        BUILDINGS,
        (("graded_away", "building", None),),
        (Route("kampala", "farther", "building"),),
    ),
    Brief(
        "Keep well away from the road, the further the better; he bolts at cars.",
        "field",
        "graded_away",
        SAMPLE,
        (("graded_away", "road", None),),
        (Route("sample", "farther", "road"),),
    ),
    # ------------------------------------------------------------------------------------------
    # graded_toward: the nearer, the cheaper
    # ------------------------------------------------------------------------------------------
    Brief(
        "Stay close to the water, he loves watching the ducks.",
        "field",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "water", None),),
        (Route("sample", "closer", "water"),),
        why="the ducks are the reason, not a place; only the nearness is expected",
    ),
    Brief(
        "Keep the shoreline in view at all times: the nearer the water the better, but don't go in.",
        "field",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "water", None),),
        (Route("nb1", "closer", "water"),),
    ),
    Brief(
        "Should it stay near the road? I'd feel a lot better if it kept close to the road, if that's okay?",
        "field",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "road", None),),
        (Route("sample", "closer", "road"),),
        why="a nervous operator's question, but the wish is plain: close to the road",
    ),
    Brief(
        "Stay within 3 m of the road wherever possible.",
        "robot",
        "graded_toward",
        NB,
        (("graded_toward", "road", 3),),
        (Route("nb1", "closer", "road"),),
        why="'wherever possible' makes it an attraction, not a hard corridor",
    ),
    Brief(
        "Lookout to Engine 7: keep within sight of the trail the whole way in.",
        "field",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "trail", None),),
        (Route("sample", "closer", "trail"),),
    ),
    Brief(
        "Let the route linger by the trees, the nearer their cool shade the sweeter the journey.",
        "analyst",
        "graded_toward",
        TREES,
        (("graded_toward", "tree", None),),
        (Route("neon", "closer", "tree"),),
    ),
    Brief(
        "Stay near the buildings, the closer the better; the cache is always tucked against a wall.",
        "field",
        "graded_toward",
        BUILDINGS,
        (("graded_toward", "building", None),),
        (Route("kampala", "closer", "building"),),
    ),
    # ------------------------------------------------------------------------------------------
    # on_beside: along X but not on X
    # ------------------------------------------------------------------------------------------
    Brief(
        "Walk beside the railway, never on the rails themselves.",
        "field",
        "on_beside",
        NB,
        (("beside", "railway"),),
        (Route("nb2", "beside", "railway", 10),),
    ),
    Brief(
        "Keep him on the verge next to the road, not on the road itself.",
        "field",
        "on_beside",
        SAMPLE,
        (("beside", "road"),),
        (Route("sample", "beside", "road", 5),),
        why="the verge is the unlabelled strip beside the road; grass is not named, so not expected",
    ),
    Brief(
        "Drive alongside the access road, not on it; the road belongs to the trucks.",
        "field",
        "on_beside",
        NB,
        (("beside", "road"),),
        (Route("nb1", "beside", "road", 5),),
    ),
    Brief(
        "Follow the trail, but a step or two off to the side, never on the trail itself.",
        "field",
        "on_beside",
        SAMPLE,
        (("beside", "trail"),),
        (Route("sample", "beside", "trail", 5),),
    ),
    Brief(
        "Run parallel to the creek, close alongside the water, but keep your wheels dry.",
        "field",
        "on_beside",
        SAMPLE,
        (("beside", "water"),),
        (Route("sample", "beside", "water", 10),),
    ),
    Brief(
        "AGV rule: run along the building walls, close beside them, never into them.",
        "robot",
        "on_beside",
        BUILDINGS,
        (("beside", "building"),),
        (Route("massachusetts", "beside", "building", 5),),
    ),
    Brief(
        "[road]\non = false\nbeside = true",
        "robot",
        "on_beside",
        SAMPLE,
        (("beside", "road"),),
        (Route("sample", "beside", "road", 5),),
    ),
    # ------------------------------------------------------------------------------------------
    # qualified: paved / unpaved, dead / healthy trees, excepted sub-areas
    # ------------------------------------------------------------------------------------------
    Brief(
        "Paved road is where you want to be; the unpaved road is a last resort.",
        "analyst",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("below", "paved road", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
        why="'a last resort' ranks the unpaved road below; its level is not pinned",
    ),
    Brief(
        "The robot will take the roads with asphalt (paved) and will avoid the roads of earth (unpaved).",
        "analyst",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        "Avoid the grass, except the baseball field, which is fine.",
        "field",
        "qualified",
        SAMPLE,
        (("avoided", "grass"), ("neutral", "baseball field"), ("below", "baseball field", "grass")),
        (Route("sample", "less_on", "grass"),),
        why="the exception is carried by its own layer; 'fine' is a permission: neutral",
    ),
    Brief(
        "Avoid trees, except the lone tree by the gate; that one you can go right under.",
        "field",
        "qualified",
        SAMPLE,
        (("avoided", "tree"), ("unread", "gate")),
        (Route("sample", "less_on", "tree"),),
        why="no layer marks the lone tree by the gate: the exception is unread, the rule stands",
    ),
    Brief(
        "Feature request: the planner should avoid *dead* trees only (they drop branches); healthy trees are fine.",
        "robot",
        "qualified",
        TREES,
        (("unread", "dead"), ("not_lethal", "tree")),
        why="no layer tells dead trees from healthy ones; nothing forbids trees",
    ),
    Brief(
        "Dirt roads are allowed; the paved ones are better.",
        "analyst",
        "qualified",
        VEGAS,
        (("below", "paved road", "unpaved road"), ("not_lethal", "unpaved road")),
        (Route("vegas", "more_on", "paved road"),),
        why="dirt roads are the unpaved road",
    ),
    Brief(
        "Grass, yes, a lovely soft grass everywhere, save the baseball field, which the route should avoid.",
        "analyst",
        "qualified",
        SAMPLE,
        (("avoided", "baseball field"), ("below", "grass", "baseball field")),
        (Route("sample", "less_on", "baseball field"),),
        why="'save' is an exception; grass is welcomed but its level is not pinned",
    ),
    Brief(
        "Stay on the road, except the stretch over the bridge, which is closed.",
        "field",
        "qualified",
        NB,
        (("preferred", "road"), ("unread", "bridge")),
        (Route("nb1", "more_on", "road"),),
        why="no layer marks the bridge: the exception is unread, the road rule stands",
    ),
    # ------------------------------------------------------------------------------------------
    # terse: haiku, bullets, "X: no", typos
    # ------------------------------------------------------------------------------------------
    Brief(
        "road, then the trail; / grass only if you must; / water, never.",
        "field",
        "terse",
        SAMPLE,
        (("below", "road", "trail"), ("below", "trail", "grass"), ("lethal", "water")),
        (Route("sample", "zero_on", "water"), Route("sample", "more_on", "road")),
    ),
    Brief(
        "Priorities:\n- 1. road\n- 2. vegetation\n  - only if the road runs out\n- never: railway",
        "analyst",
        "terse",
        NB,
        (("below", "road", "vegetation"), ("lethal", "railway")),
        (Route("nb2", "zero_on", "railway"), Route("nb1", "more_on", "road")),
    ),
    Brief(
        "basball feild: avoid. road: prefer.",
        "robot",
        "terse",
        SAMPLE,
        (("avoided", "baseball field"), ("preferred", "road")),
        (Route("sample", "less_on", "baseball field"), Route("sample", "more_on", "road")),
        why="'basball feild' is the baseball field misspelt",
    ),
    Brief(
        "paved roud: prefered. unpaved road: no.",
        "robot",
        "terse",
        VEGAS,
        (("preferred", "paved road"), ("lethal", "unpaved road")),
        (Route("vegas", "more_on", "paved road"), Route("vegas", "zero_on", "unpaved road")),
        why="'X: no' forbids; 'paved roud' is the paved road misspelt",
    ),
    Brief(
        "trees fine. water no. buildings no.",
        "field",
        "terse",
        SAMPLE,
        (("neutral", "tree"), ("lethal", "water"), ("lethal", "building")),
        (Route("sample", "zero_on", "water"), Route("sample", "zero_on", "building")),
        why="'X fine' is a permission (neutral), 'X no' forbids",
    ),
    Brief(
        "rail: no. road: best.",
        "field",
        "terse",
        NB,
        (("lethal", "railway"), ("preferred", "road")),
        (Route("nb2", "zero_on", "railway"), Route("nb1", "more_on", "road")),
    ),
    Brief(
        "vegitation fine; raillway: no",
        "field",
        "terse",
        NB,
        (("neutral", "vegetation"), ("lethal", "railway")),
        (Route("nb2", "zero_on", "railway"),),
        why="both names misspelt",
    ),
    # ------------------------------------------------------------------------------------------
    # permission: permissions that lift priors, and stay-out wording that forbids
    # ------------------------------------------------------------------------------------------
    Brief(
        "You are allowed to cross the railway. You must stay out of the water.",
        "analyst",
        "permission",
        NB,
        (("neutral", "railway"), ("lethal", "water")),
        (Route("nb1", "zero_on", "water"), Route("nb2", "zero_on", "water")),
    ),
    Brief(
        "Is it allowed to go under the trees? I think yes, it's allowed. But keep it out of the "
        "buildings, okay? Please?",
        "field",
        "permission",
        SAMPLE,
        (("neutral", "tree"), ("lethal", "building")),
        (Route("sample", "zero_on", "building"),),
        why="the asker answers the question: trees allowed; 'keep it out of' forbids",
    ),
    Brief(
        "Trees are fair game, the cache is usually under one. The water is a no-go though.",
        "field",
        "permission",
        SAMPLE,
        (("neutral", "tree"), ("lethal", "water")),
        (Route("sample", "zero_on", "water"),),
    ),
    Brief(
        "Cleared to walk on the railway today. Keep out of the lineside buildings.",
        "field",
        "permission",
        NB,
        (("neutral", "railway"), ("lethal", "building")),
        (Route("nb1", "zero_on", "building"), Route("nb2", "zero_on", "building")),
        why="'today' is no condition on anything else; 'lineside' names where the buildings are",
    ),
    Brief(
        "[layers.tree]\ntraversable = true\n\n[layers.building]\ntraversable = false",
        "robot",
        "permission",
        SAMPLE,
        (("neutral", "tree"), ("lethal", "building")),
        (Route("sample", "zero_on", "building"),),
    ),
    Brief(
        "The rover may trundle over the railway if it really must, I suppose; the water, however, is "
        "quite out of bounds.",
        "analyst",
        "permission",
        NB,
        (("not_lethal", "railway"), ("lethal", "water")),
        (Route("nb2", "zero_on", "water"),),
        why="a grudging permission ('if it really must'): not forbidden, level not pinned",
    ),
    Brief(
        "Engine 7, you're clear to drive through the vegetation; do not enter any building.",
        "field",
        "permission",
        NB,
        (("neutral", "vegetation"), ("lethal", "building")),
        (Route("nb1", "zero_on", "building"),),
    ),
    Brief(
        "The trees are no problem, drive under them. If it touches the water, the rover is lost.",
        "analyst",
        "permission",
        SAMPLE,
        (("neutral", "tree"), ("lethal", "water")),
        (Route("sample", "zero_on", "water"),),
        why="a consequence that forbids: a careful reader never lets the rover touch the water",
    ),
    # ------------------------------------------------------------------------------------------
    # clauses: every clause accounted for
    # ------------------------------------------------------------------------------------------
    Brief(
        "Prefer the road today, and if the showers arrive this afternoon, keep off the grass.",
        "analyst",
        "clauses",
        SAMPLE,
        (("preferred", "road"), ("unread", "showers"), ("not_lethal", "grass")),
        (Route("sample", "more_on", "road"),),
        why="the grass rule hangs on the weather, which no layer carries: unread, grass not forbidden",
    ),
    Brief(
        "Avoid the water, and if swimmers are about, keep 20 m clear of it.",
        "field",
        "clauses",
        SAMPLE,
        (("avoided", "water"), ("unread", "swimmers")),
        (Route("sample", "less_on", "water"),),
        why="the clearance hangs on swimmers being present, which no layer carries",
    ),
    Brief(
        "Roads are twice as good as trails, and trails are twice as good as grass.",
        "analyst",
        "clauses",
        SAMPLE,
        (("below", "road", "trail"), ("below", "trail", "grass"), ("all_read",)),
        (Route("sample", "more_on", "road"),),
    ),
    Brief(
        "Spend at most 10 % of the route on grass; the rest belongs on the road or the trail.",
        "analyst",
        "clauses",
        SAMPLE,
        (("avoided", "grass"), ("below", "road", "grass"), ("below", "trail", "grass")),
        (Route("sample", "less_on", "grass"),),
        why="a share cap on grass can only be priced as grass avoided; road and trail rank above it",
    ),
    Brief(
        "Avoid the water, and steer clear of the dog park by the car park.",
        "field",
        "clauses",
        SAMPLE,
        (("avoided", "water"), ("unread", "dog park")),
        (Route("sample", "less_on", "water"),),
        why="no layer stands for the dog park",
    ),
    Brief(
        "Take the road where you can, avoid the trees, and stay out of the water.",
        "analyst",
        "clauses",
        SAMPLE,
        (("preferred", "road"), ("avoided", "tree"), ("lethal", "water"), ("all_read",)),
        (
            Route("sample", "zero_on", "water"),
            Route("sample", "more_on", "road"),
            Route("sample", "less_on", "tree"),
        ),
    ),
    Brief(
        "Use the road; after dark, keep clear of the buildings.",
        "field",
        "clauses",
        NB,
        (("preferred", "road"), ("unread", "dark")),
        (Route("nb1", "more_on", "road"),),
        why="the building rule hangs on the time of day, which no layer carries",
    ),
    Brief(
        "If there is a road, use it; otherwise the trail; otherwise the grass.",
        "analyst",
        "clauses",
        SAMPLE,
        (("below", "road", "trail"), ("below", "trail", "grass")),
        (Route("sample", "more_on", "road"),),
        why="an if/otherwise chain on what the map holds is a ranking",
    ),
    Brief(
        "Avoid the buildings, and if crews are on site, stay off the road.",
        "field",
        "clauses",
        NB,
        (("avoided", "building"), ("unread", "crews"), ("not_lethal", "road")),
        (Route("nb1", "less_on", "building"),),
        why="the road rule hangs on people being present, which no layer carries",
    ),
]

#: Briefs retired after scoring because their expectation contradicts the contract (id -> reason).
DOUBTFUL: dict[str, str] = {}
