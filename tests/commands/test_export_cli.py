"""`overseec export` through the CLI: outputs, manifest, and one-line errors (exit 2)."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np
import pytest
from rasterio.transform import from_origin

from overseec_core.cli import main
from tests.plan.conftest import smooth_costmap, write_costmap, write_lethal


@pytest.fixture
def scene(tmp_path: Path) -> dict:
    cost = smooth_costmap((30, 40), seed=5, lethal_fraction=0.0)
    lethal = np.zeros(cost.shape, np.uint8)
    lethal[5:20, 12] = 1
    costmap = write_costmap(tmp_path / "costmap.tif", cost, tags={"OVERSEEC_LETHAL_FILE": "lethal.tif"})
    write_lethal(tmp_path / "lethal.tif", lethal, tags={"OVERSEEC_COSTMAP_FILE": "costmap.tif"})
    return {"costmap": costmap, "dir": tmp_path, "cost": cost}


def sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def one_line_error(capsys, code: int, *needles: str) -> str:
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert len(err.splitlines()) == 1 and err.startswith("overseec: error: "), err
    for needle in needles:
        assert needle in err, err
    return err


def test_export_costmap_formats_and_manifest(scene: dict, capsys) -> None:
    out = scene["dir"] / "out"
    out.mkdir()
    for to, name in (("nav2", "map.yaml"), ("costmap2d", "c2d.tif"), ("npy", "cost.npy")):
        assert main(["--quiet", "export", "costmap", str(scene["costmap"]), "--to", to, "--out", str(out / name)]) == 0
    assert {p.name for p in out.iterdir()} >= {
        "map.yaml",
        "map.pgm",
        "c2d.tif",
        "cost.npy",
        "cost.flags.npy",
        "cost.json",
        "manifest.json",
    }
    manifest = json.loads((out / "manifest.json").read_text())
    assert set(manifest["exports"]) == {"map.yaml", "c2d.tif", "cost.npy"}
    assert manifest["inputs"]["export_costmap_costmap.tif"]["sha256"] == sha(scene["costmap"])
    assert manifest["inputs"]["export_lethal_lethal.tif"]["sha256"] == sha(scene["dir"] / "lethal.tif")
    assert [c["command"] for c in manifest["commands"]] == ["export"] * 3
    capsys.readouterr()
    assert (
        main(
            [
                "--quiet",
                "export",
                "costmap",
                str(scene["costmap"]),
                "--to",
                "nav2",
                "--nav2-mode",
                "scale",
                "--out",
                str(out / "scale.yaml"),
                "--json",
            ]
        )
        == 0
    )
    doc = json.loads(capsys.readouterr().out)
    assert doc["details"]["mode"] == "scale" and doc["outputs"]["image"].endswith("scale.png")


def test_export_path_formats(scene: dict, capsys) -> None:
    path = scene["dir"] / "path.geojson"
    assert (
        main(
            [
                "--quiet",
                "plan",
                str(scene["costmap"]),
                "--start",
                "500000.75",
                "3999999.25",
                "--goal",
                "500019.25",
                "3999985.25",
                "--out",
                str(path),
            ]
        )
        == 0
    )
    for to in ("gpx", "kml", "csv"):
        assert main(["--quiet", "export", "path", str(path), "--to", to, "--out", str(scene["dir"] / f"p.{to}")]) == 0
        assert (scene["dir"] / f"p.{to}").stat().st_size > 0
    assert (
        main(
            [
                "--quiet",
                "export",
                "path",
                str(path),
                "--to",
                "csv",
                "--frame",
                "nav2",
                "--out",
                str(scene["dir"] / "nav2.csv"),
            ]
        )
        == 0
    )
    first = (scene["dir"] / "nav2.csv").read_text().splitlines()[1].split(",")
    assert float(first[2]) == pytest.approx(0.75) and float(first[3]) == pytest.approx(15 - 0.75)


def test_output_equal_to_an_input_is_refused(scene: dict, capsys) -> None:
    before = {p: sha(p) for p in (scene["costmap"], scene["dir"] / "lethal.tif")}
    code = main(
        ["--quiet", "export", "costmap", str(scene["costmap"]), "--to", "costmap2d", "--out", str(scene["costmap"])]
    )
    one_line_error(capsys, code, "is the input")
    code = main(
        [
            "--quiet",
            "export",
            "costmap",
            str(scene["costmap"]),
            "--to",
            "costmap2d",
            "--out",
            str(scene["dir"] / "lethal.tif"),
        ]
    )
    one_line_error(capsys, code, "is the input")
    assert {p: sha(p) for p in before} == before
    path = scene["dir"] / "p.geojson"
    path.write_text(json.dumps({"type": "LineString", "coordinates": [[15, 36], [15.001, 36.001]]}))
    code = main(["--quiet", "export", "path", str(path), "--to", "gpx", "--out", str(path)])
    one_line_error(capsys, code, "is the input")


def test_geographic_costmap_to_nav2_is_refused(tmp_path: Path, capsys) -> None:
    cost = smooth_costmap((20, 20), seed=2, lethal_fraction=0.0)
    costmap = write_costmap(tmp_path / "geo.tif", cost, crs="EPSG:4326", transform=from_origin(15.0, 47.0, 5e-6, 5e-6))
    code = main(["--quiet", "export", "costmap", str(costmap), "--to", "nav2", "--out", str(tmp_path / "map.yaml")])
    one_line_error(capsys, code, "geographic", "gdalwarp -t_srs EPSG:32633")
    assert not (tmp_path / "map.yaml").exists() and not (tmp_path / "map.pgm").exists()
    # the other formats keep the grid as it is
    assert main(["--quiet", "export", "costmap", str(costmap), "--to", "npy", "--out", str(tmp_path / "geo.npy")]) == 0


def test_missing_lethal_sidecar(scene: dict, capsys) -> None:
    (scene["dir"] / "lethal.tif").unlink()
    code = main(
        ["--quiet", "export", "costmap", str(scene["costmap"]), "--to", "npy", "--out", str(scene["dir"] / "cost.npy")]
    )
    one_line_error(capsys, code, "lethal.tif", "--lethal")
    assert not (scene["dir"] / "cost.npy").exists()
    # a costmap that names no sidecar exports with a note
    bare = write_costmap(scene["dir"] / "bare.tif", scene["cost"])
    assert main(["export", "costmap", str(bare), "--to", "npy", "--out", str(scene["dir"] / "b.npy")]) == 0
    assert "no lethal sidecar" in capsys.readouterr().out


def test_bad_arguments_are_one_line(scene: dict, tmp_path: Path, capsys) -> None:
    code = main(
        ["--quiet", "export", "costmap", str(scene["costmap"]), "--to", "nav2", "--out", str(tmp_path / "map.pgm")]
    )
    one_line_error(capsys, code, ".yaml")
    code = main(
        ["--quiet", "export", "path", str(tmp_path / "nope.geojson"), "--to", "gpx", "--out", str(tmp_path / "p.gpx")]
    )
    one_line_error(capsys, code, "no such file")
    bad = tmp_path / "bad.geojson"
    bad.write_text("{not json")
    code = main(["--quiet", "export", "path", str(bad), "--to", "kml", "--out", str(tmp_path / "p.kml")])
    one_line_error(capsys, code, "not JSON")
    good = tmp_path / "good.geojson"
    good.write_text(json.dumps({"type": "LineString", "coordinates": [[15, 36], [15.001, 36.001]]}))
    code = main(
        ["--quiet", "export", "path", str(good), "--to", "gpx", "--frame", "nav2", "--out", str(tmp_path / "p.gpx")]
    )
    one_line_error(capsys, code, "--frame")
    code = main(["--quiet", "export", "path", str(good), "--to", "csv", "--out", str(tmp_path / "p.csv")])
    one_line_error(capsys, code, "--costmap")
