"""Benchmark of ndlfd.hmm: exactness and speed against hmmlearn, and scaling in m.

Run from the repository root:

    .venv/bin/python benchmarks/bench_hmm.py

It (1) decodes the same model with hmmlearn's ``CategoricalHMM`` (dense Viterbi)
and with ``ndlfd.hmm.viterbi`` at m = 900 (2-D, 30 levels) and m = 3600 (2-D, 60
levels) and compares log-probabilities, paths and speed; (2) measures fit time,
decode time and memory for m from 1e2 to 8e6 and at m = 1e12, each row in its
own process; (3) times fit + decode at m = 8e6 in a fresh process with the numba
cache warm. The results replace the ``hmm`` section of benchmarks/RESULTS.md.
"""

from __future__ import annotations

import argparse
import json
import platform
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
from numba import njit

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "src"))

RESULTS = ROOT / "benchmarks" / "RESULTS.md"
START, END = "<!-- hmm:start -->", "<!-- hmm:end -->"
COMMAND = ".venv/bin/python benchmarks/bench_hmm.py"

N_DEMOS = 100
N_KEY = 50
N_TEST_KEY = 60
N_BINS = 60
DENSE = 1000  # samples of the dense path a demonstration is cut from

# name -> (position dims, position levels, velocity dims, velocity levels)
CONFIGS = {
    "2-D@10": (2, 10, 0, 0),
    "2-D@20": (2, 20, 0, 0),
    "2-D@30": (2, 30, 0, 0),
    "2-D@60": (2, 60, 0, 0),
    "3-D@20": (3, 20, 0, 0),
    "2-D@20 + vel 2-D@10": (2, 20, 2, 10),
    "3-D@20 + vel 2-D@10": (3, 20, 2, 10),
    "3-D@20 + vel 3-D@10": (3, 20, 3, 10),
    "3-D@100 + vel 3-D@100": (3, 100, 3, 100),
}
TABLE_ROWS = [
    "2-D@10",
    "2-D@20",
    "2-D@60",
    "3-D@20",
    "2-D@20 + vel 2-D@10",
    "3-D@20 + vel 2-D@10",
    "3-D@20 + vel 3-D@10",
    "3-D@100 + vel 3-D@100",
]


# ----------------------------------------------------------------------- data


def _dense_path(dims: int, rng: np.random.Generator, noise: float) -> np.ndarray:
    """A smooth curve (2-D wave or 3-D square-ish spiral) with smooth noise."""
    s = np.linspace(0.0, 1.0, DENSE)
    if dims == 2:
        P = np.column_stack([10 * s, 4 * np.sin(2 * np.pi * s) + 2 * s])
    else:
        P = np.column_stack(
            [
                10 * np.cos(4 * np.pi * s),
                5 + 5 * np.sin(4 * np.pi * s),
                -5 + 10 * s,
            ]
        )
    span = P.max(axis=0) - P.min(axis=0)
    # low-frequency noise: a few random sine components per column
    for k in range(dims):
        for f in (1, 2, 3):
            P[:, k] += (
                noise * span[k] / f * np.sin(2 * np.pi * f * s + rng.uniform(0, 6.3))
            )
    P += rng.normal(0.0, 0.2 * noise, size=P.shape) * span
    return P


def _demo(cfg, rng, n_key, noise=0.05):
    pd, _, vd, _ = cfg
    P = _dense_path(pd, rng, noise)
    # variable speed: time runs non-uniformly along the path
    w = 1.0 + 0.5 * np.sin(2 * np.pi * np.linspace(0, 1, DENSE) + rng.uniform(0, 6.3))
    t = np.concatenate([[0.0], np.cumsum(w[1:])]) * rng.uniform(0.8, 1.2)
    cols = [P]
    if vd:
        cols.append(np.gradient(P[:, :vd], t, axis=0))
    X = np.hstack(cols)
    key = np.sort(rng.choice(np.arange(1, DENSE - 1), n_key - 2, replace=False))
    key = np.concatenate([[0], key, [DENSE - 1]])
    return t[key], X[key]


def make_problem(name: str, seed: int = 0):
    """Training states/symbols, test symbols and the codebook size."""
    from ndlfd.codebook import Codebook, TimeBins

    cfg = CONFIGS[name]
    pd, pl, vd, vl = cfg
    rng = np.random.default_rng(seed)
    demos = [_demo(cfg, rng, N_KEY) for _ in range(N_DEMOS)]
    test_t, _ = _demo(cfg, rng, N_TEST_KEY, noise=0.025)
    allX = np.vstack([X for _, X in demos])
    groups = [slice(0, pd)] + ([slice(pd, pd + vd)] if vd else [])
    lo = [allX[:, g].min() for g in groups]
    hi = [allX[:, g].max() for g in groups]

    def normalize(X):
        U = np.empty_like(X)
        for g, a, b in zip(groups, lo, hi, strict=True):
            U[:, g] = (X[:, g] - a) / (b - a)
        return U

    cb = Codebook([pl] * pd + [vl] * vd)
    tb = TimeBins(N_BINS)
    states = [cb.encode(normalize(X)) for _, X in demos]
    symbols = [tb.transform(t) for t, _ in demos]
    return states, symbols, tb.transform(test_t), cb.n_states


# ----------------------------------------------------------------- hmmlearn


def _timeit(fn, repeat: int, number: int = 1) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        best = min(best, (time.perf_counter() - t0) / number)
    return best


def compare_hmmlearn(name: str, r: float = 1e-3) -> dict:
    import warnings

    from hmmlearn.hmm import CategoricalHMM

    from ndlfd.hmm import estimate, viterbi

    states, symbols, obs, m = make_problem(name)
    model = estimate(states, symbols, m, N_BINS, pseudo_emission=r)
    A = model.transition_matrix(dense=True)
    B = model.emission_matrix(dense=True)
    pi = model.initial_distribution()
    h = CategoricalHMM(n_components=m, n_features=N_BINS, init_params="", params="")
    h.startprob_ = pi
    h.transmat_ = A
    h.emissionprob_ = B
    X = obs.reshape(-1, 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        their_logp, their_path = h.decode(X, algorithm="viterbi")
    our_path, our_logp = viterbi(model, obs)

    with np.errstate(divide="ignore"):
        lA, lB, lpi = np.log(A), np.log(B), np.log(pi)

    def path_logp(path):
        s = lpi[path[0]] + lB[path[0], obs[0]]
        for t in range(1, len(obs)):
            s += lA[path[t - 1], path[t]] + lB[path[t], obs[t]]
        return s

    same_path = bool(np.array_equal(our_path, their_path))
    t_ours = _timeit(lambda: viterbi(model, obs), repeat=7, number=20)
    reps = 3 if m <= 1000 else 1
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t_theirs = _timeit(lambda: h.decode(X, algorithm="viterbi"), repeat=reps)
    return {
        "config": name,
        "m": m,
        "T": len(obs),
        "r": r,
        "seen": int(model.states_.shape[0]),
        "ours_logp": our_logp,
        "theirs_logp": float(their_logp),
        "logp_close": bool(np.isclose(our_logp, their_logp, rtol=1e-12, atol=1e-9)),
        "same_path": same_path,
        "n_steps_differ": int(np.sum(our_path != their_path)),
        "our_path_logp_eq_theirs": bool(
            np.isclose(path_logp(our_path), their_logp, rtol=1e-12, atol=1e-9)
        ),
        "their_path_logp_eq_theirs": bool(
            np.isclose(path_logp(their_path), their_logp, rtol=1e-12, atol=1e-9)
        ),
        "ours_ms": t_ours * 1e3,
        "theirs_ms": t_theirs * 1e3,
        "speedup": t_theirs / t_ours,
    }


# ----------------------------------------------------------------- scaling rows


def _status_mib(field: str) -> float:
    """A memory field of /proc/self/status (Linux) in MiB.

    VmHWM is this process's peak RSS; unlike ``ru_maxrss`` it is not inherited
    from the parent across fork + exec.
    """
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith(field + ":"):
                return int(line.split()[1]) / 1024
    raise RuntimeError(f"no {field} in /proc/self/status")


def _rss_mib() -> float:
    return _status_mib("VmRSS")


def run_row(name: str) -> dict:
    """One table row, meant to run in its own process."""
    from ndlfd.hmm import estimate, viterbi

    states, symbols, obs, m = make_problem(name)
    # warm up: loads (or compiles) the numba kernel on a tiny model
    viterbi(estimate([0, 1], [0, 1], 2, 2), [0, 1])
    rss_before = _rss_mib()
    tracemalloc.start()
    model = estimate(states, symbols, m, N_BINS)
    _path, logp = viterbi(model, obs)
    _, traced_peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    rss_after = _rss_mib()
    t_fit = _timeit(lambda: estimate(states, symbols, m, N_BINS), repeat=7)

    def fit_decode():
        viterbi(estimate(states, symbols, m, N_BINS), obs)

    def decode_fresh_tables():
        model._tables = None  # include building the log tables
        viterbi(model, obs)

    t_dec = _timeit(decode_fresh_tables, repeat=7)
    t_dec_cached = _timeit(lambda: viterbi(model, obs), repeat=7, number=10)
    t_both = _timeit(fit_decode, repeat=7)
    peak = _status_mib("VmHWM")
    return {
        "config": name,
        "m": m,
        "seen": int(model.states_.shape[0]),
        "transitions": int(model.transition_counts_.nnz),
        "T": len(obs),
        "fit_ms": t_fit * 1e3,
        "decode_ms": t_dec * 1e3,
        "decode_cached_ms": t_dec_cached * 1e3,
        "fit_decode_ms": t_both * 1e3,
        "traced_peak_kib": traced_peak / 1024,
        "rss_delta_mib": rss_after - rss_before,
        "peak_rss_mib": peak,
        "logp": logp,
    }


FRESH_SNIPPET = r"""
import json, sys, time
sys.path.insert(0, {bench!r})
sys.path.insert(0, {src!r})
import numpy
t0 = time.perf_counter()
from ndlfd.hmm import estimate, viterbi
t1 = time.perf_counter()
import bench_hmm
states, symbols, obs, m = bench_hmm.make_problem({name!r})
t2 = time.perf_counter()
path, logp = viterbi(estimate(states, symbols, m, bench_hmm.N_BINS), obs)
t3 = time.perf_counter()
print(json.dumps({{"import_s": t1 - t0, "first_fit_decode_s": t3 - t2,
                  "peak_rss_mib": bench_hmm._status_mib("VmHWM")}}))
"""

FLOOR_SNIPPET = r"""
import json, sys, time
sys.path.insert(0, {bench!r})
import numpy as np
import numba
import bench_hmm
a = np.ones(3)
t0 = time.perf_counter()
bench_hmm.trivial_kernel(a)
print(json.dumps({{"trivial_first_call_s": time.perf_counter() - t0}}))
"""


@njit(cache=True, nogil=True)
def trivial_kernel(a):
    """A trivial cached kernel: its first call measures numba's fixed load cost."""
    s = 0.0
    for x in a:
        s += x
    return s


def _run_json(code: str) -> dict:
    out = subprocess.run(
        [sys.executable, "-c", code], check=True, capture_output=True, text=True
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def fresh_process(name: str) -> dict:
    kw = {"bench": str(ROOT / "benchmarks"), "src": str(ROOT / "src")}
    code = FRESH_SNIPPET.format(name=name, **kw)
    floor = FLOOR_SNIPPET.format(**kw)
    # first runs make sure the numba caches are warm; the next ones are measured
    _run_json(code)
    _run_json(floor)
    runs, floors, walls = [], [], []
    for _ in range(3):
        t0 = time.perf_counter()
        runs.append(_run_json(code))
        walls.append(time.perf_counter() - t0)
        floors.append(_run_json(floor)["trivial_first_call_s"])
    res = min(runs, key=lambda r: r["first_fit_decode_s"])
    res["all_first_fit_decode_s"] = [r["first_fit_decode_s"] for r in runs]
    res["process_wall_s"] = min(walls)
    res["trivial_first_call_s"] = min(floors)
    return res


# ----------------------------------------------------------------- report


def _fmt_m(m: int) -> str:
    return f"{m:,}" if m < 10**9 else f"{float(m):.0e}"


def write_section(text: str, start: str = START, end: str = END) -> None:
    """Replace the text between the markers in RESULTS.md (or append it)."""
    from ndlfd._fileformat import atomic_path

    block = f"{start}\n{text.rstrip()}\n{end}"
    old = RESULTS.read_text() if RESULTS.exists() else "# Benchmark results\n"
    if start in old and end in old:
        head, rest = old.split(start, 1)
        _, tail = rest.split(end, 1)
        new = head + block + tail
    else:
        new = old.rstrip() + "\n\n" + block + "\n"
    with atomic_path(RESULTS) as tmp:
        tmp.write_text(new)


def report(cmp_rows, table, fresh) -> str:
    import hmmlearn
    import numba

    lines = [
        "## HMM: exact structured Viterbi vs dense, and scaling in m",
        "",
        f"Command: `{COMMAND}` (about a minute).",
        f"Machine: {platform.machine()}, {platform.processor() or 'cpu'},"
        f" Python {platform.python_version()}, numpy {np.__version__},"
        f" numba {numba.__version__}, hmmlearn {hmmlearn.__version__}.",
        "",
        f"Data: {N_DEMOS} noisy demonstrations of a smooth path (2-D wave or 3-D"
        f" spiral, velocity by `np.gradient`), {N_KEY} key points each, group-"
        f"normalized and encoded by the codebook; {N_BINS} time bins; the decoded"
        f" test demonstration has {N_TEST_KEY} key points. p = 1/m.",
        "",
        "### 1. Against hmmlearn `CategoricalHMM.decode(algorithm='viterbi')`",
        "",
        "Same model in both (hmmlearn gets our dense `pi`, `A`, `B`; emission"
        " pseudo-count r = 1e-3 in both so that no row of B is zero). Times are the"
        " best of several runs, ours warm.",
        "",
        "| config | m | seen states | T | same log-prob | same path"
        " | our path's log-prob = theirs | hmmlearn ms | ndlfd ms | speed-up |",
        "|---|---:|---:|---:|---|---|---|---:|---:|---:|",
    ]
    for c in cmp_rows:
        lines.append(
            f"| {c['config']} | {c['m']:,} | {c['seen']} | {c['T']} |"
            f" {c['logp_close']} ({c['ours_logp']:.6f}) | {c['same_path']}"
            f" ({c['n_steps_differ']} steps differ) | {c['our_path_logp_eq_theirs']}"
            f" | {c['theirs_ms']:.1f} | {c['ours_ms']:.3f} | {c['speedup']:,.0f}x |"
        )
    lines += [
        "",
        "### 2. Fit and decode time, memory, as m grows",
        "",
        "Each row runs in its own process after a warm-up call (numba kernel"
        " loaded). fit = `estimate`; decode = `viterbi` including building the log"
        " tables (cached: tables already built); best of 7. traced peak ="
        " tracemalloc peak of one fit + decode (numpy allocations); RSS delta ="
        " resident memory grown by that fit + decode; peak RSS = whole process"
        " (interpreter, numpy, scipy, numba, data) at its maximum.",
        "",
        "| config | m | seen states | counted transitions | fit ms | decode ms"
        " | decode ms (cached) | fit+decode ms | traced peak KiB | RSS delta MiB"
        " | peak RSS MiB |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for t in table:
        lines.append(
            f"| {t['config']} | {_fmt_m(t['m'])} | {t['seen']:,} |"
            f" {t['transitions']:,} | {t['fit_ms']:.2f} | {t['decode_ms']:.2f} |"
            f" {t['decode_cached_ms']:.3f} | {t['fit_decode_ms']:.2f} |"
            f" {t['traced_peak_kib']:,.0f} | {t['rss_delta_mib']:.1f} |"
            f" {t['peak_rss_mib']:.0f} |"
        )
    lines += [
        "",
        "### 3. Fresh process at m = 8,000,000 (3-D@20 + vel 3-D@10), numba cache warm",
        "",
        "- first fit + decode in a new process (best of 3 runs:"
        f" {', '.join(f'{v:.3f}' for v in fresh['all_first_fit_decode_s'])} s):"
        f" {fresh['first_fit_decode_s']:.3f} s. This includes loading the cached"
        " numba kernel; for scale, the first call of a *trivial* cached kernel in a"
        " fresh process that imports only numpy and numba takes"
        f" {fresh['trivial_first_call_s']:.3f} s on the"
        " same machine (best of 3), so almost all of it is numba start-up, paid once"
        " per process and shared with the other kernels.",
        f"- `from ndlfd.hmm import ...` in a fresh process (imports the whole `ndlfd`"
        f" package with numpy, scipy, numba): {fresh['import_s']:.3f} s",
        f"- whole process (interpreter start, imports, data generation, fit, decode):"
        f" {fresh['process_wall_s']:.2f} s; peak RSS (VmHWM)"
        f" {fresh['peak_rss_mib']:.0f} MiB",
        "",
        "Targets (issue): identical paths to the dense reference (tests); decode"
        " >= 100x faster than hmmlearn at m = 900 and >= 1000x at m = 3600; at"
        " m = 8e6 fit + decode < 50 ms warm, < 0.5 s in a fresh process with the"
        " cache warm, < 300 MB peak RSS.",
    ]
    return "\n".join(lines)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--row", help="run one table row and print JSON (internal)")
    ap.add_argument("--no-write", action="store_true", help="print, do not write")
    args = ap.parse_args(argv)
    if args.row:
        print(json.dumps(run_row(args.row)))
        return
    cmp_rows = []
    for name in ("2-D@30", "2-D@60"):
        c = compare_hmmlearn(name)
        print(json.dumps(c), flush=True)
        cmp_rows.append(c)
    table = []
    for name in TABLE_ROWS:
        out = subprocess.run(
            [sys.executable, __file__, "--row", name],
            check=True,
            capture_output=True,
            text=True,
        )
        row = json.loads(out.stdout.strip().splitlines()[-1])
        print(json.dumps(row), flush=True)
        table.append(row)
    fresh = fresh_process("3-D@20 + vel 3-D@10")
    print(json.dumps(fresh), flush=True)
    text = report(cmp_rows, table, fresh)
    if args.no_write:
        print(text)
    else:
        write_section(text)
        print(f"wrote the hmm section of {RESULTS}")


if __name__ == "__main__":
    main()
