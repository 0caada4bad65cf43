"""The rank-optimal reference of `overseec eval`: the rank costmap, the optimal RRPI, ratios."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from overseec_core.errors import PlanError
from overseec_core.evaluate import (
    ClassTable,
    EvaluateOptions,
    RankOptimalPlanner,
    evaluate_paths,
    parse_ranks,
    rank_costmap,
    rank_optimal_rrpi,
    rank_scale,
    rrpi,
    rrpi_ratio,
    summarise_ratios,
)
from overseec_core.io.write import write_array

from .test_evaluate import CLASSES, utm_grid, write_classes

TABLE = ClassTable(CLASSES)  # 0 unlabeled, 1 road, 2 grass, 3 water (Hydro)


def test_rank_costmap_encodes_the_ranks_exactly() -> None:
    labels = np.array([[1, 2, 3, 0], [9, 1, 255, 2]], dtype=np.uint8)
    ranks = parse_ranks("road=1,grass=2,water=5", TABLE)  # unranked = max = 5, K = 5
    assert rank_scale(ranks) == 5
    cost = rank_costmap(labels, ranks, nodata=255)
    assert cost.dtype == np.float32 and cost.shape == labels.shape
    np.testing.assert_array_equal(cost[0], np.float32([0.0, 0.25, 1.0, 1.0]))  # unlabeled: unranked
    assert cost[1, 0] == 1.0 and cost[1, 1] == 0.0 and math.isnan(cost[1, 2]) and cost[1, 3] == 0.25
    # an unranked rank above every class rank sets K
    wide = parse_ranks("road=1,grass=2", TABLE, unranked=3)
    assert rank_scale(wide) == 3
    np.testing.assert_array_equal(rank_costmap(labels, wide)[0], np.float32([0.0, 0.5, 1.0, 1.0]))
    # K == 1: every class is as good as every other
    flat = parse_ranks("road=1", TABLE)
    assert rank_scale(flat) == 1 and not rank_costmap(labels, flat).any()
    # a nodata value that is also a ranked class is still nodata
    assert math.isnan(rank_costmap(labels, ranks, nodata=1)[0, 0])


def test_rrpi_ratio_edge_cases() -> None:
    assert rrpi_ratio(0, 0) == 1.0
    assert rrpi_ratio(5, 0) == math.inf
    assert rrpi_ratio(9, 4) == 2.25
    assert rrpi_ratio(3, 4) == 0.75  # possible: the planner minimises metres, RRPI counts pixels


def corridor_scene() -> tuple[np.ndarray, tuple[int, int], tuple[int, int]]:
    """7 x 9 of water (rank 3) with a one-pixel road corridor (rank 1) shaped like a U on its side."""
    labels = np.full((7, 9), 3, dtype=np.uint8)
    labels[1, 1:8] = 1
    labels[1:6, 7] = 1
    labels[5, 1:8] = 1
    return labels, (1, 1), (5, 1)


def test_the_optimal_route_follows_a_one_pixel_corridor() -> None:
    labels, start, goal = corridor_scene()
    ranks = parse_ranks("road=1,grass=2,water=3", TABLE)
    best = RankOptimalPlanner(labels, ranks).optimum(start, goal)
    assert best.rrpi == 0
    assert (labels[best.pixels[:, 0], best.pixels[:, 1]] == 1).all(), "the optimum left the corridor"
    assert tuple(best.pixels[0]) == start and tuple(best.pixels[-1]) == goal
    assert (1, 7) in map(tuple, best.pixels) or (2, 7) in map(tuple, best.pixels)  # it went round
    assert rank_optimal_rrpi(labels, ranks, start, goal) == 0
    # the straight cut through the water: 3 water pixels of rank 3 -> RRPI 6, ratio infinite
    cut = np.array([(r, 1) for r in range(1, 6)])
    assert rrpi(labels, cut, ranks) == 6 and rrpi_ratio(6, 0) == math.inf


def test_a_route_through_worse_terrain_has_a_ratio_above_one() -> None:
    """5 x 9 of grass (rank 2) with a road (rank 1) on row 2; start and goal on row 0.

    Along row 0 the route crosses 9 grass pixels (RRPI 9); the best route drops to the road and
    climbs back: its start, its goal and one grass pixel on each side (RRPI 4).
    """
    labels = np.full((5, 9), 2, dtype=np.uint8)
    labels[2, :] = 1
    ranks = parse_ranks("road=1,grass=2", TABLE)
    best = rank_optimal_rrpi(labels, ranks, (0, 0), (0, 8))
    straight = rrpi(labels, np.array([(0, c) for c in range(9)]), ranks)
    assert (straight, best) == (9, 4) and rrpi_ratio(straight, best) == 2.25
    # the same with non-square pixels and a zero base cost (the ranks still decide)
    assert rank_optimal_rrpi(labels, ranks, (0, 0), (0, 8), pixel_size_m=(2.0, 0.5), base_cost_per_m=0.0) == 4


def test_no_optimum_across_label_nodata() -> None:
    labels = np.full((5, 9), 2, dtype=np.uint8)
    labels[:, 4] = 255  # a nodata wall
    ranks = parse_ranks("road=1,grass=2", TABLE)
    planner = RankOptimalPlanner(labels, ranks, nodata=255)
    assert planner.optimum((0, 0), (4, 3)).rrpi == 5
    with pytest.raises(PlanError):
        planner.optimum((0, 0), (0, 8))
    with pytest.raises(PlanError):
        planner.optimum((0, 4), (0, 0))  # an end on nodata


def test_summarise_ratios() -> None:
    s = summarise_ratios([0, 9, 10, 3, 7], [0, 4, 10, 0, None])
    # ratios 1, 2.25, 1, inf; one path without an optimum
    assert s["n"] == 4 and s["n_without_optimum"] == 1 and s["n_infinite"] == 1
    assert s["median_ratio"] == pytest.approx(1.625) and s["share_within_5pct"] == 0.5
    assert s["worst_ratio"] is None and s["best_ratio"] == 1.0
    assert s["mean_excess_rrpi"] == pytest.approx((0 + 5 + 0 + 3) / 4)
    assert summarise_ratios([2, 4], [2, 2])["worst_ratio"] == 2.0
    assert summarise_ratios([1], [None]) == {"n": 0, "n_without_optimum": 1}


# ---------------------------------------------------------------------------------- in `evaluate`


def _cross_scene(tmp_path: Path, cost_of: dict[int, float]) -> dict[str, Path]:
    """60 x 80 px of grass with a road cross; the costmap gives each class ``cost_of[class]``."""
    grid = utm_grid(80, 60)
    labels = np.full((60, 80), 2, dtype=np.uint8)
    labels[30, :] = 1
    labels[:, 40] = 1
    labels[45:55, 5:25] = 3
    table = np.array([cost_of.get(k, 1.0) for k in range(4)], dtype=np.float32)
    return {
        "labels": write_array(tmp_path / "labels.tif", labels, grid),
        "costmap": write_array(tmp_path / "cost.tif", table[labels], grid),
        "classes": write_classes(tmp_path / "classes.json"),
    }


def test_a_costmap_equal_to_the_rank_costmap_is_rank_optimal(tmp_path: Path) -> None:
    # ranks road=1, grass=2, water=3 -> rank costs 0, 0.5, 1: the costmap is exactly the rank costmap
    s = _cross_scene(tmp_path, {1: 0.0, 2: 0.5, 3: 1.0})
    out = tmp_path / "out"
    evaluate_paths(
        EvaluateOptions(
            out_dir=out,
            labels=s["labels"],
            classes=s["classes"],
            ranks="road=1,grass=2,water=3",
            costmap=s["costmap"],
            pairs=12,
            seed=2,
            plots=False,
        )
    )
    m = json.loads((out / "metrics.json").read_text())
    sampled = [p for p in m["paths"] if p["group"] == "sampled"]
    assert len(sampled) == 12
    for p in sampled:
        assert p["rrpi_optimal"] == p["rrpi"] and p["rrpi_ratio"] == 1.0 and not p["rrpi_ratio_infinite"]
    g = m["rank_optimal"]["groups"]["sampled"]
    assert m["rank_optimal"]["headline"] == "sampled"
    assert (g["n"], g["median_ratio"], g["share_within_5pct"], g["worst_ratio"]) == (12, 1.0, 1.0, 1.0)
    report = (out / "report.md").read_text()
    assert "## Rank-optimal reference" in report and "| sampled | 12 | 1.000 | 100 % | 1.000 | 0.0 |" in report
    header = (out / "pairs.csv").read_text().splitlines()[0].split(",")
    assert "rrpi_optimal" in header and "rrpi_ratio" in header


def test_a_road_avoiding_costmap_is_far_from_rank_optimal(tmp_path: Path) -> None:
    s = _cross_scene(tmp_path, {1: 0.9, 2: 0.1, 3: 0.1})
    out = tmp_path / "out"
    evaluate_paths(
        EvaluateOptions(
            out_dir=out,
            labels=s["labels"],
            classes=s["classes"],
            ranks="road=1,grass=2",
            costmap=s["costmap"],
            pairs=12,
            seed=2,
            plots=False,
        )
    )
    m = json.loads((out / "metrics.json").read_text())
    g = m["rank_optimal"]["groups"]["sampled"]
    assert g["n"] == 12 and g["best_ratio"] >= 1.0
    assert g["median_ratio"] is None or g["median_ratio"] > 1.05
    assert g["share_within_5pct"] < 0.5
    for p in m["paths"]:
        assert p["rrpi_optimal"] <= p["rrpi"]
