"""Sphinx configuration of ndlfd's documentation site.

Built offline by ``make docs`` (``sphinx-build -W --keep-going``): numpydoc
renders the docstrings, autosummary writes one page per public name
(``docs/generated/``), sphinx-gallery runs ``examples/plot_*.py`` and keeps
their figures (``docs/auto_examples/``), myst-parser reads the Markdown notes
already in ``docs/``. No extension reaches the network: intersphinx is not
loaded, the theme ships its assets.
"""

import inspect
import os
import re
import sys
import warnings
from pathlib import Path

from sphinx.errors import PycodeError
from sphinx.pycode import ModuleAnalyzer

import ndlfd
from ndlfd._registry import Registry

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

# The gallery draws with matplotlib without a display.
os.environ.setdefault("MPLBACKEND", "agg")

project = "ndlfd"
author = "ndlfd developers"
copyright = "ndlfd developers"
version = release = ndlfd.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "myst_parser",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
templates_path = ["_templates"]
exclude_patterns = [
    "_build",
    "Thumbs.db",
    ".DS_Store",
    # sphinx-gallery's own by-products, not pages
    "auto_examples/*.ipynb",
    "auto_examples/*.py",
    "auto_examples/*.zip",
    "auto_examples/*.md5",
    "auto_examples/*.codeobj.json",
    "auto_examples/*.json",
]

# -- API reference -----------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": True, "inherited-members": False}
autodoc_typehints = "none"  # numpydoc's Parameters say the types and shapes
autodoc_member_order = "groupwise"
add_module_names = False

numpydoc_show_class_members = True
numpydoc_show_inherited_class_members = False
numpydoc_class_members_toctree = False
numpydoc_attributes_as_param_list = True
numpydoc_xref_param_type = False
# every documented object has a docstring (numpydoc GL08)
numpydoc_validation_checks = {"GL08"}

# -- Gallery -----------------------------------------------------------------
sphinx_gallery_conf = {
    "examples_dirs": str(ROOT / "examples"),
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "ignore_pattern": r"__init__\.py|/_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "doc_module": ("ndlfd",),
    "backreferences_dir": "generated/backreferences",
    "reference_url": {"ndlfd": None},
    "within_subsection_order": "FileNameSortKey",
    "matplotlib_animations": False,
    "plot_gallery": "True",
    "abort_on_example_error": True,
    "only_warn_on_example_error": False,
    "show_memory": False,
    "show_signature": False,
}

# -- Markdown ----------------------------------------------------------------
myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 3

# The Markdown notes in docs/ are written for reading on the repository's web
# view; a few of their links point where the site has no page. Each known one is
# mended here at read time (the file itself is left alone; once it is fixed the
# replacement no longer matches and does nothing).
MARKDOWN_MENDS = {
    # a copy of evaluation/summary.md's text, its figure path relative to there
    "evaluation": [
        ("](boxplot_dtw.png)", "](evaluation/boxplot_dtw.png)"),
        # a folder and a file outside docs/: named, not linked
        ("[evaluation/shapes/](evaluation/shapes/)", "`docs/evaluation/shapes/`"),
        (
            "[benchmarks/RESULTS.md](../benchmarks/RESULTS.md)",
            "`benchmarks/RESULTS.md`",
        ),
    ],
}
# evaluation/summary.md is written by `ndlfd evaluate`: a title, then a level-3
# heading per table. MyST warns of the skipped level in such Markdown only.
suppress_warnings = ["myst.header"]

# -- HTML --------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"ndlfd {release}"
html_static_path = []
html_show_sourcelink = False
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
}

SHAPE = re.compile(r"shape \(([^)]*)\)")


def _mend_markdown(app, docname, source):
    """Apply :data:`MARKDOWN_MENDS` to one Markdown note as Sphinx reads it."""
    for old, new in MARKDOWN_MENDS.get(docname, ()):
        source[0] = source[0].replace(old, new)


def _escape_shapes(app, what, name, obj, options, lines):
    """Keep ``shape (n_features_in_,)`` from reading as a reST link target.

    The docstrings name shapes by fitted attributes (``n_features_in_``); a
    trailing underscore is reST's reference syntax, so it is escaped inside the
    parentheses of ``shape (...)`` only.
    """

    def escape(match):
        inner = re.sub(r"(\w)_(?=[,\s)]|$)", r"\1\\_", match.group(1))
        return f"shape ({inner})"

    lines[:] = [SHAPE.sub(escape, line) for line in lines]


def _defining_comment(obj, name):
    """The ``#:`` comment above ``name = ...`` in the ndlfd module defining it.

    A constant re-exported by a package (``ndlfd.learner.DECODERS`` from a
    private module) has its comment where it is assigned, which autodoc does
    not look at; it looks only in the module it documents.
    """
    for modname, module in sorted(sys.modules.items()):
        if not modname.startswith("ndlfd") or getattr(module, name, None) is not obj:
            continue
        try:
            docs = ModuleAnalyzer.for_module(modname).find_attr_docs()
        except PycodeError:
            continue
        if ("", name) in docs:
            return list(docs[("", name)])
    return []


def _constant_docs(app, what, name, obj, options, lines):
    """A constant's own words, never its type's docstring.

    Without a ``#:`` comment in the documented module, autodoc shows the
    docstring of the value's type (``int``'s, or the options registry's); here
    such a constant gets the comment where it is defined, or for a registry of
    options the names it holds, or nothing (its value is shown beside it).
    """
    if what != "data" or type(obj).__doc__ is None:
        return
    inherited = inspect.cleandoc(type(obj).__doc__).splitlines()
    if [ln for ln in lines if ln.strip()] != [ln for ln in inherited if ln.strip()]:
        return  # the module's own comment
    own = _defining_comment(obj, name.rpartition(".")[2])
    if not own and isinstance(obj, Registry):
        choices = ", ".join(f"``{n!r}``" for n in obj)
        own = [f"The choices of the option ``{obj.option}``: {choices}."]
    lines[:] = own


def setup(app):
    """Connect the Markdown mends and the docstring fixes."""
    app.connect("source-read", _mend_markdown)
    # before numpydoc (priority 500) reads the docstring
    app.connect("autodoc-process-docstring", _constant_docs, priority=400)
    app.connect("autodoc-process-docstring", _escape_shapes)


# the gallery's examples warn only through our own warnings; matplotlib's Agg
# backend says nothing when asked to show a figure headless
warnings.filterwarnings("ignore", message="Matplotlib is currently using agg")
