"""Imagery from any raster layer (overseec_qgis.extract, the extent tool, overseec:extractimagery).

Every source is real and offline, written by the test with seeded content:

* an XYZ tile tree under ``file://.../{z}/{x}/{y}.png`` (QGIS's ``wms`` provider) at zooms 16-18
  near Innsbruck: one world picture of 4 x 4 zoom-18 tiles, each tile's area one palette colour,
  drawn at every zoom, so whichever zoom QGIS picks, the colour at a place is known;
* a VRT mosaic of two GeoTIFFs in UTM 33N, and GeoTIFFs in UTM 33N and in EPSG:4326.

Georeferencing is checked where a coloured area lands in the output (its centroid within one GSD
of where the source puts it, transformed by QGIS) and the output's pixel size and CRS.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from osgeo import gdal, osr
from qgis.core import (
    QgsApplication,
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsCoordinateTransformContext,
    QgsFeedback,
    QgsPointXY,
    QgsProcessingException,
    QgsProcessingFeedback,
    QgsProject,
    QgsRasterLayer,
    QgsRectangle,
)

from overseec_core.errors import Cancelled, InputError, OutputError
from overseec_qgis import extract, extract_plan
from overseec_qgis.extract import ExtractTask, extract_layer
from overseec_qgis.extract_plan import ExtractPlan, plan_extraction

from .conftest import REPO, wait_until
from .xyz_source import LAT, LON, XyzSource

pytestmark = pytest.mark.qgis

WEB = QgsCoordinateReferenceSystem("EPSG:3857")
WGS84 = QgsCoordinateReferenceSystem("EPSG:4326")
UTM32 = QgsCoordinateReferenceSystem("EPSG:32632")
UTM33 = QgsCoordinateReferenceSystem("EPSG:32633")


# --------------------------------------------------------------------------------------------
# Sources
# --------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def xyz(tmp_path_factory) -> XyzSource:
    return XyzSource(tmp_path_factory.mktemp("xyz"))


def write_tif(path: Path, rgb: np.ndarray, epsg: int, origin: tuple[float, float], pixel: float) -> Path:
    """A north-up RGB GeoTIFF written with osgeo.gdal."""
    h, w, _ = rgb.shape
    ds = gdal.GetDriverByName("GTiff").Create(str(path), w, h, 3, gdal.GDT_Byte, ["PHOTOMETRIC=RGB"])
    ds.SetGeoTransform((origin[0], pixel, 0, origin[1], 0, -pixel))
    srs = osr.SpatialReference()
    srs.ImportFromEPSG(epsg)
    ds.SetProjection(srs.ExportToWkt())
    for b in range(3):
        ds.GetRasterBand(b + 1).WriteArray(rgb[:, :, b])
    ds = None
    return path


def seeded_rgb(h: int, w: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.integers(0, 256, (h, w, 3), dtype=np.uint8)


def read(path: Path) -> tuple[np.ndarray, np.ndarray, tuple, str]:
    """(rgb (h, w, 3), mask (h, w) bool, geotransform, WKT) of a written output."""
    ds = gdal.Open(str(path))
    rgb = np.stack([ds.GetRasterBand(b + 1).ReadAsArray() for b in range(3)], axis=-1)
    mask = ds.GetRasterBand(1).GetMaskBand().ReadAsArray() > 0
    return rgb, mask, ds.GetGeoTransform(), ds.GetProjection()


def where_is(rgb: np.ndarray, colour: np.ndarray, tol: int = 3) -> np.ndarray:
    return np.all(np.abs(rgb.astype(int) - colour.astype(int)) <= tol, axis=-1)


def centroid_world(hits: np.ndarray, plan: ExtractPlan) -> tuple[float, float]:
    rows, cols = np.nonzero(hits)
    return (
        plan.extent.xMinimum() + (cols.mean() + 0.5) * plan.gsd_m,
        plan.extent.yMaximum() - (rows.mean() + 0.5) * plan.gsd_m,
    )


def to(crs_from, crs_to, x: float, y: float) -> QgsPointXY:
    return QgsCoordinateTransform(crs_from, crs_to, QgsCoordinateTransformContext()).transform(QgsPointXY(x, y))


def no_partials(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith("."))


# --------------------------------------------------------------------------------------------
# Planning
# --------------------------------------------------------------------------------------------


def test_xyz_plan_is_utm_snapped_to_the_gsd_grid(xyz) -> None:
    plan = plan_extraction(xyz.layer(), xyz.area(0.5), WEB, 0.5, project_crs=WEB)
    assert plan.crs.authid() == "EPSG:32632"  # Web Mercator is not true to scale at 47 N
    for v in (plan.extent.xMinimum(), plan.extent.yMinimum(), plan.extent.xMaximum(), plan.extent.yMaximum()):
        assert abs(v / 0.5 - round(v / 0.5)) < 1e-6
    assert plan.width == round(plan.extent.width() / 0.5) and plan.height == round(plan.extent.height() / 0.5)
    # the snapped grid covers the requested area
    box = QgsCoordinateTransform(WEB, UTM32, QgsProject.instance().transformContext()).transformBoundingBox(
        xyz.area(0.5)
    )
    assert plan.extent.contains(box)
    assert plan.extent.width() - box.width() < 2 * 0.5 + 1e-6
    assert plan.megapixels() == pytest.approx(plan.width * plan.height / 1e6)


def test_crs_choice(tmp_path, xyz) -> None:
    layer_utm = QgsRasterLayer(
        str(write_tif(tmp_path / "u.tif", seeded_rgb(64, 64, 1), 32633, (534_000, 5_213_000), 1.0)), "u"
    )
    ext = QgsRectangle(534_010, 5_212_960, 534_050, 5_212_990)
    assert plan_extraction(layer_utm, ext, UTM33, 1.0, project_crs=WEB).crs == UTM33  # the layer's own
    # a metric, true-to-scale project CRS is used before falling back to UTM
    plan = plan_extraction(xyz.layer(), xyz.area(1), WEB, 1.0, project_crs=QgsCoordinateReferenceSystem("EPSG:31254"))
    assert plan.crs.authid() == "EPSG:31254"  # MGI / Austria GK West
    # an explicit target CRS wins; it must be projected in metres
    plan = plan_extraction(xyz.layer(), xyz.area(1), WEB, 1.0, target_crs=UTM33)
    assert plan.crs == UTM33
    with pytest.raises(InputError, match="not projected in metres"):
        plan_extraction(xyz.layer(), xyz.area(1), WEB, 1.0, target_crs=WGS84)
    # UTM zones both sides of the equator
    assert extract_plan.utm_crs(-70.6, -33.4).authid() == "EPSG:32719"
    assert extract_plan.utm_crs(179.9, 10).authid() == "EPSG:32660"


def test_size_limit_is_one_clear_line_with_a_gsd_that_fits(xyz) -> None:
    world = QgsRectangle(-2_000_000, 5_000_000, 2_000_000, 7_000_000)
    with pytest.raises(InputError) as err:
        plan_extraction(xyz.layer(), world, WEB, 0.5, max_pixels=400_000_000, project_crs=WEB)
    msg = str(err.value)
    assert "\n" not in msg and "above the extraction limit of 400 Mpx" in msg
    assert "choose a GSD of" in msg
    # the GSD it proposes does fit, for a moderate extent too
    area = xyz.area(0)
    with pytest.raises(InputError) as err:
        plan_extraction(xyz.layer(), area, WEB, 0.1, max_pixels=1_000_000, project_crs=WEB)
    proposed = float(str(err.value).split("choose a GSD of ")[1].split(" m")[0])
    plan = plan_extraction(xyz.layer(), area, WEB, proposed, max_pixels=1_000_000, project_crs=WEB)
    assert plan.width * plan.height <= 1_000_000
    assert plan.width * plan.height > 0.8e6  # and is not far coarser than needed


@pytest.mark.parametrize(
    ("gsd", "extent", "match"),
    [
        (0, QgsRectangle(0, 0, 100, 100), "positive"),
        (-1, QgsRectangle(0, 0, 100, 100), "positive"),
        (float("nan"), QgsRectangle(0, 0, 100, 100), "positive"),
        ("abc", QgsRectangle(0, 0, 100, 100), "not a number"),
        (1.0, QgsRectangle(), "empty"),
        (1.0, QgsRectangle(5, 5, 5, 90), "empty"),
        (10.0, QgsRectangle(1_270_000, 5_985_000, 1_270_050, 5_985_050), "is only"),
    ],
)
def test_bad_requests(xyz, gsd, extent, match) -> None:
    with pytest.raises(InputError, match=match):
        plan_extraction(xyz.layer(), extent, WEB, gsd, project_crs=WEB)


def test_extent_off_a_file_layer_and_invalid_layer(tmp_path) -> None:
    layer = QgsRasterLayer(
        str(write_tif(tmp_path / "u.tif", seeded_rgb(64, 64, 1), 32633, (534_000, 5_213_000), 1.0)), "u"
    )
    with pytest.raises(InputError, match="does not overlap"):
        plan_extraction(layer, QgsRectangle(600_000, 5_000_000, 600_500, 5_000_500), UTM33, 1.0)
    with pytest.raises(InputError, match="valid raster layer"):
        plan_extraction(QgsRasterLayer(str(tmp_path / "missing.tif"), "m"), QgsRectangle(0, 0, 9, 9), UTM33, 1.0)


def test_openstreetmap_tile_policy() -> None:
    osm = QgsRasterLayer("type=xyz&url=https://tile.openstreetmap.org/{z}/{x}/{y}.png&zmax=19", "osm", "wms")
    centre = to(WGS84, WEB, LON, LAT)
    big = QgsRectangle(centre.x() - 6_900, centre.y() - 6_900, centre.x() + 6_900, centre.y() + 6_900)
    with pytest.raises(InputError, match="tile usage policy"):
        plan_extraction(osm, big, WEB, 0.5, project_crs=WEB)
    small = QgsRectangle(centre.x() - 500, centre.y() - 500, centre.x() + 500, centre.y() + 500)
    assert plan_extraction(osm, small, WEB, 0.5, project_crs=WEB).width > 0  # planned, nothing fetched


# --------------------------------------------------------------------------------------------
# Extraction
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("gsd", [0.5, 1.3])
def test_xyz_extraction_lands_every_tile_where_it_belongs(xyz, tmp_path, gsd) -> None:
    layer = xyz.layer()
    plan = plan_extraction(layer, xyz.area(0.25), WEB, gsd, project_crs=WEB)
    progress: list[float] = []
    feedback = QgsFeedback()
    feedback.progressChanged.connect(progress.append)
    out = extract_layer(layer, plan, tmp_path / "xyz.tif", feedback, tile_px=512)
    rgb, mask, gt, wkt = read(out)
    assert rgb.shape == (plan.height, plan.width, 3)
    assert gt == pytest.approx(plan.geotransform()) and gt[1] == gsd and gt[5] == -gsd
    assert QgsCoordinateReferenceSystem.fromWkt(wkt).authid() == "EPSG:32632"
    assert mask.all()  # the area is inside the covered tiles
    for j in range(1, 3):  # the inner tiles lie wholly inside the extent
        for i in range(1, 3):
            hits = where_is(rgb, xyz.colour(i, j))
            t = xyz.tile(i, j)
            expect = to(WEB, plan.crs, t.center().x(), t.center().y())
            cx, cy = centroid_world(hits, plan)
            assert math.hypot(cx - expect.x(), cy - expect.y()) <= gsd, (i, j)
            side_m = t.width() * math.cos(math.radians(LAT))  # ground size of a tile
            assert hits.sum() * gsd**2 == pytest.approx(side_m**2, rel=0.05)
    assert progress[-1] == 100 and progress == sorted(progress)
    assert len(progress) >= len(list(extract.tiles(plan, 512))) + 1
    assert no_partials(tmp_path) == []
    ds = gdal.Open(str(out))
    assert ds.GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE") in ("ZSTD", "DEFLATE")
    assert ds.GetRasterBand(1).GetBlockSize() == [512, 512]
    assert ds.GetMetadataItem("OVERSEEC_GSD_M") == f"{gsd:g}"


def test_uncovered_area_is_masked_not_black(xyz, tmp_path) -> None:
    """Half the extent lies east of the seeded tiles: those pixels are masked out."""
    area = xyz.area(0)
    east = QgsRectangle(area.center().x(), area.yMinimum(), area.xMaximum() + area.width() / 2, area.yMaximum())
    layer = xyz.layer()
    plan = plan_extraction(layer, east, WEB, 1.0, project_crs=WEB)
    rgb, mask, _, _ = read(extract_layer(layer, plan, tmp_path / "half.tif"))
    edge = to(WEB, plan.crs, area.xMaximum(), area.center().y()).x()
    col = int((edge - plan.extent.xMinimum()) / plan.gsd_m)
    mid = plan.height // 2
    assert mask[mid, : col - 3].all() and not mask[mid, col + 3 :].any()
    assert (rgb[~mask] == 0).all()


def test_nothing_drawn_is_an_error_not_an_empty_image(xyz, tmp_path) -> None:
    far = to(WGS84, WEB, LON + 0.2, LAT)  # no tiles there
    layer = xyz.layer()
    plan = plan_extraction(
        layer, QgsRectangle(far.x(), far.y(), far.x() + 200, far.y() + 200), WEB, 2.0, project_crs=WEB
    )
    with pytest.raises(OutputError, match="drew nothing"):
        extract_layer(layer, plan, tmp_path / "empty.tif")
    assert list(tmp_path.iterdir()) == []


def test_geotiff_in_its_own_crs_at_its_own_gsd_is_copied_exactly(tmp_path) -> None:
    src = seeded_rgb(700, 900, 11)
    path = write_tif(tmp_path / "src.tif", src, 32633, (534_000, 5_213_000), 0.5)
    layer = QgsRasterLayer(str(path), "src")
    plan = plan_extraction(layer, layer.extent(), UTM33, 0.5, project_crs=WEB)
    assert plan.crs == UTM33 and (plan.width, plan.height) == (900, 700)
    rgb, mask, gt, _ = read(extract_layer(layer, plan, tmp_path / "copy.tif"))
    assert gt == (534_000, 0.5, 0, 5_213_000, 0, -0.5)
    assert mask.all() and np.array_equal(rgb, src)


def test_a_dimmed_basemap_is_extracted_opaque(tmp_path) -> None:
    """Opacity and blending are the canvas's business: the image is the layer at full strength,
    and the user's layer keeps its style."""
    src = seeded_rgb(100, 120, 5)
    layer = QgsRasterLayer(str(write_tif(tmp_path / "src.tif", src, 32633, (534_000, 5_213_000), 1.0)), "src")
    layer.renderer().setOpacity(0.4)
    plan = plan_extraction(layer, layer.extent(), UTM33, 1.0)
    rgb, mask, _, _ = read(extract_layer(layer, plan, tmp_path / "opaque.tif"))
    assert mask.all() and np.array_equal(rgb, src)
    assert layer.renderer().opacity() == pytest.approx(0.4)


def test_geotiff_in_lonlat_goes_to_utm(tmp_path) -> None:
    rgb0 = np.full((400, 400, 3), 90, np.uint8)
    rgb0[100:140, 250:300] = (255, 40, 0)  # a marker, rows 100-140, cols 250-300
    step = 1e-5  # about 0.75 m east, 1.1 m north
    path = write_tif(tmp_path / "ll.tif", rgb0, 4326, (LON, LAT), step)
    layer = QgsRasterLayer(str(path), "ll")
    plan = plan_extraction(layer, layer.extent(), WGS84, 0.5, project_crs=WGS84)
    assert plan.crs.authid() == "EPSG:32632"
    rgb, _, _, _ = read(extract_layer(layer, plan, tmp_path / "ll_utm.tif"))
    hits = where_is(rgb, np.array([255, 40, 0]))
    expect = to(WGS84, plan.crs, LON + 275 * step, LAT - 120 * step)
    cx, cy = centroid_world(hits, plan)
    assert math.hypot(cx - expect.x(), cy - expect.y()) <= plan.gsd_m


def test_vrt_mosaic(tmp_path) -> None:
    left, right = np.full((200, 100, 3), 60, np.uint8), np.full((200, 100, 3), 160, np.uint8)
    right[50:70, 30:50] = (250, 250, 0)  # marker at x 534130-534150, y 5212930-5212950
    a = write_tif(tmp_path / "a.tif", left, 32633, (534_000, 5_213_000), 1.0)
    b = write_tif(tmp_path / "b.tif", right, 32633, (534_100, 5_213_000), 1.0)
    gdal.BuildVRT(str(tmp_path / "mosaic.vrt"), [str(a), str(b)]).FlushCache()  # closed when dropped
    layer = QgsRasterLayer(str(tmp_path / "mosaic.vrt"), "mosaic")
    assert layer.isValid()
    plan = plan_extraction(layer, layer.extent(), UTM33, 2.0)
    assert (plan.width, plan.height) == (100, 100)
    rgb, mask, _, _ = read(extract_layer(layer, plan, tmp_path / "mosaic.tif"))
    assert mask.all()
    assert (rgb[:, :48] == 60).all() and (rgb[:, 52:][~where_is(rgb[:, 52:], np.array([250, 250, 0]))] == 160).all()
    cx, cy = centroid_world(where_is(rgb, np.array([250, 250, 0])), plan)
    assert math.hypot(cx - 534_140, cy - 5_212_940) <= 2.0


def test_cancel_leaves_nothing_and_keeps_the_earlier_file(xyz, tmp_path) -> None:
    out = tmp_path / "keep.tif"
    out.write_bytes(b"earlier result")
    layer = xyz.layer()
    plan = plan_extraction(layer, xyz.area(0), WEB, 0.5, project_crs=WEB)
    feedback = QgsFeedback()
    feedback.progressChanged.connect(lambda p: feedback.cancel() if 0 < p < 100 else None)
    with pytest.raises(Cancelled):
        extract_layer(layer, plan, out, feedback, tile_px=512)
    assert out.read_bytes() == b"earlier result"
    assert no_partials(tmp_path) == []


def test_output_over_the_input_is_refused(tmp_path) -> None:
    path = write_tif(tmp_path / "src.tif", seeded_rgb(64, 64, 3), 32633, (534_000, 5_213_000), 1.0)
    before = path.read_bytes()
    layer = QgsRasterLayer(str(path), "src")
    plan = plan_extraction(layer, layer.extent(), UTM33, 1.0)
    with pytest.raises(OutputError, match="layer's own file"):
        extract_layer(layer, plan, path)
    with pytest.raises(OutputError, match="does not exist"):
        extract_layer(layer, plan, tmp_path / "nope" / "x.tif")
    assert path.read_bytes() == before


def test_task_runs_in_the_background_and_cancels(xyz, tmp_path) -> None:
    layer = xyz.layer()
    plan = plan_extraction(layer, xyz.area(0.5), WEB, 1.0, project_crs=WEB)
    task = ExtractTask(layer, plan, tmp_path / "task.tif")
    got: list = []
    task.succeeded.connect(got.append)
    QgsApplication.taskManager().addTask(task)
    wait_until(lambda: got, 60, "the extraction task")
    assert got == [tmp_path / "task.tif"] and task.result_path == got[0]
    assert read(got[0])[0].shape == (plan.height, plan.width, 3)

    big = plan_extraction(layer, xyz.area(0), WEB, 0.3, project_crs=WEB)
    task = ExtractTask(layer, big, tmp_path / "cancelled.tif")
    failed: list = []
    task.failed.connect(lambda msg, details: failed.append(msg))
    task.progressChanged.connect(lambda p: task.cancel() if p > 0 else None)
    QgsApplication.taskManager().addTask(task)
    wait_until(lambda: failed, 60, "the cancelled task")
    assert "cancelled" in failed[0]
    assert not (tmp_path / "cancelled.tif").exists() and no_partials(tmp_path) == []


def test_plugin_modules_import_neither_rasterio_nor_torch() -> None:
    """The extraction uses osgeo.gdal only: QGIS on Windows/macOS ships no rasterio, and the QGIS
    process never imports torch. Checked in a fresh process (this one has both loaded)."""
    code = (
        "import sys; import overseec_qgis.extract, overseec_qgis.extent_tool, "
        "overseec_qgis.processing.extract_algorithm; "
        "print(sorted(m for m in ('rasterio', 'torch', 'transformers') if m in sys.modules))"
    )
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
    done = subprocess.run([sys.executable, "-c", code], cwd=REPO, env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip().splitlines()[-1] == "[]"


def test_compress_fallback(monkeypatch) -> None:
    monkeypatch.setenv("OVERSEEC_COMPRESS", "deflate")
    assert "COMPRESS=DEFLATE" in extract.creation_options()
    monkeypatch.delenv("OVERSEEC_COMPRESS")
    assert "COMPRESS=ZSTD" in extract.creation_options()
    assert os.environ.get("OVERSEEC_COMPRESS") is None


# --------------------------------------------------------------------------------------------
# Processing: overseec:extractimagery
# --------------------------------------------------------------------------------------------


def extent_param(rect: QgsRectangle, authid: str) -> str:
    return f"{rect.xMinimum()},{rect.xMaximum()},{rect.yMinimum()},{rect.yMaximum()} [{authid}]"


def run_alg(params: dict, load: bool = False, feedback=None) -> dict:
    import processing

    from overseec_qgis.processing.extract_algorithm import ExtractImageryAlgorithm

    alg = ExtractImageryAlgorithm()
    alg.initAlgorithm()
    if load:
        return processing.runAndLoadResults(alg, params, feedback=feedback)
    return processing.run(alg, params, feedback=feedback)


def test_processing_xyz_to_temporary_output_that_loads(qgis_processing, qgis_new_project, xyz) -> None:
    layer = xyz.layer()
    QgsProject.instance().addMapLayer(layer)
    area = xyz.area(0.5)
    res = run_alg(
        {"INPUT": layer.id(), "EXTENT": extent_param(area, "EPSG:3857"), "GSD": 1.0, "OUTPUT": "TEMPORARY_OUTPUT"},
        load=True,
    )
    out = Path(res["OUTPUT"])
    assert out.suffix == ".tif" and out.exists()
    loaded = [lyr for lyr in QgsProject.instance().mapLayers().values() if lyr.source() == str(out)]
    assert len(loaded) == 1 and loaded[0].isValid() and loaded[0].crs().authid() == "EPSG:32632"
    assert loaded[0].rasterUnitsPerPixelX() == 1.0 and loaded[0].rasterUnitsPerPixelY() == 1.0
    rgb, mask, gt, _ = read(out)
    t = xyz.tile(1, 1)
    expect = to(WEB, UTM32, t.center().x(), t.center().y())
    col, row = int((expect.x() - gt[0]) / gt[1]), int((expect.y() - gt[3]) / gt[5])
    assert (rgb[row, col] == xyz.colour(1, 1)).all() and mask.all()


class ErrorsKept(QgsProcessingFeedback):
    """Processing's feedback, keeping the errors it reports (the algorithm's own message)."""

    def __init__(self) -> None:
        super().__init__()
        self.errors: list[str] = []

    def reportError(self, error: str, fatalError: bool = False) -> None:  # noqa: N803
        self.errors.append(error)
        super().reportError(error, fatalError)


def test_processing_options_and_errors(qgis_processing, xyz, tmp_path) -> None:
    area = extent_param(xyz.area(1), "EPSG:3857")
    res = run_alg(
        {
            "INPUT": "wms://" + xyz.uri(),  # how qgis_process names a tile service
            "EXTENT": area,
            "GSD": 2.0,
            "TARGET_CRS": "EPSG:31254",
            "OUTPUT": str(tmp_path / "gk.tif"),
        }
    )
    ds = gdal.Open(res["OUTPUT"])
    assert ds.GetGeoTransform()[1] == 2.0
    assert QgsCoordinateReferenceSystem.fromWkt(ds.GetProjection()).authid() == "EPSG:31254"
    for params, message in (
        ({"GSD": 0.2, "MAX_MEGAPIXELS": 1}, "above the extraction limit of 1 Mpx; choose a GSD of"),
        ({"GSD": 2.0, "TARGET_CRS": "EPSG:4326"}, "not projected in metres"),
    ):
        feedback = ErrorsKept()
        with pytest.raises(QgsProcessingException):
            run_alg(
                {"INPUT": xyz.layer(), "EXTENT": area, "OUTPUT": str(tmp_path / "x.tif"), **params}, feedback=feedback
            )
        assert any(message in e for e in feedback.errors), feedback.errors
    assert sorted(p.name for p in tmp_path.iterdir()) == ["gk.tif"]


def test_processing_cancel(qgis_processing, xyz, tmp_path) -> None:
    feedback = ErrorsKept()
    feedback.progressChanged.connect(lambda p: feedback.cancel() if 0 < p < 100 else None)
    area = extent_param(xyz.area(0), "EPSG:3857")
    with pytest.raises(QgsProcessingException, match="cancelled"):  # processAlgorithm's message is the error
        run_alg(
            {"INPUT": xyz.layer(), "EXTENT": area, "GSD": 0.3, "OUTPUT": str(tmp_path / "c.tif")}, feedback=feedback
        )
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------------------------
# Seams, the core reading the output, the extent tool
# --------------------------------------------------------------------------------------------


def test_tiles_have_no_seams(xyz, tmp_path) -> None:
    """512 px tiles give the image one 1024 px tile gives (XYZ reprojected to UTM).

    Nearest-neighbour reprojection (QgsRasterProjector's approximate grid, and the zoom QGIS
    picks) depends on the tile's extent, so pixels along colour edges may move by a pixel or
    two; nothing else may differ -- no seam rows or columns at the tile borders."""
    layer = xyz.layer()
    plan = plan_extraction(layer, xyz.area(0.3), WEB, 0.45, project_crs=WEB)
    assert 512 < min(plan.width, plan.height) and max(plan.width, plan.height) <= 1024
    small, _, _, _ = read(extract_layer(layer, plan, tmp_path / "small.tif", tile_px=512))
    whole, _, _, _ = read(extract_layer(layer, plan, tmp_path / "whole.tif", tile_px=1024))
    differ = np.any(small != whole, axis=-1)
    assert differ.mean() < 0.01
    for i, j in zip(*np.nonzero(differ)):  # each one is an edge pixel: its colour lies within 2 px
        near = whole[max(0, i - 2) : i + 3, max(0, j - 2) : j + 3].reshape(-1, 3)
        assert (near == small[i, j]).all(axis=1).any(), (i, j)
    for k in (510, 511, 512, 513):  # no seam lines along the tile borders
        assert differ[k].mean() < 0.05 and differ[:, k].mean() < 0.05


def test_the_core_reads_the_extract_as_rgb_with_its_mask(xyz, tmp_path) -> None:
    from rasterio.windows import Window

    from overseec_core.io.read import RasterSource

    area = xyz.area(0)
    east = QgsRectangle(area.center().x(), area.yMinimum(), area.xMaximum() + area.width() / 2, area.yMaximum())
    layer = xyz.layer()
    plan = plan_extraction(layer, east, WEB, 2.0, project_crs=WEB)
    out = extract_layer(layer, plan, tmp_path / "core.tif")
    rgb, mask, _, _ = read(out)
    with RasterSource(out) as src:
        assert src.grid.pixel_size_m() == pytest.approx((2.0, 2.0), rel=1e-3)
        chip = src.read_chip(Window(0, 0, plan.width, plan.height))
    assert np.array_equal(chip.rgb, rgb)
    assert np.array_equal(chip.valid, mask) and 0.3 < mask.mean() < 0.7  # the uncovered half is invalid


@pytest.fixture
def extent_tool(qgis_canvas, qgis_parent):
    from qgis.PyQt.QtCore import QCoreApplication

    from overseec_qgis.extent_tool import ExtentMapTool

    qgis_parent.resize(600, 400)
    qgis_parent.show()
    qgis_canvas.resize(600, 400)
    QCoreApplication.processEvents()
    qgis_canvas.setDestinationCrs(WEB)
    qgis_canvas.setExtent(QgsRectangle(1_268_000, 5_984_000, 1_272_000, 5_988_000))
    tool = ExtentMapTool(qgis_canvas)
    qgis_canvas.setMapTool(tool)
    yield tool, qgis_canvas
    qgis_canvas.unsetMapTool(tool)
    tool.reset()


def mouse(tool, canvas, kind: str, x: int, y: int, button=None) -> None:
    from qgis.gui import QgsMapMouseEvent
    from qgis.PyQt.QtCore import QEvent, QPoint, Qt

    button = Qt.LeftButton if button is None else button
    pos = QPoint(x, y)
    if kind == "press":
        tool.canvasPressEvent(QgsMapMouseEvent(canvas, QEvent.MouseButtonPress, pos, button, button))
    elif kind == "move":
        tool.canvasMoveEvent(QgsMapMouseEvent(canvas, QEvent.MouseMove, pos, Qt.NoButton, button))
    else:
        tool.canvasReleaseEvent(QgsMapMouseEvent(canvas, QEvent.MouseButtonRelease, pos, button, Qt.NoButton))


def test_extent_tool_draws_and_emits_the_rectangle_in_canvas_crs(extent_tool) -> None:
    tool, canvas = extent_tool
    drawn: list = []
    tool.extent_drawn.connect(drawn.append)
    mouse(tool, canvas, "press", 300, 250)
    mouse(tool, canvas, "move", 200, 150)
    assert tool.band.numberOfVertices() > 0  # the band follows the mouse
    mouse(tool, canvas, "release", 100, 50)  # dragged up and left: still a normal rectangle
    assert len(drawn) == 1
    to_map = canvas.getCoordinateTransform()
    a, b = to_map.toMapCoordinates(100, 50), to_map.toMapCoordinates(300, 250)
    rect = drawn[0]
    assert rect.xMinimum() == pytest.approx(a.x()) and rect.xMaximum() == pytest.approx(b.x())
    assert rect.yMinimum() == pytest.approx(b.y()) and rect.yMaximum() == pytest.approx(a.y())
    assert rect.width() > 0 and rect.height() > 0
    assert tool.extent == rect and tool.band.asGeometry().boundingBox() == rect  # kept on the map
    # it plans: the drawn rectangle (canvas CRS) is a valid extent
    assert tool.band.asGeometry().area() == pytest.approx(rect.area())


def test_extent_tool_cancels_on_esc_right_click_and_plain_click(extent_tool) -> None:
    from qgis.PyQt.QtCore import QEvent, Qt
    from qgis.PyQt.QtGui import QKeyEvent

    tool, canvas = extent_tool
    drawn: list = []
    cancelled: list = []
    tool.extent_drawn.connect(drawn.append)
    tool.cancelled.connect(lambda: cancelled.append(True))

    mouse(tool, canvas, "press", 100, 100)
    mouse(tool, canvas, "move", 200, 200)
    tool.keyPressEvent(QKeyEvent(QEvent.KeyPress, Qt.Key_Escape, Qt.NoModifier))
    mouse(tool, canvas, "release", 200, 200)  # the release after Esc draws nothing
    assert drawn == [] and len(cancelled) == 1 and tool.extent is None and tool.band.numberOfVertices() == 0

    mouse(tool, canvas, "press", 100, 100)
    mouse(tool, canvas, "move", 200, 200)
    mouse(tool, canvas, "press", 200, 200, Qt.RightButton)
    assert drawn == [] and len(cancelled) == 2 and tool.band.numberOfVertices() == 0

    mouse(tool, canvas, "press", 100, 100)
    mouse(tool, canvas, "release", 102, 101)  # a click, not a drag
    assert drawn == [] and len(cancelled) == 3

    tool.show_extent(QgsRectangle(1_269_000, 5_985_000, 1_270_000, 5_986_000))  # e.g. the canvas extent
    assert tool.extent == QgsRectangle(1_269_000, 5_985_000, 1_270_000, 5_986_000)
    tool.reset()
    assert tool.extent is None and tool.band.numberOfVertices() == 0 and len(cancelled) == 3


# --------------------------------------------------------------------------------------------
# Screenshot: the drawn rectangle on an XYZ basemap, and what came out
# --------------------------------------------------------------------------------------------


def render(layers, crs, extent: QgsRectangle, size: tuple[int, int]):
    from qgis.core import QgsMapRendererParallelJob, QgsMapSettings
    from qgis.PyQt.QtCore import QSize
    from qgis.PyQt.QtGui import QColor

    settings = QgsMapSettings()
    settings.setLayers(layers)
    settings.setDestinationCrs(crs)
    settings.setExtent(extent)
    settings.setOutputSize(QSize(*size))
    settings.setBackgroundColor(QColor("white"))
    job = QgsMapRendererParallelJob(settings)
    job.start()
    job.waitForFinished()
    return job.renderedImage(), settings


def test_screenshot_of_an_xyz_extraction(tmp_path) -> None:
    """docs/img/extract.png: the sample scene served as file:// XYZ tiles (EPSG:3857), the
    rectangle drawn on it, and the extracted GeoTIFF (UTM 33N, 0.6 m) beside it."""
    from qgis.core import QgsPointXY
    from qgis.PyQt.QtCore import QPointF, QRectF, Qt
    from qgis.PyQt.QtGui import QColor, QFont, QImage, QPainter, QPen

    from .conftest import SAMPLE, artifacts_dir
    from .test_screenshot import as_array, assert_not_blank
    from .xyz_source import write_xyz_from_raster

    uri, count = write_xyz_from_raster(SAMPLE / "sample.tif", tmp_path / "tiles", range(16, 19))
    assert count > 20
    basemap = QgsRasterLayer(uri, "sample basemap (XYZ)", "wms")
    assert basemap.isValid()
    ds = gdal.Open(str(SAMPLE / "sample.tif"))
    x0, dx, _, y0, _, dy = ds.GetGeoTransform()
    scene = QgsRectangle(x0, y0 + ds.RasterYSize * dy, x0 + ds.RasterXSize * dx, y0)
    view = QgsCoordinateTransform(UTM33, WEB, QgsCoordinateTransformContext()).transformBoundingBox(scene)
    view.grow(view.width() * 0.04)
    drawn = QgsRectangle(  # what the operator drew on the canvas (EPSG:3857)
        view.xMinimum() + 0.22 * view.width(),
        view.yMinimum() + 0.18 * view.height(),
        view.xMinimum() + 0.80 * view.width(),
        view.yMinimum() + 0.70 * view.height(),
    )
    plan = plan_extraction(basemap, drawn, WEB, 0.6, project_crs=WEB)
    assert plan.crs.authid() == "EPSG:32633"
    out = extract_layer(basemap, plan, tmp_path / "extract.tif")
    extracted = QgsRasterLayer(str(out), "extract.tif")
    assert extracted.isValid()

    side = 760
    left, left_settings = render([basemap], WEB, view, (side, side))
    right, _ = render([extracted], plan.crs, plan.extent, (side, round(side * plan.height / plan.width)))
    assert_not_blank(as_array(left), "the basemap")
    assert_not_blank(as_array(right), "the extract")

    caption_h, gap = 70, 24
    shot = QImage(2 * side + gap, side + caption_h, QImage.Format_RGB32)
    shot.fill(Qt.white)
    painter = QPainter(shot)
    painter.setRenderHint(QPainter.Antialiasing)
    painter.drawImage(0, caption_h, left)
    painter.drawImage(side + gap, caption_h + (side - right.height()) // 2, right)
    m2p = left_settings.mapToPixel()
    a = m2p.transform(QgsPointXY(drawn.xMinimum(), drawn.yMaximum()))
    b = m2p.transform(QgsPointXY(drawn.xMaximum(), drawn.yMinimum()))
    box = QRectF(QPointF(a.x(), a.y() + caption_h), QPointF(b.x(), b.y() + caption_h))
    painter.setPen(QPen(QColor(255, 0, 110), 3))
    painter.drawRect(box)
    painter.setPen(QColor(20, 20, 20))
    font = QFont()
    font.setPixelSize(17)
    painter.setFont(font)
    painter.drawText(
        QRectF(8, 6, side - 16, caption_h - 8),
        Qt.TextWordWrap,
        "XYZ basemap (file://…/{z}/{x}/{y}.png, EPSG:3857) with the rectangle drawn by the extent tool",
    )
    painter.drawText(
        QRectF(side + gap + 8, 6, side - 16, caption_h - 8),
        Qt.TextWordWrap,
        f"Extracted GeoTIFF: {plan.width} x {plan.height} px at {plan.gsd_m:g} m, "
        f"{plan.crs.authid()} (UTM zone 33N, chosen from the extent), ready for overseec",
    )
    painter.end()
    path = artifacts_dir() / "extract.png"
    assert shot.save(str(path), "PNG")
    assert path.stat().st_size > 50_000
