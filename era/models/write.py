"""A MatrixModel written as the files era.load_model reads (a folder or a .zip): K.mtx, M.mtx (Matrix Market,
symmetric coordinate form, 17 significant digits so the numbers come back exactly), dofs.csv, coordinates.csv,
parts/<name>.mtx, part_masses/<name>.mtx and units.txt."""

from __future__ import annotations

import io
import zipfile
from pathlib import Path

import scipy.io
import scipy.sparse

from .matrix import UNIT_SYSTEMS, MatrixModel


def mtx_bytes(matrix, comment: str = "") -> bytes:
    """A symmetric matrix (n, n) as Matrix Market text (coordinate, real, symmetric: one triangle stored)."""
    out = io.BytesIO()
    scipy.io.mmwrite(out, scipy.sparse.coo_matrix(matrix), comment=comment, field="real", precision=17,
                     symmetry="symmetric")
    return out.getvalue()


def model_files(model: MatrixModel) -> dict[str, bytes]:
    """{file name: content} of ``model`` in the layout load_model reads."""
    files = {"K.mtx": mtx_bytes(model.stiffness, f"stiffness of {model.name}"),
             "M.mtx": mtx_bytes(model.mass, f"mass of {model.name}"),
             "dofs.csv": ("node,direction\n" + "".join(f"{n},{d}\n" for n, d in model.dofs)).encode()}
    if model.coordinates is not None:
        files["coordinates.csv"] = ("node,x,y,z\n" + "".join(
            f"{n},{x!r},{y!r},{z!r}\n" for n, (x, y, z) in model.coordinates.items())).encode()
    for name, p in model.parts.items():
        files[f"parts/{name}.mtx"] = mtx_bytes(p, f"stiffness of part {name}")
    for name, p in model.part_masses.items():
        files[f"part_masses/{name}.mtx"] = mtx_bytes(p, f"mass of part {name}")
    preset = next((k for k, v in UNIT_SYSTEMS.items() if v == model.units), None)
    if preset is not None:
        files["units.txt"] = f"{preset}\n".encode()
    return files


def save_model(model: MatrixModel, path) -> Path:
    """Write ``model`` as Matrix Market files: a .zip when the name ends so, else a folder (made if missing).

    :func:`era.load_model` reads it back.

    Parameters
    ----------
    model : MatrixModel
        The model to write (``K.mtx``, ``M.mtx``, ``dofs.csv`` and its coordinates, parts and units).
    path : str or os.PathLike
        A ``.zip`` file or a folder.

    Returns
    -------
    pathlib.Path
        ``path``.

    Examples
    --------
    >>> import os, tempfile
    >>> k = 1e5 * (2 * np.eye(6) - np.eye(6, k=1) - np.eye(6, k=-1))  # six 1 kg masses on springs of 100 kN/m
    >>> k[-1, -1] = 1e5  # the top is free; below node 1 the chain is fixed to ground
    >>> dofs = [(str(i + 1), "z") for i in range(6)]
    >>> model = era.MatrixModel(k, np.eye(6), dofs, sensors=dofs)
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     written = era.save_model(model, os.path.join(folder, "chain.zip"))
    ...     again = era.load_model(written)
    >>> written.name, again.n_dofs, again.dofs[0]
    ('chain.zip', 6, ('1', 'z'))
    """
    path = Path(path)
    files = model_files(model)
    if path.suffix.lower() == ".zip":
        with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as zf:
            for name, data in files.items():
                zf.writestr(name, data)
        return path
    for name, data in files.items():
        target = path / name
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(data)
    return path
