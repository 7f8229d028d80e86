"""What keeps the local explorer safe: security headers, a bound on request bodies, host and
origin checks. Each is a plain ASGI middleware, applied to every answer, errors included.

- **Headers.** A strict Content-Security-Policy (only the page's own scripts, styles and
  connections; no inline script, no frames, no plug-ins), ``nosniff``, no referrer, no framing,
  same-origin isolation, and ``no-store`` on the API's answers.
- **Request size.** A body longer than the limit (by its Content-Length, or counted as it
  arrives) is refused with 413 before the handler reads it.
- **Origin.** A request that changes state (POST, DELETE) sent by a page of another origin is
  refused with 403 (the browser sends ``Origin``; a script's request without it is allowed).

The host check (only the names the server was started for, against DNS rebinding) is
Starlette's ``TrustedHostMiddleware``, set up in `sandlight.web.app`.
"""

from __future__ import annotations

import json
from collections.abc import Awaitable, Callable
from typing import Any

__all__ = ["SECURITY_HEADERS", "SecurityHeaders", "BodyLimit", "SameOrigin"]

Scope = dict[str, Any]
Receive = Callable[[], Awaitable[dict]]
Send = Callable[[dict], Awaitable[None]]
App = Callable[[Scope, Receive, Send], Awaitable[None]]

#: Headers of every answer (the page uses no inline script or style, so 'self' suffices).
SECURITY_HEADERS: dict[str, str] = {
    "content-security-policy": (
        "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' data: blob:; "
        "connect-src 'self'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'"
    ),
    "x-content-type-options": "nosniff",
    "referrer-policy": "no-referrer",
    "x-frame-options": "DENY",
    "cross-origin-opener-policy": "same-origin",
    "cross-origin-resource-policy": "same-origin",
    "permissions-policy": "camera=(), microphone=(), geolocation=(), payment=(), usb=()",
}


async def _refuse(send: Send, status: int, kind: str, message: str) -> None:
    body = json.dumps({"error": kind, "message": message}).encode()
    headers = [(b"content-type", b"application/json"), (b"content-length", str(len(body)).encode())]
    headers += [(k.encode(), v.encode()) for k, v in SECURITY_HEADERS.items()]
    await send({"type": "http.response.start", "status": status, "headers": headers})
    await send({"type": "http.response.body", "body": body})


def _header(scope: Scope, name: bytes) -> str | None:
    for key, value in scope.get("headers", ()):
        if key == name:
            return value.decode("latin-1")
    return None


class SecurityHeaders:
    """Adds `SECURITY_HEADERS` to every answer, and ``cache-control: no-store`` to the API's."""

    def __init__(self, app: App) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        api = scope["path"].startswith("/api/")

        async def with_headers(message: dict) -> None:
            if message["type"] == "http.response.start":
                headers = [(k, v) for k, v in message.get("headers", []) if k.decode().lower() not in SECURITY_HEADERS]
                headers += [(k.encode(), v.encode()) for k, v in SECURITY_HEADERS.items()]
                if api:
                    headers.append((b"cache-control", b"no-store"))
                message = {**message, "headers": headers}
            await send(message)

        await self.app(scope, receive, with_headers)


class BodyLimit:
    """Refuses request bodies longer than ``limit_for(path)`` bytes with 413."""

    def __init__(self, app: App, limit_for: Callable[[str], int]) -> None:
        self.app, self.limit_for = app, limit_for

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        limit = self.limit_for(scope["path"])
        message = f"the request body is larger than the limit of {limit:,} bytes for {scope['path']}"
        length = _header(scope, b"content-length")
        if length is not None and (not length.isdigit() or int(length) > limit):
            await _refuse(send, 413, "limit", message)
            return
        received = 0
        too_large = False

        async def counted() -> dict:
            nonlocal received, too_large
            event = await receive()
            if event["type"] == "http.request":
                received += len(event.get("body", b""))
                if received > limit:
                    too_large = True
                    raise _TooLarge
            return event

        started = False

        async def watched(event: dict) -> None:
            nonlocal started
            started = started or event["type"] == "http.response.start"
            await send(event)

        try:
            await self.app(scope, counted, watched)
        except _TooLarge:
            if not started:
                await _refuse(send, 413, "limit", message)


class _TooLarge(Exception):
    """A streamed body passed the limit (caught by `BodyLimit`)."""


class SameOrigin:
    """Refuses a POST or DELETE whose ``Origin`` is not this server (a page of another site)."""

    def __init__(self, app: App) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http" and scope["method"] in ("POST", "PUT", "DELETE", "PATCH"):
            origin = _header(scope, b"origin")
            host = (_header(scope, b"host") or "").lower()
            if origin is not None and origin.lower() not in (f"http://{host}", f"https://{host}"):
                await _refuse(send, 403, "origin", f"requests sent by the page {origin!r} are not accepted")
                return
        await self.app(scope, receive, send)
