"""A via point's reading of the templates, chosen by leaving each out (_choice)."""

import numpy as np
import pytest

from ndlfd import Demonstration, KeypointHMM
from ndlfd.learner._choice import CLOCK_MARGIN, prefers_clock

TAU = np.linspace(0.0, 1.0, 200)


def _linear_task(a, b):
    """A path linear in a task parameter (a, b): a bump of height a, a stretch b."""
    return np.column_stack([TAU + b * TAU**2, a * np.sin(np.pi * TAU)])


def _templates(paths):
    """Equal timing: matched by place and by clock alike."""
    index = [np.array([0, 50, 100, 150, 199])] * len(paths)
    weights = np.ones(len(paths))
    knots = TAU[index[0]]
    return (list(paths), [TAU] * len(paths), index, weights, knots), index


def _observe(path, taus):
    """Observations of every column at phases (the obs_tau, observed pair)."""
    obs = [(k, [0, 1], np.array([np.interp(t, TAU, c) for c in path.T]))
           for k, t in enumerate(taus)]  # fmt: skip
    return np.array(taus), obs


@pytest.fixture(scope="module")
def linear_model():
    """A model of 10 demonstrations of the linear task, and their timing."""
    rng = np.random.default_rng(1)
    t = 4.0 * TAU
    demos = [
        Demonstration.from_arrays(t, position=_linear_task(*rng.uniform(-0.3, 0.3, 2)))
        for _ in range(10)
    ]
    return KeypointHMM(groups=("position",)).fit(demos), t


def test_a_task_parameter_is_read_on_the_clock_and_random_variation_by_place():
    rng = np.random.default_rng(0)
    linear = [_linear_task(*rng.uniform(-0.3, 0.3, 2)) for _ in range(8)]
    # the same base with smooth random wiggles: nothing the points predict
    wiggly = []
    for _ in range(8):
        c = rng.normal(0, 0.05, (6, 2))
        bumps = sum(np.outer(np.sin((k + 1) * np.pi * TAU), c[k]) for k in range(6))
        wiggly.append(_linear_task(0.0, 0.0) + bumps)
    for paths, want in ((linear, True), (wiggly, False)):
        templates, index = _templates(paths)
        held = _linear_task(0.1, -0.2) if want else wiggly[0] + 0.01
        obs_tau, observed = _observe(held, [0.0, 0.5, 1.0])
        got = prefers_clock(templates, index, templates, obs_tau, observed, [0, 1])
        assert got is want


def test_fewer_than_three_templates_leave_nothing_to_choose_by():
    templates, index = _templates([_linear_task(0.1, 0.0), _linear_task(0.2, 0.1)])
    obs_tau, observed = _observe(_linear_task(0.15, 0.05), [0.5])
    got = prefers_clock(templates, index, templates, obs_tau, observed, [0, 1])
    assert got is False
    assert 0.0 < CLOCK_MARGIN < 1.0


def test_a_via_point_of_a_linear_task_recovers_the_held_out_path(linear_model):
    # the demonstrations differ only by (a, b), which the via point and the
    # goal show: the path through them is the held-out one (as ProMP's
    # conditional gives it), not a shifted average
    model, t = linear_model
    for a, b in ((0.25, -0.2), (-0.1, 0.28)):
        P = _linear_task(a, b)
        via = [(t[100], {"position": P[100]})]
        path = model.generate(t, dense=True, via=via, goal={"position": P[-1]})
        err = np.linalg.norm(path.get("position") - P, axis=1).max()
        assert err < 0.01 * np.ptp(P, axis=0).max(), (a, b, err)
    # a plain shift of the unconditioned path through the via point is not
    plain = model.generate(t, dense=True).get("position")
    shifted = plain + (P[100] - plain[100])
    assert np.linalg.norm(shifted - P, axis=1).max() > 0.05 * np.ptp(P, axis=0).max()


def test_samples_through_the_via_point_of_a_linear_task_are_read_as_generate_reads(
    linear_model,
):
    model, t = linear_model
    P = _linear_task(0.25, -0.2)
    kw = {"via": [(t[100], {"position": P[100]})], "goal": {"position": P[-1]}}
    paths = model.sample(t, 20, dense=True, random_state=0, **kw)
    errs = [np.linalg.norm(p.get("position") - P, axis=1).max() for p in paths]
    # every draw follows the points as the task does (the place reading's
    # samples, weighted by their distance to the via point, missed by up to
    # 13 % of the range)
    assert max(errs) < 0.015 * np.ptp(P, axis=0).max(), max(errs)
