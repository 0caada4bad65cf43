"""The offline interpreter's vocabulary: entity table (geometry, part-of parent, aliases) and weights.

These tables are the documentation: what the offline interpreter knows is exactly what is listed
here. Everything else in a prompt is either grammar (``FILLER``) or reported back as unparsed.

Weights here are ordinal keys (lower = preferred); :mod:`.merge` turns them into ranks and into
levels on the cost scale (``NEUTRAL`` = 0.5 is unmentioned and unlabelled ground, preferred below,
avoided above, lethal impassable; see ``costlang/LANGUAGE.md``):

==========  ======  ===================================================================
tier        key     phrases (examples)
==========  ======  ===================================================================
prefer      0.10    prefer, best, ideal, stay on, stick to, use, keep to, great
fine        0.50    fine, okay, acceptable, allowed, can go under, you may cross, dry
                    (= neutral: permission is no preference either way)
tolerable   0.60    tolerable, if needed, if necessary, as a last resort, not ideal
avoid       0.85    avoid, stay off, keep away from, don't, should not, dangerous
avoid+      0.95    avoid ... as much as possible / whenever possible / strictly
lethal      1.00    never, forbidden, impassable, off limits, at all costs, must not
==========  ======  ===================================================================

An entity the prompt gives no preference -- one of the default set the segmenter always looks
for, or one named only in a cue -- is ``NEUTRAL``: no invented preference.

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

from dataclasses import dataclass

from ..schema import DEFAULT_ENTITIES

# ----------------------------------------------------------------------------- weights
PREFER = 0.10
#: The neutral level of the cost scale: unmentioned entities, unlabelled ground, "X is fine".
NEUTRAL = 0.5
FINE = NEUTRAL
TOLERABLE = 0.60
AVOID = 0.85
STRONG_AVOID = 0.95
LETHAL = 1.0
#: Distance between neighbours in an ordering ("first X, then Y"; "X is better than Y").
STEP = 0.10
#: Highest weight an ordering may give (orderings stay on the preferred side of neutral).
ORDER_MAX = 0.45
#: Distance in metres for "near X" / "unless near X" / "far from X" when the prompt gives none.
DEFAULT_CUE_DISTANCE_M = 10.0

#: Tier name -> (weight, lethal).
TIERS: dict[str, tuple[float, bool]] = {
    "prefer": (PREFER, False),
    "fine": (FINE, False),
    "tolerable": (TOLERABLE, False),
    "avoid": (AVOID, False),
    "avoid+": (STRONG_AVOID, False),
    "lethal": (LETHAL, True),
}
#: How strongly a tier speaks against an entity; when triggers stand together the highest wins
#: ("don't use" = avoid, "never use" = lethal).
SEVERITY = {"prefer": 0, "fine": 1, "tolerable": 2, "avoid": 3, "avoid+": 4, "lethal": 5}


# ----------------------------------------------------------------------------- entities
@dataclass(frozen=True)
class Known:
    """One entity the offline interpreter knows by name."""

    name: str
    geometry: str
    parent: str | None = None
    aliases: tuple[str, ...] = ()
    #: Extra text prompts for the segmenter (the name itself always comes first).
    prompts: tuple[str, ...] = ()


def _k(name, geometry, parent=None, aliases=(), prompts=()):
    return Known(name, geometry, parent, tuple(aliases), tuple(prompts))


_DEFAULT_ALIASES = {
    "road": ("roadway", "paved road", "asphalt road", "tarmac"),
    # "dirt tracks" are trails; a bare "tracks" is the railway (see railway below)
    "trail": ("dirt trail", "hiking trail", "dirt track", "gravel track", "farm track",
              "forest track", "jeep track", "vehicle track"),
    "grass": ("grassland", "grassy area", "grass area", "grass field", "grassy field", "grassy",
              "turf"),
    "tree": ("tree canopy", "treeline", "tree line", "tree cover", "canopy", "canopy cover"),
    "building": ("structure", "built-up area"),
    "water": ("water body", "body of water", "waterbody", "open water"),
}

KNOWN: tuple[Known, ...] = tuple(
    _k(name, geom, None, _DEFAULT_ALIASES.get(name, ())) for name, geom in DEFAULT_ENTITIES
) + (
    # inside grass
    _k("baseball field", "areal", "grass", ("baseball diamond", "ballfield", "ball field",
                                            "baseball pitch")),
    _k("football field", "areal", "grass", ("football pitch",)),
    _k("soccer field", "areal", "grass", ("soccer pitch",)),
    _k("sports field", "areal", "grass", ("playing field", "sports pitch", "athletic field")),
    _k("lawn", "areal", "grass"),
    _k("park", "areal", "grass"),
    _k("meadow", "areal", "grass"),
    _k("golf course", "areal", "grass"),
    _k("field", "areal", "grass"),
    # inside water
    _k("river", "linear", "water", ("riverbed", "river bed")),
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
    _k("parking lot", "areal", "road", ("car park", "parking area", "parking space", "parking")),
    # inside trail
    _k("path", "linear", "trail", ("dirt path",)),
    _k("footpath", "linear", "trail", ("foot path", "walkway", "footway")),
    _k("bike path", "linear", "trail", ("bicycle path", "cycle path", "cycleway", "bike trail")),
    # inside tree
    _k("forest", "areal", "tree", ("woods", "woodland")),
    _k("orchard", "areal", "tree"),
    # inside building
    _k("house", "areal", "building", ("home",)),
    _k("shed", "areal", "building"),
    _k("garage", "areal", "building"),
    _k("barn", "areal", "building"),
    _k("warehouse", "areal", "building"),
    # entities of their own
    _k("electric tower", "areal", None,
       ("electrical tower", "electricity tower", "transmission tower", "power tower", "pylon",
        "power pylon", "electricity pylon", "electric pylon", "lattice tower", "utility tower"),
       ("electric tower", "transmission tower", "pylon")),
    _k("power line", "linear", None, ("powerline", "transmission line", "electric line",
                                      "overhead line", "power cable")),
    # a bare "tracks" means the railway ("stay off the tracks"); "dirt/farm tracks" are trails
    _k("railway", "linear", None, ("railroad", "rail track", "rail line", "train track",
                                   "railway track", "railroad track", "railway line", "tracks")),
    _k("level crossing", "areal", None, ("railway crossing", "railroad crossing", "rail crossing",
                                         "grade crossing", "train crossing"),
       ("level crossing", "railroad crossing")),
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
    _k("bare soil", "areal", None, ("bare ground", "soil")),
    _k("open ground", "areal", None, ("open terrain", "open land", "open country", "open area")),
    _k("crop field", "areal", None, ("farmland", "cropland", "crops", "farm field", "agricultural field")),
    _k("wetland", "areal", None, ("marsh", "swamp", "bog")),
    _k("vegetation", "areal"),
    _k("playground", "areal"),
    _k("tennis court", "areal"),
    _k("basketball court", "areal"),
    _k("construction site", "areal"),
    _k("solar panel", "areal", None, ("solar farm",)),
    _k("car", "areal", None, ("parked car",)),
)

KNOWN_BY_NAME: dict[str, Known] = {k.name: k for k in KNOWN}

#: Head words (last word of a name) that make an unknown entity linear.
LINEAR_HEADS = frozenset({
    "road", "street", "highway", "trail", "path", "footpath", "track", "lane", "line", "river",
    "stream", "creek", "canal", "ditch", "railway", "railroad", "rail", "fence", "wall", "hedge",
    "pipeline", "cable", "route", "corridor", "sidewalk", "bridge", "avenue", "boulevard", "way",
})


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


def geometry_of(name: str) -> str:
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
