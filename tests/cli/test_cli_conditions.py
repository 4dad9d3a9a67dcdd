"""ndlfd generate / sample: --start/--goal for every group, and --observed."""

import re
import sys
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import cli

from ndlfd._errors import ExtrapolationWarning
from ndlfd.demonstration import Demonstration
from ndlfd.io import read_csv, write_csv
from ndlfd.learner import KeypointHMM

sys.path.insert(0, str(Path(__file__).parents[1] / "learner"))
from test_learner_routes import obstacle

T = np.linspace(0.0, 4.0, 200)
Q0 = [float(np.cos(0.2)), 0.0, 0.0, float(np.sin(0.2))]  # 0.4 rad about z


def pick_demos(n_demos=6, seed=0):
    """3-D carries turning about z, the gripper closing half way."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n_demos):
        s = np.linspace(0.0, 1.0, 150)
        P = np.column_stack([0.5 * s, 0.1 * np.sin(np.pi * s), 0.3 - 0.2 * s])
        P += rng.normal(0.0, 0.002, P.shape)
        half = 0.25 * s + rng.normal(0.0, 0.01)
        Q = np.column_stack([np.cos(half), 0 * s, 0 * s, np.sin(half)])
        t = 4.0 * s * rng.uniform(0.95, 1.05)
        out.append(Demonstration.from_arrays(t, position=P, orientation=Q,
                                             gripper=(s > 0.5) * 1.0))  # fmt: skip
    return out


@pytest.fixture(scope="module")
def pick_model(tmp_path_factory):
    path = tmp_path_factory.mktemp("pick") / "pick.ndlfd"
    KeypointHMM().fit(pick_demos()).save(path)
    return path, KeypointHMM.load(path)


def test_start_and_goal_take_every_learned_group(capsys, tmp_path, pick_model):
    path, model = pick_model
    q = ",".join(map(repr, Q0))
    rc, err = cli(capsys, "generate", path, "--duration", "4", "--samples", "200",
                  "--dense", "--start", "position=0.02,0,0.31", "--start",
                  f"orientation={q}", "--start", "gripper=1", "--goal",
                  "0.5,0.01,0.1", "-o", tmp_path / "p.csv")  # fmt: skip
    assert rc == 0, err
    # Q0 turns 0.4 rad and the gripper starts closed; every demonstration
    # starts within 0.05 rad of no turn, the gripper open: notes
    far = "the start of orientation (qw, qx, qy, qz) = (0.9801, 0, 0, 0.1987) is"
    shut = "the start of gripper (gripper0) = (1) is 20.0 spreads from"
    notes = [e for e in err if "warning" in e]
    assert len(notes) == 2, err
    assert notes[0].startswith(f"ndlfd generate: warning: {far}")
    assert notes[1].startswith(f"ndlfd generate: warning: {shut}")
    got = read_csv(tmp_path / "p.csv")
    start = {"position": [0.02, 0.0, 0.31], "orientation": Q0, "gripper": [1.0]}
    with pytest.warns(ExtrapolationWarning) as caught:
        expected = model.generate(T, dense=True, start=start,
                                  goal={"position": [0.5, 0.01, 0.1]})  # fmt: skip
    texts = [str(w.message) for w in caught]
    assert len(texts) == 2 and texts[0].startswith(far) and texts[1].startswith(shut)
    np.testing.assert_allclose(got.X, expected.X, rtol=5e-10, atol=1e-12)
    np.testing.assert_allclose(got.get("position")[0], [0.02, 0.0, 0.31], atol=1e-9)
    np.testing.assert_allclose(got.get("orientation")[0], Q0, atol=1e-9)
    assert got.get("gripper")[0, 0] == 1.0
    assert set(np.unique(got.get("gripper"))) <= {0.0, 1.0}  # stays two-valued
    np.testing.assert_allclose(got.get("position")[-1], [0.5, 0.01, 0.1], atol=1e-9)
    # -q is the same rotation: the same path
    minus = ",".join(repr(-v) for v in Q0)
    rc, err = cli(capsys, "generate", path, "--duration", "4", "--samples", "200",
                  "--dense", "--start", "position=0.02,0,0.31", "--start",
                  f"orientation={minus}", "--start", "gripper=1", "--goal",
                  "0.5,0.01,0.1", "-o", tmp_path / "m.csv")  # fmt: skip
    assert rc == 0, err
    assert (tmp_path / "m.csv").read_bytes() == (tmp_path / "p.csv").read_bytes()


def test_a_bare_start_is_a_position(capsys, tmp_path, pick_model):
    path, _ = pick_model
    for name, flag in (("bare", "0.02,0,0.31"), ("named", "position=0.02,0,0.31")):
        rc, err = cli(capsys, "sample", path, "--duration", "4", "--samples", "200",
                      "--start", flag, "--random-state", "2", "-n", "2",
                      "-o", tmp_path / name)  # fmt: skip
        assert rc == 0, err
    for f in sorted((tmp_path / "bare").glob("*.csv")):
        assert f.read_bytes() == (tmp_path / "named" / f.name).read_bytes()
        np.testing.assert_allclose(read_csv(f).get("position")[0], [0.02, 0, 0.31])


@pytest.mark.parametrize(
    ("flags", "message"),
    [
        (["--start", "force=1"], "--start names group 'force', which the model did"
         " not learn; it learned position, velocity, orientation, gripper"),
        (["--goal", "orientation=1,0,0"], "--goal must give 4 orientation values"
         " (one per column: qw, qx, qy, qz); got 3"),
        (["--start", "1,2"], "--start must give 3 position values (one per column:"
         " x, y, z); got 2"),
        (["--start", "1,2,3", "--start", "position=1,2,3"], "--start gives position"
         " twice"),
        (["--goal", "gripper=x"], "--goal gripper must be comma-separated numbers;"
         " got 'x'"),
        (["--start", "my grip=1"], "--start must look like GROUP=V1,V2,..."),
        (["--start", "orientation=0,0,0,0"], "must be a quaternion w, x, y, z of"
         " non-zero norm"),
    ],
)  # fmt: skip
def test_bad_start_and_goal_flags(capsys, tmp_path, pick_model, flags, message):
    path, _ = pick_model
    for command in ("generate", "sample"):
        rc, err = cli(capsys, command, path, "--duration", "4", *flags,
                      "-o", tmp_path / "out.csv")  # fmt: skip
        assert rc == 2 and len(err) == 1, err
        assert message in err[0], err


def test_a_negative_bare_start_is_told_to_take_an_equals_sign(capsys, tmp_path,
                                                              pick_model):  # fmt: skip
    path, _ = pick_model
    with pytest.raises(SystemExit) as exit_:  # argparse's usage error
        cli(capsys, "generate", path, "--duration", "4", "--start", "-1,0,0",
            "-o", tmp_path / "o.csv")  # fmt: skip
    err = capsys.readouterr().err.splitlines()
    assert exit_.value.code == 2 and len(err) == 1
    assert "a value that starts with '-' takes '=': --start=-..." in err[0]
    rc, err = cli(capsys, "generate", path, "--duration", "4", "--start=-0.01,0,0.3",
                  "-o", tmp_path / "o.csv")  # fmt: skip
    assert rc == 0, err
    np.testing.assert_allclose(read_csv(tmp_path / "o.csv").get("position")[0],
                               [-0.01, 0.0, 0.3])  # fmt: skip


# ------------------------------------------------------------- --observed

G = np.linspace(0.0, 5.0, 201)


@pytest.fixture(scope="module")
def routes_model(tmp_path_factory):
    demos = obstacle(9, 3)  # 9 over the bump above, 3 below
    path = tmp_path_factory.mktemp("observed") / "m.ndlfd"
    KeypointHMM().fit(demos).save(path)
    return demos, path, KeypointHMM.load(path)


def _write_prefix(demo, times, path):
    """``demo`` on the normalized clock of ``G``, at ``times``: a CSV file."""
    tau = demo.t / demo.t[-1]
    X = np.column_stack([np.interp(times / G[-1], tau, c) for c in demo.X.T])
    write_csv(Demonstration(times, X, demo.columns, demo.groups), path)
    return read_csv(path)


def _no_jump(P, n, prefix, demos):
    rng = np.ptp(np.vstack([d.get("position") for d in demos]), axis=0)
    largest = np.abs(np.diff(prefix.X, axis=0)).max(axis=0)
    return bool(np.all(np.abs(P[n] - P[n - 1]) <= largest + 0.005 * rng))


def test_generate_continues_an_observed_prefix(capsys, tmp_path, routes_model):
    demos, path, model = routes_model
    prefix = _write_prefix(demos[10], G[:60], tmp_path / "prefix.csv")  # minor
    rc, err = cli(capsys, "generate", path, "--duration", "5", "--samples", "201",
                  "--observed", tmp_path / "prefix.csv",
                  "-o", tmp_path / "p.csv")  # fmt: skip
    assert rc == 0, err
    assert "generated 201 samples (the first 60 observed)" in err[-1]
    got = read_csv(tmp_path / "p.csv")
    np.testing.assert_array_equal(got.t, G)  # the prefix's stamps, then the grid's
    np.testing.assert_allclose(got.get("position")[:60], prefix.X, rtol=5e-10)
    expected = model.generate(G, observed=prefix)
    np.testing.assert_allclose(got.X, expected.X, rtol=5e-10, atol=1e-12)
    P = got.get("position")
    assert _no_jump(P, 60, prefix, demos)
    assert P[100, 1] < -4.5  # the minor route, as the prefix


def test_the_prefix_gives_the_first_time_stamps(capsys, tmp_path, routes_model):
    # a prefix at its own rate: its stamps, then the grid's after them
    demos, path, _ = routes_model
    times = np.arange(0.0, 1.19, 0.04)  # 30 samples, not on the grid
    prefix = _write_prefix(demos[1], times, tmp_path / "prefix.csv")
    rc, err = cli(capsys, "generate", path, "--duration", "5", "--samples", "201",
                  "--observed", tmp_path / "prefix.csv",
                  "-o", tmp_path / "p.csv")  # fmt: skip
    assert rc == 0, err
    got = read_csv(tmp_path / "p.csv")
    n = times.size
    np.testing.assert_array_equal(got.t[:n], prefix.t)
    # the grid's stamps more than half its step (0.0125 s) after the prefix
    np.testing.assert_array_equal(got.t[n:], G[G > times[-1] + 0.0125])
    assert _no_jump(got.get("position"), n, prefix, demos)
    assert got.get("position")[np.argmin(np.abs(got.t - 2.5)), 1] > 4.5  # major


def test_samples_all_continue_an_observed_prefix(capsys, tmp_path, routes_model):
    demos, path, model = routes_model
    prefix = _write_prefix(demos[9], G[:60], tmp_path / "prefix.csv")  # minor
    for out in ("a", "b"):
        rc, err = cli(capsys, "sample", path, "-n", "6", "--duration", "5",
                      "--samples", "201", "--observed", tmp_path / "prefix.csv",
                      "--random-state", "4", "-o", tmp_path / out)  # fmt: skip
        assert rc == 0, err
    assert "drew 6 path(s) of samples, each continuing the 60 observed" in err[-1]
    expected = model.sample(G, 6, observed=prefix, random_state=4)
    files = sorted((tmp_path / "a").glob("sample_*.csv"))
    assert len(files) == 6
    tails = []
    for f, e in zip(files, expected, strict=True):
        assert f.read_bytes() == (tmp_path / "b" / f.name).read_bytes()
        got = read_csv(f)
        np.testing.assert_allclose(got.X, e.X, rtol=5e-10, atol=1e-12)
        P = got.get("position")
        np.testing.assert_allclose(P[:60], prefix.X, rtol=5e-10)
        assert _no_jump(P, 60, prefix, demos)
        assert P[100, 1] < -4.5
        tails.append(P[60:])
    assert np.unique(np.round(tails, 6), axis=0).shape[0] > 1


@pytest.mark.parametrize(
    ("prefix_times", "flags", "message"),
    [
        (G[5:40], [], "--observed starts at 0.125 s, the timing at 0 s"),
        (np.linspace(0, 5.2, 30), [], "--observed ends at 5.2 s, not before the"
         " timing's end 5 s"),
        (G[:40], ["--start=-10,0"], "cannot be combined with --start or --via"),
        (G[:40], ["--via", "2:position=-6,5"], "cannot be combined with --start"),
    ],
)  # fmt: skip
def test_bad_observed_flags(capsys, tmp_path, routes_model, prefix_times, flags,
                            message):  # fmt: skip
    demos, path, _ = routes_model
    _write_prefix(demos[0], prefix_times, tmp_path / "prefix.csv")
    for command in ("generate", "sample"):
        rc, err = cli(capsys, command, path, "--duration", "5", "--observed",
                      tmp_path / "prefix.csv", *flags,
                      "-o", tmp_path / "o.csv")  # fmt: skip
        assert rc == 2, err
        assert re.search(re.escape(message), err[-1]), err


def test_observed_needs_one_demonstration_and_a_blend_model(capsys, tmp_path,
                                                            routes_model):  # fmt: skip
    demos, path, _ = routes_model
    folder = tmp_path / "two"
    folder.mkdir()
    for k in range(2):
        _write_prefix(demos[k], G[:30], folder / f"p{k}.csv")
    rc, err = cli(capsys, "generate", path, "--duration", "5", "--observed", folder,
                  "-o", tmp_path / "o.csv")  # fmt: skip
    assert rc == 2 and "--observed must name one demonstration" in err[-1]
    paper = tmp_path / "paper.ndlfd"
    KeypointHMM(generation="paper").fit(demos).save(paper)
    rc, err = cli(capsys, "generate", paper, "--duration", "5", "--observed",
                  folder / "p0.csv", "-o", tmp_path / "o.csv")  # fmt: skip
    assert rc == 2
    assert "--observed needs a model fitted with --generation blend" in err[-1]
