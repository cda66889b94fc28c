"""The mode-shape viewer in a real browser: viser's client over the same-port bridge, pixels of frozen frames,
the animation's frame rate, and a recorded cycle played back with no live session.

Runs tests/e2e/viewer_app.py under uvicorn on a free 127.0.0.1 port and drives Debian's Chromium (never downloaded).
Screenshots go to $VIEWER_SHOTS if set (to look at them), else to pytest's tmp dir.
"""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import numpy as np
import pytest
from ports import free_port

pytestmark = pytest.mark.e2e

CHROMIUM = "/usr/bin/chromium"
HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--enable-unsafe-swiftshader"]

Image = pytest.importorskip("PIL.Image")

# Hide everything in the viewer page but the WebGL canvas (control panel, notifications).
ISOLATE_CANVAS = """() => {
  const canvas = [...document.querySelectorAll('canvas')].sort((a, b) => b.width * b.height - a.width * a.height)[0];
  for (const el of document.body.querySelectorAll('*'))
    if (el !== canvas && !el.contains(canvas)) el.style.visibility = 'hidden';
}"""
SHOW_ALL = "() => { for (const el of document.body.querySelectorAll('*')) el.style.visibility = ''; }"


def get_json(url: str) -> dict:
    with urllib.request.urlopen(url, timeout=10) as r:
        return json.load(r)


def post_json(url: str, body: dict) -> dict:
    req = urllib.request.Request(url, data=json.dumps(body).encode(), headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=10) as r:
        return json.load(r)


@pytest.fixture(scope="module")
def base(tmp_path_factory):
    port = free_port()
    log = tmp_path_factory.mktemp("viewer") / "uvicorn.log"
    env = dict(os.environ, PYTHONPATH=str(REPO))
    with open(log, "wb") as out:
        proc = subprocess.Popen([sys.executable, "-m", "uvicorn", "viewer_app:app", "--app-dir", str(HERE),
                                 "--host", "127.0.0.1", "--port", str(port), "--workers", "1"],
                                cwd=REPO, env=env, stdout=out, stderr=subprocess.STDOUT)
    url = f"http://127.0.0.1:{port}"
    try:
        for _ in range(120):
            try:
                get_json(url + "/test/key")
                break
            except OSError:
                if proc.poll() is not None:
                    pytest.fail(f"the test app did not start:\n{log.read_text()}")
                time.sleep(0.25)
        else:
            pytest.fail(f"the test app did not answer within 30 s:\n{log.read_text()}")
        yield url
    finally:
        proc.terminate()
        proc.wait(timeout=10)


@pytest.fixture(scope="module")
def browser(playwright):
    """A Chromium of this module's own: WebGL drawn in software (swiftshader) for the scene's pixels."""
    b = playwright.chromium.launch(executable_path=CHROMIUM, args=ARGS)
    yield b
    b.close()


@pytest.fixture(scope="module")
def shots(tmp_path_factory) -> Path:
    folder = Path(os.environ["VIEWER_SHOTS"]) if os.environ.get("VIEWER_SHOTS") else tmp_path_factory.mktemp("shots")
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def canvas_pixels(page, path: Path) -> np.ndarray:
    """The viewer iframe's pixels (after ISOLATE_CANVAS: just the scene). A page screenshot clipped to the iframe
    takes a fraction of a second; an element screenshot of a live WebGL canvas takes seconds in software."""
    png = page.screenshot(path=str(path), clip=page.locator("#viewer").bounding_box())
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)


def drawn(img: np.ndarray) -> np.ndarray:
    """Mask of saturated pixels: the coloured trace lines and sensors (background white, undeformed lines grey)."""
    return (img.max(axis=-1) - img.min(axis=-1)) > 60


def red(img: np.ndarray) -> np.ndarray:
    """Mask of the colour scale's top end: nodes at their largest excursion."""
    return (img[..., 0] > 170) & (img[..., 1] < 90) & (img[..., 2] < 90)


def warm(img: np.ndarray) -> np.ndarray:
    """Mask of the colour scale's upper half (yellow to red): nodes far from rest."""
    return drawn(img) & (img[..., 0] > 150) & (img[..., 0] > img[..., 2] + 60)


def test_live_viewer_draws_the_selected_mode_displaced(base, browser, shots):
    info = get_json(base + "/test/key")
    mode_url = f"{base}/viser/{info['key']}/mode"
    post_json(mode_url, {"index": 0, "amplitude": 0.15, "speed": 0.5})
    page = browser.new_page(viewport={"width": 1000, "height": 700})
    page.goto(base + "/test/page")                           # the app's page with the viewer in an <iframe>
    viewer = page.frame_locator("#viewer")
    viewer.get_by_text("Connected").wait_for(timeout=30_000)
    expand = viewer.locator("[aria-label='Expand panel']")
    expand.wait_for()
    assert not viewer.get_by_text("Amplitude").is_visible()  # the panel starts minimized, the structure uncovered
    expand.click()                                            # its + opens it
    viewer.get_by_text("Amplitude").wait_for()
    assert viewer.get_by_text("Share").count() == 0
    assert get_json(base + "/test/key")["sessions"] == 1
    before = get_json(base + "/test/key")["frames_sent"]
    time.sleep(2.0)
    assert get_json(base + "/test/key")["frames_sent"] - before >= 15      # animating (30 frames/s nominal; a loaded
    #                                                                        machine sends fewer, never none)
    page.screenshot(path=str(shots / "live_page.png"))

    # The viewer's own controls and the POST route drive the same state, both ways.
    post_json(mode_url, {"index": 0, "speed": 0})
    viewer.get_by_role("combobox", name="Mode").click()
    viewer.get_by_role("option", name="Mode 2 · 21.7 Hz").click()
    for _ in range(40):
        if get_json(base + "/test/key")["index"] == 1:
            break
        time.sleep(0.1)
    assert get_json(base + "/test/key")["index"] == 1
    post_json(mode_url, {"index": 2})
    viewer.locator("input[type=hidden][value='Mode 3 · 33.3 Hz']").wait_for(state="attached", timeout=5_000)

    page.frame(url=lambda u: "/viser/" in u).evaluate(ISOLATE_CANVAS)

    def frozen(name: str, **choice) -> np.ndarray:
        """Freeze a view and return its pixels once two screenshots in a row agree (the client has drawn it)."""
        post_json(mode_url, {"speed": 0, "phase_deg": 0, "interpolate": False, **choice})
        time.sleep(0.5)
        previous = canvas_pixels(page, shots / f"{name}.png")
        for _ in range(10):
            time.sleep(0.3)
            img = canvas_pixels(page, shots / f"{name}.png")
            if (np.abs(img - previous).sum(axis=-1) > 60).sum() < 20:
                return img
            previous = img
        pytest.fail(f"the {name} view did not settle")

    flat = frozen("still", index=0, amplitude=0.5, phase_deg=90)   # a real mode passes zero a quarter cycle on
    bend = frozen("bending_sensors_only", index=0, amplitude=0.5, interpolate=False)
    twist = frozen("torsion_sensors_only", index=1, amplitude=0.5, interpolate=False)
    plate = frozen("bending_interpolated", index=0, amplitude=0.5, interpolate=True)

    # Undisplaced: the grid is drawn, every node still (blue), nothing at the top of the colour scale.
    # (At amplitude 0 the colours would still show |ψ|: colour is relative to the mode's own peak.)
    ys, xs = np.nonzero(drawn(flat))
    assert drawn(flat).sum() > 2000 and red(flat).sum() == 0
    left, right = xs.min(), xs.max()
    third = (right - left) / 3

    # Bending frozen at its peak: pixels change, the structure grows upwards, the red peak is mid-span.
    assert (np.abs(bend - flat).sum(axis=-1) > 60).sum() > 1000
    assert np.nonzero(drawn(bend))[0].min() < ys.min() - 30
    ry, rx = np.nonzero(red(bend))
    assert rx.size > 30 and left + third < rx.mean() < right - third

    # Torsion: the two red peaks sit at the ends (x = 1 and 9 ft), nothing red mid-span.
    tx = np.nonzero(red(twist))[1]
    assert (tx < left + third).sum() > 10 and (tx > right - third).sum() > 10
    assert ((tx > left + third) & (tx < right - third)).sum() == 0

    # Interpolated: the unmeasured nodes move too, so many more trace-line pixels are warm than with sensors only.
    assert warm(plate).sum() > 3 * warm(bend).sum() > 0
    page.close()


def test_bridge_streams_about_thirty_frames_per_second(base):
    """Frame rate as a browser sees it: a websocket client through the bridge counts line updates for 3 s."""
    msgspec = pytest.importorskip("msgspec")
    zstandard = pytest.importorskip("zstandard")
    from websockets.sync.client import connect

    info = get_json(base + "/test/key")
    post_json(f"{base}/viser/{info['key']}/mode", {"index": 0, "amplitude": 0.2, "speed": 0.5})
    camera = {"type": "ViewerCameraMessage", "wxyz": [1.0, 0.0, 0.0, 0.0], "position": [0.0, 0.0, 5.0],
              "fov": 1.0, "near": 0.01, "far": 100.0, "image_height": 500, "image_width": 800,
              "look_at": [0.0, 0.0, 0.0], "up_direction": [0.0, 0.0, 1.0]}
    unzip = zstandard.ZstdDecompressor()
    times = []
    ws_url = base.replace("http://", "ws://") + f"/viser/{info['key']}"
    with connect(ws_url, subprotocols=["viser-v1.1.1"], max_size=None) as ws:
        ws.send(msgspec.msgpack.encode(camera))              # viser counts a client as connected after its camera
        start = time.monotonic()
        while time.monotonic() - start < 4.0:
            raw = ws.recv(timeout=5)
            size, packed = int.from_bytes(raw[:8], "little"), int.from_bytes(raw[8:16], "little")
            batch = msgspec.msgpack.decode(unzip.decompress(raw[16:16 + packed], max_output_size=size))
            now = time.monotonic()
            times += [now for m in batch["messages"]
                      if m.get("name") == "/mode/lines" and "points" in m.get("updates", {})]
    steady = [t for t in times if t - start > 1.0]
    fps = (len(steady) - 1) / (steady[-1] - steady[0])
    print(f"line updates received through the bridge: {fps:.1f} frames/s")
    assert fps > 15                                          # nominal 30; generous for a loaded 2-core CI machine


def test_recorded_cycle_plays_back_without_a_live_session(base, browser, shots):
    page = browser.new_page(viewport={"width": 1000, "height": 700})
    sockets = []
    page.on("websocket", lambda ws: sockets.append(ws.url))
    loaded = []
    page.on("console", lambda m: loaded.append(m.text) if "File loaded" in m.text else None)
    page.goto(base + "/test/playback")
    viewer = page.frame_locator("#viewer")
    for _ in range(120):
        if loaded:
            break
        page.wait_for_timeout(250)
    assert loaded and "1.1.1" in loaded[0]                   # "File loaded! Saved with Viser version: 1.1.1"
    page.wait_for_timeout(1000)
    page.screenshot(path=str(shots / "playback_page.png"))
    # Pause at chosen times through the player's time field: the 2 s cycle starts at the bending peak (t = 0), is at
    # rest a quarter cycle on (t = 0.5 s) and at the opposite peak half a cycle on (t = 1 s).
    player = page.frame(url=lambda u: "/viser/" in u)
    time_field = viewer.locator("input[inputmode=decimal]").first
    images = {}
    # At most four times asked for: on a loaded machine the player has once shown the same frame for two of them
    # (seen in CI); two frames that differ are what this test needs, wherever in the cycle they fall.
    for t in ("0.5", "1", "0.25", "1.5"):
        player.evaluate(SHOW_ALL)
        time_field.fill(t)
        time_field.press("Enter")
        page.wait_for_timeout(800)
        player.evaluate(ISOLATE_CANVAS)
        page.wait_for_timeout(200)
        images[t] = canvas_pixels(page, shots / f"playback_t{t}.png")
        shown = list(images.values())
        if len(shown) >= 2 and max((np.abs(a.astype(int) - shown[-1].astype(int)).sum(axis=-1) > 60).sum()
                                   for a in shown[:-1]) > 1000:
            break
    shown = list(images.values())
    assert all(drawn(img).sum() > 2000 for img in shown)                # the grid is there
    # On a loaded machine the player may not sit exactly on the time asked for (seen in CI: at t = 0.5 s it showed
    # the upward bend), so check that it animates the mode: a clearly displaced frame with red mid-span, and two
    # different deformations among the times asked for.
    displaced = max(shown, key=lambda img: warm(img).sum())
    assert warm(displaced).sum() > 1000 and red(displaced).sum() > 10
    assert max((np.abs(a.astype(int) - b.astype(int)).sum(axis=-1) > 60).sum()
               for i, a in enumerate(shown) for b in shown[i + 1:]) > 1000
    assert sockets == []                                     # no live session behind it
    page.close()


def test_standalone_report_file_plays_with_no_server(base, browser, shots, tmp_path):
    """The self-contained HTML (for downloaded reports) opened from a file: no HTTP, no websocket."""
    with urllib.request.urlopen(base + "/test/standalone", timeout=30) as r:
        path = tmp_path / "mode2.html"
        path.write_bytes(r.read())
    page = browser.new_page(viewport={"width": 800, "height": 500})
    requests = []
    page.on("request", lambda req: requests.append(req.url) if not req.url.startswith(("file:", "data:", "blob:"))
            else None)
    page.goto(path.as_uri())
    for _ in range(20):  # the player draws within ~2 s; a loaded machine gets up to 20 s
        page.wait_for_timeout(1000)
        page.evaluate(ISOLATE_CANVAS)
        png = page.screenshot(path=str(shots / "standalone.png"))
        img = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
        if drawn(img).sum() > 2000:
            break
    assert drawn(img).sum() > 2000 and requests == []
    page.close()


def test_viewer_page_fetches_nothing_from_another_origin(base, browser):
    """A crafted ?playbackPath= pointing elsewhere is blocked by the page's Content-Security-Policy."""
    page = browser.new_page()
    blocked = []
    page.on("console", lambda m: blocked.append(m.text) if "Content Security Policy" in m.text else None)
    elsewhere = base.replace("127.0.0.1", "localhost") + "/test/mode1.viser"     # same server, another origin
    page.goto(base + "/viser/?playbackPath=" + elsewhere)
    for _ in range(40):
        if blocked:
            break
        page.wait_for_timeout(250)
    assert blocked and "connect-src" in blocked[0]
    page.close()
