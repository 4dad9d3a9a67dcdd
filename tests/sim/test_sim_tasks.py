"""The simulated ALOHA tasks (extra sim): scene, scripted experts, LeRobot files."""

import numpy as np
import pytest

gym_aloha = pytest.importorskip(
    "gym_aloha",
    reason='the simulated tasks need the extra sim: pip install "ndlfd[sim]"',
)

from ndlfd.sim import (  # noqa: E402
    CONTROL_DT,
    EE_NAMES,
    JOINT_NAMES,
    TASKS,
    Scene,
    expert_episode,
    record_expert,
    render_plan,
    sample_objects,
    write_task_dataset,
)


@pytest.fixture(scope="module")
def cube_scene():
    return Scene("transfer-cube", "joint")


def _cols(demo, names):
    return np.column_stack([demo.X[:, demo.columns.index(n)] for n in names])


def _record(scene, seed):
    rng = np.random.default_rng(seed)
    objects = sample_objects(scene.spec.name, rng)
    scene.reset(objects)
    plan = expert_episode(scene.spec.name, objects, rng, start=scene.hands())
    return record_expert(scene, plan, objects)


def test_objects_over_gym_aloha_ranges():
    from gym_aloha.utils import sample_box_pose, sample_insertion_pose

    cube = TASKS.get("transfer-cube").ranges[0]
    peg, socket = TASKS.get("insertion").ranges
    for seed in range(50):
        assert np.all(
            (cube[0] <= sample_box_pose(seed)[:3])
            & (sample_box_pose(seed)[:3] <= cube[1])
        )
        p, s = sample_insertion_pose(seed)
        assert np.all((peg[0] <= p[:3]) & (p[:3] <= peg[1]))
        assert np.all((socket[0] <= s[:3]) & (s[:3] <= socket[1]))
    ours = np.array(
        [
            sample_objects("transfer-cube", np.random.default_rng(k))[0]
            for k in range(200)
        ]
    )
    assert np.all(ours.min(axis=0) >= cube[0]) and np.all(ours.max(axis=0) <= cube[1])
    # spread over the range, not a corner of it
    assert np.all(
        ours.max(axis=0)[:2] - ours.min(axis=0)[:2] > 0.9 * (cube[1] - cube[0])[:2]
    )


def test_scene_at_rest_scores_nothing():
    for task in ("transfer-cube", "insertion"):
        scene = Scene(task, "joint")
        scene.reset(sample_objects(task, np.random.default_rng(0)))
        start = scene.qpos()
        rewards = [scene.step(start) for _ in range(10)]
        assert rewards == [0] * 10
        # objects fall onto the table and rest where they were placed in x, y
        placed = sample_objects(task, np.random.default_rng(0))
        np.testing.assert_allclose(scene.objects()[:, :2], placed[:, :2], atol=1e-3)
        assert np.all(scene.objects()[:, 2] < 0.03)


def test_expert_plan_varies_timing_within_twenty_percent():
    nominal = np.array([1.0, 0.3, 0.6, 0.4, 1.2, 0.3, 0.6, 0.4, 0.3, 0.8])
    ratios = []
    for seed in range(30):
        rng = np.random.default_rng(seed)
        plan = expert_episode(
            "transfer-cube", sample_objects("transfer-cube", rng), rng
        )
        ratios.append(plan.durations / nominal)
        t, hands = render_plan(plan)
        assert hands.shape == (t.size, 16)
        np.testing.assert_allclose(np.diff(t), CONTROL_DT)
        assert t[-1] <= plan.durations.sum() < t[-1] + CONTROL_DT
        # quaternions stay unit between keys (slerp)
        np.testing.assert_allclose(
            np.linalg.norm(hands[:, 3:7], axis=1), 1.0, atol=1e-9
        )
    ratios = np.array(ratios)
    assert np.all((0.8 <= ratios) & (ratios <= 1.2))
    assert ratios.min() < 0.82 and ratios.max() > 1.18  # the whole +-20 %


def test_expert_is_deterministic(cube_scene):
    a, b = _record(cube_scene, 7), _record(cube_scene, 7)
    np.testing.assert_array_equal(a.joint_action, b.joint_action)
    np.testing.assert_array_equal(a.reward, b.reward)
    assert a.joint_action.shape == (a.t.size, 14)
    # the joints commanded are the ones the arm reached, to its servos' lag
    # (measured: median 1e-3 rad, 0.055 at most while moving fast)
    arms = [0, 1, 2, 3, 4, 5, 7, 8, 9, 10, 11, 12]
    lag = np.abs(a.state[:, arms] - a.joint_action[:, arms])
    assert np.median(lag) < 0.005 and lag.max() < 0.1
    # the hands went where the plan (ee_action) asked: tremor-sized misses
    miss = np.linalg.norm(
        a.hands[:, :, :3] - a.ee_action[:, [[0, 1, 2], [8, 9, 10]]], axis=2
    )
    assert np.median(miss) < 0.005
    # the wrists' rolls never move faster than the ViperX's limit
    rolls = a.joint_action[:, [3, 5, 10, 12]]
    assert np.abs(np.diff(rolls, axis=0)).max() <= np.pi * CONTROL_DT + 1e-9


def test_ik_reaches_poses_the_arm_can_take(cube_scene):
    """Poses from random joints (forward kinematics by mujoco itself) are solved."""
    import mujoco

    from ndlfd.sim import TOOL_DEPTH, ArmIK

    ik = ArmIK(cube_scene.physics)
    m = cube_scene.physics.model.ptr
    data = mujoco.MjData(m)
    rng = np.random.default_rng(3)
    start = np.array([0.0, -0.96, 1.16, 0.0, -0.3, 0.0])
    for side, adr in (("left", 0), ("right", 8)):
        body = mujoco.mj_name2id(
            m, mujoco.mjtObj.mjOBJ_BODY, f"vx300s_{side}/gripper_link"
        )
        for _ in range(10):
            q = start + rng.uniform(-0.4, 0.4, size=6)
            data.qpos[:] = m.qpos0
            data.qpos[adr : adr + 6] = q
            mujoco.mj_forward(m, data)
            R = data.xmat[body].reshape(3, 3)
            point = data.xpos[body] + TOOL_DEPTH * R[:, 0]
            quat = data.xquat[body].copy()
            got, err = ik.solve(side, point, quat, start, iterations=200)
            data.qpos[adr : adr + 6] = got
            mujoco.mj_forward(m, data)
            R2 = data.xmat[body].reshape(3, 3)
            assert (
                np.linalg.norm(data.xpos[body] + TOOL_DEPTH * R2[:, 0] - point) < 1e-3
            )
            # the same orientation: the rotation between them under 0.01 rad
            cos = (np.trace(R.T @ R2) - 1) / 2
            assert np.arccos(np.clip(cos, -1, 1)) < 0.01
            assert err < 2e-3


def test_experts_succeed_on_a_handful_of_poses(cube_scene):
    # measured over 100 poses: Transfer Cube and Insertion (docs/tasks.md)
    assert all(_record(cube_scene, 1000 + k).success for k in range(3))
    scene = Scene("insertion", "joint")
    assert sum(_record(scene, 1000 + k).success for k in range(3)) >= 2


def test_lerobot_round_trip(cube_scene, tmp_path):
    pytest.importorskip("pyarrow")
    from ndlfd.io import read_lerobot

    recs = [_record(cube_scene, 1000 + k) for k in range(3)]
    root = write_task_dataset(recs, tmp_path / "aloha", "transfer-cube")
    arms = [n for n in JOINT_NAMES if not n.endswith("gripper")]
    grippers = ["left_gripper", "right_gripper"]
    demos = read_lerobot(
        root, feature="action", groups={"joints": arms, "gripper": grippers}
    )
    assert len(demos) == 3
    for d, r in zip(demos, recs, strict=True):
        np.testing.assert_allclose(d.t, r.t.astype(np.float32), rtol=0, atol=1e-6)
        got = _cols(d, JOINT_NAMES)
        np.testing.assert_array_equal(got, r.joint_action.astype(np.float32))
    right = [f"right_{c}" for c in "xyz"]
    ee = read_lerobot(
        root,
        feature="action.ee",
        groups={
            "position": right,
            "orientation": [f"right_q{c}" for c in "wxyz"],
            "left": [f"left_{c}" for c in "xyz"],
            "left_quat": [f"left_q{c}" for c in "wxyz"],
            "gripper": grippers,
        },
        frames={"cube": "observation.cube"},
    )
    for d, r in zip(ee, recs, strict=True):
        np.testing.assert_allclose(
            d.frames["cube"], r.objects[0].astype(np.float32), atol=1e-7
        )
        np.testing.assert_array_equal(
            _cols(d, EE_NAMES), r.ee_action.astype(np.float32)
        )
    with pytest.raises(ValueError, match="already holds"):
        write_task_dataset(recs, root, "transfer-cube")
