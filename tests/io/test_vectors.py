"""The one vector reader (overseec_core.io.vectors): errors, CRS handling, the geometry filter."""

from __future__ import annotations

import json
from pathlib import Path

import fiona
import pytest
import shapely.geometry
from rasterio.crs import CRS

from overseec_core.errors import InputError
from overseec_core.io.vectors import read_vector

UTM = CRS.from_epsg(32633)


def _geojson(path: Path, geometries: list[dict | None], crs: str | None = None) -> Path:
    doc: dict = {
        "type": "FeatureCollection",
        "features": [{"type": "Feature", "properties": {"k": i}, "geometry": g} for i, g in enumerate(geometries)],
    }
    if crs:
        doc["crs"] = {"type": "name", "properties": {"name": crs}}
    path.write_text(json.dumps(doc))
    return path


def test_missing_unreadable_and_crs_less_files_are_one_line_input_errors(tmp_path: Path) -> None:
    with pytest.raises(InputError, match=r"^--vector: no such file: .*none\.gpkg$"):
        read_vector(tmp_path / "none.gpkg", UTM, label="--vector")
    junk = tmp_path / "junk.gpkg"
    junk.write_text("nonsense")
    with pytest.raises(InputError, match=r"^--vector .*junk\.gpkg: not a readable vector layer \(") as err:
        read_vector(junk, UTM, label="--vector")
    assert "\n" not in str(err.value)
    with pytest.raises(InputError, match="not a readable vector file"):
        read_vector(junk, UTM, label="reference path", noun="file")
    shp = tmp_path / "nocrs.shp"
    with fiona.open(shp, "w", driver="ESRI Shapefile", schema={"geometry": "Point", "properties": {}}) as dst:
        dst.write({"geometry": {"type": "Point", "coordinates": (1.0, 2.0)}, "properties": {}})
    with pytest.raises(InputError, match="has no CRS"):
        read_vector(shp, UTM, label="--override")
    (feature,) = read_vector(shp, CRS.from_epsg(4326), label="paths", assume_crs="EPSG:4326")
    assert feature.geometry.coords[0] == pytest.approx((1.0, 2.0))


def test_features_are_reprojected_and_filtered_by_type(tmp_path: Path) -> None:
    line = {"type": "LineString", "coordinates": [[15.0, 0.0], [15.001, 0.001]]}
    point = {"type": "Point", "coordinates": [15.0, 0.0]}
    path = _geojson(tmp_path / "f.geojson", [point, None, line], crs="EPSG:4326")
    everything = read_vector(path, UTM, label="--vector")
    assert [f.geometry is None for f in everything] == [False, True, False]
    assert [f.properties["k"] for f in everything] == [0, 1, 2]
    # 15 E on the equator is UTM 33N's central meridian: x = 500 km, y = 0
    assert everything[0].geometry.coords[0] == pytest.approx((500000.0, 0.0), abs=1e-6)
    (only,) = read_vector(path, UTM, label="--vector", geometry_types={"LineString"})
    assert only.index == 2 and only.geometry.geom_type == "LineString"
    assert shapely.geometry.mapping(only.geometry)["coordinates"][0] == pytest.approx((500000.0, 0.0), abs=1e-6)


def test_too_many_features_are_refused_before_reading(tmp_path: Path) -> None:
    point = {"type": "Point", "coordinates": [15.0, 0.0]}
    path = _geojson(tmp_path / "many.geojson", [point] * 3, crs="EPSG:4326")
    assert len(read_vector(path, UTM, label="--override", max_features=3)) == 3
    with pytest.raises(InputError, match="3 features; at most 2 are allowed"):
        read_vector(path, UTM, label="--override", max_features=2)
