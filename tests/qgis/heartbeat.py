"""A GUI-thread heartbeat: how long the Qt event loop was blocked while an action ran.

A 10 ms :class:`QTimer` ticks on the GUI thread; each tick records the gap since the previous
one. Whatever keeps the GUI thread busy (a synchronous worker call in a click handler, a costmap
read) delays the next tick, so the largest gap is the longest time QGIS could not repaint or
react. The rule of the issue: no action blocks the GUI thread for more than
:data:`MAX_BLOCK_MS`.

On a machine shared with other work a gap also holds the time the GUI thread was ready to run but
waited for a CPU (Linux counts it per thread in ``/proc/thread-self/schedstat``); that is the
machine's load, not the action's doing. :attr:`Heartbeat.longest_ms` is the plain largest gap;
:attr:`Heartbeat.blocked_ms` the largest gap less that wait -- the time the GUI thread ran or was
blocked (computing, or waiting for a lock, a pipe, a file) -- which is what the rule is about.
Both are recorded; the tests hold ``blocked_ms`` to the rule (equal to ``longest_ms`` where the
kernel does not count the wait).

Use it around an action, processing events the whole time (the action's own handler runs inside
the measured span)::

    with Heartbeat() as beat:
        pump(0.05)
        QTest.mouseClick(...)
        wait_for(lambda: done, 30)
    assert beat.blocked_ms <= MAX_BLOCK_MS

Self-contained (Qt and the standard library only): the desktop tests paste this file's text into
the script they give QGIS with ``--code``.
"""

from __future__ import annotations

import time

from qgis.PyQt.QtCore import QCoreApplication, QEventLoop, QTimer

#: The longest the GUI thread may be blocked by one action (ms).
MAX_BLOCK_MS = 100.0
#: The heartbeat's period (ms).
TICK_MS = 10


def cpu_wait_s() -> float:
    """Seconds this thread has waited for a CPU while ready to run (0 where Linux does not say)."""
    try:
        with open("/proc/thread-self/schedstat") as f:
            return int(f.read().split()[1]) / 1e9
    except (OSError, ValueError, IndexError):
        return 0.0


class Heartbeat:
    """Records the longest gap between ticks of a 10 ms timer on the GUI thread (ms), as is
    (:attr:`longest_ms`) and less the time the thread waited for a CPU (:attr:`blocked_ms`)."""

    def __init__(self, tick_ms: int = TICK_MS) -> None:
        self.timer = QTimer()
        self.timer.setInterval(tick_ms)
        self.timer.timeout.connect(self._tick)
        self.longest_ms = 0.0
        self.blocked_ms = 0.0
        self.ticks = 0
        self._last = 0.0
        self._last_wait = 0.0

    def start(self) -> Heartbeat:
        """Start measuring (forgets an earlier measurement)."""
        self.longest_ms, self.blocked_ms, self.ticks = 0.0, 0.0, 0
        self._last, self._last_wait = time.monotonic(), cpu_wait_s()
        self.timer.start()
        return self

    def stop(self) -> float:
        """Stop measuring; the gap up to now counts too. Returns :attr:`blocked_ms`."""
        self._tick()
        self.timer.stop()
        return self.blocked_ms

    def _tick(self) -> None:
        now, wait = time.monotonic(), cpu_wait_s()
        gap = 1000.0 * (now - self._last)
        self.longest_ms = max(self.longest_ms, gap)
        self.blocked_ms = max(self.blocked_ms, gap - 1000.0 * (wait - self._last_wait))
        self._last, self._last_wait = now, wait
        self.ticks += 1

    def __enter__(self) -> Heartbeat:
        return self.start()

    def __exit__(self, *_exc) -> None:
        self.stop()


def pump(seconds: float) -> None:
    """Process Qt events for a while (the heartbeat ticks only while events are processed)."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        QCoreApplication.processEvents(QEventLoop.AllEvents, 5)
        time.sleep(0.001)


def wait_for(predicate, timeout_s: float = 60.0) -> bool:
    """Process Qt events until ``predicate()`` is true; False if it stayed false for ``timeout_s``."""
    end = time.monotonic() + timeout_s
    while not predicate():
        if time.monotonic() > end:
            return False
        pump(0.005)
    return True
