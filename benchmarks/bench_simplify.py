"""Benchmark of ndlfd's n-D Douglas–Peucker against the usual peers.

Run:  .venv/bin/python benchmarks/bench_simplify.py            (a few minutes)
      .venv/bin/python benchmarks/bench_simplify.py --quick    (smaller, faster)

Peers: rdp (pure python, iterative), simplification (``simplify_coords_idx``,
Rust), shapely (``shapely.simplify(..., preserve_topology=False)``, GEOS; returns
coordinates) and fastrdp (``rdp_index``, C++). fastrdp measures the distance to
the infinite line (our default ``"line"``); simplification and shapely measure
the distance to the segment (our ``"segment"``). Their results are checked
against ours. Worst cases and the 1e6 zigzag run in subprocesses with a time
cap, so a peer that crashes (recursion, stack overflow) cannot take the
benchmark down. A second table gives every distance mode's rate by dimension
in the same run, and the zigzag is timed with and without the tree of bounding
boxes. The tables go into benchmarks/RESULTS.md between the markers
``<!-- simplify:start -->`` and ``<!-- simplify:end -->``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
from functools import partial
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "RESULTS.md"
START, END = "<!-- simplify:start -->", "<!-- simplify:end -->"
PY = sys.executable
#: Dimensions of the table of distance modes.
MODE_DIMS = (2, 3, 6, 13, 16)


def random_walk(n, d, seed=0):
    return np.cumsum(np.random.default_rng(seed).normal(size=(n, d)), axis=0)


def zigzag(n):
    """Every split peels one point: depth n - 3, n²/2 distance evaluations."""
    i = np.arange(n, dtype=float)
    y = np.where(np.arange(n) % 2 == 0, 1.0, -1.0) * (n - i)
    return np.column_stack([i, y])


def noisy_zigzag(n, seed=0):
    """The zigzag with unit Gaussian noise on both coordinates (no exact ties)."""
    return zigzag(n) + np.random.default_rng(seed).normal(size=(n, 2))


def best_of(fn, reps):
    fn()  # warm-up (compilation, caches)
    times = []
    out = None
    for _ in range(reps):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def best_of_each(fns, reps, clock=time.perf_counter):
    """Best time of each of ``fns`` (a dict), timed in turn, round by round.

    Peers whose times are compared take their turns in the same rounds, so a
    change of load on the shared cores touches them alike.
    """
    for fn in fns.values():
        fn()  # warm-up (compilation, caches)
    best = dict.fromkeys(fns, float("inf"))
    for _ in range(reps):
        for key, fn in fns.items():
            t = clock()
            fn()
            best[key] = min(best[key], clock() - t)
    return best


def load():
    return os.getloadavg()[0]


def cache_sizes():
    """The data caches of CPU 0, e.g. ``"L1 48K, L2 1024K, L3 32768K"``."""
    root = Path("/sys/devices/system/cpu/cpu0/cache")
    out = []
    for index in sorted(root.glob("index*")):
        try:
            if (index / "type").read_text().strip() == "Instruction":
                continue
            level = (index / "level").read_text().strip()
            out.append(f"L{level} {(index / 'size').read_text().strip()}")
        except OSError:
            continue
    return ", ".join(out) or "unknown"


def kernel_profile(dims, modes, sizes, eps, reps):
    """Where the time of one serial call goes, per dimension and mode.

    For each size: the kernel's distance evaluations per input point (the
    levels of splitting), its CPU time per evaluation (ns), the CPU time per
    point of one scan of the whole walk (the top level alone: a plain stream
    over the data), and the CPU time of the column layout (the transposition
    the kernels scan). One scan over data that fit in the caches (the smaller
    size) and over data that do not (the larger) shows whether a mode's
    scans are memory- or compute-bound.
    """
    from ndlfd.dp import _simplify

    out = {}
    for d in dims:
        for n in sizes:
            X = random_walk(n, d)
            times = np.arange(n, dtype=float)
            for mode in modes:
                t = times if mode == "sed" else None
                job = _simplify._prepare(X, eps, mode, None, t, None)
                dp, scan, args = _simplify._line_layout(job.P, job.t, job.mode)
                tree = _simplify._tree(job)
                box = {}

                def run(dp=dp, args=args, job=job, tree=tree, box=box, n=n):
                    keep = np.zeros(n, np.uint8)
                    box["work"] = dp(*args, job.eps2, job.utol2, keep, 0, n - 1, tree)
                    box["kept"] = int(keep.sum())

                def layout(job=job):
                    _simplify._line_layout(job.P, job.t, job.mode)

                def top(scan=scan, args=args, job=job, n=n):
                    scan(*args, 0, n - 1, job.utol2, 1, n - 1)

                fns = {"run": run, "layout": layout, "top": top}
                cpu = best_of_each(fns, reps, time.process_time)
                out[d, n, mode] = {
                    "work": box["work"] / n,
                    "ns": cpu["run"] / box["work"] * 1e9,
                    "scan": cpu["top"] / n * 1e9,
                    "kept": box["kept"] / n,
                    "layout": cpu["layout"],
                }
            print(
                f"{d:2d}-D n={n:,d} "
                + " ".join(
                    f"{m} {out[d, n, m]['work']:.1f}/pt {out[d, n, m]['ns']:.2f} ns"
                    f" (scan {out[d, n, m]['scan']:.2f})"
                    for m in modes
                )
                + f" | layout {out[d, n, modes[0]]['layout'] * 1e3:.1f} ms"
            )
    return out


# ---------------------------------------------------------------- peers


def peers():
    import fastrdp
    import rdp
    import shapely
    import simplification.cutil as sc

    def shapely_simplify(X, eps):
        line = shapely.LineString(X)
        return shapely.get_coordinates(
            shapely.simplify(line, eps, preserve_topology=False)
        )

    return {
        "fastrdp": lambda X, eps: np.sort(fastrdp.rdp_index(X, eps)),
        "simplification": lambda X, eps: np.asarray(sc.simplify_coords_idx(X, eps)),
        "shapely": shapely_simplify,
        "rdp": lambda X, eps: np.flatnonzero(rdp.rdp(X, eps, return_mask=True)),
    }


# ----------------------------------------------------------- subprocesses

CHILD = textwrap.dedent(
    """
    import json, os, sys, threading, time
    import numpy as np
    sys.setrecursionlimit(10**6)  # give recursive peers their best chance
    spec = json.loads(sys.argv[1])
    sys.path.insert(0, spec["bench_dir"])
    from bench_simplify import noisy_zigzag, peers, zigzag
    X = {"zigzag": zigzag, "noisy zigzag": noisy_zigzag}[spec["data"]](spec["n"])
    kw = {}
    if spec.get("mode", "line") != "line":
        kw["distance"] = spec["mode"]
    if spec.get("mode") == "sed":
        kw["times"] = np.arange(spec["n"], dtype=float)
    if spec["impl"] == "ndlfd":
        from ndlfd.dp import simplify
        simplify(X[:5000], spec["eps"], **{k: v[:5000] if k == "times" else v
                                           for k, v in kw.items()})  # compile
    else:
        fns = peers()
    def rss_mib():  # resident memory now
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20
    base = rss_mib()
    def report(status, seconds, kept=None):
        print(json.dumps({"status": status, "seconds": seconds, "kept": kept,
                          "rss_mib": rss_mib() - base}), flush=True)
    def watchdog():
        time.sleep(spec["cap"])
        report("timeout", spec["cap"])
        os._exit(0)
    threading.Thread(target=watchdog, daemon=True).start()
    if spec["impl"] == "ndlfd":
        fn = lambda: simplify(X, spec["eps"], **kw)
    else:
        fn = lambda: fns[spec["impl"]](X, spec["eps"])
    t = time.perf_counter()
    try:
        out = fn()
    except RecursionError:
        report("crashed: RecursionError", time.perf_counter() - t)
        os._exit(0)
    except Exception as exc:  # report whatever a peer raises
        report(f"crashed: {type(exc).__name__}", time.perf_counter() - t)
        os._exit(0)
    report("ok", time.perf_counter() - t, int(len(out)))
    os._exit(0)
    """
)


def run_child(impl, n, eps, cap, data="zigzag", mode="line"):
    spec = {
        "impl": impl,
        "n": n,
        "eps": eps,
        "cap": cap,
        "data": data,
        "mode": mode,
        "bench_dir": str(HERE),
    }
    try:
        proc = subprocess.run(
            [PY, "-c", CHILD, json.dumps(spec)],
            capture_output=True,
            text=True,
            timeout=cap + 120,
        )
    except subprocess.TimeoutExpired:
        return {"status": "timeout (killed)", "seconds": cap}
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
    if proc.returncode < 0:
        name = signal.Signals(-proc.returncode).name
        return {"status": f"crashed: {name}", "seconds": None}
    if proc.returncode != 0 or not lines:
        tail = proc.stderr.strip().splitlines()[-1:] or ["?"]
        return {"status": f"crashed: {tail[0][:60]}", "seconds": None}
    return json.loads(lines[-1])


FIRST_CALL = textwrap.dedent(
    """
    import json, time
    t0 = time.perf_counter()
    import numpy as np
    from ndlfd.dp import simplify
    t1 = time.perf_counter()
    X = np.cumsum(np.random.default_rng(0).normal(size=(1000, 2)), axis=0)
    simplify(X, 1.0)
    t2 = time.perf_counter()
    for d, kw in ((3, {}), (6, {}), (3, {"distance": "segment"}),
                  (3, {"distance": "paper"}),
                  (3, {"distance": "sed", "times": np.arange(1000.0)})):
        simplify(np.cumsum(np.ones((1000, d)), axis=0), 1.0, **kw)
    simplify(X, n_points=10)
    simplify(np.cumsum(np.ones((300_000, 2)), axis=0), 1.0)  # parallel path
    t3 = time.perf_counter()
    print(json.dumps({"import": t1 - t0, "first": t2 - t1, "others": t3 - t2}))
    """
)


def first_call_times():
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        out = []
        for _ in range(2):
            proc = subprocess.run(
                [PY, "-c", FIRST_CALL], capture_output=True, text=True, env=env
            )
            if proc.returncode:
                raise RuntimeError(proc.stderr)
            out.append(json.loads(proc.stdout.strip().splitlines()[-1]))
        return out


# ------------------------------------------------------------------ main


def fmt_rate(n, seconds):
    return f"{n / seconds / 1e6:,.1f}" if seconds else "–"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smaller sizes")
    ap.add_argument("--reps", type=int, default=None, help="repetitions (best of)")
    ap.add_argument("--cap", type=float, default=None, help="ndlfd's cap, 1e6 zigzag")
    ap.add_argument("--peer-cap", type=float, default=None, help="peers' time cap")
    ap.add_argument("--no-write", action="store_true", help="do not touch RESULTS.md")
    args = ap.parse_args(argv)
    from ndlfd.dp import _simplify, simplify

    quick = args.quick
    n = 200_000 if quick else 1_000_000
    reps = args.reps or (3 if quick else 7)
    cap = args.cap or (20.0 if quick else 600.0)
    peer_cap = args.peer_cap or (20.0 if quick else 60.0)
    n_zig = 30_000 if quick else 100_000
    n_big = 300_000 if quick else 1_000_000
    eps2d = 5.0
    load0 = load()
    rows = []  # (case, impl, n, seconds, note)
    P = peers()

    def add(case, impl, size, seconds, note=""):
        rows.append((case, impl, size, seconds, note))
        rate = fmt_rate(size, seconds)
        print(f"{case:14s} {impl:26s} {size:>9,d} {seconds:9.4f}s {rate:>6s} {note}")

    # 1. 2-D random walk
    X = random_walk(n, 2)
    t_ours, ours = best_of(lambda: simplify(X, eps2d), reps)
    kept = f"keeps {len(ours) / n:.1%}"
    add("2-D walk", "ndlfd line", n, t_ours, kept)
    t_ser, ours_ser = best_of(lambda: simplify(X, eps2d, n_jobs=1), reps)
    add("2-D walk", "ndlfd line, 1 thread", n, t_ser)
    t_seg, ours_seg = best_of(lambda: simplify(X, eps2d, distance="segment"), reps)
    add("2-D walk", "ndlfd segment", n, t_seg)
    t_fast, fast = best_of(lambda: P["fastrdp"](X, eps2d), reps)
    add("2-D walk", "fastrdp", n, t_fast, f"same indices: {np.array_equal(fast, ours)}")
    t_simp, simp = best_of(lambda: P["simplification"](X, eps2d), reps)
    same = np.array_equal(simp, ours_seg)
    add("2-D walk", "simplification", n, t_simp, f"same as segment: {same}")
    t_shp, shp = best_of(lambda: P["shapely"](X, eps2d), reps)
    same = np.array_equal(shp, X[ours_seg])
    add("2-D walk", "shapely", n, t_shp, f"same as segment: {same}")
    assert np.array_equal(ours, ours_ser)
    n_rdp = 10_000
    Xs = X[:n_rdp]
    t0 = time.perf_counter()
    r = P["rdp"](Xs, eps2d)  # pure python: one run
    t_rdp = time.perf_counter() - t0
    t_small, small = best_of(lambda: simplify(Xs, eps2d), reps)
    add("2-D walk 1e4", "rdp", n_rdp, t_rdp, f"same: {np.array_equal(r, small)}")
    add("2-D walk 1e4", "ndlfd line", n_rdp, t_small)

    # 2. 3-D random walk
    X3 = random_walk(n, 3)
    t3, ours3 = best_of(lambda: simplify(X3, eps2d), reps)
    add("3-D walk", "ndlfd line", n, t3, f"keeps {len(ours3) / n:.1%}")
    t3s, _ = best_of(lambda: simplify(X3, eps2d, n_jobs=1), reps)
    add("3-D walk", "ndlfd line, 1 thread", n, t3s)
    t3f, fast3 = best_of(lambda: P["fastrdp"](X3, eps2d), reps)
    add("3-D walk", "fastrdp", n, t3f, f"same indices: {np.array_equal(fast3, ours3)}")

    # 3. 6-D random walk
    X6 = random_walk(n, 6)
    t6, ours6 = best_of(lambda: simplify(X6, eps2d), reps)
    add("6-D walk", "ndlfd line", n, t6, f"keeps {len(ours6) / n:.1%}")
    t6s, _ = best_of(lambda: simplify(X6, eps2d, n_jobs=1), reps)
    add("6-D walk", "ndlfd line, 1 thread", n, t6s)

    # 4. every distance mode by dimension, in this one run, the modes of one
    # dimension timed in turn (round by round, so they share the load)
    modes = ("line", "segment", "sed")
    mode_rates = {}  # (d, mode) -> best wall seconds, default threads
    mode_cpu = {}  # (d, mode) -> best CPU seconds, one thread
    for d in MODE_DIMS:
        Xd = random_walk(n, d)
        times = np.arange(n, dtype=float)
        kws = {m: {"times": times} if m == "sed" else {} for m in modes}
        calls = {m: partial(simplify, Xd, eps2d, distance=m, **kws[m]) for m in modes}
        for m, sec in best_of_each(calls, reps).items():
            mode_rates[d, m] = sec
        calls = {m: partial(c, n_jobs=1) for m, c in calls.items()}
        for m, sec in best_of_each(calls, reps, time.process_time).items():
            mode_cpu[d, m] = sec
        print(
            f"{d:2d}-D walk "
            + " ".join(f"{m} {fmt_rate(n, mode_rates[d, m])}" for m in modes)
            + " | 1 thread, CPU: "
            + " ".join(f"{m} {fmt_rate(n, mode_cpu[d, m])}" for m in modes)
        )

    # 4b. where a serial call's time goes: levels, cost per evaluation in and
    # out of the caches, the column layout
    sizes = (n // 10, n)
    prof = kernel_profile(MODE_DIMS, modes, sizes, eps2d, reps)

    # 5. worst case zigzag, with the tree of bounding boxes and without
    Z = zigzag(n_zig)
    tz, kz = best_of(lambda: simplify(Z, 0.5), 1)
    add("2-D zigzag", "ndlfd line", n_zig, tz, f"depth {n_zig - 3}, kept {len(kz)}")
    for mode in ("segment", "sed"):
        kw = {"times": np.arange(n_zig, dtype=float)} if mode == "sed" else {}
        tzm, _ = best_of(partial(simplify, Z, 0.5, distance=mode, **kw), 1)
        add("2-D zigzag", f"ndlfd {mode}", n_zig, tzm)
    tree_min = _simplify.TREE_MIN
    _simplify.TREE_MIN = n_zig  # no segment is long enough: plain scans
    try:
        tzp, kzp = best_of(lambda: simplify(Z, 0.5), 1)
    finally:
        _simplify.TREE_MIN = tree_min
    same = np.array_equal(kzp, kz)
    add("2-D zigzag", "ndlfd line, no tree", n_zig, tzp, f"same indices: {same}")
    Zn = noisy_zigzag(n_zig)
    tzn, kzn = best_of(lambda: simplify(Zn, 0.5), 1)
    add("2-D noisy zigzag", "ndlfd line", n_zig, tzn, f"kept {len(kzn)}")
    zig_peers = {}
    for impl in ("fastrdp", "simplification", "shapely", "rdp"):
        res = run_child(impl, n_zig, 0.5, peer_cap)
        zig_peers[impl] = res
        status = res["status"]
        seconds = res["seconds"] if status == "ok" else None
        rows.append(("2-D zigzag", impl, n_zig, seconds, status))
        print(f"2-D zigzag {impl}: {res}")

    # 6. 1e6 zigzag under a time cap, every implementation in a subprocess
    big = {}
    for impl in ("ndlfd", "fastrdp", "simplification", "shapely", "rdp"):
        res = run_child(impl, n_big, 0.5, cap if impl == "ndlfd" else peer_cap)
        big[impl] = res
        print(f"{n_big:,d} zigzag {impl}: {res}")
    for name, data, mode in (
        ("ndlfd segment", "zigzag", "segment"),
        ("ndlfd sed", "zigzag", "sed"),
        ("ndlfd, noisy zigzag", "noisy zigzag", "line"),
    ):
        big[name] = run_child("ndlfd", n_big, 0.5, cap, data, mode)
        print(f"{n_big:,d} {data} {name}: {big[name]}")

    # 7. compile time and warm-cache first call
    fc = first_call_times()
    print("first calls:", fc)
    load1 = load()

    # ------------------------------------------------------------ report
    flags = " ".join(sys.argv[1:])
    flags = f" {flags}" if flags else ""

    def ratio(a, b):
        return f"{b / a:.2f}x"

    lines = [
        "## simplify: n-D Douglas–Peucker vs rdp, simplification, shapely, fastrdp",
        "",
        f"Command: `.venv/bin/python benchmarks/bench_simplify.py{flags}` (best of"
        f" {reps}; {time.strftime('%Y-%m-%d %H:%M')}).",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python"
        f" {platform.python_version()}, numpy {np.__version__}; load average"
        f" {load0:.2f} at start, {load1:.2f} at end (other jobs share the cores, so"
        " thread speed-ups vary from run to run).",
        "",
        f"Data: Gaussian random walks (`cumsum(normal(size=(n, d)))`), epsilon"
        f' {eps2d}. fastrdp (infinite line) is checked against our `"line"`;'
        " simplification and shapely (distance to the segment) against our"
        ' `"segment"`. Mpt/s = input points per second.',
        "",
        "| case | implementation | n | best time (s) | Mpt/s | note |",
        "|---|---|---:|---:|---:|---|",
    ]
    for case, impl, size, seconds, note in rows:
        sec = f"{seconds:.4f}" if seconds else "–"
        lines.append(
            f"| {case} | {impl} | {size:,d} | {sec} | {fmt_rate(size, seconds)}"
            f" | {note} |"
        )
    lines += [
        "",
        "Ratios (our throughput / theirs; > 1 means ndlfd is faster):",
        "",
        f"- 2-D vs fastrdp: {ratio(t_ours, t_fast)} (1 thread:"
        f" {ratio(t_ser, t_fast)}); target >= 1.0x",
        f"- 2-D vs simplification: {ratio(t_ours, t_simp)} (our segment mode,"
        f" same distance: {ratio(t_seg, t_simp)}); target >= 5x",
        f"- 2-D vs shapely: {ratio(t_ours, t_shp)} (segment mode:"
        f" {ratio(t_seg, t_shp)})",
        f"- 2-D vs rdp at 1e4: {ratio(t_small, t_rdp)}",
        f"- 3-D vs fastrdp: {ratio(t3, t3f)} (1 thread: {ratio(t3s, t3f)});"
        " target >= 1.0x",
        f"- 6-D rate / our 2-D rate: {t_ours / t6:.2f} (1 thread:"
        f" {t_ser / t6s:.2f}); target >= 0.4",
        f"- zigzag {n_zig:,d} (depth {n_zig - 3:,d}, {n_zig**2 / 2:.1e} distance"
        f" evaluations for a plain scan): {tz:.2f} s, {tzp / tz:.0f}x faster than"
        f" without the tree of bounding boxes ({tzp:.2f} s); target < 10 s",
        "",
        f"Every distance mode by dimension ({n:,d}-point random walks, epsilon"
        f" {eps2d}, best of {reps}, all in this run): Mpt/s, and in brackets the"
        " ratio to `line` at the same dimension (target >= 0.7); the last column"
        " is `line`'s rate over its own 2-D rate (target at 6-D >= 0.4). Twice:"
        " wall clock with the default threads, and CPU time of one thread (the"
        " kernels' own speed, less disturbed by other jobs on the cores).",
        "",
        "| d | line | segment | sed | line / 2-D line"
        " | 1 thread, CPU: line | segment | sed | line / 2-D line |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]

    def cells(rates, d):
        line_sec = rates[d, "line"]
        out = [fmt_rate(n, line_sec)] + [
            f"{fmt_rate(n, rates[d, m])} ({line_sec / rates[d, m]:.2f}x)"
            for m in modes[1:]
        ]
        return out + [f"{rates[MODE_DIMS[0], 'line'] / line_sec:.2f}"]

    for d in MODE_DIMS:
        row = cells(mode_rates, d) + cells(mode_cpu, d)
        lines.append(f"| {d} | {' | '.join(row)} |")
    n_small, n_large = sizes
    lines += [
        "",
        "Where a serial call's time goes (`kernel_profile`: 1 thread, best CPU"
        f" time of {reps}; data: 8·d bytes a point; caches: {cache_sizes()})."
        " One scan = the top level alone, one plain stream over the whole walk,"
        f" in CPU ns per point, on walks of {n_small:,d} points (in the caches"
        f" up to the last level) and of {n_large:,d}: a cost that rises with the"
        " size is memory, one that does not is compute. Then the epsilon"
        f" kernel on the {n_large:,d}-point walks: distance evaluations per"
        " point (the levels of splitting) and CPU ns per evaluation (short"
        " segments deep in the split cost more per point than the top's long"
        " scans), and the CPU time of the column layout (the transposition the"
        " kernels scan, with its allocation).",
        "",
        f"| d | data at {n_large:,d} (MB) | mode | one scan, ns / point,"
        f" {n_small:,d} | one scan, {n_large:,d} | kept | evaluations / point"
        " | ns / evaluation | layout (ms) |",
        "|---:|---:|---|---:|---:|---:|---:|---:|---:|",
    ]
    for d in MODE_DIMS:
        for m in modes:
            p_small, p_big = prof[d, n_small, m], prof[d, n_large, m]
            lines.append(
                f"| {d} | {8 * d * n_large / 1e6:.0f} | {m} | {p_small['scan']:.2f}"
                f" | {p_big['scan']:.2f} | {p_big['kept']:.1%}"
                f" | {p_big['work']:.1f} | {p_big['ns']:.2f}"
                f" | {p_big['layout'] * 1e3:.1f} |"
            )
    if 2 in MODE_DIMS and 6 in MODE_DIMS:
        l6 = {size: prof[6, size, "line"] for size in sizes}
        l2 = {size: prof[2, size, "line"] for size in sizes}
        big6, big2 = l6[n_large], l2[n_large]
        lines += [
            "",
            "`line` at 6-D against 2-D: one scan costs"
            f" {l6[n_small]['scan'] / l2[n_small]['scan']:.1f}x as much per point"
            f" at {n_small:,d} points and"
            f" {big6['scan'] / big2['scan']:.1f}x at {n_large:,d}; in the kernel"
            f" each evaluation {big6['ns'] / big2['ns']:.1f}x, with"
            f" {big6['work']:.1f} against {big2['work']:.1f} evaluations per"
            f" point; layout {big6['layout'] * 1e3:.1f} against"
            f" {big2['layout'] * 1e3:.1f} ms.",
        ]
    lines += [
        "",
        f"Zigzag at {n_big:,d} points (depth {n_big - 3:,d}), each implementation in"
        f" its own process, time cap {cap:.0f} s for ndlfd and {peer_cap:.0f} s for"
        " the peers; memory = growth of the process's resident memory during the"
        " call (measured at its end, or at the cap). The noisy zigzag adds unit"
        " Gaussian noise to both coordinates:",
        "",
        "| implementation | status | time (s) | memory (MiB) |",
        "|---|---|---:|---:|",
    ]
    for impl, res in big.items():
        sec = f"{res['seconds']:.1f}" if res.get("seconds") else "–"
        mem = f"{res['rss_mib']:.0f}" if "rss_mib" in res else "–"
        lines.append(f"| {impl} | {res['status']} | {sec} | {mem} |")
    lines += [
        "",
        "First call in a fresh process (empty numba cache, then a second process"
        " with the cache warm); `first` = the first `simplify` call on 1,000 2-D"
        " points, `others` = then one call of every other kernel (3-D, 6-D,"
        " segment, paper, sed, budget, parallel path):",
        "",
        "| process | import (s) | first call (s) | other kernels (s) |",
        "|---|---:|---:|---:|",
    ]
    for name, r in zip(("cold cache", "warm cache"), fc, strict=True):
        lines.append(
            f"| {name} | {r['import']:.2f} | {r['first']:.2f} | {r['others']:.2f} |"
        )
    section = "\n".join(lines) + "\n"
    print()
    print(section)
    if not args.no_write:
        write_section(section)


def write_section(section):
    text = RESULTS.read_text() if RESULTS.exists() else "# Benchmark results\n"
    block = f"{START}\n{section}{END}"
    if START in text and END in text:
        head, rest = text.split(START, 1)
        _, tail = rest.split(END, 1)
        text = head + block + tail
    else:
        text = text.rstrip("\n") + "\n\n" + block + "\n"
    RESULTS.write_text(text)
    print(f"wrote {RESULTS}")


if __name__ == "__main__":
    main()
