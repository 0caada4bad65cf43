"""What a ``semantic`` model's metadata says (:mod:`.semantic` documents the keys): the JSON sidecar
beside a checkpoint or ``.onnx`` file (:func:`sidecar_path`, :func:`read_meta`,
:func:`parse_meta`), and the Deepness plugin's metadata embedded in an ONNX file
(:func:`deepness_meta`). Pure reading and checking: no model is loaded here.
"""

from __future__ import annotations

import ast
import json
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from overseec_core.errors import ModelError
from overseec_core.interpret.matching import normalise

#: The sidecar's name: appended to the model folder's or file's name.
SIDECAR_SUFFIX = ".overseec.json"
#: The sidecar's name inside a model folder.
SIDECAR_IN_FOLDER = "overseec.json"
#: What a model's output holds: raw per-class logits (softmax applied here) or probabilities.
OUTPUT_KINDS = ("logits", "probs")
META_KEYS = ("classes", "entities", "gsd_m", "input_size", "mean", "std", "outputs")


@dataclass(frozen=True)
class SemanticMeta:
    """What a model's metadata says; None = not said (a default or the other source decides)."""

    classes: tuple[str, ...] | None = None
    entities: Mapping[str, tuple[str, ...]] = field(default_factory=dict)  # normalised entity -> labels
    gsd_m: float | None = None
    input_size: int | None = None
    mean: tuple[float, ...] | None = None
    std: tuple[float, ...] | None = None
    outputs: str | None = None
    source: str | None = None  # the file it came from

    def over(self, base: SemanticMeta) -> SemanticMeta:
        """This metadata with ``base`` filling what it does not say (entity maps are merged)."""
        said = {k: getattr(self, k) for k in ("classes", "gsd_m", "input_size", "mean", "std", "outputs")}
        merged = replace(base, **{k: v for k, v in said.items() if v is not None})
        return replace(merged, entities={**base.entities, **self.entities}, source=self.source or base.source)


def sidecar_path(model_path: Path) -> Path | None:
    """The metadata file of a model folder or file, if there is one."""
    candidates = [model_path.with_name(model_path.name + SIDECAR_SUFFIX)]
    if model_path.suffix.lower() == ".onnx":
        candidates.append(model_path.with_suffix(SIDECAR_SUFFIX))  # model.onnx -> model.overseec.json
    if model_path.is_dir():
        candidates.append(model_path / SIDECAR_IN_FOLDER)
    return next((p for p in candidates if p.is_file()), None)


def _parse_classes(value: Any, where: str) -> tuple[str, ...]:
    """{"0": "background", ...} or ["background", ...] -> labels in index order (0..C-1)."""
    if isinstance(value, list) and value and all(isinstance(v, str) for v in value):
        return tuple(value)
    if isinstance(value, dict) and value:
        try:
            by_index = {int(k): str(v) for k, v in value.items()}
        except (TypeError, ValueError):
            raise ModelError(f"{where}: class indices must be integers, got {sorted(value)!r}") from None
        if sorted(by_index) != list(range(len(by_index))):
            raise ModelError(f"{where}: class indices must be 0..{len(by_index) - 1}, got {sorted(by_index)}")
        return tuple(by_index[i] for i in range(len(by_index)))
    raise ModelError(f'{where}: "classes" must be a non-empty {{"index": "name"}} object or list of names')


def _parse_entities(value: Any, where: str) -> dict[str, tuple[str, ...]]:
    """{"road": ["road", "street"], "tree": "tree"} -> {normalised entity: class labels}."""
    if not isinstance(value, dict):
        raise ModelError(f'{where}: "entities" must be an object of entity -> class name(s)')
    out = {}
    for entity, labels in value.items():
        items = [labels] if isinstance(labels, str) else labels
        if not isinstance(items, list) or not items or not all(isinstance(x, str) for x in items):
            raise ModelError(f'{where}: "entities" {entity!r} must be a class name or a list of them')
        out[normalise(entity)] = tuple(items)
    return out


def _positive(value: Any, key: str, where: str, kind: type = float) -> Any:
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and value > 0
    if not ok or (kind is int and int(value) != value):
        raise ModelError(f'{where}: "{key}" must be a positive {kind.__name__}, got {value!r}')
    return kind(value)


def _triple(value: Any, key: str, where: str, positive: bool = False) -> tuple[float, ...]:
    ok = isinstance(value, list) and len(value) == 3 and all(isinstance(v, (int, float)) for v in value)
    if not ok or (positive and min(value) <= 0):
        raise ModelError(f'{where}: "{key}" must be three {"positive " if positive else ""}numbers (R, G, B)')
    return tuple(float(v) for v in value)


def parse_meta(data: Any, where: str) -> SemanticMeta:
    """Validate a metadata object (the sidecar's JSON); one-line ModelError naming ``where``."""
    if not isinstance(data, dict):
        raise ModelError(f"{where}: metadata must be a JSON object")
    unknown = sorted(set(data) - set(META_KEYS))
    if unknown:
        raise ModelError(f"{where}: unknown key(s) {', '.join(unknown)}; the keys are {', '.join(META_KEYS)}")
    outputs = data.get("outputs")
    if outputs is not None and outputs not in OUTPUT_KINDS:
        raise ModelError(f'{where}: "outputs" must be one of {", ".join(OUTPUT_KINDS)}, got {outputs!r}')
    return SemanticMeta(
        classes=_parse_classes(data["classes"], where) if "classes" in data else None,
        entities=_parse_entities(data["entities"], where) if "entities" in data else {},
        gsd_m=_positive(data["gsd_m"], "gsd_m", where) if "gsd_m" in data else None,
        input_size=_positive(data["input_size"], "input_size", where, int) if "input_size" in data else None,
        mean=_triple(data["mean"], "mean", where) if "mean" in data else None,
        std=_triple(data["std"], "std", where, positive=True) if "std" in data else None,
        outputs=outputs,
        source=where,
    )


def read_meta(path: Path | None) -> SemanticMeta:
    """The sidecar at ``path`` (empty metadata for None)."""
    if path is None:
        return SemanticMeta()
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise ModelError(f"model metadata {path}: unreadable ({' '.join(str(exc).split())[:160]})") from None
    return parse_meta(data, str(path))


def _literal(text: str) -> Any:
    """A metadata value written as JSON or as a Python literal (Deepness writes both)."""
    try:
        return json.loads(text)
    except ValueError:
        try:
            return ast.literal_eval(text)
        except (ValueError, SyntaxError):
            return text


def deepness_meta(props: Mapping[str, str], where: str) -> SemanticMeta:
    """The Deepness plugin's ONNX metadata: class_names, resolution (cm/px), tiles_size,
    standardization_parameters, model_type ('Segmentor' models output probabilities)."""
    data: dict[str, Any] = {}
    if "class_names" in props:
        data["classes"] = _literal(props["class_names"])
    if "resolution" in props:
        data["gsd_m"] = float(_literal(props["resolution"])) / 100.0
    if "tiles_size" in props:
        data["input_size"] = int(_literal(props["tiles_size"]))
    std = _literal(props.get("standardization_parameters", "null"))
    if isinstance(std, dict):
        for key in ("mean", "std"):
            if key in std:
                data[key] = [float(v) for v in std[key]]
    if str(_literal(props.get("model_type", ""))).lower() == "segmentor":
        data["outputs"] = "probs"
    return parse_meta(data, where) if data else SemanticMeta()
