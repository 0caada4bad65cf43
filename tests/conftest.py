"""Fixtures shared by every test area: tiny seeded GeoTIFFs and the real scenes.

Area-specific fixtures live in the area's own conftest.py (tests/<area>/conftest.py).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
import rasterio
from rasterio.crs import CRS
from rasterio.transform import from_origin

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

REPO = Path(__file__).resolve().parent.parent
SCENES = Path(os.environ.get("OVERSEEC_SCENES", REPO.parent / "shared" / "scenes"))


def write_tif(
    path: Path,
    data: np.ndarray,
    crs: str | None = "EPSG:32633",
    transform=None,
    nodata=None,
    colorinterp=None,
    **profile,
) -> Path:
    """Write a small GeoTIFF from a (count, H, W) or (H, W) array."""
    arr = data[None] if data.ndim == 2 else data
    transform = transform or from_origin(500000.0, 4000000.0, 0.5, 0.5)
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        width=arr.shape[2],
        height=arr.shape[1],
        count=arr.shape[0],
        dtype=arr.dtype.name,
        crs=CRS.from_user_input(crs) if crs else None,
        transform=transform,
        nodata=nodata,
        **profile,
    ) as ds:
        ds.write(arr)
        if colorinterp:
            ds.colorinterp = colorinterp
    return path


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(12345)


@pytest.fixture
def rgb_tif(tmp_path: Path, rng: np.random.Generator) -> Path:
    """A 300 x 200 RGB uint8 GeoTIFF in UTM 33N at 0.5 m."""
    return write_tif(tmp_path / "rgb.tif", rng.integers(0, 256, (3, 200, 300), dtype=np.uint8))


def scene_images() -> list[Path]:
    """Every source image among the real scenes (empty when shared/ is absent)."""
    if not SCENES.is_dir():
        return []
    return sorted(p for p in SCENES.glob("*/image*.tif"))


@pytest.fixture
def scenes_dir() -> Path:
    if not SCENES.is_dir():
        pytest.skip(f"real scenes not found at {SCENES}")
    return SCENES
