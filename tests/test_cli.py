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
    for cmd in ("simplify", "fit", "generate", "demo", "reproduce"):
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
    mask = simplify(data[:, 1:], 1.5, return_mask=True)
    np.testing.assert_array_equal(out[:, :4], data)
    np.testing.assert_array_equal(out[:, 4], mask.astype(float))


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
        ("t,x,y\n0,1,2\n1,2,3\n", ["--columns", "x,z"], "column(s) z not found"),
        ("t,x,y\n0,1,2\n1,abc,3\n", [], "line 3"),
        ("t,x,y\n0,1,2\n1,nan,3\n", [], "line 3"),
        (
            "t,x\n0,1\n1,2\n",
            ["--distance", "sed", "--time-column", "time"],
            "time column 'time' not found",
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
    np.testing.assert_allclose(gen.X, expected.X, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(gen.t, expected.t)
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
    np.testing.assert_allclose(pinned.X, expected.X, rtol=1e-9, atol=1e-12)
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
    args = ["simplify", str(tmp_path / "walk.csv"), "--epsilon", "1.5", "--mask"]
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
    base = ["simplify", str(f), "-o", str(out), "-q"]
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
