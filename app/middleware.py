"""The app's middleware, outermost first: the upload limit (ERA_MAX_UPLOAD_MB: 413 before a body is parsed), the
websocket guard (the access rule and a cap on open viewers for /viser/{key}, which no HTTP middleware sees), and
the access rule with per-user rate limits (ERA_RATE_LIMIT_PER_MINUTE, ERA_RATE_LIMIT_HEAVY_PER_MINUTE: 429 with
Retry-After). :func:`install` adds them to an app in that order."""

from __future__ import annotations

import time
from collections import deque

from fastapi import FastAPI, Request
from starlette.requests import HTTPConnection
from starlette.websockets import WebSocket

from .access import Access
from .config import Settings
from .errors import error_response


class UploadLimit:
    """Pure ASGI middleware: a request body above ``limit`` bytes gets 413 before it is parsed.

    Checks Content-Length first; a body without one (chunked) is counted as it arrives.
    """

    def __init__(self, app, limit: int):
        self.app, self.limit = app, limit

    def _message(self) -> str:
        return (f"The upload is larger than this server's limit of {self.limit / 2**20:.0f} MB (ERA_MAX_UPLOAD_MB). "
                "Send fewer channels or samples, or raise the limit.")

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http" or scope["method"] not in ("POST", "PUT"):
            return await self.app(scope, receive, send)
        for name, value in scope.get("headers", []):
            if name == b"content-length" and value.isdigit() and int(value) > self.limit:
                return await error_response(413, self._message())(scope, receive, send)
        seen = 0
        answered = False  # we sent the 413 ourselves: drop whatever the app sends after it

        async def counting_receive():
            nonlocal seen, answered
            if answered:
                return {"type": "http.disconnect"}
            message = await receive()
            if message["type"] == "http.request":
                seen += len(message.get("body", b""))
                if seen > self.limit:
                    answered = True
                    await error_response(413, self._message())(scope, receive, send)
                    return {"type": "http.disconnect"}  # the app stops reading: the client went away
            return message

        async def guarded_send(message):
            if not answered:
                await send(message)

        try:
            await self.app(scope, counting_receive, guarded_send)
        except Exception:
            if not answered:
                raise



class RateLimit:
    """Sliding one-minute windows per user (app.access.Access.user: the proxy's user, a signed-in browser, else
    the client address): all requests it limits, and the heavy ones (POST)."""

    def __init__(self, per_minute: int, heavy_per_minute: int):
        self.limits = {"all": per_minute, "heavy": heavy_per_minute}
        self._hits: dict[tuple[str, str], deque] = {}

    def check(self, client: str, heavy: bool) -> int | None:
        """Seconds to wait, or None when the request may go ahead (and is counted)."""
        now = time.monotonic()
        kinds = ("all", "heavy") if heavy else ("all",)
        for kind in kinds:
            q = self._hits.setdefault((client, kind), deque())
            while q and now - q[0] > 60.0:
                q.popleft()
            if len(q) >= self.limits[kind]:
                return max(1, int(60.0 - (now - q[0])) + 1)
        for kind in kinds:
            self._hits[(client, kind)].append(now)
        if len(self._hits) > 10_000:  # forget idle clients
            for key in [k for k, q in self._hits.items() if not q or now - q[-1] > 60.0]:
                del self._hits[key]
        return None



class SocketGuard:
    """Pure ASGI middleware for websockets (the viewer's /viser/{key}), which HTTP middleware never sees: the access
    rule as for the API, and at most ``per_user`` open at once per user (Access.user). A refusal closes the socket
    before it is accepted (the server answers the handshake with 403)."""

    def __init__(self, app, access: Access, per_user: int):
        self.app, self.access, self.per_user = app, access, max(1, int(per_user))
        self.open: dict[str, int] = {}

    async def __call__(self, scope, receive, send):
        if scope["type"] != "websocket":
            return await self.app(scope, receive, send)
        conn = HTTPConnection(scope)
        if not self.access.allowed(conn):
            return await WebSocket(scope, receive, send).close(1008, "Sign in first (the team token or the lab's "
                                                                     "sign-in proxy).")
        who = self.access.user(conn)
        if self.open.get(who, 0) >= self.per_user:
            return await WebSocket(scope, receive, send).close(
                1013, f"At most {self.per_user} open viewers per user (ERA_VIEWER_CONNECTIONS): close one.")
        self.open[who] = self.open.get(who, 0) + 1
        try:
            await self.app(scope, receive, send)
        finally:
            self.open[who] -= 1
            if not self.open[who]:
                del self.open[who]


def install(app: FastAPI, settings: Settings, access: Access) -> None:
    """Add the middleware to ``app``: the access rule and rate limits (innermost), the websocket guard, and the
    upload limit (outermost: oversized bodies are refused before anything reads them)."""
    limiter = RateLimit(settings.rate_limit_per_minute, settings.rate_limit_heavy_per_minute)

    @app.middleware("http")
    async def rate_limit(request: Request, call_next):
        path = request.url.path
        refused = access.check(request)
        # the API, and the links and sign-in a stranger could guess tokens at; refusals count for their address
        if path.startswith(("/api/", "/r/", "/c/", "/s/")) or path == "/login" or refused is not None:
            who = access.user(request)
            # uploads, identifications, examples, reports and sign-ins start heavy work (or guess a token);
            # publishing to the viewer does not
            heavy = request.method == "POST" and not path.endswith("/viewer")
            wait = limiter.check(who, heavy=heavy)
            if wait is not None:
                return error_response(429, f"Too many requests from {who}: the limit is "
                                           f"{settings.rate_limit_per_minute} per minute "
                                           f"({settings.rate_limit_heavy_per_minute} for uploads and computations). "
                                           f"Try again in {wait} s.", {"Retry-After": str(wait)})
        if refused is not None:
            return refused
        return await call_next(request)

    app.add_middleware(SocketGuard, access=access, per_user=settings.viewer_connections)
    app.add_middleware(UploadLimit, limit=settings.max_upload_bytes)
