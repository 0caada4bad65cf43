"""Fixtures for the planner tests: seeded costmaps written as tiny GeoTIFFs."""

from __future__ import annotations

import heapq
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
import pytest
import rasterio
from rasterio.crs import CRS
from rasterio.transform import from_origin
from scipy import ndimage

UTM_ORIGIN = (500000.0, 4000000.0)  # UTM 33N: about 15 E, 36.1 N
#: The 8 neighbour steps (row, col) and the knight moves 16 neighbours add, for the references.
STEPS8 = [(-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (-1, 1), (1, -1), (1, 1)]
KNIGHTS = [(-2, -1), (-2, 1), (2, -1), (2, 1), (-1, -2), (-1, 2), (1, -2), (1, 2)]


def textbook_dijkstra(
    shape: tuple[int, int],
    start: tuple[int, int],
    steps: Sequence[tuple[int, int]],
    price: Callable[[int, int, int, int], float | None],
) -> np.ndarray:
    """Dijkstra with a binary heap over the (directed) edges ``steps``: ``price(r, c, dr, dc)``
    is a step's cost, None where it may not be taken (off the grid, a blocked cell). The tests'
    reference for the planner's searches: each test writes its own step rule as ``price``."""
    dist = np.full(shape, np.inf)
    dist[start] = 0.0
    heap = [(0.0, start)]
    while heap:
        d, (r, c) = heapq.heappop(heap)
        if d > dist[r, c]:
            continue
        for dr, dc in steps:
            p = price(r, c, dr, dc)
            if p is not None and d + p < dist[r + dr, c + dc]:
                dist[r + dr, c + dc] = d + p
                heapq.heappush(heap, (d + p, (r + dr, c + dc)))
    return dist


def smooth_costmap(
    shape: tuple[int, int], seed: int, lethal_fraction: float = 0.1, nodata_fraction: float = 0.0
) -> np.ndarray:
    """A smooth float32 field in [0.05, 1] with cheap lines, lethal blobs (inf) and nodata (NaN)."""
    rng = np.random.default_rng(seed)
    field = ndimage.gaussian_filter(rng.random(shape), sigma=max(1.0, min(shape) / 12))
    field = (field - field.min()) / max(field.max() - field.min(), 1e-9)
    cost = (0.05 + 0.95 * field).astype(np.float32)
    cost[rng.integers(0, shape[0]), :] = 0.02  # a cheap "road" row and column
    cost[:, rng.integers(0, shape[1])] = 0.02
    blobs = ndimage.gaussian_filter(rng.random(shape), sigma=2.0)
    if lethal_fraction > 0:
        cost[blobs > np.quantile(blobs, 1 - lethal_fraction)] = np.inf
    if nodata_fraction > 0:
        cost[blobs < np.quantile(blobs, nodata_fraction)] = np.nan
    return cost


def write_costmap(
    path: Path,
    cost: np.ndarray,
    crs: str = "EPSG:32633",
    transform=None,
    nodata: float | None = float("nan"),
    tags: dict | None = None,
) -> Path:
    transform = transform or from_origin(*UTM_ORIGIN, 0.5, 0.5)
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        width=cost.shape[1],
        height=cost.shape[0],
        count=1,
        dtype=cost.dtype.name,
        crs=CRS.from_user_input(crs),
        transform=transform,
        nodata=nodata,
    ) as ds:
        ds.write(cost, 1)
        if tags:
            ds.update_tags(**tags)
    return path


def write_lethal(
    path: Path, lethal: np.ndarray, crs: str = "EPSG:32633", transform=None, tags: dict | None = None
) -> Path:
    transform = transform or from_origin(*UTM_ORIGIN, 0.5, 0.5)
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        width=lethal.shape[1],
        height=lethal.shape[0],
        count=1,
        dtype="uint8",
        crs=CRS.from_user_input(crs),
        transform=transform,
    ) as ds:
        ds.write(lethal.astype(np.uint8), 1)
        if tags:
            ds.update_tags(**tags)
    return path


@pytest.fixture
def utm_costmap(tmp_path: Path) -> tuple[Path, np.ndarray]:
    """A 60 x 80 costmap in UTM 33N at 0.5 m, with nodata NaN, and its array."""
    cost = smooth_costmap((60, 80), seed=3, lethal_fraction=0.08)
    cost[0:3, 0:3] = 0.5
    cost[-3:, -3:] = 0.5
    return write_costmap(tmp_path / "costmap.tif", cost), cost
