"""The route of an executed prefix, from the prefix itself (no plan time).

A robot replanning during an execution calls ``generate(times,
observed=prefix)`` again and again. Its plan's duration is a guess: a plan
10 % longer or shorter than the execution puts the prefix's samples at the
wrong normalized times, and anything that compares the prefix with the
demonstrations *at those times* (time bins, forward filtering) may take the
prefix for the other route. While the prefix has not yet reached the place
where the routes part, nothing tells them apart, and a rule that weighs the
routes anew at every tick may flip from one to the other and back.

So a route is *ruled out* by the prefix's shape alone, once and for good,
when the prefix makes it :data:`COMMIT_ODDS` times less likely than another:

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
  and it can only grow with ``i``. It is taken twice: of the places (where
  the prefix is) and of the motion (the prefix and the curves each less
  their first point: where it goes from where it began, so a start a few
  degrees off, as every episode's is, does not hide the direction);
* each route's distances are in units of that route's own spread
  (:func:`route_spreads`: the median, over its templates, of the Fréchet
  distance to the nearest other template of the route, of the places and of
  the motion; a median, so it does not grow with the number of
  demonstrations as a largest one does), and the prefix's evidence for the
  route is a Gaussian's, ``-(d_place**2 + d_motion**2) / 2`` in those units
  (:func:`prefix_evidence`);
* with the routes' prior weights (the most demonstrations, or a goal's), a
  route is ruled out when, for some first ``i`` samples, its posterior is
  below ``1 / COMMIT_ODDS`` of the best route's: the odds are fixed, so the
  decision is the same however many demonstrations there are. Judged over
  every ``i``, a route once ruled out stays so as the prefix grows (the
  hysteresis: a route comes back only if every route is ruled out, and then
  it is the one ruled out last, :func:`allowed_routes`);
* ``generate`` follows, among the routes not ruled out, the one with the
  largest prior weight: while the prefix is ambiguous that is the same route
  at every tick, and it changes only when that route is ruled out (once).
  ``sample`` draws among them by the prior.
"""

from __future__ import annotations

import numpy as np

from ._curves import frechet_matrix, open_end_frechet, route_curves
from ._routes import (
    CURVES_KEY,
    MAX_JUDGED,
    MIN_GAP,
    route_columns,
    route_probabilities,
)

__all__ = [
    "COMMIT_ODDS",
    "allowed_routes",
    "prefix_distances",
    "prefix_evidence",
    "prefix_stride",
    "route_prior",
    "route_spreads",
]

#: Prefix samples matched, at most (the stride: the timing's length over it).
PREFIX_MATCH_POINTS = 256

#: Odds against a route (posterior, prior included) at which a prefix rules
#: it out for good.
COMMIT_ODDS = 20.0

#: The least spread of a route, as a share of :data:`MIN_GAP` (a route of
#: identical templates, or of one, still has the recordings' noise).
SPREAD_FLOOR = 0.25


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


def prefix_distances(
    est, prefix_U: np.ndarray, stride: int, cache: dict, motion: bool = False
):
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
    motion : bool, default=False
        Of the motion: the prefix and every curve less its first point.

    Returns
    -------
    distances : ndarray of shape (n_routes, n_matched)
        Row ``r``, column ``i``: the least open-end Fréchet distance of the
        first ``i + 1`` matched samples to a template of route ``r``.
    """
    curves, cols, _ = _curves(est, cache)
    rows = np.arange(0, prefix_U.shape[0], stride)  # the same at every tick
    P = np.ascontiguousarray(prefix_U[np.ix_(rows, cols)], dtype=np.float64)
    if motion:
        curves = curves - curves[:, :1]
        P = P - P[:1]
    per = open_end_frechet(P, curves)
    routes = np.asarray(est.routes_)[est.template_indices_]
    n_routes = int(np.max(est.routes_)) + 1
    out = np.full((n_routes, rows.size), np.inf)
    for r in range(n_routes):
        mine = routes == r
        if mine.any():
            out[r] = per[mine].min(axis=0)
    return out


def _near_same_route(D: np.ndarray, routes: np.ndarray) -> np.ndarray:
    """Each template's distance to its nearest other template of its route."""
    same = routes[:, None] == routes[None, :]
    np.fill_diagonal(same, False)
    return np.where(same, D, np.inf).min(axis=1)


def route_spreads(est, cache: dict) -> np.ndarray:
    """Each route's spread, of the places and of the motion (once per model).

    The median, over a route's templates, of the Fréchet distance to the
    nearest other template of the route: of the route curves as they are,
    and less their first points (the motion). At least ``SPREAD_FLOOR *
    MIN_GAP``; a route of one template takes the median over all routes'.

    Returns
    -------
    spreads : ndarray of shape (2, n_routes)
        Row 0 of the places, row 1 of the motion.
    """
    if "prefix spreads" not in cache:
        curves, _, D = _curves(est, cache)
        routes = np.asarray(est.routes_)[est.template_indices_]
        if D.shape[0] < curves.shape[0]:  # more templates than judged
            D = frechet_matrix(curves)
        motion = frechet_matrix(curves - curves[:, :1])
        n_routes = int(np.max(est.routes_)) + 1
        out = np.full((2, n_routes), SPREAD_FLOOR * MIN_GAP)
        for k, M in enumerate((D, motion)):
            near = _near_same_route(M, routes)
            ok = np.isfinite(near)
            pooled = float(np.median(near[ok])) if ok.any() else 0.0
            for r in range(n_routes):
                mine = ok & (routes == r)
                value = float(np.median(near[mine])) if mine.any() else pooled
                out[k, r] = max(value, out[k, r])
        cache["prefix spreads"] = out
    return cache["prefix spreads"]


def prefix_evidence(est, prefix_U: np.ndarray, stride: int, cache: dict):
    """Each route's log-evidence from the prefix's first samples.

    ``-(d_place**2 + d_motion**2) / 2`` with each open-end distance
    (:func:`prefix_distances`) in units of the route's spread
    (:func:`route_spreads`).

    Returns
    -------
    evidence : ndarray of shape (n_routes, n_matched)
    """
    spread = route_spreads(est, cache)
    place = prefix_distances(est, prefix_U, stride, cache) / spread[0][:, None]
    motion = prefix_distances(est, prefix_U, stride, cache, True) / spread[1][:, None]
    return -0.5 * (place**2 + motion**2)


def allowed_routes(
    est, prefix_U: np.ndarray, stride: int, cache: dict, prior=None
) -> np.ndarray:
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
    prior : ndarray of shape (n_routes,), optional
        The routes' prior weights (even by default).

    Returns
    -------
    allowed : ndarray of shape (n_routes,), dtype bool
        At least one true: when every route was ruled out at some point, the
        one ruled out last.
    """
    n_routes = int(np.max(est.routes_)) + 1
    if n_routes == 1:
        return np.ones(1, dtype=bool)
    post = prefix_evidence(est, prefix_U, stride, cache)
    if prior is not None:
        post = (
            post
            + np.log(np.maximum(np.asarray(prior, dtype=np.float64), 1e-300))[:, None]
        )
    out = post < post.max(axis=0) - np.log(COMMIT_ODDS)
    if not out.any(axis=1).all():
        return ~out.any(axis=1)
    first_out = np.argmax(out, axis=1)  # the sample that ruled each out
    return first_out == first_out.max()


def route_prior(est, prefix, n_times: int, logw, routes, cache) -> np.ndarray:
    """Each route's prior share, zero for the routes a prefix ruled out.

    The routes' shares (:func:`~ndlfd.learner._routes.route_probabilities` of
    the demonstrations' log weights ``logw``) are the prior of
    :func:`allowed_routes`, which rules out the routes the prefix (a checked
    :class:`~ndlfd.Demonstration`) has left.

    Returns
    -------
    p : ndarray of shape (n_routes,)
        Sums to 1 (ties of ``argmax``: the lowest route number).
    """
    U = est.scaler_.transform(prefix.X, weighted=False)
    prior = route_probabilities(routes, logw)
    ok = allowed_routes(est, U, prefix_stride(n_times), cache, prior)
    p = np.where(ok, prior, 0.0)
    if not p.sum() > 0:  # every allowed route's weight underflowed: the allowed
        p = ok.astype(np.float64)
    return p / p.sum()
