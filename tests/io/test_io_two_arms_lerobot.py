"""Two arms in LeRobot datasets: ALOHA's layout and two hands' poses (issue 43).

Datasets are written as LeRobot writes them (``tests/lerobot_writer.py``);
the groups each episode must read into are worked out by hand from its 14
columns (per arm, left then right, 6 joints and the gripper).
"""

import json

import numpy as np
import pytest

pytest.importorskip("pyarrow")

from scipy.spatial.transform import Rotation

from lerobot_writer import write_lerobot
from ndlfd import DataFileError
from ndlfd.io import (
    read_csv,
    read_demos,
    read_lerobot,
    read_parquet,
    write_csv,
    write_parquet,
)
from ndlfd.io._names import ALOHA_NAMES


def _unit_quaternions(n, seed):
    """Quaternions w, x, y, z with w > 0.5 (no sign flip along the rows)."""
    rng = np.random.default_rng(seed)
    q = np.column_stack([np.full(n, 2.0), rng.normal(0, 0.5, (n, 3))])
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _angle(q1, q2):
    """The rotation angle between two arrays of quaternions w, x, y, z (rad)."""
    r1 = Rotation.from_quat(q1, scalar_first=True)
    r2 = Rotation.from_quat(q2, scalar_first=True)
    return (r1.inv() * r2).magnitude()


def _aloha_episodes(n_demos=2, seed=0):
    rng = np.random.default_rng(seed)
    eps = []
    for e in range(n_demos):
        n = 30 + 5 * e
        state = rng.normal(0, 0.5, (n, 14))
        state[:, [6, 13]] = rng.uniform(0, 1, (n, 2))  # the grippers
        eps.append({"observation.state": state, "action": state + 0.01})
    return eps


def _aloha_expect(d, values):
    """The groups of an ALOHA episode, worked by hand from its 14 columns."""
    v = np.asarray(values, dtype=np.float32).astype(np.float64)
    np.testing.assert_array_equal(d.get("left_joints"), v[:, 0:6])
    np.testing.assert_array_equal(d.get("gripper"), v[:, [6, 13]])
    np.testing.assert_array_equal(d.get("right_joints"), v[:, 7:13])


@pytest.mark.parametrize("names_as", [dict, list, "nested"])
def test_aloha_dataset_reads_into_two_arms(tmp_path, names_as):
    eps = _aloha_episodes()
    names = {"observation.state": list(ALOHA_NAMES), "action": list(ALOHA_NAMES)}
    root = write_lerobot(
        tmp_path / "aloha",
        eps,
        names,
        fps=50,
        names_as=list if names_as == "nested" else names_as,
    )
    if names_as == "nested":  # [[...]], as some ALOHA conversions store them
        info = json.loads((root / "meta" / "info.json").read_text())
        for key in names:
            info["features"][key]["names"] = [list(ALOHA_NAMES)]
        (root / "meta" / "info.json").write_text(json.dumps(info))
    demos, maps = read_demos(root, return_mappings=True)
    assert len(demos) == 2
    assert str(maps[0]) == (
        "time=timestamp; left_joints=left_waist,left_shoulder,left_elbow,"
        "left_forearm_roll,left_wrist_angle,left_wrist_rotate;"
        " gripper=left_gripper,right_gripper; right_joints=right_waist,"
        "right_shoulder,right_elbow,right_forearm_roll,right_wrist_angle,"
        "right_wrist_rotate (LeRobot v3.0, observation.state)"
    )
    for d, ep in zip(demos, eps, strict=True):
        assert d.group_names == ("left_joints", "gripper", "right_joints")
        _aloha_expect(d, ep["observation.state"])
    acts = read_lerobot(root, feature="action")
    _aloha_expect(acts[1], eps[1]["action"])


def test_aloha_without_names_gives_the_mapping_to_pass(tmp_path):
    eps = _aloha_episodes(1)
    names = {"observation.state": list(ALOHA_NAMES), "action": list(ALOHA_NAMES)}
    root = write_lerobot(tmp_path / "aloha", eps, names, fps=50, names_as=None)
    with pytest.raises(DataFileError) as err:
        read_lerobot(root)
    msg = str(err.value)
    assert "If they are ALOHA's 14 values as LeRobot records them" in msg
    line = msg.split("6 joints and the gripper: ")[1].split(", pass: ")[1]
    groups = {
        "left_joints": [f"state_{i}" for i in range(6)],
        "gripper": ["state_6", "state_13"],
        "right_joints": [f"state_{i}" for i in range(7, 13)],
    }
    assert line == f"groups={groups!r}"
    (d,) = read_lerobot(root, groups=groups)  # pasted, it reads
    _aloha_expect(d, eps[0]["observation.state"])


def test_end_effector_feature_of_two_hands(tmp_path):
    """The layout ndlfd.sim writes (action.ee): per hand x..qz and the gripper."""
    hand = ("x", "y", "z", "qw", "qx", "qy", "qz", "gripper")
    ee = [f"{side}_{c}" for side in ("left", "right") for c in hand]
    n = 20
    rng = np.random.default_rng(6)
    qL, qR = _unit_quaternions(n, 7), _unit_quaternions(n, 8)
    v = np.column_stack(
        [
            rng.normal(size=(n, 3)),
            qL,
            rng.uniform(0, 1, n),
            rng.normal(size=(n, 3)),
            qR,
            rng.uniform(0, 1, n),
        ]
    )
    root = write_lerobot(tmp_path / "ee", [{"action.ee": v}], {"action.ee": ee})
    (d,) = read_lerobot(root, feature="action.ee")
    assert d.group_names == (
        "left_position",
        "left_orientation",
        "gripper",
        "right_position",
        "right_orientation",
    )
    v32 = v.astype(np.float32).astype(np.float64)
    np.testing.assert_array_equal(d.get("left_position"), v32[:, 0:3])
    np.testing.assert_array_equal(d.get("gripper"), v32[:, [7, 15]])
    np.testing.assert_array_equal(d.get("right_position"), v32[:, 8:11])
    for group, cols in (
        ("left_orientation", slice(3, 7)),
        ("right_orientation", slice(11, 15)),
    ):
        q = d.get(group)
        np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1, atol=1e-12)
        assert np.max(_angle(q, v32[:, cols])) < 1e-6  # float32, renormalized


def test_two_arms_written_and_read_back(tmp_path):
    """CSV and Parquet: a two-arm path keeps its groups, names and values."""
    eps = _aloha_episodes(1)
    names = {"observation.state": list(ALOHA_NAMES)}
    root = write_lerobot(tmp_path / "aloha", eps, names, fps=50, names_as=dict)
    (d,), (m,) = read_demos(root, return_mappings=True)
    # the demonstration's own names (group.column where a name says no group)
    p = write_csv(d, tmp_path / "own.csv")
    header = p.read_text().splitlines()[0].split(",")
    assert header[1:3] == ["left_joints.left_waist", "left_joints.left_shoulder"]
    assert header[7:9] == ["gripper.left_gripper", "gripper.right_gripper"]
    back = read_csv(p)
    assert back.group_names == ("left_joints", "gripper", "right_joints")
    np.testing.assert_array_equal(back.X, d.X)
    # the input's names and order, and a Parquet episode in LeRobot's layout
    p = write_csv(d, tmp_path / "like.csv", mapping=m)
    assert p.read_text().splitlines()[0].split(",") == ["timestamp", *ALOHA_NAMES]
    back = read_csv(p)
    assert back.columns == d.columns and back.groups == d.groups
    np.testing.assert_array_equal(back.X, d.X)
    back = read_parquet(write_parquet(d, tmp_path / "ep.parquet", mapping=m))
    assert back.columns == d.columns and back.groups == d.groups
    np.testing.assert_array_equal(back.X, d.X)


def test_two_hands_with_a_task_frame(tmp_path):
    """An object's position as a task frame of a two-hand end-effector feature."""
    hand = ("x", "y", "z", "qw", "qx", "qy", "qz", "gripper")
    ee = [f"{side}_{c}" for side in ("left", "right") for c in hand]
    n = 12
    rng = np.random.default_rng(9)
    eps = []
    for e in range(2):
        qL, qR = _unit_quaternions(n, 10 + e), _unit_quaternions(n, 20 + e)
        v = np.column_stack(
            [
                rng.normal(size=(n, 3)),
                qL,
                np.ones(n),
                rng.normal(size=(n, 3)),
                qR,
                np.zeros(n),
            ]
        )
        cube = np.tile([0.1 * e, 0.5, 0.02], (n, 1))
        eps.append({"action.ee": v, "observation.cube": cube})
    names = {"action.ee": ee, "observation.cube": ["x", "y", "z"]}
    root = write_lerobot(tmp_path / "ee", eps, names)
    demos = read_lerobot(root, feature="action.ee", frames={"cube": "observation.cube"})
    for e, d in enumerate(demos):
        assert d.group_names[:2] == ("left_position", "left_orientation")
        want = np.array([0.1 * e, 0.5, 0.02], dtype=np.float32)
        np.testing.assert_array_equal(d.frames["cube"], want.astype(np.float64))
