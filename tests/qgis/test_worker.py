"""The worker protocol: JSON-lines parsing, overall progress, errors and cancellation.

The worker here is a real subprocess (a tiny Python script speaking the CLI's protocol), so
terminate/kill and stderr handling are exercised for real.
"""

from __future__ import annotations

import sys
import textwrap
import time
from pathlib import Path

import pytest

from overseec_qgis.worker import (
    StageProgress,
    WorkerEvent,
    WorkerFailed,
    cli_argv,
    find_worker,
    parse_event,
    run_worker,
    worker_env,
)

pytestmark = pytest.mark.qgis


def test_parse_event_reads_the_cli_protocol() -> None:
    ev = parse_event(
        '{"event": "progress", "stage": "segment", "done": 3, "total": 12, "fraction": 0.25, "eta_s": 9.5}'
    )
    assert ev == WorkerEvent(kind="progress", stage="segment", done=3, total=12, fraction=0.25, eta_s=9.5)
    assert parse_event('{"event": "begin", "stage": "costmap", "total": 4, "unit": "block"}').kind == "begin"
    assert parse_event('{"event": "message", "text": "CLIPSeg on cpu"}').text == "CLIPSeg on cpu"
    # fraction derived when only done/total are given; clamped to [0, 1]
    assert parse_event('{"event": "progress", "stage": "s", "done": 1, "total": 4}').fraction == 0.25
    assert parse_event('{"event": "progress", "stage": "s", "fraction": 7}').fraction == 1.0
    assert parse_event("   ") is None
    stray = parse_event("Some library printed this")
    assert stray.kind == "text" and stray.text == "Some library printed this"
    assert parse_event("[1, 2]").kind == "text"


def test_stage_progress_weights_a_multi_stage_run() -> None:
    sp = StageProgress({"segment": 3.0, "costmap": 1.0})
    assert sp.update(WorkerEvent("begin", "segment")) == 0.0
    assert sp.update(WorkerEvent("progress", "segment", fraction=0.5)) == pytest.approx(0.375)
    assert sp.update(WorkerEvent("end", "segment")) == pytest.approx(0.75)
    assert sp.update(WorkerEvent("progress", "costmap", fraction=0.5)) == pytest.approx(0.875)
    assert sp.update(WorkerEvent("message", text="x")) is None
    # an unknown stage shows its own fraction
    assert sp.update(WorkerEvent("progress", "other", fraction=0.3)) == pytest.approx(0.3)


def _script(tmp_path: Path, body: str) -> list[str]:
    path = tmp_path / "fake_worker.py"
    path.write_text(textwrap.dedent(body))
    return [sys.executable, str(path)]


def test_run_worker_streams_events_and_reports_success(tmp_path: Path) -> None:
    argv = _script(
        tmp_path,
        """
        import json, sys
        def emit(**e): print(json.dumps(e), flush=True)
        emit(event="begin", stage="segment", total=2, unit="tile")
        emit(event="progress", stage="segment", done=1, total=2, fraction=0.5, eta_s=1.0)
        print("not json", flush=True)
        emit(event="progress", stage="segment", done=2, total=2, fraction=1.0, eta_s=0.0)
        emit(event="end", stage="segment", done=2)
        emit(event="message", text="wrote probs.tif")
    """,
    )
    events = []
    res = run_worker(argv, on_event=events.append)
    assert res.ok and res.returncode == 0 and not res.cancelled
    assert [e.kind for e in events] == ["begin", "progress", "text", "progress", "end", "message"]
    assert res.messages == ("not json", "wrote probs.tif")


def test_run_worker_leaves_no_unclosed_pipe(tmp_path: Path) -> None:
    """Each unclosed pipe was a 'ResourceWarning: unclosed file' line in QGIS's log."""
    import gc
    import warnings

    argv = _script(tmp_path, "import sys; print('x'); print('y', file=sys.stderr)")
    gc.collect()  # what earlier tests left for the collector is theirs, not run_worker's
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", ResourceWarning)
        for _ in range(3):
            assert run_worker(argv).ok
        gc.collect()
    assert not [w for w in caught if issubclass(w.category, ResourceWarning)], [str(w.message) for w in caught]


def test_run_worker_keeps_the_cli_one_line_error(tmp_path: Path) -> None:
    argv = _script(
        tmp_path,
        """
        import sys
        print("some warning", file=sys.stderr)
        print("overseec: error: no such file: nowhere.tif", file=sys.stderr)
        sys.exit(2)
    """,
    )
    res = run_worker(argv)
    assert not res.ok and res.returncode == 2
    assert res.error == "no such file: nowhere.tif"
    assert res.summary() == "no such file: nowhere.tif"
    assert "some warning" in res.stderr
    assert str(WorkerFailed(res)) == "no such file: nowhere.tif"


def test_cancel_terminates_then_kills_a_stubborn_worker(tmp_path: Path) -> None:
    """SIGTERM first; a worker that ignores it is killed after the grace period."""
    argv = _script(
        tmp_path,
        """
        import json, signal, time
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        print(json.dumps({"event": "begin", "stage": "segment", "total": 100}), flush=True)
        time.sleep(60)
    """,
    )
    started = []
    t0 = time.monotonic()
    cancel_at = [None]

    def on_event(ev):
        started.append(ev)
        cancel_at[0] = time.monotonic()

    res = run_worker(argv, on_event=on_event, is_cancelled=lambda: cancel_at[0] is not None, grace_s=0.5)
    assert started and res.cancelled and not res.ok
    assert res.returncode != 0
    assert time.monotonic() - t0 < 20, "the worker was not killed after the grace period"
    assert res.summary().startswith("cancelled")


def test_cancel_lets_a_cooperative_worker_stop_cleanly(tmp_path: Path) -> None:
    """The real CLI turns SIGTERM into a clean stop with exit status 130."""
    argv = _script(
        tmp_path,
        """
        import json, signal, sys, time
        stop = []
        signal.signal(signal.SIGTERM, lambda *a: stop.append(1))
        print(json.dumps({"event": "begin", "stage": "segment", "total": 100}), flush=True)
        while not stop:
            time.sleep(0.01)
        print("overseec: error: cancelled by the user; partial outputs were discarded", file=sys.stderr)
        sys.exit(130)
    """,
    )
    flag = []
    res = run_worker(argv, on_event=lambda ev: flag.append(ev), is_cancelled=lambda: bool(flag))
    assert res.cancelled and res.returncode == 130


def test_worker_discovery_and_argv(tmp_path: Path, monkeypatch) -> None:
    venv = tmp_path / "venv"
    (venv / "bin").mkdir(parents=True)
    exe = venv / "bin" / "overseec"
    exe.write_text("#!/bin/sh\n")
    exe.chmod(0o755)
    monkeypatch.delenv("OVERSEEC_WORKER", raising=False)
    assert find_worker(venv=str(venv)) == exe
    monkeypatch.setenv("OVERSEEC_VENV", str(venv))
    assert find_worker() == exe
    assert find_worker(setting=str(exe)) == exe
    assert cli_argv(exe, "segment", ["a b.tif", 3]) == [str(exe), "--json-progress", "segment", "a b.tif", "3"]
    monkeypatch.setenv("PYTHONPATH", "/qgis/python")
    env = worker_env({"OVERSEEC_LLM_API_KEY": "k"})
    assert "PYTHONPATH" not in env and env["OVERSEEC_LLM_API_KEY"] == "k"


@pytest.mark.parametrize(
    "event",
    [
        WorkerEvent("begin", stage="segment", total=12, unit="tile"),
        WorkerEvent("begin", stage="interpret", total=None, unit="step"),
        WorkerEvent("progress", stage="segment", done=3, total=12, fraction=0.25, eta_s=9.5),
        WorkerEvent("progress", stage="plan", done=2, total=None, fraction=None, eta_s=None),
        WorkerEvent("end", stage="segment", done=12),
        WorkerEvent("message", text="CLIPSeg on cpu"),
    ],
)
def test_every_event_kind_round_trips_through_the_one_schema(event: WorkerEvent) -> None:
    """What the core writes (encode_event) the plugin reads back unchanged (parse_event)."""
    from overseec_core.progress import EVENT_FIELDS, encode_event

    assert event.kind in EVENT_FIELDS
    assert parse_event(encode_event(event)) == event


def test_json_lines_progress_writes_what_the_worker_reads() -> None:
    """The writer's real output, line by line, parses into the events it reported."""
    import io

    from overseec_core.progress import JsonLinesProgress

    stream = io.StringIO()
    p = JsonLinesProgress(stream=stream, min_interval_s=0.0)
    p.begin("segment", 2, unit="tile")
    p.advance()
    p.advance()
    p.message("hello")
    p.end()
    events = [parse_event(line) for line in stream.getvalue().splitlines()]
    assert [e.kind for e in events] == ["begin", "progress", "progress", "message", "end"]
    assert events[0] == WorkerEvent("begin", stage="segment", total=2, unit="tile")
    assert (events[2].done, events[2].total, events[2].fraction) == (2, 2, 1.0)
    assert events[3].text == "hello" and events[4] == WorkerEvent("end", stage="segment", done=2)
