"""Figures made headless, the colours every drawing shares, and saving.

matplotlib is imported by :func:`figure_class`, when a figure is made, never
on import.
"""

from __future__ import annotations

import os

import numpy as np

from .._errors import MissingExtraError
from .._fileformat import atomic_path

__all__ = [
    "DEMO_COLOR",
    "GEN_COLOR",
    "KEY_COLOR",
    "PALETTE",
    "ROUTE_COLORS",
    "TEST_COLOR",
    "TRIAD_COLORS",
    "figure_class",
    "new_figure",
    "new_grid",
    "save_figure",
    "xyz",
]

DEMO_COLOR = "#7fa7d6"
KEY_COLOR = "#1f3f8f"
GEN_COLOR = "#d62728"
TEST_COLOR = "#222222"
#: Colours of an orientation triad's x, y and z axes (red, green, blue, as RViz).
TRIAD_COLORS = ("#d62728", "#2ca02c", "#1f77b4")
#: Colours of the demonstrations' routes, in order (lines and key points;
#: none is GEN_COLOR, the generated path's).
ROUTE_COLORS = ("#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b")

#: Colours of compared generators, in order (ndlfd itself is always GEN_COLOR).
PALETTE = (
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#7f7f7f",
    "#bcbd22",
    "#17becf",
)


def figure_class():
    """Matplotlib's ``Figure`` class, imported now (the ``plot`` extra)."""
    try:
        import matplotlib  # noqa: F401
        from matplotlib.figure import Figure
    except ImportError:  # pragma: no cover - depends on the environment
        raise MissingExtraError(
            'plotting needs matplotlib; install it with: pip install "ndlfd[plot]"'
        ) from None
    return Figure


def new_figure(n_axes: int = 1, *, dims: int = 2, size=(6.0, 5.0)):
    """Create a headless figure with ``n_axes`` side-by-side axes.

    Parameters
    ----------
    n_axes : int, default=1
        Number of axes in one row.
    dims : {2, 3}, default=2
        Make 3-D axes when 3.
    size : tuple of float, default=(6.0, 5.0)
        Size of one panel in inches.

    Returns
    -------
    fig : matplotlib.figure.Figure
    axes : list of Axes

    Examples
    --------
    >>> fig, axes = new_figure(2)
    >>> len(axes)
    2
    """
    Figure = figure_class()
    fig = Figure(figsize=(size[0] * n_axes, size[1]), layout="constrained")
    kw = {"projection": "3d"} if dims == 3 else {}
    axes = [fig.add_subplot(1, n_axes, i + 1, **kw) for i in range(n_axes)]
    return fig, axes


def new_grid(n_rows: int, n_cols: int, *, size=(4.5, 4.0)):
    """Create a headless figure with a grid of 2-D axes.

    Parameters
    ----------
    n_rows, n_cols : int
        Grid shape.
    size : tuple of float, default=(4.5, 4.0)
        Size of one panel in inches.

    Returns
    -------
    fig : matplotlib.figure.Figure
    axes : list of list of Axes
        ``axes[row][col]``.

    Examples
    --------
    >>> fig, axes = new_grid(2, 3)
    >>> len(axes), len(axes[0])
    (2, 3)
    """
    Figure = figure_class()
    fig = Figure(figsize=(size[0] * n_cols, size[1] * n_rows), layout="constrained")
    axes = [
        [fig.add_subplot(n_rows, n_cols, r * n_cols + c + 1) for c in range(n_cols)]
        for r in range(n_rows)
    ]
    return fig, axes


def xyz(values: np.ndarray) -> list[np.ndarray]:
    """The first two or three columns of ``values`` (n_samples, d), for ``ax.plot``."""
    return [values[:, c] for c in range(min(values.shape[1], 3))]


def save_figure(fig, path: str | os.PathLike, *, dpi: int = 110):
    """Save ``fig`` atomically (the format follows the file's suffix).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    path : str or path-like
        Destination, e.g. ``"out/figure.png"``.
    dpi : int, default=110
        Resolution.

    Returns
    -------
    path : str or path-like
    """
    suffix = os.path.splitext(os.fspath(path))[1] or ".png"
    with atomic_path(path, suffix=suffix) as tmp:
        fig.savefig(tmp, dpi=dpi, format=suffix.lstrip("."))
    return path
