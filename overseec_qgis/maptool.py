"""Click-to-plan map tool: start, optional vias, goal -> a planned path on the costmap.

* Left click: the first click sets the start, Shift+left click adds a via point, a plain left click
  sets the goal and plans. After a path is planned, the next plain click starts a new one.
* Moving a point re-plans: press on a marker, drag it, release (a click within a few pixels of
  a marker moves that marker instead of adding a point).
* Right click or Esc cancels the points being placed (planned paths stay in the layer).
* Re-prompting: when the tool is given a new costmap while a route is planned, it plans the same
  points on the new costmap into a new layer named after that costmap's prompt, so the routes of
  the prompts lie side by side, one legend entry each.
* Overrides: with an override polygon layer set (:meth:`PlanMapTool.set_overrides_layer`; fields
  ``cost``/``prefer``/``lethal``, as `overseec plan --override` reads them), its polygons —
  including unsaved edits — are applied to the costmap while planning, and every edit re-plans.

Points are picked in the canvas CRS and transformed to the costmap's CRS
(QgsCoordinateTransform), then to pixels by the core (``grid.world_to_pixel``). The costmap is
loaded once into a core ``Planner`` and kept, so repeated plans on the same costmap (dragging a
point around) do not reload it. Paths go into a memory line layer with ``total_cost``,
``length_m``, ``mode`` and ``vias`` attributes (the property names of the core's path GeoJSON),
in the costmap's CRS; :meth:`PlanMapTool.save_paths` writes
them as RFC 7946 GeoJSON (WGS 84), atomically (temporary file, then rename).
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from qgis.core import (
    Qgis,
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsFeature,
    QgsField,
    QgsGeometry,
    QgsPointXY,
    QgsProject,
    QgsRasterLayer,
    QgsVectorLayer,
    QgsWkbTypes,
)
from qgis.gui import QgsMapToolEmitPoint, QgsRubberBand
from qgis.PyQt.QtCore import Qt, QVariant, pyqtSignal
from qgis.PyQt.QtGui import QColor

from .jobs import PLAN_MODE
from .layers import PROP_ROLE, Provenance, apply_style, set_provenance

#: A click within this many screen pixels of a marker grabs that marker.
GRAB_TOLERANCE_PX = 8
#: Planners kept in memory (one per costmap file).
PLANNER_CACHE_SIZE = 2


@dataclass(frozen=True)
class PlannedPath:
    """A plan, in the costmap's CRS: vertices, and the core's cost and length figures."""

    points: tuple[tuple[float, float], ...]
    cost: float
    length_m: float
    mode: str
    vias: int
    #: What the core said about the route (e.g. a distance rule that cannot be met).
    notes: tuple[str, ...] = ()


class CostmapSession:
    """One costmap loaded into a core Planner, reused for every click on it; keep-out zones
    (distance rules) are entered only when no route avoids them, as `overseec plan` does."""

    def __init__(self, path: str, crs: QgsCoordinateReferenceSystem) -> None:
        from overseec_core.plan import load_costmap

        self.path = path
        self.crs = crs
        self.mtime = os.path.getmtime(path)
        self.base = load_costmap(path)
        #: Which override edit the planner reflects (see :meth:`apply_overrides`).
        self.overrides_version = -1
        self.apply_overrides((), 0)

    def apply_overrides(self, files: tuple[Path, ...], version: int) -> None:
        """Plan on the costmap with these override files applied (on a copy: the loaded costmap
        stays as read, so each edit starts again from it)."""
        from overseec_core.overrides import apply_to_planning_grid, load_overrides
        from overseec_core.plan import Planner
        from overseec_core.plan.stage import RulePlanner

        grid = self.base
        if files:
            keep_out = None if grid.keep_out is None else grid.keep_out.copy()
            grid = replace(grid, cost=grid.cost.copy(), keep_out=keep_out)
            assert grid.grid is not None  # read from a GeoTIFF, so georeferenced
            apply_to_planning_grid(grid, load_overrides(files, grid.grid))
        self.grid = grid
        self.planner = RulePlanner(Planner(grid))
        self.overrides_version = version

    def to_pixel(self, x: float, y: float) -> tuple[int, int]:
        """Pixel of a point already in the costmap's CRS (QGIS did the reprojection)."""
        row, col = self.grid.world_to_pixel(x, y)
        return int(row), int(col)

    def plan(self, points_xy: list[tuple[float, float]], mode: str) -> PlannedPath:
        """Plan through world points (costmap CRS); raises the core's PlanError when impossible."""
        pixels = [self.to_pixel(x, y) for x, y in points_xy]
        res, _ = self.planner.plan(pixels, mode=mode)
        rc = np.asarray(res.pixels)
        xs, ys = self.grid.pixel_to_world(rc[:, 0], rc[:, 1])
        coords = tuple(zip(np.atleast_1d(xs).tolist(), np.atleast_1d(ys).tolist()))
        return PlannedPath(
            points=coords,
            cost=float(res.cost),
            length_m=float(res.length_m),
            mode=str(getattr(res, "mode", mode)),
            vias=max(0, len(points_xy) - 2),
            notes=tuple(res.notes),
        )


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


class PlanMapTool(QgsMapToolEmitPoint):
    """The map tool; emits ``planned(PlannedPath)`` or ``failed(message)``."""

    planned = pyqtSignal(object)
    failed = pyqtSignal(str)

    def __init__(self, canvas, iface=None) -> None:
        super().__init__(canvas)
        self.canvas = canvas
        self.iface = iface
        self.mode = PLAN_MODE  # interactive: every click re-plans (see jobs.Params)
        self.costmap_layer: QgsRasterLayer | None = None
        self.points: list[QgsPointXY] = []  # canvas CRS: start, vias..., goal
        self.complete = False
        self.feature_id: int | None = None
        self.paths_layer: QgsVectorLayer | None = None
        self._drag: int | None = None
        self._sessions: dict[str, CostmapSession] = {}
        self.overrides_layer: QgsVectorLayer | None = None
        self._overrides_version = 0
        self._overrides_files: tuple[Path, ...] = ()
        self._overrides_dir = tempfile.TemporaryDirectory(prefix="overseec-overrides-")
        self.markers = QgsRubberBand(canvas, QgsWkbTypes.PointGeometry)
        self.markers.setColor(QColor(255, 255, 255))
        self.markers.setStrokeColor(QColor(20, 20, 20))
        self.markers.setIconSize(10)
        self.markers.setIcon(QgsRubberBand.ICON_CIRCLE)
        self.setCursor(Qt.CrossCursor)

    # -- configuration -----------------------------------------------------------------------

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
        if carried and layer is not None:
            self.points, self.complete = carried, True
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
        """The override polygons changed: write them (with unsaved edits) for the core, re-plan."""
        self._overrides_version += 1
        self._overrides_files = self._write_overrides()
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
        """The loaded planner for the current costmap (loaded once, reloaded if the file changed)."""
        layer = self.costmap_layer
        if layer is None or not layer.isValid() or QgsProject.instance().mapLayer(layer.id()) is None:
            layer = self.costmap_layer = find_costmap_layer()
        if layer is None:
            raise LookupError("no costmap layer: build a costmap first (or add costmap.tif)")
        path = layer.dataProvider().dataSourceUri().split("|")[0]
        s = self._sessions.get(path)
        if s is None or s.mtime != os.path.getmtime(path):
            s = CostmapSession(path, layer.crs())
            self._sessions[path] = s
            while len(self._sessions) > PLANNER_CACHE_SIZE:
                self._sessions.pop(next(iter(self._sessions)))
        if s.overrides_version != self._overrides_version:
            s.apply_overrides(self._overrides_files, self._overrides_version)
        return s

    # -- events --------------------------------------------------------------------------------

    def _near(self, pos) -> int | None:
        for i, p in enumerate(self.points):
            screen = self.toCanvasCoordinates(p)
            if abs(screen.x() - pos.x()) <= GRAB_TOLERANCE_PX and abs(screen.y() - pos.y()) <= GRAB_TOLERANCE_PX:
                return i
        return None

    def canvasPressEvent(self, e) -> None:  # noqa: N802 -- Qt API
        if e.button() == Qt.LeftButton:
            self._drag = self._near(e.pos())

    def canvasMoveEvent(self, e) -> None:  # noqa: N802
        if self._drag is not None and e.buttons() & Qt.LeftButton:
            self.points[self._drag] = self.toMapCoordinates(e.pos())
            self._draw_markers()

    def canvasReleaseEvent(self, e) -> None:  # noqa: N802
        if e.button() == Qt.RightButton:
            self.cancel()
            return
        if e.button() != Qt.LeftButton:
            return
        point = self.toMapCoordinates(e.pos())
        if self._drag is not None:
            index, self._drag = self._drag, None
            self.points[index] = point
            self._draw_markers()
            if self.complete:
                self.replan()
            return
        shift = bool(e.modifiers() & Qt.ShiftModifier)
        if self.complete:  # a finished path stays in the layer; this click starts a new one
            self.points, self.complete, self.feature_id = [], False, None
        if not self.points or shift:
            self.points.append(point)
            self._draw_markers()
            return
        self.points.append(point)
        self.complete = True
        self._draw_markers()
        self.replan()

    def keyPressEvent(self, e) -> None:  # noqa: N802
        if e.key() == Qt.Key_Escape:
            self.cancel()
            e.accept()
        else:
            e.ignore()

    def deactivate(self) -> None:
        self.cancel()
        super().deactivate()

    # -- planning ------------------------------------------------------------------------------

    def cancel(self) -> None:
        """Drop the points being placed; a path already planned stays."""
        self._drag = None
        self.points, self.complete, self.feature_id = [], False, None
        self._draw_markers()

    def clear(self) -> None:
        """Cancel, forget loaded planners and take the markers off the canvas (plugin unload)."""
        self.cancel()
        self.set_overrides_layer(None)
        self._sessions.clear()
        self._overrides_dir.cleanup()
        if self.markers is not None:
            self.canvas.scene().removeItem(self.markers)
            self.markers = None

    def replan(self) -> PlannedPath | None:
        """Plan through the current points and put the result in the paths layer."""
        from overseec_core.errors import OverseecError

        try:
            session = self.session()
            to_costmap = QgsCoordinateTransform(
                self.canvas.mapSettings().destinationCrs(), session.crs, QgsProject.instance()
            )
            xy = []
            for p in self.points:
                q = to_costmap.transform(p)
                xy.append((q.x(), q.y()))
            result = session.plan(xy, self.mode)
        except (OverseecError, LookupError, OSError) as exc:
            self._fail(str(exc))
            return None
        except Exception as exc:  # QgsCsException and friends: report, do not crash the canvas
            self._fail(f"{type(exc).__name__}: {exc}")
            return None
        self._store(result, session)
        for note in result.notes:
            if self.iface is not None:
                self.iface.messageBar().pushMessage("overseec", note, Qgis.Warning, 8)
        self.planned.emit(result)
        return result

    def _fail(self, message: str) -> None:
        if self.iface is not None:
            self.iface.messageBar().pushMessage("overseec", f"cannot plan: {message}", Qgis.Warning, 6)
        self.failed.emit(message)

    def _paths_layer(self, session: CostmapSession) -> QgsVectorLayer:
        layer = self.paths_layer
        if layer is not None and QgsProject.instance().mapLayer(layer.id()) is not None:
            return layer
        prompt = self.costmap_layer.customProperty("overseec/prompt", "") if self.costmap_layer else ""
        if prompt:
            name = f"path — {prompt if len(prompt) <= 60 else prompt[:57] + '...'}"
        else:
            name = f"planned paths ({self.costmap_layer.name() if self.costmap_layer else 'costmap'})"
        layer = QgsVectorLayer(f"LineString?crs={session.crs.authid() or 'EPSG:4326'}", name, "memory")
        if not session.crs.authid():
            layer.setCrs(session.crs)
        layer.dataProvider().addAttributes(
            [
                QgsField("total_cost", QVariant.Double),
                QgsField("length_m", QVariant.Double),
                QgsField("mode", QVariant.String),
                QgsField("vias", QVariant.Int),
            ]
        )
        layer.updateFields()
        apply_style(layer, "path")
        run_dir = self.costmap_layer.customProperty("overseec/run_dir", "") if self.costmap_layer else ""
        set_provenance(layer, Provenance(run_dir=run_dir, stage="plan", extra=(("costmap", session.path),)), "path")
        QgsProject.instance().addMapLayer(layer)
        self.paths_layer = layer
        return layer

    def _store(self, result: PlannedPath, session: CostmapSession) -> None:
        layer = self._paths_layer(session)
        geom = QgsGeometry.fromPolylineXY([QgsPointXY(x, y) for x, y in result.points])
        attrs = [result.cost, result.length_m, result.mode, result.vias]
        provider = layer.dataProvider()
        if self.feature_id is not None and layer.getFeature(self.feature_id).isValid():
            provider.changeGeometryValues({self.feature_id: geom})
            provider.changeAttributeValues({self.feature_id: dict(enumerate(attrs))})
        else:
            feature = QgsFeature(layer.fields())
            feature.setGeometry(geom)
            feature.setAttributes(attrs)
            ok, added = provider.addFeatures([feature])
            self.feature_id = added[0].id() if ok and added else None
        layer.updateExtents()
        layer.triggerRepaint()

    def _draw_markers(self) -> None:
        if self.markers is None:
            return
        self.markers.reset(QgsWkbTypes.PointGeometry)
        for p in self.points:
            self.markers.addPoint(p, False)
        self.markers.updatePosition()
        self.markers.update()

    def save_paths(self, path: str | os.PathLike) -> Path:
        """Write the planned paths as GeoJSON (WGS 84, RFC 7946) and return the file."""
        from qgis.core import QgsVectorFileWriter

        if self.paths_layer is None:
            raise LookupError("no planned paths to save")
        options = QgsVectorFileWriter.SaveVectorOptions()
        options.driverName = "GeoJSON"
        options.layerOptions = ["RFC7946=YES"]
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
