"""Offline XYZ tile sources for the extraction tests, the screenshot and bench/bench_extract.py.

QGIS's ``wms`` provider reads ``type=xyz&url=file:///.../{z}/{x}/{y}.png`` like any tile server,
so these folders stand in for a basemap without a network:

* :class:`XyzSource`: a 4 x 4 block of zoom-18 tiles near Innsbruck, each tile's area one palette
  colour, drawn at zooms 16-18 (so whichever zoom QGIS picks, the colour at a place is known);
* :func:`write_xyz_from_raster`: the tiles of any georeferenced raster (e.g. the sample scene)
  at chosen zooms, warped by GDAL into Web Mercator (RGBA PNGs; tiles it does not touch are
  not written).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from osgeo import gdal, osr
from qgis.core import QgsRasterLayer, QgsRectangle

R = 20037508.342789244  # half the Web Mercator world width
LON, LAT = 11.40, 47.26  # Innsbruck: UTM zone 32N
#: 16 colours, pairwise far apart (each channel step is 70)
PALETTE = np.array([(30 + 70 * (i % 4), 30 + 70 * (i // 4), 200 - 40 * (i % 3)) for i in range(16)], np.uint8)


def xyz_uri(folder: Path, zmin: int, zmax: int) -> str:
    """The QGIS data source of a file:// XYZ tile folder."""
    return f"type=xyz&url=file://{Path(folder).as_posix()}/{{z}}/{{x}}/{{y}}.png&zmin={zmin}&zmax={zmax}"


def tile_index(lon: float, lat: float, z: int) -> tuple[int, int]:
    n = 2**z
    lat_r = math.radians(lat)
    x = int((lon + 180.0) / 360.0 * n)
    y = int((1.0 - math.asinh(math.tan(lat_r)) / math.pi) / 2.0 * n)
    return x, y


def tile_bounds(x: int, y: int, z: int) -> QgsRectangle:
    """A tile's extent in EPSG:3857."""
    size = 2 * R / 2**z
    return QgsRectangle(-R + x * size, R - (y + 1) * size, -R + (x + 1) * size, R - y * size)


def write_png(path: Path, rgb: np.ndarray) -> None:
    """An RGB or RGBA (h, w, bands) uint8 array as a PNG."""
    path.parent.mkdir(parents=True, exist_ok=True)
    mem = gdal.GetDriverByName("MEM").Create("", rgb.shape[1], rgb.shape[0], rgb.shape[2], gdal.GDT_Byte)
    for b in range(rgb.shape[2]):
        mem.GetRasterBand(b + 1).WriteArray(rgb[:, :, b])
    assert gdal.GetDriverByName("PNG").CreateCopy(str(path), mem) is not None


class XyzSource:
    """A 4 x 4 block of zoom-18 tiles (x0..x0+3, y0..y0+3), drawn at zooms 16, 17 and 18."""

    def __init__(self, folder: Path, z: int = 18, block: int = 4) -> None:
        x, y = tile_index(LON, LAT, z)
        self.folder, self.z, self.block = folder, z, block
        self.x0, self.y0 = x - x % block, y - y % block
        world = np.zeros((256 * block, 256 * block, 3), np.uint8)
        for j in range(block):
            for i in range(block):
                world[j * 256 : (j + 1) * 256, i * 256 : (i + 1) * 256] = self.colour(i, j)
        for level in range(int(math.log2(block)) + 1):  # zoom z - level: 2**level coarser
            f, n = 2**level, block // 2**level
            for j in range(n):
                for i in range(n):
                    part = world[j * 256 * f : (j + 1) * 256 * f : f, i * 256 * f : (i + 1) * 256 * f : f]
                    write_png(
                        folder / str(z - level) / str((self.x0 >> level) + i) / f"{(self.y0 >> level) + j}.png", part
                    )
        self.zmin = z - int(math.log2(block))

    @staticmethod
    def colour(i: int, j: int) -> np.ndarray:
        return PALETTE[j * 4 + i]

    def uri(self) -> str:
        return xyz_uri(self.folder, self.zmin, self.z)

    def layer(self) -> QgsRasterLayer:
        layer = QgsRasterLayer(self.uri(), "xyz", "wms")
        assert layer.isValid()
        return layer

    def tile(self, i: int, j: int) -> QgsRectangle:
        return tile_bounds(self.x0 + i, self.y0 + j, self.z)

    def area(self, margin_tiles: float = 0.0) -> QgsRectangle:
        """The covered area in EPSG:3857, shrunk by ``margin_tiles`` tiles each side."""
        a, b = self.tile(0, 0), self.tile(self.block - 1, self.block - 1)
        m = margin_tiles * a.width()
        return QgsRectangle(a.xMinimum() + m, b.yMinimum() + m, b.xMaximum() - m, a.yMaximum() - m)


def write_xyz_from_raster(src: Path, folder: Path, zooms: range) -> tuple[str, int]:
    """Cut ``src`` into XYZ tiles (RGBA PNG) at ``zooms`` under ``folder``; returns (the QGIS
    source of the tile folder, the number of tiles written)."""
    ds = gdal.Open(str(src))
    x0, dx, _, y0, _, dy = ds.GetGeoTransform()
    corners = [(x0 + i * ds.RasterXSize * dx, y0 + j * ds.RasterYSize * dy) for i in (0, 1) for j in (0, 1)]
    src_srs = osr.SpatialReference(wkt=ds.GetProjection())
    web = osr.SpatialReference()
    web.ImportFromEPSG(3857)
    for s in (src_srs, web):
        s.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
    ct = osr.CoordinateTransformation(src_srs, web)
    xs, ys = zip(*[ct.TransformPoint(x, y)[:2] for x, y in corners])
    written = 0
    for z in zooms:  # one warp per zoom onto the tile grid, then sliced into tiles
        size = 2 * R / 2**z
        tx0, tx1 = int((min(xs) + R) // size), int((max(xs) + R) // size)
        ty0, ty1 = int((R - max(ys)) // size), int((R - min(ys)) // size)
        a, b = tile_bounds(tx0, ty0, z), tile_bounds(tx1, ty1, z)
        nx, ny = tx1 - tx0 + 1, ty1 - ty0 + 1
        mosaic = gdal.Warp(
            "",
            ds,
            format="MEM",
            outputBounds=(a.xMinimum(), b.yMinimum(), b.xMaximum(), a.yMaximum()),
            width=256 * nx,
            height=256 * ny,
            dstSRS="EPSG:3857",
            resampleAlg="bilinear",
            dstAlpha=True,
        )
        rgba = np.stack([mosaic.GetRasterBand(k + 1).ReadAsArray() for k in range(4)], axis=-1)
        for j in range(ny):
            for i in range(nx):
                tile = rgba[j * 256 : (j + 1) * 256, i * 256 : (i + 1) * 256]
                if tile[:, :, 3].any():
                    write_png(folder / str(z) / str(tx0 + i) / f"{ty0 + j}.png", tile)
                    written += 1
    return xyz_uri(folder, zooms.start, zooms.stop - 1), written
