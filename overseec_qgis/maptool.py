"""Click-to-plan map tool: start, optional vias, goal -> a planned path on the costmap.

* Click sets the start, Shift+click adds a via point, a plain click sets the goal and plans.
  After a path is planned, the next click starts a new one (its markers replace the old ones).
* Drag any marker of the current path (press on it, move, release) to re-plan it. Only a press
  that moves a few pixels is a drag: a click near an old marker starts a new path. While the
  point moves, the route is re-planned live as a dashed preview (fast mode, while a re-plan takes
  at most :data:`LIVE_PREVIEW_MAX_MS`); the release plans it into the layer.
* Right click or Esc cancels the points being placed (Esc during a drag puts the point back);
  planned paths stay in their layer.
* Markers: start green, vias orange, goal red (canvas items, always above the map).
* Re-prompting: when the tool is given a new costmap while a route is planned, it plans the same
  points on the new costmap into a new layer named after that costmap's prompt, so the routes of
  the prompts lie side by side, one legend entry each.
* Overrides: with an override polygon layer set (:meth:`PlanMapTool.set_overrides_layer`; fields
  ``cost``/``prefer``/``lethal``, as `overseec plan --override` reads them), its polygons --
  including unsaved edits -- are applied to the costmap while planning, and every edit re-plans.

Planning runs in the planner worker of the overseec environment
(:mod:`overseec_qgis.planclient`): QGIS's Python never loads the native kernel. Points are picked
in the canvas CRS and transformed to the costmap's CRS by QGIS; the worker keeps the costmap
loaded, so a re-plan after a drag costs the search only.

Paths go into ``paths.gpkg`` in the run folder (one table per costmap, see
:func:`overseec_qgis.layers.open_paths_layer`), a layer added at the top of the legend so it is
drawn above the costmap. Every plan is one command in that layer's edit buffer (Edit > Undo
takes it back); the edits are committed when the project is saved, so the reopened project
shows the same paths. :meth:`PlanMapTool.save_paths` also writes them as RFC 7946 GeoJSON.
"""

from __future__ import annotations

import os
import tempfile
import uuid
from dataclasses import dataclass
from pathlib import Path

from qgis.core import (
    Qgis,
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsFeature,
    QgsFeatureRequest,
    QgsGeometry,
    QgsPointXY,
    QgsProject,
    QgsRasterLayer,
    QgsVectorLayer,
    QgsWkbTypes,
)
from qgis.gui import QgsMapTool, QgsRubberBand, QgsVertexMarker
from qgis.PyQt.QtCore import Qt, pyqtSignal
from qgis.PyQt.QtGui import QColor

from overseec_core import runfiles

from .layers import (
    PROP_ROLE,
    PROP_RUN,
    Provenance,
    add_on_top,
    find_paths_layer,
    open_paths_layer,
    paths_table,
)
from .params import PLAN_MODE
from .planclient import CostmapInfo, PlanClient, PlanClientError, shared_client

#: A press within this many screen pixels of a marker grabs that marker.
GRAB_TOLERANCE_PX = 8
#: A press becomes a drag once the mouse moved this many pixels (less is a click).
DRAG_START_PX = 4
#: Marker colours: start, via, goal.
START_COLOUR, VIA_COLOUR, GOAL_COLOUR = QColor(0, 200, 0), QColor(255, 140, 0), QColor(230, 0, 0)
MARKER_SIZE = 16
#: Re-plan live while a point is dragged as long as a re-plan takes at most this long (ms);
#: slower ones (exact mode, very large costmaps) plan only on release.
LIVE_PREVIEW_MAX_MS = 250.0


@dataclass(frozen=True)
class PlannedPath:
    """A plan, in the costmap's CRS: vertices, and the core's cost and length figures."""

    points: tuple[tuple[float, float], ...]
    cost: float
    length_m: float
    mode: str
    vias: int
    #: What the core said about the route (e.g. a keep-out rule that cannot be met).
    notes: tuple[str, ...] = ()
    #: The request seen from QGIS, in milliseconds (worker time plus the round trip).
    ms: float = 0.0


@dataclass(frozen=True)
class CostmapSession:
    """The costmap the tool plans on: its file, CRS, and georeferencing from the worker."""

    path: str
    crs: QgsCoordinateReferenceSystem
    grid: CostmapInfo
    mtime: float


def find_costmap_layer(project: QgsProject | None = None) -> QgsRasterLayer | None:
    """The topmost costmap layer of the project (layers the plugin tagged, else named costmap)."""
    project = project or QgsProject.instance()
    root = project.layerTreeRoot()
    for layer in root.layerOrder() or list(project.mapLayers().values()):
        if isinstance(layer, QgsRasterLayer) and layer.customProperty(PROP_ROLE) == "costmap":
            return layer
    for layer in project.mapLayers().values():
        if isinstance(layer, QgsRasterLayer) and "costmap" in layer.name().lower():
            return layer
    return None


def _marker_colours(n: int, complete: bool) -> list[QColor]:
    """Start green, vias orange, goal red (while placing, every point after the start is a via)."""
    if n == 0:
        return []
    colours = [START_COLOUR] + [VIA_COLOUR] * (n - 1)
    if complete and n > 1:
        colours[-1] = GOAL_COLOUR
    return colours


class PlanMapTool(QgsMapTool):
    """The map tool; emits ``planned(PlannedPath)`` or ``failed(message)``.

    A plain :class:`QgsMapTool` (no zoom-rectangle flag), so the canvas hands Shift+click to the
    tool instead of starting a zoom rectangle.
    """

    planned = pyqtSignal(object)
    failed = pyqtSignal(str)

    def __init__(self, canvas, iface=None, client: PlanClient | None = None) -> None:
        super().__init__(canvas)
        self.canvas = canvas
        self.iface = iface
        self._client = client
        self.mode = PLAN_MODE  # interactive: every click re-plans (see params.Params)
        self.costmap_layer: QgsRasterLayer | None = None
        self.points: list[QgsPointXY] = []  # canvas CRS: start, vias..., goal
        self.complete = False
        self.path_key: str | None = None  # path_id of the current path's feature
        self.paths_layer: QgsVectorLayer | None = None
        self._run_folder: Path | None = None
        self._press: tuple[int, int, int | None] | None = None  # x, y, grabbed marker
        self._drag: int | None = None
        self._drag_from: QgsPointXY | None = None
        self._sessions: dict[str, CostmapSession] = {}
        self._edited_layers: dict[str, QgsVectorLayer] = {}
        self.overrides_layer: QgsVectorLayer | None = None
        self._overrides_version = 0
        self._overrides_files: tuple[Path, ...] = ()
        self._overrides_dir = tempfile.TemporaryDirectory(prefix="overseec-overrides-")
        self.markers: list[QgsVertexMarker] | None = []
        self.preview: QgsRubberBand | None = QgsRubberBand(canvas, QgsWkbTypes.LineGeometry)
        self.preview.setColor(QColor(0, 80, 255, 170))
        self.preview.setWidth(3)
        self.preview.setLineStyle(Qt.DashLine)
        self._last_ms = 0.0
        self.setCursor(Qt.CrossCursor)
        QgsProject.instance().writeProject.connect(self._project_writing)
        # while a mouse button is down the canvas passes keys only to this signal, not the tool
        canvas.keyPressed.connect(self._key_during_drag)

    # -- configuration -----------------------------------------------------------------------

    @property
    def client(self) -> PlanClient:
        """The planner worker's client (the session's shared one unless one was given)."""
        return self._client if self._client is not None else shared_client()

    def set_run_folder(self, folder: str | os.PathLike | None) -> None:
        """Keep ``paths.gpkg`` in this folder (None: the costmap's run folder, else its folder)."""
        self._run_folder = None if folder is None else Path(folder)
        self.paths_layer = None

    def run_folder(self, costmap: str) -> Path:
        """Where ``paths.gpkg`` goes: the folder set, else the costmap layer's run folder, else
        the costmap's own folder."""
        if self._run_folder is not None:
            return self._run_folder
        run_dir = self.costmap_layer.customProperty(PROP_RUN, "") if self.costmap_layer is not None else ""
        return Path(run_dir) if run_dir and Path(run_dir).is_dir() else Path(costmap).parent

    def set_costmap(self, layer: QgsRasterLayer | None) -> None:
        """Plan on ``layer`` (None = the project's topmost costmap at the next click).

        A route planned on the previous costmap is planned again on the new one, into its own
        layer: re-prompting shows the prompts' routes side by side."""
        if layer is self.costmap_layer:
            return
        carried = list(self.points) if self.complete else []
        self.cancel()
        self.paths_layer = None  # paths on another costmap go to their own layer
        self.costmap_layer = layer
        if layer is not None and layer.isValid():
            try:  # read it in the worker while the user picks points
                self.client.preload(layer.dataProvider().dataSourceUri().split("|")[0])
            except PlanClientError:
                pass  # no environment yet: the first plan says so
        if carried and layer is not None:
            self.points, self.complete, self.path_key = carried, True, uuid.uuid4().hex
            self._draw_markers()
            self.replan()

    def set_overrides_layer(self, layer: QgsVectorLayer | None) -> None:
        """Apply this polygon layer's overrides while planning; any edit to it re-plans."""
        old = self.overrides_layer
        if old is not None:
            for signal in self._override_signals(old):
                try:
                    signal.disconnect(self._overrides_edited)
                except TypeError:
                    pass
        self.overrides_layer = layer
        if layer is not None:
            for signal in self._override_signals(layer):
                signal.connect(self._overrides_edited)
        self._overrides_edited()

    @staticmethod
    def _override_signals(layer: QgsVectorLayer) -> tuple:
        return (
            layer.featureAdded,
            layer.featuresDeleted,
            layer.geometryChanged,
            layer.attributeValueChanged,
            layer.afterCommitChanges,
            layer.afterRollBack,
        )

    def _overrides_edited(self, *_args) -> None:
        """The override polygons changed: write them (with unsaved edits) for the worker, re-plan."""
        self._overrides_version += 1
        old = self._overrides_files
        self._overrides_files = self._write_overrides()
        for f in old:  # the worker read them when it applied them; only the latest matters
            f.unlink(missing_ok=True)
        if self.complete:
            self.replan()

    def _write_overrides(self) -> tuple[Path, ...]:
        from qgis.core import QgsVectorFileWriter

        layer = self.overrides_layer
        if layer is None or QgsProject.instance().mapLayer(layer.id()) is None or layer.featureCount() == 0:
            return ()
        out = Path(self._overrides_dir.name) / f"overrides-{self._overrides_version}.gpkg"
        options = QgsVectorFileWriter.SaveVectorOptions()
        options.driverName = "GPKG"
        # a GeoPackage source's own fid column would clash with the new file's (new features
        # in the edit buffer carry temporary ids): the core reads only cost/prefer/lethal
        options.attributes = [i for i, f in enumerate(layer.fields()) if f.name().lower() != "fid"]
        err, msg = QgsVectorFileWriter.writeAsVectorFormatV3(
            layer, str(out), QgsProject.instance().transformContext(), options
        )[:2]
        if err != QgsVectorFileWriter.NoError:
            self._fail(f"cannot read the override polygons ({msg})")
            return ()
        return (out,)

    def session(self) -> CostmapSession:
        """The current costmap, loaded in the planner worker (once; again if the file changed)."""
        layer = self.costmap_layer
        if layer is None or not layer.isValid() or QgsProject.instance().mapLayer(layer.id()) is None:
            layer = self.costmap_layer = find_costmap_layer()
        if layer is None:
            raise LookupError(f"no costmap layer: build a costmap first (or add {runfiles.COSTMAP})")
        path = os.path.abspath(layer.dataProvider().dataSourceUri().split("|")[0])
        mtime = os.path.getmtime(path)
        s = self._sessions.get(path)
        if s is None or s.mtime != mtime:
            info = self.client.load(path, overrides=[str(f) for f in self._overrides_files])
            s = CostmapSession(path=path, crs=layer.crs(), grid=info, mtime=mtime)
            self._sessions[path] = s
        return s

    # -- events --------------------------------------------------------------------------------

    def _near(self, pos) -> int | None:
        """The current path's marker under a screen position (the last placed wins)."""
        for i in reversed(range(len(self.points))):
            screen = self.toCanvasCoordinates(self.points[i])
            if abs(screen.x() - pos.x()) <= GRAB_TOLERANCE_PX and abs(screen.y() - pos.y()) <= GRAB_TOLERANCE_PX:
                return i
        return None

    def canvasPressEvent(self, e) -> None:  # noqa: N802 -- Qt API
        if e.button() == Qt.LeftButton:
            self._press = (e.pos().x(), e.pos().y(), self._near(e.pos()))
            self._drag = None

    def canvasMoveEvent(self, e) -> None:  # noqa: N802
        if self._press is None:
            return
        x, y, grabbed = self._press
        if self._drag is None:
            moved = max(abs(e.pos().x() - x), abs(e.pos().y() - y))
            if grabbed is None or moved < DRAG_START_PX:
                return
            self._drag, self._drag_from = grabbed, self.points[grabbed]
        self.points[self._drag] = self.toMapCoordinates(e.pos())
        self._draw_markers()
        self._preview_drag()

    def canvasReleaseEvent(self, e) -> None:  # noqa: N802
        if e.button() == Qt.RightButton:
            self.cancel()
            return
        if e.button() != Qt.LeftButton:
            return
        pressed, self._press = self._press, None
        point = self.toMapCoordinates(e.pos())
        if self._drag is not None:
            index, self._drag, self._drag_from = self._drag, None, None
            self.points[index] = point
            self._draw_markers()
            self._clear_preview()
            if self.complete:
                self.replan()
            return
        if pressed is None:
            return  # the press went elsewhere (e.g. it cancelled a drag)
        self._click(point, bool(e.modifiers() & Qt.ShiftModifier))

    def _click(self, point: QgsPointXY, shift: bool) -> None:
        if self.complete:  # a finished path stays in the layer; this click starts a new one
            self.points, self.complete, self.path_key = [], False, None
        self.points.append(point)
        if len(self.points) == 1 or shift:
            self._draw_markers()
            return
        self.complete, self.path_key = True, uuid.uuid4().hex
        self._draw_markers()
        self.replan()

    def keyPressEvent(self, e) -> None:  # noqa: N802
        if e.key() != Qt.Key_Escape:
            e.ignore()
            return
        if not self._undo_drag():
            self.cancel()
        e.accept()

    def _key_during_drag(self, e) -> None:
        if e.key() == Qt.Key_Escape and self.canvas.mapTool() is self:
            self._undo_drag()

    def _undo_drag(self) -> bool:
        """Esc during a drag: the point goes back where it was and nothing is planned."""
        if self._drag is None or self._drag_from is None:
            return False
        self.points[self._drag] = self._drag_from
        self._drag, self._drag_from, self._press = None, None, None
        self._draw_markers()
        self._clear_preview()
        return True

    def deactivate(self) -> None:
        self.cancel()
        super().deactivate()

    # -- planning ------------------------------------------------------------------------------

    def cancel(self) -> None:
        """Drop the points being placed; a path already planned stays."""
        self._press, self._drag, self._drag_from = None, None, None
        self.points, self.complete, self.path_key = [], False, None
        self._draw_markers()
        self._clear_preview()

    def clear(self) -> None:
        """Cancel, forget loaded costmaps and take the markers off the canvas (plugin unload).
        The worker itself is the session's: the plugin stops it (planclient.close_shared_client)."""
        self.cancel()
        self.set_overrides_layer(None)
        self._sessions.clear()
        self._overrides_dir.cleanup()
        for signal, slot in (
            (QgsProject.instance().writeProject, self._project_writing),
            (self.canvas.keyPressed, self._key_during_drag),
        ):
            try:
                signal.disconnect(slot)
            except TypeError:
                pass
        self._remove_markers()
        self.markers = None
        if self.preview is not None:
            self.canvas.scene().removeItem(self.preview)
            self.preview = None

    def _request(self) -> tuple[PlannedPath, CostmapSession]:
        """Plan through the current points in the worker (raises what the worker or QGIS raise)."""
        session = self.session()
        to_costmap = QgsCoordinateTransform(
            self.canvas.mapSettings().destinationCrs(), session.crs, QgsProject.instance()
        )
        xy = []
        for p in self.points:
            q = to_costmap.transform(p)
            xy.append((q.x(), q.y()))
        reply = self.client.plan(session.path, xy, self.mode, overrides=[str(f) for f in self._overrides_files])
        self._last_ms = reply.round_trip_ms
        result = PlannedPath(
            points=reply.points,
            cost=reply.cost,
            length_m=reply.length_m,
            mode=reply.mode,
            vias=reply.vias,
            notes=reply.notes,
            ms=reply.round_trip_ms,
        )
        return result, session

    def _preview_drag(self) -> None:
        """The dragged route, re-planned now, as a dashed line (nothing stored; silent on failure:
        the release plans for real and reports)."""
        if self.preview is None or not self.complete or self.mode != "fast" or self._last_ms > LIVE_PREVIEW_MAX_MS:
            return
        try:
            result, session = self._request()
            line = QgsGeometry.fromPolylineXY([QgsPointXY(x, y) for x, y in result.points])
            line.transform(
                QgsCoordinateTransform(session.crs, self.canvas.mapSettings().destinationCrs(), QgsProject.instance())
            )
        except Exception:  # noqa: BLE001 -- e.g. the point is over a lethal cell right now
            self._clear_preview()
            return
        self.preview.setToGeometry(line, None)

    def _clear_preview(self) -> None:
        if self.preview is not None:
            self.preview.reset(QgsWkbTypes.LineGeometry)

    def replan(self) -> PlannedPath | None:
        """Plan through the current points in the worker and put the result in the paths layer."""
        try:
            result, session = self._request()
            self._store(result, session)
        except (PlanClientError, LookupError, OSError, ValueError) as exc:
            self._fail(str(exc))
            return None
        except Exception as exc:  # QgsCsException and friends: report, do not crash the canvas
            self._fail(f"{type(exc).__name__}: {exc}")
            return None
        for note in result.notes:
            if self.iface is not None:
                self.iface.messageBar().pushMessage("overseec", note, Qgis.Warning, 8)
        self.planned.emit(result)
        return result

    def _fail(self, message: str) -> None:
        if self.iface is not None:
            self.iface.messageBar().pushMessage("overseec", f"cannot plan: {message}", Qgis.Warning, 6)
        self.failed.emit(message)

    # -- the paths layer ---------------------------------------------------------------------------

    def _paths_layer(self, session: CostmapSession) -> QgsVectorLayer:
        layer = self.paths_layer
        if layer is not None and QgsProject.instance().mapLayer(layer.id()) is not None:
            return layer
        folder, table = self.run_folder(session.path), paths_table(session.path)
        layer = find_paths_layer(folder, table)
        if layer is None:  # named by the costmap's prompt, unique in the project; above every costmap
            from .layers import PROP_COSTMAP
            from .legend import layer_name

            prompt = self.costmap_layer.customProperty("overseec/prompt", "") if self.costmap_layer else ""
            fallback = f"planned paths ({self.costmap_layer.name() if self.costmap_layer else 'costmap'})"
            name = layer_name("path", prompt, fallback, QgsProject.instance())
            prov = Provenance(run_dir=str(folder), prompt=prompt, stage="plan", extra=(("costmap", session.path),))
            layer = open_paths_layer(folder, table, session.crs, name, prov)
            layer.setCustomProperty(PROP_COSTMAP, session.path)
            add_on_top(layer)
        self.paths_layer = layer
        return layer

    def _current_feature(self, layer: QgsVectorLayer) -> int | None:
        """The feature id of the current path (found by its path_id: commits renumber features)."""
        if self.path_key is None:
            return None
        request = QgsFeatureRequest().setFilterExpression(f"\"path_id\" = '{self.path_key}'")  # a hex uuid
        for feature in layer.getFeatures(request):
            return int(feature.id())
        return None

    def _store(self, result: PlannedPath, session: CostmapSession) -> None:
        """One edit command in the paths layer's edit buffer: add the path, or replace it."""
        layer = self._paths_layer(session)
        if not layer.isEditable() and not layer.startEditing():
            raise OSError(f"cannot edit {layer.source().split('|')[0]}")
        self._edited_layers[layer.id()] = layer
        geom = QgsGeometry.fromPolylineXY([QgsPointXY(x, y) for x, y in result.points])
        values = {
            "total_cost": result.cost,
            "length_m": result.length_m,
            "mode": result.mode,
            "vias": result.vias,
            "path_id": self.path_key,
        }
        fid = self._current_feature(layer)
        layer.beginEditCommand("overseec: plan a path" if fid is None else "overseec: re-plan a path")
        try:
            if fid is None:
                feature = QgsFeature(layer.fields())
                feature.setGeometry(geom)
                for name, value in values.items():
                    feature[name] = value
                ok = layer.addFeature(feature)
            else:
                fields = layer.fields()
                ok = layer.changeGeometry(fid, geom)
                for name, value in values.items():
                    ok = layer.changeAttributeValue(fid, fields.indexOf(name), value) and ok
        except Exception:
            layer.destroyEditCommand()
            raise
        if not ok:
            layer.destroyEditCommand()
            raise OSError(f"cannot store the path in {layer.name()}")
        layer.endEditCommand()
        layer.triggerRepaint()
        self._make_current(layer)

    def _make_current(self, layer: QgsVectorLayer) -> None:
        """Select the paths layer in the legend, as QGIS's own digitizing does: Edit › Undo and
        Ctrl+Z act on the current layer's edit buffer, so they take back the plan just made."""
        if self.iface is not None and self.iface.activeLayer() is not layer:
            self.iface.setActiveLayer(layer)

    def commit_paths(self) -> None:
        """Write the paths layers' pending edits to ``paths.gpkg`` (they stay editable)."""
        for layer in list(self._edited_layers.values()):
            try:
                editing = QgsProject.instance().mapLayer(layer.id()) is not None and layer.isEditable()
            except RuntimeError:  # the layer object is gone
                editing = False
            if editing and layer.isModified() and not layer.commitChanges(False):
                self._fail(f"cannot save the paths: {'; '.join(layer.commitErrors())}")

    def _project_writing(self, *_args) -> None:
        self.commit_paths()

    # -- markers -------------------------------------------------------------------------------------

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

    def save_paths(self, path: str | os.PathLike) -> Path:
        """Write the planned paths as GeoJSON (WGS 84, RFC 7946) and return the file."""
        from qgis.core import QgsVectorFileWriter

        if self.paths_layer is None:
            raise LookupError("no planned paths to save")
        options = QgsVectorFileWriter.SaveVectorOptions()
        options.driverName = "GeoJSON"
        options.layerOptions = ["RFC7946=YES"]
        options.attributes = [i for i, f in enumerate(self.paths_layer.fields()) if f.name() not in ("fid", "path_id")]
        wgs84 = QgsCoordinateReferenceSystem("EPSG:4326")
        options.ct = QgsCoordinateTransform(self.paths_layer.crs(), wgs84, QgsProject.instance())
        path = Path(path)
        tmp = path.with_name(f".{path.stem}.partial.geojson")
        write = getattr(QgsVectorFileWriter, "writeAsVectorFormatV3", None) or QgsVectorFileWriter.writeAsVectorFormatV2
        err, msg = write(self.paths_layer, str(tmp), QgsProject.instance().transformContext(), options)[:2]
        if err != QgsVectorFileWriter.NoError:
            tmp.unlink(missing_ok=True)
            raise OSError(f"cannot write {path}: {msg}")
        os.replace(tmp, path)
        return path
