"""Segmentation IoU: a masks raster (or a class raster) against a ground-truth class raster,
streamed in row blocks (see :mod:`overseec_core.evaluate` for which pixels count)."""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from rasterio.windows import Window

from overseec_core.errors import EvaluateError
from overseec_core.evaluate.classes import ClassTable, norm_name
from overseec_core.evaluate.geometry import check_same_grid
from overseec_core.io.read import open_raster, read_grid
from overseec_core.progress import NullProgress, Progress, check_cancelled

#: Pixels per block when IoU streams two rasters.
IOU_BLOCK_PIXELS = 1 << 22


@dataclass(frozen=True)
class ClassIoU:
    """IoU of one ground-truth class; ``bands`` are the mask bands that predicted it."""

    class_id: int
    name: str
    bands: tuple[str, ...]
    tp: int
    fp: int
    fn: int

    @property
    def iou(self) -> float | None:
        union = self.tp + self.fp + self.fn
        return self.tp / union if union else None

    def to_json(self) -> dict[str, Any]:
        return {
            "class_id": self.class_id,
            "name": self.name,
            "bands": list(self.bands),
            "tp": self.tp,
            "fp": self.fp,
            "fn": self.fn,
            "iou": self.iou,
        }


@dataclass(frozen=True)
class IoUResult:
    """Per-class IoU, their mean (classes with a non-empty union), and what did not match."""

    mode: str  # "masks" or "classes"
    classes: tuple[ClassIoU, ...]
    unmatched_bands: tuple[str, ...]
    missing_classes: tuple[str, ...]
    valid_pixels: int

    @property
    def mean_iou(self) -> float | None:
        values = [c.iou for c in self.classes if c.iou is not None]
        return float(np.mean(values)) if values else None

    def to_json(self) -> dict[str, Any]:
        return {
            "mode": self.mode,
            "mean_iou": self.mean_iou,
            "valid_pixels": self.valid_pixels,
            "classes": [c.to_json() for c in self.classes],
            "unmatched_bands": list(self.unmatched_bands),
            "missing_classes": list(self.missing_classes),
        }


def parse_matches(items: Iterable[str]) -> list[tuple[str, str]]:
    """``['road=paved road', ...]`` -> [(ground-truth class, mask band name), ...]."""
    out = []
    for item in items or ():
        gt, sep, band = str(item).partition("=")
        if not sep or not gt.strip() or not band.strip():
            raise EvaluateError(f"--match takes CLASS=BAND like 'road=paved road', not {item!r}")
        out.append((gt.strip(), band.strip()))
    return out


def _row_blocks(height: int, width: int) -> Iterable[Window]:
    rows = max(1, IOU_BLOCK_PIXELS // max(width, 1))
    for r0 in range(0, height, rows):
        yield Window(0, r0, width, min(rows, height - r0))


def _valid(data: np.ndarray, nodata: float | None) -> np.ndarray:
    """Pixels holding data: not the band's nodata value and, for floats, finite."""
    ok = np.isfinite(data) if data.dtype.kind == "f" else np.ones(data.shape, dtype=bool)
    if nodata is not None and not math.isnan(nodata):
        ok &= data != nodata
    return ok


def compute_iou(
    pred_path: str | os.PathLike,
    labels_path: str | os.PathLike,
    classes: ClassTable,
    matches: Sequence[tuple[str, str]] = (),
    mask_threshold: float | None = None,
    progress: Progress | None = None,
) -> IoUResult:
    """Per-class IoU of a masks raster (or a class raster) against a ground-truth class raster.

    Streams both rasters in row blocks (memory independent of the image size). See the package
    docstring (:mod:`overseec_core.evaluate`) for which prediction pixels count as positive.
    """
    progress = progress or NullProgress()
    check_same_grid(read_grid(labels_path), read_grid(pred_path), f"labels {labels_path}", f"masks {pred_path}")
    with open_raster(labels_path) as gt_ds, open_raster(pred_path) as pr_ds:
        descriptions = [d.strip() if d else "" for d in pr_ds.descriptions]
        class_mode = pr_ds.count == 1 and not descriptions[0] and pr_ds.dtypes[0][0] in "ui"
        band_names = [d or f"band {i + 1}" for i, d in enumerate(descriptions)]
        ids = sorted(classes.names)
        if class_mode:
            if matches:
                raise EvaluateError(
                    "--match needs a masks raster with named bands; "
                    f"{pred_path} is a single-band class raster read with classes.json"
                )
            assign: dict[int, list[int]] = {cid: [] for cid in ids}
            unmatched: list[str] = []
        else:
            assign, unmatched = _assign_bands(band_names, classes, matches)
        missing = [classes.names[c] for c in ids if not class_mode and not assign.get(c)]
        used = [c for c in ids if class_mode or assign.get(c)]
        tp = dict.fromkeys(used, 0)
        fp = dict.fromkeys(used, 0)
        fn = dict.fromkeys(used, 0)
        valid_total = 0
        gt_nodata, pr_nodata = gt_ds.nodata, pr_ds.nodata
        is_float = pr_ds.dtypes[0][0] == "f"
        threshold = mask_threshold if mask_threshold is not None else (0.5 if is_float else None)
        blocks = list(_row_blocks(gt_ds.height, gt_ds.width))
        progress.begin("evaluate: IoU", len(blocks), unit="block")
        for window in blocks:
            check_cancelled(progress)
            gt = gt_ds.read(1, window=window)
            pred = pr_ds.read(window=window)
            valid = _valid(gt, gt_nodata)
            for b in range(pred.shape[0]):
                valid &= _valid(pred[b], pr_nodata)
            valid_total += int(valid.sum())
            for cid in used:
                truth = (gt == cid) & valid
                if class_mode:
                    guess = (pred[0] == cid) & valid
                else:
                    guess = np.zeros(gt.shape, dtype=bool)
                    for b in assign[cid]:
                        band = pred[b]
                        guess |= band >= threshold if threshold is not None else band > 0
                    guess &= valid
                inter = int(np.count_nonzero(truth & guess))
                tp[cid] += inter
                fp[cid] += int(np.count_nonzero(guess)) - inter
                fn[cid] += int(np.count_nonzero(truth)) - inter
            progress.advance()
        progress.end()
    per_class = tuple(
        ClassIoU(
            class_id=c,
            name=classes.names[c],
            bands=tuple(band_names[b] for b in assign.get(c, [])),
            tp=tp[c],
            fp=fp[c],
            fn=fn[c],
        )
        for c in used
    )
    return IoUResult(
        mode="classes" if class_mode else "masks",
        classes=per_class,
        unmatched_bands=tuple(unmatched),
        missing_classes=tuple(missing),
        valid_pixels=valid_total,
    )


def _assign_bands(
    band_names: Sequence[str], classes: ClassTable, matches: Sequence[tuple[str, str]]
) -> tuple[dict[int, list[int]], list[str]]:
    """Which mask bands predict which class: explicit --match pairs first, then equal names."""
    by_name: dict[str, list[int]] = {}
    for i, name in enumerate(band_names):
        by_name.setdefault(norm_name(name), []).append(i)
    assign: dict[int, list[int]] = {}
    claimed: set[int] = set()
    for gt_name, band in matches:
        cid = classes.lookup(gt_name)
        if cid is None:
            raise EvaluateError(f"--match: unknown class {gt_name!r}; classes.json has {classes.describe()}")
        bands = by_name.get(norm_name(band))
        if not bands:
            raise EvaluateError(f"--match: the masks have no band {band!r}; bands: {', '.join(band_names)}")
        assign.setdefault(cid, []).extend(b for b in bands if b not in assign.get(cid, []))
        claimed.update(bands)
    for i, name in enumerate(band_names):
        if i in claimed:
            continue
        cid = classes.lookup(name)
        if cid is not None:
            assign.setdefault(cid, []).append(i)
            claimed.add(i)
    unmatched = [band_names[i] for i in range(len(band_names)) if i not in claimed]
    return assign, unmatched
