"""Imagery from any raster layer: render it to a georeferenced GeoTIFF at a chosen ground resolution.

Analysts mostly have basemaps (XYZ tiles, WMS/WMTS, VRT mosaics), not a GeoTIFF of the area. This
module turns whatever QGIS can draw into the image overseec runs on:

1. :func:`plan_extraction` fixes the output grid: a projected CRS in metres (the layer's, else
   the project's, when it is true to scale there, else the WGS 84 / UTM zone of the extent's
   centre), the extent transformed into it and snapped outwards to the GSD grid, and the size in
   pixels -- refused in one line, before anything is fetched, when it is above the pixel limit
   (with the GSD that would fit).
2. :func:`extract_layer` renders the layer tile by tile (1024 px, aligned to the GeoTIFF's 512 px
   blocks) with QGIS's own map renderer, so every provider QGIS draws works alike (``wms`` for
   XYZ/WMS/WMTS, ``gdal`` for files and VRTs) and the image looks as the layer looks on the
   canvas. Tiles go into a tiled, compressed RGB GeoTIFF with an internal mask (transparent, i.e.
   uncovered, pixels are masked) and internal overviews, written with osgeo.gdal (rasterio is not
   part of QGIS everywhere) into a hidden temporary file beside the target, checked, and renamed
   only when whole (``overseec_core.io.atomic``). Progress goes to ``feedback.setProgress``; a
   cancel raises :class:`~overseec_core.errors.Cancelled` and leaves nothing behind.
3. :class:`ExtractTask` runs that on QGIS's task manager, on a clone of the layer made on the
   main thread (QGIS's own "Convert map to raster" does the same).

Why "true to scale": overseec measures ground metres (DESIGN.md, "Georeferencing is never
lost"); a Web Mercator metre is 0.68 ground metres at 47 deg N, so an XYZ layer's own CRS would
silently give the wrong GSD. A CRS is used as it is only when a step at the extent's centre
measures within 0.1 % of its nominal length on the ellipsoid -- the core's rule for stating a
projected raster's pixel size.
"""

from __future__ import annotations

import math
import os
import traceback
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from urllib.parse import urlparse

import numpy as np
from qgis.core import (
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsCoordinateTransformContext,
    QgsCsException,
    QgsDistanceArea,
    QgsFeedback,
    QgsMapRendererCustomPainterJob,
    QgsMapSettings,
    QgsPointXY,
    QgsProject,
    QgsProviderRegistry,
    QgsRasterLayer,
    QgsRectangle,
    QgsUnitTypes,
)
from qgis.PyQt.QtCore import QSize
from qgis.PyQt.QtGui import QColor, QImage, QPainter

from overseec_core.errors import Cancelled, InputError, OutputError, OverseecError
from overseec_core.io.atomic import atomic_path, output_error

from .task import _BaseTask

#: Default pixel limit of one extraction: 400 Mpx is a 20,000 x 20,000 image, 8 x 8 km at 0.4 m --
#: already hours of segmentation on a CPU, and a heavy download from a tile server.
DEFAULT_MAX_PIXELS = 400_000_000
#: Tiles rendered per map-renderer call (a multiple of the GeoTIFF block size).
TILE_PX = 1024
#: GeoTIFF block size (the core's RasterWriter uses the same).
BLOCK_PX = 512
#: Smallest useful image side; below it the extent is almost certainly a mis-click.
MIN_SIDE_PX = 16
#: A CRS is "true to scale" when a step at the extent's centre measures within this fraction of
#: its nominal length on the ellipsoid (the core's rule for a projected raster's pixel size).
TRUE_SCALE_TOLERANCE = 1e-3
#: Fixed rendering DPI: symbology in points/mm stays the same whatever the machine's screen.
RENDER_DPI = 96.0
#: openstreetmap.org's tile usage policy forbids bulk downloading; QGIS's "Convert map to raster"
#: stops at 5000 tiles, so does this.
OSM_MAX_TILES = 5000
OSM_TILE_HOSTS = ("tile.openstreetmap.org",)
#: Share of the progress bar the tiles take (overviews and the check take the rest).
TILES_SHARE = 95.0


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


# --------------------------------------------------------------------------------------------
# Rendering and writing
# --------------------------------------------------------------------------------------------


def tiles(plan: ExtractPlan, tile_px: int = TILE_PX) -> Iterator[tuple[int, int, int, int]]:
    """(col, row, width, height) of each render tile, row by row (the GeoTIFF's write order)."""
    for row in range(0, plan.height, tile_px):
        for col in range(0, plan.width, tile_px):
            yield col, row, min(tile_px, plan.width - col), min(tile_px, plan.height - row)


def opaque_copy(layer: QgsRasterLayer) -> QgsRasterLayer:
    """A clone of ``layer`` drawn fully opaque and in normal blending.

    A basemap is often dimmed on the canvas (opacity 50 %) under other layers; drawn that way the
    image would be half transparent and masked as "no data". Everything else of the style
    (bands, stretch, colour adjustments, resampling) is kept.
    """
    copy = layer.clone()
    if copy.renderer() is not None:
        copy.renderer().setOpacity(1.0)
    copy.setBlendMode(QPainter.CompositionMode_SourceOver)
    return copy


def map_settings(layer: QgsRasterLayer, plan: ExtractPlan) -> QgsMapSettings:
    """Map settings shared by every tile: the layer alone, the plan's CRS, transparent background."""
    ms = QgsMapSettings()
    ms.setLayers([layer])
    ms.setDestinationCrs(plan.crs)
    ms.setBackgroundColor(QColor(0, 0, 0, 0))
    ms.setOutputDpi(RENDER_DPI)
    ms.setTransformContext(QgsProject.instance().transformContext())
    for name in ("RenderMapTile", "Antialiasing", "HighQualityImageTransforms"):  # the last from QGIS 3.24
        flag = getattr(QgsMapSettings, name, None)
        if flag is not None:
            ms.setFlag(flag, True)
    return ms


def render_tile(
    settings: QgsMapSettings, plan: ExtractPlan, col: int, row: int, w: int, h: int
) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Render the ``w`` x ``h`` pixels at (col, row) of the plan's grid.

    Returns (rgb (h, w, 3) uint8, valid (h, w) bool: alpha >= 128, renderer error messages).
    """
    g = plan.gsd_m
    x0 = plan.extent.xMinimum() + col * g
    y1 = plan.extent.yMaximum() - row * g
    settings.setExtent(QgsRectangle(x0, y1 - h * g, x0 + w * g, y1))
    settings.setOutputSize(QSize(w, h))
    image = QImage(w, h, QImage.Format_ARGB32_Premultiplied)
    image.fill(0)
    painter = QPainter(image)
    try:
        job = QgsMapRendererCustomPainterJob(settings, painter)
        job.renderSynchronously()
    finally:
        painter.end()
    errors = [f"{e.layerID}: {e.message}" for e in job.errors()]
    image = image.convertToFormat(QImage.Format_ARGB32)  # un-premultiplied colours
    ptr = image.constBits()
    ptr.setsize(image.sizeInBytes())
    bgra = np.frombuffer(ptr, np.uint8).reshape(h, image.bytesPerLine())[:, : w * 4].reshape(h, w, 4)
    rgb = np.ascontiguousarray(bgra[:, :, 2::-1])  # memory order B, G, R, A (little-endian ARGB32)
    return rgb, bgra[:, :, 3] >= 128, errors


def _gdal():
    from osgeo import gdal

    return gdal


class GdalMessages:
    """Collects GDAL's failure messages (not printed) while entered, on this thread.

    Entered only around the calls on the output file, so that errors the renderer's own GDAL
    reads report (a damaged source file) are not taken for a failed write.
    """

    def __init__(self) -> None:
        self.messages: list[str] = []

    def _collect(self, cls: int, _no: int, msg: str) -> None:
        if cls >= _gdal().CE_Failure and len(self.messages) < 20:
            self.messages.append(" ".join(str(msg).split()))

    def __enter__(self) -> list[str]:
        _gdal().PushErrorHandler(self._collect)
        return self.messages

    def __exit__(self, *exc: object) -> None:
        _gdal().PopErrorHandler()


def creation_options() -> list[str]:
    """Tiled, pixel-interleaved RGB; ZSTD (as the core writes) where this GDAL has it, else DEFLATE;
    ``OVERSEEC_COMPRESS=deflate`` for older readers."""
    gdal = _gdal()
    wanted = os.environ.get("OVERSEEC_COMPRESS", "zstd").strip().lower() or "zstd"
    available = gdal.GetDriverByName("GTiff").GetMetadataItem("DMD_CREATIONOPTIONLIST") or ""
    if wanted == "zstd" and "ZSTD" not in available:
        wanted = "deflate"
    opts = [
        "TILED=YES",
        f"BLOCKXSIZE={BLOCK_PX}",
        f"BLOCKYSIZE={BLOCK_PX}",
        "INTERLEAVE=PIXEL",
        "PHOTOMETRIC=RGB",
        "BIGTIFF=IF_SAFER",
        f"COMPRESS={wanted.upper()}",
        "NUM_THREADS=ALL_CPUS",
    ]
    if wanted in ("zstd", "deflate", "lzw"):
        opts.append("PREDICTOR=2")
    if wanted == "zstd":
        opts.append("ZSTD_LEVEL=1")
    return opts


def overview_factors(width: int, height: int, block: int = BLOCK_PX) -> list[int]:
    """2, 4, 8 ... until the smallest overview fits in one block (as the core's writer)."""
    factors, f = [], 2
    while max(width, height) > block and max(width, height) / f >= block / 2:
        factors.append(f)
        f *= 2
    return factors


def layer_file(layer: QgsRasterLayer) -> Path | None:
    """The file behind a GDAL layer (None for services)."""
    if layer.providerType() != "gdal":
        return None
    path = QgsProviderRegistry.instance().decodeUri("gdal", layer.source()).get("path") or ""
    return Path(path) if path and os.path.exists(path) else None


def _check_output(out: Path, layer: QgsRasterLayer) -> None:
    src = layer_file(layer)
    if src is not None and (out.resolve() == src.resolve() or (out.exists() and os.path.samefile(out, src))):
        raise OutputError(f"output {out} is the layer's own file; choose another output path")
    if out.is_dir():
        raise OutputError(f"cannot write {out}: it is a directory")
    parent = out.parent if str(out.parent) else Path(".")
    if not parent.is_dir():
        raise OutputError(f"cannot write {out}: folder {parent} does not exist")


def _describe_dataset(ds: Any, layer: QgsRasterLayer, plan: ExtractPlan) -> None:
    """Georeferencing, RGB colour interpretation, provenance tags and an internal mask band."""
    gdal = _gdal()
    ds.SetGeoTransform(plan.geotransform())
    ds.SetProjection(plan.crs.toWkt(QgsCoordinateReferenceSystem.WKT_PREFERRED_GDAL))
    ds.SetMetadata(
        {
            "OVERSEEC_EXTRACTED_FROM": layer.name(),
            "OVERSEEC_PROVIDER": layer.providerType(),
            "OVERSEEC_GSD_M": f"{plan.gsd_m:g}",
        }
    )
    for i, interp in enumerate((gdal.GCI_RedBand, gdal.GCI_GreenBand, gdal.GCI_BlueBand), start=1):
        ds.GetRasterBand(i).SetColorInterpretation(interp)
    gdal.SetThreadLocalConfigOption("GDAL_TIFF_INTERNAL_MASK", "YES")  # not a .msk sidecar
    try:
        ds.CreateMaskBand(gdal.GMF_PER_DATASET)
    finally:
        gdal.SetThreadLocalConfigOption("GDAL_TIFF_INTERNAL_MASK", None)


def _write_tiles(
    ds: Any,
    layer: QgsRasterLayer,
    plan: ExtractPlan,
    tile_px: int,
    feedback: QgsFeedback | None,
    report: Callable[[str], None] | None,
    gdal_log: GdalMessages,
) -> bool:
    """Render and write every tile; True when any pixel was drawn. Raises Cancelled, or OSError
    when GDAL refuses a write."""
    gdal = _gdal()
    drawn = opaque_copy(layer)  # kept referenced: map settings hold layers weakly
    settings = map_settings(drawn, plan)
    mask = ds.GetRasterBand(1).GetMaskBand()
    todo = list(tiles(plan, tile_px))
    any_valid = False
    for k, (col, row, w, h) in enumerate(todo):
        if _cancelled(feedback):
            raise Cancelled("extraction cancelled by the user; nothing was written")
        rgb, valid, errors = render_tile(settings, plan, col, row, w, h)
        if errors and report is not None:
            report(f"tile {k + 1}/{len(todo)}: " + "; ".join(errors)[:500])
        any_valid = any_valid or bool(valid.any())
        rgb[~valid] = 0
        with gdal_log:
            rc = ds.WriteRaster(col, row, w, h, rgb.tobytes(), w, h, gdal.GDT_Byte, [1, 2, 3], 3, 3 * w, 1)
            rc_mask = mask.WriteArray(valid.astype(np.uint8) * 255, col, row)
        if rc != gdal.CE_None or rc_mask != gdal.CE_None:
            raise OSError(f"GDAL could not write tile {k + 1} of {len(todo)}")
        _progress(feedback, TILES_SHARE * (k + 1) / len(todo))
    return any_valid


def _verify(path: Path, plan: ExtractPlan) -> str | None:
    """None when the written file reads back with the plan's grid and every block present."""
    gdal = _gdal()
    ds = gdal.Open(str(path))
    if ds is None:
        return "it does not read back"
    try:
        if (ds.RasterXSize, ds.RasterYSize, ds.RasterCount) != (plan.width, plan.height, 3):
            return f"it reads back as {ds.RasterCount} x {ds.RasterYSize} x {ds.RasterXSize}"
        if any(abs(a - b) > 1e-9 * max(1.0, abs(b)) for a, b in zip(ds.GetGeoTransform(), plan.geotransform())):
            return "its georeferencing did not survive"
        band = ds.GetRasterBand(1)
        size = path.stat().st_size
        for by in range(-(-plan.height // BLOCK_PX)):
            for bx in range(-(-plan.width // BLOCK_PX)):
                off = band.GetMetadataItem(f"BLOCK_OFFSET_{bx}_{by}", "TIFF")
                n = band.GetMetadataItem(f"BLOCK_SIZE_{bx}_{by}", "TIFF")
                if not off or not n or int(off) <= 0 or int(n) <= 0 or int(off) + int(n) > size:
                    return f"block {bx},{by} was not written"
        last = ((plan.height - 1) // BLOCK_PX) * BLOCK_PX
        if ds.ReadRaster(0, last, plan.width, plan.height - last) is None:
            return "its last block row does not decode"
    finally:
        ds = None
    return None


def _progress(feedback: QgsFeedback | None, value: float) -> None:
    if feedback is not None:
        feedback.setProgress(value)


def _cancelled(feedback: QgsFeedback | None) -> bool:
    return feedback is not None and feedback.isCanceled()


def extract_layer(
    layer: QgsRasterLayer,
    plan: ExtractPlan,
    out_path: str | os.PathLike,
    feedback: QgsFeedback | None = None,
    *,
    tile_px: int = TILE_PX,
    log: Callable[[str], None] | None = None,
) -> Path:
    """Render ``layer`` on ``plan``'s grid into the RGB GeoTIFF ``out_path``; returns its path.

    Tile by tile (``tile_px``, a multiple of 512); progress through ``feedback.setProgress``
    (0-100); ``feedback.isCanceled()`` is checked before every tile and during the overviews and
    raises Cancelled. The file appears under ``out_path`` only when complete and checked; on a
    cancel or any failure it does not, and an earlier file there is untouched. Renderer errors
    (a tile server that failed) go to ``log`` (or ``feedback.pushInfo``); a layer that rendered
    nothing at all is an OutputError rather than an empty image.
    """
    if tile_px <= 0 or tile_px % BLOCK_PX:
        raise InputError(f"tile size must be a positive multiple of {BLOCK_PX}, not {tile_px}")
    out = Path(out_path)
    _check_output(out, layer)
    report = log or (feedback.pushInfo if feedback is not None and hasattr(feedback, "pushInfo") else None)
    gdal = _gdal()
    _progress(feedback, 0.0)
    gdal_log = GdalMessages()
    messages = gdal_log.messages
    with atomic_path(out, suffix=".partial.tif", sidecars=(".aux.xml", ".msk")) as tmp:
        with gdal_log:
            ds = gdal.GetDriverByName("GTiff").Create(
                str(tmp), plan.width, plan.height, 3, gdal.GDT_Byte, creation_options()
            )
            if ds is None:
                raise output_error(out, messages=messages, tmp=tmp)
            _describe_dataset(ds, layer, plan)
        try:
            any_valid = _write_tiles(ds, layer, plan, tile_px, feedback, report, gdal_log)
            with gdal_log:
                ds.FlushCache()
        except OSError as exc:  # a failed GDAL write (see _write_tiles), with GDAL's own messages
            raise output_error(out, exc, messages=messages, tmp=tmp) from None
        finally:
            with gdal_log:
                ds = None  # close (flush) before anything else touches the file
        if messages:
            raise output_error(out, messages=messages, tmp=tmp)
        if not any_valid:
            raise OutputError(
                f"layer {layer.name()!r} drew nothing over this extent (no tiles there, the server did "
                "not answer, or the layer is hidden at this scale); check the layer on the canvas"
            )
        with gdal_log:
            _build_overviews(tmp, plan, feedback, messages, out)
            problem = _verify(tmp, plan)
        if problem or messages:
            raise output_error(out, messages=[*messages, f"the written file failed its check: {problem}"], tmp=tmp)
    _progress(feedback, 100.0)
    return out


def _build_overviews(
    tmp: Path, plan: ExtractPlan, feedback: QgsFeedback | None, messages: list[str], out: Path
) -> None:
    """Internal average overviews (QGIS draws large extracts fast), cancellable."""
    factors = overview_factors(plan.width, plan.height)
    if not factors:
        return
    gdal = _gdal()
    ds = gdal.Open(str(tmp), gdal.GA_Update)
    if ds is None:
        raise output_error(out, messages=messages, tmp=tmp)

    def step(done: float, _msg: Any, _data: Any) -> int:
        _progress(feedback, TILES_SHARE + (100.0 - TILES_SHARE) * 0.9 * done)
        return 0 if _cancelled(feedback) else 1

    try:
        rc = ds.BuildOverviews("AVERAGE", factors, callback=step)
    finally:
        ds = None
    if _cancelled(feedback):
        raise Cancelled("extraction cancelled by the user; nothing was written")
    if rc != gdal.CE_None:
        raise output_error(out, messages=messages, tmp=tmp)


# --------------------------------------------------------------------------------------------
# Background task
# --------------------------------------------------------------------------------------------


class ExtractTask(_BaseTask):
    """Runs :func:`extract_layer` on QGIS's task manager.

    The layer is cloned here, on the main thread, and the clone rendered on the task thread (the
    project's layer stays the GUI's). Reports like the dock's other tasks: ``succeeded(Path)``
    with ``result`` the written path, or ``failed(message, details)`` with ``error`` one line
    (``details`` holds a traceback only for a bug). Cancelling the task stops at the next tile.
    """

    def __init__(
        self, layer: QgsRasterLayer, plan: ExtractPlan, out_path: str | os.PathLike, description: str = ""
    ) -> None:
        super().__init__(description or f"overseec: extract imagery from {layer.name()}")
        self.plan = plan
        self.out_path = Path(out_path)
        self.result_path: Path | None = None
        self._layer = layer.clone()
        self._feedback = QgsFeedback()
        self._feedback.progressChanged.connect(self.setProgress)

    def cancel(self) -> None:
        self._feedback.cancel()
        super().cancel()

    def run(self) -> bool:  # task thread
        try:
            self.result = self.result_path = extract_layer(self._layer, self.plan, self.out_path, self._feedback)
            return True
        except OverseecError as exc:
            self.error = str(exc)
        except Exception as exc:  # a bug: keep the traceback for the log panel
            self.error = f"unexpected failure: {type(exc).__name__}: {exc}"
            self.details = traceback.format_exc()
        return False
