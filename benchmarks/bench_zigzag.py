"""Worst cases of Douglas–Peucker: 1e6-point zigzags in every distance mode.

Run:  .venv/bin/python benchmarks/bench_zigzag.py            (about 5 minutes)
      .venv/bin/python benchmarks/bench_zigzag.py --n 100000 --no-write

A zigzag whose every corner is kept makes each split peel one point off, so
a plain scan costs ``n²/2`` distance evaluations (5e11 at 1e6 points: hours).
The tree of bounding boxes (``ndlfd._dp_tree``) skips what cannot win;
ties need its exact bounds (``ndlfd._dp_exact``). The shapes:

* ``falling``: ``y = ±(n - i)``, the farthest corner next to a segment's
  first point (``bench_simplify``'s zigzag);
* ``noisy``: the same with unit Gaussian noise (no exact ties);
* ``growing``: ``y = ±(i + 1)``, the farthest corner next to the last point;
* ``flat``: constant height (every corner ties), in ``d`` dimensions: the
  first column ``i``, the others ``(i % 2)`` times 0.5, 0.75, ...

Each row: the best of ``--repeats`` calls after a warm-up on the first 20,000
points, one thread (``n_jobs=1``), and the points kept. The table goes into
benchmarks/RESULTS.md between ``<!-- zigzag:start -->`` and
``<!-- zigzag:end -->``.
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np

from bench_hmm import write_section
from bench_simplify import noisy_zigzag, zigzag
from ndlfd import simplify

START, END = "<!-- zigzag:start -->", "<!-- zigzag:end -->"


def growing(n):
    """The zigzag with its corners growing towards the end."""
    i = np.arange(n, dtype=float)
    sign = np.where(np.arange(n) % 2 == 0, 1.0, -1.0)
    return np.column_stack([i, sign * (i + 1)])


def flat(n, d=2):
    """Constant height in every column but the first: every corner ties."""
    k = np.arange(n)
    rest = [(k % 2) * (0.5 + 0.25 * j) for j in range(d - 1)]
    return np.column_stack([k * 1.0, *rest])


def time_one(P, mode, repeats):
    """Best time of ``simplify`` on ``P`` (epsilon 0.1), and the points kept."""
    t = np.arange(len(P), dtype=float)
    kw = {"times": t} if mode == "sed" else {}
    warm = {"times": t[:20_000]} if kw else {}
    simplify(P[:20_000], 0.1, distance=mode, n_jobs=1, **warm)
    best, kept = float("inf"), None
    for _ in range(repeats):
        t0 = time.perf_counter()
        kept = simplify(P, 0.1, distance=mode, n_jobs=1, **kw)
        best = min(best, time.perf_counter() - t0)
    return best, len(kept)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--no-write", action="store_true", help="do not touch RESULTS.md")
    args = ap.parse_args()
    n = args.n
    cases = [
        (name, fn(n), 2)
        for name, fn in [
            ("falling", zigzag),
            ("noisy", noisy_zigzag),
            ("growing", growing),
            ("flat", flat),
        ]
    ]
    cases += [("flat", flat(n, d), d) for d in (6, 16)]
    load0 = os.getloadavg()[0]
    rows = []
    for name, P, d in cases:
        modes = ["line", "segment", "sed"] + (
            ["paper"] if d == 2 and name in ("flat", "growing") else []
        )
        for mode in modes:
            seconds, kept = time_one(P, mode, args.repeats)
            rows.append((name, d, mode, seconds, kept))
            print(
                f"{name:8s} d={d:2d} {mode:8s} {seconds:7.2f} s  kept {kept}",
                flush=True,
            )
    load1 = os.getloadavg()[0]
    stamp = time.strftime("%Y-%m-%d %H:%M")
    cmd = f".venv/bin/python benchmarks/bench_zigzag.py --n {n}"
    py = platform.python_version()
    lines = [
        "## Zigzags: Douglas–Peucker's worst cases, every distance mode",
        "",
        f"Command: `{cmd}` ({stamp}; best of {args.repeats}, one thread;"
        f" load average {load0:.2f} at start, {load1:.2f} at end).",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {py},"
        f" numpy {np.__version__}.",
        "",
        f"{n:,} points, epsilon 0.1, every corner kept (a plain scan: n²/2 ="
        f" {n * n / 2:.1e} distance evaluations). Shapes in the script's docstring.",
        "",
        "| zigzag | d | distance | seconds | kept |",
        "|---|---:|---|---:|---:|",
    ]
    lines += [
        f"| {name} | {d} | {mode} | {s:.2f} | {kept:,} |"
        for name, d, mode, s, kept in rows
    ]
    section = "\n".join(lines) + "\n"
    print(section)
    if not args.no_write:
        write_section(section, START, END)


if __name__ == "__main__":
    main()
