"""The plugin's side of the SAM worker: one ``overseec sam-server`` process per QGIS session.

QGIS never imports torch: the fix-mask tool (:mod:`overseec_qgis.fixtool`) sends its clicks to the
worker of the overseec environment (protocol: :mod:`overseec_core.commands.sam_server`), which
keeps SAM's image embedding of the open view, so each click costs the mask decoder only.

The process handling is the planner client's (:class:`overseec_qgis.planclient.PlanClient`: started
lazily, one request at a time, answers matched by id, every wait bounded, a worker that misses a
timeout stopped and started again by the next request). On top of it this client remembers the
open view: when the worker was restarted (it died, or missed a timeout), the next prompt opens the
view again first, so the tool never has to replay anything. Failures are :class:`SamClientError`
with a one-line message: ``SamRejected`` when the worker refused the request (a point outside the
view, an unknown entity), ``SamWorkerError`` when the worker could not be started or failed.

Plain Python, no Qt: the tests and the bench drive it directly.
"""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from .lineclient import SessionClient, require_worker
from .planclient import PlanClient, PlanClientError, PlanRejected

#: Seconds opening a view may take: loading SAM and one image-encoder pass (ViT-B on a laptop
#: CPU: about 10-30 s; the first start also imports torch).
OPEN_TIMEOUT_S = 900.0
#: Seconds one prompt (mask decoder) or apply (rewriting the mask files) may take.
PROMPT_TIMEOUT_S = 120.0
SHORT_TIMEOUT_S = 10.0

Ring = tuple[tuple[float, float], ...]


class SamClientError(Exception):
    """A request to the SAM worker failed; ``str()`` is one line for a message bar."""


class SamRejected(SamClientError):
    """The worker answered with an error the user can fix (a point outside the view ...)."""


class SamWorkerError(SamClientError):
    """The worker could not be started, died, or did not answer in time."""


@dataclass(frozen=True)
class ViewInfo:
    """An open view as the worker reports it (coordinates in the image's CRS)."""

    window: tuple[int, int, int, int]  # col_off, row_off, width, height in image pixels
    bounds: tuple[float, float, float, float]
    crs_wkt: str
    entities: tuple[str, ...]
    mask_file: str
    embed_ms: float
    reused: bool
    model: str
    device: str

    @staticmethod
    def from_answer(answer: Mapping[str, Any]) -> ViewInfo:
        w, b = answer["window"], answer["bounds"]
        return ViewInfo(
            window=(int(w[0]), int(w[1]), int(w[2]), int(w[3])),
            bounds=(float(b[0]), float(b[1]), float(b[2]), float(b[3])),
            crs_wkt=str(answer["crs"]),
            entities=tuple(str(e) for e in answer["entities"]),
            mask_file=str(answer.get("mask_file", "")),
            embed_ms=float(answer.get("embed_ms", 0.0)),
            reused=bool(answer.get("reused", False)),
            model=str(answer.get("model", "")),
            device=str(answer.get("device", "")),
        )


@dataclass(frozen=True)
class MaskReply:
    """The entity's edited mask on the view as polygons (rings of (x, y), outer first)."""

    polygons: tuple[tuple[Ring, ...], ...]
    truncated: bool
    area_px: int
    added_px: int
    removed_px: int
    candidate_px: int
    score: float
    #: Time in the worker (all of it, the decoder's part) and the request seen from here (ms).
    worker_ms: float
    decoder_ms: float
    round_trip_ms: float
    #: The worker's CPU time for the prompt (ms, all threads; not inflated by a busy machine).
    worker_cpu_ms: float = 0.0
    #: Image pixels per cell of the outline (1: exact; more for a speckled mask).
    outline_scale: int = 1

    @staticmethod
    def from_answer(answer: Mapping[str, Any], round_trip_ms: float) -> MaskReply:
        polys = tuple(
            tuple(tuple((float(x), float(y)) for x, y in ring) for ring in polygon) for polygon in answer["polygons"]
        )
        return MaskReply(
            polygons=polys,
            truncated=bool(answer.get("truncated", False)),
            area_px=int(answer["area_px"]),
            added_px=int(answer["added_px"]),
            removed_px=int(answer["removed_px"]),
            candidate_px=int(answer.get("candidate_px", 0)),
            score=float(answer.get("score", 0.0)),
            worker_ms=float(answer.get("ms", 0.0)),
            decoder_ms=float(answer.get("decoder_ms", 0.0)),
            round_trip_ms=round_trip_ms,
            worker_cpu_ms=float(answer.get("cpu_ms", 0.0)),
            outline_scale=int(answer.get("outline_scale", 1)),
        )


@dataclass(frozen=True)
class ApplyReply:
    """What an apply wrote: the manifest key of the edit and the files changed."""

    edit: str
    files: tuple[str, ...]
    pixels_added: int
    pixels_removed: int
    worker_ms: float


def worker_argv(worker: str | os.PathLike) -> list[str]:
    """The command line of the SAM worker for an ``overseec`` executable (no shell)."""
    return [str(worker), "sam-server"]


def _renamed(message: str) -> str:
    """The planner client's messages, told of the SAM worker."""
    return message.replace("planner worker", "SAM worker").replace("the next plan", "the next request")


class SamClient:
    """Talks to one SAM worker and keeps its view open across restarts (module docstring)."""

    def __init__(
        self,
        argv: Sequence[str] | Callable[[], Sequence[str]],
        env: Mapping[str, str] | None = None,
        prompt_timeout_s: float = PROMPT_TIMEOUT_S,
        open_timeout_s: float = OPEN_TIMEOUT_S,
    ) -> None:
        self._transport = PlanClient(argv, env, plan_timeout_s=prompt_timeout_s, load_timeout_s=open_timeout_s)
        self.open_timeout_s = open_timeout_s
        self._lock = threading.RLock()
        self._view: dict[str, Any] | None = None  # the last open request's fields
        self._view_pid: int | None = None
        self.info: ViewInfo | None = None

    @property
    def pid(self) -> int | None:
        return self._transport.pid

    @property
    def starts(self) -> int:
        """How many worker processes this client started."""
        return self._transport.starts

    def request(self, op: str, timeout_s: float | None = None, **fields: Any) -> dict[str, Any]:
        """One request (the worker starts if needed); its answer, or a SamClientError."""
        try:
            return self._transport.request(op, timeout_s=timeout_s, **fields)
        except PlanRejected as exc:
            raise SamRejected(_renamed(str(exc))) from None
        except PlanClientError as exc:
            raise SamWorkerError(_renamed(str(exc))) from None

    def ping(self) -> dict[str, Any]:
        return self.request("ping", timeout_s=SHORT_TIMEOUT_S)

    def open(
        self,
        image: str | os.PathLike,
        segment_dir: str | os.PathLike,
        bounds: Sequence[float],
        model: str | None = None,
        bands: Sequence[int] | None = None,
    ) -> ViewInfo:
        """Open a view (bounds in the image's CRS): the worker embeds it once; the same view
        again is answered at once."""
        fields = {
            "image": os.path.abspath(image),
            "segment_dir": os.path.abspath(segment_dir),
            "bounds": [float(v) for v in bounds],
            "model": model,
            "bands": None if bands is None else [int(b) for b in bands],
        }
        with self._lock:
            self._view = None
            answer = self.request("open", timeout_s=self.open_timeout_s, **fields)
            self._view, self._view_pid = fields, self.pid
            self.info = ViewInfo.from_answer(answer)
            return self.info

    def _ensure_view(self) -> None:
        """Open the view again in a worker that was restarted since it was opened."""
        if self._view is None:
            raise SamRejected("no view is open: open one first")
        if self.pid is None or self.pid != self._view_pid:
            answer = self.request("open", timeout_s=self.open_timeout_s, **self._view)
            self._view_pid = self.pid
            self.info = ViewInfo.from_answer(answer)

    @staticmethod
    def _prompt_fields(
        entity: str,
        points: Sequence[tuple[float, float]],
        labels: Sequence[int],
        box: Sequence[float] | None,
        mode: str,
    ) -> dict[str, Any]:
        return {
            "entity": entity,
            "points": [[float(x), float(y)] for x, y in points],
            "labels": [int(v) for v in labels],
            "box": None if box is None else [float(v) for v in box],
            "mode": mode,
        }

    def prompt(
        self,
        entity: str,
        points: Sequence[tuple[float, float]] = (),
        labels: Sequence[int] = (),
        box: Sequence[float] | None = None,
        mode: str = "add",
        show: str = "mask",
    ) -> MaskReply:
        """The entity's mask edited by these prompts (image CRS; labels 1 include, 0 exclude)."""
        t0 = time.monotonic()
        with self._lock:
            self._ensure_view()
            fields = self._prompt_fields(entity, points, labels, box, mode)
            answer = self.request("prompt", show=show, **fields)
        return MaskReply.from_answer(answer, 1000.0 * (time.monotonic() - t0))

    def apply(
        self,
        entity: str,
        points: Sequence[tuple[float, float]] = (),
        labels: Sequence[int] = (),
        box: Sequence[float] | None = None,
        mode: str = "add",
    ) -> ApplyReply:
        """Write the edit these prompts make into the segment folder (see the worker's ``apply``)."""
        with self._lock:
            self._ensure_view()
            answer = self.request("apply", **self._prompt_fields(entity, points, labels, box, mode))
        return ApplyReply(
            edit=str(answer["edit"]),
            files=tuple(str(f) for f in answer["files"]),
            pixels_added=int(answer["pixels_added"]),
            pixels_removed=int(answer["pixels_removed"]),
            worker_ms=float(answer.get("ms", 0.0)),
        )

    def close_view(self) -> None:
        """Forget the view (the worker frees its embedding); a later prompt needs a new open."""
        with self._lock:
            self._view, self.info = None, None
            if self.pid is not None:
                try:
                    self.request("close", timeout_s=SHORT_TIMEOUT_S)
                except SamClientError:
                    pass

    def close(self) -> None:
        """Stop the worker (plugin unload); a request still running is not waited for."""
        self._view, self.info = None, None
        self._transport.close()


# ------------------------------------------------------------------------------------------------
# The session's client
# ------------------------------------------------------------------------------------------------

_session: SessionClient[SamClient] = SessionClient(lambda: SamClient(default_argv))


def default_argv() -> list[str]:
    """The worker command from the plugin settings (the overseec environment's ``overseec``)."""
    return worker_argv(require_worker(SamWorkerError, "run SAM in"))


def shared_client() -> SamClient:
    """The one SAM client of this QGIS session (its worker starts with the first view)."""
    return _session.get()


def close_shared_client() -> None:
    """Stop the session's SAM worker (plugin unload); a later view starts a new one."""
    _session.close()
