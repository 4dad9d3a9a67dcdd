"""Where a recording rests: cutting one long recording into demonstrations.

A robot recorded over several demonstrations keeps publishing while it waits
between them (``/tf``, ``/joint_states``), so the pauses are not gaps in the
stamps but stretches where nothing moves. :func:`rest_pieces` finds them.

**Rest.** Each column is scaled by its range over the recording (a column that
never changes is left out; quaternions are sign-aligned first), so joints,
metres and a gripper count alike. The *speed* at a sample is the distance the
scaled point travels between ``t - h`` and ``t + h`` (linear interpolation,
``h`` a quarter of ``seconds``, clipped at the ends) divided by that time: an
average that measurement noise of a rest does not make look like motion. The
recording's *typical moving speed* is the 90th percentile of the speeds (the
recording may rest up to most of its time and this is still a speed of
motion). A sample **rests** when its speed is below 5 % of the typical moving
speed; a **rest** is a run of resting samples lasting at least ``seconds``.

A resting sample's window lies inside the rest, so a run of resting samples
from ``t_a`` to ``t_b`` is a rest from ``t_a - h`` to ``t_b + h``. The pieces
are the stretches between rests, each from the last sample of the rest before
it to the first sample of the rest after it (so each starts and ends at rest);
rests at the start or end of the recording are left out.
"""

from __future__ import annotations

import numpy as np

__all__ = ["MOVING_PERCENTILE", "REST_SHARE", "rest_pieces"]

#: The percentile of the speeds taken as the recording's typical moving speed.
MOVING_PERCENTILE = 90.0
#: A sample rests below this share of the typical moving speed.
REST_SHARE = 0.05


def _aligned(X: np.ndarray, quaternions) -> np.ndarray:
    """``X`` with each quaternion's sign chosen to follow the one before it."""
    X = X.copy()
    for cols in quaternions:
        Q = X[:, list(cols)]
        flip = np.einsum("ij,ij->i", Q[1:], Q[:-1]) < 0
        sign = np.concatenate([[1.0], np.where(np.cumsum(flip) % 2 == 1, -1.0, 1.0)])
        X[:, list(cols)] = Q * sign[:, None]
    return X


def speeds(t: np.ndarray, X: np.ndarray, seconds: float, quaternions=()) -> np.ndarray:
    """The scaled speed at each sample (see the module's text).

    Parameters
    ----------
    t : ndarray of shape (n,)
        Seconds, strictly increasing.
    X : ndarray of shape (n, d)
        The values.
    seconds : float
        The shortest rest; the speed is averaged over a quarter of it on each
        side.
    quaternions : sequence of sequence of int
        The columns of each quaternion (sign-aligned first).

    Returns
    -------
    speed : ndarray of shape (n,)
    """
    X = _aligned(np.asarray(X, dtype=np.float64), quaternions)
    span = X.max(axis=0) - X.min(axis=0)
    moving = span > 0
    if not moving.any() or t.size < 2:
        return np.zeros(t.size)
    U = (X[:, moving] - X[:, moving].min(axis=0)) / span[moving]
    h = seconds / 4.0
    lo = np.maximum(t - h, t[0])
    hi = np.minimum(t + h, t[-1])
    a = np.column_stack([np.interp(lo, t, u) for u in U.T])
    b = np.column_stack([np.interp(hi, t, u) for u in U.T])
    return np.linalg.norm(b - a, axis=1) / (hi - lo)


def rest_pieces(
    t: np.ndarray, X: np.ndarray, seconds: float, quaternions=()
) -> list[tuple[int, int]]:
    """The pieces of a recording between rests of at least ``seconds``.

    Parameters
    ----------
    t : ndarray of shape (n,)
        Seconds, strictly increasing.
    X : ndarray of shape (n, d)
        The values.
    seconds : float
        The shortest rest that separates two pieces (> 0).
    quaternions : sequence of sequence of int
        The columns of each quaternion.

    Returns
    -------
    pieces : list of (start, stop)
        Index ranges (``stop`` exclusive) of the pieces, in order; the whole
        recording when it has no rest, and none when it never moves.

    Examples
    --------
    >>> t = np.arange(0.0, 10.0, 0.1)
    >>> x = np.clip(t - 1, 0, 2) + np.clip(t - 6, 0, 2)  # moves 1-3 s and 6-8 s
    >>> [(float(t[a]), float(t[b - 1])) for a, b in rest_pieces(t, x[:, None], 1.5)]
    [(0.0, 3.1), (5.9, 8.1)]
    """
    speed = speeds(t, X, seconds, quaternions)
    typical = float(np.percentile(speed, MOVING_PERCENTILE))
    if typical <= 0:
        return []
    rest = speed < REST_SHARE * typical
    edges = np.flatnonzero(np.diff(np.concatenate([[0], rest.astype(np.int8), [0]])))
    h = seconds / 4.0  # a resting sample's window lies in the rest: widen by h
    pieces = []
    start = 0
    for a, b in zip(edges[::2], edges[1::2], strict=True):
        lo, hi = max(t[a] - h, t[0]), min(t[b - 1] + h, t[-1])
        if hi - lo < seconds * (1 - 1e-9):
            continue
        stop = int(np.searchsorted(t, lo, "left")) + 1  # the first sample at rest
        if stop - start >= 2:
            pieces.append((start, stop))
        start = int(np.searchsorted(t, hi, "right")) - 1  # the last one at rest
    if t.size - start >= 2:
        pieces.append((start, t.size))
    return pieces
