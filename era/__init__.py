"""ERA: the Eigensystem Realization Algorithm of Juang & Pappa (1985) for modal identification.

Pure numerics (numpy/scipy); no web dependency.
"""

from .data import ResponseData
from .errors import DataError, EraError, HankelError, OrderError
from .geometry import Geometry
from .indicators import mac
from .modal import ModalModel
from .realization import Identification, identify
from .stabilization import StableMode, Stabilization, stabilization

__all__ = [
    "ResponseData", "Geometry", "identify", "Identification", "stabilization", "Stabilization", "StableMode", "ModalModel", "mac",
    "EraError", "DataError", "HankelError", "OrderError",
]
