"""Every public name of era documents each of its parameters (numpydoc) and shows a runnable example.

For each function and class in ``era.__all__`` (after python-control's ``control/tests/docstrings_test.py``):
every parameter of its signature has an entry in its ``Parameters`` section (a class may list its dataclass
fields under ``Attributes``), no entry names a parameter that does not exist, and its ``Examples`` section runs
as a doctest. The public methods users call document their parameters likewise. Parameters whose names start
with "_" (a dataclass's private fields) and ``*args``/``**kwargs`` need no entry (an entry for them is allowed).
The examples see ``np`` (numpy) and ``era`` already imported, as python-control's see ``ct``.
"""

from __future__ import annotations

import doctest
import inspect
import re

import numpy as np
import pytest

import era

PUBLIC = [name for name in era.__all__ if inspect.isfunction(getattr(era, name)) or inspect.isclass(getattr(era, name))]
# a numpydoc entry: "name : type" (or a bare name) at the section's indentation, one parameter per entry
ENTRY = re.compile(r"^(?P<names>\*{0,2}[A-Za-z_][\w]*)(?: : .*)?$")


def sections(doc: str) -> dict[str, list[str]]:
    """The numpydoc sections of a cleaned docstring: {heading: its lines}."""
    lines = doc.splitlines()
    found: dict[str, list[str]] = {}
    heading = None
    for i, line in enumerate(lines):
        underline = i + 1 < len(lines) and re.fullmatch(r"-{3,}", lines[i + 1].strip() or "x")
        if line.strip() and not line.startswith(" ") and underline:
            heading = line.strip()
            found[heading] = []
        elif heading is not None and not re.fullmatch(r"-{3,}", line.strip() or "x"):
            found[heading].append(line)
    return found


def documented(lines: list[str]) -> list[str]:
    """The parameter names a Parameters/Attributes section gives entries to (unindented lines)."""
    names = []
    for line in lines:
        if line.strip() and not line.startswith(" "):
            match = ENTRY.match(line.strip())
            assert match, f"not a numpydoc entry of one parameter ('name : type'): {line!r}"
            names.append(match.group("names").lstrip("*"))
    return names


def needed(obj) -> list[str]:
    """The parameters a docstring must document: the signature's, without self, private ones and */**."""
    params = inspect.signature(obj).parameters.values()
    return [p.name for p in params if p.name != "self" and not p.name.startswith("_")
            and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]


@pytest.mark.parametrize("name", PUBLIC)
def test_every_parameter_has_one_entry_and_no_entry_is_stale(name):
    obj = getattr(era, name)
    doc = inspect.getdoc(obj) or ""
    found = sections(doc)
    assert doc.splitlines() and doc.splitlines()[0].strip(), f"era.{name}: no one-line summary"
    assert "Examples" in found, f"era.{name}: no Examples section"
    entries = documented(found.get("Parameters", []))
    if inspect.isclass(obj):
        entries += documented(found.get("Attributes", []))
    params = needed(obj)
    missing = [p for p in params if p not in entries]
    signature = inspect.signature(obj).parameters
    stale = [e for e in entries if e not in signature and not (inspect.isclass(obj) and e in dir(obj))]
    assert not missing, f"era.{name}: parameters without an entry: {missing}"
    assert not stale, f"era.{name}: entries for parameters that do not exist: {stale}"
    assert len(entries) == len(set(entries)), f"era.{name}: a parameter documented twice"


#: Public methods that era's own modules call, not users: explain's model protocol (documented once, in
#: era.discrepancy.protocol.ExplainModel) and the helpers of the uncertainty, the FE solution and the effects.
INTERNAL_METHODS = {"ritz", "screening_ritz", "modal_rows", "member_energy_fractions", "member_shape_sensitivity",
                    "member_scale_sensitivity", "Identification.decomposed", "Identification.mode_std",
                    "Identification.pole_covariance", "Identification.records_used", "FrameModel.member_index",
                    "FrameModel.bending_rotations", "Frame.beam_ends", "Frame.solution", "Frame.ritz_modes",
                    "Frame.at_sensors"}


def public_methods() -> list[tuple[str, object]]:
    """("Class.method", function, parameters) of every public method and classmethod of the public classes
    that users call (not INTERNAL_METHODS) and that takes parameters."""
    found = []
    for name in PUBLIC:
        cls = getattr(era, name)
        if not inspect.isclass(cls):
            continue
        for attr, value in vars(cls).items():
            func = getattr(value, "__func__", value)
            if attr.startswith("_") or not inspect.isfunction(func) or attr in INTERNAL_METHODS \
                    or f"{name}.{attr}" in INTERNAL_METHODS:
                continue
            params = needed(func)[1:] if isinstance(value, classmethod) else needed(func)
            if params:
                found.append((f"{name}.{attr}", func, params))
    return found


@pytest.mark.parametrize("name, func, params", public_methods(), ids=[m[0] for m in public_methods()])
def test_every_public_method_documents_its_parameters(name, func, params):
    entries = documented(sections(inspect.getdoc(func) or "").get("Parameters", []))
    signature = inspect.signature(func).parameters
    missing = [p for p in params if p not in entries]
    stale = [e for e in entries if e not in signature]
    assert not missing, f"era.{name}: parameters without an entry: {missing}"
    assert not stale, f"era.{name}: entries for parameters that do not exist: {stale}"


def test_no_docstring_line_of_a_public_name_is_over_120_characters():
    long = [(name, line) for name in PUBLIC for line in (getattr(era, name).__doc__ or "").splitlines()
            if len(line) > 120]
    assert not long, long


@pytest.mark.parametrize("name", PUBLIC)
def test_examples_run(name):
    obj = getattr(era, name)
    finder = doctest.DocTestFinder(recurse=True, exclude_empty=True)
    tests = [t for t in finder.find(obj, f"era.{name}", globs={"np": np, "era": era}) if t.examples]
    assert tests, f"era.{name}: no doctest found"
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    with np.printoptions(precision=4, suppress=True, legacy=False):
        for test in tests:
            report = []
            runner = doctest.DocTestRunner(optionflags=flags)
            result = runner.run(test, out=report.append, clear_globs=True)
            assert result.failed == 0, "".join(report)
