"""Imagery from any raster layer: render it to a georeferenced GeoTIFF at a chosen ground resolution.

Analysts mostly have basemaps (XYZ tiles, WMS/WMTS, VRT mosaics), not a GeoTIFF of the area. This
module turns whatever QGIS can draw into the image overseec runs on:

1. :func:`overseec_qgis.extract_plan.plan_extraction` fixes the output grid (CRS, extent, size),
   refusing it in one line before anything is fetched.
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
"""

from __future__ import annotations

import os
import traceback
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
from qgis.core import (
    QgsCoordinateReferenceSystem,
    QgsFeedback,
    QgsMapRendererCustomPainterJob,
    QgsMapSettings,
    QgsProject,
    QgsProviderRegistry,
    QgsRasterLayer,
    QgsRectangle,
)
from qgis.PyQt.QtCore import QSize
from qgis.PyQt.QtGui import QColor, QImage, QPainter

from overseec_core.errors import Cancelled, InputError, OutputError, OverseecError
from overseec_core.io.atomic import atomic_path, output_error

from .extract_plan import ExtractPlan
from .task import _BaseTask

#: Tiles rendered per map-renderer call (a multiple of the GeoTIFF block size).
TILE_PX = 1024
#: GeoTIFF block size (the core's RasterWriter uses the same).
BLOCK_PX = 512
#: Fixed rendering DPI: symbology in points/mm stays the same whatever the machine's screen.
RENDER_DPI = 96.0
#: Share of the progress bar the tiles take (overviews and the check take the rest).
TILES_SHARE = 95.0


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
