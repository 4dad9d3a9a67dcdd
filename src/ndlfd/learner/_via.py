"""Via points and continuing an execution: route weights and exact offsets.

**Via points.** ``generate(..., via=[(time, {group: values}), ...])`` asks
the path to pass through ``values`` at ``time``. Two steps:

* *the route*: every demonstration is weighted by a Gaussian kernel on the
  distance of its normalized value at the via point's normalized time to the
  requested one (the kernel width as for a start:
  :func:`~ndlfd.learner._conditioning.condition_bandwidth` of the
  demonstrations' values at that time). A template's value is interpolated
  from its samples; a demonstration that is not a template (only its
  statistics are kept) takes the centroid of its segment state at that time's
  bin (:func:`~ndlfd.learner._routes.segment_paths`), the curve its route was
  found from (:func:`demo_values_at`). The route followed is the one with the
  largest total weight, as for a start (:mod:`ndlfd.learner._routes`);
* *the phase and the shape* (:mod:`ndlfd.learner._phase`,
  :func:`blend_observations`): the blend's clock is warped so it reaches
  the via point's closest pass (or a grasp's start) at the via time, and
  the blend is conditioned on the start's and via points' positions (joints
  for a model without a position: :func:`place_groups`; a Gaussian over
  the aligned templates' deviations,
  :func:`~ndlfd.learner._blend.condition_offsets`, the holds they share
  aligned, :func:`~ndlfd.learner._rests.hold_knots`), so a wide or late via
  point carries over the whole motion as the templates that are so carry
  it;
* *the offsets* (:func:`apply_via`): the blended path, already pinned to a
  start and goal, is shifted, per group, by an offset that equals the
  remaining difference at every via time and fades by a minimum-jerk ramp to
  the neighbouring via points and to zero at the ends. Each piece has zero
  slope and curvature at its ends, so the shift is twice continuously
  differentiable and the path stays as smooth as the blend; the ends stay
  where they were pinned.

**Continuing an execution.** ``generate(times, observed=prefix)`` takes what
the robot executed so far, at the first time stamps of ``times``:

* *the route* (:mod:`ndlfd.learner._prefix_route`): a route is ruled out
  once the prefix's shape has left all its templates by more than its
  demonstrations ever stray (the open-end Fréchet distance: no plan time,
  so a plan longer or shorter than the execution does not matter); the
  route followed is, among those left, the one of largest prior weight (the
  same at every tick until it is ruled out: no flip-flop), and ``sample``
  draws among them by that weight. Within the route every demonstration is
  weighted (:func:`observed_log_weights`) by the prefix's likelihood on its
  own segment path, tempered (:data:`PATH_TEMPER`,
  :func:`~ndlfd.learner._filtering.path_log_likelihoods`), and by the mean,
  over up to :data:`PREFIX_POINTS` prefix samples spread evenly, of the same
  log kernel as for a via point (the prefix is a series of via points): the
  templates hold the demonstrations' full values, where the segment model
  sees the codebook's cells;
* *the phase* (:mod:`ndlfd.learner._phase`): the blend runs at the rate
  that matches the prefix's samples up to the last one, then on to the end;
  it is conditioned on up to :data:`PREFIX_POINTS` of them
  (:func:`blend_observations`, noise :data:`PREFIX_RIDGE`). The filtered
  segment state at the last observed bin places the robot only to within a
  segment; used for the phase it scored worse (measured in
  :mod:`ndlfd.learner._filtering`);
* *the junction* (:func:`continue_from`): the path is the observed samples
  where observed; after them, the generated path shifted by the offset at the
  last observed sample, faded out by a minimum-jerk ramp that ends at the
  path's next slow-down (:func:`~ndlfd.learner._rests.contact_window`)
  or gripper switch (:func:`~ndlfd.learner._conditioning.switch_window`),
  as :func:`~ndlfd.learner._conditioning.pin` does for a start; and by the
  offset of the prefix's velocity at its end to the path's, faded within
  :data:`JUNCTION_FADE`, so the path leaves at the velocity the robot has.
  With less than :data:`JUNCTION_FADE` of the motion left before the end
  (a late robot's last replans), only ``(left / JUNCTION_FADE)^2`` of the
  offset is faded and the rest kept to the end: the plan ends beside the
  route's end pose rather than snapping onto it (before: 5-13 deg in the
  last 33 ms, SO-101-like joints replanned at 10 Hz).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import numpy as np

from .._demo_kernels import window_derivative
from .._errors import ValidationError
from ..demonstration import Demonstration
from ._conditioning import (
    check_condition,
    condition_bandwidth,
    condition_log_weights,
    condition_target,
    fade_pieces,
    group_columns,
    minimum_jerk,
    orient_condition,
    switch_window,
)
from ._filtering import path_log_likelihoods
from ._rests import contact_window, path_rests, rest_clock
from ._routes import route_columns, segment_paths
from ._spec import negated_orientation, prepare

__all__ = [
    "JUNCTION_FADE",
    "JUNCTION_SPAN",
    "PATH_TEMPER",
    "PREFIX_POINTS",
    "PREFIX_RIDGE",
    "apply_via",
    "blend_observations",
    "check_observed",
    "check_via",
    "complete_prefix",
    "continue_from",
    "demo_values_at",
    "observed_log_weights",
    "orient_prefix",
    "orient_via",
    "place_groups",
    "prefix_rows",
    "stamp_tolerance",
    "via_log_weights",
]

#: Prefix samples (spread evenly, the last included) the route is inferred from.
PREFIX_POINTS = 10

#: A prefix's template weights add each demonstration's log-likelihood of the
#: prefix along its own segment path
#: (:func:`~ndlfd.learner._filtering.path_log_likelihoods`) over this: the
#: bins' noise about the centroids is fitted within the demonstrations, and a
#: new execution's bins stray further and together, so the full likelihood
#: would keep one template. Leave-one-out LASA, protocol *P*, median over
#: shapes of the per-shape DTW ratio to the best peer (single shapes,
#: Multi_Models; without the term 0.899 and 1.12): 30 gave 0.896 and 1.09,
#: 100 gave 0.870 and 1.08, 300 gave 0.879 and 1.15, 1000 gave 0.893 and 1.15;
#: fold by fold, the geometric mean of the DTW ratios to no term at 100 was
#: 0.974 (single shapes) and 0.960 (Multi_Models).
PATH_TEMPER = 100.0

#: Observation noise of the blend conditioned on a prefix's samples
#: (:func:`~ndlfd.learner._blend.condition_offsets`; a start and via points
#: take :data:`~ndlfd.learner._blend.CONDITION_RIDGE`): the prefix's samples
#: are many and close together, so each is trusted less. Leave-one-out LASA,
#: median over shapes of the per-shape prefix DTW ratio to the best peer: 1
#: gave 0.882 on the single shapes and 1.18 on Multi_Models, 10 gave 0.899 and
#: 1.12 (100: 1.10 on Multi_Models).
PREFIX_RIDGE = 10.0

#: The prefix's velocity at its last sample: the slope of a least-squares
#: line through its samples over this much of the motion before it (at least
#: 3 samples; a robot's joint states are noisy). 60 prefixes per set
#: (``benchmarks/bench_envelope.py``'s draws; LASA Angle, BendedLine, Worm;
#: SO-101-like joints at rest before and after), largest acceleration after
#: the junction over the demonstrations' envelope: 0.01 gave 4.2, 4.1, 2.4,
#: 2.9; 0.02 gave 4.2, 4.2, 4.2, 2.6 (a line's slope lags an accelerating
#: prefix; a parabola's end slope over 0.02: 4.6, 4.1, 2.4, 4.2); 3 samples
#: only: the SO-101 speed 7.3 times the envelope (its noise). (Measured with
#: the path's velocity as a central difference across the junction.)
JUNCTION_SPAN = 0.01

#: The offset of the prefix's velocity at its end to the velocity the path
#: leaves with (one-sided: the prefix's clock turns there, from the
#: prefix's rate to the one that ends the plan on time,
#: :func:`~ndlfd.learner._phase.prefix_warp`) is added as ``dv * s * (1 -
#: minimum_jerk(s / w))`` (``s`` the normalized time since the last observed
#: sample): the path leaves at the prefix's velocity and is back on its own
#: after ``w``, this much of the motion, or longer where the ramp would
#: accelerate more than the path itself does in that column
#: (``_RAMP_BEND``), or shorter where the path's next slow-down comes
#: sooner. As for
#: :data:`JUNCTION_SPAN`, largest acceleration after the junction: without
#: the term 23.1, 21.1, 26.6, 2.9 (medians 5.7, 5.0, 6.4, 1.1: the velocity
#: jumped there), with it 2.8, 2.9, 2.4, 2.9 (medians 1.1, 1.1, 1.3, 1.0);
#: on the arcs of ``tests/learner/test_learner_envelope.py`` 46.4, with a
#: fixed ``w`` 11.1, with it 7.3. A clock easing from the prefix's rate
#: instead (a minimum-jerk ramp of its slope, curvature within
#: :data:`~ndlfd.learner._phase.MAX_BEND`) gave 4.2, 4.1, 2.4, 2.9 and was
#: worse on held-out LASA (Multi_Models_2 1.64 times the best peer's DTW,
#: against 1.38). Held-out LASA, protocol prefix, against no term: DTW 0.992
#: (single shapes) and 0.978 (Multi_Models) times, fold by fold (geometric
#: mean); per shape, to the best peer, 0.869 -> 0.865 and 1.09 -> 1.08.
JUNCTION_FADE = 0.1

#: The largest of ``|d^2/dx^2 x (1 - minimum_jerk(x))|`` on [0, 1] (at ``x =
#: (900 - sqrt(118800)) / 1440``): the velocity offset's ramp over a width
#: ``w`` accelerates by at most this times ``|dv| / w``.
_RAMP_BEND = 4.6218


def check_via(via, all_t: np.ndarray, column_groups, groups) -> list | None:
    """Check via points; return them as ``[(tau, {group: values})]`` by time.

    Parameters
    ----------
    via : sequence of (float, mapping of str to array-like), or None
        Time (on the timing's clock) and values per group, physical units.
    all_t : ndarray of shape (n_samples,)
        The timing.
    column_groups, groups : sequence of str
        The group of each learned column; the learned groups.

    Returns
    -------
    via : list of (float, dict of str to ndarray), or None
        Normalized times, increasing.

    Examples
    --------
    >>> check_via([(1.0, {"p": [2.0]})], np.array([0.0, 4.0]), ("p",), ("p",))
    [(0.25, {'p': array([2.])})]
    """
    if via is None:
        return None
    if isinstance(via, (str, bytes)) or not isinstance(via, Sequence) or not via:
        raise ValidationError(
            "via must be a list of (time, {group: values}) pairs, e.g."
            f" [(2.5, {{'position': [x, y]}})]; got {via!r}"
        )
    t0, t1 = float(all_t[0]), float(all_t[-1])
    out = []
    for i, item in enumerate(via):
        if not (isinstance(item, Sequence) and len(item) == 2):
            raise ValidationError(
                f"via[{i}] must be a (time, {{group: values}}) pair; got {item!r}"
            )
        time, values = item
        try:
            time = float(time)
        except (TypeError, ValueError):
            raise ValidationError(
                f"via[{i}]'s time must be a number; got {time!r}"
            ) from None
        if not t0 <= time <= t1:
            raise ValidationError(
                f"via[{i}]'s time must lie within the timing, {t0:g} to {t1:g};"
                f" got {time:g}"
            )
        cond = check_condition(values, f"via[{i}]", column_groups, groups)
        n_pos = len(group_columns(column_groups, "position"))
        if "velocity" in cond and n_pos == len(cond["velocity"]):
            raise ValidationError(
                f"via[{i}] gives a velocity, but the path's velocity is the"
                " derivative of its positions; give a position instead"
            )
        out.append(((time - t0) / (t1 - t0), cond))
    out.sort(key=lambda p: p[0])
    for (ta, a), (tb, b) in itertools.pairwise(out):
        if ta == tb and set(a) & set(b):
            raise ValidationError(
                f"two via points give {sorted(set(a) & set(b))[0]!r} at the same"
                f" time {t0 + ta * (t1 - t0):g}; give one"
            )
    return out


def demo_values_at(est, taus: np.ndarray, cache: dict) -> np.ndarray:
    """Every demonstration's normalized values at normalized times.

    Templates are interpolated from their samples; the other demonstrations
    take the centroid of their segment state at each time's bin.

    Parameters
    ----------
    est : KeypointHMM
        Fitted, with training values.
    taus : ndarray of shape (n_times,)
        Normalized times in ``[0, 1]``.
    cache : dict
        The model's cache (the segment paths, under ``"segment paths"``).

    Returns
    -------
    values : ndarray of shape (n_demos, n_times, n_columns)
    """
    nt = est.n_time_bins
    if "segment paths" not in cache:  # the training data's only: once per model
        cache["segment paths"] = segment_paths(est.fit_stats_, est.centroid_states_, nt)
    taus = np.asarray(taus, dtype=np.float64)
    bins = np.clip(np.floor(taus * nt).astype(np.int64), 0, nt - 1)
    V = est.centroids_[cache["segment paths"][:, bins]]
    for k, j in enumerate(est.template_indices_):
        U, tau = est.train_values_[k], est.train_tau_[k]
        V[j] = np.column_stack([np.interp(taus, tau, c) for c in U.T])
    return V


def orient_via(est, via, cache: dict) -> list | None:
    """Checked via points, their orientations on the demonstrations' side.

    As for a start (:func:`~ndlfd.learner._conditioning.orient_condition`),
    against the demonstrations' orientations at the via point's time
    (:func:`demo_values_at`): ``-q`` is the rotation ``q``, and the offset
    the path is shifted by must not turn it the long way round.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    via : list of (float, dict), or None
        From :func:`check_via`.
    cache : dict
        See :func:`demo_values_at`.

    Returns
    -------
    via : list of (float, dict), or None
    """
    if via is None or not any("orientation" in cond for _, cond in via):
        return via
    V = demo_values_at(est, np.array([tau for tau, _ in via]), cache)
    cg, scaler = est.column_groups_, est.scaler_
    out = []
    for k, (tau, cond) in enumerate(via):
        out.append((tau, orient_condition(cond, V[:, k], scaler, cg, f"via[{k}]")))
    return out


def orient_prefix(est, prefix, all_t: np.ndarray, cache: dict):
    """A checked prefix's orientations on the demonstrations' side.

    ``q`` and ``-q`` are one rotation, and a recorded stream (a ROS 2 ``/tf``
    bag, say) may give either: a prefix whose quaternions point away from
    the demonstrations' at the same times (summed over its samples) is
    negated, so its weights, the blend's conditioning and the junction's
    offsets compare it with the same sign (before, the offset at the junction
    turned the path the long way round: 176 degrees in one step). The path
    generated from it is negated back (``restore``): its first samples are
    the observed ones as given, and the rest continues them without a sign
    flip.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    prefix : Demonstration or None
        From :func:`check_observed`.
    all_t : ndarray of shape (n_samples,)
        The timing.
    cache : dict
        See :func:`demo_values_at`.

    Returns
    -------
    prefix : Demonstration or None
    restore : callable
        ``restore(path) -> path`` for the paths generated from it.
    """
    cols = group_columns(est.column_groups_, "orientation")
    if prefix is None or len(cols) != 4:
        return prefix, _as_is
    n = prefix.t.size
    tq = est.time_bins_.normalize(all_t)[:n]
    mean = demo_values_at(est, tq, cache).mean(axis=0)
    ref = est.scaler_.inverse_transform(mean, weighted=False)[:, cols]
    if float(np.sum(prefix.X[:, cols] * ref)) >= 0.0:
        return prefix, _as_is
    return negated_orientation(prefix), negated_orientation


def _as_is(path):
    return path


def via_log_weights(est, via, cache: dict) -> np.ndarray:
    """Every demonstration's log weight for checked via points.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    via : list of (float, dict), or None
        From :func:`check_via`; ``None`` gives zeros.
    cache : dict
        See :func:`demo_values_at`.

    Returns
    -------
    log_weights : ndarray of shape (n_demos,)
        The sum over the via points of their kernels' logarithms.
    """
    logw = np.zeros(est.n_demos_)
    if via is None:
        return logw
    V = demo_values_at(est, np.array([tau for tau, _ in via]), cache)
    for k, (_, cond) in enumerate(via):
        cols, target = condition_target(cond, est.scaler_, est.column_groups_)
        pts = V[:, k, cols]
        logw += condition_log_weights(pts, target, condition_bandwidth(pts))
    return logw


def apply_via(X, at, via, column_groups, n_dense) -> np.ndarray:
    """Shift a path through the via points, offsets faded by minimum-jerk ramps.

    Parameters
    ----------
    X : ndarray of shape (n_rows, n_columns)
        The path, physical units (changed in place).
    at : ndarray of shape (n_rows,)
        Normalized time of each row; the first ``n_dense`` are the path in
        time order (the offsets are measured on them, interpolated).
    via : list of (float, dict), or None
        From :func:`check_via`.
    column_groups : sequence of str
    n_dense : int

    Returns
    -------
    X : ndarray of shape (n_rows, n_columns)

    Examples
    --------
    >>> X = np.zeros((5, 1)); at = np.linspace(0.0, 1.0, 5)
    >>> apply_via(X, at, [(0.5, {"p": np.array([1.0])})], ("p",), 5)[:, 0]
    array([0. , 0.5, 1. , 0.5, 0. ])
    """
    if via is None:
        return X
    tq = at[:n_dense]
    rests = path_rests(X[:n_dense], tq, column_groups)
    for g in dict.fromkeys(g for _, cond in via for g in cond):
        cols = group_columns(column_groups, g)
        taus, offsets = [0.0], [np.zeros(len(cols))]
        for tau, cond in via:
            if g in cond:
                now = [np.interp(tau, tq, X[:n_dense, c]) for c in cols]
                if tau == 0.0:
                    taus, offsets = [], []
                taus.append(tau)
                offsets.append(cond[g] - np.array(now))
        if taus[-1] < 1.0:
            taus.append(1.0)
            offsets.append(np.zeros(len(cols)))
        taus, offsets = np.array(taus), np.array(offsets)
        # on a clock that stops where the path rests: an offset is not faded
        # while the hand holds still (a grasp), it holds with it
        X[:, cols] += fade_pieces(rest_clock(at, rests), rest_clock(taus, rests),
                                  offsets)  # fmt: skip
    return X


def check_observed(
    est, observed, all_t: np.ndarray, *, start=None, via=None
) -> Demonstration | None:
    """Check an executed prefix against the model, the timing and the conditions.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    observed : Demonstration or None
        The samples executed so far.
    all_t : ndarray of shape (n_samples,)
        The timing (the prefix is at its first time stamps).
    start, via : optional
        The other conditions asked: a prefix replaces a start (its first
        sample is where the robot started) and cannot be combined with via
        points (a goal is fine).

    Returns
    -------
    prefix : Demonstration or None
        With the learned columns (velocity derived if learned so).
    """
    if observed is None:
        return None
    if start is not None or via is not None:
        raise ValidationError(
            "observed continues an execution from its last sample; it cannot"
            " be combined with start or via (a goal is fine)"
        )
    if not isinstance(observed, Demonstration):
        raise ValidationError(
            "observed must be a Demonstration of the samples executed so far;"
            f" got {type(observed).__name__}"
        )
    d = prepare(observed, est.groups_, derive_velocity=est.derive_velocity)
    if d.columns != est.columns_:
        raise ValidationError(
            f"observed must have the learned columns {est.columns_}; got {d.columns}"
        )
    n = d.t.size
    if n >= all_t.size:
        raise ValidationError(
            f"observed must be shorter than the timing ({all_t.size} time"
            f" stamps); got {n} samples"
        )
    tol = stamp_tolerance(all_t[:n], all_t[-1] - all_t[0])
    off = np.abs(d.t - all_t[:n]) > tol
    if off.any():
        bad = int(np.flatnonzero(off)[0])
        raise ValidationError(
            "observed must be sampled at the first time stamps of the timing;"
            f" its sample {bad} is at {d.t[bad]!r}, the timing's at"
            f" {all_t[bad]!r} (a difference of {abs(d.t[bad] - all_t[bad]):.3g} s;"
            f" expected at most {tol[bad]:.3g} s)"
        )
    return d


def complete_prefix(est, observed, all_t: np.ndarray, plan_path):
    """An executed prefix with the learned groups it lacks filled in.

    A robot may report only some channels (its position, not its gripper):
    the groups a prefix lacks (besides a velocity derived from its
    positions) are taken from the path generated for the timing from the
    prefix's first sample, at the prefix's time stamps. A prefix with every
    learned group, or anything else, is returned as it is
    (:func:`check_observed` checks it).

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    observed : Demonstration or None
    all_t : ndarray of shape (n_samples,)
    plan_path : callable
        ``plan_path(start) -> Demonstration``, the dense generated path from
        ``start`` (``_generation.prefix_completer``).

    Returns
    -------
    observed : Demonstration or None
    """
    if not isinstance(observed, Demonstration):
        return observed
    derived = {"velocity"} if est.derive_velocity else set()
    have = set(observed.group_names)
    missing = [g for g in est.groups_ if g not in have and g not in derived]
    n = observed.n_samples
    if not missing or not have & set(est.groups_) or n >= all_t.size:
        return observed  # complete, or nothing to go on: check_observed says
    path = plan_path({g: observed.get(g)[0] for g in est.groups_ if g in have})
    out = observed
    for g in missing:
        names = tuple(path.columns[j] for j in path.columns_of(g))
        out = out.with_group(g, path.get(g)[:n], names)
    return out


def stamp_tolerance(t: np.ndarray, span: float) -> np.ndarray:
    """How far a prefix's stamp may be from the timing's and still be the same.

    A billionth of the timing's ``span``, or one float32 spacing at the stamp
    (``numpy.spacing``), whichever is larger: a stamp stored as float32
    (LeRobot's ``timestamp``) is within half a float32 spacing of the float64
    clock that made it (``k / fps``), so the two are the same sample.

    Examples
    --------
    >>> t = np.array([0.0, 8 / 30])
    >>> bool(abs(np.float32(8 / 30) - 8 / 30) <= stamp_tolerance(t, 3.0)[1])
    True
    >>> print(f"{stamp_tolerance(t, 3.0)[0]:.3g}")  # at 0: a billionth of the span
    3e-09
    """
    t = np.asarray(t, dtype=np.float64)
    f32 = np.spacing(np.abs(t).astype(np.float32)).astype(np.float64)
    return np.maximum(1e-9 * float(span), f32)


def prefix_rows(n: int) -> np.ndarray:
    """The prefix samples a route is inferred from: up to :data:`PREFIX_POINTS`.

    Spread evenly, the first and the last included.

    Examples
    --------
    >>> prefix_rows(4), prefix_rows(100)
    (array([0, 1, 2, 3]), array([ 0, 11, 22, 33, 44, 55, 66, 77, 88, 99]))
    """
    return np.unique(np.linspace(0, n - 1, min(n, PREFIX_POINTS)).round().astype(int))


def observed_log_weights(est, prefix, tq: np.ndarray, cache: dict) -> np.ndarray:
    """Every demonstration's log weight for an executed prefix.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    prefix : Demonstration
        From :func:`check_observed`.
    tq : ndarray of shape (n_samples,)
        Normalized times of the whole timing.
    cache : dict
        See :func:`demo_values_at`.

    Returns
    -------
    log_weights : ndarray of shape (n_demos,)
        The mean, over up to :data:`PREFIX_POINTS` prefix samples, of the
        kernels' logarithms (a tempered weight: it keeps several templates
        of the route in the blend), plus the demonstration's log-likelihood
        of the prefix along its segment path over :data:`PATH_TEMPER`.
    """
    rows = prefix_rows(prefix.t.size)
    U = est.scaler_.transform(prefix.X, weighted=False)
    V = demo_values_at(est, tq[rows], cache)
    logw = np.zeros(V.shape[0])
    for k, row in enumerate(rows):
        pts = V[:, k]
        logw += condition_log_weights(pts, U[row], condition_bandwidth(pts))
    path = path_log_likelihoods(est, U, tq[: prefix.t.size], cache)
    return logw / rows.size + path / PATH_TEMPER


def continue_from(X, tq, prefix, column_groups) -> np.ndarray:
    """The observed samples, then the path shifted onto the last one, faded.

    The offset at the last observed sample fades by a minimum-jerk ramp up to
    the path's next slow-down or gripper switch (else its end); over less
    than :data:`JUNCTION_FADE` of the motion, only the share
    :func:`_fade_share` of it, the rest kept to the end.

    Parameters
    ----------
    X : ndarray of shape (n_samples, n_columns)
        The generated path at every time stamp (changed in place).
    tq : ndarray of shape (n_samples,)
        Their normalized times.
    prefix : Demonstration
        From :func:`check_observed` (its ``n`` samples are the first rows).
    column_groups : sequence of str

    Returns
    -------
    X : ndarray of shape (n_samples, n_columns)

    Examples
    --------
    A path at rest at 0; the prefix reached 1 at time 0.25, moving at 4. The
    path leaves at 4 and both offsets, of 1 and of 4 per unit time, fade
    over the rest (a path at rest has no acceleration of its own to keep the
    velocity offset's fade within):

    >>> from ndlfd import Demonstration
    >>> X = np.zeros((5, 1)); tq = np.linspace(0.0, 1.0, 5)
    >>> prefix = Demonstration(tq[:2], np.array([[0.0], [1.0]]), ("p",), ("p",))
    >>> np.round(continue_from(X, tq, prefix, ("p",))[:, 0], 3)
    array([0.  , 1.  , 1.58, 0.63, 0.  ])
    """
    n = prefix.t.size
    last = tq[n - 1]
    pos = group_columns(column_groups, "position")
    first = contact_window(X[n - 1 :, pos], tq[n - 1 :])[0] if pos else 1.0
    first = min(first, switch_window(X[n - 1 :], tq[n - 1 :], column_groups)[0])
    if not first > last:
        first = 1.0
    fade = 1.0 - minimum_jerk((tq - last) / (first - last))
    if 2 <= n < X.shape[0]:  # leave at the prefix's velocity, not the path's
        leave = (X[n] - X[n - 1]) / (tq[n] - tq[n - 1])  # the path's, one-sided
        dv = _end_velocity(tq[:n], prefix.X) - leave
        width = np.minimum(_junction_width(X[n - 1 :], tq[n - 1 :], dv), first - last)
        s = np.maximum(tq - last, 0.0)[:, None]
        X += dv * s * (1.0 - minimum_jerk(s / width))
    offset = prefix.X[n - 1] - X[n - 1]
    faded = offset * _fade_share(first - last)
    X += faded * fade[:, None] + (offset - faded)  # the rest kept to the end
    X[:n] = prefix.X
    return X


def _fade_share(span: float) -> float:
    """The share of the offset at the junction a ramp over ``span`` fades.

    All of it when ``span`` (normalized time) is at least
    :data:`JUNCTION_FADE`; over a shorter span (a junction close to the
    plan's end or to a contact), ``(span / JUNCTION_FADE)^2``: the ramp then
    moves and accelerates no more than fading the whole offset over
    :data:`JUNCTION_FADE` would. The rest is kept to the end.

    Examples
    --------
    >>> _fade_share(0.5), _fade_share(0.05)
    (1.0, 0.25)
    """
    return min(1.0, span / JUNCTION_FADE) ** 2


def _junction_width(X: np.ndarray, tq: np.ndarray, dv: np.ndarray) -> np.ndarray:
    """How long each column's velocity offset ``dv`` takes to fade (normalized time).

    :data:`JUNCTION_FADE`, or longer where the fade's acceleration would
    exceed the path's own largest in the column (``X``: the path from the
    last observed sample on; a column the path keeps still: as long as it
    may).
    """
    if X.shape[0] < 3:
        return np.full(X.shape[1], JUNCTION_FADE)
    dt = np.diff(tq)
    V = np.diff(X, axis=0) / dt[:, None]
    a = (np.abs(np.diff(V, axis=0)) / dt[1:, None]).max(axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        need = np.where(dv == 0.0, 0.0, _RAMP_BEND * np.abs(dv) / a)
    return np.maximum(JUNCTION_FADE, need)


def _end_velocity(tq: np.ndarray, X: np.ndarray) -> np.ndarray:
    """The least-squares slope over the last :data:`JUNCTION_SPAN` (>= 3 samples)."""
    k = max(int(np.sum(tq >= tq[-1] - JUNCTION_SPAN)), min(tq.size, 3))
    return window_derivative(tq[-k:], X[-k:], tq[-1] - tq[-k])[-1]


def place_groups(column_groups) -> tuple[str, ...]:
    """The groups that say where the path is: what a via point's clock and blend follow.

    The position if the model learned one; else the groups a route is judged
    on (:func:`~ndlfd.learner._routes.route_columns`: a robot's joints, not
    its gripper, orientation or velocity).

    Examples
    --------
    >>> place_groups(("position", "position", "gripper"))
    ('position',)
    >>> place_groups(("joints", "joints", "gripper"))
    ('joints',)
    """
    cg = tuple(column_groups)
    return tuple(dict.fromkeys(cg[c] for c in route_columns(cg)))


def blend_observations(
    est, tq: np.ndarray, *, start=None, via=None, prefix=None, goal=None
):
    """What the blend is conditioned on: a start and goal with via points, or a prefix.

    The positions (or, for a model without one, the joints:
    :func:`place_groups`) of a start, the via points and a goal (only when a
    via point gives them: the demonstrations' deviations then carry all of
    them over the motion, as they co-vary; a pick-and-place whose place
    follows its goal), or of up to :data:`PREFIX_POINTS` samples of a prefix
    (:func:`prefix_rows`), as values at normalized times, normalized as the
    templates are (unweighted;
    :func:`~ndlfd.learner._blend.condition_offsets` shifts the blend towards
    them; the offsets that remain are faded as before).

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    tq : ndarray of shape (n_samples,)
        Normalized times of the timing.
    start, goal : dict of str to ndarray, optional
        A checked start and goal (used with via points only).
    via : list of (float, dict), optional
        From :func:`check_via`.
    prefix : Demonstration, optional
        From :func:`check_observed`.

    Returns
    -------
    taus : ndarray of shape (n_obs,)
        The observations' normalized times.
    observed : list of (int, list of int, ndarray)
        Each one's index into ``taus``, its columns and its values.
    """
    scaler, cg = est.scaler_, est.column_groups_
    taus, observed = [], []
    if via is not None:
        place = place_groups(cg)
        ends = [(0.0, start)] if start is not None else []
        for tau, cond in ends + via + ([(1.0, goal)] if goal is not None else []):
            given = {g: cond[g] for g in place if cond is not None and g in cond}
            if not given:
                continue
            cols, target = condition_target(given, scaler, cg, weighted=False)
            observed.append((len(taus), cols, target))
            taus.append(tau)
        if not any(0.0 < tau < 1.0 for tau in taus):
            return np.zeros(0), []  # no via position: the offsets only
    elif prefix is not None:
        rows = prefix_rows(prefix.t.size)
        U = scaler.transform(prefix.X[rows], weighted=False)
        pos = group_columns(cg, "position")
        if not pos:
            return np.zeros(0), []
        for k in range(rows.size):
            observed.append((k, pos, U[k, pos]))
        taus = list(tq[rows])
    return np.asarray(taus, dtype=np.float64), observed
