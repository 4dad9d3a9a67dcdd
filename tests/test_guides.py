"""The user guides' examples really run (docs/guides/*.md, issue 41).

Their Python examples are doctests, run here page by page (one namespace per
page); their shell examples (``$ ndlfd ...``) run section by section on the
files they name, written here. Every section with a shell example is one of
:data:`RUN`, so an example added to a guide cannot go unrun.
"""

import doctest
import sys
from pathlib import Path

import numpy as np
import pytest

from doc_blocks import (
    GUIDES,
    README,
    commands,
    python_blocks,
    run,
    section,
    sections_with_commands,
)
from ndlfd import Demonstration, synth
from ndlfd.io import read_csv, write_csv, write_table

PAGES = sorted(GUIDES.glob("*.md"))

#: The sections whose shell examples run, and the test that runs them.
RUN = {
    ("command_line.md", "# The command line"): "test_command_line_examples_run",
    ("own_data.md", "## On the command line"): "test_own_data_examples_are_the_readmes",
    ("own_data.md", "## A whole robot log"): "test_whole_robot_log_examples_run",
    ("ros2.md", "# ROS 2 bags"): "test_ros_bag_examples_run",
    ("robots.md", "## Joint trajectories for a ROS 2 controller"): (
        "test_joint_trajectory_examples_run"
    ),
    ("robots.md", "## From a LeRobot SO-101 dataset to a ROS 2 controller"): (
        "test_so101_to_ros2_examples_run"
    ),
    ("lerobot.md", "## Reading a dataset"): "test_lerobot_examples_run",
    ("lerobot.md", "## An SO-101 arm"): "test_so101_examples_run",
}


def _text(page: str) -> str:
    return (GUIDES / page).read_text(encoding="utf-8")


def _examples(page: str, heading: str) -> list[list[str]]:
    return commands(section(_text(page), heading))


def test_every_shell_example_is_run():
    found = {
        (page.name, heading)
        for page in PAGES
        for heading in sections_with_commands(page.read_text(encoding="utf-8"))
    }
    assert found == set(RUN)
    assert all(name in globals() for name in RUN.values())


def test_the_section_reader_on_a_known_text():
    text = "# A\n$ ndlfd fit a/ -o m.ndlfd  # note\n## B\n\n```console\n$ ls\n```\n"
    assert sections_with_commands(text) == {"# A": [["ndlfd", "fit", "a/", "-o",
                                                     "m.ndlfd"]]}  # fmt: skip
    assert section(text, "## B") == "\n```console\n$ ls\n```\n"
    assert python_blocks("```python\n>>> 1\n1\n```\n") == [">>> 1\n1\n"]


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.stem)
def test_python_examples_are_doctests(page):
    # a block that is not a doctest would be shown and never run
    blocks = python_blocks(page.read_text(encoding="utf-8"))
    assert all(b.lstrip().startswith(">>>") for b in blocks), page.name


DOCTEST_PAGES = [p for p in PAGES if ">>> " in p.read_text(encoding="utf-8")]


@pytest.mark.parametrize("page", DOCTEST_PAGES, ids=lambda p: p.stem)
def test_python_examples_run(page):
    text = page.read_text(encoding="utf-8")
    test = doctest.DocTestParser().get_doctest(text, {}, page.name, str(page), 0)
    assert test.examples
    flags = doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS
    runner = doctest.DocTestRunner(optionflags=flags)
    report = []
    result = runner.run(test, out=report.append)
    assert result.failed == 0, "".join(report)


def test_command_line_examples_run(tmp_path):
    examples = _examples("command_line.md", "# The command line")
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
    for args in examples:
        if args[1] == "reproduce":
            args = [*args, "--quick"]  # the full run is checked by its own test
        if args[1] == "evaluate":  # the full run is docs/evaluation.md
            args = [*args, "--shapes", "Line", "--folds", "1", "--no-plot"]
        run(args, tmp_path)
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


def test_own_data_examples_are_the_readmes():
    # the README's quickstart, which tests/test_readme.py runs on the
    # recordings of the guide's picture
    guide = _examples("own_data.md", "## On the command line")
    quickstart = commands(README.read_text(encoding="utf-8"))[:3]
    assert [e[1] for e in guide] == ["fit", "generate", "plot"]
    assert guide == quickstart


def test_whole_robot_log_examples_run(tmp_path):
    pytest.importorskip("matplotlib")
    sys.path.insert(0, str(Path(__file__).parent / "io"))
    from lab_logs import FRANKA_COLUMNS, write_franka

    examples = _examples("own_data.md", "## A whole robot log")
    assert [e[1] for e in examples] == ["fit", "generate", "plot"]
    write_franka(tmp_path / "logs", n_demos=5, n=120)  # 27 columns, no time, 20 Hz
    assert (tmp_path / "logs" / "task0.csv").read_text().split("\n")[0] == ",".join(
        FRANKA_COLUMNS
    )
    for args in examples:
        run(args, tmp_path)
    path = read_csv(tmp_path / "task-path.csv")
    assert path.n_samples == 120 and path.t[-1] == 119 / 20
    assert not any(c.startswith("goal_") for c in path.columns)
    assert set(path.group_names) >= {"position", "orientation", "force", "joints"}
    assert (tmp_path / "task.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_ros_bag_examples_run(tmp_path):
    pytest.importorskip("rosbags")
    pytest.importorskip("matplotlib")
    from bag_samples import pick_place_messages, write_bag
    from ndlfd.io import read_bag

    examples = _examples("ros2.md", "# ROS 2 bags")
    assert [e[1] for e in examples] == ["fit", "generate", "generate", "plot"]
    # the picture's bags (docs/images/ros-pick-triads.png)
    (tmp_path / "bags").mkdir()
    for i in range(6):
        _, _, _, poses, grip = pick_place_messages(seed=i)
        write_bag(tmp_path / "bags" / f"pick{i}", {"/ee_pose": poses, "/gripper": grip})
    for args in examples:
        run(args, tmp_path)
    (path,) = read_bag(tmp_path / "pick.mcap", ["/ndlfd/path", "/ndlfd/path/gripper"])
    assert path.n_samples == 300 and path.t[-1] == 6.0
    assert path.group_names == ("position", "orientation", "gripper")
    assert (tmp_path / "pick.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def _trajectory(bag):
    """The one JointTrajectory of a bag: its joint names, times, positions, speeds."""
    from rosbags.rosbag2 import Reader

    from bag_samples import STORE

    with Reader(bag) as reader:
        (conn,) = reader.connections
        ((_, _, raw),) = list(reader.messages())
        msg = STORE.deserialize_cdr(raw, conn.msgtype)
    assert conn.msgtype == "trajectory_msgs/msg/JointTrajectory"
    stamps = [
        p.time_from_start.sec + p.time_from_start.nanosec * 1e-9 for p in msg.points
    ]
    P = np.array([p.positions for p in msg.points])
    V = np.array([p.velocities for p in msg.points])
    return list(msg.joint_names), np.array(stamps), P, V


def test_joint_trajectory_examples_run(tmp_path):
    pytest.importorskip("rosbags")
    from bag_samples import joint_state, write_bag

    examples = _examples("robots.md", "## Joint trajectories for a ROS 2 controller")
    assert [e[1] for e in examples] == ["fit", "generate"]  # not ros2 bag play
    # three recordings of two joints on /joint_states at 50 Hz, moving from
    # the first sample to the last (a reach cut out of a longer motion)
    (tmp_path / "arm_bags").mkdir()
    rng = np.random.default_rng(0)
    for i in range(3):
        s = np.linspace(0.0, 1.0, 60)
        q = np.column_stack([s, 1 - s]) + rng.normal(0, 1e-3, (60, 2))
        ns = 1_700_000_000 * 10**9 + np.arange(60) * 20_000_000
        msgs = [(int(k), joint_state(int(k), ["a", "b"], v))
                for k, v in zip(ns, q, strict=True)]  # fmt: skip
        write_bag(tmp_path / "arm_bags" / f"reach{i}", {"/joint_states": msgs})
    for args in examples:
        run(args, tmp_path)
    names, t, _, V = _trajectory(tmp_path / "traj_bag")
    assert names == ["joint_1", "joint_2"]
    # as the guide says: 601 samples over 6 s, moving at both ends, come to
    # rest along the path: 661 points over 6.6 s, zero velocity at both ends
    assert len(t) == 661 and t[-1] == pytest.approx(6.6, abs=1e-9)
    assert np.all(np.diff(t) > 0) and not np.any(V[[0, -1]])


def test_lerobot_examples_run(tmp_path):
    pytest.importorskip("pyarrow")
    from lerobot_writer import write_lerobot

    examples = _examples("lerobot.md", "## Reading a dataset")
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
        run(args, tmp_path)
    pick = (tmp_path / "pick.csv").read_text().splitlines()[0]
    assert pick == "timestamp,x,y,z,roll,pitch,yaw,gripper,vx,vy,vz"
    assert f"`{pick}`" in _text("lerobot.md")  # as it says


def test_so101_examples_run(tmp_path):
    pytest.importorskip("pyarrow")
    pytest.importorskip("matplotlib")
    from lerobot_writer import SO101_STATE, write_so101
    from ndlfd.io import read_parquet

    examples = _examples("lerobot.md", "## An SO-101 arm")
    assert [e[1] for e in examples] == ["fit", "generate", "generate", "plot"]
    write_so101(tmp_path / "so101_pick", n_demos=12)  # LeRobot v3.0, as it writes
    for args in examples:
        run(args, tmp_path)
    header = (tmp_path / "next.csv").read_text().splitlines()[0]
    assert header == ",".join(["timestamp", *SO101_STATE])
    assert f"`{header}`" in _text("lerobot.md")
    back = read_parquet(tmp_path / "next.parquet")
    assert back.groups == ("joints",) * 5 + ("gripper",)
    assert (tmp_path / "so101.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_so101_to_ros2_examples_run(tmp_path):
    pytest.importorskip("pyarrow")
    pytest.importorskip("rosbags")
    from lerobot_writer import write_so101

    heading = "## From a LeRobot SO-101 dataset to a ROS 2 controller"
    examples = _examples("robots.md", heading)
    assert [e[1] for e in examples] == ["fit", "generate"]
    write_so101(tmp_path / "so101_pick", n_demos=12)  # LeRobot v3.0, as it writes
    for args in examples:
        run(args, tmp_path)
    flags = examples[1]
    names = flags[flags.index("--joint-names") + 1].split(",")
    start = [float(v) for v in flags[flags.index("--start") + 1][7:].split(",")]
    joint_names, stamps, P, V = _trajectory(tmp_path / "so101_traj")
    assert joint_names == names
    # radians, from the given start, within 30 deg/s per joint, at rest at both ends
    np.testing.assert_allclose(P[0, :5], np.deg2rad(start), rtol=0, atol=1e-9)
    assert np.abs(V[:, :5]).max() <= np.deg2rad(30.0) * (1 + 1e-3)
    assert np.all(V[[0, -1]] == 0.0)
    assert np.all(np.diff(stamps) > 0) and stamps[-1] > 4.0  # slowed down
