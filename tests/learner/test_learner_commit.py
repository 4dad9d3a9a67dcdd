"""Replanning commits when the prefix is decisive, however many demonstrations.

Issue 39: an SO-101-like arm is shown a pick-and-place that pans to +40 or
to -40 degrees (more episodes to +40); a held-out episode is replanned at
10 Hz with plans 0.85x-1.15x its length. The plan follows the prior's route
(+40) until the prefix tells; the prefix must tell by 30 % of the divergence
(12 of 40 degrees), with 10, 22 or 50 episodes (a rule whose margin grows with
the data committed at 75 %), and never flip back. Episodes vary as recorded
ones do: every joint's pose +-3 degrees, the pan's amplitude +-3 degrees,
the place phase's depth +-3 degrees, sensor noise.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
from test_learner_replan import FPS
from test_learner_replan import _episode as replan_episode

from ndlfd import Demonstration, KeypointHMM
from ndlfd.learner._prefix_route import COMMIT_ODDS, prefix_evidence, prefix_stride


def _episode(rng, side):
    """Lift, pan to side * 40 deg, place: every variation +-3 deg (degrees)."""
    return replan_episode(rng, side, pose=3.0, place=True)


@functools.cache
def _set(n: int):
    """``n`` episodes, 7 in 22 of them to -40 deg, shuffled; fixed seed."""
    rng = np.random.default_rng(5)
    n_minor = round(n * 7 / 22)
    sides = np.array([1] * (n - n_minor) + [-1] * n_minor)[rng.permutation(n)]
    return [_episode(rng, s) for s in sides], sides


@functools.cache
def _fitted(n: int, side: int):
    demos, sides = _set(n)
    held = int(np.flatnonzero(sides == side)[0])
    train = [d for i, d in enumerate(demos) if i != held]
    model = KeypointHMM(groups=("joints", "gripper"),
                        levels={"joints": 20, "gripper": 10}).fit(train)  # fmt: skip
    return model, demos[held]


def _ticks(model, episode, factor):
    """Every 3 samples (10 Hz): how far the prefix has panned, and the plan's end."""
    plan_t = np.arange(0.0, factor * episode.t[-1], 1.0 / FPS)
    out = []
    for m in range(6, min(episode.t.size, plan_t.size) - 3, 3):
        prefix = Demonstration(episode.t[:m], episode.X[:m], episode.columns,
                               episode.groups)  # fmt: skip
        path = model.generate(plan_t, observed=prefix)
        out.append((float(prefix.X[-1, 0] - prefix.X[0, 0]), float(path.X[-1, 0])))
    return np.array(out)


@pytest.mark.parametrize("n", [10, 22, 50])
@pytest.mark.parametrize("factor", [0.85, 1.0, 1.15])
def test_a_minor_route_is_committed_to_by_30_percent_of_the_divergence(n, factor):
    model, episode = _fitted(n, -1)
    assert np.bincount(model.routes_).size == 2
    ticks = _ticks(model, episode, factor)
    end = np.sign(ticks[:, 1])
    assert end[0] == 1  # the prior's route (most episodes) while ambiguous
    changes = np.flatnonzero(end[1:] != end[:-1])
    assert changes.size == 1, ticks.round(1).tolist()  # one commit, no flip
    panned = -ticks[changes[0] + 1, 0]  # how far the prefix had panned then
    assert 0 < panned <= 12.0, ticks.round(1).tolist()
    # from then on, while the pan goes on, the plan ends where the route does
    going = np.flatnonzero(-ticks[:, 0] < 30.0)
    after = going[going > changes[0]]
    assert after.size and np.all(np.abs(ticks[after, 1] + 40.0) < 8.0)


@pytest.mark.parametrize("n", [10, 22, 50])
@pytest.mark.parametrize("factor", [0.85, 1.15])
def test_the_major_route_is_never_left(n, factor):
    model, episode = _fitted(n, 1)
    ticks = _ticks(model, episode, factor)
    assert np.all(ticks[:, 1] > 30.0), ticks.round(1).tolist()


def test_the_odds_are_the_posterior_of_the_evidence_and_the_prior():
    # the rule against its definition: a route is out from the first matched
    # sample where its posterior falls below 1/COMMIT_ODDS of the best one's,
    # recomputed here from prefix_evidence and the routes' shares
    model, episode = _fitted(22, -1)
    U = model.scaler_.transform(episode.X, weighted=False)
    stride = prefix_stride(400)
    ev = prefix_evidence(model, U, stride, model._cache)
    prior = np.bincount(model.routes_) / len(model.routes_)
    post = ev + np.log(prior)[:, None]
    major = int(np.argmax(prior))
    behind = post[major] < post.max(axis=0) - np.log(COMMIT_ODDS)
    first = int(np.argmax(behind))
    assert behind.any() and not behind[:first].any()
    from ndlfd.learner._prefix_route import allowed_routes

    rows = np.arange(0, U.shape[0], stride)
    before = allowed_routes(model, U[: rows[first]], stride, model._cache, prior)
    after = allowed_routes(model, U[: rows[first] + 1], stride, model._cache, prior)
    assert before[major] and not after[major]
