"""The detectors of the ``boxes+sam`` segmenter (:mod:`.boxes_sam`): OWLv2 and Grounding DINO
loaded offline (:func:`load_detector`), each giving per tile and entity the boxes it keeps --
score above the box threshold, clipped to the tile, greedy non-maximum suppression, at most
:data:`MAX_BOXES` by score (:func:`select_boxes`, :class:`BoxSettings`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # torch is imported where a model runs, never at import time
    import torch

from overseec_core.errors import InputError, ModelError
from overseec_core.locate.models import (
    ModelRef,
    attention_implementation,
    autocast,
    cached_model,
    compile_module,
    load_aux,
    load_pretrained,
    resolve_device,
    resolve_precision,
)

#: The detector used when no model is named (OWLv2 ViT-B/16, trained on an ensemble of datasets).
DEFAULT_DETECTOR = "google/owlv2-base-patch16-ensemble"
#: The model kind :func:`overseec_core.locate.models.resolve_model` knows detectors by.
DETECTOR_KIND = "detector"
#: Default box-score thresholds by detector family (``config.model_type``).
BOX_THRESHOLDS: dict[str, float] = {"owlv2": 0.1, "grounding-dino": 0.3}
#: Boxes kept per entity per tile, after non-maximum suppression.
MAX_BOXES = 16
#: Boxes overlapping a better one by more than this IoU are dropped (per entity).
NMS_IOU = 0.5


@dataclass(frozen=True)
class BoxSettings:
    """Which boxes are kept: threshold (None = the detector's default), NMS IoU and cap."""

    box_threshold: float | None = None
    max_boxes: int = MAX_BOXES
    nms_iou: float = NMS_IOU

    def __post_init__(self) -> None:
        t = self.box_threshold
        if t is not None and not 0.0 <= t < 1.0:
            raise InputError(f"box threshold {t} must be in [0, 1)")
        if self.max_boxes < 1:
            raise InputError(f"max boxes per entity {self.max_boxes} must be at least 1")
        if not 0.0 < self.nms_iou <= 1.0:
            raise InputError(f"NMS IoU {self.nms_iou} must be in (0, 1]")

    def threshold_for(self, family: str) -> float:
        """The box threshold for a detector family (``owlv2`` or ``grounding-dino``)."""
        return BOX_THRESHOLDS[family] if self.box_threshold is None else float(self.box_threshold)


@dataclass
class EntityBoxes:
    """One entity's kept boxes on one tile: (k, 4) xyxy in tile pixels and (k,) scores, best first."""

    boxes: np.ndarray
    scores: np.ndarray

    def __len__(self) -> int:
        return len(self.scores)


# --------------------------------------------------------------------------------------------
# Box selection (host side, no model)
# --------------------------------------------------------------------------------------------


def box_iou(box: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """IoU of one xyxy box with each of (n, 4) boxes (0 where both are empty)."""
    x0 = np.maximum(box[0], boxes[:, 0])
    y0 = np.maximum(box[1], boxes[:, 1])
    x1 = np.minimum(box[2], boxes[:, 2])
    y1 = np.minimum(box[3], boxes[:, 3])
    inter = np.clip(x1 - x0, 0, None) * np.clip(y1 - y0, 0, None)
    area = lambda b: np.clip(b[..., 2] - b[..., 0], 0, None) * np.clip(b[..., 3] - b[..., 1], 0, None)  # noqa: E731
    union = area(box) + area(boxes) - inter
    return np.where(union > 0, inter / np.where(union > 0, union, 1), 0.0)


def nms_cap(boxes: np.ndarray, scores: np.ndarray, iou: float, cap: int) -> EntityBoxes:
    """Greedy non-maximum suppression, best score first, stopping at ``cap`` boxes.

    Ties keep the earlier box (a stable sort), so the result is deterministic.
    """
    order = np.argsort(-scores, kind="stable")
    boxes, scores = boxes[order], scores[order]
    suppressed = np.zeros(len(scores), bool)
    keep: list[int] = []
    for i in range(len(scores)):
        if suppressed[i]:
            continue
        keep.append(i)
        if len(keep) == cap:
            break
        suppressed |= box_iou(boxes[i], boxes) > iou
    idx = np.asarray(keep, np.int64)
    return EntityBoxes(boxes[idx].astype(np.float32).reshape(-1, 4), scores[idx].astype(np.float32))


def clip_boxes(boxes: np.ndarray, height: int, width: int) -> np.ndarray:
    """xyxy boxes clipped to a ``height`` x ``width`` tile (detectors may reach past its edges)."""
    out = boxes.copy()
    out[:, 0::2] = np.clip(out[:, 0::2], 0, width)
    out[:, 1::2] = np.clip(out[:, 1::2], 0, height)
    return out


def select_boxes(
    boxes: np.ndarray, scores: np.ndarray, threshold: float, settings: BoxSettings, height: int, width: int
) -> EntityBoxes:
    """Boxes scoring above ``threshold``, clipped to the tile, NMS'd and capped (:class:`BoxSettings`)."""
    keep = scores > threshold
    return nms_cap(clip_boxes(boxes[keep], height, width), scores[keep], settings.nms_iou, settings.max_boxes)


def _corners(cxcywh: torch.Tensor, side: int) -> np.ndarray:
    """Normalised (cx, cy, w, h) -> xyxy pixels of a ``side`` square (the detectors' padded frame),
    as the library's ``center_to_corners_format`` and ``_scale_boxes`` compute them."""
    import torch

    cx, cy, w, h = cxcywh.float().unbind(-1)
    corners = torch.stack([cx - 0.5 * w, cy - 0.5 * h, cx + 0.5 * w, cy + 0.5 * h], dim=-1)
    return (corners * side).cpu().numpy()


# --------------------------------------------------------------------------------------------
# Detectors
# --------------------------------------------------------------------------------------------


@dataclass
class DetectorBundle:
    """A loaded detector checkpoint with its processor (tokenizer + image processor)."""

    ref: ModelRef
    model: Any  # Owlv2ForObjectDetection or GroundingDinoForObjectDetection
    processor: Any
    device: Any
    precision: str

    @property
    def family(self) -> str:
        """``owlv2`` or ``grounding-dino``."""
        return str(self.model.config.model_type)


def load_detector(
    ref: ModelRef, device: str = "auto", precision: str = "auto", compile: bool = False
) -> DetectorBundle:
    """Load (and cache) a resolved OWLv2 or Grounding DINO checkpoint and its processor, offline."""
    from transformers import AutoProcessor, GroundingDinoForObjectDetection, Owlv2ForObjectDetection

    classes = {"owlv2": Owlv2ForObjectDetection, "grounding-dino": GroundingDinoForObjectDetection}
    if ref.model_type not in classes:
        raise ModelError(f"detector {ref.name}: model type {ref.model_type!r} is not one of {', '.join(classes)}")
    dev = resolve_device(device)
    prec = resolve_precision(precision, dev)

    def build() -> DetectorBundle:
        # Grounding DINO has no SDPA path of its own, so the project's rule would force eager on its
        # BERT and Swin too; the library's default keeps SDPA there, and the two differ by several
        # logits on the same weights: None keeps the library's choice (what its docs run).
        attn = None if ref.model_type == "grounding-dino" else attention_implementation(classes[ref.model_type])
        model = load_pretrained(classes[ref.model_type], ref, dev, attn_implementation=attn)
        processor = load_aux(AutoProcessor.from_pretrained, ref)
        if processor is None or not hasattr(processor, "image_processor"):
            raise ModelError(
                f"detector {ref.name}: no processor in {ref.path} (tokenizer files and preprocessor_config.json)"
            )
        if compile:
            vision = model.owlv2.vision_model if ref.model_type == "owlv2" else model.model.backbone
            compile_module(vision)
        return DetectorBundle(ref, model, processor, dev, prec)

    return cached_model((DETECTOR_KIND, ref.path, str(dev), prec, bool(compile)), build)


def _query_table(prompts: Sequence[Sequence[str]]) -> tuple[list[str], list[np.ndarray]]:
    """All prompts as one flat query list, and for each entity the indices of its queries."""
    flat = [p for group in prompts for p in group]
    owners, start = [], 0
    for group in prompts:
        owners.append(np.arange(start, start + len(group)))
        start += len(group)
    return flat, owners


class Owlv2Detector:
    """OWLv2 boxes for all entities, the text queries embedded once per run.

    ``Owlv2ForObjectDetection.forward`` runs the text model with every image; here
    :meth:`raw` runs the library's own ``image_embedder``, ``class_predictor`` and
    ``box_predictor`` against query embeddings computed once, as the forward does
    (``text_projection`` of the pooled text output, L2-normalised).
    """

    family = "owlv2"

    def __init__(self, bundle: DetectorBundle, prompts: Sequence[Sequence[str]], model_size: int | None = None):
        import torch

        self.bundle = bundle
        cfg = bundle.model.config.vision_config
        self.native_size = int(cfg.image_size)
        self.size = int(model_size or self.native_size)
        if self.size % int(cfg.patch_size) or self.size < 2 * int(cfg.patch_size):
            raise InputError(
                f"--model-size {self.size} must be a multiple of the detector's patch size {cfg.patch_size} "
                f"and at least {2 * int(cfg.patch_size)}"
            )
        self.queries, self.owners = _query_table(prompts)
        enc = bundle.processor(text=[self.queries], return_tensors="pt")
        with torch.inference_mode():
            feats = bundle.model.owlv2.get_text_features(
                input_ids=enc["input_ids"].to(bundle.device), attention_mask=enc["attention_mask"].to(bundle.device)
            ).pooler_output
            self.query_embeds = feats / torch.linalg.norm(feats, ord=2, dim=-1, keepdim=True)
        self.query_mask = (enc["input_ids"][:, 0] > 0).to(bundle.device)

    def pixel_values(self, rgb: np.ndarray) -> torch.Tensor:
        """(B, h, w, 3) uint8 -> (B, 3, S, S): the library's OWLv2 image processor (pad, resize)."""
        proc = self.bundle.processor.image_processor
        size = {"height": self.size, "width": self.size}
        return proc(images=list(rgb), size=size, return_tensors="pt")["pixel_values"].to(self.bundle.device)

    def raw(self, pixel_values: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """(B, patches, queries) class logits and (B, patches, 4) normalised cxcywh boxes."""
        import torch

        model, interpolate = self.bundle.model, self.size != self.native_size
        with torch.inference_mode(), autocast(self.bundle.device, self.bundle.precision):
            feature_map = model.image_embedder(pixel_values=pixel_values, interpolate_pos_encoding=interpolate)[0]
            b, h, w, d = feature_map.shape
            feats = feature_map.reshape(b, h * w, d)
            queries = self.query_embeds[None].expand(b, -1, -1)
            logits, _ = model.class_predictor(feats, queries, self.query_mask[None].expand(b, -1))
            boxes = model.box_predictor(feats, feature_map, interpolate)
        return logits.float(), boxes.float()

    def detect(self, rgb: np.ndarray, settings: BoxSettings) -> list[list[EntityBoxes]]:
        """Per tile, per entity: the kept boxes (see :func:`select_boxes`)."""
        import torch

        logits, boxes = self.raw(self.pixel_values(rgb))
        h, w = rgb.shape[1:3]
        threshold = settings.threshold_for(self.family)
        out = []
        for t in range(len(rgb)):
            corners = _corners(boxes[t], max(h, w))  # OWLv2 pads to a square, bottom/right
            per_entity = []
            for idx in self.owners:
                scores = torch.sigmoid(logits[t][:, idx].max(dim=-1).values).cpu().numpy()
                per_entity.append(select_boxes(corners, scores, threshold, settings, h, w))
            out.append(per_entity)
        return out


class GroundingDinoDetector:
    """Grounding DINO boxes: all prompts in one caption (``"a. b. c."``), tokenised once.

    A box's score for an entity is the best sigmoid score over the tokens of the entity's phrases
    (the library's post-processing takes the best over all tokens, then names the phrases whose
    tokens pass the text threshold; here each entity is scored on its own tokens, so one box can
    serve several entities). Text and image are fused inside the model, so the text model runs
    with every batch.
    """

    family = "grounding-dino"

    def __init__(self, bundle: DetectorBundle, prompts: Sequence[Sequence[str]], model_size: int | None = None):
        self.bundle = bundle
        if model_size is not None:
            raise InputError("--model-size is not supported with a Grounding DINO detector (it keeps aspect ratio)")
        self.size = int(bundle.processor.image_processor.size.get("shortest_edge", 800))
        self.queries, self.owners = _query_table(prompts)
        caption = " ".join(f"{q.strip().rstrip('.').lower()}." for q in self.queries)
        enc = bundle.processor.tokenizer([caption], return_tensors="pt")
        self.text = {k: v.to(bundle.device) for k, v in enc.items()}
        self.token_owner = self._token_owners(enc["input_ids"][0].tolist())

    def _token_owners(self, ids: list[int]) -> list[np.ndarray]:
        """For each entity, the caption token positions of its phrases (tokenised one by one)."""
        tok = self.bundle.processor.tokenizer
        positions, start = [], 1  # after [CLS]
        for q in self.queries:
            n = len(tok(q.strip().rstrip(".").lower(), add_special_tokens=False)["input_ids"])
            positions.append(np.arange(start, start + n))
            start += n + 1  # the phrase and its "."
        if start > len(ids):
            raise InputError("the prompts are too long for Grounding DINO's caption; use fewer or shorter prompts")
        return [np.concatenate([positions[i] for i in idx]) for idx in self.owners]

    def raw(self, rgb: np.ndarray) -> tuple[torch.Tensor, torch.Tensor]:
        """(B, queries, tokens) logits and (B, queries, 4) normalised cxcywh boxes of the library forward."""
        import torch

        b = self.bundle
        inputs = b.processor.image_processor(images=list(rgb), return_tensors="pt")
        batch = {k: v.expand(len(rgb), -1) for k, v in self.text.items()}
        with torch.inference_mode(), autocast(b.device, b.precision):
            out = b.model(
                pixel_values=inputs["pixel_values"].to(b.device), pixel_mask=inputs["pixel_mask"].to(b.device), **batch
            )
        return out.logits.float(), out.pred_boxes.float()

    def detect(self, rgb: np.ndarray, settings: BoxSettings) -> list[list[EntityBoxes]]:
        """Per tile, per entity: the kept boxes (see :func:`select_boxes`)."""
        import torch

        logits, boxes = self.raw(rgb)
        h, w = rgb.shape[1:3]
        threshold = settings.threshold_for(self.family)
        out = []
        for t in range(len(rgb)):
            corners = _corners(boxes[t], 1) * np.array([w, h, w, h], np.float32)  # relative to the image
            per_entity = []
            for tokens in self.token_owner:
                scores = torch.sigmoid(logits[t][:, tokens].max(dim=-1).values).cpu().numpy()
                per_entity.append(select_boxes(corners, scores, threshold, settings, h, w))
            out.append(per_entity)
        return out


Detector = Owlv2Detector | GroundingDinoDetector
