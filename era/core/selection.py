"""Which modes to keep: the one rule for model reduction (section III), the app's γ/μ table and explain's filter.

A mode is kept when its modal amplitude coherence γ (eqs. 42-45) and its modal phase collinearity μ (eqs. 46-54)
reach their thresholds, its contribution reaches a fraction of the largest one, and, when only physical modes are
wanted, it is a complex pair that decays (0 < ζ < 1): real poles and growing poles are computational.
"""

from __future__ import annotations

import numpy as np

from ..errors import EraError


def _fraction(value, name: str) -> float | None:
    if value is None:
        return None
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise EraError(f"`{name}` is a fraction in [0, 1], got {value!r}.") from None
    if not 0.0 <= v <= 1.0:
        raise EraError(f"`{name}` is a fraction in [0, 1], got {value!r}.")
    return v


def keep_mask(emac, mpc, *, contribution=None, damping_ratio=None, is_pair=None, min_emac=None, min_mpc=None,
              min_contribution=None, physical_only: bool = False, max_damping: float | None = None) -> np.ndarray:
    """The modes that pass every threshold given (None: no threshold on that indicator).

    Parameters
    ----------
    emac : array_like, shape (modes,)
        Each mode's EMAC γ, a fraction.
    mpc : array_like, shape (modes,)
        Each mode's MPC μ, a fraction.
    contribution : array_like, shape (modes,), optional
        Each mode's contribution (any unit); needed with ``min_contribution``.
    damping_ratio : array_like, shape (modes,), optional
        Each mode's ζ; needed with ``physical_only`` and ``max_damping``.
    is_pair : array_like of bool, shape (modes,), optional
        True for a complex-conjugate pair; needed with ``physical_only``.
    min_emac : float in [0, 1], optional
        Keep modes with γ ≥ min_emac.
    min_mpc : float in [0, 1], optional
        Keep modes with μ ≥ min_mpc.
    min_contribution : float in [0, 1], optional
        Keep modes whose contribution is at least this fraction of the largest finite contribution.
    physical_only : bool, optional
        Keep decaying pairs only (0 < ζ < 1): real poles and growing poles are computational.
    max_damping : float, optional
        Keep modes with ζ ≤ max_damping.

    Returns
    -------
    bool ndarray, shape (modes,)
        True where the mode passes.

    Raises
    ------
    era.EraError
        For a threshold outside [0, 1].

    References
    ----------
    Juang & Pappa (1985), section III (model reduction); γ of eqs. 42-45 and μ of eqs. 46-54.

    Examples
    --------
    >>> era.keep_mask([0.99, 0.4, 0.95], [0.98, 0.9, 0.5], min_emac=0.8, min_mpc=0.8)
    array([ True, False, False])
    >>> era.keep_mask([1, 1], [1, 1], damping_ratio=[0.02, -0.01], is_pair=[True, True], physical_only=True)
    array([ True, False])
    """
    emac, mpc = np.asarray(emac, dtype=float), np.asarray(mpc, dtype=float)
    keep = np.ones(emac.shape, dtype=bool)
    lo_emac, lo_mpc = _fraction(min_emac, "min_emac"), _fraction(min_mpc, "min_mpc")
    lo_contrib = _fraction(min_contribution, "min_contribution")
    if lo_emac is not None:
        keep &= emac >= lo_emac
    if lo_mpc is not None:
        keep &= mpc >= lo_mpc
    if lo_contrib is not None and keep.size:
        c = np.asarray(contribution, dtype=float)
        finite = c[np.isfinite(c)]
        keep &= c >= lo_contrib * (finite.max() if finite.size else 0.0)
    if physical_only or max_damping is not None:
        zeta = np.asarray(damping_ratio, dtype=float)
        if physical_only:
            keep &= np.asarray(is_pair, dtype=bool) & (zeta > 0) & (zeta < 1)
        if max_damping is not None:
            keep &= zeta <= max_damping
    return keep


def kept_modes(model, indices=None, *, min_emac=None, min_mpc=None, min_contribution=None,
               physical_only: bool = False) -> np.ndarray:
    """Sorted indices of the modes of ``model`` to keep: those named AND passing the thresholds.

    Parameters
    ----------
    model : ModalModel
        The model whose modes are judged (its ``emac``, ``mpc``, ``contribution``, ``damping_ratio``).
    indices : sequence of int or bool array_like, shape (modes,), optional
        The modes named (negative indices count from the end), or a mask of them. Default: all.
    min_emac : float in [0, 1], optional
        Keep modes with γ ≥ min_emac (see :func:`keep_mask`).
    min_mpc : float in [0, 1], optional
        Keep modes with μ ≥ min_mpc.
    min_contribution : float in [0, 1], optional
        Keep modes whose contribution is at least this fraction of the largest.
    physical_only : bool, optional
        Keep decaying pairs only (0 < ζ < 1).

    Returns
    -------
    int ndarray, shape (kept,)
        Positions among the model's modes, sorted.

    Raises
    ------
    era.EraError
        For an index out of range, a mask of the wrong length or a threshold outside [0, 1].

    Examples
    --------
    >>> from era.examples import paper_cases
    >>> model = era.identify(paper_cases.case_1(), 40, 40).realize(10)
    >>> era.kept_modes(model, [-1, 0, 2], min_emac=0.9)
    array([0, 2, 4])
    """
    n = model.n_modes
    named = np.ones(n, dtype=bool)
    if indices is not None:
        idx = np.asarray(indices)
        named = np.zeros(n, dtype=bool)
        if idx.dtype == bool:
            if idx.shape != (n,):
                raise EraError(f"A boolean mode mask needs {n} entries, got {idx.shape}.")
            named = idx.copy()
        elif idx.size:
            if not np.issubdtype(idx.dtype, np.integer):
                raise EraError(f"Mode indices must be integers, got {indices!r}.")
            bad = idx[(idx < -n) | (idx >= n)]
            if bad.size:
                raise EraError(f"Mode {int(bad[0])} is out of range: this model has {n} modes "
                               f"(indices 0..{n - 1}).")
            named[idx] = True
    passing = keep_mask(model.emac, model.mpc, contribution=model.contribution, damping_ratio=model.damping_ratio,
                        is_pair=model.is_pair, min_emac=min_emac, min_mpc=min_mpc,
                        min_contribution=min_contribution, physical_only=physical_only)
    return np.flatnonzero(named & passing)
