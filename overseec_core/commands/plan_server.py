"""`overseec plan-server`: the planner worker the QGIS plugin talks to (JSON lines on stdin/stdout).

One request per line in, one answer per line out; see :mod:`overseec_core.plan.server` for the
protocol. It stops at end of input or on a ``shutdown`` request, and at once on SIGTERM/SIGINT
(a driving process that goes away closes its end of the pipe, which also ends the worker).
"""

from __future__ import annotations

import argparse
import signal

from overseec_core.progress import Progress


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `plan-server` subcommand (no options)."""
    p = sub.add_parser(
        "plan-server",
        help="planner worker for the QGIS plugin: JSON-lines requests on stdin, answers on stdout",
        description=__doc__,
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `plan-server` (plan.server.main): answer JSON-lines plan requests from stdin on stdout
    until stdin closes; SIGINT and SIGTERM stop it at once, since it blocks reading stdin."""
    from overseec_core.plan.server import main

    for sig in (signal.SIGINT, signal.SIGTERM):
        try:  # a worker blocked reading stdin must stop when told to, not wait for a token check
            signal.signal(sig, signal.SIG_DFL)
        except ValueError:  # not the main thread (tests call the CLI from threads)
            pass
    return main()
