"""Mission briefs, set 1: voice mostly "analyst".

GIS analysts writing missions for a costmap: measured wording, sometimes list-like, sometimes
long multi-sentence briefs with distances in metres; a few briefs in the "robot" and "field"
voices. Written without reading the interpreter, its tests or its corpora, and scored once at
first contact (``bench/mission_briefs_report.py --set 1``). Never edit a brief to make the
interpreter pass; a case whose expectation contradicts the cost-scale contract is retired in
``DOUBTFUL`` with the reason.
"""

from __future__ import annotations

from .mission_briefs import Brief, Route

B = Brief
R = Route

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------ distance_hard
    B(
        "Plan the survey route so that it never comes closer than 15 m to any building. "
        "Roads are preferred where they exist.",
        "analyst",
        "distance_hard",
        ("building", "road", "vegetation", "water"),
        (("keep_out", "building", 15), ("preferred", "road"), ("below", "road", "vegetation")),
        routes=(R("nb1", "keeps", "building", 15),),
    ),
    B(
        "The vehicle must stay at least 3 metres from the fence at all times. Open grass is fine to cross.",
        "analyst",
        "distance_hard",
        ("fence", "grass", "tree"),
        (("keep_out", "fence", 3), ("not_lethal", "grass")),
    ),
    B(
        "Maintain a minimum standoff of 25 m from the railway line throughout the mission. Use "
        "the road network where possible and avoid open water.",
        "analyst",
        "distance_hard",
        ("railway", "road", "water", "vegetation"),
        (("keep_out", "railway", 25), ("preferred", "road"), ("avoided", "water"), ("not_lethal", "water")),
        routes=(R("nb2", "keeps", "railway", 25),),
    ),
    B(
        "Hard constraint: never within 5 m of the power line corridor. Otherwise shortest path.",
        "robot",
        "distance_hard",
        ("power line", "grass", "paved road"),
        (("keep_out", "power line", 5), ("not_lethal", "grass")),
    ),
    B(
        "don't ever get within 10 metres of the river, the banks are undercut. stick to the track",
        "field",
        "distance_hard",
        ("river", "unpaved road", "tree"),
        (("keep_out", "river", 10), ("preferred", "unpaved road")),
    ),
    B(
        "Under no circumstances should the route pass within 8 m of a house. The houses in "
        "this tile are occupied and the owners have not given consent. Gardens and lawns may "
        "be crossed.",
        "analyst",
        "distance_hard",
        ("building", "grass", "paved road"),
        (("keep_out", "building", 8), ("not_lethal", "grass")),
        routes=(R("massachusetts", "keeps", "building", 8),),
    ),
    B(
        "Keep a minimum clearance of 2 m from every structure at all times. The footpaths "
        "between dwellings are acceptable where they satisfy that clearance.",
        "analyst",
        "distance_hard",
        ("building", "unpaved road"),
        (("keep_out", "building", 2), ("not_lethal", "unpaved road")),
        routes=(R("kampala", "keeps", "building", 2),),
    ),
    # ------------------------------------------------------------------ distance_soft
    B(
        "Where practical, try to keep some 10 m of separation from the hedgerows; this is not critical.",
        "analyst",
        "distance_soft",
        ("hedge", "grass", "unpaved road"),
        (("soft_zone", "hedge", 10), ("not_lethal", "hedge")),
    ),
    B(
        "Ideally the route should stay roughly 20 m back from the lake shore, but it may come "
        "closer if the detour would be long. Gravel tracks are preferred over open grass.",
        "analyst",
        "distance_soft",
        ("water", "unpaved road", "grass"),
        (("soft_zone", "water", 20), ("preferred", "unpaved road"), ("below", "unpaved road", "grass")),
        why="'ideally ... may come closer' is a soft buffer, not a keep-out.",
    ),
    B(
        "try and stay a few metres back from the trees if you can, say 5",
        "field",
        "distance_soft",
        ("tree", "grass"),
        (("soft_zone", "tree", 5), ("not_lethal", "tree")),
    ),
    B(
        "Preferably keep about 15 m from the buildings. This is a preference, not a hard "
        "limit. The road can be used freely.",
        "analyst",
        "distance_soft",
        ("building", "road", "vegetation"),
        (("soft_zone", "building", 15), ("not_lethal", "road"), ("below", "road", "building")),
        why="'used freely' is a permission, so the road is only asserted cheaper than buildings.",
    ),
    B(
        "Soft constraint: 30 m buffer from wetland edge. Penalise, do not forbid.",
        "robot",
        "distance_soft",
        ("marsh", "grass", "unpaved road"),
        (("soft_zone", "marsh", 30), ("not_lethal", "marsh"), ("avoided", "marsh")),
    ),
    B(
        "If it can be managed, give the car park a berth of around 12 m because of pedestrians. Not essential.",
        "analyst",
        "distance_soft",
        ("parking lot", "building", "paved road"),
        (("soft_zone", "parking lot", 12), ("not_lethal", "parking lot")),
    ),
    # ------------------------------------------------------------------ graded_away
    B(
        "Keep well away from the railway line; the further from it the better.",
        "analyst",
        "graded_away",
        ("railway", "road", "vegetation", "building"),
        (("graded_away", "railway", None), ("avoided", "railway"), ("not_lethal", "railway")),
        routes=(R("nb1", "farther", "railway"),),
    ),
    B(
        "don't go near the pond",
        "field",
        "graded_away",
        ("water", "grass", "tree"),
        (("graded_away", "water", None), ("avoided", "water"), ("not_lethal", "water")),
        routes=(R("sample", "farther", "water"),),
        why="'don't go near' prices nearness; it does not forbid the pond outright.",
    ),
    B(
        "The route should favour distance from the buildings: the closer it passes, the higher "
        "the cost, with no penalty beyond about 40 m.",
        "analyst",
        "graded_away",
        ("building", "road", "grass"),
        (("graded_away", "building", 40), ("avoided", "building")),
        routes=(R("massachusetts", "farther", "building"),),
    ),
    B(
        "Stay as far as practicable from the power lines, which are live. Passing beneath them "
        "is permitted where it cannot be avoided.",
        "analyst",
        "graded_away",
        ("power line", "field", "unpaved road"),
        (("graded_away", "power line", None), ("not_lethal", "power line"), ("avoided", "power line")),
    ),
    B(
        "minimise proximity to creek. no hard limit.",
        "robot",
        "graded_away",
        ("stream", "tree", "grass"),
        (("graded_away", "stream", None), ("not_lethal", "stream")),
    ),
    B(
        "Give the houses a wide berth where you can; the further the better up to roughly "
        "25 m, beyond which it makes no difference. Tracks and roads are both acceptable.",
        "analyst",
        "graded_away",
        ("building", "paved road", "unpaved road", "grass"),
        (
            ("graded_away", "building", 25),
            ("avoided", "building"),
            ("not_lethal", "unpaved road"),
            ("not_lethal", "paved road"),
        ),
    ),
    # ------------------------------------------------------------------ graded_toward
    B(
        "Stay close to the road for the whole route so that the support vehicle can reach the "
        "robot. It need not be on the road itself.",
        "analyst",
        "graded_toward",
        ("road", "vegetation", "building"),
        (("graded_toward", "road", None), ("not_lethal", "road")),
        routes=(R("nb1", "closer", "road"),),
    ),
    B(
        "keep within sight of the river, we navigate by it",
        "field",
        "graded_toward",
        ("river", "tree", "grass"),
        (("graded_toward", "river", None), ("avoided", "river")),
        why="Navigating by the river means staying near it, not driving in it; the river keeps its hazard prior.",
    ),
    B(
        "Hug the tree line where possible, as the canopy edge reduces visibility from the road. "
        "The nearer the edge of the trees the better, out to about 20 m.",
        "analyst",
        "graded_toward",
        ("tree", "grass", "paved road"),
        (("graded_toward", "tree", 20), ("below", "grass", "paved road")),
        routes=(R("sample", "closer", "tree"),),
        why="The road is where visibility comes from, so open grass is the better of the two.",
    ),
    B(
        "Remain in the vicinity of the gravel track; the nearer the better.",
        "analyst",
        "graded_toward",
        ("unpaved road", "grass", "tree"),
        (("graded_toward", "unpaved road", None), ("not_lethal", "unpaved road")),
    ),
    B(
        "The drone's radio link is short, so keep the ground vehicle as close to the building "
        "cluster as practicable, without entering any building.",
        "analyst",
        "graded_toward",
        ("building", "paved road", "grass"),
        (("graded_toward", "building", None), ("lethal", "building")),
        why="'without entering any building' forbids entry.",
    ),
    B(
        "Follow the general line of the railway, staying within about 50 m of it, so that the "
        "route can be cross-referenced against the track chainage.",
        "analyst",
        "graded_toward",
        ("railway", "road", "vegetation"),
        (("graded_toward", "railway", 50),),
    ),
    # ------------------------------------------------------------------ on_beside
    B(
        "Follow the river bank downstream but stay out of the water itself.",
        "analyst",
        "on_beside",
        ("water", "vegetation", "road"),
        (("beside", "water"), ("lethal", "water")),
        routes=(R("nb1", "beside", "water", 5), R("nb1", "zero_on", "water")),
    ),
    B(
        "go along the fence line, never on it",
        "field",
        "on_beside",
        ("fence", "grass"),
        (("beside", "fence"), ("not_lethal", "grass")),
    ),
    B(
        "Route along the verge of the main road, keeping off the carriageway itself, which is live with traffic.",
        "analyst",
        "on_beside",
        ("paved road", "grass", "building"),
        (("beside", "paved road"), ("not_lethal", "grass")),
        routes=(R("vegas", "beside", "paved road", 5),),
    ),
    B(
        "Track alongside railway, offset 2-5 m. Do not occupy the rail corridor.",
        "robot",
        "on_beside",
        ("railway", "vegetation", "road"),
        (("beside", "railway"), ("not_lethal", "vegetation")),
    ),
    B(
        "Walk the edge of the marsh to map its boundary. Keep to the firm ground next to it rather than in the marsh.",
        "analyst",
        "on_beside",
        ("marsh", "grass", "tree"),
        (("beside", "marsh"), ("not_lethal", "grass")),
    ),
    B(
        "Trace the hedge on its field side: run parallel to it a couple of metres out, but do "
        "not drive through the hedge.",
        "analyst",
        "on_beside",
        ("hedge", "field", "unpaved road"),
        (("beside", "hedge"), ("not_lethal", "field")),
    ),
    B(
        "Skirt the lake along its shoreline without entering the water. Paths and grass are both fine for this leg.",
        "analyst",
        "on_beside",
        ("water", "grass", "trail", "tree"),
        (("beside", "water"), ("lethal", "water"), ("not_lethal", "trail")),
        routes=(R("sample", "beside", "water", 5),),
    ),
    B(
        "follow the creek but keep your feet dry",
        "field",
        "on_beside",
        ("stream", "tree", "grass"),
        (("beside", "stream"), ("not_lethal", "grass")),
        why="'Keep your feet dry' means walking beside the creek, not in it.",
    ),
    # ------------------------------------------------------------------ qualified
    B(
        "Use tarmac before gravel tracks, and gravel tracks before open ground.",
        "analyst",
        "qualified",
        ("paved road", "unpaved road", "grass"),
        (("below", "paved road", "unpaved road"), ("below", "unpaved road", "grass"), ("preferred", "paved road")),
        routes=(R("vegas", "more_on", "paved road"),),
    ),
    B(
        "The lawns are fine to cross except the cricket pitch, which must not be driven on.",
        "analyst",
        "qualified",
        ("grass", "cricket pitch", "building"),
        (("not_lethal", "grass"), ("lethal", "cricket pitch")),
        why="'must not be driven on' forbids the pitch.",
    ),
    B(
        "Deciduous woodland may be crossed if necessary; the conifer plantation is dense and should be avoided.",
        "analyst",
        "qualified",
        ("deciduous forest", "coniferous forest", "grass"),
        (
            ("below", "deciduous forest", "coniferous forest"),
            ("avoided", "coniferous forest"),
            ("not_lethal", "deciduous forest"),
            ("not_lethal", "coniferous forest"),
        ),
    ),
    B(
        "dirt tracks are ok but stick to the paved lanes when you can",
        "field",
        "qualified",
        ("paved road", "unpaved road", "tree"),
        (("preferred", "paved road"), ("below", "paved road", "unpaved road"), ("not_lethal", "unpaved road")),
    ),
    B(
        "The open fields may be crossed, apart from the fenced paddock in the north-east, which "
        "holds livestock and is off limits.",
        "analyst",
        "qualified",
        ("field", "paddock", "fence"),
        (("lethal", "paddock"), ("not_lethal", "field")),
    ),
    B(
        "Prefer the sealed roads. The unsealed farm tracks flood after rain and are to be avoided.",
        "analyst",
        "qualified",
        ("paved road", "unpaved road", "field"),
        (("preferred", "paved road"), ("avoided", "unpaved road"), ("not_lethal", "unpaved road")),
    ),
    B(
        "Grass is fine everywhere except the baseball field; stay out of the diamond entirely. "
        "Use the trails where they go the right way.",
        "analyst",
        "qualified",
        ("grass", "baseball field", "trail", "road"),
        (("lethal", "baseball field"), ("not_lethal", "grass"), ("preferred", "trail")),
        routes=(R("sample", "zero_on", "baseball field"), R("sample", "more_on", "trail")),
    ),
    # ------------------------------------------------------------------ terse
    B(
        "roads good. scrub ok. houses, ponds: no.",
        "field",
        "terse",
        ("paved road", "shrub", "building", "water"),
        (("preferred", "paved road"), ("neutral", "shrub"), ("avoided", "building"), ("avoided", "water")),
        why="In a terse list 'no' means avoid, not forbid; 'ok' means allowed (neutral).",
    ),
    B(
        "trail > meadow > marsh",
        "analyst",
        "terse",
        ("trail", "grass", "marsh"),
        (("below", "trail", "grass"), ("below", "grass", "marsh"), ("preferred", "trail")),
        why="The meadow is the grass layer.",
    ),
    B(
        "paved road >> unpaved road",
        "robot",
        "terse",
        ("paved road", "unpaved road", "building"),
        (("below", "paved road", "unpaved road"), ("preferred", "paved road")),
    ),
    B(
        "power lines: avoid. railway: avoid. fields: fine.",
        "analyst",
        "terse",
        ("power line", "railway", "field"),
        (("avoided", "power line"), ("avoided", "railway"), ("not_lethal", "power line"), ("neutral", "field")),
    ),
    B(
        "stick to teh gravle trak, keep off the wheet",
        "field",
        "terse",
        ("unpaved road", "crop", "tree"),
        (("preferred", "unpaved road"), ("avoided", "crop")),
        why="'gravle trak' is the gravel track (unpaved road); 'wheet' is the wheat crop.",
    ),
    B(
        "use the pavd raod, avoid the buidlings",
        "field",
        "terse",
        ("paved road", "building", "grass"),
        (("preferred", "paved road"), ("avoided", "building"), ("not_lethal", "building")),
    ),
    B(
        "water: no-go. trees: avoid. road: prefer.",
        "analyst",
        "terse",
        ("water", "tree", "road", "grass"),
        (("lethal", "water"), ("avoided", "tree"), ("not_lethal", "tree"), ("preferred", "road")),
    ),
    B(
        "car park ok, lawn ok, flower beds no",
        "robot",
        "terse",
        ("parking lot", "grass", "flower bed"),
        (("neutral", "parking lot"), ("neutral", "grass"), ("avoided", "flower bed")),
        why="'no' in a terse list means avoid, not forbid.",
    ),
    # ------------------------------------------------------------------ permission
    B(
        "No need to avoid the sheds, they are empty ruins. Keep out of the pond entirely.",
        "analyst",
        "permission",
        ("building", "water", "grass"),
        (("neutral", "building"), ("lethal", "water")),
        routes=(R("sample", "zero_on", "water"),),
    ),
    B(
        "the trees are fine to go under, canopy's high. just don't go into the river",
        "field",
        "permission",
        ("tree", "river", "grass"),
        (("neutral", "tree"), ("lethal", "river")),
    ),
    B(
        "Avoid the wetland where possible, but it is not forbidden: the vehicle can cope with shallow water.",
        "analyst",
        "permission",
        ("marsh", "grass", "unpaved road"),
        (("avoided", "marsh"), ("not_lethal", "marsh")),
    ),
    B(
        "The railway is disused and may be crossed or followed freely. Stay out of the buildings.",
        "analyst",
        "permission",
        ("railway", "building", "vegetation", "road"),
        (("neutral", "railway"), ("lethal", "building")),
        routes=(R("nb1", "zero_on", "building"),),
    ),
    B(
        "building: permitted (demolition site, no occupants). water: stay out.",
        "robot",
        "permission",
        ("building", "water", "unpaved road"),
        (("neutral", "building"), ("lethal", "water")),
    ),
    B(
        "Do not go into the fenced compound under any circumstances. Avoid the hedges, though "
        "they can be pushed through if there is no other way.",
        "analyst",
        "permission",
        ("compound", "hedge", "grass"),
        (("lethal", "compound"), ("avoided", "hedge"), ("not_lethal", "hedge")),
    ),
    B(
        "The water bodies in this tile are dry seasonal channels and need not be avoided. The "
        "road is the preferred surface.",
        "analyst",
        "permission",
        ("water", "road", "vegetation", "building"),
        (("neutral", "water"), ("preferred", "road")),
        routes=(R("nb2", "more_on", "road"),),
    ),
    # ------------------------------------------------------------------ clauses
    B(
        "Prefer the gravel tracks and avoid the woods, and bring the survey drone back by noon.",
        "analyst",
        "clauses",
        ("unpaved road", "forest", "grass"),
        (("preferred", "unpaved road"), ("avoided", "forest"), ("unread", "noon")),
    ),
    B(
        "weather permitting, take the road and stay out of the railway cutting",
        "field",
        "clauses",
        ("road", "railway", "vegetation"),
        (("preferred", "road"), ("lethal", "railway"), ("unread", "weather")),
    ),
    B(
        "Avoid the buildings and the water. Stay on the roads where possible.",
        "analyst",
        "clauses",
        ("building", "water", "road", "vegetation"),
        (("avoided", "building"), ("avoided", "water"), ("preferred", "road"), ("all_read",)),
    ),
    B(
        "Keep the route on the lawns, avoid the flower beds, and make sure the operator logs the "
        "battery level at each waypoint.",
        "analyst",
        "clauses",
        ("grass", "flower bed", "paved road"),
        (("preferred", "grass"), ("avoided", "flower bed"), ("unread", "battery")),
    ),
    B(
        "Prefer paved road. Avoid unpaved road. Transmit telemetry at 10 Hz.",
        "robot",
        "clauses",
        ("paved road", "unpaved road"),
        (("preferred", "paved road"), ("avoided", "unpaved road"), ("unread", "telemetry")),
    ),
    B(
        "Keep out of the marsh, keep to the embankment path, and remember that the tide turns at 4 pm.",
        "analyst",
        "clauses",
        ("marsh", "trail", "water"),
        (("lethal", "marsh"), ("preferred", "trail"), ("unread", "tide")),
    ),
    B(
        "Prefer the trail over the grass, avoid the trees, and avoid the water.",
        "analyst",
        "clauses",
        ("trail", "grass", "tree", "water"),
        (("below", "trail", "grass"), ("avoided", "tree"), ("avoided", "water"), ("all_read",)),
    ),
    B(
        "avoid the houses, go by the lane, and the blue van is the pickup",
        "field",
        "clauses",
        ("building", "paved road", "grass"),
        (("avoided", "building"), ("preferred", "paved road"), ("unread", "van")),
    ),
]

DOUBTFUL: dict[str, str] = {}
