import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd._errors import OptionError, ValidationError
from ndlfd.demo import Demonstration, with_velocity
from ndlfd.synth import SHAPES, curve, make_dataset, spiral, square, square_spiral

GENERATORS = {
    "square": square,
    "square_spiral": square_spiral,
    "spiral": spiral,
    "curve": curve,
}


@pytest.mark.parametrize(
    ("gen", "n", "d"),
    [(square, 80, 2), (square_spiral, 71, 3), (spiral, 150, 3), (curve, 100, 2)],
)
def test_shapes_counts_and_sampling(gen, n, d):
    demo = gen()
    assert isinstance(demo, Demonstration)
    assert demo.n_samples == n and demo.n_dims == 2 * d
    assert demo.group_names == ("position", "velocity")
    np.testing.assert_allclose(demo.t, np.arange(n) * 0.1, rtol=0, atol=1e-12)
    assert gen(n_points=7, dt=0.5).t[-1] == 3.0


def test_registry_names():
    assert SHAPES.names == ("square", "square_spiral", "spiral", "curve")
    for name, gen in GENERATORS.items():
        assert SHAPES.get(name) is gen


def test_clean_square_geometry():
    P = square(side=4.0).get("position")
    on_edge = np.isclose(P, 0.0) | np.isclose(P, 4.0)
    assert np.all(on_edge.any(axis=1))  # every sample lies on the square
    np.testing.assert_array_equal(P[0], [0, 0])
    np.testing.assert_allclose(P[-1], [0, 0], atol=1e-12)
    # constant speed: |v| = perimeter / duration everywhere
    V = square(side=4.0).get("velocity")
    np.testing.assert_allclose(np.linalg.norm(V, axis=1), 16.0 / 7.9)
    # the path visits the four corners in order (counter-clockwise)
    dense = square(n_points=401, side=4.0).get("position")
    np.testing.assert_allclose(
        dense[[0, 100, 200, 300, 400]],
        [[0, 0], [4, 0], [4, 4], [0, 4], [0, 0]],
        atol=1e-12,
    )


def test_square_spiral_and_spiral_geometry():
    P = square_spiral(n_points=401, speed="constant").get("position")
    np.testing.assert_allclose(P[:, 2], np.linspace(0, 10, 401), atol=1e-12)
    np.testing.assert_allclose(
        P[[0, 200, 400], :2], [[0, 0], [0, 0], [0, 0]], atol=1e-12
    )
    S = spiral(n_points=601).get("position")
    np.testing.assert_allclose(S.min(axis=0), [-10, 0, -5], atol=1e-3)
    np.testing.assert_allclose(S.max(axis=0), [10, 10, 5], atol=1e-3)


@pytest.mark.parametrize("name", ["spiral", "curve", "square_spiral", "square"])
@pytest.mark.parametrize("speed", ["constant", "variable"])
def test_analytic_velocity_matches_numerical_derivative(name, speed):
    demo = GENERATORS[name](n_points=2001, speed=speed)
    numeric = with_velocity(demo.select("position")).get("velocity")
    analytic = demo.get("velocity")
    err = np.abs(numeric - analytic).max(axis=1)
    scale = np.abs(analytic).max()
    if name.startswith("square"):
        # corners are kinks: compare away from them (a few samples per corner)
        good = np.sort(err)[: int(0.95 * len(err))]
        assert good.max() < 1e-5 * scale  # O(h^2) from the warp
    else:
        assert err.max() < 1e-3 * scale


def test_variable_speed_warp():
    const, var = square(n_points=801), square(n_points=801, speed="variable")
    np.testing.assert_array_equal(const.t, var.t)
    np.testing.assert_allclose(
        var.get("position")[[0, -1]], const.get("position")[[0, -1]], atol=1e-12
    )
    speed = np.linalg.norm(var.get("velocity"), axis=1)
    mean = 4 * 10.0 / var.duration
    # ds/dτ = 1 + 0.5 cos(4πτ): between 0.5 and 1.5 times the mean speed
    np.testing.assert_allclose(
        [speed.min(), speed.max()], [0.5 * mean, 1.5 * mean], rtol=1e-4
    )
    tau = var.t / var.t[-1]
    np.testing.assert_allclose(
        speed, mean * (1 + 0.5 * np.cos(4 * np.pi * tau)), rtol=1e-9
    )
    # same path: every sample still lies on the square
    P = var.get("position")
    assert np.all((np.isclose(P, 0.0) | np.isclose(P, 10.0)).any(axis=1))


def test_curve_speed_profile():
    d = curve(n_points=1001)
    tau = d.t / d.t[-1]
    a, k = 0.7, 3
    s = tau + a * np.sin(2 * np.pi * k * tau) / (2 * np.pi * k)
    ds = 1 + a * np.cos(2 * np.pi * k * tau)
    T = d.t[-1]
    np.testing.assert_allclose(
        d.get("position"),
        np.column_stack([10 * s, 4 * np.sin(2 * np.pi * s)]),
        atol=1e-12,
    )
    np.testing.assert_allclose(d.get("velocity")[:, 0], 10 * ds / T, rtol=1e-12)
    # constant speed uses the plain parameter
    c = curve(n_points=1001, speed="constant")
    np.testing.assert_allclose(c.get("position")[:, 0], 10 * tau, atol=1e-12)


@pytest.mark.parametrize("name", list(GENERATORS))
def test_reproducible_by_seed_and_seeds_differ(name):
    gen = GENERATORS[name]
    a = gen(noise=0.05, random_state=3)
    b = gen(noise=0.05, random_state=3)
    c = gen(noise=0.05, random_state=4)
    assert a == b
    assert not np.array_equal(a.X, c.X)
    assert gen(noise=0.0, random_state=3) == gen()
    g = np.random.default_rng(9)
    assert gen(noise=0.05, random_state=g) != gen(noise=0.05, random_state=g)


@pytest.mark.parametrize(
    ("model", "factor"), [("gaussian", 1.0), ("uniform", 1 / np.sqrt(3))]
)
def test_noise_level_as_documented(model, factor):
    clean = spiral(n_points=4000)
    noisy = spiral(n_points=4000, noise=0.05, noise_model=model, random_state=0)
    dP = noisy.get("position") - clean.get("position")
    dV = noisy.get("velocity") - clean.get("velocity")
    P, V = clean.get("position"), clean.get("velocity")
    p_std, v_std = 0.05 * (P.max() - P.min()), 0.03 * (V.max() - V.min())
    # 12000 draws each: the sample std is within 3 % of the true one (> 5 sigma)
    assert abs(dP.std() / (factor * p_std) - 1) < 0.03
    assert abs(dV.std() / (factor * v_std) - 1) < 0.03
    assert abs(dP.mean()) < 0.05 * p_std
    if model == "uniform":
        assert np.abs(dP).max() <= p_std and np.abs(dV).max() <= v_std
    # explicit velocity noise
    n2 = spiral(n_points=4000, noise=0.05, velocity_noise=0.0, random_state=0)
    np.testing.assert_array_equal(n2.get("velocity"), clean.get("velocity"))


def test_make_dataset():
    train, test = make_dataset("square", n_demos=30, random_state=0)
    assert len(train) == 30 and all(d.n_samples == 80 for d in train)
    clean = square()
    assert all(np.array_equal(d.t, clean.t) for d in train + [test])
    rng_train = np.std([d.get("position") - clean.get("position") for d in train])
    rng_test = np.std(test.get("position") - clean.get("position"))
    assert abs(rng_train / 1.0 - 1) < 0.05  # 10 % of the range 10
    assert 0.5 * 0.5 < rng_test < 0.5 * 1.5  # 5 % of the range 10, 160 draws
    again, again_test = make_dataset("square", n_demos=30, random_state=0)
    assert again == train and again_test == test
    other, _ = make_dataset("square", n_demos=30, random_state=1)
    assert other != train
    _, t2 = make_dataset(
        "square_spiral", 3, speed="constant", n_points=50, side=2.0, random_state=0
    )
    assert t2.n_samples == 50 and t2.n_dims == 6
    assert make_dataset("spiral", 1, noise=0, test_noise=0)[1] == spiral()


@pytest.mark.parametrize(
    ("call", "error", "match"),
    [
        (
            lambda: square(n_points=1),
            ValidationError,
            "n_points must be an integer >= 2; got 1",
        ),
        (lambda: square(n_points=2.5), ValidationError, "n_points must be an integer"),
        (
            lambda: square(noise=-0.1),
            ValidationError,
            "noise must be a finite number >= 0",
        ),
        (
            lambda: square(noise=np.nan),
            ValidationError,
            "noise must be a finite number",
        ),
        (lambda: square(velocity_noise=-1), ValidationError, "velocity_noise must be"),
        (lambda: square(dt=0), ValidationError, "dt must be > 0; got 0"),
        (lambda: square(side=0), ValidationError, "side must be > 0"),
        (
            lambda: square_spiral(turns=0),
            ValidationError,
            "turns must be an integer >= 1",
        ),
        (
            lambda: square(speed="fast"),
            OptionError,
            "unknown speed 'fast'; expected one of: 'constant', 'variable'",
        ),
        (
            lambda: curve(noise_model="pink"),
            OptionError,
            "unknown noise_model 'pink'; expected one of: 'gaussian', 'uniform'",
        ),
        (
            lambda: square(random_state="x"),
            ValidationError,
            "random_state must be None",
        ),
        (
            lambda: make_dataset("circle"),
            OptionError,
            "unknown shape 'circle'; expected one of: 'square', 'square_spiral',"
            " 'spiral', 'curve'",
        ),
        (
            lambda: make_dataset("curve", side=3.0),
            ValidationError,
            r"make_dataset\('curve'\): .*side",
        ),
        (
            lambda: make_dataset("square", 0),
            ValidationError,
            "n_demos must be an integer >= 1",
        ),
    ],
)
def test_errors(call, error, match):
    with pytest.raises(error, match=match):
        call()


@settings(max_examples=30, deadline=None)
@given(
    st.sampled_from(list(GENERATORS)),
    st.integers(2, 60),
    st.sampled_from(["constant", "variable"]),
    st.floats(0, 0.3),
    st.integers(0, 2**32 - 1),
)
def test_generators_property(name, n, speed, noise, seed):
    d = GENERATORS[name](n_points=n, speed=speed, noise=noise, random_state=seed)
    assert d.n_samples == n
    assert np.all(np.isfinite(d.X)) and np.all(np.diff(d.t) > 0)
    clean = GENERATORS[name](n_points=n, speed=speed)
    if noise == 0:
        assert d == clean
