"""The learner's HMMs: the key-point HMM and the segment model, counted in batches.

**Segment model.** While a training demonstration runs from one key point to
the next it stays in the *segment* that starts at the first of them: its state
at time bin ``b`` is the state of its last key point at or before ``b``
(:func:`segment_states`). Every bin is then an observation of the segment the
demonstration is in, so decoding all bins ``0..N_t-1`` gives the key points
*and their times* jointly: a key point is where the decoded state changes (see
:mod:`ndlfd.learner._blend`).
"""

from __future__ import annotations

import numpy as np

from .. import hmm
from ._fit_kernels import segment_rows

__all__ = ["estimate", "learned_from_stats", "segment_model", "segment_states"]

#: Sequences per ``hmm.estimate`` call when counting many demonstrations.
_ESTIMATE_BATCH = 4096


def segment_states(key_bins: np.ndarray, key_states: np.ndarray, n_bins: int):
    """State of the segment a demonstration is in at each time bin.

    Parameters
    ----------
    key_bins : ndarray of shape (n_keys,), dtype int64
        Time bin of each key point (non-decreasing, the first is 0).
    key_states : ndarray of shape (n_keys,), dtype int64
        Codebook state of each key point.
    n_bins : int
        Number of time bins.

    Returns
    -------
    states : ndarray of shape (n_bins,), dtype int64
        ``states[b]`` is the state of the last key point whose bin is ``<= b``.

    Examples
    --------
    >>> segment_states(np.array([0, 2, 2, 4]), np.array([7, 8, 9, 5]), 5)
    array([7, 7, 9, 9, 5])
    """
    n = len(key_bins)
    return segment_rows(key_bins, key_states, [0], [n], n_bins)[0]


def estimate(
    states, symbols, n_states: int, n_symbols: int, *, pseudo_transition,
    pseudo_emission,
) -> hmm.DiscreteHMM:  # fmt: skip
    """:func:`ndlfd.hmm.estimate` on batches of sequences, merged (the same counts).

    Batches keep the temporary memory of counting 100,000 demonstrations
    small; :func:`ndlfd.hmm.merge` adds the counts exactly.

    Parameters
    ----------
    states, symbols : list of ndarray of shape (n_j,), or ndarray of shape (n, k)
        One state and one symbol sequence per demonstration (a 2-D array: one
        per row), int64.
    n_states, n_symbols : int
    pseudo_transition, pseudo_emission : float or None
        As in :func:`ndlfd.hmm.estimate`.

    Returns
    -------
    model : ndlfd.hmm.DiscreteHMM
    """
    models = [
        hmm.estimate(
            states[at : at + _ESTIMATE_BATCH],
            symbols[at : at + _ESTIMATE_BATCH],
            n_states,
            n_symbols,
            pseudo_transition=pseudo_transition,
            pseudo_emission=pseudo_emission,
        )
        for at in range(0, len(states), _ESTIMATE_BATCH)
    ]
    return models[0] if len(models) == 1 else hmm.merge(models)


def segment_model(
    stats, demos, n_states: int, n_bins: int, *, pseudo_transition, pseudo_emission
) -> hmm.DiscreteHMM:
    """The segment model of some demonstrations: every bin a symbol of its segment.

    Parameters
    ----------
    stats : FitStats
        The fit statistics (their key states and bins).
    demos : ndarray of int
        Positions (in ``stats``) of the demonstrations to count.
    n_states, n_bins : int
        Codebook states and time bins.
    pseudo_transition, pseudo_emission : float or None
        As in :func:`ndlfd.hmm.estimate`.

    Returns
    -------
    model : ndlfd.hmm.DiscreteHMM
    """
    ends = np.cumsum(stats.n_keys)
    starts = ends - stats.n_keys
    demos = np.asarray(demos, dtype=np.int64)
    rows = segment_rows(
        stats.key_bins, stats.key_states, starts[demos], ends[demos], n_bins
    )  # segment_states of every demonstration, in one pass
    return estimate(
        rows,
        np.broadcast_to(np.arange(n_bins), rows.shape),  # every bin, every row
        n_states,
        n_bins,
        pseudo_transition=pseudo_transition,
        pseudo_emission=pseudo_emission,
    )


def learned_from_stats(
    stats, n_states: int, n_bins: int, *, pseudo_transition, pseudo_emission
) -> dict:
    """Every attribute a KeypointHMM learns from its fit statistics (fit and load).

    Parameters
    ----------
    stats : FitStats
    n_states, n_bins : int
        The codebook's possible cells (``prod(levels)``, of any size: the
        pseudo-count's ``m``) and time bins. The HMM's states are the
        statistics' interned cells, ids ``0..n_seen-1``.
    pseudo_transition, pseudo_emission : float or None
        As in :func:`ndlfd.hmm.estimate`.

    Returns
    -------
    attributes : dict of str to object
        ``model_`` (the key-point HMM), ``segment_model_``, the key points,
        the seen time bins, the conditioning points, the templates and the
        centroids, and ``fit_stats_`` itself (see :class:`ndlfd.KeypointHMM`).
    """
    keypoints, key_states, key_bins = stats.keypoint_lists()
    hmm_kw = dict(pseudo_transition=pseudo_transition, pseudo_emission=pseudo_emission)
    model = estimate(key_states, key_bins, n_states, n_bins, **hmm_kw)
    seen = np.zeros(n_bins, dtype=bool)
    seen[stats.key_bins] = True
    train_values, train_tau = stats.templates()
    centroid_states, centroids = stats.centroids()
    return {
        "model_": model,
        "keypoints_": keypoints,
        "n_keypoints_": stats.n_keys,
        "n_states_used_": int(model.states_.size),
        "n_clipped_": int(stats.n_clipped),
        "n_demos_": stats.n_demos,
        "symbols_seen_": seen,
        # the blended generation (see ndlfd.learner._generation)
        "first_values_": stats.first,
        "last_values_": stats.last,
        "template_indices_": stats.template_index,
        "train_values_": train_values,
        "train_tau_": train_tau,
        "centroid_states_": centroid_states,
        "centroid_cells_": stats.centroid_cells,
        "centroids_": centroids,
        "segment_model_": segment_model(
            stats, np.arange(stats.n_demos), n_states, n_bins, **hmm_kw
        ),
        "fit_stats_": stats,
    }
