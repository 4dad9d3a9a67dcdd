"""n-dimensional Douglas–Peucker: key points of a trajectory (SPEC §1.3).

The public doorways are :func:`simplify` (one trajectory) and
:func:`simplify_many` (many demonstrations in parallel threads). They check
and convert the input, then hand it to the numba kernels of
:mod:`ndlfd.dp._kernels`, which use an explicit stack (never recursion) and
release the GIL.

Distances (the ``distance=`` option, registry :data:`DISTANCES`):

``"line"`` (default)
    Exact perpendicular distance from ``P_i`` to the infinite line through the
    segment's endpoints ``P_a, P_b``, in any number of dimensions, computed as
    the norm of the residual ``v - (v·u / |u|²) u`` (``v = P_i - P_a``,
    ``u = P_b - P_a``), never as the cancellation-prone
    ``|v|²|u|² - (v·u)²``; in 2-D and 3-D as the equivalent, equally stable
    ``|v × u| / |u|``.
``"segment"``
    Distance to the closed segment ``[P_a, P_b]``: a point that reaches past an
    endpoint and comes back is measured from that endpoint.
``"sed"``
    Synchronized Euclidean distance: ``P_i`` is compared with the chord's
    position at the same time, ``P_a + (t_i - t_a) / (t_b - t_a) · u``.
    Needs ``times``.
``"paper"``
    The paper's determinant formula (eq. 5–6), kept for reproduction only.

Coincident endpoints: when ``|u| <= 8 · 2.2e-16 · max|P|`` (a few ulps of the
data's largest coordinate, so the line's direction is not defined by the data)
the distance to ``P_a`` is used instead (paper eq. 4), in every mode but
``"sed"``.
"""

from __future__ import annotations

import itertools
import math
import os
from dataclasses import dataclass

import numpy as np

from .._errors import ValidationError
from .._parallel import thread_pool
from .._registry import Registry
from .._validation import (
    as_float_array,
    check_nonnegative_scalar,
    check_points,
    check_positive_int,
    check_times,
    check_weights,
)
from . import _kernels as K
from ._budget import dp_budget
from ._exact import lopsided
from ._generic import dp_generic
from ._tree import TREE_LINE, TREE_PAPER, TREE_SED, TREE_SEGMENT, make_tree

__all__ = ["DISTANCES", "DistanceMode", "simplify", "simplify_many"]

_EPS = float(np.finfo(np.float64).eps)
#: ``|u|`` below ``_UTOL_ULPS * eps * max|P|`` means coincident endpoints.
_UTOL_ULPS = 8.0


@dataclass(frozen=True)
class DistanceMode:
    """A distance option of :func:`simplify`.

    Parameters
    ----------
    name : str
        The option's name.
    code : int
        The kernel's mode number.
    needs_times : bool
        Whether the mode needs the ``times`` argument.
    description : str
        One line for humans.
    """

    name: str
    code: int
    needs_times: bool
    description: str


DISTANCES: Registry[DistanceMode] = Registry("distance")
for _mode in (
    DistanceMode("line", K.MODE_LINE, False, "perpendicular distance to the line"),
    DistanceMode("segment", K.MODE_SEGMENT, False, "distance to the closed segment"),
    DistanceMode("sed", K.MODE_SED, True, "synchronized Euclidean distance"),
    DistanceMode("paper", K.MODE_PAPER, False, "paper eq. 5-6 (exact in 2-D only)"),
):
    DISTANCES.add(_mode.name, _mode)
del _mode

_EMPTY_TIMES = np.zeros(0)


def _pow2_scale(m: float) -> float:
    """A power of two that brings ``m = max|a|`` near 1, or 1.0 if not needed.

    Multiplying by a power of two is exact, so the kernels' comparisons are
    unchanged; it only keeps fourth powers of the coordinates (the keys of the
    kernels) away from overflow and underflow.
    """
    if m == 0.0 or 2.0**-64 <= m <= 2.0**64:
        return 1.0
    return math.ldexp(1.0, -math.frexp(m)[1])


def _detrended(P: np.ndarray, t: np.ndarray, m: float):
    """``(P - t g, its max|.|)``, ``g`` about each column's mean drift.

    The synchronized distance (``"sed"``) is unchanged by a drift linear in
    time: it moves a point and the chord at the same time alike. Taken out,
    a column that moves with time keeps tight boxes in the tree
    (:mod:`ndlfd.dp._tree`), whose exact ``"sed"`` bounds then skip the
    ties of a zigzag. A column keeps its drift where taking it out does not
    halve its range (a column that swings back and forth: any drift left
    would loosen its boxes), judged on at most 4,096 evenly spaced rows, so
    that a path that does not move with time costs no pass over the data.
    ``g`` is rounded to 10 bits below the power of two of ``m / t[-1]``, so
    that on integer data the result stays a short dyadic fraction and ties
    are still decided exactly.
    """
    g = (P[-1] - P[0]) / t[-1]
    if m == 0.0 or not np.any(g):
        return P, m
    unit = math.ldexp(1.0, math.frexp(m / t[-1])[1] - 10)
    g = np.round(g / unit) * unit
    rows = slice(None, None, max(1, P.shape[0] // 4096))
    Ps, ts = P[rows], t[rows]
    helps = np.ptp(Ps - ts[:, None] * g, axis=0) <= 0.5 * np.ptp(Ps, axis=0)
    if not helps.any():
        return P, m
    Q = P - t[:, None] * np.where(helps, g, 0.0)
    return Q, K.finite_maxabs(Q)[1]


@dataclass
class _Job:
    """One checked trajectory, ready for a kernel."""

    P: np.ndarray
    t: np.ndarray
    mode: int
    eps2: float
    k: int
    utol2: float
    m: float


def _checked_points(points, name):
    # Fast path: one compiled pass checks finiteness and finds max|P|; the
    # shared check_points (slower on large arrays) explains any problem.
    P = as_float_array(points, name)
    if P.ndim == 2 and P.shape[0] >= 1 and P.shape[1] >= 1:
        finite, m = K.finite_maxabs(P)
        if finite:
            return P, m
    P = check_points(points, name)
    return P, K.finite_maxabs(P)[1]


def _shifted_times(times, n, name):
    """``times - times[0]``, checked: finite and strictly increasing, length ``n``.

    One compiled pass checks and shifts; the shared :func:`check_times`
    (slower on long vectors) explains any problem.
    """
    t = as_float_array(times, name)
    if t.ndim == 1 and t.shape[0] == n and n >= 1:
        out = np.empty(n)
        if K.shifted_times(t, out):
            return out
    t = check_times(times, n, name=name)
    return t - t[0] if t.size else t


def _prepare(
    points,
    epsilon,
    distance,
    weights,
    times,
    n_points,
    name="points",
    times_name="times",
):
    mode = DISTANCES.get(distance)
    P, m = _checked_points(points, name)
    n, d = P.shape
    if (epsilon is None) == (n_points is None):
        got = "both" if epsilon is not None else "neither"
        raise ValidationError(
            "give exactly one of epsilon (a tolerance) and n_points (a budget of"
            f" key points); got {got}"
        )
    eps = 0.0
    k = 0
    if epsilon is not None:
        eps = check_nonnegative_scalar(epsilon, "epsilon")
    else:
        k = check_positive_int(n_points, "n_points")
    if weights is not None:
        w = check_weights(weights, d)
        P = P * w
        m = K.finite_maxabs(P)[1]
    if mode.needs_times:
        if times is None:
            raise ValidationError(
                f"distance={mode.name!r} needs times (one strictly increasing"
                f" time per point, length {n}); got times=None"
            )
        t = _shifted_times(times, n, times_name)
    else:
        if times is not None:
            raise ValidationError(
                f"times are only used by distance='sed'; got times with"
                f" distance={mode.name!r}"
            )
        t = _EMPTY_TIMES
    s = _pow2_scale(m)
    if s != 1.0:
        P = P * s
        eps *= s
        m *= s
    if t.size:
        ts = _pow2_scale(float(t[-1]))
        if ts != 1.0:
            t = t * ts
    if t.size > 1:
        P, m = _detrended(P, t, m)
    utol = _UTOL_ULPS * _EPS * m
    return _Job(P, t, mode.code, eps * eps, k, utol * utol, m)


#: Below this many points one trajectory is simplified serially.
PARALLEL_MIN = 100_000
#: A lone segment at least this long is scanned in parallel chunks (a thread
#: round trip costs tens of microseconds, a 200k-point scan about 100).
CHUNK_MIN = 200_000
#: Segments at least this long are split one level at a time in parallel
#: before the independent segments are handed to the workers.
SPLIT_MIN = 20_000


#: The top of the tree is split until there are this many segments per thread.
PENDING_PER_WORKER = 4
#: Dimensions handled by the column-tuple kernels (one compiled version each):
#: ``"line"`` from 4 (2 and 3 have their own), ``"segment"`` and ``"sed"``
#: from 1; above, the transposed-array kernel. Measured (1e6-point walks, one
#: thread, AVX-512): the tuples take 0.57-0.81x the time at d = 9 and 10 and
#: 1.05-2.8x from 11 on, where the columns' constants no longer fit in the
#: vector registers.
COLS_DIMS = range(1, 11)


#: Segments longer than this are scanned through a tree of bounding boxes
#: (:mod:`ndlfd.dp._tree`), which skips the blocks that cannot hold the
#: farthest point; shorter ones are scanned plainly.
TREE_MIN = 4096
#: The tree is built once lopsided splits of long segments (a zigzag: each
#: split peels one point off) have cost this many scans of the whole input;
#: 0 builds it at once.
TREE_BUDGET = 4
#: The tree's bound for each distance mode ("paper" is not a distance).
_TREE_KINDS = {
    K.MODE_LINE: TREE_LINE,
    K.MODE_SEGMENT: TREE_SEGMENT,
    K.MODE_SED: TREE_SED,
    K.MODE_PAPER: TREE_PAPER,
}


def _tree(job: _Job):
    """The (unbuilt) box tree for ``job``, built by the kernel when needed.

    ``None`` for a trajectory too short for a tree or the exact keys
    (:data:`ndlfd.dp._kernels.TREE_NONE_MAX`): the kernels then compile
    without them.
    """
    n = job.P.shape[0]
    if n <= min(TREE_MIN, K.TREE_NONE_MAX):
        return None
    kind = _TREE_KINDS.get(job.mode) if n > TREE_MIN else None
    if kind == TREE_PAPER and job.P.shape[1] == 1:
        kind = TREE_LINE  # in 1-D the paper's distance is the line's
    return make_tree(job.P, job.t, kind, job.m, TREE_MIN, TREE_BUDGET * n)


def _line_layout(P, t, mode, pool=None, workers=1):
    """The column-major kernels for ``P``: ``(dp, scan_range, args)``.

    ``dp(*args, eps2, utol2, keep, a, b, tree)`` simplifies one segment and
    ``scan_range(*args, a, b, utol2, lo, hi)`` scans one chunk of one, in
    ``mode`` (any but ``"paper"``; ``t`` the times). The data are laid out
    column by column (structure of arrays); with a thread ``pool`` the
    transposition is shared among ``workers`` threads.
    """
    n, d = P.shape
    Pt = np.empty((d, n))
    if pool is None and n < PARALLEL_MIN:
        # numpy's copy is as fast up to here (4 us at 1,000 x 4, 0.18 ms at
        # 100,000 x 4; the kernel 5 us, 0.43 ms), with no kernel to compile
        np.copyto(Pt, P.T)
    elif pool is None:
        K.transpose(P, Pt, 0, n)
    else:
        cuts = np.linspace(0, n, workers + 1).astype(np.int64).tolist()
        parts = itertools.pairwise(cuts)
        _gather(pool, [(K.transpose, (P, Pt, lo, hi)) for lo, hi in parts])
    line = mode == K.MODE_LINE
    if line and d in (2, 3):
        z = Pt[2] if d == 3 else _EMPTY_TIMES
        args = (d, Pt[0], Pt[1], z, np.zeros((d, 0)), t, mode)
        return K.dp_line, K.scan_line_range, args
    if d in COLS_DIMS and (d >= 4 or not line):
        return K.dp_cols, K.scan_cols_range, (tuple(Pt), t, mode)
    e = _EMPTY_TIMES
    return K.dp_line, K.scan_line_range, (0, e, e, e, Pt, t, mode)


def _gather(pool, calls):
    """Run ``calls`` (function, args) on the pool and this thread, in order."""
    futures = [pool.submit(f, *a) for f, a in calls[1:]]
    first = calls[0][0](*calls[0][1])
    return [first, *(f.result() for f in futures)]


def _line_parallel(job, keep, workers, tree):
    """Epsilon-mode DP on two or more threads; same result as the serial kernel.

    The top of the split tree is built level by level: while there are few
    long segments, the longest are scanned at the same time (one thread
    each), and a lone segment longer than :data:`CHUNK_MIN` is scanned in
    chunks whose results are reduced in index order (so the first maximum
    still wins). Then each remaining segment is finished by the serial
    kernel in a worker thread, longest first (the kernels release the GIL;
    segment interiors are disjoint, so threads write disjoint ``keep``
    entries).
    """
    eps2, utol2 = job.eps2, job.utol2
    n = keep.shape[0]
    keep[0] = 1
    keep[n - 1] = 1
    pending = [(0, n - 1, False)]  # (a, b, from a lopsided split)
    lop_work = 0
    pool = thread_pool(workers)
    dp, scan_range, args = _line_layout(job.P, job.t, job.mode, pool, workers)
    while pending and len(pending) < PENDING_PER_WORKER * workers:
        pending.sort(key=lambda seg: seg[0] - seg[1])  # longest first
        longest = pending[0][1] - pending[0][0]
        if longest < SPLIT_MIN:
            break
        top = [
            seg
            for seg in pending[:workers]
            if seg[1] - seg[0] >= max(SPLIT_MIN, longest // 4)
        ]
        if len(top) == 1:
            if longest < CHUNK_MIN:
                break
            a, b, lop = top[0]
            cuts = np.linspace(a + 1, b, workers + 1).astype(np.int64).tolist()
            calls = [
                (scan_range, (*args, a, b, utol2, lo, hi, lop))
                for lo, hi in itertools.pairwise(cuts)
            ]
            parts = _gather(pool, calls)
            far, best, S = parts[0]
            for f, q, _ in parts[1:]:  # in index order: first maximum wins
                if q > best:
                    far, best = f, q
            results = [(far, best, S)]
        else:
            calls = [
                (scan_range, (*args, a, b, utol2, a + 1, b, lop)) for a, b, lop in top
            ]
            results = _gather(pool, calls)
        del pending[: len(top)]
        for (a, b, _), (far, q, S) in zip(top, results, strict=True):
            if q > eps2 * S:
                keep[far] = 1
                lop = lopsided(a, b, far)
                pending += [
                    (lo, hi, lop) for lo, hi in ((a, far), (far, b)) if hi - lo > 1
                ]
                lop_work += (b - a) if lop else 0
        if lop_work > TREE_BUDGET * n:
            break  # a zigzag: the kernels' tree peels it faster
    pending.sort(key=lambda seg: seg[0] - seg[1])
    list(
        pool.map(
            lambda seg: dp(*args, eps2, utol2, keep, seg[0], seg[1], tree, seg[2]),
            pending,
        )
    )


def _run(job: _Job, n_jobs) -> np.ndarray:
    P = job.P
    n = P.shape[0]
    keep = np.zeros(n, np.uint8)
    tree = None if job.k else _tree(job)
    if job.k:
        dp_budget(P, job.t, job.mode, job.k, job.utol2, keep)
    elif job.mode != K.MODE_PAPER:
        if n_jobs is None:
            workers = (os.cpu_count() or 1) if n >= PARALLEL_MIN else 1
        else:
            workers = n_jobs
        if workers > 1 and n > 2:
            _line_parallel(job, keep, workers, tree)
        else:
            dp, _, args = _line_layout(P, job.t, job.mode)
            dp(*args, job.eps2, job.utol2, keep, 0, n - 1, tree)
    else:
        dp_generic(P, job.t, job.mode, job.eps2, job.utol2, keep, 0, n - 1, tree)
    return keep.view(np.bool_)


def _output(mask: np.ndarray, return_mask: bool) -> np.ndarray:
    if return_mask:
        return mask
    return np.flatnonzero(mask).astype(np.int64, copy=False)


def simplify(
    points,
    epsilon=None,
    *,
    distance="line",
    weights=None,
    times=None,
    n_points=None,
    return_mask=False,
    n_jobs=None,
):
    """Key points of a trajectory by n-dimensional Douglas–Peucker.

    Each segment ``[P_a, P_b]`` (starting with the whole trajectory) is
    scanned for its farthest point: the *first* index reaching the largest
    distance. The point is kept, and the segment split there, when its
    distance is *strictly* greater than ``epsilon``. Endpoints are always kept.

    Parameters
    ----------
    points : array-like of shape (n_samples, n_dims)
        The trajectory, one row per sample; any ``n_samples >= 1`` and
        ``n_dims >= 1``. Finite real numbers.
    epsilon : float, optional
        Tolerance, finite and ``>= 0``. Give exactly one of ``epsilon`` and
        ``n_points``.
    distance : {"line", "segment", "sed", "paper"}, default="line"
        How far a point is from a segment ``P_a, P_b``:

        - ``"line"``: exact perpendicular distance to the infinite line through
          ``P_a`` and ``P_b`` in ``n_dims`` dimensions (the norm of the
          residual of ``P_i - P_a`` after projection on ``P_b - P_a``).
        - ``"segment"``: distance to the closed segment.
        - ``"sed"``: synchronized Euclidean distance to the chord's position at
          time ``times[i]``; needs ``times``.
        - ``"paper"``: the paper's ``|det(A_d)| / |P_a P_b|`` (eq. 5–6) with
          the canonical completion rows, for reproduction only. It equals
          ``"line"`` in 2-D (and, by definition, in 1-D), but in 3-D and above
          it is **not a distance**: it only depends on the last three columns
          of ``P_i - P_a`` and its ratio to the true distance ranges from
          about 0.0002 to 1.7 on random points.

        When ``|P_b - P_a|`` is below ``8 · 2.2e-16 · max|P|`` the endpoints
        count as coincident and the distance to ``P_a`` is used (paper eq. 4),
        in every mode except ``"sed"``.
    weights : array-like of shape (n_dims,), optional
        Non-negative per-column weights; columns are multiplied by them before
        any distance is computed.
    times : array-like of shape (n_samples,), optional
        Strictly increasing time stamps; only for ``distance="sed"``.
    n_points : int, optional
        Budget mode instead of ``epsilon``: keep ``min(max(n_points, 2),
        n_samples)`` points (the endpoints are always kept, so ``n_points=1``
        still gives both). Starting from the whole trajectory, the segment
        whose farthest point is farthest is split at that point, repeatedly;
        equal distances go to the smaller index. Segments whose points all lie
        at distance 0 are split too, so the count is always reached.
        An ``epsilon`` result is always a prefix of this order:
        ``simplify(P, eps)`` equals ``simplify(P, n_points=k)`` with ``k`` the
        size of the former (up to rounding at distances equal to ``eps``).
        The converse does not hold: a split can reveal a point farther than
        the one that made it, and a budget that stops between the two matches
        no ``epsilon``.
    return_mask : bool, default=False
        Return a boolean mask of length ``n_samples`` instead of indices.
    n_jobs : int, optional
        Threads for one long trajectory (every mode but ``"paper"``).
        ``None`` uses all cores above a size threshold; ``1`` is serial. The
        result does not depend on it.

    Returns
    -------
    indices : ndarray of shape (n_kept,), dtype int64
        Sorted unique indices of the kept points, including ``0`` and
        ``n_samples - 1``; or, with ``return_mask=True``, a boolean ndarray of
        shape (n_samples,).

    Raises
    ------
    ValidationError
        Non-finite, non-numeric or wrongly shaped points, bad ``epsilon``,
        ``n_points``, ``weights`` or ``times``, or both/neither of
        ``epsilon`` and ``n_points``.
    OptionError
        Unknown ``distance``.

    Examples
    --------
    >>> simplify([[0, 0], [1, 0.1], [2, 0]], 0.5)
    array([0, 2])
    >>> simplify([[0, 0], [5, 0], [10, 0], [5, 0.01], [1, 0]], 1,
    ...          distance="segment")
    array([0, 2, 4])
    >>> simplify([[0, 0], [1, 2], [2, 0], [3, 1], [4, 0]], n_points=3)
    array([0, 1, 4])
    """
    if n_jobs is not None:
        n_jobs = check_positive_int(n_jobs, "n_jobs")
    job = _prepare(points, epsilon, distance, weights, times, n_points)
    return _output(_run(job, n_jobs), return_mask)


def simplify_many(
    trajectories,
    epsilon=None,
    *,
    distance="line",
    weights=None,
    times=None,
    n_points=None,
    return_mask=False,
    n_jobs=None,
):
    """Run :func:`simplify` over many trajectories in parallel threads.

    Every trajectory is checked first (errors name the trajectory), then the
    GIL-free kernels run in a :class:`~concurrent.futures.ThreadPoolExecutor`.

    Parameters
    ----------
    trajectories : sequence of array-like of shape (n_samples_j, n_dims_j)
        The demonstrations.
    epsilon, distance, weights, n_points, return_mask
        As in :func:`simplify`, shared by all trajectories.
    times : sequence of array-like of shape (n_samples_j,), optional
        One time vector per trajectory, for ``distance="sed"``.
    n_jobs : int, optional
        Number of threads; ``None`` means ``os.cpu_count()``, ``1`` runs in
        the calling thread.

    Returns
    -------
    results : list of ndarray
        One result per trajectory, as :func:`simplify` would return it.

    Examples
    --------
    >>> demos = [[[0, 0], [1, 1], [2, 0]], [[0, 0], [1, 0], [2, 0]]]
    >>> simplify_many(demos, 0.5)
    [array([0, 1, 2]), array([0, 2])]
    """
    if isinstance(trajectories, np.ndarray) and trajectories.ndim == 2:
        raise ValidationError(
            "trajectories must be a sequence of (n_samples, n_dims) arrays; got"
            f" one array of shape {trajectories.shape} (use simplify for one"
            " trajectory)"
        )
    try:
        trajs = list(trajectories)
    except TypeError:
        raise ValidationError(
            "trajectories must be a sequence of (n_samples, n_dims) arrays; got"
            f" {type(trajectories).__name__}"
        ) from None
    if times is None:
        tlist = [None] * len(trajs)
    else:
        tlist = list(times)
        if len(tlist) != len(trajs):
            raise ValidationError(
                f"times must hold one time vector per trajectory ({len(trajs)});"
                f" got {len(tlist)}"
            )
    if n_jobs is None:
        workers = os.cpu_count() or 1
    else:
        workers = check_positive_int(n_jobs, "n_jobs")
    jobs = [
        _prepare(
            p,
            epsilon,
            distance,
            weights,
            t,
            n_points,
            name=f"trajectories[{j}]",
            times_name=f"times[{j}]",
        )
        for j, (p, t) in enumerate(zip(trajs, tlist, strict=True))
    ]

    def one(job):
        return _output(_run(job, 1), return_mask)

    if workers == 1 or len(jobs) < 2:
        return [one(job) for job in jobs]
    # the persistent pool: starting threads per call costs more than a short
    # demonstration's reduction (one() never submits to the pool itself)
    return list(thread_pool(min(workers, len(jobs))).map(one, jobs))
