"""Streaming tiling engine: window grid (slicer), blending (merger) and the driver between them.

A model sees fixed-size tiles read in windows; its per-class maps are blended where tiles overlap
with a smooth weight window normalised by the summed weights, accumulated in a buffer a few tile
rows tall, and written out as soon as rows are complete. Memory is bounded by
``channels x (tile + block) x width`` floats, never by the image height.

Tiles at the right and bottom edges are shifted back inside the image (never padded), so every
tile has the same size and can be batched; an image smaller than a tile is one tile of its size.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import Protocol, TypeVar

import numpy as np
from rasterio.windows import Window

from overseec_core import defaults
from overseec_core.errors import TilingError
from overseec_core.locate.stages import StageClock, ThreadStage, pipeline
from overseec_core.progress import Progress, check_cancelled

BLEND_MODES = defaults.BLEND_MODES
T = TypeVar("T")
R = TypeVar("R")
G = TypeVar("G")

#: A batch model: (B, h, w, 3) uint8 RGB and (B, h, w) validity -> (B, C, h, w) float maps.
BatchPredictor = Callable[[np.ndarray, np.ndarray], np.ndarray]


# --------------------------------------------------------------------------------------------
# Slicer: pure window arithmetic
# --------------------------------------------------------------------------------------------


def axis_offsets(length: int, tile: int, overlap: int) -> list[int]:
    """Start offsets of tiles along one axis; the last tile ends exactly at ``length``."""
    if length <= tile:
        return [0]
    stride = tile - overlap
    offsets = list(range(0, length - tile, stride))
    offsets.append(length - tile)
    return sorted(set(offsets))


@dataclass(frozen=True)
class TileGrid:
    """Overlapping tiles covering a ``width`` x ``height`` image, in row-major order."""

    width: int
    height: int
    tile_size: int = 512
    overlap: int = 64

    def __post_init__(self) -> None:
        if self.width <= 0 or self.height <= 0:
            raise TilingError(f"image size must be positive, got {self.width}x{self.height}")
        if self.tile_size < 8:
            raise TilingError(f"tile size must be at least 8 pixels, got {self.tile_size}")
        if not 0 <= self.overlap < self.tile_size:
            raise TilingError(
                f"overlap must be in 0..{self.tile_size - 1} for {self.tile_size} px tiles, got {self.overlap}"
            )

    @property
    def tile_shape(self) -> tuple[int, int]:
        """(h, w) of every tile: the tile size, clipped to a smaller image."""
        return (min(self.tile_size, self.height), min(self.tile_size, self.width))

    def row_offsets(self) -> list[int]:
        return axis_offsets(self.height, self.tile_size, self.overlap)

    def col_offsets(self) -> list[int]:
        return axis_offsets(self.width, self.tile_size, self.overlap)

    def windows(self) -> list[Window]:
        h, w = self.tile_shape
        return [Window(c, r, w, h) for r in self.row_offsets() for c in self.col_offsets()]

    def __len__(self) -> int:
        return len(self.row_offsets()) * len(self.col_offsets())


def blend_weights(shape: tuple[int, int], mode: str = "hann") -> np.ndarray:
    """Per-pixel weights of one tile: strictly positive so every covered pixel is defined.

    ``hann``: separable sin^2 window sampled at pixel centres, so edges get tiny but non-zero
    weight and overlaps cross-fade smoothly; ``mean`` and ``max``: flat.
    """
    if mode not in BLEND_MODES:
        raise TilingError(f"unknown blend mode {mode!r}; choose one of {', '.join(BLEND_MODES)}")
    h, w = shape
    if mode != "hann":
        return np.ones((h, w), np.float32)
    wy = np.sin(np.pi * (np.arange(h) + 0.5) / h) ** 2
    wx = np.sin(np.pi * (np.arange(w) + 0.5) / w) ** 2
    return np.outer(wy, wx).astype(np.float32)


# --------------------------------------------------------------------------------------------
# Merger: streaming accumulation
# --------------------------------------------------------------------------------------------


class RowSink(Protocol):
    """Receives finished rows: (C, h, W) float32 starting at ``row_off``."""

    def __call__(self, rows: np.ndarray, row_off: int) -> None: ...


class StreamingBlender:
    """Accumulates weighted tile predictions and emits rows once no later tile can touch them.

    Call :meth:`add` for tiles in row-major order and :meth:`flush_before` with the first row a
    later tile may still cover; :meth:`close` emits the rest. Pixels no valid tile covered come out
    as ``fill`` (NaN by default, the outputs' nodata). The buffers are allocated once for
    ``capacity_rows`` rows and reused; rows handed to the sink are a view it may modify in place.
    """

    def __init__(
        self,
        width: int,
        height: int,
        channels: int,
        sink: RowSink,
        mode: str = "hann",
        flush_rows: int = 1,
        fill: float = np.nan,
        capacity_rows: int = 0,
    ) -> None:
        if mode not in BLEND_MODES:
            raise TilingError(f"unknown blend mode {mode!r}; choose one of {', '.join(BLEND_MODES)}")
        self.width, self.height, self.channels = width, height, channels
        self.sink, self.mode, self.fill = sink, mode, fill
        self.flush_rows = max(1, flush_rows)
        self._init = -np.inf if mode == "max" else 0.0
        self._start = 0  # image row of buffer row 0
        self._used = 0  # buffer rows holding data
        self._values = np.full((channels, capacity_rows, width), self._init, np.float32)
        self._weights = np.zeros((capacity_rows, width), np.float32)
        self._scratch = np.empty(0, np.float32)  # weighted tile, reused (no allocation per tile)
        self.peak_buffer_rows = 0

    def _ensure_rows(self, end_row: int) -> None:
        need = end_row - self._start
        self._used = max(self._used, need)
        self.peak_buffer_rows = max(self.peak_buffer_rows, need)
        have = self._weights.shape[0]
        if need <= have:
            return
        extra = need - have
        self._values = np.concatenate(
            [self._values, np.full((self.channels, extra, self.width), self._init, np.float32)], axis=1
        )
        self._weights = np.concatenate([self._weights, np.zeros((extra, self.width), np.float32)])

    def add(self, window: Window, pred: np.ndarray, weight: np.ndarray, valid: np.ndarray) -> None:
        """Blend one tile's (C, h, w) prediction; pixels where ``valid`` is False are ignored."""
        r0, c0 = int(window.row_off), int(window.col_off)
        h, w = int(window.height), int(window.width)
        if r0 < self._start:
            raise TilingError(f"tile at row {r0} arrived after rows up to {self._start} were written")
        self._ensure_rows(r0 + h)
        rows = slice(r0 - self._start, r0 - self._start + h)
        cols = slice(c0, c0 + w)
        all_valid = bool(valid.all())
        wv = weight if all_valid else np.where(valid, weight, np.float32(0))
        target = self._values[:, rows, cols]
        if self.mode == "max":
            np.maximum(target, pred if all_valid else np.where(valid, pred, -np.inf), out=target)
        else:
            if self._scratch.size != pred.size:
                self._scratch = np.empty(pred.shape, np.float32)
            scratch = self._scratch.reshape(pred.shape)
            np.multiply(pred, wv, out=scratch)
            target += scratch
        self._weights[rows, cols] += wv

    def flush_before(self, row: int, final: bool = False) -> None:
        """Emit finished rows below ``row`` (whole multiples of ``flush_rows`` unless final)."""
        row = min(row, self.height)
        n = row - self._start
        if not final:
            n -= n % self.flush_rows
        if n <= 0:
            return
        self._ensure_rows(self._start + n)
        values, weights = self._values[:, :n], self._weights[:n]
        uncovered = weights <= 0
        if not uncovered.any():
            if self.mode != "max":
                values /= weights
        else:
            if self.mode != "max":
                np.divide(values, weights, out=values, where=~uncovered)
            values[:, uncovered] = self.fill
        self.sink(values, self._start)
        self._shift(n)

    def _shift(self, n: int) -> None:
        """Drop the first ``n`` buffer rows, moving the rest to the top."""
        rest = max(0, self._used - n)
        if rest:
            self._values[:, :rest] = self._values[:, n : n + rest]
            self._weights[:rest] = self._weights[n : n + rest]
        self._values[:, rest : self._used] = self._init
        self._weights[rest : self._used] = 0
        self._start += n
        self._used = rest

    def close(self) -> None:
        self.flush_before(self.height, final=True)


# --------------------------------------------------------------------------------------------
# Driver: the tile loop's model and blending stages (the thread pipeline is locate/stages.py)
# --------------------------------------------------------------------------------------------


def blend_groups(
    blender: StreamingBlender, weight: np.ndarray, next_rows: Sequence[int]
) -> Callable[[tuple[list, list]], None]:
    """A function blending (chips, maps) groups given in tile order, a map of None meaning "no
    prediction here", and flushing the rows above the next tile after each tile."""
    index = 0

    def blend(group: tuple[list, list]) -> None:
        nonlocal index
        chips, maps = group
        for chip, pred in zip(chips, maps):
            if pred is not None:
                blender.add(chip.window, pred, weight, chip.valid)
            blender.flush_before(next_rows[index])  # rows above the next tile are final
            index += 1

    return blend


def drive_in_order(
    groups: Iterable[G],
    model: Callable[[G], tuple[list, list]],
    blender: StreamingBlender,
    weight: np.ndarray,
    next_rows: Sequence[int],
    progress: Progress | None,
    stage: str,
    clock: StageClock | None = None,
) -> None:
    """The tile loop's last two stages: ``model`` runs in the caller's thread on each group (read
    ahead by a :func:`pipeline`), returning (chips, maps); a :class:`ThreadStage` thread blends them in
    tile order and writes the finished rows through the blender's sink, ``PREDICT_AHEAD`` groups
    waiting at most. The model stays in the caller's thread: CUDA streams, autocast and torch's CPU
    thread pool (and the memory it caches) are those of the thread that loaded the model.
    Cancellation is checked before each group."""
    if progress is not None:
        progress.begin(stage, len(next_rows), "tile")
    try:
        with ThreadStage("blend+write", blend_groups(blender, weight, next_rows), PREDICT_AHEAD, clock) as post:
            for group in groups:
                check_cancelled(progress)
                t0 = time.perf_counter()
                chips, maps = model(group)
                if clock is not None:
                    clock.add("model", time.perf_counter() - t0)
                post.submit((chips, maps))
                if progress is not None:
                    progress.advance(len(chips))
                del chips, maps  # the worker holds them until blended
        blender.close()
    finally:
        if progress is not None:
            progress.end()


# --------------------------------------------------------------------------------------------
# Driver
# --------------------------------------------------------------------------------------------


class ChipReader(Protocol):
    """Anything that reads RGB chips by window (a :class:`overseec_core.io.read.RasterSource`)."""

    def read_chip(self, window: Window): ...


@dataclass(frozen=True)
class StreamStats:
    """What a streaming run did: counts and where the time went (stage seconds overlap)."""

    tiles: int
    tiles_skipped: int
    batches: int
    seconds: float
    seconds_reading: float
    seconds_predicting: float
    peak_buffer_rows: int
    seconds_blending: float = 0.0  # blending and writing (one thread)


#: Batches read ahead of the model, and predicted batches waiting to be blended and written.
READ_AHEAD, PREDICT_AHEAD = 2, 1


def _batches(windows: Sequence[Window], size: int) -> Iterator[list[Window]]:
    for i in range(0, len(windows), size):
        yield list(windows[i : i + size])


def stream_predict(
    source: ChipReader,
    predict: BatchPredictor,
    sink: RowSink,
    grid: TileGrid,
    channels: int,
    blend: str = "hann",
    batch_size: int = 4,
    flush_rows: int = 1,
    skip_empty: bool = True,
    progress: Progress | None = None,
    stage: str = "predict",
) -> StreamStats:
    """Run ``predict`` over every tile of ``grid`` and stream the blended maps to ``sink``.

    Three overlapping stages: a reader thread reads chips up to ``READ_AHEAD`` batches ahead, the
    model runs in the caller's thread, and a worker thread blends in tile order and writes the
    finished rows (:func:`drive_in_order`). Tiles with no valid pixel are skipped when
    ``skip_empty`` is set.
    """
    if batch_size < 1:
        raise TilingError(f"batch size must be at least 1, got {batch_size}")
    windows = grid.windows()
    weight = blend_weights(grid.tile_shape, blend)
    clock = StageClock()
    t0 = time.perf_counter()
    skipped = 0

    def read(batch: list[Window]) -> list:
        return [source.read_chip(w) for w in batch]

    def model(chips: list) -> tuple[list, list]:
        nonlocal skipped
        wanted = [c.any_valid or not skip_empty for c in chips]
        keep = [c for c, w in zip(chips, wanted) if w]
        skipped += len(chips) - len(keep)
        preds = iter(_predict_checked(predict, keep, channels) if keep else ())
        return chips, [next(preds) if w else None for w in wanted]

    batches = list(_batches(windows, batch_size))
    next_rows = [int(w.row_off) for w in windows[1:]] + [grid.height]
    blender = StreamingBlender(
        grid.width, grid.height, channels, sink, blend, flush_rows, capacity_rows=grid.tile_shape[0] + flush_rows
    )
    with contextlib.closing(pipeline(batches, [("read", read, READ_AHEAD)], clock)) as chips:
        drive_in_order(chips, model, blender, weight, next_rows, progress, stage, clock)
    busy = clock.busy
    return StreamStats(
        tiles=len(windows),
        tiles_skipped=skipped,
        batches=len(batches),
        seconds=time.perf_counter() - t0,
        seconds_reading=busy.get("read", 0.0),
        seconds_predicting=busy.get("model", 0.0),
        peak_buffer_rows=blender.peak_buffer_rows,
        seconds_blending=busy.get("blend+write", 0.0),
    )


def _predict_checked(predict: BatchPredictor, chips: list, channels: int) -> np.ndarray:
    rgb = np.stack([c.rgb for c in chips])
    valid = np.stack([c.valid for c in chips])
    preds = np.asarray(predict(rgb, valid), dtype=np.float32)
    expected = (len(chips), channels, rgb.shape[1], rgb.shape[2])
    if preds.shape != expected:
        raise TilingError(
            f"model returned maps of shape {preds.shape}, expected {expected} (batch, classes, tile height, tile width)"
        )
    return preds


def writer_sink(writer, dtype: str | None = None) -> RowSink:
    """A sink that writes rows into a :class:`overseec_core.io.write.RasterWriter`.

    Integer outputs are rounded and clipped to the dtype's range; NaN becomes the writer's nodata.
    Works in place on the rows it is given (the blender's buffer view).
    """
    out_dtype = np.dtype(dtype or writer.dtype)
    nodata = writer.nodata

    def sink(rows: np.ndarray, row_off: int) -> None:
        needs_fill = out_dtype.kind in "iu" or (nodata is not None and not np.isnan(nodata))
        missing = np.isnan(rows) if needs_fill else None
        if missing is not None and not missing.any():
            missing = None
        if out_dtype.kind in "iu":
            info = np.iinfo(out_dtype)
            np.rint(rows, out=rows)
            # minimum/maximum ufuncs: numpy 1.24's np.clip goes through a slow Python wrapper
            np.minimum(rows, info.max, out=rows)
            np.maximum(rows, info.min, out=rows)
            if missing is not None:
                rows[missing] = nodata if nodata is not None else 0
        elif missing is not None:
            rows[missing] = nodata
        writer.write(rows.astype(out_dtype, copy=False), row_off)

    return sink
