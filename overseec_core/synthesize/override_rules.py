"""What makes a feature an override: the attribute and geometry rules, with no GIS libraries.

The rules of :mod:`overseec_core.synthesize.overrides` that adapters apply before handing a
layer over (the QGIS plugin checks its overrides layer's features with them, so a feature the
core would refuse is skipped with a warning instead of stopping every plan). Only the standard
library and numpy: importable in QGIS's own Python, where shapely and rasterio may be missing.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

#: Cost of a ``prefer`` override: the bottom of the scale, like the most preferred entity.
PREFER_COST = 0.0
#: Cost written under a lethal override (the lethal sidecar says 1 there).
LETHAL_COST = 1.0
#: Feature kinds, in the order summaries list them.
KINDS = ("cost", "prefer", "lethal")
#: Geometry types an override may have.
POLYGON_TYPES = ("Polygon", "MultiPolygon")

_TRUE = {"1", "true", "yes", "y", "t"}
_FALSE = {"0", "false", "no", "n", "f", ""}


def _prop(props: Mapping[str, Any], name: str) -> Any:
    """A property by name, ignoring case (QGIS users write 'Cost' as often as 'cost')."""
    for key, value in props.items():
        if str(key).strip().lower() == name:
            return value
    return None


def parse_flag(value: Any) -> bool:
    """``lethal``/``prefer`` value -> bool: true/1/yes or false/0/no/empty; ValueError otherwise."""
    if value is None:
        return False
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, float, np.integer, np.floating)) and value in (0, 1):
        return bool(value)
    text = str(value).strip().lower()
    if text in _TRUE:
        return True
    if text in _FALSE:
        return False
    raise ValueError(f"{value!r} is not true/false or 1/0")


def parse_cost(value: Any) -> float | None:
    """``cost`` value -> float in [0, 1], None when absent; ValueError for anything else."""
    if value is None or (isinstance(value, str) and not value.strip()):
        return None
    if isinstance(value, (bool, np.bool_)):
        raise ValueError(f"cost {value!r} is not a number")
    try:
        cost = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"cost {value!r} is not a number") from None
    if not (math.isfinite(cost) and 0.0 <= cost <= 1.0):
        raise ValueError(f"cost {value!r} is outside [0, 1]")
    return cost


def classify(props: Mapping[str, Any]) -> tuple[str, float]:
    """(kind, cost) a feature's properties ask for; ValueError naming what is wrong.

    Exactly one of ``cost``, ``lethal``, ``prefer`` must be set: two would contradict each
    other (a cost under a lethal flag means nothing) and none says nothing.
    """
    cost = parse_cost(_prop(props, "cost"))
    lethal, prefer = (_named_flag(props, name) for name in ("lethal", "prefer"))
    given = [k for k, on in (("cost", cost is not None), ("lethal", lethal), ("prefer", prefer)) if on]
    if not given:
        raise ValueError("has none of cost, lethal, prefer; give one (cost in [0, 1], lethal=1 or prefer=1)")
    if len(given) > 1:
        raise ValueError(f"has both {' and '.join(given)}; give only one")
    if lethal:
        return "lethal", LETHAL_COST
    if prefer:
        return "prefer", PREFER_COST
    assert cost is not None  # the one given
    return "cost", float(cost)


def _named_flag(props: Mapping[str, Any], name: str) -> bool:
    try:
        return parse_flag(_prop(props, name))
    except ValueError as exc:
        raise ValueError(f"{name} {exc}") from None


def geometry_problem(geom_type: str | None, is_empty: bool) -> str | None:
    """Why a geometry of this type (None: no geometry) cannot be an override; None when it can
    (a non-empty polygon)."""
    if geom_type is None:
        return "has no geometry"
    if geom_type not in POLYGON_TYPES:
        return f"is a {geom_type}; overrides are polygons"
    if is_empty:
        return "has an empty polygon"
    return None
