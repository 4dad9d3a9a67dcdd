"""rate=: files without time stamps (fixed-rate logs), row k at k / rate."""

import numpy as np
import pytest

from ndlfd._errors import DataFileError, ValidationError
from ndlfd.io import DemoFiles, read_demos


def franka_log(path, n=41, seed=0, bad_row=None):
    """A 20 Hz log without a time column: 7 joints and a gripper width."""
    rng = np.random.default_rng(seed)
    q = np.cumsum(rng.normal(0, 0.01, (n, 7)), axis=0)
    width = np.linspace(0.08, 0.0, n)
    rows = ["q0,q1,q2,q3,q4,q5,q6,gripper"]
    for i in range(n):
        values = [*q[i], width[i]]
        if i == bad_row:
            values[2] = float("nan")
        rows.append(",".join(repr(float(v)) for v in values))
    path.write_text("\n".join(rows) + "\n")
    return q, width


def test_rate_times_rows_of_a_log_without_time(tmp_path):
    q, width = franka_log(tmp_path / "a.csv")
    franka_log(tmp_path / "b.csv", n=30, seed=1)
    groups = {"joints": [f"q{k}" for k in range(7)]}
    demos, maps = read_demos(tmp_path, rate=20, groups=groups, return_mappings=True)
    assert [d.n_samples for d in demos] == [41, 30]
    assert np.array_equal(demos[0].t, np.arange(41) / 20)  # row k at k / 20 s
    assert np.array_equal(demos[0].get("joints"), q)
    assert np.array_equal(demos[0].get("gripper")[:, 0], width)
    assert str(maps[0]).startswith("time=(row number) / 20 Hz; joints=q0,")
    # without rate: the error says what is missing
    with pytest.raises(DataFileError, match="expected a time column named 't'"):
        read_demos(tmp_path, groups=groups)
    # dropping a bad row would shift the later rows' times: refused
    franka_log(tmp_path / "c.csv", n=10, bad_row=4)
    with pytest.raises(ValidationError, match=r"rate= times the rows by their"
                       r" number, and dropping a bad row would shift"):  # fmt: skip
        read_demos(tmp_path / "c.csv", rate=10, groups=groups, bad_rows="drop")
    (first,) = DemoFiles(tmp_path / "a.csv", rate=20, groups=groups)[0].read()
    assert first == demos[0]


def test_rate_errors_say_what_was_expected(tmp_path):
    franka_log(tmp_path / "a.csv")
    timed = tmp_path / "timed.csv"
    timed.write_text("t,x\n0,1\n1,2\n")
    with pytest.raises(ValidationError, match=r"rate= must be a sample rate in Hz"
                       r" > 0; got 0"):  # fmt: skip
        read_demos(tmp_path / "a.csv", rate=0)
    with pytest.raises(DataFileError, match=r"timed.csv: rate= gives the time of"
                       r" files without time stamps; this one has a time column"
                       r" 't' \(name it with time_column= instead"):  # fmt: skip
        read_demos(timed, rate=5)
    with pytest.raises(ValidationError, match="rate= and time_column= both give"):
        read_demos(timed, rate=5, time_column="t")
