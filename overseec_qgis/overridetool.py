"""Draw override polygons with a preset: a map tool for the run's ``overrides.gpkg``.

Analysts correct a costmap by drawing polygons that say *what* the ground is to the route: no-go,
preferred, or a cost on the costmap's 0..1 scale. The tool takes a :class:`OverridePreset`
(:class:`PresetWidget` sets it: "Lethal (no-go)", "Prefer", "Cost" with a slider) and writes the
matching attributes, so nobody needs to know the field names the core reads (``cost``/
``prefer``/``lethal``, :data:`overseec_core.synthesize.overrides.KINDS`, here from
:data:`overseec_qgis.override_layer.OVERRIDE_FIELDS`: QGIS's own Python may have no rasterio).

* Left click adds a vertex; a rubber band previews the polygon with the pointer as its next
  vertex.
* Right click, double click or Enter finishes: the polygon is added to the overrides layer as
  one edit command (Edit > Undo takes it back), in the layer's CRS.
* Backspace removes the last vertex, Esc drops the polygon being drawn.

The layer comes from ``open_layer`` (the plugin passes the dock's Draw overrides, which opens
or creates ``overrides.gpkg`` in the costmap's run folder, puts it in edit mode and has the plan
map tool re-plan on its edits). Each added polygon is then an ordinary edit of that layer: the
route re-plans, Build costmap applies it (saved or not), and the layer's style shows its kind.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from qgis.core import (
    Qgis,
    QgsCoordinateTransform,
    QgsFeature,
    QgsGeometry,
    QgsPointXY,
    QgsProject,
    QgsVectorLayer,
    QgsWkbTypes,
)
from qgis.gui import QgsMapTool, QgsRubberBand
from qgis.PyQt.QtCore import Qt, pyqtSignal
from qgis.PyQt.QtGui import QColor
from qgis.PyQt.QtWidgets import QDoubleSpinBox, QHBoxLayout, QRadioButton, QSizePolicy, QSlider, QWidget

from .override_layer import OVERRIDE_FIELDS

#: The kinds, by the field names `--override` reads (the core's ``synthesize.overrides.KINDS``,
#: which tests check; that module needs rasterio, which QGIS's own Python may lack).
KINDS = tuple(name for name, _kind in OVERRIDE_FIELDS)
COST, PREFER, LETHAL = KINDS
#: What the preset widget calls each kind.
KIND_LABELS = {LETHAL: "Lethal (no-go)", PREFER: "Prefer", COST: "Cost"}
#: A double click this close (screen pixels) to the last vertex finishes without adding one.
DOUBLE_CLICK_PX = 3
#: Slider steps over the 0..1 cost scale.
COST_STEPS = 100
BAND_FILL, BAND_LINE = QColor(255, 140, 0, 70), QColor(255, 140, 0, 230)


@dataclass(frozen=True)
class OverridePreset:
    """What a drawn polygon says: ``kind`` is one of :data:`KINDS`; ``cost`` counts for ``cost``
    only (the core gives prefer its PREFER_COST, 0, and lethal its LETHAL_COST, 1, impassable)."""

    kind: str = LETHAL
    cost: float = 0.5

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"override kind {self.kind!r}: one of {', '.join(KINDS)}")
        if not 0.0 <= self.cost <= 1.0:
            raise ValueError(f"override cost {self.cost}: between 0 and 1")

    def attributes(self) -> dict[str, float | int | None]:
        """Field values of a feature with this preset: exactly one of the kinds set (the core
        rejects a feature with none or several), the others NULL."""
        values: dict[str, float | int | None] = dict.fromkeys(KINDS)
        values[self.kind] = round(self.cost, 4) if self.kind == COST else 1
        return values

    def describe(self) -> str:
        """A short name for messages and the undo stack."""
        return f"cost {self.cost:g}" if self.kind == COST else KIND_LABELS[self.kind].lower()


class PresetWidget(QWidget):
    """Three choices and a cost slider/spin box (0..1); emits ``changed(OverridePreset)``."""

    changed = pyqtSignal(object)

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setObjectName("overseecOverridePresets")
        row = QHBoxLayout(self)
        row.setContentsMargins(2, 0, 2, 0)
        # as wide as its contents (a toolbar would stretch it, and a click beside a button's
        # text would hit nothing)
        self.setSizePolicy(QSizePolicy.Maximum, QSizePolicy.Fixed)
        self.buttons: dict[str, QRadioButton] = {}
        for kind in (LETHAL, PREFER, COST):
            button = QRadioButton(KIND_LABELS[kind])
            button.setObjectName(f"overseecOverride_{kind}")
            button.toggled.connect(self._emit)
            self.buttons[kind] = button
            row.addWidget(button)
        self.slider = QSlider(Qt.Horizontal)
        self.slider.setRange(0, COST_STEPS)
        self.slider.setMaximumWidth(120)
        self.spin = QDoubleSpinBox()
        self.spin.setRange(0.0, 1.0)
        self.spin.setSingleStep(0.05)
        self.spin.setDecimals(2)
        self.spin.setMaximumWidth(70)
        for w in (self.slider, self.spin):
            w.setToolTip("Cost under the polygon: 0 preferred, 0.5 neutral, 1 most avoided (still passable)")
            row.addWidget(w)
        self.slider.valueChanged.connect(lambda v: self.spin.setValue(v / COST_STEPS))
        self.spin.valueChanged.connect(self._cost_changed)
        self.set_preset(OverridePreset())

    def _cost_changed(self, value: float) -> None:
        self.slider.blockSignals(True)
        self.slider.setValue(round(value * COST_STEPS))
        self.slider.blockSignals(False)
        if not self.buttons[COST].isChecked():
            self.buttons[COST].setChecked(True)  # moving the cost means drawing cost polygons
        else:
            self._emit()

    def _emit(self, *_args) -> None:
        if any(b.isChecked() for b in self.buttons.values()):
            self.changed.emit(self.preset())

    def preset(self) -> OverridePreset:
        """The preset the widget shows."""
        kind = next((k for k, b in self.buttons.items() if b.isChecked()), LETHAL)
        return OverridePreset(kind, round(self.spin.value(), 4))

    def set_preset(self, preset: OverridePreset) -> None:
        """Show ``preset`` (emits ``changed`` once)."""
        self.spin.blockSignals(True)
        self.spin.setValue(preset.cost)
        self.spin.blockSignals(False)
        self.slider.blockSignals(True)
        self.slider.setValue(round(preset.cost * COST_STEPS))
        self.slider.blockSignals(False)
        if self.buttons[preset.kind].isChecked():
            self._emit()
        else:
            self.buttons[preset.kind].setChecked(True)


class OverrideTool(QgsMapTool):
    """The map tool (see the module docstring). ``open_layer`` returns the overrides layer
    (opening or creating it), or None after saying why; emits ``added(fid)`` after each polygon
    and ``failed(message)``."""

    added = pyqtSignal(int)
    failed = pyqtSignal(str)

    def __init__(
        self,
        canvas,
        iface=None,
        open_layer: Callable[[], QgsVectorLayer | None] | None = None,
        preset: OverridePreset | None = None,
    ) -> None:
        super().__init__(canvas)
        self.canvas, self.iface = canvas, iface
        self.open_layer = open_layer
        self.preset = preset or OverridePreset()
        self.layer: QgsVectorLayer | None = None
        self.points: list[QgsPointXY] = []  # canvas CRS
        self._skip_release = False
        self.band = QgsRubberBand(canvas, QgsWkbTypes.PolygonGeometry)
        self.band.setFillColor(BAND_FILL)
        self.band.setStrokeColor(BAND_LINE)
        self.band.setWidth(2)
        self.setCursor(Qt.CrossCursor)

    def set_preset(self, preset: OverridePreset) -> None:
        """Draw the next polygons with ``preset`` (the one being drawn too)."""
        self.preset = preset

    def set_layer(self, layer: QgsVectorLayer | None) -> None:
        """Add the polygons to ``layer`` (None: ask ``open_layer`` at the next polygon)."""
        self.layer = layer

    def target_layer(self, start_editing: bool = True) -> QgsVectorLayer | None:
        """The overrides layer, opened again if it was removed from the project; in edit mode
        unless ``start_editing`` is False (the caller turns it on later)."""
        layer = self.layer
        if layer is None or QgsProject.instance().mapLayer(layer.id()) is None:
            layer = self.layer = self.open_layer() if self.open_layer is not None else None
        if layer is None or not start_editing:
            return layer
        return layer if self.start_editing() else None

    def start_editing(self) -> bool:
        """Turn editing on for the layer (if it is not on); False after saying why it cannot be."""
        layer = self.layer
        if layer is None or QgsProject.instance().mapLayer(layer.id()) is None:
            return False
        if not layer.isEditable() and not layer.startEditing():
            self._fail(f"{layer.name()} cannot be edited (read-only file?)")
            return False
        return True

    # -- events --------------------------------------------------------------------------------

    def canvasPressEvent(self, e) -> None:
        self._skip_release = False  # a new click: no double click's release is pending

    def canvasMoveEvent(self, e) -> None:
        if self.points:
            self._draw_band(e.mapPoint())

    def canvasReleaseEvent(self, e) -> None:
        if self._skip_release:  # the release that ends a double click
            self._skip_release = False
            return
        if e.button() == Qt.RightButton:
            self.finish()
        elif e.button() == Qt.LeftButton:
            self.points.append(QgsPointXY(e.mapPoint()))
            self._draw_band()

    def canvasDoubleClickEvent(self, e) -> None:
        # a user's double click is press, release (which placed the vertex), double click,
        # release (skipped); without that first release the vertex is placed here
        point = QgsPointXY(e.mapPoint())
        last = self.toCanvasCoordinates(self.points[-1]) if self.points else None
        if last is None or (last - e.pos()).manhattanLength() > DOUBLE_CLICK_PX:
            self.points.append(point)
        self._skip_release = True
        self.finish()

    def keyPressEvent(self, e) -> None:
        key = e.key()
        if key in (Qt.Key_Return, Qt.Key_Enter):
            self.finish()
        elif key in (Qt.Key_Backspace, Qt.Key_Delete) and self.points:
            self.points.pop()
            self._draw_band()
        elif key == Qt.Key_Escape:
            self.cancel()
        else:
            e.ignore()
            return
        e.accept()  # not QGIS's "delete selected features" on Backspace/Delete

    def deactivate(self) -> None:
        self.cancel()
        super().deactivate()

    def cancel(self) -> None:
        """Drop the polygon being drawn."""
        self.points = []
        self.band.reset(QgsWkbTypes.PolygonGeometry)

    def clear(self) -> None:
        """Drop the drawing and forget the layer (the plugin is unloading)."""
        self.cancel()
        self.layer = None
        self.canvas.scene().removeItem(self.band)

    # -- the polygon -----------------------------------------------------------------------------

    def _draw_band(self, pointer: QgsPointXY | None = None) -> None:
        self.band.reset(QgsWkbTypes.PolygonGeometry)
        points = self.points + ([QgsPointXY(pointer)] if pointer is not None else [])
        for i, p in enumerate(points):
            self.band.addPoint(p, i == len(points) - 1)

    def polygon(self) -> QgsGeometry | None:
        """The polygon drawn so far (canvas CRS), or None with fewer than three vertices."""
        if len(self.points) < 3:
            return None
        return QgsGeometry.fromPolygonXY([self.points + [self.points[0]]])

    def finish(self) -> int | None:
        """Add the polygon drawn so far to the overrides layer (one undoable command) with the
        preset's attributes; the new feature's id, or None after saying why not."""
        geometry = self.polygon()
        if geometry is None:
            if self.points:
                self._fail("an override polygon needs at least three vertices (Backspace removes one, Esc drops it)")
            return None
        if not geometry.isGeosValid():
            self._fail("the polygon crosses itself: Backspace removes the last vertex")
            return None
        layer = self.target_layer()
        if layer is None:
            return None
        fid = self.add_polygon(layer, geometry, self.canvas.mapSettings().destinationCrs())
        if fid is not None:
            self.cancel()
            self.added.emit(fid)
        return fid

    def add_polygon(self, layer: QgsVectorLayer, geometry: QgsGeometry, crs) -> int | None:
        """``geometry`` (in ``crs``) into ``layer`` with the preset's attributes, as one edit
        command; the feature's (temporary) id, or None after saying why."""
        missing = [name for name in KINDS if layer.fields().indexOf(name) < 0]
        if missing:
            self._fail(f"{layer.name()} has no field {', '.join(missing)}: not an overseec overrides layer")
            return None
        geometry = QgsGeometry(geometry)
        if crs.isValid() and layer.crs().isValid() and crs != layer.crs():
            geometry.transform(QgsCoordinateTransform(crs, layer.crs(), QgsProject.instance()))
        feature = QgsFeature(layer.fields())
        feature.setGeometry(geometry)
        for name, value in self.preset.attributes().items():
            feature.setAttribute(name, value)
        layer.beginEditCommand(f"Add override polygon ({self.preset.describe()})")
        if not layer.addFeature(feature):
            layer.destroyEditCommand()
            self._fail(f"{layer.name()} refused the polygon")
            return None
        layer.endEditCommand()
        layer.triggerRepaint()
        return int(feature.id())

    def _fail(self, message: str) -> None:
        self.failed.emit(message)
        if self.iface is not None:
            self.iface.messageBar().pushMessage("overseec overrides", message, Qgis.Warning, 5)


def write_overrides_snapshot(layer: QgsVectorLayer, path: str | os.PathLike) -> Path | None:
    """``layer`` as it is now -- saved features plus unsaved edits, those the core accepts
    (:func:`~overseec_qgis.overridecheck.usable_features`) -- as a GeoPackage at ``path`` (in
    the layer's CRS) for `overseec costmap --override`; None when no feature is left to apply.
    Raises OSError with a one-line reason when it cannot be written."""
    from .planfiles import OverridesSnapshot

    snapshot = OverridesSnapshot(layer, Path(path), QgsProject.instance().transformContext())
    if not snapshot.features:
        return None
    try:
        snapshot.ensure_written()
    except OSError as exc:
        raise OSError(f"cannot write the unsaved override edits of {layer.name()} to {path}: {exc}") from None
    return Path(path)
