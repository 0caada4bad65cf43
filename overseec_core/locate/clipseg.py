"""CLIPSeg for the Locate stage: the model bundle and a batch predictor sharing one encoder pass.

Work is shared rather than repeated (the reference code runs the whole model once per class per
tile):

* text embeddings are computed once per run (several prompts of one entity are averaged);
* the CLIP vision encoder runs once per tile whatever the number of entities, and only up to the
  deepest layer the decoder reads (``extract_layers``; 10 of 12 layers for ViT-B/16);
* the decoder's per-layer reductions of those activations are computed once per tile too; only
  the FiLM conditioning and the small decoder layers run per entity, batched over entities.

This is why :class:`ClipSegPredictor` drives the sub-modules of ``CLIPSegForImageSegmentation``
itself rather than calling its ``forward``: the library's forward has no way to reuse one image's
encoder pass for several prompts. A test checks the logits equal the library forward's.

Pre-processing (resize to the model's input size, rescale, normalise with the checkpoint's image
processor values) is done with torch on the whole batch, on the device, matching the library's
PIL-based processor to within one grey level; output logits are resampled back to the tile with
bilinear interpolation before the sigmoid.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # torch is imported where a model runs, never at import time
    import torch

from overseec_core.errors import InputError, ModelError
from overseec_core.locate.models import (
    BatchState,
    ModelRef,
    autocast,
    cached_model,
    channels_last_on_gpu,
    compile_module,
    default_batch_size,
    describe_device,
    load_aux,
    load_pretrained,
    resolve_device,
    resolve_model,
    resolve_precision,
)
from overseec_core.locate.segmenters.base import predict_in_chunks, resize_maps


@dataclass(frozen=True)
class ImageNorm:
    """Pre-processing values from the checkpoint's image processor config."""

    size: int
    mean: tuple[float, ...]  # R, G, B (as the processor config gives them)
    std: tuple[float, ...]
    rescale: float = 1.0 / 255.0
    resample: str = "bilinear"


@dataclass
class ClipSegBundle:
    """A loaded CLIPSeg checkpoint with its tokenizer and pre-processing values."""

    ref: ModelRef
    model: Any  # CLIPSegForImageSegmentation
    tokenizer: Any
    norm: ImageNorm
    device: Any
    precision: str

    @property
    def patch_size(self) -> int:
        return int(self.model.config.vision_config.patch_size)


_PIL_RESAMPLE = {2: "bilinear", 3: "bicubic"}


def _image_norm(processor: Any, config: Any) -> ImageNorm:
    """Read size/mean/std from an image processor, with CLIP's defaults when there is none."""
    default_size = int(config.vision_config.image_size)
    if processor is None:
        return ImageNorm(default_size, (0.485, 0.456, 0.406), (0.229, 0.224, 0.225))
    size = getattr(processor, "size", None) or {}
    side = size.get("height") or size.get("shortest_edge") or default_size
    resample = _PIL_RESAMPLE.get(int(getattr(processor, "resample", 2) or 2), "bilinear")
    rescale = float(getattr(processor, "rescale_factor", 1 / 255)) if getattr(processor, "do_rescale", True) else 1.0
    mean, std = processor.image_mean, processor.image_std
    if not getattr(processor, "do_normalize", True):
        mean, std = (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)
    return ImageNorm(int(side), tuple(float(v) for v in mean), tuple(float(v) for v in std), rescale, resample)


def load_clipseg(name: str, device: str = "auto", precision: str = "auto", compile: bool = False) -> ClipSegBundle:
    """Resolve (offline), load and cache a CLIPSeg checkpoint on a device.

    Attention is PyTorch's scaled-dot-product kernel (``attn_implementation='sdpa'``); on CUDA the
    weights are channels-last; ``compile`` wraps the vision encoder's and the decoder's layers in
    ``torch.compile`` (the first batch pays the compilation).
    """
    from transformers import AutoImageProcessor, AutoTokenizer, CLIPSegForImageSegmentation

    ref = resolve_model(name, "clipseg")
    dev = resolve_device(device)
    prec = resolve_precision(precision, dev)

    def build() -> ClipSegBundle:
        model = load_pretrained(CLIPSegForImageSegmentation, ref, dev)
        channels_last_on_gpu(model, dev)
        if compile:
            for layer in (*model.clip.vision_model.encoder.layers, *model.decoder.layers):
                compile_module(layer)  # the predictor calls the layers, not the models' forward
        tokenizer = load_aux(AutoTokenizer.from_pretrained, ref)
        if tokenizer is None:
            raise ModelError(
                f"clipseg model {ref.name}: no tokenizer in {ref.path} (vocab.json/merges.txt or tokenizer.json)"
            )
        processor = load_aux(AutoImageProcessor.from_pretrained, ref)
        return ClipSegBundle(ref, model, tokenizer, _image_norm(processor, model.config), dev, prec)

    return cached_model(("clipseg", ref.path, str(dev), prec, bool(compile)), build)


def preprocess(rgb: np.ndarray, norm: ImageNorm, size: int, device) -> torch.Tensor:
    """(B, h, w, 3) uint8 -> (B, 3, size, size) float normalised pixel values, with torch.

    Resizes with antialiasing (PIL's filter, one axis at a time) and rounds to grey levels as the
    library's uint8 processor does, then rescales and normalises.
    """
    import torch
    import torch.nn.functional as F  # noqa: N812 (PyTorch's own convention)

    x = torch.from_numpy(np.ascontiguousarray(rgb)).to(device, non_blocking=True).permute(0, 3, 1, 2).float()
    if x.shape[-2:] != (size, size):
        # PIL resamples uint8 images horizontally, then vertically, rounding half up after each
        # pass; doing the same keeps the model's input within one grey level of the processor's.
        for shape in ((x.shape[-2], size), (size, size)):
            x = F.interpolate(x, size=shape, mode=norm.resample, align_corners=False, antialias=True)
            x = torch.floor(x + 0.5).clamp_(0, 255)
    mean = torch.tensor(norm.mean, device=device).view(1, 3, 1, 1)
    std = torch.tensor(norm.std, device=device).view(1, 3, 1, 1)
    return (x * norm.rescale - mean) / std


def text_embeddings(bundle: ClipSegBundle, prompts: Sequence[Sequence[str]]) -> torch.Tensor:
    """(E, projection_dim) conditional embeddings, one per entity (mean over its prompts).

    Computed once per run, never per tile.
    """
    import torch

    flat = [p for group in prompts for p in group]
    max_len = int(bundle.model.config.text_config.max_position_embeddings)
    enc = bundle.tokenizer(flat, padding=True, truncation=True, max_length=max_len, return_tensors="pt")
    with torch.inference_mode():
        feats = bundle.model.clip.get_text_features(
            input_ids=enc["input_ids"].to(bundle.device), attention_mask=enc["attention_mask"].to(bundle.device)
        ).pooler_output.float()
    out, k = [], 0
    for group in prompts:
        out.append(feats[k : k + len(group)].mean(dim=0))
        k += len(group)
    return torch.stack(out)


class ClipSegPredictor:
    """Batch predictor for the tiling engine: (B, h, w, 3) uint8 -> (B, E, h, w) probabilities.

    One vision-encoder pass per tile for all E entities (see the module docstring). It is the
    ``clipseg`` segmenter's :class:`~overseec_core.locate.segmenters.base.LoadedSegmenter`:
    ``encoder_calls`` counts tiles encoded (tests, the manifest), ``timings`` holds the load's
    extra phases (text embeddings).
    """

    def __init__(
        self, bundle: ClipSegBundle, cond: torch.Tensor, model_size: int | None = None, batch_size: int | None = None
    ) -> None:
        self.bundle = bundle
        self.model = bundle.model
        self.ref: ModelRef = bundle.ref
        self.device = bundle.device
        self.precision: str = bundle.precision
        self.timings: dict[str, float] = {}
        self.cond = cond.to(bundle.device)
        self.model_size = int(model_size or bundle.norm.size)
        patch = bundle.patch_size
        if self.model_size % patch or self.model_size < 2 * patch:
            raise InputError(
                f"--model-size {self.model_size} must be a multiple of the model's "
                f"patch size {patch} and at least {2 * patch}"
            )
        self.extract_layers = tuple(int(i) for i in self.model.config.extract_layers)
        self.state = BatchState(batch_size or default_batch_size(bundle.device, 4, 16))
        self.encoder_calls = 0

    @property
    def entities(self) -> int:
        return int(self.cond.shape[0])

    def describe(self) -> str:
        """'CLIPSeg NAME on DEVICE (PRECISION), model input S px': the progress log's line."""
        return (
            f"CLIPSeg {self.ref.name} on {describe_device(self.device)} ({self.precision}), "
            f"model input {self.model_size} px"
        )

    def encode(self, pixel_values: torch.Tensor) -> list[torch.Tensor]:
        """Activations of the vision encoder at ``extract_layers``, running only the layers needed."""
        vm = self.model.clip.vision_model
        hidden = vm.pre_layrnorm(vm.embeddings(pixel_values, interpolate_pos_encoding=True))
        wanted = set(self.extract_layers)
        acts: dict[int, Any] = {}
        for i, layer in enumerate(vm.encoder.layers[: max(self.extract_layers) + 1]):
            hidden = layer(hidden, None)
            if i in wanted:
                acts[i] = hidden
        self.encoder_calls += int(pixel_values.shape[0])
        return [acts[i] for i in self.extract_layers]

    def decode(self, activations: list[torch.Tensor], cond: torch.Tensor) -> torch.Tensor:
        """(B, S, S) -> (B, E, S, S) logits: CLIPSegDecoder.forward, shared parts done once per tile."""
        dec = self.model.decoder
        batch, entities = activations[0].shape[0], cond.shape[0]
        film_mul = dec.film_mul(cond).repeat(batch, 1)[:, None, :]
        film_add = dec.film_add(cond).repeat(batch, 1)[:, None, :]
        output = None
        for i, (activation, layer, reduce) in enumerate(zip(activations[::-1], dec.layers, dec.reduces)):
            reduced = reduce(activation).repeat_interleave(entities, dim=0)  # once per tile
            output = reduced if output is None else reduced + output
            if i == dec.conditional_layer:
                output = film_mul * output + film_add
            output = layer(output, attention_mask=None)
        assert output is not None  # CLIPSeg's decoder has layers
        output = output[:, 1:, :].transpose(1, 2)
        side = int(math.isqrt(output.shape[2]))
        output = output.reshape(batch * entities, output.shape[1], side, side)
        logits = dec.transposed_convolution(output).squeeze(1)
        return logits.reshape(batch, entities, *logits.shape[-2:])

    def logits(self, rgb: np.ndarray) -> torch.Tensor:
        """Model-resolution logits (B, E, S, S) for a batch of RGB tiles."""
        import torch

        b = self.bundle
        with torch.inference_mode(), autocast(b.device, b.precision):
            pixels = preprocess(rgb, b.norm, self.model_size, b.device)
            return self.decode(self.encode(pixels), self.cond).float()

    def _chunk(self, rgb: np.ndarray, start: int, stop: int) -> np.ndarray:
        import torch

        logits = self.logits(rgb[start:stop])
        with torch.inference_mode():
            return torch.sigmoid(resize_maps(logits, (rgb.shape[1], rgb.shape[2]))).cpu().numpy()

    def __call__(self, rgb: np.ndarray, valid: np.ndarray) -> np.ndarray:
        """(B, h, w, 3) uint8 tiles -> (B, E, h, w) float32 probabilities (``valid`` is not needed:
        the blender ignores pixels without data)."""
        return predict_in_chunks(lambda a, z: self._chunk(rgb, a, z), len(rgb), self.state)


__all__ = [
    "ClipSegBundle",
    "ClipSegPredictor",
    "ImageNorm",
    "load_clipseg",
    "preprocess",
    "text_embeddings",
]
