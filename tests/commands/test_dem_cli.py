"""`overseec costmap --dem`: terrain from a DEM through the command line (and `run --dem`'s flag)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import rasterio
from rasterio.transform import Affine

from overseec_core.cli import EXIT_USER, main
from overseec_core.io.write import write_array

from ..synthesize.test_compose import utm_grid
from ..synthesize.test_terrain import write_dem

PROGRAM = 'cost = where(M["road"], 0.1, 0.5)\ncost = max(cost, normalize(slope, 15, 30))\n'


@pytest.fixture
def scene(tmp_path: Path) -> dict[str, Path]:
    """Labels (a road row band on grass, 1 m pixels, 60 x 40) and a DEM in another CRS and
    resolution: flat west of x = 30 m, a 45 degree ramp east of it, reaching beyond the grid."""
    grid = utm_grid(60, 40, 1.0, 1.0)
    labels = np.full(grid.shape, 2, np.uint8)
    labels[18:22] = 1
    write_array(tmp_path / "gt.tif", labels, grid)
    (tmp_path / "classes.json").write_text(json.dumps({"1": "road", "2": "grass"}))
    # a 0.5 m DEM offset by a quarter of its cell: resampled onto the grid, not copied
    step = 0.5
    t = grid.transform * Affine.translation(-4.25, -4.25) * Affine.scale(step)
    rows, cols = np.mgrid[0:176, 0:256]
    x, _ = t * (cols + 0.5, rows + 0.5)
    x0, _ = grid.transform * (0, 0)
    z = np.maximum(x - x0 - 30.0, 0.0) + 120.0
    dem = write_dem(tmp_path / "dem.tif", z, grid.crs, t)
    prog = tmp_path / "p.txt"
    prog.write_text(PROGRAM)
    return {"dir": tmp_path, "dem": dem, "program": prog}


def _args(scene: dict[str, Path], *extra: str) -> list[str]:
    d = scene["dir"]
    return [
        "-q",
        "costmap",
        "--labels",
        str(d / "gt.tif"),
        "--classes",
        str(d / "classes.json"),
        "--out",
        str(d / "out" / "c.tif"),
        *extra,
    ]


def test_costmap_with_a_dem_mixes_slope_and_semantics(scene, capsys) -> None:
    assert main([*_args(scene, "--program", str(scene["program"]), "--dem", str(scene["dem"])), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["terrain"]["fields"] == ["slope"] and doc["terrain"]["missing_pixels"] == 0
    with rasterio.open(scene["dir"] / "out" / "c.tif") as ds:
        cost = ds.read(1)
        assert ds.tags()["OVERSEEC_DEM_FILE"] == str(scene["dem"])
    assert cost[20, 5] == pytest.approx(0.1) and cost[5, 5] == pytest.approx(0.5)  # flat
    assert cost[20, 50] == pytest.approx(1.0) and cost[5, 50] == pytest.approx(1.0)  # 45 degrees
    manifest = json.loads((scene["dir"] / "out" / "manifest.json").read_text())
    assert manifest["terrain"]["unit"] == "m"
    assert any("dem" in key for key in json.dumps(manifest["inputs"]).split('"'))


def test_a_program_reading_slope_without_dem_is_a_one_line_error(scene, capsys) -> None:
    assert main(_args(scene, "--program", str(scene["program"]))) == EXIT_USER
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--dem" in err and "line 2" in err
    assert not (scene["dir"] / "out" / "c.tif").exists()


def test_a_dem_that_cannot_be_read_is_a_one_line_error(scene, capsys) -> None:
    bad = scene["dir"] / "bad.tif"
    bad.write_text("not a raster")
    assert main(_args(scene, "--program", str(scene["program"]), "--dem", str(bad))) == EXIT_USER
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--dem" in err and "bad.tif" in err
    missing = scene["dir"] / "missing.tif"
    assert main(_args(scene, "--program", str(scene["program"]), "--dem", str(missing))) == EXIT_USER
    assert capsys.readouterr().err.count("\n") == 1


def test_a_dem_covering_part_of_the_grid_says_how_much_is_missing(scene, capsys) -> None:
    grid = utm_grid(60, 40, 1.0, 1.0)
    half = write_dem(scene["dir"] / "half.tif", np.full((40, 30), 5.0), grid.crs, grid.transform)
    assert main([*_args(scene, "--program", str(scene["program"]), "--dem", str(half)), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["terrain"]["missing_pixels"] == 40 * 30
    assert any("50 % of the grid" in w for w in doc["warnings"])
    with rasterio.open(scene["dir"] / "out" / "c.tif") as ds:
        cost = ds.read(1)
    with rasterio.open(scene["dir"] / "out" / "c.lethal.tif") as ds:
        lethal = ds.read(1)
    assert np.isnan(cost[:, 30:]).all() and (lethal[:, 30:] == 1).all()
    assert np.isfinite(cost[:, :30]).all()


def test_a_prompt_with_a_dem_gets_the_slope_term(scene, capsys) -> None:
    args = _args(scene, "--prompt", "prefer the road", "--dem", str(scene["dem"]))
    assert main([*args, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert "normalize(slope, 15, 30)" in doc["program"]
    with rasterio.open(scene["dir"] / "out" / "c.tif") as ds:
        cost = ds.read(1)
    assert cost[5, 50] == pytest.approx(1.0) and cost[20, 5] < 0.5


def test_a_dem_the_program_does_not_read_is_a_warning(scene, capsys) -> None:
    prog = scene["dir"] / "plain.txt"
    prog.write_text('cost = where(M["road"], 0.1, 0.5)\n')
    assert main([*_args(scene, "--program", str(prog), "--dem", str(scene["dem"])), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["terrain"]["used"] is False
    assert any("DEM is not used" in w for w in doc["warnings"])


def test_run_takes_dem() -> None:
    from overseec_core.cli import build_parser

    args = build_parser().parse_args(["run", "img.tif", "--prompt", "p", "--out", "o", "--dem", "d.tif"])
    assert args.dem == Path("d.tif")


def test_run_with_labels_and_a_dem_costs_the_slopes(scene) -> None:
    """`overseec run` passes the DEM to its costmap: the prompt's program gets the slope term."""
    d = scene["dir"]
    rgb = np.zeros((3, 40, 60), np.uint8)
    write_array(d / "image.tif", rgb, utm_grid(60, 40, 1.0, 1.0))
    argv = ["-q", "run", str(d / "image.tif"), "--prompt", "prefer the road", "--offline", "--no-eval"]
    argv += ["--labels", str(d / "gt.tif"), "--classes", str(d / "classes.json"), "--dem", str(scene["dem"])]
    assert main([*argv, "--out", str(d / "run")]) == 0
    with rasterio.open(d / "run" / "costmap.tif") as ds:
        cost = ds.read(1)
    assert cost[5, 50] == pytest.approx(1.0) and cost[20, 5] < 0.5
    assert "normalize(slope, 15, 30)" in (d / "run" / "costmap.program.txt").read_text()
