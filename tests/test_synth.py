import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd._errors import OptionError, ValidationError
from ndlfd.demonstration import Demonstration, with_velocity
from ndlfd.synth import (
    SHAPES,
    curve,
    make_dataset,
    obstacle,
    spiral,
    square,
    square_spiral,
)

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
    # every sample lies exactly on the square: one coordinate is 0 or the side
    # (side * (corner + local * step) has a zero step in that coordinate)
    on_edge = (P == 0.0) | (P == 4.0)
    assert np.all(on_edge.any(axis=1))
    np.testing.assert_array_equal(P[0], [0, 0])
    np.testing.assert_allclose(P[-1], [0, 0], atol=1e-12)
    # constant speed: |v| = perimeter / duration everywhere (one non-zero
    # component, so the norm is that component: a couple of roundings)
    V = square(side=4.0).get("velocity")
    np.testing.assert_allclose(
        np.linalg.norm(V, axis=1), 16.0 / 7.9, rtol=4 * np.finfo(float).eps
    )
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
    d = spiral(n_points=601)
    S = d.get("position")
    # the documented formula at the warped parameter s(tau)
    tau = d.t / d.t[-1]
    w = 2 * np.pi * 2
    s = tau + 0.5 * np.sin(w * tau) / w
    W = 2 * np.pi * 3
    want = np.column_stack([-10 + 20 * s, 5 + 5 * np.cos(W * s), 5 * np.sin(W * s)])
    np.testing.assert_allclose(S, want, rtol=0, atol=1e-13)
    # 601 samples of a symmetric warp hit s = 0, 1/12, 1/6, ..., 1 exactly
    # enough that the extremes are the exact bounds
    np.testing.assert_array_equal(S.min(axis=0), [-10, 0, -5])
    np.testing.assert_array_equal(S.max(axis=0), [10, 10, 5])


def _side_index(name, demo, speed):
    """Which side of the square each sample is on (corners are kinks)."""
    tau = demo.t / demo.t[-1]
    s = tau
    if speed == "variable":
        w = 2 * np.pi * 2
        s = tau + 0.5 * np.sin(w * tau) / w
    loops = 2 if name == "square_spiral" else 1
    return np.minimum(np.floor(4 * loops * s), 4 * loops - 1)


@pytest.mark.parametrize("name", ["spiral", "curve", "square_spiral", "square"])
@pytest.mark.parametrize("speed", ["constant", "variable"])
def test_analytic_velocity_matches_numerical_derivative(name, speed):
    demo = GENERATORS[name](n_points=2001, speed=speed)
    numeric = with_velocity(demo.select("position")).get("velocity")
    V = demo.get("velocity")
    err = np.abs(numeric - V).max(axis=1)
    # np.gradient (second order, one-sided second order at the ends) errs by
    # h^2 V''/6 inside and h^2 V''/3 at the ends, and h^2 V'' is about the
    # second difference of the analytic velocity: err <= |V[i-1:i+2] 2nd diff|/3
    smooth = np.ones(len(err), dtype=bool)
    if name.startswith("square"):
        # the corners are kinks: leave out two samples either side of each
        side = _side_index(name, demo, speed)
        corner = np.flatnonzero(np.diff(side) != 0)
        for c in corner:
            smooth[max(c - 2, 0) : c + 4] = False
    d2 = np.abs(np.diff(V, 2, axis=0)).max(axis=1)
    d2 = np.r_[d2[0], d2, d2[-1]][smooth].max()
    scale = np.abs(V).max()
    # a little over 1/3 for the O(h^3) terms, plus rounding
    assert err[smooth].max() <= 0.4 * d2 + 1e-12 * scale
    if speed == "constant" and name.startswith("square"):
        # straight sides at constant speed: the differences are exact
        assert err[smooth].max() <= 1e-12 * scale


def test_variable_speed_warp():
    const, var = square(n_points=801), square(n_points=801, speed="variable")
    np.testing.assert_array_equal(const.t, var.t)
    np.testing.assert_allclose(
        var.get("position")[[0, -1]], const.get("position")[[0, -1]], atol=1e-12
    )
    speed = np.linalg.norm(var.get("velocity"), axis=1)
    mean = 4 * 10.0 / var.duration
    # ds/dτ = 1 + 0.5 cos(4πτ): between 0.5 and 1.5 times the mean speed
    # 801 samples put tau = k/4 (cos = +-1) on samples: the extremes are hit
    eps = np.finfo(float).eps
    np.testing.assert_allclose(
        [speed.min(), speed.max()], [0.5 * mean, 1.5 * mean], rtol=4 * eps
    )
    tau = var.t / var.t[-1]
    np.testing.assert_allclose(
        speed, mean * (1 + 0.5 * np.cos(4 * np.pi * tau)), rtol=4 * eps
    )
    # same path: every sample still lies exactly on the square
    P = var.get("position")
    assert np.all(((P == 0.0) | (P == 10.0)).any(axis=1))


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
    st.sampled_from(["gaussian", "uniform"]),
    st.integers(0, 2**32 - 1),
)
def test_generators_add_the_documented_noise(name, n, speed, noise, model, seed):
    gen = GENERATORS[name]
    d = gen(n_points=n, speed=speed, noise=noise, noise_model=model, random_state=seed)
    clean = gen(n_points=n, speed=speed)
    assert d.n_samples == n and clean.n_samples == n
    np.testing.assert_array_equal(d.t, np.arange(n) * 0.1)
    np.testing.assert_array_equal(d.t, clean.t)
    assert d.columns == clean.columns and d.groups == clean.groups
    if noise == 0:
        assert d == clean
    # the module docs: i.i.d. per sample and column, position first, then
    # velocity; scale = noise (0.6 noise for velocity) x the clean group's range
    rng = np.random.default_rng(seed)
    for group, fraction in (("position", noise), ("velocity", 0.6 * noise)):
        C = clean.get(group)
        scale = fraction * (C.max() - C.min())
        if model == "gaussian":
            want = scale * rng.standard_normal(C.shape)
        else:
            want = -scale + 2 * scale * rng.random(C.shape)
        got = d.get(group) - C
        tol = 4 * np.finfo(float).eps * (np.abs(C) + np.abs(want))
        assert np.all(np.abs(got - want) <= tol), group
        if model == "uniform":
            assert np.all(np.abs(got) <= scale * (1 + 1e-15) + tol)


@pytest.mark.parametrize("lift", [0.0, 1.0])
def test_obstacle_routes_go_around_the_bump(lift):
    demos = obstacle(4, 2, n_samples=101, lift=lift)
    assert len(demos) == 6
    for k, d in enumerate(demos):
        sign = 1.0 if k < 4 else -1.0
        assert d.groups == ("position", "position") or list(d.groups) == [
            "position",
            "position",
        ]
        P = d.get("position")
        # by hand: y = ±(5.5 sin(pi s) + lift (1 - s)) plus noise of sd 0.05
        # and a drift of at most 101 steps of sd 0.0005
        assert P[0] == pytest.approx([-10.0, sign * lift], abs=0.3)
        assert P[50] == pytest.approx([-5.0, sign * (5.5 + 0.5 * lift)], abs=0.3)
        assert P[-1] == pytest.approx([0.0, 0.0], abs=0.3)
        assert 4.5 <= d.t[-1] <= 5.5 and d.t[0] == 0.0
    again = obstacle(4, 2, n_samples=101, lift=lift)
    assert all(np.array_equal(a.X, b.X) for a, b in zip(demos, again, strict=True))


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        (dict(n_up=-1), "n_up"),
        (dict(n_up=0, n_down=0), "at least one"),
        (dict(n_samples=1), "n_samples"),
        (dict(n_down=2.5), "n_down"),
    ],
)
def test_obstacle_refuses_bad_sizes(kw, match):
    with pytest.raises(ValidationError, match=match):
        obstacle(**kw)


def test_pick_place_is_rigid_in_its_frames():
    from scipy.spatial.transform import Rotation

    from ndlfd import synth

    demos, frames = synth.pick_place(4, n_samples=201, yaw=np.deg2rad(60), noise=0.0)
    for d, f in zip(demos, frames, strict=True):
        P, Q, g = d.get("position"), d.get("orientation"), d.get("gripper")[:, 0]
        tau = (d.t - d.t[0]) / d.duration
        for frame, at in (("object", 0.42), ("place", 0.9)):
            k = int(np.argmin(np.abs(tau - at)))
            np.testing.assert_allclose(P[k], f[frame][:3], atol=1e-12)
            # the hand's rotation there is the frame's (up to the sign of q)
            r = Rotation.from_quat(np.roll(Q[k], -1)).inv() * Rotation.from_quat(
                np.roll(f[frame][3:], -1)
            )
            assert r.magnitude() < 1e-9
        closed = (tau >= synth.PICK_PLACE_GRASP) & (tau < synth.PICK_PLACE_RELEASE)
        assert np.array_equal(g, np.where(closed, 0.0, 1.0))
        # the retreat, like the approach, turns with the frame: 0.05 back along
        # the frame's x axis (horizontal: the hand points down), 0.1 up
        x_axis = Rotation.from_quat(np.roll(f["place"][3:], -1)).apply([1, 0, 0])
        back = -0.05 * x_axis + [0, 0, 0.1]
        np.testing.assert_allclose(P[-1], f["place"][:3] + back, atol=1e-12)
    yaws = [Rotation.from_quat(np.roll(f["object"][3:], -1)).as_euler("zyx")[0]
            for f in frames]  # fmt: skip
    assert np.ptp(yaws) > 0.2 and np.max(np.abs(yaws)) <= np.deg2rad(60) + 1e-12
