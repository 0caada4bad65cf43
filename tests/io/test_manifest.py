"""Run directories record inputs, timings and outcomes; JSON is written atomically."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pytest

from overseec_core.errors import Cancelled, OutputError
from overseec_core.io.manifest import RunDir, check_output_name, check_run_folder, read_manifest


def test_manifest_records_inputs_stages_and_reruns(tmp_path: Path, rgb_tif: Path) -> None:
    run = RunDir(tmp_path / "run", command="segment", args={"tile_size": 512})
    run.record_input("image", rgb_tif)
    with run.stage("segment"):
        run.set("entities", [{"name": "road", "geometry": "linear"}])
    data = json.loads(run.manifest_path.read_text())
    assert data["inputs"]["image"]["sha256"] == hashlib.sha256(rgb_tif.read_bytes()).hexdigest()
    assert data["inputs"]["image"]["size"] == rgb_tif.stat().st_size
    assert data["stages"]["segment"]["status"] == "ok" and data["stages"]["segment"]["seconds"] >= 0
    assert data["versions"]["gdal"] and data["entities"][0]["name"] == "road"
    # A second stage on the same directory keeps the first one's record.
    again = RunDir(tmp_path / "run", command="costmap")
    with again.stage("costmap"):
        pass
    data = json.loads(again.manifest_path.read_text())
    assert set(data["stages"]) == {"segment", "costmap"}
    assert [c["command"] for c in data["commands"]] == ["segment", "costmap"]


@pytest.mark.parametrize("error,status", [(RuntimeError("boom"), "failed"), (Cancelled("stop"), "cancelled")])
def test_failed_and_cancelled_stages_are_recorded(tmp_path: Path, error, status) -> None:
    run = RunDir(tmp_path)
    with pytest.raises(type(error)):
        with run.stage("plan"):
            raise error
    assert json.loads(run.manifest_path.read_text())["stages"]["plan"]["status"] == status


def test_run_dir_must_be_a_directory(tmp_path: Path) -> None:
    (tmp_path / "file").write_text("x")
    with pytest.raises(OutputError, match="not a directory"):
        RunDir(tmp_path / "file")


@pytest.mark.parametrize(
    "damage",
    [b"\xff\xfe{}", b"[1, 2]", b'"text"', b'{"inputs": ', b""],
    ids=["not-utf8", "a-list", "a-string", "truncated", "empty"],
)
def test_a_damaged_manifest_is_refused_not_replaced(tmp_path: Path, damage: bytes) -> None:
    (tmp_path / "manifest.json").write_bytes(damage)
    with pytest.raises(OutputError, match=r"manifest.json is not a manifest \(not UTF-8 JSON object\)"):
        RunDir(tmp_path, command="plan")
    with pytest.raises(OutputError, match="move it away or choose another --out"):
        check_run_folder(tmp_path)
    assert (tmp_path / "manifest.json").read_bytes() == damage
    assert sorted(p.name for p in tmp_path.iterdir()) == ["manifest.json"]


def test_a_manifest_that_is_a_folder_is_refused(tmp_path: Path) -> None:
    (tmp_path / "manifest.json").mkdir()
    with pytest.raises(OutputError, match="is not a manifest"):
        RunDir(tmp_path)
    assert read_manifest(tmp_path / "elsewhere") is None
    check_run_folder(tmp_path / "not-made-yet")  # a folder still to be created is fine


def test_a_manifest_damaged_between_saves_is_refused(tmp_path: Path) -> None:
    run = RunDir(tmp_path)
    run.save()
    run.manifest_path.write_text("[]")
    with pytest.raises(OutputError, match="is not a manifest"):
        run.save()
    assert run.manifest_path.read_text() == "[]"


@pytest.mark.parametrize("name", ["manifest.json", "MANIFEST.JSON", ".manifest.lock"])
def test_bookkeeping_names_are_no_output_names(tmp_path: Path, name: str) -> None:
    with pytest.raises(OutputError, match="bookkeeping"):
        check_output_name(tmp_path / name)
    check_output_name(tmp_path / "manifest.geojson")
