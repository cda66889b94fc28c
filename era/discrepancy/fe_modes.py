"""Test modes against a finite-element program's modes (UFF 55 from NASTRAN, ANSYS, Abaqus: era.read_modes_uff):
pairing, MAC, COMAC and the gap table. No effect is named: naming and fixing one needs a model this library can
change (an era.Frame, with era.explain); a list of another program's modes can only be compared.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.correlation import Gap, ModePairing, comac, gap, pair_modes, real_shapes
from ..errors import DataError
from ..structure import DIRECTIONS
from .measured import MeasuredModes

NOT_UPDATABLE = ("These modes come from another program: they can be paired and compared, but naming the missing "
                 "effect and closing the gap needs a model era can change (describe the structure as an era.Frame "
                 "and run era.explain).")


@dataclass(frozen=True, eq=False)
class ModeComparison:
    """pairing : ModePairing of the measured modes with the FE modes; mac_matrix (k, n_fe); comac (p,) per sensor;
    gap : Gap (max |Δf| %, rms, min and mean MAC); fe_sensor_shapes (p, n_fe) the FE shapes at the sensors;
    table : one dict per measured mode (measured Hz, FE mode and Hz, error %, MAC; None when unpaired);
    message : one paragraph, which says that no effect is named and why."""

    pairing: ModePairing
    mac_matrix: np.ndarray
    comac: np.ndarray
    gap: Gap
    fe_sensor_shapes: np.ndarray
    table: list
    message: str


def fe_sensor_shapes(fe, sensors) -> np.ndarray:
    """(p, n_fe) real FE shapes along each sensor: sensors [(node id, "x" | "-x" | ... | (dx, dy, dz))] in the
    measured channel order (e.g. era.Frame.sensors); node ids matched to the UFF node numbers as text."""
    ids = {str(int(n)) if np.issubdtype(np.asarray(fe.node_ids).dtype, np.integer) else str(n): k
           for k, n in enumerate(fe.node_ids)}
    rows = []
    for node, d in sensors:
        if str(node) not in ids:
            raise DataError(f"compare_fe_modes: sensor node {node} is not among the FE modes' {len(ids)} nodes.")
        v = DIRECTIONS[d] if isinstance(d, str) else np.asarray(d, float) / np.linalg.norm(d)
        rows.append(np.einsum("c,cn->n", v, fe.shapes[ids[str(node)]]))
    return real_shapes(np.array(rows))


def compare_fe_modes(measured: MeasuredModes, fe, sensors, *, max_freq_error: float = 0.5) -> ModeComparison:
    """Pair measured modes with a finite-element program's modes at the test's sensors and report the gap.

    No effect is named: naming and fixing one needs a model this library can change (an era.Frame or an
    era.MatrixModel, with era.explain); see the module docstring.

    Parameters
    ----------
    measured : MeasuredModes
        The k measured modes (era.discrepancy.measured_modes, or era.discrepancy.modes_from_arrays).
    fe : ModeSet
        The FE program's modes (from UFF 55: era.read_modes_uff).
    sensors : sequence of (node, direction)
        One per measured channel, in channel order: node ids matched to the UFF node numbers as text, direction
        "x" | "-x" | ... | (dx, dy, dz) (e.g. era.Frame.sensors).
    max_freq_error : float, optional
        The largest relative frequency error of a pair (default 0.5).

    Returns
    -------
    ModeComparison
        ``pairing``, ``mac_matrix`` (k, n_fe), ``comac`` (p,), ``gap``, ``fe_sensor_shapes`` (p, n_fe), ``table``
        (one dict per measured mode) and ``message``.

    Raises
    ------
    era.DataError
        When a sensor's node is not among the FE modes' nodes.

    Examples
    --------
    >>> from era.discrepancy import modes_from_arrays
    >>> shapes = np.zeros((3, 3, 2))  # three nodes, their X/Y/Z translations, two modes
    >>> shapes[:, 2] = [[0.5, 1.0], [1.0, 0.0], [0.5, -1.0]]
    >>> fe = era.ModeSet(np.array([2.0, 5.0]), np.zeros(2), np.array([1, 2, 3]), shapes, ("FE 1", "FE 2"))
    >>> measured = modes_from_arrays([2.1, 4.9], np.array([[0.5, 1.0], [1.0, 0.05], [0.5, -1.0]]))
    >>> comparison = era.compare_fe_modes(measured, fe, [(1, "z"), (2, "z"), (3, "z")])
    >>> [(row["fe_mode"], round(row["error_pct"], 2)) for row in comparison.table]
    [(1, -4.76), (2, 2.04)]
    """
    s_fe = fe_sensor_shapes(fe, sensors)
    f_fe = np.asarray(fe.frequency_hz, float)
    pairing = pair_modes(measured.frequency_hz, measured.shapes, f_fe, s_fe, max_freq_error=max_freq_error)
    c = comac(measured.shapes[:, pairing.measured_index], s_fe[:, pairing.model_index]) if pairing.n_pairs \
        else np.zeros(0)
    g = gap(pairing)
    table = []
    for i in range(measured.n_modes):
        hit = np.flatnonzero(pairing.measured_index == i)
        k = int(hit[0]) if hit.size else None
        table.append({"measured_hz": float(measured.frequency_hz[i]),
                      "fe_mode": None if k is None else int(pairing.model_index[k]) + 1,
                      "fe_hz": None if k is None else float(pairing.frequency_model_hz[k]),
                      "error_pct": None if k is None else float(pairing.frequency_error_pct[k]),
                      "mac": None if k is None else float(pairing.mac[k])})
    low = np.flatnonzero(c < 0.9)
    message = (f"{pairing.n_pairs} of {measured.n_modes} measured modes pair with the FE modes: max |Δf| "
               f"{g.max_abs_freq_error_pct:.2f} %, min MAC {g.min_mac:.3f}"
               + (f"; sensors {', '.join(str(i + 1) for i in low)} have COMAC < 0.9" if low.size else "")
               + ". " + NOT_UPDATABLE)
    return ModeComparison(pairing, pairing.mac_matrix, c, g, s_fe, table, message)
