"""The engineer's model of their structure: an era.Frame described in the browser from the dataset's
geometry, or uploaded as a model file, checked against the dataset's channels, kept with the dataset.

The model is kept as the person described it, in era.structure's file format (a section may stay
{"shape": "rectangle", "width": m, "depth": m, "material": "steel"}, so the panel can show it again as typed);
:func:`frame` turns it into an era.Frame. Units: SI (m, kg, N, Pa) as in the file format; the browser converts
its millimetres. Blocking functions (a model's modes): call them through app.jobs.
"""

from __future__ import annotations

import hashlib
import json
import math
import re
import tomllib

import numpy as np

import era
from era.structure import DIRECTIONS, MATERIALS, UNITS_M
from era.words import counted

#: Frequencies of a saved model shown beside the test's, and computed to check it (a mechanism fails here).
N_MODES = 10
#: Largest model file accepted, bytes.
MAX_MODEL_BYTES = 2_000_000
SHAPES = ("rectangle", "tube", "square_tube", "circle")
TABLES = ("nodes", "sections", "supports", "masses", "joint_springs", "added_mass_per_length")
LISTS = ("members", "sensors")


def draft(geometry: era.Geometry | None, outputs: tuple) -> dict:
    """What the model step starts from: the geometry's nodes (m), one member per trace line segment, grouped by the
    trace line it was drawn in (one group per named trace line, e.g. Test.Lab's "Stator"; members of unnamed trace
    lines by direction: "vertical", "along x", "along y", "inclined"), and one sensor per channel (node,
    direction). A segment drawn twice is one member, in the first trace line that draws it.

    Raises era.DataError when there is no geometry, no trace line, or a channel without a node or a direction
    (the message says what to do instead: upload a model file)."""
    if geometry is None:
        raise era.DataError("This dataset has no test geometry (nodes and trace lines), so there is nothing to "
                            "build the model from: upload a model file (era.Frame JSON or TOML) instead.")
    scale = UNITS_M.get(str(geometry.units).strip().lower())
    if scale is None:
        raise era.DataError(f"The geometry's length unit {geometry.units!r} is not one of {sorted(UNITS_M)}.")
    ids = [str(i) for i in geometry.node_ids]
    named: dict[tuple, str] = {}
    for e, name in zip(geometry.edges, geometry.edge_names()):
        if e[0] != e[1]:
            named.setdefault(tuple(sorted(map(int, e))), name)
    edges = sorted(named)
    if not edges:
        raise era.DataError("The geometry has nodes but no trace lines, so there are no members to draw: add trace "
                            "lines (UFF 82) to the file, or upload a model file.")
    xyz = np.asarray(geometry.coordinates, float) * scale
    members = [[ids[a], ids[b], named[a, b] or _group(xyz[b] - xyz[a])] for a, b in edges]
    used = sorted({i for e in edges for i in e})
    sensors = []
    for ch, (node, d) in enumerate(zip(geometry.channel_nodes, geometry.channel_directions)):
        name = outputs[ch] if ch < len(outputs) else f"channel {ch + 1}"
        if node < 0 or not np.any(d):
            raise era.DataError(f"Output {ch + 1} ({name}) has no node or direction in the geometry, so the model "
                                "cannot place its sensor: upload a model file that lists the sensors.")
        if node not in used:
            raise era.DataError(f"Output {ch + 1} ({name}) measures node {ids[node]}, which is on no trace line, so "
                                "no member carries its sensor: add the trace lines to it in the file, or upload a "
                                "model file.")
        axis = [k for k, v in DIRECTIONS.items() if np.allclose(v, d, atol=1e-9)]
        sensors.append([ids[node], axis[0] if axis else [float(v) for v in d]])
    return {"nodes": {ids[i]: [float(v) for v in xyz[i]] for i in used}, "members": members,
            "sensors": sensors, "outputs": list(outputs), "units": "m",
            "groups": sorted({m[2] for m in members}), "materials": sorted(MATERIALS), "shapes": list(SHAPES)}


def _group(d: np.ndarray) -> str:
    a = np.abs(d) / max(np.linalg.norm(d), 1e-300)
    if a[2] > 0.999:
        return "vertical"
    if a[0] > 0.999:
        return "along x"
    if a[1] > 0.999:
        return "along y"
    return "inclined"


def _check_sections(sections) -> None:
    """A shape section must say its material (or E, G and density): the helpers' default steel would be a guess."""
    if not isinstance(sections, dict) or not sections:
        raise era.DataError("The model has no sections: give every member group a section and a material.")
    for name, s in sections.items():
        at = f"section:{name}"
        if not isinstance(s, dict):
            raise era.DataError(f"Section {name!r} must be a table (shape and sizes, or area, iy, iz, j, e, g, "
                                "density).", option=at)
        if "shape" in s:
            if s["shape"] not in SHAPES:
                raise era.DataError(f"Section {name!r}: shape {s['shape']!r} is not one of {', '.join(SHAPES)}.",
                                    option=at)
            if not s.get("material") and not all(k in s for k in ("e", "density")):
                raise era.DataError(f"Section {name!r} has no material: choose one ({', '.join(sorted(MATERIALS))}) "
                                    "or give e (Pa) and density (kg/m³).", option=at)
            sizes = [k for k in s if k not in ("shape", "material", "e", "g", "density")]
            bad = [k for k in sizes if not (isinstance(s[k], (int, float)) and not isinstance(s[k], bool)
                                            and math.isfinite(s[k]) and s[k] > 0)]
            if bad:
                raise era.DataError(f"Section {name!r}: {bad[0]} must be a positive size in m, got {s[bad[0]]!r}.",
                                    option=at)


def frame_of(model: dict) -> era.Frame:
    """The era.Frame of a stored model (the file format); era.DataError with the reason when it is not one."""
    if not isinstance(model, dict):
        raise era.DataError("A model must be a table of nodes, members, sections, supports, masses and sensors.")
    for key in TABLES:
        if key in model and not isinstance(model[key], dict):
            raise era.DataError(f"The model's {key} must be a table {{node or name: ...}}, got "
                                f"{type(model[key]).__name__}.")
    for key in LISTS:
        if key in model and not isinstance(model[key], list):
            raise era.DataError(f"The model's {key} must be a list, got {type(model[key]).__name__}.")
        if not all(isinstance(x, list) for x in model.get(key, [])):
            form = "[node i, node j, section]" if key == "members" else "[node, direction]"
            raise era.DataError(f"Each of the model's {key} must be a list: {form}.")
    g = model.get("gravity")
    if g is not None and not (isinstance(g, list) and len(g) == 3 and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in g)):
        raise era.DataError(f"The model's gravity must be null or [gx, gy, gz] in m/s², got {g!r}.")
    _check_sections(model.get("sections"))
    try:
        return era.Frame.from_dict(model)
    except era.EraError as exc:                     # era.Frame's own refusal, placed at the control that fixes it
        raise era.DataError(str(exc), option=exc.option or control(str(exc), model)) from None
    except (TypeError, ValueError) as exc:          # a value of the wrong kind somewhere era did not expect it
        raise era.DataError(f"The model is not in era.Frame's file format: {exc}.") from None


#: era.Frame's refusals (era/structure/, era/fem/space.py) -> the panel's control that fixes them.
_CONTROLS = ((re.compile(r"^Frame: member (\d+) \("), "member:{}"),
             (re.compile(r"\b(?:support|mass|joint spring) at node (.+?)(?::| must| which|, which)"), "node:{}"),
             (re.compile(r"^Frame: node (.+?) (?:must have|is on no member)"), "node:{}"),
             (re.compile(r"^Frame is a mechanism: node (.+?) (?:translation|rotation) "), "node:{}"),
             (re.compile(r"^Frame: (?:a )?sensor"), "sensors"),
             (re.compile(r"^Frame: gravity"), "gravity"))


def control(message: str, model: dict) -> str | None:
    """Which control of the Model panel fixes era.Frame's refusal ``message`` of ``model``: "member:k" (its index
    in model["members"]), "node:id" (its support, mass or members), "section:name", "sensors", "gravity"; None
    when the message names none of them."""
    for pattern, option in _CONTROLS:
        m = pattern.search(message)
        if m:
            return option.format(*m.groups())
    if message.startswith("Section"):               # era.Section does not say which: find the one it refuses
        for name, s in (model.get("sections") or {}).items():
            try:
                era.Section.from_dict(s)
            except (era.EraError, TypeError, ValueError):
                return f"section:{name}"
    return None


def check_channels(fr: era.Frame, outputs: tuple, geometry: era.Geometry | None) -> None:
    """The model's sensors must be the dataset's outputs, in order: as many, and, when the model's nodes carry the
    geometry's labels, at the node and along the direction each channel measures. era.DataError otherwise."""
    p = len(outputs)
    if len(fr.sensors) != p:
        raise era.DataError(f"The model has {counted(len(fr.sensors), 'sensor')} but this dataset has "
                            f"{counted(p, 'output')} "
                            f"({', '.join(outputs)}): list one sensor (node, direction) per output, in the "
                            "outputs' order.", option="sensors")
    if geometry is None or geometry.channel_nodes.size != p:
        return
    labels = [str(i) for i in geometry.node_ids]
    if not all(n in labels for n, _ in fr.sensors):
        return                                   # the model names its nodes its own way: only the count is checked
    for ch, ((node, d), at, where) in enumerate(zip(fr.sensors, geometry.channel_nodes,
                                                    geometry.channel_directions)):
        if at < 0:
            continue
        along = DIRECTIONS[d] if isinstance(d, str) else np.asarray(d, float)
        if labels[at] != node or not np.allclose(along, where, atol=1e-3):
            raise era.DataError(f"Sensor {ch + 1} of the model is at node {node} along {_dir_text(d)}, but output "
                                f"{ch + 1} ({outputs[ch]}) measures node {labels[at]} along {_dir_text(where)}: "
                                "list the sensors in the outputs' order.", option="sensors")


def check_channels_of(model: dict, outputs: tuple, geometry: era.Geometry | None) -> None:
    """:func:`check_channels` of a stored model: a quick refusal before an explanation is queued."""
    check_channels(frame_of(model), outputs, geometry)


def _dir_text(d) -> str:
    if isinstance(d, str):
        return d
    axis = [k for k, v in DIRECTIONS.items() if np.allclose(v, d, atol=1e-3)]
    return axis[0] if axis else "(" + ", ".join(f"{float(v):.3g}" for v in d) + ")"


def read_file(name: str, blob: bytes) -> dict:
    """A model file's table: TOML when the name ends in .toml, else JSON. era.DataError for anything else."""
    if len(blob) > MAX_MODEL_BYTES:
        raise era.DataError(f"{name}: a model file of {len(blob)} bytes is larger than {MAX_MODEL_BYTES}.")
    try:
        text = blob.decode("utf-8")
        return tomllib.loads(text) if name.lower().endswith(".toml") else json.loads(text)
    except (UnicodeDecodeError, ValueError) as exc:          # JSONDecodeError and TOMLDecodeError are ValueErrors
        raise era.DataError(f"{name}: not a readable model file (era.Frame JSON, or TOML named .toml): {exc}") from None


def checked(model: dict, outputs: tuple, geometry: era.Geometry | None) -> tuple[era.Frame, np.ndarray]:
    """(Frame, its lowest N_MODES frequencies in Hz) of a model for this dataset, or era.DataError: a member to a
    missing node, a section without a material, a mechanism (the solver names the free DOF), sensors that are
    not the dataset's channels. Blocking (one eigen-solution)."""
    fr = frame_of(model)
    check_channels(fr, outputs, geometry)
    try:     # the elastic modes: a free frame's six rigid-body modes at 0 Hz left out, as explain leaves them
        f_hz = fr.modes(N_MODES + fr.n_rigid_modes)[0][fr.n_rigid_modes:]
    except era.EraError as exc:                     # a mechanism: at the node the solver names
        raise era.DataError(str(exc), option=exc.option or control(str(exc), model)) from None
    return fr, f_hz


def fingerprint(model: dict) -> str:
    """A short hash of a model as described (its JSON with sorted keys): equal exactly when the model is, whatever
    the order its tables were written in. Tells whether an explanation was made with the model stored now."""
    text = json.dumps(model, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def used(stored: dict | None) -> dict:
    """What an explanation was made with (schemas.UsedModel), kept in its summary: the stored model's source, name,
    time saved, fingerprint and one-line description; or, with no stored model, the NASA grid's built-in model."""
    if stored is None:
        return {"source": "grid", "name": None, "saved": None, "fingerprint": None,
                "text": "the NASA grid's built-in model (era.examples.grid.nasa_grid)"}
    return {"source": stored["source"], "name": stored.get("name"), "saved": stored.get("saved"),
            "fingerprint": fingerprint(stored["model"]), "text": describe(stored["model"])}


def stale(summary: dict, stored: dict | None) -> str | None:
    """Why an explanation (its stored summary) no longer matches the dataset's model ``stored`` now, in words; None
    while it does. An explanation stored before its model was recorded is compared by its one-line description."""
    was = summary.get("model_used")
    if was is None:                                  # before model_used was kept: its description, if a frame
        if stored is None:
            return None
        if summary.get("model_text") == describe(stored["model"]):
            return None
        was = {"source": "geometry" if summary.get("model_text") else "grid", "fingerprint": None,
               "text": summary.get("model_text") or used(None)["text"]}
    elif stored is None:
        return None if was["source"] == "grid" else (
            "This result was made with a structure model the dataset no longer has; run simulation vs test again.")
    elif was.get("fingerprint") == fingerprint(stored["model"]):
        return None
    return (f"This result was made with an earlier model: {was['text']}. The dataset's model has changed since "
            f"(now {describe(stored['model'])}): run simulation vs test again to compare with it.")


def summary(stored: dict, fr: era.Frame, f_hz) -> dict:
    """The answer for a stored model (schemas.StructureModel): the model as described, where it came from, and
    what it is (counts, mass in kg, lowest frequencies in Hz, a one-line description, its fingerprint)."""
    return {"model": stored["model"], "source": stored["source"], "name": stored.get("name"),
            "saved": stored.get("saved"), "fingerprint": fingerprint(stored["model"]),
            "n_nodes": len(fr.nodes), "n_members": len(fr.members),
            "n_sensors": len(fr.sensors), "total_mass_kg": fr.total_mass_kg, "total_mass": fr.total_mass_kg,
            "mass_unit": "kg", "mass_unit_note": "era.Frame models are in SI units",
            "frequency_hz": [float(f) for f in f_hz], "text": describe(stored["model"])}


def describe(model: dict) -> str:
    """The model in one line, for the panel and the report: counts, sections, supports, masses; an FE model's
    file and counts, and how many outputs its mapping matches."""
    if "fe" in model:
        rows = model.get("mapping", [])
        return (f"{model['fe']['text']}; {sum(r['matched'] for r in rows)} of {len(rows)} outputs matched to its "
                "nodes")
    nodes, members = model.get("nodes", {}), model.get("members", [])
    secs = []
    for name, s in model.get("sections", {}).items():
        if "shape" in s:
            sizes = " × ".join(f"{1000 * s[k]:g}" for k in ("width", "depth", "diameter", "wall") if k in s)
            secs.append(f"{name}: {s['shape'].replace('_', ' ')} {sizes} mm {s.get('material', '')}".rstrip())
        else:
            secs.append(f"{name}: A {s.get('area', 0):.3g} m², E {s.get('e', 0):.3g} Pa")
    sup = [f"{n} {s if isinstance(s, str) else 'springs'}" for n, s in model.get("supports", {}).items()]
    mass = [f"{n} {m:g} kg" for n, m in model.get("masses", {}).items()]
    return (f"{len(nodes)} nodes, {len(members)} members; sections {'; '.join(secs) or 'none'}; supports "
            f"{', '.join(sup) or 'none (free-free)'}; masses {', '.join(mass) or 'none'}; "
            f"{len(model.get('sensors', []))} sensors" + ("; gravity" if model.get("gravity") else ""))


def compare(fr: era.Frame, frequency_hz, shapes) -> dict:
    """The model's modes beside the test's (schemas.ModelComparison): frequencies (Hz), the MAC matrix (test
    modes × model modes) at the sensors, and each test mode's partner (era.core.correlation.pair_modes: frequency and
    MAC together, as explain pairs them; null when none is acceptable). frequency_hz (k,), shapes (p, k) complex:
    the test's modes, e.g. those kept at one order. The model gives 6 modes more than the test, so a mode that
    moved can still be found. A free frame's rigid-body modes (0 Hz) are left out, as explain leaves them."""
    from era import real_shapes

    f_test = np.asarray(frequency_hz, float)
    test = real_shapes(np.asarray(shapes))
    r = fr.n_rigid_modes
    f_model, s_model = fr.modes(max(N_MODES, test.shape[1] + 6) + r)
    f_model, s_model = f_model[r:], s_model[:, r:]
    return comparison(f_test, test, f_model, s_model)


def comparison(f_test, test, f_model, s_model) -> dict:
    """schemas.ModelComparison of test modes (f_test (k,) Hz, real shapes (p, k)) and model modes (f_model (n,) Hz,
    shapes (p, n) at the same points): each test mode's partner by era.pair_modes, or null when none is acceptable."""
    from era import pair_modes

    p = pair_modes(f_test, test, f_model, s_model)
    partner = {int(i): k for k, i in enumerate(p.measured_index)}
    best = [None if i not in partner else {"model_mode": int(p.model_index[partner[i]]),
                                           "mac": float(p.mac[partner[i]]),
                                           "frequency_error_pct": float(p.frequency_error_pct[partner[i]])}
            for i in range(f_test.size)]
    return {"test_hz": [float(f) for f in f_test], "model_hz": [float(f) for f in f_model],
            "mac": [[float(v) for v in row] for row in p.mac_matrix], "best": best}
