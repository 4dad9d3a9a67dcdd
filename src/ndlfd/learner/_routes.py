"""Routes: which demonstrations the decoded skeleton follows.

Demonstrations of one skill often take different routes (around an obstacle,
some on the left and some on the right). Blending all of them gives a path
between the routes, which nobody showed and which runs through the obstacle.
The blended generation therefore follows one route, found from the model
(the most probable single state sequence, Viterbi, is not enough: a route
shown by fewer demonstrations can hold a likelier sequence):

* every demonstration is, in the segment model, a path of states over the time
  bins (:func:`~ndlfd.learner._segments.segment_states`); with the states'
  centroids it is a curve in normalized units (:func:`segment_paths`);
* two templates are on one route when their curves are close: within
  :data:`LINK_FACTOR` times the typical distance between a template and its
  nearest neighbour, chained (single linkage); every other demonstration
  takes the route of its nearest template (:func:`route_labels`, once per
  model);
* the route followed is the most probable one: the one with the largest
  total weight of demonstrations (:func:`choose_route`). Without a start or
  goal that is the route most demonstrations take; a requested start or goal
  weights the demonstrations first (:mod:`~ndlfd.learner._conditioning`), so
  the route followed is the one that starts (ends) there.

The skeleton is decoded from the segment model of the route's demonstrations
alone, and the blend uses the route's templates: the path never runs between
routes.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_work_size

__all__ = [
    "LINK_FACTOR",
    "choose_route",
    "route_labels",
    "route_probabilities",
    "segment_paths",
]

#: Two templates are on one route when their curves lie within this many
#: times the median nearest-neighbour distance between templates (chained:
#: single linkage).
LINK_FACTOR = 3.0

#: Demonstrations per block when measuring route distances (bounds the
#: temporary memory at ``block * n_bins * n_dims`` floats).
_BLOCK = 2048


def segment_paths(stats, centroid_states: np.ndarray, n_bins: int) -> np.ndarray:
    """Every demonstration's segment-state path as rows of centroid indices.

    Parameters
    ----------
    stats : FitStats
        The fit statistics (each demonstration's key states and bins).
    centroid_states : ndarray of shape (n_seen,), dtype int64
        The sorted states that have a centroid (every state seen in training).
    n_bins : int
        Number of time bins.

    Returns
    -------
    paths : ndarray of shape (n_demos, n_bins), dtype int32
        ``paths[j, b]`` indexes the centroid of the state demonstration ``j``
        is in at bin ``b`` (its last key point at or before ``b``).

    Examples
    --------
    Two demonstrations, in states 5 then 9 (from bin 3) and 9 then 7 (bin 1):

    >>> from types import SimpleNamespace
    >>> stats = SimpleNamespace(n_keys=[2, 2], key_bins=[0, 3, 0, 1],
    ...                         key_states=[5, 9, 9, 7])
    >>> segment_paths(stats, np.array([5, 7, 9]), 4)
    array([[0, 0, 0, 2],
           [2, 1, 1, 1]], dtype=int32)
    """
    n_keys = np.asarray(stats.n_keys, dtype=np.int64)
    n_demos = n_keys.size
    check_work_size(
        8 * n_demos * n_bins,
        f"the segment paths of {n_demos} demonstrations over {n_bins} time bins",
        "fit with fewer time bins (n_time_bins)",
    )
    owner = np.repeat(np.arange(n_demos, dtype=np.int64), n_keys)
    # key points sorted by (demonstration, bin): one search for every bin
    keys = owner * (n_bins + 1) + np.asarray(stats.key_bins, dtype=np.int64)
    query = (np.arange(n_demos, dtype=np.int64)[:, None] * (n_bins + 1)) + np.arange(
        n_bins, dtype=np.int64
    )
    at = np.searchsorted(keys, query.ravel(), side="right") - 1
    first = np.cumsum(n_keys) - n_keys
    at = np.maximum(at, np.repeat(first, n_bins))  # the first key is at bin 0
    states = np.asarray(stats.key_states, dtype=np.int64)[at]
    index = np.searchsorted(centroid_states, states).astype(np.int32)
    return index.reshape(n_demos, n_bins)


def _curves(paths: np.ndarray, centroids: np.ndarray) -> np.ndarray:
    """Centroid curves ``(n, n_bins * n_dims)``, RMS-per-bin distances apart."""
    n, n_bins = paths.shape
    return centroids[paths].reshape(n, -1) / np.sqrt(n_bins)


def _sq_distances(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    a = np.einsum("ij,ij->i", A, A)
    b = np.einsum("ij,ij->i", B, B)
    return np.maximum(a[:, None] + b[None, :] - 2.0 * (A @ B.T), 0.0)


def route_labels(
    paths: np.ndarray, template_index: np.ndarray, centroids: np.ndarray
) -> np.ndarray:
    """Which route each demonstration takes.

    The templates' curves are linked when they lie within :data:`LINK_FACTOR`
    times the median distance from a template's curve to its nearest other
    one's (RMS over the bins); a route is a connected group of templates
    (single linkage). Every other demonstration takes the route of its
    nearest template. Routes are numbered by their first template.

    Parameters
    ----------
    paths : ndarray of shape (n_demos, n_bins), dtype int32
        :func:`segment_paths`.
    template_index : ndarray of shape (n_templates,), dtype int64
        The templates' rows in ``paths`` (at least one).
    centroids : ndarray of shape (n_seen, n_dims)
        The state centroids (normalized units).

    Returns
    -------
    labels : ndarray of shape (n_demos,), dtype int64

    Examples
    --------
    Two close curves and one far from both:

    >>> C = np.array([[0.0], [0.1], [5.0]])
    >>> route_labels(np.array([[0, 0], [1, 1], [2, 2]]), np.arange(3), C)
    array([0, 0, 1])
    """
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import connected_components

    T = _curves(paths[template_index], centroids)
    n_t = T.shape[0]
    if n_t < 2:
        return np.zeros(paths.shape[0], dtype=np.int64)
    d2 = _sq_distances(T, T)
    np.fill_diagonal(d2, np.inf)
    link = LINK_FACTOR * float(np.median(np.sqrt(d2.min(axis=1))))
    if not link > 0:  # most templates coincide: one route
        return np.zeros(paths.shape[0], dtype=np.int64)
    np.fill_diagonal(d2, 0.0)
    _, comp = connected_components(csr_matrix(d2 <= link * link), directed=False)
    _, first = np.unique(comp, return_index=True)  # number by first template
    rank = np.empty(first.size, dtype=np.int64)
    rank[np.argsort(first, kind="stable")] = np.arange(first.size)
    template_route = rank[comp]
    labels = np.empty(paths.shape[0], dtype=np.int64)
    for lo in range(0, paths.shape[0], _BLOCK):
        X = _curves(paths[lo : lo + _BLOCK], centroids)
        nearest = np.argmin(_sq_distances(X, T), axis=1)  # ties: first template
        labels[lo : lo + _BLOCK] = template_route[nearest]
    labels[template_index] = template_route
    return labels


def choose_route(labels: np.ndarray, log_weights: np.ndarray) -> int:
    """The most probable route: the largest total weight of its demonstrations.

    Parameters
    ----------
    labels : ndarray of shape (n_demos,), dtype int64
        :func:`route_labels`.
    log_weights : ndarray of shape (n_demos,)
        The demonstrations' log weights (0 without a start or goal: then the
        route most demonstrations take).

    Returns
    -------
    route : int
        Ties go to the lowest route number.

    Examples
    --------
    >>> choose_route(np.array([0, 1, 1]), np.zeros(3))
    1
    >>> choose_route(np.array([0, 1, 1]), np.array([0.0, -5.0, -5.0]))
    0
    """
    w = np.exp(log_weights - log_weights.max())
    return int(np.argmax(np.bincount(labels, weights=w)))


def route_probabilities(routes: np.ndarray, log_weights: np.ndarray) -> np.ndarray:
    """Probability of each route: its share of the demonstrations' weight.

    Parameters
    ----------
    routes : ndarray of shape (n_demos,), dtype int64
        Each demonstration's route (numbered from 0).
    log_weights : ndarray of shape (n_demos,)
        The demonstrations' log weights (0 without a start or goal).

    Returns
    -------
    p : ndarray of shape (n_routes,)
        Sums to 1; the route :func:`~ndlfd.learner._routes.choose_route`
        follows has the largest.

    Examples
    --------
    >>> route_probabilities(np.array([0, 0, 0, 1]), np.zeros(4))
    array([0.75, 0.25])
    """
    w = np.exp(log_weights - log_weights.max())
    total = np.bincount(routes, weights=w)
    return total / total.sum()
