"""Mission briefs, set 31: held-out briefs for issue 31, written blind.

This set was written without reading the interpreter (``overseec_core/interpret/``), its tests,
its corpora, the bench, the docs or the briefs of earlier sets: only the contract
(``tests/mission_briefs.py`` and its format test ``tests/test_mission_briefs.py``), the scene index
(``../shared/scenes/INDEX.md`` and the scenes' ``classes.json``), the first 80 lines of set 30
(for the layout, and its docstring's list of voices and wordings), the first 25 lines of sets 27,
28 and 29 (their docstrings' lists of voices, which this set avoids) and the ``[tool.ruff]``
sections of ``pyproject.toml`` were read. Set 30's first 80 lines are all docstring, so the layout
below (``BRIEFS`` and ``DOUBTFUL``) follows the contract's ``Brief`` and ``Route`` and what the format
test imports. It is scored once, at first contact, with ``bench/mission_briefs_report.py --set
31``; that figure is the one that counts, and the set is not edited afterwards to make the
interpreter pass.

The voices are a rail-yard shunting supervisor ("while the yard is live", "the running lines",
"walk it down the cess, never the four-foot", "yard's under possession", "ring the signaller",
"the points heaters"), a ski-resort snowcat groomer in summer (the cat up the service trail to the
lift towers, the lodge windows, shade along the tree line, steel tracks that chew up asphalt), a
forestry harvester operator (the riparian buffer "one chain either side", the forwarder scuffing
bark, a clearfell, bogging down by the creek, "the inspector'd have my hide"), an elderly gardener
("dear", "I shan't make a fuss", the roots, the roses, the bird bath, the ankle-deep pond, the
lawn that marks when wet), a Canadian speaker ("eh", "bud", "get 'er done", "a couple klicks",
"the drink", "CN runs freight", "moose", "suppertime"), a Welsh speaker ("now then", "mind",
"tidy", "see", "like", "there's no harm done", "that's where the lorries go"), a Boston speaker ("wicked close",
"period", "Stay outta the houses", "fair game"), a Kampala community health worker ("This one we
are very strict on", the boda bodas, the chickens and charcoal stoves), a wheelchair user (the
sidewalk beside the paved road, the dirt too rough for the wheels), an orienteering course setter
("advisory only", "out of bounds (olive green)", "runnable", the safety marshal's buggy), a
pest-control technician (the bait-station bot along the foundation), a homeowners' association
covenant ("ARTICLE VII, SECTION 3", "admits of no variance by the Board", "Subject to Section
4(c)", "reserved for equestrian use"), Markdown task lists (``- [x]``, ``- [ ]`` pending items,
"HARD: abort the run if breached", "no hard floor"), SMS threads with timestamps and abbreviations
("shd", "tbh", "k", "not a dealbreaker", "lol"), a voice-memo transcript with ums and restarts
("sorry, let me start that again", "Did I... yeah"), INI files (``[clearance]``, ``; hard``,
``on_violation = reject_route``, ``[avoid]``), Lisp s-expressions (``(clearance railway 15
:strict nil)``, ``(prefer (road :surface paved))``, ``(forbid building)``), protobuf text format
(``effect: REPEL``, ``shape: LINEAR_DECAY``, ``range_m: 30``, ``effect: ATTRACT``), and terse
lines with typos and symbols ("rlwy: 10m clr, hard", "bldgs bad. veg ok. h2o worse", "tress",
"watr", "basebal feild", "paved rd ✓✓  unpaved rd ✓", "trail >> grass > road"). The commission
also proposed a mountain-bike trail builder, a wedding planner, a solar farm O&M technician, an
Irish, a Nigerian and a Singlish speaker, a "notwithstanding" clause, a TOML file, a flight-school
NOTAM and a museum curator; sets 26 to 30 had used those (or a near copy), so this set has the
groomer, the harvester operator, the Welsh and Boston speakers, the health worker, the wheelchair
user, the course setter, the pest controller, the HOA covenant, INI, Lisp and protobuf instead.

Units come in metres and meters ("five meters"), feet (25 feet = 7.62 m, 30 feet = 9.144 m),
yards (two or three yards: 1.8288 m probed), a chain (20.1168 m), numbers as words ("ten metres",
"twelve metres", "fifteen metres", "twenty-five (25) feet"), ranges ("three to four metres", "3-4
m", "4-5 m", "between 6 and 8 m": the lower figure is probed, the upper is inside the probe's
margin), "~20m" and config numbers. Hard distance rules are worded "That's yard rules", "absolute
and admits of no variance", "does not go inside it, full stop", ``; hard`` with ``mode =
strict``, "No exceptions", "no ifs, ands or buts", "HARD: abort the run if breached", "five
meters, period", "Even where the passage is narrow it should not pass closer ... very strict" and
"10m clr, hard"; soft ones "Try and keep ... if you can ... if the trail takes you closer then it
takes you closer", "there's no harm done if it strays a bit closer", "nah just if it can, not a
dealbreaker", "I shan't make a fuss if it can't manage", "a preference, not a rule. Squeeze by",
``:strict nil``, "not a hard rule or nothin'" and "advisory only ... where practical". Graded
nearness away comes as "the nearer it creeps ..., the twitchier I get. Once it's 20 m clear it
makes no odds", "worse and worse the closer it gets ... after about twelve metres it stops
mattering", "Farther's better", ``REPEL`` with ``LINEAR_DECAY``, "the nearer it goes to a house,
the worse", "Closer you get to the creek ... the likelier we bog down ... by fifteen metres out
it's firm" (an implicit verdict), "rises as the gap shrinks (no hard floor) ... fades to zero at
6 m", "further = better (fades out ~20m)" and "Keep it well away"; toward as "as close to the
paved road as it can", "closer = better", "remain within sight of the water ... the quicker a
rescue", "nice and close, the closer the better", ``ATTRACT`` with ``INVERSE_DISTANCE`` and "The
closer to the walls the better". On versus beside comes as "the cess, never the four-foot", "tight
to the trees ... but you don't drive into them", "right along the edge of the water ... don't you
dare put 'er in the drink", "on that strip beside the road, not out on the road itself", "tight
along the foundation ... never goes inside", ``surface = forbidden`` / ``verge = preferred``,
"beside it I mean, not on it" and "alongside the trail ... not on the trail itself". Qualified
kinds are paved versus unpaved road (tarmac and asphalt, dirt and gravel) and an excepted sub-area
(the baseball field out of bounds, the rest of the grass runnable). Permissions lift the priors of
the railway ("free to go over the rails any place it likes", "fine 2 cross", and implicitly "dead
since the pits closed ... don't you go worrying about it"), trees ("a clearfell ... drive right
through the stand", "trees: fine", ``(allow tree)``) and water ("it can splash straight through
it", "permitted to traverse any pond or watercourse ... no penalty", ``(allow water)``), next to
forbidding in "Keep it out of the buildings", "not to go into any of the buildings", "shall not
enter", "stay out of it completely", "Stay outta", "out of bounds ... do not enter", "keep out",
"never enter", "no-go", "off limits", ``forbidden``, ``FORBID`` and ``(forbid building)``.
Conditions are stated as holding ("While the yard is live (and it's live all shift today)", "It
poured last night, and when the lawn's wet"). Unmentioned hazards are expected at their priors and
unmentioned non-hazards neutral. Clauses no layer carries (the battery, the signaller, the points
heaters, roses, the bird bath, the cat, the beaver dam, GPS logging, potholes, moose, suppertime,
chickens, charcoal stoves) are expected to be reported as not understood, and one protobuf brief
whose every line names a layer is expected to be read in full.
"""

from __future__ import annotations

from tests.mission_briefs import Brief, Route

NB = ("building", "road", "water", "vegetation", "railway")
SAMPLE = ("grass", "road", "trail", "tree", "water", "building", "baseball field")
VEGAS = ("paved road", "unpaved road")
KAMPALA = ("building",)
MASS = ("building",)
NEON = ("tree",)

BRIEFS: list[Brief] = [
    # ------------------------------------------------------------------------------------------
    # distance_hard
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="Right, listen in. While the yard is live (and it's live all shift today) nobody takes that rover within 6 metres of the running lines. That's yard rules, not me being awkward. The sheds and the mess hut are obstacles like anything else.",
        voice="field",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "railway", 6), ("avoided", "building")),
        routes=(Route("nb2", "keeps", "railway", 6.0),),
        why="The condition (the yard is live) is stated as holding today, so the clearance is in force, and 'yard rules' make it absolute. The sheds and mess hut are buildings, left as obstacles: avoided, as the prior has them.",
    ),
    Brief(
        prompt="ARTICLE VII, SECTION 3 (Autonomous Yard Equipment). No autonomous device operated upon the Common Areas shall approach nearer than twenty-five (25) feet to any dwelling, garage or other structure. This restriction is absolute and admits of no variance by the Board.",
        voice="analyst",
        construct="distance_hard",
        layers=MASS,
        expect=(("keep_out", "building", 7.62),),
        routes=(Route("massachusetts", "keeps", "building", 7.62),),
        why="25 feet = 7.62 m; 'absolute and admits of no variance' is a hard zone. Dwellings, garages and other structures are all the building layer.",
    ),
    Brief(
        prompt="We run a riparian buffer on every creek in this block, one chain either side of the water, and the harvester does not go inside it, full stop. If the inspector finds a rut in there we're shut down.",
        voice="field",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "water", 20.1168),),
        routes=(Route("nb1", "keeps", "water", 20.1168),),
        why="A (Gunter's) chain is 66 ft = 20.1168 m; 'does not go inside it, full stop' is absolute.",
    ),
    Brief(
        prompt="[clearance]\nbuilding = 12 m   ; hard\nwater = 5 m       ; hard\n\n[enforcement]\nmode = strict\non_violation = reject_route",
        voice="robot",
        construct="distance_hard",
        layers=SAMPLE,
        expect=(("keep_out", "building", 12), ("keep_out", "water", 5), ("neutral", "grass")),
        routes=(Route("sample", "keeps", "building", 12.0), Route("sample", "keeps", "water", 5.0)),
        why="An INI file: both clearances are marked hard and enforced strictly. Grass is not mentioned and is no hazard: neutral.",
    ),
    Brief(
        prompt="Um, okay, is this... yeah it's recording. So for the tree plot tomorrow the rover has to stay, uh, three to four metres off the... sorry, let me start that again. It has to stay at least three to four metres from every tree. No exceptions, because the mast clips the branches otherwise. Um. Yeah, that's it.",
        voice="field",
        construct="distance_hard",
        layers=NEON,
        expect=(("keep_out", "tree", 3),),
        routes=(Route("neon", "keeps", "tree", 3.0),),
        why="A voice memo with a restart; the rule as restated is 'at least three to four metres ... no exceptions'. The lower figure is probed; the upper one is inside the probe's margin, so either reading passes.",
    ),
    Brief(
        prompt="Okay bud, here's the deal, eh: the rover stays a good ten metres off the road the whole way, no ifs, ands or buts, 'cause the plows come through and the township's got rules about it. Other than that just get 'er done, it's only a couple klicks.",
        voice="field",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "road", 10), ("avoided", "water"), ("avoided", "building")),
        routes=(Route("nb1", "keeps", "road", 10.0),),
        why="'No ifs, ands or buts' is absolute; 'a good ten metres' means at least ten. Water and buildings are not mentioned: hazards at their priors. 'A couple klicks' is the length of the run, not a distance rule.",
    ),
    Brief(
        prompt="## Pre-run checklist\n- [x] Battery at 100 %\n- [x] Min. clearance to buildings: 8 m (HARD: abort the run if breached)\n- [x] Water: off limits\n- [ ] Client sign-off (still pending)",
        voice="analyst",
        construct="distance_hard",
        layers=NB,
        expect=(("keep_out", "building", 8), ("lethal", "water"), ("unread", "battery")),
        routes=(Route("nb2", "keeps", "building", 8.0), Route("nb2", "zero_on", "water")),
        why="A Markdown task list: the clearance is marked HARD, water 'off limits' forbids it, and the battery line says nothing any layer can carry.",
    ),
    Brief(
        prompt="Listen, I'm not kiddin' around here. That thing does not go within 5 meters of anybody's house. Not wicked close, not kinda close: five meters, period. The neighbors'll have a fit otherwise.",
        voice="field",
        construct="distance_hard",
        layers=MASS,
        expect=(("keep_out", "building", 5),),
        routes=(Route("massachusetts", "keeps", "building", 5.0),),
        why="A Boston speaker; 'five meters, period' is absolute.",
    ),
    Brief(
        prompt="Please, the machine must never come closer than 2 metres to any house in this area. Even where the passage is narrow it should not pass closer, people sit outside their doors in the evening. This one we are very strict on.",
        voice="field",
        construct="distance_hard",
        layers=KAMPALA,
        expect=(("keep_out", "building", 2),),
        routes=(Route("kampala", "keeps", "building", 2.0),),
        why="'Must never come closer', held even where the passage is narrow, and 'very strict': a hard zone.",
    ),
    # ------------------------------------------------------------------------------------------
    # distance_soft
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="Summers we drive the cat up the service trail to check on the lift towers. Try and keep about 15 m back from the lodge and the other buildings if you can, it rattles the windows, but if the trail takes you closer then it takes you closer.",
        voice="field",
        construct="distance_soft",
        layers=SAMPLE,
        expect=(("soft_zone", "building", 15), ("preferred", "trail")),
        routes=(Route("sample", "farther", "building"), Route("sample", "more_on", "trail")),
        why="'Try ... if you can' and the shrug about the trail make the 15 m soft. That the cat drives up the service trail is the mission itself: the trail is preferred, a verdict left implicit.",
    ),
    Brief(
        prompt="Now then, I'd like it to keep a tidy distance from the water, mind. Ten metres or so would be lovely, but there's no harm done if it strays a bit closer where it has to, see.",
        voice="field",
        construct="distance_soft",
        layers=SAMPLE,
        expect=(("soft_zone", "water", 10), ("not_lethal", "water")),
        routes=(Route("sample", "farther", "water"),),
        why="A Welsh speaker; 'no harm done if it strays a bit closer' makes the ten metres a wish.",
    ),
    Brief(
        prompt="[09:14] Dana: can the bot keep like 4-5 m off the paved road? trucks\n[09:15] Sam: is that a must?\n[09:15] Dana: nah just if it can, not a dealbreaker\n[09:16] Sam: k",
        voice="field",
        construct="distance_soft",
        layers=VEGAS,
        expect=(("soft_zone", "paved road", 4), ("not_lethal", "paved road"), ("neutral", "unpaved road")),
        routes=(Route("vegas", "farther", "paved road"),),
        why="An SMS thread: the answer to 'is that a must?' is 'nah', so the 4-5 m is soft (lower figure probed). The unpaved road is not mentioned: neutral.",
    ),
    Brief(
        prompt="Oh, I don't like it trundling too near my trees, dear, the roots come right up to the top. If it could stay two or three yards away from them I'd be ever so grateful, though I shan't make a fuss if it can't manage.",
        voice="field",
        construct="distance_soft",
        layers=SAMPLE,
        expect=(("soft_zone", "tree", 1.8288),),
        routes=(Route("sample", "farther", "tree"),),
        why="Two yards = 1.8288 m (the lower end of 'two or three yards'); 'I shan't make a fuss if it can't' is soft.",
    ),
    Brief(
        prompt="When we're thinning this stand I'd rather the forwarder kept roughly 5 m clear of the standing trees, it scuffs the bark, but that's a preference, not a rule. Squeeze by if you have to.",
        voice="field",
        construct="distance_soft",
        layers=NEON,
        expect=(("soft_zone", "tree", 5), ("not_lethal", "tree")),
        routes=(Route("neon", "farther", "tree"),),
        why="'A preference, not a rule. Squeeze by if you have to.'",
    ),
    Brief(
        prompt="(mission\n  (prefer road)\n  (clearance railway 15 :strict nil)\n  (clearance building 6 :strict nil))",
        voice="robot",
        construct="distance_soft",
        layers=NB,
        expect=(("preferred", "road"), ("soft_zone", "railway", 15), ("soft_zone", "building", 6)),
        routes=(Route("nb2", "farther", "railway"),),
        why="Lisp s-expressions: ':strict nil' says the clearances are not strict, so both zones are soft.",
    ),
    Brief(
        prompt="If ya can, keep 'er about 30 feet from the tracks, eh? CN runs freight through there. It's not a hard rule or nothin', just good sense. Sorry, I know that's kinda vague.",
        voice="field",
        construct="distance_soft",
        layers=NB,
        expect=(("soft_zone", "railway", 9.144), ("not_lethal", "railway")),
        routes=(Route("nb2", "farther", "railway"),),
        why="30 feet = 9.144 m; 'not a hard rule' says so.",
    ),
    Brief(
        prompt="Course setter's note (advisory only): the support buggy should, where practical, hold between 6 and 8 m off the trail so it doesn't spook runners. It may cross the trail square-on wherever it needs to.",
        voice="analyst",
        construct="distance_soft",
        layers=SAMPLE,
        expect=(("soft_zone", "trail", 6), ("not_lethal", "trail")),
        routes=(Route("sample", "farther", "trail"),),
        why="An orienteering course setter: 'advisory only' and 'where practical' are soft, and the trail may be crossed, so it is not impassable. The lower end of 6-8 m is probed.",
    ),
    # ------------------------------------------------------------------------------------------
    # graded_away
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="The nearer it creeps to the rails, the twitchier I get. Once it's 20 m clear it makes no odds to me either way.",
        voice="field",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "railway", 20),),
        routes=(Route("nb2", "farther", "railway"),),
        why="The closer, the worse, fading out at 20 m.",
    ),
    Brief(
        prompt="So, uh, the water. The... okay. Nearer the water is worse. Not forbidden, just, like, worse and worse the closer it gets. Um, and after about twelve metres it stops mattering. Twelve, yeah.",
        voice="field",
        construct="graded_away",
        layers=SAMPLE,
        expect=(("graded_away", "water", 12), ("not_lethal", "water")),
        routes=(Route("sample", "farther", "water"),),
        why="Graded nearness with a fall-off at twelve metres; 'not forbidden' keeps the water passable.",
    ),
    Brief(
        prompt="The nearer it gets to the houses, the more it bugs people, so keep it as far off 'em as you can. Farther's better, y'know?",
        voice="field",
        construct="graded_away",
        layers=MASS,
        expect=(("graded_away", "building", None),),
        routes=(Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        prompt='rule {\n  class: "building"\n  effect: REPEL\n  shape: LINEAR_DECAY\n  range_m: 30\n}',
        voice="robot",
        construct="graded_away",
        layers=SAMPLE,
        expect=(("graded_away", "building", 30),),
        routes=(Route("sample", "farther", "building"),),
        why="Protobuf text format: a repulsion decaying linearly to nothing at 30 m.",
    ),
    Brief(
        prompt="The houses here are very close together, so the robot cannot stay far from them. But the nearer it goes to a house, the worse; let it keep to the middle of the passages where it can.",
        voice="field",
        construct="graded_away",
        layers=KAMPALA,
        expect=(("graded_away", "building", None),),
        routes=(Route("kampala", "farther", "building"),),
        why="The speaker concedes no fixed distance is possible; what is asked is graded (the middle of the passage is the farthest from the walls).",
    ),
    Brief(
        prompt="Closer you get to the creek the softer the ground and the likelier we bog down. A bit back from the bank is alright, and by fifteen metres out it's firm.",
        voice="field",
        construct="graded_away",
        layers=NB,
        expect=(("graded_away", "water", 15),),
        routes=(Route("nb1", "farther", "water"),),
        why="An implicit verdict: nothing says 'avoid', but bogging down is what a harvester operator wants to avoid, worse the closer, and no concern from 15 m out.",
    ),
    Brief(
        prompt="- [x] Proximity penalty near trees: rises as the gap shrinks (no hard floor)\n- [x] Penalty fades to zero at 6 m\n- [x] All other classes: defaults",
        voice="analyst",
        construct="graded_away",
        layers=SAMPLE,
        expect=(("graded_away", "tree", 6), ("avoided", "water"), ("neutral", "grass")),
        routes=(Route("sample", "farther", "tree"),),
        why="'No hard floor' rules out a keep-out; the fall-off ends at 6 m. 'Defaults' leaves water at its hazard prior and grass neutral.",
    ),
    # ------------------------------------------------------------------------------------------
    # graded_toward
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="I'm in a chair, so the scout robot should stay as close to the paved road as it can. The nearer the paved road, the better for me; the dirt off to the side is too rough for my wheels.",
        voice="field",
        construct="graded_toward",
        layers=VEGAS,
        expect=(("graded_toward", "paved road", None), ("preferred", "paved road")),
        routes=(Route("vegas", "closer", "paved road"), Route("vegas", "more_on", "paved road")),
        why="A wheelchair user: the road itself is the best of all for the wheels, and ground is dearer the farther from it.",
    ),
    Brief(
        prompt="Mia: where shd the rover go\nJo: near the trail, closer = better\nMia: on it too or just near\nJo: on it is best tbh",
        voice="field",
        construct="graded_toward",
        layers=SAMPLE,
        expect=(("graded_toward", "trail", None), ("preferred", "trail"), ("avoided", "water")),
        routes=(Route("sample", "closer", "trail"), Route("sample", "more_on", "trail")),
        why="An SMS thread. Water is not mentioned: a hazard at its prior.",
    ),
    Brief(
        prompt="Safety marshal's buggy: remain within sight of the water at all times. The nearer the shoreline, the quicker a rescue.",
        voice="analyst",
        construct="graded_toward",
        layers=SAMPLE,
        expect=(("graded_toward", "water", None),),
        routes=(Route("sample", "closer", "water"),),
        why="The second sentence gives the reason, and its verdict is implicit: nearer the water is better.",
    ),
    Brief(
        prompt="I like it to potter about near the house and the shed, nice and close, the closer the better, so I can keep an eye on it from the kitchen window.",
        voice="field",
        construct="graded_toward",
        layers=SAMPLE,
        expect=(("graded_toward", "building", None),),
        routes=(Route("sample", "closer", "building"),),
        why="The house and the shed are the building layer.",
    ),
    Brief(
        prompt='rule { class: "tree" effect: ATTRACT shape: INVERSE_DISTANCE }  # shade for the battery',
        voice="robot",
        construct="graded_toward",
        layers=NEON,
        expect=(("graded_toward", "tree", None),),
        routes=(Route("neon", "closer", "tree"),),
    ),
    Brief(
        prompt="Let the robot move close to the houses, along the walls, so it is not in the way of the boda bodas in the open. The closer to the walls the better.",
        voice="field",
        construct="graded_toward",
        layers=KAMPALA,
        expect=(("graded_toward", "building", None),),
        routes=(Route("kampala", "closer", "building"),),
    ),
    # ------------------------------------------------------------------------------------------
    # on_beside
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="Walk it down the cess, never the four-foot. For the new starters: the cess is the strip alongside the track, the four-foot is between the rails.",
        voice="field",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "railway"),),
        routes=(Route("nb2", "beside", "railway", 5.0),),
        why="A shunting supervisor's jargon, explained in the brief: alongside the track, never on it.",
    ),
    Brief(
        prompt="On hot days we run the cat along the tree line for a bit of shade on the engine, tight to the trees, the tighter the better, but you don't drive into them, obviously.",
        voice="field",
        construct="on_beside",
        layers=SAMPLE,
        expect=(("beside", "tree"),),
        routes=(Route("sample", "beside", "tree", 5.0),),
    ),
    Brief(
        prompt="We're doin' a shoreline survey, eh, so run 'er right along the edge of the water, tight to it, but don't you dare put 'er in the drink.",
        voice="field",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "water"),),
        routes=(Route("nb1", "beside", "water", 5.0),),
        why="'The drink' is the water.",
    ),
    Brief(
        prompt="The sidewalk runs right next to the paved road. I want the robot on that strip beside the road, not out on the road itself with the cars.",
        voice="field",
        construct="on_beside",
        layers=VEGAS,
        expect=(("beside", "paved road"),),
        routes=(Route("vegas", "beside", "paved road", 5.0),),
    ),
    Brief(
        prompt="I run the bait-station bot round the outside of each house, tight along the foundation, about 3-4 m out at most. It never goes inside, obviously.",
        voice="field",
        construct="on_beside",
        layers=MASS,
        expect=(("beside", "building"),),
        routes=(Route("massachusetts", "beside", "building", 4.0),),
        why="A pest-control technician: a band along the walls, never into the house.",
    ),
    Brief(
        prompt="[road]\nsurface = forbidden\nverge = preferred   ; ride the strip beside it",
        voice="robot",
        construct="on_beside",
        layers=SAMPLE,
        expect=(("beside", "road"), ("lethal", "road")),
        routes=(Route("sample", "beside", "road", 5.0),),
        why="The road surface is forbidden outright; the verge beside it is preferred.",
    ),
    Brief(
        prompt="Okay so, um, the road. Follow along the road, beside it I mean, not on it. On it is bad. Beside it is good. Did I... yeah. Okay, done.",
        voice="field",
        construct="on_beside",
        layers=NB,
        expect=(("beside", "road"), ("avoided", "water")),
        routes=(Route("nb1", "beside", "road", 5.0),),
        why="Water is not mentioned: a hazard at its prior.",
    ),
    Brief(
        prompt="Run it alongside the trail now, on the grass next to it like, not on the trail itself mind, that's for the walkers.",
        voice="field",
        construct="on_beside",
        layers=SAMPLE,
        expect=(("beside", "trail"),),
        routes=(Route("sample", "beside", "trail", 5.0),),
        why="A Welsh speaker. 'The grass next to it' names where the band lies, not a preference for all grass, so grass is not asserted.",
    ),
    # ------------------------------------------------------------------------------------------
    # qualified
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="Paved road is best for my wheels. Unpaved road I can't do at all, so stay out of it completely.",
        voice="field",
        construct="qualified",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("lethal", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"), Route("vegas", "zero_on", "unpaved road")),
    ),
    Brief(
        prompt="Lee: dirt roads ok for the bot?\nKim: dirt's ok but tarmac's better\nLee: 👍",
        voice="field",
        construct="qualified",
        layers=VEGAS,
        expect=(("below", "paved road", "unpaved road"), ("preferred", "paved road"), ("not_lethal", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="Dirt roads are the unpaved road, tarmac the paved one; dirt is allowed, tarmac better.",
    ),
    Brief(
        prompt="Map legend applies. The baseball field is out of bounds (olive green), do not enter. The rest of the open grass is runnable and may be crossed freely.",
        voice="analyst",
        construct="qualified",
        layers=SAMPLE,
        expect=(("lethal", "baseball field"), ("neutral", "grass"), ("not_lethal", "grass")),
        routes=(Route("sample", "zero_on", "baseball field"),),
        why="An excepted sub-area: of the grassy ground only the baseball field is forbidden; the rest of the grass is merely allowed (neutral).",
    ),
    Brief(
        prompt="Section 5.2. Operation of the device shall be confined to paved roads. Unpaved roads within the Community are reserved for equestrian use, and the device shall not enter them.",
        voice="analyst",
        construct="qualified",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("lethal", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"), Route("vegas", "zero_on", "unpaved road")),
        why="An HOA covenant: 'shall not enter' forbids the unpaved roads.",
    ),
    Brief(
        prompt="(prefer (road :surface paved))\n(avoid (road :surface unpaved))",
        voice="robot",
        construct="qualified",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("avoided", "unpaved road"), ("below", "paved road", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        prompt="The cat's steel tracks chew up asphalt, so keep it off the paved road as much as you can and run it on the unpaved road instead. That's what gravel's for.",
        voice="field",
        construct="qualified",
        layers=VEGAS,
        expect=(("avoided", "paved road"), ("preferred", "unpaved road"), ("below", "unpaved road", "paved road")),
        routes=(Route("vegas", "less_on", "paved road"),),
        why="'As much as you can' makes the paved road avoided, not forbidden.",
    ),
    Brief(
        prompt="The unpaved road's fine for it, tidy. The paved road though, I'd rather it kept mostly off there, that's where the lorries go, see.",
        voice="field",
        construct="qualified",
        layers=VEGAS,
        expect=(("avoided", "paved road"), ("not_lethal", "unpaved road"), ("below", "unpaved road", "paved road")),
        routes=(Route("vegas", "less_on", "paved road"),),
    ),
    # ------------------------------------------------------------------------------------------
    # terse
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="trail >> grass > road; water = no-go",
        voice="robot",
        construct="terse",
        layers=SAMPLE,
        expect=(
            ("below", "trail", "grass"),
            ("below", "grass", "road"),
            ("lethal", "water"),
            ("avoided", "building"),
        ),
        routes=(Route("sample", "more_on", "trail"), Route("sample", "zero_on", "water")),
        why="Buildings are not mentioned: a hazard at its prior.",
    ),
    Brief(
        prompt="rlwy: 10m clr, hard",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(("keep_out", "railway", 10),),
        routes=(Route("nb2", "keeps", "railway", 10.0),),
    ),
    Brief(
        prompt="bldgs bad. veg ok. h2o worse than bldgs.",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(
            ("avoided", "building"),
            ("neutral", "vegetation"),
            ("avoided", "water"),
            ("below", "building", "water"),
        ),
        routes=(Route("nb1", "less_on", "water"),),
        why="'veg ok' merely allows the vegetation: neutral.",
    ),
    Brief(
        prompt="paved rd ✓✓  unpaved rd ✓",
        voice="robot",
        construct="terse",
        layers=VEGAS,
        expect=(("below", "paved road", "unpaved road"), ("preferred", "paved road"), ("not_lethal", "unpaved road")),
        routes=(Route("vegas", "more_on", "paved road"),),
        why="Two ticks against one: both allowed, the paved road better.",
    ),
    Brief(
        prompt="tress: avoid if poss / grass: gd / watr: never enter",
        voice="robot",
        construct="terse",
        layers=SAMPLE,
        expect=(("avoided", "tree"), ("preferred", "grass"), ("lethal", "water")),
        routes=(Route("sample", "zero_on", "water"), Route("sample", "more_on", "grass")),
        why="Typos ('tress', 'watr'); 'if poss' keeps the trees passable.",
    ),
    Brief(
        prompt="nr bldngs = bad, further = better (fades out ~20m)",
        voice="robot",
        construct="terse",
        layers=MASS,
        expect=(("graded_away", "building", 20),),
        routes=(Route("massachusetts", "farther", "building"),),
    ),
    Brief(
        prompt="rd: fine. rlwy: fine 2 cross.",
        voice="robot",
        construct="terse",
        layers=NB,
        expect=(("neutral", "road"), ("neutral", "railway"), ("not_lethal", "railway")),
        why="'fine 2 cross' lifts the railway's prior: merely allowed, neutral.",
    ),
    Brief(
        prompt="basebal feild: keep out. trees: fine.",
        voice="robot",
        construct="terse",
        layers=SAMPLE,
        expect=(("lethal", "baseball field"), ("neutral", "tree"), ("not_lethal", "tree")),
        routes=(Route("sample", "zero_on", "baseball field"),),
        why="A typo in the two-word name; 'keep out' forbids; 'trees: fine' lifts their prior to neutral.",
    ),
    # ------------------------------------------------------------------------------------------
    # permission
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="Yard's under possession today, nothing moving, so the rover's free to go over the rails any place it likes. Keep it out of the buildings though.",
        voice="field",
        construct="permission",
        layers=NB,
        expect=(("neutral", "railway"), ("not_lethal", "railway"), ("lethal", "building")),
        routes=(Route("nb2", "zero_on", "building"),),
    ),
    Brief(
        prompt="This block's a clearfell, so don't fuss about the trees. Drive right through the stand, it's all coming down anyway.",
        voice="field",
        construct="permission",
        layers=NEON,
        expect=(("neutral", "tree"), ("not_lethal", "tree")),
        why="The trees' prior is lifted: they are merely allowed, so neutral.",
    ),
    Brief(
        prompt="Oh, the pond? It's barely ankle deep, dear, it can splash straight through it, I don't mind a bit. But it's not to go into any of the buildings.",
        voice="field",
        construct="permission",
        layers=SAMPLE,
        expect=(("neutral", "water"), ("not_lethal", "water"), ("lethal", "building")),
        routes=(Route("sample", "zero_on", "building"),),
        why="The pond is the water layer; splashing through is allowed (neutral), going into buildings forbidden.",
    ),
    Brief(
        prompt="Section 4(b). Subject to Section 4(c), the Operator is hereby permitted to traverse any pond or watercourse within the Premises, and such traversal shall carry no penalty. Section 4(c). The Operator shall not enter any building.",
        voice="analyst",
        construct="permission",
        layers=NB,
        expect=(("neutral", "water"), ("not_lethal", "water"), ("lethal", "building")),
        routes=(Route("nb1", "zero_on", "building"),),
    ),
    Brief(
        prompt="That old railway's been dead since the pits closed. Rusted solid, nothing's run on it for forty years, so don't you go worrying about it.",
        voice="field",
        construct="permission",
        layers=NB,
        expect=(("neutral", "railway"), ("not_lethal", "railway")),
        why="An implicit permission: a disused line with nothing to fear, and 'don't go worrying about it' lifts the railway's prior.",
    ),
    Brief(
        prompt="(allow water)\n(allow tree)\n(forbid building)",
        voice="robot",
        construct="permission",
        layers=SAMPLE,
        expect=(("neutral", "water"), ("neutral", "tree"), ("lethal", "building")),
        routes=(Route("sample", "zero_on", "building"),),
    ),
    Brief(
        prompt="Stay outta the houses, obviously. Everything else is fair game.",
        voice="field",
        construct="permission",
        layers=MASS,
        expect=(("lethal", "building"),),
        routes=(Route("massachusetts", "zero_on", "building"),),
        why="'Stay outta' is stay-out wording: it forbids.",
    ),
    # ------------------------------------------------------------------------------------------
    # clauses
    # ------------------------------------------------------------------------------------------
    Brief(
        prompt="Keep it well away from the rails, ring the signaller on channel 4 before you set off, and don't let it anywhere near the points heaters.",
        voice="field",
        construct="clauses",
        layers=NB,
        expect=(("graded_away", "railway", None), ("unread", "signaller"), ("unread", "heater")),
        routes=(Route("nb2", "farther", "railway"),),
        why="Ringing the signaller and the points heaters are nothing a layer carries.",
    ),
    Brief(
        prompt="Mind the trees. And mind my roses, they're by the back door. And the bird bath, my late husband made that.",
        voice="field",
        construct="clauses",
        layers=SAMPLE,
        expect=(("avoided", "tree"), ("unread", "roses"), ("unread", "bird bath")),
        routes=(Route("sample", "less_on", "tree"),),
    ),
    Brief(
        prompt="Ash: rover route pls?\nBo: avoid water, use the trail, dont run over the cat lol",
        voice="field",
        construct="clauses",
        layers=SAMPLE,
        expect=(("avoided", "water"), ("preferred", "trail"), ("unread", "cat")),
        routes=(Route("sample", "more_on", "trail"), Route("sample", "less_on", "water")),
    ),
    Brief(
        prompt="- [x] Avoid buildings\n- [x] Prefer roads\n- [x] Steer clear of the beaver dam on the east side\n- [x] Log GPS at 1 Hz",
        voice="analyst",
        construct="clauses",
        layers=NB,
        expect=(("avoided", "building"), ("preferred", "road"), ("unread", "beaver"), ("unread", "GPS")),
        routes=(Route("nb1", "more_on", "road"),),
    ),
    Brief(
        prompt="[prefer]\npaved road = yes\n\n[avoid]\nunpaved road = yes\npotholes = yes",
        voice="robot",
        construct="clauses",
        layers=VEGAS,
        expect=(("preferred", "paved road"), ("avoided", "unpaved road"), ("unread", "pothole")),
        routes=(Route("vegas", "more_on", "paved road"),),
    ),
    Brief(
        prompt="Stick to the road, eh, watch out for moose, and have 'er back by suppertime.",
        voice="field",
        construct="clauses",
        layers=NB,
        expect=(("preferred", "road"), ("unread", "moose"), ("unread", "suppertime")),
        routes=(Route("nb1", "more_on", "road"),),
    ),
    Brief(
        prompt='rule { class: "trail" effect: PREFER }\nrule { class: "water" effect: AVOID }\nrule { class: "building" effect: FORBID }',
        voice="robot",
        construct="clauses",
        layers=SAMPLE,
        expect=(("preferred", "trail"), ("avoided", "water"), ("lethal", "building"), ("all_read",)),
        routes=(Route("sample", "more_on", "trail"), Route("sample", "zero_on", "building")),
        why="Every line names a layer and an effect: nothing is left unread.",
    ),
    Brief(
        prompt="Please avoid the houses, and also the chickens and the charcoal stoves people keep outside.",
        voice="field",
        construct="clauses",
        layers=KAMPALA,
        expect=(("avoided", "building"), ("unread", "chicken"), ("unread", "charcoal")),
        routes=(Route("kampala", "less_on", "building"),),
    ),
    Brief(
        prompt="It poured last night, and when the lawn's wet I'd rather it stayed off the grass, so today it's the paths for it. Not that the grass is forbidden, it just marks.",
        voice="field",
        construct="clauses",
        layers=SAMPLE,
        expect=(("avoided", "grass"), ("not_lethal", "grass"), ("preferred", "trail")),
        routes=(Route("sample", "less_on", "grass"), Route("sample", "more_on", "trail")),
        why="A conditional whose condition is stated as holding (it poured, the lawn is wet), so the rule is in force: grass avoided but not forbidden; 'the paths' are the trail.",
    ),
    Brief(
        prompt="Road's best, then the open ground, then the bush if there's no other way, and never into the water, the inspector'd have my hide.",
        voice="field",
        construct="clauses",
        layers=NB,
        expect=(
            ("preferred", "road"),
            ("avoided", "vegetation"),
            ("below", "road", "vegetation"),
            ("lethal", "water"),
        ),
        routes=(
            Route("nb1", "more_on", "road"),
            Route("nb1", "less_on", "vegetation"),
            Route("nb1", "zero_on", "water"),
        ),
        why="A ranking: road < open (unlabelled) ground < bush, so the bush is above neutral; 'never into the water' forbids it.",
    ),
]

#: Briefs whose expectation was found to contradict the cost-scale contract (id or prompt -> why).
DOUBTFUL: dict[str, str] = {}
