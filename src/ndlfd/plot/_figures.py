"""Figures a person would rather look at than read (optional ``plot`` extra).

Everything here draws on :class:`matplotlib.figure.Figure` objects without
pyplot, so it works headless (no display, no backend switching) in scripts,
tests and the command line. Install the extra with ``pip install "ndlfd[plot]"``.

Conventions: demonstrations in one light colour, key points as dots, the start
as ``×`` and the goal as ``*``, the generated path in red over them, the test
demonstration dashed, sampled paths as thin red lines, orientation triads
with the x, y and z axes in red, green and blue (as RViz draws frames), and
task frames as markers in their demonstration's colour (:func:`plot_frames`).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence

import numpy as np

from .._errors import MissingExtraError, ValidationError
from .._fileformat import atomic_path
from ._band import band_polygons
from ._frames import plot_frames

__all__ = [
    "new_figure",
    "new_figure_beside",
    "new_grid",
    "plot_band",
    "plot_boxplot",
    "plot_channels",
    "plot_comparison",
    "plot_demos",
    "plot_frames",
    "plot_keypoint_counts",
    "plot_path",
    "plot_samples",
    "plot_triads",
    "save_figure",
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
    Figure = _matplotlib()
    fig = Figure(figsize=(size[0] * n_cols, size[1] * n_rows), layout="constrained")
    axes = [
        [fig.add_subplot(n_rows, n_cols, r * n_cols + c + 1) for c in range(n_cols)]
        for r in range(n_rows)
    ]
    return fig, axes


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
    Figure = _matplotlib()
    height = max(5.0, 1.2 + 1.5 * n_channels)
    fig = Figure(figsize=(13.0, height), layout="constrained")
    left, side = fig.subfigures(1, 2, width_ratios=[6.0, 7.0])
    kw = {"projection": "3d"} if dims == 3 else {}
    return fig, left.add_subplot(1, 1, 1, **kw), side


def _xyz(values: np.ndarray) -> list[np.ndarray]:
    return [values[:, c] for c in range(min(values.shape[1], 3))]


def plot_path(
    ax, values, *, keypoints=None, label=None, color=DEMO_COLOR, key_color=None, **kw
):
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
    key_color : str, optional
        Colour of the key-point dots (default: one dark blue for all).
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
        dots = KEY_COLOR if key_color is None else key_color
        ax.plot(*_xyz(K), "o", color=dots, markersize=3.5, linestyle="none")
    ax.plot(*_xyz(V[:1]), "x", color="black", markersize=8, mew=2, linestyle="none")
    ax.plot(*_xyz(V[-1:]), "*", color="black", markersize=11, linestyle="none")
    return ax


def plot_samples(ax, paths, *, color=GEN_COLOR, label="samples", **kw):
    """Draw paths drawn from a model as thin lines (one legend entry).

    Parameters
    ----------
    ax : Axes
        Target axes (3-D axes for 3-column values).
    paths : sequence of array-like of shape (n_samples, 2) or (n_samples, 3)
        The sampled paths (``KeypointHMM.sample``, ``ndlfd sample -o DIR``);
        the first two columns are drawn on 2-D axes, three on 3-D axes.
    color : str, default=GEN_COLOR
        Line colour.
    label : str, default="samples"
        The legend label (of the first line only).
    **kw
        Passed to ``ax.plot`` (default ``lw=0.6, alpha=0.5``).

    Returns
    -------
    ax : Axes

    Examples
    --------
    >>> import numpy as np
    >>> _, (ax,) = new_figure(1)
    >>> s = np.linspace(0, 1, 20)
    >>> ax = plot_samples(ax, [np.column_stack([s, s**k]) for k in (1, 2, 3)])
    >>> [ln.get_label() for ln in ax.lines][:2], ax.lines[0].get_linewidth()
    (['samples', '_nolegend_'], 0.6)
    """
    paths = [np.asarray(p, dtype=float) for p in paths]
    if not paths:
        raise ValidationError("plot_samples needs at least one path; got none")
    for p in paths:
        if p.ndim != 2 or p.shape[1] < 2:
            raise ValidationError(
                f"a path to plot must have shape (n_samples, 2 or 3); got {p.shape}"
            )
    style = {"lw": 0.6, "alpha": 0.5, **kw}
    dims = 3 if ax.name == "3d" else 2
    for i, p in enumerate(paths):
        ax.plot(*_xyz(p)[:dims], color=color,
                label=label if i == 0 else "_nolegend_", **style)  # fmt: skip
    return ax


def triad_indices(positions, n_triads: int) -> np.ndarray:
    """Where to draw ``n_triads`` triads: equal steps of arc length, ends included.

    Parameters
    ----------
    positions : array-like of shape (n_samples, d)
    n_triads : int
        How many (at most ``n_samples``; a path that does not move gets them
        at equal steps of the sample index instead).

    Returns
    -------
    indices : ndarray of int64, sorted, distinct

    Examples
    --------
    >>> import numpy as np
    >>> x = np.r_[np.zeros(5), np.linspace(0, 1, 11)]  # a pause, then a move
    >>> triad_indices(np.column_stack([x, 0 * x]), 3).tolist()
    [0, 10, 15]
    """
    P = np.asarray(positions, dtype=float)
    n = P.shape[0]
    k = min(int(n_triads), n)
    if k <= 0:
        return np.zeros(0, np.int64)
    s = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))]
    if k == 1:
        return np.zeros(1, np.int64)
    if s[-1] <= 0:
        return np.unique(np.round(np.linspace(0, n - 1, k)).astype(np.int64))
    # the first sample at or past each of k equal steps of the path's length
    idx = np.searchsorted(s, np.linspace(0.0, s[-1], k) * (1 - 1e-12))
    return np.unique(np.minimum(idx, n - 1)).astype(np.int64)


def plot_triads(ax, positions, quaternions, *, n_triads: int = 8, length=None):
    """Draw orientation triads (the body's x, y, z axes) along a 3-D path.

    Each triad is three short lines from a sample's position along the columns
    of its rotation matrix, x red, y green, z blue (as RViz draws frames). The
    triads stand at equal steps of the path's arc length, both ends included,
    so a pause gets no pile of them (:func:`triad_indices`). The axes get
    equal scales, so that the triads look square.

    Parameters
    ----------
    ax : Axes
        3-D axes.
    positions : array-like of shape (n_samples, 3)
    quaternions : array-like of shape (n_samples, 4)
        Unit quaternions ``(w, x, y, z)`` (normalized here).
    n_triads : int, default=8
        How many triads (fewer on a shorter path).
    length : float, optional
        The length of each axis line. Default: a tenth of the largest extent
        of the positions (1 for a path that does not move).

    Returns
    -------
    indices : ndarray of int64
        The samples that got a triad.

    Examples
    --------
    >>> import numpy as np
    >>> _, (ax,) = new_figure(1, dims=3)
    >>> p = np.column_stack([np.linspace(0, 1, 5), np.zeros(5), np.zeros(5)])
    >>> q = np.tile([np.sqrt(0.5), 0, 0, np.sqrt(0.5)], (5, 1))  # 90 deg about z
    >>> plot_triads(ax, p, q, n_triads=2, length=0.5).tolist()
    [0, 4]
    >>> x_axis = ax.lines[0].get_data_3d()  # the body's x now points along y
    >>> np.round([c[:2] for c in x_axis], 6).tolist()
    [[0.0, 0.0], [0.0, 0.5], [0.0, 0.0]]
    """
    from scipy.spatial.transform import Rotation

    P = np.asarray(positions, dtype=float)
    Q = np.asarray(quaternions, dtype=float)
    if P.ndim != 2 or P.shape[1] != 3 or Q.shape != (P.shape[0], 4):
        raise ValidationError(
            "plot_triads needs positions of shape (n, 3) and quaternions of shape"
            f" (n, 4); got {P.shape} and {Q.shape}"
        )
    if not (np.all(np.isfinite(P)) and np.all(np.isfinite(Q))):
        raise ValidationError("plot_triads needs finite positions and quaternions")
    norms = np.linalg.norm(Q, axis=1)
    if np.any(norms < 1e-12):
        raise ValidationError("plot_triads needs quaternions of non-zero norm")
    if length is None:
        extent = float(np.ptp(P, axis=0).max()) if P.size else 0.0
        length = 0.1 * extent if extent > 0 else 1.0
    idx = triad_indices(P, n_triads)
    R = Rotation.from_quat((Q[idx] / norms[idx, None])[:, [1, 2, 3, 0]]).as_matrix()
    gap = np.full((idx.size, 1, 3), np.nan)
    for a, color in enumerate(TRIAD_COLORS):
        tips = P[idx] + length * R[:, :, a]  # column a: the body's axis a
        segs = np.concatenate([P[idx][:, None], tips[:, None], gap], axis=1)
        xyz = segs.reshape(-1, 3)
        label = "orientation: x, y, z axes" if a == 0 else "_nolegend_"
        ax.plot(xyz[:, 0], xyz[:, 1], xyz[:, 2], color=color, lw=1.2, label=label)
    ax.set_aspect("equal")  # else the triads do not look square
    return idx


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
    routes=None,
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
    routes : array-like of int, optional
        Each demonstration's route (``KeypointHMM.routes_``): with more than
        one, each route in its own colour, labelled with its number and size.

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
    routes = None if routes is None else np.asarray(routes, dtype=np.int64)
    if routes is not None and routes.shape != (len(demos),):
        raise ValidationError(
            f"routes must hold one route per demonstration ({len(demos)}); got"
            f" shape {routes.shape}"
        )
    several = routes is not None and np.unique(routes).size > 1
    labelled: set = set()
    for i, d in enumerate(shown):
        kp = None if keypoints is None else keypoints[i]
        color, label = DEMO_COLOR, "demonstrations" if i == 0 else None
        if several:
            r = int(routes[i])
            color = ROUTE_COLORS[r % len(ROUTE_COLORS)]
            n_r = int(np.sum(routes == r))
            label = None if r in labelled else f"route {r} ({n_r} demonstrations)"
            labelled.add(r)
        plot_path(ax, d.get(group), keypoints=kp, color=color, lw=0.8, alpha=0.7,
                  label=label, key_color=color if several else None)  # fmt: skip
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
        Figure = _matplotlib()
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


def plot_band(
    ax, values, std, *, k: float = 1.0, color=GEN_COLOR, alpha=0.2, label=None
):
    """Shade a band of ``k`` standard deviations around a 2-D path.

    The band is the union of, at every point, the ellipse with semi-axes
    ``k * std`` (independent coordinates) and, along every segment, the strip
    reaching on both sides along the segment's normal ``n`` to the standard
    deviation in that direction, ``k * sqrt((n_x s_x)^2 + (n_y s_y)^2)``
    (:func:`ndlfd.plot._band.band_polygons`). It is drawn as one patch, so
    overlapping pieces do not darken each other and a path that crosses
    itself leaves no holes.

    Parameters
    ----------
    ax : Axes
        Target (2-D) axes.
    values : array-like of shape (n_samples, 2)
        The path.
    std : array-like of shape (n_samples, 2)
        Standard deviation of each coordinate at each point.
    k : float, default=1.0
        Half-width of the band in standard deviations.
    color : str
        Fill colour.
    alpha : float, default=0.2
        Fill opacity.
    label : str, optional
        Legend label.

    Returns
    -------
    ax : Axes

    Examples
    --------
    >>> _, (ax,) = new_figure(1)
    >>> ax = plot_band(ax, [[0, 0], [1, 0], [2, 0]], [[0, 1], [0, 1], [0, 2]])
    >>> [float(v) for v in ax.patches[0].get_path().get_extents().bounds]
    [0.0, -2.0, 2.0, 4.0]
    """
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path as MplPath

    pieces = band_polygons(values, std, k)
    verts, codes = [], []
    for poly in pieces:
        m = poly.shape[1]
        code = np.full(m + 1, MplPath.LINETO, dtype=MplPath.code_type)
        code[0], code[-1] = MplPath.MOVETO, MplPath.CLOSEPOLY
        verts.append(np.concatenate([poly, poly[:, :1]], axis=1).reshape(-1, 2))
        codes.append(np.tile(code, poly.shape[0]))
    patch = PathPatch(
        MplPath(np.concatenate(verts), np.concatenate(codes)),
        facecolor=color,
        edgecolor="none",
        alpha=alpha,
        label=label,
    )
    ax.add_patch(patch)
    ax.update_datalim(patch.get_path().vertices)
    ax.autoscale_view()
    return ax


def plot_comparison(
    train,
    test,
    paths: Mapping[str, np.ndarray],
    *,
    stds: Mapping[str, np.ndarray] | None = None,
    group: str = "position",
    ax=None,
    title: str | None = None,
):
    """Training demonstrations, a held-out one, and several generated paths.

    Parameters
    ----------
    train : sequence of Demonstration
        Training demonstrations (thin, light).
    test : Demonstration
        The held-out demonstration (dashed black).
    paths : mapping of str to array-like of shape (n_samples, 2)
        Generator name → generated positions, each in its own colour
        (``"ndlfd"`` in the generated-path red).
    stds : mapping of str to array-like of shape (n_samples, 2), optional
        Generator name → standard deviation, drawn as a 1-sigma band
        (:func:`plot_band`) under that generator's path.
    group : str, default="position"
        The group of the demonstrations to draw.
    ax : Axes, optional
        Where to draw; a new figure is made otherwise.
    title : str, optional
        Axes title.

    Returns
    -------
    ax : Axes
    """
    if ax is None:
        _, (ax,) = new_figure(1)
    for i, d in enumerate(train):
        ax.plot(
            *_xyz(d.get(group))[:2],
            color=DEMO_COLOR,
            lw=0.8,
            label="training demos" if i == 0 else None,
        )
    T = test.get(group)
    ax.plot(T[:, 0], T[:, 1], color=TEST_COLOR, lw=1.4, ls="--", label="held out")
    ax.plot(T[:1, 0], T[:1, 1], "x", color="black", markersize=8, mew=2)
    ax.plot(T[-1:, 0], T[-1:, 1], "*", color="black", markersize=11)
    others = iter(PALETTE * (1 + len(paths) // len(PALETTE)))
    for name, values in paths.items():
        color = GEN_COLOR if name == "ndlfd" else next(others)
        V = np.asarray(values, dtype=float)
        if stds is not None and stds.get(name) is not None:
            plot_band(ax, V, stds[name], color=color, label=f"{name} ±1 sd")
        ax.plot(V[:, 0], V[:, 1], color=color, lw=1.6, label=name)
    ax.set_aspect("equal", adjustable="datalim")
    if title:
        ax.set_title(title)
    ax.legend(loc="best", fontsize="small")
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
