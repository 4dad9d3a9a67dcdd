"""``ndlfd fit`` reports the demonstrations' peak velocity and acceleration.

The references are worked by hand (polynomials whose ``numpy.gradient`` is
exact) or by ``numpy.gradient`` on the values read back, never by the
command's own code.
"""

import re

import numpy as np
import pytest
from cli_helpers import cli
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd.cli._fit import demos_peaks_line
from ndlfd.demonstration import Demonstration
from ndlfd.io import read_lerobot


def _peaks_by_hand(t, X):
    """Largest |velocity| and |acceleration| per column (second-order ends)."""
    V = np.gradient(X, t, axis=0, edge_order=2)
    A = np.gradient(V, t, axis=0, edge_order=2)
    return np.abs(V).max(axis=0), np.abs(A).max(axis=0)


def test_the_peaks_of_one_file_of_episodes_are_the_largest_of_all(tmp_path, capsys):
    # two episodes of quadratic motion: gradient is exact, so the peaks are
    # worked by hand. ep1: x = 3 t^2 on [0, 2] (velocity 12, acceleration 6);
    # ep2: y = -5 t^2 on [0, 1] (velocity 10, acceleration 10)
    h5py = pytest.importorskip("h5py")
    p = tmp_path / "two.h5"
    with h5py.File(p, "w") as f:
        for name, t, x, y in (
            ("ep1", np.linspace(0, 2, 41), lambda t: 3 * t**2, lambda t: t),
            ("ep2", np.linspace(0, 1, 31), lambda t: t, lambda t: -5 * t**2),
        ):
            g = f.create_group(name)
            g["time"], g["pos"] = t, np.column_stack([x(t), y(t)])
    rc, err = cli(capsys, "fit", p, "-o", tmp_path / "m.npz", "--time-bins", "10")
    assert rc == 0
    (line,) = [e for e in err if e.startswith("demonstrations' peaks")]
    # velocity beside a position is left out (derived), as generate's line does
    assert line == (
        "demonstrations' peaks: position velocity 12 /s (x), acceleration 10 /s^2 (y)"
    )


def test_the_peaks_of_a_lerobot_dataset_are_its_first_episodes(tmp_path, capsys):
    pytest.importorskip("pyarrow")
    from lerobot_writer import write_so101

    root, _ = write_so101(tmp_path / "so101", n_demos=4)
    demos = read_lerobot(root)
    cols = demos[0].columns_of("joints")
    v, a = _peaks_by_hand(demos[0].t, demos[0].X[:, cols])
    names = [demos[0].columns[c] for c in cols]
    rc, err = cli(capsys, "fit", root, "-o", tmp_path / "m.npz")
    assert rc == 0
    (line,) = [e for e in err if e.startswith("demonstrations' peaks")]
    assert line == (
        f"demonstrations' peaks (of {root} episode 0 only, the first of 4):"
        f" joints velocity {v.max():.3g} /s ({names[int(np.argmax(v))]}),"
        f" acceleration {a.max():.3g} /s^2 ({names[int(np.argmax(a))]})"
    )  # the gripper (40 or 5) switches in one sample: left out
    # another episode's peaks differ: the line is episode 0's, as it says
    v3, _ = _peaks_by_hand(demos[3].t, demos[3].X[:, cols])
    assert f"{v3.max():.3g}" != f"{v.max():.3g}"
    # one episode read: no caveat
    rc, err = cli(capsys, "fit", root, "-o", tmp_path / "m.npz", "--episodes", "0")
    assert rc == 0
    assert [e for e in err if e.startswith("demonstrations' peaks")] == [
        line.replace(f" (of {root} episode 0 only, the first of 4)", "")
    ]


def test_no_peaks_line_when_quiet_or_too_short(tmp_path, capsys):
    p = tmp_path / "short.csv"
    p.write_text("t,x,y\n0,0,0\n1,1,1\n")
    rc, err = cli(capsys, "fit", p, "-o", tmp_path / "m.npz", "--time-bins", "2")
    assert rc == 0
    assert not [
        e for e in err if e.startswith("demonstrations' peaks")
    ]  # 2 samples: no acceleration
    q = tmp_path / "long.csv"
    q.write_text("t,x,y\n" + "".join(f"{i},{i * i},0\n" for i in range(5)))
    rc, err = cli(capsys, "fit", q, "-o", tmp_path / "m.npz", "-q")
    assert rc == 0 and err == []


def _derivative_by_hand(t, y):
    """Second-order finite differences on uneven stamps, one sample at a time."""
    n = len(t)
    d = np.empty(n)
    for i in range(1, n - 1):
        a, b = t[i] - t[i - 1], t[i + 1] - t[i]
        d[i] = (a * a * y[i + 1] - b * b * y[i - 1] + (b * b - a * a) * y[i]) / (
            a * b * (a + b)
        )
    a, b = t[1] - t[0], t[2] - t[1]
    d[0] = (-(2 * a + b) / (a * (a + b)) * y[0] + (a + b) / (a * b) * y[1]
            - a / (b * (a + b)) * y[2])  # fmt: skip
    a, b = t[-2] - t[-3], t[-1] - t[-2]
    d[-1] = (b / (a * (a + b)) * y[-3] - (a + b) / (a * b) * y[-2]
             + (2 * b + a) / (b * (a + b)) * y[-1])  # fmt: skip
    return d


_DEMO = st.integers(3, 12).flatmap(
    lambda n: st.tuples(
        st.lists(st.floats(0.05, 2.0), min_size=n - 1, max_size=n - 1),
        st.lists(
            st.lists(st.floats(-50, 50), min_size=2, max_size=2),
            min_size=n,
            max_size=n,
        ),
    )
)


@settings(max_examples=80, deadline=None)
@given(st.lists(_DEMO, min_size=1, max_size=3))
def test_the_peaks_line_is_the_largest_over_demonstrations(demos):
    built, best = [], {}
    for steps, values in demos:
        t = np.concatenate([[0.0], np.cumsum(steps)])
        X = np.array(values)
        built.append(Demonstration.from_arrays(t, joints=X))
        for c in range(2):
            v = _derivative_by_hand(t, X[:, c])
            a = _derivative_by_hand(t, v)
            was = best.get(c, (0.0, 0.0))
            best[c] = (max(was[0], np.abs(v).max()), max(was[1], np.abs(a).max()))
    line = demos_peaks_line(built, ["joints"])
    m = re.fullmatch(
        r"joints velocity (\S+) /s \((\w+)\), acceleration (\S+) /s\^2 \((\w+)\)",
        line,
    )
    assert m, line
    names = built[0].columns
    for k, (value, name) in enumerate([(m[1], m[2]), (m[3], m[4])]):
        top = max(best[c][k] for c in range(2))
        assert float(value) == pytest.approx(top, rel=5e-3, abs=1e-9)
        # the column named has the peak (up to rounding: near-ties either way)
        assert best[names.index(name)][k] == pytest.approx(top, rel=1e-9, abs=1e-9)
