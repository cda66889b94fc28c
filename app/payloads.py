"""The JSON the API answers, built from era/ results: plain dicts shaped as the models in app/schemas/.

Plain dicts, not schema objects: the order slider's /step answer goes out as JSON directly (see
routes/analyses.py), and the routes with a ``response_model`` have FastAPI validate the dict once. Every float
list goes through :func:`floats` (NaN and ±inf are not JSON: they become null). Curves are decimated to at most
``max_points`` samples; fits are computed on every sample.
"""

from __future__ import annotations

import math

import numpy as np

import era
from era.core import CLUSTER_SCREEN, COHERENT_MIN, cmif, order_from_singular_values

from .choosing import Diagram, band_of, default_hankel, named_hankel
from .config import Settings


def floats(values) -> list:
    """A float array as a (nested) JSON list: NaN and ±inf (not valid JSON) become null."""
    a = np.asarray(values, dtype=float)
    out = a.tolist()
    if not np.isfinite(a).all():
        return _nulls(out)
    return out


def _nulls(x):
    if isinstance(x, list):
        return [_nulls(v) for v in x]
    return x if math.isfinite(x) else None


def decimate(n_samples: int, max_points: int) -> slice:
    """Every k-th sample, k chosen so that at most ``max_points`` of ``n_samples`` remain."""
    return slice(None, None, max(1, math.ceil(n_samples / max_points)))


def fit_percent(error) -> list | float | None:
    """Fit 100 (1 - e) in percent from the normalised RMS error e, (p, m) or a scalar; negative for a bad model."""
    return floats(100.0 * (1.0 - np.asarray(error, dtype=float)))


# ---- datasets -------------------------------------------------------------------------------------------
def dataset_summary(data: era.ResponseData, geometry: era.Geometry | None, name: str, settings: Settings,
                    source: dict | None = None, rows: int | None = None, cols: int | None = None) -> dict:
    """What the API says about a dataset (schemas.Dataset without the id and sha256 the store adds): labels,
    sampling, era's default Hankel size within the server's limits (``rows``/``cols`` override it, e.g. the
    paper's choice), the limits, and the band FRF records hold (kept here: the stored NPZ does not carry it)."""
    n, p, m = data.markov.shape
    choice = named_hankel(rows, cols, p, m, settings) if rows and cols else default_hankel(n, p, m, settings)
    band = band_of(data)
    return {
        "name": name,
        "outputs": list(data.outputs), "inputs": list(data.inputs),
        "output_units": list(data.output_units) if data.output_units else None,
        "input_units": list(data.input_units) if data.input_units else None,
        "dt": data.dt, "n_samples": n, "n_outputs": p, "n_inputs": m,
        "duration_s": n * data.dt, "nyquist_hz": 0.5 / data.dt,
        "geometry": None if geometry is None else {"n_nodes": int(geometry.n_nodes), "units": geometry.units,
                                                   "n_edges": int(len(geometry.edges))},
        "source": source or {},
        "defaults": {"rows": choice.rows, "cols": choice.cols, "max_order": choice.max_order},
        "band_hz": None if band is None else floats(band),
        "limits": {"rows_plus_cols_max": n, "max_hankel_elements": settings.max_hankel_elements,
                   "max_order": settings.max_order,
                   "note": (f"With consecutive shifts rows + cols ≤ {n} (N samples); rows·{p} × cols·{m} ≤ "
                            f"{settings.max_hankel_elements:,} elements; max order ≤ min(rows·{p}, cols·{m}, "
                            f"{settings.max_order}).")},
    }


def records_json(data: era.ResponseData, input_index: int, max_points: int) -> dict:
    """Every output's record for one input (schemas.Records). Raises era.EraError for an input out of range."""
    if not 0 <= input_index < data.n_inputs:
        raise era.EraError(f"`input` must be 0..{data.n_inputs - 1} (this dataset has {data.n_inputs} inputs), "
                           f"got {input_index}.")
    sl = decimate(data.n_samples, max_points)
    return {"time_s": floats(data.time_s[sl]), "input": data.inputs[input_index],
            "outputs": list(data.outputs), "series": [floats(data.markov[sl, i, input_index])
                                                      for i in range(data.n_outputs)]}


def spectrum_json(data: era.ResponseData, max_points: int) -> dict:
    """The complex mode indicator function of the records (schemas.Spectrum)."""
    f, values = cmif(data)
    sl = decimate(f.size, max_points)
    return {"frequency_hz": floats(f[sl]), "values": [floats(v[sl]) for v in values]}


# ---- analyses ---------------------------------------------------------------------------------------------
def analysis_json(analysis_id: str, dataset_id: str, params: dict, ident: era.Identification,
                  diagram: Diagram) -> dict:
    """An identification (schemas.Analysis): its Hankel parameters, the singular values, and the order and modes
    era chooses from its diagram (``suggested_order``, ``chosen_indices``: era.choose_modes)."""
    d = ident.singular_values
    return {
        "id": analysis_id, "dataset_id": dataset_id, "rows": ident.rows, "cols": ident.cols,
        "row_shifts": ident.row_shifts[1:].tolist(), "col_shifts": ident.col_shifts[1:].tolist(),
        "max_order": ident.max_order, "requested_max_order": params.get("max_order"),
        "hankel_shape": [int(ident.P.shape[0]), int(ident.Q.shape[0])], "svd_method": ident.svd_method,
        "singular_values": floats(d[: min(d.size, max(2 * ident.max_order, 50), 2000)]),
        "suggested_order": diagram.order, "chosen_indices": diagram.chosen_indices,
        "noise_floor_order": order_from_singular_values(d, ident.max_order),
    }


def std_groups(model: era.ModalModel) -> list:
    """(k,) for each mode, the indices of the modes that share its ± (itself included, ascending), or None.

    era gives every member of a repeated cluster the cluster's largest σ (era.Identification.decomposed,
    era.core.mode_uncertainty.mode_std): poles closer together than CLUSTER_SIGMAS times their scatter
    (era.core.decomposition.repeated_clusters) are one eigenvalue as far as the data can tell; which of them the noise
    pushed where is not determined, and first-order perturbation does not hold for each alone (it divides by their
    distance), so each one's own σ would claim a precision the data do not give. The model does not keep its
    clusters; they are found again as the connected groups of poles of the same kind within CLUSTER_SCREEN of
    each other whose frequency and damping σ are equal (the cluster's largest, copied: equal floats, which two
    separately computed σ are not)."""
    f_std, d_std = model.standard_deviations()
    z, pair = np.asarray(model.z), np.asarray(model.is_pair)
    linked = ((np.abs(z[:, None] - z[None, :]) <= CLUSTER_SCREEN) & (pair[:, None] == pair[None, :])
              & (f_std[:, None] == f_std[None, :]) & (d_std[:, None] == d_std[None, :])
              & np.isfinite(f_std)[:, None])
    out: list = [None] * len(z)
    for k in range(len(z)):
        if out[k] is not None or linked[k].sum() < 2:
            continue
        group, grown = {k}, True
        while grown:  # the connected group (a chain of close poles is one cluster)
            more = set(np.flatnonzero(linked[sorted(group)].any(axis=0)).tolist())
            grown = not more <= group
            group |= more
        for j in group:
            out[j] = sorted(int(i) for i in group)
    return out


def modes_json(model: era.ModalModel, data: era.ResponseData, with_fit: bool = True,
               shape_scatter: np.ndarray | None = None) -> dict:
    """The modes of one order (schemas.Modes); with_fit adds the fit of all modes to every channel (one full
    reconstruction, which the slider skips); shape_scatter (modes,) is each shape's expected 1 - MAC from the
    data (Identification.shape_scatter: n pole functionals per mode, so only when asked), else null."""
    contrib = np.asarray(model.contribution, dtype=float)
    finite = contrib[np.isfinite(contrib)]
    top = finite.max() if finite.size else 0.0
    rel = contrib / top if top > 0 else np.zeros_like(contrib)
    f_std, d_std = model.standard_deviations()
    return {
        "order": model.order, "n_modes": model.n_modes, "outputs": list(data.outputs), "inputs": list(data.inputs),
        "frequency_hz": floats(model.frequency_hz), "natural_frequency_hz": floats(model.natural_frequency_hz),
        "eigenvalue_re": floats(model.eigenvalues.real), "eigenvalue_im": floats(model.eigenvalues.imag),
        "damping_ratio": floats(model.damping_ratio), "emac": floats(model.emac), "mpc": floats(model.mpc),
        "frequency_std_hz": floats(f_std), "damping_std": floats(d_std),
        "uncertainty_source": model.uncertainty_source or None, "std_group": std_groups(model),
        "emac_mpc": floats(model.emac * model.mpc), "contribution": floats(contrib),
        "contribution_relative": floats(rel), "is_pair": model.is_pair.tolist(),
        "shapes_re": [floats(c) for c in model.shapes.real.T], "shapes_im": [floats(c) for c in model.shapes.imag.T],
        "points": list(model.points),
        "point_shapes_re": [floats(c) for c in model.point_shapes.real.T],
        "point_shapes_im": [floats(c) for c in model.point_shapes.imag.T],
        "fit_percent": fit_percent(model.fit_error(data)) if with_fit else None,
        "shape_scatter": None if shape_scatter is None else floats(shape_scatter),
    }


def reconstruction_json(model: era.ModalModel, data: era.ResponseData, kept: np.ndarray | None, output: int,
                        input_: int, max_points: int) -> dict:
    """Measured against reconstructed response of one channel with the kept modes (None: all), schemas.Reconstruction.

    Only the drawn channel is reconstructed (eq. 35 in modal form, with ``model.channel``): p·m times less work
    than every channel, which keeps the slider fast. Raises era.EraError for an output or input out of range.
    """
    channel = model.channel(output, input_)
    if kept is not None:
        channel = channel.select(kept)
    measured = data.markov[:, output:output + 1, input_:input_ + 1]
    rebuilt = channel.reconstruct(data.n_samples)[:, 0, 0]
    error = channel.fit_error(measured)[0, 0]
    sl = decimate(data.n_samples, max_points)
    return {
        "output": data.outputs[output], "input": data.inputs[input_],
        "kept": list(range(model.n_modes)) if kept is None else kept.tolist(),
        "time_s": floats(data.time_s[sl]), "measured": floats(measured[sl, 0, 0]),
        "reconstructed": floats(rebuilt[sl]), "fit_percent": fit_percent(error),
    }


def _pole_std(values, order) -> list:
    """Each pole's standard deviation from the data (null where not computed)."""
    return floats(np.full(np.shape(order), np.nan) if values is None else values)


#: A cluster era.choose_modes gave no verdict (none today: every cluster is chosen or rejected with a reason).
_NO_VERDICT = {"chosen": False, "code": None, "reason": None, "mode": None}


def _verdict(candidate) -> dict:
    """A cluster's verdict from era.choose_modes (schemas.StableMode's chosen, code, reason, mode)."""
    return {"chosen": candidate.chosen, "code": candidate.code, "reason": candidate.reason,
            "mode": None if candidate.mode is None else int(candidate.mode)}


def _evidence(values: dict | None) -> dict | None:
    """What era weighed for a candidate ({name: number}), JSON-safe."""
    if not values:
        return None
    return {str(k): (None if v is None or not math.isfinite(float(v)) else float(v)) for k, v in values.items()}


def candidate_json(c) -> dict:
    """One of era.choose_modes' candidates (schemas.ChoiceCandidate): a cluster of the diagram, or, for noise-free
    data of exact rank, a mode of the exact realization (``cluster`` null)."""
    return {"frequency_hz": floats(c.frequency_hz), "damping_ratio": floats(c.damping_ratio),
            "emac": floats(c.emac), "mpc": floats(c.mpc), "orders": [int(o) for o in c.orders],
            "pole_indices": [int(i) for i in c.pole_indices],
            "cluster": int(c.diagram_index) if c.diagram_index >= 0 else None,
            **_verdict(c), "evidence": _evidence(getattr(c, "evidence", None))}


def stabilization_json(diagram: Diagram, data: era.ResponseData, max_points: int) -> dict:
    """The stabilization diagram (schemas.Stabilization): every pole of every order with its stability flags,
    the suggested modes (clusters: each marked coherent when its mean γ·μ ≥ stabilization.COHERENT_MIN, and
    with era.choose_modes' verdict: chosen, or why not), every candidate era judged with its verdict, the order
    and modes chosen, and the CMIF of the records drawn under it."""
    stab, choice = diagram.stabilization, diagram.choice
    verdicts = {c.diagram_index: _verdict(c) for c in choice.candidates()}
    return {
        "orders": np.asarray(stab.orders).tolist(), "order": np.asarray(stab.order).tolist(),
        "mode_index": np.asarray(stab.mode_index).tolist(),
        "frequency_hz": floats(stab.frequency_hz), "damping_ratio": floats(stab.damping_ratio),
        "emac": floats(stab.emac), "mpc": floats(stab.mpc), "contribution": floats(stab.contribution),
        "frequency_std_hz": _pole_std(stab.frequency_std_hz, stab.order),
        "damping_std": _pole_std(stab.damping_std, stab.order),
        "uncertainty_source": stab.uncertainty_source or None,
        "stable_frequency": np.asarray(stab.stable_frequency).tolist(),
        "stable_damping": np.asarray(stab.stable_damping).tolist(),
        "stable_shape": np.asarray(stab.stable_shape).tolist(), "stable": np.asarray(stab.stable).tolist(),
        "modes": [{"frequency_hz": floats(mo.frequency_hz), "frequency_std_hz": floats(mo.frequency_std_hz),
                   "damping_ratio": floats(mo.damping_ratio), "damping_std": floats(mo.damping_std),
                   "data_frequency_std_hz": floats(getattr(mo, "data_frequency_std_hz", np.nan)),
                   "data_damping_std": floats(getattr(mo, "data_damping_std", np.nan)),
                   "emac": floats(mo.emac), "mpc": floats(mo.mpc), "orders": list(mo.orders),
                   "pole_indices": [int(i) for i in mo.pole_indices], "coherent": bool(mo.coherent),
                   **verdicts.get(k, _NO_VERDICT)} for k, mo in enumerate(stab.modes)],
        "coherent_min": COHERENT_MIN,
        "candidates": [candidate_json(c) for c in sorted(choice.chosen + choice.rejected,
                                                          key=lambda c: (c.frequency_hz, c.diagram_index))],
        "chosen_order": diagram.order, "chosen_indices": diagram.chosen_indices,
        "band_hz": floats(diagram.band_hz),
        "nyquist_hz": 0.5 / data.dt,
        "spectrum": spectrum_json(data, max_points),
    }
