"""Channels over time (joints, a gripper, forces), beside a position or alone."""

from __future__ import annotations

import numpy as np

from .._errors import ValidationError
from ._figures import DEMO_COLOR, GEN_COLOR, KEY_COLOR, ROUTE_COLORS, figure_class

__all__ = ["new_figure_beside", "plot_channels"]


def new_figure_beside(n_channels: int, *, dims: int = 2):
    """A headless figure: a position's axes, its channels over time beside them.

    Parameters
    ----------
    n_channels : int
        Number of channels drawn over time (one axis each, stacked), e.g. by
        :func:`plot_channels` with ``fig=side``.
    dims : {2, 3}, default=2
        Make the position's axes 3-D when 3.

    Returns
    -------
    fig : matplotlib.figure.Figure
    ax : Axes
        The position's axes, on the left.
    side : SubFigure
        The right-hand part, for the channels.

    Examples
    --------
    >>> from ndlfd import Demonstration
    >>> fig, ax, side = new_figure_beside(3)
    >>> _, axes = plot_channels([Demonstration.from_arrays([0.0, 1.0],
    ...     joints=[[0, 1, 2], [1, 2, 3]])], fig=side)
    >>> len(fig.axes), [a.get_ylabel() for a in axes]
    (4, ['joints0', 'joints1', 'joints2'])
    """
    Figure = figure_class()
    height = max(5.0, 1.2 + 1.5 * n_channels)
    fig = Figure(figsize=(13.0, height), layout="constrained")
    left, side = fig.subfigures(1, 2, width_ratios=[6.0, 7.0])
    kw = {"projection": "3d"} if dims == 3 else {}
    return fig, left.add_subplot(1, 1, 1, **kw), side


def plot_channels(
    demos, *, columns=None, keypoints=None, generated=None, std=None, routes=None,
    samples=(), title=None, fig=None,
):  # fmt: skip
    """Each channel over time: one axis per channel, one shared time axis.

    For joints, a gripper, forces: any channel that is not a Cartesian
    position, where a 2-D or 3-D drawing of several channels against each
    other means little.

    Parameters
    ----------
    demos : sequence of Demonstration
        Drawn in one light colour (each route in its own with ``routes``).
    columns : sequence of str, optional
        The channels (column names), one axis each, top to bottom; default
        every column of the first demonstration.
    keypoints : sequence of ndarray of int, optional
        Key-point indices per demonstration, marked with dots.
    generated : Demonstration, optional
        A generated path, drawn in red on the axes of the columns it has.
    std : array-like of shape (n_samples, generated.n_dims), optional
        Its standard deviation per column, drawn as a band of ±1 sd.
    routes : array-like of int, optional
        Each demonstration's route.
    samples : sequence of Demonstration, optional
        Sampled paths, thin red lines.
    title : str, optional
        Title of the figure.
    fig : Figure or SubFigure, optional
        Where to draw (the channels' side of :func:`new_figure_beside`); a
        new figure otherwise.

    Returns
    -------
    fig : matplotlib.figure.Figure or SubFigure
    axes : list of Axes
        One per column, sharing the time axis.

    Examples
    --------
    >>> from ndlfd import Demonstration
    >>> d = Demonstration.from_arrays([0.0, 1.0, 2.0], joints=[[0, 1], [2, 3], [4, 5]])
    >>> fig, axes = plot_channels([d])
    >>> [ax.get_ylabel() for ax in axes], axes[0].lines[0].get_xydata().tolist()
    (['joints0', 'joints1'], [[0.0, 0.0], [1.0, 2.0], [2.0, 4.0]])
    """
    demos = list(demos)
    if not demos:
        raise ValidationError("plot_channels needs at least one demonstration")
    columns = list(demos[0].columns if columns is None else columns)
    missing = [c for c in columns if c not in demos[0].columns]
    if missing or not columns:
        raise ValidationError(
            f"columns must name columns of the demonstrations"
            f" ({', '.join(demos[0].columns)}); got {columns}"
        )
    n = len(columns)
    if fig is None:
        Figure = figure_class()
        fig = Figure(figsize=(8.0, 1.2 + 1.5 * n), layout="constrained")
    axes = list(np.atleast_1d(fig.subplots(n, 1, sharex=True, squeeze=False)[:, 0]))
    routes = None if routes is None else np.asarray(routes, dtype=np.int64)
    if routes is not None and routes.shape != (len(demos),):
        raise ValidationError(
            f"routes must hold one route per demonstration ({len(demos)}); got"
            f" shape {routes.shape}"
        )
    several = routes is not None and np.unique(routes).size > 1
    for j, (ax, c) in enumerate(zip(axes, columns, strict=True)):
        for i, d in enumerate(demos):
            color = DEMO_COLOR
            if several:
                color = ROUTE_COLORS[int(routes[i]) % len(ROUTE_COLORS)]
            y = d.X[:, d.columns.index(c)]
            label = "demonstrations" if i == 0 and j == 0 else None
            ax.plot(d.t, y, color=color, lw=0.8, alpha=0.7, label=label)
            if keypoints is not None:
                k = np.asarray(keypoints[i], dtype=np.int64)
                ax.plot(d.t[k], y[k], "o", color=KEY_COLOR if not several else color,
                        markersize=3, linestyle="none")  # fmt: skip
        for i, d in enumerate(samples):
            if c in d.columns:
                label = "samples" if i == 0 and j == 0 else None
                y = d.X[:, d.columns.index(c)]
                ax.plot(d.t, y, color=GEN_COLOR, lw=0.6, alpha=0.5, label=label)
        if generated is not None and c in generated.columns:
            g = generated.X[:, generated.columns.index(c)]
            first = j == 0 or columns[0] not in generated.columns
            if std is not None:
                s = np.asarray(std, dtype=float)[:, generated.columns.index(c)]
                label = "generated ±1 sd" if first else None
                ax.fill_between(generated.t, g - s, g + s, color=GEN_COLOR,
                                alpha=0.2, lw=0, label=label)  # fmt: skip
            ax.plot(generated.t, g, color=GEN_COLOR, lw=1.8,
                    label="generated" if first else None)  # fmt: skip
        ax.set_ylabel(c, fontsize="small")
    axes[-1].set_xlabel("time")
    if title:
        fig.suptitle(title)
    axes[0].legend(loc="best", fontsize="small")
    return fig, axes
