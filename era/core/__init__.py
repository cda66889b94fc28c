"""The ERA method itself: data in, Hankel matrices, SVD, realization, modal parameters, indicators,
the stabilization diagram, uncertainty and the correlation of mode sets."""
