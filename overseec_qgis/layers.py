"""Run outputs as QGIS layers: one group per run, styled, with provenance in the metadata.

Layers point at the run directory's files (GeoTIFF/GeoJSON), so a saved project reopens with
them. Styles are the QML files in ``resources/styles`` (costmap: colour ramp 0..1 with a legend;
probability: transparent-to-bright ramp; mask: paletted 0/1; path: cased line). A multi-band
``probs.tif`` becomes one layer per entity, each a single-band renderer on its band. Each
layer's metadata (title, abstract, keywords) records the prompt, the cost program and the run
directory; custom properties keep the same for code (the map tool finds costmaps by them).
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from qgis.core import (
    QgsLayerMetadata,
    QgsLayerTreeGroup,
    QgsMapLayer,
    QgsPalettedRasterRenderer,
    QgsProject,
    QgsProviderRegistry,
    QgsRasterLayer,
    QgsVectorLayer,
)
from qgis.PyQt.QtGui import QColor

from overseec_core import runfiles

from .legend import PROP_ROLE, add_below_routes, add_to_routes, below_routes_index, is_route_layer, layer_name

#: Distinct colours for per-entity masks (ColorBrewer Set1 + Dark2).
ENTITY_COLOURS = (
    "#e41a1c",
    "#377eb8",
    "#4daf4a",
    "#984ea3",
    "#ff7f00",
    "#a65628",
    "#f781bf",
    "#1b9e77",
    "#d95f02",
    "#7570b3",
    "#e7298a",
    "#66a61e",
)
PROP_RUN = "overseec/run_dir"


def resources_dir() -> Path:
    """``resources/`` beside the package: the checkout's root, or the plugin folder in the zip."""
    return Path(__file__).resolve().parent.parent / "resources"


def style_path(name: str) -> Path:
    """Path of a shipped QML style (``costmap``, ``probability``, ``mask``, ``path``)."""
    return resources_dir() / "styles" / f"{name}.qml"


def icon_path() -> Path:
    """The plugin's icon (SVG) in its resources."""
    return resources_dir() / "icons" / "overseec.svg"


@dataclass(frozen=True)
class Provenance:
    """What produced a layer: recorded in its metadata so the project keeps it."""

    run_dir: str = ""
    prompt: str = ""
    program: str = ""
    entities: tuple[str, ...] = ()
    stage: str = ""
    extra: tuple[tuple[str, str], ...] = field(default=())

    @staticmethod
    def from_run_dir(run_dir: str | os.PathLike, stage: str = "") -> Provenance:
        """Read prompt, program and entities from a run directory's manifest.json (if any)."""
        run_dir = Path(run_dir)
        data = {}
        try:
            data = json.loads((run_dir / runfiles.MANIFEST).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            pass

        def get(*keys):
            node: Any = data
            for k in keys:
                node = node.get(k) if isinstance(node, dict) else None
            return node

        prompt = (
            get("prompt")
            or get("interpretation", "prompt")
            or get("cost_program", "interpretation", "prompt")
            or get("parameters", "costmap", "prompt")
            or ""
        )
        program = get("cost_program", "text") or get("program") or get("interpretation", "program") or ""
        ents = get("entities") or get("interpretation", "entities") or []
        names = tuple(str(e.get("name", e)) if isinstance(e, dict) else str(e) for e in ents)
        return Provenance(run_dir=str(run_dir), prompt=str(prompt), program=str(program), entities=names, stage=stage)

    def abstract(self) -> str:
        parts = []
        if self.stage:
            parts.append(f"overseec {self.stage} output.")
        if self.prompt:
            parts.append(f"Mission prompt: {self.prompt}")
        if self.entities:
            parts.append("Entities: " + ", ".join(self.entities))
        if self.program:
            parts.append("Cost program:\n" + self.program)
        if self.run_dir:
            parts.append(f"Run directory: {self.run_dir} ({runfiles.MANIFEST} has the full provenance)")
        parts += [f"{k}: {v}" for k, v in self.extra]
        return "\n\n".join(parts)


def set_provenance(layer: QgsMapLayer, prov: Provenance, role: str) -> None:
    """Write provenance into the layer's metadata and custom properties."""
    md = QgsLayerMetadata(layer.metadata())
    md.setTitle(layer.name())
    md.setAbstract(prov.abstract())
    md.setType("dataset")
    md.addKeywords("overseec", ["overseec", role] + ([prov.stage] if prov.stage else []))
    if prov.entities:
        md.addKeywords("entities", list(prov.entities))
    if prov.run_dir:
        md.setIdentifier(prov.run_dir)
    layer.setMetadata(md)
    layer.setCustomProperty(PROP_ROLE, role)
    if prov.run_dir:
        layer.setCustomProperty(PROP_RUN, prov.run_dir)
    if prov.prompt:
        layer.setCustomProperty("overseec/prompt", prov.prompt)
    if prov.program:
        layer.setCustomProperty("overseec/program", prov.program)


def run_group(title: str, project: QgsProject | None = None) -> QgsLayerTreeGroup:
    """A new layer-tree group for one run's layers: at the top of the legend, but below the
    routes group (:func:`overseec_qgis.legend.routes_group`), so a new costmap never covers the routes."""
    project = project or QgsProject.instance()
    return project.layerTreeRoot().insertGroup(below_routes_index(project), title)


def _add(layer: QgsMapLayer, group: QgsLayerTreeGroup | None, project: QgsProject | None) -> QgsMapLayer:
    """Add a valid layer to ``group``; without one, at the top of the legend below the routes.
    A path or overrides layer always goes into the routes group, whatever group was given, so
    that no costmap is ever drawn over it."""
    if not layer.isValid():
        raise ValueError(f"QGIS cannot open {layer.source()}")
    project = project or QgsProject.instance()
    if is_route_layer(layer):
        add_to_routes(layer, project)
    elif group is None:
        add_below_routes(layer, project)
    else:
        project.addMapLayer(layer, False)
        group.addLayer(layer)
    return layer


def apply_style(layer: QgsMapLayer, name: str) -> None:
    """Load a shipped QML; raise if QGIS rejects it (a broken style is a bug worth seeing)."""
    msg, ok = layer.loadNamedStyle(str(style_path(name)))
    if not ok:
        raise ValueError(f"style {name}.qml: {msg}")


def band_names(path: str | os.PathLike) -> list[str]:
    """Band descriptions (entity names written by the core), 'band N' where missing."""
    import rasterio

    with rasterio.open(path) as ds:
        return [d or f"band {i + 1}" for i, d in enumerate(ds.descriptions)]


def _set_band(layer: QgsRasterLayer, band: int) -> None:
    """Point a single-band pseudocolour renderer (from a QML) at ``band``."""
    renderer = layer.renderer().clone()
    renderer.setBand(band)
    layer.setRenderer(renderer)


def _colour_mask(layer: QgsRasterLayer, band: int, entity: str, colour: QColor) -> None:
    """Give a 0/1 mask layer its entity's colour (value 1) and keep 0 transparent."""
    old = layer.renderer()
    classes = [
        QgsPalettedRasterRenderer.Class(0, QColor(0, 0, 0, 0), "absent"),
        QgsPalettedRasterRenderer.Class(1, colour, entity),
    ]
    renderer = QgsPalettedRasterRenderer(layer.dataProvider(), band, classes)
    renderer.setOpacity(old.opacity())
    layer.setRenderer(renderer)


def add_costmap(
    path: str | os.PathLike,
    group: QgsLayerTreeGroup | None = None,
    prov: Provenance | None = None,
    name: str = "costmap",
    project: QgsProject | None = None,
) -> QgsRasterLayer:
    """The costmap GeoTIFF with the 0..1 colour ramp (lower = better)."""
    layer = QgsRasterLayer(str(path), name, "gdal")
    if layer.isValid():
        apply_style(layer, "costmap")
        set_provenance(layer, prov or Provenance(stage="costmap"), "costmap")
    return _add(layer, group, project)


def add_band_layers(
    path: str | os.PathLike,
    style: str,
    role: str,
    group: QgsLayerTreeGroup | None = None,
    prov: Provenance | None = None,
    suffix: str = "",
    names: Sequence[str] | None = None,
    project: QgsProject | None = None,
) -> list[QgsRasterLayer]:
    """One layer per band of a multi-band raster (probabilities or masks), named by entity."""
    names = list(names) if names else band_names(path)
    layers = []
    for i, entity in enumerate(names):
        layer = QgsRasterLayer(str(path), f"{entity}{suffix}", "gdal")
        if not layer.isValid():
            raise ValueError(f"QGIS cannot open {path}")
        apply_style(layer, style)
        if style == "mask":
            _colour_mask(layer, i + 1, entity, QColor(ENTITY_COLOURS[i % len(ENTITY_COLOURS)]))
        else:
            _set_band(layer, i + 1)
        set_provenance(layer, prov or Provenance(), role)
        layer.setCustomProperty("overseec/entity", entity)
        layers.append(_add(layer, group, project))
    return layers


def add_probabilities(path, group=None, prov=None, names=None, project=None) -> list[QgsRasterLayer]:
    """Add one layer per band of a probabilities raster, named "<entity> probability", to the project."""
    return add_band_layers(path, "probability", "probability", group, prov, " probability", names, project)


def add_masks(path, group=None, prov=None, names=None, project=None) -> list[QgsRasterLayer]:
    """Add one layer per band of a masks raster, coloured per entity and named "<entity> mask"."""
    return add_band_layers(path, "mask", "mask", group, prov, " mask", names, project)


#: Route colours, one per route layer of a comparison: blues, magentas, cyans, oranges and
#: browns that stand out on the costmap's green-to-red ramp and are none of the sidecar's colours
#: (black lethal, purple keep-out).
ROUTE_COLOURS = (
    (0, 80, 255),
    (200, 0, 200),
    (0, 190, 210),
    (255, 120, 0),
    (0, 0, 128),
    (255, 105, 180),
    (0, 128, 128),
    (140, 70, 20),
)


def _route_colour_of(layer: QgsMapLayer) -> tuple[int, int, int] | None:
    try:
        symbol = layer.renderer().symbol()
        c = symbol.symbolLayer(symbol.symbolLayerCount() - 1).color()
    except AttributeError:  # not a single-symbol line layer
        return None
    return (c.red(), c.green(), c.blue())


def style_route(layer: QgsVectorLayer, project: QgsProject | None = None) -> None:
    """The path style (``path.qml``: a white casing under a coloured line) with the line in the
    first of :data:`ROUTE_COLOURS` no other route layer of the project has, so each route of a
    comparison has its own colour (cycling once all are taken)."""
    apply_style(layer, "path")
    project = project or QgsProject.instance()
    used = [
        _route_colour_of(lyr)
        for lyr in project.mapLayers().values()
        if lyr.id() != layer.id() and lyr.customProperty("overseec/role") == "path"
    ]
    free = [c for c in ROUTE_COLOURS if c not in used]
    colour = free[0] if free else ROUTE_COLOURS[len(used) % len(ROUTE_COLOURS)]
    renderer = layer.renderer().clone()
    symbol = renderer.symbol()
    symbol.symbolLayer(symbol.symbolLayerCount() - 1).setColor(QColor(*colour))
    layer.setRenderer(renderer)


def add_path(
    path: str | os.PathLike,
    group: QgsLayerTreeGroup | None = None,
    prov: Provenance | None = None,
    name: str | None = None,
    project: QgsProject | None = None,
) -> QgsVectorLayer:
    """A path GeoJSON as a styled line layer."""
    layer = QgsVectorLayer(str(path), name or Path(path).stem, "ogr")
    if layer.isValid():
        style_route(layer, project)
        set_provenance(layer, prov or Provenance(stage="plan"), "path")
    return _add(layer, group, project)  # into the routes group, above the costmaps


#: The map tool's paths table: the core's path GeoJSON property names, plus the id the tool
#: finds a route by when it re-plans it (feature ids change when edits are committed).
PATH_FIELDS = (
    ("total_cost", "double"),
    ("length_m", "double"),
    ("mode", "string"),
    ("vias", "int"),
    ("path_id", "string"),
    ("waypoints", "string"),  # the route's start, vias and goal (WKT MULTIPOINT): undo moves the markers
)
#: The paths table's fields that are the map tool's bookkeeping, not the route's figures: exports
#: (the tool's GeoJSON, Save planned paths) leave them out.
PATH_INTERNAL_FIELDS = ("fid", "path_id", "waypoints")


def paths_table(costmap: str | os.PathLike) -> str:
    """The table of ``paths.gpkg`` holding the routes planned on ``costmap`` (by its file stem)."""
    return "paths_" + (re.sub(r"[^0-9A-Za-z_]+", "_", Path(costmap).stem).strip("_") or "costmap")


def ogr_parts(layer: QgsMapLayer) -> tuple[str, str]:
    """(file, table) of an OGR layer's source."""
    parts = QgsProviderRegistry.instance().decodeUri("ogr", layer.source())
    return os.path.normcase(os.path.abspath(parts.get("path") or "")), str(parts.get("layerName") or "")


def find_paths_layer(folder: str | os.PathLike, table: str, project: QgsProject | None = None) -> QgsVectorLayer | None:
    """The project's layer on ``folder/paths.gpkg``'s ``table``, if one is loaded (a reopened project)."""
    project = project or QgsProject.instance()
    wanted = (os.path.normcase(os.path.abspath(Path(folder) / runfiles.PATHS_LAYER)), table)
    for layer in project.mapLayers().values():
        if isinstance(layer, QgsVectorLayer) and layer.providerType() == "ogr" and ogr_parts(layer) == wanted:
            return layer
    return None


def create_paths_table(path: Path, table: str, crs, context) -> str:
    """Create ``table`` (LineString, :data:`PATH_FIELDS`) in the GeoPackage ``path`` (the file
    too when missing); returns "" or QGIS's reason it could not."""
    from qgis.core import QgsField, QgsFields, QgsVectorFileWriter, QgsWkbTypes
    from qgis.PyQt.QtCore import QVariant

    kinds = {"double": QVariant.Double, "int": QVariant.Int, "string": QVariant.String}
    fields = QgsFields()
    for field_name, kind in PATH_FIELDS:
        fields.append(QgsField(field_name, kinds[kind]))
    options = QgsVectorFileWriter.SaveVectorOptions()
    options.driverName = "GPKG"
    options.layerName = table
    options.actionOnExistingFile = (
        QgsVectorFileWriter.CreateOrOverwriteLayer if path.exists() else QgsVectorFileWriter.CreateOrOverwriteFile
    )
    writer = QgsVectorFileWriter.create(str(path), fields, QgsWkbTypes.LineString, crs, context, options)
    error = writer.errorMessage() if writer.hasError() else ""
    del writer  # closes the file
    return error


def open_paths_layer(
    folder: str | os.PathLike, table: str, crs, name: str, prov: Provenance | None = None
) -> QgsVectorLayer:
    """``folder/paths.gpkg``'s ``table`` as a styled line layer (file and table created when
    missing, in ``crs``); not added to a project (see :func:`add_on_top`).

    The layer's source is the file, so a saved project reopens with the routes, and edits go
    through the layer's edit buffer (undo, commit, roll back) like any other vector layer.
    """
    path = Path(folder) / runfiles.PATHS_LAYER
    uri = f"{path}|layername={table}"
    layer = QgsVectorLayer(uri, name, "ogr") if path.exists() else None
    if layer is None or not layer.isValid():
        error = create_paths_table(path, table, crs, QgsProject.instance().transformContext())
        if error:
            raise ValueError(f"cannot create {path}: {error}")
        layer = QgsVectorLayer(uri, name, "ogr")
        if not layer.isValid():
            raise ValueError(f"QGIS cannot open {uri}")
    style_route(layer)
    set_provenance(layer, prov or Provenance(run_dir=str(folder), stage="plan"), "path")
    return layer


def add_on_top(layer: QgsMapLayer, project: QgsProject | None = None) -> QgsMapLayer:
    """Add ``layer`` at the top of the legend: first in the routes group, which stays above every
    costmap group (so it is drawn above the costmap wherever the legend selection is), and first
    in a custom layer order if one is set."""
    return add_to_routes(layer, project)


#: The costmap a paths layer's routes were planned on (a custom property the map tool sets).
PROP_COSTMAP = "overseec/costmap"


#: Roles of a run's outputs in legend order (top first); file names are the core's (runfiles.ROLES).
ROLE_ORDER = ("path", "costmap", "mask", "probability")


# -- polygons (overseec vectorize, segment --vectors) -----------------------------------------

#: The QML of every entity's polygon layer (its fill and outline then take the entity's colour).
POLYGON_STYLE = "polygons"
#: The role polygon layers carry (after the raster roles in a run's group).
POLYGON_ROLE = "polygons"


def _entity_colour(layer: QgsVectorLayer, colour: QColor) -> None:
    """Give the style's fill and outline the entity's colour, keeping the fill's transparency."""
    renderer = layer.renderer().clone()
    symbol = renderer.symbol()
    for symbol_layer in symbol.symbolLayers():
        fill = QColor(colour)
        fill.setAlpha(symbol_layer.color().alpha())
        symbol_layer.setColor(fill)
        symbol_layer.setStrokeColor(colour)
    layer.setRenderer(renderer)


def add_polygon_layers(
    path: str | Path,
    group: QgsLayerTreeGroup | None = None,
    prov: Provenance | None = None,
    project: QgsProject | None = None,
) -> list[QgsVectorLayer]:
    """One styled layer per table of a vectorize GeoPackage, named "<entity> polygons", coloured
    as the entity's mask is (:data:`overseec_qgis.ENTITY_COLOURS`, in table order)."""
    project = project or QgsProject.instance()
    added = []
    for i, sub in enumerate(QgsProviderRegistry.instance().querySublayers(str(path))):
        layer = QgsVectorLayer(sub.uri(), f"{sub.name()} polygons", "ogr")
        if not layer.isValid():
            raise ValueError(f"QGIS cannot open {sub.uri()}")
        apply_style(layer, POLYGON_STYLE)
        _entity_colour(layer, QColor(ENTITY_COLOURS[i % len(ENTITY_COLOURS)]))
        set_provenance(layer, prov or Provenance(stage="vectorize"), POLYGON_ROLE)
        layer.setCustomProperty("overseec/entity", sub.name())
        project.addMapLayer(layer, False)
        (group if group is not None else project.layerTreeRoot()).addLayer(layer)
        added.append(layer)
    return added


def add_run_outputs(
    run_dir: str | os.PathLike,
    title: str | None = None,
    project: QgsProject | None = None,
    roles: Iterable[str] = ROLE_ORDER,
) -> tuple[QgsLayerTreeGroup, list[QgsMapLayer]]:
    """Add a run directory's outputs as a new group; returns the group and its layers.

    Each role's preferred file is used (refined masks over coarse ones). With the masks come
    their polygons (``masks.gpkg``, `segment --vectors`), above them, when the folder holds them.
    Probability layers start hidden: masks and costmap say more at a glance.
    """
    run_dir = Path(run_dir)
    prov_base = Provenance.from_run_dir(run_dir)
    group = run_group(title or f"overseec: {run_dir.name}", project)
    layers: list[QgsMapLayer] = []
    for role in (r for r in ROLE_ORDER if r in set(roles)):
        path = runfiles.first_existing(run_dir, role)
        if path is None:
            continue
        prov = replace(prov_base, stage=role)
        if role == "costmap":
            layers.append(add_costmap(path, group, prov, project=project))
        elif role == "path":  # in the routes group, above this and every later costmap
            layers.append(add_path(path, None, prov, project=project))
        elif role == "mask":
            layers += _add_mask_polygons(run_dir, group, prov, project)
            layers += add_masks(path, group, prov, project=project)
        else:
            added = add_probabilities(path, group, prov, project=project)
            for layer in added:
                group.findLayer(layer.id()).setItemVisibilityChecked(False)
            layers += added
    return group, layers


def _add_mask_polygons(
    run_dir: Path, group: QgsLayerTreeGroup, prov: Provenance, project: QgsProject | None
) -> list[QgsVectorLayer]:
    """The run folder's ``masks.gpkg`` as one styled layer per entity, or none when absent."""
    path = run_dir / runfiles.MASK_POLYGONS
    if not path.is_file():
        return []
    return add_polygon_layers(path, group, replace(prov, stage=POLYGON_ROLE), project)


# -- compare: the cost difference ------------------------------------------------------------------

#: The diverging style of a cost difference: blue cheaper, red dearer, transparent where equal.
DIFFERENCE_STYLE = "difference"


def add_difference(
    path: str | os.PathLike,
    group: QgsLayerTreeGroup | None = None,
    prov: Provenance | None = None,
    names: Sequence[str] | None = None,
    project: QgsProject | None = None,
) -> list[QgsRasterLayer]:
    """One layer per band of compare's ``difference.tif`` (cost of candidate k minus candidate 1),
    styled diverging around 0 (:data:`DIFFERENCE_STYLE`) and named ``cost difference — <what>``
    (``names``: one label per band, else the bands' descriptions)."""
    project = project or QgsProject.instance()
    probe = QgsRasterLayer(str(path), "difference", "gdal")
    if not probe.isValid():
        raise ValueError(f"QGIS cannot open {path}")
    count = probe.bandCount()
    labels = list(names or [])
    labels += [probe.dataProvider().bandDescription(b + 1) or f"band {b + 1}" for b in range(len(labels), count)]
    added = []
    for band in range(1, count + 1):
        layer = QgsRasterLayer(str(path), layer_name("cost difference", labels[band - 1], project=project), "gdal")
        apply_style(layer, DIFFERENCE_STYLE)
        if band != 1:
            _set_band(layer, band)
            renderer = layer.renderer()  # setBand forgets the range; the style's is -1..1
            renderer.setClassificationMin(-1.0)
            renderer.setClassificationMax(1.0)
        set_provenance(layer, prov or Provenance(stage="compare"), "difference")
        added.append(_add(layer, group, project))
    return added
