"""`overseec costmap`: layers + prompt/program -> costmap, lethal sidecar, program text, manifest."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import rasterio

from overseec_core.cli import EXIT_USER, main
from overseec_core.io.manifest import sha256_file
from overseec_core.io.write import write_array

from ..synthesize.test_compose import utm_grid, write_mask_dir, write_vectors

OVERSEEC = Path(sys.executable).with_name("overseec")
PROGRAM = (
    'acc = sum(0.1 * P["road"], 0.6 * P["grass"])\n'
    'cost = where(OR(M["road"], M["grass"]), acc, 1.0)\n'
    'cost = where(near(M["water"], 2), 1.0, cost)\n'
    'lethal = M["water"]\n'
)


@pytest.fixture
def run_dir(tmp_path: Path) -> Path:
    """A segment-like output folder: 60 x 40 px at 0.5 m, road row band, water block, grass."""
    grid = utm_grid(60, 40)
    road = np.zeros(grid.shape, bool)
    road[10:14] = True
    water = np.zeros(grid.shape, bool)
    water[30:, 40:] = True
    grass = ~(road | water)
    probs = {"road": np.full(grid.shape, 0.9), "grass": np.full(grid.shape, 0.5), "water": np.full(grid.shape, 0.8)}
    return write_mask_dir(tmp_path / "run", grid, {"road": road, "grass": grass, "water": water}, probs)


def read(path: Path) -> np.ndarray:
    with rasterio.open(path) as ds:
        return ds.read(1)


def test_costmap_from_masks_and_a_program(run_dir, tmp_path, capsys):
    prog = tmp_path / "mission.txt"
    prog.write_text(PROGRAM)
    out = run_dir / "costmap.tif"
    assert main(["-q", "costmap", "--masks", str(run_dir), "--program", str(prog), "--out", str(out)]) == 0
    assert "costmap" in capsys.readouterr().out
    cost, lethal = read(out), read(run_dir / "lethal.tif")
    assert cost[11, 5] == pytest.approx(0.09) and cost[0, 0] == pytest.approx(0.3)
    assert np.all(cost[30:, 40:] == 1.0) and np.all(lethal[30:, 40:] == 1)
    assert lethal.sum() == 10 * 20
    assert cost[29, 45] == 1.0 and lethal[29, 45] == 0  # near water: avoided, passable
    assert (run_dir / "costmap.program.txt").read_text() == PROGRAM
    with rasterio.open(out) as ds:
        assert ds.tags()["OVERSEEC_PROGRAM_FILE"] == "costmap.program.txt"
        assert ds.tags()["OVERSEEC_LETHAL_FILE"] == "lethal.tif"
    manifest = json.loads((run_dir / "manifest.json").read_text())
    assert manifest["cost_program"]["text"] == PROGRAM
    assert manifest["cost_program"]["source"] == "file"
    assert manifest["stages"]["costmap"]["status"] == "ok"
    assert manifest["inputs"]["cost_program"]["sha256"] == sha256_file(prog)


def test_editing_the_saved_program_and_rerunning_reads_only_the_masks(run_dir):
    out = run_dir / "costmap.tif"
    before = {p.name: sha256_file(p) for p in run_dir.glob("*.tif")}
    assert (
        main(["-q", "costmap", "--masks", str(run_dir), "--prompt", "prefer roads, avoid water", "--out", str(out)])
        == 0
    )
    saved = run_dir / "costmap.program.txt"
    assert 'P["road"]' in saved.read_text()
    saved.write_text('cost = 0.25 + 0.5 * M["grass"]\n')
    assert main(["-q", "costmap", "--masks", str(run_dir), "--program", str(saved), "--out", str(out)]) == 0
    cost = read(out)
    assert cost[0, 0] == 0.75 and cost[11, 0] == 0.25
    assert saved.read_text() == 'cost = 0.25 + 0.5 * M["grass"]\n'
    after = {p.name: sha256_file(p) for p in run_dir.glob("*.tif") if p.name in before}
    assert after == before  # the masks were only read


def test_prompt_costmap_orders_road_grass_water(run_dir):
    out = run_dir / "c.tif"
    assert (
        main(
            [
                "-q",
                "costmap",
                "--masks",
                str(run_dir),
                "--prompt",
                "Prefer the roads, grass is fine, never enter the water",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    cost, lethal = read(out), read(run_dir / "c.lethal.tif")
    assert cost[11, 5] < cost[0, 0] < 1.0
    assert np.all(lethal[30:, 40:] == 1) and lethal[:30].sum() == 0


def test_labels_and_vectors_combine(tmp_path):
    grid = utm_grid(40, 30, 1.0, 1.0)
    labels = np.full(grid.shape, 2, np.uint8)  # grass everywhere
    labels[:, 30:] = 0  # unlabeled strip
    write_array(tmp_path / "gt.tif", labels, grid)
    (tmp_path / "classes.json").write_text(json.dumps({"0": "unlabeled", "1": "road", "2": "grass"}))
    # a track from the vector layer along row 5 (y = 4000000 - 5.5)
    track = write_vectors(
        tmp_path / "track.gpkg",
        "EPSG:32633",
        [
            {
                "geometry": {"type": "LineString", "coordinates": [(500000.5, 3999994.5), (500039.5, 3999994.5)]},
                "properties": {},
            }
        ],
        {"geometry": "LineString", "properties": {}},
    )
    prog = tmp_path / "p.txt"
    prog.write_text('cost = where(M["track"], 0.1, where(M["grass"], 0.5, 1.0))\n')
    out = tmp_path / "out.tif"
    assert (
        main(
            [
                "-q",
                "costmap",
                "--labels",
                str(tmp_path / "gt.tif"),
                "--classes",
                str(tmp_path / "classes.json"),
                "--vector",
                f"track={track}",
                "--program",
                str(prog),
                "--out",
                str(out),
            ]
        )
        == 0
    )
    cost = read(out)
    assert np.all(cost[5] == pytest.approx(0.1))
    assert cost[0, 0] == 0.5 and cost[0, 35] == 1.0


def test_vectors_alone_need_a_grid(tmp_path, capsys):
    track = write_vectors(
        tmp_path / "t.gpkg",
        "EPSG:32633",
        [{"geometry": {"type": "Point", "coordinates": (500002.2, 3999997.7)}, "properties": {}}],
        {"geometry": "Point", "properties": {}},
    )
    prog = tmp_path / "p.txt"
    prog.write_text('cost = where(M["track"], 0.0, 0.5)\n')
    args = ["-q", "costmap", "--vector", f"track={track}", "--program", str(prog), "--out", str(tmp_path / "c.tif")]
    assert main(args) == EXIT_USER
    assert "need a grid" in capsys.readouterr().err
    ref = write_array(tmp_path / "ref.tif", np.zeros((6, 8), np.uint8), utm_grid(8, 6, 1.0, 1.0))
    assert main(args + ["--grid", str(ref)]) == 0
    cost = read(tmp_path / "c.tif")
    assert cost[2, 2] == 0.0 and (cost == 0.0).sum() == 1


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["--program", "{prog_bad}"], "line 2, column 9: unknown entity 'lava'"),
        (["--program", "{prog_syntax}"], "line 1"),
        (["--program", "{missing}"], "no such file"),
        (["--prompt", "   "], "empty"),
        (["--program", "{prog}", "--out-override", "{run}/masks.tif"], "is the input"),
        (["--program", "{prog}", "--out-override", "{run}/costmap.png"], ".tif"),
        (["--program", "{prog}", "--out-override", "{tmp}/ok.txt/c.tif"], "is a file, not a folder"),
        (["--program", "{prog}", "--labels", "{run}/masks.tif"], "--classes"),
    ],
)
def test_user_errors_are_one_line_and_exit_2(run_dir, tmp_path, capsys, argv, fragment):
    (tmp_path / "bad.txt").write_text('a = 1\ncost = M["lava"]\n')
    (tmp_path / "syntax.txt").write_text("cost = (\n")
    (tmp_path / "ok.txt").write_text(PROGRAM)
    fill = {
        "prog_bad": tmp_path / "bad.txt",
        "prog_syntax": tmp_path / "syntax.txt",
        "prog": tmp_path / "ok.txt",
        "missing": tmp_path / "none.txt",
        "run": run_dir,
        "tmp": tmp_path,
    }
    argv = [a.format(**fill) for a in argv]
    out = str(run_dir / "costmap.tif")
    if "--out-override" in argv:
        i = argv.index("--out-override")
        out = argv[i + 1]
        del argv[i : i + 2]
    code = main(["-q", "costmap", "--masks", str(run_dir), *argv, "--out", out])
    err = capsys.readouterr().err
    assert code == EXIT_USER
    assert err.startswith("overseec: error: ") and err.count("\n") == 1
    assert fragment in err
    assert not (run_dir / "costmap.tif").exists()


def test_no_layers_is_a_user_error(tmp_path, capsys):
    prog = tmp_path / "p.txt"
    prog.write_text("cost = 1")
    assert main(["-q", "costmap", "--program", str(prog), "--out", str(tmp_path / "c.tif")]) == EXIT_USER
    assert "no entity layers" in capsys.readouterr().err


def test_json_output(run_dir, tmp_path, capsys):
    prog = tmp_path / "p.txt"
    prog.write_text(PROGRAM)
    assert (
        main(
            [
                "-q",
                "costmap",
                "--masks",
                str(run_dir),
                "--program",
                str(prog),
                "--out",
                str(tmp_path / "cm.tif"),
                "--json",
            ]
        )
        == 0
    )
    doc = json.loads(capsys.readouterr().out)
    assert doc["entities"] == ["road", "grass", "water"]
    assert doc["halo"] == [5, 5] and doc["lethal_pixels"] == 200
    assert Path(doc["program_file"]).name == "cm.program.txt"


def test_subprocess_success_and_failure(run_dir, tmp_path):
    prog = tmp_path / "p.txt"
    prog.write_text(PROGRAM)
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
    ok = subprocess.run(
        [
            str(OVERSEEC),
            "-q",
            "costmap",
            "--masks",
            str(run_dir),
            "--program",
            str(prog),
            "--out",
            str(tmp_path / "c.tif"),
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert ok.returncode == 0, ok.stderr
    assert (tmp_path / "c.tif").exists() and (tmp_path / "c.lethal.tif").exists()
    prog.write_text("cost = __import__('os').system('true')\n")
    bad = subprocess.run(
        [str(OVERSEEC), "costmap", "--masks", str(run_dir), "--program", str(prog), "--out", str(tmp_path / "d.tif")],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert bad.returncode == 2
    assert "Traceback" not in bad.stderr
    assert "only operators from the table" in bad.stderr


def test_reprompting_does_not_load_models(run_dir, tmp_path):
    """The costmap stage reads mask files only: no torch, no segmentation in the process."""
    code = (
        "import sys\n"
        "from pathlib import Path\n"
        "from overseec_core.synthesize.options import CostmapOptions\n"
        "from overseec_core.pipeline import run_costmap\n"
        f"r = run_costmap(CostmapOptions(out=Path({str(tmp_path / 'c.tif')!r}), "
        f"masks=Path({str(run_dir)!r}), prompt='prefer roads, avoid water'))\n"
        "assert r.costmap.exists()\n"
        "bad = [m for m in ('torch', 'transformers', 'overseec_core.segment', 'overseec_core.refine')"
        " if m in sys.modules]\n"
        "assert not bad, bad\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr


@pytest.mark.scenes
def test_real_labels_costmap_with_a_prompt(scenes_dir, tmp_path):
    scene = scenes_dir / "nrcan_newbrunswick_bakerlake_5class"
    if not (scene / "gt_1of2.tif").exists():
        pytest.skip("Baker Lake scene not present")
    out = tmp_path / "costmap.tif"
    assert (
        main(
            [
                "-q",
                "costmap",
                "--labels",
                str(scene / "gt_1of2.tif"),
                "--classes",
                str(scene / "classes.json"),
                "--prompt",
                "Prefer the roads, vegetation is fine, avoid buildings, never enter the water",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    with rasterio.open(scene / "gt_1of2.tif") as ds:
        labels, grid = ds.read(1), (ds.crs, ds.transform, ds.shape)
    with rasterio.open(out) as ds:
        cost = ds.read(1)
        assert (ds.crs, ds.transform, ds.shape) == grid
    lethal = read(tmp_path / "lethal.tif")
    road, veg, building, water = (cost[labels == k] for k in (2, 4, 1, 3))
    assert road.mean() < veg.mean() < building.mean()
    assert np.all(water == 1.0) and np.all(lethal[labels == 3] == 1)
    # "avoid buildings" keeps their prior: an obstacle (keep-out, flag 2), gone around where possible
    assert np.all(lethal[labels == 1] == 2) and lethal[(labels != 3) & (labels != 1)].sum() == 0
    assert np.all(cost[labels == 0] == 0.5)  # unlabeled: neutral ground
    assert np.all(veg == 0.5)  # "fine": neutral too
    assert road.max() < 0.5 < building.min()  # preferred below, avoided above
    assert np.isfinite(cost).all() and cost.min() >= 0 and cost.max() <= 1
    program = (tmp_path / "costmap.program.txt").read_text()
    assert 'M["water"]' in program


def baker_lake(scenes_dir: Path) -> Path:
    scene = scenes_dir / "nrcan_newbrunswick_bakerlake_5class"
    if not (scene / "gt_2of2.tif").exists():
        pytest.skip("Baker Lake scene not present")
    return scene


def test_prompt_words_are_matched_to_class_names_and_the_mapping_recorded(scenes_dir, tmp_path, capsys):
    scene = baker_lake(scenes_dir)
    out = tmp_path / "costmap.tif"
    assert (
        main(
            [
                "costmap",
                "--labels",
                str(scene / "gt_2of2.tif"),
                "--classes",
                str(scene / "classes.json"),
                "--prompt",
                "stay on the paved roads, avoid the lake and the tracks, the trees are fine",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    printed = capsys.readouterr()
    assert "road -> road (name)" in printed.err and "lake -> water (broader)" in printed.err
    with rasterio.open(scene / "gt_2of2.tif") as ds:
        labels = ds.read(1)
    cost = read(out)
    assert cost[labels == 2].max() < 0.5  # roads preferred
    assert cost[labels == 3].min() > 0.5 and cost[labels == 5].min() > 0.5  # water, railway avoided
    assert np.all(cost[labels == 4] == 0.5) and np.all(cost[labels == 0] == 0.5)
    manifest = json.loads((tmp_path / "manifest.json").read_text())
    layers = {m["entity"]: m for m in manifest["cost_program"]["entity_layers"]}
    assert layers["railway"]["layers"] == ["railway"]  # "the tracks"
    assert layers["lake"] == {"entity": "lake", "layers": ["water"], "rule": "broader"}
    assert layers["trail"]["rule"] == "unmatched"


def test_alias_and_unmatched_entities(scenes_dir, tmp_path, capsys):
    scene = baker_lake(scenes_dir)
    args = [
        "costmap",
        "--labels",
        str(scene / "gt_2of2.tif"),
        "--classes",
        str(scene / "classes.json"),
        "--out",
        str(tmp_path / "c.tif"),
    ]
    # nothing the prompt speaks about exists on this map: an error, not a uniform costmap
    assert main(args + ["--prompt", "avoid the electric towers"]) == EXIT_USER
    err = capsys.readouterr().err
    assert "matches a layer" in err and "--alias" in err and not (tmp_path / "c.tif").exists()
    assert main(args + ["--prompt", "hello there"]) == EXIT_USER
    assert "states no preference" in capsys.readouterr().err
    # a ranked entity without a layer is a warning; the alias makes it count
    assert main(args + ["--prompt", "avoid the compounds, prefer the roads"]) == 0
    assert "'compound' matches no layer" in capsys.readouterr().err
    assert main(args + ["--prompt", "avoid the compounds", "--alias", "compound=building"]) == 0
    with rasterio.open(scene / "gt_2of2.tif") as ds:
        labels = ds.read(1)
    assert read(tmp_path / "c.tif")[labels == 1].min() > 0.5
    assert main(args + ["--prompt", "avoid the lake", "--alias", "lake=pond"]) == 0
    assert "alias lake=pond: no layer is called 'pond'" in capsys.readouterr().err
    with pytest.raises(SystemExit) as bad:
        main(args + ["--prompt", "avoid x", "--alias", "compound"])
    assert bad.value.code == 2 and "ENTITY=LAYER" in capsys.readouterr().err
