"""Markdown tables and report folders, shared by the experiment modules.

:mod:`ndlfd.jobs.reproduction` and :mod:`ndlfd.jobs.evaluation` each write a folder with
one Markdown file and some figures. This module holds what they have in common:
a Markdown table, a number formatter for table cells, the joining of Markdown
blocks into a document, and :class:`Report`, the folder, into which every file
is written atomically (a temporary file beside it, renamed into place).
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Sequence
from pathlib import Path

from .._errors import ValidationError
from .._fileformat import atomic_path
from ..plot import save_figure

__all__ = ["Report", "fmt_number", "image", "markdown", "markdown_table"]

_RULES = {"l": "---", "r": "---:"}


def fmt_number(x: float | None, spec: str = ".3g") -> str:
    """Format a table cell: ``"–"`` for a missing value (None or NaN).

    Parameters
    ----------
    x : float or None
        The value.
    spec : str, default=".3g"
        Format specification of a finite value.

    Returns
    -------
    text : str

    Examples
    --------
    >>> fmt_number(0.000123456), fmt_number(2.0), fmt_number(float("nan"))
    ('0.000123', '2', '–')
    >>> fmt_number(float("inf")), fmt_number(1 / 3, ".2f")
    ('inf', '0.33')
    """
    if x is None or math.isnan(x):
        return "–"
    return format(x, spec)


def _cell(value) -> str:
    return str(value).replace("|", r"\|").replace("\n", " ")


def markdown_table(
    header: Sequence,
    rows: Iterable[Sequence],
    align: str | None = None,
) -> str:
    r"""A Markdown (GitHub) table, one line per row, without a trailing newline.

    Parameters
    ----------
    header : sequence
        Column titles.
    rows : iterable of sequence
        The cells, one sequence per row, as long as ``header``. Cells are
        converted with ``str``; a ``|`` in a cell is escaped as ``\|`` and a
        line break becomes a space.
    align : str, optional
        One letter per column: ``"l"`` (left, ``---``) or ``"r"`` (right,
        ``---:``, for numbers). Every column is left-aligned by default.

    Returns
    -------
    text : str

    Raises
    ------
    ValidationError
        ``align`` or a row does not have one entry per column, or ``align``
        holds a letter other than ``"l"`` and ``"r"``.

    Examples
    --------
    >>> print(markdown_table(["name", "n"], [["a", 1], ["b|c", 20]], align="lr"))
    | name | n |
    |---|---:|
    | a | 1 |
    | b\|c | 20 |
    """
    n = len(header)
    align = "l" * n if align is None else align
    if len(align) != n or set(align) - set(_RULES):
        raise ValidationError(
            f"align must have one letter 'l' or 'r' per column ({n}); got {align!r}"
        )
    lines = [
        "| " + " | ".join(map(_cell, header)) + " |",
        "|" + "|".join(_RULES[a] for a in align) + "|",
    ]
    for row in rows:
        if len(row) != n:
            raise ValidationError(
                f"every row must have {n} cells (one per column); got {len(row)}:"
                f" {list(row)!r}"
            )
        lines.append("| " + " | ".join(map(_cell, row)) + " |")
    return "\n".join(lines)


def image(path: str, alt: str) -> str:
    """A Markdown image link.

    Examples
    --------
    >>> image("fig2.png", "Fig. 2")
    '![Fig. 2](fig2.png)'
    """
    return f"![{alt}]({path})"


def markdown(blocks: Iterable[str]) -> str:
    r"""Join Markdown blocks with one blank line; end with a newline.

    A block is a heading, a paragraph, a table, a list: one or more lines.
    Empty blocks (``""``, e.g. an optional note that does not apply) are left
    out.

    Examples
    --------
    >>> markdown(["# Title", "", "Text.", "- a\n- b"])
    '# Title\n\nText.\n\n- a\n- b\n'
    """
    return "\n\n".join(b for b in blocks if b) + "\n"


class Report:
    """A report folder; figures and Markdown files are each written atomically.

    Parameters
    ----------
    folder : str or path-like
        The folder (created with its parents).
    dpi : int, default=110
        Resolution of the figures.

    Attributes
    ----------
    folder : Path
    files : list of Path
        The files written so far, in order.

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.mkdtemp()
    >>> report = Report(tmp)
    >>> path = report.write("report.md", ["# Title", markdown_table(["a"], [[1]])])
    >>> print(path.read_text(), end="")
    # Title
    <BLANKLINE>
    | a |
    |---|
    | 1 |
    >>> [p.name for p in report.files]
    ['report.md']
    """

    def __init__(self, folder: str | os.PathLike, *, dpi: int = 110) -> None:
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.dpi = dpi
        self.files: list[Path] = []

    def figure(self, fig, name: str) -> Path:
        """Save a matplotlib figure as ``name`` (e.g. ``"shapes/Line.png"``)."""
        path = self.folder / name
        save_figure(fig, path, dpi=self.dpi)
        self.files.append(path)
        return path

    def write(self, name: str, blocks: Iterable[str]) -> Path:
        """Write the Markdown blocks (see :func:`markdown`) as ``name``."""
        path = self.folder / name
        text = markdown(blocks)
        with atomic_path(path, suffix=Path(name).suffix) as tmp:
            tmp.write_text(text, encoding="utf-8")
        self.files.append(path)
        return path
