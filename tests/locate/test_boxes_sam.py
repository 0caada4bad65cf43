"""The ``boxes+sam`` segmenter: parity of its boxes and masks with the library's own pipeline
(OWLv2 forward + post-processing, SamProcessor + SamModel forward + ``post_process_masks``), text
embedded once, batches equal tiles one by one, invalid pixels, missing models, tiling end to end."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import rasterio

torch = pytest.importorskip("torch")
pytest.importorskip("transformers")

from overseec_core.errors import InputError, ModelError  # noqa: E402
from overseec_core.io.read import RasterSource  # noqa: E402
from overseec_core.locate.entities import entity_prompts  # noqa: E402
from overseec_core.locate.segmenters import boxes_sam  # noqa: E402
from overseec_core.locate.segmenters.boxes_sam import (  # noqa: E402
    BoxSettings,
    box_iou,
    clip_boxes,
    combine,
    load,
    nms_cap,
    select_boxes,
)
from overseec_core.locate.tiling import TileGrid, stream_predict  # noqa: E402
from overseec_core.schema import Entity  # noqa: E402

from . import builders_detect  # noqa: E402
from .conftest import write_geotiff  # noqa: E402

ENTITIES = (Entity("road", "linear"), Entity("tree", "areal", prompts=("tree", "water")))


@pytest.fixture(scope="module")
def tiny_owlv2(tmp_path_factory) -> Path:
    return builders_detect.save_owlv2(tmp_path_factory.mktemp("models") / "tiny-owlv2")


def opts(sam: Path, **kw) -> SimpleNamespace:
    """The SegmentOptions fields the backend reads (the registry's SegmentOptions once merged)."""
    base = dict(
        device="cpu",
        precision="fp32",
        batch_size=None,
        model_size=None,
        prompt_template="{}",
        compile=False,
        sam_model=str(sam),
    )
    return SimpleNamespace(**{**base, **kw})


@pytest.fixture
def seg(tiny_owlv2, tiny_sam):
    return load(str(tiny_owlv2), ENTITIES, opts(tiny_sam))


@pytest.fixture
def tiles(rng) -> np.ndarray:
    return rng.integers(0, 256, (3, 96, 96, 3), dtype=np.uint8)


# --- the library's own pipeline, for parity --------------------------------------------------


def library_boxes(owl_dir: Path, tile: np.ndarray, prompts: list[str], threshold: float) -> tuple:
    """OWLv2 as its docs run it: processor(text, images) -> forward -> post-processing."""
    from transformers import Owlv2ForObjectDetection, Owlv2Processor

    proc = Owlv2Processor.from_pretrained(owl_dir)
    model = Owlv2ForObjectDetection.from_pretrained(owl_dir).eval()
    inputs = proc(text=[prompts], images=[tile], return_tensors="pt")
    with torch.inference_mode():
        out = model(**inputs)
    side = max(tile.shape[:2])  # boxes are relative to the image padded to a square
    (res,) = proc.post_process_grounded_object_detection(outputs=out, threshold=threshold, target_sizes=[(side, side)])
    return res["boxes"].numpy(), res["scores"].numpy()


def library_masks(sam_dir: Path, tile: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """SAM as its docs run it: SamProcessor(images, input_boxes) -> forward -> post_process_masks."""
    from transformers import SamModel, SamProcessor

    proc = SamProcessor.from_pretrained(sam_dir)
    model = SamModel.from_pretrained(sam_dir).eval()
    inputs = proc(images=[tile], input_boxes=[boxes.tolist()], return_tensors="pt")
    with torch.inference_mode():
        out = model(**inputs, multimask_output=False)
    masks = proc.post_process_masks(
        out.pred_masks, inputs["original_sizes"], inputs["reshaped_input_sizes"], binarize=False
    )[0]
    return torch.sigmoid(masks[:, 0]).numpy()


@pytest.mark.parametrize("shape", [(96, 96), (80, 96)])
def test_boxes_equal_owlv2_forward_and_post_processing(seg, tiny_owlv2, rng, shape):
    """Per entity, our boxes are the library's (that entity's prompts as the text queries), kept
    by the same threshold, then clipped, NMS'd and capped; also for a non-square tile."""
    tile = rng.integers(0, 256, (*shape, 3), dtype=np.uint8)
    (ours,) = seg.detect(tile[None])
    settings, threshold = seg.settings, seg.settings.threshold_for("owlv2")
    assert sum(len(e) for e in ours) > 2 * len(ENTITIES)  # a test with few boxes would prove little
    for entity, got in zip(ENTITIES, ours):
        boxes, scores = library_boxes(tiny_owlv2, tile, list(entity_prompts(entity)), threshold)
        want = nms_cap(clip_boxes(boxes, *shape), scores, settings.nms_iou, settings.max_boxes)
        np.testing.assert_allclose(got.scores, want.scores, rtol=0, atol=1e-5)
        np.testing.assert_allclose(got.boxes, want.boxes, rtol=0, atol=1e-5 * max(shape))


def test_masks_equal_sam_processor_and_forward(seg, tiny_sam, tiles):
    """All boxes of a tile decoded in one call equal SamProcessor + SamModel + post_process_masks."""
    tile = tiles[0]
    (dets,) = seg.detect(tile[None])
    boxes = np.concatenate([d.boxes for d in dets])
    emb, resized = seg.sam.embed(tile[None])
    calls = seg.sam.decoder_calls
    ours = seg.sam.probabilities(emb, boxes, tile.shape[:2], resized[0])
    assert seg.sam.decoder_calls == calls + 1  # one decoder call for the tile's boxes
    want = library_masks(tiny_sam, tile, boxes)
    assert ours.shape == want.shape == (len(boxes), *tile.shape[:2])
    np.testing.assert_allclose(ours, want, rtol=0, atol=1e-5)
    assert want.std() > 0.05  # masks vary: the comparison is not between constants


def test_tile_probability_is_max_of_score_times_mask(seg, tiny_owlv2, tiny_sam, tiles):
    """The whole recipe against the library pieces: P_e = max over e's boxes of score x mask."""
    tile = tiles[1]
    got = seg(tile[None], np.ones((1, *tile.shape[:2]), bool))[0]
    want = np.zeros_like(got)
    for e, entity in enumerate(ENTITIES):
        boxes, scores = library_boxes(tiny_owlv2, tile, list(entity_prompts(entity)), 0.1)
        kept = nms_cap(clip_boxes(boxes, *tile.shape[:2]), scores, 0.5, boxes_sam.MAX_BOXES)
        want[e] = (library_masks(tiny_sam, tile, kept.boxes) * kept.scores[:, None, None]).max(axis=0)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-5)


def test_output_shape_range_and_invalid_pixels(seg, tiles):
    valid = np.ones(tiles.shape[:3], bool)
    valid[1] = False  # an empty tile: no model runs for it
    valid[2, :30] = False
    out = seg(tiles, valid)
    assert out.shape == (3, len(ENTITIES), 96, 96) and out.dtype == np.float32
    assert 0.0 <= out.min() and out.max() <= 1.0
    assert (out[1] == 0).all() and (out[2][:, :30] == 0).all()
    assert out[0].max() > 0.1 and out[2][:, 30:].max() > 0.1
    assert seg.encoder_calls == 2 and seg.sam_tiles == 2


def test_all_invalid_batch_runs_no_model(seg, tiles):
    out = seg(tiles, np.zeros(tiles.shape[:3], bool))
    assert (out == 0).all() and seg.encoder_calls == 0 and seg.sam_tiles == 0


def test_batch_equals_tile_by_tile(seg, tiles):
    valid = np.ones(tiles.shape[:3], bool)
    valid[2, 50:] = False
    batch = seg(tiles, valid)
    one = np.concatenate([seg(tiles[i : i + 1], valid[i : i + 1]) for i in range(len(tiles))])
    np.testing.assert_allclose(batch, one, rtol=0, atol=1e-5)


def test_text_queries_encoded_once_per_run(tiny_owlv2, tiny_sam, tiles):
    """The text model runs at load, never per batch; the vision encoder once per tile."""
    from overseec_core.locate.models import release_models

    release_models()  # a fresh bundle, so the hooks see its load
    seg = load(str(tiny_owlv2), ENTITIES, opts(tiny_sam, batch_size=2))
    model = seg.detector.bundle.model
    text, vision = [], []
    handles = [
        model.owlv2.text_model.register_forward_hook(lambda m, a, o: text.append(1)),
        model.owlv2.vision_model.register_forward_hook(
            lambda m, a, kw, o: vision.append(len(kw["pixel_values"])), with_kwargs=True
        ),
    ]
    try:
        seg(tiles, np.ones(tiles.shape[:3], bool))
        seg(tiles[:1], np.ones((1, 96, 96), bool))
    finally:
        for h in handles:
            h.remove()
    assert text == [] and sum(vision) == 4 and len(vision) == 3  # batches of 2 + 1, then 1


def test_several_prompts_score_with_their_best_query(seg, tiles):
    """'tree' has prompts tree and water: its box scores are the better of the two queries."""
    logits, boxes = seg.detector.raw(seg.detector.pixel_values(tiles[:1]))
    (dets,) = seg.detect(tiles[:1])
    best = torch.sigmoid(logits[0][:, 1:3].max(dim=-1).values).numpy()
    assert set(np.round(dets[1].scores, 6)) <= set(np.round(best, 6))
    assert dets[1].scores[0] == pytest.approx(best.max(), abs=1e-6)


def test_box_threshold_and_cap_from_options(tiny_owlv2, tiny_sam, tiles):
    few = load(str(tiny_owlv2), ENTITIES, opts(tiny_sam, box_threshold=0.6, max_boxes=2))
    (dets,) = few.detect(tiles[:1])
    assert all(len(d) <= 2 and (d.scores > 0.6).all() for d in dets)
    none = load(str(tiny_owlv2), ENTITIES, opts(tiny_sam, box_threshold=0.999))
    out = none(tiles[:1], np.ones((1, 96, 96), bool))
    assert (out == 0).all() and none.encoder_calls == 1 and none.sam_tiles == 0  # no box: SAM skipped


def test_model_size_resizes_the_detector_input(tiny_owlv2, tiny_sam, tiles):
    seg = load(str(tiny_owlv2), ENTITIES, opts(tiny_sam, model_size=96))
    assert seg.model_size == 96 and seg.detector.pixel_values(tiles[:1]).shape[-1] == 96
    out = seg(tiles[:1], np.ones((1, 96, 96), bool))
    assert out.shape == (1, 2, 96, 96) and 0 <= out.min() and out.max() <= 1
    with pytest.raises(InputError, match="multiple of the detector's patch size 16"):
        load(str(tiny_owlv2), ENTITIES, opts(tiny_sam, model_size=100))


# --- box selection ---------------------------------------------------------------------------


def test_nms_keeps_best_first_non_overlapping_and_capped(rng):
    xy = rng.uniform(0, 80, (200, 2))
    boxes = np.concatenate([xy, xy + rng.uniform(5, 30, (200, 2))], axis=1).astype(np.float32)
    scores = rng.uniform(0, 1, 200).astype(np.float32)
    kept = nms_cap(boxes, scores, 0.3, 1000)
    assert (np.diff(kept.scores) <= 0).all()
    for i in range(len(kept)):
        assert (box_iou(kept.boxes[i], kept.boxes[i + 1 :]) <= 0.3).all()
    # greedy: every dropped box overlaps a better kept one
    for b, s in zip(boxes, scores):
        if not (kept.boxes == b).all(axis=1).any():
            better = kept.scores > s
            assert (box_iou(b, kept.boxes[better]) > 0.3).any()
    capped = nms_cap(boxes, scores, 0.3, 5)
    np.testing.assert_array_equal(capped.boxes, kept.boxes[:5])


def test_select_boxes_thresholds_and_clips():
    boxes = np.array([[-5, -5, 20, 20], [10, 10, 200, 50], [0, 0, 5, 5]], np.float32)
    kept = select_boxes(boxes, np.array([0.9, 0.5, 0.05], np.float32), 0.1, BoxSettings(), 64, 100)
    np.testing.assert_array_equal(kept.boxes, [[0, 0, 20, 20], [10, 10, 100, 50]])
    empty = select_boxes(boxes, np.zeros(3, np.float32), 0.1, BoxSettings(), 64, 100)
    assert len(empty) == 0 and empty.boxes.shape == (0, 4)


def test_combine_is_max_of_score_times_mask():
    masks = np.stack([np.full((2, 2), 0.5), np.eye(2), np.ones((2, 2))]).astype(np.float32)
    out = combine(masks, np.array([0.8, 0.9, 0.3], np.float32), np.array([0, 0, 2]), 3)
    np.testing.assert_allclose(out[0], [[0.9, 0.4], [0.4, 0.9]])
    assert (out[1] == 0).all() and np.allclose(out[2], 0.3)


def test_bad_settings_are_one_line_errors():
    with pytest.raises(InputError, match="box threshold 1.5"):
        BoxSettings(box_threshold=1.5)
    with pytest.raises(InputError, match="max boxes"):
        BoxSettings(max_boxes=0)


# --- models that are not there ---------------------------------------------------------------


def test_missing_detector_fails_fast_naming_it(tiny_sam, tmp_path):
    with pytest.raises(ModelError, match="nowhere/owlv2-missing") as err:
        load("nowhere/owlv2-missing", ENTITIES, opts(tiny_sam))
    assert "\n" not in str(err.value) and "--model" in str(err.value)


def test_missing_sam_fails_fast_naming_it(tiny_owlv2, tmp_path):
    with pytest.raises(ModelError, match="sam model .*no-sam-here") as err:
        load(str(tiny_owlv2), ENTITIES, opts(tmp_path / "no-sam-here"))
    assert "\n" not in str(err.value)


def test_a_sam_checkpoint_is_not_a_detector(tiny_sam):
    with pytest.raises(ModelError, match="unsupported model type 'sam'"):
        load(str(tiny_sam), ENTITIES, opts(tiny_sam))


def test_default_models(tiny_owlv2):
    from overseec_core.locate.models import DEFAULT_SAM

    with pytest.raises(ModelError, match="google/owlv2-base-patch16-ensemble"):
        load(None, ENTITIES, opts(tiny_owlv2, sam_model=None))  # the default detector is not cached here
    assert boxes_sam.DEFAULT_DETECTOR == "google/owlv2-base-patch16-ensemble" and DEFAULT_SAM


# --- end to end through the tiling engine ----------------------------------------------------


def run_tiled(seg, image: Path, tile: int, overlap: int) -> np.ndarray:
    """What segment_image does with a backend: stream_predict over the tile grid into an array."""
    with RasterSource(image) as src:
        grid = src.grid
        out = np.full((len(ENTITIES), grid.height, grid.width), np.nan, np.float32)

        def sink(rows: np.ndarray, row_off: int) -> None:
            out[:, row_off : row_off + rows.shape[1]] = rows

        stats = stream_predict(src, seg, sink, TileGrid(grid.width, grid.height, tile, overlap), len(ENTITIES))
    assert stats.tiles > 1 or tile >= max(grid.width, grid.height)
    return out


def test_stream_predict_end_to_end(seg, tmp_path):
    image = write_geotiff(tmp_path / "img.tif", width=150, height=120, nodata_box=(0, 40, 0, 50))
    out = run_tiled(seg, image, 64, 8)
    assert np.isnan(out[:, :40, :50]).all()  # no valid tile covers the nodata corner
    body = out[:, 40:, :]
    assert np.isfinite(body).all() and 0 <= body.min() and body.max() <= 1 and body.max() > 0.1
    np.testing.assert_array_equal(out, run_tiled(seg, image, 64, 8))  # deterministic


def test_single_tile_run_equals_the_predictor(seg, tmp_path):
    image = write_geotiff(tmp_path / "small.tif", width=90, height=70, nodata_box=(0, 10, 0, 20))
    out = run_tiled(seg, image, 128, 16)
    with rasterio.open(image) as ds:
        data = ds.read()
    rgb, valid = np.moveaxis(data[:3], 0, -1)[None], (data[3] > 0)[None]
    rgb[~valid] = 0  # as the reader gives chips
    want = seg(rgb, valid)[0]
    np.testing.assert_allclose(out[:, valid[0]], want[:, valid[0]], rtol=0, atol=1e-6)


def test_segment_image_with_the_registry(tiny_owlv2, tiny_sam, tmp_path):
    """segment_image(SegmentOptions(segmenter='boxes+sam', model=..., sam_model=...)): the
    detector and SAM named in the options run end to end; box_threshold and max_boxes reach the
    backend (None: its defaults)."""
    from overseec_core.locate.segment import SegmentOptions, segment_image

    image = write_geotiff(tmp_path / "img.tif", width=120, height=100)
    options = SegmentOptions(
        segmenter="boxes+sam", model=str(tiny_owlv2), sam_model=str(tiny_sam), device="cpu", tile_size=64
    )
    res = segment_image(image, ENTITIES, tmp_path / "out", options)
    with rasterio.open(res.probs_path) as ds:
        probs = ds.read()
    assert probs.shape == (2, 100, 120) and 0 <= np.nanmin(probs) and np.nanmax(probs) <= 1
    assert res.segmenter == "boxes+sam" and res.model.path == str(tiny_owlv2.resolve())
    seg = load(str(tiny_owlv2), ENTITIES, replace(options, box_threshold=0.25, max_boxes=3))
    assert (seg.settings.box_threshold, seg.settings.max_boxes) == (0.25, 3)
    assert load(str(tiny_owlv2), ENTITIES, options).settings == boxes_sam.BoxSettings()  # None: defaults
    with pytest.raises(InputError, match=r"^max boxes per entity 0 must be at least 1$"):
        segment_image(image, ENTITIES, tmp_path / "bad", replace(options, max_boxes=0))


# --- Grounding DINO ----------------------------------------------------------------------------

GD_ENTITIES = (Entity("road", "linear"), Entity("tree", "areal", prompts=("a tree", "water")))


@pytest.fixture(scope="module")
def tiny_gdino(tmp_path_factory) -> Path:
    return builders_detect.save_grounding_dino(tmp_path_factory.mktemp("models") / "tiny-gdino")


def test_grounding_dino_boxes_equal_the_library_forward(tiny_gdino, tiny_sam, rng):
    """config.model_type picks Grounding DINO; its logits and boxes are the library forward's on
    processor(images, text=caption), and an entity's score is the best over its phrases' tokens."""
    from transformers import GroundingDinoForObjectDetection, GroundingDinoProcessor

    seg = load(str(tiny_gdino), GD_ENTITIES, opts(tiny_sam, box_threshold=0.3))
    det = seg.detector
    assert det.family == "grounding-dino" and "Grounding DINO" in seg.describe()
    tile = rng.integers(0, 256, (96, 80, 3), dtype=np.uint8)
    proc = GroundingDinoProcessor.from_pretrained(tiny_gdino)
    model = GroundingDinoForObjectDetection.from_pretrained(tiny_gdino).eval()
    inputs = proc(images=[tile], text="road. a tree. water.", return_tensors="pt")
    with torch.inference_mode():
        out = model(**inputs)
    logits, boxes = det.raw(tile[None])
    np.testing.assert_allclose(logits[0].numpy(), out.logits[0].numpy(), rtol=0, atol=1e-5)
    np.testing.assert_allclose(boxes[0].numpy(), out.pred_boxes[0].numpy(), rtol=0, atol=1e-5)
    # token positions of each entity's phrases, read off the library's own tokenisation
    words = proc.tokenizer.convert_ids_to_tokens(inputs["input_ids"][0].tolist())
    assert words[:9] == ["[CLS]", "road", ".", "a", "tree", ".", "water", ".", "[SEP]"]
    assert [list(t) for t in det.token_owner] == [[1], [3, 4, 6]]
    (res,) = proc.post_process_grounded_object_detection(
        out, inputs["input_ids"], threshold=0.0, text_threshold=0.0, target_sizes=[(96, 80)]
    )
    (ours,) = seg.detect(tile[None])
    probs = torch.sigmoid(out.logits[0])
    for got, tokens in zip(ours, ([1], [3, 4, 6])):
        scores = probs[:, tokens].max(dim=-1).values.numpy()
        want = select_boxes(res["boxes"].numpy(), scores, 0.3, seg.settings, 96, 80)
        np.testing.assert_allclose(got.scores, want.scores, rtol=0, atol=1e-5)
        np.testing.assert_allclose(got.boxes, want.boxes, rtol=0, atol=1e-4)
    assert sum(len(e) for e in ours) > 2
    valid = np.ones((2, 96, 80), bool)
    valid[1, :, :40] = False
    probs_out = seg(np.stack([tile, tile]), valid)
    assert probs_out.shape == (2, 2, 96, 80) and 0 <= probs_out.min() and probs_out.max() <= 1
    assert (probs_out[1][:, :, :40] == 0).all() and probs_out[0].max() > 0.1


def test_grounding_dino_refuses_model_size(tiny_gdino, tiny_sam):
    with pytest.raises(InputError, match="--model-size is not supported with a Grounding DINO"):
        load(str(tiny_gdino), GD_ENTITIES, opts(tiny_sam, model_size=96))
