"""Entity layers, read a window at a time from files the user or earlier stages made.

- the segment stage's directory: ``masks.tif`` (+ ``probs.tif``), or ``refined_masks.tif``
  (+ ``refined_probs.tif``) when present; one band per entity, band descriptions = entity names;
- a class raster plus ``classes.json`` (class id -> name): each class becomes an entity with
  probability 1.0 inside it (background names such as "unlabeled" are no entity);
- vector layers (``road=roads.gpkg``), reprojected to the grid's CRS and rasterised per window
  (lines and points with ``all_touched``, or buffered to a width; polygons by pixel centre).

Sources can be combined; an entity present in several is their union (mask OR, probability max).
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

import numpy as np
import shapely
from rasterio.errors import RasterioError
from rasterio.features import rasterize
from rasterio.windows import Window
from rasterio.windows import bounds as window_bounds
from rasterio.windows import transform as window_transform

from overseec_core import runfiles
from overseec_core.errors import InputError, RasterError
from overseec_core.io.grid import Grid
from overseec_core.io.inputs import check_class_raster
from overseec_core.io.read import open_raster, read_classes_json
from overseec_core.io.vectors import read_vector

if TYPE_CHECKING:  # annotation only (options are plain values; layers are read before them)
    from overseec_core.synthesize.options import CostmapOptions

#: Names that mark a classes.json class as background, not an entity. A class is background when
#: one of its "/"-separated aliases, with parenthetical notes dropped, is one of these (see
#: :func:`is_background_class`).
BACKGROUND_NAMES = frozenset(
    {
        "unlabeled",
        "unlabelled",
        "unclassified",
        "background",
        "nodata",
        "no data",
        "no-data",
        "void",
        "ignore",
    }
)


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
            raise InputError(f"--masks {d}: not a directory (give the folder that holds {runfiles.MASKS})")
        chosen = next(((d / m, d / p) for m, p in runfiles.MASK_FILES if (d / m).exists()), None)
        if chosen is None:
            raise InputError(
                f"--masks {d}: no {runfiles.MASKS} or {runfiles.REFINED_MASKS} in it; run "
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


def is_background_class(label: str) -> bool:
    """Whether a classes.json name marks background (no entity).

    Datasets spell background in many ways: "unlabeled", "background/unlabeled",
    "background/unlabeled (non-road)", "Clutter/background". The name is read as "/"-separated
    aliases of one class, each with its parenthetical notes dropped ("(non-road)" says what the
    background is not, never that it is something); the class is background when any alias is a
    background name (:data:`BACKGROUND_NAMES`, case-insensitive). Only whole aliases count: a class
    called "background road" or "unlabeled building" names a thing and stays an entity.
    """
    aliases = (class_entity_name(part) for part in re.sub(r"\([^)]*\)", " ", str(label)).split("/"))
    return any(alias in BACKGROUND_NAMES for alias in aliases)


def load_class_entities(path: str | os.PathLike) -> dict[int, str]:
    """classes.json (class id -> name) as {id: entity name}, background classes
    (:func:`is_background_class`) left out."""
    labels = read_classes_json(path)
    classes = {cid: class_entity_name(name) for cid, name in labels.items() if not is_background_class(name)}
    if not classes:
        raise InputError(f"--classes {Path(path)}: only background classes, no entity")
    return classes


class LabelSource:
    """A class raster: each class is an entity mask with probability 1.0 inside it."""

    def __init__(self, labels: str | os.PathLike, classes: str | os.PathLike | Mapping[int, str]) -> None:
        self.path = Path(labels)
        self.classes = dict(classes) if isinstance(classes, Mapping) else load_class_entities(classes)
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
        """The layer's non-empty geometries, in the grid's CRS."""
        features = read_vector(path, grid.crs, label="--vector")
        geoms = np.array([f.geometry for f in features if f.geometry is not None], dtype=object)
        return geoms[~shapely.is_empty(geoms)] if len(geoms) else geoms

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
