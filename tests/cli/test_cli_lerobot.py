"""``ndlfd fit DATASET_DIR``: LeRobot datasets, Euler angles and grippers."""

import sys

import numpy as np
import pytest

pytest.importorskip("pyarrow")

from cli_helpers import cli, run

from lerobot_writer import SO101_STATE, write_lerobot, write_so101
from ndlfd.io import read_csv, read_lerobot, read_parquet
from ndlfd.learner import KeypointHMM

STATE = ["x", "y", "z", "roll", "pitch", "yaw", "gripper"]


def pick_dataset(root, n_demos=6, version="v3.0", seed=0):
    """A pick: reach, close the gripper half way, lift; orientation turning."""
    rng = np.random.default_rng(seed)
    eps = []
    for i in range(n_demos):
        n = 60 + 7 * i
        s = np.linspace(0, 1, n)
        state = np.column_stack(
            [
                s,
                0.3 * np.sin(np.pi * s),
                0.2 * s**2,
                0.1 * s,
                -0.2 * s,
                0.8 * s - 0.4,
                (s > 0.5 + 0.01 * i).astype(float),
            ]
        )
        state[:, :6] += rng.normal(0, 0.003, (n, 6))
        eps.append({"observation.state": state, "action": state[:, :3] * 2})
    names = {"observation.state": STATE, "action": ["vx", "vy", "vz"]}
    return write_lerobot(root, eps, names, version=version, per_file=4), eps


def test_fit_a_v3_dataset_with_no_other_flag(tmp_path, capsys):
    root, _ = pick_dataset(tmp_path / "pick")
    model = tmp_path / "m.npz"
    rc, err = cli(capsys, "fit", root, "-o", model)
    assert rc == 0
    assert err[0] == (
        "read 6 demonstration(s) from 6 LeRobot episode(s): time=timestamp;"
        " position=x,y,z; orientation=roll,pitch,yaw (Euler xyz); gripper=gripper"
        " (LeRobot v3.0, observation.state)"
    )
    m = KeypointHMM.load(model)
    assert m.n_demos_ == 6
    # position, velocity and orientation learned; the gripper is mapped as a
    # group and learned once the learner's AUTO_GROUPS has it
    assert {"position", "velocity", "orientation"} <= set(m.groups_)
    if "gripper" not in m.groups_:
        assert err[-1].startswith("not learned: gripper")


@pytest.mark.parametrize("version", ["v2.1", "v3.0"])
def test_episodes_feature_and_the_generated_euler_angles(tmp_path, capsys, version):
    root, _ = pick_dataset(tmp_path / "pick", version=version)
    model = tmp_path / "m.npz"
    rc, err = cli(capsys, "fit", root, "-o", model, "--episodes", "0:4",
                  "--groups", "position,velocity,orientation,gripper",
                  "--levels", "gripper=2")  # fmt: skip
    assert rc == 0, err
    assert err[0].startswith("read 4 demonstration(s) from 4 LeRobot episode(s)")
    out = tmp_path / "path.csv"
    rc, err = cli(capsys, "generate", model, "--like", root, "--episodes", "5",
                  "--dense", "-o", out)  # fmt: skip
    assert rc == 0, err
    header = out.read_text().splitlines()[0]
    # the dataset's time column and names in its order; the derived velocity after
    assert header == "timestamp,x,y,z,roll,pitch,yaw,gripper,vx,vy,vz"
    path = read_csv(out)  # read back: roll, pitch, yaw are orientation again
    (like,) = read_lerobot(root, episodes=[5])
    np.testing.assert_array_equal(path.t, like.t)
    assert path.group_names == ("position", "orientation", "gripper", "velocity")
    # the yaw ramps from -0.4 to 0.4 like the demonstrations'
    yaw = np.loadtxt(out, delimiter=",", skiprows=1)[:, 6]
    assert yaw[0] == pytest.approx(-0.4, abs=0.1)
    assert yaw[-1] == pytest.approx(0.4, abs=0.1)
    rc, err = cli(capsys, "fit", root, "-o", model, "--feature", "action")
    assert rc == 0, err
    assert "position=vx,vy,vz" not in err[0] and "velocity=vx,vy,vz" in err[0]


def test_errors_are_one_line(tmp_path):
    root, _ = pick_dataset(tmp_path / "pick", n_demos=2)
    model = tmp_path / "m.npz"
    for flags, message in [
        (
            ["--feature", "observation.effort"],
            "has no feature 'observation.effort'; its features are"
            " observation.state, action, observation.images.top",
        ),
        (["--episodes", "2"], "has no episode 2; its 2 episodes are 0-1"),
        (["--episodes", "1-3"], "episodes must look like 0:40"),
        (["--euler", "xyw"], "--euler must be three axes from xyz"),
    ]:
        r = run("fit", root, "-o", model, *flags)
        assert r.returncode == 2, r.stderr
        lines = r.stderr.strip().splitlines()
        assert len(lines) == 1 and message in lines[0], r.stderr


def test_dataset_flags_need_a_dataset(tmp_path, capsys):
    f = tmp_path / "a.csv"
    f.write_text("t,x\n0,0\n1,1\n2,0\n")
    rc, err = cli(capsys, "fit", f, "-o", tmp_path / "m.npz", "--episodes", "0:2")
    assert rc == 2
    assert "--episodes selects from a LeRobot dataset" in err[-1]


def test_quaternion_order_on_the_command_line(tmp_path, capsys):
    n = 30
    s = np.linspace(0, 1, n)
    half = 0.5 * s
    rows = np.column_stack([s, s, s**2, 0 * s, 0 * s, np.sin(half), np.cos(half)])
    text = "t,x,y,a,b,c,d\n" + "\n".join(",".join(map(repr, r)) for r in rows.tolist())
    (tmp_path / "q.csv").write_text(text + "\n")
    model = tmp_path / "m.npz"
    args = ["fit", tmp_path / "q.csv", "-o", model, "--group", "orientation=a,b,c,d"]
    rc, err = cli(capsys, *args, "--quaternion-order", "xyzw")
    assert rc == 0, err
    assert "orientation=d,a,b,c" in err[0]  # listed w, x, y, z
    m = KeypointHMM.load(model)
    assert "orientation" in m.groups_


def test_without_pyarrow_says_how_to_install_it(tmp_path, capsys, monkeypatch):
    root, _ = pick_dataset(tmp_path / "pick", n_demos=2)
    for name in ("pyarrow", "pyarrow.parquet", "pyarrow.compute"):
        monkeypatch.setitem(sys.modules, name, None)  # import pyarrow now fails
    rc, err = cli(capsys, "fit", root, "-o", tmp_path / "m.ndlfd")
    assert rc == 2
    assert err == [
        "ndlfd fit: error: reading LeRobot datasets needs pyarrow; install it"
        ' with: pip install "ndlfd[lerobot]"'
    ]


def test_a_gripper_column_of_another_name(tmp_path, capsys):
    n = 40
    s = np.linspace(0, 1, n)
    rows = np.column_stack([s, s, s**2, s > 0.5]).tolist()
    text = "t,x,y,hand\n" + "\n".join(",".join(map(repr, r)) for r in rows)
    (tmp_path / "g.csv").write_text(text + "\n")
    model = tmp_path / "m.npz"
    rc, err = cli(capsys, "fit", tmp_path / "g.csv", "-o", model,
                  "--group", "gripper=hand", "--groups", "position,gripper",
                  "--levels", "position=20,gripper=2")  # fmt: skip
    assert rc == 0, err
    assert "gripper=hand" in err[0]
    assert KeypointHMM.load(model).groups_ == ("position", "gripper")


@pytest.mark.parametrize("version", ["v2.1", "v3.0"])
def test_so101_fit_and_generate_in_one_attempt(tmp_path, capsys, version):
    root, _ = write_so101(tmp_path / "so101", n_demos=5, version=version)
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", root, "-o", model)
    assert rc == 0, err
    assert err[0] == (
        "read 5 demonstration(s) from 5 LeRobot episode(s): time=timestamp;"
        " joints=shoulder_pan.pos,shoulder_lift.pos,elbow_flex.pos,wrist_flex.pos,"
        f"wrist_roll.pos; gripper=gripper.pos (LeRobot {version}, observation.state)"
    )
    assert not any(line.startswith("not learned") for line in err)
    m = KeypointHMM.load(model)
    assert m.groups_ == ("gripper", "joints")
    out = tmp_path / "path.csv"
    rc, err = cli(capsys, "generate", model, "--like", root, "--episodes", "3",
                  "--dense", "-o", out, "--std", tmp_path / "std.csv")  # fmt: skip
    assert rc == 0, err
    header = out.read_text().splitlines()[0].split(",")
    assert header == ["timestamp", *SO101_STATE]  # the dataset's names and order
    assert tmp_path.joinpath("std.csv").read_text().splitlines()[0].split(",") == (
        header
    )
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    (like,) = read_lerobot(root, episodes=[3])
    np.testing.assert_array_equal(table[:, 0], like.t)  # the stamps exactly
    # each joint follows the demonstration it was timed like (same shape, noise)
    err_deg = np.abs(table[:, 1:6] - like.X[:, :5]).max(axis=0)
    assert np.all(err_deg < 0.05 * np.ptp(like.X[:, :5], axis=0) + 2.0), err_deg
    # read back with the same names: the time column and the groups
    again = read_csv(out)
    assert again.columns == like.columns and again.groups == like.groups


def test_so101_generate_a_parquet_episode_and_fit_it_again(tmp_path, capsys):
    root, _ = write_so101(tmp_path / "so101", n_demos=4)
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", root, "-o", model, "--feature", "action")
    assert rc == 0, err
    out = tmp_path / "path.parquet"
    rc, err = cli(capsys, "generate", model, "--like", root, "--feature", "action",
                  "--episodes", "2", "--dense", "-o", out)  # fmt: skip
    assert rc == 0, err
    pq = pytest.importorskip("pyarrow.parquet")
    assert pq.read_schema(out).names[-1] == "action"  # the input's feature
    (like,) = read_lerobot(root, feature="action", episodes=[2])
    got = KeypointHMM.load(model).generate(like, dense=True)
    path = read_parquet(out)
    assert path.columns == like.columns and path.groups == like.groups
    np.testing.assert_array_equal(path.t, like.t)  # float32 stamps, as read
    np.testing.assert_array_equal(
        path.get("joints"), got.get("joints").astype(np.float32)
    )
    rc, err = cli(capsys, "fit", out, "-o", tmp_path / "again.ndlfd")
    assert rc == 0, err
    assert "joints=shoulder_pan.pos" in err[0] and "time=timestamp" in err[0]


def test_so101_observed_prefix_with_episodes_and_a_float64_clock(tmp_path, capsys):
    # --episodes selects the --like episode, not from the --observed CSV; the
    # robot logged its prefix on the float64 clock k / 30, the dataset float32
    root, _ = write_so101(tmp_path / "so101", n_demos=5)
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", root, "-o", model, "--episodes", "0:4")
    assert rc == 0, err
    (like,) = read_lerobot(root, episodes=[4])
    k = 12
    rows = np.column_stack([np.arange(k) / 30.0, like.X[:k]])
    prefix = tmp_path / "prefix.csv"
    prefix.write_text(
        ",".join(["time", *SO101_STATE]) + "\n"
        + "\n".join(",".join(map(repr, r)) for r in rows.tolist()) + "\n"
    )  # fmt: skip
    out = tmp_path / "next.csv"
    rc, err = cli(capsys, "generate", model, "--like", root, "--episodes", "4",
                  "--observed", prefix, "-o", out)  # fmt: skip
    assert rc == 0, err
    assert err[-1].endswith(f"(the first {k} observed) -> {out}")
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_array_equal(table[:k, 0], rows[:, 0])  # the prefix's stamps
    np.testing.assert_array_equal(table[k:, 0], like.t[k:])  # then the episode's
    np.testing.assert_allclose(table[:k, 1:], like.X[:k], rtol=1e-9)
