"""Finite elements of planar frames and grillages (:class:`PlaneFrame`, :class:`BeamSection`): bar elements,
assembly, statics, modes.

3-D frames (era.Frame, era/structure/) are solved by three modules of their own: ``beam3d`` (the 12-DOF element's
matrices), ``space`` (meshing, assembly, the self-weight solve, the lowest modes) and ``solution`` (a described
era.Frame's arrays, mesh and modes); ``reduced`` screens many local changes of one frame.
"""

from .frame import Assembled, PlaneFrame, assemble_out_of_plane, dof_map, lowest_modes
from .sections import BeamSection, flat_bar
from .statics import G_STANDARD, SelfWeight, self_weight

__all__ = ["BeamSection", "flat_bar", "PlaneFrame", "Assembled", "assemble_out_of_plane", "dof_map", "lowest_modes",
           "SelfWeight", "self_weight", "G_STANDARD"]
