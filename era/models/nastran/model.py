"""A Nastran deck as a model explain() can vary (its core protocol: params, sensors, with_params, modes,
node_modes): a property off by a factor re-assembles the deck with the changed card; a point mass, a spring to
ground, a part stiffer or heavier change the assembled matrices.

Keywords (``DeckModel.with_params``): stiffness_factor (every stiffness, the global nuisance); property_at (a
change key, "PSHELL 3 T", "MAT1 1 E", "PBAR 7 I": era.models.nastran.mesh.CHANGEABLE) with property_factor;
point_mass_at (a grid, str) with point_mass_kg (the model's mass unit, on its translations); spring_at ("grid
direction", e.g. "12 z") with spring_stiffness (force per length); part_at (a part, "PSHELL 3") with part_factor
(its stiffness) and part_mass_factor (its mass).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...errors import DataError
from ...fem.eigen import sparse_modes
from .deck import Deck
from .mesh import CHANGEABLE, change_key
from .reader import NastranModel, deck_model

DEFAULTS = {"stiffness_factor": 1.0, "property_at": None, "property_factor": 1.0, "point_mass_at": None,
            "point_mass_kg": 0.0, "spring_at": None, "spring_stiffness": 0.0, "part_at": None, "part_factor": 1.0,
            "part_mass_factor": 1.0}


def property_keys(deck: Deck) -> tuple[str, ...]:
    """Every property change a factor can make in ``deck``: "PSHELL 3 T", "MAT1 1 E", "PBAR 7 I", ..."""
    keys = [change_key("PSHELL", p, "T") for p in sorted(deck.shell_sections)]
    keys += [change_key("MAT1", m, "E") for m in sorted(deck.materials)]
    keys += [change_key(s.kind, p, "A" if s.kind == "PROD" else "I") for p, s in sorted(deck.line_sections.items())]
    return tuple(k for k in keys if k.split()[2] in CHANGEABLE[k.split()[0]])


@dataclass(frozen=True, eq=False)
class DeckModel:
    """A deck and a parameter set (DEFAULTS' keywords), with the sensors ((grid, direction), ...) whose shapes
    .modes returns; models of one deck share their solved matrices (``cache``)."""

    deck: Deck
    sensors: tuple
    p: dict = field(default_factory=lambda: dict(DEFAULTS))
    cache: dict = field(default_factory=dict)

    @classmethod
    def of(cls, model: NastranModel, sensors) -> "DeckModel":
        """The nominal DeckModel of a read deck (era.models.nastran.read_bdf) at ``sensors``."""
        if model.deck is None:
            raise DataError("this model was not read from a Nastran deck; use read_bdf.")
        out = cls(model.deck, tuple((str(g), str(d)) for g, d in sensors), dict(DEFAULTS), {(): model})
        for g, d in out.sensors:
            model.index(g, d)            # every sensor must be a free DOF: a clear error now, not in a solve
        return out

    @property
    def params(self) -> dict:
        return dict(self.p)

    def with_params(self, **changes) -> "DeckModel":
        unknown = set(changes) - set(DEFAULTS)
        if unknown:
            raise DataError(f"unknown deck-model keywords {sorted(unknown)}; use {sorted(DEFAULTS)}.")
        return DeckModel(self.deck, self.sensors, {**self.p, **changes}, self.cache)

    def matrices(self) -> NastranModel:
        """The deck assembled with this parameter set's property change (cached per change)."""
        key = () if self.p["property_at"] is None else (self.p["property_at"], float(self.p["property_factor"]))
        got = self.cache.get(key)
        if got is None:
            got = self.cache[key] = deck_model(self.deck, {key[0]: key[1]} if key else None)
        return got

    def _solve(self, n_modes: int):
        m = self.matrices()
        K = m.stiffness * float(self.p["stiffness_factor"])
        M = m.mass.tolil(copy=True) if self.p["point_mass_at"] is not None else m.mass
        part = self.p["part_at"]
        if part is not None:
            if part not in m.parts:
                raise DataError(f"part {part!r} is not in the deck; its parts are {sorted(m.parts)}.")
            K = K + (float(self.p["part_factor"]) - 1) * float(self.p["stiffness_factor"]) * m.parts[part]
            M = M + (float(self.p["part_mass_factor"]) - 1) * m.part_masses[part]
        if self.p["point_mass_at"] is not None:
            M = M.tolil()
            for d in ("x", "y", "z"):
                key = (str(self.p["point_mass_at"]), d)
                if key in m.dof_index:
                    M[m.dof_index[key], m.dof_index[key]] += float(self.p["point_mass_kg"])
        if self.p["spring_at"] is not None:
            grid, d = str(self.p["spring_at"]).split()
            K = K.tolil()
            i = m.index(grid, d)
            K[i, i] += float(self.p["spring_stiffness"])
        return m, sparse_modes(K.tocsr(), M.tocsr(), min(n_modes, m.n_dofs - 1))

    def node_modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) and mass-normalised shapes at every free translation (n_translations, n)."""
        m, (f, phi) = self._solve(n_modes)
        rows = np.array([i for i, (_, d) in enumerate(m.dofs) if d in ("x", "y", "z")], dtype=int)
        return f, phi[rows]

    def modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (n,) Hz and mass-normalised shapes at the sensors (p, n)."""
        m, (f, phi) = self._solve(n_modes)
        rows, signs = m.at(self.sensors)
        return f, phi[rows] * signs[:, None]
