"""A JointTrajectory played as ros2_control's joint_trajectory_controller plays it.

The controller interpolates between points: a quintic Hermite polynomial
through positions, velocities and accelerations when accelerations are given,
a cubic one through positions and velocities otherwise (joint_trajectory_
controller's interpolation_methods spline). Here each segment's polynomial is
solved from its end conditions (independent of ndlfd's spline), played at
1 kHz and compared with the written positions (their chords), and its
velocity and acceleration with the limits the path was scaled to.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd._trajectory import EASE_SHARE
from ndlfd.demonstration import Demonstration
from ndlfd.io._bagout import joint_trajectory_points
from ndlfd.limits import TOLERANCE, path_peaks, time_scale


def play(t, Q, V, A=None, per_second=1000):
    """Position, velocity, acceleration of the controller's Hermite segments."""
    out_p, out_v, out_a = [], [], []
    for i in range(t.size - 1):
        h = t[i + 1] - t[i]
        p0, p1, v0, v1 = Q[i], Q[i + 1], V[i], V[i + 1]
        if A is None:
            M = np.array([[h**2, h**3], [2 * h, 3 * h**2]])
            c23 = np.linalg.solve(M, np.vstack([p1 - p0 - v0 * h, v1 - v0]))
            c = np.vstack([p0, v0, c23])
        else:
            a0, a1 = A[i], A[i + 1]
            M = np.array([[h**3, h**4, h**5], [3 * h**2, 4 * h**3, 5 * h**4],
                          [6 * h, 12 * h**2, 20 * h**3]])  # fmt: skip
            rhs = np.vstack([p1 - (p0 + v0 * h + a0 / 2 * h**2),
                             v1 - (v0 + a0 * h), a1 - a0])  # fmt: skip
            c = np.vstack([p0, v0, a0 / 2, np.linalg.solve(M, rhs)])
        k = np.arange(c.shape[0])
        u = np.linspace(0.0, h, max(int(np.ceil(h * per_second)), 2) + 1)[:-1]
        out_p.append((u[:, None] ** k) @ c)
        out_v.append((k[1:] * u[:, None] ** (k[1:] - 1)) @ c[1:])
        out_a.append((k[2:] * (k[2:] - 1) * u[:, None] ** (k[2:] - 2)) @ c[2:])
        chord = Q[i] + (Q[i + 1] - Q[i]) * (u / h)[:, None]
        out_p[-1] = out_p[-1] - chord  # off the positions' chord
    return (np.abs(np.vstack(out_p)).max(), np.abs(np.vstack(out_v)).max(axis=0),
            np.abs(np.vstack(out_a)).max(axis=0))  # fmt: skip


def so101_like(seed, rate, seconds=4.0):
    """Five joints and a gripper in degrees, SO-101-like ranges, moving at both ends."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(seconds * rate) + 1) / rate
    f = rng.uniform(0.1, 0.4, 6)
    amp = rng.uniform(10.0, 60.0, 6)
    J = amp * np.sin(2 * np.pi * f * t[:, None] + rng.uniform(0, 6, 6))
    return Demonstration.from_arrays(t, joints=J[:, :5], gripper=J[:, 5:])


@settings(max_examples=20, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    rate=st.sampled_from([30.0, 100.0]),
    v_share=st.floats(0.3, 0.9),
    a_share=st.floats(0.3, 0.9),
    prefix=st.sampled_from([0, 0.2, 0.5]),
    quintic=st.booleans(),
)
def test_the_controller_follows_the_positions_within_the_limits(
    seed, rate, v_share, a_share, prefix, quintic
):
    path = so101_like(seed, rate)
    peaks = path_peaks(path)
    v_lim = v_share * peaks["velocity"]
    a_lim = a_share * peaks["acceleration"]
    limits = {"joints": {"velocity": v_lim[:5], "acceleration": a_lim[:5]},
              "gripper": {"velocity": v_lim[5], "acceleration": a_lim[5]}}  # fmt: skip
    keep = int(prefix * path.n_samples)
    out = time_scale(path, limits, keep=keep)
    sent = out if keep == 0 else out.take(np.arange(keep - 1, out.n_samples))
    _, t, Q, V, A = joint_trajectory_points(sent, units="deg", moving_start=keep > 0)
    off, v, a = play(t, Q, V, A if quintic else None)
    assert np.degrees(off) <= (0.1 if rate == 100.0 else 0.3)
    assert np.all(np.degrees(v) <= v_lim * (1 + TOLERANCE) + 1e-9)
    assert np.all(np.degrees(a) <= a_lim * (1 + TOLERANCE) + 1e-9)
    assert np.all(V[-1] == 0.0) and (keep > 0 or np.all(V[0] == 0.0))
    # the written fields within the limits too, and the positions unchanged
    assert np.all(np.degrees(np.abs(V)).max(axis=0) <= v_lim * (1 + TOLERANCE))
    assert np.all(np.degrees(np.abs(A)).max(axis=0) <= a_lim * (1 + TOLERANCE))
    np.testing.assert_allclose(np.degrees(Q), sent.X, atol=1e-9)


@pytest.mark.parametrize("moving_start", [False, True])
@pytest.mark.parametrize("rate", [30.0, 100.0])
def test_an_unscaled_path_comes_to_rest_in_its_positions(moving_start, rate):
    """Moving at both ends (the generated timing): the positions themselves stop,
    the velocities are theirs, and the easing adds a bounded deceleration."""
    path = so101_like(7, rate)
    _, t, Q, V, A = joint_trajectory_points(
        path, units="deg", moving_start=moving_start
    )
    assert t[-1] > path.duration  # eased: longer
    steps = np.degrees(np.abs(np.diff(Q, axis=0)))
    assert steps[-1].max() <= 0.01 * steps.max()  # the last step: at rest
    if not moving_start:
        assert steps[0].max() <= 0.01 * steps.max()
    else:
        np.testing.assert_allclose(np.degrees(Q[:3]), path.X[:3], atol=1e-9)
        assert np.abs(V[0]).min() > 0.0
    for quintic in (True, False):
        off, v, a = play(t, Q, V, A if quintic else None)
        assert np.degrees(off) <= (0.1 if rate == 100.0 else 0.3)
        own = path_peaks(path)
        assert np.all(np.degrees(v) <= own["velocity"] * 1.01)
        # the path's own acceleration plus the easing's: at most the larger of
        # its own peak and its top speed stopped in EASE_SHARE of its duration
        ease = np.maximum(
            own["acceleration"], 1.875 * own["velocity"] / (EASE_SHARE * path.duration)
        )
        assert np.all(np.degrees(a) <= (own["acceleration"] + ease) * 1.05)


def test_the_old_fade_left_the_controller_off_its_positions():
    """The replaced output: numpy.gradient faded over 5 % under moving
    positions. Played the same way it peaks far above the positions' own
    acceleration at the ends (what the new output avoids, above)."""
    path = so101_like(7, 30.0)
    Q = np.radians(path.X)
    t = path.t
    x = np.clip(np.minimum(t, t[-1] - t) / (0.05 * t[-1]), 0, 1)
    V = np.gradient(Q, t, axis=0) * (x**3 * (10 - 15 * x + 6 * x * x))[:, None]
    V[[0, -1]] = 0.0
    A = np.gradient(V, t, axis=0)
    A[[0, -1]] = 0.0
    a = play(t, Q, V, A)[2]
    assert np.all(np.degrees(a) > 2.0 * path_peaks(path)["acceleration"])
