"""A deck's matrices as a polynomial in one property's factor, from a few assemblies, so that a fit over the
factor does not re-assemble the deck at every trial.

K and M are linear in a MAT1's E (with G) or RHO, in a bar or beam section's I (I1 and I2: bending stiffness and
the polar mass ρ(I1 + I2)), A or J, and in a PROD's A: two assemblies (factors 1 and 2) give them exactly. In a
PSHELL's thickness the membrane, transverse shear and drilling stiffness and the translational mass go as t, the
bending stiffness and the rotary inertia as t³: a cubic through four assemblies (0.5, 1, 1.5, 2), exact for
quadrilaterals; the triangles' shear stabilisation t²/(t² + 0.1 h²) makes it a close approximation for them
(checked against re-assembly in tests/models/test_nastran_effects.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .deck import Deck
from .reader import NastranModel, deck_model

_SAMPLES = {1: (1.0, 2.0), 3: (0.5, 1.0, 1.5, 2.0)}


@dataclass(frozen=True, eq=False)
class PropertyVariation:
    """K(f) = Σ_k f^k stiffness[k], M(f) = Σ_k f^k mass[k] (csr (n, n) each) for one property change key, and
    each part's the same way ({name: coefficients})."""

    key: str
    stiffness: tuple
    mass: tuple
    parts: dict
    part_masses: dict

    def model(self, nominal: NastranModel, factor: float) -> NastranModel:
        """``nominal`` (the deck as read) with this property times ``factor``: its matrices and parts."""
        return NastranModel(_at(self.stiffness, factor), _at(self.mass, factor), nominal.dofs,
                            coordinates=nominal.coordinates, name=nominal.name, units=nominal.units,
                            parts={n: _at(c, factor) for n, c in self.parts.items()},
                            part_masses={n: _at(c, factor) for n, c in self.part_masses.items()},
                            notes=nominal.notes, deck=nominal.deck, factors={self.key: float(factor)})


def _at(coefficients: tuple, factor: float):
    out = coefficients[0].copy()
    for k, c in enumerate(coefficients[1:], start=1):
        out = out + float(factor) ** k * c
    return out.tocsr()


def property_variation(deck: Deck, key: str, nominal: NastranModel | None = None) -> PropertyVariation:
    """The polynomial of ``deck``'s matrices in the factor on ``key`` ("PSHELL 3 T", "MAT1 1 E", ...); the
    ``nominal`` model (factor 1) when it is already assembled."""
    degree = 3 if key.split()[0] == "PSHELL" else 1
    samples = _SAMPLES[degree]
    models = [nominal if (f == 1.0 and nominal is not None) else deck_model(deck, {key: f}) for f in samples]
    inverse = np.linalg.inv(np.vander(np.array(samples), degree + 1, increasing=True))

    def coefficients(mats):
        return tuple(sum(inverse[k, j] * mats[j] for j in range(len(mats))).tocsr() for k in range(degree + 1))

    return PropertyVariation(key, coefficients([m.stiffness for m in models]), coefficients([m.mass for m in models]),
                             {n: coefficients([m.parts[n] for m in models]) for n in models[0].parts},
                             {n: coefficients([m.part_masses[n] for m in models]) for n in models[0].part_masses})
