"""A real HTTP server speaking the chat completions protocol, with scripted replies, for tests.

Runs ``http.server.ThreadingHTTPServer`` on 127.0.0.1 (port 0) in a thread. Each POST takes the
next scripted action and records the request (path, headers, JSON body), so tests can assert both
on what the client did with the replies and on what it sent.

Actions (dicts): ``{"content": text}`` a normal reply; ``{"status": 500, "body": text}`` an
HTTP error (``headers`` optional); ``{"raw": bytes}`` a 200 with that body; ``{"sleep": s, ...}``
waits ``s`` seconds before acting (timeouts). When the script runs out the server answers
HTTP 599 so a test that sends too many requests fails loudly.

Hostile actions (issue 13): ``{"trickle": s, "for": t}`` sends a 200 with a large Content-Length
and then one body byte every ``s`` seconds for ``t`` seconds; ``{"slow_headers": s, "for": t}``
sends the status line and then one header line every ``s`` seconds; ``{"status": 401,
"echo_auth": True}`` answers with the request's Authorization header in the error message
(``"echo_raw": True``: as a plain-text body); ``{"redirect": url, "status": 307}`` answers with
``Location: url``.
"""

from __future__ import annotations

import json
import socket
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any


def completion(content: str, model: str = "test-model") -> dict[str, Any]:
    """A chat completion response body."""
    return {
        "id": "chatcmpl-test",
        "object": "chat.completion",
        "created": 0,
        "model": model,
        "choices": [{"index": 0, "finish_reason": "stop", "message": {"role": "assistant", "content": content}}],
        "usage": {"prompt_tokens": 1, "completion_tokens": 1, "total_tokens": 2},
    }


class _Server(ThreadingHTTPServer):
    daemon_threads = True
    block_on_close = False

    def handle_error(self, request, client_address) -> None:  # a client that timed out and left
        pass


class ChatServer:
    """Scripted chat completions endpoint; ``url`` is the base URL (``.../v1``)."""

    def __init__(self) -> None:  # noqa: C901
        self.script: list[dict[str, Any]] = []
        self.requests: list[dict[str, Any]] = []
        self._lock = threading.Lock()
        owner = self

        class Handler(BaseHTTPRequestHandler):
            protocol_version = "HTTP/1.1"

            def log_message(self, *args) -> None:
                pass

            def do_POST(self) -> None:
                length = int(self.headers.get("Content-Length") or 0)
                raw = self.rfile.read(length)
                try:
                    body = json.loads(raw)
                except ValueError:
                    body = None
                with owner._lock:
                    owner.requests.append({"path": self.path, "headers": dict(self.headers), "body": body})
                    action = owner.script.pop(0) if owner.script else {"status": 599, "body": "script exhausted"}
                if action.get("sleep"):
                    time.sleep(action["sleep"])
                if "trickle" in action:
                    self._trickle(action["trickle"], action.get("for", 10.0))
                elif "slow_headers" in action:
                    self._slow_headers(action["slow_headers"], action.get("for", 10.0))
                elif "redirect" in action:
                    self._send(action.get("status", 307), b"", {"Location": action["redirect"]})
                elif action.get("echo_auth"):
                    auth = self.headers.get("Authorization", "")
                    data = (
                        f"denied: {auth}".encode()
                        if action.get("echo_raw")
                        else json.dumps({"error": {"message": f"invalid credentials {auth}"}}).encode()
                    )
                    self._send(action.get("status", 401), data, action.get("headers", {}))
                elif "content" in action:
                    self._send(200, json.dumps(completion(action["content"])).encode())
                elif "raw" in action:
                    self._send(200, action["raw"])
                else:
                    body = action.get("body", "")
                    data = body if isinstance(body, bytes) else json.dumps({"error": {"message": body}}).encode()
                    self._send(action["status"], data, action.get("headers", {}))

            def _send(self, status: int, data: bytes, headers: dict | None = None) -> None:
                try:
                    self.send_response(status)
                    self.send_header("Content-Type", "application/json")
                    self.send_header("Content-Length", str(len(data)))
                    for k, v in (headers or {}).items():
                        self.send_header(k, v)
                    self.end_headers()
                    self.wfile.write(data)
                except OSError:  # the client gave up (timeout test)
                    pass

            def do_GET(self) -> None:
                with owner._lock:
                    owner.requests.append(
                        {"path": self.path, "headers": dict(self.headers), "body": None, "method": "GET"}
                    )
                self._send(405, json.dumps({"error": {"message": "GET not allowed"}}).encode())

            def _trickle(self, interval: float, duration: float) -> None:
                """A 200 whose body never completes: one byte per ``interval``."""
                try:
                    self.send_response(200)
                    self.send_header("Content-Type", "application/json")
                    self.send_header("Content-Length", str(1 << 20))
                    self.end_headers()
                    self.wfile.flush()
                    end = time.monotonic() + duration
                    while time.monotonic() < end:
                        self.wfile.write(b" ")
                        self.wfile.flush()
                        time.sleep(interval)
                except OSError:  # the client gave up
                    pass
                self.close_connection = True

            def _slow_headers(self, interval: float, duration: float) -> None:
                """A status line, then a header line per ``interval``, never the blank line."""
                try:
                    self.wfile.write(b"HTTP/1.1 200 OK\r\n")
                    self.wfile.flush()
                    end, n = time.monotonic() + duration, 0
                    while time.monotonic() < end:
                        time.sleep(interval)
                        n += 1
                        self.wfile.write(f"X-Slow-{n}: {n}\r\n".encode())
                        self.wfile.flush()
                except OSError:
                    pass
                self.close_connection = True

        self._server = _Server(("127.0.0.1", 0), Handler)
        self.port = self._server.server_address[1]
        self.url = f"http://127.0.0.1:{self.port}/v1"
        self._thread = threading.Thread(target=self._server.serve_forever, kwargs={"poll_interval": 0.02}, daemon=True)

    def start(self) -> ChatServer:
        self._thread.start()
        return self

    def stop(self) -> None:
        self._server.shutdown()
        self._server.server_close()

    def reply(self, *actions: dict[str, Any] | str) -> ChatServer:
        """Queue actions (a plain string is a normal reply with that content)."""
        with self._lock:
            self.script.extend({"content": a} if isinstance(a, str) else a for a in actions)
        return self

    def bodies(self) -> list[dict[str, Any]]:
        return [r["body"] for r in self.requests]


def refused_url() -> str:
    """A base URL on 127.0.0.1 where nothing listens (a port bound, then closed)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    return f"http://127.0.0.1:{port}/v1"
