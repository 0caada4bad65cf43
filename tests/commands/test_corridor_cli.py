"""`overseec corridor`: ratio + mask GeoTIFFs on the costmap's grid, manifest, one-line errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import rasterio

from overseec_core.cli import EXIT_USER, main
from overseec_core.plan import Planner, load_costmap
from overseec_core.plan.corridor import cost_distance

from ..plan.conftest import smooth_costmap, write_costmap

START = ("500000.75", "3999999.25")  # pixel (1, 1) at 0.5 m from (500000, 4000000)
GOAL = ("500039.25", "3999970.25")  # pixel (59, 78)


@pytest.fixture
def costmap(tmp_path: Path) -> Path:
    cost = smooth_costmap((60, 80), seed=3, lethal_fraction=0.08)
    cost[0:3, 0:3] = 0.5
    cost[-3:, -3:] = 0.5
    cost[10, 10] = np.inf
    return write_costmap(tmp_path / "costmap.tif", cost)


def read(path: Path) -> tuple[np.ndarray, dict]:
    with rasterio.open(path) as ds:
        return ds.read(1), {"crs": ds.crs, "transform": ds.transform, "nodata": ds.nodata, "dtype": ds.dtypes[0]}


def corridor_argv(costmap: Path, out: Path, *extra: str) -> list[str]:
    return ["-q", "corridor", str(costmap), "--start", *START, "--goal", *GOAL, "--out", str(out), *extra]


def test_corridor_writes_ratio_mask_and_manifest(costmap: Path, tmp_path: Path, capsys) -> None:
    out = tmp_path / "out" / "corridor.tif"
    assert main(corridor_argv(costmap, out, "--within", "10", "--json")) == 0
    doc = json.loads(capsys.readouterr().out)
    ratio, meta = read(out)
    mask, mmeta = read(out.with_name("corridor-within.tif"))
    with rasterio.open(costmap) as src:
        assert (meta["crs"], meta["transform"]) == (src.crs, src.transform) == (mmeta["crs"], mmeta["transform"])
    assert meta["dtype"] == "float32" and np.isnan(meta["nodata"]) and mmeta["dtype"] == "uint8"
    # the mask is the threshold of the ratio (a cell at the limit may round either way in float32)
    limit = np.float32(1.10)
    clear = np.isfinite(ratio) & (np.abs(ratio - limit) > 1e-6)
    assert np.array_equal(mask[clear] == 1, ratio[clear] <= limit)
    assert not mask[~np.isfinite(ratio)].any()
    assert doc["cells_within"] == int(mask.sum())
    # 1.0 exactly on the exact route; the optimum is the planned route's cost
    grid = load_costmap(costmap)
    planner = Planner(grid)
    route = planner.plan([(1, 1), (59, 78)])
    assert np.all(ratio[route.pixels[:, 0], route.pixels[:, 1]] == 1.0)
    assert doc["optimum"] == pytest.approx(route.cost, rel=1e-12)
    assert np.isnan(ratio[10, 10])  # lethal: no route passes
    # ratio = (d_start + d_goal) / optimum
    expect = (cost_distance(planner, (1, 1)) + cost_distance(planner, (59, 78))) / route.cost
    np.testing.assert_allclose(ratio[np.isfinite(ratio)], expect[np.isfinite(expect)], rtol=1e-6)
    manifest = json.loads((out.parent / "manifest.json").read_text())
    assert manifest["corridor"]["outputs"] == {"corridor": "corridor.tif", "mask": "corridor-within.tif"}
    assert manifest["parameters"]["corridor"]["within_pct"] == 10.0


def test_mask_out_and_percent_sign(costmap: Path, tmp_path: Path) -> None:
    out, mask = tmp_path / "c.tif", tmp_path / "near.tif"
    assert main(corridor_argv(costmap, out, "--within", "5%", "--mask-out", str(mask))) == 0
    narrow, _ = read(mask)
    assert main(corridor_argv(costmap, tmp_path / "d.tif", "--within", "20")) == 0
    wide, _ = read(tmp_path / "d-within.tif")
    assert narrow.sum() < wide.sum() and np.all(wide[narrow == 1] == 1)  # a wider threshold holds the narrower


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"--goal": ("510039.25", "3999970.25")}, "outside the costmap"),
        ({"--goal": ("500005.25", "3999994.75")}, "lethal"),
        ({"--goal": START}, "same cell"),
    ],
)
def test_bad_points_are_one_line_errors(costmap: Path, tmp_path: Path, capsys, change, message) -> None:
    argv = corridor_argv(costmap, tmp_path / "c.tif", "--within", "10")
    for flag, (x, y) in change.items():
        i = argv.index(flag)
        argv[i + 1 : i + 3] = [x, y]
    assert main(argv) == EXIT_USER
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1
    assert not (tmp_path / "c.tif").exists()


@pytest.mark.parametrize("within", ["0", "-5", "nan", "x"])
def test_within_must_be_positive(costmap: Path, tmp_path: Path, within: str) -> None:
    with pytest.raises(SystemExit) as exc:
        main(corridor_argv(costmap, tmp_path / "c.tif", "--within", within))
    assert exc.value.code == EXIT_USER
