"""Serial fit time per demonstration, split by stage, against one ``simplify`` call.

The case of issue 20: ``KeypointHMM(random_state=0, n_jobs=1).fit`` on 1,000
in-memory demonstrations of 1,000 samples of 3-D position (the noisy spirals
of ``bench_scale``), velocity derived, so 6 learned columns. The yardstick is
one :func:`ndlfd.simplify` call on one of the same normalized 6-D
demonstrations with the fit's epsilon: the fit's per-demonstration work is
reported as a multiple of it, measured in the same run (the target is 5x).

The stages are timed on their own over all demonstrations, each as the fit
runs it (the public functions of the learner's modules):

* ``prepare``: velocity derived from position, the groups selected
  (:func:`ndlfd.learner._spec.prepare`);
* ``ranges``: per-column extremes (:meth:`RangeStats.of_items`);
* ``normalize``: :meth:`GroupScaler.transform`;
* ``simplify``: the key points (:func:`ndlfd.simplify`, the reduction);
* ``encode``: the key points' time bins and codebook states;
* ``statistics``: the fit statistics of all of them at once
  (:meth:`FitStats.of_demos`: exact centroid sums, templates);
* ``other``: the whole fit minus the stages (scheduling, merges, the HMM).

Every timing is the CPU time of the process (a shared machine's waiting for a
core is not counted), the best of ``--repeats`` rounds, the rounds interleaved
(a fit, then each stage, then the yardstick) so that a change of load hits
them alike; the wall time of the best whole fit is printed beside it.
Run: ``.venv/bin/python benchmarks/bench_fit.py`` (about a minute);
``--write`` puts the table into benchmarks/RESULTS.md between
``<!-- fit:start -->`` and ``<!-- fit:end -->``; ``--baseline SRC`` also
times the whole fit (and its own yardstick) with the package at ``SRC`` in a
subprocess, before and after the main rounds (best of 3 each).
"""

from __future__ import annotations

import argparse
import os
import platform
import shlex
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_scale import Spirals

#: CPU time of this process: on a shared machine, waiting for a core is not
#: counted (the wall time of the whole fit is printed beside it).
clock = time.process_time

START, END = "<!-- fit:start -->", "<!-- fit:end -->"
COMMAND = ".venv/bin/python benchmarks/bench_fit.py"
STAGES = ("prepare", "ranges", "normalize", "simplify", "encode", "statistics")


def stage_runs(model, demos):
    """One callable per stage, each over all demonstrations, as the fit runs it."""
    import ndlfd
    from ndlfd.learner._spec import DemoSpec, prepare
    from ndlfd.learner._stats import DemoStats, FitStats, RangeStats

    spec = DemoSpec.of_model(model)
    prepared = [prepare(d, model.groups_) for d in demos]
    U = [model.scaler_.transform(d, weighted=False) for d in prepared]
    keys = [ndlfd.simplify(u, model.epsilon) for u in U]
    reduced = [spec.encode(d, n_jobs=1) for d in prepared]
    exponents = model.fit_stats_.exponents
    kept = set(model.template_indices_.tolist())
    parts = [
        DemoStats(j, r.values, r.tau if j in kept else None, r.keypoints,
                  r.key_states, r.key_bins, r.n_clipped, j in kept)
        for j, r in enumerate(reduced)
    ]  # fmt: skip

    def encode():
        for d, u, k in zip(prepared, U, keys, strict=True):
            spec.time_bins.symbols(ndlfd.demonstration.unit_time(d.t[k]))
            spec.codebook.encode_checked(u[k])

    return {
        "prepare": lambda: [prepare(d, model.groups_) for d in demos],
        "ranges": lambda: RangeStats.of_items(
            [(j, [d.X], (), ()) for j, d in enumerate(prepared)]
        ),
        "normalize": lambda: [
            model.scaler_.transform(d, weighted=False) for d in prepared
        ],
        "simplify": lambda: [ndlfd.simplify(u, model.epsilon) for u in U],
        "encode": encode,
        "statistics": lambda: FitStats.of_demos(parts, exponents=exponents),
    }


def measure(n_demos: int, repeats: int) -> dict:
    import ndlfd
    from ndlfd import KeypointHMM

    demos = list(Spirals(n_demos))

    def fit():
        return KeypointHMM(random_state=0, n_jobs=1).fit(demos)

    model = fit()  # warm-up: compilation, caches
    runs = stage_runs(model, demos)
    u = model.scaler_.transform(runs["prepare"]()[0], weighted=False)
    one = 200

    def yardstick():
        for _ in range(one):
            ndlfd.simplify(u, model.epsilon)

    best = {k: np.inf for k in ("fit", "fit, wall", *STAGES, "one simplify")}
    for _ in range(repeats):
        t0, w0 = clock(), time.perf_counter()
        fit()
        best["fit"] = min(best["fit"], clock() - t0)
        best["fit, wall"] = min(best["fit, wall"], time.perf_counter() - w0)
        for k in STAGES:
            t0 = clock()
            runs[k]()
            best[k] = min(best[k], clock() - t0)
        t0 = clock()
        yardstick()
        best["one simplify"] = min(best["one simplify"], clock() - t0)
    ms = {k: 1e3 * v / (one if k == "one simplify" else n_demos)
          for k, v in best.items()}  # fmt: skip
    ms["other"] = ms["fit"] - sum(ms[k] for k in STAGES)
    return dict(ms=ms, n_demos=n_demos, repeats=repeats,
                keys=float(model.fit_stats_.n_keys.mean()))  # fmt: skip


#: A fresh process keeps 1,000 new arrays of 1,000 x 6 (a prepared
#: demonstration's values) and prints the CPU milliseconds per array.
_FIRST_TOUCH = """
import time, numpy as np
t0 = time.process_time()
kept = [np.ones((1000, 6)) for _ in range(1000)]
print((time.process_time() - t0) / len(kept) * 1e3)
"""


def first_touch(repeats: int = 3) -> float:
    """CPU ms to make and keep one 1,000 x 6 array in a fresh process (best of N).

    Memory a process has not used before costs its first touch (the system
    maps and clears it): what keeping the prepared demonstrations between the
    passes costs beyond copying them.
    """
    import subprocess

    return min(
        float(subprocess.run([sys.executable, "-c", _FIRST_TOUCH], check=True,
                             capture_output=True, text=True).stdout)
        for _ in range(repeats)
    )  # fmt: skip


def measure_fit_only(n_demos: int, repeats: int) -> dict:
    """The whole fit and the yardstick only (for a baseline: older code)."""
    import ndlfd
    from ndlfd import KeypointHMM

    demos = list(Spirals(n_demos))
    model = KeypointHMM(random_state=0, n_jobs=1).fit(demos)
    d = ndlfd.with_velocity(demos[0]).select(*model.groups_)
    u = model.scaler_.transform(d, weighted=False)
    fit = one = np.inf
    for _ in range(repeats):
        t0 = clock()
        KeypointHMM(random_state=0, n_jobs=1).fit(demos)
        fit = min(fit, clock() - t0)
        t0 = clock()
        for _ in range(200):
            ndlfd.simplify(u, model.epsilon)
        one = min(one, clock() - t0)
    return {"fit": 1e3 * fit / n_demos, "one simplify": 1e3 * one / 200}


def baseline(src: str, n_demos: int, repeats: int) -> dict:
    """:func:`measure_fit_only` with the package at ``src`` (a subprocess)."""
    import json
    import subprocess

    out = subprocess.run(
        [sys.executable, __file__, "--fit-only", "--demos", str(n_demos),
         "--repeats", str(repeats), "--baseline", src],
        check=True, capture_output=True, text=True,
    ).stdout  # fmt: skip
    got = json.loads(out.strip().splitlines()[-1])
    if not got.pop("package").startswith(str(Path(src).resolve())):
        raise RuntimeError(f"the baseline run did not import ndlfd from {src}")
    return got


def table(res: dict) -> str:
    ms = res["ms"]
    ref = ms["one simplify"]
    rows = ["| stage | ms per demonstration | × one simplify call |", "|---|---:|---:|"]
    for k in (*STAGES, "other", "fit"):
        name = "**whole fit**" if k == "fit" else k
        rows.append(f"| {name} | {ms[k]:.4f} | {ms[k] / ref:.1f} |")
    rows.append(f"| one simplify call (yardstick) | {ref:.4f} | 1.0 |")
    rows.append(f"| whole fit, wall time | {ms['fit, wall']:.4f} | |")
    if "first touch" in res:
        rows.append(
            "| making and keeping one new 1,000 x 6 array (a fresh process, as a"
            f" prepared demonstration is kept) | {res['first touch']:.4f} |"
            f" {res['first touch'] / ref:.1f} |"
        )
    if "baseline" in res:
        b = res["baseline"]
        rows.append(
            f"| whole fit, baseline code ({res['baseline_name']}) | {b['fit']:.4f} |"
            f" {b['fit'] / b['one simplify']:.1f} (its own simplify:"
            f" {b['one simplify']:.4f} ms) |"
        )
    return "\n".join(rows)


def report(res: dict, load: str, command: str = COMMAND) -> str:
    import numba

    return "\n".join([
        "## fit: per-demonstration work of a serial fit, by stage",
        "",
        f"Command: `{command}` ({time.strftime('%Y-%m-%d %H:%M')}, best of"
        f" {res['repeats']} interleaved rounds; load average {load} on"
        f" {os.cpu_count()} cores, shared).",
        f"Machine: {platform.machine()}, Python {platform.python_version()},"
        f" numpy {np.__version__}, numba {numba.__version__}.",
        "",
        f"`KeypointHMM(random_state=0, n_jobs=1).fit` on {res['n_demos']:,}"
        " in-memory demonstrations of 1,000 samples of 3-D position (velocity"
        " derived: 6 columns), against one `ndlfd.simplify` call on one of the"
        f" same normalized 6-D demonstrations ({res['keys']:.1f} key points on"
        " average):",
        "",
        table(res),
        "",
        "The stages are compiled kernels behind checked doorways, and each fit"
        " checks a demonstration's values once: the codebook states and time"
        " bins of the key points come from the fit's own checked values"
        " (`Codebook.encode_checked`), the two HMMs count all sequences at once"
        " (`ndlfd.hmm` checks a list of integer arrays in one pass), pass 1"
        " makes one `RangeStats` per chunk, and the templates' values are never"
        " copied while the statistics merge. The model is bit for bit the one"
        " before (`tests/learner/test_learner_identity.py`).",
        "",
        "Reading the split: each stage is timed over all demonstrations in"
        " turn, so `ranges` and `normalize` read their input from memory, where"
        " the fit runs `ranges` right after `prepare` on data still in cache;"
        " the stages then over-count and `other` (the fit minus the stages:"
        " scheduling, merges, both HMMs) can come out small or even below"
        " zero."
        " What is left beyond the reduction is mostly memory: the prepared"
        " demonstrations kept between the two passes are new memory for the"
        " process, first touched in `prepare` (the row \"making and keeping"
        " one new array\"), and the load of other jobs slows this"
        " memory-bound work more than the yardstick, which runs on one"
        " demonstration in cache. CPU times: the machine is shared by several"
        " jobs, so wall times are longer and vary.",
    ])  # fmt: skip


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--demos", type=int, default=1000)
    ap.add_argument("--repeats", type=int, default=7)
    ap.add_argument("--write", action="store_true", help="update RESULTS.md")
    ap.add_argument(
        "--baseline",
        metavar="SRC",
        help="also time the whole fit with the package at SRC"
        " (for example a checkout of main's src/), before and after",
    )
    ap.add_argument("--baseline-name", default="baseline")
    ap.add_argument("--fit-only", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.fit_only:  # bench_scale put this checkout's src first: put SRC first
        import json

        assert "ndlfd" not in sys.modules
        sys.path.insert(0, str(Path(args.baseline).resolve()))
        import ndlfd

        res = measure_fit_only(args.demos, args.repeats)
        print(json.dumps(dict(res, package=str(Path(ndlfd.__file__).resolve()))))
        return
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    base = [baseline(args.baseline, args.demos, 3)] if args.baseline else []
    res = measure(args.demos, args.repeats)
    res["first touch"] = first_touch()
    if args.baseline:
        base.append(baseline(args.baseline, args.demos, 3))
        res["baseline"] = {k: min(b[k] for b in base) for k in base[0]}
        res["baseline_name"] = args.baseline_name
    load = f"{load} before, {', '.join(f'{x:.2f}' for x in os.getloadavg())} after"
    argv = sys.argv[1:] if argv is None else argv
    text = report(res, load, " ".join([COMMAND, shlex.join(argv)]))
    print(text)
    if args.write:
        from bench_hmm import write_section

        write_section(text, START, END)


if __name__ == "__main__":
    main()
