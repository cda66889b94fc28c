"""A spectrum of the data to draw under a stabilization diagram: the complex mode indicator function."""

from __future__ import annotations

import numpy as np

from .data import ResponseData


def cmif(data: ResponseData) -> tuple[np.ndarray, np.ndarray]:
    """Complex mode indicator function: the singular values of the pulse responses' spectrum at each frequency.

    The discrete Fourier transform of Y(k) (k = 0..N-1) times Δτ approximates the FRF matrix G(f) (p × m);
    its singular values peak at the damped natural frequencies, and a second curve rising with the first
    flags a repeated root (the paper's Case II).

    Returns
    -------
    frequency_hz : (F,), from 0 to the Nyquist frequency 1/(2Δτ), F = N // 2 + 1
    values : (min(p, m), F), descending at each frequency, in the units of Y times seconds
    """
    spectrum = np.fft.rfft(data.markov, axis=0) * data.dt  # (F, p, m)
    if min(spectrum.shape[1:]) == 1:  # one output or one input: the one singular value is the vector's norm
        values = np.sqrt(np.einsum("fk,fk->f", spectrum.reshape(spectrum.shape[0], -1).conj(),
                                   spectrum.reshape(spectrum.shape[0], -1)).real)[:, None]  # (F, 1)
    else:
        values = np.linalg.svd(spectrum, compute_uv=False)  # (F, min(p, m))
    return np.fft.rfftfreq(data.n_samples, data.dt), np.ascontiguousarray(values.T)
