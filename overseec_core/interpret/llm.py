"""A small client for the OpenAI-compatible chat completions API (standard library only).

``POST {base_url}/chat/completions`` is what Ollama (``http://localhost:11434/v1``), vLLM,
llama.cpp's server and hosted APIs all speak. Written on ``urllib.request`` rather than an SDK:
the call is one JSON POST, the official SDKs pull in a dozen packages (httpx, pydantic, ...) that
QGIS's own Python does not have, and the plugin runs the interpret stage in-process.

Behaviour:

- configuration from arguments, else the environment: ``OVERSEEC_LLM_URL``,
  ``OVERSEEC_LLM_MODEL``, ``OVERSEEC_LLM_API_KEY`` (sent as ``Authorization: Bearer``; never
  logged, never in an error message or ``repr``), ``OVERSEEC_LLM_TIMEOUT`` (seconds),
  ``OVERSEEC_LLM_RETRIES``, ``OVERSEEC_LLM_FALLBACK=offline``;
- a timeout per request; timeouts, connection errors, HTTP 429 and 5xx are retried a bounded
  number of times with exponential backoff (``backoff_s * 2**k``, at most ``backoff_max_s``,
  or the server's ``Retry-After`` when shorter than that);
- ``response_format`` (JSON-schema structured output) is sent when asked; a server that rejects
  it with HTTP 400 is asked again without it, and is not sent it again by this client;
- any other failure is an :class:`~overseec_core.errors.LLMError` with one line that says what
  to check.
"""

from __future__ import annotations

import http.client
import json
import os
import socket
import time
import urllib.error
import urllib.parse
import urllib.request
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence

from ..errors import InputError, LLMError
from ..progress import Progress, check_cancelled

ENV_URL = "OVERSEEC_LLM_URL"
ENV_MODEL = "OVERSEEC_LLM_MODEL"
ENV_KEY = "OVERSEEC_LLM_API_KEY"
ENV_TIMEOUT = "OVERSEEC_LLM_TIMEOUT"
ENV_RETRIES = "OVERSEEC_LLM_RETRIES"
ENV_FALLBACK = "OVERSEEC_LLM_FALLBACK"

#: Largest reply body read (bytes); a chat reply is a few kilobytes.
MAX_REPLY_BYTES = 8 << 20


@dataclass(frozen=True)
class LLMConfig:
    """Where and how to reach the LLM. ``api_key`` is kept out of ``repr`` and messages."""

    base_url: str
    model: str
    api_key: str | None = field(default=None, repr=False)
    #: Seconds per HTTP request (connect + reply).
    timeout_s: float = 120.0
    #: Extra tries after a timeout, connection error, HTTP 429 or 5xx.
    retries: int = 3
    backoff_s: float = 1.0
    backoff_max_s: float = 20.0
    #: Replies asked for per call when the reply is unusable (bad JSON, invalid program).
    attempts: int = 3
    temperature: float = 0.0
    #: Ask for JSON-schema structured output in the entity call.
    structured: bool = True
    #: On an unreachable or failing LLM, interpret offline (with a note) instead of failing.
    fallback_offline: bool = False

    def __post_init__(self) -> None:
        url = urllib.parse.urlsplit(self.base_url)
        if url.scheme not in ("http", "https") or not url.netloc:
            raise InputError(f"LLM URL {self.base_url!r} is not an http(s) URL "
                             "(e.g. http://localhost:11434/v1)")
        if not self.model.strip():
            raise InputError("no LLM model name given (--llm-model or OVERSEEC_LLM_MODEL)")
        if not self.timeout_s > 0:
            raise InputError(f"LLM timeout must be positive, got {self.timeout_s}")
        if self.retries < 0 or self.attempts < 1:
            raise InputError("LLM retries must be >= 0 and attempts >= 1")

    @property
    def endpoint(self) -> str:
        return self.base_url.rstrip("/") + "/chat/completions"

    def describe(self) -> dict[str, Any]:
        """What the manifest records (no key: only whether one was sent)."""
        return {"url": self.base_url, "model": self.model, "api_key": bool(self.api_key),
                "timeout_s": self.timeout_s, "retries": self.retries, "attempts": self.attempts,
                "temperature": self.temperature, "structured": self.structured,
                "fallback_offline": self.fallback_offline}


def _env_float(env: Mapping[str, str], name: str) -> float | None:
    raw = env.get(name, "").strip()
    if not raw:
        return None
    try:
        return float(raw)
    except ValueError:
        raise InputError(f"{name}={raw!r} is not a number") from None


def resolve_config(*, url: str | None = None, model: str | None = None,
                   key_env: str | None = None, api_key: str | None = None,
                   timeout_s: float | None = None, retries: int | None = None,
                   fallback_offline: bool | None = None,
                   env: Mapping[str, str] | None = None) -> LLMConfig | None:
    """An LLMConfig from explicit values, else the environment; None when no URL is set anywhere.

    ``key_env`` names the environment variable that holds the API key (default
    ``OVERSEEC_LLM_API_KEY``); keys are never taken from the command line itself.
    """
    env = os.environ if env is None else env
    url = url or env.get(ENV_URL, "").strip() or None
    if url is None:
        if model or key_env:
            raise InputError("an LLM model or key was given but no LLM URL "
                             f"(--llm-url or {ENV_URL})")
        return None
    model = model or env.get(ENV_MODEL, "").strip()
    if not model:
        raise InputError(f"LLM URL given but no model name (--llm-model or {ENV_MODEL})")
    if api_key is None:
        if key_env:
            if key_env not in env:
                raise InputError(f"environment variable {key_env} (named by --llm-key-env) is not set")
            api_key = env[key_env]
        else:
            api_key = env.get(ENV_KEY) or None
    if timeout_s is None:
        timeout_s = _env_float(env, ENV_TIMEOUT)
    if retries is None:
        r = _env_float(env, ENV_RETRIES)
        retries = int(r) if r is not None else None
    if fallback_offline is None:
        fallback_offline = env.get(ENV_FALLBACK, "").strip().lower() in ("offline", "1", "true", "yes")
    kwargs: dict[str, Any] = {"api_key": api_key or None, "fallback_offline": fallback_offline}
    if timeout_s is not None:
        kwargs["timeout_s"] = timeout_s
    if retries is not None:
        kwargs["retries"] = retries
    return LLMConfig(url, model, **kwargs)


class LLMHTTPError(LLMError):
    """The endpoint answered with an HTTP error status."""

    def __init__(self, message: str, status: int):
        super().__init__(message)
        self.status = status


class _Retryable(Exception):
    """Internal: a failure worth another try (timeout, connection, 429, 5xx)."""

    def __init__(self, why: str, retry_after: float | None = None):
        super().__init__(why)
        self.why = why
        self.retry_after = retry_after


_HINTS = {401: "check the API key", 403: "check the API key and its permissions",
          404: "check the LLM URL (most servers want it to end in /v1) and the model name"}


def _snippet(raw: bytes, limit: int = 200) -> str:
    text = raw.decode("utf-8", "replace")
    try:  # OpenAI-style {"error": {"message": ...}}
        err = json.loads(text).get("error")
        text = err.get("message", text) if isinstance(err, dict) else str(err or text)
    except (ValueError, AttributeError):
        pass
    text = " ".join(text.split())
    return text[:limit] + ("..." if len(text) > limit else "")


def _retry_after(headers) -> float | None:
    raw = headers.get("Retry-After") if headers is not None else None
    try:
        return max(0.0, float(raw)) if raw is not None else None
    except ValueError:
        return None


class ChatClient:
    """Chat completions over HTTP with timeouts and bounded retries."""

    def __init__(self, config: LLMConfig, *, progress: Progress | None = None,
                 sleep: Callable[[float], None] = time.sleep):
        self.config = config
        self.progress = progress
        self.sleep = sleep
        #: False once the server rejected ``response_format``.
        self.structured_ok = config.structured
        #: Requests sent (for the notes/manifest).
        self.requests = 0

    def complete(self, messages: Sequence[Mapping[str, str]],
                 response_format: Mapping[str, Any] | None = None) -> str:
        """The assistant's reply text for ``messages``."""
        body: dict[str, Any] = {"model": self.config.model, "messages": list(messages),
                                "temperature": self.config.temperature, "stream": False}
        if response_format is not None and self.structured_ok:
            try:
                return self._content(self._post({**body, "response_format": response_format}))
            except LLMHTTPError as exc:
                if exc.status != 400:
                    raise
                self.structured_ok = False
                self._say("LLM rejected structured output (HTTP 400); asking without it")
        return self._content(self._post(body))

    # -- transport
    def _say(self, text: str) -> None:
        if self.progress is not None:
            self.progress.message(text)

    def _post(self, body: Mapping[str, Any]) -> dict:
        cfg = self.config
        tries = cfg.retries + 1
        for attempt in range(tries):
            if self.progress is not None:
                check_cancelled(self.progress)
            try:
                return self._post_once(body)
            except _Retryable as exc:
                if attempt + 1 >= tries:
                    raise LLMError(f"LLM at {cfg.endpoint} failed after {tries} tries: {exc.why}") from None
                delay = min(cfg.backoff_max_s, cfg.backoff_s * 2 ** attempt)
                if exc.retry_after is not None:  # the server knows best, within our bound
                    delay = min(exc.retry_after, cfg.backoff_max_s)
                self._say(f"LLM: {exc.why}; retrying in {delay:.1f} s ({attempt + 2}/{tries})")
                self.sleep(delay)
        raise AssertionError("unreachable")  # pragma: no cover

    def _post_once(self, body: Mapping[str, Any]) -> dict:
        cfg = self.config
        headers = {"Content-Type": "application/json", "Accept": "application/json",
                   "User-Agent": "overseec"}
        if cfg.api_key:
            headers["Authorization"] = f"Bearer {cfg.api_key}"
        req = urllib.request.Request(cfg.endpoint, data=json.dumps(body).encode("utf-8"),
                                     headers=headers, method="POST")
        self.requests += 1
        try:
            with urllib.request.urlopen(req, timeout=cfg.timeout_s) as resp:
                raw = resp.read(MAX_REPLY_BYTES + 1)
        except urllib.error.HTTPError as exc:
            status, detail = exc.code, _snippet(exc.read(4096) if exc.fp else b"")
            exc.close()
            if status == 429 or status >= 500:
                raise _Retryable(f"HTTP {status} ({detail or exc.reason})", _retry_after(exc.headers))
            hint = _HINTS.get(status, "")
            raise LLMHTTPError(f"LLM at {cfg.endpoint} answered HTTP {status}"
                               f"{': ' + detail if detail else ''}{' -- ' + hint if hint else ''}",
                               status) from None
        except urllib.error.URLError as exc:
            reason = exc.reason
            if isinstance(reason, (TimeoutError, socket.timeout)):
                raise _Retryable(f"no answer within {cfg.timeout_s:g} s") from None
            raise _Retryable(f"cannot connect ({getattr(reason, 'strerror', None) or reason})") from None
        except (TimeoutError, socket.timeout):
            raise _Retryable(f"no answer within {cfg.timeout_s:g} s") from None
        except (ConnectionError, http.client.HTTPException) as exc:
            raise _Retryable(f"connection failed ({type(exc).__name__}: {exc})") from None
        if len(raw) > MAX_REPLY_BYTES:
            raise LLMError(f"LLM reply from {cfg.endpoint} is larger than {MAX_REPLY_BYTES >> 20} MiB")
        try:
            data = json.loads(raw.decode("utf-8"))
        except (UnicodeDecodeError, ValueError):
            raise LLMError(f"LLM at {cfg.endpoint} did not answer with JSON "
                           f"(is this a chat completions endpoint?): {_snippet(raw, 80)!r}") from None
        if not isinstance(data, dict):
            raise LLMError(f"LLM at {cfg.endpoint} answered {type(data).__name__}, not a JSON object")
        return data

    def _content(self, data: dict) -> str:
        try:
            message = data["choices"][0]["message"]
            content = message.get("content")
        except (KeyError, IndexError, TypeError, AttributeError):
            raise LLMError(f"LLM reply from {self.config.endpoint} has no choices[0].message "
                           f"(keys: {', '.join(map(str, data)) or 'none'})") from None
        if isinstance(content, list):  # content parts: [{"type": "text", "text": ...}]
            content = "".join(p.get("text", "") for p in content if isinstance(p, dict))
        # An empty reply is returned as "": the caller's parser says so and asks again.
        return content if isinstance(content, str) else ""
