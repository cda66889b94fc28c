"""Who may use the app on a network: everyone (the default, for one engineer on 127.0.0.1), the holders of a
shared team token (``ERA_ACCESS_TOKEN``), or the users a reverse proxy has authenticated (``ERA_TRUST_USER_HEADER``,
e.g. X-Forwarded-User; the proxy must strip it from outside requests).

Report links stay readable by whoever has them (the token in the link is the secret): the report page, its JSON
and downloads (its mode shapes are recordings the viewer's client plays at /viser/, with no live connection), the
static files. A browser signs in once at /login (the token goes into an HttpOnly cookie); scripts send
``Authorization: Bearer <token>``. The live viewer (its pages /viser/{key}/ and websockets /viser/{key}) is behind
the same rule (app.middleware.SocketGuard for the websockets, which no HTTP middleware sees), with a cap on the
connections each user holds open.
"""

from __future__ import annotations

import html
import re
import secrets

from fastapi import Request
from fastapi.responses import HTMLResponse, JSONResponse, RedirectResponse, Response
from starlette.requests import HTTPConnection

COOKIE = "era_token"
#: A browser's own random id, set at sign-in beside the token: who the limits count for on a token server.
SESSION = "era_session"
#: Open without signing in (GET only): report and campaign links (a multi-setup test's reports too), the page's
#: assets, the viewer's client for recordings (/viser/ itself: a live key's page, picks and websocket are not),
#: health, sign-in.
_PUBLIC = re.compile(r"^/(r/[^/]+|api/reports/[^/]+(/.*)?|s/[^/]+/r/[^/]+|"
                     r"api/setups/[^/]+/reports/[^/]+(/modes\.(csv|uff))?|c/[^/]+|"
                     r"api/campaigns/(?!folders$)[^/]+(/.*)?|static/.*|"
                     r"vendor/.*|viser/|api/health|login|favicon\.ico)$")


class Access:
    """The access rule of one app: ``check(request)`` is None when the request may go on, else the refusal."""

    def __init__(self, token: str | None, user_header: str | None):
        self.token = token or None
        self.user_header = user_header or None

    @property
    def open(self) -> bool:
        return self.token is None and self.user_header is None

    def allowed(self, request: HTTPConnection) -> bool:
        """The request (or websocket) is let in: the server is open, or it carries the proxy's user / the token."""
        return self.open or self._allowed(request)

    def user(self, request: HTTPConnection) -> str:
        """Who a request's limits count for: the proxy's user when this server trusts one, else the browser's
        session of a token holder (signed in at /login), else the client address (scripts, open servers, and
        every request that is not let in)."""
        if self.user_header and request.headers.get(self.user_header):
            return "user " + request.headers[self.user_header][:100]
        session = request.cookies.get(SESSION, "")
        if self.token and re.fullmatch(r"[A-Za-z0-9_-]{16,64}", session) and self._allowed(request):
            return "session " + session
        return "address " + (request.client.host if request.client else "unknown")

    def _allowed(self, request: HTTPConnection) -> bool:
        if self.user_header and not request.headers.get(self.user_header):
            return False
        if self.token:
            given = request.cookies.get(COOKIE) or ""
            auth = request.headers.get("authorization", "")
            if auth.lower().startswith("bearer "):
                given = auth[7:].strip()
            return secrets.compare_digest(given.encode(), self.token.encode())
        return True

    def check(self, request: Request) -> Response | None:
        path = request.url.path
        public = (request.method in ("GET", "HEAD") and _PUBLIC.match(path)) or path == "/login"
        if self.open or public or self._allowed(request):
            return None
        if self.user_header and not request.headers.get(self.user_header):
            why = (f"This server lets in only users its sign-in proxy vouches for (header {self.user_header}); "
                   "open it through the lab's address, not directly.")
        else:
            why = "This server needs the team's access token: sign in at /login, or send Authorization: Bearer <token>."
        if path.startswith("/api/") or request.method != "GET":
            return JSONResponse({"error": why}, status_code=401)
        return login_page(why, status=401, next_path=path)

    def login(self, given: str, next_path: str) -> Response:
        """POST /login: the token right -> the cookie and back to the page; wrong -> the form again."""
        if not self.token or not secrets.compare_digest(given.encode(), self.token.encode()):
            return login_page("That token is not this server's. Ask the server's administrator for it.", 401,
                              next_path)
        target = next_path if next_path.startswith("/") and not next_path.startswith("//") else "/"
        out = RedirectResponse(target, status_code=303)
        out.set_cookie(COOKIE, self.token, httponly=True, samesite="strict", max_age=30 * 86400)
        out.set_cookie(SESSION, secrets.token_urlsafe(18), httponly=True, samesite="strict", max_age=30 * 86400)
        return out


def login_page(message: str, status: int = 200, next_path: str = "/") -> HTMLResponse:
    return HTMLResponse(
        "<!doctype html><meta charset=utf-8><title>Sign in: ERA modal analysis</title>"
        "<body style='font:15px system-ui;max-width:32em;margin:4em auto'><h1>ERA modal analysis</h1>"
        f"<p>{html.escape(message)}</p><form method=post action='/login'>"
        f"<input type=hidden name=next value='{html.escape(next_path, quote=True)}'>"
        "<label>Team access token <input type=password name=token autofocus required></label> "
        "<button>Sign in</button></form></body>", status_code=status)
