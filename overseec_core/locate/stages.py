"""Stages in threads joined by bounded queues: a :func:`pipeline` of producer stages read ahead of
the caller, a :class:`ThreadStage` consumer behind it, :func:`lookahead` for futures, and a
:class:`StageClock` of the seconds each stage worked. Generic (nothing here knows tiles); the tile
loops of :mod:`.tiling`, :mod:`.refine` and :mod:`.dask` are built on it. A stage's failure is
raised in the caller's thread; a stop from the caller ends every stage.
"""

from __future__ import annotations

import queue
import threading
import time
from collections import deque
from collections.abc import Callable, Generator, Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

from overseec_core.errors import TilingError

T = TypeVar("T")
R = TypeVar("R")


@dataclass
class StageClock:
    """Seconds each stage spent working (not waiting): with stages overlapping, their sum exceeds
    the wall time; the bench prints them as the overlap profile."""

    busy: dict[str, float] = field(default_factory=dict)

    def add(self, stage: str, seconds: float) -> None:
        self.busy[stage] = self.busy.get(stage, 0.0) + seconds


_DONE = object()


class _Failed:
    def __init__(self, exc: BaseException) -> None:
        self.exc = exc


def _put(q: queue.Queue, item: object, stop: threading.Event) -> bool:
    """Put unless the pipeline is stopping; False when it stopped first."""
    while not stop.is_set():
        try:
            q.put(item, timeout=0.1)
            return True
        except queue.Full:
            continue
    return False


def _next_input(source: Iterator[Any], inbox: queue.Queue | None) -> Any:
    """The next item for a stage: from the source iterator (first stage) or its input queue;
    raises queue.Empty after a short wait so the caller can check for a stop."""
    if inbox is None:
        return next(source, _DONE)
    return inbox.get(timeout=0.1)


def _stage_loop(
    name: str,
    fn: Callable[[Any], Any],
    source: Iterator[Any],
    inbox: queue.Queue | None,
    out: queue.Queue,
    stop: threading.Event,
    clock: StageClock | None,
) -> None:
    """One pipeline stage (a thread): apply ``fn`` to each input in order, pass on the end marker
    or the first failure, stop when the pipeline stops."""
    while not stop.is_set():
        try:
            item = _next_input(source, inbox)
        except queue.Empty:
            continue
        if item is _DONE or isinstance(item, _Failed):
            _put(out, item, stop)
            return
        t0 = time.perf_counter()
        try:
            result = fn(item)
        except BaseException as exc:  # handed to the consumer, raised there
            _put(out, _Failed(exc), stop)
            return
        if clock is not None:
            clock.add(name, time.perf_counter() - t0)
        if not _put(out, result, stop):
            return


def pipeline(
    items: Iterable[T],
    stages: Sequence[tuple[str, Callable[[Any], Any], int]],
    clock: StageClock | None = None,
) -> Generator[Any, None, None]:
    """Run each item through ``stages`` (name, function, queue depth), each stage in its own
    thread, yielding the last stage's results in item order.

    A stage's output queue holds at most ``depth`` results, so at most about ``sum(depths)``
    items are in flight whatever the input size: memory is bounded by the queue depths, while
    reading, the model and post-processing overlap (GDAL, numpy and torch release the GIL). The
    first exception of any stage is raised to the consumer; when the consumer stops (an error,
    a cancellation: close the generator), the threads are stopped and joined.
    """
    stop = threading.Event()
    source = iter(items)
    queues: list[queue.Queue] = [queue.Queue(maxsize=max(1, depth)) for _, _, depth in stages]
    threads = [
        threading.Thread(
            target=_stage_loop,
            args=(name, fn, source, queues[k - 1] if k else None, queues[k], stop, clock),
            name=f"tiles-{name}",
            daemon=True,
        )
        for k, (name, fn, _) in enumerate(stages)
    ]
    for t in threads:
        t.start()
    try:
        while True:
            try:
                item = queues[-1].get(timeout=0.1)
            except queue.Empty:
                if not any(t.is_alive() for t in threads) and queues[-1].empty():
                    raise TilingError("tile pipeline stopped without finishing") from None
                continue
            if item is _DONE:
                return
            if isinstance(item, _Failed):
                raise item.exc
            yield item
    finally:
        stop.set()
        for t in threads:
            t.join()


class ThreadStage:
    """Runs ``fn(item)`` on submitted items, in order, in one background thread.

    At most ``depth`` items wait (:meth:`submit` blocks beyond that), so memory stays bounded.
    The first error of ``fn`` is raised at the next :meth:`submit` or at :meth:`close`; after it,
    the remaining items are dropped unprocessed.
    """

    def __init__(self, name: str, fn: Callable[[Any], Any], depth: int = 1, clock: StageClock | None = None) -> None:
        self._name, self._fn, self._clock = name, fn, clock
        self._queue: queue.Queue = queue.Queue(maxsize=max(1, depth))
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._run, name=f"tiles-{name}", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while True:
            item = self._queue.get()
            if item is _DONE:
                return
            if self._error is not None:
                continue  # drain: the error is reported to the caller
            t0 = time.perf_counter()
            try:
                self._fn(item)
            except BaseException as exc:  # reported to the caller
                self._error = exc
            del item
            if self._clock is not None:
                self._clock.add(self._name, time.perf_counter() - t0)

    def _raise(self) -> None:
        if self._error is not None:
            raise self._error

    def submit(self, item: Any) -> None:
        self._raise()
        self._queue.put(item)

    def _stop(self) -> None:
        if self._thread.is_alive():
            self._queue.put(_DONE)
            self._thread.join()

    def close(self) -> None:
        """Wait until every submitted item is processed; raise the first error."""
        self._stop()
        self._raise()

    def __enter__(self) -> ThreadStage:
        return self

    def __exit__(self, *exc: object) -> None:
        if exc[0] is None:
            self.close()
            return
        self._error = self._error or RuntimeError("stopped")  # an error upstream: drop the rest
        self._stop()


def lookahead(items: Iterable[T], start: Callable[[T], R], depth: int) -> Iterator[R]:
    """``start(item)`` for up to ``depth`` items ahead, yielding what it returned in order.

    With Dask, ``start`` submits a task and returns its future, so ``depth`` groups of tiles are
    computed at once while the caller waits for the oldest; with ``depth=1`` it is a plain loop.
    """
    pending: deque[R] = deque()
    for item in items:
        pending.append(start(item))
        if len(pending) >= depth:
            yield pending.popleft()
    while pending:
        yield pending.popleft()
