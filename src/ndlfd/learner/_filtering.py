"""Continuing an execution: how well each demonstration explains a prefix.

``generate(times, observed=prefix)`` weighs the templates of the route it
continues on (the route itself is ruled by the prefix's shape,
:mod:`ndlfd.learner._prefix_route`) by how well each explains the executed
samples. The segment model (:mod:`ndlfd.learner._segments`), whose state at
every time bin is the segment of the motion a demonstration is in, gives an
observation model:

* *what is observed*: the prefix covers the time bins ``0..b`` (``b`` the
  bin of its last sample); the mean of its samples in each bin
  (:func:`bin_observations`, normalized units, every learned column) is an
  observation of the demonstration's segment state there, Gaussian around the
  state's centroid with a per-column variance fitted once per model: the mean
  squared distance of the templates' bin means from the centroids of their
  own segment states (:func:`observation_noise`; at least a codebook cell's,
  ``width**2 / 12``). A bin without a sample is no observation;
* *each demonstration's log-likelihood* of the prefix along its own segment
  path (:func:`path_log_likelihoods`), tempered by
  :data:`~ndlfd.learner._via.PATH_TEMPER` and added to the template matching
  of :func:`~ndlfd.learner._via.observed_log_weights` (measured there: 0.899
  to 0.870 on the single LASA shapes, 1.12 to 1.08 on Multi_Models).

Until issue 26 the route was chosen here too, by forward filtering on each
route's segment model: exact, but on the plan's time bins, so a plan longer
or shorter than the execution could take the prefix for another route, and
the posterior could swing between two routes from one tick to the next.
"""

from __future__ import annotations

import numpy as np

from ._routes import segment_paths

__all__ = [
    "bin_observations",
    "observation_noise",
    "path_log_likelihoods",
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
