"""Simulation against test: which candidate physical effect is the model missing.

explain() runs ERA, pairs the modes with the model, fits every candidate effect of a library (the nominal plus a
global stiffness nuisance plus the effect's parameters), compares them by Bayesian evidence (Laplace, Beck &
Yuen 2004) and names one only when the data clearly support it; while the model with the named effects still
misses the test, a further effect is sought on top of them (search.py, at most three), and nothing is named
unless the named set fits within the measurement error (a χ² test, ranking.adequacy).
"""

from .deck_model import DeckExplainModel
from .effects import EffectSpec, Param
from .effects_deck import deck_effects
from .effects_frame import frame_effects
from .effects_grid import grid_effects
from .effects_matrix import matrix_effects
from .explain import explain
from .explanation import VERDICTS, Explanation, NamedEffect
from .fitting import ErrorLevels, Fit
from .fe_modes import ModeComparison, compare_fe_modes
from .frame_model import FrameModel
from .matrix_model import MatrixExplainModel
from .measured import MeasuredModes, identify_modes, measured_modes, modes_from_arrays
from .overlay import model_response, overlay
from .ranking import RankedEffect

__all__ = ["explain", "Explanation", "NamedEffect", "RankedEffect", "EffectSpec", "Param", "grid_effects",
           "FrameModel", "frame_effects", "MatrixExplainModel", "matrix_effects", "DeckExplainModel",
           "deck_effects", "compare_fe_modes", "ModeComparison",
           "ErrorLevels", "Fit", "MeasuredModes", "identify_modes", "measured_modes", "modes_from_arrays", "VERDICTS",
           "model_response", "overlay"]
