"""First run (issue 41): kernels compile only what a call needs, same results.

The ``dp_*`` kernels given ``tree=None`` (a trajectory of at most
``TREE_NONE_MAX`` points) are compiled without the tree's and the exact keys'
branches; they must keep the very points the full kernels keep. The demo's
warm-up says what numba compiles while it does.
"""

from __future__ import annotations

import io
import re
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit
from numba.core import event

from ndlfd.dp import _generic as G
from ndlfd.dp import _kernels as K
from ndlfd.dp import _simplify
from ndlfd.dp._tree import make_tree
from ndlfd.jobs import demo
from ndlfd.learner._fit_kernels import column_extremes

SETTINGS = settings(max_examples=60, deadline=None)

# (distance, d): dp_line's 2-D kernel, dp_cols in "line" (d = 4) and
# "segment" / "sed", dp_line's transposed kernel (d = 12), dp_generic ("paper")
CASES = [("line", 2), ("line", 4), ("segment", 2), ("sed", 3), ("line", 12),
         ("paper", 3)]  # fmt: skip


def _keep(job, tree):
    """``(keep, work)`` of the serial kernel ``_simplify`` picks for ``job``."""
    n = job.P.shape[0]
    keep = np.zeros(n, np.uint8)
    if job.mode == K.MODE_PAPER:
        args = (job.P, job.t, job.mode)
        work = G.dp_generic(*args, job.eps2, job.utol2, keep, 0, n - 1, tree)
    else:
        dp, _, args = _simplify._line_layout(job.P, job.t, job.mode)
        work = dp(*args, job.eps2, job.utol2, keep, 0, n - 1, tree)
    return keep, work


@SETTINGS
@given(
    st.sampled_from(CASES),
    st.integers(3, 300),
    st.integers(0, 2**32 - 1),
    st.sampled_from([0.0, 0.01, 0.3]),
    st.booleans(),
)
def test_no_tree_keeps_the_points_of_an_unbuilt_tree(case, n, seed, eps, integers):
    """``tree=None`` and the tuple of a tree never built: same points, same work."""
    distance, d = case
    rng = np.random.default_rng(seed)
    P = np.cumsum(rng.normal(size=(n, d)), axis=0)
    if integers:  # ties and exactly-epsilon distances
        P = np.round(P)
    times = np.cumsum(rng.uniform(0.5, 1.5, n)) if distance == "sed" else None
    job = _simplify._prepare(P, eps, distance, None, times, None)
    assert _simplify._tree(job) is None  # short: the kernels get no tree
    unbuilt = make_tree(job.P, job.t, None, job.m, _simplify.TREE_MIN)
    got, work = _keep(job, None)
    want, want_work = _keep(job, unbuilt)
    assert got.tolist() == want.tolist()
    assert work == want_work


def test_a_trajectory_past_the_bound_gets_its_tree():
    """Past TREE_MIN points (TREE_NONE_MAX at most) the kernels get the tree."""
    n = min(_simplify.TREE_MIN, K.TREE_NONE_MAX)
    for m, none in ((n, True), (n + 1, False)):
        P = np.column_stack([np.arange(m, dtype=float), np.zeros(m)])
        job = _simplify._prepare(P, 0.1, "line", None, None, None)
        assert (_simplify._tree(job) is None) is none


def test_without_a_tree_the_kernel_calls_no_tree_function():
    """dp_cols compiled for ``tree=None`` holds no call to the tree or exact keys."""
    fresh = njit(nogil=True)(K.dp_cols.py_func)  # compiled here, not cached
    P = np.cumsum(np.random.default_rng(0).normal(size=(50, 4)), axis=0)
    keep = np.zeros(50, np.uint8)
    fresh(tuple(np.ascontiguousarray(P.T)), np.zeros(0), 0, 0.1, 0.0, keep, 0, 49, None)
    (cres,) = fresh.overloads.values()
    ir = cres.library.get_llvm_str()
    assert "scan_line_cols" in ir  # the names are there to find
    for name in ("tree_begin", "tree_next", "tree_split", "scan_loo", "loo_workspace",
                 "lopsided"):  # fmt: skip
        assert name not in ir, name


@pytest.mark.parametrize(
    "P",
    [
        [[0.0]],
        [[-0.0, -3.5], [2.0, 1.0]],
        [[-5e-324, -1e300]],
        [[1.0, np.inf]],
        [[-np.inf, 0.0]],
        [[np.nan, 1.0]],
        [[1.0, -np.nan]],
    ],
)
def test_finite_maxabs_against_numpy(P):
    """(all finite, max |P|) as numpy computes them; a NaN or inf: not finite."""
    P = np.array(P)
    finite, m = K.finite_maxabs(P)
    assert finite == bool(np.isfinite(P).all())
    if finite:
        assert m == np.abs(P).max()
        assert np.signbit(m) == np.signbit(np.abs(P).max())


def test_read_only_or_not_the_extremes_compile_once():
    """column_extremes: one compiled version for writable and read-only input."""
    from ndlfd.learner import _fit_kernels

    X = np.array([[1.0, 5.0], [-2.0, 7.0], [3.0, 6.0]])
    frozen = X.copy()
    frozen.flags.writeable = False
    got = [column_extremes(a) for a in (X, frozen)]
    for lo, hi in got:
        assert lo.tolist() == [-2.0, 5.0] and hi.tolist() == [3.0, 7.0]
    assert len(_fit_kernels._extremes.signatures) == 1
    assert X.flags.writeable  # the caller's array is left as it was


def test_the_warm_up_says_what_it_compiles_while_it_does():
    """A line when the first kernel starts compiling, ended with its seconds."""

    @njit
    def kernel(x):
        return x + 1

    out = io.StringIO()
    said = []

    class AtTheEnd(event.Listener):  # what was written when numba finished
        def on_start(self, ev):
            pass

        def on_end(self, ev):
            said.append(out.getvalue())

    with demo._compiling("test", "one kernel", out) as report:
        with event.install_listener("numba:compile", AtTheEnd()):
            assert kernel(1) == 2
    assert report.kernels == 1
    start = "compiling the test kernels (one kernel; first run only, cached after) ..."
    assert said == [start]  # written while numba compiled
    assert re.fullmatch(re.escape(start) + r" \d+\.\d s, 1 kernel\n", out.getvalue())
    again = io.StringIO()
    with demo._compiling("test", "one kernel", again) as report:
        assert kernel(2) == 3
    assert report.kernels == 0
    assert again.getvalue() == ""  # compiled already: nothing said


@SETTINGS
@given(
    st.lists(st.integers(-20, 20), min_size=1, max_size=40),
    st.one_of(st.integers(-25, 25).map(lambda k: k / 2), st.just(float("nan"))),
)
def test_the_blend_s_bisection_is_numpy_searchsorted_right(knots, x):
    """_blend._after: numpy.searchsorted(side="right"), ties and NaN included."""
    from ndlfd.learner._blend import _after

    tau = np.sort(np.array(knots, dtype=np.float64) / 2)
    assert _after(tau, x) == np.searchsorted(tau, x, side="right")


@pytest.mark.parametrize("d", [1, 3])
def test_one_sample_is_read_as_its_row_everywhere(d):
    """_blend._interp_rows of a single sample: that row at every time (np.interp)."""
    from ndlfd.learner._blend import _interp_rows

    U = np.arange(1.0, d + 1.0)[None, :]
    at = np.array([-1.0, 0.0, 0.5, 2.0])
    want = np.stack([np.interp(at, [0.0], U[:, c]) for c in range(d)], axis=1)
    assert _interp_rows(U, np.zeros(1), at).tobytes() == want.tobytes()


def test_the_second_process_compiles_what_a_generation_calls():
    """compile_generation's made-up calls: a generation's very signatures.

    After it, a fit and a generation (keys, then dense with the band, as the
    demo's warm-up runs them) add no signature to the generation's kernels,
    so what a second process compiled into the cache is what is loaded.
    """
    from ndlfd import synth
    from ndlfd.hmm._kernels import viterbi_sparse
    from ndlfd.learner import KeypointHMM, _blend
    from ndlfd.learner._warm import compile_generation

    kernels = (viterbi_sparse, _blend._align_kernel, _blend._window_rows)
    assert compile_generation() >= 0
    before = [set(k.signatures) for k in kernels]
    assert all(len(s) >= 1 for s in before)
    train, test = synth.make_dataset("square", n_demos=4, random_state=0)
    for kw in ({}, demo.DEMO_SETTINGS["square"]):
        model = KeypointHMM(**kw).fit(train)
        model.generate(test.t)
        model.generate(test.t, dense=True, return_std=True)
    assert [set(k.signatures) for k in kernels] == before


def _fake(second, code):
    """``second`` running ``code`` instead of the generation's kernels."""
    second.proc = subprocess.Popen(
        [sys.executable, "-c", code], stdout=subprocess.PIPE, text=True
    )
    return second


def test_the_second_process_says_what_it_compiled_and_is_counted_once():
    """_SecondProcess.join: waited for, it says so; its kernels counted once."""
    second = demo._SecondProcess()
    assert second.proc is not None
    assert second.join() >= 0  # the real one: the cached kernels, or compiled
    assert second.join() == 0  # joined already
    said = "import json, time; time.sleep({}); print(json.dumps({}))"
    out = io.StringIO()
    _fake(second, said.format(1.0, {"kernels": 3, "seconds": 1.25}))
    assert second.join(out) == 3
    assert out.getvalue() == (
        "compiling the generation kernels (decoder, blend) in a second process"
        " ... 1.2 s, 3 kernels\n"
    )
    assert second.join(out) == 0
    out = io.StringIO()  # finished before it is joined: said in one line
    _fake(second, said.format(0.0, {"kernels": 1, "seconds": 0.5})).proc.wait()
    assert second.join(out) == 1
    assert out.getvalue() == (
        "compiled the generation kernels (decoder, blend) in a second process"
        " meanwhile: 0.5 s, 1 kernel\n"
    )
    out = io.StringIO()  # all from the cache: nothing to say
    _fake(second, said.format(0.0, {"kernels": 0, "seconds": 0.1})).proc.wait()
    assert second.join(out) == 0 and out.getvalue() == ""
    _fake(second, "raise SystemExit(1)").proc.wait()  # failed: compiled here
    assert second.join() == 0
    proc = _fake(second, "import time; time.sleep(60)").proc  # an error came first
    second.close()
    assert proc.returncode is not None and second.proc is None
    assert second.join() == 0


@pytest.mark.parametrize("frozen", [(False, False), (True, False), (False, True)])
def test_the_derivative_kernels_compile_one_version_for_any_writability(frozen):
    """_demo_kernels: the kernels get read-only views, the callers' arrays as they were.

    Writability is part of numba's array type; every compiled version takes
    read-only times and values, so the callers' mix compiles one each.
    """
    from ndlfd import _demo_kernels as D

    t = np.array([0.0, 1.0, 2.5, 3.0])
    P = np.column_stack([t**2, np.sin(t)])
    for a, f in zip((t, P), frozen, strict=True):
        a.flags.writeable = not f
    V, _ = D.gradient(t, P, 0.1)
    assert V.tobytes() == np.gradient(P, t, axis=0, edge_order=2).tobytes()
    W = D.with_room(P, 2)
    D.gradient(t, P, 0.1, out=W[:, 2:])
    assert W.tobytes() == np.column_stack([P, V]).tobytes()
    slopes = D.window_derivative(t, P, 10.0)  # every sample: one line each column
    assert np.allclose(slopes, np.polyfit(t, P, 1)[0][None, :].repeat(4, axis=0))
    assert [a.flags.writeable for a in (t, P)] == [not f for f in frozen]
    for kernel, n_read in ((D._gradient, 2), (D._with_room, 1), (D._window_slopes, 2)):
        for sig in kernel.signatures:
            assert not any(a.mutable for a in sig[:n_read]), (kernel, sig)


def test_on_one_core_no_second_process_is_started(monkeypatch):
    """One CPU: the demo compiles the generation's kernels itself, as before."""
    monkeypatch.setattr(demo, "_cores", lambda: 1)
    second = demo._SecondProcess()
    assert second.proc is None and not second.running()
    assert second.join(io.StringIO()) == 0
    second.close()
