"""The output grid of an imagery extraction: CRS, extent and size, fixed before anything is fetched.

:func:`plan_extraction` fixes the grid :func:`overseec_qgis.extract.extract_layer` renders into: a
projected CRS in metres (the layer's, else the project's, when it is true to scale there, else
the WGS 84 / UTM zone of the extent's centre), the extent transformed into it and snapped
outwards to the GSD grid, and the size in pixels -- refused in one line, before anything is
fetched, when it is above the pixel limit (with the GSD that would fit).

Why "true to scale": overseec measures ground metres (DESIGN.md, "Georeferencing is never
lost"); a Web Mercator metre is 0.68 ground metres at 47 deg N, so an XYZ layer's own CRS would
silently give the wrong GSD. A CRS is used as it is only when a step at the extent's centre
measures within 0.1 % of its nominal length on the ellipsoid -- the core's rule for stating a
projected raster's pixel size.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any
from urllib.parse import urlparse

from qgis.core import (
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsCoordinateTransformContext,
    QgsCsException,
    QgsDistanceArea,
    QgsPointXY,
    QgsProject,
    QgsProviderRegistry,
    QgsRasterLayer,
    QgsRectangle,
    QgsUnitTypes,
)

from overseec_core.errors import InputError

#: Default pixel limit of one extraction: 400 Mpx is a 20,000 x 20,000 image, 8 x 8 km at 0.4 m --
#: already hours of segmentation on a CPU, and a heavy download from a tile server.
DEFAULT_MAX_PIXELS = 400_000_000
#: Smallest useful image side; below it the extent is almost certainly a mis-click.
MIN_SIDE_PX = 16
#: A CRS is "true to scale" when a step at the extent's centre measures within this fraction of
#: its nominal length on the ellipsoid (the core's rule for a projected raster's pixel size).
TRUE_SCALE_TOLERANCE = 1e-3
#: openstreetmap.org's tile usage policy forbids bulk downloading; QGIS's "Convert map to raster"
#: stops at 5000 tiles, so does this.
OSM_MAX_TILES = 5000
OSM_TILE_HOSTS = ("tile.openstreetmap.org",)


@dataclass(frozen=True)
class ExtractPlan:
    """The output grid of one extraction: ``width`` x ``height`` pixels of ``gsd_m`` metres in
    ``crs`` (projected, metres), covering ``extent`` (snapped to the GSD grid, so
    ``extent.width() == width * gsd_m``)."""

    crs: QgsCoordinateReferenceSystem
    extent: QgsRectangle
    gsd_m: float
    width: int
    height: int

    def megapixels(self) -> float:
        """The output's size in millions of pixels."""
        return self.width * self.height / 1e6

    def geotransform(self) -> tuple[float, float, float, float, float, float]:
        """GDAL's geotransform of the output (north up, square pixels)."""
        return (self.extent.xMinimum(), self.gsd_m, 0.0, self.extent.yMaximum(), 0.0, -self.gsd_m)

    def describe(self) -> str:
        """One line for a dock or a log: size, GSD and CRS."""
        return (
            f"{self.width:,} x {self.height:,} px ({self.megapixels():.1f} Mpx) at {self.gsd_m:g} m "
            f"in {self.crs.authid() or self.crs.description()}"
        )


# --------------------------------------------------------------------------------------------
# Planning: CRS, extent, size
# --------------------------------------------------------------------------------------------


def utm_crs(lon: float, lat: float) -> QgsCoordinateReferenceSystem:
    """WGS 84 / UTM zone of a longitude/latitude (EPSG:326zz north, 327zz south)."""
    zone = min(60, max(1, int(math.floor((lon + 180.0) / 6.0)) + 1))
    return QgsCoordinateReferenceSystem(f"EPSG:{(32600 if lat >= 0 else 32700) + zone}")


def is_metric_projected(crs: QgsCoordinateReferenceSystem) -> bool:
    """A valid projected CRS whose map unit is the metre."""
    return crs.isValid() and not crs.isGeographic() and crs.mapUnits() == QgsUnitTypes.DistanceMeters


def local_scale(crs: QgsCoordinateReferenceSystem, x: float, y: float, step: float = 100.0) -> tuple[float, float]:
    """Ground metres per map metre east and north at (x, y) of a projected CRS, measured as
    geodesics on the CRS's ellipsoid (about 1 on UTM, about 0.68 on Web Mercator at 47 deg N)."""
    da = QgsDistanceArea()
    da.setSourceCrs(crs, QgsCoordinateTransformContext())
    da.setEllipsoid(crs.ellipsoidAcronym() or "EPSG:7030")
    east = da.measureLine(QgsPointXY(x - step / 2, y), QgsPointXY(x + step / 2, y))
    north = da.measureLine(QgsPointXY(x, y - step / 2), QgsPointXY(x, y + step / 2))
    return east / step, north / step


def true_to_scale(
    crs: QgsCoordinateReferenceSystem, centre: QgsPointXY, centre_crs: QgsCoordinateReferenceSystem
) -> bool:
    """Whether map metres of ``crs`` are ground metres (within 0.1 %) at ``centre``."""
    if not is_metric_projected(crs):
        return False
    try:
        p = QgsCoordinateTransform(centre_crs, crs, QgsCoordinateTransformContext()).transform(centre)
        sx, sy = local_scale(crs, p.x(), p.y())
    except QgsCsException:
        return False
    return all(math.isfinite(s) and abs(s - 1.0) <= TRUE_SCALE_TOLERANCE for s in (sx, sy))


def choose_crs(
    layer_crs: QgsCoordinateReferenceSystem,
    extent: QgsRectangle,
    extent_crs: QgsCoordinateReferenceSystem,
    project_crs: QgsCoordinateReferenceSystem | None = None,
) -> QgsCoordinateReferenceSystem:
    """The output CRS: the layer's, else the project's, when projected in metres and true to scale
    at the extent's centre; else the WGS 84 / UTM zone of that centre."""
    centre = extent.center()
    for candidate in (layer_crs, project_crs):
        if candidate is not None and true_to_scale(candidate, centre, extent_crs):
            return candidate
    wgs84 = QgsCoordinateReferenceSystem("EPSG:4326")
    try:
        lonlat = QgsCoordinateTransform(extent_crs, wgs84, QgsCoordinateTransformContext()).transform(centre)
    except QgsCsException as exc:
        raise InputError(f"the extent's centre cannot be placed on the globe ({exc})") from None
    return utm_crs(lonlat.x(), lonlat.y())


def _snap(lo: float, hi: float, gsd: float) -> tuple[float, float, int]:
    """Widen [lo, hi] to whole GSD steps on the grid through 0; returns (lo, hi, steps)."""
    eps = 1e-6  # coordinates already on the grid stay there despite float noise
    a = math.floor(lo / gsd + eps)
    b = math.ceil(hi / gsd - eps)
    b = max(b, a + 1)
    return a * gsd, b * gsd, b - a


def fitting_gsd(width_m: float, height_m: float, gsd: float, max_pixels: int) -> float:
    """The smallest GSD, rounded up to two significant figures, whose snapped grid over a
    ``width_m`` x ``height_m`` extent fits in ``max_pixels``."""
    g = gsd * math.sqrt(max(1.0, (width_m / gsd) * (height_m / gsd) / max_pixels))
    for _ in range(100):
        digits = 10 ** (math.floor(math.log10(g)) - 1)
        nice = math.ceil(g / digits - 1e-9) * digits
        if (math.ceil(width_m / nice) + 1) * (math.ceil(height_m / nice) + 1) <= max_pixels:
            return nice
        g = nice * 1.01
    return g


def _is_osm_tiles(layer: QgsRasterLayer) -> bool:
    if layer.providerType() != "wms":
        return False
    url = QgsProviderRegistry.instance().decodeUri("wms", layer.source()).get("url", "") or ""
    host = (urlparse(str(url)).hostname or "").lower()
    return any(host == h or host.endswith("." + h) for h in OSM_TILE_HOSTS)


def _finite(rect: QgsRectangle) -> bool:
    values = (rect.xMinimum(), rect.yMinimum(), rect.xMaximum(), rect.yMaximum())
    return not rect.isNull() and all(math.isfinite(v) for v in values)


def _check_request(layer: QgsRasterLayer, extent: QgsRectangle, extent_crs, gsd_m: Any, max_pixels: int) -> float:
    """The GSD as a float, after refusing an unusable layer, GSD, limit or extent (one line each)."""
    if layer is None or not layer.isValid():
        raise InputError("choose a valid raster layer to extract imagery from")
    try:
        gsd = float(gsd_m)
    except (TypeError, ValueError):
        raise InputError(f"GSD {gsd_m!r} is not a number of metres") from None
    if not math.isfinite(gsd) or gsd <= 0:
        raise InputError(f"GSD must be a positive number of metres per pixel, not {gsd_m!r}")
    if max_pixels < 1:
        raise InputError(f"the pixel limit must be at least 1, not {max_pixels}")
    if not _finite(extent) or extent.width() <= 0 or extent.height() <= 0:
        raise InputError("the extent is empty; draw a rectangle on the map or use the canvas extent")
    if not extent_crs.isValid():
        raise InputError("the extent has no valid CRS")
    return gsd


def _target_crs(
    layer: QgsRasterLayer,
    extent: QgsRectangle,
    extent_crs: QgsCoordinateReferenceSystem,
    target_crs: QgsCoordinateReferenceSystem | None,
    project_crs: QgsCoordinateReferenceSystem | None,
) -> QgsCoordinateReferenceSystem:
    if target_crs is None or not target_crs.isValid():
        if project_crs is None:
            project_crs = QgsProject.instance().crs()
        return choose_crs(layer.crs(), extent, extent_crs, project_crs)
    if not is_metric_projected(target_crs):
        raise InputError(
            f"target CRS {target_crs.authid() or target_crs.description()} is not projected in metres; "
            "choose a projected CRS (e.g. a UTM zone) or leave it empty"
        )
    return target_crs


def _extent_in(
    layer: QgsRasterLayer, extent: QgsRectangle, extent_crs: QgsCoordinateReferenceSystem, crs
) -> QgsRectangle:
    """The extent's bounding box in ``crs`` (edges densified); refused when it misses a file layer."""
    context = QgsProject.instance().transformContext()
    try:
        box = QgsCoordinateTransform(extent_crs, crs, context).transformBoundingBox(extent)
    except QgsCsException as exc:
        raise InputError(f"the extent cannot be transformed to {crs.authid()} ({exc})") from None
    if not _finite(box):
        raise InputError(f"the extent cannot be transformed to {crs.authid()}")
    if layer.providerType() != "wms":  # files and VRTs have a real extent; tile services cover the world
        try:
            covered = QgsCoordinateTransform(layer.crs(), crs, context).transformBoundingBox(layer.extent())
        except QgsCsException:
            return box
        if not covered.intersects(box):
            raise InputError(f"the extent does not overlap layer {layer.name()!r}; draw the rectangle over it")
    return box


def _check_size(layer: QgsRasterLayer, box: QgsRectangle, gsd: float, width: int, height: int, max_pixels: int) -> None:
    count = width * height
    if count > max_pixels:
        better = fitting_gsd(box.width(), box.height(), gsd, max_pixels)
        raise InputError(
            f"extent {box.width() / 1000:.3g} x {box.height() / 1000:.3g} km at {gsd:g} m is {width:,} x {height:,} = "
            f"{count / 1e6:,.0f} Mpx, above the extraction limit of {max_pixels / 1e6:,.0f} Mpx; "
            f"choose a GSD of {better:g} m or more, or a smaller extent"
        )
    if min(width, height) < MIN_SIDE_PX:
        raise InputError(
            f"the extent is only {width} x {height} px at {gsd:g} m; draw a larger rectangle or choose a finer GSD"
        )
    if _is_osm_tiles(layer) and count / (256 * 256) > OSM_MAX_TILES:
        raise InputError(
            f"about {count / 65536:,.0f} tiles from openstreetmap.org: its tile usage policy forbids bulk "
            f"downloads (at most {OSM_MAX_TILES} tiles); choose a coarser GSD or a smaller extent"
        )


def plan_extraction(
    layer: QgsRasterLayer,
    extent: QgsRectangle,
    extent_crs: QgsCoordinateReferenceSystem,
    gsd_m: float,
    max_pixels: int = DEFAULT_MAX_PIXELS,
    target_crs: QgsCoordinateReferenceSystem | None = None,
    *,
    project_crs: QgsCoordinateReferenceSystem | None = None,
) -> ExtractPlan:
    """The output grid for rendering ``layer`` over ``extent`` (in ``extent_crs``, e.g. the
    canvas CRS) at ``gsd_m`` ground metres per pixel.

    ``target_crs`` forces the output CRS (it must be projected, in metres); otherwise
    :func:`choose_crs` picks it (``project_crs`` defaults to the current project's). Raises
    InputError, one line, for an invalid layer, a GSD that is not a positive number, an empty
    extent or one that misses a file layer, an image under 16 px a side, and an image above
    ``max_pixels`` (saying its size, the limit and the GSD that would fit).
    """
    gsd = _check_request(layer, extent, extent_crs, gsd_m, max_pixels)
    crs = _target_crs(layer, extent, extent_crs, target_crs, project_crs)
    box = _extent_in(layer, extent, extent_crs, crs)
    x0, x1, width = _snap(box.xMinimum(), box.xMaximum(), gsd)
    y0, y1, height = _snap(box.yMinimum(), box.yMaximum(), gsd)
    _check_size(layer, box, gsd, width, height, max_pixels)
    return ExtractPlan(crs=crs, extent=QgsRectangle(x0, y0, x1, y1), gsd_m=gsd, width=width, height=height)
