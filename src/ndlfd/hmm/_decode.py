"""Decoding the supervised discrete HMM: exact sparse Viterbi and the posterior.

The decoders work on plain arrays, never on the model class: the counts of
:class:`~ndlfd.hmm._counts.Counts` (the posterior) or the log tables that
:func:`log_tables` builds from them once (Viterbi, in the compiled kernel of
:mod:`ndlfd.hmm._kernels`). ``ndlfd.hmm.viterbi(model, ...)`` and
``ndlfd.hmm.posterior(model, ...)`` pass a fitted model's arrays in.

Both use the model's structure: the transition matrix is a per-row constant
(the pseudo-count baseline) plus a sparse correction on the counted
transitions. Viterbi's best predecessor of ``j`` is the better of the states
with a counted transition into ``j`` and the best state under the baseline
alone; one forward or backward step of the posterior is a rank-one term plus a
sparse matrix-vector product. A step costs ``O(n_seen + counted transitions)``,
never ``O(m)`` or ``O(m^2)``. All unseen states behave alike and are carried as
one class.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._errors import DecodeError, ValidationError
from .._registry import Registry
from .._validation import check_int_sequence, check_work_size
from ._counts import Counts, Table
from ._kernels import sample_backward, viterbi_sparse

__all__ = [
    "STARTS",
    "FilterTables",
    "Filtered",
    "LogTables",
    "Posterior",
    "check_symbols",
    "ffbs",
    "filter_tables",
    "forward_backward",
    "forward_filter",
    "log_tables",
    "viterbi_path",
]

#: Start distributions of the decoders. ``"learned"``: the learned ``pi``;
#: ``"state1"``: MATLAB's convention, the chain is in state 0 before the first
#: emission (row 0 of ``A``).
STARTS: Registry[str] = Registry("start")
STARTS.add("learned", "learned")
STARTS.add("state1", "state1")

_NEG_INF = -np.inf
#: The smallest scale of a forward step (the smallest normal float64 over
#: 2**20, so the backward step's division by it stays finite).
_TINY = float(np.finfo(np.float64).tiny) * 2.0**20


class Posterior(NamedTuple):
    """Posterior state probabilities of a symbol sequence.

    Attributes
    ----------
    states : ndarray of shape (n_seen,), dtype int64
        The states seen in training (columns of ``probabilities``).
    probabilities : ndarray of shape (n_steps, n_seen)
        ``P(state at step t = states[k] | all symbols)``.
    unseen : ndarray of shape (n_steps,)
        Total posterior probability of all states never seen in training
        (zero unless ``pseudo_emission > 0``).
    log_likelihood : float
        ``log P(symbols)`` under the model.
    """

    states: np.ndarray
    probabilities: np.ndarray
    unseen: np.ndarray
    log_likelihood: float


def check_symbols(symbols, n_symbols: int, start) -> tuple[str, np.ndarray]:
    """The start mode and the symbols of a decoding call, checked.

    Parameters
    ----------
    symbols : array-like of shape (n_steps,)
        Symbols in ``0..n_symbols-1``, at least one.
    n_symbols : int
    start : str
        A name in :data:`STARTS`.

    Returns
    -------
    mode : str
    obs : ndarray of shape (n_steps,), int64
    """
    mode = STARTS.get(start)
    obs = check_int_sequence(symbols, "symbols", low=0, high=n_symbols)
    if obs.size == 0:
        raise ValidationError("symbols must hold at least one symbol; got length 0")
    return mode, obs


# --------------------------------------------------------------------------- Viterbi


def _log(x) -> np.ndarray:
    """Natural log with ``log(0) = -inf`` and no warning."""
    with np.errstate(divide="ignore"):
        return np.log(np.asarray(x, dtype=np.float64))


def _log_table(table: Table, n_cols: int):
    """Log-probabilities of one counted table (CSR over the seen states).

    Each counted entry ``(i, c)`` gets the log of the ratio
    ``log((count + pseudo) / (totals[i] + width * pseudo))`` (one float formula
    for bit-exact ties); each row the baseline ``log(pseudo / (totals[i] +
    width * pseudo))`` of its uncounted entries (``-inf`` when ``pseudo == 0``);
    an unseen row ``log(1 / width)``.

    Returns
    -------
    logp : ndarray, per entry in CSR order
    row_base : ndarray of shape (n_rows,)
    unseen : float
    col_indptr, col_rows, col_logp : ndarray
        The same entries grouped by column (CSC), rows ascending in a column.
    """
    totals = table.totals.astype(np.float64)
    pseudo, cols = table.pseudo, table.columns
    rows = table.rows()
    wp = table.width * pseudo
    logp = _log((table.counts + pseudo) / (totals[rows] + wp))
    if pseudo > 0:
        row_base = _log(pseudo / (totals + wp))
        unseen = float(_log(np.array([pseudo / wp]))[0])
    else:
        row_base = np.full(totals.shape[0], _NEG_INF)
        unseen = _NEG_INF
    order = np.lexsort((rows, cols))
    col_indptr = np.zeros(n_cols + 1, dtype=np.int64)
    np.cumsum(np.bincount(cols, minlength=n_cols), out=col_indptr[1:])
    return (
        logp,
        row_base,
        unseen,
        col_indptr,
        np.ascontiguousarray(rows[order]),
        np.ascontiguousarray(logp[order]),
    )


def _emitted_symbols(table: Table) -> tuple[np.ndarray, Table]:
    """The distinct emitted symbols, and the emission table over their ranks.

    Column ``k`` of the returned table is symbol ``symbols[k]``; column
    ``len(symbols)`` stands for every symbol never emitted (it has no counted
    entry). The width (``n_symbols``, in the denominators) is kept, and nothing
    of size ``n_symbols`` is allocated.
    """
    symbols = np.unique(table.columns)
    return symbols, table._replace(columns=np.searchsorted(symbols, table.columns))


def _symbol_ranks(symbols: np.ndarray, obs: np.ndarray) -> np.ndarray:
    """Rank of each symbol of ``obs`` among ``symbols`` (``len(symbols)``: absent)."""
    n = symbols.shape[0]
    pos = np.searchsorted(symbols, obs)
    hit = symbols[np.minimum(pos, n - 1)] == obs if n else np.zeros(obs.shape, bool)
    return np.where(hit, pos, n).astype(np.int64)


class LogTables(NamedTuple):
    """The log tables of the Viterbi kernel (:func:`~._kernels.viterbi_sparse`).

    The fields from ``gid`` to ``emit_all`` are the kernel's arguments of the
    same names; ``starts`` maps each start mode to ``(start_base, start_idx,
    start_logp)``. The emission columns are the ranks of the emitted symbols
    ``em_symbols`` (:func:`_emitted_symbols`), so the tables never grow with
    ``n_symbols``.
    """

    n_symbols: int
    gid: np.ndarray
    has_unseen: bool
    in_indptr: np.ndarray
    in_src: np.ndarray
    in_logp: np.ndarray
    row_base: np.ndarray
    unseen_trans: float
    em_indptr: np.ndarray
    em_state: np.ndarray
    em_logp: np.ndarray
    em_base: np.ndarray
    unseen_emit: float
    emit_all: bool
    starts: dict
    em_symbols: np.ndarray


def log_tables(counts: Counts) -> LogTables:
    """Log-probability tables of a model for :func:`viterbi_path`.

    Parameters
    ----------
    counts : Counts
        The model's arrays.

    Returns
    -------
    LogTables
        Arrays of size ``O(n_seen + counted entries)``, nothing of size
        ``n_states``.
    """
    m, nt = counts.n_states, counts.n_symbols
    p, r = counts.pseudo_transition, counts.pseudo_emission
    seen = counts.states
    n_seen = seen.shape[0]
    trans = counts.transitions()
    la, row_base, unseen_trans, in_indptr, in_src, in_logp = _log_table(trans, n_seen)
    em_symbols, em_table = _emitted_symbols(counts.emissions())
    _, em_base, unseen_emit, em_indptr, em_state, em_logp = _log_table(
        em_table, em_symbols.shape[0] + 1
    )
    lowest_unseen = counts.lowest_unseen_state()
    has_unseen = lowest_unseen is not None
    gid = np.empty(n_seen + 1, dtype=np.int64)
    gid[:n_seen] = seen
    gid[n_seen] = lowest_unseen if has_unseen else m

    # start="learned": pi[j] = (F[j] + p) / (D + m p)
    mp = m * p
    f = counts.start_counts
    d = float(counts.n_sequences)
    s_idx = np.flatnonzero(f).astype(np.int64)
    s_logp = _log((f[s_idx] + p) / (d + mp))
    s_base = float(_log(np.array([p / (d + mp)]))[0]) if p > 0 else _NEG_INF
    # start="state1": row 0 of A
    if n_seen and seen[0] == 0:
        lo, hi = trans.indptr[0], trans.indptr[1]
        s1 = (float(row_base[0]), trans.columns[lo:hi].copy(), la[lo:hi].copy())
    else:
        s1 = (unseen_trans, np.empty(0, np.int64), np.empty(0, np.float64))
    return LogTables(
        nt, gid, has_unseen, in_indptr, in_src, in_logp, row_base, unseen_trans,
        em_indptr, em_state, em_logp, em_base, unseen_emit, r > 0,
        {"learned": (s_base, s_idx, s_logp), "state1": s1}, em_symbols,
    )  # fmt: skip


def viterbi_path(
    tables: LogTables, symbols, start: str = "learned"
) -> tuple[np.ndarray, float]:
    """Most likely state path of a symbol sequence, from the log tables.

    Log space, exact. Ties go to the lowest state index, both for predecessors
    and for the final state.

    Parameters
    ----------
    tables : LogTables
        :func:`log_tables` of the model's counts.
    symbols : array-like of shape (n_steps,)
        Symbols in ``0..n_symbols-1`` (at least one).
    start : {"learned", "state1"}, default="learned"
        The start distribution (:data:`STARTS`).

    Returns
    -------
    path : ndarray of shape (n_steps,), dtype int64
        State ids; an unseen state appears as the lowest unseen id.
    log_probability : float

    Raises
    ------
    DecodeError
        If at some step no reachable state can emit the symbol.

    Examples
    --------
    >>> from ndlfd.hmm._counts import count
    >>> counts = count([[0, 1, 2]], [[0, 1, 1]], 3, 2, 0.0, 0.0)
    >>> viterbi_path(log_tables(counts), [0, 1, 1])
    (array([0, 1, 2]), 0.0)
    """
    mode, obs = check_symbols(symbols, tables.n_symbols, start)
    tb = tables
    n_seen = tb.gid.shape[0] - 1
    ranks = _symbol_ranks(tb.em_symbols, obs)  # the kernel's emission columns
    if tb.emit_all:  # every state is a candidate at every step
        n_cand = obs.shape[0] * (n_seen + int(tb.has_unseen))
    else:  # the states that emitted the step's symbol in training
        n_cand = int(np.diff(tb.em_indptr)[ranks].sum())
    check_work_size(
        4 * n_cand,
        f"Viterbi back-pointers for {obs.shape[0]:,} steps over {n_seen:,} seen states",
        "Decode fewer steps at once, or use pseudo_emission=0.",
    )
    s_base, s_idx, s_logp = tb.starts[mode]
    path, logp, fail = viterbi_sparse(
        ranks, tb.gid, tb.has_unseen, tb.in_indptr, tb.in_src, tb.in_logp,
        tb.row_base, tb.unseen_trans, tb.em_indptr, tb.em_state, tb.em_logp,
        tb.em_base, tb.unseen_emit, tb.emit_all, s_base, s_idx, s_logp,
    )  # fmt: skip
    if fail >= 0:
        o = int(obs[fail])
        k = ranks[fail]
        never = not tb.emit_all and tb.em_indptr[k + 1] == tb.em_indptr[k]
        why = (
            "it was never emitted in training and pseudo_emission is 0"
            if never
            else "no state that emits it is reachable from the states before it"
        )
        raise DecodeError(
            f"cannot decode symbol {o} at step {fail}: {why} (start={mode!r})"
        )
    return tb.gid[path], float(logp)


# ------------------------------------------------------------------------- posterior


def _probability_tables(counts: Counts, start: str):
    """Probability-space pieces of the model over the seen states.

    Each probability is the same ratio the log tables use, ``(count + p) /
    (total + width * p)``, split into the row's baseline ``p / (total + width
    * p)`` and the counted part ``count / (total + width * p)``.
    """
    m, nt, p, r = counts[:4]
    seen = counts.states
    n_seen = seen.shape[0]
    n_unseen = float(m - n_seen)
    trans = counts.transitions()
    base = trans.baseline()
    delta = trans.csr(n_seen, trans.counted(trans.rows()))
    unseen_row = 1.0 / m if p > 0 else 0.0  # A[u, j] of an unseen row u
    if start == "learned":
        d = counts.n_sequences + m * p
        pi = (counts.start_counts + p) / d
        pi_unseen = n_unseen * p / d
    elif n_seen and seen[0] == 0:  # "state1": row 0 of A
        pi = base[0] + delta[0:1].toarray()[0]
        pi_unseen = n_unseen * base[0]
    else:  # "state1" from an unseen state 0: a uniform row
        pi = np.full(n_seen, unseen_row)
        pi_unseen = n_unseen * unseen_row
    em_symbols, em = _emitted_symbols(counts.emissions())
    emis = em.csr(em_symbols.shape[0] + 1, em.counted(em.rows())).tocsc()
    emis_unseen = 1.0 / nt if r > 0 else 0.0
    return (
        base,
        delta,
        unseen_row,
        n_unseen,
        pi,
        pi_unseen,
        (emis, em.baseline(), emis_unseen, em_symbols),
    )


def _emissions(em, rank: int) -> tuple[np.ndarray, float]:
    """``B[j, o]`` for the seen states and for one unseen state.

    ``rank`` is the symbol's rank among the emitted symbols
    (:func:`_symbol_ranks`).
    """
    emis, emis_base, emis_unseen, _ = em
    e = emis_base.copy()
    lo, hi = emis.indptr[rank], emis.indptr[rank + 1]
    e[emis.indices[lo:hi]] += emis.data[lo:hi]
    return e, emis_unseen


class _Forward(NamedTuple):
    """The scaled forward pass and the probability pieces it used."""

    obs: np.ndarray
    alpha: np.ndarray  # (n_steps, n_seen), each row with alpha_u sums to 1
    alpha_u: np.ndarray  # (n_steps,), the unseen class
    scale: np.ndarray  # (n_steps,)
    base: np.ndarray  # (n_seen,), the transition rows' baseline
    delta: object  # csr (n_seen, n_seen), the counted part of A
    unseen_row: float  # A[u, j] of an unseen row u
    n_unseen: float
    emis: list  # per step: B[:, o_t] over the seen states, and an unseen one's
    shift: float = 0.0  # log of the factors taken out of the observations' terms


class FilterTables(NamedTuple):
    """A model's tables for repeated forward passes (:func:`filter_tables`)."""

    start: str
    pieces: tuple  # _probability_tables(counts, start)
    delta_t: object  # csr, the counted part of A transposed


def filter_tables(counts: Counts, start: str = "learned") -> FilterTables:
    """The tables :func:`forward_filter` builds from the counts, built once.

    Pass them to :func:`forward_filter` to filter many sequences of one
    model without building them again (``O(n_seen + counted entries)``).

    Examples
    --------
    >>> from ndlfd.hmm._counts import count
    >>> counts = count([[0, 1]], [[0, 1]], 2, 2, 0.0, 0.0)
    >>> tables = filter_tables(counts)
    >>> forward_filter(counts, [0, 1], tables=tables).probabilities
    array([0., 1.])
    """
    mode = STARTS.get(start)
    pieces = _probability_tables(counts, mode)
    return FilterTables(mode, pieces, pieces[1].T.tocsr())


def _forward(
    counts: Counts,
    obs: np.ndarray,
    mode: str,
    loglik: np.ndarray | None = None,
    tables: FilterTables | None = None,
) -> _Forward:
    """Scaled forward pass over the seen states and the unseen class.

    ``loglik`` (shape ``(n_steps, n_seen)``, optional) adds an observation
    term per step and seen state; the unseen class then has none (it has no
    value to compare with) and takes probability zero. ``tables``: the
    model's :func:`filter_tables` for ``mode``, built here without.
    """
    if tables is None:
        tables = filter_tables(counts, mode)
    base, delta, unseen_row, n_unseen, pi, pi_u, em = tables.pieces
    delta_t = tables.delta_t
    n_steps, n_seen = obs.size, pi.size
    check_work_size(  # alpha, and the emissions of every step
        8 * n_steps * (n_seen + 1),
        f"the forward pass of {n_steps:,} steps over {n_seen:,} seen states",
        "Pass fewer steps at once.",
    )
    alpha = np.empty((n_steps, n_seen))
    alpha_u = np.empty(n_steps)  # total over the unseen class
    scale = np.empty(n_steps)
    emis = [_emissions(em, int(k)) for k in _symbol_ranks(em[3], obs)]
    a, au = pi, pi_u
    shift = 0.0
    for t in range(n_steps):
        if t:
            prev, prev_u = alpha[t - 1], alpha_u[t - 1]
            flow = float(base @ prev) + prev_u * unseen_row
            a = flow + delta_t @ prev
            au = n_unseen * flow
        e, eu = emis[t]
        a = a * e
        au = au * eu
        if loglik is not None:  # scaled by the likeliest state that has mass
            row = loglik[t]
            top = float(row[a > 0].max(initial=-np.inf))
            top = top if np.isfinite(top) else 0.0
            with np.errstate(invalid="ignore"):  # -inf - top is -inf: exp 0
                a = a * np.exp(row - top)
            au, shift = 0.0, shift + top
        c = float(a.sum() + au)
        if not c > 0:
            raise DecodeError(
                f"the symbols have probability zero: no state can emit symbol"
                f" {int(obs[t])} at step {t} after the steps before it"
                f" (start={mode!r})"
            )
        if c < _TINY:  # dividing by a subnormal scale overflows
            raise DecodeError(
                f"the probability of symbol {int(obs[t])} at step {t} given the"
                f" steps before it is {c:.3g}, below the float64 range of the"
                " forward pass (pseudo-counts near zero); viterbi works in log"
                " space"
            )
        alpha[t], alpha_u[t], scale[t] = a / c, au / c, c
    return _Forward(
        obs, alpha, alpha_u, scale, base, delta, unseen_row, n_unseen, emis, shift
    )


def forward_backward(counts: Counts, symbols, start: str = "learned") -> Posterior:
    """Posterior state probabilities at every step, from the counts.

    Scaled forward–backward in float64; a step costs ``O(n_seen + counted
    transitions)``.

    Parameters
    ----------
    counts : Counts
        The model's arrays.
    symbols : array-like of shape (n_steps,)
        Symbols in ``0..n_symbols-1`` (at least one).
    start : {"learned", "state1"}, default="learned"
        The start distribution (:data:`STARTS`).

    Returns
    -------
    Posterior

    Raises
    ------
    DecodeError
        If the symbols have probability zero under the model (the step is
        named).

    Examples
    --------
    >>> from ndlfd.hmm._counts import count
    >>> counts = count([[0, 1], [0, 2]], [[0, 1], [0, 1]], 3, 2, 0.0, 0.0)
    >>> forward_backward(counts, [0, 1]).probabilities
    array([[1. , 0. , 0. ],
           [0. , 0.5, 0.5]])
    """
    mode, obs = check_symbols(symbols, counts.n_symbols, start)
    fw = _forward(counts, obs, mode)
    alpha, alpha_u, scale, base, delta = fw[1:6]
    unseen_row, n_unseen, emis = fw.unseen_row, fw.n_unseen, fw.emis
    n_steps, n_seen = alpha.shape
    beta = np.ones(n_seen)
    beta_u = 1.0 if n_unseen else 0.0  # per unseen state
    gamma = np.empty_like(alpha)
    gamma_u = np.empty(n_steps)
    gamma[-1], gamma_u[-1] = alpha[-1], alpha_u[-1]
    with np.errstate(over="ignore", invalid="ignore"):  # checked below
        for t in range(n_steps - 2, -1, -1):
            e, eu = emis[t + 1]
            f = e * beta
            fu = eu * beta_u
            total = float(f.sum()) + n_unseen * fu
            beta = (base * total + delta @ f) / scale[t + 1]
            beta_u = unseen_row * total / scale[t + 1]
            gamma[t] = alpha[t] * beta
            gamma_u[t] = alpha_u[t] * beta_u
    if not (np.isfinite(gamma).all() and np.isfinite(gamma_u).all()):
        raise DecodeError(
            "the posterior of these symbols leaves the float64 range in the"
            " backward pass (probabilities near 1e-308, from pseudo-counts near"
            f" zero; start={mode!r}); viterbi works in log space"
        )
    return Posterior(counts.states.copy(), gamma, gamma_u, float(np.log(scale).sum()))


# ------------------------------------------------------------------- filtering


class Filtered(NamedTuple):
    """The state at the last step given every step up to it (forward filtering).

    Attributes
    ----------
    states : ndarray of shape (n_seen,), dtype int64
        The states seen in training (the entries of ``probabilities``).
    probabilities : ndarray of shape (n_seen,)
        ``P(state at the last step = states[k] | symbols, observations)``.
    unseen : float
        Total probability of the states never seen in training (zero with
        observations, or unless ``pseudo_emission > 0``).
    log_likelihood : float
        ``log p(symbols, observations)`` under the model.
    """

    states: np.ndarray
    probabilities: np.ndarray
    unseen: float
    log_likelihood: float


def forward_filter(
    counts: Counts,
    symbols,
    start: str = "learned",
    log_likelihood=None,
    tables: FilterTables | None = None,
) -> Filtered:
    """Forward filtering: the last step's state given the symbols and observations.

    The forward pass of :func:`forward_backward`, optionally with an
    observation of each step besides its symbol: ``log_likelihood[t, k]`` is
    ``log p(observation t | state states[k])``, so every step's term is
    ``B[j, o_t] * p(observation t | j)``. A state never seen in training has
    no observation model and takes probability zero then. A step costs
    ``O(n_seen + counted transitions)``, never ``O(n_states)``.

    Parameters
    ----------
    counts : Counts
        The model's arrays.
    symbols : array-like of shape (n_steps,)
        Symbols in ``0..n_symbols-1`` (at least one).
    start : {"learned", "state1"}, default="learned"
        The start distribution (:data:`STARTS`).
    log_likelihood : array-like of shape (n_steps, n_seen), optional
        The observations' log-likelihoods per seen state (``-inf`` allowed).
    tables : FilterTables, optional
        :func:`filter_tables` of these counts and this start, to filter many
        sequences of one model (built here without).

    Returns
    -------
    Filtered

    Raises
    ------
    DecodeError
        If the symbols and observations have probability zero.
    ValidationError
        If ``log_likelihood`` has another shape or holds NaN or ``+inf``.

    Examples
    --------
    Two sequences, 0 then 1 and 0 then 2; the second step's observation is
    twice as likely in state 2:

    >>> from ndlfd.hmm._counts import count
    >>> counts = count([[0, 1], [0, 2]], [[0, 1], [0, 1]], 3, 2, 0.0, 0.0)
    >>> like = np.log([[1.0, 1.0, 1.0], [1.0, 1.0, 2.0]])
    >>> f = forward_filter(counts, [0, 1], log_likelihood=like)
    >>> np.round(f.probabilities, 4), round(f.log_likelihood, 4)
    (array([0.    , 0.3333, 0.6667]), 0.4055)
    """
    mode, obs = check_symbols(symbols, counts.n_symbols, start)
    loglik = None
    if log_likelihood is not None:
        loglik = np.asarray(log_likelihood, dtype=np.float64)
        n_seen = counts.states.shape[0]
        if loglik.shape != (obs.size, n_seen):
            raise ValidationError(
                f"log_likelihood must have shape (n_steps, n_seen) = ({obs.size},"
                f" {n_seen}); got {loglik.shape}"
            )
        if np.isnan(loglik).any() or np.isposinf(loglik).any():
            raise ValidationError(
                "log_likelihood must hold finite values or -inf; got NaN or +inf"
            )
    if tables is not None and tables.start != mode:
        raise ValidationError(
            f"tables were built for start={tables.start!r}; got start={mode!r}"
        )
    fw = _forward(counts, obs, mode, loglik, tables)
    logp = float(np.log(fw.scale).sum()) + fw.shift
    return Filtered(counts.states.copy(), fw.alpha[-1], float(fw.alpha_u[-1]), logp)


# ---------------------------------------------------------------- sampling (FFBS)


def ffbs(counts: Counts, symbols, n_samples: int, start: str, rng) -> np.ndarray:
    """State paths drawn from their exact posterior given the symbols (FFBS).

    Forward filtering (the forward pass of :func:`forward_backward`), then
    backward sampling: the last state from the filtered distribution, each
    earlier state ``i`` given the next ``j`` with probability proportional to
    ``alpha_t(i) A[i, j]``. That weight is the row baseline ``alpha_t(i) b_i``
    (the same for every ``j``, and the unseen class's ``alpha_t(u) / m``) plus
    the counted part ``alpha_t(i) K[i, j]`` over the counted transitions into
    ``j``, so a step costs ``O(n_seen)`` once and ``O(log n_seen + counted
    transitions into j)`` per sample (:func:`~._kernels.sample_backward`),
    never ``O(m)``.

    Parameters
    ----------
    counts : Counts
        The model's arrays.
    symbols : array-like of shape (n_steps,)
        Symbols in ``0..n_symbols-1`` (at least one).
    n_samples : int
        Number of paths (at least 0).
    start : {"learned", "state1"}
        The start distribution (:data:`STARTS`).
    rng : numpy.random.Generator
        The source of the uniforms (``n_samples * n_steps`` of them, drawn at
        once).

    Returns
    -------
    paths : ndarray of shape (n_samples, n_steps), dtype int64
        State ids; a state never seen in training appears as the lowest
        unseen id (as in :func:`viterbi_path`).

    Raises
    ------
    DecodeError
        If the symbols have probability zero under the model.

    Examples
    --------
    >>> from ndlfd.hmm._counts import count
    >>> counts = count([[0, 1], [0, 2]], [[0, 1], [0, 1]], 3, 2, 0.0, 0.0)
    >>> paths = ffbs(counts, [0, 1], 1000, "learned", np.random.default_rng(0))
    >>> paths.shape, bool(np.all(paths[:, 0] == 0))
    ((1000, 2), True)
    >>> bool(400 < np.sum(paths[:, 1] == 1) < 600)
    True
    """
    mode, obs = check_symbols(symbols, counts.n_symbols, start)
    check_work_size(
        8 * int(n_samples) * obs.shape[0],
        f"{int(n_samples):,} sampled paths of {obs.shape[0]:,} steps",
        "Draw fewer samples per call.",
    )
    fw = _forward(counts, obs, mode)
    n_steps, n_seen = fw.alpha.shape
    # per step the baseline weights of every predecessor, the unseen class last
    W = np.empty((n_steps, n_seen + 1))
    W[:, :n_seen] = fw.alpha * fw.base
    W[:, n_seen] = fw.alpha_u * fw.unseen_row
    np.cumsum(W, axis=1, out=W)
    # the last step: the filtered distribution itself
    last = np.cumsum(np.r_[fw.alpha[-1], fw.alpha_u[-1]])
    col = fw.delta.tocsc()
    col.sort_indices()
    u = rng.random((int(n_samples), n_steps))
    idx = sample_backward(
        fw.alpha, W, last, col.indptr.astype(np.int64),
        col.indices.astype(np.int64), col.data.astype(np.float64), u,
    )  # fmt: skip
    gid = np.empty(n_seen + 1, dtype=np.int64)
    gid[:n_seen] = counts.states
    lowest = counts.lowest_unseen_state()
    gid[n_seen] = counts.n_states if lowest is None else lowest
    return gid[idx]
