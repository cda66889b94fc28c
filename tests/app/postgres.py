"""A real PostgreSQL server for the tests: Debian's `postgresql` binaries, a cluster in a temporary folder, run as
an unprivileged user (the `postgres` system user when the tests run as root), on a free port of 127.0.0.1 only."""

from __future__ import annotations

import glob
import os
import shutil
import subprocess
from contextlib import contextmanager
from pathlib import Path
from ports import free_port


def _bindir() -> Path:
    found = sorted(glob.glob("/usr/lib/postgresql/*/bin/initdb"))
    if not found:
        raise RuntimeError("PostgreSQL is not installed: .ci/run installs Debian's `postgresql` package "
                           "(apt-get install postgresql).")
    return Path(found[-1]).parent


@contextmanager
def postgres_server(folder: Path):
    """Start a throw-away cluster in ``folder``; yields the SQLAlchemy URL of its database `era_test`."""
    bindir, port = _bindir(), free_port()
    data, sockets = folder / "pgdata", folder / "sockets"
    sockets.mkdir(parents=True)
    as_user: list[str] = []
    if os.geteuid() == 0:  # PostgreSQL refuses to run as root: run it as the package's own unprivileged user
        shutil.chown(folder, "postgres", "postgres")
        shutil.chown(sockets, "postgres", "postgres")
        as_user = ["runuser", "-u", "postgres", "--"]
    run = lambda *cmd: subprocess.run([*as_user, *cmd], check=True, capture_output=True, timeout=120)  # noqa: E731
    run(str(bindir / "initdb"), "-D", str(data), "-U", "era", "-A", "trust", "--no-sync", "-E", "UTF8")
    run(str(bindir / "pg_ctl"), "-D", str(data), "-l", str(folder / "server.log"), "-w", "-o",
        f"-p {port} -k {sockets} -c listen_addresses=127.0.0.1 -c fsync=off", "start")
    try:
        run(str(bindir / "createdb"), "-h", "127.0.0.1", "-p", str(port), "-U", "era", "era_test")
        yield f"postgresql+psycopg://era@127.0.0.1:{port}/era_test"
    finally:
        subprocess.run([*as_user, str(bindir / "pg_ctl"), "-D", str(data), "-m", "immediate", "-w", "stop"],
                       capture_output=True, timeout=120)
