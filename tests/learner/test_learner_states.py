"""States for any number of channels (issue 37): visited cells, interned.

A real robot log (a Franka export: position, orientation, force, torque, 7
joints, a gripper) has far more possible codebook cells than ``int64`` can
number (27 columns at 10-20 levels: about 1e30). A state is a visited cell,
interned in lexicographic order, so such a model fits and generates at its
default levels; and where the paper's mixed-radix numbers fit, every result
is the one they gave (the ids are their ranks: see test_learner_identity).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from ndlfd import Codebook, KeypointHMM, hmm
from ndlfd.demonstration import Demonstration
from ndlfd.learner._spec import DemoSpec


def _robot_log(k: int, n: int = 160, seed: int = 0) -> Demonstration:
    """One reach of a 7-joint arm logged whole (21 columns, 24 with velocity)."""
    rng = np.random.default_rng(seed + k)
    t = np.arange(n) / 20.0  # a fixed-rate log, 20 Hz
    s = 0.5 - 0.5 * np.cos(np.pi * np.linspace(0, 1, n))  # rest to rest
    start = np.array([0.4, -0.2, 0.3]) + rng.normal(0, 0.01, 3)
    goal = np.array([0.7, 0.25, 0.1]) + rng.normal(0, 0.01, 3)
    position = start + s[:, None] * (goal - start)
    turn = Rotation.from_rotvec(np.outer(s, [0.0, 0.0, 0.8 + 0.05 * rng.normal()]))
    quat = (turn * Rotation.from_euler("x", np.pi)).as_quat(scalar_first=True)
    contact = np.clip((s - 0.8) / 0.2, 0, 1)
    force = np.column_stack([0.2 * contact, -0.1 * contact, 5.0 * contact])
    force += rng.normal(0, 0.05, force.shape)
    torque = np.column_stack([0.02 * contact, 0.01 * contact, -0.03 * contact])
    joints = np.linspace(
        [0, -0.8, 0, -2.3, 0, 1.6, 0.8], [0.6, -0.2, 0.1, -1.7, 0.1, 1.9, 1.4], n
    )
    joints = joints + rng.normal(0, 0.002, joints.shape)
    gripper = (s > 0.9).astype(float)
    return Demonstration.from_arrays(
        t, position=position, orientation=quat, force=force, torque=torque,
        joints=joints, gripper=gripper,
    )  # fmt: skip


@pytest.fixture(scope="module")
def logs():
    return [_robot_log(k) for k in range(5)]


def test_a_whole_robot_log_fits_and_generates_at_default_levels(logs):
    model = KeypointHMM().fit(logs)
    assert set(model.groups_) == {
        "position", "velocity", "orientation", "force", "torque", "joints", "gripper",
    }  # fmt: skip
    cb = model.codebook_
    assert cb.n_dims == 24 and not cb.fits_int64  # 20**10 * 10**13 * 2 cells
    assert cb.n_states == 20**10 * 10**13 * 2
    # states: the visited cells, ids 0..n-1 in lexicographic order, in range
    cells = model.centroid_cells_
    assert cells.shape == (model.n_states_used_, 24)
    assert np.all(cells >= 0) and np.all(cells < np.array(cb.levels))
    rows = [tuple(r) for r in cells.tolist()]
    assert rows == sorted(set(rows))
    # each key point's state is the cell its normalized value falls in
    spec = DemoSpec.of_model(model)
    keys, ids, _ = model.fit_stats_.keypoint_lists()
    for demo, k, i in zip(logs, keys, ids, strict=True):
        u = spec.reduce(spec.prepared(demo)).values[k]
        np.testing.assert_array_equal(cells[i], cb.cells(u))
    # the HMM's pseudo-count is 1 / (number of possible cells), of any size
    assert model.model_.n_states == cb.n_states
    assert model.model_.pseudo_transition_ == 1.0 / cb.n_states
    path = model.generate(logs[0].t, dense=True)
    assert path.X.shape == (logs[0].n_samples, 24) and np.all(np.isfinite(path.X))
    quat = path.get("orientation")
    np.testing.assert_allclose(np.linalg.norm(quat, axis=1), 1.0, atol=1e-9)
    goal = model.generate(logs[0].t, dense=True, goal={"position": [0.72, 0.26, 0.1]})
    np.testing.assert_allclose(goal.get("position")[-1], [0.72, 0.26, 0.1], atol=1e-9)
    paper = KeypointHMM(generation="paper").fit(logs).generate(logs[1])
    assert np.all(np.isfinite(paper.X))


def test_the_same_log_saves_loads_and_merges_the_same(logs, tmp_path):
    model = KeypointHMM(n_jobs=2).fit(logs)
    model.save(tmp_path / "log.ndlfd")
    again = KeypointHMM.load(tmp_path / "log.ndlfd")
    assert again.fit_stats_ == model.fit_stats_
    t = np.linspace(0.0, 7.0, 90)
    np.testing.assert_array_equal(again.generate(t).X, model.generate(t).X)
    # statistics merged from parts (a Dask fit's reduce) intern alike
    serial = KeypointHMM(n_jobs=1).fit(logs)
    assert serial.fit_stats_ == model.fit_stats_
    np.testing.assert_array_equal(serial.generate(t).X, model.generate(t).X)


def test_interned_model_equals_the_mixed_radix_model_where_it_fits(logs):
    # position and velocity at 20/10 levels (8e6 cells): the paper's numbers
    # fit, and an HMM estimated on them decodes to the very same cells
    groups = ("position", "velocity")
    model = KeypointHMM(groups=groups).fit(logs)
    cb = model.codebook_
    assert cb.fits_int64
    numbers = cb.from_levels(model.centroid_cells_)
    _, ids, bins = model.fit_stats_.keypoint_lists()
    by_number = hmm.estimate([numbers[i] for i in ids], list(bins), cb.n_states,
                             model.n_time_bins)  # fmt: skip
    np.testing.assert_array_equal(by_number.states_, numbers)
    symbols = bins[0]  # the first demonstration's key-point bins
    a, la = hmm.viterbi(model.model_, symbols)
    b, lb = hmm.viterbi(by_number, symbols)
    np.testing.assert_array_equal(numbers[a], b)
    assert la == lb


def test_a_big_hmm_saves_and_loads_its_n_states(tmp_path):
    m = 20**10 * 10**16 * 2
    model = hmm.estimate([[0, 3, 3, 7]], [[0, 1, 1, 2]], m, 3)
    model.save(tmp_path / "big.npz")
    again = hmm.DiscreteHMM.load(tmp_path / "big.npz")
    assert again.n_states == m and again.pseudo_transition_ == 1.0 / m
    (a, la), (b, lb) = hmm.viterbi(again, [0, 1, 2]), hmm.viterbi(model, [0, 1, 2])
    np.testing.assert_array_equal(a, [0, 3, 7])
    np.testing.assert_array_equal(a, b)
    assert la == lb
    codebook = Codebook([20] * 10 + [10] * 16 + [2])
    assert codebook.n_states == m
