"""Processing results as layers: Compare's routes and diverging cost difference, the exports
QGIS can open, unique names, and every route above the costmaps (the routes group).

Runs the algorithms as the toolbox does with "Open output file" ticked
(``processing.runAndLoadResults``), through the real `overseec` worker.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from overseec_qgis.layers import DIFFERENCE_STYLE, apply_style
from overseec_qgis.legend import PROP_ROUTES_GROUP, find_routes_group, layer_name

from .conftest import SAMPLE
from .processing_fixtures import *  # noqa: F403 (the fixtures: private settings, provider, project)

pytestmark = pytest.mark.qgis
#: The provider runs the worker the settings find (processing_fixtures.provider).
CONFIGURED_WORKER = True

META = json.loads((SAMPLE / "sample.json").read_text())
PROMPTS = ("prefer roads", "prefer grass, avoid roads")


def run_and_load(alg: str, params: dict) -> dict:
    import processing

    return processing.runAndLoadResults(f"overseec:{alg}", params)


def points() -> dict:
    (sx, sy), (gx, gy) = META["start"], META["goal"]
    return {"START": f"{sx},{sy} [EPSG:32633]", "GOAL": f"{gx},{gy} [EPSG:32633]"}


@pytest.fixture
def compared(provider, project, tmp_path):
    res = run_and_load(
        "compare",
        {
            "PROMPTS": "\n".join(PROMPTS),
            "LABELS": str(SAMPLE / "sample_labels.tif"),
            "CLASSES": str(SAMPLE / "classes.json"),
            **points(),
            "MODE": 1,
            "OUTPUT_DIR": str(tmp_path / "cmp"),
        },
    )
    return project, res


def test_compare_loads_its_routes_above_the_difference(compared) -> None:
    project, res = compared
    root = project.layerTreeRoot()
    routes = find_routes_group(project)
    assert routes is not None and root.children()[0] is routes
    names = [node.layer().name() for node in routes.findLayers()]
    assert sorted(names) == sorted(f"path — {p}" for p in PROMPTS)
    out = Path(res["OUTPUT_DIR"])
    sources = {node.layer().source().split("|")[0] for node in routes.findLayers()}
    assert sources == {str(out / "prompt_1" / "path.geojson"), str(out / "prompt_2" / "path.geojson")}
    # each candidate's route in its own colour
    colours = {node.layer().renderer().symbol().symbolLayers()[-1].color().name() for node in routes.findLayers()}
    assert len(colours) == 2
    drawn = [lyr.customProperty("overseec/role") for lyr in root.layerOrder()]
    assert drawn == ["path", "path", "difference"]


def test_compare_difference_is_diverging_blue_cheaper_red_dearer(compared) -> None:
    project, res = compared
    (layer,) = [lyr for lyr in project.mapLayers().values() if lyr.customProperty("overseec/role") == "difference"]
    assert layer.source() == res["DIFFERENCE"]
    assert layer.name() == layer_name("cost difference", f"{PROMPTS[1]} − {PROMPTS[0]}")
    group = project.layerTreeRoot().findLayer(layer.id()).parent()
    assert group.name().startswith("overseec compare — ") and not group.customProperty(PROP_ROUTES_GROUP)
    renderer = layer.renderer()
    assert renderer.type() == "singlebandpseudocolor" and renderer.band() == 1
    assert (renderer.classificationMin(), renderer.classificationMax()) == (-1.0, 1.0)
    ref = layer.clone()
    apply_style(ref, DIFFERENCE_STYLE)
    items = renderer.shader().rasterShaderFunction().colorRampItemList()
    assert items == ref.renderer().shader().rasterShaderFunction().colorRampItemList()
    shader = renderer.shader()

    def rgba(value):
        ok, r, g, b, a = shader.shade(value)
        assert ok
        return r, g, b, a

    r, g, b, a = rgba(-0.8)
    assert b > r + 80 and a > 200  # cheaper: blue
    r, g, b, a = rgba(0.8)
    assert r > b + 80 and a > 200  # dearer: red
    assert rgba(0.0)[3] == 0  # unchanged: transparent
    assert rgba(0.0005)[3] < 10


def test_exports_load_where_qgis_opens_them(compared, tmp_path) -> None:
    project, res = compared
    out = Path(res["OUTPUT_DIR"])
    costmap = run_and_load(
        "exportcostmap", {"COSTMAP": str(out / "prompt_1" / "costmap.tif"), "FORMAT": 1, "OUTPUT": str(tmp_path / "c")}
    )
    (exported,) = [lyr for lyr in project.mapLayers().values() if lyr.source() == costmap["OUTPUT"]]
    assert exported.isValid() and exported.crs().authid() == "EPSG:32633"
    assert exported.renderer().type() == "singlebandpseudocolor" and exported.renderer().classificationMax() == 254
    assert exported.name().startswith("costmap_2d")
    gpx = run_and_load(
        "exportpath", {"PATH": str(out / "prompt_1" / "path.geojson"), "FORMAT": 0, "OUTPUT": str(tmp_path / "r")}
    )
    (track,) = [lyr for lyr in project.mapLayers().values() if lyr.source().split("|")[0] == gpx["OUTPUT"]]
    assert track.isValid() and track.featureCount() == 1 and track.geometryType() == 1  # lines
    assert find_routes_group(project).findLayer(track.id()) is not None
    kml = run_and_load(
        "exportpath", {"PATH": str(out / "prompt_1" / "path.geojson"), "FORMAT": 1, "OUTPUT": str(tmp_path / "r")}
    )
    (placemark,) = [lyr for lyr in project.mapLayers().values() if lyr.source().split("|")[0] == kml["OUTPUT"]]
    assert kml["OUTPUT"].endswith(".kml") and placemark.isValid() and placemark.featureCount() == 1
    csv = run_and_load(
        "exportpath", {"PATH": str(out / "prompt_1" / "path.geojson"), "FORMAT": 2, "OUTPUT": str(tmp_path / "r")}
    )
    assert not [lyr for lyr in project.mapLayers().values() if lyr.source().split("|")[0] == csv["OUTPUT"]]
    drawn = [lyr.customProperty("overseec/role") for lyr in project.layerTreeRoot().layerOrder()]
    assert drawn[:4] == ["path"] * 4 and "export" in drawn[4:]


def test_processing_costmaps_of_one_prompt_get_distinct_names(provider, project, scene) -> None:
    program = 'cost = where(M["road"], 0.05, 0.5)'
    for _ in range(2):
        run_and_load("costmap", {"MASKS": str(scene.folder), "PROGRAM_TEXT": program, "OUTPUT": "TEMPORARY_OUTPUT"})
    names = sorted(lyr.name() for lyr in project.mapLayers().values())
    assert names == ["costmap — cost program", "costmap — cost program (2)"]
