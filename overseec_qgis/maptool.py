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
* Overrides: with an override polygon layer set (:meth:`PlanMapTool.set_overrides_layer`), its
  polygons, unsaved edits included, are applied while planning, and any edit of that layer,
  whatever tool made it, re-plans the current route (:mod:`overseec_qgis.planoverrides`).

This module holds the tool's events and points (clicks, drags, Esc), its costmap and the project's
signals. The rest of the tool is split by concern into mixins, each a module of its own (see
:mod:`overseec_qgis.planmixin` for why mixins): the requests to the planner worker, none of which
waits on QGIS's GUI thread (:mod:`overseec_qgis.planrequests`), the paths layer with its undo and
redo (:mod:`overseec_qgis.planpaths`), the override polygons (:mod:`overseec_qgis.planoverrides`),
and the markers, drag preview and messages (:mod:`overseec_qgis.planmarkers`). The names other
modules and tests use are all importable from here.

For scripts and tests: :meth:`PlanMapTool.replan` dispatches and returns (``block=True`` waits
and returns the result), :meth:`PlanMapTool.wait` processes Qt events until every request has
been answered, and ``planned``/``failed`` are emitted on the GUI thread. The dock asks
:meth:`PlanMapTool.costmap_path` (no worker call); :meth:`PlanMapTool.session` loads and blocks.
"""

from __future__ import annotations

import uuid
from pathlib import Path

from qgis.core import QgsPointXY, QgsProject, QgsRasterLayer
from qgis.gui import QgsMapTool
from qgis.PyQt.QtCore import Qt, pyqtSignal

from .params import PLAN_MODE, PLAN_STEPS
from .planclient import PlanClient
from .planmarkers import GOAL_COLOUR, LOADING_MESSAGE, MARKER_SIZE, START_COLOUR, VIA_COLOUR, MarkersMixin
from .planoverrides import OVERRIDES_SETTLE_MS, OverridesMixin, find_overrides_layer
from .planpaths import WAYPOINTS_FIELD, PathsMixin, ensure_waypoints_field, parse_waypoints, waypoints_wkt
from .planrequests import (
    LIVE_PREVIEW_MAX_MS,
    TASK_AFTER_MS,
    CostmapSession,
    PlannedPath,
    PlanRequest,
    RequestsMixin,
    find_costmap_layer,
    layer_file,
)

__all__ = [
    "DRAG_START_PX",
    "GOAL_COLOUR",
    "GRAB_TOLERANCE_PX",
    "LIVE_PREVIEW_MAX_MS",
    "LOADING_MESSAGE",
    "MARKER_SIZE",
    "OVERRIDES_SETTLE_MS",
    "START_COLOUR",
    "TASK_AFTER_MS",
    "VIA_COLOUR",
    "WAYPOINTS_FIELD",
    "CostmapSession",
    "PlanMapTool",
    "PlanRequest",
    "PlannedPath",
    "ensure_waypoints_field",
    "find_costmap_layer",
    "find_overrides_layer",
    "layer_file",
    "parse_waypoints",
    "waypoints_wkt",
]

#: A press within this many screen pixels of a marker grabs that marker.
GRAB_TOLERANCE_PX = 8
#: A press becomes a drag once the mouse moved this many pixels (less is a click).
DRAG_START_PX = 4


class PlanMapTool(RequestsMixin, PathsMixin, OverridesMixin, MarkersMixin, QgsMapTool):
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
        self.mode = PLAN_MODE  # interactive: every click re-plans (see params.Params)
        self.neighbours = PLAN_STEPS[0]  # steps: 8, or 16 with knight moves (the dock's Steps)
        self.costmap_layer: QgsRasterLayer | None = None
        self.points: list[QgsPointXY] = []  # canvas CRS: start, vias..., goal
        self.complete = False
        self.path_key: str | None = None  # path_id of the current path's feature
        self._press: tuple[int, int, int | None] | None = None  # x, y, grabbed marker
        self._drag: int | None = None
        self._drag_from: QgsPointXY | None = None
        self._init_requests(client)
        self._init_paths()
        self._init_overrides()
        self._init_markers()
        self.setCursor(Qt.CrossCursor)
        project = QgsProject.instance()
        project.writeProject.connect(self._project_writing)
        project.readProject.connect(self._project_read)
        project.cleared.connect(self._project_cleared)
        # while a mouse button is down the canvas passes keys only to this signal, not the tool
        canvas.keyPressed.connect(self._key_during_drag)

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

    # -- events --------------------------------------------------------------------------------

    def _near(self, pos) -> int | None:
        """The current path's marker under a screen position (the last placed wins)."""
        for i in reversed(range(len(self.points))):
            screen = self.toCanvasCoordinates(self.points[i])
            if abs(screen.x() - pos.x()) <= GRAB_TOLERANCE_PX and abs(screen.y() - pos.y()) <= GRAB_TOLERANCE_PX:
                return i
        return None

    def canvasPressEvent(self, e) -> None:
        if e.button() == Qt.LeftButton:
            self._press = (e.pos().x(), e.pos().y(), self._near(e.pos()))
            self._drag = None

    def canvasMoveEvent(self, e) -> None:
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

    def canvasReleaseEvent(self, e) -> None:
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

    def keyPressEvent(self, e) -> None:
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

    def activate(self) -> None:
        """The tool was armed: the worker starts loading the costmap the first click will plan
        on (the topmost one when none was given, e.g. a costmap the analyst added with Layer ›
        Add Raster Layer), so the load runs while the analyst picks the start, not after the
        goal click."""
        super().activate()
        layer = self._costmap()
        if layer is not None and layer.isValid():
            self._load(layer)

    def deactivate(self) -> None:
        """Another tool took over: a drag in progress goes back and points being placed are
        dropped; the planned route (points, markers) stays, so override edits re-plan it."""
        self._undo_drag()
        self._press = None
        if not self.complete:
            self.points = []
            self._draw_markers()
        super().deactivate()

    # -- cancel and clear ------------------------------------------------------------------------

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
