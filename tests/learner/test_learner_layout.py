"""The learner package: no import cycle, no private import, small modules."""

import ast
import importlib
import inspect
import pkgutil

import ndlfd.learner

#: Allowed until ndlfd.hmm exports STARTS (the hmm package's own change).
_TEMPORARY = {("ndlfd.learner._decoding", "ndlfd._hmm_model", "_STARTS")}


def _modules():
    for info in pkgutil.iter_modules(ndlfd.learner.__path__):
        yield importlib.import_module(f"ndlfd.learner.{info.name}")
    yield ndlfd.learner


def _imports(mod):
    """(module imported, names) of every import of ``mod``, lazy ones too."""
    pkg = mod.__name__ if mod.__name__ == "ndlfd.learner" else mod.__package__
    for node in ast.walk(ast.parse(inspect.getsource(mod))):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = pkg.split(".")
                base = ".".join(parts[: len(parts) - node.level + 1] + [base]).strip(
                    "."
                )
            yield base, [a.name for a in node.names]
        elif isinstance(node, ast.Import):
            for a in node.names:
                yield a.name, []


def test_no_import_cycle_inside_the_learner():
    mods = {m.__name__: m for m in _modules()}
    graph = {
        name: {b for b, _ in _imports(m) if b in mods and b != name}
        for name, m in mods.items()
    }
    graph["ndlfd.learner"] = set()  # the package re-exports; nothing imports it
    done, path = set(), []

    def visit(n):
        assert n not in path, " -> ".join([*path, n])
        if n in done:
            return
        path.append(n)
        for m in sorted(graph[n]):
            visit(m)
        path.pop()
        done.add(n)

    for n in sorted(graph):
        visit(n)


def test_no_private_name_is_imported_from_another_module():
    for mod in _modules():
        for base, names in _imports(mod):
            for name in names:
                if (
                    name.startswith("_")
                    and (mod.__name__, base, name) not in _TEMPORARY
                ):
                    raise AssertionError(f"{mod.__name__} imports {name} from {base}")


def test_no_module_over_800_lines_and_no_class_over_about_400():
    for mod in _modules():
        src = inspect.getsource(mod)
        assert src.count("\n") <= 800, mod.__name__
        for node in ast.walk(ast.parse(src)):
            if isinstance(node, ast.ClassDef):
                n = node.end_lineno - node.lineno + 1
                assert n <= 470, f"{mod.__name__}.{node.name}: {n} lines"


def test_the_package_exports_the_contract():
    for name in ("KeypointHMM", "AUTO_GROUPS", "DEFAULT_LEVELS", "NORMALIZATIONS",
                 "DECODERS", "GENERATIONS", "STARTS", "FitStats", "minimum_jerk",
                 "pin_offset"):  # fmt: skip
        assert name in ndlfd.learner.__all__
        assert getattr(ndlfd.learner, name) is not None
