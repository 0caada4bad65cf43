"""Evaluation: the OVerSeeC paper's metrics on planned or given paths, plus segmentation IoU.

What each figure means here (the paper leaves some choices open; these are ours, stated once):

RRPI (rank-relative path index)
    Given a class raster on the costmap grid and a rank per class (1 = most preferred), the RRPI of
    a path is ``sum over its pixels of (rank(class(pixel)) - 1)``: a path that stays on rank-1
    terrain scores 0, every pixel on worse terrain adds its rank distance from the best. Pixels
    whose class has no rank (background, classes left out of ``--ranks``, label nodata) count as
    ``unranked_rank``, by default the largest rank given (``"max"``): not knowing what a pixel is
    is treated as the least preferred known terrain. A path's pixels are its 8-connected pixel
    chain (the planner's output, or a drawn line rasterised with Bresenham's algorithm).

Hausdorff distance to reference paths
    Reference paths are human-drawn LineStrings in any vector format and CRS; they are reprojected
    to the costmap's CRS with pyproj. Distances are in metres using the pixel size on the ground
    (x and y apart, so non-square pixels and geographic CRSs are right): from a path pixel to the
    reference lines they are exact (see :class:`ReferenceSet`); the reverse direction samples the
    references every quarter of the smaller pixel side (error below an eighth of a pixel).
    A path is only compared with the reference paths *of its own start and goal*: those whose
    first and last points lie within max(3 pixels, 1 % of the map diagonal) in ground metres of
    the path's start and goal (either direction). Paths without such a reference get no
    Hausdorff distance (null), and the report says how many were matched per group.
    The default is the *directed* Hausdorff distance from a system path to the union of the
    reference paths of its pair, ``max over path pixels p of min over reference points r
    |p - r|``: how far the path strays from anywhere a human would go (the union holds several
    humans' paths, so the reverse direction would charge the system for not following all of them
    at once). ``symmetric`` takes the max of both directions. Each distance is normalised by the
    map diagonal in metres, and the reported "mean Hausdorff" is the mean of the normalised
    distances over the matched paths. The mean point-to-reference distance is reported beside it.

Rank-optimal reference
    For each path with an RRPI, the best route under the ranks between the same ends: planned in
    exact mode with the project's planner (same base cost per metre as the evaluated costmap's
    planner) on a costmap that encodes the ranks exactly, ``(rank - 1) / (K - 1)`` with ``K`` the
    largest rank (unranked rank included; all zeros when K = 1) and label nodata impassable.
    ``rrpi_ratio = rrpi / rrpi_optimal``: 1 when both are 0, infinite when only the optimum is 0
    (written null in JSON with ``rrpi_ratio_infinite: true``, ``inf`` in pairs.csv). Summaries per
    group: median ratio, share of paths within 5 % (ratio <= 1.05), worst and best ratio, mean
    excess RRPI. A costmap equal to the rank costmap scores exactly 1. The planner minimises
    metre-weighted cost while RRPI counts pixels (a diagonal step is one pixel but 1.41 pixel
    lengths), so the reference is not the minimum-RRPI pixel chain and ratios a little below 1
    occur (down to 0.93 on a real scene); the exact minimum (a node-weighted search, e.g.
    skimage.graph.MCP) measured 6x slower than the planner.

KDE centre of mass
    A Gaussian KDE (scipy.stats.gaussian_kde, Scott's bandwidth) of the (path length in metres,
    RRPI) points of the sampled pairs is evaluated on a grid spanning the data padded by three
    kernel standard deviations and clipped at 0 (neither figure can be negative); the centre of
    mass is the density-weighted mean of that grid, the mode its densest cell. Axes with no spread
    (e.g. every path has RRPI 0) are held at their constant value. The linear fit is
    scipy.stats.linregress of RRPI on length (slope in RRPI per metre).

IoU
    Per ground-truth class, ``|pred AND gt| / |pred OR gt|`` over pixels valid in both rasters.
    The prediction is either a masks raster (one band per entity, band description = entity name;
    integer bands are positive where > 0, float bands where >= 0.5) or a single-band class raster
    with no band description, read with the same classes.json.

Everything is streamed or bounded: IoU reads row blocks, the labels for RRPI are read once
(1 byte per pixel for uint8 labels), and plots read decimated rasters.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Iterable, Mapping, Sequence

import numpy as np
from rasterio.windows import Window

from .atomic import write_text_atomic
from .errors import EvaluateError, InputError, OutputError, PlanError
from .manifest import write_json_atomic
from .progress import NullProgress, Progress, check_cancelled
from .inputs import check_class_raster
from .limits import check_pixels
from .raster import Grid, check_output_path, crs_label, open_raster, read_classes_json, read_grid

Pixel = tuple[int, int]

#: Pairs are drawn with a separation of at least this fraction of the map diagonal by default.
DEFAULT_MIN_SEPARATION_FRACTION = 0.2
#: Pixels per block when IoU streams two rasters.
IOU_BLOCK_PIXELS = 1 << 22
KDE_GRID_SIZE = 128


# --------------------------------------------------------------------------------------------
# Classes and ranks
# --------------------------------------------------------------------------------------------


def _norm(name: str) -> str:
    return " ".join(str(name).lower().split())


@dataclass(frozen=True)
class ClassTable:
    """Class ids and names of a ground-truth raster (from classes.json)."""

    names: Mapping[int, str]

    def aliases(self) -> dict[str, int]:
        """Lower-case names users may type for each class.

        Besides the full name, 'water (Hydro)' also answers to 'water' and 'hydro', as long as the
        short form names only one class.
        """
        out: dict[str, int] = {}
        seen: dict[str, set[int]] = {}
        for cid, name in self.names.items():
            full = _norm(name)
            out[full] = cid
            m = re.fullmatch(r"(.*?)\s*\((.*)\)\s*", full)
            for alias in ([m.group(1), m.group(2)] if m else []):
                if alias:
                    seen.setdefault(alias, set()).add(cid)
        for alias, ids in seen.items():
            if len(ids) == 1 and alias not in out:
                out[alias] = next(iter(ids))
        return out

    def lookup(self, key: str | int) -> int | None:
        """Class id for a name (case-insensitive, see :meth:`aliases`) or an id; None if unknown."""
        text = str(key).strip()
        if re.fullmatch(r"-?\d+", text):
            cid = int(text)
            return cid if cid in self.names else None
        return self.aliases().get(_norm(text))

    def describe(self) -> str:
        return ", ".join(f"{cid}={name}" for cid, name in sorted(self.names.items()))


def load_classes(path: str | os.PathLike) -> ClassTable:
    """Read classes.json: an object mapping class id (as text) to class name (all kept)."""
    return ClassTable(names=read_classes_json(path, EvaluateError))


@dataclass(frozen=True)
class RankTable:
    """Rank per class id (1 = most preferred) and the rank of everything unranked."""

    ranks: Mapping[int, int]
    unranked_rank: int

    def penalties(self, values: np.ndarray, nodata: float | None = None) -> np.ndarray:
        """``rank - 1`` for each class value (int64); unknown values and nodata are unranked."""
        out = np.full(values.shape, self.unranked_rank - 1, dtype=np.int64)
        for cid, rank in self.ranks.items():
            if nodata is not None and cid == nodata:
                continue
            out[values == cid] = rank - 1
        return out

    def to_json(self, classes: ClassTable) -> dict[str, Any]:
        return {"ranks": {classes.names.get(c, str(c)): r for c, r in sorted(self.ranks.items(), key=lambda kv: kv[1])},
                "unranked_rank": self.unranked_rank}


def parse_ranks(spec: str | Mapping[str, int], classes: ClassTable,
                unranked: int | str = "max") -> RankTable:
    """``'road=1,grass=2'`` (names or ids from classes.json) -> :class:`RankTable`.

    ``unranked`` is the rank of pixels whose class has no rank: ``"max"`` (the largest rank
    given, the default) or an integer >= 1.
    """
    items: list[tuple[str, str]]
    if isinstance(spec, Mapping):
        items = [(str(k), str(v)) for k, v in spec.items()]
    else:
        items = []
        for part in str(spec).split(","):
            if not part.strip():
                continue
            name, sep, value = part.rpartition("=")
            if not sep or not name.strip():
                raise EvaluateError(f"--ranks takes CLASS=RANK pairs like road=1,grass=2, not {part.strip()!r}")
            items.append((name.strip(), value.strip()))
    if not items:
        raise EvaluateError("--ranks is empty; give CLASS=RANK pairs like road=1,grass=2")
    ranks: dict[int, int] = {}
    for name, value in items:
        cid = classes.lookup(name)
        if cid is None:
            raise EvaluateError(f"--ranks: unknown class {name!r}; classes.json has {classes.describe()}")
        try:
            rank = int(value)
        except ValueError:
            raise EvaluateError(f"--ranks: rank of {name!r} must be an integer >= 1, not {value!r}") from None
        if rank < 1:
            raise EvaluateError(f"--ranks: rank of {name!r} must be >= 1 (1 = most preferred), not {rank}")
        if cid in ranks:
            raise EvaluateError(f"--ranks: class {classes.names[cid]!r} is ranked twice")
        ranks[cid] = rank
    if isinstance(unranked, str) and unranked.strip().lower() == "max":
        unranked_rank = max(ranks.values())
    else:
        try:
            unranked_rank = int(unranked)
        except (TypeError, ValueError):
            raise EvaluateError(f"--unranked-rank takes 'max' or an integer >= 1, not {unranked!r}") from None
        if unranked_rank < 1:
            raise EvaluateError(f"--unranked-rank must be >= 1, not {unranked_rank}")
    return RankTable(ranks=ranks, unranked_rank=unranked_rank)


def rrpi(labels: np.ndarray, pixels: np.ndarray, ranks: RankTable, nodata: float | None = None) -> int:
    """RRPI of a path: sum of ``rank - 1`` over its (row, col) pixels (see the module docstring)."""
    pixels = np.asarray(pixels, dtype=np.int64).reshape(-1, 2)
    if pixels.size == 0:
        return 0
    values = labels[pixels[:, 0], pixels[:, 1]]
    return int(ranks.penalties(values, nodata).sum())


# --------------------------------------------------------------------------------------------
# Rank-optimal reference
# --------------------------------------------------------------------------------------------

#: A route within this factor of the rank-optimal RRPI counts as "near optimal" in the summary.
NEAR_OPTIMAL_RATIO = 1.05


def rank_scale(ranks: RankTable) -> int:
    """K: the largest rank among the ranked classes and the unranked rank."""
    return max([ranks.unranked_rank, *ranks.ranks.values()])


def rank_costmap(labels: np.ndarray, ranks: RankTable, nodata: float | None = None) -> np.ndarray:
    """A costmap that encodes the ranks exactly: ``(rank - 1) / (K - 1)`` per pixel, float32.

    ``K`` is :func:`rank_scale` (all zeros when K == 1); unranked classes get
    ``unranked_rank``, as in :func:`rrpi`; label nodata is NaN (impassable, as nodata is to the
    planner). Built class by class into one float32 array (4 bytes per pixel, 1-byte temporaries).
    """
    k = rank_scale(ranks)
    scale = 1.0 / (k - 1) if k > 1 else 0.0
    out = np.full(labels.shape, (ranks.unranked_rank - 1) * scale, dtype=np.float32)
    for cid, rank in ranks.ranks.items():
        if nodata is not None and cid == nodata:
            continue
        out[labels == cid] = (rank - 1) * scale
    if nodata is not None and not math.isnan(nodata):
        out[labels == nodata] = np.nan
    return out


def rrpi_ratio(value: int, optimal: int) -> float:
    """``value / optimal``: 1.0 when both are 0, ``inf`` when only the optimum is 0."""
    if optimal == 0:
        return 1.0 if value == 0 else math.inf
    return value / optimal


@dataclass(frozen=True, eq=False)
class RankOptimum:
    """The rank-optimal route between two cells: its RRPI and the route itself."""

    rrpi: int
    pixels: np.ndarray  # (N, 2) (row, col)
    length_m: float
    cost: float  # on the rank costmap, base cost included


class RankOptimalPlanner:
    """Plans on :func:`rank_costmap` of the labels with the project's planner (exact mode).

    ``base_cost_per_m`` should be the evaluated planner's (default: the planner's default), so
    that both routes trade length against terrain the same way. Memory: the float32 rank costmap
    (4 bytes per pixel) plus the planner's working buffers (about 13 bytes per pixel); the labels
    are only referenced.

    The planner minimises ``sum over steps of (mean rank cost of the two cells + base) x step
    metres`` while RRPI counts pixels (a diagonal step is one pixel but 1.41 pixel lengths), so
    the route found is the planner's best on a costmap that encodes the ranks exactly, not the
    minimum-RRPI pixel chain: another route can score a somewhat lower RRPI (ratios a little
    below 1 do occur). What it guarantees instead: a costmap equal to the rank costmap scores a
    ratio of exactly 1.
    """

    def __init__(self, labels: np.ndarray, ranks: RankTable, nodata: float | None = None,
                 grid: Grid | None = None, *, base_cost_per_m: float | None = None,
                 pixel_size_m: tuple[float, float] | None = None) -> None:
        from .plan import DEFAULT_BASE_COST_PER_M, Planner, PlanningGrid

        self.labels, self.ranks, self.nodata = labels, ranks, nodata
        cost = rank_costmap(labels, ranks, nodata)
        if pixel_size_m is None:
            pixel_size_m = grid.pixel_size_m() if grid is not None else (1.0, 1.0)
        # built directly (PlanningGrid.from_array would copy the 4 bytes/pixel array once more);
        # the values are finite and in [0, 1] or NaN by construction
        self.grid = PlanningGrid(cost=cost, grid=grid, pixel_size_m=tuple(map(float, pixel_size_m)),
                                 source="rank costmap")
        self.base_cost_per_m = DEFAULT_BASE_COST_PER_M if base_cost_per_m is None else float(base_cost_per_m)
        self.planner = Planner(self.grid, self.base_cost_per_m)

    def optimum(self, start: Sequence[int], goal: Sequence[int], progress: Progress | None = None) -> RankOptimum:
        """The rank-optimal route from ``start`` to ``goal`` ((row, col)); PlanError when there is
        none (an end on label nodata, or nodata cutting them apart)."""
        res = self.planner.plan([tuple(map(int, start)), tuple(map(int, goal))], mode="exact", progress=progress)
        pixels = np.asarray(res.pixels, dtype=np.int64)
        return RankOptimum(rrpi=rrpi(self.labels, pixels, self.ranks, self.nodata), pixels=pixels,
                           length_m=float(res.length_m), cost=float(res.cost))


def rank_optimal_rrpi(labels: np.ndarray, ranks: RankTable, start: Sequence[int], goal: Sequence[int],
                      nodata: float | None = None, *, grid: Grid | None = None,
                      base_cost_per_m: float | None = None,
                      pixel_size_m: tuple[float, float] | None = None) -> int:
    """RRPI of the rank-optimal route between two (row, col) cells (see :class:`RankOptimalPlanner`;
    build that once to plan many pairs). Raises PlanError when no route exists."""
    return RankOptimalPlanner(labels, ranks, nodata, grid, base_cost_per_m=base_cost_per_m,
                              pixel_size_m=pixel_size_m).optimum(start, goal).rrpi


def summarise_ratios(values: Sequence[int], optima: Sequence[int | None]) -> dict[str, Any]:
    """Summary of route RRPI against rank-optimal RRPI over paths (None: no optimum for that path).

    ``median_ratio`` and ``worst_ratio`` are null when infinite (a route off rank 1 where the
    optimum stays on it); ``n_infinite`` counts those routes.
    """
    pairs = [(int(v), int(o)) for v, o in zip(values, optima) if o is not None]
    out: dict[str, Any] = {"n": len(pairs), "n_without_optimum": sum(o is None for o in optima)}
    if not pairs:
        return out
    ratios = np.array([rrpi_ratio(v, o) for v, o in pairs], dtype=np.float64)
    median = float(np.median(ratios))
    worst = float(ratios.max())
    out.update({"median_ratio": median if math.isfinite(median) else None,
                "share_within_5pct": float(np.mean(ratios <= NEAR_OPTIMAL_RATIO)),
                "worst_ratio": worst if math.isfinite(worst) else None,
                "best_ratio": float(ratios.min()),
                "n_infinite": int(np.isinf(ratios).sum()),
                "mean_excess_rrpi": float(np.mean([v - o for v, o in pairs]))})
    return out


# --------------------------------------------------------------------------------------------
# Path geometry
# --------------------------------------------------------------------------------------------


def to_metres(rows_cols: np.ndarray, pixel_size: tuple[float, float]) -> np.ndarray:
    """(row, col) pixel-centre coordinates -> (x, y) metres on the ground, origin at pixel (0, 0)."""
    rc = np.asarray(rows_cols, dtype=np.float64).reshape(-1, 2)
    return np.column_stack([rc[:, 1] * pixel_size[0], rc[:, 0] * pixel_size[1]])


def world_to_rowcol(grid: Grid, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """World coordinates in the grid's CRS -> fractional (row, col), integers at pixel centres."""
    cols, rows = ~grid.transform * (np.asarray(xs, dtype=np.float64), np.asarray(ys, dtype=np.float64))
    return np.column_stack([np.asarray(rows) - 0.5, np.asarray(cols) - 0.5])


def rasterise_line(rows_cols: np.ndarray) -> np.ndarray:
    """8-connected pixel chain (Bresenham, skimage.draw.line) through a polyline's vertices."""
    from skimage.draw import line

    vertices = np.floor(np.asarray(rows_cols, dtype=np.float64) + 0.5).astype(np.int64)
    if len(vertices) == 1:
        return vertices.copy()
    parts = []
    for k in range(len(vertices) - 1):
        (r0, c0), (r1, c1) = vertices[k], vertices[k + 1]
        rr, cc = line(int(r0), int(c0), int(r1), int(c1))
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
    import fiona
    from fiona.errors import FionaError
    from pyproj import CRS as ProjCRS
    from pyproj import Transformer
    from pyproj.exceptions import ProjError

    p = Path(path)
    if not p.is_file():
        raise InputError(f"no such {what} file: {p}")
    try:
        with fiona.open(p) as src:
            src_wkt = src.crs_wkt
            features = list(src)
    except (FionaError, OSError, ValueError) as exc:
        raise InputError(f"{p} is not a readable vector file ({' '.join(str(exc).split())[:160]})") from None
    try:
        src_crs = ProjCRS.from_wkt(src_wkt) if src_wkt else ProjCRS.from_epsg(4326)
        transformer = Transformer.from_crs(src_crs, ProjCRS.from_wkt(grid.crs.to_wkt()), always_xy=True)
    except ProjError as exc:
        raise EvaluateError(f"{p}: cannot reproject to the costmap CRS ({exc})") from None
    lines: list[VectorLine] = []
    for k, feat in enumerate(features):
        geom = feat.get("geometry") if hasattr(feat, "get") else feat["geometry"]
        if geom is None:
            continue
        gtype = geom["type"]
        if gtype == "LineString":
            parts = [geom["coordinates"]]
        elif gtype == "MultiLineString":
            parts = list(geom["coordinates"])
        else:
            continue
        coords = np.array([c[:2] for part in parts for c in part], dtype=np.float64)
        if len(coords) == 0:
            continue
        xs, ys = transformer.transform(coords[:, 0], coords[:, 1])
        xs, ys = np.asarray(xs), np.asarray(ys)
        if not (np.all(np.isfinite(xs)) and np.all(np.isfinite(ys))):
            raise EvaluateError(f"{p}: feature {k + 1} cannot be reprojected to {crs_label(grid.crs)}")
        props = dict(feat["properties"] or {})
        name = str(props.get("name") or props.get("id") or f"{what} {k + 1}")
        lines.append(VectorLine(name=name, rows_cols=world_to_rowcol(grid, xs, ys), properties=props))
    if not lines:
        raise EvaluateError(f"{p} holds no LineString features; {what} must be lines")
    return lines


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
    def build(cls, lines: Sequence[VectorLine], pixel_size: tuple[float, float],
              step_m: float | None = None) -> "ReferenceSet":
        from scipy.spatial import cKDTree

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
        return cls(names=tuple(line.name for line in lines), points_m=points,
                   segment_of=np.concatenate(seg_of), seg_a=np.vstack(seg_a), seg_b=np.vstack(seg_b),
                   seg_line=np.concatenate(seg_line), step_m=step, tree=cKDTree(points))

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


def map_diagonal_m(grid: Grid) -> float:
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


def matching_references(start: Sequence[float], goal: Sequence[float], references: Sequence[VectorLine],
                        pixel_size: tuple[float, float], tolerance_m: float) -> list[int]:
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


def hausdorff(pixels: np.ndarray, reference: ReferenceSet, pixel_size: tuple[float, float],
              diagonal_m: float, symmetric: bool = False) -> HausdorffResult:
    """Directed (default) or symmetric Hausdorff distance of a pixel path to the references."""
    from scipy.spatial import cKDTree

    pts = to_metres(pixels, pixel_size)
    if len(pts) == 0:
        raise EvaluateError("an empty path has no Hausdorff distance")
    d = reference.distance(pts)
    directed = float(d.max())
    reverse = None
    if symmetric:
        reverse = float(cKDTree(pts).query(reference.points_m)[0].max())
    value = max(directed, reverse) if reverse is not None else directed
    return HausdorffResult(directed_m=directed, reverse_m=reverse, hausdorff_m=value,
                           mean_m=float(d.mean()), normalised=value / diagonal_m)


# --------------------------------------------------------------------------------------------
# KDE centre of mass and linear fit
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class KdeSummary:
    """Centre of mass and mode of a KDE of (length, RRPI); grid and density kept for plotting."""

    n: int
    com: tuple[float, float]
    mode: tuple[float, float]
    note: str = ""
    xs: np.ndarray | None = None  # grid along length
    ys: np.ndarray | None = None  # grid along RRPI
    density: np.ndarray | None = None  # (len(ys), len(xs))

    def to_json(self) -> dict[str, Any]:
        return {"n": self.n, "com": {"length_m": self.com[0], "rrpi": self.com[1]},
                "mode": {"length_m": self.mode[0], "rrpi": self.mode[1]}, "note": self.note or None}


def kde_centre_of_mass(lengths: Sequence[float], values: Sequence[float],
                       grid_size: int = KDE_GRID_SIZE) -> KdeSummary:
    """KDE centre of mass and mode of 2-D points (see the module docstring for the method)."""
    from scipy.stats import gaussian_kde

    pts = np.vstack([np.asarray(lengths, dtype=np.float64), np.asarray(values, dtype=np.float64)])
    n = pts.shape[1]
    if n == 0:
        raise EvaluateError("no paths to summarise (every sampled pair was unreachable?)")
    mean = pts.mean(axis=1)
    spread = pts.std(axis=1)
    scale = np.maximum(np.abs(mean), 1.0)
    active = np.flatnonzero(spread > 1e-9 * scale)
    if n < 3 or active.size == 0:
        why = "fewer than 3 points" if n < 3 else "all points equal"
        return KdeSummary(n=n, com=(float(mean[0]), float(mean[1])), mode=(float(mean[0]), float(mean[1])),
                          note=f"KDE not defined ({why}); centre of mass is the plain mean")
    try:
        kde = gaussian_kde(pts[active])
    except np.linalg.LinAlgError:
        # Perfectly correlated axes: the KDE's covariance is singular. Fall back to the mean.
        return KdeSummary(n=n, com=(float(mean[0]), float(mean[1])), mode=(float(mean[0]), float(mean[1])),
                          note="KDE singular (points on a line); centre of mass is the plain mean")
    sd = np.sqrt(np.diag(np.atleast_2d(kde.covariance)))
    axes = []
    for k, dim in enumerate(active):
        lo = max(pts[dim].min() - 3 * sd[k], 0.0)
        hi = pts[dim].max() + 3 * sd[k]
        axes.append(np.linspace(lo, hi, grid_size))
    mesh = np.meshgrid(*axes, indexing="ij")
    dens = kde(np.vstack([m.ravel() for m in mesh])).reshape(mesh[0].shape)
    total = dens.sum()
    com, mode = mean.copy(), mean.copy()
    peak = np.unravel_index(np.argmax(dens), dens.shape)
    for k, dim in enumerate(active):
        com[dim] = float((mesh[k] * dens).sum() / total)
        mode[dim] = float(mesh[k][peak])
    xs = ys = density = None
    if active.size == 2:
        xs, ys, density = axes[0], axes[1], dens.T
    note = "" if active.size == 2 else \
        f"{'length' if 0 not in active else 'RRPI'} is the same for every path; KDE is 1-D"
    return KdeSummary(n=n, com=(float(com[0]), float(com[1])), mode=(float(mode[0]), float(mode[1])),
                      note=note, xs=xs, ys=ys, density=density)


@dataclass(frozen=True)
class LinearFit:
    """RRPI = slope * length_m + intercept (scipy.stats.linregress)."""

    slope: float  # RRPI per metre
    intercept: float
    r: float
    p: float
    stderr: float
    n: int


def linear_fit(lengths: Sequence[float], values: Sequence[float]) -> LinearFit | None:
    """Least-squares line of RRPI on path length; None with fewer than 2 distinct lengths."""
    from scipy.stats import linregress

    x = np.asarray(lengths, dtype=np.float64)
    y = np.asarray(values, dtype=np.float64)
    if len(x) < 2 or np.ptp(x) == 0:
        return None
    res = linregress(x, y)
    r = float(res.rvalue) if np.isfinite(res.rvalue) else 0.0
    p = float(res.pvalue) if np.isfinite(res.pvalue) else 1.0
    return LinearFit(slope=float(res.slope), intercept=float(res.intercept), r=r, p=p,
                     stderr=float(res.stderr), n=len(x))


# --------------------------------------------------------------------------------------------
# Sampling start-goal pairs
# --------------------------------------------------------------------------------------------


def sample_pairs(passable: np.ndarray, n: int, rng: np.random.Generator, min_separation_m: float,
                 pixel_size: tuple[float, float], max_tries: int = 200_000) -> list[tuple[Pixel, Pixel]]:
    """``n`` start-goal pairs drawn uniformly over passable cells, at least ``min_separation_m`` apart.

    Cells are drawn uniformly over the whole grid and kept when passable (rejection sampling),
    so no index array of the valid cells is built (100 M cells would cost 800 MB); when fewer
    than 1 % of the cells are passable the valid cells are listed once instead. Same seed, same
    pairs. May return fewer than ``n`` pairs when the separation is hard to meet.
    """
    h, w = passable.shape
    n_valid = int(np.count_nonzero(passable))
    if n_valid < 2:
        raise EvaluateError("the costmap has fewer than 2 passable cells; nothing to sample")
    px, py = pixel_size
    max_dist = math.hypot((h - 1) * py, (w - 1) * px)
    if min_separation_m > max_dist:
        raise EvaluateError(f"--min-separation {min_separation_m:g} m is longer than the map diagonal "
                            f"({max_dist:.1f} m)")
    flat = passable.ravel()
    listed = np.flatnonzero(flat) if n_valid < 0.01 * flat.size else None
    batch = 256

    def draw() -> np.ndarray:
        if listed is not None:
            return listed[rng.integers(0, len(listed), size=batch)]
        cand = rng.integers(0, flat.size, size=batch)
        return cand[flat[cand]]

    pairs: list[tuple[Pixel, Pixel]] = []
    tries = 0
    while len(pairs) < n and tries < max_tries:
        starts = draw()
        tries += batch
        if starts.size == 0:
            continue
        sr, sc = divmod(int(starts[0]), w)
        for _ in range(8):  # a few batches of goals per start, then draw a new start
            goals = draw()
            tries += batch
            gr, gc = np.divmod(goals, w)
            far = np.hypot((gr - sr) * py, (gc - sc) * px) >= min_separation_m
            if far.any():
                k = int(np.argmax(far))
                pairs.append(((sr, sc), (int(gr[k]), int(gc[k]))))
                break
    return pairs


# --------------------------------------------------------------------------------------------
# IoU
# --------------------------------------------------------------------------------------------


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
        return {"class_id": self.class_id, "name": self.name, "bands": list(self.bands), "tp": self.tp,
                "fp": self.fp, "fn": self.fn, "iou": self.iou}


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
        return {"mode": self.mode, "mean_iou": self.mean_iou, "valid_pixels": self.valid_pixels,
                "classes": [c.to_json() for c in self.classes],
                "unmatched_bands": list(self.unmatched_bands),
                "missing_classes": list(self.missing_classes)}


def parse_matches(items: Iterable[str]) -> list[tuple[str, str]]:
    """``['road=paved road', ...]`` -> [(ground-truth class, mask band name), ...]."""
    out = []
    for item in items or ():
        gt, sep, band = str(item).partition("=")
        if not sep or not gt.strip() or not band.strip():
            raise EvaluateError(f"--match takes CLASS=BAND like 'road=paved road', not {item!r}")
        out.append((gt.strip(), band.strip()))
    return out


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
    raise EvaluateError(f"{what_a} and {what_b} are on different grids ({why}); "
                        f"resample one onto the other's grid first")


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


def compute_iou(pred_path: str | os.PathLike, labels_path: str | os.PathLike, classes: ClassTable,
                matches: Sequence[tuple[str, str]] = (), mask_threshold: float | None = None,
                progress: Progress | None = None) -> IoUResult:
    """Per-class IoU of a masks raster (or a class raster) against a ground-truth class raster.

    Streams both rasters in row blocks (memory independent of the image size). See the module
    docstring for which prediction pixels count as positive.
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
                raise EvaluateError("--match needs a masks raster with named bands; "
                                    f"{pred_path} is a single-band class raster read with classes.json")
            assign = {cid: [] for cid in ids}
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
    per_class = tuple(ClassIoU(class_id=c, name=classes.names[c],
                               bands=tuple(band_names[b] for b in assign.get(c, [])),
                               tp=tp[c], fp=fp[c], fn=fn[c]) for c in used)
    return IoUResult(mode="classes" if class_mode else "masks", classes=per_class,
                     unmatched_bands=tuple(unmatched), missing_classes=tuple(missing),
                     valid_pixels=valid_total)


def _assign_bands(band_names: Sequence[str], classes: ClassTable,
                  matches: Sequence[tuple[str, str]]) -> tuple[dict[int, list[int]], list[str]]:
    """Which mask bands predict which class: explicit --match pairs first, then equal names."""
    by_name = {}
    for i, name in enumerate(band_names):
        by_name.setdefault(_norm(name), []).append(i)
    assign: dict[int, list[int]] = {}
    claimed: set[int] = set()
    for gt_name, band in matches:
        cid = classes.lookup(gt_name)
        if cid is None:
            raise EvaluateError(f"--match: unknown class {gt_name!r}; classes.json has {classes.describe()}")
        bands = by_name.get(_norm(band))
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


# --------------------------------------------------------------------------------------------
# The evaluate stage: sample, plan, measure, plot, report
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class EvaluateOptions:
    """What `overseec eval` was asked to do. Every input is optional; each metric runs when its
    inputs are there (IoU: masks + labels + classes; RRPI: labels + classes + ranks; sampling:
    costmap; Hausdorff: reference paths)."""

    out_dir: Path
    labels: Path | None = None
    classes: Path | None = None
    ranks: str | Mapping[str, int] | None = None
    unranked_rank: int | str = "max"
    costmap: Path | None = None
    pairs: int = 50
    seed: int = 0
    min_separation_m: float | None = None
    plan_mode: str = "exact"
    reference: Path | None = None
    paths: Path | None = None
    symmetric: bool = False
    masks: Path | None = None
    matches: tuple[str, ...] = ()
    mask_threshold: float | None = None
    image: Path | None = None
    plots: bool = True
    plot_size: int = 1600

    def inputs(self) -> dict[str, Path]:
        """Input files by role (for the manifest and the never-overwrite check)."""
        roles = ("labels", "classes", "costmap", "reference", "paths", "masks", "image")
        return {r: Path(getattr(self, r)) for r in roles if getattr(self, r) is not None}


@dataclass(frozen=True, eq=False)
class EvaluatedPath:
    """One system path and its figures; ``pixels`` is its (N, 2) (row, col) chain."""

    name: str
    #: "sampled" (random pair), "reference-ends" (planned between a reference's ends),
    #: "given" (--paths) or "reference" (a reference path itself, for its RRPI and cost)
    group: str
    pixels: np.ndarray
    length_m: float
    cost: float | None = None
    mode: str | None = None
    rrpi: int | None = None
    hausdorff: HausdorffResult | None = None
    #: RRPI of the rank-optimal route between the same ends (None: not computed or no route)
    rrpi_optimal: int | None = None
    #: whether the rank-optimal route was looked for (ranks given)
    rank_optimal_ran: bool = False
    #: names of the reference paths of the same start and goal; None when there are no
    #: references (and for a reference path itself)
    references: tuple[str, ...] | None = None

    @property
    def ratio(self) -> float | None:
        """RRPI / rank-optimal RRPI (inf when only the optimum is 0); None without both."""
        if self.rrpi is None or self.rrpi_optimal is None:
            return None
        return rrpi_ratio(self.rrpi, self.rrpi_optimal)

    def to_json(self, grid: Grid) -> dict[str, Any]:
        start, goal = self.pixels[0], self.pixels[-1]
        out: dict[str, Any] = {"name": self.name, "group": self.group,
                               "start": _point_json(grid, start), "goal": _point_json(grid, goal),
                               "length_m": self.length_m, "pixels": int(len(self.pixels)),
                               "cost": self.cost, "mode": self.mode, "rrpi": self.rrpi}
        if self.rrpi is not None:
            out["rrpi_per_pixel"] = self.rrpi / len(self.pixels)
        if self.rank_optimal_ran:
            ratio = self.ratio
            out["rrpi_optimal"] = self.rrpi_optimal
            out["rrpi_ratio"] = ratio if ratio is not None and math.isfinite(ratio) else None
            out["rrpi_ratio_infinite"] = ratio is not None and math.isinf(ratio)
        if self.references is not None:
            out["hausdorff"] = None if self.hausdorff is None else asdict(self.hausdorff)
            out["hausdorff_references"] = list(self.references)
        elif self.hausdorff is not None:
            out["hausdorff"] = asdict(self.hausdorff)
        return out


@dataclass(frozen=True)
class EvaluateResult:
    """The figures (as written to metrics.json) and the files written."""

    metrics: Mapping[str, Any]
    files: Mapping[str, Path]


def _point_json(grid: Grid, rc: Sequence[int]) -> dict[str, Any]:
    r, c = int(rc[0]), int(rc[1])
    x, y = grid.transform * (c + 0.5, r + 0.5)
    return {"row": r, "col": c, "x": float(x), "y": float(y)}


def check_options(o: EvaluateOptions) -> None:
    """One-line InputErrors for options that cannot work together or files that do not exist."""
    if o.ranks is not None and (o.labels is None or o.classes is None):
        raise InputError("--ranks needs --labels (class raster) and --classes (classes.json)")
    if o.masks is not None and (o.labels is None or o.classes is None):
        raise InputError("--masks needs --labels (ground-truth class raster) and --classes")
    if o.labels is not None and o.classes is None:
        raise InputError("--labels needs --classes (classes.json: class id -> name)")
    if o.pairs < 0:
        raise InputError(f"--pairs must be >= 0, not {o.pairs}")
    if o.min_separation_m is not None and o.min_separation_m < 0:
        raise InputError(f"--min-separation must be >= 0 metres, not {o.min_separation_m:g}")
    if o.matches and o.masks is None:
        raise InputError("--match needs --masks")
    if o.image is not None and o.costmap is None:
        raise InputError("--image is drawn under the costmap; give --costmap too")
    nothing = o.masks is None and o.costmap is None and o.paths is None
    if nothing:
        raise InputError("nothing to evaluate: give --costmap (paths, RRPI, Hausdorff), "
                         "--paths (given paths) or --masks (IoU)")
    if o.paths is not None and o.costmap is None and o.labels is None:
        raise InputError("--paths needs --costmap or --labels to place the paths on a grid")
    for role, path in o.inputs().items():
        if not Path(path).exists():
            raise InputError(f"no such file for --{role}: {path}")
    for role in ("labels", "costmap"):
        path = getattr(o, role)
        if path is not None:
            grid = read_grid(path)
            check_pixels(grid.width, grid.height, path, role)
    # cheap content checks, so that a mistake fails before any output is made
    classes = load_classes(o.classes) if o.classes is not None else None
    if classes is not None and o.labels is not None:
        check_class_raster(o.labels, classes.names)  # warnings: IoU reports absent classes itself
    if o.ranks is not None:
        parse_ranks(o.ranks, classes, o.unranked_rank)
    parse_matches(o.matches)
    if o.costmap is not None:
        from .plan import MODES

        if o.plan_mode not in MODES:
            raise InputError(f"unknown planning mode {o.plan_mode!r}; use {' or '.join(MODES)}")
        if o.labels is not None:
            check_same_grid(read_grid(o.costmap), read_grid(o.labels), f"costmap {o.costmap}", f"labels {o.labels}")
    if o.masks is not None:
        check_same_grid(read_grid(o.labels), read_grid(o.masks), f"labels {o.labels}", f"masks {o.masks}")


def _output_paths(o: EvaluateOptions) -> dict[str, Path]:
    out = Path(o.out_dir)
    if out.exists() and not out.is_dir():
        raise OutputError(f"--out {out} exists and is not a folder")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"cannot create output folder {out} ({exc.strerror})") from None
    names = {"metrics": "metrics.json", "report": "report.md", "pairs_csv": "pairs.csv",
             "paths_geojson": "paths.geojson", "rrpi_plot": "rrpi_vs_length.png",
             "overlay_plot": "paths_overlay.png", "iou_plot": "iou.png"}
    files = {k: out / v for k, v in names.items()}
    inputs = list(o.inputs().values())
    for f in files.values():
        check_output_path(f, inputs)
    return files


def _read_labels(path: Path, grid: Grid) -> tuple[np.ndarray, float | None]:
    check_same_grid(grid, read_grid(path), "the costmap", f"labels {path}")
    with open_raster(path) as ds:
        if ds.dtypes[0][0] not in "ui":
            raise EvaluateError(f"labels {path} must hold integer class ids, not {ds.dtypes[0]}")
        return ds.read(1), ds.nodata


def _planned(name: str, group: str, res: Any) -> EvaluatedPath:
    return EvaluatedPath(name=name, group=group, pixels=np.asarray(res.pixels, dtype=np.int64),
                         length_m=float(res.length_m), cost=float(res.cost), mode=str(res.mode))


class _CancelOnly(NullProgress):
    """Forwards only cancellation to the planner, so its per-query bars do not replace ours."""

    def __init__(self, outer: Progress) -> None:
        super().__init__()
        self._outer = outer

    def cancelled(self) -> bool:
        return self._outer.cancelled()


def _sample_and_plan(rules: Any, o: EvaluateOptions, grid: Grid, progress: Progress
                     ) -> tuple[list[EvaluatedPath], dict[str, Any]]:
    """Draw ``o.pairs`` seeded pairs over passable cells and plan each; unreachable ones are listed."""
    sep = o.min_separation_m if o.min_separation_m is not None \
        else DEFAULT_MIN_SEPARATION_FRACTION * map_diagonal_m(grid)
    pairs = sample_pairs(rules.grid.passable, o.pairs, np.random.default_rng(o.seed), sep,
                         grid.pixel_size_m())
    paths: list[EvaluatedPath] = []
    unreachable: list[dict[str, Any]] = []
    broken_before = rules.rules_broken
    inner = _CancelOnly(progress)
    progress.begin("evaluate: planning", len(pairs), unit="pair")
    for k, (start, goal) in enumerate(pairs):
        check_cancelled(progress)
        try:
            res, _ = rules.plan([start, goal], mode=o.plan_mode, progress=inner)
            paths.append(_planned(f"pair {k + 1}", "sampled", res))
        except PlanError as exc:
            unreachable.append({"name": f"pair {k + 1}", "start": _point_json(grid, start),
                                "goal": _point_json(grid, goal), "error": str(exc)})
        progress.advance()
    progress.end()
    sampling = {"seed": o.seed, "requested": o.pairs, "drawn": len(pairs), "planned": len(paths),
                "min_separation_m": sep, "mode": o.plan_mode, "unreachable": unreachable,
                "rules_not_met": rules.rules_broken - broken_before}
    return paths, sampling


def _drawn_paths(lines: Sequence[VectorLine], group: str, grid: Grid, planner: Any | None,
                 source: Path, notes: list[str]) -> list[EvaluatedPath]:
    """Lines rasterised to pixel chains, priced on the costmap when there is one.

    Given paths (``group == "given"``) must lie inside the grid; reference paths that leave it
    are only noted (they still count for the Hausdorff distance).
    """
    from .plan import path_length_m

    dx, dy = grid.pixel_size_m()
    out = []
    for line in lines:
        chain = rasterise_line(line.rows_cols)
        inside = ((chain >= 0) & (chain < (grid.height, grid.width))).all()
        if not inside:
            if group == "given":
                raise EvaluateError(f"path {line.name!r} in {source} leaves the costmap's extent")
            notes.append(f"reference {line.name!r} leaves the grid; it has no RRPI or cost")
            continue
        cost = planner.path_cost(chain) if planner is not None else None
        if cost is not None and not math.isfinite(cost):
            notes.append(f"{group} path {line.name!r} crosses impassable cells of the costmap")
            cost = None
        out.append(EvaluatedPath(name=line.name, group=group, pixels=chain,
                                 length_m=path_length_m(chain, dx, dy), cost=cost))
    return out


def _reference_plans(rules: Any, references: Sequence[VectorLine], mode: str,
                     notes: list[str]) -> list[EvaluatedPath]:
    """Plan between the first and last vertex of each reference path (keep-out zones entered
    only when they must be, as for sampled pairs)."""
    out = []
    for line in references:
        ends = np.floor(line.rows_cols[[0, -1]] + 0.5).astype(np.int64)
        try:
            res, _ = rules.plan([tuple(map(int, ends[0])), tuple(map(int, ends[1]))], mode=mode)
        except PlanError as exc:
            notes.append(f"no plan between the ends of reference {line.name!r}: {exc}")
            continue
        out.append(_planned(f"plan along {line.name}", "reference-ends", res))
    return out


def evaluate(options: EvaluateOptions, progress: Progress | None = None) -> EvaluateResult:
    """Run every metric the inputs allow and write metrics.json, report.md, pairs.csv,
    paths.geojson and the PNG plots into ``options.out_dir`` (created if missing)."""
    o = options
    progress = progress or NullProgress()
    check_options(o)
    files = _output_paths(o)
    metrics: dict[str, Any] = {"inputs": {k: str(v) for k, v in o.inputs().items()},
                               "definitions": DEFINITIONS, "notes": []}
    notes: list[str] = metrics["notes"]
    classes = load_classes(o.classes) if o.classes is not None else None
    ranks = parse_ranks(o.ranks, classes, o.unranked_rank) if o.ranks is not None else None
    if ranks is not None:
        metrics["ranks"] = ranks.to_json(classes)

    iou = None
    if o.masks is not None:
        iou = compute_iou(o.masks, o.labels, classes, parse_matches(o.matches), o.mask_threshold, progress)
        metrics["iou"] = iou.to_json()

    paths: list[EvaluatedPath] = []
    references: list[VectorLine] = []
    kde = fit = None
    grid = None
    cost_preview = None
    if o.costmap is not None or o.paths is not None:
        grid = read_grid(o.costmap if o.costmap is not None else o.labels)
        metrics["grid"] = {"crs": crs_label(grid.crs), "width": grid.width, "height": grid.height,
                           "pixel_size_m": list(grid.pixel_size_m()), "diagonal_m": map_diagonal_m(grid)}
        if o.reference is not None:
            references = read_lines(o.reference, grid, what="reference path")
        planner = None
        base_cost_per_m = None
        if o.costmap is not None:
            from .plan import Planner, load_costmap
            from .plan.stage import RulePlanner

            planner = Planner(load_costmap(o.costmap))
            rules = RulePlanner(planner)  # one relaxed copy at most, shared by all queries
            base_cost_per_m = planner.base_cost_per_m
            if o.pairs > 0:
                sampled, metrics["sampling"] = _sample_and_plan(rules, o, grid, progress)
                paths += sampled
                if metrics["sampling"]["drawn"] < o.pairs:
                    notes.append(f"only {metrics['sampling']['drawn']} of {o.pairs} pairs could be drawn "
                                 f"{metrics['sampling']['min_separation_m']:.1f} m apart; "
                                 "lower --min-separation for more")
            if references and o.paths is None:
                paths += _reference_plans(rules, references, o.plan_mode, notes)
        if o.paths is not None:
            paths += _drawn_paths(read_lines(o.paths, grid, what="path"), "given", grid, planner, o.paths, notes)
        paths += _drawn_paths(references, "reference", grid, planner, o.reference, notes)
        if planner is not None and o.plots:
            from .plots import cost_preview_from_array

            cost_preview = cost_preview_from_array(planner.grid.cost, o.plot_size)
        # the costmap and its planner are done with: free them before the rank planner is built
        planner = None
        labels, nodata = _read_labels(o.labels, grid) if ranks is not None else (None, None)
        paths = _measure_all(paths, o, grid, ranks, labels, nodata, references)
        if labels is not None and paths:
            paths, metrics["rank_optimal"] = _rank_optimal(paths, labels, ranks, nodata, grid, base_cost_per_m,
                                                           progress, notes)
        labels = None
        metrics["paths"] = [p.to_json(grid) for p in paths]
        metrics["summary"] = _summaries(paths)
        if references:
            metrics["hausdorff"] = _hausdorff_summary(paths, references, o.symmetric, grid)
        sampled = [p for p in paths if p.group == "sampled" and p.rrpi is not None]
        if sampled:
            kde = kde_centre_of_mass([p.length_m for p in sampled], [p.rrpi for p in sampled])
            fit = linear_fit([p.length_m for p in sampled], [p.rrpi for p in sampled])
            metrics["kde"] = kde.to_json()
            metrics["fit"] = None if fit is None else {**asdict(fit), "unit": "RRPI per metre"}

    written: dict[str, Path] = {}
    if o.plots:
        written.update(_write_plots(o, files, grid, paths, references, kde, fit, iou, cost_preview))
    if paths:
        written["pairs_csv"] = _write_csv(files["pairs_csv"], paths)
        written["paths_geojson"] = _write_geojson(files["paths_geojson"], paths, grid)
    metrics["files"] = {k: v.name for k, v in written.items()}
    written["metrics"] = write_json_atomic(files["metrics"], metrics)
    written["report"] = write_text_atomic(files["report"], render_report(metrics))
    return EvaluateResult(metrics=metrics, files=written)


def _measure_all(paths: Sequence[EvaluatedPath], o: EvaluateOptions, grid: Grid, ranks: RankTable | None,
                 labels: np.ndarray | None, nodata: float | None,
                 references: Sequence[VectorLine]) -> list[EvaluatedPath]:
    """RRPI of every path (with ranks) and, for every system path whose start and goal match a
    reference path's ends, its Hausdorff distance to the reference paths of that pair."""
    from dataclasses import replace

    pixel_size = grid.pixel_size_m()
    diagonal = map_diagonal_m(grid)
    tolerance = endpoint_tolerance_m(grid)
    refsets: dict[tuple[int, ...], ReferenceSet] = {}
    out = []
    for p in paths:
        value = rrpi(labels, p.pixels, ranks, nodata) if labels is not None and ranks is not None else None
        hd = None
        matched = None
        if references and p.group != "reference":
            idx = tuple(matching_references(p.pixels[0], p.pixels[-1], references, pixel_size, tolerance))
            matched = tuple(references[i].name for i in idx)
            if idx:
                if idx not in refsets:
                    refsets[idx] = ReferenceSet.build([references[i] for i in idx], pixel_size)
                hd = hausdorff(p.pixels, refsets[idx], pixel_size, diagonal, o.symmetric)
        out.append(replace(p, rrpi=value, hausdorff=hd, references=matched))
    return out


def _rank_optimal(paths: Sequence[EvaluatedPath], labels: np.ndarray, ranks: RankTable, nodata: float | None,
                  grid: Grid, base_cost_per_m: float | None, progress: Progress,
                  notes: list[str]) -> tuple[list[EvaluatedPath], dict[str, Any]]:
    """The rank-optimal RRPI between the ends of every path with an RRPI, and its summary."""
    from dataclasses import replace

    try:
        ropt = RankOptimalPlanner(labels, ranks, nodata, grid, base_cost_per_m=base_cost_per_m)
    except ImportError as exc:  # the planner's native kernel is not built
        notes.append(f"no rank-optimal reference: the planner is not available ({exc})")
        return list(paths), {"groups": {}, "headline": None, "error": str(exc)}
    inner = _CancelOnly(progress)
    out: list[EvaluatedPath] = []
    failed: list[str] = []
    progress.begin("evaluate: rank-optimal routes", sum(p.rrpi is not None for p in paths), unit="path")
    for p in paths:
        if p.rrpi is None:
            out.append(p)
            continue
        check_cancelled(progress)
        try:
            best = ropt.optimum(p.pixels[0], p.pixels[-1], progress=inner).rrpi
        except PlanError:
            best = None
            failed.append(p.name)
        out.append(replace(p, rrpi_optimal=best, rank_optimal_ran=True))
        progress.advance()
    progress.end()
    if failed:
        shown = ", ".join(repr(n) for n in failed[:5]) + (" ..." if len(failed) > 5 else "")
        notes.append(f"no rank-optimal route for {len(failed)} path(s) (an end on label nodata, or nodata "
                     f"between the ends): {shown}")
    groups = {}
    for group in dict.fromkeys(p.group for p in out):
        members = [p for p in out if p.group == group and p.rrpi is not None]
        if members:
            groups[group] = summarise_ratios([p.rrpi for p in members], [p.rrpi_optimal for p in members])
    headline = next((g for g in ("sampled", "reference-ends", "given", "reference")
                     if groups.get(g, {}).get("n")), None)
    k = rank_scale(ranks)
    summary = {"rank_scale": k, "cost": f"(rank - 1) / {k - 1}" if k > 1 else "0",
               "base_cost_per_m": ropt.base_cost_per_m, "mode": "exact",
               "near_optimal_ratio": NEAR_OPTIMAL_RATIO, "headline": headline, "groups": groups}
    return out, summary


def _summaries(paths: Sequence[EvaluatedPath]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for group in dict.fromkeys(p.group for p in paths):
        members = [p for p in paths if p.group == group]
        s: dict[str, Any] = {"n": len(members),
                             "mean_length_m": float(np.mean([p.length_m for p in members]))}
        if members[0].rrpi is not None:
            s["mean_rrpi"] = float(np.mean([p.rrpi for p in members]))
            s["mean_rrpi_per_pixel"] = float(np.mean([p.rrpi / len(p.pixels) for p in members]))
        measured = [p for p in members if p.hausdorff is not None]
        if any(p.references is not None for p in members):
            s["n_hausdorff"] = len(measured)
        if measured:
            s["mean_hausdorff_normalised"] = float(np.mean([p.hausdorff.normalised for p in measured]))
            s["mean_hausdorff_m"] = float(np.mean([p.hausdorff.hausdorff_m for p in measured]))
        out[group] = s
    return out


def _hausdorff_summary(paths: Sequence[EvaluatedPath], references: Sequence[VectorLine], symmetric: bool,
                       grid: Grid) -> dict[str, Any]:
    """How many paths matched a reference pair, per group, and the headline figure: the mean
    normalised Hausdorff over the matched given paths, else reference-end plans, else sampled
    pairs (the first group with a match)."""
    matched = {}
    for group in dict.fromkeys(p.group for p in paths if p.group != "reference"):
        members = [p for p in paths if p.group == group]
        matched[group] = {"matched": sum(p.hausdorff is not None for p in members), "paths": len(members)}
    out: dict[str, Any] = {"references": [line.name for line in references],
                           "kind": "symmetric" if symmetric else "directed",
                           "sample_step_m": min(grid.pixel_size_m()) / 4.0,
                           "endpoint_tolerance_m": endpoint_tolerance_m(grid), "matched": matched}
    for group in ("given", "reference-ends", "sampled"):
        members = [p for p in paths if p.group == group and p.hausdorff is not None]
        if members:
            break
    else:
        out.update({"paths": None, "n": 0, "mean_normalised": None})
        return out
    out.update({"paths": group, "n": len(members), "n_paths": matched[group]["paths"],
                "mean_normalised": float(np.mean([p.hausdorff.normalised for p in members])),
                "mean_m": float(np.mean([p.hausdorff.hausdorff_m for p in members])),
                "mean_point_distance_m": float(np.mean([p.hausdorff.mean_m for p in members]))})
    return out


def _plot_tag(p: EvaluatedPath) -> str:
    """What the overlay writes beside a path's start and goal: the pair number, else its name."""
    m = re.fullmatch(r"pair (\d+)", p.name)
    if m:
        return m.group(1)
    return p.name if len(p.name) <= 14 else p.name[:13] + "…"


def _write_plots(o: EvaluateOptions, files: Mapping[str, Path], grid: Grid | None,
                 paths: Sequence[EvaluatedPath], references: Sequence[VectorLine], kde, fit,
                 iou: IoUResult | None, cost_preview: Any = None) -> dict[str, Path]:
    from . import plots

    written: dict[str, Path] = {}
    sampled = [p for p in paths if p.group == "sampled" and p.rrpi is not None]
    if sampled:
        written["rrpi_plot"] = plots.plot_rrpi_vs_length(
            files["rrpi_plot"], [p.length_m for p in sampled], [p.rrpi for p in sampled], kde, fit,
            title=f"RRPI vs path length ({len(sampled)} sampled pairs)")
    if grid is not None and (paths or references) and (o.costmap is not None or o.image is not None or paths):
        draw = [plots.PlotPath(line.rows_cols, kind="reference") for line in references]
        system = [p for p in paths if p.group != "reference"]
        draw += [plots.PlotPath(p.pixels, tag=_plot_tag(p)) for p in system]
        written["overlay_plot"] = plots.plot_paths_overlay(
            files["overlay_plot"], grid, draw, costmap=o.costmap if cost_preview is None else None,
            image=o.image, max_size=o.plot_size, cost=cost_preview,
            title=f"{len(system)} path(s) on {Path(o.costmap).name if o.costmap else 'the grid'}")
    if iou is not None and iou.classes:
        written["iou_plot"] = plots.plot_iou(files["iou_plot"], [c.name for c in iou.classes],
                                             [c.iou for c in iou.classes], iou.mean_iou)
    return written


def _ratio_text(ratio: float | None) -> str:
    if ratio is None:
        return ""
    return "inf" if math.isinf(ratio) else f"{ratio:.4f}"


def _write_csv(path: Path, paths: Sequence[EvaluatedPath]) -> Path:
    import csv
    import io

    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["name", "group", "start_row", "start_col", "goal_row", "goal_col", "length_m", "pixels",
                "cost", "mode", "rrpi", "hausdorff_m", "hausdorff_normalised", "mean_distance_m",
                "rrpi_optimal", "rrpi_ratio", "hausdorff_references"])
    for p in paths:
        hd = p.hausdorff
        w.writerow([p.name, p.group, *map(int, p.pixels[0]), *map(int, p.pixels[-1]), f"{p.length_m:.3f}",
                    len(p.pixels), "" if p.cost is None else f"{p.cost:.6g}", p.mode or "",
                    "" if p.rrpi is None else p.rrpi, "" if hd is None else f"{hd.hausdorff_m:.3f}",
                    "" if hd is None else f"{hd.normalised:.6f}", "" if hd is None else f"{hd.mean_m:.3f}",
                    "" if p.rrpi_optimal is None else p.rrpi_optimal, _ratio_text(p.ratio),
                    "" if p.references is None else ";".join(p.references)])
    return write_text_atomic(path, buf.getvalue())


def _write_geojson(path: Path, paths: Sequence[EvaluatedPath], grid: Grid) -> Path:
    """Evaluated paths as RFC 7946 GeoJSON (WGS 84 lon/lat) LineStrings with their figures,
    written compactly like the plan stage's paths (plan.export)."""
    from pyproj import CRS as ProjCRS
    from pyproj import Transformer

    from .plan.export import LONLAT_DECIMALS, write_geojson

    to_wgs84 = Transformer.from_crs(ProjCRS.from_wkt(grid.crs.to_wkt()), ProjCRS.from_epsg(4326), always_xy=True)
    features = []
    for p in paths:
        xs, ys = grid.transform * (p.pixels[:, 1] + 0.5, p.pixels[:, 0] + 0.5)
        lon, lat = to_wgs84.transform(np.asarray(xs), np.asarray(ys))
        coords = np.round(np.column_stack([lon, lat]), LONLAT_DECIMALS).tolist()
        if len(coords) == 1:
            coords = coords * 2
        props = {k: v for k, v in p.to_json(grid).items() if k not in ("start", "goal")}
        features.append({"type": "Feature", "properties": props,
                         "geometry": {"type": "LineString", "coordinates": coords}})
    return write_geojson(path, {"type": "FeatureCollection", "features": features})


DEFINITIONS = {
    "rrpi": "sum over path pixels of (rank - 1); unranked classes and nodata count as unranked_rank",
    "hausdorff": "max over path pixels of the distance (m) to the union of the reference paths of the same "
                 "start and goal (both ends within max(3 px, 1 % of the map diagonal), either direction; "
                 "paths without one get null) (directed; symmetric adds the reverse direction), divided by "
                 "the map diagonal (m)",
    "rrpi_optimal": "RRPI of the exact-mode route between the same ends on a costmap of (rank - 1) / (K - 1), "
                    "K = the largest rank incl. the unranked rank (label nodata impassable), with the same "
                    "base cost per metre; rrpi_ratio = rrpi / rrpi_optimal (1 when both are 0; infinite when "
                    "only the optimum is 0: written null with rrpi_ratio_infinite true)",
    "kde_com": "density-weighted mean of a Gaussian KDE of (length_m, rrpi) over a grid spanning the data "
               "+/- 3 kernel sd, clipped at 0; mode = densest grid cell",
    "fit": "scipy.stats.linregress of rrpi on length_m (slope in RRPI per metre)",
    "iou": "per ground-truth class |pred & gt| / |pred | gt| over pixels valid in both rasters",
}


def _fmt(value: Any, digits: int = 4) -> str:
    if value is None:
        return "n/a"
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    return str(value)


def render_report(metrics: Mapping[str, Any]) -> str:
    """A short Markdown report of metrics.json, linking the PNG plots beside it."""
    lines = ["# overseec evaluation", ""]
    files = metrics.get("files", {})
    inputs = metrics.get("inputs", {})
    if inputs:
        lines += ["Inputs: " + ", ".join(f"{k} `{Path(v).name}`" for k, v in inputs.items()), ""]
    if "ranks" in metrics:
        r = metrics["ranks"]
        lines += ["Ranks: " + ", ".join(f"{k}={v}" for k, v in r["ranks"].items())
                  + f"; unranked = {r['unranked_rank']}", ""]
    s = metrics.get("sampling")
    if s:
        lines += ["## Sampled start-goal pairs", "",
                  f"{s['planned']} of {s['drawn']} pairs planned ({s['mode']} mode, seed {s['seed']}, "
                  f"at least {s['min_separation_m']:.1f} m apart); {len(s['unreachable'])} unreachable."]
        if s.get("rules_not_met"):
            lines += [f"**{s['rules_not_met']} of them could not keep a distance rule**: no route "
                      "between their points avoids the rule's keep-out zone, so they enter it as "
                      "little as they can."]
        lines += [""]
    kde, fit = metrics.get("kde"), metrics.get("fit")
    if kde:
        lines += [f"- KDE centre of mass: length **{kde['com']['length_m']:.1f} m**, "
                  f"RRPI **{kde['com']['rrpi']:.2f}** (mode {kde['mode']['length_m']:.1f} m, "
                  f"{kde['mode']['rrpi']:.2f}){'; ' + kde['note'] if kde.get('note') else ''}"]
    if fit:
        sign = "-" if fit["intercept"] < 0 else "+"
        lines += [f"- Linear fit: RRPI = {fit['slope']:.4g} x length_m {sign} {abs(fit['intercept']):.4g} "
                  f"(r = {fit['r']:.3f}, n = {fit['n']})"]
    elif kde:
        lines += ["- Linear fit: n/a (fewer than 2 distinct lengths)"]
    if kde or fit:
        lines += [""]
    if "rrpi_plot" in files:
        lines += [f"![RRPI vs path length]({files['rrpi_plot']})", ""]
    ro = metrics.get("rank_optimal")
    if ro and ro.get("groups"):
        lines += ["## Rank-optimal reference", "",
                  f"Each path's RRPI against the best route under the ranks between the same ends (planned "
                  f"{ro['mode']} on a costmap of {ro['cost']} per pixel, base cost {ro['base_cost_per_m']:g} "
                  f"per metre); ratio = RRPI / optimal RRPI. A ratio of 1 is as good as a costmap that "
                  "encodes the ranks exactly; a little below 1 is possible (RRPI counts pixels, the planner "
                  "weighs metres).", "",
                  f"| group | n | median ratio | within {100 * (ro['near_optimal_ratio'] - 1):.0f} % | "
                  "worst ratio | mean excess RRPI |", "|---|---|---|---|---|---|"]
        for group, g in ro["groups"].items():
            if not g["n"]:
                lines += [f"| {group} | 0 | n/a | n/a | n/a | n/a |"]
                continue
            median = "inf" if g["median_ratio"] is None else f"{g['median_ratio']:.3f}"
            worst = "inf" if g["worst_ratio"] is None else f"{g['worst_ratio']:.3f}"
            lines += [f"| {group} | {g['n']} | {median} | {100 * g['share_within_5pct']:.0f} % | {worst} | "
                      f"{g['mean_excess_rrpi']:.1f} |"]
        lines += [""]
    h = metrics.get("hausdorff")
    if h:
        lines += ["## Hausdorff distance to reference paths", ""]
        matched = h.get("matched") or {}
        if matched:
            counts = ", ".join(f"{v['matched']} of {v['paths']} {g}" for g, v in matched.items())
            lines += [f"Only paths whose start and goal lie within {h['endpoint_tolerance_m']:.1f} m of a "
                      f"reference path's ends are measured, each against the reference path(s) of its pair; "
                      f"matched: {counts}.", ""]
        if h.get("mean_normalised") is not None:
            lines += [f"Mean {h['kind']} Hausdorff distance of the {h['n']} matched {h['paths']} path(s) to "
                      f"their reference path(s) ({len(h['references'])} in all): **{h['mean_normalised']:.4f}** "
                      f"of the map diagonal ({h['mean_m']:.1f} m; mean point distance "
                      f"{h['mean_point_distance_m']:.1f} m).", ""]
        else:
            lines += ["No evaluated path shares its start and goal with a reference path: no Hausdorff "
                      "distance.", ""]
    summary = metrics.get("summary", {})
    if summary:
        lines += ["## Paths", "", "| group | n | mean length (m) | mean RRPI | mean Hausdorff / diagonal |",
                  "|---|---|---|---|---|"]
        for group, g in summary.items():
            lines += [f"| {group} | {g['n']} | {g['mean_length_m']:.1f} | {_fmt(g.get('mean_rrpi'))} | "
                      f"{_fmt(g.get('mean_hausdorff_normalised'))} |"]
        lines += [""]
        shown = metrics.get("paths", [])[:50]
        lines += ["| path | start (row, col) | goal (row, col) | length (m) | cost | RRPI | optimal RRPI | "
                  "ratio | Hausdorff (m) |", "|---|---|---|---|---|---|---|---|---|"]
        for p in shown:
            hd = p.get("hausdorff")
            ratio = "inf" if p.get("rrpi_ratio_infinite") else _fmt(p.get("rrpi_ratio"))
            lines += [f"| {p['name']} | {p['start']['row']}, {p['start']['col']} | {p['goal']['row']}, "
                      f"{p['goal']['col']} | {p['length_m']:.1f} | {_fmt(p['cost'])} | {_fmt(p['rrpi'])} | "
                      f"{_fmt(p.get('rrpi_optimal'))} | {ratio} | "
                      f"{'n/a' if not hd else format(hd['hausdorff_m'], '.2f')} |"]
        if len(metrics.get("paths", [])) > len(shown):
            lines += [f"| ... {len(metrics['paths']) - len(shown)} more in pairs.csv | | | | | | | | |"]
        lines += [""]
    if s and s["unreachable"]:
        lines += ["Unreachable pairs (skipped):", ""]
        lines += [f"- {u['name']}: {u['error']}" for u in s["unreachable"]] + [""]
    if "overlay_plot" in files:
        lines += [f"![paths over the costmap]({files['overlay_plot']})", ""]
    iou = metrics.get("iou")
    if iou:
        scored = sum(c["iou"] is not None for c in iou["classes"])
        lines += ["## IoU", "", f"Mean IoU **{_fmt(iou['mean_iou'])}** over the {scored} class(es) present in "
                  f"either raster ({iou['mode']} mode; {iou['valid_pixels']} valid pixels).", "", "| class | predicted by | IoU | TP | FP | FN |",
                  "|---|---|---|---|---|---|"]
        for c in iou["classes"]:
            lines += [f"| {c['name']} | {', '.join(c['bands']) or 'same class id'} | {_fmt(c['iou'])} | "
                      f"{c['tp']} | {c['fp']} | {c['fn']} |"]
        if iou["missing_classes"]:
            lines += ["", "No mask band for: " + ", ".join(iou["missing_classes"])]
        if iou["unmatched_bands"]:
            lines += ["", "Bands matching no class (use --match CLASS=BAND): " + ", ".join(iou["unmatched_bands"])]
        lines += [""]
        if "iou_plot" in files:
            lines += [f"![IoU per class]({files['iou_plot']})", ""]
    for note in metrics.get("notes", []):
        lines += [f"> {note}", ""]
    return "\n".join(lines).rstrip() + "\n"
