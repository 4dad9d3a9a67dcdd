"""Forward–backward on the sparse supervised HMM: posterior state probabilities.

The model's transition matrix is a per-row constant (the pseudo-count
baseline) plus a sparse correction on the counted transitions, so one step of
the forward or backward recursion is a rank-one term plus a sparse
matrix–vector product over the states seen in training: ``O(n_seen +
counted transitions)`` per step, never ``O(m)`` or ``O(m²)``. All unseen
states behave alike (same rows, same emissions) and are carried as one class
holding their total probability.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from ._errors import DecodeError, ValidationError
from ._validation import check_int_sequence

__all__ = ["Posterior", "posterior"]


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


def _tables(model, start: str):
    """Probability-space pieces of the model over the seen states.

    Each probability is the same ratio the log tables use, ``(count + p) /
    (total + width * p)``, split into the row's baseline ``p / (total + width
    * p)`` and the counted part ``count / (total + width * p)``.
    """
    from .hmm import _safe_ratio

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
    from .hmm import _STARTS, DiscreteHMM

    if not isinstance(model, DiscreteHMM):
        raise ValidationError(
            f"model must be a fitted DiscreteHMM; got {type(model).__name__}"
        )
    model._check_fitted()
    mode = _STARTS.get(start)
    obs = check_int_sequence(symbols, "symbols", low=0, high=model._nt)
    if obs.size == 0:
        raise ValidationError("symbols must hold at least one symbol; got length 0")
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
