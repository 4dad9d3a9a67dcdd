"""KeypointHMM: parameters, fit, the stages composed, options."""

import numpy as np
import pytest

from learner_helpers import (
    tight_starts,
    waves,
)
from ndlfd import (
    DecodeError,
    NotFittedError,
    OptionError,
    ValidationError,
    hmm,
)
from ndlfd.codebook import Codebook, TimeBins
from ndlfd.demonstration import Demonstration
from ndlfd.dp import simplify
from ndlfd.learner import KeypointHMM
from ndlfd.learner._spec import prepare
from ndlfd.normalize import GroupScaler


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
    np.testing.assert_array_equal(m.train_values_[0], prepare(train[0], m.groups_).X)

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


def test_fit_options_and_their_errors(capsys, monkeypatch):
    import sys

    from ndlfd import MissingExtraError

    demos = [Demonstration.from_arrays(t, position=P) for t, P in waves(5)]
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


def test_the_same_demonstrations_give_the_same_model_and_path_without_a_seed():
    demos = tight_starts(n=40, seed=3)
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
