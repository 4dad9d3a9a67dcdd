"""Limits on a group's norm: a position's speed, an orientation's rotation rate."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from ndlfd import Demonstration
from ndlfd._errors import ValidationError
from ndlfd._norm_limits import DIRECTIONS, INSCRIBED, QuaternionCurve
from ndlfd.limits import MARGIN, TOLERANCE, check_limits, path_peaks, time_scale


def _pose_path(seed, n=301, duration=2.0):
    """A wavy 3-D position and a rotation about a drifting axis."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, duration, n)
    f = rng.uniform(0.3, 1.2, 3)
    P = rng.uniform(0.05, 0.3, 3) * np.sin(
        2 * np.pi * f * t[:, None] + rng.uniform(0, 6, 3)
    )
    rv = rng.uniform(0.3, 1.5, 3) * np.sin(
        np.pi * rng.uniform(0.2, 0.8, 3) * t[:, None] + rng.uniform(0, 6, 3)
    )
    xyzw = Rotation.from_rotvec(rv).as_quat()
    Q = np.column_stack([xyzw[:, 3], xyzw[:, :3]])
    return Demonstration.from_arrays(t, position=P, orientation=Q)


def _speed(path):
    """The written samples' speed: chord lengths over the steps (independent of
    numpy.gradient)."""
    P = path.get("position")
    return np.linalg.norm(np.diff(P, axis=0), axis=1) / np.diff(path.t)


def _angular(path):
    """Angular velocity per step from the relative rotation of consecutive samples
    (scipy's rotation vectors) and angular acceleration from their differences."""
    Q = path.get("orientation")
    R = Rotation.from_quat(np.column_stack([Q[:, 1:], Q[:, 0]]))
    dt = np.diff(path.t)
    w = (R[:-1].inv() * R[1:]).as_rotvec() / dt[:, None]  # body rates, mid-step
    W = R[:-1].apply(w)  # in the world frame: their differences are alpha
    mid = 0.5 * (path.t[1:] + path.t[:-1])
    alpha = np.diff(W, axis=0) / np.diff(mid)[:, None]
    return np.linalg.norm(w, axis=1), np.linalg.norm(alpha, axis=1)


def _route_gap(scaled, path, group):
    P, S = path.get(group), scaled.get(group)
    d = np.linalg.norm(S[:, None, :] - P[None, :, :], axis=2)
    return float(d.min(axis=1).max())


def test_the_inscribed_polytope_touches_the_unit_ball():
    """Brute force: every vertex of {x : n . x <= INSCRIBED} is within 1, the
    farthest exactly at 1."""
    far = 0.0
    for idx in itertools.combinations(range(len(DIRECTIONS)), 3):
        M = DIRECTIONS[list(idx)]
        if abs(np.linalg.det(M)) < 1e-9:
            continue
        x = np.linalg.solve(M, np.full(3, INSCRIBED))
        if np.all(DIRECTIONS @ x <= INSCRIBED + 1e-12):
            far = max(far, float(np.linalg.norm(x)))
    assert far == pytest.approx(1.0, abs=1e-12)


def test_the_quaternion_curve_has_the_rates_of_a_hand_worked_rotation():
    """q(t) = (cos(t^2/4), 0, sin(t^2/4), 0): about y at t rad/s, t^2/2 turned,
    angular acceleration 1 rad/s^2."""
    t = np.linspace(0.0, 2.0, 401)
    Q = np.column_stack([np.cos(t**2 / 4), 0 * t, np.sin(t**2 / 4), 0 * t])
    c = QuaternionCurve(t, Q)
    s = np.array([0.5, 1.0, 1.5])
    w, b = c.rates(s)
    np.testing.assert_allclose(w, np.column_stack([0 * s, s, 0 * s]), atol=1e-5)
    # angular acceleration along the path at sdot = 1, sddot = 0: b
    np.testing.assert_allclose(b, np.column_stack([0 * s, 0 * s + 1, 0 * s]), atol=1e-4)


def test_a_speed_limit_bounds_the_norm_and_not_each_axis():
    """A diagonal line at 3 /s per axis (5.196 /s speed), speed limited to 1:
    the per-axis limit 1 would leave it at 1.73."""
    t = np.linspace(0.0, 1.0, 201)
    path = Demonstration.from_arrays(t, position=np.column_stack([3 * t, 3 * t, 3 * t]))
    out = time_scale(path, {"position": {"speed": 1.0}})
    assert _speed(out).max() <= 1.0 * (1 + TOLERANCE)
    assert _speed(out).max() >= 1.0 * (1 - 2 * MARGIN)  # time-optimal: reached
    # 5.196 units at 1 /s (plus the ramps)
    assert out.duration >= np.sqrt(27) * (1 - MARGIN)
    np.testing.assert_array_equal(out.X[[0, -1]], path.X[[0, -1]])
    assert np.abs(np.diff(out.X, axis=1)).max() < 1e-12  # still on the diagonal


@settings(max_examples=15, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    v_share=st.floats(0.2, 0.9),
    w_share=st.floats(0.2, 0.9),
    a_share=st.floats(0.2, 0.9),
)
def test_norm_limits_hold_on_the_written_samples_and_keep_the_route(
    seed, v_share, w_share, a_share
):
    path = _pose_path(seed)
    v0, (w0, a0) = _speed(path).max(), _angular(path)
    limits = {
        "position": {"speed": v_share * v0},
        "orientation": {
            "angular_velocity": w_share * w0.max(),
            "angular_acceleration": a_share * a0.max(),
        },
    }
    out = time_scale(path, limits)
    w, a = _angular(out)
    # independent finite differences against the limits; a few per mille for
    # the difference between chords and path_peaks' gradients
    assert _speed(out).max() <= v_share * v0 * 1.005
    assert w.max() <= w_share * w0.max() * 1.005
    assert a.max() <= a_share * a0.max() * 1.02
    assert out.duration >= path.duration
    np.testing.assert_allclose(np.linalg.norm(out.get("orientation"), axis=1), 1.0)
    np.testing.assert_array_equal(out.X[[0, -1]], path.X[[0, -1]])
    # the same route: near the original's samples (within one step of it)
    step = np.linalg.norm(np.diff(path.get("position"), axis=0), axis=1).max()
    assert _route_gap(out, path, "position") <= step
    # and the same rotations, by angle to the nearest original sample
    Q, S = path.get("orientation"), out.get("orientation")
    turn = 2 * np.arccos(np.clip(np.abs(S @ Q.T).max(axis=1), 0, 1))
    assert turn.max() <= w0.max() * (path.t[1] - path.t[0])


def test_a_quaternion_stream_of_either_sign_keeps_its_signs():
    path = _pose_path(4)
    Q = path.get("orientation").copy()
    Q[150:] *= -1.0  # a recording's sign flip: the same rotations
    cols = path.columns_of("orientation")
    X = path.X.copy()
    X[:, cols] = Q
    flipped = Demonstration(path.t, X, path.columns, path.groups)
    lim = {"orientation": {"angular_velocity": 0.3}}
    a, b = time_scale(path, lim), time_scale(flipped, lim)
    np.testing.assert_allclose(np.abs(a.X), np.abs(b.X), atol=1e-12)
    assert _angular(b)[0].max() <= 0.3 * 1.005  # no half turn at the flip


@pytest.mark.parametrize(
    "limits, match",
    [
        ({"orientation": {"speed": 1.0}}, "speed limit is of a position group"),
        ({"position": {"angular_velocity": 1.0}}, "quaternion group"),
        ({"x": {"speed": 1.0}}, "'x' is not one: the path has 'position'"),
        ({"position": {"speed": [1.0, 2.0]}}, "must be one value"),
        ({"orientation": {"angular_acceleration": 0.0}}, "finite and > 0"),
        ({"position": {"spin": 1.0}}, "speed, angular_velocity"),
    ],
)
def test_bad_norm_limits_say_what_was_expected(limits, match):
    path = _pose_path(0, n=11)
    with pytest.raises(ValidationError, match=match):
        time_scale(path, limits)


def test_joints_have_no_speed():
    t = np.linspace(0.0, 1.0, 11)
    d = Demonstration.from_arrays(t, joints=np.column_stack([t, t]))
    with pytest.raises(ValidationError, match="joints are limited one by one"):
        check_limits({"joints": {"speed": 1.0}}, d)


def test_peaks_report_the_norms_on_their_groups_columns():
    path = _pose_path(2)
    peaks = path_peaks(path)
    pos, ori = path.columns_of("position"), path.columns_of("orientation")
    V = np.gradient(path.get("position"), path.t, axis=0, edge_order=2)
    assert peaks["speed"][pos].tolist() == [np.linalg.norm(V, axis=1).max()] * 3
    assert np.all(peaks["speed"][ori] == 0.0)
    # the gradient-based angular velocity agrees with the chord-based one
    assert peaks["angular_velocity"][ori[0]] == pytest.approx(
        _angular(path)[0].max(), rel=0.01
    )
