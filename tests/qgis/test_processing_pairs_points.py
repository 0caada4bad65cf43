"""``overseec:plan`` with START_POINTS and GOAL_POINTS: pairs given as two point layers.

Through ``processing.run`` with the worker pinned to this checkout's CLI: starts in WGS 84 and
goals in the costmap's CRS, paired by a shared ``id`` (goals listed in another order) or by
feature order; every route costs what a single `overseec plan` between the same points costs.
"""

from __future__ import annotations

import json
from pathlib import Path

import fiona
import pytest
from qgis.core import QgsProcessingException

from overseec_core.cli import main as cli_main

from .test_processing_corridor import checkout_worker, loaded, private_settings, project, provider  # noqa: F401

pytestmark = pytest.mark.qgis

#: (id, start pixel, goal pixel) on the conftest scene (48 x 64, water in the middle)
ENDS = (("west", (44, 2), (2, 60)), ("east", (40, 60), (5, 5)), ("north", (3, 3), (3, 62)))


def _points(scene, which: int, crs: str, ids: bool, order=None):
    """A memory point layer of the ENDS' starts (which=1) or goals (which=2) in ``crs``."""
    from qgis.core import (
        QgsCoordinateReferenceSystem,
        QgsCoordinateTransform,
        QgsFeature,
        QgsField,
        QgsGeometry,
        QgsPointXY,
        QgsProject,
        QgsVectorLayer,
    )
    from qgis.PyQt.QtCore import QVariant

    layer = QgsVectorLayer(f"Point?crs={crs}", "starts" if which == 1 else "goals", "memory")
    if ids:
        layer.dataProvider().addAttributes([QgsField("id", QVariant.String)])
        layer.updateFields()
    to_crs = QgsCoordinateTransform(
        QgsCoordinateReferenceSystem("EPSG:32633"), QgsCoordinateReferenceSystem(crs), QgsProject.instance()
    )
    for end in order or ENDS:
        f = QgsFeature(layer.fields())
        f.setGeometry(QgsGeometry.fromPointXY(to_crs.transform(QgsPointXY(*scene.world(*end[which])))))
        if ids:
            f.setAttribute("id", end[0])
        layer.dataProvider().addFeatures([f])
    return layer


def _single_costs(scene, tmp_path: Path) -> dict[str, float]:
    costs = {}
    for ident, a, b in ENDS:
        out = tmp_path / "single" / ident / "path.geojson"
        (x0, y0), (x1, y1) = scene.world(*a), scene.world(*b)
        argv = ["-q", "plan", str(scene.costmap), "--start", repr(x0), repr(y0), "--goal", repr(x1), repr(y1)]
        assert cli_main([*argv, "--out", str(out)]) == 0
        costs[ident] = json.loads(out.read_text())["features"][0]["properties"]["total_cost"]
    return costs


def test_point_layers_pair_by_id_and_by_order(provider, project, scene, tmp_path: Path) -> None:  # noqa: F811
    import processing

    single = _single_costs(scene, tmp_path)
    # by id: starts in WGS 84, goals in the costmap's CRS listed backwards
    starts = _points(scene, 1, "EPSG:4326", ids=True)
    goals = _points(scene, 2, "EPSG:32633", ids=True, order=tuple(reversed(ENDS)))
    res = processing.runAndLoadResults(
        "overseec:plan",
        {
            "COSTMAP": str(scene.costmap),
            "START_POINTS": starts,
            "GOAL_POINTS": goals,
            "MODE": 1,
            "OUTPUT": str(tmp_path / "by_id.gpkg"),
        },
    )
    assert res["ROUTES"] == 3
    with fiona.open(res["OUTPUT"], layer="routes") as src:
        got = {f["properties"]["id"]: f["properties"]["total_cost"] for f in src}
    assert got == pytest.approx(single, rel=1e-9)
    assert loaded(project, "routes — 3 of 3 pairs").featureCount() == 3
    # by order: no id fields, ids are the positions
    starts, goals = _points(scene, 1, "EPSG:4326", ids=False), _points(scene, 2, "EPSG:32633", ids=False)
    res = processing.run(
        "overseec:plan",
        {
            "COSTMAP": str(scene.costmap),
            "START_POINTS": starts,
            "GOAL_POINTS": goals,
            "MODE": 1,
            "OUTPUT": str(tmp_path / "by_order.gpkg"),
        },
    )
    with fiona.open(res["OUTPUT"], layer="routes") as src:
        got = {f["properties"]["id"]: f["properties"]["total_cost"] for f in src}
    assert got == pytest.approx({str(n): single[e[0]] for n, e in enumerate(ENDS, start=1)}, rel=1e-9)


def test_point_layers_that_do_not_pair_fail_in_one_line(provider, scene, tmp_path: Path) -> None:  # noqa: F811
    import processing

    starts = _points(scene, 1, "EPSG:32633", ids=False)
    goals = _points(scene, 2, "EPSG:32633", ids=False, order=ENDS[:2])
    base = {"COSTMAP": str(scene.costmap), "OUTPUT": str(tmp_path / "x.gpkg")}
    with pytest.raises(QgsProcessingException, match="3 start points but 2 goal points"):
        processing.run("overseec:plan", {**base, "START_POINTS": starts, "GOAL_POINTS": goals})
    with pytest.raises(QgsProcessingException, match="START_POINTS needs GOAL_POINTS"):
        processing.run("overseec:plan", {**base, "START_POINTS": starts})
    with pytest.raises(QgsProcessingException, match="one of them"):
        processing.run("overseec:plan", {**base, "START_POINTS": starts, "GOAL_POINTS": goals, "START": "1,2"})
    assert not (tmp_path / "x.gpkg").exists()
