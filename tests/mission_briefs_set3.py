"""Mission briefs, set 3: held-out briefs mostly in the "field" voice.

Field teams on phones and radios: terse, lower case, little punctuation, typos, symbols such as
``>`` and ``>>``, colloquial words, voice-dictated filler ("um", "uh", "like"), and sometimes a
non-native speaker. A few briefs are in the "analyst" and "robot" voices.

Written WITHOUT reading the interpreter, its tests or its corpora, and scored ONCE at first
contact; that first-contact figure is the one that counts. Never edit a brief to make the
interpreter pass: a case whose expectation contradicts the cost-scale contract is retired in
``DOUBTFUL`` with the reason instead.
"""

from __future__ import annotations

from .mission_briefs import Brief, Route

B = Brief
R = Route

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------ distance_hard
    B(
        "never get closer than 10m to the houses ppl still live there",
        "field", "distance_hard",
        ("building", "road"),
        (("keep_out", "building", 10), ("not_lethal", "road")),
        routes=(R("massachusetts", "keeps", "building", 10),),
    ),
    B(
        "stay 5 m off the rail at all times no matter what",
        "field", "distance_hard",
        ("railway", "road", "vegetation", "building"),
        (("keep_out", "railway", 5), ("not_lethal", "road")),
        routes=(R("nb2", "keeps", "railway", 5),),
    ),
    B(
        "keep 15m from the water no matter what bank is crumbling",
        "field", "distance_hard",
        ("water", "road", "vegetation", "building"),
        (("keep_out", "water", 15), ("not_lethal", "road")),
        routes=(R("nb1", "keeps", "water", 15),),
        why="'no matter what' makes the 15 m absolute; the crumbling bank is only the reason.",
    ),
    B(
        "must stay at least 3 metres from the shacks, um, dont wanna spook nobody",
        "field", "distance_hard",
        ("building", "unpaved road"),
        (("keep_out", "building", 3), ("not_lethal", "unpaved road")),
        routes=(R("kampala", "keeps", "building", 3),),
    ),
    B(
        "dont come within 30 m of the power lines EVER",
        "field", "distance_hard",
        ("power line", "grass", "paved road"),
        (("keep_out", "power line", 30), ("not_lethal", "grass")),
    ),
    B(
        "is forbidden to go more close than 12 meter to the pond",
        "field", "distance_hard",
        ("water", "grass", "tree"),
        (("keep_out", "water", 12), ("not_lethal", "grass")),
        why="non-native phrasing of an absolute minimum distance ('forbidden', 'more close than').",
    ),
    B(
        "Maintain minimum standoff 8 m from fence. Hard constraint.",
        "robot", "distance_hard",
        ("fence", "grass", "gravel"),
        (("keep_out", "fence", 8), ("not_lethal", "grass")),
    ),
    B(
        "Under no circumstances pass within 25 m of the farm buildings; the tenant keeps a dog.",
        "analyst", "distance_hard",
        ("building", "field", "unpaved road"),
        (("keep_out", "building", 25), ("not_lethal", "field")),
    ),
    # ------------------------------------------------------------------ distance_soft
    B(
        "try keep a bit of distance from the houses, like 10m if u can",
        "field", "distance_soft",
        ("building", "road", "grass"),
        (("soft_zone", "building", 10), ("not_lethal", "grass")),
        routes=(R("massachusetts", "farther", "building"),),
    ),
    B(
        "ideally stay 20 m or so from the river but its not a big deal",
        "field", "distance_soft",
        ("river", "tree", "grass"),
        (("soft_zone", "river", 20), ("not_lethal", "river")),
    ),
    B(
        "if poss give the hedges 5m, cows dont care tho",
        "field", "distance_soft",
        ("hedge", "field", "unpaved road"),
        (("soft_zone", "hedge", 5), ("not_lethal", "field")),
    ),
    B(
        "Where practical, keep roughly 15 metres from the rail line.",
        "analyst", "distance_soft",
        ("railway", "road", "vegetation", "water", "building"),
        (("soft_zone", "railway", 15), ("not_lethal", "railway")),
    ),
    B(
        "prefer 30m clear of the marsh, not essential",
        "field", "distance_soft",
        ("marsh", "grass", "tree"),
        (("soft_zone", "marsh", 30), ("not_lethal", "marsh")),
    ),
    B(
        "uh yeah so if you can sort of keep like ten meters off the car park thatd be good",
        "field", "distance_soft",
        ("parking lot", "building", "grass"),
        (("soft_zone", "parking lot", 10), ("not_lethal", "parking lot")),
        why="voice-dictated; 'ten meters' spelled out; 'if you can ... thatd be good' is soft.",
    ),
    # ------------------------------------------------------------------ graded_away
    B(
        "dont go near the river",
        "field", "graded_away",
        ("water", "road", "vegetation", "building"),
        (("graded_away", "water", None), ("avoided", "water")),
        routes=(R("nb1", "farther", "water"),),
        why="'don't go near' prices nearness; it does not forbid entry, so water is avoided, not lethal.",
    ),
    B(
        "keep well away from the tracks lads",
        "field", "graded_away",
        ("railway", "road", "vegetation", "building"),
        (("graded_away", "railway", None), ("avoided", "railway")),
        routes=(R("nb2", "farther", "railway"),),
    ),
    B(
        "the further from the bog the better",
        "field", "graded_away",
        ("marsh", "grass", "unpaved road"),
        (("graded_away", "marsh", None), ("avoided", "marsh")),
    ),
    B(
        "stay wel clear of teh pylons",
        "field", "graded_away",
        ("power line", "field", "paved road"),
        (("graded_away", "power line", None), ("avoided", "power line")),
        why="'well clear' with no number reads as 'the farther the better', not a hard zone.",
    ),
    B(
        "Keep as far from the buildings as the terrain allows; proximity is the main risk.",
        "analyst", "graded_away",
        ("building", "road", "grass", "tree", "trail", "water"),
        (("graded_away", "building", None), ("avoided", "building")),
        routes=(R("sample", "farther", "building"),),
    ),
    B(
        "bees at the hives dont go anywhere near em, past 40m dont matter",
        "field", "graded_away",
        ("beehive", "grass", "hedge"),
        (("graded_away", "beehive", 40), ("avoided", "beehive")),
        why="nearness is priced and the fall-off ends at 40 m ('past 40m dont matter').",
    ),
    # ------------------------------------------------------------------ graded_toward
    B(
        "stay close to the road if u can",
        "field", "graded_toward",
        ("road", "vegetation", "building", "water", "railway"),
        (("graded_toward", "road", None), ("not_lethal", "vegetation")),
        routes=(R("nb2", "closer", "road"),),
    ),
    B(
        "keep within sight of the trail, phone signal dies in there",
        "field", "graded_toward",
        ("trail", "tree", "grass", "water", "building", "road"),
        (("graded_toward", "trail", None), ("not_lethal", "trail")),
        routes=(R("sample", "closer", "trail"),),
    ),
    B(
        "hug the fence line the closer the better",
        "field", "graded_toward",
        ("fence", "grass", "shrub"),
        (("graded_toward", "fence", None), ("not_lethal", "grass")),
    ),
    B(
        "Remain near the river. Proximity to river preferred.",
        "robot", "graded_toward",
        ("river", "grass", "tree"),
        (("graded_toward", "river", None), ("not_lethal", "grass")),
    ),
    B(
        "please you stay near of the gravel road, not go far from it",
        "field", "graded_toward",
        ("unpaved road", "grass", "tree"),
        (("graded_toward", "unpaved road", None), ("not_lethal", "unpaved road")),
        why="non-native speaker; 'gravel road' is the unpaved layer.",
    ),
    B(
        "stick near the blacktop so the truck can get to u, dirt roads whatever",
        "field", "graded_toward",
        ("paved road", "unpaved road"),
        (("graded_toward", "paved road", None), ("neutral", "unpaved road"),
         ("below", "paved road", "unpaved road")),
        routes=(R("vegas", "closer", "paved road"),),
        why="'whatever' = indifferent, so the dirt roads are merely allowed (neutral).",
    ),
    # ------------------------------------------------------------------ on_beside
    B(
        "walk along the creek bank but not in the creek",
        "field", "on_beside",
        ("water", "grass", "tree", "trail", "road", "building"),
        (("beside", "water"), ("not_lethal", "grass")),
        routes=(R("sample", "beside", "water", 5),),
    ),
    B(
        "follow the fence never on it",
        "field", "on_beside",
        ("fence", "grass", "field"),
        (("beside", "fence"), ("not_lethal", "field")),
    ),
    B(
        "skirt the bush edge dont go in",
        "field", "on_beside",
        ("shrub", "grass", "unpaved road"),
        (("beside", "shrub"), ("lethal", "shrub")),
        why="'dont go in' is 'don't go into' the bush: forbidding wording, so the bush is lethal.",
    ),
    B(
        "run alongside the rail tracks, not on em",
        "field", "on_beside",
        ("railway", "road", "vegetation", "building", "water"),
        (("beside", "railway"), ("not_lethal", "road")),
        routes=(R("nb2", "beside", "railway", 5),),
    ),
    B(
        "Follow the hedgerow on its field side; do not travel through the hedge itself.",
        "analyst", "on_beside",
        ("hedge", "field", "paved road"),
        (("beside", "hedge"), ("not_lethal", "field")),
    ),
    B(
        "go along the edge of the woods, out in the open but right next to the trees",
        "field", "on_beside",
        ("tree", "grass", "road", "trail", "water", "building"),
        (("beside", "tree"), ("not_lethal", "grass")),
    ),
    B(
        "Traverse parallel to road, offset from carriageway. Do not drive on road surface.",
        "robot", "on_beside",
        ("paved road", "grass", "gravel"),
        (("beside", "paved road"), ("not_lethal", "grass")),
    ),
    # ------------------------------------------------------------------ qualified
    B(
        "tarmac before gravel tracks, gravel before open ground",
        "field", "qualified",
        ("paved road", "unpaved road", "grass"),
        (("below", "paved road", "unpaved road"), ("below", "unpaved road", "grass"),
         ("preferred", "paved road")),
    ),
    B(
        "paddocks fine except the bull paddock, avoid that one",
        "field", "qualified",
        ("field", "bull paddock", "unpaved road"),
        (("neutral", "field"), ("avoided", "bull paddock"), ("below", "field", "bull paddock")),
    ),
    B(
        "dirt roads ok, stay off the paved ones theres traffic",
        "field", "qualified",
        ("paved road", "unpaved road", "building"),
        (("neutral", "unpaved road"), ("below", "unpaved road", "paved road"),
         ("not_lethal", "unpaved road")),
        why="'dirt roads' is the unpaved layer; the paved ones are the paved layer. 'stay off' is "
        "not one of the forbidding phrases, so only the order is asserted for the paved road.",
    ),
    B(
        "Prefer the sealed road over the gravel road; neither is forbidden.",
        "analyst", "qualified",
        ("paved road", "unpaved road"),
        (("preferred", "paved road"), ("below", "paved road", "unpaved road"),
         ("not_lethal", "unpaved road")),
        routes=(R("vegas", "more_on", "paved road"),),
    ),
    B(
        "pine woods ok to cut thru but avoid the deciduous stuff too thick",
        "field", "qualified",
        ("conifer", "deciduous tree", "grass"),
        (("neutral", "conifer"), ("avoided", "deciduous tree"),
         ("below", "conifer", "deciduous tree")),
        why="'ok to cut thru' lifts the tree prior on the conifers to neutral.",
    ),
    B(
        "fields all good except the flooded one by the brook, keep off that",
        "field", "qualified",
        ("field", "flooded field", "stream"),
        (("below", "field", "flooded field"), ("not_lethal", "field")),
        why="excepted sub-area: the flooded field is dearer than the other fields.",
    ),
    B(
        "tarmac better than dirt tracks but both beat the scrub",
        "field", "qualified",
        ("paved road", "unpaved road", "shrub"),
        (("below", "paved road", "unpaved road"), ("below", "unpaved road", "shrub")),
    ),
    # ------------------------------------------------------------------ terse
    B(
        "roads good. scrub ok. houses, ponds: no.",
        "field", "terse",
        ("road", "shrub", "building", "water"),
        (("preferred", "road"), ("neutral", "shrub"), ("avoided", "building"),
         ("avoided", "water")),
        why="'no' in a terse list reads as avoid, not forbid; 'ok' is merely allowed (neutral).",
    ),
    B(
        "trail > meadow > marsh",
        "field", "terse",
        ("trail", "grass", "marsh"),
        (("below", "trail", "grass"), ("below", "grass", "marsh")),
        why="'meadow' runs over the grass layer.",
    ),
    B(
        "blacktop >> gravel",
        "field", "terse",
        ("paved road", "unpaved road"),
        (("below", "paved road", "unpaved road"), ("preferred", "paved road")),
    ),
    B(
        "teh gravle trak fine, wods: avoid",
        "field", "terse",
        ("unpaved road", "tree", "grass"),
        (("neutral", "unpaved road"), ("avoided", "tree"), ("below", "unpaved road", "tree")),
        why="typos: 'gravle trak' is the gravel track (unpaved layer), 'wods' the woods (tree).",
    ),
    B(
        "roads good. trees, houses: no",
        "field", "terse",
        ("road", "tree", "building", "grass", "trail", "water"),
        (("preferred", "road"), ("avoided", "tree"), ("avoided", "building")),
        routes=(R("sample", "more_on", "road"), R("sample", "less_on", "tree")),
        why="'no' without forbidding words reads as avoid.",
    ),
    B(
        "PATH: pref. GRASS: ok. WATER: no-go.",
        "robot", "terse",
        ("footpath", "grass", "water"),
        (("preferred", "footpath"), ("neutral", "grass"), ("lethal", "water")),
    ),
    B(
        "lawns are nice. flower beds NO",
        "field", "terse",
        ("lawn", "flower bed", "paved path"),
        (("preferred", "lawn"), ("below", "lawn", "flower bed")),
        why="capital NO may or may not forbid; only the order and the preference are asserted.",
    ),
    B(
        "rail line: avoid. car park fine",
        "field", "terse",
        ("railway", "parking lot", "building"),
        (("avoided", "railway"), ("neutral", "parking lot")),
    ),
    # ------------------------------------------------------------------ permission
    B(
        "no need to avoid the sheds theyre empty ruins",
        "field", "permission",
        ("building", "grass", "unpaved road"),
        (("neutral", "building"), ("not_lethal", "building")),
    ),
    B(
        "the creek is dry this month so u can just walk thru it",
        "field", "permission",
        ("water", "grass", "tree"),
        (("neutral", "water"), ("not_lethal", "water")),
    ),
    B(
        "stay out of the woods entirely, ticks everywhere",
        "field", "permission",
        ("tree", "grass", "road", "trail", "building", "water"),
        (("lethal", "tree"), ("not_lethal", "grass")),
        routes=(R("sample", "zero_on", "tree"),),
    ),
    B(
        "keep out of the swamp",
        "field", "permission",
        ("marsh", "grass", "tree"),
        (("lethal", "marsh"), ("not_lethal", "grass")),
    ),
    B(
        "dont go into the water under any circumstances",
        "field", "permission",
        ("water", "grass", "road", "trail", "tree", "building"),
        (("lethal", "water"), ("not_lethal", "grass")),
        routes=(R("sample", "zero_on", "water"),),
    ),
    B(
        "avoid the bog",
        "field", "permission",
        ("marsh", "field", "unpaved road"),
        (("avoided", "marsh"), ("not_lethal", "marsh")),
    ),
    B(
        "trees r fine to walk under, canopy is high",
        "field", "permission",
        ("tree", "grass", "road"),
        (("neutral", "tree"), ("not_lethal", "tree")),
    ),
    B(
        "The rail line is disused; no need to treat it as a hazard. Keep out of the quarry.",
        "analyst", "permission",
        ("railway", "quarry", "grass"),
        (("neutral", "railway"), ("lethal", "quarry")),
    ),
    B(
        "buildings off limits, rest is fair game",
        "field", "permission",
        ("building", "road", "vegetation", "water", "railway"),
        (("lethal", "building"), ("not_lethal", "road")),
        routes=(R("nb2", "zero_on", "building"),),
    ),
    # ------------------------------------------------------------------ clauses
    B(
        "stay on the trail and ring me when ur there",
        "field", "clauses",
        ("trail", "grass", "tree"),
        (("preferred", "trail"), ("unread", "ring")),
    ),
    B(
        "bring the spare battery, avoid the marsh",
        "field", "clauses",
        ("marsh", "grass", "unpaved road"),
        (("avoided", "marsh"), ("unread", "battery")),
    ),
    B(
        "keep out of the ball field theres a game on, and text me b4 u leave",
        "field", "clauses",
        ("baseball field", "grass", "road", "trail", "tree", "building"),
        (("lethal", "baseball field"), ("unread", "text")),
        routes=(R("sample", "zero_on", "baseball field"),),
    ),
    B(
        "roads preferred, avoid the ponds",
        "field", "clauses",
        ("road", "water", "grass"),
        (("preferred", "road"), ("avoided", "water"), ("all_read",)),
    ),
    B(
        "Prefer the gravel track, avoid the buildings, and stay out of the marsh.",
        "analyst", "clauses",
        ("unpaved road", "building", "marsh", "grass"),
        (("preferred", "unpaved road"), ("avoided", "building"), ("lethal", "marsh"),
         ("all_read",)),
    ),
    B(
        "ok so um take the road mostly, uh, and film the bridge on the way",
        "field", "clauses",
        ("road", "grass", "water"),
        (("preferred", "road"), ("unread", "film")),
    ),
    B(
        "Avoid vegetation. Return to base when battery below 20 percent.",
        "robot", "clauses",
        ("vegetation", "road", "building", "water", "railway"),
        (("avoided", "vegetation"), ("unread", "battery")),
        routes=(R("nb1", "less_on", "vegetation"),),
    ),
    B(
        "stay off the lawns pls, the groundskeeper is a nightmare lol",
        "field", "clauses",
        ("lawn", "paved path", "building"),
        (("below", "paved path", "lawn"), ("unread", "groundskeeper")),
        why="the groundskeeper clause is chatter a costmap cannot express; it must be reported, "
        "not dropped. 'stay off' is not a forbidding phrase, so only the order is asserted.",
    ),
]

DOUBTFUL: dict[str, str] = {}
