"""The curve a controller follows through a sampled path, at rest at its ends.

A ``joint_trajectory_controller`` (ros2_control) interpolates between a
JointTrajectory's points: a quintic Hermite polynomial through positions,
velocities and accelerations when all three are given, a cubic one through
positions and velocities. For it to stay on the positions, the velocities
and accelerations must be the derivatives of one curve through them. Here
that curve is the cubic spline through the positions (twice continuously
differentiable): both Hermite forms reproduce each of its pieces exactly (a
cubic is its own cubic and quintic Hermite interpolant), so the controller
follows it and nothing else.

At rest means the positions themselves stop: :func:`come_to_rest` re-times a
path whose ends still move, easing its clock from the path's pace to 0 (a
minimum-jerk ramp of the pace, :data:`EASE_SHARE` of the route's time at
least, longer where that would decelerate harder than the path's own peak),
along the same route. The spline is then clamped to velocity 0 there
(:func:`rest_curve`). A continuation of an executed prefix (``moving_start``)
leaves its first point at the path's own velocity.
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import CubicSpline

__all__ = [
    "EASE_SHARE",
    "REST",
    "come_to_rest",
    "curve_peaks",
    "rest_curve",
    "rest_points",
]

#: An end whose velocity is at most this share of the path's peak is at rest.
REST = 1e-3
#: The least share of the path's duration over which a moving end is eased
#: to rest (the clock covers half of it: the route's last 5 %).
EASE_SHARE = 0.1
#: The largest slope of the minimum-jerk ramp ``10 x^3 - 15 x^4 + 6 x^5``.
_RAMP_SLOPE = 1.875


def _end_velocity(t, X, end: int) -> np.ndarray:
    return CubicSpline(t, X, axis=0)(t[end], 1)


def _at_rest(t, X, end: int) -> bool:
    V = CubicSpline(t, X, axis=0)(t, 1)
    peak = np.abs(V).max(axis=0)
    return bool(np.all(np.abs(V[end]) <= REST * np.maximum(peak, 1e-300)))


def rest_curve(t, X, *, moving_start: bool = False) -> CubicSpline:
    """The cubic spline through the samples, at rest (velocity 0) at the ends.

    Parameters
    ----------
    t : ndarray of shape (n,)
        Increasing times, ``n >= 2``.
    X : ndarray of shape (n, k)
    moving_start : bool, default=False
        The first point moves: its velocity the spline's own there
        (not-a-knot), not 0.

    Returns
    -------
    curve : scipy.interpolate.CubicSpline
        ``curve(t, 1)``, ``curve(t, 2)``: the velocities and accelerations.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 5)
    >>> c = rest_curve(t, (3 * t**2 - 2 * t**3)[:, None])  # a smooth step
    >>> np.round(c(t, 1)[:, 0], 6).tolist()
    [0.0, 1.125, 1.5, 1.125, 0.0]
    """
    t = np.asarray(t, dtype=np.float64)
    X = np.asarray(X, dtype=np.float64)
    if t.size == 2 and moving_start:
        return CubicSpline(t, X, axis=0, bc_type=((2, np.zeros(X.shape[1])), "clamped"))
    start = "not-a-knot" if moving_start else "clamped"
    if t.size < 4 and moving_start:
        start = (2, np.zeros(X.shape[1]))  # not-a-knot needs four points
    return CubicSpline(t, X, axis=0, bc_type=(start, "clamped"))


def _ease(x: np.ndarray) -> np.ndarray:
    """The clock covered at ``x`` in [0, 1] of a ramp of the pace from 1 to 0.

    ``x - (2.5 x^4 - 3 x^5 + x^6)``: the integral of ``1 - (10 x^3 - 15 x^4 +
    6 x^5)``; half of the ramp's time at its end.
    """
    return x - (2.5 * x**4 - 3.0 * x**5 + x**6)


def come_to_rest(t, X, *, moving_start: bool = False, ease=None, held=None):
    """The path re-timed so that its positions come to rest at the ends.

    An end already at rest (its velocity at most :data:`REST` times the
    path's peak, per column) is kept. A moving end is eased: over ``L``
    seconds the clock's pace falls from 1 to 0 along a minimum-jerk ramp
    (covering ``L / 2`` of the path's time), ``L`` at least
    :data:`EASE_SHARE` of the duration and long enough that the easing's
    own deceleration of no column exceeds the path's peak acceleration (or
    what stops its top speed in that share, if more); the path's own
    acceleration, scaled by the slower pace, comes on top. The
    samples keep the path's step (its median), the last one at the end.

    Parameters
    ----------
    t : ndarray of shape (n,)
    X : ndarray of shape (n, k)
    moving_start : bool, default=False
        The first point is left moving (only the last end is eased).
    ease : float, optional
        The least seconds over which a moving end is eased (default
        :data:`EASE_SHARE` of the duration).
    held : ndarray of bool of shape (k,), optional
        Columns that switch between values (a gripper): held from the sample
        at or before each new clock, not splined, and not judged for rest.

    Returns
    -------
    t, X : ndarray of shape (m,), (m, k)
        ``t`` from the first stamp; unchanged when both ends are at rest.

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 101)
    >>> t2, X2 = come_to_rest(t, t[:, None])  # a line at 1 /s: both ends moving
    >>> X2[[0, -1], 0].tolist(), round(float(t2[-1]), 2)
    ([0.0, 1.0], 1.1)
    >>> bool(X2[1, 0] - X2[0, 0] < 1e-4)  # the positions stop: 1e-2 a step before
    True
    """
    t = np.asarray(t, dtype=np.float64)
    X = np.asarray(X, dtype=np.float64)
    held = np.zeros(X.shape[1], bool) if held is None else np.asarray(held, bool)
    smooth = ~held
    ends = [end for end in ((-1,) if moving_start else (0, -1))
            if t.size >= 3 and smooth.any()
            and not _at_rest(t, X[:, smooth], end)]  # fmt: skip
    if not ends:
        return t, X
    curve = CubicSpline(t, X[:, smooth], axis=0)
    span = float(t[-1] - t[0])
    least = EASE_SHARE * span if ease is None else float(ease)
    step = float(np.median(np.diff(t)))
    # the path's own peak acceleration, or what stops its top speed within
    # EASE_SHARE of its duration (a line at constant speed has none)
    top = np.abs(curve(t, 1)).max(axis=0)
    acc = np.maximum(
        np.abs(curve(t, 2)).max(axis=0),
        _RAMP_SLOPE * top / max(least, EASE_SHARE * span),
    )
    lengths = {}
    for end in ends:
        v = np.abs(curve(t[end], 1))
        with np.errstate(divide="ignore", invalid="ignore"):
            need = np.where(v > 0, _RAMP_SLOPE * v / np.maximum(acc, 1e-300), 0.0)
        # at most the whole path's time for each end
        lengths[end] = min(max(least, float(need.max())), span)
    head = lengths.get(0, 0.0)
    tail = lengths.get(-1, 0.0)
    total = span + 0.5 * (head + tail)
    n = max(int(np.ceil(total / step - 1e-9)), 2)
    tail += 2.0 * (n * step - total)  # the end on a whole step
    tau = np.arange(n + 1) * step
    tau[-1] = n * step
    s = tau - 0.5 * head  # the path's time since its start, eased below
    if head:
        x = np.clip(tau / head, 0.0, 1.0)
        s = np.where(tau < head, head * (0.5 - _ease(1.0 - x)), s)
    if tail:
        t0 = tau[-1] - tail
        x = np.clip((tau - t0) / tail, 0.0, 1.0)
        s = np.where(tau > t0, (t0 - 0.5 * head) + tail * _ease(x), s)
    s = np.clip(s, 0.0, span)
    s[0], s[-1] = 0.0, span
    out = np.empty((s.size, X.shape[1]))
    out[:, smooth] = curve(t[0] + s)
    before = np.searchsorted(t - t[0], s, side="right") - 1
    out[:, held] = X[np.clip(before, 0, t.size - 1)][:, held]
    out[[0, -1]] = X[[0, -1]]
    return t[0] + tau, out


def rest_points(t, X, *, moving_start: bool = False, ease=None, held=None):
    """The points a controller is sent: come to rest, with the curve's derivatives.

    :func:`come_to_rest`, then the velocities and accelerations of
    :func:`rest_curve` through the result at its samples (0 for ``held``
    columns), the velocity at a rest end exactly 0.

    Parameters
    ----------
    t : ndarray of shape (n,)
        Increasing times, ``n >= 2``.
    X : ndarray of shape (n, k)
    moving_start, ease, held
        As for :func:`come_to_rest`.

    Returns
    -------
    t, X, V, A : ndarray of shape (m,), and (m, k) each

    Examples
    --------
    >>> t = np.linspace(0.0, 1.0, 101)
    >>> t2, X2, V, A = rest_points(t, t[:, None])  # a line at 1 /s, eased
    >>> t2.size, V[[0, -1], 0].tolist(), round(float(V[:, 0].max()), 2)
    (111, [0.0, 0.0], 1.0)
    """
    held = None if held is None else np.asarray(held, bool)
    t, X = come_to_rest(t, X, moving_start=moving_start, ease=ease, held=held)
    smooth = np.ones(X.shape[1], bool) if held is None else ~held
    V, A = np.zeros_like(X), np.zeros_like(X)
    if smooth.any():
        curve = rest_curve(t, X[:, smooth], moving_start=moving_start)
        V[:, smooth], A[:, smooth] = curve(t, 1), curve(t, 2)
    V[[-1] if moving_start else [0, -1]] = 0.0  # exactly, not up to rounding
    return t, X, V, A


def curve_peaks(curve: CubicSpline, t: np.ndarray, per_step: int = 8):
    """The largest velocity and acceleration of ``curve`` over ``t``, per column.

    On the samples and ``per_step - 1`` points between each two (a cubic
    spline's acceleration is linear between its knots: its extremes are at
    them; its velocity may peak between).

    Returns
    -------
    velocity, acceleration : ndarray of shape (k,)
    """
    u = np.linspace(0.0, 1.0, per_step + 1)[:-1]
    fine = np.append((t[:-1, None] + np.diff(t)[:, None] * u).ravel(), t[-1])
    return np.abs(curve(fine, 1)).max(axis=0), np.abs(curve(t, 2)).max(axis=0)
