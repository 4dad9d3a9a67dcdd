"""ndlfd fit: every option honoured, the files read as a stream.

In-process (ndlfd.cli.main, the console script's function) to keep this fast.
"""

import copy
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import (
    assert_same_fit,
    cli,
    fit_model,
    own_name_demos,
    reach_demos,
    square_demos,
    write_obstacle,
    write_reach,
)

from ndlfd.cli import main
from ndlfd.demonstration import Demonstration
from ndlfd.dp import simplify
from ndlfd.io import read_csv, read_table, write_csv, write_table
from ndlfd.learner import KeypointHMM


@pytest.fixture(scope="module")
def fit_setup(tmp_path_factory):
    """The demonstration folder, its demos read back, and the default fit."""
    tmp = tmp_path_factory.mktemp("fit")
    folder = square_demos(tmp / "demos")
    demos = [read_csv(p) for p in sorted(folder.glob("*.csv"))]
    default = fit_model(folder, tmp / "default.ndlfd")
    return folder, demos, default, tmp


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
    assert_same_fit(default, KeypointHMM().fit(demos))


def test_fit_n_points(fit_setup):
    folder, demos, default, tmp = fit_setup
    model = fit_model(folder, tmp / "n5.ndlfd", "--n-points", "5")
    assert model.n_points == 5
    assert model.n_keypoints_.tolist() == [5] * len(demos)
    assert np.all(default.n_keypoints_ > 5)
    assert [k.tolist() for k in model.keypoints_] == _keypoints_by_simplify(
        model, demos, n_points=5
    )


def test_fit_groups_learns_only_those_columns(fit_setup):
    folder, _demos, default, tmp = fit_setup
    model = fit_model(folder, tmp / "pos.ndlfd", "--groups", "position")
    assert model.groups_ == ("position",)
    assert model.columns_ == ("x", "y")
    assert model.column_groups_ == ("position", "position")
    assert model.codebook_.levels == (20, 20)
    assert model.model_.n_states == 20 * 20
    assert default.columns_ == ("x", "y", "vx", "vy")


def test_fit_weights_zero_velocity_reduces_on_position_only(fit_setup):
    folder, demos, default, tmp = fit_setup
    model = fit_model(folder, tmp / "w.ndlfd", "--weights", "velocity=0")
    assert model.weights == {"velocity": 0.0}
    # velocity is still learned, but the key points are those of position alone
    assert model.columns_ == default.columns_
    position_only = fit_model(folder, tmp / "pos-only.ndlfd", "--groups", "position")
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
    model = fit_model(folder, tmp / "pd.ndlfd", "--normalization", "per-dimension")
    assert model.normalization == "per-dimension"
    np.testing.assert_array_equal(model.scaler_.data_min_, X.min(axis=0))
    np.testing.assert_array_equal(model.scaler_.data_max_, X.max(axis=0))
    assert not np.array_equal(model.scaler_.data_min_, default.scaler_.data_min_)


def test_fit_pseudo_emission(fit_setup):
    folder, _demos, default, tmp = fit_setup
    model = fit_model(folder, tmp / "r.ndlfd", "--pseudo-emission", "0.5")
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
    model = fit_model(folder, tmp / "mw.ndlfd", "--match-window", "0")
    assert model.match_window == 0.0
    assert model.fit_stats_ == default.fit_stats_
    t = np.linspace(0.0, 2.0, 40)
    ref = KeypointHMM(**{**default.get_params(), "match_window": 0.0})
    got = model.generate(t, dense=True).X
    np.testing.assert_array_equal(got, ref.fit(_demos).generate(t, dense=True).X)
    assert not np.array_equal(got, default.generate(t, dense=True).X)


def test_fit_start_changes_the_decoder_not_the_fit(fit_setup):
    folder, _demos, default, tmp = fit_setup
    model = fit_model(folder, tmp / "s1.ndlfd", "--start", "state1")
    assert model.start == "state1" and default.start == "learned"
    assert_same_fit(model, default)


def test_fit_generation_and_decoder_change_generation_not_the_fit(fit_setup):
    folder, _demos, default, tmp = fit_setup
    model = fit_model(
        folder, tmp / "paper.ndlfd", "--generation", "paper", "--decoder", "map"
    )
    assert model.generation == "paper" and default.generation == "blend"
    assert model.decoder == "map" and default.decoder == "viterbi"
    assert_same_fit(model, default)
    grid = np.linspace(0.0, 2.0, 50)
    paper = copy.deepcopy(default).set_params(generation="paper", decoder="map")
    np.testing.assert_array_equal(model.generate(grid).X, paper.generate(grid).X)


def test_fit_random_state_is_the_library_parameter(fit_setup):
    folder, demos, default, tmp = fit_setup
    model = fit_model(folder, tmp / "seeded.ndlfd", "--random-state", "5")
    assert model.get_params() == {**default.get_params(), "random_state": 5}
    assert_same_fit(model, KeypointHMM(random_state=5).fit(demos))
    # without it, a fixed choice: two runs give the same model
    again = fit_model(folder, tmp / "again.ndlfd")
    assert_same_fit(again, default)


def test_fit_distance(fit_setup):
    folder, demos, default, tmp = fit_setup
    model = fit_model(folder, tmp / "sed.ndlfd", "--distance", "sed")
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
    model = fit_model(folder, tmp / "l4.ndlfd", "--levels", "4")
    assert model.levels == 4
    assert model.codebook_.levels == (4, 4, 4, 4)
    assert model.model_.n_states == 4**4
    assert default.codebook_.levels == (20, 20, 10, 10)
    # the key points do not depend on the codebook
    assert [k.tolist() for k in model.keypoints_] == [
        k.tolist() for k in default.keypoints_
    ]


def test_fit_names_the_groups_learned_and_not_learned(tmp_path, capsys):
    folder = write_reach(tmp_path / "reach")
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
    # a group of the user's own is learned by default (10 levels, no --levels
    # needed), and fewer samples than the default time bins
    short = write_reach(tmp_path / "short", demos=[
        (t[:30], np.column_stack([p[:30], p[:30, :1]]), q[:30])
        for t, p, q in reach_demos()
    ], names=("t", "x", "y", "z", "grip.w", "qw", "qx", "qy", "qz"))  # fmt: skip
    rc, err = cli(capsys, "fit", short, "-o", tmp_path / "m.ndlfd")
    assert rc == 0, err
    assert "50 time bins" not in err[1]
    assert "30 time bins (the default 50 lowered to the longest demonstration's 30" \
           " samples)" in err[1]  # fmt: skip
    assert KeypointHMM.load(tmp_path / "m.ndlfd").n_time_bins == 30
    # cut at 30 samples, the first (50 Hz) goes three fifths of the way, the
    # others a quarter: two routes, one against two
    assert err[2].startswith(
        "routes: 2 found on position (route 0: 1, route 1: 2 demonstrations)"
    )
    assert err[3].startswith("demonstrations' peaks (of ")  # test_cli_fit_peaks
    assert len(err) == 4 and not any(e.startswith("not learned") for e in err)
    model = KeypointHMM.load(tmp_path / "m.ndlfd")
    assert model.groups_ == ("position", "velocity", "orientation", "grip")
    assert model.codebook_.levels[-1] == 10  # OTHER_LEVELS


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
        (["--random-state", "-1"], "--random-state must be an integer >= 0; got -1"),
    ],
)  # fmt: skip
def test_fit_settings_out_of_range_are_one_line_errors(tmp_path, capsys, args,
                                                        message):  # fmt: skip
    folder = write_reach(tmp_path / "d")
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd", "-q", *args)
    assert rc == 2 and len(err) == 1, err
    assert err[0].startswith(f"ndlfd fit: error: {message.format(d=folder)}")
    assert not (tmp_path / "m.ndlfd").exists()


def test_fit_on_a_dask_scheduler_gives_the_local_model(tmp_path, capsys):
    distributed = pytest.importorskip("distributed")
    folder = write_reach(tmp_path / "reach")
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "local.ndlfd", "-q",
                  "--n-jobs", "2")  # fmt: skip
    assert rc == 0, err
    with distributed.LocalCluster(
        n_workers=2, processes=False, dashboard_address=":0"
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

    folder = write_reach(tmp_path / "d", demos=reach_demos(7))
    reads: list[str] = []
    real = ndlfd.io.read_file

    def counting(p, *args, **kw):
        reads.append(Path(p).name)
        return real(p, *args, **kw)

    # every place that reads a file: the command and the DemoFile items (both
    # through ndlfd.io.read_or_skip)
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


def test_fit_records_the_input_names_for_generate_and_sample(tmp_path, capsys):
    """Without --like, the output keeps the training files' names and time column.

    The reference: the same model's path written with the model's own names
    (the numbers must not change, only the header).
    """
    folder = own_name_demos(tmp_path / "d")
    model = tmp_path / "m.ndlfd"
    assert main(["fit", str(folder), "-o", str(model), "-q",
                 "--group", "position=pos_x,pos_y"]) == 0  # fmt: skip
    fitted = KeypointHMM.load(model)
    assert fitted.input_mapping_.time == "time"
    assert dict(fitted.input_mapping_.groups)["position"] == ("pos_x", "pos_y")
    out = tmp_path / "g.csv"
    rc, err = cli(capsys, "generate", model, "--duration", "2", "--samples", "9",
                  "--dense", "-o", out)  # fmt: skip
    assert rc == 0, err
    header, data = read_table(out)
    # the files' names in their order, the derived velocity after them
    assert header == ["time", "pos_x", "pos_y", "gripper", "vx", "vy"]
    ref = fitted.generate(np.linspace(0, 2, 9), dense=True)
    assert ref.columns == ("pos_x", "pos_y", "vx", "vy", "gripper")
    want = ref.X[:, [0, 1, 4, 2, 3]]
    np.testing.assert_allclose(data[:, 1:], want, rtol=1e-9, atol=1e-12)
    rc, err = cli(capsys, "sample", model, "--duration", "2", "--samples", "9",
                  "-n", "2", "-o", tmp_path / "s")  # fmt: skip
    assert rc == 0, err
    assert read_table(tmp_path / "s" / "sample_000.csv")[0] == header
    # files read in two ways: no one set of names to keep, the model's
    (folder / "d9.csv").write_text(
        "t,pos_x,pos_y,gripper\n0,0,0,0\n0.5,1,1,0\n1,2,1,1\n"
    )
    assert main(["fit", str(folder), "-o", str(model), "-q",
                 "--group", "position=pos_x,pos_y"]) == 0  # fmt: skip
    assert KeypointHMM.load(model).input_mapping_ is None
    assert main(["generate", str(model), "--duration", "2", "-o", str(out)]) == 0
    assert read_table(out)[0][:3] == ["t", "position.pos_x", "position.pos_y"]


def test_fit_records_euler_angles_for_the_output(tmp_path, capsys):
    """roll, pitch, yaw in: roll, pitch, yaw out, without --like."""
    from ndlfd.orientation import euler_to_quaternions

    folder = tmp_path / "d"
    folder.mkdir()
    t = np.linspace(0, 1, 30)
    for k in range(3):
        rpy = np.column_stack([0.2 * t, -0.1 * t, 0.5 * t + 0.05 * k])
        xyz = np.column_stack([t, t**2, 0.1 * t + 0.01 * k])
        write_table(folder / f"d{k}.csv", ["t", "x", "y", "z", "roll", "pitch",
                    "yaw"], np.column_stack([t, xyz, rpy]))  # fmt: skip
    model = tmp_path / "m.ndlfd"
    assert main(["fit", str(folder), "-o", str(model), "-q"]) == 0
    out = tmp_path / "g.csv"
    assert main(["generate", str(model), "--duration", "1", "--samples", "30",
                 "--dense", "-o", str(out), "-q"]) == 0  # fmt: skip
    header, data = read_table(out)
    # the files' order (the derived velocity after the recorded columns)
    assert header == ["t", "x", "y", "z", "roll", "pitch", "yaw", "vx", "vy", "vz"]
    path = KeypointHMM.load(model).generate(t, dense=True)
    q = path.get("orientation")
    back = euler_to_quaternions(data[:, 4:7], "xyz")
    # the same rotation (q and -q alike)
    np.testing.assert_allclose(np.abs(np.sum(q * back, axis=1)), 1.0, atol=1e-8)


def test_fit_reports_the_routes_and_takes_an_override(tmp_path, capsys):
    folder = write_obstacle(tmp_path / "d", 5, 3)
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd")
    assert rc == 0, err
    assert err[-2].startswith(  # before the peaks
        "routes: 2 found on position (route 0: 5, route 1: 3 demonstrations)"
    )
    model = KeypointHMM.load(tmp_path / "m.ndlfd")
    np.testing.assert_array_equal(model.routes_, [0] * 5 + [1] * 3)
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd", "--routes", "1")
    assert rc == 0, err
    assert err[-2].startswith("routes: 1 asked for (--routes) on position")
    assert KeypointHMM.load(tmp_path / "m.ndlfd").n_routes == 1
    np.testing.assert_array_equal(KeypointHMM.load(tmp_path / "m.ndlfd").routes_, 0)
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd",
                  "--route-groups", "velocity")  # fmt: skip
    assert rc == 0, err
    assert "on velocity" in err[-2]
    rc, err = cli(capsys, "fit", folder, "-o", tmp_path / "m.ndlfd",
                  "--route-groups", "force")  # fmt: skip
    assert rc == 2 and "route_groups names none of the learned groups" in err[-1]
