"""Mission briefs, set 7: held-out briefs mostly in the "analyst" voice, with some robot and field.

The analyst briefs read like planning documents: long, hedged, passive sentences, lettered
clauses and headings, advisory versus mandatory wording, British and American spelling, numbers
spelled out. The robot briefs are clipped key/value or policy lines; the field briefs are
lower-case chat with abbreviations and asides.

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
        "Routing constraint (mandatory): the planned route shall at no point pass within 10 metres "
        "of any building footprint. This requirement is not subject to relaxation.",
        "analyst",
        "distance_hard",
        ("building",),
        (("keep_out", "building", 10),),
        routes=(R("massachusetts", "keeps", "building", 10),),
        why="'shall at no point pass within' is absolute distance wording: a hard 10 m zone.",
    ),
    B(
        "For the purposes of this survey a minimum stand-off of 15 m from the railway must be "
        "maintained at all times; the vehicle may otherwise use the roads as required.",
        "analyst",
        "distance_hard",
        ("building", "road", "water", "vegetation", "railway"),
        (("keep_out", "railway", 15), ("neutral", "road")),
        routes=(R("nb1", "keeps", "railway", 15), R("nb2", "keeps", "railway", 15)),
        why="'minimum stand-off ... must be maintained at all times' is hard; roads are merely allowed.",
    ),
    B(
        "Hard constraint: clearance from water >= 5 m, no exceptions. Grass and road both drivable.",
        "robot",
        "distance_hard",
        ("water", "grass", "road"),
        (("keep_out", "water", 5), ("neutral", "grass"), ("neutral", "road")),
        routes=(R("sample", "keeps", "water", 5),),
        why="'drivable' only allows grass and road: neutral, not preferred.",
    ),
    B(
        "It is a condition of the operating licence that the ground track remain no less than "
        "20 metres from any building throughout the sortie.",
        "analyst",
        "distance_hard",
        ("building", "road", "water", "vegetation", "railway"),
        (("keep_out", "building", 20),),
        routes=(R("nb2", "keeps", "building", 20),),
    ),
    B(
        "absolutely no closer than 3 m to any tree, the rotor wash brings branches down",
        "field",
        "distance_hard",
        ("tree",),
        (("keep_out", "tree", 3),),
        routes=(R("neon", "keeps", "tree", 3),),
    ),
    B(
        "Section 3, Constraints. (a) The route must maintain a clearance of at least twelve metres "
        "from all buildings. (b) Roads are preferred for transit where available. (c) Water bodies "
        "are off limits.",
        "analyst",
        "distance_hard",
        ("building", "road", "water", "vegetation", "railway"),
        (("keep_out", "building", 12), ("preferred", "road"), ("lethal", "water")),
        routes=(R("nb1", "keeps", "building", 12), R("nb1", "zero_on", "water")),
        why="The number is spelled out; 'must maintain ... at least' is absolute.",
    ),
    B(
        "Geofence: 25 m exclusion radius around every building. Stay on roads where you can.",
        "robot",
        "distance_hard",
        ("building", "road"),
        (("keep_out", "building", 25), ("preferred", "road")),
        routes=(R("massachusetts", "keeps", "building", 25),),
        why="An exclusion radius is a hard zone; 'stay on roads where you can' is a preference.",
    ),
    B(
        "A 10 m buffer around the railway is to be treated as a no-go area, and the route must not "
        "enter it under any circumstances.",
        "analyst",
        "distance_hard",
        ("building", "road", "water", "vegetation", "railway"),
        (("keep_out", "railway", 10),),
        routes=(R("nb2", "keeps", "railway", 10),),
    ),
    B(
        "Owing to the density of the settlement, passage between structures is unavoidable; "
        "nevertheless, the route must never come closer than 2 m to a building.",
        "analyst",
        "distance_hard",
        ("building",),
        (("keep_out", "building", 2),),
        routes=(R("kampala", "keeps", "building", 2),),
        why="'must never come closer than 2 m' is absolute; the first clause only explains.",
    ),
    # ------------------------------------------------------------------ distance_soft
    B(
        "Where practicable, the route should maintain a separation of approximately 10 m from "
        "buildings; this is advisory rather than mandatory.",
        "analyst",
        "distance_soft",
        ("building",),
        (("soft_zone", "building", 10),),
        routes=(R("massachusetts", "farther", "building"),),
        why="'where practicable ... advisory rather than mandatory' makes the 10 m zone soft.",
    ),
    B(
        "A margin of roughly five metres from the water's edge is desirable, and closer approach "
        "should be penalised rather than prohibited.",
        "analyst",
        "distance_soft",
        ("water", "grass", "road"),
        (("soft_zone", "water", 5), ("not_lethal", "water")),
        routes=(R("sample", "farther", "water"),),
        why="'penalised rather than prohibited': a soft zone, and nothing is forbidden.",
    ),
    B(
        "try and stay 15 m or so off the railway if you can, not the end of the world if you clip it",
        "field",
        "distance_soft",
        ("building", "road", "water", "vegetation", "railway"),
        (("soft_zone", "railway", 15),),
    ),
    B(
        "It would be preferable, though not required, for the ground track to stay roughly "
        "20 meters from the tree line. Water should be avoided. Sunset is at 19:40, so plan "
        "accordingly.",
        "analyst",
        "distance_soft",
        ("tree", "water", "grass"),
        (("soft_zone", "tree", 20), ("avoided", "water"), ("unread", "sunset")),
        routes=(R("sample", "farther", "tree"),),
        why="The sunset sentence is timing the costmap cannot act on.",
    ),
    B(
        "A clearance of about 3 m from the road edge is desirable, but it may be reduced where the "
        "corridor is narrow. Vegetation may be traversed.",
        "analyst",
        "distance_soft",
        ("building", "road", "water", "vegetation", "railway"),
        (("soft_zone", "road", 3), ("neutral", "vegetation")),
    ),
    B(
        "Ideally a gap of around 2 m from buildings should be kept, although in the denser parts "
        "of the settlement closer passage is tolerated.",
        "analyst",
        "distance_soft",
        ("building",),
        (("soft_zone", "building", 2),),
        routes=(R("kampala", "farther", "building"),),
    ),
    # ------------------------------------------------------------------ graded_away
    B(
        "The survey vehicle should keep well clear of water bodies; the greater the distance "
        "maintained from the water's edge, the better.",
        "analyst",
        "graded_away",
        ("water", "grass", "road", "tree"),
        (("graded_away", "water", None), ("neutral", "grass"), ("neutral", "road")),
        routes=(R("sample", "farther", "water"),),
    ),
    B(
        "don't go near the buildings, residents get twitchy about it",
        "field",
        "graded_away",
        ("building",),
        (("graded_away", "building", None),),
        routes=(R("massachusetts", "farther", "building"),),
    ),
    B(
        "Proximity to the railway is undesirable: the cost should rise as the route approaches the "
        "line, with no penalty applied beyond 30 metres.",
        "analyst",
        "graded_away",
        ("building", "road", "water", "vegetation", "railway"),
        (("graded_away", "railway", 30), ("all_read",)),
        routes=(R("nb1", "farther", "railway"),),
        why="The penalty grows with nearness and reaches nothing at 30 m: graded, with a number.",
    ),
    B(
        "Tree crowns should be avoided, and in general the route ought to maximise its distance from the trees.",
        "analyst",
        "graded_away",
        ("tree",),
        (("graded_away", "tree", None), ("avoided", "tree")),
        routes=(R("neon", "farther", "tree"), R("neon", "less_on", "tree")),
    ),
    B(
        "Operators are advised to give buildings a wide berth. Roads may be used freely, and "
        "vegetation is acceptable ground.",
        "analyst",
        "graded_away",
        ("building", "road", "water", "vegetation", "railway"),
        (("graded_away", "building", None), ("neutral", "road"), ("neutral", "vegetation")),
        routes=(R("nb2", "farther", "building"),),
        why="'may be used freely' and 'acceptable' allow, they do not prefer.",
    ),
    B(
        "Given the risk of bank collapse, the planned path is to remain as far from the water as "
        "reasonably possible, although crossing it is not prohibited.",
        "analyst",
        "graded_away",
        ("water", "vegetation", "road"),
        (("graded_away", "water", None), ("not_lethal", "water")),
        routes=(R("nb1", "farther", "water"),),
        why="'not prohibited' explicitly leaves water passable.",
    ),
    B(
        "Because of traffic, the farther the team stays from paved roads, the better; unpaved roads are acceptable.",
        "analyst",
        "graded_away",
        ("paved road", "unpaved road"),
        (("graded_away", "paved road", None), ("neutral", "unpaved road")),
        routes=(R("vegas", "farther", "paved road"),),
    ),
    # ------------------------------------------------------------------ graded_toward
    B(
        "To support visual navigation, the route should remain within sight of the road network "
        "wherever possible; the closer to the road, the better.",
        "analyst",
        "graded_toward",
        ("road", "building", "vegetation"),
        (("graded_toward", "road", None),),
        routes=(R("nb1", "closer", "road"),),
    ),
    B(
        "Given the difficulty of navigation in this terrain, teams are advised to remain in close "
        "proximity to the marked trail throughout.",
        "analyst",
        "graded_toward",
        ("trail", "tree", "grass"),
        (("graded_toward", "trail", None), ("neutral", "grass")),
        routes=(R("sample", "closer", "trail"),),
    ),
    B(
        "Localisation degrades away from paved road. Stay near paved road.",
        "robot",
        "graded_toward",
        ("paved road", "unpaved road"),
        (("graded_toward", "paved road", None),),
        routes=(R("vegas", "closer", "paved road"),),
    ),
    B(
        "Recovery considerations dictate that the vehicle should not stray far from buildings; "
        "proximity to buildings is therefore favoured, although entry into them is not permitted.",
        "analyst",
        "graded_toward",
        ("building",),
        (("graded_toward", "building", None), ("lethal", "building")),
        routes=(R("massachusetts", "closer", "building"), R("massachusetts", "zero_on", "building")),
        why="Near buildings is cheaper; 'entry ... is not permitted' forbids the buildings themselves.",
    ),
    B(
        "Keep the track in the vicinity of the tree line; the nearer the canopy edge, the lower the "
        "cost. Open grass is acceptable.",
        "analyst",
        "graded_toward",
        ("tree", "grass"),
        (("graded_toward", "tree", None), ("neutral", "grass")),
        routes=(R("sample", "closer", "tree"),),
    ),
    B(
        "In view of the limited communications range, it is recommended that the route be kept as "
        "close to the road as is reasonably practicable; vegetation should be avoided.",
        "analyst",
        "graded_toward",
        ("building", "road", "water", "vegetation", "railway"),
        (("graded_toward", "road", None), ("avoided", "vegetation"), ("not_lethal", "vegetation")),
        routes=(R("nb2", "closer", "road"), R("nb2", "less_on", "vegetation")),
    ),
    # ------------------------------------------------------------------ on_beside
    B(
        "The route is to follow the railway corridor but must not run on the track bed itself.",
        "analyst",
        "on_beside",
        ("building", "road", "water", "vegetation", "railway"),
        (("beside", "railway"),),
        routes=(R("nb1", "beside", "railway", 5),),
    ),
    B(
        "walk along the road, not on it - stick to the verge",
        "field",
        "on_beside",
        ("road", "grass"),
        (("beside", "road"),),
        routes=(R("sample", "beside", "road", 5),),
    ),
    B(
        "The vehicle should travel parallel to the road, off the carriageway, although crossing the "
        "road is permitted where required.",
        "analyst",
        "on_beside",
        ("road", "building"),
        (("beside", "road"), ("not_lethal", "road")),
        routes=(R("nb1", "beside", "road", 4),),
        why="Crossing is allowed, so the road is avoided, not forbidden.",
    ),
    B(
        "The inspection path should trace the edge of the watercourse, keeping to the bank and "
        "staying out of the water itself.",
        "analyst",
        "on_beside",
        ("water", "vegetation", "building"),
        (("beside", "water"), ("lethal", "water"), ("all_read",)),
        routes=(R("nb2", "beside", "water", 5), R("nb2", "zero_on", "water")),
        why="'staying out of' is forbidding wording.",
    ),
    B(
        "Survey lines are to run alongside the paved road rather than on it; the unpaved shoulder "
        "is an acceptable running surface.",
        "analyst",
        "on_beside",
        ("paved road", "unpaved road"),
        (("beside", "paved road"), ("neutral", "unpaved road")),
        routes=(R("vegas", "beside", "paved road", 5),),
    ),
    B(
        "The transect is to follow the tree line closely, without at any point entering the canopy.",
        "analyst",
        "on_beside",
        ("tree", "grass"),
        (("beside", "tree"), ("neutral", "grass")),
        routes=(R("sample", "beside", "tree", 5),),
    ),
    # ------------------------------------------------------------------ qualified
    B(
        "Paved roads are the preferred transit surface. Unpaved roads are to be avoided owing to dust.",
        "analyst",
        "qualified",
        ("paved road", "unpaved road"),
        (
            ("preferred", "paved road"),
            ("avoided", "unpaved road"),
            ("below", "paved road", "unpaved road"),
            ("all_read",),
        ),
        routes=(R("vegas", "more_on", "paved road"),),
    ),
    B(
        "All buildings are off limits, with the exception of the open-sided equipment shelter, "
        "which may be passed through.",
        "analyst",
        "qualified",
        ("building", "shelter"),
        (("lethal", "building"), ("not_lethal", "shelter"), ("neutral", "shelter")),
        why="The excepted sub-area is merely allowed: neutral.",
    ),
    B(
        "conifers are fine to push through. keep out of the deciduous stuff, too many low branches",
        "field",
        "qualified",
        ("conifer tree", "deciduous tree"),
        (("neutral", "conifer tree"), ("not_lethal", "conifer tree"), ("lethal", "deciduous tree")),
        why="'fine' allows conifers (lifting the tree prior); 'keep out of' forbids deciduous trees.",
    ),
    B(
        "Surface policy: asphalt road preferred; gravel road permitted; dirt track avoided.",
        "robot",
        "qualified",
        ("asphalt road", "gravel road", "dirt track"),
        (
            ("preferred", "asphalt road"),
            ("neutral", "gravel road"),
            ("avoided", "dirt track"),
            ("below", "asphalt road", "gravel road"),
            ("below", "gravel road", "dirt track"),
        ),
    ),
    B(
        "Water is to be treated as impassable, save for the shallow ford, which is suitable for "
        "crossing. The crossing should be completed before the tide turns.",
        "analyst",
        "qualified",
        ("water", "ford", "grass"),
        (("lethal", "water"), ("not_lethal", "ford"), ("neutral", "ford"), ("unread", "tide")),
        why="'impassable' forbids water; the ford is the excepted, allowed sub-area; the tide is timing.",
    ),
    B(
        "Mowed grass may be used as needed; tall grass should be avoided where feasible, and the "
        "baseball field must not be entered.",
        "analyst",
        "qualified",
        ("mowed grass", "tall grass", "baseball field"),
        (("neutral", "mowed grass"), ("avoided", "tall grass"), ("lethal", "baseball field")),
    ),
    B(
        "Paved roads are off limits during the event; unpaved roads may be used.",
        "analyst",
        "qualified",
        ("paved road", "unpaved road"),
        (("lethal", "paved road"), ("neutral", "unpaved road")),
    ),
    # ------------------------------------------------------------------ terse
    B(
        "road > grass > tree",
        "robot",
        "terse",
        ("road", "grass", "tree"),
        (("below", "road", "grass"), ("below", "grass", "tree"), ("all_read",)),
        routes=(R("sample", "more_on", "road"),),
    ),
    B(
        "water: no. bldgs: no. veg ok",
        "field",
        "terse",
        ("building", "road", "water", "vegetation", "railway"),
        (("lethal", "water"), ("lethal", "building"), ("neutral", "vegetation")),
        routes=(R("nb1", "zero_on", "water"), R("nb1", "zero_on", "building")),
        why="'X: no' refuses the class outright; 'bldgs' and 'veg' are abbreviations of the layers.",
    ),
    B(
        "unpavd road: avoid",
        "robot",
        "terse",
        ("paved road", "unpaved road"),
        (("avoided", "unpaved road"), ("not_lethal", "unpaved road"), ("neutral", "paved road")),
        why="The typo must still land on the unpaved class, not the paved one.",
    ),
    B(
        "railway fine. vegetation fine. buildings - avoid",
        "field",
        "terse",
        ("building", "road", "water", "vegetation", "railway"),
        (("neutral", "railway"), ("neutral", "vegetation"), ("avoided", "building")),
        routes=(R("nb2", "less_on", "building"),),
        why="'fine' lifts the railway prior to neutral.",
    ),
    B(
        "Preference order: paved road > unpaved road > open ground.",
        "analyst",
        "terse",
        ("paved road", "unpaved road"),
        (
            ("below", "paved road", "unpaved road"),
            ("preferred", "paved road"),
            ("preferred", "unpaved road"),
        ),
        routes=(R("vegas", "more_on", "paved road"),),
        why="Open ground is neutral, so both road classes ranked above it are preferred.",
    ),
    # ------------------------------------------------------------------ permission
    B(
        "The vehicle is amphibious and is therefore cleared to traverse water where necessary.",
        "analyst",
        "permission",
        ("water", "grass", "road"),
        (("neutral", "water"), ("not_lethal", "water")),
        why="Permission lifts the water prior to neutral.",
    ),
    B(
        "Railway land is strictly off limits. Crossing vegetation is permitted.",
        "analyst",
        "permission",
        ("building", "road", "water", "vegetation", "railway"),
        (("lethal", "railway"), ("neutral", "vegetation"), ("all_read",)),
    ),
    B(
        "Cutting through the stand of trees is permissible, as the trunks are widely spaced.",
        "analyst",
        "permission",
        ("tree", "grass"),
        (("neutral", "tree"), ("not_lethal", "tree")),
    ),
    B(
        "Permissions: building = no-go; water = allowed; railway = allowed.",
        "robot",
        "permission",
        ("building", "road", "water", "vegetation", "railway"),
        (("lethal", "building"), ("neutral", "water"), ("neutral", "railway")),
        routes=(R("nb2", "zero_on", "building"),),
    ),
    B(
        "Under the landowner's agreement the party may cross the baseball field, but must keep out "
        "of all buildings and stay out of the water.",
        "analyst",
        "permission",
        ("baseball field", "building", "water", "grass"),
        (("neutral", "baseball field"), ("lethal", "building"), ("lethal", "water")),
        routes=(R("sample", "zero_on", "building"), R("sample", "zero_on", "water")),
    ),
    B(
        "Do not enter the tree canopy under any circumstances; it is acceptable, however, to drive "
        "across grass and along the trail.",
        "analyst",
        "permission",
        ("tree", "grass", "trail", "road"),
        (("lethal", "tree"), ("neutral", "grass"), ("neutral", "trail")),
        routes=(R("sample", "zero_on", "tree"),),
        why="'acceptable' allows grass and trail; it does not prefer them.",
    ),
    B(
        "Driving on roads is permitted but should be minimized where alternatives exist.",
        "analyst",
        "permission",
        ("road", "grass", "building"),
        (("avoided", "road"), ("not_lethal", "road"), ("neutral", "grass")),
        routes=(R("sample", "less_on", "road"),),
        why="Permitted (not forbidden) yet to be minimised: avoided, not lethal.",
    ),
    # ------------------------------------------------------------------ clauses
    B(
        "Mission brief, Site B. The route should avoid buildings and favour the road. Radio "
        "check-ins are required every fifteen minutes on channel 4.",
        "analyst",
        "clauses",
        ("building", "road"),
        (("avoided", "building"), ("preferred", "road"), ("unread", "radio")),
        routes=(R("nb1", "less_on", "building"), R("nb1", "more_on", "road")),
    ),
    B(
        "stay out of the water and keep well away from the railway. bring spare batteries, it'll be cold",
        "field",
        "clauses",
        ("building", "road", "water", "vegetation", "railway"),
        (("lethal", "water"), ("graded_away", "railway", None), ("unread", "batteries")),
        routes=(R("nb2", "zero_on", "water"), R("nb2", "farther", "railway")),
    ),
    B(
        "Avoid vegetation. Prefer roads. Launch window opens 0600 local.",
        "robot",
        "clauses",
        ("building", "road", "water", "vegetation", "railway"),
        (("avoided", "vegetation"), ("preferred", "road"), ("unread", "launch")),
        routes=(R("nb1", "less_on", "vegetation"),),
    ),
    B(
        "Buildings must be avoided, roads are preferred, and water is off limits.",
        "analyst",
        "clauses",
        ("building", "road", "water", "vegetation", "railway"),
        (("avoided", "building"), ("preferred", "road"), ("lethal", "water"), ("all_read",)),
        routes=(R("nb2", "zero_on", "water"), R("nb2", "more_on", "road")),
    ),
    B(
        "Please note that the client has requested the final report in PDF format. For routing "
        "purposes, the vehicle must stay out of the water and keep at least 5 m from buildings at "
        "all times.",
        "analyst",
        "clauses",
        ("building", "road", "water", "vegetation", "railway"),
        (("unread", "report"), ("lethal", "water"), ("keep_out", "building", 5)),
        routes=(R("nb1", "keeps", "building", 5), R("nb1", "zero_on", "water")),
    ),
    B(
        "OBJECTIVE: Inspect the culvert on the eastern boundary. CONSTRAINTS: Stay out of the "
        "railway corridor. Prefer roads. Avoid vegetation where practical. LOGISTICS: The support "
        "vehicle will be parked at the north gate.",
        "analyst",
        "clauses",
        ("building", "road", "water", "vegetation", "railway"),
        (
            ("lethal", "railway"),
            ("preferred", "road"),
            ("avoided", "vegetation"),
            ("unread", "parked"),
        ),
        routes=(R("nb1", "more_on", "road"), R("nb1", "less_on", "vegetation")),
    ),
]

DOUBTFUL: dict[str, str] = {}
