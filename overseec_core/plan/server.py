"""The planner worker: one process per QGIS session answering plan requests as JSON lines.

QGIS never runs the native kernel itself: the plugin starts ``overseec plan-server`` from the
project's environment and talks to it over stdin/stdout, one JSON object per line each way.
The worker loads each costmap once (an LRU of :data:`CACHE_SIZE`, reloaded when the costmap,
its lethal sidecar or an override file changes on disk) and plans with the same core code as
``overseec plan``: :func:`~overseec_core.plan.load_costmap`, override polygons applied in memory
(:func:`~overseec_core.plan.overrides.apply_to_planning_grid`), a :class:`~overseec_core.plan.Planner`
kept per costmap (buffers allocated once) behind a :class:`~overseec_core.plan.stage.RulePlanner`
(keep-out zones entered only when no route avoids them).

Requests (``id`` is echoed back; any JSON scalar)::

    {"id": 1, "op": "ping"}
    {"id": 2, "op": "load", "costmap": PATH, "band": null, "overrides": [GPKG, ...]}
    {"id": 3, "op": "plan", "costmap": PATH, "points": [[x, y], ...], "mode": "fast",
     "band": null, "overrides": [...], "crs": null, "vertices": "turns", "neighbours": 8}
    {"id": 4, "op": "unload", "costmap": PATH}        # or no costmap: forget them all
    {"id": 5, "op": "shutdown"}

Answers: ``{"id": .., "ok": true, ...}`` or ``{"id": .., "ok": false, "error": "one line",
"kind": "PlanError"}``. ``load`` answers the costmap's ``crs`` (WKT), ``width``, ``height`` and
``transform`` (the affine a, b, c, d, e, f); ``plan`` answers ``points`` (pixel centres in the
costmap's CRS, start to goal: with ``"vertices": "turns"``, the default, only where the route
turns, at the vias and at its ends -- the same line with a fraction of the vertices to encode,
send and draw; ``"pixels"`` gives every pixel), ``n_pixels``, ``cost``, ``length_m``, ``mode``,
``bound``, ``vias``, ``notes``, ``ms`` and ``cpu_ms`` (wall and CPU time spent planning in the
worker). Points are in the costmap's CRS unless ``crs`` names theirs. ``neighbours`` is the
planner's steps (8, the default, or 16 with knight moves; ``overseec plan --neighbours``): a costmap
keeps one planner, rebuilt when a request asks for the other steps. A plan request loads its
costmap when needed, so a restarted worker needs no replay.

Every line gets one answer, and a malformed one an error answer (the worker keeps serving):
a line that is not one JSON object, a number that is not finite (``NaN``, ``Infinity``,
``1e400``) or longer than :data:`MAX_DIGITS` digits, brackets nested deeper than
:data:`MAX_DEPTH`, a value of the wrong type or range, a line over :data:`MAX_LINE`
characters. Bytes that are not UTF-8 read as U+FFFD; a last line cut off by the end of input is
answered like any other.

Only protocol lines go to stdout: :func:`main` moves file descriptor 1 onto stderr before
anything else runs, so a stray ``print`` or a driver writing to stdout cannot corrupt the stream.
Requests carry data only (paths, numbers); nothing in them is executed. Started as
``overseec plan-server``, the process first writes start-up lines (``{"event": "starting",
"modules": N}``, no ``id``) while its imports run (:mod:`overseec_core.liveness`); they stop before
the first answer.
"""

from __future__ import annotations

import json
import math
import os
import sys
import time
import traceback
from collections import OrderedDict
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import IO, Any

import numpy as np

from overseec_core import liveness
from overseec_core.errors import InputError, OverseecError
from overseec_core.plan.grid import PlanningGrid, load_costmap
from overseec_core.plan.overrides import apply_to_planning_grid
from overseec_core.plan.paths import DEFAULT_BASE_COST_PER_M
from overseec_core.plan.planner import MODES, NEIGHBOURS, Planner, check_neighbours
from overseec_core.plan.stage import RulePlanner, points_to_pixels
from overseec_core.synthesize.overrides import load_overrides

#: Costmaps kept loaded (least recently used dropped first).
CACHE_SIZE = 2
#: Longest request line read; longer ones are refused (and skipped) without reading them whole.
MAX_LINE = 1 << 20
#: Deepest nesting of lists and objects in a request (a plan request needs 3).
MAX_DEPTH = 16
#: Most digits in an integer of a request (a JSON number past 2**64 is no id, band or point).
MAX_DIGITS = 20
#: Highest band number a request may name.
MAX_BAND = 1 << 16
#: Most points in one plan request (start, vias, goal).
MAX_POINTS = 1000
PROTOCOL_VERSION = 1
#: Coarse shortest-path trees fast mode keeps per costmap (start and goal while a via is dragged,
#: and the next drag's; see Planner's ``coarse_trees``).
COARSE_TREES = 4
OPS = ("ping", "load", "plan", "unload", "shutdown")


def _stamp(path: str | os.PathLike | None) -> tuple[str, int, int] | None:
    """What identifies a file's content on disk: path, mtime (ns), size."""
    if path is None:
        return None
    st = os.stat(path)
    return (str(path), st.st_mtime_ns, st.st_size)


@dataclass(frozen=True)
class _Key:
    path: str
    band: int | None


class LoadedCostmap:
    """One costmap loaded for planning, with the override files currently applied to it."""

    def __init__(self, key: _Key, base_cost_per_m: float = DEFAULT_BASE_COST_PER_M) -> None:
        self.key = key
        self.base_cost_per_m = base_cost_per_m
        self.base = load_costmap(key.path, band=key.band)
        self.stamps = (_stamp(key.path), _stamp(self.base.lethal_source))
        self.overrides: tuple[tuple[str, int, int] | None, ...] = ()
        self.neighbours = NEIGHBOURS[0]
        self.planner = self._rule_planner(self.base)

    def is_current(self) -> bool:
        """Whether the files on disk are still the ones loaded."""
        try:
            return (_stamp(self.key.path), _stamp(self.base.lethal_source)) == self.stamps
        except OSError:
            return False

    def _rule_planner(self, grid: PlanningGrid) -> RulePlanner:
        # interactive re-plans never show fast mode's tight bound (the octile one is free), and
        # keep coarse trees at the ends that stay put while a point is dragged
        planner = Planner(
            grid, self.base_cost_per_m, tight_bound=False, coarse_trees=COARSE_TREES, neighbours=self.neighbours
        )
        planner.prepare_fast()
        return RulePlanner(planner)

    @property
    def grid(self) -> PlanningGrid:
        return self.planner.grid

    def use_overrides(self, files: Sequence[str]) -> None:
        """Plan with these override files applied (to a copy: the loaded costmap stays as read)."""
        stamps = tuple(_stamp(f) for f in files)
        if stamps == self.overrides:
            return
        grid = self.base
        if files:
            keep_out = None if grid.keep_out is None else grid.keep_out.copy()
            grid = replace(grid, cost=grid.cost.copy(), keep_out=keep_out)
            if grid.grid is None:
                raise InputError("overrides need a georeferenced costmap")
            grid, _counts = apply_to_planning_grid(grid, load_overrides([Path(f) for f in files], grid.grid))
        self.planner = self._rule_planner(grid)
        self.overrides = stamps

    def use_neighbours(self, neighbours: int) -> None:
        """Plan with these steps (8 or 16): the planner is rebuilt on the grid it plans on (the
        overrides stay applied) when they change; one planner, so its buffers are never doubled."""
        if neighbours == self.neighbours:
            return
        previous, self.neighbours = self.neighbours, neighbours
        try:
            self.planner = self._rule_planner(self.planner.grid)
        except Exception:
            self.neighbours = previous  # e.g. the fallback refuses 16: keep the planner that works
            raise

    def describe(self) -> dict[str, Any]:
        g = self.base.need_grid()
        t = g.transform
        return {
            "costmap": self.key.path,
            "crs": g.crs.to_wkt(),
            "width": g.width,
            "height": g.height,
            "transform": [t.a, t.b, t.c, t.d, t.e, t.f],
            "prompt": self.base.prompt,
            "keep_out": self.base.keep_out is not None,
        }


class PlanServer:
    """The request handler: a small LRU of loaded costmaps and one method per operation."""

    def __init__(self, cache_size: int = CACHE_SIZE) -> None:
        self.cache_size = cache_size
        self.cache: OrderedDict[_Key, LoadedCostmap] = OrderedDict()
        #: How many times a costmap was read from disk (tests and the bench check reuse).
        self.loads = 0

    def handle(self, request: Any) -> tuple[dict[str, Any], bool]:
        """The answer to one request, and whether the server should stop after sending it."""
        return dispatch(
            self,
            request,
            OPS,
            worker="planner worker",
            out_of_memory="not enough memory for this costmap; close other programs",
            on_memory_error=self.cache.clear,
        )

    # -- operations ----------------------------------------------------------------------------

    def op_ping(self, _request: dict) -> dict[str, Any]:
        return {
            "version": PROTOCOL_VERSION,
            "pid": os.getpid(),
            "loaded": [k.path for k in self.cache],
            "loads": self.loads,
        }

    def op_shutdown(self, _request: dict) -> dict[str, Any]:
        return {}

    def op_unload(self, request: dict) -> dict[str, Any]:
        path = request.get("costmap")
        if path is None:
            dropped = len(self.cache)
            self.cache.clear()
        else:
            target = _path(path)
            keys = [k for k in self.cache if k.path == target]
            for k in keys:
                del self.cache[k]
            dropped = len(keys)
        return {"unloaded": dropped}

    def op_load(self, request: dict) -> dict[str, Any]:
        loaded = self._costmap(request)
        return loaded.describe()

    def op_plan(self, request: dict) -> dict[str, Any]:
        points = _points(request.get("points"))
        mode = request.get("mode", "fast")
        if mode not in MODES:
            raise InputError(f"unknown planning mode {mode!r}; use {' or '.join(MODES)}")
        vertices = request.get("vertices", "turns")
        if vertices not in ("turns", "pixels"):
            raise InputError(f"vertices must be 'turns' or 'pixels', not {vertices!r}")
        crs = request.get("crs")
        if crs is not None and not isinstance(crs, str):
            raise InputError("crs must be a string such as 'EPSG:4326'")
        neighbours = check_neighbours(request.get("neighbours", NEIGHBOURS[0]))
        loaded = self._costmap(request)
        loaded.use_neighbours(neighbours)
        t0, c0 = time.perf_counter(), time.thread_time()
        grid = loaded.grid
        pixels, labels = points_to_pixels(grid, points, crs)
        result, _planner = loaded.planner.plan(pixels, mode=mode, labels=labels)
        line = result.pixels if vertices == "pixels" else turning_points(result.pixels, result.waypoints)
        xs, ys = grid.pixel_to_world(line[:, 0], line[:, 1])
        return {
            "points": [[x, y] for x, y in zip(np.atleast_1d(xs).tolist(), np.atleast_1d(ys).tolist())],
            "n_pixels": len(result.pixels),
            "cost": _finite(result.cost),
            "length_m": _finite(result.length_m),
            "mode": result.mode,
            "bound": _finite(result.bound),
            "vias": len(points) - 2,
            "notes": list(result.notes),
            "ms": round(1000.0 * (time.perf_counter() - t0), 3),
            "cpu_ms": round(1000.0 * (time.thread_time() - c0), 3),
        }

    # -- the cache -------------------------------------------------------------------------------

    def _costmap(self, request: dict) -> LoadedCostmap:
        """The loaded costmap a request names, with its overrides applied (loaded if needed)."""
        band = request.get("band")
        if band is not None and (not isinstance(band, int) or isinstance(band, bool) or not 1 <= band <= MAX_BAND):
            raise InputError("band must be a whole number from 1 (the first band)")
        overrides = request.get("overrides") or []
        if not isinstance(overrides, list) or not all(isinstance(f, str) and f for f in overrides):
            raise InputError("overrides must be a list of file paths")
        key = _Key(_path(request.get("costmap")), band)
        loaded = self.cache.get(key)
        if loaded is not None and not loaded.is_current():
            del self.cache[key]
            loaded = None
        if loaded is None:
            # drop the oldest first, so two large costmaps are never held beside a third
            while len(self.cache) >= self.cache_size:
                self.cache.popitem(last=False)
            loaded = LoadedCostmap(key)
            self.loads += 1
            self.cache[key] = loaded
        self.cache.move_to_end(key)
        loaded.use_overrides(overrides)
        return loaded


def turning_points(pixels: np.ndarray, waypoints: Sequence[tuple[int, int]] = ()) -> np.ndarray:
    """The pixels of an 8-connected route where its step changes, its ends and its waypoints:
    the same polyline through pixel centres with the straight runs' inner vertices left out."""
    px = np.asarray(pixels)
    if len(px) <= 2:
        return px
    steps = np.diff(px, axis=0)
    keep = np.ones(len(px), dtype=bool)
    keep[1:-1] = np.any(steps[1:] != steps[:-1], axis=1)
    for r, c in waypoints:
        keep[(px[:, 0] == r) & (px[:, 1] == c)] = True
    return px[keep]


def _path(value: Any) -> str:
    if not isinstance(value, str) or not value:
        raise InputError('the request names no costmap ("costmap": PATH)')
    return os.path.abspath(value)


def _points(value: Any) -> tuple[tuple[float, float], ...]:
    """Start, vias and goal as (x, y) floats; a one-line error for anything else."""
    if not isinstance(value, list) or not 2 <= len(value) <= MAX_POINTS:
        raise InputError(f"points must be a list of 2 to {MAX_POINTS} [x, y] pairs (start, vias..., goal)")
    out = []
    for p in value:
        if not (isinstance(p, list) and len(p) == 2 and all(_is_number(v) for v in p)):
            raise InputError(f"each point must be [x, y] with finite numbers, not {json.dumps(p)[:60]}")
        out.append((float(p[0]), float(p[1])))
    return tuple(out)


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _finite(v: float) -> float | None:
    return float(v) if math.isfinite(v) else None


def _one_line(text: str) -> str:
    return " ".join(str(text).split()) or "unknown error"


def dispatch(
    server: Any,
    request: Any,
    ops: Sequence[str],
    *,
    worker: str,
    out_of_memory: str,
    on_memory_error: Callable[[], None],
) -> tuple[dict[str, Any], bool]:
    """The answer to one request of a JSON-lines worker (this one and `overseec sam-server`), and
    whether it should stop after sending it: the request checked (an object, a scalar id, a known
    op), ``server.op_<op>(request)`` run, and every failure one error answer -- the user's as its
    message, running out of memory as ``out_of_memory`` after ``on_memory_error`` dropped what
    the worker holds, a bug as one line naming the ``worker`` (its traceback to stderr)."""
    if not isinstance(request, dict):
        return error_answer(None, InputError("a request is one JSON object per line")), False
    rid = request.get("id")
    if not (rid is None or isinstance(rid, (int, float, str, bool))):
        return error_answer(None, InputError("the request id must be a number or a string")), False
    op = request.get("op")
    if op not in ops:
        return error_answer(rid, InputError(f"unknown op {op!r}; use one of {', '.join(ops)}")), False
    try:
        answer = getattr(server, f"op_{op}")(request)
    except (OverseecError, OSError, ValueError) as exc:
        return error_answer(rid, exc), False
    except MemoryError:
        on_memory_error()
        return error_answer(rid, MemoryError(out_of_memory)), False
    except Exception as exc:  # a bug: one line back, the traceback to stderr
        traceback.print_exc(file=sys.stderr)
        return error_answer(
            rid, RuntimeError(f"unexpected failure in the {worker}: {type(exc).__name__}: {exc}")
        ), False
    return {"id": rid, "ok": True, **answer}, op == "shutdown"


def error_answer(rid: Any, exc: BaseException) -> dict[str, Any]:
    """The one-line error answer to request ``rid`` (OS errors as 'reason: file')."""
    if isinstance(exc, OSError) and exc.strerror:
        message = f"{exc.strerror}: {exc.filename}" if exc.filename else exc.strerror
    else:
        message = str(exc)
    return {"id": rid, "ok": False, "error": _one_line(message), "kind": type(exc).__name__}


class _BadNumber(ValueError):
    """A JSON number the protocol refuses (not finite, or too many digits)."""


def _refuse_constant(name: str) -> Any:
    raise _BadNumber(f"numbers must be finite, not {name}")


def _parse_float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise _BadNumber(f"numbers must be finite, not {text[:40]}")
    return value


def _parse_int(text: str) -> int:
    if len(text.lstrip("-")) > MAX_DIGITS:
        raise _BadNumber(f"integers have at most {MAX_DIGITS} digits, not {len(text.lstrip('-'))}")
    return int(text)


def _depth(value: Any) -> int:
    """How deeply lists and objects nest in a parsed value (without recursion)."""
    deepest, stack = 0, [(value, 1)]
    while stack:
        item, depth = stack.pop()
        if isinstance(item, (list, dict)):
            deepest = max(deepest, depth)
            if depth <= MAX_DEPTH:  # deeper is refused anyway: no need to walk it
                stack.extend((child, depth + 1) for child in (item.values() if isinstance(item, dict) else item))
    return deepest


def parse_request(line: str) -> Any:
    """One request line as JSON data, or an :class:`InputError` saying why it is none."""
    try:
        value = json.loads(line, parse_constant=_refuse_constant, parse_float=_parse_float, parse_int=_parse_int)
    except _BadNumber as exc:
        raise InputError(f"bad request: {exc}") from None
    except RecursionError:
        raise InputError(f"bad request: lists and objects nested deeper than {MAX_DEPTH}") from None
    except ValueError as exc:  # JSONDecodeError
        raise InputError(f"not a JSON request: {exc}") from None
    if _depth(value) > MAX_DEPTH:
        raise InputError(f"bad request: lists and objects nested deeper than {MAX_DEPTH}")
    return value


def _encode(answer: dict[str, Any], worker: str = "planner worker") -> str:
    """One answer line; an answer JSON cannot hold (a bug) becomes an error answer, not a crash."""
    try:
        return json.dumps(answer, separators=(",", ":"), allow_nan=False)
    except (TypeError, ValueError, RecursionError) as exc:
        traceback.print_exc(file=sys.stderr)
        rid = answer.get("id")
        if not (rid is None or isinstance(rid, (str, bool)) or (_is_number(rid) and abs(rid) < 2**63)):
            rid = None
        failure = RuntimeError(f"unexpected failure in the {worker}: an answer JSON cannot hold ({exc})")
        return json.dumps(error_answer(rid, failure), separators=(",", ":"))


def _read_line(infile: IO[str]) -> tuple[str | None, bool]:
    """The next request line (None at end of input), and whether it was too long (then skipped)."""
    line = infile.readline(MAX_LINE + 1)
    if not line:
        return None, False
    if len(line) > MAX_LINE and not line.endswith("\n"):
        while True:  # skip the rest of the oversized line without holding it
            rest = infile.readline(MAX_LINE)
            if not rest or rest.endswith("\n"):
                return "", True
    return line, False


def serve(infile: IO[str], outfile: IO[str], server: PlanServer | None = None) -> int:
    """Answer requests from ``infile`` on ``outfile`` until end of input or ``shutdown``."""
    return serve_lines(infile, outfile, server or PlanServer(), "planner worker")


def serve_lines(infile: IO[str], outfile: IO[str], server: Any, worker: str) -> int:
    """The JSON-lines loop every overseec worker speaks (this planner's, the SAM worker's): one
    request per line to ``server.handle`` (-> answer, stop), one answer line back; oversized,
    malformed and blank lines are answered or skipped without stopping the worker."""
    while True:
        line, too_long = _read_line(infile)
        if line is None:
            return 0
        if too_long:
            answer, stop = error_answer(None, InputError(f"request longer than {MAX_LINE} bytes")), False
        elif not line.strip():
            continue
        else:
            try:
                request = parse_request(line)
            except InputError as exc:
                answer, stop = error_answer(None, exc), False
            else:
                answer, stop = server.handle(request)
        outfile.write(_encode(answer, worker) + "\n")
        outfile.flush()
        if stop:
            return 0


def protocol_stdout() -> IO[str]:
    """A private stream on the process's stdout; fd 1 (and ``sys.stdout``) then write to stderr.

    Anything else that prints -- Python code, GDAL, a C library -- lands on stderr, so the
    protocol stream holds answers only. The start-up lines (:mod:`overseec_core.liveness`) stop
    first: after this, every line on the stream is an answer.
    """
    liveness.stop()
    sys.stdout.flush()
    proto = os.dup(1)
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    return os.fdopen(proto, "w", encoding="utf-8", buffering=1)


def main() -> int:
    """Serve stdin/stdout (``overseec plan-server``)."""
    out = protocol_stdout()
    stdin = open(sys.stdin.fileno(), encoding="utf-8", errors="replace", closefd=False)
    try:
        return serve(stdin, out)
    finally:
        out.close()
