"""The planner worker (`overseec plan-server`): JSON lines in, JSON lines out, same plans as the core.

The protocol is exercised in-process through :func:`serve` on text streams and, for what only a
process shows (stdout hygiene, end of input, SIGTERM), through the real console script.
"""

from __future__ import annotations

import io
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import rasterio

from overseec_core.plan import Planner, load_costmap
from overseec_core.plan import server as srv
from overseec_core.plan.stage import plan_keeping_rules

from .conftest import UTM_ORIGIN, write_costmap
from .test_keep_out import write_lethal

REPO = Path(__file__).resolve().parents[2]


def world(row: int, col: int, px: float = 0.5) -> list[float]:
    """Map coordinates of a pixel centre of the conftest costmaps (UTM 33N, 0.5 m)."""
    return [UTM_ORIGIN[0] + (col + 0.5) * px, UTM_ORIGIN[1] - (row + 0.5) * px]


def talk(requests: list, server: srv.PlanServer | None = None) -> list[dict]:
    """Feed requests (dicts, or raw strings) to serve() and return its answers."""
    text = "".join((r if isinstance(r, str) else json.dumps(r)) + "\n" for r in requests)
    out = io.StringIO()
    assert srv.serve(io.StringIO(text), out, server) == 0
    return [json.loads(line) for line in out.getvalue().splitlines()]


def test_load_reports_the_grid_and_plans_match_the_core(utm_costmap) -> None:
    path, cost = utm_costmap
    start, goal = (1, 1), (58, 78)
    plan = {"op": "plan", "costmap": str(path), "points": [world(*start), world(*goal)]}
    load, exact, fast = talk(
        [
            {"id": 1, "op": "load", "costmap": str(path)},
            {**plan, "id": 2, "mode": "exact", "vertices": "pixels"},
            {**plan, "id": "f", "mode": "fast"},
        ]
    )
    with rasterio.open(path) as ds:
        assert load["ok"] and (load["width"], load["height"]) == (ds.width, ds.height)
        assert load["transform"] == list(ds.transform)[:6]
        assert rasterio.crs.CRS.from_wkt(load["crs"]) == ds.crs
    grid = load_costmap(path)
    ref, _ = plan_keeping_rules(grid, [start, goal], mode="exact")
    assert exact["id"] == 2 and exact["ok"] and exact["mode"] == "exact"
    assert exact["cost"] == pytest.approx(ref.cost, rel=1e-12)
    assert exact["length_m"] == pytest.approx(ref.length_m, rel=1e-12)
    xs, ys = grid.pixel_to_world(ref.pixels[:, 0], ref.pixels[:, 1])
    assert exact["points"] == [[x, y] for x, y in zip(xs.tolist(), ys.tolist())]
    assert exact["vias"] == 0 and exact["notes"] == [] and exact["ms"] >= 0 and exact["n_pixels"] == len(xs)
    # fast mode: the worker's planner skips only the tight bound; the path is the core's
    core_fast = Planner(grid).plan([start, goal], mode="fast")
    assert fast["id"] == "f" and fast["cost"] == pytest.approx(core_fast.cost, rel=1e-12)
    assert fast["bound"] <= fast["cost"] + 1e-9


def densify(vertices: np.ndarray) -> np.ndarray:
    """Every pixel of the 8-connected straight runs between consecutive vertices."""
    out = [vertices[0]]
    for a, b in zip(vertices[:-1], vertices[1:]):
        step = np.sign(b - a)
        n = int(np.abs(b - a).max())
        assert np.array_equal(a + n * step, b), "vertices must lie on one 8-connected run"
        out.extend(a + i * step for i in range(1, n + 1))
    return np.array(out)


def test_turning_points_keep_the_line_and_the_waypoints() -> None:
    rng = np.random.default_rng(5)
    moves = np.array([(0, 1), (1, 1), (1, 0), (-1, 1), (0, -1)])
    pixels = np.cumsum(np.repeat(moves[rng.integers(0, 5, 40)], rng.integers(1, 6, 40), axis=0), axis=0)
    pixels = np.vstack([[0, 0], pixels])
    via = tuple(pixels[len(pixels) // 2])
    turns = srv.turning_points(pixels, [tuple(pixels[0]), via, tuple(pixels[-1])])
    assert np.array_equal(densify(turns), pixels)
    assert len(turns) < len(pixels) and any((turns == via).all(axis=1))
    assert np.array_equal(srv.turning_points(pixels[:2]), pixels[:2])


def test_the_default_answer_is_the_same_line_with_fewer_vertices(utm_costmap) -> None:
    path, cost = utm_costmap
    ok = np.argwhere(np.isfinite(cost))
    via = tuple(int(v) for v in ok[np.argmin(np.abs(ok - (30, 40)).sum(axis=1))])
    plan = {"op": "plan", "costmap": str(path), "points": [world(1, 1), world(*via), world(58, 78)]}
    turns, every = talk([{**plan, "id": 1}, {**plan, "id": 2, "vertices": "pixels"}])
    grid = load_costmap(path)

    def cells(answer: dict) -> np.ndarray:
        return np.array([grid.world_to_pixel(x, y) for x, y in answer["points"]])

    assert len(turns["points"]) < len(every["points"]) == turns["n_pixels"]
    assert np.array_equal(densify(cells(turns)), cells(every)) and via in map(tuple, cells(turns))
    assert turns["cost"] == every["cost"] and turns["vias"] == 1


def test_errors_are_one_line_and_the_worker_keeps_answering(utm_costmap, tmp_path) -> None:
    path, cost = utm_costmap
    r, c = map(int, np.argwhere(np.isinf(cost))[0])
    plan = {"op": "plan", "costmap": str(path)}
    answers = talk(
        [
            {"id": 1, "op": "plan", "costmap": str(tmp_path / "missing.tif"), "points": [world(1, 1), world(2, 2)]},
            {**plan, "id": 2, "points": [world(1, 1), world(r, c)]},
            {**plan, "id": 3, "points": [world(1, 1), world(500, 500)]},
            {**plan, "id": 4, "points": [world(1, 1)]},
            {**plan, "id": 5, "points": [[1, "x"], [2, 3]]},
            {**plan, "id": 6, "points": [world(1, 1), world(2, 2)], "mode": "slow", "vertices": "some"},
            {"id": 7, "op": "exec", "code": "print(1)"},
            "{not json",
            "[1, 2]",
            {"id": 8, "op": "load"},
            {"id": 9, "op": "load", "costmap": str(path), "band": 2},
            {**plan, "id": 10, "points": [world(1, 1), world(58, 78)]},
        ]
    )
    assert [a["ok"] for a in answers] == [False] * 11 + [True]
    for a in answers[:-1]:
        assert "\n" not in a["error"] and a["error"] and "Traceback" not in a["error"]
    by_id = {a["id"]: a for a in answers}
    assert "missing.tif" in by_id[1]["error"]
    assert "goal" in by_id[2]["error"] and "lethal" in by_id[2]["error"]
    assert "goal" in by_id[3]["error"] and "outside" in by_id[3]["error"]
    assert "points" in by_id[4]["error"] and "finite" in by_id[5]["error"]
    assert "slow" in by_id[6]["error"] and "unknown op 'exec'" in by_id[7]["error"]
    assert answers[7]["id"] is None and "JSON" in answers[7]["error"]
    assert "one JSON object" in answers[8]["error"]
    assert "costmap" in by_id[8]["error"] and "band" in by_id[9]["error"]


def test_sixteen_neighbours_plan_like_the_core_and_switch_without_a_reload(utm_costmap, tmp_path) -> None:
    """``neighbours`` reaches the worker's planner: 16 gives the core's 16-neighbour route, 8 the
    8-neighbour one, both from one load; a bad value is one line and the worker keeps answering."""
    path, _cost = utm_costmap
    start, goal = (1, 1), (58, 78)
    server = srv.PlanServer()
    plan = {"op": "plan", "costmap": str(path), "points": [world(*start), world(*goal)], "mode": "exact"}
    sixteen, eight, again, fast, *bad = talk(
        [
            {**plan, "id": 1, "neighbours": 16, "vertices": "pixels"},
            {**plan, "id": 2, "neighbours": 8},
            {**plan, "id": 3, "neighbours": 16},
            {**plan, "id": 4, "neighbours": 16, "mode": "fast"},
            {**plan, "id": 5, "neighbours": 4},
            {**plan, "id": 6, "neighbours": "16"},
            {**plan, "id": 7, "neighbours": True},
        ],
        server,
    )
    grid = load_costmap(path)
    ref16, _ = plan_keeping_rules(grid, [start, goal], mode="exact", neighbours=16)
    ref8, _ = plan_keeping_rules(grid, [start, goal], mode="exact")
    assert sixteen["cost"] == pytest.approx(ref16.cost, rel=1e-12) and sixteen["n_pixels"] == len(ref16.pixels)
    assert eight["cost"] == pytest.approx(ref8.cost, rel=1e-12) and again["cost"] == sixteen["cost"]
    assert sixteen["cost"] < eight["cost"] and server.loads == 1
    assert fast["ok"] and fast["bound"] <= fast["cost"] + 1e-9 and fast["cost"] >= sixteen["cost"] - 1e-9
    for answer in bad:
        assert not answer["ok"] and "neighbours must be 8 or 16" in answer["error"] and "\n" not in answer["error"]


def test_steps_a_planner_refuses_leave_the_working_planner(utm_costmap, monkeypatch) -> None:
    """When the planner cannot take 16 (the scikit-image fallback), the request fails in one line,
    the costmap keeps planning with 8, and a second request for 16 is refused again."""
    path, _cost = utm_costmap
    real = srv.Planner

    def fallback(*args, **kwargs):
        return real(*args, planner="fallback", **kwargs)

    monkeypatch.setattr(srv, "Planner", fallback)
    plan = {"op": "plan", "costmap": str(path), "points": [world(1, 1), world(58, 78)], "mode": "exact"}
    refused, again, eight = talk([{**plan, "id": 1, "neighbours": 16}, {**plan, "id": 2, "neighbours": 16}, plan])
    assert not refused["ok"] and "16" in refused["error"] and "\n" not in refused["error"]
    assert not again["ok"] and "16" in again["error"]  # never planned with 8 under 16's name
    assert eight["ok"] and eight["mode"] == "exact"


def test_an_oversized_request_is_refused_and_skipped(utm_costmap, monkeypatch) -> None:
    monkeypatch.setattr(srv, "MAX_LINE", 64)
    long = json.dumps({"id": 1, "op": "ping", "pad": "x" * 500})
    first, second = talk([long, {"id": 2, "op": "ping"}])
    assert not first["ok"] and "longer than 64" in first["error"]
    assert second["id"] == 2 and second["ok"]


def test_costmaps_load_once_reload_when_changed_and_two_stay_loaded(utm_costmap, tmp_path) -> None:
    path, cost = utm_costmap
    server = srv.PlanServer()
    plan = {"op": "plan", "costmap": str(path), "points": [world(1, 1), world(58, 78)], "mode": "exact"}
    first, again = talk([{**plan, "id": 1}, {**plan, "id": 2}], server)
    assert server.loads == 1 and first["cost"] == again["cost"]
    # the file changes on disk (as a re-run of the costmap stage would): reloaded, new result
    cheaper = np.where(np.isfinite(cost), cost * 0.5, cost).astype(np.float32)
    time.sleep(0.01)
    write_costmap(path, cheaper)
    (changed,) = talk([{**plan, "id": 3}], server)
    assert server.loads == 2 and changed["cost"] < first["cost"]
    # an LRU of two: a third costmap drops the least recently used
    others = [write_costmap(tmp_path / f"c{i}.tif", cost) for i in range(2)]
    talk([{"id": i, "op": "load", "costmap": str(p)} for i, p in enumerate(others)], server)
    assert [k.path for k in server.cache] == [str(p) for p in others]
    (ping,) = talk([{"id": 9, "op": "ping"}], server)
    assert ping["loaded"] == [str(p) for p in others]
    (gone,) = talk([{"id": 10, "op": "unload", "costmap": str(others[0])}], server)
    assert gone["unloaded"] == 1 and [k.path for k in server.cache] == [str(others[1])]


def test_override_files_apply_in_memory_and_follow_edits(tmp_path) -> None:
    import fiona
    import shapely

    cost = np.full((20, 40), 0.5, np.float32)
    path = write_costmap(tmp_path / "costmap.tif", cost)
    before = path.read_bytes()
    x0, y0 = UTM_ORIGIN
    schema = {"geometry": "Polygon", "properties": {"cost": "float", "lethal": "int", "prefer": "int"}}

    def overrides(name: str, rows: tuple[int, int]) -> str:
        wall = shapely.box(x0 + 20 * 0.5, y0 - rows[1] * 0.5, x0 + 21 * 0.5, y0 - rows[0] * 0.5)
        with fiona.open(tmp_path / name, "w", driver="GPKG", crs="EPSG:32633", schema=schema) as dst:
            dst.write(
                {"geometry": shapely.geometry.mapping(wall), "properties": {"cost": None, "lethal": 1, "prefer": None}}
            )
        return str(tmp_path / name)

    def crossing_rows(answer: dict) -> set[int]:
        """Rows where the route crosses column 20."""
        return {round((y0 - y) / 0.5 - 0.5) for x, y in answer["points"] if x == world(0, 20)[0]}

    plan = {
        "op": "plan",
        "costmap": str(path),
        "points": [world(10, 2), world(10, 37)],
        "mode": "exact",
        "vertices": "pixels",
    }
    server = srv.PlanServer()
    wall_a = overrides("a.gpkg", (0, 18))  # a wall on column 20 with a gap at rows 18-19
    free, walled, again = talk([{**plan, "id": 1}, {**plan, "id": 2, "overrides": [wall_a]}, {**plan, "id": 3}], server)
    assert free["length_m"] == pytest.approx(17.5)
    assert walled["length_m"] > free["length_m"] + 3
    assert crossing_rows(walled) <= {18, 19}
    assert again["cost"] == free["cost"] and server.loads == 1  # overrides never touch the loaded costmap
    # an edit (a new file with the gap at the top instead) is planned on the costmap as read
    wall_b = overrides("b.gpkg", (2, 20))
    (edited,) = talk([{**plan, "id": 4, "overrides": [wall_b]}], server)
    assert crossing_rows(edited) <= {0, 1} and crossing_rows(edited)
    assert server.loads == 1
    assert path.read_bytes() == before


def test_a_rule_that_cannot_be_met_is_planned_and_noted(tmp_path) -> None:
    cost = np.full((20, 20), 0.5, np.float32)
    path = write_costmap(tmp_path / "costmap.tif", cost)
    flags = np.zeros((20, 20), np.uint8)
    flags[:, 10] = 2
    write_lethal(tmp_path / "lethal.tif", flags, path)
    (answer,) = talk([{"id": 1, "op": "plan", "costmap": str(path), "points": [world(10, 2), world(10, 17)]}])
    assert answer["ok"] and answer["length_m"] == pytest.approx(7.5)
    assert "cannot be met between start and goal" in answer["notes"][0]


def _start_worker(*extra_env: tuple[str, str]) -> subprocess.Popen:
    env = {**os.environ, "PYTHONUNBUFFERED": "1", **dict(extra_env)}
    return subprocess.Popen(
        [sys.executable, "-m", "overseec_core.cli", "plan-server"],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=REPO,
        env=env,
    )


def test_the_console_command_speaks_the_protocol_until_end_of_input(utm_costmap) -> None:
    path, _ = utm_costmap
    requests = [
        {"id": 1, "op": "ping"},
        {"id": 2, "op": "plan", "costmap": str(path), "points": [world(1, 1), world(58, 78)], "mode": "fast"},
    ]
    proc = _start_worker()
    out, err = proc.communicate("".join(json.dumps(r) + "\n" for r in requests), timeout=120)
    assert proc.returncode == 0, err
    answers = [json.loads(line) for line in out.splitlines()]  # every stdout line is an answer
    assert [a["id"] for a in answers] == [1, 2] and all(a["ok"] for a in answers)
    assert answers[0]["pid"] == proc.pid


def test_stray_output_goes_to_stderr_never_into_the_protocol() -> None:
    code = (
        "import os, sys\n"
        "from overseec_core.plan.server import protocol_stdout\n"
        "out = protocol_stdout()\n"
        "print('python noise')\n"
        "os.write(1, b'c noise\\n')\n"
        'out.write(\'{"id":1,"ok":true}\\n\'); out.flush()\n'
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout == '{"id":1,"ok":true}\n'
    assert "python noise" in done.stderr and "c noise" in done.stderr


def test_sigterm_stops_a_waiting_worker_at_once() -> None:
    proc = _start_worker()
    try:
        proc.stdin.write('{"id": 1, "op": "ping"}\n')
        proc.stdin.flush()
        assert json.loads(proc.stdout.readline())["ok"]
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=10) == -signal.SIGTERM
    finally:
        proc.kill()
        proc.communicate()
