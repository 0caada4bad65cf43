"""Hostile inputs for the LLM client (issue 13): secrets, redirects, deadlines, bad settings.

Real HTTP servers on 127.0.0.1 (``chat_server``): a server that echoes the Authorization header,
one that redirects to another origin (a second server: another port is another origin), one
that trickles its body or its headers. Every test can fail: each checks that the hostile thing
actually happened (the server saw the key, the echo was there) before checking it was contained.
"""

from __future__ import annotations

import base64
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from overseec_core.errors import InputError, LLMError
from overseec_core.interpret.llm import LLMConfig, redact, redact_url, resolve_config, split_userinfo
from overseec_core.interpret.llm_client import ChatClient, LLMHTTPError, origin
from overseec_core.progress import BaseProgress

from .chat_server import ChatServer

KEY = "sk-hostile-KEY-0123456789"
PASSWORD = "pa%40ss-SECRET-987"  # percent-encoded in the URL: the password is "pa@ss-SECRET-987"
PLAIN_PASSWORD = "pa@ss-SECRET-987"
MESSAGES = [{"role": "user", "content": "hello"}]
OVERSEEC = Path(sys.executable).with_name("overseec")


class Recorder(BaseProgress):
    def __init__(self):
        super().__init__()
        self.messages: list[str] = []

    def message(self, text: str) -> None:
        self.messages.append(text)


def with_userinfo(url: str, user: str = "alice", password: str = PASSWORD) -> str:
    return url.replace("http://", f"http://{user}:{password}@", 1)


def client(url: str, *, progress=None, **kw) -> ChatClient:
    cfg = LLMConfig(
        url,
        "test-model",
        api_key=kw.pop("api_key", KEY),
        timeout_s=kw.pop("timeout_s", 2.0),
        retries=kw.pop("retries", 0),
        backoff_s=0.0,
        **kw,
    )
    return ChatClient(cfg, progress=progress, sleep=lambda s: None)


def assert_clean(text: str) -> None:
    """None of the test secrets, in any spelling, is in ``text``."""
    basic = base64.b64encode(f"alice:{PLAIN_PASSWORD}".encode()).decode()
    for secret in (KEY, PASSWORD, PLAIN_PASSWORD, basic, "SECRET", "0123456789"):
        assert secret not in text, f"{secret!r} leaked into {text!r}"


@pytest.fixture
def other_server():
    server = ChatServer().start()
    try:
        yield server
    finally:
        server.stop()


# ----------------------------------------------------------------------------- pure helpers


def test_redact_url_and_split_userinfo():
    assert redact_url("http://alice:pw@host:8/v1") == "http://***@host:8/v1"
    assert redact_url("https://TOKEN@host/v1?x=a@b") == "https://***@host/v1?x=a@b"
    assert redact_url("alice:pw@host:8") == "***@host:8"  # not even a URL: still hidden
    assert redact_url("http://host/v1") == "http://host/v1"
    assert split_userinfo("http://alice:pa%40ss@h:1/v1") == ("http://h:1/v1", "alice", "pa@ss")
    assert split_userinfo("http://h/v1") == ("http://h/v1", None, None)


def test_redact_every_spelling_and_any_auth_value():
    key = 'k"ey\\with-odd-chars'
    for text in (f"echo {key}", "echo " + json.dumps(key), "echo k%22ey%5Cwith-odd-chars"):
        assert "with-odd-chars" not in redact(text, [key])
    assert (
        redact("Authorization: Bearer abcdefgh123 and Basic YWxpY2U6cHc=", [])
        == "Authorization: Bearer *** and Basic ***"
    )
    assert redact("see ftp://u:p@h/x", []) == "see ftp://***@h/x"


def test_origin_fills_default_ports():
    assert origin("http://H/v1") == origin("http://h:80/x") == ("http", "h", 80)
    assert origin("https://h/v1") != origin("http://h:443/v1")
    assert origin("http://127.0.0.1:1/v1") != origin("http://127.0.0.1:2/v1")


# ----------------------------------------------------------------------------- secrets


def test_401_echoing_the_key_never_shows_it(chat_server):
    chat_server.reply({"status": 401, "echo_auth": True}, {"status": 403, "echo_auth": True, "echo_raw": True})
    c = client(chat_server.url)
    for _ in range(2):
        with pytest.raises(LLMHTTPError) as exc:
            c.complete(MESSAGES)
        assert "invalid credentials" in str(exc.value) or "denied" in str(exc.value)
        assert "***" in str(exc.value)  # the echo was there, and scrubbed
        assert_clean(str(exc.value))
    assert all(r["headers"]["Authorization"] == f"Bearer {KEY}" for r in chat_server.requests)


def test_retry_messages_and_final_error_are_redacted(chat_server):
    chat_server.reply(*[{"status": 500, "echo_auth": True}] * 2)
    progress = Recorder()
    with pytest.raises(LLMError) as exc:
        client(chat_server.url, retries=1, progress=progress).complete(MESSAGES)
    assert progress.messages and "HTTP 500" in progress.messages[0]
    assert_clean(str(exc.value) + " ".join(progress.messages))


def test_reply_content_echoing_the_key_is_redacted(chat_server):
    chat_server.reply(f"your key is {KEY}")
    assert client(chat_server.url).complete(MESSAGES) == "your key is ***"


def test_url_credentials_authenticate_as_basic_and_are_never_shown(chat_server):
    url = with_userinfo(chat_server.url)
    chat_server.reply("ok", {"status": 401, "echo_auth": True}, {"raw": b"<html>"})
    c = client(url, api_key=None)
    assert c.complete(MESSAGES) == "ok"
    basic = base64.b64encode(f"alice:{PLAIN_PASSWORD}".encode()).decode()
    assert chat_server.requests[0]["headers"]["Authorization"] == f"Basic {basic}"
    assert chat_server.requests[0]["path"] == "/v1/chat/completions"
    for _ in range(2):
        with pytest.raises(LLMError) as exc:
            c.complete(MESSAGES)
        assert f"http://***@127.0.0.1:{chat_server.port}/v1" in str(exc.value)
        assert_clean(str(exc.value))
    cfg = c.config
    assert cfg.describe()["url"] == f"http://***@127.0.0.1:{chat_server.port}/v1"
    assert cfg.describe()["url_credentials"] is True
    assert_clean(json.dumps(cfg.describe()) + repr(cfg) + str(cfg))


def test_url_credentials_and_an_api_key_together_are_refused():
    with pytest.raises(InputError, match="give one") as exc:
        LLMConfig("http://alice:pw-SECRET@h/v1", "m", api_key=KEY)
    assert_clean(str(exc.value))


def test_invalid_url_with_credentials_is_not_echoed():
    with pytest.raises(InputError) as exc:
        LLMConfig("ftp://alice:pw-SECRET@h/v1", "m")
    assert "ftp://***@h/v1" in str(exc.value)
    assert_clean(str(exc.value))


def test_notes_never_carry_the_url_password(chat_server):
    from overseec_core.interpret import interpret

    chat_server.reply(*[{"status": 500, "echo_auth": True}] * 4)
    cfg = LLMConfig(with_userinfo(chat_server.url), "test-model", timeout_s=2.0, retries=0, fallback_offline=True)
    it = interpret("prefer the road", llm=cfg)
    assert any("interpreted offline" in n for n in it.notes)
    assert_clean(json.dumps(it.to_json()))


# ----------------------------------------------------------------------------- redirects


def test_cross_origin_redirect_is_not_followed(chat_server, other_server):
    target = other_server.url + "/chat/completions"
    chat_server.reply(
        {"redirect": target, "status": 302}, {"redirect": with_userinfo(target, "eve", "evil-SECRET"), "status": 307}
    )
    c = client(chat_server.url)
    messages = []
    for _ in range(2):
        with pytest.raises(LLMError) as exc:
            c.complete(MESSAGES)
        messages.append(str(exc.value))
    assert other_server.requests == []  # no Authorization (nor anything) went there
    assert len(chat_server.requests) == 2  # and it is not retried
    for msg in messages:
        assert f"127.0.0.1:{other_server.port}/" in msg and "not followed" in msg
        assert "\n" not in msg
        assert_clean(msg)
    assert f"http://***@127.0.0.1:{other_server.port}/" in messages[1]  # its userinfo hidden


def test_same_origin_redirect_keeps_the_post_and_the_key(chat_server):
    chat_server.reply({"redirect": f"{chat_server.url}/v2/chat/completions", "status": 308}, "moved ok")
    assert client(chat_server.url).complete(MESSAGES) == "moved ok"
    first, second = chat_server.requests
    assert second["path"] == "/v1/v2/chat/completions"
    assert second["headers"]["Authorization"] == f"Bearer {KEY}"
    assert second["body"] == first["body"]


# ----------------------------------------------------------------------------- one deadline


@pytest.mark.parametrize(
    "action", [{"trickle": 0.05, "for": 8.0}, {"slow_headers": 0.05, "for": 8.0}], ids=["trickled-body", "slow-headers"]
)
def test_a_trickling_server_fails_at_the_deadline(chat_server, action):
    chat_server.reply(action)
    t0 = time.monotonic()
    with pytest.raises(LLMError, match=r"timed out \(no complete answer within 0.6 s\)") as exc:
        client(chat_server.url, timeout_s=0.6).complete(MESSAGES)
    elapsed = time.monotonic() - t0
    assert 0.5 < elapsed < 0.6 + 1.5
    assert "\n" not in str(exc.value) and "1 try" in str(exc.value)


def test_each_retry_has_its_own_deadline(chat_server):
    chat_server.reply({"trickle": 0.05, "for": 8.0}, "second try")
    progress = Recorder()
    t0 = time.monotonic()
    assert client(chat_server.url, timeout_s=0.5, retries=1, progress=progress).complete(MESSAGES) == "second try"
    assert time.monotonic() - t0 < 0.5 + 1.5
    assert any("timed out" in m and "retrying" in m for m in progress.messages)


# ----------------------------------------------------------------------------- settings


@pytest.mark.parametrize("raw", ["inf", "1e300", "nan", "-1", "0", "3601", "soon"])
def test_bad_timeouts_are_input_errors(raw):
    env = {"OVERSEEC_LLM_URL": "http://h/v1", "OVERSEEC_LLM_MODEL": "m", "OVERSEEC_LLM_TIMEOUT": raw}
    with pytest.raises(InputError, match=r"OVERSEEC_LLM_TIMEOUT.*3600") as exc:
        resolve_config(env=env)
    assert "\n" not in str(exc.value)


@pytest.mark.parametrize("value", [float("inf"), float("nan"), 0, -1.0, 1e300, True, "5"])
def test_bad_timeout_values_in_code_are_input_errors(value):
    with pytest.raises(InputError, match="3600"):
        LLMConfig("http://h/v1", "m", timeout_s=value)


@pytest.mark.parametrize("raw", ["1.5", "-1", "11", "1e9", "many"])
def test_bad_retries_are_input_errors(raw):
    env = {"OVERSEEC_LLM_URL": "http://h/v1", "OVERSEEC_LLM_MODEL": "m", "OVERSEEC_LLM_RETRIES": raw}
    with pytest.raises(InputError, match=r"OVERSEEC_LLM_RETRIES.*0 to 10"):
        resolve_config(env=env)


def test_good_limits_are_accepted():
    env = {
        "OVERSEEC_LLM_URL": "http://h/v1",
        "OVERSEEC_LLM_MODEL": "m",
        "OVERSEEC_LLM_TIMEOUT": "3600",
        "OVERSEEC_LLM_RETRIES": "10",
    }
    cfg = resolve_config(env=env)
    assert (cfg.timeout_s, cfg.retries) == (3600.0, 10)


# ----------------------------------------------------------------------------- the command line


def _cli(args: list[str], env: dict[str, str], cwd: Path) -> subprocess.CompletedProcess:
    clean = {
        k: v
        for k, v in os.environ.items()
        if not k.startswith("OVERSEEC_LLM") and k.lower() not in ("http_proxy", "https_proxy", "all_proxy")
    }
    return subprocess.run(
        [str(OVERSEEC), *args], env={**clean, **env}, cwd=cwd, capture_output=True, text=True, timeout=30
    )


@pytest.mark.parametrize(
    "args, env",
    [
        ([], {"OVERSEEC_LLM_TIMEOUT": "1e300"}),
        (["--llm-timeout", "inf"], {}),
    ],
    ids=["env-1e300", "arg-inf"],
)
def test_cli_bad_timeout_is_one_line_exit_2(tmp_path, args, env):
    proc = _cli(
        ["interpret", "prefer the road", "--llm-url", "http://127.0.0.1:9/v1", "--llm-model", "m", *args], env, tmp_path
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "3600" in lines[0] and "Traceback" not in proc.stderr


def test_cli_never_prints_or_records_secrets(tmp_path, chat_server):
    """A 500 and a 401 that echo the key, with progress messages on: stderr, stdout and the run
    directory's manifest stay clean."""
    chat_server.reply(
        {"status": 500, "echo_auth": True, "headers": {"Retry-After": "0"}},
        {"status": 401, "echo_auth": True},
        {"status": 401, "echo_auth": True},
    )
    run_dir = tmp_path / "run"
    proc = _cli(
        [
            "interpret",
            "prefer the road",
            "--llm-url",
            chat_server.url,
            "--llm-model",
            "m",
            "--llm-retries",
            "1",
            "--run-dir",
            str(run_dir),
        ],
        {"OVERSEEC_LLM_API_KEY": KEY, "OVERSEEC_LLM_TIMEOUT": "5"},
        tmp_path,
    )
    assert proc.returncode == 2, proc.stderr
    assert chat_server.requests[0]["headers"]["Authorization"] == f"Bearer {KEY}"
    assert "HTTP 401" in proc.stderr and "***" in proc.stderr
    manifest = (run_dir / "manifest.json").read_text()
    assert "HTTP 401" in manifest
    assert_clean(proc.stderr + proc.stdout + manifest)


def test_cli_url_password_is_never_shown(tmp_path, chat_server):
    chat_server.reply({"status": 401, "echo_auth": True})
    run_dir = tmp_path / "run"
    proc = _cli(
        [
            "interpret",
            "prefer the road",
            "--llm-url",
            with_userinfo(chat_server.url),
            "--llm-model",
            "m",
            "--run-dir",
            str(run_dir),
        ],
        {},
        tmp_path,
    )
    assert proc.returncode == 2, proc.stderr
    assert chat_server.requests[0]["headers"]["Authorization"].startswith("Basic ")
    assert f"http://***@127.0.0.1:{chat_server.port}" in proc.stderr
    manifest = json.loads((run_dir / "manifest.json").read_text())
    assert manifest["parameters"]["interpret"]["llm"]["url"].startswith("http://***@")
    assert_clean(proc.stderr + proc.stdout + json.dumps(manifest))


def test_a_token_as_url_user_name_is_a_secret_too(chat_server):
    chat_server.reply({"status": 401, "echo_auth": True, "echo_raw": True})
    c = client(chat_server.url.replace("http://", "http://tok-SECRET-123@"), api_key=None)
    with pytest.raises(LLMHTTPError) as exc:
        c.complete(MESSAGES)
    expected = base64.b64encode(b"tok-SECRET-123:").decode()
    assert chat_server.requests[0]["headers"]["Authorization"] == f"Basic {expected}"
    assert_clean(str(exc.value) + json.dumps(c.config.describe()))


def test_doctor_shows_no_url_credentials(chat_server):
    from overseec_core.commands.doctor import _llm

    report = _llm(with_userinfo(chat_server.url))
    assert report["reachable"] is True and report["url"].startswith("http://***@127.0.0.1:")
    assert [r["path"] for r in chat_server.requests] == ["/v1/models"]
    assert_clean(json.dumps(report) + json.dumps(chat_server.requests[0]["headers"]))
