import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ndlfd._simplify import simplify
from ndlfd.io import read_table, write_table

BIN = Path(sys.executable).parent / "ndlfd"


def run(*args, cwd=None):
    cmd = (
        [str(BIN), *map(str, args)]
        if BIN.exists()
        else [sys.executable, "-m", "ndlfd.cli", *map(str, args)]
    )
    env = dict(os.environ, PYTHONWARNINGS="error")
    return subprocess.run(
        cmd, capture_output=True, text=True, cwd=cwd, env=env, timeout=300
    )


def _walk_csv(path, n=300, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.01
    xy = np.cumsum(rng.normal(size=(n, 2)), axis=0)
    data = np.column_stack([t, xy, rng.normal(size=n)])
    write_table(path, ["t", "x", "y", "extra"], data)
    return data


def test_help_for_every_command():
    r = run("--help")
    assert r.returncode == 0
    for cmd in ("simplify", "fit", "generate", "demo", "reproduce"):
        assert cmd in r.stdout
        h = run(cmd, "--help")
        assert h.returncode == 0, h.stderr
        assert "usage: ndlfd " + cmd in h.stdout


def test_simplify_round_trip(tmp_path):
    data = _walk_csv(tmp_path / "walk.csv")
    r = run(
        "simplify",
        tmp_path / "walk.csv",
        "--epsilon",
        "2.0",
        "--columns",
        "x,y",
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
    data = _walk_csv(tmp_path / "walk.csv")
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
    mask = simplify(data[:, 1:], 1.5, return_mask=True)
    np.testing.assert_array_equal(out[:, :4], data)
    np.testing.assert_array_equal(out[:, 4], mask.astype(float))


def test_simplify_sed_uses_time_column_and_budget(tmp_path):
    data = _walk_csv(tmp_path / "walk.csv")
    r = run(
        "simplify",
        tmp_path / "walk.csv",
        "--n-points",
        "12",
        "--distance",
        "sed",
        "--columns",
        "x,y",
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
        ("t,x,y\n0,1,2\n1,2,3\n", ["--columns", "x,z"], "column(s) z not found"),
        ("t,x,y\n0,1,2\n1,abc,3\n", [], "line 3"),
        ("t,x,y\n0,1,2\n1,nan,3\n", [], "line 3"),
        (
            "t,x\n0,1\n1,2\n",
            ["--distance", "sed", "--time-column", "time"],
            "time column 'time' not found",
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


def test_fit_generate_round_trip(tmp_path):
    from ndlfd import synth
    from ndlfd.io import read_csv, write_csv
    from ndlfd.learner import KeypointHMM

    train, test = synth.make_dataset("square", n_demos=12, random_state=5)
    (tmp_path / "demos").mkdir()
    for i, d in enumerate(train):
        write_csv(d.select("position"), tmp_path / "demos" / f"demo{i:02d}.csv")
    write_csv(test.select("position"), tmp_path / "test.csv")
    r = run(
        "fit",
        tmp_path / "demos",
        "-o",
        tmp_path / "m.ndlfd",
        "--levels",
        "position=20,velocity=10",
        "--epsilon",
        "0.05",
        "--time-bins",
        "30",
    )
    assert r.returncode == 0, r.stderr
    assert "fitted 12 demonstration(s)" in r.stderr
    r = run(
        "generate",
        tmp_path / "m.ndlfd",
        "--like",
        tmp_path / "test.csv",
        "-o",
        tmp_path / "gen.csv",
    )
    assert r.returncode == 0, r.stderr
    gen = read_csv(tmp_path / "gen.csv")
    # the same as the library on the same files
    demos = [read_csv(p) for p in sorted((tmp_path / "demos").glob("*.csv"))]
    model = KeypointHMM(
        levels={"position": 20, "velocity": 10}, epsilon=0.05, n_time_bins=30
    ).fit(demos)
    expected = model.generate(read_csv(tmp_path / "test.csv"))
    np.testing.assert_allclose(gen.X, expected.X, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(gen.t, expected.t)
    r = run(
        "generate",
        tmp_path / "m.ndlfd",
        "--duration",
        "2",
        "--samples",
        "101",
        "--dense",
        "-o",
        tmp_path / "dense.csv",
    )
    assert r.returncode == 0, r.stderr
    dense = read_csv(tmp_path / "dense.csv")
    assert dense.n_samples == 101 and dense.group_names == ("position", "velocity")
    assert dense.t[-1] == 2.0  # the last sample is at the end of the duration
    r = run(
        "generate",
        tmp_path / "m.ndlfd",
        "--duration",
        "3",
        "--samples",
        "61",
        "--dense",
        "--start",
        "0.5,-0.25",
        "--goal",
        "0.25,0.5",
        "-o",
        tmp_path / "pinned.csv",
    )
    assert r.returncode == 0, r.stderr
    pinned = read_csv(tmp_path / "pinned.csv")
    expected = model.generate(
        np.linspace(0.0, 3.0, 61),
        dense=True,
        start={"position": [0.5, -0.25]},
        goal={"position": [0.25, 0.5]},
    )
    np.testing.assert_allclose(pinned.X, expected.X, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(
        pinned.get("position")[[0, -1]], [[0.5, -0.25], [0.25, 0.5]], atol=1e-12
    )
    r = run("generate", tmp_path / "m.ndlfd", "--duration", "3", "--start", "0,x",
            "-o", tmp_path / "bad.csv")  # fmt: skip
    assert r.returncode == 2 and "--start must be comma-separated" in r.stderr


def test_fit_and_generate_errors(tmp_path):
    r = run("generate", tmp_path / "nope.ndlfd", "--duration", "1", "-o", "x.csv")
    assert r.returncode == 2 and "no such file" in r.stderr
    (tmp_path / "junk.ndlfd").write_bytes(b"junk")
    r = run("generate", tmp_path / "junk.ndlfd", "--duration", "1", "-o", "x.csv")
    assert r.returncode == 2 and "not readable" in r.stderr
    r = run("fit", tmp_path / "empty-dir-missing", "-o", tmp_path / "m.ndlfd")
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1
    r = run("fit", tmp_path, "-o", tmp_path / "m.ndlfd", "--levels", "position=x")
    assert r.returncode == 2


def test_demo_quick(tmp_path):
    r = run("demo", "--quick", "--out", tmp_path / "out")
    assert r.returncode == 0, r.stderr
    assert "square" in r.stdout and "DTW to the held-out test" in r.stdout
    names = {p.name for p in (tmp_path / "out").iterdir()}
    assert {
        "square_generated_keypoints.csv",
        "square_generated_dense.csv",
        "square.png",
    } <= names
