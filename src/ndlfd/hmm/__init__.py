"""Supervised discrete HMM from sparse counts, and exact structured Viterbi.

The model follows MATLAB's ``hmmestimate`` / ``hmmviterbi`` (paper §2.4.2–2.4.3).
From state sequences and their symbol sequences (one pair per demonstration) it
counts transitions between consecutive states *within* each sequence (``C``),
emissions state → symbol at every step (``E``) and first states (``F``), then

* ``A[i, j] = (C[i, j] + p) / (n_i + m p)`` with ``n_i = sum_j C[i, j]``,
* ``B[i, k] = (E[i, k] + r) / (e_i + N_t r)`` with ``e_i = sum_k E[i, k]``,
* ``pi[j] = (F[j] + p) / (D + m p)`` over the ``D`` demonstrations,

where ``m`` is the number of states, ``N_t`` the number of symbols, ``p`` the
transition pseudo-count (``1/m`` by default) and ``r`` the emission pseudo-count
(0 by default). A row whose denominator is 0 (no counts, no pseudo-count) is all
zero, never NaN.

**Memory and time follow the distinct states seen in training, not m.** The model
keeps the counts over the sorted seen states ``states_`` and never allocates
anything of size ``m``, ``m x m`` or ``m x N_t`` unless a dense matrix is asked
for (and then only below :data:`DENSE_LIMIT_BYTES`). ``A`` is the sparse count
part plus a per-row constant: ``A[i, j] = K[i, j] + b_i`` with
``K[i, j] = C[i, j] / (n_i + m p)`` and ``b_i = p / (n_i + m p)``.

Viterbi is exact under this structure: the best predecessor of ``j`` is the better
of (a) the states with a counted transition into ``j`` and (b) the best state
overall under the row baseline alone, so a step costs ``O(states that can emit +
counted transitions)``. The states never seen in training form one class with
identical scores, represented by its lowest id.

The package, in the order data flows: ``_counts`` (the counts as plain arrays:
counting labelled sequences, merging counts, the ratio of one counted table),
``_kernels`` (the compiled Viterbi and backward sampling), ``_decode``
(Viterbi, the posterior and sampling (FFBS) over plain arrays, never the model
class; the start modes :data:`STARTS`),
``_format`` (the file format, one reader per version) and ``_model``
(:class:`DiscreteHMM` and the public functions, which pass a model's arrays to
the decoders). A new decoder is a function over the counts or log tables in
``_decode``; a new file version a reader in ``_format``.
"""

from ._decode import STARTS, Posterior
from ._format import FORMAT_KIND, FORMAT_VERSION
from ._model import (
    DENSE_LIMIT_BYTES,
    DiscreteHMM,
    estimate,
    merge,
    posterior,
    sample_paths,
    viterbi,
)

__all__ = [
    "DENSE_LIMIT_BYTES",
    "FORMAT_KIND",
    "FORMAT_VERSION",
    "STARTS",
    "DiscreteHMM",
    "Posterior",
    "estimate",
    "merge",
    "posterior",
    "sample_paths",
    "viterbi",
]
