"""The chat completions client against a real HTTP server on 127.0.0.1 (scripted replies)."""

from __future__ import annotations

import pytest

from overseec_core.errors import InputError, LLMError
from overseec_core.interpret.llm import LLMConfig, resolve_config
from overseec_core.interpret.llm_client import ChatClient, LLMHTTPError
from overseec_core.progress import BaseProgress

KEY = "sk-test-SECRET-123"
MESSAGES = [{"role": "user", "content": "hello"}]


class Recorder(BaseProgress):
    def __init__(self):
        super().__init__()
        self.messages: list[str] = []

    def message(self, text: str) -> None:
        self.messages.append(text)


def client_for(url: str, *, sleeps: list | None = None, progress=None, **kw) -> ChatClient:
    cfg = LLMConfig(
        url,
        kw.pop("model", "test-model"),
        api_key=kw.pop("api_key", KEY),
        timeout_s=kw.pop("timeout_s", 2.0),
        retries=kw.pop("retries", 2),
        backoff_s=kw.pop("backoff_s", 0.01),
        **kw,
    )
    sleeps = sleeps if sleeps is not None else []
    return ChatClient(cfg, progress=progress, sleep=sleeps.append)


def test_good_reply_and_what_was_sent(chat_server):
    chat_server.reply("the answer")
    fmt = {"type": "json_schema", "json_schema": {"name": "x", "schema": {"type": "object"}}}
    assert client_for(chat_server.url).complete(MESSAGES, response_format=fmt) == "the answer"
    [req] = chat_server.requests
    assert req["path"] == "/v1/chat/completions"
    assert req["headers"]["Authorization"] == f"Bearer {KEY}"
    assert req["headers"]["Content-Type"] == "application/json"
    assert req["body"]["model"] == "test-model"
    assert req["body"]["messages"] == MESSAGES
    assert req["body"]["response_format"] == fmt
    assert req["body"]["temperature"] == 0.0


def test_no_key_no_authorization_header(chat_server):
    chat_server.reply("ok")
    assert client_for(chat_server.url + "/", api_key=None).complete(MESSAGES) == "ok"
    assert "Authorization" not in chat_server.requests[0]["headers"]
    assert chat_server.requests[0]["path"] == "/v1/chat/completions"  # trailing slash tolerated


def test_http_500_then_success_retries_with_backoff(chat_server):
    chat_server.reply({"status": 500, "body": "overloaded"}, {"status": 503, "body": "busy"}, "ok")
    sleeps: list[float] = []
    progress = Recorder()
    assert client_for(chat_server.url, sleeps=sleeps, progress=progress).complete(MESSAGES) == "ok"
    assert len(chat_server.requests) == 3
    assert sleeps == [0.01, 0.02]  # exponential
    assert any("HTTP 500" in m and "retrying" in m for m in progress.messages)


def test_http_500_forever_is_an_llm_error_after_bounded_retries(chat_server):
    chat_server.reply(*[{"status": 500, "body": "boom"}] * 5)
    with pytest.raises(LLMError) as exc:
        client_for(chat_server.url, retries=2).complete(MESSAGES)
    assert len(chat_server.requests) == 3
    msg = str(exc.value)
    assert "HTTP 500" in msg and "3 tries" in msg and "boom" in msg
    assert KEY not in msg and "\n" not in msg


def test_backoff_is_capped(chat_server):
    chat_server.reply(*[{"status": 502, "body": "x"}] * 4, "ok")
    sleeps: list[float] = []
    client_for(chat_server.url, sleeps=sleeps, retries=4, backoff_s=1.0, backoff_max_s=2.5).complete(MESSAGES)
    assert sleeps == [1.0, 2.0, 2.5, 2.5]


def test_retry_after_header_is_honoured(chat_server):
    chat_server.reply({"status": 429, "body": "slow down", "headers": {"Retry-After": "0.05"}}, "ok")
    sleeps: list[float] = []
    assert client_for(chat_server.url, sleeps=sleeps, backoff_s=1.0).complete(MESSAGES) == "ok"
    assert sleeps == [0.05]


def test_timeout_then_success(chat_server):
    chat_server.reply({"sleep": 1.0, "content": "too late"}, "in time")
    assert client_for(chat_server.url, timeout_s=0.3).complete(MESSAGES) == "in time"
    assert len(chat_server.requests) == 2


def test_timeouts_exhaust_retries(chat_server):
    chat_server.reply(*[{"sleep": 1.0, "content": "late"}] * 2)
    with pytest.raises(LLMError, match=r"timed out \(no complete answer within 0.3 s\)"):
        client_for(chat_server.url, timeout_s=0.3, retries=1).complete(MESSAGES)
    assert len(chat_server.requests) == 2


def test_connection_refused(dead_url):
    sleeps: list[float] = []
    with pytest.raises(LLMError, match=r"cannot connect") as exc:
        client_for(dead_url, sleeps=sleeps, retries=2).complete(MESSAGES)
    assert len(sleeps) == 2  # retried, bounded
    assert KEY not in str(exc.value)


def test_http_400_for_response_format_retries_without_it(chat_server):
    chat_server.reply({"status": 400, "body": "response_format json_schema is not supported"}, "plain", "again")
    client = client_for(chat_server.url)
    fmt = {"type": "json_schema", "json_schema": {"name": "x", "schema": {}}}
    assert client.complete(MESSAGES, response_format=fmt) == "plain"
    assert "response_format" in chat_server.requests[0]["body"]
    assert "response_format" not in chat_server.requests[1]["body"]
    assert client.structured_ok is False
    assert client.complete(MESSAGES, response_format=fmt) == "again"  # not sent again
    assert "response_format" not in chat_server.requests[2]["body"]


def test_http_400_without_response_format_is_an_error(chat_server):
    chat_server.reply({"status": 400, "body": "bad request"})
    with pytest.raises(LLMHTTPError) as exc:
        client_for(chat_server.url).complete(MESSAGES)
    assert exc.value.status == 400 and len(chat_server.requests) == 1


@pytest.mark.parametrize("status, hint", [(401, "check the API key"), (404, "check the LLM URL")])
def test_client_errors_are_not_retried_and_say_what_to_check(chat_server, status, hint):
    chat_server.reply({"status": status, "body": "nope"}, "never reached")
    with pytest.raises(LLMHTTPError) as exc:
        client_for(chat_server.url).complete(MESSAGES)
    assert len(chat_server.requests) == 1
    assert f"HTTP {status}" in str(exc.value) and hint in str(exc.value)
    assert KEY not in str(exc.value)


def test_not_json_and_no_choices_are_clear_errors(chat_server):
    chat_server.reply({"raw": b"<html>hello</html>"}, {"raw": b'{"object": "list"}'})
    client = client_for(chat_server.url)
    with pytest.raises(LLMError, match="did not answer with JSON"):
        client.complete(MESSAGES)
    with pytest.raises(LLMError, match=r"no choices\[0\]\.message"):
        client.complete(MESSAGES)


def test_content_parts_are_joined(chat_server):
    import json

    body = {
        "choices": [
            {
                "message": {
                    "role": "assistant",
                    "content": [{"type": "text", "text": "a"}, {"type": "text", "text": "b"}],
                }
            }
        ]
    }
    chat_server.reply({"raw": json.dumps(body).encode()})
    assert client_for(chat_server.url).complete(MESSAGES) == "ab"


def test_key_never_in_repr_or_description():
    cfg = LLMConfig("http://localhost:11434/v1", "m", api_key=KEY)
    assert KEY not in repr(cfg)
    assert KEY not in str(cfg.describe()) and cfg.describe()["api_key"] is True


@pytest.mark.parametrize("url", ["localhost:11434", "ftp://x/v1", "http://"])
def test_bad_urls_are_input_errors(url):
    with pytest.raises(InputError, match="not an http"):
        LLMConfig(url, "m")


def test_resolve_config_from_environment():
    env = {
        "OVERSEEC_LLM_URL": "http://h:1/v1",
        "OVERSEEC_LLM_MODEL": "llama3",
        "OVERSEEC_LLM_API_KEY": KEY,
        "OVERSEEC_LLM_TIMEOUT": "7.5",
        "OVERSEEC_LLM_RETRIES": "1",
        "OVERSEEC_LLM_FALLBACK": "offline",
    }
    cfg = resolve_config(env=env)
    assert (cfg.base_url, cfg.model, cfg.api_key, cfg.timeout_s, cfg.retries, cfg.fallback_offline) == (
        "http://h:1/v1",
        "llama3",
        KEY,
        7.5,
        1,
        True,
    )
    # explicit values win; the key comes from the variable --llm-key-env names
    cfg = resolve_config(url="http://x:2/v1", model="m2", key_env="MY_KEY", env={**env, "MY_KEY": "k2"})
    assert (cfg.base_url, cfg.model, cfg.api_key) == ("http://x:2/v1", "m2", "k2")
    assert resolve_config(env={}) is None


def test_resolve_config_errors():
    with pytest.raises(InputError, match="no model"):
        resolve_config(url="http://h/v1", env={})
    with pytest.raises(InputError, match="MY_KEY"):
        resolve_config(url="http://h/v1", model="m", key_env="MY_KEY", env={})
    with pytest.raises(InputError, match="no LLM URL"):
        resolve_config(model="m", env={})
    with pytest.raises(InputError, match="not a number"):
        resolve_config(
            env={"OVERSEEC_LLM_URL": "http://h/v1", "OVERSEEC_LLM_MODEL": "m", "OVERSEEC_LLM_TIMEOUT": "soon"}
        )
