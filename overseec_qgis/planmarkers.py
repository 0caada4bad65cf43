"""The map tool's canvas items and messages: the markers, the drag preview line, the message bar.

* Markers: start green, vias orange, goal red (:class:`QgsVertexMarker` canvas items, always
  above the map), redrawn from the tool's points whenever they change.
* The drag preview: a dashed blue rubber band showing the route re-planned while a marker is
  dragged (the requests behind it: :mod:`overseec_qgis.planrequests`).
* Message bar: "cannot plan: …" warnings (and ``failed``), and a busy item while a plan waits
  for its costmap to load.

A mixin of :class:`~overseec_qgis.maptool.PlanMapTool` (see :mod:`overseec_qgis.planmixin` for
why): drawing reads the tool's points and canvas, and every other part of the tool redraws.
"""

from __future__ import annotations

from qgis.core import (
    Qgis,
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsGeometry,
    QgsPointXY,
    QgsProject,
    QgsWkbTypes,
)
from qgis.gui import QgsRubberBand, QgsVertexMarker
from qgis.PyQt.QtCore import Qt
from qgis.PyQt.QtGui import QColor

from .planmixin import ToolMixin

#: Marker colours: start, via, goal.
START_COLOUR, VIA_COLOUR, GOAL_COLOUR = QColor(0, 200, 0), QColor(255, 140, 0), QColor(230, 0, 0)
MARKER_SIZE = 16
#: The message shown while a plan waits for its costmap to load.
LOADING_MESSAGE = "loading costmap… the route is planned when it is loaded"


def _marker_colours(n: int, complete: bool) -> list[QColor]:
    """Start green, vias orange, goal red (while placing, every point after the start is a via)."""
    if n == 0:
        return []
    colours = [START_COLOUR] + [VIA_COLOUR] * (n - 1)
    if complete and n > 1:
        colours[-1] = GOAL_COLOUR
    return colours


class MarkersMixin(ToolMixin):
    """The tool's markers, drag preview line and message-bar items."""

    def _init_markers(self) -> None:
        self._loading_item = None
        self.markers: list[QgsVertexMarker] | None = []
        self.preview: QgsRubberBand | None = QgsRubberBand(self.canvas, QgsWkbTypes.LineGeometry)
        self.preview.setColor(QColor(0, 80, 255, 170))
        self.preview.setWidth(3)
        self.preview.setLineStyle(Qt.DashLine)

    def _remove_markers(self) -> None:
        for marker in self.markers or []:
            self.canvas.scene().removeItem(marker)
        if self.markers is not None:
            self.markers.clear()

    def _draw_markers(self) -> None:
        if self.markers is None:
            return
        self._remove_markers()
        for point, colour in zip(self.points, _marker_colours(len(self.points), self.complete)):
            marker = QgsVertexMarker(self.canvas)
            marker.setIconType(QgsVertexMarker.ICON_CIRCLE)
            marker.setIconSize(MARKER_SIZE)
            marker.setPenWidth(3)
            marker.setColor(QColor(255, 255, 255))
            marker.setFillColor(colour)
            marker.setZValue(1000)
            marker.setCenter(point)
            self.markers.append(marker)

    def _show_preview(self, points, crs: QgsCoordinateReferenceSystem) -> None:
        if self.preview is None:
            return
        line = QgsGeometry.fromPolylineXY([QgsPointXY(x, y) for x, y in points])
        try:
            line.transform(
                QgsCoordinateTransform(crs, self.canvas.mapSettings().destinationCrs(), QgsProject.instance())
            )
        except Exception:
            self._clear_preview()
            return
        self.preview.setToGeometry(line, None)

    def _clear_preview(self) -> None:
        if self.preview is not None:
            self.preview.reset(QgsWkbTypes.LineGeometry)

    def _fail(self, message: str) -> None:
        if self.iface is not None:
            self.iface.messageBar().pushMessage("overseec", f"cannot plan: {message}", Qgis.Warning, 6)
        self.failed.emit(message)

    def _show_loading(self) -> None:
        """A message-bar item with a busy bar while a plan waits for its costmap to load."""
        if self.iface is None or self._loading_item is not None:
            return
        from qgis.PyQt.QtWidgets import QProgressBar

        bar = self.iface.messageBar()
        item = bar.createMessage("overseec", LOADING_MESSAGE)
        progress = QProgressBar(item)
        progress.setRange(0, 0)  # busy: the worker reports no progress for a load
        progress.setMaximumWidth(160)
        item.layout().addWidget(progress)
        bar.pushWidget(item, Qgis.Info)
        self._loading_item = item

    def _hide_loading(self) -> None:
        item, self._loading_item = self._loading_item, None
        if item is None or self.iface is None:
            return
        try:
            self.iface.messageBar().popWidget(item)
        except RuntimeError:  # the bar already deleted it
            pass
