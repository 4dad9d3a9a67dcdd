"""The units of ROS outputs: degrees by default for LeRobot SO-100/101 joints.

LeRobot records an SO-100/101 arm's joints in degrees; ROS reads radians.
``generate`` takes them for degrees when the data came from a LeRobot dataset
with those names (``NAME.pos`` or the older ``main_NAME``), says so, and
``--units rad`` keeps them as they are. The reference is the model's own
path, converted here with ``numpy.deg2rad``.
"""

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
from ndlfd.learner import KeypointHMM


def _trajectory(out):
    """The YAML joint trajectory's names and positions."""
    import yaml

    msg = yaml.safe_load(out.read_text())
    return msg["joint_names"], np.array([p["positions"] for p in msg["points"]])


def _want(model_file):
    """The model's dense path on the command's timing: joints, then the gripper."""
    path = KeypointHMM.load(model_file).generate(np.linspace(0, 2, 30), dense=True)
    return np.column_stack([path.get("joints"), path.get("gripper")])


GENERATE = ("--duration", 2, "--samples", 30, "--dense")


@pytest.mark.parametrize(
    ("write", "first", "joints"),
    [
        (write_so101, "shoulder_pan.pos", SO101_MOTORS),
        (write_so100, "main_shoulder_pan", SO100_STATE),
    ],
)  # fmt: skip
def test_so_arm_joints_go_out_in_radians_by_default(
    tmp_path, capsys, write, first, joints
):
    root, _ = write(tmp_path / "ds", n_demos=4)
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", root, "-o", model, "-q")
    assert rc == 0, err
    out = tmp_path / "traj.yaml"
    rc, err = cli(capsys, "generate", model, *GENERATE, "-o", out)
    assert rc == 0, err
    names, got = _trajectory(out)
    assert names == list(joints)
    want = _want(model)
    np.testing.assert_allclose(got, np.deg2rad(want), rtol=1e-12, atol=0)
    assert err[-2] == (
        "joints taken for degrees, as LeRobot records an SO-100/101 arm"
        f" ({first}, ...), and written in radians for ROS; --units rad if they"
        " are radians"
    )
    assert err[-1] == f"generated 30 samples -> {out}"
    # a bag's JointState alike
    pytest.importorskip("rosbags")
    from bag_samples import rosbags_read

    rc, err = cli(capsys, "generate", model, *GENERATE, "-o", tmp_path / "j.mcap")
    assert rc == 0 and err[-2].startswith("joints taken for degrees"), err
    got = rosbags_read(tmp_path / "j.mcap", "/ndlfd/path/joint_states")
    np.testing.assert_allclose(
        [m.position for _, m in got], np.deg2rad(want[:, :5]), rtol=1e-12
    )
    # --units rad: as they are (and the warning that they look like degrees)
    rc, err = cli(capsys, "generate", model, *GENERATE, "--units", "rad",
                  "-o", out)  # fmt: skip
    assert rc == 0, err
    np.testing.assert_array_equal(_trajectory(out)[1], want)
    assert not any(e.startswith("joints taken") for e in err)
    assert any("more than a turn in radians" in e for e in err)
    # --units deg given: no note, the same radians
    rc, err = cli(capsys, "generate", model, *GENERATE, "--units", "deg", "-o", out)
    assert rc == 0 and err[-1] == f"generated 30 samples -> {out}"
    assert not any(e.startswith("joints taken") for e in err)
    np.testing.assert_allclose(_trajectory(out)[1], np.deg2rad(want), rtol=1e-12)


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
    assert not any(e.startswith("joints taken") for e in err)
    np.testing.assert_array_equal(_trajectory(out)[1], _want(model))


def test_like_decides_the_units_of_a_model_without_a_mapping(tmp_path, capsys):
    # an SO-101 dataset's joints as a --like file: its mapping says degrees
    root, _ = write_so101(tmp_path / "ds", n_demos=4)
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", root, "-o", model, "-q")
    assert rc == 0, err
    m = KeypointHMM.load(model)
    m.input_mapping_ = None  # as a model fitted on several mappings
    m.save(model)
    out = tmp_path / "traj.yaml"
    rc, err = cli(capsys, "generate", model, "--like", root, "--episodes", "1",
                  "--dense", "-o", out)  # fmt: skip
    assert rc == 0, err
    assert err[-2].startswith("joints taken for degrees")
    np.testing.assert_allclose(
        _trajectory(out)[1][:, :5],
        np.deg2rad(KeypointHMM.load(model).generate(
            read_lerobot(root, episodes=[1])[0], dense=True).get("joints")),
        rtol=1e-12,
    )  # fmt: skip
    rc, err = cli(capsys, "generate", model, *GENERATE, "-o", out)
    assert rc == 0 and not any(e.startswith("joints taken") for e in err)
    assert any("more than a turn in radians" in e for e in err)
