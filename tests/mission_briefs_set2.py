"""Mission briefs, set 2 (issue 31): held-out briefs, voice mostly "robot".

Set 2 is written mostly in the "robot" voice: robotics engineers and UGV / rover operators
writing mission constraints -- technical and imperative ("the platform must", "the UGV shall"),
clearances in metres, sometimes numbered rules -- with a few "analyst" and "field" briefs.

It was written WITHOUT reading the interpreter (``overseec_core/interpret/``), its tests or its
corpora, from a plain sense of how such people write, and it is scored ONCE at first contact
(``bench/mission_briefs_report.py --set 2``); that first-contact figure is the one that counts.
Never edit a brief to make the interpreter pass; a case whose expectation contradicts the
cost-scale contract in ``tests/mission_briefs.py`` is retired in ``DOUBTFUL`` with the reason.
"""

from __future__ import annotations

from .mission_briefs import Brief, Route

B = Brief
R = Route

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------ distance_hard
    B(
        "The UGV shall maintain a minimum standoff of 8 m from all structures at all times. "
        "Paved roads are preferred for transit.",
        "robot", "distance_hard",
        ("building", "paved road", "grass"),
        (("keep_out", "building", 8), ("preferred", "paved road"), ("below", "paved road", "grass")),
        routes=(R("massachusetts", "keeps", "building", 8),),
    ),
    B(
        "Rule 1: the platform must never come closer than 15 m to the river. "
        "Rule 2: remain on the road network where practical.",
        "robot", "distance_hard",
        ("river", "paved road", "grass"),
        (("keep_out", "river", 15), ("preferred", "paved road"), ("below", "paved road", "grass")),
    ),
    B(
        "The rover must stay at least 3 metres off the perimeter fence. Use the gravel track for transit.",
        "robot", "distance_hard",
        ("fence", "unpaved road", "grass"),
        (("keep_out", "fence", 3), ("preferred", "unpaved road")),
    ),
    B(
        "Minimum separation from the railway line is 20 m. No exceptions. Roads preferred.",
        "robot", "distance_hard",
        ("railway", "road", "vegetation", "building"),
        (("keep_out", "railway", 20), ("preferred", "road")),
        routes=(R("nb1", "keeps", "railway", 20),),
    ),
    B(
        "The vehicle must stay at least 5 m from any building and at least 10 m from open water.",
        "robot", "distance_hard",
        ("building", "water", "road", "vegetation"),
        (("keep_out", "building", 5), ("keep_out", "water", 10)),
        routes=(R("nb2", "keeps", "building", 5), R("nb2", "keeps", "water", 10)),
    ),
    B(
        "The UGV must hold at least 2 m from tree crowns at all times (mast clearance).",
        "robot", "distance_hard",
        ("tree", "grass"),
        (("keep_out", "tree", 2), ("not_lethal", "grass")),
        routes=(R("neon", "keeps", "tree", 2),),
    ),
    B(
        "Hard constraint: no path segment within 12 m of the pylons. Crop fields may be crossed.",
        "analyst", "distance_hard",
        ("pylon", "power line", "crop field", "unpaved road"),
        (("keep_out", "pylon", 12), ("not_lethal", "crop field")),
    ),
    B(
        "Standoff from the fuel depot: 25 m minimum, mandatory. The platform shall use the "
        "asphalt access road.",
        "robot", "distance_hard",
        ("fuel depot", "paved road", "building", "grass"),
        (("keep_out", "fuel depot", 25), ("preferred", "paved road")),
    ),
    # ------------------------------------------------------------------ distance_soft
    B(
        "Where possible, keep some clearance from the hedgerows, about 4 m would be nice. "
        "Farm tracks preferred.",
        "robot", "distance_soft",
        ("hedge", "unpaved road", "crop field"),
        (("soft_zone", "hedge", 4), ("preferred", "unpaved road"), ("not_lethal", "hedge")),
    ),
    B(
        "The platform should ideally stay around 10 m from buildings, but it may pass closer "
        "if the route demands it.",
        "robot", "distance_soft",
        ("building", "paved road", "grass"),
        (("soft_zone", "building", 10), ("not_lethal", "building")),
    ),
    B(
        "Try to keep roughly 6 metres off the water's edge if you can; it is not a hard limit.",
        "robot", "distance_soft",
        ("water", "grass", "tree", "road", "building"),
        (("soft_zone", "water", 6), ("avoided", "water")),
        why="'not a hard limit' makes it soft; water is an unmentioned-hazard prior, so avoided, not lethal",
    ),
    B(
        "Preferably maintain 5 m from the wetland margin. Not mandatory.",
        "robot", "distance_soft",
        ("marsh", "grass", "unpaved road"),
        (("soft_zone", "marsh", 5), ("avoided", "marsh")),
        why="keeping off the margin implies not driving into the wetland either, but softly",
    ),
    B(
        "if u can keep a few metres off the orchard rows, say 3 m, but dont sweat it",
        "field", "distance_soft",
        ("orchard", "grass", "unpaved road"),
        (("soft_zone", "orchard", 3), ("not_lethal", "orchard")),
    ),
    B(
        "Soft constraint: a clearance of 8 m from parked vehicles in the lot is desirable.",
        "analyst", "distance_soft",
        ("parking lot", "car", "paved road"),
        (("soft_zone", "car", 8), ("not_lethal", "car")),
    ),
    # ------------------------------------------------------------------ graded_away
    B(
        "The UGV should not go near the drainage ditches. Roads are the preferred surface.",
        "robot", "graded_away",
        ("ditch", "road", "grass"),
        (("graded_away", "ditch", None), ("avoided", "ditch"), ("preferred", "road")),
    ),
    B(
        "Maximise distance from the power lines throughout the traverse.",
        "robot", "graded_away",
        ("power line", "grass", "crop field", "unpaved road"),
        (("graded_away", "power line", None), ("not_lethal", "power line")),
    ),
    B(
        "Keep well away from the pond. The further from it the better.",
        "robot", "graded_away",
        ("water", "grass", "tree", "building", "road"),
        (("graded_away", "water", None), ("avoided", "water")),
        routes=(R("sample", "farther", "water"),),
    ),
    B(
        "The platform must keep well clear of the railway, the further the better, out to about 30 m.",
        "robot", "graded_away",
        ("railway", "road", "vegetation", "building", "water"),
        (("graded_away", "railway", 30), ("not_lethal", "railway")),
        routes=(R("nb1", "farther", "railway"),),
        why="'well clear ... the further the better, out to about 30 m' prices distance, reaching neutral at 30 m",
    ),
    B(
        "Stay as far from the dwellings as practicable; the settlement is occupied.",
        "robot", "graded_away",
        ("building", "unpaved road"),
        (("graded_away", "building", None), ("avoided", "building"), ("not_lethal", "building")),
        routes=(R("kampala", "farther", "building"),),
    ),
    B(
        "Route should minimise proximity to the substation and the pylons.",
        "analyst", "graded_away",
        ("substation", "pylon", "grass", "paved road"),
        (("graded_away", "substation", None), ("graded_away", "pylon", None)),
    ),
    # ------------------------------------------------------------------ graded_toward
    B(
        "Hug the tree line on the way to the rally point; the platform should remain close to cover.",
        "robot", "graded_toward",
        ("tree", "grass", "road", "water", "building"),
        (("graded_toward", "tree", None), ("not_lethal", "tree")),
        routes=(R("sample", "closer", "tree"),),
    ),
    B(
        "The UGV shall stay close to the road at all times so that recovery remains possible.",
        "robot", "graded_toward",
        ("road", "vegetation", "building", "water"),
        (("graded_toward", "road", None), ("preferred", "road")),
    ),
    B(
        "Keep within sight of the river, ideally within 50 m of the bank. Do not drive into it.",
        "robot", "graded_toward",
        ("river", "grass", "tree", "unpaved road"),
        (("graded_toward", "river", 50), ("lethal", "river")),
        why="'do not drive into it' forbids entering the river (like 'don't go into')",
    ),
    B(
        "Remain near the fence line; it is the navigation reference for this sortie.",
        "robot", "graded_toward",
        ("fence", "grass", "crop field"),
        (("graded_toward", "fence", None), ("not_lethal", "grass")),
    ),
    B(
        "Stay near the buildings for comms relay coverage. Paved roads preferred where available.",
        "robot", "graded_toward",
        ("building", "paved road", "grass"),
        (("graded_toward", "building", None), ("preferred", "paved road")),
        routes=(R("massachusetts", "closer", "building"),),
    ),
    B(
        "stick close to the hedgerow so it isnt seen from the lane, and stay off the tarmac if you can",
        "field", "graded_toward",
        ("hedge", "grass", "paved road"),
        (("graded_toward", "hedge", None), ("avoided", "paved road")),
        why="'stay off ... if you can' is a soft avoid, not a prohibition",
    ),
    # ------------------------------------------------------------------ on_beside
    B(
        "Travel alongside the canal but never in it.",
        "robot", "on_beside",
        ("water", "grass", "building"),
        (("beside", "water"), ("lethal", "water")),
        why="'never in it' forbids the canal itself",
    ),
    B(
        "Follow the fence line, never on it.",
        "robot", "on_beside",
        ("fence", "grass", "crop field"),
        (("beside", "fence"), ("lethal", "fence")),
    ),
    B(
        "Skirt the forest edge without entering the forest.",
        "robot", "on_beside",
        ("forest", "grass", "unpaved road"),
        (("beside", "forest"), ("below", "grass", "forest")),
    ),
    B(
        "The UGV shall track parallel to the road on the verge, not on the carriageway itself; "
        "keep within 5 m of the road edge.",
        "robot", "on_beside",
        ("road", "grass", "tree", "building", "water"),
        (("beside", "road"), ("below", "grass", "road")),
        routes=(R("sample", "beside", "road", 5),),
    ),
    B(
        "Run along the railway embankment, off the tracks, within about 5 m of the rails.",
        "robot", "on_beside",
        ("railway", "vegetation", "road", "building", "water"),
        (("beside", "railway"), ("below", "vegetation", "railway")),
        routes=(R("nb1", "beside", "railway", 5),),
    ),
    B(
        "go along the stream bank, dont drive in the stream",
        "field", "on_beside",
        ("stream", "grass", "tree"),
        (("beside", "stream"), ("below", "grass", "stream")),
        why="'dont drive in' may be read as forbidding; the beside cue accepts avoided or lethal",
    ),
    B(
        "Traverse along the edge of the paved road on the shoulder, not on the asphalt.",
        "robot", "on_beside",
        ("paved road", "unpaved road"),
        (("beside", "paved road"),),
        routes=(R("vegas", "beside", "paved road", 5),),
    ),
    # ------------------------------------------------------------------ qualified
    B(
        "Asphalt preferred over gravel tracks; the platform may use gravel where no asphalt exists.",
        "robot", "qualified",
        ("paved road", "unpaved road", "grass"),
        (("below", "paved road", "unpaved road"), ("preferred", "paved road"), ("not_lethal", "unpaved road")),
    ),
    B(
        "Grass is fine except the helipad, which is also grass but must be avoided.",
        "robot", "qualified",
        ("grass", "helipad", "paved road"),
        (("avoided", "helipad"), ("below", "grass", "helipad"), ("not_lethal", "grass")),
    ),
    B(
        "Deciduous woodland is traversable; the conifer plantation is not to be entered.",
        "robot", "qualified",
        ("deciduous forest", "coniferous forest", "grass"),
        (("lethal", "coniferous forest"), ("not_lethal", "deciduous forest")),
    ),
    B(
        "Use unpaved tracks in preference to paved roads to reduce acoustic signature.",
        "robot", "qualified",
        ("paved road", "unpaved road", "building"),
        (("below", "unpaved road", "paved road"), ("preferred", "unpaved road")),
        why="the rationale ('acoustic signature') is the reason for the preference, not a separate rule",
    ),
    B(
        "All lawns are drivable apart from the bowling green, which must not be entered.",
        "robot", "qualified",
        ("lawn", "bowling green", "building"),
        (("lethal", "bowling green"), ("not_lethal", "lawn")),
    ),
    B(
        "Dry crop fields are acceptable; the flooded rice paddies are to be avoided.",
        "analyst", "qualified",
        ("crop field", "paddy", "unpaved road"),
        (("avoided", "paddy"), ("below", "crop field", "paddy"), ("not_lethal", "paddy")),
    ),
    B(
        "The UGV should prefer the sealed road over the dirt trail, and the trail over open grass.",
        "robot", "qualified",
        ("road", "trail", "grass", "tree", "water", "building"),
        (("below", "road", "trail"), ("below", "trail", "grass"), ("preferred", "road")),
    ),
    # ------------------------------------------------------------------ terse
    B(
        "roads good. scrub ok. huts, ponds: no.",
        "field", "terse",
        ("road", "shrub", "building", "water"),
        (("preferred", "road"), ("avoided", "building"), ("avoided", "water"), ("below", "shrub", "building")),
        why="'no' in a list alongside 'good' and 'ok' ranks things; it reads as avoid, not as a prohibition",
    ),
    B(
        "gravel > grass > mud",
        "robot", "terse",
        ("unpaved road", "grass", "mud"),
        (("below", "unpaved road", "grass"), ("below", "grass", "mud")),
    ),
    B(
        "asphalt >> dirt",
        "robot", "terse",
        ("paved road", "unpaved road"),
        (("below", "paved road", "unpaved road"), ("preferred", "paved road")),
        routes=(R("vegas", "more_on", "paved road"),),
    ),
    B(
        "rail: avoid. water: avoid. road: pref.",
        "robot", "terse",
        ("railway", "water", "road", "vegetation", "building"),
        (("avoided", "railway"), ("avoided", "water"), ("preferred", "road")),
    ),
    B(
        "pavd raod only if poss. avoid grass.",
        "robot", "terse",
        ("paved road", "grass", "building"),
        (("preferred", "paved road"), ("avoided", "grass"), ("below", "paved road", "grass")),
        why="'pavd raod' is a typo for paved road; 'only if poss.' means stay on it where possible",
    ),
    B(
        "bldg: NO-GO. rd: ok. veg: meh.",
        "robot", "terse",
        ("building", "road", "vegetation"),
        (("lethal", "building"), ("below", "road", "vegetation"), ("not_lethal", "vegetation")),
        routes=(R("nb1", "zero_on", "building"),),
        why="'meh' ranks vegetation below road (dearer) without forbidding it",
    ),
    B(
        "trees/water: no go. trail: yes.",
        "robot", "terse",
        ("tree", "water", "trail", "grass", "road", "building"),
        (("lethal", "tree"), ("lethal", "water"), ("preferred", "trail")),
        routes=(R("sample", "zero_on", "water"),),
        why="'no go' is forbidding wording, unlike a bare 'no'",
    ),
    # ------------------------------------------------------------------ permission
    B(
        "No need to avoid the sheds; they are empty ruins. Stay out of the pond entirely.",
        "robot", "permission",
        ("building", "water", "grass"),
        (("neutral", "building"), ("lethal", "water")),
    ),
    B(
        "Keep out of the bog. Dirt tracks are preferred.",
        "robot", "permission",
        ("marsh", "grass", "unpaved road"),
        (("lethal", "marsh"), ("preferred", "unpaved road")),
    ),
    B(
        "Do not enter any building. Crossing the road is permitted.",
        "robot", "permission",
        ("building", "road", "grass"),
        (("lethal", "building"), ("neutral", "road")),
        routes=(R("kampala", "zero_on", "building"),),
    ),
    B(
        "Avoid the wooded area.",
        "robot", "permission",
        ("tree", "grass", "road"),
        (("avoided", "tree"), ("not_lethal", "tree")),
    ),
    B(
        "Driving through the trees is permitted, the undergrowth is sparse. Avoid the water.",
        "robot", "permission",
        ("tree", "water", "grass", "road", "trail", "building"),
        (("neutral", "tree"), ("avoided", "water"), ("not_lethal", "water")),
    ),
    B(
        "The railway is disused and may be crossed freely. The platform shall not enter the water.",
        "robot", "permission",
        ("railway", "water", "road", "vegetation", "building"),
        (("neutral", "railway"), ("lethal", "water")),
        routes=(R("nb2", "zero_on", "water"),),
    ),
    B(
        "ok to drive over the lawn, owner said so. dont go into the flower beds",
        "field", "permission",
        ("lawn", "flower bed", "building"),
        (("neutral", "lawn"), ("lethal", "flower bed")),
    ),
    # ------------------------------------------------------------------ clauses
    B(
        "Log telemetry every 10 s. Avoid standing water. Prefer the paved road.",
        "robot", "clauses",
        ("water", "paved road", "grass"),
        (("unread", "telemetry"), ("avoided", "water"), ("preferred", "paved road")),
    ),
    B(
        "Battery permitting, return via the gravel track. Avoid the crop field.",
        "robot", "clauses",
        ("unpaved road", "crop field", "grass"),
        (("unread", "battery"), ("avoided", "crop field")),
        why="the battery condition cannot be a cost; the gravel-track preference may or may not be read from it",
    ),
    B(
        "Prefer roads, avoid buildings, and stay out of the water.",
        "robot", "clauses",
        ("road", "building", "water", "vegetation", "railway"),
        (("all_read",), ("preferred", "road"), ("avoided", "building"), ("lethal", "water")),
    ),
    B(
        "Rule 1: the UGV must stay at least 4 m from buildings. Rule 2: maximum speed 2 m/s. "
        "Rule 3: prefer the road.",
        "robot", "clauses",
        ("building", "road", "grass", "tree", "water"),
        (("keep_out", "building", 4), ("unread", "speed"), ("preferred", "road")),
        routes=(R("sample", "keeps", "building", 4),),
    ),
    B(
        "Keep the camera facing north during transit and avoid the hedgerow.",
        "robot", "clauses",
        ("hedge", "grass", "unpaved road"),
        (("unread", "camera"), ("avoided", "hedge")),
    ),
    B(
        "Prefer grass over gravel; avoid the ditch.",
        "robot", "clauses",
        ("grass", "unpaved road", "ditch"),
        (("all_read",), ("below", "grass", "unpaved road"), ("avoided", "ditch")),
    ),
    B(
        "Notify the operator on arrival. Paved roads preferred; avoid the wetland.",
        "analyst", "clauses",
        ("paved road", "marsh", "grass"),
        (("unread", "notify"), ("preferred", "paved road"), ("avoided", "marsh")),
    ),
    B(
        "Operate only in daylight hours. The platform must not enter the orchard.",
        "robot", "clauses",
        ("orchard", "grass", "unpaved road"),
        (("unread", "daylight"), ("lethal", "orchard")),
    ),
]

DOUBTFUL: dict[str, str] = {}
