"""`overseec interpret`: the stable JSON document, the summary, LLM options and one-line errors."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from overseec_core.cli import EXIT_USER, main
from overseec_core.costlang import check_program

from ..interpret.chat_server import refused_url
from ..interpret.conftest import _no_llm_env, chat_server  # noqa: F401 (fixtures)

OVERSEEC = Path(sys.executable).with_name("overseec")
PAPER = "Prefer the roads and trails, grass should be fine, try to avoid the baseball field as much as possible."
LLM_VARS = (
    "OVERSEEC_LLM_URL",
    "OVERSEEC_LLM_MODEL",
    "OVERSEEC_LLM_API_KEY",
    "OVERSEEC_LLM_TIMEOUT",
    "OVERSEEC_LLM_RETRIES",
    "OVERSEEC_LLM_FALLBACK",
)


def test_prompt_option_reads_as_the_argument_does(tmp_path, capsys):
    """`interpret --prompt TEXT`, as run, costmap and compare take it; the positional form stays."""
    assert main(["-q", "interpret", "--offline", "--json", "--prompt", PAPER]) == 0
    by_option = json.loads(capsys.readouterr().out)
    assert main(["-q", "interpret", "--offline", "--json", PAPER]) == 0
    assert json.loads(capsys.readouterr().out) == by_option and by_option["prompt"] == PAPER
    assert main(["-q", "interpret", f"--prompt={PAPER}", "--offline", "--run-dir", str(tmp_path)]) == 0
    assert "baseball field" in capsys.readouterr().out
    assert json.loads((tmp_path / "interpretation.json").read_text()) == by_option


def test_json_document_is_stable_and_complete(capsys):
    assert main(["-q", "interpret", "--offline", "--json", PAPER]) == 0
    doc = json.loads(capsys.readouterr().out)
    for key in ("entities", "preferences", "hierarchy", "cues", "program", "unparsed"):
        assert key in doc
    assert all({"name", "geometry"} <= set(e) for e in doc["entities"])
    assert all(set(p) == {"entity", "rank", "weight", "lethal", "phrase", "prior", "band"} for p in doc["preferences"])
    phrases = {p["entity"]: p["phrase"] for p in doc["preferences"]}
    assert phrases["grass"] == "grass should be fine" and phrases["tree"] == ""  # tree: unstated
    ranks = {p["entity"]: p["rank"] for p in doc["preferences"]}
    assert (ranks["road"], ranks["trail"], ranks["grass"], ranks["baseball field"]) == (1, 1, 2, 3)
    bands = {p["entity"]: p["band"] for p in doc["preferences"]}
    assert (bands["road"], bands["grass"], bands["tree"], bands["baseball field"]) == (
        "preferred",
        "neutral",
        "prior",
        "avoided",
    )
    assert doc["hierarchy"] == [["baseball field", "grass"]]
    assert doc["unparsed"] == [] and doc["cues"] == []
    check_program(doc["program"], [e["name"] for e in doc["entities"]])
    # stable: the same prompt prints the same bytes
    assert main(["-q", "interpret", "--offline", "--json", PAPER]) == 0
    assert json.loads(capsys.readouterr().out) == doc


def test_summary_table(capsys):
    assert main(["-q", "interpret", "--offline", "avoid grass unless near a road, on weekends"]) == 0
    out = capsys.readouterr().out
    assert "entity" in out and "geometry" in out and "rank" in out and "level" in out
    # levels in words: what the prompt avoids, what priors cover, what stays neutral
    assert re.search(r"^grass +areal +\d+ +0\.70 +avoided$", out, re.M)
    assert re.search(r"^building +areal +\d+ +1\.00 +prior$", out, re.M)
    assert re.search(r"^road +linear +\d+ +0\.50 +neutral$", out, re.M)
    assert "grass: not within 10 m of road" in out
    assert "'on weekends'" in out or "'weekends'" in out
    assert "cost program:" in out and "cost = " in out


def test_prompt_file_out_and_run_dir(tmp_path: Path, capsys):
    prompt = tmp_path / "prompt.txt"
    prompt.write_text("never cross the river\n", encoding="utf-8")
    out = tmp_path / "interp.json"
    run_dir = tmp_path / "run"
    assert (
        main(
            ["-q", "interpret", "--offline", "--prompt-file", str(prompt), "--out", str(out), "--run-dir", str(run_dir)]
        )
        == 0
    )
    doc = json.loads(out.read_text())
    assert doc["prompt"] == "never cross the river"
    river = {p["entity"]: p for p in doc["preferences"]}["river"]
    assert river["lethal"] is False and river["band"] == "avoided"  # a rule that bends, not lethal
    assert {"kind": "no_cross", "entity": "river", "metres": None, "other": None, "hard": True} in doc["cues"]
    manifest = json.loads((run_dir / "manifest.json").read_text())
    assert manifest["interpretation"] == doc
    assert manifest["stages"]["interpret"]["status"] == "ok"
    assert manifest["parameters"]["interpret"]["interpreter"] == "offline"
    assert json.loads((run_dir / "interpretation.json").read_text()) == doc
    assert not list(tmp_path.glob(".*partial"))


@pytest.mark.parametrize(
    "argv, match",
    [
        (["interpret", "--offline", ""], "the mission prompt is empty"),
        (["interpret", "--offline"], "no prompt: give the prompt once, as an argument, with --prompt TEXT or"),
        (
            ["interpret", "--offline", "--prompt", "avoid water", "prefer roads"],
            "both the PROMPT argument and --prompt",
        ),
        (["interpret", "--offline", "--prompt", "x", "--prompt-file", "-"], "both --prompt and --prompt-file"),
        (["interpret", "--offline", "--prompt", ""], "the mission prompt is empty"),
        (["interpret", "--offline", "--prompt-file", "/no/such/file.txt"], "no such file"),
        (["interpret", "--offline", "--llm-url", "http://h/v1", "avoid water"], "choose one"),
        (["interpret", "--llm-url", "http://h/v1", "avoid water"], "no model name"),
        (["interpret", "--llm-url", "h:1", "--llm-model", "m", "avoid water"], "not an http"),
        (
            [
                "interpret",
                "--llm-url",
                "http://h/v1",
                "--llm-model",
                "m",
                "--llm-key-env",
                "NO_SUCH_VAR_X",
                "avoid water",
            ],
            "NO_SUCH_VAR_X",
        ),
        (["interpret", "--offline", "--out", f"{__file__}/x.json", "avoid water"], "is a file, not a folder"),
    ],
)
def test_user_errors_are_one_line(argv, match, capsys):
    assert main(["-q"] + argv) == EXIT_USER
    err = capsys.readouterr().err
    assert match in err and err.count("\n") == 1 and "Traceback" not in err


def test_unreachable_llm_is_a_one_line_error(capsys):
    assert (
        main(["-q", "interpret", "--llm-url", refused_url(), "--llm-model", "m", "--llm-retries", "0", "avoid water"])
        == EXIT_USER
    )
    err = capsys.readouterr().err
    assert "cannot connect" in err and err.count("\n") == 1


def test_unreachable_llm_with_fallback(capsys):
    assert (
        main(
            [
                "-q",
                "interpret",
                "--json",
                "--llm-url",
                refused_url(),
                "--llm-model",
                "m",
                "--llm-retries",
                "0",
                "--llm-fallback-offline",
                "avoid water",
            ]
        )
        == 0
    )
    doc = json.loads(capsys.readouterr().out)
    assert doc["source"] == "offline" and "LLM failed" in doc["notes"][0]


def test_llm_via_cli_options(chat_server, monkeypatch, capsys):  # noqa: F811 (pytest fixture)
    monkeypatch.setenv("MY_LLM_KEY", "sk-cli-key")
    reply = {
        "entities": [{"name": "water", "geometry": "areal", "prompts": ["water"]}],
        "preferences": [{"entity": "water", "rank": 2, "weight": 1.0, "lethal": True}],
        "hierarchy": [],
        "cues": [],
        "unparsed": [],
    }
    chat_server.reply(json.dumps(reply), '```\ncost = where(M["water"], 1.0, 0.5)\nlethal = M["water"]\n```')
    assert (
        main(
            [
                "-q",
                "interpret",
                "--json",
                "--llm-url",
                chat_server.url,
                "--llm-model",
                "cli-model",
                "--llm-key-env",
                "MY_LLM_KEY",
                "--no-priors",
                "never enter water",
            ]
        )
        == 0
    )
    doc = json.loads(capsys.readouterr().out)
    assert doc["source"] == "llm:cli-model"
    assert doc["program"] == 'cost = where(M["water"], 1.0, 0.5)\nlethal = M["water"]\n'
    assert chat_server.requests[0]["headers"]["Authorization"] == "Bearer sk-cli-key"
    assert chat_server.requests[0]["body"]["model"] == "cli-model"


def test_subprocess(tmp_path: Path):
    env = {k: v for k, v in os.environ.items() if k not in LLM_VARS}
    ok = subprocess.run(
        [
            str(OVERSEEC),
            "-q",
            "interpret",
            "--offline",
            "--json",
            "stay on the center of the road, avoid the electric tower",
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert ok.returncode == 0, ok.stderr
    doc = json.loads(ok.stdout)
    assert {"kind": "centre", "entity": "road", "metres": None, "other": None, "hard": False} in doc["cues"]
    weights = {p["entity"]: p["weight"] for p in doc["preferences"]}
    assert weights["electric tower"] == 0.7 and weights["road"] == 0.0  # avoided / preferred
    bad = subprocess.run(
        [str(OVERSEEC), "interpret", "--offline", "   "], capture_output=True, text=True, env=env, timeout=300
    )
    assert bad.returncode == EXIT_USER and "Traceback" not in bad.stderr
    assert bad.stderr.strip().startswith("overseec: error: the mission prompt is empty")
