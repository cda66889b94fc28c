"""The house rules of the code, read from the source with ast (nothing is imported):

- no import circle among era/ and app/ modules, lazy imports inside functions included (``if TYPE_CHECKING:``
  blocks, which never run, left out); importing ``a.b.c`` counts as importing the packages ``a.b`` and ``a`` too;
- no import running back up into a circle: a module that takes names from its own package's ``__init__``
  (``from . import name``) is not imported by that ``__init__``, directly or not;
- era/ imports nothing from app/ or a web package (the numerics run without a server);
- no class name defined twice in era/ and app/ (app/schemas/ mirrors era's names on purpose);
- no module over 450 lines;
- private names stay in their module: none is imported (``from .x import _y``) or read off a module
  (``x._y``) by another module of era/ or app/;
- app/ takes era's public names only: from ``era`` itself or a room's face (``era.core``, ``era.choice``,
  ``era.setups``, ``era.io``, ...: the names in that package's ``__all__``), never from a module inside a room;
- one word per concept: no public function name is defined in two modules for two different things.
"""

from __future__ import annotations

import ast
from functools import cache
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("era", "app")
WEB = {"app", "fastapi", "starlette", "uvicorn", "viser", "plotly", "pydantic", "websockets", "jinja2"}
MAX_LINES = 450
#: Modules allowed over MAX_LINES, each with its reason. Keep it empty when possible.
LONG_MODULES: dict[str, str] = {}

#: Private names still read across modules, {(module, name): reason}. Keep it empty.
PRIVATE_CROSSINGS: dict[tuple[str, str], str] = {}

#: era modules app/ may import from although they are not a room's face, {module: reason}.
PUBLIC_MODULES = {
    "era.errors": "the exceptions every room raises",
    "era.words": "plural and list wording shared by every message",
    "era.io.preview": "the import preview; it reads with era.io's own reader, so the face cannot hold it",
}
#: Rooms whose modules app/ may take anything from: built-in examples and demo data, not the method.
EXAMPLE_ROOMS = ("era.examples",)

#: Public function names defined in more than one module, {name: why it is one concept}. Route handlers
#: (app/routes/: named after the HTTP operation, as FastAPI does) and migrations (alembic's upgrade/downgrade) are
#: left out. Keep it short: a name used for two different things is renamed instead.
SAME_CONCEPT = {
    "compare": "a structure model's modes against the test's: for frames (app.modeling) and FE models (app.femodel)",
    "describe": "what an effect or a model holds, in words, for the page",
    "summary": "a stored model's summary for the page: frames and FE models",
    "load": "read the stored thing of the room (a test file, a setups test, an FE model)",
    "unmatched": "the test's points with no partner: in a setups test and in an FE model",
    "even_step": "the sampling step of a clock; era.io.arrays's refuses a jittered clock where arrays take no option",
    "free_decays": "the free decays of an example's simulated test",
    "install": "install the app's handlers on the FastAPI app (errors, middleware)",
    "main": "a package's command line (python3 -m era / -m app)",
    "modes_csv": "chosen modes as CSV: of an analysis report and of a setups merge",
    "modes_uff": "chosen modes as UFF 55: of an analysis report and of a setups merge",
    "self_weight": "the static solve under the structure's own weight: plane and space frames",
    "standalone_html": "a page that works offline: report, campaign, viewer recording",
}


def _modules() -> dict[str, tuple[Path, bool]]:
    """{dotted name: (path, is a package's __init__)} of every module of era/ and app/."""
    out = {}
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            parts = list(path.relative_to(ROOT).with_suffix("").parts)
            is_package = parts[-1] == "__init__"
            out[".".join(parts[:-1] if is_package else parts)] = (path, is_package)
    return out


MODULES = _modules()


def _type_checking_lines(tree: ast.Module) -> set[int]:
    """Line numbers inside ``if TYPE_CHECKING:`` blocks."""
    lines = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for inner in node.body:
                lines.update(range(inner.lineno, (inner.end_lineno or inner.lineno) + 1))
    return lines


def _source(name: str, is_package: bool, node: ast.ImportFrom) -> str:
    """The dotted module a ``from ... import`` in module ``name`` reads from."""
    if not node.level:
        return node.module or ""
    base = name.split(".") if is_package else name.split(".")[:-1]
    base = base[:len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


@cache
def _imports(name: str) -> list[tuple[str, str | None, int]]:
    """(module imported, name taken from that module or None for the module itself, line) of every import in
    module ``name`` that runs (function bodies included); only modules of era/ and app/ and third-party roots."""
    path, is_package = MODULES[name]
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skip = _type_checking_lines(tree)
    out = []
    for node in ast.walk(tree):
        if getattr(node, "lineno", None) in skip:
            continue
        if isinstance(node, ast.Import):
            out += [(a.name, None, node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            target = _source(name, is_package, node)
            for a in node.names:
                sub = f"{target}.{a.name}"
                out.append((sub, None, node.lineno) if sub in MODULES else (target, a.name, node.lineno))
    return out


@cache
def _graph() -> dict[str, set[str]]:
    """{module: modules its imports run}: the module imported and every package above it, except the importing
    module's own packages (already running when it runs)."""
    graph = {}
    for name in MODULES:
        edges = set()
        for target, _, _ in _imports(name):
            parts = target.split(".")
            for k in range(1, len(parts) + 1):
                prefix = ".".join(parts[:k])
                own = name == prefix or name.startswith(prefix + ".")
                if prefix in MODULES and (prefix == target or not own):
                    edges.add(prefix)
        graph[name] = edges - {name}
    return graph


def _circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan, iterative)."""
    index, low, on_stack, stack, found = {}, {}, set(), [], []
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            v, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[v] = min(low[v], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                component = []
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    component.append(w)
                    if w == v:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def _reachable(graph: dict[str, set[str]], start: str) -> set[str]:
    """Every module that importing ``start`` runs."""
    seen, todo = set(), [start]
    while todo:
        for nxt in graph[todo.pop()] - seen:
            seen.add(nxt)
            todo.append(nxt)
    return seen


def test_the_walk_sees_the_code():
    graph = _graph()
    assert len(MODULES) > 100 and "era.structure.frame" in graph["era.structure"]
    assert "era.fem" in graph["era.structure.frame"]  # importing era.fem.solution runs era/fem/__init__ too
    assert _circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_no_import_circles_in_era_and_app():
    assert _circles(_graph()) == []


def test_no_import_runs_back_up_into_a_circle():
    graph = _graph()
    wrong = []
    for name in MODULES:
        for target, taken, line in _imports(name):
            if taken is not None and name.startswith(target + ".") and name in _reachable(graph, target):
                wrong.append(f"{name}:{line} takes {taken} from {target}, whose __init__ imports {name}")
    assert wrong == []


def test_era_imports_nothing_from_the_app_or_the_web():
    wrong = [f"{name}:{line} imports {target}" for name in MODULES if name.split(".")[0] == "era"
             for target, _, line in _imports(name) if target.split(".")[0] in WEB]
    assert wrong == []


def test_no_class_name_is_defined_twice_outside_the_schemas():
    where: dict[str, list[str]] = {}
    for name, (path, _) in MODULES.items():
        if name == "app.schemas" or name.startswith("app.schemas."):
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ClassDef):
                where.setdefault(node.name, []).append(name)
    assert {k: v for k, v in where.items() if len(v) > 1} == {}


def test_no_module_is_over_450_lines():
    long = {}
    for path, _ in MODULES.values():
        rel = path.relative_to(ROOT).as_posix()
        n = len(path.read_text(encoding="utf-8").splitlines())
        if n > MAX_LINES and rel not in LONG_MODULES:
            long[rel] = n
    assert long == {}


def test_private_names_stay_in_their_module():
    wrong = []
    for name, (path, _) in MODULES.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        imported = {}   # local name -> the module of era/ or app/ it is
        for target, taken, line in _imports(name):
            if target.split(".")[0] not in PACKAGES:
                continue
            private = taken if taken is not None else target.rsplit(".", 1)[-1]
            if private.startswith("_") and not private.startswith("__") and (name, private) not in PRIVATE_CROSSINGS:
                wrong.append(f"{name}:{line} imports {private} from {target}")
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                imported.update({a.asname or a.name.split(".")[0]: a.name for a in node.names
                                 if a.name.split(".")[0] in PACKAGES})
            elif isinstance(node, ast.ImportFrom):
                source = _source(name, MODULES[name][1], node)
                imported.update({a.asname or a.name: f"{source}.{a.name}" for a in node.names
                                 if f"{source}.{a.name}" in MODULES})
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in imported:
                attr = node.attr
                if attr.startswith("_") and not attr.startswith("__") and (name, attr) not in PRIVATE_CROSSINGS:
                    wrong.append(f"{name}:{node.lineno} reads {node.value.id}.{attr}")
    assert wrong == []


def _face(package: str) -> set[str]:
    """The names in a package's ``__all__`` (read from its ``__init__`` with ast), or empty."""
    path, is_package = MODULES[package]
    if not is_package:
        return set()
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "__all__" for t in node.targets):
            return set(ast.literal_eval(node.value))
    return set()


def test_app_takes_era_public_names_only():
    wrong = []
    for name in MODULES:
        if not name.startswith("app"):
            continue
        for target, taken, line in _imports(name):
            if not (target == "era" or target.startswith("era.")):
                continue
            if target in PUBLIC_MODULES or target.startswith(EXAMPLE_ROOMS) or target == "era" and taken is None:
                continue
            package = target if taken is not None else target.rsplit(".", 1)[0]
            what = taken if taken is not None else target.rsplit(".", 1)[1]
            if MODULES.get(package, (None, False))[1] and what in _face(package):
                continue
            wrong.append(f"{name}:{line} takes {what} from {package}")
    assert wrong == []


def test_one_public_function_name_per_concept():
    where: dict[str, list[str]] = {}
    for name, (path, _) in MODULES.items():
        if name.startswith(("app.routes", "app.store.migrations")):
            continue
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and not node.name.startswith("_"):
                where.setdefault(node.name, []).append(name)
    twice = {k: v for k, v in where.items() if len(v) > 1 and k not in SAME_CONCEPT}
    assert twice == {}, "a function name defined for two things: rename one, or say in SAME_CONCEPT why it is one"
