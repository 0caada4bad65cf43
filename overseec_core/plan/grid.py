"""The costmap as the planner sees it: one float32 grid, georeferencing, and impassable cells.

Impassable cells are encoded in the cost grid itself, so they cost no extra memory:
``+inf`` = lethal (flagged by the sidecar ``lethal.tif``, at or above ``lethal_threshold``, or
already infinite in the file) and ``NaN`` = nodata. Every other value is a finite cost >= 0.
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

from ..errors import InputError, PlanError, RasterError
from ..limits import check_pixels, check_planner_memory
from ..raster import Grid, crs_label, open_raster, parse_crs

#: Costmap tag naming the lethal sidecar (relative to the costmap's folder, or absolute).
LETHAL_TAG = "OVERSEEC_LETHAL_FILE"
#: Sidecar name looked for beside the costmap when the tag is absent.
LETHAL_DEFAULT_NAME = "lethal.tif"
#: Tag of a lethal sidecar naming the costmap it belongs to.
COSTMAP_TAG = "OVERSEEC_COSTMAP_FILE"
#: Costmap tags that may carry the mission prompt, first match wins.
PROMPT_TAGS = ("OVERSEEC_PROMPT", "PROMPT", "prompt")
#: Rows read per strip when loading (bounds the temporary memory of big costmaps).
STRIP_ROWS = 1024
#: Lethal-sidecar value of keep-out cells (compose.KEEP_OUT_FLAG; 1 = lethal or no data).
KEEP_OUT_FLAG = 2
#: Price per metre of a keep-out cell when a route cannot avoid the zone: far above the scale's
#: top (1.0), so the route runs as few metres inside as it can before anything else.
KEEP_OUT_ENTRY_COST = 100.0


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
    #: Bool (H, W), True on keep-out cells (zones a distance rule forbids; impassable here, +inf
    #: in ``cost``), or None when the sidecar has none. See :meth:`entering_keep_out`.
    keep_out: np.ndarray | None = None

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
        """A copy on which keep-out cells are passable at :data:`KEEP_OUT_ENTRY_COST`, for when no
        route exists without entering them: the route then stays in them as little as it can."""
        if self.keep_out is None:
            return self
        cost = self.cost.copy()
        cost[self.keep_out] = KEEP_OUT_ENTRY_COST
        return replace(self, cost=cost)

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
    The file is read in row strips into one float32 array: 4 bytes per pixel.
    """
    p = Path(path)
    with open_raster(p) as ds:
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
                strip = ds.read(band, window=Window(0, r0, ds.width, h)).astype(np.float32, copy=False)
                if nodata is not None and not math.isnan(nodata):
                    strip = np.where(strip == np.float32(nodata), np.float32(np.nan), strip)
                cost[r0 : r0 + h] = strip
        except Exception as exc:  # rasterio raises RasterioError; GDAL can surface others
            raise RasterError(f"{p}: corrupt or truncated costmap ({' '.join(str(exc).split())[:200]})") from None
    _check_costs(cost, str(p), unit_scale=True)
    lethal_file = _find_lethal(p, tags, lethal_path)
    keep_out = None
    if lethal_file is not None:
        keep_out = _apply_lethal_file(cost, grid, lethal_file)
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
    # compose's naming: X.tif -> X.lethal.tif, costmap.tif -> lethal.tif; a lethal.tif that says
    # (tag OVERSEEC_COSTMAP_FILE) it belongs to another costmap in the folder is not this one's.
    for candidate in (costmap.with_name(f"{costmap.stem}.lethal.tif"), costmap.parent / LETHAL_DEFAULT_NAME):
        if candidate.exists() and candidate.resolve() != costmap.resolve():
            if candidate.name == LETHAL_DEFAULT_NAME and _owner(candidate) not in (None, costmap.name):
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


def _apply_lethal_file(cost: np.ndarray, grid: Grid, path: Path) -> np.ndarray | None:
    """Make flagged cells +inf; return the keep-out cells (flag 2) or None when there are none."""
    with open_raster(path) as ds:
        other = Grid(crs=ds.crs, transform=ds.transform, width=ds.width, height=ds.height)
        if not grid.same_as(other):
            raise InputError(
                f"lethal mask {path} is not on the costmap's grid "
                f"({ds.width}x{ds.height} vs {grid.width}x{grid.height}, or CRS/transform differ)"
            )
        nodata = ds.nodata
        # 2 means keep-out only in overseec's own sidecar (compose tags it); in any other mask
        # every nonzero value is impassable, as the option's help says
        ours = bool(ds.tags().get(COSTMAP_TAG))
        keep_out = None
        try:
            for r0 in range(0, ds.height, STRIP_ROWS):
                h = min(STRIP_ROWS, ds.height - r0)
                flags = ds.read(1, window=Window(0, r0, ds.width, h))
                hit = flags != 0
                if nodata is not None and not (isinstance(nodata, float) and math.isnan(nodata)):
                    hit &= flags != nodata
                strip = cost[r0 : r0 + h]
                keep = hit & (flags == KEEP_OUT_FLAG) & ~np.isnan(strip)
                if ours and keep.any():
                    if keep_out is None:
                        keep_out = np.zeros(cost.shape, dtype=bool)
                    keep_out[r0 : r0 + h] = keep
                strip[hit & ~np.isnan(strip)] = np.inf
        except Exception as exc:  # see load_costmap
            why = " ".join(str(exc).split())[:200]
            raise RasterError(f"{path}: corrupt or truncated lethal mask ({why})") from None
    return keep_out
