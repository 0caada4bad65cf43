"""Match the entities a prompt names to the layers a costmap is built from.

Layers are class names from ``classes.json``, vector layer names and mask bands; prompts say
"paved road", "lake" or "tree cover". Matching is tried in this order, and the first rule that
finds any layer decides (each match records its rule, so the mapping can be printed and kept in
the manifest):

1. ``alias``: the user said so (``--alias lake=water``);
2. ``name``: equal after normalisation (case, spaces, punctuation, plural of each word;
   a class label's parenthetical and ``a/b`` alternatives are separate names:
   "water (Hydro)" answers to "water" and "hydro");
3. ``synonym``: both names belong to one group of :data:`SYNONYMS` or of the interpreter's
   entity table (``lexicon``: "woods" is "forest", "railroad" is "railway");
4. ``modifier``: one name is the other with modifiers in front: the entity "paved road" matches a
   "road" layer, and the entity "road" matches every "... road" layer ("paved road" and
   "unpaved road"). Rules 3 and 4 are tried together (all their layers count);
5. ``broader``: the entity is drawn as a layer (:data:`DRAWN_AS`: a trail on a map of paved and
   unpaved roads is the unpaved road), or is a kind of a layer: part-of parents from the interpreter's table
   ("lake" inside "water", "baseball field" inside "grass") and :data:`BROADER` ("grass",
   "tree", "bush" are "vegetation"), followed upwards.

An entity that matches nothing is "unmatched"; the cost stage warns when the prompt ranked it.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

from overseec_core.interpret import lexicon

#: Terrain words that name the same thing on an aerial image (each group is one meaning).
SYNONYMS: tuple[frozenset[str], ...] = tuple(
    frozenset(g)
    for g in (
        {"water", "hydro", "hydrography", "water body", "open water", "surface water"},
        {"tree", "tree crown", "tree cover", "tree canopy", "canopy", "wood", "woodland", "forest", "forested area"},
        {"road", "roadway", "street", "carriageway"},
        {"railway", "railroad", "rail", "train", "rail track", "train track", "railway track", "track"},
        {"building", "structure", "built up area", "house"},
        {"vegetation", "greenery", "plant", "green area"},
        {"grass", "grassland", "lawn", "turf"},
        {"bush", "shrub", "scrub", "shrubland", "brush"},
        {"bare soil", "bare ground", "soil", "dirt"},
        {"trail", "path", "footpath"},
    )
)
#: Broader classes an entity falls under when no layer names it (child -> parent).
BROADER: dict[str, str] = {
    "grass": "vegetation",
    "tree": "vegetation",
    "bush": "vegetation",
    "forest": "vegetation",
    "meadow": "vegetation",
    "crop field": "vegetation",
    "hedge": "bush",
    "wetland": "water",
    "parking lot": "road",
    "highway": "road",
    "street": "road",
    "level crossing": "railway",
    "house": "building",
    "shed": "building",
    "garage": "building",
    "barn": "building",
    "warehouse": "building",
}
#: Where a kind of way has no layer of its own, the layer it is drawn in (a trail or bare dirt on
#: a map of paved and unpaved roads is the unpaved road), tried before broader classes.
DRAWN_AS: dict[str, tuple[str, ...]] = {
    "trail": ("unpaved road", "unpaved", "dirt road", "gravel road", "track"),
    "bare soil": ("unpaved road", "unpaved", "dirt road"),
}
RULES: tuple[str, ...] = ("alias", "name", "synonym", "modifier", "broader")


@dataclass(frozen=True)
class Match:
    """One entity's layers (empty when unmatched) and the rule that found them."""

    entity: str
    layers: tuple[str, ...]
    rule: str  # one of RULES, or "unmatched"
    #: For ``broader``: how many steps up the layer is (1 = the parent; "baseball field" ->
    #: grass -> vegetation is 2), so a nearer kind wins a shared layer.
    depth: int = 0

    def describe(self) -> str:
        if not self.layers:
            return f"{self.entity} -> unmatched"
        return f"{self.entity} -> {', '.join(self.layers)} ({self.rule})"

    def to_json(self) -> dict:
        return {"entity": self.entity, "layers": list(self.layers), "rule": self.rule}


def normalise(name: str) -> str:
    """Lower case, punctuation as spaces, each word singular: 'Paved-Roads' -> 'paved road'."""
    words = re.sub(r"[^0-9a-z]+", " ", str(name).lower()).split()
    return " ".join(lexicon.singularise(w) for w in words)


def layer_names(label: str) -> set[str]:
    """The normalised names one layer answers to: the label, its parenthetical and alternatives.

    'water (Hydro)' -> {'water', 'hydro'}; 'background/unlabeled' -> {'background', 'unlabeled'};
    'tree crown (bounding box)' -> {'tree crown', 'bounding box'} (parentheticals that are notes
    rather than names never equal an entity, so keeping them is harmless).
    """
    text = str(label)
    parts = re.findall(r"\(([^)]*)\)", text)
    base = re.sub(r"\([^)]*\)", " ", text)
    names = {normalise(p) for chunk in [base, *parts] for p in chunk.split("/")}
    return {n for n in names if n}


def _canonical(name: str) -> set[str]:
    """Every meaning a normalised name has: its synonym groups and its entity-table name."""
    out = {name}
    words = tuple(name.split())
    # "deciduous forest", "coniferous stands": the qualified kind a qualifier and a head name
    surface = lexicon.SURFACE.get(words) or (lexicon.qualified_head(*words) if len(words) == 2 else None)
    surface = surface or _modified_surface(words)
    if surface:
        out.add(normalise(surface))
    for group in SYNONYMS:
        if out & group:
            out |= group
    return out


def _modified_surface(words: tuple[str, ...]) -> str | None:
    """The entity a name ends in when the words before it only modify it ("sealed asphalt road":
    an asphalt road, the paved one; "graded unpaved road": the unpaved one), the longest such
    ending; None when a word before it negates it ("non paved road") or nothing known ends it."""
    for k in range(1, len(words)):
        if NEGATIONS & set(words[:k]):
            return None
        if (kind := lexicon.SURFACE.get(words[k:])) is not None:
            return kind
    return None


def _layer_meanings(name: str) -> set[str]:
    """What a layer's name answers to: its meanings, and for a qualified kind
    (:data:`~overseec_core.interpret.lexicon.QUALIFIED_KINDS`) those of the kind it qualifies:
    "paved road" is a road, so it answers to "street". The entity side is not widened: tarmac
    never lands on an "unpaved road" layer."""
    words = tuple(name.split())
    kind = lexicon.SURFACE.get(words) or (lexicon.qualified_head(*words) if len(words) == 2 else None)
    parent = lexicon.parent_of(kind) if kind in lexicon.QUALIFIED_KINDS else None
    if parent is None:
        return _canonical(name)
    return _canonical(name) | _canonical(normalise(parent))


def meanings(name: str) -> set[str]:
    """Every normalised name ``name`` stands for: itself, its entity-table name and synonyms."""
    return _canonical(normalise(name))


#: Words that make a modified name the opposite of its head ("non road" is not a road).
NEGATIONS = frozenset({"non", "not", "no", "without", "except"})


def _modifies(longer: str, head: str) -> bool:
    """'paved road' is 'road' with a modifier in front; 'non road' is not."""
    if longer == head or not longer.endswith(" " + head):
        return False
    return not NEGATIONS & set(longer[: -len(head)].split())


def _broader(name: str) -> list[str]:
    """Broader names, nearest first: 'baseball field' -> ['grass', 'vegetation']."""
    out: list[str] = []
    node: str | None = name
    while node is not None:
        parent = lexicon.parent_of(node) or next((BROADER[n] for n in sorted(_canonical(node)) if n in BROADER), None)
        node = normalise(parent) if parent else None
        if node is None or node == name or node in out:  # a synonym may lead back: stop there
            break
        out.append(node)
    return out


def match_entity(entity: str, layers: Sequence[str], aliases: Mapping[str, str] | None = None) -> Match:
    """The layers ``entity`` stands for, by the first rule that finds any (see the module doc)."""
    want = normalise(entity)
    names = {layer: layer_names(layer) for layer in layers}
    for key, target in (aliases or {}).items():
        if normalise(key) == want:
            hits = tuple(layer for layer in layers if normalise(target) in names[layer])
            if hits:
                return Match(entity, hits, "alias")
    hits = tuple(layer for layer in layers if want in names[layer])
    if hits:
        return Match(entity, hits, "name")
    meanings = _canonical(want)
    synonym = [layer for layer in layers if meanings & {m for n in names[layer] for m in _layer_meanings(n)}]
    modifier = [layer for layer in layers if any(_modifies(want, n) or _modifies(n, want) for n in names[layer])]
    hits = tuple(layer for layer in layers if layer in synonym or layer in modifier)
    if hits:
        return Match(entity, hits, "synonym" if synonym else "modifier")
    drawn = tuple(layer for layer in layers if names[layer] & set(DRAWN_AS.get(want, ())))
    if drawn:
        return Match(entity, drawn, "broader", 1)
    for depth, broader in enumerate(_broader(want), start=1):
        hits = tuple(layer for layer in layers if broader in names[layer] or _canonical(broader) & names[layer])
        if hits:
            return Match(entity, hits, "broader", depth)
    return Match(entity, (), "unmatched")


def match_entities(
    entities: Iterable[str], layers: Sequence[str], aliases: Mapping[str, str] | None = None
) -> tuple[Match, ...]:
    """:func:`match_entity` for each entity, in order."""
    return tuple(match_entity(e, layers, aliases) for e in entities)


def parse_alias(spec: str) -> tuple[str, str]:
    """'lake=water' -> ('lake', 'water'); ValueError with a one-line message otherwise."""
    entity, sep, layer = spec.partition("=")
    if not sep or not entity.strip() or not layer.strip():
        raise ValueError(f"--alias {spec!r}: write ENTITY=LAYER, e.g. --alias lake=water")
    return " ".join(entity.split()).lower(), " ".join(layer.split()).lower()


def parse_aliases(text: str) -> tuple[tuple[str, str], ...]:
    """'lake=water, woods=tree' (commas or semicolons) -> (('lake', 'water'), ('woods', 'tree'))."""
    return tuple(parse_alias(part) for part in text.replace(";", ",").split(",") if part.strip())
