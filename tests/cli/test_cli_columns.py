"""Your own data, as it really comes: the column mapping flags (issue 11)."""

import sys

import numpy as np
import pytest
from cli_helpers import (
    assert_same_fit,
    cli,
    reach_demos,
    write_reach,
)

from ndlfd.learner import KeypointHMM


@pytest.mark.parametrize("sep", [",", ";", "\t", " "])
def test_column_mapping_on_the_command_line(tmp_path, capsys, sep):
    names = ("TIME", "Pos_X", "Pos_Y", "pos_z", "qw", "qx", "qy", "qz")
    folder = write_reach(tmp_path / "d", sep=sep, names=names)
    reference = write_reach(tmp_path / "ref")  # the same data, conventional names
    m = ["--time-column", "time", "--group", "position=pos_x,POS_Y,Pos_Z"]
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd", *m)
    assert rc == 0, err
    layout = {",": "", ";": " (semicolon-separated)", "\t": " (tab-separated)",
              " ": " (whitespace-separated)"}[sep]  # fmt: skip
    assert err[0] == (
        "read 3 demonstration(s) from 3 file(s): time=TIME;"
        f" position=Pos_X,Pos_Y,pos_z; orientation=qw,qx,qy,qz{layout}"
    )
    rc, _ = cli(capsys, "fit", reference, "-o", tmp_path / "ref.ndlfd")
    assert rc == 0
    assert_same_fit(KeypointHMM.load(tmp_path / "m.ndlfd"),
                     KeypointHMM.load(tmp_path / "ref.ndlfd"))  # fmt: skip
    # the other commands that read demonstrations take the same flags
    one = folder / "reach0.csv"
    rc, err = cli(capsys, "generate", tmp_path / "m.ndlfd", "--like", one, *m,
                  "-o", tmp_path / "g.csv")  # fmt: skip
    assert rc == 0, err
    assert err[0].startswith("read 1 demonstration(s) from 1 file(s): time=TIME;")
    rc, err = cli(capsys, "simplify", one, "--epsilon", "0.01", *m,
                  "-o", tmp_path / "k.csv")  # fmt: skip
    assert rc == 0, err
    assert err[0] == (
        f"read {one}: time=TIME; position=Pos_X,Pos_Y,pos_z; orientation=qw,qx,qy,qz"
        f"{layout}; normalization group"
    )
    if sep == ",":  # errors name the flags, never the Python parameters
        for args, message in [
            (["--time-column", "when"], "--time-column names 'when', but there is no"
             " such column; got columns ['TIME', 'Pos_X',"),
            ([*m[:2], "--group", "position=pos_x,"], "--group position must be a"
             " comma-separated list of names without empty entries"),
            ([*m[:2], "--group", "position=px,py"], "--group position names 'px',"
             " but there is no such column"),
            # pos_z is a position by its name (issue 37): listed or dropped
            ([*m[:2], "--group", "position=pos_x,pos_y"],
             "column 'pos_z' belongs to group 'position' by its name, but"
             " --group position does not list it; add it there or leave it"
             " out with --drop NAME[,NAME...] (e.g. --drop pos_z)"),
        ]:  # fmt: skip
            rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "x.ndlfd", *args)
            assert rc == 2 and len(err) == 1, err
            assert message in err[0]
            assert "time_column=" not in err[0] and "groups={" not in err[0]
        assert not (tmp_path / "x.ndlfd").exists()
        stamp = tmp_path / "stamp.csv"
        stamp.write_text("stamp,x,y\n0,0,0\n1,1,1\n")
        rc, err = cli(capsys, "fit", stamp, "-o", tmp_path / "x.ndlfd")
        assert rc == 2 and err == [
            f"ndlfd fit: error: {stamp}: expected a time column named 't' or 'time' or"
            " 'timestamp' (any case); got columns ['stamp', 'x', 'y']; name it with"
            " --time-column NAME, or give the sample rate of a log without time"
            " stamps with --rate HZ"
        ]
        # names as labs export them need no flag besides the time column now
        rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "y.ndlfd",
                      "--time-column", "TIME")  # fmt: skip
        assert rc == 0, err
        assert "position=Pos_X,Pos_Y,pos_z; orientation=qw,qx,qy,qz" in err[0]
        # names that say nothing: the error says how, with a line to paste
        odd = tmp_path / "odd.csv"
        odd.write_text("TIME,x,y,a,b\n0,0,0,1,2\n1,1,1,1,2\n")
        rc, err = cli(capsys, "fit", odd, "-o", tmp_path / "x.ndlfd",
                      "--time-column", "TIME")  # fmt: skip
        assert rc == 2 and len(err) == 1
        assert (
            "cannot tell the group of column(s) ['a', 'b'] from their names" in (err[0])
        )
        assert (
            "map them with --group GROUP=NAME[,NAME...], or leave them out with"
            " --drop NAME[,NAME...]; e.g., in place of your --group/--drop:"
            " --group position=x,y --drop a,b"
        ) in err[0]
        rc, err = cli(capsys, "fit", odd, "-o", tmp_path / "x.ndlfd",
                      "--time-column", "TIME", "--group", "position=x,y",
                      "--drop", "a,b")  # fmt: skip
        assert rc == 0, err


def test_plain_npz_and_hdf5_fit_the_same_model_as_csv(tmp_path, capsys):
    h5py = pytest.importorskip("h5py")
    demos = reach_demos()
    csv = write_reach(tmp_path / "csv", suffix=".CSV", demos=demos)
    (tmp_path / "npz").mkdir()
    with h5py.File(tmp_path / "reach.h5", "w") as f:
        for i, (t, pos, q) in enumerate(demos):
            np.savez(tmp_path / "npz" / f"reach{i}.npz", t=t, pos=pos, quat=q)
            g = f.create_group(f"episode{i}")
            g["time"], g["P"], g["quat"] = t, pos, q
    groups = ["--groups", "position,velocity,orientation", "--levels", "8"]
    rc, err = cli(capsys, "fit", csv, "-o", tmp_path / "csv.ndlfd", *groups)
    assert rc == 0, err
    assert err[0].startswith("read 3 demonstration(s) from 3 file(s):")
    rc, err = cli(capsys, "fit", tmp_path / "npz", "-o", tmp_path / "npz.ndlfd",
                  *groups)  # fmt: skip
    assert rc == 0, err
    assert err[0] == (
        "read 3 demonstration(s) from 3 file(s): time=t; position=pos; orientation=quat"
    )
    rc, err = cli(capsys, "fit", tmp_path / "reach.h5", "-o", tmp_path / "h5.ndlfd",
                  "--group", "position=p", *groups)  # fmt: skip
    assert rc == 0, err
    assert err[0] == (
        "read 3 demonstration(s) from 1 file(s): time=time; position=P;"
        " orientation=quat"
    )
    ref = KeypointHMM.load(tmp_path / "csv.ndlfd")
    for name in ("npz", "h5"):
        assert_same_fit(KeypointHMM.load(tmp_path / f"{name}.ndlfd"), ref)


def test_hdf5_without_h5py_says_how_to_install_it(tmp_path, capsys, monkeypatch):
    (tmp_path / "d.h5").write_bytes(b"\x89HDF\r\n\x1a\n")
    monkeypatch.setitem(sys.modules, "h5py", None)  # import h5py now fails
    rc, err = cli(capsys, "fit", tmp_path / "d.h5", "-o", tmp_path / "m.ndlfd")
    assert rc == 2
    assert err == [
        "ndlfd fit: error: reading HDF5 files needs h5py; install it with:"
        ' pip install "ndlfd[hdf5]"'
    ]
