import numpy as np
import pytest

from ndlfd import (
    DecodeError,
    ModelFormatError,
    NotFittedError,
    OptionError,
    ValidationError,
    hmm,
    synth,
)
from ndlfd._blend import minimum_jerk
from ndlfd._simplify import simplify
from ndlfd.codebook import Codebook, TimeBins
from ndlfd.demonstration import Demonstration
from ndlfd.learner import KeypointHMM
from ndlfd.metrics import dtw_distance
from ndlfd.normalize import GroupScaler


@pytest.fixture(scope="module")
def square():
    return synth.make_dataset("square", n_demos=30, random_state=3)


def test_hand_worked_three_point_example():
    # position (0,0), (1,0.5), (2,2): group range 0..2 -> u = (0,0), (.5,.25), (1,1)
    # epsilon 0 keeps the middle point (distance 0.177 to the diagonal);
    # 2 levels per column -> digits (0,0), (1,0), (1,1) -> states 0, 2, 3;
    # centres (.25,.25), (.75,.25), (.75,.75) -> physical (.5,.5), (1.5,.5), (1.5,1.5)
    t = np.array([0.0, 1.0, 2.0])
    d = Demonstration.from_arrays(t, position=[[0, 0], [1, 0.5], [2, 2]])
    model = KeypointHMM(
        groups=("position",), levels=2, epsilon=0.0, n_time_bins=3, generation="paper"
    )
    model.fit([d, d])
    assert [k.tolist() for k in model.keypoints_] == [[0, 1, 2], [0, 1, 2]]
    assert model.n_states_used_ == 3
    path = model.generate(d)
    np.testing.assert_array_equal(path.t, t)
    np.testing.assert_allclose(path.X, [[0.5, 0.5], [1.5, 0.5], [1.5, 1.5]])
    # the same from a plain time vector (one observation per time bin)
    path2 = model.generate(np.array([10.0, 11.0, 12.0]))
    np.testing.assert_allclose(path2.X, path.X)
    np.testing.assert_array_equal(path2.t, [10.0, 11.0, 12.0])


def test_matches_manual_composition_of_the_stages(square):
    train, test = square
    kw = dict(levels={"position": 20, "velocity": 10}, epsilon=0.05, n_time_bins=40)
    model = KeypointHMM(**kw, generation="paper").fit(train)
    # the pipeline written out by hand from the public pieces
    sel = [d.select("position", "velocity") for d in train]
    scaler = GroupScaler().fit(sel)
    cb = Codebook([20, 20, 10, 10])
    tb = TimeBins(40)
    states, symbols = [], []
    for d in sel:
        u = scaler.transform(d)
        idx = simplify(u, 0.05)
        states.append(cb.encode(u[idx]))
        symbols.append(tb.transform(d.t)[idx])
    ref = hmm.estimate(states, symbols, cb.n_states, 40)
    u_test = scaler.transform(test.select("position", "velocity"))
    idx = simplify(u_test, 0.05)
    path, logp = hmm.viterbi(ref, tb.transform(test.t)[idx])
    expected = scaler.inverse_transform(cb.decode(path))
    got = model.generate(test)
    np.testing.assert_array_equal(got.t, test.t[idx])
    np.testing.assert_allclose(got.X, expected, rtol=0, atol=1e-12)
    assert model.decode(test)[2] == pytest.approx(logp)


def test_generated_path_is_an_average_not_a_copy():
    # smooth demonstrations with their own timing and offsets: the generated
    # path is closer to a held-out one than a typical training demonstration
    # is (an average), and closer than the time-aligned mean where timing varies
    t = np.linspace(0.0, 1.0, 300)
    rng = np.random.default_rng(7)
    demos = []
    for _ in range(7):
        warp = t ** rng.uniform(0.6, 1.6)  # each runs the shape at its own pace
        off = rng.normal(0, 0.05, 2)
        P = np.column_stack([np.cos(3 * warp), np.sin(5 * warp)]) + off
        demos.append(Demonstration.from_arrays(t * rng.uniform(2, 3), position=P))
    test, train = demos[0], demos[1:]
    model = KeypointHMM(groups=("position",), epsilon=0.01).fit(train)
    P = model.generate(test.t, dense=True).get("position")
    T = test.get("position")
    mine = dtw_distance(P, T, normalize=True)
    each = [dtw_distance(d.get("position"), T, normalize=True) for d in train]
    assert mine < np.median(each)
    assert all(not np.allclose(P, d.get("position")) for d in train)
    tau = [(d.t - d.t[0]) / d.duration for d in train]
    at = (test.t - test.t[0]) / test.duration
    mean = np.mean(
        [
            np.column_stack([np.interp(at, s, c) for c in d.get("position").T])
            for s, d in zip(tau, train, strict=True)
        ],
        axis=0,
    )
    assert mine < dtw_distance(mean, T, normalize=True)


def test_deterministic_and_save_load_round_trip(square, tmp_path):
    # with at most max_templates demonstrations nothing is random: two fits on
    # threads agree bit for bit
    train, test = square
    a = KeypointHMM(epsilon=0.05, n_time_bins=40, n_jobs=2).fit(train)
    b = KeypointHMM(epsilon=0.05, n_time_bins=40, n_jobs=1).fit(train)
    ga, gb = a.generate(test), b.generate(test)
    np.testing.assert_array_equal(ga.X, gb.X)
    a.save(tmp_path / "m.ndlfd")
    c = KeypointHMM.load(tmp_path / "m.ndlfd")
    gc = c.generate(test)
    np.testing.assert_array_equal(gc.X, ga.X)
    np.testing.assert_array_equal(gc.t, ga.t)
    assert c.get_params() == a.get_params() | {"groups": ("position", "velocity")}
    np.testing.assert_array_equal(c.n_keypoints_, a.n_keypoints_)
    grid = np.linspace(0, 3, 200)
    np.testing.assert_array_equal(
        c.generate(grid, dense=True).X, a.generate(grid, dense=True).X
    )


def test_load_refuses_foreign_and_tampered_files(square, tmp_path):
    train, _ = square
    m = KeypointHMM(epsilon=0.05, n_time_bins=40).fit(train)
    m.save(tmp_path / "m.ndlfd")
    m.model_.save(tmp_path / "hmm.npz")
    with pytest.raises(ModelFormatError, match="KeypointHMM"):
        KeypointHMM.load(tmp_path / "hmm.npz")
    z = dict(np.load(tmp_path / "m.ndlfd", allow_pickle=False))
    z["levels"] = z["levels"][:-1]
    with open(tmp_path / "bad.ndlfd", "wb") as fh:
        np.savez(fh, **z)
    with pytest.raises(ModelFormatError, match=r"tampered|inconsistent"):
        KeypointHMM.load(tmp_path / "bad.ndlfd")


def test_unfitted_and_bad_parameters(square):
    train, test = square
    with pytest.raises(NotFittedError, match="not fitted"):
        KeypointHMM().generate(test)
    with pytest.raises(OptionError, match="normalization"):
        KeypointHMM(normalization="global").fit(train)
    with pytest.raises(OptionError, match="distance"):
        KeypointHMM(distance="euclid").fit(train)
    with pytest.raises(OptionError, match="start"):
        KeypointHMM(start="first").fit(train)
    with pytest.raises(ValidationError, match="epsilon"):
        KeypointHMM(epsilon=-1).fit(train)
    with pytest.raises(ValidationError, match="n_time_bins"):
        KeypointHMM(n_time_bins=0).fit(train)
    with pytest.raises(ValidationError, match="levels names group"):
        KeypointHMM(levels={"force": 3}).fit(train)
    with pytest.raises(ValidationError, match="lacks group"):
        KeypointHMM(groups=("position", "force")).fit(train)
    with pytest.raises(ValidationError, match="Demonstration"):
        KeypointHMM().fit(np.zeros((10, 2)))
    with pytest.raises(ValidationError, match="at least one"):
        KeypointHMM().fit([])
    with pytest.raises(ValidationError, match="unknown parameter"):
        KeypointHMM().set_params(eps=1)


def test_undecodable_timing_is_a_clear_error():
    t = np.linspace(0, 1, 5)
    d = Demonstration.from_arrays(t, position=np.column_stack([t, t**2]))
    # 2 key points per demo only -> only bins 0 and 9 are ever emitted
    model = KeypointHMM(
        groups=("position",), epsilon=10.0, n_time_bins=10, generation="paper"
    ).fit([d])
    grid = np.linspace(0, 1, 50)
    path = model.generate(grid)  # plain times: only bins seen in training
    assert path.n_samples == 2
    other = Demonstration.from_arrays(
        np.linspace(0, 1, 7),
        position=np.column_stack([np.linspace(0, 1, 7), np.sin(np.arange(7))]),
    )
    model0 = KeypointHMM(
        groups=("position",), epsilon=0.0, n_time_bins=10, generation="paper"
    ).fit([d])
    with pytest.raises(DecodeError, match="cannot generate"):
        model0.generate(other)


def test_velocity_is_derived_when_missing():
    t = np.linspace(0, 2 * np.pi, 60)
    demos = [
        Demonstration.from_arrays(
            t, position=np.column_stack([np.cos(t), np.sin(t)]) * s
        )
        for s in (1.0, 1.05, 0.95)
    ]
    model = KeypointHMM(epsilon=0.02, n_time_bins=20).fit(demos)
    assert model.columns_ == ("x", "y", "vx", "vy")
    assert model.column_groups_ == ("position",) * 2 + ("velocity",) * 2


def test_repr_and_params():
    m = KeypointHMM(epsilon=0.1)
    assert repr(m) == "KeypointHMM(epsilon=0.1)"
    assert m.set_params(n_time_bins=7) is m and m.n_time_bins == 7


def test_orientation_group_round_trip_and_unit_quaternions(tmp_path):
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(4)
    t = np.linspace(0, 2, 60)
    demos = []
    for _ in range(8):
        P = np.column_stack([t, np.sin(t)]) + rng.normal(scale=0.02, size=(60, 2))
        angles = np.column_stack([t, 0.5 * t, np.zeros(60)]) + rng.normal(
            scale=0.02, size=(60, 3)
        )
        q = Rotation.from_euler("xyz", angles).as_quat()  # scalar-last
        demos.append(
            Demonstration.from_arrays(
                t, position=P, orientation=q, quaternion_order="xyzw"
            )
        )
    model = KeypointHMM(
        groups=("position", "orientation"),
        levels={"position": 20, "orientation": 12},
        epsilon=0.05,
        n_time_bins=15,
    ).fit(demos)
    path = model.generate(demos[0], dense=True)
    q = path.get("orientation")
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-12)
    model.save(tmp_path / "o.ndlfd")
    again = KeypointHMM.load(tmp_path / "o.ndlfd").generate(demos[0], dense=True)
    np.testing.assert_array_equal(again.X, path.X)


def test_committed_v1_model_file_still_loads_and_generates_the_same():
    import importlib.util
    from pathlib import Path

    from ndlfd.io import read_csv

    here = Path(__file__).parent / "data"
    spec = importlib.util.spec_from_file_location(
        "make_kp", here / "make_keypointhmm_v1.py"
    )
    mk = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mk)
    model = KeypointHMM.load(mk.FIXTURE)
    expected = read_csv(mk.EXPECTED)
    got = model.generate(mk.GRID, dense=True)
    np.testing.assert_array_equal(got.t, expected.t)
    np.testing.assert_allclose(got.X, expected.X, rtol=0, atol=1e-12)
    assert got.columns == expected.columns
    # and the file holds what a fresh fit with the recorded parameters learns
    np.testing.assert_array_equal(mk.build().generate(mk.GRID, dense=True).X, got.X)


def test_a_model_loaded_from_a_v1_file_is_saved_as_v1(tmp_path):
    import json

    mk = _fixture_module("make_keypointhmm_v1")
    model = KeypointHMM.load(mk.FIXTURE)
    assert not hasattr(model, "fit_stats_")  # v1 has no statistics
    model.save(tmp_path / "again.ndlfd")
    with np.load(tmp_path / "again.ndlfd", allow_pickle=False) as z:
        assert json.loads(str(z["__ndlfd__"]))["version"] == 1
        with np.load(mk.FIXTURE, allow_pickle=False) as ref:
            for k in ref.files:
                if k != "__ndlfd__":
                    np.testing.assert_array_equal(z[k], ref[k], err_msg=k)
    again = KeypointHMM.load(tmp_path / "again.ndlfd")
    np.testing.assert_array_equal(
        again.generate(mk.GRID, dense=True).X, model.generate(mk.GRID, dense=True).X
    )


@pytest.mark.parametrize("distance", ["line", "segment", "sed", "paper"])
def test_budget_mode_and_every_distance(square, distance):
    train, test = square
    model = KeypointHMM(n_points=25, distance=distance, n_time_bins=10).fit(train)
    assert np.all(model.n_keypoints_ == 25)
    key_t, symbols, _ = model.timing(test)
    assert key_t.size == symbols.size == 25
    u = model.scaler_.transform(test.select("position", "velocity"))
    times = test.t if distance == "sed" else None
    idx = simplify(u, n_points=25, distance=distance, times=times)
    np.testing.assert_array_equal(key_t, test.t[idx])
    paper = model.set_params(generation="paper")
    assert paper.generate(test).n_samples == 25


def test_weights_change_the_reduction_not_the_codebook(square):
    train, _ = square
    plain = KeypointHMM(epsilon=0.1, n_time_bins=10).fit(train)
    heavy = KeypointHMM(epsilon=0.1, n_time_bins=10, weights={"velocity": 3.0})
    heavy.fit(train)
    assert heavy.n_keypoints_.sum() > plain.n_keypoints_.sum()
    assert heavy.n_clipped_ == 0
    assert heavy.codebook_.n_states == plain.codebook_.n_states
    with pytest.raises(ValidationError, match="weights name unknown group"):
        KeypointHMM(weights={"force": 1.0}).fit(train)


# ------------------------------------------------------------ blended generation
def _two_routes(n=200, per_route=4, seed=0):
    """Demonstrations from (0, 1) over the top or from (0, -1) underneath to (2, 0)."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 2.0, n)
    s = t / 2.0
    demos = []
    for sign in (1.0, -1.0):
        for _ in range(per_route):
            x = 2.0 * s + rng.normal(0, 0.01)
            y = sign * (1.0 - s) * (1.0 + np.sin(np.pi * s)) + rng.normal(0, 0.01)
            demos.append(
                Demonstration.from_arrays(
                    t * rng.uniform(0.9, 1.1), position=np.column_stack([x, y])
                )
            )
    return demos


def test_identical_demonstrations_are_reproduced_exactly():
    t = np.linspace(0.0, 3.0, 40)
    P = np.column_stack([np.sin(t), t**2])
    d = Demonstration.from_arrays(t, position=P)
    model = KeypointHMM(groups=("position",), epsilon=0.01, n_time_bins=10).fit([d] * 3)
    path, std = model.generate(t, dense=True, return_std=True)
    np.testing.assert_array_equal(path.t, t)
    np.testing.assert_allclose(path.X, P, rtol=0, atol=1e-12)
    np.testing.assert_allclose(std, 0.0, atol=1e-12)


def test_start_and_goal_are_honoured_and_velocity_is_the_derivative(square):
    train, test = square
    model = KeypointHMM(epsilon=0.05, n_time_bins=40).fit(train)
    start, goal = [0.3, -0.2], [0.1, 0.4]
    path = model.generate(
        test.t, dense=True, start={"position": start}, goal={"position": goal}
    )
    P = path.get("position")
    np.testing.assert_array_equal(P[0], start)
    np.testing.assert_array_equal(P[-1], goal)
    np.testing.assert_allclose(
        path.get("velocity"), np.gradient(P, test.t, axis=0), rtol=0, atol=1e-12
    )
    # key points: the first and last are at the ends of the timing, pinned too
    keys = model.generate(test.t, start={"position": start}, goal={"position": goal})
    assert keys.t[0] == test.t[0] and keys.t[-1] == test.t[-1]
    np.testing.assert_allclose(keys.get("position")[[0, -1]], [start, goal], atol=1e-12)


def test_the_last_sample_is_at_the_end_of_the_timing(square):
    train, _ = square
    model = KeypointHMM(epsilon=0.05, n_time_bins=20).fit(train)
    grid = np.linspace(0.0, 3.0, 61)
    assert model.generate(grid, dense=True).t[-1] == 3.0
    assert model.generate(grid).t[-1] == 3.0


def test_a_conditioned_path_follows_the_matching_route():
    demos = _two_routes()
    model = KeypointHMM(groups=("position",), epsilon=0.01, n_time_bins=30)
    model.fit(demos)
    t = np.linspace(0.0, 2.0, 200)
    routes = {
        1.0: np.mean([d.get("position") for d in demos[:4]], axis=0),
        -1.0: np.mean([d.get("position") for d in demos[4:]], axis=0),
    }
    for sign, mine in routes.items():
        path = model.generate(t, dense=True, start={"position": [0.0, sign]})
        P = path.get("position")
        other = routes[-sign]
        assert dtw_distance(P, mine, normalize=True) < 0.02
        assert dtw_distance(P, other, normalize=True) > 0.5
        # the mean of both routes (what an unconditioned average gives) is far
        both = (mine + other) / 2
        assert dtw_distance(P, both, normalize=True) > 0.25


def test_band_is_the_posterior_spread_of_the_centroids():
    demos = _two_routes(per_route=2)
    model = KeypointHMM(groups=("position",), epsilon=0.01, n_time_bins=10)
    model.fit(demos)
    t = np.linspace(0.0, 2.0, 50)
    _, std = model.generate(t, dense=True, return_std=True)
    assert std.shape == (50, 2)
    # independent check at one bin: posterior of the segment model by hand
    post = hmm.posterior(model.segment_model_, np.arange(10))
    C = model.centroids_[np.searchsorted(model.centroid_states_, post.states)]
    g = post.probabilities[4] / post.probabilities[4].sum()
    mu = g @ C
    sd_u = np.sqrt(g @ (C - mu) ** 2)
    sd = sd_u * (model.scaler_.data_max_ - model.scaler_.data_min_)
    tau = (t - t[0]) / (t[-1] - t[0])
    at = np.flatnonzero(np.isclose(tau, 0.45))  # bin 4's centre
    if at.size:
        np.testing.assert_allclose(std[at[0]], sd, rtol=1e-9)
    # two routes apart in y: the band's y spread is about the routes' distance
    assert std[:, 1].max() > 0.5
    with pytest.raises(ValidationError, match="return_std"):
        model.set_params(generation="paper").generate(t, return_std=True)


def test_decoders_and_generations_are_named_options(square):
    train, test = square
    with pytest.raises(OptionError, match=r"decoder.*'viterbi', 'map'"):
        KeypointHMM(decoder="beam").fit(train)
    with pytest.raises(OptionError, match=r"generation.*'blend', 'paper'"):
        KeypointHMM(generation="dmp").fit(train)
    m = KeypointHMM(epsilon=0.05, n_time_bins=20, decoder="map").fit(train)
    key_t, states, _ = m.decode(test.t)
    assert np.all(np.diff(key_t) > 0) and states.size == key_t.size
    assert m.generate(test.t, dense=True).n_samples == test.n_samples


def test_bad_start_and_goal(square):
    train, test = square
    model = KeypointHMM(epsilon=0.05, n_time_bins=20).fit(train)
    with pytest.raises(ValidationError, match="mapping of group"):
        model.generate(test.t, start=[0, 0])
    with pytest.raises(ValidationError, match="not learned"):
        model.generate(test.t, start={"force": [0, 0]})
    with pytest.raises(ValidationError, match=r"2 finite value"):
        model.generate(test.t, goal={"position": [0, np.nan]})
    with pytest.raises(ValidationError, match="at least two"):
        model.generate([1.0])


def test_paper_dense_path_is_linear_interpolation_of_its_key_points(square):
    train, test = square
    model = KeypointHMM(epsilon=0.05, n_time_bins=40, generation="paper").fit(train)
    keys = model.generate(test)
    dense = model.generate(test, dense=True)
    for c in range(keys.X.shape[1]):
        np.testing.assert_allclose(
            dense.X[:, c], np.interp(test.t, keys.t, keys.X[:, c]), atol=1e-12
        )


def _reaches(n_demos=8, seed=2):
    """3-D minimum-jerk reaches with a turning orientation, 50-125 Hz, 2.6-3.1 s."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(seed)
    demos = []
    for k in range(n_demos):
        duration = rng.uniform(2.6, 3.1)
        t = np.arange(0.0, duration, 1.0 / (50, 100, 125)[k % 3])
        s = minimum_jerk(t / t[-1])
        a = np.array([0.4, -0.2, 0.3]) + rng.normal(0, 0.01, 3)
        b = np.array([0.7, 0.25, 0.1]) + rng.normal(0, 0.01, 3)
        P = a + s[:, None] * (b - a)
        angles = np.column_stack([0.8 * s, 0.3 * s, np.zeros_like(s)])
        q = Rotation.from_euler("xyz", angles + rng.normal(0, 0.01, 3)).as_quat()
        demos.append(
            Demonstration.from_arrays(
                t, position=P, orientation=q, quaternion_order="xyzw"
            )
        )
    return demos


def test_a_reach_with_orientation_is_smooth_not_a_staircase():
    # defaults on a 3-D reach: orientation learned (not dropped), no standing
    # still, the demonstrations' speed, a start among theirs, unit quaternions
    demos = _reaches()
    model = KeypointHMM().fit(demos[1:])
    assert model.groups_ == ("position", "velocity", "orientation")
    grid = np.linspace(0.0, 3.0, 300)
    path = model.generate(grid, dense=True)
    P = path.get("position")
    steps = np.linalg.norm(np.diff(P, axis=0), axis=1)
    interior = steps[5:-5]  # a minimum-jerk reach is at rest only at its ends
    assert np.all(interior > 1e-5)
    speed = steps / np.diff(grid)
    demo_peak = np.median(
        [
            np.max(np.linalg.norm(np.diff(d.get("position"), axis=0), axis=1)
                   / np.diff(d.t)) * d.duration / 3.0
            for d in demos[1:]
        ]
    )  # fmt: skip
    assert 0.8 < speed.max() / demo_peak < 1.25
    starts = np.array([d.get("position")[0] for d in demos[1:]])
    assert np.linalg.norm(P[0] - starts.mean(axis=0)) < 2 * np.max(
        np.linalg.norm(starts - starts.mean(axis=0), axis=1)
    )
    np.testing.assert_allclose(
        np.linalg.norm(path.get("orientation"), axis=1), 1.0, atol=1e-12
    )
    # the held-out reach: as close as the mean of the demonstrations (the
    # endpoints' 1 cm scatter bounds both)
    held_out = _resample(demos[0], grid)
    mean = np.mean([_resample(d, grid) for d in demos[1:]], axis=0)
    err = np.linalg.norm(P - held_out, axis=1).mean()
    assert err < 1.1 * np.linalg.norm(mean - held_out, axis=1).mean()


def _resample(demo, grid):
    tau = (demo.t - demo.t[0]) / demo.duration
    at = (grid - grid[0]) / (grid[-1] - grid[0])
    P = demo.get("position")
    return np.column_stack([np.interp(at, tau, c) for c in P.T])


def test_each_option_changes_what_it_should_and_nothing_else(square):
    train, test = square
    kw = dict(epsilon=0.05, n_time_bins=30)
    base = KeypointHMM(**kw).fit(train)
    seen = base.model_.states_

    def same_reduction(m):
        assert all(
            np.array_equal(a, b)
            for a, b in zip(m.keypoints_, base.keypoints_, strict=True)
        )

    m = KeypointHMM(**kw, pseudo_emission=0.5).fit(train)
    same_reduction(m)
    # every symbol becomes possible in every seen state: (E + r) / (e + N r)
    assert np.all(m.model_.emission_baseline(seen) == 0.5 / (
        m.model_.emission_totals_ + 30 * 0.5))  # fmt: skip
    assert np.all(base.model_.emission_baseline(seen) == 0)

    m = KeypointHMM(**kw, pseudo_transition=0.25).fit(train)
    same_reduction(m)
    n = m.codebook_.n_states
    np.testing.assert_array_equal(
        m.model_.transition_baseline(seen),
        0.25 / (m.model_.transition_totals_ + n * 0.25),
    )

    m = KeypointHMM(**kw, start="state1").fit(train)
    same_reduction(m)
    assert m.decode(test.t)[2] != base.decode(test.t)[2]  # other start term

    m = KeypointHMM(**kw, normalization="per-dimension").fit(train)
    lo, hi = m.scaler_.data_min_, m.scaler_.data_max_
    allX = np.vstack([d.get("position") for d in train])
    np.testing.assert_array_equal(lo[:2], allX.min(axis=0))
    np.testing.assert_array_equal(hi[:2], allX.max(axis=0))
    assert base.scaler_.data_min_[0] == base.scaler_.data_min_[1] == allX.min()

    m = KeypointHMM(**kw, normalization="none").fit(train)
    np.testing.assert_array_equal(m.train_values_[0], m._prepare(train[0], m.groups_).X)

    pos_only = [d.select("position") for d in train]
    pv = ("position", "velocity")
    with pytest.raises(ValidationError, match="lacks group"):
        KeypointHMM(**kw, groups=pv, derive_velocity=False).fit(pos_only)
    # "auto" without derivation learns what is there
    m = KeypointHMM(**kw, derive_velocity=False).fit(pos_only)
    assert m.columns_ == ("x", "y")
    m = KeypointHMM(**kw).fit(pos_only)  # derived from position and time
    assert m.columns_ == base.columns_
    assert KeypointHMM(**kw, groups=None).fit(pos_only).columns_ == ("x", "y")


# ------------------------------------------------- map and reduce, out of core, Dask
def _fixture_module(name):
    import importlib.util
    from pathlib import Path

    here = Path(__file__).parent / "data"
    spec = importlib.util.spec_from_file_location(name, here / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_committed_v2_model_file_still_loads_and_generates_the_same():
    from ndlfd.io import read_csv

    mk = _fixture_module("make_keypointhmm_v2")
    model = KeypointHMM.load(mk.FIXTURE)
    for expected, kw in ((mk.EXPECTED, {}), (mk.EXPECTED_START, {"start": mk.START})):
        got = model.generate(mk.GRID, dense=True, **kw)
        want = read_csv(expected)
        np.testing.assert_array_equal(got.t, want.t)
        np.testing.assert_allclose(got.X, want.X, rtol=0, atol=1e-12)
        # a fresh fit of the recorded data and parameters generates the same,
        # matching raw samples as format 2 did; today's default does not
        fresh = mk.build(match_window=0.0).generate(mk.GRID, dense=True, **kw)
        np.testing.assert_array_equal(fresh.X, got.X)
        assert not np.array_equal(mk.build().generate(mk.GRID, dense=True).X, got.X)
    # every demonstration was a template; the statistics are a fresh fit's
    assert model.max_templates is None and model.template_indices_.size == 6
    assert model.match_window == 0.0 and KeypointHMM().match_window == 0.05
    assert model.fit_stats_ == mk.build().fit_stats_


class _Reiterable:
    """Makes its demonstrations on demand; counts passes and live objects."""

    def __init__(self, demos, bad=None):
        self._demos = demos  # (t, P) pairs, not Demonstrations
        self.bad = bad
        self.passes = 0
        self.alive = 0
        self.most_alive = 0

    def _gone(self):
        self.alive -= 1

    def __iter__(self):
        import weakref

        self.passes += 1
        for i, (t, P) in enumerate(self._demos):
            if i == self.bad:
                yield Demonstration.from_arrays(t, force=P)  # no position
                continue
            d = Demonstration.from_arrays(t, position=P)
            self.alive += 1
            self.most_alive = max(self.most_alive, self.alive)
            weakref.finalize(d, self._gone)
            yield d


def _waves(n, seed=0, m=120):
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, m)
    out = []
    for _ in range(n):
        a = rng.uniform(0.8, 1.2)
        P = np.column_stack([t, a * np.sin(2 * np.pi * t)]) + rng.normal(0, 0.01, 2)
        out.append((t * rng.uniform(1.5, 2.5), P))
    return out


def _fitted_arrays(model):
    """Everything a fit learns, as arrays."""
    arrays = model.fit_stats_.to_arrays()
    arrays.update(model.model_.to_arrays(prefix="hmm_"))
    arrays.update(model.segment_model_.to_arrays(prefix="seg_"))
    arrays.update(
        scaler_min=model.scaler_.data_min_,
        scaler_max=model.scaler_.data_max_,
        centroids=model.centroids_,
        templates=model.template_indices_,
    )
    return arrays


def _assert_same_model(a, b, timing):
    fa, fb = _fitted_arrays(a), _fitted_arrays(b)
    assert fa.keys() == fb.keys()
    for k in fa:
        np.testing.assert_array_equal(fa[k], fb[k], err_msg=k)
    assert a.fit_stats_ == b.fit_stats_
    for kw in ({}, {"start": {"position": [0.0, 0.05]}}):
        pa, sa = a.generate(timing, dense=True, return_std=True, **kw)
        pb, sb = b.generate(timing, dense=True, return_std=True, **kw)
        np.testing.assert_array_equal(pa.X, pb.X)
        np.testing.assert_array_equal(sa, sb)


@pytest.fixture(scope="module")
def dask_client():
    distributed = pytest.importorskip("distributed")
    with (
        distributed.LocalCluster(
            n_workers=2,
            processes=False,
            threads_per_worker=1,
            dashboard_address=None,
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        yield client


def _run_in(where, request, monkeypatch):
    """(KeypointHMM parameters, fit arguments) that run a fit ``where``."""
    import ndlfd._fitmap as _fitmap
    import ndlfd._parallel as _parallel

    seen = []
    for name in ("_run_threads", "_run_processes"):
        real = getattr(_parallel, name)

        def spy(*args, _real=real, _name=name):
            seen.append(_name)
            return _real(*args)

        monkeypatch.setitem(_parallel.BACKENDS._items, name[5:], spy)
    if where == "threads":  # short demonstrations go to processes otherwise
        monkeypatch.setattr(_fitmap, "_THREAD_MIN_SAMPLES", 1)
    params = {"serial": dict(n_jobs=1), "threads": dict(n_jobs=2),
              "processes": dict(n_jobs=2), "dask": {}}[where]  # fmt: skip
    fit = {"client": request.getfixturevalue("dask_client")} if where == "dask" else {}
    return params, fit, seen


@pytest.mark.parametrize("where", ["threads", "processes", "dask"])
@pytest.mark.parametrize("max_templates", [200, 9])
def test_serial_and_parallel_fits_give_the_same_model(
    where, max_templates, request, monkeypatch
):
    demos = [Demonstration.from_arrays(t, position=P) for t, P in _waves(40)]
    kw = dict(epsilon=0.02, n_time_bins=20, max_templates=max_templates,
              random_state=7)  # fmt: skip
    serial = KeypointHMM(**kw, n_jobs=1).fit(demos)
    params, fit, seen = _run_in(where, request, monkeypatch)
    timing = np.linspace(0.0, 2.0, 150)
    _assert_same_model(serial, KeypointHMM(**kw, **params).fit(demos, **fit), timing)
    lazy = _Reiterable(_waves(40))
    _assert_same_model(serial, KeypointHMM(**kw, **params).fit(lazy, **fit), timing)
    # each pass ran where asked
    assert seen == ([] if where == "dask" else [f"_run_{where}"] * 4)
    assert serial.n_demos_ == 40
    if max_templates < 40:
        from ndlfd._fitstats import template_mask

        want = np.flatnonzero(template_mask(40, max_templates, 7))
        np.testing.assert_array_equal(serial.template_indices_, want)
        assert len(serial.train_values_) == max_templates
    else:  # all are templates, in order: as before the statistics
        np.testing.assert_array_equal(serial.template_indices_, np.arange(40))


def test_more_demonstrations_than_templates(tmp_path):
    # two routes; few templates: the counts, centroids and conditioning use all
    # demonstrations, the blend only the templates; random_state picks them
    demos = _two_routes(per_route=10)
    kw = dict(groups=("position",), epsilon=0.01, n_time_bins=30)
    full = KeypointHMM(**kw).fit(demos)
    few = KeypointHMM(**kw, max_templates=6, random_state=1).fit(demos)
    other = KeypointHMM(**kw, max_templates=6, random_state=2).fit(demos)
    assert few.template_indices_.size == 6
    assert not np.array_equal(few.template_indices_, other.template_indices_)
    for m in (few, other):
        for k in ("key_states", "key_bins", "keypoints", "first", "last",
                  "centroid_limbs", "centroid_counts"):  # fmt: skip
            np.testing.assert_array_equal(
                getattr(m.fit_stats_, k), getattr(full.fit_stats_, k), err_msg=k
            )
        np.testing.assert_array_equal(m.centroids_, full.centroids_)
        for j, u in zip(m.template_indices_, m.train_values_, strict=True):
            np.testing.assert_array_equal(u, full.train_values_[j])
    # conditioned on either start, the path follows that route (as with all)
    t = np.linspace(0.0, 2.0, 200)
    for sign in (1.0, -1.0):
        route = np.mean(
            [d.get("position") for d in demos if d.get("position")[0, 1] * sign > 0],
            axis=0,
        )
        P = few.generate(t, dense=True, start={"position": [0.0, sign]})
        assert dtw_distance(P.get("position"), route, normalize=True) < 0.03
    # saved and loaded: the same model, the same paths
    few.save(tmp_path / "few.ndlfd")
    again = KeypointHMM.load(tmp_path / "few.ndlfd")
    _assert_same_model(few, again, t)
    assert again.get_params() == few.get_params()


def test_a_reiterable_is_read_twice_and_never_held_whole():
    lazy = _Reiterable(_waves(150))
    model = KeypointHMM(
        epsilon=0.02, n_time_bins=20, n_jobs=1, max_templates=10, random_state=3
    )
    model.fit(lazy)
    assert lazy.passes == 2
    assert lazy.most_alive < 80  # a chunk at a time (64), not all 150
    assert model.n_demos_ == 150 and len(model.train_values_) == 10
    listed = [Demonstration.from_arrays(t, position=P) for t, P in _waves(150)]
    _assert_same_model(model, KeypointHMM(**model.get_params()).fit(listed),
                       np.linspace(0, 2, 50))  # fmt: skip


def test_a_generator_is_refused_with_what_to_pass_instead():
    demos = (Demonstration.from_arrays(t, position=P) for t, P in _waves(3))
    with pytest.raises(ValidationError, match=r"one-shot iterator.*re-iterable"):
        KeypointHMM().fit(demos)
    with pytest.raises(ValidationError, match=r"one-shot iterator"):
        KeypointHMM().fit(iter([]))
    with pytest.raises(ValidationError, match=r"single path.*\[path\]"):
        KeypointHMM().fit("demos.csv")
    with pytest.raises(ValidationError, match=r"Demonstration or a file path; got int"):
        t, P = _waves(1)[0]
        KeypointHMM().fit([Demonstration.from_arrays(t, position=P), 3])


@pytest.mark.parametrize("where", ["serial", "threads", "processes", "dask"])
def test_a_corrupt_demonstration_is_named(where, request, monkeypatch):
    run, fit, _ = _run_in(where, request, monkeypatch)
    lazy = _Reiterable(_waves(30), bad=17)
    model = KeypointHMM(epsilon=0.02, n_time_bins=20, **run)
    want = (
        r"^demos\[17\]: a demonstration lacks group\(s\) position, velocity;"
        r" it has force$"
    )
    with pytest.raises(ValidationError, match=want):
        model.fit(lazy, **fit)
    assert not hasattr(model, "model_")


@pytest.mark.parametrize("where", ["threads", "processes", "dask"])
def test_files_are_read_in_each_pass_and_a_bad_one_is_named(
    where, request, monkeypatch, tmp_path
):
    from ndlfd import DataFileError
    from ndlfd.io import write_csv

    demos = [Demonstration.from_arrays(t, position=P) for t, P in _waves(12)]
    paths = []
    for i, d in enumerate(demos):
        write_csv(d, tmp_path / f"d{i:02d}.csv")
        paths.append(tmp_path / f"d{i:02d}.csv")
    params, fit, _ = _run_in(where, request, monkeypatch)
    kw = dict(epsilon=0.02, n_time_bins=20, **params)
    from_files = KeypointHMM(**kw).fit(paths, **fit)
    from_demos = KeypointHMM(epsilon=0.02, n_time_bins=20, n_jobs=1).fit(demos)
    _assert_same_model(from_files, from_demos, np.linspace(0, 2, 50))
    (tmp_path / "d07.csv").write_text("t,x,y\n0,1,2\n1,oops,3\n")
    with pytest.raises(DataFileError, match=r"^demos\[7\]: .*d07\.csv"):
        KeypointHMM(**kw).fit([str(p) for p in paths], **fit)


def test_the_scaler_is_groupscalers_fit_exactly():
    demos = [Demonstration.from_arrays(t, position=P) for t, P in _waves(9)]
    for mode in ("group", "per-dimension", "none"):
        m = KeypointHMM(normalization=mode, weights={"velocity": 0.5}).fit(demos)
        prepared = [m._prepare(d, m.groups_) for d in demos]
        ref = GroupScaler(mode=mode, weights={"velocity": 0.5}).fit(prepared)
        got, want = vars(m.scaler_), vars(ref)
        assert got.keys() == want.keys()
        for k, v in want.items():
            assert np.array_equal(got[k], v) if isinstance(v, np.ndarray) else (
                got[k] == v), k  # fmt: skip


def test_fit_options_and_their_errors(capsys, monkeypatch):
    import sys

    from ndlfd import MissingExtraError

    demos = [Demonstration.from_arrays(t, position=P) for t, P in _waves(5)]
    KeypointHMM(n_time_bins=10).fit(demos, progress=True)
    err = capsys.readouterr().err
    assert "fit 1/2 ranges" in err and "fit 2/2 key points" in err
    KeypointHMM(n_time_bins=10).fit(demos)  # not a terminal: silent
    assert capsys.readouterr().err == ""
    with pytest.raises(ValidationError, match="max_templates"):
        KeypointHMM(max_templates=0).fit(demos)
    with pytest.raises(ValidationError, match="random_state"):
        KeypointHMM(random_state="abc").fit(demos)
    with pytest.raises(ValidationError, match="n_jobs"):
        KeypointHMM(n_jobs=0).fit(demos)
    pytest.importorskip("distributed")
    with pytest.raises(ValidationError, match=r"client must be a distributed\.Client"):
        KeypointHMM().fit(demos, client="tcp://localhost:8786")
    monkeypatch.setitem(sys.modules, "distributed", None)  # as if not installed
    with pytest.raises(MissingExtraError, match=r'pip install "ndlfd\[dask\]"'):
        KeypointHMM().fit(demos, client=True)


def test_batched_counting_and_the_prepared_cache_change_nothing(monkeypatch):
    import ndlfd._fitmap as _fitmap
    import ndlfd.learner as learner

    demos = [Demonstration.from_arrays(t, position=P) for t, P in _waves(40)]
    kw = dict(epsilon=0.02, n_time_bins=20, n_jobs=1)
    ref = KeypointHMM(**kw).fit(demos)
    monkeypatch.setattr(learner, "_ESTIMATE_BATCH", 3)  # hmm.merge of 14 parts
    monkeypatch.setattr(_fitmap, "_CACHE_BYTES", 0)  # prepare again in pass 2
    _assert_same_model(ref, KeypointHMM(**kw).fit(demos), np.linspace(0, 2, 50))


def test_a_long_first_demonstration_then_short_ones_on_two_workers():
    # pass 1 picks threads (by the first), pass 2 processes (by the mean): the
    # prepared cache of pass 1 stays local, and the model is the same
    long_t = np.linspace(0.0, 2.0, 6000)
    long_P = np.column_stack([np.sin(long_t), np.cos(long_t)])
    demos = [Demonstration.from_arrays(long_t, position=long_P)]
    demos += [Demonstration.from_arrays(t, position=P) for t, P in _waves(12)]
    kw = dict(epsilon=0.02, n_time_bins=20)
    serial = KeypointHMM(**kw, n_jobs=1).fit(demos)
    _assert_same_model(serial, KeypointHMM(**kw, n_jobs=2).fit(demos),
                       np.linspace(0.0, 2.0, 80))  # fmt: skip


def test_match_window_is_checked_saved_and_zero_for_older_files(tmp_path):
    from ndlfd._fileformat import load_npz, save_npz

    demos = [Demonstration.from_arrays(t, position=P) for t, P in _waves(8)]
    for bad in (-0.1, 0.6, float("nan"), "wide"):
        with pytest.raises(ValidationError, match="match_window"):
            KeypointHMM(match_window=bad).fit(demos)
    model = KeypointHMM(epsilon=0.02, n_time_bins=20, match_window=0.1).fit(demos)
    model.save(tmp_path / "m.ndlfd")
    again = KeypointHMM.load(tmp_path / "m.ndlfd")
    assert again.match_window == 0.1
    t = np.linspace(0.0, 2.0, 60)
    _assert_same_model(model, again, t)
    # the same file as format 3 wrote it (no match_window): raw matching
    arrays, meta = load_npz(tmp_path / "m.ndlfd", kind="KeypointHMM", version=4)
    del meta["params"]["match_window"]
    extra = {k: v for k, v in meta.items() if k not in ("format", "kind", "version")}
    save_npz(tmp_path / "v3.ndlfd", arrays, kind="KeypointHMM", version=3,
             metadata=extra)  # fmt: skip
    old = KeypointHMM.load(tmp_path / "v3.ndlfd")
    raw = KeypointHMM(epsilon=0.02, n_time_bins=20, match_window=0.0).fit(demos)
    assert old.match_window == 0.0
    _assert_same_model(old, raw, t)


def test_a_refit_forgets_the_conditioning_widths_of_the_last_fit():
    a = [Demonstration.from_arrays(t, position=P) for t, P in _waves(10, seed=1)]
    b = [Demonstration.from_arrays(t, position=3 * P) for t, P in _waves(10, seed=2)]
    kw = dict(epsilon=0.02, n_time_bins=20)
    start = {"position": [0.0, 0.1]}
    t = np.linspace(0.0, 2.0, 50)
    model = KeypointHMM(**kw).fit(a)
    model.generate(t, dense=True, start=start)  # widths of a, kept
    model.fit(b)
    got = model.generate(t, dense=True, start=start)
    fresh = KeypointHMM(**kw).fit(b).generate(t, dense=True, start=start)
    np.testing.assert_array_equal(got.X, fresh.X)


def _tight_starts(n=300, seed=0):
    """One smooth 2-D motion whose starts lie within 0.003 of each other."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, 120)
    base = np.column_stack([2.0 * t, np.sin(np.pi * t)])
    demos = []
    for _ in range(n):
        P = base + rng.normal(0.0, 0.002, base.shape)
        P[0] = rng.uniform(-0.0015, 0.0015, 2)
        demos.append(Demonstration(t, P, ["x", "y"], ["position"] * 2))
    return demos


@pytest.mark.parametrize("offset", [0.02, 0.5, 30.0])
def test_a_start_nearest_to_a_demonstration_that_is_no_template(offset):
    # the kernel weight of every kept template underflows to 0 when the start
    # lies beyond a demonstration that is not among them: a path all the same
    demos = _tight_starts()
    model = KeypointHMM(max_templates=200, epsilon=0.05).fit(demos)
    starts = model.first_values_[:, :2]
    others = np.setdiff1d(np.arange(len(demos)), model.template_indices_)
    centre = starts.mean(axis=0)
    j = others[np.argmax(np.linalg.norm(starts[others] - centre, axis=1))]
    away = (starts[j] - centre) / np.linalg.norm(starts[j] - centre)
    here = demos[j].X[0] + offset * away  # demonstration j is the nearest
    path = model.generate(demos[0].t, dense=True, start={"position": here})
    P = path.get("position")
    assert np.isfinite(P).all()
    np.testing.assert_allclose(P[0], here, atol=1e-12)
    # it ends where the demonstrations end
    np.testing.assert_allclose(P[-1], [2.0, 0.0], atol=0.05)


def test_the_same_demonstrations_give_the_same_model_and_path_without_a_seed():
    demos = _tight_starts(n=40, seed=3)
    a = KeypointHMM(max_templates=10, epsilon=0.05).fit(demos)
    b = KeypointHMM(max_templates=10, epsilon=0.05).fit(demos)
    np.testing.assert_array_equal(a.template_indices_, b.template_indices_)
    t = demos[0].t
    np.testing.assert_array_equal(
        a.generate(t, dense=True).X, b.generate(t, dense=True).X
    )
    # a seed asks for another choice; the same seed for the same one
    c = KeypointHMM(max_templates=10, epsilon=0.05, random_state=5).fit(demos)
    d = KeypointHMM(max_templates=10, epsilon=0.05, random_state=5).fit(demos)
    np.testing.assert_array_equal(c.template_indices_, d.template_indices_)
    assert not np.array_equal(a.template_indices_, c.template_indices_)
