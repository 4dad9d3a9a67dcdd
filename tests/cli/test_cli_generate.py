"""ndlfd generate (from a model ndlfd fit wrote)."""

from pathlib import Path

import numpy as np
from cli_helpers import (
    cli,
    run,
    square_demos,
)

from ndlfd import synth
from ndlfd.io import read_csv, write_csv
from ndlfd.learner import KeypointHMM


def test_fit_generate_round_trip(tmp_path):

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
    # computed numbers are written with ten significant digits
    np.testing.assert_allclose(gen.X, expected.X, rtol=5e-10, atol=1e-300)
    np.testing.assert_allclose(gen.t, expected.t, rtol=5e-10, atol=1e-300)
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
    np.testing.assert_allclose(pinned.X, expected.X, rtol=5e-10, atol=1e-300)
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
    # a real folder of demonstrations, so the run gets as far as --levels
    folder = square_demos(tmp_path / "demos", n_demos=3)
    r = run("fit", folder, "-o", tmp_path / "m.ndlfd", "--levels", "position=x")
    assert r.returncode == 2
    assert r.stderr.strip().splitlines() == [
        "ndlfd fit: error: --levels: 'x' is not a valid number in 'position=x'"
    ]
    assert not (tmp_path / "m.ndlfd").exists()


def test_generate_refuses_a_wrong_model_file(tmp_path, capsys):
    import pickle

    marker = tmp_path / "pwned"

    class Evil:
        def __reduce__(self):
            return (Path.touch, (marker,))

    bad = {
        "model.csv": (b"t,x,y\n0,1,2\n", "a text file starting 't,x,y' (a CSV file?)"),
        "model.json": (b'{"levels": 20}', "a JSON text file"),
        "model.pkl": (pickle.dumps(Evil()), "a Python pickle, which ndlfd never loads"),
        "model.ndlfd": (b"", "an empty file"),
    }
    for name, (content, _) in bad.items():
        (tmp_path / name).write_bytes(content)
    np.savez(tmp_path / "plain.npz", t=np.arange(3.0))
    np.savez(tmp_path / "objects.npz", a=np.array([Evil()], dtype=object))
    bad["plain.npz"] = (None, "an .npz archive without ndlfd metadata")
    bad["objects.npz"] = (None, "pickled Python objects, which ndlfd never loads")
    for name, (_, what) in bad.items():
        rc, err = cli(capsys, "generate", tmp_path / name, "--duration", "1",
                      "-o", tmp_path / "g.csv")  # fmt: skip
        assert rc == 2 and len(err) == 1, err
        assert err[0].startswith(
            f"ndlfd generate: error: {tmp_path / name}: not an ndlfd model file"
        ), err
        assert what in err[0]
        assert "allow_pickle" not in err[0] and "pickle.load" not in err[0]
        assert "unsafe" not in err[0]
    assert not marker.exists()
    assert not (tmp_path / "g.csv").exists()


def test_generate_writes_the_format_of_its_suffix_or_says_why_not(tmp_path, capsys):
    # before: -o x.npz and -o x.parquet wrote CSV text under those names
    from cli_helpers import fit_model, write_obstacle

    from ndlfd.io import read_npz, read_parquet

    model = fit_model(write_obstacle(tmp_path / "d", 3, 2), tmp_path / "m.ndlfd")
    args = ("generate", tmp_path / "m.ndlfd", "--duration", "5", "--samples", "50",
            "--dense")  # fmt: skip
    rc, err = cli(capsys, *args, "-o", tmp_path / "p.csv")
    assert rc == 0, err
    rc, err = cli(capsys, *args, "-o", tmp_path / "p.npz")
    assert rc == 0, err
    got = read_npz(tmp_path / "p.npz")
    want = read_csv(tmp_path / "p.csv")
    assert got.columns == model.columns_ and got.groups == model.column_groups_
    np.testing.assert_allclose(got.X, want.X, rtol=1e-9, atol=1e-12)  # csv: 10 digits
    np.testing.assert_allclose(got.t, want.t, rtol=1e-9, atol=1e-12)
    rc, err = cli(capsys, *args, "-o", tmp_path / "p.parquet")  # LeRobot's layout
    assert rc == 0, err
    got = read_parquet(tmp_path / "p.parquet")
    assert got.columns == want.columns and got.groups == want.groups
    np.testing.assert_allclose(got.X, want.X, rtol=1e-6)  # float32, as LeRobot
    for name in ("p", "p.parquet.gz"):
        rc, err = cli(capsys, *args, "-o", tmp_path / name)
        assert rc == 2
        assert (
            "expected a file ending in .csv, .db3, .mcap, .npz, .parquet, .txt"
            in err[-1]
        )
        assert not (tmp_path / name).exists()
    rc, err = cli(capsys, *args, "-o", tmp_path / "p.out", "--format", "csv")
    assert rc == 0, err
    assert read_csv(tmp_path / "p.out").n_samples == 50


def test_generate_and_sample_at_a_rate_write_exact_stamps(tmp_path, capsys):
    from cli_helpers import fit_model, write_obstacle

    fit_model(write_obstacle(tmp_path / "d", 3, 2), tmp_path / "m.ndlfd")
    model = tmp_path / "m.ndlfd"
    for rate, n in ((100.0, 601), (30.0, 181), (7.0, 43)):
        rc, err = cli(capsys, "generate", model, "--duration", "6", "--rate",
                      str(rate), "--dense", "-o", tmp_path / "p.csv")  # fmt: skip
        assert rc == 0, err
        t = read_csv(tmp_path / "p.csv").t
        assert t.size == n
        np.testing.assert_array_equal(t, np.arange(n) / rate)  # bit for bit
    rc, err = cli(capsys, "sample", model, "-n", "2", "--duration", "2", "--rate",
                  "30", "-o", tmp_path / "s")  # fmt: skip
    assert rc == 0, err
    t = read_csv(tmp_path / "s" / "sample_000.csv").t
    np.testing.assert_array_equal(t, np.arange(61) / 30.0)
    for bad, message in ((["--samples", "5"], "either --samples or --rate"),
                         (["--rate", "0"], "--rate must be a finite number > 0"),
                         (["--rate", "1e9"], "expected 2 to")):  # fmt: skip
        rc, err = cli(capsys, "generate", model, "--duration", "6", *bad,
                      *(["--rate", "10"] if bad[0] == "--samples" else []),
                      "-o", tmp_path / "q.csv")  # fmt: skip
        assert rc == 2 and message in err[-1], err
