"""Random-weight semantic-segmentation checkpoints (SegFormer, UperNet) built from configs, their
metadata sidecars, and ONNX exports of them, for the ``semantic`` segmenter's tests.

Nothing is downloaded. Weights are re-initialised with PyTorch's own layer initialisation (the
library's, ``initializer_range=0.02``, gives logits of a few thousandths: every class probability
would be about 1/C and any comparison would pass trivially) and the classifier is scaled up, so
per-class probabilities spread over most of [0, 1].
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import torch

#: The tiny models' classes, in index order (names the entity matching can find: synonyms, plurals).
CLASSES = ("background", "road", "tree", "grass", "water")
IMAGENET_MEAN, IMAGENET_STD = [0.485, 0.456, 0.406], [0.229, 0.224, 0.225]


def _labels(classes: Sequence[str]) -> dict:
    return {"id2label": dict(enumerate(classes)), "label2id": {c: i for i, c in enumerate(classes)}}


def tiny_segformer_config(classes: Sequence[str] = CLASSES):
    """A two-stage SegFormer (MiT) with 16/32 channels; logits at a quarter of the input size."""
    from transformers import SegformerConfig

    return SegformerConfig(
        num_channels=3,
        num_encoder_blocks=2,
        depths=[1, 1],
        sr_ratios=[2, 1],
        hidden_sizes=[16, 32],
        patch_sizes=[7, 3],
        strides=[4, 2],
        num_attention_heads=[1, 2],
        mlp_ratios=[2, 2],
        decoder_hidden_size=32,
        num_labels=len(classes),
        **_labels(classes),
    )


def tiny_upernet_config(classes: Sequence[str] = CLASSES):
    """UperNet on a two-stage ConvNeXt; its forward upsamples the logits to the input size itself."""
    from transformers import ConvNextConfig, UperNetConfig

    backbone = ConvNextConfig(
        num_channels=3, hidden_sizes=[16, 32], depths=[1, 1], num_stages=2, out_features=["stage1", "stage2"]
    )
    return UperNetConfig(
        backbone_config=backbone,
        hidden_size=16,
        auxiliary_in_channels=32,
        auxiliary_channels=8,
        use_auxiliary_head=False,
        pool_scales=[1, 2],
        num_labels=len(classes),
        **_labels(classes),
    )


def _spread(model, classifier) -> None:
    """PyTorch's own init for every layer, then a larger classifier: logits of a few units."""
    with torch.no_grad():
        for module in model.modules():
            if module is not model and hasattr(module, "reset_parameters"):
                module.reset_parameters()
        classifier.weight.mul_(8.0)


def save_semantic(
    folder: Path, arch: str = "segformer", classes: Sequence[str] = CLASSES, size: int = 64, seed: int = 0
) -> Path:
    """A random SegFormer or UperNet with a SegformerImageProcessor (``size`` px) in ``folder``."""
    from transformers import SegformerForSemanticSegmentation, SegformerImageProcessor, UperNetForSemanticSegmentation

    folder.mkdir(parents=True, exist_ok=True)
    torch.manual_seed(seed)
    if arch == "segformer":
        model = SegformerForSemanticSegmentation(tiny_segformer_config(classes)).eval()
        _spread(model, model.decode_head.classifier)
    elif arch == "upernet":
        model = UperNetForSemanticSegmentation(tiny_upernet_config(classes)).eval()
        _spread(model, model.decode_head.classifier)
    else:
        raise ValueError(f"unknown architecture {arch!r}")
    model.save_pretrained(folder)
    SegformerImageProcessor(
        size={"height": size, "width": size}, resample=2, image_mean=IMAGENET_MEAN, image_std=IMAGENET_STD
    ).save_pretrained(folder)
    return folder


def write_sidecar(model_path: Path, **meta) -> Path:
    """``<model>.overseec.json`` beside the model folder or ONNX file, holding ``meta``."""
    path = model_path.with_name(model_path.name + ".overseec.json")
    path.write_text(json.dumps(meta), encoding="utf-8")
    return path


class _Logits(torch.nn.Module):
    """The checkpoint's forward reduced to pixel values -> logits (what the ONNX graph holds)."""

    def __init__(self, model) -> None:
        super().__init__()
        self.model = model

    def forward(self, pixel_values):
        return self.model(pixel_values=pixel_values).logits


def export_onnx(folder: Path, out: Path, size: int = 64) -> Path:
    """The checkpoint in ``folder`` as an ONNX graph (dynamic batch and size), with the TorchScript
    exporter (the dynamo one needs onnxscript). Needs the ``onnx`` package."""
    from transformers import AutoModelForSemanticSegmentation

    model = AutoModelForSemanticSegmentation.from_pretrained(folder).eval()
    wrapper = _Logits(model).eval()  # export restores the wrapper's mode: keep it eval
    example = torch.zeros(1, 3, size, size)
    with torch.no_grad():
        torch.onnx.export(
            wrapper,
            (example,),
            str(out),
            input_names=["pixel_values"],
            output_names=["logits"],
            dynamic_axes={
                "pixel_values": {0: "batch", 2: "height", 3: "width"},
                "logits": {0: "batch", 2: "h", 3: "w"},
            },
            opset_version=17,
            dynamo=False,
        )
    return out
