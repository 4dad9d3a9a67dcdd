"""Fitting at scale: time, memory and throughput of KeypointHMM.fit in N demonstrations.

Synthetic 6-D data: noisy 3-D spirals of 1,000 samples with variable speed,
position only, so every fit derives the velocity (6 learned columns, 20
position and 10 velocity levels: m = 8,000,000 states). Each demonstration is
an NPZ file (``ndlfd.io.write_npz``, uncompressed), written once into
``--data`` (default ``/tmp/ndlfd-bench-scale``; 1e5 files take about 3.3 GB and
a few minutes to write, and are reused by later runs). ``fit`` gets the
sorted list of paths and reads every file twice (ranges, then key points), on
whichever worker runs it.

Modes, each run in a fresh process (so its peak RSS is its own):

* ``serial``: ``n_jobs=1``;
* ``processes``: ``n_jobs=2``, which on 1,000-sample demonstrations is two
  worker processes (the default backend for short demonstrations; the pool's
  start-up is inside the fit time);
* ``threads``: ``n_jobs=2`` forced onto two threads of one process, to show
  why processes are the default (not run at 1e5);
* ``dask``: ``fit(paths, client=...)`` on a ``distributed.LocalCluster`` of 2
  worker processes with one thread each (``pip install "ndlfd[dask]"``);
  cluster start-up is not counted (it is shown apart).

Each run reports the fit time, the time reading the files takes (measured on
a sample, times two passes; inside the fit time), the peak RSS of the process
(and of the largest Dask worker or pool process), the size of the fit
statistics, and a digest of the statistics, which must be the same in every
mode. Throughput is demonstrations per second per core used (1 for serial, 2
otherwise).

Run: ``.venv/bin/python benchmarks/bench_scale.py`` (1e2, 1e3 and 1e4
demonstrations, about 4 minutes on 2 cores the first time); ``--largest
100000`` adds 1e5 (serial, processes and Dask, about 15 minutes more). Writes
its section of benchmarks/RESULTS.md.
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
MODES = ("serial", "processes", "threads", "dask")


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


def _path(folder: Path, i: int) -> Path:
    return folder / f"spiral_{i:06d}.npz"


def _write_range(folder: str, lo: int, hi: int) -> None:
    from ndlfd.io import write_npz

    sp = Spirals(hi)
    for i in range(lo, hi):
        p = _path(Path(folder), i)
        if not p.exists():
            tmp = p.with_name(p.stem + ".part.npz")
            write_npz(sp.demo(i), tmp)
            tmp.replace(p)


def write_files(folder: Path, n: int) -> list[str]:
    """Files 0..n-1 in ``folder`` (written on 2 processes where missing)."""
    from concurrent.futures import ProcessPoolExecutor

    folder.mkdir(parents=True, exist_ok=True)
    missing = [i for i in range(n) if not _path(folder, i).exists()]
    if missing:
        t0 = time.perf_counter()
        lo, hi = missing[0], n
        cuts = np.linspace(lo, hi, 17).astype(int)
        with ProcessPoolExecutor(2) as pool:
            list(pool.map(_write_range, [str(folder)] * 16, cuts[:-1], cuts[1:]))
        print(f"wrote {len(missing):,} files in {time.perf_counter() - t0:.0f} s",
              file=sys.stderr)  # fmt: skip
    return [str(_path(folder, i)) for i in range(n)]


def _check_stored(folder: Path) -> None:
    """Refuse files of an older run written compressed (they read slower)."""
    import zipfile

    p = _path(folder, 0)
    if p.exists():
        with zipfile.ZipFile(p) as z:
            if any(i.compress_type != zipfile.ZIP_STORED for i in z.infolist()):
                raise SystemExit(f"{folder} holds compressed files of an older run;"
                                 " remove it or pass another --data")  # fmt: skip


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


def run_one(mode: str, n: int, folder: Path) -> dict:
    """One fit in this process; the numbers as a dict."""
    import ndlfd.learner._passes
    from ndlfd import KeypointHMM
    from ndlfd.io import read_demos

    paths = write_files(folder, n)
    warm = Spirals(20, seed=1)
    KeypointHMM(**PARAMS, n_jobs=1).fit(warm)  # compile and import once
    sample = paths[:: max(1, n // 500)]
    t0 = time.perf_counter()
    for p in sample:
        read_demos(p)
    read_s = (time.perf_counter() - t0) * n / len(sample) * 2  # two passes
    out = {"mode": mode, "n": n, "read_s": read_s}
    if mode == "dask":
        from distributed import Client, LocalCluster

        t0 = time.perf_counter()
        with (
            LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                         dashboard_address=":0") as cluster,
            Client(cluster) as client,
        ):  # fmt: skip
            out["startup_s"] = time.perf_counter() - t0
            KeypointHMM(**PARAMS).fit(paths[:20], client=client)
            t0 = time.perf_counter()
            model = KeypointHMM(**PARAMS).fit(paths, client=client)
            out["fit_s"] = time.perf_counter() - t0
            peaks = client.run(_peak_mib)
            out["worker_peak_mib"] = max(peaks.values())
    else:
        if mode == "threads":  # short demonstrations: processes otherwise
            ndlfd.learner._passes._THREAD_MIN_SAMPLES = 0
        n_jobs = 1 if mode == "serial" else 2
        t0 = time.perf_counter()
        model = KeypointHMM(**PARAMS, n_jobs=n_jobs).fit(paths)
        out["fit_s"] = time.perf_counter() - t0
        if mode == "processes":
            from ndlfd._parallel import _PROCESS_POOLS

            (pool,) = _PROCESS_POOLS.values()
            out["worker_peak_mib"] = max(
                f.result() for f in [pool.submit(_peak_mib) for _ in range(8)]
            )
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
    start = {"position": [1.0, 0.0, 0.0]}
    t0 = time.perf_counter()
    model.generate(t, dense=True, start=start)  # computes the kernel width
    out["generate_start_ms"] = (time.perf_counter() - t0) * 1e3
    t0 = time.perf_counter()
    model.generate(t, dense=True, start=start)
    out["generate_start_again_ms"] = (time.perf_counter() - t0) * 1e3
    return out


def run_fresh(mode: str, n: int, folder: Path) -> dict:
    cmd = [sys.executable, __file__, "--one", mode, str(n), "--data", str(folder)]
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
        "## Fitting at scale: serial, processes, threads and Dask, 100 to"
        f" {max(by_n):,} demonstrations",
        "",
        f"Command: `{COMMAND}{'' if max(by_n) <= 10_000 else ' --largest 100000'}`"
        f" ({wall_s / 60:.0f} min, {time.strftime('%Y-%m-%d %H:%M')}).",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python"
        f" {platform.python_version()}, numpy {np.__version__}, numba"
        f" {numba.__version__}, dask {dask.__version__}; load average"
        f" {os.getloadavg()[0]:.2f} at the end (other jobs share the cores).",
        "",
        f"Data: noisy 3-D spirals of {N_SAMPLES:,} samples, position only, one"
        " NPZ file each (`write_npz`, uncompressed, 33 kB); fit derives the"
        " velocity (6-D, 20 position and 10 velocity levels, m = 8,000,000),"
        f" `{', '.join(f'{k}={v!r}' for k, v in PARAMS.items())}`. `fit` gets"
        " the list of paths and reads every file twice, on the worker that maps"
        " it. Reading: the time one core takes to read every file twice"
        " (`read_demos`, timed on a sample of up to 500 files before the fit,"
        " from a cold or warm page cache as it comes); it is inside the fit"
        " time, spread over the workers. Every run is a fresh process."
        " `processes`: `n_jobs=2`, the"
        " default backend for short demonstrations, pool start-up included."
        " `threads`: `n_jobs=2` forced onto threads (the per-demonstration work"
        " is mostly Python and holds the GIL; not run at 100,000). Dask:"
        " `LocalCluster` of 2 worker processes x 1 thread, start-up not counted."
        " Worker MiB: the largest peak RSS of a pool process or Dask worker.",
        "",
        "| demos | mode | fit s | reading s (1 core) | demos/s/core |"
        " peak RSS MiB | worker MiB | statistics MiB | generate ms"
        " (from a start: first, again) | vs processes |",
        "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for n, d in sorted(by_n.items()):
        base = d.get("processes")
        for mode in MODES:
            if mode not in d:
                continue
            r = d[mode]
            cores = 1 if mode == "serial" else 2
            worker = f"{r['worker_peak_mib']:.0f}" if "worker_peak_mib" in r else ""
            ratio = f"{r['fit_s'] / base['fit_s']:.2f}x" if base else ""
            lines.append(
                f"| {n:,} | {mode} | {r['fit_s']:.2f} | {r['read_s']:.2f} |"
                f" {n / r['fit_s'] / cores:.0f} | {r['peak_mib']:.0f} | {worker} |"
                f" {r['stats_mib']:.1f} | {r['generate_ms']:.0f}"
                f" ({r['generate_start_ms']:.0f}, {r['generate_start_again_ms']:.0f})"
                f" | {ratio} |"
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
    d = by_n[any_n]
    if {"serial", "processes", "dask"} <= set(d):
        s, p, k = (d[m]["fit_s"] for m in ("serial", "processes", "dask"))
        small = min(by_n)
        grow = d["serial"]["peak_mib"] - by_n[small]["serial"]["peak_mib"]
        stats = d["serial"]["stats_mib"] - by_n[small]["serial"]["stats_mib"]
        lines += [
            f"At {any_n:,} demonstrations: `n_jobs=2` (processes) fits {s / p:.2f}"
            f" times as fast as serial; Dask on 2 local workers takes {k / p:.2f}"
            f" times as long as `n_jobs=2` (target: at most 1.3). The serial"
            f" peak RSS grows by {grow:.0f} MiB from {small:,} to {any_n:,}"
            f" demonstrations, of which {stats:.0f} MiB are the fit statistics"
            " themselves (key points and states of every demonstration, which"
            " the HMM is estimated from); the demonstrations are never held.",
            "",
        ]
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--one", nargs=2, metavar=("MODE", "N"))
    ap.add_argument("--largest", type=int, default=10_000)
    ap.add_argument("--modes", default=",".join(MODES))
    ap.add_argument("--data", type=Path, default=Path("/tmp/ndlfd-bench-scale"))
    args = ap.parse_args()
    if args.one:
        print(json.dumps(run_one(args.one[0], int(args.one[1]), args.data)))
        return
    sizes = [n for n in (100, 1_000, 10_000, 100_000) if n <= args.largest]
    _check_stored(args.data)
    write_files(args.data, max(sizes))
    t0 = time.perf_counter()
    rows = []
    for n in sizes:
        for mode in args.modes.split(","):
            if n >= 100_000 and mode == "threads":
                continue  # no faster than serial here (see the report)
            r = run_fresh(mode, n, args.data)
            print(json.dumps(r), flush=True)
            rows.append(r)
    text = report(rows, time.perf_counter() - t0)
    write_section(text, START, END)
    print(text)


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).parent))
    main()
