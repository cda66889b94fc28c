"""A stiffened panel, shells joined with beams or with shell webs, against two independent solvers: OpenSees
(ShellMITC4 or ShellDKGT + elasticBeamColumn, other code with lumped masses) and CalculiX (ccx run as a
separate program; its S8R/S6 shells are expanded into 20-node and 15-node solids, another theory altogether)."""

import numpy as np
import pytest

from era.fem import assemble, sparse_modes

from calculix import frequencies, frequency_inp, run
from stiffened_panel import opensees_hz, with_beams, with_webs


def modes(mesh, n):
    m = assemble(mesh)
    return sparse_modes(m.stiffness, m.mass, n)[0]


@pytest.mark.parametrize("triangles, nx, ny", [(False, 12, 9), (True, 24, 18)])
def test_plate_with_beam_stiffeners_matches_opensees(triangles, nx, ny):
    """Quads against ShellMITC4; triangles against ShellDKGT (discrete Kirchhoff: another plate theory, the same
    answer on a thin plate once the mesh is fine)."""
    mesh = with_beams(nx, ny, triangles=triangles)
    f = modes(mesh, 10)
    np.testing.assert_allclose(f, opensees_hz(mesh, 10), rtol=0.005)
    # the stiffeners matter: the bare plate's first bending is far lower
    bare = modes(type(mesh)(mesh.nodes, mesh.shells, (), mesh.shell_properties, fixed=mesh.fixed), 1)
    assert f[0] > 1.5 * bare[0]


@pytest.mark.parametrize("triangles", [False, True])
def test_plate_with_shell_webs_matches_calculix(triangles, tmp_path):
    """Plate and webs meet at a T-junction: the plate's bending loads the web in its plane (the quads' incompatible
    modes keep that from locking) and the drilling rotation carries the web's twist into the plate."""
    mesh = with_webs(24, 18, triangles=triangles)
    truth = frequencies(run(frequency_inp(mesh, 7), tmp_path))
    np.testing.assert_allclose(modes(mesh, 7), truth, rtol=0.01)
