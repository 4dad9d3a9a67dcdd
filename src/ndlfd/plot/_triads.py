"""Orientation triads along a 3-D path: the body's x, y and z axes.

Red, green and blue, as RViz draws frames, at equal steps of arc length.
"""

from __future__ import annotations

import numpy as np

from .._errors import ValidationError
from ._figures import TRIAD_COLORS

__all__ = ["plot_triads", "triad_indices"]


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
    >>> from ndlfd.plot import new_figure
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
