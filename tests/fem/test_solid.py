"""era.fem's linear solids against CalculiX on the same mesh (ccx run as a separate program): the plain trilinear
hexahedron is ccx's C3D8 (the same shapes, Gauss rule and consistent mass), so a block's modes agree to ccx's
printed digits; a distorted hexahedron with incompatible modes passes the patch test (a uniform strain's exact
energy)."""

from __future__ import annotations

import numpy as np
import pytest
from calculix import frequencies, run

from era.fem.eigen import sparse_modes
from era.fem.mesh import FEMesh, assemble
from era.fem.solid import SolidProperty, solid_batch

STEEL = SolidProperty(2.1e11, 0.3, 7850.0)


def _block(nx=6, ny=1, nz=2, size=(0.12, 0.02, 0.03)):
    gid = {(i, j, k): 1 + i + (nx + 1) * (j + (ny + 1) * k)
           for k in range(nz + 1) for j in range(ny + 1) for i in range(nx + 1)}
    nodes = {str(g): (size[0] * i / nx, size[1] * j / ny, size[2] * k / nz) for (i, j, k), g in gid.items()}
    hexes = [[gid[i, j, k], gid[i + 1, j, k], gid[i + 1, j + 1, k], gid[i, j + 1, k], gid[i, j, k + 1],
              gid[i + 1, j, k + 1], gid[i + 1, j + 1, k + 1], gid[i, j + 1, k + 1]]
             for k in range(nz) for j in range(ny) for i in range(nx)]
    return nodes, hexes


def test_the_plain_hexahedron_is_calculix_s_c3d8(tmp_path, monkeypatch):
    import era.fem.solid as solid
    plain = solid.solid_batch
    monkeypatch.setattr(solid, "solid_batch", lambda xyz, prop: plain(xyz, prop, incompatible=False))
    nodes, hexes = _block()
    rot = ("rx", "ry", "rz")
    fixed = tuple((n, d) for n, x in nodes.items() for d in (("x", "y", "z") + rot if x[0] == 0 else rot))
    mesh = FEMesh(nodes, solids=tuple(("s", tuple(map(str, h))) for h in hexes), solid_properties={"s": STEEL},
                  fixed=fixed)
    am = assemble(mesh)
    f = sparse_modes(am.stiffness, am.mass, 6)[0]
    lines = ["*NODE"] + [f"{n}, {x!r}, {y!r}, {z!r}" for n, (x, y, z) in nodes.items()]
    lines += ["*ELEMENT, TYPE=C3D8, ELSET=EALL"] + [f"{e + 1}, " + ", ".join(map(str, h)) for e, h in enumerate(hexes)]
    lines += ["*BOUNDARY"] + [f"{n}, 1, 3" for n, x in nodes.items() if x[0] == 0]
    lines += ["*MATERIAL, NAME=STEEL", "*ELASTIC", "2.1e11, 0.3", "*DENSITY", "7850.",
              "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL", "*STEP", "*FREQUENCY", "6", "*END STEP"]
    truth = frequencies(run("\n".join(lines) + "\n", tmp_path))
    assert f == pytest.approx(truth, rel=1e-6)


def test_a_distorted_hexahedron_with_incompatible_modes_passes_the_patch_test():
    """A uniform strain ε on a distorted hexahedron (u = ε x) stores exactly V εᵀDε: the incompatible modes stay
    silent (Taylor's centre Jacobian), so a patch of such elements carries a uniform stress."""
    xyz = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    xyz[6] += [0.2, 0.1, 0.15]
    xyz[1] += [0.1, -0.05, 0.0]
    strain = np.array([[1e-3, 2e-4, 0.0], [2e-4, -5e-4, 1e-4], [0.0, 1e-4, 3e-4]])
    k, _ = solid_batch(xyz[None], STEEL)
    u = (xyz @ strain.T).ravel()
    # the volume: the mass at unit density (the trilinear map's det J is integrated exactly by 2 × 2 × 2 points)
    volume = solid_batch(xyz[None], SolidProperty(1.0, 0.0, 1.0))[1][0][0::3, 0::3].sum()
    lam, g = STEEL.e * STEEL.nu / ((1 + STEEL.nu) * (1 - 2 * STEEL.nu)), STEEL.e / (2 * (1 + STEEL.nu))
    energy = lam * np.trace(strain) ** 2 + 2 * g * np.sum(strain * strain)
    assert u @ k[0] @ u == pytest.approx(volume * energy, rel=1e-10)
