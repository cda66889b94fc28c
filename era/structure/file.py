"""Frame model files: an era.Frame (era/structure/frame.py) as JSON (written) and JSON or TOML (read).

The format (``Frame.to_dict``/``save``: JSON; ``Frame.load`` also reads TOML, by the ``.toml`` suffix)::

    {"format": "era.frame", "version": 1,              # SI units throughout: m, kg, N, Pa, s
     "nodes": {"1": [0, 0, 0], "2": [0, 0, 0.9]},     # id -> [x, y, z] m
     "sections": {"col": {"area": 3e-4, "iy": 9e-10, "iz": 6.25e-8, "j": 3.4e-9, "e": 2e11, "g": 7.7e10,
                          "density": 7850, "ip": 6.3e-8},
                  "bar": {"shape": "rectangle", "width": 0.05, "depth": 0.006, "material": "steel"}},
     "members": [["1", "2", "col"], ["2", "3", "bar", [0, 1, 0]]],   # [node i, node j, section(, local z)]
     "supports": {"1": "fixed", "4": "pinned", "7": {"kz": 2e5, "ry": 1e3, "kx": "fixed"},
                  "9": {"cable": 0.51}},
     "masses": {"9": 0.025},                           # kg on the node's three translations
     "sensors": [["3", "x"], ["7", "-z"], ["8", [0.6, 0.8, 0]]],   # [node, "x"|"-x"|... or a direction vector]
     "gravity": [0, 0, -9.81],                          # or null / absent
     "elements_per_member": null}                       # null: automatic (converged to 0.1 %), n, or [n, ...]

See era/structure/frame.py for sections given by shape, supports and cables. The functions take the Frame class
(``cls``) they build: this module does not import era/structure/frame.py, which imports it.
"""

from __future__ import annotations

import json
import math
import tomllib
from dataclasses import asdict, fields
from pathlib import Path

from ..errors import DataError
from ..fem.solution import SUPPORT_KEYS
from ..words import listed


def frame_to_dict(frame) -> dict:
    """The file format of the module docstring, of an era.Frame ``frame`` (JSON-ready: no inf, no numpy types)."""
    def support(spec):
        if spec == dict.fromkeys(SUPPORT_KEYS, math.inf):
            return "fixed"
        if spec == dict.fromkeys(SUPPORT_KEYS[:3], math.inf):
            return "pinned"
        return {k: "fixed" if math.isinf(v) else v for k, v in spec.items()}
    return {"format": "era.frame", "version": 1,
            "nodes": {k: list(v) for k, v in frame.nodes.items()},
            "sections": {k: asdict(s) for k, s in frame.sections.items()},
            "members": [[i, j, s] + ([] if o is None else [list(o)]) for i, j, s, o in frame.members],
            "supports": {k: support(v) for k, v in frame.supports.items()},
            "masses": dict(frame.masses),
            "sensors": [[n, d if isinstance(d, str) else list(d)] for n, d in frame.sensors],
            "gravity": None if frame.gravity is None else list(frame.gravity),
            "elements_per_member": (list(frame.elements_per_member) if isinstance(frame.elements_per_member, tuple)
                                    else frame.elements_per_member)} | (
            {"joint_springs": dict(frame.joint_springs)} if frame.joint_springs else {}) | (
            {"added_mass_per_length": dict(frame.added_mass_per_length)} if frame.added_mass_per_length else {})


def frame_from_dict(d: dict, cls: type):
    """A ``cls`` (era.Frame) from the file format (as read from JSON or TOML); unknown keys are refused."""
    if not isinstance(d, dict):
        raise DataError(f"Frame: a model must be a table of nodes, sections, members, ..., got {type(d).__name__}.")
    if d.get("format", "era.frame") != "era.frame" or d.get("version", 1) != 1:
        raise DataError(f"Frame: not an era.frame model of version 1 (format {d.get('format')!r}, "
                        f"version {d.get('version')!r}).")
    known = {f.name for f in fields(cls)}
    unknown = set(d) - known - {"format", "version"}
    if unknown:
        raise DataError(f"Frame: unknown {'keys' if len(unknown) > 1 else 'key'} {listed(sorted(unknown), quote=True)}; "
                        f"known: {listed(sorted(known), quote=True)}.")
    missing = {"nodes", "members", "sections"} - set(d)
    if missing:
        raise DataError(f"Frame: the model lacks {sorted(missing)}.")
    sections = d["sections"]
    if not isinstance(sections, dict) or not all(isinstance(s, dict) for s in sections.values()):
        raise DataError("Frame: sections must be a table of section tables.")
    return cls(**{k: v for k, v in d.items() if k in known})


def save_frame(frame, path) -> None:
    """Write an era.Frame ``frame`` as JSON."""
    Path(path).write_text(json.dumps(frame_to_dict(frame), indent=1) + "\n", encoding="utf-8")


def load_frame(path, cls: type):
    """A ``cls`` (era.Frame) read from JSON, or from TOML when the name ends in .toml."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
        d = tomllib.loads(text) if path.suffix.lower() == ".toml" else json.loads(text)
    except (OSError, UnicodeDecodeError, ValueError) as exc:    # JSONDecodeError and TOMLDecodeError too
        raise DataError(f"{path.name}: not a readable model file: {exc}") from None
    try:
        return frame_from_dict(d, cls)
    except DataError as exc:
        raise DataError(f"{path.name}: {exc}") from None


