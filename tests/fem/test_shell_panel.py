"""A stiffened panel, shells joined with beams or with shell webs, against two independent solvers: OpenSees
(ShellMITC4 or ShellDKGT + elasticBeamColumn, other code with lumped masses) and CalculiX (ccx run as a separate
program; its S8R/S6 shells are expanded into 20-node and 15-node solids, another theory altogether)."""

import numpy as np
import pytest

from era.fem import assemble, sparse_modes

from calculix import frequencies, frequency_inp, run
from stiffened_panel import opensees_hz, with_beams, with_eccentric_beams, with_webs

N_CCX = 7


def modes(mesh, n):
    m = assemble(mesh)
    return sparse_modes(m.stiffness, m.mass, n)[0]


@pytest.fixture(scope="module")
def ccx_webs(tmp_path_factory):
    """CalculiX's first modes of the panel with shell webs (24 x 18 plate elements, 2 over the web's height)."""
    return frequencies(run(frequency_inp(with_webs(24, 18), N_CCX), tmp_path_factory.mktemp("ccx_webs")))


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


def test_plate_with_shell_webs_matches_calculix(ccx_webs):
    """Plate and webs meet at a T-junction: the plate's bending loads the web in its plane (the quads' incompatible
    modes keep that from locking) and the web's drilling rotation is the plate's bending slope."""
    np.testing.assert_allclose(modes(with_webs(24, 18), N_CCX), ccx_webs, rtol=0.01)


def test_plate_of_triangles_with_shell_webs_matches_calculix(tmp_path):
    mesh = with_webs(24, 18, triangles=True)
    np.testing.assert_allclose(modes(mesh, N_CCX), frequencies(run(frequency_inp(mesh, N_CCX), tmp_path)),
                               rtol=0.01)


def test_eccentric_beam_stiffeners_on_rbe2_match_calculix_webs(ccx_webs):
    """The engineer's usual model of the same panel: each stiffener a beam on its centroid line, HEIGHT/2 above
    the plate, held to the plate's nodes by RBE2s, against CalculiX's shell webs. The beams' bending about the
    plate's normal meets the shells' drilling rotation here: with a drilling penalty of G (OpenSees' choice) the
    panel's twisting mode came out 6-11 % stiff and stiffer as the mesh was refined; era.fem's G/100 is within
    1 %."""
    np.testing.assert_allclose(modes(with_eccentric_beams(24, 18), N_CCX), ccx_webs, rtol=0.01)
