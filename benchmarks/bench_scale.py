"""Fitting at scale: time, memory and throughput of KeypointHMM.fit in N demonstrations.

Synthetic 6-D data: noisy 3-D spirals of 1,000 samples with variable speed,
position only, so every fit derives the velocity (6 learned columns, 20
position and 10 velocity levels: m = 8,000,000 states). The demonstrations come
from a *re-iterable* that makes each one from its index on demand, so no mode
ever holds them all (fit reads them twice: ranges, then key points).

Modes, each run in a fresh process (so its peak RSS is its own):

* ``serial``: ``n_jobs=1``;
* ``threads``: ``n_jobs=2`` (threads of one process);
* ``dask``: ``fit(demos, client=...)`` on a ``distributed.LocalCluster`` of 2
  worker processes with one thread each (``pip install "ndlfd[dask]"``); the
  client makes the demonstrations and scatters them to the workers in chunks.
  Cluster start-up is not counted.

Each run reports the fit time, the time only making the demonstrations takes
(included in the fit time: two passes), the peak RSS of the process (and of the
largest Dask worker), the size of the fit statistics, and a digest of the
statistics, which must be the same in every mode. Throughput is demonstrations
per second per core used (1 for serial, 2 otherwise).

Run: ``.venv/bin/python benchmarks/bench_scale.py`` (1e2, 1e3 and 1e4
demonstrations, about 2 minutes on 2 cores); ``--largest 100000`` adds 1e5
(serial and Dask, about 7 minutes more). Writes its section of
benchmarks/RESULTS.md.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from bench_hmm import ROOT, write_section

START, END = "<!-- scale:start -->", "<!-- scale:end -->"
COMMAND = ".venv/bin/python benchmarks/bench_scale.py"
N_SAMPLES = 1000
PARAMS = dict(epsilon=0.05, n_time_bins=50, max_templates=200, random_state=0)
MODES = ("serial", "threads", "dask")


class Spirals:
    """``n`` noisy 3-D spirals of ``N_SAMPLES`` samples, made on demand (re-iterable).

    Demonstration ``i`` depends only on ``(seed, i)``.
    """

    def __init__(self, n: int, seed: int = 0) -> None:
        self.n = n
        self.seed = seed

    def __len__(self) -> int:
        return self.n

    def demo(self, i: int):
        from ndlfd import Demonstration

        rng = np.random.default_rng([self.seed, i])
        s = np.linspace(0.0, 1.0, N_SAMPLES)
        warp = s ** rng.uniform(0.7, 1.4)  # variable speed
        a = 4 * np.pi * warp
        P = np.column_stack([np.cos(a) * (1 - 0.5 * warp),
                             np.sin(a) * (1 - 0.5 * warp), warp])  # fmt: skip
        P += rng.normal(0.0, 0.01, 3)  # offset
        P += 0.005 * np.cumsum(rng.normal(0.0, 0.05, (N_SAMPLES, 3)), axis=0)
        t = s * rng.uniform(2.5, 3.5)
        return Demonstration.from_arrays(t, position=P)

    def __iter__(self):
        for i in range(self.n):
            yield self.demo(i)


def _peak_mib() -> float:
    """This process's peak RSS (VmHWM) in MiB (self-contained: runs on workers)."""
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    return float("nan")


def digest(stats) -> str:
    h = hashlib.sha256()
    for k, v in sorted(stats.to_arrays().items()):
        h.update(k.encode())
        h.update(np.ascontiguousarray(v).tobytes())
    return h.hexdigest()[:16]


def run_one(mode: str, n: int) -> dict:
    """One fit in this process; the numbers as a dict."""
    from ndlfd import KeypointHMM

    demos = Spirals(n)
    warm = Spirals(20, seed=1)
    KeypointHMM(**PARAMS, n_jobs=1).fit(warm)  # compile and import once
    t0 = time.perf_counter()
    for _ in Spirals(min(n, 2000), seed=2):
        pass
    make_s = (time.perf_counter() - t0) * n / min(n, 2000) * 2  # two passes
    out = {"mode": mode, "n": n, "make_s": make_s}
    if mode == "dask":
        from distributed import Client, LocalCluster

        t0 = time.perf_counter()
        with (
            LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                         dashboard_address=None) as cluster,
            Client(cluster) as client,
        ):  # fmt: skip
            out["startup_s"] = time.perf_counter() - t0
            KeypointHMM(**PARAMS).fit(warm, client=client)
            t0 = time.perf_counter()
            model = KeypointHMM(**PARAMS).fit(demos, client=client)
            out["fit_s"] = time.perf_counter() - t0
            peaks = client.run(_peak_mib)
            out["worker_peak_mib"] = max(peaks.values())
    else:
        n_jobs = 1 if mode == "serial" else 2
        t0 = time.perf_counter()
        model = KeypointHMM(**PARAMS, n_jobs=n_jobs).fit(demos)
        out["fit_s"] = time.perf_counter() - t0
    out["peak_mib"] = _peak_mib()
    stats = model.fit_stats_
    out["stats_mib"] = sum(a.nbytes for a in stats.to_arrays().values()) / 2**20
    out["digest"] = digest(stats)
    out["keys_per_demo"] = float(stats.n_keys.mean())
    out["states_seen"] = model.n_states_used_
    out["templates"] = int(model.template_indices_.size)
    t = np.linspace(0.0, 3.0, N_SAMPLES)
    model.generate(t, dense=True)
    t0 = time.perf_counter()
    model.generate(t, dense=True)
    out["generate_ms"] = (time.perf_counter() - t0) * 1e3
    t0 = time.perf_counter()
    model.generate(t, dense=True, start={"position": [1.0, 0.0, 0.0]})
    out["generate_start_ms"] = (time.perf_counter() - t0) * 1e3
    return out


def run_fresh(mode: str, n: int) -> dict:
    cmd = [sys.executable, __file__, "--one", mode, str(n)]
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    res = subprocess.run(cmd, capture_output=True, text=True, env=env, check=False)
    if res.returncode != 0:
        raise RuntimeError(f"{mode} {n} failed:\n{res.stderr[-3000:]}")
    return json.loads(res.stdout.strip().splitlines()[-1])


def report(rows: list[dict], wall_s: float) -> str:
    import dask
    import numba

    by_n: dict = {}
    for r in rows:
        by_n.setdefault(r["n"], {})[r["mode"]] = r
    same = all(len({r["digest"] for r in d.values()}) == 1 for d in by_n.values())
    lines = [
        "## Fitting at scale: serial, threads and Dask, 100 to"
        f" {max(by_n):,} demonstrations",
        "",
        f"Command: `{COMMAND}{'' if max(by_n) <= 10_000 else ' --largest 100000'}`"
        f" ({wall_s / 60:.0f} min, {time.strftime('%Y-%m-%d %H:%M')}).",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python"
        f" {platform.python_version()}, numpy {np.__version__}, numba"
        f" {numba.__version__}, dask {dask.__version__}; load average"
        f" {os.getloadavg()[0]:.2f} at the end (other jobs share the cores).",
        "",
        f"Data: noisy 3-D spirals of {N_SAMPLES:,} samples, position only; fit"
        " derives the velocity (6-D, 20 position and 10 velocity levels, m ="
        f" 8,000,000), `{', '.join(f'{k}={v!r}' for k, v in PARAMS.items())}`."
        " The demonstrations come from a re-iterable that makes each one on"
        " demand (the time to make them, twice, is inside the fit time and shown"
        " apart). Every run is a fresh process; Dask: `LocalCluster` of 2 worker"
        " processes x 1 thread, start-up not counted, the client makes the"
        " demonstrations and scatters them in chunks. `threads` is not run at"
        " 100,000 (on 1,000-sample demonstrations it is no faster than serial:"
        " the per-demonstration work is mostly Python, holding the GIL).",
        "",
        "| demos | mode | fit s | of which making demos s | demos/s/core |"
        " peak RSS MiB | largest worker MiB | statistics MiB | generate ms"
        " (from a start) |",
        "|---:|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for n, d in sorted(by_n.items()):
        for mode in MODES:
            if mode not in d:
                continue
            r = d[mode]
            cores = 1 if mode == "serial" else 2
            worker = f"{r['worker_peak_mib']:.0f}" if "worker_peak_mib" in r else ""
            lines.append(
                f"| {n:,} | {mode} | {r['fit_s']:.2f} | {r['make_s']:.2f} |"
                f" {n / r['fit_s'] / cores:.0f} | {r['peak_mib']:.0f} | {worker} |"
                f" {r['stats_mib']:.1f} | {r['generate_ms']:.0f}"
                f" ({r['generate_start_ms']:.0f}) |"
            )
    any_n = max(by_n)
    r = next(iter(by_n[any_n].values()))
    lines += [
        "",
        f"Same statistics (digest of `fit_stats_.to_arrays()`) in every mode at"
        f" every size: {'yes' if same else 'NO'}. At {any_n:,} demonstrations:"
        f" {r['keys_per_demo']:.1f} key points per demonstration,"
        f" {r['states_seen']:,} codebook states seen, {r['templates']} templates.",
        "",
    ]
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--one", nargs=2, metavar=("MODE", "N"))
    ap.add_argument("--largest", type=int, default=10_000)
    ap.add_argument("--modes", default=",".join(MODES))
    args = ap.parse_args()
    if args.one:
        print(json.dumps(run_one(args.one[0], int(args.one[1]))))
        return
    sizes = [n for n in (100, 1_000, 10_000, 100_000) if n <= args.largest]
    t0 = time.perf_counter()
    rows = []
    for n in sizes:
        for mode in args.modes.split(","):
            if n >= 100_000 and mode == "threads":
                continue  # as serial on 1,000-sample demonstrations (see above)
            r = run_fresh(mode, n)
            print(json.dumps(r), flush=True)
            rows.append(r)
    text = report(rows, time.perf_counter() - t0)
    write_section(text, START, END)
    print(text)


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).parent))
    main()
