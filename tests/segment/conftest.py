"""Tiny random-weight CLIPSeg and SAM checkpoints, built from configs and saved into tmp dirs.

Nothing is downloaded: the tokenizer is a CLIP byte-level BPE built from a handwritten vocab
(the 256 byte symbols, their end-of-word forms, a few merges and the two special tokens), and the
image processors are saved with the checkpoints' published pre-processing values.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

torch = pytest.importorskip("torch")
transformers = pytest.importorskip("transformers")

import rasterio  # noqa: E402
from rasterio.transform import from_origin  # noqa: E402

MERGES = ["r o", "ro a", "roa d</w>", "t r", "tr e", "tre e</w>", "w a", "wa t", "wat e", "wate r</w>"]


def _byte_symbols() -> list[str]:
    """GPT-2/CLIP byte-to-unicode table: the 256 symbols byte-level BPE works on."""
    bs = list(range(ord("!"), ord("~") + 1)) + list(range(ord("¡"), ord("¬") + 1)) \
        + list(range(ord("®"), ord("ÿ") + 1))
    cs, n = bs[:], 0
    for b in range(256):
        if b not in bs:
            bs.append(b)
            cs.append(256 + n)
            n += 1
    return [chr(c) for c in cs]


def write_tokenizer(folder: Path):
    from transformers import CLIPTokenizer

    symbols = _byte_symbols()
    vocab: dict[str, int] = {}
    for s in symbols + [s + "</w>" for s in symbols] + [m.replace(" ", "") for m in MERGES]:
        vocab.setdefault(s, len(vocab))
    vocab["<|startoftext|>"] = len(vocab)
    vocab["<|endoftext|>"] = len(vocab)
    (folder / "vocab.json").write_text(json.dumps(vocab), encoding="utf-8")
    (folder / "merges.txt").write_text("#version: 0.2\n" + "\n".join(MERGES) + "\n", encoding="utf-8")
    tok = CLIPTokenizer(vocab=str(folder / "vocab.json"), merges=str(folder / "merges.txt"))
    tok.save_pretrained(folder)
    return tok, len(vocab)


def build_tiny_clipseg(folder: Path, image_size: int = 64) -> Path:
    from transformers import CLIPSegConfig, CLIPSegForImageSegmentation, ViTImageProcessor

    folder.mkdir(parents=True, exist_ok=True)
    _, vocab_size = write_tokenizer(folder)
    torch.manual_seed(0)
    config = CLIPSegConfig(
        text_config=dict(vocab_size=vocab_size, hidden_size=32, intermediate_size=48,
                         num_hidden_layers=2, num_attention_heads=2, max_position_embeddings=32,
                         eos_token_id=vocab_size - 1, bos_token_id=vocab_size - 2, pad_token_id=vocab_size - 1),
        vision_config=dict(hidden_size=32, intermediate_size=48, num_hidden_layers=4,
                           num_attention_heads=2, image_size=image_size, patch_size=16),
        projection_dim=24, extract_layers=[1, 2], reduce_dim=16, decoder_num_attention_heads=2,
        decoder_intermediate_size=32, conditional_layer=0, use_complex_transposed_convolution=True)
    model = CLIPSegForImageSegmentation(config).eval()
    with torch.no_grad():  # random init gives logits of a few hundred; scale to a useful range
        last = model.decoder.transposed_convolution[-1]
        last.weight.mul_(0.01)
        last.bias.zero_()
    model.save_pretrained(folder)
    ViTImageProcessor(size={"height": image_size, "width": image_size}, resample=2,
                      image_mean=[0.485, 0.456, 0.406], image_std=[0.229, 0.224, 0.225]
                      ).save_pretrained(folder)
    return folder


def build_tiny_sam(folder: Path, image_size: int = 128) -> Path:
    from transformers import SamConfig, SamModel

    folder.mkdir(parents=True, exist_ok=True)
    torch.manual_seed(1)
    config = SamConfig(
        vision_config=dict(hidden_size=32, output_channels=32, num_hidden_layers=2, num_attention_heads=2,
                           image_size=image_size, patch_size=16, window_size=4, global_attn_indexes=[1],
                           num_pos_feats=16, mlp_dim=64),
        prompt_encoder_config=dict(hidden_size=32, image_size=image_size, patch_size=16,
                                   mask_input_channels=8),
        mask_decoder_config=dict(hidden_size=32, mlp_dim=64, num_hidden_layers=2, num_attention_heads=2,
                                 iou_head_hidden_dim=32))
    model = SamModel(config).eval()
    model.save_pretrained(folder)
    (folder / "preprocessor_config.json").write_text(json.dumps({
        "image_processor_type": "SamImageProcessor", "do_resize": True,
        "size": {"longest_edge": image_size}, "resample": 2, "do_rescale": True,
        "rescale_factor": 1 / 255, "do_normalize": True, "image_mean": [0.485, 0.456, 0.406],
        "image_std": [0.229, 0.224, 0.225], "do_pad": True,
        "pad_size": {"height": image_size, "width": image_size},
        "mask_size": {"longest_edge": image_size // 4},
        "mask_pad_size": {"height": image_size // 4, "width": image_size // 4}}), encoding="utf-8")
    return folder


@pytest.fixture(scope="session")
def tiny_clipseg(tmp_path_factory) -> Path:
    return build_tiny_clipseg(tmp_path_factory.mktemp("models") / "tiny-clipseg")


@pytest.fixture(scope="session")
def tiny_sam(tmp_path_factory) -> Path:
    return build_tiny_sam(tmp_path_factory.mktemp("models") / "tiny-sam")


def write_geotiff(path: Path, width: int = 200, height: int = 150, seed: int = 0, crs: str = "EPSG:32633",
                  nodata_box: tuple[int, int, int, int] | None = None) -> Path:
    """An RGB uint8 GeoTIFF with smooth structure; ``nodata_box`` (row0, row1, col0, col1) -> alpha 0."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:height, 0:width]
    base = np.stack([(np.sin(xx / 9.0) + 1) * 100, (np.cos(yy / 7.0) + 1) * 100,
                     ((xx + yy) % 64) * 3.0])
    rgb = np.clip(base + rng.normal(0, 8, base.shape), 0, 255).astype(np.uint8)
    alpha = np.full((height, width), 255, np.uint8)
    if nodata_box is not None:
        r0, r1, c0, c1 = nodata_box
        alpha[r0:r1, c0:c1] = 0
    profile = dict(driver="GTiff", width=width, height=height, count=4, dtype="uint8", crs=crs,
                   transform=from_origin(500000.0, 4000000.0, 0.5, 0.5), photometric="RGB")
    with rasterio.open(path, "w", **profile) as ds:
        ds.write(np.concatenate([rgb, alpha[None]]))
        ds.colorinterp = [rasterio.enums.ColorInterp.red, rasterio.enums.ColorInterp.green,
                          rasterio.enums.ColorInterp.blue, rasterio.enums.ColorInterp.alpha]
    return path


@pytest.fixture(autouse=True, scope="package")
def one_torch_thread():
    """Tiny models run fastest on one thread, and the 2 shared cores stay free for others."""
    before = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(before)
