"""SAM refinement: component prompts, native tiles, shared embedding, skipping, outputs."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import rasterio

torch = pytest.importorskip("torch")

from overseec_core.errors import Cancelled, InputError, RasterError  # noqa: E402
from overseec_core.io.grid import Grid  # noqa: E402
from overseec_core.io.write import write_array  # noqa: E402
from overseec_core.locate.prompts import (  # noqa: E402
    MASK_PROMPT_LIMIT,
    RefineParams,
    calibrate,
    coarse_mask_logits,
    find_components,
    make_prompt,
    needs_sam,
    negative_points,
    positive_points,
)
from overseec_core.locate.refine import RefineOptions, refine_image  # noqa: E402
from overseec_core.locate.sam import SamRefiner  # noqa: E402
from overseec_core.locate.sam_model import load_sam, sam_preprocess  # noqa: E402
from overseec_core.schema import Entity  # noqa: E402

from .conftest import write_geotiff  # noqa: E402
from .test_segment import CancelAfter  # noqa: E402

ENTITIES = (Entity("building", "areal", threshold=0.5), Entity("road", "linear"))


@pytest.fixture
def sam(tiny_sam):
    return load_sam(str(tiny_sam), "cpu")


def squares_mask(h: int = 128, w: int = 128) -> np.ndarray:
    mask = np.zeros((h, w), bool)
    mask[10:40, 12:50] = True  # 1140 px
    mask[70:110, 80:100] = True  # 800 px
    mask[5:8, 100:103] = True  # 9 px: too small for SAM
    return mask


# --------------------------------------------------------------------------------------------
# prompts (pure numpy)
# --------------------------------------------------------------------------------------------


def test_components_largest_first_small_ones_left_coarse() -> None:
    labels, comps, left = find_components(squares_mask(), min_area=64, max_components=8)
    assert [c.area for c in comps] == [1140, 800] and left == 1
    assert (comps[0].rows, comps[0].cols) == (slice(10, 40), slice(12, 50))
    assert (labels == comps[1].label).sum() == 800
    assert len(find_components(squares_mask(), 64, 1)[1]) == 1
    diagonal = np.eye(20, dtype=bool)  # 8-connected: one component
    assert len(find_components(diagonal, 1, 8)[1]) == 1


def test_positive_points_at_distance_maxima_spread_along_the_shape() -> None:
    bar = np.zeros((30, 120), bool)
    bar[10:21, 5:115] = True  # a thick road
    points = positive_points(bar, 3)
    assert len(points) == 3
    assert all(bar[r, c] for r, c in points)
    assert points[0][0] == 15  # the first is on the centre line, as deep as it gets
    cols = sorted(c for _, c in points)
    assert min(np.diff(cols)) >= 20  # spread along the bar, not clustered
    assert positive_points(np.zeros((5, 5), bool), 3) == []


def test_negative_points_are_confident_background_near_the_component() -> None:
    fg = np.zeros((60, 60), bool)
    fg[20:40, 20:40] = True
    score = np.full((60, 60), 0.5, np.float32)
    score[50:55, 5:10] = 0.01  # the most confident background
    score[0:3, 0:3] = np.nan  # nodata is never a prompt
    points = negative_points(fg, score, 2)
    assert len(points) == 2
    assert 50 <= points[0][0] < 55 and 5 <= points[0][1] < 10
    for r, c in points:
        assert not fg[r, c] and np.isfinite(score[r, c])
        assert min(abs(r - 30), abs(c - 30)) > 10  # outside the band around the component
    assert negative_points(np.ones((10, 10), bool), np.zeros((10, 10)), 2) == []


def test_prompt_for_a_component() -> None:
    mask = squares_mask()
    labels, comps, _ = find_components(mask, 64, 8)
    probs = np.where(mask, 0.9, 0.1).astype(np.float32)
    prompt = make_prompt(0, comps[1], labels == comps[1].label, probs, RefineParams())
    x0, y0, x1, y1 = prompt.box
    assert x0 <= 80 and y0 <= 70 and x1 >= 99 and y1 >= 109  # the box holds the component
    assert x1 - x0 < 40 and y1 - y0 < 60  # ... tightly (small margin), not the tile
    pos = prompt.points[prompt.labels == 1].astype(int)
    neg = prompt.points[prompt.labels == 0].astype(int)
    assert len(pos) >= 1 and all(mask[y, x] for x, y in pos)
    assert len(neg) >= 1 and not any(mask[y, x] for x, y in neg)
    rr, cc = prompt.region
    assert rr.start <= 70 and rr.stop >= 110 and cc.start <= 80 and cc.stop >= 100


def test_coarse_logits_are_relative_to_the_threshold() -> None:
    probs = np.array([0.8, 0.5, 0.2, np.nan, 1.0], np.float32)
    logits = coarse_mask_logits(probs, 0.5)
    assert logits[1] == pytest.approx(0.0, abs=1e-5)
    assert logits[0] > 0 > logits[2]
    assert logits[3] == -MASK_PROMPT_LIMIT and logits[4] == MASK_PROMPT_LIMIT
    assert coarse_mask_logits(np.array([0.8], np.float32), 0.8)[0] == pytest.approx(0.0, abs=1e-5)


def test_calibration_puts_each_threshold_at_one_half() -> None:
    coarse = np.array([[[0.0, 0.4, 0.8, 0.9, 1.0, np.nan]]] * 2, np.float32)
    out = calibrate(coarse, (0.8, 0.4))
    np.testing.assert_allclose(out[0, 0, :5], [0.0, 0.25, 0.5, 0.75, 1.0], atol=1e-6)
    np.testing.assert_allclose(out[1, 0, :5], [0.0, 0.5, 0.5 + 0.5 * 0.4 / 0.6, 0.5 + 0.5 * 0.5 / 0.6, 1.0], atol=1e-6)
    assert np.isnan(out[:, 0, 5]).all()
    with np.errstate(invalid="ignore"):
        np.testing.assert_array_equal(out >= 0.5, coarse >= np.array([0.8, 0.4])[:, None, None])


def test_points_on_large_components_are_searched_subsampled() -> None:
    big = np.zeros((1024, 1024), bool)
    big[480:560, 20:1000] = True  # a wide road across a SAM tile
    points = positive_points(big, 3)
    assert len(points) == 3 and all(big[r, c] for r, c in points)
    assert all(abs(r - 520) <= 4 for r, _ in points)  # on the centre line
    assert min(np.diff(sorted(c for _, c in points))) > 200  # spread along it
    score = np.full(big.shape, 0.5, np.float32)
    score[700:710, 500:510] = 0.0
    neg = negative_points(big, score, 1)
    assert len(neg) == 1 and 700 <= neg[0][0] < 710 and 500 <= neg[0][1] < 510


def test_needs_sam() -> None:
    coarse = np.zeros((2, 64, 64), np.float32)
    assert not needs_sam(coarse, (0.5, 0.4), RefineParams())
    coarse[1, 10:15, 10:15] = 0.9  # 25 px, below min_area
    assert not needs_sam(coarse, (0.5, 0.4), RefineParams())
    coarse[1, 30:50, 30:50] = 0.9
    assert needs_sam(coarse, (0.5, 0.4), RefineParams())
    with pytest.raises(InputError, match="iterations"):
        RefineParams(iterations=0).check()
    with pytest.raises(InputError, match="stop IoU"):
        RefineParams(stop_iou=1.5).check()


# --------------------------------------------------------------------------------------------
# SAM on tiles
# --------------------------------------------------------------------------------------------


def test_sam_preprocessing_matches_the_processor_and_pads_small_tiles(sam, rng) -> None:
    from transformers import SamImageProcessor

    s = sam.image_size
    full = rng.integers(0, 256, (1, s, s, 3), dtype=np.uint8)
    ref = SamImageProcessor.from_pretrained(sam.ref.path)(images=list(full), return_tensors="pt")
    torch.testing.assert_close(sam_preprocess(full, sam), ref["pixel_values"], atol=1e-5, rtol=0)
    small = full[:, :50, :70]
    x = sam_preprocess(small, sam)
    assert x.shape == (1, 3, s, s)  # padded to the input size, never upscaled
    torch.testing.assert_close(x[:, :, :50, :70], ref["pixel_values"][:, :, :50, :70], atol=1e-5, rtol=0)
    assert (x[:, :, 50:] == 0).all() and (x[:, :, :, 70:] == 0).all()


def test_one_embedding_per_tile_shared_by_entities_and_components(sam) -> None:
    s = sam.image_size
    coarse = np.full((2, s, s), 0.05, np.float32)
    coarse[0][squares_mask(s, s)] = 0.9  # two components (+ a tiny one) for entity 0
    coarse[1, 50:60, 0:128] = 0.7  # one road for entity 1
    encoder, decoder_batches = [], []
    h1 = sam.model.vision_encoder.register_forward_hook(lambda m, a, o: encoder.append(a[0].shape[0]))
    h2 = sam.model.mask_decoder.register_forward_hook(
        lambda m, a, kw, o: decoder_batches.append(kw["image_embeddings"].shape[0]), with_kwargs=True
    )
    try:
        refiner = SamRefiner(sam, RefineParams(iterations=2, stop_iou=1.0, decoder_batch=8), batch_size=2)
        rgb = np.random.default_rng(3).integers(0, 256, (2, s, s, 3), dtype=np.uint8)
        outs = refiner(rgb, [coarse, coarse], (0.5, 0.4))
    finally:
        h1.remove()
        h2.remove()
    assert encoder == [2]  # one encoder call for the batch of two tiles, once per tile
    assert refiner.stats.encoder_calls == 2
    # per tile 3 components (2 buildings separately + 1 road); the 6 of both tiles are decoded
    # together, each call gathering every component's own tile embedding; 2 passes
    assert decoder_batches == [6, 6]
    assert refiner.stats.components_refined == 6 and refiner.stats.components_coarse == 2
    out = outs[0]
    assert out.shape == (2, s, s) and out.dtype == np.float32
    # a pass that leaves a mask as it was ends that component's iterations
    decoder_batches.clear()
    h2 = sam.model.mask_decoder.register_forward_hook(
        lambda m, a, kw, o: decoder_batches.append(kw["image_embeddings"].shape[0]), with_kwargs=True
    )
    try:
        SamRefiner(sam, RefineParams(iterations=3, stop_iou=0.0))(rgb[:1], [coarse], (0.5, 0.4))
    finally:
        h2.remove()
    assert decoder_batches == [3]
    # far from every component the (recalibrated) coarse values stay: SAM is trusted only near
    # what it refined; the tiny component keeps its coarse mask
    calibrated = calibrate(coarse, (0.5, 0.4))
    np.testing.assert_array_equal(out[0, 118:, :60], calibrated[0, 118:, :60])
    assert (out[0, 118:, :60] < 0.5).all()
    np.testing.assert_array_equal(out[0, 5:8, 100:103], calibrated[0, 5:8, 100:103])
    assert (out[0, 5:8, 100:103] >= 0.5).all()
    assert not np.array_equal(out[0, 10:40, 12:50], calibrated[0, 10:40, 12:50])  # refined


def image_and_probs(
    tmp_path: Path, width: int, height: int, components: bool = True, nodata_box=None
) -> tuple[Path, Path]:
    """An image and a hand-made probs.tif on its grid (coarse masks where we want them)."""
    image = write_geotiff(tmp_path / "img.tif", width, height, nodata_box=nodata_box)
    with rasterio.open(image) as ds:
        grid = Grid(ds.crs, ds.transform, ds.width, ds.height)
    probs = np.full((2, height, width), 0.1, np.float32)
    if components:
        probs[0, 20:60, 30:70] = 0.9
        probs[1, 100:110, :] = 0.6
    if nodata_box is not None:
        r0, r1, c0, c1 = nodata_box
        probs[:, r0:r1, c0:c1] = np.nan
    out = tmp_path / "seg"
    out.mkdir(exist_ok=True)
    path = write_array(out / "probs.tif", probs, grid, nodata=float("nan"), descriptions=[e.name for e in ENTITIES])
    return image, path


def test_refine_image_outputs(tiny_sam, tmp_path) -> None:
    image, probs_path = image_and_probs(tmp_path, 300, 200)
    result = refine_image(
        image, probs_path, ENTITIES, tmp_path / "seg", RefineOptions(sam_model=str(tiny_sam), device="cpu")
    )
    assert result.tile_size == 128 and result.overlap == 8  # 1/16 of the SAM input
    assert result.tiles == 6 and result.stats.tiles_sam + result.stats.tiles_no_mask == 6
    assert result.stats.tiles_sam >= 3 and result.stats.encoder_calls == result.stats.tiles_sam
    with rasterio.open(image) as src:
        ref = (src.width, src.height, src.crs, src.transform)
    arrays = {}
    for path in (result.refined_probs_path, result.refined_masks_path, result.gated_path):
        with rasterio.open(path) as ds:
            assert (ds.width, ds.height, ds.crs, ds.transform) == ref
            assert ds.descriptions == ("building", "road")
            arrays[path.name] = ds.read()
    p, m, g = arrays["refined_probs.tif"], arrays["refined_masks.tif"], arrays["gated.tif"]
    assert set(np.unique(m)) <= {0, 1}
    np.testing.assert_allclose(g, p * m, atol=1e-7)
    assert np.isfinite(p).all() and 0 <= p.min() and p.max() <= 1
    assert 0.0 < m.mean() < 1.0 and p.std() > 0.05  # SAM answered, not a constant
    with rasterio.open(probs_path) as ds:
        coarse = ds.read()
    assert (m != (coarse >= np.array([0.5, 0.4])[:, None, None])).any()  # and changed the coarse masks


def test_tiles_without_masks_skip_sam(tiny_sam, tmp_path) -> None:
    image, probs_path = image_and_probs(tmp_path, 300, 200, components=False)
    sam = load_sam(str(tiny_sam), "cpu")
    calls = []
    hook = sam.model.vision_encoder.register_forward_hook(lambda *a: calls.append(1))
    try:
        result = refine_image(
            image, probs_path, ENTITIES, tmp_path / "seg", RefineOptions(sam_model=str(tiny_sam), device="cpu")
        )
    finally:
        hook.remove()
    assert calls == [] and result.stats.tiles_sam == 0 and result.stats.tiles_no_mask == 6
    with rasterio.open(result.refined_probs_path) as ds, rasterio.open(probs_path) as coarse:
        np.testing.assert_allclose(ds.read(), calibrate(coarse.read(), (0.5, 0.4)), atol=1e-6)


def test_nodata_is_kept_and_empty_tiles_skipped(tiny_sam, tmp_path) -> None:
    image, probs_path = image_and_probs(tmp_path, 300, 200, nodata_box=(0, 200, 0, 150))
    result = refine_image(
        image, probs_path, ENTITIES, tmp_path / "seg", RefineOptions(sam_model=str(tiny_sam), device="cpu", overlap=0)
    )
    assert result.tiles_nodata == 2  # SAM tiles at columns 0 hold no data
    with rasterio.open(result.refined_masks_path) as ds:
        masks = ds.read()
    with rasterio.open(result.gated_path) as ds:
        gated = ds.read()
    assert (masks[:, :, :150] == 255).all() and np.isnan(gated[:, :, :150]).all()
    assert (masks[:, :, 150:] <= 1).all() and np.isfinite(gated[:, :, 150:]).all()


def test_probs_must_match_the_image(tiny_sam, tmp_path) -> None:
    image, probs_path = image_and_probs(tmp_path, 300, 200)
    other = write_geotiff(tmp_path / "other.tif", 310, 200)
    opts = RefineOptions(sam_model=str(tiny_sam), device="cpu")
    with pytest.raises(RasterError, match="not on the image's grid"):
        refine_image(other, probs_path, ENTITIES, tmp_path / "o1", opts)
    with pytest.raises(RasterError, match="2 bands for 1 entities"):
        refine_image(image, probs_path, ENTITIES[:1], tmp_path / "o2", opts)
    with pytest.raises(RasterError, match="holds entities building, road"):
        refine_image(image, probs_path, (Entity("tree"), Entity("water")), tmp_path / "o3", opts)


def test_cancel_stops_inside_the_sam_encoder(tiny_sam, tmp_path) -> None:
    """A cancel during a SAM tile stops before the next encoder layer (a CPU tile is ~15 s)."""
    image, probs_path = image_and_probs(tmp_path, 300, 200)
    sam = load_sam(str(tiny_sam), "cpu")
    progress = CancelAfter(10**6)
    second = []
    hooks = [
        sam.model.vision_encoder.layers[0].register_forward_hook(lambda *a: progress.token.cancel()),
        sam.model.vision_encoder.layers[1].register_forward_hook(lambda *a: second.append(1)),
    ]
    out = tmp_path / "out"
    try:
        with pytest.raises(Cancelled):
            refine_image(
                image, probs_path, ENTITIES, out, RefineOptions(sam_model=str(tiny_sam), device="cpu"), progress
            )
    finally:
        for h in hooks:
            h.remove()
    assert second == []  # the first tile's encoder stopped after its first layer
    assert list(out.iterdir()) == []  # nothing under the final names, no partial files


def test_params_reach_the_manifest_dict(tiny_sam, tmp_path) -> None:
    image, probs_path = image_and_probs(tmp_path, 130, 130)
    params = replace(RefineParams(), iterations=1, min_area=32)
    result = refine_image(
        image,
        probs_path,
        ENTITIES,
        tmp_path / "seg",
        RefineOptions(sam_model=str(tiny_sam), device="cpu", params=params),
    )
    doc = result.to_json()
    assert doc["params"]["iterations"] == 1 and doc["params"]["min_area"] == 32
    assert doc["model"]["model_type"] == "sam" and doc["tiles_sam"] >= 1


def test_chunked_global_attention_equals_the_library(tiny_sam, rng, monkeypatch) -> None:
    """The memory-bounded global attention gives the library's image embeddings."""
    from transformers import SamModel

    from overseec_core.locate import sam_model as refine

    monkeypatch.setattr(refine, "GLOBAL_ATTENTION_CHUNK", 16)  # 2 of the 8 token rows per chunk
    library = SamModel.from_pretrained(tiny_sam).eval()
    chunked = SamModel.from_pretrained(tiny_sam).eval()
    assert refine.chunk_global_attention(chunked) == 1  # the tiny SAM has one global layer
    with torch.no_grad():  # non-zero relative positions, so the bias matters
        for a, b in zip(library.vision_encoder.layers, chunked.vision_encoder.layers):
            for name in ("rel_pos_h", "rel_pos_w"):
                values = torch.from_numpy(rng.normal(0, 0.5, getattr(a.attn, name).shape)).float()
                getattr(a.attn, name).copy_(values)
                getattr(b.attn, name).copy_(values)
        pixels = torch.randn(2, 3, 128, 128)
        expected = library.get_image_embeddings(pixels)
        assert expected.abs().max() > 0.1  # a real encoder, not near-zero random init
        torch.testing.assert_close(chunked.get_image_embeddings(pixels), expected, atol=1e-5, rtol=0)
        library.vision_encoder.layers[1].attn.rel_pos_h.mul_(3)  # the global layer's bias
        assert (library.get_image_embeddings(pixels) - expected).abs().max() > 1e-3


def test_contiguous_decoder_tokens_change_layout_not_results(tiny_sam) -> None:
    from transformers import SamModel

    from overseec_core.locate.sam_model import contiguous_decoder_tokens

    model = SamModel.from_pretrained(tiny_sam).eval()
    n = 3
    torch.manual_seed(0)
    inputs = dict(
        image_embeddings=torch.randn(1, 32, 8, 8).expand(n, -1, -1, -1),
        input_points=torch.rand(n, 1, 4, 2) * 120,
        input_labels=torch.tensor([[[1, 1, 0, -10]]] * n),
        input_boxes=torch.tensor([[[10.0, 20.0, 90.0, 100.0]]] * n),
        input_masks=torch.randn(n, 1, 32, 32),
        multimask_output=False,
    )
    seen = []
    probe = model.mask_decoder.transformer.register_forward_pre_hook(
        lambda m, a, kw: seen.append(kw["image_embeddings"].is_contiguous(memory_format=torch.channels_last)),
        with_kwargs=True,
    )
    with torch.no_grad():
        plain = model(**inputs).pred_masks
        handle = contiguous_decoder_tokens(model)
        fast = model(**inputs).pred_masks
    handle.remove()
    probe.remove()
    assert plain.abs().max() > 1e-3
    torch.testing.assert_close(fast, plain, atol=1e-6, rtol=0)
    assert seen == [False, False]  # the probe ran before the layout hook registered after it


# --------------------------------------------------------------------------------------------
# crop-local work equals the whole-tile computation it replaces
# --------------------------------------------------------------------------------------------


def test_cell_pool_and_region_upsampling_equal_torch_on_the_whole_tile(rng) -> None:
    from overseec_core.locate.prompts import cell_pool, upsample_region

    F = torch.nn.functional  # noqa: N806 (PyTorch's own convention)
    x = rng.normal(0, 3, (2, 64, 64)).astype(np.float32)
    np.testing.assert_allclose(
        cell_pool(x, 4), F.adaptive_avg_pool2d(torch.from_numpy(x), (16, 16)).numpy(), rtol=0, atol=1e-5
    )
    low = rng.normal(0, 5, (32, 32)).astype(np.float32)
    full = F.interpolate(torch.from_numpy(low)[None, None], size=(128, 128), mode="bilinear", align_corners=False)
    for region in [(slice(0, 128), slice(0, 128)), (slice(5, 37), slice(90, 127)), (slice(127, 128), slice(0, 1))]:
        np.testing.assert_allclose(upsample_region(low, 128, region), full[0, 0][region].numpy(), rtol=0, atol=1e-5)


def test_prompts_from_crops_equal_prompts_from_the_whole_tile() -> None:
    from overseec_core.locate.prompts import context_region

    mask = squares_mask()
    labels, comps, _ = find_components(mask, 64, 8)
    probs = np.where(mask, 0.9, 0.1).astype(np.float32)
    for comp in comps:
        whole = make_prompt(0, comp, labels == comp.label, probs, RefineParams())
        rr, cc = context_region(comp, mask.shape, RefineParams())
        crop = make_prompt(
            0, comp, labels[rr, cc] == comp.label, probs[rr, cc], RefineParams(), (rr.start, cc.start), mask.shape
        )
        np.testing.assert_array_equal(crop.points, whole.points)
        np.testing.assert_array_equal(crop.labels, whole.labels)
        assert (crop.box, crop.region) == (whole.box, whole.region)


@pytest.mark.parametrize("side", [None, 100])  # a whole SAM tile, and a smaller (padded) one
def test_mask_prompts_from_component_boxes_equal_the_whole_tile_pooling(sam, side) -> None:
    """Each component's mask prompt (coarse logits, the entity's other components forced to
    background, pooled to SAM's grid) is computed from its box; the old whole-tile way agrees."""
    s, m = sam.image_size, sam.mask_size
    h = w = side or s
    coarse = np.full((2, h, w), 0.05, np.float32)
    coarse[0][squares_mask(h, w)] = 0.9
    coarse[1, 50:60, 0:w] = 0.7
    thresholds = (0.5, 0.4)
    refiner = SamRefiner(sam, RefineParams(min_area=64))
    plan = refiner.prepare(coarse, thresholds)
    assert len(plan.prompts) == 3
    for prompt, region_mask, got in zip(plan.prompts, plan.masks, plan.mask_prompts):
        e = prompt.entity
        with np.errstate(invalid="ignore"):
            labels, _, _ = find_components(coarse[e] >= thresholds[e], 64, 8)
        fg = labels == prompt.component.label
        logits = np.where(
            (labels > 0) & ~fg, np.float32(-MASK_PROMPT_LIMIT), coarse_mask_logits(coarse[e], thresholds[e])
        )
        canvas = torch.full((1, 1, s, s), -MASK_PROMPT_LIMIT)
        canvas[0, 0, :h, :w] = torch.from_numpy(logits)
        expected = torch.nn.functional.adaptive_avg_pool2d(canvas, (m, m))[0, 0].numpy()
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-4)
        np.testing.assert_array_equal(region_mask, fg[prompt.region])  # the component, on its region
        assert fg[prompt.region].sum() == fg.sum()  # ... which holds all of it


def test_refined_outputs_equal_those_of_the_code_before_the_locate_package(tiny_sam, tmp_path) -> None:
    """Regression: refined masks and probabilities of a fixed scene equal what the refiner gave
    before its per-component work became crop-local and batched across tiles (commit 289d1fc,
    ``refine_image`` with the same tiny seeded SAM; masks bit-packed, probabilities every 5th px)."""
    golden = np.load(Path(__file__).parent / "data" / "refine_before_locate.npz")
    image, probs_path = image_and_probs(tmp_path, 300, 200)
    res = refine_image(
        image, probs_path, ENTITIES, tmp_path / "out", RefineOptions(sam_model=str(tiny_sam), device="cpu")
    )
    with rasterio.open(res.refined_masks_path) as ds:
        masks = ds.read() == 1
    with rasterio.open(res.refined_probs_path) as ds:
        probs = ds.read()
    expected = np.unpackbits(golden["masks"])[: masks.size].reshape(tuple(golden["shape"])).astype(bool)
    assert np.count_nonzero(masks != expected) <= masks.size // 10000  # float rounding at the threshold only
    np.testing.assert_allclose(probs[:, ::5, ::5], golden["probs_sample"], rtol=0, atol=1e-4)
