"""The supervised discrete HMM as a class, and the public functions over it.

:class:`DiscreteHMM` keeps its counts as plain arrays
(:class:`~ndlfd.hmm._counts.Counts`) and answers with probabilities; the
counting is :mod:`ndlfd.hmm._counts`, the decoders :mod:`ndlfd.hmm._decode`
(which never see the class: :func:`viterbi` and :func:`posterior` pass the
model's arrays in), the file format :mod:`ndlfd.hmm._format`.
"""

from __future__ import annotations

import os

import numpy as np
import scipy.sparse as sp

from .._errors import NotFittedError, ValidationError
from .._validation import check_int_sequence, check_positive_int, check_random_state
from ._counts import Counts, Table, count, merge_counts
from ._decode import (
    LogTables,
    Posterior,
    ffbs,
    forward_backward,
    log_tables,
    viterbi_path,
)
from ._format import counts_from_arrays, counts_to_arrays, load_counts, save_counts

__all__ = [
    "DENSE_LIMIT_BYTES",
    "DiscreteHMM",
    "estimate",
    "merge",
    "posterior",
    "sample_paths",
    "viterbi",
]

#: Largest dense matrix (in bytes) that ``dense=True`` accessors build: 256 MiB.
DENSE_LIMIT_BYTES = 256 * 2**20


def _check_dense_size(n_entries: int, what: str) -> None:
    nbytes = n_entries * 8
    if nbytes > DENSE_LIMIT_BYTES:
        raise ValidationError(
            f"a dense {what} would need {nbytes / 2**20:.1f} MiB, above the"
            f" {DENSE_LIMIT_BYTES / 2**20:.0f} MiB limit; use dense=False (sparse"
            " counts plus a per-row baseline)"
        )


def _table_matrix(counts: Counts, table: Table, columns, dense: bool, name: str):
    """One table over all states: its count part (COO) or, dense, the matrix.

    ``columns`` are the entries' column ids in the full matrix (global state
    ids for transitions, symbols for emissions).
    """
    m, seen = counts.n_states, counts.states
    if m > np.iinfo(np.int64).max:
        raise ValidationError(
            f"the {name} matrix over all {m:.3g} states cannot be indexed (scipy and"
            f" numpy index with int64); the model's counts are over its"
            f" {seen.shape[0]} seen states (states_), which is what the decoders"
            " use"
        )
    shape = (m, table.width)
    src = table.rows()
    rows = seen[src]
    if not dense:
        return sp.coo_array((table.counted(src), (rows, columns)), shape=shape)
    _check_dense_size(m * table.width, f"{name} matrix ({m} x {table.width})")
    M = np.empty(shape)
    M[:] = table.unseen_baseline()
    M[seen, :] = table.baseline()[:, None]
    M[rows, columns] = table.counted(src, smoothed=True)
    return M


# ----------------------------------------------------------------------------- model


class DiscreteHMM:
    """A supervised discrete HMM stored as sparse counts over the seen states.

    Use :func:`estimate` (or ``DiscreteHMM(...).fit(states, symbols)``) to build
    one and :func:`viterbi` (or :meth:`decode`) to decode symbols.

    Parameters
    ----------
    n_states : int
        Number of states ``m`` (may be huge, up to the int64 range).
    n_symbols : int
        Number of symbols ``N_t``.
    pseudo_transition : float or None, default=None
        Transition pseudo-count ``p``; ``None`` means ``1 / n_states``.
    pseudo_emission : float, default=0.0
        Emission pseudo-count ``r``.

    Attributes
    ----------
    states_ : ndarray of shape (n_seen,), dtype int64
        Sorted distinct states seen in training. Rows and columns of the count
        matrices below follow this order.
    transition_counts_ : scipy.sparse.csr_array of shape (n_seen, n_seen)
        ``C`` restricted to the seen states.
    emission_counts_ : scipy.sparse.csr_array of shape (n_seen, n_symbols)
        ``E`` restricted to the seen states.
    start_counts_ : ndarray of shape (n_seen,), dtype int64
        ``F``: how many demonstrations start in each seen state.
    transition_totals_ : ndarray of shape (n_seen,), dtype int64
        ``n_i``, transitions out of each seen state.
    emission_totals_ : ndarray of shape (n_seen,), dtype int64
        ``e_i``, occurrences of each seen state.
    n_sequences_ : int
        ``D``, the number of training sequences.
    pseudo_transition_ : float
        The transition pseudo-count in use (``1 / n_states`` when the parameter is
        ``None``).
    lowest_unseen_state_ : int or None
        Lowest state id never seen in training (``None`` if all were seen); it
        represents every unseen state in decoded paths.

    Examples
    --------
    >>> hmm = DiscreteHMM(4, 2, pseudo_transition=0).fit([[0, 1, 2], [0, 2]],
    ...                                                 [[0, 0, 1], [0, 1]])
    >>> hmm.states_
    array([0, 1, 2])
    >>> hmm.transition_matrix(dense=True)[0]
    array([0. , 0.5, 0.5, 0. ])
    >>> path, logp = hmm.decode([0, 1])
    >>> path, round(float(np.exp(logp)), 3)
    (array([0, 2]), 0.5)
    """

    def __init__(
        self,
        n_states: int,
        n_symbols: int,
        *,
        pseudo_transition: float | None = None,
        pseudo_emission: float = 0.0,
    ) -> None:
        self.n_states = n_states
        self.n_symbols = n_symbols
        self.pseudo_transition = pseudo_transition
        self.pseudo_emission = pseudo_emission

    def __repr__(self) -> str:
        return (
            f"DiscreteHMM(n_states={self.n_states}, n_symbols={self.n_symbols},"
            f" pseudo_transition={self.pseudo_transition!r},"
            f" pseudo_emission={self.pseudo_emission!r})"
        )

    # -- fitting -------------------------------------------------------------------

    def fit(self, states, symbols) -> DiscreteHMM:
        """Count transitions, emissions and first states of training sequences.

        Parameters
        ----------
        states : array-like of shape (n_steps,) or list of them
            State sequences, one per demonstration, each in ``0..n_states-1``.
            A single 1-D array is one demonstration; a 2-D array is one
            demonstration per row. Empty sequences are refused.
        symbols : array-like of shape (n_steps,) or list of them
            Symbol sequences of the same structure and lengths, in
            ``0..n_symbols-1``.

        Returns
        -------
        self : DiscreteHMM

        Examples
        --------
        >>> hmm = DiscreteHMM(3, 1).fit([0, 1, 1], [0, 0, 0])
        >>> hmm.transition_totals_, hmm.emission_totals_
        (array([1, 1]), array([1, 2]))
        """
        params = self.n_states, self.n_symbols
        pseudo = self.pseudo_transition, self.pseudo_emission
        return self._set_counts(count(states, symbols, *params, *pseudo))

    def _set_counts(self, counts: Counts) -> DiscreteHMM:
        self._counts, self._tables = counts, None
        trans, emis = counts.transitions(), counts.emissions()
        self.states_ = counts.states
        self.n_sequences_ = int(counts.n_sequences)
        self.pseudo_transition_ = float(counts.pseudo_transition)
        self.transition_totals_, self.emission_totals_ = trans.totals, emis.totals
        self.start_counts_ = counts.start_counts
        self.transition_counts_ = trans.csr(counts.states.shape[0])
        self.emission_counts_ = emis.csr(counts.n_symbols)
        self.lowest_unseen_state_ = counts.lowest_unseen_state()
        return self

    @classmethod
    def _from_counts(cls, counts: Counts, pseudo_transition) -> DiscreteHMM:
        kw = {
            "pseudo_transition": pseudo_transition,
            "pseudo_emission": counts.pseudo_emission,
        }
        return cls(counts.n_states, counts.n_symbols, **kw)._set_counts(counts)

    def _check_fitted(self) -> None:
        if not hasattr(self, "_counts"):
            raise NotFittedError(
                "this DiscreteHMM is not fitted yet; call fit(states, symbols) or"
                " ndlfd.hmm.estimate(...) first"
            )

    def _log_tables(self) -> LogTables:
        """The decoder's log tables, built on first use and kept."""
        if self._tables is None:
            self._tables = log_tables(self._counts)
        return self._tables

    # -- decoding ------------------------------------------------------------------

    def decode(self, symbols, *, start: str = "learned") -> tuple[np.ndarray, float]:
        """Most likely state path for ``symbols`` (see :func:`viterbi`).

        Parameters
        ----------
        symbols : array-like of shape (n_steps,)
            Symbols in ``0..n_symbols-1``.
        start : {"learned", "state1"}, default="learned"
            Start distribution (see :func:`viterbi`).

        Returns
        -------
        path : ndarray of shape (n_steps,), dtype int64
        log_probability : float

        Examples
        --------
        >>> hmm = estimate([[0, 1]], [[0, 1]], 2, 2)
        >>> hmm.decode([0, 1])[0]
        array([0, 1])
        """
        return viterbi(self, symbols, start=start)

    # -- probabilities -------------------------------------------------------------

    def transition_baseline(self, states) -> np.ndarray:
        """Per-row constant ``b_i = p / (n_i + m p)`` of the transition matrix.

        Every entry ``A[i, j]`` without a counted transition equals ``b_i``
        (0 when ``p == 0``).

        Parameters
        ----------
        states : array-like of shape (n,)
            State ids ``i`` (rows of ``A``).

        Returns
        -------
        baseline : ndarray of shape (n,), dtype float64

        Examples
        --------
        >>> hmm = estimate([[0, 1]], [[0, 0]], 4, 1)   # p = 1/4
        >>> hmm.transition_baseline([0, 3])
        array([0.125, 0.25 ])
        """
        self._check_fitted()
        return self._baseline(states, self._counts.transitions())

    def emission_baseline(self, states) -> np.ndarray:
        """Per-row constant ``r / (e_i + N_t r)`` of the emission matrix.

        Parameters
        ----------
        states : array-like of shape (n,)
            State ids ``i`` (rows of ``B``).

        Returns
        -------
        baseline : ndarray of shape (n,), dtype float64

        Examples
        --------
        >>> hmm = estimate([[0, 1]], [[0, 0]], 4, 2, pseudo_emission=1.0)
        >>> hmm.emission_baseline([0, 3])
        array([0.33333333, 0.5       ])
        """
        self._check_fitted()
        return self._baseline(states, self._counts.emissions())

    def _baseline(self, states, table: Table) -> np.ndarray:
        """The row baseline of ``table`` per state (an unseen row has total 0)."""
        s = check_int_sequence(states, "states", low=0, high=self._counts.n_states)
        pos = np.minimum(np.searchsorted(self.states_, s), self.states_.shape[0] - 1)
        totals = np.where(self.states_[pos] == s, table.totals[pos], 0)
        return table._replace(totals=totals).baseline()

    def transition_matrix(self, dense: bool = False):
        """The transition matrix ``A`` (sparse count part, or dense on request).

        ``A`` is dense in truth when ``p > 0``, so the sparse form is its count
        part: ``A[i, j] = K[i, j] + b_i`` with ``K[i, j] = C[i, j] / (n_i + m p)``
        and ``b_i`` from :meth:`transition_baseline`. When ``p == 0`` the baseline
        is 0 and ``K`` *is* ``A``. The sparse form never allocates anything of
        size ``m``.

        Parameters
        ----------
        dense : bool, default=False
            Return the full ``(m, m)`` array built with
            ``(C + p) / (n_i + m p)``; refused above :data:`DENSE_LIMIT_BYTES`.

        Returns
        -------
        K : scipy.sparse.coo_array of shape (n_states, n_states)
            When ``dense`` is false (call ``.tocsr()`` for row access).
        A : ndarray of shape (n_states, n_states)
            When ``dense`` is true.

        Examples
        --------
        >>> hmm = estimate([[0, 1, 1]], [[0, 0, 0]], 2, 1, pseudo_transition=0)
        >>> hmm.transition_matrix().toarray()
        array([[0., 1.],
               [0., 1.]])
        """
        self._check_fitted()
        table = self._counts.transitions()
        columns = self.states_[table.columns]
        return _table_matrix(self._counts, table, columns, dense, "transition")

    def emission_matrix(self, dense: bool = False):
        """The emission matrix ``B`` (sparse count part, or dense on request).

        As for :meth:`transition_matrix`: ``B[i, k] = K[i, k] + c_i`` with
        ``K[i, k] = E[i, k] / (e_i + N_t r)`` and ``c_i`` from
        :meth:`emission_baseline`; with ``r == 0`` (the default) ``K`` is ``B``.

        Parameters
        ----------
        dense : bool, default=False
            Return the full ``(m, N_t)`` array built with
            ``(E + r) / (e_i + N_t r)``; refused above :data:`DENSE_LIMIT_BYTES`.

        Returns
        -------
        K : scipy.sparse.coo_array of shape (n_states, n_symbols)
            When ``dense`` is false.
        B : ndarray of shape (n_states, n_symbols)
            When ``dense`` is true.

        Examples
        --------
        >>> hmm = estimate([[0, 1, 1]], [[0, 0, 1]], 2, 2)
        >>> hmm.emission_matrix(dense=True)
        array([[1. , 0. ],
               [0.5, 0.5]])
        """
        self._check_fitted()
        table = self._counts.emissions()
        return _table_matrix(self._counts, table, table.columns, dense, "emission")

    def initial_distribution(self) -> np.ndarray:
        """The learned start distribution ``pi[j] = (F[j] + p) / (D + m p)``.

        Returns
        -------
        pi : ndarray of shape (n_states,)
            Dense; refused above :data:`DENSE_LIMIT_BYTES`.

        Examples
        --------
        Two demonstrations start in state 0 (``F = (2, 0)``, ``D = 2``) and the
        default ``p = 1/m = 1/2``: ``pi = (2.5 / 3, 0.5 / 3)``.

        >>> estimate([[0, 1], [0, 0]], [[0, 0], [0, 0]], 2, 1).initial_distribution()
        array([0.83333333, 0.16666667])
        """
        self._check_fitted()
        m, p = self._counts.n_states, self._counts.pseudo_transition
        _check_dense_size(m, f"initial distribution ({m},)")
        d = float(self.n_sequences_)
        pi = np.empty(m)
        pi[:] = p / (d + m * p)
        pi[self.states_] = (self.start_counts_ + p) / (d + m * p)
        return pi

    # -- persistence ---------------------------------------------------------------

    def to_arrays(self, prefix: str = "") -> dict[str, np.ndarray]:
        """The model as plain numeric arrays (for embedding in another file).

        Parameters
        ----------
        prefix : str, default=""
            Prepended to every key.

        Returns
        -------
        arrays : dict of str to ndarray

        Examples
        --------
        >>> hmm = estimate([[0, 1]], [[0, 1]], 2, 2)
        >>> sorted(hmm.to_arrays("hmm/"))[:2]
        ['hmm/emission_counts', 'hmm/emission_indptr']
        """
        self._check_fitted()
        default_p = self.pseudo_transition is None
        return counts_to_arrays(self._counts, default_p, prefix)

    @classmethod
    def from_arrays(cls, arrays, prefix: str = "") -> DiscreteHMM:
        """Rebuild a model from :meth:`to_arrays` output, validating everything.

        Parameters
        ----------
        arrays : mapping of str to ndarray
            May hold other keys; only those starting with ``prefix`` are read.
        prefix : str, default=""
            The prefix given to :meth:`to_arrays`.

        Returns
        -------
        model : DiscreteHMM

        Raises
        ------
        ModelFormatError
            If an array is missing or inconsistent (shape, dtype, range, counts).

        Examples
        --------
        >>> hmm = estimate([[0, 1]], [[0, 1]], 2, 2)
        >>> DiscreteHMM.from_arrays(hmm.to_arrays()).decode([0, 1])[0]
        array([0, 1])
        """
        return cls._from_counts(*counts_from_arrays(arrays, prefix))

    def save(self, path: str | os.PathLike) -> None:
        """Write the model to an ``.npz`` file (kind ``DiscreteHMM``, version 1).

        Parameters
        ----------
        path : str or path-like
            Destination; written atomically.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> f = pathlib.Path(tempfile.mkdtemp()) / "hmm.npz"
        >>> estimate([[0, 1]], [[0, 1]], 2, 2).save(f)
        >>> DiscreteHMM.load(f).states_
        array([0, 1])
        """
        self._check_fitted()
        save_counts(path, self._counts, self.pseudo_transition is None)

    @classmethod
    def load(cls, path: str | os.PathLike) -> DiscreteHMM:
        """Read a model written by :meth:`save`.

        Parameters
        ----------
        path : str or path-like
            The file.

        Returns
        -------
        model : DiscreteHMM

        Raises
        ------
        ModelFormatError
            For a foreign, truncated, tampered or other-version file.
        """
        return cls._from_counts(*load_counts(path))


# ----------------------------------------------------------------------------- API


def estimate(
    states,
    symbols,
    n_states: int,
    n_symbols: int,
    *,
    pseudo_transition: float | None = None,
    pseudo_emission: float = 0.0,
) -> DiscreteHMM:
    """Estimate a discrete HMM from labelled sequences (MATLAB ``hmmestimate``).

    Parameters
    ----------
    states : array-like of shape (n_steps,) or list of them
        State sequences (one per demonstration), ids in ``0..n_states-1``.
    symbols : array-like of shape (n_steps,) or list of them
        Symbol sequences of the same lengths, ids in ``0..n_symbols-1``.
    n_states : int
        Number of states ``m`` (may be far larger than the states seen).
    n_symbols : int
        Number of symbols ``N_t``.
    pseudo_transition : float or None, default=None
        ``p`` in ``A[i, j] = (C[i, j] + p) / (n_i + m p)``; ``None`` means
        ``1 / n_states``.
    pseudo_emission : float, default=0.0
        ``r`` in ``B[i, k] = (E[i, k] + r) / (e_i + N_t r)``.

    Returns
    -------
    model : DiscreteHMM
        Fitted; its memory follows the number of distinct states seen.

    Examples
    --------
    >>> hmm = estimate([[3, 5, 5], [3, 5]], [[0, 1, 2], [0, 2]], 10**12, 3)
    >>> hmm.states_, hmm.n_sequences_
    (array([3, 5]), 2)
    >>> hmm.decode([0, 1, 2])[0]
    array([3, 5, 5])
    """
    return DiscreteHMM(
        n_states,
        n_symbols,
        pseudo_transition=pseudo_transition,
        pseudo_emission=pseudo_emission,
    ).fit(states, symbols)


def merge(models) -> DiscreteHMM:
    """Combine HMMs estimated on separate groups of demonstrations.

    Transition, emission and first-state counts are per demonstration and add
    up, so estimating on chunks of the demonstrations (in other threads,
    processes or machines, e.g. with Dask) and merging gives exactly the model
    that :func:`estimate` gives on all of them at once.

    Parameters
    ----------
    models : sequence of DiscreteHMM
        Fitted models with the same ``n_states``, ``n_symbols`` and
        pseudo-counts.

    Returns
    -------
    model : DiscreteHMM

    Examples
    --------
    >>> a = estimate([[0, 1, 1]], [[0, 1, 2]], 4, 3)
    >>> b = estimate([[0, 2, 1]], [[0, 1, 2]], 4, 3)
    >>> both = estimate([[0, 1, 1], [0, 2, 1]], [[0, 1, 2], [0, 1, 2]], 4, 3)
    >>> merged = merge([a, b])
    >>> merged.states_, merged.n_sequences_
    (array([0, 1, 2]), 2)
    >>> (merged.transition_counts_ != both.transition_counts_).nnz
    0
    """
    if isinstance(models, DiscreteHMM):
        models = [models]
    try:
        models = list(models)
    except TypeError:
        raise ValidationError(
            "models must be a sequence of fitted DiscreteHMM; got"
            f" {type(models).__name__}"
        ) from None
    if not models:
        raise ValidationError("merge needs at least one fitted DiscreteHMM; got none")
    for k, mod in enumerate(models):
        if not isinstance(mod, DiscreteHMM):
            raise ValidationError(
                f"models[{k}] must be a DiscreteHMM; got {type(mod).__name__}"
            )
        mod._check_fitted()
    first = models[0]
    key = first._counts[:4]  # n_states, n_symbols, p, r
    for k, mod in enumerate(models[1:], start=1):
        other = mod._counts[:4]
        if other != key:
            raise ValidationError(
                "models must share n_states, n_symbols and pseudo-counts; models[0]"
                f" has {key} and models[{k}] has {other}"
            )
    out = DiscreteHMM(
        first.n_states,
        first.n_symbols,
        pseudo_transition=first.pseudo_transition,
        pseudo_emission=first.pseudo_emission,
    )
    return out._set_counts(merge_counts([mod._counts for mod in models]))


def _fitted(model) -> DiscreteHMM:
    if not isinstance(model, DiscreteHMM):
        raise ValidationError(
            f"model must be a fitted DiscreteHMM; got {type(model).__name__}"
        )
    model._check_fitted()
    return model


def posterior(model, symbols, *, start: str = "learned") -> Posterior:
    """Posterior state probabilities at every step (forward–backward).

    Exact (scaled forward–backward in float64) and sparse: a step costs
    ``O(n_seen + counted transitions)``; nothing of size ``n_states`` is
    allocated.

    Parameters
    ----------
    model : DiscreteHMM
        A fitted model.
    symbols : array-like of shape (n_steps,)
        Symbols in ``0..n_symbols-1`` (at least one).
    start : {"learned", "state1"}, default="learned"
        Start distribution, as in :func:`ndlfd.hmm.viterbi`.

    Returns
    -------
    Posterior
        ``states``, ``probabilities`` of shape ``(n_steps, n_seen)``,
        ``unseen`` of shape ``(n_steps,)`` and ``log_likelihood``.

    Raises
    ------
    DecodeError
        If the symbols have probability zero under the model (the step is
        named).

    Examples
    --------
    >>> from ndlfd import hmm
    >>> model = hmm.estimate([[0, 1], [0, 2]], [[0, 1], [0, 1]], 3, 2,
    ...                      pseudo_transition=0)
    >>> post = hmm.posterior(model, [0, 1])
    >>> post.states
    array([0, 1, 2])
    >>> post.probabilities
    array([[1. , 0. , 0. ],
           [0. , 0.5, 0.5]])
    >>> round(post.log_likelihood, 6)  # log(1 * 1 * (1/2 * 1 + 1/2 * 1))
    0.0
    """
    return forward_backward(_fitted(model)._counts, symbols, start)


def viterbi(
    model: DiscreteHMM, symbols, *, start: str = "learned"
) -> tuple[np.ndarray, float]:
    """Most likely state path of a symbol sequence (MATLAB ``hmmviterbi``).

    Log space, exact. Ties go to the lowest state index, both for predecessors and
    for the final state.

    Parameters
    ----------
    model : DiscreteHMM
        A fitted model.
    symbols : array-like of shape (n_steps,)
        Symbols in ``0..n_symbols-1`` (at least one).
    start : {"learned", "state1"}, default="learned"
        ``"learned"``: ``delta_1(j) = log pi[j] + log B[j, o_1]`` with the learned
        start distribution. ``"state1"``: MATLAB's convention, the chain is in state
        0 before the first emission, so ``delta_1(j) = log A[0, j] + log
        B[j, o_1]``.

    Returns
    -------
    path : ndarray of shape (n_steps,), dtype int64
        State ids. A state never seen in training appears as the lowest unseen id
        (all unseen states are indistinguishable).
    log_probability : float
        Log-probability of the path jointly with the symbols.

    Raises
    ------
    DecodeError
        If at some step no reachable state can emit the symbol.

    Notes
    -----
    A step costs ``O(candidates + counted transitions into them)``, where the
    candidates are the seen states that emitted the step's symbol (``r == 0``)
    or all seen states plus the unseen class (``r > 0``). Back-pointers take
    4 bytes per candidate and step, so with ``r > 0`` decoding holds
    ``n_steps * (n_seen + 1)`` of them; the emission index takes one
    integer per distinct emitted symbol. Nothing of size ``n_states`` or
    ``n_symbols`` is allocated; a call whose back-pointers would pass
    :data:`~ndlfd._validation.MAX_WORK_BYTES` is refused
    (:class:`~ndlfd.ResourceLimitError`) before decoding.

    Examples
    --------
    >>> from ndlfd.hmm import estimate
    >>> hmm = estimate([[0, 1, 2], [0, 2, 2]], [[0, 1, 2], [0, 1, 2]], 3, 3)
    >>> path, logp = viterbi(hmm, [0, 1, 2])
    >>> path
    array([0, 1, 2])
    >>> viterbi(hmm, [0, 1, 2], start="state1")[0]
    array([0, 1, 2])
    """
    return viterbi_path(_fitted(model)._log_tables(), symbols, start)


def sample_paths(
    model: DiscreteHMM,
    symbols,
    n_samples: int = 1,
    *,
    start: str = "learned",
    random_state=None,
) -> np.ndarray:
    """State paths drawn from the posterior given the symbols (FFBS).

    Exact forward-filtering backward-sampling: each path is drawn with its
    probability ``P(path | symbols)``. Sparse, as :func:`posterior`: the
    forward pass costs ``O(n_seen + counted transitions)`` per step, and a
    drawn state ``O(log n_seen + counted transitions into the next state)``;
    nothing of size ``n_states`` is allocated.

    Parameters
    ----------
    model : DiscreteHMM
        A fitted model.
    symbols : array-like of shape (n_steps,)
        Symbols in ``0..n_symbols-1`` (at least one).
    n_samples : int, default=1
        Number of paths to draw.
    start : {"learned", "state1"}, default="learned"
        Start distribution, as in :func:`viterbi`.
    random_state : None, int or numpy.random.Generator, default=None
        The same seed and input give the same paths.

    Returns
    -------
    paths : ndarray of shape (n_samples, n_steps), dtype int64
        State ids. A state never seen in training appears as the lowest unseen
        id (all unseen states are indistinguishable), as in :func:`viterbi`.

    Raises
    ------
    DecodeError
        If the symbols have probability zero under the model.

    Examples
    --------
    Two demonstrations go 0 → 1 and 0 → 2 under the same symbols: each path
    is drawn about half the time.

    >>> from ndlfd import hmm
    >>> model = hmm.estimate([[0, 1], [0, 2]], [[0, 1], [0, 1]], 3, 2,
    ...                      pseudo_transition=0)
    >>> paths = hmm.sample_paths(model, [0, 1], 4, random_state=0)
    >>> paths.shape
    (4, 2)
    >>> sorted({tuple(map(int, p)) for p in
    ...         hmm.sample_paths(model, [0, 1], 100, random_state=0)})
    [(0, 1), (0, 2)]
    """
    n = check_positive_int(n_samples, "n_samples")
    rng = check_random_state(random_state)
    return ffbs(_fitted(model)._counts, symbols, n, start, rng)
