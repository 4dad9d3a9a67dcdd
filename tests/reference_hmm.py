"""Slow, obviously-correct dense HMM: counting, matrices, Viterbi, brute force.

Everything is written with plain loops and full ``m x m`` arrays, for tiny models
only. The probabilities use the same ratio formula as ndlfd
(``(count + pseudo) / (total + size * pseudo)``, 0 where the denominator is 0) and
the logarithms come from ``np.log`` on those ratios, so log-probabilities can be
compared for exact equality.
"""

from __future__ import annotations

import itertools

import numpy as np


def dense_counts(states, symbols, m, nt):
    """Return C (m, m), E (m, nt), F (m,), D from lists of sequences."""
    C = np.zeros((m, m))
    E = np.zeros((m, nt))
    F = np.zeros(m)
    for s, o in zip(states, symbols, strict=True):
        F[s[0]] += 1
        for k in range(len(s)):
            E[s[k], o[k]] += 1
            if k + 1 < len(s):
                C[s[k], s[k + 1]] += 1
    return C, E, F, len(states)


def _ratio(num, den):
    out = np.zeros(np.broadcast_shapes(np.shape(num), np.shape(den)))
    num = np.broadcast_to(num, out.shape)
    den = np.broadcast_to(den, out.shape)
    for idx in np.ndindex(out.shape):
        if den[idx] != 0:
            out[idx] = num[idx] / den[idx]
    return out


def dense_model(states, symbols, m, nt, p=None, r=0.0):
    """Dense A, B, pi with the hmmestimate formulas."""
    if p is None:
        p = 1.0 / m
    C, E, F, D = dense_counts(states, symbols, m, nt)
    n = C.sum(axis=1)
    e = E.sum(axis=1)
    A = _ratio(C + p, (n + m * p)[:, None])
    B = _ratio(E + r, (e + nt * r)[:, None])
    pi = _ratio(F + p, np.full(m, D + m * p))
    return A, B, pi


def log(x):
    with np.errstate(divide="ignore"):
        return np.log(np.asarray(x, dtype=np.float64))


def dense_viterbi(logA, logB, logpi, obs):
    """Textbook log-space Viterbi; np.argmax gives the lowest index on ties.

    Returns (path, log_probability), or (None, -inf) if no path has positive
    probability.
    """
    m = logA.shape[0]
    T = len(obs)
    delta = logpi + logB[:, obs[0]]
    back = np.zeros((T, m), dtype=np.int64)
    for t in range(1, T):
        scores = delta[:, None] + logA  # scores[i, j]
        back[t] = np.argmax(scores, axis=0)
        delta = scores[back[t], np.arange(m)] + logB[:, obs[t]]
    last = int(np.argmax(delta))
    if delta[last] == -np.inf:
        return None, -np.inf
    path = [last]
    for t in range(T - 1, 0, -1):
        path.append(int(back[t, path[-1]]))
    return np.array(path[::-1], dtype=np.int64), float(delta[last])


def reference_viterbi(states, symbols, m, nt, obs, *, p=None, r=0.0, start="learned"):
    """Dense reference for ndlfd.hmm.viterbi on a model estimated from counts."""
    A, B, pi = dense_model(states, symbols, m, nt, p, r)
    logA, logB = log(A), log(B)
    logpi = log(pi) if start == "learned" else logA[0]
    return dense_viterbi(logA, logB, logpi, np.asarray(obs))


def brute_force_best(logA, logB, logpi, obs):
    """Best log-probability over all m**T paths (no tie rule)."""
    m = logA.shape[0]
    best = -np.inf
    for path in itertools.product(range(m), repeat=len(obs)):
        s = logpi[path[0]] + logB[path[0], obs[0]]
        for t in range(1, len(obs)):
            s += logA[path[t - 1], path[t]] + logB[path[t], obs[t]]
        best = max(best, s)
    return best
