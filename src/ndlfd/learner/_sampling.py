"""Sampling: paths drawn from the model, each on one route of the demonstrations.

:meth:`KeypointHMM.sample` draws every path in three steps, the same parts as
the blended generation (:mod:`ndlfd.learner._generation`) with draws where it
takes the most probable choice:

* **the route**, in proportion to its total weight: the weights
  :func:`~ndlfd.learner._routes.choose_route` sums (one per demonstration
  without a start or goal, so a route shown by 9 of 12 demonstrations is
  drawn 3 times in 4; with a start, goal or via points the conditioned
  kernel weights; with an executed prefix the same weights over the routes
  the prefix has not ruled out, :mod:`ndlfd.learner._prefix_route`, so a
  prefix that has left a route never draws it);
* **the skeleton**, the segment state of every time bin, drawn from its exact
  posterior under the route's segment model by forward-filtering
  backward-sampling (:func:`ndlfd.hmm.sample_paths`), instead of the decoded
  most probable one; a key point where the state changes;
* **the blend weights** of the route's templates, drawn from a Dirichlet
  distribution of total concentration :data:`CONCENTRATION` whose mean is
  the generation's weights (even, with task frames or when ``generate``
  would read the via points by clock, :mod:`ndlfd.learner._choice`, and
  every sample is then read so too). The skeleton alone moves the key points'
  timing and the matches, but the blend still averages every template, so
  all samples lie close to the mean path (on the two-route obstacle of the
  tests their spread was 0.24 of the demonstrations'). A
  Dirichlet-weighted average of the templates stays within their convex
  hull, so a sample is never wilder than the demonstrations; the
  concentration sets how far from their mean it goes (see
  :data:`CONCENTRATION`).

The templates are then aligned to the drawn skeleton, blended and pinned to
the start and goal (or continued from a prefix's last sample) exactly as
:func:`~ndlfd.learner._generation.make_plan` and
:func:`~ndlfd.learner._generation.render` do. The same input and random state
give the same samples.
"""

from __future__ import annotations

import numpy as np

from .. import hmm
from .._validation import check_positive_int, check_random_state
from ..demonstration import Demonstration
from ._choice import via_plan
from ._conditioning import check_condition
from ._frames import check_new_frames
from ._generation import (
    demo_log_weights,
    make_plan,
    orient_conditions,
    plan_from_states,
    prefix_completer,
    render,
    route_model,
    template_weights,
    times_of,
)
from ._prefix_route import route_prior
from ._routes import route_probabilities
from ._via import (
    check_observed,
    check_via,
    complete_prefix,
    observed_log_weights,
    orient_prefix,
    orient_via,
    via_log_weights,
)

__all__ = ["CONCENTRATION", "sample_paths"]

#: Total Dirichlet concentration of a sample's template weights. The variance
#: of a Dirichlet-weighted mean of ``n`` points is about their variance over
#: ``CONCENTRATION + 1``. Measured on the major route of the two-route
#: obstacle of ``tests/learner/test_learner_sampling.py`` (200 draws, the
#: standard deviation across samples, RMS over the course, over the
#: demonstrations'): 0.24 without Dirichlet weights, 0.46 at 4, 0.65 at 1,
#: 0.79 at 0.3. At 1 a sample is a mix of the templates (not a copy of one)
#: that varies about two thirds as much as they do.
CONCENTRATION = 1.0


def _seen_only(states: np.ndarray, seen: np.ndarray) -> np.ndarray:
    """Bins in a state without a centroid (never seen) keep the state before.

    Only with ``pseudo_emission > 0`` can a drawn path pass through an unseen
    state; the first bin is seen whenever any is.
    """
    ok = np.isin(states, seen)
    if ok.all() or not ok.any():
        return states
    at = np.maximum.accumulate(np.where(ok, np.arange(states.size), -1))
    at[at < 0] = np.flatnonzero(ok)[0]
    return states[at]


def sample_paths(
    est,
    times_or_demo,
    n_samples,
    *,
    dense,
    start,
    goal,
    random_state,
    cache,
    via=None,
    observed=None,
    frames=None,
):
    """Paths drawn from a fitted model (see :meth:`KeypointHMM.sample`).

    Parameters
    ----------
    est : KeypointHMM
        Fitted, with training values (format 2 or later).
    times_or_demo : Demonstration or ndarray of shape (n_times,)
        The timing.
    n_samples : int
        Number of paths.
    dense : bool
        Every time stamp, or each path's key points only.
    start, goal : mapping of str to array-like, or None
        Where the paths start and end (as in :meth:`KeypointHMM.generate`).
    random_state : None, int or numpy.random.Generator
        The source of every draw.
    via : sequence of (float, mapping), optional
        Via points (:mod:`ndlfd.learner._via`): the routes weighted by them,
        every path through them.
    observed : Demonstration, optional
        The samples executed so far (:mod:`ndlfd.learner._via`): the routes
        weighted by them, every path them and then its continuation from the
        last one (every time stamp, as :meth:`KeypointHMM.generate`).
    frames : mapping of str to array-like, optional
        New poses of the model's task frames (:mod:`ndlfd.learner._frames`).
    cache : ModelCache
        The model's cache (:func:`~ndlfd.learner._generation.demo_log_weights`).

    Returns
    -------
    paths : list of Demonstration
        ``n_samples`` of them.
    """
    groups, cols = est.groups_, est.column_groups_
    start = check_condition(start, "start", cols, groups)
    goal = check_condition(goal, "goal", cols, groups)
    start, goal = orient_conditions(est, start, goal)
    n_samples = check_positive_int(n_samples, "n_samples")
    rng = check_random_state(random_state)
    all_t = times_of(times_or_demo)
    via = orient_via(est, check_via(via, all_t, cols, groups), cache)
    frames = check_new_frames(est, frames)
    fill = prefix_completer(est, all_t, goal, frames, cache)
    observed = complete_prefix(est, observed, all_t, fill)
    prefix = check_observed(est, observed, all_t, start=start, via=via)
    prefix, restore = orient_prefix(est, prefix, all_t, cache)  # -q is q
    logw, routes = demo_log_weights(est, start, goal, cache)
    extra = via_log_weights(est, via, cache)
    logw = logw + extra
    clock = False  # generate's reading of the via points (._choice)
    if via is not None and frames is None:
        clock = via_plan(est, make_plan, all_t, start, goal, via, extra, cache)[1]
    if prefix is None:
        p = route_probabilities(routes, logw)
    else:  # the routes the prefix has not ruled out, the blend as generate's
        tq = est.time_bins_.normalize(all_t)
        p = route_prior(est, prefix, all_t.size, logw, routes, cache)
        logw = logw + observed_log_weights(est, prefix, tq, cache)
    drawn = rng.choice(p.size, size=n_samples, p=p)
    bins = np.arange(est.n_time_bins)
    out: list[Demonstration | None] = [None] * n_samples
    for route in np.unique(drawn):
        who = np.flatnonzero(drawn == route)
        even = frames is not None or clock  # every template alike (._choice)
        lw = np.where(routes == route, 0.0 if even else logw, -np.inf)
        model = route_model(est, lw, cache)
        skeletons = hmm.sample_paths(
            model, bins, who.size, start=est.start, random_state=rng
        )
        _, tw = template_weights(est, lw)
        alpha = CONCENTRATION * tw / tw.sum()
        for k, states in zip(who, skeletons, strict=True):
            g = rng.dirichlet(alpha) if tw.size > 1 else np.ones(1)
            states = _seen_only(states, est.centroid_states_)
            plan = plan_from_states(est, states, np.nan, model, lw, g / g.max())
            out[k] = render(est, plan, all_t, start, goal, dense=dense, cache=cache,
                            via=via, prefix=prefix, frames=frames,
                            clock=clock)[0]  # fmt: skip
    return [restore(path) for path in out]
