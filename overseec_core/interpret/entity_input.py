"""The one parser of entities a user names: ``road:linear``-style text and entity JSON files.

Used by the CLI (`overseec segment --entity/--entities-json`) and the QGIS plugin (the entity
field and file of the dock and the Processing algorithms), so the same text means the same
entities everywhere.

The rule for a name without a geometry (``grass`` rather than ``grass:areal``), in text and in
JSON alike: the geometry the interpreter would give it, from the lexicon
(:func:`overseec_core.interpret.lexicon.geometry_of`: known names, then the head word, so
``road`` and ``dirt track`` are linear, ``tree`` and ``baseball field`` areal; areal when
nothing is known). An explicit geometry always wins.

It lives beside :mod:`overseec_core.schema` rather than in it because it asks the lexicon, which
itself builds on the schema (the schema stays the ground module, importing nothing of ours).
"""

from __future__ import annotations

import os
from pathlib import Path

from overseec_core.errors import InputError
from overseec_core.interpret.lexicon import geometry_of
from overseec_core.limits import MAX_JSON_BYTES, read_json_limited
from overseec_core.schema import Entity, is_geometry


def parse_entity(text: str, what: str = "--entity") -> Entity:
    """``'road:linear'`` | ``'baseball field:areal'`` | ``'tree'`` (geometry from the lexicon).

    ``what`` names the source in error messages (an option, a form field).
    """
    name, sep, geometry = text.rpartition(":")
    if not sep:
        name = text
        geometry = geometry_of(text.strip().lower())
    name, geometry = name.strip(), geometry.strip().lower()
    if not is_geometry(geometry):
        raise InputError(f"{what} {text!r}: geometry must be linear or areal (e.g. road:linear)")
    if not name:
        raise InputError(f"{what} {text!r}: empty entity name")
    return Entity(name=name, geometry=geometry)


def parse_entity_list(text: str, what: str = "entity") -> list[Entity]:
    """``'road:linear, grass, baseball field:areal'`` -> entities (each as :func:`parse_entity`)."""
    entities = [parse_entity(item, what) for item in (t.strip() for t in text.split(",")) if item]
    if not entities:
        raise InputError("no entities given (e.g. 'road:linear, grass, water')")
    return entities


def load_entities_json(path: str | os.PathLike, what: str = "--entities-json") -> list[Entity]:
    """A list of entity objects, or any document with an "entities" list (`overseec interpret --json`).

    An entity without "geometry" gets the lexicon's, as in :func:`parse_entity`.
    """
    path = Path(path)
    doc = read_json_limited(path, MAX_JSON_BYTES, what)
    items = doc.get("entities") if isinstance(doc, dict) else doc
    if not isinstance(items, list):
        raise InputError(
            f"{what} {path}: expected a list of entities or an object with "
            '"entities", e.g. [{"name": "road", "geometry": "linear"}]'
        )
    entities = []
    for i, item in enumerate(items):
        if not isinstance(item, dict) or not isinstance(item.get("name"), str):
            raise InputError(f'{what} {path}: entity {i + 1} has no "name"')
        prompts = item.get("prompts") or ()
        threshold = item.get("threshold")
        if not isinstance(prompts, (list, tuple)) or not all(isinstance(p, str) for p in prompts):
            raise InputError(f'{what} {path}: entity {item["name"]!r}: "prompts" must be a list of strings')
        if threshold is not None and not isinstance(threshold, (int, float)):
            raise InputError(f'{what} {path}: entity {item["name"]!r}: "threshold" must be a number')
        if "geometry" not in item:
            item = {**item, "geometry": geometry_of(item["name"].strip().lower())}
        entities.append(Entity.from_json(item))
    return entities
