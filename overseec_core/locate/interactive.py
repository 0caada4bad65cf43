"""Click to fix a mask: SAM prompted with include/exclude points and a box on one view of the image.

A :class:`FixSession` holds one *view*: a window of the image (read with
:class:`~overseec_core.io.read.RasterSource`, whole pixels, at most :data:`MAX_VIEW_PX` a side)
that ``transformers``' ``SamProcessor`` resizes to SAM's input (longest side = the model's
``image_size``, zero-padded). SAM's image encoder runs once per view (:meth:`FixSession.embed_ms`
reports its time, :attr:`FixSession.encoder_calls` counts it); each prompt runs only the prompt
encoder and the mask decoder on that embedding, then ``SamProcessor.post_process_masks`` brings the
low-resolution logits back to the window's own pixels. Coordinates come in the image's CRS.

A prompt answers SAM's mask (the *candidate*) and the entity's *edited* mask on the window: the
existing mask of the segment folder combined with the candidate by a mode -- ``add`` (union, the
default: click a missed object), ``remove`` (click a false one) or ``replace`` (the window becomes
SAM's mask). Pixels without image data or with the mask's nodata are never changed.

:meth:`FixSession.apply` writes the edited mask into the entity's band of the folder's mask raster
(:func:`overseec_core.runfiles.first_existing` ``"mask"``: refined masks over coarse ones), its
probability band (SAM's probability on added pixels, 0 on removed ones, so a refined mask stays
``probs >= 0.5``) and, beside refined masks, the gated band (probability x mask), inside the window
only. Each file is copied beside itself, updated in place with rasterio (overviews rebuilt when it
has them), checked and renamed over the original (:mod:`overseec_core.locate.maskfiles`), all
files inside one output transaction: a failure leaves every file as it was, never a half-written
file under its name. The edit is
recorded in ``manifest.json`` (section ``mask_edits``), and ``overseec costmap --masks DIR`` reads
the edited files like any others.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import math
import os
import time
import uuid
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from rasterio.features import shapes
from rasterio.transform import Affine
from rasterio.windows import Window
from rasterio.windows import from_bounds as window_from_bounds
from rasterio.windows import transform as window_transform

from overseec_core.errors import InputError, OutputError
from overseec_core.io.grid import Grid
from overseec_core.io.manifest import RunDir, read_manifest
from overseec_core.io.read import RasterSource, open_raster
from overseec_core.io.transaction import output_transaction
from overseec_core.locate.entities import MASK_NODATA
from overseec_core.locate.maskfiles import MaskFiles, read_window, scaled, write_window
from overseec_core.locate.models import DEFAULT_SAM, autocast, load_aux
from overseec_core.locate.sam_model import SamBundle, load_sam

#: Longest side of a view in image pixels: SAM sees it at its input size (1024 px), so a larger
#: window only loses detail, and the masks it answers grow with the square of it.
MAX_VIEW_PX = 2048
#: How the candidate combines with the existing mask.
MODES = ("add", "remove", "replace")
DEFAULT_MODE = "add"
#: Most points in one prompt.
MAX_POINTS = 64
#: Most polygon vertices :func:`mask_polygons` returns (the largest polygons first).
MAX_VERTICES = 50_000
#: Most pixel edges an overlay outline is traced from (:func:`mask_outline`): a smooth object has
#: hundreds; a speckled mask (random weights: 240 000 on a 1024 px view, 0.3-0.6 s to trace and
#: 140 000 vertices to send and draw) is shown at a coarser scale instead.
MAX_OUTLINE_EDGES = 20_000
#: The manifest section edits are recorded in.
MANIFEST_SECTION = "mask_edits"


# --------------------------------------------------------------------------------------------
# Prompts and answers
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Prompt:
    """What the user clicked, in the image's CRS: include (label 1) and exclude (0) points, a box."""

    points: tuple[tuple[float, float], ...] = ()
    labels: tuple[int, ...] = ()
    box: tuple[float, float, float, float] | None = None  # xmin, ymin, xmax, ymax

    def check(self) -> None:
        """Raise a one-line InputError for a prompt SAM cannot take."""
        if not self.points and self.box is None:
            raise InputError("a prompt needs at least one point or a box")
        if len(self.points) != len(self.labels):
            raise InputError(f"{len(self.points)} points but {len(self.labels)} labels")
        if len(self.points) > MAX_POINTS:
            raise InputError(f"at most {MAX_POINTS} points per prompt, not {len(self.points)}")
        if any(label not in (0, 1) for label in self.labels):
            raise InputError("point labels are 1 (include) or 0 (exclude)")
        values = [v for p in self.points for v in p] + list(self.box or ())
        if not all(math.isfinite(v) for v in values):
            raise InputError("prompt coordinates must be finite numbers")
        if self.box is not None and not (self.box[0] < self.box[2] and self.box[1] < self.box[3]):
            raise InputError("a box is [xmin, ymin, xmax, ymax] with xmin < xmax and ymin < ymax")

    def to_json(self) -> dict[str, Any]:
        return {
            "points": [list(p) for p in self.points],
            "labels": list(self.labels),
            "box": None if self.box is None else list(self.box),
        }


@dataclass
class MaskAnswer:
    """SAM's answer to one prompt on the view's pixels, and the entity's mask edited with it."""

    entity: str
    mode: str
    probability: np.ndarray  # (h, w) float32: SAM's probability (sigmoid of its logits)
    candidate: np.ndarray  # (h, w) bool: SAM's mask (probability > 0.5), image data only
    mask: np.ndarray  # (h, w) bool: the edited mask (what apply writes)
    added: np.ndarray  # (h, w) bool: pixels the edit turns on
    removed: np.ndarray  # (h, w) bool: pixels the edit turns off
    score: float  # SAM's predicted IoU of the candidate
    timings_ms: dict[str, float] = field(default_factory=dict)


@dataclass(frozen=True)
class View:
    """The window of the image a session works on, with its georeferencing."""

    window: Window
    transform: Affine  # the window's own (pixel (0, 0) at its corner)
    crs: Any

    @property
    def shape(self) -> tuple[int, int]:
        return int(self.window.height), int(self.window.width)

    def bounds(self) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) of the window's pixels in the image's CRS."""
        h, w = self.shape
        xs, ys = zip(*(self.transform * (c, r) for c, r in ((0, 0), (w, 0), (0, h), (w, h))))
        return min(xs), min(ys), max(xs), max(ys)

    def to_pixels(self, xs: np.ndarray, ys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Continuous (col, row) in the window (pixel edges at whole numbers) of map points."""
        cols, rows = ~self.transform * (np.asarray(xs, float), np.asarray(ys, float))
        return np.asarray(cols, float), np.asarray(rows, float)

    def to_json(self) -> dict[str, Any]:
        w = self.window
        t = self.transform
        return {
            "window": [int(w.col_off), int(w.row_off), int(w.width), int(w.height)],
            "bounds": list(self.bounds()),
            "transform": [t.a, t.b, t.c, t.d, t.e, t.f],
            "crs": self.crs.to_wkt(),
        }


def view_window(grid: Grid, bounds: Sequence[float], max_px: int = MAX_VIEW_PX) -> Window:
    """The whole-pixel window of ``grid`` covering ``bounds`` (xmin, ymin, xmax, ymax, in the
    grid's CRS), clipped to the image; a one-line InputError when it is empty or too large."""
    if len(bounds) != 4 or not all(math.isfinite(v) for v in bounds):
        raise InputError("view bounds are [xmin, ymin, xmax, ymax] in the image's CRS")
    xmin, ymin, xmax, ymax = (float(v) for v in bounds)
    if not (xmin < xmax and ymin < ymax):
        raise InputError("view bounds need xmin < xmax and ymin < ymax")
    # clipped to the image's own extent first: the window arithmetic stays finite for any bounds
    xs, ys = zip(
        *(grid.transform * (c, r) for c, r in ((0, 0), (grid.width, 0), (0, grid.height), (grid.width, grid.height)))
    )
    xmin, ymin, xmax, ymax = max(xmin, min(xs)), max(ymin, min(ys)), min(xmax, max(xs)), min(ymax, max(ys))
    if not (xmin < xmax and ymin < ymax):
        raise InputError("the view does not overlap the image")
    win = window_from_bounds(xmin, ymin, xmax, ymax, transform=grid.transform)
    c0, r0 = max(0, math.floor(win.col_off + 1e-6)), max(0, math.floor(win.row_off + 1e-6))
    c1 = min(grid.width, math.ceil(win.col_off + win.width - 1e-6))
    r1 = min(grid.height, math.ceil(win.row_off + win.height - 1e-6))
    if c1 <= c0 or r1 <= r0:
        raise InputError("the view does not overlap the image")
    if max(c1 - c0, r1 - r0) > max_px:
        raise InputError(
            f"the view is {c1 - c0} x {r1 - r0} image pixels; zoom in to at most {max_px} px a side "
            "(SAM sees the view at its input size)"
        )
    return Window(c0, r0, c1 - c0, r1 - r0)


def combine(existing: np.ndarray, candidate: np.ndarray, editable: np.ndarray, mode: str) -> np.ndarray:
    """The edited mask: ``existing`` with ``candidate`` added, removed or swapped in (``mode``),
    on ``editable`` pixels only."""
    if mode == "add":
        new = existing | candidate
    elif mode == "remove":
        new = existing & ~candidate
    elif mode == "replace":
        new = candidate.copy()
    else:
        raise InputError(f"unknown mode {mode!r}; use one of {', '.join(MODES)}")
    return np.where(editable, new, existing)


def mask_polygons(
    mask: np.ndarray, transform: Affine, max_vertices: int = MAX_VERTICES
) -> tuple[list[list[list[list[float]]]], bool]:
    """The mask's pixel outlines as polygons in map coordinates (each a list of rings, the outer
    first; each ring a closed list of [x, y]), the largest first; and whether some were left out to
    stay within ``max_vertices``."""
    polys: list[tuple[float, list[list[list[float]]]]] = []
    if mask.any():
        for geom, _value in shapes(mask.astype(np.uint8), mask=mask, transform=transform):
            rings = [[[float(x), float(y)] for x, y in ring] for ring in geom["coordinates"]]
            polys.append((_ring_area(rings[0]), rings))
    polys.sort(key=lambda p: -p[0])
    out: list[list[list[list[float]]]] = []
    used = 0
    for _area, rings in polys:
        n = sum(len(r) for r in rings)
        if used + n > max_vertices:
            return out, True
        out.append(rings)
        used += n
    return out, False


def _edges(mask: np.ndarray) -> int:
    """Pixel edges between mask and background (the outline's length in pixel sides)."""
    return int(np.count_nonzero(mask[1:] != mask[:-1]) + np.count_nonzero(mask[:, 1:] != mask[:, :-1]))


def downsample_majority(mask: np.ndarray, k: int) -> np.ndarray:
    """A k x k block is on where at least half of its pixels are (edge blocks padded with off)."""
    h, w = mask.shape
    padded = np.zeros((-(-h // k) * k, -(-w // k) * k), np.float32)
    padded[:h, :w] = mask
    return padded.reshape(padded.shape[0] // k, k, padded.shape[1] // k, k).mean(axis=(1, 3)) >= 0.5


def mask_outline(
    mask: np.ndarray, transform: Affine, max_edges: int = MAX_OUTLINE_EDGES, max_vertices: int = MAX_VERTICES
) -> tuple[list[list[list[list[float]]]], bool, int]:
    """:func:`mask_polygons` of the mask for an overlay, at the finest scale (1, 2, 4 ... image
    pixels per cell, majority of each cell) whose outline has at most ``max_edges`` pixel edges, so
    that tracing, sending and drawing it stay bounded; also returns that scale."""
    k, shown = 1, mask
    while _edges(shown) > max_edges and k < 64:
        k *= 2
        shown = downsample_majority(mask, k)
    polygons, truncated = mask_polygons(shown, transform * Affine.scale(k), max_vertices)
    return polygons, truncated, k


def _ring_area(ring: list[list[float]]) -> float:
    xy = np.asarray(ring)
    return 0.5 * abs(float(np.dot(xy[:-1, 0], xy[1:, 1]) - np.dot(xy[1:, 0], xy[:-1, 1])))


# --------------------------------------------------------------------------------------------
# The session
# --------------------------------------------------------------------------------------------


@contextlib.contextmanager
def _torch_threads(n: int | None) -> Iterator[None]:
    """Run the block on ``n`` CPU threads (None: as set); the earlier count is restored."""
    if n is None:
        yield
        return
    import torch

    before = torch.get_num_threads()
    torch.set_num_threads(n)
    try:
        yield
    finally:
        torch.set_num_threads(before)


def sam_processor(bundle: SamBundle) -> Any:
    """The checkpoint's ``SamProcessor``; one built from the bundle's values when it has none."""
    from transformers import SamImageProcessor, SamProcessor

    proc = load_aux(SamProcessor.from_pretrained, bundle.ref)
    if proc is None:
        s = bundle.image_size
        image = SamImageProcessor(
            size={"longest_edge": s},
            pad_size={"height": s, "width": s},
            image_mean=list(bundle.mean),
            image_std=list(bundle.std),
            rescale_factor=bundle.rescale,
        )
        proc = SamProcessor(image)
    return proc


def default_sam_model(folder: str | os.PathLike) -> str:
    """The SAM the segment folder was refined with (its manifest), else the default checkpoint."""
    try:
        manifest = read_manifest(folder) or {}
    except OutputError:
        manifest = {}
    sam = (manifest.get("models") or {}).get("sam") or {}
    path = sam.get("path")
    if isinstance(path, str) and Path(path).is_dir():
        return path
    name = sam.get("name")
    return name if isinstance(name, str) and name else DEFAULT_SAM


class FixSession:
    """SAM's embedding of one view of an image, answering prompts for a segment folder's entities
    (see the module docstring).

    The encoder runs on torch's threads as set; the mask decoder on ``decoder_threads`` (default
    1, None: as set). A click's decoder work is small, and on a CPU shared with other programs a
    thread pool spends more waiting for its threads than it saves (bench/bench_fix_mask.py)."""

    def __init__(
        self,
        image: str | os.PathLike,
        segment_dir: str | os.PathLike,
        bounds: Sequence[float],
        model: str | None = None,
        device: str = "auto",
        precision: str = "auto",
        bands: Sequence[int] | str | None = None,
        max_view_px: int = MAX_VIEW_PX,
        decoder_threads: int | None = 1,
    ) -> None:
        self.image = Path(image)
        self.files = MaskFiles.find(segment_dir)
        self.bundle = load_sam(model or default_sam_model(segment_dir), device, precision)
        self.processor = sam_processor(self.bundle)
        with RasterSource(self.image, bands) as src:
            if not src.grid.same_as(self.files.grid):
                raise InputError(f"{self.image} and {self.files.mask} are not on the same pixel grid")
            window = view_window(src.grid, bounds, max_view_px)
            chip = src.read_chip(window)
        self.view = View(window, window_transform(window, src.grid.transform), src.grid.crs)
        self.valid = chip.valid
        self.decoder_threads = decoder_threads
        self.encoder_calls = 0
        self.embed_ms = 0.0
        self._embed(chip.rgb)
        self._existing: dict[str, tuple[tuple[int, int], np.ndarray]] = {}
        self._warm_up()

    def _warm_up(self) -> None:
        """One decoder pass on a point at the view's centre, so the first click does not pay the
        decoder's first-call set-up (about twice a click's time on a CPU)."""
        h, w = self.view.shape
        x, y = self.view.transform * (w / 2, h / 2)
        self.decode(Prompt(((float(x), float(y)),), (1,)))

    def _embed(self, rgb: np.ndarray) -> None:
        """The library's pre-processing, then SAM's image encoder (once per view)."""
        import torch

        b = self.bundle
        t0 = time.perf_counter()
        enc = self.processor(images=rgb, return_tensors="pt")
        self.original_size = tuple(int(v) for v in enc["original_sizes"][0])
        self.reshaped_size = tuple(int(v) for v in enc["reshaped_input_sizes"][0])
        with torch.inference_mode(), autocast(b.device, b.precision):
            self.embedding = b.model.get_image_embeddings(enc["pixel_values"].to(b.device))
        self.encoder_calls += 1
        self.embed_ms = 1000.0 * (time.perf_counter() - t0)

    # -- prompts -------------------------------------------------------------------------------

    def _model_inputs(self, prompt: Prompt) -> dict[str, Any]:
        """Points and box on SAM's input frame (what SamProcessor's coordinate scaling gives)."""
        import torch

        (oh, ow), (nh, nw) = self.original_size, self.reshaped_size
        scale = np.array([nw / ow, nh / oh])
        h, w = self.view.shape
        dev = self.bundle.device
        inputs: dict[str, Any] = {"input_points": None, "input_labels": None, "input_boxes": None}
        if prompt.points:
            xs, ys = zip(*prompt.points)
            cols, rows = self.view.to_pixels(np.array(xs), np.array(ys))
            if ((cols < 0) | (cols > w) | (rows < 0) | (rows > h)).any():
                raise InputError("a point lies outside the view; open a view that contains it")
            # SAM's prompt encoder takes pixel indices (it adds 0.5 itself): edges -> index space
            px = np.stack([cols - 0.5, rows - 0.5], axis=-1) * scale
            inputs["input_points"] = torch.tensor(px[None, None], dtype=torch.float32, device=dev)
            inputs["input_labels"] = torch.tensor([[list(prompt.labels)]], dtype=torch.int64, device=dev)
        if prompt.box is not None:
            x0, y0, x1, y1 = prompt.box
            cols, rows = self.view.to_pixels(np.array([x0, x1]), np.array([y0, y1]))
            c0, c1 = np.clip(np.sort(cols), 0, w)
            r0, r1 = np.clip(np.sort(rows), 0, h)
            if c1 - c0 < 1 or r1 - r0 < 1:
                raise InputError("the box lies outside the view (or is under one pixel)")
            box = np.array([c0, r0, c1, r1]) - 0.5
            box = box * np.tile(scale, 2)
            inputs["input_boxes"] = torch.tensor(box[None, None], dtype=torch.float32, device=dev)
        return inputs

    def decode(self, prompt: Prompt) -> tuple[np.ndarray, float, dict[str, float]]:
        """SAM's logits on the view's pixels for a prompt (mask decoder only), its predicted IoU,
        and the time the steps took (ms). One include point alone is ambiguous: SAM answers three
        masks and the best-scored one is kept, as SAM's own predictor does."""
        import torch

        prompt.check()
        b = self.bundle
        multimask = prompt.box is None and len(prompt.points) == 1
        with _torch_threads(self.decoder_threads):
            t0 = time.perf_counter()
            with torch.inference_mode(), autocast(b.device, b.precision):
                out = b.model(image_embeddings=self.embedding, multimask_output=multimask, **self._model_inputs(prompt))
                scores = out.iou_scores[0, 0].float()
                best = int(torch.argmax(scores))
                low = out.pred_masks[0, :, best : best + 1].float()  # (1, 1, m, m)
            t1 = time.perf_counter()
            logits = self.processor.post_process_masks(
                [low.cpu()], [self.original_size], [self.reshaped_size], binarize=False
            )[0][0, 0]
            t2 = time.perf_counter()
        timings = {"decoder_ms": 1000.0 * (t1 - t0), "postprocess_ms": 1000.0 * (t2 - t1)}
        return logits.numpy(), float(scores[best]), timings

    def existing(self, entity: str) -> tuple[np.ndarray, np.ndarray]:
        """The entity's current mask on the view and where the mask raster holds data (re-read
        when the file changed on disk)."""
        stamp = self.files.stamp()
        cached = self._existing.get(entity)
        if cached is None or cached[0] != stamp:
            cached = (stamp, read_window(self.files.mask, self.files.band(entity), self.view.window))
            self._existing[entity] = cached
        band = cached[1]
        return (band > 0) & (band != MASK_NODATA), band != MASK_NODATA

    def prompt(self, entity: str, prompt: Prompt, mode: str = DEFAULT_MODE) -> MaskAnswer:
        """SAM's mask for a prompt and the entity's mask edited with it (nothing is written)."""
        if mode not in MODES:
            raise InputError(f"unknown mode {mode!r}; use one of {', '.join(MODES)}")
        self.files.band(entity)
        logits, score, timings = self.decode(prompt)
        with np.errstate(over="ignore"):
            prob = (1.0 / (1.0 + np.exp(-logits))).astype(np.float32)
        existing, has_data = self.existing(entity)
        editable = self.valid & has_data
        candidate = (logits > 0) & self.valid
        mask = combine(existing, candidate, editable, mode)
        added, removed = mask & ~existing, existing & ~mask
        return MaskAnswer(entity, mode, prob, candidate, mask, added, removed, score, timings)

    # -- apply -----------------------------------------------------------------------------------

    def apply(self, entity: str, prompt: Prompt, mode: str = DEFAULT_MODE) -> dict[str, Any]:
        """Write the entity's edited mask for this prompt into the segment folder (all files or
        none) and record the edit in its manifest; returns the manifest record with its key (``edit``)."""
        answer = self.prompt(entity, prompt, mode)
        band, win, files = self.files.band(entity), self.view.window, self.files
        written = []
        with output_transaction():
            mask = read_window(files.mask, band, win)
            mask[answer.added], mask[answer.removed] = 1, 0
            write_window(files.mask, band, win, mask)
            written.append(files.mask.name)
            for path in (files.probability, files.gated):
                if path is None:
                    continue
                with open_raster(path) as ds:
                    dtype = np.dtype(ds.dtypes[band - 1])
                values = read_window(path, band, win)
                values[answer.added] = scaled(answer.probability, dtype)[answer.added]
                values[answer.removed] = 0
                write_window(path, band, win, values)
                written.append(path.name)
            edit_id, record = self._record(answer, prompt, written)
            run = RunDir(files.folder)
            run.set_entry(MANIFEST_SECTION, edit_id, record)
            run.save()
        self._existing.pop(entity, None)
        return {"edit": edit_id, **record}

    def _record(self, answer: MaskAnswer, prompt: Prompt, written: list[str]) -> tuple[str, dict[str, Any]]:
        """The edit's manifest key (sortable by time, unique) and record."""
        now = _dt.datetime.now(_dt.UTC)
        return f"{now.strftime('%Y%m%dT%H%M%S')}-{uuid.uuid4().hex[:6]}", {
            "at": now.isoformat(timespec="seconds"),
            "entity": answer.entity,
            "mode": answer.mode,
            "image": str(self.image.resolve()),
            "view": {k: v for k, v in self.view.to_json().items() if k in ("window", "bounds")},
            "prompt": prompt.to_json(),
            "model": self.bundle.ref.to_json(),
            "score": answer.score,
            "pixels_added": int(answer.added.sum()),
            "pixels_removed": int(answer.removed.sum()),
            "files": written,
        }

    def describe(self) -> dict[str, Any]:
        """The view, the entities, the model and the embedding's cost, for the worker's answer."""
        return {
            **self.view.to_json(),
            "image": str(self.image),
            "segment_dir": str(self.files.folder),
            "mask_file": self.files.mask.name,
            "entities": list(self.files.entities),
            "model": self.bundle.ref.name,
            "device": str(self.bundle.device),
            "input_size": list(self.reshaped_size),
            "embed_ms": round(self.embed_ms, 3),
            "encoder_calls": self.encoder_calls,
        }


__all__ = [
    "DEFAULT_MODE",
    "MANIFEST_SECTION",
    "MAX_VIEW_PX",
    "MODES",
    "FixSession",
    "MaskAnswer",
    "MaskFiles",
    "Prompt",
    "View",
    "combine",
    "default_sam_model",
    "mask_outline",
    "mask_polygons",
    "sam_processor",
    "view_window",
    "write_window",
]
