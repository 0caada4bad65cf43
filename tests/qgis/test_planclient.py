"""The plugin's planner-worker client against a real `overseec plan-server` process (and a few
broken stand-ins for a worker: one that hangs, one that fails at start, one that is missing)."""

from __future__ import annotations

import os
import signal
import sys
import threading
import time

import pytest

from overseec_qgis import planclient
from overseec_qgis.planclient import PlanClient, PlanRejected, Superseded, WorkerError

WORKER = [sys.executable, "-m", "overseec_core.cli", "plan-server"]


@pytest.fixture
def client():
    c = PlanClient(WORKER)
    yield c
    c.close()


def test_load_and_plan_in_one_worker_that_restarts_when_it_dies(client, scene) -> None:
    info = client.load(scene.costmap)
    assert info.shape == (48, 64) and "UTM" in info.crs_wkt
    assert info.world_to_pixel(*scene.world(44, 2)) == (44, 2)
    assert info.pixel_to_world(44, 2) == pytest.approx(scene.world(44, 2))
    points = [scene.world(44, 2), scene.world(3, 60)]
    first = client.plan(scene.costmap, points, "exact")
    pid = client.pid
    assert first.mode == "exact" and first.cost > 0 and first.points[0] == pytest.approx(points[0])
    assert client.plan(scene.costmap, points, "exact").cost == first.cost and client.pid == pid
    os.kill(pid, signal.SIGKILL)
    time.sleep(0.2)
    again = client.plan(scene.costmap, points, "exact")  # a fresh worker loads the costmap itself
    assert again.cost == first.cost and client.starts == 2 and client.pid != pid


def test_a_refused_request_is_one_line_and_the_worker_stays(client, scene) -> None:
    with pytest.raises(PlanRejected) as err:
        client.plan(scene.costmap, [scene.world(44, 2), scene.world(25, 30)], "fast")  # into the water
    assert "goal" in str(err.value) and "lethal" in str(err.value) and "\n" not in str(err.value)
    with pytest.raises(PlanRejected, match="missing.tif"):
        client.load(scene.folder / "missing.tif")
    assert client.starts == 1 and client.ping()["ok"]


def test_concurrent_requests_from_threads_each_get_their_own_answer(client, scene) -> None:
    goals = [(3, 60), (5, 45), (40, 55), (10, 12)]
    expected = {g: client.plan(scene.costmap, [scene.world(44, 2), scene.world(*g)], "exact").cost for g in goals}
    got: dict = {}
    errors: list = []

    def run(goal) -> None:
        try:
            for _ in range(5):
                reply = client.plan(scene.costmap, [scene.world(44, 2), scene.world(*goal)], "exact")
                got.setdefault(goal, set()).add(reply.cost)
        except Exception as exc:  # reported below
            errors.append(exc)

    threads = [threading.Thread(target=run, args=(g,)) for g in goals]
    for t in threads:
        t.start()
    for t in threads:
        t.join(60)
    assert not errors and got == {g: {c} for g, c in expected.items()}


def test_a_worker_that_does_not_answer_is_stopped_after_the_timeout(scene) -> None:
    c = PlanClient([sys.executable, "-c", "import time; time.sleep(60)"], plan_timeout_s=1.0, load_timeout_s=1.0)
    t0 = time.monotonic()
    with pytest.raises(WorkerError, match="did not answer within 1 s"):
        c.plan(scene.costmap, [scene.world(44, 2), scene.world(3, 60)])
    assert time.monotonic() - t0 < 5 and c.pid is None
    c.close()


def test_a_worker_that_fails_at_start_says_why_in_one_line(scene) -> None:
    code = "import sys; print('overseec: error: the environment is broken', file=sys.stderr); sys.exit(2)"
    c = PlanClient([sys.executable, "-c", code])
    with pytest.raises(WorkerError) as err:
        c.ping()
    assert str(err.value) == "the planner worker stopped: overseec: error: the environment is broken"
    missing = PlanClient(["/nonexistent/overseec", "plan-server"])
    with pytest.raises(WorkerError, match="cannot start the planner worker /nonexistent/overseec"):
        missing.ping()


def test_close_stops_the_worker(scene) -> None:
    c = PlanClient(WORKER)
    c.ping()
    pid = c.pid
    c.close()
    assert c.pid is None
    with pytest.raises(ProcessLookupError):
        for _ in range(50):  # reaped by close(); the pid is gone
            os.kill(pid, 0)
            time.sleep(0.1)


def test_the_shared_client_runs_the_configured_environments_worker(monkeypatch, tmp_path) -> None:
    from qgis.core import QgsSettings

    QgsSettings().remove("overseec")
    fake = tmp_path / "overseec"
    fake.write_text("#!/bin/sh\nexit 0\n")
    fake.chmod(0o755)
    monkeypatch.setenv("OVERSEEC_WORKER", str(fake))
    assert planclient.default_argv() == [str(fake), "plan-server"]
    planclient.close_shared_client()
    first = planclient.shared_client()
    assert planclient.shared_client() is first
    planclient.close_shared_client()
    assert planclient.shared_client() is not first
    planclient.close_shared_client()


def test_preload_reads_the_costmap_in_the_background_and_close_does_not_wait_for_it(scene) -> None:
    c = PlanClient(WORKER)
    c.preload(scene.costmap).join(60)
    assert c.ping()["loaded"] == [str(scene.costmap)]
    c.close()
    # a load still running when the plugin unloads: close() kills the worker at once
    slow = PlanClient([sys.executable, "-c", "import time; time.sleep(60)"], load_timeout_s=60)
    thread = slow.preload(scene.costmap)
    time.sleep(0.5)
    t0 = time.monotonic()
    slow.close()
    thread.join(10)
    assert time.monotonic() - t0 < 5 and not thread.is_alive() and slow.pid is None


def test_a_plan_no_longer_wanted_when_its_turn_comes_is_not_sent(client, scene) -> None:
    """Requests from several threads go one at a time; one whose caller gave up meanwhile (a
    stale drag preview) is dropped unsent."""
    client.load(scene.costmap)
    points = [scene.world(44, 2), scene.world(3, 60)]
    sent = []
    real = client.request

    def counting(op, timeout_s=None, **fields):
        sent.append(op)
        return real(op, timeout_s, **fields)

    client.request = counting  # type: ignore[method-assign]
    with pytest.raises(Superseded):
        client.plan(scene.costmap, points, "fast", wanted=lambda: False)
    assert sent == []
    answers = []
    threads = [
        threading.Thread(target=lambda: answers.append(client.plan(scene.costmap, points, "fast", wanted=lambda: True)))
        for _ in range(4)
    ]
    for t in threads:
        t.start()
    for t in threads:
        t.join(60)
    assert len(answers) == 4 and len({a.cost for a in answers}) == 1 and sent == ["plan"] * 4


def _slow_starter(tmp_path, seconds: float, growing: bool) -> list[str]:
    """A stand-in worker that 'imports' for ``seconds`` (start-up lines, module count growing or
    stuck), then answers requests like the real one."""
    script = tmp_path / "slow_worker.py"
    script.write_text(
        "import json, sys, time\n"
        "from overseec_core.liveness import starting_line\n"
        f"end = time.monotonic() + {seconds}\n"
        "n = 10\n"
        "while time.monotonic() < end:\n"
        f"    n += {1 if growing else 0}\n"
        "    sys.stdout.write(starting_line(n)); sys.stdout.flush(); time.sleep(0.2)\n"
        "for line in sys.stdin:\n"
        "    req = json.loads(line)\n"
        "    sys.stdout.write(json.dumps({'id': req['id'], 'ok': True}) + '\\n'); sys.stdout.flush()\n"
    )
    return [sys.executable, str(script)]


def test_a_worker_still_importing_past_the_timeout_is_alive(tmp_path) -> None:
    c = PlanClient(_slow_starter(tmp_path, 3.0, growing=True))
    t0 = time.monotonic()
    assert c.request("ping", timeout_s=1.0)["ok"]  # 3 s of start-up against a 1 s timeout
    assert time.monotonic() - t0 >= 2.5 and c.starts == 1
    assert c.request("ping", timeout_s=1.0)["ok"]
    c.close()


def test_a_worker_stuck_while_starting_is_stopped_after_the_timeout(tmp_path) -> None:
    c = PlanClient(_slow_starter(tmp_path, 30.0, growing=False))  # lines come, imports do not advance
    t0 = time.monotonic()
    with pytest.raises(WorkerError, match="did not answer within 1 s"):
        c.request("ping", timeout_s=1.0)
    assert time.monotonic() - t0 < 5 and c.pid is None
    c.close()


def test_the_real_worker_is_alive_while_it_imports_slowly(tmp_path) -> None:
    """The installed ``overseec``, its imports slowed as on a loaded machine (every module lookup
    waits 10 ms: seconds in all), answers a ping whose timeout is shorter than its start-up."""
    (tmp_path / "sitecustomize.py").write_text(
        "import sys, time\n"
        "class Slow:\n"
        "    @staticmethod\n"
        "    def find_spec(name, path=None, target=None):\n"
        "        time.sleep(0.01)\n"
        "sys.meta_path.insert(0, Slow)\n"
    )
    exe = os.path.join(os.path.dirname(sys.executable), "overseec")
    c = PlanClient([exe, "plan-server"], env={**os.environ, "PYTHONPATH": str(tmp_path)})
    t0 = time.monotonic()
    assert c.request("ping", timeout_s=2.0)["ok"]
    took = time.monotonic() - t0
    c.close()
    assert took > 2.0, f"the worker started in {took:.2f} s: too fast to show that start-up lines keep it alive"
