"""Override features checked as the core checks them, so one bad feature never stops planning.

`overseec costmap|plan --override` refuses a whole file for one feature it cannot read (a CLI
contract: a batch run must not silently drop an edit). In QGIS a polygon digitized with QGIS's
own Add Polygon and an all-NULL form is an ordinary moment of editing, not a reason to stop every
plan: the plugin hands the core only the features it accepts
(:mod:`overseec_core.synthesize.override_rules`, the core's own rules) and says, once, which it
skipped -- by the feature id the attribute table shows, with a zoom-to action.
"""

from __future__ import annotations

from dataclasses import dataclass

from qgis.core import QgsFeature, QgsProject, QgsVectorLayer, QgsWkbTypes
from qgis.PyQt.QtCore import QVariant

from overseec_core.synthesize.override_rules import classify, geometry_problem

from .legend import PROP_ROLE


@dataclass(frozen=True)
class SkippedFeature:
    """A feature of an overrides layer the core would refuse: which, and why."""

    layer_id: str
    layer_name: str
    fid: int
    why: str

    def describe(self) -> str:
        """One line, naming the feature as the analyst sees it."""
        which = f"feature {self.fid}" if self.fid >= 0 else "a new (unsaved) feature"
        return (
            f"{self.layer_name}: {which} {self.why}; skipped -- in its attribute table set lethal=1, "
            "prefer=1 or a cost in 0-1"
        )


def _value(value):
    """A feature attribute as the core reads it (QGIS's NULL, a null QVariant, is None)."""
    return None if value is None or (isinstance(value, QVariant) and value.isNull()) else value


def feature_problem(feature: QgsFeature) -> str | None:
    """Why the core would refuse this feature as an override (None when it takes it)."""
    geom = feature.geometry()
    if geom is None or geom.isNull():
        why = geometry_problem(None, True)
    else:
        kind = QgsWkbTypes.displayString(QgsWkbTypes.flatType(geom.wkbType()))
        why = geometry_problem(kind, geom.isEmpty())
    if why is not None:
        return why
    props = {field.name(): _value(feature[field.name()]) for field in feature.fields()}
    try:
        classify(props)
    except ValueError as exc:
        return str(exc)
    return None


def usable_features(layer: QgsVectorLayer) -> tuple[list[QgsFeature], list[SkippedFeature]]:
    """The layer's features now (unsaved edits included) the core accepts, and those it would refuse."""
    kept, skipped = [], []
    for feature in layer.getFeatures():
        why = feature_problem(feature)
        if why is None:
            kept.append(feature)
        else:
            skipped.append(SkippedFeature(layer.id(), layer.name(), int(feature.id()), why))
    return kept, skipped


def project_overrides_layers(project: QgsProject | None = None) -> list[QgsVectorLayer]:
    """Every overrides layer of the project (the dock's Draw overrides layers, the override
    tool's), in legend order: the analyst's corrections belong to the project, whatever run
    folder is current."""
    project = project or QgsProject.instance()
    order = [lyr.id() for lyr in project.layerTreeRoot().layerOrder()]
    found = [
        lyr
        for lyr in project.mapLayers().values()
        if isinstance(lyr, QgsVectorLayer) and lyr.isValid() and lyr.customProperty(PROP_ROLE) == "overrides"
    ]
    return sorted(found, key=lambda lyr: order.index(lyr.id()) if lyr.id() in order else len(order))


def push_skipped(iface, skipped: list[SkippedFeature], title: str = "overseec overrides") -> None:
    """One message-bar warning for the skipped features, with a button that selects and zooms to
    the first (and opens its row in the attribute table)."""
    if iface is None or not skipped:
        return
    from qgis.core import Qgis
    from qgis.PyQt.QtWidgets import QPushButton

    first = skipped[0]
    text = first.describe() + (f" (and {len(skipped) - 1} more)" if len(skipped) > 1 else "")
    bar = iface.messageBar()
    widget = bar.createMessage(title, text)
    button = QPushButton("Zoom to feature", widget)

    def zoom() -> None:
        layer = QgsProject.instance().mapLayer(first.layer_id)
        if layer is None:
            return
        ids = [s.fid for s in skipped if s.layer_id == first.layer_id]
        layer.selectByIds(ids)
        iface.mapCanvas().zoomToFeatureIds(layer, ids)
        iface.showAttributeTable(layer, f"$id = {first.fid}")

    button.clicked.connect(zoom)
    widget.layout().addWidget(button)
    bar.pushWidget(widget, Qgis.Warning, 15)
