"""Decoding the supervised discrete HMM: exact sparse Viterbi and the posterior.

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
import scipy.sparse as sp

from ._errors import DecodeError, ValidationError
from ._hmm_kernels import viterbi_sparse
from ._hmm_model import _STARTS, DiscreteHMM, _safe_ratio
from ._validation import check_int_sequence

__all__ = ["Posterior", "posterior", "viterbi"]


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


def _checked(model, symbols, start) -> tuple[str, np.ndarray]:
    """The start mode and the symbols of a decoding call, checked."""
    if not isinstance(model, DiscreteHMM):
        raise ValidationError(
            f"model must be a fitted DiscreteHMM; got {type(model).__name__}"
        )
    model._check_fitted()
    mode = _STARTS.get(start)
    obs = check_int_sequence(symbols, "symbols", low=0, high=model._nt)
    if obs.size == 0:
        raise ValidationError("symbols must hold at least one symbol; got length 0")
    return mode, obs


def _tables(model, start: str):
    """Probability-space pieces of the model over the seen states.

    Each probability is the same ratio the log tables use, ``(count + p) /
    (total + width * p)``, split into the row's baseline ``p / (total + width
    * p)`` and the counted part ``count / (total + width * p)``.
    """
    raw = model._raw
    m, nt, p, r = model._m, model._nt, model._p, model._r
    seen = raw["states"]
    n_seen = seen.shape[0]
    n_unseen = float(m - n_seen)
    den = model.transition_totals_ + m * p
    base = _safe_ratio(np.full(n_seen, p), den)
    t_indptr = raw["transition_indptr"]
    rows = np.repeat(np.arange(n_seen), np.diff(t_indptr))
    delta = sp.csr_array(
        (_safe_ratio(raw["transition_counts"], den[rows]),
         raw["transition_targets"], t_indptr),
        shape=(n_seen, n_seen),
    )  # fmt: skip
    unseen_row = 1.0 / m if p > 0 else 0.0  # A[u, j] of an unseen row u
    if start == "learned":
        d = model.n_sequences_ + m * p
        pi = (model.start_counts_ + p) / d
        pi_unseen = n_unseen * p / d
    elif n_seen and seen[0] == 0:  # "state1": row 0 of A
        pi = base[0] + delta[0:1].toarray()[0]
        pi_unseen = n_unseen * base[0]
    else:  # "state1" from an unseen state 0: a uniform row
        pi = np.full(n_seen, unseen_row)
        pi_unseen = n_unseen * unseen_row
    eden = model.emission_totals_ + nt * r
    erows = np.repeat(np.arange(n_seen), np.diff(raw["emission_indptr"]))
    emis = sp.csr_array(
        (_safe_ratio(raw["emission_counts"], eden[erows]),
         raw["emission_symbols"], raw["emission_indptr"]),
        shape=(n_seen, nt),
    ).tocsc()  # fmt: skip
    emis_base = _safe_ratio(np.full(n_seen, r), eden)
    emis_unseen = 1.0 / nt if r > 0 else 0.0
    return (
        base,
        delta,
        unseen_row,
        n_unseen,
        pi,
        pi_unseen,
        (emis, emis_base, emis_unseen),
    )


def _emissions(em, symbol: int) -> tuple[np.ndarray, float]:
    """``B[j, symbol]`` for the seen states and for one unseen state."""
    emis, emis_base, emis_unseen = em
    e = emis_base.copy()
    lo, hi = emis.indptr[symbol], emis.indptr[symbol + 1]
    e[emis.indices[lo:hi]] += emis.data[lo:hi]
    return e, emis_unseen


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
    mode, obs = _checked(model, symbols, start)
    base, delta, unseen_row, n_unseen, pi, pi_u, em = _tables(model, mode)
    delta_t = delta.T.tocsr()
    n_steps, n_seen = obs.size, pi.size
    alpha = np.empty((n_steps, n_seen))
    alpha_u = np.empty(n_steps)  # total over the unseen class
    scale = np.empty(n_steps)
    emis = [_emissions(em, int(o)) for o in obs]
    a, au = pi, pi_u
    for t in range(n_steps):
        if t:
            prev, prev_u = alpha[t - 1], alpha_u[t - 1]
            flow = float(base @ prev) + prev_u * unseen_row
            a = flow + delta_t @ prev
            au = n_unseen * flow
        e, eu = emis[t]
        a = a * e
        au = au * eu
        c = float(a.sum() + au)
        if not c > 0:
            raise DecodeError(
                f"the symbols have probability zero: no state can emit symbol"
                f" {int(obs[t])} at step {t} after the steps before it"
                f" (start={mode!r})"
            )
        alpha[t], alpha_u[t], scale[t] = a / c, au / c, c
    beta = np.ones(n_seen)
    beta_u = 1.0 if n_unseen else 0.0  # per unseen state
    gamma = np.empty_like(alpha)
    gamma_u = np.empty(n_steps)
    gamma[-1], gamma_u[-1] = alpha[-1], alpha_u[-1]
    for t in range(n_steps - 2, -1, -1):
        e, eu = emis[t + 1]
        f = e * beta
        fu = eu * beta_u
        total = float(f.sum()) + n_unseen * fu
        beta = (base * total + delta @ f) / scale[t + 1]
        beta_u = unseen_row * total / scale[t + 1]
        gamma[t] = alpha[t] * beta
        gamma_u[t] = alpha_u[t] * beta_u
    return Posterior(model.states_.copy(), gamma, gamma_u, float(np.log(scale).sum()))


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
    ``n_steps * (n_seen + 1)`` of them; the symbol index takes
    ``n_symbols + 1`` integers. Nothing of size ``n_states`` is allocated.

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
    mode, obs = _checked(model, symbols, start)
    tb = model._kernel_tables()
    s_base, s_idx, s_logp = tb["start"][mode]
    path, logp, fail = viterbi_sparse(
        obs,
        tb["gid"],
        tb["has_unseen"],
        tb["in_indptr"],
        tb["in_src"],
        tb["in_logp"],
        tb["row_base"],
        tb["unseen_trans"],
        tb["em_indptr"],
        tb["em_state"],
        tb["em_logp"],
        tb["em_base"],
        tb["unseen_emit"],
        tb["emit_all"],
        s_base,
        s_idx,
        s_logp,
    )
    if fail >= 0:
        o = int(obs[fail])
        never = not tb["emit_all"] and tb["em_indptr"][o + 1] == tb["em_indptr"][o]
        why = (
            "it was never emitted in training and pseudo_emission is 0"
            if never
            else "no state that emits it is reachable from the states before it"
        )
        raise DecodeError(
            f"cannot decode symbol {o} at step {fail}: {why} (start={mode!r})"
        )
    return tb["gid"][path], float(logp)
