import copy
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ndlfd import synth
from ndlfd._simplify import simplify
from ndlfd.cli import main
from ndlfd.demonstration import Demonstration
from ndlfd.io import read_csv, read_table, write_csv, write_table
from ndlfd.learner import KeypointHMM

BIN = Path(sys.executable).parent / "ndlfd"


def run(*args, cwd=None):
    cmd = (
        [str(BIN), *map(str, args)]
        if BIN.exists()
        else [sys.executable, "-m", "ndlfd.cli", *map(str, args)]
    )
    env = dict(os.environ, PYTHONWARNINGS="error")
    return subprocess.run(
        cmd, capture_output=True, text=True, cwd=cwd, env=env, timeout=300
    )


def _walk_csv(path, n=300, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.01
    xy = np.cumsum(rng.normal(size=(n, 2)), axis=0)
    data = np.column_stack([t, xy, rng.normal(size=n)])
    write_table(path, ["t", "x", "y", "extra"], data)
    return data


def _square_demos(folder, n_demos=6, seed=0):
    """A folder of small demonstrations (position and velocity, 80 samples)."""
    folder.mkdir(parents=True, exist_ok=True)
    train, _ = synth.make_dataset("square", n_demos=n_demos, random_state=seed)
    for i, d in enumerate(train):
        write_csv(d, folder / f"demo{i:02d}.csv")
    return folder


def test_help_for_every_command():
    r = run("--help")
    assert r.returncode == 0
    for cmd in ("simplify", "fit", "generate", "plot", "demo", "reproduce"):
        assert cmd in r.stdout
        h = run(cmd, "--help")
        assert h.returncode == 0, h.stderr
        assert "usage: ndlfd " + cmd in h.stdout


def test_simplify_round_trip(tmp_path):
    data = _walk_csv(tmp_path / "walk.csv")
    r = run(
        "simplify",
        tmp_path / "walk.csv",
        "--epsilon",
        "2.0",
        "--columns",
        "x,y",
        "--normalization",
        "none",
        "-o",
        tmp_path / "out.csv",
    )
    assert r.returncode == 0, r.stderr
    cols, out = read_table(tmp_path / "out.csv")
    assert cols == ["t", "x", "y", "extra"]
    idx = simplify(data[:, 1:3], 2.0)
    np.testing.assert_array_equal(out, data[idx])
    assert f"kept {idx.size} of 300 points" in r.stderr


def test_simplify_default_columns_exclude_time_and_mask(tmp_path):
    data = _walk_csv(tmp_path / "walk.csv")
    r = run(
        "simplify",
        tmp_path / "walk.csv",
        "--epsilon",
        "1.5",
        "--mask",
        "-o",
        tmp_path / "mask.csv",
        "-q",
    )
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""
    cols, out = read_table(tmp_path / "mask.csv")
    assert cols == ["t", "x", "y", "extra", "keep"]
    # x, y share the position range; 'extra' (no group by its name) has its own
    xy, extra = data[:, 1:3], data[:, 3:]
    U = np.column_stack(
        [(xy - xy.min()) / (xy.max() - xy.min()),
         (extra - extra.min()) / (extra.max() - extra.min())]
    )  # fmt: skip
    mask = simplify(U, 1.5, return_mask=True)
    np.testing.assert_array_equal(out[:, :4], data)
    np.testing.assert_array_equal(out[:, 4], mask.astype(float))
    assert (tmp_path / "mask.csv").read_text().splitlines()[1].endswith(",1")


def test_simplify_sed_uses_time_column_and_budget(tmp_path):
    data = _walk_csv(tmp_path / "walk.csv")
    r = run(
        "simplify",
        tmp_path / "walk.csv",
        "--n-points",
        "12",
        "--distance",
        "sed",
        "--columns",
        "x,y",
        "--normalization",
        "none",
        "-o",
        tmp_path / "o.csv",
    )
    assert r.returncode == 0, r.stderr
    _, out = read_table(tmp_path / "o.csv")
    idx = simplify(data[:, 1:3], n_points=12, distance="sed", times=data[:, 0])
    np.testing.assert_array_equal(out, data[idx])


@pytest.mark.parametrize(
    ("content", "args", "match"),
    [
        (
            "t,x,y\n0,1,2\n1,2,3\n",
            ["--columns", "x,z"],
            "--columns names 'z', but there is no such column; got columns ['t',",
        ),
        ("t,x,y\n0,1,2\n1,abc,3\n", [], "line 3"),
        ("t,x,y\n0,1,2\n1,nan,3\n", [], "line 3"),
        (
            "t,x\n0,1\n1,2\n",
            ["--distance", "sed", "--time-column", "time"],
            "--time-column names 'time', but there is no such column",
        ),
        ("t,x\n0,1\n1,2\n", ["--weights", "1,x"], "--weights"),
        ("t,x\n0,1\n1,2\n", ["--weights", "1,2"], "weights"),
    ],
)
def test_simplify_bad_input_is_one_line_exit_2(tmp_path, content, args, match):
    f = tmp_path / "bad.csv"
    f.write_text(content)
    r = run("simplify", f, "--epsilon", "0.1", *args, "-o", tmp_path / "o.csv")
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert match in lines[0]
    assert "Traceback" not in r.stderr
    assert not (tmp_path / "o.csv").exists()


def test_usage_errors_are_one_line(tmp_path):
    r = run("simplify", tmp_path / "x.csv", "-o", tmp_path / "o.csv")
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1
    assert "--epsilon" in r.stderr
    r = run("simplify", tmp_path / "missing.csv", "--epsilon", "1", "-o", "o.csv")
    assert r.returncode == 2 and "missing.csv" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    r = run()
    assert r.returncode == 2


def test_fit_generate_round_trip(tmp_path):
    from ndlfd import synth
    from ndlfd.io import read_csv, write_csv
    from ndlfd.learner import KeypointHMM

    train, test = synth.make_dataset("square", n_demos=12, random_state=5)
    (tmp_path / "demos").mkdir()
    for i, d in enumerate(train):
        write_csv(d.select("position"), tmp_path / "demos" / f"demo{i:02d}.csv")
    write_csv(test.select("position"), tmp_path / "test.csv")
    r = run(
        "fit",
        tmp_path / "demos",
        "-o",
        tmp_path / "m.ndlfd",
        "--levels",
        "position=20,velocity=10",
        "--epsilon",
        "0.05",
        "--time-bins",
        "30",
    )
    assert r.returncode == 0, r.stderr
    assert "fitted 12 demonstration(s)" in r.stderr
    r = run(
        "generate",
        tmp_path / "m.ndlfd",
        "--like",
        tmp_path / "test.csv",
        "-o",
        tmp_path / "gen.csv",
    )
    assert r.returncode == 0, r.stderr
    gen = read_csv(tmp_path / "gen.csv")
    # the same as the library on the same files
    demos = [read_csv(p) for p in sorted((tmp_path / "demos").glob("*.csv"))]
    model = KeypointHMM(
        levels={"position": 20, "velocity": 10}, epsilon=0.05, n_time_bins=30
    ).fit(demos)
    expected = model.generate(read_csv(tmp_path / "test.csv"))
    # computed numbers are written with ten significant digits
    np.testing.assert_allclose(gen.X, expected.X, rtol=5e-10, atol=1e-300)
    np.testing.assert_allclose(gen.t, expected.t, rtol=5e-10, atol=1e-300)
    r = run(
        "generate",
        tmp_path / "m.ndlfd",
        "--duration",
        "2",
        "--samples",
        "101",
        "--dense",
        "-o",
        tmp_path / "dense.csv",
    )
    assert r.returncode == 0, r.stderr
    dense = read_csv(tmp_path / "dense.csv")
    assert dense.n_samples == 101 and dense.group_names == ("position", "velocity")
    assert dense.t[-1] == 2.0  # the last sample is at the end of the duration
    r = run(
        "generate",
        tmp_path / "m.ndlfd",
        "--duration",
        "3",
        "--samples",
        "61",
        "--dense",
        "--start",
        "0.5,-0.25",
        "--goal",
        "0.25,0.5",
        "-o",
        tmp_path / "pinned.csv",
    )
    assert r.returncode == 0, r.stderr
    pinned = read_csv(tmp_path / "pinned.csv")
    expected = model.generate(
        np.linspace(0.0, 3.0, 61),
        dense=True,
        start={"position": [0.5, -0.25]},
        goal={"position": [0.25, 0.5]},
    )
    np.testing.assert_allclose(pinned.X, expected.X, rtol=5e-10, atol=1e-300)
    np.testing.assert_allclose(
        pinned.get("position")[[0, -1]], [[0.5, -0.25], [0.25, 0.5]], atol=1e-12
    )
    r = run("generate", tmp_path / "m.ndlfd", "--duration", "3", "--start", "0,x",
            "-o", tmp_path / "bad.csv")  # fmt: skip
    assert r.returncode == 2 and "--start must be comma-separated" in r.stderr


def test_fit_and_generate_errors(tmp_path):
    r = run("generate", tmp_path / "nope.ndlfd", "--duration", "1", "-o", "x.csv")
    assert r.returncode == 2 and "no such file" in r.stderr
    (tmp_path / "junk.ndlfd").write_bytes(b"junk")
    r = run("generate", tmp_path / "junk.ndlfd", "--duration", "1", "-o", "x.csv")
    assert r.returncode == 2 and "not readable" in r.stderr
    r = run("fit", tmp_path / "empty-dir-missing", "-o", tmp_path / "m.ndlfd")
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1
    # a real folder of demonstrations, so the run gets as far as --levels
    folder = _square_demos(tmp_path / "demos", n_demos=3)
    r = run("fit", folder, "-o", tmp_path / "m.ndlfd", "--levels", "position=x")
    assert r.returncode == 2
    assert r.stderr.strip().splitlines() == [
        "ndlfd fit: error: --levels: 'x' is not a valid number in 'position=x'"
    ]
    assert not (tmp_path / "m.ndlfd").exists()


def test_demo_quick(tmp_path):
    r = run("demo", "--quick", "--out", tmp_path / "out")
    assert r.returncode == 0, r.stderr
    assert "square" in r.stdout and "DTW to the held-out test" in r.stdout
    names = {p.name for p in (tmp_path / "out").iterdir()}
    assert {
        "square_generated_keypoints.csv",
        "square_generated_dense.csv",
        "square.png",
    } <= names


# -- ndlfd fit honours every option ------------------------------------------------
# In-process (ndlfd.cli.main, the console script's function) to keep this fast.


@pytest.fixture(scope="module")
def fit_setup(tmp_path_factory):
    """The demonstration folder, its demos read back, and the default fit."""
    tmp = tmp_path_factory.mktemp("fit")
    folder = _square_demos(tmp / "demos")
    demos = [read_csv(p) for p in sorted(folder.glob("*.csv"))]
    default = _fit(folder, tmp / "default.ndlfd")
    return folder, demos, default, tmp


def _fit(folder, out, *options):
    assert main(["fit", str(folder), "-o", str(out), "-q", *options]) == 0
    return KeypointHMM.load(out)


def _fitted_arrays(model):
    """Everything fit learns (not the constructor parameters)."""
    arrays = {
        "keypoints": np.concatenate(model.keypoints_),
        "levels": np.asarray(model.codebook_.levels),
        "scaler_min": model.scaler_.data_min_,
        "scaler_max": model.scaler_.data_max_,
    }
    arrays.update(model.model_.to_arrays())
    return arrays


def _assert_same_fit(a, b):
    fa, fb = _fitted_arrays(a), _fitted_arrays(b)
    assert fa.keys() == fb.keys()
    for k in fa:
        np.testing.assert_array_equal(fa[k], fb[k], err_msg=k)


def _keypoints_by_simplify(model, demos, **kw):
    """Key points of each demo from the model's own scaling, by simplify."""
    return [
        simplify(model.scaler_.transform(d.select(*model.groups_)), **kw).tolist()
        for d in demos
    ]


def test_fit_default_is_the_library_default(fit_setup):
    _folder, demos, default, _ = fit_setup
    assert (
        default.get_params()
        == KeypointHMM(groups=("position", "velocity")).get_params()
    )
    _assert_same_fit(default, KeypointHMM().fit(demos))


def test_fit_n_points(fit_setup):
    folder, demos, default, tmp = fit_setup
    model = _fit(folder, tmp / "n5.ndlfd", "--n-points", "5")
    assert model.n_points == 5
    assert model.n_keypoints_.tolist() == [5] * len(demos)
    assert np.all(default.n_keypoints_ > 5)
    assert [k.tolist() for k in model.keypoints_] == _keypoints_by_simplify(
        model, demos, n_points=5
    )


def test_fit_groups_learns_only_those_columns(fit_setup):
    folder, _demos, default, tmp = fit_setup
    model = _fit(folder, tmp / "pos.ndlfd", "--groups", "position")
    assert model.groups_ == ("position",)
    assert model.columns_ == ("x", "y")
    assert model.column_groups_ == ("position", "position")
    assert model.codebook_.levels == (20, 20)
    assert model.model_.n_states == 20 * 20
    assert default.columns_ == ("x", "y", "vx", "vy")


def test_fit_weights_zero_velocity_reduces_on_position_only(fit_setup):
    folder, demos, default, tmp = fit_setup
    model = _fit(folder, tmp / "w.ndlfd", "--weights", "velocity=0")
    assert model.weights == {"velocity": 0.0}
    # velocity is still learned, but the key points are those of position alone
    assert model.columns_ == default.columns_
    position_only = _fit(folder, tmp / "pos-only.ndlfd", "--groups", "position")
    keys = [k.tolist() for k in model.keypoints_]
    assert keys == [k.tolist() for k in position_only.keypoints_]
    assert keys != [k.tolist() for k in default.keypoints_]
    assert keys == _keypoints_by_simplify(
        model, demos, epsilon=0.05, weights=[1, 1, 0, 0]
    )


def test_fit_normalization(fit_setup):
    folder, demos, default, tmp = fit_setup
    X = np.concatenate([d.X for d in demos])
    # group (default): x and y share the position range, vx and vy the velocity one
    lo = [X[:, :2].min()] * 2 + [X[:, 2:].min()] * 2
    hi = [X[:, :2].max()] * 2 + [X[:, 2:].max()] * 2
    np.testing.assert_array_equal(default.scaler_.data_min_, lo)
    np.testing.assert_array_equal(default.scaler_.data_max_, hi)
    model = _fit(folder, tmp / "pd.ndlfd", "--normalization", "per-dimension")
    assert model.normalization == "per-dimension"
    np.testing.assert_array_equal(model.scaler_.data_min_, X.min(axis=0))
    np.testing.assert_array_equal(model.scaler_.data_max_, X.max(axis=0))
    assert not np.array_equal(model.scaler_.data_min_, default.scaler_.data_min_)


def test_fit_pseudo_emission(fit_setup):
    folder, _demos, default, tmp = fit_setup
    model = _fit(folder, tmp / "r.ndlfd", "--pseudo-emission", "0.5")
    assert model.pseudo_emission == 0.5 and model.model_.pseudo_emission == 0.5
    B0 = default.model_.emission_matrix(dense=True)
    B = model.model_.emission_matrix(dense=True)
    assert (B0 == 0).any()
    assert B.min() > 0
    np.testing.assert_allclose(B.sum(axis=1), 1.0, rtol=1e-12)
    # the counts are the same; only the pseudo-count differs
    E0 = default.model_.emission_counts_.toarray()
    np.testing.assert_array_equal(model.model_.emission_counts_.toarray(), E0)
    rows = model.model_.states_
    nt = model.n_time_bins
    want = (E0 + 0.5) / (E0.sum(axis=1, keepdims=True) + nt * 0.5)
    np.testing.assert_allclose(B[rows], want, rtol=1e-14)


def test_fit_match_window_changes_the_generation_not_the_fit(fit_setup):
    folder, _demos, default, tmp = fit_setup
    assert default.match_window == KeypointHMM().match_window == 0.05
    model = _fit(folder, tmp / "mw.ndlfd", "--match-window", "0")
    assert model.match_window == 0.0
    assert model.fit_stats_ == default.fit_stats_
    t = np.linspace(0.0, 2.0, 40)
    ref = KeypointHMM(**{**default.get_params(), "match_window": 0.0})
    got = model.generate(t, dense=True).X
    np.testing.assert_array_equal(got, ref.fit(_demos).generate(t, dense=True).X)
    assert not np.array_equal(got, default.generate(t, dense=True).X)


def test_fit_start_changes_the_decoder_not_the_fit(fit_setup):
    folder, _demos, default, tmp = fit_setup
    model = _fit(folder, tmp / "s1.ndlfd", "--start", "state1")
    assert model.start == "state1" and default.start == "learned"
    _assert_same_fit(model, default)


def test_fit_generation_and_decoder_change_generation_not_the_fit(fit_setup):
    folder, _demos, default, tmp = fit_setup
    model = _fit(
        folder, tmp / "paper.ndlfd", "--generation", "paper", "--decoder", "map"
    )
    assert model.generation == "paper" and default.generation == "blend"
    assert model.decoder == "map" and default.decoder == "viterbi"
    _assert_same_fit(model, default)
    grid = np.linspace(0.0, 2.0, 50)
    paper = copy.deepcopy(default).set_params(generation="paper", decoder="map")
    np.testing.assert_array_equal(model.generate(grid).X, paper.generate(grid).X)


def test_fit_distance(fit_setup):
    folder, demos, default, tmp = fit_setup
    model = _fit(folder, tmp / "sed.ndlfd", "--distance", "sed")
    assert model.distance == "sed"
    keys = [k.tolist() for k in model.keypoints_]
    assert keys != [k.tolist() for k in default.keypoints_]
    want = [
        simplify(model.scaler_.transform(d), 0.05, distance="sed", times=d.t).tolist()
        for d in demos
    ]
    assert keys == want


def test_fit_integer_levels_apply_to_every_group(fit_setup):
    folder, _demos, default, tmp = fit_setup
    model = _fit(folder, tmp / "l4.ndlfd", "--levels", "4")
    assert model.levels == 4
    assert model.codebook_.levels == (4, 4, 4, 4)
    assert model.model_.n_states == 4**4
    assert default.codebook_.levels == (20, 20, 10, 10)
    # the key points do not depend on the codebook
    assert [k.tolist() for k in model.keypoints_] == [
        k.tolist() for k in default.keypoints_
    ]


# -- ndlfd simplify: --mask-column and --time-column ---------------------------------


def test_simplify_mask_column_names_the_mask(tmp_path):
    data = _walk_csv(tmp_path / "walk.csv")
    out = tmp_path / "o.csv"
    args = ["simplify", str(tmp_path / "walk.csv"), "--epsilon", "1.5", "--mask",
            "--normalization", "none"]  # fmt: skip
    assert main([*args, "--mask-column", "key", "-o", str(out), "-q"]) == 0
    cols, table = read_table(out)
    assert cols == ["t", "x", "y", "extra", "key"]
    mask = simplify(data[:, 1:], 1.5, return_mask=True)
    np.testing.assert_array_equal(table[:, 4], mask.astype(float))


def test_simplify_time_column_is_excluded_and_used_by_sed(tmp_path):
    rng = np.random.default_rng(4)
    n = 120
    time = np.cumsum(rng.uniform(0.5, 2.0, size=n))
    xy = np.cumsum(rng.normal(size=(n, 2)), axis=0)
    data = np.column_stack([xy[:, 0], time, xy[:, 1]])
    f = tmp_path / "walk.csv"
    write_table(f, ["x", "stamp", "y"], data)
    out = tmp_path / "o.csv"
    base = ["simplify", str(f), "-o", str(out), "-q", "--normalization", "none"]
    # --time-column: the column is not simplified, and sed uses it as time
    assert main([*base, "--n-points", "15", "--distance", "sed",
                 "--time-column", "stamp"]) == 0  # fmt: skip
    idx = simplify(xy, n_points=15, distance="sed", times=time)
    np.testing.assert_array_equal(read_table(out)[1], data[idx])
    assert not np.array_equal(idx, simplify(xy, n_points=15))
    assert main([*base, "--epsilon", "2", "--time-column", "stamp"]) == 0
    np.testing.assert_array_equal(read_table(out)[1], data[simplify(xy, 2.0)])
    # without it, "stamp" is a value column like the others
    assert main([*base, "--epsilon", "2"]) == 0
    np.testing.assert_array_equal(read_table(out)[1], data[simplify(data, 2.0)])
    assert not np.array_equal(simplify(data, 2.0), simplify(xy, 2.0))


# -- a time column that repeats or decreases is refused by every command ------------


@pytest.mark.parametrize(
    ("times", "line", "got"),
    [
        ([0.0, 0.1, 0.2, 0.15, 0.3], 5, "got 0.15 after 0.2 on line 4"),
        ([0.0, 0.1, 0.1, 0.2, 0.3], 4, "got 0.1 after 0.1 on line 3"),
    ],
)
def test_time_column_must_increase_in_every_command(tmp_path, times, line, got):
    demo = np.column_stack([times, np.arange(5.0), np.arange(5.0) ** 2])
    f = tmp_path / "d.csv"
    write_table(f, ["t", "x", "y"], demo)
    message = (
        f"error: {f}, line {line}: time column 't' must be strictly increasing; {got}"
    )
    out = tmp_path / "o.csv"
    runs = {
        "simplify": ["simplify", f, "--epsilon", "0.1", "-o", out],
        "simplify --time-column": [
            "simplify", f, "--epsilon", "0.1", "--time-column", "t", "-o", out
        ],
        "simplify sed": [
            "simplify", f, "--n-points", "3", "--distance", "sed", "-o", out
        ],
        "fit": ["fit", f, "-o", tmp_path / "m.ndlfd", "--groups", "position"],
    }  # fmt: skip
    for what, args in runs.items():
        r = run(*args)
        assert r.returncode == 2, what
        assert r.stderr.splitlines() == [f"ndlfd {args[0]}: {message}"], what
        assert not out.exists() and not (tmp_path / "m.ndlfd").exists()


# -- issue 11: your own data, as it really comes -------------------------------------
# In-process (ndlfd.cli.main) to stay fast; stderr is read through capsys.


def cli(capsys, *args):
    """Run ``ndlfd ARGS`` in-process: (exit status, stderr lines)."""
    capsys.readouterr()
    rc = main([str(a) for a in args])
    return rc, capsys.readouterr().err.splitlines()


def _reach_demos(n_demos=3, seed=0):
    """3-D reaches with orientation at 50/100/125 Hz, irregular time stamps."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n_demos):
        n = (50, 100, 125)[i % 3]
        t = np.cumsum(rng.uniform(0.97, 1.03, n)) / n
        s = np.linspace(0.0, 1.0, n)
        pos = np.column_stack([s, np.sin(np.pi * s) * 0.3, 0.2 * s**2])
        pos += rng.normal(0.0, 1e-3, pos.shape)
        half = 0.4 * s + 0.05 * i  # about z: exact unit quaternions
        q = np.column_stack([np.cos(half), 0 * s, 0 * s, np.sin(half)])
        out.append((t, pos, q))
    return out


def _write_reach(folder, sep=",", names=("t", "x", "y", "z", "qw", "qx", "qy", "qz"),
                 suffix=".csv", demos=None):  # fmt: skip
    folder.mkdir(parents=True, exist_ok=True)
    for i, (t, pos, q) in enumerate(demos or _reach_demos()):
        rows = np.column_stack([t, pos, q]).tolist()
        text = [sep.join(names)] + [sep.join(map(repr, r)) for r in rows]
        (folder / f"reach{i}{suffix}").write_text("\n".join(text) + "\n")
    return folder


def test_fit_names_the_groups_learned_and_not_learned(tmp_path, capsys):
    folder = _write_reach(tmp_path / "reach")
    # by default every known group the files have is learned: orientation too
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd")
    assert rc == 0, err
    fitted = next(e for e in err if e.startswith("fitted"))
    assert (
        " on position, velocity, orientation (velocity derived from position):"
        in fitted
    )
    assert not any(e.startswith("not learned") for e in err)
    model = KeypointHMM.load(tmp_path / "m.ndlfd")
    assert model.groups_ == ("position", "velocity", "orientation")
    assert model.columns_[-4:] == ("qw", "qx", "qy", "qz")
    # asked for fewer groups, the others are named with the flag to learn them
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd",
                  "--groups", "position,velocity")  # fmt: skip
    assert rc == 0, err
    assert err[-1] == (
        "not learned: orientation (in the files but not in --groups; learn it with"
        " --groups position,velocity,orientation)"
    )
    assert KeypointHMM.load(tmp_path / "m.ndlfd").groups_ == ("position", "velocity")
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd", "-q")
    assert rc == 0 and err == []
    # a group of the user's own is not learned by default, and fewer samples
    # than the default time bins
    short = _write_reach(tmp_path / "short", demos=[
        (t[:30], np.column_stack([p[:30], p[:30, :1]]), q[:30])
        for t, p, q in _reach_demos()
    ], names=("t", "x", "y", "z", "grip.w", "qw", "qx", "qy", "qz"))  # fmt: skip
    rc, err = cli(capsys, "fit", short, "-o", tmp_path / "m.ndlfd")
    assert rc == 0, err
    assert "50 time bins" not in err[1]
    assert "30 time bins (the default 50 lowered to the longest demonstration's 30" \
           " samples)" in err[1]  # fmt: skip
    assert KeypointHMM.load(tmp_path / "m.ndlfd").n_time_bins == 30
    assert err[2] == (
        "not learned: grip (in the files but not in --groups; learn it with"
        " --groups position,velocity,orientation,grip)"
    )


@pytest.mark.parametrize("sep", [",", ";", "\t", " "])
def test_column_mapping_on_the_command_line(tmp_path, capsys, sep):
    names = ("TIME", "Pos_X", "Pos_Y", "pos_z", "qw", "qx", "qy", "qz")
    folder = _write_reach(tmp_path / "d", sep=sep, names=names)
    reference = _write_reach(tmp_path / "ref")  # the same data, conventional names
    m = ["--time-column", "time", "--group", "position=pos_x,POS_Y,Pos_Z"]
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd", *m)
    assert rc == 0, err
    layout = {",": "", ";": " (semicolon-separated)", "\t": " (tab-separated)",
              " ": " (whitespace-separated)"}[sep]  # fmt: skip
    assert err[0] == (
        "read 3 demonstration(s) from 3 file(s): time=TIME;"
        f" position=Pos_X,Pos_Y,pos_z; orientation=qw,qx,qy,qz{layout}"
    )
    rc, _ = cli(capsys, "fit", reference, "-o", tmp_path / "ref.ndlfd")
    assert rc == 0
    _assert_same_fit(KeypointHMM.load(tmp_path / "m.ndlfd"),
                     KeypointHMM.load(tmp_path / "ref.ndlfd"))  # fmt: skip
    # the other commands that read demonstrations take the same flags
    one = folder / "reach0.csv"
    rc, err = cli(capsys, "generate", tmp_path / "m.ndlfd", "--like", one, *m,
                  "-o", tmp_path / "g.csv")  # fmt: skip
    assert rc == 0, err
    assert err[0].startswith("read 1 demonstration(s) from 1 file(s): time=TIME;")
    rc, err = cli(capsys, "simplify", one, "--epsilon", "0.01", *m,
                  "-o", tmp_path / "k.csv")  # fmt: skip
    assert rc == 0, err
    assert err[0] == (
        f"read {one}: time=TIME; position=Pos_X,Pos_Y,pos_z; orientation=qw,qx,qy,qz"
        f"{layout}; normalization group"
    )
    if sep == ",":  # errors name the flags, never the Python parameters
        for args, message in [
            (["--time-column", "when"], "--time-column names 'when', but there is no"
             " such column; got columns ['TIME', 'Pos_X',"),
            (["--time-column", "TIME"], "cannot tell the group of column(s)"
             " ['Pos_X', 'Pos_Y', 'pos_z'] from their names"),
            (["--time-column", "TIME"], "map them with --group GROUP=NAME[,NAME...],"
             " or leave them out with --drop NAME[,NAME...]"),
            ([*m[:2], "--group", "position=pos_x,"], "--group position must be a"
             " comma-separated list of names without empty entries"),
            ([*m[:2], "--group", "position=px,py"], "--group position names 'px',"
             " but there is no such column"),
            ([*m[:2], "--group", "position=pos_x,pos_y"],
             "cannot tell the group of column(s) ['pos_z']"),
        ]:  # fmt: skip
            rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "x.ndlfd", *args)
            assert rc == 2 and len(err) == 1, err
            assert message in err[0]
            assert "time_column=" not in err[0] and "groups={" not in err[0]
        assert not (tmp_path / "x.ndlfd").exists()
        stamp = tmp_path / "stamp.csv"
        stamp.write_text("stamp,x,y\n0,0,0\n1,1,1\n")
        rc, err = cli(capsys, "fit", stamp, "-o", tmp_path / "x.ndlfd")
        assert rc == 2 and err == [
            f"ndlfd fit: error: {stamp}: expected a time column named 't' or 'time'"
            " (any case); got columns ['stamp', 'x', 'y']; name it with --time-column"
            " NAME"
        ]


def test_plain_npz_and_hdf5_fit_the_same_model_as_csv(tmp_path, capsys):
    h5py = pytest.importorskip("h5py")
    demos = _reach_demos()
    csv = _write_reach(tmp_path / "csv", suffix=".CSV", demos=demos)
    (tmp_path / "npz").mkdir()
    with h5py.File(tmp_path / "reach.h5", "w") as f:
        for i, (t, pos, q) in enumerate(demos):
            np.savez(tmp_path / "npz" / f"reach{i}.npz", t=t, pos=pos, quat=q)
            g = f.create_group(f"episode{i}")
            g["time"], g["P"], g["quat"] = t, pos, q
    groups = ["--groups", "position,velocity,orientation", "--levels", "8"]
    rc, err = cli(capsys, "fit", csv, "-o", tmp_path / "csv.ndlfd", *groups)
    assert rc == 0, err
    assert err[0].startswith("read 3 demonstration(s) from 3 file(s):")
    rc, err = cli(capsys, "fit", tmp_path / "npz", "-o", tmp_path / "npz.ndlfd",
                  *groups)  # fmt: skip
    assert rc == 0, err
    assert err[0] == (
        "read 3 demonstration(s) from 3 file(s): time=t; position=pos; orientation=quat"
    )
    rc, err = cli(capsys, "fit", tmp_path / "reach.h5", "-o", tmp_path / "h5.ndlfd",
                  "--group", "position=p", *groups)  # fmt: skip
    assert rc == 0, err
    assert err[0] == (
        "read 3 demonstration(s) from 1 file(s): time=time; position=P;"
        " orientation=quat"
    )
    ref = KeypointHMM.load(tmp_path / "csv.ndlfd")
    for name in ("npz", "h5"):
        _assert_same_fit(KeypointHMM.load(tmp_path / f"{name}.ndlfd"), ref)


def test_hdf5_without_h5py_says_how_to_install_it(tmp_path, capsys, monkeypatch):
    (tmp_path / "d.h5").write_bytes(b"\x89HDF\r\n\x1a\n")
    monkeypatch.setitem(sys.modules, "h5py", None)  # import h5py now fails
    rc, err = cli(capsys, "fit", tmp_path / "d.h5", "-o", tmp_path / "m.ndlfd")
    assert rc == 2
    assert err == [
        "ndlfd fit: error: reading HDF5 files needs h5py; install it with:"
        ' pip install "ndlfd[hdf5]"'
    ]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--time-bins", "100000000"], "--time-bins must be between 2 and 125 (the"
         " number of samples of the longest demonstration, {d}/reach2.csv); got"
         " 100000000"),
        (["--time-bins", "1"], "--time-bins must be an integer >= 2; got 1"),
        (["--levels", "1"], "--levels must be an integer >= 2; got 1"),
        (["--levels", "position=20,velocity=1"],
         "--levels velocity must be an integer >= 2; got 1"),
        (["--levels", "position=20,"], "--levels must look like position=20,"
         "velocity=10 (or one number for every group); got 'position=20,' (an empty"
         " entry: a trailing or doubled comma)"),
        (["--levels", "force=10"], "--levels names force, which is not learned; the"
         " learned groups are position, velocity, orientation (--groups)"),
        (["--groups", "position,grip", "--levels", "position=20"],
         "--levels must give the codebook levels of group 'grip', which has no"
         " default (e.g. --levels grip=10)"),
        (["--n-points", "500"], "--n-points must be between 2 and 50 (the number of"
         " samples of the shortest demonstration, {d}/reach0.csv); got 500"),
        (["--n-points", "1"], "--n-points must be an integer >= 2; got 1"),
        (["--epsilon", "-0.1"], "--epsilon must be a finite number >= 0; got -0.1"),
        (["--epsilon", "nan"], "--epsilon must be a finite number >= 0; got nan"),
        (["--weights", "velocity=0.5,"], "--weights must look like velocity=0.5"),
        (["--weights", "velocity=-1"], "--weights velocity must be a finite number"
         " >= 0; got -1.0"),
        (["--groups", "position,"], "--groups must be a comma-separated list of"
         " names without empty entries; got 'position,'"),
        (["--groups", "position,orientation,force"], "--groups asks for force, but"
         " {d}/reach0.csv has only position, orientation"),
        (["--pseudo-emission", "-1"], "--pseudo-emission must be a finite number"
         " >= 0; got -1.0"),
        (["--match-window", "0.7"], "--match-window must be between 0 and 0.5;"
         " got 0.7"),
    ],
)  # fmt: skip
def test_fit_settings_out_of_range_are_one_line_errors(tmp_path, capsys, args,
                                                        message):  # fmt: skip
    folder = _write_reach(tmp_path / "d")
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd", "-q", *args)
    assert rc == 2 and len(err) == 1, err
    assert err[0].startswith(f"ndlfd fit: error: {message.format(d=folder)}")
    assert not (tmp_path / "m.ndlfd").exists()


def test_other_settings_out_of_range_and_documented_ranges(tmp_path, capsys):
    folder = _write_reach(tmp_path / "d")
    f = folder / "reach0.csv"
    o = tmp_path / "o.csv"
    assert main(["fit", str(folder), "-o", str(tmp_path / "m.ndlfd"), "-q"]) == 0
    for args, message in [
        (["simplify", f, "--n-points", "51", "-o", o], "simplify: error: --n-points"
         " must be between 2 and 50 (the file's number of samples); got 51"),
        (["simplify", f, "--epsilon", "-1", "-o", o],
         "simplify: error: --epsilon must be a finite number >= 0; got -1.0"),
        (["simplify", f, "--epsilon", "1", "--columns", "x,", "-o", o],
         "simplify: error: --columns must be a comma-separated list of names"),
        (["simplify", f, "--epsilon", "1", "--weights", "1,2", "-o", o],
         "simplify: error: --weights must give one weight per simplified column (7:"
         " x, y, z, qw, qx, qy, qz); got 2"),
        (["generate", tmp_path / "m.ndlfd", "--duration", "1", "--samples",
          "100000000", "-o", o], "generate: error: --samples must be between 2 and"
         " 10000000; got 100000000"),
        (["generate", tmp_path / "m.ndlfd", "--duration", "inf", "-o", o],
         "generate: error: --duration must be a finite number > 0; got inf"),
        (["generate", tmp_path / "m.ndlfd", "--duration", "1", "--start", "1,2",
          "-o", o], "generate: error: --start must give 3 position values (one per"
         " column: x, y, z); got 2"),
        (["plot", folder, "--n-points", "99", "-o", tmp_path / "p.png"],
         "plot: error: --n-points must be between 2 and 50"),
    ]:  # fmt: skip
        rc, err = cli(capsys, *args, "-q")
        assert rc == 2 and len(err) == 1, err
        assert err[0].startswith(f"ndlfd {message}"), err
        assert not o.exists()
    helps = {"fit": ["2 <= N <= the longest demonstration's number of samples",
                     "codebook levels >= 2", "2 <= N <= the shortest"],
             "simplify": ["2 <= N <= the file's number of samples", ">= 0"],
             "generate": ["2 <= N <= 10,000,000"],
             "plot": ["2 <= N <= the shortest"]}  # fmt: skip
    for command, phrases in helps.items():
        text = " ".join(build_parser_help(command).split())
        for phrase in phrases:
            assert phrase in text, (command, phrase)


def build_parser_help(command):
    from ndlfd.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    return sub.choices[command].format_help()


def test_output_paths_numbers_and_mask(tmp_path, capsys):
    folder = _write_reach(tmp_path / "d")
    f = folder / "reach0.csv"
    assert main(["fit", str(folder), "-o", str(tmp_path / "m.ndlfd"), "-q"]) == 0
    model = tmp_path / "m.ndlfd"
    runs = {
        "simplify": ["simplify", f, "--epsilon", "0.1"],
        "fit": ["fit", folder],
        "generate": ["generate", model, "--duration", "1"],
        "plot": ["plot", folder],
    }
    for command, args in runs.items():
        # a missing folder: one line naming it; nothing is created
        target = tmp_path / "missing" / "out.png"
        rc, err = cli(capsys, *args, "-o", target)
        assert rc == 2
        assert err == [
            f"ndlfd {command}: error: -o {target}: the folder {target.parent} does"
            " not exist; create it first"
        ]
        assert not target.parent.exists()
        # a folder: one line naming it, no errno and no temporary file
        rc, err = cli(capsys, *args, "-o", folder)
        assert rc == 2 and len(err) == 1, err
        assert err[0].startswith(f"ndlfd {command}: error: -o {folder}: is a folder;")
        assert "Errno" not in err[0] and ".tmp" not in err[0]
    rc, err = cli(capsys, "generate", model, "--duration", "1", "--std",
                  tmp_path / "no" / "s.csv", "-o", tmp_path / "g.csv")  # fmt: skip
    assert rc == 2
    assert err[0].endswith(
        f"the folder {tmp_path / 'no'} does not exist; create it first"
    )
    assert sorted(p.name for p in folder.iterdir()) == [
        "reach0.csv", "reach1.csv", "reach2.csv"
    ]  # fmt: skip
    # computed numbers: ten significant digits at most
    rc, _ = cli(capsys, "generate", model, "--duration", "0.7", "--samples", "33",
                "--dense", "-o", tmp_path / "g.csv")  # fmt: skip
    assert rc == 0
    lines = (tmp_path / "g.csv").read_text().splitlines()
    numbers = [v for line in lines[1:] for v in line.split(",")]
    digits = [
        len(v.lstrip("-").split("e")[0].replace(".", "").lstrip("0")) for v in numbers
    ]
    assert max(digits) <= 10 and max(digits) >= 9
    assert lines[1].startswith("0,") and lines[-1].startswith("0.7,")
    # --mask: 0/1 integers; the rows themselves unchanged
    rc, _ = cli(capsys, "simplify", f, "--epsilon", "0.05", "--mask",
                "-o", tmp_path / "k.csv")  # fmt: skip
    assert rc == 0
    given = f.read_text().splitlines()
    written = (tmp_path / "k.csv").read_text().splitlines()
    assert written[0] == given[0] + ",keep"
    assert {w.rsplit(",", 1)[1] for w in written[1:]} == {"0", "1"}
    assert [w.rsplit(",", 1)[0] for w in written[1:]] == given[1:]


def test_generate_refuses_a_wrong_model_file(tmp_path, capsys):
    import pickle

    marker = tmp_path / "pwned"

    class Evil:
        def __reduce__(self):
            return (Path.touch, (marker,))

    bad = {
        "model.csv": (b"t,x,y\n0,1,2\n", "a text file starting 't,x,y' (a CSV file?)"),
        "model.json": (b'{"levels": 20}', "a JSON text file"),
        "model.pkl": (pickle.dumps(Evil()), "a Python pickle, which ndlfd never loads"),
        "model.ndlfd": (b"", "an empty file"),
    }
    for name, (content, _) in bad.items():
        (tmp_path / name).write_bytes(content)
    np.savez(tmp_path / "plain.npz", t=np.arange(3.0))
    np.savez(tmp_path / "objects.npz", a=np.array([Evil()], dtype=object))
    bad["plain.npz"] = (None, "an .npz archive without ndlfd metadata")
    bad["objects.npz"] = (None, "pickled Python objects, which ndlfd never loads")
    for name, (_, what) in bad.items():
        rc, err = cli(capsys, "generate", tmp_path / name, "--duration", "1",
                      "-o", tmp_path / "g.csv")  # fmt: skip
        assert rc == 2 and len(err) == 1, err
        assert err[0].startswith(
            f"ndlfd generate: error: {tmp_path / name}: not an ndlfd model file"
        ), err
        assert what in err[0]
        assert "allow_pickle" not in err[0] and "pickle.load" not in err[0]
        assert "unsafe" not in err[0]
    assert not marker.exists()
    assert not (tmp_path / "g.csv").exists()


def test_plot_draws_demos_keypoints_path_and_band(tmp_path, capsys, monkeypatch):
    pytest.importorskip("matplotlib")
    import ndlfd.plot

    figures = []
    save = ndlfd.plot.save_figure

    def keep(fig, path, **kw):
        figures.append(fig)
        return save(fig, path, **kw)

    monkeypatch.setattr(ndlfd.plot, "save_figure", keep)
    folder = _square_demos(tmp_path / "demos", n_demos=4)
    model, gen, std = tmp_path / "m.ndlfd", tmp_path / "g.csv", tmp_path / "s.csv"
    assert main(["fit", str(folder), "-o", str(model), "-q"]) == 0
    assert main(["generate", str(model), "--duration", "2", "--samples", "60",
                 "--dense", "--std", str(std), "-o", str(gen), "-q"]) == 0  # fmt: skip
    rc, err = cli(capsys, "plot", folder, "--path", gen, "--std", std,
                  "--title", "square", "-o", tmp_path / "p.png")  # fmt: skip
    assert rc == 0, err
    assert (tmp_path / "p.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    fitted = KeypointHMM.load(model)
    counts = [len(k) for k in fitted.keypoints_]
    assert err[-1] == (
        f"drew 4 demonstration(s) in 2-D (position) with their key points"
        f" ({min(counts)}-{max(counts)} at --epsilon 0.05), the generated path and"
        f" its ±1 sd band -> {tmp_path / 'p.png'}"
    )
    (ax,) = figures[-1].axes
    assert ax.get_title() == "square" and ax.name != "3d"
    # per demonstration: line, key points (those fit finds), start, goal
    demos = [read_csv(p) for p in sorted(folder.glob("*.csv"))]
    for i, (d, k) in enumerate(zip(demos, fitted.keypoints_, strict=True)):
        np.testing.assert_array_equal(ax.lines[4 * i].get_xydata(), d.get("position"))
        np.testing.assert_array_equal(
            ax.lines[4 * i + 1].get_xydata(), d.get("position")[k]
        )
    path = read_csv(gen).get("position")
    generated = [ln for ln in ax.lines if ln.get_label() == "generated"]
    np.testing.assert_array_equal(generated[0].get_xydata(), path)
    (band,) = ax.patches
    assert band.get_label() == "generated ±1 sd"
    s = read_table(std)[1][:, 1:3]
    assert band.get_path().contains_point(path[30] + 0.9 * s[30] * [1, 0])
    # 3-D positions: 3-D axes, no band; --n-points sets the key points
    folder3 = _write_reach(tmp_path / "reach")
    rc, err = cli(capsys, "plot", folder3, "--n-points", "6", "-o", tmp_path / "r.svg")
    assert rc == 0, err
    assert figures[-1].axes[0].name == "3d"
    assert err[-1].startswith("drew 3 demonstration(s) in 3-D (position) with their"
                              " key points (6-6 at --n-points 6) -> ")  # fmt: skip
    assert (tmp_path / "r.svg").read_text().lstrip().startswith("<?xml")
    for args, message in [
        (["--std", std], "--std draws the band of --path FILE.csv; pass --path"),
        (["-o", tmp_path / "p.xyz"], f"-o {tmp_path / 'p.xyz'}: expected a figure"
         " file ending in"),
        (["--path", gen, "--std", folder / "demo00.csv"], "--std"),
    ]:  # fmt: skip
        out = [] if "-o" in args else ["-o", tmp_path / "q.png"]
        rc, err = cli(capsys, "plot", folder, "-q", *args, *out)
        assert rc == 2 and len(err) == 1, err
        assert err[0].startswith(f"ndlfd plot: error: {message}")


def test_simplify_normalizes_groups_like_fit(tmp_path, capsys):
    from ndlfd import GroupScaler

    # a reach in millimetres: position noise of 0.05 mm is above an epsilon of
    # 0.01 in raw units, and nothing next to a 500 mm range
    rng = np.random.default_rng(3)
    (t, pos, q), = _reach_demos(1)  # fmt: skip
    pos = pos * 500 + rng.normal(0, 0.05, pos.shape)
    f = tmp_path / "reach.csv"
    write_csv(ndlfd_demo(t, pos, q), f)
    kept = {}
    for mode in ("group", "per-dimension", "none"):
        rc, err = cli(capsys, "simplify", f, "--epsilon", "0.01", "--normalization",
                      mode, "-o", tmp_path / f"{mode}.csv")  # fmt: skip
        assert rc == 0, err
        assert err[0].endswith(f"; normalization {mode}")
        demo = read_csv(f)
        U = GroupScaler(mode=mode).fit(demo).transform(demo)
        idx = simplify(U, 0.01)
        np.testing.assert_array_equal(read_table(tmp_path / f"{mode}.csv")[1],
                                      read_table(f)[1][idx])  # fmt: skip
        kept[mode] = idx.size
    assert kept["none"] > 0.5 * t.size > 3 * kept["group"]
    # the default is fit's: group
    rc, _ = cli(capsys, "simplify", f, "--epsilon", "0.01", "-o", tmp_path / "d.csv")
    assert rc == 0
    assert (tmp_path / "d.csv").read_text() == (tmp_path / "group.csv").read_text()
    text = " ".join(build_parser_help("simplify").split())
    assert "(default: group, one range per group" in text
    assert "as in 'ndlfd fit'" in text


def ndlfd_demo(t, pos, q):
    return Demonstration.from_arrays(t, position=pos, orientation=q)


def test_fit_on_a_dask_scheduler_gives_the_local_model(tmp_path, capsys):
    distributed = pytest.importorskip("distributed")
    folder = _write_reach(tmp_path / "reach")
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "local.ndlfd", "-q",
                  "--n-jobs", "2")  # fmt: skip
    assert rc == 0, err
    with distributed.LocalCluster(
        n_workers=2, processes=False, dashboard_address=None
    ) as cluster:
        rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "dask.ndlfd", "-q",
                      "--scheduler", cluster.scheduler_address)  # fmt: skip
    assert rc == 0, err
    local = KeypointHMM.load(tmp_path / "local.ndlfd")
    remote = KeypointHMM.load(tmp_path / "dask.ndlfd")
    assert local.fit_stats_ == remote.fit_stats_
    grid = np.linspace(0.0, 2.0, 40)
    np.testing.assert_array_equal(
        local.generate(grid, dense=True).X, remote.generate(grid, dense=True).X
    )
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd", "--n-jobs", "0")
    assert rc == 2 and err == [
        "ndlfd fit: error: --n-jobs must be an integer >= 1; got 0"
    ]


@pytest.mark.parametrize("n_jobs", ["1", "2"])
def test_fit_streams_the_files_once_per_pass_and_names_a_bad_one(
    tmp_path, capsys, monkeypatch, n_jobs
):
    import ndlfd.io
    import ndlfd.io._files

    folder = _write_reach(tmp_path / "d", demos=_reach_demos(7))
    reads: list[str] = []
    real = ndlfd.io.read_file

    def counting(p, *args, **kw):
        reads.append(Path(p).name)
        return real(p, *args, **kw)

    # every place that reads a file: the command and the DemoFile items
    monkeypatch.setattr(ndlfd.io, "read_file", counting)
    monkeypatch.setattr(ndlfd.io._files, "read_file", counting)
    args = ("fit", folder, "-o", tmp_path / "m.ndlfd", "--n-jobs", "1")
    rc, err = cli(capsys, *args)
    assert rc == 0, err
    # the first file here (groups, checks) and by fit (columns), then every
    # file once per pass
    names = sorted(p.name for p in folder.iterdir())
    assert reads == [names[0], names[0], *names, *names]
    assert err[0].startswith("read 7 demonstration(s) from 7 file(s): time=t;")
    # the same model as from the demonstrations in memory
    model = KeypointHMM.load(tmp_path / "m.ndlfd")
    demos = ndlfd.io.read_demos(folder)
    ref = KeypointHMM(n_time_bins=model.n_time_bins, n_jobs=1).fit(demos)
    assert model.fit_stats_ == ref.fit_stats_
    # a corrupt file in the middle: one line naming it, on any number of workers
    (folder / "reach3.csv").write_text("t,x,y,z,qw,qx,qy,qz\n0,1,2,3,1,0,0,0\n1,x\n")
    args = ("fit", folder, "-o", tmp_path / "bad.ndlfd", "--n-jobs", n_jobs)
    rc, err = cli(capsys, *args)
    assert rc != 0 and not (tmp_path / "bad.ndlfd").exists()
    assert len(err) == 1 and "reach3.csv" in err[0] and "demos[" not in err[0]
    # a file past the first without a learned group: the flag that maps it
    write_csv(Demonstration.from_arrays([0.0, 1.0, 2.0], force=np.ones((3, 2))),
              folder / "reach3.csv")  # fmt: skip
    rc, err = cli(capsys, *args)
    assert rc != 0 and len(err) == 1
    assert "reach3.csv: a demonstration lacks group(s) position, velocity" in err[0]
    assert "map its columns with --group position=NAME" in err[0]
