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
"""

from __future__ import annotations

import numpy as np

from ._blend import (
    CONDITION_REACH,
    CONDITION_RIDGE,
    condition_coefficients,
    output_step,
    warped,
)
from ._conditioning import group_columns
from ._frames import clock_aligned
from ._via import blend_observations

__all__ = ["CLOCK_MARGIN", "CLOCK_RIDGE", "prefers_clock", "via_plan"]

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
    quat_cols = group_columns(est.column_groups_, "orientation")
    quat_cols = quat_cols if len(quat_cols) == 4 else None  # as the blend's
    other = make_plan(est, all_t, start, goal, cache, extra, even=True)
    place = (plan.values, plan.taus, plan.index, plan.weights, plan.knots)
    truth = clock_aligned(plan.taus, plan.knots)
    index = clock_aligned(other.taus, other.knots)
    clock = (other.values, other.taus, index, other.weights, other.knots)
    step = output_step(tq)
    if prefers_clock(place, truth, clock, obs_tau, observed, pos, quat_cols, step):
        return other, True
    return plan, False
