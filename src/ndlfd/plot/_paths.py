"""Paths on a position's axes: one path, sampled paths, demonstrations, a comparison.

Demonstrations in one light colour (each route in its own), key points as
dots, the start as ``×`` and the goal as ``*``, the generated path in red over
them, the test demonstration dashed, sampled paths as thin red lines.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from .._errors import ValidationError
from ._band import plot_band
from ._figures import (
    DEMO_COLOR,
    GEN_COLOR,
    KEY_COLOR,
    PALETTE,
    ROUTE_COLORS,
    TEST_COLOR,
    new_figure,
    xyz,
)

__all__ = ["plot_comparison", "plot_demos", "plot_path", "plot_samples"]


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
    cols = xyz(V)
    ax.plot(*cols, color=color, label=label, **kw)
    if keypoints is not None:
        K = V[np.asarray(keypoints, dtype=np.int64)]
        dots = KEY_COLOR if key_color is None else key_color
        ax.plot(*xyz(K), "o", color=dots, markersize=3.5, linestyle="none")
    ax.plot(*xyz(V[:1]), "x", color="black", markersize=8, mew=2, linestyle="none")
    ax.plot(*xyz(V[-1:]), "*", color="black", markersize=11, linestyle="none")
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
        ax.plot(*xyz(p)[:dims], color=color,
                label=label if i == 0 else "_nolegend_", **style)  # fmt: skip
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
        ax.plot(*xyz(G), "o", color=GEN_COLOR, markersize=3, linestyle="none")
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
            *xyz(d.get(group))[:2],
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
