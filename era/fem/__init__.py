"""Finite elements of planar frames and grillages: sections, bar elements, assembly, statics, modes."""

from .frame import Assembled, Frame, assemble_out_of_plane, dof_map, lowest_modes
from .sections import Section, flat_bar
from .statics import G_STANDARD, SelfWeight, self_weight

__all__ = ["Section", "flat_bar", "Frame", "Assembled", "assemble_out_of_plane", "dof_map", "lowest_modes",
           "SelfWeight", "self_weight", "G_STANDARD"]
