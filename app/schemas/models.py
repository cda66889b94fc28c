"""The structure model of a dataset (simulation vs test on the engineer's own structure)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, Field

from .common import Floats, Matrix, Schema

class ModelDraft(Schema):
    """GET /api/datasets/{id}/model/draft: what the model step starts from, read from the dataset's geometry."""

    nodes: dict[str, list[float]] = Field(description="{node id: [x, y, z]} in m (the geometry's labels)")
    members: list[list[str]] = Field(description="[node i, node j, group] per trace line segment; the group is "
                                                 "the trace line's name, or for an unnamed one its direction: "
                                                 "vertical, along x, along y, inclined")
    sensors: list[list[Any]] = Field(description="[node, direction] per output, in the outputs' order")
    outputs: list[str] = Field(description="(p,) output labels")
    units: str = Field(description="always m")
    groups: list[str] = Field(description="the groups the members fall into")
    materials: list[str] = Field(description="materials the section helpers know")
    shapes: list[str] = Field(description="section shapes: rectangle, tube, square_tube, circle")


class PointMatch(Schema):
    """One output of the test matched to a DOF of an FE model."""

    output: str = Field(description="the output's label")
    point: str | None = Field(description="the test point it measures (node and signed direction), or null")
    node: str | None = Field(description="the model node matched, or null")
    direction: str | None = Field(description="x, y, z, rx, ry or rz, with a sign when the channel reads -axis")
    matched: bool = Field(description="whether the output is matched to a free DOF of the model")


class StructureModel(Schema):
    """A dataset's stored structure model (GET/PUT /api/datasets/{id}/model, POST .../model/file)."""

    model: dict[str, Any] = Field(description="the model in era.Frame's file format (SI units), as described; for "
                                              "an FE model {fe: the file's description, mapping}")
    source: Literal["geometry", "file", "fe"] = Field(description="built from the geometry in the panel, an "
                                                                  "uploaded era.Frame file, or an uploaded FE model "
                                                                  "(a Nastran deck or a .zip of matrices)")
    name: str | None = Field(description="the uploaded file's name, or null")
    saved: float | None = Field(description="when it was saved, Unix s")
    fingerprint: str = Field(description="a hash of the model as described: an explanation made with another "
                                         "fingerprint is stale")
    n_nodes: int
    n_members: int
    n_sensors: int
    total_mass_kg: float = Field(description="members plus lumped masses, kg; an FE model: the mass moving with a "
                                             "rigid translation, in kg when its mass unit is known (mass_unit), "
                                             "else total_mass as it is (kg only if the model is in SI units)")
    total_mass: float | None = Field(None, description="the same mass in the model's own mass unit (mass_unit)")
    mass_unit: str | None = Field(None, description="the model's mass unit (kg, t, lbf·s²/in, kip·s²/in, slug) "
                                                    "when known: an era.Frame's kg, a zip's units.txt, a deck's "
                                                    "PARAM WTMASS of 1/g; null when the file does not say")
    mass_unit_note: str | None = Field(None, description="how the mass unit is known, or that it is not, in one "
                                                         "sentence")
    frequency_hz: Floats = Field(description="the model's lowest frequencies, Hz")
    text: str = Field(description="the model in one line")
    mapping: list[PointMatch] | None = Field(None, description="an FE model: each output's test point and the "
                                                               "model node and direction it is matched to")
    unmatched: str | None = Field(None, description="an FE model: the outputs that match no model DOF, in one "
                                                    "sentence; null when every one does")
    notes: list[str] | None = Field(None, description="an FE model: how the file was read (a deck's cards not "
                                                      "modelled, by name and count)")
    n_dofs: int | None = Field(None, description="an FE model: its free DOFs")


class ModelViewLink(Schema):
    """POST /api/datasets/{id}/model/viewer: the model being described, in the 3-D viewer, its nodes clickable."""

    key: str = Field(description="the view's key (random)")
    url: str = Field(description="the viewer page for an <iframe>")
    picks_url: str = Field(description="GET ?after=n: the nodes clicked there since pick n")
    look_url: str = Field(description="POST {node}: turn the view to a node")
    marks_url: str = Field(description="POST {marks: {node: fixed | pinned | springs | mass}}: the nodes' colours")


class BestPartner(Schema):
    model_mode: int = Field(description="index of the model mode with the largest MAC, from 0")
    mac: float | None = Field(description="that MAC, fraction")
    frequency_error_pct: float | None = Field(description="(model − test)/test, %")


class ModelComparison(Schema):
    """GET /api/analyses/{id}/model/mac: the dataset's model beside the test's modes, at the sensors."""

    test_hz: Floats = Field(description="(k,) the test modes compared, Hz")
    model_hz: Floats = Field(description="(n,) the model's lowest modes, Hz")
    mac: Matrix = Field(description="(k, n) MAC of each test mode with each model mode")
    best: list[BestPartner | None] = Field(description="(k,) each test mode's model partner (frequency and MAC "
                                                      "together, as explain pairs them), null when none fits")


# ---- requests -----------------------------------------------------------------------------------------------
class ModelRequest(BaseModel):
    model: dict = Field(description="the model in era.Frame's file format (SI units): nodes, members, sections "
                                    "(constants, or shape + sizes in m + material), supports, masses, sensors "
                                    "(one per output, in order), gravity")
    source: Literal["geometry", "file"] = Field("geometry", description="built in the panel, or from a file")
    name: str | None = Field(None, max_length=200, description="the model file's name")


class MappingRequest(BaseModel):
    sensors: list[list[str] | None] = Field(description="one [node, direction] per output, in the outputs' order "
                                                        "(direction x..rz, '-z' for a channel reading -z), or null "
                                                        "for an output the model does not see", max_length=100000)


class ModelView(BaseModel):
    nodes: dict[str, list[float]] = Field(description="{node id: [x, y, z]} in m, as described so far")
    members: list[list[str]] = Field(default_factory=list, description="[node i, node j] per member")
    marks: dict[str, str] = Field(default_factory=dict, description="{node id: fixed | pinned | springs | mass} "
                                                                    "(the node's colour)")
