"""Locate, coarse: text-prompted segmentation with CLIPSeg over overlapping tiles.

For each entity (name, linear|areal, text prompts) CLIPSeg predicts a probability map; tiles are
read in windows, predicted in batches and blended seam-free by the tiling engine
(:func:`overseec_core.tiling.stream_predict`) straight into ``probs.tif`` (one float32 band per
entity, NaN nodata) and ``masks.tif`` (uint8, 1 where the probability reaches the entity's
threshold, 255 nodata), both on the input's grid.

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

import json
import math
import os
import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # torch is imported where a model runs, never at import time
    import torch

from . import defaults, runfiles
from .errors import InputError, ModelError, OutputError
from .limits import check_pixels
from .models import (
    DEFAULT_CLIPSEG,
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
from .progress import Progress
from .raster import RasterSource, RasterWriter
from .schema import GEOMETRIES, Entity
from .tiling import TileGrid, stream_predict, writer_sink

#: The paper's binarisation thresholds by geometry.
DEFAULT_THRESHOLDS: dict[str, float] = defaults.THRESHOLDS
#: Nodata of masks.tif (0 and 1 are the mask values).
MASK_NODATA = 255
#: Smallest image side the segmenter accepts (CLIPSeg patches are 16 px).
MIN_IMAGE_SIDE = 16
#: Prompt templates selectable with --prompt-template (off by default until measured better).
PROMPT_TEMPLATES: dict[str, str] = {
    "none": "{}",
    "aerial": "aerial view of {}",
    "satellite": "satellite image of {}",
}
PROBS_NAME, MASKS_NAME = runfiles.PROBS, runfiles.MASKS


# --------------------------------------------------------------------------------------------
# Entities and thresholds
# --------------------------------------------------------------------------------------------


def threshold_of(entity: Entity) -> float:
    """The entity's binarisation threshold: its own, else its geometry's default."""
    if entity.threshold is not None:
        return float(entity.threshold)
    return DEFAULT_THRESHOLDS[entity.geometry]


def validate_entities(entities: Sequence[Entity]) -> tuple[Entity, ...]:
    """Non-empty, unique (case-insensitive) names, known geometries, thresholds in (0, 1)."""
    ents = tuple(entities)
    if not ents:
        raise InputError(
            "no entities to segment; pass --entity NAME:linear|areal "
            "(e.g. --entity road:linear) or --entities-json FILE"
        )
    seen: dict[str, str] = {}
    for e in ents:
        name = e.name.strip()
        if not name:
            raise InputError("an entity has an empty name")
        if name.lower() in seen:
            raise InputError(f"duplicate entity name {name!r}; each entity is one output band")
        seen[name.lower()] = name
        if e.geometry not in GEOMETRIES:
            raise InputError(f"entity {name!r}: geometry {e.geometry!r} is not one of {', '.join(GEOMETRIES)}")
        t = e.threshold
        if t is not None and not (isinstance(t, (int, float)) and 0.0 < float(t) < 1.0):
            raise InputError(f"entity {name!r}: threshold {t!r} must be between 0 and 1 (exclusive)")
        if any(not p.strip() for p in e.text_prompts):
            raise InputError(f"entity {name!r}: empty text prompt")
    return ents


def apply_thresholds(entities: Sequence[Entity], overrides: dict[str, float]) -> tuple[Entity, ...]:
    """Set per-entity thresholds from ``{name: value}``; unknown names are an InputError."""
    by_name = {e.name.lower(): e for e in entities}
    unknown = [n for n in overrides if n.lower() not in by_name]
    if unknown:
        raise InputError(
            f"--threshold for unknown entit{'y' if len(unknown) == 1 else 'ies'} "
            f"{', '.join(map(repr, unknown))}; entities are "
            f"{', '.join(e.name for e in entities)}"
        )
    lowered = {k.lower(): v for k, v in overrides.items()}
    return tuple(replace(e, threshold=lowered[e.name.lower()]) if e.name.lower() in lowered else e for e in entities)


def entity_prompts(entity: Entity, template: str = "{}") -> tuple[str, ...]:
    """The texts CLIPSeg sees for an entity: each prompt put into the template."""
    return tuple(template.replace("{}", p) if "{}" in template else f"{template} {p}" for p in entity.text_prompts)


def entities_tag(entities: Sequence[Entity]) -> str:
    """JSON stored in the output GeoTIFFs so later stages know names, geometries, thresholds."""
    return json.dumps(
        [
            {"name": e.name, "geometry": e.geometry, "threshold": threshold_of(e), "prompts": list(e.text_prompts)}
            for e in entities
        ]
    )


# --------------------------------------------------------------------------------------------
# Model bundle and shared-encoder predictor
# --------------------------------------------------------------------------------------------


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


def load_clipseg(name: str, device: str = "auto", precision: str = "auto") -> ClipSegBundle:
    """Resolve (offline), load and cache a CLIPSeg checkpoint on a device."""
    from transformers import AutoImageProcessor, AutoTokenizer, CLIPSegForImageSegmentation

    ref = resolve_model(name, "clipseg")
    dev = resolve_device(device)
    prec = resolve_precision(precision, dev)

    def build() -> ClipSegBundle:
        model = load_pretrained(CLIPSegForImageSegmentation, ref, dev)
        tokenizer = load_aux(AutoTokenizer.from_pretrained, ref)
        if tokenizer is None:
            raise ModelError(
                f"clipseg model {ref.name}: no tokenizer in {ref.path} (vocab.json/merges.txt or tokenizer.json)"
            )
        processor = load_aux(AutoImageProcessor.from_pretrained, ref)
        return ClipSegBundle(ref, model, tokenizer, _image_norm(processor, model.config), dev, prec)

    return cached_model(("clipseg", ref.path, str(dev), prec), build)


def preprocess(rgb: np.ndarray, norm: ImageNorm, size: int, device) -> torch.Tensor:
    """(B, h, w, 3) uint8 -> (B, 3, size, size) float normalised pixel values, with torch.

    Resizes with antialiasing (PIL's filter, one axis at a time) and rounds to grey levels as the
    library's uint8 processor does, then rescales and normalises.
    """
    import torch
    import torch.nn.functional as F  # noqa: N812 (PyTorch's own convention)

    x = torch.from_numpy(np.ascontiguousarray(rgb)).to(device).permute(0, 3, 1, 2).float()
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

    One vision-encoder pass per tile for all E entities (see the module docstring).
    ``encoder_calls`` counts tiles encoded, for tests and the manifest.
    """

    def __init__(
        self, bundle: ClipSegBundle, cond: torch.Tensor, model_size: int | None = None, batch_size: int | None = None
    ) -> None:
        self.bundle = bundle
        self.model = bundle.model
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
        import torch.nn.functional as F  # noqa: N812 (PyTorch's own convention)

        logits = self.logits(rgb[start:stop])
        n, e, s, _ = logits.shape
        h, w = rgb.shape[1:3]
        with torch.inference_mode():
            up = F.interpolate(logits.reshape(n * e, 1, s, s), size=(h, w), mode="bilinear", align_corners=False)
            return torch.sigmoid(up).reshape(n, e, h, w).cpu().numpy()

    def __call__(self, rgb: np.ndarray, valid: np.ndarray) -> np.ndarray:
        chunks = run_with_backoff(lambda a, z: self._chunk(rgb, a, z), len(rgb), self.state)
        return np.concatenate(chunks).astype(np.float32, copy=False)


# --------------------------------------------------------------------------------------------
# The stage
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class SegmentOptions:
    """Settings of the coarse segmentation; None means 'the sensible default for this input'."""

    clipseg_model: str = DEFAULT_CLIPSEG
    tile_size: int = defaults.TILE_SIZE
    overlap: int | None = None  # default: defaults.overlap_for(tile_size), an eighth of a tile
    model_size: int | None = None  # default: the checkpoint's input size (352)
    batch_size: int | None = None  # default: 4 on CPU, 16 on GPU
    device: str = defaults.DEVICE
    precision: str = "auto"
    blend: str = "hann"
    prompt_template: str = "{}"
    bands: str | Sequence[int] | None = None
    assume_crs: str | None = None
    dask_scheduler: str | None = None

    def resolved_overlap(self) -> int:
        return defaults.overlap_for(self.tile_size) if self.overlap is None else int(self.overlap)


@dataclass(frozen=True)
class SegmentResult:
    """What the stage wrote and how: the manifest records :meth:`to_json`."""

    probs_path: Path
    masks_path: Path
    entities: tuple[Entity, ...]
    thresholds: tuple[float, ...]
    model: ModelRef
    device: str
    precision: str
    tile_size: int
    overlap: int
    model_size: int
    batch_size: int
    tiles: int
    tiles_skipped: int
    encoder_calls: int
    timings: dict[str, float] = field(default_factory=dict)
    dask_scheduler: str | None = None

    def to_json(self) -> dict:
        return {
            "probs": str(self.probs_path),
            "masks": str(self.masks_path),
            "entities": [e.to_json() for e in self.entities],
            "thresholds": list(self.thresholds),
            "model": self.model.to_json(),
            "device": self.device,
            "precision": self.precision,
            "tile_size": self.tile_size,
            "overlap": self.overlap,
            "model_size": self.model_size,
            "batch_size": self.batch_size,
            "tiles": self.tiles,
            "tiles_skipped": self.tiles_skipped,
            "encoder_calls": self.encoder_calls,
            "dask_scheduler": self.dask_scheduler,
            "timings_s": {k: round(v, 3) for k, v in self.timings.items()},
        }


def check_tile_options(tile_size: int, overlap: int, what: str = "tile") -> None:
    """Tiles of at least 32 px, overlapping by at most half a tile (the reference's 50%)."""
    if tile_size < 32:
        raise InputError(f"--tile-size {tile_size} is too small; use at least 32 px")
    if not 0 <= overlap <= tile_size // 2:
        raise InputError(f"overlap {overlap} must be between 0 and half the {what} ({tile_size // 2} px)")


def prepare_out_dir(out_dir: str | os.PathLike, image: str | os.PathLike) -> Path:
    """Create the output folder (and parents); refuse the input's own path."""
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise InputError(f"--out {out} exists and is not a folder")
    if out.resolve() == Path(image).resolve():
        raise InputError(f"--out {out} is the input image")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"cannot create output folder {out} ({exc.strerror or exc})") from None
    return out


def mask_sink(probs_writer: RasterWriter, masks_writer: RasterWriter, thresholds: Sequence[float]):
    """A row sink writing blended probabilities and their thresholded masks in one pass."""
    probs_sink = writer_sink(probs_writer)
    tau = np.asarray(thresholds, np.float32)[:, None, None]

    def sink(rows: np.ndarray, row_off: int) -> None:
        with np.errstate(invalid="ignore"):
            masks = np.where(np.isnan(rows), MASK_NODATA, rows >= tau).astype(np.uint8)
        masks_writer.write(masks, row_off)
        probs_sink(rows, row_off)  # last: it may modify the blender's rows in place

    return sink


def segment_image(
    image: str | os.PathLike,
    entities: Sequence[Entity],
    out_dir: str | os.PathLike,
    options: SegmentOptions = SegmentOptions(),
    progress: Progress | None = None,
) -> SegmentResult:
    """Coarse per-entity probabilities and masks of ``image`` into ``out_dir``.

    Writes ``probs.tif`` and ``masks.tif`` atomically (nothing under the final names on error or
    cancellation). With ``options.dask_scheduler`` the tiles run on a dask.distributed cluster.
    """
    t_start = time.perf_counter()
    ents = validate_entities(entities)
    overlap = options.resolved_overlap()
    check_tile_options(options.tile_size, overlap)
    thresholds = tuple(threshold_of(e) for e in ents)
    out = prepare_out_dir(out_dir, image)
    with RasterSource(image, bands=options.bands, assume_crs=options.assume_crs) as src:
        grid = src.grid
        if min(grid.width, grid.height) < MIN_IMAGE_SIDE:
            raise InputError(
                f"{image} is {grid.width}x{grid.height} px; segmentation needs at "
                f"least {MIN_IMAGE_SIDE} px on each side"
            )
        check_pixels(grid.width, grid.height, image, "image")
        t0 = time.perf_counter()
        bundle = load_clipseg(options.clipseg_model, options.device, options.precision)
        t_load = time.perf_counter() - t0
        t0 = time.perf_counter()
        cond = text_embeddings(bundle, [entity_prompts(e, options.prompt_template) for e in ents])
        t_text = time.perf_counter() - t0
        predictor = ClipSegPredictor(bundle, cond, options.model_size, options.batch_size)
        tiles = TileGrid(grid.width, grid.height, options.tile_size, overlap)
        device_label = describe_device(bundle.device)
        if progress is not None:
            progress.message(
                f"segment: CLIPSeg {bundle.ref.name} on {device_label} "
                f"({bundle.precision}), {len(tiles)} tiles of {options.tile_size} px, "
                f"{len(ents)} entities"
            )
        names = [e.name for e in ents]
        tags = {"OVERSEEC_STAGE": "segment", "OVERSEEC_ENTITIES": entities_tag(ents), "OVERSEEC_MODEL": bundle.ref.name}
        t0 = time.perf_counter()
        with (
            RasterWriter(
                out / PROBS_NAME,
                grid,
                len(ents),
                "float32",
                nodata=float("nan"),
                descriptions=names,
                tags=tags,
                inputs=[image],
            ) as pw,
            RasterWriter(
                out / MASKS_NAME,
                grid,
                len(ents),
                "uint8",
                nodata=MASK_NODATA,
                descriptions=names,
                tags=tags,
                inputs=[image],
            ) as mw,
        ):
            sink = mask_sink(pw, mw, thresholds)
            if options.dask_scheduler:
                from .distributed import Cluster, ModelSpec, segment_on_dask

                spec = ModelSpec(
                    options.clipseg_model, options.device, options.precision, predictor.state.size, predictor.model_size
                )
                with Cluster(options.dask_scheduler, options.device) as cluster:
                    stats = segment_on_dask(
                        src,
                        cluster,
                        spec,
                        cond.cpu().numpy(),
                        sink,
                        tiles,
                        len(ents),
                        options.blend,
                        predictor.state.size,
                        pw.block_rows,
                        progress,
                    )
                    device_label = cluster.device_label
                encoder_calls = stats.tiles - stats.tiles_skipped
            else:
                stats = stream_predict(
                    src,
                    predictor,
                    sink,
                    tiles,
                    len(ents),
                    blend=options.blend,
                    batch_size=predictor.state.size,
                    flush_rows=pw.block_rows,
                    progress=progress,
                    stage="segment",
                )
                encoder_calls = predictor.encoder_calls
        t_tiles = time.perf_counter() - t0
    return SegmentResult(
        probs_path=out / PROBS_NAME,
        masks_path=out / MASKS_NAME,
        entities=ents,
        thresholds=thresholds,
        model=bundle.ref,
        device=device_label,
        precision=bundle.precision,
        tile_size=options.tile_size,
        overlap=overlap,
        model_size=predictor.model_size,
        batch_size=predictor.state.size,
        tiles=stats.tiles,
        tiles_skipped=stats.tiles_skipped,
        encoder_calls=encoder_calls,
        timings={
            "load_model": t_load,
            "text_embeddings": t_text,
            "tiles": t_tiles,
            "predict": stats.seconds_predicting,
            "read": stats.seconds_reading,
            "total": time.perf_counter() - t_start,
        },
        dask_scheduler=options.dask_scheduler,
    )


@dataclass(frozen=True)
class LocateResult:
    """The Locate stage as the pipeline runs it: coarse, refined (or None) and the manifest."""

    segment: SegmentResult
    refine: Any  # overseec_core.refine.RefineResult | None (refine imports this module)
    manifest: Path | None = None

    def to_json(self) -> dict:
        return {
            "segment": self.segment.to_json(),
            "refine": None if self.refine is None else self.refine.to_json(),
            "manifest": None if self.manifest is None else str(self.manifest),
        }


__all__ = [
    "ClipSegBundle",
    "LocateResult",
    "ClipSegPredictor",
    "DEFAULT_THRESHOLDS",
    "ImageNorm",
    "MASK_NODATA",
    "PROMPT_TEMPLATES",
    "SegmentOptions",
    "SegmentResult",
    "apply_thresholds",
    "entity_prompts",
    "load_clipseg",
    "preprocess",
    "segment_image",
    "text_embeddings",
    "threshold_of",
    "validate_entities",
]
