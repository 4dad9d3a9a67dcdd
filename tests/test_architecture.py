"""The house: no import cycle, no private name taken across modules, sizes kept.

The import graph is read from the source with :mod:`ast` (every import, also
those inside functions: a lazy import that dodges a cycle is still a cycle;
only ``if TYPE_CHECKING:`` blocks, which never run, are left out).
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1] / "src" / "ndlfd"
MAX_MODULE_LINES = 800
MAX_CLASS_LINES = 400


def _modules() -> dict[str, Path]:
    out = {}
    for path in sorted(ROOT.rglob("*.py")):
        parts = path.relative_to(ROOT.parent).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


MODULES = _modules()


def _is_package(name: str) -> bool:
    return MODULES[name].name == "__init__.py"


def _type_checking_only(tree: ast.AST) -> set[int]:
    """ids of import nodes inside ``if TYPE_CHECKING:`` blocks."""
    skip = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            for sub in node.body:
                skip.update(id(n) for n in ast.walk(sub))
    return skip


def _imports(name: str):
    """(target module, imported names or None, line) of every ndlfd import."""
    path = MODULES[name]
    tree = ast.parse(path.read_text(), str(path))
    skip = _type_checking_only(tree)
    package = name if _is_package(name) else name.rpartition(".")[0]
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name == "ndlfd" or a.name.startswith("ndlfd."):
                    yield a.name, None, node.lineno
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                target = ".".join([*base, *([node.module] if node.module else [])])
            else:
                target = node.module or ""
            if target == "ndlfd" or target.startswith("ndlfd."):
                yield target, [a.name for a in node.names], node.lineno


def _graph() -> dict[str, set[str]]:
    graph: dict[str, set[str]] = {m: set() for m in MODULES}
    for name in MODULES:
        for target, names, _ in _imports(name):
            # ``from pkg import sub`` needs the submodule only (a package's
            # __init__ always runs before its submodules); a name that is not a
            # module comes from ``pkg`` itself
            subs = [f"{target}.{n}" for n in names or ()]
            wanted = [t for t in subs if t in MODULES]
            if names is None or len(wanted) < len(subs):
                wanted.append(target)
            graph[name].update(t for t in wanted if t in MODULES and t != name)
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out = []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_the_cycle_finder_finds_a_cycle():
    g = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": set()}
    assert _cycles(g) == [["a", "b", "c"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_the_import_graph_has_no_cycle():
    assert _cycles(_graph()) == []


def test_the_graph_sees_lazy_imports():
    # ndlfd's top-level package imports the learner inside the package body;
    # any module importing something lazily still shows as an arrow
    graph = _graph()
    assert "ndlfd.demonstration" in graph["ndlfd"]
    assert len(MODULES) > 20


def _private_imports():
    for name in MODULES:
        own_package = name if _is_package(name) else name.rpartition(".")[0]
        for target, names, line in _imports(name):
            for n in names or ():
                if not n.startswith("_") or n.startswith("__"):
                    continue
                sub = f"{target}.{n}"
                # a private module of one's own package is the package's business
                if sub in MODULES and target == own_package:
                    continue
                yield f"{MODULES[name].relative_to(ROOT.parent)}:{line}: {target}.{n}"


def test_no_module_imports_another_modules_private_names():
    assert list(_private_imports()) == []


@pytest.mark.parametrize("name", sorted(MODULES))
def test_sizes(name):
    path = MODULES[name]
    text = path.read_text()
    n = text.count("\n")
    assert n <= MAX_MODULE_LINES, f"{path.name}: {n} lines"
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.ClassDef):
            length = node.end_lineno - node.lineno + 1
            assert length <= MAX_CLASS_LINES, f"class {node.name}: {length} lines"


def _private_defs(tree) -> set[str]:
    return {
        n.name
        for n in ast.walk(tree)
        if isinstance(n, (ast.FunctionDef, ast.ClassDef, ast.AsyncFunctionDef))
        and n.name.startswith("_")
        and not n.name.startswith("__")
    }


def _private_calls():
    """``obj._name`` where ``_name`` is a private function or method that another
    ndlfd module defines and this one does not (a worker calling an estimator's
    private method, say)."""
    trees = {m: ast.parse(p.read_text()) for m, p in MODULES.items()}
    defined = {m: _private_defs(t) for m, t in trees.items()}
    everywhere = set().union(*defined.values())
    for m, tree in trees.items():  # a module's own private attributes
        defined[m] |= {
            n.attr
            for n in ast.walk(tree)
            if isinstance(n, ast.Attribute) and isinstance(n.ctx, ast.Store)
        }
    for name, tree in trees.items():
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Attribute)
                and node.attr in everywhere
                and node.attr not in defined[name]
            ):
                path = MODULES[name].relative_to(ROOT.parent)
                yield f"{path}:{node.lineno}: {ast.unparse(node)}"


def test_no_module_calls_another_modules_private_functions():
    assert list(_private_calls()) == []


#: Stages of several modules kept in one package each (issue 41): the package,
#: and the prefixes of ground-floor modules that would put a piece of it
#: beside the package instead.
STAGE_PACKAGES = {
    "ndlfd.dp": ("_dp", "_simplify"),
    "ndlfd.plot": ("_plot", "_frame_plot", "_band"),
}


def _beside(package: str, modules) -> list[str]:
    """Ground-floor modules named like a piece of ``package``'s stage."""
    prefixes = STAGE_PACKAGES[package]
    return [
        m
        for m in modules
        if m.count(".") == 1
        and m != package
        and m.rpartition(".")[2].startswith(prefixes)
    ]


def _reexports_only(name: str) -> list[str]:
    """What a package's ``__init__`` does besides importing and ``__all__``."""
    tree = ast.parse(MODULES[name].read_text())
    extra = []
    for node in tree.body:
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            continue
        if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant):
            continue  # the docstring
        targets = getattr(node, "targets", None) or [getattr(node, "target", None)]
        if [ast.unparse(t) for t in targets if t is not None] == ["__all__"]:
            continue
        extra.append(f"{MODULES[name].relative_to(ROOT.parent)}:{node.lineno}")
    return extra


@pytest.mark.parametrize("package", sorted(STAGE_PACKAGES))
def test_a_stage_is_one_package(package):
    assert _is_package(package)
    assert _beside(package, MODULES) == []
    # the package's __init__ only re-exports what its private modules define
    assert _reexports_only(package) == []
    inside = [m for m in MODULES if m.startswith(package + ".")]
    assert inside and all(m.rpartition(".")[2].startswith("_") for m in inside)


def test_the_stage_check_sees_a_flat_module():
    flat = ["ndlfd._dp_kernels", "ndlfd._simplify", "ndlfd.dp", "ndlfd.dp._tree",
            "ndlfd.cli._simplify", "ndlfd.normalize"]  # fmt: skip
    assert _beside("ndlfd.dp", flat) == ["ndlfd._dp_kernels", "ndlfd._simplify"]
    flat = ["ndlfd.plot", "ndlfd._band", "ndlfd._frame_plot", "ndlfd.plot._band"]
    assert _beside("ndlfd.plot", flat) == ["ndlfd._band", "ndlfd._frame_plot"]
