"""Figures a person would rather look at than read (optional ``plot`` extra).

Everything here draws on :class:`matplotlib.figure.Figure` objects without
pyplot, so it works headless (no display, no backend switching) in scripts,
tests and the command line. Install the extra with ``pip install "ndlfd[plot]"``.

Conventions: demonstrations in one light colour, key points as dots, the start
as ``×`` and the goal as ``*``, the generated path in red over them, the test
demonstration dashed.
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence

import numpy as np

from ._errors import MissingExtraError, ValidationError
from ._fileformat import atomic_path

__all__ = [
    "new_figure",
    "plot_demos",
    "plot_keypoint_counts",
    "plot_path",
    "save_figure",
]

DEMO_COLOR = "#7fa7d6"
KEY_COLOR = "#1f3f8f"
GEN_COLOR = "#d62728"
TEST_COLOR = "#222222"


def _matplotlib():
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
    Figure = _matplotlib()
    fig = Figure(figsize=(size[0] * n_axes, size[1]), layout="constrained")
    kw = {"projection": "3d"} if dims == 3 else {}
    axes = [fig.add_subplot(1, n_axes, i + 1, **kw) for i in range(n_axes)]
    return fig, axes


def _xyz(values: np.ndarray) -> list[np.ndarray]:
    return [values[:, c] for c in range(min(values.shape[1], 3))]


def plot_path(ax, values, *, keypoints=None, label=None, color=DEMO_COLOR, **kw):
    """Draw one path (2-D or 3-D) with optional key points, start and goal marks.

    Parameters
    ----------
    ax : Axes
        Target axes (3-D axes for 3-column values).
    values : array-like of shape (n_samples, 2) or (n_samples, 3)
        The path (further columns are ignored).
    keypoints : array-like of int, optional
        Indices of key points to mark with dots.
    label : str, optional
        Legend label.
    color : str
        Line colour.
    **kw
        Passed to ``ax.plot`` for the line.

    Returns
    -------
    ax : Axes
    """
    V = np.asarray(values, dtype=float)
    if V.ndim != 2 or V.shape[1] < 2:
        raise ValidationError(
            f"a path to plot must have shape (n_samples, 2 or 3); got {V.shape}"
        )
    cols = _xyz(V)
    ax.plot(*cols, color=color, label=label, **kw)
    if keypoints is not None:
        K = V[np.asarray(keypoints, dtype=np.int64)]
        ax.plot(*_xyz(K), "o", color=KEY_COLOR, markersize=3.5, linestyle="none")
    ax.plot(*_xyz(V[:1]), "x", color="black", markersize=8, mew=2, linestyle="none")
    ax.plot(*_xyz(V[-1:]), "*", color="black", markersize=11, linestyle="none")
    return ax


def plot_demos(
    demos,
    *,
    group: str = "position",
    keypoints: Sequence[np.ndarray] | None = None,
    generated=None,
    test=None,
    ax=None,
    title: str | None = None,
    max_demos: int | None = 30,
):
    """Plot demonstrations, their key points, a generated path and a test path.

    Parameters
    ----------
    demos : sequence of Demonstration
        Training demonstrations (drawn in one light colour).
    group : str, default="position"
        The group to draw (its first two or three columns).
    keypoints : sequence of ndarray of int, optional
        Key-point indices per demonstration, marked with dots.
    generated : Demonstration, optional
        The generated path, drawn in red with its key points.
    test : Demonstration, optional
        The test demonstration, drawn dashed.
    ax : Axes, optional
        Where to draw; a new figure is made otherwise.
    title : str, optional
        Axes title.
    max_demos : int or None, default=30
        Draw at most this many demonstrations (all if None).

    Returns
    -------
    ax : Axes
    """
    demos = list(demos)
    if not demos and generated is None and test is None:
        raise ValidationError("plot_demos needs at least one path to draw; got none")
    ref = demos[0] if demos else (generated if generated is not None else test)
    dims = min(ref.get(group).shape[1], 3)
    if ax is None:
        _, (ax,) = new_figure(1, dims=dims)
    shown = demos if max_demos is None else demos[:max_demos]
    for i, d in enumerate(shown):
        kp = None if keypoints is None else keypoints[i]
        plot_path(
            ax,
            d.get(group),
            keypoints=kp,
            color=DEMO_COLOR,
            lw=0.8,
            alpha=0.7,
            label="demonstrations" if i == 0 else None,
        )
    if test is not None:
        plot_path(ax, test.get(group), color=TEST_COLOR, lw=1.2, ls="--", label="test")
    if generated is not None:
        G = generated.get(group)
        plot_path(ax, G, color=GEN_COLOR, lw=2.0, label="generated")
        ax.plot(*_xyz(G), "o", color=GEN_COLOR, markersize=3, linestyle="none")
    cols = [c for c, g in zip(ref.columns, ref.groups, strict=True) if g == group]
    ax.set_xlabel(cols[0])
    ax.set_ylabel(cols[1] if len(cols) > 1 else "")
    if dims == 3:
        ax.set_zlabel(cols[2])
    else:
        ax.set_aspect("equal", adjustable="datalim")
    if title:
        ax.set_title(title)
    ax.legend(loc="best", fontsize="small")
    return ax


def plot_keypoint_counts(counts: Mapping[str, Sequence[int]], *, ax=None, title=None):
    """Box plots of key-point counts, one box per setting.

    Parameters
    ----------
    counts : mapping of str to sequence of int
        Setting name → key-point count per demonstration.
    ax : Axes, optional
        Where to draw.
    title : str, optional
        Axes title.

    Returns
    -------
    ax : Axes

    Examples
    --------
    >>> ax = plot_keypoint_counts({"2-D": [45, 50, 60], "4-D": [39, 41, 46]})
    >>> [t.get_text() for t in ax.get_xticklabels()]
    ['2-D', '4-D']
    """
    if not counts:
        raise ValidationError("plot_keypoint_counts needs at least one setting")
    if ax is None:
        _, (ax,) = new_figure(1, size=(2.0 + 1.2 * len(counts), 4.0))
    names = list(counts)
    ax.boxplot([np.asarray(counts[k]) for k in names], tick_labels=names)
    ax.set_ylabel("key points per demonstration")
    if title:
        ax.set_title(title)
    return ax


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
