"""Compose: a checked cost program + entity layers -> costmap.tif and lethal.tif, block by block.

Entity layers come from files the user or earlier stages made, read a window at a time:

- the segment stage's directory: ``masks.tif`` (+ ``probs.tif``), or ``refined_masks.tif``
  (+ ``refined_probs.tif``) when present; one band per entity, band descriptions = entity names;
- a class raster plus ``classes.json`` (class id -> name): each class becomes an entity with
  probability 1.0 inside it (background names such as "unlabeled" are no entity);
- vector layers (``road=roads.gpkg``), reprojected to the grid's CRS and rasterised per window
  (lines and points with ``all_touched``, or buffered to a width; polygons by pixel centre).

Sources can be combined; an entity present in several is their union (mask OR, probability max).

The program is evaluated on each block plus a halo equal to its spatial reach
(:meth:`Program.halo`), so the costmap equals a whole-image evaluation exactly while memory stays
bounded by the block size: no entity layer is ever read at full size.
"""

from __future__ import annotations

import math
import os
import re
import time
import warnings
from collections.abc import Iterable, Iterator, Mapping, Sequence
from contextlib import ExitStack
from dataclasses import dataclass, field, replace
from functools import partial
from pathlib import Path
from typing import Protocol

import numpy as np
import rasterio
import shapely
from pyproj import CRS as ProjCRS  # noqa: N811 (pyproj's CRS, named apart from rasterio's)
from pyproj import Transformer
from rasterio.errors import RasterioError
from rasterio.features import rasterize
from rasterio.windows import Window
from rasterio.windows import bounds as window_bounds
from rasterio.windows import transform as window_transform

from overseec_core import runfiles
from overseec_core.costlang import Program, check_program, evaluate_program, program_from_interpretation
from overseec_core.costlang.ops import Poll, never_cancelled
from overseec_core.costlang.scale import NEUTRAL, off_neutral
from overseec_core.errors import CostProgramError, InputError, RasterError
from overseec_core.inputs import check_class_raster
from overseec_core.interpret import interpret
from overseec_core.interpret.matching import RULES, match_entities, match_entity
from overseec_core.interpret.merge import dense_ranks
from overseec_core.interpret.priors import BUILT_IN as BUILT_IN_PRIORS
from overseec_core.interpret.priors import PriorTable, resolve_priors
from overseec_core.limits import MAX_PROGRAM_BYTES, check_input_file, read_text_limited
from overseec_core.overrides import OverrideCounts, OverrideSet, apply_to_block
from overseec_core.progress import NullProgress, Progress, check_cancelled
from overseec_core.raster import Grid, RasterWriter, check_output_path, open_raster, read_classes_json
from overseec_core.schema import Preference

#: Pixels per side of a composition block (a multiple of the writer's 512 tiles).
DEFAULT_BLOCK = 1024
#: Largest halo (pixels on each side) a program may need on a given grid.
MAX_HALO_PX = 2048
#: Most pixels one extended window (block + halo) may hold when blocks grow to amortise a halo
#: wider than the block: the window of a default block with the largest halo, the most
#: composition ever reads at once anyway.
MAX_WINDOW_PX = (DEFAULT_BLOCK + 2 * MAX_HALO_PX) ** 2
#: Above this ratio of pixels read (blocks with their halos) to pixels written, compose says so
#: before it starts, since the time grows with it.
HALO_NOTICE_RATIO = 4.0
#: GDAL block cache while composing (bytes). GDAL's default, 5% of RAM, lets the cache of the
#: inputs and of the two outputs grow with the image; this keeps composition's memory bounded.
GDAL_CACHE_BYTES = 256 * 2**20
#: Class names in classes.json that are background, not an entity.
BACKGROUND_NAMES = frozenset({"unlabeled", "unlabelled", "background", "nodata", "no data", "void", "ignore"})
#: File names the segment stage writes, most refined first.
MASK_FILES = runfiles.MASK_FILES
#: Value of keep-out cells in the lethal sidecar (1 = lethal or no data): zones a rule forbids (a
#: distance rule, a never-cross rule, an obstacle), impassable wherever a route exists without
#: them (see plan.grid).
KEEP_OUT_FLAG = 2
#: Tags on the costmap that name its sidecars (file names, relative to the costmap).
TAG_PROGRAM, TAG_LETHAL = "OVERSEEC_PROGRAM_FILE", "OVERSEEC_LETHAL_FILE"


@dataclass
class LayerBlock:
    """Entity layers for one window: masks (bool), raw probabilities (float), and valid pixels."""

    masks: dict[str, np.ndarray]
    probs: dict[str, np.ndarray]
    valid: np.ndarray


class LayerSource(Protocol):
    """Anything that serves entity layers window by window on one grid."""

    grid: Grid
    names: tuple[str, ...]
    inputs: tuple[Path, ...]

    def read(self, names: Sequence[str], window: Window) -> LayerBlock: ...

    def close(self) -> None: ...


def _read(ds, indexes, window: Window, path) -> np.ndarray:
    try:
        return ds.read(indexes, window=window)
    except RasterioError as exc:
        raise RasterError(f"{path}: corrupt or truncated raster ({' '.join(str(exc).split())[:160]})") from None


def _nodata_mask(ds, band: np.ndarray, index: int) -> np.ndarray:
    """True where a band holds data: not its nodata value, finite for floats.

    Uses the band's nodata value rather than GDAL's dataset mask on purpose: GDAL reads a 3- or
    4-band uint8 GeoTIFF as RGB(A) and would take the fourth entity's mask for an alpha band.
    """
    nodata = ds.nodatavals[index - 1]
    valid = np.ones(band.shape, dtype=bool) if band.dtype.kind not in "fc" else np.isfinite(band)
    if nodata is not None and not np.isnan(nodata):
        valid &= band != nodata
    return valid


def _grid_of(ds) -> Grid:
    if ds.crs is None:
        raise RasterError(f"{ds.name} has no CRS; costmaps need georeferenced masks")
    return Grid(crs=ds.crs, transform=ds.transform, width=ds.width, height=ds.height)


def _band_names(ds, path: Path) -> tuple[str, ...]:
    names = tuple((d or "").strip() for d in ds.descriptions)
    missing = [i + 1 for i, n in enumerate(names) if not n]
    if missing:
        raise InputError(
            f"{path}: band(s) {', '.join(map(str, missing))} have no description; "
            "each band must be named after its entity"
        )
    if len(set(names)) != len(names):
        raise InputError(f"{path}: two bands have the same entity name")
    return names


def _probabilities(raw: np.ndarray) -> np.ndarray:
    """Probabilities as float32 from float or integer-scaled (0..max) bands.

    Non-finite values are left for the caller's validity mask; the evaluator clips to [0, 1].
    """
    if raw.dtype.kind in "ui":
        return raw.astype(np.float32) / float(np.iinfo(raw.dtype).max)
    return raw.astype(np.float32, copy=False)


class MaskDirSource:
    """The segment stage's output directory: masks (and probabilities), one band per entity."""

    def __init__(self, directory: str | os.PathLike) -> None:
        d = Path(directory)
        if not d.is_dir():
            raise InputError(f"--masks {d}: not a directory (give the folder that holds masks.tif)")
        chosen = next(((d / m, d / p) for m, p in MASK_FILES if (d / m).exists()), None)
        if chosen is None:
            raise InputError(
                f"--masks {d}: no masks.tif or refined_masks.tif in it; run "
                "`overseec segment` first or give --labels/--vector"
            )
        self.mask_path, prob_path = chosen
        self._masks = open_raster(self.mask_path)
        self._probs = None
        try:
            self.grid = _grid_of(self._masks)
            self.names = _band_names(self._masks, self.mask_path)
            self._mask_band = {n: i + 1 for i, n in enumerate(self.names)}
            self._prob_band: dict[str, int] = {}
            self.prob_path = prob_path if prob_path.exists() else None
            if self.prob_path is not None:
                self._probs = open_raster(self.prob_path)
                if not _grid_of(self._probs).same_as(self.grid):
                    raise InputError(f"{self.prob_path} and {self.mask_path} are on different grids")
                self._prob_band = {n: i + 1 for i, n in enumerate(_band_names(self._probs, self.prob_path))}
        except BaseException:
            self.close()
            raise
        self.inputs = tuple(p for p in (self.mask_path, self.prob_path) if p is not None)

    def read(self, names: Sequence[str], window: Window) -> LayerBlock:
        indexes = [self._mask_band[n] for n in names] or [1]
        data = _read(self._masks, indexes, window, self.mask_path)
        valid = np.ones(data.shape[1:], dtype=bool)
        for i, band in zip(indexes, data):
            valid &= _nodata_mask(self._masks, band, i)
        masks, probs = {}, {}
        for n, band in zip(names, data):
            masks[n] = (band > 0) & valid
        with_prob = [n for n in names if n in self._prob_band]
        if with_prob:
            idx = [self._prob_band[n] for n in with_prob]
            raw = _read(self._probs, idx, window, self.prob_path)
            for n, i, band in zip(with_prob, idx, raw):
                ok = _nodata_mask(self._probs, band, i)
                valid &= ok
                probs[n] = np.where(ok, _probabilities(band), 0.0)
        return LayerBlock(masks, probs, valid)

    def close(self) -> None:
        for ds in (self._masks, self._probs):
            if ds is not None:
                ds.close()


def class_entity_name(label: str) -> str:
    """Entity name of a class: lower case, a parenthetical alias dropped ('water (Hydro)' -> 'water')."""
    name = re.sub(r"\s*\([^)]*\)\s*", " ", str(label)).strip()
    return " ".join(name.split()).lower() or str(label).strip().lower()


def load_classes(path: str | os.PathLike) -> dict[int, str]:
    """classes.json (class id -> name) as {id: entity name}, background classes left out."""
    classes = {cid: class_entity_name(name) for cid, name in read_classes_json(path).items()}
    classes = {cid: name for cid, name in classes.items() if name not in BACKGROUND_NAMES}
    if not classes:
        raise InputError(f"--classes {Path(path)}: only background classes, no entity")
    return classes


class LabelSource:
    """A class raster: each class is an entity mask with probability 1.0 inside it."""

    def __init__(self, labels: str | os.PathLike, classes: str | os.PathLike | Mapping[int, str]) -> None:
        self.path = Path(labels)
        self.classes = dict(classes) if isinstance(classes, Mapping) else load_classes(classes)
        #: What the user should know about these labels (classes.json ids absent from the raster).
        self.warnings = tuple(check_class_raster(self.path, self.classes))
        self._ds = open_raster(self.path)
        try:
            self.grid = _grid_of(self._ds)
        except BaseException:
            self._ds.close()
            raise
        self._ids: dict[str, list[int]] = {}
        for cid, name in sorted(self.classes.items()):
            self._ids.setdefault(name, []).append(cid)
        self.names = tuple(self._ids)
        self.inputs = (self.path,) + ((Path(classes),) if not isinstance(classes, Mapping) else ())

    def read(self, names: Sequence[str], window: Window) -> LayerBlock:
        lab = _read(self._ds, 1, window, self.path)
        valid = _nodata_mask(self._ds, lab, 1)
        masks = {n: np.isin(lab, self._ids[n]) & valid for n in names}
        return LayerBlock(masks, {}, valid)

    def close(self) -> None:
        self._ds.close()


def parse_vector_spec(spec: str) -> tuple[str, Path]:
    """'road=roads.gpkg' -> ('road', Path('roads.gpkg')), with a one-line error otherwise."""
    name, sep, path = spec.partition("=")
    if not sep or not name.strip() or not path.strip():
        raise InputError(f"--vector {spec!r}: write ENTITY=FILE, e.g. --vector road=roads.gpkg")
    return " ".join(name.split()).lower(), Path(path.strip())


class VectorSource:
    """Vector layers (any OGR format) rasterised onto a grid, window by window.

    Geometries are reprojected to the grid's CRS once and indexed with a shapely STRtree; each
    window rasterises only those it touches (rasterio.features.rasterize). Lines and points are
    burnt with ``all_touched`` (every pixel they cross), or buffered to ``line_width_m`` when
    given; polygons by pixel centre.
    """

    def __init__(self, layers: Mapping[str, str | os.PathLike], grid: Grid, line_width_m: float = 0.0) -> None:
        self.grid = grid
        self.names = tuple(layers)
        self.inputs = tuple(Path(p) for p in layers.values())
        if line_width_m < 0 or not math.isfinite(line_width_m):
            raise InputError(f"--line-width {line_width_m}: give a width in metres >= 0")
        self._layers = {}
        for name, path in layers.items():
            geoms = self._load(Path(path), grid)
            if line_width_m > 0:
                geoms = self._buffer_lines(geoms, line_width_m)
            areal = shapely.get_dimensions(geoms) == 2 if len(geoms) else np.zeros(0, bool)
            polys, thin = geoms[areal], geoms[~areal]
            self._layers[name] = ((polys, shapely.STRtree(polys)), (thin, shapely.STRtree(thin)))

    @staticmethod
    def _load(path: Path, grid: Grid) -> np.ndarray:
        import fiona  # fiona (GDAL's vector drivers, ~70 ms): only when a --vector layer is read

        if not path.exists():
            raise InputError(f"--vector: no such file: {path}")
        check_input_file(path, "--vector", folders=True)  # a FIFO would block fiona.open forever
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                with fiona.open(path) as src:
                    crs_wkt = src.crs_wkt
                    raw = [f["geometry"] for f in src if f["geometry"] is not None]
        except Exception as exc:  # fiona raises DriverError, CPLE_* and friends
            raise InputError(
                f"--vector {path}: not a readable vector layer ({' '.join(str(exc).split())[:120]})"
            ) from None
        if not crs_wkt:
            raise InputError(f"--vector {path}: the layer has no CRS; assign one (e.g. with ogr2ogr -a_srs)")
        geoms = np.array([shapely.geometry.shape(g) for g in raw], dtype=object)
        geoms = geoms[~shapely.is_empty(geoms)] if len(geoms) else geoms
        src_crs, dst_crs = ProjCRS.from_wkt(crs_wkt), ProjCRS.from_wkt(grid.crs.to_wkt())
        if len(geoms) and not src_crs.equals(dst_crs):
            tf = Transformer.from_crs(src_crs, dst_crs, always_xy=True)
            geoms = shapely.transform(geoms, lambda xy: np.column_stack(tf.transform(xy[:, 0], xy[:, 1])))
        return geoms

    def _buffer_lines(self, geoms: np.ndarray, width_m: float) -> np.ndarray:
        if not len(geoms):
            return geoms
        px_m, _ = self.grid.pixel_size_m()
        unit_per_m = math.hypot(self.grid.transform.a, self.grid.transform.d) / px_m
        thin = shapely.get_dimensions(geoms) < 2
        out = geoms.copy()
        out[thin] = shapely.buffer(geoms[thin], width_m / 2.0 * unit_per_m)
        return out

    def read(self, names: Sequence[str], window: Window) -> LayerBlock:
        shape = (int(window.height), int(window.width))
        box = shapely.box(*window_bounds(window, self.grid.transform))
        wt = window_transform(window, self.grid.transform)
        masks = {}
        for n in names:
            out = np.zeros(shape, dtype=bool)
            for (geoms, tree), touched in zip(self._layers[n], (False, True)):
                hits = geoms[tree.query(box)] if len(geoms) else geoms
                if len(hits):
                    burnt = rasterize(
                        ((g, 1) for g in hits),
                        out_shape=shape,
                        transform=wt,
                        fill=0,
                        all_touched=touched,
                        dtype="uint8",
                    )
                    out |= burnt > 0
            masks[n] = out
        return LayerBlock(masks, {}, np.ones(shape, dtype=bool))

    def close(self) -> None:
        pass


class CombinedSource:
    """Several sources on one grid; an entity in more than one is their union."""

    def __init__(self, sources: Sequence[LayerSource]) -> None:
        if not sources:
            raise InputError("no entity layers: give --masks, --labels with --classes, or --vector")
        self.sources = tuple(sources)
        self.grid = sources[0].grid
        for s in sources[1:]:
            if not s.grid.same_as(self.grid):
                raise InputError(
                    f"{s.inputs[0] if s.inputs else 'a layer'} is not on the grid of "
                    f"{sources[0].inputs[0] if sources[0].inputs else 'the first layer'}"
                    " (CRS, transform and size must match)"
                )
        names: list[str] = []
        for s in sources:
            names += [n for n in s.names if n not in names]
        self.names = tuple(names)
        self.inputs = tuple(p for s in sources for p in s.inputs)
        self.warnings = tuple(w for s in sources for w in getattr(s, "warnings", ()))

    def read(self, names: Sequence[str], window: Window) -> LayerBlock:
        out: LayerBlock | None = None
        for s in self.sources:
            block = s.read([n for n in names if n in s.names], window)
            if out is None:
                out = block
                continue
            out.valid &= block.valid
            for n, m in block.masks.items():
                if n in out.masks:
                    prev_p = out.probs.get(n, out.masks[n].astype(np.float32))
                    new_p = block.probs.get(n, m.astype(np.float32))
                    out.masks[n] = out.masks[n] | m
                    if n in out.probs or n in block.probs:
                        out.probs[n] = np.maximum(prev_p, new_p)
                else:
                    out.masks[n] = m
                    if n in block.probs:
                        out.probs[n] = block.probs[n]
        assert out is not None  # there is at least one source (__init__)
        return out

    def close(self) -> None:
        for s in self.sources:
            s.close()


@dataclass(frozen=True)
class ArraySource:
    """In-memory layers on a grid (tests, benchmarks, callers that already hold small arrays)."""

    grid: Grid
    masks: Mapping[str, np.ndarray]
    probs: Mapping[str, np.ndarray] = field(default_factory=dict)
    valid: np.ndarray | None = None
    inputs: tuple[Path, ...] = ()

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.masks)

    def read(self, names: Sequence[str], window: Window) -> LayerBlock:
        (r0, r1), (c0, c1) = window.toranges()
        sl = (slice(r0, r1), slice(c0, c1))
        valid = np.ones((r1 - r0, c1 - c0), bool) if self.valid is None else self.valid[sl].copy()
        return LayerBlock(
            {n: np.asarray(self.masks[n][sl], bool) for n in names},
            {n: self.probs[n][sl] for n in names if n in self.probs},
            valid,
        )

    def close(self) -> None:
        pass


# --------------------------------------------------------------------------------------------
# Block-wise composition
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ComposeStats:
    """What a composition produced: where, on what, and a summary of the costmap."""

    cost_path: Path
    lethal_path: Path
    halo: tuple[int, int]
    block_size: int
    blocks: int
    valid_pixels: int
    lethal_pixels: int
    mean_cost: float | None
    seconds: float
    keep_out_pixels: int = 0
    #: Cells the override polygons changed (overrides.OverrideCounts), None without overrides.
    overrides: OverrideCounts | None = None


def blocks(grid: Grid, block_size: int, halo: tuple[int, int]) -> Iterator[tuple[Window, Window]]:
    """(core, extended) windows covering the grid; extended = core + halo, clipped to the grid."""
    hr, hc = halo
    for r0 in range(0, grid.height, block_size):
        r1 = min(r0 + block_size, grid.height)
        for c0 in range(0, grid.width, block_size):
            c1 = min(c0 + block_size, grid.width)
            er0, er1 = max(r0 - hr, 0), min(r1 + hr, grid.height)
            ec0, ec1 = max(c0 - hc, 0), min(c1 + hc, grid.width)
            yield (Window(c0, r0, c1 - c0, r1 - r0), Window(ec0, er0, ec1 - ec0, er1 - er0))


def check_entities(program: Program, source_names: Sequence[str]) -> None:
    """Every entity the program reads must have a layer."""
    missing = [e for e in program.entities if e not in source_names]
    if missing:
        raise InputError(
            f"the program uses {', '.join(repr(m) for m in missing)} but the layers "
            f"have only {', '.join(source_names) or 'none'}; segment those entities or "
            "add them with --vector/--labels"
        )


def compute_halo(program: Program, grid: Grid) -> tuple[int, int]:
    """The program's halo on this grid, refused when it exceeds :data:`MAX_HALO_PX`."""
    px, py = grid.pixel_size_m()
    halo = program.halo((px, py))
    if max(halo) > MAX_HALO_PX:
        widest = max(program.statements, key=lambda s: s.value.reach[0])
        raise CostProgramError(
            f"the program looks {program.reach_m:g} m around each pixel, {max(halo)} pixels at "
            f"{min(px, py):.3g} m per pixel; at most {MAX_HALO_PX} pixels are allowed, use smaller radii",
            widest.line,
            widest.col,
        )
    return halo


def window_pixels(block_size: int, halo: tuple[int, int], grid: Grid) -> int:
    """Pixels of the largest extended window (block + halo on each side, clipped to the grid)."""
    hr, hc = halo
    return min(block_size + 2 * hr, grid.height) * min(block_size + 2 * hc, grid.width)


def pixels_read(block_size: int, halo: tuple[int, int], grid: Grid) -> int:
    """Pixels read and evaluated over all blocks of the grid (halos counted with each block)."""
    return sum(int(ext.width) * int(ext.height) for _, ext in blocks(grid, block_size, halo))


def grown_block_size(block_size: int, halo: tuple[int, int], grid: Grid) -> int:
    """The block size to compose with: ``block_size``, grown in whole multiples of itself while the
    halo is more than half a block wide, as long as a window stays within :data:`MAX_WINDOW_PX`
    (or the requested block's own window, when that is larger).

    Why: every block is evaluated on its window, so a halo of 2000 pixels around 1024-pixel
    blocks reads each pixel about 25 times; blocks at least twice the halo read each at most about
    4 times. The result is the same whatever the block size (block-wise evaluation is exact), and
    memory stays bounded by the window budget.
    """
    budget = max(MAX_WINDOW_PX, window_pixels(block_size, halo, grid))
    size = block_size
    while (
        size < 2 * max(halo)
        and size < max(grid.height, grid.width)
        and window_pixels(size + block_size, halo, grid) <= budget
    ):
        size += block_size
    return size


def evaluate_block(
    program: Program,
    source: LayerSource,
    core: Window,
    ext: Window,
    sampling: tuple[float, float],
    poll: Poll = never_cancelled,
) -> tuple[np.ndarray, np.ndarray]:
    """Cost (float32, NaN where no data) and lethal (uint8: 1 lethal or no data, 2 keep-out)
    for one core window. ``poll`` is the evaluator's cancellation check (raises to stop)."""
    block = source.read(program.entities, ext)
    shape = (int(ext.height), int(ext.width))
    result = evaluate_program(program, block.masks, block.probs, sampling=sampling, shape=shape, poll=poll)
    r0, c0 = int(core.row_off - ext.row_off), int(core.col_off - ext.col_off)
    sl = (slice(r0, r0 + int(core.height)), slice(c0, c0 + int(core.width)))
    valid = block.valid[sl]
    cost = result.cost[sl].astype(np.float32)
    cost[~valid] = np.nan
    lethal = (result.lethal[sl] | ~valid).astype(np.uint8)
    lethal[(lethal == 0) & result.keep_out[sl]] = KEEP_OUT_FLAG
    return cost, lethal


def compose_costmap(
    program: Program,
    source: LayerSource,
    out: str | os.PathLike,
    lethal_out: str | os.PathLike | None = None,
    *,
    block_size: int = DEFAULT_BLOCK,
    tags: Mapping[str, str] | None = None,
    progress: Progress | None = None,
    overrides: OverrideSet | None = None,
) -> ComposeStats:
    """Evaluate ``program`` over ``source`` block by block into ``out`` (+ the lethal sidecar).

    Both files are written atomically on the source's exact grid: ``out`` float32 'cost' in
    [0, 1], NaN where the layers have no data; ``lethal_out`` (default from :func:`output_paths`)
    uint8, 1 where the program says lethal or there is no data. Blocks grow when the program's
    halo is wide (:func:`grown_block_size`), and ``progress`` hears up front when the blocks will
    read many times the image's pixels. A cancel is honoured between blocks and inside the
    program's operations (``progress.cancelled()`` is polled throughout). ``overrides`` (operator
    polygons, :mod:`overseec_core.overrides`) are applied to each block after the program.
    """
    progress = progress or NullProgress()
    if block_size < 16:
        raise InputError(f"block size {block_size} is too small (at least 16 pixels)")
    t0 = time.perf_counter()
    out = Path(out)
    lethal_out = Path(lethal_out) if lethal_out is not None else output_paths(out)[1]
    if out.resolve() == lethal_out.resolve():
        raise InputError(f"the costmap and the lethal sidecar would both be {out}")
    check_entities(program, source.names)
    grid = source.grid
    halo = compute_halo(program, grid)
    block_size = grown_block_size(block_size, halo, grid)
    px, py = grid.pixel_size_m()
    sampling = (py, px)
    poll = partial(check_cancelled, progress)
    all_tags = {TAG_LETHAL: lethal_out.name, **(tags or {})}
    windows = list(blocks(grid, block_size, halo))
    valid_n = lethal_n = keep_out_n = 0
    override_n = OverrideCounts()  # reported only when there are overrides
    cost_sum = 0.0
    ratio = pixels_read(block_size, halo, grid) / max(grid.width * grid.height, 1)
    if ratio > HALO_NOTICE_RATIO:
        progress.message(
            f"the program looks {program.reach_m:g} m ({max(halo)} pixels) around each "
            f"pixel: {len(windows)} block(s) of {block_size} pixels read {ratio:.1f}x "
            "the image's pixels; the time grows with it"
        )
    progress.begin("costmap", len(windows), unit="block")
    try:
        with rasterio.Env(GDAL_CACHEMAX=GDAL_CACHE_BYTES), ExitStack() as stack:
            cost_w = stack.enter_context(
                RasterWriter(
                    out,
                    grid,
                    1,
                    "float32",
                    nodata=float("nan"),
                    descriptions=["cost"],
                    tags=all_tags,
                    inputs=source.inputs,
                )
            )
            lethal_w = stack.enter_context(
                RasterWriter(
                    lethal_out,
                    grid,
                    1,
                    "uint8",
                    descriptions=["lethal"],
                    tags={"OVERSEEC_COSTMAP_FILE": out.name},
                    inputs=source.inputs,
                )
            )
            for core, ext in windows:
                check_cancelled(progress)
                cost, lethal = evaluate_block(program, source, core, ext, sampling, poll)
                if overrides is not None:
                    cost, lethal, changed = apply_to_block(cost, lethal, overrides.burn(core))
                    override_n += changed
                ok = ~np.isnan(cost)
                valid_n += int(ok.sum())
                lethal_n += int(((lethal == 1) & ok).sum())
                keep_out_n += int((lethal == KEEP_OUT_FLAG).sum())
                cost_sum += float(cost[ok].sum(dtype=np.float64))
                cost_w.write(cost, int(core.row_off), int(core.col_off))
                lethal_w.write(lethal, int(core.row_off), int(core.col_off))
                progress.advance(1)
    finally:
        progress.end()
    return ComposeStats(
        cost_path=out,
        lethal_path=lethal_out,
        halo=halo,
        block_size=block_size,
        blocks=len(windows),
        valid_pixels=valid_n,
        lethal_pixels=lethal_n,
        mean_cost=cost_sum / valid_n if valid_n else None,
        seconds=time.perf_counter() - t0,
        keep_out_pixels=keep_out_n,
        overrides=override_n if overrides is not None else None,
    )


def compose_array(
    program: Program, source: LayerSource, block_size: int | None = None, poll: Poll = never_cancelled
) -> tuple[np.ndarray, np.ndarray]:
    """The whole costmap in memory (small grids, tests): block-wise when ``block_size`` is given
    (used as given: this is what tests block-wise exactness with). ``poll``: a cancellation check."""
    grid = source.grid
    px, py = grid.pixel_size_m()
    check_entities(program, source.names)
    halo = compute_halo(program, grid)
    size = block_size or max(grid.width, grid.height)
    cost = np.empty(grid.shape, np.float32)
    lethal = np.empty(grid.shape, np.uint8)
    for core, ext in blocks(grid, size, halo):
        c, lt = evaluate_block(program, source, core, ext, (py, px), poll)
        sl = core.toslices()
        cost[sl], lethal[sl] = c, lt
    return cost, lethal


def output_paths(out: str | os.PathLike) -> tuple[Path, Path, Path]:
    """(costmap, lethal sidecar, program text) beside each other.

    ``costmap.tif`` -> ``lethal.tif`` and ``costmap.program.txt``; any other name ``X.tif`` ->
    ``X.lethal.tif`` and ``X.program.txt``, so several costmaps can share a folder. The costmap's
    tags name both sidecars.
    """
    out = Path(out)
    if out.suffix.lower() not in (".tif", ".tiff"):
        raise InputError(f"--out {out}: the costmap is a GeoTIFF; give a .tif path")
    default = Path(runfiles.COSTMAP).stem
    lethal = out.with_name(runfiles.LETHAL if out.stem == default else f"{out.stem}.lethal.tif")
    return out, lethal, out.with_name(f"{out.stem}.program.txt")


def check_outputs(paths: Sequence[Path], inputs: Sequence[Path]) -> None:
    """Refuse outputs that would overwrite an input (before any work is done)."""
    for p in paths:
        check_output_path(p, inputs)


# --------------------------------------------------------------------------------------------
# The costmap stage: options, program resolution, result
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class CostmapOptions:
    """What `overseec costmap` (and the QGIS task) asks for.

    Layers: ``masks`` (a segment output folder) and/or ``labels`` + ``classes`` and/or
    ``vectors`` ("name=path" strings; rasterised on the grid of the other layers, or of ``grid``).
    Program: exactly one of ``prompt`` (interpreted offline), ``program`` (a file) or
    ``program_text``.
    """

    out: Path
    masks: Path | None = None
    labels: Path | None = None
    classes: Path | None = None
    vectors: tuple[str, ...] = ()
    grid: Path | None = None
    prompt: str | None = None
    program: Path | None = None
    program_text: str | None = None
    line_width_m: float = 0.0
    block_size: int = DEFAULT_BLOCK
    #: Prompt entity -> layer name, for names the matching rules do not find ("lake" -> "water").
    aliases: tuple[tuple[str, str], ...] = ()
    #: Override polygon files (overseec_core.overrides), applied after the program.
    overrides: tuple[Path, ...] = ()
    #: The prior table for hazards a prompt leaves unsaid (``interpret.priors``): a JSON file
    #: replacing the built-in one; ``no_priors`` switches priors off. Prompts only.
    priors: Path | None = None
    no_priors: bool = False

    def prior_table(self) -> PriorTable:
        """The priors a prompt is read with (one-line InputError for a bad file)."""
        return resolve_priors(self.priors, enabled=not self.no_priors)


@dataclass(frozen=True)
class ResolvedProgram:
    """The program text to run, where it came from, and what was said on the way."""

    text: str
    source: str  # "file", "text", "prompt:<interpreter source>"
    notes: tuple[str, ...] = ()
    interpretation: dict | None = None
    #: How the prompt's entities were matched to the layers (see interpret.matching).
    mapping: tuple = ()
    warnings: tuple[str, ...] = ()


@dataclass(frozen=True)
class CostmapResult:
    """What the costmap stage wrote and how."""

    costmap: Path
    lethal: Path
    program_file: Path
    manifest: Path
    program: str
    program_source: str
    entities: tuple[str, ...]  # entities the program reads
    layers: tuple[str, ...]  # entities the inputs provide
    notes: tuple[str, ...]
    warnings: tuple[str, ...]
    halo: tuple[int, int]
    blocks: int
    valid_pixels: int
    lethal_pixels: int
    mean_cost: float | None
    timings: dict[str, float]
    keep_out_pixels: int = 0
    #: Summary of the override polygons applied (overrides.OverrideSet.summary), if any.
    overrides: dict | None = None

    def to_json(self) -> dict:
        return {
            "costmap": str(self.costmap),
            "lethal": str(self.lethal),
            "program_file": str(self.program_file),
            "manifest": str(self.manifest),
            "program": self.program,
            "program_source": self.program_source,
            "entities": list(self.entities),
            "layers": list(self.layers),
            "notes": list(self.notes),
            "warnings": list(self.warnings),
            "halo": list(self.halo),
            "blocks": self.blocks,
            "valid_pixels": self.valid_pixels,
            "lethal_pixels": self.lethal_pixels,
            "keep_out_pixels": self.keep_out_pixels,
            "mean_cost": self.mean_cost,
            "timings": self.timings,
            "overrides": self.overrides,
        }


def open_layers(options: CostmapOptions) -> CombinedSource:
    """Open every layer source the options name, on one grid."""
    sources: list[LayerSource] = []
    try:
        if options.masks is not None:
            sources.append(MaskDirSource(options.masks))
        if options.labels is not None or options.classes is not None:
            if options.labels is None or options.classes is None:
                raise InputError("--labels and --classes go together (a class raster and its classes.json)")
            sources.append(LabelSource(options.labels, options.classes))
        if options.vectors:
            if sources:
                grid = sources[0].grid
            elif options.grid is not None:
                with open_raster(options.grid) as ds:
                    grid = _grid_of(ds)
            else:
                raise InputError("--vector layers need a grid: add --masks, --labels or --grid RASTER (e.g. the image)")
            specs = [parse_vector_spec(s) for s in options.vectors]
            names = [n for n, _ in specs]
            if len(set(names)) != len(names):
                raise InputError("two --vector layers have the same entity name; merge the files")
            sources.append(VectorSource(dict(specs), grid, options.line_width_m))
        return CombinedSource(sources)
    except BaseException:
        for s in sources:
            s.close()
        raise


def resolve_program(options: CostmapOptions, layer_names: Sequence[str]) -> ResolvedProgram:
    """The program text from a file, inline text or a prompt (interpreted offline).

    For a prompt, the interpreter's own program is used when every entity it reads has a layer;
    otherwise the program is synthesised again from its preferences restricted to the entities
    that have layers, and the notes say which entities were left out.
    """
    given = [x for x in (options.prompt, options.program, options.program_text) if x is not None]
    if len(given) != 1:
        raise InputError("give exactly one of --prompt TEXT or --program FILE")
    if options.program is not None:
        text = read_text_limited(options.program, MAX_PROGRAM_BYTES, "--program")
        return ResolvedProgram(text, "file")
    if options.program_text is not None:
        return ResolvedProgram(options.program_text, "text")
    assert options.prompt is not None  # the one given (above)
    return program_for_prompt(options.prompt, layer_names, dict(options.aliases), options.prior_table())


def program_for_prompt(
    prompt: str,
    layer_names: Sequence[str],
    aliases: Mapping[str, str] | None = None,
    priors: PriorTable | None = None,
) -> ResolvedProgram:
    """Interpret ``prompt`` offline and fit its program to the entities that have layers."""
    if not prompt or not prompt.strip():
        raise InputError("--prompt is empty; say what to prefer and avoid")
    return fit_program(interpret(prompt, offline=True, priors=priors), layer_names, aliases, priors)


def _said(pref, cues) -> bool:
    """Whether the prompt said something about this entity: a preference it stated (a level off
    neutral, or a permission, which carries the words it came from) or a cue naming it. A level
    taken from the prior table is not something the prompt said."""
    if any(pref.entity in (c.entity, c.other) for c in cues):
        return True
    return not getattr(pref, "prior", False) and (off_neutral(pref) or bool(getattr(pref, "phrase", "")))


def layer_preferences(interp, matches, priors: PriorTable | None = None) -> tuple[dict, list[str]]:
    """The preference each matched layer takes, and notes on conflicts.

    When several entities land on one layer, what the prompt said wins over what it did not
    (priors and unstated defaults), then the closer match (alias, name, synonym/modifier,
    broader, and among broader matches the nearer kind: grass before the baseball field on a
    ``vegetation`` layer; "follow the road, avoid the highway" keeps the road's preference on a
    ``road`` layer), then a prior over plain neutral, then the preference farthest from neutral
    (lethal first, ties to the worse). A prior carries over only to a layer that has a prior of
    its own (trees' prior never makes a whole ``vegetation`` layer avoided).
    """
    table = BUILT_IN_PRIORS if priors is None else priors
    prefs = {p.entity: p for p in interp.preferences}
    by_layer: dict[str, list] = {}
    for m in matches:
        if m.entity in prefs:
            pref = prefs[m.entity]
            for layer in m.layers:
                if getattr(pref, "prior", False) and table.for_name(layer) is None:
                    continue
                by_layer.setdefault(layer, []).append((pref, (RULES.index(m.rule), m.depth)))
    chosen, notes = {}, []
    for layer, cands in by_layer.items():
        best, _ = max(
            cands,
            key=lambda pr: (
                _said(pr[0], interp.cues),
                -pr[1][0],
                -pr[1][1],
                off_neutral(pr[0]),
                pr[0].lethal,
                abs(pr[0].weight - NEUTRAL),
                pr[0].weight,
            ),
        )
        chosen[layer] = replace(best, entity=layer)
        overruled = [
            p.entity
            for p, _ in cands
            if p is not best
            and _said(p, interp.cues)
            and (abs(p.weight - best.weight) > 1e-9 or p.lethal != best.lethal)
        ]
        if overruled:
            notes.append(
                f"layer '{layer}' stands for {', '.join(p.entity for p, _ in cands)}; "
                f"kept the preference of '{best.entity}' (over {', '.join(overruled)})"
            )
    return chosen, notes


def layer_priors(layer_names: Sequence[str], taken: Iterable[str], priors: PriorTable) -> dict:
    """Preferences from the prior table for layers no prompt entity stands for ("railway (Train)"
    in a class raster when the prompt never speaks of railways)."""
    out = {}
    for layer in layer_names:
        prior = priors.for_name(layer)
        if layer not in taken and prior is not None:
            out[layer] = Preference(layer, 0, prior.level, prior.lethal, prior=True)
    return out


def _layer_cues(interp, layer_of: Mapping[str, tuple[str, ...]]) -> tuple[list, list[str]]:
    """Cues carried over to layers; a condition whose other entity lands on the entity's own
    layer ("except at level crossings" on a ``railway`` layer) cannot be told apart: dropped."""
    cues, notes = [], []
    for c in interp.cues:
        for a in layer_of.get(c.entity, ()):
            others = layer_of.get(c.other, ()) if c.other else (None,)
            for b in others:
                if c.other and b == a:
                    notes.append(
                        f"'{c.kind}' of {c.entity} near {c.other}: both are the layer "
                        f"'{a}', so the condition cannot be drawn; dropped"
                    )
                    continue
                cues.append(replace(c, entity=a, other=b))
    return cues, notes


def fit_program(
    interp,
    layer_names: Sequence[str],
    aliases: Mapping[str, str] | None = None,
    priors: PriorTable | None = None,
) -> ResolvedProgram:
    """An interpretation's program, fitted to the layers that exist.

    Prompt entities are matched to layer names (:mod:`interpret.matching`: normalised names,
    synonyms, modifiers, broader classes, user ``aliases``). The interpretation's own program
    (LLM-written or synthesised) is kept when every entity matches a layer of its own name and
    no other layer takes a prior; otherwise a program is synthesised from the preferences
    carried over to the matched layers plus the priors (``priors``; None = the built-in table)
    of the layers no entity stands for. Raises :class:`InputError` when the prompt says nothing
    this tool understood, or nothing it says matches a layer (its words would have no effect).
    A prompt that only gives permissions ("buildings are fine") is kept, with a note: without
    priors to fall back on, its costmap is the shortest-route one.
    """
    table = BUILT_IN_PRIORS if priors is None else priors
    notes = list(getattr(interp, "notes", ()))
    unparsed = list(getattr(interp, "unparsed", ()))
    if unparsed:
        notes.append("not understood in the prompt: " + "; ".join(repr(u) for u in unparsed))
    source = f"prompt:{getattr(interp, 'source', 'offline')}"
    data = interp.to_json() if hasattr(interp, "to_json") else None
    matches = match_entities([e.name for e in interp.entities], layer_names, aliases)
    mapping_note = "entities -> layers: " + "; ".join(m.describe() for m in matches)
    stated = [p for p in interp.preferences if _said(p, interp.cues)]
    layer_of = {m.entity: m.layers for m in matches}
    warnings = [
        f"'{p.entity}' matches no layer, so the prompt's words about it have no effect "
        f"(layers: {', '.join(layer_names)}); add --alias '{p.entity}=LAYER'"
        for p in stated
        if not layer_of.get(p.entity)
    ]
    warnings += [
        f"alias {key}={target}: no layer is called '{target}' (layers: {', '.join(layer_names)}); ignored"
        for key, target in (aliases or {}).items()
        if match_entity(target, layer_names).rule != "name"
    ]
    if stated and not any(layer_of.get(p.entity) for p in stated):
        raise InputError(
            f"none of the entities the prompt speaks about "
            f"({', '.join(p.entity for p in stated)}) matches a layer "
            f"({', '.join(layer_names) or 'none'}); name a layer or add "
            "--alias ENTITY=LAYER"
        )
    if not stated:
        raise InputError(
            "the prompt states no preference this tool understood, so the costmap "
            "would be uniform; say what to prefer or avoid"
            + (f" (not understood: {'; '.join(repr(u) for u in unparsed)})" if unparsed else "")
        )
    notes.append(mapping_note)
    prefs, conflict_notes = layer_preferences(interp, matches, table)
    extra = layer_priors(layer_names, prefs, table)
    if extra:
        notes.append(
            "layers no prompt entity stands for, at their priors: "
            + ", ".join(f"{n} {'lethal' if p.lethal else f'{p.weight:g}'}" for n, p in extra.items())
        )
    permission_only = all(not off_neutral(p) for p in stated) and not interp.cues
    if permission_only:
        moved = [n for n, p in {**prefs, **extra}.items() if off_neutral(p)]
        notes.append(
            "the prompt only gives permission ("
            + ", ".join(p.entity for p in stated)
            + " at neutral); "
            + (
                f"the unsaid hazards keep their priors ({', '.join(moved)})"
                if moved
                else "nothing else is priced, so this is the shortest-route costmap"
            )
        )
    identity = all(m.layers == (m.entity,) for m in matches if m.layers)
    if identity and not extra:
        try:
            check_program(interp.program, layer_names)
            return ResolvedProgram(interp.program, source, tuple(notes), data, matches, tuple(warnings))
        except CostProgramError:
            pass
    cues, cue_notes = _layer_cues(interp, layer_of)
    notes += conflict_notes + cue_notes
    prefs.update(extra)
    ranks = dense_ranks({n: (p.weight, p.lethal) for n, p in prefs.items()})
    prefs = {n: replace(p, rank=ranks[n]) for n, p in prefs.items()}
    entities = list(prefs)
    hierarchy = {
        (a, b) for c, p in interp.hierarchy for a in layer_of.get(c, ()) for b in layer_of.get(p, ()) if a != b
    }
    text = program_from_interpretation(entities, list(prefs.values()), sorted(hierarchy), cues)
    return ResolvedProgram(text, source + "+refit", tuple(notes), data, matches, tuple(warnings))
