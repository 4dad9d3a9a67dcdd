"""Joint-space peers of the task evaluation (:mod:`ndlfd.jobs._tasks`).

:class:`ContextualProMP` is the contextual probabilistic movement primitive of
Paraschos et al. (2013, "Probabilistic Movement Primitives", NeurIPS): each
demonstration's weights on a normalized Gaussian basis in time, a joint
Gaussian of (weights, context), and generation as the weights' conditional
mean given a new context, mapped back through the basis. movement_primitives'
``ProMP`` has no context; its basis (centres evenly on [0, 1], width from an
overlap of 0.7) is the one used here.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ContextualProMP", "rbf_basis"]


def rbf_basis(n_steps: int, n_weights: int, overlap: float = 0.7) -> np.ndarray:
    """Normalized Gaussian radial basis functions on normalized time.

    Centres evenly on [0, 1], variance ``-1 / (8 n_weights^2 ln overlap)``
    (movement_primitives' ``ProMP``), each step's activations summing to 1.

    Returns
    -------
    phi : ndarray of shape (n_steps, n_weights)
    """
    t = np.linspace(0.0, 1.0, n_steps)[:, None]
    centers = np.linspace(0.0, 1.0, n_weights)[None, :]
    h = -1.0 / (8.0 * n_weights**2 * np.log(overlap))
    a = np.exp(-((t - centers) ** 2) / (2.0 * h))
    return a / a.sum(axis=1, keepdims=True)


class ContextualProMP:
    """A ProMP whose weights are conditioned on a context vector.

    Parameters
    ----------
    n_weights_per_dim : int, default=25
        Basis functions per trajectory dimension.
    ridge : float, default=1e-8
        Each demonstration's weights are ridge least squares with this
        penalty relative to the mean diagonal of the basis' Gram matrix.
    context_ridge : float, default=1e-6
        Added to the context covariance's diagonal, relative to its mean
        diagonal (its trace over its size): keeps few demonstrations with
        more context values than they span well posed (the directions they
        do not span then get no gain; the others are all but unchanged).

    Attributes
    ----------
    mean_weights_ : ndarray of shape (n_weights_per_dim, n_dims)
    gain_ : ndarray of shape (n_varying, n_weights_per_dim * n_dims)
        ``S_ss^-1 S_sw`` (regularized): the weights' move per unit of context.
    varying_ : ndarray of bool, shape (n_context,)
        The context coordinates that vary across the demonstrations (the
        others are dropped: they carry no information).
    mean_context_ : ndarray of shape (n_varying,)
    """

    def __init__(
        self,
        n_weights_per_dim: int = 25,
        ridge: float = 1e-8,
        context_ridge: float = 1e-6,
    ):
        self.n_weights_per_dim = n_weights_per_dim
        self.ridge = ridge
        self.context_ridge = context_ridge

    def fit(self, trajectories, contexts) -> ContextualProMP:
        """Learn the joint Gaussian of weights and context.

        Parameters
        ----------
        trajectories : array-like of shape (n_demos, n_steps, n_dims)
            The demonstrations on one normalized-time grid.
        contexts : array-like of shape (n_demos, n_context)

        Returns
        -------
        self : ContextualProMP
        """
        Y = np.asarray(trajectories, dtype=float)
        S = np.asarray(contexts, dtype=float).reshape(len(Y), -1)
        k, n, d = Y.shape
        nw = int(self.n_weights_per_dim)
        phi = rbf_basis(n, nw)
        gram = phi.T @ phi
        gram[np.diag_indices(nw)] += self.ridge * np.trace(gram) / nw
        # every demonstration's (nw, d) weights in one solve, then flattened
        W = np.linalg.solve(gram, phi.T @ Y).reshape(k, nw * d)
        scale = np.abs(S).max(axis=0) + 1.0
        self.varying_ = np.ptp(S, axis=0) > 1e-12 * scale
        Sv = S[:, self.varying_]
        self.mean_weights_ = W.mean(axis=0).reshape(nw, d)
        self.mean_context_ = Sv.mean(axis=0)
        if Sv.shape[1] == 0:
            self.gain_ = np.zeros((0, nw * d))
            return self
        ds, dw = Sv - self.mean_context_, W - W.mean(axis=0)
        s_ss = ds.T @ ds / max(k - 1, 1)
        s_sw = ds.T @ dw / max(k - 1, 1)
        c = s_ss.shape[0]
        s_ss[np.diag_indices(c)] += self.context_ridge * np.trace(s_ss) / c
        self.gain_ = np.linalg.solve(s_ss, s_sw)
        return self

    def generate(self, context, n_steps: int) -> np.ndarray:
        """The conditional mean trajectory given ``context``.

        ``mu_w + S_ws S_ss^-1 (s - mu_s)`` over the varying coordinates,
        through the basis on ``n_steps`` evenly spaced normalized times.

        Returns
        -------
        trajectory : ndarray of shape (n_steps, n_dims)
        """
        s = np.ravel(np.asarray(context, dtype=float))[self.varying_]
        w = self.mean_weights_ + ((s - self.mean_context_) @ self.gain_).reshape(
            self.mean_weights_.shape
        )
        return rbf_basis(n_steps, self.n_weights_per_dim) @ w
