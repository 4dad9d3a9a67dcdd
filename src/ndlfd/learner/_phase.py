"""The phase of a via point or a prefix: the blend's clock warped to meet it.

A held-out execution that is slow or fast is, at a given time, at another
phase of the motion than the blend. Shifting the blend in space onto a via
point then dents it towards a point the blend passes elsewhere, and a prefix
is continued from the wrong phase. So, before the blend is conditioned and
the remaining offsets are faded (:mod:`ndlfd.learner._via`), its clock is
warped:

* *via points* (:func:`via_clock`): for each via point, the phase ``p`` at
  which the (start-conditioned) blend passes closest to it, searched where
  the warp stays monotone; the blend is then read at ``phi(tau) = tau +
  delta(tau)``, ``delta`` equal to ``p - tau_v`` at each via time and faded to
  zero at the ends and between via points by minimum-jerk pieces
  (:func:`~ndlfd.learner._conditioning.fade_pieces`), so the clock is smooth,
  starts at 0 and ends at 1. Its slope is kept at least
  :data:`MIN_RATE` and its curvature within :data:`MAX_BEND`. A via point
  near a hold of the blend (a grasp: :data:`HOLD_REACH`) is read at the
  hold's start instead, the curvature within :data:`HOLD_BEND` times as
  much (:func:`_rest_start`): the path holds it as the demonstrations do;
* *a prefix* (:func:`prefix_clock`): the blend's rate ``s`` (phase per unit of
  time) that best matches the observed samples' shape (least squares, the
  mean offset taken out, over up to
  :data:`~ndlfd.learner._via.PREFIX_POINTS` of them, ``s`` on a grid of
  :data:`RATES`); the clock is ``s * tau`` over the prefix, then runs
  linearly from the phase reached at the last observed sample to 1, or,
  where that would run faster than :data:`MAX_PACE` times the prefix's
  pace (a late robot near its plan's end), on within that bound to rest
  at the plan's end, short of the route's end (:func:`prefix_warp`).
"""

from __future__ import annotations

import numpy as np

from ._conditioning import fade_pieces, minimum_jerk
from ._rests import HOLD_SPAN, rest_windows

__all__ = [
    "HOLD_BEND",
    "HOLD_REACH",
    "HOLD_SPAN",
    "MAX_BEND",
    "MAX_PACE",
    "MIN_RATE",
    "RATES",
    "SLACK",
    "prefix_clock",
    "prefix_warp",
    "via_clock",
    "warp_clock",
    "warp_for",
]

#: The warped clock's least slope (phase per unit of time) between via points.
MIN_RATE = 0.5

#: The warped clock's largest curvature (phase per unit of time squared): a
#: via point's phase shift is at most this times the squared width of each of
#: its two pieces over a minimum-jerk ramp's largest curvature. The shift
#: speeds the path up and slows it down as its second derivative, so a short
#: piece (a via point early or late in the motion) may shift the clock little.
#: 1,000 via points within 3 spreads (``benchmarks/bench_envelope.py``),
#: largest acceleration over the envelope, unbounded -> 2 (speed in brackets):
#: LASA Angle 2.34 -> 2.13 (1.71 -> 1.53), Sshape 1.59 -> 1.14, Worm 2.08 ->
#: 1.80 (1.87 -> 1.58), the arcs of tests/learner/test_learner_envelope.py 3.33
#: -> 2.50. Held-out LASA, protocol via, ndlfd's median DTW per shape: the
#: same on every shape but JShape_2 (1.084 times); with 3, on every shape
#: (arcs 3.11); with 1, 1.03 times in geometric mean (arcs 2.37).
MAX_BEND = 2.0

#: A via point's phase shift is shrunk by this much (soft threshold): a shift
#: within the closest-pass search's noise leaves the clock alone.
SLACK = 0.01

#: A via point this little before a hold's start (a share of the motion),
#: or in the hold, is read at the hold's start however near its closest
#: pass is elsewhere (:func:`_rest_start`): a grasp off the demonstrations'
#: places passes closer to their approach, and in joint space to another
#: pose altogether (a planar arm: the place pose, 0.3 of the motion later).
#: The grasp sets of ``tests/learner/test_learner_rests.py`` (each phase's
#: duration +-15 %) start their holds up to 0.07 from the blend's. Via
#: points after a hold's end are not (held-out pick-and-place, protocol
#: via, halfway: median DTW 0.0199 -> 0.0291 when they were).
HOLD_REACH = 0.1

#: A via point read at a hold's start may bend the clock this many times
#: :data:`MAX_BEND`: an execution that reaches its grasp early hurries to
#: it. 40 grasp sets (``benchmarks/probe_rests.py``), largest drift over the
#: hold in joint space: 72.1 mm with 1 (the clock short of the hold, the
#: hand went on down after the via point), 2.1 mm with 3 and with 4;
#: Cartesian 1.6 mm with each.
HOLD_BEND = 3.0

#: After a prefix the clock runs at most this times the prefix's pace
#: (its rate, or 1 if slower: :func:`prefix_warp`). A robot late near the
#: end of its plan (replanned at 10 Hz, plans 0.85 times the execution) had
#: the route's last 17 % run in its last 5 samples: steps 3.9 times the
#: demonstrations' largest over their last 10 % (``synth.obstacle``; LASA
#: Multi_Models_1 75 times, at 1.0 up to 17 times: 3 samples of 1,000 left).
#: With this bound: at most 0.83 (the execution's own noisy steps) and 1.59
#: (the plan's steps at most 1.5 times the execution's own last ones); 1.5
#: gave 1.88 on LASA.
MAX_PACE = 1.25

#: The rates a prefix's phase is searched over (phase per unit of time).
RATES = np.linspace(0.6, 1.6, 41)

#: The grid a stopping clock's slope is kept within its bound on.
_EASE_GRID = 201

#: Candidate phases a via point's closest pass is searched over.
_GRID = 401

#: A minimum-jerk ramp's largest slope (at its middle), for the monotone bound.
_MJ_SLOPE = 1.875

#: A minimum-jerk ramp's largest curvature (at ``1/2 -+ sqrt(3)/6``).
_MJ_CURVATURE = 10.0 / np.sqrt(3.0)


def warp_clock(at: np.ndarray, taus, deltas) -> np.ndarray:
    """The warped clock ``at + delta(at)``, ``delta`` faded between its knots.

    Parameters
    ----------
    at : ndarray of shape (n_rows,)
        Normalized times.
    taus : ndarray of shape (n_knots,)
        Increasing knot times, ``0`` first and ``1`` last.
    deltas : ndarray of shape (n_knots,)
        The clock's shift at each knot (``0`` at the ends).

    Returns
    -------
    phase : ndarray of shape (n_rows,)

    Examples
    --------
    >>> warp_clock(np.array([0.0, 0.25, 0.5, 1.0]), [0.0, 0.5, 1.0], [0.0, -0.1, 0.0])
    array([0. , 0.2, 0.4, 1. ])
    """
    taus = np.asarray(taus, dtype=np.float64)
    deltas = np.asarray(deltas, dtype=np.float64)[:, None]
    return np.clip(at + fade_pieces(at, taus, deltas)[:, 0], 0.0, 1.0)


def via_clock(mean, via_taus, targets) -> tuple[np.ndarray, np.ndarray]:
    """Knots of the clock that brings the blend to each via point at its time.

    Parameters
    ----------
    mean : callable
        ``mean(phases) -> ndarray of shape (n, n_columns)``: the blend at
        normalized phases (normalized units).
    via_taus : sequence of float
        The via points' normalized times, increasing, inside ``(0, 1)``
        (others are left unwarped).
    targets : sequence of (list of int, ndarray)
        Each via point's columns and values (normalized units).

    Returns
    -------
    taus, deltas : ndarray of shape (n_knots,)
        For :func:`warp_clock`.

    Examples
    --------
    A blend that runs along a line reaches 0.45 at phase 0.45; a via point at
    0.45 at time 0.5 warps the clock back by 0.05, less :data:`SLACK`:

    >>> taus, deltas = via_clock(lambda p: p[:, None], [0.5], [([0], np.array([0.45]))])
    >>> taus, np.round(deltas, 3)
    (array([0. , 0.5, 1. ]), array([ 0.  , -0.04,  0.  ]))

    At time 0.2 the clock may move back by at most ``MAX_BEND * 0.2**2 /
    (10 / sqrt(3))``, 0.0139 (0.0125 on the search's grid of 1/400), less
    :data:`SLACK`:

    >>> taus, deltas = via_clock(lambda p: p[:, None], [0.2], [([0], np.array([0.1]))])
    >>> np.round(deltas, 4)
    array([ 0.    , -0.0025,  0.    ])
    """
    grid = np.linspace(0.0, 1.0, _GRID)
    U = mean(grid)
    taus, deltas = [0.0], [0.0]
    for tau, (cols, target) in zip(via_taus, targets, strict=True):
        if not 0.0 < tau < 1.0 or tau - taus[-1] <= 0.0:
            continue
        # monotone: a piece's slope is 1 + (change of delta) * ramp slope /
        # width; its curvature (change of delta) * ramp curvature / width^2
        before, after = tau - taus[-1], 1.0 - tau
        slope, bend = (1.0 - MIN_RATE) / _MJ_SLOPE, MAX_BEND / _MJ_CURVATURE
        lo = deltas[-1] - min(slope * before, bend * before**2)
        hi = deltas[-1] + bend * before**2
        lo = max(lo, -bend * after**2)  # and back to 0 at the end
        hi = min(hi, slope * after, bend * after**2)
        # where they cross (an earlier shift too large for the pieces left)
        # the curvature gives way, never the slope
        lo = min(lo, hi)
        d = np.sum((U[:, cols] - target) ** 2, axis=1)
        ok = (grid - tau >= lo) & (grid - tau <= hi)
        cand = np.flatnonzero(ok)
        if cand.size == 0:  # a window narrower than the grid: its nearest
            p = tau + min(max(0.0, lo), hi)
        else:  # the closest pass; ties to the phase nearest the via time
            best = cand[np.lexsort((np.abs(grid[cand] - tau), d[cand]))[0]]
            p = grid[best]
            if 0 < best < _GRID - 1 and ok[best - 1] and ok[best + 1]:
                # between grid points: the vertex of the parabola through three
                a, b, c = d[best - 1], d[best], d[best + 1]
                curv = a - 2.0 * b + c
                if curv > 0.0:
                    p += 0.5 * (a - c) / curv * (grid[1] - grid[0])
        # a hold may bend the clock further (HOLD_BEND): its start is exact
        held = bend * HOLD_BEND / MAX_BEND
        hlo = deltas[-1] - min(slope * before, held * before**2)
        hhi = min(deltas[-1] + held * before**2, slope * after, held * after**2)
        hlo = min(max(hlo, -held * after**2), hhi)
        p, hold = _rest_start(p, tau, U[:, cols], grid, (tau + lo, tau + hi),
                              (tau + hlo, tau + hhi))  # fmt: skip
        taus.append(float(tau))
        # soft-thresholded: a phase within the search's noise is left alone;
        # but never before a hold's start (read on the approach's slow end,
        # the path went on down after the via point)
        delta = float(np.sign(p - tau) * max(abs(p - tau) - SLACK, 0.0))
        deltas.append(max(delta, p - tau) if hold else delta)
    taus.append(1.0)
    deltas.append(0.0)
    return np.array(taus), np.array(deltas)


def _rest_start(p: float, tau: float, U: np.ndarray, grid: np.ndarray, near, far):
    """The phase a via point is read at when the blend rests near it.

    Where the blend holds still (a grasp) every phase of the rest passes the
    via point equally close, and a via point at a grasp off the
    demonstrations' places passes closer to their approach (above or beside
    the object, or, in joint space, to another pose altogether) than to
    their rest: read there, the path went on with the approach after the
    via point and sank below it. So a rest of the blend
    (:func:`~ndlfd.learner._rests.rest_windows`) that holds the closest pass
    ``p`` is where the via point is read, at the rest's start; and a hold
    (:data:`HOLD_SPAN` long at least) that is at least as near the via
    point's time ``tau`` as ``p`` is, or that ``tau`` falls in or at most
    :data:`HOLD_REACH` before, is read at its start, on a clock that may
    bend :data:`HOLD_BEND` times more (and never before the start: the
    soft threshold :data:`SLACK` only moves it into the hold): the path
    holds the via point over the whole rest as the demonstrations do.
    The start is the rest's first phase as close to its place (its median)
    as its phases are in the median (the slow end of the approach is not yet
    the rest: read there, the path sank with the blend's last millimetres of
    approach), or the nearest allowed one.

    Parameters
    ----------
    p : float
        The closest pass.
    tau : float
        The via point's time.
    U : ndarray of shape (n_grid, n_cols)
        The blend at the phases ``grid``, the via point's columns.
    grid : ndarray of shape (n_grid,)
    near, far : tuple of float
        The phases allowed (``lo, hi``), for a rest and for a hold.

    Returns
    -------
    phase : float
    hold : bool
        The phase is a hold's start (soft-thresholded into the hold only).

    Examples
    --------
    Moving, a rest from 0.45 to 0.55, moving again:

    >>> grid = np.linspace(0.0, 1.0, 21)
    >>> U = np.r_[np.arange(8.0), np.full(5, 8.0), np.arange(9.0, 17.0)][:, None]
    >>> _rest_start(0.5, 0.5, U, grid, (0.0, 1.0), (0.0, 1.0))  # in it: its start
    (0.45, True)
    >>> _rest_start(0.5, 0.5, U, grid, (0.48, 1.0), (0.47, 1.0))  # the earliest
    (0.47, True)
    >>> _rest_start(0.2, 0.38, U, grid, (0.0, 1.0), (0.0, 1.0))  # near in time
    (0.45, True)
    >>> _rest_start(0.2, 0.3, U, grid, (0.0, 1.0), (0.0, 1.0))  # the pass nearer
    (0.2, False)
    """
    for a, b in rest_windows(U, grid):
        long = bool(b - a >= HOLD_SPAN)
        lo, hi = far if long else near
        if b < lo or a > hi:
            continue
        gap = max(a - tau, tau - b, 0.0)
        soon = a - HOLD_REACH <= tau <= b  # before the hold ends, not after
        if not (a <= p <= b or (long and (gap <= abs(p - tau) or soon))):
            continue
        rows = np.flatnonzero((grid >= a) & (grid <= b))
        d = np.linalg.norm(U[rows] - np.median(U[rows], axis=0), axis=1)
        start = float(grid[rows[np.argmax(d <= np.median(d))]])
        return float(min(max(start, lo, 0.0), hi)), long
    return p, False


def prefix_clock(mean, prefix_taus, values, cols) -> float:
    """The blend's rate over a prefix: phase per unit of time, from :data:`RATES`.

    Parameters
    ----------
    mean : callable
        As for :func:`via_clock`.
    prefix_taus : ndarray of shape (n_points,)
        Normalized times of prefix samples (the last one the last observed).
    values : ndarray of shape (n_points, len(cols))
        Their values (normalized units).
    cols : list of int

    Returns
    -------
    rate : float
        Least total squared distance once the mean offset is taken out (a
        prefix executed beside the blend at its pace has rate 1; measured
        on LASA, taking out half of it instead scored better but found rate
        1.225 for such a prefix); ties to the rate nearest 1.

    Examples
    --------
    >>> taus = np.linspace(0.0, 0.3, 4)
    >>> float(prefix_clock(lambda p: p[:, None], taus, (0.8 * taus)[:, None], [0]))
    0.8
    """
    last = float(prefix_taus[-1])
    rates = RATES[RATES * last < 1.0]
    if rates.size == 0:
        return 1.0
    P = mean((rates[:, None] * prefix_taus[None, :]).ravel())[:, cols]
    P = P.reshape(rates.size, len(prefix_taus), len(cols))
    R = P - values[None]  # an offset in space is no evidence of phase
    cost = np.sum((R - R.mean(axis=1, keepdims=True)) ** 2, axis=(1, 2))
    return float(rates[np.lexsort((np.abs(rates - 1.0), cost))[0]])


def prefix_warp(at: np.ndarray, last: float, rate: float) -> np.ndarray:
    """The prefix's clock: ``rate * at`` up to ``last``, then on towards 1.

    After ``last`` the clock runs linearly from the phase reached,
    ``rate * last``, to 1, unless that is faster than :data:`MAX_PACE`
    times the prefix's pace (``max(1, rate)``): then it leaves at the
    prefix's rate, speeds up to at most that bound and eases to rest at the
    plan's end (:func:`_eased_rest`), short of the route's end.

    Parameters
    ----------
    at : ndarray of shape (n_rows,)
        Normalized times.
    last : float
        The last observed sample's normalized time, in ``[0, 1)``.
    rate : float
        The prefix's rate (:func:`prefix_clock`), ``rate * last < 1``.

    Returns
    -------
    phase : ndarray of shape (n_rows,)

    Examples
    --------
    >>> prefix_warp(np.array([0.0, 0.5, 1.0]), 0.5, 0.8)
    array([0. , 0.4, 1. ])

    Late in the motion the rest of the route does not fit: the clock runs on
    at most 1.25 times the prefix's pace and comes to rest short of 1:

    >>> np.round(prefix_warp(np.array([0.9, 0.95, 1.0]), 0.9, 0.8), 3)
    array([0.72 , 0.774, 0.801])
    """
    at = np.asarray(at, dtype=np.float64)
    reached, left = rate * last, 1.0 - last
    need = (1.0 - reached) / left if left > 0.0 else 0.0
    if need <= MAX_PACE * max(1.0, rate):  # the rest of the route fits
        after = reached + (at - last) * need
    else:
        u = np.clip((at - last) / left, 0.0, 1.0)
        after = reached + left * _eased_rest(u, rate, MAX_PACE * max(1.0, rate))
    return np.clip(np.where(at <= last, rate * at, after), 0.0, 1.0)


def _eased_rest(u: np.ndarray, start: float, most: float) -> np.ndarray:
    """A clock that leaves at slope ``start``, stays within ``most`` and stops.

    Its slope is ``start * (1 - minimum_jerk(u)) + b * 30 u^2 (1 - u)^2``
    (the minimum-jerk ramp's own slope), ``b`` the largest that keeps it
    within ``most`` (on a grid of :data:`_EASE_GRID`): twice differentiable,
    monotone, at rest at ``u = 1``, having gone ``start / 2 + b``.

    Parameters
    ----------
    u : ndarray of shape (n,)
        Times in ``[0, 1]``.
    start, most : float
        The slope at ``u = 0`` and the largest, ``0 <= start <= most``.

    Returns
    -------
    progress : ndarray of shape (n,)

    Examples
    --------
    Leaving at 1, never faster than 2: it speeds up, then stops.

    >>> u = np.linspace(0.0, 1.0, 5)
    >>> p = _eased_rest(u, 1.0, 2.0)
    >>> np.round(p, 3), bool(np.all(np.diff(p) > 0))
    (array([0.   , 0.322, 0.802, 1.174, 1.26 ]), True)
    """
    grid = np.linspace(0.0, 1.0, _EASE_GRID)[1:-1]
    bump = 30.0 * grid**2 * (1.0 - grid) ** 2
    b = max(0.0, float(np.min((most - start * (1.0 - minimum_jerk(grid))) / bump)))
    ramp = u - 2.5 * u**4 + 3.0 * u**5 - u**6  # the integral of 1 - minimum_jerk
    return start * ramp + b * minimum_jerk(u)


def warp_for(mean, at: np.ndarray, obs_tau: np.ndarray, observed, *, prefix: bool):
    """The phases to read the blend at, for its rows and its observations.

    Parameters
    ----------
    mean : callable
        As for :func:`via_clock`.
    at : ndarray of shape (n_rows,)
        The output rows' normalized times.
    obs_tau : ndarray of shape (n_obs,)
        The observations' normalized times
        (:func:`~ndlfd.learner._via.blend_observations`).
    observed : list of (int, list of int, ndarray)
        Their indices into ``obs_tau``, columns and values.
    prefix : bool
        The observations are a prefix's samples (:func:`prefix_clock`), not a
        start and via points (:func:`via_clock`).

    Returns
    -------
    phase_at : ndarray of shape (n_rows,)
    phase_obs : ndarray of shape (n_obs,)
    """
    if prefix:
        cols = observed[0][1]
        values = np.array([v for _, _, v in observed])
        rate = prefix_clock(mean, obs_tau, values, cols)
        last = float(obs_tau[-1])
        return prefix_warp(at, last, rate), prefix_warp(obs_tau, last, rate)
    taus, deltas = via_clock(mean, obs_tau, [(c, v) for _, c, v in observed])
    return warp_clock(at, taus, deltas), warp_clock(obs_tau, taus, deltas)
