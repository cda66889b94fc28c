"""Multi-setup tests in the app: several files, each the records of one setup of a test, read as a
single upload is (era.load); the reference channels picked (the same physical sensors, in the same order, in every
setup); each setup through era.analyse, the setups through era.merge_setups; the merged modes kept as one JSON
document.

A test is files only (no table), in the store's ``setups/{id}/``: the uploaded files as they came
(``setup1.bin`` ...), ``test.json`` (schemas.SetupsTest without ``merged``: the setups' channels and the proposed
references), written once after the files, and ``merged.json`` (schemas.SetupsMerged), written again at every
merge. The merged document holds everything the page draws, so the test's link (/s/{id}) reopens the result.
Every setup is read and analysed as era.load and era.analyse do (ambient records through NExT), and the merge takes
the library's path, era.merge_choosing_next: ambient setups are merged with every channel as NExT reference and with
the picked references only, and the merge with more modes complete is kept (so the page and
era.merge_ambient_setups give one answer). The upload analyses the setups at once to propose the references from
the data through the analyses the merge uses (app.setups_analyses: era.propose_ambient_references on ambient
records, era.reference_evidence on others); the names propose them only when the data cannot and the names are not
generic. A merge may also join the correlations before one identification (PreGER, app.setups_preger).

A mode seen in some setups only follows era.merge_setups' rule: kept when two setups or more chose it (its
frequency and damping from those), its shape unknown (null, never 0) at the points of the setups that did not see
it; a mode of one setup only is left out with its reason. The page says "seen in 3 of 4 setups"; UFF 55 keeps the
modes known at every point and the CSV leaves unknown values empty.

Every function is plain and blocking (the routes run them on the job pools).
"""

from __future__ import annotations

import json
import re
import time

import numpy as np

import era
from era.setups import (WAY_WORDS, merge_with_evidence, merged_geometry, parse_points, point_aliases,
                        points_geometry)
from era.words import listed

from .errors import NotFound
from .importing import page_words
from .loading import check_stored, load_upload
from .payloads import floats
from . import setups_analyses, setups_preger
from .reporting import geometry_json
from .store import new_token, write_atomic

#: A multi-setup test has at least this many setups (one file is an ordinary dataset) ...
MIN_SETUPS = 2
#: ... and at most this many.
MAX_SETUPS = 32
#: What a test id looks like (store.new_token's alphabet): nothing else becomes a folder name.
_ID = re.compile(r"[A-Za-z0-9_-]{1,64}")
#: References a merge needs at least: with one, every pair of modes has reference MAC 1, so a wrong pick passes.
MIN_REFERENCES = 2
#: A setup's scale whose relative σ exceeds this is said in its mode's note.
SCALE_STD_SAID = 0.05
#: The options a setups upload takes (the controls of the page's form), as era.load names them.
OPTIONS = ("kind", "dt")


class Refusal(era.DataError):
    """A refusal said next to the page's control ``option`` ("file", "kind", "dt", "references", "points")."""

    def __init__(self, message: str, option: str):
        super().__init__(message, option=option)


# ---- a new test: one file per setup ------------------------------------------------------------------------------
def create(store, settings, files: list[tuple[str, bytes]], kind: str = "auto", dt: float | None = None,
           name: str | None = None) -> dict:
    """Read every file as one setup (era.load, the rules of a single upload), keep the files, and write the test.
    Returns schemas.SetupsTest. Refuses (Refusal, its control named) one file, too many, or a file that cannot be
    read, before keeping anything."""
    if len(files) < MIN_SETUPS:
        raise Refusal(f"One file is one setup: a multi-setup test needs {MIN_SETUPS} files or more, one per setup "
                      "(each with the reference sensors and that setup's roving ones). For one file, use the main "
                      "page's import step.", "file")
    if len(files) > MAX_SETUPS:
        raise Refusal(f"{len(files)} files: at most {MAX_SETUPS} setups make one test.", "file")
    setups = []
    for k, (file_name, blob) in enumerate(files):
        data, geometry, source = _read(settings, k, file_name, blob, kind, dt)
        conversions = " ".join(str(c) for c in source.get("conversions") or ())
        setups.append({"file": file_name, "outputs": list(data.outputs), "n_samples": int(data.n_samples),
                       "dt": float(data.dt), "has_geometry": geometry is not None, "ambient": "NExT" in conversions})
    outputs = [s["outputs"] for s in setups]
    test = {"id": new_token(), "name": name or f"{files[0][0]} + {len(files) - 1} more", "created": time.time(),
            "kind": kind, "dt": dt, "setups": setups, "unmatched": unmatched(outputs)}
    folder = _folder(store, test["id"])
    for k, (_, blob) in enumerate(files):
        write_atomic(folder / f"setup{k + 1}.bin", blob)
    try:
        evidence = setups_analyses.propose_from_data(_reader(store, settings, test), test, _refusal)
    except Refusal as exc:  # a setup that cannot be analysed: said at the merge, next to its file
        evidence = era.ReferenceProposal(None, np.zeros(0), np.zeros((len(files), 0), int), (),
                                         f"the setups could not all be analysed ({exc}), so the data propose nothing")
    test.update(proposal(outputs, evidence))
    write_atomic(folder / "test.json", json.dumps(test).encode())  # last: the commit point
    return dict(test, merged=None)


def _read(settings, k: int, file_name: str, blob: bytes, kind: str, dt: float | None, references=None):
    """(data, geometry, source) of setup k's file through era.load (app.loading.load_upload); the refusal in the
    page's words, prefixed with the setup, next to the control that fixes it."""
    try:
        data, geometry, source = load_upload([(file_name, blob)], kind, settings.max_upload_bytes, dt=dt,
                                             references=references)
        check_stored(data, settings.max_upload_bytes)
    except era.TooLargeError:
        raise
    except era.EraError as exc:
        option = getattr(exc, "option", None)
        raise Refusal(f"Setup {k + 1} ({file_name}): {page_words(str(exc))}",
                      option if option in OPTIONS else "file") from None
    return data, geometry, source


def propose_by_names(outputs: list[list[str]]) -> tuple[list[str], list[list[int]]]:
    """The references the names propose: the channel names in every setup, in the first setup's order; (names,
    their index in each setup). Empty when no name is in every setup, or when every channel of a setup is among
    them (generic names such as ch1..ch8 repeat in every setup and say nothing of where the sensors are)."""
    common = [name for name in outputs[0] if all(name in out for out in outputs[1:])]
    if any(len(common) >= len(out) for out in outputs):
        return [], [[] for _ in outputs]
    return common, [[out.index(name) for name in common] for out in outputs]


#: How many of era.reference_evidence's candidate pairs the page shows (best first).
SHOWN_CANDIDATES = 4


def proposal(outputs: list[list[str]], evidence) -> dict:
    """The fields of schemas.SetupsTest that propose the references: from the data (era.reference_evidence) when
    they tell, else from the names (:func:`propose`) when those are not generic, else none; with the evidence."""
    names, by_name = propose_by_names(outputs)
    if evidence.references is not None:
        refs, source = evidence.references, "data"
    elif names:
        refs, source = by_name, "names"
    else:
        refs, source = [[] for _ in outputs], ""
    shown = []
    for c in evidence.candidates[:SHOWN_CANDIDATES]:
        shown.append({"channels": [[outputs[k][i] for i in ch] for k, ch in enumerate(c.channels)],
                      "indices": [list(ch) for ch in c.channels], "score": float(c.score),
                      "runner_up": _num(c.runner_up), "mac": floats(c.mac)})
    return {"proposed": [list(r) for r in refs], "proposed_names": [outputs[0][i] for i in refs[0]],
            "proposed_from": source, "data_proposal": evidence.reason,
            "shared_hz": floats(evidence.shared_hz), "candidates": shown}


def unmatched(outputs: list[list[str]]) -> list[dict]:
    """The first setup's channel names that some other setups have and some do not (a reference renamed or
    missing in a setup): [{"name", "missing_in": [setups, 1-based]}]."""
    out = []
    for name in outputs[0]:
        missing = [k + 1 for k, names in enumerate(outputs) if name not in names]
        if missing and len(missing) < len(outputs) - 1:
            out.append({"name": name, "missing_in": missing})
    return out


def _folder(store, test_id: str):
    """The test's folder in the store's data folder (``setups/{id}``); NotFound for a string that is no id."""
    if not _ID.fullmatch(test_id):
        raise NotFound(f"No multi-setup test {test_id!r}: check that the whole link was copied.")
    return store.root / "setups" / test_id


def load(store, test_id: str) -> dict:
    """schemas.SetupsTest: the test and its last merge (or null). NotFound for an unknown id."""
    folder = _folder(store, test_id)
    if not (folder / "test.json").is_file():
        raise NotFound(f"No multi-setup test {test_id!r}: check that the whole link was copied.")
    test = json.loads((folder / "test.json").read_bytes())
    merged = folder / "merged.json"
    nodes = folder / "nodes.json"
    return dict(test, merged=json.loads(merged.read_bytes()) if merged.is_file() else None,
                nodes=json.loads(nodes.read_bytes()) if nodes.is_file() else None)


# ---- a report: the last merge frozen --------------------------------------------------------------------------
def freeze(store, test_id: str) -> dict:
    """A report of the test's last merge: the test and its merged modes and geometry as they are now, frozen in
    ``setups/{id}/reports/{token}.json`` (a later merge does not change it). Returns {"token", "url"}; the link
    (/s/{id}/r/{token}) reopens the merged modes on their geometry. NotFound before the first merge."""
    test = load(store, test_id)
    if test["merged"] is None:
        raise NotFound("This test is not merged yet: pick its references and merge it first.")
    token = new_token()
    url = f"/s/{test_id}/r/{token}"
    doc = dict(test, report={"token": token, "url": url, "created": time.time()})
    write_atomic(_folder(store, test_id) / "reports" / f"{token}.json", json.dumps(doc).encode())
    return {"token": token, "url": url}


def report(store, test_id: str, token: str) -> dict:
    """schemas.SetupsTest as frozen by :func:`freeze` (its ``report`` says when); NotFound for an unknown link."""
    path = _folder(store, test_id) / "reports" / f"{token}.json"
    if not _ID.fullmatch(token) or not path.is_file():
        raise NotFound("No report of this multi-setup test has this link: check that the whole link was copied.")
    return json.loads(path.read_bytes())


# ---- the nodes of a UFF file (UFF 15, trace lines 82): where a points table point,node,direction puts its points
def set_nodes(store, settings, test_id: str, file_name: str, blob: bytes) -> dict:
    """Keep a UFF file of the test's nodes (``nodes.bin``, its summary in ``nodes.json``) for a points table
    ``point,node,direction`` (era.setups.geometry). Returns schemas.SetupsTest. Refusal next to the points when the
    file has no nodes."""
    test = load(store, test_id)
    geometry = _nodes_geometry(settings, file_name, blob)
    summary = {"file": file_name, "n_nodes": int(geometry.node_ids.size), "n_lines": int(len(geometry.line_ids)),
               "node_ids": [int(n) for n in geometry.node_ids[:200]]}
    folder = _folder(store, test_id)
    write_atomic(folder / "nodes.bin", blob)
    write_atomic(folder / "nodes.json", json.dumps(summary).encode())
    return dict(test, nodes=summary)


def _nodes_geometry(settings, file_name: str, blob: bytes):
    """era.Geometry of a UFF file's nodes and trace lines (era.load); Refusal ("points") when it has none."""
    try:
        geometry = era.load(blob, name=file_name, max_bytes=settings.max_upload_bytes).geometry
    except era.TooLargeError:
        raise
    except era.EraError as exc:
        raise Refusal(f"{file_name}: {page_words(str(exc))}", "points") from None
    if geometry is None or geometry.node_ids.size == 0:
        raise Refusal(f"{file_name} defines no nodes: give a UFF file with nodes (UFF 15, and trace lines, UFF 82) "
                      "for a points table point,node,direction.", "points")
    return geometry


def stored_nodes(store, settings, test: dict):
    """The test's nodes (era.Geometry of its kept UFF file), or None when none was given."""
    if not test.get("nodes"):
        return None
    blob = (_folder(store, test["id"]) / "nodes.bin").read_bytes()
    return _nodes_geometry(settings, test["nodes"]["file"], blob)


# ---- the merge --------------------------------------------------------------------------------------------------
def checked_references(test: dict, references) -> list[list[int]]:
    """The references as the picker sent them, checked in the page's words (Refusal next to the picker)."""
    setups = test["setups"]
    if len(references) != len(setups):
        raise Refusal(f"References are given for {len(references)} setups, but the test has {len(setups)}: pick "
                      "them for every setup.", "references")
    if len(references[0]) < MIN_REFERENCES:
        picked = "No reference channel is" if not references[0] else "One reference channel is"
        raise Refusal(f"{picked} picked: the setups are joined through sensors that stay in place in every setup, "
                      f"and it takes {MIN_REFERENCES} or more to tell a wrong pick (with one, every mode's "
                      "references agree). Pick at least two in every setup.", "references")
    out = []
    for k, (refs, s) in enumerate(zip(references, setups)):
        refs = [int(i) for i in refs]
        label = f"Setup {k + 1} ({s['file']})"
        if len(refs) != len(references[0]):
            raise Refusal(f"{label} has {len(refs)} reference channels picked where setup 1 has "
                          f"{len(references[0])}: the references are the same sensors in every setup.", "references")
        if any(i < 0 or i >= len(s["outputs"]) for i in refs):
            raise Refusal(f"{label} has {len(s['outputs'])} channels; a picked reference is not one of them.",
                          "references")
        if len(set(refs)) != len(refs):
            names = [s["outputs"][i] for i in refs]
            raise Refusal(f"{label}: channel {next(n for n in names if names.count(n) > 1)} is picked as two "
                          "references; each reference is another sensor.", "references")
        out.append(refs)
    return out


#: era.merge_setups' words -> the page's (the picker, not the ``references`` argument).
_PAGE_WORDS = ((re.compile(r"Check references\[(\d+)\] \(or the earlier setups' references\)"),
                lambda m: f"Check setup {int(m.group(1)) + 1}'s references in the picker (or the earlier setups')"),
               (re.compile(r"\(era\.analyse chose none\)"), "(its analysis found none)"))


def _in_page_words(text: str) -> str:
    for pattern, words in _PAGE_WORDS:
        text = pattern.sub(words, text)
    return text


def _reader(store, settings, test: dict):
    """read(k, setup) -> (data, geometry): setup k's kept file through era.load (app.setups_analyses reads once)."""
    folder = _folder(store, test["id"])

    def read(k: int, s: dict):
        blob = (folder / f"setup{k + 1}.bin").read_bytes()
        data, geometry, _ = _read(settings, k, s["file"], blob, test["kind"], test.get("dt"))
        return data, geometry
    return read


def _refusal(k: int, s: dict, exc) -> Refusal:
    return Refusal(f"Setup {k + 1} ({s['file']}) cannot be analysed: {exc}", "file")


def analyse_setups(store, settings, test: dict, refs: list[list[int]] | None = None) -> list:
    """[(era.analyse result, geometry or None)] of every setup, as era.load and era.analyse make them (ambient
    records: NExT with every channel as reference, or with ``refs``, per setup its reference indices, only):
    app.setups_analyses, which reads each file once and keeps the analyses for the merges."""
    return setups_analyses.analyses(_reader(store, settings, test), test, refs, _refusal)


#: How ambient records are correlated (NExT) at a merge: "auto" merges both ways and keeps the better merge
#: (era.merge_choosing_next: more modes complete, ties to more consistent shapes); "every" channel a reference
#: (era.load's default) or the picked "references" only (era.load's ``references``) as asked.
NEXT_REFERENCES = ("auto", "every", "references")


def merge_test(store, settings, test: dict, references, points: str | None = None,
               next_references: str = "auto", method: str = "poser") -> dict:
    """Analyse every setup, merge them through ``references`` (per setup, the indices of its reference channels),
    write and return schemas.SetupsMerged. ``points``: the test's points table as typed (CSV point,x,y,z,direction
    then optional from,to lines, era.setups.geometry), which places the merged points; else the files' geometry.
    ``method``: "poser" (each setup identified, then the shapes joined: era.merge_setups) or "preger" (the
    correlations joined, then one identification: app.setups_preger). ``next_references`` (PoSER): "auto" (ambient
    records merged with both NExT references and the better merge kept, as era.merge_ambient_setups does),
    "every" (every channel a NExT reference) or "references" (the picked ones only).
    Refusal next to the picker when the merge refuses, next to the points when the table is wrong."""
    refs = checked_references(test, references)
    ambient = any(s.get("ambient") for s in test["setups"])
    preger = None
    try:
        if method == "preger":
            result, geometries, said, preger = setups_preger.preger(
                _reader(store, settings, test), test, refs, lambda text: Refusal(text, "references"))
            used, complete = "references", []
        else:
            runs = analyse_setups(store, settings, test)  # every channel: made at the upload, reused
            if next_references == "auto":
                only = analyse_setups(store, settings, test, refs) if ambient else None
                choice = era.merge_choosing_next([a for a, _ in runs],
                                                 None if only is None else [a for a, _ in only], refs)
                result, used, said = choice.result, choice.used, choice.reason
                complete = [int(x) for x in choice.complete]
            else:
                if next_references == "references":
                    runs = analyse_setups(store, settings, test, refs)
                result, used = merge_with_evidence([a for a, _ in runs], refs), next_references
                said, complete = f"As asked: {WAY_WORDS[used]}.", []
            geometries = [g for _, g in runs]
    except era.DataError as exc:
        raise Refusal(_in_page_words(str(exc)), "references") from None
    if points and points.strip():
        aliases = point_aliases(result.model.points, result.point_setup, result.point_channel,
                                [s["outputs"] for s in test["setups"]], refs)
        try:
            table = parse_points(points, nodes=stored_nodes(store, settings, test))
            geometry = points_geometry(table, aliases)
        except era.DataError as exc:
            raise Refusal(str(exc), "points") from None
    else:
        geometry = merged_geometry(geometries, result)
    merged = dict(merged_json(test, refs, result, geometry), points_table=points or "", next_references=used,
                  next_asked=next_references, next_choice=_in_page_words(said), next_complete=complete,
                  method=method)
    if preger is not None:
        merged.update(modes=setups_preger.modes_words(merged["modes"], len(test["setups"])),
                      next_asked="references", preger_scales=floats(preger.scales),
                      preger_residual=floats(preger.reference_residual))
    write_atomic(_folder(store, test["id"]) / "merged.json", json.dumps(merged).encode())
    return merged


def merged_json(test: dict, refs: list[list[int]], result, geometry) -> dict:
    """schemas.SetupsMerged of an era.setups.poser.merge_with_evidence result."""
    model = result.model
    setups = test["setups"]
    n_setups = len(setups)
    chosen = result.members >= 0
    known = chosen | result.recovered
    modes = []
    for j in range(model.n_modes):
        missing = [k for k in range(n_setups) if not known[j, k]]
        unknown_at = [model.points[q] for q in np.flatnonzero(~np.isfinite(model.point_shapes[:, j]))]
        n_seen = int(chosen[j].sum())
        note = [f"shape unknown at the points of setup{'s' if len(missing) > 1 else ''} "
                f"{listed(k + 1 for k in missing)} ({', '.join(unknown_at)})"] if missing else []
        note += [f"setup {k + 1}'s part from a weak cluster its analysis had left out, confirmed by the others"
                 for k in np.flatnonzero(result.recovered[j])]
        by_f = [k + 1 for k in np.flatnonzero(result.by_frequency[j])]
        if by_f:
            note.append(f"setup{'s' if len(by_f) > 1 else ''} {listed(by_f)} paired by frequency alone (the only "
                        "mode there within the window; the references barely move in this mode, so their "
                        "components did not agree)")
        sd = result.scale_std[j]
        if np.any(np.isfinite(sd)) and np.nanmax(sd) > SCALE_STD_SAID:
            worst = int(np.nanargmax(sd))
            note.append(f"scale of setup {worst + 1}'s part uncertain by ±{100 * sd[worst]:.0f} %")
        modes.append({"frequency_hz": float(model.frequency_hz[j]), "damping_ratio": float(model.damping_ratio[j]),
                      "frequency_std_hz": _num(model.frequency_std_hz[j]), "damping_std": _num(model.damping_std[j]),
                      "mpc": _num(model.mpc[j]), "seen_in": n_seen, "seen": f"seen in {n_seen} of {n_setups} setups",
                      "complete": bool(not missing), "missing_setups": [k + 1 for k in missing],
                      "paired_by_frequency": [k + 1 for k in np.flatnonzero(result.by_frequency[j])],
                      "scale_std": [_num(x) for x in result.scale_std[j]],
                      "note": "; ".join(note)})
    s = np.asarray(model.eigenvalues, dtype=complex)
    return {
        "references": refs, "reference_names": [setups[0]["outputs"][i] for i in refs[0]],
        "setups": [s["file"] for s in setups], "points": list(model.points),
        "point_setup": [int(k) + 1 for k in result.point_setup],  # 0: a reference (every setup)
        "modes": modes, "eigenvalue_re": floats(s.real), "eigenvalue_im": floats(s.imag),
        "shapes_re": floats(model.point_shapes.real.T), "shapes_im": floats(model.point_shapes.imag.T),
        "dropped": [{"setup": d.setup + 1, "file": setups[d.setup]["file"], "frequency_hz": d.frequency_hz,
                     "reason": d.reason} for d in result.dropped],
        "geometry": geometry_json(geometry), "uncertainty_source": model.uncertainty_source, "merged": time.time(),
    }


def _num(x) -> float | None:
    x = float(x)
    return x if np.isfinite(x) else None
