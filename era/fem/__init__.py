"""Finite elements of planar frames and grillages: sections, bar elements, assembly, statics, modes.

3-D frames (era.Frame) live in two modules of their own: ``beam3d`` (the 12-DOF element's matrices) and ``space``
(meshing, assembly, the self-weight solve, the lowest modes).
"""

from .frame import Assembled, Frame, assemble_out_of_plane, dof_map, lowest_modes
from .sections import Section, flat_bar
from .statics import G_STANDARD, SelfWeight, self_weight

__all__ = ["Section", "flat_bar", "Frame", "Assembled", "assemble_out_of_plane", "dof_map", "lowest_modes",
           "SelfWeight", "self_weight", "G_STANDARD"]
