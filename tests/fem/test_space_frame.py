"""era.Frame's modes against closed forms: cantilever, free-free beam, portal frame (exact dynamic stiffness) and a
3-D two-storey frame against a much finer mesh."""

import numpy as np
import pytest
import scipy.optimize

from era.fem import space
from era.structure import Frame, Section

STEEL_BAR = Section.rectangle(width=0.05, depth=0.006, material="steel")
CANTILEVER_BL = np.array([1.87510407, 4.69409113, 7.85475744])
FREE_BL = np.array([4.73004074, 7.85320462, 10.99560784])


def bending_hz(beta_l, EI, m, L):
    return beta_l**2 / (2 * np.pi) * np.sqrt(EI / (m * L**4))


def closest(f, targets):
    """The model frequency closest to each target, and its relative error."""
    f = np.asarray(f)
    got = np.array([f[np.argmin(np.abs(f - t))] for t in targets])
    return got, got / targets - 1


def test_cantilever_bending_in_both_planes_torsion_and_axial_within_0p1_percent():
    """A 0.8 m steel strip 50 × 6 mm along a skew axis, clamped at one end: β_n L of Euler-Bernoulli, the
    quarter-wave twist √(GJ/ρI_p)/(4L) and axial √(E/ρ)/(4L), the 17th mode."""
    L = 0.8
    axis = np.array([0.48, 0.6, 0.64])                       # unit vector
    s = STEEL_BAR
    frame = Frame(nodes={"root": (0, 0, 0), "tip": tuple(L * axis)}, members=[("root", "tip", "bar")],
                  sections={"bar": s}, supports={"root": "fixed"})
    f, _ = frame.modes(18)
    m = s.mass_per_length
    expected = {
        "bending, depth plane": bending_hz(CANTILEVER_BL, s.e * s.iy, m, L),
        "bending, width plane": bending_hz(CANTILEVER_BL, s.e * s.iz, m, L),
        "torsion": [np.sqrt(s.g * s.j / (s.density * s.ip)) / (4 * L)],
        "axial": [np.sqrt(s.e / s.density) / (4 * L)],
    }
    for name, target in expected.items():
        _, err = closest(f, np.asarray(target))
        assert np.all(np.abs(err) < 1e-3), (name, err)
        assert np.all(err > -1e-6), name                     # consistent mass: an upper bound


def test_free_free_beam_has_six_rigid_modes_then_the_elastic_pairs():
    """A round tube in space with no support: six modes at 0 Hz, then β L = 4.730, 7.853, 10.996 (two planes each)."""
    tube = Section.tube(diameter=0.04, wall=0.003, material="aluminium")
    a, b = np.array([0.2, -0.1, 0.3]), np.array([1.1, 0.5, 1.2])
    L = np.linalg.norm(b - a)
    frame = Frame(nodes={"a": tuple(a), "b": tuple(b)}, members=[("a", "b", "t")], sections={"t": tube})
    f, _ = frame.modes(12)
    elastic = bending_hz(FREE_BL, tube.e * tube.iy, tube.mass_per_length, L)
    assert np.all(f[:6] < 1e-3 * elastic[0])
    np.testing.assert_allclose(f[6:12], np.repeat(elastic, 2), rtol=1e-3)


def _dynamic_stiffness_2d(L, EA, EI, m, omega):
    """Exact dynamic stiffness (6 × 6) of a uniform Euler-Bernoulli member in its plane, local (u, v, θ) at both
    ends, from the closed-form solutions of EA u'' + m ω² u = 0 and EI v'''' = m ω² v."""
    k = omega * np.sqrt(m / EA)
    beta = (m * omega**2 / EI) ** 0.25
    out = np.zeros((6, 6))
    ua = np.array([[1, 0], [np.cos(k * L), np.sin(k * L)]])                 # u(0), u(L) from (a cos, b sin)
    fa = EA * k * np.array([[0, -1], [-np.sin(k * L), np.cos(k * L)]])       # f1 = -EA u'(0), f2 = EA u'(L)
    out[np.ix_([0, 3], [0, 3])] = fa @ np.linalg.inv(ua)

    def basis(x, d):
        bx = beta * x
        funcs = [(np.cos(bx), -np.sin(bx), -np.cos(bx), np.sin(bx)), (np.sin(bx), np.cos(bx), -np.sin(bx), -np.cos(bx)),
                 (np.cosh(bx), np.sinh(bx), np.cosh(bx), np.sinh(bx)),
                 (np.sinh(bx), np.cosh(bx), np.sinh(bx), np.cosh(bx))]
        return np.array([f[d] for f in funcs]) * beta**d

    B = np.array([basis(0, 0), basis(0, 1), basis(L, 0), basis(L, 1)])
    F = EI * np.array([basis(0, 3), -basis(0, 2), -basis(L, 3), basis(L, 2)])
    out[np.ix_([1, 2, 4, 5], [1, 2, 4, 5])] = F @ np.linalg.inv(B)
    return out


def _portal_determinant(omega, h, b, EA, EI, m):
    """det of the exact dynamic stiffness of a fixed-base portal (columns h, beam b) on the 6 DOFs of its knees."""
    members = [((0, 0), (0, h)), ((0, h), (b, h)), ((b, h), (b, 0))]
    index = {(0, h): 0, (b, h): 1}
    K = np.zeros((6, 6))
    for p, q in members:
        d = np.subtract(q, p)
        c, s = d / np.linalg.norm(d)
        t3 = np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]])
        T = np.kron(np.eye(2), t3)
        ke = T.T @ _dynamic_stiffness_2d(np.linalg.norm(d), EA, EI, m, omega) @ T
        for a, na in enumerate((p, q)):
            for bb, nb in enumerate((p, q)):
                if na in index and nb in index:
                    ra, rb = 3 * index[na], 3 * index[nb]
                    K[ra:ra + 3, rb:rb + 3] += ke[3 * a:3 * a + 3, 3 * bb:3 * bb + 3]
    return np.linalg.det(K / EI)


def test_dynamic_stiffness_reference_reproduces_a_cantilever():
    L, EA, EI, m = 0.9, 1e6, 20.0, 1.5
    exact = bending_hz(CANTILEVER_BL[:1], EI, m, L)[0] * 2 * np.pi
    det = lambda w: np.linalg.det(_dynamic_stiffness_2d(L, EA, EI, m, w)[3:, 3:][[1, 2]][:, [1, 2]])   # noqa: E731
    root = scipy.optimize.brentq(det, exact * 0.99, exact * 1.01)
    assert root == pytest.approx(exact, rel=1e-8)


def test_portal_frame_in_plane_modes_match_the_exact_dynamic_stiffness_solution():
    """A fixed-base steel portal (columns 1.0 m, beam 1.2 m, 50 × 6 mm strip bending in the frame's plane): its first
    three in-plane frequencies (sway first) agree with the roots of the exact dynamic-stiffness determinant."""
    h, b = 1.0, 1.2
    s = STEEL_BAR
    frame = Frame(nodes={"A": (0, 0, 0), "B": (0, 0, h), "C": (b, 0, h), "D": (b, 0, 0)},
                  members=[("A", "B", "bar"), ("B", "C", "bar"), ("C", "D", "bar")], sections={"bar": s},
                  supports={"A": "fixed", "D": "fixed"}, sensors=[("B", "x"), ("C", "x")])
    f, u = frame.node_modes(10)
    in_plane = np.abs(u[:, 1]).max(axis=0) < 1e-6 * np.abs(u).max(axis=(0, 1))
    f_in = f[in_plane][:3]
    assert f_in.size == 3 and in_plane[0]                     # the sway is the lowest mode of all
    _, sway = frame.modes(1)
    assert sway[0, 0] * sway[1, 0] > 0                        # both knees move the same way
    EA, EI, m = s.e * s.area, s.e * s.iy, s.mass_per_length
    for fe in f_in:
        w = 2 * np.pi * fe
        root = scipy.optimize.brentq(_portal_determinant, w * (1 - 3e-3), w * (1 + 1e-6), args=(h, b, EA, EI, m))
        assert fe / (root / (2 * np.pi)) - 1 == pytest.approx(0, abs=1e-3)
    # the textbook bound: sway between a rigid beam (24 EI/h³ on the whole mass) and the exact value
    assert f_in[0] < np.sqrt(24 * EI / h**3 / (m * (b + 2 * h * 13 / 35))) / (2 * np.pi)


def two_storey_frame(rotation=np.eye(3), elements_per_member=None):
    """A 3-D two-storey steel frame 1.2 × 0.9 m in plan, 0.8 m storeys: square-tube columns, strip beams turned
    about their axes (orientation vectors), a diagonal brace, spring and fixed supports, a lumped mass."""
    col = Section.square_tube(width=0.03, wall=0.002)
    beam = Section.rectangle(width=0.04, depth=0.008)
    brace = Section.circle(diameter=0.01)
    plan = [(0, 0), (1.2, 0), (1.2, 0.9), (0, 0.9)]
    nodes = {f"{k}{c}": (x, y, 0.8 * k) for k in range(3) for c, (x, y) in zip("abcd", plan)}
    members = [(f"{k}{c}", f"{k + 1}{c}", "col") for k in range(2) for c in "abcd"]
    members += [(f"{k}{c}", f"{k}{d}", "beam", (0, 0, 1) if c in "ab" else (0.3, 0.2, 1))
                for k in (1, 2) for c, d in zip("abcd", "bcda")]
    members += [("0a", "1b", "brace")]
    rot = lambda v: tuple(rotation @ np.asarray(v, float))   # noqa: E731
    return Frame(nodes={n: rot(x) for n, x in nodes.items()},
                 members=[m if len(m) == 3 else (*m[:3], rot(m[3])) for m in members],
                 sections={"col": col, "beam": beam, "brace": brace},
                 supports={"0a": "fixed", "0b": "fixed", "0c": {"kx": 2e5, "ky": 2e5, "kz": "fixed", "rx": 1e3,
                                                                 "ry": 1e3, "rz": 1e3}, "0d": "pinned"},
                 masses={"2c": 1.5}, sensors=[("2a", rot((1, 0, 0))), ("2c", rot((0, 1, 0)))],
                 elements_per_member=elements_per_member)


def test_space_frame_automatic_mesh_agrees_with_a_much_finer_mesh_within_0p1_percent():
    auto = two_storey_frame()
    f_auto, _ = auto.modes(10)
    f_fine, _ = two_storey_frame(elements_per_member=24).modes(10)
    err = f_auto / f_fine - 1
    assert np.all(err > -1e-6) and np.all(err < 1e-3), err
    mesh, _ = auto.solution(10)
    assert mesh.elements.shape[0] < 24 * 17                 # and it needed far fewer elements


def test_space_frame_modes_do_not_depend_on_where_the_axes_point():
    """Turning the whole frame (nodes, orientation vectors, sensor directions) changes neither the frequencies
    nor the sensor shapes; supports turn only about z, their springs being on global axes."""
    c, s = np.cos(0.7), np.sin(0.7)
    turn = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    f0, s0 = two_storey_frame(elements_per_member=4).modes(8)
    f1, s1 = two_storey_frame(turn, elements_per_member=4).modes(8)
    # the spring support (2e5 N/m on x and y, equal) is isotropic in the plane, so turning about z keeps the model
    np.testing.assert_allclose(f1, f0, rtol=1e-9)
    np.testing.assert_allclose(np.abs(s1), np.abs(s0), rtol=1e-6, atol=1e-9 * np.abs(s0).max())


def test_mass_normalised_shapes_and_node_modes_agree():
    frame = two_storey_frame(elements_per_member=3)
    mesh, result = frame.solution(10)
    M = space.mass(mesh)
    phi = result.shapes.reshape(-1, 10)
    np.testing.assert_allclose(phi.T @ (M @ phi), np.eye(10), atol=1e-8)
    f, shapes = frame.modes(10)
    _, u = frame.node_modes(10)
    ids = frame.node_ids
    np.testing.assert_allclose(shapes[0], u[ids.index("2a"), 0])
    np.testing.assert_allclose(shapes[1], u[ids.index("2c"), 1])
    f5, s5 = frame.modes(5)                                   # same mesh: a prefix of modes(10)
    np.testing.assert_allclose(f5, f[:5])
    np.testing.assert_allclose(s5, shapes[:, :5])
    along_x = np.zeros((mesh.n_nodes, 6))
    along_x[:, 0] = 1.0
    assert along_x.ravel() @ (M @ along_x.ravel()) == pytest.approx(frame.total_mass_kg, rel=1e-12)


def test_sparse_and_dense_solvers_agree_and_a_free_structure_keeps_its_six_rigid_modes_on_either():
    """Lanczos from one start vector can lose members of a six-fold zero eigenvalue: the rigid modes are known
    exactly and set aside. 101 nodes (606 DOFs) go the sparse way, 11 nodes the dense one."""
    tube = Section.tube(diameter=0.04, wall=0.003, material="aluminium")
    a, b = np.array([0.2, -0.1, 0.3]), np.array([1.1, 0.5, 1.2])
    for n_el in (10, 100):
        frame = Frame(nodes={"a": tuple(a), "b": tuple(b)}, members=[("a", "b", "t")], sections={"t": tube},
                      elements_per_member=n_el)
        f, _ = frame.modes(12)
        mesh, result = frame.solution(12)
        assert np.all(f[:6] == 0) and f[6] > 100
        K, M = space.stiffness(mesh), space.mass(mesh)
        phi = result.shapes.reshape(-1, 12)
        np.testing.assert_allclose(phi.T @ (M @ phi), np.eye(12), atol=1e-8)
        lam = np.einsum("ij,ij->j", phi, K @ phi)                 # Rayleigh quotients = the eigenvalues
        # the rigid modes' quotients are round-off: compared as eigenvalues (their square roots magnify it)
        assert np.abs(lam[:6]).max() <= 1e-9 * lam[6]
        np.testing.assert_allclose(np.sqrt(lam[6:]) / (2 * np.pi), f[6:], rtol=1e-8)
        residual = K @ phi - (M @ phi) * (2 * np.pi * f) ** 2
        assert np.abs(residual).max() < 1e-6 * np.abs(K @ phi).max()


def test_the_orientation_vector_turns_the_section():
    """A strip cantilever along x: by default its depth (6 mm) is vertical and the weak bending moves it along z;
    with the orientation (0, 1, 0) the depth lies along y and the weak bending moves it along y."""
    def strip(*orientation):
        return Frame(nodes={"0": (0, 0, 0), "1": (0.5, 0, 0)}, members=[("0", "1", "s", *orientation)],
                     sections={"s": STEEL_BAR}, supports={"0": "fixed"}, sensors=[("1", "y"), ("1", "z")])
    weak = bending_hz(CANTILEVER_BL[:1], STEEL_BAR.e * STEEL_BAR.iy, STEEL_BAR.mass_per_length, 0.5)[0]
    for frame, moving in ((strip(), 1), (strip((0, 1, 0)), 0), (strip((0, 1, 1e-3)), 0)):
        f, shapes = frame.modes(1)
        assert f[0] == pytest.approx(weak, rel=1e-3)
        assert abs(shapes[1 - moving, 0]) < 2e-3 * abs(shapes[moving, 0])        # the last one tilts 1e-3 rad


def test_frames_are_immutable_and_replace_revalidates():
    from dataclasses import replace
    frame = two_storey_frame(elements_per_member=2)
    with pytest.raises(TypeError):
        frame.nodes["9x"] = (0, 0, 0)
    with pytest.raises(TypeError):
        frame.supports["0a"]["kx"] = 1.0
    heavier = replace(frame, masses={**frame.masses, "2a": 3.0})
    assert heavier.modes(1)[0][0] < frame.modes(1)[0][0]
    assert replace(frame).to_dict() == frame.to_dict()


def test_a_variant_can_keep_the_nominal_mesh():
    """element_counts() of the automatic mesh, given back as elements_per_member, reproduces the same modes."""
    from dataclasses import replace
    frame = two_storey_frame()
    counts = frame.element_counts(10)
    assert len(counts) == len(frame.members) and max(counts) > 1
    fixed = replace(frame, elements_per_member=counts)
    np.testing.assert_array_equal(fixed.modes(10)[0], frame.modes(10)[0])
    assert Frame.from_dict(fixed.to_dict()).elements_per_member == counts


def test_portal_with_a_rigid_heavy_beam_sways_at_the_textbook_frequency():
    """Shear building: two fixed-fixed columns (12 EI/h³ each) carrying a rigid beam and 2 × 40 kg; the columns' own
    mass enters with its Rayleigh share 13/35. f = √(24 EI/h³ / M) / 2π."""
    h, b = 0.9, 1.2
    col = STEEL_BAR
    beam = Section(area=1e-2, iy=1e-4, iz=1e-4, j=1e-4, e=2e11, g=8e10, density=100.0)   # 1 kg/m, rigid
    frame = Frame(nodes={"A": (0, 0, 0), "B": (0, 0, h), "C": (b, 0, h), "D": (b, 0, 0)},
                  members=[("A", "B", "col"), ("B", "C", "beam"), ("C", "D", "col")],
                  sections={"col": col, "beam": beam}, supports={"A": "fixed", "D": "fixed"},
                  masses={"B": 40.0, "C": 40.0}, sensors=[("B", "x")])
    f, u = frame.node_modes(4)
    sway = next(k for k in range(4) if abs(u[1, 0, k]) > 10 * abs(u[1, 1, k]))
    mass = 80.0 + beam.mass_per_length * b + 2 * 13 / 35 * col.mass_per_length * h
    textbook = np.sqrt(24 * col.e * col.iy / h**3 / mass) / (2 * np.pi)
    assert f[sway] == pytest.approx(textbook, rel=1e-3)


def test_rayleigh_ritz_in_the_reference_modes_screens_a_local_change():
    """Frame.ritz_modes: the reference itself comes back exactly; a lumped mass or a softer member on the two-storey
    frame is within 0.5 % in frequency and 0.99 in MAC of its own solve (enough to rank places; the best are then
    solved in full); a support made flexible, or another mesh, gives None (those are solved). (FrameModels
    without their reduced model: explain's own screening is era.fem.reduced's, tests/fem/test_reduced.py.)"""
    from era.discrepancy.frame_model import FrameModel
    from era.examples.frames import two_storey

    ref = FrameModel.of(two_storey(), reduced=False)
    f_ref, u_ref = ref.updated_frame.ritz_modes(ref.updated_frame, 30)
    f0, u0 = ref.updated_frame.node_modes(10)
    np.testing.assert_allclose(f_ref[:10], f0, rtol=1e-10)
    node = ref.frame.sensors[0][0]
    base = next(iter(ref.frame.supports))
    for kw in (dict(point_mass_kg=5.0, point_mass_at=node), dict(member_at=ref.frame.members[3][:2], member_factor=0.6)):
        trial = ref.with_params(**kw)
        approx, (f, s) = trial.ritz(ref, 30), trial.modes(6)
        fr, sr = approx.modes(6)
        np.testing.assert_allclose(fr, f, rtol=5e-3, err_msg=str(kw))
        assert np.all(fr >= f * (1 - 1e-9))  # Rayleigh-Ritz bounds every frequency from above
        mac = np.abs(np.sum(sr * s, axis=0)) ** 2 / np.sum(sr * sr, axis=0) / np.sum(s * s, axis=0)
        assert mac.min() > 0.99, (kw, mac)
    assert ref.with_params(support_at=base, support_rotation_stiffness=5e4).ritz(ref, 30) is None
    other = FrameModel.of(two_storey(), n_mesh=30, reduced=False)
    assert other.updated_frame.elements_per_member != ref.updated_frame.elements_per_member
    assert other.ritz(ref, 30) is None
