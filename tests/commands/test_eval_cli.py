"""`overseec eval`: one-line errors, IoU-only runs, and full runs with the real planner."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from rasterio.transform import from_origin

from overseec_core.cli import EXIT_USER, main
from overseec_core.io.grid import Grid
from overseec_core.io.write import write_array

from ..conftest import write_tif
from ..evaluate.test_evaluate import utm_grid, write_classes, write_lines

OVERSEEC = Path(sys.executable).with_name("overseec")


def _planner_available() -> bool:
    try:
        from overseec_core.plan import Planner, load_costmap  # noqa: F401
    except ImportError:
        return False
    return True


needs_planner = pytest.mark.skipif(
    not _planner_available(), reason="overseec_core.plan (Planner, load_costmap) is not importable yet"
)

ROAD_ROW, ROAD_COL = 30, 40


def scene(tmp_path: Path, road_cost: float = 0.05, grass_cost: float = 0.5) -> dict[str, Path]:
    """80 x 60 px at 1 m: grass, a road cross, a water ring (nodata) enclosing a grass island."""
    grid = utm_grid(80, 60)
    labels = np.full((60, 80), 2, dtype=np.uint8)
    labels[ROAD_ROW, :] = 1
    labels[:, ROAD_COL] = 1
    labels[2:22, 2:22] = 3  # water ring, 20 x 20 ...
    labels[5:19, 5:19] = 2  # ... around a 14 x 14 island of grass nobody can reach
    cost = np.where(labels == 1, road_cost, grass_cost).astype(np.float32)
    cost[labels == 3] = np.nan
    return {
        "labels": write_array(tmp_path / "labels.tif", labels, grid),
        "costmap": write_array(tmp_path / f"cost_{road_cost}_{grass_cost}.tif", cost, grid, nodata=float("nan")),
        "classes": write_classes(tmp_path / "classes.json"),
        "reference": write_lines(tmp_path / "ref.geojson", grid, [[(ROAD_ROW, 30), (ROAD_ROW, 79)]]),
        "image": write_array(
            tmp_path / "image.tif", np.stack([labels * 60, labels * 30, 255 - labels * 50]).astype(np.uint8), grid
        ),
    }


def _err(capsys) -> str:
    err = capsys.readouterr().err
    assert err.startswith("overseec: error: ") and err.count("\n") == 1 and "Traceback" not in err
    return err


# ---------------------------------------------------------------------------------- errors


def test_unknown_class_in_ranks(tmp_path: Path, capsys) -> None:
    s = scene(tmp_path)
    argv = [
        "eval",
        "--labels",
        str(s["labels"]),
        "--classes",
        str(s["classes"]),
        "--ranks",
        "road=1,gravel=2",
        "--costmap",
        str(s["costmap"]),
        "--out",
        str(tmp_path / "out"),
    ]
    assert main(argv) == EXIT_USER
    err = _err(capsys)
    assert "unknown class 'gravel'" in err and "2=grass" in err


def test_grids_differ(tmp_path: Path, capsys) -> None:
    s = scene(tmp_path)
    other = write_tif(
        tmp_path / "cost_small.tif", np.ones((20, 20), np.float32), transform=from_origin(500000.0, 4000000.0, 1.0, 1.0)
    )
    argv = [
        "eval",
        "--labels",
        str(s["labels"]),
        "--classes",
        str(s["classes"]),
        "--ranks",
        "road=1",
        "--costmap",
        str(other),
        "--out",
        str(tmp_path / "out"),
    ]
    assert main(argv) == EXIT_USER
    assert "different grids (20x20 vs 80x60 px)" in _err(capsys)
    argv = [
        "eval",
        "--labels",
        str(s["labels"]),
        "--classes",
        str(s["classes"]),
        "--masks",
        str(other),
        "--out",
        str(tmp_path / "out"),
    ]
    assert main(argv) == EXIT_USER
    assert "different grids" in _err(capsys)


@pytest.mark.parametrize(
    "extra, match",
    [
        ([], "nothing to evaluate"),
        (["--masks", "{labels}", "--match", "road=x"], "--masks needs --labels"),
        (["--costmap", "{costmap}", "--ranks", "road=1"], "--ranks needs --labels"),
        (["--costmap", "{costmap}", "--pairs", "-3"], "--pairs must be >= 0"),
        (["--costmap", "{costmap}", "--reference", "{missing}"], "no such file for --reference"),
        (
            ["--costmap", "{costmap}", "--pair-draw", "image", "--min-separation", "5"],
            "the paper's image draw keeps no separation",
        ),
        (["--costmap", "{costmap}", "--out", "{classes}"], "is not a directory"),
        (["--labels", "{labels}", "--classes", "{classes}", "--masks", "{labels}", "--match", "road-x"], "CLASS=BAND"),
        (
            ["--labels", "{labels}", "--classes", "{classes}", "--masks", "{labels}", "--match", "road=x"],
            "single-band class raster",
        ),
    ],
)
def test_bad_option_combinations(tmp_path: Path, capsys, extra: list[str], match: str) -> None:
    s = {k: str(v) for k, v in scene(tmp_path).items()} | {"missing": str(tmp_path / "nope.geojson")}
    argv = ["eval", "--out", str(tmp_path / "out")] + [a.format(**s) for a in extra]
    assert main(argv) == EXIT_USER
    assert match in _err(capsys)


def test_iou_only_run_in_a_subprocess(tmp_path: Path) -> None:
    s = scene(tmp_path)
    out = tmp_path / "iou"
    proc = subprocess.run(
        [
            str(OVERSEEC),
            "--quiet",
            "eval",
            "--labels",
            str(s["labels"]),
            "--classes",
            str(s["classes"]),
            "--masks",
            str(s["labels"]),
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr
    assert "mean IoU: 1.0000" in proc.stdout
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["iou"]["mean_iou"] == 1.0 and (out / "iou.png").is_file()
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["stages"]["evaluate"]["status"] == "ok"
    assert "sha256" in manifest["inputs"]["eval_labels"]


# ---------------------------------------------------------------------------------- with the planner


def geojson_pixels(feature: dict, grid: Grid) -> np.ndarray:
    """(row, col) of the vertices of a WGS 84 LineString on ``grid``."""
    from pyproj import Transformer

    lon, lat = np.array(feature["geometry"]["coordinates"]).T
    xs, ys = Transformer.from_crs("EPSG:4326", grid.crs.to_wkt(), always_xy=True).transform(lon, lat)
    cols, rows = ~grid.transform * (np.asarray(xs), np.asarray(ys))
    return np.column_stack([np.floor(rows), np.floor(cols)]).astype(int)


@needs_planner
def test_eval_end_to_end_with_the_planner(tmp_path: Path, capsys) -> None:
    s = scene(tmp_path)
    out = tmp_path / "out"
    argv = [
        "--quiet",
        "eval",
        "--labels",
        str(s["labels"]),
        "--classes",
        str(s["classes"]),
        "--ranks",
        "road=1,grass=2",
        "--unranked-rank",
        "5",
        "--costmap",
        str(s["costmap"]),
        "--pairs",
        "30",
        "--seed",
        "3",
        "--min-separation",
        "15",
        "--reference",
        str(s["reference"]),
        "--image",
        str(s["image"]),
        "--out",
        str(out),
    ]
    assert main(argv) == 0
    printed = capsys.readouterr().out
    assert "KDE centre of mass" in printed and "report:" in printed
    m = json.loads((out / "metrics.json").read_text())
    sampling = m["sampling"]
    assert sampling["drawn"] == 30 and sampling["planned"] + len(sampling["unreachable"]) == 30
    assert sampling["unreachable"], "the seed should draw pairs on the walled-off island"
    for u in sampling["unreachable"]:
        assert u["error"] and {"row", "col", "x", "y"} <= set(u["start"])
    sampled = [p for p in m["paths"] if p["group"] == "sampled"]
    assert len(sampled) == sampling["planned"]
    gj = {f["properties"]["name"]: f for f in json.loads((out / "paths.geojson").read_text())["features"]}
    import rasterio

    with rasterio.open(s["labels"]) as ds:
        labels = ds.read(1)
    for p in sampled:
        assert p["length_m"] >= 15.0 * 0.999 and p["cost"] > 0
        # the pixels written to paths.geojson give back the RRPI in metrics.json (road 0, grass 1)
        pix = geojson_pixels(gj[p["name"]], utm_grid(80, 60))
        assert len(pix) == p["pixels"]
        cls = labels[pix[:, 0], pix[:, 1]]
        assert not (cls == 3).any(), "a path crossed the water"
        assert p["rrpi"] == int((cls == 2).sum())
    kde, fit = m["kde"], m["fit"]
    assert kde["n"] == len(sampled) and kde["com"]["length_m"] > 0 and fit["n"] == len(sampled)
    assert np.isfinite(fit["slope"])
    # the plan between the reference's ends follows the road it was drawn on
    h = m["hausdorff"]
    assert h["paths"] == "reference-ends" and h["n"] == 1 and h["mean_m"] <= 1.0 + 1e-6
    for name in ("rrpi_vs_length.png", "paths_overlay.png", "report.md", "pairs.csv", "manifest.json"):
        assert (out / name).is_file()
    assert "![RRPI vs path length](rrpi_vs_length.png)" in (out / "report.md").read_text()


@needs_planner
def test_the_papers_draw_is_uniform_over_the_image_and_reports_pairs_on_impassable_cells(tmp_path: Path) -> None:
    s = scene(tmp_path)
    out = tmp_path / "out"
    argv = ["--quiet", "eval", "--costmap", str(s["costmap"]), "--pair-draw", "image", "--seed", "2", "--out", str(out)]
    assert main(argv) == 0
    sampling = json.loads((out / "metrics.json").read_text())["sampling"]
    assert sampling["draw"] == "image" and sampling["min_separation_m"] is None
    # 50 pairs as the paper draws them; over the whole image, some land on the water ring or the
    # walled-off island, and are reported unreachable instead of being redrawn
    assert sampling["drawn"] == 50 and sampling["planned"] + len(sampling["unreachable"]) == 50
    assert sampling["unreachable"] and sampling["planned"] > 25
    report = (out / "report.md").read_text()
    assert "drawn uniformly over the image, as the paper draws them" in report
    # the passable draw never lands on the water
    assert main(["--quiet", "eval", "--costmap", str(s["costmap"]), "--seed", "2", "--out", str(tmp_path / "o2")]) == 0
    other = json.loads((tmp_path / "o2" / "metrics.json").read_text())["sampling"]
    assert other["draw"] == "passable" and all("passable" not in u["error"] for u in other["unreachable"])


@needs_planner
def test_seeded_runs_repeat_and_costmaps_are_told_apart(tmp_path: Path) -> None:
    """Same seed, same pairs; a road-preferring costmap scores a lower RRPI than a road-avoiding one."""
    prefer = scene(tmp_path, road_cost=0.02, grass_cost=0.6)
    avoid = scene(tmp_path, road_cost=0.9, grass_cost=0.1)
    com = {}
    for name, s in (("prefer", prefer), ("avoid", avoid), ("again", prefer)):
        argv = [
            "--quiet",
            "eval",
            "--labels",
            str(s["labels"]),
            "--classes",
            str(s["classes"]),
            "--ranks",
            "road=1,grass=2",
            "--costmap",
            str(s["costmap"]),
            "--pairs",
            "20",
            "--seed",
            "11",
            "--no-plots",
            "--out",
            str(tmp_path / name),
        ]
        assert main(argv) == 0
        com[name] = json.loads((tmp_path / name / "metrics.json").read_text())
    pairs = [
        [(p["start"]["row"], p["start"]["col"]), (p["goal"]["row"], p["goal"]["col"])] for p in com["prefer"]["paths"]
    ]
    assert pairs == [
        [(p["start"]["row"], p["start"]["col"]), (p["goal"]["row"], p["goal"]["col"])] for p in com["again"]["paths"]
    ]
    assert com["prefer"]["paths"] == com["again"]["paths"]
    assert com["prefer"]["kde"]["com"]["rrpi"] < com["avoid"]["kde"]["com"]["rrpi"]
    assert not (tmp_path / "prefer" / "rrpi_vs_length.png").exists()


@needs_planner
def test_given_paths_are_priced_and_cancellation_publishes_nothing(tmp_path: Path, capsys) -> None:
    s = scene(tmp_path)
    grid = utm_grid(80, 60)
    # "road run" ends 2 m short of the reference's end (within the 3 m tolerance): the same pair
    paths = write_lines(
        tmp_path / "mine.geojson",
        grid,
        [[(ROAD_ROW, 30), (ROAD_ROW, 77)], [(10, 30), (10, 0)]],
        epsg=32633,
        names=["road run", "swim"],
    )
    out = tmp_path / "given"
    assert (
        main(
            [
                "--quiet",
                "eval",
                "--labels",
                str(s["labels"]),
                "--classes",
                str(s["classes"]),
                "--ranks",
                "road=1,grass=2,water=3",
                "--costmap",
                str(s["costmap"]),
                "--pairs",
                "0",
                "--paths",
                str(paths),
                "--reference",
                str(s["reference"]),
                "--out",
                str(out),
            ]
        )
        == 0
    )
    m = json.loads((out / "metrics.json").read_text())
    by = {p["name"]: p for p in m["paths"]}
    # 47 road steps of 1 m at cost 0.05 plus the planner's base cost per metre
    from overseec_core.plan import DEFAULT_BASE_COST_PER_M

    assert by["road run"]["cost"] == pytest.approx(47 * (0.05 + DEFAULT_BASE_COST_PER_M))
    assert by["road run"]["rrpi"] == 0 and by["road run"]["hausdorff"]["directed_m"] == pytest.approx(0, abs=1e-6)
    assert by["swim"]["cost"] is None and any("'swim' crosses impassable" in n for n in m["notes"])
    # "swim" starts and ends far from the reference's ends: not measured against it
    assert by["swim"]["hausdorff"] is None and by["swim"]["hausdorff_references"] == []
    h = m["hausdorff"]
    assert h["paths"] == "given" and h["n"] == 1 and h["matched"]["given"] == {"matched": 1, "paths": 2}
    assert m["summary"]["reference"]["mean_rrpi"] == 0
    assert by["line 0"]["group"] == "reference" and "hausdorff" not in by["line 0"]
    # rank-optimal under road=1, grass=2, water=3 (water is passable on the rank costmap): "swim" crosses
    # 6 water and 25 grass pixels (RRPI 6 x 2 + 25 = 37); the best route walks 10 grass pixels east to
    # the north-south road, follows the roads round the ring and walks 20 grass pixels north (RRPI 30)
    assert by["road run"]["rrpi_optimal"] == 0 and by["road run"]["rrpi_ratio"] == 1.0
    assert (by["swim"]["rrpi"], by["swim"]["rrpi_optimal"]) == (37, 30)
    assert by["swim"]["rrpi_ratio"] == pytest.approx(37 / 30)
    ro = m["rank_optimal"]
    assert ro["headline"] == "given" and ro["rank_scale"] == 3 and ro["cost"] == "(rank - 1) / 2"
    assert ro["groups"]["given"]["worst_ratio"] == pytest.approx(37 / 30)
    assert ro["groups"]["reference"]["median_ratio"] == 1.0

    from overseec_core.errors import Cancelled
    from overseec_core.evaluate import EvaluateOptions, evaluate_paths
    from overseec_core.progress import NullProgress

    progress = NullProgress()
    progress.token.cancel()
    with pytest.raises(Cancelled):
        evaluate_paths(
            EvaluateOptions(
                out_dir=tmp_path / "cancelled",
                labels=s["labels"],
                classes=s["classes"],
                ranks="road=1",
                costmap=s["costmap"],
                pairs=5,
            ),
            progress,
        )
    assert not (tmp_path / "cancelled" / "metrics.json").exists()


# ---------------------------------------------------------------------------------- a real scene


@pytest.mark.scenes
def test_real_scene_iou_of_ground_truth_with_itself(scenes_dir: Path, tmp_path: Path, capsys) -> None:
    folder = scenes_dir / "nrcan_newbrunswick_bakerlake_5class"
    gt, classes = folder / "gt_1of2.tif", folder / "classes.json"
    assert (
        main(
            [
                "--quiet",
                "eval",
                "--labels",
                str(gt),
                "--classes",
                str(classes),
                "--masks",
                str(gt),
                "--out",
                str(tmp_path / "iou"),
            ]
        )
        == 0
    )
    m = json.loads((tmp_path / "iou" / "metrics.json").read_text())
    ious = {c["name"]: c["iou"] for c in m["iou"]["classes"]}
    assert m["iou"]["mean_iou"] == 1.0 and ious["road"] == 1.0 and ious["building"] == 1.0
    assert ious["railway (Train)"] is None  # absent from this clip
    assert m["iou"]["valid_pixels"] == 280 * 341


@pytest.mark.scenes
@needs_planner
def test_real_scene_eval_with_a_costmap_from_the_labels(scenes_dir: Path, tmp_path: Path) -> None:
    folder = scenes_dir / "nrcan_newbrunswick_bakerlake_5class"
    gt, classes = folder / "gt_1of2.tif", folder / "classes.json"
    import rasterio

    from overseec_core.io.read import read_grid

    with rasterio.open(gt) as ds:
        labels = ds.read(1)
    # 0 unlabeled, 1 building, 2 road, 3 water, 4 vegetation: buildings and water are impassable
    table = np.array([0.3, np.nan, 0.05, np.nan, 0.7, 0.1], dtype=np.float32)
    costmap = write_array(tmp_path / "cost.tif", table[labels], read_grid(gt), nodata=float("nan"))
    out = tmp_path / "out"
    assert (
        main(
            [
                "--quiet",
                "eval",
                "--labels",
                str(gt),
                "--classes",
                str(classes),
                "--ranks",
                "road=1,unlabeled=2,vegetation=3",
                "--costmap",
                str(costmap),
                "--pairs",
                "12",
                "--seed",
                "0",
                "--image",
                str(folder / "image_1of2.tif"),
                "--out",
                str(out),
            ]
        )
        == 0
    )
    m = json.loads((out / "metrics.json").read_text())
    assert m["sampling"]["planned"] >= 6
    gj = json.loads((out / "paths.geojson").read_text())
    for feat in gj["features"]:
        pix = geojson_pixels(feat, read_grid(gt))
        cls = labels[pix[:, 0], pix[:, 1]]
        assert not np.isin(cls, [1, 3]).any(), "a path crossed a building or water"
        assert feat["properties"]["rrpi"] == sum({2: 0, 0: 1, 4: 2}.get(int(c), 2) for c in cls)
    assert (out / "paths_overlay.png").stat().st_size > 10_000
