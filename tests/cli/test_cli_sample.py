"""ndlfd sample: one CSV per drawn path, the same as the library's."""

import numpy as np
import pytest
from cli_helpers import cli, fit_model, square_demos

from ndlfd.io import read_csv, write_csv


@pytest.fixture(scope="module")
def model_file(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("sample")
    demos = square_demos(tmp / "demos", n_demos=8)
    out = tmp / "m.ndlfd"
    return out, fit_model(demos, out, "--time-bins", "20")


def test_writes_one_csv_per_sample_as_the_library_draws(capsys, tmp_path, model_file):
    path, model = model_file
    out = tmp_path / "draws"
    rc, err = cli(capsys, "sample", path, "-n", "5", "--duration", "8",
                  "--samples", "400", "-o", out, "--random-state", "3")  # fmt: skip
    assert rc == 0, err
    assert "drew 5 path(s) of samples" in err[-1]
    files = sorted(out.glob("*.csv"))
    assert [f.name for f in files] == [f"sample_{k:03d}.csv" for k in range(5)]
    expected = model.sample(np.linspace(0.0, 8.0, 400), 5, random_state=3)
    for f, e in zip(files, expected, strict=True):
        got = read_csv(f)
        assert got.t.size == 400
        # computed numbers are written with ten significant digits
        np.testing.assert_allclose(got.X, e.X, rtol=5e-10, atol=1e-12)
    # the same seed: the same files
    again = tmp_path / "again"
    cli(capsys, "sample", path, "-n", "5", "--duration", "8", "--samples", "400",
        "-o", again, "--random-state", "3", "-q")  # fmt: skip
    for f in files:
        assert (again / f.name).read_bytes() == f.read_bytes()


def test_like_start_goal_and_key_points(capsys, tmp_path, model_file):
    path, model = model_file
    like = model.generate(np.linspace(0.0, 2.0, 120), dense=True)
    write_csv(like, tmp_path / "like.csv")
    out = tmp_path / "draws"
    rc, err = cli(capsys, "sample", path, "-n", "3", "--like", tmp_path / "like.csv",
                  "--start", "0.1,0.05", "--goal", "0.9,0.1", "-o", out,
                  "--random-state", "0")  # fmt: skip
    assert rc == 0, err
    for f in sorted(out.glob("*.csv")):
        P = read_csv(f)
        np.testing.assert_array_equal(P.t, read_csv(tmp_path / "like.csv").t)
        np.testing.assert_allclose(P.get("position")[0], [0.1, 0.05], atol=1e-9)
        np.testing.assert_allclose(P.get("position")[-1], [0.9, 0.1], atol=1e-9)
    keys = tmp_path / "keys"
    rc, err = cli(capsys, "sample", path, "--duration", "2", "--key-points",
                  "-o", keys)  # fmt: skip
    assert rc == 0, err
    assert read_csv(keys / "sample_000.csv").t.size < 1000


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["-n", "0", "--duration", "1"], "-n must be between"),
        (["--duration", "1", "--like", "x.csv"], "either --like or"),
        ([], "pass --like FILE or --duration"),
        (["--duration", "1", "--start", "1,2,3"], "--start must give 2 position"),
    ],
)
def test_errors(capsys, tmp_path, model_file, args, message):
    path, _ = model_file
    rc, err = cli(capsys, "sample", path, *args, "-o", tmp_path / "o")
    assert rc == 2
    assert message in err[-1]


def test_output_must_be_a_folder(capsys, tmp_path, model_file):
    path, _ = model_file
    (tmp_path / "f.csv").write_text("")
    rc, err = cli(capsys, "sample", path, "--duration", "1", "-o", tmp_path / "f.csv")
    assert rc == 2 and "expected a folder" in err[-1]
    rc, err = cli(capsys, "sample", path, "--duration", "1",
                  "-o", tmp_path / "no" / "such")  # fmt: skip
    assert rc == 2 and "does not exist" in err[-1]
