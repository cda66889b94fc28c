"""A stiffened panel (an aluminium plate with two stiffeners, clamped on one short edge) as an era.fem FEMesh:
stiffeners as beams on the plate's nodes, as eccentric beams held to them by RBE2s, or as shell webs standing on
them; and the beam versions built in OpenSees (ShellMITC4 or ShellDKGT and elasticBeamColumn, an RBE2 as the
beam's rigid joint offset, the elements' own masses), an independent solver."""

from __future__ import annotations

import numpy as np

from era.fem import BeamProperty, FEMesh, ShellProperty

from plates import grid, label

A, B = 0.6, 0.4                     # plate (m), clamped along x = 0
PLATE = ShellProperty(thickness=0.003, e=70e9, nu=0.33, rho=2700.0)
WEB = ShellProperty(thickness=0.004, e=70e9, nu=0.33, rho=2700.0)
HEIGHT, WIDTH = 0.02, 0.004         # stiffener section (m): depth along z, width along y


def stiffener() -> BeamProperty:
    """The rectangular stiffener's section; torsion constant β h w³ after Roark,
    β = 1/3 - 0.21 w/h (1 - w⁴/12h⁴)."""
    beta = 1 / 3 - 0.21 * WIDTH / HEIGHT * (1 - (WIDTH / HEIGHT) ** 4 / 12)
    return BeamProperty(area=HEIGHT * WIDTH, iy=WIDTH * HEIGHT**3 / 12, iz=HEIGHT * WIDTH**3 / 12,
                        j=beta * HEIGHT * WIDTH**3, e=PLATE.e, g=PLATE.e / (2 * (1 + PLATE.nu)), rho=PLATE.rho)


def rows(ny: int) -> tuple:
    return (ny // 3, 2 * ny // 3)


def clamped(nodes: dict) -> tuple:
    return tuple((n, d) for n, x in nodes.items() if x[0] == 0.0 for d in ("x", "y", "z", "rx", "ry", "rz"))


def with_beams(nx: int, ny: int, triangles: bool = False) -> FEMesh:
    nodes, shells = grid(nx, ny, A, B, triangles)
    beams = tuple(("stiffener", label(i, j), label(i + 1, j), (0.0, 0.0, 1.0)) for j in rows(ny) for i in range(nx))
    return FEMesh(nodes, shells, beams, {"plate": PLATE}, {"stiffener": stiffener()}, fixed=clamped(nodes))


def with_eccentric_beams(nx: int, ny: int) -> FEMesh:
    """The stiffeners as beams on their own centroid line, HEIGHT/2 + t/2 above the plate's mid-plane, each node
    held to the plate node below by an RBE2 (all six DOFs): the usual model of an eccentric stiffener."""
    nodes, shells = grid(nx, ny, A, B)
    fixed = clamped(nodes)                  # the plate's edge; the stiffeners' end nodes follow through the RBE2
    offset = 0.5 * HEIGHT
    nodes = dict(nodes)
    nodes.update({f"s{label(i, j)}": (A * i / nx, B * j / ny, offset) for j in rows(ny) for i in range(nx + 1)})
    beams = tuple(("stiffener", f"s{label(i, j)}", f"s{label(i + 1, j)}", (0.0, 0.0, 1.0))
                  for j in rows(ny) for i in range(nx))
    rigid = tuple((label(i, j), (f"s{label(i, j)}",), ("x", "y", "z", "rx", "ry", "rz"))
                  for j in rows(ny) for i in range(nx + 1))
    return FEMesh(nodes, shells, beams, {"plate": PLATE}, {"stiffener": stiffener()}, fixed=fixed, rigid=rigid)


def with_webs(nx: int, ny: int, nz: int = 2, triangles: bool = False) -> FEMesh:
    """The stiffeners as shell webs HEIGHT tall (nz elements), standing on the plate's nodes (a T-junction: the
    plate's bending meets the web's membrane through the drilling and rotation DOFs)."""
    nodes, shells = grid(nx, ny, A, B, triangles)
    nodes, shells = dict(nodes), list(shells)
    for j in rows(ny):
        def at(i, k):
            return label(i, j) if k == 0 else f"web{j}_{i}_{k}"
        for k in range(1, nz + 1):
            nodes.update({at(i, k): (A * i / nx, B * j / ny, HEIGHT * k / nz) for i in range(nx + 1)})
        shells += [("web", (at(i, k), at(i + 1, k), at(i + 1, k + 1), at(i, k + 1))) for k in range(nz)
                   for i in range(nx)]
    return FEMesh(nodes, tuple(shells), (), {"plate": PLATE, "web": WEB}, fixed=clamped(nodes))


def opensees_hz(mesh: FEMesh, n_modes: int) -> np.ndarray:
    """The lowest frequencies (Hz) of a shell-and-beam FEMesh (one shell and one beam property, fixed DOFs) by
    OpenSees: ShellMITC4 quads or ShellDKGT triangles (discrete Kirchhoff bending, a thin-plate theory) on an
    ElasticMembranePlateSection, elasticBeamColumn with a Linear transformation, each element's own mass,
    ARPACK."""
    import openseespy.opensees as ops

    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    # an RBE2 that carries a beam's end (all six DOFs) becomes the beam's rigid joint offset
    follows = {dep: ind for ind, deps, _ in mesh.rigid for dep in deps}
    tag = {n: t + 1 for t, n in enumerate(n for n in mesh.nodes if n not in follows)}
    for n in tag:
        ops.node(tag[n], *map(float, mesh.nodes[n]))
    held: dict = {}
    for n, d in (f for f in mesh.fixed if f[0] in tag):
        held.setdefault(n, [0] * 6)["x y z rx ry rz".split().index(d)] = 1
    for n, flags in held.items():
        ops.fix(tag[n], *flags)
    (sname, sp), = mesh.shell_properties.items()
    ops.section("ElasticMembranePlateSection", 1, sp.e, sp.nu, sp.thickness, sp.rho)
    eid = 0
    for _, conn in mesh.shells:
        eid += 1
        ops.element("ShellMITC4" if len(conn) == 4 else "ShellDKGT", eid, *[tag[n] for n in conn], 1)
    for t, (name, n1, n2, v) in enumerate(mesh.beams):
        p = mesh.beam_properties[name]
        ends = [follows.get(n1, n1), follows.get(n2, n2)]
        offsets = [np.subtract(mesh.nodes[n], mesh.nodes[e]) for n, e in zip((n1, n2), ends)]
        ops.geomTransf("Linear", 100 + t, *map(float, v), "-jntOffset", *map(float, np.concatenate(offsets)))
        eid += 1
        ops.element("elasticBeamColumn", eid, tag[ends[0]], tag[ends[1]], p.area, p.e, p.g, p.j, p.iy, p.iz, 100 + t,
                    "-mass", p.rho * p.area)
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("UmfPack")
    lam = np.array(ops.eigen("-genBandArpack", n_modes))
    ops.wipe()
    return np.sqrt(lam) / (2 * np.pi)
