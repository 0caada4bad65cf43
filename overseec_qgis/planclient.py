"""The plugin's side of the planner worker: one ``overseec plan-server`` process per QGIS session.

QGIS's own Python never loads the native planner kernel (the plugin zip is pure Python): the map
tool sends plan requests to the worker of the overseec environment, found like every other worker
run (:func:`overseec_qgis.worker.find_worker`), and reads one JSON answer per request (protocol:
:mod:`overseec_core.plan.server`). The worker keeps the costmaps loaded, so a re-plan after a
drag costs the search only.

* Started lazily by the first request; started again by the next request when it has died.
* Thread-safe: any thread may send requests; they go one at a time (a re-entrant lock held for
  the whole request), answers are matched by id. The map tool sends each request from a thread
  of its own (:mod:`overseec_qgis.planjobs`), so the GUI thread never waits for the worker; a
  plan that is no longer wanted by the time its turn comes (a stale drag preview) is not sent
  (``plan(wanted=...)`` raises :class:`Superseded`).
* Every wait has a timeout; a worker that misses one is stopped (its state is unknown) and the
  next request starts a fresh one. While a worker starts, the timeout counts from its last sign
  of progress (:mod:`overseec_core.liveness`): a worker still importing on a loaded machine is
  alive, not dead after a fixed wall clock.
* Every failure is a :class:`PlanClientError` whose message is one line: ``PlanRejected`` when
  the worker refused the request (a point on a lethal cell, a missing file), ``WorkerError``
  when the worker itself could not be started or failed.
* :func:`shared_client` is the session's client; :func:`close_shared_client` (plugin unload)
  stops its worker.

Plain Python, no Qt: the tests drive it directly.
"""

from __future__ import annotations

import collections
import itertools
import json
import math
import os
import queue
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import IO, Any

from overseec_core import liveness

from .lineclient import SessionClient, require_worker
from .worker import worker_env

#: Seconds a plan may take (exact mode on a 10000² costmap takes about 13 s).
PLAN_TIMEOUT_S = 120.0
#: Seconds loading a costmap may take (reading it and building fast mode's coarse level).
LOAD_TIMEOUT_S = 600.0
#: Seconds for a ping (counted from a starting worker's last progress).
SHORT_TIMEOUT_S = 10.0
#: Most seconds a request waits for a worker that keeps starting (its imports still advancing).
START_LIMIT_S = 300.0


class PlanClientError(Exception):
    """A plan request failed; ``str()`` is one line for a message bar."""


class PlanRejected(PlanClientError):
    """The worker answered with an error (bad point, missing file, no path): the user can fix it."""


class WorkerError(PlanClientError):
    """The worker could not be started, died, or did not answer in time."""


class Superseded(PlanClientError):
    """The request was dropped before it was sent: its caller no longer wanted the answer."""


@dataclass(frozen=True)
class CostmapInfo:
    """A loaded costmap's georeferencing as the worker reports it (pure Python, no GDAL)."""

    path: str
    crs_wkt: str
    width: int
    height: int
    #: The affine transform (a, b, c, d, e, f): x = a*col + b*row + c, y = d*col + e*row + f.
    transform: tuple[float, float, float, float, float, float]
    prompt: str | None = None

    @property
    def shape(self) -> tuple[int, int]:
        return self.height, self.width

    def world_to_pixel(self, x: float, y: float) -> tuple[int, int]:
        """(row, col) of the pixel holding a point in the costmap's CRS (may lie outside)."""
        a, b, c, d, e, f = self.transform
        det = a * e - b * d
        col = (e * (x - c) - b * (y - f)) / det
        row = (a * (y - f) - d * (x - c)) / det
        return math.floor(row), math.floor(col)

    def pixel_to_world(self, row: float, col: float) -> tuple[float, float]:
        """Map coordinates of a pixel centre."""
        a, b, c, d, e, f = self.transform
        return a * (col + 0.5) + b * (row + 0.5) + c, d * (col + 0.5) + e * (row + 0.5) + f

    @staticmethod
    def from_answer(answer: Mapping[str, Any]) -> CostmapInfo:
        t = tuple(float(v) for v in answer["transform"])
        return CostmapInfo(
            path=str(answer["costmap"]),
            crs_wkt=str(answer["crs"]),
            width=int(answer["width"]),
            height=int(answer["height"]),
            transform=(t[0], t[1], t[2], t[3], t[4], t[5]),
            prompt=answer.get("prompt"),
        )


@dataclass(frozen=True)
class PlanReply:
    """A planned route in the costmap's CRS and the worker's figures for it."""

    points: tuple[tuple[float, float], ...]
    cost: float
    length_m: float
    mode: str
    bound: float | None
    vias: int
    notes: tuple[str, ...]
    #: Time spent planning inside the worker, and the whole request seen from here (ms).
    worker_ms: float
    round_trip_ms: float
    #: CPU time the worker spent planning (ms; unlike wall time, not inflated by a busy machine).
    worker_cpu_ms: float = 0.0


def worker_argv(worker: str | os.PathLike) -> list[str]:
    """The command line of the planner worker for an ``overseec`` executable (no shell)."""
    return [str(worker), "plan-server"]


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


class PlanClient:
    """Talks to one planner worker; see the module docstring.

    ``argv`` is the worker's command line, or a callable giving it when the worker starts (so a
    changed setting or a newly built environment is picked up by the next start).
    """

    def __init__(
        self,
        argv: Sequence[str] | Callable[[], Sequence[str]],
        env: Mapping[str, str] | None = None,
        plan_timeout_s: float = PLAN_TIMEOUT_S,
        load_timeout_s: float = LOAD_TIMEOUT_S,
    ) -> None:
        self._argv = argv
        self._env = dict(env) if env is not None else None
        self.plan_timeout_s = plan_timeout_s
        self.load_timeout_s = load_timeout_s
        self._lock = threading.RLock()
        self._proc: subprocess.Popen[str] | None = None
        self._answers: queue.Queue[str | None] = queue.Queue()
        self._stderr: collections.deque[str] = collections.deque(maxlen=40)
        self._ids = itertools.count(1)
        #: Costmaps the current worker process has loaded (a plan on another one loads it first).
        self._loaded: set[str] = set()
        #: How many worker processes this client started.
        self.starts = 0

    # -- the process ---------------------------------------------------------------------------

    @property
    def pid(self) -> int | None:
        proc = self._proc
        return proc.pid if proc is not None and proc.poll() is None else None

    def _start(self) -> subprocess.Popen[str]:
        argv = list(self._argv() if callable(self._argv) else self._argv)
        flags = getattr(subprocess, "CREATE_NO_WINDOW", 0) if sys.platform == "win32" else 0
        try:
            proc = subprocess.Popen(
                argv,
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
                encoding="utf-8",
                errors="replace",
                bufsize=1,
                env=self._env if self._env is not None else worker_env(),
                creationflags=flags,
            )
        except OSError as exc:
            raise WorkerError(f"cannot start the planner worker {argv[0]}: {exc.strerror or exc}") from None
        self._answers = queue.Queue()
        self._stderr.clear()
        self._loaded = set()
        threading.Thread(target=self._pump, args=(proc.stdout, self._answers), daemon=True).start()
        threading.Thread(target=self._drain, args=(proc.stderr,), daemon=True).start()
        self._proc = proc
        self.starts += 1
        return proc

    @staticmethod
    def _pump(stream: IO[str], answers: queue.Queue[str | None]) -> None:
        try:
            for line in iter(stream.readline, ""):
                answers.put(line)
        except (OSError, ValueError):
            pass
        finally:
            answers.put(None)

    def _drain(self, stream: IO[str]) -> None:
        try:
            for line in iter(stream.readline, ""):
                if line.strip():
                    self._stderr.append(line.rstrip())
        except (OSError, ValueError):
            pass

    def _stop(self, proc: subprocess.Popen[str] | None, grace_s: float = 2.0) -> None:
        if proc is None:
            return
        if proc is self._proc:
            self._proc = None
        try:
            if proc.stdin is not None:
                proc.stdin.close()  # end of input: the worker returns
        except OSError:
            pass
        try:
            proc.wait(timeout=grace_s)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(timeout=grace_s)

    def _died(self, proc: subprocess.Popen[str]) -> WorkerError:
        code = proc.poll()
        if code is None:
            try:
                code = proc.wait(timeout=1.0)
            except subprocess.TimeoutExpired:
                code = None
        self._proc = None if proc is self._proc else self._proc
        errors = [ln for ln in self._stderr if ln.startswith("overseec: error:")]
        tail = errors[-1] if errors else (self._stderr[-1] if self._stderr else "")
        why = f": {_one_line(tail)}" if tail else (f" (exit status {code})" if code is not None else "")
        return WorkerError(f"the planner worker stopped{why}")

    # -- requests --------------------------------------------------------------------------------

    def request(self, op: str, timeout_s: float | None = None, **fields: Any) -> dict[str, Any]:
        """Send one request and return the worker's answer (``ok`` true), or raise."""
        with self._lock:
            proc = self._proc
            if proc is None or proc.poll() is not None:
                proc = self._start()
            rid = next(self._ids)
            line = json.dumps({"id": rid, "op": op, **fields}, allow_nan=False)
            try:
                assert proc.stdin is not None
                proc.stdin.write(line + "\n")
                proc.stdin.flush()
            except (OSError, ValueError):
                raise self._died(proc) from None
            answer = self._await(proc, rid, self.plan_timeout_s if timeout_s is None else timeout_s)
        if not answer.get("ok"):
            raise PlanRejected(_one_line(answer.get("error") or "the planner worker refused the request"))
        return answer

    def _await(self, proc: subprocess.Popen[str], rid: int, timeout_s: float) -> dict[str, Any]:
        """The answer to request ``rid``; the timeout counts from the worker's last progress.

        While the worker starts it writes start-up lines (:mod:`overseec_core.liveness`): one
        whose module count grew is progress, and the wait starts again from it (up to
        :data:`START_LIMIT_S` in all), so a worker importing slowly on a loaded machine is alive
        and one stuck in an import is not."""
        t0 = _now()
        deadline = t0 + timeout_s
        modules = -1
        while True:
            left = deadline - _now()
            if left <= 0:
                self._stop(proc, grace_s=0.5)
                raise WorkerError(
                    f"the planner worker did not answer within {timeout_s:g} s; it was stopped "
                    "and starts again with the next plan"
                )
            try:
                line = self._answers.get(timeout=min(left, 0.5))
            except queue.Empty:
                if proc.poll() is not None and self._answers.empty():
                    raise self._died(proc) from None
                continue
            if line is None:
                raise self._died(proc)
            try:
                answer = json.loads(line)
            except ValueError:
                continue  # not a protocol line (the worker never writes one; be lenient)
            if isinstance(answer, dict) and answer.get("id") == rid:
                return answer
            count = _starting_modules(answer)
            if count > modules:  # the worker's imports advanced: wait again from now
                modules = count
                deadline = max(deadline, min(_now() + timeout_s, t0 + START_LIMIT_S))

    def ping(self) -> dict[str, Any]:
        return self.request("ping", timeout_s=SHORT_TIMEOUT_S)

    def load(self, costmap: str | os.PathLike, band: int | None = None, overrides: Sequence[str] = ()) -> CostmapInfo:
        """Load a costmap in the worker (kept until evicted) and return its georeferencing."""
        path = os.path.abspath(costmap)
        with self._lock:
            answer = self.request(
                "load", timeout_s=self.load_timeout_s, costmap=path, band=band, overrides=[str(f) for f in overrides]
            )
            self._loaded.add(path)
        return CostmapInfo.from_answer(answer)

    def plan(
        self,
        costmap: str | os.PathLike,
        points: Sequence[tuple[float, float]],
        mode: str = "fast",
        band: int | None = None,
        overrides: Sequence[str] = (),
        wanted: Callable[[], bool] | None = None,
        neighbours: int = 8,
    ) -> PlanReply:
        """Plan through points in the costmap's CRS (start, vias..., goal), with ``neighbours``
        steps (8, or 16 with knight moves).

        ``wanted`` is asked once this request's turn has come (after any request of another
        thread): False drops it unsent (:class:`Superseded`), so stale previews never pile up."""
        path = os.path.abspath(costmap)
        t0 = _now()
        with self._lock:
            if wanted is not None and not wanted():
                raise Superseded("the plan was superseded by a newer one")
            first = path not in self._loaded or self._proc is None or self._proc.poll() is not None
            answer = self.request(
                "plan",
                timeout_s=self.load_timeout_s if first else self.plan_timeout_s,
                costmap=path,
                points=[[float(x), float(y)] for x, y in points],
                mode=mode,
                band=band,
                overrides=[str(f) for f in overrides],
                neighbours=int(neighbours),
            )
            self._loaded.add(path)
        return PlanReply(
            points=tuple((float(x), float(y)) for x, y in answer["points"]),
            cost=float(answer["cost"]),
            length_m=float(answer["length_m"]),
            mode=str(answer["mode"]),
            bound=answer.get("bound"),
            vias=int(answer.get("vias", max(0, len(points) - 2))),
            notes=tuple(str(n) for n in answer.get("notes", ())),
            worker_ms=float(answer.get("ms", 0.0)),
            round_trip_ms=1000.0 * (_now() - t0),
            worker_cpu_ms=float(answer.get("cpu_ms", 0.0)),
        )

    def close(self) -> None:
        """Stop the worker (plugin unload) without making QGIS wait for it: its input is closed
        (the worker returns) and a background thread reaps it, killing it after a grace period.
        A worker holding a large costmap takes a while to exit, and QGIS's exit should not.

        A request still running in another thread (a long load) is not waited for: the worker
        is killed, and that request fails with a WorkerError."""
        idle = self._lock.acquire(timeout=1.0)
        try:
            proc = self._proc
            if proc is None:
                return
            self._proc = None
            if not idle:
                proc.kill()
            threading.Thread(target=self._stop, args=(proc,), name="overseec-plan-reap", daemon=True).start()
        finally:
            if idle:
                self._lock.release()

    def warm_up(self) -> threading.Thread:
        """Start the worker in a background thread (its imports take a second or two), so a
        costmap being built can be loaded the moment it is written; failures are left for the
        first request to report."""
        return self._in_background("overseec-plan-warm-up", self.ping)

    def preload(self, costmap: str | os.PathLike) -> threading.Thread:
        """Load a costmap in a background thread (the worker starts if needed), so the first
        plan on it does not wait for the read; failures are left for that plan to report."""
        return self._in_background("overseec-plan-preload", lambda: self.load(costmap))

    @staticmethod
    def _in_background(name: str, call: Callable[[], object]) -> threading.Thread:
        """Run a request in a daemon thread, its PlanClientError left for the next request."""

        def run() -> None:
            try:
                call()
            except PlanClientError:
                pass

        thread = threading.Thread(target=run, name=name, daemon=True)
        thread.start()
        return thread


def _now() -> float:
    return time.monotonic()


def _starting_modules(line: object) -> int:
    """The module count of a start-up line (:mod:`overseec_core.liveness`), -1 for any other line."""
    if isinstance(line, dict) and line.get("event") == liveness.STARTING and "id" not in line:
        count = line.get("modules")
        if isinstance(count, int) and not isinstance(count, bool):
            return count
    return -1


# ------------------------------------------------------------------------------------------------
# The session's client
# ------------------------------------------------------------------------------------------------

_session: SessionClient[PlanClient] = SessionClient(lambda: PlanClient(default_argv))


def default_argv() -> list[str]:
    """The worker command from the plugin settings (the overseec environment's ``overseec``)."""
    return worker_argv(require_worker(WorkerError, "plan in"))


def shared_client() -> PlanClient:
    """The one client of this QGIS session (its worker starts with the first plan)."""
    return _session.get()


def close_shared_client() -> None:
    """Stop the session's worker (plugin unload); a later plan starts a new one."""
    _session.close()
