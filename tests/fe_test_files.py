"""A small FE model and a test simulated on it, for the app's tests of an uploaded FE model (tests/app,
tests/e2e).

The structure: a cantilever steel plate, 600 × 400 × 5 mm, CQUAD4 6 × 4, clamped along x = 0, written as a
Nastran deck. The test: pulse responses at eight points (z), struck at two, simulated from the modes of the deck's
matrices with 1.5 kg hidden on node 28 (free edge, y = 0.3 m; not in the model), solved by scipy's dense eigh
(not era's sparse eigensolver); 1 % damping, 0.3 % noise. The last point's label, "TIP z", names no model node.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

import era

NX, NY, A, B, T = 6, 4, 0.6, 0.4, 0.005
HIDDEN_NODE, HIDDEN_KG = "28", 1.5
#: The test's points: node, direction as the data label them (the forms engineers write), and where the data is.
POINTS = [("4:z", "4"), ("7 +Z", "7"), ("13z", "13"), ("18Z", "18"), ("21 z", "21"), ("25z", "25"),
          ("32z", "32"), ("TIP z", "35")]
STRUCK = (1, 4)      # outputs 7 +Z and 21 z are also the hammer points


def grid_id(i: int, j: int) -> int:
    return 1 + i + (NX + 1) * j


def deck() -> str:
    lines = ["SOL 103", "CEND", "BEGIN BULK", "MAT1,1,2.1+11,,0.3,7850.", f"PSHELL,1,1,{T},1", "EIGRL,10,,,8"]
    for j in range(NY + 1):
        for i in range(NX + 1):
            lines.append(f"GRID,{grid_id(i, j)},,{A * i / NX:.6g},{B * j / NY:.6g},0.")
    eid = 1
    for j in range(NY):
        for i in range(NX):
            lines.append(f"CQUAD4,{eid},1,{grid_id(i, j)},{grid_id(i + 1, j)},{grid_id(i + 1, j + 1)},"
                         f"{grid_id(i, j + 1)}")
            eid += 1
    lines.append("SPC1,1,123456," + ",".join(str(grid_id(0, j)) for j in range(NY + 1)))
    lines.append("ENDDATA")
    return "\n".join(lines) + "\n"


def simulated(model: era.MatrixModel, n_samples: int = 1200, dt: float = 1 / 800) -> era.ResponseData:
    """Pulse responses of the model with the hidden mass, at POINTS, struck at STRUCK (dense eigh)."""
    m = model.mass.toarray()
    for d in ("x", "y", "z"):
        k = model.index(HIDDEN_NODE, d)
        m[k, k] += HIDDEN_KG
    lam, phi = scipy.linalg.eigh(model.stiffness.toarray(), m)
    keep = np.flatnonzero(np.sqrt(lam) / (2 * np.pi) < 0.4 / dt)[:12]
    wn, phi = np.sqrt(lam[keep]), phi[:, keep]
    rows = [model.index(node, "z") for _, node in POINTS]
    zeta = 0.01
    wd = wn * np.sqrt(1 - zeta**2)
    t = np.arange(n_samples) * dt
    h = np.exp(-zeta * wn * t[:, None]) * np.sin(wd * t[:, None]) / wd           # (N, modes)
    out = phi[rows]
    y = np.einsum("kr,pr,mr->kpm", h, out, out[list(STRUCK)]) * dt
    rng = np.random.default_rng(3)
    y += 0.003 * np.std(y) * rng.standard_normal(y.shape)
    return era.ResponseData(y, dt, outputs=tuple(label for label, _ in POINTS),
                            inputs=tuple(POINTS[k][0] for k in STRUCK))
