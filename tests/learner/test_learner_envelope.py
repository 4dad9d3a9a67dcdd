"""Conditioned paths stay within the demonstrations' motion envelope (issue 27).

1,360 random conditions over two sets (SO-101-like joints in degrees, at rest
before and after; smooth arcs in 2-D), 340 of each kind: starts and goals
within 3 times the demonstrations' spread there, via points within 3 times
one route's spread at a random phase, and observed prefixes (a demonstration
run late or early, as far off, cut at a random phase). Each path's largest
speed and acceleration over the demonstrations' 95th percentile at the same
phase
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
#: where it must hurry (measured: 2.86 and 0.30 on the joints, 1.33 and 2.60
#: on the arcs; on the arcs with the earlier 167 draws, 3.33 before the
#: clock's curvature was bounded by ``MAX_BEND``, 4.1 before the conditioned
#: shift was averaged over ``CONDITION_SMOOTH``; ProMP through the same
#: points on LASA: up to 2.9 and 5.1).
#:
#: A prefix (a demonstration 15 % late or early, 3 spreads off, cut between
#: 10 % and 90 %) is counted from its last observed sample on. The path
#: leaves at the prefix's own velocity (measured: speed 3.96 and 0.79 on the
#: joints, 3.48 and 7.29 on the arcs; 3.31 and 1.83, 3.08 and 46.4 before
#: the junction matched velocities): a late prefix still moves where the
#: demonstrations have slowed (the speed), and an offset is gone by the
#: path's next slow-down, on the arcs as little as 5 % of the motion later
#: (the acceleration).
BOUNDS = {
    "start": (1.1, 1.1),
    "goal": (1.1, 1.1),
    "via": (3.0, 2.8),
    "prefix": (4.5, 8.0),
}
DRAWS = 680  # per set: 170 of each kind


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
        kind = tuple(BOUNDS)[k % len(BOUNDS)]
        u = rng.uniform(-1.0, 1.0, span.size)
        phase = rng.uniform(0.1, 0.9)
        if kind == "prefix":
            yield kind, phase, prefix_draw(demos, group, routes, phase, span, u, rng)
            continue
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


def prefix_draw(demos, group, routes, cut, span, u, rng):
    """An execution so far: a demonstration of one route, late or early, off.

    Run from 15 % slower to 15 % faster than the plan, offset by ``3 * u``
    spreads of the route at the cut (as a via point; a constant offset, so
    its own motion is the demonstration's), cut at ``cut`` of the plan.
    Returns a function of the plan's time stamps giving the prefix (of the
    group alone). ``benchmarks/bench_envelope.py`` draws its prefixes here.
    """
    r = rng.choice(np.unique(routes))
    on = [d for d, label in zip(demos, routes, strict=True) if label == r]
    demo = on[int(rng.integers(len(on)))].select(group)
    factor = rng.uniform(0.85, 1.15)
    tau = (demo.t - demo.t[0]) / demo.duration
    at = min(cut * factor, 1.0)
    spread = np.std([[np.interp(at, (d.t - d.t[0]) / d.duration, c)
                      for c in d.get(group).T] for d in on], axis=0)  # fmt: skip
    offset = 3.0 * (spread + 1e-3 * span) * u

    def prefix(t):
        k = round(cut * (t.size - 1)) + 1
        phase = np.minimum(factor * (t[:k] - t[0]) / (t[-1] - t[0]), 1.0)
        X = np.column_stack([np.interp(phase, tau, c) for c in demo.X.T])
        return Demonstration(t[:k], X + offset, demo.columns, demo.groups)

    return prefix


@pytest.mark.parametrize("name", ["joints", "arcs"])
def test_conditioned_paths_stay_within_the_envelope(name):
    demos, model, group = _sets()[name]
    env = phase_envelope(demos, group)
    t = np.linspace(0.0, float(np.median([d.duration for d in demos])), 400)
    worst = {kind: np.zeros(2) for kind in BOUNDS}
    rng = np.random.default_rng(0)
    for kind, phase, point in _conditions(demos, group, model.routes_, rng):
        since = 0
        if kind == "prefix":  # from its last observed sample on
            since = round(phase * (t.size - 1))
            path = model.generate(t, dense=True, observed=point(t))
        elif kind == "via":
            at = t[int(np.rint(phase * (t.size - 1)))]
            path = model.generate(t, dense=True, via=[(at, {group: point})])
        else:
            path = model.generate(t, dense=True, **{kind: {group: point}})
        ratios = envelope_ratios(path, env, group, since=since)
        worst[kind] = np.maximum(worst[kind], ratios)
    for kind, (speed, acc) in BOUNDS.items():
        assert worst[kind][0] <= speed, (name, kind, worst[kind])
        assert worst[kind][1] <= acc, (name, kind, worst[kind])
