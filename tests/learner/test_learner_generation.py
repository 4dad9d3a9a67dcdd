"""Generation: the blend, conditioning on a start and goal, the band."""

import numpy as np
import pytest

from learner_helpers import (
    reaches,
    resample,
    tight_starts,
    two_routes,
    waves,
)
from ndlfd import (
    ValidationError,
    synth,
)
from ndlfd.demonstration import Demonstration
from ndlfd.learner import KeypointHMM, minimum_jerk
from ndlfd.metrics import dtw_distance


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
    demos = two_routes()
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


def test_band_is_the_spread_of_the_route_s_aligned_templates():
    # the reference: each template of the followed route warped by hand
    # (np.interp of its values at its matched times, on the smoothed warp
    # tested in test_learner_blend), their weighted std
    from ndlfd.learner._blend import smooth_warp
    from ndlfd.learner._generation import make_plan

    demos = two_routes(per_route=3)
    model = KeypointHMM(groups=("position",), epsilon=0.01, n_time_bins=10)
    model.fit(demos)
    t = np.linspace(0.0, 2.0, 41)
    _, std = model.generate(t, dense=True, return_std=True)
    assert std.shape == (41, 2)
    plan = make_plan(model, t, None, None, model._cache)
    tq = (t - t[0]) / (t[-1] - t[0])
    W = []
    for U, tau, idx in zip(plan.values, plan.taus, plan.index, strict=True):
        at = smooth_warp(tq, plan.knots, tau[idx])
        W.append(np.column_stack([np.interp(at, tau, c) for c in U.T]))
    W = np.array(W)
    w = plan.weights / plan.weights.sum()
    mean = np.einsum("j,jnd->nd", w, W)
    sd = np.sqrt(np.einsum("j,jnd->nd", w, (W - mean) ** 2))
    want = sd * (model.scaler_.data_max_ - model.scaler_.data_min_)
    np.testing.assert_allclose(std, want, rtol=1e-9, atol=1e-12)
    # the route's three demonstrations differ everywhere: a real spread at
    # every sample, small against the distance between the routes (2 in y)
    assert np.all(std > 0)
    assert std[:, 1].max() < 0.1
    # key points only: the band at the key points
    keys, kstd = model.generate(t, return_std=True)
    assert kstd.shape == (keys.n_samples, 2) and np.all(kstd > 0)
    with pytest.raises(ValidationError, match="return_std"):
        model.set_params(generation="paper").generate(t, return_std=True)


def test_band_of_one_demonstration_is_zero_and_of_identical_ones_too():
    demos = two_routes(per_route=1)[:1]
    model = KeypointHMM(groups=("position",), epsilon=0.01, n_time_bins=10)
    _, std = model.fit(demos).generate(np.linspace(0, 2, 30), return_std=True,
                                       dense=True)  # fmt: skip
    np.testing.assert_array_equal(std, 0.0)


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


def test_a_reach_with_orientation_is_smooth_not_a_staircase():
    # defaults on a 3-D reach: orientation learned (not dropped), no standing
    # still, the demonstrations' speed, a start among theirs, unit quaternions
    demos = reaches()
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
    held_out = resample(demos[0], grid)
    mean = np.mean([resample(d, grid) for d in demos[1:]], axis=0)
    err = np.linalg.norm(P - held_out, axis=1).mean()
    assert err < 1.1 * np.linalg.norm(mean - held_out, axis=1).mean()


def test_a_refit_forgets_the_conditioning_widths_of_the_last_fit():
    a = [Demonstration.from_arrays(t, position=P) for t, P in waves(10, seed=1)]
    b = [Demonstration.from_arrays(t, position=3 * P) for t, P in waves(10, seed=2)]
    kw = dict(epsilon=0.02, n_time_bins=20)
    start = {"position": [0.0, 0.1]}
    t = np.linspace(0.0, 2.0, 50)
    model = KeypointHMM(**kw).fit(a)
    model.generate(t, dense=True, start=start)  # widths of a, kept
    model.fit(b)
    got = model.generate(t, dense=True, start=start)
    fresh = KeypointHMM(**kw).fit(b).generate(t, dense=True, start=start)
    np.testing.assert_array_equal(got.X, fresh.X)


@pytest.mark.parametrize("offset", [0.02, 0.5, 30.0])
@pytest.mark.filterwarnings("ignore::ndlfd.ExtrapolationWarning")  # far on purpose
def test_a_start_nearest_to_a_demonstration_that_is_no_template(offset):
    # the kernel weight of every kept template underflows to 0 when the start
    # lies beyond a demonstration that is not among them: a path all the same
    demos = tight_starts()
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


@pytest.mark.parametrize("pseudo_emission", [0.0, 0.5])
def test_timing_keeps_every_bin_the_model_can_emit(pseudo_emission):
    # few key points in many bins: most bins are unseen in training. Without
    # an emission pseudo-count they cannot be emitted and are dropped; with
    # one every bin can be, and each bin the timing touches is an observation
    demos = two_routes(per_route=2)
    nt = 40
    model = KeypointHMM(epsilon=0.2, n_time_bins=nt, pseudo_emission=pseudo_emission)
    model.fit(demos)
    seen = set()
    for d, kp in zip(demos, model.keypoints_, strict=True):
        tau = (d.t - d.t[0]) / (d.t[-1] - d.t[0])
        seen |= set(np.minimum(np.floor(tau[kp] * nt), nt - 1).astype(int).tolist())
    assert 0 < len(seen) < nt  # the case this test is about
    t = np.linspace(0.0, 3.0, 301)
    touched = np.minimum(np.floor((t - t[0]) / (t[-1] - t[0]) * nt), nt - 1)
    expected = sorted(set(touched.astype(int).tolist()))
    if pseudo_emission == 0:
        expected = [b for b in expected if b in seen]
    key_t, symbols, all_t = model.timing(t)
    np.testing.assert_array_equal(symbols, expected)
    # each observation at the first time stamp of its bin
    np.testing.assert_array_equal(key_t, [t[np.argmax(touched == b)] for b in expected])
    np.testing.assert_array_equal(all_t, t)


def _picks(n_demos=8, seed=4):
    """3-D pick-and-place: reach the grasp, stop there, carry over to the place."""
    rng = np.random.default_rng(seed)
    start, grasp, place = np.array([0, 0, 0.2]), np.array([0.4, 0, 0]), [0.4, 0.5, 0]
    demos = []
    for _ in range(n_demos):
        tau = np.linspace(0.0, 1.0, 200)
        a = minimum_jerk(np.clip(tau / 0.3, 0, 1))[:, None]
        b = minimum_jerk(np.clip((tau - 0.4) / 0.6, 0, 1))[:, None]
        P = start + a * (grasp - start) + b * (np.asarray(place) - grasp)
        P[:, 2] += 0.15 * np.sin(np.pi * b[:, 0])  # lift while carrying
        P += rng.normal(0, 0.003, 3)  # each demonstration a little apart
        t = 4.0 * tau * rng.uniform(0.97, 1.03)
        demos.append(Demonstration.from_arrays(t, position=P))
    return demos, grasp


@pytest.mark.filterwarnings("ignore::ndlfd.ExtrapolationWarning")  # far on purpose
def test_a_start_offset_is_gone_by_the_grasp():
    demos, grasp = _picks()
    model = KeypointHMM().fit(demos)
    t = np.linspace(0.0, 4.0, 200)
    here = {"position": [0.0, -0.10, 0.15]}  # 10 cm right and 5 cm low
    path = model.generate(t, dense=True, start=here).get("position")
    np.testing.assert_allclose(path[0], here["position"], atol=1e-12)
    at_grasp = path[np.argmin(np.linalg.norm(path - grasp, axis=1))]
    # at the grasp (the demonstrations stop there for 10 % of the motion) the
    # hand is where they grasp, not shifted by the start's offset
    assert np.linalg.norm(at_grasp - grasp) < 0.01
    stay = path[(t >= 0.31 * 4.0) & (t <= 0.39 * 4.0)]
    assert np.linalg.norm(stay - grasp, axis=1).max() < 0.01
    # the same with a goal off the demonstrations' place: the grasp is kept
    there = {"position": [0.45, 0.55, 0.02]}
    path = model.generate(t, dense=True, start=here, goal=there).get("position")
    np.testing.assert_allclose(path[-1], there["position"], atol=1e-12)
    stay = path[(t >= 0.31 * 4.0) & (t <= 0.39 * 4.0)]
    assert np.linalg.norm(stay - grasp, axis=1).max() < 0.01


def test_a_two_valued_gripper_stays_two_valued_and_switches_on_time():
    # the gripper closes at 35 % of each demonstration (+- 3 %): learned by
    # default, generated as 0 or 1 only, closing at the demonstrations' median
    rng = np.random.default_rng(5)
    demos, switches = [], []
    for _ in range(9):
        tau = np.linspace(0.0, 1.0, 150)
        at = 0.35 + rng.uniform(-0.03, 0.03)
        P = np.column_stack([tau, np.sin(2 * tau)]) + rng.normal(0, 0.002, 2)
        grip = (tau >= at).astype(float)
        switches.append(tau[np.argmax(grip > 0)])
        demos.append((tau, P, grip))
    demos_of = lambda scale: [  # noqa: E731
        Demonstration.from_arrays(3.0 * tau, position=P, gripper=scale * grip)
        for tau, P, grip in demos
    ]
    model = KeypointHMM().fit(demos_of(1.0))
    assert model.groups_ == ("position", "velocity", "gripper")
    t = np.linspace(0.0, 3.0, 300)
    g = model.generate(t, dense=True).get("gripper")[:, 0]
    assert set(np.unique(g)) == {0.0, 1.0}
    closes = t[np.argmax(g > 0.5)] / 3.0
    assert np.all(g[t / 3.0 >= closes] == 1.0)  # one switch
    assert abs(closes - np.median(switches)) <= 0.02
    # a gripper of recorded positions (two values, not 0/1) keeps them
    g = KeypointHMM().fit(demos_of(0.085)).generate(t, dense=True).get("gripper")
    g = g[:, 0]
    assert set(np.unique(g)) == {0.0, 0.085}


def carries(n_demos=6, seed=0, noise=2e-3):
    """3-D carries turning about z, the gripper closing half way."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n_demos):
        s = np.linspace(0.0, 1.0, 150)
        P = np.column_stack([0.5 * s, 0.1 * np.sin(np.pi * s), 0.3 - 0.2 * s])
        half = 0.25 * s + rng.normal(0.0, 5 * noise)
        Q = np.column_stack([np.cos(half), 0 * s, 0 * s, np.sin(half)])
        t = 4.0 * s * rng.uniform(0.95, 1.05)
        P = P + rng.normal(0.0, noise, P.shape)
        grip = (s > 0.5) * 1.0
        out.append(
            Demonstration.from_arrays(t, position=P, orientation=Q, gripper=grip)
        )
    return out


@pytest.mark.parametrize("generation", ["blend", "paper"])
@pytest.mark.filterwarnings("ignore::ndlfd.ExtrapolationWarning")  # far on purpose
def test_a_start_orientation_and_gripper_keep_the_path_valid(generation):
    # a requested orientation is pinned as a unit quaternion, -q as q (one
    # rotation); a requested gripper value leaves the gripper on its two values
    model = KeypointHMM(generation=generation).fit(carries())
    t = np.linspace(0.0, 4.0, 200)
    q = np.array([np.cos(0.2), 0.0, 0.0, np.sin(0.2)])
    goal = {"orientation": [2.0, 0.0, 0.0, 0.0]}
    paths = [
        model.generate(
            t, dense=True, goal=goal, start={"orientation": s * q, "gripper": [1.0]}
        )
        for s in (1.0, -1.0, -3.0)
    ]
    np.testing.assert_array_equal(paths[0].X, paths[1].X)
    np.testing.assert_allclose(paths[0].X, paths[2].X, rtol=1e-12, atol=1e-12)
    Q = paths[0].get("orientation")
    np.testing.assert_allclose(np.linalg.norm(Q, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(Q[0], q, atol=1e-12)
    np.testing.assert_allclose(Q[-1], [1.0, 0.0, 0.0, 0.0], atol=1e-12)
    if generation == "blend":
        grip = paths[0].get("gripper")[:, 0]
        assert grip[0] == 1.0 and set(np.unique(grip)) <= {0.0, 1.0}
    with pytest.raises(ValidationError, match="non-zero norm"):
        model.generate(t, start={"orientation": [0.0, 0.0, 0.0, 0.0]})


def test_a_start_offset_is_gone_when_the_gripper_closes():
    # the carries never slow down before the gripper closes (half way): the
    # offset to a start 5 cm off is faded out by the last sample before the
    # switch, so the hand closes where the unconditioned path does; the
    # goal's offset comes in after the switch. The demonstrations are one
    # carry at different speeds, so any blend of them is that carry.
    model = KeypointHMM().fit(carries(noise=0.0))
    t = np.linspace(0.0, 4.0, 400)
    plain = model.generate(t, dense=True)
    here = plain.get("position")[0] + [0.05, -0.05, 0.0]
    there = plain.get("position")[-1] + [0.0, 0.05, 0.05]
    path = model.generate(t, dense=True, start={"position": here},
                          goal={"position": there})  # fmt: skip
    grip = path.get("gripper")[:, 0]
    np.testing.assert_array_equal(grip, plain.get("gripper")[:, 0])
    close = int(np.flatnonzero(np.diff(grip))[0])  # the last row before it
    P, Q = path.get("position"), plain.get("position")
    np.testing.assert_allclose(P[0], here)
    np.testing.assert_allclose(P[close : close + 2], Q[close : close + 2], atol=1e-12)
    assert np.linalg.norm(P[close // 2] - Q[close // 2]) > 0.01  # faded, not cut
    np.testing.assert_allclose(P[-1], there, atol=1e-12)


def test_a_prefix_offset_is_gone_when_the_gripper_closes():
    # as for a start: the junction's offset is faded out before the switch
    model = KeypointHMM().fit(carries(noise=0.0))
    t = np.linspace(0.0, 4.0, 400)
    plain = model.generate(t, dense=True)
    X = plain.X[:80].copy()
    X[:, :3] += [0.03, 0.0, -0.03]  # executed 3 cm off the demonstrations
    prefix = Demonstration(t[:80], X, plain.columns, plain.groups)
    path = model.generate(t, observed=prefix)
    grip = path.get("gripper")[:, 0]
    np.testing.assert_array_equal(grip, plain.get("gripper")[:, 0])
    close = int(np.flatnonzero(np.diff(grip))[0])
    P, Q = path.get("position"), plain.get("position")
    np.testing.assert_array_equal(P[:80], X[:, :3])
    np.testing.assert_allclose(P[close : close + 2], Q[close : close + 2], atol=1e-12)
    assert np.linalg.norm(P[(80 + close) // 2] - Q[(80 + close) // 2]) > 0.005


@pytest.mark.parametrize("generation", ["blend", "paper"])
@pytest.mark.parametrize("weight", [0.5, 2.0])
def test_a_weighted_group_comes_out_in_its_own_units(generation, weight):
    # group weights scale the normalized values for the reduction only: the
    # path is read back unweighted (a position weighted 2 came out at half its
    # size about its minimum, one weighted 0.5 at twice it)
    train, test = synth.make_dataset("square", n_demos=8, random_state=1)
    plain = KeypointHMM(generation=generation).fit(train)
    weighted = KeypointHMM(weights={"position": weight}, generation=generation)
    weighted.fit(train)
    P = np.concatenate([d.get("position") for d in train])
    lo, hi = P.min(axis=0), P.max(axis=0)
    spans = []
    for m in (plain, weighted):
        path = m.generate(test, dense=True).get("position")
        assert np.all(path >= lo - 1e-9) and np.all(path <= hi + 1e-9)
        spans.append(np.ptp(path, axis=0))
    ratio = spans[1] / spans[0]  # other key points, the same square's size
    assert np.all((ratio > 0.85) & (ratio < 1.15)), (weight, ratio)
    if generation == "blend":
        start, goal = test.get("position")[[0, -1]]
        path = weighted.generate(test.t, dense=True, start={"position": start},
                                 goal={"position": goal}).get("position")  # fmt: skip
        np.testing.assert_allclose(path[[0, -1]], [start, goal], atol=1e-9)
