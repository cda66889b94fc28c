"""``era.grid``: the public name of :mod:`era.examples.grid`, the NASA grid model of the built-in example."""

import sys

from .examples import grid as _grid

sys.modules[__name__] = _grid
