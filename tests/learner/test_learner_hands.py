"""Several hands (pose groups) and task frames for any model (issue 43).

Known answers from tasks built so (``hands_data``): the right hand rigid in
an object's frame at the grasp, then in the world at a fixed handover; the
left hand in the world throughout; a planar 2-link arm whose joints reach a
target, the target as the frame of a joint-space model.
"""

import warnings

import numpy as np
import pytest
from scipy.interpolate import interp1d

from hands_data import (
    GRASP,
    HANDOVER,
    forward,
    object_pose,
    planar_arm,
    planar_target,
    two_hands,
)
from ndlfd import Demonstration, KeypointHMM, NdlfdWarning, ValidationError


@pytest.fixture(scope="module")
def handover():
    demos, _ = two_hands(12, seed=1, flip_signs=True)
    return demos, KeypointHMM().fit(demos)


def _continuous_unit(Q):
    norms = np.linalg.norm(Q, axis=1)
    dots = np.sum(Q[1:] * Q[:-1], axis=1)
    return float(np.max(np.abs(norms - 1.0))), float(dots.min())


def test_a_second_hands_quaternions_are_continuous_and_unit(handover):
    demos, model = handover
    raw = two_hands(1, seed=1, flip_signs=True)[0][0]
    for g in ("left_orientation", "right_orientation"):
        off, worst = _continuous_unit(raw.get(g))
        assert off < 1e-12 and worst > 0.99  # made continuous on construction
    o, _ = object_pose(np.random.default_rng(3), spread=0.1)
    path = model.generate(demos[0].t, dense=True, frames={"object": o})
    for g in ("left_orientation", "right_orientation"):
        off, worst = _continuous_unit(path.get(g))
        assert off < 1e-12, g
        assert worst > 0.99, g  # no sign flip between two rows (0.3 deg apart)


def test_each_hand_follows_its_frame_in_each_phase(handover):
    """Right: on the new object, then at the handover; left: in the world."""
    demos, model = handover
    left = np.mean([d.get("left_position") for d in demos], axis=0)
    curve = interp1d(np.linspace(0, 1, len(left)), left, axis=0)(
        np.linspace(0, 1, 20000)
    )
    rng = np.random.default_rng(7)
    for _ in range(4):
        o, _ = object_pose(rng, spread=0.1)  # up to 2 cm outside the shown
        path = model.generate(demos[0].t, dense=True, frames={"object": o})
        R, L = path.get("right_position"), path.get("left_position")
        reach = np.linalg.norm(R - (o + GRASP), axis=1)
        assert reach.min() < 0.002  # the noise: 0.5 mm per sample
        held = reach < 0.005
        assert held.sum() >= 20  # held there (0.15 of the motion: 30 rows)
        assert np.linalg.norm(R[-1] - HANDOVER) < 0.002
        off_curve = np.sqrt(((L[:, None] - curve[None]) ** 2).sum(-1)).min(axis=1)
        assert off_curve.max() < 0.002  # the left hand where it always went
        # the world did not move the left hand with the object: its end is fixed
        assert np.linalg.norm(L[-1] - left[-1]) < 0.002


def test_a_named_hand_needs_three_position_columns():
    t = np.linspace(0, 1, 5)
    with pytest.raises(ValidationError, match="'left_position' must have 3 columns"):
        Demonstration.from_arrays(t, left_position=np.zeros((5, 2)))
    with pytest.raises(ValidationError, match="left_orientation must have shape"):
        Demonstration.from_arrays(
            t, left_position=np.zeros((5, 3)), left_orientation=np.ones((5, 3))
        )


def test_a_joint_space_model_reaches_a_moved_target():
    """Within 1 % of the reach (1 m) at the end, for targets it was not shown."""
    demos, _ = planar_arm(30, seed=2)
    model = KeypointHMM().fit(demos)
    rng = np.random.default_rng(11)
    for _ in range(8):
        p = planar_target(rng)
        q = model.generate(demos[0].t, dense=True, frames={"target": p}).get("joints")
        assert np.linalg.norm(forward(q[-1]) - p) < 0.01
        assert np.linalg.norm(q[0] - demos[0].get("joints")[0]) < 0.02  # from home


def test_a_joint_space_model_without_a_relation_says_so():
    demos, _ = planar_arm(6, seed=2)
    same = [d.with_frames({"target": [0.5, 0.3]}) for d in demos]
    model = KeypointHMM().fit(same)
    with pytest.warns(NdlfdWarning, match="learned no relation"):
        model.generate(same[0].t, frames={"target": [0.6, 0.3]})


def test_a_frame_of_a_joint_space_model_is_checked():
    demos, _ = planar_arm(6, seed=2)
    model = KeypointHMM().fit(demos)
    with pytest.raises(ValidationError, match=r"frames\['target'\] must hold 2"):
        model.generate(demos[0].t, frames={"target": [0.6, 0.3, 0.1]})
    with pytest.raises(ValidationError, match="unknown task frame 'goal'"):
        model.generate(demos[0].t, frames={"goal": [0.6, 0.3]})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model.generate(demos[0].t, frames={"target": [0.6, 0.3]})


def test_every_hand_is_limited_as_a_pose(handover):
    """Angular limits on a named hand's rotation, a speed limit on another's."""
    pytest.importorskip("toppra")
    from ndlfd.limits import TOLERANCE, path_peaks, time_scale

    demos, model = handover
    o, _ = object_pose(np.random.default_rng(1))
    path = model.generate(demos[0].t, dense=True, frames={"object": o})
    before = path_peaks(path)
    right = path.columns_of("right_orientation")
    left = path.columns_of("left_position")
    w = 0.5 * float(before["angular_velocity"][right].max())
    s = 0.5 * float(before["speed"][left].max())
    lim = {"right_orientation": {"angular_velocity": w}, "left_position": {"speed": s}}
    slow = time_scale(path, lim)
    after = path_peaks(slow)
    assert after["angular_velocity"][right].max() <= w * (1 + TOLERANCE)
    assert after["speed"][left].max() <= s * (1 + TOLERANCE)
    assert slow.duration > path.duration
    # the velocity of each hand is the derivative of its positions again
    for hand in ("left", "right"):
        P, V = slow.get(f"{hand}_position"), slow.get(f"{hand}_velocity")
        np.testing.assert_allclose(
            V, np.gradient(P, slow.t, axis=0, edge_order=2), atol=1e-9
        )


def test_a_frame_moves_only_the_hands_it_names():
    demos, objs = two_hands(12, seed=1)
    o = np.array([0.22, 0.35, 0.0])  # 12 cm from the objects' mean
    away = float(np.linalg.norm(o - np.mean(objs, axis=0)))
    right = KeypointHMM(frame_hands={"object": ["right"]}).fit(demos)
    left = KeypointHMM(frame_hands={"object": ["left_position"]}).fit(demos)
    reach = {}
    for name, model in (("right", right), ("left", left)):
        path = model.generate(demos[0].t, dense=True, frames={"object": o})
        R = path.get("right_position")
        reach[name] = float(np.linalg.norm(R - (o + GRASP), axis=1).min())
    assert reach["right"] < 0.002
    assert reach["left"] > 0.5 * away  # the right hand went where it always went


@pytest.mark.parametrize(
    ("frame_hands", "match"),
    [
        ({"object": ["middle"]}, "names the hand 'middle'; this model's hands are"),
        ({"cube": ["left"]}, "names the frame 'cube', which the demonstrations"),
        ({"object": "left"}, "must map a frame's name to a non-empty list"),
        ({"object": []}, "must map a frame's name to a non-empty list"),
    ],
)
def test_frame_hands_is_checked(frame_hands, match):
    demos, _ = two_hands(4, seed=1, n_samples=60)
    with pytest.raises(ValidationError, match=match):
        KeypointHMM(frame_hands=frame_hands).fit(demos)


def test_two_hands_fit_at_default_levels(handover):
    """2 poses + 2 velocities + 2 grippers: 10**22+ cells, interned, no levels=."""
    _, model = handover
    levels = np.asarray(model.codebook_.levels, dtype=float)
    assert model.columns_[:3] == ("left_x", "left_y", "left_z")
    assert len(model.columns_) == 22  # 2 x (3 + 3 + 4) + 2 grippers
    assert float(np.prod(levels)) > 2.0**63  # beyond int64's mixed radix
    assert not model.codebook_.fits_int64
    assert 0 < model.n_states_used_ <= sum(len(k) for k in model.keypoints_)
