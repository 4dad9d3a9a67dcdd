"""generate and sample warn of a --start or --goal far outside the demonstrations.

Issue 37: a start 95 degrees outside every demonstration in joint space was
accepted without a word. The distance is checked here against a reference
computed from the CSV files themselves (numpy.loadtxt), not from the model.
"""

import numpy as np
from cli_helpers import cli

from ndlfd.learner._extrapolation import FAR_SPREADS, SPREAD_FLOOR

JOINTS = ("shoulder_pan", "elbow_flex", "wrist_flex")
FLAGS = ("--time-column", "stamp", "--group", "joints=" + ",".join(JOINTS),
         "--drop", "temp_c")  # fmt: skip


def write_log(folder, n_demos=5, seed=0):
    """Joint logs in degrees, every value at full precision (repr)."""
    rng = np.random.default_rng(seed)
    folder.mkdir(parents=True, exist_ok=True)
    for i in range(n_demos):
        n = 90 + 7 * i
        t = np.arange(n) / 30.0
        s = np.linspace(0.0, 1.0, n)
        rows = np.column_stack([t, 10.0 + 40.0 * s + rng.normal(0, 2.0),
                                25.0 * np.sin(np.pi * s) + 3.0 * i,
                                -15.0 * s**2 + rng.normal(0, 1.0),
                                30 + rng.normal(size=n)])  # fmt: skip
        lines = [",".join(("stamp", *JOINTS, "temp_c"))]
        lines += [",".join(repr(float(v)) for v in r) for r in rows]
        (folder / f"log{i}.csv").write_text("\n".join(lines) + "\n")
    return sorted(folder.glob("*.csv"))


def reference(files, row, target):
    """(spreads, nearest file, degrees) by the definition, from the files."""
    tables = [np.loadtxt(f, delimiter=",", skiprows=1)[:, 1:4] for f in files]
    P = np.array([a[row] for a in tables])
    everything = np.concatenate(tables)
    floor = SPREAD_FLOOR * (everything.max() - everything.min())
    spread = np.maximum(P.std(axis=0), floor)
    d = [float(np.sqrt(np.sum(((target - p) / spread) ** 2))) for p in P]
    i = int(np.argmin(d))
    return d[i], i, float(np.linalg.norm(target - P[i])), P


def test_a_start_95_degrees_outside_is_warned(tmp_path, capsys):
    files = write_log(tmp_path / "logs")
    model = tmp_path / "m.ndlfd"
    rc, err = cli(capsys, "fit", tmp_path / "logs", *FLAGS, "-o", model, "-q")
    assert rc == 0, err
    out = tmp_path / "g.csv"
    timing = ("--duration", "3", "--samples", "60")
    # the start of a demonstration, as written: inside, not a word
    first = np.loadtxt(files[2], delimiter=",", skiprows=1)[0, 1:4]
    start = "joints=" + ",".join(repr(float(v)) for v in first)
    rc, err = cli(capsys, "generate", model, *timing, "--start", start, "-o", out)
    assert rc == 0 and not [e for e in err if "warning" in e], err
    # 95 degrees past the widest shoulder_pan start
    _, _, _, P = reference(files, 0, first)
    far = P[np.argmax(P[:, 0])] + [95.0, 0.0, 0.0]
    spreads, i, degrees, _ = reference(files, 0, far)
    assert spreads > FAR_SPREADS
    start = "joints=" + ",".join(repr(float(v)) for v in far)
    rc, err = cli(capsys, "generate", model, *timing, "--start", start, "-o", out)
    assert rc == 0, err
    (line,) = [e for e in err if "warning" in e]
    values = ", ".join(f"{v:.4g}" for v in far)
    assert line.startswith(
        f"ndlfd generate: warning: the start of joints ({', '.join(JOINTS)}) ="
        f" ({values}) is {spreads:.1f} spreads from the nearest demonstration's"
        f" start (demonstration {i}, "
    ), line
    assert f": {degrees:.3g} away in the data's units)" in line
    assert abs(degrees - 95.0) < 1e-9  # the nearest is the one it left from
    path = np.loadtxt(out, delimiter=",", skiprows=1, ndmin=2)
    np.testing.assert_allclose(path[0, 1:4], far, rtol=1e-9)  # made as asked
    # sample --goal: the same check on the demonstrations' last samples
    goals = reference(files, -1, far)[3]
    goal_far = goals[np.argmin(goals[:, 2])] + [0.0, 0.0, -80.0]
    spreads, i, degrees, _ = reference(files, -1, goal_far)
    assert spreads > FAR_SPREADS and abs(degrees - 80.0) < 1e-9
    goal = "joints=" + ",".join(repr(float(v)) for v in goal_far)
    rc, err = cli(capsys, "sample", model, *timing, "-n", "2", "--random-state",
                  "0", "--goal", goal, "-o", tmp_path / "samples")  # fmt: skip
    assert rc == 0, err
    (line,) = [e for e in err if "warning" in e]
    assert f"the goal of joints ({', '.join(JOINTS)}) = (" in line
    assert f" is {spreads:.1f} spreads from the nearest demonstration's goal" in line
    assert f"(demonstration {i}, " in line and f": {degrees:.3g} away" in line
