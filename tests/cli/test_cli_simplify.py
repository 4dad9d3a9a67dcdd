"""ndlfd simplify."""

import numpy as np
import pytest
from cli_helpers import (
    build_parser_help,
    cli,
    ndlfd_demo,
    reach_demos,
    run,
    walk_csv,
)

from ndlfd.cli import main
from ndlfd.dp import simplify
from ndlfd.io import read_csv, read_table, write_csv, write_table


def test_simplify_round_trip(tmp_path):
    data = walk_csv(tmp_path / "walk.csv")
    r = run(
        "simplify",
        tmp_path / "walk.csv",
        "--epsilon",
        "2.0",
        "--columns",
        "x,y",
        "--normalization",
        "none",
        "-o",
        tmp_path / "out.csv",
    )
    assert r.returncode == 0, r.stderr
    cols, out = read_table(tmp_path / "out.csv")
    assert cols == ["t", "x", "y", "extra"]
    idx = simplify(data[:, 1:3], 2.0)
    np.testing.assert_array_equal(out, data[idx])
    assert f"kept {idx.size} of 300 points" in r.stderr


def test_simplify_default_columns_exclude_time_and_mask(tmp_path):
    data = walk_csv(tmp_path / "walk.csv")
    r = run(
        "simplify",
        tmp_path / "walk.csv",
        "--epsilon",
        "1.5",
        "--mask",
        "-o",
        tmp_path / "mask.csv",
        "-q",
    )
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""
    cols, out = read_table(tmp_path / "mask.csv")
    assert cols == ["t", "x", "y", "extra", "keep"]
    # x, y share the position range; 'extra' (no group by its name) has its own
    xy, extra = data[:, 1:3], data[:, 3:]
    U = np.column_stack(
        [(xy - xy.min()) / (xy.max() - xy.min()),
         (extra - extra.min()) / (extra.max() - extra.min())]
    )  # fmt: skip
    mask = simplify(U, 1.5, return_mask=True)
    np.testing.assert_array_equal(out[:, :4], data)
    np.testing.assert_array_equal(out[:, 4], mask.astype(float))
    assert (tmp_path / "mask.csv").read_text().splitlines()[1].endswith(",1")


def test_simplify_sed_uses_time_column_and_budget(tmp_path):
    data = walk_csv(tmp_path / "walk.csv")
    r = run(
        "simplify",
        tmp_path / "walk.csv",
        "--n-points",
        "12",
        "--distance",
        "sed",
        "--columns",
        "x,y",
        "--normalization",
        "none",
        "-o",
        tmp_path / "o.csv",
    )
    assert r.returncode == 0, r.stderr
    _, out = read_table(tmp_path / "o.csv")
    idx = simplify(data[:, 1:3], n_points=12, distance="sed", times=data[:, 0])
    np.testing.assert_array_equal(out, data[idx])


@pytest.mark.parametrize(
    ("content", "args", "match"),
    [
        (
            "t,x,y\n0,1,2\n1,2,3\n",
            ["--columns", "x,z"],
            "--columns names 'z', but there is no such column; got columns ['t',",
        ),
        ("t,x,y\n0,1,2\n1,abc,3\n", [], "line 3"),
        ("t,x,y\n0,1,2\n1,nan,3\n", [], "line 3"),
        (
            "t,x\n0,1\n1,2\n",
            ["--distance", "sed", "--time-column", "time"],
            "--time-column names 'time', but there is no such column",
        ),
        ("t,x\n0,1\n1,2\n", ["--weights", "1,x"], "--weights"),
        ("t,x\n0,1\n1,2\n", ["--weights", "1,2"], "weights"),
    ],
)
def test_simplify_bad_input_is_one_line_exit_2(tmp_path, content, args, match):
    f = tmp_path / "bad.csv"
    f.write_text(content)
    r = run("simplify", f, "--epsilon", "0.1", *args, "-o", tmp_path / "o.csv")
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert match in lines[0]
    assert "Traceback" not in r.stderr
    assert not (tmp_path / "o.csv").exists()


def test_simplify_mask_column_names_the_mask(tmp_path):
    data = walk_csv(tmp_path / "walk.csv")
    out = tmp_path / "o.csv"
    args = ["simplify", str(tmp_path / "walk.csv"), "--epsilon", "1.5", "--mask",
            "--normalization", "none"]  # fmt: skip
    assert main([*args, "--mask-column", "key", "-o", str(out), "-q"]) == 0
    cols, table = read_table(out)
    assert cols == ["t", "x", "y", "extra", "key"]
    mask = simplify(data[:, 1:], 1.5, return_mask=True)
    np.testing.assert_array_equal(table[:, 4], mask.astype(float))


def test_simplify_time_column_is_excluded_and_used_by_sed(tmp_path):
    rng = np.random.default_rng(4)
    n = 120
    time = np.cumsum(rng.uniform(0.5, 2.0, size=n))
    xy = np.cumsum(rng.normal(size=(n, 2)), axis=0)
    data = np.column_stack([xy[:, 0], time, xy[:, 1]])
    f = tmp_path / "walk.csv"
    write_table(f, ["x", "stamp", "y"], data)
    out = tmp_path / "o.csv"
    base = ["simplify", str(f), "-o", str(out), "-q", "--normalization", "none"]
    # --time-column: the column is not simplified, and sed uses it as time
    assert main([*base, "--n-points", "15", "--distance", "sed",
                 "--time-column", "stamp"]) == 0  # fmt: skip
    idx = simplify(xy, n_points=15, distance="sed", times=time)
    np.testing.assert_array_equal(read_table(out)[1], data[idx])
    assert not np.array_equal(idx, simplify(xy, n_points=15))
    assert main([*base, "--epsilon", "2", "--time-column", "stamp"]) == 0
    np.testing.assert_array_equal(read_table(out)[1], data[simplify(xy, 2.0)])
    # without it, "stamp" is a value column like the others
    assert main([*base, "--epsilon", "2"]) == 0
    np.testing.assert_array_equal(read_table(out)[1], data[simplify(data, 2.0)])
    assert not np.array_equal(simplify(data, 2.0), simplify(xy, 2.0))


def test_simplify_normalizes_groups_like_fit(tmp_path, capsys):
    from ndlfd import GroupScaler

    # a reach in millimetres: position noise of 0.05 mm is above an epsilon of
    # 0.01 in raw units, and nothing next to a 500 mm range
    rng = np.random.default_rng(3)
    (t, pos, q), = reach_demos(1)  # fmt: skip
    pos = pos * 500 + rng.normal(0, 0.05, pos.shape)
    f = tmp_path / "reach.csv"
    write_csv(ndlfd_demo(t, pos, q), f)
    kept = {}
    for mode in ("group", "per-dimension", "none"):
        rc, err = cli(capsys, "simplify", f, "--epsilon", "0.01", "--normalization",
                      mode, "-o", tmp_path / f"{mode}.csv")  # fmt: skip
        assert rc == 0, err
        assert err[0].endswith(f"; normalization {mode}")
        demo = read_csv(f)
        U = GroupScaler(mode=mode).fit(demo).transform(demo)
        idx = simplify(U, 0.01)
        np.testing.assert_array_equal(read_table(tmp_path / f"{mode}.csv")[1],
                                      read_table(f)[1][idx])  # fmt: skip
        kept[mode] = idx.size
    assert kept["none"] > 0.5 * t.size > 3 * kept["group"]
    # the default is fit's: group
    rc, _ = cli(capsys, "simplify", f, "--epsilon", "0.01", "-o", tmp_path / "d.csv")
    assert rc == 0
    assert (tmp_path / "d.csv").read_text() == (tmp_path / "group.csv").read_text()
    text = " ".join(build_parser_help("simplify").split())
    assert "(default: group, one range per group" in text
    assert "as in 'ndlfd fit'" in text


@pytest.mark.parametrize("mask", [False, True])
def test_simplify_bad_rows_drop(tmp_path, capsys, mask):
    """--bad-rows drop: the key points of the file without its bad rows.

    The reference is the same command on the file with those rows deleted.
    """
    data = walk_csv(tmp_path / "walk.csv", n=60)
    header = ["t", "x", "y", "extra"]
    lines = (tmp_path / "walk.csv").read_text().splitlines()
    for row, col, text in [(10, 1, "nan"), (31, 2, "inf")]:
        cells = lines[row + 1].split(",")
        cells[col] = text
        lines[row + 1] = ",".join(cells)
    (tmp_path / "bad.csv").write_text("\n".join(lines) + "\n")
    keep = np.ones(len(data), bool)
    keep[[10, 31]] = False
    write_table(tmp_path / "ref.csv", header, data[keep])
    more = ["--mask"] if mask else []
    rc, err = cli(capsys, "simplify", tmp_path / "bad.csv", "--epsilon", "0.05",
                  "-o", tmp_path / "o.csv", *more)  # fmt: skip
    assert rc == 2 and len(err) == 1
    assert "line 12, column 'x': expected a finite number" in err[0]
    rc, err = cli(capsys, "simplify", tmp_path / "bad.csv", "--epsilon", "0.05",
                  "-o", tmp_path / "o.csv", "--bad-rows", "drop", *more)  # fmt: skip
    assert rc == 0, err
    assert err[0] == (
        f"ndlfd simplify: warning: {tmp_path / 'bad.csv'}: dropped 2 of 60 row(s)"
        " with NaN or inf"
    )
    assert main(["simplify", str(tmp_path / "ref.csv"), "--epsilon", "0.05",
                 "-o", str(tmp_path / "r.csv"), "-q", *more]) == 0  # fmt: skip
    assert read_table(tmp_path / "o.csv")[0] == read_table(tmp_path / "r.csv")[0]
    np.testing.assert_array_equal(
        read_table(tmp_path / "o.csv")[1], read_table(tmp_path / "r.csv")[1]
    )
    rc, err = cli(capsys, "simplify", tmp_path / "bad.csv", "--epsilon", "0.05",
                  "-o", tmp_path / "o.csv", "--bad-rows", "drop", "-q")  # fmt: skip
    assert rc == 0 and err == []
    # one file: no --bad-files
    with pytest.raises(SystemExit) as exit_:
        main(["simplify", str(tmp_path / "bad.csv"), "--epsilon", "0.05",
              "-o", str(tmp_path / "o.csv"), "--bad-files", "skip"])  # fmt: skip
    assert exit_.value.code == 2
    assert "unrecognized arguments: --bad-files" in capsys.readouterr().err
