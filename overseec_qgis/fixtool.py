"""Click to fix a mask: a map tool that prompts SAM for one entity and writes the corrected mask.

* Left click: an include point (green); right click or Shift+click: an exclude point (red); drag
  with the left button: a box (one per prompt; a new drag replaces it). After each one the
  entity's edited mask on the view is drawn as a filled overlay.
* Enter (or :meth:`FixMaskTool.apply`): write it into the entity's band of the segment folder's
  mask raster (refined masks over coarse ones) and its probability band; the folder's mask layers
  are reloaded and ``overseec costmap --masks DIR`` rebuilds from it. Esc drops the prompts,
  Backspace the last point.
* Modes: A adds SAM's mask to the entity's mask (the default: a missed object), D removes it (a
  false one), R replaces the view's mask with it.

SAM runs in the overseec environment's worker (``overseec sam-server``, through
:mod:`overseec_qgis.samclient`): QGIS never imports torch. The worker embeds the *view* once --
the canvas extent on the image, at most :data:`MAX_VIEW_PX` image pixels a side around the first
click, outlined dashed on the canvas -- in a background thread (seconds on a GPU, tens of seconds
on a CPU for SAM ViT-B), and answers every click with the mask decoder alone. A click outside the
view starts over on a new view there. Points are picked in the canvas CRS and sent in the image's.
"""

from __future__ import annotations

import json
import os
import threading
from dataclasses import dataclass
from pathlib import Path

from qgis.core import (
    Qgis,
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsGeometry,
    QgsPointXY,
    QgsProject,
    QgsRasterLayer,
    QgsRectangle,
    QgsWkbTypes,
)
from qgis.gui import QgsMapTool, QgsRubberBand, QgsVertexMarker
from qgis.PyQt.QtCore import QPoint, Qt, pyqtSignal
from qgis.PyQt.QtGui import QColor

from overseec_core import runfiles

from .layers import PROP_ROLE
from .samclient import ApplyReply, MaskReply, SamClient, SamClientError, ViewInfo, shared_client

#: A press becomes a box drag once the mouse moved this many screen pixels.
DRAG_START_PX = 4
#: The longest side of a view in image pixels (the worker's default limit).
MAX_VIEW_PX = 2048
INCLUDE_COLOUR, EXCLUDE_COLOUR = QColor(0, 200, 0), QColor(230, 0, 0)
MASK_FILL, MASK_LINE = QColor(255, 0, 255, 90), QColor(255, 0, 255, 220)
MODES = ("add", "remove", "replace")
MODE_KEYS = {Qt.Key_A: "add", Qt.Key_D: "remove", Qt.Key_R: "replace"}


@dataclass(frozen=True)
class FixTarget:
    """What the tool fixes: an entity of a segment folder, on the image it was segmented from."""

    image: str
    segment_dir: str
    entity: str
    crs: QgsCoordinateReferenceSystem  # the image's (and the masks')


def image_of(segment_dir: str | os.PathLike) -> str | None:
    """The image a segment folder was made from (its manifest's ``inputs.image``), if it exists."""
    try:
        manifest = json.loads((Path(segment_dir) / runfiles.MANIFEST).read_text(encoding="utf-8"))
        path = manifest["inputs"]["image"]["path"]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    return path if isinstance(path, str) and Path(path).is_file() else None


def target_from_layer(layer, image: str | None = None) -> FixTarget:
    """The target an entity's mask layer (added by the plugin) names; ``image`` overrides the
    manifest's. A LookupError says what is missing."""
    if not isinstance(layer, QgsRasterLayer) or layer.customProperty(PROP_ROLE) != "mask":
        raise LookupError("select an entity's mask layer of an overseec run in the Layers panel first")
    entity = str(layer.customProperty("overseec/entity", "") or "")
    folder = os.path.dirname(layer.dataProvider().dataSourceUri().split("|")[0])
    image = image or image_of(folder)
    if not entity or image is None:
        raise LookupError(f"cannot tell the entity and image of {layer.name()}: its folder has no manifest")
    return FixTarget(image=image, segment_dir=folder, entity=entity, crs=layer.crs())


def view_bounds(
    extent: QgsRectangle, centre: QgsPointXY, pixel: float, max_px: int = MAX_VIEW_PX
) -> tuple[float, float, float, float]:
    """The view to embed (image CRS): the canvas extent, or a ``max_px`` square of image pixels
    (``pixel`` map units each) around ``centre`` where the extent is larger."""
    half = 0.5 * max_px * pixel
    x0, x1 = extent.xMinimum(), extent.xMaximum()
    y0, y1 = extent.yMinimum(), extent.yMaximum()
    if x1 - x0 > 2 * half:
        x0, x1 = centre.x() - half, centre.x() + half
    if y1 - y0 > 2 * half:
        y0, y1 = centre.y() - half, centre.y() + half
    return x0, y0, x1, y1


class FixMaskTool(QgsMapTool):
    """The map tool (see the module docstring); emits ``changed(MaskReply)`` after each prompt,
    ``applied(ApplyReply)`` after a write and ``failed(message)``."""

    changed = pyqtSignal(object)
    applied = pyqtSignal(object)
    failed = pyqtSignal(str)
    _opened = pyqtSignal(object, object)  # (ViewInfo or exception, view token), from the thread

    def __init__(self, canvas, iface=None, client: SamClient | None = None) -> None:
        super().__init__(canvas)
        self.canvas, self.iface, self._client = canvas, iface, client
        self.target: FixTarget | None = None
        self.mode = "add"
        self.points: list[tuple[QgsPointXY, int]] = []  # canvas CRS, label (1 include, 0 exclude)
        self.box: QgsRectangle | None = None  # canvas CRS
        self.view: ViewInfo | None = None
        self.last: MaskReply | None = None
        self._opening: object | None = None  # token of the view being embedded
        self._press: tuple[int, int, object] | None = None  # x, y, button
        self._dragging = False
        self.markers: list[QgsVertexMarker] = []
        self.mask_band = QgsRubberBand(canvas, QgsWkbTypes.PolygonGeometry)
        self.mask_band.setFillColor(MASK_FILL)
        self.mask_band.setStrokeColor(MASK_LINE)
        self.mask_band.setWidth(1)
        self.box_band = QgsRubberBand(canvas, QgsWkbTypes.PolygonGeometry)
        self.box_band.setFillColor(QColor(0, 0, 0, 0))
        self.box_band.setStrokeColor(QColor(255, 200, 0))
        self.box_band.setWidth(2)
        self.view_band = QgsRubberBand(canvas, QgsWkbTypes.PolygonGeometry)
        self.view_band.setFillColor(QColor(0, 0, 0, 0))
        self.view_band.setStrokeColor(QColor(0, 120, 255, 200))
        self.view_band.setLineStyle(Qt.DashLine)
        self._opened.connect(self._on_opened)
        self.setCursor(Qt.CrossCursor)

    # -- configuration -----------------------------------------------------------------------

    @property
    def client(self) -> SamClient:
        """The SAM worker's client (the session's shared one unless one was given)."""
        return self._client if self._client is not None else shared_client()

    def set_target(self, target: FixTarget) -> None:
        """Fix ``target``'s entity from now on (the prompts and the view start over)."""
        if target != self.target:
            self.reset()
            self.view, self.target = None, target
            self.view_band.reset(QgsWkbTypes.PolygonGeometry)

    def set_mode(self, mode: str) -> None:
        """``add``, ``remove`` or ``replace`` (see the module docstring); re-prompts."""
        if mode not in MODES:
            raise ValueError(f"mode must be one of {', '.join(MODES)}")
        self.mode = mode
        self._message(f"fix mask: {mode}", Qgis.Info, 2)
        self.update_mask()

    def _to_image(self) -> QgsCoordinateTransform:
        assert self.target is not None
        return QgsCoordinateTransform(
            self.canvas.mapSettings().destinationCrs(), self.target.crs, QgsProject.instance()
        )

    # -- events --------------------------------------------------------------------------------

    def canvasPressEvent(self, e) -> None:
        self._press, self._dragging = (e.pos().x(), e.pos().y(), e.button()), False

    def canvasMoveEvent(self, e) -> None:
        if self._press is None or self._press[2] != Qt.LeftButton:
            return
        x, y, _button = self._press
        if not self._dragging and max(abs(e.pos().x() - x), abs(e.pos().y() - y)) < DRAG_START_PX:
            return
        self._dragging = True
        rect = QgsRectangle(self.toMapCoordinates(QPoint(x, y)), self.toMapCoordinates(e.pos()))
        self.box_band.setToGeometry(QgsGeometry.fromRect(rect), None)

    def canvasReleaseEvent(self, e) -> None:
        pressed, self._press = self._press, None
        if pressed is None:
            return
        point = self.toMapCoordinates(e.pos())
        if self._dragging:
            self._dragging = False
            self.box = QgsRectangle(self.toMapCoordinates(QPoint(pressed[0], pressed[1])), point)
            self.box.normalize()
            self._prompt_at(self.box.center(), from_box=True)
            return
        if e.button() not in (Qt.LeftButton, Qt.RightButton):
            return
        exclude = e.button() == Qt.RightButton or bool(e.modifiers() & Qt.ShiftModifier)
        self.points.append((point, 0 if exclude else 1))
        self._draw_markers()
        self._prompt_at(point)

    def keyPressEvent(self, e) -> None:
        key = e.key()
        if key in (Qt.Key_Return, Qt.Key_Enter):
            self.apply()
        elif key == Qt.Key_Escape:
            self.reset()
        elif key == Qt.Key_Backspace and self.points:
            self.points.pop()
            self._draw_markers()
            self.update_mask()
        elif key in MODE_KEYS:
            self.set_mode(MODE_KEYS[key])
        else:
            e.ignore()
            return
        e.accept()

    def deactivate(self) -> None:
        self.reset()
        super().deactivate()

    # -- the view and the prompts -------------------------------------------------------------------

    def _in_view(self, point: QgsPointXY) -> bool:
        if self.view is None:
            return False
        p = self._to_image().transform(point)
        x0, y0, x1, y1 = self.view.bounds
        return x0 <= p.x() <= x1 and y0 <= p.y() <= y1

    def _prompt_at(self, point: QgsPointXY, from_box: bool = False) -> None:
        """After a click (or a box, centred at ``point``): prompt, opening a view there first if
        needed."""
        if self.target is None:
            self._fail("no mask to fix: choose an entity's mask layer first")
            return
        if self._opening is not None:
            return  # the view is being embedded; its completion prompts with everything so far
        if self.view is not None and not self._in_view(point):
            self.view = None  # a click beyond the view: start over there with this click alone
            if from_box:
                self.points = []
            else:
                self.points, self.box = self.points[-1:], None
                self.box_band.reset(QgsWkbTypes.PolygonGeometry)
            self._draw_markers()
        if self.view is None:
            self._open_view(point)
            return
        self.update_mask()

    def _open_view(self, centre: QgsPointXY) -> None:
        """Embed the view around ``centre`` in the worker, in a background thread."""
        assert self.target is not None
        to_image = self._to_image()
        extent = to_image.transformBoundingBox(self.canvas.extent())
        layer = QgsRasterLayer(self.target.image, "probe", "gdal")
        pixel = layer.rasterUnitsPerPixelX() if layer.isValid() else 1.0
        bounds = view_bounds(extent, to_image.transform(centre), pixel)
        token = object()
        self._opening = token
        target, client = self.target, self.client
        self._message("SAM is embedding the view…", Qgis.Info, 3)

        def run() -> None:
            try:
                result: object = client.open(target.image, target.segment_dir, bounds)
            except SamClientError as exc:
                result = exc
            self._opened.emit(result, token)

        threading.Thread(target=run, name="overseec-sam-open", daemon=True).start()

    def _on_opened(self, result: object, token: object) -> None:
        if token is not self._opening:
            return  # a newer view was asked for (or the tool was reset)
        self._opening = None
        if isinstance(result, Exception):
            self._fail(str(result))
            return
        assert isinstance(result, ViewInfo)
        self.view = result
        if self.target is not None and self.target.entity not in result.entities:
            self._fail(f"{self.target.entity} is not among the folder's entities ({', '.join(result.entities)})")
            return
        x0, y0, x1, y1 = result.bounds
        outline = QgsGeometry.fromRect(QgsRectangle(x0, y0, x1, y1))
        outline.transform(self._to_image(), QgsCoordinateTransform.ReverseTransform)
        self.view_band.setToGeometry(outline, None)
        self._message(
            f"view embedded in {result.embed_ms / 1000:.1f} s ({result.model} on {result.device})", Qgis.Info, 3
        )
        self.update_mask()

    def _prompt_fields(self) -> dict:
        """Points, labels and box in the image's CRS."""
        to_image = self._to_image()
        points = [to_image.transform(p) for p, _label in self.points]
        box = None
        if self.box is not None:
            r = to_image.transformBoundingBox(self.box)
            box = (r.xMinimum(), r.yMinimum(), r.xMaximum(), r.yMaximum())
        return {
            "points": [(p.x(), p.y()) for p in points],
            "labels": [label for _p, label in self.points],
            "box": box,
            "mode": self.mode,
        }

    def update_mask(self) -> MaskReply | None:
        """Prompt SAM with the current points and box; draw the entity's edited mask."""
        if self.target is None or self.view is None or (not self.points and self.box is None):
            self.mask_band.reset(QgsWkbTypes.PolygonGeometry)
            return None
        try:
            reply = self.client.prompt(self.target.entity, **self._prompt_fields())
        except SamClientError as exc:
            self._fail(str(exc))
            return None
        self.last = reply
        self._draw_mask(reply)
        self.changed.emit(reply)
        return reply

    def apply(self) -> ApplyReply | None:
        """Write the current edit into the segment folder, reload its layers, start over."""
        if self.target is None or self.view is None or (not self.points and self.box is None):
            self._fail("nothing to apply: click on the map first")
            return None
        try:
            reply = self.client.apply(self.target.entity, **self._prompt_fields())
        except SamClientError as exc:
            self._fail(str(exc))
            return None
        self._reload_layers()
        self.reset()
        self._message(
            f"{self.target.entity}: {reply.pixels_added} pixels added, {reply.pixels_removed} removed "
            f"({', '.join(reply.files)})",
            Qgis.Success,
            5,
        )
        self.applied.emit(reply)
        return reply

    def _reload_layers(self) -> None:
        """Reload every layer of the project reading a file of the segment folder."""
        assert self.target is not None
        folder = os.path.realpath(self.target.segment_dir)
        for layer in QgsProject.instance().mapLayers().values():
            source = layer.dataProvider().dataSourceUri().split("|")[0] if layer.dataProvider() else ""
            if source and os.path.dirname(os.path.realpath(source)) == folder:
                layer.reload()
                layer.triggerRepaint()

    def reset(self) -> None:
        """Drop the prompts and the overlay (the view stays embedded in the worker)."""
        self.points, self.box, self.last = [], None, None
        self._press, self._dragging = None, False
        self._draw_markers()
        self.mask_band.reset(QgsWkbTypes.PolygonGeometry)
        self.box_band.reset(QgsWkbTypes.PolygonGeometry)

    def clear(self) -> None:
        """Reset and take every canvas item off the canvas (plugin unload)."""
        self.reset()
        self._opening = None
        for band in (self.mask_band, self.box_band, self.view_band):
            self.canvas.scene().removeItem(band)

    # -- drawing and messages -------------------------------------------------------------------

    def _draw_mask(self, reply: MaskReply) -> None:
        polygons = [[[QgsPointXY(x, y) for x, y in ring] for ring in polygon] for polygon in reply.polygons]
        if not polygons:
            self.mask_band.reset(QgsWkbTypes.PolygonGeometry)
            return
        geom = QgsGeometry.fromMultiPolygonXY(polygons)
        geom.transform(self._to_image(), QgsCoordinateTransform.ReverseTransform)
        self.mask_band.setToGeometry(geom, None)

    def _draw_markers(self) -> None:
        for marker in self.markers:
            self.canvas.scene().removeItem(marker)
        self.markers = []
        for point, label in self.points:
            marker = QgsVertexMarker(self.canvas)
            marker.setIconType(QgsVertexMarker.ICON_CIRCLE)
            marker.setIconSize(12)
            marker.setPenWidth(2)
            marker.setColor(QColor(255, 255, 255))
            marker.setFillColor(INCLUDE_COLOUR if label else EXCLUDE_COLOUR)
            marker.setZValue(1000)
            marker.setCenter(point)
            self.markers.append(marker)

    def _message(self, text: str, level, seconds: int) -> None:
        if self.iface is not None:
            self.iface.messageBar().pushMessage("overseec", text, level, seconds)

    def _fail(self, message: str) -> None:
        self._message(f"cannot fix the mask: {message}", Qgis.Warning, 6)
        self.failed.emit(message)
