"""Mission language read by structure (issue 20): the corpus, the checks' own strictness, scene
invariants per phrasing family, and the priors figure.

- Corpus (tests/mission_prompts.py): >= 70 new prompts in nine phrasing families, each with
  machine-checked expectations measured on layers (the cost program fitted to the case's layers,
  evaluated with the cost language on synthetic probes), on the interpretation (cues, bands,
  notes) or on outcomes (costmap stage, CLI). ``bench/mission_language_report.py`` prints the
  pass rate per family.
- The checks are shown to fail on programs and interpretations that break them (a check that
  passes whatever the interpreter does is useless).
- Scene invariants: for families 1-6, a prompt moves the planned route the way it says, on the
  New Brunswick clips or the bundled sample (fixed pixels; the baseline's premise is asserted).
- Priors figure: with the paper's headline prompt, over 40 seeded start/goal pairs per scene
  (sample, nb1, nb2), the route metres on the unmentioned buildings and water stay within 1.2x
  of those of a route on a hand-written, paper-style rank costmap. Printed (``-s``) and recorded
  with ``record_property``.

Run: .venv/bin/python -m pytest -q -p no:cacheprovider tests/test_mission_language.py
"""

from __future__ import annotations

import json
import math
from functools import cache
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from overseec_core import evaluate
from overseec_core.errors import PlanError
from overseec_core.pipeline import run_costmap
from overseec_core.plan import Planner, load_costmap
from overseec_core.plan.paths import step_lengths_m
from overseec_core.plan.stage import plan_keeping_rules
from overseec_core.schema import Cue
from overseec_core.synthesize.layers import load_class_entities
from overseec_core.synthesize.options import CostmapOptions

from . import mission_prompts as mp
from . import mission_prompts_heldout as heldout
from . import mission_prompts_heldout2 as heldout2
from . import mission_prompts_heldout3 as heldout3
from .invariants_data import REPO, SCENE_FILES
from .test_invariants import Harness, _class_mask, _distance_to, _labels, share_on

# ==============================================================================================
# The corpus
# ==============================================================================================


def test_corpus_size_families_and_novelty() -> None:
    prompts = [c.prompt for c in mp.CASES]
    assert len(prompts) == len(set(prompts)), "a prompt appears twice"
    ids = [c.id for c in mp.CASES]
    assert len(ids) == len(set(ids)), "case ids must be unique"
    new = [p for p in prompts if p != mp.HEADLINE]
    assert len(new) >= mp.MIN_CASES, f"only {len(new)} new prompts"
    for family in mp.FAMILIES:
        n = sum(c.family == family for c in mp.CASES)
        assert n >= mp.MIN_PER_FAMILY, f"family {family}: only {n} prompts"
    assert {c.family for c in mp.CASES} <= set(mp.FAMILIES)
    old = mp.old_prompts(REPO)
    assert old, "the older prompt files were not found"
    copied = [p for p in new if mp.normalise_prompt(p) in old]
    assert not copied, f"prompts copied from {mp.OLD_PROMPT_FILES}: {copied}"


def test_every_case_is_well_formed() -> None:
    for c in mp.CASES:
        assert c.expect, c.id
        for e in c.expect:
            assert e[0] in mp.KINDS, (c.id, e)
            if e[0] in ("preferred", "neutral", "avoided", "lethal", "not_lethal", "no_cross", "no_no_cross"):
                assert e[1] in c.layers, f"{c.id}: {e} names a layer the case lacks"
            if e[0] in ("below", "not_below", "near_above_far", "near_below_far"):
                assert e[1] in c.layers and e[2] in c.layers, f"{c.id}: {e} names a layer the case lacks"
            if e[0] in ("band", "ge_prompt"):
                assert e[1] in c.layers, f"{c.id}: {e} names a layer the case lacks"
            if e[0] == "far_band":
                assert e[1] in c.layers and e[2] in c.layers and e[3] in mp.BANDS, (c.id, e)
            if e[0] == "band":
                assert e[2] in mp.BANDS, (c.id, e)
            if e[0] == "cli_band":
                assert e[2] in mp.BANDS, (c.id, e)
    prompts = {c.prompt for c in mp.CASES}
    assert set(mp.DOUBTFUL) <= prompts, f"doubts about prompts not in the corpus: {set(mp.DOUBTFUL) - prompts}"
    # family 1 contrasts the two readings; family 6 both the hard and the soft one
    f1 = [e[0] for c in mp.CASES if c.family == "negation_motion" for e in c.expect]
    assert "preferred" in f1 and "avoided" in f1
    f6 = [e[0] for c in mp.CASES if c.family == "no_cross" for e in c.expect]
    assert "no_cross" in f6 and "no_no_cross" in f6


#: The held-out sets, oldest first: (module, its cases). Each must not repeat the corpus, the older
#: tests or an earlier set.
HELDOUT_SETS = [(heldout, heldout.HELDOUT), (heldout2, heldout2.HELDOUT2), (heldout3, heldout3.HELDOUT3)]


@pytest.mark.parametrize("index", range(len(HELDOUT_SETS)), ids=["heldout", "heldout2", "heldout3"])
def test_heldout_set_format(index: int) -> None:
    """A held-out set's format only: its pass rate is a measurement
    (``bench/mission_language_report.py --heldout[2|3]``), never asserted here."""
    module, cases = HELDOUT_SETS[index]
    prompts = [c.prompt for c in cases]
    assert len(prompts) >= module.MIN_CASES >= 50, f"only {len(prompts)} prompts"
    assert len({mp.normalise_prompt(p) for p in prompts}) == len(prompts), "a prompt appears twice"
    assert len({c.id for c in cases}) == len(cases), "case ids must be unique"
    assert {c.family for c in cases} <= set(mp.FAMILIES)
    for family in mp.FAMILIES:
        n = sum(c.family == family for c in cases)
        assert n >= module.MIN_PER_FAMILY >= 5, f"family {family}: only {n} prompts"
    old = module.old_prompts(REPO)
    assert {mp.normalise_prompt(c.prompt) for c in mp.CASES} <= old, "the main corpus was not read"
    for _, earlier in HELDOUT_SETS[:index]:
        assert {mp.normalise_prompt(c.prompt) for c in earlier} <= old, "an earlier held-out set was not read"
    assert mp.normalise_prompt("avoid $schema and ${defaults} $$") in old, "tests/interpret/*.py were not read"
    copied = [p for p in prompts if mp.normalise_prompt(p) in old]
    assert not copied, f"prompts copied from the corpus, an earlier set or the older tests: {copied}"
    problems = [p for c in cases for p in mp.format_problems(c)]
    assert not problems, problems
    assert set(module.DOUBTFUL) <= set(prompts), "doubts about prompts not in the set"


@pytest.mark.parametrize("case", [pytest.param(c, id=c.id) for c in mp.CASES])
def test_mission_prompt(case: mp.Case, tmp_path: Path, record_property) -> None:
    failures = mp.check_case(case, tmp_path)
    record_property("failures", json.dumps(failures))
    assert not failures, f"{case.prompt!r} on layers {list(case.layers)}:\n  " + "\n  ".join(failures)


# ==============================================================================================
# The checks fail where they should (independent of the interpreter)
# ==============================================================================================

LAYERS = ("road", "trail", "water", "building")


def _reading(program: str, prefs=(), cues=(), notes=(), unparsed=(), mapping=()) -> mp.Reading:
    """A Reading with a hand-written program and a stand-in interpretation."""
    interp = SimpleNamespace(preferences=tuple(prefs), cues=tuple(cues), notes=tuple(notes), unparsed=tuple(unparsed))
    resolved = SimpleNamespace(text=program, mapping=tuple(mapping), notes=())
    return mp.Reading("(hand-written)", LAYERS, interp, resolved)


PROGRAM = (
    'acc = sum(-0.3 * P["road"], 0.2 * P["building"], -0.1 * P["trail"])\n'
    "cost = clip(0.5 + acc, 0.0, 1.0)\n"
    'lethal = M["water"]\n'
)


def test_layer_cost_reads_the_program() -> None:
    assert mp.layer_cost(PROGRAM, LAYERS, ("road",)) == pytest.approx((0.2, False, False))
    assert mp.layer_cost(PROGRAM, LAYERS, ("building",))[:2] == (pytest.approx(0.7), False)
    assert mp.layer_cost(PROGRAM, LAYERS, ("water",))[1] is True
    assert mp.layer_cost(PROGRAM, LAYERS, ())[0] == pytest.approx(0.5)  # empty ground: neutral
    # near / far: the other layer 3 px or 40 px from the probe
    cond = 'cost = 0.5 + 0.3 * M["trail"] * (distance(M["water"]) < 10)\n'
    assert mp.layer_cost(cond, LAYERS, ("trail",), near="water", gap=3)[0] == pytest.approx(0.8)
    assert mp.layer_cost(cond, LAYERS, ("trail",), near="water", gap=40)[0] == pytest.approx(0.5)


def test_level_and_order_checks_fail_when_broken() -> None:
    r = _reading(PROGRAM)
    assert mp._level(r, "preferred", "road") is None
    assert mp._level(r, "preferred", "building") is not None
    assert mp._level(r, "avoided", "road") is not None
    assert mp._level(r, "neutral", "road") is not None
    assert mp._level(r, "avoided", "water") is not None  # lethal is not "avoided"
    assert mp._level(r, "lethal", "water") is None and mp._level(r, "not_lethal", "water") is not None
    assert mp._order(r, "below", "road", "trail") is None
    assert mp._order(r, "below", "trail", "road") is not None
    assert mp._order(r, "below", "road", "road") is not None  # strict
    assert mp._order(r, "below", "road", "water") is not None  # a lethal side fails
    assert mp._order(r, "not_below", "building", "road") is None
    assert mp._order(r, "not_below", "road", "building") is not None
    neutral = _reading('cost = 0.5 + 0 * P["road"]\n')
    assert mp._level(neutral, "neutral", "road") is None


def test_condition_checks_fail_when_broken() -> None:
    unless = _reading('cost = 0.5 + 0.3 * M["trail"] * (distance(M["water"]) < 10)\n')
    assert mp._condition(unless, "far_band", "trail", "water", "neutral") is None
    assert mp._condition(unless, "near_above_far", "trail", "water") is None
    assert mp._condition(unless, "near_below_far", "trail", "water") is not None
    flat = _reading('cost = 0.5 + 0.3 * P["trail"] + 0 * P["water"]\n')  # uniform on the trail
    assert mp._condition(flat, "near_above_far", "trail", "water") is not None
    assert mp._condition(flat, "far_band", "trail", "water", "neutral") is not None
    except_near = _reading('cost = 0.5 + 0.3 * M["trail"] * (distance(M["water"]) > 10)\n')
    assert mp._condition(except_near, "far_band", "trail", "water", "avoided") is None
    assert mp._condition(except_near, "near_below_far", "trail", "water") is None


def test_interpretation_checks_fail_when_broken() -> None:
    class Pref(SimpleNamespace):
        pass

    prior = Pref(entity="building", phrase="", prior=True, band="prior")
    stated = Pref(entity="house", phrase="avoid the houses", prior=False, band="avoided")
    mapping = (
        SimpleNamespace(entity="house", layers=("building",)),
        SimpleNamespace(entity="building", layers=("building",)),
    )
    r = _reading(PROGRAM, prefs=[prior], mapping=mapping)
    assert mp._band(r, "building", "prior") is None
    assert mp._band(r, "building", "avoided") is not None
    r2 = _reading(PROGRAM, prefs=[prior, stated], mapping=mapping)
    assert mp._band(r2, "building", "avoided") is None  # the stated one counts
    assert mp._band(r2, "building", "prior") is not None
    no_band = _reading(PROGRAM, prefs=[Pref(entity="building", phrase="", prior=True)], mapping=mapping)
    assert mp._band(no_band, "building", "prior") is not None
    hard = Cue(kind="no_cross", entity="railway", hard=True)
    soft = Cue(kind="no_cross", entity="railway", hard=False)
    rail = (SimpleNamespace(entity="railway", layers=("road",)),)
    assert mp._cross(_reading(PROGRAM, cues=[hard], mapping=rail), "no_cross", "road") is None
    assert mp._cross(_reading(PROGRAM, cues=[soft], mapping=rail), "no_cross", "road") is not None
    assert mp._cross(_reading(PROGRAM, cues=[], mapping=rail), "no_cross", "road") is not None
    assert mp._cross(_reading(PROGRAM, cues=[hard], mapping=rail), "no_no_cross", "road") is not None
    assert mp._cross(_reading(PROGRAM, cues=[], mapping=rail), "no_no_cross", "road") is None
    noted = _reading(PROGRAM, notes=["read 'vegitation' as vegetation"], unparsed=["blah"])
    assert mp._note_quotes(noted, "vegitation") is None
    assert mp._note_quotes(noted, "raod") is not None
    assert mp._note_quotes(_reading(PROGRAM, notes=["read vegitation as vegetation"]), "vegitation") is not None
    assert mp._not_unparsed(noted, "blah") is not None and mp._not_unparsed(noted, "vegitation") is None


def test_outcome_checks_fail_when_broken(tmp_path: Path) -> None:
    nonsense = mp.Case("Good evening, everybody!", "outcome", mp.SAMPLE_LAYERS, ())
    clear = mp.Case("prefer the road and avoid the water", "outcome", mp.SAMPLE_LAYERS, ())
    assert mp._outcome(clear, "costmap_ok", tmp_path / "a", {}) is None
    assert mp._outcome(clear, "error", tmp_path / "b", {}) is not None
    assert mp._outcome(clear, "permission_note", tmp_path / "c", {}) is not None  # it avoids: not permission only
    assert mp._cli_exit(clear, 2, tmp_path / "d") is not None
    assert mp._cli_exit(nonsense, 2, tmp_path / "e") is None
    assert mp._cli_band(clear, "road", "avoided", {}) is not None
    assert mp._cli_band(clear, "nosuchthing", "avoided", {}) is not None


# ==============================================================================================
# Scene invariants, one or more per family 1-6
# ==============================================================================================


class SceneHarness(Harness):
    """The invariants harness, plus costmaps from hand-written program text."""

    def program_costmap(self, scene: str, text: str):
        key = (scene, "program:" + text, ())
        if key not in self._grids:
            self._made += 1
            out = self.root / f"pg{self._made:03d}" / "costmap.tif"
            out.parent.mkdir(parents=True)
            s = SCENE_FILES[scene]
            result = run_costmap(CostmapOptions(out=out, labels=s.labels, classes=s.classes, program_text=text))
            self._grids[key] = (load_costmap(out), result)
        return self._grids[key]


@pytest.fixture(scope="module")
def scenes(tmp_path_factory: pytest.TempPathFactory) -> SceneHarness:
    return SceneHarness(tmp_path_factory.mktemp("mission"))


def _need(scene: str) -> None:
    s = SCENE_FILES[scene]
    if not (s.labels.exists() and s.classes.exists()):
        pytest.skip(f"scene {scene} not found at {s.labels.parent}")


def _marks(scene: str) -> list:
    return [] if SCENE_FILES[scene].bundled else [pytest.mark.scenes]


def _route(scenes: SceneHarness, scene: str, prompt: str, points):
    grid, result = scenes.costmap(scene, prompt)
    try:
        res, _ = plan_keeping_rules(grid, list(points))
    except PlanError as exc:  # e.g. a clause made lethal what it never named
        pytest.fail(f"{scene}: no route for {prompt!r} between {points}: {exc}", pytrace=False)
    return grid, result, res


@pytest.mark.timeout(120)
@pytest.mark.parametrize("case", [pytest.param(c, id=c.id, marks=_marks(c.scene)) for c in mp.SCENE_CASES])
def test_scene_invariant(case: mp.SceneCase, scenes: SceneHarness, record_property) -> None:
    _need(case.scene)
    points = (case.start, case.goal)
    labels, nodata = _labels(case.scene)
    for r, c in points:
        assert 0 <= r < labels.shape[0] and 0 <= c < labels.shape[1] and (nodata is None or labels[r, c] != nodata)
    grid_a, cm_a, route_a = _route(scenes, case.scene, case.prompt_a, points)
    grid_b, _, route_b = _route(scenes, case.scene, case.prompt_b, points)
    size = grid_a.pixel_size_m
    mask = _class_mask(case.scene, case.classes)
    what = (
        f"{case.scene} {points} on {'/'.join(case.classes)}: A={case.prompt_a!r} vs B={case.prompt_b!r}\n"
        f"  program A notes: {'; '.join(cm_a.notes[-2:])}"
    )
    a, b = share_on(route_a.pixels, mask, size), share_on(route_b.pixels, mask, size)
    measured = {"share_a": a, "share_b": b}
    rel = case.relation
    if rel == "less_on":
        assert b > 0, f"premise: the baseline route does not touch the class ({what})"
        assert a < b, f"A did not lower the share on the class: {a:.4f} >= {b:.4f} ({what})"
    elif rel == "more_on":
        assert b < 1, f"premise: the baseline route is already all on the class ({what})"
        assert a > b, f"A did not raise the share on the class: {a:.4f} <= {b:.4f} ({what})"
    elif rel == "zero_on":
        assert b > 0, f"premise: the baseline route does not touch the class ({what})"
        assert a == 0, f"route on a class A forbids: share {a:.4f} ({what})"
    elif rel == "uses":
        assert b > 0, f"premise: the baseline route does not cross the class ({what})"
        assert a > 0, f"A's route never runs on the class, as if A made it lethal ({what})"
        lethal = grid_a.lethal if grid_a.keep_out is None else grid_a.lethal & ~grid_a.keep_out  # keep-out is no lethal
        assert not lethal[mask].any(), f"A made the class lethal ({what})"
    elif rel == "farther":
        dist = _distance_to(case.scene, case.classes, size)
        px_a, px_b = np.asarray(route_a.pixels), np.asarray(route_b.pixels)
        da, db = float(dist[px_a[:, 0], px_a[:, 1]].min()), float(dist[px_b[:, 0], px_b[:, 1]].min())
        measured.update(min_a=da, min_b=db)
        assert da > db, f"A's route did not keep farther from the class: {da:.2f} m <= {db:.2f} m ({what})"
    else:  # pragma: no cover - a typo in the data
        pytest.fail(f"unknown relation {rel!r}")
    record_property("measured", json.dumps(measured))


def test_scene_cases_cover_families_1_to_6() -> None:
    covered = {c.family for c in mp.SCENE_CASES}
    want = {"negation_motion", "last_resort", "comparative", "condition", "scope", "no_cross"}
    assert want <= covered, f"no scene invariant for {want - covered}"


# ==============================================================================================
# The priors figure: headline prompt vs a paper-style rank costmap, 40 seeded pairs per scene
# ==============================================================================================


@cache
def _layer_names(scene: str) -> tuple[str, ...]:
    from overseec_core.synthesize.layers import class_entity_name

    return tuple(dict.fromkeys(class_entity_name(n) for n in load_class_entities(SCENE_FILES[scene].classes).values()))


def metres_on(pixels: np.ndarray, mask: np.ndarray, pixel_size_m: tuple[float, float]) -> float:
    """Ground metres of the route on ``mask`` (each step counts by its two ends)."""
    px = np.asarray(pixels, dtype=np.int64)
    steps = step_lengths_m(px, *pixel_size_m)
    on = mask[px[:, 0], px[:, 1]].astype(np.float64)
    return float((steps * 0.5 * (on[1:] + on[:-1])).sum())


def priors_figure(scenes: SceneHarness, scene: str) -> dict:
    """Metres on the unmentioned buildings + water over seeded pairs: headline vs rank costmap."""
    grid, result = scenes.costmap(scene, mp.HEADLINE)
    ref_grid, _ = scenes.program_costmap(scene, mp.rank_program(_layer_names(scene)))
    size = grid.pixel_size_m
    hazard = _class_mask(scene, mp.PRIOR_HAZARD_CLASSES[scene])
    h, w = grid.shape
    min_sep = evaluate.DEFAULT_MIN_SEPARATION_FRACTION * math.hypot(h * size[1], w * size[0])
    passable = grid.passable & ref_grid.passable
    pairs = evaluate.sample_pairs(passable, mp.PRIOR_PAIRS, np.random.default_rng(mp.PRIOR_SEED), min_sep, size)
    ref_planner = Planner(ref_grid)
    prompt_m, ref_m, zero_ref, entered, ref_entered, no_route = [], [], 0, 0, 0, 0
    for start, goal in pairs:
        try:
            res, _ = plan_keeping_rules(grid, [start, goal])
        except PlanError:
            no_route += 1
            continue
        ref = ref_planner.plan([start, goal])
        m, rm = metres_on(res.pixels, hazard, size), metres_on(ref.pixels, hazard, size)
        prompt_m.append(m)
        ref_m.append(rm)
        zero_ref += rm == 0
        entered += m > 0
        ref_entered += rm > 0
    pixel_m = max(size)
    total, ref_total = float(sum(prompt_m)), float(sum(ref_m))
    return {
        "scene": scene,
        "prompt": mp.HEADLINE,
        "pairs": len(pairs),
        "no_route": no_route,
        "hazard_classes": list(mp.PRIOR_HAZARD_CLASSES[scene]),
        "metres_prompt": round(total, 2),
        "metres_reference": round(ref_total, 2),
        "ratio": round(total / ref_total, 3) if ref_total > 0 else (math.inf if total > 0 else 1.0),
        "bound_m": round(mp.PRIOR_TOLERANCE * ref_total + zero_ref * pixel_m, 2),
        "routes_entering_prompt": entered,
        "routes_entering_reference": ref_entered,
        "program": result.program,
    }


@pytest.mark.timeout(300)
@pytest.mark.parametrize("scene", [pytest.param(s, marks=_marks(s)) for s in mp.PRIOR_SCENES])
def test_priors_figure(scene: str, scenes: SceneHarness, record_property) -> None:
    _need(scene)
    fig = priors_figure(scenes, scene)
    shown = {k: v for k, v in fig.items() if k != "program"}
    record_property("priors_figure", json.dumps(shown))
    print(
        f"\nPRIORS {scene}: {fig['pairs']} pairs, metres on {'+'.join(fig['hazard_classes'])}: "
        f"prompt {fig['metres_prompt']:.1f} m vs rank reference {fig['metres_reference']:.1f} m "
        f"(ratio {fig['ratio']}, bound {fig['bound_m']:.1f} m); routes entering them: "
        f"prompt {fig['routes_entering_prompt']}, reference {fig['routes_entering_reference']}"
    )
    assert fig["pairs"] == mp.PRIOR_PAIRS, f"only {fig['pairs']} pairs could be drawn"
    assert fig["no_route"] == 0, f"{fig['no_route']} pairs had no route under the headline prompt"
    assert fig["metres_prompt"] <= fig["bound_m"] + 1e-6, (
        f"{scene}: the headline prompt's routes run {fig['metres_prompt']:.1f} m on unmentioned "
        f"buildings/water, more than {mp.PRIOR_TOLERANCE}x the rank costmap's "
        f"{fig['metres_reference']:.1f} m (bound {fig['bound_m']:.1f} m)\nprogram:\n{fig['program']}"
    )
