"""The default generation: decode a skeleton, align the demonstrations to it, blend.

Three steps, each exact and cheap:

1. **Segment model.** While a training demonstration runs from one key point to
   the next it stays in the *segment* that starts at the first of them: its
   state at time bin ``b`` is the state of its last key point at or before
   ``b``. Every bin is then an observation of the segment the demonstration is
   in, so a bin without a key point is not an observation of a key-point state,
   and decoding all bins ``0..N_t-1`` with the ordinary sparse Viterbi (or the
   posterior) gives the key points *and their times* jointly: a key point is
   where the decoded state changes. No hopping between demonstrations is forced
   (each chain emits every bin).
2. **Alignment.** The decoded key points, at the centroids of the training
   values encoded to their states, are a skeleton. Each training
   demonstration is aligned to it by a monotone dynamic programme (the sample
   of the demonstration matched to each skeleton point, ends pinned, least
   total squared distance in normalized units). The distances are taken from
   a moving average of the demonstration (:data:`MATCH_WINDOW`), so a sample
   is not matched *for* its noise: matching raw samples picks, at every
   skeleton point, the ones whose noise lies towards it, and on noisy data the
   blend then spikes towards the skeleton (whose centroids are of key points,
   noise extremes themselves).
3. **Blend.** Between consecutive skeleton points every demonstration's
   matched segment is time-warped onto the skeleton's times (the weighted mean
   of the matched samples' normalized times) and the segments are averaged
   with the demonstrations' weights. The path follows the demonstrations'
   shape between key points; averaging after alignment keeps corners sharp
   where a time-aligned mean cuts them.

The segment model is in :mod:`ndlfd.learner._segments`, the conditioning on a
start or goal in :mod:`ndlfd.learner._conditioning`, and the plan that puts the
steps together in :mod:`ndlfd.learner._generation`.
"""

from __future__ import annotations

import os

import numpy as np
from numba import njit

from .._parallel import thread_pool
from ._rests import hold_knots, moving_average, rest_clock

__all__ = [
    "CONDITION_GRID",
    "CONDITION_REACH",
    "CONDITION_RIDGE",
    "CONDITION_SMOOTH",
    "MATCH_WINDOW",
    "TEMPLATE_WINDOW",
    "WARP_SMOOTH",
    "align_many",
    "align_to_skeleton",
    "blend",
    "condition_coefficients",
    "condition_offsets",
    "moving_average",
    "output_step",
    "skeleton_times",
    "smooth_warp",
    "spread",
    "warped",
    "window_half",
]


#: Half-width of the moving average the alignment matches on, as a fraction of
#: a demonstration's samples (each side). Measured (leave-one-out DTW, ratio to
#: the mean of the demonstrations): the paper's noisy square (100 training
#: demonstrations, seeds 0-2) 1.049, 1.035, 1.065 with raw samples and 1.007,
#: 0.998, 0.999 with 0.05; single LASA shapes, time only, 0.939 and 0.941 (ratio
#: of medians over 7 folds x 26 shapes): smooth data hardly notice it.
MATCH_WINDOW = 0.05

#: Observation noise of a conditioned blend (:func:`condition_offsets`), as a
#: share of the templates' mean variance at the observed values. Measured on
#: BendedLine (via, leave-one-out, median DTW/range): 0.1 overshoots (folds
#: 0.03 where ProMP has 0.01), 1 follows the held-out path, 1000 (no
#: conditioning) does not.
CONDITION_RIDGE = 1.0

#: How far (Mahalanobis distance under the templates' covariance, observation
#: noise included) an observation is followed by the conditioned blend
#: (:func:`condition_offsets`); the rest of its offset is left to the smooth
#: fade that pins it. Beyond the demonstrations' spread the templates'
#: deviations say nothing: a via point 50 spreads off the route multiplied
#: each template's noise by about 25 (on ``synth.obstacle``: steps of 3.3
#: where the demonstrations' are 0.1, speed 68 times theirs).
CONDITION_REACH = 2.0

#: Half-width, in normalized time, of the window the conditioned blend's
#: shift is averaged over (:func:`blend`; read on a grid of
#: :data:`CONDITION_GRID` phases). The shift is a combination of the
#: templates' deviations from their mean, and a template warped onto the
#: skeleton turns fast where its pace differs from the skeleton's: the mean
#: averages that out, a combination of deviations keeps it. Measured with
#: ``benchmarks/bench_envelope.py``'s via points (LASA, 1,000 samples, the
#: largest acceleration over the demonstrations' 95th percentile at each
#: phase; median and largest of 333): Angle 1.88 and 5.17 without the
#: window, 1.34 and 3.80 with 0.01, 1.04 and 3.47 with 0.02, 0.92 and 2.49
#: with 0.04, 0.90 and 2.64 with 0.06; Worm's largest 6.16, 1.96 (0.04) and
#: 1.85 (0.06). Leave-one-out LASA (median over shapes of the DTW ratio to
#: ProMP, single shapes / Multi_Models): via 0.585 / 0.658 without, 0.580 /
#: 0.657 with 0.04 (0.563 / 0.662 with 0.06); prefix 0.649 / 1.08 without,
#: 0.637 / 1.09 with 0.04.
CONDITION_SMOOTH = 0.04

#: Phases the conditioned blend's shift is computed on before it is averaged
#: (:data:`CONDITION_SMOOTH`) and read at the path's rows.
CONDITION_GRID = 201


@njit(cache=True, nogil=True)
def _align_kernel(U, C, strict):  # pragma: no cover - compiled
    n, d = U.shape
    k = C.shape[0]
    prev = np.full(n, np.inf)
    cur = np.full(n, np.inf)
    # zeros, not empty: a cost that overflowed to inf leaves no finite path,
    # and backtracking must still read indices in range (never stale memory)
    back = np.zeros((k, n), dtype=np.int32)
    s = 0.0
    for c in range(d):
        diff = U[0, c] - C[0, c]
        s += diff * diff
    prev[0] = s
    for i in range(1, k):
        best = np.inf
        arg = -1
        for p in range(n):
            # best predecessor p' < p (strict) or p' <= p; ties keep the earliest
            q = p - 1 if strict else p
            if q >= 0 and prev[q] < best:
                best = prev[q]
                arg = q
            if arg < 0:
                cur[p] = np.inf
                continue
            s = 0.0
            for c in range(d):
                diff = U[p, c] - C[i, c]
                s += diff * diff
            cur[p] = best + s
            back[i, p] = arg
        prev, cur = cur, prev
    out = np.empty(k, dtype=np.int64)
    out[k - 1] = n - 1
    for i in range(k - 1, 0, -1):
        out[i - 1] = back[i, out[i]]
    return out, prev[n - 1]


def align_many(
    U_list,
    C: np.ndarray,
    n_jobs=None,
    max_candidates: int | None = None,
    window: float = 0.0,
) -> list[np.ndarray]:
    """:func:`align_to_skeleton` for many demonstrations, on threads.

    The compiled kernel releases the GIL; the threads come from the persistent
    pool that :func:`ndlfd.simplify_many` uses.

    Parameters
    ----------
    U_list : list of ndarray of shape (n_j, n_dims)
        The demonstrations (normalized units).
    C : ndarray of shape (n_keys, n_dims)
        The skeleton points.
    n_jobs : int, optional
        Threads; ``None`` means one per CPU.
    max_candidates, window : optional
        See :func:`align_to_skeleton`.

    Returns
    -------
    indices : list of ndarray of shape (n_keys,)
    """

    def one(U):
        return align_to_skeleton(U, C, max_candidates, window)

    workers = min(n_jobs or os.cpu_count() or 1, len(U_list))
    C = np.ascontiguousarray(C, dtype=np.float64)
    if workers <= 1:
        return [one(U) for U in U_list]
    return list(thread_pool(workers).map(one, U_list))


def align_to_skeleton(
    U: np.ndarray,
    C: np.ndarray,
    max_candidates: int | None = None,
    window: float = 0.0,
) -> np.ndarray:
    """Samples of a demonstration matched to the skeleton points.

    Parameters
    ----------
    U : ndarray of shape (n_samples, n_dims)
        The demonstration (normalized units).
    C : ndarray of shape (n_keys, n_dims)
        The skeleton points, ``n_keys >= 2``.
    max_candidates : int, optional
        Match only to this many samples, evenly spread (always with the first
        and the last): the cost is ``O(n_keys * max_candidates * n_dims)``
        instead of ``O(n_keys * n_samples * n_dims)``.
    window : float, default=0.0
        Match on the :func:`moving_average` of ``U`` over ``round(window *
        n_samples)`` rows each side (0: the raw samples).

    Returns
    -------
    index : ndarray of shape (n_keys,), dtype int64
        Non-decreasing sample indices with ``index[0] = 0`` and ``index[-1] =
        n_samples - 1`` that minimize ``sum_i |U[index[i]] - C[i]|^2``;
        strictly increasing when ``n_keys <= n_samples``. Ties go to the
        earliest sample.

    Examples
    --------
    >>> U = np.array([[0.0], [1.0], [2.0], [3.0], [4.0]])
    >>> align_to_skeleton(U, np.array([[0.0], [2.9], [4.0]]))
    array([0, 3, 4])
    """
    U = np.asarray(U, dtype=np.float64)
    C = np.ascontiguousarray(C, dtype=np.float64)
    n = U.shape[0]
    U = moving_average(U, round(window * n))
    cand = None
    if max_candidates is not None and n > max_candidates:
        cand = np.unique(np.r_[np.linspace(0, n - 1, max_candidates).astype(np.int64)])
        U = U[cand]
    # one common scale: the same matches, and squared distances of values
    # near 1e300 that do not overflow to inf
    big = max(float(np.abs(U).max(initial=0.0)), float(np.abs(C).max(initial=0.0)))
    if big > 1e100:
        U, C = U / big, C / big
    U = np.ascontiguousarray(U)
    strict = C.shape[0] <= U.shape[0]
    index, _ = _align_kernel(U, C, strict)
    return index if cand is None else cand[index]


def skeleton_times(tau_list, index_list, weights) -> np.ndarray:
    """Normalized time of each skeleton point (weighted mean of the matches').

    The weighted mean of the matched samples' normalized times.

    Parameters
    ----------
    tau_list : list of ndarray of shape (n_j,)
        Normalized times of the demonstrations.
    index_list : list of ndarray of shape (n_keys,)
        Each one's samples matched to the skeleton points.
    weights : ndarray of shape (n_demos,)
        Non-negative, not all zero.

    Returns
    -------
    key_tau : ndarray of shape (n_keys,)

    Examples
    --------
    >>> tau = np.linspace(0.0, 1.0, 5)
    >>> skeleton_times([tau, tau], [np.array([0, 1, 4]), np.array([0, 3, 4])],
    ...                np.array([1.0, 1.0]))
    array([0. , 0.5, 1. ])
    """
    w = np.asarray(weights, dtype=np.float64)
    keys = np.array([tau[idx] for tau, idx in zip(tau_list, index_list, strict=True)])
    return (w / w.sum()) @ keys


@njit(cache=True, nogil=True)
def _interp_rows(U, tau, at):  # pragma: no cover - compiled
    """``np.interp`` of every column of ``U`` (sampled at ``tau``) at ``at``.

    A forward scan, restarted when ``at`` steps back; values outside
    ``[tau[0], tau[-1]]`` take the end rows, as ``np.interp`` does.
    """
    n, d = U.shape
    out = np.empty((at.shape[0], d))
    if n == 1:  # element by element: a row slice assignment compiles numba's
        # broadcast check and its error message (1.8 s of CPU on a first run)
        for r in range(at.shape[0]):
            for c in range(d):
                out[r, c] = U[0, c]
        return out
    j = 0
    for r in range(at.shape[0]):
        x = at[r]
        if x < tau[j]:
            j = 0
        while j < n - 2 and tau[j + 1] <= x:
            j += 1
        f = (x - tau[j]) / (tau[j + 1] - tau[j])
        f = min(max(f, 0.0), 1.0)
        for c in range(d):
            out[r, c] = U[j, c] + f * (U[j + 1, c] - U[j, c])
    return out


#: How much wider than its sample spacing a template's reading window may
#: grow (:func:`window_half`). Read by linear interpolation at the times it
#: was sampled, a template is itself; read finer, its velocity jumps at each
#: of its samples, and a path sampled finer than the demonstrations turned
#: their noise into accelerations as much larger as the sampling was finer.
#: So a template read at a step ``s`` finer than its spacing ``D`` is
#: averaged over ``x +- h``, ``h = D min(TEMPLATE_WINDOW, 2 (1 - s / D))``:
#: none at its own sampling (a demonstration is reproduced exactly), one
#: spacing either side from ``s <= D / 2``. The finite-difference
#: acceleration is then no larger than the template's own at its spacing, at
#: every output step from ``D`` to ``D / 8`` (a zigzag and white noise of 50
#: samples, ``tests/learner/test_learner_blend.py``). Measured with
#: ``benchmarks/bench_envelope.py`` (1,000 samples per path; the largest
#: acceleration over the demonstrations' 95th percentile at each phase,
#: unconditioned): ``synth.obstacle`` (200 noisy samples per demonstration)
#: 2.98 read linearly, 0.99 with the window; the SO-101-like joints 1.04 and
#: 0.35; a fixed window of 0.5 and 1.5 spacings gave 2.21 and 0.67 on
#: ``synth.obstacle``; LASA (1,000 samples) unchanged, its leave-one-out DTW
#: within 0.03 %.
TEMPLATE_WINDOW = 1.0


@njit(cache=True, nogil=True)
def _after(tau, x):  # pragma: no cover - compiled
    """``np.searchsorted(tau, x, side="right")``, its bisection written out.

    numba's own compiles its string argument's handling and a NaN-aware
    comparison for complex numbers too (0.3 s of CPU on a first run); this is
    the same bisection and comparison (a NaN ``x`` sorts after everything).
    """
    lo, hi = 0, tau.shape[0]
    while lo < hi:
        mid = lo + ((hi - lo) >> 1)
        if x != x or tau[mid] <= x:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(cache=True, nogil=True)
def _segment_integral(U, tau, c, p, q, base):  # pragma: no cover - compiled
    """``int_p^q (u(s) - base) ds`` of column ``c``'s linear interpolant.

    ``tau[0] <= p <= q <= tau[-1]``; summed segment by segment, so a stretch
    where the column equals ``base`` adds exactly nothing.
    """
    n = tau.shape[0]
    j = min(max(_after(tau, p) - 1, 0), n - 2)
    total = 0.0
    while p < q:
        e = min(tau[j + 1], q)
        du = U[j + 1, c] - U[j, c]
        width = tau[j + 1] - tau[j]
        vp = U[j, c] + (p - tau[j]) / width * du
        ve = U[j, c] + (e - tau[j]) / width * du
        total += ((vp - base) + (ve - base)) * 0.5 * (e - p)
        p = e
        j = min(j + 1, n - 2)
    return total


@njit(cache=True, nogil=True)
def _window_rows(U, tau, at, half):  # pragma: no cover - compiled
    """The mean of each column's linear interpolant over ``[x - h, x + h]``.

    ``h = min(half, tau[-1] - tau[0])`` for each ``x`` of ``at`` (clipped to
    ``[tau[0], tau[-1]]``). Beyond its ends the interpolant is continued by
    its point reflection through the end sample (``2 u[0] - u(2 tau[0] -
    s)``), the same line as at the end: the ends are read exactly and the
    velocity has no kink there. The mean is the linear interpolant's value
    at ``x`` plus the window's integral of the difference to it, summed over
    the segments in the window: a window where a column is constant reads
    that constant exactly. A window narrower than ``1e-9`` of the span
    (``half=0``) is :func:`_interp_rows`.
    """
    n, d = U.shape
    out = _interp_rows(U, tau, at)
    lo, hi = tau[0], tau[n - 1]
    h = min(half, hi - lo)
    if n < 2 or h <= 1e-9 * (hi - lo):  # a window too narrow to average
        return out
    for r in range(at.shape[0]):
        x = min(max(at[r], lo), hi)
        a, b = x - h, x + h
        for c in range(d):
            base = out[r, c]
            total = _segment_integral(U, tau, c, max(a, lo), min(b, hi), base)
            if a < lo:  # through the reflection 2 u0 - u(2 lo - s)
                total += 2.0 * (U[0, c] - base) * (lo - a)
                total -= _segment_integral(U, tau, c, lo, 2.0 * lo - a, base)
            if b > hi:  # 2 u_n - u(2 hi - s)
                total += 2.0 * (U[n - 1, c] - base) * (b - hi)
                total -= _segment_integral(U, tau, c, 2.0 * hi - b, hi, base)
            out[r, c] = base + total / (2.0 * h)
    return out


def window_half(tau: np.ndarray, step: float) -> float:
    """The half-width a template is read through at an output step.

    Parameters
    ----------
    tau : ndarray of shape (n_samples,)
        The template's normalized times.
    step : float
        The output's step in normalized time.

    Returns
    -------
    half : float
        ``D min(TEMPLATE_WINDOW, 2 (1 - step / D))``, at least 0, with ``D``
        the median spacing of ``tau`` (see :data:`TEMPLATE_WINDOW`).

    Examples
    --------
    >>> tau = np.linspace(0.0, 1.0, 11)
    >>> [round(window_half(tau, s), 12) for s in (0.1, 0.075, 0.01)]
    [0.0, 0.05, 0.1]
    """
    if tau.size < 2:
        return 0.0
    gaps = np.sort(np.diff(tau))  # their median, as np.median (without its cost)
    m = gaps.size // 2
    spacing = float(gaps[m] if gaps.size % 2 else (gaps[m - 1] + gaps[m]) / 2)
    return spacing * min(TEMPLATE_WINDOW, max(0.0, 2.0 * (1.0 - step / spacing)))


def output_step(tq: np.ndarray) -> float:
    """The median step between an output's distinct times (``inf`` for one).

    Examples
    --------
    >>> output_step(np.array([0.0, 0.5, 0.25, 1.0]))
    0.25
    """
    gaps = np.diff(np.unique(tq))
    return float(np.median(gaps)) if gaps.size else np.inf


def blend(
    U_list,
    tau_list,
    index_list,
    weights,
    knots,
    tq,
    quat_cols=None,
    observed=None,
    ridge: float = CONDITION_RIDGE,
    mix=None,
    step=None,
    reach: float = CONDITION_REACH,
):
    """Weighted average of demonstrations time-warped onto a common skeleton.

    Parameters
    ----------
    U_list : list of ndarray of shape (n_j, n_dims)
        Demonstrations, normalized units.
    tau_list : list of ndarray of shape (n_j,)
        Their normalized times (0 to 1).
    index_list : list of ndarray of shape (n_keys,)
        Each one's samples matched to the skeleton points.
    weights : ndarray of shape (n_demos,)
        Non-negative, not all zero.
    knots : ndarray of shape (n_keys,)
        Normalized time of each skeleton point: :func:`skeleton_times` of the
        matches under ``weights / weights.sum()``. Each demonstration's
        matched samples are warped onto them.
    tq : ndarray of shape (n_out,)
        Normalized output times.
    quat_cols : sequence of int, optional
        Four quaternion columns, sign-aligned to the heaviest demonstration
        before averaging.
    observed : sequence of (int, list of int, ndarray), optional
        Rows of ``tq``, columns and values observed (normalized): the holds
        the templates share on those columns are aligned first
        (:func:`~ndlfd.learner._rests.hold_knots`), the mean is conditioned
        on them (:func:`condition_offsets`), the shift averaged over
        :data:`CONDITION_SMOOTH` either side of the time spent moving
        (:func:`~ndlfd.learner._rests.rest_clock` of the holds: the shift
        holds still in them; the ends kept by point reflection, as
        :func:`_window_rows` does).
    ridge : float, default=:data:`CONDITION_RIDGE`
        The observations' noise (:func:`condition_offsets`).
    mix : callable, optional
        ``mix(W, w, tq) -> W``, applied to the time-warped demonstrations
        before they are averaged (task frames: :mod:`ndlfd.learner._frames`).
    reach : float, default=:data:`CONDITION_REACH`
        How far an observation is followed (:func:`condition_offsets`).
    step : float, optional
        The step, in normalized time, of the path the templates are read for
        (:func:`window_half`); by default that of ``tq``
        (:func:`output_step`). A search on a finer grid passes the path's.

    Returns
    -------
    mean : ndarray of shape (n_out, n_dims)

    Examples
    --------
    Two demonstrations of one line at different speeds, matched at their ends
    and middles, blend into the line:

    >>> tau = np.linspace(0.0, 1.0, 5)
    >>> U = [tau[:, None], (tau**2)[:, None]]
    >>> index = [np.array([0, 2, 4]), np.array([0, 3, 4])]
    >>> w = np.array([1.0, 1.0])
    >>> knots = skeleton_times([tau, tau], index, w / w.sum())
    >>> blend(U, [tau, tau], index, w, knots, np.array([0.0, 1.0]))
    array([[0.],
           [1.]])
    """
    holds = np.zeros((0, 2))
    if observed is not None:  # the templates' shared holds aligned (._rests)
        cols = sorted({c for _, obs_cols, _ in observed for c in obs_cols})
        knots, index_list, holds = hold_knots(
            U_list, tau_list, index_list, weights, knots, cols
        )
    W, w = warped(
        U_list, tau_list, index_list, weights, knots, tq, quat_cols, mix, step
    )
    mean = np.tensordot(w, W, axes=1)
    if observed is not None:  # the shift, on a grid, averaged over a window
        coef = condition_coefficients(W, w, mean, observed, ridge, reach)
        grid = np.linspace(0.0, 1.0, CONDITION_GRID)
        Wg, _ = warped(
            U_list, tau_list, index_list, weights, knots, grid, quat_cols, mix, step
        )
        shift = np.tensordot(coef, Wg - np.tensordot(w, Wg, axes=1)[None], axes=1)
        rows = np.asarray(tq, dtype=np.float64)
        # over the time spent moving: what the shift does around a hold is
        # not smeared into it (the path holds still where the templates do)
        clock = rest_clock(grid, holds)
        mean += _window_rows(shift, clock, rest_clock(rows, holds), CONDITION_SMOOTH)
    return mean


#: Half-width of the moving average that smooths each template's time warp,
#: as a share of the motion (:func:`smooth_warp`). The warp is piecewise
#: linear between the skeleton's knots: its slope, the template's pace,
#: jumps at every knot, and so did the blend's velocity. Measured on LASA
#: (Angle, Sshape, Worm; 1,000 samples) against the demonstrations' 95th
#: percentile at each phase: the generated path's largest acceleration went
#: from 2.4, 1.3, 5.2 times it to 0.74, 0.71, 0.83 (0.02: 0.72, 0.72, 0.85);
#: DTW to held-out demonstrations unchanged to three digits.
WARP_SMOOTH = 0.01


def smooth_warp(tq, knots, at, half: float = WARP_SMOOTH) -> np.ndarray:
    """The piecewise-linear warp through ``(knots, at)``, averaged over a window.

    Each output time ``x`` takes the mean of the warp over ``[x - h, x + h]``
    with ``h = min(half, x - knots[0], knots[-1] - x)``: computed exactly
    from the warp's integral (piecewise quadratic). Both window ends move
    forward with ``x``, so a non-decreasing warp stays non-decreasing; at the
    first and last knot the window is empty and the warp is kept exactly; its
    slope is now continuous (the path's velocity has no jumps).

    Parameters
    ----------
    tq : ndarray of shape (n_out,)
        Output times (any order).
    knots : ndarray of shape (n_knots,)
        Non-decreasing.
    at : ndarray of shape (n_knots,) or (n_warps, n_knots)
        The warp's value at each knot (a row per warp: several warps on the
        same knots at once, each as if alone).
    half : float, default=:data:`WARP_SMOOTH`

    Returns
    -------
    warp : ndarray of shape (n_out,) or (n_warps, n_out)

    Examples
    --------
    A corner at 0.5 (slope 0, then 2) is rounded within 0.1 of it:

    >>> k, a = np.array([0.0, 0.5, 1.0]), np.array([0.0, 0.0, 1.0])
    >>> smooth_warp(np.array([0.0, 0.4, 0.5, 0.6, 1.0]), k, a, half=0.1).round(6)
    array([0.  , 0.  , 0.05, 0.2 , 1.  ])
    """
    tq = np.asarray(tq, dtype=np.float64)
    at = np.asarray(at, dtype=np.float64)
    A = at.reshape(-1, at.shape[-1])
    if knots.size < 2 or half <= 0:
        out = np.array([np.interp(tq, knots, a) for a in A])
        return out.reshape(at.shape[:-1] + tq.shape)
    # the window's ends depend on the knots and times only: shared by every row
    x = np.clip(tq, knots[0], knots[-1])
    h = np.minimum(half, np.minimum(x - knots[0], knots[-1] - x))
    wide = h > 1e-12
    lo, hi = x[wide] - h[wide], x[wide] + h[wide]
    last = knots.size - 2
    i_lo = np.clip(np.searchsorted(knots, lo, side="right") - 1, 0, last)
    i_hi = np.clip(np.searchsorted(knots, hi, side="right") - 1, 0, last)
    dk = np.diff(knots)
    out = np.empty((A.shape[0], tq.size))
    for r, a in enumerate(A):
        area = np.concatenate([[0.0], np.cumsum(dk * (a[1:] + a[:-1]) / 2)])
        # the warp's integral from knots[0] to each end
        up = area[i_hi] + (hi - knots[i_hi]) * (a[i_hi] + np.interp(hi, knots, a)) / 2
        down = area[i_lo] + (lo - knots[i_lo]) * (a[i_lo] + np.interp(lo, knots, a)) / 2
        out[r] = np.interp(x, knots, a)
        out[r, wide] = (up - down) / (2.0 * h[wide])
    return out.reshape(at.shape[:-1] + tq.shape)


def warped(
    U_list,
    tau_list,
    index_list,
    weights,
    knots,
    tq,
    quat_cols=None,
    mix=None,
    step=None,
):
    """The demonstrations time-warped onto the skeleton, and their weights.

    What :func:`blend` averages; see its parameters. Each is read through a
    window when the output is sampled finer than it (:data:`TEMPLATE_WINDOW`).

    Returns
    -------
    W : ndarray of shape (n_demos, n_out, n_dims)
        Each demonstration at the output times (quaternions sign-aligned to
        the heaviest demonstration's).
    w : ndarray of shape (n_demos,)
        The weights, summing to 1.
    """
    w = np.asarray(weights, dtype=np.float64)
    w = w / w.sum()
    if step is None:
        step = output_step(np.asarray(tq, dtype=np.float64))

    # every template's warp at once (the same knots)
    ats = smooth_warp(
        tq, knots, np.array([t[i] for t, i in zip(tau_list, index_list, strict=True)])
    )
    W = np.stack(
        [
            _window_rows(U, tau, at, window_half(tau, step))
            for tau, at, U in zip(tau_list, ats, U_list, strict=True)
        ]
    )  # (n_demos, n_out, n_dims)
    quats = [] if quat_cols is None or len(quat_cols) % 4 else quat_cols
    for b in range(0, len(quats), 4):  # each orientation group's 4 columns
        cols = list(quats[b : b + 4])
        Q = W[:, :, cols]
        flip = np.sum(Q * Q[int(np.argmax(w))][None], axis=2) < 0  # (n_demos, n_out)
        W[:, :, cols] = np.where(flip[:, :, None], -Q, Q)
    if mix is not None:
        W = mix(W, w, np.asarray(tq, dtype=np.float64))
    return W, w


def spread(
    U_list,
    tau_list,
    index_list,
    weights,
    knots,
    tq,
    quat_cols=None,
    mix=None,
    step=None,
):
    """Weighted standard deviation of the warped demonstrations at each time.

    The blend's band: how much the demonstrations it averages differ where
    they are aligned (zero only where they coincide, or for one).

    Parameters
    ----------
    U_list, tau_list, index_list, weights, knots, tq, quat_cols, mix, step
        As :func:`blend`'s.

    Returns
    -------
    std : ndarray of shape (n_out, n_dims)
        Normalized units.

    Examples
    --------
    Two lines 0.2 apart, weighted equally, spread 0.1 about their mean:

    >>> tau = np.linspace(0.0, 1.0, 5)
    >>> U = [np.zeros((5, 1)), np.full((5, 1), 0.2)]
    >>> index = [np.array([0, 4])] * 2
    >>> s = spread(U, [tau, tau], index, np.ones(2), np.array([0.0, 1.0]),
    ...            np.array([0.0, 0.5]))
    >>> np.round(s, 12)
    array([[0.1],
           [0.1]])
    """
    W, w = warped(
        U_list, tau_list, index_list, weights, knots, tq, quat_cols, mix, step
    )
    D = W - np.tensordot(w, W, axes=1)[None]
    return np.sqrt(np.tensordot(w, D * D, axes=1))


def condition_offsets(
    W, w, mean, observed, ridge: float = CONDITION_RIDGE, reach: float = CONDITION_REACH
):
    """The blend's shift given observed values: Gaussian conditioning on the templates.

    The time-warped templates' deviations from their weighted mean are a
    Gaussian process over the output rows (covariance ``sum_j w_j D_j
    D_j^T``); the shift is its conditional mean given the observed values,
    with observation noise ``ridge`` times the mean variance at them, and
    followed up to a Mahalanobis distance of :data:`CONDITION_REACH` (an
    observation farther off is followed that far along its direction: the
    templates co-vary only within their spread). As a
    ProMP conditions its weights, but on templates aligned to the decoded
    skeleton: an observation that is wide, early or late carries over the
    whole motion as the templates that are so carry it. Without deviations
    (one template) the shift is zero.

    Parameters
    ----------
    W : ndarray of shape (n_demos, n_out, n_dims)
        The time-warped templates.
    w : ndarray of shape (n_demos,)
        Their weights, summing to 1.
    mean : ndarray of shape (n_out, n_dims)
        Their weighted mean.
    observed : sequence of (int, list of int, ndarray)
        Observations: a row of the output, its observed columns, their values.
    ridge : float, default=:data:`CONDITION_RIDGE`
    reach : float, default=:data:`CONDITION_REACH`
        The largest Mahalanobis distance followed (``inf``: all of it).

    Returns
    -------
    shift : ndarray of shape (n_out, n_dims)

    Examples
    --------
    Two templates, 0 and 2, weighted equally: observing 2 at the first row
    moves every row by the same share (the ridge, as large as the variance
    there, keeps it to half):

    >>> W = np.array([[[0.0], [0.0]], [[2.0], [2.0]]])
    >>> w = np.array([0.5, 0.5])
    >>> mean = np.tensordot(w, W, axes=1)
    >>> condition_offsets(W, w, mean, [(0, [0], np.array([2.0]))])
    array([[0.5],
           [0.5]])
    """
    coef = condition_coefficients(W, w, mean, observed, ridge, reach)
    return np.tensordot(coef, W - mean[None], axes=1)


def condition_coefficients(
    W, w, mean, observed, ridge: float = CONDITION_RIDGE, reach: float = CONDITION_REACH
):
    """How much of each template's deviation :func:`condition_offsets` adds.

    Parameters
    ----------
    W, w, mean, observed, ridge, reach
        As :func:`condition_offsets`'s.

    Returns
    -------
    coef : ndarray of shape (n_demos,)
        The shift is ``sum_j coef[j] * (W[j] - mean)``.

    Examples
    --------
    >>> W = np.array([[[0.0], [0.0]], [[2.0], [2.0]]])
    >>> w = np.array([0.5, 0.5])
    >>> mean = np.tensordot(w, W, axes=1)
    >>> condition_coefficients(W, w, mean, [(0, [0], np.array([2.0]))])
    array([-0.25,  0.25])
    """
    D = W - mean[None]
    A = np.concatenate([D[:, r, c] for r, c, _ in observed], axis=1)
    resid = np.concatenate([v - mean[r, c] for r, c, v in observed])
    S = (A.T * w) @ A  # (n_obs, n_obs)
    noise = ridge * max(float(np.trace(S)) / S.shape[0], 1e-12)
    alpha = np.linalg.solve(S + noise * np.eye(S.shape[0]), resid)
    far = float(np.sqrt(max(float(resid @ alpha), 0.0)))
    if far > reach:
        alpha *= reach / far
    return w * (A @ alpha)
