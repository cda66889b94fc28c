"""``era.simulate``: the public name of :mod:`era.examples.grid_simulation`, the simulated grid test."""

import sys

from .examples import grid_simulation as _grid_simulation

sys.modules[__name__] = _grid_simulation
