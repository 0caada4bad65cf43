"""CLIPSeg over tiles: shared encoder, pre-processing, thresholds, georeferenced outputs, bad input."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import rasterio

torch = pytest.importorskip("torch")

from overseec_core.errors import Cancelled, InputError, OutputError  # noqa: E402
from overseec_core.locate.clipseg import ClipSegPredictor, load_clipseg, preprocess, text_embeddings  # noqa: E402
from overseec_core.locate.entities import (  # noqa: E402
    apply_thresholds,
    entity_prompts,
    threshold_of,
    validate_entities,
)
from overseec_core.locate.segment import SegmentOptions, segment_image  # noqa: E402
from overseec_core.progress import NullProgress  # noqa: E402
from overseec_core.schema import Entity  # noqa: E402

from .conftest import write_geotiff  # noqa: E402

ENTITIES = (
    Entity("road", "linear"),
    Entity("tree", "areal"),
    Entity("water", "areal", threshold=0.5),
    Entity("baseball field", "areal"),
)


@pytest.fixture
def bundle(tiny_clipseg):
    return load_clipseg(str(tiny_clipseg), "cpu")


@pytest.fixture
def tiles(rng) -> np.ndarray:
    return rng.integers(0, 256, (2, 80, 72, 3), dtype=np.uint8)


def options(model: Path, **kw) -> SegmentOptions:
    return SegmentOptions(clipseg_model=str(model), device="cpu", tile_size=96, **kw)


class EncoderCounter:
    """Counts tiles through the vision encoder's entry and each encoder layer."""

    def __init__(self, model) -> None:
        vm = model.clip.vision_model
        self.tiles = 0
        self.layer_calls = [0] * len(vm.encoder.layers)
        self.handles = [vm.embeddings.register_forward_hook(self._count)]
        for i, layer in enumerate(vm.encoder.layers):
            self.handles.append(layer.register_forward_hook(lambda m, a, o, i=i: self._layer(i)))

    def _count(self, module, args, output) -> None:
        self.tiles += int(output.shape[0])

    def _layer(self, i: int) -> None:
        self.layer_calls[i] += 1

    def __enter__(self) -> EncoderCounter:
        return self

    def __exit__(self, *exc) -> None:
        for h in self.handles:
            h.remove()


def test_shared_encoder_gives_the_library_forward_logits(bundle, tiles) -> None:
    """One encoder pass for all entities == CLIPSegForImageSegmentation(pixel_values, input_ids)."""
    from transformers import CLIPSegProcessor

    processor = CLIPSegProcessor.from_pretrained(bundle.ref.path)
    texts = ["road", "tree", "baseball field"]
    pixels = processor(images=list(tiles), return_tensors="pt")["pixel_values"]
    cond = text_embeddings(bundle, [(t,) for t in texts])
    predictor = ClipSegPredictor(bundle, cond)
    with torch.no_grad():
        shared = predictor.decode(predictor.encode(pixels), cond)  # (B, E, S, S)
        text = processor(text=texts, padding=True, return_tensors="pt")
        for b in range(len(tiles)):
            plain = bundle.model(
                input_ids=text["input_ids"],
                attention_mask=text["attention_mask"],
                pixel_values=pixels[b : b + 1].expand(len(texts), -1, -1, -1),
            ).logits
            assert plain.abs().max() > 0.5  # the comparison is not between near-zero maps
            torch.testing.assert_close(shared[b], plain, atol=1e-5, rtol=0)


def test_torch_preprocessing_matches_the_clipseg_processor(bundle, tiles, tmp_path) -> None:
    """Within a grey level of the library's PIL processor: exact without resize, nearly always
    exact on imagery, at most two levels off on pure noise (PIL's fixed-point filter weights)."""
    from transformers import CLIPSegProcessor

    from overseec_core.sample import generate

    processor = CLIPSegProcessor.from_pretrained(bundle.ref.path)
    size = bundle.norm.size
    level = 1 / 255 / min(bundle.norm.std)  # one grey level after normalisation

    def compare(rgb: np.ndarray) -> torch.Tensor:
        ours = preprocess(rgb, bundle.norm, size, "cpu")
        ref = processor(images=list(rgb), return_tensors="pt")["pixel_values"]
        assert ours.shape == ref.shape == (len(rgb), 3, size, size)
        return (ours - ref).abs()

    noise = compare(tiles)
    assert noise.max() <= 2 * level + 1e-4 and noise.mean() < 0.1 * level
    with rasterio.open(generate(tmp_path / "scene", size=256).image) as ds:
        scene = np.moveaxis(ds.read(), 0, -1)
    imagery = compare(np.stack([scene[:100, :90], scene[100:200, 50:140]]))
    assert imagery.max() <= level + 1e-4 and (imagery > 1e-4).float().mean() < 0.01
    exact = np.ascontiguousarray(tiles[:, :size, :size])  # no resize: identical
    assert compare(exact).max() < 1e-5


def test_output_is_bilinear_resampled_logits(bundle, tiles) -> None:
    cond = text_embeddings(bundle, [("road",), ("tree",)])
    predictor = ClipSegPredictor(bundle, cond, model_size=32)
    probs = predictor(tiles, np.ones(tiles.shape[:3], bool))
    assert probs.shape == (2, 2, 80, 72) and probs.dtype == np.float32
    logits = predictor.logits(tiles)
    assert logits.shape == (2, 2, 32, 32)  # model size is separate from the tile size
    expected = torch.sigmoid(
        torch.nn.functional.interpolate(
            logits.reshape(4, 1, 32, 32), size=(80, 72), mode="bilinear", align_corners=False
        )
    )
    np.testing.assert_allclose(probs, expected.reshape(2, 2, 80, 72).numpy(), atol=1e-6)
    assert len(np.unique(probs[0, 0])) > 32 * 32  # interpolated, not nearest-neighbour blocks


def test_prompt_ensemble_is_the_mean_embedding(bundle) -> None:
    both = text_embeddings(bundle, [("water", "lake")])
    single = text_embeddings(bundle, [("water",), ("lake",)])
    torch.testing.assert_close(both[0], single.mean(dim=0), atol=1e-6, rtol=0)
    assert entity_prompts(Entity("tree", prompts=("tree", "forest")), "aerial view of {}") == (
        "aerial view of tree",
        "aerial view of forest",
    )


def test_encoder_runs_once_per_tile_whatever_the_number_of_entities(tiny_clipseg, tmp_path) -> None:
    image = write_geotiff(tmp_path / "img.tif", 200, 150)
    bundle = load_clipseg(str(tiny_clipseg), "cpu")
    last_needed = max(bundle.model.config.extract_layers)
    for n_entities in (1, 4):
        with EncoderCounter(bundle.model) as counter:
            result = segment_image(image, ENTITIES[:n_entities], tmp_path / f"out{n_entities}", options(tiny_clipseg))
        assert result.tiles == 6 and result.tiles_skipped == 0
        assert counter.tiles == result.encoder_calls == 6
        assert counter.layer_calls[last_needed + 1 :] == [0] * (len(counter.layer_calls) - last_needed - 1)


def test_outputs_are_georeferenced_thresholded_and_named(tiny_clipseg, tmp_path) -> None:
    image = write_geotiff(tmp_path / "img.tif", 200, 150, crs="EPSG:4326")
    result = segment_image(image, ENTITIES, tmp_path / "out", options(tiny_clipseg))
    assert result.thresholds == (0.4, 0.8, 0.5, 0.8)
    with rasterio.open(image) as src, rasterio.open(result.probs_path) as p, rasterio.open(result.masks_path) as m:
        for ds in (p, m):
            assert (ds.width, ds.height, ds.crs, ds.transform) == (src.width, src.height, src.crs, src.transform)
            assert ds.descriptions == ("road", "tree", "water", "baseball field")
        assert p.dtypes[0] == "float32" and np.isnan(p.nodata)
        assert m.dtypes[0] == "uint8" and m.nodata == 255
        probs, masks = p.read(), m.read()
        assert "baseball field" in p.tags()["OVERSEEC_ENTITIES"]
    assert np.isfinite(probs).all() and 0 <= probs.min() and probs.max() <= 1
    assert 0.01 < probs.std()  # a real, varying prediction
    for band, tau in enumerate(result.thresholds):
        np.testing.assert_array_equal(masks[band], (probs[band] >= tau).astype(np.uint8))
    assert set(np.unique(masks)) <= {0, 1}


def test_tiles_blend_to_the_single_tile_prediction_where_tiles_do_not_overlap(tiny_clipseg, tmp_path) -> None:
    """The first tile's interior (no other tile reaches it) equals the model on that window."""
    image = write_geotiff(tmp_path / "img.tif", 200, 150)
    result = segment_image(image, ENTITIES[:2], tmp_path / "out", options(tiny_clipseg, overlap=16))
    bundle = load_clipseg(str(tiny_clipseg), "cpu")
    with rasterio.open(image) as ds:
        rgb = np.moveaxis(ds.read([1, 2, 3], window=((0, 96), (0, 96))), 0, -1)[None]
    cond = text_embeddings(bundle, [entity_prompts(e) for e in ENTITIES[:2]])
    direct = ClipSegPredictor(bundle, cond)(rgb, np.ones((1, 96, 96), bool))[0]
    with rasterio.open(result.probs_path) as ds:
        blended = ds.read(window=((0, 96), (0, 96)))
    # tiles start at rows 0, 54 and columns 0, 80, 104: rows < 54 and columns < 80 are tile 1's alone
    np.testing.assert_allclose(blended[:, :54, :80], direct[:, :54, :80], atol=1e-6)
    assert np.abs(blended[:, 60:, 85:96] - direct[:, 60:, 85:96]).max() > 1e-3  # blended there


def test_all_nodata_tiles_are_skipped(tiny_clipseg, tmp_path) -> None:
    # tiles start at columns 0, 96, 104: the two tiles in column 0 hold no data at all
    image = write_geotiff(tmp_path / "img.tif", 200, 150, nodata_box=(0, 150, 0, 100))
    bundle = load_clipseg(str(tiny_clipseg), "cpu")
    with EncoderCounter(bundle.model) as counter:
        result = segment_image(image, ENTITIES[:2], tmp_path / "out", options(tiny_clipseg, overlap=0))
    assert result.tiles == 6 and result.tiles_skipped == 2
    assert counter.tiles == 4
    with rasterio.open(result.probs_path) as p, rasterio.open(result.masks_path) as m:
        probs, masks = p.read(), m.read()
    assert np.isnan(probs[:, :, :100]).all() and (masks[:, :, :100] == 255).all()
    assert np.isfinite(probs[:, :, 100:]).all() and (masks[:, :, 100:] <= 1).all()


def test_image_smaller_than_a_tile(tiny_clipseg, tmp_path) -> None:
    image = write_geotiff(tmp_path / "small.tif", 40, 30)
    result = segment_image(image, ENTITIES[:1], tmp_path / "out", replace(options(tiny_clipseg), tile_size=512))
    assert result.tiles == 1
    with rasterio.open(result.probs_path) as ds:
        assert (ds.width, ds.height) == (40, 30) and np.isfinite(ds.read()).all()
    tiny = write_geotiff(tmp_path / "tiny.tif", 12, 40)
    with pytest.raises(InputError, match="12x40 px"):
        segment_image(tiny, ENTITIES[:1], tmp_path / "out2", options(tiny_clipseg))


def test_bad_entities() -> None:
    with pytest.raises(InputError, match="no entities"):
        validate_entities([])
    with pytest.raises(InputError, match="duplicate entity name 'Road'"):
        validate_entities([Entity("road", "linear"), Entity("Road", "areal")])
    with pytest.raises(InputError, match="geometry 'blob'"):
        validate_entities([Entity("road", "blob")])  # type: ignore[arg-type]
    with pytest.raises(InputError, match="threshold 1.5"):
        validate_entities([Entity("road", threshold=1.5)])
    with pytest.raises(InputError, match="empty name"):
        validate_entities([Entity("  ")])
    assert threshold_of(Entity("road", "linear")) == 0.4
    assert threshold_of(Entity("grass", "areal")) == 0.8
    ents = apply_thresholds([Entity("road", "linear")], {"ROAD": 0.3})
    assert threshold_of(ents[0]) == 0.3
    with pytest.raises(InputError, match="unknown entity 'river'"):
        apply_thresholds([Entity("road", "linear")], {"river": 0.3})


def test_bad_settings(tiny_clipseg, tmp_path) -> None:
    image = write_geotiff(tmp_path / "img.tif", 100, 100)
    with pytest.raises(InputError, match="multiple of the model's patch size 16"):
        segment_image(image, ENTITIES[:1], tmp_path / "o1", options(tiny_clipseg, model_size=40))
    with pytest.raises(InputError, match="overlap 60"):
        segment_image(image, ENTITIES[:1], tmp_path / "o2", options(tiny_clipseg, overlap=60))
    from overseec_core.errors import ModelError

    with pytest.raises(ModelError, match="unknown device 'gpu7'"):
        segment_image(image, ENTITIES[:1], tmp_path / "o3", replace(options(tiny_clipseg), device="gpu7"))


def test_never_overwrites_the_input(tiny_clipseg, tmp_path) -> None:
    out = tmp_path / "out"
    out.mkdir()
    image = write_geotiff(out / "probs.tif", 100, 100)
    before = image.read_bytes()
    with pytest.raises(OutputError, match="is the input"):
        segment_image(image, ENTITIES[:1], out, options(tiny_clipseg))
    assert image.read_bytes() == before


class CancelAfter(NullProgress):
    """Cancels once ``n`` tiles were reported."""

    def __init__(self, n: int) -> None:
        super().__init__()
        self.n = n

    def advance(self, n: int = 1) -> None:
        super().advance(n)
        if self.done >= self.n:
            self.token.cancel()


def test_cancellation_leaves_no_outputs(tiny_clipseg, tmp_path) -> None:
    image = write_geotiff(tmp_path / "img.tif", 300, 300)
    out = tmp_path / "out"
    with pytest.raises(Cancelled):
        segment_image(image, ENTITIES[:2], out, replace(options(tiny_clipseg), batch_size=1), progress=CancelAfter(2))
    assert sorted(p.name for p in out.iterdir()) == []


def test_out_of_memory_halves_the_batch_with_the_same_result(bundle, tiles, monkeypatch) -> None:
    cond = text_embeddings(bundle, [("road",), ("tree",)])
    valid = np.ones(tiles.shape[:3], bool)
    expected = ClipSegPredictor(bundle, cond, batch_size=2)(tiles, valid)
    predictor = ClipSegPredictor(bundle, cond, batch_size=2)
    real = predictor.logits

    def small_batches_only(rgb):
        if len(rgb) > 1:
            raise torch.cuda.OutOfMemoryError("CUDA out of memory. Tried to allocate 8 GiB")
        return real(rgb)

    monkeypatch.setattr(predictor, "logits", small_batches_only)
    np.testing.assert_allclose(predictor(tiles, valid), expected, atol=1e-6)
    assert predictor.state.size == 1 and predictor.state.halvings == 1
