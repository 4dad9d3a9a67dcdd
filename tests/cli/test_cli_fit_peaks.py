"""``ndlfd fit`` reports the demonstrations' peak velocity and acceleration.

The references are worked by hand (polynomials whose ``numpy.gradient`` is
exact) or by ``numpy.gradient`` on the values read back, never by the
command's own code.
"""

import numpy as np
import pytest
from cli_helpers import cli

from ndlfd.io import read_lerobot

h5py = pytest.importorskip("h5py")


def _peaks_by_hand(t, X):
    """Largest |velocity| and |acceleration| per column (second-order ends)."""
    V = np.gradient(X, t, axis=0, edge_order=2)
    A = np.gradient(V, t, axis=0, edge_order=2)
    return np.abs(V).max(axis=0), np.abs(A).max(axis=0)


def test_the_peaks_of_one_file_of_episodes_are_the_largest_of_all(tmp_path, capsys):
    # two episodes of quadratic motion: gradient is exact, so the peaks are
    # worked by hand. ep1: x = 3 t^2 on [0, 2] (velocity 12, acceleration 6);
    # ep2: y = -5 t^2 on [0, 1] (velocity 10, acceleration 10)
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
