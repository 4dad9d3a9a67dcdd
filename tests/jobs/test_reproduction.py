"""Tests of ``ndlfd reproduce``: the paper's qualitative results and the outputs."""

from __future__ import annotations

import os
import pkgutil
import re
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ndlfd import synth
from ndlfd._errors import OptionError, ValidationError
from ndlfd.demonstration import Demonstration
from ndlfd.dp import simplify
from ndlfd.jobs._reproduction_report import sentences
from ndlfd.jobs._reproduction_runs import CHANNELS, DISTANCES, first_split
from ndlfd.jobs.reproduction import (
    PAPER,
    ReproductionSettings,
    fig2_normalization,
    fig3_channels,
    fig5_learning,
    fig6_levels,
    fig6_noise_sweep,
    reproduce,
)

S = ReproductionSettings()
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def square_data():
    """The Fig. 5/6 square dataset at the real parameters (100 demonstrations)."""
    return synth.make_dataset(
        "square",
        n_demos=S.n_demos,
        noise=S.noise,
        test_noise=S.test_noise,
        random_state=S.seed,
    )


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("repro")
    lines = []
    res = reproduce(out, quick=True, echo=lines.append)
    return out, res, lines


# ------------------------------------------------------------------ Fig. 2
def test_fig2_proportions_match_hand_computed_ranges():
    demo = synth.spiral()
    P = demo.get("position")
    raw = P.max(axis=0) - P.min(axis=0)
    r = fig2_normalization(demo, epsilon=S.fig2_epsilon)
    # none: the raw ranges; group: one divisor for all three; per-dimension: 1:1:1
    np.testing.assert_allclose(r["none"]["ranges"], raw, rtol=1e-12)
    np.testing.assert_allclose(
        r["group"]["ranges"], raw / (P.max() - P.min()), rtol=1e-12
    )
    np.testing.assert_allclose(r["per-dimension"]["ranges"], 1.0, rtol=1e-12)
    np.testing.assert_allclose(
        r["group"]["proportions"], r["none"]["proportions"], rtol=1e-12
    )
    # the paper's spiral: X spans 20, Y and Z span 10 → 1 : 0.5 : 0.5
    np.testing.assert_allclose(r["group"]["proportions"], [1, 0.5, 0.5], atol=0.02)
    for mode in r:
        k = r[mode]["keypoints"]
        assert k[0] == 0 and k[-1] == demo.n_samples - 1
        assert r[mode]["n_keypoints"] == k.size


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(3, 25),
    d=st.integers(2, 6),
    seed=st.integers(0, 2**32 - 1),
    closed=st.booleans(),
)
def test_first_split_agrees_with_the_kernels(n, d, seed, closed):
    """The numpy-det reference decides the first split like the compiled kernels."""
    U = np.random.default_rng(seed).normal(size=(n, d))
    if closed:  # coincident endpoints: distance to P_1 (paper eq. 4)
        U[-1] = U[0]
        far = np.linalg.norm(U[1:-1] - U[0], axis=1).max()
        assert first_split(U) == {"line": far, "paper": far}
    split = first_split(U)
    if d == 2:  # the determinant formula is exact in 2-D
        assert split["paper"] == pytest.approx(split["line"], rel=1e-9, abs=1e-12)
    for distance in DISTANCES:
        v = split[distance]
        assert simplify(U, 1.001 * v + 1e-12, distance=distance).size == 2
        if v > 1e-9:
            assert simplify(U, 0.999 * v, distance=distance).size > 2


def test_fig2_paper_distance_collapses_on_the_spiral():
    r = fig2_normalization(synth.spiral(), epsilon=S.fig2_epsilon, distance="paper")
    for m in r:
        assert r[m]["n_keypoints"] == 2
        assert r[m]["first_split"]["paper"] < 1e-12 < r[m]["first_split"]["line"]
        np.testing.assert_allclose(r[m]["chord"][1:], 0, atol=1e-12)


def test_fig2_needs_velocity():
    d = synth.spiral().select("position")
    with pytest.raises(ValidationError, match="velocity"):
        fig2_normalization(d)


# ------------------------------------------------------------------ Fig. 3
def test_fig3_order_at_the_reported_epsilon():
    r = fig3_channels(synth.curve(), epsilon=S.fig3_epsilon)
    n = {c: r[c]["n_keypoints"] for c in CHANNELS}
    assert n["position"] < n["velocity"], n
    assert n["velocity"] + 2 <= n["both"], n


def test_fig3_paper_distance_equals_line_in_2d():
    """The determinant formula is exact in 2-D: same key points for one group."""
    c = synth.curve()
    line = fig3_channels(c, epsilon=S.fig3_epsilon)
    paper = fig3_channels(c, epsilon=S.fig3_epsilon, distance="paper")
    for name in ("position", "velocity"):
        np.testing.assert_array_equal(line[name]["keypoints"], paper[name]["keypoints"])


def test_fig3_counts_equal_a_direct_reduction():
    """Each channel set equals simplify() on hand-normalized columns."""
    demo = synth.curve()
    r = fig3_channels(demo, epsilon=S.fig3_epsilon)
    for name, groups in CHANNELS.items():
        cols = []
        for g in groups:
            V = demo.get(g)
            cols.append((V - V.min()) / (V.max() - V.min()))
        U = np.column_stack(cols)
        np.testing.assert_array_equal(r[name]["keypoints"], simplify(U, S.fig3_epsilon))


def test_fig3_unknown_distance_lists_choices():
    with pytest.raises(OptionError, match="line"):
        fig3_channels(synth.curve(), distance="manhattan")


def test_fig3_rejects_demo_without_velocity():
    d = synth.curve().select("position")
    with pytest.raises(ValidationError, match="velocity"):
        fig3_channels(d)


# ------------------------------------------------------------------ Fig. 5
@pytest.fixture(scope="module")
def fig5_square(square_data):
    train, test = square_data
    return {d: fig5_learning(train, test, settings=S, distance=d) for d in DISTANCES}


def test_fig5_velocity_narrows_the_spread_on_the_square(fig5_square):
    r = fig5_square["line"]
    lo, hi = r["position"], r["position+velocity"]
    assert lo["counts"].size == S.n_demos == hi["counts"].size
    assert hi["std"] < 0.75 * lo["std"], (lo["std"], hi["std"])
    assert hi["iqr"] < lo["iqr"], (lo["iqr"], hi["iqr"])
    q75, q25 = np.percentile(lo["counts"], [75, 25])
    assert lo["iqr"] == q75 - q25 and lo["std"] == pytest.approx(lo["counts"].std())


def test_fig5_paper_distance_agrees_in_2d_only(fig5_square):
    line, paper = fig5_square["line"], fig5_square["paper"]
    np.testing.assert_array_equal(
        line["position"]["counts"], paper["position"]["counts"]
    )
    assert not np.array_equal(
        line["position+velocity"]["counts"], paper["position+velocity"]["counts"]
    )


@pytest.mark.parametrize("distance", DISTANCES)
def test_fig5_generated_path_is_close_but_not_a_copy(
    fig5_square, square_data, distance
):
    train, test = square_data
    r = fig5_square[distance]
    # reference: the median difference of the training demonstrations to the test
    P = test.get("position")
    diag = np.linalg.norm(P.max(axis=0) - P.min(axis=0))
    per_demo = [
        100 * np.sqrt(np.mean(np.sum((d.get("position") - P) ** 2, axis=1))) / diag
        for d in train
    ]
    assert r["demos_median"] == pytest.approx(np.median(per_demo), rel=1e-12)
    for name in ("position", "position+velocity"):
        e = r[name]["errors"]["difference_pct"]
        assert 0.0 < e < 1.5 * r["demos_median"], (name, e)


# ------------------------------------------------------------------ Fig. 6
@pytest.mark.parametrize("distance", DISTANCES)
def test_fig6_difference_is_the_defined_one(square_data, distance):
    train, test = square_data
    r = fig6_levels(train, test, levels=S.fig6_levels, settings=S, distance=distance)
    d = r["differences"]
    assert set(d) == {"10-20", "20-30"} and all(v > 0 for v in d.values())
    # independent recomputation: both dense paths sit on the test's time stamps,
    # so the time-aligned RMSE is the plain RMS of row-wise distances
    for (a, b), key in (((10, 20), "10-20"), ((20, 30), "20-30")):
        A, B = r["paths"][a].get("position"), r["paths"][b].get("position")
        rms = np.sqrt(np.mean(np.sum((A - B) ** 2, axis=1)))
        np.testing.assert_allclose(d[key], 100 * rms / r["scale"], rtol=1e-12)
    P = test.get("position")
    np.testing.assert_allclose(
        r["scale"], np.hypot(*(P.max(axis=0) - P.min(axis=0))), rtol=1e-12
    )


def test_fig6_resolution_gains_shrink_where_quantization_dominates():
    """At 2 % noise the 10 -> 20 change exceeds the 20 -> 30 change.

    At the paper's 10 % noise this does not hold for ndlfd's noise model (the
    report says so); where quantization dominates it does, on every data set.
    """
    sweep = fig6_noise_sweep((0.02,), settings=replace(S, n_sweep_seeds=3))
    rows = [r for r in sweep[0.02] if r is not None]
    assert len(rows) >= 2
    for r in rows:
        d = r["differences"]
        assert d["10-20"] > 1.05 * d["20-30"], d


# --------------------------------------------------------- verdict sentences
def _fake_results(fig3_counts, iqr_lo, iqr_hi, d1020, d2030):
    split = {"first_split": {"line": 1.0, "paper": 0.0}, "chord": np.eye(6)[0]}
    mode = {
        "none": {"proportions": np.array([1.0, 0.5, 0.5]), **split},
        "per-dimension": {"proportions": np.array([1.0, 1.0, 1.0]), **split},
        "group": {"proportions": np.array([1.0, 0.5, 0.5]), **split},
    }
    err = {"errors": {"difference_pct": 5.0}}

    def f5():
        one = {"counts": np.array([40]), **err}
        return {
            "position": {"iqr": iqr_lo, "std": iqr_lo, **one},
            "position+velocity": {"iqr": iqr_hi, "std": iqr_hi, **one},
            "baseline": err,
            "demos_median": 6.0,
            "n_samples": 80,
            "dims": 2,
        }

    def spread(x):
        return {"std": x, "iqr": x, "min": 1, "max": 2}

    f3 = {
        c: {"n_keypoints": n, **split}
        for c, n in zip(CHANNELS, fig3_counts, strict=True)
    }
    counts = dict(zip(CHANNELS, fig3_counts, strict=True))
    sweep5 = {"position": spread(iqr_lo), "position+velocity": spread(iqr_hi)}
    return {
        "fig2": {"line": mode, "paper": {m: {"n_keypoints": 2} for m in mode}},
        "fig3": {d: f3 for d in DISTANCES},
        "fig3_sweep": {
            v: {0.1: {d: counts for d in DISTANCES}} for v in ("clean", "noisy")
        },
        "fig5": {s: {d: f5() for d in DISTANCES} for s in S.shapes},
        "fig5_sweep": {s: {d: {0.1: sweep5} for d in DISTANCES} for s in S.shapes},
        "fig6": {
            d: {"differences": {"10-20": d1020, "20-30": d2030}} for d in DISTANCES
        },
        "fig6_sweep": {0.1: [{"differences": {"10-20": d1020, "20-30": d2030}}, None]},
    }


@settings(max_examples=30, deadline=None)
@given(
    counts=st.tuples(*[st.integers(2, 60)] * 3),
    iqr=st.tuples(st.floats(0, 20), st.floats(0, 20)),
    diffs=st.tuples(st.floats(0.1, 50), st.floats(0.1, 50)),
)
def test_sentences_follow_the_numbers(counts, iqr, diffs):
    res = _fake_results(counts, *iqr, *diffs)
    s = sentences(res, S)
    order = counts[0] < counts[1] < counts[2]
    assert s["fig3"].startswith("**Holds.**" if order else "**Does not hold.**")
    assert s["fig6"].startswith(
        "**Holds.**" if diffs[0] > diffs[1] else "**Does not hold.**"
    )
    narrower = iqr[1] < iqr[0]
    for line in s["fig5"]:
        assert ("**Holds.**" in line) == narrower
        assert f"narrows at {int(iqr[1] < iqr[0])} of 1" in line
    assert s["fig2"].startswith("**Holds.**")
    assert ("keeps only the two endpoints" in s["fig3_paper"]) == (2 in counts)
    assert "every normalization mode" in s["fig2_paper"]
    assert "singular" in s["fig2_paper"]
    assert s["holds"]["fig3"]["line"] == order
    assert s["holds"]["fig6"]["paper"] == (diffs[0] > diffs[1])
    ok = int(diffs[0] > diffs[1])
    assert f"{ok} of 1 data sets at 10% noise" in s["fig6"]


def test_fig2_sentence_notices_lost_proportions():
    res = _fake_results((1, 2, 3), 2, 1, 2, 1)
    res["fig2"]["line"]["group"]["proportions"] = np.array([1.0, 1.0, 1.0])
    assert sentences(res, S)["fig2"].startswith("**Does not hold.**")


# ------------------------------------------------------------------ outputs
def test_quick_reproduce_writes_every_figure_and_the_report(quick_run):
    out, res, lines = quick_run
    names = {
        "fig2.png",
        "fig3.png",
        "fig5_square.png",
        "fig5_square_spiral.png",
        "fig6.png",
        "report.md",
    }
    assert names <= {p.name for p in out.iterdir()}
    assert {Path(f).name for f in res["files"]} == names
    for n in names - {"report.md"}:
        data = (out / n).read_bytes()
        assert data[:8] == PNG_MAGIC and len(data) > 5_000, n
    assert not [p for p in out.iterdir() if p.name.endswith(".tmp")]
    text = (out / "report.md").read_text(encoding="utf-8")
    assert "| figure | quantity | paper | ndlfd, line | ndlfd, paper distance |" in text
    assert "--quick" in text
    # our measured numbers are in the table, beside the paper's
    f6 = res["fig6"]["line"]["differences"]["10-20"]
    assert f"| {PAPER['fig6']['10-20']:.2f} | {f6:.2f} |" in text
    f3 = res["fig3"]["line"]
    assert " / ".join(str(f3[c]["n_keypoints"]) for c in CHANNELS) in text
    assert "Difference %" in text and "noise" in text.lower()
    for key in ("fig2", "fig3", "fig6"):
        assert res["sentences"][key] in text
    assert any(line.startswith("Fig. 6") for line in lines)


def test_report_names_only_existing_library_objects(quick_run):
    """Every ``ndlfd.module.name`` the report cites can be resolved."""
    text = (quick_run[0] / "report.md").read_text(encoding="utf-8")
    cited = set(re.findall(r"ndlfd(?:\.[A-Za-z_]\w*)+", text))
    assert "ndlfd.metrics.mean_demo_baseline" in cited
    for name in cited:
        pkgutil.resolve_name(name)


def test_out_must_be_a_folder(tmp_path):
    f = tmp_path / "file"
    f.write_text("x")
    with pytest.raises(OSError):
        reproduce(f, quick=True, echo=None)


def test_cli_reproduce_quick_is_deterministic(quick_run, tmp_path):
    """The CLI exits 0 and writes the same report as the in-process run."""
    exe = Path(sys.executable).with_name("ndlfd")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "ndlfd.cli"]
    out = tmp_path / "cli"
    proc = subprocess.run(
        [*cmd, "reproduce", "--quick", "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "MPLBACKEND": "Agg"},
    )
    assert proc.returncode == 0, proc.stderr
    assert "Fig. 5" in proc.stdout
    first = (quick_run[0] / "report.md").read_text(encoding="utf-8")
    again = (out / "report.md").read_text(encoding="utf-8")
    # no run time in the report: a rerun writes it byte for byte the same
    assert again == first
    assert "run time on the console" in first
    assert not re.search(r"\d s\b", first)
    assert re.search(r"to \S+ in \d+\.\d s; see report\.md", proc.stdout)


def test_demo_type_of_generated_paths(square_data):
    train, test = square_data
    r = fig6_levels(train[:20], test, levels=(10, 20), settings=S)
    assert isinstance(r["paths"][10], Demonstration)
    np.testing.assert_array_equal(r["paths"][10].t, test.t)


def test_fig6_sentence_reads_the_noise_sweep():
    res = _fake_results((1, 2, 3), 2, 1, 5.0, 9.0)
    res["fig6_sweep"] = {
        0.01: [{"differences": {"10-20": 2.0, "20-30": 1.0}}],
        0.1: [{"differences": {"10-20": 9.0, "20-30": 9.5}}, None],
    }
    s = sentences(res, S)["fig6"]
    assert s.startswith("**Does not hold.**")
    assert "At 1% noise" in s and "no systematic resolution gain" in s
    res["fig6_sweep"][0.01] = [{"differences": {"10-20": 1.0, "20-30": 2.0}}]
    assert "At 1% noise" not in sentences(res, S)["fig6"]
