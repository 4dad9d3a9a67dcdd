"""No end snap: a replanned plan's last part steps as the demonstrations do there.

A robot replans at 10 Hz with ``generate(plan_times, observed=prefix)``, the
plan 0.85 to 1.15 times the execution's length. Near the plan's end the
executed prefix may be far from the route's end pose (the robot is late, or
runs beside the demonstrations): the offset at the junction used to be faded
to nothing over the few samples left, 5-13 deg in 33 ms where the
demonstrations step about 1 deg (:func:`ndlfd.learner._via.continue_from`).
"""

import functools

import numpy as np
import pytest
from test_learner_replan import FPS, _fitted, _pan_set

from ndlfd import Demonstration, KeypointHMM
from ndlfd.synth import obstacle

FACTORS = (0.85, 0.9, 1.0, 1.1, 1.15)


def _last_steps(demos, share=0.1):
    """Per joint, the demonstrations' largest step over their last ``share``."""
    out = 0.0
    for d in demos:
        tau = (d.t - d.t[0]) / d.duration
        mid = (tau[1:] + tau[:-1]) / 2
        steps = np.abs(np.diff(d.get("joints"), axis=0))
        out = np.maximum(out, steps[mid >= 1.0 - share].max(axis=0))
    return out


@functools.cache
def _case(minor):
    demos, sides = _pan_set()
    held = int(np.flatnonzero(sides == (-1 if minor else 1))[0])
    model, episode, _ = _fitted(held)
    train = [d for i, d in enumerate(demos) if i != held]
    return model, episode, _last_steps(train)


def _final_plan(model, episode, factor, offset):
    """The plan of the last tick of ``test_learner_replan._ticks`` (every 3
    samples from the 6th, at least 3 samples of the plan and execution left),
    the execution shifted by ``offset`` degrees on every joint."""
    plan_t = np.arange(0.0, factor * episode.t[-1], 1.0 / FPS)
    X = episode.X.copy()
    X[:, episode.columns_of("joints")] += offset
    m = list(range(6, min(episode.t.size, plan_t.size) - 3, 3))[-1]
    prefix = Demonstration(episode.t[:m], X[:m], episode.columns, episode.groups)
    return model.generate(plan_t, observed=prefix), prefix


@pytest.mark.parametrize("offset", [0.0, 5.0])
@pytest.mark.parametrize("minor", [False, True])
def test_the_final_plan_steps_no_more_than_the_demonstrations_at_its_end(minor, offset):
    model, episode, most = _case(minor)
    worst = {}
    for factor in FACTORS:
        path, prefix = _final_plan(model, episode, factor, offset)
        J = path.get("joints")
        np.testing.assert_array_equal(J[: prefix.n_samples], prefix.get("joints"))
        tail = np.abs(np.diff(J, axis=0))[int(0.9 * (J.shape[0] - 1)) :]
        worst[factor] = float((tail.max(axis=0) / most).max())
    # before: up to 2.4 (on the route) and 4.0 (the minor route, 5 deg off)
    # at 0.85; measured now: at most 0.96, the execution's own noisy steps
    assert max(worst.values()) <= 1.5, worst


@pytest.mark.parametrize("minor", [False, True])
def test_a_late_plan_ends_beside_the_route_end_by_the_robots_offset(minor):
    # the plan 0.85 times the execution: at the last tick the robot is still
    # on its way down, well short of the route's end pose (the mean end of
    # its route's demonstrations). The plan continues from it and keeps most
    # of that offset to its end (3 % of the motion fades (0.03 / 0.1)^2 of
    # it), where it used to land on the route's end.
    demos, sides = _pan_set()
    model, episode, _ = _case(minor)
    side = -1 if minor else 1
    end = np.mean([d.get("joints")[-1] for d, s in zip(demos, sides, strict=True)
                   if s == side and d is not episode], axis=0)  # fmt: skip
    path, prefix = _final_plan(model, episode, 0.85, 0.0)
    gap = prefix.get("joints")[-1] - end
    j = int(np.argmax(np.abs(gap)))
    assert abs(gap[j]) > 5.0  # far from the route's end (13 and 12 deg)
    kept = (path.get("joints")[-1, j] - end[j]) / gap[j]
    assert kept > 0.5, kept


# Position models: after a prefix the blend's clock is warped to the phase the
# robot reached (ndlfd.learner._phase.prefix_warp); a late robot's last plan
# ran the rest of the route in its last few samples (synth.obstacle, 0.85:
# 3.9 times the demonstrations' largest step; LASA Multi_Models_1: 75 times).


@functools.cache
def _obstacle_case(held):
    demos = obstacle()
    train = [d for i, d in enumerate(demos) if i != held]
    most = 0.0
    for d in train:  # per column, the largest step over the last 10 %
        tau = (d.t - d.t[0]) / d.duration
        mid = (tau[1:] + tau[:-1]) / 2
        steps = np.abs(np.diff(d.get("position"), axis=0))
        most = np.maximum(most, steps[mid >= 0.9].max(axis=0))
    return KeypointHMM().fit(train), demos[held], most


def _obstacle_plan(model, episode, factor):
    """The last tick's plan: every 3 samples from the 6th, 3 or more left."""
    dt = float(np.median(np.diff(episode.t)))
    plan_t = np.arange(0.0, factor * episode.duration, dt)
    m = list(range(6, min(episode.t.size, plan_t.size) - 3, 3))[-1]
    prefix = Demonstration(episode.t[:m], episode.X[:m], episode.columns,
                           episode.groups)  # fmt: skip
    return model.generate(plan_t, observed=prefix), prefix


@pytest.mark.parametrize("held", [0, 8])  # over the top, underneath
def test_a_position_models_final_plan_steps_no_more_than_the_demonstrations(held):
    model, episode, most = _obstacle_case(held)
    worst = {}
    for factor in FACTORS:
        path, prefix = _obstacle_plan(model, episode, factor)
        P = path.get("position")
        np.testing.assert_array_equal(P[: prefix.n_samples], prefix.get("position"))
        steps = np.abs(np.diff(P, axis=0)) / most
        worst[factor] = float(steps[int(0.9 * (P.shape[0] - 1)) :].max())
        if factor < 1.0:  # late: the rest of the route does not fit, it stops
            # its last step a quarter of the demonstrations' largest at
            # most (measured 0.03-0.13; before: 1.6-2.7, still moving)
            assert steps[-1].max() < 0.25, steps[-1]
    # before: 3.9 (over the top) and 3.4 at 0.85, 2.1 and 2.2 at 0.9;
    # measured now: at most 0.83 (the execution's own noisy steps)
    assert max(worst.values()) <= 1.5, worst
