"""Signs of life from a worker while it starts: one JSON line on stdout every half second.

The QGIS plugin talks to its workers (``overseec plan-server``, ``overseec sam-server``) over
stdin/stdout and gives every request a timeout. The first request also waits for the worker's
start-up -- Python, numpy, rasterio, torch imports -- which takes 1 s on an idle machine and
tens of seconds on a loaded one, so a fixed wall clock either kills healthy workers or waits
forever for a hung one. Instead, from the first instant of the process (before any heavy import)
a daemon thread writes a *start-up line* to the protocol stream::

    {"event": "starting", "modules": 412}

``modules`` is how many modules the process has imported so far: it grows while the imports
advance. The client (:mod:`overseec_qgis.planclient`) counts a request's timeout from the last
line whose count grew, so a worker that is still importing is alive and one stuck in an import
is not. The thread stops (:func:`stop`) when the server takes over the stream
(``protocol_stdout``), before the first answer is written; clients that do not know these lines
skip them (they carry no ``id``).

Imports the standard library only: :mod:`overseec_core.console` starts it before the CLI.
"""

from __future__ import annotations

import json
import os
import sys
import threading

#: The commands that serve a line protocol on stdout (``overseec <command>``).
SERVER_COMMANDS = ("plan-server", "sam-server")
#: Seconds between two start-up lines.
INTERVAL_S = 0.5
#: The ``event`` value of a start-up line.
STARTING = "starting"

_stop = threading.Event()
_thread: threading.Thread | None = None


def starting_line(modules: int) -> str:
    """One start-up line (newline included)."""
    return json.dumps({"event": STARTING, "modules": int(modules)}) + "\n"


def _beat(fd: int) -> None:
    while True:
        try:
            os.write(fd, starting_line(len(sys.modules)).encode("ascii"))
        except OSError:
            return  # the reader went away: nothing to tell
        if _stop.wait(INTERVAL_S):
            return


def start(argv: list[str]) -> bool:
    """Start the start-up lines when ``argv`` (``sys.argv``) runs a server command; True if started."""
    global _thread
    command = next((a for a in argv[1:] if not a.startswith("-")), None)  # past "-q", "-v"
    if _thread is not None or command not in SERVER_COMMANDS:
        return False
    _stop.clear()
    _thread = threading.Thread(target=_beat, args=(1,), name="overseec-starting", daemon=True)
    _thread.start()
    return True


def stop() -> None:
    """Stop the start-up lines and wait until the last one is written (no-op when not started)."""
    global _thread
    thread, _thread = _thread, None
    if thread is not None:
        _stop.set()
        thread.join()
