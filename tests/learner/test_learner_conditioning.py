"""Conditioning (ndlfd.learner._conditioning): the kernel width, a far start."""

import re
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd._errors import ExtrapolationWarning
from ndlfd.learner._conditioning import (
    BANDWIDTH_FACTOR,
    BRUTE_FORCE_POINTS,
    condition_bandwidth,
)
from ndlfd.learner._extrapolation import FAR_SPREADS, SPREAD_FLOOR, envelope_distance


def _reference_width(points):
    """Loops over every pair: the median nearest-other distance, times the factor."""
    n = len(points)
    nearest = []
    for i in range(n):
        others = [np.sqrt(np.sum((points[i] - points[j]) ** 2)) for j in range(n)
                  if j != i]  # fmt: skip
        nearest.append(float(min(others)))
    return BANDWIDTH_FACTOR * float(np.median(nearest))


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(2, 2 * BRUTE_FORCE_POINTS),
    d=st.integers(1, 6),
    seed=st.integers(0, 2**31 - 1),
)
def test_both_ways_give_the_median_nearest_distance(n, d, seed):
    # all pairs up to BRUTE_FORCE_POINTS points, a k-d tree beyond: the same width
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(n, d)) * rng.uniform(0.01, 100.0)
    if n > 3:
        points[1] = points[0]  # a duplicate: its nearest distance is 0
    expected = _reference_width(points)
    if not expected > 0:  # most coincide: the width of the set (not drawn here)
        return
    assert np.isclose(condition_bandwidth(points), expected, rtol=1e-12, atol=0.0)


def test_coinciding_points_take_the_width_of_the_set():
    points = np.array([[0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [3.0, 4.0]])
    assert condition_bandwidth(points) == 5.0
    assert condition_bandwidth(np.zeros((1, 2))) == 1.0


def _mean_around(x, share=0.01):
    """Each row the mean of the rows within round(share * n) (at least 1) of it."""
    n = len(x)
    h = max(1, round(share * n))
    return np.array([np.mean(x[max(0, i - h) : i + h + 1], axis=0) for i in range(n)])


def test_contact_window_is_judged_while_moving_not_at_rest():
    from ndlfd.learner._rests import SMOOTH_SHARE, contact_window

    # a brute-force reference: the typical speed is the median of the speeds
    # of at least a tenth of the 95th percentile; the first slow step after
    # the first at that speed or faster, the last the same backwards
    def reference(x, tq):
        v = np.abs(np.diff(_mean_around(x, SMOOTH_SHARE))) / np.diff(tq)
        fast = np.quantile(v, 0.95)
        typical = np.median([s for s in v if s >= 0.1 * fast])
        go = [i for i, s in enumerate(v) if s >= typical]
        first = next((tq[i] for i in range(go[0], len(v)) if v[i] < 0.2 * typical), 1.0)
        last = next(
            (tq[i + 1] for i in range(go[-1], -1, -1) if v[i] < 0.2 * typical), 0.0
        )
        return first, last

    rng = np.random.default_rng(0)
    tq = np.linspace(0.0, 1.0, 1000)
    # at rest for 70 % of the time (noise only), moving 10 %, a stop, moving
    x = np.concatenate([np.zeros(700), np.linspace(0, 1, 101)[1:],
                        np.ones(50), np.linspace(1, 2, 151)[1:]])  # fmt: skip
    x = x + rng.normal(0, 1e-5, x.size)
    first, last = contact_window(x[:, None], tq)
    assert (first, last) == reference(x, tq)
    # the stop at 80 % is the first slow-down, not the rest before the motion
    assert 0.79 < first < 0.81
    assert 0.84 < last < 0.86


def test_progress_against_a_loop_over_the_rows():
    from ndlfd.learner._conditioning import progress
    from ndlfd.learner._rests import SMOOTH_SHARE

    rng = np.random.default_rng(3)
    X = np.column_stack([np.cumsum(rng.normal(size=40)), 100 * rng.normal(size=40),
                         rng.integers(0, 2, 40), rng.normal(size=40)])  # fmt: skip
    groups = ("position", "joints", "gripper", "velocity")
    tq = np.sort(rng.uniform(size=40))
    S = _mean_around(X, SMOOTH_SHARE)  # the moving average, by a loop
    spans = [np.ptp(S[:, 0]), np.ptp(S[:, 1])]
    want = [0.0]
    for i in range(1, 40):  # the position and the joints, each by its range
        d = [(S[i, c] - S[i - 1, c]) / spans[c] for c in (0, 1)]
        want.append(want[-1] + float(np.sqrt(d[0] ** 2 + d[1] ** 2)))
    np.testing.assert_allclose(progress(X, tq, groups), want, rtol=1e-12)
    # extra rows (key points) at their times, between the dense rows
    extra = np.vstack([X, X[[5]]])
    at = np.append(tq, tq[5])
    assert progress(extra, at, groups, n_dense=40)[-1] == want[5]


def _waiting(n_demos=6, seed=0):
    """At rest 60 % of the time (noise), then one reach without a stop."""
    from ndlfd import Demonstration
    from ndlfd.learner import minimum_jerk

    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n_demos):
        t = np.linspace(0.0, 10.0, 500)
        s = minimum_jerk(np.clip((t / 10.0 - 0.6) / 0.4, 0.0, 1.0))
        P = np.column_stack([s, np.sin(np.pi * s) * 0.3]) + rng.normal(
            0, 0.002, (500, 2)
        )
        out.append(Demonstration.from_arrays(t, position=P))
    return out


def test_a_start_offset_waits_while_the_robot_waits():
    """The offset is faded as the path moves, not while it rests.

    Faded over time, a start 0.3 off moved the path at 1.6 times the largest
    step of the resting demonstrations, half way through their rest.
    """
    from ndlfd import KeypointHMM

    demos = _waiting()
    model = KeypointHMM().fit(demos)
    t = demos[0].t
    # 0.36 from every demonstration's start, which lie within 0.01 of (0, 0)
    with pytest.warns(ExtrapolationWarning, match="spreads from the nearest"):
        path = model.generate(t, dense=True, start={"position": [-0.3, 0.2]})
    P = path.get("position")
    np.testing.assert_allclose(P[0], [-0.3, 0.2])
    rest = slice(0, int(0.55 * t.size))
    resting = max(np.linalg.norm(np.diff(d.get("position")[rest], axis=0), axis=1).max()
                  for d in demos)  # fmt: skip
    assert np.linalg.norm(np.diff(P[rest], axis=0), axis=1).max() <= resting


# ------------------------------------------------- a start far from every one
def _reference_distance(target, points, floor):
    """Loops: per column the population std (at least floor), the nearest row."""
    n, k = len(points), len(target)
    spread = []
    for c in range(k):
        mean = sum(points[i][c] for i in range(n)) / n
        var = sum((points[i][c] - mean) ** 2 for i in range(n)) / n
        spread.append(max(float(np.sqrt(var)), floor))
    best = None
    for i in range(n):
        d = float(np.sqrt(sum(((target[c] - points[i][c]) / spread[c]) ** 2
                              for c in range(k))))  # fmt: skip
        if best is None or d < best[0]:
            best = (d, i)
    return best[0], best[1], spread


@settings(max_examples=60, deadline=None)
@given(n=st.integers(1, 12), k=st.integers(1, 5), seed=st.integers(0, 2**31 - 1),
       same=st.booleans())  # fmt: skip
def test_envelope_distance_against_loops(n, k, seed, same):
    rng = np.random.default_rng(seed)
    scale = rng.uniform(1e-3, 1e3)
    points = rng.normal(size=(n, k)) * scale
    if same:  # starts that coincide: the floor is the spread
        points[:] = points[0]
    target = rng.normal(size=k) * scale * 3
    floor = 0.05 * scale
    d, i, spread = envelope_distance(target, points, floor)
    want_d, want_i, want_spread = _reference_distance(target, points, floor)
    np.testing.assert_allclose(spread, want_spread, rtol=1e-12)
    assert np.isclose(d, want_d, rtol=1e-12)
    assert i == want_i  # the first of equals, as the loop


def _fan(n_demos=5, seed=0):
    """Reaches fanning out from starts spread along x, in metres."""
    from ndlfd import Demonstration

    rng = np.random.default_rng(seed)
    out = []
    for i in range(n_demos):
        t = np.linspace(0.0, 2.0, 120)
        s = t / 2.0
        x0 = 0.02 * i + rng.normal(0, 0.003)
        P = np.column_stack([x0 + 0.6 * s, 0.25 * np.sin(np.pi * s) + 0.01 * i])
        out.append(Demonstration.from_arrays(t, position=P))
    return out


def _outward(demos, row, k):
    """A point ``k`` spreads past the demonstration farthest along +x.

    By the definition, from the demonstrations (not the model): the spread
    per column is the std of their ``row`` samples, at least SPREAD_FLOOR of
    the position's range over every sample. Every other demonstration's
    sample has a smaller x, so the one farthest along +x is the nearest.
    """
    P = np.array([d.get("position")[row] for d in demos])
    everything = np.concatenate([d.get("position") for d in demos])
    floor = SPREAD_FLOOR * (everything.max() - everything.min())
    spread = np.maximum(P.std(axis=0), floor)
    far = int(np.argmax(P[:, 0]))
    return P[far] + [k * spread[0], 0.0], far, k * spread[0]


@pytest.mark.parametrize("generation", ["blend", "paper"])
@pytest.mark.parametrize("what", ["start", "goal"])
def test_a_far_start_or_goal_is_warned_past_the_threshold(what, generation):
    from ndlfd import KeypointHMM

    demos = _fan()
    model = KeypointHMM(generation=generation).fit(demos)
    t = demos[0].t
    row = 0 if what == "start" else -1
    inside, _, _ = _outward(demos, row, FAR_SPREADS - 0.1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # not a word inside the threshold
        model.generate(t, dense=True, **{what: {"position": inside}})
        if generation == "blend":
            model.sample(t, 2, random_state=0, **{what: {"position": inside}})
    k = FAR_SPREADS + 0.1
    outside, far, metres = _outward(demos, row, k)
    want = (
        f"the {what} of position (x, y) = ({outside[0]:.4g}, {outside[1]:.4g}) is"
        f" {k:.1f} spreads from the nearest demonstration's {what} (demonstration"
        f" {far}, "
    )
    with pytest.warns(ExtrapolationWarning) as got:
        path = model.generate(t, dense=True, **{what: {"position": outside}})
    assert len(got) == 1
    text = str(got[0].message)
    assert text.startswith(want), text
    assert f": {metres:.3g} away in the data's units)" in text
    np.testing.assert_allclose(path.get("position")[row], outside)  # still made
    if generation == "blend":
        with pytest.warns(ExtrapolationWarning, match=re.escape(want)):
            model.sample(t, 2, random_state=0, **{what: {"position": outside}})


def test_coinciding_starts_and_one_demonstration_take_the_floor():
    from ndlfd import Demonstration, KeypointHMM

    t = np.linspace(0.0, 1.0, 80)
    demos = [Demonstration.from_arrays(t, position=np.column_stack(
        [t, a * np.sin(np.pi * t)])) for a in (0.2, 0.3, 0.4)]  # fmt: skip
    everything = np.concatenate([d.get("position") for d in demos])
    floor = SPREAD_FLOOR * (everything.max() - everything.min())  # std is 0
    for fitted in (demos, demos[:1]):
        model = KeypointHMM().fit(fitted)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            model.generate(t, start={"position": [0.0, -2.9 * floor]})
        with pytest.warns(ExtrapolationWarning, match=r" is 3\.1 spreads "):
            model.generate(t, start={"position": [0.0, -3.1 * floor]})


def test_a_far_goal_is_warned_once_when_a_prefix_is_completed():
    # a prefix without the gripper is completed from a first plan (the goal
    # oriented again): one warning per call, not one per plan
    from ndlfd import Demonstration, KeypointHMM

    demos = []
    for i in range(5):
        t = np.linspace(0.0, 2.0, 120)
        s = t / 2.0
        P = np.column_stack([0.6 * s + 0.02 * i, 0.25 * np.sin(np.pi * s)])
        demos.append(Demonstration.from_arrays(t, position=P, gripper=1.0 * (s > 0.5)))
    model = KeypointHMM().fit(demos)
    t = demos[0].t
    prefix = Demonstration.from_arrays(t[:30], position=demos[1].get("position")[:30])
    goal = {"position": [3.0, 0.0]}
    for call in (lambda: model.generate(t, observed=prefix, goal=goal),
                 lambda: model.sample(t, 2, observed=prefix, goal=goal,
                                      random_state=0)):  # fmt: skip
        with pytest.warns(ExtrapolationWarning) as got:
            call()
        assert len(got) == 1
        assert str(got[0].message).startswith("the goal of position (x, y) = (3, 0)")
