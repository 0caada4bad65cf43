"""The dock and Processing interpret through an LLM, the key coming from QGIS's auth database.

The endpoint is the interpret tests' real scripted chat server on 127.0.0.1; what it received
shows the key travelled as an Authorization header (and nowhere in the settings).
"""

from __future__ import annotations

import json

import pytest
from qgis.core import QgsApplication, QgsSettings

from overseec_qgis.settings import store_api_key
from tests.interpret.chat_server import ChatServer

from .conftest import wait_until

pytestmark = pytest.mark.qgis

KEY = "sk-qgis-llm-7f3a"
PROMPT = "Prefer the roads, grass is fine, avoid the baseball field"
ENTITIES = {
    "entities": [
        {"name": "road", "geometry": "linear", "prompts": ["road", "paved road"]},
        {"name": "grass", "geometry": "areal", "prompts": ["grass"]},
        {"name": "baseball field", "geometry": "areal", "prompts": ["baseball field"]},
    ],
    "preferences": [
        {"entity": "road", "rank": 1, "weight": 0.1, "lethal": False},
        {"entity": "grass", "rank": 2, "weight": 0.4, "lethal": False},
        {"entity": "baseball field", "rank": 3, "weight": 0.95, "lethal": False},
    ],
    "hierarchy": [{"child": "baseball field", "parent": "grass"}],
    "cues": [],
    "unparsed": [],
}
#: The LLM's program: it must also price the hazards the prompt leaves unsaid at their built-in
#: priors (trees 0.85; buildings and water obstacles, kept out), or the core asks it again.
PROGRAM = (
    'g = REMOVE(M["grass"], M["baseball field"])\n'
    'acc = sum(-0.5 * P["road"], -0.25 * P["grass"] * g, 0.5 * P["baseball field"], '
    '0.35 * P["tree"], 0.5 * P["building"], 0.5 * P["water"])\n'
    "cost = clip(0.5 + acc, 0.0, 1.0)\n"
    'keep_out = OR(M["building"], M["water"])\n'
)


@pytest.fixture
def server(monkeypatch):
    for var in (
        "OVERSEEC_LLM_URL",
        "OVERSEEC_LLM_MODEL",
        "OVERSEEC_LLM_API_KEY",
        "http_proxy",
        "HTTP_PROXY",
        "all_proxy",
        "ALL_PROXY",
    ):
        monkeypatch.delenv(var, raising=False)
    s = ChatServer().start()
    s.reply(json.dumps(ENTITIES), f"```python\n{PROGRAM}```")
    yield s
    s.stop()


@pytest.fixture
def authcfg():
    manager = QgsApplication.authManager()
    if manager.isDisabled():
        pytest.skip("QGIS authentication system disabled here")
    if not manager.masterPasswordIsSet():
        assert manager.setMasterPassword("overseec-test-master", True)
    cfg = store_api_key(KEY)
    yield cfg
    manager.removeAuthenticationConfig(cfg)


def test_dock_interprets_with_the_llm_and_the_stored_key(plugin, server, authcfg) -> None:
    dock = plugin.dock
    dock.mission.prompt_edit.setPlainText(PROMPT)
    dock.mission.offline_check.setChecked(False)
    page = plugin.options_factory.createWidget(None)  # the LLM is set on Settings › Options › overseec
    page.endpoint_edit.setText(server.url)
    page.model_edit.setText("test-model")
    page.auth_select.setConfigId(authcfg)
    page.apply()
    done = []
    dock.task_done.connect(lambda stage, ok: done.append((stage, ok)))
    dock.mission.interpret_button.click()
    wait_until(lambda: done, 60, "the LLM interpretation")
    assert done == [("interpret", True)], dock.runs.status_label.text()
    assert dock.mission.interpretation.source == "llm:test-model"
    rows = {r["name"]: r for r in dock.mission.entity_rows()}
    assert rows["road"]["prompts"] == ["road", "paved road"] and rows["road"]["geometry"] == "linear"
    assert dock.mission.program_edit.toPlainText() == PROGRAM
    assert all(r["headers"]["Authorization"] == f"Bearer {KEY}" for r in server.requests)
    assert PROMPT in server.requests[0]["body"]["messages"][-1]["content"]
    assert KEY not in str([QgsSettings().value(k) for k in QgsSettings().allKeys()])


def test_processing_interpret_with_an_auth_config(qgis_processing, server, authcfg, tmp_path) -> None:
    import processing

    from overseec_qgis import classFactory

    plugin = classFactory(None)
    plugin.initProcessing()
    try:
        res = processing.run(
            "overseec:interpret",
            {
                "PROMPT": PROMPT,
                "LLM_URL": server.url,
                "LLM_MODEL": "test-model",
                "LLM_AUTHCFG": authcfg,
                "OUTPUT": str(tmp_path / "i.json"),
            },
        )
    finally:
        plugin.unload()
    doc = json.loads((tmp_path / "i.json").read_text())
    assert doc["source"] == "llm:test-model" and doc["program"] == PROGRAM
    assert res["PROGRAM"] == PROGRAM
    assert server.requests[0]["headers"]["Authorization"] == f"Bearer {KEY}"


def test_the_llm_endpoint_model_and_key_reach_the_worker_by_environment_only(tmp_path) -> None:
    from overseec_qgis import jobs, params

    llm = params.LlmSettings(endpoint="http://user:s3cret@127.0.0.1:9/v1", model="test-model", api_key=KEY)
    worker = tmp_path / "bin" / "overseec"
    plugin_params = params.Params()
    commands = {
        "interpret": jobs.interpret_command(worker, PROMPT, llm),
        "run": jobs.run_command(worker, "in.tif", tmp_path / "run", PROMPT, plugin_params, llm=llm),
    }
    for name, (argv, env) in commands.items():
        assert not any("s3cret" in a or KEY in a or "127.0.0.1:9" in a for a in argv), (name, argv)
        assert env[jobs.LLM_URL_ENV] == llm.endpoint and env[jobs.LLM_MODEL_ENV] == "test-model", name
        assert env[jobs.API_KEY_ENV] == KEY, name
    argv, _env = jobs.interpret_command(worker, "-avoid water", params.LlmSettings())
    assert argv[-3:] == ["--offline", "--", "-avoid water"]  # a prompt that starts with a dash stays the prompt


def test_a_worker_document_is_read_back_or_refused_in_one_line() -> None:
    from overseec_qgis import jobs

    lines = ["costmap: 50%", "{", '  "costmap": "/r/costmap.tif",', '  "lethal": "/r/l.tif"', "}"]
    assert jobs.result_document(lines) == {"costmap": "/r/costmap.tif", "lethal": "/r/l.tif"}
    assert jobs.result_document(["no document"]) == {}
    assert jobs.result_document(["{", "  truncated"]) == {}
    with pytest.raises(jobs.InputError, match="missing 'program_file'"):
        jobs.CostmapSummary.from_json(jobs.result_document(lines))
