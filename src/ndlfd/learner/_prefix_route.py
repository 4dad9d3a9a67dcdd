"""The route of an executed prefix, from the prefix itself (no plan time).

A robot replanning during an execution calls ``generate(times,
observed=prefix)`` again and again. Its plan's duration is a guess: a plan
10 % longer or shorter than the execution puts the prefix's samples at the
wrong normalized times, and anything that compares the prefix with the
demonstrations *at those times* (time bins, forward filtering) may take the
prefix for the other route. While the prefix has not yet reached the place
where the routes part, nothing tells them apart, and a rule that weighs the
routes anew at every tick may flip from one to the other and back.

So a route is *ruled out* by the prefix's shape alone, once and for good:

* the prefix's samples on the route columns
  (:func:`~ndlfd.learner._routes.route_columns`, normalized), every
  ``stride``-th of them (a stride fixed by the timing, so the samples matched
  are the same at every tick; 1 for a timing of up to
  :data:`PREFIX_MATCH_POINTS` stamps), are matched against every
  template's route curve (:func:`~ndlfd.learner._curves.route_curves`) by
  the *open-end* discrete Fréchet distance: the least, over monotone
  pairings of the prefix with any beginning of the curve, of the largest
  distance of a pair. Pace-free: the plan's duration does not enter. For
  every first ``i`` samples it is known at once (:func:`prefix_distances`),
  and it can only grow with ``i``;
* a route is ruled out when, for some first ``i`` samples, its nearest
  template is farther than the nearest template of any route plus
  :func:`route_margin` (twice how far a demonstration strays from the
  others of its route, at least half of
  :data:`~ndlfd.learner._routes.MIN_GAP`, at most half the distance between
  two routes): the prefix has left it by more than its demonstrations ever
  do. Judged over every ``i``, a route once ruled out stays so as the prefix
  grows (:func:`allowed_routes`);
* ``generate`` follows, among the routes not ruled out, the one with the
  largest prior weight (the most demonstrations, or a goal's): while the
  prefix is ambiguous that is the same route at every tick, and it changes
  only when that route is ruled out (once). ``sample`` draws among them by
  the prior.
"""

from __future__ import annotations

import numpy as np

from ._curves import frechet_matrix, open_end_frechet, route_curves
from ._routes import CURVES_KEY, MAX_JUDGED, MIN_GAP, route_columns

__all__ = ["allowed_routes", "prefix_distances", "prefix_stride", "route_margin"]

#: Prefix samples matched, at most (the stride: the timing's length over it).
PREFIX_MATCH_POINTS = 256


def prefix_stride(n_times: int) -> int:
    """Every how many prefix samples one is matched (fixed by the timing).

    Examples
    --------
    >>> prefix_stride(200), prefix_stride(1000)
    (1, 4)
    """
    return max(1, -(-int(n_times) // PREFIX_MATCH_POINTS))


def _curves(est, cache: dict):
    """The templates' route curves, columns and distances (once per model).

    Kept by the fit (:func:`~ndlfd.learner._routes.model_routes`); made here
    for a model whose cache lacks them.
    """
    if CURVES_KEY not in cache:
        cols = route_columns(est.column_groups_, getattr(est, "route_groups", None))
        curves = route_curves(est.train_values_, est.train_tau_, cols)
        cache[CURVES_KEY] = (curves, cols, frechet_matrix(curves[:MAX_JUDGED]))
    return cache[CURVES_KEY]


def prefix_distances(est, prefix_U: np.ndarray, stride: int, cache: dict):
    """Every route's open-end distance to the prefix's first samples.

    Parameters
    ----------
    est : KeypointHMM
        Fitted, with training values.
    prefix_U : ndarray of shape (n_samples, n_columns)
        The prefix, normalized (unweighted).
    stride : int
        :func:`prefix_stride`.
    cache : dict

    Returns
    -------
    distances : ndarray of shape (n_routes, n_matched)
        Row ``r``, column ``i``: the least open-end Fréchet distance of the
        first ``i + 1`` matched samples to a template of route ``r``.
    """
    curves, cols, _ = _curves(est, cache)
    rows = np.arange(0, prefix_U.shape[0], stride)  # the same at every tick
    P = np.ascontiguousarray(prefix_U[np.ix_(rows, cols)], dtype=np.float64)
    per = open_end_frechet(P, curves)
    routes = np.asarray(est.routes_)[est.template_indices_]
    n_routes = int(np.max(est.routes_)) + 1
    out = np.full((n_routes, rows.size), np.inf)
    for r in range(n_routes):
        mine = routes == r
        if mine.any():
            out[r] = per[mine].min(axis=0)
    return out


def route_margin(est, cache: dict) -> float:
    """How far past the nearest route a prefix must be to rule a route out.

    Twice the largest distance from a template to its nearest template of
    the same route (how far a demonstration strays from its route), at least
    ``MIN_GAP / 2`` and at most half the smallest distance between two
    routes' templates; once per model.
    """
    if "prefix margin" not in cache:
        curves, _, D = _curves(est, cache)
        routes = np.asarray(est.routes_)[est.template_indices_]
        if D.shape[0] < curves.shape[0]:  # more templates than judged
            D = frechet_matrix(curves)
        same = routes[:, None] == routes[None, :]
        np.fill_diagonal(same, False)
        near = np.where(same, D, np.inf).min(axis=1)
        stray = float(near[np.isfinite(near)].max()) if np.isfinite(near).any() else 0.0
        other = np.where(routes[:, None] != routes[None, :], D, np.inf)
        gap = float(other.min())
        cache["prefix margin"] = min(max(2.0 * stray, 0.5 * MIN_GAP), 0.5 * gap)
    return cache["prefix margin"]


def allowed_routes(est, prefix_U: np.ndarray, stride: int, cache: dict) -> np.ndarray:
    """The routes the prefix has not ruled out (see the module's text).

    Parameters
    ----------
    est : KeypointHMM
        Fitted, with training values.
    prefix_U : ndarray of shape (n_samples, n_columns)
        The prefix, normalized (unweighted).
    stride : int
        :func:`prefix_stride`.
    cache : dict

    Returns
    -------
    allowed : ndarray of shape (n_routes,), dtype bool
        At least one true: at every step the nearest route is within the
        margin of itself.
    """
    n_routes = int(np.max(est.routes_)) + 1
    if n_routes == 1:
        return np.ones(1, dtype=bool)
    D = prefix_distances(est, prefix_U, stride, cache)
    return ~np.any(D > D.min(axis=0) + route_margin(est, cache), axis=1)
