"""Mission briefs, set 8: held-out briefs mostly in the "robot" voice, with some analyst and field.

The robot voice is a robotics engineer or UGV/UAV operator configuring a planner: key: value lines,
YAML-ish lists, config comments, comparison symbols (>, >=, <, =), ALL CAPS and RFC-style
MUST/SHOULD/MAY wording, mission-order headings, units in m / metres / ft and clipped abbreviations.
The analyst and field briefs are plain prose and spoken shorthand, some with typos.

Written WITHOUT reading the interpreter, its tests or its corpora, and scored ONCE at first
contact; that first-contact figure is the one that counts. Never edit a brief to make the
interpreter pass: a case whose expectation contradicts the cost-scale contract is retired in
``DOUBTFUL`` with the reason instead.
"""

from __future__ import annotations

from .mission_briefs import Brief, Route

B = Brief
R = Route

#: Layer sets matching the scenes' ground-truth class names exactly.
NB = ("building", "road", "water", "vegetation", "railway")
SAMPLE = ("grass", "road", "trail", "tree", "water", "building", "baseball field")
VEGAS = ("paved road", "unpaved road")
BLDG = ("building",)
TREE = ("tree",)

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------ distance_hard
    B(
        "CONSTRAINTS (hard):\n  building.standoff >= 15 m\n  railway.standoff >= 20 m\n  road: preferred surface",
        "robot",
        "distance_hard",
        NB,
        (("keep_out", "building", 15), ("keep_out", "railway", 20), ("preferred", "road")),
        routes=(R("nb1", "keeps", "building", 15), R("nb2", "keeps", "railway", 20)),
        why="standoffs under a (hard) heading with >= are absolute distance rules",
    ),
    B(
        "UGV MUST NOT come within 10 m of any building footprint. No exceptions, no waivers.",
        "robot",
        "distance_hard",
        BLDG,
        (("keep_out", "building", 10),),
        routes=(R("massachusetts", "keeps", "building", 10),),
    ),
    B(
        "min_clearance_water: 5m   # absolute, planner shall never violate\ncomms: check-in every 10 min on TAC-2",
        "robot",
        "distance_hard",
        NB,
        (("keep_out", "water", 5), ("unread", "comms")),
        routes=(R("nb2", "keeps", "water", 5),),
        why="the comms schedule is not something a costmap can express",
    ),
    B(
        "The route has to stay at least 30 metres from the railway line at every point. The rail "
        "operator treats this as a safety requirement, not a preference.",
        "analyst",
        "distance_hard",
        NB,
        (("keep_out", "railway", 30),),
        routes=(R("nb1", "keeps", "railway", 30),),
    ),
    B(
        "Whatever you do, never get closer than 25 ft to any building.",
        "field",
        "distance_hard",
        SAMPLE,
        (("keep_out", "building", 7.62),),
        routes=(R("sample", "keeps", "building", 7.62),),
        why="25 ft = 7.62 m; 'never closer than' is absolute",
    ),
    B(
        "dist(veh, tree) > 3 m   ALWAYS\ndist(veh, water) > 12 m  ALWAYS",
        "robot",
        "distance_hard",
        SAMPLE,
        (("keep_out", "tree", 3), ("keep_out", "water", 12)),
        routes=(R("sample", "keeps", "water", 12), R("sample", "keeps", "tree", 3)),
    ),
    B(
        "GEOFENCE: 25 m buffer around all water. Buffer is HARD -- treat as impassable.",
        "robot",
        "distance_hard",
        NB,
        (("keep_out", "water", 25),),
        routes=(R("nb1", "keeps", "water", 25),),
    ),
    # ------------------------------------------------------------------ distance_soft
    B(
        "building: soft standoff 8 m (cost penalty only, NOT a constraint)",
        "robot",
        "distance_soft",
        BLDG,
        (("soft_zone", "building", 8),),
        routes=(R("massachusetts", "farther", "building"),),
    ),
    B(
        "Vehicle SHOULD maintain ~20 m separation from the railway where practical; MAY close to "
        "less if no alternative exists.",
        "robot",
        "distance_soft",
        NB,
        (("soft_zone", "railway", 20),),
        routes=(R("nb2", "farther", "railway"),),
        why="SHOULD ... MAY close to less: a soft zone, the 20 m kept",
    ),
    B(
        "Ideally keep about 15 metres back from the water's edge, though coming closer is "
        "acceptable where the terrain forces it.",
        "analyst",
        "distance_soft",
        SAMPLE,
        (("soft_zone", "water", 15),),
        routes=(R("sample", "farther", "water"),),
    ),
    B(
        "try to stay 10 m or so off the road, not the end of the world if you can't",
        "field",
        "distance_soft",
        NB,
        (("soft_zone", "road", 10),),
        routes=(R("nb1", "farther", "road"),),
    ),
    # ------------------------------------------------------------------ graded_away
    B(
        "water: repel. Cost climbs as range to water shrinks. No hard limit.",
        "robot",
        "graded_away",
        SAMPLE,
        (("graded_away", "water", None),),
        routes=(R("sample", "farther", "water"),),
    ),
    B(
        "buildings -> the farther the better; influence radius 40 m, flat beyond.",
        "robot",
        "graded_away",
        BLDG,
        (("graded_away", "building", 40),),
        routes=(R("massachusetts", "farther", "building"),),
    ),
    B(
        "Don't go near the railway.",
        "analyst",
        "graded_away",
        NB,
        (("graded_away", "railway", None), ("all_read",)),
        routes=(R("nb1", "farther", "railway"),),
    ),
    B(
        "keep well clear of the water, the further out from it the better",
        "field",
        "graded_away",
        NB,
        (("graded_away", "water", None),),
        routes=(R("nb2", "farther", "water"),),
    ),
    B(
        "PENALTY(building): max at the wall, linear decay with range, zero at 30 m and beyond",
        "robot",
        "graded_away",
        BLDG,
        (("graded_away", "building", 30),),
        routes=(R("kampala", "farther", "building"),),
    ),
    B(
        "- road: stand off (traffic); penalty falls with distance\n- grass: ok\n- log GPS fix at 1 Hz",
        "robot",
        "graded_away",
        SAMPLE,
        (("graded_away", "road", None), ("neutral", "grass"), ("unread", "GPS")),
        routes=(R("sample", "farther", "road"),),
        why="grass merely allowed: neutral; GPS logging is not a costmap clause",
    ),
    # ------------------------------------------------------------------ graded_toward
    B(
        "The convoy should stay within sight of the road throughout; the nearer to it, the better.",
        "analyst",
        "graded_toward",
        NB,
        (("graded_toward", "road", None),),
        routes=(R("nb1", "closer", "road"),),
    ),
    B(
        "treeline: ATTRACT, radius 25 m (cover from aerial observation)",
        "robot",
        "graded_toward",
        TREE,
        (("graded_toward", "tree", 25),),
        routes=(R("neon", "closer", "tree"),),
    ),
    B(
        "stick close to the trail if you can, closer the better",
        "field",
        "graded_toward",
        SAMPLE,
        (("graded_toward", "trail", None),),
        routes=(R("sample", "closer", "trail"),),
    ),
    B(
        "PREF proximity(building): minimise range to buildings, rooftop relays need line of sight",
        "robot",
        "graded_toward",
        BLDG,
        (("graded_toward", "building", None),),
        routes=(R("massachusetts", "closer", "building"),),
    ),
    B(
        "vegetation: shadow it. Stay near for concealment.",
        "robot",
        "graded_toward",
        NB,
        (("graded_toward", "vegetation", None),),
        routes=(R("nb2", "closer", "vegetation"),),
    ),
    B(
        "attractor:\n  layer: paved road\n  mode: proximity\n  strength: high",
        "robot",
        "graded_toward",
        VEGAS,
        (("graded_toward", "paved road", None),),
        routes=(R("vegas", "closer", "paved road"),),
    ),
    # ------------------------------------------------------------------ on_beside
    B(
        "follow road; do NOT drive on it. offset 1-4 m, shoulder only.",
        "robot",
        "on_beside",
        NB,
        (("beside", "road"),),
        routes=(R("nb1", "beside", "road", 5),),
    ),
    B(
        "walk alongside the railway but stay off the tracks themselves",
        "field",
        "on_beside",
        NB,
        (("beside", "railway"),),
        routes=(R("nb2", "beside", "railway", 10),),
    ),
    B(
        "track the paved road corridor from the shoulder, 1-4 m off\npaved road surface itself: NO",
        "robot",
        "on_beside",
        VEGAS,
        (("beside", "paved road"),),
        routes=(R("vegas", "beside", "paved road", 5),),
    ),
    B(
        "water: edge-follow, never in. Preferred band 1-5 m from shoreline.",
        "robot",
        "on_beside",
        SAMPLE,
        (("beside", "water"),),
        routes=(R("sample", "beside", "water", 6),),
    ),
    B(
        "tree crowns: skirt, don't penetrate. Hold 1-3 m off the canopy edge.",
        "robot",
        "on_beside",
        TREE,
        (("beside", "tree"),),
        routes=(R("neon", "beside", "tree", 3),),
    ),
    B(
        "perimeter run: building outline, 1-3 m offset. Never enter footprints.",
        "robot",
        "on_beside",
        BLDG,
        (("beside", "building"), ("lethal", "building")),
        routes=(R("massachusetts", "beside", "building", 3), R("massachusetts", "zero_on", "building")),
        why="'never enter' forbids the footprints; the band beside them is preferred",
    ),
    # ------------------------------------------------------------------ qualified
    B(
        "paved road: preferred\nunpaved road: avoid",
        "robot",
        "qualified",
        VEGAS,
        (
            ("preferred", "paved road"),
            ("avoided", "unpaved road"),
            ("below", "paved road", "unpaved road"),
            ("all_read",),
        ),
        routes=(R("vegas", "more_on", "paved road"),),
    ),
    B(
        "unpaved road: OK\npaved road: KEEP OFF",
        "robot",
        "qualified",
        VEGAS,
        (("neutral", "unpaved road"), ("lethal", "paved road")),
        routes=(R("vegas", "less_on", "paved road"),),
        why="OK is a mere allowance (neutral); KEEP OFF forbids",
    ),
    B(
        "tree.deciduous: ok\ntree.conifer: avoid",
        "robot",
        "qualified",
        ("deciduous tree", "conifer tree", "grass"),
        (("neutral", "deciduous tree"), ("avoided", "conifer tree"), ("below", "deciduous tree", "conifer tree")),
    ),
    B(
        "Avoid the grass, except on the baseball field, which is fine to cross.",
        "analyst",
        "qualified",
        SAMPLE,
        (("avoided", "grass"), ("neutral", "baseball field"), ("below", "baseball field", "grass")),
        routes=(R("sample", "less_on", "grass"),),
        why="the baseball field is excepted from the grass rule and merely allowed",
    ),
    B(
        "building: NO-GO\n  except: hangar (access granted)",
        "robot",
        "qualified",
        ("building", "hangar", "road"),
        (("lethal", "building"), ("not_lethal", "hangar"), ("neutral", "hangar")),
    ),
    B(
        "surface.primary: paved road\nsurface.fallback: unpaved road (only where no paved link exists)",
        "robot",
        "qualified",
        VEGAS,
        (("preferred", "paved road"), ("below", "paved road", "unpaved road"), ("not_lethal", "unpaved road")),
        routes=(R("vegas", "more_on", "paved road"),),
        why="a fallback is allowed, so not lethal, but dearer than the primary surface",
    ),
    # ------------------------------------------------------------------ terse
    B(
        "pref: road > trail > grass",
        "robot",
        "terse",
        SAMPLE,
        (("below", "road", "trail"), ("below", "trail", "grass"), ("all_read",)),
        routes=(R("sample", "more_on", "road"),),
    ),
    B(
        "water: no\nrailway: no\nroad: yes",
        "robot",
        "terse",
        NB,
        (("lethal", "water"), ("lethal", "railway"), ("not_lethal", "road")),
        routes=(R("nb1", "zero_on", "water"),),
        why="'X: no' in a go/no-go list forbids X",
    ),
    B(
        "pavd road ok / unpavd raod avoid",
        "robot",
        "terse",
        VEGAS,
        (("neutral", "paved road"), ("avoided", "unpaved road")),
        why="typos in multi-word class names",
    ),
    B(
        "basebal feild - stay out",
        "field",
        "terse",
        SAMPLE,
        (("lethal", "baseball field"),),
        routes=(R("sample", "zero_on", "baseball field"),),
    ),
    B(
        "cost: grass < road < building",
        "robot",
        "terse",
        SAMPLE,
        (("below", "grass", "road"), ("below", "road", "building")),
        why="an explicit cost ordering, cheapest first",
    ),
    B(
        "rail=lethal  veg=ok  bldg=avoid",
        "robot",
        "terse",
        NB,
        (("lethal", "railway"), ("neutral", "vegetation"), ("avoided", "building")),
        routes=(R("nb2", "less_on", "building"),),
    ),
    # ------------------------------------------------------------------ permission
    B(
        "Water crossing PERMITTED (amphibious platform).",
        "robot",
        "permission",
        SAMPLE,
        (("neutral", "water"), ("not_lethal", "water")),
        why="permission lifts the water prior to neutral",
    ),
    B(
        "you can walk through the trees, they're no problem. stay out of the water though.",
        "field",
        "permission",
        SAMPLE,
        (("neutral", "tree"), ("lethal", "water")),
        routes=(R("sample", "zero_on", "water"),),
    ),
    B(
        "The buildings here are derelict and the team is cleared to pass through them; the railway, "
        "however, is off limits.",
        "analyst",
        "permission",
        NB,
        (("neutral", "building"), ("lethal", "railway")),
        routes=(R("nb1", "zero_on", "railway"),),
    ),
    B(
        "railway: MAY cross at any point\nwater: MUST NOT enter",
        "robot",
        "permission",
        NB,
        (("neutral", "railway"), ("not_lethal", "railway"), ("lethal", "water")),
        routes=(R("nb2", "zero_on", "water"),),
    ),
    B(
        "no_go: [building, water]\nallowed: [vegetation, railway]",
        "robot",
        "permission",
        NB,
        (("lethal", "building"), ("lethal", "water"), ("neutral", "vegetation"), ("neutral", "railway"), ("all_read",)),
        routes=(R("nb1", "zero_on", "building"),),
    ),
    B(
        "grass: fine\ntrees: do not go into",
        "robot",
        "permission",
        SAMPLE,
        (("neutral", "grass"), ("lethal", "tree")),
        routes=(R("sample", "zero_on", "tree"),),
    ),
    # ------------------------------------------------------------------ clauses
    B(
        "telemetry: 10 Hz downlink\nbuilding: keep out\nroad: prefer",
        "robot",
        "clauses",
        NB,
        (("unread", "telemetry"), ("lethal", "building"), ("preferred", "road")),
        routes=(R("nb1", "zero_on", "building"), R("nb1", "more_on", "road")),
    ),
    B(
        "RTB if battery < 20 %.\navoid water\nprefer trail",
        "robot",
        "clauses",
        SAMPLE,
        (("unread", "battery"), ("avoided", "water"), ("preferred", "trail")),
        routes=(R("sample", "more_on", "trail"), R("sample", "less_on", "water")),
    ),
    B(
        "radio check every 15 minutes on channel 3. keep to the road where you can.",
        "field",
        "clauses",
        NB,
        (("unread", "radio"), ("preferred", "road")),
        routes=(R("nb2", "more_on", "road"),),
    ),
    B(
        "payload: 4 kg LiDAR, gimbal locked\nwater: stay out\ngrass: favour",
        "robot",
        "clauses",
        SAMPLE,
        (("unread", "payload"), ("lethal", "water"), ("preferred", "grass")),
        routes=(R("sample", "zero_on", "water"),),
    ),
    B(
        "avoid: building\nprefer: road\nno-go: water",
        "robot",
        "clauses",
        NB,
        (("avoided", "building"), ("preferred", "road"), ("lethal", "water"), ("all_read",)),
        routes=(R("nb1", "less_on", "building"), R("nb1", "more_on", "road")),
    ),
    B(
        "SITUATION: night transit, UGV-2.\nEXECUTION:\n- MUST hold >= 10 m from building\n- prefer road\n"
        "- vegetation permitted\n- water: no-go\nSUSTAINMENT: battery swap at RP ALPHA",
        "robot",
        "clauses",
        NB,
        (
            ("unread", "battery"),
            ("keep_out", "building", 10),
            ("preferred", "road"),
            ("neutral", "vegetation"),
            ("lethal", "water"),
        ),
        routes=(R("nb2", "keeps", "building", 10), R("nb2", "zero_on", "water")),
        why="a mission order mixing a hard standoff, a preference, a permission, a no-go and a logistics line",
    ),
]

DOUBTFUL: dict[str, str] = {}
