"""The cost language's spatial kernels: distances, the geodesic dilation and the centre/edge field.

The array work behind ``distance``, ``near``, ``far``, ``borders``, ``inside``, ``centre`` and
``edge`` (:mod:`overseec_core.costlang.ops` holds the operator table that calls them). scipy.ndimage
does the spatial work (exact Euclidean distance transform with anisotropic ``sampling``, separable
maximum filter, labelling) and scikit-image's minimum-cost path the reach test; both are imported
inside the kernels, so checking a program (which QGIS's Python does as the user types) needs numpy
only.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TypeAlias, cast

import numpy as np
import numpy.typing as npt

#: A cancellation check: returns when the work may go on, raises (``Cancelled``) when it must stop.
Poll = Callable[[], None]


def never_cancelled() -> None:
    """The default :data:`Poll`: work that nobody can cancel (tests, constant folding)."""


#: A boolean mask and a float field: the arrays the kernels work on.
Mask: TypeAlias = npt.NDArray[np.bool_]
Field: TypeAlias = npt.NDArray[np.float64]
#: A float field, or one number where the input was 0-d (constant folding).
FieldValue: TypeAlias = Field | np.float64
#: Pixel size (y, x) in metres, as scipy.ndimage's ``sampling`` wants it.
Sampling: TypeAlias = tuple[float, float]


def raw_distance(mask: npt.ArrayLike, sampling: Sampling) -> FieldValue:
    """Metres from each pixel to the nearest True pixel of ``mask`` (inf when there is none).

    Distances are rounded through float32 so that ties between equally near pixels (possible with
    non-square pixels) give the same value whichever pixel the transform picks, in a block or in
    the whole image.
    """
    from scipy import ndimage

    m = np.asarray(mask, dtype=bool)
    if m.ndim == 0:
        return np.float64(0.0 if m else np.inf)
    if not m.any():
        return np.full(m.shape, np.inf, dtype=np.float64)
    d: Field = ndimage.distance_transform_edt(~m, sampling=sampling)
    return d.astype(np.float32).astype(np.float64)


def distance_to(mask: npt.ArrayLike, sampling: Sampling, cap: float) -> FieldValue:
    """Metres from each pixel to the nearest True pixel of ``mask``, saturating at ``cap``.

    Saturation is what makes block-wise evaluation exact: a distance up to ``cap`` is found within
    ``cap`` metres, so a halo of ``cap`` metres around a block sees the same nearest pixel as the
    whole image, and a larger distance is ``cap`` in both. (Comparisons with a radius, as in
    ``near``, use the unsaturated distance: a window can only over-estimate distances beyond the
    radius, which does not change the answer.)
    """
    return np.minimum(raw_distance(mask, sampling), cap)


def _inner_distance(mask: npt.ArrayLike, sampling: Sampling, cap: float) -> FieldValue:
    """Metres from each mask pixel to the nearest pixel outside the mask (0 outside), capped."""
    m = np.asarray(mask, dtype=bool)
    if m.ndim == 0:
        return np.float64(cap if m else 0.0)
    return np.where(m, distance_to(~m, sampling, cap), 0.0)


def _footprint_radius(metres: float, sampling: Sampling) -> tuple[int, int]:
    return (math.ceil(metres / sampling[0]), math.ceil(metres / sampling[1]))


#: 8-connectivity: the neighbourhood of one 3x3 maximum-filter step.
_EIGHT = np.ones((3, 3), dtype=bool)
#: Up to this many dilation steps, :func:`local_half_width` runs the plain step loop over the
#: whole array (cheaper than labelling components when there are few steps).
LOOP_STEPS = 32


def geodesic_dilation(values: Field, mask: Mask, steps: tuple[int, int], poll: Poll = never_cancelled) -> Field:
    """The largest of ``values`` reachable inside ``mask`` within ``steps`` (rows, cols) steps.

    The definition of the local half width: ``max(steps)`` 3x3 maximum filters (3x1 or 1x3 once
    one axis has used its steps), each kept to the mask (0 outside). ``values`` must be >= 0 and
    0 outside the mask. The loop stops as soon as a step changes nothing, which is exact: every
    later step would start from the same array (a 3x3 step that changes nothing leaves a 3x1 step
    nothing to change either). ``poll`` runs before every step so a cancel is honoured mid-loop.
    """
    from scipy import ndimage

    ry, rx = steps
    h = values
    for step in range(max(ry, rx)):
        poll()
        size = (3 if step < ry else 1, 3 if step < rx else 1)
        grown = np.where(mask, ndimage.maximum_filter(h, size=size, mode="constant", cval=0.0), 0.0)
        if np.array_equal(grown, h):
            break
        h = grown
    return h


def _peak_reaches_all(values: Field, component: Mask, peak: float, reach: int) -> bool:
    """Whether every pixel of one 8-connected component lies within ``reach`` steps of a pixel
    holding the component's ``peak`` value (``values`` and ``component`` cut to its bounding box).

    Step counts come from one Dijkstra run (``skimage.graph.MCP``, unit costs, 8 neighbours; it
    counts the start pixel, hence the - 1).
    """
    from skimage.graph import MCP

    starts = np.argwhere(component & (values == peak))
    costs = np.where(component, 1.0, -1.0)  # negative costs are impassable
    counts, _ = MCP(costs, fully_connected=True).find_costs(starts)
    return bool((counts[component] - 1 <= reach).all())


def _box_area(box: tuple[slice, slice]) -> int:
    return int((box[0].stop - box[0].start) * (box[1].stop - box[1].start))


def _union_box(boxes: Sequence[tuple[slice, slice]]) -> tuple[slice, slice]:
    return (
        slice(min(b[0].start for b in boxes), max(b[0].stop for b in boxes)),
        slice(min(b[1].start for b in boxes), max(b[1].stop for b in boxes)),
    )


def local_half_width(values: Field, mask: Mask, steps: tuple[int, int], poll: Poll = never_cancelled) -> Field:
    """Exactly :func:`geodesic_dilation`, usually in time that does not grow with the steps.

    Values only travel inside an 8-connected component of the mask, so components are solved
    apart: a component's largest value (its peak) reaches all of it when every pixel is within
    ``min(steps)`` steps of a peak pixel, which holds outright for a component of at most
    ``min(steps) + 1`` pixels and is checked with one Dijkstra run for larger ones
    (:func:`_peak_reaches_all`). Components that fail the check (a long winding feature) run the
    step loop on their bounding boxes, or on the box around all of them when that is smaller,
    so the work never exceeds the plain loop's. A dilation of at most :data:`LOOP_STEPS` steps
    runs the step loop directly. ``poll`` runs between components and steps.
    """
    from scipy import ndimage

    if max(steps) <= LOOP_STEPS:
        return geodesic_dilation(values, mask, steps, poll)
    labels, n = ndimage.label(mask, structure=_EIGHT)
    poll()
    if n == 0:
        return np.zeros_like(values)
    peaks = np.zeros(n + 1, dtype=values.dtype)
    peaks[1:] = ndimage.maximum(values, labels, np.arange(1, n + 1))
    h = np.where(mask, peaks[labels], 0.0)
    sizes = np.bincount(labels.ravel(), minlength=n + 1)
    boxes = ndimage.find_objects(labels)
    failing = []
    for k in np.flatnonzero(sizes[1:] > min(steps) + 1) + 1:
        poll()
        box = boxes[k - 1]
        if not _peak_reaches_all(values[box], labels[box] == k, peaks[k], min(steps)):
            failing.append(k)
    if not failing:
        return h
    union = _union_box([boxes[k - 1] for k in failing])
    if sum(_box_area(boxes[k - 1]) for k in failing) <= _box_area(union):
        regions = [(boxes[k - 1], [k]) for k in failing]
    else:
        regions = [(union, failing)]
    for box, ks in regions:
        inside = np.isin(labels[box], ks)
        grown = geodesic_dilation(np.where(inside, values[box], 0.0), inside, steps, poll)
        h[box][inside] = grown[inside]
    return h


def centre_field(
    mask: npt.ArrayLike, width: float, sampling: Sampling, edge: bool = False, poll: Poll = never_cancelled
) -> FieldValue:
    """0 on the medial axis of a linear feature rising to ~1 at its border (1 outside the mask).

    ``d`` is the distance to the outside, capped at half the nominal width ``width``. The local
    half width ``h`` is the largest ``d`` reachable *inside the mask* within half a width (a
    geodesic dilation: repeated 3x3 maximum filters, each step kept to the mask, at most half a
    width of steps per axis; see :func:`geodesic_dilation`, computed by :func:`local_half_width`),
    so a narrow road beside a wide one is not measured against the wide one. ``1 - d/h`` is 0 on
    the centre line of any feature up to ``width`` wide. ``edge`` returns ``d/h`` instead: low
    along the borders, 1 on the centre line. ``poll`` is called between units of work and may
    raise to cancel.
    """
    half = width / 2.0
    m = np.asarray(mask, dtype=bool)
    if m.ndim == 0:
        return np.float64(1.0 if (edge or not m) else 0.0)
    d = cast(Field, _inner_distance(m, sampling, half))  # an array: the mask is not 0-d
    poll()
    h = local_half_width(d, m, _footprint_radius(half, sampling), poll)
    ratio = np.divide(d, h, out=np.zeros_like(d), where=h > 0)
    out = ratio if edge else 1.0 - ratio
    return np.where(m, out, 1.0)
