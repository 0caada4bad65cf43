"""The costmap as the planner sees it: one float32 grid, georeferencing, and impassable cells.

Impassable cells are encoded in the cost grid itself, so they cost no extra memory:
``+inf`` = lethal (flagged by the sidecar ``lethal.tif``, at or above ``lethal_threshold``, or
already infinite in the file) and ``NaN`` = nodata. Every other value is a finite cost >= 0.
Keep-out cells (sidecar flag 2: zones a distance rule forbids, entities a never-cross rule
forbids, and obstacles nobody mentioned such as buildings and water) are +inf too; the grid also
remembers where they are and the costmap's own value at each, for the route that cannot avoid
them (:meth:`PlanningGrid.entering_keep_out`, :meth:`PlanningGrid.own_cost`).
"""

from __future__ import annotations

import functools
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
from rasterio.windows import Window

from overseec_core import runfiles
from overseec_core.errors import InputError, PlanError, RasterError
from overseec_core.io.grid import Grid, crs_label, parse_crs
from overseec_core.io.read import open_raster
from overseec_core.limits import check_pixels, check_planner_memory

#: Costmap tag naming the lethal sidecar (relative to the costmap's folder, or absolute).
LETHAL_TAG = "OVERSEEC_LETHAL_FILE"
#: Tag of a lethal sidecar naming the costmap it belongs to.
COSTMAP_TAG = "OVERSEEC_COSTMAP_FILE"
#: Costmap tags that may carry the mission prompt, first match wins.
PROMPT_TAGS = (runfiles.TAG_PROMPT, "PROMPT", "prompt")
#: Rows read per strip when loading (bounds the temporary memory of big costmaps).
STRIP_ROWS = 1024
#: Rows of the keep-out mask unpacked at a time to look up own costs (ZoneCosts.at).
ZONE_ROWS = 64
#: Lethal-sidecar value of keep-out cells (compose.KEEP_OUT_FLAG; 1 = lethal or no data).
KEEP_OUT_FLAG = 2
#: Price per metre of a keep-out cell, on top of the cell's own cost, when a route cannot avoid
#: the zone. A route's own costs are at most 1.0 + base per metre, so one metre less inside the
#: zone outweighs any detour shorter than about a kilometre: the route runs as few metres inside
#: as it can, and among such routes the cheapest under the costmap (in the zone too: it skirts the
#: buildings a "keep 20 m from buildings" zone surrounds). At 100 a route on a New Brunswick clip
#: ran 18.27 m inside where 18.06 m was possible, for a shorter route. Larger would blur the own
#: costs: float32 holds 1000 + c to within 6e-5 of c. (With zero-cost cells in the costmap, the
#: relaxed grid's cost range sends the kernel from its bucket ring to its radix heap: 1.9 s
#: instead of 1.2 s for a 4000² exact query.)
KEEP_OUT_ENTRY_COST = 1000.0
#: A keep-out cell's own cost when the grid does not hold it (a grid built in memory with a
#: ``keep_out`` mask but no values): the top of the scale, the safe side.
UNKNOWN_KEEP_OUT_COST = 1.0
#: Neutral ground on overseec's scale (``costlang.scale.NEUTRAL``); a broken rule's note counts the
#: metres inside the zone on ground that costs more (avoided ground).
NEUTRAL_COST = 0.5


@dataclass(frozen=True, eq=False)
class ZoneCosts:
    """The costmap's own values under keep-out cells, which the cost grid holds as +inf.

    ``cells`` marks the keep-out cells as loaded, bit-packed per row (``np.packbits(axis=1)``),
    ``values`` holds their float32 costs in row-major order and ``row_start`` (H + 1, int64) how
    many of them precede each row. That is 4 bytes per keep-out cell and one bit per pixel: a
    dense copy of the costmap would be 4 bytes per pixel, and a town under "keep 20 m from
    buildings" is nearly all zone. Keeping the mask as loaded keeps the values right when
    overrides later take cells out of :attr:`PlanningGrid.keep_out`.
    """

    cells: np.ndarray
    width: int
    values: np.ndarray
    row_start: np.ndarray

    @property
    def nbytes(self) -> int:
        return int(self.cells.nbytes + self.values.nbytes + self.row_start.nbytes)

    def rows(self, r0: int, r1: int) -> np.ndarray:
        """Bool (r1 - r0, W): the keep-out cells (as loaded) of rows r0..r1-1."""
        return np.unpackbits(self.cells[r0:r1], axis=1, count=self.width).astype(bool)

    def at(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """Float64 own cost at each (row, col); NaN where the cell was not a keep-out cell.

        Reads only the rows asked for, :data:`ZONE_ROWS` at a time (a cell's place in ``values``
        is ``row_start`` of its row plus the cells before it in the row)."""
        rows = np.asarray(rows, dtype=np.int64).reshape(-1)
        cols = np.asarray(cols, dtype=np.int64).reshape(-1)
        out = np.full(len(rows), np.nan)
        if not len(self.values):
            return out
        wanted = np.unique(rows)
        for k in range(0, len(wanted), ZONE_ROWS):
            chunk = wanted[k : k + ZONE_ROWS]
            bits = np.unpackbits(self.cells[chunk], axis=1, count=self.width)
            upto = np.cumsum(bits, axis=1, dtype=np.int32)  # zone cells up to and including each
            sel = np.flatnonzero((rows >= chunk[0]) & (rows <= chunk[-1]))
            j, c = np.searchsorted(chunk, rows[sel]), cols[sel]
            hit = bits[j, c] == 1
            rank = self.row_start[rows[sel][hit]] + upto[j[hit], c[hit]] - 1
            found = out[sel]
            found[hit] = self.values[rank]
            out[sel] = found
        return out

    def fill(self, cost: np.ndarray, keep_out: np.ndarray, offset: float) -> None:
        """Set ``cost`` to ``offset`` + own cost on the cells of ``keep_out`` that have one."""
        for r0 in range(0, cost.shape[0], STRIP_ROWS):
            r1 = min(r0 + STRIP_ROWS, cost.shape[0])
            zone = self.rows(r0, r1)
            still = keep_out[r0:r1][zone]
            values = self.values[self.row_start[r0] : self.row_start[r1]]
            cost[r0:r1][zone & keep_out[r0:r1]] = np.float32(offset) + values[still]


@dataclass(frozen=True, eq=False)
class PlanningGrid:
    """A costmap loaded for planning.

    ``cost`` is (H, W) float32, C-contiguous: finite values >= 0 are costs, ``+inf`` marks lethal
    cells and ``NaN`` nodata; both are impassable. ``grid`` is the georeferencing (None for a bare
    array), ``pixel_size_m`` the ground size (x, y) of one pixel in metres.
    """

    cost: np.ndarray
    grid: Grid | None
    pixel_size_m: tuple[float, float]
    source: str | None = None
    lethal_source: str | None = None
    lethal_threshold: float | None = None
    tags: Mapping[str, str] = field(default_factory=dict)
    #: Bool (H, W), True on keep-out cells (distance-rule zones, never-cross entities, obstacles;
    #: impassable here, +inf in ``cost``), or None when the sidecar has none. See :meth:`entering_keep_out`.
    keep_out: np.ndarray | None = None
    #: The costmap's own values under the keep-out cells (``cost`` holds +inf there), or None
    #: where unknown (a grid built in memory; see :data:`UNKNOWN_KEEP_OUT_COST`).
    zone_costs: ZoneCosts | None = None

    # ---------------------------------------------------------------- construction

    @classmethod
    def from_array(
        cls,
        cost: np.ndarray,
        grid: Grid | None = None,
        *,
        lethal: np.ndarray | None = None,
        lethal_threshold: float | None = None,
        pixel_size_m: tuple[float, float] | None = None,
        source: str | None = None,
        tags: Mapping[str, str] | None = None,
    ) -> PlanningGrid:
        """Build from an in-memory array (float costs; NaN = nodata, inf = lethal).

        ``lethal`` (bool/uint8, nonzero = impassable) and ``lethal_threshold`` add lethal cells.
        Without a ``grid`` the pixel size defaults to 1 m x 1 m.
        """
        arr = np.asarray(cost)
        if arr.ndim != 2 or arr.size == 0:
            raise InputError(f"a costmap must be a non-empty 2-D array, not shape {arr.shape}")
        if grid is not None and (grid.height, grid.width) != arr.shape:
            raise InputError(f"costmap shape {arr.shape} does not match its grid ({grid.height} x {grid.width})")
        out = np.array(arr, dtype=np.float32, order="C", copy=True)
        _check_costs(out, source or "costmap")
        if lethal is not None:
            mask = np.asarray(lethal)
            if mask.shape != out.shape:
                raise InputError(f"lethal mask shape {mask.shape} does not match the costmap {out.shape}")
            out[(mask != 0) & ~np.isnan(out)] = np.inf
        if lethal_threshold is not None:
            _apply_threshold(out, lethal_threshold)
        if pixel_size_m is None:
            pixel_size_m = grid.pixel_size_m() if grid is not None else (1.0, 1.0)
        dx, dy = (float(v) for v in pixel_size_m)
        if not (dx > 0 and dy > 0 and math.isfinite(dx) and math.isfinite(dy)):
            raise InputError(f"pixel size must be positive metres, not {pixel_size_m}")
        return cls(
            cost=out,
            grid=grid,
            pixel_size_m=(dx, dy),
            source=source,
            lethal_threshold=lethal_threshold,
            tags=dict(tags or {}),
        )

    # ---------------------------------------------------------------- shape and cells

    @property
    def shape(self) -> tuple[int, int]:
        return self.cost.shape  # type: ignore[return-value]

    @property
    def height(self) -> int:
        return self.cost.shape[0]

    @property
    def width(self) -> int:
        return self.cost.shape[1]

    @property
    def passable(self) -> np.ndarray:
        """Bool (H, W), True where a path may go (computed on demand; 1 byte/pixel)."""
        return np.isfinite(self.cost)

    @property
    def lethal(self) -> np.ndarray:
        """Bool (H, W), True on lethal cells (nodata excluded)."""
        return np.isposinf(self.cost)

    @property
    def nodata(self) -> np.ndarray:
        """Bool (H, W), True on nodata cells."""
        return np.isnan(self.cost)

    def contains(self, row: int, col: int) -> bool:
        return 0 <= row < self.height and 0 <= col < self.width

    def blocked_reason(self, row: int, col: int) -> str | None:
        """'outside', 'lethal' or 'nodata' when (row, col) cannot be on a path, else None."""
        if not self.contains(row, col):
            return "outside"
        v = float(self.cost[row, col])
        if math.isnan(v):
            return "nodata"
        if math.isinf(v):
            return "lethal"
        return None

    @property
    def prompt(self) -> str | None:
        """The mission prompt recorded in the costmap's tags, if any."""
        for key in PROMPT_TAGS:
            if self.tags.get(key):
                return str(self.tags[key])
        return None

    @property
    def nbytes(self) -> int:
        return int(self.cost.nbytes)

    def entering_keep_out(self) -> PlanningGrid:
        """A copy on which keep-out cells are passable at :data:`KEEP_OUT_ENTRY_COST` plus their
        own cost, for when no route exists without entering them.

        Under the planner's step rule a route then costs ENTRY x (its metres inside the zone,
        each step counted by the mean of its two cells) + its cost under the costmap's own values,
        so it runs as few metres inside as it can and, among those routes, takes the cheapest
        ground: through a zone around buildings it passes beside them, not through them.
        Lethal and nodata cells stay impassable. The copy is one more float32 grid.
        """
        if self.keep_out is None:
            return self
        cost = self.cost.copy()
        cost[self.keep_out] = np.float32(KEEP_OUT_ENTRY_COST + UNKNOWN_KEEP_OUT_COST)
        if self.zone_costs is not None:
            self.zone_costs.fill(cost, self.keep_out, KEEP_OUT_ENTRY_COST)
        return replace(self, cost=cost)

    def own_cost(self, pixels: np.ndarray) -> np.ndarray:
        """The costmap's own value at each (row, col) of ``pixels`` (N, 2), float64: ``cost``
        there, except on keep-out cells, where it is the value the costmap holds under the
        rule's +inf (:data:`UNKNOWN_KEEP_OUT_COST` where the grid does not know it)."""
        px = np.asarray(pixels, dtype=np.int64).reshape(-1, 2)
        out = self.cost[px[:, 0], px[:, 1]].astype(np.float64)
        if self.keep_out is None:
            return out
        inside = self.keep_out[px[:, 0], px[:, 1]]
        if not inside.any():
            return out
        own = np.full(int(inside.sum()), np.nan)
        if self.zone_costs is not None:
            own = self.zone_costs.at(px[inside, 0], px[inside, 1])
        out[inside] = np.where(np.isnan(own), UNKNOWN_KEEP_OUT_COST, own)
        return out

    # ---------------------------------------------------------------- georeferencing

    def need_grid(self) -> Grid:
        """The georeferencing, or PlanError when the costmap has none."""
        if self.grid is None:
            raise PlanError("this costmap has no georeferencing; give points as pixel (row, col)")
        return self.grid

    def world_to_pixel(self, x, y, crs=None):
        """(row, col) of the pixel containing map point(s) (x, y).

        ``crs`` names the points' CRS (anything rasterio/pyproj accepts, e.g. 'EPSG:4326';
        x = longitude/easting, y = latitude/northing); None = the costmap's CRS. Scalars give a
        tuple of ints, arrays give two int64 arrays. Points outside the raster give indices
        outside 0..H-1 / 0..W-1 (check with :meth:`contains`).
        """
        g = self.need_grid()
        xs, ys = _to_crs(np.asarray(x, dtype=float), np.asarray(y, dtype=float), crs, g.crs)
        cols, rows = ~g.transform * (xs, ys)
        rows = np.floor(np.asarray(rows, dtype=float))
        cols = np.floor(np.asarray(cols, dtype=float))
        if not (np.all(np.isfinite(rows)) and np.all(np.isfinite(cols))):
            src = crs_label(parse_crs(crs)) if isinstance(crs, str) else crs_label(crs or g.crs)
            raise PlanError(
                f"point ({x}, {y}) in {src} cannot be placed on the costmap "
                f"in {crs_label(g.crs)} (the transformation gave no finite result)"
            )
        if np.ndim(rows) == 0:
            return int(rows), int(cols)
        return rows.astype(np.int64), cols.astype(np.int64)

    def pixel_to_world(self, rows, cols, crs=None):
        """Map coordinates (xs, ys) of pixel centres; in ``crs`` if given (x = lon for 4326)."""
        g = self.need_grid()
        r = np.asarray(rows, dtype=float) + 0.5
        c = np.asarray(cols, dtype=float) + 0.5
        xs, ys = g.transform * (c, r)
        xs, ys = _to_crs(np.asarray(xs, dtype=float), np.asarray(ys, dtype=float), g.crs, crs)
        if np.ndim(xs) == 0:
            return float(xs), float(ys)
        return np.asarray(xs, dtype=float), np.asarray(ys, dtype=float)


def _check_costs(cost: np.ndarray, name: str, unit_scale: bool = False) -> None:
    """Negative costs would break shortest paths: refuse them in one line. With ``unit_scale``
    (costmap files), finite costs above 1 are refused too: they are not on overseec's scale.
    NaN (nodata) and +inf (impassable) are allowed."""
    for r0 in range(0, cost.shape[0], STRIP_ROWS):
        strip = cost[r0 : r0 + STRIP_ROWS]
        with np.errstate(invalid="ignore"):
            if (strip < 0).any():
                low = float(np.nanmin(strip))
                raise InputError(
                    f"{name}: costs must be >= 0, found {low:g}; rescale the costmap (overseec costmaps are in [0, 1])"
                )
            if unit_scale and ((strip > 1) & np.isfinite(strip)).any():
                high = float(np.max(strip[np.isfinite(strip)]))
                raise InputError(
                    f"{name}: costs must be in [0, 1] (+inf = impassable), found "
                    f"{high:g}; rescale the costmap or check it is one"
                )


def check_costmap_kind(ds, path: Path, band: int | None) -> int:
    """The band holding costs: a costmap is one float band (or the band the user names).

    An RGB photo or a class raster handed to the planner would otherwise plan on its first
    band's digital numbers without a word.
    """
    if band is None:
        if ds.count != 1:
            raise InputError(f"{path} has {ds.count} bands; a costmap has one (pass --band N to plan on band N)")
        band = 1
    elif not 1 <= band <= ds.count:
        raise InputError(f"--band {band}: {path} has {ds.count} band(s)")
    dtype = ds.dtypes[band - 1]
    if not np.dtype(dtype).kind == "f":
        raise InputError(
            f"{path} band {band} holds {dtype} values; a costmap holds float costs "
            "in [0, 1] (is this an image or a class raster?)"
        )
    return band


def _apply_threshold(cost: np.ndarray, threshold: float) -> None:
    if not math.isfinite(threshold):
        raise InputError(f"--lethal-threshold must be a finite number, not {threshold}")
    for r0 in range(0, cost.shape[0], STRIP_ROWS):
        strip = cost[r0 : r0 + STRIP_ROWS]
        with np.errstate(invalid="ignore"):
            strip[strip >= threshold] = np.inf


@functools.lru_cache(maxsize=32)
def _transformer(src_wkt: str, dst_wkt: str):
    import pyproj

    return pyproj.Transformer.from_crs(pyproj.CRS.from_wkt(src_wkt), pyproj.CRS.from_wkt(dst_wkt), always_xy=True)


def _to_crs(xs: np.ndarray, ys: np.ndarray, src, dst):
    """Transform coordinates between CRSs (None on either side = no change)."""
    if src is None or dst is None:
        return xs, ys
    src_crs = src if hasattr(src, "to_wkt") else parse_crs(src)
    dst_crs = dst if hasattr(dst, "to_wkt") else parse_crs(dst)
    if src_crs == dst_crs:
        return xs, ys
    tx, ty = _transformer(src_crs.to_wkt(), dst_crs.to_wkt()).transform(xs, ys)
    return np.asarray(tx, dtype=float), np.asarray(ty, dtype=float)


# ------------------------------------------------------------------------------------------------
# Loading
# ------------------------------------------------------------------------------------------------


def load_costmap(
    path: str | os.PathLike,
    lethal_path: str | os.PathLike | None = None,
    lethal_threshold: float | None = None,
    band: int | None = None,
) -> PlanningGrid:
    """Read a costmap GeoTIFF (its one float band, or ``band``) and its lethal sidecar into a :class:`PlanningGrid`.

    Nodata (the band's nodata value or NaN) becomes NaN; the sidecar (uint8, nonzero =
    impassable; ``lethal_path``, else the file named by the costmap tag ``OVERSEEC_LETHAL_FILE``,
    else ``X.lethal.tif`` or ``lethal.tif`` beside costmap ``X.tif``) and ``cost >=
    lethal_threshold`` become +inf.
    The file is read in row strips into one float32 array: 4 bytes per pixel. Keep-out cells (2 in
    overseec's own sidecar) are +inf too, remembered in ``keep_out`` (1 byte per pixel) with their
    own costs in ``zone_costs`` (4 bytes per keep-out cell and one bit per pixel).
    """
    p = Path(path)
    with open_raster(p, threads=True) as ds:
        if ds.crs is None:
            raise RasterError(f"{p} has no CRS; a costmap must be georeferenced")
        grid = Grid(crs=ds.crs, transform=ds.transform, width=ds.width, height=ds.height)
        band = check_costmap_kind(ds, p, band)
        check_pixels(ds.width, ds.height, p, "costmap")
        check_planner_memory(ds.width, ds.height, p)
        tags = dict(ds.tags())
        nodata = ds.nodatavals[band - 1]
        cost = np.empty((ds.height, ds.width), dtype=np.float32)
        try:
            for r0 in range(0, ds.height, STRIP_ROWS):
                h = min(STRIP_ROWS, ds.height - r0)
                strip = cost[r0 : r0 + h]  # read in place: no strip-sized temporaries to fault in
                ds.read(band, window=Window(0, r0, ds.width, h), out=strip, out_dtype=np.float32)
                if nodata is not None and not math.isnan(nodata):
                    strip[strip == np.float32(nodata)] = np.nan
        except Exception as exc:  # rasterio raises RasterioError; GDAL can surface others
            raise RasterError(f"{p}: corrupt or truncated costmap ({' '.join(str(exc).split())[:200]})") from None
    _check_costs(cost, str(p), unit_scale=True)
    lethal_file = _find_lethal(p, tags, lethal_path)
    keep_out = zone_costs = None
    if lethal_file is not None:
        threshold = None if lethal_threshold is None else float(lethal_threshold)
        zone = _apply_lethal_file(cost, grid, lethal_file, threshold)
        if zone is not None:
            keep_out, zone_costs = zone
    if lethal_threshold is not None:
        _apply_threshold(cost, float(lethal_threshold))
    return PlanningGrid(
        cost=cost,
        grid=grid,
        pixel_size_m=grid.pixel_size_m(),
        source=str(p),
        lethal_source=None if lethal_file is None else str(lethal_file),
        lethal_threshold=lethal_threshold,
        tags=tags,
        keep_out=keep_out,
        zone_costs=zone_costs,
    )


def _find_lethal(costmap: Path, tags: Mapping[str, str], explicit) -> Path | None:
    if explicit is not None:
        lp = Path(explicit)
        if not lp.exists():
            raise InputError(f"lethal mask not found: {lp}")
        return lp
    named = tags.get(LETHAL_TAG)
    if named:
        lp = Path(named)
        if not lp.is_absolute():
            lp = costmap.parent / lp
        if not lp.exists():
            raise InputError(
                f"{costmap} names the lethal mask {lp} (tag {LETHAL_TAG}), which is "
                "missing; restore it or pass --lethal PATH"
            )
        return lp
    # X.lethal.tif (the cost stage's name for any costmap but the run folder's), then the run
    # folder's lethal.tif (runfiles.lethal_sidecar); a lethal.tif that says (tag
    # OVERSEEC_COSTMAP_FILE) it belongs to another costmap in the folder is not this one's.
    for candidate in (costmap.with_name(costmap.stem + runfiles.LETHAL_SUFFIX), costmap.parent / runfiles.LETHAL):
        if candidate.exists() and candidate.resolve() != costmap.resolve():
            if candidate.name == runfiles.LETHAL and _owner(candidate) not in (None, costmap.name):
                continue
            return candidate
    return None


def _owner(lethal: Path) -> str | None:
    """The costmap file name a lethal sidecar was written for (compose tags it), if known."""
    try:
        with open_raster(lethal) as ds:
            return ds.tags().get(COSTMAP_TAG) or None
    except (InputError, RasterError):
        return None


def _check_mask_kind(ds, path: Path) -> None:
    """A lethal mask is one band of integer flags (or of floats, checked for 0/1 as it is read)."""
    if ds.count != 1:
        raise InputError(
            f"lethal mask {path} has {ds.count} bands; a lethal mask is one band of integer flags "
            "(0 passable, nonzero impassable): is this an image?"
        )
    if np.dtype(ds.dtypes[0]).kind not in "iuf":
        raise InputError(f"lethal mask {path}: a lethal mask holds integer flags, not {ds.dtypes[0]}")


def _check_float_mask(flags: np.ndarray, nodata: float | None, path: Path) -> None:
    """A float lethal mask must hold 0/1 only (NaN and nodata aside): anything else is an image."""
    if flags.dtype.kind != "f":
        return
    other = ~((flags == 0) | (flags == 1) | np.isnan(flags))
    if nodata is not None and not math.isnan(nodata):
        other &= flags != nodata
    if other.any():
        value = flags[other].flat[0]
        raise InputError(
            f"lethal mask {path} holds float values such as {value:.6g}; a lethal mask is one band of "
            "integer flags, or of 0/1 floats (is this a costmap or an image?)"
        )


def _apply_lethal_file(
    cost: np.ndarray, grid: Grid, path: Path, lethal_threshold: float | None = None
) -> tuple[np.ndarray, ZoneCosts] | None:
    """Make flagged cells +inf; return the keep-out cells (flag 2) and the costmap's own values
    there (read before the +inf), or None when there are none. A flagged cell the costmap itself
    makes impassable (+inf, NaN, at or above ``lethal_threshold``) is no keep-out cell: it is
    never entered."""
    with open_raster(path) as ds:
        other = Grid(crs=ds.crs, transform=ds.transform, width=ds.width, height=ds.height)
        if not grid.same_as(other):
            raise InputError(
                f"lethal mask {path} is not on the costmap's grid "
                f"({ds.width}x{ds.height} vs {grid.width}x{grid.height}, or CRS/transform differ)"
            )
        nodata = ds.nodata
        _check_mask_kind(ds, path)
        # 2 means keep-out only in overseec's own sidecar (compose tags it); in any other mask
        # every nonzero value is impassable, as the option's help says
        ours = bool(ds.tags().get(COSTMAP_TAG))
        keep_out = None
        packed = np.zeros((0, 0), dtype=np.uint8)
        per_row = np.zeros(ds.height + 1, dtype=np.int64)
        values: list[np.ndarray] = []
        try:
            for r0 in range(0, ds.height, STRIP_ROWS):
                h = min(STRIP_ROWS, ds.height - r0)
                flags = ds.read(1, window=Window(0, r0, ds.width, h))
                hit = flags != 0
                if nodata is not None and not (isinstance(nodata, float) and math.isnan(nodata)):
                    hit &= flags != nodata
                _check_float_mask(flags, nodata, path)
                strip = cost[r0 : r0 + h]
                keep = hit & (flags == KEEP_OUT_FLAG) & np.isfinite(strip)
                if lethal_threshold is not None:
                    keep &= strip < lethal_threshold
                if ours and keep.any():
                    if keep_out is None:
                        keep_out = np.zeros(cost.shape, dtype=bool)
                        packed = np.zeros((ds.height, (ds.width + 7) // 8), dtype=np.uint8)
                    keep_out[r0 : r0 + h] = keep
                    packed[r0 : r0 + h] = np.packbits(keep, axis=1)
                    per_row[r0 + 1 : r0 + h + 1] = keep.sum(axis=1)
                    values.append(strip[keep])
                strip[hit & ~np.isnan(strip)] = np.inf
        except InputError:
            raise
        except Exception as exc:  # see load_costmap
            why = " ".join(str(exc).split())[:200]
            raise RasterError(f"{path}: corrupt or truncated lethal mask ({why})") from None
    if keep_out is None:
        return None
    zone = ZoneCosts(cells=packed, width=grid.width, values=np.concatenate(values), row_start=np.cumsum(per_row))
    return keep_out, zone
