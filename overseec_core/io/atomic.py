"""Atomic file output: write beside the target under a hidden temporary name, then rename.

A cancelled or failed job never leaves a truncated file under the final name, and readers
(QGIS, a planner polling the folder) never see half a file. The temporary file is flushed to
the disk (``fsync``) before the rename, so a write error the kernel reports late (delayed
allocation, network file systems) still stops the rename, and a crash right after it cannot
leave an empty file under the final name.

A full disk, a quota or a file size limit (ENOSPC, EDQUOT, EFBIG) anywhere in a write is one
:class:`~overseec_core.errors.OutputError` naming the final path, e.g.
``cannot write out/costmap.tif: no space left on device``; see :func:`output_error`.
"""

from __future__ import annotations

import errno
import os
import tempfile
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

from overseec_core.errors import OutputError, OverseecError
from overseec_core.io.transaction import before_replace

try:
    import resource
except ImportError:  # not on Windows; there is no RLIMIT_FSIZE to run into
    resource = None  # type: ignore[assignment]

#: What a write failure with each of these errno values tells the user.
SPACE_ERRNOS: dict[int, str] = {
    errno.ENOSPC: "no space left on device",
    errno.EDQUOT: "disk quota exceeded",
    errno.EFBIG: "file too large for the file system or this process's file size limit",
}
#: Texts libraries print for those errors instead of raising them (GDAL and libtiff print
#: strerror(); SQLite, under GeoPackage writes, says SQLITE_FULL's message).
_SPACE_TEXTS: tuple[tuple[str, str], ...] = tuple(
    (os.strerror(code).lower(), reason) for code, reason in SPACE_ERRNOS.items()
) + (("database or disk is full", SPACE_ERRNOS[errno.ENOSPC]),)
#: A write that failed for an unstated reason while the folder had less than this free is
#: reported as a full disk (GDAL sometimes reports only the consequence, e.g. a bad directory).
NEARLY_FULL_BYTES = 1 << 20


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def space_reason(exc: BaseException | None = None, messages: Iterable[str] = ()) -> str | None:
    """The space problem an exception (or its cause chain) or a library's messages describe.

    Returns e.g. "no space left on device", or None when neither mentions ENOSPC, EDQUOT or
    EFBIG. GDAL and SQLite report these as text, not as an errno, hence the messages.
    """
    seen: set[int] = set()
    while exc is not None and id(exc) not in seen:
        seen.add(id(exc))
        if isinstance(exc, OSError) and exc.errno in SPACE_ERRNOS:
            return SPACE_ERRNOS[exc.errno]
        messages = [*messages, str(exc)]
        exc = exc.__cause__ or exc.__context__
    for text in messages:
        low = text.lower()
        for needle, reason in _SPACE_TEXTS:
            if needle in low:
                return reason
    return None


def _free_bytes(folder: Path) -> int | None:
    """Bytes an unprivileged writer may still use in ``folder``'s file system, or None."""
    try:
        st = os.statvfs(folder)
    except OSError:
        return None
    return st.f_bavail * st.f_frsize


def _size_limited(tmp: Path | None) -> bool:
    """True when ``tmp`` has grown to this process's RLIMIT_FSIZE (writes past it fail EFBIG)."""
    if resource is None or tmp is None:
        return False
    soft, _ = resource.getrlimit(resource.RLIMIT_FSIZE)
    if soft == resource.RLIM_INFINITY:
        return False
    try:
        return tmp.stat().st_size + NEARLY_FULL_BYTES >= soft
    except OSError:
        return False


def diagnose(
    path: str | os.PathLike,
    exc: BaseException | None = None,
    messages: Iterable[str] = (),
    tmp: str | os.PathLike | None = None,
) -> str | None:
    """Why a write to ``path`` failed, when the cause is space: stated, else inferred.

    Stated: an errno or message (:func:`space_reason`). Inferred (call this before deleting the
    temporary file ``tmp``): the folder is all but full, or ``tmp`` reached the file size limit.
    """
    messages = list(messages)
    reason = space_reason(exc, messages)
    if reason is not None:
        return reason
    tmp_path = Path(tmp) if tmp is not None else None
    if _size_limited(tmp_path):
        return SPACE_ERRNOS[errno.EFBIG]
    free = _free_bytes(Path(path).parent if str(Path(path).parent) else Path("."))
    if free is not None and free < NEARLY_FULL_BYTES:
        return SPACE_ERRNOS[errno.ENOSPC]
    return None


def output_error(
    path: str | os.PathLike,
    exc: BaseException | None = None,
    messages: Iterable[str] = (),
    tmp: str | os.PathLike | None = None,
) -> OutputError:
    """One-line OutputError for a failed write of ``path``: the space reason, else the error's own.

    ``cannot write PATH: no space left on device`` for ENOSPC (EDQUOT, EFBIG alike, stated or
    inferred by :func:`diagnose`); otherwise ``cannot write PATH: <first message or error>``.
    """
    messages = list(messages)
    reason = diagnose(path, exc, messages, tmp)
    if reason is None:
        if isinstance(exc, OSError) and exc.strerror:
            reason = exc.strerror[:1].lower() + exc.strerror[1:]
        else:
            text = messages[0] if messages else (str(exc) if exc is not None else "")
            reason = " ".join(text.split())[:200] or (type(exc).__name__ if exc else "unknown error")
    return OutputError(f"cannot write {path}: {reason}")


def fsync_file(path: str | os.PathLike) -> None:
    """Flush a closed file's data to the disk; raises OSError (e.g. ENOSPC, EIO) if that fails."""
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _fsync_folder(folder: Path) -> None:
    """Best effort: make a rename in ``folder`` durable (some file systems refuse; that is fine)."""
    try:
        fd = os.open(folder, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def temp_beside(path: str | os.PathLike, suffix: str = ".partial") -> Path:
    """Create an empty hidden temporary file in the target's folder and return its path."""
    path = Path(path)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix, dir=path.parent)
    except OSError as exc:
        raise output_error(path, exc) from None
    os.close(fd)
    return Path(tmp)


def publish(tmp: str | os.PathLike, path: str | os.PathLike) -> Path:
    """Flush a finished temporary file to the disk, give it normal permissions, rename it over
    ``path`` and make the rename durable. A failed flush (ENOSPC, EIO) raises OSError before
    anything is renamed; the caller deletes ``tmp``."""
    fsync_file(tmp)
    os.chmod(tmp, 0o666 & ~_umask())
    before_replace(path)  # inside an output transaction, the earlier file is kept until commit
    os.replace(tmp, path)
    parent = Path(path).parent
    _fsync_folder(parent if str(parent) else Path("."))
    return Path(path)


def discard(tmp: str | os.PathLike, sidecars: Iterable[str] = ()) -> None:
    """Delete a temporary file and the sidecars libraries leave beside it (``tmp + suffix``)."""
    tmp = Path(tmp)
    for p in (tmp, *(tmp.with_name(tmp.name + s) for s in sidecars)):
        try:
            p.unlink(missing_ok=True)
        except OSError:
            pass


@contextmanager
def atomic_path(path: str | os.PathLike, suffix: str = ".partial", sidecars: Iterable[str] = ()) -> Iterator[Path]:
    """Yield a temporary path to write; publish it on success, delete it on any error.

    An OSError while writing or publishing (not an OverseecError, which already says what went
    wrong) becomes one :func:`output_error` line naming ``path``. ``sidecars`` are suffixes of
    files a library may create beside the temporary one (SQLite's ``-journal``); they are
    deleted with it.
    """
    tmp = temp_beside(path, suffix)
    try:
        yield tmp
        publish(tmp, path)
    except OverseecError:
        discard(tmp, sidecars)
        raise
    except OSError as exc:
        err = output_error(path, exc, tmp=tmp)
        discard(tmp, sidecars)
        raise err from None
    except BaseException:
        discard(tmp, sidecars)
        raise


def write_text_atomic(path: str | os.PathLike, text: str) -> Path:
    """Write a text file atomically (UTF-8), flushed to the disk before the rename.

    A full disk (or quota, or file size limit) is an OutputError naming ``path``; the old file,
    if any, is untouched and no temporary file is left.
    """
    data = text.encode("utf-8")
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as f:  # close() flushes; publish() fsyncs before the rename
            f.write(data)
    return Path(path)
