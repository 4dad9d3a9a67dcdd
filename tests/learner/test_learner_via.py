"""Via points and continuing an execution (ndlfd.learner._via)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_learner_routes import obstacle

from learner_helpers import resample
from ndlfd import synth
from ndlfd._errors import ValidationError
from ndlfd.demonstration import Demonstration
from ndlfd.learner import KeypointHMM
from ndlfd.learner._conditioning import minimum_jerk
from ndlfd.learner._via import apply_via, check_via, continue_from

T = np.linspace(0.0, 5.0, 201)


@pytest.fixture(scope="module")
def two_routes():
    demos = obstacle(9, 3)  # 9 over the bump above, 3 below
    return demos, KeypointHMM().fit(demos)


def _range(demos):
    return np.ptp(np.vstack([d.get("position") for d in demos]), axis=0)


def _smooth(n_demos=8, seed=1, n=200):
    """Smooth arcs of slightly different heights and timings (no noise)."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n_demos):
        s = np.linspace(0.0, 1.0, n)
        a = rng.uniform(0.8, 1.2)
        P = np.column_stack([s, a * np.sin(np.pi * s)])
        out.append(Demonstration(5.0 * s, P, ["x", "y"], ["position"] * 2))
    return out


def _max_acc(P, t):
    return float(np.abs(np.gradient(np.gradient(P, t, axis=0), t, axis=0)).max())


def test_a_via_point_on_the_minor_route_makes_the_path_follow_it(two_routes):
    demos, model = two_routes
    assert model.generate(T, dense=True).get("position")[100, 1] > 4.5
    target = [-5.0, -5.2]
    path = model.generate(T, dense=True, via=[(T[100], {"position": target})])
    P = path.get("position")
    assert np.all(np.abs(P[100] - target) <= 0.005 * _range(demos))
    # on the minor route the whole way, never through the obstacle
    minor = np.stack([np.interp(P[:, 0], d.X[:, 0], d.X[:, 1]) for d in demos[9:]])
    assert np.all(P[:, 1] >= minor.min(axis=0) - 0.3)
    assert np.all(P[:, 1] <= minor.max(axis=0) + 0.3)


def test_several_via_points_are_all_hit_and_the_ends_stay_pinned(two_routes):
    demos, model = two_routes
    via = [(T[150], {"position": [-2.3, 4.2]}), (T[60], {"position": [-7.0, 4.9]})]
    start = {"position": [-10.0, 0.3]}
    path = model.generate(T, dense=True, start=start, via=via)
    P = path.get("position")
    tol = 0.005 * _range(demos)
    assert np.all(np.abs(P[150] - [-2.3, 4.2]) <= tol)
    assert np.all(np.abs(P[60] - [-7.0, 4.9]) <= tol)
    np.testing.assert_allclose(P[0], [-10.0, 0.3], atol=1e-12)
    # key points only: the same offsets at the key rows
    keys = model.generate(T, start=start, via=via)
    assert keys.n_samples < T.size


def test_a_via_point_keeps_the_path_as_smooth_as_the_demonstrations():
    demos = _smooth()
    model = KeypointHMM().fit(demos)
    t = demos[0].t
    # a via point between two demonstrations' heights at a third of the course
    target = [1 / 3, 0.95 * np.sin(np.pi / 3)]
    path = model.generate(t, dense=True, via=[(t[66], {"position": target})])
    P = path.get("position")
    assert np.all(np.abs(P[66] - target) <= 0.005 * _range(demos))
    worst = max(_max_acc(d.get("position"), d.t) for d in demos)
    assert _max_acc(P, t) <= 1.5 * worst


def _max_step(P):
    return float(np.linalg.norm(np.diff(P, axis=0), axis=1).max())


@pytest.mark.parametrize("above", [1.0, 2.0, 5.0])
def test_a_via_point_off_the_route_does_not_amplify_the_noise(above):
    """A via point beyond the demonstrations' spread: followed smoothly, no jumps.

    Conditioning on the templates' deviations (their noise included) once
    multiplied each template's noise by how many spreads the point lay off:
    5 above the upper route, steps of 3.3 where the demonstrations' are 0.1.
    """
    demos = synth.obstacle(7, 5)
    model = KeypointHMM().fit(demos)
    t = np.linspace(0.0, 5.0, 1000)
    target = [-5.0, 5.5 + above]  # above the upper route, mid-course
    path = model.generate(t, dense=True, via=[(t[500], {"position": target})])
    P = path.get("position")
    assert np.abs(P[500] - target).max() <= 1e-9 * 10
    # demonstrations resampled to the same 1,000 steps over the same course
    worst = max(_max_step(resample(d, t)) for d in demos)
    # the detour makes the path longer, and its steps with it: 1.8, 2.1 and
    # 2.2 times the demonstrations' largest (without the reach: 9.7, 17, 45)
    assert _max_step(P) <= 2.5 * worst


def test_apply_via_against_a_hand_worked_offset():
    # offset 2 at tau = 0.25, none at the ends: two minimum-jerk pieces
    at = np.linspace(0.0, 1.0, 9)
    X = np.column_stack([at, -at])
    Y = apply_via(X.copy(), at, [(0.25, {"p": np.array([2.25, -0.25])})],
                  ("p", "p"), 9)  # fmt: skip
    off = np.where(at <= 0.25, minimum_jerk(at / 0.25),
                   1.0 - minimum_jerk((at - 0.25) / 0.75))  # fmt: skip
    np.testing.assert_allclose(Y, X + 2.0 * off[:, None] * [1, 0], atol=1e-12)


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.integers(1, 39), min_size=1, max_size=4, unique=True),
    st.lists(st.floats(-5, 5), min_size=8, max_size=8),
    st.integers(0, 2**31),
)
def test_apply_via_hits_every_via_point_and_keeps_the_ends(rows, values, seed):
    at = np.linspace(0.0, 1.0, 41)
    X = np.random.default_rng(seed).normal(size=(41, 2)).cumsum(axis=0)
    via = [(at[r], {"p": np.array(values[2 * k : 2 * k + 2])})
           for k, r in enumerate(sorted(rows))]  # fmt: skip
    Y = apply_via(X.copy(), at, via, ("p", "p"), 41)
    for r, (_, cond) in zip(sorted(rows), via, strict=True):
        np.testing.assert_allclose(Y[r], cond["p"], atol=1e-9)
    np.testing.assert_allclose(Y[[0, -1]], X[[0, -1]], atol=1e-12)


def test_a_via_point_on_a_derived_velocity_is_refused():
    demos = _smooth(4)
    model = KeypointHMM(groups=["position", "velocity"]).fit(demos)
    with pytest.raises(ValidationError, match="velocity is the derivative"):
        model.generate(demos[0].t, via=[(1.0, {"velocity": [0.0, 0.0]})])


def test_sampled_paths_pass_through_the_via_points_on_the_minor_route(two_routes):
    demos, model = two_routes
    via = [(T[100], {"position": [-5.0, -5.2]})]
    paths = model.sample(T, 6, via=via, random_state=0)
    tol = 0.005 * _range(demos)
    for p in paths:
        P = p.get("position")
        assert np.all(np.abs(P[100] - [-5.0, -5.2]) <= tol)
        assert P[50, 1] < -3.0 and P[150, 1] < -3.0


def test_a_prefix_on_the_minor_route_continues_on_it_without_a_jump(two_routes):
    demos, model = two_routes
    d = demos[10]  # on the minor route (below)
    n = 60
    # the prefix at the timing's first time stamps, same normalized clock
    X = np.column_stack([np.interp(T[:n] / T[-1], d.t / d.t[-1], c) for c in d.X.T])
    prefix = Demonstration(T[:n], X, d.columns, d.groups)
    path = model.generate(T, observed=prefix)
    assert path.n_samples == T.size and np.array_equal(path.t, T)
    P = path.get("position")
    np.testing.assert_array_equal(P[:n], X)
    # no jump: the step after the prefix is like the demonstrations' steps
    step = np.abs(P[n] - P[n - 1])
    assert np.all(
        step <= np.abs(np.diff(X, axis=0)).max(axis=0) + 0.005 * _range(demos)
    )
    assert P[100, 1] < -4.5  # still below the obstacle mid-course
    plain = model.generate(T, dense=True)
    assert plain.get("position")[100, 1] > 4.5  # the major route without it


@pytest.mark.parametrize(
    ("via", "match"),
    [
        ([(9.0, {"position": [0.0, 0.0]})], "via\\[0\\]'s time must lie within"),
        ([(-1.0, {"position": [0.0, 0.0]})], "within the timing, 0 to 5; got -1"),
        ([(1.0, {"force": [0.0]})], "names group 'force', which is not learned"),
        ([(1.0, {"position": [0.0]})], "must hold 2 finite value"),
        ([(1.0, {"position": [0.0, 0.0]}), (1.0, {"position": [1.0, 0.0]})],
         "two via points give 'position' at the same time"),
        ([], "via must be a list of \\(time"),
        ([(1.0,)], "via\\[0\\] must be a \\(time"),
        ([("x", {"position": [0.0, 0.0]})], "time must be a number"),
    ],
)  # fmt: skip
def test_bad_via_points_are_refused(two_routes, via, match):
    _, model = two_routes
    with pytest.raises(ValidationError, match=match):
        model.generate(T, via=via)


def test_bad_prefixes_are_refused(two_routes):
    demos, model = two_routes
    d = demos[0]
    with pytest.raises(ValidationError, match="observed must be a Demonstration"):
        model.generate(T, observed=d.X)
    long = Demonstration(
        np.linspace(0, 6, 300), np.zeros((300, 2)), d.columns, d.groups
    )
    with pytest.raises(ValidationError, match="shorter than the timing \\(201"):
        model.generate(T, observed=long)
    off = Demonstration(T[:10] + 0.01, np.zeros((10, 2)), d.columns, d.groups)
    with pytest.raises(ValidationError, match="first time stamps of the timing"):
        model.generate(T, observed=off)
    other = Demonstration(T[:10], np.zeros((10, 2)), ["a", "b"], d.groups)
    with pytest.raises(ValidationError, match="learned columns"):
        model.generate(T, observed=other)
    ok = Demonstration(T[:10], d.X[:10], d.columns, d.groups)
    with pytest.raises(ValidationError, match="cannot be combined with start or via"):
        model.generate(T, observed=ok, start={"position": [-10.0, 0.0]})


def test_paper_generation_refuses_via_and_observed():
    train, _ = synth.make_dataset("square", n_demos=6, random_state=0)
    model = KeypointHMM(generation="paper", n_time_bins=20).fit(train)
    with pytest.raises(ValidationError, match="need generation='blend'"):
        model.generate(np.linspace(0, 1, 20), via=[(0.5, {"position": [0, 0]})])


def test_check_via_sorts_by_time():
    out = check_via([(3.0, {"p": [1]}), (1.0, {"p": [2]})], np.array([0.0, 4.0]),
                    ("p",), ("p",))  # fmt: skip
    assert [tau for tau, _ in out] == [0.25, 0.75]


def test_an_orientation_via_point_as_minus_q_is_the_same_rotation():
    from test_learner_generation import carries

    model = KeypointHMM().fit(carries())
    t = np.linspace(0.0, 4.0, 201)
    q = np.array([np.cos(0.2), 0.0, 0.0, np.sin(0.2)])
    paths = [model.generate(t, dense=True, via=[(t[100], {"orientation": s * q})])
             for s in (1.0, -1.0)]  # fmt: skip
    np.testing.assert_array_equal(paths[0].X, paths[1].X)
    Q = paths[0].get("orientation")
    np.testing.assert_allclose(Q[100], q, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(Q, axis=1), 1.0, atol=1e-12)
    # no flip: as smooth as the path without the via point
    plain = model.generate(t, dense=True).get("orientation")
    assert np.abs(np.diff(Q, axis=0)).max() < 2 * np.abs(np.diff(plain, axis=0)).max()


def test_with_a_via_point_the_goal_carries_over_as_the_demonstrations_co_vary():
    """A pick-and-place whose place follows its goal: the goal moves the place.

    Before the goal was an observation (it was only pinned after the release),
    the path put the object down where the demonstrations did on average:
    median 0.078 m from the held-out place, their spread 0.074 m; now 0.027.
    """
    demos, frames = synth.pick_place(12)
    errors, spreads = [], []
    for k in range(6):
        train = [d for i, d in enumerate(demos) if i != k]
        test = demos[k]
        t, P = test.t, test.get("position")
        grasp = int(np.rint(synth.PICK_PLACE_GRASP * (t.size - 1)))
        place = int(np.rint(0.9 * (t.size - 1)))  # PICK_PLACE_PLAN: down at 0.9
        model = KeypointHMM().fit(train)
        via = [(t[grasp], {"position": frames[k]["object"][:3]})]
        path = model.generate(t, dense=True, start={"position": P[0]},
                              goal={"position": P[-1]}, via=via)  # fmt: skip
        errors.append(
            np.linalg.norm(path.get("position")[place] - frames[k]["place"][:3])
        )
        at = [d.get("position")[int(0.9 * (d.n_samples - 1))] for d in train]
        spreads.append(np.linalg.norm(np.std(at, axis=0)))
    assert np.median(errors) <= 0.5 * np.median(spreads)


@settings(max_examples=30, deadline=None, derandomize=True)
@given(
    n=st.integers(5, 300),
    speed=st.floats(-3.0, 3.0),
    offset=st.floats(-1.0, 1.0),
)
def test_the_junction_leaves_at_the_prefix_velocity(n, speed, offset):
    # a path at rest at 0, a prefix moving along a line at ``speed`` from
    # ``offset``: the path never slows down and never accelerates, so both
    # the offset and the velocity offset fade over the whole rest; by hand,
    # (P_end + speed * s) * (1 - minimum_jerk(s / (1 - last)))
    tq = np.linspace(0.0, 1.0, 1001)
    X = np.zeros((tq.size, 1))
    P = offset + speed * tq[:n, None]
    out = continue_from(X, tq, Demonstration(tq[:n], P, ("p",), ("p",)), ("p",))
    np.testing.assert_array_equal(out[:n], P)
    last = tq[n - 1]
    s = tq - last
    ref = (P[-1, 0] + speed * s) * (1.0 - minimum_jerk(s / (1.0 - last)))
    np.testing.assert_allclose(out[n:, 0], ref[n:], atol=1e-12)
    leave = (out[n, 0] - out[n - 1, 0]) / (tq[1] - tq[0])
    # the offset's own fade adds about 10 * offset * (h / rest)^3 / h
    assert leave == pytest.approx(speed, abs=1e-4)


@settings(max_examples=30, deadline=None, derandomize=True)
@given(
    n=st.integers(902, 999),
    speed=st.floats(-3.0, 3.0),
    offset=st.floats(-1.0, 1.0),
)
def test_a_junction_near_the_end_keeps_what_it_cannot_fade(n, speed, offset):
    # as above, but less than JUNCTION_FADE (0.1) of the motion left: only
    # (rest / 0.1)^2 of the offset is faded over the rest, the remainder
    # kept to the end (before: all of it, an offset of 1 gone in 2 samples);
    # by hand, with the velocity offset still faded within the rest
    tq = np.linspace(0.0, 1.0, 1001)
    X = np.zeros((tq.size, 1))
    P = offset + speed * tq[:n, None]
    out = continue_from(X, tq, Demonstration(tq[:n], P, ("p",), ("p",)), ("p",))
    np.testing.assert_array_equal(out[:n], P)
    last = tq[n - 1]
    rest = 1.0 - last
    s = tq - last
    share = (rest / 0.1) ** 2
    ramp = 1.0 - minimum_jerk(s / rest)
    ref = P[-1, 0] * (1.0 - share) + (P[-1, 0] * share + speed * s) * ramp
    np.testing.assert_allclose(out[n:, 0], ref[n:], atol=1e-12)
    # the end: beside the path's, by the part kept; the offset's own fade
    # accelerates no more than fading it all over 0.1 would (5.774 / 0.1^2)
    assert out[-1, 0] == pytest.approx(P[-1, 0] * (1.0 - share), abs=1e-12)
    h = tq[1] - tq[0]
    faded = P[-1, 0] * share * ramp[n - 1 :]
    bend = np.abs(np.diff(faded, 2)).max() / h**2
    assert bend <= 5.774 * abs(P[-1, 0]) / 0.1**2 * 1.01 + 1e-9


def test_an_observed_prefix_as_minus_q_is_the_same_rotation():
    # a recorded stream may give -q for q: the path is the same rotations,
    # its first samples the observed ones as given, and it continues them
    # without a sign flip (before: a 176 degree turn in one step)
    from test_learner_generation import carries

    demos = carries()
    model = KeypointHMM().fit(demos)
    demo = demos[0]
    t = np.linspace(0.0, demo.t[-1], 201)
    tau = (demo.t - demo.t[0]) / demo.duration
    X = np.column_stack([np.interp(t[:80] / t[-1], tau, c) for c in demo.X.T])
    q = demo.columns_of("orientation")
    runs = []
    for s in (1.0, -1.0):
        Y = X.copy()
        Y[:, q] *= s
        prefix = Demonstration(t[:80], Y, demo.columns, demo.groups)
        path = model.generate(t, dense=True, observed=prefix)
        for g in ("position", "orientation"):
            np.testing.assert_array_equal(path.get(g)[:80], prefix.get(g))
        drawn = model.sample(t, 2, observed=prefix, random_state=3)
        runs.append([path, *drawn])
    q = runs[0][0].columns_of("orientation")
    other = np.setdiff1d(np.arange(runs[0][0].X.shape[1]), q)
    for plus, minus in zip(*runs, strict=True):
        np.testing.assert_array_equal(minus.X[:, q], -plus.X[:, q])
        np.testing.assert_array_equal(minus.X[:, other], plus.X[:, other])
        Q = minus.X[:, q]
        step = 2.0 * np.arccos(np.clip(np.sum(Q[1:] * Q[:-1], axis=1), -1.0, 1.0))
        assert np.degrees(step).max() < 1.0
