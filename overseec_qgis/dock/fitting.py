"""An interpretation's program fitted to the dock's entity layers, away from the GUI thread.

Reading the layers' names opens rasters (and, the first time, imports rasterio: about half a
second), so the dock does it on QGIS's task thread: :func:`read_names` for the program check,
:func:`fit_for_dock` after Interpret. Both are plain functions of plain values (no widget is
touched), and what did not match is phrased for the dock's own fields (Entity aliases), from the
facts the core hands over -- never by rewriting the CLI's text.
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from qgis.core import Qgis

from .. import jobs, params

#: The dock's field where an entity is tied to a layer.
ALIASES_FIELD = "Entity aliases"
#: The dock's field where the DEM (an elevation raster, ``--dem``) is chosen.
DEM_FIELD = "DEM (elevation)"
#: The layer sources that name entities (a source dict may also carry ``dem``, which names none).
ENTITY_SOURCES = ("masks_dir", "labels", "classes")


def entity_sources(sources: Mapping[str, Any]) -> dict[str, Any]:
    """The sources that name entity layers (the DEM is left out: it gives terrain, not entities)."""
    return {k: sources.get(k) for k in ENTITY_SOURCES}


def names_key(sources: Mapping[str, Any]) -> tuple | None:
    """What the entity layers' names depend on (None: no entity layers, the table names them)."""
    src = entity_sources(sources)
    if not (src["masks_dir"] or (src["labels"] and src["classes"])):
        return None
    return tuple(sorted((k, str(v)) for k, v in src.items()))


def terrain_error(program, dem: str, dem_problem: str = "") -> jobs.CostProgramError | None:
    """Why ``program`` (a checked Program) cannot run with the DEM chosen in the dock, located at
    its first terrain field, phrased for the dock's DEM field; None when it can. ``dem``: the DEM
    file ('' for none); ``dem_problem``: why the chosen DEM layer is unusable ('' if it is not).
    The facts (which field, its unit) come from the core's program and terrain table."""
    if not program.terrain_uses:
        return None
    from overseec_core.costlang.ops import TERRAIN

    name, line, col = program.terrain_uses[0]
    if dem and not dem_problem:
        return None
    why = dem_problem or f"no DEM is chosen: choose an elevation raster in {DEM_FIELD}"
    return jobs.CostProgramError(f"'{name}' ({TERRAIN[name].unit}) is read from a DEM, but {why}", line, col)


@dataclass(frozen=True)
class Names:
    """The entity layers' names (``names`` None: QGIS's Python cannot read rasters, so the
    table stands in and the worker checks), or why the layers are unusable (``error``)."""

    key: tuple | None
    names: tuple[str, ...] | None = None
    error: str = ""


def read_names(sources: Mapping[str, Any], progress=None) -> Names:
    """The names the costmap stage will see for these layer sources (any thread)."""
    key = names_key(sources)
    if key is None:
        return Names(None)
    try:
        return Names(key, jobs.layer_names(**entity_sources(sources)))
    except ImportError:
        return Names(key)
    except jobs.OverseecError as exc:
        return Names(key, error=str(exc))


def alias_example(entity: str, layers: Sequence[str]) -> str:
    """``entity=LAYER`` with the layer name closest to the entity's as the example."""
    close = difflib.get_close_matches(entity, list(layers), n=1, cutoff=0.0)
    return f"{entity}={close[0] if close else 'LAYER'}"


def unmatched_advice(entities: Sequence[str], layers: Sequence[str], none_matched: bool = False) -> str:
    """One line for the dock: which prompt entities match no entity layer, and the alias to add
    in the dock's Entity aliases field (the CLI says ``--alias`` instead)."""
    shown = ", ".join(layers) or "none"
    who = ", ".join(f"'{e}'" for e in entities)
    if none_matched:
        head = f"none of the entities the prompt speaks about ({who}) matches an entity layer ({shown})"
    elif len(entities) == 1:
        head = f"{who} matches no entity layer ({shown}), so the prompt's words about it have no effect"
    else:
        head = f"{who} match no entity layer ({shown}), so the prompt's words about them have no effect"
    examples = ", ".join(alias_example(e, layers) for e in entities)
    return f"{head}: name a layer in the prompt, or add e.g. {examples} in {ALIASES_FIELD}"


@dataclass(frozen=True)
class Fitted:
    """What the program box shows after Interpret: the program (fitted to the layers when
    there are any), the layer names read on the way, the dock's advice for what did not
    match, and lines for the log panel (text, level)."""

    program: str
    names: Names
    advice: tuple[str, ...] = ()
    log: tuple[tuple[str, int], ...] = field(default=())


def fit_for_dock(
    interp, sources: Mapping[str, Any], names: Names | None, aliases: str, priors: params.Priors
) -> Fitted:
    """The interpretation's program fitted to the layers' names as `overseec costmap --prompt`
    fits it (any thread; ``names``: those already read for these sources, else read here)."""
    key = names_key(sources)
    if key is None:
        return Fitted(interp.program, Names(None))
    if names is None or names.key != key:
        names = read_names(sources)
    if names.names is None:
        why = names.error or "QGIS's Python cannot read the rasters; the worker checks the names"
        line = f"interpret: the program is not fitted to the layers ({why})"
        return Fitted(interp.program, names, log=((line, Qgis.Warning),))
    from overseec_core.synthesize.fit import NoLayerMatched, unmatched_entities

    try:
        fitted = jobs.fit_to_layers(interp, names.names, aliases, priors)
    except NoLayerMatched as exc:
        none = unmatched_advice(exc.entities, exc.layers, none_matched=True)
        return Fitted(interp.program, names, (none,), ((f"interpret: {exc}", Qgis.Warning),))
    except jobs.OverseecError as exc:
        return Fitted(interp.program, names, (str(exc),), ((f"interpret: {exc}", Qgis.Warning),))
    lines = [(f"interpret: {n}", Qgis.Info) for n in fitted.notes if n.startswith("entities -> layers")]
    lines += [(f"interpret: {w}", Qgis.Warning) for w in fitted.warnings]
    unmatched = unmatched_entities(interp, fitted.mapping)
    advice = (unmatched_advice(unmatched, names.names),) if unmatched else ()
    return Fitted(fitted.text, names, advice, tuple(lines))
