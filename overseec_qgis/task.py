"""Background work for the dock: QgsTasks for the worker process and for plain functions.

* :class:`WorkerTask` runs an ``overseec`` CLI command (every pipeline stage) in a subprocess and
  turns its JSON-lines events into task progress; cancelling the task terminates the process.
  With ``capture`` it keeps what the command printed (its ``--json`` document) for the caller.
* :class:`PipelineTask` runs a function that reports through the core's Progress protocol (the
  environment check) on QGIS's task thread, so the GUI never blocks.

Both report back on the main thread through ``finished()``: ``succeeded(result)`` or
``failed(one_line_message, details_for_the_log)``; after a failure ``was_cancelled`` says whether
the user asked for it (the dock shows that as information, not as an error). :class:`QgisProgress` adapts the core's
Progress protocol to a QgsTask here and to Processing's ``QgsProcessingFeedback`` there.
"""

from __future__ import annotations

import traceback
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from qgis.core import Qgis, QgsFeedback, QgsMessageLog, QgsTask
from qgis.PyQt.QtCore import pyqtSignal

from overseec_core.errors import Cancelled, OverseecError
from overseec_core.progress import BaseProgress

from .worker import event_reporter, run_worker

LOG_TAG = "overseec"


def log(text: str, level: int = Qgis.Info) -> None:
    """Write ``text`` to the QGIS message log under the plugin's tag."""
    QgsMessageLog.logMessage(text, LOG_TAG, level)


class QgisProgress(BaseProgress):
    """overseec's Progress protocol over anything with ``setProgress`` and ``isCanceled``: the
    dock's QgsTask or Processing's QgsProcessingFeedback. Messages go to the feedback's log
    when it has one, else to the QGIS log panel."""

    def __init__(self, target: QgsTask | QgsFeedback, on_stage: Callable[[str], None] | None = None) -> None:
        super().__init__()
        self._target = target
        self._on_stage = on_stage

    def begin(self, stage: str, total: int | None, unit: str = "tile") -> None:
        super().begin(stage, total, unit)
        if self._on_stage is not None:
            self._on_stage(stage)
        if hasattr(self._target, "setProgressText"):
            self._target.setProgressText(stage)
        self._target.setProgress(0.0)

    def advance(self, n: int = 1) -> None:
        super().advance(n)
        if self.total:
            self._target.setProgress(min(100.0, 100.0 * self.done / self.total))

    def end(self) -> None:
        self._target.setProgress(100.0)

    def message(self, text: str) -> None:
        if hasattr(self._target, "pushInfo"):
            self._target.pushInfo(text)
        else:
            log(text)

    def cancelled(self) -> bool:
        return self._target.isCanceled() or super().cancelled()


class _BaseTask(QgsTask):
    """Common plumbing: result/error held for ``finished()``, signals to the main thread."""

    succeeded = pyqtSignal(object)
    failed = pyqtSignal(str, str)
    #: stage name and a short line for the dock's status label
    status = pyqtSignal(str)

    def __init__(self, description: str) -> None:
        super().__init__(description, QgsTask.CanCancel)
        self.result: Any = None
        self.error = ""
        self.details = ""
        self._cancelled = False

    @property
    def was_cancelled(self) -> bool:
        """The task stopped because it was cancelled (by the user, or the work said so)."""
        return self._cancelled or self.isCanceled()

    def finished(self, ok: bool) -> None:  # main thread
        if ok:
            self.succeeded.emit(self.result)
            return
        if not self.error:
            self.error = "cancelled; partial outputs were discarded" if self.was_cancelled else "the task failed"
        level = Qgis.Info if self.was_cancelled else Qgis.Warning
        log(f"{self.description()}: {self.error}\n{self.details}".rstrip(), level)
        self.failed.emit(self.error, self.details)


class WorkerTask(_BaseTask):
    """Runs ``argv`` (the overseec CLI with --json-progress) as a cancellable subprocess.

    ``precheck`` (run first, on the task thread) returns "" when the run can go ahead, else the
    one-line reason it cannot (e.g. every missing model's weights, before any model loads).
    ``after`` (run last, on the task thread, with what the command printed) turns a successful
    run into the task's ``result`` (e.g. reading the interpretation and fitting its program to
    the entity layers), so that nothing slow is left for the GUI thread.
    """

    def __init__(
        self,
        description: str,
        argv: Sequence[str],
        env: Mapping[str, str] | None = None,
        weights: Mapping[str, float] | None = None,
        precheck: Callable[[], str] | None = None,
        capture: bool = False,
        after: Callable[[list[str]], Any] | None = None,
    ) -> None:
        super().__init__(description)
        self.argv = list(argv)
        self.env = env
        self.precheck = precheck
        self.after = after
        #: with ``capture``, the lines the command printed (its ``--json`` document), not logged
        self.printed: list[str] = []
        report = event_reporter(weights, self.setProgress, self.status.emit, log)

        def on_event(event) -> None:
            if capture and event.kind == "text":
                self.printed.append(event.text)
            else:
                report(event)

        self._report = on_event

    def run(self) -> bool:  # task thread
        if self.precheck is not None:
            problem = self.precheck()
            if problem:
                self.error = problem
                return False
            if self.isCanceled():
                return False
        log("running: " + " ".join(self.argv))
        try:
            res = run_worker(self.argv, on_event=self._report, is_cancelled=self.isCanceled, env=self.env)
        except OSError as exc:
            self.error = f"cannot start the overseec worker {self.argv[0]} ({exc.strerror or exc})"
            return False
        self.result = res
        self._cancelled = res.cancelled
        if not res.ok:
            self.error = res.summary()
            self.details = "command: " + " ".join(res.argv) + "\n" + res.stderr
            return False
        if self.after is not None:
            return self._after()
        self.setProgress(100.0)
        return True

    def _after(self) -> bool:  # task thread
        assert self.after is not None
        try:
            self.result = self.after(self.printed)
        except OverseecError as exc:
            self.error = str(exc)
            return False
        except Exception as exc:  # a bug: keep the traceback for the log panel
            self.error = f"unexpected failure: {type(exc).__name__}: {exc}"
            self.details = traceback.format_exc()
            return False
        self.setProgress(100.0)
        return True


class PipelineTask(_BaseTask):
    """Runs ``fn(*args, progress=..., **kwargs)`` (e.g. the environment check) in a task."""

    def __init__(self, description: str, fn: Callable[..., Any], *args: Any, **kwargs: Any) -> None:
        super().__init__(description)
        self._fn, self._args, self._kwargs = fn, args, kwargs

    def run(self) -> bool:  # task thread
        progress = QgisProgress(self, on_stage=self.status.emit)
        try:
            self.result = self._fn(*self._args, progress=progress, **self._kwargs)
            return True
        except Cancelled as exc:
            self.error = str(exc)
            self._cancelled = True
        except OverseecError as exc:
            self.error = str(exc)
        except Exception as exc:  # a bug: keep the traceback for the log panel
            self.error = f"unexpected failure: {type(exc).__name__}: {exc}"
            self.details = traceback.format_exc()
        return False
