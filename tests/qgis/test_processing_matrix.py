"""``overseec:costmatrix``: the route cost between point layers' points (``plan --matrix``).

Through ``processing.run`` with the worker pinned to this checkout's CLI, on the conftest scene:
from start points in WGS 84 (a memory layer) to goal points in the costmap's CRS (a table of a
GeoPackage holding two), each diagonal cell costs what a single exact `overseec plan` between the
same two points costs, and every cell what the CLI's own `plan --matrix` writes.
"""

from __future__ import annotations

import csv
from pathlib import Path

import pytest
from qgis.core import QgsProcessingException

from overseec_core.cli import main as cli_main

from .test_processing_corridor import checkout_worker, loaded, private_settings, project, provider  # noqa: F401
from .test_processing_pairs_points import ENDS, _points, _single_costs

pytestmark = pytest.mark.qgis


def _table(path: Path) -> dict[str, dict[str, str]]:
    with open(path, newline="") as f:
        return {row.pop("from"): row for row in csv.DictReader(f)}


def _as_gpkg_table(layer, gpkg: Path, table: str) -> str:
    """``layer`` written as ``table`` of ``gpkg`` (beside others); the QGIS source of that table."""
    from qgis.core import QgsProject, QgsVectorFileWriter

    options = QgsVectorFileWriter.SaveVectorOptions()
    options.driverName, options.layerName = "GPKG", table
    if gpkg.exists():
        options.actionOnExistingFile = QgsVectorFileWriter.CreateOrOverwriteLayer
    context = QgsProject.instance().transformContext()
    error = QgsVectorFileWriter.writeAsVectorFormatV3(layer, str(gpkg), context, options)
    assert error[0] == QgsVectorFileWriter.NoError, error
    return f"{gpkg}|layername={table}"


def test_one_to_many_costs_are_the_single_routes_and_the_clis_table(provider, scene, tmp_path: Path) -> None:  # noqa: F811
    import processing

    single = _single_costs(scene, tmp_path)
    starts = _points(scene, 1, "EPSG:4326", ids=True)
    gpkg = tmp_path / "points.gpkg"
    _as_gpkg_table(_points(scene, 1, "EPSG:32633", ids=True), gpkg, "starts")
    goals = _as_gpkg_table(_points(scene, 2, "EPSG:32633", ids=True), gpkg, "goals")  # the second table
    res = processing.run(
        "overseec:costmatrix",
        {
            "COSTMAP": str(scene.costmap),
            "SOURCES": starts,
            "POINTS": goals,
            "MODE": 1,
            "OUTPUT": str(tmp_path / "m.csv"),
        },
    )
    assert (res["ROWS"], res["COLUMNS"], res["UNREACHABLE"]) == (3, 3, 0)
    table = _table(Path(res["OUTPUT"]))
    ids = [e[0] for e in ENDS]
    assert list(table) == ids and all(list(row) == ids for row in table.values())
    for ident in ids:
        assert float(table[ident][ident]) == pytest.approx(single[ident], rel=1e-9)
    # the CLI on the same points (CSV tables in the costmap's CRS) writes the same table
    tables = {}
    for which, name in ((1, "sources.csv"), (2, "points.csv")):
        rows = [f"{e[0]},{x!r},{y!r}" for e in ENDS for x, y in [scene.world(*e[which])]]
        tables[name] = tmp_path / name
        tables[name].write_text("id,x,y\n" + "\n".join(rows) + "\n")
    cli_csv = tmp_path / "cli.csv"
    argv = ["-q", "plan", str(scene.costmap), "--sources", str(tables["sources.csv"])]
    assert cli_main([*argv, "--points", str(tables["points.csv"]), "--matrix", str(cli_csv)]) == 0
    cli = _table(cli_csv)
    for a in ids:
        for b in ids:
            assert float(table[a][b]) == pytest.approx(float(cli[a][b]), rel=1e-9), (a, b)


def test_a_point_outside_the_costmap_fails_in_one_line(provider, scene, tmp_path: Path) -> None:  # noqa: F811
    import processing
    from qgis.core import QgsFeature, QgsGeometry, QgsPointXY, QgsVectorLayer

    far = QgsVectorLayer("Point?crs=EPSG:32633", "far", "memory")
    f = QgsFeature()
    f.setGeometry(QgsGeometry.fromPointXY(QgsPointXY(*scene.world(3, 3))))
    g = QgsFeature()
    g.setGeometry(QgsGeometry.fromPointXY(QgsPointXY(10.0, 10.0)))  # far outside the map
    far.dataProvider().addFeatures([f, g])
    params = {"COSTMAP": str(scene.costmap), "POINTS": far, "OUTPUT": str(tmp_path / "m.csv")}
    with pytest.raises(QgsProcessingException) as err:
        processing.run("overseec:costmatrix", params)
    assert "\n" not in str(err.value).strip() and "outside" in str(err.value)
    assert not (tmp_path / "m.csv").exists()
