"""``--gsd``: a segmenter run at a chosen ground resolution, its outputs on the image's own grid.

A probe segmenter registered like any backend (one module + a registry line) returns the pixel
values it is given, so on an image whose colours are a known smooth function of position the
outputs must be that function, whatever the processing resolution; a tiny random CLIPSeg on a
scene at 0.5 m with ``--gsd 1`` must match the same model on the scene pre-downsampled to 1 m.
"""

from __future__ import annotations

import json
import math
import sys
import tracemalloc
import types
from pathlib import Path

import numpy as np
import pytest
import rasterio
from rasterio.transform import from_origin

torch = pytest.importorskip("torch")

from overseec_core.cli import main  # noqa: E402
from overseec_core.errors import InputError  # noqa: E402
from overseec_core.locate import segmenters  # noqa: E402
from overseec_core.locate.gsd import (  # noqa: E402
    MAX_NATIVE_TILE,
    Resampling,
    parse_gsd,
    plan_resampling,
    resample_tiles,
)
from overseec_core.locate.models import BatchState, ModelRef  # noqa: E402
from overseec_core.locate.segment import SegmentOptions, segment_image  # noqa: E402
from overseec_core.schema import Entity  # noqa: E402

from .conftest import write_geotiff  # noqa: E402

ENTITIES = [Entity("red", "areal"), Entity("green", "linear")]
PROBE_SIZE = 64


class Probe:
    """A batch predictor whose probabilities are its input colours: entity 0 = red / 255, entity
    1 = green / 255. It records the tile shapes it is given (the model's pixels)."""

    def __init__(self, gsd_m: float | None = None) -> None:
        self.ref = ModelRef("probe", "probe", "probe", None)
        self.device = torch.device("cpu")
        self.precision = "fp32"
        self.state = BatchState(4)
        self.model_size = PROBE_SIZE
        self.encoder_calls = 0
        self.gsd_m = gsd_m
        self.shapes: list[tuple[int, int]] = []

    def describe(self) -> str:
        return "probe"

    def __call__(self, rgb: np.ndarray, valid: np.ndarray) -> np.ndarray:
        self.encoder_calls += len(rgb)
        self.shapes += [tuple(rgb.shape[1:3])] * len(rgb)
        return (rgb[..., :2].transpose(0, 3, 1, 2) / 255.0).astype(np.float32)


@pytest.fixture
def probe(monkeypatch) -> list[Probe]:
    """A 'probe' segmenter in the registry (its module in sys.modules); the loaded probes."""
    loaded: list[Probe] = []
    module = types.ModuleType("overseec_core.locate.segmenters.probe")

    def load(model, entities, options):
        loaded.append(Probe(float(model) if model else None))
        return loaded[-1]

    module.load = load  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, module.__name__, module)
    monkeypatch.setitem(segmenters.SEGMENTERS, "probe", segmenters.SegmenterInfo("probe", "probe", "", "test probe"))
    return loaded


def red(yy: np.ndarray, xx: np.ndarray) -> np.ndarray:
    """The red channel's function of position, in [0.1, 0.9] (periods of 150 and 110 px)."""
    return 0.5 + 0.4 * np.sin(2 * math.pi * xx / 150.0) * np.cos(2 * math.pi * yy / 110.0)


def green(yy: np.ndarray, xx: np.ndarray) -> np.ndarray:
    """The green channel's: a ramp down the image."""
    return 0.1 + 0.8 * yy / yy.max()


def position_image(path: Path, width: int, height: int, crs: str = "EPSG:32633", pixel: float = 0.5) -> Path:
    """An RGB GeoTIFF whose red and green are :func:`red` and :func:`green` of the pixel centre."""
    yy, xx = np.mgrid[0:height, 0:width].astype(np.float64) + 0.5
    rgb = np.stack([red(yy, xx), green(yy, xx), np.full_like(xx, 0.5)]) * 255
    transform = from_origin(15.0, 36.0, pixel, pixel) if crs == "EPSG:4326" else from_origin(5e5, 4e6, pixel, pixel)
    profile = dict(driver="GTiff", width=width, height=height, count=3, dtype="uint8", crs=crs, transform=transform)
    with rasterio.open(path, "w", **profile) as ds:
        ds.write(np.round(rgb).astype(np.uint8))
    return path


def read_bands(path: Path) -> tuple[np.ndarray, rasterio.Affine, object]:
    with rasterio.open(path) as ds:
        return ds.read(), ds.transform, ds.crs


# ---------------------------------------------------------------------------------------------
# Parsing and planning
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("value, expected", [("0.3", 0.3), (2, 2.0), ("AUTO", "auto"), (None, None), ("", None)])
def test_parse_gsd(value, expected) -> None:
    assert parse_gsd(value) == expected


@pytest.mark.parametrize("value", ["0", "-0.5", "abc", "nan", "inf", True, [1]])
def test_bad_gsd_is_a_one_line_input_error(value) -> None:
    with pytest.raises(InputError, match="--gsd") as info:
        parse_gsd(value)
    assert "\n" not in str(info.value)


def test_tile_side_covers_the_models_ground() -> None:
    r = Resampling(1.2, 1.2, (0.3, 0.3))
    assert r.tile_size(352) == round(352 * 1.2 / 0.3) == 1408
    assert r.model_shape(1408, 1408, 352) == (352, 352)  # a full tile is exactly the model's side
    assert r.model_shape(704, 1408, 352) == (176, 352)  # an image smaller than a tile: same factor
    assert plan_resampling("auto", None, (0.5, 0.5)) is None  # no trained resolution: native
    assert plan_resampling("auto", 0.3, (0.5, 0.5)) == Resampling("auto", 0.3, (0.5, 0.5))


def test_resampling_averages_areas_when_shrinking_and_is_bilinear_when_enlarging() -> None:
    rgb = np.array([[0, 3, 30, 60, 90, 120]], np.uint8)[:, None, :, None].repeat(3, axis=1).repeat(3, axis=3)
    valid = np.ones((1, 3, 6), bool)
    valid[0, :, :2] = False
    small, ok = resample_tiles(rgb, valid, (1, 2))
    assert small[0, 0, :, 0].tolist() == [11, 90]  # the means of 3 x 3 pixels, not samples
    assert ok[0].tolist() == [[False, True]]  # valid where at least half the ground was
    big, _ = resample_tiles(rgb[:, :2, 2:4], np.ones((1, 2, 2), bool), (4, 4))
    assert big[0, 0, :, 0].tolist() == [30, 38, 52, 60]  # bilinear, half-pixel centres, edges clamped


# ---------------------------------------------------------------------------------------------
# Outputs on the native grid
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("gsd", [1.0, 0.3, 1.55])
def test_known_function_of_position_comes_back_on_the_native_grid(probe, tmp_path, gsd) -> None:
    image = position_image(tmp_path / "image.tif", 300, 220)
    result = segment_image(image, ENTITIES, tmp_path / "out", SegmentOptions(segmenter="probe", gsd=gsd))
    assert {s for p in probe for s in p.shapes} == {(PROBE_SIZE, PROBE_SIZE)}  # the model saw its own size
    assert result.tile_size == round(PROBE_SIZE * gsd / 0.5)
    assert result.gsd == {"requested": gsd, "processing_m": gsd, "native_m": [0.5, 0.5]}
    probs, transform, crs = read_bands(result.probs_path)
    _, image_transform, image_crs = read_bands(image)
    assert probs.shape == (2, 220, 300) and transform == image_transform and crs == image_crs
    yy, xx = np.mgrid[0:220, 0:300].astype(np.float64) + 0.5
    # the function sampled at gsd and interpolated back: within the interpolation error of a
    # smooth function (second derivative x pixel^2 / 8, doubled for area averaging) and uint8
    # rounding; at the image's edges, within half a coarse pixel of slope (no data beyond them)
    ratio = gsd / 0.5
    curvature = 0.4 * 2 * (2 * math.pi / 110.0) ** 2
    interior = 0.006 + curvature * ratio**2 / 4
    edge = interior + 0.4 * 2 * math.pi / 110.0 * max(ratio, 1.0) / 2
    err = np.abs(probs[0] - red(yy, xx))
    border = math.ceil(ratio)
    assert err[border:-border, border:-border].max() < interior
    assert err.max() < edge
    assert np.abs(probs[1] - green(yy, xx)).max() < 0.01


def test_ground_resolution_of_a_geographic_image(probe, tmp_path) -> None:
    from overseec_core.io.read import read_info

    image = position_image(tmp_path / "image.tif", 240, 200, crs="EPSG:4326", pixel=5e-6)
    native = read_info(image).grid.pixel_size_m()  # about 0.45 m east-west, 0.55 m north-south at 36 N
    result = segment_image(image, ENTITIES, tmp_path / "out", SegmentOptions(segmenter="probe", gsd=1.0))
    assert result.gsd is not None and result.gsd["native_m"] == pytest.approx(list(native), rel=1e-5)
    assert result.tile_size == round(PROBE_SIZE * 1.0 / (sum(native) / 2))
    probs, transform, _ = read_bands(result.probs_path)
    assert probs.shape == (2, 200, 240) and transform == read_bands(image)[1]


def test_auto_uses_the_models_trained_resolution_else_native(probe, tmp_path) -> None:
    image = position_image(tmp_path / "image.tif", 200, 160)
    trained = segment_image(image, ENTITIES, tmp_path / "a", SegmentOptions(segmenter="probe", model="1.5", gsd="auto"))
    assert trained.gsd == {"requested": "auto", "processing_m": 1.5, "native_m": [0.5, 0.5]}
    assert trained.tile_size == 192
    native = segment_image(image, ENTITIES, tmp_path / "b", SegmentOptions(segmenter="probe", gsd="auto"))
    assert native.gsd is None and native.tile_size == SegmentOptions().tile_size


def test_an_image_smaller_than_a_tile_is_scaled_by_the_same_factor(probe, tmp_path) -> None:
    image = position_image(tmp_path / "image.tif", 100, 80)
    segment_image(image, ENTITIES, tmp_path / "out", SegmentOptions(segmenter="probe", gsd=1.0))
    assert probe[0].shapes == [(40, 50)]


def test_scene_at_half_metre_with_gsd_one_matches_the_scene_downsampled_to_one_metre(tiny_clipseg, tmp_path) -> None:
    from overseec_core.sample import generate

    scene = generate(tmp_path / "scene", size=384)
    with rasterio.open(scene.image) as src:
        fine, profile = src.read(), src.profile
    coarse = np.round(fine.reshape(3, 192, 2, 192, 2).astype(np.float64).mean(axis=(2, 4))).astype(np.uint8)
    t = profile["transform"]
    profile.update(width=192, height=192, transform=rasterio.Affine(t.a * 2, 0, t.c, 0, t.e * 2, t.f))
    with rasterio.open(tmp_path / "coarse.tif", "w", **profile) as dst:
        dst.write(coarse)
    entities = [Entity("road", "linear"), Entity("tree", "areal")]
    base = dict(clipseg_model=str(tiny_clipseg), device="cpu")
    at_gsd = segment_image(scene.image, entities, tmp_path / "gsd", SegmentOptions(gsd=1.0, **base))
    native = segment_image(tmp_path / "coarse.tif", entities, tmp_path / "coarse", SegmentOptions(tile_size=64, **base))
    assert at_gsd.tile_size == 128 and at_gsd.overlap == 16 and native.overlap == 8  # the same tiles on the ground
    probs, transform, _ = read_bands(at_gsd.probs_path)
    assert probs.shape == (2, 384, 384) and transform == t
    # the model saw the same pixels; its answers, brought to 0.5 m bilinearly as --gsd does per
    # tile, differ only by the blending weights' sampling and the tiles' edges
    coarse_probs = torch.from_numpy(read_bands(native.probs_path)[0])[None]
    reference = torch.nn.functional.interpolate(coarse_probs, size=(384, 384), mode="bilinear")[0].numpy()
    diff = np.abs(probs - reference)
    assert diff.mean() < 2e-3 and diff.max() < 0.05, (diff.mean(), diff.max())


# ---------------------------------------------------------------------------------------------
# Errors, the manifest, memory
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("value", ["0", "-1", "abc"])
def test_cli_bad_gsd_is_one_line(tmp_path, capsys, value) -> None:
    image = write_geotiff(tmp_path / "img.tif", 64, 64)
    with pytest.raises(SystemExit) as exit_:
        main(["-q", "segment", str(image), "--entity", "road", "--out", str(tmp_path / "o"), "--gsd", value])
    err = capsys.readouterr().err.strip().splitlines()
    assert exit_.value.code == 2 and err[-1].startswith("overseec segment: error: argument --gsd:")
    assert not (tmp_path / "o").exists()


def test_api_bad_gsd_fails_before_the_folder_is_made(probe, tmp_path) -> None:
    image = position_image(tmp_path / "image.tif", 64, 64)
    with pytest.raises(InputError, match="--gsd"):
        segment_image(image, ENTITIES, tmp_path / "out", SegmentOptions(segmenter="probe", gsd=-2.0))
    assert not (tmp_path / "out").exists()


def test_tiles_too_large_or_an_image_too_small_for_the_gsd(probe, tmp_path) -> None:
    image = position_image(tmp_path / "image.tif", 64, 64)
    with pytest.raises(InputError, match=f"the most is {MAX_NATIVE_TILE}"):
        segment_image(image, ENTITIES, tmp_path / "a", SegmentOptions(segmenter="probe", gsd=40.0))
    with pytest.raises(InputError, match="shrinks this 64x64 px image to 13 px"):
        segment_image(image, ENTITIES, tmp_path / "b", SegmentOptions(segmenter="probe", gsd=2.5))
    with pytest.raises(InputError, match="tiles of 13 px"):
        segment_image(image, ENTITIES, tmp_path / "c", SegmentOptions(segmenter="probe", gsd=0.1))


def test_cli_records_the_gsd_in_the_manifest(tiny_clipseg, tmp_path, capsys) -> None:
    image = write_geotiff(tmp_path / "img.tif", 160, 120)
    out = tmp_path / "run"
    args = ["-q", "segment", str(image), "--entity", "road:linear", "--out", str(out), "--no-refine"]
    code = main([*args, "--clipseg-model", str(tiny_clipseg), "--device", "cpu", "--gsd", "0.75"])
    assert code == 0, capsys.readouterr().err
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["parameters"]["segment"]["gsd"] == 0.75
    assert manifest["segment"]["gsd"] == {"requested": 0.75, "processing_m": 0.75, "native_m": [0.5, 0.5]}
    assert manifest["segment"]["tile_size"] == 96  # 64 model px of 0.75 m on a 0.5 m image
    with rasterio.open(image) as src, rasterio.open(out / "masks.tif") as m:
        assert (m.crs, m.transform, m.width, m.height) == (src.crs, src.transform, src.width, src.height)


def test_memory_is_bounded_by_tile_rows_not_image_height(probe, tmp_path) -> None:
    """The same block streaming: a strip six times taller peaks at about the same memory, far
    below the size of its output (one float32 band per entity).

    The peak itself varies by a few blocks from run to run (how many sit in the pipeline's bounded
    queues depends on thread scheduling; 0.66 MB was seen), so the strips differ by enough rows
    that keeping even an eighth of the extra output would stand out clearly."""
    heights = (2400, 14400)
    peaks = []
    for rows in heights:
        image = position_image(tmp_path / f"strip{rows}.tif", 128, rows)
        tracemalloc.start()
        segment_image(image, ENTITIES, tmp_path / f"out{rows}", SegmentOptions(segmenter="probe", gsd=1.0))
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    output_bytes = 128 * heights[1] * len(ENTITIES) * 4
    extra_output = 128 * (heights[1] - heights[0]) * len(ENTITIES) * 4  # 12.3 MB
    assert peaks[1] < peaks[0] + extra_output / 8, peaks
    assert peaks[1] < output_bytes / 4, peaks
