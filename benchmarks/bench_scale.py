"""Fitting at scale: time, memory and throughput of KeypointHMM.fit in N demonstrations.

Synthetic 6-D data: noisy 3-D spirals of 1,000 samples with variable speed,
position only, so every fit derives the velocity (6 learned columns, 20
position and 10 velocity levels: m = 8,000,000 states). Each demonstration is
an NPZ file (``ndlfd.io.write_npz``, uncompressed) and a CSV file
(``ndlfd.io.write_csv``: ``t, x, y, z`` in shortest round-trip form, so both
hold the same numbers), written once into ``--data`` (default
``/tmp/ndlfd-bench-scale``, the CSV files in its ``csv/`` folder; 1e5 files
take about 3.3 GB as NPZ and 7.5 GB as CSV, and a few minutes to write, and
are reused by later runs). ``fit`` gets the sorted list of paths and reads
every file twice (ranges, then key points), on whichever worker runs it.

Two parts. **The library** (``--modes``, NPZ files), each mode run in a fresh
process (so its peak RSS is its own):

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

**The command line** (``--cli-modes``, ``--formats``): ``ndlfd fit PATTERN -o
model.ndlfd`` with the default parameters (no seed), run as a user runs it, on
the NPZ and on the CSV files: ``serial`` (``--n-jobs 1``), ``jobs2``
(``--n-jobs 2``) and ``dask`` (``--scheduler`` of a ``LocalCluster`` of 2
worker processes x 1 thread, started before and not counted). Each run
reports the command's wall time (interpreter start-up, imports and saving
included), the fit time the command prints, the peak of the summed RSS of the
command, its worker processes and the Dask workers (sampled every 0.1 s;
the Dask scheduler runs in the benchmark's own process and is not counted),
and the digest of the fit statistics of the model file it wrote: the same
for every mode and both formats, or the run says ``NO``.

Run: ``.venv/bin/python benchmarks/bench_scale.py`` (1e2, 1e3 and 1e4
demonstrations, both parts, about 10 minutes on 2 cores the first time);
``--largest 100000`` adds 1e5 (the library: serial, processes and Dask; the
command line: ``jobs2`` only; about 40 minutes more); ``--modes ""`` or
``--cli-modes ""`` skips a part. Writes its sections of benchmarks/RESULTS.md
(``scale``: the library; ``scale-cli``: the command line).
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
CLI_START, CLI_END = "<!-- scale-cli:start -->", "<!-- scale-cli:end -->"
COMMAND = ".venv/bin/python benchmarks/bench_scale.py"
N_SAMPLES = 1000
PARAMS = dict(epsilon=0.05, n_time_bins=50, max_templates=200, random_state=0)
MODES = ("serial", "processes", "threads", "dask")
CLI_MODES = ("serial", "jobs2", "dask")
FORMATS = ("npz", "csv")


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


def _path(folder: Path, i: int, fmt: str = "npz") -> Path:
    """File ``i``: NPZ files in ``folder``, CSV files in its ``csv/`` folder."""
    if fmt == "csv":
        return folder / "csv" / f"spiral_{i:06d}.csv"
    return folder / f"spiral_{i:06d}.npz"


def _pattern(folder: Path, n: int, fmt: str) -> str:
    """A glob pattern of files 0..n-1 (``n`` a power of ten up to 1e6)."""
    digits = len(str(n)) - 1
    assert n == 10**digits, n
    return str(_path(folder, 0, fmt)).replace(
        "0" * 6, "0" * (6 - digits) + "?" * digits
    )


def _write_range(folder: str, lo: int, hi: int, fmt: str) -> None:
    from ndlfd.io import write_csv, write_npz

    write = write_csv if fmt == "csv" else write_npz
    sp = Spirals(hi)
    for i in range(lo, hi):
        p = _path(Path(folder), i, fmt)
        if not p.exists():
            tmp = p.with_name(p.stem + f".part.{fmt}")
            write(sp.demo(i), tmp)
            tmp.replace(p)


def write_files(folder: Path, n: int, fmt: str = "npz") -> list[str]:
    """Files 0..n-1 of ``fmt`` in ``folder`` (written on 2 processes where missing)."""
    from concurrent.futures import ProcessPoolExecutor

    _path(folder, 0, fmt).parent.mkdir(parents=True, exist_ok=True)
    missing = [i for i in range(n) if not _path(folder, i, fmt).exists()]
    if missing:
        t0 = time.perf_counter()
        lo, hi = missing[0], n
        cuts = np.linspace(lo, hi, 17).astype(int)
        with ProcessPoolExecutor(2) as pool:
            list(pool.map(_write_range, [str(folder)] * 16, cuts[:-1], cuts[1:],
                          [fmt] * 16))  # fmt: skip
        print(f"wrote {len(missing):,} {fmt} files in"
              f" {time.perf_counter() - t0:.0f} s", file=sys.stderr)  # fmt: skip
    return [str(_path(folder, i, fmt)) for i in range(n)]


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


# ------------------------------------------------------------ the command line
def _tree_rss_mib(root: int) -> float:
    """Summed RSS of the processes below ``root`` (not ``root`` itself), in MiB."""
    parent = {}
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                with open(f"/proc/{d}/stat") as fh:
                    parent[int(d)] = int(fh.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                pass  # gone meanwhile
    below, todo = set(), [root]
    while todo:
        q = todo.pop()
        kids = [c for c, pp in parent.items() if pp == q and c not in below]
        below.update(kids)
        todo.extend(kids)
    total = 0
    for q in below:
        try:
            with open(f"/proc/{q}/statm") as fh:
                total += int(fh.read().split()[1])
        except (OSError, IndexError, ValueError):
            pass
    return total * os.sysconf("SC_PAGE_SIZE") / 2**20


def _run_sampled(
    cmd: list[str], env: dict
) -> tuple[subprocess.CompletedProcess, float, float]:
    """Run ``cmd``; its wall time and the peak summed RSS of this process's children."""
    import threading

    peak = [0.0]
    done = threading.Event()

    def sample():
        while not done.wait(0.1):
            peak[0] = max(peak[0], _tree_rss_mib(os.getpid()))

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    t0 = time.perf_counter()
    try:
        res = subprocess.run(cmd, capture_output=True, text=True, env=env, check=False)
    finally:
        wall = time.perf_counter() - t0
        done.set()
        sampler.join()
    return res, wall, peak[0]


def run_cli(mode: str, n: int, fmt: str, folder: Path) -> dict:
    """``ndlfd fit`` on files 0..n-1 of ``fmt`` in a subprocess; the numbers."""
    import contextlib
    import re
    import tempfile

    from ndlfd import KeypointHMM

    write_files(folder, n, fmt)
    out = {"mode": mode, "n": n, "format": fmt}
    with tempfile.TemporaryDirectory() as tmp, contextlib.ExitStack() as stack:
        model_path = Path(tmp) / "model.ndlfd"
        pattern = _pattern(folder, n, fmt)
        if mode == "dask":
            from distributed import LocalCluster

            cluster = stack.enter_context(
                LocalCluster(
                    n_workers=2,
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=":0",
                )
            )
            flags = ["--scheduler", cluster.scheduler_address]
            out["flags"] = "--scheduler ADDRESS"
        else:
            flags = ["--n-jobs", "1" if mode == "serial" else "2"]
            out["flags"] = " ".join(flags)
        cmd = [sys.executable, "-m", "ndlfd.cli", "fit", pattern, "-o", str(model_path)]
        res, out["wall_s"], out["peak_tree_mib"] = _run_sampled(
            cmd + flags, dict(os.environ)
        )
        if res.returncode != 0:
            raise RuntimeError(f"{cmd + flags} failed:\n{res.stderr[-3000:]}")
        summary = re.search(
            r"fitted (\d+) demonstration\(s\) in ([\d.]+) s", res.stderr
        )
        out["fit_s"] = float(summary.group(2))
        assert int(summary.group(1)) == n, res.stderr
        model = KeypointHMM.load(model_path)
    out["digest"] = digest(model.fit_stats_)
    out["keys_per_demo"] = float(model.fit_stats_.n_keys.mean())
    return out


def run_cli_fresh(mode: str, n: int, fmt: str, folder: Path) -> dict:
    cmd = [sys.executable, __file__, "--cli", mode, str(n), fmt, "--data", str(folder)]
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    res = subprocess.run(cmd, capture_output=True, text=True, env=env, check=False)
    if res.returncode != 0:
        raise RuntimeError(f"cli {mode} {n} {fmt} failed:\n{res.stderr[-3000:]}")
    return json.loads(res.stdout.strip().splitlines()[-1])


def cli_report(rows: list[dict], wall_s: float) -> str:
    import dask

    by_n: dict = {}
    for r in rows:
        by_n.setdefault(r["n"], []).append(r)
    digests = {r["digest"] for r in rows if r["n"] == max(by_n)}
    same = all(len({r["digest"] for r in rs}) == 1 for rs in by_n.values())
    largest = max(by_n)
    lines = [
        "## Fitting at scale from the command line: NPZ and CSV files, serial,"
        " `--n-jobs 2` and Dask",
        "",
        f"Command: `{COMMAND}{'' if largest <= 10_000 else f' --largest {largest}'}"
        f' --modes ""` ({wall_s / 60:.0f} min, {time.strftime("%Y-%m-%d %H:%M")}).',
        f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python"
        f" {platform.python_version()}, numpy {np.__version__}, dask"
        f" {dask.__version__}; load average {os.getloadavg()[0]:.2f} at the end"
        " (other jobs share the cores).",
        "",
        f"Data: the same noisy 3-D spirals of {N_SAMPLES:,} samples as above, one"
        " file each, as NPZ (`write_npz`, 33 kB) and as CSV (`write_csv`:"
        " `t, x, y, z`, shortest round-trip floats, about 75 kB), read by"
        " `ndlfd fit PATTERN -o model.ndlfd` with its defaults (no seed;"
        " velocity derived; 20 position and 10 velocity levels, epsilon 0.05,"
        " 50 time bins) in a subprocess. Wall: the command from start to exit"
        " (start-up, imports, the first read, the fit and saving); fit: the"
        " time the command prints for the fit itself. Peak MiB: the largest"
        " sum of the resident memory of the command, its workers and the Dask"
        " workers, sampled every 0.1 s. Digest: SHA-256 of the fit statistics"
        " in the model file written (`fit_stats_.to_arrays()`), first 16 hex"
        " digits.",
        "",
        "| demos | format | mode | wall s | fit s | demos/s | peak MiB | digest |",
        "|---:|---|---|---:|---:|---:|---:|---|",
    ]
    for n, rs in sorted(by_n.items()):
        for r in rs:
            lines.append(
                f"| {n:,} | {r['format']} | {r['mode']} | {r['wall_s']:.1f} |"
                f" {r['fit_s']:.1f} | {n / r['fit_s']:.0f} | {r['peak_tree_mib']:.0f}"
                f" | `{r['digest']}` |"
            )
    lines += [
        "",
        f"Same digest in every mode and both formats at every size:"
        f" {'yes' if same else 'NO'} (at {largest:,}: {', '.join(sorted(digests))}).",
        "",
    ]
    return "\n".join(lines)


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
    ap.add_argument("--cli", nargs=3, metavar=("MODE", "N", "FORMAT"))
    ap.add_argument("--largest", type=int, default=10_000)
    ap.add_argument("--smallest", type=int, default=100)
    ap.add_argument("--modes", default=",".join(MODES))
    ap.add_argument("--cli-modes", default=",".join(CLI_MODES))
    ap.add_argument("--formats", default=",".join(FORMATS))
    ap.add_argument("--data", type=Path, default=Path("/tmp/ndlfd-bench-scale"))
    args = ap.parse_args()
    if args.one:
        print(json.dumps(run_one(args.one[0], int(args.one[1]), args.data)))
        return
    if args.cli:
        mode, n, fmt = args.cli
        print(json.dumps(run_cli(mode, int(n), fmt, args.data)))
        return
    sizes = [
        n for n in (100, 1_000, 10_000, 100_000) if args.smallest <= n <= args.largest
    ]
    modes = [m for m in args.modes.split(",") if m]
    cli_modes = [m for m in args.cli_modes.split(",") if m]
    formats = [f for f in args.formats.split(",") if f]
    _check_stored(args.data)
    for fmt in formats if cli_modes else ["npz"] if modes else []:
        write_files(args.data, max(sizes), fmt)
    if modes:
        t0 = time.perf_counter()
        rows = []
        for n in sizes:
            for mode in modes:
                if n >= 100_000 and mode == "threads":
                    continue  # no faster than serial here (see the report)
                r = run_fresh(mode, n, args.data)
                print(json.dumps(r), flush=True)
                rows.append(r)
        text = report(rows, time.perf_counter() - t0)
        write_section(text, START, END)
        print(text)
    if cli_modes:
        t0 = time.perf_counter()
        rows = []
        for n in sizes:
            for fmt in formats:
                for mode in cli_modes:
                    if n >= 100_000 and mode != "jobs2":
                        continue  # the targets' mode (serial: 10 minutes more)
                    r = run_cli_fresh(mode, n, fmt, args.data)
                    print(json.dumps(r), flush=True)
                    rows.append(r)
        text = cli_report(rows, time.perf_counter() - t0)
        write_section(text, CLI_START, CLI_END)
        print(text)


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).parent))
    main()
