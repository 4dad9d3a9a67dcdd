"""Continuing an execution: the route by forward filtering on the segment model.

``generate(times, observed=prefix)`` must tell from the executed samples
which route the robot is on and how far along it is. The segment model
(:mod:`ndlfd.learner._segments`), whose state at every time bin is the
segment of the motion a demonstration is in, gives both exactly:

* *what the model observes*: the prefix covers the time bins ``0..b`` (``b``
  the bin of its last sample); each bin is a step of the segment model (its
  symbol is the bin) and the mean of the prefix's samples in it (normalized
  units, every learned column) an observation of the step's state, Gaussian
  around the state's centroid with a per-column variance fitted once per
  model: the mean squared distance of the templates' bin means from the
  centroids of their own segment states (:func:`observation_noise`; at least
  a codebook cell's, ``width**2 / 12``). A bin without a sample is a step
  without an observation;
* *the route* (:func:`route_posterior`): every route
  (:mod:`ndlfd.learner._routes`) has its segment model (its demonstrations'
  counts); the forward pass over the prefix's bins
  (:func:`ndlfd.hmm._decode.forward_filter`) gives ``log p(prefix |
  route)``, and the route's posterior is that plus the log of its prior, its
  share of the demonstrations' weight (a goal's kernel, or 1 each);
* *the demonstrations' weights* (:func:`path_log_likelihoods`): each
  demonstration's log-likelihood of the prefix along its own segment path,
  the same observation model, tempered by
  :data:`~ndlfd.learner._via.PATH_TEMPER` and added to the template
  matching of :func:`~ndlfd.learner._via.observed_log_weights` (measured
  there: 0.899 to 0.870 on the single shapes, 1.12 to 1.08 on Multi_Models);
* *the state at the last observed bin* (``Filtered.probabilities`` of each
  route) says in which segment the robot is. It is not used for the blend's
  phase: a segment spans several bins, and the rate that matches the
  prefix's shape (:func:`~ndlfd.learner._phase.prefix_clock`) places the
  robot within it. Measured (leave-one-out LASA, protocol *P*, median over
  shapes of the per-shape DTW ratio to the best peer; ``/tmp`` harness over
  :func:`ndlfd.evaluate`, peers from the same code): the rate alone 0.899 on
  the 26 single shapes and 1.12 on Multi_Models; the phase at the middle of
  the filtered state's occupancy, instead of the rate, 1.23 and 1.49; the
  rate searched only where the phase lies in that occupancy, 0.885 and
  1.14, but worse paired fold by fold (geometric mean of the DTW ratios to
  the rate alone 1.032 on the single shapes, 0.988 on Multi_Models); the
  rate's cost plus the log of the probability that the route's
  demonstrations are in the filtered state at that phase, 0.875 and 1.14
  (paired 1.038 and 0.996); all with the template weights of before (no
  path term). The route itself was the same in every fold.

Exact (tested against enumerating every state path of a tiny model) and
cheap: a step costs ``O(seen states + counted transitions)`` of the route,
never the codebook's size; everything that depends on the training data
only (the routes' counts, the noise) is computed once per model.
"""

from __future__ import annotations

import numpy as np

from .._errors import DecodeError
from ..hmm._decode import filter_tables, forward_filter
from ..hmm._format import counts_from_arrays
from ._routes import route_probabilities, segment_paths
from ._segments import segment_model

__all__ = [
    "bin_observations",
    "filter_route",
    "observation_noise",
    "path_log_likelihoods",
    "route_counts",
    "route_posterior",
]


def bin_observations(U: np.ndarray, tau: np.ndarray, n_bins: int):
    """The mean of a prefix's samples in each time bin up to its last.

    Parameters
    ----------
    U : ndarray of shape (n_samples, n_columns)
        The samples (normalized units).
    tau : ndarray of shape (n_samples,)
        Their normalized times, increasing.
    n_bins : int

    Returns
    -------
    means : ndarray of shape (last_bin + 1, n_columns)
        NaN in a bin without a sample.

    Examples
    --------
    >>> bin_observations(np.array([[0.0], [2.0], [5.0]]),
    ...                  np.array([0.0, 0.1, 0.6]), 4)
    array([[ 1.],
           [nan],
           [ 5.]])
    """
    bins = np.clip(np.floor(tau * n_bins).astype(np.int64), 0, n_bins - 1)
    n = int(bins[-1]) + 1
    first = np.searchsorted(bins, np.arange(n))  # the samples are in time order
    counts = np.diff(np.r_[first, bins.size])
    means = np.full((n, U.shape[1]), np.nan)
    has = counts > 0
    means[has] = np.add.reduceat(U, first[has], axis=0) / counts[has, None]
    return means


def observation_noise(est, cache: dict) -> np.ndarray:
    """Per-column variance of an observed bin mean around its state's centroid.

    Fitted once per model on the templates (:func:`bin_observations` of each,
    against the centroid of its segment state in each bin), at least a
    codebook cell's ``(1 / levels)**2 / 12``.

    Parameters
    ----------
    est : KeypointHMM
        Fitted, with training values.
    cache : dict
        The model's cache (the noise under ``"filter noise"``, the segment
        paths under ``"segment paths"``).

    Returns
    -------
    variance : ndarray of shape (n_columns,)
    """
    if "filter noise" in cache:
        return cache["filter noise"]
    nt = est.n_time_bins
    if "segment paths" not in cache:  # as ndlfd.learner._via.demo_values_at
        cache["segment paths"] = segment_paths(est.fit_stats_, est.centroid_states_, nt)
    paths = cache["segment paths"]
    sq, n = 0.0, 0
    for k, j in enumerate(est.template_indices_):
        M = bin_observations(est.train_values_[k], est.train_tau_[k], nt)
        ok = ~np.isnan(M[:, 0])
        R = M[ok] - est.centroids_[paths[j, : M.shape[0]][ok]]
        sq, n = sq + np.sum(R * R, axis=0), n + int(ok.sum())
    floor = (1.0 / np.asarray(est.codebook_.levels, dtype=np.float64)) ** 2 / 12.0
    var = np.maximum(sq / max(n, 1), floor)
    cache["filter noise"] = var
    return var


def route_counts(est, routes: np.ndarray, cache: dict) -> list:
    """Every route's segment model as counts, with its states' centroid rows.

    Once per model (under ``"route counts"``): the
    :func:`~ndlfd.learner._segments.segment_model` of the route's
    demonstrations.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    routes : ndarray of shape (n_demos,), dtype int64
        Each demonstration's route (numbered from 0).
    cache : dict

    Returns
    -------
    tables : list of (Counts, ndarray of int, FilterTables)
        Per route, the counts, the row in ``est.centroids_`` of each of their
        seen states, and their forward filter's tables.
    """
    if "route counts" in cache:
        return cache["route counts"]
    out = []
    for r in range(int(routes.max()) + 1):
        model = segment_model(
            est.fit_stats_,
            np.flatnonzero(routes == r),
            est.codebook_.n_states,
            est.n_time_bins,
            pseudo_transition=est.pseudo_transition,
            pseudo_emission=est.pseudo_emission,
        )
        counts, _ = counts_from_arrays(model.to_arrays())
        rows = np.searchsorted(est.centroid_states_, counts.states)
        out.append((counts, rows, filter_tables(counts, est.start)))
    cache["route counts"] = out
    return out


def filter_route(est, route, means: np.ndarray, var: np.ndarray):
    """Forward filtering of a prefix's bin means on one route's segment model.

    Parameters
    ----------
    est : KeypointHMM
        Fitted.
    route : tuple
        The route's segment model, its states' centroid rows and tables
        (:func:`route_counts`).
    means : ndarray of shape (n_steps, n_columns)
        :func:`bin_observations` (normalized units; NaN rows unobserved).
    var : ndarray of shape (n_columns,)
        :func:`observation_noise`.

    Returns
    -------
    filtered : ndlfd.hmm._decode.Filtered
        The state at the last observed bin, and ``log p(prefix | route)``.
    """
    counts, rows, tables = route
    C = est.centroids_[rows]
    D = means[:, None, :] - C[None, :, :]
    loglik = -0.5 * np.sum(D * D / var, axis=2) - 0.5 * np.sum(np.log(2 * np.pi * var))
    loglik[np.isnan(means[:, 0])] = 0.0  # a bin without a sample: no observation
    steps = np.arange(means.shape[0])
    return forward_filter(counts, steps, est.start, loglik, tables)


def route_posterior(est, prefix_U, prefix_tau, routes, log_weights, cache: dict):
    """Every route's log posterior given a prefix, and the filtered states.

    Parameters
    ----------
    est : KeypointHMM
        Fitted, with training values.
    prefix_U : ndarray of shape (n_samples, n_columns)
        The prefix (normalized units, unweighted).
    prefix_tau : ndarray of shape (n_samples,)
        Its normalized times.
    routes : ndarray of shape (n_demos,), dtype int64
        Each demonstration's route.
    log_weights : ndarray of shape (n_demos,)
        The demonstrations' log weights (a goal's; 0 without): a route's
        prior is its share (:func:`~ndlfd.learner._routes.route_probabilities`).
    cache : dict

    Returns
    -------
    log_posterior : ndarray of shape (n_routes,)
        Normalized (``logsumexp`` 0).
    filtered : list of Filtered or None
        Per route, the state at the last observed bin (``None`` for a route
        not considered or that cannot emit the prefix, and for the only
        route considered: its posterior is 1 without filtering).

    Raises
    ------
    DecodeError
        If no route can emit the prefix.
    """
    with np.errstate(divide="ignore"):  # a share that underflows: not considered
        log_prior = np.log(route_probabilities(routes, log_weights))
    if np.isfinite(log_prior).sum() == 1:  # one route: nothing to weigh
        return np.where(np.isfinite(log_prior), 0.0, -np.inf), [None] * log_prior.size
    means = bin_observations(prefix_U, prefix_tau, est.n_time_bins)
    var = observation_noise(est, cache)
    logp = np.full(log_prior.size, -np.inf)
    filtered: list = [None] * log_prior.size
    error = None
    for r, route in enumerate(route_counts(est, routes, cache)):
        if not np.isfinite(log_prior[r]):
            continue
        try:
            filtered[r] = filter_route(est, route, means, var)
        except DecodeError as e:  # this route cannot emit the prefix's bins
            error = e
            continue
        logp[r] = log_prior[r] + filtered[r].log_likelihood
    if not np.isfinite(logp).any():
        raise error or DecodeError("no route of the model can emit the prefix")
    top = logp.max()
    return logp - (top + np.log(np.sum(np.exp(logp - top)))), filtered


def path_log_likelihoods(est, prefix_U, prefix_tau, cache: dict) -> np.ndarray:
    """Each demonstration's log-likelihood of a prefix along its own segment path.

    The observation model of :func:`filter_route` (the prefix's bin means
    around the centroids, :func:`observation_noise`) on the one state path a
    demonstration takes (:func:`~ndlfd.learner._routes.segment_paths`), up
    to a constant shared by all demonstrations.

    Parameters
    ----------
    est : KeypointHMM
        Fitted, with training values.
    prefix_U : ndarray of shape (n_samples, n_columns)
        The prefix (normalized units, unweighted).
    prefix_tau : ndarray of shape (n_samples,)
        Its normalized times.
    cache : dict

    Returns
    -------
    log_likelihoods : ndarray of shape (n_demos,)
        ``-0.5 * sum`` over the observed bins of the squared distances to the
        path's centroids over the noise variance.
    """
    means = bin_observations(prefix_U, prefix_tau, est.n_time_bins)
    var = observation_noise(est, cache)  # fills the segment paths too
    ok = np.flatnonzero(~np.isnan(means[:, 0]))
    out = np.zeros(est.n_demos_)
    for b in ok:  # a bin at a time: memory of one bin's centroids
        D = est.centroids_[cache["segment paths"][:, b]] - means[b]
        out -= 0.5 * np.sum(D * D / var, axis=1)
    return out
