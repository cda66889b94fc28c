"""read_bdf: a Nastran bulk-data deck as the engineer's FE model (an era.MatrixModel with the deck's notes)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ...fem.mesh import AssembledMesh, assemble
from ..matrix import MatrixModel
from .constraints import reduce
from .coords import resolve
from .deck import Deck, read_deck
from .mesh import deck_mesh


@dataclass(frozen=True, eq=False, init=False)
class NastranModel(MatrixModel):
    """A MatrixModel read from a Nastran deck: the same matrices, DOFs (grid id, direction in the grid's
    displacement frame), coordinates (basic) and parts ("PSHELL 3", "PCOMP 4", "PSOLID 5", "PBAR 7": each
    property's stiffness and mass).

    A grid's DOFs are Nastran's components 1-6 in its displacement frame CD, as Nastran reports them: "x", "y",
    "z" (and "rx", "ry", "rz" about them) are basic x, y, z for CD 0, the frame's axes for a rectangular CD, and
    the local directions at the grid for a curvilinear one: radial, tangential (θ), axial for a cylindrical CD;
    radial, meridian (θ), azimuth (φ) for a spherical CD. A test's points are matched to them by these names, so
    a sensor on such a grid is read along those directions. Besides MatrixModel's attributes:

    dof_axes : {grid: (3, 3)} the basic directions (columns) of the DOFs "x", "y", "z" of every grid whose CD is
        not basic (to draw or compare its shapes in basic);
    notes : sentences on how the deck was read: the cards not modelled by name and count (one sentence), the
        SPC set, PARAM WTMASS, the DOFs AUTOSPC held;
    deck : the deck's modelled cards (era.models.nastran.deck.Deck), for effects and patches;
    factors : {"PSHELL 3 T": factor, ...} the property changes this model was built with ({} as read).
    """

    notes: tuple = ()
    deck: Deck | None = field(default=None, repr=False)
    factors: dict | None = None
    dof_axes: dict | None = field(default=None, repr=False)

    def __init__(self, stiffness, mass, dofs, *, notes=(), deck=None, factors=None, dof_axes=None, **kwargs):
        super().__init__(stiffness, mass, dofs, **kwargs)
        object.__setattr__(self, "notes", tuple(notes))
        object.__setattr__(self, "deck", deck)
        object.__setattr__(self, "factors", dict(factors or {}))
        object.__setattr__(self, "dof_axes", dict(dof_axes or {}))

    def total_mass(self) -> float:
        """The mass that moves with a rigid translation along basic x, y or z, the largest (rᵀ M r with r the
        translation's components in each grid's displacement frame), in the model's mass unit."""
        if not self.dof_axes:
            return super().total_mass()
        out = 0.0
        for k in range(3):
            r = np.zeros(self.n_dofs)
            for i, (node, d) in enumerate(self.dofs):
                if d in ("x", "y", "z"):
                    r[i] = self.dof_axes[node][k, "xyz".index(d)] if node in self.dof_axes else float(d == "xyz"[k])
            out = max(out, float(r @ (self.mass @ r)))
        return out

    @property
    def unmodelled(self) -> str:
        """The cards not modelled, by name and count, in one sentence ("" when every card is modelled)."""
        return self.deck.unmodelled_sentence() if self.deck is not None else ""


def deck_model(deck: Deck, factors: dict | None = None, units="SI") -> NastranModel:
    """The model of a read deck, its properties multiplied by ``factors`` ({"PSHELL 3 T": 0.9, "MAT1 1 E": 1.1,
    "PBAR 7 I": 0.5, ...}; see era.models.nastran.mesh.CHANGEABLE)."""
    dm = deck_mesh(deck, factors)
    assembled = assemble(dm.mesh)
    ratios = {p.pid: p.bending_ratio for p in deck.shell_sections.values() if abs(p.bending_ratio - 1) > 1e-12}
    if ratios:
        assembled = _bending_ratios(deck, factors, assembled, ratios)
    red = reduce(deck, dm, assembled, resolve(deck.grids, deck.frames)[0])
    coordinates = {label: xyz for label, xyz in dm.positions.items() if "@" not in label}
    notes = [s for s in (deck.unmodelled_sentence(),) if s] + list(deck.notes) + list(red.notes)
    name = deck.path.replace("\\", "/").rsplit("/", 1)[-1]
    return NastranModel(red.stiffness, red.mass, red.dofs, coordinates=coordinates, parts=red.parts,
                        part_masses=red.part_masses, name=name, units=units, notes=notes, deck=deck,
                        factors=factors, dof_axes=dm.cd_axes)


def _bending_ratios(deck: Deck, factors, assembled: AssembledMesh, ratios: dict) -> AssembledMesh:
    """The assembled mesh with each listed PSHELL's bending stiffness times its 12I/T³ (``ratios`` {pid: ratio}).
    A plate's stiffness is a t + b t³ (membrane, transverse shear and drilling; bending): assembled again twice
    as thick, the bending part is (K(2t) − 2 K(t)) / 6 (exact for quadrilaterals; the triangles' shear
    stabilisation makes it close for them). The mass stays the plate's of thickness T."""
    doubled = assemble(deck_mesh(deck, factors, thicker=tuple(ratios)).mesh)
    k, parts = assembled.stiffness, dict(assembled.part_stiffness)
    for pid, ratio in ratios.items():
        name = f"PSHELL {pid}"
        bending = (doubled.part_stiffness[name] - 2 * parts[name]) / 6
        parts[name] = (parts[name] + (ratio - 1) * bending).tocsr()
        k = k + (ratio - 1) * bending
    return replace(assembled, stiffness=k.tocsr(), part_stiffness=parts)


def read_bdf(path, *, units="SI") -> NastranModel:
    """A Nastran bulk-data deck (``.bdf``, ``.dat``, ``.nas``, with its INCLUDE files) as an FE model.

    Parameters
    ----------
    path : the deck's main file.
    units : the deck's unit system (a name of era.models.matrix.UNIT_SYSTEMS or {"mass", "force", "length"});
        a deck does not say its units, frequencies are right in any consistent set (PARAM WTMASS applied).

    Returns
    -------
    NastranModel (an era.MatrixModel): the free DOFs' stiffness and mass, DOFs (grid id, "x".."rz" in the grid's
    displacement frame), coordinates in basic, parts {"PSHELL 3": stiffness}, ``notes`` (the cards not modelled
    in one sentence, and how constraints were read). DataError names the file, line and card of a bad card.
    """
    return deck_model(read_deck(path), units=units)
