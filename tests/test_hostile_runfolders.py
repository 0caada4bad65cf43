"""Damaged run folders and bookkeeping names used as outputs, through the real `overseec` command.

The run folder's ``manifest.json`` is read before anything is written. One that is not a UTF-8
JSON object (binary, truncated, a JSON list, a folder) is refused with one line naming it, exit
2, and the folder is left exactly as it was: nothing is merged into it, nothing replaces it. The
folder's bookkeeping names (``manifest.json``, ``.manifest.lock``) are never output names, and
`compare` never writes through a symbolic link in place of its ``OUT/prompt_k`` folders.

Each case asserts, like tests/test_hostile.py: exit status 2, exactly one stderr line
``overseec: error: ...`` (no traceback), no file changed or added anywhere in the scene. Only
the folder whose manifest records the command is checked: an output written elsewhere (plan
--pixels-out) beside a damaged manifest is written, and that manifest is left alone.
"""

from __future__ import annotations

import json
import shutil
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests import test_hostile
from tests.test_hostile import LABELS, POINTS, assert_one_line_error, overseec, partial_files, snapshot

#: The sample scene test_hostile builds (module fixture), copied per test by ``runs``.
scene_template = test_hostile.scene_template

#: How a manifest is damaged: (id, writer into the folder, what the message says).
DAMAGE = {
    "not-utf8": lambda d: (d / "manifest.json").write_bytes(b'\xff\xfe{"inputs": {}}\n'),
    "not-an-object": lambda d: (d / "manifest.json").write_text("[1, 2, 3]\n"),
    "truncated": lambda d: (d / "manifest.json").write_text('{"inputs": {"image": '),
    "a-folder": lambda d: ((d / "manifest.json").mkdir(), (d / "manifest.json" / "keep.txt").write_text("x")),
}

#: A command writing into the folder ``d`` of the scene (the damaged one).
COMMANDS = {
    "plan": ("plan", "c/costmap.tif", *POINTS, "--out", "d/path.geojson"),
    "export-costmap": ("export", "costmap", "c/costmap.tif", "--to", "npy", "--out", "d/cost.npy"),
    "export-path": ("export", "path", "p0/path.geojson", "--to", "csv", "--out", "d/path.csv"),
    "costmap": ("costmap", *LABELS, "--prompt", "prefer roads", "--out", "d/costmap.tif"),
    "compare": ("compare", *LABELS, "--prompt", "prefer roads", "--prompt", "avoid roads", *POINTS, "--out", "d"),
}


@pytest.fixture
def runs(scene_template: Path, tmp_path: Path) -> Path:
    """The hostile scene plus a planned path (p0/path.geojson) and empty folders d/ and p/."""
    scene = tmp_path / "scene"
    shutil.copytree(scene_template, scene)
    done = overseec("plan", "c/costmap.tif", *POINTS, "--out", "p0/path.geojson", cwd=scene)
    assert done.returncode == 0, done.stderr
    (scene / "d").mkdir()
    (scene / "p").mkdir(exist_ok=True)
    return scene


def assert_refused(done, folder: Path, before: dict[str, str], says: str) -> None:
    assert_one_line_error(done, 2, says)
    assert "Traceback" not in done.stderr + done.stdout
    assert snapshot(folder) == before
    assert partial_files(folder) == []


@pytest.mark.parametrize("command", list(COMMANDS))
@pytest.mark.parametrize("damage", list(DAMAGE))
def test_damaged_manifest_is_refused_and_left_alone(runs: Path, damage: str, command: str) -> None:
    DAMAGE[damage](runs / "d")
    before = snapshot(runs)
    done = overseec(*COMMANDS[command], cwd=runs)
    assert_refused(done, runs, before, "d/manifest.json is not a manifest")
    assert sorted(p.name for p in (runs / "d").iterdir()) == ["manifest.json"]


def test_damaged_manifest_of_a_compare_subfolder_is_refused(runs: Path) -> None:
    (runs / "d" / "prompt_2").mkdir()
    DAMAGE["not-an-object"](runs / "d" / "prompt_2")
    before = snapshot(runs)
    done = overseec(*COMMANDS["compare"], cwd=runs)
    assert_refused(done, runs, before, "d/prompt_2/manifest.json is not a manifest")
    assert sorted(p.name for p in (runs / "d").iterdir()) == ["prompt_2"]


@dataclass(frozen=True)
class NameCase:
    id: str
    argv: tuple[str, ...]
    says: str = "c/manifest.json"


NAME_CASES = [
    NameCase("plan-out", ("plan", "c/costmap.tif", *POINTS, "--out", "c/manifest.json")),
    NameCase(
        "plan-native-out", ("plan", "c/costmap.tif", *POINTS, "--out", "p/p.geojson", "--native-out", "c/manifest.json")
    ),
    NameCase(
        "plan-pixels-out", ("plan", "c/costmap.tif", *POINTS, "--out", "p/p.geojson", "--pixels-out", "c/manifest.json")
    ),
    NameCase(
        "plan-cumulative", ("plan", "c/costmap.tif", *POINTS, "--out", "p/p.geojson", "--cumulative", "c/manifest.json")
    ),
    NameCase("export-path-csv", ("export", "path", "p0/path.geojson", "--to", "csv", "--out", "c/manifest.json")),
    NameCase("export-path-gpx", ("export", "path", "p0/path.geojson", "--to", "gpx", "--out", "c/manifest.json")),
    NameCase("export-costmap-nav2", ("export", "costmap", "c/costmap.tif", "--to", "nav2", "--out", "c/manifest.json")),
    NameCase("export-costmap-npy", ("export", "costmap", "c/costmap.tif", "--to", "npy", "--out", "c/manifest.json")),
    NameCase("export-npy-sidecar", ("export", "costmap", "c/costmap.tif", "--to", "npy", "--out", "c/manifest.npy")),
    NameCase("plan-out-lock-file", ("plan", "c/costmap.tif", *POINTS, "--out", "c/.manifest.lock"), "c/.manifest.lock"),
]


@pytest.mark.parametrize("case", NAME_CASES, ids=[c.id for c in NAME_CASES])
def test_bookkeeping_names_are_never_outputs(runs: Path, case: NameCase) -> None:
    manifest = json.loads((runs / "c" / "manifest.json").read_text())
    assert isinstance(manifest, dict)
    before = snapshot(runs)
    done = overseec(*case.argv, cwd=runs)
    assert_refused(done, runs, before, case.says)
    assert "bookkeeping" in done.stderr


def test_compare_never_writes_through_a_symlinked_subfolder(runs: Path) -> None:
    outside = runs / "outside"
    outside.mkdir()
    (outside / "mine.txt").write_text("not compare's")
    (runs / "d" / "prompt_1").symlink_to(outside, target_is_directory=True)
    before = snapshot(runs)
    done = overseec(*COMMANDS["compare"], cwd=runs)
    assert_refused(done, runs, before, "d/prompt_1")
    assert "symbolic link" in done.stderr
    assert sorted(p.name for p in outside.iterdir()) == ["mine.txt"]
    assert (runs / "d" / "prompt_1").is_symlink()
    assert sorted(p.name for p in (runs / "d").iterdir()) == ["prompt_1"]


def test_an_output_beside_a_damaged_manifest_outside_the_run_folder_is_written(runs: Path) -> None:
    """Only the folder whose manifest records the command is checked: --pixels-out elsewhere
    writes its file and leaves that folder's (damaged) manifest.json as it is."""
    DAMAGE["not-an-object"](runs / "d")
    done = overseec("plan", "c/costmap.tif", *POINTS, "--out", "p/path.geojson", "--pixels-out", "d/px.csv", cwd=runs)
    assert done.returncode == 0, done.stderr
    assert (runs / "d" / "manifest.json").read_text() == "[1, 2, 3]\n"
    assert sorted(p.name for p in (runs / "d").iterdir()) == ["manifest.json", "px.csv"]
    assert isinstance(json.loads((runs / "p" / "manifest.json").read_text()), dict)
