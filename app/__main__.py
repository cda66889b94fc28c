"""``era-app`` / ``python3 -m app``: serve the web app (one worker: the viser viewer lives in it).

Options override the environment (ERA_HOST, ERA_PORT, ERA_DATA_DIR, ERA_DATABASE_URL); the limits are the ERA_* variables of
app/config.py. ``era-app --help`` lists them.
"""

from __future__ import annotations

import argparse
import os

import era


def parse(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="era-app", description=f"ERA modal analysis web app {era.__version__}: upload vibration tests, identify "
        "modes with the Eigensystem Realization Algorithm, share reports.",
        epilog="Limits and other settings: the ERA_* environment variables (see the README's table), e.g. "
               "ERA_MAX_UPLOAD_MB, ERA_MAX_HANKEL_ELEMENTS, ERA_HEAVY_WORKERS, ERA_VIEWER=0.")
    parser.add_argument("--host", default=os.environ.get("ERA_HOST", "127.0.0.1"),
                        help="address to listen on (ERA_HOST; default 127.0.0.1: this machine only)")
    parser.add_argument("--port", type=int, default=int(os.environ.get("ERA_PORT", "8000")),
                        help="port (ERA_PORT; default 8000)")
    parser.add_argument("--data-dir", default=os.environ.get("ERA_DATA_DIR", "data"),
                        help="folder of the database and the stored datasets, analyses and reports (ERA_DATA_DIR; "
                             "default ./data)")
    parser.add_argument("--database-url", default=os.environ.get("ERA_DATABASE_URL"),
                        help="SQLAlchemy URL of the index database, e.g. postgresql+psycopg://era:pw@host/era "
                             "(ERA_DATABASE_URL; default SQLite in the data folder)")
    parser.add_argument("--version", action="version", version=f"era-modal {era.__version__}")
    return parser.parse_args(argv)


def main(argv=None) -> None:
    args = parse(argv)
    os.environ["ERA_DATA_DIR"] = args.data_dir  # read by app.config.from_env when app.main builds the app
    if args.database_url:
        os.environ["ERA_DATABASE_URL"] = args.database_url
    import uvicorn

    print(f"ERA modal analysis {era.__version__}: open http://{args.host}:{args.port}/  (data in "
          f"{os.path.abspath(args.data_dir)}; Ctrl+C to stop)", flush=True)
    uvicorn.run("app.main:app", host=args.host, port=args.port, workers=1, log_level="info")


if __name__ == "__main__":
    main()
