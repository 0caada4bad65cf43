"""Configuration of the LLM endpoint, and keeping its secrets out of text (standard library only).

The chat call itself is :class:`overseec_core.interpret.llm_client.ChatClient`; this module is
what it is configured with (:class:`LLMConfig`, :func:`resolve_config`) and what every message
passes through (:func:`redact`, :func:`redact_url`):

- configuration from arguments, else the environment: ``OVERSEEC_LLM_URL``,
  ``OVERSEEC_LLM_MODEL``, ``OVERSEEC_LLM_API_KEY`` (sent as ``Authorization: Bearer``),
  ``OVERSEEC_LLM_TIMEOUT`` (seconds, finite, in (0, 3600]), ``OVERSEEC_LLM_RETRIES`` (a whole
  number in [0, 10]), ``OVERSEEC_LLM_FALLBACK=offline``; a bad value is a one-line InputError;
- credentials in the URL (``http://user:password@host/v1``) are sent as HTTP Basic auth and
  removed from the URL that is requested; a URL with credentials *and* an API key is refused
  (which one to send would be a guess);
- **secrets never leave in text**: the API key and the URL's password are replaced by ``***``
  in every message, note, progress line, ``describe()`` (the manifest) and ``repr``, and in any
  reply text, including a server that echoes them back (:func:`redact`; URLs are shown with
  their user information as ``***@``, :func:`redact_url`);
"""

from __future__ import annotations

import base64
import json
import math
import os
import re
import urllib.parse
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from overseec_core.errors import InputError

ENV_URL = "OVERSEEC_LLM_URL"
ENV_MODEL = "OVERSEEC_LLM_MODEL"
ENV_KEY = "OVERSEEC_LLM_API_KEY"
ENV_TIMEOUT = "OVERSEEC_LLM_TIMEOUT"
ENV_RETRIES = "OVERSEEC_LLM_RETRIES"
ENV_FALLBACK = "OVERSEEC_LLM_FALLBACK"

#: Longest timeout accepted (seconds): an hour is already far past any useful chat reply.
MAX_TIMEOUT_S = 3600.0
#: Most retries accepted: with the backoff cap, more only delays the error the user must see.
MAX_RETRIES = 10
#: What a secret is replaced with.
MASK = "***"


# ----------------------------------------------------------------------------- secrets


def _authority(url: str) -> tuple[int, int]:
    """Start and end of the ``[userinfo@]host[:port]`` part of ``url``, found by hand rather
    than by ``urlsplit`` so that text which is no valid URL (``user:pw@host``, ``http://[bad``)
    is still split, and redacted, without an exception."""
    scheme_end = url.find("//")
    start = scheme_end + 2 if scheme_end >= 0 else 0
    end = min((i for i in (url.find(c, start) for c in "/?#") if i >= 0), default=len(url))
    return start, end


def split_userinfo(url: str) -> tuple[str, str | None, str | None]:
    """``url`` without its ``user:password@`` part, plus the (percent-decoded) user and password.

    The credentials must not stay in the URL that is requested or shown: urllib would put them in
    the Host header (and fail), and messages would print them.
    """
    start, end = _authority(url)
    userinfo, at, hostport = url[start:end].rpartition("@")
    if not at:
        return url, None, None
    user, sep, password = userinfo.partition(":")
    return (
        url[:start] + hostport + url[end:],
        urllib.parse.unquote(user),
        urllib.parse.unquote(password) if sep else None,
    )


def redact_url(url: str) -> str:
    """``url`` with any user information shown as ``***@`` (``http://***@host/v1``).

    Works on text that is not a valid URL too (``user:pw@host``), since it is used on whatever the
    user typed, including URLs refused as invalid.
    """
    start, end = _authority(url)
    if "@" not in url[start:end]:
        return url
    return f"{url[:start]}{MASK}@{url[start:end].rpartition('@')[2]}{url[end:]}"


def url_secrets(url: str) -> tuple[str, ...]:
    """The secrets a URL carries: its password, or its user name when there is no password
    (``http://TOKEN@host`` is a token in the user name)."""
    _, user, password = split_userinfo(url)
    if password:
        return (password,)
    return (user,) if user else ()


def basic_auth(user: str, password: str | None) -> str:
    """The ``Authorization`` value for HTTP Basic auth with these credentials."""
    token = base64.b64encode(f"{user}:{password or ''}".encode()).decode("ascii")
    return f"Basic {token}"


def secret_forms(secret: str) -> set[str]:
    """The spellings of ``secret`` a reply or an error may carry: as is, JSON-escaped (a body that
    echoes it), percent-encoded (a URL that carries it)."""
    forms = {
        secret,
        json.dumps(secret)[1:-1],
        json.dumps(secret, ensure_ascii=False)[1:-1],
        urllib.parse.quote(secret, safe=""),
        urllib.parse.quote(secret),
    }
    return {f for f in forms if f}


#: ``scheme://anything@`` in free text: user information in a URL, whatever it is.
_URL_USERINFO = re.compile(r"(?i)\b([a-z][a-z0-9+.-]*://)[^/\s@?#]*@")
#: ``Bearer xxx`` / ``Basic xxx``: an echoed Authorization value, whichever key it carries.
_AUTH_VALUE = re.compile(r"(?i)\b(bearer|basic)(\s+|%20|\+)[A-Za-z0-9._~+/=-]{6,}")


def redact(text: str, secrets: Iterable[str] = ()) -> str:
    """``text`` with every form of each secret, URL user information and any
    ``Bearer``/``Basic`` credential replaced by ``***``.

    The one function every message, note and reply passes through before anyone can see it, so
    that a key cannot reach a manifest, a log or the screen by a path nobody thought of (a server
    that echoes the request, an exception that prints the URL).
    """
    forms = sorted({f for s in secrets if s for f in secret_forms(s)}, key=len, reverse=True)
    for form in forms:  # longest first: a secret that contains another is removed whole
        text = text.replace(form, MASK)
    text = _URL_USERINFO.sub(lambda m: m.group(1) + MASK + "@", text)
    return _AUTH_VALUE.sub(lambda m: m.group(1) + " " + MASK, text)


# ----------------------------------------------------------------------------- configuration


def check_timeout(value: Any, what: str = "LLM timeout") -> float:
    """``value`` as a timeout in seconds: finite and in (0, MAX_TIMEOUT_S]; else an InputError
    that names the allowed range (``inf`` or ``1e300`` would otherwise overflow the socket
    layer with a traceback, ``nan`` and ``0`` would never or always time out)."""
    x = float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else math.nan
    if not (math.isfinite(x) and 0 < x <= MAX_TIMEOUT_S):
        raise InputError(f"{what} must be a number of seconds above 0 and at most {MAX_TIMEOUT_S:g}, got {value!r}")
    return x


def check_retries(value: Any, what: str = "LLM retries") -> int:
    """``value`` as a retry count: a whole number in [0, MAX_RETRIES]; else an InputError."""
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int):
        raise InputError(f"{what} must be a whole number from 0 to {MAX_RETRIES}, got {value!r}")
    if not 0 <= value <= MAX_RETRIES:
        raise InputError(f"{what} must be a whole number from 0 to {MAX_RETRIES}, got {value}")
    return value


def _check_url(url: str) -> None:
    """An InputError unless ``url`` is an http(s) URL with a host and a valid port."""
    shown = redact(redact_url(url), url_secrets(url))
    try:
        parts = urllib.parse.urlsplit(url)
        parts.port  # noqa: B018 -- raises ValueError on a bad port
    except ValueError:
        raise InputError(f"LLM URL {shown!r} has an invalid host or port (e.g. http://localhost:11434/v1)") from None
    if parts.scheme not in ("http", "https") or not parts.hostname:
        raise InputError(f"LLM URL {shown!r} is not an http(s) URL (e.g. http://localhost:11434/v1)")


@dataclass(frozen=True)
class LLMConfig:
    """Where and how to reach the LLM. Secrets (the API key, a password in ``base_url``) are kept
    out of ``repr``, ``describe()`` and every message: use :meth:`redact` on any text that may
    hold them and :attr:`display_url` to show the URL."""

    base_url: str
    model: str
    api_key: str | None = field(default=None, repr=False)
    #: Seconds per HTTP request, all of it (connect + headers + body + same-host redirects).
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
        _check_url(self.base_url)
        if not self.model.strip():
            raise InputError("no LLM model name given (--llm-model or OVERSEEC_LLM_MODEL)")
        # normalised in place (frozen): 3.0 retries is 3, and range() wants an int
        object.__setattr__(
            self, "timeout_s", check_timeout(self.timeout_s, "LLM timeout (--llm-timeout or OVERSEEC_LLM_TIMEOUT)")
        )
        object.__setattr__(
            self, "retries", check_retries(self.retries, "LLM retries (--llm-retries or OVERSEEC_LLM_RETRIES)")
        )
        if isinstance(self.attempts, bool) or not isinstance(self.attempts, int) or self.attempts < 1:
            raise InputError(f"LLM attempts must be a whole number >= 1, got {self.attempts!r}")
        for name in ("backoff_s", "backoff_max_s"):
            value = getattr(self, name)
            if (
                isinstance(value, bool)
                or not isinstance(value, (int, float))
                or not (math.isfinite(value) and value >= 0)
            ):
                raise InputError(f"LLM {name} must be a finite number >= 0, got {value!r}")
        if url_secrets(self.base_url) and self.api_key:
            raise InputError(
                f"the LLM URL {self.display_url} carries a user name/password and an "
                "API key is set too (OVERSEEC_LLM_API_KEY or --llm-key-env); give one"
            )

    def __repr__(self) -> str:
        return (
            f"LLMConfig(base_url={self.display_url!r}, model={self.model!r}, "
            f"api_key={'***' if self.api_key else None}, timeout_s={self.timeout_s!r}, "
            f"retries={self.retries!r})"
        )

    @property
    def request_url(self) -> str:
        """``base_url`` without user information: what is actually requested."""
        return split_userinfo(self.base_url)[0]

    @property
    def display_url(self) -> str:
        """``base_url`` as shown in messages and the manifest (user information as ``***@``)."""
        return self.redact(redact_url(self.base_url))

    @property
    def endpoint(self) -> str:
        """The chat completions URL requested (no user information)."""
        return self.request_url.rstrip("/") + "/chat/completions"

    @property
    def display_endpoint(self) -> str:
        """The chat completions URL as shown in messages."""
        return self.display_url.rstrip("/") + "/chat/completions"

    @property
    def secrets(self) -> tuple[str, ...]:
        """Everything that must never be shown: the API key, the URL's password (or token), and
        the Basic auth token made from it."""
        out = [self.api_key] if self.api_key else []
        for secret in url_secrets(self.base_url):
            out.append(secret)
            out.append(self.authorization().split(" ", 1)[1])  # type: ignore[union-attr]
        return tuple(out)

    def authorization(self) -> str | None:
        """The ``Authorization`` header value: Bearer for an API key, Basic for URL credentials."""
        if self.api_key:
            return f"Bearer {self.api_key}"
        _, user, password = split_userinfo(self.base_url)
        return basic_auth(user, password) if user is not None else None

    def redact(self, text: str) -> str:
        """``text`` without this configuration's secrets (see :func:`redact`)."""
        return redact(text, self.secrets)

    def describe(self) -> dict[str, Any]:
        """What the manifest records: no secret, only whether one was sent."""
        return {
            "url": self.display_url,
            "model": self.model,
            "api_key": bool(self.api_key),
            "url_credentials": bool(url_secrets(self.base_url)),
            "timeout_s": self.timeout_s,
            "retries": self.retries,
            "attempts": self.attempts,
            "temperature": self.temperature,
            "structured": self.structured,
            "fallback_offline": self.fallback_offline,
        }


def _env_timeout(env: Mapping[str, str]) -> float | None:
    raw = env.get(ENV_TIMEOUT, "").strip()
    if not raw:
        return None
    try:
        value = float(raw)
    except ValueError:
        raise InputError(
            f"{ENV_TIMEOUT}={raw!r} is not a number (seconds above 0 and at most {MAX_TIMEOUT_S:g})"
        ) from None
    return check_timeout(value, f"{ENV_TIMEOUT}={raw!r}: the LLM timeout")


def _env_retries(env: Mapping[str, str]) -> int | None:
    raw = env.get(ENV_RETRIES, "").strip()
    if not raw:
        return None
    try:
        value = int(raw)
    except ValueError:
        raise InputError(f"{ENV_RETRIES}={raw!r} is not a whole number (0 to {MAX_RETRIES})") from None
    return check_retries(value, f"{ENV_RETRIES}={raw!r}: the LLM retries")


def resolve_config(  # noqa: C901
    *,
    url: str | None = None,
    model: str | None = None,
    key_env: str | None = None,
    api_key: str | None = None,
    timeout_s: float | None = None,
    retries: int | None = None,
    fallback_offline: bool | None = None,
    env: Mapping[str, str] | None = None,
) -> LLMConfig | None:
    """An LLMConfig from explicit values, else the environment; None when no URL is set anywhere.

    ``key_env`` names the environment variable that holds the API key (default
    ``OVERSEEC_LLM_API_KEY``); keys are never taken from the command line itself.
    """
    env = os.environ if env is None else env
    url = url or env.get(ENV_URL, "").strip() or None
    if url is None:
        if model or key_env:
            raise InputError(f"an LLM model or key was given but no LLM URL (--llm-url or {ENV_URL})")
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
        timeout_s = _env_timeout(env)
    if retries is None:
        retries = _env_retries(env)
    if fallback_offline is None:
        fallback_offline = env.get(ENV_FALLBACK, "").strip().lower() in ("offline", "1", "true", "yes")
    kwargs: dict[str, Any] = {"api_key": api_key or None, "fallback_offline": fallback_offline}
    if timeout_s is not None:
        kwargs["timeout_s"] = timeout_s
    if retries is not None:
        kwargs["retries"] = retries
    return LLMConfig(url, model, **kwargs)
