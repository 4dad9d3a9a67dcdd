"""Decoders of the learner: a time-symbol sequence to codebook states."""

from __future__ import annotations

import numpy as np

from .. import hmm
from .._errors import DecodeError
from .._registry import Registry
from ..hmm import STARTS

__all__ = ["DECODERS", "STARTS", "decode_states"]


def _decode_viterbi(model, symbols, start):
    return hmm.viterbi(model, symbols, start=start)


def _decode_map(model, symbols, start):
    post = hmm.posterior(model, symbols, start=start)
    best = np.argmax(post.probabilities, axis=1)  # ties: the lowest state
    logp = float(np.sum(np.log(post.probabilities[np.arange(best.size), best])))
    return post.states[best], logp


#: Decoders: a function ``(model, symbols, start) -> (states, log_probability)``.
#: ``"viterbi"`` is the most likely state sequence; ``"map"`` the most likely
#: state at each step on its own (posterior argmax; the log-probability is the
#: sum of the chosen states' log posteriors).
DECODERS = Registry("decoder")
DECODERS.add("viterbi", _decode_viterbi)
DECODERS.add("map", _decode_map)


def decode_states(decoder: str, model, symbols, start: str):
    """Decode ``symbols`` with the named decoder; an undecodable timing explained.

    Parameters
    ----------
    decoder : str
        A name of :data:`DECODERS`.
    model : ndlfd.hmm.DiscreteHMM
    symbols : ndarray of shape (n_obs,), dtype int64
    start : str
        A name of :data:`STARTS`.

    Returns
    -------
    states : ndarray of shape (n_obs,), dtype int64
    log_probability : float
    """
    try:
        return DECODERS.get(decoder)(model, symbols, start)
    except DecodeError as exc:
        raise DecodeError(
            f"cannot generate a path for this timing: {exc}. Use fewer time"
            " bins, more demonstrations, or pseudo_emission > 0."
        ) from None
