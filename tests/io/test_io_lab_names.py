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
