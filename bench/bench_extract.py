"""Benchmark: imagery extraction (overseec_qgis.extract) from an XYZ basemap, a VRT and a GeoTIFF.

The bundled sample scene (resources/sample/sample.tif, UTM 33N, 0.5 m) is tiled into a mosaic of
``--size`` pixels a side and served three ways: cut into ``file://`` XYZ tiles at one zoom (EPSG:3857, as a
tile server would serve it), as a VRT over it, and as the GeoTIFF itself. Each source is
extracted over the scene at ``--gsd`` metres into UTM 33N (QGIS renders tile by tile; the
GeoTIFF gets a mask and overviews) and the wall time, output megapixels and Mpx/s are printed.
Tile cutting is not timed.

    QT_QPA_PLATFORM=offscreen .venv/bin/python bench/bench_extract.py              # 4096 px scene
    QT_QPA_PLATFORM=offscreen .venv/bin/python bench/bench_extract.py --size 2048  # quick check
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))


def make_scene(path: Path, size: int) -> Path:
    """The bundled sample scene repeated into a ``size`` x ``size`` RGB GeoTIFF at its origin."""
    import numpy as np
    from osgeo import gdal

    sample = gdal.Open(str(REPO / "resources" / "sample" / "sample.tif"))
    rgb = sample.ReadAsArray()  # (3, 1024, 1024)
    reps = -(-size // rgb.shape[1])
    mosaic = np.tile(rgb, (1, reps, reps))[:, :size, :size]
    ds = gdal.GetDriverByName("GTiff").Create(
        str(path), size, size, 3, gdal.GDT_Byte, ["TILED=YES", "COMPRESS=DEFLATE", "PHOTOMETRIC=RGB"]
    )
    ds.SetGeoTransform(sample.GetGeoTransform())
    ds.SetProjection(sample.GetProjection())
    ds.WriteArray(mosaic)
    ds = None
    return path


def main() -> None:
    """Extract the same scene from an XYZ tile source, a VRT and a GeoTIFF in QGIS and print the
    seconds and Mpx/s of each."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=4096, help="scene side in pixels (0.5 m each)")
    ap.add_argument("--gsd", type=float, default=0.5, help="output ground resolution in metres")
    ap.add_argument("--zoom", type=int, default=19, help="XYZ zoom level the tiles are cut at")
    ap.add_argument("--tile", type=int, default=1024, help="render tile size (pixels)")
    args = ap.parse_args()

    from osgeo import gdal
    from qgis.core import QgsApplication, QgsCoordinateReferenceSystem, QgsRasterLayer

    app = QgsApplication([], True)
    app.initQgis()

    from overseec_qgis.extract import extract_layer
    from overseec_qgis.extract_plan import plan_extraction
    from tests.qgis.xyz_source import write_xyz_from_raster

    utm = QgsCoordinateReferenceSystem("EPSG:32633")
    web = QgsCoordinateReferenceSystem("EPSG:3857")
    with tempfile.TemporaryDirectory(prefix="overseec-bench-extract-") as tmp:
        folder = Path(tmp)
        image = make_scene(folder / "scene.tif", args.size)
        t0 = time.perf_counter()
        uri, count = write_xyz_from_raster(image, folder / "tiles", range(args.zoom, args.zoom + 1))
        gdal.BuildVRT(str(folder / "scene.vrt"), [str(image)]).FlushCache()
        print(
            f"scene {args.size} x {args.size} px at 0.5 m; {count} XYZ tiles at z={args.zoom} "
            f"(cut in {time.perf_counter() - t0:.1f} s, not timed below)"
        )
        sources = (
            ("xyz file://", QgsRasterLayer(uri, "xyz", "wms")),
            ("vrt", QgsRasterLayer(str(folder / "scene.vrt"), "vrt")),
            ("geotiff", QgsRasterLayer(str(image), "tif")),
        )
        extent = sources[2][1].extent()
        print(f"{'source':<12} {'output':>13} {'Mpx':>7} {'seconds':>8} {'Mpx/s':>7}")
        for name, layer in sources:
            assert layer.isValid(), name
            plan = plan_extraction(layer, extent, utm, args.gsd, project_crs=web)
            t = time.perf_counter()
            extract_layer(layer, plan, folder / f"out_{name.split()[0]}.tif", tile_px=args.tile)
            dt = time.perf_counter() - t
            print(
                f"{name:<12} {plan.width:>6}x{plan.height:<6} {plan.megapixels():>7.1f} {dt:>8.2f} "
                f"{plan.megapixels() / dt:>7.1f}"
            )
        del sources, layer  # close the files before the folder goes
    app.exitQgis()


if __name__ == "__main__":
    main()
