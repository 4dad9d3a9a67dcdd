"""Peer generators for the evaluation: the mean, ProMP, GMR, DMP, and ndlfd itself.

Every generator has the same small interface, so :func:`ndlfd.evaluate` treats
them alike:

``fit(demos) -> self``
    Learn from a list of :class:`~ndlfd.Demonstration` (their ``"position"``
    group and time stamps ``demo.t``).
``generate(times, *, start=None, via=None, observed=None) -> ndarray``
    Positions, of shape ``(n_samples, n_dims)``, at the given time stamps.
    Time is normalized: ``times`` are mapped to ``[0, 1]`` (first to last
    stamp), and so is every demonstration, so the generated motion lasts
    exactly as long as ``times`` span. With ``start`` (a position), the path
    must begin there; with ``via`` (``[(time, position)]``), pass through
    each position at its time; with ``observed`` (the positions executed so
    far, at the first time stamps of ``times``), return them followed by the
    path continued from the last one.

Each baseline conditions as its method allows (the class says how: ProMP
conditions its weight distribution on the points) and then passes through the
conditions exactly: the offset to each point is added and faded by minimum-jerk
ramps (:func:`minimum_jerk`) to the neighbouring points and to zero at the ends
(:func:`pass_through`).

The baselines are deliberately plain, each the textbook use of a well-known
library:

============  =============================================================
``"mean"``    :class:`MeanBaseline`, the time-aligned mean of the demos
``"promp"``   :class:`ProMPBaseline`, ``movement_primitives.promp.ProMP``
``"gmr"``     :class:`GMRBaseline`, ``gmr.GMM`` on ``(time, position)``
``"dmp"``     :class:`DMPBaseline`, ``movement_primitives.dmp.DMP``
============  =============================================================

ProMP, GMR and DMP need the optional ``eval`` extra
(``pip install "ndlfd[eval]"``); without it, :func:`make_baseline` and ``fit``
raise :class:`~ndlfd.MissingExtraError`. :class:`KeypointHMMGenerator` puts
:class:`~ndlfd.KeypointHMM` behind the same interface.

Examples
--------
>>> import numpy as np
>>> from ndlfd import Demonstration
>>> t = np.linspace(0.0, 1.0, 5)
>>> demos = [
...     Demonstration.from_arrays(t, position=np.column_stack([t, t + y0]))
...     for y0 in (0.0, 1.0)
... ]
>>> MeanBaseline().fit(demos).generate([0.0, 2.0])
array([[0. , 0.5],
       [1. , 1.5]])
>>> MeanBaseline().fit(demos).generate([0.0, 2.0], start=[0.0, 0.0])
array([[0. , 0. ],
       [1. , 1.5]])
>>> MeanBaseline().fit(demos).generate([0.0, 1.0, 2.0], via=[(1.0, [0.5, 0.0])])
array([[0. , 0.5],
       [0.5, 0. ],
       [1. , 1.5]])
"""

from ..learner import minimum_jerk
from ._generator import KeypointHMMGenerator, pass_through, prefix_pins
from ._peers import (
    BASELINES,
    DMPBaseline,
    GMRBaseline,
    MeanBaseline,
    ProMPBaseline,
    make_baseline,
)

__all__ = [
    "BASELINES",
    "DMPBaseline",
    "GMRBaseline",
    "KeypointHMMGenerator",
    "MeanBaseline",
    "ProMPBaseline",
    "make_baseline",
    "minimum_jerk",
    "pass_through",
    "prefix_pins",
]
