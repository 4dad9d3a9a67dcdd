"""Compile the generation's kernels without a fitted model (a first run's second core).

A fresh install compiles each kernel on its first call (numba, cached on disk
after). A generation needs three, the Viterbi decoder
(:func:`ndlfd.hmm.viterbi`), the skeleton alignment
(:func:`~ndlfd.learner._blend.align_to_skeleton`) and the windowed reading of
the templates (:func:`~ndlfd.learner._blend.warped`), and none of them needs a
fit to be compiled: only the argument types count, not their values.
:func:`compile_generation` calls each on a tiny made-up input with the types
a generation passes, so that a second process can compile them into the
cache while the first compiles the fit's kernels (``ndlfd demo``'s warm-up,
:mod:`ndlfd.jobs.demo`); the first then loads them instead of compiling them.
Run as ``python -m ndlfd.learner._warm``, it prints ``{"kernels": n,
"seconds": s}``: how many kernels it compiled (0 when all came from the
cache) and in how long.
"""

from __future__ import annotations

import json
import time

import numpy as np
from numba.core import event

from .. import hmm
from ._blend import align_to_skeleton, warped

__all__ = ["compile_generation"]


class _Count(event.Listener):
    """Kernels compiled from Python (each with the kernels it calls)."""

    def __init__(self):
        self.depth = 0
        self.kernels = 0

    def on_start(self, ev) -> None:
        self.kernels += self.depth == 0
        self.depth += 1

    def on_end(self, ev) -> None:
        self.depth -= 1


def compile_generation() -> int:
    """Compile (or load from numba's cache) the kernels a generation calls.

    Each kernel is called on a made-up input of two or three rows with the
    argument types a generation gives it (contiguous float64 and int64
    arrays, Python bools and floats); the values are thrown away.

    Returns
    -------
    kernels : int
        How many kernels were compiled (0 when all were compiled or cached
        already).

    Examples
    --------
    >>> compile_generation() >= 0
    True
    """
    count = _Count()
    with event.install_listener("numba:compile", count):
        model = hmm.estimate([[0, 1]], [[0, 1]], n_states=3, n_symbols=2)
        hmm.viterbi(model, np.array([0, 1]))
        U = np.array([[0.0, 0.0], [0.5, 1.0], [1.0, 0.0]])
        tau = np.array([0.0, 0.5, 1.0])
        index = align_to_skeleton(U, U[[0, 2]])
        tq = np.linspace(0.0, 1.0, 9)  # finer than U: read through a window
        warped([U], [tau], [index], np.ones(1), tau[index], tq)
    return count.kernels


if __name__ == "__main__":  # pragma: no cover - run by ndlfd.jobs.demo
    t0 = time.perf_counter()
    n = compile_generation()
    print(json.dumps({"kernels": n, "seconds": time.perf_counter() - t0}))
