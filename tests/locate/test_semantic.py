"""The ``semantic`` segmenter: a fixed-ontology model (a transformers checkpoint or an ONNX file)
whose classes are summed into entity probabilities.

Tiny random-weight SegFormer and UperNet checkpoints are built from configs
(:mod:`tests.locate.builders_semantic`); parity is against the library's own forward and
upsampling, and the ONNX path against the torch forward of the same weights.
"""

from __future__ import annotations

import importlib.util
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
import rasterio

torch = pytest.importorskip("torch")
pytest.importorskip("transformers")

from overseec_core.errors import InputError, ModelError  # noqa: E402
from overseec_core.io.read import RasterSource  # noqa: E402
from overseec_core.io.write import RasterWriter  # noqa: E402
from overseec_core.locate.segment import SegmentOptions  # noqa: E402
from overseec_core.locate.segmenters import SEGMENTERS, semantic  # noqa: E402
from overseec_core.locate.tiling import TileGrid, stream_predict, writer_sink  # noqa: E402
from overseec_core.schema import Entity  # noqa: E402

from . import builders_semantic as bs  # noqa: E402
from .conftest import write_geotiff  # noqa: E402

CPU = SegmentOptions(device="cpu", precision="fp32")
SIZE = 64  # the tiny models' processor size


@pytest.fixture(scope="session")
def segformer_dir(tmp_path_factory) -> Path:
    return bs.save_semantic(tmp_path_factory.mktemp("models") / "tiny-segformer", "segformer")


@pytest.fixture(scope="session")
def upernet_dir(tmp_path_factory) -> Path:
    return bs.save_semantic(tmp_path_factory.mktemp("models") / "tiny-upernet", "upernet")


@pytest.fixture
def segformer(segformer_dir: Path, tmp_path: Path) -> Path:
    """A private copy (its own sidecar, its own cache key) of the tiny SegFormer."""
    return Path(shutil.copytree(segformer_dir, tmp_path / "segformer"))


def _tiles(n: int, side: int, seed: int = 0) -> np.ndarray:
    """Smooth RGB tiles with structure (a model sees shapes, not only noise)."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:side, 0:side]
    out = []
    for _ in range(n):
        fx, fy, phase = rng.uniform(3, 12, 3)
        base = np.stack([np.sin(xx / fx + phase), np.cos(yy / fy), np.sin((xx + yy) / (fx + fy))]) * 110 + 128
        out.append(np.clip(base + rng.normal(0, 12, base.shape), 0, 255).astype(np.uint8).transpose(1, 2, 0))
    return np.stack(out)


def _valid(rgb: np.ndarray) -> np.ndarray:
    return np.ones(rgb.shape[:3], bool)


def _library_probs(folder: Path, rgb: np.ndarray) -> np.ndarray:
    """The library's way: image processor, the model's forward, logits upsampled to the tile, softmax."""
    from transformers import AutoImageProcessor, AutoModelForSemanticSegmentation

    processor = AutoImageProcessor.from_pretrained(folder)
    model = AutoModelForSemanticSegmentation.from_pretrained(folder).eval()
    pixels = processor(images=list(rgb), return_tensors="pt")["pixel_values"]
    with torch.no_grad():
        logits = model(pixel_values=pixels).logits
    up = torch.nn.functional.interpolate(logits, size=rgb.shape[1:3], mode="bilinear", align_corners=False)
    return up.softmax(dim=1).numpy()


# ------------------------------------------------------------------------------ parity


@pytest.mark.parametrize("arch", ["segformer", "upernet"])
def test_class_probabilities_equal_the_library_forward(arch: str, segformer_dir: Path, upernet_dir: Path) -> None:
    folder = segformer_dir if arch == "segformer" else upernet_dir
    seg = semantic.load(str(folder), [Entity("road")], CPU)
    rgb = _tiles(2, SIZE)
    ours = seg.class_probabilities(rgb)
    ref = _library_probs(folder, rgb)
    assert ours.shape == ref.shape == (2, len(bs.CLASSES), SIZE, SIZE)
    assert ref.std() > 0.05, "random weights too flat for the comparison to mean anything"
    np.testing.assert_allclose(ours, ref, atol=1e-5)
    np.testing.assert_allclose(ours.sum(axis=1), 1.0, atol=1e-5)


def test_resized_tiles_see_the_processors_pixels_within_one_grey_level(segformer_dir: Path) -> None:
    """A tile larger than the model's input is resized as the library's processor does (to one
    grey level), and the probabilities come back on the tile's own grid."""
    from transformers import AutoImageProcessor

    seg = semantic.load(str(segformer_dir), [Entity("road")], CPU)
    assert seg.model_size == SIZE  # the processor's size
    rgb = _tiles(2, 100, seed=3)
    processor = AutoImageProcessor.from_pretrained(segformer_dir)
    theirs = processor(images=list(rgb), return_tensors="pt")["pixel_values"]
    ours = semantic.preprocess(rgb, seg.norm, seg.model_size, torch.device("cpu"))
    grey = (ours - theirs).abs() * torch.tensor(semantic.IMAGENET_STD).view(1, 3, 1, 1) * 255
    assert float(grey.max()) <= 1.0 + 1e-3
    probs = seg.class_probabilities(rgb)
    assert probs.shape == (2, len(bs.CLASSES), 100, 100)
    np.testing.assert_allclose(probs, _library_probs(segformer_dir, rgb), atol=5e-3)


# ------------------------------------------------------------------------------ entities


def test_an_entity_is_the_sum_of_its_classes(segformer: Path) -> None:
    bs.write_sidecar(segformer, entities={"paved area": ["road", "water"]})
    seg = semantic.load(str(segformer), [Entity("paved area"), Entity("tree")], CPU)
    assert [m.labels for m in seg.mapping] == [("road", "water"), ("tree",)]
    assert [m.rule for m in seg.mapping] == ["metadata", "name"]
    rgb = _tiles(2, SIZE, seed=1)
    classes = seg.class_probabilities(rgb)
    probs = seg(rgb, _valid(rgb))
    assert probs.shape == (2, 2, SIZE, SIZE) and probs.dtype == np.float32
    np.testing.assert_allclose(probs[:, 0], classes[:, 1] + classes[:, 4], atol=1e-6)
    np.testing.assert_allclose(probs[:, 1], classes[:, 2], atol=1e-6)
    assert 0.0 <= probs.min() and probs.max() <= 1.0


def test_entities_match_classes_by_synonym_modifier_broader_and_prompt(segformer: Path) -> None:
    ents = [
        Entity("Streets", "linear"),  # plural, synonym of road
        Entity("woods"),  # synonym of tree (via forest)
        Entity("lake"),  # inside water
        Entity("dirt road", "linear"),  # a road with a modifier
        Entity("lawn area", prompts=("turf", "grass")),  # no class by name; its prompt "turf" is grass
    ]
    seg = semantic.load(str(segformer), ents, CPU)
    got = {m.entity: (m.labels, m.rule) for m in seg.mapping}
    assert got["Streets"] == (("road",), "synonym")
    assert got["woods"] == (("tree",), "synonym")
    assert got["lake"] == (("water",), "broader")
    assert got["dirt road"] == (("road",), "modifier")
    assert got["lawn area"][0] == ("grass",) and got["lawn area"][1].startswith("prompt:")
    assert "woods <- tree (synonym)" in seg.describe()


def test_an_entity_no_class_maps_to_fails_in_one_line_listing_the_classes(segformer: Path) -> None:
    with pytest.raises(InputError) as err:
        semantic.load(str(segformer), [Entity("road"), Entity("volcano")], CPU)
    message = str(err.value)
    assert "\n" not in message and "'volcano'" in message
    assert all(f"{i}:{c}" in message for i, c in enumerate(bs.CLASSES))
    assert "overseec.json" in message  # where to map it


def test_metadata_mapping_to_a_missing_class_is_an_error(segformer: Path) -> None:
    bs.write_sidecar(segformer, entities={"road": ["road", "motorway"]})
    with pytest.raises(ModelError, match=r"entity 'road' to class 'motorway', which the model lacks"):
        semantic.load(str(segformer), [Entity("road")], CPU)


# ------------------------------------------------------------------------------ metadata


def test_sidecar_classes_resolution_and_size_are_used(segformer: Path) -> None:
    classes = {"0": "clutter", "1": "impervious surface", "2": "tree", "3": "low vegetation", "4": "water"}
    bs.write_sidecar(segformer, classes=classes, gsd_m=0.3, input_size=32, entities={"road": "impervious surface"})
    seg = semantic.load(str(segformer), [Entity("road"), Entity("water")], CPU)
    assert seg.classes == tuple(classes.values())
    assert seg.gsd_m == 0.3 and seg.model_size == 32 and seg.norm.size == 32
    assert [m.labels for m in seg.mapping] == [("impervious surface",), ("water",)]
    assert "0.3 m/px" in seg.describe()
    assert seg.to_json()["entities"]["road"] == {"classes": ["impervious surface"], "rule": "metadata"}
    rgb = _tiles(1, 48)
    assert seg(rgb, _valid(rgb)).shape == (1, 2, 48, 48)


def test_model_size_option_wins_over_metadata(segformer: Path) -> None:
    bs.write_sidecar(segformer, input_size=32)
    seg = semantic.load(str(segformer), [Entity("road")], SegmentOptions(device="cpu", model_size=96))
    assert seg.model_size == 96


@pytest.mark.parametrize(
    ("meta", "match"),
    [
        ({"clases": {}}, r"unknown key\(s\) clases"),
        ({"classes": {"0": "a", "2": "b"}}, r"class indices must be 0\.\.1"),
        ({"gsd_m": -1}, r'"gsd_m" must be a positive float'),
        ({"input_size": 51.5}, r'"input_size" must be a positive int'),
        ({"std": [0.2, 0, 0.2]}, r'"std" must be three positive numbers'),
        ({"outputs": "softmax"}, r'"outputs" must be one of logits, probs'),
        ({"entities": {"road": []}}, r"must be a class name or a list"),
    ],
)
def test_bad_metadata_is_a_one_line_error_naming_the_file(segformer: Path, meta: dict, match: str) -> None:
    sidecar = bs.write_sidecar(segformer, **meta)
    with pytest.raises(ModelError, match=match) as err:
        semantic.load(str(segformer), [Entity("road")], CPU)
    assert str(sidecar) in str(err.value) and "\n" not in str(err.value)


def test_classes_that_disagree_with_the_model_output_are_an_error(segformer: Path) -> None:
    bs.write_sidecar(segformer, classes=["background", "road", "tree"])
    seg = semantic.load(str(segformer), [Entity("road")], CPU)
    rgb = _tiles(1, SIZE)
    with pytest.raises(ModelError, match=r"outputs 5 classes but its metadata names 3"):
        seg(rgb, _valid(rgb))


def test_deepness_onnx_metadata_is_read() -> None:
    props = {
        "class_names": "{0: 'background', 1: 'field'}",  # Deepness writes Python dict literals too
        "resolution": "30",  # cm/px
        "tiles_size": "256",
        "model_type": '"Segmentor"',
        "standardization_parameters": '{"mean": [0.1, 0.2, 0.3], "std": [0.5, 0.5, 0.5]}',
    }
    meta = semantic.deepness_meta(props, "m.onnx")
    assert meta.classes == ("background", "field")
    assert meta.gsd_m == pytest.approx(0.3) and meta.input_size == 256
    assert meta.mean == (0.1, 0.2, 0.3) and meta.std == (0.5, 0.5, 0.5) and meta.outputs == "probs"


# ------------------------------------------------------------------------------ batches


def test_batches_give_the_same_probabilities_as_single_tiles(segformer_dir: Path) -> None:
    seg = semantic.load(str(segformer_dir), [Entity("road"), Entity("tree"), Entity("grass")], CPU)
    rgb = _tiles(5, 80, seed=7)
    together = seg(rgb, _valid(rgb))
    alone = np.concatenate([seg(rgb[i : i + 1], _valid(rgb[i : i + 1])) for i in range(len(rgb))])
    np.testing.assert_allclose(together, alone, atol=1e-6)
    calls = seg.encoder_calls
    seg.state.size = 2  # micro-batches of 2 (as after an out-of-memory halving)
    np.testing.assert_allclose(seg(rgb, _valid(rgb)), together, atol=1e-6)
    assert seg.encoder_calls == calls + len(rgb)


def test_through_the_tiling_engine(segformer_dir: Path, tmp_path: Path) -> None:
    """The segmenter is the engine's BatchPredictor: tiles in, blended probability bands out."""
    image = write_geotiff(tmp_path / "img.tif", width=150, height=110)
    seg = semantic.load(str(segformer_dir), [Entity("road", "linear"), Entity("tree")], CPU)
    with RasterSource(image) as src:
        grid = TileGrid(src.grid.width, src.grid.height, 64, 16)
        with RasterWriter(tmp_path / "probs.tif", src.grid, 2, "float32", nodata=float("nan")) as writer:
            stats = stream_predict(src, seg, writer_sink(writer), grid, 2, batch_size=3, flush_rows=writer.block_rows)
    with rasterio.open(tmp_path / "probs.tif") as ds:
        probs = ds.read()
    assert probs.shape == (2, 110, 150) and np.isfinite(probs).all()
    assert 0.0 <= probs.min() and probs.max() <= 1.0 and probs.std() > 0.01
    assert seg.encoder_calls == stats.tiles - stats.tiles_skipped


# ------------------------------------------------------------------------------ resolution


def test_the_default_model_is_the_registrys_and_fails_fast_offline() -> None:
    default = SEGMENTERS["semantic"].default_model
    with pytest.raises(ModelError, match="not available offline") as err:
        semantic.load(None, [Entity("road")], CPU)
    assert default in str(err.value) and "overseec models download" in str(err.value)


def test_missing_and_wrong_models_are_one_line_errors(tmp_path: Path, tiny_clipseg: Path) -> None:
    cases = [
        ("someone/not-cached-segformer", "not available offline"),
        (str(tmp_path / "nothing.onnx"), "no such ONNX file"),
        (str(tmp_path / "nowhere"), "not a hub id"),
        (str(tmp_path), "has no config.json"),
        (str(tiny_clipseg), "model type 'clipseg' is not a semantic segmenter"),
    ]
    for name, match in cases:
        with pytest.raises(ModelError, match=match) as err:
            semantic.load(name, [Entity("road")], CPU)
        assert name in str(err.value) and "\n" not in str(err.value)


def test_an_onnx_model_without_onnxruntime_says_how_to_install_it(tmp_path: Path, monkeypatch) -> None:
    model = tmp_path / "model.onnx"
    model.write_bytes(b"not read: onnxruntime is missing first")
    monkeypatch.setitem(sys.modules, "onnxruntime", None)  # `import onnxruntime` raises ImportError
    with pytest.raises(ModelError, match=r"needs onnxruntime: pip install onnxruntime"):
        semantic.load(str(model), [Entity("road")], CPU)


# ------------------------------------------------------------------------------ ONNX

_ONNX_MISSING = [m for m in ("onnxruntime", "onnx") if importlib.util.find_spec(m) is None]


@pytest.mark.skipif(
    bool(_ONNX_MISSING),
    reason=f"{' and '.join(_ONNX_MISSING)} not installed (optional: pip install onnxruntime onnx) "
    "- the ONNX path is untested here",
)
def test_onnx_model_equals_the_torch_forward(segformer_dir: Path, tmp_path: Path) -> None:
    onnx_path = bs.export_onnx(segformer_dir, tmp_path / "segformer.onnx")
    ents = [Entity("road", "linear"), Entity("woods")]
    with pytest.raises(ModelError, match="names no classes"):
        semantic.load(str(onnx_path), ents, CPU)  # an ONNX graph has no id2label
    rgb = _tiles(3, 80, seed=11)
    torch_seg = semantic.load(str(segformer_dir), ents, CPU)
    bs.write_sidecar(onnx_path, classes=list(bs.CLASSES), input_size=SIZE)
    unscaled = semantic.load(str(onnx_path), ents, CPU)  # ONNX default: 0..1 pixels, no mean/std
    assert unscaled.norm.mean == (0.0, 0.0, 0.0) and unscaled.norm.std == (1.0, 1.0, 1.0)
    assert np.abs(unscaled(rgb, _valid(rgb)) - torch_seg(rgb, _valid(rgb))).max() > 1e-2
    bs.write_sidecar(
        onnx_path, classes=list(bs.CLASSES), input_size=SIZE, mean=bs.IMAGENET_MEAN, std=bs.IMAGENET_STD, gsd_m=0.5
    )
    onnx_seg = semantic.load(str(onnx_path), ents, CPU)
    assert onnx_seg.ref.model_type == "onnx" and "CPUExecutionProvider" in onnx_seg.describe()
    assert [m.labels for m in onnx_seg.mapping] == [("road",), ("tree",)]
    np.testing.assert_allclose(onnx_seg.class_probabilities(rgb), torch_seg.class_probabilities(rgb), atol=1e-4)
    np.testing.assert_allclose(onnx_seg(rgb, _valid(rgb)), torch_seg(rgb, _valid(rgb)), atol=1e-4)
    assert onnx_seg.gsd_m == 0.5


@pytest.mark.skipif(bool(_ONNX_MISSING), reason=f"{' and '.join(_ONNX_MISSING)} not installed")
def test_onnx_deepness_metadata_in_the_file(segformer_dir: Path, tmp_path: Path) -> None:
    import onnx

    onnx_path = bs.export_onnx(segformer_dir, tmp_path / "deep.onnx")
    graph = onnx.load(str(onnx_path))
    for key, value in {
        "class_names": '{"0": "background", "1": "road", "2": "tree", "3": "grass", "4": "water"}',
        "resolution": "50",
        "tiles_size": str(SIZE),
    }.items():
        entry = graph.metadata_props.add()
        entry.key, entry.value = key, value
    onnx.save(graph, str(onnx_path))
    seg = semantic.load(str(onnx_path), [Entity("street")], CPU)
    assert seg.classes == bs.CLASSES and seg.gsd_m == pytest.approx(0.5) and seg.model_size == SIZE
    assert seg.mapping[0].labels == ("road",)
