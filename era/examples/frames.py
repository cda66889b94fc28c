"""Example structures as era.Frame models (SI units): a cantilever, a 2-D portal, a 3-D two-storey frame, a truss.

Each function returns the nominal model an engineer would draw; era.examples.frame_simulation hides effects in a
truth that differs from it.
"""

from __future__ import annotations

from ..structure import Frame, Section

STRIP = Section.rectangle(width=0.05066, depth=0.00514, material="steel")     # the USC strip, 50.66 × 5.14 mm


def cantilever(length_m: float = 0.759, n_members: int = 4, section: Section = STRIP, **kw) -> Frame:
    """A horizontal cantilever along x, clamped at node "0", ``n_members`` equal members; sensors along z (the
    thin direction) at every free node and along y at the tip."""
    nodes = {str(k): (length_m * k / n_members, 0.0, 0.0) for k in range(n_members + 1)}
    sensors = [(str(k), "z") for k in range(1, n_members + 1)] + [(str(n_members), "y")]
    return Frame(**{**dict(nodes=nodes, members=[(str(k), str(k + 1), "strip") for k in range(n_members)],
                           sections={"strip": section}, supports={"0": "fixed"}, sensors=sensors), **kw})


def portal(span_m: float = 4.0, height_m: float = 3.0, **kw) -> Frame:
    """A single-bay portal in the x-z plane, fixed bases A and D, beam B-E-C with a mid node E; wide flat
    sections (300 × 50 mm) so the out-of-plane modes sit far above the in-plane ones; sensors in the plane."""
    sec = Section.rectangle(width=0.3, depth=0.05, material="steel")
    nodes = {"A": (0, 0, 0), "B": (0, 0, height_m), "E": (span_m / 2, 0, height_m), "C": (span_m, 0, height_m),
             "D": (span_m, 0, 0), "F": (0, 0, height_m / 2), "G": (span_m, 0, height_m / 2)}
    members = [("A", "F", "col"), ("F", "B", "col"), ("B", "E", "beam"), ("E", "C", "beam"), ("C", "G", "col"),
               ("G", "D", "col")]
    sensors = [("F", "x"), ("B", "x"), ("E", "z"), ("E", "x"), ("C", "z"), ("G", "x"), ("B", "z")]
    return Frame(**{**dict(nodes=nodes, members=members, sections={"col": sec, "beam": sec},
                           supports={"A": "fixed", "D": "fixed"}, sensors=sensors), **kw})


def two_storey(bay_x: float = 4.0, bay_y: float = 3.0, storey_m: float = 3.0, **kw) -> Frame:
    """A 3-D two-storey, one-bay frame: four steel tube columns (150 × 8 mm square) fixed at the base, floor
    beams (120 × 6 mm square) at both levels; sensors x and y at two opposite corners of each floor and z at
    the middle of two beams (mid nodes)."""
    col, beam = Section.square_tube(0.15, 0.008), Section.square_tube(0.12, 0.006)
    corners = {"1": (0, 0), "2": (bay_x, 0), "3": (bay_x, bay_y), "4": (0, bay_y)}
    nodes = {}
    for level in range(3):
        for c, (x, y) in corners.items():
            nodes[f"{c}{level}"] = (x, y, level * storey_m)
    members = [(f"{c}{lv}", f"{c}{lv + 1}", "col") for lv in range(2) for c in corners]
    for lv in (1, 2):
        for a, b in (("1", "2"), ("2", "3"), ("3", "4"), ("4", "1")):
            members.append((f"{a}{lv}", f"{b}{lv}", "beam"))
    nodes["m1"] = (bay_x / 2, 0, storey_m)          # mid nodes of two first-floor beams, for z sensors
    nodes["m2"] = (bay_x / 2, bay_y, 2 * storey_m)
    members = [m for m in members if (m[0], m[1]) not in (("11", "21"), ("32", "42"))]
    members += [("11", "m1", "beam"), ("m1", "21", "beam"), ("32", "m2", "beam"), ("m2", "42", "beam")]
    sensors = [("11", "x"), ("11", "y"), ("31", "x"), ("31", "y"), ("12", "x"), ("12", "y"), ("32", "x"),
               ("32", "y"), ("m1", "z"), ("m2", "z")]
    return Frame(**{**dict(nodes=nodes, members=members, sections={"col": col, "beam": beam},
                           supports={f"{c}0": "fixed" for c in corners}, sensors=sensors), **kw})


def truss(panel_m: float = 1.0, depth_m: float = 1.0, **kw) -> Frame:
    """A 4-panel Pratt truss in the x-z plane of welded steel tubes (60 × 4 mm), pinned at both bottom ends,
    the top chord held laterally (y) at its ends; sensors along z on the bottom chord and x on the top."""
    tube = Section.tube(0.06, 0.004)
    nodes = {f"b{k}": (k * panel_m, 0.0, 0.0) for k in range(5)}
    nodes.update({f"t{k}": (k * panel_m, 0.0, depth_m) for k in range(1, 4)})
    members = [(f"b{k}", f"b{k + 1}", "t") for k in range(4)] + [(f"t{k}", f"t{k + 1}", "t") for k in (1, 2)]
    members += [(f"b{k}", f"t{k}", "t") for k in (1, 2, 3)]
    members += [("b0", "t1", "t"), ("t1", "b2", "t"), ("b2", "t3", "t"), ("t3", "b4", "t")]
    sensors = [("b1", "z"), ("b2", "z"), ("b3", "z"), ("t1", "x"), ("t2", "z"), ("t3", "z"), ("t2", "y")]
    return Frame(**{**dict(nodes=nodes, members=members, sections={"t": tube},
                           supports={"b0": "pinned", "b4": "pinned", "t1": {"ky": "fixed"},
                                     "t3": {"ky": "fixed"}}, sensors=sensors), **kw})


STRUCTURES = {"cantilever": cantilever, "portal": portal, "two_storey": two_storey, "truss": truss}


def nasa_grid_frame(**changes) -> Frame:
    """The NASA grid (era.examples.grid) as an era.Frame: 88 joints named "x,y" in feet, the 157 one-foot bars
    (2 in × 1/4 in aluminium, the thin side out of the plane z), hanging in the x-y plane (gravity along -y) from two
    0.51 m cables at (2, 7) and (8, 7) ft, the left cable also holding x; the nine sensors along z. Matches
    nasa_grid() within 1e-5 (tests/fem/test_frame_gravity.py)."""
    from .grid import CABLES_FT, FT, JOINTS_FT, SEGMENT_JOINTS, SENSORS_FT, joint_index
    bar = Section.rectangle(width=2 * 0.0254, depth=0.25 * 0.0254, material="aluminium")
    names = [f"{int(x)},{int(y)}" for x, y in JOINTS_FT]
    left, right = (names[joint_index(c)] for c in CABLES_FT)
    kw = dict(nodes={n: (x * FT, y * FT, 0.0) for n, (x, y) in zip(names, JOINTS_FT)},
              members=[(names[a], names[b], "bar") for a, b in SEGMENT_JOINTS], sections={"bar": bar},
              supports={left: {"cable": 0.51, "kx": "fixed"}, right: {"cable": 0.51}},
              sensors=[(names[joint_index(s)], "z") for s in SENSORS_FT], gravity=(0, -9.80665, 0))
    return Frame(**{**kw, **changes})
