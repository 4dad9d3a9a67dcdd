"""The README's shell examples really run (its Python examples run as doctests)."""

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ndlfd import Demonstration, synth
from ndlfd.io import read_csv, write_csv, write_table

README = Path(__file__).resolve().parents[1] / "README.md"
BIN = Path(sys.executable).parent / "ndlfd"


_ROBOT_DATA = "## From ROS 2 and LeRobot"


def _shell_examples(section: str | None = None) -> list[list[str]]:
    """The README's ``$ ndlfd`` lines: of one section, or outside the robot data."""
    text = README.read_text(encoding="utf-8")
    if section is not None:
        text = text.split(section, 1)[1]
        text = re.split(r"^##+ ", text, flags=re.M)[0]
    elif _ROBOT_DATA in text:  # run by their own tests (they need the extras)
        head, rest = text.split(_ROBOT_DATA, 1)
        text = head + rest[rest.index("\n## ") :]
    lines = re.findall(r"^\$ (ndlfd .+)$", text, re.M)
    return [shlex.split(m, comments=True) for m in lines]


def _run(args, cwd):
    env = dict(os.environ, PYTHONWARNINGS="error")
    # this source tree, also from the examples' folder (PYTHONPATH=src)
    paths = env.get("PYTHONPATH", "").split(os.pathsep)
    env["PYTHONPATH"] = os.pathsep.join(str(Path(p).resolve()) for p in paths if p)
    r = subprocess.run(
        [str(BIN), *args[1:]],
        cwd=cwd,
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    assert r.returncode == 0, f"{shlex.join(args)} failed: {r.stderr}"


def test_readme_shell_examples_run(tmp_path):
    examples = _shell_examples()
    assert [e[1] for e in examples] == [
        "simplify",
        "fit",
        "generate",
        "generate",
        "generate",
        "generate",
        "generate",
        "sample",
        "evaluate",
        "reproduce",
        "fit",
        "generate",
        "plot",
    ]
    # the files the examples name
    rng = np.random.default_rng(0)
    walk = np.column_stack(
        [np.arange(500) * 0.1, np.cumsum(rng.normal(size=(500, 2)), 0)]
    )
    write_table(tmp_path / "walk.csv", ["t", "x", "y"], walk)
    train, test = synth.make_dataset("square", n_demos=15, random_state=2)
    (tmp_path / "demos").mkdir()
    for i, d in enumerate(train):
        write_csv(d, tmp_path / "demos" / f"d{i}.csv")
    # what a robot executed so far: the held-out square's first 30 %, from 0 s
    n = int(0.3 * test.n_samples)
    so_far = Demonstration(test.t[:n] - test.t[0], test.X[:n], test.columns,
                           test.groups)  # fmt: skip
    write_csv(so_far, tmp_path / "so-far.csv")
    # "Your own data": the picture's recordings (docs/images/plot-own-data.png)
    own, _ = synth.make_dataset("square", n_demos=6, noise=0.02, random_state=2)
    (tmp_path / "recordings").mkdir()
    for i, d in enumerate(own):
        rows = np.column_stack([d.t, d.get("position")]).tolist()
        text = ["time;pos_x;pos_y"] + [";".join(f"{v:.6g}" for v in r) for r in rows]
        (tmp_path / "recordings" / f"reach{i}.csv").write_text("\n".join(text) + "\n")
    for args in examples:
        if args[1] == "reproduce":
            args = [*args, "--quick"]  # the full run is checked by its own test
        if args[1] == "evaluate":  # the full run is docs/evaluation.md
            args = [*args, "--shapes", "Line", "--folds", "1", "--no-plot"]
        _run(args, tmp_path)
    assert read_csv(tmp_path / "keypoints.csv").n_samples < 500
    path = read_csv(tmp_path / "path.csv")
    assert path.n_samples == 400 and path.t[-1] == 8.0
    at_100 = read_csv(tmp_path / "path-100hz.csv")  # --rate: stamps k / 100
    np.testing.assert_array_equal(at_100.t, np.arange(801) / 100.0)
    here = read_csv(tmp_path / "from-here.csv").get("position")[0]
    np.testing.assert_array_equal(here, [0.5, 0.0])
    via = read_csv(tmp_path / "via.csv")  # through the via point at t = 4
    at = [np.interp(4.0, via.t, c) for c in via.get("position").T]
    np.testing.assert_allclose(at, [10.0, 10.5], atol=0.01)
    so_far = read_csv(tmp_path / "so-far.csv")
    rest = read_csv(tmp_path / "rest.csv")  # the prefix, then its continuation
    np.testing.assert_array_equal(rest.t[:n], so_far.t)
    np.testing.assert_allclose(rest.get("position")[:n], so_far.get("position"))
    continuations = sorted((tmp_path / "continuations").glob("sample_*.csv"))
    assert len(continuations) == 20
    assert (tmp_path / "evaluation" / "summary.md").exists()
    assert (tmp_path / "docs" / "reproduction" / "report.md").exists()
    # the generated path keeps the recordings' names (fit recorded them)
    assert (tmp_path / "reach.csv").read_text().startswith("time,pos_x,pos_y,")
    reach = read_csv(tmp_path / "reach.csv", groups={"position": ["pos_x", "pos_y"]})
    assert reach.n_samples == 200 and reach.columns[:2] == ("pos_x", "pos_y")
    assert (tmp_path / "reach.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_readme_whole_robot_log_examples_run(tmp_path):
    pytest.importorskip("matplotlib")
    sys.path.insert(0, str(Path(__file__).parent / "io"))
    from lab_logs import FRANKA_COLUMNS, write_franka

    examples = _shell_examples("### A whole robot log")
    assert [e[1] for e in examples] == ["fit", "generate", "plot"]
    write_franka(tmp_path / "logs", n_demos=5, n=120)  # 27 columns, no time, 20 Hz
    assert (tmp_path / "logs" / "task0.csv").read_text().split("\n")[0] == ",".join(
        FRANKA_COLUMNS
    )
    for args in examples:
        _run(args, tmp_path)
    path = read_csv(tmp_path / "task-path.csv")
    assert path.n_samples == 120 and path.t[-1] == 119 / 20
    assert not any(c.startswith("goal_") for c in path.columns)
    assert set(path.group_names) >= {"position", "orientation", "force", "joints"}
    assert (tmp_path / "task.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_readme_ros_bag_examples_run(tmp_path):
    pytest.importorskip("rosbags")
    pytest.importorskip("matplotlib")
    from bag_samples import pick_place_messages, write_bag
    from ndlfd.io import read_bag

    examples = _shell_examples("### ROS 2 bags")
    assert [e[1] for e in examples] == ["fit", "generate", "generate", "plot"]
    # the picture's bags (docs/images/ros-pick-triads.png)
    (tmp_path / "bags").mkdir()
    for i in range(6):
        _, _, _, poses, grip = pick_place_messages(seed=i)
        write_bag(tmp_path / "bags" / f"pick{i}", {"/ee_pose": poses, "/gripper": grip})
    for args in examples:
        _run(args, tmp_path)
    (path,) = read_bag(tmp_path / "pick.mcap", ["/ndlfd/path", "/ndlfd/path/gripper"])
    assert path.n_samples == 300 and path.t[-1] == 6.0
    assert path.group_names == ("position", "orientation", "gripper")
    assert (tmp_path / "pick.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_readme_lerobot_examples_run(tmp_path):
    pytest.importorskip("pyarrow")
    from lerobot_writer import write_lerobot

    examples = _shell_examples("### LeRobot datasets")
    assert [e[1] for e in examples] == ["fit", "generate"]
    # a v3.0 dataset of 41 picks (x, y, z, roll, pitch, yaw, gripper), as
    # LeRobot writes it
    s = np.linspace(0, 1, 50)
    picks = [
        np.column_stack([s, s**2, 0 * s + 0.01 * i, 0.1 * s, 0 * s, s - 0.5, s > 0.5])
        for i in range(41)
    ]
    names = ["x", "y", "z", "roll", "pitch", "yaw", "gripper"]
    write_lerobot(tmp_path / "pick_cube", [{"observation.state": p} for p in picks],
                  {"observation.state": names})  # fmt: skip
    for args in examples:
        _run(args, tmp_path)
    pick = (tmp_path / "pick.csv").read_text().splitlines()[0]
    assert pick == "timestamp,x,y,z,roll,pitch,yaw,gripper,vx,vy,vz"
    assert f"`{pick}`" in README.read_text(encoding="utf-8")  # as it says


def test_readme_so101_examples_run(tmp_path):
    pytest.importorskip("pyarrow")
    pytest.importorskip("matplotlib")
    from lerobot_writer import SO101_STATE, write_so101
    from ndlfd.io import read_parquet

    examples = _shell_examples("### An SO-101 arm")
    assert [e[1] for e in examples] == ["fit", "generate", "generate", "plot"]
    write_so101(tmp_path / "so101_pick", n_demos=12)  # LeRobot v3.0, as it writes
    for args in examples:
        _run(args, tmp_path)
    header = (tmp_path / "next.csv").read_text().splitlines()[0]
    assert header == ",".join(["timestamp", *SO101_STATE])
    assert f"`{header}`" in README.read_text(encoding="utf-8")
    back = read_parquet(tmp_path / "next.parquet")
    assert back.groups == ("joints",) * 5 + ("gripper",)
    assert (tmp_path / "so101.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_readme_so101_to_ros2_examples_run(tmp_path):
    pytest.importorskip("pyarrow")
    pytest.importorskip("rosbags")
    from rosbags.rosbag2 import Reader

    from bag_samples import STORE
    from lerobot_writer import write_so101

    examples = _shell_examples("### From a LeRobot SO-101 dataset to a ROS 2")
    assert [e[1] for e in examples] == ["fit", "generate"]
    write_so101(tmp_path / "so101_pick", n_demos=12)  # LeRobot v3.0, as it writes
    for args in examples:
        _run(args, tmp_path)
    flags = examples[1]
    names = flags[flags.index("--joint-names") + 1].split(",")
    start = [float(v) for v in flags[flags.index("--start") + 1][7:].split(",")]
    with Reader(tmp_path / "so101_traj") as reader:
        (conn,) = reader.connections
        ((_, _, raw),) = list(reader.messages())
        msg = STORE.deserialize_cdr(raw, conn.msgtype)
    assert conn.msgtype == "trajectory_msgs/msg/JointTrajectory"
    assert list(msg.joint_names) == names
    P = np.array([p.positions for p in msg.points])
    V = np.array([p.velocities for p in msg.points])
    # radians, from the given start, within 30 deg/s per joint, at rest at both ends
    np.testing.assert_allclose(P[0, :5], np.deg2rad(start), rtol=0, atol=1e-9)
    assert np.abs(V[:, :5]).max() <= np.deg2rad(30.0) * (1 + 1e-3)
    assert np.all(V[[0, -1]] == 0.0)
    stamps = [
        p.time_from_start.sec + p.time_from_start.nanosec * 1e-9 for p in msg.points
    ]
    assert np.all(np.diff(stamps) > 0) and stamps[-1] > 4.0  # slowed down
