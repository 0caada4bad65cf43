"""Directional invariants of prompts on planned routes, on the real scenes and the sample (issue 9).

Each case (tests/invariants_data.py) is a pair of prompts and the effect prompt A must have on the
route planned between fixed pixels, compared with prompt B: "avoid X" lowers the share of route
length on X, "prefer X" raises it, "X is impassable" makes it zero, "keep N m from X" keeps the
route >= N m from X where possible and warns otherwise, "X is fine" vs "avoid X" moves the route.
Every measure is in ground metres (step lengths, Euclidean distance transform with the pixel size
of the grid). The premise of each case (the baseline route touches X, comes closer than N m, ...)
is asserted too, so a case cannot pass because its points say nothing.

Pipeline under test: prompt -> overseec_core.pipeline.run_costmap (offline interpreter, entity
matching, cost program) -> overseec_core.plan.load_costmap -> plan.stage.plan_keeping_rules.

RRPI: on the New Brunswick clips and the sample, a prompt with hand-stated ranks is planned
between 100 seeded random pairs; its route's RRPI must be within 1.05x of the rank-optimal
route's on >= 90 % of the pairs. The per-scene summary is printed (``-s``) and recorded with
``record_property`` (``--junitxml``).

Run: QT_QPA_PLATFORM=offscreen .venv/bin/python -m pytest tests/test_invariants.py -q
"""

from __future__ import annotations

import json
import math
import re
from functools import cache
from pathlib import Path

import numpy as np
import pytest
import rasterio
from scipy.ndimage import distance_transform_edt
from scipy.spatial.distance import directed_hausdorff

from overseec_core import evaluate
from overseec_core.errors import PlanError
from overseec_core.pipeline import run_costmap
from overseec_core.plan import Planner, PlanningGrid, load_costmap
from overseec_core.plan.paths import step_lengths_m
from overseec_core.plan.stage import plan_keeping_rules
from overseec_core.synthesize.options import CostmapOptions

from .invariants_data import (
    CASES,
    POINTS,
    RRPI_CASES,
    RRPI_PAIRS,
    RRPI_PASS_SHARE,
    RRPI_SEED,
    RRPI_TOLERANCE,
    SCENE_FILES,
    InvariantCase,
    all_prompts,
)

#: Seconds one case may take (costmaps and plans here take well under a second each; a case that
#: runs this long is stuck, e.g. in entity matching).
CASE_TIMEOUT_S = 60
WARNING_MARK = "cannot be met"
EPS_M = 1e-6


# --------------------------------------------------------------------------------------------
# Harness: costmaps and routes, cached for the session
# --------------------------------------------------------------------------------------------


def _need_scene(scene: str) -> None:
    s = SCENE_FILES[scene]
    if not (s.labels.exists() and s.classes.exists()):
        pytest.skip(f"scene {scene} not found at {s.labels.parent}")


@cache
def _labels(scene: str) -> tuple[np.ndarray, float | None]:
    with rasterio.open(SCENE_FILES[scene].labels) as ds:
        return ds.read(1), ds.nodata


@cache
def _class_ids(scene: str, names: tuple[str, ...]) -> tuple[int, ...]:
    table = evaluate.load_classes(SCENE_FILES[scene].classes)
    ids = []
    for n in names:
        cid = table.lookup(n)
        assert cid is not None, f"{scene}: no class {n!r} ({table.describe()})"
        ids.append(cid)
    return tuple(ids)


@cache
def _class_mask(scene: str, names: tuple[str, ...]) -> np.ndarray:
    labels, _ = _labels(scene)
    return np.isin(labels, _class_ids(scene, names))


@cache
def _distance_to(scene: str, names: tuple[str, ...], pixel_size_m: tuple[float, float]) -> np.ndarray:
    """Ground metres from each pixel centre to the nearest pixel of the classes (0 on them)."""
    mask = _class_mask(scene, names)
    assert mask.any(), f"{scene}: no pixel of {names}"
    dx, dy = pixel_size_m
    return distance_transform_edt(~mask, sampling=(dy, dx))


class _Stuck(Exception):
    pass


@cache
def _matching_terminates(scene: str) -> str | None:
    """None, or the reproduction of a hang in entity matching on this scene's layers.

    Matching is pure Python over a few names (microseconds); it is tried here for the entities
    the offline interpreter always lists under a SIGALRM time limit, so a matching bug fails the
    scene's cases at once instead of hanging the suite.
    """
    import signal
    import threading

    from overseec_core.interpret.matching import match_entity
    from overseec_core.synthesize.layers import load_class_entities

    layers = sorted(set(load_class_entities(SCENE_FILES[scene].classes).values()))
    entities = [
        "road",
        "trail",
        "grass",
        "tree",
        "water",
        "building",
        "railway",
        "vegetation",
        "lake",
        "woods",
        "house",
        "street",
        "tracks",
    ]
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "setitimer"):
        return None

    def alarm(signum, frame):
        raise _Stuck

    import time

    pending, _ = signal.getitimer(signal.ITIMER_REAL)  # pytest-timeout's alarm, re-armed below
    t0 = time.monotonic()
    previous = signal.signal(signal.SIGALRM, alarm)
    try:
        for e in entities:
            signal.setitimer(signal.ITIMER_REAL, 2.0)
            try:
                match_entity(e, layers)
            except _Stuck:
                return (
                    f"entity matching does not terminate on {scene}'s layers: "
                    f"overseec_core.interpret.matching.match_entity({e!r}, {layers!r}) loops"
                )
            finally:
                signal.setitimer(signal.ITIMER_REAL, 0)
    finally:
        signal.signal(signal.SIGALRM, previous)
        if pending > 0:
            signal.setitimer(signal.ITIMER_REAL, max(pending - (time.monotonic() - t0), 0.01))
    return None


class Harness:
    """Costmaps (one per scene, prompt and aliases) and routes, built once per session."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self._grids: dict[tuple, tuple[PlanningGrid, object]] = {}
        self._routes: dict[tuple, object] = {}
        self._made = 0

    def costmap(self, scene: str, prompt: str, aliases=()) -> tuple[PlanningGrid, object]:
        key = (scene, prompt, tuple(aliases))
        if key not in self._grids:
            _need_scene(scene)
            problem = _matching_terminates(scene)
            if problem:
                pytest.fail(problem, pytrace=False)
            self._made += 1
            out = self.root / f"cm{self._made:03d}" / "costmap.tif"
            out.parent.mkdir(parents=True)
            s = SCENE_FILES[scene]
            result = run_costmap(
                CostmapOptions(out=out, labels=s.labels, classes=s.classes, prompt=prompt, aliases=tuple(aliases))
            )
            self._grids[key] = (load_costmap(out), result)
        return self._grids[key]

    def route(self, scene: str, prompt: str, points: str, aliases=()):
        key = (scene, prompt, tuple(aliases), points)
        if key not in self._routes:
            grid, _ = self.costmap(scene, prompt, aliases)
            start, goal = POINTS[scene][points]
            res, _ = plan_keeping_rules(grid, [start, goal])
            self._routes[key] = res
        return self._routes[key]


@pytest.fixture(scope="session")
def harness(tmp_path_factory: pytest.TempPathFactory) -> Harness:
    return Harness(tmp_path_factory.mktemp("invariants"))


# --------------------------------------------------------------------------------------------
# Measures (ground metres)
# --------------------------------------------------------------------------------------------


def share_on(pixels: np.ndarray, mask: np.ndarray, pixel_size_m: tuple[float, float]) -> float:
    """Share of the route's ground length on ``mask``: each step counts by its two ends."""
    px = np.asarray(pixels, dtype=np.int64)
    steps = step_lengths_m(px, *pixel_size_m)
    total = float(steps.sum())
    if total == 0:
        return float(mask[px[0, 0], px[0, 1]])
    on = mask[px[:, 0], px[:, 1]].astype(np.float64)
    return float((steps * 0.5 * (on[1:] + on[:-1])).sum() / total)


def distances_along(pixels: np.ndarray, dist: np.ndarray) -> np.ndarray:
    px = np.asarray(pixels, dtype=np.int64)
    return dist[px[:, 0], px[:, 1]]


def mean_distance(pixels: np.ndarray, dist: np.ndarray, pixel_size_m: tuple[float, float]) -> float:
    """Length-weighted mean distance from the route to the class."""
    px = np.asarray(pixels, dtype=np.int64)
    d = distances_along(px, dist)
    steps = step_lengths_m(px, *pixel_size_m)
    if steps.sum() == 0:
        return float(d[0])
    return float((steps * 0.5 * (d[1:] + d[:-1])).sum() / steps.sum())


def hausdorff_m(a: np.ndarray, b: np.ndarray, pixel_size_m: tuple[float, float]) -> float:
    """Symmetric Hausdorff distance between two pixel routes, in ground metres."""
    ma, mb = evaluate.to_metres(a, pixel_size_m), evaluate.to_metres(b, pixel_size_m)
    return max(directed_hausdorff(ma, mb)[0], directed_hausdorff(mb, ma)[0])


def warned(result) -> bool:
    return any(WARNING_MARK in n for n in result.notes)


# --------------------------------------------------------------------------------------------
# The suite's own promises
# --------------------------------------------------------------------------------------------

REQUIRED_FAMILIES = {
    "plain",
    "strength",
    "negation",
    "exception",
    "last_resort",
    "comparative",
    "concealment",
    "permission",
    "stay_off",
    "cross_country",
    "distance",
    "synonym",
    "impassable",
}


def test_at_least_40_distinct_prompts() -> None:
    prompts = all_prompts()
    assert len(prompts) >= 40, f"only {len(prompts)} distinct prompts"


def test_every_phrasing_family_and_relation_is_covered() -> None:
    families = {part for c in CASES for part in re.split(r"[+]", c.family)}
    families |= {"negation", "exception"} if "negation+exception" in {c.family for c in CASES} else set()
    assert REQUIRED_FAMILIES <= families, f"missing families: {REQUIRED_FAMILIES - families}"
    relations = {c.relation.split(">=")[0].split("<=")[0] for c in CASES}
    assert {"less_on", "more_on", "zero_on", "min_distance", "moves"} <= relations
    ids = [c.id for c in CASES]
    assert len(ids) == len(set(ids)), "case ids must be unique"
    for c in CASES:
        assert c.points in POINTS[c.scene], c.id
        if "or warn" in c.relation:
            assert c.expect_warning is not None, f"{c.id}: say whether the rule can be met"


def test_points_are_valid_pixels() -> None:
    """Every start/goal is inside its raster and not on label nodata."""
    for scene, pairs in POINTS.items():
        s = SCENE_FILES[scene]
        if not s.labels.exists():
            continue
        labels, nodata = _labels(scene)
        for name, pts in pairs.items():
            for r, c in pts:
                assert 0 <= r < labels.shape[0] and 0 <= c < labels.shape[1], (scene, name, (r, c))
                if nodata is not None:
                    assert labels[r, c] != nodata, (scene, name, (r, c))


# --------------------------------------------------------------------------------------------
# Directional invariants
# --------------------------------------------------------------------------------------------


def _scene_marks(case: InvariantCase):
    return [] if SCENE_FILES[case.scene].bundled else [pytest.mark.scenes]


@pytest.mark.timeout(CASE_TIMEOUT_S)
@pytest.mark.parametrize("case", [pytest.param(c, id=c.id, marks=_scene_marks(c)) for c in CASES])
def test_invariant(case: InvariantCase, harness: Harness, record_property) -> None:  # noqa: C901
    grid_a, cm_a = harness.costmap(case.scene, case.prompt_a, case.aliases)
    grid_b, _ = harness.costmap(case.scene, case.prompt_b, case.aliases)
    route_a = harness.route(case.scene, case.prompt_a, case.points, case.aliases)
    route_b = harness.route(case.scene, case.prompt_b, case.points, case.aliases)
    size = grid_a.pixel_size_m
    mask = _class_mask(case.scene, case.classes)
    what = (
        f"{case.scene} {POINTS[case.scene][case.points]} on {'/'.join(case.classes)}: "
        f"A={case.prompt_a!r} vs B={case.prompt_b!r}\n  program A notes: "
        f"{'; '.join(cm_a.notes[-2:])}"
    )
    rel = case.relation
    measured: dict[str, float] = {}

    if rel in ("less_on", "more_on", "zero_on"):
        a, b = share_on(route_a.pixels, mask, size), share_on(route_b.pixels, mask, size)
        measured = {"share_a": a, "share_b": b}
        if rel == "less_on":
            assert b > 0, f"premise: the baseline route does not touch the class ({what})"
            assert a < b, f"'avoid' did not lower the share on the class: {a:.4f} >= {b:.4f} ({what})"
        elif rel == "more_on":
            assert b < 1, f"premise: the baseline route is already all on the class ({what})"
            assert a > b, f"'prefer' did not raise the share on the class: {a:.4f} <= {b:.4f} ({what})"
        else:
            assert b > 0, f"premise: the baseline route does not touch the class ({what})"
            assert not warned(route_a), f"unexpected rule warning {route_a.notes} ({what})"
            assert a == 0, f"route on an impassable class: share {a:.4f} ({what})"
    elif rel.startswith(("min_distance", "max_distance")):
        m = re.fullmatch(r"(min|max)_distance(>=|<=)([0-9.]+) or warn", rel)
        assert m, rel
        n_m = float(m.group(3))
        dist = _distance_to(case.scene, case.classes, size)
        da, db = distances_along(route_a.pixels, dist), distances_along(route_b.pixels, dist)
        measured = {
            "min_a": float(da.min()),
            "min_b": float(db.min()),
            "max_a": float(da.max()),
            "max_b": float(db.max()),
        }
        assert grid_a.keep_out is not None and grid_a.keep_out.any(), (
            f"the distance rule made no keep-out zone ({what})"
        )
        if m.group(1) == "min":
            assert db.min() < n_m, f"premise: the baseline already keeps {db.min():.2f} m >= {n_m} m ({what})"
        else:
            assert db.max() > n_m, f"premise: the baseline already stays within {n_m} m ({what})"
        if warned(route_a):
            with pytest.raises(PlanError):  # the warning is honest: no route keeps the rule
                Planner(grid_a).plan(list(POINTS[case.scene][case.points]))
            assert case.expect_warning is not False, (
                f"warned although a route keeping the rule was expected: {route_a.notes} ({what})"
            )
        else:
            assert case.expect_warning is not True, (
                f"no 'cannot be met' warning where no route can keep the rule ({what})"
            )
            if m.group(1) == "min":
                assert da.min() >= n_m - EPS_M, f"route comes {da.min():.2f} m < {n_m} m close ({what})"
            else:
                assert da.max() <= n_m + EPS_M, f"route goes {da.max():.2f} m > {n_m} m away ({what})"
    elif rel == "farther":
        dist = _distance_to(case.scene, case.classes, size)
        a = float(distances_along(route_a.pixels, dist).min())
        b = float(distances_along(route_b.pixels, dist).min())
        measured = {"min_a": a, "min_b": b}
        assert a > b, f"the route did not keep farther away: {a:.2f} m <= {b:.2f} m ({what})"
    elif rel == "closer":
        dist = _distance_to(case.scene, case.classes, size)
        a = mean_distance(route_a.pixels, dist, size)
        b = mean_distance(route_b.pixels, dist, size)
        measured = {"mean_a": a, "mean_b": b}
        assert b > 0, f"premise: the baseline route is already on the class ({what})"
        assert a < b, f"the route did not stay nearer: mean {a:.2f} m >= {b:.2f} m ({what})"
    elif rel == "moves":
        h = hausdorff_m(route_a.pixels, route_b.pixels, size)
        measured = {"hausdorff_m": h}
        assert h > 0, f"the route did not move (Hausdorff 0) ({what})"
    else:  # pragma: no cover - a typo in the data
        pytest.fail(f"unknown relation {rel!r}")
    record_property("measured", json.dumps(measured))


# --------------------------------------------------------------------------------------------
# RRPI within 1.05x of the rank-optimal route
# --------------------------------------------------------------------------------------------


@pytest.mark.timeout(300)
@pytest.mark.parametrize(
    "case_id",
    [pytest.param(c, marks=[] if SCENE_FILES[RRPI_CASES[c][0]].bundled else [pytest.mark.scenes]) for c in RRPI_CASES],
)
def test_rrpi_near_rank_optimal(case_id: str, harness: Harness, record_property) -> None:
    scene, prompt, rank_spec = RRPI_CASES[case_id]
    grid, _ = harness.costmap(scene, prompt)
    labels, nodata = _labels(scene)
    table = evaluate.load_classes(SCENE_FILES[scene].classes)
    ranks = evaluate.parse_ranks(rank_spec, table, unranked=2)
    rank_planner = evaluate.RankOptimalPlanner(labels, ranks, nodata, pixel_size_m=grid.pixel_size_m)
    h, w = grid.shape
    dx, dy = grid.pixel_size_m
    min_sep = evaluate.DEFAULT_MIN_SEPARATION_FRACTION * math.hypot(h * dy, w * dx)
    passable = grid.passable & rank_planner.grid.passable
    pairs = evaluate.sample_pairs(passable, RRPI_PAIRS, np.random.default_rng(RRPI_SEED), min_sep, grid.pixel_size_m)
    assert len(pairs) == RRPI_PAIRS
    values, optima, ratios, no_route = [], [], [], 0
    for start, goal in pairs:
        try:  # as users plan: keep-out zones (rules, obstacles) entered only where they must be
            res, _ = plan_keeping_rules(grid, [start, goal])
        except PlanError:  # lethal classes may cut the map; such pairs count as failures
            no_route += 1
            ratios.append(math.inf)
            continue
        value = evaluate.rrpi(labels, res.pixels, ranks, nodata)
        opt = rank_planner.optimum(start, goal).rrpi
        values.append(value)
        optima.append(opt)
        ratios.append(evaluate.rrpi_ratio(value, opt))
    r = np.array(ratios)
    summary = {
        "case": case_id,
        "scene": scene,
        "prompt": prompt,
        "pairs": len(pairs),
        "no_route": no_route,
        "pass_rate": float(np.mean(r <= RRPI_TOLERANCE)),
        "median_ratio": float(np.median(r)),
        "worst_ratio": float(r.max()),
        **{f"summary_{k}": v for k, v in evaluate.summarise_ratios(values, optima).items()},
    }
    record_property("rrpi", json.dumps(summary))
    print(f"\nRRPI {case_id}: {json.dumps(summary)}")
    assert summary["pass_rate"] >= RRPI_PASS_SHARE, (
        f"{case_id}: only {summary['pass_rate']:.0%} of {len(pairs)} routes within "
        f"{RRPI_TOLERANCE}x of the rank-optimal RRPI (median {summary['median_ratio']:.3f}, "
        f"worst {summary['worst_ratio']:.3f}) for {prompt!r}"
    )
