"""The live viewer behind the access rule (issue 29): on a token server a websocket to /viser/{key} without the
token is refused before it is accepted, the key's page and picks need the token, the recordings' player stays
open for report links; and each user holds at most ERA_VIEWER_CONNECTIONS viewer sockets open."""

from __future__ import annotations

import time
from contextlib import ExitStack

import pytest
from starlette.websockets import WebSocketDisconnect

from apiclient import client

TOKEN = "team-secret-token"
PROTOCOL = ["viser-v1.1.1"]


def published(c, headers: dict) -> str:
    ds = c.post("/api/examples/case1", headers=headers).json()["id"]
    a = c.post("/api/analyses", json={"dataset_id": ds, "rows": 20, "cols": 20}, headers=headers).json()["id"]
    r = c.post(f"/api/analyses/{a}/viewer", json={"order": 4}, headers=headers)
    assert r.status_code == 200, r.text
    return r.json()["key"]


def leave(*sockets) -> None:
    """Close from the browser's side and let the bridge return before the test client cancels what still runs."""
    for ws in sockets:
        ws.close()
    time.sleep(0.3)


def refused(c, path: str, headers: dict | None = None) -> WebSocketDisconnect:
    with pytest.raises(WebSocketDisconnect) as closed:
        with c.websocket_connect(path, subprotocols=PROTOCOL, headers=headers or {}) as ws:
            ws.receive_bytes()
    return closed.value


def test_the_viewer_socket_needs_the_token_and_each_user_holds_a_few(tmp_path):
    bearer = {"Authorization": f"Bearer {TOKEN}"}
    with client(tmp_path, viewer=True, access_token=TOKEN, viewer_connections=2) as c:
        key = published(c, bearer)
        assert refused(c, f"/viser/{key}").code == 1008                      # no token: never accepted
        assert refused(c, f"/viser/{key}", {"Authorization": "Bearer wrong"}).code == 1008
        assert c.get(f"/viser/{key}/").status_code == 401
        assert c.get(f"/viser/{key}/picks").status_code == 401
        assert c.get("/viser/").status_code == 200                            # the report's recordings player
        assert c.get(f"/viser/{key}/", headers=bearer).status_code == 200
        with ExitStack() as held:
            sockets = [held.enter_context(c.websocket_connect(f"/viser/{key}", subprotocols=PROTOCOL,
                                                              headers=bearer)) for _ in range(2)]
            assert all(len(ws.receive_bytes()) > 16 for ws in sockets)       # viser's scene arrives
            over = refused(c, f"/viser/{key}", bearer)
            assert over.code == 1013 and "ERA_VIEWER_CONNECTIONS" in over.reason
            leave(*sockets)
        with c.websocket_connect(f"/viser/{key}", subprotocols=PROTOCOL, headers=bearer) as ws:  # room again
            assert len(ws.receive_bytes()) > 16
            leave(ws)


def test_behind_the_sign_in_proxy_the_cap_is_per_user(tmp_path):
    with client(tmp_path, viewer=True, trust_user_header="X-Forwarded-User", viewer_connections=1) as c:
        ana, bob = {"X-Forwarded-User": "ana"}, {"X-Forwarded-User": "bob"}
        key = published(c, ana)
        assert refused(c, f"/viser/{key}").code == 1008                      # not through the proxy
        with c.websocket_connect(f"/viser/{key}", subprotocols=PROTOCOL, headers=ana) as ws:
            assert len(ws.receive_bytes()) > 16
            assert refused(c, f"/viser/{key}", ana).code == 1013
            with c.websocket_connect(f"/viser/{key}", subprotocols=PROTOCOL, headers=bob) as other:
                assert len(other.receive_bytes()) > 16                         # another user, from the same address
                leave(other)
            leave(ws)
