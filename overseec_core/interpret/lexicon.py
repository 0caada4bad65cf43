"""The offline interpreter's vocabulary: entity table (geometry, part-of parent, aliases), weights
and phrase tables (triggers, modifiers, comparators, conditions, distances, grammar words).

A declarative table (phrases -> meanings): exempt from the ~600-line module limit.

These tables are the documentation: what the offline interpreter knows is exactly what is listed
here. Everything else in a prompt is either grammar (``FILLER``) or reported back as unparsed.

Weights here are ordinal keys (lower = preferred); :mod:`.merge` turns them into ranks and into
levels on the cost scale (``NEUTRAL`` = 0.5 is unmentioned and unlabelled ground, preferred below,
avoided above, lethal impassable; see ``costlang/LANGUAGE.md``). Preferred keys are spread
evenly below neutral; avoided keys are their own levels, below the priors of the hazards a
prompt leaves unsaid (:mod:`.priors`: trees 0.85, railways 0.9, buildings and water 1.0):

==========  ======  ===================================================================
tier        key     phrases (examples)
==========  ======  ===================================================================
prefer      0.10    prefer, best, ideal, stay on, stick to, use, keep to, great
fine        0.50    fine, okay, acceptable, allowed, can go under, you may cross, dry
                    (= neutral: permission is no preference either way)
tolerable   0.60    tolerable, if needed, if necessary, not ideal, second choice
last        0.65    last resort, as a last resort, only in an emergency (the worst ground still used)
avoid       0.70    avoid, stay off, keep away from, don't, should not, dangerous, leave X
avoid+      0.80    avoid ... as much as possible / whenever possible / strictly
nocross     0.80    do not cross, never cross, must not cross (+ a ``no_cross`` rule: kept
                    out of unless it separates the points, then crossed once, cheapest place)
lethal      1.00    never (enter), forbidden, impassable, off limits, at all costs, must not
==========  ======  ===================================================================

An entity the prompt gives no preference -- one of the default set the segmenter always looks
for, or one named only in a cue -- is ``NEUTRAL`` (no invented preference), or, for a hazard,
at its prior.

Negation is composed with the verb it stands with (clauses._polarity), not listed phrase by
phrase: "leave / stray from / get off / wander off X" avoids X, and negated ("don't stray from
the road", "never leave the trail") keeps to it; "cross X" alone says nothing, and negated is
the nocross rule ("avoid crossing", "try not to cross": a soft avoid).

Ordering words place entities relative to each other in steps of ``STEP``: "first X, then Y,
then Z" gives 0.10, 0.20, 0.30 (never reaching neutral); "X is better than Y" puts Y one step
above X (or X one step below Y, whichever was not stated outright).

Geometry: the table below, then a fallback on the head (last) word: roads, streets, paths,
tracks, rivers, streams, canals, ditches, railways, power lines, fences, walls and hedges are
``linear``; everything else is ``areal``.

Part-of hierarchy (child inside parent; the cost stage removes the child's mask from the
parent's): fields, lawns, parks, meadows and golf courses are inside ``grass``; rivers, lakes,
ponds, streams, creeks, canals, pools and reservoirs inside ``water``; highways, streets,
avenues, driveways and parking lots inside ``road``; paths, footpaths, walkways and bike paths
inside ``trail``; forests, woods and orchards inside ``tree``; houses, sheds, garages, barns and
warehouses inside ``building``. Electric towers (pylons), power lines, railways, fences, walls,
bridges, sand, mud, rock, snow and the like are entities of their own.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass
from itertools import product

from overseec_core.costlang import scale
from overseec_core.costlang.scale import NEUTRAL  # the one neutral level (unmentioned, "X is fine")
from overseec_core.schema import DEFAULT_ENTITIES, Geometry

# ----------------------------------------------------------------------------- weights
# The tiers' levels live in costlang.scale (one home for every cost level); the names here are
# the interpreter's. Avoided tiers keep these values as their cost levels (merge.cost_levels).
PREFER = scale.PREFER_LEVEL
FINE = NEUTRAL
TOLERABLE = scale.TOLERABLE_LEVEL
LAST_RESORT = scale.LAST_RESORT_LEVEL
AVOID = scale.AVOID_LEVEL
STRONG_AVOID = scale.STRONG_AVOID_LEVEL
LETHAL = scale.LETHAL_LEVEL
#: Distance between neighbours in an ordering ("first X, then Y"; "X is better than Y").
STEP = scale.ORDER_STEP
#: Highest weight an ordering may give (orderings stay on the preferred side of neutral).
ORDER_MAX = scale.ORDER_MAX_LEVEL
#: Distance in metres for "near X" / "unless near X" / "far from X" when the prompt gives none.
DEFAULT_CUE_DISTANCE_M = 10.0
#: Where a graded (soft) near/far cue with no number reaches neutral: "don't go near the water",
#: "stay close to the road", "the further the better" price distance over a reach that a route
#: across a scene actually feels (a 10 m band lets routes graze X and wander off a road).
DEFAULT_GRADED_DISTANCE_M = 40.0

#: Tier name -> (weight, lethal). ``nocross`` is a rule never to cross the entity ("do not cross
#: the railway"): strongly avoided, and a ``no_cross`` cue that makes it a keep-out zone (crossed
#: once, at the cheapest place, only when it separates the points).
TIERS: dict[str, tuple[float, bool]] = {
    "prefer": (PREFER, False),
    "fine": (FINE, False),
    "tolerable": (TOLERABLE, False),
    "last": (LAST_RESORT, False),
    "avoid": (AVOID, False),
    "avoid+": (STRONG_AVOID, False),
    "nocross": (STRONG_AVOID, False),
    "lethal": (LETHAL, True),
}
#: How strongly a tier speaks against an entity; when triggers stand together the highest wins
#: ("don't use" = avoid, "never use" = lethal).
SEVERITY = {"prefer": 0, "fine": 1, "tolerable": 2, "last": 2.5, "avoid": 3, "avoid+": 4, "nocross": 4.5, "lethal": 5}
#: Pseudo-tiers of verbs whose meaning depends on negation (see clauses._polarity): ``leave``
#: ("leave / stray from / get off X": avoid X; negated, "don't stray from X": stay on X) and
#: ``cross`` ("cross X": nothing by itself; negated, "do not / never cross X": the nocross rule).
VERB_TIERS = ("leave", "cross", "enter")


# ----------------------------------------------------------------------------- entities
@dataclass(frozen=True)
class Known:
    """One entity the offline interpreter knows by name."""

    name: str
    geometry: Geometry
    parent: str | None = None
    aliases: tuple[str, ...] = ()
    #: Extra text prompts for the segmenter (the name itself always comes first).
    prompts: tuple[str, ...] = ()


def _k(
    name: str, geometry: Geometry, parent: str | None = None, aliases: Iterable[str] = (), prompts: Iterable[str] = ()
) -> Known:
    return Known(name, geometry, parent, tuple(aliases), tuple(prompts))


_DEFAULT_ALIASES = {
    "road": ("roadway", "lane", "carriageway", "ring road"),
    # "dirt tracks" are trails; a bare "tracks" is the railway (see railway below)
    "trail": (
        "dirt trail",
        "hiking trail",
        "dirt track",
        "farm track",
        "forest track",
        "jeep track",
        "vehicle track",
    ),
    "grass": ("grassland", "grassy area", "grass area", "grass field", "grassy field", "grassy", "turf", "pasture"),
    "tree": ("tree canopy", "treeline", "tree line", "tree cover", "canopy", "canopy cover", "crown", "tree crown"),
    "building": ("structure", "built-up area"),
    "water": ("water body", "body of water", "waterbody", "open water"),
}

KNOWN: tuple[Known, ...] = tuple(
    _k(name, geom, None, _DEFAULT_ALIASES.get(name, ())) for name, geom in DEFAULT_ENTITIES
) + (
    # inside grass
    _k("baseball field", "areal", "grass", ("baseball diamond", "ballfield", "ball field", "baseball pitch")),
    _k("football field", "areal", "grass", ("football pitch",)),
    _k("soccer field", "areal", "grass", ("soccer pitch",)),
    _k("sports field", "areal", "grass", ("playing field", "sports pitch", "athletic field")),
    _k("lawn", "areal", "grass"),
    _k("park", "areal", "grass"),
    _k("meadow", "areal", "grass"),
    _k("golf course", "areal", "grass"),
    _k("field", "areal", "grass"),
    # inside water
    _k("river", "linear", "water", ("riverbed", "river bed", "watercourse", "waterway")),
    _k("stream", "linear", "water", ("brook",)),
    _k("creek", "linear", "water"),
    _k("canal", "linear", "water"),
    _k("lake", "areal", "water"),
    _k("pond", "areal", "water"),
    _k("swimming pool", "areal", "water", ("pool",)),
    _k("reservoir", "areal", "water"),
    # inside road
    _k("highway", "linear", "road", ("freeway", "motorway", "expressway")),
    _k("street", "linear", "road", ("avenue",)),
    _k("driveway", "linear", "road"),
    # qualified roads: a qualified word finds its own layer ("tarmac" the paved one, "gravel" the
    # unpaved one), a bare "road" every road layer (interpret.matching)
    _k(
        "paved road",
        "linear",
        "road",
        (
            "asphalt road",
            "pucca road",  # Indian English: a made (paved) road
            "pakka road",
            "tarred road",
            "tarmac",
            "tarmac road",
            "blacktop",
            "asphalt",
            "sealed road",
            "bitumen",
            "metalled road",
            "surfaced road",
            "concrete road",
            "macadam",
            "asphalted road",
            "tarred street",
            # the material after the road, as many languages put it ("the road of asphalt")
            "road of asphalt",
            "road of tarmac",
            "road of concrete",
        ),
    ),
    _k(
        "unpaved road",
        "linear",
        "road",
        (
            "dirt road",
            "gravel road",
            "gravel track",
            "unsealed road",
            "gravel",
            "unpaved track",
            "unsealed track",
            "gravel lane",
            "unsurfaced road",
            "unsurfaced track",
            "dirt lane",
            "earth road",
            "sand road",
            "kutcha road",  # Indian English: an unmade (unpaved) road
            "kuccha road",
            "kachcha road",
            "untarred road",
            "sandy road",
            "sand track",
            # the paved kind negated ("the not-paved road", "non-paved roads", "unasphalted")
            "not paved road",
            "non paved road",
            "nonpaved road",
            "unasphalted road",
            "unmetalled road",
            "road of earth",
            "road of dirt",
            "road of gravel",
            "road of sand",
            "road of soil",
            "road of clay",
        ),
    ),
    _k("parking lot", "areal", "road", ("car park", "parking area", "parking space", "parking")),
    # inside trail
    _k("path", "linear", "trail", ("dirt path", "pathway")),
    _k("footpath", "linear", "trail", ("foot path", "walkway", "footway")),
    _k("bike path", "linear", "trail", ("bicycle path", "cycle path", "cycleway", "bike trail")),
    _k("towpath", "linear", "trail", ("tow path", "bridleway", "bridle path")),
    # inside tree
    _k("forest", "areal", "tree", ("woods", "woodland")),
    _k("orchard", "areal", "tree"),
    # qualified trees: a conifer is a tree with a quality, like a paved road is a road
    _k(
        "conifer tree",
        "areal",
        "tree",
        (
            "conifer",
            "coniferous tree",
            "coniferous",
            "evergreen",
            "evergreen tree",
            "pine",
            "pine tree",
            "spruce",
            "fir",
            "fir tree",
            "larch",
            "cedar",
        ),
    ),
    _k(
        "deciduous tree",
        "areal",
        "tree",
        (
            "deciduous",
            "broadleaf",
            "broadleaf tree",
            "broadleaved tree",
            "hardwood",
            "hardwood tree",
            "oak",
            "oak tree",
            "maple",
            "maple tree",
            "birch",
            "beech",
        ),
    ),
    # inside building
    _k("house", "areal", "building", ("home", "dwelling", "residence", "cottage")),
    _k("shed", "areal", "building", ("outbuilding", "outhouse")),
    _k("garage", "areal", "building"),
    _k("barn", "areal", "building"),
    _k("warehouse", "areal", "building"),
    *(
        _k(n, "areal", "building")
        for n in ("greenhouse", "hut", "cabin", "shack", "hangar", "silo", "school", "church", "hospital", "factory")
    ),
    # entities of their own
    _k(
        "electric tower",
        "areal",
        None,
        (
            "electrical tower",
            "electricity tower",
            "transmission tower",
            "power tower",
            "pylon",
            "power pylon",
            "electricity pylon",
            "electric pylon",
            "lattice tower",
            "utility tower",
        ),
        ("electric tower", "transmission tower", "pylon"),
    ),
    _k(
        "power line",
        "linear",
        None,
        ("powerline", "transmission line", "electric line", "overhead line", "power cable"),
    ),
    # a bare "tracks" means the railway ("stay off the tracks"); "dirt/farm tracks" are trails
    _k(
        "railway",
        "linear",
        None,
        (
            "railroad",
            "rail track",
            "rail line",
            "branch line",
            "running line",  # a railway's lines in use ("the running lines"), as yard staff say
            "rail spur",
            "spur line",
            "train line",
            "train track",
            "railway track",
            "railroad track",
            "railway line",
            "tracks",
            "rails",  # "never on the rails themselves"
            "track bed",  # "it must not enter the track bed itself": the ballast the rails lie on
            "trackbed",
            "rail bed",
            "ballast",
        ),
    ),
    _k(
        "level crossing",
        "areal",
        None,
        ("railway crossing", "railroad crossing", "rail crossing", "grade crossing", "train crossing"),
        ("level crossing", "railroad crossing"),
    ),
    _k("crosswalk", "areal", "road", ("pedestrian crossing", "zebra crossing")),
    _k("sidewalk", "linear", None, ("pavement",)),
    _k("bridge", "linear"),
    _k("fence", "linear"),
    _k("wall", "linear"),
    _k("hedge", "linear", None, ("hedgerow",)),
    _k("ditch", "linear"),
    _k("pipeline", "linear"),
    _k("bush", "areal", None, ("shrub", "shrubland", "scrub", "brush")),
    _k("sand", "areal", None, ("sandy area",)),
    _k("beach", "areal"),
    _k("mud", "areal", None, ("muddy area",)),
    _k("rock", "areal", None, ("rocky area", "boulder")),
    _k("snow", "areal"),
    _k("bare soil", "areal", None, ("bare ground", "soil", "dirt", "bare earth")),
    _k(
        "open ground",
        "areal",
        None,
        ("open terrain", "open land", "open country", "open area", "offroad")
        + ("everything else", "anything else", "everywhere else"),  # "grass > everything else"
    ),
    _k("crop field", "areal", None, ("farmland", "cropland", "crops", "farm field", "agricultural field")),
    _k("wetland", "areal", None, ("marsh", "swamp", "bog")),
    _k("vegetation", "areal", None, ("greenery", "green area")),
    _k("playground", "areal"),
    _k("tennis court", "areal"),
    _k("basketball court", "areal"),
    _k("construction site", "areal"),
    _k("solar panel", "areal", None, ("solar farm",)),
    _k("car", "areal", None, ("parked car", "parked vehicle")),
)

KNOWN_BY_NAME: dict[str, Known] = {k.name: k for k in KNOWN}
#: Entities that are their parent with a quality (a paved road is a road), not a part of it (a
#: baseball field is in the grass, but is not grass): a layer of theirs answers to the parent's names.
QUALIFIED_KINDS = frozenset({"paved road", "unpaved road", "conifer tree", "deciduous tree"})

#: Nouns that are never terrain a costmap can hold (the mission's logistics: power, time,
#: photographs, samples, radio): never read as an entity, so a clause about them is reported as
#: not understood instead of segmenting "battery" or preferring "pics".
NON_TERRAIN = frozenset(
    """train trains battery batteries charge fuel sunset sunrise dusk dawn dark darkness daylight nightfall
    pic pics photo photos photograph photographs picture pictures footage video videos image images
    sample samples specimen specimens radio radios signal signals comms telemetry log logs report
    reports deliverable deliverables minute minutes hour hours percent payload camera cameras
    base hq headquarters lunch break noise tyre tyres tire tires wheel wheels motor motors
    weekend weekends week weeks weekday tomorrow tonight yesterday morning mornings afternoon
    evening evenings night nights monday tuesday wednesday thursday friday saturday sunday
    county council authority authorities police sheriff landowner landowners owner owners
    pdf pdfs file files email emails document documents spreadsheet invoice paperwork
    client clients customer customers boss manager crew team dog dogs
    game games match matches event events meeting meetings traffic site sites biggie
    worry worries concern concerns manner manners courtesy insurer insurers insurance overheat overheats
    rider riders lose loses losing speed speeds velocity kmh kph mph
    walker walkers pedestrian pedestrians equestrian equestrians cyclist cyclists resident residents
    visitor visitors public members staff people folk folks neighbour neighbours neighbor neighbors""".split()
)

#: One-word names of the qualified kinds ("deciduous", "gravel"): before another noun they
#: qualify it ("deciduous woodland", "conifer plantation") rather than name the kind alone.
QUALIFIER_WORDS = frozenset(a for k in KNOWN if k.name in QUALIFIED_KINDS for a in (k.name, *k.aliases) if " " not in a)

#: Nouns that, after a qualified kind's one-word name, still name that kind ("deciduous
#: woodland", "coniferous stands", "paved surface", "gravel lanes"): by the kind's parent.
QUALIFIED_HEADS: dict[str, frozenset[str]] = {
    "tree": frozenset(
        "tree trees stand stands cover canopy canopies crown crowns plantation plantations timber wood woods "
        "woodland woodlands forest forests belt belts".split()
    ),
    "road": frozenset("road roads surface surfaces track tracks lane lanes route routes way ways".split()),
}


def qualified_head(qualifier: str, head: str) -> str | None:
    """The qualified kind a qualifier word and the noun after it name together ("coniferous" +
    "stands" -> "conifer tree"), or None when the noun is not a head of the kind's parent."""
    for parent, heads in QUALIFIED_HEADS.items():
        # "coniferous" names the kind alone; "paved" only with its parent ("paved road")
        kind = SURFACE.get((qualifier,)) or SURFACE.get((singularise(qualifier),)) or SURFACE.get((qualifier, parent))
        if kind in QUALIFIED_KINDS and KNOWN_BY_NAME[kind].parent == parent and head in heads:
            return kind
    return None


#: Head words (last word of a name) that make an unknown entity linear.
LINEAR_HEADS = frozenset(
    {
        "road",
        "street",
        "highway",
        "trail",
        "path",
        "footpath",
        "track",
        "lane",
        "line",
        "river",
        "stream",
        "creek",
        "canal",
        "ditch",
        "railway",
        "railroad",
        "rail",
        "fence",
        "wall",
        "hedge",
        "pipeline",
        "cable",
        "route",
        "corridor",
        "sidewalk",
        "bridge",
        "avenue",
        "boulevard",
        "way",
    }
)


def pluralise(word: str) -> str:
    """English plural of a single word, good enough for the nouns in the entity table."""
    if word.endswith(("s", "x", "z", "ch", "sh")):
        return word + "es"
    if word.endswith("y") and len(word) > 1 and word[-2] not in "aeiou":
        return word[:-1] + "ies"
    return word + "s"


def singularise(word: str) -> str:
    """Inverse of :func:`pluralise` for unknown nouns ("puddles" -> "puddle")."""
    if len(word) <= 3 or word.endswith(("ss", "us", "is")):
        return word
    if word.endswith("ies"):
        return word[:-3] + "y"
    if word.endswith(("ches", "shes", "xes", "sses", "zes")):
        return word[:-2]
    if word.endswith("s"):
        return word[:-1]
    return word


def _forms(phrase: str) -> set[tuple[str, ...]]:
    words = tuple(phrase.replace("-", " ").split())
    return {words, words[:-1] + (pluralise(words[-1]),)}


def _surface_table() -> dict[tuple[str, ...], str]:
    table: dict[tuple[str, ...], str] = {}
    for known in KNOWN:
        for phrase in (known.name,) + known.aliases:
            for form in _forms(phrase):
                table.setdefault(form, known.name)
    return table


#: Word sequence (singular or plural) -> canonical entity name.
SURFACE: dict[tuple[str, ...], str] = _surface_table()
MAX_SURFACE_WORDS = max(len(k) for k in SURFACE)
#: The surfaces that are an entity's own name (singular or plural); any other surface is an
#: alias, and the interpreter notes how it read it ("read 'woods' as 'forest'").
NAME_FORMS: frozenset[tuple[str, ...]] = frozenset(f for known in KNOWN for f in _forms(known.name))


def geometry_of(name: str) -> Geometry:
    """Geometry of an entity name: from the table, else from its head (last) word."""
    known = KNOWN_BY_NAME.get(name)
    if known:
        return known.geometry
    words = name.split()
    if words:
        for n in range(len(words) - 1, 0, -1):  # "dirt road" -> "road"
            tail = SURFACE.get(tuple(words[-n:]))
            if tail:
                return KNOWN_BY_NAME[tail].geometry
        if singularise(words[-1]) in LINEAR_HEADS:
            return "linear"
    return "areal"


def parent_of(name: str) -> str | None:
    """Part-of parent of an entity name: from the table, else from a known tail.

    "dirt road" is inside "road"; "muddy baseball field" is inside what "baseball field" is
    inside ("grass"); a compound whose tail has no parent ("concrete bridge") has none either.
    """
    known = KNOWN_BY_NAME.get(name)
    if known:
        return known.parent
    words = name.split()
    for n in range(len(words) - 1, 0, -1):
        tail = SURFACE.get(tuple(words[-n:]))
        if tail:
            if tail in dict(DEFAULT_ENTITIES):
                return tail
            return KNOWN_BY_NAME[tail].parent
    return None


def prompts_of(name: str) -> tuple[str, ...]:
    """Text prompts for the segmenter: the name, then any extra prompts from the table."""
    known = KNOWN_BY_NAME.get(name)
    extra = known.prompts if known else ()
    out = [name] + [p for p in extra if p != name]
    return tuple(out)


# ----------------------------------------------------------------------------- phrase tables
# The offline interpreter's grammar (:mod:`.offline` and the modules it names hold the rules that read it).


def _expand(pattern: str) -> list[tuple[str, ...]]:
    """'can (go|pass) (under|below)' -> every combination as a word tuple ('_' = nothing)."""
    parts = re.findall(r"\([^)]*\)|\S+", pattern)
    choices = [p[1:-1].split("|") if p.startswith("(") else [p] for p in parts]
    out = []
    for combo in product(*choices):
        words = tuple(w for c in combo for w in c.split() if w != "_")
        out.append(words)
    return out


def _table(entries: Iterable[tuple[str, object]]) -> dict[str, list[tuple[tuple[str, ...], object]]]:
    """Phrase table keyed by first word, longest phrase first."""
    table: dict[str, list[tuple[tuple[str, ...], object]]] = {}
    for pattern, payload in entries:
        for words in _expand(pattern):
            table.setdefault(words[0], []).append((words, payload))
    for cands in table.values():
        cands.sort(key=lambda c: -len(c[0]))
    return table


MOVE = (
    "(go|pass|drive|walk|travel|move|fly|overfly|ride|cross|navigate|wade|slog|trudge|swim|climb|hike|"
    "run|roll|head|proceed|cut|venture|traverse|enter|use|get|take|route|steer)"
)
#: Prepositions of passage after a movement verb ("wade through", "go over"); not "around",
#: which means going round it.
PASSAGE = "(under|beneath|below|underneath|over|through|across|on|along|into|in|onto|past|_)"
#: Permission: a modal or "ok/free to" before a movement verb ("you can wade through the water",
#: "it's ok to drive through", "feel free to go over"): no objection, i.e. neutral (fine).
PERMIT = (
    "(can|may|could|might|ok to|okay to|fine to|free to|alright to|safe to|allowed to|clear to|"
    "permitted to|welcome to|acceptable to|feel free to|go ahead and|cleared to|authorised to|authorized to|"
    "approved to|good to|permission to|authorisation to|authorization to|approval to|clearance to|the go ahead to)"
)
#: Concealment: travelling hidden by something ("stay under the trees", "stay hidden in the
#: forest", "under cover of the trees") is a preference for it.
CONCEAL = [
    "(stay|keep|remain|hide|hiding|stay hidden|keep hidden|remain hidden) (under|beneath|underneath|below)",
    "(go|walk|drive|travel|pass|head|move|ride|run|roll|cycle) (under|beneath|underneath)",  # "go under the oaks"
    "(go|walk|drive|travel|pass|head|move) (under|beneath|underneath) (the|_) cover of",
    "(hidden|concealed|sheltered|unseen|out of sight|take cover|hide|hiding|"
    "stay covered|keep covered|remain covered) "
    "(in|under|beneath|underneath|among|amongst|inside|within|behind|by)",
    "(under|in|using|use|with|keep|stay in|stay under|remain under|remain in) (the|_) cover of",
    "(stay|keep|remain) in the (shade|shadow|shadows) of",
    "under the canopy of",
    "hug",
    "hugs",
    "hugging",
]
#: Ground no layer labels ("paved road > unpaved road > off-road", "roads > open ground >
#: scrub"): in an ordering it stands at neutral, so what ranks above it is preferred and what
#: ranks below it avoided (:func:`interpret.statements.resolve_weights`).
UNLABELLED_GROUND = frozenset({"open ground"})
#: Going cross-country: read as a preference for the terrain named ("go cross-country through
#: the vegetation"). Claimed before entities, so "country" or the "road" in "off-road" is never
#: taken for a name.
CROSS_COUNTRY = [
    "(cross|across) country (through|over|across|via|on|in|into|along|_)",
    "(off road|offroad|off roads|off trail|off trails|overland) (through|over|across|via|on|in|into|along)",
    "(off trail|off trails|overland)",
    "off the beaten (track|path|trail) (through|over|across|via|on|in|into|along|_)",
]
TRIGGERS = _table(
    [
        (p, "prefer")
        for p in (
            "prefer",
            "prefers",
            "preferred",
            "preferably",
            "by preference",  # "use the road by preference"
            # "preference should be given to X", "give priority to X"
            "preference should be given to",
            "preference is given to",
            "preference given to",
            "give preference to",
            "priority should be given to",
            "priority is given to",
            "give priority to",
            "want",
            "wants",
            "take",
            "takes",
            "taking",
            "would like",
            "i'd like",
            "preferable",
            "best",
            "the best",
            "cheap",
            "cheapest",
            "low cost",
            "ideal",
            "ideally",
            # terse verdicts after a name or a colon ("roads good", "trail: yes", "tracks are nice")
            "good",
            "nice",
            "great",
            "yes",
            "excellent",
            "perfect",
            "stay on",
            "stay in",
            "stay within",
            "(stick|sticks|sticking) (to|with)",
            # "operation shall be confined to paved roads": where the route may go is where it goes
            "(confined|restricted|limited) (to|on)",
            "(keep|keeps) to",
            "keep on",
            "remain on",
            "use",
            "using",
            "favour",
            "favor",
            "favoured",
            "favored",
            "great",
            "excellent",
            "optimal",
            "desirable",
            "most desirable",
            "go for",
            "choose",
            "pick",
            "prioritise",
            "prioritize",
            "priority",
            "top priority",
            "(drive|walk|travel|move|go|ride|head|hike|run|roll|proceed|continue|cycle|march|fly|traverse) (on|along)",
            "follow",
            "stay along",
            "first choice",
            "(our|the|your|my) best (bet|option|choice)",
            "(is|'s|are|_) your (best|_) (friend|friends)",  # "Trail's your friend"
            "(we|i) (still|really|do|_) need",  # "we need the trail after all"
            # "over the road it likes to drive": the way it likes to go
            "(likes|like|loves|love|prefers|enjoys) (to|_) (drive|driving|go|going|travel|travelling|ride|riding|"
            "run|running|roll|rolling|walk|walking|move|moving)",
            # an order's heading of the way to go ("Axis of advance: road", "Line of march: the ridge")
            "(axis|axes|line|lines|route|direction) of (advance|march|movement|travel|approach)",
            "ply",
            "instead",
            # what the travellers like: "the horses go sweetest on the trail", "they love the trail"
            "(go|goes|going|run|runs|ride|rides) (sweetest|happiest|easiest|smoothest) (on|along|over)",
            "(love|loves|adore|adores|enjoy|enjoys) (the|a|an|our|their|his|her|that|those|these)",
            *CONCEAL,
            "(go|drive|walk|travel|move|head|cut|ride|route|pass|proceed) (through|across|over|via|into)",
        )
    ]
    + [
        (p, "fine")
        for p in (
            "fine",
            "neutral",
            # use as it is needed: allowed ("mowed grass may be used as needed", "VEGETATION ... AS REQUIRED")
            "as (needed|required)",
            "okay",
            "ok",
            "acceptable",
            "alright",
            "all right",
            "(is|are) grand",  # "paved is grand": fine, as said in Ireland and Britain
            # no concern: "don't worry about the water", "the sheds are nothing to worry about"
            "(don't|do not|no need to|needn't|never|dont) (worry|bother|fret) (about|over|with)",
            # "don't you go worrying about it", "don't fuss about the trees"
            "(don't|do not|dont) (you|_) (go|_) (worrying|bothering|fretting|fussing|stressing) (about|over)",
            "(don't|do not|dont|no need to|needn't) (fuss|stress) (about|over)",
            "(is|are|'s|'re) nothing to worry about",
            "(is|are|'s|'re) fair game",
            # indifference: "I don't mind the trees", "not fussed about the buildings", "the
            # buildings don't matter", "the vegetation won't hurt ya", "not that I care about X"
            "(don't|do not|dont|doesn't|does not|didn't|won't|wouldn't|never) (mind|matter|matters)",
            "(don't|do not|dont|doesn't|does not|won't|will not|wouldn't|can't|cannot) (hurt|harm|bother) "
            "(ya|you|us|me|it|anyone|anybody|_)",
            "(not|never|nor|n't) (too|that|very|overly|really|much|_) (bothered|fussed|worried|concerned|fussy|"
            "picky|precious) (about|by|with|over|_)",
            "(not that|don't|do not|dont|couldn't|could not) (i|we|_) (really|_) care (much|less|_) (about|for|_)",
            "(is|are|'s|'re) (irrelevant|immaterial|unimportant|of no concern|of no consequence|of no importance)",
            "(makes|make|making) no difference",
            "(is|are) not (a|an) (concern|problem|issue|worry)",
            "(need|needs) not be avoided",
            "(treat|treated) (it|them|this|that|_) (like|as) (any other|ordinary|normal|regular|plain) "
            "(ground|terrain)",
            "(sparse|open|thin|dry|shallow|firm|solid|low|wide) enough to (drive|walk|go|pass|get|ride|roll|fly|cross) "
            "(through|over|across|under|_)",
            "(is|are) to be used",
            "(should|may|can|could) (only|_) be used",
            # "just go straight over it": the direct way allowed, not sought out
            "(go|drive|walk|head|cut|ride|run|roll) straight (through|across|over|into)",
            "(do|does|don't|doesn't|do not|does not) (not|_) (need|have) to be avoided",
            "(is|are) no (concern|problem|issue|worry)",
            # equal treatment: neither is preferred, so both are neutral ("road and grass are
            # to be treated alike, with neither preferred over the other")
            "(treated|regarded|priced|costed) (alike|equally|the same)",
            "(are|is) (equal|equivalent|alike)",
            "(neither|none) (preferred|favoured|favored) (over|to) the other",
            "(neither|none) (preferred|favoured|favored)",
            "allowed",
            "permitted",
            "permissible",
            "passable",
            "traversable",
            "drivable",
            "driveable",
            "walkable",
            "usable",
            "no problem",
            "not a problem",
            "no worries",  # "the bush and the grass are no worries"
            "unrestricted",  # "road use is unrestricted"
            # "running on it carries no penalty"
            "(carry|carries|incur|incurs|attract|attracts) no (penalty|cost|surcharge|extra cost)",
            "authorised",  # "OVERFLIGHT OF TREES AND WATER: AUTHORISED"
            "authorized",
            # "buildings are no longer a constraint following the demolition"
            "(is|are) no longer (a|an|any) (constraint|problem|issue|hazard|obstacle|concern|restriction)",
            "no longer (a|an|any) (constraint|problem|issue|hazard|obstacle|concern|restriction)",
            # "no other restrictions apply to vegetation"
            "no (other|further|_) (restriction|restrictions|constraint|constraints) (apply|applies) (to|on)",
            # "the trees pose no issue", "no concern with the sheds": no objection
            "(pose|poses|posing|present|presents|cause|causes|is|are|be) (no|not a|not an) "
            "(issue|issues|problem|problems|risk|threat|hazard|concern|obstacle)",
            "no (issue|issues|concern|concerns|objection) (with|about|for|_)",
            # "building footprints impose no constraint on the route", "the fences are no constraint"
            "(impose|imposes|place|places|put|puts|pose|poses|is|are|be) (no|not a|not any) "
            "(constraint|constraints|restriction|restrictions|limit|limits|limitation|limitations)",
            "allow",
            "permit",
            "not bad",
            "good",
            "safe",
            "dry",
            "dried up",
            "frozen",
            "shallow",
            # states that take a hazard's danger away ("the railway is disused", "empty ruins")
            "disused",
            "abandoned",
            "derelict",
            "unused",
            "decommissioned",
            "out of use",
            "out of service",
            "inactive",
            "de-energised",
            "de-energized",
            "unoccupied",
            "vacant",
            "empty",  # "them sheds out yonder are empty"
            f"{PERMIT} {MOVE} {PASSAGE}",
            "(can|may|could|might) be (used|crossed|entered|driven on|followed|walked|crossed or followed|traversed|"
            "travelled|traveled|driven|walked on|passed|crossed freely|used freely)",
            "(at|with) (normal|standard|default|usual|ordinary|baseline|neutral) cost",
            "you may cross",
        )
    ]
    + [(p, "last") for p in ("last resort", "final resort", "last option", "last choice", "final option")]
    + [
        (p, "tolerable")
        for p in (
            "tolerable",
            "tolerated",
            "tolerate",
            "(put|puts|putting) up with",  # "they'll put up with grass"
            "(will|would|'ll) do",  # "the gravel road'll do": it serves, grudgingly
            "(live|lives|cope|copes) with",
            "less preferred",
            "less preferable",
            "not ideal",
            "not great",
            "meh",  # "grass ok / road meh": no enthusiasm, a little worse than fine
            "so so",
            "not preferred",
            "not the best",
            "less desirable",
            "second choice",
            "fallback",
            "minimise",
            "minimize",
            "(kept|keep|keeping|be kept) to a minimum",
            "(is|are|be) (minimised|minimized)",
            "to a minimum",
            "limit",
            "least preferred",
            "lowest priority",
            "backup",
            "back up option",
            "emergency option",
        )
    ]
    + [
        (p, "avoid")
        for p in (
            "hard going",  # "grass is hard going" (not "heavy": "heavy next to it" restates a fall-off)
            # "the road tiles themselves carry a heavy penalty"
            "(carry|carries|incur|incurs) (a|an|_) (penalty|cost|surcharge)",
            # a price said as a noun: "a small penalty for the grass", "grass: penalty"
            "(a|an|_) (small|slight|light|mild|minor|modest|some) (penalty|cost|surcharge) (for|on|_)",
            "(penalty|penalties|surcharge) (for|on)",
            "penalties",  # a configuration's section of things penalised: penalties = {"building": ...}
            "avoid",
            "avoids",
            "avoided",
            "avoiding",
            "stay away from",
            "keep away from",
            "stay off",
            "keep off",
            # the wish's past tense: "I'd rather it stayed off the grass", "it kept mostly off there"
            "(stayed|kept) (off|away from|out of|clear of)",
            "(stay|keep) of",  # "keep of the raod": a slip for "keep off" ("of" after them is no English)
            "(is|are|'s|be) reserved (for|to)",  # "the unpaved roads are reserved for equestrian use"
            "don't",
            "do not",
            "dont",
            "should not",
            "shouldn't",
            "not",
            "no",
            "nobody",
            "no one",
            "steer clear of",
            "stay clear of",
            "skip",  # "skip the asphalt"
            "give (it|them|_) a miss",
            # allowed at a price: "unpaved road permitted with penalty"
            "(permitted|allowed|ok|okay|fine|acceptable) (with|at) (a|an|some|_) (penalty|cost|surcharge)",
            # caution: "mind the water", "watch out for the ditch", "be careful around the pylons"
            "mind",
            "(watch|look|mind) out for",
            "beware (of|_)",
            "(be|_) (careful|wary|cautious) (of|with|around|near|about)",
            "keep clear of",
            "bad",
            "dangerous",
            "fragile",
            "unsafe",
            "risky",
            "hazardous",
            "undesirable",
            "dislike",
            "dislikes",
            # "they hate the road", "the mare can't stand the tarmac"
            "(hate|hates|loathe|loathes|detest|detests)",
            "(can't|cannot|can not|couldn't) (stand|abide|bear)",
            "expensive",
            "costly",
            "not okay",
            "not ok",
            "not acceptable",
            "not fine",
            "not safe",
            "not good",
            "refrain from",
            "try not to",
            "difficult",
            "hard to cross",
            # "the pine stands are way too dense", "the tarmac gets too hot": unfit for the mission
            # (the adjective after "too" is read with it: sentence.UNFIT_ADJECTIVES)
            "(is|are|was|were|be|get|gets|getting|becomes|become) (way|much|far|just|a bit|bit|_) too",
            # harm to the vehicle ("that gravel road'll chew the tires right up")
            "(will|would|could|might|can|'ll) (chew|wreck|ruin|destroy|shred|damage|tear|rip|eat|break|bog)",
            "isn't",
            "aren't",
            "won't",
            "wouldn't",
            "doesn't",
            "wasn't",
            f"{PERMIT} {MOVE} around",
            f"{MOVE} around",
            f"{MOVE} round",  # "go round the water" (British)
            "detour around",
            "detour round",
            "skirt",
            "skirt around",
            "skirt round",
            "bypass",
        )
    ]
    + [
        (p, "leave")
        for p in (
            "leave",
            "leaves",
            "leaving",
            "(stray|strays|straying|wander|wanders|wandering|drift|drifts|drifting|veer|veers|veering) "
            "(from|off|away from|off of|_)",
            "(go|goes|going|get|gets|getting|come|comes|coming|step|steps|stepping|move|moving|wander|"
            "wandering|drive|driving) (out of|out from|away from)",
            "(deviate|deviates|deviating|depart|departs|departing|diverge|diverging) (from|_)",
            "(get|gets|getting|go|goes|going|step|steps|stepping|come|comes|coming|move|moving|"
            "turn|turning|run|running|pull|pulling|drive|driving) off",
            "(get|go|step|come|move|turn|run|drive) off of",
        )
    ]
    + [
        # a heavy price said as a noun: "a heavy penalty for the grass", "water: stiff penalty"
        (p, "avoid+")
        for p in (
            "(a|an|_) (heavy|big|large|stiff|steep|severe|huge|massive|hefty|high) (penalty|penalties|cost|surcharge) "
            "(for|on|_)",
        )
    ]
    + [(p, "cross") for p in ("cross", "crosses", "crossing", "cross over")]
    + [
        # straying *onto* something enters it: "should not stray onto the farmland" avoids it
        (p, "enter")
        for p in (
            "(stray|strays|straying|wander|wanders|wandering|drift|drifts|drifting|veer|veers|veering) "
            "(onto|into|on to|in to)",
            "(encroach|encroaches|encroaching|intrude|intrudes|intruding) (on|upon|into|onto)",
        )
    ]
    + [
        (p, "lethal")
        for p in (
            "never",
            # "it's not to go into the buildings": an order, as "must not"
            "(is|are|'s|it's|its) not to (go|enter|drive|cross|come|get|touch|set)",
            "(don't|do not|dont) (you|ya|ye|_) dare",  # "don't you dare put it in the pond"
            "forbidden",
            "verboten",  # "water verboten"
            "prohibited",
            "impassable",
            "off limits",
            "(is|are) closed (to|for) (us|the|our|all|any|vehicles|traffic)",
            "out of bounds",
            "not allowed",
            "not permitted",
            "not authorised",  # "OVERFLIGHT OF BUILDINGS IS NOT AUTHORISED"
            "not authorized",
            "unauthorised",
            "unauthorized",
            "deny",  # {"building": "deny"}
            "denied",
            "must not",
            "mustn't",
            "must never",
            # a regulation's "shall not" forbids as "must not" does ("the route shall not enter the water")
            "shall not",
            "shan't",
            "shall never",
            "cannot",
            "can't",
            "can not",
            "may not",
            "no go",
            "no entry",
            "do not enter",
            "forbid",
            "forbids",
            "don't enter",
            # staying out of a place entirely forbids it ("stay out of the marsh", "keep out of X",
            # "don't go into X"); "stay away from X" / "keep off X" stay a plain avoid
            "(stay|keep|keeping|staying|remain|remaining|get) out of",
            "(stay|keep|remain) out",  # "building: keep out", "baseball field - stay out"
            "(don't|do not|dont|never|must not|mustn't|shouldn't|should not) "
            "(go|goes|going|drive|walk|venture|step|get|move|head|travel|ride) (into|inside|in to|in)",
            "under no circumstances",
            # "nobody goes into the water": the rule said of everyone
            "(nobody|no one|noone|none of us) (goes|go|drives|walks|steps|gets|ventures|wades) (into|in|inside|onto)",
            # the passive forbids as the active does: "the field is not to be entered"
            "not to be entered",
            "(must|may|shall|should|cannot|can't) not be entered",
            # "the unpaved road shall not be used", "the pitch is not to be used"
            "not to be used",
            "(must|may|shall|cannot|can't) not be used",
            "(must|may|shall) never be used",
            "(must|may|shall|should) never be entered",
            "lethal",
            "deadly",
            "impossible",
            "not passable",
            "not traversable",
            "obstacle",
            "obstacles",
            "untraversable",
            "no way",
        )
    ]
)

#: Trigger phrases that negate the verb they stand with (clauses._polarity): "don't stray
#: from the road" is staying on it; "never cross the railway" is the nocross rule.
NEGATORS = frozenset(
    tuple(p.split())
    for p in (
        "don't",
        "do not",
        "dont",
        "should not",
        "shouldn't",
        "not",
        "no",
        "nobody",
        "never",
        "must not",
        "mustn't",
        "must never",
        "shall not",
        "shan't",
        "shall never",
        "cannot",
        "can't",
        "can not",
        "may not",
        "won't",
        "wouldn't",
        "doesn't",
        "not allowed",
        "not permitted",
        "under no circumstances",
        "refrain from",
        "try not to",
        "avoid",
        "avoids",
        "avoiding",
    )
)
#: Negators that make a wish, not a rule ("avoid crossing", "try not to cross": a soft avoid).
SOFT_NEGATORS = frozenset({("avoid",), ("avoids",), ("avoiding",), ("try", "not", "to")})

IDIOMS = _table(
    [(p, "prefer") for p in CROSS_COUNTRY]
    # "it goes only by the asphalted road": the one way it travels (claimed before "only" is
    # read as a condition)
    + [(p, "prefer") for p in ("(go|goes|drive|drives|travel|travels|run|runs|move|moves) only (by|via|on|along)",)]
    # ground in a state that makes it bad going ("the grass is muddy today"); an idiom, so the
    # adjective stays a word of names elsewhere ("the muddy canal")
    + [
        (p, "avoid")
        for p in (
            "(is|are|'s|'re|gets|get|will be|looks|seems) (very|really|too|quite|pretty|_) "
            "(muddy|boggy|soggy|waterlogged|sodden|slippery|slick|icy|swampy|marshy|treacherous|unstable)",
        )
    ]
    + [
        (p, "polite")
        for p in (
            # politeness around a request carries no preference ("it would be great if you could ...")
            "(it|that) (would|will|'d|_) (be|is) (great|nice|helpful|good|appreciated|wonderful) (if|_)",
            "it'd be (great|nice|helpful|good|appreciated|wonderful) (if|_)",
            "(try|do) your (best|utmost) (to|_)",
            "would be appreciated",
            # discourse markers: how the writer links rules, never a rule ("by contrast, the
            # trail is to be favoured", "avoid the water as a matter of course")
            "(as|_) a matter of course",
            # the purpose of a rule ("hug the walls for cover"), never terrain of its own
            "for (cover|concealment|shelter|safety reasons)",
            "(by|in) contrast",
            "on the other hand",
            "(of|as a matter of) course",
            "needless to say",
            "for the record",
            "all things considered",
            "by the way",
            "after all",
            # a time said with "last" is no step of a sequence ("decommissioned last year")
            "last (year|week|month|night|time|summer|winter|autumn|spring|season|weekend|winter's)",
        )
    ]
    + [
        (p, "slack")
        for p in (
            # "give them room, but dont go crazy over it": the rule is not to be overdone
            "(don't|dont|do not) go (crazy|overboard|mad|nuts) (over|about|with) (it|this|that)",
            "(don't|dont|do not) go (crazy|overboard|mad|nuts)",
            # "if you can manage, keep ...", "closer is allowed when there's no other way through"
            "(if|where|when) (you|we|it) (can|could) (manage|manage it|be managed)",
            "(going|getting|coming|_) (closer|nearer) (is|are|'s|would be) (allowed|ok|okay|fine|acceptable|"
            "permitted|tolerated)",
            # a rule's slack, said as chat ("but its not the end of the world if you cut a bit
            # closer"): it names no terrain and softens the sentence's distance rule
            "(it's|its|it is|that's|thats|that is) not the end of the world",
            "(if|when) you cut (a bit|it|_) (closer|close)",
            "no (biggie|big deal|drama|worries)",
            "(that one|this one|it|that|this) (isn't|is not) (critical|crucial|essential|vital|a must)",
            "not a big deal",
            "(if|when) (you|we|it|a route|the route|the path|the robot|the rover) (can't|cannot)",
            "(if|where|when) (you|we|a route|the route|the path|the robot|the rover) (can|could)",
        )
    ]
    + [
        # emphasis that names no terrain ("nothing within 12 m of the track, full stop"); the
        # sentence's absolute wording (ABSOLUTE_PHRASES) reads it
        (p, "emphasis")
        for p in (
            "full stop",
            "period",
            # "this is the red line", "that's my bottom line": the rule before it is absolute
            "(this|that|it) (is|'s) (the|a|my|our) (red|bottom|hard) line",
            "(this's|that's|it's) (the|a|my|our) (red|bottom|hard) line",
            "(this|that|it) (is|'s) (a|the) (deal breaker|dealbreaker|hard limit)",
            "(that's|it's) (a|the) (deal breaker|dealbreaker|hard limit)",
            "end of story",
            "end of discussion",
            "no two ways about it",
            "(do not|don't|never) (relax|soften|bend|waive) (it|this|that|_)",
            "not negotiable",
            "no (waiver|waivers|exemption|exemptions) (will|shall|can) be (granted|given|made)",
            "non negotiable",
        )
    ]
    + [
        # a topic's lead ("Looking at the railway: costs climb ...", "As for the water: ..."):
        # it names what the sentence is about, no rule of its own
        (p, "polite")
        for p in (
            "as for",
            "as regards",
            "regarding",
            "concerning",
            "looking at",
            "(with|in) (regard|regards|respect) to",
            "speaking of",
            "on the subject of",
        )
    ]
    + [
        # availability: a rule for where a thing is, which the costmap keeps by itself ("if
        # there's a road, take it"; "if the trail goes where we're headed, use it"; "follow the
        # road whenever it heads our way"); the condition word before the verb is read with it
        (p, "available")
        for p in (
            "(if|where|when|wherever|whenever) (there is|there's|there are|there're|there be) (a|an|any|some|_)",
            "(goes|go|heads|head|runs|run|leads|lead) (where we're headed|where we are headed|where we're going|"
            "where we are going|our way|the right way|in our direction|in the right direction|"
            "the way we're going|the way we are going)",
        )
    ]
    + [
        # alternatives that open with a condition word (an "alt" marker, claimed before the
        # conditions): "if there isn't, cut across ...", "only if neither works, go over the grass"
        (p, "alt")
        for p in (
            "(only|_) (if|when|where) (there isn't|there is not|there aren't|there are not|there is none|"
            "there's none|there is no such)",
            "(only|_) (if|when) (neither|none|nothing|that|it) (works|work|does|do|fails|is available|exists)",
            "(only|_) (if|when) (that|it) (doesn't|does not|won't) work",
        )
    ]
    + [
        (p, "traveller")
        for p in (
            # the route itself named as a path or line: the traveller, never a trail to prefer
            "(flight|planned|preferred|chosen|proposed|planning|survey|travel|transit|patrol) (path|paths|line|lines)",
        )
    ]
)
OFF_VERBS = {"stay", "keep", "get", "staying", "keeping", "getting", "remain", "steer"}
#: Words between a subject and a near cue that make the cue its predicate ("the path may come
#: within 20 m of the water", "the unit is required to keep within sight of the trail"): the
#: subject is the route, not a thing whose preference applies near the cue's object.
PREDICATE_WORDS = OFF_VERBS | {"may", "must", "shall", "should", "will", "can", "come", "comes", "go", "goes"}
PREDICATE_WORDS |= {"has", "have", "needs"}  # "the cable trench has to run between 5 and 10 m from the road"
#: Names of the route itself that are also names of terrain ("the track would stay 25 m from
#: the railway", "the path may not come within 20 m of the water"): as the subject of a modal
#: and a keeping or moving verb they are the route, not a track or path to prefer.
ROUTE_NOUNS = frozenset({"track", "path", "route", "line", "course"})
MODALS = frozenset({"may", "must", "shall", "should", "will", "would", "can", "could", "might"})
ROUTE_VERBS = OFF_VERBS | {"come", "go", "run", "pass", "get", "travel", "move", "approach", "hold", "not", "never"}

MODIFIERS = _table(
    [
        (p, "freely")
        for p in (
            "freely",
            "at will",
            "without restriction",
            # "ride under the deciduous trees all you like": allowed, as often as wanted
            "(all|as much as|as often as) (you|they|it|we) (like|likes|want|wants|please|pleases)",
        )
    ]
    + [
        (p, "strong")
        for p in (
            "as much as possible",
            "as much as you can",
            "altogether",  # "keep out of the water altogether"
            "whenever possible",
            "wherever possible",
            "whenever you can",
            "wherever you can",
            "if at all possible",
            "strongly",
            "strictly",
            "definitely",
            "really",
            "absolutely",
            "completely",
            "totally",
            "entirely",
            "by all means",
        )
    ]
    + [
        (p, "lethal")
        for p in (
            "at all costs",
            "at all cost",
            "at any cost",
            "whatever happens",
            "no matter what",
            "under any circumstances",
        )
    ]
    + [
        (p, "tolerable")
        for p in (  # qualify the whole clause: "use trees only if necessary"
            "if needed",
            "if necessary",
            "if you must",
            "if you have to",
            "if required",
            "when necessary",
            "when needed",
            "sparingly",
            "in a pinch",
            "as a fallback",
            "reluctantly",
            "only if needed",
            "only if necessary",
            "only when necessary",
            "only when needed",
            "(only|_) (if|when) (you|we) (must|have to|need to|really must|really have to|really need to)",
            "(only|_) (if|when) (absolutely|really|strictly|truly) (necessary|needed|required)",
            "(only|_) (if|when) (it is|it's|its) (necessary|needed|unavoidable)",
            "(only|_) (if|when) (it|this|that) (has|needs) to (be|_)",  # "trail if it has to be"
            "(only|_) (if|when) unavoidable",
            # "trees only if stuck", "when you're stuck": the ground used when nothing else goes
            "(only|_) (if|when) (you're|you are|we're|we are|it's|it is|_) (stuck|stranded|boxed in|cornered)",
            "(in the|at|in|_) worst case",
            "in the worst case scenario",
            "as a backup",
        )
    ]
    + [
        (p, "last")
        for p in (  # the worst ground still used: dearer than what is used "if needed"
            "as (a|the) (last|final) (resort|option|choice)",
            "(if|when) all else fails",
            "(only|_) in (an|_) (emergency|emergencies)",
            "(only|_) (if|when) there is no other (way|option|choice|route|way around)",
            "(only|_) if no other (option|way|choice|route) (is there|is available|_)",
            # "unpaved road only when nothing else gets through"
            "(only|_) (if|when|where) nothing else (works|will do|gets through|goes through|fits|is possible)",
            "(only|_) (if|when|where) nothing else (connects|joins up|links up|goes)",
            "(only|_) (if|when|where) nothing else (gets|will get|can get) (you|us|it|me|them) (there|through)",
        )
    ]
    + [
        (p, "soft")
        for p in (
            "if possible",
            "when possible",
            "where possible",
            "if poss",
            "where poss",
            "if practicable",
            "where practicable",
            "if feasible",
            "where feasible",
            "if it can be managed",
            "where it can be managed",
            "if you can",
            "when you can",
            "(where|when|if|wherever|whenever) (it's|it is|that's|that is) (easy|convenient|practical|cheap|simple)",
            "a bit",
            "if you want",
            "if you like",
            "if you wish",
            "if you prefer",
            "somewhat",
            "slightly",
            "generally",
            "mostly",
            "a little",
        )
    ]
)

COMPARATORS = _table(
    [
        (p, "better")
        for p in (
            "better than",
            "preferable to",
            "preferred to",
            "preferred over",
            "more preferable than",
            "more preferred than",
            "safer than",
            "nicer than",
            "rather than",
            "instead of",
            "superior to",
            "more desirable than",
            "easier than",
        )
    ]
    + [
        (p, "worse")
        for p in (
            "worse than",
            "less preferable than",
            "less preferred than",
            "less desirable than",
            "riskier than",
            "more dangerous than",
            "inferior to",
            "not as good as",
            "less safe than",
            "harder than",
        )
    ]
    + [
        (p, "equal")
        for p in (
            "as good as",
            "same as",
            "the same as",
            "equal to",
            "equivalent to",
            "as bad as",
            "just like",
            "as fine as",
        )
    ]
)
#: "prefer X over Y" / "prefer X to Y": these only compare after a preference verb, or, for
#: "over", between two entities ("gravel over grass over sand").
SOFT_COMPARATORS = {
    "over": "better",
    "to": "better",
    # symbols and orderings between two entities: "trail > meadow > marsh", "A >> B", "tarmac
    # before gravel tracks", "sand < mud"
    ">": "better",
    ">>": "better",
    ">>>": "better",
    "before": "better",
    "beats": "better",
    "<": "worse",
    "<<": "worse",
}
#: Of those, the ones that compare only when they stand between two entities.
BETWEEN_COMPARATORS = frozenset({"over", ">", ">>", ">>>", "before", "beats", "<", "<<"})
#: "I'd rather take X than Y" / "sooner X than Y": the first word opens a split comparison that
#: "than" closes.
RATHER_WORDS = {"rather", "sooner", "better"}
#: Verbs of passage skipped between "than" and the entity it compares ("than go through Y").
PASSAGE_VERBS = frozenset(
    """take use go drive walk ride cross wade travel head pass move cut through over across via
    along on in into by to the a an""".split()
)
#: Verbs that may stand between a condition word and its place ("unless it runs close to the
#: water", "if it lies near the road").
CONDITION_VERBS = frozenset("runs run lies lie passes pass gets get goes go comes come is are gets".split())
#: Linking verbs: an entity right before one is the subject of what follows ("roads are a last
#: resort", "sand is better than mud"): it takes that predicate, never its neighbour's.
COPULAS = frozenset(
    """is are was were be been being remains remain seems seem looks look stays stay feels feel
    makes make 's""".split()
)
PREFER_VERBS = {
    "prefer",
    "prefers",
    "preferred",
    "favour",
    "favor",
    "choose",
    "pick",
    "use",
    "prioritise",
    "prioritize",
}

CONDITIONS = _table(
    [
        (p, "unless_near")
        for p in (
            "unless",
            "except",
            "except when",
            "except if",
            "except where",
            "but not",
        )
    ]
    + [
        (p, "if_near")
        for p in (
            "if",
            "only if",
            "when",
            "only when",
            "whenever",
            "as long as",
            "so long as",
            "provided",
            "provided that",
            "where",
            "only where",
        )
    ]
    + [
        (p, "only_at")
        for p in (  # "cross the railway only at level crossings"
            "only",
            "but only",
        )
    ]
)
#: Verbs that make "only at Y" a place to cross ("avoid water, only cross at the bridge").
CROSS_VERBS = {
    "cross",
    "crosses",
    "crossing",
    "enter",
    "enters",
    "entering",
    "wade",
    "wading",
    "ford",
    "swim",
    "swimming",
    "traverse",
    "traversing",
    "pass",
    "passing",
}
#: Words that, after "except"/"unless"/"only", place the exception at the other entity
#: ("except at level crossings", "only via the bridge", "unless over the bridge").
EXCEPT_PREPS = {"at", "on", "over", "via", "through", "across", "using", "into", "onto", "in"}
PROXIMITY = _table(
    [
        (p, "near")
        for p in (
            "near",
            "nearby",
            "close to",
            "next to",
            "adjacent to",
            "beside",
            "by",
            "alongside",
            "along",
            "around",
            "in the vicinity of",
            "close by",
            "near to",
        )
    ]
)
#: Proximity words that make a cue on their own (without "unless"/"if").
NEAR = _table(
    [
        (p, "near")
        for p in (
            "near",
            "close to",
            "next to",
            "adjacent to",
            "beside",
            "alongside",
            "in the vicinity of",
            "near to",
            "nearby",
            "near of",  # non-native: "stay near of the treeline"
            "(snug|tight|hard) (to|against|up against|by)",  # "keep snug to the trail", "tight to the treeline"
            "(cling|clings|clinging) to",  # "cling to the road"
            # "stay by the trees", "keep by the road": by is beside when a verb of staying has it
            "(stay|stays|staying|keep|keeps|keeping|remain|remains|stick|sticks|hang|hangs) (by|round|about)",
            "approaching",  # "the rover shall avoid approaching water": as "avoid going near" it
            "nearing",
            # staying about a place: "let the route linger by the trees", "dwell near the water"
            # (never "dwelling": a house)
            "(linger|lingers|lingering|dwell|dwells|loiter|loiters) (by|near|around|among|beside)",
            "(right|_) up against",  # "hug the walls, right up against the buildings"
            "(right|_) (up|_) (against|by) the (side|sides|edge|edges|wall|walls) of",
            "in (close|_) proximity (to|of)",
            "close proximity (to|of)",
            "in the proximity of",
            "(within|in) (line|lines) of sight (of|to)",
            "(within|in) (sight|view) of",
            "within (visual|viewing|easy|walking) (range|distance|reach|contact) of",
        )
    ]
)
FAR_WORDS = _table(
    [
        (p, "far")
        for p in (
            "far from",
            "far away from",
            "a safe distance from",
            "(well|way|far|right) away from",  # "keep way away from the water"
            "(well|way|_) clear of",
            "(shy|shies|shying) away from",  # "the mower should shy away from the water"
            "(well|way|far|_) back from",  # "keep back from the rails", "stay well back from X"
            "a stone throw from",  # "a stone's throw from X" (the possessive is dropped): some distance
        )
    ]
)
#: Negations of "far from" that make it nearness ("don't go far from X", "never stray far from
#: X", "not too far from X"), and the words a negation does not reach past.
FAR_NEGATORS = frozenset({"don't", "dont", "never", "not", "no", "shouldn't", "mustn't", "won't"})
NEAR_FAR_STOPS = frozenset({",", ";", ":", "and", "but", "or", "from", "than"})
#: Who or what is negated before a bound ("nobody gets closer than 10 m to", "don't go any nearer
#: than"): the negation is the bound's, so it belongs to the cue; and the verbs between.
BOUND_NEGATORS = FAR_NEGATORS | {"nobody", "noone", "nothing", "none"}
BOUND_VERBS = frozenset(
    "get gets getting go goes going come comes coming move moves venture ventures wander wanders stray strays "
    "drive drives walk walks fly flies be is are".split()
)
#: Bounds before "<N> m from X": a rule, kept as a hard cue. Far: "at least 10 m from the
#: water"; near: "within 50 m of the road", "no more than 50 m from the road".
FAR_BOUNDS = {
    ("at", "least"),
    ("closer", "than"),
    ("nearer", "than"),
    ("more", "than"),
    ("no", "closer", "than"),
    ("any", "closer", "than"),  # "don't get any closer than 5 m to the rails"
    ("any", "nearer", "than"),
    ("no", "closer"),
    ("no", "nearer", "than"),
    ("not", "closer", "than"),
    ("further", "than"),
    ("farther", "than"),
    ("over",),
    ("beyond",),
    ("a", "minimum", "of"),
    ("minimum",),
    ("min",),
    ("minimum", "of"),
    (">", "="),  # ">= 3 m", "≥ 3 m", "> 3 m": at least
    ("≥",),
    (">",),
}
NEAR_BOUNDS = {
    ("<", "="),  # "<= 50 m", "≤ 50 m", "< 50 m": at most
    ("≤",),
    ("<",),
    ("no", "more", "than"),
    ("not", "more", "than"),
    ("no", "further", "than"),
    ("no", "farther", "than"),
    ("at", "most"),
    ("less", "than"),
    ("under",),
    ("a", "maximum", "of"),
    ("maximum",),
    ("max",),
    ("within",),
}
GAP_NOUNS = {
    "distance",
    "buffer",
    "clearance",
    "gap",
    "margin",
    "berth",
    "separation",
    "standoff",
    "setback",
    "range",
    "radius",
    "ring",  # "a 20-foot ring around the clubhouse"
    "cordon",
}
#: Gap nouns a terse clearance rule is named by, next to its entity and its distance
#: ("clearance tree >= 3 m", "railway standoff 15 m", "soft buffer building 6 m").
CLEARANCE_NOUNS = {"clearance", "buffer", "margin", "standoff", "setback", "separation", "berth", "gap", "offset"}
#: Two words joined by a hyphen that are one word ("stand-off", "off-road"; never "stay off the road").
HYPHEN_COMPOUNDS = frozenset(CLEARANCE_NOUNS | {"offroad"})
#: The marks between a clearance rule's entity and its distance: ">= 3 m", "= 3 m", ": 3 m".
#: Column and key names whose value is the rule itself ("enforcement: advisory", "trail: {cost:
#: preferred}", "| terrain | rule |"): a row or a nested key reads the value alone.
VERDICT_COLUMNS = frozenset(
    "enforcement rule rules verdict status action mode strictness severity preference rating cost costs weight "
    "weights penalty price value score note notes effect".split()
)
CLEARANCE_MARKS = {">", "≥", "=", ":", "of", "min", "minimum", "at", "least", "distance", "radius"}
#: Nouns and adjectives that name the kind of zone a distance makes ("a 30 m exclusion buffer
#: around", "a 10 m safety margin from", "a 15 m buffer zone around"): True where the word
#: itself keeps the route out (a hard rule unless softened), False where it only names the zone.
ZONE_MODIFIERS: dict[str, bool] = {
    "exclusion": True,
    "safety": False,
    "protective": False,
    "protection": False,
    "buffer": False,
    "standoff": False,
    "setback": False,
    "clearance": False,
}
#: Two-word zone names that keep the route out ("a 25 m keep-out zone", "a 10 m no-go buffer").
EXCLUDING_PAIRS = {("keep", "out"), ("no", "go"), ("no", "entry")}
#: Nouns after a gap noun that still name it ("buffer zone", "safety corridor").
ZONE_NOUNS = {"zone", "zones", "area", "corridor", "strip", "band", "ring"}
#: Words after a distance that make it an estimate ("20 m or so", "10 m-ish").
APPROX_AFTER = {("or", "so"), ("or", "thereabouts"), ("give", "or")}
APPROX_AFTER_WORDS = {"ish", "approx", "approximately", "roughly"}
#: A bound after the distance: "25 m or more from X" (at least), "50 m or less from X" (within).
FAR_AFTER = {("or", "more"), ("or", "further"), ("or", "farther"), ("plus",)}
NEAR_AFTER = {("or", "less"), ("or", "closer"), ("or", "nearer"), ("max",), ("maximum",)}
#: A zone stated in the passive before its object: "a 25 m exclusion zone is to be enforced
#: around the railway", "a 10 m buffer must be kept from the water".
ZONE_PASSIVE = frozenset(
    "is are to be must shall should will enforced applied kept maintained observed imposed respected"
    " applies apply extends extend in place".split()
)
#: What a route does as it nears something ("as the route approaches the railway", "as you get
#: closer to the water").
APPROACH_VERBS = frozenset({"approaches", "approach", "approaching", "nears", "closer", "nearer"})
#: Verbs that pull a route toward something ("bias the planner toward the water's edge").
BIAS_VERBS = frozenset({"bias", "biased", "pull", "pulled", "draw", "drawn", "nudge", "skew", "steer", "lean"})
#: Graded nearness worded as an aim, not a place: "as far as practicable from X", "as close as
#: you can to X" (up to :data:`AIM_GAP` words between "as far as" and the preposition).
#: The same aim with its preposition first: "as close to the road as is practicable", "as far
#: from the water as the terrain allows" (what follows the second "as" is read as softening).
AIM_WITH_PREP: dict[tuple[str, ...], str] = {
    ("as", "close", "to"): "near",
    ("as", "near", "to"): "near",
    ("as", "far", "from"): "far",
    ("as", "far", "away"): "far",
}
AIM_OPENINGS: dict[tuple[str, ...], str] = {
    ("as", "far", "as"): "far",
    ("far", "as", "possible"): "far",  # "stay far as possible from the railway"
    ("far", "as", "practicable"): "far",
    ("as", "close", "as"): "near",
    ("as", "near", "as"): "near",
    # "as much distance as possible from the railway", "as much room as you can from the pond"
    ("as", "much", "distance"): "far",
    ("as", "much", "room"): "far",
    ("as", "much", "space"): "far",
    ("as", "much", "clearance"): "far",
    ("as", "much", "separation"): "far",
}
AIM_GAP = 4
#: An aim with no object of its own, after a keeping-away or a drawing-near ("stay away from the
#: railway, as far as possible"; "hug the trail as closely as you can"): its word and where it ends.
AIM_WORDS = {"far": "far", "close": "near", "closely": "near", "near": "near", "tightly": "near"}
AIM_ENDS = tuple(
    tuple(p.split())
    for p in (
        "possible",
        "reasonably possible",
        "practicable",
        "practically possible",
        "feasible",
        "you can",
        "u can",
        "we can",
        "it can",
        "the terrain allows",
        "the ground allows",
        "you safely can",
    )
)
#: "within sight of X", "within reach of X": near, with no distance stated.
WITHIN_NOUNS = {"sight", "reach", "earshot", "range", "view", "eyeshot", "radio"}
#: Verbs that make a graded far cue of a proximity noun ("minimise proximity to the creek",
#: "reduce exposure to the road") or of a gap noun ("maximise the distance from the road").
LESSEN_VERBS = {"minimise", "minimize", "minimising", "minimizing", "reduce", "reducing", "limit", "limiting", "lessen"}
GROW_VERBS = {"maximise", "maximize", "maximising", "maximizing", "increase", "increasing"}
PROXIMITY_NOUNS = {"proximity", "exposure", "closeness", "nearness", "contact", "time"}
#: Participles that lessen or grow a noun stated before them ("proximity to the canopy should be
#: minimised", "distance from the road is to be maximised").
LESSENED = {"minimised", "minimized", "reduced", "lessened", "penalised", "penalized", "discouraged", "punished"}
GROWN = {"maximised", "maximized", "increased", "rewarded", "encouraged", "favoured", "favored"}
LESSEN_VERBS |= {"penalise", "penalize", "penalising", "penalizing", "discourage", "punish"}
GROW_VERBS |= {"reward", "rewarding", "encourage", "favour", "favor"}
#: A band priced rather than forbidden: "softly penalised within 8 m of tree crowns" (a soft
#: zone kept away from), "rewarded within 10 m of the trail" (a soft pull toward it).
PRICED_WITHIN = frozenset(
    "penalise penalize penalised penalized penalising penalizing discouraged punished charged taxed".split()
)
REWARDED_WITHIN = frozenset("reward rewarded rewarding favoured favored encouraged".split())
#: Verbs whose subject is the route, not a place with a preference of its own ("paths were
#: biased toward the road", "trajectories were penalised within 8 m of the crowns").
ROUTE_PREDICATES = BIAS_VERBS | PRICED_WITHIN | REWARDED_WITHIN
#: Words after a proximity noun that price it (a cost on proximity keeps away: "building
#: proximity cost", "proximity to X: penalty") or reward it ("proximity to X: reward").
PROXIMITY_PRICED = {"cost", "costs", "penalty", "penalties", "penalised", "penalized", "malus", "bad"}
#: "proximity to the railway carries increasing risk": a risk priced on nearness.
PROXIMITY_PRICED |= {"risk", "risks", "danger", "hazard", "hazardous", "dangerous", "risky"}
PROXIMITY_REWARDED = {"reward", "rewarded", "bonus", "good", "pref", "preferred", "attract", "attractive"}
#: "cost rises with proximity to X": the cost words and the verbs of their change.
COST_WORDS = {"cost", "costs", "price", "prices", "penalty", "penalties", "weight", "weights", "expense"}
COST_WORDS |= {"risk", "danger"}  # "the closer to the railway, the more risk"
RISE_VERBS = {"rise", "rises", "rising", "increase", "increases", "increasing", "grow", "grows", "growing"}
RISE_VERBS |= {"climb", "climbs"}
RISE_VERBS |= {"rose", "risen", "increased", "grew", "grown", "climbed"}  # a report's past tense
#: What a near cue gives, as a graded restatement says it ("the benefit diminishing with distance").
BENEFIT_WORDS = {"benefit", "bonus", "reward", "attraction", "pull", "preference", "advantage"}
FALL_VERBS = {"fall", "falls", "falling", "decrease", "decreases", "decreasing", "drop", "drops", "decline", "shrinks"}
FALL_VERBS |= {"diminish", "diminishes", "diminishing", "decay", "decays", "decaying", "fade", "fades", "fading"}
FALL_VERBS |= {"declines", "declining", "shrink", "shrinking", "lessen", "lessens", "lessening", "reduce", "reduces"}
FALL_VERBS |= {"fell", "fallen", "decreased", "dropped", "declined", "diminished", "shrank", "lessened", "decayed"}
#: "give the houses a wide berth": the adjectives of a gap noun given to an entity.
WIDE_WORDS = {"wide", "wider", "good", "generous", "big", "large", "healthy", "decent", "respectful", "broad"}
#: "give the trees a bit of room", "leave the hedge a little space": the amount before the gap
#: noun, and the nouns of room given (a gap only when given: "room" alone is no distance).
BERTH_MEASURES = {"bit", "little", "lot", "fair", "touch"}
ROOM_NOUNS = {"room", "space", "breathing"}
GIVE_VERBS = {"give", "gives", "giving", "leave", "leaves", "leaving", "allow", "keep"}
#: Verbs of keeping close to something ("hug the tree line"): a near cue on their object.
HUG_VERBS = {"hug", "hugs", "hugging", "shadow", "shadows", "shadowing"}
#: Keeping close along something ("move tight along the treeline", "run closely beside the fence").
TIGHT_WORDS = {"tight", "tightly", "close", "closely"}
TIGHT_PREPOSITIONS = {"along", "beside", "by", "alongside", "to", "against"}
#: Where a graded cue stated before reaches neutral: "<opening> N m" ("tapering off by 30 m").
REACH_OPENINGS: tuple[tuple[str, ...], ...] = tuple(
    tuple(p.split())
    for p in (
        "no effect beyond",
        "no effect past",
        "no effect after",
        "no effect over",
        "with no effect beyond",
        "no penalty beyond",
        "no penalty past",
        "no cost beyond",
        "neutral beyond",
        "neutral past",
        "up to",
        # "penalised progressively out to a distance of fifteen metres", "extending to 30 m"
        "out to",
        "out to a distance of",
        "to a distance of",
        "over a distance of",
        "extending to",
        "extending out to",
        # a field's reach, as a planner's configuration says it ("radius 25 m", "falloff 50 m",
        # "influence radius 40 m", "zero at 30 m")
        "radius",
        "radius of",
        "influence radius",
        "falloff",
        "fall off",
        "decay radius",
        "zero at",
        "zero beyond",
        "flat beyond",
        # "be negligible beyond 30 m", "vanish past 20 m": the penalty's own words for neutral
        "negligible beyond",
        "negligible past",
        "negligible after",
        "nothing beyond",
        # "heavy right next to it, nothing extra past 25 m"
        "nothing extra past",
        "nothing extra beyond",
        "nothing extra after",
        "no extra cost past",
        "no extra cost beyond",
        "nothing more past",
        "nothing more beyond",
        # "with the effect reaching at most 25 m out", "its influence extending no further than 30 m"
        "reaching at most",
        "reaching up to",
        "reaching out to",
        "reaching no further than",
        "reaching no more than",
        "extending at most",
        "extending no further than",
        # where a reward holds: "proximity to building: reward. within 10 m is pref."
        "within",
        # indifference past a point: "not bothered once it's past ~12 m", "no bother beyond 30 m"
        "not bothered past",
        "not bothered beyond",
        "not bothered once past",
        "not bothered once it's past",
        "not bothered once it is past",
        "not bothered once it gets past",
    )
) + tuple(
    # "no concern beyond fifteen metres", "no issue at all past 25 m"
    ("no", noun, *at_all, prep)
    for noun in ("concern", "issue", "bother", "problem", "worry", "risk", "harm", "danger", "penalty")
    for at_all in ((), ("at", "all"))
    for prep in ("beyond", "past", "after", "over")
)
#: What is no longer a concern where a fall-off ends ("fading to no bother at all by 30 m out",
#: "beyond 25 metres there is no issue at all").
NO_CONCERN_NOUNS = frozenset(
    {"concern", "issue", "bother", "problem", "worry", "risk", "harm", "danger", "odds", "difference"}
)
#: The reach openings by their first word (every word of a prompt is tried as an opening).
REACH_BY_FIRST: dict[str, tuple[tuple[str, ...], ...]] = {
    first: tuple(p for p in REACH_OPENINGS if p[0] == first) for first in {p[0] for p in REACH_OPENINGS}
}
#: A fall-off's own words for where it ends ("falling to nothing at 30 m", "fade out entirely
#: beyond 20 m", "drops to the background level past 40 m", "dying away by 15 m"): a verb of
#: falling, a particle, what it falls to, how wholly, and the preposition before the distance
#: (:func:`interpret.reach.fall_off_opening` reads them in that order, each but the verb
#: and the preposition optional).
FALL_OFF_VERBS = frozenset(
    f"{stem}{end}"
    for stem, ends in (
        ("fall", ("", "s", "ing")),
        ("fade", ("", "s", "d")),
        ("fading", ("",)),
        ("taper", ("", "s", "ing", "ed")),
        ("ramp", ("", "s", "ing")),
        ("drop", ("", "s", "ping")),
        ("decay", ("", "s", "ing")),
        ("die", ("", "s")),
        ("dying", ("",)),
        ("diminish", ("", "es", "ing")),
        ("decrease", ("", "s")),
        ("decreasing", ("",)),
        ("vanish", ("", "es", "ing")),
        ("disappear", ("", "s", "ing")),
        ("return", ("", "s", "ing")),
        ("reach", ("", "es", "ing")),
        ("falloff", ("",)),
        ("ease", ("", "s", "d")),  # "easing off to nothing by about 30 metres out"
        ("easing", ("",)),
    )
    for end in ends
)
FALL_OFF_PARTICLES = frozenset({"down", "off", "out", "away"})
FALL_OFF_LEVELS = frozenset({"0", "zero", "neutral", "nothing", "none", "baseline", "background", "normal"})
FALL_OFF_WHOLLY = frozenset({"entirely", "completely", "fully", "altogether", "totally", "gradually", "smoothly"})
FALL_OFF_PREPS = frozenset({"beyond", "past", "at", "by", "after", "over"})
#: How a reach says distance stops counting ("past 15 m it stops mattering", "no longer matters").
MATTERING_WORDS = frozenset({"mattering", "matters", "matter", "counts", "count", "counting", "irrelevant"})
#: Where a distance stops mattering, as indifference says it ("past 30 m I don't care", "after
#: 5 metres it is all the same", "beyond that, whatever").
INDIFFERENT_ENDS = frozenset({"care", "same", "whatever", "difference", "equal"})
#: The words that open that point ("past", "beyond", "from 4 m on").
MATTERING_OPENINGS = frozenset({"past", "beyond", "after", "over", "from", "by", "once"})
#: What a reach may say of the ground inside it ("within 10 m is pref", "within 5 m is best").
REACH_VERDICTS = frozenset(
    {"pref", "prefer", "preferred", "best", "good", "fine", "ideal", "cheap", "cheaper", "better"}
)
#: A planner's field words: an attractor pulls the route near its entity, a repulsor pushes it
#: away, both graded ("attract: road", "water: repel", "repulsor: building, radius 30 m").
ATTRACT_WORDS = frozenset({"attract", "attracts", "attracted", "attractor", "attraction", "pull", "pulls"})
REPEL_WORDS = frozenset(
    {"repel", "repels", "repelled", "repulsor", "repeller", "repulsion", "repulse", "push", "pushes"}
)
#: Verbs that link a graded quantity to how it changes ("the penalty should fade", "the closer,
#: the worse it gets"): skipped between a correlative's halves and before a reach's opening.
CORRELATIVE_VERBS = frozenset({"should", "must", "will", "would", "be", "is", "gets", "get", "becomes", "become"})
#: Keys of a configuration that set where a fall-off ends ("falloff_m": 20, "decay = 15 m"),
#: keys whose value says how a cost is shaped ("mode": "graded") and the values that say it
#: falls off with distance (:func:`interpret.reach.keyed_reach`).
REACH_KEYS = frozenset({"falloff", "fall", "decay", "fade", "fadeout", "taper", "reach", "range"})
SHAPE_KEYS = frozenset({"mode", "shape", "profile", "costing"})
GRADED_VALUES = frozenset(
    {"graded", "gradual", "gradient", "sloped", "tapered", "linear", "exponential", "inverse", "decay"}
)
#: What a reach is said of, before its opening ("with the effect reaching at most 25 m out").
REACH_SUBJECTS = frozenset({"effect", "influence", "field", "gradient"})
#: What a distance is said to be when it is all the room wanted ("About 30 m is plenty"): the
#: reach of the graded cue before it.
ENOUGH_WORDS = frozenset({"plenty", "enough", "sufficient", "ample", "adequate"})
#: "the further the better", "the closer to the river the better": a graded cue's fall-off.
GRADED_FAR = {"further", "farther"}
#: How a correlative ends: "the closer, the better / the cheaper" or "the worse / the dearer".
CORRELATIVE_GOOD = {"better", "cheaper", "safer", "nicer", "happier", "sweeter", "lovelier", "finer"}
#: "the wider the margin you give the buildings, the better": more room is further away.
WIDER_WORDS = frozenset({"wider", "bigger", "larger", "greater", "more", "broader"})
#: "the smaller the gap between unit and road, the better": less room is nearer.
NARROWER_WORDS = frozenset({"smaller", "narrower", "tighter", "less", "shorter"})
CORRELATIVE_BAD = {
    "worse",
    "dearer",
    "costlier",
    "expensive",
    "riskier",
    "higher",
    "pricier",
    "sketchier",
    "dodgier",
    "scarier",
    "hairier",
}
GRADED_NEAR = {"closer", "nearer"}
#: A correlative's end said as the speaker's feelings ("the twitchier I get", "the more nervous
#: we are", "the more it bugs people"): worse, or better ("the calmer I feel").
FEELING_WORSE = frozenset(
    "twitchier jumpier edgier nervier unhappier angrier crosser grumpier tenser warier "
    "nervous anxious worried uneasy annoyed upset cross twitchy jumpy tense wary".split()
)
FEELING_BETTER = frozenset("calmer easier relaxed comfortable calm".split())
BOTHER_VERBS = frozenset("bugs annoys worries upsets irritates bothers disturbs scares frightens".split())
#: A correlative's end that grows or shrinks a quantity ("the heavier the penalty", "the lower
#: the cost", "the bigger the reward"): good or bad by the quantity it names.
CORRELATIVE_MORE = {"heavier", "greater", "bigger", "larger", "stronger", "steeper", "harsher", "stiffer", "more"}
CORRELATIVE_LESS = {"lower", "smaller", "lighter", "less", "weaker", "milder"}
AVOID_WORDS = {"avoid", "avoids", "avoided", "avoiding", "try", "dislike"}
MIN_WORDS = {"minimum", "min", "minimal", "safe"}
#: Words in a clause that soften a stated distance into a preference ("try to stay within ...").
SOFTENERS = {
    "try",
    "trying",
    "tries",
    "attempt",
    "prefer",
    "preferably",
    "ideally",
    "possible",
    "preferable",
    "rather",
    "practicable",
    "feasible",
    "roughly",
    "approximately",
    "some",
    "bit",
    "soft",
    "desired",
    # "a gentle buffer of about twenty metres", "a mild standoff", "would be welcome"
    "gentle",
    "mild",
    "slight",
    "nominal",  # "maintain a nominal standoff of 2,5 m": a target, not a limit
    "recommended",
    "welcome",
    "wish",
    "nice",
    "poss",
    # a configuration's softness: "soft buffer 6 m (penalty only, passable)", "(weight low)",
    # "is desirable", "best effort"
    "penalty",
    "penalties",
    "passable",
    "desirable",
    "effort",
    "weight",
    "low",
    # "standoff ~10 m preferred, ok to violate"
    "preferred",
    "violate",
    "violated",
}
#: Words that label a whole sentence's rules as advice ("Mitigation measure M4 (advisory): ... at
#: least 30 m from the railway"): its distances are soft, whatever the bound says.
ADVISORY_WORDS = frozenset({"advisory", "guidance", "recommended", "recommendation", "optional", "nonbinding"})
#: Words of a sentence that make a distance a rule, wherever they stand in it ("at all times",
#: "under no circumstances", "the platform must never come within 15 m", "hard constraint:
#: no segment within 12 m"): the cue is ``hard`` unless its own clause softens it.
ABSOLUTE_WORDS = frozenset(
    {
        "never",
        "always",
        "must",
        "mustn't",
        "shall",
        "mandatory",
        "strictly",
        "absolutely",
        "absolute",
        "strict",
        "hard",
        "forbidden",
        "prohibited",
        "required",
        "requirement",
        "minimum",
        "min",
        "standoff",
    }
)
#: Words of a sentence whose absolute wording made a rule that are read with it ("never *get*
#: closer than", "no *matter what*", "the platform *must* *maintain*").
RULE_FILLER = frozenset(
    "get gets come comes go goes be is stay keep remain maintain maintains hold holds matter what "
    "times time under any all circumstances happens exceptions exception constraint constraints limit limits rule "
    "rules closer "
    "nearer than "
    "buffer buffers zone zones setback standoff clearance margin separation distance this that it "
    "every inch metre meter foot whole way point of breach violate break infringe waive relax bend "
    "law job anything zero tolerance cutting corners one".split()
)
#: What a rule is said not to be, in a sentence that makes it hard ("an absolute constraint, not
#: a preference"): a negator before one of these does not soften the rule.
WISH_NOUNS = frozenset(
    "preference suggestion guideline guidance wish recommendation weighting nicety soft advisory optional".split()
)
#: What the leftover check takes as read in a sentence whose distance rule is worded as absolute.
#: One-word sentences that make the rule before them absolute ("Keep 20 m off. Non-negotiable.").
RULE_VERDICTS = frozenset({"negotiable", "nonnegotiable", "period", "mandatory", "compulsory"})
#: Words before a trigger that lift what it says ("no need to avoid the sheds", "you don't have to
#: keep off the grass"): the entity is permitted (fine), which lifts a prior hazard to neutral.
NEED_NEGATORS = frozenset(
    {
        ("no", "need", "to"),
        ("no", "need", "for"),
        ("don't", "need", "to"),
        ("doesn't", "need", "to"),
        ("do", "not", "need", "to"),
        ("does", "not", "need", "to"),
        ("don't", "have", "to"),
        ("doesn't", "have", "to"),
        ("do", "not", "have", "to"),
        ("needn't",),
        ("not", "necessary", "to"),
        ("unnecessary", "to"),
        ("no", "reason", "to"),
        ("no", "call", "to"),  # "no call to steer around 'em": no need to
        ("no", "restriction", "on"),  # "no restriction on crossing or moving along it"
        ("no", "restrictions", "on"),
        ("no", "point", "in"),
        ("not", "required", "to"),
        ("don't", "bother", "to"),
        ("don't", "bother"),
        ("not", "needed", "to"),
        ("nobody", "needs", "to"),
        ("nobody", "has", "to"),
        # the passive: "vegetation need not be avoided", "the sheds needn't be avoided"
        ("need", "not", "be"),
        ("needs", "not", "be"),
        ("needn't", "be"),
        ("does", "not", "need", "to", "be"),
        ("doesn't", "need", "to", "be"),
        ("don't", "need", "to", "be"),
        ("do", "not", "need", "to", "be"),
        ("not", "need", "to", "be"),
    }
)
#: Conditions that make a way to go a permission, not a preference ("walk through them if it's
#: shorter", "cut across the lawn if needed").
SHORTCUT_CONDITIONS = tuple(
    tuple(p.split())
    for p in (
        "if it's shorter",
        "if it is shorter",
        "if that's shorter",
        "if shorter",
        "if it's quicker",
        "if it is quicker",
        "if quicker",
        "if it's faster",
        "if faster",
        "if it saves time",
        "if it helps",
        "if needed",
        "if need be",
        "if necessary",
        "when needed",
        "when necessary",
        "where needed",
        "where necessary",
    )
)
#: Plain negations that turn an avoiding trigger into a permission ("don't avoid the sheds").
AVOID_NEGATORS = frozenset(
    {("don't",), ("do", "not"), ("doesn't",), ("does", "not"), ("dont",), ("not",), ("won't", "be"), ("aren't",)}
)
#: Labels that say how strict the sentence's distance rule is ("Hard constraint: never within
#: 5 m of ...", "Soft constraint: a clearance of 8 m ..."): read with it, the soft ones soften it.
RULE_LABELS = {
    ("hard", "constraint"): "hard",
    ("hard", "rule"): "hard",
    ("hard", "limit"): "hard",
    ("hard", "requirement"): "hard",
    ("soft", "constraint"): "soft",
    ("soft", "rule"): "soft",
    ("soft", "limit"): "soft",
    ("soft", "requirement"): "soft",
    ("soft", "preference"): "soft",
    ("a", "preference"): "soft",  # "..., but that's a preference, not a rule"
    # a rule its writer lets be broken: "ok to violate", "can be violated", "not strict"
    ("to", "violate"): "soft",
    ("can", "violate"): "soft",
    ("be", "violated"): "soft",
    ("not", "strict"): "soft",
    ("nothing", "strict"): "soft",  # "... would be welcome, though nothing strict"
    ("not", "mandatory"): "soft",
    ("not", "required"): "soft",  # "twenty metres, desired, not required"
    ("not", "compulsory"): "soft",
}
#: Negations that make a rule-qualifying sentence soften the rule ("Not mandatory.", "no hard limit").
RULE_NEGATORS = frozenset({"not", "no", "isn't", "aren't", "nothing", "non"})
RULE_WORDS = ABSOLUTE_WORDS | RULE_FILLER | RULE_VERDICTS | WISH_NOUNS | {"no", "not", "ever", "non", "isn't", "aren't"}
ABSOLUTE_PHRASES = frozenset(
    {
        ("at", "all", "times"),
        ("full", "stop"),  # "nothing within 12 m of the track, full stop"
        ("end", "of", "story"),
        ("end", "of", "discussion"),
        ("no", "matter", "what"),
        ("under", "no", "circumstances"),
        ("under", "any", "circumstances"),  # "no vehicle is permitted within 25 m ... under any circumstances"
        ("at", "any", "time"),
        ("whatever", "happens"),
        ("not", "allowed"),
        ("not", "permitted"),
        ("no", "exceptions"),
        ("without", "exception"),
        ("without", "any", "exception"),  # "... from the buildings, without any exception"
        ("without", "exceptions"),
        ("no", "exception"),
        ("non", "negotiable"),
        ("not", "negotiable"),
        # the rule holds everywhere along the route: "thirty yards off the railroad the whole way,
        # every inch of it", "at every point", "every metre of the route"
        # "No ever, no for anything, that's the law on this job" (Scots "no" is "not")
        ("no", "ever"),
        ("not", "ever"),
        ("no", "for", "anything"),
        ("zero", "tolerance"),  # "Zero tolerance on that one."
        ("no", "tolerance"),
        ("no", "cutting", "corners"),
        ("not", "for", "anything"),
        ("the", "law"),
        ("every", "inch"),
        ("every", "metre"),
        ("every", "meter"),
        ("every", "foot"),
        ("at", "every", "point"),
        ("at", "any", "point"),
        ("the", "whole", "way"),
        ("all", "the", "way"),
        # an obligation: "the cable trench has to run between 5 and 10 m from the road" (never
        # after a negation: "you don't have to keep 10 m from it" lifts the rule)
        ("has", "to"),
        ("have", "to"),
    }
    | {
        # the rule is not to be broken: "Mandatory - do not breach it under any circumstances"
        (*neg, verb)
        for neg in (("do", "not"), ("don't",), ("never",), ("must", "not"), ("mustn't",), ("shall", "not"))
        for verb in ("breach", "violate", "break", "infringe", "waive", "relax", "bend")
    }
)
#: Words before an obligation that lift it ("don't have to", "doesn't have to", "not have to").
OBLIGATION_NEGATORS = frozenset({"don't", "doesn't", "didn't", "not", "never", "no", "dont"})
CENTRE = {"centre", "center", "middle", "centreline", "centerline", "midline"}
SIDE = {
    "side",
    "sides",
    "edge",
    "edges",
    "shoulder",
    "shoulders",
    "verge",
    "verges",
    "margin",
    "margins",
    "kerb",
    "curb",
    "border",
    "borders",
}
SIDE_TOKENS = {"roadside": "road", "kerbside": "road", "curbside": "road", "wayside": "road"}
#: ... and the water's: "walk the shoreline", "shadow the waterline" (the band beside the water).
_WATER_SIDES: tuple[str, ...] = ("shoreline", "waterline", "waterside", "waterfront", "lakeshore", "shore")
_WATER_SIDES += ("lakeside", "riverside", "riverbank", "riverbanks", "streambank", "creekside", "bankside", "creekbank")
SIDE_TOKENS |= {w: "water" for w in _WATER_SIDES}
#: Side tokens of an areal entity: ground near it, not a side of a line ("walk the shoreline").
NEAR_SIDE_TOKENS = frozenset(_WATER_SIDES)

MARKERS = _table(
    [
        (p, "start")
        for p in (
            "first",
            "firstly",
            "first of all",
            "to begin with",
            "start with",
            "primarily",
            "above all",
        )
    ]
    + [
        (p, "next")
        for p in (
            "second",
            "secondly",
            "third",
            "thirdly",
            "finally",
            "lastly",
            "last",
            "after that",
            "after (it|this|those|them)",
            "afterwards",
            "next",
        )
    ]
    + [
        # alternatives: what follows is the fallback; what came before keeps its own tier, and
        # a bare list before them is not made preferred by them
        (p, "alt")
        for p in (
            "otherwise",
            "failing that",
            "if not",
            "or else",
            "else",
        )
    ]
)
SEQ_SEPARATORS = {"then", "followed"}  # "and then", "followed by" ("and"/"by" are glue)

SEPARATORS = {
    ",",
    ":",
    "and",
    "or",
    "but",
    "while",
    "whereas",
    "although",
    "though",
    "however",
    "so",
    "plus",
    "nor",
    "yet",
    "because",
    "since",
    "owing",
    "then",
    "followed",
}
JOINERS = {",", "and", "or", "nor", "&"}
#: Separators that contrast what follows with what came before: a bare list after one never takes
#: the earlier clause's tier ("never enter the buildings, but the parking lot ...").
CONTRASTIVE = frozenset({"but", "while", "whereas", "although", "though", "however", "yet"})
LIST_GLUE = JOINERS | {"as", "well"}  # "roads as well as trails"
SENTENCE_ENDS = {".", ";", "!", "?", "\n", "|"}  # "railway: lethal | road: cheap"
ARTICLES = {
    "the",
    "a",
    "an",
    "any",
    "some",
    "all",
    "those",
    "these",
    "this",
    "that",
    "its",
    "their",
    "our",
    "your",
    "every",
    "each",
    "other",
    "both",
    "either",
    "neither",
}
PRONOUNS = {"it", "them", "they", "those", "these", "there", "this", "that", "it's", "they're", "one", "ones"}
#: Words before an entity's name that qualify where on it, skipped where a list begins ("at
#: least 3 m off the perimeter fence").
LEAD_MODIFIERS = frozenset({"perimeter", "boundary", "outer", "inner", "surrounding", "nearby", "adjacent"})
#: ... and the words that only say which ones are there ("close to existing buildings", "the
#: nearest road", "any mapped water").
LEAD_MODIFIERS |= {"existing", "visible", "mapped", "marked", "known", "remaining", "nearest", "closest", "local"}
LEAD_MODIFIERS |= {"open"}  # "apart from the open barn"
#: Words that except an entity from what its clause says of the others ("fine except the pitch").
EXCEPTING = (
    ("except", "for"),
    ("apart", "from"),
    ("other", "than"),
    ("aside", "from"),
    ("excluding",),
    ("except",),
    ("excepting",),
    ("but", "not"),
)
#: The tier an excepted entity takes: the other side of its clause's.
EXCEPTED_TIER = {
    "prefer": "avoid",
    "fine": "avoid",
    "tolerable": "avoid",
    "last": "avoid",
    "avoid": "fine",
    "avoid+": "fine",
    "lethal": "fine",
    "nocross": "fine",
}
#: Relative pronouns opening a clause about the entity named just before ("the pitch, which
#: must not be driven on").
RELATIVE_PRONOUNS = frozenset({"which", "who"})
#: Pronouns that stand for the entity named last when a preposition governs them ("keep within
#: 50 m of it", "the firm ground next to it"): read as a mention of that entity.
OBJECT_PRONOUNS = {"it", "them"}
#: "avoid that bit", "this part is fine": a demonstrative and a noun of a part of the ground
#: stand for the entity named last, as a pronoun does.
DEMONSTRATIVES = {"that", "this", "those", "these"}
PART_NOUNS = {"bit", "bits", "part", "parts", "section", "sections", "spot", "spots", "stretch", "patch", "one"}
#: Prepositions after which an object pronoun is read as the entity named last.
PRONOUN_PREPOSITIONS = {
    "of",
    "from",
    "to",
    "near",
    "beside",
    "by",
    "alongside",
    "around",
    "into",
    "past",
    "toward",
    "towards",
    "off",
    "along",
    "with",
    "onto",
    "across",
    "under",
    "over",
    "in",
    "on",
    "through",
}
#: Words that make the number after them an estimate ("within about 50 m of the railway"): the
#: distance is read, and a bound worded so is a preference, not a rule.
APPROXIMATORS = {"about", "around", "roughly", "approximately", "approx", "circa", "some", "~", "nearly", "almost"}

UNITS = {
    "m": 1.0,
    "meter": 1.0,
    "meters": 1.0,
    "metre": 1.0,
    "metres": 1.0,
    "mtr": 1.0,  # abbreviations in quick notes: "fifteen mtrs", "20 mtr"
    "mtrs": 1.0,
    "mts": 1.0,
    "km": 1000.0,
    "kilometer": 1000.0,
    "kilometers": 1000.0,
    "kilometre": 1000.0,
    "kilometres": 1000.0,
    "ft": 0.3048,
    "foot": 0.3048,
    "feet": 0.3048,
    "yd": 0.9144,
    "yard": 0.9144,
    "yards": 0.9144,
    "cm": 0.01,
    # a walker's pace, about 0.75 m ("nobody goes within twenty paces of the railway line")
    "pace": 0.75,
    "paces": 0.75,
    # a surveyor's chain, 66 ft ("a riparian buffer of one chain either side of the water")
    "chain": 20.1168,
    "chains": 20.1168,
}
#: The smaller unit a compound distance adds after its first part ("6 ft 6 in", "1 m 20 cm",
#: "5 feet 3 inches"): only there is "in" an inch.
SUB_UNITS = {"in": 0.0254, "inch": 0.0254, "inches": 0.0254, "cm": 0.01}
NUMBER_WORDS = {
    "one": 1,
    "two": 2,
    "three": 3,
    "four": 4,
    "five": 5,
    "six": 6,
    "seven": 7,
    "eight": 8,
    "nine": 9,
    "ten": 10,
    "eleven": 11,
    "twelve": 12,
    "thirteen": 13,
    "fourteen": 14,
    "fifteen": 15,
    "sixteen": 16,
    "seventeen": 17,
    "eighteen": 18,
    "nineteen": 19,
    "twenty": 20,
    "thirty": 30,
    "forty": 40,
    "fifty": 50,
    "sixty": 60,
    "seventy": 70,
    "eighty": 80,
    "ninety": 90,
    "hundred": 100,
    "a hundred": 100,
}
#: Digits spoken one word each on the radio ("two-zero metres" is 20, "one five" is 15).
RADIO_DIGITS = {w: v for w, v in NUMBER_WORDS.items() if v < 10} | {"zero": 0, "niner": 9}

#: Grammar words: understood as carrying no meaning of their own.
FILLER = frozenset(
    """
the a an any some all every each this that these those its their our your my his her both either
neither other others it it's they them they're there you you're we we're us i i'd me one ones he
she is are was were be been being am should would could will shall can may might must do does did
has have had need needs want wants like would'd let let's please kindly also just only even still
much very quite more most generally usually always really actually too well try trying tries attempt
network networks
attempting make sure go goes going gone drive drives driving walk walks walking travel travels
travelling traveling come comes coming came move moves moving ride riding fly flying navigate navigating cross crosses
crossing pass passes passing traverse traversing get getting head heading route routing plan
planning take taking stay stays staying keep keeps keeping remain remaining on in into onto
through across over under along to of for with at from via around about between up down out off
inside within towards toward robot robots rover rovers vehicle vehicles drone drones ugv ugvs agv agvs agent
bot bots rig rigs mower mowers horse horses mare mares pony ponies mission area
areas region regions zone zones terrain surface surfaces ground place places spot spots part
parts anything everything something stuff way ways time times main big small large wide narrow
open existing available certain whole entire major minor little left right possible okay here
hey hi hello listen thanks thank so as than what which who where when then there's that's i'm we'll
you'll i'll we've you've we're it'll enter enters entering visit visiting reach reaching approach
approaching want wants wanted kept wading swimming hiking cycling find finds another
blocked closed flooded unavailable jammed congested busy occupied damaged washed destroyed
proceed proceeds proceeding continue continues continuing advance advancing think guess believe
suppose feel know mean say tell suggest recommend advise hope wish target targets destination
destinations goal goals objective objectives waypoint waypoints point points location locations
position fast quick slow cell cells planner planners aircraft transit traversal treat treated
return returns returning
platform platforms ugvs agv agvs amr robots rovers trucks convoy crew crews team teams operator
quad quads atv atvs buggy buggies
operators unit units asset assets machine machines rule rules constraint constraints requirement
requirements without bank banks edge edges verge verges shore shores shoreline shorelines margin
margins perimeter fringe fringes embankment embankments boundary rim brink
everywhere anywhere somewhere elsewhere driven entered walked corridor corridors maintain maintains
maintaining itself themselves downstream upstream uphill downhill northward
northwards southward southwards
eastward eastwards westward westwards inland seaward firm solid stable higher north south east west
northeast northwest southeast southwest north-east north-west south-east south-west northern southern
eastern western
""".split()
)
#: How a graded cue falls off, said in a planner's words ("linear falloff", "exponential decay").
FILLER |= frozenset({"simply"})  # "so it simply must not"
FILLER |= frozenset(
    {"linear", "linearly", "falloff", "decay", "exponential", "exponentially", "monotonic", "monotonically"}
)
#: Chat that says nothing about the terrain ("dont go in it obviously lol").
#: How a graded price grows ("carries increasing risk", "penalised progressively").
FILLER |= frozenset({"carries", "carry", "poses", "increasing", "progressively", "increasingly", "gradually"})
FILLER |= frozenset({"footprint", "footprints", "outline", "outlines", "parallel", "offset"})  # "building footprints"
FILLER |= frozenset({"throughout", "full"})  # "move tight along the treeline throughout", "a full 10 m"
FILLER |= frozenset({"aim", "maybe", "perhaps", "probably", "straight"})
FILLER |= frozenset({"obviously", "lol", "haha", "ofc", "clearly", "btw", "fyi", "ya", "y'know", "yknow"})
FILLER |= frozenset({"honestly", "frankly", "seriously", "basically", "literally", "hey"})
FILLER |= frozenset({"measured", "calculated"})
FILLER |= frozenset({"steer", "steers", "steering"})  # "steer clear of X": the far cue is the words after it
# "I'd rather it stayed off the grass", "don't you dare put it in the pond"; Singlish "don't anyhow go in"
FILLER |= frozenset({"put", "puts", "putting", "rather", "anyhow"})
# ways of moving about that say nothing of where ("potter about near the house", "squeeze by")
FILLER |= frozenset(
    "potter potters pottering pootle pootles pootling mooch mooches trundle trundles trundling amble ambles "
    "roam roams mosey moseys squeeze squeezes squeezing creep creeps creeping sneak sneaks sneaking".split()
)
# time, never an entity: "go too far from road, later we cannot find you"
FILLER |= frozenset({"later", "soon", "meanwhile", "eventually"})
FILLER |= frozenset(
    {"tile", "tiles", "cell", "cells", "overflight", "overflights"}
)  # a game's "water tiles"  # "6 ft 6 in from buildings, measured from the wall"
#: The day of the mission itself: a state said of "today" is the state the costmap is for.
FILLER |= frozenset({"today", "currently", "presently", "now", "y'all", "yall"})
FILLER |= frozenset({"yourself", "yourselves", "ourselves", "alone"})  # "leave 20 yards between yourself and X"
#: "time spent on/over X": the participle adds nothing to "time on X"
FILLER |= frozenset({"spent", "freely", "wherever"})

#: A rule stated as its consequence ("if it touches the water, the rover is lost"): what
#: happens to the mission when the route goes there, the forbidding verdict of the "if" clause
#: before it (:mod:`overseec_core.interpret.consequences`). Its words stay out of the
#: grammar's vocabulary ("a ruined building", "dead trees" are names); they are matched as words.
DOOM = _table(
    (p, "doom")
    for p in (
        "(is|are|'s|will be|would be|gets|get|goes|go) "
        "(lost|scrubbed|ruined|toast|done for|dead|finished|wrecked|over|void|written off|a write off|"
        "a goner|gone|kaput|a loss|a total loss|scrapped|cancelled|canceled|bricked|game over)",
        "(it's|that's|it is|that is) (game over|the end|all over|over)",
        "(we're|you're|they're|it's|that's) (lost|scrubbed|ruined|toast|done for|dead|finished|wrecked|"
        "done|a goner|kaput|bricked)",
        "game over",
    )
)
#: Verbs of reaching a place in a consequence's "if" clause ("if it touches the water", "if the
#: rover ends up in the pond"); "gets within N m of X" is read with them.
CONTACT_VERBS = _table(
    (p, "contact")
    for p in (
        "(touch|touches|touched|enter|enters|entered|hit|hits|reach|reaches|reached)",
        "(get|gets|go|goes|drive|drives|end|ends|fall|falls|roll|rolls|slide|slides|wander|wanders|"
        "stray|strays|drift|drifts|ever gets|ever goes) (into|in|onto|up in|up on|on to|in to)",
        "(get|gets|come|comes|go|goes|drive|drives|stray|strays|ever gets|ever comes) within",
    )
)
#: Who the "if" clause of a consequence is about (the traveller).
CONSEQUENCE_SUBJECTS = frozenset("it we you he she they rover robot vehicle drone agv unit the our my".split())
#: Where a cost peaks, said of the ground next to something ("highest right next to it",
#: "worst at the water's edge"): a far cue, graded; its lowest there, a near one.
PEAK_WORDS = frozenset(
    {"highest", "dearest", "steepest", "heaviest", "strongest", "maximum", "max", "peak", "peaks", "heavy", "high"}
)
TROUGH_WORDS = frozenset({"lowest", "cheapest", "least"})
#: Words that put a peak right at the thing ("highest right next to it", "cheapest just by it").
PEAK_ADVERBS = frozenset({"right", "just", "directly", "immediately"})
#: Multiples in one word, before an equality phrase ("twice as good as", "half as bad as"):
#: wording, never an entity.
MULTIPLE_WORDS = {"twice": 2.0, "thrice": 3.0, "half": 0.5}
VOCAB: set[str] = set()
for _tab in (TRIGGERS, MODIFIERS, COMPARATORS, CONDITIONS, PROXIMITY, NEAR, FAR_WORDS, MARKERS, CONTACT_VERBS):
    for _cands in _tab.values():
        for _words, _ in _cands:
            VOCAB.update(_words)
VOCAB |= CENTRE | SIDE | set(SIDE_TOKENS) | SEPARATORS | set(UNITS) | set(NUMBER_WORDS) | ATTRACT_WORDS | REPEL_WORDS
VOCAB |= NARROWER_WORDS  # "the narrower the gap": wording, never a name
VOCAB |= REACH_KEYS | SHAPE_KEYS | GRADED_VALUES  # "mode": "graded" is wording
VOCAB |= NO_CONCERN_NOUNS | {"odd"}  # "it makes no odds": wording, never a name
VOCAB |= FEELING_WORSE | FEELING_BETTER | BOTHER_VERBS  # "the twitchier I get"
#: What a thing's state is said to be, never a name of it ("that old railway's disused"; "dead trees" are a kind).
FILLER |= frozenset({"disused", "defunct", "unused", "rusted", "retired"})
# "operation shall be confined to", "that thing does not go within 5 m"
FILLER |= frozenset({"operation", "operations", "operating", "device", "devices", "thing"})
#: Working machines: travellers (:data:`TRAVELLER_WORDS`), never entities ("I'd rather the
#: forwarder kept 5 m clear of the trees").
WORKING_MACHINES = frozenset(
    "forwarder harvester skidder forklift excavator digger loader dozer snowcat groomer scooter".split()
)
FILLER |= WORKING_MACHINES | {pluralise(w) for w in WORKING_MACHINES}
FILLER |= frozenset(
    "shuttle shuttles cart carts trolley trolleys tractor tractors wheelchair wheelchairs yo vibin vibing".split()
)
VOCAB |= {"falloff", "radius", "influence", "linear", "decay"} | set(MULTIPLE_WORDS) | PEAK_WORDS | TROUGH_WORDS
VOCAB |= {"spend", "spends", "spending", "rest", "belongs", "belong", "percent", "%"}  # shares of the route
VOCAB |= {"away", "least", "than", "distance", "line", "unless", "if", "followed", "by"}
VOCAB |= {"country", "offroad", "overland", "beaten"}  # idioms (claimed before entities)
VOCAB |= RULE_WORDS - {"hard"}  # "no exceptions" is wording, never an entity ("hard shoulder" may be)
VOCAB |= {"apart", "aside", "excluding", "excepting"}
VOCAB |= {"need", "needn't", "necessary", "unnecessary", "reason", "point", "required", "bother", "needed"}
VOCAB |= {"call", "restriction", "restrictions"}  # "no call to", "no restriction on": wording, never a name
VOCAB |= GIVE_VERBS | SOFTENERS | {"can", "manage", "manageable", "reasonably", "reasonable"}
VOCAB |= WITHIN_NOUNS | LESSEN_VERBS | GROW_VERBS | PROXIMITY_NOUNS | WIDE_WORDS | HUG_VERBS | APPROXIMATORS
VOCAB |= GAP_NOUNS | MIN_WORDS | {"maximum", "max", "most", "nearer", "closer", "further", "farther", "beyond"}
VOCAB |= RATHER_WORDS | COPULAS | CONDITION_VERBS | {"ever"} | set(SOFT_COMPARATORS)
VOCAB |= CORRELATIVE_GOOD | CORRELATIVE_BAD | CORRELATIVE_MORE | CORRELATIVE_LESS
VOCAB |= LESSENED | GROWN | COST_WORDS | RISE_VERBS | FALL_VERBS
VOCAB |= {w for p in REACH_OPENINGS for w in p}
VOCAB |= PRICED_WITHIN | REWARDED_WITHIN
VOCAB |= FALL_OFF_VERBS | FALL_OFF_PARTICLES | FALL_OFF_LEVELS | FALL_OFF_WHOLLY | FALL_OFF_PREPS | set(AIM_WORDS)
VOCAB |= {"level", "levels", "throughout", "dictate", "dictates", "full", "whole", "tight", "close"}
VOCAB |= MATTERING_WORDS | {"stops", "stop", "ceases", "longer"}
# the words of the cue constructs of sets 10-13 (never entities): "bias the planner toward",
# "as the route approaches", "an exclusion zone is to be enforced around", "proximity: reward"
VOCAB |= BIAS_VERBS | APPROACH_VERBS | ZONE_PASSIVE | PROXIMITY_PRICED | PROXIMITY_REWARDED
VOCAB |= {w for p in FAR_AFTER | NEAR_AFTER for w in p} | {"route", "planner", "longer", "which"}

#: The vehicle or its crew, which may stand between a verb and its particle ("keep the vehicle
#: off the grass", "keep it on the road") without breaking the phrase.
AGENT_INSERTS = frozenset(
    "the a an vehicle robot rover drone ugv truck car it us yourself yourselves ourselves them".split()
)
#: Adjectives a comparison can be built on ("less risky than", "safer than", "more dangerous
#: than"), with their valence: +1 the better the more of it, -1 the worse.
VALENCE: dict[str, int] = {
    **{
        w: +1
        for w in """good safe easy nice preferable desirable pleasant convenient fast quick comfortable
        suitable attractive appealing passable reliable smooth firm dry clear open""".split()
    },
    **{
        w: -1
        for w in """bad risky dangerous hard difficult slow unsafe unpleasant undesirable rough
        hazardous costly expensive treacherous muddy wet steep exposed""".split()
    },
}
#: Irregular comparatives.
COMPARATIVE_FORMS = {"better": "good", "worse": "bad"}
#: States a thing can be in: "only if the road is blocked" is a situation, not a preference
#: about the road.
#: States that take a hazard's danger away ("the railway is disused"); before a name with a
#: rule of its own ("Derelict buildings: off limits") they only say which ones (a qualifier).
SAFE_STATES = frozenset(
    "disused abandoned derelict unused decommissioned inactive unoccupied vacant ruined empty".split()
)
STATE_WORDS = frozenset(
    "blocked closed flooded unavailable jammed congested busy occupied damaged washed destroyed".split()
)
#: A condition negated before its place: "as long as it's not near Y" is "unless near Y".
CONDITION_NEGATORS = frozenset({"not", "never", "isn't", "aren't", "doesn't", "don't"})

#: Words that may stand inside a phrase without breaking it ("you can just wade through").
INSERTS = {
    "just",
    "also",
    "even",
    "ever",
    "still",
    "always",
    "sometimes",
    "probably",
    "perhaps",
    "maybe",
    "certainly",
    "only",
    "straight",  # "walking straight over the water is ok", "go right through"
    "right",
}
#: What a place is "too ..." for the mission ("the pine stands are way too dense", "the tarmac
#: gets too hot"): read with the avoiding "too", never an entity (kept out of VOCAB, so that
#: "muddy canal" and "dense forest" stay compounds).
UNFIT_ADJECTIVES = frozenset(
    """dense thick steep rough soft muddy wet hot narrow slippery busy exposed boggy overgrown deep bumpy
    rocky sandy icy crowded loose dusty slow risky dangerous""".split()
)
#: Table aliases that name an entity only when they stand alone: "the tracks" is the railway,
#: "muddy tracks" are tracks (open vocabulary).
AMBIGUOUS_SURFACES = {("tracks",)}
#: Nouns ending in -ly (everything else ending in -ly is an adverb: "safely", "quietly").
LY_NOUNS = {
    "gully",
    "family",
    "rally",
    "ally",
    "belly",
    "jelly",
    "lily",
    "holly",
    "assembly",
    "supply",
    "reply",
    "anomaly",
    "monopoly",
    "italy",
    "doily",
    "bully",
    "folly",
}

#: Contractions typed without their apostrophe (phones, quick notes), read as written with it:
#: "shouldnt" must stay a negation, never be "corrected" into "should".
BARE_CONTRACTIONS = {
    w.replace("'", ""): w
    for w in """don't can't won't isn't aren't doesn't didn't shouldn't wouldn't couldn't mustn't
    mightn't needn't wasn't weren't hasn't haven't it's that's there's you're we're they're
    i'm i'd you'd we'd let's""".split()
    if w not in ("it's",)  # "its" is also the possessive
} | {
    # typed in a hurry: grammar words with their letters swapped, and texting shorthand
    "teh": "the",
    "hte": "the",
    "adn": "and",
    "nad": "and",
    "thru": "through",
    "nogo": "no go",
    "sep": "separation",
    "tho": "though",
    "yr": "year",
    "u": "you",
    "ur": "your",
    "pls": "please",
    "plz": "please",
    "cos": "because",
    "coz": "because",
    "bc": "because",
    "w": "with",
    "r": "are",
    "frm": "from",
    "abt": "about",
    "atleast": "at least",
    "incase": "in case",
    "alot": "a lot",
    # field notes' abbreviations of terrain words
    "bldg": "building",
    "bldgs": "buildings",
    "rd": "road",
    "rds": "roads",
    "hwy": "highway",
    "veg": "vegetation",
    "rly": "railway",  # as British maps and timetables abbreviate it
    "clr": "clearance",
    "dist": "distance",  # "min dist to trees 3 mtrs"
    "ppl": "people",
    "rail": "railway",
    "pref": "prefer",
    "outta": "out of",
    # chat words no vowel-dropping explains ("k thx", "nvr go in2 any bldg", "H2O: 20 m")
    "thx": "thanks",
    "thnx": "thanks",
    "ty": "thanks",
    "in2": "into",
    "on2": "onto",
    "h2o": "water",
    # speech written as said: "give 'em some room", "keep it back fae the burn, dinnae fash"
    "'em": "them",
    "em": "them",
    "fae": "from",
    "frae": "from",
    "ye": "you",
    "tae": "to",  # Scots: "the closer ye get tae them"
    "gud": "good",  # "treez bad, gras gud"
    "gd": "good",  # "grass: gd"
    "nr": "near",  # "stay nr the railwy"
    "di": "the",  # Jamaican: "walk di robot side-a di railway"
    "o": "of",  # "eight metres o' the railway"
    "awa": "away",  # "keep awa' frae the buildings"
    "dinnae": "don't",
    "didnae": "didn't",
    "cannae": "can't",
    "wouldnae": "wouldn't",
    "shouldnae": "shouldn't",
    "isnae": "isn't",
    "fash": "worry",  # "dinnae fash": don't worry
}

#: Tokens: numbers, words (with one inner apostrophe), punctuation that separates.
TOKEN_RE = re.compile(
    r"[✓✔✅👍✗✘❌👎⛔🚫]|\bh2o\b|\b(?:in|on)2\b|\d+(?:\.\d+)?|[^\W\d_]+(?:'[^\W\d_]+)?|>+|<+|\++|-{2,}"
    r"|-(?=[ \t]*(?:[,;|\n]|$))"  # a lone dash only where it ends a list item ("grass -, trees --")
    r"|[≥≤~%]|[,;:.!?&/|\n]"
)
#: A verdict written as signs after a topic's mark ("road: ++", "water: --"): its word.
SIGN_VERDICTS = {"+": "good", "++": "preferred", "+++": "preferred", "--": "avoid", "---": "avoid"}
#: Signs that end a list item with no mark before them ("trail +, grass -, trees --"): a lone "-"
#: is a little worse than fine there (never elsewhere: a dash).
ITEM_SIGNS = {**SIGN_VERDICTS, "-": "meh"}
#: Marks a list writes as verdicts ("rd ✓ | rly ✗", "along the field ✅"): their words.
MARK_VERDICTS = {
    "✓": "good",
    "✔": "good",
    "✅": "good",
    "👍": "good",
    "✗": "no",
    "✘": "no",
    "❌": "no",
    "👎": "no",
    "⛔": "forbidden",
    "🚫": "forbidden",
}
#: Words whose "'s" is not a possessive.
KEEP_S = {"it's", "let's", "that's", "there's", "what's", "here's", "he's", "she's"}
#: People whose possessive only points at a thing ("anybody's house", "the neighbour's shed").
POSSESSORS = frozenset(
    "anybody anyone somebody someone everybody everyone nobody people folks neighbour neighbor owner farmer".split()
)


# ----------------------------------------------------------------------------- spelling
#: One-word surfaces of the entity table, the candidates of spelling correction ("tracks"
#: is left out: a near-miss of it is more likely "trucks" than the railway).
_ONE_WORD = {form[0]: name for form, name in SURFACE.items() if len(form) == 1 and form not in AMBIGUOUS_SURFACES}
#: Similarity (difflib's ratio) a word of 5+ letters needs to be read as an entity word: one
#: dropped, doubled or swapped letter in a long word passes ("vegitation", "buidlings"); one
#: changed letter in a short word does not ("grass"/"glass", "woods"/"words" stay apart).
SPELLING_RATIO = 0.85


def _swapped(a: str, b: str) -> bool:
    """Whether ``a`` is ``b`` with two neighbouring letters swapped ("raod" / "road")."""
    if len(a) != len(b) or a == b:
        return False
    diff = [i for i in range(len(a)) if a[i] != b[i]]
    return len(diff) == 2 and diff[1] == diff[0] + 1 and a[diff[0]] == b[diff[1]] and a[diff[1]] == b[diff[0]]


def _one_deleted(short: str, long: str) -> bool:
    """Whether ``short`` is ``long`` with one letter dropped ("gras" / "grass")."""
    return len(long) == len(short) + 1 and any(long[:i] + long[i + 1 :] == short for i in range(len(long)))


def correct_spelling(word: str) -> tuple[str, str] | None:
    """``(surface, entity)`` for a misspelt entity word, else None.

    Only words the interpreter would otherwise take for an unknown name are tried (grammar and
    phrase words never are), and only against entity words with the same first letter (typing
    slips rarely hit the first letter; "reaches" is not "beaches"). A swap of two neighbouring
    letters counts for any word of 4+ letters, one dropped letter for a 4-letter word ("gras");
    otherwise difflib's similarity must reach :data:`SPELLING_RATIO` (0.8 from 6 letters, where
    one changed letter is a typo: "streat"); the best match wins, ties to the alphabetically
    first. difflib (standard library) measures the similarity: a spelling library would bring a
    dictionary of general English, whose corrections ("raod" -> "rad") know nothing of terrain.
    A word that is never terrain ("trains", "batteries") is no slip for one ("trail").
    """
    if word in NON_TERRAIN or singularise(word) in NON_TERRAIN:
        return None
    return _closest(word, _ONE_WORD)


def correct_phrase_word(word: str) -> str | None:
    """A misspelt word of the phrase tables ("folow" -> "follow", "avoud" -> "avoid"), by the
    same rules as :func:`correct_spelling`, else None; a word never terrain is no slip ("trains")."""
    if word in NON_TERRAIN or singularise(word) in NON_TERRAIN:
        return None
    if len(word) > 4 and word.endswith("ly"):  # an adverb is no slip of its adjective ("heavily")
        return None
    known = word in FILLER or word in VOCAB or word in NOT_TYPOS or word in NON_TERRAIN or (word,) in SURFACE
    if len(word) == 4 and word.isalpha() and not known:
        # one vowel typed for another in a short word ("neer" -> "near", "stey" -> "stay"), the
        # likelier slip before a dropped letter ("neer" is "near" sooner than "never")
        hits = [c for c in sorted(_SHORT_PHRASE_WORDS) if _vowel_slip(word, c)]
        if len(hits) == 1:
            return hits[0]
    hit = _closest(word, _PHRASE_WORDS)
    return hit[0] if hit else None


def _vowel_slip(a: str, b: str) -> bool:
    """Whether ``a`` is ``b`` with one vowel (not the first letter) replaced by another vowel."""
    diff = [i for i in range(len(a)) if a[i] != b[i]]
    return len(diff) == 1 and diff[0] > 0 and a[diff[0]] in "aeiou" and b[diff[0]] in "aeiou"


def _closest(word: str, table: dict[str, str]) -> tuple[str, str] | None:
    from difflib import SequenceMatcher

    if len(word) < 4 or not word.isalpha() or word in FILLER or word in VOCAB or word in NOT_TYPOS:
        return None
    if (word,) in SURFACE:
        return None
    best: tuple[float, str] | None = None
    for cand in sorted(table):
        if cand[0] != word[0] or abs(len(cand) - len(word)) > 2:
            continue
        if abs(len(word) - len(cand)) == 2 and (word.startswith(cand) or cand.startswith(word)):
            continue  # a word of its own, not a slip: two letters more or fewer ("cabinet", "corner")
        if _swapped(word, cand) or (len(word) == 4 and _one_deleted(word, cand)):
            score = 1.0
        elif len(word) >= 5:
            score = SequenceMatcher(None, word, cand).ratio()
            if score < (SPELLING_RATIO if len(word) == 5 else LONG_SPELLING_RATIO):
                continue
        else:
            continue
        if best is None or score > best[0]:
            best = (score, cand)
    return (best[1], table[best[1]]) if best else None


def correct_surface(words: tuple[str, ...]) -> str | None:
    """The entity of a name of two or more words typed with slips ("basebal feild", "pavd
    road", "unpavd road"), else None: every word is the name's word or one slip from it (two
    neighbouring letters swapped, one letter dropped or added, or, from 5 letters, difflib's
    similarity of :data:`LONG_SPELLING_RATIO`), with its first letter, and is no grammar word;
    the closest name wins. One-word names are :func:`correct_spelling`'s."""
    from difflib import SequenceMatcher

    best: tuple[float, str] | None = None
    for form, name in _MULTI_WORD.get(len(words), ()):
        slips = [w != f for w, f in zip(words, form)]
        if not any(slips) or not all(w == f or _slip(w, f) for w, f in zip(words, form)):
            continue
        score = SequenceMatcher(None, " ".join(words), " ".join(form)).ratio()
        if best is None or score > best[0]:
            best = (score, name)
    return best[1] if best else None


def _slip(word: str, form: str) -> bool:
    """Whether ``word`` is one typing slip from the name word ``form`` (see :func:`correct_surface`)."""
    from difflib import SequenceMatcher

    if len(word) < 3 or not word.isalpha() or word[0] != form[0]:
        return False
    if word in FILLER or word in VOCAB or word in NOT_TYPOS:
        return False
    if _swapped(word, form) or _one_deleted(word, form) or _one_deleted(form, word):
        return True
    return len(word) >= 5 and SequenceMatcher(None, word, form).ratio() >= LONG_SPELLING_RATIO


#: English words a letter or two from an entity word that are words in their own right, never
#: typos of it ("weather permitting" is not "water").
NOT_TYPOS = frozenset(
    "shaded shady weather whether rather later latter leather feather heather border order tower power stand stands "
    # English words a slip away from a phrase word ("unstable" is no slip of "usable")
    "unstable stable reliable unreliable suitable unsuitable undercut stack stacks "
    # things on the ground a slip away from an entity word ("beehives" is no slip of "beeches")
    "beehive beehives hive hives "
    "planted planting".split()  # "every planted bed" is no "planned" one
)
#: The entity table's names of two or more words, by their number of words.
_MULTI_WORD: dict[int, list[tuple[tuple[str, ...], str]]] = {}
for _form, _name in sorted(SURFACE.items()):
    if len(_form) > 1:
        _MULTI_WORD.setdefault(len(_form), []).append((_form, _name))
#: Similarity a word of 6+ letters needs (one changed letter in six: 0.83).
LONG_SPELLING_RATIO = 0.8
#: Words of the trigger and modifier tables, 5+ letters: the verbs and adjectives of preference.
_PHRASE_WORDS = {
    w: w
    for tab in (TRIGGERS, MODIFIERS, COMPARATORS, IDIOMS)
    for cands in tab.values()
    for words, _ in cands
    for w in words
    if len(w) >= 5 and w.isalpha()
}
#: The short words of keeping near or away, the candidates of a vowel slip ("neer", "stey"):
#: few, because one changed vowel turns many English words into others ("fuel" / "feel").
_SHORT_PHRASE_WORDS = frozenset({"near", "stay", "keep", "away", "hold"})

# ----------------------------------------------------------------------------- self-corrections
#: Markers that withdraw what was said just before them ("avoid the vegetation -- no wait, ...",
#: "stay out of the buildings -- actually, scratch that, ..."): :mod:`interpret.corrections`.
WITHDRAWALS = frozenset(
    tuple(p.split())
    for p in (
        "no wait",
        "wait no",
        "scratch that",
        "strike that",
        "forget that",
        "ignore that",
        "cancel that",
        "disregard that",
        "on second thought",
        "on second thoughts",
        "correction",
    )
)
#: Markers that put a name in place of the one just said ("sorry, I mean the trail", "no, make
#: that the track"): only after one of :data:`CORRECTION_LEADS`.
REPLACEMENTS = frozenset(tuple(p.split()) for p in ("i mean", "i meant", "make that", "or rather", "rather"))
#: Words and marks around a correction's marker ("sorry, ...", "actually, ...", "oops, no, ...").
CORRECTION_LEADS = frozenset({",", ":", "sorry", "actually", "no", "oh", "oops", "er", "erm", "um", "uh", "i", "mean"})
#: How a cleft naming the one meant ends ("it's the water I meant", "it was the pond we meant").
CLEFT_ENDS = frozenset(tuple(p.split()) for p in ("i meant", "i mean", "we meant", "we mean"))
#: Condition words an availability verb is read with ("if the trail goes where we're headed").
AVAILABILITY_CONDITIONS = frozenset({"if", "when", "whenever", "where", "wherever"})

# ----------------------------------------------------------------------------- texting
#: Amounts said in words that a distance may be ("half a dozen metres", "a couple of metres"):
#: their number (:func:`interpret.tokens._amounts`).
AMOUNTS = {
    ("half", "a", "dozen"): "6",
    ("a", "dozen"): "12",
    ("a", "couple", "of"): "2",
    ("a", "couple"): "2",
    ("a", "hundred"): "100",
}
#: Who or what is kept somewhere in "keep it out of the trees", "keep the sedan on paved road":
#: the traveller, never terrain (:func:`interpret.tokens._kept_object` drops it).
TRAVELLER_WORDS = (
    frozenset(
        "robot robots rover rovers vehicle vehicles drone drones truck trucks car cars sedan van vans ugv ugvs "
        "bot bots machine machine unit units convoy team crew wheelchair chair bike bikes quad atv buggy tractor "
        "rig rigs mower mowers agv agvs horse horses mare mares pony ponies cart carts trolley trolleys "
        # the vehicle's parts that touch the ground: "keep its wheels off the grass"
        "wheels tyres tires "
        "device devices".split()  # "the device shall not enter them"
    )
    | WORKING_MACHINES
)
#: Who a gap is kept from, in "leave a bit of room between you and the tracks", "no less than 50
#: ft between the route and the water": the route's own side of the gap.
ROUTE_SELVES = (
    frozenset({"you", "us", "yourself", "yourselves", "me", "it", "the", "route", "path", "trajectory", "track"})
    | TRAVELLER_WORDS
)
#: The verbs and prepositions around that object ("keep ... out of", "get ... off", "stick ... to").
KEEP_OBJECT_VERBS = frozenset({"keep", "keeps", "keeping", "get", "gets", "getting", "stick", "sticks", "hold"})
KEEP_OBJECT_PREPS = frozenset("out off on to away clear within in inside onto along close near snug tight".split())
_VOWELS = frozenset("aeiou")
#: The qualified kinds' words and their qualities ("paved", "unpaved").
_QUALIFYING = frozenset(QUALIFIER_WORDS | {"paved", "unpaved", "coniferous", "deciduous"})


def _skeleton(word: str) -> str:
    """A word with its vowels dropped, as texting writes it ("never" -> "nvr", "paved" -> "pvd")."""
    return "".join(ch for ch in word if ch not in _VOWELS)


#: Words a texter writes without vowels, by skeleton: entity words, the qualified kinds' words
#: and the phrase tables' words (a skeleton two of them share is no reading: left out).
def _skeletons() -> dict[str, str]:
    words = set(_ONE_WORD) | _QUALIFYING | set(_PHRASE_WORDS) | {"never", "avoid", "into", "onto"}
    by: dict[str, set[str]] = {}
    for w in words:
        by.setdefault(_skeleton(w), set()).add(w)
    return {s: next(iter(ws)) for s, ws in by.items() if len(ws) == 1 and len(s) >= 2}


SKELETONS = _skeletons()
_QUALIFYING_TABLE = {q: q for q in _QUALIFYING}  # the candidates of a qualifier's slip


def read_texting(word: str) -> str | None:
    """The word a texted one stands for: a word written without its vowels ("nvr" -> "never",
    "pvd" -> "paved"), or a qualified kind's word with one slip ("unpavd" -> "unpaved"); None for
    a word the tables know, or one with no such reading. Chat abbreviations ("thx", "in2") are
    :data:`BARE_CONTRACTIONS`', read before this."""
    if not word.isalpha() or word in FILLER or word in VOCAB or word in NON_TERRAIN or (word,) in SURFACE:
        return None
    if not _VOWELS & set(word):
        return SKELETONS.get(word)
    if len(word) > 3 and word[-1] == "r" and word[-2] not in _VOWELS and word[:-1] + "er" in VOCAB:
        return word[:-1] + "er"  # a comparative without its "e": "closr", "cheapr"
    hit = _closest(word, _QUALIFYING_TABLE)
    return hit[0] if hit else None


#: "grass costs 2x road": the multiple's "x" is no name (interpret.levels).
VOCAB.add("x")
#: "forget the trail rule", "ignore the water bit": verbs that revoke what was said of an entity
#: and the nouns that name it (:mod:`interpret.corrections`).
REVOKE_VERBS = frozenset({"forget", "ignore", "drop", "scrap", "cancel", "scratch", "disregard", "strike"})
REVOKED_NOUNS = frozenset({"rule", "rules", "bit", "part", "instruction", "instructions", "constraint", "requirement"})
