"""A finite-element mesh of shells, beams, point masses and springs (:class:`FEMesh`), and its assembly into the
sparse stiffness and mass of the free DOFs (:func:`assemble`).

Every node carries six DOFs in the basic (global) frame: translations x, y, z (the model's length unit) and
rotations rx, ry, rz (rad). Shells are the flat MITC elements of :mod:`era.fem.shell` (CQUAD4, CTRIA3), beams the
12-DOF Euler-Bernoulli element of :mod:`era.fem.beam3d`; both give consistent mass matrices (the shape functions'
own mass, which converges from above with the stiffness and needs no lumping rule for rotations). Constraints are
eliminated, not penalised: a fixed DOF is dropped, an RBE2 dependent DOF is written through its independent node
(u_d = u_i + θ_i × (x_d - x_i), θ_d = θ_i), so the result holds the free DOFs only.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse

from ..errors import DataError
from . import beam3d, shell, solid
from .sparse import scatter

DIRECTIONS = ("x", "y", "z", "rx", "ry", "rz")
CHUNK = 4096             # shell elements computed at a time


@dataclass(frozen=True)
class ShellProperty:
    """A homogeneous isotropic shell (Nastran PSHELL with one MAT1): thickness (length), Young's modulus e and
    density rho in the model's units, Poisson's ratio nu, non-structural mass nsm per area (kg/m² in SI)."""

    thickness: float
    e: float
    nu: float
    rho: float
    nsm: float = 0.0


@dataclass(frozen=True)
class BeamProperty:
    """A straight prismatic beam section: area, second moments iy (about the local y axis: bending in the local
    x-z plane) and iz (about local z), torsion constant j, moduli e and g, density rho, non-structural mass nsm per
    length (kg/m in SI)."""

    area: float
    iy: float
    iz: float
    j: float
    e: float
    g: float
    rho: float
    nsm: float = 0.0


@dataclass(frozen=True)
class FEMesh:
    """A structure as nodes and elements, all in the basic frame.

    nodes : {label (str): (x, y, z)}.
    shells : (property name, (n1, n2, n3) or (n1, n2, n3, n4)), CTRIA3/CQUAD4 connectivity order (around the edge).
    beams : (property name, n1, n2, orientation (3,)): the orientation lies in the element's local x-z plane (the
        section's local z is its part normal to the axis; Nastran's CBAR vector v lies in the local x-y plane).
    shell_properties, beam_properties : {name: ShellProperty or era.fem.laminate.LaminateProperty},
        {name: BeamProperty}.
    masses : (node, mass, (Ixx, Iyy, Izz)): point masses with rotary inertia about the basic axes (CONM2).
    springs : (node1, dir1, node2 or None, dir2 or None, k): a spring between two DOFs, or to ground (None);
        directions "x", "y", "z", "rx", "ry", "rz" (CELAS1/CELAS2).
    fixed : (node, direction) pairs held at zero (SPC, SPC1).
    rigid : (independent node, (dependent nodes...), directions): RBE2, the dependents' listed DOFs follow the
        independent node as a rigid body.
    shell_offsets : one float per shell (or () for none): the offset of its mid-surface from its nodes' plane
        along its normal (Nastran's ZOFFS; the normal by the right-hand rule around n1, n2, n3).
    solids : (property name, 8, 6 or 4 nodes): CHEXA, CPENTA, CTETRA (era.fem.solid: translations only, a node only
        solids reach has no rotational stiffness); solid_properties : {name: era.fem.solid.SolidProperty}.
    """

    nodes: dict
    shells: tuple = ()
    beams: tuple = ()
    shell_properties: dict = field(default_factory=dict)
    beam_properties: dict = field(default_factory=dict)
    masses: tuple = ()
    springs: tuple = ()
    fixed: tuple = ()
    rigid: tuple = ()
    shell_offsets: tuple = ()
    solids: tuple = ()
    solid_properties: dict = field(default_factory=dict)


@dataclass(frozen=True, eq=False)
class AssembledMesh:
    """The free DOFs' stiffness and mass (n, n) (csr), their labels ``dofs`` ((node, direction) ...), and each
    property's share of them (``part_stiffness``, ``part_mass``: {property name: csr (n, n)}; point masses and
    springs belong to no part)."""

    stiffness: scipy.sparse.csr_matrix
    mass: scipy.sparse.csr_matrix
    dofs: tuple
    part_stiffness: dict
    part_mass: dict


def _direction(d, where: str) -> int:
    try:
        return DIRECTIONS.index(str(d).lower())
    except ValueError:
        raise DataError(f"{where}: direction {d!r} is not one of {', '.join(DIRECTIONS)}.") from None


def _used_nodes(mesh: FEMesh) -> list:
    used = {}
    for _, conn in (*mesh.shells, *mesh.solids):
        used.update(dict.fromkeys(conn))
    for b in mesh.beams:
        used.update(dict.fromkeys(b[1:3]))
    for m in mesh.masses:
        used[m[0]] = None
    for s in mesh.springs:
        used.update(dict.fromkeys(n for n in (s[0], s[2]) if n is not None))
    for ind, deps, _ in mesh.rigid:
        used.update(dict.fromkeys((ind, *deps)))
    missing = [n for n in used if n not in mesh.nodes]
    if missing:
        raise DataError(f"Elements refer to nodes that are not defined: {', '.join(map(str, missing[:10]))}; "
                        "add them to the mesh's nodes.")
    if not used:
        raise DataError(f"The mesh has no element, mass or spring; its {len(mesh.nodes)} nodes "
                        f"({', '.join(map(str, list(mesh.nodes)[:10]))}) touch nothing, so there is nothing to solve.")
    return [n for n in mesh.nodes if n in used]


def _shell_parts(mesh: FEMesh, index: dict, xyz: np.ndarray) -> dict:
    """{property name: (K (e, d, d), M (e, d, d), DOFs (e, d))} of each property's quads and triangles."""
    groups: dict = {}
    if mesh.shell_offsets and len(mesh.shell_offsets) != len(mesh.shells):
        raise DataError(f"shell_offsets has {len(mesh.shell_offsets)} values for {len(mesh.shells)} shells; give "
                        "one per shell.")
    offsets = mesh.shell_offsets or (0.0,) * len(mesh.shells)
    for (name, conn), z in zip(mesh.shells, offsets):
        if name not in mesh.shell_properties:
            raise DataError(f"Shell property {name!r} is not defined; add it to shell_properties.")
        if len(conn) not in (3, 4):
            raise DataError(f"A shell element needs 3 or 4 nodes; {tuple(conn)} has {len(conn)}.")
        groups.setdefault((name, len(conn)), []).append([index[n] for n in conn] + [float(z)])
    out: dict = {}
    for (name, nn), rows in groups.items():
        p = mesh.shell_properties[name]
        fn = shell.quad4_batch if nn == 4 else shell.tria3_batch
        for start in range(0, len(rows), CHUNK):    # bounded memory: a chunk's matrices, never the whole mesh's
            chunk = np.asarray(rows[start:start + CHUNK])
            c, z = chunk[:, :nn].astype(int), chunk[:, nn]
            k, m = fn(xyz[c], p, z if z.any() else None)
            dofs = (6 * c[:, :, None] + np.arange(6)).reshape(len(c), -1)
            out.setdefault(name, []).append((k, m, dofs))
    return out


def _solid_parts(mesh: FEMesh, index: dict, xyz: np.ndarray) -> dict:
    """{property name: [(K, M, DOFs)]} of each property's solids, grouped by their number of nodes."""
    groups: dict = {}
    for name, conn in mesh.solids:
        if name not in mesh.solid_properties:
            raise DataError(f"Solid property {name!r} is not defined; add it to solid_properties.")
        if len(conn) not in (4, 6, 8):
            raise DataError(f"A solid element needs 4, 6 or 8 nodes; {tuple(conn)} has {len(conn)}.")
        groups.setdefault((name, len(conn)), []).append([index[n] for n in conn])
    out: dict = {}
    for (name, _), conns in groups.items():
        for start in range(0, len(conns), CHUNK):
            c = np.asarray(conns[start:start + CHUNK])
            k, m = solid.solid_batch(xyz[c], mesh.solid_properties[name])
            out.setdefault(name, []).append((k, m, (6 * c[:, :, None] + np.arange(3)).reshape(len(c), -1)))
    return out


def _beam_parts(mesh: FEMesh, index: dict, xyz: np.ndarray) -> dict:
    out: dict = {}
    by_name: dict = {}
    for b in mesh.beams:
        by_name.setdefault(b[0], []).append(b)
    for name, beams in by_name.items():
        if name not in mesh.beam_properties:
            raise DataError(f"Beam property {name!r} is not defined; add it to beam_properties.")
        p = mesh.beam_properties[name]
        c = np.array([[index[b[1]], index[b[2]]] for b in beams])
        v = np.array([np.asarray(b[3], float) for b in beams]).reshape(len(beams), 3)
        xi, xj = xyz[c[:, 0]], xyz[c[:, 1]]
        axis = xj - xi
        length = np.linalg.norm(axis, axis=1)
        if np.any(length <= 0):
            raise DataError(f"A beam of property {name!r} has both ends at one point; remove it or move a node.")
        cross = np.linalg.norm(np.cross(axis, v), axis=1)
        if np.any(cross <= 1e-9 * length * np.maximum(np.linalg.norm(v, axis=1), 1e-300)):
            raise DataError(f"A beam of property {name!r} has an orientation vector parallel to its axis (or zero); "
                            "give a vector in the section's local x-z plane.")
        L, R = beam3d.element_axes(xi, xj, v)
        ones = np.ones(len(beams))
        k = beam3d.local_stiffness(L, p.e * p.area * ones, p.g * p.j * ones, p.e * p.iy * ones, p.e * p.iz * ones)
        m = beam3d.local_mass(L, (p.rho * p.area + p.nsm) * ones, p.rho * (p.iy + p.iz) * ones)
        dofs = (6 * c[:, :, None] + np.arange(6)).reshape(len(c), -1)
        out[name] = [(beam3d.to_global(k, R), beam3d.to_global(m, R), dofs)]
    return out


def _constraints(mesh: FEMesh, index: dict, xyz: np.ndarray) -> tuple[scipy.sparse.csr_matrix, np.ndarray]:
    """T (6N, n_free) with u_all = T u_free, and the kept DOFs' indices in the full numbering (n_free,)."""
    n_all = 6 * len(index)
    rows, cols, vals = [], [], []
    dependent = np.zeros(n_all, bool)
    for ind, deps, dirs in mesh.rigid:
        i = index[ind]
        for dep in deps:
            if dep == ind:
                continue
            d = index[dep]
            r = xyz[d] - xyz[i]
            for name in dirs:
                a = _direction(name, f"RBE2 of node {ind}")
                row = 6 * d + a
                dependent[row] = True
                rows.append(row), cols.append(6 * i + a), vals.append(1.0)
                if a < 3:   # u_d = u_i + θ_i × r: component a of θ × r
                    b, c = (a + 1) % 3, (a + 2) % 3
                    rows += [row, row]
                    cols += [6 * i + 3 + b, 6 * i + 3 + c]
                    vals += [r[c], -r[b]]
    keep = np.ones(n_all, bool)
    keep[dependent] = False
    for node, name in mesh.fixed:
        if node not in mesh.nodes:
            raise DataError(f"A fixed DOF names node {node!r}, which is not defined; add the node or drop the SPC.")
        if node in index:
            dof = 6 * index[node] + _direction(name, f"fixed DOF of node {node}")
            if dependent[dof]:
                raise DataError(f"DOF {name} of node {node} is both fixed and an RBE2's dependent DOF; fix the "
                                "RBE2's independent node instead.")
            keep[dof] = False
    ident = np.flatnonzero(~dependent)
    C = scipy.sparse.csr_matrix((np.concatenate([np.ones(ident.size), vals]),
                                 (np.concatenate([ident, rows]).astype(int),
                                  np.concatenate([ident, cols]).astype(int))), shape=(n_all, n_all))
    for _ in range(32):     # chains of RBE2 (a dependent node of one is the independent node of another)
        if C[:, dependent].nnz == 0:
            break
        C = C @ C
    else:
        raise DataError("RBE2 elements form a loop (a node depends on itself through others); break the loop.")
    kept = np.flatnonzero(keep)
    return C[:, kept].tocsr(), kept


def _sum(parts: list, n: int, which: int) -> scipy.sparse.csc_matrix:
    return sum((scatter(p[which], p[2], n) for p in parts), scipy.sparse.csc_matrix((n, n)))


def assemble(mesh: FEMesh) -> AssembledMesh:
    """The stiffness and mass of a mesh's free DOFs, and of each property.

    Nodes no element, mass or spring touches are left out. DOFs are numbered node by node in the order of
    ``mesh.nodes``, x y z rx ry rz within a node, without the fixed and RBE2-dependent ones.
    """
    labels = _used_nodes(mesh)
    index = {n: i for i, n in enumerate(labels)}
    xyz = np.array([np.asarray(mesh.nodes[n], float) for n in labels]).reshape(-1, 3)
    n_all = 6 * len(labels)
    parts = _shell_parts(mesh, index, xyz)
    for name, p in (*_beam_parts(mesh, index, xyz).items(), *_solid_parts(mesh, index, xyz).items()):
        if name in parts:
            raise DataError(f"Property name {name!r} names two kinds of elements (shell, beam, solid); give them "
                            "distinct names.")
        parts[name] = p
    extra_k, extra_m = _extras(mesh, index)
    T, kept = _constraints(mesh, index, xyz)
    Tt = T.T.tocsr()

    def reduce(A):
        return (Tt @ scipy.sparse.csr_matrix(A) @ T).tocsr()

    part_k = {name: reduce(_sum(p, n_all, 0)) for name, p in parts.items()}
    part_m = {name: reduce(_sum(p, n_all, 1)) for name, p in parts.items()}
    K = sum(part_k.values(), reduce(extra_k))
    M = sum(part_m.values(), reduce(extra_m))
    dofs = tuple((labels[i // 6], DIRECTIONS[i % 6]) for i in kept)
    return AssembledMesh(K.tocsr(), M.tocsr(), dofs, part_k, part_m)


def _extras(mesh: FEMesh, index: dict) -> tuple:
    """Point masses (diagonal) and springs, as (n, n) sparse matrices over all DOFs."""
    n_all = 6 * len(index)
    mr, mv = [], []
    for node, m, inertia in mesh.masses:
        mr += [6 * index[node] + a for a in range(6)]
        mv += [m, m, m, *np.asarray(inertia, float).reshape(3)]
    kr, kc, kv = [], [], []
    for n1, d1, n2, d2, k in mesh.springs:
        i = 6 * index[n1] + _direction(d1, f"spring at node {n1}")
        if n2 is None:
            kr.append(i), kc.append(i), kv.append(k)
            continue
        j = 6 * index[n2] + _direction(d2, f"spring at node {n2}")
        kr += [i, j, i, j]
        kc += [i, j, j, i]
        kv += [k, k, -k, -k]
    M = scipy.sparse.csr_matrix((mv, (mr, mr)), shape=(n_all, n_all))
    K = scipy.sparse.csr_matrix((kv, (kr, kc)), shape=(n_all, n_all))
    return K, M
