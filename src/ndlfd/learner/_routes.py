"""Routes: which demonstrations take the same way, found once per fit.

Demonstrations of one skill often take different routes (around an obstacle,
some on the left and some on the right). Blending all of them gives a path
between the routes, which nobody showed and which runs through the obstacle.
The blended generation therefore follows one route.

**Where routes are judged.** On the *route columns* (:func:`route_columns`):
the ``position`` group when the model has one, else every group but
velocity, orientation, force and a gripper (a joint-space model: its
joints), or the groups named by ``route_groups``. Velocity, orientation and
a gripper's timing vary from one demonstration of a route to the next (phase
jitter, speed) without making another route, and a whole-motion distance
over every group dilutes a brief divergence in that variation.

**How demonstrations are compared.** Each template (a demonstration kept
whole) becomes a curve of :data:`~ndlfd.learner._curves.ROUTE_POINTS` points
on its route columns (normalized units, :mod:`ndlfd.learner._curves`): its
samples averaged over short windows of time, then spaced half by time and
half by the distance travelled, so a rest at the start or between motions
takes few points and a brief detour keeps some, and point ``i`` of every
curve is at about the same phase. Which curves go together is read from
their *discrete Fréchet distances* (the least, over monotone pairings of
their points within a quarter of the curve, of the largest distance of a
pair: pace-free, and the
distance where two curves differ most, so a detour over 12 % of the motion
counts in full): the minimum spanning tree under that distance, cut top
down at its largest edge, is the single-linkage hierarchy of candidate
routes.

**The criterion** (:func:`split_routes`). A cut of the hierarchy into parts
``A`` and ``B`` is judged *where they differ most*: at the point ``i`` where
the two parts' mean curves are farthest apart (each curve averaged over
:data:`_PHASE_WINDOW` points around it, so phase jitter moves little), on
the line through the two means there. The cut stands when the gap between
the parts on that line is at least :data:`MIN_GAP` (of the route columns'
normalized range) and at least :data:`GAP_RATIO` times the spread (standard
deviation on that line) of every route found inside either part, and of
the mean distance from a curve to its nearest other there (a route of one
or two curves says nothing of its spread; with three curves or fewer there
is no such floor, so two against one splits). Cuts are judged bottom up:
a part's own routes are found first. A cut whose every route is a single
curve stands only for two curves in all (one demonstration followed rather
than a mean of two). So two routes of tight demonstrations split however
few they are, three routes side by side split in two steps, a detour over
a small share of the motion splits, and a continuous variation (an
amplitude spread, speeds, time shifts) does not: on the line where its
halves differ most, its largest gap is no larger than its spread.
``n_routes`` overrides the criterion: the cut of the hierarchy that takes
most from the spread is made until there are that many routes.

Demonstrations that are not templates (more than ``max_templates``), and
templates past :data:`MAX_JUDGED`, take the route of the nearest route
medoid (on their segment-state curves, or their own; :func:`route_labels`).

**Where it can fail** (docs/routes.md gives the measurements): routes that
differ by less than :data:`MIN_GAP` of the range, or only in orientation,
velocity or a gripper (name those with ``route_groups``), are one route;
routes whose own spread is wide (more than a fifth of the gap between them)
are merged; a demonstration far from the others of its route (at least
:data:`GAP_RATIO` times their spread and :data:`MIN_GAP`) is a route of its
own; a random continuous spread of few demonstrations is now and then split
where a gap happens to open (measured on noiseless bumps: 6 to 10 % of draws
of 5 curves, under 3 % from 10, under 1 % from 12); two routes that visit
the same places in the same order at different times are one route.

The route followed is the most probable one: the one with the largest total
weight of demonstrations (:func:`choose_route`). Without a start or goal that
is the route most demonstrations take; a requested start or goal weights the
demonstrations first (:mod:`~ndlfd.learner._conditioning`), so the route
followed is the one that starts (ends) there.
"""

from __future__ import annotations

import numpy as np

from .._errors import ValidationError
from .._pose_groups import kind
from .._validation import check_positive_int, check_work_size
from ._curves import frechet_matrix, route_curves

__all__ = [
    "CURVES_KEY",
    "GAP_RATIO",
    "MAX_JUDGED",
    "MIN_GAP",
    "choose_route",
    "demo_routes",
    "model_routes",
    "route_columns",
    "route_labels",
    "route_medoids",
    "route_probabilities",
    "segment_paths",
    "split_routes",
]

#: Smallest gap between two routes, in normalized units of the route columns
#: (their group's range is 1).
MIN_GAP = 0.05

#: A gap must be this many times the spread of every route on either side.
GAP_RATIO = 5.0

#: Points of a route curve averaged where routes are compared: a phase
#: jitter of up to a few points moves that mean little.
_PHASE_WINDOW = 7

#: Templates whose pairwise distances decide the routes (the first ones);
#: the others are assigned (:func:`route_labels`). The cost is quadratic.
MAX_JUDGED = 300

#: Up to this many curves, a route's spread has no floor (:func:`split_routes`).
_FEW = 3

#: Where a fitted model's cache keeps its templates' route curves, their
#: columns and the distances of the first :data:`MAX_JUDGED` (set by
#: :func:`model_routes`, read by :mod:`ndlfd.learner._prefix_route`).
CURVES_KEY = "route curves"

#: Groups that are not where a route is (unless named, or nothing else).
_NOT_ROUTE = ("velocity", "orientation", "force", "gripper")


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


def route_columns(column_groups, route_groups=None) -> np.ndarray:
    """The columns routes are judged on.

    Parameters
    ----------
    column_groups : sequence of str
        The group of each learned column.
    route_groups : sequence of str, optional
        The groups to judge on; by default every hand's position
        (``position``, ``left_position``, ...) if learned, else every group
        but velocity, orientation, force and gripper, else all.

    Returns
    -------
    columns : ndarray of int64

    Examples
    --------
    >>> route_columns(("position", "position", "velocity", "velocity"))
    array([0, 1])
    >>> route_columns(("joints", "joints", "gripper"))
    array([0, 1])
    >>> route_columns(("velocity",))
    array([0])
    >>> route_columns(("left_position",) * 3 + ("left_orientation",) * 4)
    array([0, 1, 2])
    >>> route_columns(("position", "gripper"), route_groups=["gripper"])
    array([1])
    """
    groups = np.asarray(column_groups, dtype=object)
    if route_groups is not None:
        return np.flatnonzero(np.isin(groups, list(route_groups)))
    kinds = np.array([kind(g) for g in column_groups], dtype=object)
    for chosen in (kinds == "position", ~np.isin(kinds, _NOT_ROUTE)):
        if chosen.any():
            return np.flatnonzero(chosen)
    return np.arange(groups.size, dtype=np.int64)


def _mst(D: np.ndarray) -> np.ndarray:
    """Edges ``(i, j, length)`` of a minimum spanning tree (Prim; ties: lowest)."""
    n = D.shape[0]
    inside = np.zeros(n, dtype=bool)
    inside[0] = True
    best = D[0].copy()
    parent = np.zeros(n, dtype=np.int64)
    edges = []
    for _ in range(n - 1):
        j = int(np.argmin(np.where(inside, np.inf, best)))
        edges.append((int(parent[j]), j, float(best[j])))
        inside[j] = True
        closer = ~inside & (D[j] < best)
        best[closer] = D[j][closer]
        parent[closer] = j
    return np.array(edges, dtype=[("i", "i8"), ("j", "i8"), ("d", "f8")])


def _sides(members: np.ndarray, pairs: list, a: int) -> tuple[np.ndarray, np.ndarray]:
    """``members`` split: the tree part (edges ``pairs``) holding ``a``, the rest."""
    near: dict[int, list[int]] = {int(m): [] for m in members}
    for i, j in pairs:
        near[i].append(j)
        near[j].append(i)
    seen = {a}
    todo = [a]
    while todo:
        for j in near[todo.pop()]:
            if j not in seen:
                seen.add(j)
                todo.append(j)
    inside = np.isin(members, np.fromiter(seen, dtype=np.int64))
    return members[inside], members[~inside]


def _smoothed(curves: np.ndarray) -> np.ndarray:
    """Each curve's mean over :data:`_PHASE_WINDOW` points around each point."""
    from scipy.ndimage import uniform_filter1d

    return uniform_filter1d(curves, _PHASE_WINDOW, axis=1, mode="nearest")


def _hierarchy(D: np.ndarray) -> list:
    """The single-linkage hierarchy, top down: nodes ``(members, gap, a, b)``.

    A node's children ``a`` and ``b`` (node numbers, ``-1`` for a leaf) are
    its members split by the largest tree edge among them (ties: the first
    in the tree's order), ``gap`` that edge's length; children come after
    their parent.
    """
    edges = _mst(D)
    nodes: list = [(np.arange(D.shape[0]), 0.0, -1, -1)]
    todo = [(0, np.arange(edges.size))]
    while todo:
        k, inner = todo.pop()
        if inner.size == 0:
            continue
        cut = inner[int(np.argmax(edges["d"][inner]))]
        rest = inner[inner != cut]
        pairs = [(int(edges["i"][e]), int(edges["j"][e])) for e in rest]
        A, B = _sides(nodes[k][0], pairs, int(edges["i"][cut]))
        kids = []
        for part in (A, B):
            nodes.append((part, 0.0, -1, -1))
            kids.append(len(nodes) - 1)
            todo.append((kids[-1], rest[np.isin(edges["i"][rest], part)]))
        nodes[k] = (nodes[k][0], float(edges["d"][cut]), kids[0], kids[1])
    return nodes


def split_routes(
    curves: np.ndarray,
    n_routes: int | None = None,
    *,
    min_gap: float = MIN_GAP,
    ratio: float = GAP_RATIO,
    distances: np.ndarray | None = None,
) -> np.ndarray:
    """Routes of curves (the criterion in the module's text).

    Parameters
    ----------
    curves : ndarray of shape (n, n_points, n_dims)
        :func:`route_curves`.
    n_routes : int, optional
        Exactly this many routes (at most ``n``) instead of the criterion.
    min_gap : float, default=:data:`MIN_GAP`
    ratio : float, default=:data:`GAP_RATIO`
    distances : ndarray of shape (n, n), optional
        :func:`frechet_matrix` of the curves, if already computed.

    Returns
    -------
    labels : ndarray of shape (n,), dtype int64
        Routes numbered by their first member.

    Examples
    --------
    Bumps of heights 0.3, 0.31 and -0.3 (two against one), and of heights
    spread evenly from -0.3 to 0.3 (one route):

    >>> tau = np.linspace(0.0, 1.0, 32)
    >>> def bumps(h):
    ...     return np.stack([np.column_stack([tau, a * np.sin(np.pi * tau)])
    ...                      for a in h])
    >>> split_routes(bumps([0.3, 0.31, -0.3]))
    array([0, 0, 1])
    >>> split_routes(bumps(np.linspace(-0.3, 0.3, 7)))
    array([0, 0, 0, 0, 0, 0, 0])

    Asked for a number of routes, the cut that takes most from the spread
    (the squared gap of the parts' means, times ``|A| |B| / (|A| + |B|)``, on
    the line where they differ most) is made first:

    >>> split_routes(bumps([0.0, 0.01, 0.02, 0.2, 0.21]), n_routes=2)
    array([0, 0, 0, 1, 1])
    """
    curves = np.asarray(curves, dtype=np.float64)
    n = curves.shape[0]
    if n < 2:
        return np.zeros(n, dtype=np.int64)
    D = frechet_matrix(curves) if distances is None else distances
    nodes = _hierarchy(D)
    V = _smoothed(curves)

    eye = np.eye(n, dtype=bool)

    def at_divergence(k: int):
        """A node's parts along the direction where they differ most.

        At the aligned point where the parts' means are farthest apart, each
        curve's value projected on the line through the two means (the
        first part's side positive); the gap between the parts there, and
        the floor of a route's spread there: the mean distance from a curve
        to its nearest other (none with three curves or fewer: two apart by
        MIN_GAP are then two routes, one demonstration followed rather than
        a mean of two).
        """
        _, _, a, b = nodes[k]
        A, B = nodes[a][0], nodes[b][0]
        diff = V[A].mean(axis=0) - V[B].mean(axis=0)
        big = float(np.abs(diff).max())  # scaled first: 1e300 squares to inf
        unit = diff / big if big > 0 else diff
        i = int(np.argmax(np.sum(unit * unit, axis=1)))
        norm = big * float(np.sqrt(np.sum(unit[i] * unit[i])))
        if norm == 0.0:
            return np.zeros(n), -np.inf, 0.0
        x = V[:, i] @ (diff[i] / norm)
        floor = 0.0
        if n > _FEW:
            pair = np.where(eye, np.inf, np.abs(x[:, None] - x[None, :]))
            floor = float(pair.min(axis=1).mean())
        return x, float(x[A].min() - x[B].max()), floor

    if n_routes is None:
        routes: dict[int, list[int]] = {}
        for k in reversed(range(len(nodes))):  # children before their parent
            _, _, a, b = nodes[k]
            parts = [k]
            if a >= 0:
                split = routes.pop(a) + routes.pop(b)
                x, gap, floor = at_divergence(k)
                widest = max(float(np.std(x[nodes[p][0]])) for p in split)
                lone = all(nodes[p][0].size == 1 for p in split) and n > 2
                if not lone and gap >= min_gap and gap >= ratio * max(widest, floor):
                    parts = split
            routes[k] = parts
        final = routes[0]
    else:

        def score(k: int) -> float:
            # what the cut takes from the spread: |A||B|/|X| (mean gap)**2
            x, _, _ = at_divergence(k)
            A, B = nodes[nodes[k][2]][0], nodes[nodes[k][3]][0]
            step = float(x[A].mean() - x[B].mean())
            return A.size * B.size / (A.size + B.size) * step * step

        final = [0]
        while len(final) < n_routes:
            best = max((k for k in final if nodes[k][2] >= 0), key=score)
            final.remove(best)
            final += [nodes[best][2], nodes[best][3]]
    labels = np.empty(n, dtype=np.int64)
    for r, k in enumerate(sorted(final, key=lambda k: int(nodes[k][0].min()))):
        labels[nodes[k][0]] = r
    return labels


def route_medoids(D: np.ndarray, labels: np.ndarray) -> np.ndarray:
    """Each route's medoid (its curve nearest the others in RMS), by route number.

    Examples
    --------
    >>> D = np.array([[0.0, 1.0, 2.0], [1.0, 0.0, 1.0], [2.0, 1.0, 0.0]])
    >>> route_medoids(D, np.array([0, 0, 0]))
    array([1])
    """
    out = np.empty(int(labels.max()) + 1, dtype=np.int64)
    for r in range(out.size):
        members = np.flatnonzero(labels == r)
        sub = D[np.ix_(members, members)]
        out[r] = members[int(np.argmin(np.sum(sub * sub, axis=1)))]
    return out


def route_labels(
    curves: np.ndarray,
    template_index: np.ndarray,
    n_demos: int,
    segment_curves=None,
    n_routes: int | None = None,
    distances: np.ndarray | None = None,
) -> np.ndarray:
    """Which route each demonstration takes.

    Parameters
    ----------
    curves : ndarray of shape (n_templates, n_points, n_columns)
        The templates' route curves (:func:`~ndlfd.learner._curves.route_curves`
        on the route columns, :func:`route_columns`).
    template_index : ndarray of shape (n_templates,), dtype int64
        Their demonstrations (at least one).
    n_demos : int
        Training demonstrations.
    segment_curves : callable, optional
        ``segment_curves(rows) -> ndarray of shape (len(rows), n_bins,
        n_columns)``: the segment-state curves of demonstrations (needed
        when some are not templates).
    n_routes : int, optional
        See :func:`split_routes`.
    distances : ndarray of shape (n_judged, n_judged), optional
        :func:`~ndlfd.learner._curves.frechet_matrix` of the first
        ``min(n_templates, MAX_JUDGED)`` curves, if already computed.

    Returns
    -------
    labels : ndarray of shape (n_demos,), dtype int64

    Examples
    --------
    >>> tau = np.linspace(0.0, 1.0, 50)
    >>> bump = np.sin(np.pi * tau)
    >>> V = [np.column_stack([tau, s * bump]) for s in (0.3, 0.31, -0.3)]
    >>> route_labels(route_curves(V, [tau] * 3, np.array([0, 1])), np.arange(3), 3)
    array([0, 0, 1])
    """
    template_index = np.asarray(template_index, dtype=np.int64)
    judged = min(len(curves), MAX_JUDGED)
    D = frechet_matrix(curves[:judged]) if distances is None else distances
    found = split_routes(curves[:judged], n_routes, distances=D)
    if found.max() == 0:  # one route: every demonstration on it
        return np.zeros(n_demos, dtype=np.int64)
    labels = np.full(n_demos, -1, dtype=np.int64)
    labels[template_index[:judged]] = found
    medoids = route_medoids(D, found)
    if judged < len(curves):  # the other templates: on their own curves
        near = np.argmin(frechet_matrix(curves[judged:], curves[medoids]), axis=1)
        labels[template_index[judged:]] = near  # route r's medoid is column r
    others = np.flatnonzero(labels < 0)
    if others.size:
        ref = segment_curves(template_index[medoids])
        for lo in range(0, others.size, 4096):
            rows = others[lo : lo + 4096]
            near = np.argmin(frechet_matrix(segment_curves(rows), ref), axis=1)
            labels[rows] = near
    return labels


def demo_routes(
    values, taus, column_groups, route_groups=None, n_routes: int | None = None
) -> np.ndarray:
    """Routes of demonstrations given as normalized values (no model needed).

    What ``ndlfd plot`` colours demonstrations by: :func:`route_labels` with
    every demonstration a template.

    Parameters
    ----------
    values : list of ndarray of shape (n_j, n_columns)
        Normalized values (a :class:`~ndlfd.GroupScaler`'s, unweighted).
    taus : list of ndarray of shape (n_j,)
        Normalized times.
    column_groups : sequence of str
    route_groups : sequence of str, optional
    n_routes : int, optional

    Returns
    -------
    routes : ndarray of shape (n_demos,), dtype int64

    Examples
    --------
    >>> tau = np.linspace(0.0, 1.0, 50)
    >>> V = [np.column_stack([tau, s * np.sin(np.pi * tau)]) for s in (.3, .31, -.3)]
    >>> demo_routes(V, [tau] * 3, ("position", "position"))
    array([0, 0, 1])
    """
    n = len(values)
    groups = f"the groups {sorted(set(column_groups))}"
    cols = _checked_columns(column_groups, route_groups, n_routes, n, groups)
    curves = route_curves(values, taus, cols)
    return route_labels(curves, np.arange(n), n, n_routes=n_routes)


def _checked_columns(column_groups, route_groups, n_routes, n_templates, groups):
    """The route columns, after checking ``route_groups`` and ``n_routes``.

    ``groups`` says which groups there are, for the error.
    """
    cols = route_columns(column_groups, route_groups)
    if cols.size == 0:
        raise ValidationError(
            f"route_groups names none of {groups}; got {list(route_groups)!r}"
        )
    if n_routes is not None:
        check_positive_int(n_routes, "n_routes")
        judged = min(n_templates, MAX_JUDGED)
        if n_routes > judged:
            raise ValidationError(
                f"n_routes={n_routes} is more than the {judged} demonstrations"
                " the routes are judged on"
            )
    return cols


def model_routes(est, cache: dict | None = None) -> np.ndarray:
    """Each training demonstration's route, from a fitted model's statistics.

    Parameters
    ----------
    est : KeypointHMM
        With its statistics set (the fit's last step); its ``n_routes`` and
        ``route_groups`` say how (:func:`route_labels`).
    cache : dict, optional
        The model's cache: the templates' route curves, their columns and
        distances are kept there under :data:`CURVES_KEY`.

    Returns
    -------
    routes : ndarray of shape (n_demos,), dtype int64
        All 0 for a model without training values (a format-1 file).

    Raises
    ------
    ValidationError
        ``route_groups`` names no learned group, or ``n_routes`` is more than
        the templates judged.
    """
    n = int(est.n_demos_)
    if not hasattr(est, "train_values_") or not len(est.train_values_):
        return np.zeros(n, dtype=np.int64)
    n_routes = getattr(est, "n_routes", None)
    cols = _checked_columns(est.column_groups_, getattr(est, "route_groups", None),
                            n_routes, len(est.train_values_),
                            f"the learned groups {est.groups_}")  # fmt: skip

    paths: list = []  # computed only when some demonstration is no template

    def segment_curves(rows):
        if not paths:
            nt = est.n_time_bins
            paths.append(segment_paths(est.fit_stats_, est.centroid_states_, nt))
        return est.centroids_[paths[0][rows]][:, :, cols]

    # the curves and their distances, kept for replanning
    # (ndlfd.learner._prefix_route), which matches prefixes against them
    curves = route_curves(est.train_values_, est.train_tau_, cols)
    D = frechet_matrix(curves[:MAX_JUDGED])
    if cache is not None:
        cache[CURVES_KEY] = (curves, cols, D)
    return route_labels(curves, est.template_indices_, n, segment_curves,
                        n_routes, distances=D)  # fmt: skip


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
