"""Names as labs export them, measured and commanded sets, globs (issue 37)."""

import numpy as np
import pytest
from lab_logs import FRANKA_COLUMNS, franka_arrays, write_franka

from ndlfd import DataFileError, NdlfdWarning
from ndlfd._repairs import Measured, collecting_repairs, summary_warnings
from ndlfd.io import group_of_column, lab_name, read_csv, read_demos


def test_lab_names_against_a_hand_made_table():
    table = {
        "current_pos_x": ("position", "current", "x"),
        "pos_y": ("position", "", "y"),
        "position_z": ("position", "", "z"),
        "EE_Pos_Z": ("position", "ee", "z"),
        "current_orientation_w": ("orientation", "current", "w"),
        "quat_x": ("orientation", "", "x"),
        "q_w": ("orientation", "", "w"),
        "goal_pos_x": ("position", "goal", "x"),
        "force_x": ("force", "", "x"),
        "wrench_torque_y": ("torque", "wrench", "y"),
        "joint_1": ("joints", "", "1"),
        "joint7": ("joints", "", "7"),
        "q3": ("joints", "", "3"),
        "actual_q_0": ("joints", "actual", "0"),
        "rotvec_z": ("orientation", "", "z"),
        "ang_vel_x": ("angular_velocity", "", "x"),
    }
    for name, want in table.items():
        assert lab_name(name) == want, name
    for name in ("speed", "pos_w", "force_w", "obj_x", "stamp", "t"):
        assert lab_name(name) is None, name
    # the naming convention is unchanged (it is tried first)
    assert group_of_column("pos_x") is None
    assert group_of_column("qx") == ("orientation", "qx")


def test_franka_log_reads_every_group_and_leaves_the_goal_out(tmp_path):
    datas = write_franka(tmp_path / "logs", n_demos=2)
    with pytest.warns(NdlfdWarning, match=r"left out 14 commanded column\(s\)") as rec:
        demos, maps = read_demos(tmp_path / "logs", rate=20, return_mappings=True)
    goal = "goal_pos_x,goal_pos_y,goal_pos_z,goal_orientation_w,goal_orientation_x,"
    goal += "goal_orientation_y,goal_orientation_z"
    assert f"task0.csv ({goal})" in str(rec[0].message)
    d, m = demos[0], maps[0]
    assert d.group_names == ("position", "orientation", "force", "torque", "joints")
    assert str(m) == (
        "time=(row number) / 20 Hz; position=current_pos_x,current_pos_y,"
        "current_pos_z; orientation=current_orientation_w,current_orientation_x,"
        "current_orientation_y,current_orientation_z; force=force_x,force_y,force_z;"
        " torque=torque_x,torque_y,torque_z; joints=joint_1,joint_2,joint_3,joint_4,"
        f"joint_5,joint_6,joint_7; left out {goal} (commanded)"
    )
    assert m.left_out == tuple(goal.split(","))
    data = datas[0]
    col = {c: j for j, c in enumerate(FRANKA_COLUMNS)}
    np.testing.assert_array_equal(d.t, np.arange(data.shape[0]) / 20)
    for group, names in m.groups:
        want = data[:, [col[c] for c in names]]
        if group == "orientation":  # q or -q: the same rotation
            want = want * np.sign(want[:, :1] * d.get(group)[:, :1])
        np.testing.assert_array_equal(d.get(group), want)


def test_library_alone_warns_once_per_file_and_the_goal_is_learned_on_request(
    tmp_path,
):
    write_franka(tmp_path, n_demos=1)
    p = tmp_path / "task0.csv"
    with pytest.warns(NdlfdWarning, match=r"left out the commanded column\(s\)"
                      r" goal_pos_x, goal_pos_y, goal_pos_z, goal_orientation_w,"
                      r" .* beside the measured current_pos_x"):  # fmt: skip
        read_csv(p, time_column=None)
    # the goal instead: a glob for the group, the measured ones dropped by glob
    d = read_csv(p, time_column=None, groups={"position": ["goal_pos_*"]},
                 drop=["CURRENT_POS_*", "goal_orientation_*"])  # fmt: skip
    assert d.columns[:3] == ("goal_pos_x", "goal_pos_y", "goal_pos_z")
    assert d.group_names[0] == "position"
    with pytest.raises(DataFileError, match=r"drop names unknown column\(s\)"
                       r" \['nothing_\*'\]"):  # fmt: skip
        read_csv(p, time_column=None, drop=["goal_*", "nothing_*"])
    with pytest.raises(DataFileError, match=r"the pattern 'j\*_9', which matches no"):
        read_csv(p, time_column=None, groups={"joints": ["j*_9"]})


def test_sets_that_cannot_be_told_give_a_mapping_to_paste(tmp_path):
    p = tmp_path / "arms.csv"
    # two sets of one group, not hands (left_/right_ with 3 columns are
    # two hands' poses: tests/io/test_io_two_arms.py)
    names = ["t", "arm1_pos_x", "arm1_pos_y", "arm2_pos_x", "arm2_pos_y"]
    p.write_text(",".join(names) + "\n0,1,2,3,4\n1,1,2,3,4\n")
    with pytest.raises(DataFileError) as err:
        read_csv(p)
    msg = str(err.value)
    assert "2 sets of columns name the group 'position'" in msg
    line = msg.split("in place of your groups/drop: ")[1]
    assert line == (
        "groups={'position': ['arm1_pos_x', 'arm1_pos_y'], 'arm2_xy':"
        " ['arm2_pos_x', 'arm2_pos_y']}"
    )
    # pasted, it reads (a second set of 2 columns is no hand: hands are 3-D)
    pasted = {"position": ["arm1_pos_x", "arm1_pos_y"],
              "arm2_xy": ["arm2_pos_x", "arm2_pos_y"]}  # fmt: skip
    d = read_csv(p, groups=pasted)
    assert d.group_names == ("position", "arm2_xy")


def test_unknown_names_error_gives_groups_and_drop(tmp_path):
    p = tmp_path / "a.csv"
    p.write_text("t,pos_x,pos_y,speed\n0,1,2,3\n1,1,2,3\n")
    with pytest.raises(DataFileError, match=r"cannot tell the group of column\(s\)"
                       r" \['speed'\].*in place of your groups/drop:"
                       r" groups=\{'position': \['pos_x', 'pos_y'\]\},"
                       r" drop=\['speed'\]"):  # fmt: skip
        read_csv(p)


def test_quaternion_summary_gives_the_deviation_measured(tmp_path):
    """Full-precision quaternions off by 4.8e-6 are not 'off by up to 1e-3'."""
    write_franka(tmp_path / "logs", n_demos=2, norm_off=4.8e-6)
    with pytest.warns(NdlfdWarning, match=r"renormalized 125 quaternion\(s\) whose"
                      r" norm was off by up to 4\.8e-06 \(up to 1e-3 is"
                      r" repaired\) in 2 files"):  # fmt: skip
        read_demos(tmp_path / "logs", rate=20, drop=["goal_*"])
    with collecting_repairs() as log:  # each file's record carries its measure
        read_csv(tmp_path / "logs" / "task1.csv", time_column=None, drop=["goal_*"])
    ((kind, count, _),) = log
    assert kind == "quaternions" and count == 65
    assert kind.worst == pytest.approx(4.8e-6, rel=1e-3)
    with pytest.warns(NdlfdWarning) as rec:
        summary_warnings([(Measured("quaternions", 4.8e-6), "a.csv", 60),
                          (Measured("quaternions", 2e-6), "b.csv", 65)])  # fmt: skip
    text = str(rec[0].message)
    assert text.startswith(
        "renormalized 125 quaternion(s) whose norm was off by up to 4.8e-06"
    )
    assert "1e-3 (logged" not in text
    # a Measured kind travels as its name (pickled for process workers)
    import pickle

    k = pickle.loads(pickle.dumps(Measured("quaternions", 3e-6)))
    assert k == "quaternions" and k.worst == 3e-6 and hash(k) == hash("quaternions")


def test_names_without_prefix_and_the_convention_together(tmp_path):
    p = tmp_path / "a.csv"
    p.write_text("time,x,y,z,goal_pos_x,goal_pos_y,goal_pos_z,q1,q2\n"
                 "0,0,0,0,1,1,1,0.1,0.2\n1,1,1,1,1,1,1,0.2,0.3\n")  # fmt: skip
    with pytest.warns(NdlfdWarning, match="beside the measured x, y, z"):
        d = read_csv(p)
    assert d.columns == ("x", "y", "z", "q1", "q2")
    assert d.group_names == ("position", "joints")
    assert franka_arrays(3).shape == (3, 27)


# l_/r_: the short hands of some bimanual logs (ndlfd.io._names' rule)


def _write(path, names, X):
    lines = [",".join(names)] + [",".join(repr(float(v)) for v in row) for row in X]
    path.write_text("\n".join(lines) + "\n")
    return path


def _short_log(n=8, seed=0):
    """Per hand x, y, z, a unit quaternion w, x, y, z, 3 joints, the gripper."""
    rng = np.random.default_rng(seed)
    per_hand = ["x", "y", "z", "qw", "qx", "qy", "qz", "joint1", "joint2",
                "joint3", "gripper"]  # fmt: skip
    names = ["t"] + [f"{h}_{c}" for h in "lr" for c in per_hand]
    X = rng.normal(size=(n, len(names)))
    X[:, 0] = np.arange(n) * 0.1
    for q in (slice(4, 8), slice(15, 19)):  # w > 0.5: no sign flip to undo
        X[:, q] = np.column_stack([np.full(n, 2.0), X[:, q][:, 1:] * 0.5])
        X[:, q] /= np.linalg.norm(X[:, q], axis=1, keepdims=True)
    return names, X


def test_short_hands_read_as_left_and_right(tmp_path):
    names, X = _short_log()
    p = _write(tmp_path / "bimanual.csv", names, X)
    (d,), (m,) = read_demos(p, return_mappings=True)
    col = {c: j for j, c in enumerate(names)}
    want = {  # worked out by hand from the header
        "left_position": ["l_x", "l_y", "l_z"],
        "left_orientation": ["l_qw", "l_qx", "l_qy", "l_qz"],
        "left_joints": ["l_joint1", "l_joint2", "l_joint3"],
        "gripper": ["l_gripper", "r_gripper"],
        "right_position": ["r_x", "r_y", "r_z"],
        "right_orientation": ["r_qw", "r_qx", "r_qy", "r_qz"],
        "right_joints": ["r_joint1", "r_joint2", "r_joint3"],
    }
    assert dict((g, list(c)) for g, c in m.groups) == want
    assert str(m) == "time=t; " + "; ".join(
        f"{g}={','.join(c)}" for g, c in want.items()
    )
    for group, cols in want.items():
        np.testing.assert_allclose(
            d.get(group), X[:, [col[c] for c in cols]], rtol=0, atol=1e-15
        )
    # the same log spelt left_/right_ reads into the same groups and values
    long = [c.replace("l_", "left_", 1).replace("r_", "right_", 1) for c in names]
    e = read_csv(_write(tmp_path / "long.csv", long, X))
    assert e.groups == d.groups and np.array_equal(e.X, d.X)


def test_short_hand_rule_edge_cases():
    from ndlfd.io._names import bare_name, lab_groups

    def lab(names):
        return lab_groups(names, group_of_column, group_of_column)

    hands = ["l_x", "l_y", "l_z", "r_x", "r_y", "r_z"]
    # a name whose rest says no group is nobody's hand: unknown, not swallowed
    found = lab([*hands, "r_squared", "l_time"])
    assert found.unknown == ["r_squared", "l_time"]
    assert found.groups == {"left_position": hands[:3], "right_position": hands[3:]}
    # r_x, r_y, r_z beside x, y, z: no l_ set like them, so no hands; r is a
    # rotation's stem, three orientation columns that need a representation
    found = lab(["x", "y", "z", "r_x", "r_y", "r_z"])
    assert found.groups == {"position": ["x", "y", "z"]}
    assert found.unsure == [("orientation", ["r_x", "r_y", "r_z"])]
    # l_ and r_ that say no group in common are not two hands
    assert lab(["l_x", "l_y", "l_z", "r_gripper"]).unknown == [
        "l_x", "l_y", "l_z", "r_gripper"
    ]  # fmt: skip
    # mirrored by any group in common: the joints here
    assert lab(["L_Joint1", "r_joint1", "r_gripper"]).groups == {
        "left_joints": ["L_Joint1"],
        "right_joints": ["r_joint1"],
        "gripper": ["r_gripper"],
    }
    # one hand spelt two ways: two sets of its group, never merged
    found = lab([*hands, "left_x", "left_y", "left_z"])
    assert found.ambiguous == [("left_position", [hands[:3], ["left_x", "left_y",
                                                             "left_z"]])]  # fmt: skip
    # a commanded set of a short hand is left out beside its measured one
    found = lab(["l_cur_pos_x", "l_goal_pos_x", "r_pos_x"])
    assert found.groups == {"left_position": ["l_cur_pos_x"],
                            "right_position": ["r_pos_x"]}  # fmt: skip
    assert found.left_out == ["l_goal_pos_x"]
    # Euler angles of a short hand, and bare names
    found = lab(["l_roll", "l_pitch", "l_yaw", "r_roll", "r_pitch", "r_yaw"])
    assert found.representation == {
        "left_orientation": "euler-xyz",
        "right_orientation": "euler-xyz",
    }
    assert bare_name("l_yaw", "left") == "yaw"
    assert bare_name("r_squared", "left") == "r_squared"
    # single names keep what lab_name said before
    assert lab_name("r_x") == ("orientation", "", "x")
    assert lab_name("l_x") is None


def test_a_column_that_only_starts_like_a_hand_is_reported(tmp_path):
    names, X = _short_log()
    names = [*names, "r_squared"]
    X = np.column_stack([X, np.linspace(0, 1, len(X))])
    p = _write(tmp_path / "fit.csv", names, X)
    with pytest.raises(DataFileError) as err:
        read_csv(p)
    msg = str(err.value)
    assert "cannot tell the group of column(s) ['r_squared']" in msg
    assert msg.endswith("drop=['r_squared']")
    d = read_csv(p, drop=["r_squared"])
    assert "r_squared" not in d.columns
    assert d.group_names[:2] == ("left_position", "left_orientation")
