"""ndlfd plot --path/--samples read what generate and sample wrote; models refused.

Issue 37: a fit with --drop (and columns mapped by --group and --time-column)
wrote a path that plot could not read back, and the error shown was not the
real one; a model given to plot was reported as a file that is not UTF-8.
"""

import shutil

import numpy as np
import pytest
from cli_helpers import cli, keep_figures

from ndlfd.cli import main

#: A robot's log: a time column of its own name, joints not named by the
#: convention, and two columns that are not learned (left out with --drop).
JOINTS = ("shoulder_pan", "elbow_flex", "wrist_flex")
FLAGS = ("--time-column", "stamp", "--group", "joints=" + ",".join(JOINTS),
         "--drop", "temp_c,mode")  # fmt: skip


def write_log(folder, n_demos=4, seed=0, position=False):
    """CSV files as a logger writes them: every value at full precision (repr)."""
    rng = np.random.default_rng(seed)
    folder.mkdir(parents=True, exist_ok=True)
    names = ("pos_x", "pos_y") if position else JOINTS
    for i in range(n_demos):
        n = 90 + 10 * i
        t = np.arange(n) / 30.0
        s = np.linspace(0.0, 1.0, n)
        values = [40.0 * s + rng.normal(0, 0.5), 25.0 * np.sin(np.pi * s) + i,
                  -15.0 * s**2][: len(names)]  # fmt: skip
        rows = np.column_stack([t, *values, 30 + rng.normal(size=n), np.ones(n)])
        head = ",".join(("stamp", *names, "temp_c", "mode"))
        lines = [head] + [",".join(repr(float(v)) for v in r) for r in rows]
        (folder / f"log{i}.csv").write_text("\n".join(lines) + "\n")
    return folder


def loadcsv(path):
    """(header, rows) of a CSV file, parsed independently of ndlfd."""
    header = path.read_text().splitlines()[0].split(",")
    return header, np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def test_plot_reads_the_path_generate_wrote_with_drop(tmp_path, capsys, monkeypatch):
    pytest.importorskip("matplotlib")
    figures = keep_figures(monkeypatch)
    logs = write_log(tmp_path / "logs")
    model, gen = tmp_path / "m.ndlfd", tmp_path / "g.csv"
    assert main(["fit", str(logs), *FLAGS, "-o", str(model), "-q"]) == 0
    assert main(["generate", str(model), "--duration", "3", "--samples", "40",
                 "--dense", "-o", str(gen), "-q"]) == 0  # fmt: skip
    header, rows = loadcsv(gen)
    assert header == ["stamp", *JOINTS]  # the input's names, no dropped column
    samples = tmp_path / "samples"
    assert main(["sample", str(model), "-n", "2", "--duration", "3", "--samples",
                 "40", "--random-state", "0", "-o", str(samples)]) == 0  # fmt: skip
    # before: "expected a time column named 't' or 'time' or 'timestamp'"
    rc, err = cli(capsys, "plot", logs, *FLAGS, "--path", gen, "--samples", samples,
                  "-o", tmp_path / "p.png")  # fmt: skip
    assert rc == 0, err
    assert err[-1].endswith(
        f", the generated path, 2 sample(s) -> {tmp_path / 'p.png'}"
    ), err
    axes = figures[-1].axes
    assert [ax.get_ylabel() for ax in axes] == list(JOINTS)
    drawn = sorted(samples.glob("*.csv"))
    for j, ax in enumerate(axes):  # each file's own column, against the file
        np.testing.assert_array_equal(ax.lines[-1].get_xydata(), rows[:, [0, 1 + j]])
        thin = [ln.get_xydata() for ln in ax.lines if ln.get_linewidth() < 0.7]
        assert len(thin) == len(drawn) == 2
        for line, f in zip(thin, drawn, strict=True):
            np.testing.assert_array_equal(line, loadcsv(f)[1][:, [0, 1 + j]])


def test_plot_reads_a_position_path_generate_wrote_with_drop(
    tmp_path, capsys, monkeypatch
):
    pytest.importorskip("matplotlib")
    figures = keep_figures(monkeypatch)
    logs = write_log(tmp_path / "logs", position=True)
    flags = ["--time-column", "stamp", "--group", "position=pos_x,pos_y",
             "--drop", "temp_c,mode"]  # fmt: skip
    model, gen = tmp_path / "m.ndlfd", tmp_path / "g.csv"
    assert main(["fit", str(logs), *flags, "-o", str(model), "-q"]) == 0
    assert main(["generate", str(model), "--duration", "3", "--samples", "50",
                 "--dense", "-o", str(gen), "-q"]) == 0  # fmt: skip
    header, rows = loadcsv(gen)
    assert header[:3] == ["stamp", "pos_x", "pos_y"]
    assert "temp_c" not in header and "mode" not in header
    rc, err = cli(capsys, "plot", logs, *flags, "--path", gen, "-o",
                  tmp_path / "p.png")  # fmt: skip
    assert rc == 0, err
    (ax,) = figures[-1].axes
    (line,) = [ln for ln in ax.lines if ln.get_label() == "generated"]
    np.testing.assert_array_equal(line.get_xydata(), rows[:, 1:3])


def test_plot_path_errors_give_the_real_reasons(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    logs = write_log(tmp_path / "logs", n_demos=2)
    other = tmp_path / "other.csv"  # a path of none of these names
    other.write_text("t,a,b\n0,1,2\n1,2,3\n")
    rc, err = cli(capsys, "plot", logs, *FLAGS, "-q", "--path", other, "-o",
                  tmp_path / "p.png")  # fmt: skip
    assert rc == 2 and len(err) == 1, err
    text = err[0]
    assert text.startswith(
        f"ndlfd plot: error: --path {other}: expected a path as 'ndlfd generate'"
        " writes it"
    )
    # each reading's own reason, in turn
    reasons = [
        "with the demonstrations' column flags: "
        f"{other}: --drop names unknown column(s) ['temp_c', 'mode']",
        f"with them but no --drop or --rate: {other}: --time-column names"
        " 'stamp', but there is no such column",
        f"by its own column names alone: {other}: cannot tell the group of"
        " column(s) ['a', 'b'] from their names",
    ]
    at = [text.index(r) for r in reasons]
    assert at == sorted(at)
    # one reason, said once, when every reading fails for it
    binary = tmp_path / "b.csv"
    binary.write_bytes(b"t,x\n\xff\xfe\x00\x01\n")
    rc, err = cli(capsys, "plot", logs, *FLAGS, "-q", "--path", binary, "-o",
                  tmp_path / "p.png")  # fmt: skip
    assert rc == 2 and len(err) == 1, err
    assert err[0].startswith(f"ndlfd plot: error: --path {binary}: expected a UTF-8")
    assert err[0].count("UTF-8") == 1
    rc, err = cli(capsys, "plot", logs, *FLAGS, "-q", "--path", tmp_path / "no.csv",
                  "-o", tmp_path / "p.png")  # fmt: skip
    assert err == [f"ndlfd plot: error: --path {tmp_path / 'no.csv'}: no such file"]


def test_plot_says_a_model_is_not_what_it_draws(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    logs = write_log(tmp_path / "logs", n_demos=3)
    model = tmp_path / "m.ndlfd"
    assert main(["fit", str(logs), *FLAGS, "-o", str(model), "-q"]) == 0
    disguised = tmp_path / "model.csv"  # found by its content, not its suffix
    shutil.copy(model, disguised)
    advice = (
        "is an ndlfd model (written by 'ndlfd fit'), which ndlfd plot does not"
        " draw; ndlfd plot draws demonstrations (files or folders, read as"
        " 'ndlfd fit' reads them) and a generated path (--path FILE.csv). Make a"
        " path from the model with 'ndlfd generate {p} --duration SECONDS -o"
        " path.csv' (or --like DEMONSTRATION), then draw it with 'ndlfd plot"
        " DEMOS --path path.csv -o FIGURE'"
    )
    for p in (model, disguised):
        rc, err = cli(capsys, "plot", p, "-o", tmp_path / "p.png")
        assert rc == 2
        assert err == [f"ndlfd plot: error: {p}: " + advice.format(p=p)]
        rc, err = cli(capsys, "plot", logs, *FLAGS, "-q", "--path", p, "-o",
                      tmp_path / "p.png")  # fmt: skip
        assert rc == 2 and len(err) == 1, err
        assert err[0].startswith(
            f"ndlfd plot: error: --path {p}: is an ndlfd model (written by 'ndlfd"
            f" fit'), which ndlfd plot does not draw; --path takes a generated"
            f" path. Make a path from the model with 'ndlfd generate {p}"
        )
    # among demonstrations with --bad-files skip: skipped, with the reason
    shutil.copy(model, logs / "zz.csv")
    rc, err = cli(capsys, "plot", logs, *FLAGS, "--bad-files", "skip", "-o",
                  tmp_path / "p.png")  # fmt: skip
    assert rc == 0, err
    (warning,) = [e for e in err if "warning" in e]
    assert f"skipped {logs / 'zz.csv'}: is an ndlfd model" in warning
    assert err[-1].startswith("drew 3 demonstration(s)")
