"""The planner without its compiled kernel: scikit-image's MCP_Geometric, same costs, says so.

Every comparison plans the same grid twice in one process, with the kernel and with the fallback
(``OVERSEEC_PLANNER=fallback``, read when a Planner is made), and requires equal costs (to 1e-9;
where several routes are equally cheap the fallback may pick another, which must cost the same
under the kernel's own pricing). A subprocess with the kernel made unimportable checks what an
install without it says and does.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from overseec_core.cli import main
from overseec_core.errors import Cancelled, InputError, PlanError
from overseec_core.plan import PLANNER_ENV, Planner, PlanningGrid, cumulative_path_cost, load_costmap, planner_backend
from overseec_core.plan import fallback as fb
from overseec_core.plan.stage import plan_keeping_rules
from overseec_core.progress import CancelToken, NullProgress

from .conftest import smooth_costmap, write_costmap
from .test_keep_out import write_lethal

REPO = Path(__file__).resolve().parents[2]
REL = 1e-9
NOTE_START = "planned with the fallback planner (scikit-image), "


def _planners(grid: PlanningGrid, monkeypatch, base: float = 0.01) -> tuple[Planner, Planner]:
    monkeypatch.delenv(PLANNER_ENV, raising=False)
    kernel = Planner(grid, base)
    monkeypatch.setenv(PLANNER_ENV, "fallback")
    fallback = Planner(grid, base)
    assert kernel.backend.name == "kernel" and fallback.backend.name == "fallback"
    return kernel, fallback


def _check_route(grid: PlanningGrid, pixels: np.ndarray, points: list[tuple[int, int]]) -> None:
    """8-connected, from the first point to the last, through passable cells only."""
    assert tuple(pixels[0]) == points[0] and tuple(pixels[-1]) == points[-1]
    steps = np.abs(np.diff(pixels, axis=0))
    assert steps.max() <= 1 and (steps.sum(axis=1) > 0).all()
    assert np.isfinite(grid.cost[pixels[:, 0], pixels[:, 1]]).all()


def _passable_points(cost: np.ndarray, rng: np.random.Generator, n: int) -> list[tuple[int, int]]:
    rows, cols = np.nonzero(np.isfinite(cost))
    pick = rng.choice(len(rows), size=n, replace=False)
    return [(int(rows[i]), int(cols[i])) for i in pick]


@pytest.mark.parametrize(
    "seed,shape,pixel",
    [
        (0, (60, 80), (0.5, 0.5)),
        (1, (75, 50), (0.7, 1.3)),  # non-square pixels
        (2, (64, 64), (2.0, 1.0)),
        (3, (41, 97), (0.3, 0.45)),
    ],
)
def test_the_fallback_finds_paths_of_the_kernels_cost(monkeypatch, seed, shape, pixel) -> None:
    """Seeded costmaps with lethal blobs and nodata, random passable pairs, exact mode."""
    cost = smooth_costmap(shape, seed, lethal_fraction=0.12, nodata_fraction=0.03)
    grid = PlanningGrid.from_array(cost, pixel_size_m=pixel)
    kernel, fallback = _planners(grid, monkeypatch)
    rng = np.random.default_rng(seed)
    compared = 0
    for _ in range(12):
        points = _passable_points(cost, rng, 2)
        try:
            want = kernel.plan(points)
        except PlanError as exc:  # a pair the lethal blobs separate: the fallback says the same
            with pytest.raises(PlanError) as got:
                fallback.plan(points)
            assert str(got.value) == str(exc)
            continue
        got = fallback.plan(points)
        assert got.cost == pytest.approx(want.cost, rel=REL)
        _check_route(grid, got.pixels, points)
        # equal or equally cheap paths: the fallback's route priced by the kernel's rule
        assert kernel.path_cost(got.pixels) == pytest.approx(want.cost, rel=REL)
        assert float(cumulative_path_cost(grid, got.pixels)[-1]) == pytest.approx(got.cost, rel=REL)
        assert (
            got.mode == "exact"
            and got.bound == got.cost
            and got.length_m == pytest.approx(fallback.path_length_m(got.pixels))
        )
        compared += 1
    assert compared >= 6


def test_via_points_give_the_same_legs(monkeypatch) -> None:
    cost = smooth_costmap((70, 90), 7, lethal_fraction=0.1)
    points = [(2, 2), (60, 10), (35, 45), (5, 85), (67, 87)]
    for r, c in points:
        cost[r, c] = 0.5
    grid = PlanningGrid.from_array(cost, pixel_size_m=(0.6, 0.9))
    kernel, fallback = _planners(grid, monkeypatch)
    want, got = kernel.plan(points), fallback.plan(points)
    assert got.leg_costs == pytest.approx(want.leg_costs, rel=REL)
    assert got.cost == pytest.approx(want.cost, rel=REL)
    assert got.waypoints == want.waypoints == tuple(points)
    _check_route(grid, got.pixels, points)
    for p in points:  # every via is on the route
        assert (got.pixels == p).all(axis=1).any()


def test_every_result_carries_the_note_and_fast_mode_runs_the_exact_search(monkeypatch) -> None:
    cost = smooth_costmap((50, 50), 4, lethal_fraction=0.05)
    cost[0, 0] = cost[-1, -1] = 0.5
    grid = PlanningGrid.from_array(cost, pixel_size_m=(0.5, 0.5))
    kernel, fallback = _planners(grid, monkeypatch)
    exact = fallback.plan([(0, 0), (49, 49)])
    fast = fallback.plan([(0, 0), (49, 49)], mode="fast")
    note = f"{NOTE_START}{fb.SLOWDOWN} slower than the compiled kernel; {PLANNER_ENV}=fallback asks for it"
    assert exact.notes == (note,)
    assert fast.notes == (
        note + f"; fast mode runs its exact search ({fb.FAST_SLOWDOWN} slower than the kernel's fast mode)",
    )
    assert fast.mode == "exact" and fast.requested_mode == "fast" and fast.bound == fast.cost
    assert fast.cost == pytest.approx(kernel.plan([(0, 0), (49, 49)]).cost, rel=REL)
    assert not any(n.startswith(NOTE_START) for n in kernel.plan([(0, 0), (49, 49)], mode="fast").notes)
    assert exact.to_json()["notes"] == [note]
    mem = fallback.memory_bytes()
    assert mem["fallback"] > 0 and mem["total"] == mem["cost"] + mem["fallback"]


def test_lethal_and_nodata_cells_are_never_entered_and_blocked_points_are_named(monkeypatch) -> None:
    cost = np.full((9, 9), 1.0, np.float32)
    cost[:8, 4] = np.inf  # a wall with one gap in the bottom row
    cost[8, 6] = np.nan  # nodata beside the gap: MCP_Geometric would crash on NaN
    grid = PlanningGrid.from_array(cost, pixel_size_m=(2.0, 1.0))
    kernel, fallback = _planners(grid, monkeypatch, base=0.0)
    got, want = fallback.plan([(0, 0), (0, 8)]), kernel.plan([(0, 0), (0, 8)])
    assert got.cost == pytest.approx(want.cost, rel=REL) and (8, 4) in map(tuple, got.pixels)
    assert np.isfinite(cost[got.pixels[:, 0], got.pixels[:, 1]]).all()
    for bad in ([(0, 0), (3, 4)], [(8, 6), (0, 0)]):
        with pytest.raises(PlanError) as k:
            kernel.plan(bad)
        with pytest.raises(PlanError) as f:
            fallback.plan(bad)
        assert str(f.value) == str(k.value)
    closed = cost.copy()
    closed[8, 4] = np.inf
    blocked = PlanningGrid.from_array(closed, pixel_size_m=(2.0, 1.0))
    monkeypatch.setenv(PLANNER_ENV, "fallback")
    with pytest.raises(PlanError, match="no path from start .* to goal"):
        Planner(blocked).plan([(0, 0), (0, 8)])


def test_the_cost_distance_raster_matches(monkeypatch) -> None:
    cost = smooth_costmap((40, 55), 9, lethal_fraction=0.1, nodata_fraction=0.02)
    cost[5, 5] = 0.5
    grid = PlanningGrid.from_array(cost, pixel_size_m=(0.8, 0.5))
    kernel, fallback = _planners(grid, monkeypatch)
    want, got = kernel.cumulative((5, 5)), fallback.cumulative((5, 5))
    assert np.array_equal(np.isnan(want), np.isnan(got))
    reached = ~np.isnan(want)
    np.testing.assert_allclose(got[reached], want[reached], rtol=1e-6)  # float32 rasters
    assert np.array_equal(fallback.cumulative_rows(10, 20), got[10:20], equal_nan=True)
    fallback.plan([(5, 5), (30, 30)] if np.isfinite(cost[30, 30]) else [(5, 5), (5, 5)])
    with pytest.raises(PlanError, match="call expand"):  # a plan replaces the raster, as with the kernel
        fallback.cumulative_rows(0, 1)


def test_keep_out_rules_bend_the_same_way_on_the_fallback(tmp_path: Path, monkeypatch) -> None:
    """RulePlanner on the fallback: kept where possible, broken as little as possible otherwise,
    with the same cost, metres inside and broken-rule note as the kernel's, and the fallback note."""
    cost = np.full((20, 20), 0.5, np.float32)
    cost[:, 14:] = 0.3
    costmap = write_costmap(tmp_path / "costmap.tif", cost)
    flags = np.zeros((20, 20), np.uint8)
    flags[3:, 10] = 2  # a keep-out wall with a gap at rows 0-2
    flags[15, 2] = 1
    write_lethal(tmp_path / "lethal.tif", flags, costmap)
    results = {}
    for name in ("auto", "fallback"):
        monkeypatch.setenv(PLANNER_ENV, name)
        grid = load_costmap(costmap)
        kept, planner = plan_keeping_rules(grid, [(10, 2), (10, 18)])
        inside, _ = plan_keeping_rules(grid, [(10, 10), (12, 18), (4, 3)])  # a start inside the zone, a via
        results[name] = (kept, inside, planner.backend.name)
    (k_kept, k_inside, k_name), (f_kept, f_inside, f_name) = results["auto"], results["fallback"]
    assert (k_name, f_name) == ("kernel", "fallback")
    assert f_kept.cost == pytest.approx(k_kept.cost, rel=REL)
    assert not (flags[f_kept.pixels[:, 0], f_kept.pixels[:, 1]] > 0).any()
    assert f_inside.cost == pytest.approx(k_inside.cost, rel=REL)
    assert f_inside.leg_costs == pytest.approx(k_inside.leg_costs, rel=REL)
    broken = [n for n in f_inside.notes if "cannot be met" in n]
    assert broken == [n for n in k_inside.notes if "cannot be met" in n] and len(broken) == 1
    assert any(n.startswith(NOTE_START) for n in f_inside.notes)
    assert not any(n.startswith(NOTE_START) for n in k_inside.notes)


def test_the_plan_server_plans_on_the_fallback(utm_costmap, monkeypatch) -> None:
    path, cost = utm_costmap
    from .test_server import talk, world

    rows, cols = np.nonzero(np.isfinite(cost[25:35, 35:45]))
    via = (25 + int(rows[0]), 35 + int(cols[0]))
    answers = {}
    for name in ("auto", "fallback"):
        monkeypatch.setenv(PLANNER_ENV, name)
        plan = {"op": "plan", "costmap": str(path), "points": [world(1, 1), world(*via), world(58, 78)]}
        answers[name] = talk([{**plan, "id": 1, "mode": "exact"}, {**plan, "id": 2, "mode": "fast"}])
    (k_exact, _k_fast), (f_exact, f_fast) = answers["auto"], answers["fallback"]
    assert f_exact["ok"] and f_fast["ok"], f_exact
    assert f_exact["cost"] == pytest.approx(k_exact["cost"], rel=REL) and f_exact["vias"] == 1
    assert f_fast["cost"] == pytest.approx(k_exact["cost"], rel=REL) and f_fast["mode"] == "exact"
    assert any(n.startswith(NOTE_START) for n in f_exact["notes"]) and not k_exact["notes"]


def test_a_fallback_query_is_cancelled_from_another_thread_and_the_planner_plans_again(monkeypatch) -> None:
    rng = np.random.default_rng(0)
    cost = rng.random((1500, 1500)).astype(np.float32)
    grid = PlanningGrid.from_array(cost, pixel_size_m=(0.5, 0.5))
    monkeypatch.setenv(PLANNER_ENV, "fallback")
    planner = Planner(grid)
    planner.prepare_fast()  # builds the fallback's search
    token = CancelToken()
    token.cancel()  # cancelled before it starts: nothing runs
    with pytest.raises(Cancelled):
        planner.plan([(0, 0), (1499, 1499)], progress=NullProgress(token))
    token = CancelToken()
    threading.Timer(0.05, token.cancel).start()  # during the search (a few seconds in full)
    started = time.perf_counter()
    with pytest.raises(Cancelled):
        planner.plan([(0, 0), (1499, 1499)], progress=NullProgress(token))
    cancelled_after = time.perf_counter() - started
    small = planner.plan([(0, 0), (10, 12)])
    assert small.cost > 0 and tuple(small.pixels[-1]) == (10, 12)
    print(f"cancelled after {cancelled_after:.2f} s")


def test_a_cancel_while_the_fallback_search_is_built_is_answered_at_once(monkeypatch) -> None:
    """Building MCP's search cannot be stopped (4-7 s at 6000² on a busy machine) but releases
    the GIL; the planner waits for it in short steps, so a cancel 0.1 s in ends the plan at once.
    The real search, its construction slowed to 3 s as on a loaded machine (issue 33 rule 5:
    'Ctrl-C within a second'; bench/fallback_cancel.py times the real thing at 6000²)."""
    real = fb._mcp_class()

    class SlowBuild(real):  # type: ignore[misc,valid-type]
        def __init__(self, *args, **kwargs) -> None:
            time.sleep(3.0)  # sleeps, like the build, without holding the GIL
            super().__init__(*args, **kwargs)

    monkeypatch.setattr(fb, "_mcp_class", lambda: SlowBuild)
    monkeypatch.setenv(PLANNER_ENV, "fallback")
    cost = np.random.default_rng(1).random((300, 300)).astype(np.float32)
    planner = Planner(PlanningGrid.from_array(cost, pixel_size_m=(1.0, 1.0)))
    token = CancelToken()
    threading.Timer(0.1, token.cancel).start()
    t0 = time.perf_counter()
    with pytest.raises(Cancelled):
        planner.plan([(0, 0), (299, 299)], progress=NullProgress(token))
    cancelled_s = time.perf_counter() - t0
    assert cancelled_s < 1.5, f"cancelled after {cancelled_s:.2f} s of a 3 s build"
    monkeypatch.setattr(fb, "_mcp_class", lambda: real)
    small = planner.plan([(0, 0), (10, 12)])  # the next query builds the search again and plans
    assert tuple(small.pixels[-1]) == (10, 12)


def test_the_planner_choice_is_checked(monkeypatch) -> None:
    grid = PlanningGrid.from_array(np.ones((4, 4), np.float32))
    monkeypatch.setenv(PLANNER_ENV, "gpu")
    with pytest.raises(InputError, match="OVERSEEC_PLANNER='gpu': use one of auto, kernel, fallback"):
        Planner(grid)
    monkeypatch.setenv(PLANNER_ENV, "kernel")
    assert Planner(grid).backend.name == "kernel" and planner_backend().forced
    assert Planner(grid, planner="fallback").backend.name == "fallback"
    monkeypatch.delenv(PLANNER_ENV)
    backend = planner_backend()
    assert backend.name == "kernel" and backend.describe().startswith("compiled kernel (")
    assert backend.kernel_file and Path(backend.kernel_file).is_file()


def test_doctor_kernel_checks_the_compiled_kernel(capsys) -> None:
    assert main(["doctor", "--kernel"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("kernel ") and "exact" in out[0] and "mcp" in out[0]
    assert len(out) >= 3 and all(line.rstrip().endswith("ok") for line in out[1:3])
    assert main(["doctor", "--kernel", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["ok"] and report["kernel"] and all(g["ok"] for g in report["grids"])


#: Runs in a fresh interpreter with the compiled kernel made unimportable (as after an install
#: where it could not be compiled); prints what the install says and does, as JSON.
NO_KERNEL = textwrap.dedent(
    """
    import contextlib, io, json, os, sys
    sys.modules["overseec_core.plan._kernel"] = None  # import fails as when it was never built
    import numpy as np
    from overseec_core.cli import main
    from overseec_core.plan import Planner, PlanningGrid, planner_backend
    from overseec_core.errors import PlanError
    out = {}
    b = planner_backend()
    out["backend"] = b.to_json()
    out["describe"] = b.describe()
    rng = np.random.default_rng(5)
    cost = rng.random((30, 40)).astype(np.float32)
    r = Planner(PlanningGrid.from_array(cost, pixel_size_m=(0.5, 1.5))).plan([(0, 0), (29, 39)], mode="fast")
    out["plan"] = {"cost": r.cost, "mode": r.mode, "notes": list(r.notes)}
    for args in (["doctor", "--kernel"], ["doctor"]):
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            out[" ".join(args) + " rc"] = main(args)
        out[" ".join(args)] = buf.getvalue()
    os.environ["OVERSEEC_PLANNER"] = "kernel"
    try:
        Planner(PlanningGrid.from_array(cost))
    except PlanError as exc:
        out["required"] = str(exc)
    print(json.dumps(out))
    """
)


def test_without_the_kernel_the_install_plans_with_the_fallback_and_says_why() -> None:
    env = {k: v for k, v in os.environ.items() if k != PLANNER_ENV}
    done = subprocess.run(
        [sys.executable, "-c", NO_KERNEL], capture_output=True, text=True, timeout=300, cwd=REPO, env=env
    )
    assert done.returncode == 0, done.stderr
    out = json.loads(done.stdout.strip().splitlines()[-1])
    backend = out["backend"]
    assert backend["planner"] == "fallback" and not backend["forced"] and backend["kernel_file"] is None
    # in this checkout's venv the advice is the checkout's own (a pip install gets pip's: tests/packaging)
    assert backend["reason"].startswith("the compiled kernel is not installed") and "make setup" in backend["reason"]
    assert out["describe"].startswith("fallback (scikit-image MCP_Geometric")
    cost = np.random.default_rng(5).random((30, 40)).astype(np.float32)
    want = Planner(PlanningGrid.from_array(cost, pixel_size_m=(0.5, 1.5))).plan([(0, 0), (29, 39)])
    assert out["plan"]["cost"] == pytest.approx(want.cost, rel=REL)
    assert out["plan"]["mode"] == "exact" and len(out["plan"]["notes"]) == 1
    assert out["plan"]["notes"][0].startswith(NOTE_START) and "not installed" in out["plan"]["notes"][0]
    assert out["doctor --kernel rc"] == 0
    assert out["doctor --kernel"].startswith("no compiled kernel: the fallback planner is in use (")
    assert "the fallback plans correctly" in out["doctor --kernel"]
    assert out["doctor rc"] == 0
    line = next(x for x in out["doctor"].splitlines() if x.startswith("planner"))
    assert "fallback (scikit-image MCP_Geometric" in line and "not installed" in line
    assert out["required"].startswith("OVERSEEC_PLANNER=kernel, but the compiled kernel is not installed")


def test_a_kernel_that_does_not_load_is_named_with_its_error(monkeypatch) -> None:
    """A compiled module that fails to import (e.g. built against NumPy 1.x, run under 2.x)."""
    from overseec_core.plan import backend as backend_module

    monkeypatch.setattr(backend_module, "_kernel", None)
    monkeypatch.setattr(backend_module, "KERNEL_ERROR", "ImportError: numpy.core.multiarray failed to import")
    monkeypatch.delenv(PLANNER_ENV, raising=False)
    backend = planner_backend()
    assert backend.name == "fallback" and backend.kernel_file and backend.kernel_file.endswith((".so", ".pyd"))
    assert f"the compiled kernel {backend.kernel_file} does not load (ImportError: numpy.core" in backend.reason
    grid = PlanningGrid.from_array(np.ones((5, 5), np.float32))
    result = Planner(grid).plan([(0, 0), (4, 4)])
    assert result.notes[0].startswith(NOTE_START) and "does not load" in result.notes[0]
    assert math.isclose(result.cost, 4 * math.hypot(1, 1) * 1.01, rel_tol=REL)


def test_doctor_kernel_refuses_a_planner_setting_plan_refuses(monkeypatch, capsys) -> None:
    """ "OVERSEEC_PLANNER=bogus": `plan` refuses it, so `doctor --kernel` does too (issue 33 rule
    6), in the same one line, instead of reporting it as the planner in use with exit 0."""
    monkeypatch.setenv(PLANNER_ENV, "bogus")
    assert main(["doctor", "--kernel"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["overseec: error: OVERSEEC_PLANNER='bogus': use one of auto, kernel, fallback"]
