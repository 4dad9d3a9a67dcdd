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

from ._discrete import DISCRETE_GROUPS

__all__ = [
    "HOLD_SPAN",
    "NO_PROGRESS",
    "REST_FRACTION",
    "REST_PACE",
    "SLOW_FRACTION",
    "SMOOTH_SHARE",
    "contact_window",
    "hold_knots",
    "moving_average",
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


def moving_average(U: np.ndarray, half: int) -> np.ndarray:
    """Mean of the rows ``i - half .. i + half`` (fewer at the ends) of each row.

    Examples
    --------
    >>> moving_average(np.array([[0.0], [3.0], [0.0], [3.0]]), 1)
    array([[1.5],
           [1. ],
           [2. ],
           [1.5]])
    """
    U = np.asarray(U, dtype=np.float64)
    if half <= 0:
        return U
    n = U.shape[0]
    c = np.concatenate([np.zeros((1, U.shape[1])), np.cumsum(U, axis=0)])
    i = np.arange(n)
    lo, hi = np.maximum(i - half, 0), np.minimum(i + half + 1, n)
    return (c[hi] - c[lo]) / (hi - lo)[:, None]


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


#: A rest this long (a share of the motion) or longer is a hold (a grasp, a
#: press): a via point near it in time is read at its start
#: (:func:`~ndlfd.learner._phase.via_clock`), and the templates' holds are
#: aligned in a conditioned blend (:func:`hold_knots`). Shorter rests (a
#: stop at a way point, a slow bend) take the via point only when the
#: closest pass falls in them. The grasp sets of
#: ``tests/learner/test_learner_rests.py`` hold 0.11-0.15 of the motion;
#: held-out LASA Multi_Models, protocol via, median DTW/range: 0.00369
#: before, 0.00409 with every rest taken so, 0.00368 with this bound.
HOLD_SPAN = 0.05


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


def hold_knots(U_list, tau_list, index_list, weights, knots, cols):
    """The skeleton's knots with the holds the templates share added.

    The skeleton (:func:`~ndlfd.learner._blend.blend`'s ``knots``) may have
    no key point where a grasp begins or ends; each template is then warped
    linearly across its hold, the templates rest at different phases, and
    their blend neither arrives nor leaves as any of them does: it creeps
    in the hold and lifts early (a planar arm's joints: a blended hold of
    0.36 s where every demonstration held 0.6 s or longer). So where every
    template of positive weight holds (a rest of :data:`HOLD_SPAN` or
    longer on the columns ``cols``, :func:`rest_windows`) at once on the
    skeleton (each hold of the heaviest template, and the hold of every
    other template that overlaps it most there), the holds' first and last
    rows become knots, at their weighted mean times, as the skeleton's
    own are (:func:`~ndlfd.learner._blend.skeleton_times`); knots the
    holds would cross (matched on the wrong side of a template's hold) are
    dropped. The blend then holds where the templates do, for as long as
    they do on average. 40 grasp sets (``benchmarks/probe_rests.py``),
    drift over the hold, median and largest: joints 1.11 and 65.1 mm
    without, 0.56 and 2.1 with; Cartesian 0.65 and 1.76, 0.62 and 1.64.

    Parameters
    ----------
    U_list : list of ndarray of shape (n_j, n_dims)
        The templates (normalized units).
    tau_list : list of ndarray of shape (n_j,)
        Their normalized times.
    index_list : list of ndarray of shape (n_keys,)
        Each one's samples matched to the knots.
    weights : ndarray of shape (n_templates,)
        Non-negative, not all zero.
    knots : ndarray of shape (n_keys,)
        The skeleton's times.
    cols : sequence of int
        The columns that say where the path is (a position, joints); at
        least two (a single column is slow wherever it turns, not only
        where it holds: no hold is added).

    Returns
    -------
    knots : ndarray of shape (n_knots,)
    index_list : list of ndarray of shape (n_knots,)
        The inputs, unchanged when no hold is shared.
    holds : ndarray of shape (n_holds, 2)
        The knots added, each hold's start and end.

    Examples
    --------
    Two templates rest at different times between the ends (found from 0.35
    to 0.45 and from 0.4 to 0.5: the moving average of :func:`rest_windows`
    blurs each edge by a row); the blend holds at their mean times:

    >>> tau = np.linspace(0.0, 1.0, 21)
    >>> a = np.r_[np.arange(6.0), np.full(5, 6.0), np.arange(7.0, 17.0)]
    >>> b = np.r_[np.arange(7.0), np.full(5, 7.0), np.arange(8.0, 17.0)]
    >>> U = [np.column_stack([x, -x / 2]) for x in (a, b)]  # a 2-D line
    >>> index = [np.array([0, 20])] * 2
    >>> k, idx, holds = hold_knots(U, [tau, tau], index, np.ones(2),
    ...                            np.array([0.0, 1.0]), [0, 1])
    >>> k.round(3), [i.tolist() for i in idx]
    (array([0.   , 0.375, 0.475, 1.   ]), [[0, 7, 9, 20], [0, 8, 10, 20]])
    >>> holds.round(3)
    array([[0.375, 0.475]])
    """
    w = np.asarray(weights, dtype=np.float64)
    w = w / w.sum()
    live = np.flatnonzero(w > 0)
    knots = np.asarray(knots, dtype=np.float64)
    none = np.zeros((0, 2))
    cols = list(cols)
    if len(cols) < 2 or knots.size < 2:  # one column is slow at every turn
        return knots, index_list, none
    holds = {}  # each live template's holds: rows, and times on the skeleton
    for j in live:
        U, tau = U_list[j][:, cols], tau_list[j]
        span = np.ptp(U, axis=0)
        win = rest_windows(U / np.where(span > 0, span, 1.0), tau)
        win = win[win[:, 1] - win[:, 0] >= HOLD_SPAN]
        holds[j] = (
            np.searchsorted(tau, win),
            np.interp(win, tau[index_list[j]], knots),
        )
    first = live[np.argmax(w[live])]
    added, rows = [], []
    for a, b in holds[first][1]:
        got = {}  # every template's hold that overlaps it most on the skeleton
        for j, (hr, ht) in holds.items():
            overlap = np.minimum(ht[:, 1], b) - np.maximum(ht[:, 0], a)
            if not (overlap > 0).any():
                break
            got[j] = hr[np.argmax(overlap)]
        else:
            at = sum(w[j] * tau_list[j][got[j]] for j in got)
            after = not added or added[-1][1] < at[0]  # holds one after another
            if after and knots[0] < at[0] < at[1] < knots[-1]:
                added.append(at)
                rows.append(got)
    if not added:
        return knots, index_list, none
    keep = np.ones(knots.size, dtype=bool)
    for at, got in zip(added, rows, strict=True):
        for k in range(1, knots.size - 1):  # knots the hold's would cross
            inside = at[0] <= knots[k] <= at[1]
            early = any(
                knots[k] < at[0] and index_list[j][k] > r[0] for j, r in got.items()
            )
            late = any(
                knots[k] > at[1] and index_list[j][k] < r[1] for j, r in got.items()
            )
            keep[k] &= not (inside or early or late)
    new = np.concatenate([knots[keep], np.ravel(added)])
    order = np.argsort(new, kind="stable")
    out = []
    for j, idx in enumerate(index_list):
        if j in holds:
            cand = np.concatenate([idx[keep], np.ravel([g[j] for g in rows])])
        else:  # no weight: read as before, at the new knots
            tau = tau_list[j]
            t = np.interp(new, knots, tau[idx])
            cand = np.clip(np.searchsorted(tau, t), 0, tau.size - 1)
        out.append(cand[order].astype(np.int64))
    if any((np.diff(i) < 0).any() for i in out) or (np.diff(new[order]) <= 0).any():
        return knots, index_list, none  # holds matched across each other: as was
    return new[order], out, np.array(added, dtype=np.float64)
