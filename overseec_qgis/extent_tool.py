"""A map tool to draw the rectangle to extract imagery from.

Press the left button, drag, release: the tool emits ``extent_drawn(QgsRectangle)`` in the canvas
CRS and keeps the rectangle on the map (a rubber band) until the next one or :meth:`reset`, also
after the tool is switched off (so the operator sees what is being extracted). A click without
a drag (under a few screen pixels), a right click or Esc cancels the rectangle being drawn and
emits ``cancelled()``. :meth:`show_extent` draws a rectangle chosen
another way (e.g. the canvas extent) the same way, so the operator sees what will be extracted.
"""

from __future__ import annotations

from qgis.core import QgsPointXY, QgsRectangle, QgsWkbTypes
from qgis.gui import QgsMapTool, QgsRubberBand
from qgis.PyQt.QtCore import QPoint, Qt, pyqtSignal
from qgis.PyQt.QtGui import QColor

#: A drag shorter than this many screen pixels on either axis is a click, not a rectangle.
MIN_DRAG_PX = 4
OUTLINE = QColor(255, 0, 110)
FILL = QColor(255, 0, 110, 40)


class ExtentMapTool(QgsMapTool):
    """Draws a rectangle on the canvas and emits it in the canvas CRS."""

    extent_drawn = pyqtSignal(QgsRectangle)
    cancelled = pyqtSignal()

    def __init__(self, canvas) -> None:
        super().__init__(canvas)
        self.band = QgsRubberBand(canvas, QgsWkbTypes.PolygonGeometry)
        self.band.setStrokeColor(OUTLINE)
        self.band.setFillColor(FILL)
        self.band.setWidth(2)
        self._start: QPoint | None = None
        self.extent: QgsRectangle | None = None
        self.setCursor(Qt.CrossCursor)

    # -- drawing -------------------------------------------------------------------------------

    def _to_map(self, pos: QPoint) -> QgsPointXY:
        return self.toMapCoordinates(pos)

    def _rectangle(self, a: QPoint, b: QPoint) -> QgsRectangle:
        return QgsRectangle(self._to_map(a), self._to_map(b))  # normalised: min/max sorted

    def show_extent(self, extent: QgsRectangle | None) -> None:
        """Draw ``extent`` (canvas CRS) as the current rectangle; None clears it."""
        self.band.reset(QgsWkbTypes.PolygonGeometry)
        self.extent = None
        if extent is None or extent.isEmpty():
            return
        corners = (
            QgsPointXY(extent.xMinimum(), extent.yMinimum()),
            QgsPointXY(extent.xMaximum(), extent.yMinimum()),
            QgsPointXY(extent.xMaximum(), extent.yMaximum()),
            QgsPointXY(extent.xMinimum(), extent.yMaximum()),
        )
        for i, p in enumerate(corners):
            self.band.addPoint(p, i == len(corners) - 1)
        self.band.show()
        self.extent = QgsRectangle(extent)

    def canvasPressEvent(self, e) -> None:
        if e.button() == Qt.RightButton:
            self.cancel()
            return
        if e.button() == Qt.LeftButton:
            self._start = e.pos()
            self.show_extent(None)

    def canvasMoveEvent(self, e) -> None:
        if self._start is None:
            return
        self.show_extent(self._rectangle(self._start, e.pos()))

    def canvasReleaseEvent(self, e) -> None:
        if e.button() != Qt.LeftButton or self._start is None:
            return
        start, self._start = self._start, None
        end = e.pos()
        if abs(end.x() - start.x()) < MIN_DRAG_PX or abs(end.y() - start.y()) < MIN_DRAG_PX:
            self.show_extent(None)
            self.cancelled.emit()
            return
        rect = self._rectangle(start, end)
        self.show_extent(rect)
        self.extent_drawn.emit(QgsRectangle(rect))

    def keyPressEvent(self, e) -> None:
        if e.key() == Qt.Key_Escape:
            self.cancel()
            e.accept()
            return
        super().keyPressEvent(e)

    # -- state ---------------------------------------------------------------------------------

    def cancel(self) -> None:
        """Drop the rectangle being drawn (and the one shown) and say so."""
        self._start = None
        self.show_extent(None)
        self.cancelled.emit()

    def reset(self) -> None:
        """Clear the rectangle without a signal (e.g. after the extraction was started)."""
        self._start = None
        self.show_extent(None)

    def deactivate(self) -> None:
        """Switching tools drops a half-drawn rectangle but keeps a finished one on the map, so
        the operator still sees what is being extracted; :meth:`reset` removes it."""
        if self._start is not None:
            self._start = None
            self.show_extent(None)
        super().deactivate()
