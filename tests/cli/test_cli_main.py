"""The command line as a whole: help, usage errors, checks every command shares."""

import numpy as np
import pytest
from cli_helpers import (
    build_parser_help,
    cli,
    run,
    write_reach,
)

from ndlfd.cli import main
from ndlfd.io import write_table


def test_help_for_every_command():
    r = run("--help")
    assert r.returncode == 0
    for cmd in ("simplify", "fit", "generate", "plot", "demo", "reproduce"):
        assert cmd in r.stdout
        h = run(cmd, "--help")
        assert h.returncode == 0, h.stderr
        assert "usage: ndlfd " + cmd in h.stdout


def test_usage_errors_are_one_line(tmp_path):
    r = run("simplify", tmp_path / "x.csv", "-o", tmp_path / "o.csv")
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1
    assert "--epsilon" in r.stderr
    r = run("simplify", tmp_path / "missing.csv", "--epsilon", "1", "-o", "o.csv")
    assert r.returncode == 2 and "missing.csv" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    r = run()
    assert r.returncode == 2


@pytest.mark.parametrize(
    ("times", "line", "got"),
    [
        ([0.0, 0.1, 0.2, 0.15, 0.3], 5, "got 0.15 after 0.2 on line 4"),
        ([0.0, 0.1, 0.1, 0.2, 0.3], 4, "got 0.1 after 0.1 on line 3"),
    ],
)
def test_time_column_must_increase_in_every_command(tmp_path, times, line, got):
    demo = np.column_stack([times, np.arange(5.0), np.arange(5.0) ** 2])
    f = tmp_path / "d.csv"
    write_table(f, ["t", "x", "y"], demo)
    message = (
        f"error: {f}, line {line}: time column 't' must be strictly increasing; {got}"
    )
    out = tmp_path / "o.csv"
    runs = {
        "simplify": ["simplify", f, "--epsilon", "0.1", "-o", out],
        "simplify --time-column": [
            "simplify", f, "--epsilon", "0.1", "--time-column", "t", "-o", out
        ],
        "simplify sed": [
            "simplify", f, "--n-points", "3", "--distance", "sed", "-o", out
        ],
        "fit": ["fit", f, "-o", tmp_path / "m.ndlfd", "--groups", "position"],
    }  # fmt: skip
    for what, args in runs.items():
        r = run(*args)
        assert r.returncode == 2, what
        assert r.stderr.splitlines() == [f"ndlfd {args[0]}: {message}"], what
        assert not out.exists() and not (tmp_path / "m.ndlfd").exists()


def test_other_settings_out_of_range_and_documented_ranges(tmp_path, capsys):
    folder = write_reach(tmp_path / "d")
    f = folder / "reach0.csv"
    o = tmp_path / "o.csv"
    assert main(["fit", str(folder), "-o", str(tmp_path / "m.ndlfd"), "-q"]) == 0
    for args, message in [
        (["simplify", f, "--n-points", "51", "-o", o], "simplify: error: --n-points"
         " must be between 2 and 50 (the file's number of samples); got 51"),
        (["simplify", f, "--epsilon", "-1", "-o", o],
         "simplify: error: --epsilon must be a finite number >= 0; got -1.0"),
        (["simplify", f, "--epsilon", "1", "--columns", "x,", "-o", o],
         "simplify: error: --columns must be a comma-separated list of names"),
        (["simplify", f, "--epsilon", "1", "--weights", "1,2", "-o", o],
         "simplify: error: --weights must give one weight per simplified column (7:"
         " x, y, z, qw, qx, qy, qz); got 2"),
        (["generate", tmp_path / "m.ndlfd", "--duration", "1", "--samples",
          "100000000", "-o", o], "generate: error: --samples must be between 2 and"
         " 10000000; got 100000000"),
        (["generate", tmp_path / "m.ndlfd", "--duration", "inf", "-o", o],
         "generate: error: --duration must be a finite number > 0; got inf"),
        (["generate", tmp_path / "m.ndlfd", "--duration", "1", "--start", "1,2",
          "-o", o], "generate: error: --start must give 3 position values (one per"
         " column: x, y, z); got 2"),
        (["plot", folder, "--n-points", "99", "-o", tmp_path / "p.png"],
         "plot: error: --n-points must be between 2 and 50"),
    ]:  # fmt: skip
        rc, err = cli(capsys, *args, "-q")
        assert rc == 2 and len(err) == 1, err
        assert err[0].startswith(f"ndlfd {message}"), err
        assert not o.exists()
    helps = {"fit": ["2 <= N <= the longest demonstration's number of samples",
                     "codebook levels >= 2", "2 <= N <= the shortest"],
             "simplify": ["2 <= N <= the file's number of samples", ">= 0"],
             "generate": ["2 <= N <= 10,000,000"],
             "plot": ["2 <= N <= the shortest"]}  # fmt: skip
    for command, phrases in helps.items():
        text = " ".join(build_parser_help(command).split())
        for phrase in phrases:
            assert phrase in text, (command, phrase)


def test_output_paths_numbers_and_mask(tmp_path, capsys):
    folder = write_reach(tmp_path / "d")
    f = folder / "reach0.csv"
    assert main(["fit", str(folder), "-o", str(tmp_path / "m.ndlfd"), "-q"]) == 0
    model = tmp_path / "m.ndlfd"
    runs = {
        "simplify": ["simplify", f, "--epsilon", "0.1"],
        "fit": ["fit", folder],
        "generate": ["generate", model, "--duration", "1"],
        "plot": ["plot", folder],
    }
    for command, args in runs.items():
        # a missing folder: one line naming it; nothing is created
        target = tmp_path / "missing" / "out.png"
        rc, err = cli(capsys, *args, "-o", target)
        assert rc == 2
        assert err == [
            f"ndlfd {command}: error: -o {target}: the folder {target.parent} does"
            " not exist; create it first"
        ]
        assert not target.parent.exists()
        # a folder: one line naming it, no errno and no temporary file
        rc, err = cli(capsys, *args, "-o", folder)
        assert rc == 2 and len(err) == 1, err
        assert err[0].startswith(f"ndlfd {command}: error: -o {folder}: is a folder;")
        assert "Errno" not in err[0] and ".tmp" not in err[0]
    rc, err = cli(capsys, "generate", model, "--duration", "1", "--std",
                  tmp_path / "no" / "s.csv", "-o", tmp_path / "g.csv")  # fmt: skip
    assert rc == 2
    assert err[0].endswith(
        f"the folder {tmp_path / 'no'} does not exist; create it first"
    )
    assert sorted(p.name for p in folder.iterdir()) == [
        "reach0.csv", "reach1.csv", "reach2.csv"
    ]  # fmt: skip
    # computed numbers: ten significant digits at most
    rc, _ = cli(capsys, "generate", model, "--duration", "0.7", "--samples", "33",
                "--dense", "-o", tmp_path / "g.csv")  # fmt: skip
    assert rc == 0
    lines = (tmp_path / "g.csv").read_text().splitlines()
    numbers = [v for line in lines[1:] for v in line.split(",")]
    digits = [
        len(v.lstrip("-").split("e")[0].replace(".", "").lstrip("0")) for v in numbers
    ]
    assert max(digits) <= 10 and max(digits) >= 9
    assert lines[1].startswith("0,") and lines[-1].startswith("0.7,")
    # --mask: 0/1 integers; the rows themselves unchanged
    rc, _ = cli(capsys, "simplify", f, "--epsilon", "0.05", "--mask",
                "-o", tmp_path / "k.csv")  # fmt: skip
    assert rc == 0
    given = f.read_text().splitlines()
    written = (tmp_path / "k.csv").read_text().splitlines()
    assert written[0] == given[0] + ",keep"
    assert {w.rsplit(",", 1)[1] for w in written[1:]} == {"0", "1"}
    assert [w.rsplit(",", 1)[0] for w in written[1:]] == given[1:]


def test_python_dash_m_ndlfd_is_the_command_line():
    """``python -m ndlfd`` runs the same parser as ``ndlfd`` (usage errors: exit 2)."""
    import subprocess
    import sys

    ok = subprocess.run(
        [sys.executable, "-m", "ndlfd", "--help"], capture_output=True, text=True
    )
    assert ok.returncode == 0 and "usage: ndlfd" in ok.stdout
    bad = subprocess.run(
        [sys.executable, "-m", "ndlfd", "no-such-command"],
        capture_output=True,
        text=True,
    )
    assert bad.returncode == 2 and "no-such-command" in bad.stderr
