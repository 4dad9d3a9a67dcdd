"""Tests of the built-in ``ndlfd demo`` job (``ndlfd.jobs.demo``)."""

from __future__ import annotations

import re

import pytest

from ndlfd import synth
from ndlfd.io import write_csv
from ndlfd.jobs.demo import DEMO_SETTINGS, WARM_UP_DEMOS, run_demo
from ndlfd.learner import KeypointHMM


@pytest.fixture(scope="module")
def quick_demo(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo")
    lines = []
    summary = run_demo(out, quick=True, plot=False, echo=lines.append)
    return out, summary, lines


def test_the_warm_up_is_reported_apart_from_the_timings(quick_demo):
    """Kernel compilation is a one-time warm-up, printed on its own line."""
    _, summary, lines = quick_demo
    assert re.fullmatch(
        r"warm-up \d+\.\d s: one-time start-up \(compiling the kernels, .*\), not"
        r" in the fit and generate times below",
        lines[0],
    )
    # the warm-up comes before every timed line
    timed = [i for i, line in enumerate(lines) if " ms, generate " in line]
    assert timed and min(timed) > 0
    for row in summary.values():
        assert row["warm_up_s"] > 0 and row["fit_s"] > 0 and row["generate_s"] > 0


def test_the_warm_up_does_not_change_the_results(quick_demo, tmp_path):
    """The timed run after a warm-up writes what a run without one would."""
    out, summary, _ = quick_demo
    train, test = synth.make_dataset("square", n_demos=20, random_state=0)
    assert WARM_UP_DEMOS < len(train)
    dense = (
        KeypointHMM(**DEMO_SETTINGS["square"]).fit(train).generate(test.t, dense=True)
    )
    write_csv(dense, tmp_path / "alone.csv")
    written = (out / "square_generated_dense.csv").read_bytes()
    assert written == (tmp_path / "alone.csv").read_bytes()
    assert summary["square"]["n_demos"] == 20
