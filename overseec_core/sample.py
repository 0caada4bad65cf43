"""The bundled sample scene: a procedural aerial image with a known truth.

A seeded generator paints a 1024 x 1024 scene at 0.5 m in UTM 33N: grass with texture, a
forest and scattered trees, a meandering river, two roads (one crosses the river on a bridge)
with centre markings, a winding trail, buildings with shadows and a baseball field on the grass.
It writes the RGB GeoTIFF, the class raster, ``classes.json``, a reference route along the roads
(GeoJSON, WGS 84) and ``sample.json`` with a mission prompt and start/goal points, so the demo
and tests have data whose truth is known exactly. Same seed, same pixels.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, overload

import numpy as np
import numpy.typing as npt
from rasterio.crs import CRS
from rasterio.transform import from_origin
from scipy import ndimage

from overseec_core.io.grid import Grid
from overseec_core.io.manifest import write_json_atomic
from overseec_core.io.write import write_array

CLASSES: dict[int, str] = {1: "grass", 2: "road", 3: "trail", 4: "tree", 5: "water", 6: "building", 7: "baseball field"}
COLOURS: dict[str, tuple[int, int, int]] = {
    "grass": (96, 140, 62),
    "road": (92, 92, 96),
    "trail": (150, 122, 88),
    "tree": (38, 78, 40),
    "water": (46, 84, 118),
    "building": (176, 160, 150),
    "baseball field": (170, 120, 80),
}
PROMPT = "Prefer the roads and trails, grass should be fine, try to avoid the baseball field as much as possible"

SIZE = 1024
PIXEL_M = 0.5
ORIGIN = (534_000.0, 5_213_000.0)  # UTM 33N, upper-left corner (x, y)
EPSG = 32633


@dataclass(frozen=True)
class SampleScene:
    """Paths of a generated sample scene."""

    folder: Path
    image: Path
    labels: Path
    classes: Path
    reference: Path
    meta: Path


def sample_grid(size: int = SIZE) -> Grid:
    """The sample scene's grid: ``size`` pixels a side at 0.5 m, UTM 33N."""
    return Grid(crs=CRS.from_epsg(EPSG), transform=from_origin(*ORIGIN, PIXEL_M, PIXEL_M), width=size, height=size)


def _smooth_noise(rng: np.random.Generator, shape: tuple[int, ...], sigma: float) -> npt.NDArray[np.float64]:
    """Zero-mean, unit-scale smooth noise (texture, illumination)."""
    noise: npt.NDArray[np.float64] = ndimage.gaussian_filter(rng.standard_normal(shape), sigma)
    scaled: npt.NDArray[np.float64] = noise / (noise.std() + 1e-9)
    return scaled


def _polyline_distance(points: npt.NDArray[np.float64], shape: tuple[int, ...]) -> npt.NDArray[np.float64]:
    """Distance in pixels from every pixel to a polyline given as (row, col) vertices."""
    seeds = np.ones(shape, bool)
    for (r0, c0), (r1, c1) in zip(points[:-1], points[1:]):
        n = int(max(abs(r1 - r0), abs(c1 - c0))) * 2 + 2
        rr = np.clip(np.rint(np.linspace(r0, r1, n)).astype(int), 0, shape[0] - 1)
        cc = np.clip(np.rint(np.linspace(c0, c1, n)).astype(int), 0, shape[1] - 1)
        seeds[rr, cc] = False
    distance: npt.NDArray[np.float64] = ndimage.distance_transform_edt(seeds)
    return distance


@overload
def _ew_road_row(col: float, s: float) -> np.float64: ...
@overload
def _ew_road_row(col: npt.NDArray[np.int_], s: float) -> npt.NDArray[np.float64]: ...
def _ew_road_row(col: npt.NDArray[np.int_] | float, s: float) -> npt.NDArray[np.float64] | np.float64:
    """Row of the east-west road's centre line at a column (scale ``s`` = size / 1024); a
    column array gives an array of rows, one column a scalar."""
    row: npt.NDArray[np.float64] | np.float64 = (700 + 40 * np.sin(np.asarray(col) / (180.0 * s))) * s
    return row


def _paint_labels(rng: np.random.Generator, size: int) -> tuple[npt.NDArray[np.uint8], dict[str, npt.NDArray[Any]]]:
    """Class raster plus the geometry the painter needs (road distances, centre lines)."""
    ids = {name: cid for cid, name in CLASSES.items()}
    labels = np.full((size, size), ids["grass"], np.uint8)
    rows, cols = np.mgrid[0:size, 0:size]
    s = size / 1024.0

    # Forest: union of crowns in the upper right, plus scattered single trees.
    for _ in range(int(140 * s * s) or 1):
        r, c = rng.uniform(40, 420) * s, rng.uniform(600, 1000) * s
        rad = rng.uniform(14, 30) * s
        labels[(rows - r) ** 2 + (cols - c) ** 2 < rad**2] = ids["tree"]
    for _ in range(int(40 * s * s) or 1):
        r, c = rng.uniform(0, size), rng.uniform(0, size)
        rad = rng.uniform(6, 12) * s
        labels[(rows - r) ** 2 + (cols - c) ** 2 < rad**2] = ids["tree"]

    # River: a sinuous band running top to bottom on the left.
    t = np.arange(size)
    river_c = (230 + 60 * np.sin(t / 140.0) + 25 * np.sin(t / 47.0 + 1.0)) * s
    river = np.abs(cols - river_c[:, None]) < 22 * s
    labels[river] = ids["water"]

    # Trail: winding narrow path from the east road into the forest.
    trail_pts = np.array([[700, 640], [600, 700], [520, 690], [430, 760], [330, 740], [200, 820], [90, 800]], float) * s
    trail_d = _polyline_distance(trail_pts, labels.shape)
    labels[trail_d < 3.0 * s + 0.5] = ids["trail"]

    # Roads: a curved east-west road crossing the river (bridge) and a straight north-south road.
    ew = np.stack([_ew_road_row(t, s), t], axis=1)[::8].astype(float)
    ns = np.array([[0, 640 * s], [size - 1, 640 * s]], float)
    ew_d = _polyline_distance(ew, labels.shape)
    ns_d = _polyline_distance(ns, labels.shape)
    road_half = 8.0 * s
    labels[(ew_d < road_half) | (ns_d < road_half)] = ids["road"]

    # Buildings along the roads (not on water or road).
    placed = 0
    for _ in range(400):
        if placed >= int(18 * s * s) + 1:
            break
        h, w = rng.integers(18, 40) * s, rng.integers(18, 44) * s
        r, c = rng.uniform(0, size - h), rng.uniform(0, size - w)
        box = (rows >= r) & (rows < r + h) & (cols >= c) & (cols < c + w)
        near = (ew_d[box].min() < 60 * s) or (ns_d[box].min() < 60 * s)
        clear = np.isin(labels[box], (ids["grass"], ids["tree"])).all()
        if near and clear and ew_d[box].min() > 14 * s and ns_d[box].min() > 14 * s and trail_d[box].min() > 8 * s:
            labels[box] = ids["building"]
            placed += 1

    # Baseball field: a quarter disc on open grass south-west of the junction.
    home_r, home_c, radius = 980 * s, 360 * s, 160 * s
    dr, dc = home_r - rows, cols - home_c
    field = (dr >= 0) & (dc >= 0) & (dr**2 + dc**2 < radius**2)
    field &= ~np.isin(labels, (ids["road"], ids["water"], ids["building"]))
    labels[field] = ids["baseball field"]
    infield = field & (np.abs(dr) + np.abs(dc) < 70 * s)
    geometry = {"ew_d": ew_d, "ns_d": ns_d, "infield": infield, "trail_d": trail_d}
    return labels, geometry


def _paint_rgb(
    rng: np.random.Generator, labels: npt.NDArray[np.uint8], geometry: dict[str, npt.NDArray[Any]]
) -> npt.NDArray[np.uint8]:
    """Colours with texture, shading and markings from the class raster."""
    shape = labels.shape
    rgb = np.zeros((*shape, 3), np.float32)
    for cid, name in CLASSES.items():
        rgb[labels == cid] = COLOURS[name]
    fine = _smooth_noise(rng, shape, 1.2)
    coarse = _smooth_noise(rng, shape, 24.0)
    amplitude = {"grass": 10, "tree": 14, "water": 4, "road": 4, "trail": 8, "building": 3, "baseball field": 6}
    for cid, name in CLASSES.items():
        m = labels == cid
        rgb[m] += (amplitude[name] * fine[m] + 6 * coarse[m])[:, None]
    # Infield dirt is browner, outfield grass is a mown green.
    field = labels == 7
    outfield = field & ~geometry["infield"]
    rgb[outfield] = np.array(COLOURS["grass"]) * 1.1 + 5 * fine[outfield][:, None]
    # Tree crowns are darker at their edges; buildings cast a shadow to the south-east.
    trees = labels == 4
    depth = ndimage.distance_transform_edt(trees)
    rgb[trees] *= (0.75 + 0.25 * np.clip(depth[trees] / 8.0, 0, 1))[:, None]
    buildings = labels == 6
    shadow = ndimage.shift(buildings.astype(np.float32), (5, 5), order=0) > 0
    rgb[shadow & ~buildings & (labels != 5)] *= 0.55
    # Dashed white centre line on the roads.
    for key in ("ew_d", "ns_d"):
        d = geometry[key]
        rr, cc = np.nonzero(d < 0.8)
        dash = ((rr + cc) // 12) % 2 == 0
        rgb[rr[dash], cc[dash]] = (225, 225, 215)
    return np.clip(rgb, 0, 255).astype(np.uint8)


def _reference_route(grid: Grid, geometry: dict[str, npt.NDArray[Any]], size: int) -> dict[str, Any]:
    """A 'human-drawn' route: along the east-west road, then the north-south road."""
    from pyproj import Transformer

    s = size / 1024.0
    junction_r = _ew_road_row(640 * s, s)
    cols = np.arange(int(40 * s), int(640 * s), max(1, int(8 * s)))
    ew_rows = _ew_road_row(cols, s)
    ns_rows = np.arange(int(junction_r), int(60 * s), -max(1, int(8 * s)))
    pix = [(r, c) for r, c in zip(ew_rows, cols)] + [(float(r), 640.0 * s) for r in ns_rows]
    xs, ys = [], []
    for r, c in pix:
        x, y = grid.transform * (c + 0.5, r + 0.5)
        xs.append(x)
        ys.append(y)
    to_wgs84 = Transformer.from_crs(grid.crs.to_wkt(), "EPSG:4326", always_xy=True)
    lon, lat = to_wgs84.transform(xs, ys)
    coords = [[round(a, 8), round(b, 8)] for a, b in zip(lon, lat)]
    return {
        "type": "FeatureCollection",
        "features": [
            {
                "type": "Feature",
                "properties": {"name": "reference route (roads)"},
                "geometry": {"type": "LineString", "coordinates": coords},
            }
        ],
    }


def generate(folder: str | Path, size: int = SIZE, seed: int = 0) -> SampleScene:
    """Write the sample scene into ``folder`` (created if needed) and return its paths."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    grid = sample_grid(size)
    labels, geometry = _paint_labels(rng, size)
    rgb = _paint_rgb(rng, labels, geometry)
    image = write_array(
        folder / "sample.tif",
        np.moveaxis(rgb, -1, 0),
        grid,
        descriptions=["red", "green", "blue"],
        tags={"OVERSEEC_SAMPLE_SEED": str(seed)},
        photometric="rgb",
    )
    label_path = write_array(folder / "sample_labels.tif", labels, grid, nodata=0, descriptions=["class"])
    classes = write_json_atomic(folder / "classes.json", {str(k): v for k, v in CLASSES.items()})
    reference = write_json_atomic(folder / "reference_route.geojson", _reference_route(grid, geometry, size))
    s = size / 1024.0
    start = grid.transform * (40 * s + 0.5, float(_ew_road_row(40 * s, s)) + 0.5)
    goal = grid.transform * (640 * s + 0.5, 60 * s + 0.5)
    meta = write_json_atomic(
        folder / "sample.json",
        {
            "description": "procedural aerial scene generated by overseec_core.sample",
            "seed": seed,
            "size": size,
            "pixel_size_m": PIXEL_M,
            "crs": f"EPSG:{EPSG}",
            "prompt": PROMPT,
            "start": [round(v, 2) for v in start],
            "goal": [round(v, 2) for v in goal],
            "ranks": {"road": 1, "trail": 1, "grass": 2, "tree": 3, "building": 4, "water": 4, "baseball field": 3},
        },
    )
    return SampleScene(folder=folder, image=image, labels=label_path, classes=classes, reference=reference, meta=meta)


#: Where the sample ships: inside the package in a wheel or sdist install (setup.py's build_py
#: copies it there), in resources/sample of a source checkout.
PACKAGE_SAMPLE = Path(__file__).resolve().parent / "data" / "sample"
CHECKOUT_SAMPLE = Path(__file__).resolve().parent.parent / "resources" / "sample"


def scene_in(folder: str | Path) -> SampleScene | None:
    """The sample scene in ``folder`` (as :func:`generate` writes it), or None when incomplete."""
    folder = Path(folder)
    scene = SampleScene(
        folder=folder,
        image=folder / "sample.tif",
        labels=folder / "sample_labels.tif",
        classes=folder / "classes.json",
        reference=folder / "reference_route.geojson",
        meta=folder / "sample.json",
    )
    parts = (scene.image, scene.labels, scene.classes, scene.reference, scene.meta)
    return scene if all(p.is_file() for p in parts) else None


def bundled_sample() -> SampleScene | None:
    """The sample shipped with this install: the package's copy (wheel, sdist), else the
    checkout's resources/sample (an editable or in-place install); None when neither is whole."""
    for folder in (PACKAGE_SAMPLE, CHECKOUT_SAMPLE):
        scene = scene_in(folder)
        if scene is not None:
            return scene
    return None
