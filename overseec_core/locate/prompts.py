"""SAM prompts from coarse masks, and the calibration of coarse probabilities (numpy/scipy only).

Per tile and entity, each connected component of the coarse mask (scipy.ndimage.label,
8-connected) is prompted separately, largest first:

* positive points at distance-transform maxima of the component (spread out by suppression),
* negative points at the most confident background in the component's context box, near it,
* a box around the component (with a small margin),
* the coarse logits, relative to the entity's threshold, as the dense mask prompt.

Every per-component computation here works on the component's bounding box or its context box
(``region``), never on the whole tile: its cost scales with the component, not the tile.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from overseec_core.errors import InputError

#: Clip of the mask-prompt logits (SAM's own low-res logits live in about this range).
MASK_PROMPT_LIMIT = 10.0
_EIGHT = np.ones((3, 3), bool)


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
    #: components per mask-decoder call, across the tiles of an encoder batch; None: 4 on CPU
    #: (fastest there), 64 on a GPU (one call for all components of a few tiles)
    decoder_batch: int | None = None

    def check(self) -> None:
        if self.iterations < 1:
            raise InputError(f"--sam-iterations must be at least 1, got {self.iterations}")
        if (
            self.min_area < 1
            or self.max_components < 1
            or self.positive_points < 1
            or self.negative_points < 0
            or (self.decoder_batch is not None and self.decoder_batch < 1)
        ):
            raise InputError("SAM prompt settings must be positive (min area, components, points)")
        if not 0.0 <= self.stop_iou <= 1.0:
            raise InputError(f"stop IoU {self.stop_iou} must be between 0 and 1")
        if not 0.0 <= self.box_margin <= 1.0:
            raise InputError(f"box margin {self.box_margin} must be between 0 and 1")

    def components_per_call(self, on_gpu: bool) -> int:
        """The decoder batch: as set, else 4 on CPU and 64 on a GPU."""
        if self.decoder_batch is not None:
            return int(self.decoder_batch)
        return 64 if on_gpu else 4


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


def context_region(component: Component, shape: tuple[int, int], params: RefineParams) -> tuple[slice, slice]:
    """Where SAM's answer for ``component`` is accepted (and negatives are searched): its bounding
    box grown by twice the box margin (at least 8 px), clipped to the tile of ``shape``."""
    rows, cols = component.rows, component.cols
    size = max(rows.stop - rows.start, cols.stop - cols.start)
    return (
        _grow(rows, size, 2 * params.box_margin, 8, shape[0]),
        _grow(cols, size, 2 * params.box_margin, 8, shape[1]),
    )


def make_prompt(
    entity: int,
    component: Component,
    foreground: np.ndarray,
    score: np.ndarray,
    params: RefineParams,
    origin: tuple[int, int] = (0, 0),
    shape: tuple[int, int] | None = None,
) -> ComponentPrompt:
    """Prompts for one component; ``foreground`` is its current mask, ``score`` the current
    foreground probability (coarse, then SAM's) used to place negatives.

    Both may be the whole tile, or crops whose top-left pixel is at ``origin`` on a tile of
    ``shape`` that cover the component's :func:`context_region`: only that region is read, so the
    refiner passes crops and the work scales with the component, not the tile.
    """
    h, w = foreground.shape if shape is None else shape
    r0, c0 = origin
    rows, cols = component.rows, component.cols
    size = max(rows.stop - rows.start, cols.stop - cols.start)
    box_r = _grow(rows, size, params.box_margin, 2, h)
    box_c = _grow(cols, size, params.box_margin, 2, w)
    region = context_region(component, (h, w), params)
    rr, rc = region
    if rr.start < r0 or rc.start < c0 or rr.stop - r0 > foreground.shape[0] or rc.stop - c0 > foreground.shape[1]:
        raise ValueError(f"the crop at {origin} of shape {foreground.shape} does not hold the region {region}")
    crop = foreground[rows.start - r0 : rows.stop - r0, cols.start - c0 : cols.stop - c0]
    pos = [(r + rows.start, c + cols.start) for r, c in positive_points(crop, params.positive_points)]
    local = (slice(rr.start - r0, rr.stop - r0), slice(rc.start - c0, rc.stop - c0))
    neg = [
        (r + rr.start, c + rc.start)
        for r, c in negative_points(foreground[local], score[local], params.negative_points)
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


def iou(a: np.ndarray, b: np.ndarray) -> float:
    """Intersection over union of two boolean masks (1 when both are empty)."""
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


# --------------------------------------------------------------------------------------------
# Crop-local arithmetic on SAM's low-resolution mask grid
# --------------------------------------------------------------------------------------------


def cell_pool(values: np.ndarray, cell: int) -> np.ndarray:
    """(..., h, w) -> (..., h/cell, w/cell) means over ``cell`` x ``cell`` blocks (h, w multiples
    of ``cell``): SAM's mask prompt grid, what ``adaptive_avg_pool2d`` gives for a whole multiple."""
    *lead, h, w = values.shape
    blocks = values.reshape(*lead, h // cell, cell, w // cell, cell)
    return blocks.mean(axis=(-3, -1), dtype=np.float32)


def cell_span(sl: slice, cell: int) -> slice:
    """The cells (of ``cell`` px) a pixel slice touches."""
    return slice(sl.start // cell, -(-sl.stop // cell))


def _linear_indices(size_in: int, size_out: int, start: int, stop: int):
    """torch's bilinear (align_corners=False) source indices and weights for output positions
    ``start:stop`` of an axis resized from ``size_in`` to ``size_out``."""
    scale = size_in / size_out
    src = np.maximum((np.arange(start, stop, dtype=np.float64) + 0.5) * scale - 0.5, 0.0).astype(np.float32)
    i0 = src.astype(np.int64)
    i1 = np.minimum(i0 + 1, size_in - 1)
    lam = (src - i0).astype(np.float32)
    return i0, i1, lam


def upsample_region(low: np.ndarray, size: int, region: tuple[slice, slice]) -> np.ndarray:
    """The ``region`` of ``low`` (m, m) bilinearly resized to (size, size), computed for that
    region only: equal (to float rounding) to ``F.interpolate(..., (size, size), 'bilinear',
    align_corners=False)[region]`` at a fraction of the cost for a small region."""
    m = low.shape[-1]
    rows, cols = region
    j0, j1, lx = _linear_indices(m, size, cols.start, cols.stop)
    i0, i1, ly = _linear_indices(m, size, rows.start, rows.stop)
    used = np.unique(np.concatenate([i0, i1]))
    lookup = np.searchsorted(used, np.arange(m))
    part = low[used]
    across = part[:, j0] * (1 - lx) + part[:, j1] * lx
    return (across[lookup[i0]] * (1 - ly)[:, None] + across[lookup[i1]] * ly[:, None]).astype(np.float32)


def sigmoid(x: np.ndarray) -> np.ndarray:
    """float32 logistic function, clipped so exp cannot overflow."""
    return (1.0 / (1.0 + np.exp(-np.clip(x, -60, 60)))).astype(np.float32)


__all__ = [
    "MASK_PROMPT_LIMIT",
    "POINT_SEARCH_PIXELS",
    "Component",
    "ComponentPrompt",
    "RefineParams",
    "calibrate",
    "cell_pool",
    "cell_span",
    "coarse_mask_logits",
    "context_region",
    "find_components",
    "iou",
    "make_prompt",
    "needs_sam",
    "negative_points",
    "positive_points",
    "sigmoid",
    "upsample_region",
]
