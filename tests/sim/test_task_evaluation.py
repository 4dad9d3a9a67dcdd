"""ndlfd evaluate --tasks end to end on a tiny cell (extra sim), and its
joint-space contextual ProMP on synthetic data (numpy only)."""

import csv
import importlib.util

import numpy as np
import pytest

from ndlfd.cli import main
from ndlfd.jobs._task_peers import ContextualProMP, rbf_basis
from ndlfd.jobs._tasks import TASK_METHODS, TaskResult, evaluate_tasks

_MISSING = [m for m in ("gym_aloha", "movement_primitives")
            if importlib.util.find_spec(m) is None]  # fmt: skip
needs_sim = pytest.mark.skipif(
    bool(_MISSING),
    reason="the simulated tasks need the extra sim and the ProMP peer the extra"
    ' eval: pip install "ndlfd[sim,eval]"',
)


def _linear_in_context(contexts, n=200):
    """Trajectories (k, n, 3): a fixed shape plus smooth gains times a 2-D context."""
    t = np.linspace(0.0, 1.0, n)
    shape = np.column_stack([np.sin(2 * np.pi * t), t**2, np.cos(np.pi * t)])
    gains = np.stack(
        [np.column_stack([t, np.sin(np.pi * t), 1 - t]),
         np.column_stack([t**2, 0.5 + 0 * t, t * np.cos(2 * np.pi * t)])],
        axis=2,
    )  # fmt: skip
    return shape[None] + np.einsum("ndc,kc->knd", gains, np.atleast_2d(contexts))


def test_contextual_promp_recovers_a_trajectory_linear_in_the_context():
    rng = np.random.default_rng(3)
    contexts = rng.uniform(-1.0, 1.0, (5, 2))
    model = ContextualProMP().fit(_linear_in_context(contexts), contexts)
    phi = rbf_basis(200, 25)
    for new in ([0.3, -0.7], [0.9, 0.9], [-1.2, 0.4], contexts[0]):
        true = _linear_in_context(new)[0]
        got = model.generate(new, 200)
        # the true path up to what 25 basis functions can draw (its ends),
        assert np.abs(got - true).max() < 0.03
        # and exactly its least-squares image on the basis: the weights are
        # linear in the path, so linear in the context
        best = phi @ np.linalg.lstsq(phi, true, rcond=None)[0]
        assert np.abs(got - best).max() < 1e-5
    # without context the mean of the demonstrations' images
    mean = ContextualProMP().fit(_linear_in_context(contexts), np.zeros((5, 0)))
    ref = (
        phi @ np.linalg.lstsq(phi, _linear_in_context(contexts).mean(0), rcond=None)[0]
    )
    assert np.abs(mean.generate([], 200) - ref).max() < 1e-6


def test_rbf_basis_is_movement_primitives_promps():
    promp = pytest.importorskip("movement_primitives.promp")
    for n, n_weights in ((50, 25), (333, 10)):
        model = promp.ProMP(n_dims=1, n_weights_per_dim=n_weights)
        ref = model._rbfs_nd_sequence(np.linspace(0.0, 1.0, n)).T
        assert np.allclose(rbf_basis(n, n_weights), ref, atol=1e-12)


def test_contextual_promp_drops_a_context_value_that_never_varies():
    rng = np.random.default_rng(4)
    contexts = rng.uniform(-1.0, 1.0, (5, 2))
    paths = _linear_in_context(contexts)
    # a third value constant over the demonstrations (as the cube's height):
    # its covariance is zero; it is dropped, and a new value of it is ignored
    with_height = np.column_stack([contexts, np.full(5, 0.05)])
    model = ContextualProMP().fit(paths, with_height)
    assert model.varying_.tolist() == [True, True, False]
    plain = ContextualProMP().fit(paths, contexts)
    new = [0.2, 0.6]
    assert np.allclose(model.generate([*new, 0.05], 150), plain.generate(new, 150))
    assert np.allclose(model.generate([*new, 0.3], 150), plain.generate(new, 150))
    # more context values than demonstrations span (3 demonstrations, 2
    # varying values plus a copy of one): well posed, still the true path
    three = np.column_stack([contexts[:3], contexts[:3, 0], np.full(3, 1.0)])
    model = ContextualProMP().fit(paths[:3], three)
    assert model.varying_.tolist() == [True, True, True, False]
    got = model.generate([*new, new[0], 1.0], 200)
    assert np.abs(got - _linear_in_context(new)[0]).max() < 0.03


@needs_sim
def test_evaluate_tasks_tiny_cell_through_the_cli(tmp_path, capsys):
    out = tmp_path / "te"
    argv = ["evaluate", "--tasks", "transfer-cube", "--demos", "2", "--episodes", "2"]
    assert main([*argv, "--no-plot", "-q", "--out", str(out)]) == 0
    with open(out / "results.csv") as fh:
        rows = list(csv.DictReader(fh))
    methods = [r["method"] for r in rows]
    # the expert once, then every method on the same two held-out poses
    assert methods == ["expert"] * 2 + [m for m in TASK_METHODS for _ in range(2)]
    poses = {r["objects"] for r in rows}
    assert len(poses) == 2
    for r in rows:
        assert (r["success"] == "True") == (int(r["max_reward"]) == 4)
        assert r["error"] == ""
    printed = capsys.readouterr().out
    assert "| transfer-cube | ndlfd-ee | 2 | 2 |" in printed
    assert (out / "summary.md").read_text().startswith("| task | method |")
    # the CSV reads back to the same table
    assert TaskResult.read_csv(out / "results.csv").to_markdown() in printed


@needs_sim
def test_evaluate_tasks_is_deterministic_and_checks_input():
    a = evaluate_tasks(["transfer-cube"], demos=[1], episodes=1, methods=["nearest"])
    b = evaluate_tasks(["transfer-cube"], demos=[1], episodes=1, methods=["nearest"])
    assert [(r.method, r.success, r.max_reward) for r in a.rows] == [
        (r.method, r.success, r.max_reward) for r in b.rows
    ]
    assert np.isclose(a.rows[-1].peak_velocity, b.rows[-1].peak_velocity)
    with pytest.raises(ValueError, match="method must be one of"):
        evaluate_tasks(["insertion"], demos=[1], episodes=1, methods=["act"])
    with pytest.raises(ValueError, match="at least 1"):
        evaluate_tasks(["insertion"], demos=[0], episodes=1)


@needs_sim
def test_evaluate_tasks_joint_space_peers_run():
    methods = ["promp-joint", "nearest-joint"]
    result = evaluate_tasks(["transfer-cube"], demos=[2], episodes=1, methods=methods)
    rows = [r for r in result.rows if r.method != "expert"]
    assert [r.method for r in rows] == methods
    for r in rows:
        assert r.error == ""
        assert r.success == (r.max_reward == 4)
        assert np.isfinite(r.peak_velocity) and r.peak_velocity > 0
    # the methods are listed after the end-effector ones, in the table too
    assert TASK_METHODS[-2:] == tuple(methods)
    table = result.to_markdown()
    assert "| transfer-cube | promp-joint | 2 | 1 |" in table
    assert "| transfer-cube | nearest-joint | 2 | 1 |" in table


@needs_sim
def test_a_tasks_episodes_do_not_depend_on_the_tasks_beside_it():
    kw = {"demos": [1], "episodes": 1, "methods": ["nearest"]}
    alone = evaluate_tasks(["insertion"], **kw).rows
    both = [r for r in evaluate_tasks(["transfer-cube", "insertion"], **kw).rows
            if r.task == "insertion"]  # fmt: skip
    assert [(r.method, r.objects, r.max_reward) for r in alone] == [
        (r.method, r.objects, r.max_reward) for r in both
    ]
