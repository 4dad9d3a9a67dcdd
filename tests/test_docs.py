"""The documentation site cannot rot (issue 41).

* every public name of the package and its public submodules has a reference
  page: an entry in one of docs/api_*.rst's autosummary tables, read here from
  the files, against each module's ``__all__``;
* every gallery example (examples/plot_*.py) runs as a script, without a
  warning (pytest's warnings are errors), and draws at least one figure;
* the site builds with Sphinx, warnings as errors, when Sphinx and its
  extensions are installed (the ``docs`` extra): a copy of docs/ and examples/
  in a temporary folder, so a stale generated page of an earlier build cannot
  pass or fail it; the examples are not run again there (``plot_gallery=0``).
"""

from __future__ import annotations

import importlib
import re
import runpy
import shutil
import subprocess
import sys
import types
from pathlib import Path

import pytest

import ndlfd

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
EXAMPLES = sorted((ROOT / "examples").glob("plot_*.py"))
MODULES = (
    "ndlfd",
    "ndlfd.hmm",
    "ndlfd.io",
    "ndlfd.learner",
    "ndlfd.limits",
    "ndlfd.metrics",
    "ndlfd.synth",
    "ndlfd.baselines",
    "ndlfd.orientation",
    "ndlfd.plot",
    "ndlfd.datasets",
    "ndlfd.evaluation",
)
#: The reST page of each module (ndlfd.evaluation is ndlfd.jobs.evaluation).
DIRECTIVE = re.compile(r"^\.\. (currentmodule|autosummary)::\s*(\S*)")


def _module(name):
    if name == "ndlfd.evaluation":  # an attribute of ndlfd, not an import path
        return ndlfd.evaluation
    return importlib.import_module(name)


def _entries(page: Path) -> set[str]:
    """Full names listed in a page's autosummary tables.

    An entry is relative to the page's ``currentmodule``; ``~`` only shortens
    what is shown.
    """
    current, names, inside = "", set(), False
    for line in page.read_text().splitlines():
        directive = DIRECTIVE.match(line)
        if directive:
            kind, arg = directive.groups()
            if kind == "currentmodule":
                current = arg
            inside = kind == "autosummary"
            continue
        if not inside:
            continue
        entry = line.strip()
        if not entry or entry.startswith(":"):
            continue
        if not line.startswith("   "):
            inside = False
            continue
        entry = entry.lstrip("~")
        names.add(entry)
        names.add(f"{current}.{entry}")
    return names


def _documented(obj, entries: set[str]) -> bool:
    """Whether ``obj`` is one of the objects the entries name."""
    for entry in entries:
        module, _, name = entry.rpartition(".")
        try:
            if getattr(_module(module), name) is obj:
                return True
        except (ImportError, AttributeError, ValueError):
            continue
    return False


def test_every_public_name_has_a_reference_page():
    entries = set().union(*(_entries(p) for p in DOCS.glob("api_*.rst")))
    missing = []
    for modname in MODULES:
        module = _module(modname)
        for name in module.__all__:
            obj = getattr(module, name)
            if isinstance(obj, types.ModuleType):
                continue  # a submodule: a page of its own, checked by name
            # constants compare by name (an int or a tuple is not unique)
            here = f"{module.__name__}.{name}" in entries or (
                f"{modname}.{name}" in entries
            )
            if not here and not (callable(obj) and _documented(obj, entries)):
                missing.append(f"{modname}.{name}")
    assert not missing, f"no reference page for: {missing}"


def test_the_entry_reader_finds_a_known_page():
    # the reader above against one table, written out by hand
    entries = _entries(DOCS / "api_limits.rst")
    expected = {"LimitError", "check_limits", "limited", "path_peaks", "time_scale"}
    assert {f"ndlfd.limits.{n}" for n in expected} <= entries
    assert "ndlfd.limits.KINDS" in entries


def test_the_gallery_has_the_journeys():
    names = {p.stem for p in EXAMPLES}
    assert {
        "plot_routes",
        "plot_task_frames",
        "plot_replanning",
        "plot_limits",
        "plot_lerobot_to_ros2",
        "plot_own_csv",
        "plot_paper_reproduction",
    } <= names


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.stem)
def test_example_runs_and_draws(script, monkeypatch):
    mpl = pytest.importorskip("matplotlib")
    mpl.use("Agg")
    import matplotlib.pyplot as plt

    for extra in re.findall(r"^import (pyarrow|toppra)", script.read_text(), re.M):
        pytest.importorskip(extra)
    plt.close("all")
    monkeypatch.chdir(script.parent)
    monkeypatch.setattr(sys, "argv", [str(script)])
    runpy.run_path(str(script), run_name="__main__")
    figures = [plt.figure(n) for n in plt.get_fignums()]
    try:
        assert figures, f"{script.name} draws no figure"
        # a figure with something on it: lines, patches or collections
        assert all(
            any(ax.lines or ax.collections or ax.patches for ax in fig.axes)
            for fig in figures
        )
    finally:
        plt.close("all")


def test_the_site_builds_without_a_warning(tmp_path):
    for module in ("sphinx", "numpydoc", "sphinx_gallery", "myst_parser"):
        pytest.importorskip(module)
    pytest.importorskip("pydata_sphinx_theme")
    skip = shutil.ignore_patterns("_build", "generated", "auto_examples")
    shutil.copytree(DOCS, tmp_path / "docs", ignore=skip)
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    out = tmp_path / "html"
    result = subprocess.run(
        [sys.executable, "-m", "sphinx", "-b", "html", "-W", "--keep-going", "-q",
         "-D", "plot_gallery=0", str(tmp_path / "docs"), str(out)],
        capture_output=True, text=True, timeout=600, cwd=tmp_path,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr[-5000:]
    assert (out / "index.html").is_file()
    # one page per public name: KeypointHMM's, with its methods
    page = out / "generated" / "ndlfd.learner.KeypointHMM.html"
    assert "generate" in page.read_text()
    assert (out / "auto_examples" / "plot_routes.html").is_file()
