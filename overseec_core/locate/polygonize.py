"""Streaming polygonization: a mask read in strips becomes its connected regions, whole.

Each region is one 4-connected set of mask pixels (the connectivity of GDAL's polygonizer and of
scipy's labelling alike). A strip of rows is labelled (``scipy.ndimage.label``) and polygonized
(``rasterio.features.shapes`` of the labels, so each polygon is one label); a region that touches
neither inner edge of its strip is finished at once. Regions touching an edge become parts of an
open group; the next strip's regions that continue a group (4-adjacent across the seam: the same
column on both sides) join it, groups joined through one region merge (union-find), and a group
none of whose parts reaches the newest strip's lower edge is finished: its parts are unioned
(exact, the coordinates being whole pixel numbers) into one polygon. Memory is a strip plus the
open groups, whatever the image's height, and the polygons do not depend on the strip height.

:class:`FeatureMaker` then takes a region from pixel coordinates to the raster's CRS with its
ground area, optionally simplified by a tolerance in ground metres.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import shapely
import shapely.affinity
import shapely.geometry
from rasterio.features import shapes
from rasterio.transform import Affine
from rasterio.windows import Window
from scipy import ndimage

from overseec_core.errors import InputError
from overseec_core.progress import Progress, check_cancelled

#: Rows read, labelled and polygonized at a time (full width): a 10 000 px wide strip holds about
#: 50 MB of labels and probabilities.
DEFAULT_BLOCK_ROWS = 512
#: scipy's 4-connectivity, which is also rasterio.features.shapes' default.
_FOUR = ndimage.generate_binary_structure(2, 1)


# --------------------------------------------------------------------------------------------
# Streaming polygonization: strips, regions across the seams
# --------------------------------------------------------------------------------------------


@dataclass
class Region:
    """One connected region of a mask: its polygon in pixel coordinates (column, row of the
    whole image, whole numbers), its pixel count and the sum of its probabilities."""

    polygon: Any
    pixels: int
    prob_sum: float


@dataclass
class _Group:
    """Regions of consecutive strips joined across their seams (parts not yet unioned)."""

    parts: list[Any] = field(default_factory=list)
    pixels: int = 0
    prob_sum: float = 0.0

    def add(self, polygon: Any, pixels: int, prob_sum: float) -> None:
        self.parts.append(polygon)
        self.pixels += pixels
        self.prob_sum += prob_sum

    def absorb(self, other: _Group) -> None:
        self.parts += other.parts
        self.pixels += other.pixels
        self.prob_sum += other.prob_sum

    def region(self) -> Region:
        polygon = self.parts[0] if len(self.parts) == 1 else shapely.union_all(self.parts)
        return Region(polygon, self.pixels, self.prob_sum)


class _UnionFind:
    """Union-find over hashable keys (the groups of the strip above and this strip's regions)."""

    def __init__(self) -> None:
        self.parent: dict[Any, Any] = {}

    def find(self, key: Any) -> Any:
        self.parent.setdefault(key, key)
        root = key
        while self.parent[root] != root:
            root = self.parent[root]
        while self.parent[key] != root:
            self.parent[key], key = root, self.parent[key]
        return root

    def union(self, a: Any, b: Any) -> None:
        ra, rb = self.find(a), self.find(b)
        if ra != rb:
            self.parent[rb] = ra


@dataclass
class _Strip:
    """One labelled strip: labels, region count, per-label pixel counts and probability sums,
    and each region's polygon (pixel coordinates of the image)."""

    labels: np.ndarray
    counts: np.ndarray
    sums: np.ndarray
    polygons: dict[int, Any]


def _label_strip(mask: np.ndarray, prob: np.ndarray | None, row0: int) -> _Strip:
    labels, n = ndimage.label(mask, structure=_FOUR)
    labels = labels.astype(np.int32, copy=False)
    flat = labels.ravel()
    counts = np.bincount(flat, minlength=n + 1)
    sums = np.bincount(flat, weights=prob.ravel(), minlength=n + 1) if prob is not None else counts.astype(np.float64)
    polygons: dict[int, Any] = {}
    if n:
        shift = Affine.translation(0, row0)
        for geom, value in shapes(labels, mask=mask, connectivity=4, transform=shift):
            polygons[int(value)] = shapely.geometry.shape(geom)
    return _Strip(labels, counts, sums, polygons)


class StripPolygonizer:
    """Feed strips top to bottom (:meth:`feed`); get every finished region, each exactly once."""

    def __init__(self, height: int) -> None:
        self.height = height
        self._open: dict[int, _Group] = {}
        self._frontier: np.ndarray | None = None  # group id per column of the last row fed, -1 none
        self._next_id = 0

    def feed(self, mask: np.ndarray, prob: np.ndarray | None, row0: int) -> Iterator[Region]:
        """Regions finished by the strip ``mask`` (rows ``row0`` ...): those inside it, and the
        groups crossing its upper seam that do not reach its lower edge."""
        strip = _label_strip(mask, prob, row0)
        last = row0 + mask.shape[0] >= self.height
        top = set(np.unique(strip.labels[0]).tolist()) - {0} if row0 > 0 else set()
        bottom = set(np.unique(strip.labels[-1]).tolist()) - {0} if not last else set()
        for lab, polygon in strip.polygons.items():
            if lab not in top and lab not in bottom:
                yield Region(polygon, int(strip.counts[lab]), float(strip.sums[lab]))
        yield from self._join(strip, top, bottom)

    def _join(self, strip: _Strip, top: set[int], bottom: set[int]) -> Iterator[Region]:
        uf = _UnionFind()
        if self._frontier is not None and top:
            first = strip.labels[0]
            both = (self._frontier >= 0) & (first > 0)
            for gid, lab in set(zip(self._frontier[both].tolist(), first[both].tolist())):
                uf.union(("g", gid), ("r", lab))
        merged: dict[Any, _Group] = {}
        for gid, group in self._open.items():
            if ("g", gid) not in uf.parent:  # nothing continues it: finished above this strip
                yield group.region()
            else:
                merged.setdefault(uf.find(("g", gid)), _Group()).absorb(group)
        for lab in top | bottom:
            merged.setdefault(uf.find(("r", lab)), _Group()).add(
                strip.polygons[lab], int(strip.counts[lab]), float(strip.sums[lab])
            )
        reach = {uf.find(("r", lab)) for lab in bottom}
        self._open = {}
        gid_of: dict[Any, int] = {}
        for root, group in merged.items():
            if root in reach:  # goes on into the next strip
                gid_of[root] = self._next_id
                self._open[self._next_id] = group
                self._next_id += 1
            else:
                yield group.region()
        lut = np.full(len(strip.counts), -1, dtype=np.int64)
        for lab in bottom:
            lut[lab] = gid_of[uf.find(("r", lab))]
        self._frontier = lut[strip.labels[-1]] if bottom else None

    def finish(self) -> Iterator[Region]:
        """Whatever is still open (nothing after the last strip, which closes every group)."""
        for group in self._open.values():
            yield group.region()
        self._open = {}


def regions(
    read: Callable[[Window], tuple[np.ndarray, np.ndarray | None]],
    width: int,
    height: int,
    block_rows: int = DEFAULT_BLOCK_ROWS,
    progress: Progress | None = None,
) -> Iterator[Region]:
    """Every connected region of a mask read strip by strip (``read(window)`` -> mask, probs)."""
    if block_rows < 1:
        raise InputError(f"block rows must be at least 1, not {block_rows}")
    poly = StripPolygonizer(height)
    for row0 in range(0, height, block_rows):
        window = Window(0, row0, width, min(block_rows, height - row0))
        mask, prob = read(window)
        yield from poly.feed(mask, prob, row0)
        if progress is not None:
            progress.advance()
        check_cancelled(progress)
    yield from poly.finish()


# --------------------------------------------------------------------------------------------
# From pixel regions to features in the raster's CRS
# --------------------------------------------------------------------------------------------


def _polygons(geom: Any) -> list[Any]:
    """The non-empty polygons of a geometry (make_valid can return a collection)."""
    if geom.is_empty:
        return []
    if geom.geom_type == "Polygon":
        return [geom]
    return [p for g in getattr(geom, "geoms", ()) for p in _polygons(g)]


@dataclass(frozen=True)
class FeatureMaker:
    """Regions (pixel coordinates) -> polygons in the CRS with their ground area: the grid's
    transform, its ground pixel size and the simplification tolerance in ground metres."""

    transform: Affine
    pixel_size_m: tuple[float, float]
    simplify_m: float = 0.0

    def features(self, region: Region) -> list[tuple[Any, float, int]]:
        """[(polygon in the CRS, area in m², pixels)]: one entry, or one per part where
        repairing a geometry split it (pixels then shared by area)."""
        px, py = self.pixel_size_m
        t = self.transform
        if self.simplify_m > 0:  # simplify in ground metres (pixels need not be square on the ground)
            geom = shapely.affinity.affine_transform(region.polygon, [px, 0, 0, py, 0, 0])
            geom = shapely.simplify(geom, self.simplify_m, preserve_topology=True)
            to_crs = [t.a / px, t.b / py, t.d / px, t.e / py, t.c, t.f]
            scale = 1.0
        else:  # exact pixel edges; the collinear vertices of a straight edge dropped
            geom = shapely.simplify(region.polygon, 0.0, preserve_topology=True)
            to_crs = [t.a, t.b, t.d, t.e, t.c, t.f]
            scale = px * py
        if not geom.is_valid:
            geom = shapely.make_valid(geom)
        parts = _polygons(geom)
        total = sum(p.area for p in parts) or 1.0
        out = []
        for part in parts:
            share = region.pixels if len(parts) == 1 else round(region.pixels * part.area / total)
            out.append((shapely.affinity.affine_transform(part, to_crs), part.area * scale, int(share)))
        return out
