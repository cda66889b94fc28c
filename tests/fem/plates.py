"""Rectangular plate meshes for the shell tests (era.fem.FEMesh), and Kirchhoff's closed-form frequencies."""

from __future__ import annotations

import numpy as np

from era.fem import FEMesh, ShellProperty

STEEL = ShellProperty(thickness=0.005, e=2.1e11, nu=0.3, rho=7850.0)


def label(i: int, j: int) -> str:
    return f"{i}_{j}"


def grid(nx: int, ny: int, a: float, b: float, triangles: bool = False) -> tuple[dict, tuple]:
    """Nodes {label: (x, y, 0)} on an (nx + 1) x (ny + 1) grid of an a x b plate and its quads, or each quad
    cut in two triangles along alternating diagonals (a criss-cross-free, direction-balanced pattern)."""
    nodes = {label(i, j): (a * i / nx, b * j / ny, 0.0) for j in range(ny + 1) for i in range(nx + 1)}
    shells = []
    for j in range(ny):
        for i in range(nx):
            q = (label(i, j), label(i + 1, j), label(i + 1, j + 1), label(i, j + 1))
            if not triangles:
                shells.append(("plate", q))
            elif (i + j) % 2 == 0:
                shells += [("plate", (q[0], q[1], q[2])), ("plate", (q[0], q[2], q[3]))]
            else:
                shells += [("plate", (q[0], q[1], q[3])), ("plate", (q[1], q[2], q[3]))]
    return nodes, tuple(shells)


def bending_only(nodes: dict) -> list:
    """Hold every node's in-plane DOFs (x, y, rz): a flat plate's bending decouples from them."""
    return [(n, d) for n in nodes for d in ("x", "y", "rz")]


def simply_supported(nx: int, ny: int, a: float, b: float, prop: ShellProperty = STEEL,
                     triangles: bool = False) -> FEMesh:
    """All four edges simply supported: w = 0 and the rotation about the edge's normal (the tangential slope) held,
    the 'hard' support that Kirchhoff's Navier solution assumes."""
    nodes, shells = grid(nx, ny, a, b, triangles)
    fixed = bending_only(nodes)
    for j in range(ny + 1):
        for i in range(nx + 1):
            if i in (0, nx):
                fixed += [(label(i, j), "z"), (label(i, j), "rx")]
            if j in (0, ny):
                fixed += [(label(i, j), "z"), (label(i, j), "ry")]
    return FEMesh(nodes, shells, shell_properties={"plate": prop}, fixed=tuple(dict.fromkeys(fixed)))


def cantilever(n: int, a: float, prop: ShellProperty = STEEL, triangles: bool = False) -> FEMesh:
    """A square a x a plate clamped along x = 0 (all six DOFs), the other edges free."""
    nodes, shells = grid(n, n, a, a, triangles)
    fixed = bending_only(nodes) + [(label(0, j), d) for j in range(n + 1) for d in ("z", "rx", "ry")]
    return FEMesh(nodes, shells, shell_properties={"plate": prop}, fixed=tuple(dict.fromkeys(fixed)))


def navier_hz(a: float, b: float, prop: ShellProperty, count: int) -> np.ndarray:
    """The lowest ``count`` frequencies (Hz) of a simply supported Kirchhoff plate: ω_mn = π² (m²/a² + n²/b²)
    √(D / ρt), D = E t³ / 12(1 - ν²) (S. Timoshenko, *Vibration Problems in Engineering*; A. W. Leissa,
    *Vibration of Plates*, NASA SP-160, 1969, eq. 4.4)."""
    D = prop.e * prop.thickness**3 / (12 * (1 - prop.nu**2))
    omega = [np.pi**2 * (m**2 / a**2 + n**2 / b**2) * np.sqrt(D / (prop.rho * prop.thickness))
             for m in range(1, 12) for n in range(1, 12)]
    return np.sort(omega)[:count] / (2 * np.pi)


def leissa_hz(a: float, prop: ShellProperty, parameters) -> np.ndarray:
    """Frequencies (Hz) of a square Kirchhoff plate of side a from the parameters λ = ω a² √(ρt / D)."""
    D = prop.e * prop.thickness**3 / (12 * (1 - prop.nu**2))
    return np.asarray(parameters) / a**2 * np.sqrt(D / (prop.rho * prop.thickness)) / (2 * np.pi)


def mindlin_hz(a: float, b: float, prop: ShellProperty, count: int, shear_factor: float = 5 / 6) -> np.ndarray:
    """The lowest ``count`` flexural frequencies (Hz) of a simply supported Reissner-Mindlin plate (the tangential
    rotation held on the edges), with shear deformation and rotary inertia. With w and a rotation potential ψ
    (β = ∇ψ) both ∝ sin(mπx/a) sin(nπy/b), k² = (mπ/a)² + (nπ/b)², Mindlin's equations become the 2 x 2 problem
    [[κGt k², κGt k²], [κGt k², D k⁴ + κGt k²]] = ω² diag(ρt, ρt³/12 k²), whose lower root is the flexural mode
    (R. D. Mindlin, J. Appl. Mech. 18, 1951, 31-38)."""
    t, rho = prop.thickness, prop.rho
    D = prop.e * t**3 / (12 * (1 - prop.nu**2))
    s = shear_factor * prop.e / (2 * (1 + prop.nu)) * t
    omega = []
    for m in range(1, 12):
        for n in range(1, 12):
            k2 = (m * np.pi / a) ** 2 + (n * np.pi / b) ** 2
            K = np.array([[s * k2, s * k2], [s * k2, D * k2**2 + s * k2]])
            M = np.diag([rho * t, rho * t**3 / 12 * k2])
            omega.append(np.sqrt(np.min(np.linalg.eigvals(np.linalg.solve(M, K)).real)))
    return np.sort(omega)[:count] / (2 * np.pi)
