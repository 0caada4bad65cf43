"""Loading costmaps for planning: nodata, the lethal sidecar, thresholds, georeferencing."""

from __future__ import annotations

import numpy as np
import pytest
from rasterio.transform import from_origin

from overseec_core.errors import InputError, PlanError
from overseec_core.plan import PlanningGrid, load_costmap

from .conftest import UTM_ORIGIN, write_costmap, write_lethal


def test_nodata_value_and_nan_become_nan_and_costs_are_float32(tmp_path) -> None:
    cost = np.array([[0.1, -9999.0, 0.3], [0.4, 0.5, 0.6]], dtype=np.float32)
    grid = load_costmap(write_costmap(tmp_path / "c.tif", cost, nodata=-9999.0))
    assert grid.cost.dtype == np.float32 and grid.cost.flags.c_contiguous
    assert np.isnan(grid.cost[0, 1]) and grid.blocked_reason(0, 1) == "nodata"
    assert grid.cost[1, 2] == pytest.approx(0.6)
    assert grid.pixel_size_m == pytest.approx((0.5, 0.5))
    assert grid.lethal_source is None and grid.source.endswith("c.tif")


def test_lethal_sidecar_named_by_the_costmap_tag(tmp_path) -> None:
    cost = np.full((4, 5), 0.2, dtype=np.float32)
    lethal = np.zeros((4, 5), np.uint8)
    lethal[1, 2] = 1
    write_lethal(tmp_path / "mask_for_it.tif", lethal)
    grid = load_costmap(write_costmap(tmp_path / "x.tif", cost, tags={"OVERSEEC_LETHAL_FILE": "mask_for_it.tif"}))
    assert grid.blocked_reason(1, 2) == "lethal" and grid.lethal.sum() == 1
    assert grid.lethal_source.endswith("mask_for_it.tif")


def test_lethal_tif_beside_the_costmap_and_compose_naming(tmp_path) -> None:
    cost = np.full((4, 5), 0.2, dtype=np.float32)
    lethal = np.zeros((4, 5), np.uint8)
    lethal[0, 0] = 1
    write_lethal(tmp_path / "lethal.tif", lethal)
    assert load_costmap(write_costmap(tmp_path / "costmap.tif", cost)).blocked_reason(0, 0) == "lethal"
    other = lethal.copy()
    other[3, 4] = 1
    write_lethal(tmp_path / "b.lethal.tif", other)
    b = load_costmap(write_costmap(tmp_path / "b.tif", cost))
    assert b.lethal.sum() == 2 and b.lethal_source.endswith("b.lethal.tif")


def test_lethal_tif_of_another_costmap_is_not_used(tmp_path) -> None:
    cost = np.full((4, 5), 0.2, dtype=np.float32)
    write_lethal(tmp_path / "lethal.tif", np.ones((4, 5)), tags={"OVERSEEC_COSTMAP_FILE": "costmap.tif"})
    grid = load_costmap(write_costmap(tmp_path / "mine.tif", cost))
    assert grid.lethal_source is None and not grid.lethal.any()


def test_explicit_lethal_on_another_grid_or_missing_is_refused(tmp_path) -> None:
    cost = np.full((4, 5), 0.2, dtype=np.float32)
    path = write_costmap(tmp_path / "c.tif", cost)
    shifted = write_lethal(
        tmp_path / "l.tif", np.zeros((4, 5)), transform=from_origin(UTM_ORIGIN[0] + 1, UTM_ORIGIN[1], 0.5, 0.5)
    )
    with pytest.raises(InputError, match="not on the costmap's grid"):
        load_costmap(path, lethal_path=shifted)
    with pytest.raises(InputError, match="lethal mask not found"):
        load_costmap(path, lethal_path=tmp_path / "nope.tif")
    tagged = write_costmap(tmp_path / "t.tif", cost, tags={"OVERSEEC_LETHAL_FILE": "gone.tif"})
    with pytest.raises(InputError, match="gone.tif.*missing"):
        load_costmap(tagged)


def test_lethal_threshold_and_negative_costs(tmp_path) -> None:
    cost = np.array([[0.1, 0.8, 0.95]], dtype=np.float32)
    grid = load_costmap(write_costmap(tmp_path / "c.tif", cost), lethal_threshold=0.8)
    assert [grid.blocked_reason(0, c) for c in range(3)] == [None, "lethal", "lethal"]
    with pytest.raises(InputError, match="costs must be >= 0"):
        load_costmap(write_costmap(tmp_path / "n.tif", np.array([[0.1, -0.2]], dtype=np.float32)))


def test_world_pixel_round_trip_in_native_and_geographic_crs(tmp_path) -> None:
    grid = load_costmap(write_costmap(tmp_path / "c.tif", np.zeros((20, 30), np.float32)))
    assert grid.world_to_pixel(UTM_ORIGIN[0] + 0.1, UTM_ORIGIN[1] - 0.1) == (0, 0)
    assert grid.world_to_pixel(UTM_ORIGIN[0] + 14.9, UTM_ORIGIN[1] - 9.9) == (19, 29)
    assert grid.world_to_pixel(UTM_ORIGIN[0] - 0.1, UTM_ORIGIN[1]) == (0, -1)  # outside: caller checks
    x, y = grid.pixel_to_world(3, 7)
    assert (x, y) == pytest.approx((UTM_ORIGIN[0] + 3.75, UTM_ORIGIN[1] - 1.75))
    lon, lat = grid.pixel_to_world(3, 7, crs="EPSG:4326")
    assert 14.9 < lon < 15.1 and 36.0 < lat < 36.2  # lon/lat order (always_xy)
    assert grid.world_to_pixel(lon, lat, crs="EPSG:4326") == (3, 7)
    rows, cols = grid.world_to_pixel(np.array([x, x + 1.0]), np.array([y, y]))
    assert rows.tolist() == [3, 3] and cols.tolist() == [7, 9]


def test_bare_arrays_have_no_map_coordinates() -> None:
    grid = PlanningGrid.from_array(np.zeros((3, 3)), lethal=np.eye(3))
    assert grid.lethal.sum() == 3 and grid.pixel_size_m == (1.0, 1.0)
    with pytest.raises(PlanError, match="no georeferencing"):
        grid.world_to_pixel(0.0, 0.0)
    with pytest.raises(InputError, match="2-D"):
        PlanningGrid.from_array(np.zeros(5))
