"""Conditioned paths stay within the demonstrations' motion envelope (issue 27).

1,000 random conditions over two sets (SO-101-like joints in degrees, at rest
before and after; smooth arcs in 2-D): starts and goals within 3 times the
demonstrations' spread there, via points within 3 times one route's spread
at a random phase. Each path's largest speed and acceleration over the
demonstrations' 95th percentile at the same phase
(:func:`ndlfd.metrics.phase_envelope`, itself checked against loops in
tests/test_metrics.py) must stay under the bounds below, the numbers the
README gives (``benchmarks/bench_envelope.py`` prints them for LASA and the
obstacle set too, with ProMP beside).
"""

import functools

import numpy as np
import pytest
from test_learner_replan import _resting

from ndlfd import Demonstration, KeypointHMM
from ndlfd.metrics import envelope_ratios, phase_envelope

#: Largest speed and acceleration over the envelope, per kind. A start or a
#: goal adds no motion the demonstrations do not make (measured: speed 0.81
#: and acceleration 0.22 on the joints, 1.02 and 1.01 on the arcs). A via
#: point forces the path through a point up to 3 spreads off at a given
#: time, as early as a tenth of the motion: that costs speed and acceleration
#: where it must hurry (measured: 2.59 and 0.27 on the joints, 1.35 and 2.50
#: on the arcs; 3.33 before the clock's curvature was bounded by
#: ``MAX_BEND``, 4.1 before the conditioned shift was averaged over
#: ``CONDITION_SMOOTH``; ProMP through the same points on LASA: up to 2.9
#: and 5.1).
BOUNDS = {"start": (1.1, 1.1), "goal": (1.1, 1.1), "via": (3.0, 2.8)}
DRAWS = 500  # per set


def _arcs(n_demos=8, seed=1, n=200):
    """Smooth arcs of different heights and paces, from rest to rest."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n_demos):
        s = np.linspace(0.0, 1.0, n)
        pace = s + rng.uniform(-0.05, 0.05) * np.sin(np.pi * s)
        u = pace * pace * (3 - 2 * pace)
        a = rng.uniform(0.8, 1.2)
        P = np.column_stack([u + rng.uniform(-0.05, 0.05), a * np.sin(np.pi * u)])
        out.append(Demonstration.from_arrays(5.0 * s, position=P))
    return out


@functools.cache
def _sets():
    demos, model = _resting()
    arcs = _arcs()
    return {
        "joints": (demos, model, "joints"),
        "arcs": (arcs, KeypointHMM().fit(arcs), "position"),
    }


def _conditions(demos, group, routes, rng):
    starts = np.array([d.get(group)[0] for d in demos])
    goals = np.array([d.get(group)[-1] for d in demos])
    span = np.ptp(np.vstack([d.get(group) for d in demos]), axis=0)
    for k in range(DRAWS):
        kind = ("start", "goal", "via")[k % 3]
        u = rng.uniform(-1.0, 1.0, span.size)
        phase = rng.uniform(0.1, 0.9)
        if kind == "via":
            r = rng.choice(np.unique(routes))
            on = [d for d, label in zip(demos, routes, strict=True) if label == r]
            vals = np.array([[np.interp(phase, (d.t - d.t[0]) / d.duration, c)
                              for c in d.get(group).T] for d in on])  # fmt: skip
        else:
            vals = starts if kind == "start" else goals
        yield (
            kind,
            phase,
            vals.mean(axis=0) + 3.0 * (vals.std(axis=0) + 1e-3 * span) * u,
        )


@pytest.mark.parametrize("name", ["joints", "arcs"])
def test_conditioned_paths_stay_within_the_envelope(name):
    demos, model, group = _sets()[name]
    env = phase_envelope(demos, group)
    t = np.linspace(0.0, float(np.median([d.duration for d in demos])), 400)
    worst = {kind: np.zeros(2) for kind in BOUNDS}
    rng = np.random.default_rng(0)
    for kind, phase, point in _conditions(demos, group, model.routes_, rng):
        if kind == "via":
            at = t[int(np.rint(phase * (t.size - 1)))]
            path = model.generate(t, dense=True, via=[(at, {group: point})])
        else:
            path = model.generate(t, dense=True, **{kind: {group: point}})
        worst[kind] = np.maximum(worst[kind], envelope_ratios(path, env, group))
    for kind, (speed, acc) in BOUNDS.items():
        assert worst[kind][0] <= speed, (name, kind, worst[kind])
        assert worst[kind][1] <= acc, (name, kind, worst[kind])
