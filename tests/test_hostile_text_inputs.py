"""Text and JSON inputs are checked alike, and no input blocks (issue 33 rules 2 and 3).

One table per rule, across every command that takes that kind of input: each JSON input (a
priors table, a class table, an entities file, a path GeoJSON) and each CSV input (pairs, matrix
points and sources) is given a file nested deeper than Python's parser goes or a field longer
than the field limit, and then a named pipe with no writer. Each case runs the real console
script and must end with exit 2, exactly one ``overseec: error:`` line naming the input, no
traceback, no file changed or added -- and a pipe is refused at once (the run is given 20 s; one
that opened the pipe would wait forever).
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from overseec_core.limits import MAX_CSV_FIELD_CHARS
from tests import test_hostile
from tests.test_hostile import GOAL, LABELS, START, assert_one_line_error, overseec, partial_files, snapshot

scene_template = test_hostile.scene_template
scene = test_hostile.scene

#: JSON nested far deeper than Python's recursion limit, under every size cap (40 KB).
DEEP_JSON = "[" * 20_000 + "]" * 20_000
#: A CSV whose one id field is longer than the field limit (and than Python's csv default).
LONG_FIELD = "id,x,y\n" + "a" * 200_000 + f",{START[0]},{START[1]}\n"
PAIRS_HEADER = "start_x,start_y,goal_x,goal_y"

#: (case, the input file's name, argv using it, words of the error). {f} is the input's name.
JSON_INPUTS = [
    ("interpret --priors", "priors.json", ("interpret", "avoid water", "--offline", "--priors", "{f}"), "--priors"),
    (
        "costmap --priors",
        "priors.json",
        ("costmap", *LABELS, "--prompt", "prefer roads", "--priors", "{f}", "--out", "o/c.tif"),
        "--priors",
    ),
    (
        "costmap --classes",
        "classes_deep.json",
        (
            "costmap",
            "--labels",
            "sample_labels.tif",
            "--classes",
            "{f}",
            "--prompt",
            "prefer roads",
            "--out",
            "o/c.tif",
        ),
        "--classes",
    ),
    (
        "segment --entities-json",
        "entities.json",
        ("segment", "sample.tif", "--entities-json", "{f}", "--out", "o"),
        "--entities-json",
    ),
    ("export path", "path.geojson", ("export", "path", "{f}", "--to", "gpx", "--out", "o/p.gpx"), "path"),
]
CSV_INPUTS = [
    ("plan --pairs", "pairs.csv", ("plan", "c/costmap.tif", "--pairs", "{f}", "--out", "o/routes.gpkg"), "--pairs"),
    (
        "plan --points --matrix",
        "points.csv",
        ("plan", "c/costmap.tif", "--points", "{f}", "--matrix", "o/m.csv"),
        "--points",
    ),
    (
        "plan --sources --matrix",
        "sources.csv",
        ("plan", "c/costmap.tif", "--points", "ok_points.csv", "--sources", "{f}", "--matrix", "o/m.csv"),
        "--sources",
    ),
]


def _argv(argv: tuple[str, ...], name: str) -> list[str]:
    return [a.format(f=name) for a in argv]


def _refused(scene: Path, argv: list[str], says: str) -> None:
    before = snapshot(scene)
    done = overseec(*argv, cwd=scene, timeout=20)
    assert_one_line_error(done, 2, says)
    assert "Traceback" not in done.stdout + done.stderr
    assert not partial_files(scene)
    assert snapshot(scene) == before, "a refused command changed or added a file"


@pytest.mark.parametrize(("case", "name", "argv", "says"), JSON_INPUTS, ids=[c[0] for c in JSON_INPUTS])
def test_a_json_input_nested_too_deeply_is_one_line(scene: Path, case: str, name: str, argv: tuple, says: str) -> None:
    (scene / name).write_text(DEEP_JSON)
    _refused(scene, _argv(argv, name), f"{says} {name}: JSON nested too deeply")


@pytest.mark.parametrize(("case", "name", "argv", "says"), CSV_INPUTS, ids=[c[0] for c in CSV_INPUTS])
def test_a_csv_field_over_the_limit_is_one_line_naming_the_line(
    scene: Path, case: str, name: str, argv: tuple, says: str
) -> None:
    (scene / "ok_points.csv").write_text(f"id,x,y\na,{START[0]},{START[1]}\nb,{GOAL[0]},{GOAL[1]}\n")
    text = (
        LONG_FIELD
        if name != "pairs.csv"
        else f"{PAIRS_HEADER},id\n{START[0]},{START[1]},{GOAL[0]},{GOAL[1]},{'a' * 200_000}\n"
    )
    (scene / name).write_text(text)
    _refused(scene, _argv(argv, name), f"{says} {name} line 2")
    # a field just over our limit (under Python's csv limit) is refused the same way
    (scene / name).write_text(text.replace("a" * 200_000, "a" * (MAX_CSV_FIELD_CHARS + 1)))
    _refused(scene, _argv(argv, name), f"longer than {MAX_CSV_FIELD_CHARS} characters")


@pytest.mark.parametrize(
    ("case", "name", "argv", "says"), JSON_INPUTS + CSV_INPUTS, ids=[c[0] for c in JSON_INPUTS + CSV_INPUTS]
)
def test_a_named_pipe_as_input_is_refused_at_once(scene: Path, case: str, name: str, argv: tuple, says: str) -> None:
    (scene / "ok_points.csv").write_text(f"id,x,y\na,{START[0]},{START[1]}\nb,{GOAL[0]},{GOAL[1]}\n")
    os.mkfifo(scene / name)
    _refused(scene, _argv(argv, name), "not a regular file")


#: Every command that reads a DEM (issue 33 rule 1: a DEM is checked as every raster input is).
DEM_COMMANDS = {
    "plan --dem": ("plan", "c/costmap.tif", *test_hostile.POINTS, "--dem", "{f}", "--out", "o/p.geojson"),
    "costmap --dem": ("costmap", *LABELS, "--prompt", "avoid steep slopes", "--dem", "{f}", "--out", "o/c.tif"),
    "run --dem": (
        "run",
        "sample.tif",
        *test_hostile.RUN,
        *test_hostile.POINTS,
        "--dem",
        "{f}",
        "--out",
        "o/run",
        "--no-eval",
    ),
}


@pytest.mark.parametrize("case", list(DEM_COMMANDS))
def test_a_photo_or_an_oversized_raster_is_refused_as_a_dem(scene: Path, case: str) -> None:
    argv = DEM_COMMANDS[case]
    _refused(scene, _argv(argv, "sample.tif"), "3 bands; a DEM has one band")  # an RGB photo
    _refused(scene, _argv(argv, "huge_labels.vrt"), "above the pixel budget")
