"""Section properties of PBARL and PBEAML shapes (GROUP MSCBML0) from their dimensions: area, the two bending
inertias and the torsion constant, by the thin-walled formulas.

Axes as in Nastran: the section's y axis is element y (I1 is about element z: bending in plane 1), z is element
z. Heights are along y, widths along z (a BAR of DIM1 × DIM2 has I1 = DIM1·DIM2³/12): an I, CHAN, T or BOX bends
about its strong axis in plane 1. Built from rectangles: A and I about the centroid exactly, J = Σ b t³/3 for open
walls (a solid rectangle's own formula for BAR), Bredt's 4 A_m² / ∮ds/t for BOX and TUBE. The shear centre's
offset from the centroid (channels, angles) is not modelled, as Nastran's PBARL does not either.
"""

from __future__ import annotations

import math

#: the number of dimensions of each shape read
DIMENSIONS = {"ROD": 1, "TUBE": 2, "BAR": 2, "BOX": 4, "I": 6, "CHAN": 4, "T": 4, "L": 4, "H": 4, "CROSS": 4}


def section_properties(shape: str, dims) -> tuple[float, float, float, float]:
    """(A, I1, I2, J) of a PBARL/PBEAML shape, in the deck's length unit (L², L⁴, L⁴, L⁴).

    shape : "ROD", "TUBE", "BAR", "BOX", "I", "CHAN", "T", "L", "H" or "CROSS"; dims : its DIM1, DIM2, ...
    Raises KeyError for another shape, ValueError when a dimension is not positive or walls overlap."""
    d = [float(x) for x in dims]
    if any(x <= 0 for x in d) or len(d) < DIMENSIONS[shape]:
        raise ValueError(f"{shape} needs {DIMENSIONS[shape]} positive dimensions, got {d}")
    if shape == "ROD":
        i = math.pi * d[0] ** 4 / 4
        return math.pi * d[0] ** 2, i, i, 2 * i
    if shape == "TUBE":
        ro, ri = d[0], d[1]
        if ri >= ro:
            raise ValueError("the inner radius DIM2 must be smaller than the outer DIM1")
        i = math.pi * (ro ** 4 - ri ** 4) / 4
        return math.pi * (ro ** 2 - ri ** 2), i, i, 2 * i
    if shape == "BAR":
        b, h = d[0], d[1]
        a, t = max(b, h), min(b, h)
        j = a * t ** 3 * (1 / 3 - 0.21 * t / a * (1 - t ** 4 / (12 * a ** 4)))
        return b * h, b * h ** 3 / 12, h * b ** 3 / 12, j
    rects, j = _walls(shape, d)
    area, i1, i2 = _rectangles(rects)
    return area, i1, i2, j


def _walls(shape: str, d: list) -> tuple[list, float]:
    """The section as rectangles (width along z, height along y, centre z, centre y) and its torsion constant."""
    if shape == "BOX":
        w, h, tf, tw = d[:4]
        _check(2 * tf < h and 2 * tw < w)
        rects = [(w, tf, 0, (h - tf) / 2), (w, tf, 0, -(h - tf) / 2),
                 (tw, h - 2 * tf, (w - tw) / 2, 0), (tw, h - 2 * tf, -(w - tw) / 2, 0)]
        am = (w - tw) * (h - tf)
        return rects, 4 * am ** 2 / (2 * (w - tw) / tf + 2 * (h - tf) / tw)
    if shape == "I":
        h, wb, wt, tw, tb, tt = d[:6]
        _check(tb + tt < h)
        web = h - tb - tt
        rects = [(wb, tb, 0, tb / 2), (wt, tt, 0, h - tt / 2), (tw, web, 0, tb + web / 2)]
        return rects, (wb * tb ** 3 + wt * tt ** 3 + web * tw ** 3) / 3
    if shape == "CHAN":
        w, h, tw, tf = d[:4]
        _check(2 * tf < h and tw < w)
        rects = [(w, tf, w / 2, tf / 2), (w, tf, w / 2, h - tf / 2), (tw, h - 2 * tf, tw / 2, h / 2)]
        return rects, (2 * w * tf ** 3 + (h - 2 * tf) * tw ** 3) / 3
    if shape == "T":
        w, h, tf, tw = d[:4]
        _check(tf < h and tw < w)
        rects = [(w, tf, 0, h - tf / 2), (tw, h - tf, 0, (h - tf) / 2)]
        return rects, (w * tf ** 3 + (h - tf) * tw ** 3) / 3
    if shape == "L":
        w, h, tf, tw = d[:4]
        _check(tf < h and tw < w)
        rects = [(w, tf, w / 2, tf / 2), (tw, h - tf, tw / 2, tf + (h - tf) / 2)]
        return rects, (w * tf ** 3 + (h - tf) * tw ** 3) / 3
    if shape == "H":
        gap, tf2, hf, tw = d[:4]
        _check(tw < hf)
        tf = tf2 / 2
        rects = [(tf, hf, -(gap + tf) / 2, 0), (tf, hf, (gap + tf) / 2, 0), (gap, tw, 0, 0)]
        return rects, (2 * hf * tf ** 3 + gap * tw ** 3) / 3
    if shape == "CROSS":
        arms, tv, hv, ta = d[:4]
        _check(ta < hv)
        rects = [(tv, hv, 0, 0), (arms / 2, ta, -(tv + arms / 2) / 2, 0), (arms / 2, ta, (tv + arms / 2) / 2, 0)]
        return rects, (hv * tv ** 3 + arms * ta ** 3) / 3
    raise KeyError(shape)


def _check(ok: bool) -> None:
    if not ok:
        raise ValueError("the walls are thicker than the section is wide or high")


def _rectangles(rects) -> tuple[float, float, float]:
    """(A, I about the centroidal z axis, I about the centroidal y axis) of rectangles (b_z, h_y, z, y)."""
    area = sum(b * h for b, h, _, _ in rects)
    yc = sum(b * h * y for b, h, _, y in rects) / area
    zc = sum(b * h * z for b, h, z, _ in rects) / area
    i1 = sum(b * h ** 3 / 12 + b * h * (y - yc) ** 2 for b, h, _, y in rects)
    i2 = sum(h * b ** 3 / 12 + b * h * (z - zc) ** 2 for b, h, z, _ in rects)
    return area, i1, i2
