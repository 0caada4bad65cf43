"""The one vector reader: any OGR layer (GeoPackage, GeoJSON, Shapefile ...) as shapely features
in a target CRS.

Three stages read vectors (Synthesize's ``--vector`` layers and ``--override`` polygons,
Evaluate's reference and given paths); they all open the file here, so a missing, unreadable or
CRS-less file fails the same way, as a one-line :class:`~overseec_core.errors.InputError` that
names the option (``label``) and the file. What a stage then requires of the features (polygons
with a ``cost``, at least one line ...) it checks itself.

fiona (GDAL's vector drivers, ~70 ms to import) loads on first use: only when a vector is read.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Collection, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import shapely
import shapely.geometry
from pyproj import CRS as ProjCRS  # noqa: N811 (pyproj's CRS, named apart from rasterio's)
from pyproj import Transformer
from pyproj.exceptions import ProjError
from rasterio.crs import CRS

from overseec_core.errors import InputError
from overseec_core.io.grid import crs_label
from overseec_core.limits import check_input_file

#: Characters of the driver's own message kept in an "unreadable" error (it can be a page long).
DETAIL_CHARS = 160


@dataclass(frozen=True)
class Feature:
    """One feature of a vector layer, its geometry in the CRS the layer was read into."""

    index: int  # 0-based position in the layer (counts features without geometry too)
    fid: str  # the driver's feature id (GeoPackage fids start at 1, GeoJSON's at 0)
    geometry: Any  # a shapely geometry, or None when the feature has none
    properties: Mapping[str, Any] = field(default_factory=dict)


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())[:DETAIL_CHARS]


def _open_features(
    path: Path, label: str, noun: str, max_features: int | None, layer: str | None = None
) -> tuple[str, list[Feature]]:
    """(CRS WKT, '' when the layer has none; every feature in the layer's own CRS) of ``layer``
    (None: the file's first layer)."""
    import fiona  # only when a vector is read (GDAL's vector drivers)

    if layer is not None and layer not in (names := vector_layers(path, label, noun)):
        raise InputError(f"{label} {path}: no layer {layer!r} (it has: {', '.join(names)})")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with fiona.open(path, layer=layer) as src:
                if max_features is not None and len(src) > max_features:
                    raise InputError(f"{label} {path}: {len(src)} features; at most {max_features} are allowed")
                crs_wkt = src.crs_wkt or ""
                features = [
                    Feature(
                        index=k,
                        fid=str(f["id"]),
                        geometry=shapely.geometry.shape(f["geometry"]) if f["geometry"] else None,
                        properties=dict(f["properties"] or {}),
                    )
                    for k, f in enumerate(src)
                ]
    except InputError:
        raise
    except Exception as exc:  # fiona raises DriverError, CPLE_* and friends; shapely GeometryTypeError
        raise InputError(f"{label} {path}: not a readable vector {noun} ({_one_line(exc)})") from None
    return crs_wkt, features


def vector_layers(path: str | os.PathLike, label: str, noun: str = "layer") -> tuple[str, ...]:
    """The names of the layers in a vector file (a GeoPackage can hold several; most formats
    hold one), with the same one-line errors as :func:`read_vector`."""
    import fiona

    p = Path(path)
    if not p.exists():
        raise InputError(f"{label}: no such file: {p}")
    check_input_file(p, label, folders=True)  # a FIFO would block fiona forever
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return tuple(fiona.listlayers(p))
    except Exception as exc:  # fiona's DriverError and friends
        raise InputError(f"{label} {p}: not a readable vector {noun} ({_one_line(exc)})") from None


def _reprojected(geoms: list[Any], src: ProjCRS, dst: ProjCRS) -> list[Any]:
    """Geometries reprojected vertex by vertex (as GIS layers are), 2-D; unchanged when the CRSs are equal."""
    if not geoms or src.equals(dst):
        return geoms
    tf = Transformer.from_crs(src, dst, always_xy=True)
    arr = np.array(geoms, dtype=object)
    return list(shapely.transform(arr, lambda xy: np.column_stack(tf.transform(xy[:, 0], xy[:, 1]))))


def read_vector(
    path: str | os.PathLike,
    crs: CRS,
    *,
    label: str,
    geometry_types: Collection[str] | None = None,
    assume_crs: str | None = None,
    max_features: int | None = None,
    noun: str = "layer",
    layer: str | None = None,
) -> tuple[Feature, ...]:
    """The features of a vector file, their geometries reprojected to ``crs``.

    ``label`` names the input in messages (``"--vector"``, ``"--override"``, ``"reference
    path"``), ``noun`` what it should have been ("not a readable vector layer"). With
    ``geometry_types`` (shapely type names such as ``"LineString"``) only features of those
    types are kept, and features without geometry are dropped; without it every feature is
    kept, ``geometry`` None where it has none. A layer without a CRS is read in ``assume_crs``
    when given (RFC 7946 GeoJSON is WGS 84), else refused. More than ``max_features`` features
    are refused before any is read. ``layer`` names the layer of a file holding several (a
    GeoPackage's table); None reads the first.
    """
    p = Path(path)
    if not p.exists():
        raise InputError(f"{label}: no such file: {p}")
    check_input_file(p, label, folders=True)  # a FIFO would block fiona.open forever
    crs_wkt, features = _open_features(p, label, noun, max_features, layer)
    if not crs_wkt and assume_crs is None:
        raise InputError(f"{label} {p}: the layer has no CRS; assign one (e.g. with ogr2ogr -a_srs)")
    if geometry_types is not None:
        wanted = frozenset(geometry_types)
        features = [f for f in features if f.geometry is not None and f.geometry.geom_type in wanted]
    try:
        src = ProjCRS.from_wkt(crs_wkt) if crs_wkt else ProjCRS.from_user_input(assume_crs)
        dst = ProjCRS.from_wkt(crs.to_wkt())
        with_geometry = [f for f in features if f.geometry is not None]
        moved = iter(_reprojected([f.geometry for f in with_geometry], src, dst))
    except ProjError as exc:
        raise InputError(f"{label} {p}: cannot reproject to {crs_label(crs)} ({_one_line(exc)})") from None
    return tuple(Feature(f.index, f.fid, next(moved), f.properties) if f.geometry is not None else f for f in features)
