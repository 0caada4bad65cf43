"""What the plugin's JSON-lines worker clients share: the session's client and its command line.

The planner client (:mod:`overseec_qgis.planclient`) and the SAM client
(:mod:`overseec_qgis.samclient`) each keep one worker process per QGIS session, talked to over
JSON lines; the SAM client sends its requests through a planner-client transport, so the process
handling itself is already one piece of code. What both modules spelled out again is here:

* :class:`SessionClient`: the session's one client of a kind, made by the first request (so a
  changed setting is read then) and closed on plugin unload; a later request makes a new one.
* :func:`require_worker`: the configured overseec environment's ``overseec``, or the client's own
  one-line error saying where to set the environment up.

Plain Python, no Qt.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from pathlib import Path
from typing import Generic, Protocol, TypeVar

from .worker import configured_worker


class Closable(Protocol):
    """A client whose worker can be stopped."""

    def close(self) -> None:
        """Stop the client's worker."""


C = TypeVar("C", bound=Closable)


class SessionClient(Generic[C]):
    """The one client of this QGIS session, made on first use by ``make``; thread-safe."""

    def __init__(self, make: Callable[[], C]) -> None:
        self._make = make
        self._client: C | None = None
        self._lock = threading.Lock()

    def get(self) -> C:
        """The session's client (made now if there is none; its worker starts with a request)."""
        with self._lock:
            if self._client is None:
                self._client = self._make()
            return self._client

    def close(self) -> None:
        """Stop the session's worker (plugin unload); a later :meth:`get` makes a new client."""
        with self._lock:
            client, self._client = self._client, None
        if client is not None:
            client.close()


def require_worker(missing: Callable[[str], Exception], purpose: str) -> Path:
    """The configured overseec environment's ``overseec`` (the plugin settings); when there is
    none, raises ``missing(message)``, the message saying where to set one up ("no overseec
    environment found to <purpose>: ...")."""
    worker = configured_worker()
    if worker is None:
        raise missing(
            f"no overseec environment found to {purpose}: set it up from the overseec panel "
            "(Set up environment), or set it under Settings › Options › overseec, or set OVERSEEC_VENV"
        )
    return worker
