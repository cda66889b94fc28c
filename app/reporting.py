"""Reports: freeze an analysis into one JSON document, and export it as self-contained HTML and as CSV.

A report holds everything its page draws (no recomputation when it is opened): the dataset's summary and
hash, the parameters, the modes of the chosen order with the kept ones marked, the stabilization diagram,
measured and reconstructed records, the geometry for the animation, the structure model simulation vs test used,
and the software versions.
"""

from __future__ import annotations

import base64
import csv
import datetime as dt
import io
import json
import platform
from types import SimpleNamespace

import numpy as np

import era

from . import modeling, payloads, viewing
from .cache import Analysis
from .choosing import Diagram

#: Reconstructions stored per report: at most this many (output, input) pairs, this many points each.
MAX_REPORT_PAIRS = 36
MAX_REPORT_POINTS = 1500


def _software(version: str) -> dict:
    import numpy
    import scipy
    return {"era-modal": version, "python": platform.python_version(), "numpy": numpy.__version__,
            "scipy": scipy.__version__}


def geometry_json(geometry: era.Geometry | None) -> dict | None:
    """The test geometry for the report's animation (schemas.ReportGeometry), or None."""
    if geometry is None:
        return None
    return {"node_ids": geometry.node_ids.tolist(), "coordinates": payloads.floats(geometry.coordinates),
            "edges": geometry.edges.tolist(), "channel_nodes": geometry.channel_nodes.tolist(),
            "channel_directions": payloads.floats(geometry.channel_directions), "units": geometry.units}


def build(a: Analysis, ident: era.Identification, model: era.ModalModel, kept: np.ndarray,
          diagram: Diagram, *, dataset: dict, explanation: dict | None, recordings: dict[str, str],
          version: str, plot_points: int, structure: dict | None = None) -> dict:
    """The report document (schemas.ReportDocument) of analysis ``a`` at the order of ``model`` (from ``ident``)
    with the modes ``kept`` (sorted indices); ``diagram``: its stabilization diagram and era's choice of modes
    (app/choosing.py), frozen with the verdict on every cluster. Blocking (one full reconstruction): run it on a pool.

    dataset : the dataset's stored summary; explanation : the stored simulation-vs-test result with every
    overlay (explaining.for_report), or None; recordings : {mode index: file name} of the mode-shape recordings;
    plot_points : points of the stabilization diagram's CMIF curve; structure : the dataset's structure model as
    stored (app/modeling.py), frozen with the report, or None.
    """
    data = a.data
    reduced = model.select(kept)
    rebuilt = reduced.reconstruct(data.n_samples)
    sl = payloads.decimate(data.n_samples, MAX_REPORT_POINTS)
    pairs = [(i, j) for j in range(data.n_inputs) for i in range(data.n_outputs)][:MAX_REPORT_PAIRS]
    return {
        "created": dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"),
        "software": _software(version),
        "dataset": dataset,
        "analysis": payloads.analysis_json(a.id, a.dataset_id, a.params, ident, diagram),
        "order": int(model.order), "kept": kept.tolist(),
        "modes": payloads.modes_json(model, data, shape_scatter=ident.shape_scatter(model.order)),
        "kept_fit_percent": payloads.fit_percent(reduced.fit_error(data)),
        "reconstruction": {
            "time_s": payloads.floats(data.time_s[sl]),
            "pairs": [{"output": data.outputs[i], "input": data.inputs[j], "output_index": i, "input_index": j,
                       "measured": payloads.floats(data.markov[sl, i, j]),
                       "reconstructed": payloads.floats(rebuilt[sl, i, j])} for i, j in pairs]},
        "stabilization": payloads.stabilization_json(diagram, data, plot_points),
        "geometry": geometry_json(viewing.modes_scene(a, model)[0]),  # its channels the points, when placed
        "explanation": explanation,
        "structure_model": None if structure is None else {
            k: structure.get(k) for k in ("model", "source", "name", "saved")} | {
            "text": modeling.describe(structure["model"])},
        "recordings": dict(recordings),
    }


def modes_csv(report: dict) -> str:
    """The modes of a report, one row per mode: kept flag, frequency and its standard deviation from the data,
    damping and its standard deviation, which scatter they come from (std_source), γ, μ, the shape's scatter from the data (expected 1 - MAC against the
    true shape), contribution, shape (a 95 % interval is value ± 1.96 std)."""
    m = report["modes"]
    kept = set(report["kept"])
    buf = io.StringIO()
    w = csv.writer(buf)
    shape_cols = [f"{_cell(o)} {part}" for o in m["outputs"] for part in ("re", "im")]
    points = m.get("points") or []  # the shape at every measured or struck point, when more than the sensors
    points = points if points != m["outputs"] else []
    shape_cols += [f"point {_cell(q)} {part}" for q in points for part in ("re", "im")]
    w.writerow(["mode", "kept", "frequency_hz", "frequency_std_hz", "natural_frequency_hz", "damping_ratio",
                "damping_std", "std_source", "emac", "mpc", "shape_scatter", "contribution_relative", "is_pair",
                *shape_cols])
    none = [None] * m["n_modes"]  # reports frozen before the standard deviations (or the scatter) existed
    f_std, d_std = m.get("frequency_std_hz") or none, m.get("damping_std") or none
    scatter = m.get("shape_scatter") or none
    source = m.get("uncertainty_source") or ""
    for k in range(m["n_modes"]):
        shape = [v for re, im in zip(m["shapes_re"][k], m["shapes_im"][k]) for v in (re, im)]
        if points:
            shape += [v for re, im in zip(m["point_shapes_re"][k], m["point_shapes_im"][k]) for v in (re, im)]
        w.writerow([k, int(k in kept), m["frequency_hz"][k], f_std[k], m["natural_frequency_hz"][k],
                    m["damping_ratio"][k], d_std[k], source, m["emac"][k], m["mpc"][k], scatter[k],
                    m["contribution_relative"][k], int(m["is_pair"][k]), *shape])
    return buf.getvalue()


def _cell(text: str) -> str:
    """A label safe for spreadsheets: a leading = + - @ would be read as a formula."""
    return "'" + text if text[:1] in ("=", "+", "-", "@") else text


#: What the viewer's standalone page holds where a recording goes (ModeViewer.standalone_html of empty bytes).
_EMBED_MARKER = 'window.__VISER_EMBED_DATA__=""'


def offline_viser(viewer, recordings: dict[str, bytes]) -> tuple[str | None, dict[str, str]]:
    """(viser's standalone player page with an empty recording, {mode: recording as base64}) for the download.

    The page (about 0.8 MB) is stored once; report.js puts one mode's recording into it for an <iframe srcdoc>.
    (None, {}) when the viewer is off, there is nothing recorded, or the player page no longer has the expected
    marker.
    """
    if viewer is None or not recordings:
        return None, {}
    template = viewer.standalone_html(b"")
    if template.count(_EMBED_MARKER) != 1:
        return None, {}
    return template, {k: base64.b64encode(v).decode("ascii") for k, v in recordings.items()}


def standalone_html(report: dict, token: str, viser_page: str | None = None,
                    viser_recordings: dict[str, str] | None = None) -> str:
    """report.html with plotly.js, the CSS, the page script and the report data (schemas.OfflineReport) inlined:
    opens offline.

    With ``viser_page`` and ``viser_recordings`` (from :func:`offline_viser`) the kept modes also play in viser's
    own client, with no server; otherwise the page animates them with plotly."""
    from .offline_page import offline_page, script, static_text

    extra = {"offline_recordings": viser_recordings or {}, "viser_marker": _EMBED_MARKER if viser_page else None}
    data = script_json(dict(report, token=token, standalone=True, **extra))
    return offline_page("report.html", {
        '<script src="/static/js/format.js"></script>': script(static_text("js", "format.js")),
        '<script src="/static/js/explain_view.js"></script>': script(static_text("js", "explain_view.js")),
        '<script src="/static/js/report.js"></script>':
            f"<script>window.REPORT_DATA = {data};</script>"
            + (f"<script>window.VISER_PAGE = {script_json(viser_page)};</script>" if viser_page else "")
            + script(static_text("js", "report.js")),
    })


def script_json(value) -> str:
    """JSON to put inside a <script> element: "</" and "<!--" escaped so the element cannot end early."""
    return json.dumps(value, separators=(",", ":")).replace("</", "<\\/").replace("<!--", "<\\!--")


def geometry_from_json(g: dict | None) -> era.Geometry | None:
    if g is None:
        return None
    return era.Geometry(node_ids=g["node_ids"], coordinates=g["coordinates"], edges=g["edges"],
                        channel_nodes=g["channel_nodes"], channel_directions=g["channel_directions"], units=g["units"])


def modes_uff(report: dict) -> bytes:
    """The kept modes as UFF 55 (with the geometry as UFF 15/82) through era.save_modes_uff."""
    m = report["modes"]
    kept = report["kept"]
    if not kept:
        raise era.EraError("This report keeps no modes, so there is nothing to write as UFF 55.")
    shapes = (np.array(m["shapes_re"], dtype=float) + 1j * np.array(m["shapes_im"], dtype=float)).T[:, kept]
    s = np.array(m["eigenvalue_re"], dtype=float)[kept] + 1j * np.array(m["eigenvalue_im"], dtype=float)[kept]
    pick = (lambda key: None if not m.get(key) else
            np.array([np.nan if m[key][k] is None else m[key][k] for k in kept], dtype=float))
    # what save_modes_uff reads of a ModalModel; a report frozen before σ or the scatter existed leaves them NONE
    points = m.get("points") or []  # reports frozen before points were kept have none: the sensors' shapes are written
    at_points = (np.array(m["point_shapes_re"], dtype=float) + 1j * np.array(m["point_shapes_im"], dtype=float)
                 ).T.reshape(len(points), -1)[:, kept] if points else None
    modes = SimpleNamespace(shapes=shapes, eigenvalues=s, frequency_std_hz=pick("frequency_std_hz"),
                            outputs=tuple(m["outputs"]), points=tuple(points), point_shapes=at_points,
                            damping_std=pick("damping_std"), uncertainty_source=m.get("uncertainty_source") or "")
    buf = io.BytesIO()
    era.save_modes_uff(buf, modes, geometry_from_json(report.get("geometry")), name="ERA",
                       shape_scatter=pick("shape_scatter"))
    return buf.getvalue()
