"""Random-weight CLIPSeg and SAM checkpoints built from configs, saved with save_pretrained.

Nothing is downloaded: the tokenizer is a CLIP byte-level BPE built from a handwritten vocab
(the 256 byte symbols, their end-of-word forms, a few merges and the two special tokens), and the
image processors are saved with the checkpoints' published pre-processing values. Used by the
tests (tiny models) and by bench/bench_segment.py (the published full-size architectures).
"""

from __future__ import annotations

import json
from pathlib import Path

import torch

MERGES = ["r o", "ro a", "roa d</w>", "t r", "tr e", "tre e</w>", "w a", "wa t", "wat e", "wate r</w>"]
IMAGENET_MEAN, IMAGENET_STD = [0.485, 0.456, 0.406], [0.229, 0.224, 0.225]


def _byte_symbols() -> list[str]:
    """GPT-2/CLIP byte-to-unicode table: the 256 symbols byte-level BPE works on."""
    bs = list(range(ord("!"), ord("~") + 1)) + list(range(ord("¡"), ord("¬") + 1)) + list(range(ord("®"), ord("ÿ") + 1))
    cs, n = bs[:], 0
    for b in range(256):
        if b not in bs:
            bs.append(b)
            cs.append(256 + n)
            n += 1
    return [chr(c) for c in cs]


def write_tokenizer(folder: Path) -> int:
    """A CLIP tokenizer from a handmade vocab.json + merges.txt; returns the vocabulary size."""
    from transformers import CLIPTokenizer

    symbols = _byte_symbols()
    vocab: dict[str, int] = {}
    for s in symbols + [s + "</w>" for s in symbols] + [m.replace(" ", "") for m in MERGES]:
        vocab.setdefault(s, len(vocab))
    vocab["<|startoftext|>"] = len(vocab)
    vocab["<|endoftext|>"] = len(vocab)
    (folder / "vocab.json").write_text(json.dumps(vocab), encoding="utf-8")
    (folder / "merges.txt").write_text("#version: 0.2\n" + "\n".join(MERGES) + "\n", encoding="utf-8")
    CLIPTokenizer(vocab=str(folder / "vocab.json"), merges=str(folder / "merges.txt")).save_pretrained(folder)
    return len(vocab)


def tiny_clipseg_config(vocab_size: int, image_size: int = 64):
    from transformers import CLIPSegConfig

    return CLIPSegConfig(
        text_config=dict(
            vocab_size=vocab_size,
            hidden_size=32,
            intermediate_size=48,
            num_hidden_layers=2,
            num_attention_heads=2,
            max_position_embeddings=32,
            eos_token_id=vocab_size - 1,
            bos_token_id=vocab_size - 2,
            pad_token_id=vocab_size - 1,
        ),
        vision_config=dict(
            hidden_size=32,
            intermediate_size=48,
            num_hidden_layers=4,
            num_attention_heads=2,
            image_size=image_size,
            patch_size=16,
        ),
        projection_dim=24,
        extract_layers=[1, 2],
        reduce_dim=16,
        decoder_num_attention_heads=2,
        decoder_intermediate_size=32,
        conditional_layer=0,
        use_complex_transposed_convolution=True,
    )


def full_clipseg_config(vocab_size: int):
    """CIDAS/clipseg-rd64-refined's architecture: CLIP ViT-B/16, reduce dim 64, refined decoder."""
    from transformers import CLIPSegConfig

    return CLIPSegConfig(
        text_config=dict(
            vocab_size=max(vocab_size, 49408),
            hidden_size=512,
            intermediate_size=2048,
            num_hidden_layers=12,
            num_attention_heads=8,
            max_position_embeddings=77,
            eos_token_id=vocab_size - 1,
            bos_token_id=vocab_size - 2,
            pad_token_id=vocab_size - 1,
        ),
        vision_config=dict(
            hidden_size=768,
            intermediate_size=3072,
            num_hidden_layers=12,
            num_attention_heads=12,
            image_size=352,
            patch_size=16,
        ),
        projection_dim=512,
        extract_layers=[3, 6, 9],
        reduce_dim=64,
        decoder_num_attention_heads=4,
        decoder_intermediate_size=2048,
        conditional_layer=0,
        use_complex_transposed_convolution=True,
    )


def save_clipseg(folder: Path, config_fn=tiny_clipseg_config, seed: int = 0) -> Path:
    """Random CLIPSeg with tokenizer and image processor in ``folder``."""
    from transformers import CLIPSegForImageSegmentation, ViTImageProcessor

    folder.mkdir(parents=True, exist_ok=True)
    config = config_fn(write_tokenizer(folder))
    torch.manual_seed(seed)
    model = CLIPSegForImageSegmentation(config).eval()
    with torch.no_grad():  # random init gives logits of a few hundred; scale to a useful range
        last = model.decoder.transposed_convolution[-1]
        last.weight.mul_(0.01)
        last.bias.zero_()
    model.save_pretrained(folder)
    side = 352 if config.vision_config.hidden_size == 768 else config.vision_config.image_size
    ViTImageProcessor(
        size={"height": side, "width": side}, resample=2, image_mean=IMAGENET_MEAN, image_std=IMAGENET_STD
    ).save_pretrained(folder)
    return folder


def tiny_sam_config(image_size: int = 128):
    from transformers import SamConfig

    return SamConfig(
        vision_config=dict(
            hidden_size=32,
            output_channels=32,
            num_hidden_layers=2,
            num_attention_heads=2,
            image_size=image_size,
            patch_size=16,
            window_size=4,
            global_attn_indexes=[1],
            num_pos_feats=16,
            mlp_dim=64,
            initializer_range=0.02,
        ),
        prompt_encoder_config=dict(hidden_size=32, image_size=image_size, patch_size=16, mask_input_channels=8),
        mask_decoder_config=dict(
            hidden_size=32, mlp_dim=64, num_hidden_layers=2, num_attention_heads=2, iou_head_hidden_dim=32
        ),
    )


def full_sam_config():
    """facebook/sam-vit-base: ViT-B image encoder at 1024 px, 256-d prompt encoder and decoder."""
    from transformers import SamConfig

    return SamConfig(
        vision_config=dict(
            hidden_size=768,
            output_channels=256,
            num_hidden_layers=12,
            num_attention_heads=12,
            image_size=1024,
            patch_size=16,
            window_size=14,
            global_attn_indexes=[2, 5, 8, 11],
            num_pos_feats=128,
            mlp_ratio=4.0,
            initializer_range=0.02,
        ),
        prompt_encoder_config=dict(hidden_size=256, image_size=1024, patch_size=16, mask_input_channels=16),
        mask_decoder_config=dict(
            hidden_size=256, mlp_dim=2048, num_hidden_layers=2, num_attention_heads=8, iou_head_hidden_dim=256
        ),
    )


def save_sam(folder: Path, config_fn=tiny_sam_config, seed: int = 1) -> Path:
    """Random SAM with SamProcessor's pre-processing config in ``folder``.

    The vision config's initializer_range is 0.02 (the library's default, 1e-10, gives an encoder
    whose embeddings are ~1e-21: every comparison of them would pass trivially), and the weights
    are re-initialised so that embeddings and mask logits have a useful spread."""
    from transformers import SamModel

    folder.mkdir(parents=True, exist_ok=True)
    torch.manual_seed(seed)
    config = config_fn()
    model = SamModel(config).eval()
    with torch.no_grad():
        # the library's init shrinks activations layer by layer: PyTorch's own init keeps them,
        # and a larger hypernetwork output gives mask logits of a few units, so masks vary
        for module in model.modules():
            if module is not model and hasattr(module, "reset_parameters"):
                module.reset_parameters()
        for mlp in model.mask_decoder.output_hypernetworks_mlps:
            mlp.proj_out.weight.mul_(100.0)
    model.save_pretrained(folder)
    size = config.vision_config.image_size
    (folder / "preprocessor_config.json").write_text(
        json.dumps(
            {
                "image_processor_type": "SamImageProcessor",
                "do_resize": True,
                "size": {"longest_edge": size},
                "resample": 2,
                "do_rescale": True,
                "rescale_factor": 1 / 255,
                "do_normalize": True,
                "image_mean": IMAGENET_MEAN,
                "image_std": IMAGENET_STD,
                "do_pad": True,
                "pad_size": {"height": size, "width": size},
                "mask_size": {"longest_edge": size // 4},
                "mask_pad_size": {"height": size // 4, "width": size // 4},
            }
        ),
        encoding="utf-8",
    )
    return folder
