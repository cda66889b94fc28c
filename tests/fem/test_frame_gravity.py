"""Gravity in era.Frame: the self-weight's axial forces stiffen the frame (hanging chain, a bar on two cables) and
the NASA grid described as an era.Frame reproduces nasa_grid()."""

import numpy as np
import pytest

from era.examples.frames import nasa_grid_frame
from era.examples.grid import nasa_grid
from era.fem import space
from era.fem.statics import G_STANDARD
from era.structure import Frame, Section

# a chain: EI/(m g L³) ≈ 8e-7
THREAD = Section(area=1e-4, iy=1e-16, iz=1e-16, j=1e-16, e=2e11, g=8e10, density=7850)


def test_self_weight_reactions_carry_the_whole_weight():
    frame = Frame(nodes={"a": (0, 0, 0), "b": (1.0, 0.2, 0.1), "c": (2.0, 0, 0.3)},
                  members=[("a", "b", "s"), ("b", "c", "s")], sections={"s": Section.tube(0.03, 0.002)},
                  supports={"a": "fixed", "c": "pinned"}, masses={"b": 2.0}, gravity=(0, 0, -9.81))
    statics = space.self_weight(frame.space_frame(), np.array(frame.gravity))
    total = statics.reactions[:, :3].sum(axis=0)
    np.testing.assert_allclose(total, [0, 0, frame.total_mass_kg * 9.81], rtol=1e-9, atol=1e-6)


def test_hanging_chain_swings_at_the_zeros_of_bessel_j0():
    """A chain hanging from a point: ω_n = (j0,n / 2) √(g/L) in both planes; twist held at the top. The mesh
    resolves the bending boundary layer √(EI/N) ≈ 1 mm at the top: about 1200 elements."""
    L = 1.5
    frame = Frame(nodes={"top": (0, 0, L), "end": (0, 0, 0)}, members=[("top", "end", "chain")],
                  sections={"chain": THREAD}, supports={"top": {"kx": "fixed", "ky": "fixed", "kz": "fixed",
                                                                "rz": "fixed"}},
                  gravity=(0, 0, -G_STANDARD))
    f, _ = frame.modes(6)
    exact = np.array([2.40482556, 5.52007811, 8.65372791]) / 2 * np.sqrt(G_STANDARD / L) / (2 * np.pi)
    np.testing.assert_allclose(f, np.repeat(exact, 2), rtol=1e-3)
    _, result = frame.solution(6)
    assert result.axial_force.max() == pytest.approx(THREAD.mass_per_length * G_STANDARD * L, rel=0.02)


def test_bar_on_two_cables_swings_as_a_pendulum():
    """A stiff bar hung by its ends from cables of length Lc: f = √(g/Lc)/2π across the bar and along it."""
    Lc = 0.4
    frame = Frame(nodes={"a": (0, 0, 0), "b": (1.0, 0, 0)}, members=[("a", "b", "bar")],
                  sections={"bar": Section.tube(0.05, 0.005)},
                  supports={"a": {"cable": Lc, "rx": "fixed"}, "b": {"cable": Lc}}, gravity=(0, 0, -G_STANDARD))
    f, _ = frame.modes(3)
    pendulum = np.sqrt(G_STANDARD / Lc) / (2 * np.pi)
    np.testing.assert_allclose(f[:2], pendulum, rtol=1e-4)          # swing along and across (the bar bends 2e-5)
    assert f[2] == pytest.approx(np.sqrt(3) * pendulum, rel=1e-3)   # yaw: k L²/2 against m L²/12


def test_nasa_grid_described_as_a_frame_matches_nasa_grid_within_0p5_percent():
    frame = nasa_grid_frame()
    f, shapes = frame.modes(10)
    f0, s0 = nasa_grid().modes(10)
    np.testing.assert_allclose(f, f0, rtol=5e-3)
    np.testing.assert_allclose(f, f0, rtol=1e-5)         # in fact the same model: one element per 1-ft bar
    mac = (shapes * s0).sum(0) ** 2 / (shapes**2).sum(0) / (s0**2).sum(0)
    assert np.all(mac > 0.9999)
    np.testing.assert_allclose(np.abs(shapes), np.abs(s0), atol=1e-4 * np.abs(s0).max())
    assert frame.total_mass_kg == pytest.approx(nasa_grid().total_mass_kg, rel=1e-3)   # J/A series differ in the 4th
    # the automatic mesh keeps one element per bar for ten modes, and nasa_grid's finer mesh agrees within 0.05 %
    mesh, _ = frame.solution(10)
    assert mesh.elements.shape[0] == 157
    np.testing.assert_allclose(f, nasa_grid(elements_per_bar=4).modes(10)[0], rtol=5e-4)


def test_the_grid_frame_with_a_softer_cable_and_a_point_mass_follows_nasa_grid():
    """Longer cables and a 1 kg mass at a joint move both models the same way."""
    frame = nasa_grid_frame(supports={"2,7": {"cable": 0.7, "kx": "fixed"}, "8,7": {"cable": 0.7}}, masses={"10,0": 1.0})
    f0 = nasa_grid(cable_length_m=0.7, point_mass_kg=1.0, point_mass_at=(10, 0)).modes(10)[0]
    np.testing.assert_allclose(frame.modes(10)[0], f0, rtol=1e-5)
