"""Simulation against test for one analysis (issue 5): run era.explain on the analysis's dataset, and keep the result.

The result is stored next to the analysis in the data folder (``explanations/{analysis_id}.json`` for the
summary, ``.npz`` for the full measured / nominal / updated responses), so a reload, a restart or a report shows
it without running the ranking again. Blocking functions: call them through app.jobs.
"""

from __future__ import annotations

import inspect
import io
import json
import math
import time

import numpy as np

import era

from . import payloads
from .store import Store, write_atomic

#: Points per overlay curve in the JSON (the stored responses keep every sample).
MAX_OVERLAY_POINTS = 1500
#: The same in a report, which keeps every (output, input) pair.
REPORT_OVERLAY_POINTS = 700
#: Nominal-model keywords a request may set, with the JSON types each accepts.
_NUMBER = (int, float)


def _grid():
    from era.examples.grid import nasa_grid
    return nasa_grid


def nominal_keywords() -> tuple[str, ...]:
    return tuple(inspect.signature(_grid()).parameters)


def nominal_model(params: dict | None):
    """``nasa_grid(**params)``, with a clear era.EraError (422) for unknown keywords or values of the wrong type."""
    params = dict(params or {})
    known = nominal_keywords()
    unknown = sorted(set(params) - set(known))
    if unknown:
        raise era.EraError(f"Unknown nominal-model parameter(s) {unknown}: nasa_grid() takes {', '.join(known)}.")
    for name, value in params.items():
        ok = (value is None or isinstance(value, (bool,) + _NUMBER)
              or (isinstance(value, list) and len(value) == 2 and all(isinstance(v, _NUMBER) for v in value)))
        if not ok or (isinstance(value, float) and not math.isfinite(value)):
            raise era.EraError(f"Nominal-model parameter {name!r} must be a number, true/false, null or an "
                               f"(x_ft, y_ft) pair; got {value!r}.")
    try:
        return _grid()(**params)
    except era.EraError:
        raise
    except (TypeError, ValueError) as exc:  # e.g. a number where the model wants a joint: say so, not a 500
        raise era.EraError(f"The nominal model rejected these parameters: {exc}") from None


def check_grid_dataset(data: era.ResponseData, geometry: era.Geometry | None, model) -> None:
    """Raise era.DataError unless the dataset has the grid's nine sensors, in model.sensors order."""
    need = ("The simulation-vs-test panel needs the NASA grid's nine sensors in order: outputs w at "
            + ", ".join(f"({x:g}, {y:g})" for x, y in model.sensors) + " ft, with the grid geometry (the built-in "
            "grid example has them).")
    if data.n_outputs != len(model.sensors):
        raise era.DataError(f"This dataset has {data.n_outputs} output(s). {need}")
    if geometry is None:
        raise era.DataError(f"This dataset has no geometry, so its sensors cannot be matched to the model. {need}")
    ref = model.geometry()
    at = lambda g: np.asarray(g.coordinates, float)[np.asarray(g.channel_nodes)]  # noqa: E731
    if (np.any(np.asarray(geometry.channel_nodes) < 0) or geometry.units != ref.units
            or not np.allclose(at(geometry), at(ref), atol=1e-3)
            or not np.allclose(np.abs(np.asarray(geometry.channel_directions, float)), ref.channel_directions,
                               atol=1e-3)):
        raise era.DataError(f"This dataset's channels are not at the grid's sensor positions. {need}")


def _json(x):
    """Numpy scalars and arrays to plain JSON; NaN and ±inf to null."""
    if isinstance(x, dict):
        return {str(k): _json(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_json(v) for v in x]
    if isinstance(x, np.ndarray):
        return _json(x.tolist())
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    return x


def run(data: era.ResponseData, geometry: era.Geometry | None, params: dict | None) -> tuple[dict, dict]:
    """era.explain on a grid dataset: (summary JSON, {"measured", "nominal", "updated": (N, p, m)} responses)."""
    from era.discrepancy import overlay

    model = nominal_model(params)
    check_grid_dataset(data, geometry, model)
    t0 = time.perf_counter()
    result = era.explain(data, model)
    seconds = time.perf_counter() - t0
    summary = result.as_dict()
    n_model = len(summary["mac_before"][0]) if summary["mac_before"] else 0
    responses = overlay(result, data)
    summary.update(
        nominal_params=_json(params or {}),
        model_hz_before=result.nominal_model.modes(n_model)[0] if n_model else [],
        model_hz_after=result.updated_model.modes(n_model)[0] if n_model else [],
        measured_hz=result.measured.take(result.fit_modes).frequency_hz,
        grid_shape=[int(np.unique(result.node_xy_ft[:, 0]).size), int(np.unique(result.node_xy_ft[:, 1]).size)],
        sensors_ft=[list(s) for s in model.sensors],
        outputs=list(data.outputs), inputs=list(data.inputs),
        overlay_fit_percent={k: payloads.fit_percent(responses[f"fit_error_{k}"]) for k in ("nominal", "updated")},
        seconds=seconds)
    return _json(summary), {k: np.asarray(responses[k], float) for k in ("measured", "nominal", "updated")}


# ---- storage ----------------------------------------------------------------------------------------
def _paths(store: Store, analysis_id: str):
    folder = store.root / "explanations"
    return folder / f"{analysis_id}.json", folder / f"{analysis_id}.npz"


def save(store: Store, analysis_id: str, summary: dict, responses: dict, dt: float) -> None:
    """Responses first, then the summary: a summary on disk always has its responses."""
    js, npz = _paths(store, analysis_id)
    buf = io.BytesIO()
    np.savez(buf, dt=np.array(dt), **responses)
    write_atomic(npz, buf.getvalue())
    write_atomic(js, json.dumps(summary, separators=(",", ":")).encode())


def load(store: Store, analysis_id: str) -> dict | None:
    """The stored summary of an analysis, or None when the panel has not run on it."""
    js, npz = _paths(store, analysis_id)
    if not (js.is_file() and npz.is_file()):
        return None
    return json.loads(js.read_bytes())


def overlay_json(store: Store, analysis_id: str, output: int, input: int,
                 max_points: int = MAX_OVERLAY_POINTS) -> dict:
    """Measured, nominal and updated response of one output for one input, decimated for plotting."""
    _, npz = _paths(store, analysis_id)
    with np.load(npz, allow_pickle=False) as z:
        measured, nominal, updated, dt = z["measured"], z["nominal"], z["updated"], float(z["dt"])
    n, p, m = measured.shape
    if not (0 <= output < p and 0 <= input < m):
        raise era.EraError(f"Choose an output 0..{p - 1} and an input 0..{m - 1}; got output {output}, "
                           f"input {input}.")
    sl = payloads.decimate(n, max_points)
    return {"output_index": output, "input_index": input, "time_s": payloads.floats((np.arange(n) * dt)[sl]),
            "measured": payloads.floats(measured[sl, output, input]), "nominal": payloads.floats(nominal[sl, output, input]),
            "updated": payloads.floats(updated[sl, output, input])}


def for_report(store: Store, analysis_id: str) -> dict | None:
    """The stored explanation with every output's overlay for every input (coarser, 4 significant digits), for
    a report; None if the panel never ran on this analysis."""
    summary = load(store, analysis_id)
    if summary is None:
        return None
    p, m = len(summary["outputs"]), len(summary["inputs"])
    rounded = lambda v: [None if x is None else float(f"{x:.4g}") for x in v]  # noqa: E731
    overlays = []
    for j in range(m):
        for i in range(p):
            o = overlay_json(store, analysis_id, i, j, REPORT_OVERLAY_POINTS)
            overlays.append({k: rounded(v) if isinstance(v, list) else v for k, v in o.items()})
    summary["overlays"] = overlays
    return summary
