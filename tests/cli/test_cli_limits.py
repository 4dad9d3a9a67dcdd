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


@pytest.mark.parametrize("command", ["generate", "sample"])
def test_an_observed_prefix_is_kept_and_the_rest_slowed(
    model_file, tmp_path, capsys, command
):
    # a robot replanning with limits: what it executed stays as it was, with
    # its stamps; the rest is slowed to the limits from the prefix's last
    # sample on
    from ndlfd import KeypointHMM

    model = KeypointHMM.load(model_file)
    plain = model.generate(np.linspace(0.0, 5.0, 251), dense=True)
    prefix = plain.take(np.arange(60)).select("position")
    np.savetxt(tmp_path / "prefix.csv", np.column_stack([prefix.t, prefix.X]),
               delimiter=",", header="t,x,y", comments="", fmt="%.17g")  # fmt: skip
    top = path_peaks(plain)["velocity"][plain.columns_of("position")].max()
    out = tmp_path / ("p.csv" if command == "generate" else "s")
    extra = ["-n", "2", "--random-state", "1"] if command == "sample" else []
    rc, err = cli(capsys, command, model_file, "--duration", "5", "--samples",
                  "251", "--observed", tmp_path / "prefix.csv", "--max-velocity",
                  f"position={0.6 * top}", *extra, "-o", out)  # fmt: skip
    assert rc == 0, err
    files = [out] if command == "generate" else sorted(out.glob("sample_*.csv"))
    assert files
    for f in files:
        path = read_csv(f)
        np.testing.assert_array_equal(path.t[:60], prefix.t)
        # as observed, up to the output's 10 significant digits
        np.testing.assert_allclose(path.get("position")[:60], prefix.X, rtol=5e-10)
        rest = path.take(np.arange(59, path.n_samples))
        v = path_peaks(rest)["velocity"][rest.columns_of("position")]
        assert np.all(v <= 0.6 * top * (1 + TOLERANCE))
        assert path.duration > 5.0
