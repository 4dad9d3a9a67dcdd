import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from ndlfd._errors import OptionError, ValidationError
from ndlfd.demonstration import Demonstration, default_columns, with_velocity


def _demo(n=5):
    t = np.linspace(0.0, 1.0, n)
    return Demonstration.from_arrays(
        t,
        position=np.column_stack([t, 2 * t]),
        velocity=np.column_stack([np.ones(n), 2 * np.ones(n)]),
        grip=t**2,
    )


# ------------------------------------------------------------------ construction
def test_constructor_stores_read_only_copies():
    t = np.array([0.0, 1.0, 2.0])
    X = np.arange(6.0).reshape(3, 2)
    d = Demonstration(t, X, ["a", "b"], ["g", "g"])
    t[0] = -5
    X[0, 0] = 99
    assert d.t[0] == 0.0 and d.X[0, 0] == 0.0
    assert d.columns == ("a", "b") and d.groups == ("g", "g")
    with pytest.raises(ValueError, match="read-only"):
        d.X[0, 0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        d.t[0] = 1.0
    with pytest.raises(AttributeError):
        d.t = t  # frozen dataclass


def test_properties_and_repr():
    d = _demo()
    assert d.n_samples == 5 == len(d)
    assert d.n_dims == 5
    assert d.group_names == ("position", "velocity", "grip")
    assert d.columns == ("x", "y", "vx", "vy", "grip0")
    assert d.duration == 1.0
    assert repr(d) == (
        "Demonstration(n_samples=5, duration=1, position=(x, y),"
        " velocity=(vx, vy), grip=(grip0))"
    )
    assert d.has_group("grip") and not d.has_group("force")


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        (
            {"t": [0, 1, 1]},
            ValidationError,
            r"t must be strictly increasing; got t\[2\]",
        ),
        (
            {"t": [0, np.nan, 2]},
            ValidationError,
            "t must be finite; got nan at index 1",
        ),
        ({"t": []}, ValidationError, "at least one sample"),
        ({"t": [0, 1]}, ValidationError, r"one row per time stamp \(2 rows\); got 3"),
        ({"X": [1, 2, 3]}, ValidationError, r"X must have shape \(n_samples, n_dims\)"),
        (
            {"X": [[1, np.inf]] * 3},
            ValidationError,
            r"X must be finite; got \[1.0, inf\]",
        ),
        ({"X": [["a", "b"]] * 3}, ValidationError, "X must hold real numbers"),
        (
            {"columns": ["a"]},
            ValidationError,
            r"one entry per column of X \(2\); got 1",
        ),
        ({"columns": ["a", "a"]}, ValidationError, "columns must be unique; got 'a'"),
        ({"columns": "ab"}, ValidationError, "columns must be a sequence of str"),
        ({"columns": ["a", "b,c"]}, ValidationError, "must not contain commas"),
        ({"columns": ["a", ""]}, ValidationError, "non-empty str"),
        ({"groups": ["g"]}, ValidationError, r"groups must have one entry .* got 1"),
        ({"groups": ["g", "a.b"]}, ValidationError, "groups must be names made of"),
        ({"groups": ["g", 3]}, ValidationError, "non-empty str"),
    ],
)
def test_constructor_errors(kwargs, error, match):
    args = {"t": [0, 1, 2], "X": np.zeros((3, 2)), "columns": ["a", "b"]}
    args["groups"] = ["g", "g"]
    args.update(kwargs)
    with pytest.raises(error, match=match):
        Demonstration(**args)


def test_groups_must_be_adjacent():
    with pytest.raises(
        ValidationError, match=r"adjacent; got group 'a' at columns 0 and 2"
    ):
        Demonstration([0.0], [[1, 2, 3]], ["p", "q", "r"], ["a", "b", "a"])


def test_single_sample_is_allowed():
    d = Demonstration.from_arrays([3.0], position=[[1.0, 2.0]])
    assert d.n_samples == 1 and d.duration == 0.0


def test_from_arrays_defaults_and_column_mapping():
    t = [0.0, 1.0]
    d = Demonstration.from_arrays(
        t, force=[[0, 0, 1]] * 2, position=[[0, 0, 0, 0]] * 2, custom=[[1, 2]] * 2
    )
    assert d.columns == ("p0", "p1", "p2", "p3", "fx", "fy", "fz", "custom0", "custom1")
    assert d.group_names == ("position", "force", "custom")
    np.testing.assert_array_equal(d.X, [[0, 0, 0, 0, 0, 0, 1, 1, 2]] * 2)
    np.testing.assert_array_equal(d.get("force"), [[0, 0, 1]] * 2)
    d2 = Demonstration.from_arrays(
        t, position=[[0, 0]] * 2, columns={"position": ["u", "w"]}
    )
    assert d2.columns == ("u", "w")
    d3 = Demonstration.from_arrays(
        t, position=[1, 2], velocity=[3, 4], columns=["p", "v"]
    )
    assert d3.columns == ("p", "v") and d3.groups == ("position", "velocity")
    np.testing.assert_array_equal(d3.X, [[1, 3], [2, 4]])
    assert default_columns("velocity", 5) == ("v0", "v1", "v2", "v3", "v4")
    assert default_columns("force", 2) == ("fx", "fy")


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({}, ValidationError, "at least one group"),
        ({"position": [[0, 0]] * 3}, ValidationError, "one row per time stamp"),
        (
            {"position": [[0]] * 2, "velocity": [[0]] * 3},
            ValidationError,
            r"same number of rows; got shapes \{'position': \(2, 1\), 'velocity'",
        ),
        (
            {"position": np.zeros((2, 1, 1))},
            ValidationError,
            r"position must have shape",
        ),
        (
            {"orientation": [[1, 0, 0]] * 2},
            ValidationError,
            r"orientation must have shape \(n_samples, 4\)",
        ),
        (
            {"position": [1, 2], "columns": {"force": ["f"]}},
            ValidationError,
            r"columns names groups that were not given: \['force'\]",
        ),
        (
            {"position": [1, 2], "quaternion_order": "zwxy"},
            OptionError,
            "unknown quaternion_order",
        ),
    ],
)
def test_from_arrays_errors(kwargs, error, match):
    with pytest.raises(error, match=match):
        Demonstration.from_arrays([0.0, 1.0], **kwargs)


# ------------------------------------------------------------------ orientation
def test_orientation_is_checked_and_made_continuous_scalar_last():
    rots = Rotation.from_rotvec(np.outer(np.linspace(0, 3, 30), [0.3, 1.0, -0.2]))
    xyzw = rots.as_quat()
    xyzw[1::3] *= -1  # sign flips
    t = np.arange(30.0)
    d = Demonstration.from_arrays(
        t, position=np.zeros((30, 1)), orientation=xyzw, quaternion_order="xyzw"
    )
    Q = d.get("orientation")
    assert d.columns[1:] == ("qw", "qx", "qy", "qz")
    assert np.all(np.einsum("ij,ij->i", Q[1:], Q[:-1]) >= 0)
    back = Rotation.from_quat(Q[:, [1, 2, 3, 0]])
    np.testing.assert_allclose(back.as_matrix(), rots.as_matrix(), atol=1e-12)
    # the constructor itself keeps the invariant
    flipped = np.array(d.X)
    flipped[5, 1:] *= -1
    d2 = Demonstration(t, flipped, d.columns, d.groups)
    np.testing.assert_array_equal(d2.X, d.X)


def test_orientation_errors():
    with pytest.raises(
        ValidationError, match=r"orientation must have unit norm.*at row 1"
    ):
        Demonstration.from_arrays([0, 1], orientation=[[1, 0, 0, 0], [2, 0, 0, 0]])
    with pytest.raises(ValidationError, match="orientation group must have 4 columns"):
        Demonstration([0.0], [[1.0, 0.0]], ["a", "b"], ["orientation"] * 2)


# ------------------------------------------------------------------ access
def test_columns_of_get_select_take():
    d = _demo()
    np.testing.assert_array_equal(d.columns_of("velocity"), [2, 3])
    v = d.get("velocity")
    np.testing.assert_array_equal(v, np.column_stack([np.ones(5), 2 * np.ones(5)]))
    np.testing.assert_array_equal(v, d.X[:, [2, 3]])
    assert np.shares_memory(v, d.X)
    with pytest.raises(
        ValidationError,
        match="unknown group 'force'; this demonstration has groups:"
        " 'position', 'velocity', 'grip'",
    ):
        d.get("force")
    s = d.select("grip", "position")
    assert s.columns == ("grip0", "x", "y") and s.groups == (
        "grip",
        "position",
        "position",
    )
    np.testing.assert_array_equal(s.X, d.X[:, [4, 0, 1]])
    with pytest.raises(ValidationError, match="at least one group"):
        d.select()
    with pytest.raises(ValidationError, match="select got a group twice"):
        d.select("grip", "grip")
    k = d.take([0, 2, 4])
    np.testing.assert_array_equal(k.t, [0.0, 0.5, 1.0])
    np.testing.assert_array_equal(k.X, d.X[[0, 2, 4]])
    assert k.columns == d.columns


@pytest.mark.parametrize(
    ("indices", "match"),
    [
        (
            [0, 2, 2],
            r"strictly increasing; got indices\[2\] = 2 after indices\[1\] = 2",
        ),
        ([3, 1], "strictly increasing"),
        ([0, 5], r"indices must lie in 0..4; got indices\[1\] = 5"),
        ([], "at least one row"),
        ([0.5], "whole numbers"),
    ],
)
def test_take_errors(indices, match):
    with pytest.raises(ValidationError, match=match):
        _demo().take(indices)


def test_with_group_appends_and_replaces_in_place():
    d = _demo()
    e = d.with_group("force", np.ones((5, 3)))
    assert e.columns == (*d.columns, "fx", "fy", "fz")
    assert e.groups == (*d.groups, "force", "force", "force")
    np.testing.assert_array_equal(e.X, np.column_stack([d.X, np.ones((5, 3))]))
    np.testing.assert_array_equal(e.t, d.t)
    r = d.with_group("velocity", np.zeros((5, 3)), columns=["a", "b", "c"])
    assert r.columns == ("x", "y", "a", "b", "c", "grip0")
    assert r.groups == ("position",) * 2 + ("velocity",) * 3 + ("grip",)
    np.testing.assert_array_equal(r.get("velocity"), 0.0)
    np.testing.assert_array_equal(r.get("grip"), d.get("grip"))
    with pytest.raises(
        ValidationError, match=r"values must have shape \(5, k\).*\(4, 1\)"
    ):
        d.with_group("force", np.ones((4, 1)))
    with pytest.raises(ValidationError, match="columns must be unique; got 'x'"):
        d.with_group("force", np.ones(5), columns=["x"])


@pytest.mark.parametrize(
    "name, values, columns, match",
    [
        (
            "force",
            [[np.inf]] * 5,
            None,
            r"finite; got \[.*inf\] \(NaN or inf\) at row 0",
        ),
        ("force", np.ones(5), ["a,b"], "must not contain commas"),
        ("force", np.ones(5), [" a"], "without surrounding spaces"),
        ("bad name", np.ones(5), None, "letters, digits"),
        ("grip\n", np.ones(5), ["g"], "groups must be non-empty str without"),
        ("force", np.ones(5), ["grip0"], "columns must be unique; got 'grip0'"),
        ("orientation", [[2.0, 0, 0, 0]] * 5, None, "unit|norm"),
    ],
)
def test_with_group_checks_the_new_block_as_the_constructor(
    name, values, columns, match
):
    with pytest.raises(ValidationError, match=match):
        _demo().with_group(name, values, columns=columns)


def test_with_group_gives_what_the_constructor_gives():
    # the new block alone is checked; the result is the constructor's
    d = _demo(9)
    rng = np.random.default_rng(0)
    for name, k in (("force", 3), ("velocity", 2), ("grip", 1), ("extra-1", 2)):
        e = d.with_group(name, rng.normal(size=(9, k)))
        full = Demonstration(e.t, e.X, e.columns, e.groups)
        assert e == full and e.X.tobytes() == full.X.tobytes()
        assert not e.X.flags.writeable and not e.t.flags.writeable
        assert e.X.flags.c_contiguous and e.X.dtype == np.float64


@pytest.mark.parametrize("smoothing", ["auto", "none", "window"])
def test_with_velocity_appended_is_with_group_of_numpys_gradient(smoothing):
    # velocity written straight into the new columns: the same demonstration
    # as with_group of the velocity (checked by the constructor)
    rng = np.random.default_rng(3)
    t = np.cumsum(rng.uniform(0.96, 1.04, 30))  # steady, not uniform
    d = Demonstration.from_arrays(t, position=rng.normal(size=(30, 2)), grip=t * 0)
    v = with_velocity(d, smoothing=smoothing)
    V = v.get("velocity")
    if smoothing != "window":
        want = np.gradient(d.get("position"), t, axis=0, edge_order=2)
        assert V.tobytes() == want.tobytes()
    want = d.with_group("velocity", V, ("vx", "vy"))
    full = Demonstration(want.t, want.X, want.columns, want.groups)
    assert v == full and v.X.tobytes() == full.X.tobytes()
    assert not v.X.flags.writeable and v.X.flags.c_contiguous


def test_with_velocity_that_overflows_is_refused():
    # finite positions a tiny step apart: the derived velocity is inf
    d = Demonstration.from_arrays([0.0, 1e-300, 1.0], position=[-1e300, 1e300, 0.0])
    with pytest.raises(ValidationError, match=r"X must be finite; got .*inf"):
        with_velocity(d, smoothing="none")


def test_equality():
    assert _demo() == _demo()
    assert _demo() != _demo(6)
    assert _demo() != _demo().select("position", "velocity", "grip").with_group(
        "grip", np.zeros(5)
    )
    assert _demo().__eq__(3) is NotImplemented
    with pytest.raises(TypeError):
        hash(_demo())


# ------------------------------------------------------------------ velocity
def _circle(n, seed, R=3.0, omega=2 * np.pi, T=2.0):
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.5, 1.5, n))  # non-uniform steps
    t = (t - t[0]) / (t[-1] - t[0]) * T
    P = np.column_stack([R * np.cos(omega * t), R * np.sin(omega * t)])
    V = np.column_stack([-R * omega * np.sin(omega * t), R * omega * np.cos(omega * t)])
    return t, P, V


def test_velocity_of_circle_with_non_uniform_time_stamps():
    R, omega = 3.0, 2 * np.pi
    errors = []
    for n in (200, 400, 800):
        t, P, V = _circle(n, n, R, omega)
        d = with_velocity(Demonstration.from_arrays(t, position=P))
        assert d.columns == ("x", "y", "vx", "vy")
        err = np.abs(d.get("velocity") - V).max()
        h = np.diff(t).max()
        # second-order scheme: error below (omega h)^2 times the speed R omega
        assert err <= (omega * h) ** 2 * R * omega
        errors.append(err)
    # and it converges at second order (halving h divides the error by about 4)
    assert errors[1] < errors[0] / 2.5 and errors[2] < errors[1] / 2.5


def test_velocity_small_n_rules():
    d2 = Demonstration.from_arrays([0.0, 2.0], position=[[0.0, 1.0], [4.0, 1.0]])
    np.testing.assert_array_equal(with_velocity(d2).get("velocity"), [[2.0, 0.0]] * 2)
    d1 = Demonstration.from_arrays([0.0], position=[[0.0, 1.0]])
    with pytest.raises(ValidationError, match=r"at least 2 samples .* got 1"):
        with_velocity(d1)
    # exact on a quadratic with non-uniform steps (edge_order=2 is exact there),
    # up to rounding: a few ulps of the values divided by the smallest step
    t = np.array([0.0, 0.1, 0.4, 0.5, 1.1])
    d = with_velocity(Demonstration.from_arrays(t, position=t**2))
    tol = 16 * np.finfo(float).eps * (t**2).max() / np.diff(t).min()
    np.testing.assert_allclose(d.get("velocity")[:, 0], 2 * t, rtol=0, atol=tol)


def test_velocity_keeps_existing_unless_overwrite():
    d = _demo()
    assert with_velocity(d) is d
    o = with_velocity(d, overwrite=True)
    assert o.columns == d.columns and o.groups == d.groups
    # recomputed from the position (t, 2t): exact up to rounding
    tol = 16 * np.finfo(float).eps * 2.0 / np.diff(d.t).min()
    np.testing.assert_allclose(o.get("velocity"), d.get("velocity"), rtol=0, atol=tol)
    np.testing.assert_array_equal(o.get("position"), d.get("position"))
    np.testing.assert_array_equal(o.get("grip"), d.get("grip"))
    with pytest.raises(ValidationError, match="unknown group 'position'"):
        with_velocity(Demonstration.from_arrays([0, 1], force=[1, 2]))


def test_velocity_savgol_smoothing():
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 1.0, 101)
    P = np.column_stack([np.sin(2 * np.pi * t), t**2])
    V = np.column_stack([2 * np.pi * np.cos(2 * np.pi * t), 2 * t])
    noisy = Demonstration.from_arrays(
        t, position=P + rng.normal(scale=1e-3, size=P.shape)
    )
    raw = with_velocity(noisy).get("velocity")
    smooth = with_velocity(noisy, smoothing="savgol", window_length=11, polyorder=3)
    err_raw = np.sqrt(np.mean((raw - V) ** 2))
    err_smooth = np.sqrt(np.mean((smooth.get("velocity") - V) ** 2))
    assert err_smooth < err_raw / 2
    # a quadratic is untouched by a polyorder-2 filter (up to rounding: a few
    # ulps of max|x| = 1 per step h = 0.01)
    q = Demonstration.from_arrays(t, position=t**2)
    np.testing.assert_allclose(
        with_velocity(q, smoothing="savgol", window_length=5).get("velocity")[:, 0],
        2 * t,
        rtol=0,
        atol=16 * np.finfo(float).eps / 0.01,
    )


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        (
            {"smoothing": "kalman"},
            OptionError,
            r"unknown smoothing 'kalman'; expected one of: 'auto', 'none', 'savgol',"
            r" 'window'",
        ),
        (
            {"smoothing": "savgol", "window_length": 4},
            ValidationError,
            "window_length must be odd.*got 4",
        ),
        (
            {"smoothing": "savgol", "window_length": 3, "polyorder": 3},
            ValidationError,
            r"greater than polyorder \(3\)",
        ),
        (
            {"smoothing": "savgol", "window_length": 11},
            ValidationError,
            r"at most n_samples \(5\); got 11",
        ),
        (
            {"smoothing": "savgol", "window_length": 2.0},
            ValidationError,
            "window_length must be an integer",
        ),
    ],
)
def test_velocity_option_errors(kwargs, error, match):
    d = _demo().select("position")
    with pytest.raises(error, match=match):
        with_velocity(d, **kwargs)


@settings(max_examples=30, deadline=None)
@given(
    st.lists(st.floats(0.01, 10.0), min_size=2, max_size=30),
    st.floats(-5, 5),
    st.floats(-5, 5),
)
def test_velocity_of_a_line_is_exact(steps, a, b):
    # exact up to rounding: the gradient's three coefficients sum in absolute
    # value to at most 4 / h_min and each term is rounded a few times, so the
    # error is a few ulps of max|x| per h_min (measured: under 3 eps max|x| / h_min)
    t = np.concatenate([[0.0], np.cumsum(steps)])
    x = a * t + b
    d = with_velocity(Demonstration.from_arrays(t, position=x))
    tol = 16 * np.finfo(float).eps * np.abs(x).max() / np.diff(t).min()
    np.testing.assert_allclose(d.get("velocity")[:, 0], a, rtol=0, atol=tol)


@settings(max_examples=60, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    st.integers(2, 40),
    st.integers(1, 4),
    st.sampled_from(["uniform", "integer", "random", "one-off"]),
)
def test_the_gradient_kernel_is_numpy_gradient_bit_for_bit(seed, n, d, steps):
    # the compiled velocity against the numpy call it replaced; uniform steps
    # (all exactly equal) take numpy's uniform formulas, others its general ones
    from ndlfd._demo_kernels import gradient, with_room
    from ndlfd.demonstration import JITTER_TOL

    rng = np.random.default_rng(seed)
    dt = {
        "uniform": np.full(n - 1, rng.uniform(0.001, 2.0)),
        "integer": np.full(n - 1, 1.0),
        "random": rng.uniform(0.001, 2.0, n - 1),
        "one-off": np.where(np.arange(n - 1) == n // 2, 0.3, 0.25),
    }[steps]
    t = rng.uniform(-5, 5) + np.concatenate([[0.0], np.cumsum(dt)])
    P = rng.normal(0, rng.uniform(0.1, 100), (n, d))
    V, steady = gradient(t, P, JITTER_TOL)
    want = np.gradient(P, t, axis=0, edge_order=2 if n >= 3 else 1)
    assert V.tobytes() == want.tobytes()
    diffs = np.diff(t)
    assert steady == (n < 10 or np.ptp(diffs) <= JITTER_TOL * diffs.min())
    # written into the last columns of a wider array (velocity appended)
    X = rng.normal(size=(n, 2))
    wide = with_room(X, d)
    got, again = gradient(t, P, JITTER_TOL, out=wide[:, 2:])
    assert again == steady and np.shares_memory(got, wide)
    assert wide.tobytes() == np.concatenate([X, want], axis=1).tobytes()


@settings(max_examples=40, deadline=None)
@given(
    st.integers(0, 2**31),
    st.floats(0.15, 0.45),
    st.integers(200, 1500),
)
def test_velocity_on_jittery_time_stamps_follows_the_true_derivative(seed, amp, n):
    # a smooth reach sampled at true times k*dt, logged with stamps jittered by
    # up to amp*dt: neighbouring differences divide by jittered steps, the
    # window fit does not
    from ndlfd import NdlfdWarning
    from ndlfd.demonstration import timing_jitter

    rng = np.random.default_rng(seed)
    dt = 3.0 / n
    t_true = np.arange(n) * dt
    s = t_true / t_true[-1]
    P = np.column_stack([0.4 * (10 * s**3 - 15 * s**4 + 6 * s**5), np.sin(2 * s)])
    ds = (30 * s**2 - 60 * s**3 + 30 * s**4) / t_true[-1]
    V = np.column_stack([0.4 * ds, 2 * np.cos(2 * s) / t_true[-1]])
    stamps = t_true + rng.uniform(-amp, amp, n) * dt
    assert np.all(np.diff(stamps) > 0) and timing_jitter(stamps) > 0.1
    demo = Demonstration.from_arrays(stamps, position=P)
    with pytest.warns(NdlfdWarning, match="jittery"):
        got = with_velocity(demo).get("velocity")
    naive = with_velocity(demo, smoothing="none").get("velocity")
    speed = np.abs(V).max()
    err = np.abs(got - V).max()
    # the fit's error: the stamps' jitter over the window's spread, times the
    # speed (measured at most 0.51 amp for a +-4-step window), plus its bias
    assert err < 0.65 * amp * speed
    assert err < 0.5 * np.abs(naive - V).max()


def test_exact_irregular_stamps_keep_the_exact_derivative_without_warning():
    t, P, _ = _circle(400, 3)  # random steps, exact stamps, smooth motion
    auto = with_velocity(Demonstration.from_arrays(t, position=P))  # no warning
    exact = with_velocity(Demonstration.from_arrays(t, position=P), smoothing="none")
    np.testing.assert_array_equal(auto.X, exact.X)


def test_window_derivative_is_exact_on_lines_and_matches_a_slow_fit():
    from ndlfd.demonstration import window_derivative

    rng = np.random.default_rng(0)
    t = np.cumsum(rng.uniform(0.2, 1.0, 60))
    X = np.column_stack([2.5 * t - 1, -t + 3])
    np.testing.assert_allclose(window_derivative(t, X, 1.3), [[2.5, -1.0]] * 60,
                               rtol=0, atol=1e-12)  # fmt: skip
    Y = np.column_stack([np.sin(t), t**2])
    got = window_derivative(t, Y, 1.3)
    for i in (0, 1, 30, 59):  # np.polyfit over the same window (>= neighbours)
        inside = np.abs(t - t[i]) <= 1.3
        inside[max(i - 1, 0) : i + 2] = True
        ref = [np.polyfit(t[inside], y[inside], 1)[0] for y in Y.T]
        np.testing.assert_allclose(got[i], ref, rtol=1e-9, atol=1e-12)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**31), st.floats(0.0, 0.2), st.integers(5, 60))
def test_the_jitter_check_decides_as_its_definition(seed, spread, n):
    # the cheap pre-check (all steps within 10 % of the smallest) must never
    # change the decision of timing_jitter and the speed roughness
    import warnings

    from ndlfd import NdlfdWarning
    from ndlfd._timing import speed_roughness
    from ndlfd.demonstration import JITTER_TOL, timing_jitter

    rng = np.random.default_rng(seed)
    t = np.concatenate([[0.0], np.cumsum(rng.uniform(1 - spread, 1 + spread, n))])
    P = np.column_stack([np.arange(n + 1.0), rng.normal(0, 0.3, n + 1)])
    expected = timing_jitter(t) > JITTER_TOL and speed_roughness(P, t) > JITTER_TOL
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with_velocity(Demonstration.from_arrays(t, position=P))
    warned = any(issubclass(w.category, NdlfdWarning) for w in caught)
    assert warned == expected
