"""How Processing results arrive in the project: named after what they are, styled, grouped.

Processing loads a destination output (a costmap, a path) itself when the user asked for it
(the dialog's "Open output file", ``processing.runAndLoadResults``); the algorithm only names the
layer and gives it a post-processor (:class:`StyleLayer`) that loads the shipped QML style from
``resources/styles/``, records provenance and, for a run, moves the layer into the run's group.
Outputs that are not destinations (a run's costmap, masks and path) are registered with
``context.addLayerToLoadOnCompletion`` and handled the same way. Masks and probabilities are
multi-band rasters: their post-processor replaces the loaded layer by one layer per entity (the
dock's :func:`overseec_qgis.layers.add_masks`), in the same group. A GeoPackage of polygons
(``overseec vectorize``) becomes one layer per entity the same way (:class:`PolygonLayers`,
:func:`overseec_qgis.layers.add_polygon_layers`, which the dock uses too), each styled from
``polygons.qml`` in its entity's colour.

Post-processors run on the main thread after the algorithm; QGIS does not own the Python object,
so each one is kept in :data:`_ALIVE` until it has run.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from qgis.core import (
    QgsLayerTreeGroup,
    QgsMapLayer,
    QgsProcessingContext,
    QgsProcessingFeedback,
    QgsProcessingLayerPostProcessorInterface,
    QgsProject,
)

from overseec_core import runfiles

from .. import layers, legend
from ..layers import add_polygon_layers

#: Legend order inside a run's group, top first (the dock's order).
ROLE_ORDER = layers.ROLE_ORDER
#: Longest prompt shown in a layer or group name (the names are :func:`overseec_qgis.legend.layer_name`'s).
NAME_PROMPT_CHARS = legend.NAME_PROMPT_CHARS
short_text = legend.short_text


def costmap_name(prompt: str = "", program: str = "") -> str:
    """'costmap — prefer roads, avoid the water' (or the program file's name)."""
    what = Path(program).name if program else "cost program"
    return legend.layer_name("costmap", prompt, f"costmap — {what}", project=None)


def length_text(metres: float) -> str:
    """'623 m' below a kilometre, else '1.24 km'."""
    return f"{metres:.0f} m" if metres < 1000 else f"{metres / 1000:.2f} km"


def path_name(cost: float, length_m: float) -> str:
    """'path — cost 412.3, 1.24 km'."""
    return f"path — cost {cost:.4g}, {length_text(length_m)}"


def run_title(prompt: str) -> str:
    """The layer-tree group of one run: 'overseec run — <prompt>'."""
    return f"overseec run — {short_text(prompt)}" if prompt.strip() else "overseec run"


@dataclass
class RunGroup:
    """One layer-tree group shared by the post-processors of one run (created on first use)."""

    title: str
    group: QgsLayerTreeGroup | None = field(default=None, repr=False)

    def get(self, project: QgsProject) -> QgsLayerTreeGroup:
        """The group, created on first use at the top of the legend below the routes group."""
        if self.group is None:
            self.group = layers.run_group(self.title, project)
        return self.group


def _rank(layer: QgsMapLayer) -> int:
    role = layer.customProperty(layers.PROP_ROLE, "")
    return ROLE_ORDER.index(role) if role in ROLE_ORDER else len(ROLE_ORDER)


def move_into(group: QgsLayerTreeGroup, layer: QgsMapLayer, project: QgsProject) -> None:
    """Move ``layer``'s legend node into ``group``, placed by role (path, costmap, masks, ...)."""
    root = project.layerTreeRoot()
    old = root.findLayer(layer.id())
    index = sum(1 for node in group.findLayers() if node.layer() is not None and _rank(node.layer()) <= _rank(layer))
    group.insertLayer(index, layer)  # a second node first, so the layer never leaves the tree
    if old is not None and old.parent() is not None:
        old.parent().removeChildNode(old)


def place(layer: QgsMapLayer, group: QgsLayerTreeGroup | None, project: QgsProject) -> None:
    """Where a loaded result goes: a path into the routes group (above every costmap), anything
    else into its run's group, else to the top of the legend below the routes group."""
    if legend.is_route_layer(layer):
        legend.add_to_routes(layer, project)
    elif group is not None:
        move_into(group, layer, project)
    else:
        legend.add_below_routes(layer, project)


#: Post-processors waiting to run (QGIS keeps only a pointer to them).
_ALIVE: list[QgsProcessingLayerPostProcessorInterface] = []


class StyleLayer(QgsProcessingLayerPostProcessorInterface):
    """Style a loaded result from ``resources/styles/<style>.qml``, record its provenance, and
    move it into ``group`` when given. ``bands`` (mask / probability) splits a multi-band raster
    into one layer per entity instead."""

    def __init__(
        self,
        style: str,
        role: str,
        prov: layers.Provenance | None = None,
        group: RunGroup | None = None,
        bands: bool = False,
    ) -> None:
        super().__init__()
        self.style, self.role, self.prov, self.group, self.bands = style, role, prov, group, bands
        _ALIVE.append(self)

    def postProcessLayer(
        self, layer: QgsMapLayer, context: QgsProcessingContext, feedback: QgsProcessingFeedback
    ) -> None:
        try:
            project = layer.project() or context.project() or QgsProject.instance()
            group = self.group.get(project) if self.group is not None else None
            prov = self.prov or layers.Provenance(stage=self.role)
            if self.bands:
                self._split(layer, project, group, prov)
                return
            layer.setName(legend.unique_name(layer.name(), project, exclude=layer))
            layers.apply_style(layer, self.style)
            layers.set_provenance(layer, prov, self.role)
            place(layer, group, project)
        except Exception as exc:  # a style problem must not lose the result layer
            feedback.reportError(f"overseec: could not style {layer.name()}: {exc}", False)
        finally:
            release(self)

    def _split(self, layer: QgsMapLayer, project: QgsProject, group, prov: layers.Provenance) -> None:
        """One styled layer per band (entity), where ``layer`` was; ``layer`` leaves."""
        path = layer.source().split("|")[0]
        add = layers.add_masks if self.role == "mask" else layers.add_probabilities
        target = group if group is not None else project.layerTreeRoot()
        added = add(path, None, prov, project=project)
        for new in added:
            move_into(target, new, project)
            if self.role == "probability":
                node = target.findLayer(new.id())
                if node is not None:
                    node.setItemVisibilityChecked(False)
        project.removeMapLayer(layer.id())


def release(post: QgsProcessingLayerPostProcessorInterface) -> None:
    """Forget a post-processor that will not run."""
    if post in _ALIVE:
        _ALIVE.remove(post)


def name_destination(
    context: QgsProcessingContext, dest: str, name: str, post: QgsProcessingLayerPostProcessorInterface
) -> None:
    """Name and post-process a destination output Processing will load (if it will)."""
    if not context.willLoadLayerOnCompletion(dest):
        release(post)
        return
    details = context.layerToLoadOnCompletionDetails(dest)
    details.name = name
    details.forceName = True
    details.setPostProcessor(post)


def load_on_completion(
    context: QgsProcessingContext, path: str, name: str, output: str, post: QgsProcessingLayerPostProcessorInterface
) -> bool:
    """Ask Processing to load a non-destination output file; False where there is no project
    to load into (``qgis_process``, a model's child)."""
    project = context.project()
    if project is None:
        release(post)
        return False
    details = QgsProcessingContext.LayerDetails(name, project, output)
    details.forceName = True
    details.setPostProcessor(post)
    context.addLayerToLoadOnCompletion(path, details)
    return True


def load_run_layers(
    context: QgsProcessingContext,
    folder: Path,
    prompt: str,
    roles: Sequence[str] = ROLE_ORDER,
    path_label: str = "",
    title: str = "",
) -> None:
    """Ask Processing to load a run folder's outputs (the preferred file of each role) into one
    group named after the run."""
    group = RunGroup(title or run_title(prompt))
    prov = layers.Provenance.from_run_dir(folder)
    for role in roles:
        found = runfiles.first_existing(folder, role)
        if found is None:
            continue
        name = {"costmap": costmap_name(prompt), "path": path_label or "path"}.get(role, role)
        style = {"path": "path", "costmap": "costmap", "mask": "mask"}.get(role, "probability")
        post = StyleLayer(
            style,
            role,
            layers.Provenance(**{**prov.__dict__, "stage": role}),
            group,
            bands=role in ("mask", "probability"),
        )
        load_on_completion(context, str(found), name, role.upper(), post)


# -- polygons (overseec vectorize) -----------------------------------------------------------------


class PolygonLayers(QgsProcessingLayerPostProcessorInterface):
    """Replace the layer Processing loaded from a vectorize GeoPackage (its first table) by one
    styled layer per entity, in ``group`` when given."""

    def __init__(self, prov: layers.Provenance | None = None, group: RunGroup | None = None) -> None:
        super().__init__()
        self.prov, self.group = prov, group
        _ALIVE.append(self)

    def postProcessLayer(
        self, layer: QgsMapLayer, context: QgsProcessingContext, feedback: QgsProcessingFeedback
    ) -> None:
        try:
            project = layer.project() or context.project() or QgsProject.instance()
            group = self.group.get(project) if self.group is not None else None
            add_polygon_layers(layer.source().split("|")[0], group, self.prov, project)
            project.removeMapLayer(layer.id())
        except Exception as exc:  # a style problem must not lose the result
            feedback.reportError(f"overseec: could not load the polygons of {layer.name()}: {exc}", False)
        finally:
            release(self)


# -- compare: routes and the cost difference ------------------------------------------------------

#: Route colours of compare's candidates after the first (which keeps the path style's blue).
ROUTE_COLOURS = ("#e41a1c", "#ff7f00", "#984ea3", "#a65628", "#f781bf", "#4daf4a")


def recolour_route(layer: QgsMapLayer, colour: str) -> None:
    """Give a path-styled layer's core line (its top symbol layer) another colour."""
    from qgis.PyQt.QtGui import QColor

    renderer = layer.renderer().clone()
    renderer.symbol().symbolLayers()[-1].setColor(QColor(colour))
    layer.setRenderer(renderer)


class RouteLayer(StyleLayer):
    """A compare route: the path style (in the candidate's colour), into the routes group."""

    def __init__(self, prov: layers.Provenance, colour: str | None) -> None:
        super().__init__("path", "path", prov)
        self.colour = colour

    def postProcessLayer(
        self, layer: QgsMapLayer, context: QgsProcessingContext, feedback: QgsProcessingFeedback
    ) -> None:
        colour = self.colour
        super().postProcessLayer(layer, context, feedback)
        if colour is not None:
            try:
                recolour_route(layer, colour)
            except Exception as exc:  # the route stays in the path style
                feedback.reportError(f"overseec: could not colour {layer.name()}: {exc}", False)


class DifferenceLayers(QgsProcessingLayerPostProcessorInterface):
    """Replace the layer Processing loaded from compare's ``difference.tif`` by one diverging-styled
    layer per band (:func:`overseec_qgis.layers.add_difference`), in ``group``."""

    def __init__(self, prov: layers.Provenance, names: Sequence[str], group: RunGroup) -> None:
        super().__init__()
        self.prov, self.names, self.group = prov, list(names), group
        _ALIVE.append(self)

    def postProcessLayer(
        self, layer: QgsMapLayer, context: QgsProcessingContext, feedback: QgsProcessingFeedback
    ) -> None:
        try:
            project = layer.project() or context.project() or QgsProject.instance()
            path = layer.source().split("|")[0]
            layers.add_difference(path, self.group.get(project), self.prov, self.names, project)
            project.removeMapLayer(layer.id())
        except Exception as exc:  # a style problem must not lose the result
            feedback.reportError(f"overseec: could not load the cost difference {layer.name()}: {exc}", False)
        finally:
            release(self)


def load_compare_layers(context: QgsProcessingContext, out_dir: Path, doc: dict) -> None:
    """Ask Processing to load what ``overseec compare --json`` wrote: each candidate's route
    (named by its prompt, in its own colour, in the routes group) and the difference raster
    (one diverging-styled layer per candidate after the first, in a compare group)."""
    rows = [row for row in doc.get("prompts") or [] if isinstance(row, dict)]
    labels = [str(row.get("prompt") or row.get("name") or "") for row in rows]
    for k, row in enumerate(rows):
        route = out_dir / str(row.get("route") or "")  # relative to the output folder
        if not row.get("route") or not route.is_file():
            continue
        prov = layers.Provenance(run_dir=str(Path(route).parent), prompt=str(row.get("prompt") or ""), stage="compare")
        colour = None if k == 0 else ROUTE_COLOURS[(k - 1) % len(ROUTE_COLOURS)]
        name = legend.layer_name("path", labels[k], str(row.get("name") or "route"))
        load_on_completion(context, str(route), name, f"ROUTE_{k + 1}", RouteLayer(prov, colour))
    difference = out_dir / str((doc.get("files") or {}).get("difference") or "")
    if (doc.get("files") or {}).get("difference") and difference.is_file():
        names = [f"{labels[k]} − {labels[0]}" for k in range(1, len(labels))] if labels else []
        group = RunGroup(f"overseec compare — {short_text(' / '.join(labels)) or out_dir.name}")
        post = DifferenceLayers(layers.Provenance(run_dir=str(out_dir), stage="compare"), names, group)
        load_on_completion(context, str(difference), "cost difference", "DIFFERENCE", post)
