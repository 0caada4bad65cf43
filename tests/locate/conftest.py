"""Fixtures of the locate area: tiny random-weight CLIPSeg and SAM checkpoints (built from configs
by :mod:`tests.locate.builders`, saved once per session) and small RGBA GeoTIFFs."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import rasterio
from rasterio.transform import from_origin


def _builders():
    """The model builders (torch and transformers), or a skip where they are not installed: the
    tiling tests in this folder need neither."""
    pytest.importorskip("torch")
    pytest.importorskip("transformers")
    from . import builders

    return builders


@pytest.fixture(scope="session")
def tiny_clipseg(tmp_path_factory) -> Path:
    return _builders().save_clipseg(tmp_path_factory.mktemp("models") / "tiny-clipseg")


@pytest.fixture(scope="session")
def tiny_sam(tmp_path_factory) -> Path:
    return _builders().save_sam(tmp_path_factory.mktemp("models") / "tiny-sam")


@pytest.fixture
def empty_hub_cache(tmp_path, monkeypatch):
    """An empty Hugging Face cache: every hub id is missing offline."""
    from huggingface_hub import constants

    cache = tmp_path / "hub"
    cache.mkdir()
    monkeypatch.setattr(constants, "HF_HUB_CACHE", str(cache))
    return cache


def write_geotiff(
    path: Path,
    width: int = 200,
    height: int = 150,
    seed: int = 0,
    crs: str = "EPSG:32633",
    nodata_box: tuple[int, int, int, int] | None = None,
) -> Path:
    """An RGB uint8 GeoTIFF with smooth structure; ``nodata_box`` (row0, row1, col0, col1) -> alpha 0."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:height, 0:width]
    base = np.stack([(np.sin(xx / 9.0) + 1) * 100, (np.cos(yy / 7.0) + 1) * 100, ((xx + yy) % 64) * 3.0])
    rgb = np.clip(base + rng.normal(0, 8, base.shape), 0, 255).astype(np.uint8)
    alpha = np.full((height, width), 255, np.uint8)
    if nodata_box is not None:
        r0, r1, c0, c1 = nodata_box
        alpha[r0:r1, c0:c1] = 0
    geographic = rasterio.crs.CRS.from_user_input(crs).is_geographic
    transform = from_origin(15.0, 36.0, 5e-6, 5e-6) if geographic else from_origin(500000.0, 4000000.0, 0.5, 0.5)
    profile = dict(
        driver="GTiff",
        width=width,
        height=height,
        count=4,
        dtype="uint8",
        crs=crs,
        transform=transform,
        photometric="RGB",
    )
    with rasterio.open(path, "w", **profile) as ds:
        ds.write(np.concatenate([rgb, alpha[None]]))
        ds.colorinterp = [
            rasterio.enums.ColorInterp.red,
            rasterio.enums.ColorInterp.green,
            rasterio.enums.ColorInterp.blue,
            rasterio.enums.ColorInterp.alpha,
        ]
    return path


@pytest.fixture(autouse=True, scope="package")
def one_torch_thread():
    """Tiny models run fastest on one thread, and the 2 shared cores stay free for others."""
    try:
        import torch
    except ImportError:  # the tiling tests run without torch
        yield
        return
    before = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(before)
