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

from overseec_core.errors import InputError
from overseec_core.locate.entities import entity_prompts
from overseec_core.locate.models import (
    DEFAULT_SAM,
    BatchState,
    ModelRef,
    autocast,
    default_batch_size,
    describe_device,
    load_aux,
    resolve_model,
    run_with_backoff,
)
from overseec_core.locate.sam_model import SamBundle, load_sam
from overseec_core.locate.segmenters.detectors import (
    BOX_THRESHOLDS,
    DEFAULT_DETECTOR,
    DETECTOR_KIND,
    MAX_BOXES,
    NMS_IOU,
    BoxSettings,
    Detector,
    DetectorBundle,
    EntityBoxes,
    GroundingDinoDetector,
    Owlv2Detector,
    box_iou,
    clip_boxes,
    load_detector,
    nms_cap,
    select_boxes,
)
from overseec_core.schema import Entity

#: Boxes per SAM mask-decoder call (each holds a copy of the tile's image embedding).
DECODER_BATCH = 32


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
