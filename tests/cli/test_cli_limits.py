"""ndlfd generate --max-velocity / --max-acceleration (ndlfd.limits on the shell)."""

import numpy as np
import pytest
from cli_helpers import cli, fit_model, write_obstacle

from ndlfd.io import read_csv
from ndlfd.limits import TOLERANCE, path_peaks


@pytest.fixture(scope="module")
def model_file(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("limits")
    fit_model(write_obstacle(tmp / "demos", 4, 2), tmp / "m.ndlfd")
    return tmp / "m.ndlfd"


def test_the_path_is_slowed_to_the_limits_on_an_exact_grid(
    model_file, tmp_path, capsys
):
    out = tmp_path / "p.csv"
    rc, err = cli(capsys, "generate", model_file, "--duration", "5", "--rate", "50",
                  "--dense", "--max-velocity", "position=2", "--max-acceleration",
                  "position=4", "-o", out)  # fmt: skip
    assert rc == 0
    path = read_csv(out)
    peaks = path_peaks(path)
    pos = path.columns_of("position")
    assert np.all(peaks["velocity"][pos] <= 2 * (1 + TOLERANCE))
    assert np.all(peaks["acceleration"][pos] <= 4 * (1 + TOLERANCE))
    assert np.array_equal(path.t, np.arange(path.n_samples) / 50.0)
    assert path.duration > 5.0
    assert any(line.startswith("slowed down to the limits: 5 s ->") for line in err)
    # time-optimal: a limit is reached (on these noisy demonstrations, the
    # acceleration's)
    top = max(peaks["velocity"][pos].max() / 2, peaks["acceleration"][pos].max() / 4)
    assert top >= 0.95  # aimed 1 % below (MARGIN)
    said = f"position velocity {peaks['velocity'][pos].max():.3g} /s"
    assert any(line.startswith("peaks: " + said) for line in err)


def test_without_limits_the_peaks_are_reported(model_file, tmp_path, capsys):
    rc, err = cli(capsys, "generate", model_file, "--duration", "5", "--dense",
                  "-o", tmp_path / "p.csv")  # fmt: skip
    assert rc == 0
    path = read_csv(tmp_path / "p.csv")
    top = path_peaks(path)["velocity"][path.columns_of("position")].max()
    assert any(f"position velocity {top:.3g} /s" in line for line in err)


@pytest.mark.parametrize(
    "extra, match",
    [
        ([], "pass --dense"),
        (["--dense", "--max-velocity", "joints=1"], "no group or column 'joints'"),
        (["--dense", "--max-velocity", "1,2"], "NAME=V1[,V2,...]"),
        (["--dense", "--max-velocity", "position=0"], "finite and > 0"),
        (["--dense", "--max-velocity", "position=1,2,3"], "one value or 2"),
    ],
)
def test_bad_limit_flags_are_refused(model_file, tmp_path, capsys, extra, match):
    args = ["generate", model_file, "--duration", "5", "-o", tmp_path / "p.csv"]
    if not extra:
        extra = ["--max-velocity", "position=1"]
    rc, err = cli(capsys, *args, *extra)
    assert rc == 2
    assert any(match in line for line in err)


def test_sampled_paths_are_each_slowed_to_the_limits(model_file, tmp_path, capsys):
    folder = tmp_path / "s"
    rc, err = cli(capsys, "sample", model_file, "-n", "3", "--duration", "5",
                  "--rate", "20", "--max-velocity", "position=2", "--random-state",
                  "1", "-o", folder)  # fmt: skip
    assert rc == 0
    assert "slowed down 3 of 3 path(s) to the limits" in err
    for f in sorted(folder.glob("sample_*.csv")):
        path = read_csv(f)
        v = path_peaks(path)["velocity"][path.columns_of("position")]
        assert np.all(v <= 2 * (1 + TOLERANCE))
        assert np.array_equal(path.t, np.arange(path.n_samples) / 20.0)
