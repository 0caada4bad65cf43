"""Progress and cancellation: a small protocol the core reports to.

Long stages call ``progress.begin(stage, total)``, ``advance()`` per unit of work and ``end()``,
and call :func:`check_cancelled` between units. Front ends adapt it: the CLI draws a tqdm bar
(with an ETA) or prints JSON lines for a driving process (the QGIS plugin), and QGIS adapts
``QgsFeedback``. The core never knows which.
"""

from __future__ import annotations

import json
import sys
import threading
import time
from dataclasses import dataclass
from typing import IO, Any, Protocol, runtime_checkable

from overseec_core.errors import Cancelled
from overseec_core.io.transaction import watch

# --------------------------------------------------------------------------------------------
# The JSON-lines protocol (``overseec --json-progress``): one event per line, written by
# JsonLinesProgress, read by the QGIS worker (overseec_qgis.worker) -- both through this schema.
# --------------------------------------------------------------------------------------------

#: The fields each event kind carries on the wire (besides ``"event": kind``).
EVENT_FIELDS: dict[str, tuple[str, ...]] = {
    "begin": ("stage", "total", "unit"),
    "progress": ("stage", "done", "total", "fraction", "eta_s"),
    "end": ("stage", "done"),
    "message": ("text",),
}
#: The kind a reader gives a line that is not a protocol event (a library printing to stdout).
TEXT_KIND = "text"


@dataclass(frozen=True)
class ProgressEvent:
    """One protocol event: ``kind`` is begin, progress, end, message (or ``text`` when read)."""

    kind: str
    stage: str = ""
    done: int | None = None
    total: int | None = None
    fraction: float | None = None
    eta_s: float | None = None
    text: str = ""
    unit: str = ""


def encode_event(event: ProgressEvent) -> str:
    """The event as one JSON line (no newline): ``event`` plus its kind's :data:`EVENT_FIELDS`."""
    data: dict[str, Any] = {"event": event.kind}
    data.update((name, getattr(event, name)) for name in EVENT_FIELDS[event.kind])
    return json.dumps(data)


def _number(value: object) -> float | None:
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None


def parse_event(line: str) -> ProgressEvent | None:
    """Parse one line; blank lines give None, anything that is not an event a ``text`` event.

    Lenient, for a reader: ``fraction`` is derived from done/total when missing and clamped to
    [0, 1]; values of the wrong type read as absent.
    """
    line = line.strip()
    if not line:
        return None
    try:
        data = json.loads(line)
    except ValueError:
        return ProgressEvent(kind=TEXT_KIND, text=line)
    if not isinstance(data, dict) or "event" not in data:
        return ProgressEvent(kind=TEXT_KIND, text=line)
    done, total = data.get("done"), data.get("total")
    fraction = _number(data.get("fraction"))
    done_n, total_n = _number(done), _number(total)
    if fraction is None and done_n is not None and total_n:
        fraction = done_n / total_n
    return ProgressEvent(
        kind=str(data.get("event")),
        stage=str(data.get("stage") or ""),
        done=done if isinstance(done, int) else None,
        total=total if isinstance(total, int) else None,
        fraction=None if fraction is None else max(0.0, min(1.0, float(fraction))),
        eta_s=_number(data.get("eta_s")),
        text=str(data.get("text") or ""),
        unit=str(data.get("unit") or ""),
    )


@runtime_checkable
class Progress(Protocol):
    """What a long-running stage reports to."""

    def begin(self, stage: str, total: int | None, unit: str = "tile") -> None: ...

    def advance(self, n: int = 1) -> None: ...

    def end(self) -> None: ...

    def message(self, text: str) -> None: ...

    def cancelled(self) -> bool: ...


class CancelToken:
    """A thread-safe flag a front end sets (Cancel button, SIGTERM) and the core polls."""

    def __init__(self) -> None:
        self._event = threading.Event()

    def cancel(self) -> None:
        self._event.set()

    def is_set(self) -> bool:
        return self._event.is_set()


class BaseProgress:
    """Counts work and owns a cancel token; subclasses decide how to show it."""

    def __init__(self, token: CancelToken | None = None) -> None:
        self.token = token or CancelToken()
        self.stage = ""
        self.total: int | None = None
        self.done = 0
        self._t0 = time.monotonic()

    def begin(self, stage: str, total: int | None, unit: str = "tile") -> None:
        self.stage, self.total, self.done, self.unit = stage, total, 0, unit
        self._t0 = time.monotonic()

    def advance(self, n: int = 1) -> None:
        self.done += n

    def end(self) -> None:
        pass

    def message(self, text: str) -> None:
        pass

    def cancelled(self) -> bool:
        return self.token.is_set()

    def eta_seconds(self) -> float | None:
        """Remaining seconds at the mean rate so far, or None before the first unit."""
        if not self.total or not self.done:
            return None
        elapsed = time.monotonic() - self._t0
        return elapsed / self.done * (self.total - self.done)


class NullProgress(BaseProgress):
    """Reports nothing; still cancellable."""


class TqdmProgress(BaseProgress):
    """A progress bar on stderr with rate and ETA; messages go above the bar."""

    def __init__(self, token: CancelToken | None = None, stream: IO[str] | None = None) -> None:
        super().__init__(token)
        self._stream = stream or sys.stderr
        self._bar = None

    def begin(self, stage: str, total: int | None, unit: str = "tile") -> None:
        from tqdm import tqdm

        super().begin(stage, total, unit)
        self.end()
        self._bar = tqdm(total=total, desc=stage, unit=unit, file=self._stream, leave=True, dynamic_ncols=True)

    def advance(self, n: int = 1) -> None:
        super().advance(n)
        if self._bar is not None:
            self._bar.update(n)

    def end(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def message(self, text: str) -> None:
        from tqdm import tqdm

        tqdm.write(text, file=self._stream)


class JsonLinesProgress(BaseProgress):
    """One JSON object per line for a driving process (the QGIS task parses these)."""

    def __init__(
        self, token: CancelToken | None = None, stream: IO[str] | None = None, min_interval_s: float = 0.2
    ) -> None:
        super().__init__(token)
        self._stream = stream or sys.stdout
        self._min_interval = min_interval_s
        self._last_emit = 0.0

    def _emit(self, event: ProgressEvent) -> None:
        self._stream.write(encode_event(event) + "\n")
        self._stream.flush()

    def begin(self, stage: str, total: int | None, unit: str = "tile") -> None:
        super().begin(stage, total, unit)
        self._emit(ProgressEvent("begin", stage=stage, total=total, unit=unit))

    def advance(self, n: int = 1) -> None:
        super().advance(n)
        now = time.monotonic()
        if now - self._last_emit >= self._min_interval or self.done == self.total:
            self._last_emit = now
            fraction = self.done / self.total if self.total else None
            eta = self.eta_seconds()
            self._emit(
                ProgressEvent(
                    "progress",
                    stage=self.stage,
                    done=self.done,
                    total=self.total,
                    fraction=fraction,
                    eta_s=None if eta is None else round(eta, 1),
                )
            )

    def end(self) -> None:
        self._emit(ProgressEvent("end", stage=self.stage, done=self.done))

    def message(self, text: str) -> None:
        self._emit(ProgressEvent("message", text=text))


def check_cancelled(progress: Progress | None) -> None:
    """Raise :class:`Cancelled` if the user asked to stop; call between units of work.

    The running output transaction also notes ``progress``, to look at it once more just before
    it commits (:func:`overseec_core.io.transaction.watch`)."""
    if progress is None:
        return
    watch(progress)
    if progress.cancelled():
        raise Cancelled("cancelled by the user; partial outputs were discarded")
