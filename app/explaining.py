"""Simulation against test for one analysis: era.explain on the analysis itself, and the result kept.

Explain runs on the analysis it is named after: the analysis's own identification (its Hankel size and SVD) and
the modes era chose from its diagram (era.choose_modes, the modes the page ticks by default) at the choice's
order, or, when asked, exactly the modes the person kept at their order; either tracked over the diagram's orders
(or a stated set) for their spread. The summary says which (``basis``). The result goes through the store
(summary JSON and the full measured / nominal / updated responses), so a reload, a restart or a report shows it
without running the ranking again. Blocking functions: call them through app.jobs.
"""

from __future__ import annotations

import inspect
import math
import time

import numpy as np

import era
from era.words import counted, listed

from . import payloads

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
        raise era.EraError(f"Unknown nominal-model {'parameters' if len(unknown) > 1 else 'parameter'} "
                           f"{listed(unknown, quote=True)}: nasa_grid() takes {', '.join(known)}.")
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
            "grid example has them); for another structure, describe it in the Model panel or upload a model file "
            "first.")
    if data.n_outputs != len(model.sensors):
        raise era.DataError(f"This dataset has {counted(data.n_outputs, 'output')}. {need}")
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


def orders_for(ident: era.Identification, diagram_orders, orders=None, order: int | None = None) -> list[int]:
    """The orders the modes are tracked over (their spread is the measurement error level): ``orders`` as asked
    (each ≤ the analysis's largest order), by default the analysis's diagram orders (``diagram_orders``, those
    the page shows), plus ``order``, the order the modes are read at."""
    top = ident.max_order
    if orders:
        bad = [o for o in orders if not 1 <= int(o) <= top]
        if bad:
            raise era.OrderError(f"Order {bad[0]} is outside this analysis (orders 1..{top}); choose orders for the "
                                 "spread within it.")
        chosen = {int(o) for o in orders}
    else:
        chosen = {int(o) for o in diagram_orders if int(o) <= top} or {top}
    if order is not None:
        chosen.add(int(order))
    return sorted(chosen)


def chosen_modes(choice: era.ModeChoice) -> tuple[int, list[int]]:
    """(order, indices) of the modes era chose (era.choose_modes), the modes the page ticks by default; an
    era.DataError (422) when it chose none."""
    if not choice.n_modes:
        raise era.DataError("era chose no mode of the structure from this analysis's stabilization diagram (see "
                            "the reasons in its table): tick the modes to compare at an order and run with the "
                            "kept modes.")
    return int(choice.order), [int(k) for k in choice.indices]


def run_explain(ident: era.Identification, geometry: era.Geometry | None, model, params: dict | None, *,
        orders: list[int], kept: tuple, chosen: bool = False, described: dict | None = None) -> tuple[dict, dict]:
    """era.explain on the identification of a dataset against the nominal ``model``: the grid
    (nominal_model(params)), or None with ``described``, the dataset's structure model as stored (app/modeling.py:
    the era.Frame is built from it here, in the worker process, so the stored JSON is what travels to it).

    orders : the orders the modes are tracked over (:func:`orders_for`); kept : (order, mode indices), the modes
    compared at that order: those era chose (``chosen``, :func:`chosen_modes`) or those the person kept.
    Returns (summary JSON, {"measured", "nominal", "updated": (N, p, m)} responses).
    """
    from era.discrepancy import overlay

    data = ident.data
    is_fe = described is not None and "fe" in described
    is_frame = described is not None and not is_fe
    if is_fe:       # the engineer's FE model (app/femodel.py), seen at the outputs its mapping matches
        from . import femodel
        model = femodel.load(described["path"]).with_sensors(femodel.sensors_of(described["mapping"]))
    elif is_frame:
        from . import modeling
        model = modeling.frame_of(described)
        modeling.check_channels(model, data.outputs, geometry)
    else:
        check_grid_dataset(data, geometry, model)
    t0 = time.perf_counter()
    result = era.explain(ident, model, orders=orders, kept=kept)
    seconds = time.perf_counter() - t0
    summary = result.as_dict()
    n_model = len(summary["mac_before"][0]) if summary["mac_before"] else 0
    responses = overlay(result, data)
    summary.update(
        basis=basis(ident, orders, kept, chosen),
        nominal_params=_json(params or {}),
        model_hz_before=result.nominal_model.modes(n_model)[0] if n_model else [],
        model_hz_after=result.updated_model.modes(n_model)[0] if n_model else [],
        measured_hz=result.measured.take(result.fit_modes).frequency_hz,
        grid_shape=None if described is not None else [int(np.unique(result.node_xy_ft[:, 0]).size),
                                          int(np.unique(result.node_xy_ft[:, 1]).size)],
        sensors_ft=None if described is not None else [list(s) for s in model.sensors],
        outputs=list(data.outputs), inputs=list(data.inputs),
        overlay_fit_percent={k: payloads.fit_percent(responses[f"fit_error_{k}"]) for k in ("nominal", "updated")},
        seconds=seconds)
    if is_fe:
        from . import modeling
        summary.update(model_text=modeling.describe(described), fe_model=True,
                       mesh=femodel.mesh(model, result.node_labels))
    if is_frame:
        # the compared sensors: the frame's, then the struck points explain compared too (era.explain)
        summary.update(frame=frame_json(getattr(result.nominal_model, "frame", model), result.node_labels),
                       model_text=modeling.describe(described))
    return _json(summary), {k: np.asarray(responses[k], float) for k in ("measured", "nominal", "updated")}


def frame_json(frame: era.Frame, node_labels) -> dict:
    """What the panel and the report draw a frame's shapes with: nodes (m), members, sensors, and the node
    translation of each row of the expanded shapes ("7:x", ...)."""
    return {"nodes": {n: list(xyz) for n, xyz in frame.nodes.items()},
            "members": [[i, j] for i, j, *_ in frame.members],
            "sensors": [[n, d if isinstance(d, str) else list(d)] for n, d in frame.sensors],
            "node_labels": list(node_labels)}


def basis(ident: era.Identification, orders: list[int], kept: tuple, chosen: bool = False) -> dict:
    """What the explanation was computed from, for the panel and the report: the analysis's Hankel size, the
    orders tracked, and which modes ("stable": the modes era chose from the diagram, at the choice's order;
    "kept": the modes the person kept at one order), with that order and their indices."""
    rows, cols = int(ident.P.shape[0]), int(ident.Q.shape[0])
    order, indices = int(kept[0]), [int(k) for k in kept[1]]
    out = {"hankel_rows": ident.rows, "hankel_cols": ident.cols, "hankel_shape": [rows, cols],
           "orders": [int(o) for o in orders], "modes": "stable" if chosen else "kept", "order": order,
           "kept": indices}
    span = f"orders {orders[0]}-{orders[-1]}" if len(orders) > 1 else f"order {orders[0]}"
    which = (f"the {counted(len(indices), 'mode')} era chose at order {order}" if chosen else
             f"the {counted(len(indices), 'mode')} kept at order {order}") + f" (spread over {span})"
    out["text"] = f"This analysis's H(0) ({rows} × {cols}, r = {ident.rows}, s = {ident.cols}); {which}."
    return out


def overlay_json(responses: dict, dt: float, output: int, input: int,
                 max_points: int = MAX_OVERLAY_POINTS) -> dict:
    """Measured, nominal and updated response (arrays (N, p, m) in ``responses``) of one output for one input,
    decimated for plotting (schemas.Overlay)."""
    measured = responses["measured"]
    n, p, m = measured.shape
    if not (0 <= output < p and 0 <= input < m):
        raise era.EraError(f"Choose an output 0..{p - 1} and an input 0..{m - 1}; got output {output}, "
                           f"input {input}.")
    sl = payloads.decimate(n, max_points)
    return {"output_index": output, "input_index": input, "time_s": payloads.floats((np.arange(n) * dt)[sl]),
            **{k: payloads.floats(responses[k][sl, output, input]) for k in ("measured", "nominal", "updated")}}


def for_report(summary: dict | None, stored: tuple[dict, float] | None, model: dict | None = None) -> dict | None:
    """The explanation with every output's overlay for every input (coarser, 4 significant digits), for a report;
    None if the panel never ran. ``stored``: (responses, dt) as Store.explanation_responses gives them; ``model``:
    the dataset's structure model as stored now (the report freezes it): an explanation made with another one is
    frozen with ``stale`` saying so, beside the model it was made with (``model_used``)."""
    if summary is None or stored is None:
        return None
    from . import modeling

    summary = dict(summary, stale=modeling.stale(summary, model))
    responses, dt = stored
    rounded = lambda v: [None if x is None else float(f"{x:.4g}") for x in v]  # noqa: E731
    n, p, m = responses["measured"].shape
    overlays = []
    for j in range(m):
        for i in range(p):
            o = overlay_json(responses, dt, i, j, REPORT_OVERLAY_POINTS)
            overlays.append({k: rounded(v) if isinstance(v, list) else v for k, v in o.items()})
    return dict(summary, overlays=overlays)
