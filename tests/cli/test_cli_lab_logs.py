"""Real logs in, whole (issue 37): lab names, rotation vectors, .npy, --rate."""

import shlex
import sys
from pathlib import Path

import numpy as np
from cli_helpers import cli
from scipy.spatial.transform import Rotation

sys.path.insert(0, str(Path(__file__).parents[1] / "io"))
from lab_logs import FRANKA_COLUMNS, franka_arrays, write_franka, write_ur

from ndlfd.io import read_table
from ndlfd.learner import KeypointHMM

GROUPS = "position,orientation,force,torque,joints"


def test_franka_log_without_time_first_try_with_rate_only(tmp_path, capsys):
    folder = tmp_path / "logs"
    write_franka(folder, n_demos=4, norm_off=4.8e-6)
    model = tmp_path / "m.ndlfd"
    # the default fit, every group of 23 learned columns at default levels
    rc, err = cli(capsys, "fit", folder, "--rate", 20, "--groups", GROUPS,
                  "-o", model)  # fmt: skip
    assert rc == 0, err
    assert err[0].startswith(
        "read 4 demonstration(s) from 4 file(s): time=(row number) / 20 Hz;"
        " position=current_pos_x,current_pos_y,current_pos_z; orientation="
    )
    assert "torque=torque_x,torque_y,torque_z; joints=joint_1," in err[0]
    assert "left out goal_pos_x,goal_pos_y,goal_pos_z,goal_orientation_w," in err[0]
    warned = [line for line in err if "warning:" in line]
    assert any("left out 28 commanded column(s)" in w for w in warned), warned
    # the quaternion repair gives the deviation measured, not the tolerance
    quat = [w for w in warned if "renormalized" in w]
    assert quat and "off by up to 4.8e-06" in quat[0], quat
    fitted = KeypointHMM.load(model)
    assert fitted.n_demos_ == 4
    assert fitted.groups == tuple(GROUPS.split(","))
    # plot reads the same way
    rc, err = cli(capsys, "plot", folder, "--rate", 20, "-o", tmp_path / "p.png")
    assert rc == 0, err
    assert (tmp_path / "p.png").read_bytes()[:4] == b"\x89PNG"
    # generate --like the very file: its length, stamps k / 20 Hz
    like = folder / "task2.csv"
    out = tmp_path / "g.csv"
    rc, err = cli(capsys, "generate", model, "--like", like, "--rate", 20,
                  "--dense", "-o", out)  # fmt: skip
    assert rc == 0, err
    names, data = read_table(out)
    n = franka_arrays(70, seed=2).shape[0]
    assert data.shape[0] == n
    np.testing.assert_array_equal(data[:, 0], np.arange(n) / 20)
    assert names[1:4] == ["current_pos_x", "current_pos_y", "current_pos_z"]
    # a file with its own stamps must agree with --rate
    timed = tmp_path / "timed.csv"
    timed.write_text("t,x\n0,0\n0.1,1\n0.2,2\n")
    rc, err = cli(capsys, "generate", model, "--like", timed, "--rate", 20,
                  "-o", tmp_path / "h.csv")  # fmt: skip
    assert rc == 2 and "are not k / 20 Hz" in err[-1]


def test_suggested_mapping_line_reads_when_pasted(tmp_path, capsys):
    folder = tmp_path / "logs"
    write_franka(folder, n_demos=3)
    for i in range(3):  # a column no name rule knows
        p = folder / f"task{i}.csv"
        lines = p.read_text().splitlines()
        lines = [lines[0] + ",status"] + [r + ",1.0" for r in lines[1:]]
        p.write_text("\n".join(lines) + "\n")
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", folder, "--rate", 20, "-o", model)
    assert rc == 2 and "cannot tell the group of column(s) ['status']" in err[-1]
    line = err[-1].split("in place of your --group/--drop: ")[1]
    assert line.endswith("--drop goal_pos_x,goal_pos_y,goal_pos_z,goal_orientation_w,"
                         "goal_orientation_x,goal_orientation_y,goal_orientation_z,"
                         "status")  # fmt: skip
    pasted = shlex.split(line)
    rc, err = cli(capsys, "fit", folder, "--rate", 20, *pasted, "--groups",
                  "position,joints", "--levels", 4, "-o", model)  # fmt: skip
    assert rc == 0, err
    assert "dropped goal_pos_x," in err[0] and "status" in err[0]


def test_ur_rotvec_log_fit_generate_plot(tmp_path, capsys):
    folder = tmp_path / "ur"
    logs = write_ur(folder, n_demos=3)
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", folder, "-o", model)
    assert rc == 2 and "rx, ry, rz hold an orientation of three numbers" in err[-1]
    assert "--group position=x,y,z --group orientation=rx,ry,rz:rotvec" in err[-1]
    m = ["--group", "orientation=rx,ry,rz:rotvec"]
    rc, err = cli(capsys, "fit", folder, *m, "--groups", "position,orientation",
                  "-o", model)  # fmt: skip
    assert rc == 0, err
    assert "orientation=rx,ry,rz (rotation vector)" in err[0]
    like = folder / "reach1.csv"
    out = tmp_path / "g.csv"
    rc, err = cli(capsys, "generate", model, "--like", like, "--dense", *m,
                  "-o", out)  # fmt: skip
    assert rc == 0, err
    names, data = read_table(out)
    assert names == ["t", "x", "y", "z", "rx", "ry", "rz"]
    # the generated rotation vectors are the model's quaternions, by scipy
    t, _, rv = logs[1]
    ref = KeypointHMM.load(model).generate(t, dense=True).get("orientation")
    got = Rotation.from_rotvec(data[:, 4:])
    want = Rotation.from_quat(ref, scalar_first=True)
    assert (got * want.inv()).magnitude().max() < 1e-8
    # near the demonstration (same rotation family), not an Euler reading
    assert (got * Rotation.from_rotvec(rv).inv()).magnitude().max() < 0.3
    rc, err = cli(capsys, "plot", folder, *m, "--path", out, "-o", tmp_path / "p.png")
    assert rc == 0, err


def test_npy_folder_fit_plot_generate(tmp_path, capsys):
    folder = tmp_path / "npy"
    folder.mkdir()
    cols = FRANKA_COLUMNS
    for i in range(3):
        np.save(folder / f"task{i}.npy", franka_arrays(50 + 5 * i, seed=i))
    names = ",".join(cols)
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", folder, "-o", model)
    assert rc == 2 and "name its columns with --columns a,b,c" in err[-1]
    rc, err = cli(capsys, "fit", folder, "--columns", names, "--rate", 20,
                  "--drop", "goal_*", "--groups", "position,orientation,joints",
                  "-o", model)  # fmt: skip
    assert rc == 0, err
    assert "(npy)" in err[0] and "dropped goal_pos_x" in err[0]
    # a sidecar instead of --columns
    for i in range(3):
        (folder / f"task{i}.columns.txt").write_text("\n".join(cols) + "\n")
    rc, err = cli(capsys, "plot", folder, "--rate", 20, "--drop", "goal_*",
                  "-o", tmp_path / "p.png")  # fmt: skip
    assert rc == 0, err
    out = tmp_path / "g.csv"
    rc, err = cli(capsys, "generate", model, "--like", folder / "task1.npy",
                  "--rate", 20, "--drop", "goal_*", "--dense", "-o", out)  # fmt: skip
    assert rc == 0, err
    _, data = read_table(out)
    np.testing.assert_array_equal(data[:, 0], np.arange(55) / 20)
