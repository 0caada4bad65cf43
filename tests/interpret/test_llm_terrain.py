"""Terrain in the LLM's program prompt (issue 26): with a DEM the operator reference offers
``slope`` (degrees) and ``roughness`` (metres); without one it does not, and a program that reads
them goes back for repair. Against the real scripted chat completions server."""

from __future__ import annotations

import json

from overseec_core.costlang import TERRAIN, operator_reference
from overseec_core.interpret.llm_interpreter import interpret_llm

from .test_llm_interpreter import ENTITY_REPLY, GOOD_PROGRAM, PROMPT, config, fenced

#: GOOD_PROGRAM with steep ground raised: valid only when the run has a DEM.
SLOPE_PROGRAM = GOOD_PROGRAM + "cost = max(cost, normalize(slope, 15, 30))\n"


def _request_text(request: dict) -> str:
    """Everything a request sent to the LLM, as one string."""
    return "\n".join(m["content"] for m in request["body"]["messages"])


def test_reference_lists_the_terrain_fields_only_with_a_dem():
    with_dem, without = operator_reference(terrain=True), operator_reference()
    for name, spec in TERRAIN.items():
        assert f"`{name}`" in with_dem and spec.unit in with_dem
        assert name not in without
    assert with_dem.startswith(without)


def test_with_a_dem_the_program_request_offers_slope_and_roughness(chat_server):
    chat_server.reply(json.dumps(ENTITY_REPLY), fenced(GOOD_PROGRAM))
    it = interpret_llm(PROMPT, config(chat_server.url), terrain=True)
    entity_call, program_call = chat_server.requests
    system = program_call["body"]["messages"][0]["content"]
    assert "`slope`" in system and "degrees" in system
    assert "`roughness`" in system and "metres" in system
    assert "slope" not in _request_text(entity_call)
    assert it.program == GOOD_PROGRAM


def test_with_a_dem_a_slope_program_is_kept(chat_server):
    chat_server.reply(json.dumps(ENTITY_REPLY), fenced(SLOPE_PROGRAM))
    it = interpret_llm(PROMPT, config(chat_server.url), terrain=True)
    assert it.program == SLOPE_PROGRAM
    assert any("valid on attempt 1" in n for n in it.notes)


def test_without_a_dem_no_request_mentions_slope(chat_server):
    chat_server.reply(json.dumps(ENTITY_REPLY), fenced(GOOD_PROGRAM))
    it = interpret_llm(PROMPT, config(chat_server.url))
    assert len(chat_server.requests) == 2
    for request in chat_server.requests:
        text = _request_text(request)
        assert "slope" not in text and "roughness" not in text
    assert it.program == GOOD_PROGRAM


def test_without_a_dem_a_slope_program_goes_back_with_the_reason(chat_server):
    chat_server.reply(json.dumps(ENTITY_REPLY), fenced(SLOPE_PROGRAM), fenced(GOOD_PROGRAM))
    it = interpret_llm(PROMPT, config(chat_server.url))
    assert len(chat_server.requests) == 3
    repair = chat_server.requests[2]["body"]["messages"][-1]["content"]
    assert "'slope' is a terrain field and this run has no DEM" in repair
    assert it.program == GOOD_PROGRAM
    assert any("program 1 invalid" in n and "no DEM" in n for n in it.notes)


def test_interpret_terrain_reaches_the_llm_and_the_manifest(chat_server, tmp_path, capsys):
    """`overseec interpret --terrain` (what `run --dem` and the dock with a DEM ask) offers the LLM
    the terrain fields, keeps a slope program and records the choice in the run's manifest;
    without it the same program is sent back for repair."""
    from overseec_core.cli import main

    chat_server.reply(json.dumps(ENTITY_REPLY), fenced(SLOPE_PROGRAM))
    base = ["interpret", "--llm-url", chat_server.url, "--llm-model", "m", "--json"]
    assert main([*base, "--terrain", "--run-dir", str(tmp_path / "run"), "--", PROMPT]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["program"] == SLOPE_PROGRAM
    assert "`slope`" in _request_text(chat_server.requests[1])
    manifest = json.loads((tmp_path / "run" / "manifest.json").read_text())
    assert manifest["parameters"]["interpret"]["terrain"] is True
