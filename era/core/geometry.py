"""Test geometry: nodes, trace lines, and where each output channel measures."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import DataError


@dataclass(frozen=True, eq=False)
class Geometry:
    """Nodes, trace lines and sensor placement of a test article.

    Attributes
    ----------
    node_ids : int ndarray, shape (n_nodes,)
        Node labels as in the source file (unique).
    coordinates : float ndarray, shape (n_nodes, 3)
        x, y, z of each node in ``units``.
    edges : int ndarray, shape (n_edges, 2)
        Trace lines as pairs of row indices into ``node_ids`` (not labels).
    channel_nodes : int ndarray, shape (p,)
        Row index into ``node_ids`` of the node each output channel measures, -1 when unknown.
    channel_directions : float ndarray, shape (p, 3)
        Unit vector of the measured direction of each output channel (global axes), zeros when unknown.
    units : str
        Length unit of the coordinates (e.g. "m", "ft").
    edge_lines : int ndarray, shape (n_edges,)
        Row index into ``line_ids``/``line_names`` of the trace line each edge was drawn in, -1 when unknown
        (default: all unknown).
    line_ids : int ndarray, shape (n_lines,)
        The trace lines' numbers as in the source file (UFF 82 trace line number).
    line_names : tuple of str, (n_lines,)
        The trace lines' descriptions as in the source file (e.g. "Stator"); "" when the file gives none.

    Raises
    ------
    era.DataError
        When the arrays do not fit together (coordinates not (n_nodes, 3), repeated node ids, an edge or a
        channel naming a node that does not exist, channel counts that differ).

    Examples
    --------
    Two accelerometers on the ends of a 1 m bar, both measuring along z:

    >>> geometry = era.Geometry(node_ids=[1, 2], coordinates=[[0, 0, 0], [1, 0, 0]], edges=[[0, 1]],
    ...                         channel_nodes=[0, 1], channel_directions=[[0, 0, 1], [0, 0, 1]])
    >>> geometry.n_nodes, geometry.edges.tolist(), geometry.units
    (2, [[0, 1]], 'm')
    >>> geometry.displaced(np.array([0.5, 1.0]), scale=0.1)[:, 2]
    array([0.05, 0.1 ])
    """

    node_ids: np.ndarray
    coordinates: np.ndarray
    edges: np.ndarray
    channel_nodes: np.ndarray
    channel_directions: np.ndarray
    units: str = "m"
    edge_lines: np.ndarray | None = None
    line_ids: np.ndarray = ()
    line_names: tuple = ()

    def __post_init__(self):
        ids = np.asarray(self.node_ids, dtype=int).reshape(-1)
        xyz = np.asarray(self.coordinates, dtype=float)
        if xyz.shape != (ids.size, 3):
            raise DataError(f"Geometry: coordinates have shape {xyz.shape}, expected ({ids.size}, 3) for {ids.size} nodes.")
        if not np.isfinite(xyz).all():
            raise DataError("Geometry: node coordinates contain NaN or infinite values.")
        if np.unique(ids).size != ids.size:
            raise DataError("Geometry: node ids are not unique.")
        edges = np.asarray(self.edges, dtype=int).reshape(-1, 2)
        if edges.size and (edges.min() < 0 or edges.max() >= ids.size):
            raise DataError("Geometry: a trace line refers to a node that does not exist.")
        nodes = np.asarray(self.channel_nodes, dtype=int).reshape(-1)
        if nodes.size and (nodes.min() < -1 or nodes.max() >= ids.size):
            raise DataError("Geometry: a channel refers to a node that does not exist.")
        dirs = np.asarray(self.channel_directions, dtype=float).reshape(-1, 3)
        if dirs.shape[0] != nodes.size:
            raise DataError(f"Geometry: {nodes.size} channel nodes but {dirs.shape[0]} channel directions.")
        line_ids = np.asarray(self.line_ids, dtype=int).reshape(-1)
        names = tuple(str(n) for n in np.asarray(self.line_names, dtype=str).reshape(-1))
        if len(names) != line_ids.size:
            raise DataError(f"Geometry: {line_ids.size} trace line ids but {len(names)} trace line names.")
        lines = np.full(len(edges), -1) if self.edge_lines is None else \
            np.asarray(self.edge_lines, dtype=int).reshape(-1)
        if lines.size != len(edges):
            raise DataError(f"Geometry: {len(edges)} trace line segments but {lines.size} trace line indices.")
        if lines.size and (lines.min() < -1 or lines.max() >= line_ids.size):
            raise DataError("Geometry: a trace line segment refers to a trace line that does not exist.")
        object.__setattr__(self, "line_names", names)
        for name, value in (("node_ids", ids), ("coordinates", xyz), ("edges", edges),
                            ("channel_nodes", nodes), ("channel_directions", dirs), ("edge_lines", lines),
                            ("line_ids", line_ids)):
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    @property
    def n_nodes(self) -> int:
        return self.node_ids.size

    def edge_names(self) -> list[str]:
        """(n_edges,) the name of the trace line each edge was drawn in; "" when unnamed or unknown. Placeholder
        descriptions (pyuff's "NONE") count as unnamed."""
        names = [n.strip() for n in self.line_names]
        names = ["" if n.upper() == "NONE" else n for n in names]
        return [names[k] if k >= 0 else "" for k in self.edge_lines]

    def displaced(self, shape: np.ndarray, scale: float = 1.0) -> np.ndarray:
        """Node coordinates displaced by a real sensor shape (p,) along each channel's direction: (n_nodes, 3).

        Only nodes with a sensor move; several channels on one node add up (e.g. x, y, z sensors).

        Parameters
        ----------
        shape : ndarray, shape (p,)
            A real sensor shape, one value per output channel (in ``units`` after ``scale``).
        scale : float, optional
            Factor on the shape (default 1).
        """
        shape = np.asarray(shape, dtype=float).reshape(-1)
        if shape.size != self.channel_nodes.size:
            raise DataError(f"Geometry: a shape of {shape.size} values for {self.channel_nodes.size} channels.")
        out = self.coordinates.copy()
        known = self.channel_nodes >= 0
        np.add.at(out, self.channel_nodes[known], scale * shape[known, None] * self.channel_directions[known])
        return out
