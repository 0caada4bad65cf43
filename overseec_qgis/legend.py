"""The legend overseec keeps: routes and overrides above every costmap, names by prompt.

Path and overrides layers live in one group, :data:`ROUTES_GROUP` (found by the custom property
:data:`PROP_ROUTES_GROUP`, whatever the user renames it to), kept first in the legend: every new
costmap, mask or Processing result goes right below it (:func:`add_below_routes`,
:func:`overseec_qgis.layers.run_group`), so a new costmap (drawn at 0.85 opacity, with an opaque
lethal sidecar) never covers a route. A project read back gets the same order
(:class:`RoutesKeeper`: :func:`tidy_routes` on ``QgsProject.readProject``).

Layers are named by what made them, ``'<kind> — <shortened prompt>'``, unique within the project
(:func:`layer_name`): the dock, the map tool and Processing all use it.
"""

from __future__ import annotations

from qgis.core import QgsLayerTreeGroup, QgsMapLayer, QgsProject

# -- the routes group: paths and overrides above every costmap ------------------------------------

#: The custom property holding an overseec layer's role (costmap, path, overrides, mask ...).
PROP_ROLE = "overseec/role"
#: The legend group of the routes and overrides, kept at the top of the legend.
ROUTES_GROUP = "overseec routes & overrides"
#: The custom property that marks that group (found by it, whatever the user renamed it to).
PROP_ROUTES_GROUP = "overseec/routes_group"
#: Roles of the layers that live in the routes group.
ROUTE_ROLES = ("path", "overrides")


def find_routes_group(project: QgsProject | None = None) -> QgsLayerTreeGroup | None:
    """The project's routes group, if it has one (anywhere in the legend)."""
    project = project or QgsProject.instance()
    for group in project.layerTreeRoot().findGroups(True):
        if group.customProperty(PROP_ROUTES_GROUP):
            return group
    return None


def routes_group(project: QgsProject | None = None) -> QgsLayerTreeGroup:
    """The routes group, first child of the legend's root (created there when missing; moved
    there when it is not): path and override layers go in it, so they are drawn above every
    costmap, mask and image."""
    project = project or QgsProject.instance()
    root = project.layerTreeRoot()
    group = find_routes_group(project)
    if group is None:
        group = root.insertGroup(0, ROUTES_GROUP)
        group.setCustomProperty(PROP_ROUTES_GROUP, True)
        group.setItemVisibilityChecked(True)
    elif group.parent() is not root or root.children()[0] is not group:
        group = _move_node(group, root, 0)
    return group


def _move_node(node, parent: QgsLayerTreeGroup, index: int):
    """Move a legend node to ``parent`` at ``index`` (a clone goes in, the node comes out: the
    layer tree has no move); returns the node now in the tree."""
    clone = node.clone()
    parent.insertChildNode(index, clone)
    old_parent = node.parent()
    if old_parent is not None:
        old_parent.removeChildNode(node)
    return clone


def below_routes_index(project: QgsProject) -> int:
    """Where a new top-level legend node goes: right below the routes group, else at the very top."""
    if find_routes_group(project) is None:
        return 0
    routes_group(project)  # first child
    return 1


def add_below_routes(layer: QgsMapLayer, project: QgsProject | None = None) -> QgsMapLayer:
    """Add ``layer`` (or move its legend node) to the top of the legend, right below the routes
    group: a costmap or mask that is new on the map, but never drawn over the routes."""
    project = project or QgsProject.instance()
    if project.mapLayer(layer.id()) is None:
        project.addMapLayer(layer, False)
    root = project.layerTreeRoot()
    index = below_routes_index(project)
    node = root.findLayer(layer.id())
    if node is None:
        root.insertLayer(index, layer)
    else:
        _move_node(node, root, index)
    return layer


def add_to_routes(layer: QgsMapLayer, project: QgsProject | None = None) -> QgsMapLayer:
    """Put ``layer`` (a path or overrides layer) first in the routes group, added to the project
    when it is not yet, visible; first in a custom layer order too, where the project has one."""
    project = project or QgsProject.instance()
    if project.mapLayer(layer.id()) is None:
        project.addMapLayer(layer, False)
    group = routes_group(project)
    node = project.layerTreeRoot().findLayer(layer.id())
    if node is None:
        node = group.insertLayer(0, layer)
    elif node.parent() is not group:
        node = _move_node(node, group, 0)
    node.setItemVisibilityChecked(True)
    group.setItemVisibilityChecked(True)
    _routes_first_in_custom_order(project)
    return layer


def _routes_first_in_custom_order(project: QgsProject) -> None:
    """In a custom layer order (the Layer Order panel), the routes group's layers come first."""
    root = project.layerTreeRoot()
    group = find_routes_group(project)
    if group is None or not root.hasCustomLayerOrder():
        return
    ours = [node.layer() for node in group.findLayers() if node.layer() is not None]
    ids = {lyr.id() for lyr in ours}
    root.setCustomLayerOrder(ours + [lyr for lyr in root.customLayerOrder() if lyr.id() not in ids])


def is_route_layer(layer: QgsMapLayer) -> bool:
    """A path or overrides layer of overseec (by the role its provenance recorded)."""
    return layer.customProperty(PROP_ROLE, "") in ROUTE_ROLES


def tidy_routes(project: QgsProject | None = None) -> QgsLayerTreeGroup | None:
    """Routes and overrides back on top: every path and overrides layer into the routes group,
    the group first in the legend (and its layers first in a custom layer order). Run when a
    project is read; ``None`` where the project has no such layer and no routes group."""
    project = project or QgsProject.instance()
    root = project.layerTreeRoot()
    strays = [
        node
        for node in root.findLayers()
        if node.layer() is not None and is_route_layer(node.layer()) and not _in_routes_group(node)
    ]
    if not strays and find_routes_group(project) is None:
        return None
    group = routes_group(project)
    for node in strays:
        _move_node(node, group, len(group.children()))
    _routes_first_in_custom_order(project)
    return group


def _in_routes_group(node) -> bool:
    parent = node.parent()
    while parent is not None:
        if parent.customProperty(PROP_ROUTES_GROUP):
            return True
        parent = parent.parent()
    return False


def evict_from_routes(layers, project: QgsProject | None = None) -> list[QgsMapLayer]:
    """Layers the analyst added that QGIS put inside the routes group (Layer › Add ... while a
    route layer is selected puts a new layer beside it) move out, to the top level right below
    the group: above the costmaps, never over the routes. Returns the layers moved."""
    project = project or QgsProject.instance()
    group = find_routes_group(project)
    if group is None:
        return []
    moved = []
    root = project.layerTreeRoot()
    for layer in layers:
        try:
            if layer is None or is_route_layer(layer):
                continue
            node = root.findLayer(layer.id())
        except RuntimeError:  # deleted meanwhile
            continue
        if node is not None and _in_routes_group(node):
            routes_group(project)  # first child of the root: right below it is index 1
            _move_node(node, root, 1)
            moved.append(layer)
    if moved:  # the next layer added goes there too, not back into the group
        bridge = project.layerTreeRegistryBridge()
        bridge.setLayerInsertionPoint(bridge.InsertionPoint(root, 1))
    return moved


class RoutesKeeper:
    """Keeps the routes group on top of a project and holding only routes: :func:`tidy_routes`
    each time a project is read (a project saved before the group existed, or one whose legend
    was rearranged), and :func:`evict_from_routes` each time layers are added to the legend. The
    plugin holds one for its session; :meth:`close` disconnects it."""

    def __init__(self, project: QgsProject | None = None) -> None:
        self.project = project or QgsProject.instance()
        self.project.readProject.connect(self.restore)
        self.project.legendLayersAdded.connect(self.added)

    def restore(self, *_args) -> None:
        """The project was read: routes and overrides above everything again."""
        tidy_routes(self.project)

    def added(self, layers) -> None:
        """Layers were added to the legend: any that landed in the routes group move below it."""
        evict_from_routes(layers, self.project)

    def close(self) -> None:
        """Stop watching the project."""
        for signal, slot in ((self.project.readProject, self.restore), (self.project.legendLayersAdded, self.added)):
            try:
                signal.disconnect(slot)
            except TypeError:
                pass


# -- layer names: by prompt, unique within the project ------------------------------------------

#: Longest prompt shown in a layer or group name.
NAME_PROMPT_CHARS = 48


def short_text(text: str, limit: int = NAME_PROMPT_CHARS) -> str:
    """One line, at most ``limit`` characters, cut at a word with an ellipsis."""
    line = " ".join(text.split())
    if len(line) <= limit:
        return line
    cut = line[: limit - 1].rsplit(" ", 1)[0] or line[: limit - 1]
    return cut.rstrip(" ,;.") + "…"


def unique_name(name: str, project: QgsProject | None = None, exclude: QgsMapLayer | None = None) -> str:
    """``name``, or ``name (2)``, ``name (3)`` ... the first no other layer of the project has."""
    project = project or QgsProject.instance()
    taken = {lyr.name() for lyr in project.mapLayers().values() if exclude is None or lyr.id() != exclude.id()}
    if name not in taken:
        return name
    n = 2
    while f"{name} ({n})" in taken:
        n += 1
    return f"{name} ({n})"


def layer_name(
    kind: str,
    prompt: str = "",
    fallback: str = "",
    project: QgsProject | None = None,
    exclude: QgsMapLayer | None = None,
) -> str:
    """A layer's name by what made it: ``'<kind> — <shortened prompt>'``, else ``fallback`` (else
    ``kind``), made unique in ``project`` when one is given (:func:`unique_name`; Processing
    names on its own thread and makes the name unique when the layer is loaded). The dock, the
    map tool and Processing all name costmaps and paths with it."""
    base = f"{kind} — {short_text(prompt)}" if prompt.strip() else (fallback or kind)
    if project is None:
        return base
    return unique_name(distinguishing_name(kind, prompt, base, project, exclude), project, exclude)


def distinguishing_name(
    kind: str, prompt: str, base: str, project: QgsProject, exclude: QgsMapLayer | None = None
) -> str:
    """``base``, unless another layer already has it for a different prompt with the same
    opening ("Prefer the roads and trails, grass is fine, avoid the baseball field" / "... avoid
    the water"): then ``'<kind> — …<the words where this prompt differs>'``, so two routes of a
    comparison are told apart by what their prompts say differently, not by " (2)"."""
    words = prompt.split()
    for layer in project.mapLayers().values():
        if exclude is not None and layer.id() == exclude.id():
            continue
        other = str(layer.customProperty("overseec/prompt", "") or "")
        if layer.name() != base or not other or other.split() == words:
            continue
        theirs = other.split()
        same = next((i for i, (a, b) in enumerate(zip(words, theirs)) if a != b), min(len(words), len(theirs)))
        tail = words[max(0, same - 1) :]
        if tail:
            return f"{kind} — …{short_text(' '.join(tail))}"
    return base
