"""Hausdorff distances only against reference paths of the same start and goal."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from overseec_core.evaluate import (
    EvaluateOptions,
    VectorLine,
    endpoint_tolerance_m,
    evaluate_paths,
    matching_references,
    render_report,
)
from overseec_core.io.write import write_array

from .test_evaluate import utm_grid, write_classes, write_lines


def _ref(name: str, pts: list[tuple[float, float]]) -> VectorLine:
    return VectorLine(name, np.array(pts, dtype=np.float64))


def test_endpoint_tolerance_is_three_pixels_or_one_percent_of_the_diagonal() -> None:
    assert endpoint_tolerance_m(utm_grid(40, 30)) == 3.0  # diagonal 50 m: 1 % is 0.5 m
    assert endpoint_tolerance_m(utm_grid(40, 30, px=2.0, py=0.5)) == 6.0  # 3 of the larger pixel side
    assert endpoint_tolerance_m(utm_grid(1000, 1000)) == pytest.approx(0.01 * math.hypot(1000, 1000))


def test_references_match_by_both_ends_in_either_direction() -> None:
    refs = [
        _ref("a", [(10, 0), (12, 20), (10, 39)]),
        _ref("b", [(20, 0), (20, 39)]),
        _ref("a again", [(9.0, 1.0), (10, 38)]),
    ]
    px = (1.0, 1.0)
    assert matching_references((10, 0), (10, 39), refs, px, 3.0) == [0, 2]
    assert matching_references((10, 39), (10, 0), refs, px, 3.0) == [0, 2]  # reversed
    assert matching_references((12, 0), (10, 39), refs, px, 2.0) == [0]  # 2 m off one end: still "a"
    assert matching_references((12, 0), (10, 39), refs, px, 1.9) == []
    assert matching_references((10, 0), (20, 39), refs, px, 3.0) == []  # one end of a, one of b
    assert matching_references((10, 0), (10, 20), refs, px, 3.0) == []  # the goal is mid-way along a
    # distances are in ground metres: 2 rows of 0.5 m is 1 m, 2 columns of 2 m is 4 m
    assert matching_references((12, 0), (10, 39), refs, (2.0, 0.5), 1.0) == [0]
    assert matching_references((10, 2), (10, 39), refs, (2.0, 0.5), 2.0) == []  # 4 m from a, 2.06 m from a again


def test_eval_measures_each_path_against_the_references_of_its_own_pair(tmp_path: Path) -> None:
    grid = utm_grid(40, 40)
    labels = np.full((40, 40), 2, dtype=np.uint8)
    labels_tif = write_array(tmp_path / "gt.tif", labels, grid)
    classes = write_classes(tmp_path / "classes.json")
    # two humans drew the north pair (one straight, one dipping to row 13); south is another pair
    refs = write_lines(
        tmp_path / "ref.geojson",
        grid,
        [[(10, 0), (10, 39)], [(17, 0), (17, 39)], [(10, 0), (13, 3), (13, 36), (10, 39)]],
        names=["north", "south", "north low"],
    )
    # "bent" runs between north's ends and dips to row 16, 1 m from south but 3 m from the nearest
    # north reference (north low): against its own pair's references it strays 3 m (against the union
    # of every reference, the old rule, it would be 2 m)
    paths = write_lines(
        tmp_path / "paths.geojson",
        grid,
        [[(10, 0), (16, 6), (16, 33), (10, 39)], [(17, 39), (17, 0)], [(30, 0), (30, 39)]],
        names=["bent", "south backwards", "nowhere"],
    )
    out = tmp_path / "out"
    evaluate_paths(EvaluateOptions(out_dir=out, labels=labels_tif, classes=classes, paths=paths, reference=refs))
    m = json.loads((out / "metrics.json").read_text())
    by = {p["name"]: p for p in m["paths"]}
    assert by["bent"]["hausdorff_references"] == ["north", "north low"]
    assert by["bent"]["hausdorff"]["directed_m"] == pytest.approx(3.0, abs=1e-6)
    assert by["south backwards"]["hausdorff_references"] == ["south"]
    assert by["south backwards"]["hausdorff"]["directed_m"] == pytest.approx(0.0, abs=1e-6)
    assert by["nowhere"]["hausdorff"] is None and by["nowhere"]["hausdorff_references"] == []
    h = m["hausdorff"]
    assert h["n"] == 2 and h["n_paths"] == 3 and h["matched"] == {"given": {"matched": 2, "paths": 3}}
    diag = math.hypot(40, 40)
    assert h["mean_normalised"] == pytest.approx((by["bent"]["hausdorff"]["directed_m"] + 0.0) / 2 / diag)
    # the reference paths themselves are not measured
    assert all("hausdorff" not in p for p in m["paths"] if p["group"] == "reference")
    report = (out / "report.md").read_text()
    assert "within 3.0 m of a reference path's ends" in report and "matched: 2 of 3 given" in report
    csv = (out / "pairs.csv").read_text()
    assert "north;north low" in csv


def test_no_matching_reference_means_no_hausdorff_anywhere(tmp_path: Path) -> None:
    grid = utm_grid(40, 40)
    labels_tif = write_array(tmp_path / "gt.tif", np.full((40, 40), 2, dtype=np.uint8), grid)
    classes = write_classes(tmp_path / "classes.json")
    refs = write_lines(tmp_path / "ref.geojson", grid, [[(10, 0), (10, 39)]])
    paths = write_lines(tmp_path / "paths.geojson", grid, [[(30, 0), (30, 39)]], names=["far"])
    out = tmp_path / "out"
    evaluate_paths(EvaluateOptions(out_dir=out, labels=labels_tif, classes=classes, paths=paths, reference=refs))
    m = json.loads((out / "metrics.json").read_text())
    assert m["hausdorff"]["mean_normalised"] is None and m["hausdorff"]["n"] == 0
    assert "No evaluated path shares its start and goal" in (out / "report.md").read_text()
    from overseec_core.commands.eval import summary_lines

    assert "Hausdorff: no path shares its start and goal with a reference path" in summary_lines(m)
    assert render_report(m).count("## Hausdorff") == 1
