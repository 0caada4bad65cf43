"""Fixtures for the interpret tests: a real scripted chat completions server on 127.0.0.1."""

from __future__ import annotations

import pytest

from .chat_server import ChatServer, refused_url


@pytest.fixture
def chat_server():
    server = ChatServer().start()
    try:
        yield server
    finally:
        server.stop()


@pytest.fixture
def dead_url() -> str:
    return refused_url()


@pytest.fixture(autouse=True)
def _no_llm_env(monkeypatch):
    """Tests decide about the LLM themselves: no endpoint or key leaks in from the environment."""
    for var in (
        "OVERSEEC_LLM_URL",
        "OVERSEEC_LLM_MODEL",
        "OVERSEEC_LLM_API_KEY",
        "OVERSEEC_LLM_TIMEOUT",
        "OVERSEEC_LLM_RETRIES",
        "OVERSEEC_LLM_FALLBACK",
        "http_proxy",
        "HTTP_PROXY",
        "https_proxy",
        "HTTPS_PROXY",
        "all_proxy",
        "ALL_PROXY",
    ):
        monkeypatch.delenv(var, raising=False)
