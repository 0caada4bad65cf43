"""The map tool's requests to the planner worker: costmap loads, plans and drag previews.

Nothing here waits for the planner on QGIS's GUI thread. Planning runs in the planner worker of
the overseec environment (:mod:`overseec_qgis.planclient`; QGIS's Python never loads the native
kernel), each request in a thread of its own (:mod:`overseec_qgis.planjobs`) whose answer comes
back through a queued Qt signal. Points are picked in the canvas CRS and transformed to the
costmap's CRS on the GUI thread before a request leaves (:class:`PlanRequest`). The worker loads
a costmap as soon as the tool is given it (``set_costmap``, also when a project opens); a plan
asked for before the load finished waits for it behind a "loading costmap…" message in the
message bar. Exact plans and plans that took longer than :data:`TASK_AFTER_MS` run as tasks in
QGIS's task manager (progress, Cancel drops the answer). Drag previews (only in fast mode, while
a re-plan takes at most :data:`LIVE_PREVIEW_MAX_MS`) never pile up: while one is in flight only
the latest position waits, and a preview that is stale by its turn is not sent. Answers that are
moot by the time they arrive (an older plan of a route, a costmap or project the tool has left)
are dropped. A plan's answer is stored by :mod:`overseec_qgis.planpaths`.

For scripts and tests: :meth:`RequestsMixin.replan` dispatches and returns (``block=True``
waits and returns the result), :meth:`RequestsMixin.wait` processes Qt events until every
request has been answered. The dock asks :meth:`RequestsMixin.costmap_path` (no worker call);
:meth:`RequestsMixin.session` loads and blocks.

A mixin of :class:`~overseec_qgis.maptool.PlanMapTool` (see :mod:`overseec_qgis.planmixin` for
why): requests are built from the tool's points, and answers move its layers and markers.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass

from qgis.core import (
    QgsApplication,
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsProject,
    QgsRasterLayer,
)
from qgis.PyQt.QtCore import QCoreApplication, QEventLoop, Qt

from overseec_core import runfiles

from .layers import PROP_ROLE, paths_table
from .planclient import CostmapInfo, PlanClient, PlanClientError, PlanReply, Superseded, shared_client
from .planfiles import OverridesSnapshot, prepare_paths_table
from .planjobs import Job, PlanTask, Relay
from .planmixin import ToolMixin

#: Re-plan live while a point is dragged as long as a re-plan takes at most this long (ms);
#: slower ones (exact mode, very large costmaps) plan only on release.
LIVE_PREVIEW_MAX_MS = 250.0
#: A plan runs as a task in QGIS's task manager (progress, Cancel) in exact mode, or when the
#: last plan on its costmap took longer than this (ms).
TASK_AFTER_MS = 1000.0


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
    #: Steps: 8 neighbours, or 16 with knight moves.
    neighbours: int
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


def layer_file(layer: QgsRasterLayer) -> str:
    """The absolute path of a raster layer's file (no worker call)."""
    return os.path.abspath(layer.dataProvider().dataSourceUri().split("|")[0])


class RequestsMixin(ToolMixin):
    """The tool's worker requests: costmap sessions, plans, previews, and their answers."""

    # the tool's costmap (:class:`~overseec_qgis.maptool.PlanMapTool`)
    costmap_layer: QgsRasterLayer | None

    def _init_requests(self, client: PlanClient | None) -> None:
        self._client = client
        self._sessions: dict[str, CostmapSession] = {}
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
        #: The last plan stored (what ``replan(block=True)`` returns).
        self.last_planned: PlannedPath | None = None
        self._last_ms = 0.0

    @property
    def client(self) -> PlanClient:
        """The planner worker's client (the session's shared one unless one was given)."""
        return self._client if self._client is not None else shared_client()

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
            neighbours=self.neighbours,
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

    def warm_up(self) -> None:
        """Start the planner worker now, in the background (e.g. while a costmap is built, so
        its load starts at once when the costmap is shown)."""
        client = self.client_or_none()
        if client is not None:
            client.warm_up()

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
            return client.plan(
                request.costmap,
                request.xy,
                request.mode,
                overrides=files,
                wanted=job.wanted,
                neighbours=request.neighbours,
            )

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
        except Exception as exc:
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

    def _stop_preview(self) -> None:
        """The drag ended: drop the preview in flight and the one waiting, clear the line."""
        self._preview_next = None
        if self._preview_job is not None:
            self._preview_job.cancel()
        self._clear_preview()
