"""Masks as polygons: a segment folder's masks or a class raster as a GeoPackage, one layer per entity.

Each polygon is one 4-connected region of an entity's mask (the connectivity of GDAL's
polygonizer and of scipy's labelling alike), with

* ``area_m2``: its area in ground square metres: pixel counts times the ground size of a pixel
  (:func:`overseec_core.io.grid.ground_scale`, geodesic for geographic CRSs, the local scale for
  Web Mercator), or the simplified polygon's area measured in ground metres;
* ``mean_prob``: the mean probability over its pixels (the probability raster that goes with the
  mask; 1.0 for a class raster; empty when a segment folder has no probabilities);
* ``pixels``: how many pixels it covers.

Geometries are in the raster's CRS. With ``simplify_m`` > 0 each polygon is simplified by that
tolerance in ground metres (Douglas-Peucker with topology preserved: rings neither cross nor
vanish, each geometry stays valid); with 0 (the default) the edges are the exact pixel edges,
collinear vertices dropped, so the areas are the pixel counts exactly.

Streaming (:mod:`.polygonize`): the raster is read in strips of ``block_rows`` rows
(:data:`DEFAULT_BLOCK_ROWS`) over the full width; regions inside a strip are written at once,
regions crossing strips are joined across the seams and written once complete, so memory is a
strip plus the regions still open, whatever the image's height, and the polygons are the same for
any strip height (tested). Entities are done one after the other (one pass each), so one
GeoPackage layer is open for writing at a time.

The GeoPackage is written under a hidden temporary name beside the target, reopened and its
features counted, flushed and renamed (:mod:`overseec_core.io.atomic`); an output that is one of
the inputs is refused before anything is read. Cancel: checked after every strip.
"""

from __future__ import annotations

import os
import time
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import shapely.geometry
from rasterio.errors import RasterioError
from rasterio.windows import Window

from overseec_core import runfiles
from overseec_core.errors import InputError, OutputError, RasterError
from overseec_core.io.atomic import atomic_path, output_error, space_reason
from overseec_core.io.grid import Grid
from overseec_core.io.inputs import check_class_raster
from overseec_core.io.manifest import RunDir
from overseec_core.io.read import GDAL_ERRORS, open_raster
from overseec_core.io.transaction import output_transaction
from overseec_core.io.write import check_output_path, gdal_errors
from overseec_core.locate.polygonize import DEFAULT_BLOCK_ROWS, FeatureMaker, regions
from overseec_core.progress import Progress, check_cancelled

#: The fields of every layer (fiona schema types).
FIELDS = {"area_m2": "float", "mean_prob": "float", "pixels": "int"}
SCHEMA = {"geometry": "Polygon", "properties": dict(FIELDS)}
#: Files SQLite may leave beside a GeoPackage being written (deleted with a failed one).
SQLITE_SIDECARS = ("-journal", "-wal", "-shm")
#: Records handed to fiona at a time.
_WRITE_BATCH = 2000


# --------------------------------------------------------------------------------------------
# Sources: what is vectorized, one entity's mask (and probabilities) a window at a time
# --------------------------------------------------------------------------------------------


def _read(ds, indexes: int, window: Window, path: Path) -> np.ndarray:
    try:
        return ds.read(indexes, window=window)
    except (*GDAL_ERRORS, RasterioError) as exc:
        raise RasterError(f"{path}: corrupt or truncated raster ({' '.join(str(exc).split())[:160]})") from None


def _grid(ds, path: Path) -> Grid:
    if ds.crs is None:
        raise RasterError(f"{path} has no CRS; polygons need a georeferenced raster")
    return Grid(crs=ds.crs, transform=ds.transform, width=ds.width, height=ds.height)


def _band_names(ds, path: Path) -> tuple[str, ...]:
    """Band descriptions as entity names: every band named, no two alike (GeoPackage tables
    compare names without case)."""
    names = tuple(" ".join((d or "").split()) for d in ds.descriptions)
    missing = [str(i + 1) for i, n in enumerate(names) if not n]
    if missing:
        raise InputError(f"{path}: band(s) {', '.join(missing)} have no description; each band names its entity")
    folded = [n.casefold() for n in names]
    if len(set(folded)) != len(folded):
        raise InputError(f"{path}: two bands have the same entity name ({', '.join(names)})")
    return names


class MaskFolderSource:
    """A segment folder: the preferred mask raster (refined over coarse, ``runfiles``) and the
    probability raster that goes with it; one band per entity, named by its description."""

    kind = "segment folder"

    def __init__(self, folder: str | os.PathLike) -> None:
        d = Path(folder)
        if not d.is_dir():
            raise InputError(f"{d}: no such folder (give the folder `overseec segment` wrote)")
        mask = runfiles.first_existing(d, "mask")
        if mask is None:
            raise InputError(
                f"{d}: no {runfiles.MASKS} or {runfiles.REFINED_MASKS} in it; run `overseec segment` first"
            )
        self.mask_path = mask
        prob = d / dict(runfiles.MASK_FILES)[mask.name]
        self.prob_path = prob if prob.is_file() else None
        self._masks = open_raster(mask)
        self._probs = None
        try:
            self.grid = _grid(self._masks, mask)
            self.names = _band_names(self._masks, mask)
            self._prob_band: dict[str, int] = {}
            if self.prob_path is not None:
                self._probs = open_raster(self.prob_path)
                if not _grid(self._probs, self.prob_path).same_as(self.grid):
                    raise InputError(f"{self.prob_path} and {mask} are on different grids")
                self._prob_band = {n: i + 1 for i, n in enumerate(_band_names(self._probs, self.prob_path))}
        except BaseException:
            self.close()
            raise
        self.inputs = tuple(p for p in (mask, self.prob_path) if p is not None)

    def has_probabilities(self, name: str) -> bool:
        """Whether the folder holds ``name``'s probabilities (else its mean_prob stays empty)."""
        return name in self._prob_band

    def read(self, name: str, window: Window) -> tuple[np.ndarray, np.ndarray | None]:
        """(mask, probabilities or None) of entity ``name`` in ``window``; nodata is outside."""
        band = self.names.index(name) + 1
        raw = _read(self._masks, band, window, self.mask_path)
        nodata = self._masks.nodatavals[band - 1]
        mask = raw > 0
        if nodata is not None and not np.isnan(nodata):
            mask &= raw != nodata
        if name not in self._prob_band or self._probs is None:
            return mask, None
        prob = _read(self._probs, self._prob_band[name], window, self.prob_path or Path())
        if prob.dtype.kind in "ui":  # integer-scaled probabilities (0..max)
            prob = prob.astype(np.float32) / float(np.iinfo(prob.dtype).max)
        return mask, np.nan_to_num(prob.astype(np.float32, copy=False), nan=0.0)

    def close(self) -> None:
        """Close the rasters."""
        for ds in (self._masks, self._probs):
            if ds is not None:
                ds.close()


class ClassRasterSource:
    """A class raster and its classes (class id -> entity name, background left out by the
    caller): each class name is an entity, several ids of one name one entity; probability 1."""

    kind = "class raster"

    def __init__(
        self, labels: str | os.PathLike, classes: Mapping[int, str], classes_file: str | os.PathLike | None
    ) -> None:
        self.path = Path(labels)
        self.warnings = tuple(check_class_raster(self.path, classes))  # one band of ids that go with classes
        self._ids: dict[str, list[int]] = {}
        for cid, name in sorted(classes.items()):
            self._ids.setdefault(name, []).append(int(cid))
        self.names = tuple(self._ids)
        if len({n.casefold() for n in self.names}) != len(self.names):
            raise InputError(f"--classes: two class names differ only in case ({', '.join(self.names)})")
        self._ds = open_raster(self.path)
        try:
            self.grid = _grid(self._ds, self.path)
        except BaseException:
            self._ds.close()
            raise
        self.inputs = (self.path,) + ((Path(classes_file),) if classes_file is not None else ())

    def has_probabilities(self, name: str) -> bool:
        """Always: a class is certain (probability 1 over its pixels)."""
        return True

    def read(self, name: str, window: Window) -> tuple[np.ndarray, np.ndarray | None]:
        """(mask of the entity's class ids, None: probability 1) in ``window``."""
        lab = _read(self._ds, 1, window, self.path)
        mask = np.isin(lab, self._ids[name])
        nodata = self._ds.nodatavals[0]
        if nodata is not None and not np.isnan(nodata):
            mask &= lab != nodata
        return mask, None

    def close(self) -> None:
        """Close the raster."""
        self._ds.close()


# --------------------------------------------------------------------------------------------
# The result
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class LayerSummary:
    """One entity's layer: polygons written, their total area (m²) and pixels."""

    name: str
    polygons: int
    area_m2: float
    pixels: int

    def to_json(self) -> dict[str, Any]:
        """JSON-ready summary."""
        return {"name": self.name, "polygons": self.polygons, "area_m2": self.area_m2, "pixels": self.pixels}


@dataclass(frozen=True)
class VectorizeResult:
    """What ``vectorize`` wrote: the GeoPackage, its layers, and how."""

    out: Path
    source: str
    inputs: tuple[Path, ...]
    layers: tuple[LayerSummary, ...]
    pixel_size_m: tuple[float, float]
    simplify_m: float
    block_rows: int
    seconds: float
    warnings: tuple[str, ...] = ()

    def to_json(self) -> dict[str, Any]:
        """The ``--json`` document (and the manifest's ``vectors`` entry)."""
        return {
            "out": str(self.out),
            "source": self.source,
            "inputs": [str(p) for p in self.inputs],
            "layers": [s.to_json() for s in self.layers],
            "polygons": sum(s.polygons for s in self.layers),
            "pixel_size_m": list(self.pixel_size_m),
            "simplify_m": self.simplify_m,
            "block_rows": self.block_rows,
            "seconds": round(self.seconds, 3),
            "warnings": list(self.warnings),
        }


# --------------------------------------------------------------------------------------------
# Writing
# --------------------------------------------------------------------------------------------


def _write_layer(tmp: Path, name: str, crs_wkt: str, records: Iterator[dict[str, Any]]) -> int:
    """Write one layer of the GeoPackage ``tmp`` from a stream of records; return the count."""
    import fiona  # GDAL's vector drivers: only when polygons are written

    count = 0
    with fiona.open(tmp, "w", driver="GPKG", layer=name, schema=SCHEMA, crs_wkt=crs_wkt) as dst:
        batch: list[dict[str, Any]] = []
        for record in records:
            batch.append(record)
            if len(batch) >= _WRITE_BATCH:
                dst.writerecords(batch)
                count += len(batch)
                batch = []
        if batch:
            dst.writerecords(batch)
            count += len(batch)
    return count


def _check_layers(tmp: Path, written: Mapping[str, int]) -> str | None:
    """None when every layer of the written GeoPackage holds its features, else what is wrong."""
    import fiona

    present = set(fiona.listlayers(tmp))
    for name, count in written.items():
        if name not in present:
            return f"incomplete file: layer {name} is missing"
        with fiona.open(tmp, layer=name) as src:
            if len(src) != count:
                return f"incomplete file: layer {name} has {len(src)} of {count} features"
    return None


@dataclass
class _Tally:
    """What one layer received so far."""

    polygons: int = 0
    area_m2: float = 0.0
    pixels: int = 0


Source = MaskFolderSource | ClassRasterSource


#: Every this many polygons of a layer, a progress message with the count and the rate.
COUNT_EVERY = 50_000
#: A layer with more polygons than this gets one warning: a speckled mask (minutes to write,
#: a file QGIS draws slowly), and what makes it smaller.
VERY_MANY_POLYGONS = 500_000


def _count_message(progress: Progress | None, name: str, tally: _Tally, t0: float) -> None:
    """The running count of a layer's polygons and the rate, every :data:`COUNT_EVERY`; one
    warning when it passes :data:`VERY_MANY_POLYGONS`."""
    n = tally.polygons
    too_many = n == VERY_MANY_POLYGONS + 1
    if progress is None or (n % COUNT_EVERY != 0 and not too_many):
        return
    rate = n / max(time.perf_counter() - t0, 1e-9)
    if too_many:
        progress.message(
            f"vectorize: {name} has over {VERY_MANY_POLYGONS:,} polygons (a speckled mask; {rate:,.0f}/s); "
            "--simplify METRES, or sieving the mask first (gdal_sieve.py -st N), makes it far smaller and faster"
        )
    else:
        progress.message(f"vectorize: {name}: {n:,} polygons so far ({rate:,.0f}/s)")


def _entity_records(
    source: Source, name: str, maker: FeatureMaker, block_rows: int, progress: Progress | None, tally: _Tally
) -> Iterator[dict[str, Any]]:
    """The records of one entity's layer, region by region as the strips finish them; the
    count and rate said as they grow (:func:`_count_message`)."""
    g = source.grid
    with_prob = source.has_probabilities(name)
    t0 = time.perf_counter()
    for region in regions(lambda w: source.read(name, w), g.width, g.height, block_rows, progress):
        mean = (region.prob_sum / region.pixels) if (with_prob and region.pixels) else None
        for polygon, area, pixels in maker.features(region):
            tally.polygons += 1
            tally.area_m2 += area
            tally.pixels += pixels
            _count_message(progress, name, tally, t0)
            yield {
                "geometry": shapely.geometry.mapping(polygon),
                "properties": {"area_m2": area, "mean_prob": mean, "pixels": pixels},
            }


def write_polygons(
    source: Source, out: Path, maker: FeatureMaker, block_rows: int, progress: Progress | None
) -> tuple[LayerSummary, ...]:
    """Every entity of ``source`` as a layer of the GeoPackage ``out``, written atomically."""
    import fiona

    names = source.names
    if progress is not None:
        progress.begin("vectorize", len(names) * -(-source.grid.height // block_rows), unit="strip")
    summaries: list[LayerSummary] = []
    written: dict[str, int] = {}
    crs_wkt = source.grid.crs.to_wkt()
    with fiona.Env(), gdal_errors() as messages:
        with atomic_path(out, suffix=".partial.gpkg", sidecars=SQLITE_SIDECARS) as tmp:
            tmp.unlink()  # the driver creates the file itself
            try:
                for name in names:
                    tally = _Tally()
                    records = _entity_records(source, name, maker, block_rows, progress, tally)
                    written[name] = _write_layer(tmp, name, crs_wkt, records)
                    summaries.append(LayerSummary(name, tally.polygons, tally.area_m2, tally.pixels))
                problem = _check_layers(tmp, written)
            except (OSError, RuntimeError, fiona.errors.FionaError) as exc:
                raise output_error(out, exc, messages, tmp) from None
            if problem or space_reason(None, messages):
                raise output_error(out, None, [problem] if problem else messages, tmp)
    if progress is not None:
        progress.end()
    return tuple(summaries)


# --------------------------------------------------------------------------------------------
# The stage
# --------------------------------------------------------------------------------------------


def _check_out(out: Path, inputs: Sequence[Path]) -> Path:
    """Refuse an output that is an input (or bookkeeping, or unwritable), then one not *.gpkg."""
    check_output_path(out, inputs)
    if out.suffix.lower() != ".gpkg":
        raise OutputError(f"--out {out}: polygons are written as a GeoPackage; name it *.gpkg")
    return out


def vectorize(
    source: Source,
    out: str | os.PathLike,
    simplify_m: float = 0.0,
    block_rows: int = DEFAULT_BLOCK_ROWS,
    progress: Progress | None = None,
    command_args: dict[str, Any] | None = None,
) -> VectorizeResult:
    """Write ``source``'s entities as polygons into the GeoPackage ``out`` (one layer each) and
    record it in the manifest of ``out``'s folder (``vectors.<file name>``); closes ``source``."""
    t0 = time.perf_counter()
    try:
        if not (simplify_m >= 0 and np.isfinite(simplify_m)):
            raise InputError(f"--simplify must be a distance in metres >= 0, not {simplify_m}")
        if block_rows < 1:
            raise InputError(f"--block-rows must be at least 1, not {block_rows}")
        out = _check_out(Path(out), source.inputs)
        scale = source.grid.ground_scale()
        maker = FeatureMaker(source.grid.transform, scale.pixel_size_m, float(simplify_m))
        with output_transaction(progress):
            layers = write_polygons(source, out, maker, block_rows, progress)
            check_cancelled(progress)
            result = VectorizeResult(
                out=out,
                source=source.kind,
                inputs=tuple(source.inputs),
                layers=layers,
                pixel_size_m=scale.pixel_size_m,
                simplify_m=float(simplify_m),
                block_rows=block_rows,
                seconds=time.perf_counter() - t0,
                warnings=tuple(getattr(source, "warnings", ())),
            )
            run = RunDir(out.parent, command="vectorize", args=command_args)
            for path in source.inputs:
                run.record_input(f"vectorize_{path.name}", path)
            run.set_entry("vectors", out.name, {**result.to_json(), "ground_scale": scale.to_dict()})
            run.save()
        return result
    finally:
        source.close()


def vectorize_folder(folder: str | os.PathLike, out: str | os.PathLike, **kwargs: Any) -> VectorizeResult:
    """A segment folder's masks (refined over coarse) as polygons in ``out``; see :func:`vectorize`
    (``segment --vectors`` calls this after segmenting)."""
    return vectorize(MaskFolderSource(folder), out, **kwargs)


def vectorize_labels(
    labels: str | os.PathLike,
    classes: Mapping[int, str],
    out: str | os.PathLike,
    classes_file: str | os.PathLike | None = None,
    **kwargs: Any,
) -> VectorizeResult:
    """A class raster as polygons, one layer per class name of ``classes`` (id -> entity name,
    background already left out, as ``synthesize.layers.load_class_entities`` gives it)."""
    return vectorize(ClassRasterSource(labels, classes, classes_file), out, **kwargs)


__all__ = [
    "DEFAULT_BLOCK_ROWS",
    "ClassRasterSource",
    "MaskFolderSource",
    "Source",
    "VectorizeResult",
    "vectorize",
    "vectorize_folder",
    "vectorize_labels",
]
