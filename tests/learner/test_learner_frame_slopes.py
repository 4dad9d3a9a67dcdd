"""The slopes on the frames (learner/_frame_slopes.py): known answers."""

import numpy as np
import pytest

from hands_data import forward, planar_arm, planar_target
from ndlfd import KeypointHMM
from ndlfd.learner._frame_slopes import (
    fit_slopes,
    frame_slopes,
    quadratic_features,
)


def _moved(Y, fit, f_new):
    """Every template moved to the new frames (what the mixer does)."""
    return Y - np.tensordot(fit.dz(f_new), fit.B, axes=1)


def _data(n, curve, seed=0):
    """Templates (n, 4 rows, 2 columns) exactly a function of 2-D frames."""
    rng = np.random.default_rng(seed)
    F = rng.uniform(-1.0, 1.0, size=(n, 2))
    rows = np.array([0.0, 1.0, 2.0, 3.0])

    def value(f):
        lin = 0.3 + 2.0 * f[0] - f[1]
        return np.stack([(lin + curve * f[0] * f[1]) * (1 + rows)] * 2, axis=-1)

    return F, np.array([value(f) for f in F]), value


def test_an_exact_linear_relation_is_recovered():
    F, Y, value = _data(10, curve=0.0)
    f_new = np.array([0.4, -0.7])
    w = np.full(10, 0.1)
    fit, loo = fit_slopes(Y, w, F, [0, 1])
    # every template moved lands on the value at the new frames
    want = np.broadcast_to(value(f_new), Y.shape)
    np.testing.assert_allclose(_moved(Y, fit, f_new), want, rtol=5e-3)
    assert loo < 1e-3


@pytest.mark.parametrize("n", [3, 4])
def test_few_templates_shrink_a_hand_not_a_joint_space_model(n):
    """2 features: a hand's rule shrinks below 2 * 2 + 2 = 6 templates, a
    joint-space model's (1 per feature plus the intercept) from 3 on fits."""
    F, Y, value = _data(n, curve=0.0, seed=3)
    f_new = np.array([0.9, 0.9])
    w = np.full(n, 1.0 / n)
    want = value(f_new)
    fit, _ = fit_slopes(Y, w, F, [0, 1], few=1, spare=1)
    np.testing.assert_allclose(_moved(Y, fit, f_new)[0], want, rtol=2e-2)
    fit, _ = fit_slopes(Y, w, F, [0, 1])  # a hand's rule: ridge 1
    assert np.abs(_moved(Y, fit, f_new)[0] - want).max() > 0.1


@pytest.mark.parametrize("n, exact", [(12, True), (11, False)])
def test_a_curved_relation_is_taken_with_enough_templates(n, exact):
    """Squares and products (5 features) need 2 * 5 + 2 = 12 templates."""
    F, Y, value = _data(n, curve=1.5, seed=5)
    f_new = np.array([0.8, -0.8])
    w = np.full(n, 1.0 / n)
    F2, f2 = quadratic_features(F, f_new)
    fit = frame_slopes(Y, w, [F], [0, 1], curved=F2)
    assert (fit.which == -1) == exact  # the squares, or the only candidate
    f = f2 if fit.which == -1 else f_new
    err = np.abs(_moved(Y, fit, f) - value(f_new)).max()
    assert (err < 2e-2) == exact


def test_a_joint_space_model_from_few_demonstrations():
    """The planar arm (reach 1 m) from 5 and 12 demonstrations: the end's error.

    Measured: median / largest 4.2 / 16.5 mm from 5 (66 / 107 with the
    hands' shrinkage), 0.6 / 2.6 mm from 12 (6.5 / 13.0 without the squares).
    """
    for n, bound in ((5, 0.025), (12, 0.005)):
        demos, _ = planar_arm(n, seed=2)
        model = KeypointHMM().fit(demos)
        rng = np.random.default_rng(11)
        for _ in range(8):
            p = planar_target(rng)
            path = model.generate(demos[0].t, dense=True, frames={"target": p})
            assert np.linalg.norm(forward(path.get("joints")[-1]) - p) < bound
