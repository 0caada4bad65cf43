"""The worker process: run the ``overseec`` CLI, read its JSON-lines progress, cancel it.

Heavy inference (CLIPSeg, SAM) never runs inside QGIS: the plugin starts the ``overseec`` command
of the project's Python environment with ``--json-progress`` and reads one JSON object per line on
stdout (``begin`` / ``progress`` / ``end`` / ``message``). Writer and reader share one schema,
``overseec_core.progress`` (``ProgressEvent``, ``encode_event``, ``parse_event``; standard library
only, so importing it here is cheap). Errors arrive on stderr as ``overseec: error: <one line>``
with exit status 2. Cancelling terminates the process (SIGTERM,
which the CLI turns into a clean stop that discards partial outputs), then kills it after a grace
period.

This module is plain Python (no Qt), so the QgsTask, the Processing algorithms and the tests share
it. ``subprocess`` does the process work, and argv lists are passed without a shell.
"""

from __future__ import annotations

import os
import queue
import shutil
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from overseec_core.progress import ProgressEvent, parse_event

from . import venvs

#: Seconds between SIGTERM and SIGKILL when a run is cancelled.
CANCEL_GRACE_S = 5.0
ERROR_PREFIX = "overseec: error: "
#: Exit status the CLI uses for a cancelled run.
EXIT_CANCELLED = 130


#: One line of worker output (the core's protocol event; ``kind`` ``text`` for a non-JSON line).
WorkerEvent = ProgressEvent


class StageProgress:
    """Turns per-stage fractions into one overall fraction for a multi-stage run.

    ``weights`` gives the expected stages and their share of the run's time (segmentation
    dominates); a stage the table does not know simply shows its own fraction. Sub-stages
    ("evaluate: planning") count towards their stage ("evaluate").
    """

    def __init__(self, weights: Mapping[str, float] | None = None) -> None:
        self.weights = dict(weights or {})
        self._total = sum(self.weights.values()) or 1.0
        self._finished: set[str] = set()

    def update(self, event: WorkerEvent) -> float | None:
        """Overall fraction in [0, 1] after ``event``, or None when it says nothing new."""
        stage = event.stage.split(":")[0].strip()
        if event.kind == "end" and stage:
            self._finished.add(stage)
        if event.kind not in ("begin", "progress", "end"):
            return None
        stage_fraction = 1.0 if event.kind == "end" else (event.fraction or 0.0)
        if stage not in self.weights:
            return stage_fraction
        done = sum(self.weights[s] for s in self._finished if s in self.weights and s != stage)
        return min(1.0, (done + self.weights[stage] * stage_fraction) / self._total)


def event_reporter(
    weights: Mapping[str, float] | None,
    set_progress: Callable[[float], None],
    on_stage: Callable[[str], None],
    on_text: Callable[[str], None],
) -> Callable[[WorkerEvent], None]:
    """An ``on_event`` for :func:`run_worker`: overall percent, stage names and messages."""
    stages = StageProgress(weights)

    def report(event: WorkerEvent) -> None:
        fraction = stages.update(event)
        if fraction is not None:
            set_progress(100.0 * fraction)
        if event.kind == "begin" and event.stage:
            on_stage(event.stage)
        elif event.kind in ("message", "text") and event.text:
            on_text(event.text)

    return report


@dataclass(frozen=True)
class WorkerResult:
    """How a worker run ended."""

    argv: tuple[str, ...]
    returncode: int
    cancelled: bool
    stderr: str
    #: The CLI's one-line error (without the ``overseec: error:`` prefix), or "".
    error: str = ""
    messages: tuple[str, ...] = field(default=())

    @property
    def ok(self) -> bool:
        return self.returncode == 0 and not self.cancelled

    def summary(self) -> str:
        """One line for a message bar."""
        if self.cancelled:
            return "cancelled; partial outputs were discarded"
        if self.ok:
            return "finished"
        if self.error:
            return self.error
        tail = [ln for ln in self.stderr.strip().splitlines() if ln.strip()]
        return tail[-1] if tail else f"the worker exited with status {self.returncode}"


class WorkerFailed(Exception):
    """A worker run failed or was cancelled; ``result`` holds the details for the log."""

    def __init__(self, result: WorkerResult) -> None:
        self.result = result
        super().__init__(result.summary())


def _read_lines(stream, sink: queue.Queue[tuple[str, str | None]], tag: str) -> None:
    try:
        for line in iter(stream.readline, ""):
            sink.put((tag, line))
    finally:
        sink.put((tag, None))


def run_worker(  # noqa: C901
    argv: Sequence[str],
    on_event: Callable[[WorkerEvent], None] | None = None,
    is_cancelled: Callable[[], bool] | None = None,
    env: Mapping[str, str] | None = None,
    cwd: str | os.PathLike | None = None,
    poll_s: float = 0.1,
    grace_s: float = CANCEL_GRACE_S,
    on_start: Callable[[subprocess.Popen], None] | None = None,
) -> WorkerResult:
    """Run ``argv`` (no shell), feed its JSON-lines events to ``on_event``, honour cancellation.

    ``is_cancelled`` is polled every ``poll_s`` seconds; when it turns true the process is
    terminated, and killed if it has not exited after ``grace_s`` seconds. Returns a
    :class:`WorkerResult`; never raises for a failing worker (the caller decides).
    """
    proc = subprocess.Popen(
        list(argv),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        stdin=subprocess.DEVNULL,
        text=True,
        encoding="utf-8",
        errors="replace",
        bufsize=1,
        env=None if env is None else dict(env),
        cwd=None if cwd is None else str(cwd),
    )
    if on_start is not None:
        on_start(proc)
    lines: queue.Queue[tuple[str, str | None]] = queue.Queue()
    readers = [
        threading.Thread(target=_read_lines, args=(proc.stdout, lines, "out"), daemon=True),
        threading.Thread(target=_read_lines, args=(proc.stderr, lines, "err"), daemon=True),
    ]
    for t in readers:
        t.start()
    stderr: list[str] = []
    messages: list[str] = []
    open_streams = 2
    cancelled = False
    kill_at: float | None = None
    while open_streams:
        if not cancelled and is_cancelled is not None and is_cancelled():
            cancelled = True
            _terminate(proc)
            kill_at = time.monotonic() + grace_s
        if kill_at is not None and time.monotonic() >= kill_at and proc.poll() is None:
            proc.kill()
            kill_at = None
        try:
            tag, line = lines.get(timeout=poll_s)
        except queue.Empty:
            continue
        if line is None:
            open_streams -= 1
            continue
        if tag == "err":
            stderr.append(line)
            continue
        event = parse_event(line)
        if event is None:
            continue
        if event.kind in ("message", "text"):
            messages.append(event.text)
        if on_event is not None:
            on_event(event)
    returncode = proc.wait()
    for t in readers:
        t.join(timeout=1.0)
    _close_pipes(proc)
    err_text = "".join(stderr)
    error = ""
    for ln in err_text.splitlines():
        if ln.startswith(ERROR_PREFIX):
            error = ln[len(ERROR_PREFIX) :].strip()
    cancelled = cancelled or returncode == EXIT_CANCELLED
    return WorkerResult(
        argv=tuple(argv),
        returncode=returncode,
        cancelled=cancelled,
        stderr=err_text,
        error=error,
        messages=tuple(messages),
    )


def _close_pipes(proc: subprocess.Popen) -> None:
    """Close our ends of the worker's pipes: left to the garbage collector, each one is a
    ``ResourceWarning: unclosed file`` in QGIS's log."""
    for stream in (proc.stdout, proc.stderr):
        if stream is not None:
            try:
                stream.close()
            except OSError:
                pass


def _terminate(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        try:
            proc.terminate()
        except OSError:
            pass


# --------------------------------------------------------------------------------------------
# Finding the worker
# --------------------------------------------------------------------------------------------


def candidate_workers(
    setting: str = "", venv: str = "", plugin_dir: str | os.PathLike | None = None
) -> list[tuple[str, Path]]:
    """Where the ``overseec`` command may be, in the order they are tried, with their origin.

    1. the plugin setting (a path to the ``overseec`` executable), or $OVERSEEC_WORKER;
    2. the configured environment (setting, or $OVERSEEC_VENV): ``<venv>/bin/overseec``
       (``<venv>\\Scripts\\overseec.exe`` in a Windows venv, see :mod:`venvs`);
    3. this interpreter's prefix: ``sys.prefix/bin/overseec`` (QGIS started from the venv);
    4. a ``.venv`` beside the plugin's source checkout (a developer's symlinked plugin);
    5. ``overseec`` on PATH.
    """
    found: list[tuple[str, Path]] = []
    explicit = setting or os.environ.get("OVERSEEC_WORKER", "")
    if explicit:
        found.append(("setting", Path(explicit).expanduser()))
    env_dir = venv or os.environ.get("OVERSEEC_VENV", "")
    if env_dir:
        found.append(("environment", venvs.executable(Path(env_dir).expanduser(), "overseec")))
    found.append(("sys.prefix", venvs.executable(sys.prefix, "overseec")))
    if plugin_dir is not None:
        for parent in list(Path(plugin_dir).resolve().parents)[:3]:
            found.append(("checkout", venvs.executable(parent / ".venv", "overseec")))
    on_path = shutil.which("overseec")
    if on_path:
        found.append(("PATH", Path(on_path)))
    return found


def find_worker(setting: str = "", venv: str = "", plugin_dir: str | os.PathLike | None = None) -> Path | None:
    """The first existing, executable ``overseec`` command (see :func:`candidate_workers`)."""
    for _origin, path in candidate_workers(setting, venv, plugin_dir):
        if path.is_file() and os.access(path, os.X_OK):
            return path
    return None


def configured_worker() -> Path | None:
    """The ``overseec`` command the plugin settings name (read from QgsSettings now), found as
    :func:`find_worker` finds it; None when there is none."""
    from .settings import PluginSettings  # QgsSettings: the rest of this module stays plain Python

    settings = PluginSettings.load()
    return find_worker(settings.worker_path, settings.venv, Path(__file__).parent)


def worker_python(worker: str | os.PathLike) -> Path:
    """The Python interpreter beside an ``overseec`` entry point (the same venv; ``python3`` or
    ``python`` in ``bin/``, ``python.exe`` in ``Scripts/`` or, for a conda environment on
    Windows, at the environment's root above ``Scripts/``), else this interpreter."""
    for name in ("python3", "python"):
        cand = venvs.sibling(worker, name)
        if cand is not None:
            return cand
    if Path(worker).parent.name == "Scripts" and (venvs.venv_of(worker) / "python.exe").is_file():
        return venvs.venv_of(worker) / "python.exe"
    return Path(sys.executable)


def worker_env(extra: Mapping[str, str] | None = None) -> dict[str, str]:
    """Environment for the worker: ours plus ``extra``, without QGIS's Python overrides.

    QGIS may set PYTHONPATH/PYTHONHOME for its embedded interpreter; the worker is a venv's own
    interpreter and must see only that venv. Qt runs headless there.
    """
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONHOME", "PYTHONPATH")}
    env.setdefault("QT_QPA_PLATFORM", "offscreen")
    env["PYTHONUNBUFFERED"] = "1"
    if extra:
        env.update(extra)
    return env


def cli_argv(worker: str | os.PathLike, command: str, args: Iterable[str]) -> list[str]:
    """``[worker, --json-progress, command, *args]``."""
    return [str(worker), "--json-progress", command, *[str(a) for a in args]]
