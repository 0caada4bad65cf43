"""Tiling engine: exact window arithmetic, seam-free blending, bounded memory, cancellation."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import rasterio
from rasterio.windows import Window

from overseec_core.errors import Cancelled, TilingError
from overseec_core.io.read import RasterSource, read_grid
from overseec_core.io.write import RasterWriter
from overseec_core.locate.stages import ThreadStage, pipeline
from overseec_core.locate.tiling import (
    StreamingBlender,
    TileGrid,
    axis_offsets,
    blend_weights,
    stream_predict,
    writer_sink,
)
from overseec_core.progress import NullProgress

from ..conftest import write_tif


@pytest.mark.parametrize(
    "length,tile,overlap,expected",
    [
        (100, 512, 64, [0]),  # image smaller than a tile: one tile
        (512, 512, 64, [0]),
        (1000, 512, 64, [0, 448, 488]),  # last tile shifted back inside, never padded
        (896, 512, 64, [0, 384]),
        (960, 512, 64, [0, 448]),
        (10, 4, 0, [0, 4, 6]),
    ],
)
def test_axis_offsets(length: int, tile: int, overlap: int, expected: list[int]) -> None:
    assert axis_offsets(length, tile, overlap) == expected


def test_grid_covers_the_image_with_same_size_tiles() -> None:
    grid = TileGrid(1000, 700, 256, 32)
    covered = np.zeros((700, 1000), int)
    for w in grid.windows():
        assert (w.height, w.width) == (256, 256)
        covered[w.row_off : w.row_off + 256, w.col_off : w.col_off + 256] += 1
    assert covered.min() >= 1 and len(grid) == len(grid.windows())
    small = TileGrid(100, 60, 512, 64)
    assert small.tile_shape == (60, 100) and small.windows() == [Window(0, 0, 100, 60)]


@pytest.mark.parametrize(
    "kwargs,match",
    [
        (dict(width=0, height=10), "positive"),
        (dict(width=10, height=10, tile_size=64, overlap=64), "overlap"),
        (dict(width=10, height=10, tile_size=4), "at least 8"),
    ],
)
def test_grid_rejects_bad_geometry(kwargs: dict, match: str) -> None:
    with pytest.raises(TilingError, match=match):
        TileGrid(**kwargs)


def test_hann_weights_are_positive_and_peak_in_the_middle() -> None:
    w = blend_weights((64, 64), "hann")
    assert w.min() > 0 and w[32, 32] == pytest.approx(w.max()) and w[0, 0] < 1e-3
    with pytest.raises(TilingError):
        blend_weights((8, 8), "median")


# A test image that encodes each pixel's absolute position, so a 'model' that only sees pixels
# can return a known smooth function of absolute position.
def _position_image(tmp_path: Path, width: int, height: int) -> Path:
    rows, cols = np.mgrid[0:height, 0:width]
    data = np.stack([cols % 256, rows % 256, (cols // 256) * 16 + rows // 256]).astype(np.uint8)
    return write_tif(tmp_path / "pos.tif", data)


def _decode(rgb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r, g, b = (rgb[..., k].astype(np.float64) for k in range(3))
    return g + (b % 16) * 256, r + (b // 16) * 256  # rows, cols


def smooth(rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
    return np.stack([np.sin(cols / 37.0) * np.cos(rows / 53.0), rows / 1000.0 + cols / 2000.0])


def position_model(rgb: np.ndarray, valid: np.ndarray) -> np.ndarray:
    rows, cols = _decode(rgb)
    return np.moveaxis(smooth(rows, cols), 0, 1).astype(np.float32)


def _run(
    path: Path,
    out: Path,
    model,
    channels: int,
    blend: str = "hann",
    tile: int = 128,
    overlap: int = 32,
    batch: int = 3,
    progress=None,
):
    with RasterSource(path) as src:
        g = src.grid
        grid = TileGrid(g.width, g.height, tile, overlap)
        with RasterWriter(out, g, channels, "float32", nodata=float("nan")) as writer:
            stats = stream_predict(
                src,
                model,
                writer_sink(writer),
                grid,
                channels,
                blend=blend,
                batch_size=batch,
                flush_rows=writer.block_rows,
                progress=progress,
            )
    with rasterio.open(out) as ds:
        return ds.read(), stats


@pytest.mark.parametrize("blend", ["hann", "mean", "max"])
def test_smooth_function_of_position_comes_back_seamless(tmp_path: Path, blend: str) -> None:
    path = _position_image(tmp_path, 700, 530)
    result, stats = _run(path, tmp_path / "out.tif", position_model, 2, blend)
    rows, cols = np.mgrid[0:530, 0:700]
    truth = smooth(rows, cols)
    assert np.abs(result - truth).max() < 1e-3
    assert stats.tiles == len(TileGrid(700, 530, 128, 32)) and stats.tiles_skipped == 0


def test_constant_model_comes_back_constant(tmp_path: Path) -> None:
    path = _position_image(tmp_path, 300, 260)

    def constant(rgb, valid):
        return np.full((rgb.shape[0], 3, rgb.shape[1], rgb.shape[2]), 0.25, np.float32)

    result, _ = _run(path, tmp_path / "c.tif", constant, 3)
    assert np.all(result == np.float32(0.25))


def test_blending_removes_tile_edge_artefacts(tmp_path: Path) -> None:
    """A model that is wrong near its tile borders (as CNNs are) is healed by Hann blending."""
    path = _position_image(tmp_path, 600, 200)
    margin = 12

    def edgy(rgb, valid):
        out = position_model(rgb, valid)
        out[:, :, :margin, :] += 0.5
        out[:, :, -margin:, :] += 0.5
        out[:, :, :, :margin] += 0.5
        out[:, :, :, -margin:] += 0.5
        return out

    rows, cols = np.mgrid[0:200, 0:600]
    truth = smooth(rows, cols)
    hann, _ = _run(path, tmp_path / "h.tif", edgy, 2, "hann", tile=128, overlap=64)
    mean, _ = _run(path, tmp_path / "m.tif", edgy, 2, "mean", tile=128, overlap=64)
    interior = (slice(None), slice(margin, -margin), slice(margin, -margin))
    assert np.abs(hann - truth)[interior].mean() < 0.5 * np.abs(mean - truth)[interior].mean()


def test_memory_is_bounded_by_tile_rows_not_image_height(tmp_path: Path) -> None:
    sink_calls = []
    tall = StreamingBlender(64, 5000, 1, lambda rows, off: sink_calls.append((off, rows.shape[1])), flush_rows=32)
    grid = TileGrid(64, 5000, 64, 16)
    weight = blend_weights(grid.tile_shape)
    windows = grid.windows()
    for k, w in enumerate(windows):
        tall.add(w, np.ones((1, 64, 64), np.float32), weight, np.ones((64, 64), bool))
        nxt = windows[k + 1].row_off if k + 1 < len(windows) else 5000
        tall.flush_before(nxt)
    tall.close()
    assert tall.peak_buffer_rows <= 64 + 32
    assert sum(n for _, n in sink_calls) == 5000
    assert [off for off, _ in sink_calls] == sorted(off for off, _ in sink_calls)


def test_nodata_tiles_are_skipped_and_stay_nodata(tmp_path: Path) -> None:
    data = np.full((3, 256, 512), 100, np.uint8)
    data[:, :, 256:] = 0
    path = write_tif(tmp_path / "nd.tif", data, nodata=0)
    calls = []

    def model(rgb, valid):
        calls.append(rgb.shape[0])
        return np.ones((rgb.shape[0], 1, rgb.shape[1], rgb.shape[2]), np.float32)

    result, stats = _run(path, tmp_path / "o.tif", model, 1, tile=128, overlap=0, batch=1)
    assert stats.tiles_skipped == 4 and sum(calls) == 4
    assert np.isnan(result[0, :, 256:]).all() and (result[0, :, :256] == 1).all()


def test_wrong_model_shape_is_a_clear_error(tmp_path: Path) -> None:
    path = _position_image(tmp_path, 200, 150)
    with pytest.raises(TilingError, match="expected"):
        _run(path, tmp_path / "w.tif", lambda rgb, valid: np.zeros((1, 1, 8, 8)), 1)
    assert not (tmp_path / "w.tif").exists()


def test_cancel_discards_the_partial_output(tmp_path: Path) -> None:
    path = _position_image(tmp_path, 600, 600)
    progress = NullProgress()
    seen = []

    def model(rgb, valid):
        seen.append(1)
        if len(seen) == 2:
            progress.token.cancel()
        return position_model(rgb, valid)

    with pytest.raises(Cancelled):
        _run(path, tmp_path / "x.tif", model, 2, batch=1, progress=progress)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pos.tif"]


def test_output_grid_is_the_input_grid(tmp_path: Path) -> None:
    path = _position_image(tmp_path, 300, 200)
    _run(path, tmp_path / "g.tif", position_model, 2)
    assert read_grid(tmp_path / "g.tif").same_as(read_grid(path))


# --------------------------------------------------------------------------------------------
# the pipeline: stages in threads with bounded queues
# --------------------------------------------------------------------------------------------


def test_pipeline_keeps_order_and_bounds_items_in_flight() -> None:
    import threading

    started: list[int] = []
    lock = threading.Lock()

    def first(x: int) -> int:
        with lock:
            started.append(x)
        return x * 10

    out = []
    gen = pipeline(range(50), [("a", first, 2), ("b", lambda x: x + 1, 3)])
    for item in gen:
        out.append(item)
        if len(out) == 1:  # the consumer is slow: the stages run ahead only as far as their queues
            threading.Event().wait(0.3)
            with lock:
                ahead = len(started)
            assert ahead <= 1 + 2 + 1 + 3 + 1  # consumed + queues + one in each stage's hands
    assert out == [x * 10 + 1 for x in range(50)]


def test_pipeline_raises_a_stage_error_and_stops_its_threads() -> None:
    import threading

    def boom(x: int) -> int:
        if x == 3:
            raise ValueError("bad tile 3")
        return x

    before = threading.active_count()
    with pytest.raises(ValueError, match="bad tile 3"):
        list(pipeline(range(10), [("a", lambda x: x, 1), ("b", boom, 1)]))
    gen = pipeline(range(1000), [("a", lambda x: x, 1)])
    assert next(gen) == 0
    gen.close()  # the consumer stops early (an error, a cancellation): the threads end
    assert threading.active_count() == before


def test_stages_overlap() -> None:
    """The reader reads batch k+1 while the model runs on batch k (no timing: the model of batch
    0 waits until the reader has started on batch 1, which a sequential loop never does)."""
    import threading

    reading = [threading.Event() for _ in range(3)]
    overlapped = []

    def read(k: int) -> int:
        reading[k].set()
        return k

    def model(k: int) -> int:
        if k + 1 < len(reading):
            overlapped.append(reading[k + 1].wait(timeout=30))
        return k

    assert list(pipeline(range(3), [("read", read, 1), ("model", model, 1)])) == [0, 1, 2]
    assert overlapped == [True, True]


def test_worker_runs_items_in_order_and_reports_errors() -> None:
    got = []
    with ThreadStage("w", got.append, depth=2) as worker:
        for k in range(20):
            worker.submit(k)
    assert got == list(range(20))

    def failing(item):
        raise OSError("disk full")

    worker = ThreadStage("w", failing)
    worker.submit(1)
    with pytest.raises(OSError, match="disk full"):
        worker.close()


def test_worker_holds_at_most_depth_items() -> None:
    """submit blocks while ``depth`` items wait: memory is bounded however fast the caller is."""
    import threading

    release = threading.Event()
    done = []

    def slow(item):
        release.wait(timeout=30)
        done.append(item)

    worker = ThreadStage("w", slow, depth=1)
    worker.submit(0)  # taken by the worker, which now waits
    worker.submit(1)  # waits in the queue
    third = threading.Thread(target=worker.submit, args=(2,))
    third.start()
    third.join(timeout=0.3)
    assert third.is_alive()  # blocked: the queue is full
    release.set()
    third.join(timeout=30)
    worker.close()
    assert done == [0, 1, 2]


def test_model_runs_in_the_callers_thread_while_reading_and_blending_overlap(tmp_path: Path) -> None:
    """stream_predict: the model in the calling thread (where torch and CUDA state live), the
    reader and the blend-and-write stage in other threads."""
    import threading

    path = _position_image(tmp_path, 300, 200)
    threads = set()

    def model(rgb, valid):
        threads.add(threading.get_ident())
        return position_model(rgb, valid)

    _, stats = _run(path, tmp_path / "t.tif", model, 2, batch=1)
    assert threads == {threading.get_ident()}
    assert stats.seconds_reading > 0 and stats.seconds_blending > 0
