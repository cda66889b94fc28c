"""ERA: the Eigensystem Realization Algorithm of Juang & Pappa (1985) for modal identification.

Pure numerics (numpy/scipy); no web dependency. The public names, nothing else.
"""

__version__ = "0.2.0"

# the ERA core: data, one SVD, the realization of every order, the diagram
from .core.data import ResponseData
from .errors import DataError, EraError, HankelError, OrderError, TooLargeError
from .core.geometry import Geometry
from .core.indicators import mac
from .core.modal import ModalModel
from .core.selection import keep_mask, kept_modes
from .core.realization import Identification, identify
from .core.stabilization import StableMode, Stabilization, stabilization

# modes in one click: the default analysis and the automatic choice of the structure's modes
from .choice.choose import Candidate, ModeChoice, choose_modes
from .choice.analysis import AnalysisResult, analyse
from .setups.poser import SetupMerge, merge_setups  # multi-setup tests: one shape through the references
from .setups.references import ReferenceProposal, propose_references, reference_evidence  # references from the data
from .setups.next_references import NextChoice, choose_next, merge_ambient_setups, merge_choosing_next  # NExT refs
from .setups.preger import PregerMerge, merge_correlations  # merging before identifying (PreGER)
from .setups.ambient_references import AmbientReferences, propose_ambient_references  # ambient tests' references
from .setups.correlation_columns import references_only  # NExT with fewer references, from the correlations made

# test data in: readers, writers and pulse responses from every kind of test
from .io import Dataset, ModeSet, load, read_modes_uff, save_modes_uff, save_npz
from .markov import markov_from_ambient, markov_from_decay, markov_from_frf, markov_from_io

# simulation against test: correlation of test and model modes, and which effect the model misses
from .core.correlation import Gap, ModePairing, comac, gap, pair_modes, real_shapes, serep, subspace_mac
from .discrepancy import Explanation, explain

# the engineer's own structure: a 3-D frame model described in SI units, JSON/TOML in and out
from .structure import Frame, Section
from .discrepancy import FrameModel, compare_fe_modes, frame_effects

# the engineer's own FE model: matrices from any FE program, CalculiX's and Nastran's files, the patch
from .models import MatrixModel, load_model, save_model, save_patch
from .discrepancy import MatrixExplainModel, matrix_effects
from .discrepancy import DeckExplainModel, deck_effects

__all__ = [
    "__version__",
    "ResponseData", "Geometry", "identify", "Identification", "stabilization", "Stabilization", "StableMode",
    "analyse", "AnalysisResult", "choose_modes", "ModeChoice", "Candidate", "merge_setups", "SetupMerge",
    "propose_references", "reference_evidence", "ReferenceProposal",
    "merge_ambient_setups", "merge_choosing_next", "choose_next", "NextChoice", "merge_correlations", "PregerMerge",
    "propose_ambient_references", "AmbientReferences", "references_only",
    "ModalModel", "kept_modes", "keep_mask", "mac", "EraError", "DataError", "HankelError", "OrderError",
    "TooLargeError",
    "load", "Dataset", "ModeSet", "read_modes_uff", "save_modes_uff", "save_npz",
    "markov_from_frf", "markov_from_io", "markov_from_ambient", "markov_from_decay",
    "explain", "Explanation", "pair_modes", "ModePairing", "comac", "serep", "gap", "Gap", "real_shapes",
    "subspace_mac", "Frame", "Section", "FrameModel", "frame_effects", "compare_fe_modes",
    "MatrixModel", "load_model", "save_model", "save_patch", "MatrixExplainModel", "matrix_effects",
    "DeckExplainModel", "deck_effects",
]
