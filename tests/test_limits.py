"""Peaks and time-scaling to a robot's limits (ndlfd.limits, TOPP-RA)."""

import numpy as np
import pytest
import toppra
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd import Demonstration, KeypointHMM, synth
from ndlfd._errors import ValidationError
from ndlfd.limits import (
    MARGIN,
    TOLERANCE,
    LimitError,
    check_limits,
    path_peaks,
    time_scale,
)


def _line(speed=3.0, n=201, duration=1.0):
    t = np.linspace(0.0, duration, n)
    P = np.column_stack([speed * t, 0.0 * t])
    return Demonstration.from_arrays(t, position=P)


def _within(path, limits):
    peaks, lim = path_peaks(path), check_limits(limits, path)
    return all(np.all(peaks[k] <= lim[k] * (1 + TOLERANCE)) for k in lim)


def _off_path(scaled, path, cols):
    """Largest distance of the scaled samples from the original polyline (dense)."""
    P, Q = path.X[:, cols], scaled.X[:, cols]
    d = np.linalg.norm(Q[:, None, :] - P[None, :, :], axis=2)
    return float(d.min(axis=1).max())


def test_a_straight_line_takes_the_trapezoid_a_hand_computes():
    """3 units at most 1.5 /s and 10 /s^2, from rest to rest: 3/1.5 + 1.5/10 s."""
    path = _line()
    limits = {"position": {"velocity": 1.5, "acceleration": 10.0}}
    out = time_scale(path, limits)
    # aimed MARGIN below the limits, on a grid of the path's step (0.005 s)
    v, a = 1.5 * (1 - MARGIN), 10.0 * (1 - MARGIN)
    assert out.duration == pytest.approx(3 / v + v / a, abs=0.005 + 1e-9)
    assert _within(out, limits)
    assert out.X[0].tolist() == [0.0, 0.0] and out.X[-1].tolist() == [3.0, 0.0]
    assert np.all(np.diff(out.X[:, 0]) >= -1e-12)  # never backwards
    assert np.abs(out.X[:, 1]).max() == 0.0  # on the line
    # the velocity limit is reached (time-optimal, not merely slower)
    assert path_peaks(out)["velocity"][0] >= (1 - 2 * MARGIN) * 1.5


def test_a_path_within_its_limits_is_returned_as_it_is():
    path = _line(speed=1.0)
    assert time_scale(path, {"position": {"velocity": 2.0}}) is path


def test_the_stamps_are_k_over_the_rate():
    out = time_scale(_line(), {"position": {"velocity": 1.0}}, rate=50.0)
    assert np.array_equal(out.t, np.arange(out.n_samples) / 50.0)


def _waves(seed, n_cols, n=300):
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 4.0, n)
    f = rng.uniform(0.2, 1.0, n_cols)
    a = rng.uniform(10.0, 90.0, n_cols)
    J = a * np.sin(2 * np.pi * f * t[:, None] + rng.uniform(0, 6, n_cols))
    return Demonstration.from_arrays(t, joints=J)


@settings(max_examples=25, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    n_cols=st.integers(1, 6),
    v_share=st.floats(0.2, 1.5),
    a_share=st.floats(0.2, 1.5),
)
def test_time_scaled_paths_keep_their_route_and_meet_the_limits(
    seed, n_cols, v_share, a_share
):
    path = _waves(seed, n_cols)
    peaks = path_peaks(path)
    limits = {
        "joints": {
            "velocity": v_share * peaks["velocity"],
            "acceleration": a_share * peaks["acceleration"],
        }
    }
    out = time_scale(path, limits)
    assert _within(out, limits)
    assert out.duration >= path.duration * (1 - 1e-9)  # never faster
    assert np.array_equal(out.X[[0, -1]], path.X[[0, -1]])
    # on the same route: every sample near the original (dense) polyline
    step = np.abs(np.diff(path.X, axis=0)).max()
    assert _off_path(out, path, slice(None)) <= step


def test_the_peaks_agree_with_toppras_own_trajectory():
    """TOPP-RA's spline derivatives and the samples' finite differences agree."""
    path = _waves(3, 3)
    lim = {"joints": {"velocity": 40.0, "acceleration": 120.0}}
    out = time_scale(path, lim)
    t = path.t - path.t[0]
    spl = toppra.SplineInterpolator(t, path.X)
    import toppra.algorithm as algo
    import toppra.constraint as con

    v = np.full(3, 40.0)
    a = np.full(3, 120.0)
    inst = algo.TOPPRA(
        [
            con.JointVelocityConstraint(np.column_stack([-v, v])),
            con.JointAccelerationConstraint(np.column_stack([-a, a])),
        ],
        spl,
        parametrizer="ParametrizeConstAccel",
    )
    traj = inst.compute_trajectory(0.0, 0.0)
    ts = np.linspace(0.0, traj.duration, 4000)
    theirs = np.abs(traj(ts, 1)).max(axis=0)
    ours = path_peaks(out)["velocity"]
    # both time-optimal under the same limits, ours also for the curve a
    # controller follows through the samples (joints: a JointTrajectory's
    # cubic spline, whose acceleration cannot jump as TOPP-RA's does): up to
    # 8 % lower peak velocities, at most 8 % longer (measured 7.6 %, 7 %)
    assert np.all(ours <= theirs * 1.001) and np.all(ours >= theirs * 0.92)
    assert traj.duration <= out.duration <= traj.duration * 1.08


def test_generate_with_limits_on_joint_and_cartesian_data():
    demos = synth.obstacle(7, 5)
    model = KeypointHMM().fit(demos)
    t = np.linspace(0.0, 5.0, 500)
    path = model.generate(t, dense=True)
    peaks = path_peaks(path)
    top = peaks["velocity"][path.columns_of("position")].max()
    lim = {"position": {"velocity": 0.6 * top}}
    out = model.generate(t, dense=True, limits=lim)
    assert _within(out, lim) and out.duration > path.duration
    pos = path.columns_of("position")
    assert np.array_equal(out.X[[0, -1]][:, pos], path.X[[0, -1]][:, pos])
    # the velocity group is the new path's derivative again
    V = np.gradient(out.get("position"), out.t, axis=0, edge_order=2)
    assert np.allclose(out.get("velocity"), V)
    with pytest.raises(ValidationError, match="dense=True"):
        model.generate(t, limits=lim)


def test_sample_time_scales_each_drawn_path():
    demos = synth.obstacle(7, 5)
    model = KeypointHMM().fit(demos)
    t = np.linspace(0.0, 5.0, 400)
    free = model.sample(t, 3, random_state=1)
    top = max(path_peaks(p)["velocity"][p.columns_of("position")].max() for p in free)
    lim = {"position": {"velocity": 0.5 * top}}
    drawn = model.sample(t, 3, random_state=1, limits=lim)
    for a, b in zip(free, drawn, strict=True):
        assert _within(b, lim) and b.duration > a.duration
        # the same draw, slowed: the same route from the same start to the end
        pos = a.columns_of("position")
        assert np.array_equal(b.X[[0, -1]][:, pos], a.X[[0, -1]][:, pos])
    with pytest.raises(ValidationError, match="dense=True"):
        model.sample(t, 2, dense=False, limits=lim)


def test_orientation_and_a_gripper_are_carried_along():
    t = np.linspace(0.0, 2.0, 201)
    ang = np.pi / 2 * t / 2
    Q = np.column_stack([np.cos(ang / 2), 0 * t, 0 * t, np.sin(ang / 2)])
    g = (t > 1.0).astype(float)
    path = Demonstration.from_arrays(
        t, position=np.column_stack([t, t]), orientation=Q, gripper=g
    )
    out = time_scale(path, {"position": {"velocity": 0.25}})
    assert np.allclose(np.linalg.norm(out.get("orientation"), axis=1), 1.0)
    assert set(np.unique(out.get("gripper"))) == {0.0, 1.0}
    # the gripper switches where the hand is at x = 1, as before
    x = out.get("position")[:, 0]
    first = int(np.argmax(out.get("gripper")[:, 0] > 0))
    assert x[first - 1] <= 1.0 + 0.01 and x[first] >= 1.0 - 0.01


@pytest.mark.parametrize(
    "limits, match",
    [
        ({"position": {"spin": 1.0}}, "unknown limit 'spin'"),
        ({"joints": {"velocity": 1.0}}, "no group or column 'joints'"),
        ({"position": {"velocity": -1.0}}, "finite and > 0"),
        ({"position": {"velocity": [1.0, 2.0, 3.0]}}, "one value or 2"),
        ({"x": {"velocity": [1.0, 2.0]}}, "one value or 1"),
        ({"position": {"velocity": "fast"}}, "must be numbers"),
        ({"orientation": {"velocity": 1.0}}, "quaternions"),
        ({"qw": {"velocity": 1.0}}, "quaternions"),
        ({"position": 1.0}, "must map velocity, acceleration, jerk"),
        ({"orientation": {"velocity": 1.0}}, "angular_velocity"),
        ([("velocity", 1.0)], "must be a mapping"),
    ],
)
def test_bad_limits_say_what_was_expected(limits, match):
    t = np.linspace(0.0, 1.0, 5)
    d = Demonstration.from_arrays(
        t, position=np.column_stack([t, t]), orientation=np.tile([1.0, 0, 0, 0], (5, 1))
    )
    with pytest.raises(ValidationError, match=match):
        time_scale(d, limits)


def test_a_limit_error_is_a_validation_error():
    assert issubclass(LimitError, ValidationError)


def test_a_column_is_limited_by_its_name_and_the_smaller_limit_wins():
    t = np.linspace(0.0, 1.0, 201)
    d = Demonstration.from_arrays(t, position=np.column_stack([3 * t, 2 * t]))
    lim = check_limits({"position": {"velocity": 5.0}, "y": {"velocity": 1.0}}, d)
    assert lim["velocity"].tolist() == [5.0, 1.0]
    out = time_scale(d, {"position": {"velocity": 5.0}, "y": {"velocity": 1.0}})
    v = path_peaks(out)["velocity"]
    assert v[1] <= 1.0 * (1 + TOLERANCE) and v[0] <= 3.0 * (1 + TOLERANCE)


@pytest.mark.parametrize("share", [0.5, 0.1])
def test_a_jerk_limit_is_met_by_slowing_down(share):
    path = _waves(5, 3)
    jerk = path_peaks(path)["jerk"]
    lim = {"joints": {"jerk": share * jerk}}
    out = time_scale(path, lim)
    assert _within(out, lim)
    assert np.array_equal(out.X[[0, -1]], path.X[[0, -1]])
    # a uniform slow-down by k divides jerk by k**2 to k**3: at least this slow
    assert out.duration >= path.duration * share ** (-1 / 3) * (1 - 0.02)


def test_an_executed_prefix_is_kept_and_the_rest_leaves_at_its_speed():
    """A line at 1 /s speeding up smoothly to 3 /s from 0.5 s on; limits 1.5 /s
    and 20 /s^2; the first 80 samples (0.395 s) executed: kept with their
    stamps, and the rest leaves at 1 /s (the path's own speed there, within
    the limits), not from rest, and meets the limits."""
    t = np.linspace(0.0, 1.0, 201)
    s = np.clip((t - 0.5) / 0.3, 0.0, 1.0)
    speed = 1.0 + 2.0 * s**3 * (10.0 - 15.0 * s + 6.0 * s * s)
    x = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(t))])
    path = Demonstration.from_arrays(t, position=np.column_stack([x, 0 * t]))
    limits = {"position": {"velocity": 1.5, "acceleration": 20.0}}
    out = time_scale(path, limits, keep=80)
    np.testing.assert_array_equal(out.t[:80], path.t[:80])
    np.testing.assert_array_equal(out.X[:80], path.X[:80])
    rest = out.take(np.arange(79, out.n_samples))
    assert _within(rest, limits)
    v = np.diff(out.X[:, 0]) / np.diff(out.t)
    assert v[79] == pytest.approx(1.0, abs=0.01)  # no jump at the junction
    assert v.max() >= 1.5 * (1 - 2 * MARGIN)  # time-optimal: up to the limit
    assert out.X[-1].tolist() == path.X[-1].tolist()
    # from rest without keep
    v0 = np.diff(time_scale(path, limits).X[:, 0]) / 0.005
    assert v0[0] < 0.1


@pytest.mark.parametrize("keep", [1, 40])
def test_a_prefix_faster_than_the_limits_hands_over_at_the_limit(keep):
    path = _line(speed=3.0)
    limits = {"position": {"velocity": 1.5, "acceleration": 10.0}}
    out = time_scale(path, limits, keep=keep)
    np.testing.assert_array_equal(out.X[:keep], path.X[:keep])
    np.testing.assert_array_equal(out.t[:keep], path.t[:keep])
    speed = np.diff(out.X[:, 0]) / np.diff(out.t)
    assert speed[keep - 1] == pytest.approx(1.5 * (1 - MARGIN), rel=0.01)
    assert _within(out.take(np.arange(keep - 1, out.n_samples)), limits)


@pytest.mark.parametrize("keep", [-1, 200, 1.5, True])
def test_keep_out_of_range_says_so(keep):
    with pytest.raises(ValidationError, match="keep must"):
        time_scale(_line(), {"position": {"velocity": 1.0}}, keep=keep)


def test_generate_with_limits_keeps_the_observed_prefix():
    demos = synth.obstacle(7, 5)
    model = KeypointHMM().fit(demos)
    t = np.linspace(0.0, 5.0, 400)
    plain = model.generate(t, dense=True)
    top = path_peaks(plain)["velocity"][plain.columns_of("position")].max()
    lim = {"position": {"velocity": 0.6 * top}}
    prefix = plain.take(np.arange(120)).select("position")
    out = model.generate(t, dense=True, observed=prefix, limits=lim)
    np.testing.assert_array_equal(out.t[:120], t[:120])
    np.testing.assert_array_equal(out.get("position")[:120], prefix.X)
    assert _within(out.take(np.arange(119, out.n_samples)), lim)
    for drawn in model.sample(t, 2, observed=prefix, limits=lim, random_state=0):
        np.testing.assert_array_equal(drawn.get("position")[:120], prefix.X)
