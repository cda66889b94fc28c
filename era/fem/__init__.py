"""Finite elements of planar frames and grillages (:class:`PlaneFrame`, :class:`BeamSection`): bar elements,
assembly, statics, modes; meshes of shells and beams (:class:`FEMesh`, :func:`assemble`, flat MITC shells in
``shell``, laminates by classical lamination theory in ``laminate``, linear solids in ``solid``) and the sparse eigensolver every model shares
(:func:`sparse_modes`).

3-D frames (era.Frame, era/structure/) are solved by three modules of their own: ``beam3d`` (the 12-DOF element's
matrices), ``space`` (meshing, assembly, the self-weight solve, the lowest modes) and ``solution`` (a described
era.Frame's arrays, mesh and modes); ``reduced`` screens many local changes of one frame.
"""

from .eigen import sparse_modes
from .frame import Assembled, PlaneFrame, assemble_out_of_plane, dof_map, lowest_modes
from .laminate import LaminateProperty, Ply, stack
from .mesh import AssembledMesh, BeamProperty, FEMesh, ShellProperty, assemble
from .sections import BeamSection, flat_bar
from .solid import SolidProperty
from .statics import G_STANDARD, SelfWeight, self_weight

__all__ = ["BeamSection", "flat_bar", "PlaneFrame", "Assembled", "assemble_out_of_plane", "dof_map", "lowest_modes",
           "SelfWeight", "self_weight", "G_STANDARD",
           "FEMesh", "ShellProperty", "LaminateProperty", "Ply", "stack", "SolidProperty", "BeamProperty", "AssembledMesh", "assemble", "sparse_modes"]
