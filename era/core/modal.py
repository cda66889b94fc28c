"""The modal model: eigensolution of a realization (eqs. 40-41, era/core/decomposition.py), its indicators, reduction
and reconstruction."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from . import indicators
from .decomposition import ModalDecomposition, continuous_eigenvalues, decompose, modal_sum, mode_order
from ..errors import EraError
from .selection import kept_modes


@dataclass(frozen=True, eq=False)
class ModalModel:
    """A realized discrete-time model x(k+1) = A x(k) + B u(k), y(k) = C x(k) and its modes.

    Made by :meth:`Identification.realize` (or ``model``); :meth:`select` keeps some modes. Modes are sorted by
    frequency (then by |s|). Modes whose eigenvalues coincide within their uncertainty (a repeated mode) are given
    the basis of their eigenspace that makes their shapes most real (align_repeated).

    Attributes
    ----------
    A : ndarray, shape (n, n)
        State matrix: real, discrete time, sampling interval ``dt`` seconds. From
        :meth:`Identification.realize` in the balanced form of eq. 34; after :meth:`select`, in real modal form
        (2 × 2 blocks as in eq. 57).
    B : ndarray, shape (n, m)
        Input matrix, in the same state basis.
    C : ndarray, shape (p, n)
        Output matrix, in the same state basis.
    dt : float
        Δτ in seconds.
    z : complex ndarray, shape (modes,)
        Discrete eigenvalues, one per mode (the member with Im z ≥ 0 of each pair).
    shapes : complex ndarray, shape (p, modes)
        Sensor modal displacements E_p^T P_d ψ (eq. 46), largest component 1.
    amplitudes : complex ndarray, shape (modes, m)
        Initial modal amplitudes ψ^{-1} Q^T E_m (eq. 42), scaled so that shapes·amplitudes is the response.
    emac : ndarray, shape (modes,)
        Modal amplitude coherence γ (eq. 43), in [0, 1].
    mpc : ndarray, shape (modes,)
        Modal phase collinearity μ, in [0, 1].
    contribution : ndarray, shape (modes,)
        Each mode's Frobenius norm in H(0) (units of the singular values): see indicators.contribution.
    is_pair : bool ndarray, shape (modes,)
        True for a complex-conjugate pair, False for a real pole.
    outputs : tuple of str
        Output channel labels (p).
    inputs : tuple of str
        Input labels (m).
    method : str
        "ERA", "A1" or "A2".
    frequency_std_hz : ndarray, shape (modes,)
        Standard deviation of the damped frequency (Hz) that the data determine, to first order from the scatter
        of the Hankel matrices (era.core.uncertainty: residual blocks of the record, or the records' scatter).
        A 95 % interval is value ± 1.96·std (:meth:`frequency_interval_hz`). NaN where not computed (A1/A2, or
        ``uncertainty=False``). For a repeated mode (a cluster, see era.core.modal.align_repeated) the largest of
        the cluster's.
    damping_std : ndarray, shape (modes,)
        The same for the damping ratio (:meth:`damping_interval`).
    uncertainty_source : str
        Which covariance gave them: "σ from N records" (the scatter of independent records) or "σ from one
        record's residuals" (residual blocks); "" when not computed.
    points : tuple of str
        A label per measured point, each once: by default the outputs. A test whose inputs were at known
        points (a roving hammer) or a merge of several setups (era.merge_setups) adds the struck points and the
        roving sensors.
    point_shapes : complex ndarray, shape (n_points, modes)
        The mode shape at each of ``points``, largest component 1: by default ``shapes``.

    References
    ----------
    Juang & Pappa (1985), eqs. 34 (the realization), 40-42 and 46 (the modes), 43 (EMAC).

    Examples
    --------
    The realization of order 10 of the paper's Case I, and its first two modes kept:

    >>> from era.examples import paper_cases
    >>> data = paper_cases.case_1()
    >>> model = era.identify(data, 40, 40).realize(10)
    >>> model.order, model.n_modes, model.outputs, model.method
    (10, 5, ('sensor 1',), 'ERA')
    >>> print(np.round(model.frequency_hz, 4), np.round(model.damping_ratio, 4))
    [0.1592 0.3183 0.4775 0.6366 0.7958] [0.01 0.01 0.01 0.01 0.01]
    >>> print(np.round(model.emac, 3), np.round(model.mpc, 3))
    [1. 1. 1. 1. 1.] [1. 1. 1. 1. 1.]
    >>> low = model.select([0, 1])
    >>> low.order, low.reconstruct(200).shape
    (4, (200, 1, 1))
    >>> print(np.round(model.fit_error(data.markov), 6))
    [[0.]]
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    dt: float
    z: np.ndarray
    shapes: np.ndarray
    amplitudes: np.ndarray
    emac: np.ndarray
    mpc: np.ndarray
    contribution: np.ndarray
    is_pair: np.ndarray
    outputs: tuple = ()
    inputs: tuple = ()
    method: str = "ERA"
    frequency_std_hz: np.ndarray | None = None
    damping_std: np.ndarray | None = None
    uncertainty_source: str = ""
    points: tuple = ()
    point_shapes: np.ndarray | None = None

    def __post_init__(self):
        if not self.points and self.point_shapes is None:  # by default the points are the sensors
            object.__setattr__(self, "points", tuple(self.outputs))
            object.__setattr__(self, "point_shapes", self.shapes)

    # ---- derived modal parameters -------------------------------------------------------------
    @property
    def order(self) -> int:
        """n, the state dimension."""
        return self.A.shape[0]

    @property
    def n_modes(self) -> int:
        return len(self.z)

    @property
    def eigenvalues(self) -> np.ndarray:
        """Continuous-time eigenvalues s (rad/s), shape (modes,): s = ln(z)/Δτ (eq. 41), Im s ≥ 0."""
        return continuous_eigenvalues(self.z, self.dt)

    @property
    def frequency_hz(self) -> np.ndarray:
        """Damped natural frequency Im(s)/2π in Hz, shape (modes,); 0 for a real positive pole.

        The paper's eq. 41 reads the damped frequency off Im s. Modes above the Nyquist frequency
        1/(2Δτ) alias below it; a real negative z sits at the Nyquist frequency.
        """
        return self.eigenvalues.imag / (2 * np.pi)

    @property
    def natural_frequency_hz(self) -> np.ndarray:
        """Undamped natural frequency |s|/2π in Hz, shape (modes,) (what a finite-element model gives)."""
        return np.abs(self.eigenvalues) / (2 * np.pi)

    def frequency_interval_hz(self, level_z: float = 1.959963984540054) -> tuple[np.ndarray, np.ndarray]:
        """(low, high) of the 95 % interval frequency_hz ± 1.96 σ (``level_z`` another normal quantile), Hz.

        Parameters
        ----------
        level_z : float, optional
            The normal quantile of the interval (default 1.96, 95 %).
        """
        f, sd = self.frequency_hz, self._std(self.frequency_std_hz)
        return f - level_z * sd, f + level_z * sd

    def damping_interval(self, level_z: float = 1.959963984540054) -> tuple[np.ndarray, np.ndarray]:
        """(low, high) of the 95 % interval damping_ratio ± 1.96 σ.

        Parameters
        ----------
        level_z : float, optional
            The normal quantile of the interval (default 1.96, 95 %).
        """
        z, sd = self.damping_ratio, self._std(self.damping_std)
        return z - level_z * sd, z + level_z * sd

    def standard_deviations(self) -> tuple[np.ndarray, np.ndarray]:
        """(frequency_std_hz (modes,) Hz, damping_std (modes,)): NaN where the data determined none (or all NaN
        when no uncertainty was computed)."""
        return self._std(self.frequency_std_hz), self._std(self.damping_std)

    def _std(self, value) -> np.ndarray:
        return np.full(self.n_modes, np.nan) if value is None else np.asarray(value, dtype=float)

    @property
    def damping_ratio(self) -> np.ndarray:
        """Damping ratio ζ = -Re(s)/|s|, shape (modes,); negative for a growing (unstable) mode, 0 when s = 0."""
        s = self.eigenvalues
        mag = np.abs(s)
        out = np.zeros(len(s))
        np.divide(-s.real, mag, out=out, where=mag > 0)
        return out

    # ---- model reduction (section III) ---------------------------------------------------------
    def select(self, indices=None, *, min_emac: float | None = None, min_mpc: float | None = None,
               min_contribution: float | None = None, physical_only: bool = False) -> "ModalModel":
        """The reduced model that keeps some modes (model reduction, section III).

        The rule is :func:`era.core.selection.kept_modes` (named modes AND thresholds).

        Parameters
        ----------
        indices : sequence of int or bool mask, optional
            Modes to keep (positions in this model's mode order). Default: all.
        min_emac : float in [0, 1], optional
            Keep only modes with γ ≥ min_emac.
        min_mpc : float in [0, 1], optional
            Keep only modes with μ ≥ min_mpc.
        min_contribution : float, optional
            Keep only modes whose contribution is at least this fraction of the largest one.
        physical_only : bool, optional
            Keep only complex pairs that decay (0 < ζ < 1).

        Returns
        -------
        ModalModel in real modal form: each pair a 2 × 2 block [[Re z, -Im z], [Im z, Re z]], each real
        pole a 1 × 1 block. Its indicators are those of the kept modes.
        """
        return self._subset(kept_modes(self, indices, min_emac=min_emac, min_mpc=min_mpc,
                                       min_contribution=min_contribution, physical_only=physical_only))

    def channel(self, output: int, input: int) -> "ModalModel":
        """The one-channel view: output ``output`` (0..p-1) for input ``input`` (0..m-1), shape (1, 1).

        C keeps that output's row and B that input's column, shapes and amplitudes likewise, so the view
        reconstructs exactly that channel of :meth:`reconstruct` (p·m times less work). γ, μ and the
        contribution stay those of the whole model (they judge a mode, not a channel).

        Parameters
        ----------
        output : int
            The output, 0..p-1.
        input : int
            The input, 0..m-1.

        Raises
        ------
        era.EraError
            For an output or input out of range.
        """
        p, m = self.shapes.shape[0], self.amplitudes.shape[1]
        for value, size, name in ((output, p, "output"), (input, m, "input")):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 0 <= value < size:
                raise EraError(f"`{name}` must be 0..{size - 1} (this model has {size} {name}s), got {value!r}.")
        i, j = int(output), int(input)
        return replace(self, B=self.B[:, j:j + 1], C=self.C[i:i + 1], shapes=self.shapes[i:i + 1],
                       amplitudes=self.amplitudes[:, j:j + 1], outputs=self.outputs[i:i + 1],
                       inputs=self.inputs[j:j + 1])

    def _subset(self, idx: np.ndarray) -> "ModalModel":
        z, c, b, pair = self.z[idx], self.shapes[:, idx], self.amplitudes[idx], self.is_pair[idx]
        n = int(np.sum(np.where(pair, 2, 1)))
        p, m = self.shapes.shape[0], self.amplitudes.shape[1]
        A, B, C = np.zeros((n, n)), np.zeros((n, m)), np.zeros((p, n))
        k = 0
        for j in range(len(idx)):
            if pair[j]:
                # ξ = x1 + i x2 with ξ(k+1) = z ξ(k) + b u and y = 2 Re(c ξ)
                A[k:k + 2, k:k + 2] = [[z[j].real, -z[j].imag], [z[j].imag, z[j].real]]
                B[k], B[k + 1] = b[j].real, b[j].imag
                C[:, k], C[:, k + 1] = 2 * c[:, j].real, -2 * c[:, j].imag
                k += 2
            else:
                A[k, k], B[k], C[:, k] = z[j].real, b[j].real, c[:, j].real
                k += 1
        return replace(self, A=A, B=B, C=C, z=z, shapes=c, amplitudes=b, emac=self.emac[idx],
                       point_shapes=None if self.point_shapes is None else self.point_shapes[:, idx],
                       mpc=self.mpc[idx], contribution=self.contribution[idx], is_pair=pair,
                       frequency_std_hz=self._std(self.frequency_std_hz)[idx],
                       damping_std=self._std(self.damping_std)[idx])

    # ---- reconstruction (eq. 35) ---------------------------------------------------------------
    def reconstruct(self, n_samples: int) -> np.ndarray:
        """Y(k) = C A^k B for k = 0..n_samples-1 from the modes (eq. 35), shape (n_samples, p, m).

        Summed in modal form: Y(k) = Σ_pairs 2 Re(c_j z_j^k b_j) + Σ_real c_j z_j^k b_j.

        Parameters
        ----------
        n_samples : int
            N, the number of samples.

        Raises
        ------
        era.EraError
            For a negative ``n_samples``.
        """
        n_samples = int(n_samples)
        if n_samples < 0:
            raise EraError(f"`n_samples` must be ≥ 0, got {n_samples}.")
        return modal_sum(self.z, self.shapes, self.amplitudes, self.is_pair, n_samples)

    def fit_error(self, markov) -> np.ndarray:
        """Normalised RMS error of the reconstruction against measured Y, per channel: shape (p, m).

        ``markov`` is an (N, p, m) array or a ResponseData. The error of channel (i, j) is
        ‖Y_ij - Ŷ_ij‖ / ‖Y_ij‖ over the N samples (0 is a perfect fit; the fit in percent is 100 (1 - e)).
        A channel that is zero throughout gets 0 if the reconstruction is zero too, else inf.

        Parameters
        ----------
        markov : ndarray, shape (N, p, m), or ResponseData
            The measured pulse responses.

        Raises
        ------
        era.EraError
            When the data's outputs and inputs do not match the model's.
        """
        y = np.asarray(getattr(markov, "markov", markov), dtype=float)
        if y.ndim != 3 or y.shape[1:] != (self.shapes.shape[0], self.amplitudes.shape[1]):
            raise EraError(f"The measured data have shape {y.shape}; this model reconstructs (N, "
                           f"{self.shapes.shape[0]}, {self.amplitudes.shape[1]}).")
        err = np.linalg.norm(y - self.reconstruct(y.shape[0]), axis=0)
        ref = np.linalg.norm(y, axis=0)
        out = np.where(err == 0, 0.0, np.inf)
        np.divide(err, ref, out=out, where=ref > 0)
        return out


def build_model(A, B, C, W, dt, row_shifts, col_shifts, outputs=(), inputs=(), method="ERA", *,
                dec: ModalDecomposition | None = None, frequency_std_hz=None, damping_std=None,
                uncertainty_source: str = "") -> ModalModel:
    """The ModalModel of the realization (A, B, C) whose state history at the column shifts is W (n, s·m).

    ``dec`` is its decomposition when the caller already has it (aligned for repeated modes,
    Identification.model); frequency_std_hz, damping_std : (modes,) in the order of ``dec``, or None.
    """
    if dec is None:
        dec = decompose(A, B, C, W)
    nan = np.full(dec.z.size, np.nan)
    f_std = nan if frequency_std_hz is None else np.asarray(frequency_std_hz, dtype=float)
    d_std = nan if damping_std is None else np.asarray(damping_std, dtype=float)
    growth = indicators.powers(dec.z, col_shifts)  # z_j^{t_i}, shared by γ and the contribution
    gamma = indicators.emac(dec.histories, dec.z, col_shifts, B.shape[1], growth)
    mu = indicators.mpc(dec.shapes)
    contrib = indicators.contribution(dec.shapes, dec.amplitudes, dec.z, row_shifts, col_shifts, dec.is_pair,
                                      growth)
    order = mode_order(dec.z, dt)
    return ModalModel(A=A, B=B, C=C, dt=dt, z=dec.z[order], shapes=dec.shapes[:, order],
                      amplitudes=dec.amplitudes[order], emac=gamma[order], mpc=mu[order],
                      contribution=contrib[order], is_pair=dec.is_pair[order], outputs=tuple(outputs),
                      inputs=tuple(inputs), method=method, frequency_std_hz=f_std[order], damping_std=d_std[order],
                      uncertainty_source=uncertainty_source)
