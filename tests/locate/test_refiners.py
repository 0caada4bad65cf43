"""The refiner choice: SAM, SAM-HQ and SAM 2 through the same refine stage.

Tiny random-weight checkpoints of each family (tests/locate/builders_refiners.py) are decoded by
our path (one encoder pass per tile, each component's tile embeddings gathered, batched decoding
on point, box and mask prompts) and compared with the library's own forward from pixels on the
same prompts; then refine_image runs end to end with each.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import rasterio

torch = pytest.importorskip("torch")
transformers = pytest.importorskip("transformers")

from overseec_core.errors import Cancelled, InputError, ModelError  # noqa: E402
from overseec_core.locate.models import DEFAULT_SAM  # noqa: E402
from overseec_core.locate.prompts import RefineParams  # noqa: E402
from overseec_core.locate.refine import RefineOptions, check_refine_options, refine_image  # noqa: E402
from overseec_core.locate.refiners import DEFAULT_REFINER, REFINERS, get_refiner, refiner_names  # noqa: E402
from overseec_core.locate.sam import SamRefiner, prompt_arrays  # noqa: E402
from overseec_core.locate.sam_model import (  # noqa: E402
    encode_tiles,
    encoder_blocks,
    gather_tiles,
    load_sam,
    pixel_values_config,
    sam_preprocess,
)

from . import builders_refiners  # noqa: E402
from .builders import IMAGENET_MEAN, IMAGENET_STD  # noqa: E402
from .test_refine import ENTITIES, image_and_probs  # noqa: E402
from .test_segment import CancelAfter  # noqa: E402

THRESHOLDS = (0.5, 0.4)
#: The fixture holding each refiner's tiny checkpoint.
CHECKPOINTS = {"sam": "tiny_sam", "sam-hq": "tiny_sam_hq", "sam2": "tiny_sam2"}


@pytest.fixture(scope="session")
def tiny_sam_hq(tmp_path_factory) -> Path:
    return builders_refiners.save_sam_hq(tmp_path_factory.mktemp("models") / "tiny-sam-hq")


@pytest.fixture(scope="session")
def tiny_sam2(tmp_path_factory) -> Path:
    return builders_refiners.save_sam2(tmp_path_factory.mktemp("models") / "tiny-sam2")


@pytest.fixture(params=list(CHECKPOINTS))
def refiner_case(request) -> tuple[str, Path]:
    """(refiner name, its tiny checkpoint), for each refiner."""
    return request.param, request.getfixturevalue(CHECKPOINTS[request.param])


@pytest.fixture
def empty_hub_cache(tmp_path, monkeypatch):
    from huggingface_hub import constants

    cache = tmp_path / "hub"
    cache.mkdir()
    monkeypatch.setattr(constants, "HF_HUB_CACHE", str(cache))
    return cache


def tiles_and_coarse(side: int) -> tuple[np.ndarray, list[np.ndarray]]:
    """Two smooth RGB tiles and their (2, side, side) coarse maps: two buildings and a road in the
    first, one building and the road in the second."""
    yy, xx = np.mgrid[0:side, 0:side]
    rgb = np.stack(
        [
            np.stack([(np.sin(xx / (7 + t)) + 1) * 110, (np.cos(yy / 5.0) + 1) * 100, ((xx + 3 * yy) % 50) * 4.0], -1)
            for t in (0, 3)
        ]
    ).astype(np.uint8)
    coarse = []
    for t in range(2):
        c = np.full((2, side, side), 0.05, np.float32)
        c[0, 10:40, 12:50] = 0.9
        if t == 0:
            c[0, 70:110, 80:100] = 0.85
        c[1, 60 + 10 * t : 68 + 10 * t, :] = 0.7
        coarse.append(c)
    return rgb, coarse


# --------------------------------------------------------------------------------------------
# the table
# --------------------------------------------------------------------------------------------


def test_the_table_names_each_refiner_and_its_default_model() -> None:
    assert refiner_names() == ("sam", "sam-hq", "sam2") and DEFAULT_REFINER == "sam"
    assert get_refiner("sam").default_model == DEFAULT_SAM
    assert get_refiner("SAM-HQ").default_model == "syscv-community/sam-hq-vit-base"
    assert get_refiner("sam2").default_model == "facebook/sam2.1-hiera-tiny"
    for info in REFINERS.values():  # each names a class this transformers has
        assert hasattr(transformers, info.model_class)
    with pytest.raises(InputError, match=r"^unknown refiner 'sam3'; use one of sam, sam-hq, sam2$"):
        get_refiner("sam3")
    assert RefineOptions().model_name == DEFAULT_SAM
    assert RefineOptions(refiner="sam2").model_name == "facebook/sam2.1-hiera-tiny"
    assert RefineOptions(refiner="sam2", sam_model="/m").model_name == "/m"


def test_the_table_imports_without_torch() -> None:
    code = "import sys, overseec_core.locate.refiners; print('torch' in sys.modules, 'numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "False"]


@pytest.mark.parametrize("refiner", ["sam-hq", "sam2"])
def test_a_missing_model_fails_fast_naming_it(refiner, empty_hub_cache, tmp_path) -> None:
    default = get_refiner(refiner).default_model
    with pytest.raises(ModelError, match=f"^{refiner} model {default} is not available offline") as err:
        check_refine_options(RefineOptions(refiner=refiner, device="cpu"))
    assert "\n" not in str(err.value) and "--sam-model" in str(err.value)
    image, probs_path = image_and_probs(tmp_path, 64, 64)
    with pytest.raises(ModelError, match=default):
        refine_image(image, probs_path, ENTITIES, tmp_path / "out", RefineOptions(refiner=refiner, device="cpu"))
    assert not (tmp_path / "out").exists()  # before any output


def test_a_checkpoint_of_another_family_is_refused(tiny_sam, tiny_sam2) -> None:
    with pytest.raises(ModelError, match=r"unsupported model type 'sam' \(expected sam2\)$"):
        check_refine_options(RefineOptions(sam_model=str(tiny_sam), refiner="sam2"))
    with pytest.raises(ModelError, match=r"unsupported model type 'sam2' \(expected sam_hq\)$"):
        load_sam(str(tiny_sam2), "cpu", refiner="sam-hq")


def test_a_dask_worker_loads_the_refiner_the_client_named(refiner_case) -> None:
    """refine_task (what a worker runs) loads the spec's refiner family: the same maps and stats
    as the local refiner on the same tiles; a spec naming another family is refused."""
    from overseec_core.locate.dask import ModelSpec, refine_task

    refiner, path = refiner_case
    params = RefineParams(min_area=16)
    rgb, coarse = tiles_and_coarse(128)
    local = SamRefiner(load_sam(str(path), "cpu", refiner=refiner), params, 2)
    expected = local(rgb, coarse, THRESHOLDS)
    maps, stats = refine_task(
        ModelSpec(str(path), "cpu", batch_size=2, refiner=refiner), params, THRESHOLDS, rgb, coarse
    )
    assert stats.components_refined == local.stats.components_refined > 0
    for got, want in zip(maps, expected):
        np.testing.assert_array_equal(got, want)
    if refiner != DEFAULT_REFINER:  # the spec's family is what loads, not SAM's
        with pytest.raises(ModelError, match="unsupported model type"):
            refine_task(ModelSpec(str(path), "cpu"), params, THRESHOLDS, rgb, coarse)
    check_refine_options(RefineOptions(sam_model=str(path), refiner=refiner, dask_scheduler="tcp://127.0.0.1:1"))


# --------------------------------------------------------------------------------------------
# parity with the library
# --------------------------------------------------------------------------------------------


def library_model(refiner: str, path: Path):
    """The checkpoint as the library loads it: none of our patches (chunked attention, decoder
    token layout), the library's default attention."""
    return getattr(transformers, REFINERS[refiner].model_class).from_pretrained(path).eval()


def test_decoding_equals_the_library_forward(refiner_case) -> None:
    """Our decoding (embeddings once per tile, gathered per component, prompts batched across
    tiles) gives the library's forward from pixels on the same point, box and mask prompts."""
    name, path = refiner_case
    bundle = load_sam(str(path), "cpu", refiner=name)
    assert bundle.refiner == name and bundle.ref.kind == name
    rgb, coarse = tiles_and_coarse(bundle.image_size)
    refiner = SamRefiner(bundle, RefineParams(decoder_batch=16), batch_size=2)
    plans = [refiner.prepare(c, THRESHOLDS) for c in coarse]
    prompts = [p for plan in plans for p in plan.prompts]
    tiles = [t for t, plan in enumerate(plans) for _ in plan.prompts]
    assert len(prompts) == 5 and tiles == [0, 0, 0, 1, 1]
    masks = torch.from_numpy(np.stack([m for plan in plans for m in plan.mask_prompts])[:, None])
    assert masks.shape[-1] == bundle.mask_size and masks.std() > 1  # real mask prompts, not a constant

    embeddings = refiner.embed(rgb)
    assert refiner.stats.encoder_calls == 2 and all(e.shape[0] == 2 for e in embeddings)
    ours = refiner.decode_tiles(embeddings, tiles, prompts, masks)

    library = library_model(name, path)
    pixels = sam_preprocess(rgb, bundle)
    points, labels, boxes = (torch.from_numpy(a) for a in prompt_arrays(prompts))
    with torch.no_grad():
        out = library(
            pixel_values=pixels[tiles],
            input_points=points,
            input_labels=labels,
            input_boxes=boxes,
            input_masks=masks,
            multimask_output=False,
        )
    expected = out.pred_masks[:, 0, 0]
    assert ours.shape == expected.shape == (5, bundle.mask_size, bundle.mask_size)
    assert expected.std() > 1  # mask logits of a few units: a comparison that can fail
    torch.testing.assert_close(ours, expected, atol=1e-5, rtol=0)
    # not trivially equal: the other tile's embeddings give other masks
    other = refiner.decode_tiles(embeddings, [1 - t for t in tiles], prompts, masks)
    assert (other - expected).abs().max() > 1e-2


def test_sam_hq_fuses_the_first_global_blocks_features(tiny_sam_hq) -> None:
    """SAM-HQ's decoder reads the first global block's ViT features: the embeddings we keep are
    those, and the last block's would give other masks."""
    bundle = load_sam(str(tiny_sam_hq), "cpu", refiner="sam-hq")
    rgb, coarse = tiles_and_coarse(bundle.image_size)
    pixels = sam_preprocess(rgb, bundle)
    with torch.no_grad():
        embedding, features = library_model("sam-hq", tiny_sam_hq).get_image_embeddings(pixels)
        ours = encode_tiles(bundle, pixels)
    assert len(features) == 2  # two global blocks in the tiny encoder
    torch.testing.assert_close(ours[0], embedding, atol=1e-5, rtol=0)
    torch.testing.assert_close(ours[1], features[0], atol=1e-5, rtol=0)
    refiner = SamRefiner(bundle, RefineParams())
    plan = refiner.prepare(coarse[0], THRESHOLDS)
    masks = torch.from_numpy(np.stack(plan.mask_prompts)[:, None])
    rows = torch.zeros(len(plan.prompts), dtype=torch.long)
    first = refiner.decode(gather_tiles(ours, rows), plan.prompts, masks)
    last = refiner.decode(gather_tiles((ours[0], features[-1]), rows), plan.prompts, masks)
    assert (first - last).abs().max() > 1e-2


def test_sam2_embeddings_are_the_librarys(tiny_sam2) -> None:
    """SAM 2 hands the decoder three levels (two projected FPN levels and the image embedding)."""
    bundle = load_sam(str(tiny_sam2), "cpu", refiner="sam2")
    rgb, _ = tiles_and_coarse(bundle.image_size)
    pixels = sam_preprocess(rgb, bundle)
    with torch.no_grad():
        expected = library_model("sam2", tiny_sam2).get_image_embeddings(pixels)
        ours = encode_tiles(bundle, pixels)
    side = bundle.image_size // 16
    assert [tuple(e.shape[-2:]) for e in ours] == [(4 * side, 4 * side), (2 * side, 2 * side), (side, side)]
    for a, b in zip(ours, expected, strict=True):
        torch.testing.assert_close(a, b, atol=1e-5, rtol=0)


def test_sam_hq_preprocessing_is_its_processors(tiny_sam_hq) -> None:
    bundle = load_sam(str(tiny_sam_hq), "cpu", refiner="sam-hq")
    rgb, _ = tiles_and_coarse(bundle.image_size)
    processor = transformers.SamHQProcessor.from_pretrained(tiny_sam_hq)
    expected = processor(images=list(rgb), return_tensors="pt")["pixel_values"]
    torch.testing.assert_close(sam_preprocess(rgb, bundle), expected, atol=1e-5, rtol=0)


def test_sam2_preprocessing_values(tiny_sam2, tmp_path) -> None:
    """SAM 2's pixel values: from Sam2Processor where torchvision is installed (its image
    processor needs it), else read from the saved processor config; the same either way."""
    bundle = load_sam(str(tiny_sam2), "cpu", refiner="sam2")
    mean, std, rescale = pixel_values_config(bundle.ref, "sam2")
    assert mean == tuple(IMAGENET_MEAN) and std == tuple(IMAGENET_STD) and rescale == pytest.approx(1 / 255)
    assert (bundle.mean, bundle.std, bundle.rescale) == (mean, std, rescale)
    # values that differ from the defaults are read, not assumed
    other = tmp_path / "other-sam2"
    shutil.copytree(tiny_sam2, other)
    config = json.loads((other / "preprocessor_config.json").read_text(encoding="utf-8"))
    config.update(image_mean=[0.5, 0.5, 0.5], image_std=[0.25, 0.25, 0.25], rescale_factor=0.5 / 255)
    (other / "preprocessor_config.json").write_text(json.dumps(config), encoding="utf-8")
    ref = load_sam(str(other), "cpu", refiner="sam2").ref
    assert pixel_values_config(ref, "sam2") == ((0.5, 0.5, 0.5), (0.25, 0.25, 0.25), 0.5 / 255)


def test_sam2_preprocessing_is_its_processors(tiny_sam2) -> None:
    """Where torchvision is installed, Sam2Processor's pixel values are ours on a full-size tile."""
    pytest.importorskip("torchvision")
    bundle = load_sam(str(tiny_sam2), "cpu", refiner="sam2")
    rgb, _ = tiles_and_coarse(bundle.image_size)
    expected = transformers.Sam2Processor.from_pretrained(tiny_sam2)(images=list(rgb), return_tensors="pt")
    torch.testing.assert_close(sam_preprocess(rgb, bundle), expected["pixel_values"], atol=1e-5, rtol=0)


# --------------------------------------------------------------------------------------------
# refine_image end to end
# --------------------------------------------------------------------------------------------


def read_outputs(result) -> list[np.ndarray]:
    arrays = []
    for path in (result.refined_probs_path, result.refined_masks_path, result.gated_path):
        with rasterio.open(path) as ds:
            arrays.append(ds.read())
    return arrays


def test_refine_image_with_each_refiner(refiner_case, tmp_path) -> None:
    name, path = refiner_case
    image, probs_path = image_and_probs(tmp_path, 300, 200)
    options = RefineOptions(sam_model=str(path), device="cpu", refiner=name)
    first = refine_image(image, probs_path, ENTITIES, tmp_path / "a", options)
    again = refine_image(image, probs_path, ENTITIES, tmp_path / "b", options)
    assert first.tile_size == 128 and first.tiles == 6 and first.stats.tiles_sam >= 3
    assert first.stats.components_refined > 0 and first.stats.encoder_calls == first.stats.tiles_sam
    with rasterio.open(image) as src:
        grid = (src.width, src.height, src.crs, src.transform)
    for out in (first.refined_probs_path, first.refined_masks_path, first.gated_path):
        with rasterio.open(out) as ds:
            assert (ds.width, ds.height, ds.crs, ds.transform) == grid
            assert ds.descriptions == ("building", "road")
    probs, masks, gated = read_outputs(first)
    assert np.isfinite(probs).all() and 0 <= probs.min() and probs.max() <= 1
    assert set(np.unique(masks)) <= {0, 1} and 0 < masks.mean() < 1
    np.testing.assert_allclose(gated, probs * masks, atol=1e-7)
    with rasterio.open(probs_path) as ds:
        coarse = ds.read()
    assert (masks != (coarse >= np.array(THRESHOLDS)[:, None, None])).any()  # the refiner changed masks
    for a, b in zip(read_outputs(first), read_outputs(again), strict=True):
        np.testing.assert_array_equal(a, b)  # deterministic
    doc = first.to_json()
    assert doc["refiner"] == name and doc["model"]["kind"] == name
    assert doc["model"]["model_type"] == REFINERS[name].model_type


@pytest.mark.parametrize("refiner", ["sam-hq", "sam2"])
def test_cancel_stops_inside_each_encoder(refiner, request, tmp_path) -> None:
    """A cancel during a tile stops before the encoder's next block, whichever the family."""
    path = request.getfixturevalue(CHECKPOINTS[refiner])
    image, probs_path = image_and_probs(tmp_path, 300, 200)
    blocks = encoder_blocks(load_sam(str(path), "cpu", refiner=refiner))
    progress = CancelAfter(10**6)
    second: list[int] = []
    hooks = [
        blocks[0].register_forward_hook(lambda *a: progress.token.cancel()),
        blocks[1].register_forward_hook(lambda *a: second.append(1)),
    ]
    out = tmp_path / "out"
    try:
        with pytest.raises(Cancelled):
            options = RefineOptions(sam_model=str(path), device="cpu", refiner=refiner)
            refine_image(image, probs_path, ENTITIES, out, options, progress)
    finally:
        for h in hooks:
            h.remove()
    assert second == [] and list(out.iterdir()) == []
