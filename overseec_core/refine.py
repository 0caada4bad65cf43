"""Locate, fine: SAM refinement of the coarse CLIPSeg masks, prompted as SAMRefiner does.

SAM is run on its own tile grid of native imagery: tiles of the model's input size (1024 px for
SAM ViT-B), never an upscaled smaller tile (the reference upscales 512 px tiles to 1024: four
times the encoder work per area). An image smaller than that is padded, as SAM's processor pads.
Tiles where no entity has a coarse mask worth refining skip SAM entirely; otherwise the image
embedding is computed once per tile and shared by every entity and component.

Per tile and entity, each connected component of the coarse mask (scipy.ndimage.label,
8-connected) is refined separately, largest first:

* positive points at distance-transform maxima of the component (spread out by suppression),
* negative points at the most confident background in the component's context box, near it,
* a box around the component (with a small margin),
* the coarse logits, relative to the entity's threshold, as the dense mask prompt,

and the prediction is fed back (its low-resolution logits as the next mask prompt, new points and
box from the refined mask) for a small number of iterations, stopping early for a component whose
mask no longer changes. Components under ``min_area`` pixels, and those beyond the
``max_components`` largest of an entity in a tile, keep their coarse mask (SAM's 4 px mask cells
cannot improve tiny ones; on CPU each decoded component costs about a hundredth of the encoder).

Per entity the tile's refined probability is SAM's (max over components) inside the components'
context boxes and, elsewhere, the coarse probability recalibrated so that the entity's threshold
maps to 0.5 (:func:`calibrate`); the refined mask is then ``refined probability >= 0.5``
everywhere: SAM's mask near what it refined, the coarse mask elsewhere. Overlapping SAM tiles are
blended by the tiling engine's :class:`~overseec_core.tiling.StreamingBlender` (one band per
entity), rows stream into ``refined_probs.tif``, ``refined_masks.tif`` and ``gated.tif``
(P^tau = P * M, what the cost stage reads).

The driver loop is written here rather than with ``stream_predict`` because each SAM tile also
needs its window of ``probs.tif``, and ``stream_predict``'s predictor sees pixels only.
"""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Iterator, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # torch is imported where a model runs, never at import time
    import torch
    from rasterio.windows import Window
from scipy import ndimage

from . import defaults, runfiles
from .errors import InputError, RasterError
from .models import (
    DEFAULT_SAM,
    BatchState,
    ModelRef,
    autocast,
    cached_model,
    default_batch_size,
    describe_device,
    load_aux,
    load_pretrained,
    resolve_device,
    resolve_model,
    resolve_precision,
    run_with_backoff,
)
from .progress import Progress, check_cancelled
from .raster import RasterSource, RasterWriter, open_raster
from .schema import Entity
from .segment import MASK_NODATA, check_tile_options, entities_tag, prepare_out_dir, threshold_of, validate_entities
from .tiling import StreamingBlender, TileGrid, blend_weights

REFINED_PROBS_NAME, REFINED_MASKS_NAME, GATED_NAME = runfiles.REFINED_PROBS, runfiles.REFINED_MASKS, runfiles.GATED
#: Clip of the mask-prompt logits (SAM's own low-res logits live in about this range).
MASK_PROMPT_LIMIT = 10.0
_EIGHT = np.ones((3, 3), bool)


# --------------------------------------------------------------------------------------------
# Prompts from coarse masks (pure numpy)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class RefineParams:
    """How coarse masks become SAM prompts."""

    iterations: int = 2  # SAM decoder passes per component (1 = no feedback)
    stop_iou: float = 0.95  # a component whose mask changed less than this between passes is done
    min_area: int = 256  # px; smaller components keep their coarse mask (SAM's mask cells are 4 px)
    max_components: int = 8  # per entity per tile, largest first; the rest keep coarse masks
    positive_points: int = 3
    negative_points: int = 2
    box_margin: float = 0.1  # box = component bbox grown by this fraction of its size
    decoder_batch: int = 4  # components per mask-decoder call (~50 MB each; 4 is fastest on CPU)

    def check(self) -> None:
        if self.iterations < 1:
            raise InputError(f"--sam-iterations must be at least 1, got {self.iterations}")
        if (
            self.min_area < 1
            or self.max_components < 1
            or self.positive_points < 1
            or self.negative_points < 0
            or self.decoder_batch < 1
        ):
            raise InputError("SAM prompt settings must be positive (min area, components, points)")
        if not 0.0 <= self.stop_iou <= 1.0:
            raise InputError(f"stop IoU {self.stop_iou} must be between 0 and 1")
        if not 0.0 <= self.box_margin <= 1.0:
            raise InputError(f"box margin {self.box_margin} must be between 0 and 1")


@dataclass(frozen=True)
class Component:
    """One connected component of a coarse mask in a tile."""

    label: int
    rows: slice
    cols: slice
    area: int


@dataclass(frozen=True)
class ComponentPrompt:
    """SAM prompts for one component: points (x, y) with labels 1/0, a box, and its context box."""

    entity: int
    component: Component
    points: np.ndarray  # (k, 2) float32, x then y, tile pixel coordinates
    labels: np.ndarray  # (k,) int64: 1 positive, 0 negative
    box: tuple[float, float, float, float]  # x0, y0, x1, y1 (inclusive pixel centres)
    region: tuple[slice, slice]  # where SAM's answer for this component is accepted


def find_components(mask: np.ndarray, min_area: int, max_components: int) -> tuple[np.ndarray, list[Component], int]:
    """8-connected components: (labels, the ones to refine (largest first), count left coarse)."""
    labels, n = ndimage.label(mask, structure=_EIGHT)
    if n == 0:
        return labels, [], 0
    areas = np.bincount(labels.ravel(), minlength=n + 1)[1:]
    slices = ndimage.find_objects(labels)
    order = np.argsort(-areas, kind="stable")
    big = [int(i) for i in order if areas[i] >= min_area]
    chosen = big[:max_components]
    comps = [Component(i + 1, slices[i][0], slices[i][1], int(areas[i])) for i in chosen]
    return labels, comps, n - len(chosen)


def _grow(sl: slice, size: int, frac: float, minimum: int, limit: int) -> slice:
    pad = max(minimum, int(round(frac * size)))
    return slice(max(0, sl.start - pad), min(limit, sl.stop + pad))


#: Pixels above which prompt points are searched on a subsampled grid (SAM's mask cells are 4 px).
POINT_SEARCH_PIXELS = 1 << 16


def _step(shape: tuple[int, ...]) -> int:
    """Subsampling step that brings an array under POINT_SEARCH_PIXELS pixels."""
    return max(1, int(np.ceil(np.sqrt(shape[0] * shape[1] / POINT_SEARCH_PIXELS))))


def positive_points(component: np.ndarray, n: int) -> list[tuple[int, int]]:
    """Up to ``n`` (row, col) points at distance-transform maxima, spread out by suppression.

    The first is the component's most interior pixel; each pick clears a disc (twice its depth,
    at least 1/(n+1) of the component's extent) so later picks land elsewhere on long shapes.
    Large components are searched on every k-th pixel (picks are still component pixels).
    """
    k = _step(component.shape)
    sub = component[::k, ::k]
    depth = ndimage.distance_transform_edt(np.pad(sub, 1))[1:-1, 1:-1]
    h, w = depth.shape
    rr, cc = np.ogrid[:h, :w]
    spread = np.hypot(h, w) / (n + 1)
    points = []
    for _ in range(n):
        idx = int(np.argmax(depth))
        value = depth.flat[idx]
        if value <= 0:
            break
        r, c = divmod(idx, w)
        points.append((r * k, c * k))
        radius = max(2.0 * value, spread)
        depth[(rr - r) ** 2 + (cc - c) ** 2 <= radius * radius] = 0
    return points


def negative_points(foreground: np.ndarray, score: np.ndarray, n: int) -> list[tuple[int, int]]:
    """Up to ``n`` (row, col) background points: lowest ``score`` (foreground probability) outside
    the foreground and a small band around it, preferring places near it; NaN scores are skipped.
    Large regions are searched on every k-th pixel.
    """
    if n <= 0:
        return []
    k = _step(foreground.shape)
    foreground, score = foreground[::k, ::k], score[::k, ::k]
    h, w = foreground.shape
    diag = float(np.hypot(h, w))
    dist = ndimage.distance_transform_edt(~foreground) if foreground.any() else np.full((h, w), diag)
    band = max(2.0 / k, 0.03 * diag)
    ok = (dist > band) & np.isfinite(score)
    if not ok.any():
        return []
    cost = np.where(ok, np.nan_to_num(score) + 0.25 * dist / diag, np.inf)
    rr, cc = np.ogrid[:h, :w]
    radius = max(4.0 / k, diag / 4)
    points = []
    for _ in range(n):
        idx = int(np.argmin(cost))
        if not np.isfinite(cost.flat[idx]):
            break
        r, c = divmod(idx, w)
        points.append((r * k, c * k))
        cost[(rr - r) ** 2 + (cc - c) ** 2 <= radius * radius] = np.inf
    return points


def make_prompt(
    entity: int, component: Component, foreground: np.ndarray, score: np.ndarray, params: RefineParams
) -> ComponentPrompt:
    """Prompts for one component; ``foreground`` is its current mask on the tile, ``score`` the
    current foreground probability (coarse, then SAM's) used to place negatives."""
    h, w = foreground.shape
    rows, cols = component.rows, component.cols
    size = max(rows.stop - rows.start, cols.stop - cols.start)
    box_r = _grow(rows, size, params.box_margin, 2, h)
    box_c = _grow(cols, size, params.box_margin, 2, w)
    region = (_grow(rows, size, 2 * params.box_margin, 8, h), _grow(cols, size, 2 * params.box_margin, 8, w))
    crop = foreground[rows, cols]
    pos = [(r + rows.start, c + cols.start) for r, c in positive_points(crop, params.positive_points)]
    rr, rc = region
    neg = [
        (r + rr.start, c + rc.start)
        for r, c in negative_points(foreground[rr, rc], score[rr, rc], params.negative_points)
    ]
    pts = np.array([(c, r) for r, c in pos + neg], np.float32).reshape(-1, 2)
    labels = np.array([1] * len(pos) + [0] * len(neg), np.int64)
    box = (float(box_c.start), float(box_r.start), float(box_c.stop - 1), float(box_r.stop - 1))
    return ComponentPrompt(entity, component, pts, labels, box, region)


def coarse_mask_logits(probs: np.ndarray, threshold: float) -> np.ndarray:
    """Coarse probabilities as logits relative to the threshold (0 at the threshold), clipped;
    NaN (nodata) becomes confident background."""
    p = np.clip(np.nan_to_num(probs, nan=0.0), 1e-6, 1 - 1e-6)
    t = np.clip(threshold, 1e-6, 1 - 1e-6)
    logits = np.log(p / (1 - p)) - np.log(t / (1 - t))
    return np.clip(logits, -MASK_PROMPT_LIMIT, MASK_PROMPT_LIMIT).astype(np.float32)


def needs_sam(coarse: np.ndarray, thresholds: Sequence[float], params: RefineParams) -> bool:
    """True when some entity has a component of at least ``min_area`` pixels in this tile."""
    for probs, tau in zip(coarse, thresholds):
        with np.errstate(invalid="ignore"):
            mask = probs >= tau
        if mask.sum() < params.min_area:
            continue
        if find_components(mask, params.min_area, 1)[1]:
            return True
    return False


# --------------------------------------------------------------------------------------------
# SAM model bundle and per-tile refinement
# --------------------------------------------------------------------------------------------


@dataclass
class SamBundle:
    """A loaded SAM checkpoint with its pre-processing values."""

    ref: ModelRef
    model: Any  # SamModel
    image_size: int  # encoder input (1024 for the published checkpoints)
    mask_size: int  # low-resolution mask side (image_size / 4)
    mean: tuple[float, float, float]
    std: tuple[float, float, float]
    rescale: float
    device: Any
    precision: str


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
    """Give SAM's global-attention layers the chunked forward; returns how many were changed."""
    import types

    changed = 0
    for layer in model.vision_encoder.layers:
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


def load_sam(name: str, device: str = "auto", precision: str = "auto") -> SamBundle:
    """Resolve (offline), load and cache a SAM (or SlimSAM) checkpoint on a device."""
    from transformers import AutoImageProcessor, SamModel

    ref = resolve_model(name, "sam")
    dev = resolve_device(device)
    prec = resolve_precision(precision, dev)

    def build() -> SamBundle:
        model = load_pretrained(SamModel, ref, dev)
        chunk_global_attention(model)
        contiguous_decoder_tokens(model)
        cfg = model.config
        proc = load_aux(AutoImageProcessor.from_pretrained, ref)
        mean = tuple(getattr(proc, "image_mean", None) or (0.485, 0.456, 0.406))
        std = tuple(getattr(proc, "image_std", None) or (0.229, 0.224, 0.225))
        rescale = float(getattr(proc, "rescale_factor", 1 / 255) or 1 / 255)
        size = int(cfg.vision_config.image_size)
        mask = 4 * int(cfg.prompt_encoder_config.image_embedding_size)
        return SamBundle(ref, model, size, mask, mean, std, rescale, dev, prec)

    return cached_model(("sam", ref.path, str(dev), prec), build)


def sam_preprocess(rgb: np.ndarray, bundle: SamBundle) -> torch.Tensor:
    """(B, h, w, 3) uint8 native tiles -> (B, 3, S, S): rescale, normalise, zero-pad bottom/right.

    What SamProcessor does for an image whose longest side is already S; smaller tiles are padded,
    never upscaled.
    """
    import torch
    import torch.nn.functional as F  # noqa: N812 (PyTorch's own convention)

    x = torch.from_numpy(np.ascontiguousarray(rgb)).to(bundle.device).permute(0, 3, 1, 2).float()
    mean = torch.tensor(bundle.mean, device=bundle.device).view(1, 3, 1, 1)
    std = torch.tensor(bundle.std, device=bundle.device).view(1, 3, 1, 1)
    x = (x * bundle.rescale - mean) / std
    h, w = x.shape[-2:]
    s = bundle.image_size
    if h > s or w > s:
        raise InputError(f"SAM tile {h}x{w} is larger than the model input {s}")
    return F.pad(x, (0, s - w, 0, s - h))


@dataclass
class TileStats:
    """Counts for the manifest."""

    tiles_sam: int = 0
    tiles_no_mask: int = 0
    components_refined: int = 0
    components_coarse: int = 0
    decoder_calls: int = 0  # mask-decoder calls (each a batch of components)
    decoder_prompts: int = 0  # component prompts decoded, passes counted
    encoder_calls: int = 0

    def add(self, other: TileStats) -> None:
        for k in vars(self):
            setattr(self, k, getattr(self, k) + getattr(other, k))


class SamRefiner:
    """Refines coarse per-entity probabilities of tiles with SAM (see the module docstring)."""

    def __init__(self, bundle: SamBundle, params: RefineParams = RefineParams(), batch_size: int | None = None) -> None:
        params.check()
        self.bundle, self.params = bundle, params
        self.state = BatchState(batch_size or default_batch_size(bundle.device, 1, 4))
        self.stats = TileStats()

    # -- model calls ---------------------------------------------------------------------------

    def embed(self, rgb: np.ndarray) -> torch.Tensor:
        """(B, C, e, e) image embeddings of B tiles: the encoder runs once per tile."""
        import torch

        b = self.bundle

        def run(a: int, z: int):
            with torch.inference_mode(), autocast(b.device, b.precision):
                return b.model.get_image_embeddings(sam_preprocess(rgb[a:z], b))

        out = torch.cat(run_with_backoff(run, len(rgb), self.state))
        self.stats.encoder_calls += len(rgb)
        return out

    def decode(
        self, embedding: torch.Tensor, prompts: Sequence[ComponentPrompt], mask_inputs: torch.Tensor
    ) -> tuple[torch.Tensor, torch.Tensor]:
        """One mask-decoder call for several components of one tile.

        Returns low-res logits (n, m, m) and the tile-resolution logits (n, S, S).
        """
        import torch
        import torch.nn.functional as F  # noqa: N812 (PyTorch's own convention)

        b = self.bundle
        n = len(prompts)
        k = max(len(p.labels) for p in prompts)
        points = np.zeros((n, 1, k, 2), np.float32)
        labels = np.full((n, 1, k), -10, np.int64)  # -10: padding, ignored by SAM
        for i, p in enumerate(prompts):
            points[i, 0, : len(p.labels)] = p.points
            labels[i, 0, : len(p.labels)] = p.labels
        boxes = np.array([[p.box] for p in prompts], np.float32)
        dev = b.device
        with torch.inference_mode(), autocast(dev, b.precision):
            out = b.model(
                image_embeddings=embedding.expand(n, -1, -1, -1),
                input_points=torch.from_numpy(points).to(dev),
                input_labels=torch.from_numpy(labels).to(dev),
                input_boxes=torch.from_numpy(boxes).to(dev),
                input_masks=mask_inputs.to(dev),
                multimask_output=False,
            )
            low = out.pred_masks[:, 0, 0].float()
            full = F.interpolate(low[:, None], size=(b.image_size, b.image_size), mode="bilinear", align_corners=False)[
                :, 0
            ]
        self.stats.decoder_calls += 1
        self.stats.decoder_prompts += n
        return low, full

    def _mask_prompt(self, logits_tiles: np.ndarray) -> torch.Tensor:
        """(n, h, w) tile logits -> (n, 1, m, m) mask prompts in SAM's padded frame (area mean)."""
        import torch
        import torch.nn.functional as F  # noqa: N812 (PyTorch's own convention)

        s, m = self.bundle.image_size, self.bundle.mask_size
        n, h, w = logits_tiles.shape
        canvas = torch.full((n, 1, s, s), -MASK_PROMPT_LIMIT)
        canvas[:, 0, :h, :w] = torch.from_numpy(logits_tiles)
        return F.adaptive_avg_pool2d(canvas, (m, m))

    # -- per tile --------------------------------------------------------------------------------

    def refine_tile(self, embedding: torch.Tensor, coarse: np.ndarray, thresholds: Sequence[float]) -> np.ndarray:
        """(E, h, w) coarse probabilities -> (E, h, w) refined probabilities (mask: >= 0.5).

        Components are decoded in batches of ``decoder_batch``; per-component arrays live only for
        their batch, so memory stays a few tile-sized arrays per entity.
        """
        e, h, w = coarse.shape
        p = self.params
        best = np.full((e, h, w), -np.inf, np.float32)
        inside = np.zeros((e, h, w), bool)
        labelled: list[np.ndarray] = []
        jobs: list[tuple[int, Component]] = []
        for ent, (probs, tau) in enumerate(zip(coarse, thresholds)):
            with np.errstate(invalid="ignore"):
                mask = probs >= tau
            labels, comps, left = find_components(mask, p.min_area, p.max_components)
            self.stats.components_coarse += left
            labelled.append(labels)
            jobs.extend((ent, comp) for comp in comps)
        self.stats.components_refined += len(jobs)
        base: dict[int, np.ndarray] = {}  # coarse logits per entity, computed once
        for start in range(0, len(jobs), p.decoder_batch):
            chunk = jobs[start : start + p.decoder_batch]
            prompts, prompt_logits = [], []
            for ent, comp in chunk:
                labels = labelled[ent]
                fg = labels == comp.label
                prompts.append(make_prompt(ent, comp, fg, coarse[ent], p))
                if ent not in base:
                    base[ent] = coarse_mask_logits(coarse[ent], thresholds[ent])
                prompt_logits.append(np.where((labels > 0) & ~fg, np.float32(-MASK_PROMPT_LIMIT), base[ent]))
            masks_in = [labelled[ent] == comp.label for ent, comp in chunk]
            for prompt, sam_probs in self._decode_iterated(embedding, prompts, np.stack(prompt_logits), masks_in, h, w):
                rr, cc = prompt.region
                target = best[prompt.entity, rr, cc]
                np.maximum(target, sam_probs[rr, cc], out=target)
                inside[prompt.entity, rr, cc] = True
        return np.where(inside, best, calibrate(coarse, thresholds)).astype(np.float32)

    def _decode_iterated(
        self,
        embedding,
        prompts: list[ComponentPrompt],
        prompt_logits: np.ndarray,
        masks: list[np.ndarray],
        h: int,
        w: int,
    ) -> list[tuple[ComponentPrompt, np.ndarray]]:
        """Decode a batch of components up to ``iterations`` times, each pass prompted by the last
        answer (its low-res logits as mask prompt, points and box re-derived from its mask).

        A component whose mask changed little (IoU >= ``stop_iou`` with the previous one, the
        coarse mask for the first pass) is done early: on CPU each decoder pass costs about a tenth
        of the tile's encoder pass.
        """
        p = self.params
        prompts, masks = list(prompts), list(masks)
        answers: list[np.ndarray | None] = [None] * len(prompts)
        active = list(range(len(prompts)))
        mask_in = self._mask_prompt(prompt_logits)
        for it in range(p.iterations):
            low, full = self.decode(embedding, [prompts[i] for i in active], mask_in)
            logits = full[:, :h, :w].cpu().numpy()
            probs = (1.0 / (1.0 + np.exp(-np.clip(logits, -60, 60)))).astype(np.float32)
            again = []
            for j, i in enumerate(active):
                answers[i] = probs[j]
                if it + 1 == p.iterations:
                    continue
                rr, cc = prompts[i].region
                fg = np.zeros((h, w), bool)
                fg[rr, cc] = probs[j][rr, cc] >= 0.5
                if fg.any() and _iou(fg, masks[i]) < p.stop_iou:
                    prompts[i] = self._reprompt(prompts[i], fg, probs[j], h, w)
                    masks[i] = fg
                    again.append((i, j))
            if not again:
                break
            active = [i for i, _ in again]
            mask_in = low[[j for _, j in again]][:, None].clamp(-MASK_PROMPT_LIMIT, MASK_PROMPT_LIMIT).cpu()
        done = [a for a in answers if a is not None]
        assert len(done) == len(answers)  # the first pass (iterations >= 1) answers every component
        return list(zip(prompts, done))

    def _reprompt(self, prompt: ComponentPrompt, fg: np.ndarray, prob: np.ndarray, h: int, w: int) -> ComponentPrompt:
        """Prompts for the next pass from SAM's answer ``fg`` inside the component's region."""
        rr, cc = prompt.region
        rows, cols = ndimage.find_objects(fg.astype(np.int32))[0]
        comp = Component(prompt.component.label, rows, cols, int(fg.sum()))
        score = np.full((h, w), np.nan, np.float32)
        score[rr, cc] = prob[rr, cc]
        new = make_prompt(prompt.entity, comp, fg, score, self.params)
        # the accepted region never shrinks below the first pass's
        region = (
            slice(min(new.region[0].start, rr.start), max(new.region[0].stop, rr.stop)),
            slice(min(new.region[1].start, cc.start), max(new.region[1].stop, cc.stop)),
        )
        return ComponentPrompt(new.entity, comp, new.points, new.labels, new.box, region)

    def __call__(self, rgb: np.ndarray, coarse: Sequence[np.ndarray], thresholds: Sequence[float]) -> list[np.ndarray]:
        """Refine a batch of tiles (all needing SAM): one encoder pass each, then per component."""
        embeddings = self.embed(rgb)
        outs = []
        for i in range(len(rgb)):
            outs.append(self.refine_tile(embeddings[i : i + 1], coarse[i], thresholds))
            self.stats.tiles_sam += 1
        return outs


def _iou(a: np.ndarray, b: np.ndarray) -> float:
    union = np.count_nonzero(a | b)
    return np.count_nonzero(a & b) / union if union else 1.0


def calibrate(coarse: np.ndarray, thresholds: Sequence[float]) -> np.ndarray:
    """(E, h, w) coarse probabilities mapped so each entity's threshold lands on 0.5.

    Piecewise linear and monotone: [0, tau] -> [0, 0.5], [tau, 1] -> [0.5, 1]. Refined
    probabilities then share SAM's decision threshold, so the refined mask is simply
    ``refined_probs >= 0.5`` everywhere: one blended band per entity instead of two.
    """
    tau = np.asarray(thresholds, np.float32)[:, None, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        low = 0.5 * coarse / tau
        high = 0.5 + 0.5 * (coarse - tau) / (1.0 - tau)
        return np.where(coarse < tau, low, high).astype(np.float32)


@contextlib.contextmanager
def cancel_between_layers(bundle: SamBundle, progress: Progress | None) -> Iterator[None]:
    """Check for cancellation before each SAM encoder layer: a CPU tile takes ~15 s, a layer ~1 s."""
    if progress is None:
        yield
        return
    handles = [
        layer.register_forward_pre_hook(lambda *_: check_cancelled(progress))
        for layer in bundle.model.vision_encoder.layers
    ]
    try:
        yield
    finally:
        for h in handles:
            h.remove()


# --------------------------------------------------------------------------------------------
# The stage
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class RefineOptions:
    """Settings of the SAM refinement."""

    sam_model: str = DEFAULT_SAM
    overlap: int | None = None  # default: SAM input size // 16 (64 px of 1024: tiles are large)
    batch_size: int | None = None  # tiles per encoder call: 1 on CPU, 4 on GPU
    device: str = defaults.DEVICE
    precision: str = "auto"
    blend: str = "hann"
    params: RefineParams = RefineParams()
    bands: str | Sequence[int] | None = None
    assume_crs: str | None = None
    dask_scheduler: str | None = None


@dataclass(frozen=True)
class RefineResult:
    """What refinement wrote and how: the manifest records :meth:`to_json`."""

    refined_probs_path: Path
    refined_masks_path: Path
    gated_path: Path
    model: ModelRef
    device: str
    precision: str
    tile_size: int
    overlap: int
    tiles: int
    tiles_nodata: int
    stats: TileStats
    params: RefineParams
    timings: dict[str, float] = field(default_factory=dict)

    def to_json(self) -> dict:
        return {
            "refined_probs": str(self.refined_probs_path),
            "refined_masks": str(self.refined_masks_path),
            "gated": str(self.gated_path),
            "model": self.model.to_json(),
            "device": self.device,
            "precision": self.precision,
            "tile_size": self.tile_size,
            "overlap": self.overlap,
            "tiles": self.tiles,
            "tiles_nodata": self.tiles_nodata,
            **asdict(self.stats),
            "params": asdict(self.params),
            "timings_s": {k: round(v, 3) for k, v in self.timings.items()},
        }


def check_refine_options(options: RefineOptions) -> ModelRef:
    """Validate settings and find the model before any work starts (fail fast, offline)."""
    options.params.check()
    resolve_precision(options.precision, resolve_device(options.device))
    if options.overlap is not None and options.overlap < 0:
        raise InputError(f"--sam-overlap must be >= 0, got {options.overlap}")
    return resolve_model(options.sam_model, "sam")


def refine_sink(probs_w: RasterWriter, masks_w: RasterWriter, gated_w: RasterWriter):
    """Blended (E, n, W) refined probabilities -> probabilities, masks (>= 0.5) and P * M."""

    def sink(rows: np.ndarray, row_off: int) -> None:
        nodata = np.isnan(rows)
        with np.errstate(invalid="ignore"):
            mask = rows >= 0.5
        probs_w.write(rows, row_off)
        masks_w.write(np.where(nodata, MASK_NODATA, mask).astype(np.uint8), row_off)
        gated_w.write(np.where(nodata, np.float32(np.nan), rows * mask).astype(np.float32), row_off)

    return sink


def _check_probs(pds, grid, entities: Sequence[Entity], probs_path) -> None:
    same = (
        (pds.width, pds.height) == (grid.width, grid.height)
        and pds.crs == grid.crs
        and pds.transform.almost_equals(grid.transform)
    )
    if not same:
        raise RasterError(f"{probs_path} is not on the image's grid; run segmentation on this image first")
    if pds.count != len(entities):
        raise RasterError(f"{probs_path} has {pds.count} bands for {len(entities)} entities")
    names = [d or "" for d in pds.descriptions]
    if any(names) and [n.lower() for n in names] != [e.name.lower() for e in entities]:
        raise RasterError(f"{probs_path} holds entities {', '.join(names)}, not {', '.join(e.name for e in entities)}")


def refine_image(
    image: str | os.PathLike,
    probs_path: str | os.PathLike,
    entities: Sequence[Entity],
    out_dir: str | os.PathLike,
    options: RefineOptions = RefineOptions(),
    progress: Progress | None = None,
) -> RefineResult:
    """Refine ``probs.tif`` of ``image`` with SAM into ``out_dir`` (three GeoTIFFs, atomically)."""
    t_start = time.perf_counter()
    ents = validate_entities(entities)
    thresholds = tuple(threshold_of(e) for e in ents)
    options.params.check()
    out = prepare_out_dir(out_dir, image)
    with RasterSource(image, bands=options.bands, assume_crs=options.assume_crs) as src, open_raster(probs_path) as pds:
        grid = src.grid
        _check_probs(pds, grid, ents, probs_path)
        t0 = time.perf_counter()
        bundle = load_sam(options.sam_model, options.device, options.precision)
        t_load = time.perf_counter() - t0
        size = bundle.image_size
        overlap = size // 16 if options.overlap is None else int(options.overlap)
        check_tile_options(size, overlap, "SAM tile")
        tiles = TileGrid(grid.width, grid.height, size, overlap)
        refiner = SamRefiner(bundle, options.params, options.batch_size)
        device_label = describe_device(bundle.device)
        if progress is not None:
            progress.message(
                f"refine: SAM {bundle.ref.name} on {device_label} ({bundle.precision}), "
                f"{len(tiles)} tiles of {size} px (tiles without coarse masks are skipped)"
            )
        names = [e.name for e in ents]
        tags = {"OVERSEEC_STAGE": "refine", "OVERSEEC_ENTITIES": entities_tag(ents), "OVERSEEC_MODEL": bundle.ref.name}
        common: dict[str, Any] = dict(descriptions=names, tags=tags, inputs=[image, probs_path])
        t0 = time.perf_counter()
        with (
            RasterWriter(out / REFINED_PROBS_NAME, grid, len(ents), "float32", nodata=float("nan"), **common) as pw,
            RasterWriter(out / REFINED_MASKS_NAME, grid, len(ents), "uint8", nodata=MASK_NODATA, **common) as mw,
            RasterWriter(out / GATED_NAME, grid, len(ents), "float32", nodata=float("nan"), **common) as gw,
        ):
            blender = StreamingBlender(
                grid.width,
                grid.height,
                len(ents),
                refine_sink(pw, mw, gw),
                options.blend,
                flush_rows=pw.block_rows,
                capacity_rows=tiles.tile_shape[0] + pw.block_rows,
            )
            with contextlib.ExitStack() as stack:
                cluster = None
                if options.dask_scheduler:
                    from .distributed import Cluster

                    cluster = stack.enter_context(Cluster(options.dask_scheduler, options.device))
                    device_label = cluster.device_label
                else:
                    stack.enter_context(cancel_between_layers(bundle, progress))
                nodata = _drive(src, pds, tiles, refiner, cluster, thresholds, blender, options, progress)
        t_tiles = time.perf_counter() - t0
    return RefineResult(
        refined_probs_path=out / REFINED_PROBS_NAME,
        refined_masks_path=out / REFINED_MASKS_NAME,
        gated_path=out / GATED_NAME,
        model=bundle.ref,
        device=device_label,
        precision=bundle.precision,
        tile_size=size,
        overlap=overlap,
        tiles=len(tiles),
        tiles_nodata=nodata,
        stats=refiner.stats,
        params=options.params,
        timings={"load_model": t_load, "tiles": t_tiles, "total": time.perf_counter() - t_start},
    )


def _drive(src, pds, tiles: TileGrid, refiner: SamRefiner, cluster, thresholds, blender, options, progress) -> int:
    """Tiles in row-major groups of the encoder batch: read, skip or refine (here, or as one Dask
    task per group with several groups in flight), blend in order, flush finished rows."""
    from .distributed import ModelSpec, blend_in_order, lookahead, refine_task

    windows = tiles.windows()
    weight = blend_weights(tiles.tile_shape, options.blend)
    batch = refiner.state.size
    groups = [windows[k : k + batch] for k in range(0, len(windows), batch)]
    next_rows = [int(w.row_off) for w in windows[1:]] + [tiles.height]
    spec = ModelSpec(options.sam_model, options.device, options.precision, batch)
    counts = {"nodata": 0}

    def start(group: list[Window]) -> tuple[list, list[np.ndarray | None], list[int], Any]:
        chips = [src.read_chip(w) for w in group]
        coarse = [pds.read(window=w).astype(np.float32) for w in group]
        outputs: list[np.ndarray | None] = [None] * len(group)
        todo = []
        for i, (chip, probs) in enumerate(zip(chips, coarse)):
            if not chip.any_valid:
                counts["nodata"] += 1
            elif needs_sam(probs, thresholds, refiner.params):
                todo.append(i)
            else:
                outputs[i] = calibrate(probs, thresholds)
                refiner.stats.tiles_no_mask += 1
        pending = None
        if todo:
            rgb, maps = np.stack([chips[i].rgb for i in todo]), [coarse[i] for i in todo]
            pending = (
                cluster.submit(refine_task, spec, refiner.params, thresholds, rgb, maps)
                if cluster is not None
                else refiner(rgb, maps, thresholds)
            )
        return chips, outputs, todo, pending

    def results():
        for chips, outputs, todo, pending in lookahead(groups, start, cluster.depth if cluster else 1):
            if cluster is not None and pending is not None:
                pending, stats = pending.result()
                refiner.stats.add(stats)
            for i, o in zip(todo, pending or ()):
                outputs[i] = o
            yield chips, outputs

    blend_in_order(results(), blender, weight, next_rows, progress, "refine")
    return counts["nodata"]


__all__ = [
    "Component",
    "ComponentPrompt",
    "RefineOptions",
    "RefineParams",
    "RefineResult",
    "SamBundle",
    "SamRefiner",
    "TileStats",
    "check_refine_options",
    "chunk_global_attention",
    "coarse_mask_logits",
    "contiguous_decoder_tokens",
    "find_components",
    "load_sam",
    "make_prompt",
    "needs_sam",
    "negative_points",
    "positive_points",
    "refine_image",
    "sam_preprocess",
    "calibrate",
]
