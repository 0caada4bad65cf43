"""Start/goal pairs from QGIS layers, read in the costmap's CRS (overseec_qgis/pairsfile.py).

The pairs come back in the target CRS whatever CRS their layer is in; a layer without a CRS is
taken to be in the target CRS; points pair by id when both layers have one, else by order.
"""

from __future__ import annotations

import pytest
from qgis.core import (
    QgsCoordinateReferenceSystem,
    QgsCoordinateTransform,
    QgsFeature,
    QgsGeometry,
    QgsPointXY,
    QgsProject,
    QgsVectorLayer,
)

from overseec_core.errors import InputError
from overseec_qgis import pairsfile

pytestmark = pytest.mark.qgis

UTM = QgsCoordinateReferenceSystem("EPSG:32633")
WGS84 = QgsCoordinateReferenceSystem("EPSG:4326")
#: start/goal pairs in UTM 33N (metres), near the sample scene
PAIRS = [((534100.0, 5212900.0), (534400.0, 5212600.0), "a"), ((534050.0, 5212500.0), (534480.0, 5212950.0), "b")]


def _to_wgs84(x: float, y: float) -> QgsPointXY:
    return QgsCoordinateTransform(UTM, WGS84, QgsProject.instance()).transform(QgsPointXY(x, y))


def _to_utm(layer: QgsVectorLayer):
    return pairsfile.transform_to(layer, UTM, QgsProject.instance().transformContext())


def _lines(crs: str, points) -> QgsVectorLayer:
    layer = QgsVectorLayer(
        f"LineString?crs={crs}&field=id:string" if crs else "LineString?field=id:string", "l", "memory"
    )
    for s, g, ident in points:
        f = QgsFeature(layer.fields())
        f.setGeometry(QgsGeometry.fromPolylineXY([s, g]))
        f["id"] = ident
        layer.dataProvider().addFeature(f)
    return layer


def _points(crs: str, points, with_id: bool) -> QgsVectorLayer:
    layer = QgsVectorLayer(f"Point?crs={crs}" + ("&field=id:string" if with_id else ""), "p", "memory")
    for p, ident in points:
        f = QgsFeature(layer.fields())
        f.setGeometry(QgsGeometry.fromPointXY(p))
        if with_id:
            f["id"] = ident
        layer.dataProvider().addFeature(f)
    return layer


def _close(got, want_xy, tol: float = 1e-3) -> bool:
    return abs(got.x() - want_xy[0]) < tol and abs(got.y() - want_xy[1]) < tol


def _check(pairs) -> None:
    assert [i for i, _s, _g in pairs] == [i for _s, _g, i in PAIRS]
    for (_i, s, g), (ws, wg, _w) in zip(pairs, PAIRS):
        assert _close(s, ws) and _close(g, wg), (s, g)


def test_lines_in_lon_lat_come_back_in_the_costmaps_crs() -> None:
    layer = _lines("EPSG:4326", [(_to_wgs84(*s), _to_wgs84(*g), i) for s, g, i in PAIRS])
    _check(pairsfile.line_pairs(layer, _to_utm(layer)))


def test_lines_without_a_crs_are_taken_as_the_costmaps() -> None:
    layer = _lines("", [(QgsPointXY(*s), QgsPointXY(*g), i) for s, g, i in PAIRS])
    layer.setCrs(QgsCoordinateReferenceSystem())  # a memory layer defaults to EPSG:4326
    assert not layer.crs().isValid()
    _check(pairsfile.line_pairs(layer, _to_utm(layer)))


def test_point_layers_pair_by_id_across_crss() -> None:
    """Starts in lon/lat listed in reverse, goals in UTM: paired by id, all in UTM."""
    starts = _points("EPSG:4326", [(_to_wgs84(*s), i) for s, _g, i in reversed(PAIRS)], with_id=True)
    goals = _points("EPSG:32633", [(QgsPointXY(*g), i) for _s, g, i in PAIRS], with_id=True)
    pairs = pairsfile.point_pairs(starts, goals, _to_utm(starts), _to_utm(goals))
    _check(sorted(pairs, key=lambda p: p[0]))


def test_point_layers_without_ids_pair_by_order_and_must_match_in_count() -> None:
    starts = _points("EPSG:4326", [(_to_wgs84(*s), i) for s, _g, i in PAIRS], with_id=False)
    goals = _points("EPSG:4326", [(_to_wgs84(*g), i) for _s, g, i in PAIRS], with_id=False)
    pairs = pairsfile.point_pairs(starts, goals, _to_utm(starts), _to_utm(goals))
    assert [i for i, _s, _g in pairs] == ["1", "2"]
    for (_i, s, g), (ws, wg, _w) in zip(pairs, PAIRS):
        assert _close(s, ws) and _close(g, wg)
    one_goal = _points("EPSG:4326", [(_to_wgs84(*PAIRS[0][1]), "a")], with_id=False)
    with pytest.raises(InputError, match="2 start points but 1 goal points"):
        pairsfile.point_pairs(starts, one_goal, _to_utm(starts), _to_utm(one_goal))
