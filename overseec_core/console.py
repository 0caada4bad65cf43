"""The `overseec` console script: guards Ctrl-C from the first instant, then runs the CLI.

Importing the CLI (numpy, rasterio, the command modules) takes a moment; a Ctrl-C in that moment
would print a long KeyboardInterrupt traceback. This module imports nothing heavy, installs a
handler that exits quietly (nothing has been written yet), and only then imports the CLI, whose
``main`` replaces the handler with the cancel token. A server command (``plan-server``,
``sam-server``) also starts its start-up lines here (:mod:`overseec_core.liveness`), so a client
sees it alive while the imports run. Library users importing
:mod:`overseec_core.cli` keep their own signal handling.
"""

from __future__ import annotations

import os
import signal
import sys
from types import FrameType


def _exit_interrupted(signum: int, frame: FrameType | None) -> None:
    """Ctrl-C before any work started (imports, argument parsing): nothing to clean up."""
    sys.stderr.write("overseec: error: interrupted\n")
    sys.stderr.flush()
    os._exit(130)


def main() -> int:
    """Console-script entry point: run the CLI with Ctrl-C and SIGTERM exiting cleanly, and ignore
    them once the command has finished so a late signal cannot change the exit status."""
    signal.signal(signal.SIGINT, _exit_interrupted)
    signal.signal(signal.SIGTERM, _exit_interrupted)
    from overseec_core import liveness

    liveness.start(sys.argv)  # a server says it is alive while the imports below run
    from overseec_core.cli import main as cli_main

    try:
        return cli_main()
    finally:
        # the command has finished or cleaned up after a cancel: a late Ctrl-C must not kill
        # the interpreter while it shuts down (exit status -2 instead of the one we return)
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        signal.signal(signal.SIGTERM, signal.SIG_IGN)


if __name__ == "__main__":
    sys.exit(main())
