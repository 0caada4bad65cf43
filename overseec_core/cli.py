"""The `overseec` command line.

Subcommands live in :mod:`overseec_core.commands`, one module per command, each with
``register(subparsers)`` and ``run(args, progress) -> int``. This module only adds the global
options, builds the progress reporter (bar, JSON lines or nothing), installs cancellation on
SIGINT/SIGTERM, and turns errors into one line and an exit status:

    0 success · 1 unexpected failure (a bug: traceback shown) · 2 user or input error · 130 cancelled

Library messages (GDAL, PROJ, Python warnings) go to a log file, not the terminal, unless
``--verbose``: a user sees overseec's one line, not the drivers' chatter behind it.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import logging.handlers
import os
import signal
import sys
import traceback
from collections.abc import Sequence
from pathlib import Path
from types import FrameType, ModuleType
from typing import Any

from overseec_core import __version__
from overseec_core.errors import Cancelled, OverseecError
from overseec_core.limits import ENV_MAX_PIXELS, parse_pixel_count
from overseec_core.progress import CancelToken, JsonLinesProgress, NullProgress, Progress, TqdmProgress

#: Command modules, in the order `overseec --help` lists them.
COMMANDS = (
    "info",
    "interpret",
    "segment",
    "vectorize",
    "costmap",
    "plan",
    "corridor",
    "plan_server",
    "sam_server",
    "export",
    "eval",
    "compare",
    "run",
    "demo",
    "sample",
    "models",
    "doctor",
)

EXIT_OK, EXIT_BUG, EXIT_USER, EXIT_CANCELLED = 0, 1, 2, 130


def _command_modules() -> list[ModuleType]:
    """Import the command modules that exist (stages land one by one)."""
    modules = []
    for name in COMMANDS:
        qualified = f"{__package__}.commands.{name}"
        try:
            modules.append(importlib.import_module(qualified))
        except ModuleNotFoundError as exc:
            if exc.name != qualified:
                raise
    return modules


#: The global options' destinations (accepted before or after the command).
GLOBAL_OPTIONS = ("quiet", "json_progress", "verbose", "cog", "max_pixels")


def add_global_options(parser: argparse.ArgumentParser, *, after_command: bool = False) -> None:
    """-q, --json-progress, -v, --cog and --max-pixels, on the main parser and again on every
    command's parser (``after_command``), so that ``overseec plan ... -q`` works as ``overseec
    -q plan ...`` does. There they default to argparse.SUPPRESS: given after the command, an
    option sets its value; not given, it leaves the value from before the command alone."""
    default: dict[str, Any] = {"default": argparse.SUPPRESS} if after_command else {}
    where = parser.add_argument_group("global options (also accepted before the command)") if after_command else parser
    output = where.add_mutually_exclusive_group()
    output.add_argument("-q", "--quiet", action="store_true", help="no progress bars or messages", **default)
    output.add_argument(
        "--json-progress",
        action="store_true",
        help="print progress as JSON lines on stdout, and a --json document as one line (for a driving process)",
        **default,
    )
    where.add_argument("-v", "--verbose", action="store_true", help="show tracebacks for errors", **default)
    where.add_argument(
        "--cog",
        action="store_true",
        help="write rasters in Cloud-Optimized GeoTIFF layout (a full rewrite; slower)",
        **default,
    )
    where.add_argument(
        "--max-pixels",
        metavar="N",
        help=f"largest raster (width x height) a stage works on; default 2e9, or {ENV_MAX_PIXELS}",
        **default,
    )


def _command_parsers(parser: argparse.ArgumentParser) -> list[argparse.ArgumentParser]:
    """Every parser below ``parser`` (commands, and sub-commands such as `export costmap`)."""
    found: list[argparse.ArgumentParser] = []
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for child in dict.fromkeys(action.choices.values()):  # aliases share a parser
                found += [child, *_command_parsers(child)]
    return found


def build_parser() -> argparse.ArgumentParser:
    """The `overseec` parser: global options, then one subcommand per command module (each adds
    its own), and the global options again after the command."""
    parser = argparse.ArgumentParser(
        prog="overseec", description="Costmaps and routes from aerial imagery and a mission prompt (OVerSeeC)."
    )
    parser.add_argument("--version", action="version", version=f"overseec {__version__}")
    add_global_options(parser)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for module in _command_modules():
        module.register(sub)
    for child in _command_parsers(parser):
        add_global_options(child, after_command=True)
    return parser


def make_progress(args: argparse.Namespace, token: CancelToken) -> Progress:
    """The progress reporter the options ask for: JSON lines (--json-progress), none (-q) or tqdm bars."""
    if args.json_progress:
        return JsonLinesProgress(token)
    if args.quiet:
        return NullProgress(token)
    return TqdmProgress(token)


def _install_cancel_handlers(token: CancelToken) -> None:
    """SIGINT/SIGTERM ask the running stage to stop cleanly; asking again changes nothing.

    Long operations check the token at least once a second, so the stop is prompt; a second
    Ctrl-C raising KeyboardInterrupt instead would interrupt the clean-up itself and leave
    partial files behind. (SIGKILL remains for a process that is truly stuck.)
    """

    def handler(signum: int, frame: FrameType | None) -> None:
        token.cancel()

    for sig in (signal.SIGINT, signal.SIGTERM):
        try:
            signal.signal(sig, handler)
        except ValueError:  # not the main thread (tests call main() from threads)
            pass


def _say(message: str) -> None:
    print(f"overseec: error: {message}", file=sys.stderr)


ENV_LOG = "OVERSEEC_LOG"


def log_path() -> Path:
    """Where library messages go: ``OVERSEEC_LOG``, else ``~/.cache/overseec/overseec.log``."""
    explicit = os.environ.get(ENV_LOG, "").strip()
    if explicit:
        return Path(explicit)
    cache = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return cache / "overseec" / "overseec.log"


def configure_logging(verbose: bool) -> None:
    """Library messages (rasterio's GDAL errors, pyproj, Python warnings) to the log file, or
    to stderr with ``--verbose``; never both, and never a failure because the log is unwritable."""
    root = logging.getLogger()
    for old in list(root.handlers):
        if getattr(old, "_overseec", False):
            root.removeHandler(old)
            old.close()
    handler: logging.Handler
    if verbose:
        handler = logging.StreamHandler(sys.stderr)
    else:
        try:
            path = log_path()
            path.parent.mkdir(parents=True, exist_ok=True)
            handler = logging.handlers.RotatingFileHandler(
                path, maxBytes=1 << 20, backupCount=2, encoding="utf-8", delay=True
            )
        except OSError:
            handler = logging.NullHandler()
    handler.setFormatter(logging.Formatter("%(asctime)s %(process)d %(name)s %(levelname)s: %(message)s"))
    handler._overseec = True  # type: ignore[union-attr]  # our marker; no stdlib handler declares it
    root.addHandler(handler)
    root.setLevel(logging.INFO if verbose else logging.WARNING)
    logging.captureWarnings(True)


#: GDAL's block cache defaults to 5% of RAM; streaming needs little, and RSS must stay bounded.
GDAL_CACHE_MB = "256"


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point: parse ``argv``, run the command (Ctrl-C cancels it) and return the exit status;
    a failure is one line on stderr, with a traceback only for a bug or with --verbose."""
    os.environ.setdefault("GDAL_CACHEMAX", GDAL_CACHE_MB)
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.quiet and args.json_progress:  # one before the command, the other after it
        parser.error("argument --json-progress: not allowed with argument -q/--quiet")
    if args.cog:
        os.environ["OVERSEEC_COG"] = "1"
    token = CancelToken()
    _install_cancel_handlers(token)
    configure_logging(args.verbose)
    progress = make_progress(args, token)
    try:
        if args.max_pixels is not None:
            os.environ[ENV_MAX_PIXELS] = str(parse_pixel_count(args.max_pixels))
        return _run_command(args, progress)
    except (Cancelled, KeyboardInterrupt) as exc:
        _say(str(exc) if isinstance(exc, Cancelled) else "interrupted")
        return EXIT_CANCELLED
    except Exception as exc:
        return _report(exc, args)
    finally:
        progress.end() if isinstance(progress, TqdmProgress) else None


def _report(exc: Exception, args: argparse.Namespace) -> int:
    """One line on stderr for a failed command, and its exit status; a traceback too for a bug
    (or with --verbose)."""
    extra = _extra_for(exc)
    bug = not isinstance(exc, (OverseecError, OSError)) and extra is None
    if bug or args.verbose:
        traceback.print_exc()
    if bug:
        _say("unexpected failure (a bug in overseec); please report it with the traceback above")
        return EXIT_BUG
    if extra is not None:  # an optional dependency the command needs is not installed
        name = getattr(exc, "name", None)
        _say(f'`{args.command}` needs {name}, which is not installed: pip install "overseec[{extra}]"')
    elif isinstance(exc, OverseecError):
        _say(str(exc))
    else:
        assert isinstance(exc, OSError)
        where = f": {exc.filename}" if exc.filename else ""
        _say(f"{exc.strerror or exc}{where}")
    return EXIT_USER


def _extra_for(exc: BaseException) -> str | None:
    """The pip extra whose module a ModuleNotFoundError says is missing (torch -> "models")."""
    if not isinstance(exc, ModuleNotFoundError):
        return None
    from overseec_core.extras import extra_for

    return extra_for(exc.name)


def _run_command(args: argparse.Namespace, progress: Progress) -> int:
    """The command inside one GDAL environment, so that every GDAL message goes through
    rasterio's handler to the log (outside an environment GDAL prints to stderr itself)."""
    import rasterio

    with rasterio.Env():
        return int(args.func(args, progress) or 0)


if __name__ == "__main__":
    sys.exit(main())
