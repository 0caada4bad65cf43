"""Path geometry on a grid: pixel <-> metre <-> world coordinates, rasterised and densified lines,
line features read from vector files, same-grid checks, and the Hausdorff distance to reference
paths (see :mod:`overseec_core.evaluate` for the definitions)."""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial import cKDTree
from skimage import draw

from overseec_core.errors import EvaluateError
from overseec_core.io.grid import Grid, crs_label
from overseec_core.io.vectors import read_vector


def to_metres(rows_cols: np.ndarray, pixel_size: tuple[float, float]) -> np.ndarray:
    """(row, col) pixel-centre coordinates -> (x, y) metres on the ground, origin at pixel (0, 0)."""
    rc = np.asarray(rows_cols, dtype=np.float64).reshape(-1, 2)
    return np.column_stack([rc[:, 1] * pixel_size[0], rc[:, 0] * pixel_size[1]])


def world_to_rowcol(grid: Grid, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """World coordinates in the grid's CRS -> fractional (row, col), integers at pixel centres."""
    cols, rows = ~grid.transform * (np.asarray(xs, dtype=np.float64), np.asarray(ys, dtype=np.float64))
    return np.column_stack([np.asarray(rows) - 0.5, np.asarray(cols) - 0.5])


def point_json(grid: Grid, rc: Sequence[int]) -> dict[str, Any]:
    """Pixel (row, col) and the map coordinates of its centre, as a JSON object."""
    r, c = int(rc[0]), int(rc[1])
    x, y = grid.transform * (c + 0.5, r + 0.5)
    return {"row": r, "col": c, "x": float(x), "y": float(y)}


def rasterise_line(rows_cols: np.ndarray) -> np.ndarray:
    """8-connected pixel chain (Bresenham, skimage.draw.line) through a polyline's vertices."""
    vertices = np.floor(np.asarray(rows_cols, dtype=np.float64) + 0.5).astype(np.int64)
    if len(vertices) == 1:
        return vertices.copy()
    parts = []
    for k in range(len(vertices) - 1):
        (r0, c0), (r1, c1) = vertices[k], vertices[k + 1]
        rr, cc = draw.line(int(r0), int(c0), int(r1), int(c1))
        seg = np.column_stack([rr, cc])
        parts.append(seg if k == 0 else seg[1:])
    chain = np.concatenate(parts)
    keep = np.ones(len(chain), dtype=bool)
    keep[1:] = np.any(chain[1:] != chain[:-1], axis=1)
    return chain[keep]


def densify(points: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray]:
    """Points along a polyline (N, 2) at most ``step`` apart, vertices included, and the index of
    the segment each point lies on (the last vertex counts as on the last segment)."""
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if len(pts) < 2:
        return pts.copy(), np.zeros(len(pts), dtype=np.int64)
    seg = np.diff(pts, axis=0)
    # the relative 1e-9 keeps float noise in a length of exactly k steps from adding a step
    n = np.maximum(1, np.ceil(np.hypot(seg[:, 0], seg[:, 1]) / step * (1 - 1e-9)).astype(np.int64))
    starts = np.repeat(pts[:-1], n, axis=0)
    steps = np.repeat(seg / n[:, None], n, axis=0)
    offsets = np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)
    which = np.repeat(np.arange(len(seg)), n)
    return np.vstack([starts + steps * offsets[:, None], pts[-1:]]), np.append(which, len(seg) - 1)


def point_segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Euclidean distance from points ``p`` (N, 2) to segments ``a``-``b`` (N, 2 each), row by row."""
    ab = b - a
    denom = np.einsum("ij,ij->i", ab, ab)
    t = np.divide(np.einsum("ij,ij->i", p - a, ab), denom, out=np.zeros(len(p)), where=denom > 0)
    closest = a + np.clip(t, 0.0, 1.0)[:, None] * ab
    return np.hypot(*(p - closest).T)


#: The geometry types :func:`read_lines` reads (a MultiLineString's parts become one line).
LINE_TYPES = frozenset({"LineString", "MultiLineString"})


@dataclass(frozen=True)
class VectorLine:
    """One line feature read from a vector file, in the grid's fractional (row, col)."""

    name: str
    rows_cols: np.ndarray  # (N, 2) float, integers at pixel centres
    properties: Mapping[str, Any] = field(default_factory=dict)


def read_lines(path: str | os.PathLike, grid: Grid, what: str = "paths") -> list[VectorLine]:
    """Read LineString / MultiLineString features (any OGR format and CRS) onto ``grid``.

    A file without a CRS is read as WGS 84 (RFC 7946 GeoJSON). The parts of a MultiLineString
    become one line, in order. Each line is named by its ``name`` or ``id`` property, else by its
    position in the file.
    """
    p = Path(path)
    features = read_vector(p, grid.crs, label=what, geometry_types=LINE_TYPES, assume_crs="EPSG:4326", noun="file")
    lines: list[VectorLine] = []
    for feat in features:
        parts = getattr(feat.geometry, "geoms", [feat.geometry])
        coords = np.array([c[:2] for part in parts for c in part.coords], dtype=np.float64).reshape(-1, 2)
        if len(coords) == 0:
            continue
        if not np.all(np.isfinite(coords)):
            raise EvaluateError(f"{p}: feature {feat.index + 1} cannot be reprojected to {crs_label(grid.crs)}")
        props = dict(feat.properties)
        name = str(props.get("name") or props.get("id") or f"{what} {feat.index + 1}")
        lines.append(
            VectorLine(name=name, rows_cols=world_to_rowcol(grid, coords[:, 0], coords[:, 1]), properties=props)
        )
    if not lines:
        raise EvaluateError(f"{p} holds no LineString features; {what} must be lines")
    return lines


def check_same_grid(a: Grid, b: Grid, what_a: str, what_b: str) -> None:
    """Raise a one-line EvaluateError unless two rasters share pixels and CRS."""
    if a.same_as(b, tol=1e-6):
        return
    if a.shape != b.shape:
        why = f"{a.width}x{a.height} vs {b.width}x{b.height} px"
    elif a.crs != b.crs:
        why = f"CRS {crs_label(a.crs)} vs {crs_label(b.crs)}"
    else:
        why = "their geotransforms differ"
    raise EvaluateError(
        f"{what_a} and {what_b} are on different grids ({why}); resample one onto the other's grid first"
    )


# --------------------------------------------------------------------------------------------
# Hausdorff distance to reference paths
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class ReferenceSet:
    """Union of reference paths in metres: their segments, dense samples and a KD-tree of those.

    Distances to the union are exact where it matters: the KD-tree (scipy cKDTree) finds the
    nearest sample, then the distance to that sample's segment and its two neighbours on the same
    line is computed exactly. Only when the nearest point lies on another line whose sample is not
    the nearest can the result exceed the true distance, by at most half a sampling step.
    (shapely's STRtree.query_nearest gives exact distances too but was 30x slower here on long,
    overlapping segments.)
    """

    names: tuple[str, ...]
    points_m: np.ndarray  # (K, 2) dense samples
    segment_of: np.ndarray  # (K,) index into seg_a / seg_b of each sample
    seg_a: np.ndarray  # (M, 2) segment starts
    seg_b: np.ndarray  # (M, 2) segment ends
    seg_line: np.ndarray  # (M,) which line each segment belongs to
    step_m: float
    tree: Any  # scipy.spatial.cKDTree over points_m

    @classmethod
    def build(
        cls, lines: Sequence[VectorLine], pixel_size: tuple[float, float], step_m: float | None = None
    ) -> ReferenceSet:
        if not lines:
            raise EvaluateError("no reference paths")
        step = step_m or min(pixel_size) / 4.0
        pts, seg_of, seg_a, seg_b, seg_line = [], [], [], [], []
        n_seg = 0
        for k, line in enumerate(lines):
            xy = to_metres(line.rows_cols, pixel_size)
            if len(xy) == 1:
                xy = np.vstack([xy, xy])
            dense, which = densify(xy, step)
            pts.append(dense)
            seg_of.append(which + n_seg)
            seg_a.append(xy[:-1])
            seg_b.append(xy[1:])
            seg_line.append(np.full(len(xy) - 1, k))
            n_seg += len(xy) - 1
        points = np.vstack(pts)
        return cls(
            names=tuple(line.name for line in lines),
            points_m=points,
            segment_of=np.concatenate(seg_of),
            seg_a=np.vstack(seg_a),
            seg_b=np.vstack(seg_b),
            seg_line=np.concatenate(seg_line),
            step_m=step,
            tree=cKDTree(points),
        )

    def distance(self, xy: np.ndarray) -> np.ndarray:
        """Distance (metres) from each point (N, 2) to the union of the reference lines."""
        d, k = self.tree.query(xy)
        seg = self.segment_of[k]
        best = d
        for offset in (-1, 0, 1):
            cand = np.clip(seg + offset, 0, len(self.seg_a) - 1)
            same = self.seg_line[cand] == self.seg_line[seg]
            exact = point_segment_distance(xy, self.seg_a[cand], self.seg_b[cand])
            best = np.where(same, np.minimum(best, exact), best)
        return best


@dataclass(frozen=True)
class HausdorffResult:
    """Distances of one system path to the reference union, in metres and per map diagonal."""

    directed_m: float  # max over path pixels of the distance to the references
    reverse_m: float | None  # max over reference points of the distance to the path (symmetric)
    hausdorff_m: float  # the one the options asked for
    mean_m: float  # mean over path pixels of the distance to the references
    normalised: float  # hausdorff_m / map diagonal
    paper: float  # the paper's figure: mean_m / map diagonal


def map_diagonal_m(grid: Grid) -> float:
    """Length in metres of the grid's diagonal: the scale of the end-matching tolerance and of the
    normalised Hausdorff distance."""
    px, py = grid.pixel_size_m()
    return math.hypot(grid.width * px, grid.height * py)


#: Ends of a path and a reference match within this many pixels ...
MATCH_TOLERANCE_PIXELS = 3.0

#: ... or this fraction of the map diagonal, whichever is larger.
MATCH_TOLERANCE_FRACTION = 0.01


def endpoint_tolerance_m(grid: Grid) -> float:
    """How close (metres) a path's start and goal must be to a reference path's ends for the two
    to count as the same start-goal pair: max(3 pixels, 1 % of the map diagonal)."""
    return max(MATCH_TOLERANCE_PIXELS * max(grid.pixel_size_m()), MATCH_TOLERANCE_FRACTION * map_diagonal_m(grid))


def matching_references(
    start: Sequence[float],
    goal: Sequence[float],
    references: Sequence[VectorLine],
    pixel_size: tuple[float, float],
    tolerance_m: float,
) -> list[int]:
    """Indices of the reference paths whose first and last points lie within ``tolerance_m`` of
    ``start`` and ``goal`` ((row, col), either direction): the references of that pair."""
    ends = to_metres(np.array([start, goal], dtype=np.float64), pixel_size)
    out = []
    for k, line in enumerate(references):
        r = to_metres(line.rows_cols[[0, -1]], pixel_size)
        forward = max(np.hypot(*(ends[0] - r[0])), np.hypot(*(ends[1] - r[1])))
        backward = max(np.hypot(*(ends[0] - r[1])), np.hypot(*(ends[1] - r[0])))
        if min(forward, backward) <= tolerance_m:
            out.append(k)
    return out


def hausdorff(
    pixels: np.ndarray,
    reference: ReferenceSet,
    pixel_size: tuple[float, float],
    diagonal_m: float,
    symmetric: bool = False,
) -> HausdorffResult:
    """Directed (default) or symmetric Hausdorff distance of a pixel path to the references, and
    the paper's figure (the mean point distance per map diagonal)."""
    pts = to_metres(pixels, pixel_size)
    if len(pts) == 0:
        raise EvaluateError("an empty path has no Hausdorff distance")
    d = reference.distance(pts)
    directed = float(d.max())
    reverse = None
    if symmetric:
        reverse = float(cKDTree(pts).query(reference.points_m)[0].max())
    value = max(directed, reverse) if reverse is not None else directed
    return HausdorffResult(
        directed_m=directed,
        reverse_m=reverse,
        hausdorff_m=value,
        mean_m=float(d.mean()),
        normalised=value / diagonal_m,
        paper=float(d.mean()) / diagonal_m,
    )
