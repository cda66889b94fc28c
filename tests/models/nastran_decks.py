"""Bulk-data decks for the Nastran reader's tests, written from one list of cards in the three field formats
(small field 8 characters with Nastran's exponent-without-E reals, large field 16 characters, free field), and
the analytic truths they are checked against."""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq


def small_real(v: float) -> str:
    """A real in 8 characters at the most digits that fit, Nastran style where it saves room: 2.1E+11 ->
    "2.1+11", 1E-9 -> "1.-9", 7850 -> "7850."."""
    v = float(v)
    for digits in range(8, 0, -1):
        mant, exp = f"{v:.{digits - 1}E}".split("E")
        mant, e = mant.rstrip("0"), int(exp)
        nastran = mant if e == 0 else f"{mant}{'+' if e > 0 else '-'}{abs(e)}"
        plain = f"{v:.{digits}g}"
        plain = None if "e" in plain else (plain if "." in plain else plain + ".")
        for text in (plain, nastran):
            if text and len(text) <= 8:
                return text
    raise ValueError(v)


def _text(v, width: int) -> str:
    if v is None or v == "":
        return ""
    if isinstance(v, (int, np.integer)) or isinstance(v, str):
        return str(v)
    return small_real(v) if width == 8 else f"{float(v):.9E}"


def card_text(name: str, values, style: str) -> str:
    """One card in ``style`` "small", "large" or "free" (continuations: "+" lines, "*" lines, "," lines)."""
    if style == "free":
        vals = [_text(v, 16) if not isinstance(v, float) else repr(v) for v in values]
        lines = [",".join([name] + vals[:8])]
        for k in range(8, len(vals), 8):
            lines.append(",".join([""] + vals[k:k + 8]))
        return "\n".join(lines)
    width, per = (8, 8) if style == "small" else (16, 4)
    vals = [_text(v, width) for v in values]
    lines = []
    for k in range(0, max(len(vals), 1), per):
        head = (name if style == "small" else name + "*") if k == 0 else ("+" if style == "small" else "*")
        lines.append(head.ljust(8) + "".join(v.rjust(width) for v in vals[k:k + per]))
    return "\n".join(lines)


def deck_text(cards, style: str, header: str = "") -> str:
    """A whole deck: an optional executive/case-control header, BEGIN BULK, the cards, ENDDATA."""
    body = "\n".join(card_text(n, v, style) for n, v in cards)
    top = f"{header}\nBEGIN BULK\n" if header else ""
    return f"{top}$ written by tests/models/nastran_decks.py ({style} field)\n{body}\nENDDATA\n"


def plate_cards(nx: int, ny: int, a: float, b: float, t: float, e: float, nu: float, rho: float,
                triangles: bool = False) -> list:
    """A flat rectangular plate a × b in the x-y plane, nx × ny CQUAD4 (or 2 CTRIA3 each), PSHELL 1, MAT1 1,
    simply supported on all edges (SPC1 set 1: w on the edges; u, v and the drilling rotation everywhere, which
    leaves plate bending only)."""
    cards, gid = [], {}
    for j in range(ny + 1):
        for i in range(nx + 1):
            gid[i, j] = 1 + i + j * (nx + 1)
            cards.append(("GRID", [gid[i, j], None, a * i / nx, b * j / ny, 0.0]))
    eid = 0
    for j in range(ny):
        for i in range(nx):
            c = [gid[i, j], gid[i + 1, j], gid[i + 1, j + 1], gid[i, j + 1]]
            if triangles:
                cards += [("CTRIA3", [eid + 1, 1, c[0], c[1], c[2]]), ("CTRIA3", [eid + 2, 1, c[0], c[2], c[3]])]
                eid += 2
            else:
                eid += 1
                cards.append(("CQUAD4", [eid, 1, *c]))
    cards += [("PSHELL", [1, 1, t, 1]), ("MAT1", [1, e, None, nu, rho])]
    edge = [g for (i, j), g in gid.items() if i in (0, nx) or j in (0, ny)]
    cards.append(("SPC1", [1, 126, 1, "THRU", gid[nx, ny]]))
    cards.append(("SPC1", [1, 3, *sorted(edge)]))
    return cards


def plate_frequencies(a: float, b: float, t: float, e: float, nu: float, rho: float, n: int) -> np.ndarray:
    """The lowest n frequencies (Hz) of a simply supported Kirchhoff plate: (π/2)(m²/a² + n²/b²)√(D/ρt)."""
    d = e * t ** 3 / (12 * (1 - nu ** 2))
    f = sorted(np.pi / 2 * (m ** 2 / a ** 2 + k ** 2 / b ** 2) * np.sqrt(d / (rho * t))
               for m in range(1, 8) for k in range(1, 8))
    return np.array(f[:n])


def cantilever_tip_mass(ei: float, mass_per_length: float, length: float, tip_mass: float, tip_inertia: float,
                        n: int, f_max: float) -> np.ndarray:
    """The lowest n bending frequencies (Hz) of an Euler-Bernoulli cantilever with a tip mass and a tip rotary
    inertia, from the roots of the 4 × 4 boundary determinant (w = a cos βx + b sin βx + c cosh βx + d sinh βx;
    w(0) = w'(0) = 0, EI w''(L) = J ω² w'(L), EI w'''(L) = -M ω² w(L))."""
    def det(w):
        beta = (mass_per_length * w ** 2 / ei) ** 0.25

        def row(x, d):
            c, s, ch, sh = np.cos(beta * x), np.sin(beta * x), np.cosh(beta * x), np.sinh(beta * x)
            table = [[c, s, ch, sh], [-s, c, sh, ch], [-c, -s, ch, sh], [s, -c, sh, ch]]
            return np.array(table[d]) * beta ** d
        return np.linalg.det(np.array([row(0, 0), row(0, 1),
                                       ei * row(length, 2) - tip_inertia * w ** 2 * row(length, 1),
                                       ei * row(length, 3) + tip_mass * w ** 2 * row(length, 0)]))
    grid = np.linspace(1.0, 2 * np.pi * f_max, 20000)
    v = np.array([det(w) for w in grid])
    roots = [brentq(det, grid[k], grid[k + 1]) for k in range(len(grid) - 1) if np.sign(v[k]) != np.sign(v[k + 1])]
    return np.array(roots[:n]) / (2 * np.pi)


def every_card() -> list:
    """A small structure with every modelled card: a plate of CQUAD4 and CTRIA3 in a CORD2R frame, a CBAR
    stiffener (PBARL I, offset below the plate), a CBEAM (PBEAM) and a CROD (PROD) leg, a CONM2 with offset and
    inertia, springs (CELAS1/PELAS, CELAS2), an RBE2 spider, SPC and SPC1 of the case control's set 1."""
    cards = [("CORD2R", [3, 0, 0., 0., 1., 0., 0., 2., 1., 0., 1.])]          # shifted up 1, axes as basic
    gid = {}
    for j in range(3):
        for i in range(4):
            gid[i, j] = 100 + 10 * j + i
            cards.append(("GRID", [gid[i, j], 3, 0.25 * i, 0.25 * j, 0.]))
    eid = 1
    for j in range(2):
        for i in range(3):
            c = [gid[i, j], gid[i + 1, j], gid[i + 1, j + 1], gid[i, j + 1]]
            if (i + j) % 2:
                cards += [("CTRIA3", [eid, 1, c[0], c[1], c[2]]), ("CTRIA3", [eid + 1, 1, c[0], c[2], c[3]])]
                eid += 2
            else:
                cards.append(("CQUAD4", [eid, 1, *c]))
                eid += 1
    cards += [("PSHELL", [1, 1, 0.005, 1]), ("MAT1", [1, 7e10, None, 0.33, 2700.]),
              ("MAT1", [2, 2.1e11, 8.1e10, None, 7850.])]
    for i in range(3):
        cards.append(("CBAR", [30 + i, 2, gid[i, 1], gid[i + 1, 1], 0., 0., 1., None, None, None,
                               0., 0., -0.02, 0., 0., -0.02]))
    cards.append(("PBARL", [2, 2, None, "I", None, None, None, None, .03, .02, .02, .002, .003, .003]))
    cards += [("GRID", [1, None, 0., 0., 0.]), ("GRID", [2, None, 0.75, 0., 0.]),
              ("CBEAM", [40, 4, 1, gid[0, 0], 1., 0., 0.]), ("PBEAM", [4, 2, 1e-4, 1e-9, 2e-9, 0., 3e-9]),
              ("CROD", [41, 5, 2, gid[3, 0]]), ("PROD", [5, 2, 5e-5, 1e-9])]
    cards += [("CONM2", [50, gid[3, 2], 0, 0.4, 0.01, 0.02, 0.05, None, 1e-4, 0., 2e-4, 0., 0., 3e-4]),
              ("CELAS1", [51, 6, gid[0, 2], 3]), ("PELAS", [6, 2e4]), ("CELAS2", [52, 5e3, gid[3, 1], 3]),
              ("GRID", [3, None, 0.375, 0.25, 1.2]), ("RBE2", [60, 3, 123456, gid[1, 1], gid[2, 1], gid[1, 2]]),
              ("CONM2", [61, 3, 0, 0.2]),
              ("SPC", [1, 1, 123456, 0., 2, 123, 0.]), ("SPC1", [1, 6, 100, "THRU", 103]),
              ("SPC1", [2, 3, 110])]
    return cards


def stiffened_panel(nx: int, ny: int, nz: int = 2) -> tuple[list, dict]:
    """An aluminium plate 0.6 × 0.4 m, 3 mm (CQUAD4, PSHELL 1), clamped along x = 0 (SPC1 123456), with two
    stiffeners along x on the rows y = 0.4/3 and 0.8/3: webs 20 mm tall and 4 mm thick (CQUAD4, PSHELL 2, nz
    elements up). Returns the deck's cards, and the same structure for an independent solver {"nodes": {label:
    xyz}, "shells": [(property, (n1..n4))], "clamped": [labels], "plate", "web": (t, e, nu, rho)}."""
    a, b, height = 0.6, 0.4, 0.02
    plate, web = (0.003, 70e9, 0.33, 2700.0), (0.004, 70e9, 0.33, 2700.0)
    gid = {(i, j, 0): 1 + i + j * (nx + 1) for j in range(ny + 1) for i in range(nx + 1)}
    nodes = {str(g): (a * i / nx, b * j / ny, 0.0) for (i, j, _), g in gid.items()}
    rows = (ny // 3, 2 * ny // 3)
    for j in rows:
        for k in range(1, nz + 1):
            for i in range(nx + 1):
                gid[i, j, k] = 10000 * k + 100 * j + i
                nodes[str(gid[i, j, k])] = (a * i / nx, b * j / ny, height * k / nz)
    shells = [("plate", tuple(str(gid[c]) for c in ((i, j, 0), (i + 1, j, 0), (i + 1, j + 1, 0), (i, j + 1, 0))))
              for j in range(ny) for i in range(nx)]
    shells += [("web", tuple(str(gid[c]) for c in ((i, j, k), (i + 1, j, k), (i + 1, j, k + 1), (i, j, k + 1))))
               for j in rows for k in range(nz) for i in range(nx)]
    clamped = [n for n, x in nodes.items() if x[0] == 0.0]
    cards = [("GRID", [int(n), None, *x]) for n, x in nodes.items()]
    cards += [("CQUAD4", [k + 1, 1 if p == "plate" else 2, *map(int, q)]) for k, (p, q) in enumerate(shells)]
    cards += [("PSHELL", [1, 1, plate[0], 1]), ("PSHELL", [2, 1, web[0], 1]), ("MAT1", [1, 70e9, None, 0.33, 2700.]),
              ("SPC1", [1, 123456, *map(int, clamped)])]
    return cards, {"nodes": nodes, "shells": shells, "clamped": clamped, "plate": plate, "web": web}
