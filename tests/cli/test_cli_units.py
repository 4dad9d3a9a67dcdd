"""The units of ROS outputs, and LeRobot SO-100/101 joints that need them said.

LeRobot records an SO-100/101 arm's joints in degrees when the robot was
configured with ``use_degrees=True``, else in -100..100 of each joint's
calibrated range (its default); ROS reads radians. ``generate`` refuses to
guess for a LeRobot dataset with those names (``NAME.pos`` or the older
``main_NAME``): ``--units deg`` converts, ``--units rad`` keeps them as they
are. The reference is the model's own path as the writer eases it to rest
(:func:`~ndlfd.io._bagout.joint_trajectory_points` in radians, the path's
numbers as they are), converted here with ``numpy.deg2rad``.
"""

import warnings

import numpy as np
import pytest
from cli_helpers import cli

pytest.importorskip("pyarrow")
pytest.importorskip("yaml")

from lerobot_writer import (
    SO100_STATE,
    SO101_MOTORS,
    so101_episodes,
    write_lerobot,
    write_so100,
    write_so101,
)
from ndlfd.io import read_lerobot
from ndlfd.io._bagout import joint_trajectory_points
from ndlfd.learner import KeypointHMM


def _trajectory(out):
    """The YAML joint trajectory's names and positions."""
    import yaml

    msg = yaml.safe_load(out.read_text())
    return msg["joint_names"], np.array([p["positions"] for p in msg["points"]])


def _want(model_file):
    """The model's dense path on the command's timing, eased to rest as written.

    The joints, then the gripper, as :func:`joint_trajectory_points` writes
    them with the path's numbers taken as radians: the path still moves at
    its ends, so its clock is eased to a stop there (more points than the
    30 samples, the first and last the path's own).
    """
    path = KeypointHMM.load(model_file).generate(np.linspace(0, 2, 30), dense=True)
    P = _eased(path)
    ends = np.column_stack([path.get("joints"), path.get("gripper")])[[0, -1]]
    assert P.shape[0] > 30
    np.testing.assert_array_equal(P[[0, -1]], ends)
    return P


def _eased(path):
    """:func:`joint_trajectory_points`' positions, the path's numbers as radians."""
    with warnings.catch_warnings():  # degrees, more than a turn: on purpose
        warnings.filterwarnings("ignore", "the joints .* more than a turn")
        return joint_trajectory_points(path)[2]


GENERATE = ("--duration", 2, "--samples", 30, "--dense")


@pytest.mark.parametrize(
    ("write", "first", "joints"),
    [
        (write_so101, "shoulder_pan.pos", SO101_MOTORS),
        (write_so100, "main_shoulder_pan", SO100_STATE),
    ],
)  # fmt: skip
def test_so_arm_joints_need_their_units_said(tmp_path, capsys, write, first, joints):
    root, _ = write(tmp_path / "ds", n_demos=4)
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", root, "-o", model, "-q")
    assert rc == 0, err
    out = tmp_path / "traj.yaml"
    rc, err = cli(capsys, "generate", model, *GENERATE, "-o", out)
    assert rc == 2 and not out.exists()
    assert f"the joints ({first}, ...) come from a LeRobot SO-100/101" in err[-1]
    assert "use_degrees=True" in err[-1] and "-100..100" in err[-1]
    want = _want(model)
    # --units deg: converted to radians, in the trajectory and a bag's JointState
    rc, err = cli(capsys, "generate", model, *GENERATE, "--units", "deg", "-o", out)
    assert rc == 0 and err[-1] == f"generated 30 samples -> {out}"
    names, got = _trajectory(out)
    assert names == list(joints)
    np.testing.assert_allclose(got, np.deg2rad(want), rtol=1e-12, atol=1e-15)
    pytest.importorskip("rosbags")
    from bag_samples import rosbags_read

    rc, err = cli(capsys, "generate", model, *GENERATE, "--units", "deg",
                  "-o", tmp_path / "j.mcap")  # fmt: skip
    assert rc == 0, err
    got = rosbags_read(tmp_path / "j.mcap", "/ndlfd/path/joint_states")
    # the path's JointState messages: its 30 samples as they are
    path = KeypointHMM.load(model).generate(np.linspace(0, 2, 30), dense=True)
    np.testing.assert_allclose(
        [m.position for _, m in got], np.deg2rad(path.get("joints")), rtol=1e-12
    )
    # --units rad: as they are (and the warning that they look like degrees)
    rc, err = cli(capsys, "generate", model, *GENERATE, "--units", "rad",
                  "-o", out)  # fmt: skip
    assert rc == 0, err
    np.testing.assert_array_equal(_trajectory(out)[1], want)
    assert any("more than a turn in radians" in e for e in err)


def test_other_lerobot_joints_stay_radians(tmp_path, capsys):
    # a LeRobot dataset whose motors are not an SO arm's: nothing inferred
    names = ["base.pos", "shoulder_pan.pos", "arm.pos", "wrist_flex.pos",
             "elbow.pos", "gripper.pos"]  # fmt: skip
    eps = [
        {k: np.deg2rad(e[k]) if k == "observation.state" else e[k] for k in e}
        for e in so101_episodes(4)
    ]
    root = write_lerobot(tmp_path / "ds", eps, {"observation.state": names,
                                               "action": names})  # fmt: skip
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", root, "-o", model, "-q")
    assert rc == 0, err
    out = tmp_path / "traj.yaml"
    rc, err = cli(capsys, "generate", model, *GENERATE, "-o", out)
    assert rc == 0 and err[-1] == f"generated 30 samples -> {out}"
    np.testing.assert_array_equal(_trajectory(out)[1], _want(model))


def test_like_decides_for_a_model_without_a_mapping(tmp_path, capsys):
    # an SO-101 dataset's joints as a --like file: its mapping needs --units
    root, _ = write_so101(tmp_path / "ds", n_demos=4)
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", root, "-o", model, "-q")
    assert rc == 0, err
    m = KeypointHMM.load(model)
    m.input_mapping_ = None  # as a model fitted on several mappings
    m.save(model)
    out = tmp_path / "traj.yaml"
    like = ("--like", root, "--episodes", "1", "--dense")
    rc, err = cli(capsys, "generate", model, *like, "-o", out)
    assert rc == 2 and "come from a LeRobot SO-100/101" in err[-1]
    rc, err = cli(capsys, "generate", model, *like, "--units", "deg", "-o", out)
    assert rc == 0, err
    path = KeypointHMM.load(model).generate(read_lerobot(root, episodes=[1])[0],
                                            dense=True)  # fmt: skip
    got = _trajectory(out)[1]
    assert got.shape[0] > path.n_samples  # eased to rest at its moving ends
    ends = np.deg2rad(path.get("joints")[[0, -1]])
    np.testing.assert_allclose(got[[0, -1], :5], ends, rtol=1e-12)
    np.testing.assert_allclose(got[:, :5], np.deg2rad(_eased(path)[:, :5]), rtol=1e-12,
                               atol=1e-15)  # fmt: skip
    # without --like, the model has no mapping: radians, with the warning
    rc, err = cli(capsys, "generate", model, *GENERATE, "-o", out)
    assert rc == 0 and any("more than a turn in radians" in e for e in err)
