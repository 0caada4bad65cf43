"""The ``boxes+sam`` segmenter: text-prompted boxes refined by SAM (the LangSAM recipe).

For object-like entities (buildings, baseball fields, towers) a text-to-box detector finds each
entity's instances on a tile, SAM turns each box into a mask, and the entity's probability on the
tile is the max over its boxes of SAM's mask probability times the box score::

    P_e(x) = max_{b in boxes(e)} score(b) * sigmoid(SAM(tile, b))(x)      (0 where no box)

* **Detector**: OWLv2 (``Owlv2ForObjectDetection``, the default ``google/owlv2-base-patch16-ensemble``)
  or Grounding DINO (``GroundingDinoForObjectDetection``), chosen by the checkpoint's
  ``config.model_type``. Every prompt of every entity is one text query; an entity's score of a box
  is the best of its queries' scores, so one box may serve two entities.
* **Boxes kept** per entity per tile: score above the box threshold (OWLv2 0.1, the library docs'
  value for its sigmoid scores; Grounding DINO 0.3, LangSAM's), then greedy non-maximum
  suppression at IoU 0.5 (OWLv2 predicts one box per image patch, so an object has dozens of
  near-copies and the cap would otherwise be spent on one object), then at most 16 by score.
  ``SegmentOptions.box_threshold`` / ``max_boxes`` override them where those fields exist.
* **Refiner**: SAM through :func:`overseec_core.locate.sam_model.load_sam` (``SegmentOptions.sam_model``
  where that field exists, else :data:`overseec_core.locate.models.DEFAULT_SAM`). Its image
  embedding is computed once per tile (batched over the tiles that have boxes) and all boxes of a
  tile are decoded in one mask-decoder call (chunks of :data:`DECODER_BATCH`).

Work is shared rather than repeated: OWLv2's text queries are embedded once per run (the library's
``forward`` re-encodes them with every image), and its vision encoder, box and class heads run
once per tile for all entities. Grounding DINO fuses text and image inside its encoder, so its
text goes through the model with each batch; it is tokenised once. Tiles with no valid pixel skip
both models, tiles with no box skip SAM; invalid pixels are 0.

Pre-processing and mask post-processing are the library's own image processors (OWLv2's pad to
square and resize, SAM's resize of the longest side and pad; ``post_process_masks``), so the boxes
and masks equal the library's pipeline (tested to 1e-5); they run on the host, per tile.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # torch is imported where a model runs, never at import time
    import torch

from overseec_core.errors import InputError, ModelError
from overseec_core.locate.entities import entity_prompts
from overseec_core.locate.models import (
    DEFAULT_SAM,
    BatchState,
    ModelRef,
    attention_implementation,
    autocast,
    cached_model,
    compile_module,
    default_batch_size,
    describe_device,
    load_aux,
    load_pretrained,
    resolve_device,
    resolve_model,
    resolve_precision,
    run_with_backoff,
)
from overseec_core.locate.sam_model import SamBundle, load_sam
from overseec_core.schema import Entity

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
#: Boxes per SAM mask-decoder call (each holds a copy of the tile's image embedding).
DECODER_BATCH = 32


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


# --------------------------------------------------------------------------------------------
# SAM: boxes -> masks
# --------------------------------------------------------------------------------------------


def sam_image_processor(bundle: SamBundle) -> Any:
    """The checkpoint's SAM image processor, set to the model's input size (resize longest side, pad)."""
    from transformers import AutoImageProcessor, SamImageProcessorPil

    proc = load_aux(AutoImageProcessor.from_pretrained, bundle.ref)
    if proc is None:
        proc = SamImageProcessorPil(image_mean=list(bundle.mean), image_std=list(bundle.std))
    s, m = bundle.image_size, bundle.mask_size
    proc.size = {"longest_edge": s}
    proc.pad_size = {"height": s, "width": s}
    proc.mask_size, proc.mask_pad_size = {"longest_edge": m}, {"height": m, "width": m}
    return proc


@dataclass
class SamBoxMasks:
    """SAM's mask for each box of a tile: one image embedding per tile, the boxes decoded together."""

    bundle: SamBundle
    processor: Any
    decoder_batch: int = DECODER_BATCH
    decoder_calls: int = 0

    def embed(self, rgb: np.ndarray) -> tuple[torch.Tensor, list[tuple[int, int]]]:
        """(B, C, g, g) image embeddings of tiles and each tile's resized size (h', w') in SAM's frame."""
        import torch

        b = self.bundle
        inputs = self.processor(images=list(rgb), return_tensors="pt")
        with torch.inference_mode(), autocast(b.device, b.precision):
            emb = b.model.get_image_embeddings(inputs["pixel_values"].to(b.device))
        return emb, [(int(rh), int(rw)) for rh, rw in inputs["reshaped_input_sizes"].tolist()]

    def probabilities(self, embedding: torch.Tensor, boxes: np.ndarray, tile: tuple[int, int], resized) -> np.ndarray:
        """(k, h, w) float32 mask probabilities of ``boxes`` (xyxy tile pixels) on one tile.

        ``embedding`` is the tile's (1, C, g, g); boxes are scaled to SAM's frame as SamProcessor
        does, decoded ``decoder_batch`` at a time with ``multimask_output=False``, and brought back
        to the tile by the processor's ``post_process_masks`` (up to the padded input, crop, down).
        """
        import torch

        b = self.bundle
        (h, w), (rh, rw) = tile, resized
        scaled = boxes.astype(np.float64) * np.array([rw / w, rh / h, rw / w, rh / h])
        out = np.empty((len(boxes), h, w), np.float32)
        # float64 boxes, as SamProcessor gives them: the prompt encoder normalises them before its
        # float32 Fourier features, and rounding the boxes first moves mask logits by ~1e-4
        box_dtype = torch.float32 if b.device.type == "mps" else torch.float64
        for a in range(0, len(boxes), self.decoder_batch):
            z = min(len(boxes), a + self.decoder_batch)
            prompt = torch.as_tensor(scaled[a:z], dtype=box_dtype, device=b.device)[None]
            with torch.inference_mode(), autocast(b.device, b.precision):
                low = b.model(image_embeddings=embedding, input_boxes=prompt, multimask_output=False).pred_masks
            self.decoder_calls += 1
            with torch.inference_mode():
                up = self.processor.post_process_masks([low[0].float()], [tile], [resized], binarize=False)[0]
                out[a:z] = torch.sigmoid(up[:, 0]).cpu().numpy()
        return out


def combine(masks: np.ndarray, scores: np.ndarray, owners: np.ndarray, entities: int) -> np.ndarray:
    """(E, h, w): per entity the max over its boxes of score x mask probability (0 without boxes)."""
    out = np.zeros((entities, *masks.shape[1:]), np.float32)
    for k in range(len(scores)):
        np.maximum(out[owners[k]], masks[k] * scores[k], out=out[owners[k]])
    return out


# --------------------------------------------------------------------------------------------
# The segmenter
# --------------------------------------------------------------------------------------------


@dataclass
class BoxesSamSegmenter:
    """The ``boxes+sam`` LoadedSegmenter: (B, h, w, 3) uint8 + validity -> (B, E, h, w) float32.

    ``encoder_calls`` counts tiles the detector encoded, ``sam_tiles`` tiles SAM encoded (those
    with at least one box) and ``boxes`` the boxes decoded.
    """

    detector: Detector
    sam: SamBoxMasks
    entities: int
    settings: BoxSettings
    state: BatchState
    encoder_calls: int = 0
    sam_tiles: int = 0
    boxes: int = 0
    last_detections: list[list[EntityBoxes]] = field(default_factory=list, repr=False)

    @property
    def ref(self) -> ModelRef:
        """The detector checkpoint (what ``--model`` names); SAM's is ``sam.bundle.ref``."""
        return self.detector.bundle.ref

    @property
    def device(self) -> Any:
        """The torch device both models run on."""
        return self.detector.bundle.device

    @property
    def precision(self) -> str:
        """fp32, bf16 or fp16."""
        return self.detector.bundle.precision

    @property
    def model_size(self) -> int:
        """Pixels per tile side the detector sees (OWLv2: its square input; Grounding DINO: shortest edge)."""
        return self.detector.size

    def describe(self) -> str:
        """One line: detector, thresholds, SAM, device."""
        d = self.detector
        name = "OWLv2" if d.family == "owlv2" else "Grounding DINO"
        return (
            f"boxes+sam: {name} {self.ref.name} boxes (score > {self.settings.threshold_for(d.family):g}, "
            f"at most {self.settings.max_boxes} per entity per tile) refined by SAM {self.sam.bundle.ref.name} "
            f"on {describe_device(self.device)} ({self.precision})"
        )

    def detect(self, rgb: np.ndarray) -> list[list[EntityBoxes]]:
        """Per tile, per entity: the kept boxes (the detector alone, no SAM)."""
        self.encoder_calls += len(rgb)
        return self.detector.detect(rgb, self.settings)

    def tile_probabilities(self, embedding: Any, dets: list[EntityBoxes], tile, resized) -> np.ndarray:
        """(E, h, w) for one tile with boxes: all its boxes decoded together, then combined."""
        boxes = np.concatenate([d.boxes for d in dets])
        scores = np.concatenate([d.scores for d in dets])
        owners = np.concatenate([np.full(len(d), e) for e, d in enumerate(dets)]).astype(np.int64)
        self.boxes += len(boxes)
        return combine(self.sam.probabilities(embedding, boxes, tile, resized), scores, owners, self.entities)

    def _chunk(self, rgb: np.ndarray, valid: np.ndarray) -> np.ndarray:
        n, h, w = rgb.shape[:3]
        out = np.zeros((n, self.entities, h, w), np.float32)
        live = np.flatnonzero(valid.reshape(n, -1).any(axis=1))
        if not len(live):
            return out
        dets = self.detect(rgb[live])
        self.last_detections = dets
        boxed = [j for j, d in enumerate(dets) if any(len(e) for e in d)]
        if boxed:
            emb, resized = self.sam.embed(rgb[live[boxed]])
            self.sam_tiles += len(boxed)
            for k, j in enumerate(boxed):
                out[live[j]] = self.tile_probabilities(emb[k : k + 1], dets[j], (h, w), resized[k])
        out *= valid[:, None]
        return out

    def __call__(self, rgb: np.ndarray, valid: np.ndarray) -> np.ndarray:
        """Per-entity probabilities of a batch of tiles, in [0, 1]; 0 on invalid pixels."""
        chunks = run_with_backoff(lambda a, z: self._chunk(rgb[a:z], valid[a:z]), len(rgb), self.state)
        return np.concatenate(chunks).astype(np.float32, copy=False)


def settings_from(options: Any) -> BoxSettings:
    """:class:`BoxSettings` from the options' ``box_threshold`` / ``max_boxes`` fields, where present."""
    max_boxes = getattr(options, "max_boxes", None)
    return BoxSettings(getattr(options, "box_threshold", None), MAX_BOXES if max_boxes is None else int(max_boxes))


def load(model: str | None, entities: Sequence[Entity], options: Any) -> BoxesSamSegmenter:
    """The ``boxes+sam`` backend: ``model`` names the detector (None = :data:`DEFAULT_DETECTOR`).

    Both checkpoints are resolved before either is loaded, so a missing one fails at once with a
    one-line ModelError naming it. ``options`` is a ``SegmentOptions`` (device, precision,
    batch_size, model_size, prompt_template, compile; ``sam_model``, ``box_threshold`` and
    ``max_boxes`` where it has them).
    """
    ents = tuple(entities)
    if not ents:
        raise InputError("boxes+sam needs at least one entity")
    settings = settings_from(options)
    det_ref = resolve_model(model or DEFAULT_DETECTOR, DETECTOR_KIND)
    sam_name = getattr(options, "sam_model", None) or DEFAULT_SAM
    resolve_model(sam_name, "sam")
    device, precision = getattr(options, "device", "auto"), getattr(options, "precision", "auto")
    compile = bool(getattr(options, "compile", False))
    bundle = load_detector(det_ref, device, precision, compile)
    sam = load_sam(sam_name, device, precision, compile)
    prompts = [entity_prompts(e, getattr(options, "prompt_template", "{}")) for e in ents]
    model_size = getattr(options, "model_size", None)
    detector: Detector = (
        Owlv2Detector(bundle, prompts, model_size)
        if bundle.family == "owlv2"
        else GroundingDinoDetector(bundle, prompts, model_size)
    )
    batch = getattr(options, "batch_size", None) or default_batch_size(bundle.device, 2, 8)
    return BoxesSamSegmenter(
        detector, SamBoxMasks(sam, sam_image_processor(sam)), len(ents), settings, BatchState(batch)
    )


__all__ = [
    "BOX_THRESHOLDS",
    "BoxSettings",
    "BoxesSamSegmenter",
    "DECODER_BATCH",
    "DEFAULT_DETECTOR",
    "DETECTOR_KIND",
    "DetectorBundle",
    "EntityBoxes",
    "GroundingDinoDetector",
    "MAX_BOXES",
    "NMS_IOU",
    "Owlv2Detector",
    "SamBoxMasks",
    "box_iou",
    "clip_boxes",
    "combine",
    "load",
    "load_detector",
    "nms_cap",
    "sam_image_processor",
    "select_boxes",
]
