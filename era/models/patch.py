"""The fix back out, in the engineer's terms: the stiffness and/or mass matrix of a MatrixModel with the effects
explain named put in, as Matrix Market files over the same DOFs (dofs.csv beside them), ready to load back into
the program the matrices came from (a DMIG/direct matrix input, an ANSYS superelement, an Abaqus *MATRIX INPUT)
or into era.load_model.

    files = patch_files(model, explanation.updated_model.params)   # {"K.mtx": ..., "dofs.csv": ..., ...}
    save_patch(model, explanation.updated_model.params, "fix.zip")
"""

from __future__ import annotations

import zipfile
from pathlib import Path

from ..errors import DataError
from .changes import EFFECT_DEFAULTS, changed_matrices, split_dof
from .matrix import MatrixModel
from .write import mtx_bytes

#: Which matrix each effect keyword changes.
STIFFNESS_KEYS = ("spring_stiffness", "part_factor")
MASS_KEYS = ("point_mass", "part_mass_factor", "distributed_mass")


def _effects(params: dict) -> dict:
    """The effect keywords of ``params`` that differ from the nominal's, the global stiffness factor left out."""
    keep = {k: v for k, v in params.items() if k in EFFECT_DEFAULTS and k != "stiffness_factor"}
    return {k: v for k, v in keep.items() if v != EFFECT_DEFAULTS[k]}


def describe_patch(model: MatrixModel, params: dict) -> list[str]:
    """One line per change, in the model's units."""
    p, u = {**EFFECT_DEFAULTS, **params}, model.units
    out = []
    if p["point_mass_at"] is not None and p["point_mass"]:
        out.append(f"point mass {p['point_mass']:.6g} {u['mass']} on the translations of node {p['point_mass_at']}"
                   " (added to M's diagonal)")
    if p["spring_at"] is not None and p["spring_stiffness"]:
        node, d = split_dof(p["spring_at"])
        unit = f"{u['force']}/{u['length']}" if d in ("x", "y", "z") else f"{u['force']}·{u['length']}/rad"
        out.append(f"spring to ground {p['spring_stiffness']:.6g} {unit} on node {node} direction {d} (added to "
                   "K's diagonal)")
    if p["part_at"] is not None and p["part_factor"] != 1.0:
        out.append(f"part {str(p['part_at']).removeprefix('part:')} stiffness × {p['part_factor']:.6g}")
    if p["part_mass_at"] is not None and p["part_mass_factor"] != 1.0:
        out.append(f"part {str(p['part_mass_at']).removeprefix('part:')} mass × {p['part_mass_factor']:.6g}")
    if p["distributed_mass"]:
        out.append(f"spread mass {p['distributed_mass']:.6g} {u['mass']} (M × "
                   f"{1 + p['distributed_mass'] / model.total_mass():.6g})")
    return out


def patch_files(model: MatrixModel, params, *, stiffness_factor: bool = False) -> dict[str, bytes]:
    """{file name: content}: ``K.mtx`` and/or ``M.mtx`` (only the matrices the effects change) with the effects
    of ``params`` put in, ``dofs.csv`` (their rows), and ``README.txt`` saying what changed.

    params : the explain parameters of the updated model ({keyword: value}, e.g. ``Explanation.updated_model
        .params``), or an object with ``.params`` or ``.updated_model``.
    stiffness_factor : also scale K by the fitted global stiffness factor (by default the named effects only:
        the factor is the nuisance every fit carries, reported in README.txt).
    """
    holder = getattr(params, "updated_model", params)
    params = dict(getattr(holder, "params", holder))
    changes = _effects(params)
    factor = float(params.get("stiffness_factor", 1.0))
    applied = {**changes, "stiffness_factor": factor if stiffness_factor else 1.0}
    lines = describe_patch(model, params)
    base, deck_text = _deck_parts(model, params, lines)
    k, m = changed_matrices(base, applied)
    files: dict[str, bytes] = {}
    changed_deck = base is not model
    if any(key in changes for key in STIFFNESS_KEYS) or (stiffness_factor and factor != 1.0) or changed_deck:
        files["K.mtx"] = mtx_bytes(k, f"stiffness of {model.name} with: " + "; ".join(lines))
    if any(key in changes for key in MASS_KEYS) or changed_deck:
        files["M.mtx"] = mtx_bytes(m, f"mass of {model.name} with: " + "; ".join(lines))
    if deck_text is not None:
        files["era_patch.bdf"] = deck_text.encode("latin-1")
    files["dofs.csv"] = ("node,direction\n" + "".join(f"{n},{d}\n" for n, d in model.dofs)).encode()
    note = [f"The matrices of {model.name} with the effects explain named put in, over the same DOFs in the same "
            "order (dofs.csv). Replace the model's own matrices by these to run it updated."]
    note += [f"- {x}" for x in lines] or ["- no effect was named: the nominal matrices stand"]
    note.append(f"Global stiffness factor fitted with them: {factor:.4f} "
                + ("(applied to K.mtx)." if stiffness_factor else "(not applied; the nuisance of every fit)."))
    if deck_text is not None:
        note.append("era_patch.bdf: the same effects as Nastran bulk data: INCLUDE it in the deck and comment out "
                    "the cards it lists as replaced (era.models.nastran.write_patched_deck writes such a copy).")
    files["README.txt"] = ("\n".join(note) + "\n").encode()
    return files


def _deck_parts(model: MatrixModel, params: dict, lines: list) -> tuple:
    """For a model read from a Nastran deck: (the model with a property factor put in by assembling the deck
    again, or ``model``; the bulk-data patch's text, or None when it cannot be written); ``lines`` gets the
    property's line. (model, None) for any other model."""
    deck = getattr(model, "deck", None)
    if deck is None:
        return model, None
    from .nastran.patch import deck_patch_for  # the bulk-data writer: loaded for a deck's model only
    from .nastran.reader import deck_model
    base = model
    factor = float(params.get("property_factor", 1.0))
    if params.get("property_at") is not None and factor != 1.0:
        key = str(params["property_at"]).removeprefix("property:")
        base = deck_model(deck, {key: factor}, units=model.units)
        lines.append(f"{key} × {factor:.6g} (the deck assembled again)")
    try:
        text = deck_patch_for(deck, params, title="; ".join(lines)).text
    except DataError:         # spread mass, or two changes of one card: the matrices still carry them
        text = None
    return base, text


def save_patch(model: MatrixModel, params, path, **kw) -> Path:
    """Write the patch of an updated model (:func:`patch_files`) into the zip ``path`` (or a folder).

    The patch is ``K.mtx`` and/or ``M.mtx`` (only the matrices the effects change) with the effects put in,
    ``dofs.csv`` (their rows), and ``README.txt`` saying what changed.

    Parameters
    ----------
    model : MatrixModel
        The nominal model the effects were fitted to.
    params : dict or object
        The explain parameters of the updated model ({keyword: value}, e.g. ``Explanation.updated_model.params``),
        or an object with ``.params`` or ``.updated_model``.
    path : str or os.PathLike
        A ``.zip`` file, or a folder when the name does not end in .zip (made if missing).
    **kw
        :func:`patch_files`' options: ``stiffness_factor`` (also scale K by the fitted global stiffness factor).

    Returns
    -------
    pathlib.Path
        ``path``.

    Examples
    --------
    The chain with a 0.5 kg mass added at node 4, written as the files to load instead of the nominal's:

    >>> import os, tempfile
    >>> k = 1e5 * (2 * np.eye(6) - np.eye(6, k=1) - np.eye(6, k=-1))  # six 1 kg masses on springs of 100 kN/m
    >>> k[-1, -1] = 1e5  # the top is free; below node 1 the chain is fixed to ground
    >>> dofs = [(str(i + 1), "z") for i in range(6)]
    >>> model = era.MatrixModel(k, np.eye(6), dofs, sensors=dofs)
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     _ = era.save_model(model, folder)
    ...     _ = era.save_patch(model, {"point_mass_at": "4", "point_mass": 0.5}, folder)
    ...     heavier = era.load_model(folder)
    >>> print(np.round(heavier.mass.diagonal(), 2))
    [1.  1.  1.  1.5 1.  1. ]
    """
    path = Path(path)
    files = patch_files(model, params, **kw)
    if path.suffix.lower() == ".zip":
        with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as zf:
            for name, data in files.items():
                zf.writestr(name, data)
        return path
    path.mkdir(parents=True, exist_ok=True)
    for name, data in files.items():
        (path / name).write_bytes(data)
    return path
