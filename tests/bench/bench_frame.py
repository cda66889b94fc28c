"""Speed of era.Frame.modes(10) on a 3-D frame of 200 nodes: the model step explain will pay per candidate.

Run: python3 -m pytest tests/bench/bench_frame.py -s
The frame: a steel building 5 × 5 bays of 1.2 m in plan, 8 levels of 0.9 m (200 nodes, 455 members, fixed bases,
1 kg on each floor node). Reference: one sparse factorization of the stiffness on the free DOFs of the mesh that
modes(10) chooses (era.fem.space.factor: SuperLU, minimum degree, symmetric mode), in the same process. A fresh
Frame's modes(10) (the automatic mesh: two solves, each a static self-weight solve when gravity is on and a
shift-invert Lanczos run) is timed as a ratio to it. Measured: 14× (17× with gravity), 0.15 s; the Lanczos solves
and the four factorizations dominate, then the meshing.
"""

import numpy as np
import pytest

from era.fem import space
from era.structure import Frame, Section
from timing import median_time

BAYS, LEVELS, BAY_M, STOREY_M = 5, 8, 1.2, 0.9


def building(gravity=None) -> Frame:
    nodes = {f"{i}.{j}.{k}": (i * BAY_M, j * BAY_M, k * STOREY_M)
             for k in range(LEVELS) for j in range(BAYS) for i in range(BAYS)}
    members = [(f"{i}.{j}.{k}", f"{i}.{j}.{k + 1}", "col")
               for k in range(LEVELS - 1) for j in range(BAYS) for i in range(BAYS)]
    members += [(f"{i}.{j}.{k}", f"{i + 1}.{j}.{k}", "beam") for k in range(1, LEVELS) for j in range(BAYS)
                for i in range(BAYS - 1)]
    members += [(f"{i}.{j}.{k}", f"{i}.{j + 1}.{k}", "beam") for k in range(1, LEVELS) for j in range(BAYS - 1)
                for i in range(BAYS)]
    return Frame(nodes=nodes, members=members,
                 sections={"col": Section.square_tube(0.06, 0.004), "beam": Section.rectangle(0.05, 0.1)},
                 supports={f"{i}.{j}.0": "fixed" for j in range(BAYS) for i in range(BAYS)},
                 masses={n: 1.0 for n in nodes if not n.endswith(".0")},
                 sensors=[(f"{BAYS - 1}.{BAYS - 1}.{LEVELS - 1}", "x"), (f"0.0.{LEVELS - 1}", "y")], gravity=gravity)


@pytest.mark.parametrize("gravity", [None, (0.0, 0.0, -9.81)], ids=["no gravity", "gravity"])
def test_modes10_of_a_200_node_frame_against_one_factorization(gravity):
    frame = building(gravity)
    assert len(frame.nodes) == 200
    mesh, _ = frame.solution(10)
    K = space.stiffness(mesh)
    free = ~mesh.restrained.ravel()
    kff = K[free][:, free].tocsc()
    reference = median_time(lambda: space.factor(kff), repeat=9)
    t = median_time(lambda: building(gravity).modes(10), repeat=5)
    f, _ = frame.modes(10)
    print(f"\n[{'gravity' if gravity else 'no gravity'}] 200 nodes, {len(frame.members)} members -> "
          f"{mesh.elements.shape[0]} elements, {int(free.sum())} free DOFs; modes(10) {t * 1e3:.0f} ms = "
          f"{t / reference:.0f}× one factorization of K ({reference * 1e3:.1f} ms); f = {np.round(f[:4], 2)} Hz")
    assert t / reference < 40
