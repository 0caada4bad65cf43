"""All-or-nothing output of a multi-file job: a cancelled or failed run leaves the folder as it was.

Each output is already written atomically (:mod:`overseec_core.atomic`): a file is either the old
one or the complete new one. A job that writes several files can still stop between two of them
— the user pressed Ctrl-C after the costmap was replaced but before the path — and leave a folder
whose costmap no longer matches its path and manifest. Inside :func:`output_transaction`, every
file about to be replaced is first kept under a hidden backup name (a hard link: no copy, no
extra space), and every new file is noted; on success the backups are deleted, on any exception
the earlier files are put back and the new ones removed.

One transaction per process at a time (the CLI runs one command; the QGIS plugin runs commands
in worker processes), shared by all threads, since writers may publish from worker threads.
"""

from __future__ import annotations

import os
import shutil
import threading
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

_lock = threading.Lock()
_active: OutputTransaction | None = None


class OutputTransaction:
    """The files a job replaced (with their backups) and created, to keep or undo together."""

    def __init__(self) -> None:
        #: (final path, backup of its earlier version or None when it is new), in order.
        self._replaced: list[tuple[Path, Path | None]] = []
        self._seen: set[Path] = set()

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


@contextmanager
def output_transaction() -> Iterator[OutputTransaction]:
    """Run the block's writes as one: all kept on success, all undone on any exception.

    Nested use joins the outer transaction (the outermost one decides).
    """
    global _active
    with _lock:
        outer = _active
        tx = outer if outer is not None else OutputTransaction()
        _active = tx
    if outer is not None:
        yield tx
        return
    try:
        yield tx
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


__all__ = ["OutputTransaction", "before_replace", "output_transaction"]
