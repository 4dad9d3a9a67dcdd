"""Rests and slow-downs of a path: where the demonstrations hold still.

A path's speed, measured on its moving average (:func:`smoothed`), against
its typical speed while moving, says where it slows down for a contact
(:func:`contact_window`: a start's offset is gone by the first) and where it
holds still between two moves (:func:`rest_windows`, :func:`path_rests`: a
grasp, a press, a pause). An offset faded on :func:`rest_clock` (a via
point's, :func:`~ndlfd.learner._via.apply_via`) or on progress held in the
rests (a start's, :func:`~ndlfd.learner._conditioning.pin`) does not change
there: the path holds still where the demonstrations do.
"""

from __future__ import annotations

import numpy as np

from ._blend import moving_average
from ._discrete import DISCRETE_GROUPS

__all__ = [
    "NO_PROGRESS",
    "REST_FRACTION",
    "REST_PACE",
    "SLOW_FRACTION",
    "SMOOTH_SHARE",
    "contact_window",
    "path_rests",
    "rest_clock",
    "rest_windows",
    "smoothed",
]

#: Groups that do not count towards a path's progress
#: (:func:`~ndlfd.learner._conditioning.progress`): quaternions, a velocity
#: derived from the position, a gripper.
NO_PROGRESS = ("orientation", "velocity", *DISCRETE_GROUPS)


#: A path is *slow* where its speed is below this fraction of its typical
#: speed while moving: where the demonstrations slow down for a contact (a
#: grasp, a placement) the offset to a requested start must be gone.
SLOW_FRACTION = 0.2

#: Speeds below this fraction of the path's 95th-percentile speed are rest
#: (noise, or a robot waiting before and after its motion), not motion.
REST_FRACTION = 0.1


#: Half-width of the moving average the speeds of :func:`contact_window` and
#: the lengths of :func:`~ndlfd.learner._conditioning.progress` are measured
#: on, as a share of the rows:
#: noise as large as the motion's steps (a robot at rest, sampled fast) is
#: neither motion nor a stop.
SMOOTH_SHARE = 0.01


def smoothed(P: np.ndarray) -> np.ndarray:
    """``P`` averaged over :data:`SMOOTH_SHARE` of its rows each side (at least 1)."""
    return moving_average(P, max(1, round(SMOOTH_SHARE * P.shape[0])))


def _slow_steps(P: np.ndarray, tq: np.ndarray):
    """The steps slower than :data:`SLOW_FRACTION` of the typical speed, and the moving.

    Speeds are measured on the path's moving average (:func:`smoothed`),
    scaled by its largest magnitude (steps of 1e300 square to inf). The
    typical speed is the median of the speeds while moving (at least
    :data:`REST_FRACTION` of the 95th-percentile speed: a robot that rests
    longer than it moves has a median speed of its noise at rest, and any
    sample would be slow). Step ``i`` goes from row ``i`` to row ``i + 1``.

    Returns
    -------
    slow, moving : ndarray of bool of shape (n_samples - 1,), or None
        ``None`` for fewer than 3 samples or a path that does not move.
    """
    if P.shape[0] < 3:
        return None
    dt = np.diff(tq)
    big = float(np.abs(P).max())
    steps = np.diff(smoothed(P / big if big > 0 else P), axis=0)
    speed = np.linalg.norm(steps, axis=1) / np.where(dt > 0, dt, np.inf)
    fast = float(np.quantile(speed, 0.95)) if np.isfinite(speed).all() else 0.0
    moving_speeds = speed[speed >= REST_FRACTION * fast]
    typical = float(np.median(moving_speeds)) if moving_speeds.size else 0.0
    if not typical > 0:
        return None
    return speed < SLOW_FRACTION * typical, speed >= typical


def contact_window(P: np.ndarray, tq: np.ndarray) -> tuple[float, float]:
    """Normalized times of the path's first and last slow-down while moving.

    Speeds are measured on the path's moving average (:func:`smoothed`). The
    path's typical speed is the median of its speeds while it moves (at
    least :data:`REST_FRACTION` of its 95th-percentile speed: a robot at rest
    before and after the motion does not count). The first: after the path
    first moves at that typical speed or faster, the
    first sample slower than :data:`SLOW_FRACTION` of it (a stop for a contact
    event); the last: the same from the end backwards. A path that never slows
    down between its ends gives ``(1, 0)``: the whole motion.

    Parameters
    ----------
    P : ndarray of shape (n_samples, n_dims)
        Positions along the path (any units).
    tq : ndarray of shape (n_samples,)
        Their normalized times, increasing.

    Returns
    -------
    first, last : float

    Examples
    --------
    Moving, a stop at tau = 0.5, moving again:

    >>> tq = np.linspace(0.0, 1.0, 21)
    >>> x = np.concatenate([np.arange(8.0), np.full(5, 8.0), np.arange(9.0, 17.0)])
    >>> [round(v, 9) for v in contact_window(x[:, None], tq)]
    [0.45, 0.55]
    """
    steps = _slow_steps(P, tq)
    if steps is None:
        return 1.0, 0.0
    slow, moving = steps
    first, last = 1.0, 0.0
    go = np.flatnonzero(moving)
    after = np.flatnonzero(slow[go[0] :]) if go.size else np.zeros(0, int)
    if after.size:
        first = float(tq[go[0] + after[0]])  # the step into the stop
    before = np.flatnonzero(slow[: go[-1] + 1]) if go.size else np.zeros(0, int)
    if before.size:
        last = float(tq[before[-1] + 1])  # the step out of the stop
    return first, last


def rest_windows(P: np.ndarray, tq: np.ndarray) -> np.ndarray:
    """Normalized times where the path holds still between moves: its rests.

    The runs of slow steps (as for :func:`contact_window`: slower than
    :data:`SLOW_FRACTION` of the typical speed while moving) that lie
    between two steps at the typical speed or faster: a grasp, a press, a
    pause, and the brief stop at a way point. The rest before the motion and
    after it are not among them.

    Parameters
    ----------
    P : ndarray of shape (n_samples, n_dims)
        Positions along the path (any units, comparable across columns).
    tq : ndarray of shape (n_samples,)
        Their normalized times, increasing.

    Returns
    -------
    windows : ndarray of shape (n_rests, 2)
        Each rest's first and last row's time, in time order.

    Examples
    --------
    Moving, a stop at tau = 0.5, moving again:

    >>> tq = np.linspace(0.0, 1.0, 21)
    >>> x = np.concatenate([np.arange(8.0), np.full(5, 8.0), np.arange(9.0, 17.0)])
    >>> rest_windows(x[:, None], tq).round(9)
    array([[0.45, 0.55]])
    """
    steps = _slow_steps(P, tq)
    if steps is None or not steps[1].any():
        return np.zeros((0, 2))
    slow, moving = steps
    go = np.flatnonzero(moving)
    inside = slow.copy()
    inside[: go[0]] = False
    inside[go[-1] :] = False
    edges = np.diff(np.concatenate([[0], inside.astype(np.int8), [0]]))
    i0, i1 = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return np.column_stack([tq[i0], tq[i1]]).astype(np.float64)


#: The pace of :func:`rest_clock` within a rest, against 1 while moving:
#: an offset faded across a rest changes there by this share of its pace
#: elsewhere, and over a span that is all rest it fades by time.
REST_PACE = 1e-3


def rest_clock(at: np.ndarray, windows: np.ndarray) -> np.ndarray:
    """A clock that almost stops in the rests: time spent moving.

    ``at`` less the time spent in the ``windows`` before it, times ``1 -``
    :data:`REST_PACE`. A ramp run on it (an offset faded between via points,
    a start's offset pinned) holds still where the path does.

    Parameters
    ----------
    at : ndarray of shape (n_rows,)
        Normalized times.
    windows : ndarray of shape (n_rests, 2)
        From :func:`rest_windows`.

    Returns
    -------
    clock : ndarray of shape (n_rows,)
        Non-decreasing in ``at``, increasing strictly.

    Examples
    --------
    >>> rest_clock(np.array([0.0, 0.4, 0.5, 0.6, 1.0]), np.array([[0.4, 0.6]]))
    array([0.    , 0.4   , 0.4001, 0.4002, 0.8002])
    """
    at = np.asarray(at, dtype=np.float64)
    out = at.copy()
    for a, b in np.asarray(windows, dtype=np.float64).reshape(-1, 2):
        out -= (1.0 - REST_PACE) * np.clip(at - a, 0.0, b - a)
    return out


def path_rests(X, tq, column_groups) -> np.ndarray:
    """The rests (:func:`rest_windows`) of a path, on the columns that progress.

    Every group but :data:`NO_PROGRESS` (a position, joints), each column
    scaled by its range over the path, as
    :func:`~ndlfd.learner._conditioning.progress` measures them: a hand that
    holds still while its gripper closes rests.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_columns)
        The path in time order.
    tq : ndarray of shape (n_samples,)
        Normalized times, increasing.
    column_groups : sequence of str

    Returns
    -------
    windows : ndarray of shape (n_rests, 2)

    Examples
    --------
    >>> tq = np.linspace(0.0, 1.0, 21)
    >>> x = np.concatenate([np.arange(8.0), np.full(5, 8.0), np.arange(9.0, 17.0)])
    >>> grip = (tq > 0.5).astype(float)  # closes during the rest
    >>> path_rests(np.column_stack([x, grip]), tq, ("position", "gripper")).round(9)
    array([[0.45, 0.55]])
    """
    cols = [c for c, g in enumerate(column_groups) if g not in NO_PROGRESS]
    if not cols:
        return np.zeros((0, 2))
    P = X[:, cols]
    span = np.ptp(P, axis=0)
    return rest_windows(P / np.where(span > 0, span, 1.0), tq)
