"""Start-up lines of the servers (:mod:`overseec_core.liveness`) on a real ``overseec`` process."""

from __future__ import annotations

import json
import os
import subprocess
import sys

from overseec_core import liveness

OVERSEEC = os.path.join(os.path.dirname(sys.executable), "overseec")


def _stdout_of(command: str, requests: str) -> list[dict]:
    res = subprocess.run([OVERSEEC, command], input=requests, capture_output=True, text=True, timeout=120, check=True)
    return [json.loads(line) for line in res.stdout.splitlines()]


def test_a_server_says_it_is_starting_until_it_answers_then_only_answers() -> None:
    lines = _stdout_of("plan-server", '{"id": 1, "op": "ping"}\n{"id": 2, "op": "ping"}\n')
    answers = [i for i, line in enumerate(lines) if "id" in line]
    assert [lines[i]["id"] for i in answers] == [1, 2] and answers == [len(lines) - 2, len(lines) - 1]
    starting = lines[: answers[0]]
    assert starting, "no start-up line before the first answer"
    assert all(line == {"event": liveness.STARTING, "modules": line["modules"]} for line in starting)
    counts = [line["modules"] for line in starting]
    assert counts == sorted(counts) and counts[0] > 0


def test_other_commands_print_no_start_up_lines() -> None:
    res = subprocess.run([OVERSEEC, "--version"], capture_output=True, text=True, timeout=120)
    assert liveness.STARTING not in res.stdout and res.returncode == 0


def test_only_server_commands_start_the_lines() -> None:
    assert not liveness.start(["overseec", "plan"]) and not liveness.start(["overseec"])
    assert liveness.start(["overseec", "-q", "sam-server"])
    liveness.stop()
    liveness.stop()  # stopping twice is harmless


def test_every_server_command_is_a_command_of_the_cli() -> None:
    for command in liveness.SERVER_COMMANDS:
        res = subprocess.run([OVERSEEC, command, "--help"], capture_output=True, text=True, timeout=120)
        assert res.returncode == 0, (command, res.stderr)
