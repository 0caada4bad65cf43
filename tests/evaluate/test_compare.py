"""`overseec compare` (issue 12, part 4): several prompts on the same layers and points ->
a costmap and route per prompt, a difference raster, a side-by-side figure, route tables."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
import rasterio

from overseec_core import sample
from overseec_core.cli import EXIT_OK, EXIT_USER, main
from overseec_core.errors import InputError
from overseec_core.evaluate import compare as compare_module
from overseec_core.evaluate import compare_report as cmp
from overseec_core.evaluate.compare import (
    CompareOptions,
    class_shares,
    hausdorff_matrix,
    make_candidates,
    route_hausdorff_m,
    sample_pixels,
    write_difference,
)
from overseec_core.evaluate.maps import PlotPath, side_by_side_figure
from overseec_core.io.manifest import sha256_file
from overseec_core.io.read import read_grid
from overseec_core.io.write import write_array
from overseec_core.pipeline import run_compare

from ..synthesize.test_compose import utm_grid, write_mask_dir

ROADS, GRASS = "prefer roads", "prefer grass, avoid roads"
START, GOAL = (534010.0, 5212990.0), (534500.0, 5212500.0)
POINT_ARGS = ["--start", str(START[0]), str(START[1]), "--goal", str(GOAL[0]), str(GOAL[1])]


@pytest.fixture(scope="module")
def scene(tmp_path_factory) -> sample.SampleScene:
    return sample.bundled_sample() or sample.generate(tmp_path_factory.mktemp("sample"))


def options(scene: sample.SampleScene, out: Path, *items: tuple[str, str], **kw) -> CompareOptions:
    return CompareOptions(
        out_dir=out,
        candidates=make_candidates(items),
        points=(START, GOAL),
        labels=scene.labels,
        classes=scene.classes,
        **kw,
    )


@pytest.fixture(scope="module")
def done(scene, tmp_path_factory) -> cmp.CompareResult:
    """One comparison of the road prompt and the grass prompt on the sample labels."""
    out = tmp_path_factory.mktemp("compare") / "out"
    return run_compare(options(scene, out, ("prompt", ROADS), ("prompt", GRASS)), command_args={"test": True})


def read_band(path: Path, band: int = 1) -> np.ndarray:
    with rasterio.open(path) as ds:
        return ds.read(band)


# ------------------------------------------------------------------- the sample, two prompts


def test_the_two_prompts_give_different_routes(done):
    roads, grass = done.rows
    assert (roads.name, roads.prompt, grass.name, grass.prompt) == ("prompt_1", ROADS, "prompt_2", GRASS)
    h = done.hausdorff_m
    assert h[0][0] == h[1][1] == 0.0 and h[0][1] == h[1][0]
    assert h[0][1] > 50.0  # the routes part ways by more than a road's width
    p1 = json.loads((done.out_dir / "prompt_1" / "path.geojson").read_text())
    p2 = json.loads((done.out_dir / "prompt_2" / "path.geojson").read_text())
    assert p1["features"][0]["geometry"] != p2["features"][0]["geometry"]
    assert roads.length_m > 0 and grass.length_m > 0 and roads.cost > 0


def test_the_road_prompt_spends_more_of_its_route_on_road(done):
    roads, grass = done.rows
    assert roads.class_share["road"] > grass.class_share["road"] + 0.2
    assert grass.class_share["grass"] > roads.class_share["grass"]
    for row in done.rows:
        assert sum(row.class_share.values()) == pytest.approx(1.0)
    assert done.classes == ("grass", "road", "trail", "tree", "water", "building", "baseball field")


def test_each_prompt_has_its_costmap_program_and_route_in_its_folder(done):
    for name in ("prompt_1", "prompt_2"):
        folder = done.out_dir / name
        for file in ("costmap.tif", "lethal.tif", "costmap.program.txt", "path.geojson", "manifest.json"):
            assert (folder / file).is_file(), folder / file
    assert 'P["road"]' in (done.out_dir / "prompt_1" / "costmap.program.txt").read_text()
    assert 'P["grass"]' in (done.out_dir / "prompt_2" / "costmap.program.txt").read_text()
    sub = json.loads((done.out_dir / "prompt_1" / "manifest.json").read_text())
    assert sub["parameters"]["costmap"]["prompt"] == ROADS


def test_the_difference_raster_is_cost2_minus_cost1(done):
    diff_path = done.out_dir / "difference.tif"
    c1 = read_band(done.out_dir / "prompt_1" / "costmap.tif")
    c2 = read_band(done.out_dir / "prompt_2" / "costmap.tif")
    with rasterio.open(diff_path) as ds:
        assert ds.count == 1 and ds.dtypes[0] == "float32"
        assert ds.descriptions == ("prompt_2 - prompt_1",)
        diff = ds.read(1)
    assert read_grid(diff_path).same_as(read_grid(done.out_dir / "prompt_1" / "costmap.tif"))
    np.testing.assert_array_equal(np.isnan(diff), np.isnan(c1) | np.isnan(c2))
    np.testing.assert_allclose(diff, c2 - c1, rtol=0, atol=1e-7)
    band = done.difference[0]
    assert band.changed_pixels > 0 and band.min < 0 < band.max
    assert band.mean == pytest.approx(float(np.nanmean(c2 - c1)), abs=1e-5)


def test_the_figure_has_one_panel_per_prompt(done, scene):
    png = done.out_dir / "compare.png"
    assert png.is_file() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    from matplotlib.image import imread

    h, w = imread(png).shape[:2]
    assert w > 1.4 * h  # two panels side by side
    grid = read_grid(done.out_dir / "prompt_1" / "costmap.tif")
    routes = [PlotPath(rows_cols=np.array([[10, 10], [10 + k, 200], [900, 900]])) for k in range(3)]
    costs = [done.out_dir / n / "costmap.tif" for n in ("prompt_1", "prompt_2", "prompt_1")]
    fig, panels = side_by_side_figure(grid, costs, routes, ["one", "two", "a third prompt"])
    assert len(panels) == 3 and [a.get_title() for a in panels] == ["one", "two", "a third prompt"]
    assert all(len(a.lines) == 3 for a in panels)  # its own route and the two others, faint
    assert all(a.artists for a in panels)  # the scale bar
    fig4, panels4 = side_by_side_figure(grid, costs + costs[:1], routes + routes[:1], list("abcd"))
    assert len(panels4) == 4


def test_csv_and_json_columns(done):
    with open(done.out_dir / "compare.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    shares = [f"share_{c}" for c in done.classes]
    assert list(rows[0]) == (
        ["name", "kind", "prompt", "length_m", "cost", "cost_per_m", "n_pixels", "mode"]
        + shares
        + ["hausdorff_m_prompt_1", "hausdorff_m_prompt_2"]
    )
    assert [r["prompt"] for r in rows] == [ROADS, GRASS]
    assert float(rows[0]["share_road"]) > float(rows[1]["share_road"])
    assert float(rows[0]["hausdorff_m_prompt_2"]) == pytest.approx(done.hausdorff_m[0][1], abs=1e-3)
    data = json.loads((done.out_dir / "compare.json").read_text())
    assert set(data) >= {"prompts", "pairs", "hausdorff_m", "difference", "points", "classes", "files"}
    assert set(data["prompts"][0]) >= {
        "name",
        "kind",
        "prompt",
        "length_m",
        "cost",
        "cost_per_m",
        "class_share",
        "costmap",
        "route",
        "program_file",
    }
    assert data["prompts"][0]["route"] == "prompt_1/path.geojson"
    assert data["pairs"] == [{"a": "prompt_1", "b": "prompt_2", "hausdorff_m": done.hausdorff_m[0][1]}]
    report = (done.out_dir / "report.md").read_text()
    assert ROADS in report and GRASS in report and "![" in report and "compare.png" in report
    assert "| prompt_1 |" in report and "Hausdorff" in report


def test_the_manifest_records_prompts_hashed_inputs_and_outputs(done, scene):
    m = json.loads((done.out_dir / "manifest.json").read_text())
    assert m["commands"][-1]["command"] == "compare"
    prompts = m["parameters"]["compare"]["prompts"]
    assert [(p["kind"], p["value"]) for p in prompts] == [("prompt", ROADS), ("prompt", GRASS)]
    hashes = {Path(v["path"]).name: v["sha256"] for v in m["inputs"].values()}
    assert hashes["sample_labels.tif"] == sha256_file(scene.labels)
    assert hashes["classes.json"] == sha256_file(scene.classes)
    assert set(m["compare"]["outputs"].values()) == {
        "difference.tif",
        "compare.png",
        "compare.csv",
        "compare.json",
        "report.md",
    }
    assert m["stages"]["compare"]["status"] == "ok"


# ------------------------------------------------------------------- refusals


@pytest.mark.parametrize("second", [ROADS, "  Prefer   ROADS. "])
def test_identical_prompts_are_refused(scene, tmp_path, second):
    with pytest.raises(InputError, match="prompt_2 repeats prompt_1"):
        run_compare(options(scene, tmp_path / "out", ("prompt", ROADS), ("prompt", second)))
    assert not (tmp_path / "out").exists()


def test_identical_programs_are_refused(scene, tmp_path):
    a, b = tmp_path / "a.txt", tmp_path / "b.txt"
    a.write_text('cost = 0.5 - 0.5 * P["road"]\n')
    b.write_text('cost = 0.5 - 0.5 * P["road"]\n\n')
    with pytest.raises(InputError, match="repeats"):
        run_compare(options(scene, tmp_path / "out", ("program", str(a)), ("program", str(b))))


def test_fewer_than_two_prompts_no_points_and_out_equal_to_an_input_are_refused(scene, tmp_path):
    with pytest.raises(InputError, match="at least two"):
        run_compare(options(scene, tmp_path / "o", ("prompt", ROADS)))
    no_points = CompareOptions(
        out_dir=tmp_path / "o",
        candidates=make_candidates([("prompt", ROADS), ("prompt", GRASS)]),
        points=(),
        labels=scene.labels,
        classes=scene.classes,
    )
    with pytest.raises(InputError, match="no points"):
        run_compare(no_points)
    masks = tmp_path / "masks"
    masks.mkdir()
    with pytest.raises(InputError, match="is the input --masks"):
        run_compare(options(scene, masks, ("prompt", ROADS), ("prompt", GRASS), masks=masks))
    prog = tmp_path / "o" / "report.md"
    prog.parent.mkdir()
    prog.write_text('cost = 0.5 - 0.5 * P["road"]\n')
    with pytest.raises(InputError, match="where compare writes report.md"):
        run_compare(options(scene, tmp_path / "o", ("prompt", ROADS), ("program", str(prog))))


def test_a_failing_prompt_is_named_and_leaves_the_folder_as_it_was(scene, tmp_path):
    out = tmp_path / "out"
    with pytest.raises(InputError, match=r"^prompt_2 \('hello there'\): .*no preference"):
        run_compare(options(scene, out, ("prompt", ROADS), ("prompt", "hello there")))
    assert not out.exists()  # nothing written, not even the folders


def test_prompts_and_programs_mix_in_order_and_equal_programs_are_noted(scene, tmp_path, done):
    prog = tmp_path / "roads.program.txt"
    prog.write_text((done.out_dir / "prompt_1" / "costmap.program.txt").read_text())
    res = run_compare(options(scene, tmp_path / "out", ("program", str(prog)), ("prompt", ROADS), ("prompt", GRASS)))
    assert [r.kind for r in res.rows] == ["program", "prompt", "prompt"]
    assert res.rows[0].prompt == "program roads.program.txt"
    assert res.hausdorff_m[0][1] == 0.0 and res.hausdorff_m[0][2] > 50
    assert any("prompt_2 and prompt_1 give the same cost program" in n for n in res.notes)
    with rasterio.open(res.files["difference"]) as ds:
        assert ds.count == 2 and ds.descriptions == ("prompt_2 - prompt_1", "prompt_3 - prompt_1")
        assert np.nanmax(np.abs(ds.read(1))) == 0.0


def test_a_segment_folder_and_lonlat_points(tmp_path):
    """--masks as `overseec costmap` takes it, points in another CRS, no class shares."""
    from pyproj import Transformer

    grid = utm_grid(120, 80)
    road = np.zeros(grid.shape, bool)
    road[10:14] = True
    road[:, 100:104] = True
    water = np.zeros(grid.shape, bool)
    water[30:60, 30:60] = True
    run = write_mask_dir(
        tmp_path / "run",
        grid,
        {"road": road, "grass": ~(road | water), "water": water},
        {"road": np.full(grid.shape, 0.9), "grass": np.full(grid.shape, 0.6), "water": np.full(grid.shape, 0.8)},
    )
    to_lonlat = Transformer.from_crs("EPSG:32633", "EPSG:4326", always_xy=True)
    start = to_lonlat.transform(500000 + 2.25, 4000000 - 35.25)
    goal = to_lonlat.transform(500000 + 57.75, 4000000 - 37.75)
    res = run_compare(
        CompareOptions(
            out_dir=tmp_path / "out",
            candidates=make_candidates([("prompt", "prefer roads, never enter the water"), ("prompt", "avoid roads")]),
            points=(start, goal),
            crs="EPSG:4326",
            masks=run,
            mode="fast",
        )
    )
    assert res.rows[0].length_m > res.rows[1].length_m and res.hausdorff_m[0][1] > 10
    assert res.classes == () and all(r.class_share is None for r in res.rows)
    with open(res.files["csv"], newline="") as f:
        assert not any(c.startswith("share_") for c in next(csv.reader(f)))
    m = json.loads(res.manifest.read_text())
    hashes = {Path(v["path"]).name: v["sha256"] for v in m["inputs"].values()}
    assert hashes["masks.tif"] == sha256_file(run / "masks.tif")
    assert hashes["probs.tif"] == sha256_file(run / "probs.tif")


# ------------------------------------------------------------------- the pieces


def test_route_hausdorff_is_zero_for_equal_routes_and_the_offset_otherwise():
    a = np.array([[5, c] for c in range(20)])
    assert route_hausdorff_m(a, a, (0.5, 0.5)) == 0.0
    assert route_hausdorff_m(a, a + [3, 0], (0.5, 0.5)) == pytest.approx(1.5)
    assert route_hausdorff_m(a, a + [0, 2], (0.5, 2.0)) == pytest.approx(1.0)  # x metres
    detour = np.array([[5, 0], [5, 5], [1, 9], [5, 13], [5, 19]])
    assert route_hausdorff_m(a, detour, (1.0, 1.0)) == pytest.approx(4.0)
    m = hausdorff_matrix([a, a + [3, 0], a], (1.0, 1.0))
    assert m == ((0.0, 3.0, 0.0), (3.0, 0.0, 3.0), (0.0, 3.0, 0.0))


def test_class_shares_count_unnamed_and_nodata_as_other():
    ids = np.array([1, 1, 2, 9, 0])
    valid = np.array([True, True, True, True, False])
    assert class_shares(ids, valid, {2: "road", 1: "grass"}) == {"grass": 0.4, "road": 0.2, "(other)": 0.4}
    assert "(other)" not in class_shares(ids[:3], valid[:3], {1: "grass", 2: "road"})


def test_sample_pixels_reads_strips_and_matches_the_array(tmp_path, monkeypatch):
    grid = utm_grid(70, 50)
    data = np.arange(50 * 70, dtype=np.int32).reshape(50, 70) % 7
    data[3, 4] = 0
    path = write_array(tmp_path / "l.tif", data, grid, nodata=0)
    monkeypatch.setattr(compare_module, "SAMPLE_STRIP_ROWS", 8)
    pixels = np.array([[3, 4], [49, 69], [0, 0], [20, 33], [21, 2], [20, 33]])
    values, valid = sample_pixels(path, pixels)
    np.testing.assert_array_equal(values, data[pixels[:, 0], pixels[:, 1]])
    np.testing.assert_array_equal(valid, data[pixels[:, 0], pixels[:, 1]] != 0)


def test_write_difference_block_by_block_equals_the_whole(tmp_path):
    grid = utm_grid(45, 37)
    rng = np.random.default_rng(4)
    costs = [rng.random(grid.shape).astype(np.float32) for _ in range(3)]
    costs[1][5, 5] = np.nan
    paths = [write_array(tmp_path / f"c{k}.tif", c, grid, nodata=float("nan")) for k, c in enumerate(costs)]
    bands = write_difference(paths, ["a", "b", "c"], tmp_path / "d.tif", block_size=16)
    for k in (1, 2):
        got = read_band(tmp_path / "d.tif", k)
        want = costs[k] - costs[0]
        np.testing.assert_array_equal(np.isnan(got), np.isnan(want))
        np.testing.assert_allclose(got[~np.isnan(got)], want[~np.isnan(want)], atol=1e-7)
        assert bands[k - 1].valid_pixels == int(np.isfinite(want).sum())
        assert bands[k - 1].max == pytest.approx(float(np.nanmax(want)))


# ------------------------------------------------------------------- the command line


def test_cli_compares_and_exits_0(scene, tmp_path, capsys):
    out = tmp_path / "cli"
    code = main(
        [
            "-q",
            "compare",
            "--labels",
            str(scene.labels),
            "--classes",
            str(scene.classes),
            "--prompt",
            ROADS,
            "--prompt",
            GRASS,
            *POINT_ARGS,
            "--out",
            str(out),
        ]
    )
    assert code == EXIT_OK
    text = capsys.readouterr().out
    assert "prompt_1:" in text and "hausdorff prompt_1 - prompt_2" in text
    assert (out / "compare.csv").is_file() and (out / "difference.tif").is_file()


@pytest.mark.parametrize(
    "args, message",
    [
        (["--prompt", ROADS, "--prompt", ROADS, *POINT_ARGS], "repeats"),
        (["--prompt", ROADS, *POINT_ARGS], "at least two"),
        (["--prompt", ROADS, "--prompt", GRASS], "no points"),
        (["--prompt", ROADS, "--prompt", GRASS, "--start", "534010", "5212990"], "both --start"),
    ],
)
def test_cli_refusals_exit_2_with_one_line(scene, tmp_path, capsys, args, message):
    code = main(
        [
            "-q",
            "compare",
            "--labels",
            str(scene.labels),
            "--classes",
            str(scene.classes),
            *args,
            "--out",
            str(tmp_path / "cli"),
        ]
    )
    assert code == EXIT_USER
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1
    assert not (tmp_path / "cli").exists()


def test_cli_refuses_out_equal_to_the_labels(scene, tmp_path, capsys):
    code = main(
        [
            "-q",
            "compare",
            "--labels",
            str(scene.labels),
            "--classes",
            str(scene.classes),
            "--prompt",
            ROADS,
            "--prompt",
            GRASS,
            *POINT_ARGS,
            "--out",
            str(scene.labels),
        ]
    )
    assert code == EXIT_USER
    assert "is the input --labels" in capsys.readouterr().err
