"""The LLM interpreter (two calls, validation, repair, fallbacks) against a real scripted server."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from overseec_core.costlang import check_program, operator_reference, program_from_interpretation
from overseec_core.errors import LLMError
from overseec_core.interpret import interpret, lexicon
from overseec_core.interpret.llm import LLMConfig
from overseec_core.interpret.llm_interpreter import (
    ENTITY_SCHEMA,
    ReplyError,
    extract_json_object,
    extract_program,
    parse_entity_reply,
)
from overseec_core.schema import Cue

KEY = "sk-interp-KEY"
PROMPT = "Prefer the roads and trails, grass should be fine, try to avoid the baseball field as much as possible."

ENTITY_REPLY = {
    "entities": [
        {"name": "road", "geometry": "linear", "prompts": ["road"]},
        {"name": "trail", "geometry": "linear", "prompts": ["trail", "footpath"]},
        {"name": "grass", "geometry": "areal", "prompts": ["grass"]},
        {"name": "Baseball Fields", "geometry": "areal", "prompts": ["baseball field"]},
    ],
    "preferences": [
        {"entity": "road", "rank": 1, "weight": 0.1, "lethal": False},
        {"entity": "trail", "rank": 1, "weight": 0.1, "lethal": False},
        {"entity": "grass", "rank": 2, "weight": 0.5, "lethal": False},
        {"entity": "baseball fields", "rank": 3, "weight": 0.95, "lethal": False},
    ],
    "hierarchy": [{"child": "baseball fields", "parent": "grass"}],
    "cues": [{"kind": "center", "entity": "road", "metres": None, "other": None, "hard": False}],
    "unparsed": [],
}
#: Reads the unsaid hazards too: their priors (tree 0.85, building and water 1.0) bind the LLM.
PRIOR_TERMS = '0.35 * P["tree"], 0.5 * P["building"], 0.5 * P["water"]'
GOOD_PROGRAM = f"""\
acc = sum(-0.5 * P["road"], -0.5 * P["trail"], 0.5 * P["baseball fields"], {PRIOR_TERMS})
cost = clip(0.5 + acc, 0.0, 1.0)
keep_out = OR(M["building"], M["water"])
"""
#: Prices the obstacles (buildings, water: level 1.0) but does not go around them: refused.
NO_KEEP_OUT_PROGRAM = f"""\
acc = sum(-0.5 * P["road"], -0.5 * P["trail"], 0.5 * P["baseball fields"], {PRIOR_TERMS})
cost = clip(0.5 + acc, 0.0, 1.0)
"""
#: Keeps the prompt's own levels but leaves the unsaid hazards neutral: refused (priors).
NO_PRIORS_PROGRAM = """\
acc = sum(-0.5 * P["road"], -0.5 * P["trail"], 0.5 * P["baseball fields"])
cost = clip(0.5 + acc, 0.0, 1.0)
"""
#: Valid in the language but off the cost scale: uncovered ground at 1.0 (the old convention).
OFF_SCALE_PROGRAM = """\
acc = sum(0.1 * P["road"], 0.1 * P["trail"], 0.4 * P["grass"], 0.95 * P["baseball fields"])
cost = where(OR(M["road"], M["trail"], M["grass"], M["baseball fields"]), min(acc, 1.0), 1.0)
"""
#: Neutral ground right, but the avoided field below neutral.
FIELD_BELOW_NEUTRAL = f"""\
acc = sum(-0.5 * P["road"], -0.5 * P["trail"], -0.1 * P["baseball fields"], {PRIOR_TERMS})
cost = clip(0.5 + acc, 0.0, 1.0)
keep_out = OR(M["building"], M["water"])
"""


def config(url: str, **kw) -> LLMConfig:
    return LLMConfig(
        url,
        "test-model",
        api_key=KEY,
        timeout_s=kw.pop("timeout_s", 2.0),
        retries=kw.pop("retries", 1),
        backoff_s=0.01,
        **kw,
    )


def fenced(text: str, lang: str = "python") -> str:
    return f"Here you go:\n```{lang}\n{text}```\nHope this helps."


def test_two_calls_good_replies(chat_server):
    chat_server.reply(json.dumps(ENTITY_REPLY), fenced(GOOD_PROGRAM))
    it = interpret(PROMPT, llm=config(chat_server.url))
    assert it.source == "llm:test-model"
    assert it.program == GOOD_PROGRAM
    prefs = {p.entity: (p.rank, p.weight, p.lethal) for p in it.preferences}
    # weights become levels on the cost scale: best 0, neutral 0.5, worst avoided 1
    assert prefs["road"] == (1, 0.0, False) and prefs["trail"] == (1, 0.0, False)
    assert prefs["grass"] == (2, 0.5, False) and prefs["baseball fields"] == (4, 0.95, False)
    # defaults not in the reply take their priors, as in the offline interpreter: trees below buildings
    assert prefs["tree"] == (3, 0.85, False) and prefs["building"] == (5, 1.0, False)
    assert {p.entity for p in it.preferences if p.prior} == {"tree", "building", "water"}
    assert [e.name for e in it.entities][:6] == ["road", "trail", "grass", "tree", "building", "water"]
    assert ("baseball fields", "grass") in it.hierarchy
    assert Cue("centre", "road") in it.cues
    assert "templates: entities.v2, program.v3" in it.notes
    assert any("valid on attempt 1" in n for n in it.notes)
    # what the server received
    first, second = chat_server.requests
    for req in (first, second):
        assert req["headers"]["Authorization"] == f"Bearer {KEY}"
        assert req["body"]["model"] == "test-model"
    assert first["body"]["response_format"]["json_schema"]["schema"] == ENTITY_SCHEMA
    assert PROMPT in first["body"]["messages"][-1]["content"]
    assert "response_format" not in second["body"]
    system, user = (m["content"] for m in second["body"]["messages"])
    assert operator_reference().strip()[:200] in system  # the operator table goes to the LLM
    assert '"baseball fields"' in system and PROMPT in user
    assert "cost = clip(0.5 + acc, 0.0, 1.0)" in user  # the mechanical baseline


def test_malformed_json_goes_back_then_fix(chat_server):
    chat_server.reply('{"entities": [ {"name": "road", ', json.dumps(ENTITY_REPLY), fenced(GOOD_PROGRAM))
    it = interpret(PROMPT, llm=config(chat_server.url))
    assert len(chat_server.requests) == 3
    repair = chat_server.requests[1]["body"]["messages"]
    assert repair[-2] == {"role": "assistant", "content": '{"entities": [ {"name": "road", '}
    assert "could not be used" in repair[-1]["content"] and "no valid JSON" in repair[-1]["content"]
    assert any("entity reply 1 unusable" in n for n in it.notes)
    assert it.program == GOOD_PROGRAM


def test_invalid_fields_go_back_with_the_reason(chat_server):
    bad = dict(ENTITY_REPLY, preferences=[{"entity": "road", "rank": 1, "weight": "cheap", "lethal": False}])
    chat_server.reply(json.dumps(bad), json.dumps(ENTITY_REPLY), fenced(GOOD_PROGRAM))
    interpret(PROMPT, llm=config(chat_server.url))
    assert "preferences[0].weight must be a number" in chat_server.requests[1]["body"]["messages"][-1]["content"]


def test_json_in_fences_with_chatter_is_accepted(chat_server):
    chat_server.reply(
        "Sure! Here is the JSON:\n```json\n" + json.dumps(ENTITY_REPLY) + "\n```", fenced(GOOD_PROGRAM, "")
    )
    it = interpret(PROMPT, llm=config(chat_server.url))
    assert len(chat_server.requests) == 2 and it.program == GOOD_PROGRAM


def test_unusable_entity_replies_are_an_error_after_the_attempts(chat_server):
    chat_server.reply("no idea", "still no idea", "{not json}")
    with pytest.raises(LLMError, match="no usable entity reply in 3 attempts"):
        interpret(PROMPT, llm=config(chat_server.url))
    assert len(chat_server.requests) == 3


def test_invalid_program_goes_back_with_line_and_column_then_fix(chat_server):
    bad = 'cost = 0.1 * M["road"]\nlethal = M["lava"]\n'
    chat_server.reply(json.dumps(ENTITY_REPLY), fenced(bad), fenced(GOOD_PROGRAM))
    it = interpret(PROMPT, llm=config(chat_server.url))
    assert it.program == GOOD_PROGRAM
    repair = chat_server.requests[2]["body"]["messages"][-1]["content"]
    assert "line 2, column" in repair and "lava" in repair
    assert any("program 1 invalid: line 2" in n for n in it.notes)


@pytest.mark.parametrize(
    "off_scale, message, line",
    [
        (OFF_SCALE_PROGRAM, "ground covered by no entity costs 1.00; it must be neutral", "line 2, column"),
        (FIELD_BELOW_NEUTRAL, "gives 'baseball fields' a cost of 0.40, at or below neutral", "line 1, column 54"),
    ],
)
def test_a_program_off_the_cost_scale_goes_back_located_then_fix(chat_server, off_scale, message, line):
    chat_server.reply(json.dumps(ENTITY_REPLY), fenced(off_scale), fenced(GOOD_PROGRAM))
    it = interpret(PROMPT, llm=config(chat_server.url))
    assert it.program == GOOD_PROGRAM
    repair = chat_server.requests[2]["body"]["messages"][-1]["content"]
    assert message in repair and line in repair


def test_a_program_that_leaves_the_unsaid_hazards_neutral_goes_back(chat_server):
    """The priors bind the LLM as they bind the offline interpreter: a program that keeps the
    prompt's own levels but prices buildings like open ground is refused, with the reason."""
    chat_server.reply(json.dumps(ENTITY_REPLY), fenced(NO_PRIORS_PROGRAM), fenced(GOOD_PROGRAM))
    it = interpret(PROMPT, llm=config(chat_server.url))
    assert it.program == GOOD_PROGRAM
    repair = chat_server.requests[2]["body"]["messages"][-1]["content"]
    assert "never reads 'tree'" in repair and "avoids" in repair


def test_a_program_that_drives_through_the_obstacles_goes_back(chat_server):
    """Buildings and water nobody mentioned are obstacles (level 1.0): a program that prices them
    but leaves them out of keep_out is refused with the reason, located at the entity."""
    chat_server.reply(json.dumps(ENTITY_REPLY), fenced(NO_KEEP_OUT_PROGRAM), fenced(GOOD_PROGRAM))
    it = interpret(PROMPT, llm=config(chat_server.url))
    assert it.program == GOOD_PROGRAM
    repair = chat_server.requests[2]["body"]["messages"][-1]["content"]
    assert "leaves 'building' out of keep_out" in repair and "obstacle" in repair


def test_still_invalid_program_falls_back_and_says_so(chat_server, tmp_path: Path):
    marker = tmp_path / "pwned"
    evil = f'cost = __import__("os").system("touch {marker}")\n'
    chat_server.reply(
        json.dumps(ENTITY_REPLY), fenced("import os\ncost = 1\n"), fenced(evil), 'cost = 0.5 * M["road"].sum()'
    )
    it = interpret(PROMPT, llm=config(chat_server.url))
    assert len(chat_server.requests) == 4
    assert not marker.exists()  # LLM output is data: nothing was executed
    expected = program_from_interpretation(it.entities, it.preferences, it.hierarchy, it.cues)
    assert it.program == expected
    check_program(it.program, [e.name for e in it.entities])
    assert any("still invalid after 3 attempts" in n and "derived from the preferences" in n for n in it.notes)


def test_http_400_for_response_format_then_success_without_it(chat_server):
    chat_server.reply(
        {"status": 400, "body": "unknown field response_format"},
        "```json\n" + json.dumps(ENTITY_REPLY) + "\n```",
        fenced(GOOD_PROGRAM),
    )
    it = interpret(PROMPT, llm=config(chat_server.url))
    bodies = chat_server.bodies()
    assert "response_format" in bodies[0] and "response_format" not in bodies[1]
    assert any("does not support structured output" in n for n in it.notes)
    assert it.program == GOOD_PROGRAM


def test_http_500_then_success(chat_server):
    chat_server.reply(
        {"status": 500, "body": "warming up"},
        json.dumps(ENTITY_REPLY),
        {"status": 502, "body": "proxy"},
        fenced(GOOD_PROGRAM),
    )
    it = interpret(PROMPT, llm=config(chat_server.url))
    assert it.program == GOOD_PROGRAM and len(chat_server.requests) == 4


def test_timeouts_are_an_llm_error(chat_server):
    chat_server.reply(*[{"sleep": 1.0, "content": "late"}] * 2)
    with pytest.raises(LLMError, match=r"timed out \(no complete answer within 0.3 s\)"):
        interpret(PROMPT, llm=config(chat_server.url, timeout_s=0.3, retries=1))


def test_unreachable_llm_is_an_error_by_default(dead_url):
    with pytest.raises(LLMError, match="cannot connect"):
        interpret(PROMPT, llm=config(dead_url, retries=0))


def test_unreachable_llm_falls_back_offline_when_configured(dead_url):
    it = interpret(PROMPT, llm=config(dead_url, retries=0, fallback_offline=True))
    assert it.source == "offline"
    assert "LLM failed" in it.notes[0] and "cannot connect" in it.notes[0]
    assert {p.entity: p.band for p in it.preferences}["baseball field"] == "avoided"


def test_program_call_failure_with_fallback_uses_the_derived_program(chat_server):
    chat_server.reply(json.dumps(ENTITY_REPLY), *[{"status": 500, "body": "down"}] * 2)
    it = interpret(PROMPT, llm=config(chat_server.url, fallback_offline=True))
    assert it.source == "llm:test-model"
    assert it.program == program_from_interpretation(it.entities, it.preferences, it.hierarchy, it.cues)
    assert any("program: LLM failed" in n for n in it.notes)


def test_interpret_uses_the_environment(chat_server, monkeypatch):
    monkeypatch.setenv("OVERSEEC_LLM_URL", chat_server.url)
    monkeypatch.setenv("OVERSEEC_LLM_MODEL", "env-model")
    monkeypatch.setenv("OVERSEEC_LLM_API_KEY", KEY)
    chat_server.reply(json.dumps(ENTITY_REPLY), fenced(GOOD_PROGRAM))
    assert interpret(PROMPT).source == "llm:env-model"
    assert chat_server.requests[0]["headers"]["Authorization"] == f"Bearer {KEY}"
    assert interpret(PROMPT, offline=True).source == "offline"  # offline wins, no request
    assert len(chat_server.requests) == 2


# ----------------------------------------------------------------------------- parsing units


def test_extract_json_object_tolerates_fences_and_chatter():
    assert extract_json_object('{"a": 1}') == {"a": 1}
    assert extract_json_object('```json\n{"a": 1}\n```') == {"a": 1}
    assert extract_json_object('The answer is {"a": {"b": [1, 2]}} -- done') == {"a": {"b": [1, 2]}}
    assert extract_json_object('[1, 2] then {"a": 2}') == {"a": 2}
    with pytest.raises(ReplyError, match="empty"):
        extract_json_object("   ")
    with pytest.raises(ReplyError, match="no valid JSON object"):
        extract_json_object('{"a": 1')


def test_extract_program_forms():
    assert extract_program("```python\ncost = 1\n```") == "cost = 1"
    assert extract_program("text\n```\ncost = 1\n```\nmore") == "cost = 1"
    assert extract_program('{"program": "cost = 1"}') == "cost = 1"
    assert extract_program("cost = 1\n") == "cost = 1"
    assert extract_program("```cost\ncost = 1") == "cost = 1"  # unterminated fence


def test_parse_entity_reply_normalises_and_notes():
    reply = parse_entity_reply(
        {
            "entities": [{"name": "  Dirt   Road ", "geometry": "line"}, "pond"],
            "preferences": [
                {"entity": "dirt road", "rank": 1},
                {"entity": "pond", "rank": 3},
                {"entity": "lava", "weight": 1.7, "lethal": "true"},
                {"entity": "grass", "weight": -0.2},
            ],
            "hierarchy": [["pond", "water"]],
            "cues": [
                {"kind": "edge", "entity": "dirt road"},
                {"kind": "far", "entity": "lava", "metres": 9000},
                {"kind": "unless_near", "entity": "grass"},
            ],
        }
    )
    names = [e.name for e in reply.entities]
    assert names == ["dirt road", "pond", "lava", "grass"]
    assert reply.entities[0].geometry == "linear"  # bad geometry -> the table's guess
    assert reply.stated["dirt road"] == (0.1, False)  # from rank 1 of 3
    assert reply.stated["pond"][0] == pytest.approx(lexicon.AVOID)
    assert reply.stated["lava"] == (1.0, True)
    assert reply.stated["grass"] == (0.0, False)
    assert reply.hierarchy == (("pond", "water"),)
    assert reply.cues == (Cue("side", "dirt road"), Cue("far", "lava", 500.0))
    notes = " | ".join(reply.notes)
    assert "'line' is not linear/areal" in notes and "clipped" in notes
    assert "did not list as an entity" in notes and "names no other entity" in notes


def test_a_cue_without_metres_takes_the_graded_reach_for_a_wish_and_the_plain_default_for_a_rule():
    cues = [
        {"kind": "far", "entity": "pond"},
        {"kind": "near", "entity": "road", "metres": None, "hard": False},
        {"kind": "far", "entity": "building", "hard": True},
        {"kind": "if_near", "entity": "grass", "other": "road"},
    ]
    reply = parse_entity_reply({"entities": ["pond", "road", "building", "grass"], "cues": cues})
    assert reply.cues == (
        Cue("far", "pond", lexicon.DEFAULT_GRADED_DISTANCE_M),
        Cue("near", "road", lexicon.DEFAULT_GRADED_DISTANCE_M),
        Cue("far", "building", lexicon.DEFAULT_CUE_DISTANCE_M, hard=True),
        Cue("if_near", "grass", lexicon.DEFAULT_CUE_DISTANCE_M, "road"),
    )
    assert lexicon.DEFAULT_GRADED_DISTANCE_M > lexicon.DEFAULT_CUE_DISTANCE_M


@pytest.mark.parametrize(
    "obj, msg",
    [
        ([], "must be a JSON object"),
        ({"preferences": []}, 'no "entities"'),
        ({"entities": [{"name": 3}]}, "entities[0].name must be a string"),
        ({"entities": [{"name": "x"}] * 40}, "at most 32"),
        ({"entities": [], "preferences": [{"entity": "road"}]}, "neither weight nor rank"),
        ({"entities": [], "preferences": [{"entity": "road", "weight": float("nan")}]}, "finite"),
        ({"entities": [], "cues": "none"}, '"cues" must be a list'),
    ],
)
def test_parse_entity_reply_rejects(obj, msg):
    with pytest.raises(ReplyError, match=msg.replace("[", r"\[").replace("]", r"\]")):
        parse_entity_reply(obj)
