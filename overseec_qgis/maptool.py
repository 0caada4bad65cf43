"""Click-to-plan map tool: start, optional vias, goal -> a planned path on the costmap.

* Click sets the start, Shift+click adds a via point, a plain click sets the goal and plans.
  After a path is planned, the next click starts a new one (its markers replace the old ones).
* Drag any marker of the current path (press on it, move, release) to re-plan it. Only a press
  that moves a few pixels is a drag: a click near an old marker starts a new path. While the
  point moves, the route is re-planned live as a dashed preview (fast mode, while a re-plan takes
  at most :data:`LIVE_PREVIEW_MAX_MS`); the release plans it into the layer.
* Right click or Esc cancels the points being placed (Esc during a drag puts the point back);
  planned paths stay in their layer.
* Markers: start green, vias orange, goal red (canvas items, always above the map). The current
  route (its points and markers) survives a switch to another map tool; only points being placed
  are dropped.
* Re-prompting: when the tool is given a new costmap while a route is planned, it plans the same
  points on the new costmap into a new layer named after that costmap's prompt, so the routes of
  the prompts lie side by side, one legend entry each.
* Overrides: with an override polygon layer set (:meth:`PlanMapTool.set_overrides_layer`; fields
  ``cost``/``prefer``/``lethal``, as `overseec plan --override` reads them), its polygons --
  including unsaved edits -- are applied to the costmap while planning (a snapshot per change,
  written for the worker off the GUI thread: :mod:`overseec_qgis.planfiles`). Any edit of that
  layer, whatever tool made it (QGIS's Add Polygon, the attribute table, undo, commit, roll
  back), re-plans the current route once, :data:`OVERRIDES_SETTLE_MS` after the last edit. A
  project that opens with an overrides layer beside its costmap has it applied again.

Nothing here waits for the planner on QGIS's GUI thread. Planning runs in the planner worker of
the overseec environment (:mod:`overseec_qgis.planclient`; QGIS's Python never loads the native
kernel), each request in a thread of its own (:mod:`overseec_qgis.planjobs`) whose answer comes
back through a queued Qt signal. Points are picked in the canvas CRS and transformed to the
costmap's CRS on the GUI thread before a request leaves. The worker loads a costmap as soon as
the tool is given it (:meth:`PlanMapTool.set_costmap`, also when a project opens); a plan asked
for before the load finished waits for it behind a "loading costmap…" message in the message
bar. Exact plans and plans that took longer than :data:`TASK_AFTER_MS` run as tasks in QGIS's
task manager (progress, Cancel drops the answer). Drag previews never pile up: while one is in
flight only the latest position waits, and a preview that is stale by its turn is not sent.
Answers that are moot by the time they arrive (an older plan of a route, a costmap or project
the tool has left) are dropped. What must stay on the GUI thread is cut into short steps: the
paths table is created while the costmap loads, and a paths layer still to be opened, or put in
edit mode, is readied one event-loop turn at a time before the route is stored.

For scripts and tests: :meth:`PlanMapTool.replan` dispatches and returns (``block=True`` waits
and returns the result), :meth:`PlanMapTool.wait` processes Qt events until every request has
been answered, and ``planned``/``failed`` are emitted on the GUI thread. The dock asks
:meth:`PlanMapTool.costmap_path` (no worker call); :meth:`PlanMapTool.session` loads and blocks.

Paths go into ``paths.gpkg`` in the run folder (one table per costmap, see
:func:`overseec_qgis.layers.open_paths_layer`), a layer added at the top of the legend so it is
drawn above the costmap. Every plan is one command in that layer's edit buffer (Edit > Undo
takes it back); the edits are committed when the project is saved, so the reopened project
shows the same paths. Each path feature keeps its waypoints (start, vias, goal; ``waypoints``,
WKT MULTIPOINT in the layer's CRS; added to older tables when missing), so when the layer's
undo stack moves (undo, redo) the markers move with the path, and the next drag starts from
there. :meth:`PlanMapTool.save_paths` also writes them as RFC 7946 GeoJSON.
"""

from __future__ import annotations

import collections
import functools
import os
import tempfile
import time
import uuid
from dataclasses import dataclass
from pathlib import Path

from qgis.core import (
    Qgis,
    QgsApplication,
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsFeature,
    QgsFeatureRequest,
    QgsField,
    QgsGeometry,
    QgsPointXY,
    QgsProject,
    QgsRasterLayer,
    QgsVectorLayer,
    QgsWkbTypes,
)
from qgis.gui import QgsMapTool, QgsRubberBand, QgsVertexMarker
from qgis.PyQt.QtCore import QCoreApplication, QEventLoop, Qt, QTimer, QVariant, pyqtSignal
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
from .planclient import CostmapInfo, PlanClient, PlanClientError, PlanReply, Superseded, shared_client
from .planfiles import OverridesSnapshot, prepare_paths_table
from .planjobs import Job, PlanTask, Relay

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
#: A plan runs as a task in QGIS's task manager (progress, Cancel) in exact mode, or when the
#: last plan on its costmap took longer than this (ms).
TASK_AFTER_MS = 1000.0
#: Edits of the override layer re-plan once, this long after the last one (ms).
OVERRIDES_SETTLE_MS = 300
#: The paths layer's field holding a route's waypoints (see :func:`waypoints_wkt`).
WAYPOINTS_FIELD = "waypoints"
#: The message shown while a plan waits for its costmap to load.
LOADING_MESSAGE = "loading costmap… the route is planned when it is loaded"


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

    @staticmethod
    def from_reply(reply: PlanReply) -> PlannedPath:
        """The worker's answer as a planned path."""
        return PlannedPath(
            points=reply.points,
            cost=reply.cost,
            length_m=reply.length_m,
            mode=reply.mode,
            vias=reply.vias,
            notes=reply.notes,
            ms=reply.round_trip_ms,
        )


@dataclass(frozen=True)
class CostmapSession:
    """The costmap the tool plans on: its file, CRS, and georeferencing from the worker."""

    path: str
    crs: QgsCoordinateReferenceSystem
    grid: CostmapInfo
    mtime: float


@dataclass(frozen=True)
class PlanRequest:
    """One plan, ready to leave the GUI thread: everything in the costmap's CRS."""

    costmap: str
    crs: QgsCoordinateReferenceSystem
    xy: tuple[tuple[float, float], ...]
    mode: str
    overrides: tuple[OverridesSnapshot, ...]
    #: The route (path_id of its feature) and this plan's number: only a route's latest counts.
    path_key: str
    seq: int
    #: The tool's generation when asked (a new costmap or project makes older answers moot).
    generation: int


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


def find_overrides_layer(folder: Path, project: QgsProject | None = None) -> QgsVectorLayer | None:
    """The project's overrides layer drawn from ``folder``'s overrides GeoPackage, if any."""
    source = str(folder / runfiles.OVERRIDES_LAYER)
    for layer in (project or QgsProject.instance()).mapLayers().values():
        if layer.customProperty(PROP_ROLE) == "overrides" and layer.source().split("|")[0] == source:
            return layer
    return None


def layer_file(layer: QgsRasterLayer) -> str:
    """The absolute path of a raster layer's file (no worker call)."""
    return os.path.abspath(layer.dataProvider().dataSourceUri().split("|")[0])


def waypoints_wkt(points: list[QgsPointXY]) -> str:
    """A route's waypoints (start, vias, goal, in order) as WKT MULTIPOINT."""
    return QgsGeometry.fromMultiPointXY(points).asWkt()


def parse_waypoints(text: object) -> list[QgsPointXY]:
    """The waypoints :func:`waypoints_wkt` wrote (empty for NULL or anything else)."""
    if not isinstance(text, str) or not text.strip():
        return []
    geom = QgsGeometry.fromWkt(text)
    return [] if geom.isNull() else list(geom.asMultiPoint())


def _marker_colours(n: int, complete: bool) -> list[QColor]:
    """Start green, vias orange, goal red (while placing, every point after the start is a via)."""
    if n == 0:
        return []
    colours = [START_COLOUR] + [VIA_COLOUR] * (n - 1)
    if complete and n > 1:
        colours[-1] = GOAL_COLOUR
    return colours


class PlanMapTool(QgsMapTool):
    """The map tool; emits ``planned(PlannedPath)`` or ``failed(message)`` (on the GUI thread).

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
        self._overrides_files: tuple[OverridesSnapshot, ...] = ()
        self._overrides_dirty = False
        self._overrides_dir = tempfile.TemporaryDirectory(prefix="overseec-overrides-")
        self._file_refs: collections.Counter[Path] = collections.Counter()  # files jobs still read
        self._retired: set[Path] = set()
        self._store_steps = 0  # stores waiting for their paths layer to be readied
        self._settle = QTimer(self)
        self._settle.setSingleShot(True)
        self._settle.setInterval(OVERRIDES_SETTLE_MS)
        self._settle.timeout.connect(self._overrides_settled)
        # requests to the worker, answered on this thread
        self._relay = Relay()
        self._relay.done.connect(self._job_done, Qt.QueuedConnection)
        self._jobs: set[Job] = set()
        self._tasks: dict[Job, PlanTask] = {}
        self._loads: dict[str, Job] = {}
        self._queued: dict[str, PlanRequest] = {}  # route -> its latest plan, waiting for a load
        self._preview_job: Job | None = None
        self._preview_next: PlanRequest | None = None
        self._seq = 0
        self._latest: dict[str, int] = {}  # path_key -> seq of the plan that counts
        self._generation = 0
        self._plan_ms: dict[str, float] = {}  # costmap -> the last plan's round trip
        self._loading_item = None
        self._storing = False
        self._history: dict[str, tuple[QgsVectorLayer, object]] = {}  # layer id -> (layer, slot)
        #: The last plan stored (what ``replan(block=True)`` returns).
        self.last_planned: PlannedPath | None = None
        self.markers: list[QgsVertexMarker] | None = []
        self.preview: QgsRubberBand | None = QgsRubberBand(canvas, QgsWkbTypes.LineGeometry)
        self.preview.setColor(QColor(0, 80, 255, 170))
        self.preview.setWidth(3)
        self.preview.setLineStyle(Qt.DashLine)
        self._last_ms = 0.0
        self.setCursor(Qt.CrossCursor)
        project = QgsProject.instance()
        project.writeProject.connect(self._project_writing)
        project.readProject.connect(self._project_read)
        project.cleared.connect(self._project_cleared)
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

        The worker starts loading it at once, in the background. A route planned on the
        previous costmap is planned again on the new one, into its own layer: re-prompting shows
        the prompts' routes side by side."""
        if layer is self.costmap_layer:
            return
        carried = list(self.points) if self.complete else []
        self.cancel()
        self._generation += 1  # answers about the previous costmap are moot
        self.paths_layer = None  # paths on another costmap go to their own layer
        self.costmap_layer = layer
        if layer is not None and layer.isValid():
            self._load(layer)
        if carried and layer is not None:
            self.points, self.complete, self.path_key = carried, True, uuid.uuid4().hex
            self._draw_markers()
            self.replan()

    def costmap_path(self) -> str | None:
        """The file of the costmap the tool plans on (the project's topmost one when none was
        given); None when there is none. Never asks the worker."""
        layer = self._costmap()
        return layer_file(layer) if layer is not None else None

    def _costmap(self) -> QgsRasterLayer | None:
        layer = self.costmap_layer
        try:
            alive = layer is not None and layer.isValid() and QgsProject.instance().mapLayer(layer.id()) is not None
        except RuntimeError:  # the layer object was deleted
            alive = False
        if not alive:
            layer = self.costmap_layer = find_costmap_layer()
        return layer

    def session(self) -> CostmapSession:
        """The current costmap, loaded in the planner worker (again if the file changed).

        Blocks until the worker has it: for scripts and tests. The tool itself never calls it
        (the dock asks :meth:`costmap_path`)."""
        layer = self._costmap()
        if layer is None:
            raise LookupError(f"no costmap layer: build a costmap first (or add {runfiles.COSTMAP})")
        path = layer_file(layer)
        s = self._fresh_session(path)
        if s is None:
            info = self.client.load(path, overrides=[f.ensure_written() for f in self._overrides_files])
            s = CostmapSession(path=path, crs=layer.crs(), grid=info, mtime=os.path.getmtime(path))
            self._sessions[path] = s
        return s

    def _fresh_session(self, path: str) -> CostmapSession | None:
        """The worker's session of a costmap if it is loaded and the file has not changed since."""
        s = self._sessions.get(path)
        try:
            return s if s is not None and s.mtime == os.path.getmtime(path) else None
        except OSError:
            return None

    @property
    def loading(self) -> bool:
        """Whether a plan is waiting for its costmap to load."""
        return bool(self._queued)

    # -- overrides ---------------------------------------------------------------------------

    def set_overrides_layer(self, layer: QgsVectorLayer | None) -> None:
        """Apply this polygon layer's overrides while planning; any edit to it, by any tool,
        re-plans the current route (once, :data:`OVERRIDES_SETTLE_MS` after the last edit)."""
        old = self.overrides_layer
        if old is not None:
            for signal in self._override_signals(old):
                try:
                    signal.disconnect(self._overrides_edited)
                except (TypeError, RuntimeError):  # not connected, or the layer is gone
                    pass
        self.overrides_layer = layer
        if layer is not None:
            for signal in self._override_signals(layer):
                signal.connect(self._overrides_edited)
        self._overrides_dirty = True
        self._flush_overrides()  # a plan asked for from now on applies them
        if self.complete:
            self._settle.start()

    @staticmethod
    def _override_signals(layer: QgsVectorLayer) -> tuple:
        return (
            layer.featureAdded,
            layer.featuresDeleted,
            layer.geometryChanged,
            layer.attributeValueChanged,
            layer.afterCommitChanges,
            layer.afterRollBack,
            layer.undoStack().indexChanged,  # undo and redo of any of the above
            layer.willBeDeleted,
        )

    def _overrides_edited(self, *_args) -> None:
        """The override polygons changed: re-plan once the edits settle (one re-plan for a burst)."""
        self._overrides_dirty = True
        self._settle.start()  # restarts: the re-plan follows the last edit

    def _overrides_settled(self) -> None:
        self._flush_overrides()
        if self.complete and len(self.points) > 1:
            self.replan()

    def _flush_overrides(self) -> None:
        """Write the override polygons (with unsaved edits) for the worker if they changed."""
        if not self._overrides_dirty:
            return
        self._overrides_dirty = False
        self._overrides_version += 1
        old, self._overrides_files = self._overrides_files, self._snapshot_overrides()
        self._retired.update(f.path for f in old)
        self._unlink_retired()

    def _unlink_retired(self) -> None:
        """Remove old override files no request still reads (the worker reads them per request)."""
        for f in [f for f in self._retired if not self._file_refs[f]]:
            f.unlink(missing_ok=True)
            self._retired.discard(f)

    def _snapshot_overrides(self) -> tuple[OverridesSnapshot, ...]:
        """The override polygons now (unsaved edits included); the file is written off this thread."""
        layer = self.overrides_layer
        try:
            if layer is None or QgsProject.instance().mapLayer(layer.id()) is None or layer.featureCount() == 0:
                return ()
        except RuntimeError:  # the layer was deleted
            self.overrides_layer = None
            return ()
        out = Path(self._overrides_dir.name) / f"overrides-{self._overrides_version}.gpkg"
        return (OverridesSnapshot(layer, out, QgsProject.instance().transformContext()),)

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
            self._stop_preview()
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
        self._stop_preview()
        return True

    def deactivate(self) -> None:
        """Another tool took over: a drag in progress goes back and points being placed are
        dropped; the planned route (points, markers) stays, so override edits re-plan it."""
        self._undo_drag()
        self._press = None
        if not self.complete:
            self.points = []
            self._draw_markers()
        super().deactivate()

    # -- planning ------------------------------------------------------------------------------

    def cancel(self) -> None:
        """Drop the points being placed and let go of the current route (it stays in its layer)."""
        self._press, self._drag, self._drag_from = None, None, None
        self.points, self.complete, self.path_key = [], False, None
        self._draw_markers()
        self._stop_preview()

    def clear(self) -> None:
        """Cancel, forget loaded costmaps and take the markers off the canvas (plugin unload).
        The worker itself is the session's: the plugin stops it (planclient.close_shared_client)."""
        self.cancel()
        self._drop_requests()
        self._settle.stop()
        self.set_overrides_layer(None)
        self._settle.stop()
        self._sessions.clear()
        project = QgsProject.instance()
        for signal, slot in (
            (project.writeProject, self._project_writing),
            (project.readProject, self._project_read),
            (project.cleared, self._project_cleared),
            (self.canvas.keyPressed, self._key_during_drag),
            (self._relay.done, self._job_done),
        ):
            try:
                signal.disconnect(slot)
            except TypeError:
                pass
        self._forget_history()
        self._overrides_dir.cleanup()
        self._remove_markers()
        self.markers = None
        if self.preview is not None:
            self.canvas.scene().removeItem(self.preview)
            self.preview = None

    def replan(self, block: bool = False) -> PlannedPath | None:
        """Plan the current route (start, vias, goal) into the paths layer.

        Returns at once: the worker plans in the background (after the costmap's load if it is
        still loading) and the answer is stored, then ``planned`` (or ``failed``) is emitted.
        ``block=True`` (scripts, tests) waits for that and returns the plan, or None."""
        if not self.complete or len(self.points) < 2 or self.path_key is None:
            return None
        request = self._request(self.mode, self.path_key)
        if request is None:
            return None
        self.last_planned = None
        self._latest[request.path_key] = request.seq
        self._dispatch(request)
        if block:
            self.wait()
            return self.last_planned
        return None

    def wait(self, timeout_s: float = 120.0) -> bool:
        """Process Qt events until every request was answered and no edit waits to re-plan
        (for scripts and tests); False if that took longer than ``timeout_s``."""
        deadline = time.monotonic() + timeout_s
        while self.busy():
            if time.monotonic() > deadline:
                return False
            QCoreApplication.processEvents(QEventLoop.AllEvents, 20)
            time.sleep(0.002)
        return True

    def busy(self) -> bool:
        """Whether a request is in flight or waiting (a load, a plan, a preview, settling edits)."""
        return bool(self._jobs or self._queued or self._preview_next or self._store_steps or self._settle.isActive())

    def _request(self, mode: str, path_key: str) -> PlanRequest | None:
        """The current points as a plan request in the costmap's CRS (reports and returns None
        when there is no costmap or a point cannot be transformed)."""
        layer = self._costmap()
        if layer is None:
            self._fail(f"no costmap layer: build a costmap first (or add {runfiles.COSTMAP})")
            return None
        self._flush_overrides()
        try:
            to_costmap = QgsCoordinateTransform(
                self.canvas.mapSettings().destinationCrs(), layer.crs(), QgsProject.instance()
            )
            xy = []
            for p in self.points:
                q = to_costmap.transform(p)
                xy.append((q.x(), q.y()))
        except Exception as exc:  # QgsCsException: report, do not crash the canvas
            self._fail(f"{type(exc).__name__}: {exc}")
            return None
        self._seq += 1
        return PlanRequest(
            costmap=layer_file(layer),
            crs=layer.crs(),
            xy=tuple(xy),
            mode=mode,
            overrides=self._overrides_files,
            path_key=path_key,
            seq=self._seq,
            generation=self._generation,
        )

    def _dispatch(self, request: PlanRequest) -> None:
        """Plan now if the worker has the costmap, else once its load is done (a route's latest
        request replaces its earlier one)."""
        if self._fresh_session(request.costmap) is None:
            if not self._queued:
                self._show_loading()
            self._queued[request.path_key] = request
            self._load(self._costmap(), request.costmap)
            return
        self._start_plan(request)

    def _load(self, layer: QgsRasterLayer | None, path: str | None = None) -> None:
        """Have the worker load a costmap in the background (once at a time per file)."""
        if layer is None:
            return
        path = path or layer_file(layer)
        if path in self._loads or self._fresh_session(path) is not None:
            return
        client, crs = self.client_or_none(), layer.crs()
        overrides = self._overrides_files
        folder, table = self.run_folder(path), paths_table(path)
        context = QgsProject.instance().transformContext()
        try:
            mtime = os.path.getmtime(path)
        except OSError as exc:
            self._fail(f"cannot read the costmap {path}: {exc.strerror or exc}")
            self._queued.clear()
            self._hide_loading()
            return

        def load(_job: Job) -> CostmapSession:
            if client is None:
                raise PlanClientError(self._no_client)
            info = client.load(path, overrides=[f.ensure_written() for f in overrides])
            prepare_paths_table(folder, table, crs, context)  # the first route then only opens it
            return CostmapSession(path=path, crs=crs, grid=info, mtime=mtime)

        self._loads[path] = self._start_job(Job("load", load, self._relay, request=(path, overrides)), overrides)

    def client_or_none(self) -> PlanClient | None:
        """The client, or None when no overseec environment is configured (said at plan time)."""
        try:
            return self.client
        except PlanClientError as exc:
            self._no_client = str(exc)
            return None

    _no_client = "no planner worker"

    def _start_plan(self, request: PlanRequest) -> None:
        client = self.client_or_none()

        def plan(job: Job) -> PlanReply:
            if client is None:
                raise PlanClientError(self._no_client)
            files = [f.ensure_written() for f in request.overrides]
            return client.plan(request.costmap, request.xy, request.mode, overrides=files, wanted=job.wanted)

        job = self._start_job(Job("plan", plan, self._relay, request=request), request.overrides)
        last = self._plan_ms.get(request.costmap, 0.0)
        if request.mode == "exact" or last > TASK_AFTER_MS:
            task = PlanTask(f"overseec: planning a route ({request.mode})", job, last or 2000.0)
            self._tasks[job] = task
            QgsApplication.taskManager().addTask(task)

    def _start_job(self, job: Job, files: tuple[OverridesSnapshot, ...]) -> Job:
        for f in files:
            self._file_refs[f.path] += 1
        self._jobs.add(job)
        return job.start()

    def _drop_requests(self) -> None:
        """Forget every request in flight or waiting (their answers are dropped)."""
        for job in list(self._jobs):
            job.cancel()
        for task in list(self._tasks.values()):
            try:
                task.cancel()
            except RuntimeError:
                pass
        self._queued, self._preview_next = {}, None
        self._generation += 1
        self._hide_loading()

    def _job_done(self, job: Job) -> None:
        """A request's answer, on the GUI thread."""
        self._jobs.discard(job)
        self._tasks.pop(job, None)
        files = job.request[1] if job.kind == "load" else job.request.overrides
        for f in files:
            self._file_refs[f.path] -= 1
        if self.markers is None:  # cleared (plugin unloaded)
            return
        self._unlink_retired()
        handler = {"load": self._load_done, "plan": self._plan_done, "preview": self._preview_done}[job.kind]
        try:
            handler(job)
        except Exception as exc:  # noqa: BLE001 -- an exception in a slot would abort QGIS: report it
            self._fail(f"{type(exc).__name__}: {exc}")

    def _load_done(self, job: Job) -> None:
        path = job.request[0]
        self._loads.pop(path, None)
        if job.error is None:
            self._sessions[path] = job.value
        waiting = [r for r in self._queued.values() if r.costmap == path]
        if not waiting:
            return
        self._queued = {k: r for k, r in self._queued.items() if r.costmap != path}
        if not self._queued:
            self._hide_loading()
        if job.error is not None:
            if any(r.generation == self._generation for r in waiting):
                self._report(job.error)
            return
        for request in waiting:
            self._start_plan(request)

    def _plan_done(self, job: Job) -> None:
        request: PlanRequest = job.request
        if job.cancelled or request.generation != self._generation:
            return  # cancelled, or about a costmap or project the tool has left
        if self._latest.get(request.path_key) != request.seq:
            return  # a newer plan of this route is on its way
        if job.error is not None:
            self._report(job.error)
            return
        reply: PlanReply = job.value
        self._last_ms = self._plan_ms[request.costmap] = reply.round_trip_ms
        result = PlannedPath.from_reply(reply)
        session = self._sessions.get(request.costmap)
        if session is None:
            self._fail("the costmap was unloaded before the route could be stored; plan again")
            return
        self._store_in_steps(result, session, request, 0)

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
        except Exception as exc:  # noqa: BLE001 -- an exception in a slot would abort QGIS: report it
            self._fail(f"{type(exc).__name__}: {exc}")

    def _paths_ready(self) -> bool:
        """Whether the paths layer is open, in the project and in edit mode (storing only edits)."""
        layer = self.paths_layer
        try:
            return layer is not None and QgsProject.instance().mapLayer(layer.id()) is not None and layer.isEditable()
        except RuntimeError:  # the layer was deleted
            return False

    def _report(self, error: BaseException) -> None:
        if isinstance(error, Superseded):
            return
        if isinstance(error, (PlanClientError, LookupError, OSError, ValueError)):
            self._fail(str(error))
        else:
            self._fail(f"{type(error).__name__}: {error}")

    # -- the drag preview --------------------------------------------------------------------------

    def _preview_drag(self) -> None:
        """Re-plan the dragged route as a dashed line (nothing stored; silent on failure: the
        release plans for real and reports). One preview at a time; the latest position waits."""
        if self.preview is None or not self.complete or self.mode != "fast" or self._last_ms > LIVE_PREVIEW_MAX_MS:
            return
        layer = self._costmap()
        if layer is None or self._fresh_session(layer_file(layer)) is None:
            return  # still loading: the release plans
        request = self._request("fast", "")
        if request is None:
            return
        if self._preview_job is not None:
            self._preview_next = request  # only the latest position matters
            return
        self._start_preview(request)

    def _start_preview(self, request: PlanRequest) -> None:
        client = self.client_or_none()
        if client is None:
            return

        def plan(job: Job) -> PlanReply:
            files = [f.ensure_written() for f in request.overrides]
            return client.plan(request.costmap, request.xy, "fast", overrides=files, wanted=job.wanted)

        self._preview_job = self._start_job(Job("preview", plan, self._relay, request=request), request.overrides)

    def _preview_done(self, job: Job) -> None:
        if job is self._preview_job:
            self._preview_job = None
        request: PlanRequest = job.request
        if self._drag is not None and not job.cancelled and request.generation == self._generation:
            if job.error is None:
                self._last_ms = job.value.round_trip_ms
                self._show_preview(job.value.points, request.crs)
            else:
                self._clear_preview()
        upcoming, self._preview_next = self._preview_next, None
        if upcoming is not None and self._drag is not None and self._preview_job is None:
            self._start_preview(upcoming)

    def _show_preview(self, points, crs: QgsCoordinateReferenceSystem) -> None:
        if self.preview is None:
            return
        line = QgsGeometry.fromPolylineXY([QgsPointXY(x, y) for x, y in points])
        try:
            line.transform(
                QgsCoordinateTransform(crs, self.canvas.mapSettings().destinationCrs(), QgsProject.instance())
            )
        except Exception:  # noqa: BLE001 -- QgsCsException: no preview this time
            self._clear_preview()
            return
        self.preview.setToGeometry(line, None)

    def _stop_preview(self) -> None:
        """The drag ended: drop the preview in flight and the one waiting, clear the line."""
        self._preview_next = None
        if self._preview_job is not None:
            self._preview_job.cancel()
        self._clear_preview()

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

    # -- the project ----------------------------------------------------------------------------

    def _project_cleared(self) -> None:
        """The project was closed (or is being replaced): let go of its layers and route."""
        self._drop_requests()
        self._settle.stop()
        self.cancel()
        self._forget_history()
        self.overrides_layer = None
        self._overrides_dirty = True
        self._flush_overrides()  # the closed project's polygons no longer apply
        self.costmap_layer, self.paths_layer = None, None
        self._edited_layers.clear()
        self._sessions.clear()  # the next project's costmaps load afresh (the worker may hold others by then)

    def _project_read(self, *_args) -> None:
        """A project opened: have the worker load its costmap now, before the first click, and
        plan with the overrides layer beside it (its edits re-plan, whatever tool makes them)."""
        layer = find_costmap_layer()
        if layer is not None:
            self.set_costmap(layer)
            overrides = find_overrides_layer(Path(layer_file(layer)).parent)
            if overrides is not None:
                self.set_overrides_layer(overrides)

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
        internal = ("fid", "path_id", WAYPOINTS_FIELD)
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


def ensure_waypoints_field(layer: QgsVectorLayer) -> None:
    """Add the ``waypoints`` field to a paths table made before it existed (old projects), through
    the layer's data provider; without it the path is stored, but undo cannot move the markers."""
    if layer.fields().indexOf(WAYPOINTS_FIELD) >= 0:
        return
    if layer.dataProvider().addAttributes([QgsField(WAYPOINTS_FIELD, QVariant.String)]):
        layer.updateFields()
