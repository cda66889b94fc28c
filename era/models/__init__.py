"""The engineer's own FE model: matrices from any FE program (MatrixModel), read from files (load_model: Matrix
Market, CalculiX's matrix storage, Nastran bulk data), and a named effect written back in the same terms
(era.models.patch)."""

from .files import load_model
from .matrix import MatrixModel
from .patch import patch_files, save_patch
from .write import save_model

__all__ = ["MatrixModel", "load_model", "save_model", "patch_files", "save_patch"]
