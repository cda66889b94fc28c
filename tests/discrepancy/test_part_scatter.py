"""An FE model's own scatter as a correlated error (era/discrepancy/correlated.py, part_scatter.py): the whitening
against shared causes equals the dense covariance's solve, and a deck's causes are its parts, its PSHELL
thicknesses and its springs to ground."""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from shell_truth import nominal, plate  # noqa: E402

from era.discrepancy.correlated import correlated_errors  # noqa: E402
from era.discrepancy.deck_model import DeckExplainModel  # noqa: E402
from era.discrepancy.fitting import ErrorLevels  # noqa: E402
from era.discrepancy.part_scatter import SUPPORT_SCATTER, THICKNESS_SCATTER, causes  # noqa: E402


def test_the_whitened_misfit_is_the_misfit_under_the_shared_causes_covariance():
    """r'ᵀr' = rᵀ (I + G Gᵀ)⁻¹ r (numpy's dense solve, not the SVD the module uses), also with a zero column."""
    rng = np.random.default_rng(5)
    g = np.column_stack([rng.normal(size=(40, 3)), np.zeros(40)])
    r = rng.normal(size=40)
    white = correlated_errors(g).whiten(r)
    assert np.isclose(white @ white, r @ np.linalg.solve(np.eye(40) + g @ g.T, r), rtol=1e-12)
    assert correlated_errors(np.zeros((40, 2))) is None


def test_a_decks_scatter_causes_are_its_parts_thicknesses_and_springs_to_ground(tmp_path):
    """The plate on elastic edges: 3 PSHELL parts (stiffness at the member scatter), their 3 thicknesses (bending
    × (1 + 3e), mass × (1 + e)), and every CELAS2 to ground (z along the short edges, x and y at the corners) at
    the support scatter, on one side."""
    model = nominal("plate", str(tmp_path), (6, 4))
    got = causes(DeckExplainModel.of(model, model.sensors), ErrorLevels(member_scatter=0.02))
    s = plate(6, 4)
    assert [(c.label, c.sigma) for c in got[:6]] == [(f"part:PSHELL {p}", 0.02) for p in (1, 2, 3)] + [
        (f"PSHELL {p} T", THICKNESS_SCATTER) for p in (1, 2, 3)]
    assert got[3].changes(0.01) == {"part_at": "part:PSHELL 1", "part_factor": 1.03, "part_mass_at": "part:PSHELL 1",
                                    "part_mass_factor": 1.01}
    springs = got[6:]
    assert sorted(c.label for c in springs) == sorted(f"{n}:{d}" for n, d, _ in s["springs"])
    assert all(c.sigma == SUPPORT_SCATTER and not c.central for c in springs)
    z = next(c for c in springs if c.label.endswith(":z"))
    assert z.changes(0.01) == {"spring_at": z.label, "spring_stiffness": 0.01 * 2.0e4 * 8 / 4}
