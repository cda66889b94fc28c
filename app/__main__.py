"""``python3 -m app``: serve the web app at http://127.0.0.1:8000 (one worker: the viser viewer lives in it).

Environment: ERA_HOST, ERA_PORT, ERA_DATA_DIR and the limits in app/config.py.
"""

import os

import uvicorn


def main() -> None:
    host = os.environ.get("ERA_HOST", "127.0.0.1")
    port = int(os.environ.get("ERA_PORT", "8000"))
    print(f"ERA modal analysis: open http://{host}:{port}/  (Ctrl+C to stop)", flush=True)
    uvicorn.run("app.main:app", host=host, port=port, workers=1, log_level="info")


if __name__ == "__main__":
    main()
