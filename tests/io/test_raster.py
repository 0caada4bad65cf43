"""Raster I/O: every kind of source reads as RGB uint8 by window; writers keep the grid exactly."""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest
import rasterio
from rasterio.enums import ColorInterp
from rasterio.transform import from_origin
from rasterio.windows import Window

from overseec_core.errors import InputError, OutputError, RasterError
from overseec_core.io.atomic import write_text_atomic
from overseec_core.io.grid import Grid, ground_scale, pixel_size_m
from overseec_core.io.read import RasterSource, read_grid, read_info
from overseec_core.io.write import RasterWriter, WriteOptions, _osgeo_gdal, gdal_errors, verify_geotiff, write_array

from ..conftest import scene_images, write_tif
from .test_full_disk import EFBIG_REASON, digest, fill, fsize_limit, hidden_leftovers, tiny_tmpfs  # noqa: F401


def test_rgb_chip_is_the_window(rgb_tif: Path) -> None:
    with rasterio.open(rgb_tif) as ds:
        expected = ds.read(window=Window(10, 20, 64, 32))
    with RasterSource(rgb_tif) as src:
        chip = src.read_chip(Window(10, 20, 64, 32))
    assert chip.rgb.dtype == np.uint8 and chip.rgb.shape == (32, 64, 3)
    np.testing.assert_array_equal(np.moveaxis(chip.rgb, -1, 0), expected)
    assert chip.valid.all()


def test_rgba_alpha_is_the_valid_mask(tmp_path: Path, rng) -> None:
    data = rng.integers(0, 256, (4, 40, 50), dtype=np.uint8)
    data[3] = 255
    data[3, :10, :] = 0
    path = write_tif(
        tmp_path / "rgba.tif",
        data,
        photometric="RGB",
        colorinterp=[ColorInterp.red, ColorInterp.green, ColorInterp.blue, ColorInterp.alpha],
    )
    with RasterSource(path) as src:
        assert src.info.plan.alpha_band == 4
        chip = src.read_chip(Window(0, 0, 50, 40))
    assert not chip.valid[:10].any() and chip.valid[10:].all()
    assert (chip.rgb[:10] == 0).all()


def test_panchromatic_uint16_is_stretched_once_for_the_whole_image(tmp_path: Path, rng) -> None:
    # Left half dark, right half bright: a per-tile stretch would make both halves look alike.
    data = np.empty((1, 64, 128), np.uint16)
    data[0, :, :64] = rng.integers(100, 200, (64, 64))
    data[0, :, 64:] = rng.integers(3000, 4000, (64, 64))
    path = write_tif(tmp_path / "pan.tif", data)
    with RasterSource(path) as src:
        assert src.info.plan.rgb_bands == (1, 1, 1)
        assert src.info.plan.stretch is not None
        left = src.read_chip(Window(0, 0, 64, 64)).rgb
        right = src.read_chip(Window(64, 0, 64, 64)).rgb
        whole = src.read_chip(Window(0, 0, 128, 64)).rgb
    assert left.mean() < 20 and right.mean() > 200
    np.testing.assert_array_equal(whole[:, :64], left)  # same pixel, same value, any window
    assert (left[..., 0] == left[..., 1]).all() and (left[..., 1] == left[..., 2]).all()


def test_float_nan_and_nodata_are_invalid(tmp_path: Path) -> None:
    data = np.ones((3, 20, 20), np.float32)
    data[:, 0, 0] = np.nan
    data[:, 1, 1] = -9999
    path = write_tif(tmp_path / "f.tif", data, nodata=-9999)
    with RasterSource(path) as src:
        chip = src.read_chip(Window(0, 0, 20, 20))
    assert not chip.valid[0, 0] and not chip.valid[1, 1] and chip.valid.sum() == 398


def test_multispectral_band_selection(tmp_path: Path, rng) -> None:
    data = np.stack([np.full((16, 16), 10 * (b + 1), np.uint8) for b in range(5)])
    path = write_tif(tmp_path / "ms.tif", data)
    with pytest.raises(RasterError, match="--bands"):
        RasterSource(path)
    with RasterSource(path, bands="4,3,2") as src:
        rgb = src.read_chip(Window(0, 0, 16, 16)).rgb
    assert tuple(rgb[0, 0]) == (40, 30, 20)
    with pytest.raises(InputError, match="bands 1..5"):
        RasterSource(path, bands="6,3,2")
    with pytest.raises(InputError, match="1 .* or 3"):
        RasterSource(path, bands="1,2")


@pytest.mark.parametrize(
    "epsg,origin,res,expected,method",
    [
        # UTM 33N near its central meridian: scale 0.9996, inside the 0.1 % tolerance -> nominal.
        ("EPSG:32633", (500000, 4000000), 0.5, (0.5, 0.5), "nominal"),
        ("EPSG:32633", (534000, 5213000), 0.5, (0.5, 0.5), "nominal"),  # the bundled sample
        # NY State Plane Long Island (US survey feet) over Manhattan: nominal feet -> metres.
        ("EPSG:2263", (987000, 200000), 1.0, (0.3048006, 0.3048006), "nominal"),
        # A UTM 33N grid 499 km west of its meridian (outside the zone): point scale 1.0027 -> measured.
        ("EPSG:32633", (1000, 1000), 0.5, (0.4986616, 0.4986616), "scaled"),
    ],
)
def test_pixel_size_projected(epsg: str, origin, res: float, expected, method: str) -> None:
    from rasterio.crs import CRS

    crs, t = CRS.from_user_input(epsg), from_origin(*origin, res, res)
    size = pixel_size_m(crs, t, 10, 10)
    assert size == pytest.approx(expected, rel=1e-6)
    scale = ground_scale(crs, t, 10, 10)
    assert scale.method == method and scale.pixel_size_m == size
    assert scale.measured_m == pytest.approx(expected, rel=1.5e-3)  # UTM's 0.9996 shows here
    assert scale.max_error < 1.5e-3


def test_pixel_size_web_mercator_is_scaled_to_the_ground() -> None:
    from pyproj import Transformer
    from rasterio.crs import CRS

    # 1 m Web Mercator pixels at 47 N are cos(47) ground metres (on the ellipsoid: x 0.6832, y 0.6811).
    x, y = Transformer.from_crs("EPSG:4326", "EPSG:3857", always_xy=True).transform(16.0, 47.0)
    t = from_origin(x - 50, y + 50, 1.0, 1.0)
    px, py = pixel_size_m(CRS.from_epsg(3857), t, 100, 100)
    assert px == pytest.approx(0.6832, abs=1e-4) and py == pytest.approx(0.6811, abs=1e-4)
    scale = ground_scale(CRS.from_epsg(3857), t, 100, 100)
    assert scale.method == "scaled" and scale.factor == pytest.approx((px, py))
    assert "scaled" in scale.describe() and scale.to_dict()["pixel_size_m"] == [px, py]
    # A 10 000 px (6.8 km) image: one centre size is off by tan(47) x 3.4 km / R = 0.057 % at its edges.
    big = ground_scale(CRS.from_epsg(3857), from_origin(x - 5000, y + 5000, 1.0, 1.0), 10000, 10000)
    assert big.max_error == pytest.approx(5.7e-4, rel=0.05) and big.span[0] < 1 < big.span[1]


def test_pixel_size_is_cached_and_cheap() -> None:
    import time

    from rasterio.crs import CRS

    grid = Grid(CRS.from_epsg(3857), from_origin(1.8e6, 5.9e6, 1.0, 1.0), 500, 400)
    first = grid.pixel_size_m()
    t0 = time.perf_counter()
    for _ in range(200):
        assert grid.pixel_size_m() == first
    assert (time.perf_counter() - t0) / 200 < 1e-3
    assert grid.ground_scale().pixel_size_m == first


def test_pixel_size_without_an_ellipsoid_is_nominal() -> None:
    from rasterio.crs import CRS

    local = CRS.from_wkt('LOCAL_CS["site grid",UNIT["metre",1],AXIS["Easting",EAST],AXIS["Northing",NORTH]]')
    scale = ground_scale(local, from_origin(0, 100, 0.25, 0.25), 10, 10)
    assert scale.pixel_size_m == (0.25, 0.25) and scale.method == "unmeasured" and scale.max_error is None


def test_pixel_size_geographic_is_measured_on_the_ellipsoid() -> None:
    from rasterio.crs import CRS

    # The SpaceNet Vegas grid: 2.7e-6 degrees at 36.24 N.
    t = from_origin(-115.171, 36.2406, 2.7e-6, 2.7e-6)
    px, py = pixel_size_m(CRS.from_epsg(4326), t, 1300, 1300)
    assert px == pytest.approx(0.2427, abs=5e-4) and py == pytest.approx(0.2996, abs=5e-4)
    assert px == pytest.approx(2.7e-6 * 111320 * math.cos(math.radians(36.2389)), rel=5e-3)
    scale = ground_scale(CRS.from_epsg(4326), t, 1300, 1300)
    assert scale.method == "geodesic" and scale.nominal_m is None and scale.max_error < 1e-4


def test_missing_crs_needs_assume_crs(tmp_path: Path, rng) -> None:
    path = write_tif(tmp_path / "nocrs.tif", rng.integers(0, 255, (3, 8, 8), dtype=np.uint8), crs=None)
    with pytest.raises(RasterError, match="--assume-crs"):
        read_info(path)
    info = read_info(path, assume_crs="EPSG:32633")
    assert info.crs_assumed and info.grid.crs.to_epsg() == 32633


@pytest.mark.parametrize(
    "content,error,match",
    [
        (None, InputError, "no such file"),
        (b"", RasterError, "empty"),
        (b"hello, not a raster\n" * 20, RasterError, "not a readable raster"),
    ],
)
def test_unreadable_inputs_give_one_line_errors(tmp_path: Path, content, error, match) -> None:
    path = tmp_path / "bad.tif"
    if content is not None:
        path.write_bytes(content)
    with pytest.raises(error, match=match) as exc:
        read_info(path)
    assert "\n" not in str(exc.value)


def test_truncated_tiff_fails_on_read_with_a_clear_error(tmp_path: Path, rng) -> None:
    path = write_tif(
        tmp_path / "t.tif",
        rng.integers(0, 255, (3, 512, 512), dtype=np.uint8),
        tiled=True,
        blockxsize=128,
        blockysize=128,
        compress="deflate",
    )
    size = path.stat().st_size
    with open(path, "r+b") as f:
        f.truncate(size // 2)
    with pytest.raises(RasterError, match="corrupt or truncated|not a readable raster"):
        with RasterSource(path) as src:
            for r in range(0, 512, 128):
                for c in range(0, 512, 128):
                    src.read_chip(Window(c, r, 128, 128))


def _grid(w: int = 700, h: int = 600, crs: str = "EPSG:32633") -> Grid:
    from rasterio.crs import CRS

    return Grid(CRS.from_user_input(crs), from_origin(500000.5, 4000000.25, 0.3, 0.4), w, h)


@pytest.mark.parametrize("cog", [False, True])
def test_writer_keeps_grid_names_and_adds_overviews(tmp_path: Path, rng, cog: bool) -> None:
    grid = _grid()
    data = rng.random((2, 600, 700), dtype=np.float32)
    out = write_array(
        tmp_path / "out.tif",
        data,
        grid,
        nodata=float("nan"),
        descriptions=["road", "grass"],
        options=WriteOptions(cog=cog),
    )
    with rasterio.open(out) as ds:
        assert ds.crs == grid.crs and ds.transform == grid.transform
        assert ds.descriptions == ("road", "grass")
        assert math.isnan(ds.nodata)
        assert ds.block_shapes[0] == (512, 512) and ds.compression.name == "zstd"
        assert ds.overviews(1) == [2]
        assert (ds.tags(ns="IMAGE_STRUCTURE").get("LAYOUT") == "COG") == cog
        np.testing.assert_array_equal(ds.read(), data)
    assert oct(out.stat().st_mode & 0o777) == oct(0o666 & ~_umask())
    assert [p.name for p in tmp_path.iterdir()] == ["out.tif"]


def test_environment_selects_cog_and_compression(monkeypatch) -> None:
    monkeypatch.setenv("OVERSEEC_COG", "1")
    monkeypatch.setenv("OVERSEEC_COMPRESS", "deflate")
    opts = WriteOptions()
    assert opts.cog and opts.compress == "deflate"


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def test_failed_write_leaves_nothing_and_keeps_the_old_file(tmp_path: Path) -> None:
    grid = _grid(64, 64)
    target = tmp_path / "out.tif"
    target.write_bytes(b"previous result")
    with pytest.raises(RuntimeError):
        with RasterWriter(target, grid, 1, "float32") as w:
            w.write(np.zeros((1, 32, 64), np.float32), 0)
            raise RuntimeError("model crashed")
    assert target.read_bytes() == b"previous result"
    assert [p.name for p in tmp_path.iterdir()] == ["out.tif"]


@pytest.mark.parametrize("fraction", [0.05, 0.9, 0.999])
def test_writer_past_the_size_limit_is_one_error_and_keeps_the_old_file(
    tmp_path: Path, rng, capfd, fraction: float
) -> None:
    """However far the write gets (blocks, overviews, the closing directory), the failure is one
    OutputError naming the target, nothing on stderr, the old file byte-for-byte, no temp files."""
    grid = _grid(1100, 1000)
    data = rng.random((2, 1000, 1100), dtype=np.float32)
    size = write_array(tmp_path / "probe.tif", data, grid).stat().st_size
    (tmp_path / "probe.tif").unlink()
    target = tmp_path / "out.tif"
    target.write_bytes(b"previous result")
    before = digest(target)
    capfd.readouterr()
    with fsize_limit(int(size * fraction)):
        with pytest.raises(OutputError) as err:
            write_array(target, data, grid, descriptions=["a", "b"])
    assert str(err.value) == f"cannot write {target}: {EFBIG_REASON}"
    assert digest(target) == before
    assert [p.name for p in tmp_path.iterdir()] == ["out.tif"]
    assert capfd.readouterr().err == ""


def test_writer_on_a_full_disk_says_no_space_left(tiny_tmpfs: Path, rng, capfd) -> None:  # noqa: F811 (fixture)
    grid = _grid(1100, 1000)
    fill(tiny_tmpfs, 64 * 1024)
    target = tiny_tmpfs / "out.tif"
    with pytest.raises(OutputError) as err:
        with RasterWriter(target, grid, 1, "float32") as w:
            for r in range(0, 1000, 500):
                w.write(rng.random((500, 1100), dtype=np.float32), r)
    assert str(err.value) == f"cannot write {target}: no space left on device"
    assert not target.exists() and hidden_leftovers(tiny_tmpfs) == []
    assert capfd.readouterr().err == ""


def test_text_past_the_size_limit_is_one_error_and_keeps_the_old_file(tmp_path: Path) -> None:
    target = tmp_path / "report.json"
    write_text_atomic(target, "{}\n")
    before = digest(target)
    with fsize_limit(4096):
        with pytest.raises(OutputError) as err:
            write_text_atomic(target, "x" * 100_000)
    assert str(err.value) == f"cannot write {target}: {EFBIG_REASON}"
    assert digest(target) == before
    assert [p.name for p in tmp_path.iterdir()] == ["report.json"]


def test_verification_finds_blocks_that_were_never_written(tmp_path: Path) -> None:
    """A block whose write failed reads back silently as nodata; the block index shows it."""
    grid = _grid(1024, 600)
    path = tmp_path / "sparse.tif"
    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        width=1024,
        height=600,
        count=1,
        dtype="float32",
        crs=grid.crs,
        transform=grid.transform,
        tiled=True,
        blockxsize=512,
        blockysize=512,
        sparse_ok=True,
    ) as ds:
        ds.write(np.ones((1, 600, 512), np.float32), window=Window(0, 0, 512, 600))
    with rasterio.open(path) as ds:
        ds.read()  # GDAL itself finds nothing wrong
    assert verify_geotiff(path, grid, 1, "float32") == "block 1,0 of band 1 was not written"
    assert verify_geotiff(path, grid, 2, "float32") == "it reads back as 1 x 600 x 1024"
    whole = write_array(tmp_path / "whole.tif", np.ones((600, 1024), np.float32), grid)
    assert verify_geotiff(whole, grid, 1, "float32", every_block=True) is None
    cut = tmp_path / "cut.tif"
    cut.write_bytes(whole.read_bytes()[: whole.stat().st_size - 2000])
    assert verify_geotiff(cut, grid, 1, "float32") is not None


def test_gdal_errors_are_collected_not_printed(tmp_path: Path, capfd) -> None:
    bad = tmp_path / "bad.tif"
    bad.write_bytes(b"II*\0 not really a tiff")
    capfd.readouterr()
    with gdal_errors() as messages:
        with pytest.raises(rasterio.errors.RasterioIOError):
            rasterio.open(bad)
    assert capfd.readouterr().err == ""
    if _osgeo_gdal() is not None:
        assert messages


def test_writer_refuses_to_overwrite_an_input(rgb_tif: Path) -> None:
    before = rgb_tif.read_bytes()
    grid = read_grid(rgb_tif)
    with pytest.raises(OutputError, match="is the input"):
        RasterWriter(rgb_tif, grid, 1, "uint8", inputs=[rgb_tif])
    alias = rgb_tif.parent / "." / rgb_tif.name
    with pytest.raises(OutputError, match="is the input"):
        RasterWriter(alias, grid, 1, "uint8", inputs=[str(rgb_tif)])
    assert rgb_tif.read_bytes() == before


def test_writer_reports_unwritable_destinations(tmp_path: Path) -> None:
    grid = _grid(16, 16)
    with pytest.raises(OutputError, match="does not exist"):
        RasterWriter(tmp_path / "missing" / "out.tif", grid, 1, "uint8")
    (tmp_path / "afile").write_text("x")
    with pytest.raises(OutputError, match="does not exist"):
        RasterWriter(tmp_path / "afile" / "out.tif", grid, 1, "uint8")
    with pytest.raises(OutputError, match="is a directory"):
        RasterWriter(tmp_path, grid, 1, "uint8")
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o500)
    try:
        if os.access(ro, os.W_OK):
            pytest.skip("running as a user that can write anywhere")
        with pytest.raises(OutputError, match="not writable"):
            RasterWriter(ro / "out.tif", grid, 1, "uint8")
    finally:
        ro.chmod(0o700)


def test_four_band_masks_are_data_not_rgba(tmp_path: Path) -> None:
    out = write_array(
        tmp_path / "masks.tif",
        np.ones((4, 600, 600), np.uint8),
        _grid(600, 600),
        descriptions=["road", "grass", "water", "tree"],
    )
    with rasterio.open(out) as ds:
        assert ColorInterp.alpha not in ds.colorinterp and ColorInterp.red not in ds.colorinterp
        assert ds.read_masks(4).all()


def test_small_outputs_are_written_untiled(tmp_path: Path) -> None:
    out = write_array(tmp_path / "small.tif", np.arange(100, dtype=np.uint8).reshape(10, 10), _grid(10, 10))
    with rasterio.open(out) as ds:
        np.testing.assert_array_equal(ds.read(1), np.arange(100).reshape(10, 10))


@pytest.mark.scenes
@pytest.mark.parametrize("image", scene_images(), ids=lambda p: f"{p.parent.name}/{p.name}")
def test_real_scenes_read_and_round_trip_georeferencing(image: Path, tmp_path: Path) -> None:
    """Every real scene reads as RGB by window and writes back on exactly its grid."""
    with RasterSource(image) as src:
        info = src.info
        g = info.grid
        chip = src.read_chip(Window(0, 0, g.width, g.height))
        assert chip.rgb.shape == (g.height, g.width, 3) and chip.valid.any()
        out = write_array(
            tmp_path / "copy.tif", np.moveaxis(chip.rgb, -1, 0), g, inputs=[image], options=WriteOptions(cog=True)
        )
    with rasterio.open(image) as a, rasterio.open(out) as b:
        # Same CRS (GeoTIFF keys may re-express the same EPSG definition with other digits).
        assert b.crs == a.crs and b.crs.to_epsg() == a.crs.to_epsg()
        assert b.transform == a.transform and (b.width, b.height) == (a.width, a.height)
        if a.dtypes[0] == "uint8":
            np.testing.assert_array_equal(b.read(1)[chip.valid], a.read(1)[chip.valid])
    px, py = info.pixel_size_m
    assert 0.05 < px < 1.2 and 0.05 < py < 1.2


def test_stretch_limits_are_the_2nd_and_98th_percentiles_of_the_image(tmp_path: Path, rng) -> None:
    """Every value 0..9999 once: the limits are numpy's 2nd and 98th percentiles (199.98 and
    9799.02), values at or below the low limit are 0, at or above the high one 255, linear between."""
    values = rng.permutation(10_000).astype(np.uint16).reshape(1, 100, 100)
    path = write_tif(tmp_path / "ramp.tif", values)
    with RasterSource(path) as src:
        assert src.info.plan.stretch is not None
        ((lo, hi),) = set(src.info.plan.stretch)  # one band, shown as grey
        grey = src.read_chip(Window(0, 0, 100, 100)).rgb[..., 0]
    assert lo == pytest.approx(199.98) and hi == pytest.approx(9799.02)
    v = values[0]
    assert (grey[v <= 199] == 0).all() and (grey[v >= 9800] == 255).all()
    expected = np.floor((v.astype(float) - lo) * 255 / (hi - lo))
    between = (v > 200) & (v < 9799)
    np.testing.assert_allclose(grey[between], expected[between], atol=1)
    assert grey[v == 5000].item() == 127
