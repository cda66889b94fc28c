"""The engineer's own FE model (a Nastran deck, or a .zip of matrices) as a dataset's structure model.

The uploaded file is kept beside the dataset's model JSON (app/store: ``models/{dataset_id}.fe{suffix}``) and read
with ``era.load_model``; the JSON keeps what it is (file name, suffix, SHA-256, a one-line description) and the
mapping of the test's outputs to model DOFs, so a changed file or mapping changes the model's fingerprint (an
explanation made before is stale). Blocking functions (reading and solving a model): call them through app.jobs.
"""

from __future__ import annotations

import functools
import re
import zipfile
from pathlib import Path

import numpy as np

import era
from era.core import axis_and_sign, channel_points
from era.words import counted, listed

from . import modeling
from .store.files import write_atomic

#: File suffixes read as an FE model (the others are era.Frame JSON or TOML).
SUFFIXES = (".bdf", ".dat", ".nas", ".zip")
#: Frequencies shown beside the test's.
N_MODES = 10
#: A mode below this fraction of the highest computed frequency is a rigid-body mode (era.discrepancy's rule).
RIGID = 1e-4
#: Test point labels: "12Z", "12z", "12:z", "12 +Z", "12-z", "E -y" (node, optional separator, sign, axis).
_POINT = re.compile(r"^(\S+?)\s*[:.\s]?\s*([+-]?)\s*(rx|ry|rz|x|y|z)$", re.IGNORECASE)
_INCLUDE = re.compile(rb"^[ \t]*include\b", re.IGNORECASE | re.MULTILINE)
_WHAT_TO_DO = ("Upload a Nastran bulk-data deck (.bdf, .dat or .nas) or a .zip with K.mtx, M.mtx and dofs.csv "
               "(docs/fe-models.md says how each FE program writes them).")


def is_fe(name: str) -> bool:
    """Whether an uploaded model file's name says it is an FE model (a deck or a zip of matrices)."""
    return Path(name).suffix.lower() in SUFFIXES


def read_upload(name: str, blob: bytes, path: Path, max_bytes: int) -> era.MatrixModel:
    """Write ``blob`` (the file ``name``) to ``path`` and read it with era.load_model; era.DataError with what is
    wrong and what to do (never another exception), era.TooLargeError above ``max_bytes``."""
    if len(blob) > max_bytes:
        raise era.TooLargeError(f"{name}: a model file of {len(blob):,} bytes is larger than this server's "
                                f"{max_bytes:,} (ERA_MAX_UPLOAD_MB).")
    if not blob.strip():
        raise era.DataError(f"{name} is empty. {_WHAT_TO_DO}")
    if path.suffix != ".zip" and _INCLUDE.search(blob):     # it would read a file of the server's
        raise era.DataError(f"{name} INCLUDEs other files, which an upload cannot bring: paste the included "
                            "bulk data into the deck (or load it with era.load_model on your machine).")
    write_atomic(path, blob)      # complete or absent, as the store's other files
    try:
        model = load(str(path), max_bytes)
    except era.TooLargeError:
        raise
    except era.EraError as exc:
        raise era.DataError(f"{name}: {str(exc).replace(str(path), name)}") from None
    except Exception as exc:     # a zip that is not one, text that is not text: a refusal, not a 500
        raise era.DataError(f"{name} is not a model era can read ({type(exc).__name__}: {exc}). {_WHAT_TO_DO}") \
            from None
    return model


@functools.lru_cache(maxsize=4)
def load(path: str, max_bytes: int | None = None) -> era.MatrixModel:
    """era.load_model of a stored file (its name carries no version: the store's path changes with the file's
    hash, app.store.Store.model_file); cached, with the modes it solved."""
    if Path(path).suffix.lower() == ".zip":
        return era.load_model(path, max_bytes=max_bytes)
    return era.load_model(path)


def describe(model: era.MatrixModel, name: str, sha256: str) -> dict:
    """What the stored JSON keeps of an FE model: counts, units and notes (the cards not modelled)."""
    notes = [str(n) for n in getattr(model, "notes", ()) or ()]
    kind = "Nastran deck" if Path(name).suffix.lower() != ".zip" else "matrices"
    text = (f"{kind} {name}: {counted(len(model.nodes), 'node')}, {counted(model.n_dofs, 'free DOF')}, "
            f"{counted(len(model.parts), 'part')}")
    return {"file": name, "suffix": Path(name).suffix.lower(), "n_nodes": len(model.nodes),
            "n_dofs": model.n_dofs, "units": dict(model.units), "notes": notes, "text": text,
            "sha256": sha256}


#: kg per unit of each mass unit era.models.matrix.UNIT_SYSTEMS names (and the slug of lbf-ft-s decks).
KG_PER = {"kg": 1.0, "t": 1000.0, "lbf·s²/in": 175.126835, "kip·s²/in": 175126.835, "slug": 14.5939029}
#: PARAM WTMASS values that say a deck's unit system: 1/g turns the weights entered into masses.
_WTMASS_UNITS = ((386.08858, "lbf·s²/in", "the deck's masses are weights in lbf over g in in/s² (kip·s²/in if "
                  "they are in kip)"),
                 (32.174049, "slug", "the deck's masses are weights in lbf over g in ft/s²"),
                 (9.80665, "kg", "the deck's masses are weights in N over g in m/s²"),
                 (9806.65, "t", "the deck's masses are weights in N over g in mm/s²"))


def mass_unit(model: era.MatrixModel, path: Path) -> dict:
    """The unit of the model's masses, as far as the file says it: {unit: a mass unit, or None when the file
    does not say; note: a sentence on how it is known}. A .zip of matrices says it in units.txt; a Nastran deck
    carries no units, but a PARAM WTMASS of 1/g (g in in/s², ft/s², m/s² or mm/s²) tells its system."""
    if path.suffix.lower() == ".zip":
        with zipfile.ZipFile(path) as z:
            declared = any(n.rsplit("/", 1)[-1].lower() == "units.txt" for n in z.namelist())
        if declared:
            return {"unit": model.units["mass"], "note": "the mass unit its units.txt gives"}
        return {"unit": None, "note": "the matrices' own mass unit: the .zip has no units.txt saying it (kg if "
                                      "they are in N, m and s)"}
    wtmass = getattr(getattr(model, "deck", None), "wtmass", 1.0)
    for g, unit, why in _WTMASS_UNITS:
        if abs(wtmass * g - 1.0) < 2e-3:
            return {"unit": unit, "note": f"PARAM WTMASS {wtmass:.6g} = 1/{g:g}: {why}"}
    return {"unit": None, "note": "the deck's own mass unit: a Nastran deck does not say its units (kg if it is "
                                  "in N, m and s; t in N, mm and s)"}


def test_points(outputs: tuple, geometry: era.Geometry | None, meta: dict | None) -> list[tuple[str, str] | None]:
    """(node, direction) each output measures, signed ("-z"), from the geometry's channel nodes and directions,
    else the data's output points ("12Z", "12:z", "12 +Z"), else the output labels; None where none names one."""
    labels, signs = channel_points(meta or {}, "output", tuple(outputs))
    out: list[tuple[str, str] | None] = []
    for ch, label in enumerate(labels):
        point = None
        if geometry is not None and ch < geometry.channel_nodes.size and int(geometry.channel_nodes[ch]) >= 0:
            axis, sign = axis_and_sign(geometry.channel_directions[ch])
            if axis:
                point = (str(geometry.node_ids[int(geometry.channel_nodes[ch])]),
                         ("-" if sign < 0 else "") + axis.lower())
        if point is None:
            hit = _POINT.match(str(label).strip())
            if hit:
                sign = -1.0 if hit.group(2) == "-" else 1.0
                sign *= float(signs[ch]) if ch < len(signs) else 1.0
                point = (hit.group(1), ("-" if sign < 0 else "") + hit.group(3).lower())
        out.append(point)
    return out


def _free(model: era.MatrixModel, point) -> bool:
    return point is not None and (str(point[0]), str(point[1]).lstrip("+-").lower()) in model.dof_index


def match(model: era.MatrixModel, outputs: tuple, points: list) -> list[dict]:
    """The mapping table: per output its test point, the model node and direction it is matched to (the same
    node label and direction when the model has that free DOF), and whether it is matched."""
    rows = []
    for label, point in zip(outputs, points):
        ok = _free(model, point)
        rows.append({"output": str(label), "point": None if point is None else f"{point[0]} {point[1]}",
                     "node": point[0] if ok else None, "direction": point[1] if ok else None, "matched": ok})
    return rows


def checked_mapping(model: era.MatrixModel, outputs: tuple, sensors: list) -> list[dict]:
    """A mapping the engineer sent: one [node, direction] (or null) per output; era.DataError naming the first
    pair that is not a free DOF of the model."""
    if len(sensors) != len(outputs):
        raise era.DataError(f"The mapping has {counted(len(sensors), 'row')} but this dataset has "
                            f"{counted(len(outputs), 'output')}: send one [node, direction] (or null) per output, "
                            "in the outputs' order.", option="mapping")
    rows = []
    for label, pair in zip(outputs, sensors):
        if pair is None:
            rows.append({"output": str(label), "point": None, "node": None, "direction": None, "matched": False})
            continue
        if len(pair) != 2:
            raise era.DataError(f"Output {label}: give [node, direction], got {pair!r}.", option="mapping")
        node, d = str(pair[0]).strip(), str(pair[1]).strip().lower()
        try:
            model.at([(node, d)])
        except era.EraError as exc:
            raise era.DataError(f"Output {label}: {exc}", option="mapping") from None
        rows.append({"output": str(label), "point": f"{node} {d}", "node": node, "direction": d, "matched": True})
    return rows


def unmatched(rows: list[dict]) -> str | None:
    """The outputs matched to no model DOF, in one sentence; None when every one is."""
    missing = [r for r in rows if not r["matched"]]
    if not missing:
        return None
    named = listed([r["output"] + (f" ({r['point']})" if r["point"] and r["point"] != r["output"] else "")
                    for r in missing])
    return (f"{counted(len(missing), 'output')} of {len(rows)} {'match' if len(missing) > 1 else 'matches'} no "
            f"free DOF of the model: {named}; give each a model node and direction in the mapping table.")


def sensors_of(rows: list[dict]) -> list[tuple[str, str]]:
    """The model's sensors from a complete mapping; era.DataError (the unmatched sentence) otherwise."""
    gap = unmatched(rows)
    if gap:
        raise era.DataError(gap, option="mapping")
    return [(r["node"], r["direction"]) for r in rows]


def elastic_modes(model: era.MatrixModel, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The lowest ``n`` elastic modes (Hz, shapes over every DOF): a free model's rigid-body modes left out."""
    f, phi = model.modes(min(n + 6, model.n_dofs))
    keep = np.flatnonzero(f >= RIGID * max(float(f.max()), 1e-300))[:n]
    return f[keep], phi[:, keep]


def compare(model: era.MatrixModel, rows: list[dict], frequency_hz, shapes) -> dict:
    """The model's modes beside the test's (schemas.ModelComparison), at the outputs the mapping matches."""
    from era import real_shapes

    use = [k for k, r in enumerate(rows) if r["matched"]]
    if len(use) < 2:
        raise era.DataError(unmatched(rows) or "Fewer than two outputs are matched to the model.", option="mapping")
    test = real_shapes(np.asarray(shapes))[use]
    f_test = np.asarray(frequency_hz, float)
    f_model, phi = elastic_modes(model, max(N_MODES, f_test.size + 6))
    dof, sign = model.at([(rows[k]["node"], rows[k]["direction"]) for k in use])
    s_model = phi[dof] * sign[:, None]
    return modeling.comparison(f_test, test, f_model, s_model)


def mesh(model: era.MatrixModel, node_labels) -> dict | None:
    """What the 3-D viewer draws an FE model's shapes on, in era.Frame's drawing format: {nodes: {node: [x, y, z]}
    (the model's length unit; the nodes of the expanded shapes, and a deck's element nodes held still, a clamped
    edge's), members: [[i, j], ...] (a deck's bars and its shells' edges, as lines), faces: [[i, j, k], ...] (its
    shells as triangles, a quad cut along its diagonal 1-3), node_labels: "node:x" per row of the expanded shapes};
    None without node coordinates."""
    if not model.coordinates:
        return None
    labels = [str(x) for x in node_labels]
    seen = dict.fromkeys(x.rsplit(":", 1)[0] for x in labels)
    deck = getattr(model, "deck", None)
    edges: dict[tuple, None] = {}
    faces: list[list[str]] = []
    if deck is not None:
        for e in deck.lines.values():
            edges[tuple(sorted((str(e.ga), str(e.gb))))] = None
        for e in deck.shells.values():
            ring = [str(g) for g in e.nodes]
            for a, b in zip(ring, ring[1:] + ring[:1]):
                edges[tuple(sorted((a, b)))] = None
            faces += [ring[:3]] + ([[ring[0], ring[2], ring[3]]] if len(ring) == 4 else [])
    drawn = dict(seen)
    drawn.update((n, None) for pair in edges for n in pair if n in model.coordinates)
    nodes = {n: [float(v) for v in model.coordinates[n]] for n in drawn}
    members = [[a, b] for a, b in edges if a in nodes and b in nodes and a != b]
    faces = [f for f in faces if all(n in nodes for n in f) and len(set(f)) == 3]
    return {"nodes": nodes, "members": members, "faces": faces, "node_labels": labels}


def masses(stored: dict) -> dict:
    """The summary's mass fields of a stored FE model: total_mass in the model's own unit, mass_unit (None when
    the file does not say it), mass_unit_note, and total_mass_kg: in kg when the unit is known, else the model's
    own number (kg only if the model is in SI units, as era reads a file that does not say)."""
    total = float(stored.get("total_mass", 0.0))
    unit = stored.get("mass_unit") or {"unit": None, "note": "the model's own mass unit (stored before the unit "
                                                             "was looked for)"}
    kg = total * KG_PER.get(unit["unit"], 1.0)
    return {"total_mass_kg": kg, "total_mass": total, "mass_unit": unit["unit"], "mass_unit_note": unit["note"]}


def summary(stored: dict, f_hz, fingerprint: str) -> dict:
    """The answer for a stored FE model (schemas.StructureModel)."""
    fe, rows = stored["model"]["fe"], stored["model"]["mapping"]
    return {"model": stored["model"], "source": "fe", "name": stored.get("name"), "saved": stored.get("saved"),
            "fingerprint": fingerprint, "n_nodes": fe["n_nodes"], "n_members": 0,
            "n_sensors": sum(r["matched"] for r in rows), **masses(stored),
            "frequency_hz": [float(f) for f in f_hz], "text": fe["text"], "mapping": rows,
            "unmatched": unmatched(rows), "notes": fe["notes"], "n_dofs": fe["n_dofs"]}
