"""Generation: from a new timing (and a start or goal) to a path.

Two generations, registered in :data:`GENERATIONS`:

* ``"blend"`` (:func:`generate_blend`): :func:`make_plan` decodes the skeleton
  (the key points and their times) with the segment model of the
  demonstrations that carry weight for the start and goal
  (:mod:`ndlfd.learner._conditioning`), aligns the templates to it, and the
  templates are blended (:mod:`ndlfd.learner._blend`); the path is pinned to
  the start and goal, velocity is the derivative of the positions, and the
  uncertainty band is the spread of the blended templates
  (:func:`~ndlfd.learner._blend.spread`);
  the steps are written once and shared with sampling
  (:mod:`ndlfd.learner._sampling`): :func:`demo_log_weights`,
  :func:`route_model`, :func:`plan_from_states` (the plan of given bin
  states) and :func:`render` (the path of a plan);
* ``"paper"`` (:func:`generate_paper`): the paper's procedure, the timing's
  symbols decoded with the key-point HMM, codebook centres and straight lines.

Every function takes a fitted :class:`~ndlfd.KeypointHMM` and reads its
public attributes only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import hmm
from .._errors import DecodeError, ValidationError
from .._registry import Registry
from .._validation import check_times
from ..demonstration import Demonstration, unit_time
from ._blend import (
    CONDITION_REACH,
    CONDITION_RIDGE,
    align_many,
    blend,
    output_step,
    skeleton_times,
    spread,
)
from ._cache import ModelCache
from ._choice import (
    CLOCK_RIDGE,
    frame_ends,
    plan_end_shift,
    via_frame_mix,
    via_plan,
)
from ._conditioning import log_weights_for, orient_condition, pin
from ._decoding import decode_states
from ._discrete import snap_physical, snap_two_valued, two_valued_columns
from ._frame_mix import frame_parts
from ._frames import check_new_frames, clock_aligned
from ._hands import derive_velocity, quat_columns, renormalized
from ._phase import warp_for
from ._prefix_route import route_prior
from ._routes import choose_route
from ._segments import segment_model
from ._spec import DemoSpec, prepare
from ._states import centroid_rows, state_centres
from ._via import (
    PREFIX_RIDGE,
    apply_via,
    blend_observations,
    check_observed,
    check_via,
    complete_prefix,
    continue_from,
    observed_log_weights,
    orient_prefix,
    orient_via,
    via_log_weights,
)

__all__ = [
    "GENERATIONS",
    "Plan",
    "aligned_templates",
    "decode_key_points",
    "decode_paper",
    "decode_route",
    "demo_log_weights",
    "generate_blend",
    "generate_paper",
    "make_plan",
    "observations",
    "orient_conditions",
    "plan_from_states",
    "prefix_completer",
    "prefix_route",
    "render",
    "route_model",
    "template_weights",
    "times_of",
]

#: Demonstrations whose start/goal weight falls below this fraction of the
#: largest are left out of the conditioned skeleton and blend.
_KEEP_WEIGHT = 0.1

#: Samples of a demonstration the skeleton is matched to (evenly spread, ends
#: included). On held-out LASA (1,000 samples) 128, 250, 500 and all gave the
#: same DTW medians to 0.1 %; the cost is linear in it.
_ALIGN_CANDIDATES = 256


@dataclass(frozen=True)
class Plan:
    """The decoded skeleton and the templates aligned to it.

    Attributes
    ----------
    states : ndarray of shape (n_keys,), dtype int64
        Codebook state of each skeleton point (key point).
    logp : float
        Log-probability of the decoded state sequence.
    model : ndlfd.hmm.DiscreteHMM
        The segment model it was decoded with.
    values, taus : list of ndarray
        The templates that carry weight: normalized values and times.
    weights : ndarray of shape (n_templates,)
        Their weights (the largest is 1).
    index : list of ndarray of shape (n_keys,)
        Each template's samples matched to the skeleton points.
    key_tau : ndarray of shape (n_keys,)
        Normalized time of each key point (ends exactly 0 and 1).
    knots : ndarray of shape (n_keys,)
        The skeleton times the templates are warped onto (the matches' mean
        time under the blend's normalized weights).
    templates : ndarray of shape (n_templates,), dtype int64
        Which templates they are (indices into ``template_indices_``).
    """

    states: np.ndarray
    logp: float
    model: hmm.DiscreteHMM
    values: list
    taus: list
    weights: np.ndarray
    index: list
    key_tau: np.ndarray
    knots: np.ndarray
    templates: np.ndarray


def times_of(times_or_demo) -> np.ndarray:
    """The time stamps of a timing (at least two)."""
    if isinstance(times_or_demo, Demonstration):
        t = times_or_demo.t
    else:
        t = check_times(times_or_demo, name="times")
    if t.size < 2:
        raise ValidationError(f"a timing needs at least two time stamps; got {t.size}")
    return t


def key_times(all_t: np.ndarray, key_tau: np.ndarray) -> np.ndarray:
    """Normalized key-point times on the timing ``all_t``."""
    t = all_t[0] + key_tau * (all_t[-1] - all_t[0])
    t[-1] = all_t[-1]  # exact, not up to the rounding of the product
    return t


def orient_conditions(est, start, goal) -> tuple:
    """Checked start and goal, their orientations on the demonstrations' side.

    See :func:`~ndlfd.learner._conditioning.orient_condition`.
    """
    cg = est.column_groups_
    first = getattr(est, "first_values_", None)  # none in a format-1 file
    last = getattr(est, "last_values_", None)
    return (
        orient_condition(start, first, est.scaler_, cg, "start"),
        orient_condition(goal, last, est.scaler_, cg, "goal"),
    )


def demo_log_weights(est, start, goal, cache: dict):
    """Every demonstration's log weight for a start and goal, and the routes.

    Parameters
    ----------
    est : KeypointHMM
        Fitted, with training values (format 2 or later).
    start, goal : dict of str to ndarray, or None
        Checked conditions.
    cache : dict
        What depends on the training data only, computed on first use: the
        conditioning kernel widths (see
        :func:`~ndlfd.learner._conditioning.log_weights_for`).

    Returns
    -------
    log_weights : ndarray of shape (n_demos,)
        0 for every demonstration without a start or goal.
    routes : ndarray of shape (n_demos,), dtype int64
        Each demonstration's route (``est.routes_``, found at fit).
    """
    if not hasattr(est, "train_values_"):
        raise ValidationError(
            "this model has no training values (a format-1 file); use"
            " generation='paper' or fit it again"
        )
    groups = est.column_groups_
    logw = log_weights_for(start, est.first_values_, est.scaler_, groups, cache, 0)
    logw = logw + log_weights_for(
        goal, est.last_values_, est.scaler_, groups, cache, -1
    )
    return logw, est.routes_


def prefix_route(est, prefix, n_times: int, goal, cache: ModelCache) -> int:
    """The route a prefix continues on: the prior's among those not ruled out.

    :func:`~ndlfd.learner._prefix_route.allowed_routes` rules out the routes
    the prefix has left (by its shape, not the plan's time); among the others
    the one of largest weight (the most demonstrations, or a goal's,
    :func:`~ndlfd.learner._routes.choose_route`), the same at every tick
    until it is ruled out.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    prefix : Demonstration
        Checked (:func:`~ndlfd.learner._via.check_observed`).
    n_times : int
        Time stamps of the timing (:func:`~ndlfd.learner._prefix_route.prefix_stride`).
    goal : dict of str to ndarray, or None
    cache : ModelCache

    Returns
    -------
    route : int
    """
    logw, routes = demo_log_weights(est, None, goal, cache)
    return int(np.argmax(route_prior(est, prefix, n_times, logw, routes, cache)))


def make_plan(
    est, all_t, start, goal, cache: ModelCache, extra=None, route=None, even=None
) -> Plan:
    """Decode the skeleton and align the templates to it.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    all_t : ndarray of shape (n_samples,)
        The timing.
    start, goal : dict of str to ndarray, or None
        Checked conditions.
    cache : ModelCache
        See :func:`demo_log_weights`; also keeps the route's model, skeleton
        and alignments (:func:`decode_route`, :func:`aligned_templates`).
    extra : ndarray of shape (n_demos,), optional
        Log weights added to the start's and goal's (via points, a prefix:
        :mod:`ndlfd.learner._via`).
    route : int, optional
        The route to follow (a prefix's, :mod:`ndlfd.learner._filtering`),
        its skeleton decoded from all its demonstrations (the prefix weighs
        the templates only, so a replanning robot decodes once per route);
        by default the one of largest weight
        (:func:`~ndlfd.learner._routes.choose_route`), decoded from the
        demonstrations that weigh.
    even : object, optional
        Not None (frames): every demonstration on the route weighs the same.

    Returns
    -------
    plan : Plan
    """
    # the demonstrations' weights for the conditions, then the route to follow
    logw, routes = demo_log_weights(est, start, goal, cache)
    if extra is not None:
        logw = logw + extra
    fixed = route is not None  # a prefix's: the whole route's skeleton
    route = choose_route(routes, logw) if route is None else route
    logw = np.where(routes == route, logw if even is None else 0.0, -np.inf)
    if not fixed:
        model, states, logp = decode_route(est, logw, cache)
    else:  # one skeleton per route while a prefix grows
        whole = np.where(routes == route, 0.0, -np.inf)
        model, states, logp = decode_route(est, whole, cache)
    return plan_from_states(est, states, logp, model, logw, cache=cache)


def decode_route(est, logw: np.ndarray, cache: ModelCache):
    """The route's segment model and its decoded skeleton (memoized).

    The same demonstrations that weigh (:func:`route_model`), decoder, start
    and number of bins give the same model and states: they are kept in the
    model's cache (:meth:`~ndlfd.learner._cache.ModelCache.memo`), so a
    replanning robot pays the decoding once per route.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    logw : ndarray of shape (n_demos,)
        The demonstrations' log weights (``-inf`` off the route followed).
    cache : ModelCache
        The model's cache.

    Returns
    -------
    model : ndlfd.hmm.DiscreteHMM
    states : ndarray of shape (n_time_bins,), dtype int64
        Read-only.
    log_probability : float
    """
    model = route_model(est, logw, cache)

    def make():
        states, logp = decode_states(
            est.decoder, model, np.arange(est.n_time_bins), est.start
        )
        states.flags.writeable = False
        return states, logp

    key = ("skeleton", est.decoder, est.start, *_route_key(est, logw))
    return (model, *cache.memo(key, make))


def template_weights(est, logw: np.ndarray):
    """The templates that carry weight, and their weights (the largest 1).

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    logw : ndarray of shape (n_demos,)
        The demonstrations' log weights (``-inf`` off the route followed).

    Returns
    -------
    templates : ndarray of shape (n_kept,), dtype int64
        Indices into ``est.template_indices_``.
    weights : ndarray of shape (n_kept,)
    """
    # normalized in log space over the templates: however far the start, the
    # nearest template weighs 1
    tlogw = logw[est.template_indices_]
    tw = np.exp(tlogw - tlogw.max())
    templates = np.flatnonzero(tw >= _KEEP_WEIGHT)
    return templates, tw[templates]


def plan_from_states(
    est, states, logp, model, logw, weights=None, cache: ModelCache | None = None
) -> Plan:
    """Align the templates to the skeleton of decoded (or drawn) bin states.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    states : ndarray of shape (n_time_bins,), dtype int64
        The segment state of every time bin; a key point where it changes.
    logp : float
        Their log-probability (kept in the plan).
    model : ndlfd.hmm.DiscreteHMM
        The segment model they come from.
    logw : ndarray of shape (n_demos,)
        The demonstrations' log weights (:func:`template_weights`).
    weights : ndarray of shape (n_kept,), optional
        Blend weights of the kept templates instead of theirs (a sample's).
    cache : ModelCache, optional
        Keep the templates' alignments to this skeleton there
        (:func:`aligned_templates`); without it they are computed (a drawn
        skeleton, which seldom comes again).

    Returns
    -------
    plan : Plan
    """
    templates, tw = template_weights(est, logw)
    weights = tw if weights is None else weights
    change = np.flatnonzero(np.r_[True, states[1:] != states[:-1]])
    skel = states[change]
    if skel.size == 1:
        skel = np.repeat(skel, 2)  # a start and an end in one state
    C = est.centroids_[centroid_rows(est, skel)]
    values = [est.train_values_[j] for j in templates]
    taus = [est.train_tau_[j] for j in templates]
    if cache is None:
        window = float(est.match_window)
        index = align_many(values, C, est.n_jobs, _ALIGN_CANDIDATES, window)
    else:
        index = aligned_templates(est, skel, C, templates, cache)
    key_tau = skeleton_times(taus, index, weights)
    # every alignment pins the ends to samples at tau 0 and 1: exact ends
    key_tau[0], key_tau[-1] = 0.0, 1.0
    norm = np.asarray(weights, dtype=np.float64)
    knots = skeleton_times(taus, index, norm / norm.sum())
    return Plan(
        skel, logp, model, values, taus, weights, index, key_tau, knots, templates
    )


def aligned_templates(est, skel, C, templates, cache: ModelCache) -> list:
    """The templates' alignments to a skeleton, each computed once per skeleton.

    A template's alignment depends on its values, the skeleton and the match
    window only (not on the other templates or the weights), so it is kept
    per skeleton in the model's cache and reused by any start, goal or
    prefix whose skeleton it is.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    skel : ndarray of shape (n_keys,), dtype int64
        The skeleton's states.
    C : ndarray of shape (n_keys, n_columns)
        Their centroids.
    templates : ndarray of int
        Indices into ``est.template_indices_`` (and ``est.train_values_``).
    cache : ModelCache

    Returns
    -------
    index : list of ndarray of shape (n_keys,)
        Read-only, one per template, as :func:`~ndlfd.learner._blend.align_many`.
    """
    window = float(est.match_window)
    key = ("aligned", window, _ALIGN_CANDIDATES, skel.tobytes())
    store = cache.memo(key, dict)
    with cache.locked():
        missing = [int(j) for j in templates if int(j) not in store]
    if missing:
        values = [est.train_values_[j] for j in missing]
        got = align_many(values, C, est.n_jobs, _ALIGN_CANDIDATES, window)
        for a in got:
            a.flags.writeable = False
        with cache.locked():
            for j, a in zip(missing, got, strict=True):
                store.setdefault(j, a)
    with cache.locked():
        return [store[int(j)] for j in templates]


def _weighing(logw: np.ndarray) -> np.ndarray:
    """Which demonstrations weigh (at least :data:`_KEEP_WEIGHT` of the largest)."""
    return np.exp(logw - logw.max()) >= _KEEP_WEIGHT


def _route_key(est, logw: np.ndarray) -> tuple:
    """What a route's segment model depends on: its demonstrations, the counts."""
    kept = np.packbits(_weighing(logw)).tobytes()
    return (est.n_time_bins, est.pseudo_transition, est.pseudo_emission, kept)


def route_model(est, logw: np.ndarray, cache: ModelCache | None = None):
    """The segment model of the demonstrations that weigh.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    logw : ndarray of shape (n_demos,)
        The demonstrations' log weights; those below :data:`_KEEP_WEIGHT` of
        the largest are left out.
    cache : ModelCache, optional
        Keep the model there, by the demonstrations that weigh.

    Returns
    -------
    model : ndlfd.hmm.DiscreteHMM
        ``est.segment_model_`` when every demonstration weighs.
    """
    demos = np.flatnonzero(_weighing(logw))
    if demos.size == logw.size:
        return est.segment_model_

    def make():
        return segment_model(
            est.fit_stats_,
            demos,
            est.codebook_.n_states,
            est.n_time_bins,
            pseudo_transition=est.pseudo_transition,
            pseudo_emission=est.pseudo_emission,
        )

    if cache is None:
        return make()
    return cache.memo(("route model", *_route_key(est, logw)), make)


def observations(est, times_or_demo):
    """Observation times and symbols of a timing (see :meth:`KeypointHMM.timing`).

    Returns
    -------
    key_times, symbols, all_times : ndarray
    """
    if isinstance(times_or_demo, Demonstration):
        d = prepare(times_or_demo, est.groups_, derive_velocity=est.derive_velocity)
        if d.columns != est.columns_:
            raise ValidationError(
                f"the demonstration's columns {d.columns} differ from the"
                f" learned columns {est.columns_}"
            )
        r = DemoSpec.of_model(est).reduce(d)
        return d.t[r.keypoints], r.key_bins, d.t
    t = check_times(times_or_demo, name="times")
    sym = est.time_bins_.transform(t)
    first = np.flatnonzero(np.r_[True, sym[1:] != sym[:-1]])
    if est.pseudo_emission == 0:
        first = first[est.symbols_seen_[sym[first]]]
    if first.size == 0:
        raise DecodeError(
            "none of the time bins of this timing was seen in training; cannot"
            " generate a path"
        )
    return t[first], sym[first], t


def decode_paper(est, times_or_demo):
    """The paper's decoding: key times, states, log-probability and all times."""
    key_t, symbols, all_t = est.timing(times_or_demo)
    states, logp = decode_states(est.decoder, est.model_, symbols, est.start)
    return key_t, states, logp, all_t


def decode_key_points(est, times_or_demo, cache: ModelCache):
    """Decoded key points of a timing: times, states, log-probability."""
    if est.generation == "paper":
        key_t, states, logp, _ = decode_paper(est, times_or_demo)
        return key_t, states, logp
    all_t = times_of(times_or_demo)
    plan = make_plan(est, all_t, None, None, cache)
    return key_times(all_t, plan.key_tau), plan.states, plan.logp


def render(
    est,
    plan: Plan,
    all_t,
    start,
    goal,
    *,
    dense: bool,
    cache: dict,
    via=None,
    prefix=None,
    with_std: bool = False,
    frames=None,
    clock: bool = False,
    ends=None,
):
    """The path of a plan: blended, in physical units, pinned, with velocity.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    plan : Plan
    all_t : ndarray of shape (n_samples,)
        The timing.
    start, goal : dict of str to ndarray, or None
        Checked conditions (the path begins and ends there).
    dense : bool
        Every time stamp, or the key points only.
    cache : dict
        The model's cache (which columns are two-valued, once per model).
    via : list of (float, dict), optional
        Checked via points the path passes through
        (:func:`~ndlfd.learner._via.apply_via`).
    prefix : Demonstration, optional
        Checked executed samples: the path is them, then continues from the
        last one (:func:`~ndlfd.learner._via.continue_from`; dense).
    with_std : bool, default=False
        Also the band: the weighted standard deviation of the templates the
        path blends, aligned as they are blended
        (:func:`~ndlfd.learner._blend.spread`), in physical units.
    frames : dict of str to ndarray, optional
        Checked new poses of the model's task frames: the templates are
        combined from their views in each (:mod:`ndlfd.learner._frames`).
    clock : bool, default=False
        Via points (or a start and goal) read on the templates' own clocks
        (:func:`~ndlfd.learner._choice.via_plan`).
    ends : tuple of (dict or None), optional
        A start and goal as frames the templates move with, given a goal
        (:func:`~ndlfd.learner._choice.frame_ends`, ``plan_end_shift``).

    Returns
    -------
    path : Demonstration
    band_tau : ndarray
        The normalized times of the path's rows.
    std : ndarray of shape (n_rows, n_columns) or None
        The band at the path's rows (``with_std``).
    """
    tq = est.time_bins_.normalize(all_t)
    groups = est.column_groups_
    at = np.concatenate([tq, plan.key_tau])  # the dense rows, then the key rows
    obs_tau, observed = blend_observations(est, tq, start=start, via=via,
                                           prefix=prefix, goal=goal)  # fmt: skip
    n_at = at.size  # the observations' rows come after, dropped after the blend
    qc = quat_columns(groups)
    index, mix = frame_parts(est, plan, frames, qc, cache)  # (plan.index, None)
    moved_first = via is not None and ends is not None and ends[1] is not None
    if moved_first:  # start, via points and goal as frames, before conditioning
        mix = via_frame_mix(est, plan, obs_tau, observed)
    templates = (plan.values, plan.taus, index, plan.weights, plan.knots)
    step = output_step(tq)  # every read of the templates is for this path
    if clock:  # a via point's templates on their own clocks (._choice)
        index = clock_aligned(plan.taus, plan.knots)
        templates = (plan.values, plan.taus, index, plan.weights, plan.knots)
    phase_at, phase_obs = at, obs_tau
    if observed and not clock:  # the clock warped to meet them (._phase)

        def mean(p):
            return blend(*templates, p, quat_cols=qc, mix=mix, step=step)

        phase_at, phase_obs = warp_for(mean, at, obs_tau, observed,
                                       prefix=prefix is not None)  # fmt: skip
    std = None
    if with_std:  # at the rows the path keeps, on the (warped) clock
        rows = (
            phase_at[: tq.size] if dense or prefix is not None else phase_at[tq.size :]
        )
        std = spread(*templates, rows, quat_cols=qc, mix=mix, step=step)
        std = est.scaler_.inverse_scale(std)
    observed = [(n_at + k, c, v) for k, c, v in observed] or None
    ridge = CONDITION_RIDGE if prefix is None else PREFIX_RIDGE
    ridge, reach = (CLOCK_RIDGE, np.inf) if clock else (ridge, CONDITION_REACH)
    U = blend(*templates, np.concatenate([phase_at, phase_obs]), quat_cols=qc,
              observed=observed, ridge=ridge, mix=mix, step=step,
              reach=reach)[:n_at]  # fmt: skip
    if not moved_first and ends is not None and ends[1] is not None:
        U = U + plan_end_shift(est, plan, at, ends)  # start and goal as frames
    if "two-valued" not in cache:  # the training data's only: once per model
        cache["two-valued"] = two_valued_columns(est.train_values_, groups)
    U = snap_two_valued(U, cache["two-valued"])
    X = renormalized(est.scaler_.inverse_transform(U, weighted=False), groups)
    X = renormalized(pin(X, at, start, goal, groups, tq.size), groups)
    if via is not None:
        X = renormalized(apply_via(X, at, via, groups, tq.size), groups)
    if prefix is not None:
        X = X[: tq.size]
        X = renormalized(continue_from(X, tq, prefix, groups), groups)
    X = snap_physical(est.scaler_, X, cache["two-valued"])  # the offsets moved them
    key_tau = plan.key_tau if prefix is None else plan.key_tau[:0]  # no key rows
    X = derive_velocity(X, tq, key_tau, all_t, groups)
    if prefix is not None:
        X[: prefix.t.size] = prefix.X  # the observed samples, velocity too
    if dense or prefix is not None:
        return Demonstration(all_t, X[: tq.size], est.columns_, groups), tq, std
    key_t = key_times(all_t, plan.key_tau)
    path = Demonstration(key_t, X[tq.size :], est.columns_, groups)
    return path, plan.key_tau, std


def generate_blend(
    est,
    times_or_demo,
    *,
    dense,
    start,
    goal,
    return_std,
    cache,
    via=None,
    observed=None,
    frames=None,
):
    """The blended generation (see :meth:`KeypointHMM.generate`)."""
    all_t = times_of(times_or_demo)
    frames = check_new_frames(est, frames)
    cols, groups = est.column_groups_, est.groups_
    start, goal = orient_conditions(est, start, goal)
    via = orient_via(est, check_via(via, all_t, cols, groups), cache)
    fill = prefix_completer(est, all_t, goal, frames, cache)
    prefix = check_observed(est, complete_prefix(est, observed, all_t, fill), all_t,
                            start=start, via=via)  # fmt: skip
    prefix, restore = orient_prefix(est, prefix, all_t, cache)  # -q is q
    extra = route = None
    if via is not None:
        extra = via_log_weights(est, via, cache)
    elif prefix is not None:
        tq = est.time_bins_.normalize(all_t)
        extra = observed_log_weights(est, prefix, tq, cache)
        route = prefix_route(est, prefix, all_t.size, goal, cache)
    ends = (None, None)  # a goal that places the task (._choice): templates even
    if prefix is None and frames is None:
        ends = frame_ends(est, start, goal)
    plan = make_plan(est, all_t, start, goal, cache, extra, route,
                     even=frames if ends[1] is None else True)  # fmt: skip
    clock = False
    if via is not None and frames is None:  # by place or by clock (._choice)
        by, clock = via_plan(est, make_plan, all_t, start, goal, via, extra, cache,
                             None if ends[1] is not None else plan)  # fmt: skip
        if clock or ends[1] is None:  # by place with a goal: via points as frames
            plan, ends = by, (None, None)
    path, _, std = render(est, plan, all_t, start, goal, dense=dense, cache=cache,
                          via=via, prefix=prefix, with_std=return_std,
                          frames=frames, clock=clock, ends=ends)  # fmt: skip
    return (restore(path), std) if return_std else restore(path)


def prefix_completer(est, all_t, goal, frames, cache):
    """``plan_path(start)``: the dense path for the timing from a start (checked)."""

    def plan_path(start):
        start_, goal_ = orient_conditions(est, start, goal)
        plan = make_plan(est, all_t, start_, goal_, cache, even=frames)
        return render(est, plan, all_t, start_, goal_, dense=True, cache=cache,
                      frames=frames)[0]  # fmt: skip

    return plan_path


def generate_paper(
    est,
    times_or_demo,
    *,
    dense,
    start,
    goal,
    return_std,
    cache,
    via=None,
    observed=None,
    frames=None,
):
    """The paper's generation (see :meth:`KeypointHMM.generate`)."""
    if via is not None or observed is not None or frames is not None:
        raise ValidationError(
            "via, observed and frames need generation='blend'; the paper's"
            " generation has none of them"
        )
    if return_std:
        raise ValidationError(
            "return_std needs generation='blend'; the paper's generation has"
            " no uncertainty band"
        )
    groups = est.column_groups_
    start, goal = orient_conditions(est, start, goal)
    key_t, states, _, all_t = decode_paper(est, times_or_demo)
    X = est.scaler_.inverse_transform(state_centres(est, states), weighted=False)
    X = renormalized(X, groups)
    if dense:
        X = np.column_stack(
            [np.interp(all_t, key_t, X[:, c]) for c in range(X.shape[1])]
        )
        X = renormalized(X, groups)
        key_t = all_t
    if start is not None or goal is not None:
        tq = unit_time(np.r_[all_t[0], key_t, all_t[-1]])[1:-1]
        X = renormalized(pin(X, tq, start, goal, groups), groups)
    return Demonstration(key_t, X, est.columns_, groups)


#: Generations: functions ``(est, times_or_demo, *, dense, start, goal,
#: return_std, cache, via, observed, frames) -> path or (path, std)``.
GENERATIONS = Registry("generation")
GENERATIONS.add("blend", generate_blend)
GENERATIONS.add("paper", generate_paper)
