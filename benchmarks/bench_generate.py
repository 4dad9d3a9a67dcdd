"""Generation: time and memory of KeypointHMM's blended generation.

Two parts, each measured in this run:

1. **Scale.** 100 synthetic demonstrations of a 3-D spiral (1,000 samples,
   variable speed, smooth noise; velocity derived), learned with 20 position
   and 10 velocity levels: m = 20^3 * 10^3 = 8,000,000 states. Warm fit and
   generate times (best of 7) for ``generation="blend"`` (with and without the
   band) and ``"paper"``, the tracemalloc peak of one generation, and the
   process's peak RSS. Target (issue 9): blend < 50 ms warm, < 300 MB.
2. **Per fold on LASA.** Median fit + generate time of one leave-one-out fold
   (6 training demonstrations, 1,000 samples) for ndlfd's default and for the
   peers ProMP, GMR and DMP (``pip install "ndlfd[eval]"``). Target: ndlfd
   <= 10 ms median.

Run: ``.venv/bin/python benchmarks/bench_generate.py`` (about a minute).
Writes its section of benchmarks/RESULTS.md.
"""

from __future__ import annotations

import os
import platform
import time
import tracemalloc

import numpy as np

from bench_hmm import DENSE, _dense_path, _status_mib, write_section

START, END = "<!-- generate:start -->", "<!-- generate:end -->"
N_DEMOS = 100
LASA_SHAPES = ("Angle", "GShape", "Sine", "Worm", "Multi_Models_1")


def spiral_demos(n_demos=N_DEMOS, seed=0):
    """3-D spirals with smooth noise and variable speed, as bench_hmm's data."""
    from ndlfd import Demonstration

    rng = np.random.default_rng(seed)
    demos = []
    for _ in range(n_demos):
        P = _dense_path(3, rng, 0.05)
        w = 1.0 + 0.5 * np.sin(
            2 * np.pi * np.linspace(0, 1, DENSE) + rng.uniform(0, 6.3)
        )
        t = np.concatenate([[0.0], np.cumsum(w[1:])]) * rng.uniform(0.8, 1.2) / 100
        demos.append(Demonstration.from_arrays(t, position=P))
    return demos


def best_ms(fn, repeat=7) -> float:
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return 1e3 * min(out)


def scale() -> dict:
    from ndlfd import KeypointHMM

    demos = spiral_demos()
    grid = np.linspace(0.0, 10.0, 1000)
    params = dict(levels={"position": 20, "velocity": 10})
    model = KeypointHMM(**params).fit(demos)
    paper = KeypointHMM(**params, generation="paper").fit(demos)
    model.generate(grid, dense=True, return_std=True)  # warm-up (numba, caches)
    paper.generate(grid, dense=True)
    row = {
        "m": model.codebook_.n_states,
        "seen": model.n_states_used_,
        "seen_segment": int(model.segment_model_.states_.size),
        "fit_ms": best_ms(lambda: KeypointHMM(**params).fit(demos), 3),
        "blend_ms": best_ms(lambda: model.generate(grid, dense=True)),
        "blend_std_ms": best_ms(
            lambda: model.generate(grid, dense=True, return_std=True)
        ),
        "blend_start_ms": best_ms(
            lambda: model.generate(
                grid, dense=True, start={"position": demos[0].get("position")[0]}
            )
        ),
        "paper_ms": best_ms(lambda: paper.generate(grid, dense=True)),
    }
    tracemalloc.start()
    model.generate(grid, dense=True, return_std=True)
    row["traced_mib"] = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    row["peak_rss_mib"] = _status_mib("VmHWM")
    return row


def per_fold() -> dict:
    from ndlfd import load_lasa
    from ndlfd.baselines import BASELINES, KeypointHMMGenerator

    makers = {"ndlfd": KeypointHMMGenerator}
    for name in ("promp", "gmr", "dmp"):
        makers[name] = BASELINES.get(name)
    times = {k: [] for k in makers}
    for shape in LASA_SHAPES:
        demos = load_lasa(shape)
        for f in range(7):
            train = [d for i, d in enumerate(demos) if i != f]
            test = demos[f]
            for name, make in makers.items():
                t0 = time.perf_counter()
                make().fit(train).generate(test.t)
                times[name].append(time.perf_counter() - t0)
    return {k: 1e3 * float(np.median(v)) for k, v in times.items()}


def main() -> None:
    import numba

    from ndlfd import load_lasa
    from ndlfd.baselines import KeypointHMMGenerator

    demos = load_lasa("Angle")  # warm every kernel once
    KeypointHMMGenerator().fit(demos[1:]).generate(demos[0].t)
    s = scale()
    f = per_fold()
    when = time.strftime("%Y-%m-%d %H:%M")
    lines = [
        "## Generation: blended vs paper at m = 8e6, and per LASA fold vs the peers",
        "",
        f"Command: `.venv/bin/python benchmarks/bench_generate.py` ({when}).",
        f"Machine: {platform.machine()}, Python {platform.python_version()},"
        f" numpy {np.__version__}, numba {numba.__version__}; load average"
        f" {os.getloadavg()[0]:.2f} at the end (other jobs share the cores).",
        "",
        f"### 1. Scale: 100 demonstrations of a 3-D spiral, 1,000 samples each,"
        f" m = {s['m']:,}",
        "",
        f"{s['seen']:,} codebook states seen at key points ({s['seen_segment']:,}"
        " in the segment model). Warm, best of 7 (fit best of 3); each"
        " generation is a dense 1,000-sample path.",
        "",
        "| step | ms |",
        "|---|---:|",
        f"| fit (reduce, codebook, HMM, segment model) | {s['fit_ms']:.1f} |",
        f"| generate, blend | {s['blend_ms']:.1f} |",
        f"| generate, blend + band (posterior) | {s['blend_std_ms']:.1f} |",
        f"| generate, blend conditioned on a start | {s['blend_start_ms']:.1f} |",
        f"| generate, paper | {s['paper_ms']:.1f} |",
        "",
        f"Memory: tracemalloc peak of one blend + band generation"
        f" {s['traced_mib']:.1f} MiB; peak RSS of the whole process (interpreter,"
        f" numpy, scipy, numba, 100 demonstrations, both models)"
        f" {s['peak_rss_mib']:.0f} MiB. Target: blend < 50 ms warm, < 300 MB.",
        "",
        "### 2. One leave-one-out fold on LASA (fit on 6, generate 1,000"
        f" samples), median over {len(LASA_SHAPES)} shapes x 7 folds",
        "",
        "| generator | median fit + generate (ms) | ratio to ndlfd |",
        "|---|---:|---:|",
        *(f"| {k} | {v:.1f} | {v / f['ndlfd']:.1f}x |" for k, v in f.items()),
        "",
        "Target: ndlfd <= 10 ms median.",
    ]
    text = "\n".join(lines) + "\n"
    write_section(text, START, END)
    print(text)


if __name__ == "__main__":
    main()
