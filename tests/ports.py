"""A free TCP port on 127.0.0.1 for a server a test starts (the app, PostgreSQL, the viewer's test app)."""

import socket


def free_port() -> int:
    """A port no process listens on now (the OS's choice; a server started at once gets it)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]
