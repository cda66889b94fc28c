"""The ERA method itself: data in, Hankel matrices, SVD, realization, modal parameters, indicators,
the stabilization diagram, uncertainty, the test's points and the correlation of mode sets.

The names below are this room's public face beside ``era``'s own (the app and other rooms take them from here, not
from the modules)."""

from .decomposition import CLUSTER_SCREEN
from .hankel import MAX_HANKEL_ELEMENTS
from .points import axis_and_sign, channel_points, point_geometry
from .spectrum import cmif
from .stabilization import COHERENT_MIN
from .suggest import HankelChoice, hankel_size, order_cap, order_from_singular_values

__all__ = ["CLUSTER_SCREEN", "MAX_HANKEL_ELEMENTS", "COHERENT_MIN", "HankelChoice", "axis_and_sign", "channel_points",
           "cmif", "hankel_size", "order_cap", "order_from_singular_values", "point_geometry"]
