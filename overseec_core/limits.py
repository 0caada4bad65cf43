"""Size limits on what a command accepts, checked before any work starts.

A raster of two million pixels a side is a valid GeoTIFF (or VRT) and streams fine, for twenty
hours; a prompt or program "file" can be ``/dev/zero``. Neither is what a user meant, and both
should be refused in one line, up front, with the number that would let them go on:

- a **pixel budget** per raster a stage works on (default :data:`DEFAULT_MAX_PIXELS`, the
  global ``--max-pixels`` option or ``OVERSEEC_MAX_PIXELS``);
- a **memory estimate** for the planner, which holds the whole costmap in memory;
- **byte limits** on text inputs (programs, prompts, JSON), read without ever loading more than
  the limit, and one reader per text format (:func:`read_json_limited`,
  :func:`read_csv_limited`) with depth and field limits and one-line errors.
"""

from __future__ import annotations

import csv
import io
import json
import os
import stat
from pathlib import Path
from typing import Any, TypeAlias

from overseec_core.errors import InputError

ENV_MAX_PIXELS = "OVERSEEC_MAX_PIXELS"
#: 2 gigapixels: a 44,700² image, about 17 hours of CLIPSeg + SAM on a 2-core CPU and 3 minutes of
#: costmap composition per 100 Mpx; beyond it a run is far more likely a mistake than a plan.
DEFAULT_MAX_PIXELS = 2_000_000_000

#: Text inputs: cost programs are a few lines, prompts a paragraph, JSON documents a few MB.
MAX_PROGRAM_BYTES = 1 << 20
MAX_PROMPT_BYTES = 64 << 10
MAX_JSON_BYTES = 64 << 20
MAX_CSV_BYTES = 64 << 20

#: The planner's memory per cell (costs, distances, states, the lethal mask): measured ~13 bytes
#: per pixel by bench/bench_plan.py, plus the float32 costmap itself.
PLANNER_BYTES_PER_PIXEL = 17


def max_pixels() -> int:
    """The pixel budget in force (``OVERSEEC_MAX_PIXELS``, else the default)."""
    raw = os.environ.get(ENV_MAX_PIXELS, "").strip()
    if not raw:
        return DEFAULT_MAX_PIXELS
    return parse_pixel_count(raw, ENV_MAX_PIXELS)


def parse_pixel_count(text: str, what: str = "--max-pixels") -> int:
    """A positive whole number of pixels; '2e9' and '2_000_000_000' are accepted."""
    try:
        value = float(text.replace("_", ""))
    except ValueError:
        raise InputError(f"{what}={text!r} is not a number of pixels") from None
    if not (value >= 1 and value < 1e15) or value != int(value):
        raise InputError(f"{what}={text!r}: expected a whole number of pixels between 1 and 1e15")
    return int(value)


def check_pixels(width: int, height: int, path: str | os.PathLike[str], role: str = "raster") -> None:
    """Refuse a raster larger than the pixel budget before any of it is read."""
    limit = max_pixels()
    count = int(width) * int(height)
    if count > limit:
        raise InputError(
            f"{role} {Path(path).name} is {width} x {height} = {count:.3g} pixels, above the pixel "
            f"budget of {limit:.3g}; crop it (e.g. gdal_translate -srcwin) or raise the budget with "
            f"--max-pixels {count}"
        )


def physical_memory_bytes() -> int | None:
    """Total RAM of this machine, or None where the OS does not say."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        return None


def check_planner_memory(width: int, height: int, path: str | os.PathLike[str]) -> None:
    """Refuse to plan on a costmap whose planner state cannot fit in this machine's memory."""
    total = physical_memory_bytes()
    need = int(width) * int(height) * PLANNER_BYTES_PER_PIXEL
    if total is not None and need > total:
        raise InputError(
            f"costmap {Path(path).name} is {width} x {height}: planning on it needs about "
            f"{need / 2**30:.1f} GiB of memory, more than this machine's {total / 2**30:.1f} GiB; "
            "crop or downsample it (gdalwarp -tr) first"
        )


def _kind(mode: int) -> str:
    if stat.S_ISFIFO(mode):
        return "a named pipe (FIFO)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def check_input_file(path: str | os.PathLike[str], what: str, folders: bool = False) -> None:
    """Refuse an input that is not a regular file (or, with ``folders``, a folder), before it is opened.

    Opening a named pipe blocks until something writes to it, and ignores Ctrl-C meanwhile; a
    device streams forever. Both are refused in one line. Missing paths pass (the opener says so).
    """
    p = Path(path)
    try:
        mode = os.stat(p).st_mode
    except OSError:
        return
    if stat.S_ISREG(mode) or (folders and stat.S_ISDIR(mode)):
        return
    if stat.S_ISDIR(mode):
        raise InputError(f"{what} {p}: is a directory, not a file")
    raise InputError(f"{what} {p}: is {_kind(mode)}, not a regular file; give the file itself")


def _shell_stream(p: Path) -> bool:
    """``/dev/stdin``, ``/dev/fd/N``, ``/proc/self/fd/N``: a pipe the shell opened, with a writer."""
    text = str(p)
    return text.startswith(("/dev/", "/proc/"))


def read_text_limited(path: str | os.PathLike[str], limit: int, what: str) -> str:
    """A UTF-8 text file of at most ``limit`` bytes, read without loading more than that.

    Devices and pipes are read the same bounded way, so ``/dev/zero`` is a clear error, not a
    MemoryError. ``what`` names the option in messages ("--program"). A named pipe elsewhere
    (``mkfifo``) is refused before it is opened: opening it would block until a writer comes.
    """
    p = Path(path)
    if not _shell_stream(p):
        try:
            mode = os.stat(p).st_mode
        except OSError:
            mode = 0
        if stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode):
            raise InputError(f"{what} {p}: is {_kind(mode)}, not a regular file; give the file itself")
    try:
        with open(p, "rb") as f:
            raw = f.read(limit + 1)
    except FileNotFoundError:
        raise InputError(f"{what} {p}: no such file") from None
    except IsADirectoryError:
        raise InputError(f"{what} {p}: is a directory, not a file") from None
    except OSError as exc:
        raise InputError(f"{what} {p}: cannot read it ({exc.strerror or exc})") from None
    if len(raw) > limit:
        raise InputError(f"{what} {p}: larger than the {limit // 1024} KiB allowed for it; is this the right file?")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"{what} {p}: not UTF-8 text (byte {exc.start})") from None


def read_json_limited(path: str | os.PathLike[str], limit: int, what: str) -> Any:
    """A JSON file of at most ``limit`` bytes (:func:`read_text_limited`), parsed; every fault
    is one InputError line naming ``what`` and the file: not JSON (with the line), or nested
    deeper than Python's parser goes (a hostile ``[[[[...]]]]`` is a RecursionError otherwise)."""
    text = read_text_limited(path, limit, what)
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{what} {path}: not JSON ({exc.msg} at line {exc.lineno})") from None
    except RecursionError:
        raise InputError(f"{what} {path}: JSON nested too deeply to be a {what.lstrip('-')} file") from None


#: A row of :func:`read_csv_limited`, typed as ``csv.DictReader`` gives it: the header's names to
#: the line's fields (a ragged line adds a None key, or None values).
CsvRow: TypeAlias = dict[str | Any, str | Any]

#: The longest CSV field accepted (characters): far over any coordinate or id, under Python's
#: ``csv`` default (131072), whose own error is a traceback.
MAX_CSV_FIELD_CHARS = 4096


def read_csv_limited(path: str | os.PathLike[str], limit: int, what: str) -> tuple[list[str], list[tuple[int, CsvRow]]]:
    """A CSV table with a header, of at most ``limit`` bytes: (the header, lower-cased and
    stripped; (line number, row) per row). A field over :data:`MAX_CSV_FIELD_CHARS` or a
    malformed line is one InputError naming the file and the line; pipes are refused and the
    read is bounded, as for every text input."""
    text = read_text_limited(path, limit, what)
    reader = csv.DictReader(io.StringIO(text))
    try:
        header = [h.strip().lower() for h in (reader.fieldnames or [])]
        reader.fieldnames = header
        rows: list[tuple[int, CsvRow]] = []
        for row in reader:
            values = [v for v in row.values() if isinstance(v, str)]
            if any(len(v) > MAX_CSV_FIELD_CHARS for v in values):
                raise InputError(
                    f"{what} {path} line {reader.line_num}: a field longer than {MAX_CSV_FIELD_CHARS} characters"
                )
            rows.append((reader.line_num, row))
    except csv.Error as exc:  # raised while reading the line after the last one counted
        raise InputError(f"{what} {path} line {reader.line_num + 1}: not a CSV line ({exc})") from None
    if any(len(h) > MAX_CSV_FIELD_CHARS for h in header):
        raise InputError(f"{what} {path} line 1: a field longer than {MAX_CSV_FIELD_CHARS} characters")
    return header, rows


__all__ = [
    "DEFAULT_MAX_PIXELS",
    "ENV_MAX_PIXELS",
    "MAX_CSV_BYTES",
    "MAX_JSON_BYTES",
    "MAX_PROGRAM_BYTES",
    "MAX_PROMPT_BYTES",
    "check_input_file",
    "check_pixels",
    "check_planner_memory",
    "max_pixels",
    "parse_pixel_count",
    "physical_memory_bytes",
    "read_csv_limited",
    "read_json_limited",
    "read_text_limited",
]
