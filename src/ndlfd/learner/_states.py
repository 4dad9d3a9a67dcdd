"""The learner's states: the codebook cells its key points visit, interned.

A fit's states are the distinct cells of its key points
(:func:`ndlfd.codebook.intern_cells`): ids ``0..n_states_used-1`` in the
cells' lexicographic order, each id's cell kept (``centroid_cells_``). That
order is the paper's mixed-radix order, so the ids are the mixed-radix
numbers' ranks and every result that follows the states' order (Viterbi's
ties, the lowest unseen state) is the one the numbers gave, while any number
of columns fits. Here: the checks of a cell table, the reading of statistics
written with mixed-radix numbers (model files of versions 3 and 4), and the
centroid rows and codebook centres of decoded ids.
"""

from __future__ import annotations

import numpy as np

from .._errors import ModelFormatError
from ..codebook import Codebook, intern_cells, lowest_unseen_cell

__all__ = ["cell_problems", "cells_of_numbers", "centroid_rows", "state_centres"]


def cell_problems(cells: np.ndarray) -> list[str]:
    """What is wrong with a table of interned cells (an empty list: nothing).

    Parameters
    ----------
    cells : ndarray of shape (n_states, n_dims), int64

    Returns
    -------
    problems : list of str

    Examples
    --------
    >>> cell_problems(np.array([[0, 1], [1, 0]]))
    []
    >>> cell_problems(np.array([[1, 0], [0, 1]]))
    ['centroid cells not in lexicographic order']
    """
    if cells.size and (
        cells.min() < 0 or intern_cells(cells)[0].shape[0] != cells.shape[0]
    ):
        return ["centroid cells negative or repeated"]
    if cells.shape[0] > 1 and np.any(
        np.lexsort(cells.T[::-1]) != np.arange(cells.shape[0])
    ):
        return ["centroid cells not in lexicographic order"]
    return []


def cells_of_numbers(arrays, prefix: str, levels) -> dict:
    """Fit statistics with mixed-radix states (format 3, 4) with cells and ids.

    ``arrays`` as :meth:`FitStats.to_arrays` wrote them before states were
    interned: ``centroid_states`` (each state's number, strictly
    increasing) and ``key_states`` (the key points' numbers). Returns the
    arrays with ``centroid_cells`` and the key points' ids among them.

    Raises
    ------
    ModelFormatError
        Numbers out of the codebook or not strictly increasing, or a key
        point's number not among them.

    Examples
    --------
    >>> out = cells_of_numbers(
    ...     {"centroid_states": np.array([1, 5]), "key_states": np.array([5, 1, 5])},
    ...     "", [2, 3],
    ... )
    >>> out["centroid_cells"], out["key_states"]
    (array([[0, 1],
           [1, 2]]), array([1, 0, 1]))
    """
    out = dict(arrays)
    codebook = Codebook([int(v) for v in levels])
    numbers = np.asarray(arrays.get(prefix + "centroid_states", ()))
    keys = np.asarray(arrays.get(prefix + "key_states", ()))
    if (
        numbers.ndim != 1
        or keys.ndim != 1
        or numbers.dtype.kind not in "iu"
        or keys.dtype.kind not in "iu"
        or not codebook.fits_int64
        or (numbers.size and (numbers.min() < 0 or numbers.max() >= codebook.n_states))
        or np.any(np.diff(numbers) <= 0)
        or not np.all(np.isin(keys, numbers))
    ):
        raise ModelFormatError(
            "inconsistent fit statistics (tampered file?): the centroid states must"
            " be strictly increasing state numbers of the codebook, and the key"
            " points' states among them"
        )
    out[prefix + "centroid_cells"] = codebook.to_levels(numbers).reshape(
        numbers.size, codebook.n_dims
    )
    out[prefix + "key_states"] = np.searchsorted(numbers, keys).astype(np.int64)
    return out


def centroid_rows(est, states: np.ndarray) -> np.ndarray:
    """Rows of ``centroids_`` of decoded states (ids of the interned cells).

    An id past them (the decoder's lowest state never seen, possible only
    with ``pseudo_emission > 0``) takes the centroid of the first seen cell
    after the lowest unseen one (the last: none after it), as the mixed-radix
    numbering placed it.
    """
    rows = np.array(states, dtype=np.int64)
    n = est.centroid_states_.size
    unseen = rows >= n
    if unseen.any():
        cells = est.centroid_cells_
        cell = lowest_unseen_cell(cells, est.codebook_.levels).tolist()
        below = sum(1 for row in cells.tolist() if row < cell)
        rows[unseen] = min(below, n - 1)
    return rows


def state_centres(est, states: np.ndarray) -> np.ndarray:
    """The codebook centres (normalized) of decoded states (eq. 9).

    States are ids of the interned cells (``centroid_cells_``); an id past
    them is the decoder's lowest state never seen, the lowest unseen cell. A
    model read from a version-1 file numbers its states in mixed radix.
    """
    cells = getattr(est, "centroid_cells_", None)
    if cells is None:  # a version-1 file's HMM: mixed-radix state numbers
        return est.codebook_.decode(states)
    states = np.asarray(states, dtype=np.int64)
    seen = states < cells.shape[0]
    out = np.empty((states.size, cells.shape[1]), dtype=np.int64)
    out[seen] = cells[states[seen]]
    if not seen.all():
        out[~seen] = lowest_unseen_cell(cells, est.codebook_.levels)
    return est.codebook_.centres(out)
