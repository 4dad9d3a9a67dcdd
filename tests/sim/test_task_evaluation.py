"""ndlfd evaluate --tasks end to end on a tiny cell (extra sim)."""

import csv

import numpy as np
import pytest

pytest.importorskip(
    "gym_aloha",
    reason='the simulated tasks need the extra sim: pip install "ndlfd[sim]"',
)
pytest.importorskip(
    "movement_primitives",
    reason='the ProMP peer needs the extra eval: pip install "ndlfd[eval]"',
)

from ndlfd.cli import main
from ndlfd.jobs._tasks import TASK_METHODS, TaskResult, evaluate_tasks


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
