"""Counts, lists and numbers in the words a person reads (era.words), and no sentence of era/, app/ or the page that
glues "(s)" to a word ("1 channel(s)", "Import 1 file(s)": a program's words, issue 28's screenshot review)."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import numpy as np

from era.words import counted, listed, sampling, significant

ROOT = Path(__file__).resolve().parents[2]
#: "channel(s)", "record(s)": a word with "(s)" glued on (not "time (s)", a unit, nor "Im(s)", a formula).
PLURAL_S = re.compile(r"[a-z]{3,}\(s\)")
#: Files another engineer is reworking today, with the sentence still to change.
REWORKED: dict = {}    # module: why it may still glue '(s)' for now (none left)
#: A JavaScript string literal ("...", '...' or `...`, one level of ${...} in a template).
JS_STRING = re.compile(r'"(?:[^"\\\n]|\\.)*"|\'(?:[^\'\\\n]|\\.)*\'|`(?:[^`\\]|\\.|\$\{[^}]*\})*`')


def test_counts_agree_with_their_nouns_and_lists_read_as_sentences():
    assert [counted(1, "channel"), counted(2, "channel"), counted(0, "record")] == ["1 channel", "2 channels",
                                                                                   "0 records"]
    assert counted(2, "axis", "axes") == "2 axes" and counted(np.int64(1), "node") == "1 node"
    assert [listed([1826]), listed([3, 4]), listed([10, 12, 14])] == ["1826", "3 and 4", "10, 12 and 14"]
    assert listed(["colour", "size"], quote=True) == "'colour' and 'size'" and listed([]) == ""


def test_steps_are_written_out_to_six_significant_digits_with_their_rate():
    assert significant(3.90625e-05) == "0.0000390625" and significant(0.00060546875000399) == "0.000605469"
    assert significant(25600.000000000004) == "25600" and significant(1.0) == "1"
    assert sampling(3.906250000000085e-05) == "Δt = 0.0000390625 s (25600 Hz)"  # was 3.90625e-05
    assert sampling(0.0006054687500039967, "from Delta_X") == "Δt = 0.000605469 s (1651.61 Hz, from Delta_X)"


def _python_strings(path: Path) -> list[tuple[int, str]]:
    """The string constants of a module that are not docstrings, with their line numbers."""
    tree = ast.parse(path.read_text())
    docs = {id(n.body[0].value) for n in ast.walk(tree)
            if isinstance(n, (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) and n.body
            and isinstance(n.body[0], ast.Expr) and isinstance(n.body[0].value, ast.Constant)}
    return [(n.lineno, n.value) for n in ast.walk(tree)
            if isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in docs]


def test_no_sentence_glues_an_s_in_brackets_to_a_word():
    found = []
    for path in sorted((ROOT / "era").rglob("*.py")) + sorted((ROOT / "app").rglob("*.py")):
        name = path.relative_to(ROOT).as_posix()
        found += [f"{name}:{line}: {text!r}" for line, text in _python_strings(path)
                  if PLURAL_S.search(text) and name not in REWORKED]
    for path in sorted((ROOT / "static" / "js").glob("*.js")):
        code = re.sub(r"^\s*/\*.*?\*/", "", path.read_text(), flags=re.M | re.S)  # comments
        code = re.sub(r"^\s*//.*$|\s// .*$", "", code, flags=re.M)
        found += [f"{path.relative_to(ROOT).as_posix()}: {m.group()[:80]}" for m in JS_STRING.finditer(code)
                  if PLURAL_S.search(m.group())]
    assert found == []
