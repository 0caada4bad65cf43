"""Requests to the planner worker off the GUI thread, answers back on it.

The map tool never waits for the planner worker on QGIS's GUI thread (a costmap load takes
seconds, an exact plan on a large costmap too):

* :class:`Job` runs one request (a costmap load, a plan, a drag preview) in a daemon thread of
  its own. The :class:`~overseec_qgis.planclient.PlanClient` is thread-safe and sends the jobs'
  requests one at a time, so jobs queue up there, in the order they were started.
* The answer (a value or an exception) comes back through :class:`Relay`'s ``done`` signal, which
  the tool connects with ``Qt.QueuedConnection``: its slot runs on the GUI thread, where the tool
  touches layers and canvas items. A cancelled job's answer is dropped there.
* :class:`PlanTask` shows a job in QGIS's task manager (exact plans, long re-plans): progress from
  the time elapsed against the last such plan's, and Cancel, which drops the answer (the worker
  finishes the search; its answer is not used).

Plain Python threads (not QThread): the work is a blocking pipe read that releases the GIL.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any

from qgis.core import QgsTask
from qgis.PyQt.QtCore import QObject, pyqtSignal

#: How often a task looks at its job and at its own Cancel (seconds).
POLL_S = 0.05


class Relay(QObject):
    """Carries finished jobs from their threads to the GUI thread (``done(Job)``)."""

    done = pyqtSignal(object)


class Job:
    """One request to the planner worker, run in a daemon thread.

    ``work(job)`` does the request (it may look at :attr:`cancelled` to skip it); ``kind`` and
    ``request`` are for whoever receives the job back. When it ends, :attr:`value` or
    :attr:`error` holds the outcome and ``relay.done`` is emitted with the job.
    """

    def __init__(self, kind: str, work: Callable[[Job], Any], relay: Relay, request: Any = None) -> None:
        self.kind = kind
        self.request = request
        self.value: Any = None
        self.error: BaseException | None = None
        self.cancelled = False
        self.finished = threading.Event()
        self.started = 0.0
        self.ended = 0.0
        self._work = work
        self._relay = relay

    def start(self) -> Job:
        """Run the request in its own thread; returns at once."""
        self.started = time.monotonic()
        threading.Thread(target=self._run, name=f"overseec-plan-{self.kind}", daemon=True).start()
        return self

    def cancel(self) -> None:
        """Drop the answer (and skip the request if it has not been sent yet)."""
        self.cancelled = True

    def wanted(self) -> bool:
        """Whether the answer is still wanted (for :meth:`PlanClient.plan`'s ``wanted``)."""
        return not self.cancelled

    @property
    def elapsed_ms(self) -> float:
        """Milliseconds from start to end (to now while it runs)."""
        return 1000.0 * ((self.ended or time.monotonic()) - self.started)

    def _run(self) -> None:
        try:
            self.value = self._work(self)
        except BaseException as exc:
            self.error = exc
        finally:
            self.ended = time.monotonic()
            self.finished.set()
            try:
                self._relay.done.emit(self)
            except RuntimeError:  # the receiver is gone (the plugin was unloaded)
                pass


class PlanTask(QgsTask):
    """A job as a task in QGIS's task manager: estimated progress, and Cancel drops its answer."""

    def __init__(self, description: str, job: Job, expected_ms: float) -> None:
        super().__init__(description, QgsTask.CanCancel)
        self.job = job
        self.expected_ms = max(expected_ms, 100.0)

    def run(self) -> bool:
        """Follow the job (which runs in its own thread) until it ends or the user cancels."""
        while not self.job.finished.wait(POLL_S):
            if self.isCanceled():
                self.job.cancel()
                return False
            # the worker reports no progress for one search: an estimate that never reaches 100
            self.setProgress(min(95.0, 95.0 * self.job.elapsed_ms / self.expected_ms))
        return not self.job.cancelled

    def cancel(self) -> None:
        """Cancel from the task manager: the job's answer is dropped at once."""
        self.job.cancel()
        super().cancel()
