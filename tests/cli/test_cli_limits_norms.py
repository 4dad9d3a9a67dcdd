"""ndlfd generate --max-speed / --max-angular-velocity / --max-angular-acceleration,
and the peaks line of what is sent after --observed."""

import numpy as np
import pytest
from cli_helpers import cli, fit_model, write_obstacle, write_reach
from scipy.spatial.transform import Rotation

from ndlfd.cli._limits import peaks_line
from ndlfd.io import read_csv
from ndlfd.limits import TOLERANCE, path_peaks


@pytest.fixture(scope="module")
def reach_model(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("norms")
    fit_model(write_reach(tmp / "demos"), tmp / "m.ndlfd")
    return tmp / "m.ndlfd"


def _speed(path):
    P = path.get("position")
    return np.linalg.norm(np.diff(P, axis=0), axis=1) / np.diff(path.t)


def _turn_rate(path):
    Q = path.get("orientation")
    R = Rotation.from_quat(np.column_stack([Q[:, 1:], Q[:, 0]]))
    return (R[:-1].inv() * R[1:]).magnitude() / np.diff(path.t)


def test_the_speed_and_the_turn_rate_are_bounded_as_norms(
    reach_model, tmp_path, capsys
):
    """Per-axis velocity limits leave the speed above them (the user's 0.079 at
    0.05 per axis); --max-speed bounds the norm, --max-angular-velocity the
    turn rate (given in degrees per second)."""
    args = ["generate", reach_model, "--duration", "1", "--rate", "100", "--dense"]
    rc, _ = cli(capsys, *args, "--max-velocity", "position=0.5",
                "-o", tmp_path / "axes.csv")  # fmt: skip
    assert rc == 0
    assert _speed(read_csv(tmp_path / "axes.csv")).max() > 0.5 * 1.05
    rc, err = cli(capsys, *args, "--max-speed", "position=0.5",
                  "--max-angular-velocity", "orientation=20deg",
                  "-o", tmp_path / "norm.csv")  # fmt: skip
    assert rc == 0, err
    path = read_csv(tmp_path / "norm.csv")
    assert _speed(path).max() <= 0.5 * 1.002
    assert _speed(path).max() >= 0.5 * 0.97  # reached: the speed was the bound
    assert _turn_rate(path).max() <= np.radians(20) * 1.002
    line = next(x for x in err if x.startswith("peaks: "))
    assert "speed 0.49" in line and "angular velocity 0.34" in line


def test_an_angular_acceleration_limit_holds(reach_model, tmp_path, capsys):
    """From rest to rest at most 0.5 rad/s^2 (the path turns at up to 2.7 rad/s
    over 0.3 s without it); measured as path_peaks does (the independent
    finite differences are in tests/test_limits_norms.py)."""
    rc, err = cli(capsys, "generate", reach_model, "--duration", "0.3", "--rate",
                  "100", "--dense", "--max-angular-acceleration", "orientation=0.5",
                  "-o", tmp_path / "p.csv")  # fmt: skip
    assert rc == 0, err
    path = read_csv(tmp_path / "p.csv")
    assert path.duration > 0.3
    top = path_peaks(path)["angular_acceleration"][path.columns_of("orientation")]
    assert np.all(top <= 0.5 * (1 + TOLERANCE))
    assert top.max() >= 0.5 * 0.88  # reached, up to the polytope (0.886 to 1)


@pytest.mark.parametrize(
    "extra, match",
    [
        (["--max-speed", "orientation=1"], "the path has 'position'"),
        (["--max-angular-velocity", "position=1"], "the path has 'orientation'"),
        (["--max-speed", "position=1,2"], "takes one value for the group position"),
        (["--max-angular-velocity", "orientation=fastdeg"], "numbers"),
        (["--max-speed", "x=1"], "'x' is not one"),
    ],
)
def test_bad_norm_flags_list_the_valid_groups(
    reach_model, tmp_path, capsys, extra, match
):
    rc, err = cli(capsys, "generate", reach_model, "--duration", "1", "--dense",
                  *extra, "-o", tmp_path / "p.csv")  # fmt: skip
    assert rc == 2
    assert any(match in line for line in err), err


def test_the_peaks_after_observed_are_of_what_is_sent(tmp_path, capsys):
    """A prefix observed fast: the peaks said are those from its last sample
    on (what a JointTrajectory sends), not the executed prefix's."""
    from ndlfd import KeypointHMM

    model_file = tmp_path / "m.ndlfd"
    fit_model(write_obstacle(tmp_path / "demos", 4, 2), model_file)
    model = KeypointHMM.load(model_file)
    plain = model.generate(np.linspace(0.0, 5.0, 251), dense=True)
    prefix = plain.take(np.arange(60)).select("position")
    prefix_fast = prefix.X.copy()
    prefix_fast[:30] += np.linspace(0, 1, 30)[:, None] * [[3.0, 0.0]]  # a jerk
    prefix_fast[30:] += [[3.0, 0.0]]
    np.savetxt(tmp_path / "prefix.csv", np.column_stack([prefix.t, prefix_fast]),
               delimiter=",", header="t,x,y", comments="", fmt="%.17g")  # fmt: skip
    out = tmp_path / "p.csv"
    rc, err = cli(capsys, "generate", model_file, "--duration", "5", "--samples",
                  "251", "--observed", tmp_path / "prefix.csv", "--max-velocity",
                  "position=1", "-o", out)  # fmt: skip
    assert rc == 0, err
    path = read_csv(out)
    rest = path.take(np.arange(59, path.n_samples))
    said = next(x for x in err if x.startswith("peaks: "))
    assert said.startswith(peaks_line(rest))
    assert said.endswith("(from the last of the 60 observed samples on)")
    assert not said.startswith(peaks_line(path))  # the prefix's were higher
