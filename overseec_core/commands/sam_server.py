"""`overseec sam-server`: the SAM worker behind the QGIS fix-mask tool (JSON lines on stdin/stdout).

QGIS never imports torch: its map tool sends the clicks to this worker, which keeps SAM's image
embedding of the current view (:class:`overseec_core.locate.interactive.FixSession`) and answers
each prompt with the mask decoder alone. One JSON object per line each way, as `overseec
plan-server` does (:mod:`overseec_core.plan.server`: same line limits and number rules, file
descriptor 1 moved onto stderr so only answers reach the protocol stream)::

    {"id": 1, "op": "ping"}
    {"id": 2, "op": "open", "image": PATH, "segment_dir": DIR, "bounds": [xmin, ymin, xmax, ymax],
     "model": null, "bands": null}
    {"id": 3, "op": "prompt", "entity": "road", "points": [[x, y], ...], "labels": [1, 0, ...],
     "box": [xmin, ymin, xmax, ymax] | null, "mode": "add", "show": "mask"}
    {"id": 4, "op": "apply", ...the prompt's fields...}
    {"id": 5, "op": "close"}
    {"id": 6, "op": "shutdown"}

Coordinates are in the image's CRS. ``open`` embeds the view (the window of whole image pixels
covering ``bounds``; ``model`` defaults to the SAM the folder was refined with, else
facebook/sam-vit-base) and answers ``window``, ``bounds``, ``transform``, ``crs`` (WKT),
``entities``, ``embed_ms`` and ``reused`` (the same view open again is not embedded again).
``prompt`` answers ``polygons`` -- the entity's edited mask on the view (``"show": "candidate"``:
SAM's own mask), each polygon a list of rings of [x, y], the largest first, ``truncated`` when some
were left out, ``outline_scale`` the image pixels per outline cell (1 unless the mask is so
speckled that its outline would be too long to trace and draw at once) -- with ``area_px``,
``added_px``, ``removed_px``, ``score`` (SAM's predicted IoU), ``ms``, ``decoder_ms``,
``postprocess_ms`` and ``polygons_ms`` (time in the worker) and ``cpu_ms`` (the worker's CPU time,
all threads: unlike wall time, not inflated by a busy machine). ``apply`` writes the edit into the
segment folder and answers the manifest record (``edit``, ``files``, ``pixels_added``, ...). Errors
are ``{"id": .., "ok": false, "error": "one line", "kind": ..}`` and the worker keeps serving; it
stops at end of input, on ``shutdown`` and on SIGTERM/SIGINT.
"""

from __future__ import annotations

import argparse
import math
import os
import signal
import sys
import time
from typing import IO, Any

from overseec_core.defaults import DEVICE, DEVICE_CHOICES, PRECISIONS
from overseec_core.errors import InputError
from overseec_core.progress import Progress

PROTOCOL_VERSION = 1
OPS = ("ping", "open", "prompt", "apply", "close", "shutdown")
SHOW = ("mask", "candidate")


def register(sub: argparse._SubParsersAction) -> None:
    """Add the `sam-server` subcommand."""
    p = sub.add_parser(
        "sam-server",
        help="SAM worker for the QGIS fix-mask tool: JSON-lines requests on stdin, answers on stdout",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "--device",
        default=DEVICE,
        metavar="DEVICE",
        help=f"where SAM runs: {', '.join(DEVICE_CHOICES)} (default auto: CUDA, then MPS, then CPU)",
    )
    p.add_argument("--precision", default="auto", choices=PRECISIONS, help="auto: bf16/fp16 on GPU, fp32 on CPU")
    p.add_argument(
        "--max-view", type=int, default=2048, metavar="PX", help="longest side of a view in image pixels (2048)"
    )
    p.add_argument(
        "--decoder-threads",
        type=int,
        default=1,
        metavar="N",
        help="CPU threads of the mask decoder, per click (default 1; 0: torch's default, all cores)",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace, progress: Progress) -> int:
    """Run `sam-server`: answer JSON-lines requests from stdin on stdout until stdin closes;
    SIGINT and SIGTERM stop it at once, since it blocks reading stdin."""
    for sig in (signal.SIGINT, signal.SIGTERM):
        try:
            signal.signal(sig, signal.SIG_DFL)
        except ValueError:  # not the main thread (tests call the CLI from threads)
            pass
    if args.max_view < 64:
        raise InputError("--max-view must be at least 64 px")
    if args.decoder_threads < 0:
        raise InputError("--decoder-threads must be 0 (torch's default) or more")
    return main(SamServer(args.device, args.precision, args.max_view, args.decoder_threads or None))


# --------------------------------------------------------------------------------------------
# Requests
# --------------------------------------------------------------------------------------------


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _text(request: dict, key: str, what: str) -> str:
    value = request.get(key)
    if not isinstance(value, str) or not value.strip():
        raise InputError(f'the request names no {what} ("{key}": ...)')
    return value


#: The largest coordinate a request may give (any CRS's coordinates are far smaller; ±1e308 would
#: overflow the pixel arithmetic).
MAX_COORDINATE = 1e15


def _numbers(value: Any, n: int, what: str) -> tuple[float, ...]:
    """``n`` finite numbers within ±:data:`MAX_COORDINATE`, checked where the request enters."""
    if not (isinstance(value, list) and len(value) == n and all(_is_number(v) for v in value)):
        raise InputError(f"{what} must be a list of {n} finite numbers")
    if any(abs(float(v)) > MAX_COORDINATE for v in value):
        raise InputError(
            f"{what}: coordinates must lie within ±{MAX_COORDINATE:g} (map coordinates in the image's CRS)"
        )
    return tuple(float(v) for v in value)


def _prompt(request: dict) -> Any:
    """The Prompt a request describes (points, labels, box), checked."""
    from overseec_core.locate.interactive import MAX_POINTS, Prompt

    points = request.get("points") or []
    labels = request.get("labels")
    if not isinstance(points, list) or len(points) > MAX_POINTS:
        raise InputError(f"points must be a list of at most {MAX_POINTS} [x, y] pairs")
    xy = tuple(_numbers(p, 2, "each point") for p in points)
    if labels is None:
        labels = [1] * len(xy)
    if not isinstance(labels, list) or not all(v in (0, 1) and not isinstance(v, bool) for v in labels):
        raise InputError("labels must be a list of 1 (include) and 0 (exclude), one per point")
    box = request.get("box")
    prompt = Prompt(
        tuple((p[0], p[1]) for p in xy),
        tuple(int(v) for v in labels),
        None if box is None else _numbers(box, 4, "box"),  # type: ignore[arg-type]
    )
    prompt.check()
    return prompt


# --------------------------------------------------------------------------------------------
# The handler
# --------------------------------------------------------------------------------------------


class SamServer:
    """One open view (its SAM embedding) and one method per operation."""

    def __init__(
        self, device: str = DEVICE, precision: str = "auto", max_view_px: int = 2048, decoder_threads: int | None = 1
    ) -> None:
        self.device, self.precision, self.max_view_px = device, precision, max_view_px
        self.decoder_threads = decoder_threads
        self.session: Any = None  # FixSession, imported when the first view opens
        self._key: tuple | None = None
        #: Views embedded by this worker (tests and the bench check reuse).
        self.embeddings = 0

    def handle(self, request: Any) -> tuple[dict[str, Any], bool]:
        """The answer to one request, and whether the server should stop after sending it."""
        from overseec_core.plan.server import dispatch  # the planner worker's answers, one shape

        return dispatch(
            self,
            request,
            OPS,
            worker="SAM worker",
            out_of_memory="not enough memory for this view; zoom in or close other programs",
            on_memory_error=self._forget_view,
        )

    def _forget_view(self) -> None:
        """Out of memory: drop the view's session and embedding."""
        self.session, self._key = None, None

    # -- operations ----------------------------------------------------------------------------

    def op_ping(self, _request: dict) -> dict[str, Any]:
        return {
            "version": PROTOCOL_VERSION,
            "pid": os.getpid(),
            "open": self.session is not None,
            "embeddings": self.embeddings,
        }

    def op_shutdown(self, _request: dict) -> dict[str, Any]:
        return {}

    def op_close(self, _request: dict) -> dict[str, Any]:
        closed = self.session is not None
        self.session, self._key = None, None
        return {"closed": closed}

    def op_open(self, request: dict) -> dict[str, Any]:
        from overseec_core.locate.interactive import FixSession

        image = os.path.abspath(_text(request, "image", "image"))
        folder = os.path.abspath(_text(request, "segment_dir", "segment folder"))
        bounds = _numbers(request.get("bounds"), 4, "bounds ([xmin, ymin, xmax, ymax])")
        model, bands = request.get("model"), request.get("bands")
        if model is not None and not isinstance(model, str):
            raise InputError("model must be a hub id or a folder")
        if bands is not None and not (isinstance(bands, list) and all(isinstance(b, int) for b in bands)):
            raise InputError("bands must be a list of band numbers")
        key = (image, folder, bounds, model, None if bands is None else tuple(bands))
        reused = key == self._key and self.session is not None
        if not reused:
            self.session, self._key = None, None  # the old view's memory goes first
            self.session = FixSession(
                image, folder, bounds, model, self.device, self.precision, bands, self.max_view_px, self.decoder_threads
            )
            self._key = key
            self.embeddings += 1
        return {**self.session.describe(), "reused": reused}

    def _open_session(self) -> Any:
        if self.session is None:
            raise InputError('no view is open; send "open" first')
        return self.session

    def op_prompt(self, request: dict) -> dict[str, Any]:
        from overseec_core.locate.interactive import DEFAULT_MODE, mask_outline

        session = self._open_session()
        t0, c0 = time.perf_counter(), time.process_time()
        entity = _text(request, "entity", "entity")
        mode = request.get("mode", DEFAULT_MODE)
        show = request.get("show", "mask")
        if show not in SHOW:
            raise InputError(f"show must be one of {', '.join(SHOW)}, not {show!r}")
        answer = session.prompt(entity, _prompt(request), mode)
        t1 = time.perf_counter()
        shown = answer.mask if show == "mask" else answer.candidate
        polygons, truncated, scale = mask_outline(shown, session.view.transform)
        t2 = time.perf_counter()
        return {
            "entity": entity,
            "mode": answer.mode,
            "show": show,
            "polygons": polygons,
            "truncated": truncated,
            "outline_scale": scale,
            "area_px": int(answer.mask.sum()),
            "candidate_px": int(answer.candidate.sum()),
            "added_px": int(answer.added.sum()),
            "removed_px": int(answer.removed.sum()),
            "score": answer.score,
            **{k: round(v, 3) for k, v in answer.timings_ms.items()},
            "polygons_ms": round(1000.0 * (t2 - t1), 3),
            "ms": round(1000.0 * (t2 - t0), 3),
            "cpu_ms": round(1000.0 * (time.process_time() - c0), 3),
        }

    def op_apply(self, request: dict) -> dict[str, Any]:
        from overseec_core.locate.interactive import DEFAULT_MODE

        session = self._open_session()
        t0 = time.perf_counter()
        entity = _text(request, "entity", "entity")
        record = session.apply(entity, _prompt(request), request.get("mode", DEFAULT_MODE))
        return {**record, "ms": round(1000.0 * (time.perf_counter() - t0), 3)}


# --------------------------------------------------------------------------------------------
# The line protocol (the planner worker's rules)
# --------------------------------------------------------------------------------------------


def serve(infile: IO[str], outfile: IO[str], server: SamServer) -> int:
    """Answer requests from ``infile`` on ``outfile`` until end of input or ``shutdown``."""
    from overseec_core.plan.server import serve_lines

    return serve_lines(infile, outfile, server, "SAM worker")


def main(server: SamServer | None = None) -> int:
    """Serve stdin/stdout; only answers reach the real stdout (see plan.server.protocol_stdout)."""
    from overseec_core.plan.server import protocol_stdout

    out = protocol_stdout()
    stdin = open(sys.stdin.fileno(), encoding="utf-8", errors="replace", closefd=False)
    try:
        return serve(stdin, out, server or SamServer())
    finally:
        out.close()
