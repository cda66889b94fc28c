"""The mode-shape viewer without a browser: drawing rules, keys and view state, recordings, routes and the bridge."""

from __future__ import annotations

import base64
import time

import numpy as np
import pytest

import msgspec  # viser's dependencies: the .viser format is zstd-compressed msgpack
import zstandard
from fastapi import FastAPI
from fastapi.testclient import TestClient
from starlette.websockets import WebSocketDisconnect

from app.viewer import ModeViewer, scene
from app.viewer.registry import Registry, ViewState, updated_state
from era.errors import DataError
from era.core.geometry import Geometry

SENSORS = [(x, y) for y in (1, 4, 6) for x in (1, 5, 9)]


def grid(sensors=SENSORS) -> Geometry:
    """11 × 8 joints 1 ft apart, bars between neighbours, sensors measuring +z."""
    xy = np.array([(x, y) for y in range(8) for x in range(11)], dtype=float)
    node = {(int(x), int(y)): k for k, (x, y) in enumerate(xy)}
    edges = [(node[x, y], node[x + 1, y]) for y in range(8) for x in range(10)]
    edges += [(node[x, y], node[x, y + 1]) for y in range(7) for x in range(11)]
    return Geometry(node_ids=np.arange(1, 89), coordinates=np.column_stack([xy, np.zeros(88)]),
                    edges=np.array(edges), channel_nodes=np.array([node[s] for s in sensors]),
                    channel_directions=np.tile([0.0, 0.0, 1.0], (len(sensors), 1)), units="ft")


def bending() -> np.ndarray:
    x, y = np.array(SENSORS, dtype=float).T
    return np.sin(np.pi * x / 10) * np.sin(np.pi * y / 7)


def decode_viser(data: bytes) -> dict:
    """Inverse of viser's StateSerializer.serialize: [u64 size][zstd([u64 len][msgpack][buffers])]."""
    size = int.from_bytes(data[:8], "little")
    inner = zstandard.ZstdDecompressor().decompress(data[8:], max_output_size=size)
    length = int.from_bytes(inner[:8], "little")
    return msgspec.msgpack.decode(inner[8:8 + length])


# ---- drawing rules ---------------------------------------------------------------------------------------------

def test_only_sensor_nodes_move_along_their_direction_by_amplitude_times_size():
    g = grid()
    psi = bending() * 2.0                                    # any scale: the viewer normalises to max |ψ| = 1
    vectors = scene.node_modal_vectors(g, psi)
    f = scene.frame(g, vectors, phase=0.0, amplitude=0.2)
    moved = np.flatnonzero(np.abs(f.positions - g.coordinates).sum(axis=1) > 0)
    assert set(moved) == set(g.channel_nodes)                # 79 unmeasured nodes stay put
    expected_z = 0.2 * 10.0 * psi / np.abs(psi).max()          # structure size: 10 ft (largest side)
    np.testing.assert_allclose(f.positions[g.channel_nodes, 2], expected_z)
    np.testing.assert_allclose(f.positions[g.channel_nodes, :2], g.coordinates[g.channel_nodes, :2])


def test_segments_follow_the_trace_lines_and_sensors_are_points():
    g = grid()
    f = scene.frame(g, scene.node_modal_vectors(g, bending()), phase=0.1, amplitude=0.3)
    assert f.segments.shape == (157, 2, 3) and f.segment_colours.shape == (157, 2, 3)
    np.testing.assert_allclose(f.segments, f.positions[g.edges], rtol=1e-6)
    assert f.segment_colours.dtype == np.uint8
    assert f.sensor_points.shape == (9, 3) and f.sensor_colours.shape == (9, 3)


def test_colour_is_displacement_over_the_largest_peak():
    g = grid()
    psi = bending()
    vectors = scene.node_modal_vectors(g, psi)
    f = scene.frame(g, vectors, phase=0.0, amplitude=0.1)
    peak = g.channel_nodes[np.argmax(np.abs(psi))]
    assert f.level[peak] == pytest.approx(1.0)
    assert tuple(scene.colours(f.level)[peak]) == (210, 20, 20)            # red: largest excursion
    still = np.setdiff1d(np.arange(88), g.channel_nodes)
    assert np.all(f.level[still] == 0) and tuple(scene.colours(0.0)) == (20, 70, 200)   # blue: still
    np.testing.assert_allclose(f.level[g.channel_nodes], np.abs(psi) / np.abs(psi).max())
    # a real mode passes through zero a quarter cycle later: everything still and blue
    quarter = scene.frame(g, vectors, phase=0.25, amplitude=0.1)
    np.testing.assert_allclose(quarter.positions, g.coordinates, atol=1e-12)
    np.testing.assert_allclose(quarter.level, 0.0, atol=1e-12)


def test_complex_mode_moves_its_imaginary_part_a_quarter_cycle_later():
    g = grid()
    psi = bending() + 0.5j * bending()[::-1]
    vectors = scene.node_modal_vectors(g, psi)
    quarter = scene.frame(g, vectors, phase=0.25, amplitude=0.1)
    np.testing.assert_allclose(quarter.positions[g.channel_nodes, 2], -1.0 * (psi.imag / np.abs(psi).max()),
                               atol=1e-12)


def test_colour_scale_is_clipped_and_interpolated_between_stops():
    rgb = scene.colours(np.array([-1.0, 0.0, 0.125, 0.5, 1.0, 3.0]))
    assert rgb.shape == (6, 3)
    np.testing.assert_array_equal(rgb[0], rgb[1])
    np.testing.assert_array_equal(rgb[4], rgb[5])
    np.testing.assert_array_equal(rgb[2], [10, 110, 185])                   # halfway between the first two stops
    np.testing.assert_array_equal(rgb[3], [60, 160, 40])


def test_spline_passes_through_the_sensors_and_reproduces_a_tilted_plane():
    g = grid()
    x, y = np.array(SENSORS, dtype=float).T
    tilt = 0.2 + 0.05 * x - 0.1 * y                          # a rigid tilt: the spline's linear part is exact
    vectors = scene.node_modal_vectors(g, tilt, interpolate=True)
    everywhere = (0.2 + 0.05 * g.coordinates[:, 0] - 0.1 * g.coordinates[:, 1]) / np.abs(tilt).max()
    np.testing.assert_allclose(vectors[:, 2].real, everywhere, atol=1e-9)
    np.testing.assert_allclose(vectors[:, :2], 0.0, atol=1e-9)
    bent = scene.node_modal_vectors(g, bending() + 0.3j * tilt, interpolate=True)
    measured = scene.node_modal_vectors(g, bending() + 0.3j * tilt)
    np.testing.assert_allclose(bent[g.channel_nodes], measured[g.channel_nodes], atol=1e-9)
    middle = 3 * 11 + 5                                      # node (5, 3), between sensors (5, 1) and (5, 4)
    assert 0.5 < bent[middle, 2].real < 1.0


def test_spline_works_for_sensors_on_a_line():
    g = Geometry(node_ids=range(1, 6), coordinates=[[k, 0, 0] for k in range(5)], edges=[[k, k + 1] for k in range(4)],
                 channel_nodes=[0, 2, 4], channel_directions=[[0, 0, 1]] * 3)
    vectors = scene.node_modal_vectors(g, np.array([0.0, 1.0, 2.0]), interpolate=True)
    np.testing.assert_allclose(vectors[:, 2].real, [0, 0.25, 0.5, 0.75, 1.0], atol=1e-9)


def test_sensors_on_one_spot_leave_the_other_nodes_still():
    g = Geometry(node_ids=[1, 2, 3], coordinates=[[0, 0, 0], [0, 0, 0], [1, 0, 0]], edges=[[0, 2], [1, 2]],
                 channel_nodes=[0, 1], channel_directions=[[0, 0, 1]] * 2)
    vectors = scene.node_modal_vectors(g, np.array([1.0, 0.5]), interpolate=True)
    np.testing.assert_allclose(vectors[:, 2], [1.0, 0.5, 0.0])


def test_channels_on_one_node_add_up():
    g = Geometry(node_ids=[1, 2], coordinates=[[0, 0, 0], [2, 0, 0]], edges=[[0, 1]], channel_nodes=[1, 1],
                 channel_directions=[[1, 0, 0], [0, 0, 1]])
    f = scene.frame(g, scene.node_modal_vectors(g, np.array([0.5, 1.0])), phase=0.0, amplitude=0.5)
    np.testing.assert_allclose(f.positions[1], [2 + 0.5, 0, 1.0])         # size 2 → 1 unit for |ψ| = 1
    np.testing.assert_allclose(f.positions[0], [0, 0, 0])


def test_default_geometry_puts_the_sensors_in_a_row_measuring_z():
    g = scene.default_geometry(4)
    np.testing.assert_array_equal(g.coordinates[:, 0], [0, 1, 2, 3])
    np.testing.assert_array_equal(g.edges, [[0, 1], [1, 2], [2, 3]])
    np.testing.assert_array_equal(g.channel_nodes, [0, 1, 2, 3])
    np.testing.assert_array_equal(g.channel_directions[:, 2], 1.0)
    one = scene.frame(scene.default_geometry(1), np.array([[0, 0, 1j]]), phase=0.0, amplitude=0.2)
    assert one.segments.shape == (0, 2, 3) and one.sensor_points.shape == (1, 3)
    # the stand-in is said under it (a lone dot says nothing by itself); a real geometry is not annotated
    assert "the one sensor drawn as a point moving up and down" in scene.stand_in_note(scene.default_geometry(1))
    assert "give each point's coordinates and direction" in scene.stand_in_note(g)  # and says what to give
    assert "the 4 sensors in a row, in channel order" in scene.stand_in_note(g)
    assert scene.stand_in_note(grid()) is None


def test_a_geometry_without_placed_channels_falls_back_and_unknown_directions_measure_z():
    g = grid()
    unplaced = Geometry(node_ids=g.node_ids, coordinates=g.coordinates, edges=g.edges,
                        channel_nodes=np.full(9, -1), channel_directions=np.zeros((9, 3)))
    assert scene.geometry_for(unplaced, 9).units == "channel" and scene.geometry_for(None, 4).n_nodes == 4
    undirected = Geometry(node_ids=g.node_ids, coordinates=g.coordinates, edges=g.edges,
                          channel_nodes=g.channel_nodes, channel_directions=np.zeros((9, 3)))
    drawn = scene.geometry_for(undirected, 9)
    assert drawn.n_nodes == 88 and np.all(drawn.channel_directions == [0, 0, 1])
    assert scene.geometry_for(g, 9) is g


def test_mismatched_modes_are_refused_with_a_message():
    g = grid()
    with pytest.raises(DataError, match="8 rows but the geometry places 9 channels"):
        scene.check_modes(g, [1.0], np.ones((8, 1)))
    with pytest.raises(DataError, match="2 mode shapes but 1 frequencies"):
        scene.check_modes(g, [1.0], np.ones((9, 2)))
    with pytest.raises(DataError, match="NaN"):
        scene.check_modes(g, [np.nan], np.ones((9, 1)))
    with pytest.raises(DataError, match="at least one mode"):
        scene.check_modes(g, [], np.ones((9, 0)))


def test_labels_default_to_frequency_and_are_made_unique():
    assert scene.mode_labels(np.array([1.5, 20.25])) == ["Mode 1 · 1.5 Hz", "Mode 2 · 20.25 Hz"]
    assert scene.mode_labels(np.array([1.0, 2.0]), ["a", "a"]) == ["1. a", "2. a"]
    with pytest.raises(DataError, match="one label per mode"):
        scene.mode_labels(np.array([1.0]), ["a", "b"])


@pytest.mark.parametrize("aspect", [1.3, 0.6])
def test_camera_frames_the_structure_from_above_filling_four_fifths_of_the_view(aspect):
    """The grid filled about half the canvas' width (the camera 1.3 sizes away from its centre): now its nodes
    span 80 % of the view's width or height, whichever is reached first, centred; a tower (tall, narrow) too."""
    tower = Geometry(node_ids=np.arange(1, 9), coordinates=np.array(
        [(x, y, z) for z in (0.0, 12.0) for x in (0.0, 2.0) for y in (0.0, 1.5)]), edges=np.array([[0, 4], [3, 7]]),
        channel_nodes=np.array([4]), channel_directions=np.array([[1.0, 0.0, 0.0]]), units="m")
    for geometry in (grid(), tower):
        position, look_at = scene.camera_pose(geometry, aspect=aspect)
        x, y = scene.project(position, look_at, geometry.coordinates, aspect=aspect)
        half = max(np.ptp(x), np.ptp(y)) / 2
        assert half == pytest.approx(scene.FRAME_FILL, abs=0.01), (x, y)
        assert abs(x.max() + x.min()) < 0.02 and abs(y.max() + y.min()) < 0.02  # centred
        assert np.abs(x).max() < 0.82 and np.abs(y).max() < 0.82  # nothing cut
        assert position[2] > geometry.coordinates[:, 2].max()  # from above
    old_x, _ = scene.project(np.array([5.0, 3.5, 0.0]) + 10 * np.array([0.45, -0.95, 0.75]), np.array([5.0, 3.5, 0.0]),
                             grid().coordinates)
    assert np.ptp(old_x) / 2 < 0.5  # the former pose: half the width


def test_a_mode_at_the_sliders_full_swing_stays_in_view():
    """Framed at rest only, the grid's first bending at amplitude 0.5 left the view (its peak at 3.3 view
    half-heights); framed with the motion, every node at every instant of the cycle is inside, and the structure
    still fills more of the width than the former pose's half."""
    from app.viewer.registry import MAX_AMPLITUDE
    geometry = grid()
    xyz = geometry.coordinates
    bending = np.zeros((geometry.n_nodes, 3), complex)
    bending[:, 2] = np.sin(np.pi * (xyz[:, 0] - xyz[:, 0].min()) / np.ptp(xyz[:, 0]))   # up at mid-span
    size = scene.structure_size(geometry)
    for motions, amplitude, inside in (((), 0.0, False), ([bending], MAX_AMPLITUDE, True)):
        position, look_at = scene.camera_pose(geometry, motions, amplitude)
        swung = [xyz + sign * MAX_AMPLITUDE * size * np.real(bending) for sign in (1, -1)]
        peak = max(np.abs(scene.project(position, look_at, nodes)[1]).max() for nodes in swung)
        assert (peak <= scene.FRAME_FILL + 1e-6) == inside, peak
        x, _ = scene.project(position, look_at, xyz)
    assert np.ptp(x) / 2 > 0.5


def test_a_single_point_is_seen_from_a_little_over_its_unit_size():
    point = Geometry(node_ids=np.array([1]), coordinates=np.zeros((1, 3)), edges=np.zeros((0, 2), int),
                     channel_nodes=np.array([0]), channel_directions=np.array([[0.0, 0.0, 1.0]]), units="m")
    position, look_at = scene.camera_pose(point)
    np.testing.assert_allclose(look_at, 0.0)
    assert np.linalg.norm(position - look_at) == pytest.approx(1.3)


# ---- keys and view state ---------------------------------------------------------------------------------------

def test_keys_are_random_url_safe_and_at_least_128_bits():
    reg = Registry()
    keys = {reg.publish(grid(), [1.0], bending()[:, None]) for _ in range(50)}
    assert len(keys) == 50
    for key in keys:
        assert len(key) >= 22 and all(c.isalnum() or c in "-_" for c in key)


def test_registry_drops_the_least_recently_used_key_beyond_capacity():
    reg = Registry(capacity=2)
    a, b = (reg.publish(None, [1.0], [[1.0], [0.5]]) for _ in range(2))
    assert reg.get(a) is not None                         # a is now the most recently used
    c = reg.publish(None, [1.0], [[1.0], [0.5]])
    assert a in reg and c in reg and b not in reg and len(reg) == 2


def test_publish_without_geometry_uses_the_row_of_sensors():
    reg = Registry()
    key = reg.publish(None, [3.0, 7.0], np.ones((5, 2)), ["first", "second"])
    entry = reg.get(key)
    assert entry.geometry.n_nodes == 5 and entry.labels == ["first", "second"] and entry.n_modes == 2


def test_view_state_changes_are_validated():
    s = ViewState(index=0, amplitude=0.1, speed=0.5, phase=0.3)
    assert updated_state(s, 3, index=0).phase == 0.3                       # same mode keeps its phase
    assert updated_state(s, 3, index=2) == ViewState(2, 0.1, 0.5, 0.0)     # another mode starts its cycle
    assert updated_state(s, 3, speed=0, phase_deg=450).phase == pytest.approx(0.25)
    with pytest.raises(ValueError, match="choose 0 to 2"):
        updated_state(s, 3, index=3)
    with pytest.raises(ValueError, match="Amplitude"):
        updated_state(s, 3, amplitude=0.9)
    with pytest.raises(ValueError, match="Speed"):
        updated_state(s, 3, speed=-1)


def test_animation_advances_the_phase_by_speed_and_freezes_at_zero():
    reg = Registry()
    key = reg.publish(grid(), [1.0], bending()[:, None])
    reg.set_state(key, speed=0.5)
    state, revision = reg.advance(key, 0.5)
    assert state.phase == pytest.approx(0.25) and revision == 1
    assert reg.advance(key, 1.6)[0].phase == pytest.approx(0.05)            # wraps after a full cycle
    reg.set_state(key, speed=0.0, phase_deg=90)
    state, revision = reg.advance(key, 10.0)
    assert state.phase == pytest.approx(0.25) and revision == 2             # ticks are not revisions
    assert reg.advance("no-such-key", 0.1) is None


# ---- recordings and URLs ---------------------------------------------------------------------------------------

def test_record_is_one_cycle_in_the_viser_format():
    viewer = ModeViewer()
    data = viewer.record(grid(), [10.0, 20.0], np.column_stack([bending(), -bending()]), 1, frames=12,
                         period_s=1.5)
    rec = decode_viser(data)
    assert rec["viserVersion"] == "1.1.1"
    assert rec["durationSeconds"] == pytest.approx(1.5)
    times = [t for t, _ in rec["messages"]]
    assert times == sorted(times) and max(times) == pytest.approx(1.5 * 11 / 12)
    kinds = {m["type"] for _, m in rec["messages"]}
    assert {"LineSegmentsMessage", "PointCloudMessage", "LabelMessage"} <= kinds
    # every frame after the first updates the moving lines
    assert len({t for t, m in rec["messages"] if t > 0}) == 11
    labels = [m for _, m in rec["messages"] if m["type"] == "LabelMessage"]
    assert len(labels) == 1  # the title; a real geometry needs no note
    alone = decode_viser(viewer.record(None, [6.6], np.ones((1, 1)), 0, frames=2))  # one sensor, no geometry
    said = [str(m) for _, m in alone["messages"] if m["type"] == "LabelMessage"]
    assert len(said) == 2 and any("No geometry in the file: the one sensor" in t for t in said)


def test_shells_are_recorded_as_a_surface_that_moves_with_the_nodes():
    """A plate of 2 × 1 quads as four triangles (scene.SurfaceGeometry): a mesh message with its faces, then
    each frame moves its vertices with the nodes (the left edge held, the right one bending)."""
    xyz = np.array([(x, y, 0.0) for y in (0, 1) for x in (0, 1, 2)], dtype=float)
    faces = [[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]]
    geometry = scene.SurfaceGeometry(node_ids=np.arange(1, 7), coordinates=xyz, edges=[[0, 1], [1, 2]],
                                     channel_nodes=np.arange(6), channel_directions=np.tile([0, 0, 1.0], (6, 1)),
                                     faces=faces)
    with pytest.raises(DataError, match="face refers to a node"):
        scene.SurfaceGeometry(node_ids=[1, 2, 3], coordinates=xyz[:3], edges=[], channel_nodes=[],
                              channel_directions=np.zeros((0, 3)), faces=[[0, 1, 3]])
    shape = np.array([0.0, 0.4, 1.0, 0.0, 0.4, 1.0])
    assert scene.faces_of(geometry).tolist() == faces and scene.faces_of(grid()).shape == (0, 3)
    drawn = scene.frame(geometry, scene.node_modal_vectors(geometry, shape), 0.0, 0.25)
    np.testing.assert_allclose(drawn.positions[:, 2], 0.25 * 2.0 * shape)       # amplitude × size × shape
    rec = decode_viser(ModeViewer().record(geometry, [5.0], shape[:, None], 0, frames=4, amplitude=0.25))
    meshes = [m for _, m in rec["messages"] if m["type"] == "MeshMessage"]
    assert [m["name"] for m in meshes] == ["/mode/surface"] and meshes[0]["props"]["side"] == "double"
    moved = [t for t, m in rec["messages"] if m["type"] == "SceneNodeUpdateMessage"
             and m["name"] == "/mode/surface" and "vertices" in m["updates"]]
    assert len(moved) == 3 and moved == sorted(moved) and moved[0] > 0       # one per later frame
    assert not [m for _, m in decode_viser(ModeViewer().record(grid(), [10.0], bending()[:, None], 0, frames=2))[
        "messages"] if m["type"] == "MeshMessage"]                             # trace lines only: no surface


def test_standalone_html_inlines_the_recording_into_the_client():
    data = ModeViewer().record(grid(), [10.0], bending()[:, None], 0, frames=4)
    html = ModeViewer.standalone_html(data)
    assert "<title>Viser</title>" in html
    head = html[:html.index("</head>")]
    encoded = head.split('window.__VISER_EMBED_DATA__="')[1].split('"')[0]
    assert base64.b64decode(encoded) == data


def test_record_refuses_a_mode_that_does_not_exist():
    with pytest.raises(DataError, match="choose 0 to 0"):
        ModeViewer().record(grid(), [10.0], bending()[:, None], 1)


def test_urls_put_the_key_in_the_path_and_escape_the_playback_file():
    viewer = ModeViewer()
    assert viewer.iframe_url("abc_-1") == "/viser/abc_-1/"
    assert viewer.playback_url("/api/reports/t k/mode 1.viser") == \
        "/viser/?playbackPath=/api/reports/t%20k/mode%201.viser"


# ---- routes and the websocket bridge ---------------------------------------------------------------------------

@pytest.fixture()
def served():
    viewer = ModeViewer()
    app = FastAPI()
    app.include_router(viewer.router)
    key = viewer.publish(grid(), [10.0, 20.0], np.column_stack([bending(), 1j * bending()]), None)
    return viewer, TestClient(app), key


def test_client_page_is_viser_build_served_for_known_keys_only(served):
    viewer, client, key = served
    page = client.get(viewer.iframe_url(key))
    assert page.status_code == 200 and page.headers["content-type"].startswith("text/html")
    assert "<title>Viser</title>" in page.text
    assert "connect-src 'self'" in page.headers["content-security-policy"]
    assert "frame-ancestors 'self'" in page.headers["content-security-policy"]
    assert client.get("/viser/").status_code == 200
    assert client.get("/viser/not-a-key/").status_code == 404
    redirect = client.get(f"/viser/{key}", follow_redirects=False)
    assert redirect.status_code == 307 and redirect.headers["location"] == viewer.iframe_url(key)


def test_mode_route_selects_validates_and_404s(served):
    viewer, client, key = served
    r = client.post(f"/viser/{key}/mode", json={"index": 1, "amplitude": 0.3, "speed": 0, "phase_deg": 45})
    assert r.status_code == 200
    assert r.json() == {"index": 1, "amplitude": 0.3, "speed": 0.0, "phase_deg": pytest.approx(45.0),
                        "interpolate": True}
    assert viewer.registry.get(key).state == ViewState(1, 0.3, 0.0, 0.125, True)
    r = client.post(f"/viser/{key}/mode", json={"index": 1, "interpolate": False})
    assert r.json()["interpolate"] is False and r.json()["phase_deg"] == pytest.approx(45.0)
    bad = client.post(f"/viser/{key}/mode", json={"index": 2})
    assert bad.status_code == 422 and "choose 0 to 1" in bad.json()["detail"]
    assert client.post(f"/viser/{key}/mode", json={"index": 0, "amplitude": 2}).status_code == 422
    assert client.post("/viser/unknown/mode", json={"index": 0}).status_code == 404


def test_bridge_forwards_viser_traffic_with_the_version_subprotocol(served):
    viewer, client, key = served
    viewer.start()
    try:
        with client.websocket_connect(f"/viser/{key}", subprotocols=["viser-v1.1.1"]) as ws:
            assert ws.accepted_subprotocol == "viser-v1.1.1"
            first = ws.receive_bytes()                       # viser's hybrid frame: u64 sizes, then zstd msgpack
            assert len(first) > 16 and int.from_bytes(first[8:16], "little") <= len(first) - 16
            ws.close()
            time.sleep(0.3)             # let the bridge return before the test client cancels what is still running
        with client.websocket_connect(f"/viser/{key}", subprotocols=["viser-v0.0.1"]) as ws:
            with pytest.raises(WebSocketDisconnect) as closed:
                ws.receive_bytes()
            assert closed.value.code == 1002 and "Version mismatch" in closed.value.reason
            time.sleep(0.3)
        with client.websocket_connect("/viser/expired-key", subprotocols=["viser-v1.1.1"]) as ws:
            assert len(ws.receive_bytes()) > 16              # viser answers (and tells the user to reload)
            ws.close()
            time.sleep(0.3)
        with pytest.raises(WebSocketDisconnect) as refused:
            with client.websocket_connect("/viser/not%20a%20key", subprotocols=["viser-v1.1.1"]):
                pass
        assert refused.value.code == 1008
    finally:
        viewer.stop()


def test_a_client_through_the_bridge_gets_the_keys_scene_and_animation(served):
    viewer, client, key = served
    camera = {"type": "ViewerCameraMessage", "wxyz": [1.0, 0.0, 0.0, 0.0], "position": [0.0, 0.0, 5.0],
              "fov": 1.0, "near": 0.01, "far": 100.0, "image_height": 500, "image_width": 800,
              "look_at": [0.0, 0.0, 0.0], "up_direction": [0.0, 0.0, 1.0]}
    unzip = zstandard.ZstdDecompressor()
    viewer.start()
    try:
        with client.websocket_connect(f"/viser/{key}", subprotocols=["viser-v1.1.1"]) as ws:
            ws.send_bytes(msgspec.msgpack.encode(camera))    # viser counts a client as connected after its camera
            seen = []
            deadline = time.monotonic() + 10
            while len([m for m in seen if m.get("name") == "/mode/lines" and "updates" in m]) < 5:
                assert time.monotonic() < deadline, "no animation frames arrived"
                raw = ws.receive_bytes()
                size, packed = int.from_bytes(raw[:8], "little"), int.from_bytes(raw[8:16], "little")
                seen += msgspec.msgpack.decode(unzip.decompress(raw[16:16 + packed], max_output_size=size))["messages"]
            assert viewer.session_count(key) == 1            # the key came back out of the websocket path
            created = {m["name"]: m for m in seen if m["type"] == "LineSegmentsMessage"}
            assert set(created) == {"/undeformed", "/mode/lines"}
            assert any(m["type"] == "GuiDropdownMessage" for m in seen)
            ws.close()
            time.sleep(0.3)
        for _ in range(20):
            if viewer.session_count(key) == 0:
                break
            time.sleep(0.1)
        assert viewer.session_count(key) == 0               # closing the browser's socket ends the viser client
    finally:
        viewer.stop()


def test_share_url_requests_are_ignored():
    from viser import _messages

    viewer = ModeViewer()
    viewer.start()
    try:
        handlers = viewer._live._server._websock_server._incoming_handlers
        assert _messages.ShareUrlRequest not in handlers and _messages.ShareUrlDisconnect not in handlers
        assert viewer._live._server.request_share_url() is None
    finally:
        viewer.stop()
    assert not viewer.running
