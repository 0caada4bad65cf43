"""Mission briefs, set 28: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench, the docs or the briefs of earlier sets: only the contract
(``tests/mission_briefs.py`` and its format test ``tests/test_mission_briefs.py``), the scene index
(``../shared/scenes/INDEX.md`` and the scenes' ``classes.json``), the first 45 lines of set 27
(for the layout, and its docstring's list of voices) and the first 25 lines of sets 24, 25 and 26
(their docstrings' lists of voices, which this set avoids) were read. It is scored once, at first
contact, with ``bench/mission_briefs_report.py --set 28``; that figure is the one that counts, and
the set is not edited afterwards to make the interpreter pass.

The voices are a city parks department's special-event permit ("PERMIT CONDITION 4", "the
Permittee shall", "save for"), a five-paragraph order fragment ("3. EXECUTION", "Coord instrs",
"min standoff", "RAILS: NO-GO", "SERVICE SUPPORT: refuel at the RV at 1400"), a telecom field
engineer's work orders ("WO-88213", the carriageway and the verge, the cabinet's radio tether, the
overhead power lines), a child of about seven ("mum says", "twenty giant steps", "the paddling
pool is ok tho"), a landscape architect (root protection areas, young conifers
and old deciduous trees), Gherkin acceptance scenarios ("Given ... Then ... And ...
But"), a speaker from the American South ("y'all", "thirty yards off the railroad", "blacktop's
better'n gravel", "them sheds out yonder"), an XML rules fragment (``<clearance ... strict=>``,
``<avoid class="crane"/>``), a museum grounds curator (the sculptures on their plinths, the
fountain's spray, bronze versus marble, the stable block, "the Hepworth"), a wedding planner (the
marquee during the vows, the photographer's golden hour, the dance floor and the cake table), a
Singapore-English speaker ("can?", "not compulsory one", "never mind lah", "Water cannot", "don't
anyhow go"), a horse rider leading a mare and hacking along hedgerows (the bridleway by the
railway), a spoken transcript with fillers ("um", "uh", "like", "I dunno"), a CSV rule table
(``class,min_clearance_m,enforcement``), a homeowners' association bylaw ("Section 7(b)", "give
houses a miss"), a crime-scene manager's log, a flood-response coordinator (the rising river, the
relay truck, shallow flood water versus the deep channel), a nature reserve's nesting-season
notice (swans that tolerate people at 50 m), Markdown tables (a hazard/rule table and a tick-box
ok/avoid/never grid), a guide-dog trainer (shorelining the grass edge), a mushroom forager (mown
grass versus long grass hiding ditches) and terse typed lines with typos ("the trial over the
gras", "keep of the raod if u can", "paved raod", "unpavd road ok-ish", "bldg: 10m hard").

Units come in metres and meters, feet (10 ft = 3.048 m, 20 feet = 6.096 m), yards (thirty yards
= 27.432 m), numbers as words ("two metres", "fifteen metres"), ranges ("three or four metres":
the lower figure is probed, so either reading passes) and a measure that gives no number ("twenty
giant steps": no metre figure is expected). Hard distance rules are worded "shall remain no less
than ... may not be waived", "No exceptions", "NOT to come within ... under any circumstances",
"not even one step closer", "sacrosanct ... treat the line as a fence", "no point of the route
is closer than", "every inch of it", ``strict="true"``, ``mandatory`` and "10m hard"; soft ones
"where it can", "ideally ... so be it", "not compulsory one", "won't get anyone in trouble", "not,
like, a hard rule", ``advisory``, "where reasonably practicable ... not an infraction" and "5m
soft". Graded nearness comes as "as far ... as it can manage, out to about 40 metres", "nearer
the water means worse", "get more agitated the closer anything comes", "the farther away from
houses the better", "favour lines well clear of it", "further is better, up to ... fifteen
metres" and "the further the better" in a table; toward as "the tighter ... to the trees, the
more shelter", "keep close to the road", "the nearer the better", "stay by the trees", "move tight
to the treeline", "the nearer the water, the better the frame" and "stay within about 30 m ...
nearer is always better". On versus beside comes as "follows the edge of the grass ... keeps its
wheels off the grass", "walk the riverbank, not the river", "follows the road verge ... Do not
drive on the carriageway", "alongside the tracks ..., never on them", "beside the trees rather
than under them", "next to the road but not ON the road" and "along the near bank and do not
cross the river". Permissions come as "treat it as open ground", "cleared to drive straight
through", "No restriction on crossing", "you ARE allowed", "authorised to operate", "may drive
beneath ... without penalty" and "no call to steer around 'em", next to forbidding in "out of
bounds", "keep out of", "NOT in the pond", "never enter", "stay out of", "dont go in" and
"cannot". Where a brief is ambiguous (is "stay away from" a ban? how dear is "meh"?) less is
checked.
"""

from __future__ import annotations

from tests.mission_briefs import Brief, Route

#: Briefs whose expectation was found to contradict the contract after scoring (none yet).
DOUBTFUL: dict[str, str] = {}

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------------------------------
    # distance_hard
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "PERMIT CONDITION 4. The Permittee's survey rover shall remain no less than 15 metres "
            "from the water's edge of Mill Pond for the duration of the permit. This condition may "
            "not be waived by park staff on the day."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=("water", "grass", "tree", "trail"),
        expect=(("keep_out", "water", 15),),
        routes=(Route("sample", "keeps", "water", 15),),
    ),
    Brief(
        prompt=(
            "3. EXECUTION.\nc. Coord instrs.\n(1) All vehicles maintain min standoff 25 m from "
            "structures. No exceptions.\n(2) Use the road where it serves."
        ),
        voice="field",
        construct="distance_hard",
        layers=("building", "road", "vegetation", "water"),
        expect=(("keep_out", "building", 25), ("preferred", "road")),
        routes=(Route("nb1", "keeps", "building", 25),),
        why="'structures' are the buildings; 'No exceptions' makes the standoff absolute.",
    ),
    Brief(
        prompt=(
            "WO-88213 / cable locate. Live carriageway, no traffic management booked: the rover is "
            "NOT to come within 10 ft of the road under any circumstances."
        ),
        voice="field",
        construct="distance_hard",
        layers=("road", "grass", "building"),
        expect=(("keep_out", "road", 3.048),),
        routes=(Route("sample", "keeps", "road", 3.048),),
        why="10 ft = 3.048 m; 'under any circumstances' is absolute.",
    ),
    Brief(
        prompt=(
            "mum says my robot is not allowed closer to the pond than twenty giant steps. not even "
            "one step closer. she means it"
        ),
        voice="field",
        construct="distance_hard",
        layers=("water", "grass", "tree"),
        expect=(("keep_out", "water", None),),
        why="Giant steps give no metre figure; 'not allowed' and 'not even one step closer' are absolute.",
    ),
    Brief(
        prompt=(
            "Root protection areas are sacrosanct on this scheme: no plant, no rover wheel, nothing "
            "within 4 m of any tree. Treat the line as a fence."
        ),
        voice="analyst",
        construct="distance_hard",
        layers=("tree", "grass", "building"),
        expect=(("keep_out", "tree", 4),),
        routes=(Route("neon", "keeps", "tree", 4),),
    ),
    Brief(
        prompt=(
            "Scenario: clearance around buildings\n"
            "  Given a planned route across the estate\n"
            "  Then no point of the route is closer than 8 metres to any building\n"
            "  And the route is allowed to get longer to achieve that"
        ),
        voice="robot",
        construct="distance_hard",
        layers=("building", "road", "grass"),
        expect=(("keep_out", "building", 8),),
        routes=(Route("massachusetts", "keeps", "building", 8),),
    ),
    Brief(
        prompt=(
            "Y'all keep that rig thirty yards off the railroad the whole way, every inch of it. "
            "Freight comes through here doin' sixty and it don't stop for nobody."
        ),
        voice="field",
        construct="distance_hard",
        layers=("railway", "road", "vegetation", "building"),
        expect=(("keep_out", "railway", 27.432),),
        routes=(Route("nb2", "keeps", "railway", 27.432),),
        why="Thirty yards = 27.432 m; 'the whole way, every inch of it' makes it absolute.",
    ),
    Brief(
        prompt=(
            "<costmap>\n"
            '  <clearance class="water" min_m="12" strict="true"/>\n'
            '  <clearance class="building" min_m="5" strict="false"/>\n'
            "</costmap>"
        ),
        voice="robot",
        construct="distance_hard",
        layers=("water", "building", "road", "grass"),
        expect=(("keep_out", "water", 12), ("soft_zone", "building", 5)),
        routes=(Route("sample", "keeps", "water", 12),),
        why="strict='true' is a hard clearance, strict='false' a soft one, the numbers kept.",
    ),
    # ------------------------------------------------------------------------------------------
    # distance_soft
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Where it can, I'd like the rover to hang back about six metres from the sculptures. "
            "They're bolted to their plinths, so a closer pass won't be a catastrophe, just poor "
            "manners."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=("sculpture", "grass", "trail"),
        expect=(("soft_zone", "sculpture", 6),),
    ),
    Brief(
        prompt=(
            "During the vows the robot ideally stays 10 m or more from the marquee. If the only way "
            "round is closer, so be it."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=("marquee", "grass", "tree", "trail"),
        expect=(("soft_zone", "marquee", 10),),
    ),
    Brief(
        prompt="Try to keep 5 metre from the building, can? Not compulsory one. If really cannot, never mind lah.",
        voice="field",
        construct="distance_soft",
        layers=("building", "road", "grass"),
        expect=(("soft_zone", "building", 5),),
    ),
    Brief(
        prompt=(
            "We'll be leading the mare behind the rover and she's only jumpy when traffic is right "
            "on top of her. Give the road roughly 20 feet where there's room; cutting closer on a "
            "tight bit won't get anyone in trouble."
        ),
        voice="field",
        construct="distance_soft",
        layers=("road", "grass", "trail", "tree"),
        expect=(("soft_zone", "road", 6.096),),
        why="20 feet = 6.096 m; 'where there's room' and 'won't get anyone in trouble' make it soft.",
    ),
    Brief(
        prompt=(
            "So, um, the water. We'd like, you know, three or four metres between the robot and the "
            "water? It's not, like, a hard rule or anything. It's just, uh, nicer."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=("water", "grass", "trail"),
        expect=(("soft_zone", "water", 3),),
        why="A range: the lower figure is probed (1 m and 2 m), so a 3 m or a 4 m zone passes.",
    ),
    Brief(
        prompt="class,min_clearance_m,enforcement\nbuilding,7,advisory\nwater,15,mandatory",
        voice="robot",
        construct="distance_soft",
        layers=("building", "water", "road", "grass"),
        expect=(("soft_zone", "building", 7), ("keep_out", "water", 15)),
        routes=(Route("sample", "keeps", "water", 15),),
        why="'advisory' is a soft clearance, 'mandatory' a hard one.",
    ),
    Brief(
        prompt=(
            "Section 7(b). Autonomous mowers and delivery devices should, where reasonably "
            "practicable, maintain a clearance of two metres from any dwelling. Non-compliance with "
            "this subsection is not an infraction."
        ),
        voice="analyst",
        construct="distance_soft",
        layers=("building", "road", "grass"),
        expect=(("soft_zone", "building", 2),),
        why="Dwellings are buildings; 'where reasonably practicable' and 'not an infraction' make it soft.",
    ),
    # ------------------------------------------------------------------------------------------
    # graded_away
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Scene log, 02:10. Keep the rover as far from the house as it can manage, out to about "
            "40 metres; beyond that it makes no odds to me. And don't go near the forensic tent."
        ),
        voice="field",
        construct="graded_away",
        layers=("building", "tent", "grass", "road"),
        expect=(("graded_away", "building", 40), ("graded_away", "tent", None)),
        why="'As far as it can manage, out to 40 m; beyond that no odds': a fall-off reaching neutral at 40 m.",
    ),
    Brief(
        prompt=(
            "River's risng by the hour. Nearer the water means worse, no two ways about it. I'd "
            "sooner the rover took the long way round on the high ground."
        ),
        voice="field",
        construct="graded_away",
        layers=("water", "road", "building", "vegetation"),
        expect=(("graded_away", "water", None),),
        routes=(Route("nb1", "farther", "water"),),
    ),
    Brief(
        prompt=(
            "Nesting season notice: the swans on the lake tolerate people at 50 m but get more "
            "agitated the closer anything comes. Plan routes with that in mind."
        ),
        voice="analyst",
        construct="graded_away",
        layers=("water", "grass", "trail", "tree"),
        expect=(("graded_away", "water", 50),),
        why="The swans are on the lake: the closer to the water the worse, with no harm beyond 50 m.",
    ),
    Brief(
        prompt=(
            "the big dog lives in one of the houses and he barks SO loud so the farther away from houses the better ok"
        ),
        voice="field",
        construct="graded_away",
        layers=("building", "grass", "road"),
        expect=(("graded_away", "building", None),),
        routes=(Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        prompt=(
            "The fountain's spray drifts a fair way on windy days. The nearer the rover runs to the "
            "pond, the wetter its cameras get, so it should favour lines well clear of it."
        ),
        voice="analyst",
        construct="graded_away",
        layers=("water", "grass", "trail", "sculpture"),
        expect=(("graded_away", "water", None),),
        routes=(Route("sample", "farther", "water"),),
    ),
    Brief(
        prompt=(
            "And, uh, trees. The closer you get to them, the, um, the worse the GPS gets. So further "
            "is better, up to, I dunno, fifteen metres, maybe?"
        ),
        voice="field",
        construct="graded_away",
        layers=("tree", "grass", "trail"),
        expect=(("graded_away", "tree", 15),),
        routes=(Route("neon", "farther", "tree"),),
    ),
    Brief(
        prompt="| hazard | rule |\n|---|---|\n| railway | the further the better |\n| road | avoid |",
        voice="robot",
        construct="graded_away",
        layers=("railway", "road", "vegetation", "building"),
        expect=(("graded_away", "railway", None), ("avoided", "road"), ("not_lethal", "road")),
        routes=(Route("nb2", "farther", "railway"),),
    ),
    # ------------------------------------------------------------------------------------------
    # graded_toward
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Hack out along the hedgerows: the tighter the rover keeps to the trees, the more "
            "shelter the horses get from the wind."
        ),
        voice="field",
        construct="graded_toward",
        layers=("tree", "grass", "road"),
        expect=(("graded_toward", "tree", None),),
        routes=(Route("sample", "closer", "tree"),),
    ),
    Brief(
        prompt=(
            "Comms are patchy out there. Keep close to the road so the relay truck can reach you; "
            "wandering off from it is what I'm worried about."
        ),
        voice="field",
        construct="graded_toward",
        layers=("road", "vegetation", "water", "building"),
        expect=(("graded_toward", "road", None), ("avoided", "water")),
        routes=(Route("nb1", "closer", "road"),),
        why="The water is not mentioned: it keeps its prior, in the avoided band.",
    ),
    Brief(
        prompt=(
            "CONDITION 9. Survey activity shall be kept, as far as practicable, in the vicinity of "
            "the existing trails, the nearer the better, so as to protect the turf."
        ),
        voice="analyst",
        construct="graded_toward",
        layers=("trail", "grass", "tree"),
        expect=(("graded_toward", "trail", None),),
        routes=(Route("sample", "closer", "trail"),),
    ),
    Brief(
        prompt="i want my robot to stay by the trees cos its really hot and thats where the shade is",
        voice="field",
        construct="graded_toward",
        layers=("tree", "grass", "water"),
        expect=(("graded_toward", "tree", None),),
    ),
    Brief(
        prompt=(
            "3.b. Scheme of manoeuvre: move tight to the treeline for concealment; the closer to "
            "cover, the better. Avoid open water."
        ),
        voice="field",
        construct="graded_toward",
        layers=("vegetation", "road", "building", "water"),
        expect=(("graded_toward", "vegetation", None), ("avoided", "water"), ("not_lethal", "water")),
        routes=(Route("nb1", "closer", "vegetation"),),
    ),
    Brief(
        prompt=(
            "Our photographer wants the robot drifting near the lake for the golden-hour shots: the "
            "nearer the water, the better the frame. It has to stay dry, obviously."
        ),
        voice="analyst",
        construct="graded_toward",
        layers=("water", "grass", "tree"),
        expect=(("graded_toward", "water", None),),
        why="Near the water, not in it: only the pull toward the shore is checked, not how dear the water is.",
    ),
    Brief(
        prompt=(
            "Radio tether to the cabinet degrades with range. Try to stay within about 30 m of the "
            "cabinet; nearer is always better."
        ),
        voice="robot",
        construct="graded_toward",
        layers=("cabinet", "road", "grass"),
        expect=(("graded_toward", "cabinet", 30),),
        why="'Try to' keeps it soft: ground 60 m away is dearer, not impassable.",
    ),
    Brief(
        prompt="Stay near the road lah, the nearer the better. Go too far from road, later we cannot find you.",
        voice="field",
        construct="graded_toward",
        layers=("road", "grass", "tree"),
        expect=(("graded_toward", "road", None),),
        routes=(Route("sample", "closer", "road"),),
    ),
    # ------------------------------------------------------------------------------------------
    # on_beside
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Shorelining drill today. The rover follows the edge of the grass closely, the way the "
            "dog does, but keeps its wheels off the grass itself."
        ),
        voice="field",
        construct="on_beside",
        layers=("grass", "trail", "road"),
        expect=(("beside", "grass"),),
    ),
    Brief(
        prompt="Walk the riverbank, not the river. Right along the water's edge, feet dry.",
        voice="field",
        construct="on_beside",
        layers=("water", "vegetation", "road", "building"),
        expect=(("beside", "water"),),
        routes=(Route("nb1", "beside", "water", 10),),
    ),
    Brief(
        prompt=("Duct survey follows the road verge end to end. Do not drive on the carriageway itself at any point."),
        voice="field",
        construct="on_beside",
        layers=("road", "grass", "building"),
        expect=(("beside", "road"), ("lethal", "road")),
        routes=(Route("sample", "beside", "road", 10),),
        why="The carriageway is the road; 'do not drive on it at any point' forbids it outright.",
    ),
    Brief(
        prompt=("The bridleway runs beside the railway for a stretch. Keep alongside the tracks there, never on them."),
        voice="field",
        construct="on_beside",
        layers=("railway", "vegetation", "road"),
        expect=(("beside", "railway"), ("lethal", "railway")),
        routes=(Route("nb2", "beside", "railway", 10),),
        why="'Never on them' forbids the tracks; alongside them is where to be.",
    ),
    Brief(
        prompt=(
            "Visitors should see the rover pass along the hedge line, so keep it beside the trees "
            "rather than under them."
        ),
        voice="analyst",
        construct="on_beside",
        layers=("tree", "grass", "trail", "sculpture"),
        expect=(("beside", "tree"),),
        routes=(Route("sample", "beside", "tree", 10),),
    ),
    Brief(
        prompt="go next to the road but not ON the road because of cars",
        voice="field",
        construct="on_beside",
        layers=("road", "grass", "building"),
        expect=(("beside", "road"),),
    ),
    Brief(
        prompt=(
            "Scenario: verge following\n"
            "  Given a road on the map\n"
            "  When the rover plans its path\n"
            "  Then the path runs on the ground next to the road\n"
            "  But never on the road surface"
        ),
        voice="robot",
        construct="on_beside",
        layers=("road", "grass", "tree"),
        expect=(("beside", "road"),),
    ),
    Brief(
        prompt=(
            "Axis follows the river line. Elements move along the near bank and do not cross the river at any point."
        ),
        voice="field",
        construct="on_beside",
        layers=("water", "vegetation", "road", "building"),
        expect=(("beside", "water"), ("no_cross", "water")),
        routes=(Route("nb1", "zero_on", "water"),),
        why="Along the bank, not in the river; 'do not cross ... at any point' is a hard never-cross rule.",
    ),
    # ------------------------------------------------------------------------------------------
    # qualified
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "Van access for the splice: paved road wherever possible. The unpaved road is washboard "
            "and shakes the kit loose, so only use it if nothing else connects."
        ),
        voice="field",
        construct="qualified",
        layers=("paved road", "unpaved road"),
        expect=(
            ("preferred", "paved road"),
            ("below", "paved road", "unpaved road"),
            ("avoided", "unpaved road"),
            ("not_lethal", "unpaved road"),
        ),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="'Only if nothing else connects' is a last resort: avoided, still passable.",
    ),
    Brief(
        prompt=(
            "Stay out of the young conifers entirely, they only went in this March. The old "
            "deciduous trees are robust; the rover can pass under those."
        ),
        voice="analyst",
        construct="qualified",
        layers=("conifer", "deciduous tree", "grass"),
        expect=(("lethal", "conifer"), ("not_lethal", "deciduous tree"), ("neutral", "deciduous tree")),
        why="'Stay out of' forbids the conifers; 'can pass under those' lifts the trees' prior for the deciduous ones.",
    ),
    Brief(
        prompt=(
            "Shallow flood water on the playing fields is fine to wade, the rover's rated for 30 cm. "
            "Deep water in the river channel: keep out of it."
        ),
        voice="field",
        construct="qualified",
        layers=("shallow water", "deep water", "grass", "road"),
        expect=(("lethal", "deep water"), ("not_lethal", "shallow water"), ("neutral", "shallow water")),
        why="'Fine to wade' is a permission that lifts the water prior for the shallow water only.",
    ),
    Brief(
        prompt=(
            "Structures within the park are to be avoided, save for the open-sided picnic shelter, "
            "through which the rover may pass."
        ),
        voice="analyst",
        construct="qualified",
        layers=("building", "picnic shelter", "grass", "tree"),
        expect=(
            ("avoided", "building"),
            ("not_lethal", "building"),
            ("not_lethal", "picnic shelter"),
            ("below", "picnic shelter", "building"),
        ),
    ),
    Brief(
        prompt="Blacktop's better'n gravel, but the gravel road ain't off limits, just slower goin'.",
        voice="field",
        construct="qualified",
        layers=("paved road", "unpaved road"),
        expect=(("below", "paved road", "unpaved road"), ("not_lethal", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="Blacktop is the paved road, gravel the unpaved; 'ain't off limits' negates the ban.",
    ),
    Brief(
        prompt="Mown grass is easy going. The long grass hides drainage ditches, so stay out of it.",
        voice="field",
        construct="qualified",
        layers=("mown grass", "long grass", "tree"),
        expect=(("lethal", "long grass"), ("not_lethal", "mown grass"), ("avoided", "tree")),
        why="The trees are not mentioned: they keep their prior, in the avoided band.",
    ),
    Brief(
        prompt="dont go in the pond!! the paddling pool is ok tho its only up to my knees",
        voice="field",
        construct="qualified",
        layers=("pond", "paddling pool", "grass"),
        expect=(("lethal", "pond"), ("not_lethal", "paddling pool")),
    ),
    Brief(
        prompt=(
            "The bronze pieces can take a bump. The marble ones cannot, so keep the rover out of the "
            "marble sculptures altogether."
        ),
        voice="analyst",
        construct="qualified",
        layers=("bronze sculpture", "marble sculpture", "grass"),
        expect=(("lethal", "marble sculpture"), ("not_lethal", "bronze sculpture")),
    ),
    # ------------------------------------------------------------------------------------------
    # terse
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="trail >> grass ; water = NO ; trees = meh",
        voice="robot",
        construct="terse",
        layers=("trail", "grass", "water", "tree"),
        expect=(("below", "trail", "grass"), ("lethal", "water"), ("not_lethal", "tree")),
        why="'meh' is lukewarm, not a ban: only that the trees stay passable is checked.",
    ),
    Brief(
        prompt="Road can. Grass also can. Water cannot.",
        voice="field",
        construct="terse",
        layers=("road", "grass", "water"),
        expect=(("lethal", "water"), ("not_lethal", "road"), ("not_lethal", "grass")),
        why="In Singapore English 'X cannot' means X is not allowed.",
    ),
    Brief(
        prompt="prefer the trial over the gras, and keep of the raod if u can",
        voice="field",
        construct="terse",
        layers=("trail", "grass", "road"),
        expect=(("below", "trail", "grass"), ("avoided", "road"), ("not_lethal", "road")),
        why="Typos for trail, grass and 'keep off the road'; 'if u can' keeps it soft.",
    ),
    Brief(
        prompt="bldg: 10m hard | water: 5m soft | rd: ok",
        voice="robot",
        construct="terse",
        layers=("building", "water", "road"),
        expect=(
            ("keep_out", "building", 10),
            ("soft_zone", "water", 5),
            ("not_lethal", "road"),
            ("neutral", "road"),
        ),
    ),
    Brief(
        prompt="road \u2192 trail \u2192 grass \u2192 trees (only if stuck)",
        voice="analyst",
        construct="terse",
        layers=("road", "trail", "grass", "tree"),
        expect=(
            ("below", "road", "trail"),
            ("below", "trail", "grass"),
            ("below", "grass", "tree"),
            ("avoided", "tree"),
            ("not_lethal", "tree"),
        ),
        routes=(Route("sample", "more_on", "road"),),
        why="A fallback chain, best first; the trees are a last resort, so avoided but passable.",
    ),
    Brief(
        prompt=(
            "| class | ok | avoid | never |\n|---|---|---|---|\n| road | x | | |\n| tree | | x | |\n| water | | | x |"
        ),
        voice="robot",
        construct="terse",
        layers=("road", "tree", "water"),
        expect=(
            ("not_lethal", "road"),
            ("avoided", "tree"),
            ("not_lethal", "tree"),
            ("lethal", "water"),
            ("below", "road", "tree"),
        ),
        routes=(Route("sample", "zero_on", "water"),),
    ),
    Brief(
        prompt="RAILS: NO-GO. VEG: AVOID. RD: USE.",
        voice="field",
        construct="terse",
        layers=("railway", "vegetation", "road", "building"),
        expect=(
            ("lethal", "railway"),
            ("avoided", "vegetation"),
            ("not_lethal", "vegetation"),
            ("preferred", "road"),
            ("avoided", "building"),
        ),
        routes=(Route("nb2", "zero_on", "railway"), Route("nb1", "more_on", "road")),
        why="The buildings are not mentioned: they keep their prior, in the avoided band.",
    ),
    Brief(
        prompt="stick to the paved raod. unpavd road ok-ish",
        voice="field",
        construct="terse",
        layers=("paved road", "unpaved road"),
        expect=(("below", "paved road", "unpaved road"), ("not_lethal", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"),),
    ),
    # ------------------------------------------------------------------------------------------
    # permission
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt=(
            "The gallery buildings are out of bounds. The old stable block, on the other hand, is "
            "empty storage now: treat it as open ground."
        ),
        voice="analyst",
        construct="permission",
        layers=("building", "stable", "grass"),
        expect=(("lethal", "building"), ("neutral", "stable"), ("not_lethal", "stable")),
        routes=(Route("sample", "zero_on", "building"),),
    ),
    Brief(
        prompt="Water's down to ankle depth across the lower field. You're cleared to drive straight through it now.",
        voice="field",
        construct="permission",
        layers=("water", "grass", "road"),
        expect=(("not_lethal", "water"), ("neutral", "water")),
    ),
    Brief(
        prompt=(
            "1.a. Terrain: the railway is disused, line closed since 2019. No restriction on "
            "crossing or moving along it."
        ),
        voice="field",
        construct="permission",
        layers=("railway", "road", "vegetation", "building"),
        expect=(("neutral", "railway"), ("not_lethal", "railway")),
    ),
    Brief(
        prompt="you ARE allowed under the trees. but NOT in the pond",
        voice="field",
        construct="permission",
        layers=("tree", "water", "grass"),
        expect=(("not_lethal", "tree"), ("neutral", "tree"), ("lethal", "water")),
        routes=(Route("sample", "zero_on", "water"),),
    ),
    Brief(
        prompt=(
            "The Permittee is authorised to operate on all turf areas. The Permittee shall keep out "
            "of the ornamental lake and every planted bed."
        ),
        voice="analyst",
        construct="permission",
        layers=("grass", "water", "flower bed", "tree"),
        expect=(
            ("not_lethal", "grass"),
            ("neutral", "grass"),
            ("lethal", "water"),
            ("lethal", "flower bed"),
        ),
        routes=(Route("sample", "zero_on", "water"),),
        why="Turf is the grass, merely authorised (neutral); 'shall keep out of' forbids the lake and the beds.",
    ),
    Brief(
        prompt=(
            "Scenario: orchard site\n"
            "  Given the trees are an orchard with high canopies\n"
            "  Then the rover may drive beneath the trees without penalty\n"
            "  And it must never enter the water"
        ),
        voice="robot",
        construct="permission",
        layers=("tree", "water", "grass"),
        expect=(("neutral", "tree"), ("not_lethal", "tree"), ("lethal", "water")),
    ),
    Brief(
        prompt=(
            "Them sheds out yonder are empty, no call to steer around 'em. The creek's another "
            "story: stay out of it, it's deeper'n it looks."
        ),
        voice="field",
        construct="permission",
        layers=("shed", "water", "grass"),
        expect=(("neutral", "shed"), ("not_lethal", "shed"), ("lethal", "water")),
    ),
    # ------------------------------------------------------------------------------------------
    # clauses
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="Avoid the road. Keep at least 3 m clear of the overhed power lines.",
        voice="field",
        construct="clauses",
        layers=("road", "grass", "building"),
        expect=(("avoided", "road"), ("not_lethal", "road"), ("unread", "power")),
        why="No layer stands for the power lines: that clause must be reported, not dropped.",
    ),
    Brief(
        prompt="Keep the robot off the dance floor and well away from the cake table; the lawn is fine.",
        voice="analyst",
        construct="clauses",
        layers=("grass", "tree", "building"),
        expect=(("unread", "dance"), ("unread", "cake"), ("not_lethal", "grass")),
        why="No layer stands for the dance floor or the cake table.",
    ),
    Brief(
        prompt="Residents' robots: use the street, give houses a miss, and never enter the retention pond.",
        voice="analyst",
        construct="clauses",
        layers=("road", "building", "water"),
        expect=(
            ("all_read",),
            ("preferred", "road"),
            ("avoided", "building"),
            ("not_lethal", "building"),
            ("lethal", "water"),
        ),
        why="'Give houses a miss' is to avoid them, not a ban; the retention pond is water.",
    ),
    Brief(
        prompt=(
            "Okay so, um, the battery's sitting at, like, sixty percent. So, uh, prefer the trail, I "
            "guess, and avoid the trees."
        ),
        voice="field",
        construct="clauses",
        layers=("trail", "tree", "grass"),
        expect=(("unread", "battery"), ("preferred", "trail"), ("avoided", "tree")),
        why="The battery level is not a rule about the ground: that clause is reported as not understood.",
    ),
    Brief(
        prompt=(
            "3. EXECUTION: avoid built-up areas; use covered routes through vegetation.\n"
            "4. SERVICE SUPPORT: refuel at the RV at 1400."
        ),
        voice="field",
        construct="clauses",
        layers=("building", "vegetation", "road"),
        expect=(("avoided", "building"), ("preferred", "vegetation"), ("unread", "refuel")),
        routes=(Route("nb1", "more_on", "vegetation"),),
    ),
    Brief(
        prompt="Take the road. Don't anyhow go into the water.",
        voice="field",
        construct="clauses",
        layers=("road", "water", "grass"),
        expect=(("all_read",), ("preferred", "road"), ("lethal", "water")),
        why="'Don't anyhow go into' is Singapore English for don't go into, at all.",
    ),
    Brief(
        prompt='<rules>\n  <prefer class="road"/>\n  <avoid class="crane"/>\n</rules>',
        voice="robot",
        construct="clauses",
        layers=("road", "building", "grass"),
        expect=(("preferred", "road"), ("unread", "crane")),
        why="No layer stands for the crane.",
    ),
    Brief(
        prompt=("Prefer the gravel trail through the sculpture lawn. And please don't let it photograph the Hepworth."),
        voice="analyst",
        construct="clauses",
        layers=("trail", "grass", "sculpture"),
        expect=(("preferred", "trail"), ("unread", "photograph")),
        why="Photographing is not a rule about where to drive.",
    ),
    Brief(
        prompt="The horses go sweetest on the trail, they'll put up with grass, and they hate the road.",
        voice="field",
        construct="clauses",
        layers=("trail", "grass", "road", "tree"),
        expect=(("all_read",), ("below", "trail", "grass"), ("below", "grass", "road")),
        why="An implied ranking: sweetest, put up with, hate.",
    ),
]
