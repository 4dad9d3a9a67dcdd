import numpy as np
import pytest

from ndlfd._errors import DataFileError
from ndlfd.io import (
    ColumnMapping,
    group_of_column,
    read_csv,
    read_demos,
)


def test_group_of_column_convention():
    assert group_of_column("x") == ("position", "x")
    assert group_of_column("p7") == ("position", "p7")
    assert group_of_column("vz") == ("velocity", "vz")
    assert group_of_column("qw") == ("orientation", "qw")
    assert group_of_column("f2") == ("force", "f2")
    assert group_of_column("tool.angle") == ("tool", "angle")
    assert group_of_column("speed") is None
    assert group_of_column(".x") is None and group_of_column("g.") is None


def test_read_csv_explicit_groups_drop_and_orders(tmp_path):
    p = tmp_path / "robot.csv"
    p.write_text("time,X,Y,label,ox,oy,oz,ow\n0,1,2,7,0,0,0,1\n0.5,2,3,7,0,0,0,-1\n")
    d = read_csv(
        p,
        time_column="time",
        groups={"position": ["X", "Y"], "orientation": ["ox", "oy", "oz", "ow"]},
        quaternion_order="xyzw",
        drop=["label"],
    )
    assert d.columns == ("X", "Y", "ow", "ox", "oy", "oz")
    np.testing.assert_array_equal(d.get("orientation"), [[1, 0, 0, 0], [1, 0, 0, 0]])
    np.testing.assert_array_equal(d.t, [0, 0.5])
    # quaternion columns named qw.. are ordered by name, whatever the file order
    q = tmp_path / "q.csv"
    q.write_text("t,qx,qy,qz,qw\n0,0.6,0,0,0.8\n")
    e = read_csv(q, quaternion_order="xyzw")
    assert e.columns == ("qw", "qx", "qy", "qz")
    np.testing.assert_array_equal(e.X, [[0.8, 0.6, 0, 0]])
    assert read_csv(q) == e
    # no time column: the row number is the time
    r = tmp_path / "r.csv"
    r.write_text("x,y\n0,0\n1,1\n3,3\n")
    np.testing.assert_array_equal(read_csv(r, time_column=None).t, [0.0, 1.0, 2.0])


def test_read_csv_matches_names_in_any_case(tmp_path):
    p = tmp_path / "d.csv"
    p.write_text("TIME,Pos_X,pos_y,QW,qx,qy,qz\n0,1,2,1,0,0,0\n0.5,2,3,1,0,0,0\n")
    d, maps = read_demos(
        p, groups={"position": ["pos_x", "POS_Y"]}, return_mappings=True
    )
    assert d[0].columns == ("Pos_X", "pos_y", "QW", "qx", "qy", "qz")
    assert d[0].groups == ("position",) * 2 + ("orientation",) * 4
    np.testing.assert_array_equal(d[0].t, [0, 0.5])
    assert maps[0] == ColumnMapping(
        str(p),
        "TIME",
        (("position", ("Pos_X", "pos_y")), ("orientation", ("QW", "qx", "qy", "qz"))),
        order=("Pos_X", "pos_y", "QW", "qx", "qy", "qz"),
    )
    assert maps[0].group_names == ("position", "orientation")
    assert read_csv(p, time_column="Time", drop=["QW", "QX", "QY", "QZ"],
                    groups={"position": ["POS_X", "POS_Y"]}).n_dims == 2  # fmt: skip
    # an exact match wins; two names equal up to case are ambiguous
    q = tmp_path / "q.csv"
    q.write_text("t,x,X,Pos,POS\n0,1,2,3,4\n")
    d = read_csv(q, groups={"a": ["x"], "b": ["X"]}, drop=["Pos", "POS"])
    assert d.columns == ("x", "X")
    with pytest.raises(DataFileError, match=r"'pos'.*\['Pos', 'POS'\], which differ"):
        read_csv(q, time_column="T", groups={"position": ["pos"]})
    with pytest.raises(DataFileError, match=r"names 'Z', but there is no such column"):
        read_csv(q, time_column="T", groups={"position": ["Z"]})


def test_read_csv_explicit_group_owns_its_conventional_columns(tmp_path):
    p = tmp_path / "d.csv"
    p.write_text("t,pos_x,pos_y,z\n0,1,2,3\n")
    with pytest.raises(
        DataFileError,
        match=r"column 'z' belongs to group 'position' by its name, but groups"
        r" position does not list it; .* drop=",
    ):
        read_csv(p, groups={"position": ["pos_x", "pos_y"]})
    d = read_csv(p, groups={"position": ["pos_x", "pos_y", "z"]})
    assert d.columns == ("pos_x", "pos_y", "z")
