"""Replanning during an execution: the route of a prefix from the prefix itself.

A robot replans at 10 Hz with ``generate(plan_times, observed=prefix)``; its
plan may run 15 % longer or shorter than the execution. The prefix's route
must not depend on that, and must not flip while the prefix is ambiguous
(:mod:`ndlfd.learner._prefix_route`).
"""

import functools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd import Demonstration, KeypointHMM
from ndlfd.learner import minimum_jerk
from ndlfd.learner._curves import open_end_frechet
from ndlfd.learner._prefix_route import allowed_routes, prefix_stride

NAMES = ("shoulder_pan", "shoulder_lift", "elbow_flex", "wrist_flex", "wrist_roll")
FPS = 30.0


def _episode(rng, side, pose=2.0, place=False):
    """An SO-101-like episode in degrees: lift, pan to +-40 deg, put down.

    Every joint's home pose varies by ``pose`` degrees (one standard
    deviation), the pan's amplitude by 3; with ``place``, so do the lift's
    and the place phase's depths and the wrist's flex there (by ``pose``).
    """
    duration = rng.uniform(6.3, 7.7)
    t = np.arange(0.0, duration, 1.0 / FPS)
    s = t / t[-1]
    w = np.clip(s + 0.02 * np.sin(2 * np.pi * s) * rng.normal(), 0.0, 1.0)
    lift = minimum_jerk(np.clip(w / 0.5, 0, 1))
    turn = minimum_jerk(np.clip((w - 0.2) / 0.4, 0, 1))  # the pan: 20 to 60 %
    down = minimum_jerk(np.clip((w - 0.6) / 0.4, 0, 1))
    J = np.tile(np.array([0.0, -100.0, 95.0, 60.0, 0.0]) + rng.normal(0, pose, 5),
                (t.size, 1))  # fmt: skip
    J[:, 0] += side * (40 + rng.normal(0, 3)) * turn
    if place:  # drawn in this order: the lift's depth, the place's, the wrist's
        J[:, 1] += (60 + rng.normal(0, pose)) * lift - (30 + rng.normal(0, pose)) * down
    else:
        J[:, 1] += 60 * lift - 30 * down
    J[:, 2] += -50 * lift + 20 * down
    J[:, 3] += 20 * lift + (rng.normal(0, pose) * down if place else 0.0)
    J[:, 4] += 10 * turn
    J += rng.normal(0, 0.3, J.shape)
    gripper = 30.0 + 20.0 * (w > 0.7)
    return Demonstration.from_arrays(t, joints=J, gripper=gripper,
                                     columns={"joints": NAMES})  # fmt: skip


@functools.cache
def _pan_set():
    """16 episodes to +40 deg, 8 to -40 deg (shuffled), fitted without one each."""
    rng = np.random.default_rng(5)
    sides = np.array([1] * 16 + [-1] * 8)[rng.permutation(24)]
    demos = [_episode(rng, s) for s in sides]
    return demos, sides


@functools.cache
def _fitted(held):
    demos, sides = _pan_set()
    train = [d for i, d in enumerate(demos) if i != held]
    model = KeypointHMM(groups=("joints", "gripper"),
                        levels={"joints": 20, "gripper": 10}).fit(train)  # fmt: skip
    return model, demos[held], int(sides[held])


def _ticks(model, episode, factor):
    """Replanning every 3 samples (10 Hz): the prefix's pan and the plan's end pan."""
    plan_t = np.arange(0.0, factor * episode.t[-1], 1.0 / FPS)
    out = []
    for m in range(6, min(episode.t.size, plan_t.size) - 3, 3):
        prefix = Demonstration(episode.t[:m], episode.X[:m], episode.columns,
                               episode.groups)  # fmt: skip
        path = model.generate(plan_t, observed=prefix)
        out.append((float(prefix.X[-1, 0]), float(path.X[-1, 0])))
    return np.array(out)


@pytest.mark.parametrize("minor", [True, False])
@pytest.mark.parametrize("factor", [0.85, 0.9, 1.0, 1.1, 1.15])
def test_replanning_follows_the_prefix_route_whatever_the_plan_length(minor, factor):
    _, sides = _pan_set()
    held = int(np.flatnonzero(sides == (-1 if minor else 1))[0])
    model, episode, side = _fitted(held)
    assert np.bincount(model.routes_).tolist() in ([7, 16], [16, 7], [8, 15], [15, 8])
    ticks = _ticks(model, episode, factor)
    end_side = np.sign(ticks[:, 1])
    # at most one change of route over the execution (no flip-flop) ...
    changes = np.flatnonzero(end_side[1:] != end_side[:-1])
    assert changes.size <= (1 if minor else 0), ticks[:, 1].round(1).tolist()
    # ... none once the prefix has committed (15 deg on its way), and the
    # plan ends on the prefix's route there
    committed = side * ticks[:, 0] > 15.0
    assert committed.any()
    assert np.all(end_side[committed] == side)
    assert np.all(np.abs(ticks[committed, 1] - side * 40.0) < 8.0)
    # before the route is known the plan follows the prior's (the major) route
    major = 1 if np.sum(sides == 1) > np.sum(sides == -1) else -1
    assert end_side[0] == major


def test_samples_continue_on_the_prefix_route():
    _, sides = _pan_set()
    held = int(np.flatnonzero(sides == -1)[0])
    model, episode, side = _fitted(held)
    plan_t = np.arange(0.0, 1.1 * episode.t[-1], 1.0 / FPS)
    at = int(np.flatnonzero(side * episode.X[:, 0] > 20.0)[0])  # committed
    prefix = Demonstration(episode.t[:at], episode.X[:at], episode.columns,
                           episode.groups)  # fmt: skip
    ends = [p.X[-1, 0] for p in model.sample(plan_t, 10, observed=prefix,
                                             random_state=0)]  # fmt: skip
    assert all(abs(e - side * 40.0) < 8.0 for e in ends), np.round(ends, 1)
    # ambiguous (before the pan): each sample on one route, none between
    early = Demonstration(episode.t[:20], episode.X[:20], episode.columns,
                          episode.groups)  # fmt: skip
    ends = [p.X[-1, 0] for p in model.sample(plan_t, 20, observed=early,
                                             random_state=1)]  # fmt: skip
    assert all(min(abs(e - 40.0), abs(e + 40.0)) < 8.0 for e in ends)


def _open_end_brute(P, C):
    """min over j of the discrete Fréchet distance of P and C[:j+1] (enumerated)."""
    best = np.inf

    def walk(i, j, worst):
        nonlocal best
        worst = max(worst, float(np.sum((P[i] - C[j]) ** 2)))
        if worst >= best:
            return
        if i == len(P) - 1:
            best = worst  # any j: the curve's end is open
        for di, dj in ((1, 0), (0, 1), (1, 1)):
            if i + di < len(P) and j + dj < len(C):
                walk(i + di, j + dj, worst)

    walk(0, 0, 0.0)
    return best


@given(st.integers(1, 5), st.integers(1, 5), st.integers(1, 3), st.integers(0, 9999))
@settings(deadline=None)
def test_open_end_distances_match_brute_force(m, k, d, seed):
    # values on a grid of 1/8: both sides compute the same squares exactly
    rng = np.random.default_rng(seed)
    P = rng.integers(-8, 9, (m, d)) / 8.0
    curves = rng.integers(-8, 9, (2, k, d)) / 8.0
    got = open_end_frechet(P, curves)
    for t in range(2):
        for i in range(m):
            assert got[t, i] == np.sqrt(_open_end_brute(P[: i + 1], curves[t]))


def test_a_route_once_ruled_out_stays_ruled_out():
    _, sides = _pan_set()
    held = int(np.flatnonzero(sides == -1)[0])
    model, episode, _ = _fitted(held)
    U = model.scaler_.transform(episode.X, weighted=False)
    stride = prefix_stride(400)
    seen = np.ones(2, dtype=bool)
    for m in range(3, episode.t.size, 3):
        now = allowed_routes(model, U[:m], stride, model._cache)
        assert not np.any(now & ~seen)  # nothing comes back
        assert now.any()
        seen = now
    assert seen.sum() == 1


@functools.cache
def _resting():
    """SO-101-like episodes with the robot at rest 3.5-4.5 s before and after.

    The gripper is a continuous position (degrees, noisy), as LeRobot records
    an SO-101's ``gripper.pos``.
    """
    rng = np.random.default_rng(1)
    demos = []
    for _ in range(10):
        d = _episode(rng, 1)
        rest = int(rng.uniform(3.5, 4.5) * FPS)
        X = np.vstack([np.repeat(d.X[:1], rest, 0), d.X, np.repeat(d.X[-1:], rest, 0)])
        X = X + rng.normal(0, 0.05, X.shape)
        demos.append(Demonstration(np.arange(X.shape[0]) / FPS, X, d.columns,
                                   d.groups))  # fmt: skip
    model = KeypointHMM(groups=("joints", "gripper"),
                        levels={"joints": 20, "gripper": 10}).fit(demos)  # fmt: skip
    return demos, model


def _same_phase_steps(demos, tau, window=0.03):
    """The demonstrations' largest joint step within ``window`` of each step's phase."""
    out = np.zeros(tau.size - 1)
    mids = (tau[1:] + tau[:-1]) / 2
    for d in demos:
        dt = (d.t - d.t[0]) / d.duration
        steps = np.abs(np.diff(d.get("joints"), axis=0)).max(axis=1)
        at = (dt[1:] + dt[:-1]) / 2
        for k, m in enumerate(mids):
            near = np.abs(at - m) <= window
            if near.any():
                out[k] = max(out[k], steps[near].max())
    return out


@pytest.mark.parametrize("offset", [1.0, 5.0, 20.0])
@pytest.mark.filterwarnings("ignore::ndlfd.ExtrapolationWarning")  # far on purpose
def test_a_start_or_goal_off_a_robot_at_rest_is_absorbed_without_a_jump(offset):
    # before: a continuous gripper counted as switching at its first sample,
    # so a start 5 deg off was gone in one sample (7 deg in 33 ms)
    demos, model = _resting()
    t = np.arange(0.0, demos[0].t[-1], 1.0 / FPS)
    most = _same_phase_steps(demos, (t - t[0]) / (t[-1] - t[0]))
    first, last = demos[0].get("joints")[0], demos[0].get("joints")[-1]
    for cond in ({"start": {"joints": first + offset}},
                 {"goal": {"joints": last - offset}},
                 {"start": {"joints": first - offset},
                  "goal": {"joints": last + offset}}):  # fmt: skip
        J = model.generate(t, dense=True, **cond).get("joints")
        if "start" in cond:
            np.testing.assert_allclose(J[0], cond["start"]["joints"])
        if "goal" in cond:
            np.testing.assert_allclose(J[-1], cond["goal"]["joints"])
        steps = np.abs(np.diff(J, axis=0)).max(axis=1)
        # no step larger than the demonstrations' at the same phase (within
        # 3 % of the motion); measured: at most 0.95 of it (20 deg both ends)
        worst = float((steps / most).max())
        assert worst <= 1.0, (offset, cond.keys(), worst)
        # at rest (the first and last second) the path moves as slowly as
        # the offset's fade over the whole motion allows, never a jump
        assert steps[: int(FPS)].max() < 0.1 * offset + 0.1
        assert steps[-int(FPS) :].max() < 0.1 * offset + 0.1


def test_a_prefix_of_the_position_only_is_completed_from_the_plan():
    """A robot that reports its position only: the gripper and orientation
    of its prefix come from the path generated for the timing."""
    from ndlfd import synth

    demos, _ = synth.pick_place(8, n_samples=200, random_state=3)
    model = KeypointHMM(random_state=0).fit(demos[1:])
    test = demos[0]
    n = 60
    full = Demonstration(test.t[:n], test.X[:n], test.columns, test.groups)
    only = full.select("position")
    a = model.generate(test.t, dense=True, observed=full)
    b = model.generate(test.t, dense=True, observed=only)
    # the observed positions are kept exactly, the rest is the plan's
    np.testing.assert_array_equal(b.get("position")[:n], only.get("position"))
    plan = model.generate(test.t, dense=True,
                          start={"position": only.get("position")[0]})  # fmt: skip
    np.testing.assert_allclose(b.get("gripper")[:n], plan.get("gripper")[:n])
    # and the continuation is the full prefix's, within a millimetre
    assert np.abs(b.get("position")[n:] - a.get("position")[n:]).max() < 1e-3
    s = model.sample(test.t, 2, observed=only, random_state=0)
    assert all(np.array_equal(p.get("position")[:n], only.get("position")) for p in s)
