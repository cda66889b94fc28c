"""era.fem.assemble: DOF numbering, fixed DOFs and unused nodes, RBE2, springs, point masses, parts, beams alone,
and the errors a mesh's user can make; truths from closed forms and small hand-built matrices."""

import numpy as np
import pytest
import scipy.linalg

from era.errors import DataError
from era.fem import BeamProperty, FEMesh, ShellProperty, assemble, sparse_modes

from plates import STEEL, grid

ALL = ("x", "y", "z", "rx", "ry", "rz")
BAR = BeamProperty(area=4e-4, iy=2e-8, iz=5e-8, j=3e-8, e=2.1e11, g=8.1e10, rho=7850.0, nsm=0.5)


def test_cantilever_beam_matches_euler_bernoulli():
    """20 beam elements clamped at one end: bending about both axes (β L = 1.8751, 4.6941), the section's
    non-structural mass included, against the closed form."""
    n, L = 20, 1.5
    nodes = {f"n{i}": (L * i / n, 0.0, 0.0) for i in range(n + 1)}
    beams = tuple(("bar", f"n{i}", f"n{i + 1}", (0.0, 0.3, 1.0)) for i in range(n))
    m = assemble(FEMesh(nodes, beams=beams, beam_properties={"bar": BAR}, fixed=tuple(("n0", d) for d in ALL)))
    f, _ = sparse_modes(m.stiffness, m.mass, 6)
    mass = BAR.rho * BAR.area + BAR.nsm
    truth = sorted(bl**2 / (2 * np.pi * L**2) * np.sqrt(BAR.e * i / mass)
                   for bl in (1.87510407, 4.69409113) for i in (BAR.iy, BAR.iz))
    bending = [x for x in f if np.min(np.abs(np.array(truth) / x - 1)) < 0.01]
    np.testing.assert_allclose(sorted(bending)[:4], truth, rtol=1e-4)


def test_fixed_dofs_and_untouched_nodes_leave_the_numbering():
    nodes, shells = grid(2, 1, 1.0, 0.5)
    nodes = dict(nodes, lonely=(9.0, 9.0, 9.0))
    m = assemble(FEMesh(nodes, shells, shell_properties={"plate": STEEL}, fixed=(("0_0", "z"), ("0_0", "rx"))))
    assert len(m.dofs) == 6 * 6 - 2
    assert ("0_0", "z") not in m.dofs and ("0_0", "ry") in m.dofs
    assert all(node != "lonely" for node, _ in m.dofs)
    assert m.dofs[:3] == (("0_0", "x"), ("0_0", "y"), ("0_0", "ry"))
    assert set(m.part_stiffness) == {"plate"}
    assert abs(m.part_stiffness["plate"] - m.stiffness).max() == 0


def test_rbe2_carries_an_offset_mass_and_a_spring_grounds_it():
    """Node a: springs to ground in y (k) and about z (kr), all else fixed; an RBE2 makes node b (offset r along
    x) follow it, and b holds a point mass m with inertia Izz: the 2 x 2 problem in (y_a, rz_a) by hand."""
    k, kr, mass, izz, r = 4.0e5, 3.0e4, 12.0, 0.2, 0.35
    mesh = FEMesh(nodes={"a": (0.0, 0.0, 0.0), "b": (r, 0.0, 0.0)},
                  masses=(("b", mass, (0.1, 0.1, izz)),),
                  springs=(("a", "y", None, None, k), ("a", "rz", None, None, kr)),
                  fixed=tuple(("a", d) for d in ("x", "z", "rx", "ry")),
                  rigid=(("a", ("b",), ALL),))
    m = assemble(mesh)
    assert m.dofs == (("a", "y"), ("a", "rz"))
    lam = scipy.linalg.eigh(np.diag([k, kr]), np.array([[mass, mass * r], [mass * r, mass * r**2 + izz]]),
                            eigvals_only=True)
    np.testing.assert_allclose(sparse_modes(m.stiffness, m.mass, 2)[0], np.sqrt(lam) / (2 * np.pi), rtol=1e-10)


def test_spring_between_two_nodes():
    mesh = FEMesh(nodes={"a": (0, 0, 0), "b": (1, 0, 0)}, masses=(("a", 2.0, (1, 1, 1)), ("b", 3.0, (1, 1, 1))),
                  springs=(("a", "x", "b", "x", 600.0),),
                  fixed=tuple((n, d) for n in "ab" for d in ALL if d != "x"))
    m = assemble(mesh)
    f, _ = sparse_modes(m.stiffness, m.mass, 2)
    assert f[0] < 1e-6 and f[1] == pytest.approx(np.sqrt(600.0 * (1 / 2 + 1 / 3)) / (2 * np.pi), rel=1e-10)


def test_parts_sum_to_the_model():
    nodes, shells = grid(3, 2, 0.6, 0.4)
    shells = tuple(("thin" if i % 2 else "thick", c) for i, (_, c) in enumerate(shells))
    beams = (("bar", "0_1", "1_1", (0, 0, 1)), ("bar", "1_1", "2_1", (0, 0, 1)))
    props = {"thin": STEEL, "thick": ShellProperty(0.01, 2.1e11, 0.3, 7850.0)}
    mesh = FEMesh(nodes, shells, beams, props, {"bar": BAR}, masses=(("3_2", 1.0, (0, 0, 0)),))
    m = assemble(mesh)
    assert set(m.part_mass) == {"thin", "thick", "bar"}
    assert abs(sum(m.part_stiffness.values()) - m.stiffness).max() < 1e-9 * abs(m.stiffness).max()
    x = np.array([d == "x" for _, d in m.dofs], float)      # a rigid translation: the model's whole mass
    total = sum(p.rho * p.thickness for p in props.values()) * 0.2 * 0.2 * 3 + 1.0 + \
        (BAR.rho * BAR.area + BAR.nsm) * 0.4
    assert x @ m.mass @ x == pytest.approx(total, rel=1e-12)


@pytest.mark.parametrize("mesh, message", [
    (FEMesh({"a": (0, 0, 0)}), "touch nothing"),
    (FEMesh({"a": (0, 0, 0)}, shells=(("p", ("a", "b", "c")),)), "not defined: b, c"),
    (FEMesh({"a": (0, 0, 0), "b": (1, 0, 0), "c": (0, 1, 0)}, shells=(("p", ("a", "b", "c")),)),
     "Shell property 'p'"),
    (FEMesh({"a": (0, 0, 0), "b": (1, 0, 0)}, beams=(("bar", "a", "b", (2, 0, 0)),), beam_properties={"bar": BAR}),
     "parallel"),
    (FEMesh({"a": (0, 0, 0)}, springs=(("a", "q", None, None, 1.0),)), "'q' is not one of"),
    (FEMesh({"a": (0, 0, 0), "b": (1, 0, 0)}, masses=(("a", 1.0, (1, 1, 1)),),
            rigid=(("a", ("b",), ALL), ("b", ("a",), ALL))), "loop"),
    (FEMesh({"a": (0, 0, 0), "b": (1, 0, 0)}, masses=(("b", 1.0, (1, 1, 1)),), rigid=(("a", ("b",), ALL),),
            fixed=(("b", "x"),)), "both fixed and an RBE2"),
    (FEMesh({"a": (0, 0, 0)}, masses=(("a", 1.0, (1, 1, 1)),), fixed=(("z9", "x"),)), "'z9', which is not defined"),
])
def test_mesh_errors_say_what_to_fix(mesh, message):
    with pytest.raises(DataError, match=message):
        assemble(mesh)
