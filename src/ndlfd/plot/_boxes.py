"""Box plots: key points per demonstration, and an error per generator."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from .._errors import ValidationError
from ._figures import new_figure

__all__ = ["plot_boxplot", "plot_keypoint_counts"]


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


def plot_boxplot(
    values: Mapping[str, Sequence[float]],
    *,
    ax=None,
    title: str | None = None,
    ylabel: str | None = None,
    log: bool = False,
):
    """Box plots of a number, one box per label (e.g. one per generator).

    Non-finite values are left out; a label without finite values gets an
    empty slot, so boxes keep their place across panels.

    Parameters
    ----------
    values : mapping of str to sequence of float
        Label → values.
    ax : Axes, optional
        Where to draw; a new figure is made otherwise.
    title : str, optional
        Axes title.
    ylabel : str, optional
        Label of the value axis.
    log : bool, default=False
        Logarithmic value axis (for errors spanning decades).

    Returns
    -------
    ax : Axes

    Examples
    --------
    >>> ax = plot_boxplot({"mean": [0.1, 0.2, 0.4], "dmp": [0.3, 0.5]}, log=True)
    >>> [t.get_text() for t in ax.get_xticklabels()], ax.get_yscale()
    (['mean', 'dmp'], 'log')
    """
    if not values:
        raise ValidationError("plot_boxplot needs at least one label")
    if ax is None:
        _, (ax,) = new_figure(1, size=(2.0 + 1.0 * len(values), 4.0))
    names = list(values)
    data = []
    for k in names:
        v = np.asarray(values[k], dtype=float).ravel()
        data.append(v[np.isfinite(v)])
    ax.boxplot(data, tick_labels=names)
    if log:
        ax.set_yscale("log")
    if ylabel:
        ax.set_ylabel(ylabel)
    if title:
        ax.set_title(title)
    return ax
