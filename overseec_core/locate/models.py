"""Model resolution, loading, devices and batch back-off for the Locate stage (its segmenters, SAM).

A model is named by a Hugging Face hub id (``CIDAS/clipseg-rd64-refined``) or a local directory
saved with ``save_pretrained``. Resolution never touches the network: a hub id is looked up in the
local Hugging Face cache only (``local_files_only``), and a missing model fails at once with a
one-line :class:`ModelError` that says how to provide it (``overseec models download NAME`` on a
machine with network, or ``--model /path/to/dir``). A segmenter backend names the ``model_type``
values its checkpoints may declare (``resolve_model(name, kind, model_types)``), so a new backend
needs no entry here. Only :func:`download_model` (the
``overseec models download`` command) goes online, with short timeouts so it cannot hang.

Devices are chosen once per run (``auto`` picks CUDA, then MPS, then CPU); on CUDA inference runs
under fp16/bf16 autocast, and :func:`run_with_backoff` halves the batch on CUDA out-of-memory.
``cached_model`` keeps one loaded model per (kind, path, device, precision) in the process, so a
Dask worker loads each model once however many tile tasks it runs.

torch and transformers are imported inside functions: importing this module stays cheap for
``overseec --help`` and the QGIS side.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from overseec_core import defaults
from overseec_core.errors import ModelError
from overseec_core.locate.segmenters import SEGMENTERS

#: Default checkpoints (the OVerSeeC paper's choices); the clipseg segmenter's registry entry owns its id.
DEFAULT_CLIPSEG = SEGMENTERS["clipseg"].default_model
DEFAULT_SAM = "facebook/sam-vit-base"
#: The other refiners' defaults (locate.refiners' table names them by these).
DEFAULT_SAM_HQ = "syscv-community/sam-hq-vit-base"
DEFAULT_SAM2 = "facebook/sam2.1-hiera-tiny"

#: Model families this stage can run, with the ``model_type`` their config.json must declare.
MODEL_TYPES: dict[str, tuple[str, ...]] = {
    "clipseg": ("clipseg",),
    "sam": ("sam",),
    "sam-hq": ("sam_hq",),
    "sam2": ("sam2",),
    "detector": ("owlv2", "grounding-dino"),
}

#: Checkpoints `overseec models list` shows, each refiner's default among them (any other checkpoint
#: of a known kind works by id or path).
KNOWN_MODELS: tuple[tuple[str, str, str], ...] = (
    ("clipseg", DEFAULT_CLIPSEG, "CLIPSeg ViT-B/16, reduce dim 64, refined decoder (default)"),
    ("clipseg", "CIDAS/clipseg-rd64", "CLIPSeg ViT-B/16, reduce dim 64"),
    ("clipseg", "CIDAS/clipseg-rd16", "CLIPSeg ViT-B/16, reduce dim 16 (smaller decoder)"),
    ("sam", DEFAULT_SAM, "SAM ViT-B (default)"),
    ("sam", "facebook/sam-vit-large", "SAM ViT-L"),
    ("sam", "facebook/sam-vit-huge", "SAM ViT-H"),
    ("sam", "Zigeng/SlimSAM-uniform-77", "SlimSAM, 77% pruned ViT-B (fast on CPU)"),
    ("sam", "Zigeng/SlimSAM-uniform-50", "SlimSAM, 50% pruned ViT-B"),
    ("sam-hq", DEFAULT_SAM_HQ, "SAM-HQ ViT-B (default of --refiner sam-hq)"),
    ("sam2", DEFAULT_SAM2, "SAM 2.1 Hiera-T (default of --refiner sam2)"),
)

WEIGHT_FILES = (
    "model.safetensors",
    "model.safetensors.index.json",
    "pytorch_model.bin",
    "pytorch_model.bin.index.json",
)
#: Files `overseec models download` fetches (weights are added by kind of checkpoint).
_DOWNLOAD_PATTERNS = ["*.json", "*.txt", "*.model"]
_HUB_ID = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*/[A-Za-z0-9][A-Za-z0-9._-]*$")
DEVICE_CHOICES, PRECISIONS = defaults.DEVICE_CHOICES, defaults.PRECISIONS


# --------------------------------------------------------------------------------------------
# Resolution: name -> local directory, without network
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ModelRef:
    """A model resolved to a local directory: what to load and what the manifest records."""

    kind: str  # "clipseg" or "sam"
    name: str  # as the user gave it
    path: str  # local directory holding config.json and weights
    source: str  # "local" (a directory) or "hub-cache" (a cached hub snapshot)
    revision: str | None = None  # commit hash of a hub snapshot
    model_type: str = ""

    def to_json(self) -> dict:
        return {
            "kind": self.kind,
            "name": self.name,
            "path": self.path,
            "source": self.source,
            "revision": self.revision,
            "model_type": self.model_type,
        }


#: The command-line flag that names a model of each kind (any other kind: ``--model``).
_MODEL_FLAGS = {
    "clipseg": "--clipseg-model (or --model)",
    "sam": "--sam-model",
    "sam-hq": "--sam-model",
    "sam2": "--sam-model",
}


def _how_to_provide(kind: str, name: str) -> str:
    flag = _MODEL_FLAGS.get(kind, "--model")
    return f"run `overseec models download {name}` on a machine with network, or pass {flag} /path/to/model-dir"


def looks_like_hub_id(name: str) -> bool:
    """'org/name' with hub-legal characters and no path syntax (./, ~, absolute)."""
    return bool(_HUB_ID.match(name)) and not name.startswith((".", "~"))


def _check_model_dir(kind: str, name: str, path: Path, model_types: Sequence[str] | None = None) -> str:
    """Validate a local model directory (its config's model_type one of ``model_types``, by
    default the kind's in :data:`MODEL_TYPES`); return its model_type."""
    types = tuple(model_types) if model_types is not None else MODEL_TYPES[kind]
    config = path / "config.json"
    if not config.is_file():
        raise ModelError(
            f"{kind} model {name}: {path} has no config.json; give a directory saved "
            "with save_pretrained (or `overseec models path NAME` for a downloaded one)"
        )
    try:
        model_type = str(json.loads(config.read_text(encoding="utf-8")).get("model_type", ""))
    except (OSError, ValueError) as exc:
        raise ModelError(f"{kind} model {name}: unreadable config.json ({exc})") from None
    if model_type not in types:
        raise ModelError(
            f"{kind} model {name}: unsupported model type {model_type or 'unknown'!r} (expected {' or '.join(types)})"
        )
    if not any((path / f).is_file() for f in WEIGHT_FILES):
        raise ModelError(
            f"{kind} model {name}: {path} has no weights (expected model.safetensors "
            f"or pytorch_model.bin); {_how_to_provide(kind, name)}"
        )
    return model_type


def resolve_model(name: str | os.PathLike, kind: str, model_types: Sequence[str] | None = None) -> ModelRef:
    """Find a model locally: an existing directory, or a hub id in the Hugging Face cache.

    ``model_types``: the config ``model_type`` values accepted (a backend's own, e.g.
    ``("owlv2",)``; then ``kind`` is just its label in messages); default the kind's in
    :data:`MODEL_TYPES`. Never downloads. Raises a one-line :class:`ModelError` naming the model
    and how to get it.
    """
    if model_types is None and kind not in MODEL_TYPES:
        raise ModelError(f"unknown model kind {kind!r}; use one of {', '.join(MODEL_TYPES)}")
    text = str(name).strip()
    if not text:
        raise ModelError(f"empty {kind} model name")
    path = Path(text).expanduser()
    if path.is_dir():
        model_type = _check_model_dir(kind, text, path, model_types)
        return ModelRef(kind, text, str(path.resolve()), "local", None, model_type)
    if path.exists():
        raise ModelError(f"{kind} model {text}: {path} is a file; give the model directory")
    if not looks_like_hub_id(text):
        raise ModelError(f"{kind} model {text}: no such directory, and not a hub id (org/name)")
    snapshot = _cached_snapshot(text)
    if snapshot is None:
        raise ModelError(
            f"{kind} model {text} is not available offline (not in the Hugging Face "
            f"cache); {_how_to_provide(kind, text)}"
        )
    model_type = _check_model_dir(kind, text, snapshot, model_types)
    return ModelRef(kind, text, str(snapshot), "hub-cache", snapshot.name, model_type)


def _cached_snapshot(repo_id: str) -> Path | None:
    """The cached snapshot directory of a hub repo, or None; local files only."""
    try:
        from huggingface_hub import snapshot_download
        from huggingface_hub.errors import LocalEntryNotFoundError
    except ImportError:  # pragma: no cover - huggingface_hub ships with transformers
        return None
    try:
        return Path(snapshot_download(repo_id, local_files_only=True))
    except (LocalEntryNotFoundError, OSError, ValueError):
        return None


def download_model(name: str, kind: str | None = None, timeout_s: float = 20.0) -> Path:
    """Fetch a hub checkpoint into the Hugging Face cache (the only function that goes online).

    Short connection timeouts: without network this fails in seconds with a ModelError.
    """
    if not looks_like_hub_id(name):
        raise ModelError(f"{name!r} is not a hub id (org/name); a local directory needs no download")
    os.environ.setdefault("HF_HUB_ETAG_TIMEOUT", str(int(timeout_s)))
    os.environ.setdefault("HF_HUB_DOWNLOAD_TIMEOUT", str(int(timeout_s)))
    try:
        from huggingface_hub import HfApi, snapshot_download
    except ImportError:
        from overseec_core.install import detect

        raise ModelError(
            "downloading models needs huggingface_hub, part of overseec's models extra (with torch and "
            f"transformers): {detect().extra_advice('models')}"
        ) from None
    _check_reachable(name, timeout_s)
    try:
        files = HfApi().list_repo_files(name)
        weights = (
            ["model.safetensors*"]
            if any(f.startswith("model.safetensors") for f in files)
            else ["pytorch_model*.bin", "pytorch_model.bin.index.json"]
        )
        path = Path(snapshot_download(name, allow_patterns=_DOWNLOAD_PATTERNS + weights))
    except Exception as exc:  # network, HTTP, auth: all become one line
        reason = " ".join(str(exc).split())[:200] or type(exc).__name__
        raise ModelError(
            f"cannot download {name}: {reason}; check the network or copy a save_pretrained directory and pass its path"
        ) from None
    if kind is not None:
        _check_model_dir(kind, name, path)
    return path


def _check_reachable(name: str, timeout_s: float) -> None:
    """Fail in seconds when the hub cannot be reached (the hub client retries for ~30 s)."""
    import socket
    from urllib.parse import urlparse

    from huggingface_hub import constants

    url = urlparse(constants.ENDPOINT)
    port = url.port or (443 if url.scheme == "https" else 80)
    try:
        socket.create_connection((url.hostname, port), timeout=min(timeout_s, 10.0)).close()
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise ModelError(
            f"cannot download {name}: {url.hostname} is unreachable ({reason}); offline, "
            "copy a save_pretrained directory and pass its path"
        ) from None


@dataclass(frozen=True)
class ModelListing:
    """One row of `overseec models list`; ``segmenter``: the segmenter whose default it is, if any."""

    kind: str
    name: str
    description: str
    available: bool
    path: str | None
    revision: str | None
    segmenter: str | None = None

    def to_json(self) -> dict:
        return {
            "kind": self.kind,
            "name": self.name,
            "description": self.description,
            "available": self.available,
            "path": self.path,
            "revision": self.revision,
            "segmenter": self.segmenter,
        }


def local_copy(name: str) -> Path | None:
    """Where ``name`` is on this machine (a directory, a file such as an ONNX model, or a cached
    hub snapshot), without checking what kind of model it is; None when it is not here."""
    path = Path(str(name)).expanduser()
    if path.exists():
        return path
    return _cached_snapshot(str(name)) if looks_like_hub_id(str(name)) else None


def _listing(kind: str, name: str, description: str, segmenter: str | None) -> ModelListing:
    if kind in MODEL_TYPES:
        try:
            ref = resolve_model(name, kind)
            return ModelListing(kind, name, description, True, ref.path, ref.revision, segmenter)
        except ModelError:
            return ModelListing(kind, name, description, False, None, None, segmenter)
    where = local_copy(name)  # another backend's default: its module checks the type when it loads
    return ModelListing(
        kind, name, description, where is not None, None if where is None else str(where), None, segmenter
    )


def list_models(extra: Sequence[tuple[str, str]] = ()) -> list[ModelListing]:
    """Known checkpoints, each segmenter's default model (kind = the segmenter's name where it is
    not a known kind), plus ``extra`` (kind, name) pairs, and whether each is usable offline."""
    described = {(k, n): d for k, n, d in KNOWN_MODELS}
    default_of = {(info.name, info.default_model): info.name for info in SEGMENTERS.values()}
    rows = [(k, n) for k, n, _ in KNOWN_MODELS]
    rows += [pair for pair in default_of if pair not in described] + list(extra)
    return [
        _listing(
            kind,
            name,
            described.get((kind, name)) or _summary(default_of.get((kind, name))),
            default_of.get((kind, name)),
        )
        for kind, name in rows
    ]


def _summary(segmenter: str | None) -> str:
    return "" if segmenter is None else f"default of the {segmenter} segmenter: {SEGMENTERS[segmenter].summary}"


# --------------------------------------------------------------------------------------------
# Devices and precision
# --------------------------------------------------------------------------------------------


def resolve_device(text: str = "auto"):
    """'auto' | 'cpu' | 'cuda' | 'cuda:N' | 'mps' -> torch.device, or a one-line ModelError."""
    import torch

    spec = (text or "auto").strip().lower()
    if spec == "auto":
        if torch.cuda.is_available():
            return torch.device("cuda", torch.cuda.current_device())
        mps = getattr(torch.backends, "mps", None)
        if mps is not None and mps.is_available():
            return torch.device("mps")
        return torch.device("cpu")
    if spec == "cpu":
        return torch.device("cpu")
    match = re.fullmatch(r"cuda(?::(\d+))?", spec)
    if match:
        if not torch.cuda.is_available():
            raise ModelError(
                f"device {text!r}: CUDA is not available in this torch build "
                f"({torch.__version__}); use --device cpu or auto"
            )
        index = int(match.group(1) or 0)
        if index >= torch.cuda.device_count():
            raise ModelError(f"device {text!r}: only {torch.cuda.device_count()} CUDA device(s) here")
        return torch.device("cuda", index)
    if spec == "mps":
        mps = getattr(torch.backends, "mps", None)
        if mps is None or not mps.is_available():
            raise ModelError("device 'mps': Apple Metal is not available here; use --device cpu or auto")
        return torch.device("mps")
    raise ModelError(f"unknown device {text!r}; use one of {', '.join(DEVICE_CHOICES)}")


def describe_device(device) -> str:
    """Human label: 'cpu (2 threads)', 'cuda:0 (NVIDIA H100 80GB HBM3)', 'mps'."""
    import torch

    if device.type == "cuda":
        return f"{device} ({torch.cuda.get_device_name(device)})"
    if device.type == "cpu":
        return f"cpu ({torch.get_num_threads()} threads)"
    return str(device)


def resolve_precision(precision: str, device) -> str:
    """'auto' -> bf16 on CUDA with bf16 support, else fp16 on CUDA/MPS, fp32 on CPU."""
    import torch

    p = (precision or "auto").lower()
    if p not in PRECISIONS:
        raise ModelError(f"unknown precision {precision!r}; use one of {', '.join(PRECISIONS)}")
    if p == "auto":
        if device.type == "cuda":
            return "bf16" if torch.cuda.is_bf16_supported() else "fp16"
        return "fp16" if device.type == "mps" else "fp32"
    if p == "fp16" and device.type == "cpu":
        raise ModelError("precision fp16 needs a GPU; use fp32 or bf16 on CPU")
    return p


def autocast(device, precision: str) -> contextlib.AbstractContextManager:
    """torch.autocast for reduced precision, or a no-op for fp32."""
    import torch

    if precision == "fp32":
        return contextlib.nullcontext()
    dtype = torch.bfloat16 if precision == "bf16" else torch.float16
    return torch.autocast(device_type=device.type, dtype=dtype)


def default_batch_size(device, cpu: int, gpu: int) -> int:
    """The batch size for ``device``: ``gpu`` on CUDA or MPS, ``cpu`` otherwise."""
    return gpu if device.type in ("cuda", "mps") else cpu


def _is_oom(exc: BaseException) -> bool:
    import torch

    return isinstance(exc, torch.cuda.OutOfMemoryError) or (
        isinstance(exc, RuntimeError) and "out of memory" in str(exc).lower() and "cuda" in str(exc).lower()
    )


@dataclass
class BatchState:
    """The current micro-batch size; lowered for the rest of the run after an OOM."""

    size: int
    halvings: int = 0
    on_halve: Callable[[int], None] | None = field(default=None, repr=False)


def run_with_backoff(fn: Callable[[int, int], Any], n: int, state: BatchState) -> list[Any]:
    """Call ``fn(start, stop)`` over ``range(n)`` in micro-batches of ``state.size``.

    On CUDA out-of-memory the cache is emptied, the batch halved (and kept halved) and the same
    items retried; with a batch of one left it raises a ModelError saying what to change.
    """
    import torch

    outputs, start = [], 0
    while start < n:
        stop = min(n, start + state.size)
        try:
            outputs.append(fn(start, stop))
        except Exception as exc:
            if not _is_oom(exc):
                raise
            if torch.cuda.is_available():
                torch.cuda.empty_cache()
            if state.size <= 1:
                raise ModelError(
                    "out of GPU memory even with batch size 1; use a smaller "
                    "--model-size, --device cpu, or a GPU with more memory"
                ) from None
            state.size = max(1, state.size // 2)
            state.halvings += 1
            if state.on_halve is not None:
                state.on_halve(state.size)
            continue
        start = stop
    return outputs


# --------------------------------------------------------------------------------------------
# Loading
# --------------------------------------------------------------------------------------------


def _load_error(ref: ModelRef, exc: BaseException) -> ModelError:
    reason = " ".join(str(exc).split())[:200] or type(exc).__name__
    return ModelError(f"{ref.kind} model {ref.name} could not be loaded from {ref.path}: {reason}")


def attention_implementation(cls) -> str:
    """'sdpa' (PyTorch's fused scaled-dot-product attention: flash/memory-efficient kernels on
    CUDA) when the model class supports it, else 'eager'."""
    return "sdpa" if getattr(cls, "_supports_sdpa", False) else "eager"


def load_pretrained(cls, ref: ModelRef, device, **kwargs):
    """``cls.from_pretrained`` from the resolved local directory (never the network), eval mode,
    with :func:`attention_implementation` unless ``attn_implementation`` is given."""
    import transformers

    transformers.logging.set_verbosity_error()
    transformers.logging.disable_progress_bar()
    kwargs.setdefault("attn_implementation", attention_implementation(cls))
    try:
        model = cls.from_pretrained(ref.path, local_files_only=True, **kwargs)
    except Exception as exc:  # corrupt or mismatched files surface as many types (SafetensorError ...)
        raise _load_error(ref, exc) from None
    model.eval()
    model.requires_grad_(False)
    return model.to(device)


def load_aux(loader: Callable[..., Any], ref: ModelRef) -> Any | None:
    """A tokenizer/processor from the model directory, offline; None when it has none."""
    try:
        return loader(ref.path, local_files_only=True)
    except (OSError, ValueError, KeyError, TypeError):
        return None


def channels_last_on_gpu(model, device) -> bool:
    """Convolution weights in channels-last memory on CUDA (the layout its conv kernels prefer,
    tensor cores included); on CPU the default layout is as fast for these models. True if done."""
    if device.type != "cuda":
        return False
    import torch

    model.to(memory_format=torch.channels_last)
    return True


def compile_module(module) -> None:
    """``torch.compile`` a module in place (``--compile``): fused kernels after a one-off
    compilation on the first batch (and on each new batch shape)."""
    module.compile()


_CACHE: dict[tuple, Any] = {}
_CACHE_LOCK = threading.RLock()  # re-entrant: a build may load its parts through the cache too
_LOAD_COUNT: dict[tuple, int] = {}


def cached_model(key: tuple, build: Callable[[], Any]) -> Any:
    """One loaded object per key in this process (thread-safe); Dask workers reuse it. ``build``
    may itself call this (a loaded segmenter caches the model bundle it is made of)."""
    with _CACHE_LOCK:
        if key not in _CACHE:
            _CACHE[key] = build()
            _LOAD_COUNT[key] = _LOAD_COUNT.get(key, 0) + 1
        return _CACHE[key]


def load_count(key_prefix: tuple = ()) -> int:
    """How many times models matching ``key_prefix`` were loaded in this process (for tests)."""
    return sum(n for k, n in _LOAD_COUNT.items() if k[: len(key_prefix)] == key_prefix)


def release_models(kind: str | None = None) -> None:
    """Drop cached models (of one kind, or all) so their memory can be returned, e.g. CLIPSeg
    before SAM runs: a CPU run then holds one model at a time."""
    import gc

    with _CACHE_LOCK:
        for key in [k for k in _CACHE if kind is None or k[0] == kind]:
            del _CACHE[key]
    gc.collect()


__all__ = [
    "BatchState",
    "attention_implementation",
    "channels_last_on_gpu",
    "compile_module",
    "DEFAULT_CLIPSEG",
    "DEFAULT_SAM",
    "DEVICE_CHOICES",
    "KNOWN_MODELS",
    "ModelListing",
    "ModelRef",
    "PRECISIONS",
    "autocast",
    "cached_model",
    "default_batch_size",
    "describe_device",
    "download_model",
    "list_models",
    "load_aux",
    "local_copy",
    "load_count",
    "load_pretrained",
    "looks_like_hub_id",
    "release_models",
    "resolve_device",
    "resolve_model",
    "resolve_precision",
    "run_with_backoff",
]
