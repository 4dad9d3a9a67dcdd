"""Reading CSV files: ndlfd against numpy.loadtxt and pyarrow.csv, side by side.

One file of 1,000 rows x 4 columns (``t, x, y, z``: time and a 3-D random
walk, written by ``ndlfd.io.write_table`` in shortest round-trip form, about
70 kB), and the same numbers separated by semicolons, tabs and runs of spaces
(with CRLF line ends), and a 10,000-row file. Each reader is timed on each
file in turns (one call of every reader, then the next round), so that the
load of other jobs falls on all of them alike; the best of the rounds is
reported. Readers:

* ``ndlfd.io.read_csv``: the whole demonstration (parse, column mapping,
  checks), the default engine;
* ``parse_table(engine=...)``: the table alone by each engine (``python`` is
  the careful line-by-line parser, which was the only one before);
* ``np.loadtxt(path, delimiter=..., skiprows=1)`` and
  ``pyarrow.csv.read_csv(path)`` with its columns stacked into one array:
  the compiled parsers themselves, with no checks.

Target (issue 20): ``read_csv`` of the 1,000 x 4 comma file in at most 1 ms,
within 2x ``np.loadtxt``.

Run: ``.venv/bin/python benchmarks/bench_io.py`` (about half a minute). Writes
its section of benchmarks/RESULTS.md.
"""

from __future__ import annotations

import os
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from bench_hmm import write_section

START, END = "<!-- io:start -->", "<!-- io:end -->"
COMMAND = ".venv/bin/python benchmarks/bench_io.py"
ROUNDS = 200


def write_files(folder: Path) -> dict[str, tuple[Path, str | None, int]]:
    """The files: name -> (path, delimiter for np.loadtxt, rows)."""
    from ndlfd.io import write_table

    rng = np.random.default_rng(0)
    files = {}
    for n in (1_000, 10_000):
        data = np.column_stack(
            [np.linspace(0.0, 3.0, n), np.cumsum(rng.normal(size=(n, 3)), axis=0)]
        )
        p = folder / f"walk_{n}.csv"
        write_table(p, ["t", "x", "y", "z"], data)
        files[f"{n:,} x 4, comma"] = (p, ",", n)
    text = files["1,000 x 4, comma"][0].read_text()
    for sep, name in ((";", "semicolon"), ("\t", "tab"), ("  ", "spaces")):
        p = folder / f"walk_{name}.csv"
        p.write_bytes(text.replace(",", sep).replace("\n", "\r\n").encode())
        delimiter = None if name == "spaces" else sep  # np.loadtxt's whitespace
        files[f"1,000 x 4, {name}, CRLF"] = (p, delimiter, 1_000)
    return files


def readers(delimiter: str | None) -> dict:
    import pyarrow.csv as pc

    from ndlfd.io import parse_table, read_csv
    from ndlfd.io._csv import ENGINES

    out = {"ndlfd read_csv": read_csv}
    for engine in ENGINES.names:
        out[f"ndlfd parse_table {engine}"] = lambda p, e=engine: parse_table(
            p, engine=e
        )
    out["np.loadtxt"] = lambda p: np.loadtxt(p, delimiter=delimiter, skiprows=1)
    if delimiter is not None:
        opts = pc.ParseOptions(delimiter=delimiter)
        out["pyarrow.csv"] = lambda p: np.column_stack(
            [c.to_numpy() for c in pc.read_csv(p, parse_options=opts).columns]
        )
    return out


def time_all(path: Path, fns: dict, rounds: int) -> dict[str, float]:
    """Best time in ms of each reader, the readers called in turns."""
    best = dict.fromkeys(fns, float("inf"))
    for fn in fns.values():
        fn(path)  # imports, first-call costs
    for _ in range(rounds):
        for name, fn in fns.items():
            t0 = time.perf_counter()
            fn(path)
            best[name] = min(best[name], time.perf_counter() - t0)
    return {k: v * 1e3 for k, v in best.items()}


def main() -> None:
    import pyarrow

    load0 = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        files = write_files(Path(tmp))
        results = {}
        for name, (path, delim, n) in files.items():
            fns = readers(delim)
            rounds = ROUNDS if n <= 1_000 else ROUNDS // 10
            results[name] = time_all(path, fns, rounds)
            print(name, {k: round(v, 3) for k, v in results[name].items()},
                  flush=True)  # fmt: skip
    names = list(next(iter(results.values())))
    lines = [
        "## Reading CSV files: ndlfd, np.loadtxt and pyarrow.csv",
        "",
        f"Command: `{COMMAND}` ({time.strftime('%Y-%m-%d %H:%M')}).",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python"
        f" {platform.python_version()}, numpy {np.__version__}, pyarrow"
        f" {pyarrow.__version__}; load average {load0:.2f} at the start,"
        f" {os.getloadavg()[0]:.2f} at the end (other jobs share the cores).",
        "",
        "Files: a 3-D random walk with its time column (`t, x, y, z`), written"
        " by `write_table` (shortest round-trip floats, about 70 kB per 1,000"
        " rows); the same numbers with semicolons, tabs or runs of spaces and"
        " CRLF line ends. Best of"
        f" {ROUNDS} rounds ({ROUNDS // 10} for 10,000 rows), every reader called"
        " once per round in turn. `read_csv`: the whole demonstration (parse,"
        " column mapping, checks) with the default engine (`auto`: pyarrow when"
        " installed and the delimiter is not whitespace, else numpy)."
        " `parse_table <engine>`: the table alone; `python` is the careful"
        " line-by-line parser (the only one before), which still takes files"
        " with comments or blank lines among the rows and finds the bad row of"
        " a file a compiled engine refuses. `np.loadtxt` and `pyarrow.csv`:"
        " the compiled parsers alone, no checks.",
        "",
        "| reader | " + " | ".join(results) + " |",
        "|---|" + "---:|" * len(results),
    ]
    for reader in names:
        cells = [
            f"{r[reader]:.3f} ms" if reader in r else "n/a" for r in results.values()
        ]
        lines.append(f"| {reader} | " + " | ".join(cells) + " |")
    cells = []
    for r in results.values():
        cells.append(f"{r['ndlfd read_csv'] / r['np.loadtxt']:.2f}x")
    lines.append("| read_csv / np.loadtxt | " + " | ".join(cells) + " |")
    r = results["1,000 x 4, comma"]
    ok = r["ndlfd read_csv"] <= 1.0 and r["ndlfd read_csv"] <= 2 * r["np.loadtxt"]
    lines += [
        "",
        f"Target (issue 20): `read_csv` of the 1,000 x 4 comma file in at most"
        f" 1 ms and within 2x `np.loadtxt`: {r['ndlfd read_csv']:.3f} ms,"
        f" {r['ndlfd read_csv'] / r['np.loadtxt']:.2f}x np.loadtxt"
        f" ({'met' if ok else 'NOT met'}); the careful parser alone takes"
        f" {r['ndlfd parse_table python'] / r['ndlfd read_csv']:.1f}x as long.",
        "",
    ]
    text = "\n".join(lines)
    write_section(text, START, END)
    print(text)


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).parent))
    main()
