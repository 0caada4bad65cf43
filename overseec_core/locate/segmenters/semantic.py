"""The ``semantic`` segmenter: a fixed-ontology model whose classes are mapped to the entities.

Where CLIPSeg is told what to look for, a semantic segmenter was trained on a fixed list of classes
(ADE20K's 150, or an aerial land-cover set such as Deepness's models). It runs as either

* a ``transformers`` checkpoint (a folder saved with ``save_pretrained``, or a hub id in the local
  cache) loaded with ``AutoModelForSemanticSegmentation``: SegFormer, UperNet, BEiT, DPT, ... -
  every model whose output is per-class ``logits`` (B, C, h, w). Mask2Former/OneFormer (mask
  queries, a different output and post-processing) are not supported; or
* an ``.onnx`` file run with onnxruntime (an optional dependency, imported when such a model is
  loaded): the CPU provider, or CUDA's when the device is CUDA and the installed onnxruntime has it.

**Metadata** (read by :mod:`.semantic_meta`). A JSON sidecar, ``<model>.overseec.json`` beside the
model folder or file (or ``overseec.json`` inside the folder), says what the classes are and how to
feed the model::

    {"classes": {"0": "background", "1": "road", ...},   # default: config.id2label / ONNX metadata
     "entities": {"road": ["road", "street"]},            # entity -> its classes (optional)
     "gsd_m": 0.3, "input_size": 512,                     # trained resolution (m/px), tile side (px)
     "mean": [0.485, 0.456, 0.406], "std": [...],         # normalisation of 0..1 pixel values
     "outputs": "logits"}                                 # or "probs" (the model applies softmax)

For a checkpoint every key is optional (``config.id2label``, the image processor's size, mean and
std are the defaults). For an ONNX model the Deepness metadata embedded in the file
(``class_names``, ``resolution`` in cm/px, ``tiles_size``, ``standardization_parameters``,
``model_type``) is read first, and the sidecar overrides it.

**Entities.** An entity's probability is the sum of the softmax probabilities of the classes mapped
to it: those the sidecar's ``entities`` lists for it, else the classes
:func:`overseec_core.interpret.matching.match_entity` finds for its name (equal names, synonyms such
as "street" for "road", modified names, broader classes), else for its text prompts. An entity no
class maps to fails at load, in one line listing the model's classes.

**Pixels.** Tiles are resized to the model's input size and normalised with torch (the same
pre-processing as CLIPSeg's, matching the library's PIL-based processor to within one grey level;
exactly when the tile already has the model's size); the model's logits are resampled back to the
tile with bilinear interpolation, as the library's ``post_process_semantic_segmentation`` does, and
only then turned into probabilities (softmax over the classes), so the result equals the library's
forward + upsampling. Tiling, blending, devices and out-of-memory back-off are the engine's.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from overseec_core.errors import InputError, ModelError
from overseec_core.interpret.matching import match_entity, normalise
from overseec_core.locate.clipseg import ImageNorm, preprocess
from overseec_core.locate.models import (
    WEIGHT_FILES,
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
    looks_like_hub_id,
    resolve_device,
    resolve_precision,
    run_with_backoff,
)
from overseec_core.locate.segmenters import SEGMENTERS
from overseec_core.locate.segmenters.semantic_meta import (
    OUTPUT_KINDS,
    SIDECAR_SUFFIX,
    SemanticMeta,
    deepness_meta,
    parse_meta,
    read_meta,
    sidecar_path,
)
from overseec_core.schema import Entity

if TYPE_CHECKING:  # torch is imported where a model runs, never at import time
    import torch

    from overseec_core.locate.segment import SegmentOptions

IMAGENET_MEAN, IMAGENET_STD = (0.485, 0.456, 0.406), (0.229, 0.224, 0.225)
#: Tile side for a model that names none (no processor size, no sidecar, dynamic ONNX input).
DEFAULT_INPUT_SIZE = 512
_PIL_RESAMPLE = {2: "bilinear", 3: "bicubic"}
KIND = "semantic"


# --------------------------------------------------------------------------------------------
# Entities -> classes
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class EntityClasses:
    """The classes one entity's probability sums, and how they were found."""

    entity: str
    classes: tuple[int, ...]
    labels: tuple[str, ...]
    rule: str  # "metadata", or a matching rule: name, synonym, modifier, broader (by a prompt: "prompt:<rule>")

    def describe(self) -> str:
        return f"{self.entity} <- {', '.join(self.labels)} ({self.rule})"


def _classes_line(classes: Sequence[str]) -> str:
    return ", ".join(f"{i}:{c}" for i, c in enumerate(classes))


def _explicit(entity: str, labels: Sequence[str], classes: Sequence[str], model: str) -> EntityClasses:
    """The classes the metadata lists for ``entity`` (by exact or normalised label)."""
    wanted: list[int] = []
    for label in labels:
        hits = [i for i, c in enumerate(classes) if c == label] or [
            i for i, c in enumerate(classes) if normalise(c) == normalise(label)
        ]
        if not hits:
            raise ModelError(
                f"semantic model {model}: the metadata maps entity {entity!r} to class {label!r}, which the "
                f"model lacks; its classes: {_classes_line(classes)}"
            )
        wanted += [i for i in hits if i not in wanted]
    return EntityClasses(entity, tuple(wanted), tuple(classes[i] for i in wanted), "metadata")


def map_entity(
    entity: Entity, classes: Sequence[str], explicit: Mapping[str, Sequence[str]], model: str, where: str = ""
) -> EntityClasses:
    """The classes ``entity`` stands for (see the module docstring), or a one-line InputError."""
    key = normalise(entity.name)
    if key in explicit:
        return _explicit(entity.name, explicit[key], classes, model)
    labels = list(dict.fromkeys(classes))  # a label may repeat; match each once
    for text, prefix in [(entity.name, "")] + [(p, "prompt:") for p in entity.text_prompts if p != entity.name]:
        match = match_entity(text, labels)
        if match.layers:
            idx = tuple(i for i, c in enumerate(classes) if c in match.layers)
            return EntityClasses(entity.name, idx, tuple(classes[i] for i in idx), prefix + match.rule)
    hint = f'; map it in {where} ("entities": {{"{entity.name}": ["CLASS", ...]}})' if where else ""
    raise InputError(
        f"semantic model {model} has no class for entity {entity.name!r}{hint}; its classes: {_classes_line(classes)}"
    )


def class_matrix(mapping: Sequence[EntityClasses], n_classes: int) -> np.ndarray:
    """(E, C) float32 with 1 where a class counts towards an entity."""
    out = np.zeros((len(mapping), n_classes), np.float32)
    for e, m in enumerate(mapping):
        out[e, list(m.classes)] = 1.0
    return out


# --------------------------------------------------------------------------------------------
# Probabilities
# --------------------------------------------------------------------------------------------


def _probabilities_last(out: torch.Tensor, size: tuple[int, int], outputs: str) -> torch.Tensor:
    """(B, C, h, w) model output -> (B, H, W, C) class probabilities on the tile.

    Bilinear resampling of the logits (half-pixel centres, as the library's post-processing),
    then softmax over the classes (or, for a model that outputs probabilities, a clip to [0, 1]).
    Channels-last, so that resampling, softmax and the class sums run over contiguous classes
    (a third faster on CPU than over planes)."""
    import torch
    import torch.nn.functional as F  # noqa: N812 (PyTorch's own convention)

    out = out.float().contiguous(memory_format=torch.channels_last)
    if tuple(out.shape[-2:]) != tuple(size):
        out = F.interpolate(out, size=size, mode="bilinear", align_corners=False)
    last = out.permute(0, 2, 3, 1)
    return last.softmax(dim=-1) if outputs == "logits" else last.clamp(0.0, 1.0)


def class_probabilities(out: torch.Tensor, size: tuple[int, int], outputs: str = "logits") -> torch.Tensor:
    """(B, C, h, w) model output -> (B, C, H, W) class probabilities on the tile (the library's
    forward + upsampling, then softmax)."""
    return _probabilities_last(out, size, outputs).permute(0, 3, 1, 2)


def entity_probabilities(
    out: torch.Tensor, matrix: torch.Tensor, size: tuple[int, int], outputs: str = "logits"
) -> torch.Tensor:
    """(B, C, h, w) model output -> (B, E, H, W): each entity's classes' probabilities summed
    (``matrix`` is :func:`class_matrix`'s (E, C)).

    One tile at a time: a tile's full-size class maps (C x H x W floats, 150 x 512 x 512 for
    ADE20K: 157 MB) are the largest transient of the run."""
    import torch

    tiles = [(_probabilities_last(out[i : i + 1], size, outputs) @ matrix.T) for i in range(out.shape[0])]
    return torch.cat(tiles).permute(0, 3, 1, 2).clamp_(0.0, 1.0)  # rounding may lift a sum a hair above 1


# --------------------------------------------------------------------------------------------
# Model resolution (a folder, a cached hub id, or an .onnx file)
# --------------------------------------------------------------------------------------------


def semantic_model_types() -> tuple[str, ...]:
    """The ``model_type`` values AutoModelForSemanticSegmentation loads (SegFormer, UperNet, ...)."""
    from transformers.models.auto.modeling_auto import MODEL_FOR_SEMANTIC_SEGMENTATION_MAPPING_NAMES

    return tuple(MODEL_FOR_SEMANTIC_SEGMENTATION_MAPPING_NAMES)


def _how_to_provide(name: str) -> str:
    return f"run `overseec models download {name}` on a machine with network, or pass --model /path/to/model-dir"


def _check_checkpoint(name: str, path: Path) -> str:
    """A local checkpoint folder's model_type, or a one-line ModelError saying what is wrong."""
    config = path / "config.json"
    if not config.is_file():
        raise ModelError(
            f"semantic model {name}: {path} has no config.json (give a save_pretrained folder or a .onnx file)"
        )
    try:
        model_type = str(json.loads(config.read_text(encoding="utf-8")).get("model_type", ""))
    except (OSError, ValueError) as exc:
        raise ModelError(f"semantic model {name}: unreadable config.json ({exc})") from None
    types = semantic_model_types()
    if model_type not in types:
        raise ModelError(
            f"semantic model {name}: model type {model_type or 'unknown'!r} is not a semantic segmenter "
            f"(expected one of {', '.join(types)})"
        )
    if not any((path / f).is_file() for f in WEIGHT_FILES):
        raise ModelError(f"semantic model {name}: {path} has no weights (model.safetensors or pytorch_model.bin)")
    return model_type


def _cached_snapshot(repo_id: str) -> Path | None:
    """The hub repo's snapshot in the local Hugging Face cache, or None (never the network)."""
    try:
        from huggingface_hub import snapshot_download
        from huggingface_hub.errors import LocalEntryNotFoundError
    except ImportError:  # pragma: no cover - huggingface_hub ships with transformers
        return None
    try:
        return Path(snapshot_download(repo_id, local_files_only=True))
    except (LocalEntryNotFoundError, OSError, ValueError):
        return None


def resolve_semantic(name: str) -> ModelRef:
    """An ``.onnx`` file, a checkpoint folder, or a hub id in the local cache -> ModelRef.

    Never downloads; a missing model is a one-line ModelError naming it and how to provide it.
    """
    text = str(name).strip()
    if not text:
        raise ModelError("empty semantic model name")
    path = Path(text).expanduser()
    if path.suffix.lower() == ".onnx":
        if not path.is_file():
            raise ModelError(f"semantic model {text}: no such ONNX file")
        return ModelRef(KIND, text, str(path.resolve()), "local", None, "onnx")
    if path.is_dir():
        return ModelRef(KIND, text, str(path.resolve()), "local", None, _check_checkpoint(text, path))
    if path.exists():
        raise ModelError(f"semantic model {text}: {path} is a file; give a .onnx file or a checkpoint folder")
    if not looks_like_hub_id(text):
        raise ModelError(f"semantic model {text}: no such folder or .onnx file, and not a hub id (org/name)")
    snapshot = _cached_snapshot(text)
    if snapshot is None:
        raise ModelError(
            f"semantic model {text} is not available offline (not in the Hugging Face cache); {_how_to_provide(text)}"
        )
    return ModelRef(KIND, text, str(snapshot), "hub-cache", snapshot.name, _check_checkpoint(text, snapshot))


# --------------------------------------------------------------------------------------------
# Runners: pixel values -> per-class output
# --------------------------------------------------------------------------------------------


@dataclass
class Network:
    """A loaded model reduced to what the segmenter needs from it (cached per process)."""

    forward: Callable[[Any], Any]  # (B, 3, S, S) float tensor on ``device`` -> (B, C, h, w) tensor
    classes: tuple[str, ...]  # the model's own labels (config.id2label, ONNX metadata), or ()
    meta: SemanticMeta  # what the model carries (processor values, ONNX metadata)
    device: Any  # torch.device the pixel values are made on
    precision: str
    label: str  # "segformer", "upernet", "onnx (CPUExecutionProvider)", ...
    runs_on: Any = None  # torch.device the model runs on, when not ``device`` (onnxruntime's CUDA)
    resample: str = "bilinear"  # the processor's resize filter
    fixed_size: int | None = None  # an ONNX input whose side is fixed
    fixed_batch: int | None = None


def _processor_meta(processor: Any, where: str) -> SemanticMeta:
    """Input size, mean and std of a checkpoint's image processor (none: nothing said)."""
    if processor is None:
        return SemanticMeta()
    if getattr(processor, "do_flip_channel_order", False):
        raise ModelError(f"semantic model {where}: its processor feeds BGR (MobileViT); it is not supported")
    size = getattr(processor, "size", None) or {}
    side = size.get("height") or size.get("shortest_edge")
    normalize = getattr(processor, "do_normalize", True)
    mean = tuple(float(v) for v in processor.image_mean) if normalize else (0.0, 0.0, 0.0)
    std = tuple(float(v) for v in processor.image_std) if normalize else (1.0, 1.0, 1.0)
    return SemanticMeta(input_size=int(side) if side else None, mean=mean, std=std)


def _resample(processor: Any) -> str:
    return _PIL_RESAMPLE.get(int(getattr(processor, "resample", 2) or 2), "bilinear")


def load_checkpoint(ref: ModelRef, device: Any, precision: str, compile: bool = False) -> Network:
    """A transformers checkpoint as a :class:`Network`: logits of the library's own forward."""
    import torch
    import transformers
    from transformers import AutoImageProcessor
    from transformers.models.auto.modeling_auto import MODEL_FOR_SEMANTIC_SEGMENTATION_MAPPING_NAMES as NAMES

    # the concrete class (SegformerForSemanticSegmentation, ...), not the Auto one: load_pretrained
    # reads its attention support from the class (sdpa where it has it)
    model = load_pretrained(getattr(transformers, NAMES[ref.model_type]), ref, device)
    channels_last_on_gpu(model, device)
    if compile:
        compile_module(model)
    processor = load_aux(AutoImageProcessor.from_pretrained, ref)
    id2label = model.config.id2label or {}
    classes = tuple(str(id2label[i]) for i in sorted(id2label))

    def forward(pixels: torch.Tensor) -> torch.Tensor:
        with torch.inference_mode(), autocast(device, precision):
            return model(pixel_values=pixels).logits

    meta = _processor_meta(processor, ref.name)
    return Network(forward, classes, meta, device, precision, ref.model_type, resample=_resample(processor))


def import_onnxruntime(model: str) -> Any:
    """onnxruntime, or a one-line ModelError saying how to install it."""
    try:
        import onnxruntime
    except ImportError:
        raise ModelError(
            f"semantic model {model} is an ONNX model, which needs onnxruntime: pip install onnxruntime "
            "(onnxruntime-gpu for CUDA)"
        ) from None
    return onnxruntime


def _onnx_providers(ort: Any, device: Any) -> list:
    """CUDA's execution provider first when the device is CUDA and onnxruntime has it, then the CPU's."""
    if device.type == "cuda" and "CUDAExecutionProvider" in ort.get_available_providers():
        return [("CUDAExecutionProvider", {"device_id": device.index or 0}), "CPUExecutionProvider"]
    return ["CPUExecutionProvider"]


def _onnx_session(ort: Any, ref: ModelRef, device: Any) -> Any:
    import torch

    options = ort.SessionOptions()
    options.intra_op_num_threads = torch.get_num_threads()  # the process's CPU share, as torch's
    options.log_severity_level = 3
    try:
        return ort.InferenceSession(ref.path, sess_options=options, providers=_onnx_providers(ort, device))
    except Exception as exc:  # onnxruntime raises its own exception types for bad graphs
        reason = " ".join(str(exc).split())[:200] or type(exc).__name__
        raise ModelError(f"semantic model {ref.name}: onnxruntime cannot load it: {reason}") from None


def _onnx_dims(session: Any, ref: ModelRef) -> tuple[str, int | None, int | None]:
    """The input's name, fixed batch and fixed square side (None where dynamic); checks the layout."""
    inputs, outputs = session.get_inputs(), session.get_outputs()
    if len(inputs) != 1 or len(inputs[0].shape) != 4 or inputs[0].type != "tensor(float)":
        raise ModelError(f"semantic model {ref.name}: expected one float input (batch, 3, height, width)")
    if len(outputs[0].shape) != 4:
        raise ModelError(f"semantic model {ref.name}: expected a (batch, classes, height, width) output")
    batch, channels, height, width = (d if isinstance(d, int) else None for d in inputs[0].shape)
    if channels not in (None, 3):
        raise ModelError(f"semantic model {ref.name}: the input has {channels} channels; RGB models only")
    if height != width:
        raise ModelError(f"semantic model {ref.name}: input {height}x{width}; square or dynamic inputs only")
    return inputs[0].name, batch, height


def check_onnx_precision(model: str, precision: str) -> None:
    """ONNX models run in the precision they were exported in (fp32 here)."""
    if precision not in ("auto", "fp32"):
        raise ModelError(f"semantic model {model}: ONNX models run as exported (fp32); use --precision auto or fp32")


def load_onnx(ref: ModelRef, device: Any, precision: str) -> Network:
    """An ONNX model as a :class:`Network` (fp32; pixel values and outputs on the CPU)."""
    import torch

    check_onnx_precision(ref.name, precision)
    ort = import_onnxruntime(ref.name)
    session = _onnx_session(ort, ref, device)
    name, batch, side = _onnx_dims(session, ref)
    meta = deepness_meta(session.get_modelmeta().custom_metadata_map, ref.path)
    # an ONNX model sees 0..1 pixel values unless its metadata says how to standardise them (Deepness's)
    meta = replace(meta, mean=meta.mean or (0.0, 0.0, 0.0), std=meta.std or (1.0, 1.0, 1.0))
    provider = session.get_providers()[0]

    def forward(pixels: torch.Tensor) -> torch.Tensor:
        x = pixels.float().cpu().numpy()
        step = batch or len(x)
        outs = [session.run(None, {name: x[i : i + step]})[0] for i in range(0, len(x), step)]
        return torch.from_numpy(np.concatenate(outs))

    cpu = torch.device("cpu")
    return Network(
        forward,
        meta.classes or (),
        replace(meta, classes=None),
        cpu,
        "fp32",
        f"onnx ({provider})",
        runs_on=device if provider == "CUDAExecutionProvider" else cpu,
        fixed_size=side,
        fixed_batch=batch,
    )


# --------------------------------------------------------------------------------------------
# The segmenter
# --------------------------------------------------------------------------------------------


class SemanticSegmenter:
    """Batch predictor for the tiling engine: (B, h, w, 3) uint8 -> (B, E, h, w) probabilities,
    each entity the sum of its classes' (see the module docstring). ``encoder_calls`` counts tiles
    through the model; ``gsd_m`` is the resolution the model was trained for (None: not said)."""

    def __init__(
        self,
        ref: ModelRef,
        net: Network,
        classes: Sequence[str],
        meta: SemanticMeta,
        mapping: Sequence[EntityClasses],
        model_size: int,
        batch_size: int,
    ) -> None:
        import torch

        self.ref = ref
        self.net = net
        self.classes = tuple(classes)
        self.meta = meta
        self.mapping = tuple(mapping)
        self.device = net.runs_on or net.device
        self.precision = net.precision
        self.model_size = int(model_size)
        self.state = BatchState(batch_size)
        self.encoder_calls = 0
        self.gsd_m = meta.gsd_m
        self.outputs = meta.outputs or "logits"
        self.norm = ImageNorm(
            self.model_size, meta.mean or IMAGENET_MEAN, meta.std or IMAGENET_STD, resample=net.resample
        )
        self.matrix = torch.from_numpy(class_matrix(self.mapping, len(self.classes))).to(net.device)

    def describe(self) -> str:
        """One line: the model, where it runs, and which classes make each entity."""
        where = describe_device(self.device)
        gsd = f", trained at {self.gsd_m:g} m/px" if self.gsd_m else ""
        return (
            f"semantic {self.ref.name} ({self.net.label}, {len(self.classes)} classes{gsd}) on {where}, "
            f"{self.precision}; {'; '.join(m.describe() for m in self.mapping)}"
        )

    def to_json(self) -> dict:
        """What the manifest may record: the model, its classes and the entity map."""
        return {
            "model": self.ref.to_json(),
            "classes": list(self.classes),
            "entities": {m.entity: {"classes": list(m.labels), "rule": m.rule} for m in self.mapping},
            "gsd_m": self.gsd_m,
            "metadata": self.meta.source,
            "outputs": self.outputs,
        }

    def outputs_for(self, rgb: np.ndarray) -> torch.Tensor:
        """The model's raw output (B, C, h, w) for a batch of tiles."""
        pixels = preprocess(rgb, self.norm, self.model_size, self.net.device)
        out = self.net.forward(pixels)
        if out.shape[1] != len(self.classes):
            raise ModelError(
                f"semantic model {self.ref.name} outputs {out.shape[1]} classes but its metadata names "
                f"{len(self.classes)} ({self.meta.source or 'config.json'})"
            )
        self.encoder_calls += len(rgb)
        return out

    def class_probabilities(self, rgb: np.ndarray) -> np.ndarray:
        """(B, C, h, w) per-class probabilities of a batch of tiles (the parity tests read them)."""
        import torch

        with torch.inference_mode():
            out = self.outputs_for(rgb)
            return class_probabilities(out, _side(rgb), self.outputs).cpu().numpy()

    def _chunk(self, rgb: np.ndarray, start: int, stop: int) -> np.ndarray:
        import torch

        with torch.inference_mode():
            out = self.outputs_for(rgb[start:stop])
            return entity_probabilities(out, self.matrix, _side(rgb), self.outputs).cpu().numpy()

    def __call__(self, rgb: np.ndarray, valid: np.ndarray) -> np.ndarray:
        """Per-entity probabilities of a batch of tiles, in micro-batches (halved on CUDA OOM)."""
        chunks = run_with_backoff(lambda a, z: self._chunk(rgb, a, z), len(rgb), self.state)
        return np.concatenate(chunks).astype(np.float32, copy=False)


def _side(rgb: np.ndarray) -> tuple[int, int]:
    """(height, width) of a batch of tiles."""
    return int(rgb.shape[1]), int(rgb.shape[2])


def _model_size(requested: int | None, meta: SemanticMeta, net: Network, options: Any, name: str) -> int:
    """The tile side the model sees: --model-size, else the metadata's, the ONNX input's, the
    processor's, the tile size; an ONNX model with a fixed side accepts only that."""
    fixed = net.fixed_size
    size = requested or fixed or meta.input_size or getattr(options, "tile_size", None) or DEFAULT_INPUT_SIZE
    if fixed is not None and size != fixed:
        raise InputError(f"--model-size {size}: semantic model {name} takes {fixed} px tiles only")
    if size < 16:
        raise InputError(f"--model-size {size} is too small for a semantic segmenter; use at least 16 px")
    return int(size)


def load(model: str | None, entities: Sequence[Entity], options: SegmentOptions) -> SemanticSegmenter:
    """Resolve (offline), load (cached per process) and map a semantic model to ``entities``.

    ``model`` None is the registry's default (a SegFormer checkpoint id). Fails fast, one line: a
    missing model, a missing onnxruntime for an ``.onnx`` file, bad metadata, an entity no class
    maps to.
    """
    name = str(model) if model else SEGMENTERS[KIND].default_model
    ref = resolve_semantic(name)
    device = resolve_device(getattr(options, "device", "auto"))
    requested = getattr(options, "precision", "auto")
    compile = bool(getattr(options, "compile", False))
    if ref.model_type == "onnx":
        check_onnx_precision(name, requested)  # before the cache: a cached session skips load_onnx
        net = cached_model((KIND, ref.path, str(device), "fp32", False), lambda: load_onnx(ref, device, requested))
    else:
        precision = resolve_precision(requested, device)
        net = cached_model(
            (KIND, ref.path, str(device), precision, compile), lambda: load_checkpoint(ref, device, precision, compile)
        )
    sidecar = sidecar_path(Path(ref.path)) or sidecar_path(Path(name).expanduser())
    meta = read_meta(sidecar).over(net.meta)
    classes = meta.classes or net.classes
    if not classes:
        raise ModelError(f'semantic model {name} names no classes; list them in {name}{SIDECAR_SUFFIX} ("classes")')
    where = str(sidecar) if sidecar else f"{name}{SIDECAR_SUFFIX}"
    mapping = [map_entity(e, classes, meta.entities, name, where) for e in entities]
    size = _model_size(getattr(options, "model_size", None), meta, net, options, name)
    batch = getattr(options, "batch_size", None) or default_batch_size(net.runs_on or device, 4, 16)
    return SemanticSegmenter(ref, net, classes, meta, mapping, size, batch)


__all__ = [
    "EntityClasses",
    "Network",
    "OUTPUT_KINDS",
    "SIDECAR_SUFFIX",
    "SemanticMeta",
    "SemanticSegmenter",
    "class_matrix",
    "class_probabilities",
    "deepness_meta",
    "entity_probabilities",
    "import_onnxruntime",
    "load",
    "load_checkpoint",
    "load_onnx",
    "map_entity",
    "parse_meta",
    "read_meta",
    "resolve_semantic",
    "semantic_model_types",
    "sidecar_path",
]
