"""The map tool's paths layer: storing plans, following undo and redo, saving.

Paths go into ``paths.gpkg`` in the run folder (one table per costmap, see
:func:`overseec_qgis.layers.open_paths_layer`), a layer named by the costmap's prompt and added
above every costmap. Every plan is one command in that layer's edit buffer (Edit > Undo takes it
back); the edits are committed when the project is saved, so the reopened project shows the same
paths. Each path feature keeps its waypoints (start, vias, goal; :data:`WAYPOINTS_FIELD`, WKT
MULTIPOINT in the layer's CRS; added to older tables when missing), so when the layer's undo
stack moves (undo, redo) the markers move with the path, and the next drag starts from there.
:meth:`PathsMixin.save_paths` also writes them as RFC 7946 GeoJSON.

What must stay on the GUI thread is cut into short steps: the paths table is created while the
costmap loads (:func:`overseec_qgis.planfiles.prepare_paths_table`), and a paths layer still to
be opened, or put in edit mode, is readied one event-loop turn at a time before the route is
stored.

A mixin of :class:`~overseec_qgis.maptool.PlanMapTool` (see :mod:`overseec_qgis.planmixin` for
why): storing reads the tool's route, and undo and redo move its points and markers.
"""

from __future__ import annotations

import functools
import os
from pathlib import Path

from qgis.core import (
    Qgis,
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsFeature,
    QgsFeatureRequest,
    QgsField,
    QgsGeometry,
    QgsPointXY,
    QgsProject,
    QgsVectorLayer,
)
from qgis.PyQt.QtCore import QTimer, QVariant

from .layers import (
    PATH_INTERNAL_FIELDS,
    PROP_RUN,
    Provenance,
    add_on_top,
    find_paths_layer,
    open_paths_layer,
    paths_table,
)
from .planmixin import ToolMixin
from .planrequests import CostmapSession, PlannedPath, PlanRequest

#: The paths layer's field holding a route's waypoints (see :func:`waypoints_wkt`).
WAYPOINTS_FIELD = "waypoints"


def waypoints_wkt(points: list[QgsPointXY]) -> str:
    """A route's waypoints (start, vias, goal, in order) as WKT MULTIPOINT."""
    return QgsGeometry.fromMultiPointXY(points).asWkt()


def parse_waypoints(text: object) -> list[QgsPointXY]:
    """The waypoints :func:`waypoints_wkt` wrote (empty for NULL or anything else)."""
    if not isinstance(text, str) or not text.strip():
        return []
    geom = QgsGeometry.fromWkt(text)
    return [] if geom.isNull() else list(geom.asMultiPoint())


def ensure_waypoints_field(layer: QgsVectorLayer) -> None:
    """Add the ``waypoints`` field to a paths table made before it existed (old projects), through
    the layer's data provider; without it the path is stored, but undo cannot move the markers."""
    if layer.fields().indexOf(WAYPOINTS_FIELD) >= 0:
        return
    if layer.dataProvider().addAttributes([QgsField(WAYPOINTS_FIELD, QVariant.String)]):
        layer.updateFields()


class PathsMixin(ToolMixin):
    """The tool's paths layers: where they live, storing a plan, undo and redo, saving."""

    # the tool's route (:class:`~overseec_qgis.maptool.PlanMapTool`) and last plan (requests)
    points: list[QgsPointXY]
    complete: bool
    last_planned: PlannedPath | None

    def _init_paths(self) -> None:
        self.paths_layer: QgsVectorLayer | None = None
        self._run_folder: Path | None = None
        self._edited_layers: dict[str, QgsVectorLayer] = {}
        self._store_steps = 0  # stores waiting for their paths layer to be readied
        self._storing = False
        self._history: dict[str, tuple[QgsVectorLayer, object]] = {}  # layer id -> (layer, slot)

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

    # -- storing a plan ---------------------------------------------------------------------------

    def _store_in_steps(self, result: PlannedPath, session: CostmapSession, request: PlanRequest, step: int) -> None:
        """Store a plan, then say so. A paths layer still to be opened (step 0), or put in edit
        mode (step 1), is readied one step per event-loop turn first: opening a GeoPackage layer
        and starting its edit session take tens of milliseconds each on the GUI thread."""
        if request.generation != self._generation or self._latest.get(request.path_key) != request.seq:
            return  # moot by now
        try:
            if step < 2 and not self._paths_ready():
                layer = self._paths_layer(session)
                if step == 1:
                    self._ready_paths_layer(layer)
                self._store_steps += 1
                QTimer.singleShot(0, functools.partial(self._next_store_step, result, session, request, step + 1))
                return
            self._store(result, session, request)
        except (OSError, ValueError) as exc:
            self._fail(str(exc))
            return
        self.last_planned = result
        for note in result.notes:
            if self.iface is not None:
                self.iface.messageBar().pushMessage("overseec", note, Qgis.Warning, 8)
        self.planned.emit(result)

    def _next_store_step(self, result: PlannedPath, session: CostmapSession, request: PlanRequest, step: int) -> None:
        self._store_steps -= 1
        if self.markers is None:  # cleared meanwhile
            return
        try:
            self._store_in_steps(result, session, request, step)
        except Exception as exc:
            self._fail(f"{type(exc).__name__}: {exc}")

    def _paths_ready(self) -> bool:
        """Whether the paths layer is open, in the project and in edit mode (storing only edits)."""
        layer = self.paths_layer
        try:
            return layer is not None and QgsProject.instance().mapLayer(layer.id()) is not None and layer.isEditable()
        except RuntimeError:  # the layer was deleted
            return False

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

    def _current_feature(self, layer: QgsVectorLayer, key: str | None = None) -> int | None:
        """The feature id of a path (the current one by default), found by its path_id:
        commits renumber features."""
        key = self.path_key if key is None else key
        if not key:
            return None
        request = QgsFeatureRequest().setFilterExpression(f"\"path_id\" = '{key}'")  # a hex uuid
        for feature in layer.getFeatures(request):
            return int(feature.id())
        return None

    def _store(self, result: PlannedPath, session: CostmapSession, request: PlanRequest) -> None:
        """One edit command in the paths layer's edit buffer: add the path, or replace it; the
        route's waypoints go with it (so undo and redo can move the markers back)."""
        layer = self._paths_layer(session)
        self._ready_paths_layer(layer)
        geom = QgsGeometry.fromPolylineXY([QgsPointXY(x, y) for x, y in result.points])
        waypoints = [QgsPointXY(x, y) for x, y in request.xy]
        if layer.crs() != session.crs:
            to_layer = QgsCoordinateTransform(session.crs, layer.crs(), QgsProject.instance())
            geom.transform(to_layer)
            waypoints = [to_layer.transform(p) for p in waypoints]
        values = {
            "total_cost": result.cost,
            "length_m": result.length_m,
            "mode": result.mode,
            "vias": result.vias,
            "path_id": request.path_key,
        }
        if layer.fields().indexOf(WAYPOINTS_FIELD) >= 0:  # else (a read-only old table) undo leaves the markers
            values[WAYPOINTS_FIELD] = waypoints_wkt(waypoints)
        fid = self._current_feature(layer, request.path_key)
        self._storing = True  # our own command moves the undo stack: nothing to restore
        try:
            self._edit(layer, fid, geom, values)
        finally:
            self._storing = False
        layer.triggerRepaint()
        self._make_current(layer)

    def _ready_paths_layer(self, layer: QgsVectorLayer) -> None:
        """The paths layer with the waypoints field, in edit mode, its history followed."""
        ensure_waypoints_field(layer)
        if not layer.isEditable() and not layer.startEditing():
            raise OSError(f"cannot edit {layer.source().split('|')[0]}")
        self._edited_layers[layer.id()] = layer
        self._follow_history(layer)

    @staticmethod
    def _edit(layer: QgsVectorLayer, fid: int | None, geom: QgsGeometry, values: dict) -> None:
        """Add the feature, or change it, as one undoable edit command."""
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

    def _make_current(self, layer: QgsVectorLayer) -> None:
        """Select the paths layer in the legend, as QGIS's own digitizing does: Edit › Undo and
        Ctrl+Z act on the current layer's edit buffer, so they take back the plan just made.
        Only while this tool is the canvas's: another tool (Add Polygon on the overrides layer)
        keeps its layer."""
        if self.iface is not None and self.canvas.mapTool() is self and self.iface.activeLayer() is not layer:
            self.iface.setActiveLayer(layer)

    # -- undo and redo move the markers ------------------------------------------------------------

    def _follow_history(self, layer: QgsVectorLayer) -> None:
        """Move the markers with the path when this layer's undo stack moves (undo, redo)."""
        if layer.id() in self._history:
            return
        slot = functools.partial(self._history_moved, layer)
        layer.undoStack().indexChanged.connect(slot)
        self._history[layer.id()] = (layer, slot)

    def _forget_history(self) -> None:
        for layer, slot in self._history.values():
            try:
                layer.undoStack().indexChanged.disconnect(slot)
            except (TypeError, RuntimeError):  # not connected, or the layer is gone
                pass
        self._history.clear()

    def _paths_id(self) -> str | None:
        try:
            return self.paths_layer.id() if self.paths_layer is not None else None
        except RuntimeError:  # the layer was deleted
            return None

    def _history_moved(self, layer: QgsVectorLayer, *_args) -> None:
        """The paths layer's edit history moved: the current route's markers (and the points
        the next drag starts from) follow its feature's waypoints; none if it is gone."""
        if self._storing or self._drag is not None or self.path_key is None or layer.id() != self._paths_id():
            return
        if self.points and not self.complete:
            return  # a new route is being placed
        fid = self._current_feature(layer)
        feature = layer.getFeature(fid) if fid is not None else None
        waypoints = parse_waypoints(feature[WAYPOINTS_FIELD]) if feature is not None else []
        if fid is None:  # undo of its creation: the route is gone (redo brings it back)
            self.points, self.complete = [], False
        elif waypoints:
            to_canvas = QgsCoordinateTransform(
                layer.crs(), self.canvas.mapSettings().destinationCrs(), QgsProject.instance()
            )
            self.points, self.complete = [to_canvas.transform(p) for p in waypoints], True
        self._draw_markers()

    # -- saving -------------------------------------------------------------------------------------

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

    def save_paths(self, path: str | os.PathLike) -> Path:
        """Write the planned paths as GeoJSON (WGS 84, RFC 7946) and return the file."""
        from qgis.core import QgsVectorFileWriter

        if self.paths_layer is None:
            raise LookupError("no planned paths to save")
        options = QgsVectorFileWriter.SaveVectorOptions()
        options.driverName = "GeoJSON"
        options.layerOptions = ["RFC7946=YES"]
        internal = PATH_INTERNAL_FIELDS
        options.attributes = [i for i, f in enumerate(self.paths_layer.fields()) if f.name() not in internal]
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
