"""How a via point's conditioning reads the templates: chosen by leaving each out.

Two readings of the templates serve a via point (with its start and goal):

* *by place* (the default): every template is aligned to the decoded skeleton
  by place (:mod:`ndlfd.learner._blend`), the blend's clock is warped to the
  via point's closest pass (:mod:`ndlfd.learner._phase`), and the
  conditioning trusts an observation as much as the templates vary there
  (:data:`~ndlfd.learner._blend.CONDITION_RIDGE`), following it up to
  :data:`~ndlfd.learner._blend.CONDITION_REACH`. Where the demonstrations
  vary at random (LASA), this predicts a held-out one best;
* *by clock*: every template of the route, weighing the same, on its own
  clock (:func:`~ndlfd.learner._frames.clock_aligned`), no clock warp, and the
  conditioning trusts the observations almost fully (:data:`CLOCK_RIDGE`,
  no reach limit). Where the demonstrations vary with a task parameter the
  points show (an object's place: ``synth.pick_place``), the rest of the path
  is then as linear in them as ProMP's conditional makes it.

:func:`prefers_clock` decides per call, from the templates themselves: each
template in turn is left out, the others are conditioned on its values at the
observations' times (on its own clock, as an execution is observed), the
offsets left at the observations are faded linearly between them (as the
path's own fades reach them), and the reading whose predictions of its
position over the whole motion are closer (weighted by the templates'
weights) is followed.

A start and a goal among the demonstrations' (:func:`frame_ends`) are frames
the templates move with (:func:`end_frame_shift`): each phase follows the
view (the world, seen from the start, seen from the goal) in which the
templates agree; what the views leave of each template is regressed on its
ends where leaving each out says it helps (:func:`end_slopes`: a board's
turn, as far as its goal's place tells it); and a route split off a spread
that is one route seen from the ends is read whole (:func:`frame_routes`,
:func:`route_mates`).
"""

from __future__ import annotations

import numpy as np

from .._pose_groups import orientation_blocks
from ._blend import (
    CONDITION_GRID,
    CONDITION_REACH,
    CONDITION_RIDGE,
    condition_coefficients,
    output_step,
    warped,
)
from ._conditioning import condition_target, group_columns
from ._curves import route_curves
from ._extrapolation import FAR_SPREADS, envelope_distance
from ._frames import clock_aligned
from ._routes import route_columns, route_labels
from ._via import blend_observations

__all__ = [
    "CLOCK_MARGIN",
    "CLOCK_RIDGE",
    "END_FAR",
    "END_FLOOR",
    "END_SLOPE_RIDGE",
    "END_SMOOTH",
    "END_SPREAD",
    "end_frame_shift",
    "end_observations",
    "end_slopes",
    "frame_ends",
    "frame_routes",
    "plan_end_shift",
    "prefers_clock",
    "route_mates",
    "via_frame_mix",
    "via_plan",
]

#: The observations' noise of the clock reading (a share of the templates'
#: mean variance at them, as :data:`~ndlfd.learner._blend.CONDITION_RIDGE`).
CLOCK_RIDGE = 0.01

#: The clock reading is followed when its held-out error is below this share
#: of the place reading's. Measured (``ndlfd evaluate``, ndlfd and ProMP in
#: one run) with a first version that read the via point's own weighted
#: templates by clock: the error ratio clock / place per call had quartiles
#: 1.34, 2.10, 3.26 on LASA's via protocol (12 % of calls below 1, 2 % below
#: 0.5) and 0.02-0.04 on the translated pick-and-place set's task protocol;
#: the LASA via ratio to ProMP (single shapes) was 0.601 with 1, 0.582 with
#: 0.5 and 0.580 with 0.25 (unchanged; Multi_Models 0.657 throughout). With
#: the route's templates weighing evenly (this version) and 0.25: LASA via
#: 0.580 / 0.657, the pick-and-place task 0.914 (translated) and 0.891
#: (turned by up to 60 deg) times ProMP's DTW, from 2.16 and 0.891.
CLOCK_MARGIN = 0.25

#: The least spread of the demonstrations' ends :func:`frame_ends` measures a
#: start or goal in (normalized units: 1 % of the range, the spread of
#: :data:`END_FLOOR`). With 0.1 %, a column the demonstrations hold up to
#: their noise (a board's height, a home) made 10 of 60 goals and starts of
#: ``synth.task_board`` (6 demonstrations, leave one out) not frames; start
#: and goal over the better peer (benchmarks/probe_board.py, 10 seeds) 0.74,
#: 0.92, 0.84 for 5, 6, 7 demonstrations, with 1 % 0.74, 0.82, 0.82.
END_SPREAD = 1e-2

#: How many times :data:`~ndlfd.learner._extrapolation.FAR_SPREADS` a start
#: or goal may lie from the nearest demonstration's and be a frame: the
#: views move the templates rigidly and :func:`end_slopes` goes no farther
#: than the farthest template, so a goal a few spreads out is still read by
#: them. Leaving one out of ``synth.task_board``, 4 % of goals lie beyond 3
#: spreads of the others (up to 5.2, the spread of 4 to 6 goals being
#: uncertain), and the faded offset missed them by twice the faded mean's
#: DTW; boards 10-19 (benchmarks/probe_board.py's run), start and goal over
#: the better peer: 0.89, 0.96, 0.87 for 5, 6, 7 demonstrations with 1,
#: 0.80, 0.90, 0.87 with 2 (boards 0-9 unchanged).
END_FAR = 2.0

#: The variance added to every view of :func:`end_frame_shift` (normalized
#: units squared: a spread of 1 % of the range).
END_FLOOR = 1e-4

#: Half-width of the averages of :func:`end_frame_shift` (twice), as a share
#: of the distance the templates travel. Measured on the arcs of
#: tests/learner/test_learner_envelope.py (goals 3 spreads off): the largest
#: acceleration over the demonstrations' envelope 1.41 with 0.04, 1.30 with
#: 0.08, 1.35 with 0.1, 1.01 with 0.15 (speed 0.88 throughout); on
#: ``synth.task_board`` (benchmarks/probe_board.py, 10 seeds) the DTW moved
#: by at most 3 % between them.
END_SMOOTH = 0.15

#: The ridge of :func:`end_slopes` (a share of the ends' mean variance).
#: ``synth.task_board``, start and goal, leave one out, 10 seeds
#: (benchmarks/probe_board.py), ndlfd over the better peer for 5, 6, 7
#: demonstrations: 0.85, 1.04, 1.04 without the regression; 0.74, 1.02, 0.87
#: with 1; 0.75, 1.03, 0.92 with 3 (without the leave-one-out test 0.64,
#: 1.04, 0.88 with 1, but a goal 3 spreads off the arcs of
#: tests/learner/test_learner_envelope.py then took 2.3 times the
#: demonstrations' acceleration). One route (``n_routes=1``): 0.79, 0.89, 0.85;
#: with :func:`route_mates` (a route split off the board's spread read
#: whole): 0.74, 0.92, 0.84.
END_SLOPE_RIDGE = 1.0

#: Phases the held-out templates' positions are compared on.
_GRID = np.linspace(0.0, 1.0, 101)


def _faded(resid_at, n_cols: int) -> np.ndarray:
    """Offsets known at some phases, linear between them, zero at free ends."""
    out = np.zeros((_GRID.size, n_cols))
    for c, pts in resid_at.items():
        taus = sorted(pts)
        xs = [0.0] * (taus[0] > 0.0) + taus + [1.0] * (taus[-1] < 1.0)
        ys = [0.0] * (taus[0] > 0.0) + [pts[x] for x in taus] + [0.0] * (taus[-1] < 1.0)
        out[:, c] = np.interp(_GRID, xs, ys)
    return out


def _held_out_error(W, w, truth, obs_tau, observed, pos, ridge, reach) -> float:
    """Weighted squared position error of each template predicted by the others."""
    n, n_grid = W.shape[0], _GRID.size
    total = 0.0
    for j in range(n):
        keep = np.arange(n) != j
        if w[j] <= 0 or w[keep].sum() <= 0:
            continue
        wk, Wk = w[keep] / w[keep].sum(), W[keep]
        mean = np.tensordot(wk, Wk, axes=1)
        obs = [(n_grid + k, c, truth[j, n_grid + k, c]) for k, c, _ in observed]
        coef = condition_coefficients(Wk, wk, mean, obs, ridge, reach)
        pred = mean + np.tensordot(coef, Wk - mean[None], axes=1)
        resid_at: dict = {}
        for k, cols, _ in observed:
            for c in set(cols) & set(pos):
                r = n_grid + k
                resid_at.setdefault(c, {})[float(obs_tau[k])] = (
                    truth[j, r, c] - pred[r, c]
                )
        pred = pred[:n_grid] + _faded(resid_at, W.shape[2])
        err = truth[j, :n_grid][:, pos] - pred[:, pos]
        total += w[j] * float(np.sum(err * err))
    return total


def prefers_clock(
    place, place_truth, clock, obs_tau, observed, pos, quat_cols=None, step=None
) -> bool:
    """Whether the held-out templates are predicted better by the clock reading.

    Parameters
    ----------
    place : tuple
        ``(values, taus, index, weights, knots)`` as
        :func:`~ndlfd.learner._blend.blend` takes them, matched by place
        (the via point's plan).
    place_truth : list of ndarray
        The same templates matched by time
        (:func:`~ndlfd.learner._frames.clock_aligned`): each one as an
        execution is observed, what it is predicted against.
    clock : tuple
        As ``place``, matched by time; its templates may be others and
        weigh otherwise (the route's, evenly).
    obs_tau : ndarray of shape (n_obs,)
        The observations' normalized times.
    observed : list of (int, list of int, ndarray)
        Each one's index into ``obs_tau``, its columns and its values.
    pos : list of int
        The position columns (the error is measured on them).
    quat_cols, step
        As :func:`~ndlfd.learner._blend.blend`'s.

    Returns
    -------
    clock : bool
        ``True`` when the clock reading's error is below
        :data:`CLOCK_MARGIN` times the place reading's; ``False`` when either
        has fewer than three templates of positive weight (too few to leave
        one out) or nothing of the position is observed.
    """
    if not pos or any(
        np.count_nonzero(np.asarray(t[3]) > 0) < 3 for t in (place, clock)
    ):
        return False
    rows = np.concatenate([_GRID, obs_tau])
    values, taus, index, weights, knots = place
    Wp, wp = warped(values, taus, index, weights, knots, rows, quat_cols, None, step)
    Tp, _ = warped(
        values, taus, place_truth, weights, knots, rows, quat_cols, None, step
    )
    values, taus, index, weights, knots = clock
    Wc, wc = warped(values, taus, index, weights, knots, rows, quat_cols, None, step)
    err_place = _held_out_error(Wp, wp, Tp, obs_tau, observed, pos, CONDITION_RIDGE,
                                CONDITION_REACH)  # fmt: skip
    err_clock = _held_out_error(Wc, wc, Wc, obs_tau, observed, pos, CLOCK_RIDGE, np.inf)
    return bool(err_clock < CLOCK_MARGIN * err_place)


def end_observations(est, start, goal) -> list:
    """A start's and a goal's positions, normalized, at phases 0 and 1.

    Returns
    -------
    ends : list of (float, list of int, ndarray)
        Each one's phase, its columns and its values normalized as the
        templates are (unweighted) (:func:`end_frame_shift`'s ``ends``).
    """
    ends = []
    for tau, cond in ((0.0, start), (1.0, goal)):
        if cond is None or "position" not in cond:
            continue
        cols, target = condition_target(
            {"position": cond["position"]}, est.scaler_, est.column_groups_
        )
        ends.append((tau, cols, target))
    return ends


def frame_ends(est, start, goal) -> tuple:
    """The start and goal that are frames: those among the demonstrations'.

    A start's (goal's) position is a frame the templates move with when it
    lies within :data:`END_FAR` times
    :data:`~ndlfd.learner._extrapolation.FAR_SPREADS` of the
    nearest demonstration's first (last) sample, in units of how those
    samples spread (their standard deviation, at least :data:`END_SPREAD` of
    the range): the demonstrations show how the path co-varies with it
    there. Farther, the co-variation would be extrapolated (a start 30 times
    as far as the demonstrations' starts spread), and the offset is only
    faded, as before the frames.

    Returns
    -------
    start, goal : dict or None
        Each condition's position, or ``None``.
    """
    out = []
    for cond, ends in ((start, est.first_values_), (goal, est.last_values_)):
        if cond is None or "position" not in cond:
            out.append(None)
            continue
        cols, target = condition_target(
            {"position": cond["position"]}, est.scaler_, est.column_groups_
        )
        pts = np.asarray(ends, dtype=np.float64)[:, cols]
        near = envelope_distance(target, pts, END_SPREAD)[0] <= END_FAR * FAR_SPREADS
        out.append({"position": cond["position"]} if near else None)
    return tuple(out)


def _progress(values, taus, weights, grid) -> np.ndarray:
    """How far the templates' weighted mean has gone at each phase (0 to 1)."""
    mean = _mean_on(values, taus, weights, grid)
    step = np.sqrt(np.sum(np.diff(mean, axis=0) ** 2, axis=1))
    total = np.r_[0.0, np.cumsum(step)]
    return total / total[-1] if total[-1] > 0 else grid.copy()


def _progress_average(U: np.ndarray, progress: np.ndarray, half: float) -> np.ndarray:
    """Each row's mean over the rows within ``half`` of its progress.

    Where the path rests (its progress does not change) the mean is the
    same: a shift so averaged changes only where the path moves.
    """
    c = np.concatenate([np.zeros((1, U.shape[1])), np.cumsum(U, axis=0)])
    lo = np.searchsorted(progress, progress - half, side="left")
    hi = np.searchsorted(progress, progress + half, side="right")
    return (c[hi] - c[lo]) / (hi - lo)[:, None]


def end_frame_shift(
    values,
    taus,
    weights,
    rows,
    ends,
    floor: float,
    smooth: float = 0.0,
    slope_ridge: float | None = None,
) -> np.ndarray:
    """The shift a start and a goal give as frames the templates move with.

    Each template is seen three ways at every phase of ``rows`` (on its own
    clock): as it is (the world), less its first sample (the start's frame)
    and less its last (the goal's frame). Each view predicts the path: the
    world its weighted mean, a frame the requested point plus the templates'
    mean seen from it; the views are combined per phase as a product of
    Gaussians, each weighed by the inverse of the templates' spread in it
    (their weighted variance summed over the observed columns, plus
    ``floor``: a view is a frame the whole position is seen from).
    Where the demonstrations agree seen from the goal (a task on a board that
    moved with it) the path moves with the goal; where they agree in the
    world (a fixed home) it stays.

    Parameters
    ----------
    values, taus : list of ndarray
        The templates' normalized values (n_j, n_cols) and times (n_j,).
    weights : ndarray of shape (n_templates,)
    rows : ndarray of shape (n_rows,)
        The phases to shift.
    ends : list of (float, list of int, ndarray)
        The start (phase 0) and goal (phase 1): each phase, its columns and
        its normalized values (:func:`end_observations`).
    floor : float
        Added to every view's variance (the spread below which views are
        not told apart).
    smooth : float, default=0.0
        With ``smooth > 0`` the shift is computed on
        :data:`~ndlfd.learner._blend.CONDITION_GRID` phases, averaged twice
        over the phases within ``smooth`` of the distance travelled either
        side (by the templates' weighted mean): where one view takes over
        from another the path does not hurry, and where the templates rest
        the shift does not change; then read at ``rows``.
    slope_ridge : float, optional
        With it (and three templates or more), what the views leave of each
        template given its own ends (averaged as the shift is) is regressed
        on its ends (:func:`end_slopes`, this ridge) and the prediction at
        the requested ends added: how the path co-varies with them otherwise
        than as a frame (a board's turn, as far as the goal's place tells it).

    Returns
    -------
    shift : ndarray of shape (n_rows, n_cols)
        Of the combined prediction from the world view's, zero in the
        columns not observed.

    Examples
    --------
    Two templates along a line, one 1.5 times the other: given the longer's
    goal, the path leaves the start as both do (they agree there in the
    world) and moves with the goal as it nears it (they agree seen from it;
    at half way both views are as tight, and the shift is half).

    >>> tau = np.linspace(0.0, 1.0, 5)
    >>> a = np.column_stack([tau]); b = np.column_stack([1.5 * tau])
    >>> shift = end_frame_shift([a, b], [tau, tau], np.ones(2), tau,
    ...                         [(1.0, [0], np.array([1.5]))], 1e-6)
    >>> np.round(shift[:, 0], 3)
    array([0.   , 0.025, 0.125, 0.225, 0.25 ])
    """
    n_cols = values[0].shape[1]
    if not ends:
        return np.zeros((rows.size, n_cols))
    w = np.asarray(weights, dtype=np.float64)
    w = w / w.sum()
    grid = np.linspace(0.0, 1.0, CONDITION_GRID) if smooth > 0 else rows
    cols, combined, owns, news = _end_views(values, taus, w, grid, ends, floor)
    world = combined(None)
    on = np.zeros((grid.size, n_cols))
    on[:, cols] = combined(news) - world
    slopes = slope_ridge is not None and len(values) >= 3
    if slopes:  # what the views leave of each template, given its own ends
        resid = np.zeros((len(values), grid.size, n_cols))
        for j, v in enumerate(values):
            own = np.column_stack([np.interp(grid, taus[j], v[:, c]) for c in cols])
            resid[j][:, cols] = own - combined([o[j] for o in owns])
    if smooth > 0:
        progress = _progress(values, taus, weights, grid)
        for _ in range(2):
            on = _progress_average(on, progress, smooth)
            if slopes:
                resid = np.stack(
                    [_progress_average(r, progress, smooth) for r in resid]
                )
    if slopes:
        F, f = np.hstack(owns), np.concatenate(news)
        on = on + end_slopes(resid, w, F, f, slope_ridge)
    if smooth > 0:
        return np.column_stack([np.interp(rows, grid, c) for c in on.T])
    return on


def _end_views(values, taus, w, rows, ends, floor):
    """The views of :func:`end_frame_shift` at ``rows``: how to combine them.

    Returns
    -------
    cols : list of int
        The observed columns.
    combined : callable
        ``combined(points)``: the views' prediction (n_rows, len(cols)) given
        a point per end (``None``: the world's mean).
    owns : list of ndarray of shape (n_templates, n_end_cols)
        Each template's point at each end's phase.
    news : list of ndarray
        The requested points.
    """
    cols = sorted({c for _, cs, _ in ends for c in cs})
    P = np.stack(
        [np.column_stack([np.interp(rows, t, v[:, c]) for c in cols])
         for v, t in zip(values, taus, strict=True)]
    )  # fmt: skip
    world = np.tensordot(w, P, axes=1)
    views, owns, news = [], [], []
    prec = [1.0 / (np.tensordot(w, np.sum((P - world) ** 2, axis=2), axes=1) + floor)]
    for tau, cs, target in ends:
        here = [cols.index(c) for c in cs]
        # each template's point at the phase (its first or last sample at 0, 1)
        own = np.stack(
            [
                [np.interp(tau, t, v[:, c]) for c in cs]
                for v, t in zip(values, taus, strict=True)
            ]
        )
        rel = P[:, :, here] - own[:, None, :]
        mean = np.tensordot(w, rel, axes=1)
        prec.append(1.0 / (np.tensordot(w, np.sum((rel - mean) ** 2, axis=2), axes=1)
                           + floor))  # fmt: skip
        views.append((here, mean))
        owns.append(own)
        news.append(np.asarray(target, dtype=np.float64))
    prec = np.stack(prec)
    share = prec / prec.sum(axis=0)

    def combined(points):
        if points is None:
            return world
        out = share[0][:, None] * world
        for s, (here, mean), pt in zip(share[1:], views, points, strict=True):
            pred = world.copy()
            pred[:, here] = pt[None] + mean
            out = out + s[:, None] * pred
        return out

    return cols, combined, owns, news


def end_slopes(resid, w, F, f, ridge: float) -> np.ndarray:
    """The ridge regression of the views' residuals on the templates' ends.

    What :func:`end_frame_shift`'s views leave of each template (its values
    less their prediction from its own start and goal) is regressed, at
    every phase, on the ends' values; the features are centred and divided
    by their root mean variance (one unit for all: an end's column that does
    not vary, a board's height, adds no noise), the ridge is ``ridge`` times
    the identity. The prediction at the new ends ``f`` is the part of the
    motion that co-varies with them otherwise than as a frame (a board's
    turn, as far as its goal's place tells it).

    Parameters
    ----------
    resid : ndarray of shape (n_templates, n_rows, n_cols)
    w : ndarray of shape (n_templates,)
        Weights summing to 1.
    F : ndarray of shape (n_templates, p)
        Each template's ends.
    f : ndarray of shape (p,)
        The requested ends.
    ridge : float

    Returns
    -------
    ndarray of shape (n_rows, n_cols)
        Zero when the ends do not vary.
    """
    mf = w @ F
    Fc = F - mf
    unit = np.sqrt(np.mean(w @ (Fc * Fc)))
    if not unit > 0:
        return np.zeros(resid.shape[1:])
    Z, z = Fc / unit, (f - mf) / unit
    gram = (Z.T * w) @ Z + ridge * np.eye(Z.shape[1])
    flat = resid.reshape(resid.shape[0], -1)
    flat = flat - w @ flat
    B = np.linalg.solve(gram, (Z.T * w) @ flat)
    # exact leave-one-out residuals of the weighted fits, with and without
    h = w * (1.0 + np.einsum("jp,pq,jq->j", Z, np.linalg.inv(gram), Z))
    loo = (flat - Z @ B) / np.maximum(1.0 - h, 1e-6)[:, None]
    loo_mean = flat / np.maximum(1.0 - w, 1e-6)[:, None]
    if w @ np.sum(loo**2, axis=1) >= w @ np.sum(loo_mean**2, axis=1):
        return np.zeros(resid.shape[1:])
    # no farther than the farthest template (beyond, the slopes are guessed)
    inv = np.linalg.inv(gram)
    far = np.sqrt(np.max(np.einsum("jp,pq,jq->j", Z, inv, Z)))
    d = np.sqrt(z @ inv @ z)
    if d > far:
        z = z * (far / d)
    return (z @ B).reshape(resid.shape[1:])


def frame_routes(est, ends) -> np.ndarray:
    """The routes of the training demonstrations seen from a start and goal as frames.

    Each template is moved by :func:`end_frame_shift`'s views from its own
    ends to the templates' mean ends (every template weighing the same), and
    the routes are found again on the moved templates
    (:func:`~ndlfd.learner._routes.route_labels`). Demonstrations that differ
    only by where the task is (a board that moved: their spread, split where
    a gap happens to open) are one route; routes that differ wherever the
    ends are (a detour left or right) stay apart.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    ends : tuple of (dict or None)
        :func:`frame_ends`' ``(start, goal)``.

    Returns
    -------
    routes : ndarray of shape (n_demos,), dtype int64
        ``est.routes_`` when it has one route, ``n_routes`` is set, not every
        demonstration is a template, or no end is a frame.
    """
    routes = est.routes_
    obs = end_observations(est, *ends)
    n = len(est.train_values_)
    if (routes.max() == 0 or getattr(est, "n_routes", None) is not None
            or not obs or n != int(est.n_demos_) or n < 3):  # fmt: skip
        return routes
    values, taus = est.train_values_, est.train_tau_
    grid = np.linspace(0.0, 1.0, CONDITION_GRID)
    w = np.full(n, 1.0 / n)
    cols, combined, owns, _ = _end_views(values, taus, w, grid, obs, END_FLOOR)
    world = combined(None)
    moved = []
    for j, (v, t) in enumerate(zip(values, taus, strict=True)):
        back = world - combined([o[j] for o in owns])
        m = np.array(v, dtype=np.float64)
        for i, c in enumerate(cols):
            m[:, c] += np.interp(t, grid, back[:, i])
        moved.append(m)
    rcols = route_columns(est.column_groups_, getattr(est, "route_groups", None))
    curves = route_curves(moved, taus, rcols)
    return route_labels(curves, est.template_indices_, n)


def plan_end_shift(est, plan, rows, ends) -> np.ndarray:
    """:func:`end_frame_shift` of a plan's templates for a start and goal.

    ``ends`` is :func:`frame_ends`' ``(start, goal)``; the shift at the
    phases ``rows``, with :data:`END_FLOOR`, :data:`END_SMOOTH` and
    :data:`END_SLOPE_RIDGE`. When the plan's route is part of a larger one
    seen from the ends (:func:`route_mates`: a board's spread split into
    routes), the shift is that route's templates' (evenly weighted), from the
    plan's templates' mean: the path the whole route predicts.
    """
    obs = end_observations(est, *ends)
    mates = route_mates(est, plan, ends)
    if mates is None:
        return end_frame_shift(plan.values, plan.taus, plan.weights, rows, obs,
                               END_FLOOR, END_SMOOTH, END_SLOPE_RIDGE)  # fmt: skip
    values = [est.train_values_[j] for j in mates]
    taus = [est.train_tau_[j] for j in mates]
    even = np.ones(len(values))
    grid = np.linspace(0.0, 1.0, CONDITION_GRID)
    on = end_frame_shift(values, taus, even, grid, obs, END_FLOOR, END_SMOOTH,
                         END_SLOPE_RIDGE)  # fmt: skip
    # the route's mean less the plan's, averaged as the shift is
    gap = _mean_on(values, taus, even, grid) - _mean_on(
        plan.values, plan.taus, plan.weights, grid
    )
    pos = sorted({c for _, cs, _ in obs for c in cs})
    progress = _progress(values, taus, even, grid)
    for _ in range(2):
        gap = _progress_average(gap, progress, END_SMOOTH)
    on[:, pos] += gap[:, pos]
    return np.column_stack([np.interp(rows, grid, c) for c in on.T])


def _mean_on(values, taus, weights, grid) -> np.ndarray:
    """The templates' weighted mean at the phases ``grid``, on their own clocks."""
    w = np.asarray(weights, dtype=np.float64) / np.sum(weights)
    return sum(
        wj * np.column_stack([np.interp(grid, t, c) for c in v.T])
        for wj, v, t in zip(w, values, taus, strict=True)
    )


def route_mates(est, plan, ends):
    """The templates of the plan's route seen from the ends, when it is larger.

    Returns
    -------
    mates : ndarray of int or None
        Indices into ``est.train_values_`` of every template on the route
        (:func:`frame_routes`) of the plan's templates, when these are on one
        such route and it has others; ``None`` otherwise.
    """
    if est.routes_.max() == 0:
        return None
    key = ("frame routes", ends[0] is not None, ends[1] is not None)
    cache = getattr(est, "_cache", None)
    routes = (frame_routes(est, ends) if cache is None
              else cache.memo(key, lambda: frame_routes(est, ends)))  # fmt: skip
    index = np.asarray(est.template_indices_)
    mine = np.unique(routes[index[plan.templates]])
    if mine.size != 1:
        return None
    mates = np.flatnonzero(routes[index] == mine[0])
    return mates if mates.size > len(plan.templates) else None


def via_frame_mix(est, plan, obs_tau, observed):
    """The step moving the templates with a start, via points and a goal as frames.

    As :func:`end_frame_shift` (each condition's position a frame, the views
    combined per phase), with a via point's frame at its phase, every
    template's point there on its own clock; applied to the templates
    (``mix(W, w, tq) -> W``) before the blend is conditioned on the same
    points, so the path meets them exactly and moves with them in between.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    plan : Plan
    obs_tau : ndarray
        The observations' phases (:func:`~ndlfd.learner._via.blend_observations`).
    observed : list of (int, list of int, ndarray)
        Each observation's index into ``obs_tau``, columns and normalized values.
    """
    pos = set(group_columns(est.column_groups_, "position"))
    ends = []
    for k, cs, v in observed:
        keep = [i for i, c in enumerate(cs) if c in pos]
        if keep:
            ends.append((float(obs_tau[k]), [cs[i] for i in keep], np.asarray(v)[keep]))
    grid = np.linspace(0.0, 1.0, CONDITION_GRID)
    on = end_frame_shift(plan.values, plan.taus, plan.weights, grid, ends, END_FLOOR,
                         END_SMOOTH)  # fmt: skip

    def mix(W, w, tq):
        tq = np.asarray(tq, dtype=np.float64)
        return W + np.column_stack([np.interp(tq, grid, c) for c in on.T])[None]

    return mix


def via_plan(est, make_plan, all_t, start, goal, via, extra, cache, plan=None):
    """The plan a via point's conditioning reads, and whether by clock.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    make_plan : callable
        :func:`~ndlfd.learner._generation.make_plan`: the via point's plan
        (its templates weighted by their distance to the conditions) and the
        same route's with every template weighing the same (``even=True``;
        made only when the conditions observe a position).
    all_t : ndarray of shape (n_samples,)
        The timing.
    start, goal : dict or None
    via : list of (float, dict)
        Checked conditions.
    extra : ndarray of shape (n_demos,)
        The via points' log weights
        (:func:`~ndlfd.learner._via.via_log_weights`).
    cache : ModelCache
        The model's cache.
    plan : Plan, optional
        The via point's plan, when it is made already.

    Returns
    -------
    plan : Plan
    clock : bool
        Read the plan's templates on their own clocks
        (:func:`~ndlfd.learner._frames.clock_aligned`), without a clock
        warp, conditioned with :data:`CLOCK_RIDGE` and no reach limit.
    """
    if plan is None:
        plan = make_plan(est, all_t, start, goal, cache, extra)
    tq = est.time_bins_.normalize(all_t)
    obs_tau, observed = blend_observations(est, tq, start=start, via=via, goal=goal)
    if not observed:
        return plan, False
    pos = group_columns(est.column_groups_, "position")
    quat_cols = [j for b in orientation_blocks(est.column_groups_) for j in b]
    quat_cols = quat_cols or None  # as the blend's
    other = make_plan(est, all_t, start, goal, cache, extra, even=True)
    place = (plan.values, plan.taus, plan.index, plan.weights, plan.knots)
    truth = clock_aligned(plan.taus, plan.knots)
    index = clock_aligned(other.taus, other.knots)
    clock = (other.values, other.taus, index, other.weights, other.knots)
    step = output_step(tq)
    if prefers_clock(place, truth, clock, obs_tau, observed, pos, quat_cols, step):
        return other, True
    return plan, False
