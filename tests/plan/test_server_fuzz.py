"""The planner worker against malformed input: every bad line gets an error answer, never a crash.

Each test drives one real `overseec plan-server` process (the console command, as the QGIS
plugin starts it) and, after every request, checks that a ``ping`` is still answered by the same
process. The explicit cases name the faults one by one (non-finite numbers, deep nesting, huge
integers, wrong types, over-long lines, bytes that are not UTF-8, end of input mid-line); the
property-based test sends random requests and random bytes.
"""

from __future__ import annotations

import io
import itertools
import json
import os
import queue
import subprocess
import sys
import tempfile
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from overseec_core import liveness
from overseec_core.plan import server as srv

from .conftest import smooth_costmap, write_costmap
from .test_server import world

REPO = Path(__file__).resolve().parents[2]
#: Seconds to wait for one answer (a costmap load included).
ANSWER_TIMEOUT = 30.0


class Worker:
    """One `overseec plan-server` process, written to in bytes and read line by line."""

    def __init__(self) -> None:
        self.stderr = tempfile.TemporaryFile()
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "overseec_core.console", "plan-server"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=self.stderr,
            cwd=REPO,
            env={**os.environ, "PYTHONUNBUFFERED": "1"},
        )
        self.lines: queue.Queue[bytes] = queue.Queue()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()
        self._ids = itertools.count()
        self.pid = self.ping()["pid"]

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.put(line)
        self.lines.put(b"")

    def send(self, data: bytes) -> None:
        assert self.proc.stdin is not None
        self.proc.stdin.write(data)
        self.proc.stdin.flush()

    def answer(self) -> dict[str, Any]:
        while True:
            try:
                line = self.lines.get(timeout=ANSWER_TIMEOUT)
            except queue.Empty:
                pytest.fail(f"no answer within {ANSWER_TIMEOUT} s; stderr: {self.errors()}")
            if not line:
                pytest.fail(f"the worker exited ({self.proc.poll()}); stderr: {self.errors()}")
            answer = json.loads(line)  # every stdout line is one JSON line of the protocol
            if answer.get("event") != liveness.STARTING or "id" in answer:
                break  # start-up lines come before the first answer only (test_liveness)
        assert isinstance(answer, dict) and isinstance(answer.get("ok"), bool), answer
        return answer

    def ping(self) -> dict[str, Any]:
        """Ping, skipping any answers before ours; the worker must answer it."""
        rid = f"ping-{next(self._ids)}"
        self.send(json.dumps({"id": rid, "op": "ping"}).encode() + b"\n")
        while True:
            answer = self.answer()
            if answer.get("id") == rid:
                assert answer["ok"], answer
                return answer

    def ask(self, line: bytes) -> list[dict[str, Any]]:
        """The answers to one raw line (a line may hold several requests or none), then a ping
        that proves the same worker is still serving."""
        rid = f"ping-{next(self._ids)}"
        self.send(line + b"\n" + json.dumps({"id": rid, "op": "ping"}).encode() + b"\n")
        answers = []
        while True:
            answer = self.answer()
            if answer.get("id") == rid and "pid" in answer:
                assert answer["pid"] == self.pid
                return answers
            answers.append(answer)

    def errors(self) -> str:
        self.stderr.seek(0)
        return self.stderr.read().decode(errors="replace")[-3000:]

    def close(self) -> int:
        assert self.proc.stdin is not None
        try:
            self.proc.stdin.close()
        except BrokenPipeError:
            pass
        try:
            return self.proc.wait(timeout=30)
        finally:
            self.proc.kill()
            self.proc.wait()
            self._reader.join(timeout=5)
            if self.proc.stdout is not None:
                self.proc.stdout.close()  # else a later gc warns "unclosed file" in another test
            self.stderr.close()


@pytest.fixture(scope="module")
def shared() -> Iterator[Worker]:
    """One worker for the explicit cases (each of which checks it still answers a ping)."""
    w = Worker()
    yield w
    w.close()


@pytest.fixture
def worker(shared: Worker) -> Worker:
    if shared.proc.poll() is not None:
        pytest.fail("an earlier case stopped the shared worker")
    return shared


@pytest.fixture
def own_worker() -> Iterator[Worker]:
    w = Worker()
    yield w
    w.close()


@pytest.fixture(scope="module")
def costmap(tmp_path_factory) -> Path:
    cost = smooth_costmap((60, 80), seed=3, lethal_fraction=0.08)
    cost[0:3, 0:3] = 0.5
    cost[-3:, -3:] = 0.5
    return write_costmap(tmp_path_factory.mktemp("fuzz") / "costmap.tif", cost)


def assert_refused(answers: list[dict[str, Any]], says: str = "") -> dict[str, Any]:
    """One error answer, given as a bad request (not the worker's bug path)."""
    assert len(answers) == 1, answers
    (answer,) = answers
    assert answer["ok"] is False and answer["error"] and "\n" not in answer["error"], answer
    assert "unexpected failure" not in answer["error"] and answer["kind"] != "RuntimeError", answer
    assert says.lower() in answer["error"].lower(), answer
    return answer


def ping_line(**fields: Any) -> bytes:
    return json.dumps({"id": 7, "op": "ping", **fields}).encode()


# -- explicit cases ------------------------------------------------------------------------------


@pytest.mark.parametrize("constant", ["NaN", "Infinity", "-Infinity", "1e400", "-1e400", "1E+999"])
def test_non_finite_numbers_are_refused(worker: Worker, costmap: Path, constant: str) -> None:
    path = costmap
    x, y = world(1, 1)
    assert_refused(worker.ask(f'{{"id": {constant}, "op": "ping"}}'.encode()), "finite")
    plan = f'{{"id": 1, "op": "plan", "costmap": {json.dumps(str(path))}, "points": [[{x}, {y}], [{constant}, {y}]]}}'
    answer = assert_refused(worker.ask(plan.encode()), "finite")
    assert answer["id"] is None  # the line is refused whole: its id is not read either


@pytest.mark.parametrize(
    "opener, closer",
    [("[", "]"), ('{"a":', "}"), ('{"id": 1, "op": "plan", "points": [', "]}")],
    ids=["list", "object", "plan"],
)
def test_deep_nesting_is_refused(worker: Worker, opener: str, closer: str) -> None:
    for depth in (srv.MAX_DEPTH + 1, 1200, (srv.MAX_LINE - 10) // len(opener + closer)):
        assert_refused(worker.ask((opener * depth + "1" + closer * depth).encode()), "nested")
    assert_refused(worker.ask((opener * ((srv.MAX_LINE - 10) // len(opener))).encode()))  # never closed


def test_a_request_nested_just_enough_is_answered(worker: Worker) -> None:
    (answer,) = worker.ask(ping_line(extra=[[[[{"a": [[1]]}]]]]))
    assert answer["ok"] and answer["id"] == 7


@pytest.mark.parametrize("digits", [21, 400, 5000, 100_000])
def test_long_integers_are_a_bad_request(worker: Worker, costmap: Path, digits: int) -> None:
    path = costmap
    big = "9" * digits
    assert_refused(worker.ask(f'{{"id": {big}, "op": "ping"}}'.encode()), "digits")
    plan = f'{{"id": 1, "op": "plan", "costmap": {json.dumps(str(path))}, "points": [[{big}, 1], [2, 3]]}}'
    assert_refused(worker.ask(plan.encode()), "digits")
    assert_refused(
        worker.ask(f'{{"id": 1, "op": "load", "costmap": {json.dumps(str(path))}, "band": -{big}}}'.encode())
    )


WRONG_TYPES = [
    ({"op": "ping", "id": [1]}, "id"),
    ({"op": "ping", "id": {"a": 1}}, "id"),
    ({"op": ["ping"]}, "op"),
    ({"op": {"ping": 1}}, "op"),
    ({"op": None}, "op"),
    ({"op": "load", "costmap": 5}, "costmap"),
    ({"op": "load", "costmap": ["a.tif"]}, "costmap"),
    ({"op": "load", "costmap": "a\u0000.tif"}, ""),
    ({"op": "load", "costmap": "COSTMAP", "band": "1"}, "band"),
    ({"op": "load", "costmap": "COSTMAP", "band": True}, "band"),
    ({"op": "load", "costmap": "COSTMAP", "band": 1.5}, "band"),
    ({"op": "load", "costmap": "COSTMAP", "band": 0}, "band"),
    ({"op": "load", "costmap": "COSTMAP", "band": -3}, "band"),
    ({"op": "load", "costmap": "COSTMAP", "band": 2**62}, "band"),
    ({"op": "load", "costmap": "COSTMAP", "overrides": "a.gpkg"}, "overrides"),
    ({"op": "load", "costmap": "COSTMAP", "overrides": [1]}, "overrides"),
    ({"op": "load", "costmap": "COSTMAP", "overrides": {"a": 1}}, "overrides"),
    ({"op": "plan", "costmap": "COSTMAP", "points": "1,2;3,4"}, "points"),
    ({"op": "plan", "costmap": "COSTMAP", "points": {"start": [1, 2]}}, "points"),
    ({"op": "plan", "costmap": "COSTMAP", "points": [[1, 2, 3], [4, 5, 6]]}, "point"),
    ({"op": "plan", "costmap": "COSTMAP", "points": [[True, False], [1, 2]]}, "point"),
    ({"op": "plan", "costmap": "COSTMAP", "points": [[None, 1], [1, 2]]}, "point"),
    ({"op": "plan", "costmap": "COSTMAP", "points": [[1e308, -1e308], [1e308, 1e308]]}, ""),
    ({"op": "plan", "costmap": "COSTMAP", "points": [[1, 2], [3, 4]], "mode": ["fast"]}, "mode"),
    ({"op": "plan", "costmap": "COSTMAP", "points": [[1, 2], [3, 4]], "mode": {"fast": 1}}, "mode"),
    ({"op": "plan", "costmap": "COSTMAP", "points": [[1, 2], [3, 4]], "vertices": []}, "vertices"),
    ({"op": "plan", "costmap": "COSTMAP", "points": [[1, 2], [3, 4]], "crs": 4326}, "crs"),
    ({"op": "plan", "costmap": "COSTMAP", "points": [[1, 2], [3, 4]], "crs": "EPSG:-1"}, "crs"),
    ({"op": "unload", "costmap": 3}, "costmap"),
    ({"op": "unload", "costmap": {}}, "costmap"),
]


@pytest.mark.parametrize("request_, says", WRONG_TYPES, ids=[json.dumps(r)[:50] for r, _ in WRONG_TYPES])
def test_wrong_types_are_a_bad_request(worker: Worker, costmap: Path, request_: dict, says: str) -> None:
    path = costmap
    line = json.dumps({"id": 1, **request_}).replace('"COSTMAP"', json.dumps(str(path)))
    assert_refused(worker.ask(line.encode()), says)


@pytest.mark.parametrize("body", ["[]", "1", '"ping"', "null", "true", '{"id": 1}', "{", '{"id": 1,,}', "\ufeff{}"])
def test_a_line_that_is_no_request_object_is_refused(worker: Worker, body: str) -> None:
    assert_refused(worker.ask(body.encode()))


def test_over_long_lines_are_refused_and_skipped(worker: Worker) -> None:
    long = ping_line(pad="x" * (srv.MAX_LINE + 10))
    assert_refused(worker.ask(long), "longer than")
    assert_refused(worker.ask(b"[" * (3 * srv.MAX_LINE)), "longer than")
    (answer,) = worker.ask(ping_line(pad="x" * (srv.MAX_LINE - 100)))  # just under: answered
    assert answer["ok"]


@pytest.mark.parametrize(
    "raw",
    [b"\xff\xfe\x00\x01", b'{"id": 1, "op": "\xc3\x28"}', b'{"id": "\xed\xa0\x80", "op": "ping"}', bytes(range(256))],
    ids=["bytes", "bad-utf8-in-string", "surrogate", "every-byte"],
)
def test_bytes_that_are_not_utf8_get_an_error_or_an_answer(worker: Worker, raw: bytes) -> None:
    """Read as U+FFFD: an error answer, or (a string that held the bad bytes) a normal one."""
    for answer in worker.ask(raw):
        assert answer["ok"] or "unexpected failure" not in answer["error"], answer


@pytest.mark.parametrize("tail", [b'{"id": 1, "op": "pi', b'{"id": 1, "op": "ping"}', b"\xe2\x82", b"[[[["])
def test_end_of_input_mid_line_is_answered_and_ends_the_worker(own_worker: Worker, tail: bytes) -> None:
    own_worker.send(tail)
    assert own_worker.proc.stdin is not None
    own_worker.proc.stdin.close()
    answer = own_worker.answer()
    assert answer["ok"] == (tail == b'{"id": 1, "op": "ping"}'), answer
    assert own_worker.proc.wait(timeout=30) == 0, own_worker.errors()


def test_an_answer_json_cannot_hold_is_an_error_answer_not_a_crash(monkeypatch) -> None:
    """In process: should an operation ever answer NaN, the worker says so and keeps serving."""
    monkeypatch.setattr(srv.PlanServer, "op_unload", lambda self, request: {"unloaded": float("nan")})
    out = io.StringIO()
    requests = [{"id": 1, "op": "unload"}, {"id": 2, "op": "ping"}]
    assert srv.serve(io.StringIO("".join(json.dumps(r) + "\n" for r in requests)), out) == 0
    first, second = (json.loads(line) for line in out.getvalue().splitlines())
    assert first["id"] == 1 and not first["ok"] and "unexpected failure" in first["error"]
    assert second["id"] == 2 and second["ok"]


# -- the fuzz ------------------------------------------------------------------------------------

#: Value texts json.dumps never writes, put in place of the markers below anywhere a value goes.
SPECIALS = ("NaN", "Infinity", "-Infinity", "1e400", "-1E+999", "9" * 400, "-" + "7" * 25, "[" * 3000 + "]" * 3000)
_special = st.sampled_from([f"@@{i}@@" for i in range(len(SPECIALS))])


def _dumps(value: Any) -> bytes:
    text = json.dumps(value, allow_nan=True)
    for i, special in enumerate(SPECIALS):
        text = text.replace(f'"@@{i}@@"', special)
    return text.encode()


_scalars = (
    _special
    | st.none()
    | st.booleans()
    | st.integers(min_value=-(10**30), max_value=10**30)
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.text(max_size=20)
)
_json = st.recursive(
    _scalars,
    lambda kids: st.lists(kids, max_size=4) | st.dictionaries(st.text(max_size=8), kids, max_size=4),
    max_leaves=12,
)
_number = _special | st.integers(-(10**25), 10**25) | st.floats(allow_nan=True, allow_infinity=True) | _scalars
_point = st.lists(_number, min_size=0, max_size=3) | _json


def _requests(costmap: str) -> st.SearchStrategy[bytes]:
    """Plausible requests with random parts (non-finite and huge numbers, deep nesting among them),
    random JSON, cut-off lines and random bytes (never ``shutdown``)."""
    fields = st.fixed_dictionaries(
        {"op": st.sampled_from(["ping", "load", "plan", "unload", "exec", ""]) | _json},
        optional={
            "id": _json,
            "costmap": st.sampled_from([costmap, "missing.tif", "", ".", "/"]) | _json,
            "points": st.lists(_point, max_size=5) | _json,
            "band": st.integers(-(10**22), 10**22) | _json,
            "overrides": st.lists(st.text(max_size=10) | _json, max_size=2) | _json,
            "mode": st.sampled_from(["fast", "exact"]) | _json,
            "vertices": st.sampled_from(["turns", "pixels"]) | _json,
            "crs": st.sampled_from(["EPSG:4326", "EPSG:32633", "no crs"]) | _json,
        },
    )
    as_json = fields.map(_dumps)
    any_json = _json.map(_dumps)
    raw = st.binary(max_size=200).map(lambda b: b.replace(b"\n", b" ").replace(b"\r", b" "))
    cut = as_json.flatmap(lambda line: st.integers(0, len(line)).map(lambda n: line[:n]))
    return as_json | any_json | raw | cut


def test_random_requests_never_stop_the_worker(own_worker: Worker, costmap: Path) -> None:
    path = costmap
    # a valid plan on the way, so the planner itself is exercised between the bad requests
    (ok,) = own_worker.ask(
        json.dumps({"id": 1, "op": "plan", "costmap": str(path), "points": [world(1, 1), world(58, 78)]}).encode()
    )
    assert ok["ok"], ok

    @settings(
        max_examples=150, deadline=10_000, suppress_health_check=list(HealthCheck), database=None, derandomize=True
    )
    @given(line=_requests(str(path)))
    def check(line: bytes) -> None:
        for answer in own_worker.ask(line):
            if not answer["ok"]:
                assert answer["error"] and "\n" not in answer["error"], answer
                assert "unexpected failure" not in answer["error"], (line[:300], answer)

    check()
    assert own_worker.close() == 0
