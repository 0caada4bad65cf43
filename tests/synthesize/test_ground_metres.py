"""Ground metres in every CRS (issue 9, item 3): path lengths, cost-language distances and the
evaluation's metres are true ground (geodesic) distances in Web Mercator, geographic and UTM grids,
not map units. Each test builds a small GeoTIFF and compares with pyproj.Geod."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import rasterio
from pyproj import Geod, Transformer
from rasterio.crs import CRS
from rasterio.transform import Affine, from_origin

from overseec_core.cli import main
from overseec_core.costlang import check_program
from overseec_core.io.grid import NOMINAL_SCALE_TOLERANCE, Grid
from overseec_core.plan import Planner, load_costmap, path_length_m
from overseec_core.synthesize.engine import compose_array
from overseec_core.synthesize.layers import ArraySource

GEOD = Geod(ellps="WGS84")
LON = 16.0
SIZE = 201  # pixels per side; the seed of a buffer sits on the centre pixel


def grid_at(crs: str, lat: float, size: int = SIZE, map_px: float | None = None) -> Grid:
    """A size x size grid centred on (LON, lat) with about 1 ground-metre pixels in ``crs``."""
    x, y = Transformer.from_crs("EPSG:4326", crs, always_xy=True).transform(LON, lat)
    if CRS.from_user_input(crs).is_geographic:
        step = map_px or 1e-5  # degrees: 0.76 m east-west, 1.11 m north-south at 47 N
    else:
        step = map_px or 1.0
    t = from_origin(x - size / 2 * step, y + size / 2 * step, step, step)
    return Grid(CRS.from_user_input(crs), t, size, size)


def lonlat(grid: Grid, rows, cols) -> tuple[np.ndarray, np.ndarray]:
    """Longitude/latitude of pixel centres."""
    x, y = grid.transform * (np.asarray(cols, float) + 0.5, np.asarray(rows, float) + 0.5)
    to = Transformer.from_crs(grid.crs.to_wkt(), "EPSG:4326", always_xy=True)
    return to.transform(np.asarray(x), np.asarray(y))


def geodesic_m(grid: Grid, a: tuple[int, int], b: tuple[int, int]) -> float:
    lon, lat = lonlat(grid, [a[0], b[0]], [a[1], b[1]])
    return float(GEOD.inv(lon[0], lat[0], lon[1], lat[1])[2])


def write_costmap(path: Path, grid: Grid, cost: np.ndarray) -> Path:
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        width=grid.width,
        height=grid.height,
        count=1,
        dtype="float32",
        crs=grid.crs,
        transform=grid.transform,
        nodata=float("nan"),
    ) as ds:
        ds.write(cost.astype(np.float32), 1)
    return path


CRSS = [("EPSG:3857", 47.0), ("EPSG:4326", 47.0), ("EPSG:32633", 47.0), ("EPSG:3857", 0.0)]
ROUTES = [((100, 10), (100, 190)), ((10, 100), (190, 100)), ((10, 10), (190, 190))]  # E-W, N-S, diagonal


# ------------------------------------------------------------------------------- (a) planned lengths


@pytest.mark.parametrize("crs,lat", CRSS)
def test_planned_length_is_the_geodesic_length(tmp_path: Path, crs: str, lat: float) -> None:
    grid = grid_at(crs, lat)
    costmap = write_costmap(tmp_path / "cost.tif", grid, np.full(grid.shape, 0.3))
    planning = load_costmap(costmap)
    assert planning.pixel_size_m == grid.pixel_size_m()
    planner = Planner(planning)
    for a, b in ROUTES:
        res = planner.plan([a, b])
        truth = geodesic_m(grid, a, b)
        assert res.length_m == pytest.approx(truth, rel=5e-3), (a, b)
        assert path_length_m(res.pixels, *planning.pixel_size_m) == pytest.approx(res.length_m)
        # Cost per metre: a uniform 0.3 costmap charges (0.3 + base) per ground metre.
        assert res.cost == pytest.approx((0.3 + planner.base_cost_per_m) * res.length_m, rel=1e-6)  # float32 0.3
    # What `overseec plan` reports, with the ends given as longitude/latitude.
    a, b = ROUTES[0]
    lon, lat_ = lonlat(grid, [a[0], b[0]], [a[1], b[1]])
    out = tmp_path / "route.geojson"
    assert (
        main(
            [
                "--quiet",
                "plan",
                str(costmap),
                "--crs",
                "EPSG:4326",
                "--start",
                repr(lon[0]),
                repr(lat_[0]),
                "--goal",
                repr(lon[1]),
                repr(lat_[1]),
                "--out",
                str(out),
            ]
        )
        == 0
    )
    (feature,) = json.loads(out.read_text())["features"]
    assert feature["properties"]["length_m"] == pytest.approx(geodesic_m(grid, a, b), rel=5e-3)


def test_web_mercator_at_47n_is_not_taken_as_ground_metres(tmp_path: Path) -> None:
    """The observed bug: a 130.6 m route was reported as 192.9 m (map units, sec 47 = 1.466)."""
    grid = grid_at("EPSG:3857", 47.0)
    a, b = (100, 5), (100, 196)  # 191 map metres east-west
    truth = geodesic_m(grid, a, b)
    assert truth == pytest.approx(130.5, abs=0.5)
    res = Planner(load_costmap(write_costmap(tmp_path / "c.tif", grid, np.full(grid.shape, 0.3)))).plan([a, b])
    assert res.length_m == pytest.approx(truth, rel=1e-3)  # far from 191
    scale = grid.ground_scale()
    assert scale.method == "scaled" and scale.factor[0] == pytest.approx(0.6832, abs=1e-4)


# ------------------------------------------------------------------- (b, c) cost-language buffers


@pytest.mark.parametrize("crs,lat", CRSS)
def test_near_buffer_reaches_ten_ground_metres(crs: str, lat: float) -> None:
    grid = grid_at(crs, lat)
    c = SIZE // 2
    seed = np.zeros(grid.shape, bool)
    seed[c, c] = True
    program = check_program('cost = where(near(M["x"], 10), 0.0, 1.0)', ["x"])
    cost, _ = compose_array(program, ArraySource(grid, {"x": seed}))
    inside = cost == 0.0
    rows, cols = np.indices(grid.shape)
    lon, lat_ = lonlat(grid, rows.ravel(), cols.ravel())
    lon0, lat0 = lonlat(grid, [c], [c])
    d = GEOD.inv(np.full(lon.size, lon0[0]), np.full(lon.size, lat0[0]), lon, lat_)[2].reshape(grid.shape)
    # The buffer is the 10 m geodesic disc, up to the scale's variation over it (< 0.1 %).
    assert inside[d < 10.0 * (1 - 1e-3)].all() and not inside[d > 10.0 * (1 + 1e-3)].any()
    px, py = grid.pixel_size_m()
    east = d[c, c:][inside[c, c:]].max()
    north = d[: c + 1, c][inside[: c + 1, c]].max()
    assert 10.0 - px <= east <= 10.0 * (1 + 1e-3)  # reaches 10 m within a pixel, along x ...
    assert 10.0 - py <= north <= 10.0 * (1 + 1e-3)  # ... and along y


def test_distance_is_in_ground_metres_in_web_mercator() -> None:
    grid = grid_at("EPSG:3857", 47.0)
    seed = np.zeros(grid.shape, bool)
    seed[:, 100] = True  # a north-south line
    program = check_program('cost = distance(M["x"], 50) / 50', ["x"])
    cost, _ = compose_array(program, ArraySource(grid, {"x": seed}))
    assert cost[100, 130] * 50 == pytest.approx(geodesic_m(grid, (100, 100), (100, 130)), rel=1e-3)
    assert cost[100, 100 + 74] == pytest.approx(1.0)  # 74 px = 50.6 ground m: saturated


# ----------------------------------------------------------------------- (d) scale factors, tolerance


def test_scale_factors_by_crs() -> None:
    merc47 = grid_at("EPSG:3857", 47.0).ground_scale()
    merc0 = grid_at("EPSG:3857", 0.0).ground_scale()
    utm = grid_at("EPSG:32633", 47.0).ground_scale()
    geo = grid_at("EPSG:4326", 47.0).ground_scale()
    assert merc47.factor == pytest.approx((0.6832, 0.6811), abs=1e-4)  # ~cos 47 on the ellipsoid
    # At the equator Web Mercator's x scale is 1; its y scale is the meridian radius a(1-e^2)/a.
    assert merc0.factor == pytest.approx((1.0, 0.99331), abs=1e-5) and merc0.method == "scaled"
    # UTM 33N at 16 E (76 km from its meridian): scale 0.99967, inside the tolerance -> nominal.
    assert utm.method == "nominal" and utm.pixel_size_m == (1.0, 1.0)
    assert all(abs(f - 1) <= NOMINAL_SCALE_TOLERANCE for f in utm.factor) and utm.max_error < 1e-3
    assert geo.method == "geodesic" and geo.pixel_size_m == pytest.approx((0.7604, 1.1114), abs=1e-3)
    for s in (merc47, merc0, utm, geo):
        assert s.max_error < 1e-3  # a 200 px image is small enough for one pixel size


def test_large_web_mercator_image_reports_its_span() -> None:
    small = grid_at("EPSG:3857", 60.0, size=100).ground_scale()
    large = grid_at("EPSG:3857", 60.0, size=20000).ground_scale()  # 20 km of map, 10 km of ground
    assert small.pixel_size_m == pytest.approx(large.pixel_size_m, rel=1e-6)
    # sec(lat) varies by tan(60) x 5 km / 6371 km = 0.14 % between the centre and the edges.
    assert large.max_error == pytest.approx(1.36e-3, rel=0.05)
    assert large.span[0] < 1.0 < large.span[1] and "0.14 %" in large.describe()


def test_rotated_transform_is_measured_along_its_axes() -> None:
    base = grid_at("EPSG:3857", 47.0)
    rotated = Grid(base.crs, base.transform * Affine.rotation(30.0), base.width, base.height)
    px, py = rotated.pixel_size_m()
    assert px == pytest.approx(geodesic_m(rotated, (100, 90), (100, 110)) / 20, rel=1e-3)
    assert py == pytest.approx(geodesic_m(rotated, (90, 100), (110, 100)) / 20, rel=1e-3)


# ------------------------------------------------------------------------------------ evaluation


def test_evaluation_lengths_and_distances_are_ground_metres(tmp_path: Path) -> None:
    from overseec_core.evaluate import EvaluateOptions, evaluate_paths

    grid = grid_at("EPSG:3857", 47.0, size=60)
    labels = np.full(grid.shape, 2, np.uint8)
    labels[30, :] = 1
    with rasterio.open(
        tmp_path / "gt.tif",
        "w",
        driver="GTiff",
        width=60,
        height=60,
        count=1,
        dtype="uint8",
        crs=grid.crs,
        transform=grid.transform,
    ) as ds:
        ds.write(labels, 1)
    (tmp_path / "classes.json").write_text(json.dumps({"1": "road", "2": "grass"}))

    def line(rows_cols):
        lon, lat = lonlat(grid, [r for r, _ in rows_cols], [c for _, c in rows_cols])
        return {
            "type": "Feature",
            "properties": {"name": f"r{max(r for r, _ in rows_cols)}"},
            "geometry": {"type": "LineString", "coordinates": list(map(list, zip(lon, lat)))},
        }

    # the detour shares the reference's ends: Hausdorff compares paths of the same start and goal
    on, off = [(30, 0), (30, 59)], [(30, 0), (40, 30), (30, 59)]
    for name, lines in (("paths", [on, off]), ("ref", [on])):
        (tmp_path / f"{name}.geojson").write_text(
            json.dumps({"type": "FeatureCollection", "features": [line(x) for x in lines]})
        )
    evaluate_paths(
        EvaluateOptions(
            out_dir=tmp_path / "out",
            labels=tmp_path / "gt.tif",
            classes=tmp_path / "classes.json",
            ranks="road=1,grass=2",
            paths=tmp_path / "paths.geojson",
            reference=tmp_path / "ref.geojson",
            plots=False,
        )
    )
    by = {p["name"]: p for p in json.loads((tmp_path / "out" / "metrics.json").read_text())["paths"]}
    assert by["r30"]["length_m"] == pytest.approx(geodesic_m(grid, *on), rel=5e-3)
    assert by["r40"]["hausdorff"]["directed_m"] == pytest.approx(geodesic_m(grid, (30, 30), (40, 30)), rel=5e-3)
