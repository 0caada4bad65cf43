"""Terrain from a DEM: slope and roughness on generated surfaces with known answers.

A plane z = a x + b y (x, y ground metres) has slope atan(hypot(a, b)) everywhere and roughness 0;
these tests build such DEMs in projected and geographic CRSs, at other resolutions and CRSs than
the costmap grid, and check what the cost language reads.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import rasterio
from pyproj import Transformer
from rasterio.crs import CRS
from rasterio.transform import Affine, from_origin
from rasterio.windows import Window

from overseec_core.costlang import check_program, evaluate_program
from overseec_core.errors import CostProgramError, InputError, RasterError
from overseec_core.io.dem import DemReader
from overseec_core.io.grid import Grid
from overseec_core.synthesize.engine import compose_array
from overseec_core.synthesize.layers import ArraySource
from overseec_core.synthesize.terrain import TerrainSource, roughness_m, slope_degrees

#: The plane's gradient: rise per ground metre east (A) and north (B); slope atan(hypot) = 26.57 deg.
A, B = 0.4, -0.3
SLOPE = math.degrees(math.atan(math.hypot(A, B)))


def write_dem(path: Path, z: np.ndarray, crs, transform: Affine, nodata=None, units: str | None = None) -> Path:
    """A single-band float32 GeoTIFF."""
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        width=z.shape[1],
        height=z.shape[0],
        count=1,
        dtype="float32",
        crs=crs,
        transform=transform,
        nodata=nodata,
    ) as ds:
        ds.write(z.astype(np.float32), 1)
        if units:
            ds.set_band_unit(1, units)
    return path


def utm_grid(width: int = 80, height: int = 60, px: float = 2.0, py: float = 2.0) -> Grid:
    """A north-up grid in UTM 33N (ground metres, nominal scale)."""
    return Grid(CRS.from_epsg(32633), Affine(px, 0, 500_000.0, 0, -py, 5_000_000.0), width, height)


def plane_on(grid: Grid, pad: int = 0, base: float = 850.0) -> tuple[np.ndarray, Affine]:
    """The plane z = base + A x + B y (x, y the grid's map metres) sampled on the grid grown by
    ``pad`` pixels each side: (z, transform)."""
    t = grid.transform * Affine.translation(-pad, -pad)
    rows, cols = np.mgrid[0 : grid.height + 2 * pad, 0 : grid.width + 2 * pad]
    x, y = t * (cols + 0.5, rows + 0.5)
    x0, y0 = grid.transform * (0, 0)
    return base + A * (x - x0) + B * (y - y0), t


def terrain_of(path: Path, grid: Grid, names=("slope", "roughness")) -> dict[str, np.ndarray]:
    """The terrain fields over the whole grid (one window) and the valid mask under 'valid'."""
    source = TerrainSource(path, grid)
    try:
        block = source.read(list(names), Window(0, 0, grid.width, grid.height))
    finally:
        source.close()
    return {**block.fields, "valid": block.valid}


# --------------------------------------------------------------------------------------------
# The kernels
# --------------------------------------------------------------------------------------------


def test_horn_slope_of_a_plane_with_non_square_pixels() -> None:
    rows, cols = np.mgrid[0:12, 0:15]
    dx, dy = 0.5, 2.0  # ground metres per pixel: the gradient per pixel differs by axis
    z = 100.0 + A * cols * dx - B * rows * dy  # rows grow southwards
    s = slope_degrees(z, (dx, dy))
    assert s.shape == (10, 13)
    np.testing.assert_allclose(s, SLOPE, rtol=1e-12)
    # the same pixels taken as square would give another slope: the pixel size is used
    assert abs(float(slope_degrees(z, (1.0, 1.0))[0, 0]) - SLOPE) > 5


def test_roughness_is_zero_on_a_plane_and_positive_on_noise() -> None:
    rows, cols = np.mgrid[0:20, 0:20]
    plane = 1500.0 + 3.0 * cols - 7.0 * rows  # steep, high: no cancellation at 1500 m
    assert np.abs(roughness_m(plane)).max() < 1e-9
    noisy = plane + np.random.default_rng(1).normal(0.0, 0.5, plane.shape)
    r = roughness_m(noisy)
    assert (r > 0).all() and 0.2 < float(np.median(r)) < 0.6  # about the noise's 0.5 m, less 3 fitted terms


def test_missing_neighbours_are_extrapolated_exactly_on_a_plane() -> None:
    rows, cols = np.mgrid[0:10, 0:10]
    z = 10.0 + A * cols + B * rows
    z[:, :4] = np.nan  # the data's edge runs through the window
    z[6, 7] = np.nan  # a nodata hole
    s = slope_degrees(z, (1.0, 1.0))
    r = roughness_m(z)
    have = ~np.isnan(z[1:-1, 1:-1])
    np.testing.assert_allclose(s[have], SLOPE, rtol=1e-12)
    assert np.abs(r[have]).max() < 1e-9
    assert np.isnan(s[~have]).all()


# --------------------------------------------------------------------------------------------
# DEM files onto the grid
# --------------------------------------------------------------------------------------------


def test_plane_on_a_projected_grid_has_its_slope_everywhere(tmp_path: Path) -> None:
    grid = utm_grid()
    z, t = plane_on(grid, pad=4)
    fields = terrain_of(write_dem(tmp_path / "dem.tif", z, grid.crs, t), grid)
    assert fields["valid"].all()
    np.testing.assert_allclose(fields["slope"], SLOPE, rtol=1e-4)  # float32 elevations
    assert fields["roughness"].max() < 1e-3


def test_dem_on_the_grid_itself_has_the_slope_on_its_edges_too(tmp_path: Path) -> None:
    """A DEM that ends where the grid ends: the edge cells extrapolate their missing neighbours."""
    grid = utm_grid(40, 30)
    z, t = plane_on(grid)
    fields = terrain_of(write_dem(tmp_path / "dem.tif", z, grid.crs, t), grid)
    assert fields["valid"].all()
    np.testing.assert_allclose(fields["slope"], SLOPE, rtol=1e-4)


def test_plane_in_epsg4326_at_45n_gives_the_same_slope(tmp_path: Path) -> None:
    """The same plane on a geographic grid (pixels 0.79 x 1.11 ground m at 45 N)."""
    lon0, lat0, step = 15.0, 45.0, 1e-5
    grid = Grid(CRS.from_epsg(4326), from_origin(lon0, lat0 + 100 * step, step, step), 120, 100)
    px, py = grid.pixel_size_m()
    assert px < 0.8 < 1.1 < py  # not square on the ground
    pad = 3
    t = grid.transform * Affine.translation(-pad, -pad)
    rows, cols = np.mgrid[0 : grid.height + 2 * pad, 0 : grid.width + 2 * pad]
    lon, lat = t * (cols + 0.5, rows + 0.5)
    east = (lon - lon0) / step * px  # ground metres from the grid's corner
    north = (lat - lat0) / step * py
    path = write_dem(tmp_path / "dem.tif", 300.0 + A * east + B * north, grid.crs, t)
    fields = terrain_of(path, grid)
    np.testing.assert_allclose(fields["slope"], SLOPE, rtol=0.01)


def test_dem_at_another_resolution_and_crs_is_resampled_onto_the_grid(tmp_path: Path) -> None:
    """A coarse DEM in EPSG:4326 (about 3.5 x 5.5 m cells) under a 2 m UTM grid."""
    grid = utm_grid(100, 80)
    to_utm = Transformer.from_crs("EPSG:4326", "EPSG:32633", always_xy=True)
    to_geo = Transformer.from_crs("EPSG:32633", "EPSG:4326", always_xy=True)
    left, top = to_geo.transform(*(grid.transform * (-20, -20)))
    step = 5e-5
    dem_t = from_origin(left, top, step, step)
    rows, cols = np.mgrid[0:80, 0:70]
    lon, lat = dem_t * (cols + 0.5, rows + 0.5)
    x, y = to_utm.transform(lon, lat)
    x0, y0 = grid.transform * (0, 0)
    path = write_dem(tmp_path / "dem.tif", 40.0 + A * (x - x0) + B * (y - y0), CRS.from_epsg(4326), dem_t)
    fields = terrain_of(path, grid)
    assert fields["valid"].all()
    np.testing.assert_allclose(fields["slope"], SLOPE, rtol=0.01)
    with DemReader(path, grid) as dem:  # the elevation itself is the plane's, bilinearly
        z = dem.read(Window(0, 0, grid.width, grid.height))
    want, _ = plane_on(grid, base=40.0)
    assert np.abs(z - want).max() < 0.05


def test_dem_in_feet_says_so_and_is_converted(tmp_path: Path) -> None:
    grid = utm_grid(30, 20)
    z, t = plane_on(grid, pad=2)
    path = write_dem(tmp_path / "feet.tif", z / 0.3048, grid.crs, t, units="ft")
    with DemReader(path, grid) as dem:
        assert dem.unit == "ft" and dem.metres_per_unit == pytest.approx(0.3048)
        np.testing.assert_allclose(dem.read(Window(0, 0, 30, 20)), z[2:-2, 2:-2], rtol=1e-6)
    np.testing.assert_allclose(terrain_of(path, grid)["slope"], SLOPE, rtol=1e-4)
    odd = write_dem(tmp_path / "odd.tif", z, grid.crs, t, units="furlong")
    with pytest.raises(InputError, match="furlong"):
        DemReader(odd, grid)


def test_dem_that_covers_part_of_the_grid_leaves_nodata(tmp_path: Path) -> None:
    grid = utm_grid(60, 40)
    z, t = plane_on(grid)
    z[:, 30:] = -9999.0  # the DEM's own nodata on the east half
    fields = terrain_of(write_dem(tmp_path / "dem.tif", z, grid.crs, t, nodata=-9999.0), grid)
    assert fields["valid"][:, :30].all() and not fields["valid"][:, 30:].any()
    np.testing.assert_allclose(fields["slope"][:, :30], SLOPE, rtol=1e-4)  # nodata never interpolated into
    assert np.isfinite(fields["slope"]).all()  # the evaluator gets finite values; validity says the rest


def test_dem_elsewhere_or_unreadable_is_a_one_line_error(tmp_path: Path) -> None:
    grid = utm_grid(30, 20)
    z, t = plane_on(grid)
    far = write_dem(tmp_path / "far.tif", z, grid.crs, t * Affine.translation(10_000, 0))
    with pytest.raises(InputError, match="does not overlap"):
        DemReader(far, grid)
    junk = tmp_path / "junk.tif"
    junk.write_bytes(b"II*\x00 this is not a tiff")
    with pytest.raises(RasterError) as err:
        DemReader(junk, grid)
    assert "\n" not in str(err.value)


# --------------------------------------------------------------------------------------------
# The language
# --------------------------------------------------------------------------------------------

MIXED = 'cost = where(M["road"], 0.1, 0.5)\ncost = max(cost, normalize(slope, 15, 30))\nlethal = roughness > 2\n'


def test_program_mixes_slope_and_an_entity_mask(tmp_path: Path) -> None:
    """West half flat, east half a 45 degree ramp; a road along the middle row band."""
    grid = utm_grid(60, 40, 1.0, 1.0)
    cols = np.arange(-2, 62)[None, :] * np.ones((44, 1))
    z = np.where(cols < 30, 0.0, (cols - 29.5) * 1.0)  # rise 1 m per 1 m pixel east of column 30
    t = grid.transform * Affine.translation(-2, -2)
    dem = write_dem(tmp_path / "dem.tif", z, grid.crs, t)
    road = np.zeros(grid.shape, bool)
    road[18:22] = True
    program = check_program(MIXED, ["road"])
    assert program.terrain == ("slope", "roughness")
    terrain = TerrainSource(dem, grid)
    try:
        cost, lethal = compose_array(program, ArraySource(grid, {"road": road}), terrain=terrain)
        blocks, _ = compose_array(program, ArraySource(grid, {"road": road}), block_size=16, terrain=terrain)
    finally:
        terrain.close()
    assert cost[20, 5] == pytest.approx(0.1) and cost[5, 5] == pytest.approx(0.5)  # flat: semantics only
    assert cost[20, 50] == pytest.approx(1.0) and cost[5, 50] == pytest.approx(1.0)  # 45 deg: 1.0 on the road too
    assert (cost >= 0).all() and (cost <= 1).all()
    assert not (lethal == 1).any()  # a ramp is not rough
    np.testing.assert_array_equal(cost, blocks)  # blocks with halos give the whole-image answer


def test_spatial_operators_over_slope_are_exact_block_by_block(tmp_path: Path) -> None:
    """A rough DEM in EPSG:4326 under a UTM grid: warped block by block, GDAL would give a cell
    different elevations in different blocks (0.14 m apart on such a surface); the fixed tiles
    make every block see the same."""
    grid = utm_grid(90, 70, 1.0, 1.0)
    rng = np.random.default_rng(3)
    z = np.cumsum(np.cumsum(rng.normal(0, 0.3, (90, 110)), axis=0), axis=1) * 0.2
    left, top = Transformer.from_crs("EPSG:32633", "EPSG:4326", always_xy=True).transform(*(grid.transform * (-5, -5)))
    dem = write_dem(tmp_path / "dem.tif", z, CRS.from_epsg(4326), from_origin(left, top, 1.2e-5, 1.0e-5))
    program = check_program("steep = slope > 25\ncost = where(near(steep, 6), 0.9, 0.5 + 0.01 * roughness)\n", ["road"])
    source = ArraySource(grid, {"road": np.zeros(grid.shape, bool)})
    terrain = TerrainSource(dem, grid)
    try:
        whole, _ = compose_array(program, source, terrain=terrain)
        for size in (16, 33):
            part, _ = compose_array(program, source, block_size=size, terrain=terrain)
            np.testing.assert_array_equal(whole, part)
    finally:
        terrain.close()
    assert 0 < (whole == 0.9).mean() < 1


def test_a_program_reading_slope_without_a_dem_names_dem() -> None:
    program = check_program("cost = 0.5\ncost = max(cost, normalize(slope, 15, 30))\n", ["road"])
    with pytest.raises(CostProgramError, match="--dem") as err:
        evaluate_program(program, {"road": np.zeros((4, 4), bool)})
    assert err.value.line == 2 and "\n" not in str(err.value)


def test_terrain_names_are_reserved_and_typed() -> None:
    with pytest.raises(CostProgramError, match="terrain field"):
        check_program("slope = 3\ncost = 0.5\n", [])
    with pytest.raises(CostProgramError, match="must be a mask"):
        check_program("cost = 0.5\nlethal = slope\n", [])
    program = check_program("cost = normalize(slope)\n", [])  # slope's static range: [0, 90]
    out = evaluate_program(program, {}, shape=(1, 2), terrain={"slope": np.array([[45.0, 90.0]])})
    np.testing.assert_allclose(out.cost, [[0.5, 1.0]])
