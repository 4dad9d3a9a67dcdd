"""ndlfd fit --rate HZ: logs without a time column."""

import numpy as np
from cli_helpers import cli

from ndlfd.learner import KeypointHMM


def write_log(path, n, seed):
    """A fixed-rate log: 7 joints, no time column."""
    q = np.cumsum(np.random.default_rng(seed).normal(0, 0.01, (n, 7)), axis=0)
    header = ",".join(f"joints.q{k}" for k in range(7))
    np.savetxt(path, q, delimiter=",", header=header, comments="")
    return q


def test_fit_a_log_without_time_at_its_rate(tmp_path, capsys):
    folder = tmp_path / "logs"
    folder.mkdir()
    for i in range(5):
        write_log(folder / f"run{i}.csv", 60 + 5 * i, i)
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", folder, "-o", model)
    assert rc == 2 and "expected a time column named 't'" in err[0]
    rc, err = cli(capsys, "fit", folder, "--rate", 20, "-o", model)
    assert rc == 0, err
    assert err[0].startswith(
        "read 5 demonstration(s) from 5 file(s): time=(row number) / 20 Hz;"
        " joints=joints.q0,"
    )
    fitted = KeypointHMM.load(model)
    assert fitted.n_demos_ == 5
    rc, err = cli(capsys, "fit", folder, "--rate", -3, "-o", model)
    assert rc == 2 and err == [
        "ndlfd fit: error: --rate must be a sample rate in Hz > 0; got -3.0"
    ]
