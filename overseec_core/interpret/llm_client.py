"""A small client for the OpenAI-compatible chat completions API (standard library only).

``POST {base_url}/chat/completions`` is what Ollama (``http://localhost:11434/v1``), vLLM,
llama.cpp's server and hosted APIs all speak. Written on ``urllib.request`` rather than an SDK:
the call is one JSON POST, the official SDKs pull in a dozen packages (httpx, pydantic, ...) that
QGIS's own Python does not have, and the plugin runs the interpret stage in-process.

Behaviour:
- **one deadline per HTTP request**: connect, headers, body and same-host redirects together
  take at most the timeout. urllib's own timeout applies to each socket operation, so a server
  that trickles a byte a second would never trip it; here a watchdog timer shuts the socket down
  at the deadline and each socket operation waits at most the time left (:class:`_Deadline`);
- redirects are followed only within the same origin (scheme, host and port), re-sending the
  same POST; a redirect elsewhere is not followed -- the ``Authorization`` header must not go to
  a host the user did not name -- and is an LLMError naming where it pointed;
- timeouts, connection errors, HTTP 429 and 5xx are retried a bounded number of times (each try
  with its own deadline) with exponential backoff (``backoff_s * 2**k``, at most
  ``backoff_max_s``, or the server's ``Retry-After`` when shorter than that);
- ``response_format`` (JSON-schema structured output) is sent when asked; a server that rejects
  it with HTTP 400 is asked again without it, and is not sent it again by this client;
- any other failure is an :class:`~overseec_core.errors.LLMError` with one line that says what
  to check.

Not bounded by the deadline: the host name lookup (``getaddrinfo`` cannot be interrupted), which
the operating system's resolver bounds.

The endpoint, model, key and limits come from :class:`overseec_core.interpret.llm.LLMConfig`.
"""

from __future__ import annotations

import functools
import http.client
import json
import math
import socket
import threading
import time
import urllib.error
import urllib.parse
import urllib.request
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any

from overseec_core.errors import LLMError
from overseec_core.interpret.llm import LLMConfig, redact, redact_url, split_userinfo
from overseec_core.progress import Progress, check_cancelled

#: Largest reply body read (bytes); a chat reply is a few kilobytes.
MAX_REPLY_BYTES = 8 << 20
#: Largest error body read (bytes): enough for the server's message.
MAX_ERROR_BYTES = 4096
#: Same-origin redirects followed per request.
MAX_REDIRECTS = 3


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


class _TimedOut(Exception):
    """Internal: the request's deadline passed."""


class _CrossOriginRedirect(Exception):
    """Internal: the server redirected to another origin (not followed)."""

    def __init__(self, status: int, target: str):
        super().__init__(target)
        self.status = status
        self.target = target


def origin(url: str) -> tuple[str, str, int | None]:
    """(scheme, host, port) of ``url``, default ports filled in: what "same host" means for
    sending the Authorization header on."""
    parts = urllib.parse.urlsplit(url)
    scheme = parts.scheme.lower()
    try:
        port = parts.port
    except ValueError:
        port = -1
    if port is None:
        port = {"http": 80, "https": 443}.get(scheme)
    return scheme, (parts.hostname or "").lower(), port


class _Deadline:
    """One wall-clock deadline for one HTTP request: connect, headers, body, redirects.

    urllib's timeout applies to each socket operation, so a server that sends a byte every few
    seconds, or its headers one by one, would keep a request alive indefinitely. A timer thread
    shuts down the request's current socket at the deadline, which wakes whatever read or write
    is blocked on it, and :meth:`op_timeout` keeps each socket operation within the time left.
    Use as a context manager around the whole request; ``expired`` says whether it fired.
    """

    def __init__(self, seconds: float):
        self.seconds = seconds
        self.at = time.monotonic() + seconds
        self.expired = False
        self._sock: socket.socket | None = None
        self._done = False
        self._lock = threading.Lock()
        self._timer = threading.Timer(seconds, self._fire)
        self._timer.daemon = True

    def __enter__(self) -> _Deadline:
        self._timer.start()
        return self

    def __exit__(self, *exc: object) -> None:
        with self._lock:
            self._done = True
        self._timer.cancel()

    def remaining(self) -> float:
        return self.at - time.monotonic()

    def op_timeout(self) -> float:
        """Timeout for the next socket operation: the time left (never more than the whole)."""
        return max(0.001, min(self.remaining(), self.seconds))

    def watch(self, sock: socket.socket) -> None:
        """Make ``sock`` the one shut down at the deadline (each new connection registers)."""
        with self._lock:
            self._sock = sock
            late = self.expired
        if late:
            _shutdown(sock)

    def tighten(self) -> None:
        """Bound the watched socket's next operation by the time left; raise once it is gone."""
        if self.expired or self.remaining() <= 0:
            raise _TimedOut
        with self._lock:
            sock = self._sock
        if sock is not None:
            try:
                sock.settimeout(self.op_timeout())
            except OSError:
                pass

    def _fire(self) -> None:
        with self._lock:
            if self._done:
                return
            self.expired = True
            sock = self._sock
        if sock is not None:
            _shutdown(sock)


def _shutdown(sock: socket.socket) -> None:
    """Shut ``sock`` down both ways (wakes a blocked recv/send); closing is left to its owner."""
    try:
        sock.shutdown(socket.SHUT_RDWR)
    except OSError:
        pass


class _WatchedSockets:
    """The socket factory both connection classes install: every socket is watched by the
    deadline and its operations bounded by it."""

    _deadline: _Deadline

    def _create_watched(self, address, timeout=None, source_address=None):
        sock = socket.create_connection(address, self._deadline.op_timeout(), source_address)
        self._deadline.watch(sock)
        return sock


class _WatchedHTTPConnection(_WatchedSockets, http.client.HTTPConnection):
    """An HTTPConnection whose sockets the deadline watches and whose operations it bounds."""

    def __init__(self, *args: Any, deadline: _Deadline, **kwargs: Any):
        super().__init__(*args, **kwargs)
        self._deadline = deadline
        self._create_connection = self._create_watched


#: Whether this Python has TLS (``ssl``); without it only http:// URLs can work.
_HAS_TLS = hasattr(http.client, "HTTPSConnection") and hasattr(urllib.request, "HTTPSHandler")

if _HAS_TLS:

    class _WatchedHTTPSConnection(_WatchedSockets, http.client.HTTPSConnection):
        """The HTTPS twin: the TLS socket is watched before its handshake starts."""

        def __init__(self, *args: Any, deadline: _Deadline, **kwargs: Any):
            super().__init__(*args, **kwargs)
            self._deadline = deadline
            self._create_connection = self._create_watched

        def connect(self) -> None:
            http.client.HTTPConnection.connect(self)  # TCP (+ proxy CONNECT tunnel)
            host = getattr(self, "_tunnel_host", None) or self.host
            # _context: HTTPSConnection's SSL context (private, so not in typeshed)
            self.sock = self._context.wrap_socket(  # type: ignore[attr-defined]
                self.sock, server_hostname=host, do_handshake_on_connect=False
            )
            self._deadline.watch(self.sock)
            self.sock.settimeout(self._deadline.op_timeout())
            self.sock.do_handshake()


class _DeadlineHTTPHandler(urllib.request.HTTPHandler):
    def __init__(self, deadline: _Deadline):
        super().__init__()
        self._deadline = deadline

    def http_open(self, req: urllib.request.Request):
        return self.do_open(functools.partial(_WatchedHTTPConnection, deadline=self._deadline), req)


if _HAS_TLS:

    class _DeadlineHTTPSHandler(urllib.request.HTTPSHandler):
        def __init__(self, deadline: _Deadline):
            super().__init__()
            self._deadline = deadline

        def https_open(self, req: urllib.request.Request):
            context = self._context  # type: ignore[attr-defined]  # HTTPSHandler's private attribute
            return self.do_open(
                functools.partial(_WatchedHTTPSConnection, deadline=self._deadline), req, context=context
            )


class _SameOriginRedirects(urllib.request.HTTPRedirectHandler):
    """Follow a redirect only within the request's origin, re-sending the same POST with its
    headers; refuse any other, so the Authorization header never reaches a host the user did not
    name (urllib's default copies it to wherever the server points, and turns a POST into a
    GET)."""

    max_redirections = MAX_REDIRECTS

    def redirect_request(self, req, fp, code, msg, headers, newurl):
        if origin(newurl) != origin(req.full_url):
            fp.close()
            raise _CrossOriginRedirect(code, newurl)
        return urllib.request.Request(
            split_userinfo(newurl)[0],
            data=req.data,
            method=req.get_method(),
            headers={**req.headers, **req.unredirected_hdrs},
            origin_req_host=req.origin_req_host,
            unverifiable=True,
        )


def _opener(deadline: _Deadline) -> urllib.request.OpenerDirector:
    """An opener for one request: the deadline on every connection, same-origin redirects only
    (proxies from the environment as usual)."""
    handlers: list[urllib.request.BaseHandler] = [_DeadlineHTTPHandler(deadline), _SameOriginRedirects()]
    if _HAS_TLS:
        handlers.append(_DeadlineHTTPSHandler(deadline))
    return urllib.request.build_opener(*handlers)


def _read(resp: Any, deadline: _Deadline, limit: int) -> bytes:
    """Up to ``limit + 1`` bytes of a response body, a chunk at a time, within the deadline."""
    read = getattr(resp, "read1", None) or resp.read
    chunks: list[bytes] = []
    total = 0
    while total <= limit:
        deadline.tighten()
        chunk = read(min(1 << 16, limit + 1 - total))
        if not chunk:
            break
        chunks.append(chunk)
        total += len(chunk)
    if deadline.expired:  # the watchdog's shutdown looks like an early end of the body
        raise _TimedOut
    return b"".join(chunks)


def _is_timeout(exc: BaseException) -> bool:
    """Whether ``exc`` is a socket timeout (urllib wraps those raised while connecting)."""
    if isinstance(exc, urllib.error.URLError):
        exc = exc.reason  # type: ignore[assignment]
    return isinstance(exc, (TimeoutError, socket.timeout))


def _transport_why(exc: BaseException) -> str:
    """Why a request failed below HTTP, in a few words (redacted by the caller)."""
    if isinstance(exc, urllib.error.URLError):
        reason = exc.reason
        return f"cannot connect ({getattr(reason, 'strerror', None) or reason})"
    return f"connection failed ({type(exc).__name__}: {exc})"


_HINTS = {
    401: "check the API key (or the user:password in the LLM URL)",
    403: "check the API key and its permissions",
    404: "check the LLM URL (most servers want it to end in /v1) and the model name",
}


def _snippet(raw: bytes, secrets: Iterable[str] = (), limit: int = 200) -> str:
    """A one-line excerpt of a reply body (the OpenAI-style error message when there is one),
    redacted before it is shortened so that no part of a secret survives the cut."""
    text = raw.decode("utf-8", "replace")
    try:  # OpenAI-style {"error": {"message": ...}}
        err = json.loads(text).get("error")
        text = err.get("message", text) if isinstance(err, dict) else str(err or text)
    except (ValueError, AttributeError):
        pass
    text = " ".join(redact(str(text), secrets).split())
    return text[:limit] + ("..." if len(text) > limit else "")


def _retry_after(headers) -> float | None:
    raw = headers.get("Retry-After") if headers is not None else None
    try:
        value = float(raw) if raw is not None else None
    except ValueError:
        return None
    return max(0.0, value) if value is not None and math.isfinite(value) else None


class ChatClient:
    """Chat completions over HTTP with one deadline per request and bounded retries."""

    def __init__(
        self, config: LLMConfig, *, progress: Progress | None = None, sleep: Callable[[float], None] = time.sleep
    ):
        self.config = config
        self.progress = progress
        self.sleep = sleep
        #: False once the server rejected ``response_format``.
        self.structured_ok = config.structured
        #: Requests sent (for the notes/manifest).
        self.requests = 0

    def complete(self, messages: Sequence[Mapping[str, str]], response_format: Mapping[str, Any] | None = None) -> str:
        """The assistant's reply text for ``messages``, with this configuration's secrets
        redacted (a reply is data that ends up in notes and the manifest)."""
        body: dict[str, Any] = {
            "model": self.config.model,
            "messages": list(messages),
            "temperature": self.config.temperature,
            "stream": False,
        }
        if response_format is not None and self.structured_ok:
            try:
                return self._content(self._post({**body, "response_format": response_format}))
            except LLMHTTPError as exc:
                if exc.status != 400:
                    raise
                self.structured_ok = False
                self._say("LLM rejected structured output (HTTP 400); asking without it")
        return self._content(self._post(body))

    # -- messages: everything shown goes through the configuration's redact()
    def _say(self, text: str) -> None:
        if self.progress is not None:
            self.progress.message(self.config.redact(text))

    def _error(self, text: str, status: int | None = None) -> LLMError:
        """An LLMError (LLMHTTPError with a status) whose one line is redacted."""
        line = " ".join(self.config.redact(text).split())
        return LLMError(line) if status is None else LLMHTTPError(line, status)

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
                    raise self._error(
                        f"LLM at {cfg.display_endpoint} failed after {tries} "
                        f"{'try' if tries == 1 else 'tries'}: {exc.why}"
                    ) from None
                delay = min(cfg.backoff_max_s, cfg.backoff_s * 2**attempt)
                if exc.retry_after is not None:  # the server knows best, within our bound
                    delay = min(exc.retry_after, cfg.backoff_max_s)
                self._say(f"LLM: {exc.why}; retrying in {delay:.1f} s ({attempt + 2}/{tries})")
                self.sleep(delay)
        raise AssertionError("unreachable")  # pragma: no cover

    def _post_once(self, body: Mapping[str, Any]) -> dict:
        """One HTTP request within one deadline; the reply as a JSON object."""
        cfg = self.config
        headers = {"Content-Type": "application/json", "Accept": "application/json", "User-Agent": "overseec"}
        auth = cfg.authorization()
        if auth:
            headers["Authorization"] = auth
        req = urllib.request.Request(
            cfg.endpoint, data=json.dumps(body).encode("utf-8"), headers=headers, method="POST"
        )
        self.requests += 1
        timed_out = _Retryable(f"timed out (no complete answer within {cfg.timeout_s:g} s)")
        with _Deadline(cfg.timeout_s) as deadline:
            try:
                raw = self._exchange(req, deadline)
            except _TimedOut:
                raise timed_out from None
            except _Retryable:
                raise
            except (OSError, http.client.HTTPException, ValueError) as exc:
                if deadline.expired or _is_timeout(exc):  # the watchdog's shutdown surfaces
                    raise timed_out from None  # as any of these
                raise _Retryable(_transport_why(exc)) from None
        return self._parse(raw)

    def _exchange(self, req: urllib.request.Request, deadline: _Deadline) -> bytes:
        """Send ``req`` and read the reply body; HTTP errors and redirects become exceptions."""
        cfg = self.config
        try:
            resp = _opener(deadline).open(req, timeout=deadline.op_timeout())
        except urllib.error.HTTPError as exc:
            try:
                detail = _snippet(_read(exc, deadline, MAX_ERROR_BYTES) if exc.fp else b"", cfg.secrets)
            finally:
                exc.close()
            status = exc.code
            if status == 429 or status >= 500:
                raise _Retryable(f"HTTP {status} ({detail or exc.reason})", _retry_after(exc.headers)) from None
            hint = _HINTS.get(status, "")
            raise self._error(
                f"LLM at {cfg.display_endpoint} answered HTTP {status}"
                f"{': ' + detail if detail else ''}{' -- ' + hint if hint else ''}",
                status,
            ) from None
        except _CrossOriginRedirect as exc:
            where = redact_url(exc.target)
            raise self._error(
                f"LLM at {cfg.display_endpoint} redirected (HTTP {exc.status}) to another host, "
                f"{where}; not followed, so the credentials are not sent there -- set the LLM URL "
                "to the new address if you trust it"
            ) from None
        with resp:
            raw = _read(resp, deadline, MAX_REPLY_BYTES)
        if len(raw) > MAX_REPLY_BYTES:
            raise self._error(f"LLM reply from {cfg.display_endpoint} is larger than {MAX_REPLY_BYTES >> 20} MiB")
        return raw

    def _parse(self, raw: bytes) -> dict:
        cfg = self.config
        try:
            data = json.loads(raw.decode("utf-8"))
        except (UnicodeDecodeError, ValueError):
            raise self._error(
                f"LLM at {cfg.display_endpoint} did not answer with JSON (is this a "
                f"chat completions endpoint?): {_snippet(raw, cfg.secrets, 80)!r}"
            ) from None
        if not isinstance(data, dict):
            raise self._error(f"LLM at {cfg.display_endpoint} answered {type(data).__name__}, not a JSON object")
        return data

    def _content(self, data: dict) -> str:
        try:
            message = data["choices"][0]["message"]
            content = message.get("content")
        except (KeyError, IndexError, TypeError, AttributeError):
            keys = ", ".join(map(str, data))[:200] or "none"
            raise self._error(
                f"LLM reply from {self.config.display_endpoint} has no choices[0].message (keys: {keys})"
            ) from None
        if isinstance(content, list):  # content parts: [{"type": "text", "text": ...}]
            content = "".join(
                p.get("text", "") for p in content if isinstance(p, dict) and isinstance(p.get("text", ""), str)
            )
        # An empty reply is returned as "": the caller's parser says so and asks again.
        return self.config.redact(content) if isinstance(content, str) else ""
