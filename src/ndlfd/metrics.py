"""How close a generated path is to a demonstration, and the simplest baseline.

Distances between two paths (DTW, discrete Fréchet, time-aligned RMSE, endpoint
error) take paths of shape ``(n, d)`` and ``(k, d)`` (the same ``d``) and compare
them with the Euclidean distance between points; their dynamic programmes run
in ``O(n k)`` time and ``O(k)`` memory in a compiled kernel. Smoothness is
compared by ratios of the generated path's arc length and total turning to the
reference's (:func:`path_length_ratio`, :func:`turning_ratio`).
:func:`mean_demo_baseline` is the time-aligned mean of demonstrations and
:func:`path_errors` the error summary the built-in jobs print.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from ._errors import ValidationError
from ._validation import (
    check_nonnegative_scalar,
    check_points,
    check_positive_int,
    check_times,
)
from .demonstration import unit_time

if TYPE_CHECKING:  # pragma: no cover
    from .demonstration import Demonstration

__all__ = [
    "discrete_frechet",
    "dtw_distance",
    "endpoint_error",
    "envelope_ratios",
    "mean_demo_baseline",
    "path_difference",
    "path_errors",
    "path_length",
    "path_length_ratio",
    "phase_envelope",
    "time_aligned_rmse",
    "total_turning",
    "turning_ratio",
]


def _pair(a, b) -> tuple[np.ndarray, np.ndarray]:
    A = check_points(a, "a")
    B = check_points(b, "b")
    if A.shape[1] != B.shape[1]:
        raise ValidationError(
            f"a and b must have the same number of columns; got {A.shape[1]} and"
            f" {B.shape[1]}"
        )
    return A, B


@njit(cache=True, nogil=True)
def _dtw_kernel(A, B):  # pragma: no cover - compiled
    n, k = A.shape[0], B.shape[0]
    prev = np.full(k + 1, np.inf)
    cur = np.full(k + 1, np.inf)
    prev[0] = 0.0
    for i in range(1, n + 1):
        cur[0] = np.inf
        for j in range(1, k + 1):
            s = 0.0
            for c in range(A.shape[1]):
                diff = A[i - 1, c] - B[j - 1, c]
                s += diff * diff
            best = prev[j - 1]
            if prev[j] < best:
                best = prev[j]
            if cur[j - 1] < best:
                best = cur[j - 1]
            cur[j] = np.sqrt(s) + best
        prev, cur = cur, prev
    return prev[k]


@njit(cache=True, nogil=True)
def _frechet_kernel(A, B):  # pragma: no cover - compiled
    n, k = A.shape[0], B.shape[0]
    prev = np.empty(k)
    cur = np.empty(k)
    for i in range(n):
        for j in range(k):
            s = 0.0
            for c in range(A.shape[1]):
                diff = A[i, c] - B[j, c]
                s += diff * diff
            d = np.sqrt(s)
            if i == 0 and j == 0:
                best = d
            elif i == 0:
                best = cur[j - 1]
            elif j == 0:
                best = prev[0]
            else:
                best = min(prev[j], prev[j - 1], cur[j - 1])
            cur[j] = max(best, d)
        prev, cur = cur, prev
    return prev[k - 1]


def dtw_distance(a, b, *, normalize: bool = False) -> float:
    """Dynamic time warping distance between two paths.

    The sum of Euclidean point distances along the cheapest monotone alignment
    (steps ``(1, 0)``, ``(0, 1)`` and ``(1, 1)``).

    Parameters
    ----------
    a : array-like of shape (n_a, n_dims)
        First path.
    b : array-like of shape (n_b, n_dims)
        Second path.
    normalize : bool, default=False
        Divide by ``n_a + n_b``, the number of points of both paths, so paths
        sampled at different rates compare fairly. This is not the length of
        the warping path (which lies between ``max(n_a, n_b)`` and
        ``n_a + n_b - 1``): two paths of ``n`` points that align one to one
        give half their mean point distance.

    Returns
    -------
    distance : float

    Examples
    --------
    >>> dtw_distance([[0, 0], [1, 0], [2, 0]], [[0, 0], [2, 0]])
    1.0

    Three point pairs, each 1 apart, sum to 3; normalized by 3 + 3 points:

    >>> dtw_distance([[0, 0], [1, 0], [2, 0]], [[0, 1], [1, 1], [2, 1]], normalize=True)
    0.5
    """
    A, B = _pair(a, b)
    d = float(_dtw_kernel(A, B))
    return d / (A.shape[0] + B.shape[0]) if normalize else d


def discrete_frechet(a, b) -> float:
    """Discrete Fréchet distance between two paths (Eiter & Mannila, 1994).

    Parameters
    ----------
    a : array-like of shape (n_a, n_dims)
        First path.
    b : array-like of shape (n_b, n_dims)
        Second path.

    Returns
    -------
    distance : float
        The smallest, over monotone couplings of the two point sequences, of the
        largest distance between coupled points.

    Examples
    --------
    >>> discrete_frechet([[0, 0], [1, 0], [2, 0]], [[0, 1], [2, 1]])
    1.4142135623730951
    """
    A, B = _pair(a, b)
    return float(_frechet_kernel(A, B))


def time_aligned_rmse(t_a, a, t_b, b) -> float:
    """Root-mean-square error of ``b`` against ``a`` at ``a``'s normalized times.

    Both time vectors are mapped to ``[0, 1]`` (first to last sample), ``b`` is
    linearly interpolated at ``a``'s normalized times, and the RMS of the
    Euclidean point errors is returned.

    Parameters
    ----------
    t_a : array-like of shape (n_a,)
        Time stamps of ``a`` (strictly increasing).
    a : array-like of shape (n_a, n_dims)
        The reference path.
    t_b : array-like of shape (n_b,)
        Time stamps of ``b`` (strictly increasing).
    b : array-like of shape (n_b, n_dims)
        The path to evaluate.

    Returns
    -------
    rmse : float

    Examples
    --------
    >>> time_aligned_rmse([0, 1, 2], [[0.0], [1.0], [2.0]], [0, 4], [[1.0], [3.0]])
    1.0
    """
    A, B = _pair(a, b)
    ta = unit_time(check_times(t_a, A.shape[0], "t_a"))
    tb = unit_time(check_times(t_b, B.shape[0], "t_b"))
    Bi = np.column_stack([np.interp(ta, tb, B[:, c]) for c in range(B.shape[1])])
    return float(np.sqrt(np.mean(np.sum((Bi - A) ** 2, axis=1))))


def endpoint_error(a, b) -> float:
    """Euclidean distance between the last points of two paths.

    Parameters
    ----------
    a : array-like of shape (n_a, n_dims)
        First path.
    b : array-like of shape (n_b, n_dims)
        Second path.

    Returns
    -------
    error : float

    Examples
    --------
    >>> endpoint_error([[0, 0], [3, 4]], [[9, 9], [0, 0]])
    5.0
    """
    A, B = _pair(a, b)
    return float(np.linalg.norm(A[-1] - B[-1]))


def path_difference(t_a, a, t_b, b, *, scale=None) -> float:
    """Difference between two paths in percent of a scale (ndlfd's "difference %").

    The paper (Fig. 6) reports a "difference" between generated paths without
    defining it. ndlfd defines it as ``100 * time_aligned_rmse(a, b) / scale``,
    where ``scale`` defaults to the diagonal of ``a``'s bounding box (the length
    of the vector of per-column ranges), so the number reads as "the paths are
    on average this many percent of the motion's extent apart".

    Parameters
    ----------
    t_a, a, t_b, b
        As in :func:`time_aligned_rmse`.
    scale : float, optional
        The length that counts as 100 %.

    Returns
    -------
    difference : float
        In percent.

    Examples
    --------
    >>> path_difference([0, 1], [[0.0, 0.0], [3.0, 4.0]], [0, 1], [[0.5, 0], [3.5, 4]])
    10.0
    """
    A = check_points(a, "a")
    if scale is None:
        scale = float(np.linalg.norm(A.max(axis=0) - A.min(axis=0)))
    if not np.isfinite(scale) or scale <= 0:
        raise ValidationError(
            f"scale must be a finite number > 0; got {scale!r} (a path that does"
            " not move needs an explicit scale)"
        )
    return 100.0 * time_aligned_rmse(t_a, A, t_b, b) / scale


def path_length(path) -> float:
    """Arc length of a polyline: the sum of its segment lengths.

    Parameters
    ----------
    path : array-like of shape (n_points, n_dims)

    Returns
    -------
    length : float
        0 for a single point.

    Examples
    --------
    >>> path_length([[0, 0], [3, 4], [3, 5]])
    6.0
    """
    P = check_points(path, "path")
    return float(np.linalg.norm(np.diff(P, axis=0), axis=1).sum())


def total_turning(path, *, min_segment: float = 0.0) -> float:
    """Total absolute turning angle of a polyline, in radians.

    The sum, over consecutive segments, of the unsigned angle between their
    direction vectors (in any number of dimensions). Segments not longer than
    ``min_segment`` (by default only segments of length zero, i.e. repeated
    points) have no direction and are skipped: the angle is taken between the
    segments on either side of them. A polyline with fewer than two segments
    left turns by 0.

    The angle between unit vectors ``u`` and ``v`` is computed as
    ``2 * atan2(|u - v|, |u + v|)``, accurate for nearly parallel and nearly
    opposite directions alike (a reversal counts as ``pi``).

    Parameters
    ----------
    path : array-like of shape (n_points, n_dims)
    min_segment : float, default=0.0
        Segments of this length or shorter are skipped.

    Returns
    -------
    turning : float
        In ``[0, pi * (n_points - 2)]``.

    Examples
    --------
    Two right-angle turns (the repeated point is skipped):

    >>> total_turning([[0, 0], [1, 0], [1, 0], [1, 1], [0, 1]])
    3.141592653589793
    """
    P = check_points(path, "path")
    tol = check_nonnegative_scalar(min_segment, "min_segment")
    seg = np.diff(P, axis=0)
    length = np.linalg.norm(seg, axis=1)
    keep = length > tol
    if np.count_nonzero(keep) < 2:
        return 0.0
    U = seg[keep] / length[keep, None]
    a, b = U[:-1], U[1:]
    angles = 2.0 * np.arctan2(
        np.linalg.norm(a - b, axis=1), np.linalg.norm(a + b, axis=1)
    )
    return float(angles.sum())


def _ratio(num: float, den: float) -> float:
    if den > 0:
        return num / den
    return 1.0 if num == 0 else float("inf")


def path_length_ratio(test, generated) -> float:
    """Arc length of ``generated`` divided by the arc length of ``test``.

    1 means as long as the reference; above 1 the generated path is longer
    (detours, jitter), below 1 it cuts corners or stops short.

    Parameters
    ----------
    test : array-like of shape (n_test, n_dims)
        The reference path (e.g. a held-out demonstration).
    generated : array-like of shape (n_generated, n_dims)
        The path to evaluate.

    Returns
    -------
    ratio : float
        ``path_length(generated) / path_length(test)``; when ``test`` does not
        move, 1.0 if ``generated`` does not either, else ``inf``.

    Examples
    --------
    >>> path_length_ratio([[0, 0], [1, 0]], [[0, 0], [0, 1], [1, 1]])
    2.0
    """
    A, B = _pair(test, generated)
    return _ratio(path_length(B), path_length(A))


def turning_ratio(test, generated, *, min_segment: float = 0.0) -> float:
    """Total turning of ``generated`` divided by that of ``test``.

    A smoothness ratio: a jittery or zig-zagging path turns far more than the
    demonstration (ratio above 1), an over-smoothed one less. See
    :func:`total_turning` for the definition (unsigned angles between
    consecutive non-degenerate segments, in any dimension).

    Parameters
    ----------
    test : array-like of shape (n_test, n_dims)
        The reference path.
    generated : array-like of shape (n_generated, n_dims)
        The path to evaluate.
    min_segment : float, default=0.0
        Passed to :func:`total_turning` for both paths.

    Returns
    -------
    ratio : float
        ``total_turning(generated) / total_turning(test)``; when ``test`` is
        straight, 1.0 if ``generated`` is straight too, else ``inf``.

    Examples
    --------
    One right angle against two:

    >>> turning_ratio([[0, 0], [1, 0], [1, 1]], [[0, 0], [1, 0], [1, 1], [0, 1]])
    2.0
    """
    A, B = _pair(test, generated)
    return _ratio(
        total_turning(B, min_segment=min_segment),
        total_turning(A, min_segment=min_segment),
    )


def _unit_times(demo) -> np.ndarray:
    return unit_time(np.asarray(demo.t, dtype=float))


def mean_demo_baseline(demos, times, group: str = "position") -> np.ndarray:
    """The simplest learner: the average of the demonstrations on normalized time.

    ``times`` and every demonstration's time stamps are mapped to ``[0, 1]``
    (first to last sample); each demonstration's ``group`` values are
    interpolated linearly at the normalized ``times`` and averaged.

    Parameters
    ----------
    demos : sequence of Demonstration
        Training demonstrations (at least one).
    times : array-like of shape (n_samples,)
        Time stamps where the baseline is evaluated (strictly increasing).
    group : str, default="position"
        The group to average.

    Returns
    -------
    values : ndarray of shape (n_samples, n_group_columns)

    Examples
    --------
    >>> from ndlfd import Demonstration
    >>> a = Demonstration.from_arrays([0, 1], position=[[0, 0], [2, 2]])
    >>> b = Demonstration.from_arrays([0, 2], position=[[2, 0], [4, 2]])
    >>> mean_demo_baseline([a, b], [10, 15, 20])
    array([[1., 0.],
           [2., 1.],
           [3., 2.]])
    """
    demos = list(demos)
    if not demos:
        raise ValidationError("mean_demo_baseline needs at least one demonstration")
    tau = unit_time(check_times(times, name="times"))
    acc = None
    for d in demos:
        s = _unit_times(d)
        V = d.get(group)
        Vi = np.column_stack([np.interp(tau, s, V[:, c]) for c in range(V.shape[1])])
        acc = Vi if acc is None else acc + Vi
    return acc / len(demos)


def path_errors(
    test: Demonstration, path: Demonstration, group: str = "position"
) -> dict:
    """Difference %, mean DTW and discrete Fréchet of ``path`` to ``test``.

    Parameters
    ----------
    test : Demonstration
        The reference demonstration.
    path : Demonstration
        The path to evaluate.
    group : str, default="position"
        The group compared.

    Returns
    -------
    errors : dict
        ``difference_pct`` (:func:`path_difference`), ``dtw_mean``
        (:func:`dtw_distance` with ``normalize=True``: divided by the number of
        points of both paths) and ``frechet`` (:func:`discrete_frechet`).

    Examples
    --------
    >>> from ndlfd import Demonstration
    >>> test = Demonstration.from_arrays([0, 1], position=[[0, 0], [3, 4]])
    >>> path = Demonstration.from_arrays([0, 1], position=[[0.3, 0.4], [3.3, 4.4]])
    >>> {k: round(v, 6) for k, v in path_errors(test, path).items()}
    {'difference_pct': 10.0, 'dtw_mean': 0.25, 'frechet': 0.5}
    """
    a, b = test.get(group), path.get(group)
    return {
        "difference_pct": path_difference(test.t, a, path.t, b),
        "dtw_mean": dtw_distance(a, b, normalize=True),
        "frechet": discrete_frechet(a, b),
    }


def _phase_motion(t, P) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Phase, speed and acceleration magnitude over normalized time."""
    tau = unit_time(t)
    V = np.gradient(P, tau, axis=0, edge_order=2 if P.shape[0] > 2 else 1)
    A = np.gradient(V, tau, axis=0, edge_order=2 if P.shape[0] > 2 else 1)
    return tau, np.linalg.norm(V, axis=1), np.linalg.norm(A, axis=1)


def _bins(tau, n_bins: int) -> np.ndarray:
    return np.minimum((tau * n_bins).astype(np.int64), n_bins - 1)


def phase_envelope(
    demos, group: str = "position", *, n_bins: int = 50, quantile: float = 0.95
) -> tuple[np.ndarray, np.ndarray]:
    """How fast the demonstrations move at each phase: the envelope of their motion.

    Each demonstration's speed and acceleration (the norms of the group's
    first and second derivatives over normalized time, ``numpy.gradient``, so
    that demonstrations of different durations compare) is reduced to its
    largest value in each of ``n_bins`` equal phase bins; the envelope of a
    bin is the ``quantile`` of those over the demonstrations, widened to the
    largest of the bin and its two neighbours (a phase shift of one bin is
    not a violation).

    Parameters
    ----------
    demos : sequence of Demonstration
    group : str, default="position"
    n_bins : int, default=50
    quantile : float, default=0.95

    Returns
    -------
    speed, acceleration : ndarray of shape (n_bins,)
        Per unit normalized time (squared).

    Examples
    --------
    >>> from ndlfd import Demonstration
    >>> t = np.linspace(0.0, 2.0, 101)
    >>> d = Demonstration.from_arrays(t, position=np.column_stack([3 * t / 2, 0 * t]))
    >>> speed, acc = phase_envelope([d], n_bins=4)
    >>> speed.round(6).tolist(), acc.round(6).tolist()
    ([3.0, 3.0, 3.0, 3.0], [0.0, 0.0, 0.0, 0.0])
    """
    if not demos:
        raise ValidationError("phase_envelope needs at least one demonstration")
    per = np.full((len(demos), 2, n_bins), np.nan)
    for i, d in enumerate(demos):
        tau, v, a = _phase_motion(d.t, d.get(group))
        b = _bins(tau, n_bins)
        for k, x in enumerate((v, a)):
            top = np.full(n_bins, -np.inf)
            np.maximum.at(top, b, x)
            per[i, k] = np.where(np.isfinite(top), top, np.nan)
    env = np.nanquantile(per, quantile, axis=0)  # (2, n_bins)
    env = np.nan_to_num(env, nan=0.0)
    padded = np.pad(env, ((0, 0), (1, 1)), mode="edge")
    env = np.maximum(np.maximum(padded[:, :-2], padded[:, 1:-1]), padded[:, 2:])
    return env[0], env[1]


def envelope_ratios(
    path, envelope, group: str = "position", *, since: int = 0
) -> tuple[float, float]:
    """The largest ratio of a path's speed and acceleration to an envelope.

    Parameters
    ----------
    path : Demonstration
    envelope : tuple of ndarray
        :func:`phase_envelope` of the demonstrations.
    group : str, default="position"
    since : int, default=0
        The first sample counted: the samples before it (an observed prefix,
        say, with ``since`` its last sample, so the step into the generated
        rest counts) are only read for the derivatives from ``since`` on.

    Returns
    -------
    speed, acceleration : float
        The largest of the path's value over the envelope's at its phase
        (values below a billionth of the envelope's top speed count as 0);
        at most 1 is within the envelope.

    Examples
    --------
    >>> from ndlfd import Demonstration
    >>> t = np.linspace(0.0, 1.0, 101)
    >>> slow = Demonstration.from_arrays(t, position=np.column_stack([t, 0 * t]))
    >>> fast = Demonstration.from_arrays(t, position=np.column_stack([2 * t, 0 * t]))
    >>> [round(r, 6) for r in envelope_ratios(fast, phase_envelope([slow]))]
    [2.0, 0.0]
    """
    n = path.t.shape[0]
    since = check_positive_int(since, "since", minimum=0)
    if since >= n:
        raise ValidationError(
            f"since must be a sample of the path (0 to {n - 1}), got {since}"
        )
    tau, v, a = _phase_motion(path.t, path.get(group))
    tau, v, a = tau[since:], v[since:], a[since:]
    # below a billionth of the top speed (per unit phase) is rounding: a
    # straight line's acceleration of 1e-13 is no motion, whatever its envelope
    floor = 1e-9 * float(np.max(envelope[0]))
    out = []
    for x, e in zip((v, a), envelope, strict=True):
        lim = np.asarray(e, dtype=np.float64)[_bins(tau, len(e))]
        x = np.where(x > floor, x, 0.0)
        with np.errstate(divide="ignore"):
            r = np.where(x > 0, x / np.maximum(lim, floor), 0.0)
        out.append(float(r.max()))
    return out[0], out[1]
