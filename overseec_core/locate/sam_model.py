"""The SAM family's models for the Locate stage: loading a checkpoint into a :class:`SamBundle`
(offline, cached per device and precision, with the two patches that bound its memory and speed
up its decoder on CPU), its pre-processing values and pixels, and the one place the refiners (SAM,
SAM-HQ, SAM 2) differ: what the image encoder hands the mask decoder (:func:`encode_tiles`,
:func:`decoder_inputs`). The refiner that uses them is :mod:`overseec_core.locate.sam`.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # torch is imported where a model runs, never at import time
    import torch

from overseec_core.errors import InputError
from overseec_core.locate.models import (
    ModelRef,
    cached_model,
    channels_last_on_gpu,
    compile_module,
    load_aux,
    load_pretrained,
    resolve_device,
    resolve_model,
    resolve_precision,
)
from overseec_core.locate.refiners import DEFAULT_REFINER, get_refiner


@dataclass
class SamBundle:
    """A loaded SAM checkpoint with its pre-processing values."""

    ref: ModelRef
    model: Any  # SamModel
    image_size: int  # encoder input (1024 for the published checkpoints)
    mask_size: int  # low-resolution mask side (image_size / 4)
    mean: tuple[float, ...]  # per channel (R, G, B)
    std: tuple[float, ...]
    rescale: float
    device: Any
    precision: str
    refiner: str = DEFAULT_REFINER  # which family (overseec_core.locate.refiners): what the encoder returns


#: Query tokens per chunk of SAM's global attention (see :func:`chunk_global_attention`).
GLOBAL_ATTENTION_CHUNK = 256


def _chunked_global_attention(self, hidden_states, output_attentions=False):
    """SamVisionAttention.forward for a global-attention layer, queries in row chunks.

    Same arithmetic as the library's SDPA path (decomposed relative-position bias added to the
    scaled dot products), but the (heads, tokens, tokens) bias is built for a few query rows at a
    time instead of whole: at 1024 px that bias is 12 x 4096 x 4096 floats, 805 MB, and the
    library's path held it plus an attention matrix of the same size, 1.7 GB per tile.
    """
    import torch
    import torch.nn.functional as F  # noqa: N812 (PyTorch's own convention)

    batch, height, width, _ = hidden_states.shape
    heads = self.num_attention_heads
    qkv = self.qkv(hidden_states).reshape(batch, height * width, 3, heads, -1).permute(2, 0, 3, 1, 4)
    query, key, value = qkv.reshape(3, batch * heads, height * width, -1).unbind(0)
    pos_h = self.get_rel_pos(height, height, self.rel_pos_h)  # (H, H, C)
    pos_w = self.get_rel_pos(width, width, self.rel_pos_w)  # (W, W, C)
    q_grid = query.reshape(batch * heads, height, width, -1)
    out = torch.empty_like(query)
    rows = max(1, GLOBAL_ATTENTION_CHUNK // width)
    for r0 in range(0, height, rows):
        r1 = min(height, r0 + rows)
        q = q_grid[:, r0:r1]
        rel_h = torch.einsum("bhwc,hkc->bhwk", q, pos_h[r0:r1])
        rel_w = torch.einsum("bhwc,wkc->bhwk", q, pos_w)
        bias = (rel_h[:, :, :, :, None] + rel_w[:, :, :, None, :]).reshape(batch * heads, (r1 - r0) * width, -1)
        out[:, r0 * width : r1 * width] = F.scaled_dot_product_attention(
            q.reshape(batch * heads, -1, q.shape[-1]), key, value, attn_mask=bias.to(q.dtype)
        )
    attn = out.view(batch, heads, height, width, -1).permute(0, 2, 3, 1, 4).reshape(batch, height, width, -1)
    return self.proj(attn), None


def chunk_global_attention(model) -> int:
    """Give SAM's (or SAM-HQ's) global-attention layers the chunked forward; returns how many were
    changed (none for SAM 2, whose Hiera encoder has no decomposed relative-position bias)."""
    import types

    changed = 0
    for layer in getattr(model.vision_encoder, "layers", ()):  # SAM and SAM-HQ's ViT (SAM 2's Hiera has none)
        attn = layer.attn
        if layer.window_size == 0 and getattr(attn, "use_rel_pos", False):
            attn.forward = types.MethodType(_chunked_global_attention, attn)
            changed += 1
    return changed


def _tokens_contiguous(module, args, kwargs):
    """Forward pre-hook of SAM's two-way transformer: image and positional embeddings in
    channels-last memory, so the transformer's (B, C, H, W) -> (B, HW, C) view is contiguous."""
    for name in ("image_embeddings", "image_positional_embeddings"):
        tensor = kwargs.get(name)
        if tensor is not None and tensor.dim() == 4:
            import torch

            kwargs[name] = tensor.contiguous(memory_format=torch.channels_last)
    return args, kwargs


def contiguous_decoder_tokens(model):
    """Speed up SAM's mask decoder on CPU by a third, same numbers.

    The library's transformer turns (B, C, H, W) embeddings into a transposed token view and then
    adds it to contiguous tensors, elementwise work that runs about five times slower on mixed
    layouts; each decoded component pays it on 4096 x 256 tokens. Only the memory layout of the
    two inputs changes (a test checks the outputs are equal).
    """
    return model.mask_decoder.transformer.register_forward_pre_hook(_tokens_contiguous, with_kwargs=True)


def resolve_refiner_model(name: str | None, refiner: str = DEFAULT_REFINER) -> ModelRef:
    """Resolve (offline) the checkpoint ``refiner`` runs: ``name``, or the refiner's default when
    None. A missing model, or a checkpoint of another family, fails here with one line naming it."""
    info = get_refiner(refiner)
    return resolve_model(name or info.default_model, info.name)


def load_sam(
    name: str | None = None,
    device: str = "auto",
    precision: str = "auto",
    compile: bool = False,
    refiner: str = DEFAULT_REFINER,
) -> SamBundle:
    """Resolve (offline), load and cache a refiner's checkpoint on a device: SAM (or SlimSAM),
    SAM-HQ or SAM 2 (``refiner``; ``name`` None is its default checkpoint).

    Attention is PyTorch's scaled-dot-product kernel (``attn_implementation='sdpa'``; SAM's and
    SAM-HQ's global layers run it in query chunks); on CUDA the encoder's weights are channels-last;
    ``compile`` wraps the image encoder in ``torch.compile`` (its first tile pays the compilation).
    """
    import transformers

    info = get_refiner(refiner)
    ref = resolve_refiner_model(name, info.name)
    dev = resolve_device(device)
    prec = resolve_precision(precision, dev)

    def build() -> SamBundle:
        model = load_pretrained(getattr(transformers, info.model_class), ref, dev)
        chunk_global_attention(model)
        contiguous_decoder_tokens(model)
        channels_last_on_gpu(model, dev)
        if compile:
            compile_module(model.vision_encoder)
        prompt_cfg = model.config.prompt_encoder_config
        size = int(prompt_cfg.image_size)
        mask = 4 * (size // int(prompt_cfg.patch_size))
        mean, std, rescale = pixel_values_config(ref, info.name)
        return SamBundle(ref, model, size, mask, mean, std, rescale, dev, prec, info.name)

    return cached_model(("sam", ref.path, str(dev), prec, bool(compile)), build)


#: The processor each refiner's checkpoints carry (its image processor holds the pixel values).
PROCESSORS = {"sam": "AutoImageProcessor", "sam-hq": "SamHQProcessor", "sam2": "Sam2Processor"}


def pixel_values_config(ref: ModelRef, refiner: str) -> tuple[tuple[float, ...], tuple[float, ...], float]:
    """(mean, std, rescale factor) of a checkpoint's pre-processing, from its processor.

    Sam2Processor's image processor needs torchvision just to be constructed; without it (or
    without a processor in the folder) the values are read from the saved processor config
    itself, and SAM's published ones fill what is missing."""
    import transformers

    loader = getattr(transformers, PROCESSORS[refiner]).from_pretrained
    try:
        proc = load_aux(loader, ref)
    except ImportError:  # a processor class whose backend (torchvision) is not installed
        proc = None
    values: dict[str, Any] = {}
    if proc is not None:
        image_proc = getattr(proc, "image_processor", proc)
        values = {k: getattr(image_proc, k, None) for k in ("image_mean", "image_std", "rescale_factor")}
    else:
        values = _saved_image_processor(Path(ref.path))
    mean = tuple(values.get("image_mean") or (0.485, 0.456, 0.406))
    std = tuple(values.get("image_std") or (0.229, 0.224, 0.225))
    return mean, std, float(values.get("rescale_factor") or 1 / 255)


def _saved_image_processor(folder: Path) -> dict[str, Any]:
    """The image processor's settings as saved (preprocessor_config.json, or the image_processor
    entry of processor_config.json); empty when neither is there or readable."""
    for name, key in (("preprocessor_config.json", None), ("processor_config.json", "image_processor")):
        try:
            data = json.loads((folder / name).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        data = data.get(key, {}) if key else data
        if isinstance(data, dict) and data:
            return data
    return {}


def sam_preprocess(rgb: np.ndarray, bundle: SamBundle) -> torch.Tensor:
    """(B, h, w, 3) uint8 native tiles -> (B, 3, S, S): rescale, normalise, zero-pad bottom/right.

    What SamProcessor does for an image whose longest side is already S; smaller tiles are padded,
    never upscaled.
    """
    import torch
    import torch.nn.functional as F  # noqa: N812 (PyTorch's own convention)

    x = torch.from_numpy(np.ascontiguousarray(rgb)).to(bundle.device, non_blocking=True).permute(0, 3, 1, 2).float()
    mean = torch.tensor(bundle.mean, device=bundle.device).view(1, 3, 1, 1)
    std = torch.tensor(bundle.std, device=bundle.device).view(1, 3, 1, 1)
    x = (x * bundle.rescale - mean) / std
    h, w = x.shape[-2:]
    s = bundle.image_size
    if h > s or w > s:
        raise InputError(f"SAM tile {h}x{w} is larger than the model input {s}")
    return F.pad(x, (0, s - w, 0, s - h))


# --------------------------------------------------------------------------------------------
# The one place the refiners differ: what the encoder hands the mask decoder
# --------------------------------------------------------------------------------------------

#: Image embeddings of a batch of tiles: tensors with the tile as first dimension.
Embeddings = tuple[Any, ...]


def encode_tiles(bundle: SamBundle, pixels: torch.Tensor) -> Embeddings:
    """The image embeddings of (B, 3, S, S) pre-processed tiles, as the decoder will take them.

    * SAM: ``(embedding,)``, (B, C, S/16, S/16);
    * SAM-HQ: ``(embedding, features)``: its library decoder fuses the ViT features of the first
      global-attention block (B, S/16, S/16, vit_dim) into the HQ token's mask; the encoder returns
      every global block's, only that first one is kept (the later ones are never read);
    * SAM 2: ``(s0, s1, embedding)``: the two finer FPN levels (already projected by the decoder's
      ``conv_s0``/``conv_s1``, as the library does once per image) and the image embedding with
      the no-memory embedding added, exactly what ``Sam2Model.get_image_embeddings`` returns.
    """
    out = bundle.model.get_image_embeddings(pixels)
    if bundle.refiner == "sam-hq":
        embedding, features = out
        return (embedding, features[0])
    if bundle.refiner == "sam2":
        return tuple(out)
    return (out,)


def decoder_inputs(bundle: SamBundle, embeddings: Embeddings) -> dict[str, Any]:
    """The model's forward keywords that carry the image side, for gathered ``embeddings``."""
    if bundle.refiner == "sam-hq":
        return {"image_embeddings": embeddings[0], "intermediate_embeddings": [embeddings[1]]}
    if bundle.refiner == "sam2":
        return {"image_embeddings": list(embeddings)}
    return {"image_embeddings": embeddings[0]}


def gather_tiles(embeddings: Embeddings, rows: torch.Tensor) -> Embeddings:
    """Each prompt's tile embeddings: ``rows`` indexes the tiles, one per prompt."""
    return tuple(t.index_select(0, rows) for t in embeddings)


def encoder_blocks(bundle: SamBundle) -> list[Any]:
    """The image encoder's transformer blocks, in order (SAM 2's Hiera keeps them in its backbone)."""
    encoder = bundle.model.vision_encoder
    backbone = getattr(encoder, "backbone", None)
    return list(backbone.blocks if backbone is not None else encoder.layers)
