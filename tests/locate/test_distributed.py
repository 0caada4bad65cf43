"""--dask-scheduler: tiles on a dask.distributed cluster give the local run's outputs."""

from __future__ import annotations

import time

import numpy as np
import pytest
import rasterio

torch = pytest.importorskip("torch")
distributed = pytest.importorskip("distributed")

from overseec_core.errors import InputError  # noqa: E402
from overseec_core.locate.dask import connect  # noqa: E402
from overseec_core.locate.models import load_count  # noqa: E402
from overseec_core.locate.refine import RefineOptions, refine_image  # noqa: E402
from overseec_core.locate.segment import SegmentOptions, segment_image  # noqa: E402

from .conftest import write_geotiff  # noqa: E402
from .test_refine import ENTITIES, image_and_probs  # noqa: E402


@pytest.fixture(scope="module")
def cluster():
    """Two worker processes: what a task gets has really been serialised, and each worker loads
    the models itself (one torch thread each: the machine's cores are shared)."""
    with distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        protocol="tcp",
        dashboard_address=None,
        env={"OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"},
    ) as c:
        yield c


def worker_loads(cluster, kind: str) -> dict[str, int]:
    """How many times each worker process loaded a model of ``kind``."""
    with distributed.Client(cluster, set_as_default=False) as client:
        return client.run(load_count, (kind,))


def read(path) -> np.ndarray:
    with rasterio.open(path) as ds:
        return ds.read()


@pytest.mark.slow  # worker processes start and load torch: about a minute on 2 shared cores
def test_segment_on_dask_equals_the_local_run(cluster, tiny_clipseg, tmp_path) -> None:
    image = write_geotiff(tmp_path / "img.tif", 260, 200, nodata_box=(0, 200, 0, 100))
    opts = SegmentOptions(clipseg_model=str(tiny_clipseg), device="cpu", tile_size=96, batch_size=2)
    local = segment_image(image, ENTITIES, tmp_path / "local", opts)
    loads = load_count(("clipseg",))
    remote = segment_image(
        image,
        ENTITIES,
        tmp_path / "dask",
        SegmentOptions(**{**opts.__dict__, "dask_scheduler": cluster.scheduler_address}),
    )
    assert remote.device.startswith("dask 2 worker(s): cpu")
    assert remote.encoder_calls == local.encoder_calls and remote.tiles_skipped == local.tiles_skipped > 0
    # same tiles in the same batches; CPU kernels may still pick another code path for an
    # array that crossed to the worker (alignment), which moves float32 sums in the last bits
    np.testing.assert_allclose(read(remote.probs_path), read(local.probs_path), rtol=0, atol=1e-6)
    np.testing.assert_array_equal(read(remote.masks_path), read(local.masks_path))
    assert load_count(("clipseg",)) == loads  # the client loaded nothing more
    per_worker = worker_loads(cluster, "clipseg")
    assert len(per_worker) == 2 and sum(per_worker.values()) >= 1  # workers load their own copy ...
    assert max(per_worker.values()) == 1  # ... once, however many tasks they ran


@pytest.mark.slow
def test_segment_at_a_gsd_on_dask_equals_the_local_run(cluster, tiny_clipseg, tmp_path) -> None:
    """--gsd reaches the workers: each wraps its segmenter in the client's resampling."""
    image = write_geotiff(tmp_path / "img.tif", 260, 200)
    opts = SegmentOptions(clipseg_model=str(tiny_clipseg), device="cpu", batch_size=2, gsd=0.8)
    local = segment_image(image, ENTITIES, tmp_path / "local", opts)
    remote = segment_image(
        image,
        ENTITIES,
        tmp_path / "dask",
        SegmentOptions(**{**opts.__dict__, "dask_scheduler": cluster.scheduler_address}),
    )
    assert remote.gsd == local.gsd and local.tile_size == remote.tile_size == round(64 * 0.8 / 0.5)
    assert remote.encoder_calls == local.encoder_calls
    np.testing.assert_allclose(read(remote.probs_path), read(local.probs_path), rtol=0, atol=1e-6)
    np.testing.assert_array_equal(read(remote.masks_path), read(local.masks_path))


@pytest.mark.slow
def test_refine_on_dask_equals_the_local_run(cluster, tiny_sam, tmp_path) -> None:
    image, probs = image_and_probs(tmp_path, 300, 200)
    opts = RefineOptions(sam_model=str(tiny_sam), device="cpu")
    local = refine_image(image, probs, ENTITIES, tmp_path / "local", opts)
    remote = refine_image(
        image,
        probs,
        ENTITIES,
        tmp_path / "dask",
        RefineOptions(**{**opts.__dict__, "dask_scheduler": cluster.scheduler_address}),
    )
    assert remote.stats.tiles_sam == local.stats.tiles_sam > 0
    assert remote.stats.encoder_calls == local.stats.encoder_calls
    assert remote.stats.components_refined == local.stats.components_refined
    np.testing.assert_allclose(read(remote.refined_probs_path), read(local.refined_probs_path), rtol=0, atol=1e-5)
    np.testing.assert_array_equal(read(remote.refined_masks_path), read(local.refined_masks_path))
    np.testing.assert_allclose(read(remote.gated_path), read(local.gated_path), rtol=0, atol=1e-5)
    per_worker = worker_loads(cluster, "sam")
    assert sum(per_worker.values()) >= 1 and max(per_worker.values()) == 1


def test_unreachable_scheduler_is_a_one_line_error() -> None:
    t0 = time.monotonic()
    with pytest.raises(InputError, match="cannot reach the Dask scheduler at tcp://127.0.0.1:9"):
        connect("tcp://127.0.0.1:9", timeout_s=2)
    assert time.monotonic() - t0 < 30
