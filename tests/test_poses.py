"""Task frames' poses (ndlfd._poses): checks and the maps between frames."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from ndlfd import Demonstration, ValidationError
from ndlfd._poses import check_frames, frame_maps


def _matrix(q):
    """Rotation matrix of a unit quaternion (w, x, y, z): the textbook formula."""
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _unit(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


quats = st.lists(st.floats(-1, 1), min_size=4, max_size=4).filter(
    lambda v: np.linalg.norm(v) > 0.1
)
points = st.lists(st.floats(-2, 2), min_size=3, max_size=3)


@settings(max_examples=60, deadline=None)
@given(quats, quats, points, points, points)
def test_a_point_keeps_its_place_in_the_frame(q_old, q_new, o_old, o_new, p):
    q_old, q_new = _unit(q_old), _unit(q_new)
    o_old, o_new, p = (np.array(v) for v in (o_old, o_new, p))
    A, b, dq = frame_maps(np.r_[o_old, q_old][None], np.r_[o_new, q_new], 3)
    moved = A[0] @ p + b[0]
    # relative to its frame, by the textbook matrices: the same before and after
    local_before = _matrix(q_old).T @ (p - o_old)
    local_after = _matrix(q_new).T @ (moved - o_new)
    np.testing.assert_allclose(local_after, local_before, atol=1e-9)
    # the orientation turns by the same rotation: dq * q_old = +-q_new
    turned = Rotation.from_quat(dq[0][[1, 2, 3, 0]]) * Rotation.from_quat(
        q_old[[1, 2, 3, 0]]
    )
    np.testing.assert_allclose(turned.as_matrix(), _matrix(q_new), atol=1e-9)


def test_a_translation_only_moves():
    A, b, dq = frame_maps(np.array([[1.0, 2.0], [0.0, 0.0]]), np.array([3.0, 3.0]), 2)
    assert dq is None
    np.testing.assert_array_equal(A, np.broadcast_to(np.eye(2), (2, 2, 2)))
    np.testing.assert_array_equal(b, [[2.0, 1.0], [3.0, 3.0]])


def test_check_frames_normalizes_the_quaternion_sign_and_length():
    f = check_frames({"o": [0, 0, 0, -0.7071, 0, 0, -0.7071]}, 3)  # 4 decimals
    np.testing.assert_allclose(f["o"][3:], [np.sqrt(0.5), 0, 0, np.sqrt(0.5)])
    assert not f["o"].flags.writeable
    with pytest.raises(TypeError):
        f["p"] = np.zeros(3)  # read-only mapping


@pytest.mark.parametrize(
    ("frames", "dims", "match"),
    [
        ([1, 2], 2, "mapping of frame name"),
        ({"o": [1, 2, 3]}, 2, "must hold 2 values"),
        ({"o": [1, 2, 3, 1]}, 3, r"3 values .* or 7"),
        ({"o": [1, np.nan]}, 2, "finite"),
        ({"o": [0, 0, 0, 2, 0, 0, 0]}, 3, "unit length"),
        ({"1o": [0, 0]}, 2, "name"),
        ({"o": [0, 0, 0, 0]}, None, r"2 values \(x, y\), 3 .* or 7"),
        ({"o": [[0, 0]]}, 2, r"shape \(1, 2\)"),
    ],
)
def test_check_frames_says_what_it_expected(frames, dims, match):
    with pytest.raises(ValidationError, match=match):
        check_frames(frames, dims)


def test_a_demonstration_keeps_its_frames():
    d = Demonstration.from_arrays(
        [0.0, 1.0, 2.0],
        position=[[0, 0], [1, 0], [1, 1]],
        force=[1.0, 2.0, 3.0],
        frames={"object": [1.0, 0.5]},
    )
    assert list(d.frames) == ["object"]
    for kept in (d.take([0, 2]), d.select("position"), d.with_group("g", [1, 2, 3])):
        np.testing.assert_array_equal(kept.frames["object"], [1.0, 0.5])
    from ndlfd import with_velocity

    assert list(with_velocity(d).frames) == ["object"]
    # without a position group (as a joint-space model) the frames stay: a
    # model of any group may be moved with them
    np.testing.assert_array_equal(d.select("force").frames["object"], [1.0, 0.5])
    assert d != d.with_frames(None)
    assert d == d.with_frames({"object": [1.0, 0.5]})
    assert "frames=(object)" in repr(d)
    with pytest.raises(ValidationError, match=r"must hold 3 values .* got .* \(2,\)"):
        d.with_group("position", np.zeros((3, 3)))


def test_frames_go_to_worker_processes():
    import pickle

    d = Demonstration.from_arrays(
        [0.0, 1.0], position=np.zeros((2, 3)), frames={"o": [1, 2, 3, 1, 0, 0, 0]}
    )
    back = pickle.loads(pickle.dumps(d))
    assert back == d
    assert not back.frames["o"].flags.writeable
