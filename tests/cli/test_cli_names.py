"""ndlfd generate --like: the input's names kept, only its time column needed."""

import numpy as np
from cli_helpers import cli, own_name_demos

from ndlfd.cli import main
from ndlfd.io import read_table
from ndlfd.learner import KeypointHMM


def test_generate_like_keeps_the_input_names(tmp_path, capsys):
    folder = own_name_demos(tmp_path / "d")
    model = tmp_path / "m.ndlfd"
    group = ("--group", "position=pos_x,pos_y")
    assert main(["fit", str(folder), "-o", str(model), "-q", *group]) == 0
    like = folder / "d1.csv"
    out = tmp_path / "g.csv"
    # with the mapping: the file's names and time column; derived velocity vx, vy
    rc, err = cli(capsys, "generate", model, "--like", like, "--dense", *group,
                  "-o", out)  # fmt: skip
    assert rc == 0, err
    header = out.read_text().splitlines()[0]
    assert header == "time,pos_x,pos_y,gripper,vx,vy"  # the file's order first
    named = read_table(out)[1]
    # the same numbers as the model's own names give
    ref = KeypointHMM.load(model).generate(read_table(like)[1][:, 0], dense=True)
    assert ref.columns == ("pos_x", "pos_y", "vx", "vy", "gripper")
    np.testing.assert_array_equal(named[:, 0], ref.t)
    want = ref.X[:, [0, 1, 4, 2, 3]]
    np.testing.assert_allclose(named[:, 1:], want, rtol=1e-9, atol=1e-12)
    # without the --group flags: pos_x, pos_y say their group by their names
    # (issue 37), the same mapping
    rc, err = cli(capsys, "generate", model, "--like", like, "--dense",
                  "-o", tmp_path / "h.csv")  # fmt: skip
    assert rc == 0, err
    assert any("time=time; position=pos_x,pos_y; gripper=gripper" in line
               for line in err)  # fmt: skip
    # names that say nothing: only the time column is read; the names are
    # those the model recorded at fit (the same)
    odd = tmp_path / "odd.csv"
    odd.write_text(like.read_text().replace("pos_x;pos_y", "a;b", 1))
    rc, err = cli(capsys, "generate", model, "--like", odd, "--dense",
                  "-o", tmp_path / "i.csv")  # fmt: skip
    assert rc == 0, err
    assert any("time=time (its time stamps only)" in line for line in err)
    np.testing.assert_array_equal(read_table(tmp_path / "i.csv")[1], named)
    assert (tmp_path / "h.csv").read_text().splitlines()[0] == (
        "time,pos_x,pos_y,gripper,vx,vy"
    )
    np.testing.assert_array_equal(read_table(tmp_path / "h.csv")[1], named)


def test_generate_like_time_only_errors(tmp_path, capsys):
    folder = own_name_demos(tmp_path / "d", n_demos=3)
    model = tmp_path / "m.ndlfd"
    group = ("--group", "position=pos_x,pos_y")
    assert main(["fit", str(folder), "-o", str(model), "-q", *group]) == 0
    bad = tmp_path / "bad.csv"
    bad.write_text("stamp;pos_x\n0;1\n1;2\n")
    rc, err = cli(capsys, "generate", model, "--like", bad, "-o", tmp_path / "o.csv")
    assert rc == 2 and len(err) == 1
    assert "expected a time column named ('t', 'time', 'timestamp')" in err[0]
    assert "--time-column" in err[0] and "--rate HZ" in err[0]
    bad.write_text("time;pos_x\n0;1\n0;2\n")
    rc, err = cli(capsys, "generate", model, "--like", bad, "-o", tmp_path / "o.csv")
    assert rc == 2 and len(err) == 1 and "strictly increasing" in err[0]
