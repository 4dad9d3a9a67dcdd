"""Rests are held (issue 39): where the demonstrations hold still, so does the path.

A grasp set as a recorder writes it (50 Hz with stamp jitter, 0.5 mm or
0.05 deg noise, each phase's duration +-15 %): the hand comes down onto an
object, holds 0.6 s while the gripper closes (a continuous width), lifts and
carries it away. A via point at the object at the start of the hold used to
be reached and then left: its offset faded while every demonstration held
still, and the blend's clock read the via point anywhere in the rest (the
noise's closest pass) or on the approach above an object off the
demonstrations' places, so the path went on down after it.
"""

import functools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd import Demonstration
from ndlfd.learner import KeypointHMM, minimum_jerk
from ndlfd.learner._conditioning import pin
from ndlfd.learner._rests import path_rests, rest_clock, rest_windows
from ndlfd.learner._via import apply_via

RATE = 50.0
HOLD = 0.6
HOME = np.array([0.30, 0.0, 0.30])
PLACE = np.array([0.30, 0.30, 0.10])
#: Nominal durations (s): above the object, down, the hold, lift, carry, settle.
PHASES = (1.2, 0.6, HOLD, 0.6, 1.2, 0.3)
#: A planar arm in the x-z plane: shoulder, elbow, and a wrist that keeps the
#: hand pointing down (m).
LINKS = (0.35, 0.30, 0.10)


def _hand(obj, home, durations, t):
    """The hand's minimum-jerk pieces through the way points; the hold's times."""
    way = np.array(
        [home, obj + [0, 0, 0.08], obj, obj, obj + [0, 0, 0.1], PLACE, PLACE]
    )
    knots = np.concatenate([[0.0], np.cumsum(durations)])
    i = np.clip(np.searchsorted(knots, t, side="right") - 1, 0, len(durations) - 1)
    u = minimum_jerk((t - knots[i]) / (knots[i + 1] - knots[i]))
    return way[i] + (way[i + 1] - way[i]) * u[:, None], knots[2], knots[3]


def _recording(rng, obj, jitter=0.15):
    """Time stamps, hand positions (noise-free), gripper width (m), the hold."""
    dur = np.array(PHASES) * rng.uniform(1 - jitter, 1 + jitter, len(PHASES))
    t = np.arange(0.0, dur.sum(), 1.0 / RATE)
    t[1:] += rng.normal(0.0, 0.002, t.size - 1)  # a recorder's stamps
    t = np.sort(t)
    home = HOME + rng.normal(0.0, 0.005, 3)
    P, g0, g1 = _hand(obj, home, dur, t)
    width = 0.08 - 0.06 * minimum_jerk((t - g0) / (0.66 * (g1 - g0)))
    return t, P, width + rng.normal(0.0, 2e-4, t.size), (g0, g1)


def fk(Q):
    """The planar arm's hand (x, z) for joint angles (rad), one row each."""
    l1, l2, l3 = LINKS
    a, b = Q[:, 0], Q[:, 0] + Q[:, 1]
    c = b + Q[:, 2]
    x = l1 * np.cos(a) + l2 * np.cos(b) + l3 * np.cos(c)
    z = l1 * np.sin(a) + l2 * np.sin(b) + l3 * np.sin(c)
    return np.column_stack([x, z])


def ik(P):
    """Joint angles putting the hand at (x, z), elbow up, the hand down."""
    l1, l2, l3 = LINKS
    wx, wz = P[:, 0], P[:, 1] + l3
    c2 = (wx**2 + wz**2 - l1**2 - l2**2) / (2.0 * l1 * l2)
    q2 = -np.arccos(np.clip(c2, -1.0, 1.0))
    q1 = np.arctan2(wz, wx) - np.arctan2(l2 * np.sin(q2), l1 + l2 * np.cos(q2))
    return np.column_stack([q1, q2, -np.pi / 2 - q1 - q2])


def test_the_arm_is_its_own_inverse():
    P = np.array([[0.5, 0.02], [0.39, -0.03], [0.61, 0.1], [0.3, 0.3]])
    np.testing.assert_allclose(fk(ik(P)), P, atol=1e-12)
    np.testing.assert_allclose(ik(P).sum(axis=1), -np.pi / 2)  # pointing down


@functools.cache
def cartesian_set(n=8, seed=0):
    """Objects within 5 cm of (0.5, 0, 0.02) in x, y and 2.5 cm in z."""
    rng = np.random.default_rng(seed)
    demos = []
    for _ in range(n):
        obj = np.array([0.5, 0.0, 0.02]) + rng.uniform(-1, 1, 3) * [0.05, 0.05, 0.025]
        t, P, width, _ = _recording(rng, obj)
        P = P + rng.normal(0.0, 5e-4, P.shape)
        demos.append(Demonstration.from_arrays(t, position=P, gripper=width))
    return demos, KeypointHMM().fit(demos)


@functools.cache
def joint_set(n=8, seed=0):
    """The planar arm's joints (rad): objects within 5 cm in x, 2.5 cm in z."""
    rng = np.random.default_rng(seed)
    demos = []
    for _ in range(n):
        obj = np.array([0.5, 0.0, 0.02]) + rng.uniform(-1, 1, 3) * [0.05, 0.0, 0.025]
        t, P, width, _ = _recording(rng, obj)
        Q = ik(P[:, [0, 2]]) + rng.normal(0.0, np.radians(0.05), (t.size, 3))
        demos.append(Demonstration.from_arrays(t, joints=Q, gripper=width))
    return demos, KeypointHMM().fit(demos)


#: Objects up to 6 cm outside the demonstrations' places (x, y, z in m).
OBJECTS = (
    (0.50, 0.00, 0.02),
    (0.61, 0.00, 0.02),
    (0.39, -0.06, 0.00),
    (0.50, 0.11, 0.02),
    (0.60, 0.10, 0.05),
    (0.44, 0.08, -0.03),
)


def _plans(n=4, seed=7):
    """Timings of new executions (as recorded), their hold's first time stamp
    and the rows of the next 0.5 s (the demonstrations hold 0.51 to 0.69 s)."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        t, _, _, (g0, _) = _recording(rng, np.array([0.5, 0.0, 0.02]))
        tv = t[np.argmin(np.abs(t - g0))]
        out.append((t, tv, (t >= tv) & (t <= tv + 0.5)))
    return out


def _held(model, space, plans):
    """Drift over the next 0.5 s and dip below the object (m), every path."""
    drift, dip = [], []
    for obj in map(np.array, OBJECTS):
        if space == "joints":
            at = obj[[0, 2]]
            via = {"joints": ik(at[None])[0]}
            off = {"joints": ik(HOME[None, [0, 2]])[0] + 0.05}
        else:
            at, via = obj, {"position": obj}
            off = {"position": HOME + [0.03, -0.04, 0.0]}
        for t, tv, hold in plans:
            for start in (None, off):
                path = model.generate(t, dense=True, start=start, via=[(tv, via)])
                H = fk(path.get("joints")) if space == "joints" else path.get(space)
                np.testing.assert_allclose(H[t == tv][0], at, atol=1e-9)
                drift.append(np.linalg.norm(H[hold] - at, axis=1).max())
                dip.append(at[-1] - H[:, -1].min())
    return np.array(drift), np.array(dip)


@pytest.mark.filterwarnings("ignore:time stamps are jittery")
@pytest.mark.parametrize("seed", [0, 10, 34])
def test_a_cartesian_grasp_is_held_where_the_via_point_puts_it(seed):
    # seeds 10 and 34: sets whose hold the clock could not reach in time
    # (before: largest 26.3 and 19.5 mm, dips as deep; now 0.8 and 1.6)
    _, model = cartesian_set(seed=seed)
    drift, dip = _held(model, "position", _plans(seed=7 if seed == 0 else 1000 + seed))
    # before: median 7.0 mm, up to 36.6 (the hand lifted early or the
    # offset faded away), dips up to 12.5 mm; then (seed 0) median 0.8, at
    # most 0.9; now 0.8 and 1.0, and over 40 sets (benchmarks/probe_rests.py)
    # median 0.6, at most 1.6, dips at most 1.2 (the demonstrations' noise:
    # 0.5 mm)
    assert np.median(drift) <= 0.0013, np.median(drift)
    assert max(drift) <= 0.0025, (np.median(drift), max(drift))
    assert max(dip) <= 0.0015, max(dip)


@pytest.mark.filterwarnings("ignore:time stamps are jittery")
@pytest.mark.parametrize("seed", [0, 27, 30])
def test_a_joint_space_grasp_is_held_where_the_via_point_puts_it(seed):
    # a joint via point warps the blend's clock to the hold's start and
    # conditions the blend as a position does (._via.place_groups); the
    # templates' holds are aligned in the blend (._rests.hold_knots): before,
    # the blend's hold was theirs smeared (seed 27: it lifted after 0.36 s)
    _, model = joint_set(seed=seed)
    drift, dip = _held(model, "joints", _plans(seed=7 if seed == 0 else 1000 + seed))
    # before: median 3.1 mm, up to 6.0, dips up to 2.1 (seed 0), then 0.9
    # and 4.9; seeds 27 and 30 up to 19.8 and 41.0, dips as deep; over 40
    # sets median 1.3, up to 41.0. Now 1.2, 0.6, 1.2 on these, and over 40
    # sets median 0.6, at most 2.1, dips at most 1.6
    assert np.median(drift) <= 0.0015, np.median(drift)
    assert max(drift) <= 0.003, (np.median(drift), max(drift))
    assert max(dip) <= 0.002, max(dip)


@settings(max_examples=50, deadline=None, derandomize=True)
@given(
    cuts=st.lists(st.floats(0.02, 0.98), min_size=2, max_size=6, unique=True),
    n=st.integers(100, 400),
)
def test_rests_are_found_where_a_path_holds_still(cuts, n):
    # moves (a half sine of speed each) and holds between them at cut pairs
    cuts = sorted(cuts)[: 2 * (len(cuts) // 2)]
    pairs = []
    for a, b in zip(cuts[::2], cuts[1::2], strict=True):
        if b - a > 0.05 and a - (pairs[-1][1] if pairs else 0.0) > 0.1:
            pairs.append((a, b))
    if pairs and pairs[-1][1] > 0.9:
        pairs.pop()
    tq = np.linspace(0.0, 1.0, n)
    mid = (tq[1:] + tq[:-1]) / 2
    edges = [0.0, *[c for p in pairs for c in p], 1.0]
    speed = np.zeros(n - 1)
    for a, b in zip(edges[::2], edges[1::2], strict=True):  # the moves
        inside = (mid > a) & (mid < b)
        speed[inside] = np.sin(np.pi * (mid[inside] - a) / (b - a))
    x = np.concatenate([[0.0], np.cumsum(speed * np.diff(tq))])
    found = rest_windows(x[:, None], tq)
    assert len(found) == len(pairs)
    for (a, b), (fa, fb) in zip(pairs, found, strict=True):
        # slow (under a fifth of the typical speed) a little before and after
        assert a - 0.1 <= fa <= a + 0.01 and b - 0.01 <= fb <= b + 0.1


@settings(max_examples=50, deadline=None, derandomize=True)
@given(a=st.floats(0.0, 0.5), width=st.floats(0.0, 0.5), at=st.floats(0.0, 1.0))
def test_the_rest_clock_is_the_time_spent_moving(a, width, at):
    # brute force: the integral of the pace (REST_PACE in the rest, 1 else)
    from ndlfd.learner._rests import REST_PACE

    b = a + width
    s = np.linspace(0.0, at, 20001)
    pace = np.where((s > a) & (s < b), REST_PACE, 1.0)
    ref = float(np.sum((pace[1:] + pace[:-1]) / 2 * np.diff(s)))
    got = float(rest_clock(np.array([at]), np.array([[a, b]]))[0])
    assert got == pytest.approx(ref, abs=1e-4)


def test_a_via_offset_holds_over_the_rest_it_starts():
    # a path at rest from 0.4 to 0.6: the offset of a via point at 0.4 is
    # all there at 0.4 and still at 0.6 (by hand: the clock moves 2e-4 there)
    tq = np.linspace(0.0, 1.0, 101)
    x = np.where(tq < 0.4, tq, np.where(tq < 0.6, 0.4, tq - 0.2))
    X = np.column_stack([x, np.zeros_like(x)])
    rests = path_rests(X, tq, ("position", "position"))
    assert rests.shape == (1, 2) and abs(rests[0, 0] - 0.4) <= 0.02
    tv = float(rests[0, 0])  # the moving average blurs its edge by a row
    out = apply_via(X.copy(), tq, [(tv, {"position": np.array([0.4, 1.0])})],
                    ("position", "position"), tq.size)  # fmt: skip
    held = (tq >= tv) & (tq <= rests[0, 1])
    np.testing.assert_allclose(out[held, 1], 1.0, atol=1e-6)
    np.testing.assert_allclose(out[held, 0], 0.4, atol=1e-12)
    assert out[0, 1] == 0.0 and out[-1, 1] == 0.0  # the ends stay


def test_a_start_offset_is_not_faded_across_a_joint_space_rest():
    # a joint path has no position to find its contact by: the start's
    # offset fades over the whole motion, on progress, and holds in the rest
    tq = np.linspace(0.0, 1.0, 201)
    x = np.where(tq < 0.4, tq, np.where(tq < 0.6, 0.4, tq - 0.2))
    X = np.column_stack([x, x + 0.001 * np.sin(400 * tq)])  # noise at rest
    out = pin(X, tq, {"joints": np.array([0.5, 0.5])}, None, ("joints", "joints"))
    held = (tq >= 0.42) & (tq <= 0.58)
    shift = out[held] - X[held]
    assert np.ptp(shift, axis=0).max() <= 1e-12
    assert shift.max() > 0.05  # part of the offset is still there


@settings(max_examples=30, deadline=None, derandomize=True)
@given(
    starts=st.lists(st.floats(0.35, 0.45), min_size=3, max_size=5),
    length=st.floats(0.12, 0.2),
    middle=st.floats(0.2, 0.8),
)
def test_a_conditioned_blend_holds_where_its_templates_do(starts, length, middle):
    # templates that move, hold still (both columns) from their own start
    # for `length`, and move on, warped linearly between the ends and a knot
    # anywhere: unconditioned their blend creeps where they hold at
    # different times; conditioned (on both columns) it holds still from
    # their mean start to their mean end, as each does (the holds overlap:
    # starts at most 0.1 apart)
    from ndlfd.learner._blend import WARP_SMOOTH, blend, skeleton_times

    tau = np.linspace(0.0, 1.0, 401)
    U, index = [], []
    for a in starts:
        s = np.clip(tau - np.clip(tau - a, 0.0, length), 0.0, None)  # time moving
        s = s / s[-1]
        U.append(np.column_stack([np.sin(2.5 * s), s**2]))
        index.append(np.array([0, round(middle * 400), 400]))
    w = np.ones(len(starts))
    knots = skeleton_times([tau] * len(starts), index, w / w.sum())
    rows = np.linspace(0.0, 1.0, 1001)
    observed = [(500, [0, 1], np.array([np.sin(2.5 * 0.5), 0.25]))]
    got = blend(U, [tau] * len(starts), index, w, knots, rows, observed=observed)
    hold = (np.mean(starts), np.mean(starts) + length)  # the found rests are
    inside = (rows > hold[0] + WARP_SMOOTH + 0.01) & (
        rows < hold[1] - WARP_SMOOTH - 0.01
    )
    assert np.ptp(got[inside], axis=0).max() <= 1e-4  # REST_PACE: 1e-3 of a pace
    plain = blend(U, [tau] * len(starts), index, w, knots, rows)
    if np.ptp(starts) > 0.05:  # the templates' holds apart: the plain blend creeps
        assert np.ptp(plain[inside], axis=0).max() > 1e-3
