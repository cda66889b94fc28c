"""What the mode-shape viewer draws: pure numpy from a geometry and a mode shape to line segments and colours.

No viser here, so the drawing rules are unit-testable: `frame()` is everything one animation frame needs.

Conventions
-----------
- A mode shape is the complex sensor vector ψ (p,) of `era.ModalModel.shapes[:, j]`, scaled here so max |ψ| = 1.
- The animation shows the real motion u(θ) = Re(ψ e^{iθ}) (p,), θ = 2π·phase, at each channel's node along the
  channel's direction (as `era.Geometry.displaced`). Nodes without a sensor either stay put (`interpolate=False`:
  exactly what was measured; the trace lines to them stretch) or follow a thin-plate spline through the measured
  nodes (`interpolate=True`, the viewer's default: a 9-sensor grid then bends like a plate). The spline (scipy's
  RBFInterpolator, with a linear term) runs in the sensors' own coordinates - a line, a plane or space, whichever
  they span - on each displacement component, real and imaginary parts apart; a component a node does not measure
  counts as zero there. It extrapolates linearly beyond the outermost sensors.
- Displacement is drawn at `amplitude` × the structure's size (largest bounding-box side), so the same slider value
  looks alike on a 0.3 m beam and a 3 m grid.
- Colour is the instantaneous |displacement| of each node divided by the largest peak of any node over the cycle
  (0 = still, 1 = the structure's largest excursion), through `COLOUR_STOPS` (blue, teal, green, orange, red: all dark enough to read on
  viser's white background).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from era.errors import DataError
from era import Geometry

# (value, R, G, B) stops of the displacement colour scale, 0..1 -> 0..255.
COLOUR_STOPS = np.array([
    (0.00, 20, 70, 200),
    (0.25, 0, 150, 170),
    (0.50, 60, 160, 40),
    (0.75, 240, 140, 0),
    (1.00, 210, 20, 20),
], dtype=float)

UNDEFORMED_RGB = (185, 185, 185)
#: The shells' surface: a blue-grey under the coloured edges (at 0.75 opacity, the grey rest lines show through),
#: seen from both sides.
SURFACE_RGB = (110, 140, 185)


@dataclass(frozen=True)
class SurfaceGeometry(Geometry):
    """An era.Geometry with surfaces: ``faces`` (n_faces, 3) int, triangles as row indices into ``node_ids`` (an
    FE model's shells), drawn as a mesh that moves with the nodes."""

    faces: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros((0, 3), dtype=int))

    def __post_init__(self):
        super().__post_init__()
        faces = np.asarray(self.faces, dtype=int).reshape(-1, 3)
        if faces.size and (faces.min() < 0 or faces.max() >= self.n_nodes):
            raise DataError("Geometry: a face refers to a node that does not exist.")
        faces.setflags(write=False)
        object.__setattr__(self, "faces", faces)


def faces_of(geometry: Geometry) -> np.ndarray:
    """(n_faces, 3) the geometry's surface triangles; (0, 3) for trace lines only."""
    return geometry.faces if isinstance(geometry, SurfaceGeometry) else np.zeros((0, 3), dtype=int)


@dataclass(frozen=True)
class SceneFrame:
    """One animation frame.

    Attributes
    ----------
    positions : (n_nodes, 3) float, displaced node coordinates in the geometry's units
    level : (n_nodes,) float in [0, 1], |displacement| / largest peak displacement
    segments : (n_edges, 2, 3) float32, start and end point of each trace line
    segment_colours : (n_edges, 2, 3) uint8, RGB at each end of each trace line
    sensor_points : (n_sensor_nodes, 3) float32, positions of the nodes that carry a channel
    sensor_colours : (n_sensor_nodes, 3) uint8
    """

    positions: np.ndarray
    level: np.ndarray
    segments: np.ndarray
    segment_colours: np.ndarray
    sensor_points: np.ndarray
    sensor_colours: np.ndarray


def default_geometry(n_channels: int) -> Geometry:
    """A stand-in when the data came without geometry: the p sensors in a row, 1 unit apart along x, joined in
    channel order, each measuring +z (a beam seen from the side), units "channel"."""
    if n_channels < 1:
        raise DataError("The viewer needs at least one channel to draw.")
    x = np.arange(n_channels, dtype=float)
    return Geometry(
        node_ids=np.arange(1, n_channels + 1),
        coordinates=np.column_stack([x, np.zeros(n_channels), np.zeros(n_channels)]),
        edges=np.column_stack([np.arange(n_channels - 1), np.arange(1, n_channels)]),
        channel_nodes=np.arange(n_channels),
        channel_directions=np.tile([0.0, 0.0, 1.0], (n_channels, 1)),
        units="channel",
    )


def stand_in_note(geometry: Geometry) -> str | None:
    """What the viewer says under a `default_geometry` stand-in (the data came without geometry), else None."""
    if geometry.units != "channel":
        return None
    give = ("; to see the structure, give each point's coordinates and direction (a geometry file, or a "
            "multi-setup test's points table)")
    if geometry.n_nodes == 1:
        return "No geometry in the file: the one sensor drawn as a point moving up and down" + give
    return (f"No geometry in the file: the {geometry.n_nodes} sensors in a row, in channel order, "
            "each moving up and down" + give)


def geometry_for(geometry: Geometry | None, n_channels: int) -> Geometry:
    """The geometry to draw for p = `n_channels` channels: `geometry` with +z for channels whose direction is unknown
    (zeros), or `default_geometry(p)` when there is none or it places none of the channels on a node."""
    if geometry is None or not (geometry.channel_nodes >= 0).any():
        return default_geometry(n_channels)
    unknown = ~geometry.channel_directions.any(axis=1)
    if not unknown.any():
        return geometry
    directions = geometry.channel_directions.copy()
    directions[unknown] = (0.0, 0.0, 1.0)
    return dataclasses.replace(geometry, channel_directions=directions)


def check_modes(geometry: Geometry, frequency_hz, shapes) -> tuple[np.ndarray, np.ndarray]:
    """Validate and return (frequency_hz (modes,) float, shapes (p, modes) complex) for `geometry`.

    Raises `era.DataError` saying what does not match (channel count, mode count, non-finite values)."""
    f = np.atleast_1d(np.asarray(frequency_hz, dtype=float)).reshape(-1)
    psi = np.asarray(shapes, dtype=complex)
    if psi.ndim == 1:
        psi = psi[:, None]
    if psi.ndim != 2:
        raise DataError(f"Mode shapes must be a (channels, modes) array, got shape {psi.shape}.")
    p = geometry.channel_nodes.size
    if psi.shape[0] != p:
        raise DataError(f"Mode shapes have {psi.shape[0]} rows but the geometry places {p} channels; "
                        "give one row per output channel.")
    if psi.shape[1] != f.size:
        raise DataError(f"{psi.shape[1]} mode shapes but {f.size} frequencies; give one frequency per mode.")
    if psi.shape[1] == 0:
        raise DataError("No modes to show: keep at least one mode.")
    if not (np.isfinite(f).all() and np.isfinite(psi).all()):
        raise DataError("Mode frequencies or shapes contain NaN or infinite values.")
    return f, psi


def structure_size(geometry: Geometry) -> float:
    """Largest side of the nodes' bounding box in the geometry's units (1.0 for a single point)."""
    size = float(np.ptp(geometry.coordinates, axis=0).max()) if geometry.n_nodes else 0.0
    return size if size > 0 else 1.0


def node_modal_vectors(geometry: Geometry, shape: np.ndarray, interpolate: bool = False) -> np.ndarray:
    """Complex displacement vector of each node, (n_nodes, 3), for a shape (p,) normalised to max |ψ| = 1.

    Several channels on one node (x, y, z sensors) add up. Nodes without a channel get zeros, or with
    `interpolate` the thin-plate spline through the measured nodes (module docstring)."""
    psi = np.asarray(shape, dtype=complex).reshape(-1)
    peak = np.abs(psi).max(initial=0.0)
    psi = psi / peak if peak > 0 else psi
    out = np.zeros((geometry.n_nodes, 3), dtype=complex)
    known = geometry.channel_nodes >= 0
    np.add.at(out, geometry.channel_nodes[known], psi[known, None] * geometry.channel_directions[known])
    measured = np.unique(geometry.channel_nodes[known])
    if interpolate and 1 < measured.size < geometry.n_nodes:
        free = np.setdiff1d(np.arange(geometry.n_nodes), measured)
        out[free] = _spline(geometry.coordinates[measured], out[measured], geometry.coordinates[free])
    return out


def _spline(at: np.ndarray, values: np.ndarray, to: np.ndarray) -> np.ndarray:
    """Thin-plate spline of complex (m, 3) `values` known at points `at` (m, 3), evaluated at `to` (k, 3)."""
    from scipy.interpolate import RBFInterpolator

    centre = at.mean(axis=0)
    _, sv, axes = np.linalg.svd(at - centre, full_matrices=False)
    axes = axes[sv > 1e-9 * sv.max()]                    # the line, plane or space the sensors span
    data = np.concatenate([values.real, values.imag], axis=1)
    try:
        spline = RBFInterpolator((at - centre) @ axes.T, data, kernel="thin_plate_spline", degree=1)
    except (ValueError, np.linalg.LinAlgError):          # sensors on one spot or on coincident nodes: no spline
        return np.zeros((to.shape[0], 3), dtype=complex)
    out = spline((to - centre) @ axes.T)
    return out[:, :3] + 1j * out[:, 3:]


def colours(level: np.ndarray) -> np.ndarray:
    """Map levels in [0, 1] (clipped) to RGB uint8 through `COLOUR_STOPS`: shape (...) -> (..., 3)."""
    v = np.clip(np.asarray(level, dtype=float), 0.0, 1.0)
    rgb = [np.interp(v, COLOUR_STOPS[:, 0], COLOUR_STOPS[:, k]) for k in (1, 2, 3)]
    return np.rint(np.stack(rgb, axis=-1)).astype(np.uint8)


def frame(geometry: Geometry, node_vectors: np.ndarray, phase: float, amplitude: float) -> SceneFrame:
    """Node positions, trace lines and colours at one instant of the motion.

    Parameters
    ----------
    geometry : the test article
    node_vectors : (n_nodes, 3) complex, from `node_modal_vectors`
    phase : fraction of the cycle, θ = 2π·phase
    amplitude : largest displacement drawn, as a fraction of `structure_size(geometry)`
    """
    theta = 2.0 * np.pi * phase
    motion = np.real(node_vectors * np.exp(1j * theta))               # (n, 3), unit = largest peak component
    peak = np.linalg.norm(np.abs(node_vectors), axis=1).max(initial=0.0)
    size = structure_size(geometry)
    positions = geometry.coordinates + (amplitude * size) * motion
    level = np.linalg.norm(motion, axis=1) / peak if peak > 0 else np.zeros(geometry.n_nodes)
    node_rgb = colours(level)
    edges = geometry.edges
    sensors = np.unique(geometry.channel_nodes[geometry.channel_nodes >= 0])
    return SceneFrame(
        positions=positions,
        level=level,
        segments=positions[edges].astype(np.float32).reshape(-1, 2, 3),
        segment_colours=node_rgb[edges].reshape(-1, 2, 3),
        sensor_points=positions[sensors].astype(np.float32),
        sensor_colours=node_rgb[sensors],
    )


#: The three-quarter direction from above the camera looks from (towards the structure's centre; z is up).
VIEW_DIRECTION = np.array([0.45, -0.95, 0.75]) / np.linalg.norm([0.45, -0.95, 0.75])
#: viser's vertical field of view (three.js' default, 75°), rad, and the width/height of the page's viewer box
#: (the card's 594 × 460 px canvas; the report's is alike).
VIEWER_FOV = float(np.radians(75.0))
VIEWER_ASPECT = 1.3
#: The share of the view's width or height the structure at rest fills, whichever is reached first (its motion,
#: 15 % of its size by default, stays in the view's remaining fifth).
FRAME_FILL = 0.8


def project(position: np.ndarray, look_at: np.ndarray, xyz: np.ndarray, fov: float = VIEWER_FOV,
            aspect: float = VIEWER_ASPECT) -> tuple[np.ndarray, np.ndarray]:
    """Where points ``xyz`` (n, 3) appear in a perspective view from ``position`` towards ``look_at`` (z up): x and
    y (n,) each, -1 to 1 from the left/bottom edge of the view to the right/top (outside beyond ±1)."""
    forward = np.asarray(look_at, float) - np.asarray(position, float)
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, (0.0, 0.0, 1.0))
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    rel = np.asarray(xyz, float).reshape(-1, 3) - position
    depth = rel @ forward
    tan_v = np.tan(fov / 2)
    return rel @ right / depth / (tan_v * aspect), rel @ up / depth / tan_v


def camera_pose(geometry: Geometry, motions=(), amplitude: float = 0.0, fov: float = VIEWER_FOV,
                aspect: float = VIEWER_ASPECT, fill: float = FRAME_FILL) -> tuple[np.ndarray, np.ndarray]:
    """(position, look_at) of a three-quarter view from above (VIEW_DIRECTION) that frames the structure: its
    nodes, and as far as ``motions`` (each (n_nodes, 3) complex, from :func:`node_modal_vectors`) may take them
    over a cycle at ``amplitude`` (a fraction of :func:`structure_size`; each node's box of reach), span ``fill``
    of the view's width or height (whichever is reached first; :func:`project` with the vertical field of view
    ``fov``, rad, and width/height ``aspect``), centred in it; so a mode drawn at that amplitude stays in view.
    A structure with no extent (one point) is seen from 1.3 structure sizes. Units: the geometry's."""
    rest = np.asarray(geometry.coordinates, dtype=float).reshape(-1, 3)
    centre = (rest.min(axis=0) + rest.max(axis=0)) / 2 if geometry.n_nodes else np.zeros(3)
    size = structure_size(geometry)
    if not geometry.n_nodes or np.ptp(rest, axis=0).max() == 0:
        return centre + 1.3 * size * VIEW_DIRECTION, centre
    # each node's reach, axis by axis, over every motion's cycle: |v| bounds Re(v·e^{iθ}); the box's corners
    reach = amplitude * size * np.max([np.abs(v) for v in motions], axis=0, initial=0.0)  # (n_nodes, 3) or 0
    corners = np.array([(a, b, c) for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)], float)
    xyz = (rest + (corners[:, None, :] * reach)).reshape(-1, 3)
    right = np.cross(-VIEW_DIRECTION, (0.0, 0.0, 1.0))
    right /= np.linalg.norm(right)
    up = np.cross(right, -VIEW_DIRECTION)
    tan_v = np.tan(fov / 2)

    def framed(distance):  # look_at centring the projected nodes at this distance, and their half span
        look_at = centre
        for _ in range(4):
            x, y = project(look_at + distance * VIEW_DIRECTION, look_at, xyz, fov, aspect)
            look_at = look_at + distance * tan_v * ((x.max() + x.min()) / 2 * aspect * right
                                                    + (y.max() + y.min()) / 2 * up)
        x, y = project(look_at + distance * VIEW_DIRECTION, look_at, xyz, fov, aspect)
        return look_at, max(np.ptp(x), np.ptp(y)) / 2

    near, far = 0.2 * size, 20.0 * size  # the span shrinks as the camera backs away: bisect for ``fill``
    for _ in range(30):
        mid = (near + far) / 2
        near, far = (mid, far) if framed(mid)[1] > fill else (near, mid)
    look_at = framed(far)[0]
    return look_at + far * VIEW_DIRECTION, look_at


def mode_labels(frequency_hz: np.ndarray, labels=None) -> list[str]:
    """Dropdown text per mode: the caller's labels, or "Mode k · f Hz"; made unique so a label picks one mode."""
    if labels is None:
        labels = [f"Mode {k + 1} · {f:.4g} Hz" for k, f in enumerate(frequency_hz)]
    labels = [str(s) for s in labels]
    if len(labels) != len(frequency_hz):
        raise DataError(f"{len(labels)} labels for {len(frequency_hz)} modes; give one label per mode.")
    if len(set(labels)) < len(labels):
        labels = [f"{k + 1}. {s}" for k, s in enumerate(labels)]
    return labels
