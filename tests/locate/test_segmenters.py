"""The segmenter registry and protocol: names, errors, lazy imports, CLIPSeg through the registry
bit for bit as the hand-wired pipeline, the CLI's --segmenter, the manifest, and a backend added
as one module plus one registry entry."""

from __future__ import annotations

import json
import subprocess
import sys
import types
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import rasterio

from overseec_core.errors import InputError, ModelError
from overseec_core.locate import segmenters
from overseec_core.locate.segmenters import (
    DEFAULT_SEGMENTER,
    SEGMENTERS,
    SegmenterInfo,
    default_model,
    get_backend,
    segmenter_info,
    segmenter_names,
)
from overseec_core.schema import Entity

from .conftest import write_geotiff

REPO = Path(__file__).resolve().parents[2]
ENTITIES = (Entity("road", "linear"), Entity("tree", "areal"), Entity("water", "areal", ("water", "lake"), 0.5))


def read(path: Path) -> np.ndarray:
    with rasterio.open(path) as ds:
        return ds.read()


# --------------------------------------------------------------------------------------------
# The registry (no torch needed)
# --------------------------------------------------------------------------------------------


def test_the_registry_names_modules_and_defaults() -> None:
    # the three, default first (Processing enums hold indices: new backends go after them)
    assert segmenter_names()[:3] == ("clipseg", "boxes+sam", "semantic") and DEFAULT_SEGMENTER == "clipseg"
    assert [SEGMENTERS[n].module for n in segmenter_names()[:3]] == ["clipseg", "boxes_sam", "semantic"]
    assert all(name == info.name and info.module.isidentifier() for name, info in SEGMENTERS.items())
    assert default_model("clipseg") == "CIDAS/clipseg-rd64-refined"
    assert default_model("boxes+sam").startswith("google/owlv2")
    assert "segformer" in default_model("semantic")
    assert all(info.summary and "\n" not in info.summary for info in SEGMENTERS.values())


def test_an_unknown_segmenter_is_one_line_listing_the_names() -> None:
    for call in (segmenter_info, get_backend, default_model):
        with pytest.raises(InputError) as err:
            call("clipsag")
        assert str(err.value) == f"unknown segmenter 'clipsag'; use one of {', '.join(segmenter_names())}"
        assert str(err.value).startswith("unknown segmenter 'clipsag'; use one of clipseg, boxes+sam, semantic")


def test_a_registered_backend_without_its_module_is_not_installed(monkeypatch) -> None:
    monkeypatch.setitem(SEGMENTERS, "later", SegmenterInfo("later", "no_such_backend", "org/model", "not yet"))
    with pytest.raises(InputError, match=r"^segmenter 'later' is not installed in this version$"):
        get_backend("later")


def test_a_backend_missing_a_dependency_says_which(monkeypatch) -> None:
    """A backend whose own import fails on a dependency is not 'not installed': the real
    ImportError reaches the caller (the models extra's refusal names the package)."""
    name = f"{segmenters.__name__}.needs_dep"
    monkeypatch.setitem(SEGMENTERS, "needs", SegmenterInfo("needs", "needs_dep", "org/model", "needs a package"))

    class Finder:
        def find_spec(self, fullname, path=None, target=None):
            if fullname == name:
                raise ModuleNotFoundError("No module named 'onnxruntime'", name="onnxruntime")
            return None

    monkeypatch.setattr(sys, "meta_path", [Finder(), *sys.meta_path])
    with pytest.raises(ModuleNotFoundError) as err:
        get_backend("needs")
    assert err.value.name == "onnxruntime"


def test_importing_the_registry_imports_no_torch() -> None:
    """--help, the plugin and Processing list the names without loading any model code."""
    script = (
        "import sys\n"
        "from overseec_core.locate.segmenters import SEGMENTERS, segmenter_names\n"
        "from overseec_core.commands import segment\n"
        "names = segmenter_names()\n"
        "heavy = sorted(m for m in sys.modules if m.split('.')[0] in ('torch', 'transformers', 'onnxruntime'))\n"
        "backends = sorted(m for m in sys.modules if m.startswith('overseec_core.locate.segmenters.'))\n"
        "print(','.join(names), heavy, backends)\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=REPO, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == [",".join(segmenter_names()), "[]", "[]"]


def test_segment_options_pick_the_model() -> None:
    from overseec_core.locate.segment import SegmentOptions

    assert SegmentOptions().resolved_model() is None  # the backend's default
    assert SegmentOptions(clipseg_model="c").resolved_model() == "c"  # the older CLIPSeg field
    assert SegmentOptions(model="m", clipseg_model="c").resolved_model() == "m"  # --model wins
    assert SegmentOptions(segmenter="semantic", clipseg_model="c").resolved_model() is None  # CLIPSeg's only
    assert SegmentOptions(segmenter="semantic", model="x.onnx").resolved_model() == "x.onnx"


# --------------------------------------------------------------------------------------------
# CLIPSeg through the registry
# --------------------------------------------------------------------------------------------


def reference_segment(image: Path, entities, out: Path, model: Path, tile: int = 96) -> tuple[np.ndarray, np.ndarray]:
    """The pre-registry wiring of segment_image, by hand: CLIPSeg bundle, text embeddings, the
    shared-encoder predictor, the tiling engine and the same writers."""
    from overseec_core import defaults, runfiles
    from overseec_core.io.read import RasterSource
    from overseec_core.io.write import RasterWriter
    from overseec_core.locate.clipseg import ClipSegPredictor, load_clipseg, text_embeddings
    from overseec_core.locate.entities import MASK_NODATA, entity_prompts, threshold_of
    from overseec_core.locate.segment import mask_sink
    from overseec_core.locate.tiling import TileGrid, stream_predict

    out.mkdir(parents=True)
    bundle = load_clipseg(str(model), "cpu")
    predictor = ClipSegPredictor(bundle, text_embeddings(bundle, [entity_prompts(e) for e in entities]))
    with RasterSource(image) as src:
        n = len(entities)
        with (
            RasterWriter(out / runfiles.PROBS, src.grid, n, "float32", nodata=float("nan")) as pw,
            RasterWriter(out / runfiles.MASKS, src.grid, n, "uint8", nodata=MASK_NODATA) as mw,
        ):
            sink = mask_sink(pw, mw, [threshold_of(e) for e in entities])
            grid = TileGrid(src.grid.width, src.grid.height, tile, defaults.overlap_for(tile))
            stream_predict(src, predictor, sink, grid, n, batch_size=predictor.state.size, flush_rows=pw.block_rows)
    return read(out / runfiles.PROBS), read(out / runfiles.MASKS)


@pytest.fixture
def image(tmp_path) -> Path:
    return write_geotiff(tmp_path / "img.tif", 230, 170, nodata_box=(0, 96, 0, 96))  # the first 96 px tile


def test_clipseg_through_the_registry_is_the_hand_wired_pipeline_bit_for_bit(tiny_clipseg, image, tmp_path) -> None:
    from overseec_core.locate.segment import SegmentOptions, segment_image

    probs, masks = reference_segment(image, ENTITIES, tmp_path / "ref", tiny_clipseg)
    for name, options in (
        ("model", SegmentOptions(segmenter="clipseg", model=str(tiny_clipseg), device="cpu", tile_size=96)),
        ("clipseg_model", SegmentOptions(clipseg_model=str(tiny_clipseg), device="cpu", tile_size=96)),
    ):
        result = segment_image(image, ENTITIES, tmp_path / name, options)
        assert result.segmenter == "clipseg" and result.to_json()["segmenter"] == "clipseg"
        assert result.model.path == str(tiny_clipseg.resolve()) and result.tiles_skipped == 1
        assert result.encoder_calls == result.tiles - 1 == 5
        np.testing.assert_array_equal(read(result.probs_path), probs)  # NaN nodata included, every bit
        np.testing.assert_array_equal(read(result.masks_path), masks)
        with rasterio.open(result.probs_path) as ds:
            assert ds.tags()["OVERSEEC_SEGMENTER"] == "clipseg"
            assert ds.tags()["OVERSEEC_MODEL"] == str(tiny_clipseg)


def test_the_clipseg_backend_is_a_loaded_segmenter(tiny_clipseg) -> None:
    from overseec_core.locate.segment import SegmentOptions
    from overseec_core.locate.segmenters.base import LoadedSegmenter

    backend = get_backend("clipseg")
    seg = backend.load(str(tiny_clipseg), ENTITIES, SegmentOptions(device="cpu", batch_size=3, model_size=64))
    assert isinstance(seg, LoadedSegmenter)
    assert (seg.state.size, seg.model_size, seg.precision, seg.device.type) == (3, 64, "fp32", "cpu")
    assert seg.ref.kind == "clipseg" and "\n" not in seg.describe() and "CLIPSeg" in seg.describe()
    rgb = np.random.default_rng(0).integers(0, 256, (2, 40, 56, 3), dtype=np.uint8)
    out = seg(rgb, np.ones(rgb.shape[:3], bool))
    assert out.shape == (2, len(ENTITIES), 40, 56) and out.dtype == np.float32
    assert 0.0 <= out.min() and out.max() <= 1.0 and seg.encoder_calls == 2
    assert seg.timings["text_embeddings"] >= 0.0


def test_the_clipseg_backend_without_a_model_asks_for_its_default(empty_hub_cache) -> None:
    from overseec_core.locate.segment import SegmentOptions

    with pytest.raises(ModelError) as err:
        get_backend("clipseg").load(None, ENTITIES, SegmentOptions(device="cpu"))
    message = str(err.value)
    assert message.startswith("clipseg model CIDAS/clipseg-rd64-refined is not available offline")
    assert "--model" in message and len(message.splitlines()) == 1


def test_cli_segmenter_clipseg_writes_the_same_rasters_and_names_it(tiny_clipseg, image, tmp_path, capsys) -> None:
    from overseec_core.cli import main

    common = [str(image), "--entity", "road:linear", "--entity", "tree", "--no-refine", "--device", "cpu"]
    common += ["--tile-size", "96"]
    assert main(["segment", *common, "--clipseg-model", str(tiny_clipseg), "--out", str(tmp_path / "a")]) == 0
    argv = ["segment", *common, "--segmenter", "clipseg", "--model", str(tiny_clipseg), "--out", str(tmp_path / "b")]
    assert main(argv) == 0
    printed = capsys.readouterr().out
    assert f"segment  clipseg ({tiny_clipseg})" in printed
    for name in ("probs.tif", "masks.tif"):
        np.testing.assert_array_equal(read(tmp_path / "a" / name), read(tmp_path / "b" / name))
    probs, masks = reference_segment(image, ENTITIES[:2], tmp_path / "ref", tiny_clipseg)
    np.testing.assert_array_equal(read(tmp_path / "b" / "probs.tif"), probs)
    np.testing.assert_array_equal(read(tmp_path / "b" / "masks.tif"), masks)
    manifest = json.loads((tmp_path / "b" / "manifest.json").read_text())
    assert manifest["segmenter"] == manifest["segment"]["segmenter"] == "clipseg"
    assert manifest["models"] == {"clipseg": manifest["segment"]["model"]}
    assert manifest["models"]["clipseg"]["path"] == str(tiny_clipseg.resolve())
    assert manifest["parameters"]["segment"]["segmenter"] == "clipseg"
    assert manifest["parameters"]["segment"]["model"] == str(tiny_clipseg)


def test_cli_refuses_an_unknown_segmenter_before_any_work(tmp_path, capsys) -> None:
    from overseec_core.cli import main

    with pytest.raises(SystemExit) as done:
        main(["segment", "x.tif", "--entity", "road", "--segmenter", "clipsag", "--out", str(tmp_path / "o")])
    assert done.value.code == 2
    err = capsys.readouterr().err
    assert "invalid choice: 'clipsag'" in err and all(name in err for name in segmenter_names())
    assert not (tmp_path / "o").exists()


def test_an_absent_backend_fails_before_the_run_folder_is_made(monkeypatch, image, tmp_path) -> None:
    from overseec_core.locate.segment import SegmentOptions
    from overseec_core.locate.stage import run_segment

    monkeypatch.setitem(SEGMENTERS, "later", SegmenterInfo("later", "no_such_backend", "org/model", "not yet"))
    with pytest.raises(InputError, match="segmenter 'later' is not installed in this version"):
        run_segment(image, ENTITIES, tmp_path / "run", SegmentOptions(segmenter="later"), None)
    assert not (tmp_path / "run").exists()


# --------------------------------------------------------------------------------------------
# A new backend is one module plus one registry entry
# --------------------------------------------------------------------------------------------


class Brightness:
    """A numpy 'model': each entity's probability is the tile's brightness, scaled per entity."""

    def __init__(self, n: int, batch_size: int | None) -> None:
        from overseec_core.locate.models import BatchState, ModelRef

        self.ref = ModelRef("brightness", "brightness", "-", "local")
        self.device = types.SimpleNamespace(type="cpu")
        self.precision = "fp32"
        self.state = BatchState(batch_size or 2)
        self.model_size = 0
        self.encoder_calls = 0
        self.scale = np.linspace(1.0, 0.5, n, dtype=np.float32)

    def describe(self) -> str:
        return "brightness (a test backend)"

    def __call__(self, rgb: np.ndarray, valid: np.ndarray) -> np.ndarray:
        self.encoder_calls += len(rgb)
        grey = rgb.astype(np.float32).mean(axis=-1) / 255.0
        return grey[:, None] * self.scale[None, :, None, None]


def test_a_new_backend_is_one_module_and_one_registry_entry(monkeypatch, image, tmp_path) -> None:
    """Register a module under the package and an entry: segment_image runs it with the shared
    tiling, blending and writers (its outputs are its function of the pixels, seam-free)."""
    from overseec_core.locate.segment import SegmentOptions, segment_image

    module = types.ModuleType(f"{segmenters.__name__}.brightness")
    loads = []

    def load(model, entities, options):
        loads.append((model, tuple(e.name for e in entities), options.batch_size))
        return Brightness(len(entities), options.batch_size)

    module.load = load  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, module.__name__, module)
    monkeypatch.setitem(SEGMENTERS, "bright", SegmenterInfo("bright", "brightness", "none", "test"))
    options = SegmentOptions(segmenter="bright", model="m", tile_size=64, batch_size=3)
    result = segment_image(image, ENTITIES[:2], tmp_path / "out", options)
    assert loads == [("m", ("road", "tree"), 3)]
    assert result.segmenter == "bright" and result.model.name == "brightness" and result.device.startswith("cpu")
    with rasterio.open(image) as ds:
        rgb, alpha = ds.read([1, 2, 3]).astype(np.float32), ds.read(4)
    expected = rgb.mean(axis=0) / 255.0
    probs = read(result.probs_path)
    valid = alpha > 0
    # a per-pixel function of the image blends back to itself wherever tiles overlap
    np.testing.assert_allclose(probs[0][valid], expected[valid], atol=1e-5)
    np.testing.assert_allclose(probs[1][valid], 0.5 * expected[valid], atol=1e-5)
    assert np.isnan(probs[:, ~valid]).all()
    masks = read(result.masks_path)
    np.testing.assert_array_equal(masks[0][valid], (probs[0][valid] >= 0.4).astype(np.uint8))


# --------------------------------------------------------------------------------------------
# Models a backend owns
# --------------------------------------------------------------------------------------------


def test_a_backend_names_the_model_types_it_accepts(tiny_clipseg) -> None:
    from overseec_core.locate.models import resolve_model

    ref = resolve_model(str(tiny_clipseg), "text-detector", model_types=("owlv2", "clipseg"))
    assert (ref.kind, ref.model_type) == ("text-detector", "clipseg")
    with pytest.raises(ModelError) as err:
        resolve_model(str(tiny_clipseg), "owlv2", model_types=("owlv2", "owlvit"))
    assert f"owlv2 model {tiny_clipseg}: unsupported model type 'clipseg' (expected owlv2 or owlvit)" == str(err.value)
    with pytest.raises(ModelError, match="pass --model /path/to/model-dir"):
        resolve_model("google/not-cached-here", "owlv2", model_types=("owlv2",))


def test_models_list_shows_each_segmenters_default(empty_hub_cache, tmp_path, capsys) -> None:
    from overseec_core.cli import main
    from overseec_core.locate.models import list_models

    rows = {(r.kind, r.name): r for r in list_models()}
    for info in SEGMENTERS.values():
        row = rows[(info.name, info.default_model)]
        assert row.segmenter == info.name and not row.available
    assert rows[("sam", "facebook/sam-vit-base")].segmenter is None
    from overseec_core.locate.refiners import REFINERS

    for refiner in REFINERS.values():  # each refiner's default, under its own kind
        assert not rows[(refiner.name, refiner.default_model)].available
    onnx = tmp_path / "model.onnx"
    onnx.write_bytes(b"onnx")
    extra = {(r.kind, r.name): r for r in list_models([("semantic", str(onnx))])}[("semantic", str(onnx))]
    assert extra.available and extra.path == str(onnx)
    assert main(["models", "list"]) == 0
    lines = capsys.readouterr().out.splitlines()
    owl = next(line for line in lines if "owlv2" in line)
    assert owl.split()[:3] == ["boxes+sam", "google/owlv2-base-patch16-ensemble", "missing"]
    assert owl.endswith("(default of --segmenter boxes+sam)")


def test_the_dask_worker_cache_may_nest(tiny_clipseg) -> None:
    """A worker caches the loaded segmenter, whose build caches the CLIPSeg bundle: the process
    cache is re-entrant (a plain lock deadlocked here)."""
    from overseec_core.locate.dask import SegmenterSpec, segmenter_task
    from overseec_core.locate.models import load_count
    from overseec_core.locate.segment import SegmentOptions

    spec = SegmenterSpec("clipseg", str(tiny_clipseg), ENTITIES, replace(SegmentOptions(device="cpu"), batch_size=2))
    rgb = np.random.default_rng(1).integers(0, 256, (2, 32, 32, 3), dtype=np.uint8)
    before = load_count(("segmenter",))
    first = segmenter_task(spec, rgb, np.ones((2, 32, 32), bool))
    again = segmenter_task(spec, rgb, np.ones((2, 32, 32), bool))
    assert load_count(("segmenter",)) == before + 1  # loaded once, then reused
    np.testing.assert_array_equal(first, again)
