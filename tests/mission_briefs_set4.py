"""Mission briefs, set 4: held-out briefs mostly in the "analyst" voice.

GIS analysts writing in full, often formal sentences: buffers, setbacks, standoffs, corridors,
exclusion zones and rights of way, with justifications and project chatter woven in. A handful of
terse "robot" configuration lines and casual "field" remarks are mixed in for contrast.

Written WITHOUT reading the interpreter, its tests or its corpora, and scored ONCE at first
contact; that first-contact figure is the one that counts. Never edit a brief to make the
interpreter pass: a case whose expectation contradicts the cost-scale contract is retired in
``DOUBTFUL`` with the reason instead.
"""

from __future__ import annotations

from .mission_briefs import Brief, Route

B = Brief
R = Route

NB = ("building", "road", "water", "vegetation", "railway")
SAMPLE = ("grass", "road", "trail", "tree", "water", "building", "baseball field")
VEGAS = ("paved road", "unpaved road")

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------ distance_hard
    B(
        "All routing must respect a minimum 10 m setback from building footprints; no segment of "
        "the path may come closer than that to any structure.",
        "analyst",
        "distance_hard",
        ("building",),
        (("keep_out", "building", 10),),
        routes=(R("massachusetts", "keeps", "building", 10),),
        why="'must respect a minimum ... setback' is absolute wording: a hard 10 m zone",
    ),
    B(
        "Please apply a hard standoff of 15 metres from the railway corridor. The path is not "
        "permitted to enter that buffer under any circumstances.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "railway", 15), ("avoided", "water")),
        routes=(R("nb1", "keeps", "railway", 15),),
        why="hard standoff with a number; water is an unmentioned hazard, so avoided by prior",
    ),
    B(
        "For safety reasons the route must remain at least 5 m from open water at all times.",
        "analyst",
        "distance_hard",
        ("grass", "road", "trail", "tree", "water", "building"),
        (("keep_out", "water", 5), ("neutral", "grass")),
        routes=(R("sample", "keeps", "water", 5),),
    ),
    B(
        "constraint: min clearance 3m to tree crowns. hard.",
        "robot",
        "distance_hard",
        ("tree",),
        (("keep_out", "tree", 3),),
        routes=(R("neon", "keeps", "tree", 3),),
    ),
    B(
        "Never get within twenty metres of the water, the bank is unstable along there.",
        "field",
        "distance_hard",
        NB,
        (("keep_out", "water", 20),),
        routes=(R("nb2", "keeps", "water", 20),),
        why="'never get within' is absolute; the number is written as a word",
    ),
    B(
        "Observe a 30 m exclusion buffer around every building in the study area. That buffer is "
        "an absolute constraint, not a preference.",
        "analyst",
        "distance_hard",
        ("building", "road"),
        (("keep_out", "building", 30), ("neutral", "road")),
    ),
    B(
        "No part of the flight path may pass within 2 meters of a tree crown; this clearance is "
        "required for the rotor span.",
        "analyst",
        "distance_hard",
        ("tree",),
        (("keep_out", "tree", 2),),
        routes=(R("neon", "keeps", "tree", 2),),
    ),
    # ------------------------------------------------------------------ distance_soft
    B(
        "Where practicable, the planned corridor should maintain a buffer of approximately 10 m "
        "from watercourses and water bodies.",
        "analyst",
        "distance_soft",
        NB,
        (("soft_zone", "water", 10),),
        routes=(R("nb1", "farther", "water"),),
        why="'where practicable ... should' softens the buffer: a soft zone keeping the 10 m",
    ),
    B(
        "Ideally keep roughly 8 m between the route and any building, though brief encroachments "
        "are acceptable if the alternative is a long detour.",
        "analyst",
        "distance_soft",
        ("building", "grass", "road"),
        (("soft_zone", "building", 8), ("not_lethal", "building")),
        routes=(R("massachusetts", "farther", "building"),),
    ),
    B(
        "prefer >= 5 m from road edge (soft, not a hard limit)",
        "robot",
        "distance_soft",
        ("road", "grass"),
        (("soft_zone", "road", 5),),
        routes=(R("sample", "farther", "road"),),
    ),
    B(
        "Try and stay about 15 meters off the railway line if you can. Not the end of the world if you can't.",
        "field",
        "distance_soft",
        NB,
        (("soft_zone", "railway", 15), ("not_lethal", "railway")),
    ),
    B(
        "A soft setback of 20 m from the shoreline is preferred for this survey; it is a weighting, not an exclusion.",
        "analyst",
        "distance_soft",
        ("water", "grass", "tree"),
        (("soft_zone", "water", 20),),
        why="the shoreline is the edge of the water layer",
    ),
    B(
        "Preferably, routes should stay five metres or more from the tree line, but this is "
        "guidance rather than a constraint.",
        "analyst",
        "distance_soft",
        ("tree", "grass"),
        (("soft_zone", "tree", 5),),
        routes=(R("neon", "farther", "tree"),),
    ),
    B(
        "Preferably maintain around 6 m of separation from the unpaved roads, as dust is a "
        "nuisance, although this is not a strict requirement.",
        "analyst",
        "distance_soft",
        VEGAS,
        (("soft_zone", "unpaved road", 6), ("neutral", "paved road")),
    ),
    # ------------------------------------------------------------------ graded_away
    B(
        "The mission should give the built-up area a wide berth: the further the route stays "
        "from buildings, the better.",
        "analyst",
        "graded_away",
        ("building", "road"),
        (("graded_away", "building", None),),
        routes=(R("massachusetts", "farther", "building"),),
    ),
    B(
        "Do not route near the railway. Proximity to the tracks should be penalised "
        "progressively, with no hard cut-off.",
        "analyst",
        "graded_away",
        NB,
        (("graded_away", "railway", None),),
        routes=(R("nb1", "farther", "railway"),),
    ),
    B(
        "Keep well away from the water, there are kids playing down there most afternoons.",
        "field",
        "graded_away",
        SAMPLE,
        (("graded_away", "water", None),),
        routes=(R("sample", "farther", "water"),),
    ),
    B(
        "cost: distance decay from building. closer = worse. no hard limit.",
        "robot",
        "graded_away",
        ("building",),
        (("graded_away", "building", None),),
        routes=(R("kampala", "farther", "building"),),
    ),
    B(
        "Proximity to tree canopy should be minimised. Treat the canopy edge as increasingly "
        "undesirable the nearer the path gets, with no effect beyond about 12 metres.",
        "analyst",
        "graded_away",
        ("tree", "grass"),
        (("graded_away", "tree", 12),),
        routes=(R("neon", "farther", "tree"),),
        why="a fall-off that stops mattering at 12 m: graded, reaching neutral at 12 m",
    ),
    B(
        "As a general principle, the route should stay as far from the road network as is "
        "reasonable, since vehicle traffic is a concern in this district.",
        "analyst",
        "graded_away",
        ("road", "grass", "tree"),
        (("graded_away", "road", None),),
        routes=(R("sample", "farther", "road"),),
    ),
    # ------------------------------------------------------------------ graded_toward
    B(
        "The route should remain in close proximity to the road network so that the vehicle can "
        "be recovered quickly if it fails.",
        "analyst",
        "graded_toward",
        NB,
        (("graded_toward", "road", None), ("avoided", "water")),
        routes=(R("nb1", "closer", "road"),),
    ),
    B(
        "Keep the flight path within visual range of the trail throughout; the nearer to the trail, the better.",
        "analyst",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "trail", None),),
        routes=(R("sample", "closer", "trail"),),
    ),
    B(
        "Stick close to the buildings, we want to be in their shade for most of the way.",
        "field",
        "graded_toward",
        ("building", "grass"),
        (("graded_toward", "building", None),),
        routes=(R("massachusetts", "closer", "building"),),
    ),
    B(
        "objective: minimise distance to road along path. hug road.",
        "robot",
        "graded_toward",
        ("road", "grass"),
        (("graded_toward", "road", None),),
        routes=(R("sample", "closer", "road"),),
    ),
    B(
        "The operator has to keep the aircraft within line of sight of the water, so the preferred "
        "path should track near the shore.",
        "analyst",
        "graded_toward",
        ("water", "grass", "tree", "building"),
        (("graded_toward", "water", None),),
        routes=(R("sample", "closer", "water"),),
        why="'within line of sight of' is the keep-within-sight construct: cheaper the nearer",
    ),
    B(
        "Favour cells close to the paved road; the benefit of proximity should decline "
        "gradually with distance from the pavement.",
        "analyst",
        "graded_toward",
        VEGAS,
        (("graded_toward", "paved road", None),),
        routes=(R("vegas", "closer", "paved road"),),
    ),
    # ------------------------------------------------------------------ on_beside
    B(
        "Follow the road corridor, but travel on the verge adjacent to the carriageway rather "
        "than on the road surface itself.",
        "analyst",
        "on_beside",
        NB,
        (("beside", "road"),),
        routes=(R("nb1", "beside", "road", 5),),
    ),
    B(
        "Walk alongside the water's edge but stay out of the water itself.",
        "field",
        "on_beside",
        ("water", "grass", "tree"),
        (("beside", "water"), ("lethal", "water")),
        routes=(R("sample", "beside", "water", 5), R("sample", "zero_on", "water")),
        why="'stay out of' forbids, so the water is lethal; the edge band is preferred",
    ),
    B(
        "Route parallel to the railway within its right of way, without occupying the track bed.",
        "analyst",
        "on_beside",
        NB,
        (("beside", "railway"),),
        routes=(R("nb2", "beside", "railway", 5),),
    ),
    B(
        "follow trail edge. do not drive on trail surface.",
        "robot",
        "on_beside",
        SAMPLE,
        (("beside", "trail"),),
        routes=(R("sample", "beside", "trail", 3),),
    ),
    B(
        "The survey line should run along the shoulder of the paved road; the paved surface itself is to be avoided.",
        "analyst",
        "on_beside",
        VEGAS,
        (("beside", "paved road"), ("avoided", "paved road")),
        routes=(R("vegas", "beside", "paved road", 5),),
    ),
    B(
        "Trace the perimeter of each building: move along the outside walls, not over the roofs.",
        "analyst",
        "on_beside",
        ("building",),
        (("beside", "building"),),
        routes=(R("massachusetts", "beside", "building", 3),),
    ),
    # ------------------------------------------------------------------ qualified
    B(
        "Use paved roads wherever available; unpaved roads should be avoided because they degrade sensor stability.",
        "analyst",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road"), ("below", "paved road", "unpaved road")),
        routes=(R("vegas", "more_on", "paved road"),),
    ),
    B(
        "Unpaved roads are acceptable, but the paved road network should be avoided owing to traffic volumes.",
        "analyst",
        "qualified",
        VEGAS,
        (("avoided", "paved road"), ("below", "unpaved road", "paved road"), ("not_lethal", "paved road")),
        routes=(R("vegas", "less_on", "paved road"),),
    ),
    B(
        "Conifers are fine to push through, deciduous trees not so much, go around those.",
        "field",
        "qualified",
        ("conifer tree", "deciduous tree", "grass"),
        (("avoided", "deciduous tree"), ("below", "conifer tree", "deciduous tree"), ("neutral", "conifer tree")),
        why="'fine' merely allows the conifers (lifting the tree prior to neutral)",
    ),
    B(
        "Treat deciduous stands as preferred cover and coniferous stands as neutral terrain.",
        "analyst",
        "qualified",
        ("deciduous tree", "conifer tree"),
        (("preferred", "deciduous tree"), ("neutral", "conifer tree")),
    ),
    B(
        "Avoid all buildings, with the exception of the hangar, which may be entered.",
        "analyst",
        "qualified",
        ("building", "hangar", "grass"),
        (("avoided", "building"), ("neutral", "hangar"), ("below", "hangar", "building")),
        why="the excepted hangar is merely allowed: neutral",
    ),
    B(
        "Water bodies are off limits, except for the ford, which the vehicle is rated to cross.",
        "analyst",
        "qualified",
        ("water", "ford", "road"),
        (("lethal", "water"), ("not_lethal", "ford")),
    ),
    # ------------------------------------------------------------------ terse
    B(
        "road > grass > tree",
        "robot",
        "terse",
        ("road", "grass", "tree"),
        (("below", "road", "grass"), ("below", "grass", "tree")),
        routes=(R("sample", "more_on", "road"),),
        why="'A > B' ranks A above B: A is the cheaper",
    ),
    B(
        "water: no-go. building: no-go.",
        "robot",
        "terse",
        SAMPLE,
        (("lethal", "water"), ("lethal", "building"), ("neutral", "grass")),
        routes=(R("sample", "zero_on", "water"), R("sample", "zero_on", "building")),
    ),
    B(
        "trees fine, water bad",
        "field",
        "terse",
        ("tree", "water", "grass"),
        (("neutral", "tree"), ("avoided", "water")),
    ),
    B(
        "pavd road: prefer. unpaved rd: avoid.",
        "robot",
        "terse",
        VEGAS,
        (("preferred", "paved road"), ("avoided", "unpaved road")),
        routes=(R("vegas", "more_on", "paved road"),),
        why="typos in both multi-word names",
    ),
    B(
        "basebal feild off limits!!",
        "field",
        "terse",
        SAMPLE,
        (("lethal", "baseball field"),),
        routes=(R("sample", "zero_on", "baseball field"),),
    ),
    B(
        "Roads: preferred. Vegetation: avoid. Railway: prohibited.",
        "analyst",
        "terse",
        NB,
        (("preferred", "road"), ("avoided", "vegetation"), ("lethal", "railway")),
        routes=(R("nb1", "more_on", "road"), R("nb1", "less_on", "vegetation")),
    ),
    # ------------------------------------------------------------------ permission
    B(
        "Crossing water is permitted for this platform. It is amphibious, so shallow water should "
        "not be penalised at all.",
        "analyst",
        "permission",
        ("water", "grass", "building"),
        (("neutral", "water"), ("not_lethal", "water"), ("avoided", "building")),
        why="permission lifts the water prior to neutral; buildings keep their prior",
    ),
    B(
        "You can go straight through the trees, no problem, they're pretty sparse.",
        "field",
        "permission",
        ("tree", "grass"),
        (("neutral", "tree"), ("not_lethal", "tree")),
    ),
    B(
        "The building interiors are strictly off limits; keep out of every footprint.",
        "analyst",
        "permission",
        ("building", "road"),
        (("lethal", "building"), ("neutral", "road")),
        routes=(R("massachusetts", "zero_on", "building"), R("kampala", "zero_on", "building")),
    ),
    B(
        "railway: crossing allowed.",
        "robot",
        "permission",
        NB,
        (("neutral", "railway"), ("not_lethal", "railway"), ("avoided", "water")),
    ),
    B(
        "Stay out of the water under all circumstances, but the railway may be crossed freely.",
        "analyst",
        "permission",
        NB,
        (("lethal", "water"), ("neutral", "railway")),
    ),
    B(
        "Do not cross the railway line at any point during the traverse.",
        "analyst",
        "permission",
        NB,
        (("no_cross", "railway"),),
    ),
    B(
        "Grass is fine to drive on, but don't go into the baseball field.",
        "field",
        "permission",
        SAMPLE,
        (("neutral", "grass"), ("lethal", "baseball field")),
        routes=(R("sample", "zero_on", "baseball field"),),
    ),
    # ------------------------------------------------------------------ clauses
    B(
        "Prefer the road network and avoid vegetation where possible. Capture oblique photographs "
        "of each bridge crossing for the inspection report.",
        "analyst",
        "clauses",
        NB,
        (("preferred", "road"), ("avoided", "vegetation"), ("unread", "photographs")),
        routes=(R("nb1", "more_on", "road"),),
    ),
    B(
        "Avoid buildings. The mission must be completed before sunset, and the battery should "
        "not drop below 30 percent.",
        "analyst",
        "clauses",
        ("building", "grass"),
        (("avoided", "building"), ("unread", "sunset"), ("unread", "battery")),
    ),
    B(
        "avoid water. log telemetry at 10 Hz. prefer trail.",
        "robot",
        "clauses",
        SAMPLE,
        (("avoided", "water"), ("preferred", "trail"), ("unread", "telemetry")),
        routes=(R("sample", "more_on", "trail"),),
    ),
    B(
        "Stay on the roads where you can and try to avoid the grass. Radio in when you reach the gate.",
        "field",
        "clauses",
        ("road", "grass"),
        (("preferred", "road"), ("avoided", "grass"), ("unread", "radio")),
    ),
    B(
        "Maintain a minimum 12 m standoff from the railway and prefer the road network elsewhere.",
        "analyst",
        "clauses",
        NB,
        (("keep_out", "railway", 12), ("preferred", "road"), ("all_read",)),
        routes=(R("nb1", "keeps", "railway", 12),),
    ),
    B(
        "Avoid trees and water; prefer grass.",
        "analyst",
        "clauses",
        ("tree", "water", "grass"),
        (("avoided", "tree"), ("avoided", "water"), ("preferred", "grass"), ("all_read",)),
        routes=(R("sample", "more_on", "grass"),),
    ),
    B(
        "Give the railway a wide berth. Coordinate with the landowner beforehand regarding access permissions.",
        "analyst",
        "clauses",
        NB,
        (("graded_away", "railway", None), ("unread", "landowner")),
    ),
    B(
        "Head through the grass rather than the trees, and bring back a soil sample from the far corner.",
        "field",
        "clauses",
        ("grass", "tree"),
        (("below", "grass", "tree"), ("unread", "soil")),
        routes=(R("sample", "less_on", "tree"),),
    ),
    B(
        "The corridor must keep at least 5 m from buildings (hard constraint). Deliverables are "
        "due to the client on Friday.",
        "analyst",
        "clauses",
        ("building", "road"),
        (("keep_out", "building", 5), ("unread", "deliverables")),
        routes=(R("massachusetts", "keeps", "building", 5),),
    ),
]

DOUBTFUL: dict[str, str] = {}
