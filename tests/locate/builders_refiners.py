"""Random-weight SAM-HQ and SAM 2 checkpoints built from configs, saved with save_pretrained.

The refiner tests' counterparts of :func:`tests.locate.builders.save_sam`: tiny architectures of
the published families (a ViT with windowed and global attention plus the HQ token and its
intermediate-feature fusion for SAM-HQ; a four-stage Hiera with an FPN neck and the decoder's
high-resolution skips for SAM 2), at 128 px so a tile runs in milliseconds on one CPU thread. Each
is saved with its own processor (``SamHQProcessor`` / ``Sam2Processor``) carrying the published
pre-processing values. Nothing is downloaded.
"""

from __future__ import annotations

import json
from pathlib import Path

import torch

from .builders import IMAGENET_MEAN, IMAGENET_STD


def tiny_sam_hq_config(image_size: int = 128):
    """SAM-HQ with a tiny SAM encoder (one windowed block, then two global ones: the HQ decoder
    must fuse the first global block's features, and a test can tell it from the last) and the HQ
    decoder on top."""
    from transformers import SamHQConfig

    return SamHQConfig(
        vision_config=dict(
            hidden_size=32,
            output_channels=32,
            num_hidden_layers=3,
            num_attention_heads=2,
            image_size=image_size,
            patch_size=16,
            window_size=4,
            global_attn_indexes=[1, 2],
            num_pos_feats=16,
            mlp_dim=64,
            initializer_range=0.02,
        ),
        prompt_encoder_config=dict(hidden_size=32, image_size=image_size, patch_size=16, mask_input_channels=8),
        mask_decoder_config=dict(
            hidden_size=32, mlp_dim=64, num_hidden_layers=2, num_attention_heads=2, iou_head_hidden_dim=32, vit_dim=32
        ),
    )


def tiny_sam2_config(image_size: int = 128):
    """SAM 2 with a four-stage Hiera (strides 4, 8, 16, 32) whose three finest FPN levels feed the
    decoder, as in sam2.1-hiera-tiny: the image embedding is image_size / 16 per side."""
    from transformers import Sam2Config

    dims = [16, 32, 64, 128]
    side = image_size // 4
    return Sam2Config(
        vision_config=dict(
            backbone_config=dict(
                model_type="sam2_hiera_det_model",
                hidden_size=dims[0],
                num_attention_heads=1,
                image_size=[image_size, image_size],
                blocks_per_stage=[1, 1, 2, 1],
                embed_dim_per_stage=dims,
                num_attention_heads_per_stage=[1, 1, 2, 2],
                window_size_per_stage=[4, 4, 4, 2],
                global_attention_blocks=[3],
                window_positional_embedding_background_size=[4, 4],
            ),
            backbone_channel_list=dims[::-1],
            backbone_feature_sizes=[[side, side], [side // 2, side // 2], [side // 4, side // 4]],
            fpn_hidden_size=32,
        ),
        prompt_encoder_config=dict(hidden_size=32, image_size=image_size, patch_size=16, mask_input_channels=8),
        mask_decoder_config=dict(
            hidden_size=32, mlp_dim=64, num_hidden_layers=2, num_attention_heads=2, iou_head_hidden_dim=32
        ),
    )


def _spread_weights(model, hypernetwork_scale: float) -> None:
    """PyTorch's own init for every layer (the library's shrinks activations layer by layer, so
    random embeddings would be ~0 and every comparison would pass trivially) and larger
    hypernetwork outputs, so that mask logits are a few units and masks vary (as save_sam does)."""
    with torch.no_grad():
        for module in model.modules():
            if module is not model and hasattr(module, "reset_parameters"):
                module.reset_parameters()
        decoder = model.mask_decoder
        for mlp in [*decoder.output_hypernetworks_mlps, getattr(decoder, "hq_mask_mlp", None)]:
            if mlp is not None:
                mlp.proj_out.weight.mul_(hypernetwork_scale)


def save_sam_hq(folder: Path, config_fn=tiny_sam_hq_config, seed: int = 2) -> Path:
    """Random SAM-HQ with its SamHQProcessor (SAM's pre-processing) in ``folder``."""
    from transformers import SamHQModel, SamHQProcessor, SamImageProcessor

    folder.mkdir(parents=True, exist_ok=True)
    torch.manual_seed(seed)
    config = config_fn()
    model = SamHQModel(config).eval()
    # HQ sums the SAM token's mask and the HQ token's over the fused features: a factor of 10
    # gives logits of a few units (std ~2), as 100 does for SAM and SAM 2
    _spread_weights(model, 10.0)
    model.save_pretrained(folder)
    size = config.vision_config.image_size
    image_processor = SamImageProcessor(
        size={"longest_edge": size},
        pad_size={"height": size, "width": size},
        mask_size={"longest_edge": size // 4},
        mask_pad_size={"height": size // 4, "width": size // 4},
        image_mean=IMAGENET_MEAN,
        image_std=IMAGENET_STD,
    )
    SamHQProcessor(image_processor).save_pretrained(folder)
    return folder


def save_sam2(folder: Path, config_fn=tiny_sam2_config, seed: int = 3) -> Path:
    """Random SAM 2 with Sam2Processor's pre-processing config in ``folder``.

    The config is written as the published checkpoints carry it (Sam2ImageProcessor needs
    torchvision just to be constructed, and the tests must run without it): resize to the square
    input, rescale, ImageNet mean and std, no padding."""
    from transformers import Sam2Model

    folder.mkdir(parents=True, exist_ok=True)
    torch.manual_seed(seed)
    config = config_fn()
    model = Sam2Model(config).eval()
    _spread_weights(model, 100.0)
    model.save_pretrained(folder)
    size = config.prompt_encoder_config.image_size
    (folder / "preprocessor_config.json").write_text(
        json.dumps(
            {
                "image_processor_type": "Sam2ImageProcessor",
                "processor_class": "Sam2Processor",
                "do_resize": True,
                "size": {"height": size, "width": size},
                "mask_size": {"height": size // 4, "width": size // 4},
                "resample": 2,
                "do_rescale": True,
                "rescale_factor": 1 / 255,
                "do_normalize": True,
                "image_mean": IMAGENET_MEAN,
                "image_std": IMAGENET_STD,
                "do_convert_rgb": True,
            }
        ),
        encoding="utf-8",
    )
    return folder
