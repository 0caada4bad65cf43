"""All-or-nothing output of a multi-file job: a cancelled or failed run leaves the folder as it was.

Each output is already written atomically (:mod:`overseec_core.io.atomic`): a file is either the old
one or the complete new one. A job that writes several files can still stop between two of them
— the user pressed Ctrl-C after the costmap was replaced but before the path — and leave a folder
whose costmap no longer matches its path and manifest. Inside :func:`output_transaction`, every
file about to be replaced is first kept under a hidden backup name (a hard link: no copy, no
extra space), and every new file is noted; on success the backups are deleted, on any exception
the earlier files are put back and the new ones removed.

A cancel counts up to the commit: the transaction watches every progress object the job polled
for a cancel (:func:`watch`, called by :func:`~overseec_core.progress.check_cancelled`, or the
``progress`` given to :func:`output_transaction`), and looks at them once more after the block's
last write, immediately before committing. A Ctrl-C that arrived during the last renames or the
manifest write therefore still undoes the whole job (:class:`~overseec_core.errors.Cancelled`,
exit status 130), and the commit itself -- dropping the backups -- is the only step after that
look. Test hook: with ``OVERSEEC_TEST_PAUSE_BEFORE_COMMIT`` set to a number of seconds, the
outermost transaction writes ``overseec: test hook: committing`` to stderr and sleeps that long
just before that look, so a test can send its signal at the latest moment.

One transaction per process at a time (the CLI runs one command; the QGIS plugin runs commands
in worker processes), shared by all threads, since writers may publish from worker threads.
"""

from __future__ import annotations

import functools
import inspect
import os
import shutil
import sys
import threading
import time
import uuid
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Protocol, TypeVar

from overseec_core.errors import Cancelled

T = TypeVar("T")

#: Seconds the outermost transaction sleeps just before its last cancel check (tests only).
ENV_PAUSE_BEFORE_COMMIT = "OVERSEEC_TEST_PAUSE_BEFORE_COMMIT"


class _Cancellable(Protocol):
    def cancelled(self) -> bool: ...


_lock = threading.Lock()
_active: OutputTransaction | None = None


class OutputTransaction:
    """The files a job replaced (with their backups) and created, to keep or undo together."""

    def __init__(self) -> None:
        #: (final path, backup of its earlier version or None when it is new), in order.
        self._replaced: list[tuple[Path, Path | None]] = []
        self._seen: set[Path] = set()
        #: The progress objects (cancel tokens) the job polled: one set means a cancel.
        self._watched: list[_Cancellable] = []

    def watch(self, progress: _Cancellable) -> None:
        """Look at this progress object's cancel flag before committing."""
        if not any(p is progress for p in self._watched):
            self._watched.append(progress)

    def cancel_requested(self) -> bool:
        """Whether any watched progress object was cancelled."""
        return any(p.cancelled() for p in self._watched)

    def before_replace(self, path: str | os.PathLike) -> None:
        """Keep the current version of ``path`` (once per path) before it is replaced."""
        target = Path(os.path.abspath(path))
        if target in self._seen:
            return
        self._seen.add(target)
        backup = None
        if target.is_file():
            backup = target.with_name(f".{target.name}.{uuid.uuid4().hex[:8]}.backup")
            try:
                os.link(target, backup)
            except OSError:  # no hard links on this file system (FAT, some network shares)
                shutil.copy2(target, backup)
        self._replaced.append((target, backup))

    def commit(self) -> None:
        """Keep the new files: drop the backups."""
        for _, backup in self._replaced:
            if backup is not None:
                backup.unlink(missing_ok=True)
        self._replaced.clear()

    def rollback(self) -> None:
        """Put every earlier file back and remove the files the job created, newest first."""
        for target, backup in reversed(self._replaced):
            if backup is not None:
                os.replace(backup, target)
            else:
                target.unlink(missing_ok=True)
        self._replaced.clear()


def before_replace(path: str | os.PathLike) -> None:
    """Called by every atomic writer just before it renames a finished file over ``path``."""
    with _lock:
        if _active is not None:
            _active.before_replace(path)


def watch(progress: Any) -> None:
    """Have the running transaction (if any) check ``progress`` for a cancel before it commits."""
    if progress is None or not callable(getattr(progress, "cancelled", None)):
        return
    with _lock:
        if _active is not None:
            _active.watch(progress)


def _test_pause() -> None:
    try:
        seconds = float(os.environ.get(ENV_PAUSE_BEFORE_COMMIT, "") or 0)
    except ValueError:
        return
    if seconds > 0:
        sys.stderr.write("overseec: test hook: committing\n")
        sys.stderr.flush()
        time.sleep(seconds)


@contextmanager
def output_transaction(progress: Any = None) -> Iterator[OutputTransaction]:
    """Run the block's writes as one: all kept on success, all undone on any exception or on
    a cancel of ``progress`` (or of any progress the job polled) that arrives before the commit.

    Nested use joins the outer transaction (the outermost one decides).
    """
    global _active
    with _lock:
        outer = _active
        tx = outer if outer is not None else OutputTransaction()
        _active = tx
        if progress is not None:
            tx.watch(progress)
    if outer is not None:
        yield tx
        return
    try:
        yield tx
        _test_pause()
        with _lock:
            if tx.cancel_requested():  # the last look: a cancel up to here undoes the job
                raise Cancelled("cancelled by the user; partial outputs were discarded")
    except BaseException:
        with _lock:
            tx.rollback()
        raise
    else:
        with _lock:
            tx.commit()
    finally:
        with _lock:
            _active = None


__all__ = ["OutputTransaction", "before_replace", "output_transaction", "watch"]


def transactional(stage: Callable[..., T]) -> Callable[..., T]:
    """Run a stage's writes as one transaction (:mod:`overseec_core.io.transaction`): cancelled or
    failed, it leaves its folder as it was, not with a new lethal.tif beside an old costmap.

    The stage's own ``progress`` argument (when it takes one) is watched by the transaction, so
    a cancel is honoured up to the commit even where the stage's work polls its progress object
    directly (a planner search, a writer) rather than through ``check_cancelled``: Ctrl-C while
    `corridor` writes its last raster undoes the run, as it does for `costmap`."""
    signature = inspect.signature(stage)

    @functools.wraps(stage)
    def run(*args: Any, **kwargs: Any) -> T:
        progress = None
        if "progress" in signature.parameters:
            try:
                progress = signature.bind_partial(*args, **kwargs).arguments.get("progress")
            except TypeError:  # the call itself is wrong: let the stage say so
                progress = None
        with output_transaction(progress):
            return stage(*args, **kwargs)

    return run
