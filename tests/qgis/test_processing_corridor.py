"""``overseec:corridor`` and ``overseec:plan`` with PAIRS through ``processing.run``: the worker
CLI's files, the same as the CLI writes, loaded named and styled."""

from __future__ import annotations

import json
from pathlib import Path

import fiona
import numpy as np
import pytest
import rasterio
from qgis.core import QgsProcessingException

from overseec_core import defaults
from overseec_core.cli import main as cli_main

from .processing_fixtures import *  # noqa: F403 (the fixtures: private settings, provider, project)

pytestmark = pytest.mark.qgis


def read(path: str | Path) -> np.ndarray:
    with rasterio.open(path) as ds:
        return ds.read(1)


def loaded(project, prefix: str):
    found = [lay for lay in project.mapLayers().values() if lay.name().startswith(prefix)]
    assert len(found) == 1, f"{prefix!r} among {[lay.name() for lay in project.mapLayers().values()]}"
    return found[0]


def test_corridor_matches_the_cli_loads_styled_and_stretched(provider, project, scene, tmp_path: Path) -> None:
    import processing
    from pyproj import Transformer
    from qgis.core import QgsSingleBandPseudoColorRenderer

    to_ll = Transformer.from_crs("EPSG:32633", "EPSG:4326", always_xy=True)
    (sx, sy), (gx, gy) = scene.world(44, 2), scene.world(2, 60)
    lon, lat = to_ll.transform(gx, gy)
    res = processing.runAndLoadResults(
        "overseec:corridor",
        {
            "COSTMAP": str(scene.costmap),
            "START": f"{sx},{sy} [EPSG:32633]",
            "GOAL": f"{lon},{lat} [EPSG:4326]",  # any CRS: Processing reprojects
            "WITHIN": 15.0,
            "OUTPUT": str(tmp_path / "q" / "corridor.tif"),
            "MASK": str(tmp_path / "q" / "within.tif"),
        },
    )
    cli_out = tmp_path / "cli" / "corridor.tif"
    argv = ["-q", "corridor", str(scene.costmap), "--start", repr(sx), repr(sy), "--goal", repr(gx), repr(gy)]
    assert cli_main([*argv, "--within", "15", "--out", str(cli_out)]) == 0
    np.testing.assert_array_equal(read(res["OUTPUT"]), read(cli_out))
    np.testing.assert_array_equal(read(res["MASK"]), read(tmp_path / "cli" / "corridor-within.tif"))
    assert res["CELLS_WITHIN"] == int(read(res["MASK"]).sum()) > 0
    manifest = json.loads((tmp_path / "cli" / "manifest.json").read_text())
    assert res["OPTIMUM"] == pytest.approx(manifest["corridor"]["optimum"], rel=1e-12)

    ratio = loaded(project, "corridor — within 15 % of cost")
    renderer = ratio.renderer()
    assert isinstance(renderer, QgsSingleBandPseudoColorRenderer)
    items = renderer.shader().rasterShaderFunction().colorRampItemList()
    assert items[0].value == 1.0 and items[-1].value == pytest.approx(1.15)
    assert items[0].color.name() == "#1a9850" and items[-1].color.name() == "#d73027"  # green .. red
    assert ratio.customProperty("overseec/role") == "corridor"
    mask = loaded(project, "corridor mask — within 15 %")
    assert mask.renderer().type() == "paletted"


def test_corridor_bad_input_is_the_clis_one_line(provider, scene, tmp_path: Path) -> None:
    import processing

    (sx, sy) = scene.world(44, 2)
    wx, wy = scene.world(25, 30)  # in the water: lethal
    with pytest.raises(QgsProcessingException, match="lethal"):
        processing.run(
            "overseec:corridor",
            {
                "COSTMAP": str(scene.costmap),
                "START": f"{sx},{sy} [EPSG:32633]",
                "GOAL": f"{wx},{wy} [EPSG:32633]",
                "WITHIN": 10.0,
                "OUTPUT": str(tmp_path / "c.tif"),
                "MASK": str(tmp_path / "m.tif"),
            },
        )
    assert not (tmp_path / "c.tif").exists()


@pytest.mark.parametrize("steps", ["8", "16"])
def test_plan_takes_a_layer_of_pairs(provider, project, scene, tmp_path: Path, steps: str) -> None:
    """Each route equals the CLI's single plan with the same Steps (NEIGHBOURS reaches --pairs)."""
    import processing
    from qgis.core import QgsFeature, QgsField, QgsGeometry, QgsPointXY, QgsVectorLayer
    from qgis.PyQt.QtCore import QVariant

    pairs = QgsVectorLayer("LineString?crs=EPSG:32633", "pairs", "memory")
    pairs.dataProvider().addAttributes([QgsField("id", QVariant.String)])
    pairs.updateFields()
    ends = {"west": ((44, 2), (2, 60)), "east": ((40, 60), (5, 5))}
    for ident, (a, b) in ends.items():
        f = QgsFeature(pairs.fields())
        f.setGeometry(QgsGeometry.fromPolylineXY([QgsPointXY(*scene.world(*a)), QgsPointXY(*scene.world(*b))]))
        f.setAttribute("id", ident)
        pairs.dataProvider().addFeatures([f])
    res = processing.runAndLoadResults(
        "overseec:plan",
        {
            "COSTMAP": str(scene.costmap),
            "PAIRS": pairs,
            "MODE": 1,
            "NEIGHBOURS": defaults.PLAN_NEIGHBOURS.index(int(steps)),
            "OUTPUT": str(tmp_path / "routes.gpkg"),
        },
    )
    assert res["ROUTES"] == 2
    with fiona.open(res["OUTPUT"], layer="routes") as src:
        got = {f["properties"]["id"]: f["properties"]["total_cost"] for f in src}
    for ident, (a, b) in ends.items():
        out = tmp_path / ident / "path.geojson"
        (x0, y0), (x1, y1) = scene.world(*a), scene.world(*b)
        argv = ["-q", "plan", str(scene.costmap), "--start", repr(x0), repr(y0), "--goal", repr(x1), repr(y1)]
        assert cli_main([*argv, "--neighbours", steps, "--out", str(out)]) == 0
        single = json.loads(out.read_text())["features"][0]["properties"]["total_cost"]
        assert got[ident] == single
    assert res["COST"] == pytest.approx(sum(got.values()))
    assert loaded(project, "routes — 2 of 2 pairs").featureCount() == 2
    with pytest.raises(QgsProcessingException, match="START and GOAL"):
        processing.run("overseec:plan", {"COSTMAP": str(scene.costmap), "OUTPUT": str(tmp_path / "x.gpkg")})
