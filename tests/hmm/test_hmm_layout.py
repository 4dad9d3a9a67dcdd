"""ndlfd.hmm: data flows one way (kernels <- decode <- model); its public names.

No private name crosses modules anywhere in ndlfd: tests/test_architecture.py.
"""

from __future__ import annotations

import ast
from pathlib import Path

import ndlfd.hmm

PACKAGE = Path(ndlfd.hmm.__file__).parent


def _imports() -> dict[str, list[tuple[str, list[str]]]]:
    """Per module of the package: (imported sibling module, names) anywhere in it."""
    out = {}
    for f in sorted(PACKAGE.glob("*.py")):
        found = []
        for node in ast.walk(ast.parse(f.read_text(), str(f))):  # also in functions
            if not (isinstance(node, ast.ImportFrom) and node.level == 1):
                continue
            if node.module:
                found.append((node.module, [a.name for a in node.names]))
            else:  # from . import _x: the sibling modules themselves
                found.extend((a.name, [a.name]) for a in node.names)
        out[f.stem] = found
    return out


def test_modules_import_downwards_only():
    # kernels <- decode <- model, counts <- format <- model; the package's
    # __init__ re-exports; nothing imports the model class but __init__
    order = ["_kernels", "_counts", "_decode", "_format", "_model", "__init__"]
    imports = _imports()
    assert sorted(imports) == sorted(order)
    for module, found in imports.items():
        for target, _ in found:
            assert order.index(target) < order.index(module), (module, target)


def test_public_names():
    assert ndlfd.hmm.__all__ == [
        "DENSE_LIMIT_BYTES",
        "FORMAT_KIND",
        "FORMAT_VERSION",
        "STARTS",
        "DiscreteHMM",
        "Posterior",
        "estimate",
        "merge",
        "posterior",
        "sample_paths",
        "viterbi",
    ]
    for name in ndlfd.hmm.__all__:
        assert getattr(ndlfd.hmm, name) is not None
